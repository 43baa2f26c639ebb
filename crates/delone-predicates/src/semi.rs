//! Semi-static filters (Meyer & Pion 2008 style) for the in-circle and in-sphere
//! tests, the two predicates whose permanent-based bound is expensive.
//!
//! Each function evaluates the translated determinant in plain floating point and
//! returns `(det, certified)`; when `certified` is true the sign of `det` is the
//! exact sign. Instead of a permanent (which repeats every product in absolute value)
//! the error bound is `C·Mᵈ`, `M` the largest computed coordinate difference and `d`
//! the degree, and `M²` is in turn bounded by the largest *lifted* term
//! `L = max_p fl(|p̂|²)`, which the determinant computes anyway and which needs no
//! absolute values: the whole filter is a few `max`, a few products and one compare.
//! (`orient2d`/`orient3d` keep the permanent bound: there it costs fewer
//! instructions than computing any maximum of absolute values.)
//!
//! # Derivation of the constants (own forward error analysis)
//!
//! Notation: `u = 2⁻⁵³`; `M` bounds every computed difference `|d̂|`. For every node
//! `v` of the evaluation tree we bound `|v̂| ≤ A_v·Mᵏ` and `|v̂ − v| ≤ E_v·Mᵏ`
//! (`k` the node's degree), where `v̂` is the computed value and `v` the exact value
//! of the same expression on the *exact* differences. Rounding to nearest gives
//! `fl(s ± t) = (s ± t)(1 + δ)`, `|δ| ≤ u`, and `fl(s·t) = s·t(1 + δ) + η` with
//! `|η| ≤ 2⁻¹⁰⁷⁵` (gradual underflow). Ignoring `η` for now:
//!
//! * input difference `d̂ = fl(p − q)`: since `p − q = d̂(1 + δ')`, `A = 1, E = u`;
//! * product `s·t`: `A = (1 + u)·A_s·A_t`, `E = A_s·E_t + (A_t + E_t)·E_s + u·A_s·A_t`;
//! * sum or difference: `A = (1 + u)(A_s + A_t)`, `E = E_s + E_t + u·(A_s + A_t)`.
//!
//! Carried through the evaluation orders below with exact rational arithmetic
//! (re-checked in `f64` by the unit test `propagated_error_coefficients`), with an
//! extra `u²·A_s·A_t` per product reserved for underflow, this gives
//! `|det̂ − det| ≤ (k + r·u)·u·Mᵈ`:
//!
//! | predicate | evaluation order (left to right)                                 | `d` | `k`  | `r`  | `A` |
//! |-----------|------------------------------------------------------------------|-----|------|------|-----|
//! | incircle  | `Σ (Δpx·Δpx + Δpy·Δpy)·(Δqx·Δry − Δrx·Δqy)` over the 3 cyclic terms | 4   | 128  | 624  | 12  |
//! | insphere  | `(l_b·D_acd − l_a·D_bcd) + (l_d·D_abc − l_c·D_abd)`, `l = (Δx² + Δy²) + Δz²`, `D_pqr = (Δpz·m_qr − Δqz·m_pr) + Δrz·m_pq`, `m_pq = Δpx·Δqy − Δqx·Δpy` | 5 | 1104 | 9072 | 72 |
//!
//! Every computed lifted term satisfies `l̂ ≥ (1 − u)³·|d̂|²` (sums of non-negative
//! rounded squares), so `M² ≤ L/(1 − u)³`. Hence, with `C = (k + 2⁻³⁰)·u`:
//!
//! * incircle certifies when `|det̂| > C·L² + T`;
//! * insphere certifies when `det̂² > C²·L⁵ + T` (squaring avoids a square root:
//!   `M⁵ ≤ (L/(1 − u)³)^(5/2)`);
//!
//! with `T = 2⁻¹⁰⁰⁰`. The bounds and the square are evaluated in floating point with
//! at most seven roundings, each losing at most a factor `(1 ± u)`, and `M²` vs `L`
//! loses `(1 − u)³` per factor; all of this is `O(50·u)` relative, far below the
//! margin `2⁻³⁰/k` built into `C`, and so is the `r·u` second-order term.
//!
//! **Underflow.** The absolute errors `η` of underflowing products, propagated
//! through the tree (multiplied by at most `A·max(1, M)ᵈ`), add at most
//! `(#products)·72·η·max(1, Mᵈ) < 2⁻¹⁰⁶²·max(1, Mᵈ)`, covered by `T` for `M < 1`
//! and by the `2⁻³⁰` margin for `M ≥ 1` (for insphere: `√(C²L⁵ + T)` exceeds
//! `C·L^(5/2) + 2⁻¹⁰⁶²` in both regimes). If `L ≥ 2⁻⁹⁰⁰` the `2η` lost in each
//! lifted term is below `u²·L`, so `M² ≤ L/(1 − u)³` still holds up to the margin.
//! If `L < 2⁻⁹⁰⁰` then `M < 2⁻⁴⁴⁹`, so `|det̂| ≤ 73·Mᵈ + 2⁻¹⁰⁶² < 2⁻¹⁰⁶¹`, and neither
//! `|det̂| > T` nor `det̂² > T` can hold: nothing is certified.
//!
//! **Overflow.** If some intermediate overflows, `det̂` is `±∞` or NaN. NaN fails the
//! comparison. Otherwise the bound is finite only if `128·L²` (incircle) resp. `L⁵`
//! (insphere) is finite, which implies `A·Mᵈ < 2¹⁰²³` for every node (`A ≤ 12`
//! resp. `M⁵ ≤ 2⁵¹²·(1 + O(u))`, `A ≤ 72`): no intermediate overflowed, and an
//! overflowing `det̂²` (= `+∞`) is then a correct certificate because
//! `|det̂| > 2⁵¹¹ >` the bound. An infinite or NaN bound never certifies. So no
//! explicit range check is needed: the range checks of Meyer & Pion are implied by
//! `T` and by the finiteness of the bound.
//!
//! When a filter does not certify, the caller falls back to the permanent-based
//! filter and then the exact stage, so the returned sign never depends on which
//! stage decided.

use crate::{Point2, Point3, U};

/// `(k + 2⁻³⁰)·u` for the first-order coefficient `k`.
const fn coef(k: f64) -> f64 {
    (k + 1.0 / (1u64 << 30) as f64) * U
}

/// incircle: `C·L²`, evaluated as `(C/128)·((128·L)·L)` so that it is infinite
/// whenever `128·L²` overflows.
const IC_C: f64 = coef(128.0) / 128.0;
/// insphere (squared comparison): `C²·L⁵`.
const IS_C2: f64 = coef(1104.0) * coef(1104.0);

/// Absolute floor of every bound, covering all underflow errors: `2⁻¹⁰⁰⁰`.
const TINY: f64 = f64::from_bits((1023 - 1000) << 52);

/// `max` that compiles to a single `maxsd` (the lifted terms are never NaN unless
/// the determinant is NaN too, which is never certified).
#[inline(always)]
fn fmax(a: f64, b: f64) -> f64 {
    if a > b {
        a
    } else {
        b
    }
}

/// Semi-static incircle: `(det, certified)`.
#[inline(always)]
pub(crate) fn incircle(a: &Point2, b: &Point2, c: &Point2, d: &Point2) -> (f64, bool) {
    let (adx, ady) = (a[0] - d[0], a[1] - d[1]);
    let (bdx, bdy) = (b[0] - d[0], b[1] - d[1]);
    let (cdx, cdy) = (c[0] - d[0], c[1] - d[1]);
    let al = adx * adx + ady * ady;
    let bl = bdx * bdx + bdy * bdy;
    let cl = cdx * cdx + cdy * cdy;
    let det =
        al * (bdx * cdy - cdx * bdy) + bl * (cdx * ady - adx * cdy) + cl * (adx * bdy - bdx * ady);
    let l = fmax(fmax(al, bl), cl);
    let eps = IC_C * ((l * 128.0) * l) + TINY;
    (det, det.abs() > eps)
}

/// Semi-static insphere: `(det, certified)`.
#[inline(always)]
pub(crate) fn insphere(a: &Point3, b: &Point3, c: &Point3, d: &Point3, e: &Point3) -> (f64, bool) {
    let sub = |q: &Point3| [q[0] - e[0], q[1] - e[1], q[2] - e[2]];
    let (ae, be, ce, de) = (sub(a), sub(b), sub(c), sub(d));
    // 2x2 (x, y) minors.
    let m = |s: &[f64; 3], t: &[f64; 3]| s[0] * t[1] - t[0] * s[1];
    let (ab, ac, ad) = (m(&ae, &be), m(&ae, &ce), m(&ae, &de));
    let (bc, bd, cd) = (m(&be, &ce), m(&be, &de), m(&ce, &de));
    // 3x3 by cofactors along z: p_z m(q, r) - q_z m(p, r) + r_z m(p, q).
    let d3 = |pz: f64, qz: f64, rz: f64, qr: f64, pr: f64, pq: f64| pz * qr - qz * pr + rz * pq;
    let bcd = d3(be[2], ce[2], de[2], cd, bd, bc);
    let acd = d3(ae[2], ce[2], de[2], cd, ad, ac);
    let abd = d3(ae[2], be[2], de[2], bd, ad, ab);
    let abc = d3(ae[2], be[2], ce[2], bc, ac, ab);
    let lift = |q: &[f64; 3]| q[0] * q[0] + q[1] * q[1] + q[2] * q[2];
    let (la, lb, lc, ld) = (lift(&ae), lift(&be), lift(&ce), lift(&de));
    let det = (lb * acd - la * bcd) + (ld * abc - lc * abd);
    let l = fmax(fmax(la, lb), fmax(lc, ld));
    let l2 = l * l;
    let eps2 = IS_C2 * ((l2 * l2) * l) + TINY;
    (det, det * det > eps2)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `(A, E)` of a node, in units of `Mᵏ` (see the module docs).
    #[derive(Clone, Copy)]
    struct N(f64, f64);
    const D: N = N(1.0, U);
    fn mul(s: N, t: N) -> N {
        N(
            (1.0 + U) * s.0 * t.0,
            s.0 * t.1 + (t.0 + t.1) * s.1 + (U + U * U) * s.0 * t.0,
        )
    }
    fn add(s: N, t: N) -> N {
        N((1.0 + U) * (s.0 + t.0), s.1 + t.1 + U * (s.0 + t.0))
    }

    /// Re-derives the first-order coefficients `k` of the module docs by propagating
    /// the error rules through the evaluation orders used above.
    #[test]
    fn propagated_error_coefficients() {
        let minor = || add(mul(D, D), mul(D, D));
        // incircle: sum of (lift2 * minor), left to right.
        let lift2 = add(mul(D, D), mul(D, D));
        let t = mul(lift2, minor());
        let ic = add(add(t, t), t);
        // insphere.
        let d3 = add(add(mul(D, minor()), mul(D, minor())), mul(D, minor()));
        let lift3 = add(add(mul(D, D), mul(D, D)), mul(D, D));
        let t = mul(lift3, d3);
        let is = add(add(t, t), add(t, t));
        for (node, k, r, a) in [(ic, 128.0, 624.0, 12.0), (is, 1104.0, 9072.0, 72.0)] {
            let e = node.1 / U;
            assert!(e > k && e <= k + (r + 1.0) * U, "E/u = {e} vs k = {k}");
            assert!(node.0 >= a && node.0 < a * (1.0 + 1e-12));
            // The filter constant covers it with a wide margin.
            assert!(coef(k) * (1.0 - 64.0 * U) > node.1);
        }
        assert_eq!(IC_C * 128.0, coef(128.0));
    }

    struct Rng(u64);
    impl Rng {
        fn f(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (self.0 >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        }
    }

    fn exact_ic(p: &[[f64; 2]; 4]) -> f64 {
        crate::exact::incircle_exact(&p[0], &p[1], &p[2], &p[3], [0.0; 4]).signum()
    }
    fn exact_is(p: &[[f64; 3]; 5]) -> f64 {
        crate::exact::insphere_exact([&p[0], &p[1], &p[2], &p[3], &p[4]], [0.0; 5]).signum()
    }
    fn ic(p: &[[f64; 2]; 4]) -> (f64, bool) {
        incircle(&p[0], &p[1], &p[2], &p[3])
    }
    fn is(p: &[[f64; 3]; 5]) -> (f64, bool) {
        insphere(&p[0], &p[1], &p[2], &p[3], &p[4])
    }
    fn pow2(e: i32) -> f64 {
        2f64.powi(e)
    }

    /// Near-degenerate inputs whose determinant is close to the filter bound: the
    /// last point is moved off the circle/sphere of the others by a log-spaced
    /// relative amount. Every certified sign must be exact, and some certified
    /// determinants must lie within a factor 4 of the bound (the tight region).
    #[test]
    fn tight_region_is_sound() {
        let mut r = Rng(11);
        let (mut tight_ic, mut tight_is, mut undecided) = (0, 0, 0);
        for i in 0..20_000 {
            let t = pow2(-52 + (i % 40));
            // incircle: d on the circle x² + y² = 1 around a random center, moved by t.
            let c0 = [r.f(), r.f()];
            let on = |r: &mut Rng, rad: f64| {
                let th = std::f64::consts::PI * r.f();
                [c0[0] + rad * th.cos(), c0[1] + rad * th.sin()]
            };
            let mut p = [on(&mut r, 1.0), on(&mut r, 1.0), on(&mut r, 1.0), [0.0; 2]];
            let off = 1.0 + t * r.f();
            p[3] = on(&mut r, off);
            let (det, ok) = ic(&p);
            if ok {
                assert_eq!(det.signum(), exact_ic(&p), "{p:?}");
                let l = p[..3]
                    .iter()
                    .map(|q| (q[0] - p[3][0]).powi(2) + (q[1] - p[3][1]).powi(2))
                    .fold(0.0, f64::max);
                if det.abs() < 4.0 * IC_C * 128.0 * l * l {
                    tight_ic += 1;
                }
            } else {
                undecided += 1;
            }
            // insphere: e on the unit sphere around a random center, moved by t.
            let c0 = [r.f(), r.f(), r.f()];
            let on = |r: &mut Rng, rad: f64| {
                let (th, z) = (std::f64::consts::PI * r.f(), r.f());
                let w = (1.0 - z * z).sqrt();
                [
                    c0[0] + rad * w * th.cos(),
                    c0[1] + rad * w * th.sin(),
                    c0[2] + rad * z,
                ]
            };
            let mut q = [[0.0; 3]; 5];
            for v in &mut q[..4] {
                *v = on(&mut r, 1.0);
            }
            let off = 1.0 + t * r.f();
            q[4] = on(&mut r, off);
            let (det, ok) = is(&q);
            if ok {
                assert_eq!(det.signum(), exact_is(&q), "{q:?}");
                let l = q[..4]
                    .iter()
                    .map(|v| (0..3).map(|k| (v[k] - q[4][k]).powi(2)).sum::<f64>())
                    .fold(0.0, f64::max);
                if det * det < 16.0 * IS_C2 * l.powi(5) {
                    tight_is += 1;
                }
            } else {
                undecided += 1;
            }
        }
        assert!(tight_ic > 10 && tight_is > 10, "{tight_ic} {tight_is}");
        assert!(undecided > 10, "the sweep must reach the undecided region");
    }

    /// Scaling by `2^s` multiplies the exact determinant by a positive power of two,
    /// so the exact sign is that at scale 1. Across the whole exponent range —
    /// including the underflow floor `T` and the overflow guards — every certified
    /// sign must match, and moderate scales must be certified.
    #[test]
    fn sound_at_extreme_scales() {
        let mut r = Rng(5);
        for _ in 0..40 {
            let p2: [[f64; 2]; 4] = std::array::from_fn(|_| [r.f(), r.f()]);
            let p3: [[f64; 3]; 5] = std::array::from_fn(|_| [r.f(), r.f(), r.f()]);
            let (s2, s3) = (exact_ic(&p2), exact_is(&p3));
            assert!(s2 != 0.0 && s3 != 0.0);
            for e in -1080..=1030 {
                let k = pow2(e);
                let q2 = p2.map(|p| p.map(|x| x * k));
                let q3 = p3.map(|p| p.map(|x| x * k));
                // Exactly scaled unless the coordinates under- or overflowed.
                if q2
                    .iter()
                    .flatten()
                    .any(|x| x * pow2(-e) != x / k || !x.is_finite())
                {
                    continue;
                }
                let (d2, ok2) = ic(&q2);
                if ok2 {
                    assert_eq!(d2.signum(), s2, "incircle at 2^{e}");
                }
                if (-100..=100).contains(&e) {
                    assert!(ok2, "incircle not certified at 2^{e}");
                }
                if q3
                    .iter()
                    .flatten()
                    .any(|x| x / k != x * pow2(-e) || !x.is_finite())
                {
                    continue;
                }
                let (d3, ok3) = is(&q3);
                if ok3 {
                    assert_eq!(d3.signum(), s3, "insphere at 2^{e}");
                }
                if (-80..=80).contains(&e) {
                    assert!(ok3, "insphere not certified at 2^{e}");
                }
            }
        }
    }

    /// Just inside / outside the thresholds: the floor `T` (tiny inputs are never
    /// certified) and the overflow guards (huge inputs are never certified, and an
    /// infinite or NaN determinant never is).
    #[test]
    fn threshold_boundaries() {
        let p2 = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.25, 0.25]];
        let p3 = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, -1.0],
            [0.125, 0.125, -0.125],
        ];
        let sc2 = |e: i32| p2.map(|p| p.map(|x| x * pow2(e)));
        let sc3 = |e: i32| p3.map(|p| p.map(|x| x * pow2(e)));
        // incircle: det ≈ 0.375·2^(4e), bound ≈ 128u·4^... ≥ T = 2^-1000.
        assert!(ic(&sc2(-240)).1);
        assert!(!ic(&sc2(-252)).1, "below the floor T");
        // 128·L² overflows once L ≥ 2^508, i.e. coordinates ≥ 2^254.
        assert!(ic(&sc2(250)).1);
        assert!(!ic(&sc2(255)).1, "overflow guard");
        // insphere: det² ≈ 2^(10e)·c > T needs e ≳ −100; L⁵ overflows for e ≥ 103.
        assert!(is(&sc3(-95)).1);
        assert!(!is(&sc3(-102)).1, "below the floor T");
        assert!(is(&sc3(100)).1);
        assert!(!is(&sc3(103)).1, "overflow guard");
        // Non-finite inputs are never certified.
        let mut q = p3;
        q[0][1] = f64::INFINITY;
        assert!(!is(&q).1);
        q[0][1] = f64::NAN;
        assert!(!is(&q).1);
        let mut q = p2;
        q[2][0] = f64::NEG_INFINITY;
        assert!(!ic(&q).1);
        q[2][0] = f64::NAN;
        assert!(!ic(&q).1);
    }
}
