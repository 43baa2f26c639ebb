//! A max-priority queue as a 4-ary heap: the refinement's queue of bad
//! cells. It pops in the same order as [`std::collections::BinaryHeap`]
//! for elements whose order is total (equal elements are identical), with
//! half the levels: on queues of hundreds of thousands of entries, each
//! level of a pop is a cache miss, and a node's four children share one or
//! two cache lines.

/// Children per node.
const ARITY: usize = 4;

/// A max-heap with four children per node (the greatest element first).
#[derive(Debug, Clone)]
pub(super) struct Heap<T> {
    v: Vec<T>,
}

impl<T: Ord + Copy> Heap<T> {
    /// An empty queue.
    pub(super) fn new() -> Self {
        Heap { v: Vec::new() }
    }

    /// Number of queued elements.
    pub(super) fn len(&self) -> usize {
        self.v.len()
    }

    /// Keeps only the elements for which `keep` holds, and restores the
    /// heap order (bottom-up, in linear time). The remaining elements pop
    /// in the same order as before: the order is total.
    pub(super) fn retain(&mut self, keep: impl FnMut(&T) -> bool) {
        self.v.retain(keep);
        let n = self.v.len();
        if n < 2 {
            return;
        }
        for i in (0..=(n - 2) / ARITY).rev() {
            self.sift_down(i);
        }
    }

    /// Moves the element at `i` down to its place below.
    fn sift_down(&mut self, mut i: usize) {
        let x = self.v[i];
        let n = self.v.len();
        loop {
            let first = ARITY * i + 1;
            if first >= n {
                break;
            }
            let end = (first + ARITY).min(n);
            let mut c = first;
            for k in first + 1..end {
                if self.v[k] > self.v[c] {
                    c = k;
                }
            }
            if self.v[c] <= x {
                break;
            }
            self.v[i] = self.v[c];
            i = c;
        }
        self.v[i] = x;
    }

    /// Queues `x`.
    pub(super) fn push(&mut self, x: T) {
        let mut i = self.v.len();
        self.v.push(x);
        while i > 0 {
            let parent = (i - 1) / ARITY;
            if self.v[parent] >= x {
                break;
            }
            self.v[i] = self.v[parent];
            i = parent;
        }
        self.v[i] = x;
    }

    /// Removes and returns the greatest element.
    pub(super) fn pop(&mut self) -> Option<T> {
        let last = self.v.pop()?;
        if self.v.is_empty() {
            return Some(last);
        }
        let top = self.v[0];
        self.v[0] = last;
        self.sift_down(0);
        Some(top)
    }
}

#[cfg(test)]
mod tests {
    use super::Heap;
    use std::collections::BinaryHeap;

    /// Pops in the order of `BinaryHeap` under interleaved pushes and pops,
    /// with repeated elements and ties on the first field.
    #[test]
    fn same_order_as_binary_heap() {
        let mut rng = crate::geom::SplitMix64::new(0x2545_f491_4f6c_dd1d);
        let mut next = || rng.next_u64();
        let mut a = Heap::new();
        let mut b = BinaryHeap::new();
        let mut popped = 0;
        for round in 0..20_000 {
            let r = next();
            if r % 3 == 0 {
                let x = a.pop();
                assert_eq!(x, b.pop(), "round {round}");
                popped += usize::from(x.is_some());
            } else {
                let x = (r >> 8) % 50;
                let y = (r >> 20) % 7;
                a.push((x, y));
                b.push((x, y));
            }
            assert_eq!(a.len(), b.len());
        }
        while let Some(x) = b.pop() {
            assert_eq!(a.pop(), Some(x));
        }
        assert_eq!(a.pop(), None);
        assert!(popped > 1000);
    }

    /// After `retain`, the kept elements pop in the order `BinaryHeap`
    /// pops them, and pushes and pops go on in that order.
    #[test]
    fn retain_keeps_the_order() {
        let mut rng = crate::geom::SplitMix64::new(0x9e37_79b9_7f4a_7c15);
        let mut a = Heap::new();
        let mut b = BinaryHeap::new();
        for round in 0..30_000u64 {
            let r = rng.next_u64();
            if r.is_multiple_of(5) {
                assert_eq!(a.pop(), b.pop(), "round {round}");
            } else {
                let x = ((r >> 8) % 64, (r >> 20) % 5);
                a.push(x);
                b.push(x);
            }
            if round.is_multiple_of(997) {
                let keep = |x: &(u64, u64)| !(x.0 + x.1 + round).is_multiple_of(3);
                a.retain(keep);
                b.retain(keep);
                assert_eq!(a.len(), b.len());
            }
        }
        assert!(a.len() > 100);
        while let Some(x) = b.pop() {
            assert_eq!(a.pop(), Some(x));
        }
        assert_eq!(a.pop(), None);
        for n in 0..6 {
            let mut c = Heap::new();
            (0..n).for_each(|k| c.push(k));
            c.retain(|&k| k != 2);
            let got: Vec<i32> = std::iter::from_fn(|| c.pop()).collect();
            let want: Vec<i32> = (0..n).rev().filter(|&k| k != 2).collect();
            assert_eq!(got, want);
        }
    }
}
