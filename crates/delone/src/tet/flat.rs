//! [`TetMesh`], the flat output of the 3D kernel (checked by
//! [`crate::tet::validate`]).

use super::local::FACET;
use crate::NONE;

/// A tetrahedralization in flat arrays, as returned by [`crate::tetrahedralize`].
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct TetMesh {
    /// Tetrahedra `[a, b, c, d]` with positive volume: `(b-a)×(c-a)·(d-a) > 0`
    /// (indices into the input points).
    pub tets: Vec<[u32; 4]>,
    /// `neighbors[t][i]` is the tetrahedron across the face opposite vertex `i`
    /// of tetrahedron `t`, or [`crate::NONE`] on the convex hull.
    pub neighbors: Vec<[u32; 4]>,
    /// For every input point, the vertex that represents it: itself, or the
    /// lowest-indexed point with identical coordinates.
    pub vertex_map: Vec<u32>,
    /// Input points that duplicate a lower-indexed one, as `(duplicate, original)`,
    /// sorted by duplicate.
    pub duplicates: Vec<(u32, u32)>,
    /// Input points left out of a *regular* (weighted) triangulation
    /// because their power cell is empty ("hidden" or redundant points),
    /// sorted; their `vertex_map` entry is [`crate::NONE`]. Always empty for
    /// unweighted input.
    pub hidden: Vec<u32>,
}

impl TetMesh {
    /// The faces of tetrahedron `t` on the convex hull, oriented outward
    /// (counterclockwise seen from outside), as `(t, local face)` pairs over
    /// the whole mesh.
    ///
    /// ```
    /// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    /// let mesh = delone::tetrahedralize(&pts).unwrap();
    /// assert_eq!(mesh.hull_faces().count(), 4);
    /// ```
    pub fn hull_faces(&self) -> impl Iterator<Item = [u32; 3]> + '_ {
        self.tets.iter().zip(&self.neighbors).flat_map(|(tv, nb)| {
            (0..4).filter(move |&f| nb[f] == NONE).map(move |f| {
                let [a, b, c] = FACET[f].map(|i| tv[i]);
                [a, c, b]
            })
        })
    }
}
