//! Shared helpers for the integration tests: a deterministic RNG and the
//! `robust` reference wrappers.
#![allow(dead_code)]

/// SplitMix64: small, deterministic, good enough for test inputs.
pub struct Rng(pub u64);

impl Rng {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    pub fn f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.f64()
    }
    /// Uniform integer in [lo, hi].
    pub fn int(&mut self, lo: i64, hi: i64) -> i64 {
        lo + (self.next_u64() % ((hi - lo + 1) as u64)) as i64
    }
    pub fn p2(&mut self) -> [f64; 2] {
        [self.range(-1.0, 1.0), self.range(-1.0, 1.0)]
    }
    pub fn p3(&mut self) -> [f64; 3] {
        [
            self.range(-1.0, 1.0),
            self.range(-1.0, 1.0),
            self.range(-1.0, 1.0),
        ]
    }
}

/// Moves `x` by `k` ulps (k may be negative).
pub fn ulps(x: f64, k: i64) -> f64 {
    let mut y = x;
    for _ in 0..k.unsigned_abs() {
        y = if k > 0 { y.next_up() } else { y.next_down() };
    }
    y
}

pub fn sign(x: f64) -> i32 {
    if x > 0.0 {
        1
    } else if x < 0.0 {
        -1
    } else {
        0
    }
}

fn c2(p: &[f64; 2]) -> robust::Coord<f64> {
    robust::Coord { x: p[0], y: p[1] }
}
fn c3(p: &[f64; 3]) -> robust::Coord3D<f64> {
    robust::Coord3D {
        x: p[0],
        y: p[1],
        z: p[2],
    }
}

pub fn r_orient2d(a: &[f64; 2], b: &[f64; 2], c: &[f64; 2]) -> f64 {
    robust::orient2d(c2(a), c2(b), c2(c))
}
pub fn r_incircle(a: &[f64; 2], b: &[f64; 2], c: &[f64; 2], d: &[f64; 2]) -> f64 {
    robust::incircle(c2(a), c2(b), c2(c), c2(d))
}
pub fn r_orient3d(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], d: &[f64; 3]) -> f64 {
    robust::orient3d(c3(a), c3(b), c3(c), c3(d))
}
pub fn r_insphere(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], d: &[f64; 3], e: &[f64; 3]) -> f64 {
    robust::insphere(c3(a), c3(b), c3(c), c3(d), c3(e))
}

/// A minimal signed big integer (sign-magnitude, base 2^32), for an independent
/// exact evaluator of determinants on dyadic inputs.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Big {
    neg: bool,
    mag: Vec<u32>, // little endian, no trailing zeros; zero = empty
}

impl Big {
    pub fn zero() -> Big {
        Big {
            neg: false,
            mag: Vec::new(),
        }
    }
    pub fn from_i64(v: i64) -> Big {
        let mut m = v.unsigned_abs();
        let mut mag = Vec::new();
        while m != 0 {
            mag.push(m as u32);
            m >>= 32;
        }
        Big {
            neg: v < 0 && !mag.is_empty(),
            mag,
        }
    }
    /// `x * 2^shift` exactly; panics if that is not an integer (test misuse).
    pub fn from_f64_shifted(x: f64, shift: i32) -> Big {
        assert!(x.is_finite());
        if x == 0.0 {
            return Big::zero();
        }
        let (m, e) = decompose(x);
        let total = e + shift;
        assert!(
            total >= 0 || m.trailing_zeros() as i32 >= -total,
            "not an integer after shift"
        );
        let mut b = Big::from_i64(m);
        if total >= 0 {
            b = b.shl(total as u32);
        } else {
            b = Big::from_i64(m >> (-total));
        }
        b
    }
    fn shl(&self, s: u32) -> Big {
        let (words, bits) = ((s / 32) as usize, s % 32);
        let mut mag = vec![0u32; words];
        let mut carry = 0u32;
        for &w in &self.mag {
            if bits == 0 {
                mag.push(w);
            } else {
                mag.push((w << bits) | carry);
                carry = w >> (32 - bits);
            }
        }
        if carry != 0 {
            mag.push(carry);
        }
        let mut r = Big { neg: self.neg, mag };
        r.trim();
        r
    }
    fn trim(&mut self) {
        while self.mag.last() == Some(&0) {
            self.mag.pop();
        }
        if self.mag.is_empty() {
            self.neg = false;
        }
    }
    pub fn sign(&self) -> i32 {
        if self.mag.is_empty() {
            0
        } else if self.neg {
            -1
        } else {
            1
        }
    }
    fn cmp_mag(a: &[u32], b: &[u32]) -> std::cmp::Ordering {
        a.len()
            .cmp(&b.len())
            .then_with(|| a.iter().rev().cmp(b.iter().rev()))
    }
    fn add_mag(a: &[u32], b: &[u32]) -> Vec<u32> {
        let mut r = Vec::with_capacity(a.len().max(b.len()) + 1);
        let mut carry = 0u64;
        for i in 0..a.len().max(b.len()) {
            let s = *a.get(i).unwrap_or(&0) as u64 + *b.get(i).unwrap_or(&0) as u64 + carry;
            r.push(s as u32);
            carry = s >> 32;
        }
        r.push(carry as u32);
        r
    }
    /// |a| - |b| with |a| >= |b|.
    fn sub_mag(a: &[u32], b: &[u32]) -> Vec<u32> {
        let mut r = Vec::with_capacity(a.len());
        let mut borrow = 0i64;
        for (i, &ai) in a.iter().enumerate() {
            let mut d = ai as i64 - *b.get(i).unwrap_or(&0) as i64 - borrow;
            borrow = 0;
            if d < 0 {
                d += 1 << 32;
                borrow = 1;
            }
            r.push(d as u32);
        }
        r
    }
    pub fn add(&self, o: &Big) -> Big {
        let mut r = if self.neg == o.neg {
            Big {
                neg: self.neg,
                mag: Big::add_mag(&self.mag, &o.mag),
            }
        } else if Big::cmp_mag(&self.mag, &o.mag) != std::cmp::Ordering::Less {
            Big {
                neg: self.neg,
                mag: Big::sub_mag(&self.mag, &o.mag),
            }
        } else {
            Big {
                neg: o.neg,
                mag: Big::sub_mag(&o.mag, &self.mag),
            }
        };
        r.trim();
        r
    }
    pub fn neg(&self) -> Big {
        let mut r = self.clone();
        r.neg = !r.neg;
        r.trim();
        r
    }
    pub fn sub(&self, o: &Big) -> Big {
        self.add(&o.neg())
    }
    pub fn mul(&self, o: &Big) -> Big {
        if self.mag.is_empty() || o.mag.is_empty() {
            return Big::zero();
        }
        let mut r = vec![0u64; self.mag.len() + o.mag.len() + 1];
        for (i, &a) in self.mag.iter().enumerate() {
            let mut carry = 0u64;
            for (j, &b) in o.mag.iter().enumerate() {
                let t = r[i + j] + a as u64 * b as u64 + carry;
                r[i + j] = t & 0xFFFF_FFFF;
                carry = t >> 32;
            }
            let mut k = i + o.mag.len();
            while carry != 0 {
                let t = r[k] + carry;
                r[k] = t & 0xFFFF_FFFF;
                carry = t >> 32;
                k += 1;
            }
        }
        let mut b = Big {
            neg: self.neg != o.neg,
            mag: r.into_iter().map(|v| v as u32).collect(),
        };
        b.trim();
        b
    }
}

/// `x = m * 2^e` with integer `m` (|m| < 2^53).
pub fn decompose(x: f64) -> (i64, i32) {
    let bits = x.to_bits();
    let exp = ((bits >> 52) & 0x7FF) as i32;
    let frac = (bits & ((1u64 << 52) - 1)) as i64;
    let (m, e) = if exp == 0 {
        (frac, -1074)
    } else {
        (frac | (1i64 << 52), exp - 1075)
    };
    (if x < 0.0 { -m } else { m }, e)
}

/// Exact determinant of a square matrix of big integers (Laplace along row 0).
pub fn big_det(m: &[Vec<Big>]) -> Big {
    let n = m.len();
    if n == 1 {
        return m[0][0].clone();
    }
    let mut acc = Big::zero();
    for c in 0..n {
        if m[0][c].sign() == 0 {
            continue;
        }
        let minor: Vec<Vec<Big>> = m[1..]
            .iter()
            .map(|row| {
                row.iter()
                    .enumerate()
                    .filter(|&(k, _)| k != c)
                    .map(|(_, v)| v.clone())
                    .collect()
            })
            .collect();
        let t = m[0][c].mul(&big_det(&minor));
        acc = if c % 2 == 0 { acc.add(&t) } else { acc.sub(&t) };
    }
    acc
}

/// Smallest power-of-two shift making every value an integer.
pub fn shift_for(vals: &[f64]) -> i32 {
    vals.iter()
        .filter(|v| **v != 0.0)
        .map(|&v| -decompose(v).1)
        .max()
        .unwrap_or(0)
        .max(0)
}

/// Exact sign of `det[p (|p|² - w) 1]` (rows = points; the weighted in-circle /
/// in-sphere determinant) for arbitrary finite dyadic inputs.
pub fn exact_power_sign<const D: usize>(pts: &[[f64; D]], w: &[f64]) -> i32 {
    let mut coords: Vec<f64> = pts.iter().flatten().copied().collect();
    // Coordinates scaled by 2^s, lifts by 2^(2s): w must be an integer at 2^(2s).
    let s = shift_for(&coords).max((shift_for(w) + 1) / 2);
    coords.clear();
    let rows: Vec<Vec<Big>> = pts
        .iter()
        .zip(w)
        .map(|(p, &wi)| {
            let mut row: Vec<Big> = p.iter().map(|&x| Big::from_f64_shifted(x, s)).collect();
            let mut lift = Big::from_f64_shifted(wi, 2 * s).neg();
            for x in &row {
                lift = lift.add(&x.mul(x));
            }
            row.push(lift);
            row.push(Big::from_i64(1));
            row
        })
        .collect();
    big_det(&rows).sign()
}

/// Exact sign of `det[p 1]` (orientation) for arbitrary finite dyadic inputs.
pub fn exact_orient_sign<const D: usize>(pts: &[[f64; D]]) -> i32 {
    let coords: Vec<f64> = pts.iter().flatten().copied().collect();
    let s = shift_for(&coords);
    let rows: Vec<Vec<Big>> = pts
        .iter()
        .map(|p| {
            let mut row: Vec<Big> = p.iter().map(|&x| Big::from_f64_shifted(x, s)).collect();
            row.push(Big::from_i64(1));
            row
        })
        .collect();
    big_det(&rows).sign()
}
