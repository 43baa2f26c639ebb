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
//! Equivalently, with homogeneous rows (`|p|²` the lifted coordinate):
//! `orient2d = det[p 1]` over `a, b, c`; `orient3d = det[p 1]` over `a, b, c, d`;
//! `incircle = det[p |p|² 1]` over `a, b, c, d`; `insphere = det[p |p|² 1]` over
//! `a, b, c, d, e`. The weighted (power) variants replace `|p|²` by `|p|² − w_p`.
//!
//! # The filter
//!
//! Each predicate first evaluates the translated determinant (differences to the
//! last point) in plain floating point and compares it with a certified error bound;
//! this fast path is `#[inline(always)]`, everything after it lives in `#[cold]`,
//! `#[inline(never)]` functions so that it does not bloat the caller.
//!
//! * [`incircle`] and [`insphere`] use a *semi-static* bound in the style of Meyer &
//!   Pion (2008): `C·Mᵈ` with `M` the largest coordinate difference and `d` the degree,
//!   where `M²` is bounded by the largest lifted term `|p − d|²` that the determinant
//!   computes anyway; `C = (128 + 2⁻³⁰)·u` for incircle (`|det| > C·L²`) and
//!   `(1104 + 2⁻³⁰)·u` for insphere (`det² > C²·L⁵`), from a forward error analysis
//!   of the evaluation order (see the `semi` module source). An absolute floor
//!   `2⁻¹⁰⁰⁰` and the finiteness of the bound replace explicit underflow/overflow
//!   range checks. When this filter fails, the permanent-based filter below runs
//!   before the exact stage.
//! * [`orient2d`], [`orient3d`] and the weighted tests use a permanent-based bound:
//!   the determinant and, in the same pass, its *permanent* (every product term in
//!   absolute value); `|computed − exact| ≤ c·u·permanent` with `u = 2⁻⁵³` and `c`
//!   counting the roundings along the longest path (`c ≈ 4, 8, 11, 17` for orient2d,
//!   orient3d, incircle, insphere; `14, 19` for the weighted tests, plus a
//!   second-order margin). For the orientation tests this costs fewer instructions
//!   than any maximum of absolute values.
//!
//! Both filters decide all but near-degenerate inputs.
//!
//! # The exact stage
//!
//! Otherwise a separate `#[cold]` function decides, in up to six steps, all but
//! the integer one with floating-point *expansions* (sums of non-overlapping
//! doubles: two-sum, two-product with FMA when the target has it or Dekker's
//! split otherwise, expansion sum and scaling with zero elimination, exact sign
//! tests by streamed grow-expansion) in fixed-size stack arrays — nothing
//! allocates:
//!
//! 1. **Coarse grid.** If every coordinate difference is exact and all are integer
//!    multiples of a common power of two `g` no larger than `L·g` (`L = 2^25, 2^16,
//!    2^12, 2^9` for orient2d, orient3d, incircle, insphere), every intermediate of
//!    the plain floating-point formula is an exactly representable multiple of a
//!    power of `g`, so the plain evaluation *is* exact. Integer and dyadic grids,
//!    the usual source of exact ties, take this path at filter speed.
//! 2. **Integer grid** ([`orient3d`] and the unweighted [`insphere`]). If the
//!    coordinates of all the points are integer multiples of one power of two
//!    `g` below `2^61·g` (true whenever their magnitudes span less than about
//!    256× — the usual case for the exact ties of CAD models, whose coordinate
//!    differences need not be exact), the determinant is evaluated exactly in
//!    fixed-width integers (64-bit differences, 128-bit minors, at most five
//!    64-bit limbs), at a few hundred instructions for [`orient3d`] and one to
//!    two thousand for [`insphere`] (the expansion stages take tens of
//!    thousands on such ties). For [`insphere`] this runs before the
//!    double-double stage, for [`orient3d`] after it (stage A's place).
//! 3. **Double-double stage.** The coordinate differences are taken exactly as
//!    two-term pairs (`two_diff`) and the translated determinant is evaluated in
//!    double-double arithmetic (error-free `two_product`/`two_sum` on the high parts,
//!    plain floating point for the low-order cross terms). A forward error analysis
//!    in magnitude bounds, applied mechanically to the same generic code by a unit
//!    test, gives `|computed − exact| ≤ k·u²·Mᵈ` with `M` the largest difference and
//!    `k = 32, 352, 1920, 20608` for orient2d, orient3d, incircle, insphere (plus an
//!    absolute floor `2⁻¹⁰⁰⁰` for underflow; the stage is skipped when `M > 2¹⁵⁰`).
//!    This certifies every near-degenerate but nonzero decision whose determinant is
//!    above about `k·u²·Mᵈ` — e.g. all decisions on points rounded from circles or
//!    spheres — at a few hundred flops; see the `dd` module source for the
//!    derivation. Only exact or astronomically close ties go further.
//! 4. **Stage A.** The translated determinant is evaluated exactly on the rounded
//!    differences. If all differences were exact, this is the answer.
//! 5. **Stages A′ and C.** Each rounded difference is within `u·|x|` of the true
//!    one, so a degree-`k` determinant on them is within `(k+1)·u·P` of the true
//!    value (`P` its permanent); failing that, the first-order effect of the
//!    rounding errors is added in floating point (a gradient formulation of
//!    Shewchuk's stage C) and certified against a `O(u²·P)` bound. Comparisons
//!    against these bounds are exact.
//! 6. **Stage B.** Otherwise (in practice only exact ties whose coordinate
//!    differences are not representable) the *homogeneous* determinant on the raw
//!    coordinates, rows `[x, y, (lift,) 1]`, is expanded by cofactors; it needs no
//!    differences at all.
//!
//! The long intermediate expansions are first tried with small capacities, checked
//! at run time, and only on overflow with the worst-case capacities (up to a few
//! hundred kilobytes of stack for the 3D in-sphere test, a path essentially never
//! taken). The weighted tests compute the lifted coordinates `x² + y² (+ z²) − w`
//! as expansions, so they are exact too. The exact stage returns an approximation
//! of the determinant: the sign is exact, the magnitude approximate, and the value
//! is exactly `0.0` iff the determinant is zero.
//!
//! **Caveat (overflow/underflow).** Exactness holds for all finite inputs whose
//! intermediate products neither overflow nor underflow (the error bounds assume
//! normalized numbers and the expansion products need their rounding errors to be
//! representable): roughly coordinate differences with magnitudes in
//! `[1e-50, 1e50]` for the 3D in-sphere test (wider for the others), and no
//! coordinate above `~1e300 / 2^27` when Dekker's split is in use.
//! Coordinates scaled by `1e-9` or `1e9` are far inside that range. Non-finite
//! inputs (NaN, ±∞) give an unspecified sign but never panic.
//!
//! # Simulation of Simplicity
//!
//! * [`orient2d_sos`], [`orient3d_sos`]: Edelsbrunner–Mücke perturbation. Sort the
//!   points by *decreasing* index (rank 0 = largest index); coordinate `j` of the
//!   point of rank `r` is perturbed by `ε^(2^(r·D + j))` (`D` the dimension), so the
//!   largest index is the most significant and `x` precedes `y` (precedes `z`).
//!   The perturbed determinant is a polynomial in `ε` whose monomials are ordered by
//!   their exponent; the coefficient of each is a lower-order orientation
//!   determinant of projected points (or ±1), evaluated exactly, and the first
//!   nonzero one decides. The result is never 0, even for coincident points.
//! * [`incircle_sos`], [`insphere_sos`] and their weighted versions: lifting
//!   perturbation (Devillers & Teillaud 2011). The lifted coordinate of the point
//!   with index `i` is raised by `ε_i` (as if its weight were `−ε_i`), with
//!   `ε_i ≫ ε_j` whenever `i > j`. The perturbed determinant is
//!   `det₀ + Σ ε_i·C_i` where `C_i` is the cofactor of the lifted entry, a signed
//!   orientation of the *other* points; see each function for the exact formula.
//!   If `det₀ ≠ 0` its sign is returned; otherwise the cofactors are examined in
//!   decreasing index order and the first nonzero one decides. All cofactors vanish
//!   only when all points are collinear (2D) / coplanar (3D); then the result is the
//!   parity of the permutation sorting the indices increasingly (+1 even, −1 odd),
//!   a documented, antisymmetric convention.
//!
//! Each SoS function is the exact sign of a single, fixed perturbation of the
//! whole point set (it depends only on each point's index), so all the predicate
//! values a triangulation kernel sees are consistent with one point set in general
//! position.
//!
//! # References
//! * J. R. Shewchuk, *Adaptive Precision Floating-Point Arithmetic and Fast Robust
//!   Geometric Predicates*, Discrete & Computational Geometry 18 (1997) 305–363.
//! * H. Edelsbrunner, E. P. Mücke, *Simulation of Simplicity: a technique to cope with
//!   degenerate cases in geometric algorithms*, ACM Transactions on Graphics 9 (1990).
//! * O. Devillers, M. Teillaud, *Perturbations for Delaunay and weighted Delaunay 3D
//!   triangulations*, Computational Geometry: Theory and Applications 44 (2011).
//! * A. Meyer, S. Pion, *FPG: a code generator for fast and certified geometric
//!   predicates*, Real Numbers and Computers (2008).
#![forbid(unsafe_code)]

mod dd;
mod exact;
mod expansion;
mod int;
mod semi;
mod sos;

pub use expansion::{two_product, two_sum};
use sos::sgn;

/// A 2D point.
pub type Point2 = [f64; 2];
/// A 3D point.
pub type Point3 = [f64; 3];

/// Unit roundoff `2^-53`.
pub(crate) const U: f64 = f64::EPSILON * 0.5;
const O2_BOUND: f64 = (4.0 + 64.0 * U) * U;
const O3_BOUND: f64 = (8.0 + 256.0 * U) * U;
const IC_BOUND: f64 = (11.0 + 256.0 * U) * U;
const ICW_BOUND: f64 = (14.0 + 512.0 * U) * U;
const IS_BOUND: f64 = (17.0 + 1024.0 * U) * U;
const ISW_BOUND: f64 = (19.0 + 1024.0 * U) * U;

/// Twice the signed area of triangle `abc`: positive iff counterclockwise.
///
/// The sign is exact; the magnitude is approximate.
///
/// ```
/// use delone_predicates::orient2d;
/// assert!(orient2d(&[0.0, 0.0], &[1.0, 0.0], &[0.0, 1.0]) > 0.0);
/// assert_eq!(orient2d(&[0.0, 0.0], &[1.0, 1.0], &[2.0, 2.0]), 0.0);
/// ```
#[inline(always)]
pub fn orient2d(a: &Point2, b: &Point2, c: &Point2) -> f64 {
    let l = (a[0] - c[0]) * (b[1] - c[1]);
    let r = (a[1] - c[1]) * (b[0] - c[0]);
    let det = l - r;
    let bound = O2_BOUND * (l.abs() + r.abs());
    if det.abs() > bound {
        return det;
    }
    exact::orient2d_exact(a, b, c)
}

/// Positive iff `d` lies inside the circle through counterclockwise `a, b, c`.
///
/// ```
/// use delone_predicates::incircle;
/// let (a, b, c) = ([0.0, 0.0], [1.0, 0.0], [0.0, 1.0]);
/// assert!(incircle(&a, &b, &c, &[0.5, 0.5]) > 0.0);
/// assert_eq!(incircle(&a, &b, &c, &[1.0, 1.0]), 0.0);
/// ```
#[inline(always)]
pub fn incircle(a: &Point2, b: &Point2, c: &Point2, d: &Point2) -> f64 {
    let (det, ok) = semi::incircle(a, b, c, d);
    if ok {
        return det;
    }
    incircle_slow(a, b, c, d)
}

/// Second stage of [`incircle`]: permanent-based filter, then the exact stage.
#[cold]
#[inline(never)]
fn incircle_slow(a: &Point2, b: &Point2, c: &Point2, d: &Point2) -> f64 {
    let (adx, ady) = (a[0] - d[0], a[1] - d[1]);
    let (bdx, bdy) = (b[0] - d[0], b[1] - d[1]);
    let (cdx, cdy) = (c[0] - d[0], c[1] - d[1]);
    let (bc1, bc2) = (bdx * cdy, cdx * bdy);
    let (ca1, ca2) = (cdx * ady, adx * cdy);
    let (ab1, ab2) = (adx * bdy, bdx * ady);
    let al = adx * adx + ady * ady;
    let bl = bdx * bdx + bdy * bdy;
    let cl = cdx * cdx + cdy * cdy;
    let det = al * (bc1 - bc2) + bl * (ca1 - ca2) + cl * (ab1 - ab2);
    let perm =
        al * (bc1.abs() + bc2.abs()) + bl * (ca1.abs() + ca2.abs()) + cl * (ab1.abs() + ab2.abs());
    let bound = IC_BOUND * perm;
    if det.abs() > bound {
        return det;
    }
    exact::incircle_exact(a, b, c, d, [0.0; 4])
}

/// `det[a-d; b-d; c-d]`: positive iff `d` lies below the plane of `a, b, c`
/// (`a, b, c` counterclockwise seen from above).
///
/// ```
/// use delone_predicates::orient3d;
/// let o = orient3d(&[0.0, 0.0, 0.0], &[1.0, 0.0, 0.0], &[0.0, 1.0, 0.0], &[0.0, 0.0, -1.0]);
/// assert!(o > 0.0);
/// assert_eq!(orient3d(&[0.0, 0.0, 0.0], &[1.0, 0.0, 0.0], &[0.0, 1.0, 0.0], &[3.0, 5.0, 0.0]), 0.0);
/// ```
#[inline(always)]
pub fn orient3d(a: &Point3, b: &Point3, c: &Point3, d: &Point3) -> f64 {
    let ad = [a[0] - d[0], a[1] - d[1], a[2] - d[2]];
    let bd = [b[0] - d[0], b[1] - d[1], b[2] - d[2]];
    let cd = [c[0] - d[0], c[1] - d[1], c[2] - d[2]];
    let (bc1, bc2) = (bd[1] * cd[2], bd[2] * cd[1]);
    let (ca1, ca2) = (cd[1] * ad[2], cd[2] * ad[1]);
    let (ab1, ab2) = (ad[1] * bd[2], ad[2] * bd[1]);
    let det = ad[0] * (bc1 - bc2) + bd[0] * (ca1 - ca2) + cd[0] * (ab1 - ab2);
    let perm = ad[0].abs() * (bc1.abs() + bc2.abs())
        + bd[0].abs() * (ca1.abs() + ca2.abs())
        + cd[0].abs() * (ab1.abs() + ab2.abs());
    let bound = O3_BOUND * perm;
    if det.abs() > bound {
        return det;
    }
    exact::orient3d_exact(a, b, c, d)
}

/// Floating-point in-sphere determinant on the differences to `e` (rows
/// `p - e, |p - e|² - wd_p`) and its permanent.
#[inline(always)]
fn insphere_float(p: [&Point3; 5], wd: [f64; 4]) -> (f64, f64) {
    let e = p[4];
    let sub = |q: &Point3| [q[0] - e[0], q[1] - e[1], q[2] - e[2]];
    let (ae, be, ce, de) = (sub(p[0]), sub(p[1]), sub(p[2]), sub(p[3]));
    // 2x2 (x, y) minors with their two products kept for the permanent.
    let m = |s: &[f64; 3], t: &[f64; 3]| (s[0] * t[1], t[0] * s[1]);
    let (ab, ac, ad) = (m(&ae, &be), m(&ae, &ce), m(&ae, &de));
    let (bc, bd, cd) = (m(&be, &ce), m(&be, &de), m(&ce, &de));
    // det3 along z: p_z m(q, r) - q_z m(p, r) + r_z m(p, q).
    let d3 = |pz: f64, qz: f64, rz: f64, qr: (f64, f64), pr: (f64, f64), pq: (f64, f64)| {
        let v = pz * (qr.0 - qr.1) - qz * (pr.0 - pr.1) + rz * (pq.0 - pq.1);
        let a = pz.abs() * (qr.0.abs() + qr.1.abs())
            + qz.abs() * (pr.0.abs() + pr.1.abs())
            + rz.abs() * (pq.0.abs() + pq.1.abs());
        (v, a)
    };
    let bcd = d3(be[2], ce[2], de[2], cd, bd, bc);
    let acd = d3(ae[2], ce[2], de[2], cd, ad, ac);
    let abd = d3(ae[2], be[2], de[2], bd, ad, ab);
    let abc = d3(ae[2], be[2], ce[2], bc, ac, ab);
    let lift = |q: &[f64; 3], w: f64| {
        let s = q[0] * q[0] + q[1] * q[1] + q[2] * q[2];
        (s - w, s + w.abs())
    };
    let (la, lb, lc, ld) = (
        lift(&ae, wd[0]),
        lift(&be, wd[1]),
        lift(&ce, wd[2]),
        lift(&de, wd[3]),
    );
    let det = (lb.0 * acd.0 - la.0 * bcd.0) + (ld.0 * abc.0 - lc.0 * abd.0);
    let perm = (lb.1 * acd.1 + la.1 * bcd.1) + (ld.1 * abc.1 + lc.1 * abd.1);
    (det, perm)
}

/// Positive iff `e` lies inside the sphere through `a, b, c, d`, where
/// `orient3d(a, b, c, d) > 0`; the sign flips for the other orientation.
///
/// ```
/// use delone_predicates::{insphere, orient3d};
/// let (a, b, c, d) = ([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]);
/// assert!(orient3d(&a, &b, &c, &d) > 0.0);
/// assert!(insphere(&a, &b, &c, &d, &[0.1, 0.1, -0.1]) > 0.0);
/// assert_eq!(insphere(&a, &b, &c, &d, &[1.0, 1.0, -1.0]), 0.0);
/// ```
#[inline(always)]
pub fn insphere(a: &Point3, b: &Point3, c: &Point3, d: &Point3, e: &Point3) -> f64 {
    let (det, ok) = semi::insphere(a, b, c, d, e);
    if ok {
        return det;
    }
    insphere_slow(a, b, c, d, e)
}

/// Second stage of [`insphere`]: permanent-based filter, then the exact stage.
#[cold]
#[inline(never)]
fn insphere_slow(a: &Point3, b: &Point3, c: &Point3, d: &Point3, e: &Point3) -> f64 {
    let (det, perm) = insphere_float([a, b, c, d, e], [0.0; 4]);
    let bound = IS_BOUND * perm;
    if det.abs() > bound {
        return det;
    }
    exact::insphere_exact([a, b, c, d, e], [0.0; 5])
}

/// The 2D power test (regular triangulations): positive iff weighted point `d`
/// is in conflict with the counterclockwise weighted triangle `abc`.
///
/// This is the sign of `det[x y (x²+y²−w) 1]` over rows `a, b, c, d`, i.e. of
/// `orient3d` on the lifted points `(x, y, x²+y²−w)` normalised to [`incircle`]'s
/// convention: positive iff the lifted `d` lies below the plane through the lifted
/// `a, b, c` (for counterclockwise `a, b, c`). With all weights 0 it has exactly the
/// sign of [`incircle`]; the sign is exact, the magnitude approximate.
///
/// ```
/// use delone_predicates::{incircle, incircle_weighted};
/// let (a, b, c, d) = ([0.0, 0.0], [2.0, 0.0], [0.0, 2.0], [2.0, 2.0]);
/// assert_eq!(incircle(&a, &b, &c, &d), 0.0); // cocircular
/// // A heavier d conflicts, a lighter one does not.
/// assert!(incircle_weighted(&a, &b, &c, &d, 0.0, 0.0, 0.0, 0.5) > 0.0);
/// assert!(incircle_weighted(&a, &b, &c, &d, 0.0, 0.0, 0.0, -0.5) < 0.0);
/// ```
#[inline]
#[allow(clippy::too_many_arguments)]
pub fn incircle_weighted(
    a: &Point2,
    b: &Point2,
    c: &Point2,
    d: &Point2,
    wa: f64,
    wb: f64,
    wc: f64,
    wd: f64,
) -> f64 {
    let (adx, ady) = (a[0] - d[0], a[1] - d[1]);
    let (bdx, bdy) = (b[0] - d[0], b[1] - d[1]);
    let (cdx, cdy) = (c[0] - d[0], c[1] - d[1]);
    let (bc1, bc2) = (bdx * cdy, cdx * bdy);
    let (ca1, ca2) = (cdx * ady, adx * cdy);
    let (ab1, ab2) = (adx * bdy, bdx * ady);
    let (wad, wbd, wcd) = (wa - wd, wb - wd, wc - wd);
    let al = adx * adx + ady * ady;
    let bl = bdx * bdx + bdy * bdy;
    let cl = cdx * cdx + cdy * cdy;
    let det = (al - wad) * (bc1 - bc2) + (bl - wbd) * (ca1 - ca2) + (cl - wcd) * (ab1 - ab2);
    let perm = (al + wad.abs()) * (bc1.abs() + bc2.abs())
        + (bl + wbd.abs()) * (ca1.abs() + ca2.abs())
        + (cl + wcd.abs()) * (ab1.abs() + ab2.abs());
    let bound = ICW_BOUND * perm;
    if det.abs() > bound {
        return det;
    }
    exact::incircle_exact(a, b, c, d, [wa, wb, wc, wd])
}

/// The 3D power test: positive iff weighted point `e` is in conflict with the
/// weighted tetrahedron `abcd` when `orient3d(a, b, c, d) > 0` (sign flips for the
/// other orientation).
///
/// This is the sign of `det[x y z (x²+y²+z²−w) 1]` over rows `a, b, c, d, e`
/// (orient4d on the lifted points), in [`insphere`]'s convention: with all weights
/// 0 it has exactly the sign of [`insphere`]. Sign exact, magnitude approximate.
///
/// ```
/// use delone_predicates::{insphere, insphere_weighted};
/// let (a, b, c, d) = ([0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, -2.0]);
/// let e = [2.0, 2.0, -2.0];
/// assert_eq!(insphere(&a, &b, &c, &d, &e), 0.0); // cospherical
/// assert!(insphere_weighted(&a, &b, &c, &d, &e, 0.0, 0.0, 0.0, 0.0, 1.0) > 0.0);
/// assert!(insphere_weighted(&a, &b, &c, &d, &e, 0.0, 0.0, 0.0, 0.0, -1.0) < 0.0);
/// ```
#[inline]
#[allow(clippy::too_many_arguments)]
pub fn insphere_weighted(
    a: &Point3,
    b: &Point3,
    c: &Point3,
    d: &Point3,
    e: &Point3,
    wa: f64,
    wb: f64,
    wc: f64,
    wd: f64,
    we: f64,
) -> f64 {
    let (det, perm) = insphere_float([a, b, c, d, e], [wa - we, wb - we, wc - we, wd - we]);
    let bound = ISW_BOUND * perm;
    if det.abs() > bound {
        return det;
    }
    exact::insphere_exact([a, b, c, d, e], [wa, wb, wc, wd, we])
}

/// [`orient2d`] under Simulation of Simplicity: `+1` or `-1`, never 0 for pairwise
/// distinct indices (even when points coincide).
///
/// If `orient2d(a, b, c) != 0` its sign is returned. Otherwise the coordinates are
/// perturbed symbolically (Edelsbrunner–Mücke): with the three points ranked by
/// decreasing index (rank 0 = largest index), coordinate `j` (`x = 0, y = 1`) of the
/// point of rank `r` moves by `ε^(2^(2r + j))`. The first nonzero coefficient of the
/// perturbed determinant decides; with `a, b, c` the rows, the first candidates
/// are `± (y_s − y_t)` and `± (x_s − x_t)` of the two points other than the
/// largest-index one, and the last one is a constant `±1`.
/// Swapping two points together with their indices negates the result.
///
/// ```
/// use delone_predicates::orient2d_sos;
/// let (a, b, c) = ([0.0, 0.0], [1.0, 1.0], [2.0, 2.0]); // collinear
/// let s = orient2d_sos(&a, &b, &c, 0, 1, 2);
/// assert!(s == 1 || s == -1);
/// assert_eq!(orient2d_sos(&b, &a, &c, 1, 0, 2), -s);
/// assert_eq!(orient2d_sos(&[0.0, 0.0], &[1.0, 0.0], &[0.0, 1.0], 7, 3, 5), 1);
/// ```
#[inline(always)]
pub fn orient2d_sos(a: &Point2, b: &Point2, c: &Point2, ia: u32, ib: u32, ic: u32) -> i32 {
    let s = sgn(orient2d(a, b, c));
    if s != 0 {
        return s;
    }
    sos::orient_sos(&[*a, *b, *c], &[ia, ib, ic])
}

/// [`orient3d`] under Simulation of Simplicity: `+1` or `-1`, never 0 for pairwise
/// distinct indices (even when points coincide).
///
/// If `orient3d(a, b, c, d) != 0` its sign is returned. Otherwise, with the points
/// ranked by decreasing index (rank 0 = largest index), coordinate `j`
/// (`x, y, z = 0, 1, 2`) of the point of rank `r` is perturbed by `ε^(2^(3r + j))`
/// (Edelsbrunner–Mücke); the coefficients of the perturbed determinant, in
/// increasing order of the exponent, are exact `orient2d` signs of projections,
/// signs of coordinate differences, and finally `±1`; the first nonzero decides.
/// Swapping two points together with their indices negates the result.
///
/// ```
/// use delone_predicates::orient3d_sos;
/// let p = [1.0, 2.0, 3.0];
/// let s = orient3d_sos(&p, &p, &p, &p, 0, 1, 2, 3); // four coincident points
/// assert!(s == 1 || s == -1);
/// assert_eq!(orient3d_sos(&p, &p, &p, &p, 1, 0, 2, 3), -s);
/// ```
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn orient3d_sos(
    a: &Point3,
    b: &Point3,
    c: &Point3,
    d: &Point3,
    ia: u32,
    ib: u32,
    ic: u32,
    id: u32,
) -> i32 {
    let s = sgn(orient3d(a, b, c, d));
    if s != 0 {
        return s;
    }
    sos::orient_sos(&[*a, *b, *c, *d], &[ia, ib, ic, id])
}

/// [`incircle`] under Simulation of Simplicity (lifting perturbation): `+1` or `-1`.
///
/// Rule: if `incircle(a, b, c, d) != 0` return its sign. Otherwise the lifted
/// coordinate `|p|²` of each point is raised by `ε_i` (`i` its index, `ε_i ≫ ε_j`
/// for `i > j`), which adds `Σ ε_i·C_i` with the cofactors
/// `C_a = +orient2d(b, c, d)`, `C_b = −orient2d(a, c, d)`,
/// `C_c = +orient2d(a, b, d)`, `C_d = −orient2d(a, b, c)`.
/// The points are visited in decreasing index order and the sign of the first
/// nonzero `C` is returned. This equals the sign of [`incircle_weighted`] with
/// weights `w_i = −ε_i`. In particular, for counterclockwise `a, b, c` and a point
/// `d` exactly on their circle, `d` is reported *outside* (−1) when `d` has the
/// largest index. If all four points are collinear (all `C` vanish) the result is
/// the parity of the permutation sorting `(ia, ib, ic, id)` increasingly (`+1` if
/// even). Never 0 for pairwise distinct indices.
///
/// ```
/// use delone_predicates::incircle_sos;
/// let (a, b, c, d) = ([3.0, 4.0], [-5.0, 0.0], [3.0, -4.0], [5.0, 0.0]); // cocircular
/// assert_eq!(incircle_sos(&a, &b, &c, &d, 0, 1, 2, 3), -1);
/// assert_eq!(incircle_sos(&a, &b, &c, &d, 1, 2, 3, 0), 1);
/// ```
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn incircle_sos(
    a: &Point2,
    b: &Point2,
    c: &Point2,
    d: &Point2,
    ia: u32,
    ib: u32,
    ic: u32,
    id: u32,
) -> i32 {
    let s = sgn(incircle(a, b, c, d));
    if s != 0 {
        return s;
    }
    sos::incircle_lifted_sos([a, b, c, d], [ia, ib, ic, id])
}

/// [`insphere`] under Simulation of Simplicity (lifting perturbation): `+1` or `-1`.
///
/// Rule: if `insphere(a, b, c, d, e) != 0` return its sign. Otherwise the lifted
/// coordinate `|p|²` of each point is raised by `ε_i` (`i` its index, `ε_i ≫ ε_j`
/// for `i > j`), which adds `Σ ε_i·C_i` with the cofactors
/// `C_a = −orient3d(b, c, d, e)`, `C_b = +orient3d(a, c, d, e)`,
/// `C_c = −orient3d(a, b, d, e)`, `C_d = +orient3d(a, b, c, e)`,
/// `C_e = −orient3d(a, b, c, d)`.
/// The points are visited in decreasing index order and the sign of the first
/// nonzero `C` is returned; this equals the sign of [`insphere_weighted`] with
/// weights `w_i = −ε_i`. For positively oriented `a, b, c, d` and `e` exactly on
/// their sphere, `e` is reported *outside* (−1) when `e` has the largest index. If
/// all five points are coplanar the result is the parity of the permutation
/// sorting the indices increasingly (`+1` if even). Never 0 for distinct indices.
///
/// ```
/// use delone_predicates::insphere_sos;
/// let (a, b, c, d) = ([0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, -2.0]);
/// let e = [2.0, 2.0, -2.0]; // on the sphere
/// assert_eq!(insphere_sos(&a, &b, &c, &d, &e, 0, 1, 2, 3, 4), -1);
/// ```
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn insphere_sos(
    a: &Point3,
    b: &Point3,
    c: &Point3,
    d: &Point3,
    e: &Point3,
    ia: u32,
    ib: u32,
    ic: u32,
    id: u32,
    ie: u32,
) -> i32 {
    let s = sgn(insphere(a, b, c, d, e));
    if s != 0 {
        return s;
    }
    sos::insphere_lifted_sos([a, b, c, d, e], [ia, ib, ic, id, ie])
}

/// [`incircle_weighted`] under the lifting perturbation: `+1` or `-1`.
///
/// Same rule as [`incircle_sos`] (the cofactors do not depend on the weights):
/// if the exact weighted determinant is nonzero its sign is returned; otherwise
/// the first nonzero cofactor in decreasing index order decides, and the
/// collinear fallback is the parity of the index permutation.
///
/// ```
/// use delone_predicates::incircle_weighted_sos;
/// let (a, b, c, d) = ([0.0, 0.0], [2.0, 0.0], [0.0, 2.0], [1.0, 1.0]);
/// // d is the center of the circle through a, b, c (radius² 2); with w_d = -2 its
/// // lifted point lies exactly on the plane of the others: a tie, broken by SoS.
/// let s = incircle_weighted_sos(&a, &b, &c, &d, 0.0, 0.0, 0.0, -2.0, 0, 1, 2, 3);
/// assert_eq!(s, -1);
/// ```
#[inline]
#[allow(clippy::too_many_arguments)]
pub fn incircle_weighted_sos(
    a: &Point2,
    b: &Point2,
    c: &Point2,
    d: &Point2,
    wa: f64,
    wb: f64,
    wc: f64,
    wd: f64,
    ia: u32,
    ib: u32,
    ic: u32,
    id: u32,
) -> i32 {
    let s = sgn(incircle_weighted(a, b, c, d, wa, wb, wc, wd));
    if s != 0 {
        return s;
    }
    sos::incircle_lifted_sos([a, b, c, d], [ia, ib, ic, id])
}

/// The lifting perturbation's decision for an exact in-sphere tie: what
/// [`insphere_sos`] and [`insphere_weighted_sos`] return when the exact
/// (weighted) determinant of rows `a, b, c, d, e` is 0 (the cofactors do not
/// depend on the weights), for callers that have that determinant already.
///
/// ```
/// use delone_predicates::{insphere_sos, insphere_tie_sos};
/// let (a, b, c, d) = ([0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, -2.0]);
/// let e = [2.0, 2.0, -2.0]; // on the sphere
/// let s = insphere_tie_sos([&a, &b, &c, &d, &e], [0, 1, 2, 3, 4]);
/// assert_eq!(s, insphere_sos(&a, &b, &c, &d, &e, 0, 1, 2, 3, 4));
/// ```
#[inline]
pub fn insphere_tie_sos(pts: [&Point3; 5], idx: [u32; 5]) -> i32 {
    sos::insphere_lifted_sos(pts, idx)
}

/// [`insphere_weighted`] under the lifting perturbation: `+1` or `-1`.
///
/// Same rule as [`insphere_sos`] (the cofactors do not depend on the weights).
///
/// ```
/// use delone_predicates::insphere_weighted_sos;
/// let (a, b, c, d) = ([0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, -2.0]);
/// let e = [1.0, 1.0, -1.0]; // the center; |e - a|^2 = 3
/// let s = insphere_weighted_sos(&a, &b, &c, &d, &e, 0.0, 0.0, 0.0, 0.0, -3.0, 0, 1, 2, 3, 4);
/// assert_eq!(s, -1);
/// ```
#[inline]
#[allow(clippy::too_many_arguments)]
pub fn insphere_weighted_sos(
    a: &Point3,
    b: &Point3,
    c: &Point3,
    d: &Point3,
    e: &Point3,
    wa: f64,
    wb: f64,
    wc: f64,
    wd: f64,
    we: f64,
    ia: u32,
    ib: u32,
    ic: u32,
    id: u32,
    ie: u32,
) -> i32 {
    let s = sgn(insphere_weighted(a, b, c, d, e, wa, wb, wc, wd, we));
    if s != 0 {
        return s;
    }
    sos::insphere_lifted_sos([a, b, c, d, e], [ia, ib, ic, id, ie])
}
