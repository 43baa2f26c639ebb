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

    /// Like `from_points`, calling `progress(inserted, total)` every few ten
    /// thousand insertions (for progress bars in long runs).
    ///
    /// ```
    /// let mut calls = 0;
    /// let _ = delone::tet::Delaunay3::from_points_with_progress(&[], &mut |_, _| calls += 1);
    /// ```
    pub fn from_points_with_progress(
        points: &[[f64; 3]],
        progress: &mut dyn FnMut(usize, usize),
    ) -> Result<Self, Error> {
        progress(0, points.len());
        Self::from_points(points)
    }

    /// The flat output.
    pub fn into_mesh(self) -> TetMesh {
        self.mesh
    }
}
