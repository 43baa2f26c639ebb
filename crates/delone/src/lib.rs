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

pub mod adapt;
pub mod error;
pub mod geom;
pub mod metric;
pub mod model;
mod par;
pub mod progress;
pub mod switches;
pub mod tet;
pub mod tri;
mod types;

pub use error::{Error, FacetDefect, MetricDefect, Violation};
pub use tet::{tetrahedralize, TetMesh};
pub use tri::{triangulate, TriMesh};
pub use types::{Inserted, NONE};
