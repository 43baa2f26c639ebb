//! 2D adaptation on the constrained triangle mesh.

use super::{AdaptOptions, Adapted, MetricField, TriMesh};
use crate::Error;

/// Adapts a triangle mesh to a metric field.
///
/// ```
/// // See the module documentation.
/// ```
pub fn adapt_tri(
    mesh: &TriMesh,
    metric: MetricField<'_, 2>,
    options: &AdaptOptions,
) -> Result<Adapted<2, 3>, Error> {
    let _ = (mesh, metric, options);
    todo!("2D adaptation engine")
}
