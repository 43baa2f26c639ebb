//! Recent answers of exact tests on tuples of vertex ids, remembered in a
//! small direct-mapped table: the flips of the recovery ask about the same
//! tuples again and again (the orientation of a cell, whether a segment
//! meets a face).

use std::cell::RefCell;

/// Entries of a [`Recent`] table: `1 <<` this many.
const BITS: u32 = 12;

/// Recent answers of an exact test on `N` vertex ids (`N ≥ 2`, in the
/// order asked): per entry a tuple and its answer, at the slot chosen by a
/// hash of the tuple (the table is allocated at the first question). An
/// answer never goes stale as long as the points are only ever appended
/// to, which is how the meshes holding a table use them.
#[derive(Debug, Clone, Default)]
pub(crate) struct Recent<const N: usize> {
    table: RefCell<Vec<([u32; N], bool)>>,
}

impl<const N: usize> Recent<N> {
    /// The answer for `key`: remembered, else `test()` (then remembered in
    /// place of the entry at its slot; `test` must not ask this table).
    #[inline(always)]
    pub(crate) fn answer(&self, key: [u32; N], test: impl FnOnce() -> bool) -> bool {
        // Rotations spread over 24 bits (4 ids: 0, 8, 16, 24).
        let step = 24 / (N as u32 - 1).max(1);
        let h = key
            .iter()
            .zip(0u32..)
            .fold(0u32, |h, (&w, i)| h ^ w.rotate_left(step * i))
            .wrapping_mul(0x9E37_79B1);
        let i = (h >> (32 - BITS)) as usize;
        let mut t = self.table.borrow_mut();
        if t.is_empty() {
            // No tuple of distinct ids equals the filler.
            t.resize(1 << BITS, ([u32::MAX; N], false));
        }
        let e = &mut t[i];
        if e.0 != key {
            *e = (key, test());
        }
        e.1
    }
}

#[cfg(test)]
mod tests {
    use super::Recent;

    #[test]
    fn answers_are_remembered_per_tuple_in_order() {
        let memo = Recent::<4>::default();
        assert!(memo.answer([1, 2, 3, 4], || true));
        assert!(memo.answer([1, 2, 3, 4], || unreachable!()));
        // Another order is another question.
        assert!(!memo.answer([2, 1, 3, 4], || false));
        assert!(memo.answer([1, 2, 3, 4], || true));
        let memo = Recent::<5>::default();
        assert!(!memo.answer([5, 6, 7, 8, 9], || false));
        assert!(!memo.answer([5, 6, 7, 8, 9], || unreachable!()));
    }
}
