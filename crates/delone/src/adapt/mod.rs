//! Mesh adaptation to a metric field: local remeshing of a triangle or
//! tetrahedral mesh so that its edges have unit length and its elements are
//! regular in a metric given at the vertices or by a function.
//!
//! The input is a [`SimplexMesh`] (points, elements and boundary faces with
//! their references, corners, ridges, required vertices) and a
//! [`MetricField`]; the output is an [`Adapted`] mesh with the metric at its
//! vertices and an [`AdaptReport`] (metric edge lengths and element quality
//! before and after, operation counts, time per phase).
//! [`metric_stats`] measures any mesh against a metric the same way (the
//! benchmark measures MMG's output with it).
//!
//! ```
//! use delone::adapt::metric_stats;
//! use delone::metric::Metric;
//! // The unit right triangle in the metric of size 1: edges 1, 1, √2.
//! let s = metric_stats(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]], &[[0, 1, 2]], &[Metric::isotropic(1.0); 3]);
//! assert_eq!((s.edges, s.in_range), (3, 3));
//! assert!((s.quality_min - 0.866).abs() < 1e-3);
//! ```

mod mesh;
mod stats;
mod tet;
mod tri;

pub use mesh::{AdaptOptions, AdaptReport, Adapted, MetricField, SimplexMesh, TetMesh, TriMesh};
pub use stats::{metric_stats, MetricStats, LENGTH_BINS, QUALITY_BINS};
pub use tet::adapt_tet;
pub use tri::adapt_tri;
