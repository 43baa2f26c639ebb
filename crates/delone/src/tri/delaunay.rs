//! The incremental 2D Delaunay kernel (placeholder until implemented).

use super::TriMesh;
use crate::Error;

/// Incremental 2D Delaunay triangulation.
#[derive(Debug, Clone, Default)]
pub struct Delaunay2 {
    mesh: TriMesh,
}

impl Delaunay2 {
    /// Builds the triangulation of `points` in BRIO order.
    ///
    /// ```
    /// let _ = delone::tri::Delaunay2::from_points(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]);
    /// ```
    pub fn from_points(points: &[[f64; 2]]) -> Result<Self, Error> {
        Err(Error::TooFewPoints {
            found: points.len(),
            needed: 3,
        })
    }

    /// The flat output.
    pub fn into_mesh(self) -> TriMesh {
        self.mesh
    }
}
