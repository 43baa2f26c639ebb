//! Geometry helpers shared by the 2D and 3D kernels: insertion order
//! (BRIO + Hilbert curve) and small vector utilities.

pub mod check;
pub(crate) mod ids;
pub mod scale;
pub mod sort;
pub(crate) mod vec3;

pub use scale::{max_abs, pow2_scale, rescaled, scaled};
pub use sort::{brio_order, SplitMix64};
