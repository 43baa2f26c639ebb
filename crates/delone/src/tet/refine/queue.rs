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
    #[cfg(test)]
    pub(super) fn len(&self) -> usize {
        self.v.len()
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
        let n = self.v.len();
        let mut i = 0;
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
            if self.v[c] <= last {
                break;
            }
            self.v[i] = self.v[c];
            i = c;
        }
        self.v[i] = last;
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
}
