//! 2D Delaunay triangulation.
//!
//! * [`triangulate`] — one call, flat output ([`TriMesh`]).
//! * [`Delaunay2`] — the incremental kernel (insert, locate, check).
//! * [`validate`] — an independent checker of a [`TriMesh`] against its points.

pub mod delaunay;
pub mod mesh;
mod topo;
pub mod voronoi;

pub use delaunay::{Delaunay2, Inserted, Location};
pub use mesh::{validate, TriMesh};
pub use voronoi::{lloyd, Voronoi2};

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

/// Exact power-of-two scaling that brings coordinates whose largest magnitude
/// is `max_abs` into the range where the exact predicates neither overflow nor
/// underflow (`incircle` is of degree 4).
///
/// Returns two factors to apply one after the other (each a power of two, so
/// that neither overflows), `(1.0, 1.0)` when `max_abs` is already in
/// `[2^-60, 2^60]` or zero. Multiplying by a power of two is exact (barring
/// underflow of coordinates more than ~2^900 times smaller than the largest),
/// so every predicate keeps its sign and equal points stay equal.
pub(crate) fn pow2_scale(max_abs: f64) -> (f64, f64) {
    const WINDOW: i32 = 60;
    if max_abs == 0.0 || !max_abs.is_finite() {
        return (1.0, 1.0);
    }
    // Binary exponent of max_abs (exact, also for subnormals).
    let bits = max_abs.to_bits();
    let biased = ((bits >> 52) & 0x7ff) as i32;
    let e = if biased == 0 {
        let mantissa = bits & ((1u64 << 52) - 1);
        -1074 + (63 - mantissa.leading_zeros() as i32)
    } else {
        biased - 1023
    };
    if (-WINDOW..=WINDOW).contains(&e) {
        return (1.0, 1.0);
    }
    let k = -e;
    (2f64.powi(k / 2), 2f64.powi(k - k / 2))
}

/// Applies [`pow2_scale`] factors to a point.
#[inline]
pub(crate) fn scaled(p: [f64; 2], s: (f64, f64)) -> [f64; 2] {
    [p[0] * s.0 * s.1, p[1] * s.0 * s.1]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pow2_scale_is_exact_and_bounded() {
        assert_eq!(pow2_scale(1e6), (1.0, 1.0));
        assert_eq!(pow2_scale(1e-9), (1.0, 1.0));
        assert_eq!(pow2_scale(0.0), (1.0, 1.0));
        for m in [1e150, 1e300, f64::MAX, 1e-150, 1e-300, 5e-324] {
            let s = pow2_scale(m);
            let x = scaled([m, -m], s);
            assert!((1.0..2.0).contains(&x[0]), "{m:e} -> {}", x[0]);
            assert_eq!(x[1], -x[0]);
        }
    }
}
