//! Benchmark cases: named, seeded, deterministic point sets.
//!
//! A case name has the form `{2d,3d}-{kind}-{size}`, for example
//! `2d-uniform-1e6` or `3d-grid-1e6`. The size is the requested number of
//! points (`1e5`, `100000`, ...); grids round it to a whole side length
//! (`2d-grid-1e6` is 1000×1000, `3d-grid-1e6` is 100³).

use std::f64::consts::TAU;
use std::fmt;

/// SplitMix64 (Steele, Lea, Flood 2014): a tiny, fast, well-mixed 64-bit PRNG.
/// Fully deterministic for a given seed, on every platform.
#[derive(Debug, Clone)]
pub struct SplitMix64 {
    state: u64,
}

impl SplitMix64 {
    /// A generator started at `seed`.
    pub fn new(seed: u64) -> Self {
        SplitMix64 { state: seed }
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A uniform double in `[0, 1)` built from the top 53 bits.
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// The shape of a point set.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// Uniform random in the unit square / cube.
    Uniform,
    /// Integer lattice points (maximally degenerate: cocircular / cospherical).
    Grid,
    /// Points on the unit circle (2D only), evenly spaced in angle.
    Circle,
    /// Uniform random points on the unit sphere (3D only).
    Sphere,
}

impl Kind {
    fn name(self) -> &'static str {
        match self {
            Kind::Uniform => "uniform",
            Kind::Grid => "grid",
            Kind::Circle => "circle",
            Kind::Sphere => "sphere",
        }
    }
}

/// One benchmark case.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Case {
    /// The name as given (used to re-create the case in the child process).
    pub name: String,
    /// 2 or 3.
    pub dim: usize,
    /// Point-set shape.
    pub kind: Kind,
    /// Requested size (before grid rounding).
    pub requested: usize,
}

/// Points of either dimension.
#[derive(Debug, Clone, PartialEq)]
pub enum Points {
    /// 2D points.
    D2(Vec<[f64; 2]>),
    /// 3D points.
    D3(Vec<[f64; 3]>),
}

impl Points {
    /// Number of points.
    pub fn len(&self) -> usize {
        match self {
            Points::D2(p) => p.len(),
            Points::D3(p) => p.len(),
        }
    }
}

/// Why a case name was rejected.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BadCase(pub String);

impl fmt::Display for BadCase {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "bad case name `{}` (expected {{2d,3d}}-{{uniform,grid,circle,sphere}}-SIZE, e.g. 2d-uniform-1e5; circle is 2D only, sphere 3D only)",
            self.0
        )
    }
}

/// The full default suite.
pub const DEFAULT_CASES: &[&str] = &[
    "2d-uniform-1e5",
    "2d-uniform-1e6",
    "2d-grid-1e6",
    "2d-circle-1e5",
    "3d-uniform-1e5",
    "3d-uniform-1e6",
    "3d-grid-1e6",
    "3d-sphere-1e5",
];

/// The `--quick` suite: only sizes around 1e5.
pub const QUICK_CASES: &[&str] = &[
    "2d-uniform-1e5",
    "2d-grid-1e5",
    "2d-circle-1e5",
    "3d-uniform-1e5",
    "3d-grid-1e5",
    "3d-sphere-1e5",
];

impl Case {
    /// Parses a case name such as `2d-uniform-1e5`.
    pub fn parse(name: &str) -> Result<Case, BadCase> {
        let bad = || BadCase(name.to_string());
        let mut parts = name.split('-');
        let (Some(d), Some(k), Some(s), None) =
            (parts.next(), parts.next(), parts.next(), parts.next())
        else {
            return Err(bad());
        };
        let dim = match d {
            "2d" => 2,
            "3d" => 3,
            _ => return Err(bad()),
        };
        let kind = match (k, dim) {
            ("uniform", _) => Kind::Uniform,
            ("grid", _) => Kind::Grid,
            ("circle", 2) => Kind::Circle,
            ("sphere", 3) => Kind::Sphere,
            _ => return Err(bad()),
        };
        let size: f64 = s.parse().map_err(|_| bad())?;
        if !size.is_finite() || !(4.0..=4.0e9).contains(&size) {
            return Err(bad());
        }
        Ok(Case {
            name: name.to_string(),
            dim,
            kind,
            requested: size.round() as usize,
        })
    }

    /// Grid side length (points per axis) for a grid case.
    fn grid_side(&self) -> usize {
        let side = (self.requested as f64).powf(1.0 / self.dim as f64).round() as usize;
        side.max(2)
    }

    /// Number of points the case generates.
    pub fn n(&self) -> usize {
        match self.kind {
            Kind::Grid => self.grid_side().pow(self.dim as u32),
            _ => self.requested,
        }
    }

    /// A human description of the shape, e.g. `grid 1000x1000`.
    pub fn describe(&self) -> String {
        match self.kind {
            Kind::Grid => {
                let s = self.grid_side();
                vec![s.to_string(); self.dim].join("x") + " grid"
            }
            k => format!("{} {}", k.name(), self.dim),
        }
    }

    /// A fixed seed derived from the case name (FNV-1a), so every case has
    /// its own stream and the same name always gives the same points.
    fn seed(&self) -> u64 {
        fnv1a(self.name.bytes())
    }

    /// Generates the points (deterministically).
    pub fn generate(&self) -> Points {
        let n = self.n();
        let mut rng = SplitMix64::new(self.seed());
        match (self.dim, self.kind) {
            (2, Kind::Uniform) => {
                Points::D2((0..n).map(|_| [rng.next_f64(), rng.next_f64()]).collect())
            }
            (3, Kind::Uniform) => Points::D3(
                (0..n)
                    .map(|_| [rng.next_f64(), rng.next_f64(), rng.next_f64()])
                    .collect(),
            ),
            (2, Kind::Grid) => {
                let s = self.grid_side();
                Points::D2((0..n).map(|i| [(i % s) as f64, (i / s) as f64]).collect())
            }
            (3, Kind::Grid) => {
                let s = self.grid_side();
                Points::D3(
                    (0..n)
                        .map(|i| [(i % s) as f64, ((i / s) % s) as f64, (i / (s * s)) as f64])
                        .collect(),
                )
            }
            (2, Kind::Circle) => Points::D2(
                (0..n)
                    .map(|i| {
                        let a = TAU * i as f64 / n as f64;
                        [a.cos(), a.sin()]
                    })
                    .collect(),
            ),
            (3, Kind::Sphere) => Points::D3(
                (0..n)
                    .map(|_| {
                        // Archimedes: z uniform in [-1, 1], angle uniform.
                        let z = 2.0 * rng.next_f64() - 1.0;
                        let a = TAU * rng.next_f64();
                        let r = (1.0 - z * z).max(0.0).sqrt();
                        [r * a.cos(), r * a.sin(), z]
                    })
                    .collect(),
            ),
            // `parse` never builds these combinations.
            _ => Points::D2(Vec::new()),
        }
    }
}

/// 64-bit FNV-1a over a byte stream.
pub fn fnv1a(bytes: impl IntoIterator<Item = u8>) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splitmix_matches_reference_sequence() {
        // First outputs of SplitMix64 seeded with 1234567, as published with
        // the reference C implementation (Vigna's splitmix64.c test vector).
        let mut r = SplitMix64::new(1234567);
        assert_eq!(r.next_u64(), 6457827717110365317);
        assert_eq!(r.next_u64(), 3203168211198807973);
        assert_eq!(r.next_u64(), 9817491932198370423);
    }

    #[test]
    fn f64_in_unit_interval() {
        let mut r = SplitMix64::new(7);
        for _ in 0..10_000 {
            let x = r.next_f64();
            assert!((0.0..1.0).contains(&x));
        }
    }

    #[test]
    fn parse_and_sizes() {
        let c = Case::parse("2d-grid-1e6").unwrap();
        assert_eq!((c.dim, c.kind, c.n()), (2, Kind::Grid, 1_000_000));
        assert_eq!(c.describe(), "1000x1000 grid");
        let c = Case::parse("3d-grid-1e6").unwrap();
        assert_eq!(c.n(), 1_000_000);
        let c = Case::parse("3d-grid-1e5").unwrap();
        assert_eq!(c.n(), 46 * 46 * 46);
        assert_eq!(Case::parse("2d-uniform-100000").unwrap().n(), 100_000);
        for bad in [
            "2d-sphere-1e5",
            "3d-circle-1e5",
            "4d-uniform-1e5",
            "2d-uniform",
            "2d-uniform-x",
            "2d-uniform-1e5-z",
            "2d-uniform-2",
        ] {
            assert!(Case::parse(bad).is_err(), "{bad}");
        }
        for name in DEFAULT_CASES.iter().chain(QUICK_CASES) {
            assert!(Case::parse(name).is_ok(), "{name}");
        }
    }

    #[test]
    fn generation_is_deterministic_and_well_formed() {
        for name in [
            "2d-uniform-1000",
            "3d-uniform-1000",
            "3d-sphere-1000",
            "2d-circle-1000",
        ] {
            let c = Case::parse(name).unwrap();
            let a = c.generate();
            assert_eq!(a, c.generate(), "{name}");
            assert_eq!(a.len(), 1000);
        }
        // Distinct cases get distinct streams.
        let a = Case::parse("2d-uniform-1000").unwrap().generate();
        let b = Case::parse("2d-uniform-1e3").unwrap().generate();
        assert_ne!(a, b);
        let Points::D3(s) = Case::parse("3d-sphere-1000").unwrap().generate() else {
            panic!("sphere must be 3D")
        };
        for p in s {
            let r2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
            assert!((r2 - 1.0).abs() < 1e-12);
        }
        let Points::D3(g) = Case::parse("3d-grid-27").unwrap().generate() else {
            panic!("grid must be 3D")
        };
        assert_eq!(g.len(), 27);
        assert_eq!(g[26], [2.0, 2.0, 2.0]);
        let mut sorted = g.clone();
        sorted.sort_by(|a, b| a.partial_cmp(b).unwrap());
        sorted.dedup();
        assert_eq!(sorted.len(), 27);
    }
}
