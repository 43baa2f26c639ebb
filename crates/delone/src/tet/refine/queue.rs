//! A max-priority queue as a 4-ary heap: the refinement's queue of bad
//! cells. It pops in the same order as [`std::collections::BinaryHeap`]
//! for elements whose order is total (equal elements are identical), with
//! half the levels: on queues of hundreds of thousands of entries, each
//! level of a pop is a cache miss, and a node's four children (their keys;
//! the rest of each element is kept aside) share one or two cache lines.

/// Children per node.
const ARITY: usize = 4;

/// An element of a [`Heap`]: ordered by a `u64` key first, then by the
/// rest (`Ord` of the element must agree with that of `(key, rest)`).
pub(super) trait Keyed: Copy {
    /// The rest of the element, compared on equal keys.
    type Rest: Ord + Copy;
    /// The key and the rest.
    fn split(self) -> (u64, Self::Rest);
    /// The element of a key and a rest.
    fn join(key: u64, rest: Self::Rest) -> Self;
}

/// A max-heap with four children per node (the greatest element first).
/// The heap proper holds each element's key and the index of its rest in
/// a side table (16 bytes an entry: a node's four children share one or
/// two cache lines); the rest is read only on equal keys.
#[derive(Debug, Clone)]
pub(super) struct Heap<T: Keyed> {
    v: Vec<(u64, u32)>,
    rest: Vec<T::Rest>,
    /// Indices of `rest` free for reuse.
    free: Vec<u32>,
}

impl<T: Keyed> Heap<T> {
    /// An empty queue.
    pub(super) fn new() -> Self {
        Heap {
            v: Vec::new(),
            rest: Vec::new(),
            free: Vec::new(),
        }
    }

    /// Number of queued elements.
    #[cfg(test)]
    pub(super) fn len(&self) -> usize {
        self.v.len()
    }

    /// Is entry `a` greater than entry `b`?
    #[inline]
    fn greater(&self, a: (u64, u32), b: (u64, u32)) -> bool {
        a.0 > b.0 || a.0 == b.0 && self.rest[a.1 as usize] > self.rest[b.1 as usize]
    }

    /// Queues `x`.
    pub(super) fn push(&mut self, x: T) {
        let (key, rest) = x.split();
        let id = match self.free.pop() {
            Some(id) => {
                self.rest[id as usize] = rest;
                id
            }
            None => {
                self.rest.push(rest);
                (self.rest.len() - 1) as u32
            }
        };
        let x = (key, id);
        let mut i = self.v.len();
        self.v.push(x);
        while i > 0 {
            let parent = (i - 1) / ARITY;
            if !self.greater(x, self.v[parent]) {
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
        let top = if self.v.is_empty() {
            last
        } else {
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
                    if self.greater(self.v[k], self.v[c]) {
                        c = k;
                    }
                }
                if !self.greater(self.v[c], last) {
                    break;
                }
                self.v[i] = self.v[c];
                i = c;
            }
            self.v[i] = last;
            top
        };
        self.free.push(top.1);
        Some(T::join(top.0, self.rest[top.1 as usize]))
    }
}

#[cfg(test)]
mod tests {
    use super::{Heap, Keyed};
    use std::collections::BinaryHeap;

    impl Keyed for (u64, u64) {
        type Rest = u64;
        fn split(self) -> (u64, u64) {
            self
        }
        fn join(key: u64, rest: u64) -> Self {
            (key, rest)
        }
    }

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
