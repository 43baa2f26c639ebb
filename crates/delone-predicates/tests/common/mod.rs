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
