//! Local numbering conventions of a tetrahedron, shared by every 3D module.
//!
//! ```text
//!                 v3
//!                /|\
//!               / | \          A tetrahedron [v0, v1, v2, v3] is *positive* when
//!              /  |  \         (v1-v0) × (v2-v0) · (v3-v0) > 0, i.e. v3 sees
//!             /   |   \        v0 → v1 → v2 counterclockwise.
//!            /    v2   \
//!           /   .    .  \      Facet f is the triangle opposite vertex f.
//!          / .         . \     FACET[f] lists its vertices in the order that
//!         v0 ------------ v1   makes (FACET[f], v_f) a positive tetrahedron:
//!                              v_f lies on the positive side of FACET[f].
//! ```
//!
//! Adjacency words pack a neighbour and the mirror facet in one `u32`:
//! `word = 4 * tet + facet`, so `word >> 2` is the neighbouring tetrahedron
//! and `word & 3` the index, *in the neighbour*, of the shared facet.
//!
//! Ghost tetrahedra on the convex hull hold the [`INF`] vertex in position 3
//! (kept there by even permutations when cells are created), so a ghost test
//! is one comparison; their finite facet `FACET[3] = [0, 1, 2]` is a hull
//! triangle oriented so that the outside of the hull is its positive side.

/// The vertex "at infinity" that closes the convex hull with ghost cells.
pub const INF: u32 = u32::MAX - 1;

/// Value of `v[0]` of a dead (free-listed) tetrahedron slot.
pub const DEAD: u32 = u32::MAX;

/// `FACET[f]`: the local vertices of facet `f`, ordered so that
/// `[FACET[f][0], FACET[f][1], FACET[f][2], f]` is an even permutation of
/// `[0, 1, 2, 3]` (vertex `f` on the positive side).
pub const FACET: [[usize; 3]; 4] = [[1, 3, 2], [0, 2, 3], [0, 3, 1], [0, 1, 2]];

/// The local vertex pairs of the six edges of a tetrahedron.
pub const EDGES: [(usize, usize); 6] = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)];

/// The face of `tv` opposite local vertex `f`, in [`FACET`] order.
#[inline]
pub(crate) fn face(tv: [u32; 4], f: usize) -> [u32; 3] {
    FACET[f].map(|i| tv[i])
}

/// The sorted key of a triangle.
#[inline]
pub(crate) fn fkey(t: [u32; 3]) -> [u32; 3] {
    // A three-element sorting network (no call into the general sort).
    let [a, b, c] = t;
    let (a, b) = (a.min(b), a.max(b));
    let (b, c) = (b.min(c), b.max(c));
    let (a, b) = (a.min(b), a.max(b));
    [a, b, c]
}

/// The sorted key of an edge.
#[inline]
pub(crate) fn ekey(a: u32, b: u32) -> (u32, u32) {
    if a < b {
        (a, b)
    } else {
        (b, a)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parity(p: [usize; 4]) -> bool {
        let mut even = true;
        for i in 0..4 {
            for j in i + 1..4 {
                if p[i] > p[j] {
                    even = !even;
                }
            }
        }
        even
    }

    #[test]
    fn keys_sort() {
        for t in [
            [1, 2, 3],
            [3, 2, 1],
            [2, 3, 1],
            [1, 3, 2],
            [3, 1, 2],
            [2, 1, 3],
        ] {
            assert_eq!(fkey(t), [1, 2, 3]);
        }
        assert_eq!(ekey(5, 2), (2, 5));
        assert_eq!(face([10, 11, 12, 13], 0), [11, 13, 12]);
    }

    #[test]
    fn facets_are_even_permutations() {
        for (f, fv) in FACET.iter().enumerate() {
            assert!(parity([fv[0], fv[1], fv[2], f]), "facet {f}");
            assert!(!fv.contains(&f));
        }
    }
}
