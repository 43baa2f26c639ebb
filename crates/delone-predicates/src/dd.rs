//! Double-double stage: the intermediate step between the floating-point filters
//! and the exact expansion stages (the role of Shewchuk's adaptive stages B/C).
//!
//! The coordinate differences are taken *exactly* as two-term pairs
//! `p − q = h + l` (`two_diff`), and the translated determinant is evaluated in
//! double-double arithmetic: every value is an unevaluated pair `h + l` whose high
//! parts are multiplied and added with error-free transformations
//! (`two_product`, `two_sum`) while the low-order cross terms are combined in plain
//! floating point. No renormalisation is done: the error analysis below works with
//! *magnitude bounds*, for which a non-normalised low part is as good as a
//! normalised one. The result `h + l` is within `E·Mᵈ` of the exact determinant,
//! where `M` bounds every rounded coordinate difference, `d` is the degree and
//! `E = k·u²` (`u = 2⁻⁵³`) with a small `k` per predicate; so every near-degenerate
//! but nonzero decision whose determinant exceeds about `k·u²·Mᵈ` — in particular
//! all decisions on points rounded from a circle or a sphere, whose determinants
//! are of order `u·Mᵈ` — is certified here at a few hundred flops, and only exact
//! (or astronomically close) ties reach the expansion stages.
//!
//! # Error analysis (own derivation)
//!
//! For a node with computed pair `(h, l)`, value `ṽ = h + l`, and exact value `v`
//! (the same expression on the exact differences), we bound `|h| ≤ H·Mᵏ`,
//! `|l| ≤ L·Mᵏ`, `|ṽ − v| ≤ E·Mᵏ` (`k` the node's degree). Rounding to nearest gives
//! `|fl(x) − x| ≤ u·|x|`, and `two_sum`/`two_diff`/`two_product` are exact (barring
//! underflow, treated below), their error term being at most `u` times the exact
//! result in magnitude.
//!
//! * **Leaf** (a coordinate difference `two_diff(p, q)`; or a weight difference,
//!   which has degree 2, see below): exact, `|h| ≤ M`, `|l| ≤ u·|h|`:
//!   `H = 1, L = u, E = 0`.
//! * **Sum/difference** `a ± b`: `(s, e) = two_sum(a.h, ±b.h)`,
//!   `c = fl(a.l ± b.l)`, result `(s, fl(e + c))`.
//!   `H = (1+u)(Ha+Hb)`; `|e| ≤ u(Ha+Hb)`, `|c| ≤ (1+u)(La+Lb)`;
//!   `L = (1+u)(u(Ha+Hb) + (1+u)(La+Lb))`; the two roundings lose at most
//!   `R = u(La+Lb) + u(u(Ha+Hb) + (1+u)(La+Lb))`; `E = Ea + Eb + R`.
//! * **Product** `a·b`: `(p, e) = two_product(a.h, b.h)`,
//!   `c = fl(fl(a.h·b.l) + fl(a.l·b.h))`, result `(p, fl(e + c))`; the term
//!   `a.l·b.l` is dropped.
//!   `H = (1+u)·Ha·Hb`; `|e| ≤ u·Ha·Hb`, `|c| ≤ (1+u)²(Ha·Lb + La·Hb)`;
//!   `L = (1+u)(u·Ha·Hb + (1+u)²(Ha·Lb + La·Hb))`;
//!   rounding `R = u(|e| + |c|) + u(Ha·Lb + La·Hb) + u(1+u)(Ha·Lb + La·Hb) + La·Lb`
//!   (last addition, the two cross products, their sum, the dropped term);
//!   propagated `|ãb̃ − ab| ≤ (Ha+La)·Eb + (Hb+Lb+Eb)·Ea`; `E` is their sum.
//!
//! These rules are applied mechanically to the *same generic code* that computes
//! the determinants (the [`Ring`] trait has a bound-propagating implementation in
//! the unit tests), which checks that the constants below dominate the propagated
//! `E` (they are rounded up with a relative margin `2⁻²⁰`):
//!
//! | predicate | degree `d` | propagated `E/u²` | constant `k` |
//! |-----------|-----------:|------------------:|-------------:|
//! | orient2d  | 2          | see `tests`        | [`O2_K`]     |
//! | orient3d  | 3          |                   | [`O3_K`]     |
//! | incircle  | 4          |                   | [`IC_K`]     |
//! | insphere  | 5          |                   | [`IS_K`]     |
//!
//! The sign of `ṽ = h + l` is that of `fl(h + l)`; it is certified when
//! `|fl(h + l)| > k·u²·Mᵈ + T`: `|ṽ| ≥ |fl(h + l)|/(1+u)`, and the bound, computed
//! with at most `d + 1` roundings, underestimates `k·u²·Mᵈ` by a relative
//! `O((d+2)·u)`, far inside the margin.
//!
//! **Weights.** The weighted tests subtract the weight difference `w_p − w_last`
//! (exact, `two_diff`) from the lifted coordinate. It is a degree-2 leaf, so `M` is
//! raised if needed so that `M² ≥ max|w_p − w_last|` (via a rounded-up square root).
//!
//! **Underflow.** `two_product` (FMA or Dekker) and the plain products lose at most a
//! few `2⁻¹⁰⁷⁵` absolutely when their results are subnormal. Propagated through the
//! later operations (multiplied by at most `A·max(1, M)ᵈ`, `A < 2⁸`, with fewer than
//! 2⁸ products), this is below `2⁻¹⁰⁵⁰·max(1, M)ᵈ`: covered by the floor
//! `T = 2⁻¹⁰⁰⁰` when `M < 1` and by the `2⁻²⁰` margin on `k·u²·Mᵈ` when `M ≥ 1`.
//! The computed `Mᵈ` underflowing loses less than `2⁻¹⁰²²`, also below `T`.
//!
//! **Overflow.** The stage only runs when `M ≤ 2¹⁵⁰` (a check that also rejects
//! NaN): then every intermediate is below `2⁸·M⁵ ≤ 2⁷⁵⁸`, Dekker's splitter product
//! below `2⁷⁸⁶`, and nothing overflows. Larger inputs go straight to the exact
//! expansion stages.

use crate::expansion::{two_diff, two_product, two_sum};
use crate::U;

/// Arithmetic on which the determinant formulas are written once: double-double
/// evaluation ([`Dd`]) and, in the tests, the propagation of the error bounds.
pub(crate) trait Ring: Copy {
    fn add(self, o: Self) -> Self;
    fn sub(self, o: Self) -> Self;
    fn mul(self, o: Self) -> Self;
}

/// An unevaluated (not necessarily normalised) pair `h + l`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Dd {
    h: f64,
    l: f64,
}

impl Ring for Dd {
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        let (s, e) = two_sum(self.h, o.h);
        Dd {
            h: s,
            l: e + (self.l + o.l),
        }
    }
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        let (s, e) = two_diff(self.h, o.h);
        Dd {
            h: s,
            l: e + (self.l - o.l),
        }
    }
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        let (p, e) = two_product(self.h, o.h);
        Dd {
            h: p,
            l: e + (self.h * o.l + self.l * o.h),
        }
    }
}

/// `orient2d` on rows `a, b` (differences to the last point).
#[inline(always)]
pub(crate) fn orient2d_g<T: Ring>(a: [T; 2], b: [T; 2]) -> T {
    a[0].mul(b[1]).sub(a[1].mul(b[0]))
}

/// `det[p; q; r]` along the first column with `(y, z)` minors.
#[inline(always)]
pub(crate) fn orient3d_g<T: Ring>(p: [T; 3], q: [T; 3], r: [T; 3]) -> T {
    let m = |s: [T; 3], t: [T; 3]| s[1].mul(t[2]).sub(s[2].mul(t[1]));
    p[0].mul(m(q, r))
        .add(q[0].mul(m(r, p)))
        .add(r[0].mul(m(p, q)))
}

/// Weighted in-circle on rows `(p, |p|² − w_p)`: `Σ l_p·m(q, r)` cyclically.
#[inline(always)]
pub(crate) fn incircle_g<T: Ring>(p: [[T; 2]; 3], w: [T; 3]) -> T {
    let m = |s: [T; 2], t: [T; 2]| s[0].mul(t[1]).sub(t[0].mul(s[1]));
    let l = |s: [T; 2], w: T| s[0].mul(s[0]).add(s[1].mul(s[1])).sub(w);
    let [a, b, c] = p;
    l(a, w[0])
        .mul(m(b, c))
        .add(l(b, w[1]).mul(m(c, a)))
        .add(l(c, w[2]).mul(m(a, b)))
}

/// Weighted in-sphere on rows `(p, |p|² − w_p)`:
/// `(l_b·D_acd − l_a·D_bcd) + (l_d·D_abc − l_c·D_abd)` with
/// `D_pqr = p_z·m_qr − q_z·m_pr + r_z·m_pq`, `m_pq = p_x·q_y − q_x·p_y`.
#[inline(always)]
pub(crate) fn insphere_g<T: Ring>(p: [[T; 3]; 4], w: [T; 4]) -> T {
    let m = |s: [T; 3], t: [T; 3]| s[0].mul(t[1]).sub(t[0].mul(s[1]));
    let [a, b, c, d] = p;
    let (ab, ac, ad) = (m(a, b), m(a, c), m(a, d));
    let (bc, bd, cd) = (m(b, c), m(b, d), m(c, d));
    let d3 = |pz: T, qz: T, rz: T, qr: T, pr: T, pq: T| pz.mul(qr).sub(qz.mul(pr)).add(rz.mul(pq));
    let bcd = d3(b[2], c[2], d[2], cd, bd, bc);
    let acd = d3(a[2], c[2], d[2], cd, ad, ac);
    let abd = d3(a[2], b[2], d[2], bd, ad, ab);
    let abc = d3(a[2], b[2], c[2], bc, ac, ab);
    let l = |s: [T; 3], w: T| {
        s[0].mul(s[0])
            .add(s[1].mul(s[1]))
            .add(s[2].mul(s[2]))
            .sub(w)
    };
    let (la, lb, lc, ld) = (l(a, w[0]), l(b, w[1]), l(c, w[2]), l(d, w[3]));
    lb.mul(acd)
        .sub(la.mul(bcd))
        .add(ld.mul(abc).sub(lc.mul(abd)))
}

/// `k·u²` rounded up by the relative margin `2⁻²⁰`.
const fn coef(k: f64) -> f64 {
    k * (1.0 + 1.0 / (1u64 << 20) as f64) * U * U
}

/// First-order coefficients `k` (in units of `u²·Mᵈ`), dominating the propagated
/// bounds (checked by the unit test `constants_dominate_propagated_bounds`).
pub(crate) const O2_K: f64 = 32.0;
/// See [`O2_K`].
pub(crate) const O3_K: f64 = 352.0;
/// See [`O2_K`].
pub(crate) const IC_K: f64 = 1920.0;
/// See [`O2_K`].
pub(crate) const IS_K: f64 = 20608.0;

/// Absolute floor covering underflow: `2⁻¹⁰⁰⁰`.
const TINY: f64 = f64::from_bits((1023 - 1000) << 52);
/// Largest `M` for which the stage runs: `2¹⁵⁰`.
const HUGE: f64 = f64::from_bits((1023 + 150) << 52);

/// Exact pairs of the differences `p − q` and the largest `|fl(p − q)|` so far.
#[inline(always)]
fn leaves<const D: usize>(p: &[f64; D], q: &[f64; D], m: &mut f64) -> [Dd; D] {
    std::array::from_fn(|k| {
        let (h, l) = two_diff(p[k], q[k]);
        let a = h.abs();
        if a > *m {
            *m = a;
        }
        Dd { h, l }
    })
}

/// Weight differences as leaves; raises `m` so that `m² ≥ max|w_p − w_last|`.
#[inline(always)]
fn weight_leaves<const D: usize>(w: &[f64], m: &mut f64) -> [Dd; D] {
    let last = w[D];
    let mut wmax = 0.0f64;
    let r = std::array::from_fn(|k| {
        let (h, l) = two_diff(w[k], last);
        wmax = wmax.max(h.abs());
        Dd { h, l }
    });
    if wmax > 0.0 {
        // fl(√W) ≥ √W(1 − u); times (1 + 4u), rounded, is ≥ √W.
        *m = m.max(wmax.sqrt() * (1.0 + 4.0 * U));
    }
    r
}

/// Sign certification of the result `v` of a degree-`d` formula with constant `c`.
#[inline(always)]
fn certify(v: Dd, m: f64, md: f64, c: f64) -> Option<f64> {
    // `m <= HUGE` is false for NaN.
    if !(m <= HUGE) {
        return None;
    }
    let s = v.h + v.l;
    if s.abs() > c * md + TINY {
        Some(s)
    } else {
        None
    }
}

/// Double-double `orient2d(a, b, c)`, if certified.
#[inline]
pub(crate) fn orient2d(a: &[f64; 2], b: &[f64; 2], c: &[f64; 2]) -> Option<f64> {
    let mut m = 0.0;
    let (ac, bc) = (leaves(a, c, &mut m), leaves(b, c, &mut m));
    let v = orient2d_g(ac, bc);
    certify(v, m, m * m, coef(O2_K))
}

/// Double-double `orient3d(a, b, c, d)`, if certified.
#[inline]
pub(crate) fn orient3d(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], d: &[f64; 3]) -> Option<f64> {
    let mut m = 0.0;
    let (ad, bd, cd) = (
        leaves(a, d, &mut m),
        leaves(b, d, &mut m),
        leaves(c, d, &mut m),
    );
    let v = orient3d_g(ad, bd, cd);
    certify(v, m, (m * m) * m, coef(O3_K))
}

/// Double-double weighted `incircle(a, b, c, d)`, if certified.
#[inline]
pub(crate) fn incircle(p: [&[f64; 2]; 4], w: &[f64; 4]) -> Option<f64> {
    let mut m = 0.0;
    let q = [
        leaves(p[0], p[3], &mut m),
        leaves(p[1], p[3], &mut m),
        leaves(p[2], p[3], &mut m),
    ];
    let wl: [Dd; 3] = weight_leaves(w, &mut m);
    let v = incircle_g(q, wl);
    let m2 = m * m;
    certify(v, m, m2 * m2, coef(IC_K))
}

/// Double-double weighted `insphere(a, b, c, d, e)`, if certified.
#[inline]
pub(crate) fn insphere(p: [&[f64; 3]; 5], w: &[f64; 5]) -> Option<f64> {
    let mut m = 0.0;
    let q = [
        leaves(p[0], p[4], &mut m),
        leaves(p[1], p[4], &mut m),
        leaves(p[2], p[4], &mut m),
        leaves(p[3], p[4], &mut m),
    ];
    let wl: [Dd; 4] = weight_leaves(w, &mut m);
    let v = insphere_g(q, wl);
    let m2 = m * m;
    certify(v, m, (m2 * m2) * m, coef(IS_K))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Bound propagation `(H, L, E)` in units of `Mᵏ` (module docs).
    #[derive(Clone, Copy, Debug)]
    struct Bnd {
        h: f64,
        l: f64,
        e: f64,
    }
    const LEAF: Bnd = Bnd {
        h: 1.0,
        l: U,
        e: 0.0,
    };
    impl Ring for Bnd {
        fn add(self, o: Self) -> Self {
            let (hs, ls) = (self.h + o.h, self.l + o.l);
            let ee = U * hs;
            let c = (1.0 + U) * ls;
            Bnd {
                h: (1.0 + U) * hs,
                l: (1.0 + U) * (ee + c),
                e: self.e + o.e + U * ls + U * (ee + c),
            }
        }
        fn sub(self, o: Self) -> Self {
            self.add(o)
        }
        fn mul(self, o: Self) -> Self {
            let hh = self.h * o.h;
            let x = self.h * o.l + self.l * o.h;
            let ee = U * hh;
            let c = (1.0 + U) * (1.0 + U) * x;
            let r = U * (ee + c) + U * x + U * (1.0 + U) * x + self.l * o.l;
            let prop = (self.h + self.l) * o.e + (o.h + o.l + o.e) * self.e;
            Bnd {
                h: (1.0 + U) * hh,
                l: (1.0 + U) * (ee + c),
                e: prop + r,
            }
        }
    }

    #[test]
    fn constants_dominate_propagated_bounds() {
        let o2 = orient2d_g([LEAF; 2], [LEAF; 2]);
        let o3 = orient3d_g([LEAF; 3], [LEAF; 3], [LEAF; 3]);
        let ic = incircle_g([[LEAF; 2]; 3], [LEAF; 3]);
        let is = insphere_g([[LEAF; 3]; 4], [LEAF; 4]);
        for (name, b, k) in [
            ("orient2d", o2, O2_K),
            ("orient3d", o3, O3_K),
            ("incircle", ic, IC_K),
            ("insphere", is, IS_K),
        ] {
            let e = b.e / (U * U);
            println!("{name}: E/u² = {e}, H = {}, k = {k}", b.h);
            assert!(e * (1.0 + 1e-9) <= k, "{name}: E/u² = {e} > k = {k}");
            // Not wastefully loose either.
            assert!(k < 1.25 * e + 2.0, "{name}: k = {k} vs E/u² = {e}");
            // Magnitudes stay below 2^8·Mᵈ (overflow/underflow arguments).
            assert!(b.h + b.l + b.e < 256.0);
        }
    }
}
