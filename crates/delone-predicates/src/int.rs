//! Exact evaluation on a common integer grid.
//!
//! Every finite `f64` is an integer multiple of a power of two (its last
//! mantissa bit). When the coordinates a predicate needs are all integer
//! multiples of one power of two `2^low` and small against it (below
//! `2^BITS · 2^low`), they are, after scaling by `2^-low`, integers of at most
//! `BITS` bits, and the determinant can be evaluated exactly in fixed-width
//! integer arithmetic: 64-bit coordinate differences, 128-bit 2x2 minors and
//! lifted coordinates, and a few 64-bit limbs beyond. No rounding happens
//! anywhere, whether the floating-point differences of the coordinates were
//! exact or not.
//!
//! This is the usual case for the exact ties of CAD inputs
//! (cospherical vertices of boxes, cylinders and grids): their coordinates have
//! similar magnitudes, so the spread between the largest coordinate and the
//! lowest mantissa bit stays within 61 bits. The integer in-sphere evaluation
//! costs one to two thousand instructions (the orientation a few hundred)
//! where the expansion stages cost tens of thousands.
//!
//! Sizes (with `|x| < 2^61` for the coordinates, hence `|d| < 2^62` for the
//! differences): 2x2 minors `< 2^125`, 3x3 minors `< 2^189` (three limbs),
//! lifted coordinates `|d|² < 2^126`, the in-sphere determinant `< 2^317` (five
//! limbs). Each fixed width holds its values with the sign bit to spare.

use crate::Point3;

/// Bits of the largest scaled coordinate (`|x| < 2^BITS`).
const BITS: i32 = 61;

/// A two's-complement integer of `N` little-endian 64-bit limbs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Wide<const N: usize>([u64; N]);

impl<const N: usize> Wide<N> {
    /// The value of an `i128`, sign-extended (needs `N >= 2`).
    fn from_i128(x: i128) -> Self {
        let mut r = [if x < 0 { u64::MAX } else { 0 }; N];
        r[0] = x as u64;
        r[1] = (x >> 64) as u64;
        Wide(r)
    }

    fn is_neg(&self) -> bool {
        self.0[N - 1] >> 63 == 1
    }

    fn neg(&self) -> Self {
        let mut r = [0u64; N];
        let mut carry = 1u64;
        for (o, &x) in r.iter_mut().zip(&self.0) {
            let (s, c) = (!x).overflowing_add(carry);
            *o = s;
            carry = c as u64;
        }
        Wide(r)
    }

    /// The magnitude as unsigned limbs and whether the value is negative.
    fn abs(&self) -> ([u64; N], bool) {
        if self.is_neg() {
            (self.neg().0, true)
        } else {
            (self.0, false)
        }
    }

    fn add(&self, o: &Self) -> Self {
        let mut r = [0u64; N];
        let mut carry = false;
        for (out, (&x, &y)) in r.iter_mut().zip(self.0.iter().zip(&o.0)) {
            let (s1, c1) = x.overflowing_add(y);
            let (s2, c2) = s1.overflowing_add(carry as u64);
            *out = s2;
            carry = c1 | c2;
        }
        Wide(r)
    }

    fn sub(&self, o: &Self) -> Self {
        self.add(&o.neg())
    }

    /// `self · o` in `R` limbs; exact when the product fits `R` limbs signed
    /// (the callers size `R` for their bounds).
    fn mul<const M: usize, const R: usize>(&self, o: &Wide<M>) -> Wide<R> {
        let ((a, na), (b, nb)) = (self.abs(), o.abs());
        let mut r = [0u64; R];
        for (i, &ai) in a.iter().enumerate() {
            let mut carry = 0u64;
            for (j, &bj) in b.iter().enumerate() {
                if i + j >= R {
                    break;
                }
                let t = ai as u128 * bj as u128 + r[i + j] as u128 + carry as u128;
                r[i + j] = t as u64;
                carry = (t >> 64) as u64;
            }
            if i + M < R {
                r[i + M] = carry;
            }
        }
        let p = Wide(r);
        if na != nb {
            p.neg()
        } else {
            p
        }
    }

    /// An `f64` with the sign of the value, zero iff it is zero, and its
    /// magnitude times `2^scale` (clamped to the finite nonzero range).
    fn to_f64(self, scale: i32) -> f64 {
        let (m, neg) = self.abs();
        let mut v = 0.0f64;
        for &x in m.iter().rev() {
            v = v * 18_446_744_073_709_551_616.0 + x as f64;
        }
        if v == 0.0 {
            return 0.0;
        }
        // Scale in steps that stay within the exponent range of `powi`.
        let mut s = scale;
        while s != 0 {
            let k = s.clamp(-1000, 1000);
            v *= 2f64.powi(k);
            s -= k;
        }
        let v = v.clamp(f64::MIN_POSITIVE, f64::MAX);
        if neg {
            -v
        } else {
            v
        }
    }
}

/// Lowest mantissa-bit exponent `low` over the nonzero `vals` such that every
/// value is an integer multiple of `2^low` below `2^(BITS + low)` in magnitude;
/// `None` if there is no such grid (spread too wide, subnormal or non-finite
/// values) or if every value is zero.
fn grid(vals: &[f64]) -> Option<i32> {
    let (mut low, mut top) = (i32::MAX, i32::MIN);
    for &x in vals {
        if x == 0.0 {
            continue;
        }
        let bits = x.to_bits();
        let exp = ((bits >> 52) & 0x7FF) as i32;
        if exp == 0 || exp == 0x7FF {
            return None;
        }
        let mant = (bits & ((1u64 << 52) - 1)) | (1u64 << 52);
        low = low.min(exp - 1075 + mant.trailing_zeros() as i32);
        // |x| < 2^(exp - 1022).
        top = top.max(exp - 1022);
    }
    if low == i32::MAX || top - low > BITS {
        return None;
    }
    Some(low)
}

/// `x / 2^low` as an integer (`x` a multiple of `2^low` below `2^(BITS + low)`).
fn scaled(x: f64, low: i32) -> i64 {
    if x == 0.0 {
        return 0;
    }
    let bits = x.to_bits();
    let exp = ((bits >> 52) & 0x7FF) as i32;
    let mant = (bits & ((1u64 << 52) - 1)) | (1u64 << 52);
    let tz = mant.trailing_zeros() as i32;
    let v = ((mant >> tz) << (exp - 1075 + tz - low)) as i64;
    if x < 0.0 {
        -v
    } else {
        v
    }
}

/// The differences `p_r - p_last` of the points as integers on their common grid
/// (`|d| < 2^62`), and the grid exponent.
fn int_diffs<const N: usize, const K: usize>(p: [&Point3; N]) -> Option<([[i64; 3]; K], i32)> {
    debug_assert_eq!(K + 1, N);
    let mut vals = [0.0; 15];
    for (k, q) in p.iter().enumerate() {
        vals[3 * k..3 * k + 3].copy_from_slice(&q[..]);
    }
    let low = grid(&vals[..3 * N])?;
    let last = p[N - 1].map(|x| scaled(x, low));
    let d = std::array::from_fn(|r| std::array::from_fn(|c| scaled(p[r][c], low) - last[c]));
    Some((d, low))
}

/// `det3` of three integer rows, expanded along `x` with `(y, z)` minors.
#[inline]
fn det3(p: &[i64; 3], q: &[i64; 3], r: &[i64; 3]) -> Wide<3> {
    let m = |s: &[i64; 3], t: &[i64; 3]| {
        Wide::<2>::from_i128(s[1] as i128 * t[2] as i128 - s[2] as i128 * t[1] as i128)
    };
    let x = |v: i64| Wide::<1>([v as u64]);
    let t1: Wide<3> = m(q, r).mul(&x(p[0]));
    let t2: Wide<3> = m(p, r).mul(&x(q[0]));
    let t3: Wide<3> = m(p, q).mul(&x(r[0]));
    t1.sub(&t2).add(&t3)
}

/// Exact `orient3d(a, b, c, d)` when the coordinates share a fine enough grid.
pub(crate) fn orient3d(p: [&Point3; 4]) -> Option<f64> {
    let ([a, b, c], low) = int_diffs::<4, 3>(p)?;
    Some(det3(&a, &b, &c).to_f64(3 * low))
}

/// Exact (unweighted) `insphere(a, b, c, d, e)` when the coordinates share a
/// fine enough grid: rows `(p - e, |p - e|²)` along the lift column (`- + - +`).
pub(crate) fn insphere(p: [&Point3; 5]) -> Option<f64> {
    let (q, low) = int_diffs::<5, 4>(p)?;
    let lift = |x: &[i64; 3]| {
        let s = x
            .iter()
            .map(|&v| (v as i128 * v as i128) as u128)
            .sum::<u128>();
        Wide::<2>::from_i128(s as i128)
    };
    let t = |r: usize, s: [usize; 3]| -> Wide<5> {
        lift(&q[r]).mul(&det3(&q[s[0]], &q[s[1]], &q[s[2]]))
    };
    let det = t(1, [0, 2, 3])
        .sub(&t(0, [1, 2, 3]))
        .add(&t(3, [0, 1, 2]).sub(&t(2, [0, 1, 3])));
    Some(det.to_f64(5 * low))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::{insphere_homogeneous, orient3d_homogeneous};

    /// Small deterministic generator (xorshift64*).
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
        }
        fn unit(&mut self) -> f64 {
            (self.next() >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    fn sign(x: f64) -> i32 {
        (x > 0.0) as i32 - (x < 0.0) as i32
    }

    /// Compares the integer in-sphere and orientation tests with the homogeneous
    /// expansion evaluation on `pts`; returns how many calls the grid decided.
    fn agree(pts: &[[f64; 3]], r: &mut Rng, n: usize) -> usize {
        let mut decided = 0;
        for _ in 0..n {
            let k: [usize; 5] = std::array::from_fn(|_| (r.next() % pts.len() as u64) as usize);
            let p: [&Point3; 5] = std::array::from_fn(|i| &pts[k[i]]);
            if let Some(v) = insphere(p) {
                decided += 1;
                let want = insphere_homogeneous(p, [0.0; 5]);
                assert_eq!(sign(v), sign(want), "insphere {p:?}");
            }
            if let Some(v) = orient3d([p[0], p[1], p[2], p[3]]) {
                let want = orient3d_homogeneous([p[0], p[1], p[2], p[3]]);
                assert_eq!(sign(v), sign(want), "orient3d {p:?}");
            }
        }
        decided
    }

    /// Points of a cylinder (two rings with the same rounded `x, y`) and of a
    /// box: every five of them on one sphere, the ties CAD models are made of.
    #[test]
    fn cospherical_cad_points_agree_with_the_expansions() {
        let mut r = Rng(0x9E37_79B9_7F4A_7C15);
        for scale in [1.0, 0.3, 1e-9, 1e9, 1.0 / 3.0, 1e-40, 1e40] {
            let mut pts = Vec::new();
            let (cx, cy, h) = (0.287649 * scale, -2.1 * scale, 0.7 * scale);
            for i in 0..12 {
                let t = i as f64 * std::f64::consts::TAU / 12.0;
                let (x, y) = (cx + 0.2 * scale * t.cos(), cy + 0.2 * scale * t.sin());
                pts.push([x, y, 0.1 * scale]);
                pts.push([x, y, 0.1 * scale + h]);
            }
            for m in 0..8 {
                let c = |b: usize, v: f64| if m >> b & 1 == 1 { v * scale } else { 0.0 };
                pts.push([c(0, 0.35857899), c(1, 0.2), c(2, 0.163128)]);
            }
            let mut zero = 0;
            for _ in 0..2000 {
                let k: [usize; 5] = std::array::from_fn(|_| (r.next() % 24) as usize);
                let p: [&Point3; 5] = std::array::from_fn(|i| &pts[k[i]]);
                if insphere(p) == Some(0.0) {
                    zero += 1;
                }
            }
            assert!(zero > 100, "scale {scale}: {zero} exact ties");
            assert!(agree(&pts, &mut r, 4000) > 3000, "scale {scale}");
        }
    }

    /// Points within a few ulps of a sphere (nearly cospherical), random points,
    /// and coordinates spanning the whole grid width.
    #[test]
    fn near_ties_random_and_wide_inputs_agree_with_the_expansions() {
        let mut r = Rng(12345);
        for scale in [1.0, 1e-30, 1e30] {
            let mut pts = Vec::new();
            for _ in 0..40 {
                let (u, v) = (
                    r.unit() * std::f64::consts::TAU,
                    r.unit() * std::f64::consts::PI,
                );
                let mut q = [u.cos() * v.sin(), u.sin() * v.sin(), v.cos()];
                for x in &mut q {
                    let ulps = (r.next() % 5) as i64 - 2;
                    *x = f64::from_bits((x.to_bits() as i64 + ulps) as u64) * scale;
                }
                pts.push(q);
            }
            agree(&pts, &mut r, 3000);
            let rand: Vec<[f64; 3]> = (0..40)
                .map(|_| [r.unit(), r.unit(), r.unit()].map(|x| x * scale))
                .collect();
            agree(&rand, &mut r, 3000);
        }
        // Integers right at the width limit: |x| < 2^61 with the lowest bit 1.
        let big = ((1u64 << 53) - 1) as f64 * 256.0;
        let wide: Vec<[f64; 3]> = (0..40)
            .map(|_| {
                let c = |r: &mut Rng| {
                    let v = (r.next() >> 3) as f64;
                    if r.next() & 1 == 1 {
                        -v.min(big)
                    } else {
                        v.min(big)
                    }
                };
                [c(&mut r), c(&mut r), 1.0]
            })
            .collect();
        agree(&wide, &mut r, 3000);
        // The extremes: every difference at its bound.
        let e = [
            [big, big, big],
            [-big, big, -big],
            [big, -big, -big],
            [-big, -big, big],
        ];
        let p = [&e[0], &e[1], &e[2], &e[3], &[-big, -big, -1.0]];
        let v = insphere(p).expect("on the grid");
        assert_eq!(sign(v), sign(insphere_homogeneous(p, [0.0; 5])));
    }

    #[test]
    fn outside_the_grid_width_is_declined() {
        let (a, b, c, d) = (
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        );
        let p = [&a, &b, &c, &d, &[0.5, 0.5, 0.5]];
        assert_eq!(
            sign(insphere(p).unwrap()),
            sign(insphere_homogeneous(p, [0.0; 5]))
        );
        // The lowest bit 2^-60 (of 3·2^-60) and 2.0 < 2^2: 62 bits, declined;
        // with 1.0 < 2^1: 61 bits, taken.
        let f = 3.0 * 2f64.powi(-60);
        assert!(insphere([&a, &b, &c, &[0.0, 0.0, 2.0], &[f, 0.0, 0.0]]).is_none());
        let p = [&a, &b, &c, &d, &[f, 0.0, 0.0]];
        assert_eq!(
            sign(insphere(p).unwrap()),
            sign(insphere_homogeneous(p, [0.0; 5]))
        );
        assert!(insphere([&a, &b, &c, &d, &[f64::NAN, 0.0, 0.0]]).is_none());
        assert!(insphere([&a, &b, &c, &d, &[f64::MIN_POSITIVE / 4.0, 0.0, 0.0]]).is_none());
        assert!(orient3d([&a, &b, &c, &[1e-300, 0.0, 1.0]]).is_none());
    }
}
