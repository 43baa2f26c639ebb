//! The incremental 3D Delaunay kernel (placeholder until implemented).

use super::TetMesh;
use crate::Error;

/// Incremental 3D Delaunay tetrahedralization.
#[derive(Debug, Clone, Default)]
pub struct Delaunay3 {
    mesh: TetMesh,
}

impl Delaunay3 {
    /// Builds the tetrahedralization of `points` in BRIO order.
    ///
    /// ```
    /// let _ = delone::tet::Delaunay3::from_points(&[[0.0, 0.0, 0.0]]);
    /// ```
    pub fn from_points(points: &[[f64; 3]]) -> Result<Self, Error> {
        Err(Error::TooFewPoints {
            found: points.len(),
            needed: 4,
        })
    }

    /// The flat output.
    pub fn into_mesh(self) -> TetMesh {
        self.mesh
    }
}
