//! 2D Delaunay triangulation.
//!
//! * [`triangulate`] — one call, flat output ([`TriMesh`]).
//! * [`mesh()`] — the meshing pipeline of a PSLG in one call ([`TriOptions`], [`TriResult`]).
//! * [`Delaunay2`] — the incremental kernel (insert, locate, check).
//! * [`validate`] — an independent checker of a [`TriMesh`] against its points.

pub(crate) mod adapt_ops;
pub(crate) mod cmesh;
pub mod conforming;
pub mod constrain;
pub mod delaunay;
pub mod domain;
pub mod existing;
pub mod mesh;
pub mod options;
pub mod pipeline;
pub mod quality;
pub mod refine;
pub(crate) mod topo;
mod triangulate;
pub mod voronoi;

pub use constrain::{check_cdt, constrained_triangulation, Cdt, CdtOptions};
pub use delaunay::{Delaunay2, Inserted, Location};
pub use domain::{boundary_rings, lloyd_in_domain, DomainCells2};
pub use mesh::{validate, validate_regular, TriMesh};
pub use options::TriOptions;
pub use pipeline::{mesh, TriError, TriResult};
pub use refine::{refine, RefineOptions, RefineReport, Refined};
pub use triangulate::{regular_triangulation, triangulate};
pub use voronoi::{lloyd, Voronoi2};
