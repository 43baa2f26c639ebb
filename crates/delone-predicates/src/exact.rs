//! Exact (slow) stages of the predicates, reached only when the floating-point
//! filter cannot certify the sign.
//!
//! Each predicate goes through up to five steps (after the coarse-grid shortcut,
//! the integer evaluation of the `int` module for `orient3d` and `insphere`, and
//! the double-double stage of the `dd` module, which certifies every
//! non-negligible near-degenerate decision):
//!
//! * **Stage A** — the translated determinant (differences to the last point) is
//!   evaluated *exactly on the rounded differences* with short expansions. If every
//!   difference was exact (rounding error zero: integer grids, nearby points by
//!   Sterbenz' lemma, most degenerate inputs), this is the exact answer.
//! * **Stage A′** — otherwise each rounded difference `x` is off by at most `u|x|`
//!   (`u = 2⁻⁵³`), so for a determinant of degree `k` in the differences the
//!   rounded-difference value is within `((1+u)^k − 1)·P` of the true one, `P` the
//!   permanent (sum of absolute monomials); beyond `(k+1)·u·P` its sign is certified.
//! * **Stage C** — add the first-order effect of the rounding errors (tails), in
//!   floating point, and certify against a second-order bound `O(u²·P)`
//!   (the idea of Shewchuk's stage C, with a generic gradient formulation).
//! * **Stage B** — otherwise the *homogeneous* determinant on the raw coordinates
//!   (rows `[x, y, (lift,) 1]`) is expanded by cofactors with expansion arithmetic;
//!   it needs no differences, hence is exact for all finite inputs barring overflow
//!   and underflow. Reached essentially only for exact ties whose coordinate
//!   differences are not representable.
//!
//! All buffers are fixed-size stack arrays; nothing allocates. The long
//! intermediate expansions are first attempted with small capacities (checked at
//! run time, since the true lengths are usually tiny thanks to zero elimination)
//! and only if one overflows with the worst-case capacities, which cannot overflow.

use crate::expansion::{two_diff, two_sum, Exp};
use crate::{dd, int};
use crate::{Point2, Point3, U};

/// `p[i] * q[j] - q[i] * p[j]`, the 2x2 minor on columns `i, j` of rows `p, q`.
#[inline(always)]
fn minor2(p: &[f64], q: &[f64], i: usize, j: usize) -> Exp<4> {
    Exp::<2>::product(p[i], q[j]).sub(&Exp::<2>::product(q[i], p[j]))
}

/// Rounded differences `p - q`, their rounding errors (tails: `p - q = x + t`
/// exactly), and whether all of them are exact.
#[inline]
fn diffs<const D: usize>(p: &[f64; D], q: &[f64; D], exact: &mut bool) -> ([f64; D], [f64; D]) {
    let mut r = [0.0; D];
    let mut t = [0.0; D];
    for k in 0..D {
        let (x, y) = two_diff(p[k], q[k]);
        *exact &= y == 0.0;
        r[k] = x;
        t[k] = y;
    }
    (r, t)
}

/// Exact sign of `e + x + y` for a nonoverlapping expansion `e` (increasing
/// magnitude) and doubles `x, y`, in O(1) memory: two streamed Grow-Expansion
/// passes (Shewchuk 1997, Thm. 10); the sign of a nonoverlapping expansion is the
/// sign of its largest nonzero component.
fn sign_plus(e: &[f64], x: f64, y: f64) -> f64 {
    let (mut q1, mut q2, mut top) = (x, y, 0.0);
    for &c in e {
        let (s1, h1) = two_sum(q1, c);
        q1 = s1;
        let (s2, h2) = two_sum(q2, h1);
        q2 = s2;
        if h2 != 0.0 {
            top = h2;
        }
    }
    let (s2, h2) = two_sum(q2, q1);
    if h2 != 0.0 {
        top = h2;
    }
    if s2 != 0.0 {
        s2.signum()
    } else if top != 0.0 {
        top.signum()
    } else {
        0.0
    }
}

/// Stages A′ and C on the exact expansion `e` of the determinant evaluated on the
/// rounded differences; `perm` is its permanent and `k` its degree in the
/// differences; `corr` computes the first-order tail correction in floating point.
///
/// * A′: every rounded difference is within `u|x|` of the true one, so the true
///   determinant is within `((1+u)^k − 1)·P ≤ (k+1)·u·P` of `e` (`P` computed in
///   floating point underestimates the exact permanent by less than the slack).
/// * C: with the first-order term added, the neglected second-order terms are
///   below `C(k,2)·u²·P` and the floating-point error of `corr` below
///   about `(5k+5)·k·u²·P` (roundings along the gradient evaluation, times
///   `Σ|x|·∂P/∂|x| = k·P`); `4k(2k+8)·u²·P` bounds both with a wide margin.
///
/// All comparisons are exact. Returns `None` if neither stage decides.
fn decide(e: &[f64], perm: f64, k: f64, corr: impl FnOnce() -> f64) -> Option<f64> {
    let v = e[e.len() - 1];
    let b = (k + 1.0) * U * perm;
    if v != 0.0 && sign_plus(e, -v.signum() * b, 0.0) == v.signum() {
        return Some(v);
    }
    let c = corr();
    let err = 4.0 * k * (2.0 * k + 8.0) * U * U * perm;
    let s = if sign_plus(e, c, -err) > 0.0 {
        1.0
    } else if sign_plus(e, c, err) < 0.0 {
        -1.0
    } else {
        return None;
    };
    // Sign certified; the magnitude is only indicative.
    Some(f64::copysign((v + c).abs().max(f64::MIN_POSITIVE), s))
}

/// Cross product.
#[inline]
fn cross(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

#[inline]
fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Whether every value is an integer multiple of a common power of two `g` with
/// magnitude at most `lim·g`. A degree-`k` determinant formula with `C` monomials
/// over such values has every intermediate result an integer multiple of `g^j`
/// (its degree `j`) below `C·lim^k·g^j ≤ 2^53·g^j`, hence exactly representable:
/// plain floating-point evaluation is then exact (no overflow/underflow assumed).
fn on_coarse_grid(vals: &[f64], lim: f64) -> bool {
    let mut low = i32::MAX;
    let mut big = 0.0f64;
    for &x in vals {
        if x == 0.0 {
            continue;
        }
        let bits = x.to_bits();
        let exp = ((bits >> 52) & 0x7FF) as i32;
        if exp == 0 {
            return false; // subnormal
        }
        let mant = (bits & ((1u64 << 52) - 1)) | (1u64 << 52);
        low = low.min(exp - 1075 + mant.trailing_zeros() as i32);
        big = big.max(x.abs());
    }
    if low == i32::MAX {
        return true;
    }
    if !(-1000..=1000).contains(&low) {
        return false;
    }
    big <= lim * f64::from_bits(((low + 1023) as u64) << 52)
}

/// Exact weighted in-circle by the homogeneous determinant only (stage B), for
/// tests that need a reference independent of the other stages.
#[cfg(test)]
pub(crate) fn incircle_homogeneous(p: [&Point2; 4], w: [f64; 4]) -> f64 {
    incircle_b::<120, 240, 480>(p, w).unwrap_or(f64::NAN)
}

/// Exact weighted in-sphere by the homogeneous determinant only (stage B).
#[cfg(test)]
pub(crate) fn insphere_homogeneous(p: [&Point3; 5], w: [f64; 5]) -> f64 {
    insphere_b::<1344, 2688, 5376, 6720>(p, w).unwrap_or(f64::NAN)
}

/// Exact `orient3d` by the homogeneous determinant only (stage B).
#[cfg(test)]
pub(crate) fn orient3d_homogeneous(p: [&Point3; 4]) -> f64 {
    orient3d_b(p[0], p[1], p[2], p[3])
}

/// Exact `orient2d`.
#[cold]
#[inline(never)]
pub(crate) fn orient2d_exact(a: &Point2, b: &Point2, c: &Point2) -> f64 {
    let mut exact = true;
    let ((ac, ta), (bc, tb)) = (diffs(a, c, &mut exact), diffs(b, c, &mut exact));
    // 2 monomials of degree 2: 2·(2^25)^2 < 2^53.
    if exact && on_coarse_grid(&[ac[0], ac[1], bc[0], bc[1]], 33_554_432.0) {
        return ac[0] * bc[1] - ac[1] * bc[0];
    }
    // A zero column (the three points on one line `x_k = const`, as in the
    // axis-parallel projections of CAD faces) or a zero row (two points
    // equal): the determinant is 0 (a difference rounds to 0 only when it is 0).
    if (0..2).any(|k| ac[k] == 0.0 && bc[k] == 0.0) || ac == [0.0; 2] || bc == [0.0; 2] {
        return 0.0;
    }
    if let Some(v) = dd::orient2d(a, b, c) {
        return v;
    }
    let e = Exp::<2>::product(ac[0], bc[1]).sub::<2, 4>(&Exp::<2>::product(ac[1], bc[0]));
    if exact {
        return e.approx();
    }
    let perm = (ac[0] * bc[1]).abs() + (ac[1] * bc[0]).abs();
    let corr = || (ta[0] * bc[1] + ac[0] * tb[1]) - (ta[1] * bc[0] + ac[1] * tb[0]);
    if let Some(r) = decide(e.comps(), perm, 2.0, corr) {
        return r;
    }
    // det [a 1; b 1; c 1] along the ones column: m(b,c) - m(a,c) + m(a,b).
    let ab = minor2(a, b, 0, 1);
    let ac = minor2(a, c, 0, 1);
    let bc = minor2(b, c, 0, 1);
    let s: Exp<8> = bc.sub(&ac);
    let t: Exp<12> = s.add(&ab);
    t.approx()
}

/// `det3` of three 3-vectors, expanded along the first column with (y, z) minors.
#[inline]
fn det3(p: &[f64; 3], q: &[f64; 3], r: &[f64; 3]) -> Exp<24> {
    let qr = minor2(q, r, 1, 2);
    let pr = minor2(p, r, 1, 2);
    let pq = minor2(p, q, 1, 2);
    let t1: Exp<8> = qr.scale(p[0]);
    let t2: Exp<8> = pr.scale(-q[0]);
    let t3: Exp<8> = pq.scale(r[0]);
    let s: Exp<16> = t1.add(&t2);
    s.add(&t3)
}

/// Permanent of `det3(p, q, r)` in floating point.
#[inline]
fn perm3(p: &[f64; 3], q: &[f64; 3], r: &[f64; 3]) -> f64 {
    let m = |s: &[f64; 3], t: &[f64; 3]| (s[1] * t[2]).abs() + (s[2] * t[1]).abs();
    p[0].abs() * m(q, r) + q[0].abs() * m(p, r) + r[0].abs() * m(p, q)
}

/// Exact `orient3d`.
#[cold]
#[inline(never)]
pub(crate) fn orient3d_exact(a: &Point3, b: &Point3, c: &Point3, d: &Point3) -> f64 {
    let mut exact = true;
    let ((ad, ta), (bd, tb), (cd, tc)) = (
        diffs(a, d, &mut exact),
        diffs(b, d, &mut exact),
        diffs(c, d, &mut exact),
    );
    // A zero column (the four points on one plane `x_k = const`, as on the
    // axis-parallel faces of CAD models) or a zero row (two points equal):
    // the determinant is 0, whether or not the other differences are exact
    // (a difference rounds to 0 only when it is 0). Without this, such
    // degenerate tests with inexact differences took the full expansion.
    if (0..3).any(|k| ad[k] == 0.0 && bd[k] == 0.0 && cd[k] == 0.0)
        || [&ad, &bd, &cd].iter().any(|r| r.iter().all(|&x| x == 0.0))
    {
        return 0.0;
    }
    // 6 monomials of degree 3: 6·(2^16)^3 < 2^53.
    if exact
        && on_coarse_grid(
            &[
                ad[0], ad[1], ad[2], bd[0], bd[1], bd[2], cd[0], cd[1], cd[2],
            ],
            65_536.0,
        )
    {
        return dot(&ad, &cross(&bd, &cd));
    }
    if let Some(v) = dd::orient3d(a, b, c, d) {
        return v;
    }
    if let Some(v) = int::orient3d([a, b, c, d]) {
        return v;
    }
    let e = det3(&ad, &bd, &cd);
    if exact {
        return e.approx();
    }
    let corr =
        || dot(&ta, &cross(&bd, &cd)) + dot(&tb, &cross(&cd, &ad)) + dot(&tc, &cross(&ad, &bd));
    if let Some(r) = decide(e.comps(), perm3(&ad, &bd, &cd), 3.0, corr) {
        return r;
    }
    orient3d_b(a, b, c, d)
}

/// Stage B of `orient3d`: `det [p 1]` over rows `a, b, c, d`, along the ones
/// column (`- + - +`).
fn orient3d_b(a: &Point3, b: &Point3, c: &Point3, d: &Point3) -> f64 {
    let bcd = det3(b, c, d);
    let acd = det3(a, c, d);
    let abd = det3(a, b, d);
    let abc = det3(a, b, c);
    let s1: Exp<48> = acd.sub(&bcd);
    let s2: Exp<48> = abc.sub(&abd);
    let s: Exp<96> = s1.add(&s2);
    s.approx()
}

/// What a stage-A evaluation yields: `None` if an intermediate exceeded the tier's
/// capacity, else the result of `fin` applied to the exact expansion.
type Tier = Option<Option<f64>>;

/// Stage A of the weighted in-circle test: rows `(p - d, |p - d|² - (w_p - w_d))`,
/// expanded along the lift column (`+ - +`), with capacities `P, S, R`.
#[inline(never)]
fn incircle_a<const P: usize, const S: usize, const R: usize>(
    q: [&[f64; 2]; 3],
    w: [f64; 4],
    fin: &dyn Fn(&[f64]) -> Option<f64>,
) -> Tier {
    let lift = |p: &[f64; 2], wp: f64| -> Exp<6> {
        let s: Exp<4> = Exp::<2>::product(p[0], p[0]).add(&Exp::<2>::product(p[1], p[1]));
        s.sub(&Exp::<2>::diff(wp, w[3]))
    };
    let [ad, bd, cd] = q;
    let t1: Exp<P> = minor2(bd, cd, 0, 1).try_mul(&lift(ad, w[0]))?;
    let t2: Exp<P> = minor2(ad, cd, 0, 1).try_mul(&lift(bd, w[1]))?;
    let t3: Exp<P> = minor2(ad, bd, 0, 1).try_mul(&lift(cd, w[2]))?;
    let s: Exp<S> = t1.try_sub(&t2)?;
    let r: Exp<R> = s.try_add(&t3)?;
    Some(fin(r.comps()))
}

/// Lifted coordinate `|p|^2 - w` of a 2D point, exactly.
#[inline]
fn lift2(p: &[f64; 2], w: f64) -> Exp<5> {
    let s: Exp<4> = Exp::<2>::product(p[0], p[0]).add(&Exp::<2>::product(p[1], p[1]));
    s.sub(&Exp::<1>::from_f64(w))
}

/// Stage B of the weighted in-circle test: homogeneous 4x4 `[x y lift 1]` along the
/// lift column (`+ - + -`), minors `det[x y 1]` of the other rows.
#[inline(never)]
fn incircle_b<const P: usize, const S: usize, const R: usize>(
    p: [&Point2; 4],
    w: [f64; 4],
) -> Option<f64> {
    let [a, b, c, d] = p;
    let m = |p: &Point2, q: &Point2| minor2(p, q, 0, 1);
    let (ab, ac, ad, bc, bd, cd) = (m(a, b), m(a, c), m(a, d), m(b, c), m(b, d), m(c, d));
    let o = |pq: &Exp<4>, pr: &Exp<4>, qr: &Exp<4>| -> Exp<12> {
        let s: Exp<8> = qr.sub(pr);
        s.add(pq)
    };
    let t1: Exp<P> = o(&bc, &bd, &cd).try_mul(&lift2(a, w[0]))?;
    let t2: Exp<P> = o(&ac, &ad, &cd).try_mul(&lift2(b, w[1]))?;
    let t3: Exp<P> = o(&ab, &ad, &bd).try_mul(&lift2(c, w[2]))?;
    let t4: Exp<P> = o(&ab, &ac, &bc).try_mul(&lift2(d, w[3]))?;
    let s1: Exp<S> = t1.try_sub(&t2)?;
    let s2: Exp<S> = t3.try_sub(&t4)?;
    let r: Exp<R> = s1.try_add(&s2)?;
    Some(r.approx())
}

/// Exact weighted in-circle determinant `det [x y (x²+y²-w) 1]` over rows
/// `a, b, c, d` (equal to `incircle` for zero weights).
#[cold]
#[inline(never)]
pub(crate) fn incircle_exact(a: &Point2, b: &Point2, c: &Point2, d: &Point2, w: [f64; 4]) -> f64 {
    let mut exact = true;
    let ((ad, ta), (bd, tb), (cd, tc)) = (
        diffs(a, d, &mut exact),
        diffs(b, d, &mut exact),
        diffs(c, d, &mut exact),
    );
    let fin = |e: &[f64]| -> Option<f64> {
        let v = e[e.len() - 1];
        if exact {
            return Some(v);
        }
        let m = |p: &[f64; 2], q: &[f64; 2]| (p[0] * q[1]).abs() + (q[0] * p[1]).abs();
        let l = |p: &[f64; 2], wp: f64| p[0] * p[0] + p[1] * p[1] + (wp - w[3]).abs();
        let perm =
            m(&bd, &cd) * l(&ad, w[0]) + m(&ad, &cd) * l(&bd, w[1]) + m(&ad, &bd) * l(&cd, w[2]);
        // Rows (x, y, L); the cofactor row of row r is the cross product of the
        // other two (cyclically); dD/dx = C_x + 2x C_L, dD/dy = C_y + 2y C_L.
        let corr = || {
            let row = |p: &[f64; 2], wp: f64| [p[0], p[1], p[0] * p[0] + p[1] * p[1] - (wp - w[3])];
            let (va, vb, vc) = (row(&ad, w[0]), row(&bd, w[1]), row(&cd, w[2]));
            let g = |p: &[f64; 2], t: &[f64; 2], c: [f64; 3]| {
                t[0] * (c[0] + 2.0 * p[0] * c[2]) + t[1] * (c[1] + 2.0 * p[1] * c[2])
            };
            g(&ad, &ta, cross(&vb, &vc))
                + g(&bd, &tb, cross(&vc, &va))
                + g(&cd, &tc, cross(&va, &vb))
        };
        decide(e, perm, 4.0, corr)
    };
    // Unweighted on a coarse grid: 12 monomials of degree 4, 12·(2^12)^4 < 2^53.
    if exact && w == [0.0; 4] && on_coarse_grid(&[ad[0], ad[1], bd[0], bd[1], cd[0], cd[1]], 4096.0)
    {
        let l = |p: &[f64; 2]| p[0] * p[0] + p[1] * p[1];
        return dot(
            &[l(&ad), l(&bd), l(&cd)],
            &[
                bd[0] * cd[1] - cd[0] * bd[1],
                cd[0] * ad[1] - ad[0] * cd[1],
                ad[0] * bd[1] - bd[0] * ad[1],
            ],
        );
    }
    if let Some(v) = dd::incircle([a, b, c, d], &w) {
        return v;
    }
    // Worst-case capacities: 2*4*6 = 48, 96, 144.
    let q = [&ad, &bd, &cd];
    let r = incircle_a::<16, 32, 32>(q, w, &fin).or_else(|| incircle_a::<48, 96, 144>(q, w, &fin));
    if let Some(Some(v)) = r {
        return v;
    }
    // Worst-case capacities: 2*12*5 = 120, 240, 480.
    incircle_b::<48, 96, 96>([a, b, c, d], w)
        .or_else(|| incircle_b::<120, 240, 480>([a, b, c, d], w))
        .unwrap_or(0.0)
}

/// Stage A of the weighted in-sphere test: rows `(p - e, |p - e|² - (w_p - w_e))`,
/// along the lift column (`- + - +`).
#[inline(never)]
fn insphere_a<const P: usize, const S: usize, const R: usize>(
    q: [&[f64; 3]; 4],
    w: [f64; 5],
    fin: &dyn Fn(&[f64]) -> Option<f64>,
) -> Tier {
    let lift = |p: &[f64; 3], wp: f64| -> Exp<8> {
        let s: Exp<4> = Exp::<2>::product(p[0], p[0]).add(&Exp::<2>::product(p[1], p[1]));
        let s: Exp<6> = s.add(&Exp::<2>::product(p[2], p[2]));
        s.sub(&Exp::<2>::diff(wp, w[4]))
    };
    let [ae, be, ce, de] = q;
    let t1: Exp<P> = det3(be, ce, de).try_mul(&lift(ae, w[0]))?;
    let t2: Exp<P> = det3(ae, ce, de).try_mul(&lift(be, w[1]))?;
    let t3: Exp<P> = det3(ae, be, de).try_mul(&lift(ce, w[2]))?;
    let t4: Exp<P> = det3(ae, be, ce).try_mul(&lift(de, w[3]))?;
    let s1: Exp<S> = t2.try_sub(&t1)?;
    let s2: Exp<S> = t4.try_sub(&t3)?;
    let r: Exp<R> = s1.try_add(&s2)?;
    Some(fin(r.comps()))
}

/// Lifted coordinate `|p|^2 - w` of a 3D point, exactly.
#[inline]
fn lift3(p: &[f64; 3], w: f64) -> Exp<7> {
    let s: Exp<4> = Exp::<2>::product(p[0], p[0]).add(&Exp::<2>::product(p[1], p[1]));
    let s: Exp<6> = s.add(&Exp::<2>::product(p[2], p[2]));
    s.sub(&Exp::<1>::from_f64(w))
}

/// Stage B of the weighted in-sphere test: homogeneous 5x5 `[x y z lift 1]` along
/// the lift column (`- + - + -`), minors `det[x y z 1]` of the other four rows,
/// each expanded along its ones column (`- + - +`).
#[inline(never)]
fn insphere_b<const P: usize, const S1: usize, const S2: usize, const R: usize>(
    p: [&Point3; 5],
    w: [f64; 5],
) -> Option<f64> {
    // The ten 3x3 minors `det3(p_i, p_j, p_k)`, `i < j < k`, each computed once.
    const TRIPLES: [[usize; 3]; 10] = [
        [0, 1, 2],
        [0, 1, 3],
        [0, 1, 4],
        [0, 2, 3],
        [0, 2, 4],
        [0, 3, 4],
        [1, 2, 3],
        [1, 2, 4],
        [1, 3, 4],
        [2, 3, 4],
    ];
    let minors: [Exp<24>; 10] = std::array::from_fn(|t| {
        let [i, j, k] = TRIPLES[t];
        det3(p[i], p[j], p[k])
    });
    let d3 = |i: usize, j: usize, k: usize| -> &Exp<24> {
        let t = TRIPLES.iter().position(|&x| x == [i, j, k]).unwrap_or(0);
        &minors[t]
    };
    let o = |q: [usize; 4]| -> Exp<96> {
        let s1: Exp<48> = d3(q[0], q[2], q[3]).sub(d3(q[1], q[2], q[3]));
        let s2: Exp<48> = d3(q[0], q[1], q[2]).sub(d3(q[0], q[1], q[3]));
        s1.add(&s2)
    };
    let term = |r: usize| -> Option<Exp<P>> {
        let mut q = [0usize; 4];
        for (slot, k) in q.iter_mut().zip((0..5).filter(|&k| k != r)) {
            *slot = k;
        }
        o(q).try_mul(&lift3(p[r], w[r]))
    };
    let s1: Exp<S1> = term(1)?.try_sub(&term(0)?)?;
    let s2: Exp<S1> = term(3)?.try_sub(&term(2)?)?;
    let s: Exp<S2> = s1.try_add(&s2)?;
    let r: Exp<R> = s.try_sub(&term(4)?)?;
    Some(r.approx())
}

/// Exact weighted in-sphere determinant `det [x y z (x²+y²+z²-w) 1]` over rows
/// `a, b, c, d, e` (equal to `insphere` for zero weights).
#[cold]
#[inline(never)]
pub(crate) fn insphere_exact(p: [&Point3; 5], w: [f64; 5]) -> f64 {
    let e = p[4];
    let mut exact = true;
    let dt = [
        diffs(p[0], e, &mut exact),
        diffs(p[1], e, &mut exact),
        diffs(p[2], e, &mut exact),
        diffs(p[3], e, &mut exact),
    ];
    let q = [dt[0].0, dt[1].0, dt[2].0, dt[3].0];
    let fin = |ex: &[f64]| -> Option<f64> {
        let v = ex[ex.len() - 1];
        if exact {
            return Some(v);
        }
        let l = |x: &[f64; 3], wp: f64| x[0] * x[0] + x[1] * x[1] + x[2] * x[2] + (wp - w[4]).abs();
        let perm = perm3(&q[1], &q[2], &q[3]) * l(&q[0], w[0])
            + perm3(&q[0], &q[2], &q[3]) * l(&q[1], w[1])
            + perm3(&q[0], &q[1], &q[3]) * l(&q[2], w[2])
            + perm3(&q[0], &q[1], &q[2]) * l(&q[3], w[3]);
        // Rows (x, y, z, L): dD/dx_rc = C_rc + 2 x_rc C_rL with C the cofactors.
        let corr = || {
            let m: [[f64; 4]; 4] = std::array::from_fn(|r| {
                let x = &q[r];
                [
                    x[0],
                    x[1],
                    x[2],
                    x[0] * x[0] + x[1] * x[1] + x[2] * x[2] - (w[r] - w[4]),
                ]
            });
            let cof = cofactors4(&m);
            let mut corr = 0.0;
            for r in 0..4 {
                for c in 0..3 {
                    corr += dt[r].1[c] * (cof[r][c] + 2.0 * q[r][c] * cof[r][3]);
                }
            }
            corr
        };
        decide(ex, perm, 5.0, corr)
    };
    // Unweighted on a coarse grid: 72 monomials of degree 5, 72·(2^9)^5 < 2^53.
    if exact && w == [0.0; 5] && on_coarse_grid(q.as_flattened(), 512.0) {
        let l = |x: &[f64; 3]| x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
        let d = |a: &[f64; 3], b: &[f64; 3], c: &[f64; 3]| dot(a, &cross(b, c));
        return (l(&q[1]) * d(&q[0], &q[2], &q[3]) - l(&q[0]) * d(&q[1], &q[2], &q[3]))
            + (l(&q[3]) * d(&q[0], &q[1], &q[2]) - l(&q[2]) * d(&q[0], &q[1], &q[3]));
    }
    // Exact integer evaluation: decides ties and near-ties alike at less than
    // the cost of the double-double stage.
    if w == [0.0; 5] {
        if let Some(v) = int::insphere(p) {
            return v;
        }
    }
    if let Some(v) = dd::insphere(p, &w) {
        return v;
    }
    // Worst-case capacities: 2*24*8 = 384, 768, 1536.
    let qr = [&q[0], &q[1], &q[2], &q[3]];
    let r =
        insphere_a::<32, 64, 64>(qr, w, &fin).or_else(|| insphere_a::<384, 768, 1536>(qr, w, &fin));
    if let Some(Some(v)) = r {
        return v;
    }
    // Worst-case capacities: 2*96*7 = 1344, 2688, 5376, 6720.
    insphere_b::<128, 256, 256, 256>(p, w)
        .or_else(|| insphere_b::<1344, 2688, 5376, 6720>(p, w))
        .unwrap_or(0.0)
}

/// Cofactor matrix of a 4x4 matrix in floating point: `C[r][c] = (-1)^(r+c)`
/// times the determinant of `m` without row `r` and column `c`.
fn cofactors4(m: &[[f64; 4]; 4]) -> [[f64; 4]; 4] {
    std::array::from_fn(|r| {
        std::array::from_fn(|c| {
            let rows: [usize; 3] = std::array::from_fn(|k| if k < r { k } else { k + 1 });
            let cols: [usize; 3] = std::array::from_fn(|k| if k < c { k } else { k + 1 });
            let e = |i: usize, j: usize| m[rows[i]][cols[j]];
            let d = e(0, 0) * (e(1, 1) * e(2, 2) - e(1, 2) * e(2, 1))
                - e(0, 1) * (e(1, 0) * e(2, 2) - e(1, 2) * e(2, 0))
                + e(0, 2) * (e(1, 0) * e(2, 1) - e(1, 1) * e(2, 0));
            if (r + c) % 2 == 0 {
                d
            } else {
                -d
            }
        })
    })
}
