//! 3D adaptation on the constrained tetrahedral mesh.

use super::{AdaptOptions, Adapted, MetricField, TetMesh};
use crate::Error;

/// Adapts a tetrahedral mesh to a metric field.
///
/// ```
/// // See the module documentation.
/// ```
pub fn adapt_tet(
    mesh: &TetMesh,
    metric: MetricField<'_, 3>,
    options: &AdaptOptions,
) -> Result<Adapted<3, 4>, Error> {
    let _ = (mesh, metric, options);
    todo!("3D adaptation engine")
}
