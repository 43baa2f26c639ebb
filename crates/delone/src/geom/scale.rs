//! Exact power-of-two rescaling of extreme coordinates.

use crate::geom::vec3::P;
use crate::Error;
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
    let e = exponent(max_abs);
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
#[inline]
pub fn max_abs<const D: usize>(points: &[[f64; D]]) -> f64 {
    let mut m = 0.0f64;
    for p in points {
        for &c in p {
            // (A NaN fails the first comparison, an infinity the second.)
            let a = c.abs();
            if a > m && a != f64::INFINITY {
                m = a;
            }
        }
    }
    m
}

/// The bounding box `[min, max]` of `pts` (inverted, `[+inf, -inf]`, when
/// empty; NaN coordinates are passed over).
pub(crate) fn bbox<'a, const D: usize>(
    pts: impl IntoIterator<Item = &'a [f64; D]>,
) -> [[f64; D]; 2] {
    let mut bb = [[f64::INFINITY; D], [f64::NEG_INFINITY; D]];
    for p in pts {
        for k in 0..D {
            bb[0][k] = bb[0][k].min(p[k]);
            bb[1][k] = bb[1][k].max(p[k]);
        }
    }
    bb
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

/// How many binary orders of magnitude a nonzero coordinate may lie below
/// the largest coordinate magnitude of a 2D input (see [`check_range`]).
///
/// The exact predicates are exact as long as no partial product
/// underflows. After the power-of-two rescale the largest magnitude is in
/// `[1, 2)` and a coordinate of magnitude `2^-r` is a multiple of
/// `2^(-r-52)`; a product of `k` such numbers is a multiple of
/// `2^(-k(r+52))`, which is representable (as a normal or subnormal double)
/// iff `k(r + 52) <= 1074`. `incircle` is of degree 4: `r <= 216`.
pub const RANGE_2D: i32 = 216;

/// The same for 3D inputs: `insphere` is of degree 5, `r <= 162`.
pub const RANGE_3D: i32 = 162;

/// The binary exponent of a finite nonzero `x` (`floor(log2 |x|)`, exact,
/// also for subnormals).
fn exponent(x: f64) -> i32 {
    let bits = x.abs().to_bits();
    let biased = ((bits >> 52) & 0x7ff) as i32;
    if biased == 0 {
        let mantissa = bits & ((1u64 << 52) - 1);
        -1074 + (63 - mantissa.leading_zeros() as i32)
    } else {
        biased - 1023
    }
}

/// Checks that every coordinate is within the range where the exact
/// predicates are exact.
///
/// The absolute scale does not matter: every kernel and checker rescales
/// by a power of two (exact), so any finite coordinates, subnormal ones
/// included, work. What the exact arithmetic cannot handle is a *dynamic
/// range* too wide: a nonzero coordinate more than `2^range` times smaller
/// than the largest coordinate magnitude (`range` is [`RANGE_2D`] or
/// [`RANGE_3D`], about 1e65 and 1e48), whose products in the predicates'
/// expansions would underflow. Zero coordinates are always fine.
/// Non-finite coordinates are skipped (reported elsewhere as
/// [`Error::InvalidCoordinate`]).
///
/// # Errors
/// [`Error::CoordinateRange`] naming the first such coordinate (point
/// index, axis, value) and the largest magnitude.
///
/// ```
/// use delone::geom::scale::{check_range, RANGE_3D};
/// assert!(check_range(&[[1e-300, 2e-300, 0.0], [3e-300, 0.0, 1e-301]], RANGE_3D).is_ok());
/// assert!(check_range(&[[1e300, 1e290, 0.0]], RANGE_3D).is_ok());
/// assert!(check_range(&[[1e300, 1.0, 0.0]], RANGE_3D).is_err());
/// let e = check_range(&[[1.0, 0.0, 0.0], [0.0, 1e-60, 0.0]], RANGE_3D).unwrap_err();
/// assert!(matches!(e, delone::Error::CoordinateRange { index: 1, axis: 1, .. }));
/// ```
pub fn check_range<const D: usize>(points: &[[f64; D]], range: i32) -> Result<(), Error> {
    let max = max_abs(points);
    if max == 0.0 {
        return Ok(());
    }
    let floor = exponent(max) - range;
    for (index, p) in points.iter().enumerate() {
        for (axis, &c) in p.iter().enumerate() {
            if c != 0.0 && c.is_finite() && exponent(c) < floor {
                return Err(Error::CoordinateRange {
                    index,
                    axis,
                    value: c,
                    max,
                });
            }
        }
    }
    Ok(())
}

/// A volume (any quantity cubic in the coordinates) measured on points
/// scaled by `s` (from [`pow2_scale`]), in the input's units:
/// `v / (s.0 s.1)^3`, by steps that are exact powers of two, so the result
/// is exact unless it leaves the range of normal doubles (then the nearest
/// subnormal, zero or infinity).
///
/// ```
/// let s = delone::geom::pow2_scale(1e-80);
/// let v = 0.75; // measured on the scaled points
/// let w = delone::geom::scale::unscale_cubic(v, s);
/// assert_eq!(delone::geom::scale::unscale_cubic(w, (1.0 / s.0, 1.0 / s.1)), v);
/// ```
pub fn unscale_cubic(v: f64, s: (f64, f64)) -> f64 {
    unscale(v, s, 3)
}

/// The points of a mesh made on rescaled points `scaled` whose first ones
/// are the caller's `input`, in input units: `input` as given, then the
/// rest of `scaled` (Steiner points) times `unscale`.
pub(crate) fn unscaled_points(input: &[P], scaled: &[P], unscale: f64) -> Vec<P> {
    let mut out = input[..input.len().min(scaled.len())].to_vec();
    out.extend(
        scaled
            .iter()
            .skip(input.len())
            .map(|p| p.map(|c| c * unscale)),
    );
    out
}

/// A quantity of the given `degree` in the coordinates (1 for lengths, 2
/// for areas, 3 for volumes) measured on points scaled by `s` (from
/// [`pow2_scale`]), in the input's units: `v / (s.0 s.1)^degree`, exact
/// unless the result leaves the range of normal doubles.
///
/// ```
/// let s = delone::geom::pow2_scale(1e200);
/// let x = delone::geom::scaled([1e200, 0.0], s)[0];
/// assert_eq!(delone::geom::scale::unscale(x, s, 1), 1e200);
/// ```
pub fn unscale(v: f64, s: (f64, f64), degree: u32) -> f64 {
    // s.0 and s.1 are both >= 1 or both <= 1: the steps are monotone, so
    // no intermediate value overflows unless the result does.
    let mut v = v;
    for _ in 0..degree {
        v = v / s.0 / s.1;
    }
    v
}

/// The points of one element scaled by [`pow2_scale`] of their own largest
/// magnitude (unchanged when it is moderate), with the factors: element
/// measures computed on them neither overflow nor underflow, and are the
/// same (angles, ratios bit for bit) at every power-of-two scale.
///
/// ```
/// let (p, s) = delone::geom::scale::local([[1e300, 0.0], [0.0, 1e300], [0.0, 0.0]]);
/// assert!(p[0][0] >= 1.0 && p[0][0] < 2.0 && s != (1.0, 1.0));
/// ```
#[inline]
pub fn local<const D: usize, const K: usize>(p: [[f64; D]; K]) -> ([[f64; D]; K], (f64, f64)) {
    let s = pow2_scale(max_abs(&p));
    if s == (1.0, 1.0) {
        (p, s)
    } else {
        (p.map(|q| scaled(q, s)), s)
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

    #[test]
    fn range_limits() {
        let at = |r: i32| [[1.0, 0.0, 0.0], [0.0, 2f64.powi(-r), 0.0]];
        assert!(check_range(&at(RANGE_3D), RANGE_3D).is_ok());
        assert!(check_range(&at(RANGE_3D + 1), RANGE_3D).is_err());
        assert!(check_range(&at(RANGE_3D + 1), RANGE_2D).is_ok());
        // Any absolute scale, subnormals included.
        assert!(check_range(&[[5e-324, 1e-323]], RANGE_2D).is_ok());
        assert!(check_range(&[[f64::MAX, 1e300]], RANGE_2D).is_ok());
        assert_eq!(exponent(5e-324), -1074);
        assert_eq!(exponent(1.5), 0);
        assert_eq!(exponent(-0.75), -1);
    }
}
