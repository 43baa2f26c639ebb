//! Metric fields for mesh adaptation: the metric tensor ([`Metric`]: sizes
//! and directions, log-Euclidean interpolation, intersection, bounds,
//! edge lengths, mean ratio), the mesh's own sizes ([`metric_from_mesh`]),
//! Hessian recovery from a solution field ([`hessians`]), the metric that
//! minimises the interpolation error for a complexity or an error level ([`metric_from_hessians`], [`Target`]) and
//! size gradation ([`gradate`]). Each works on plain arrays (points,
//! elements, values at the vertices), in 2D and 3D alike (`D` = 2 or 3,
//! `K = D + 1` corners per element).
//!
//! ```
//! use delone::metric::{edges, gradate, hessians, metric_from_hessians, Target};
//! // A field with a sharp layer along x = 0.5, on a Delaunay mesh of a grid.
//! let pts: Vec<[f64; 2]> = (0..21 * 21).map(|i| [(i % 21) as f64 / 20.0, (i / 21) as f64 / 20.0]).collect();
//! let tris = delone::triangulate(&pts).unwrap().triangles;
//! let u: Vec<f64> = pts.iter().map(|p| (10.0 * (p[0] - 0.5)).tanh()).collect();
//! let h = hessians(&pts, &tris, &u).unwrap();
//! let mut m = metric_from_hessians(&pts, &tris, &h, Target::Complexity { complexity: 500.0, p: 2.0 }, 1e-3, 0.5).unwrap();
//! gradate(&pts, &edges(&tris), &mut m, 1.3);
//! // Smaller along x near the layer than far from it.
//! let near = m[9].sizes()[0]; // x = 0.45, where the curvature is largest
//! let far = m[0].sizes()[0]; // x = 0
//! assert!(near < far);
//! ```

mod field;
mod tensor;

pub use crate::error::MetricDefect;
pub use field::{
    complexity, edges, gradate, hessians, metric_from_hessians, metric_from_mesh, Target,
};
#[cfg(test)]
pub(crate) use tensor::compose;
pub(crate) use tensor::tet_quality;
pub use tensor::{mean_ratio, Metric};
