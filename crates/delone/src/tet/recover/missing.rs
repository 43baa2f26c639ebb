//! Which input edges and triangles are missing from a tetrahedralization
//! (exact, by vertex ids).

use crate::tet::local::{ekey, face, fkey, EDGES};
use std::collections::HashSet;

/// The input edges and triangles that are not edges and faces of a
/// tetrahedralization, as found by [`missing`].
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Missing {
    /// Input edges `[a, b]` (`a < b`) that are not mesh edges, sorted.
    pub edges: Vec<[u32; 2]>,
    /// Indices of the input triangles that are not mesh faces, ascending.
    pub triangles: Vec<usize>,
}

impl Missing {
    /// True when every input edge and triangle is present.
    ///
    /// ```
    /// assert!(delone::tet::recover::Missing::default().is_empty());
    /// ```
    pub fn is_empty(&self) -> bool {
        self.edges.is_empty() && self.triangles.is_empty()
    }
}

/// Which edges and triangles of a triangulated surface are missing from the
/// tetrahedra `tets` — exactly, by vertex ids (no geometry involved).
///
/// `tets` can be [`crate::TetMesh::tets`] or [`super::super::Delaunay3::tets`].
/// Edges are reported once with their smaller id first, in sorted order.
///
/// ```
/// use delone::tet::recover::missing;
/// // Two tetrahedra sharing face 0-1-2: edge 3-4 is not an edge.
/// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.2, 0.2, 1.0], [0.2, 0.2, -1.0]];
/// let dt = delone::tet::Delaunay3::from_points(&pts).unwrap();
/// let m = missing(&[[0, 1, 2], [3, 4, 0]], dt.tets());
/// assert_eq!(m.edges, vec![[3, 4]]);
/// assert_eq!(m.triangles, vec![1]);
/// // The same from the flat mesh.
/// let mesh = delone::tetrahedralize(&pts).unwrap();
/// assert_eq!(missing(&[[0, 1, 2], [3, 4, 0]], mesh.tets.iter().copied()), m);
/// ```
pub fn missing(triangles: &[[u32; 3]], tets: impl IntoIterator<Item = [u32; 4]>) -> Missing {
    let mut edges = HashSet::new();
    let mut faces = HashSet::new();
    for tv in tets {
        for (i, j) in EDGES {
            edges.insert(ekey(tv[i], tv[j]));
        }
        for f in 0..4 {
            faces.insert(fkey(face(tv, f)));
        }
    }
    let mut out = Missing::default();
    let mut seen = HashSet::new();
    for (i, t) in triangles.iter().enumerate() {
        for k in 0..3 {
            let e = ekey(t[k], t[(k + 1) % 3]);
            if !edges.contains(&e) && seen.insert(e) {
                out.edges.push([e.0, e.1]);
            }
        }
        if !faces.contains(&fkey(*t)) {
            out.triangles.push(i);
        }
    }
    out.edges.sort_unstable();
    out
}
