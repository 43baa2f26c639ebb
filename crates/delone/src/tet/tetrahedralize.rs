//! The one-call 3D Delaunay and regular tetrahedralizations (flat output).

use super::{Delaunay3, TetMesh};
use crate::Error;

/// Delaunay tetrahedralization of `points`.
///
/// Vertex ids in the output are indices into `points`; exact duplicates are
/// merged (see [`TetMesh::vertex_map`]).
///
/// # Errors
/// [`Error::InvalidCoordinate`], [`Error::TooFewPoints`] (fewer than 4 distinct
/// points), [`Error::Degenerate`] (all points coplanar or collinear),
/// [`Error::CapacityExceeded`].
///
/// ```
/// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
/// let mesh = delone::tetrahedralize(&pts).unwrap();
/// assert_eq!(mesh.tets.len(), 1);
/// ```
pub fn tetrahedralize(points: &[[f64; 3]]) -> Result<TetMesh, Error> {
    Ok(Delaunay3::from_points(points)?.into_mesh())
}

/// Regular (weighted Delaunay) tetrahedralization of `points` with
/// `weights`, the dual of their power diagram. Points with an empty power
/// cell are listed in [`TetMesh::hidden`]; all-zero weights give exactly
/// [`tetrahedralize`]'s output.
///
/// # Errors
/// As [`tetrahedralize`], plus [`Error::InvalidWeight`] and
/// [`Error::WeightCount`].
///
/// ```
/// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 1.0, 1.0]];
/// let a = delone::tet::regular_tetrahedralization(&pts, &[0.0; 5]).unwrap();
/// assert_eq!(a, delone::tetrahedralize(&pts).unwrap());
/// ```
pub fn regular_tetrahedralization(points: &[[f64; 3]], weights: &[f64]) -> Result<TetMesh, Error> {
    Ok(Delaunay3::from_weighted_points(points, weights)?.into_mesh())
}
