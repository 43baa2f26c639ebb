//! Benchmark cases: named, seeded, deterministic point sets.
//!
//! A case name has the form `{2d,3d}-{kind}-{size}`, for example
//! `2d-uniform-1e6` or `3d-grid-1e6`. The size is the requested number of
//! points (`1e5`, `100000`, ...); grids round it to a whole side length
//! (`2d-grid-1e6` is 1000×1000, `3d-grid-1e6` is 100³).
//!
//! Two more families read real inputs from the shared data directory (see
//! [`data_dir`]) instead of generating points:
//!
//! - `2d-poly-NAME-qANGLEaAREA` (either part may be left out; `q` alone is
//!   20°) and `2d-poly-NAME-p` (constrained triangulation only):
//!   `2d/NAME.poly`, meshed with quality bounds;
//! - `2d-segs-SIZE` and `2d-holes-SIZE`: generated PSLGs of about SIZE
//!   segments (a jittered grid with random non-crossing segments; a square
//!   with octagonal holes), constrained triangulation only (`-p`);
//! - `3d-surf-MODEL`: `surf/off/MODEL.off`, a closed triangle surface whose
//!   faces are recovered in a tetrahedralization.

use std::f64::consts::TAU;
use std::fmt;
use std::path::PathBuf;

use delone::model::pslg::{Pslg, Region};

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
    /// A `.poly` file (2D only), meshed with quality bounds.
    Poly,
    /// A closed triangle surface from an `.off` file (3D only).
    Surf,
    /// A piecewise linear complex from a TetGen `.poly` / `.smesh` file in
    /// `3d_plc` (3D only): `3d-plc-NAME` (recovery, `-p`) and
    /// `3d-plcq-NAME-qB` (refinement to radius-edge B and optimisation).
    Plc,
    /// A generated PSLG (2D only): a jittered grid with a random
    /// non-crossing subset of its grid edges and cell diagonals as segments,
    /// triangulated with `-p`.
    Segs,
    /// A generated PSLG (2D only): a square with many small polygonal holes,
    /// triangulated with `-p`.
    Holes,
}

impl Kind {
    fn name(self) -> &'static str {
        match self {
            Kind::Uniform => "uniform",
            Kind::Grid => "grid",
            Kind::Circle => "circle",
            Kind::Sphere => "sphere",
            Kind::Poly => "poly",
            Kind::Surf => "surface",
            Kind::Plc => "plc",
            Kind::Segs => "segments",
            Kind::Holes => "holes",
        }
    }
}

/// One benchmark case.
#[derive(Debug, Clone, PartialEq)]
pub struct Case {
    /// The name as given (used to re-create the case in the child process).
    pub name: String,
    /// 2 or 3.
    pub dim: usize,
    /// Point-set shape.
    pub kind: Kind,
    /// Requested size (before grid rounding; 0 for the file families).
    pub requested: usize,
    /// The data file's base name (`Poly` and `Surf` cases).
    pub data: Option<String>,
    /// Quality refinement of a `Poly` case: `None` for the constrained
    /// triangulation alone (`-p`).
    pub quality: Option<Quality>,
}

/// Quality bounds of a `2d-poly-…-q…a…` case.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quality {
    /// Minimum angle in degrees (`None`: no angle bound); for a
    /// `3d-surfq-…-qB` case, the radius-edge bound B.
    pub min_angle: Option<f64>,
    /// Maximum triangle area (`None`: no area bound).
    pub max_area: Option<f64>,
}

/// A `.poly` input ready for meshing.
#[derive(Debug, Clone, PartialEq)]
pub struct PolyInput {
    /// The planar straight-line graph.
    pub pslg: Pslg,
    /// The quality bounds (`None`: constrained triangulation only).
    pub quality: Option<Quality>,
}

/// A closed triangle surface.
#[derive(Debug, Clone, PartialEq)]
pub struct SurfInput {
    /// Vertex coordinates.
    pub points: Vec<[f64; 3]>,
    /// Triangles (fan-triangulated faces).
    pub triangles: Vec<[u32; 3]>,
    /// Radius-edge bound of a `3d-surfq-…-qB` case (`None`: recovery only).
    pub ratio: Option<f64>,
    /// A `3d-surfY-…` case: recovery preserving the surface (`-Y`).
    pub preserve: bool,
}

/// A piecewise linear complex (`3d-plc-…`, `3d-plcq-…`).
#[derive(Debug, Clone, PartialEq)]
pub struct PlcInput {
    /// The complex as read (points, polygonal facets, holes, regions).
    pub plc: delone::model::plc::Plc,
    /// The file's bytes and extension (`poly` or `smesh`), for TetGen.
    pub bytes: Vec<u8>,
    /// `poly` or `smesh`.
    pub ext: &'static str,
    /// Radius-edge bound of a `3d-plcq-…-qB` case (`None`: recovery only).
    pub ratio: Option<f64>,
}

/// The input of a case: generated points or a file's content.
#[derive(Debug, Clone, PartialEq)]
pub enum Input {
    /// A point set.
    Points(Points),
    /// A planar straight-line graph with quality bounds.
    Poly(PolyInput),
    /// A closed triangle surface.
    Surf(SurfInput),
    /// A piecewise linear complex.
    Plc(PlcInput),
}

impl Input {
    /// Number of input points.
    pub fn len(&self) -> usize {
        match self {
            Input::Points(p) => p.len(),
            Input::Poly(p) => p.pslg.points.len(),
            Input::Surf(s) => s.points.len(),
            Input::Plc(p) => p.plc.points.len(),
        }
    }
}

/// The shared data directory: `$DELONE_BENCH_DATA` if set, else the first
/// `shared/data` found walking up from this crate's directory.
pub fn data_dir() -> Option<PathBuf> {
    if let Some(d) = std::env::var_os("DELONE_BENCH_DATA") {
        return Some(PathBuf::from(d));
    }
    let here = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    here.ancestors()
        .map(|a| a.join("shared").join("data"))
        .find(|d| d.is_dir())
}

/// Names of the files with extension `ext` in `sub` of the data directory,
/// sorted (empty if the directory is missing).
pub fn data_names(sub: &str, ext: &str) -> Vec<String> {
    let Some(dir) = data_dir().map(|d| d.join(sub)) else {
        return Vec::new();
    };
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .into_iter()
        .flatten()
        .flatten()
        .filter_map(|e| {
            let n = e.file_name().into_string().ok()?;
            n.strip_suffix(ext)?.strip_suffix('.').map(str::to_string)
        })
        .collect();
    names.sort();
    names
}

fn read_data(sub: &str, file: &str) -> Result<Vec<u8>, String> {
    let dir = data_dir().ok_or("shared data directory not found (set DELONE_BENCH_DATA)")?;
    let path = dir.join(sub).join(file);
    std::fs::read(&path).map_err(|e| format!("cannot read {}: {e}", path.display()))
}

/// A data-file base name: letters, digits and `_` only (no path parts).
fn is_data_name(s: &str) -> bool {
    !s.is_empty() && s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// A positive finite number.
fn positive(s: &str) -> Option<f64> {
    s.parse::<f64>().ok().filter(|v| v.is_finite() && *v > 0.0)
}

/// Parses the quality part of a poly case: `p`, `q`, `qANGLE`, `aAREA`,
/// `qANGLEaAREA`, `qaAREA`.
fn parse_quality(spec: &str) -> Option<Option<Quality>> {
    if spec == "p" {
        return Some(None);
    }
    let (q, a) = match spec.split_once('a') {
        Some((q, a)) => (q, Some(a)),
        None => (spec, None),
    };
    let min_angle = match q.strip_prefix('q') {
        Some("") => Some(20.0),
        Some(v) => Some(positive(v).filter(|&v| v < 60.0)?),
        None if q.is_empty() => None,
        None => return None,
    };
    let max_area = match a {
        Some(v) => Some(positive(v)?),
        None => None,
    };
    if min_angle.is_none() && max_area.is_none() {
        return None;
    }
    Some(Some(Quality {
        min_angle,
        max_area,
    }))
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
            "bad case name `{}` (expected {{2d,3d}}-{{uniform,grid,circle,sphere}}-SIZE, e.g. 2d-uniform-1e5; circle is 2D only, sphere 3D only; or 2d-poly-NAME-qANGLEaAREA, 2d-poly-NAME-p, 2d-segs-SIZE, 2d-holes-SIZE, 3d-surf-MODEL, 3d-surfY-MODEL, 3d-surfq-MODEL-qB, 3d-plc-NAME, 3d-plcq-NAME-qB)",
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
        if let Some(rest) = name.strip_prefix("2d-poly-") {
            let (file, spec) = rest.split_once('-').ok_or_else(bad)?;
            let quality = parse_quality(spec).ok_or_else(bad)?;
            if !is_data_name(file) {
                return Err(bad());
            }
            return Ok(Case {
                name: name.to_string(),
                dim: 2,
                kind: Kind::Poly,
                requested: 0,
                data: Some(file.to_string()),
                quality,
            });
        }
        // `3d-surfq-MODEL-qB` / `3d-plcq-NAME-qB`: refinement to radius-edge
        // ratio B (kept in `Quality::min_angle`).
        let surfq = name.strip_prefix("3d-surfq-").map(|r| (r, Kind::Surf));
        if let Some((rest, kind)) =
            surfq.or_else(|| name.strip_prefix("3d-plcq-").map(|r| (r, Kind::Plc)))
        {
            let (model, b) = rest.rsplit_once("-q").ok_or_else(bad)?;
            let b: f64 = b.parse().map_err(|_| bad())?;
            if !(is_data_name(model) && b.is_finite() && b > 1.0) {
                return Err(bad());
            }
            return Ok(Case {
                name: name.to_string(),
                dim: 3,
                kind,
                requested: 0,
                data: Some(model.to_string()),
                quality: Some(Quality {
                    min_angle: Some(b),
                    max_area: None,
                }),
            });
        }
        // `3d-surfY-MODEL`: recovery with surface preservation (`-Y`);
        // `3d-plc-NAME`: recovery of a PLC.
        let surf = name
            .strip_prefix("3d-surf-")
            .or_else(|| name.strip_prefix("3d-surfY-"))
            .map(|m| (m, Kind::Surf));
        if let Some((model, kind)) =
            surf.or_else(|| name.strip_prefix("3d-plc-").map(|m| (m, Kind::Plc)))
        {
            if !is_data_name(model) {
                return Err(bad());
            }
            return Ok(Case {
                name: name.to_string(),
                dim: 3,
                kind,
                requested: 0,
                data: Some(model.to_string()),
                quality: None,
            });
        }
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
            ("segs", 2) => Kind::Segs,
            ("holes", 2) => Kind::Holes,
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
            data: None,
            quality: None,
        })
    }

    /// Builds the case's input: generates the points, or reads the data
    /// file (an error names the file and the problem).
    pub fn load(&self) -> Result<Input, String> {
        let data = self.data.as_deref().unwrap_or_default();
        match self.kind {
            Kind::Poly => {
                let bytes = read_data("2d", &format!("{data}.poly"))?;
                let poly = delone_io::read_poly(&bytes).map_err(|e| format!("{data}.poly: {e}"))?;
                let node = if poly.node.is_empty() {
                    let b = read_data("2d", &format!("{data}.node"))?;
                    delone_io::read_node(&b).map_err(|e| format!("{data}.node: {e}"))?
                } else {
                    poly.node.clone()
                };
                let points = node
                    .points::<2>()
                    .ok_or_else(|| format!("{data}: points are not 2D"))?;
                let segments = poly
                    .segments_zero_based(node.first_index)
                    .map_err(|e| format!("{data}.poly: {e}"))?;
                let pslg = Pslg {
                    points,
                    point_markers: node.markers.clone().unwrap_or_default(),
                    segments,
                    segment_markers: poly.segment_markers.clone().unwrap_or_default(),
                    holes: poly.holes.clone(),
                    regions: poly
                        .regions
                        .iter()
                        .map(|r| Region {
                            point: [r[0], r[1]],
                            attribute: r[2],
                            max_area: r[3],
                        })
                        .collect(),
                };
                Ok(Input::Poly(PolyInput {
                    pslg,
                    quality: self.quality,
                }))
            }
            Kind::Surf => {
                let bytes = read_data("surf/off", &format!("{data}.off"))?;
                let s = delone_io::read_off(&bytes).map_err(|e| format!("{data}.off: {e}"))?;
                let triangles = s.triangles();
                Ok(Input::Surf(SurfInput {
                    points: s.points,
                    triangles,
                    ratio: self.quality.and_then(|q| q.min_angle),
                    preserve: self.name.starts_with("3d-surfY-"),
                }))
            }
            Kind::Plc => {
                let (bytes, ext) = read_data("3d_plc", &format!("{data}.poly"))
                    .map(|b| (b, "poly"))
                    .or_else(|_| {
                        read_data("3d_plc", &format!("{data}.smesh")).map(|b| (b, "smesh"))
                    })?;
                let err = |e: delone_io::IoError| format!("{data}.{ext}: {e}");
                let f = if ext == "poly" {
                    delone_io::read_poly3d(&bytes).map_err(err)?
                } else {
                    delone_io::read_smesh(&bytes).map_err(err)?
                };
                let mut plc = delone::model::plc::Plc::new(f.points);
                plc.holes = f.holes;
                plc.regions = f
                    .regions
                    .into_iter()
                    .map(|r| delone::model::plc::Region {
                        point: r.point,
                        attribute: r.attribute,
                        max_volume: r.max_volume,
                    })
                    .collect();
                plc.facets = f
                    .facets
                    .into_iter()
                    .map(|facet| delone::model::plc::Facet {
                        polygons: facet.polygons,
                        holes: facet.holes,
                        marker: facet.marker,
                    })
                    .collect();
                Ok(Input::Plc(PlcInput {
                    plc,
                    bytes,
                    ext,
                    ratio: self.quality.and_then(|q| q.min_angle),
                }))
            }
            Kind::Segs | Kind::Holes => Ok(Input::Poly(PolyInput {
                pslg: self.generate_pslg(),
                quality: None,
            })),
            _ => Ok(Input::Points(self.generate())),
        }
    }

    /// Generates the PSLG of a `2d-segs-SIZE` / `2d-holes-SIZE` case
    /// (deterministically; SIZE is the approximate number of segments).
    ///
    /// `segs`: a `side × side` grid jittered by at most 0.2 per coordinate
    /// (so its grid edges and one diagonal per cell never cross), each of
    /// those 3 edges per cell kept with probability 1/2.
    /// `holes`: the square `[0, k]²` (its boundary split every unit) with a
    /// jittered octagon hole in every unit cell, hole point at the centre.
    pub fn generate_pslg(&self) -> Pslg {
        let mut rng = SplitMix64::new(self.seed());
        let mut points = Vec::new();
        let mut segments = Vec::new();
        let mut holes = Vec::new();
        if self.kind == Kind::Segs {
            let side = ((self.requested as f64 / 1.5).sqrt().ceil() as usize).max(2);
            for j in 0..side {
                for i in 0..side {
                    let jx = 0.4 * rng.next_f64() - 0.2;
                    let jy = 0.4 * rng.next_f64() - 0.2;
                    points.push([i as f64 + jx, j as f64 + jy]);
                }
            }
            let id = |i: usize, j: usize| (j * side + i) as u32;
            for j in 0..side {
                for i in 0..side {
                    if i + 1 < side && rng.next_u64() & 1 == 0 {
                        segments.push([id(i, j), id(i + 1, j)]);
                    }
                    if j + 1 < side && rng.next_u64() & 1 == 0 {
                        segments.push([id(i, j), id(i, j + 1)]);
                    }
                    if i + 1 < side && j + 1 < side && rng.next_u64() & 1 == 0 {
                        segments.push([id(i, j), id(i + 1, j + 1)]);
                    }
                }
            }
        } else {
            let k = ((self.requested as f64 / 8.0).sqrt().ceil() as usize).max(1);
            // Boundary: 4k points counterclockwise.
            for i in 0..k {
                points.push([i as f64, 0.0]);
            }
            for i in 0..k {
                points.push([k as f64, i as f64]);
            }
            for i in 0..k {
                points.push([(k - i) as f64, k as f64]);
            }
            for i in 0..k {
                points.push([0.0, (k - i) as f64]);
            }
            let nb = 4 * k as u32;
            segments.extend((0..nb).map(|i| [i, (i + 1) % nb]));
            for j in 0..k {
                for i in 0..k {
                    let c = [i as f64 + 0.5, j as f64 + 0.5];
                    let base = points.len() as u32;
                    for e in 0..8 {
                        let a = TAU * (e as f64 + 0.3 * rng.next_f64()) / 8.0;
                        let r = 0.15 + 0.2 * rng.next_f64();
                        points.push([c[0] + r * a.cos(), c[1] + r * a.sin()]);
                    }
                    segments.extend((0..8).map(|e| [base + e, base + (e + 1) % 8]));
                    holes.push(c);
                }
            }
        }
        let mut g = Pslg::new(points, segments);
        g.holes = holes;
        g
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
            Kind::Poly | Kind::Surf | Kind::Plc | Kind::Segs | Kind::Holes => {
                self.load().map_or(0, |i| i.len())
            }
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
            Kind::Poly => {
                let d = self.data.as_deref().unwrap_or_default();
                match self.quality {
                    None => format!("{d}.poly, CDT only"),
                    Some(q) => format!(
                        "{d}.poly, min angle {}, max area {}",
                        q.min_angle.map_or("-".into(), |a| a.to_string()),
                        q.max_area.map_or("-".into(), |a| a.to_string())
                    ),
                }
            }
            Kind::Surf => format!("{}.off surface", self.data.as_deref().unwrap_or_default()),
            Kind::Plc => format!("{} PLC", self.data.as_deref().unwrap_or_default()),
            Kind::Segs => "jittered grid, random non-crossing segments, CDT only".to_string(),
            Kind::Holes => "square with octagonal holes, CDT only".to_string(),
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
    fn parse_poly_cases() {
        let c = Case::parse("2d-poly-la-q30a0.001").unwrap();
        assert_eq!((c.dim, c.kind), (2, Kind::Poly));
        assert_eq!(c.data.as_deref(), Some("la"));
        assert_eq!(
            c.quality,
            Some(Quality {
                min_angle: Some(30.0),
                max_area: Some(0.001)
            })
        );
        let c = Case::parse("2d-poly-square_circle_hole-p").unwrap();
        assert_eq!(c.data.as_deref(), Some("square_circle_hole"));
        assert_eq!(c.quality, None);
        let q = |name: &str| Case::parse(name).unwrap().quality.unwrap();
        assert_eq!(q("2d-poly-A-q").min_angle, Some(20.0));
        assert_eq!(q("2d-poly-A-q").max_area, None);
        assert_eq!(q("2d-poly-A-q25.5").min_angle, Some(25.5));
        assert_eq!(q("2d-poly-A-a0.5").min_angle, None);
        assert_eq!(q("2d-poly-A-a0.5").max_area, Some(0.5));
        assert_eq!(q("2d-poly-A-qa1e-3").max_area, Some(0.001));
        assert_eq!(q("2d-poly-A-qa1e-3").min_angle, Some(20.0));
        for bad in [
            "2d-poly-la",
            "2d-poly--p",
            "2d-poly-la-",
            "2d-poly-la-x",
            "2d-poly-la-q30a",
            "2d-poly-la-qxa1",
            "2d-poly-la-q-5",
            "2d-poly-la-q70",
            "2d-poly-la-a0",
            "2d-poly-la-anan",
            "2d-poly-la-pq",
            "2d-poly-../la-p",
            "3d-poly-la-p",
        ] {
            assert!(Case::parse(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn generated_pslg_cases() {
        use delone::tri::constrain::{check_cdt, constrained_triangulation, CdtOptions};
        for name in ["2d-segs-3000", "2d-holes-3000"] {
            let c = Case::parse(name).unwrap();
            let Ok(Input::Poly(p)) = c.load() else {
                panic!("{name}: not a PSLG");
            };
            let g = &p.pslg;
            assert!(g.segments.len() > 2000 && g.segments.len() < 4000, "{name}");
            let cdt = constrained_triangulation(g, CdtOptions::default()).unwrap();
            // Non-crossing by construction: no Steiner points.
            assert!(cdt.report.crossings.is_empty(), "{name}");
            check_cdt(g, &cdt).unwrap();
            assert_eq!(c.load().unwrap(), Input::Poly(p.clone()));
        }
        assert!(Case::parse("3d-segs-1e3").is_err());
    }

    #[test]
    fn parse_surf_cases() {
        let c = Case::parse("3d-surf-c3d_spot").unwrap();
        assert_eq!((c.dim, c.kind), (3, Kind::Surf));
        let q = Case::parse("3d-surfq-cgal_sphere-q1.414").unwrap();
        assert_eq!(
            (q.kind, q.data.as_deref()),
            (Kind::Surf, Some("cgal_sphere"))
        );
        assert_eq!(q.quality.and_then(|x| x.min_angle), Some(1.414));
        for bad in [
            "3d-surfq-cgal_sphere",
            "3d-surfq-cgal_sphere-q0.9",
            "3d-surfq--q2",
        ] {
            assert!(Case::parse(bad).is_err(), "{bad}");
        }
        assert_eq!(c.data.as_deref(), Some("c3d_spot"));
        assert_eq!(c.describe(), "c3d_spot.off surface");
        for bad in [
            "3d-surf-",
            "3d-surf-a/b",
            "3d-surf-..",
            "2d-surf-x",
            "3d-surf-a b",
        ] {
            assert!(Case::parse(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn file_cases_load_from_shared_data() {
        if data_dir().is_none() {
            println!("note: shared data directory not found; skipping");
            return;
        }
        let Ok(Input::Poly(p)) = Case::parse("2d-poly-box-p").unwrap().load() else {
            panic!("box.poly must load as a PSLG")
        };
        assert!(p.pslg.points.len() >= 3 && !p.pslg.segments.is_empty());
        let n = p.pslg.points.len() as u32;
        assert!(p.pslg.segments.iter().flatten().all(|&v| v < n));
        let c = Case::parse("3d-surf-c3d_spot").unwrap();
        let Ok(Input::Surf(s)) = c.load() else {
            panic!("c3d_spot.off must load as a surface")
        };
        assert_eq!(c.n(), s.points.len());
        assert!(s.triangles.len() >= 4);
        let missing = Case::parse("3d-surf-no_such_model").unwrap();
        let err = missing.load().unwrap_err();
        assert!(err.contains("no_such_model.off"), "{err}");
        assert_eq!(missing.n(), 0);
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
