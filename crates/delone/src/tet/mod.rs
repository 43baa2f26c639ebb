//! 3D Delaunay tetrahedralization.
//!
//! * [`tetrahedralize`] — one call, flat output ([`TetMesh`]).
//! * [`mesh()`] — the meshing pipeline of a PLC in one call ([`TetOptions`], [`TetResult`]).
//! * [`Delaunay3`] — the incremental kernel (insert, locate, check).
//! * [`validate`] — an independent checker of a [`TetMesh`] against its points.
//! * [`intersect`] — exact self-intersection and closedness checks of triangulated surfaces.

pub mod delaunay;
pub(crate) mod dmesh;
pub mod facets;
mod flat;
pub mod intersect;
pub mod local;
pub mod mesh;
pub mod optimize;
pub mod options;
pub mod pipeline;
pub mod quality;
pub mod recover;
pub mod refine;
mod tetrahedralize;
pub mod voronoi;

pub use delaunay::{Delaunay3, Inserted, Location};
pub use mesh::{validate, validate_regular, TetMesh};
pub use options::TetOptions;
pub use pipeline::{mesh, TetError, TetResult};
pub use tetrahedralize::{regular_tetrahedralization, tetrahedralize};
pub use voronoi::{lloyd, Voronoi3};
