//! 2D Delaunay triangulation.
//!
//! * [`triangulate`] — one call, flat output ([`TriMesh`]).
//! * [`Delaunay2`] — the incremental kernel (insert, locate, check).
//! * [`validate`] — an independent checker of a [`TriMesh`] against its points.

pub mod constrain;
pub mod delaunay;
pub mod mesh;
pub mod refine;
mod topo;

pub use constrain::{check_cdt, constrained_triangulation, Cdt, CdtOptions};
pub use delaunay::{Delaunay2, Inserted, Location};
pub use mesh::{validate, TriMesh};
pub use refine::{refine, RefineOptions, RefineReport, Refined};

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
