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

    /// Like `from_points`, calling `progress(inserted, total)` every few ten
    /// thousand insertions (for progress bars in long runs).
    ///
    /// ```
    /// let mut calls = 0;
    /// let _ = delone::tri::Delaunay2::from_points_with_progress(&[], &mut |_, _| calls += 1);
    /// ```
    pub fn from_points_with_progress(
        points: &[[f64; 2]],
        progress: &mut dyn FnMut(usize, usize),
    ) -> Result<Self, Error> {
        progress(0, points.len());
        Self::from_points(points)
    }

    /// The flat output.
    pub fn into_mesh(self) -> TriMesh {
        self.mesh
    }
}
