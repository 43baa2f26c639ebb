//! # delone
//!
//! Robust, fast Delaunay triangulation and meshing in 2D and 3D.
//!
//! The one-call API:
//!
//! ```
//! let pts = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]];
//! let mesh = delone::triangulate(&pts).unwrap();
//! assert_eq!(mesh.triangles.len(), 2);
//!
//! let pts3 = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 1.0, 1.0]];
//! let mesh3 = delone::tetrahedralize(&pts3).unwrap();
//! assert_eq!(mesh3.tets.len(), 2);
//! ```
//!
//! The meshing pipelines, one call each with options read from the switch
//! strings of `delone tri` / `delone tet`:
//!
//! ```
//! use delone::{model::pslg::Pslg, tri::TriOptions};
//! let g = Pslg::new(vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
//!                   vec![[0, 1], [1, 2], [2, 3], [3, 0]]);
//! let r = delone::tri::mesh(&g, &TriOptions::from_switches("pq30a0.05").unwrap()).unwrap();
//! assert!(r.mesh.triangles.len() > 20);
//! ```
//!
//! ([`tri::mesh()`], [`tet::mesh()`]). The incremental API lives in
//! [`tri::Delaunay2`] and [`tet::Delaunay3`].
#![forbid(unsafe_code)]

pub mod error;
pub mod geom;
pub mod model;
pub mod progress;
pub mod switches;
pub mod tet;
pub mod tri;

pub use error::{Error, FacetDefect, Violation};
pub use tet::{tetrahedralize, TetMesh};
pub use tri::{triangulate, TriMesh};

/// What became of a point given to an incremental kernel
/// ([`tri::Delaunay2::insert`], [`tet::Delaunay3::insert`]). Ids are indices
/// among all points given so far.
///
/// ```
/// use delone::{tri::Delaunay2, Inserted};
/// let mut d = Delaunay2::new();
/// assert_eq!(d.insert([0.0, 0.0]).unwrap(), Inserted::Pending(0));
/// assert_eq!(d.insert([0.0, 0.0]).unwrap(), Inserted::Duplicate { id: 1, original: 0 });
/// assert_eq!(d.insert([1.0, 0.0]).unwrap(), Inserted::Pending(2));
/// assert_eq!(d.insert([0.0, 1.0]).unwrap(), Inserted::Vertex(3));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Inserted {
    /// The point became vertex `id`.
    Vertex(u32),
    /// The point has the same coordinates as an earlier point and was not
    /// inserted (it still gets an id).
    Duplicate {
        /// Id of the duplicate point.
        id: u32,
        /// The vertex (or pending point) it coincides with.
        original: u32,
    },
    /// No triangle/tetrahedron exists yet (all points so far are collinear /
    /// coplanar); the point is kept and becomes a vertex as soon as one does.
    Pending(u32),
    /// Regular (weighted) triangulations only: the point's power cell is
    /// empty, so it is not a vertex ("hidden" or redundant point).
    Hidden(u32),
}

/// Marker for "no element" in index arrays (a missing neighbour, an unused slot).
pub const NONE: u32 = u32::MAX;
