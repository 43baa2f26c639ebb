//! The one-call 2D Delaunay and regular triangulations (flat output).

use super::{Delaunay2, TriMesh};
use crate::Error;

/// Delaunay triangulation of `points` (BRIO + Hilbert incremental insertion,
/// exact predicates, symbolic perturbation for cocircular points).
///
/// Vertex ids in the output are indices into `points`. Exact duplicate points
/// are merged: see [`TriMesh::vertex_map`] and [`TriMesh::duplicates`].
///
/// # Errors
/// [`Error::InvalidCoordinate`] for NaN/infinite coordinates,
/// [`Error::TooFewPoints`] for fewer than 3 distinct points,
/// [`Error::Degenerate`] when all points are collinear,
/// [`Error::CapacityExceeded`] beyond `u32` indices.
///
/// ```
/// let mesh = delone::triangulate(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.0, 0.0]]).unwrap();
/// assert_eq!(mesh.triangles.len(), 1);
/// assert_eq!(mesh.duplicates, vec![(3, 0)]);
/// ```
pub fn triangulate(points: &[[f64; 2]]) -> Result<TriMesh, Error> {
    Ok(Delaunay2::from_points(points)?.into_mesh())
}

/// Regular (weighted Delaunay) triangulation of `points` with `weights`,
/// the dual of their power diagram: see [`Delaunay2::from_weighted_points`].
/// Points whose power cell is empty are listed in [`TriMesh::hidden`] (their
/// [`TriMesh::vertex_map`] entry is [`crate::NONE`]). With all weights zero
/// the result equals [`triangulate`]'s exactly.
///
/// # Errors
/// Those of [`triangulate`], plus [`Error::WeightCount`] and
/// [`Error::InvalidWeight`] (naming the point).
///
/// ```
/// let pts = [[0.0, 0.0], [4.0, 0.0], [0.0, 4.0], [4.0, 4.0], [2.0, 2.0]];
/// let mesh = delone::tri::regular_triangulation(&pts, &[1.0, 1.0, 1.0, 1.0, -8.0]).unwrap();
/// assert_eq!(mesh.hidden, vec![4]);
/// assert_eq!(mesh.vertex_map[4], delone::NONE);
/// delone::tri::validate_regular(&pts, &[1.0, 1.0, 1.0, 1.0, -8.0], &mesh).unwrap();
/// ```
pub fn regular_triangulation(points: &[[f64; 2]], weights: &[f64]) -> Result<TriMesh, Error> {
    Ok(Delaunay2::from_weighted_points(points, weights)?.into_mesh())
}
