//! Exact (slow) stages of the predicates, reached only when the floating-point
//! filter cannot certify the sign.
//!
//! Each predicate has two exact formulations:
//!
//! * **Stage A** — when every coordinate difference `p - q` the determinant needs is
//!   itself a double (the rounding error of the subtraction is zero, which is the
//!   case for integer grids, for nearby points by Sterbenz' lemma, and for most
//!   degenerate inputs), the translated determinant is evaluated exactly on those
//!   differences: short expansions, cheap.
//! * **Stage B** — otherwise the *homogeneous* determinant on the raw coordinates
//!   (rows `[x, y, (lift,) 1]`) is expanded by cofactors with expansion arithmetic;
//!   it needs no differences at all, hence is exact for all finite inputs barring
//!   overflow and underflow.
//!
//! All buffers are fixed-size stack arrays; nothing allocates.

use crate::expansion::{two_diff, Exp};
use crate::{Point2, Point3};

/// `p[i] * q[j] - q[i] * p[j]`, the 2x2 minor on columns `i, j` of rows `p, q`.
#[inline]
fn minor2(p: &[f64], q: &[f64], i: usize, j: usize) -> Exp<4> {
    Exp::<2>::product(p[i], q[j]).sub(&Exp::<2>::product(q[i], p[j]))
}

/// Exact differences `p - q` if all are representable, else `None`.
#[inline]
fn exact_diffs<const D: usize>(p: &[f64; D], q: &[f64; D]) -> Option<[f64; D]> {
    let mut r = [0.0; D];
    for k in 0..D {
        let (x, y) = two_diff(p[k], q[k]);
        if y != 0.0 {
            return None;
        }
        r[k] = x;
    }
    Some(r)
}

/// Exact `orient2d`.
#[cold]
#[inline(never)]
pub(crate) fn orient2d_exact(a: &Point2, b: &Point2, c: &Point2) -> f64 {
    if let (Some(ac), Some(bc)) = (exact_diffs(a, c), exact_diffs(b, c)) {
        let l = Exp::<2>::product(ac[0], bc[1]);
        let r = Exp::<2>::product(ac[1], bc[0]);
        return l.sub::<2, 4>(&r).approx();
    }
    // det [a 1; b 1; c 1] along the ones column.
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

/// Exact `orient3d`.
#[cold]
#[inline(never)]
pub(crate) fn orient3d_exact(a: &Point3, b: &Point3, c: &Point3, d: &Point3) -> f64 {
    if let (Some(ad), Some(bd), Some(cd)) =
        (exact_diffs(a, d), exact_diffs(b, d), exact_diffs(c, d))
    {
        return det3(&ad, &bd, &cd).approx();
    }
    // det [p 1] over rows a, b, c, d, along the ones column: - + - +.
    let bcd = det3(b, c, d);
    let acd = det3(a, c, d);
    let abd = det3(a, b, d);
    let abc = det3(a, b, c);
    let s1: Exp<48> = acd.sub(&bcd);
    let s2: Exp<48> = abc.sub(&abd);
    let s: Exp<96> = s1.add(&s2);
    s.approx()
}

/// Lifted coordinate `|p|^2 - w` of a 2D point, exactly.
#[inline]
fn lift2(p: &[f64; 2], w: f64) -> Exp<5> {
    let s: Exp<4> = Exp::<2>::product(p[0], p[0]).add(&Exp::<2>::product(p[1], p[1]));
    s.sub(&Exp::<1>::from_f64(w))
}

/// Exact weighted in-circle determinant `det [x y (x²+y²-w) 1]` over rows
/// `a, b, c, d` (equal to `incircle` for zero weights).
#[cold]
#[inline(never)]
pub(crate) fn incircle_exact(a: &Point2, b: &Point2, c: &Point2, d: &Point2, w: [f64; 4]) -> f64 {
    if let (Some(ad), Some(bd), Some(cd)) =
        (exact_diffs(a, d), exact_diffs(b, d), exact_diffs(c, d))
    {
        // Translated: rows (p - d, |p - d|^2 - (w_p - w_d)), expanded along the lift.
        let lift = |p: &[f64; 2], wp: f64| -> Exp<6> {
            let s: Exp<4> = Exp::<2>::product(p[0], p[0]).add(&Exp::<2>::product(p[1], p[1]));
            s.sub(&Exp::<2>::diff(wp, w[3]))
        };
        let (la, lb, lc) = (lift(&ad, w[0]), lift(&bd, w[1]), lift(&cd, w[2]));
        let t1: Exp<48> = minor2(&bd, &cd, 0, 1).mul(&la);
        let t2: Exp<48> = minor2(&ad, &cd, 0, 1).mul(&lb);
        let t3: Exp<48> = minor2(&ad, &bd, 0, 1).mul(&lc);
        let s: Exp<96> = t1.sub(&t2);
        let r: Exp<144> = s.add(&t3);
        return r.approx();
    }
    // Homogeneous 4x4 along the lift column: + - + -, minors det[x y 1] of the others.
    let m = |p: &Point2, q: &Point2| minor2(p, q, 0, 1);
    let (ab, ac, ad, bc, bd, cd) = (m(a, b), m(a, c), m(a, d), m(b, c), m(b, d), m(c, d));
    let o = |pq: &Exp<4>, pr: &Exp<4>, qr: &Exp<4>| -> Exp<12> {
        let s: Exp<8> = qr.sub(pr);
        s.add(pq)
    };
    let obcd = o(&bc, &bd, &cd);
    let oacd = o(&ac, &ad, &cd);
    let oabd = o(&ab, &ad, &bd);
    let oabc = o(&ab, &ac, &bc);
    let t1: Exp<120> = obcd.mul(&lift2(a, w[0]));
    let t2: Exp<120> = oacd.mul(&lift2(b, w[1]));
    let t3: Exp<120> = oabd.mul(&lift2(c, w[2]));
    let t4: Exp<120> = oabc.mul(&lift2(d, w[3]));
    let s1: Exp<240> = t1.sub(&t2);
    let s2: Exp<240> = t3.sub(&t4);
    let r: Exp<480> = s1.add(&s2);
    r.approx()
}

/// Lifted coordinate `|p|^2 - w` of a 3D point, exactly.
#[inline]
fn lift3(p: &[f64; 3], w: f64) -> Exp<7> {
    let s: Exp<4> = Exp::<2>::product(p[0], p[0]).add(&Exp::<2>::product(p[1], p[1]));
    let s: Exp<6> = s.add(&Exp::<2>::product(p[2], p[2]));
    s.sub(&Exp::<1>::from_f64(w))
}

/// Exact weighted in-sphere determinant `det [x y z (x²+y²+z²-w) 1]` over rows
/// `a, b, c, d, e` (equal to `insphere` for zero weights).
#[cold]
#[inline(never)]
pub(crate) fn insphere_exact(p: [&Point3; 5], w: [f64; 5]) -> f64 {
    let e = p[4];
    if let (Some(ae), Some(be), Some(ce), Some(de)) = (
        exact_diffs(p[0], e),
        exact_diffs(p[1], e),
        exact_diffs(p[2], e),
        exact_diffs(p[3], e),
    ) {
        // Translated 4x4: rows (p - e, |p - e|^2 - (w_p - w_e)), along the lift: - + - +.
        let lift = |q: &[f64; 3], wq: f64| -> Exp<8> {
            let s: Exp<4> = Exp::<2>::product(q[0], q[0]).add(&Exp::<2>::product(q[1], q[1]));
            let s: Exp<6> = s.add(&Exp::<2>::product(q[2], q[2]));
            s.sub(&Exp::<2>::diff(wq, w[4]))
        };
        let t1: Exp<384> = det3(&be, &ce, &de).mul(&lift(&ae, w[0]));
        let t2: Exp<384> = det3(&ae, &ce, &de).mul(&lift(&be, w[1]));
        let t3: Exp<384> = det3(&ae, &be, &de).mul(&lift(&ce, w[2]));
        let t4: Exp<384> = det3(&ae, &be, &ce).mul(&lift(&de, w[3]));
        let s1: Exp<768> = t2.sub(&t1);
        let s2: Exp<768> = t4.sub(&t3);
        let r: Exp<1536> = s1.add(&s2);
        return r.approx();
    }
    // Homogeneous 5x5 along the lift column: - + - + -, minors det[x y z 1] of the
    // other four rows, each expanded along its ones column: - + - +.
    let d3 = |i: usize, j: usize, k: usize| det3(p[i], p[j], p[k]);
    let o = |q: [usize; 4]| -> Exp<96> {
        let s1: Exp<48> = d3(q[0], q[2], q[3]).sub(&d3(q[1], q[2], q[3]));
        let s2: Exp<48> = d3(q[0], q[1], q[2]).sub(&d3(q[0], q[1], q[3]));
        s1.add(&s2)
    };
    let term = |r: usize| -> Exp<1344> {
        let mut q = [0usize; 4];
        for (slot, k) in q.iter_mut().zip((0..5).filter(|&k| k != r)) {
            *slot = k;
        }
        o(q).mul(&lift3(p[r], w[r]))
    };
    let s1: Exp<2688> = term(1).sub(&term(0));
    let s2: Exp<2688> = term(3).sub(&term(2));
    let s: Exp<5376> = s1.add(&s2);
    let r: Exp<6720> = s.sub(&term(4));
    r.approx()
}
