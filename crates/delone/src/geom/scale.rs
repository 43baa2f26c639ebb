//! Exact power-of-two rescaling of extreme coordinates.

use std::borrow::Cow;

/// Exact power-of-two scaling that brings coordinates whose largest magnitude
/// is `max_abs` into the range where the exact predicates neither overflow nor
/// underflow (`incircle` is of degree 4).
///
/// Returns two factors to apply one after the other (each a power of two, so
/// that neither overflows), `(1.0, 1.0)` when `max_abs` is already in
/// `[2^-60, 2^60]` or zero. Multiplying by a power of two is exact (barring
/// underflow of coordinates more than ~2^900 times smaller than the largest),
/// so every predicate keeps its sign and equal points stay equal.
///
/// ```
/// use delone::geom::{pow2_scale, scaled};
/// assert_eq!(pow2_scale(1e6), (1.0, 1.0));
/// let s = pow2_scale(1e200);
/// let p = scaled([1e200, -3e199], s);
/// assert!(p[0] >= 1.0 && p[0] < 2.0);
/// ```
pub fn pow2_scale(max_abs: f64) -> (f64, f64) {
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
///
/// ```
/// assert_eq!(delone::geom::scaled([3.0, 5.0], (0.5, 0.25)), [0.375, 0.625]);
/// ```
#[inline]
pub fn scaled<const D: usize>(p: [f64; D], s: (f64, f64)) -> [f64; D] {
    p.map(|c| c * s.0 * s.1)
}

/// The largest finite coordinate magnitude of `points` (0 for none).
///
/// ```
/// assert_eq!(delone::geom::max_abs(&[[1.0, -4.0], [2.0, f64::NAN]]), 4.0);
/// ```
pub fn max_abs<const D: usize>(points: &[[f64; D]]) -> f64 {
    points
        .iter()
        .flatten()
        .filter(|c| c.is_finite())
        .fold(0.0f64, |m, c| m.max(c.abs()))
}

/// `points` themselves when their magnitudes are moderate, otherwise a copy
/// scaled by [`pow2_scale`], together with the factors used.
///
/// ```
/// let pts = [[1e-200, 0.0, 0.0], [0.0, 2e-200, 0.0]];
/// let (p, s) = delone::geom::rescaled(&pts);
/// assert!(matches!(p, std::borrow::Cow::Owned(_)) && s != (1.0, 1.0));
/// let (q, _) = delone::geom::rescaled(&[[1.0, 2.0, 3.0]]);
/// assert!(matches!(q, std::borrow::Cow::Borrowed(_)));
/// ```
pub fn rescaled<const D: usize>(points: &[[f64; D]]) -> (Cow<'_, [[f64; D]]>, (f64, f64)) {
    let s = pow2_scale(max_abs(points));
    if s == (1.0, 1.0) {
        (Cow::Borrowed(points), s)
    } else {
        (
            Cow::Owned(points.iter().map(|&p| scaled(p, s)).collect()),
            s,
        )
    }
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
