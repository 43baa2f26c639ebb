//! # delone-fuzz
//!
//! Fuzz targets for delone's file readers and mesh builders: one function per
//! target, taking arbitrary bytes. Each must return for every input without
//! panicking, in bounded time and with allocations bounded by the input
//! size (a header that claims 4e9 points must not reserve room for them).
//! Where a builder succeeds, its result is checked with the library's own
//! validators (a failed check panics, which is a finding).
//!
//! The same functions run
//!
//! * coverage-guided under libFuzzer, from the `fuzz/` crate at the root of
//!   the repository (see `fuzz/README.md`), and
//! * as property tests on stable Rust (`tests/short_run.rs` of this crate):
//!   [`mutate`] derives inputs from [`seeds`] (built-in samples plus the
//!   shared corpus) by byte flips, truncations, huge header counts,
//!   NaN/inf/1e308 coordinates and duplicated lines.
//!
//! ```
//! for t in delone_fuzz::TARGETS {
//!     (t.run)(b"3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n");
//! }
//! ```
#![forbid(unsafe_code)]

use delone::model::pslg::{Pslg, Region};
use delone::tri::{CdtOptions, RefineOptions};

/// A fuzz target: a name (the libFuzzer binary's and the seed folder's) and
/// the function under test.
#[derive(Clone, Copy)]
pub struct Target {
    /// The target's name (`node`, `stl`, `cdt_poly`, ...).
    pub name: &'static str,
    /// File extensions whose corpus files seed it (empty: built-in seeds only).
    pub extensions: &'static [&'static str],
    /// The function under test.
    pub run: fn(&[u8]),
}

/// Every target: the readers first, then the builders.
pub const TARGETS: &[Target] = &[
    Target {
        name: "node",
        extensions: &["node"],
        run: node,
    },
    Target {
        name: "ele",
        extensions: &["ele"],
        run: ele,
    },
    Target {
        name: "poly",
        extensions: &["poly"],
        run: poly,
    },
    Target {
        name: "face",
        extensions: &["face"],
        run: face,
    },
    Target {
        name: "mtr",
        extensions: &["mtr"],
        run: mtr,
    },
    Target {
        name: "area",
        extensions: &["area"],
        run: area,
    },
    Target {
        name: "poly3d",
        extensions: &["poly"],
        run: poly3d,
    },
    Target {
        name: "smesh",
        extensions: &["smesh"],
        run: smesh,
    },
    Target {
        name: "off",
        extensions: &["off"],
        run: off,
    },
    Target {
        name: "stl",
        extensions: &["stl"],
        run: stl,
    },
    Target {
        name: "ply",
        extensions: &["ply"],
        run: ply,
    },
    Target {
        name: "obj",
        extensions: &["obj"],
        run: obj,
    },
    Target {
        name: "medit",
        extensions: &["mesh"],
        run: medit,
    },
    Target {
        name: "sol",
        extensions: &["sol"],
        run: sol,
    },
    Target {
        name: "cdt_poly",
        extensions: &["poly"],
        run: cdt_poly,
    },
    Target {
        name: "delaunay2",
        extensions: &[],
        run: delaunay2,
    },
    Target {
        name: "delaunay3",
        extensions: &[],
        run: delaunay3,
    },
    Target {
        name: "recover_plc",
        extensions: &["off"],
        run: recover_plc,
    },
];

/// The target named `name`.
///
/// ```
/// assert!(delone_fuzz::target("stl").is_some());
/// assert!(delone_fuzz::target("xyz").is_none());
/// ```
pub fn target(name: &str) -> Option<&'static Target> {
    TARGETS.iter().find(|t| t.name == name)
}

/// Largest inputs the builders take (points, segments or triangles): keeps
/// one execution well under a second.
pub const BUILDER_MAX_POINTS: usize = 200;
/// Steiner-point budget of the builders' refinement and recovery.
pub const BUILDER_MAX_STEINER: usize = 300;

/// Triangle `.node`.
pub fn node(data: &[u8]) {
    if let Ok(f) = delone_io::read_node(data) {
        let _ = f.points::<2>();
        let _ = f.points::<3>();
        assert_eq!(f.lines.len(), f.len());
    }
}

/// Triangle/TetGen `.ele` (node numbering from 0 and from 1).
pub fn ele(data: &[u8]) {
    for first in [0, 1] {
        if let Ok(f) = delone_io::read_ele(data, first) {
            assert_eq!(f.elements.len(), f.len() * f.nodes_per_element);
        }
    }
}

/// Triangle `.poly` (2D).
pub fn poly(data: &[u8]) {
    if let Ok(f) = delone_io::read_poly(data) {
        let _ = f.node.points::<2>();
        let _ = f.segments_zero_based(f.node.first_index);
    }
}

/// TetGen `.face`.
pub fn face(data: &[u8]) {
    for first in [0, 1] {
        let _ = delone_io::read_face(data, first);
    }
}

/// TetGen `.mtr` (sizes).
pub fn mtr(data: &[u8]) {
    let _ = delone_io::read_mtr(data);
}

/// Triangle `.area`.
pub fn area(data: &[u8]) {
    let _ = delone_io::read_area(data);
}

/// TetGen `.poly` (3D PLC).
pub fn poly3d(data: &[u8]) {
    let _ = delone_io::read_poly3d(data);
}

/// TetGen `.smesh`.
pub fn smesh(data: &[u8]) {
    let _ = delone_io::read_smesh(data);
}

fn surface(r: Result<delone_io::Surface, delone_io::IoError>) {
    if let Ok(mut s) = r {
        let n = s.points.len();
        for f in &s.faces {
            assert!(
                f.iter().all(|&i| (i as usize) < n),
                "face index out of range"
            );
        }
        let _ = s.triangles();
        let _ = s.merge_exact_duplicates();
        let _ = s.remove_unreferenced();
    }
}

/// OFF.
pub fn off(data: &[u8]) {
    surface(delone_io::read_off(data));
}

/// STL, ASCII and binary.
pub fn stl(data: &[u8]) {
    surface(delone_io::read_stl(data));
}

/// PLY, ASCII and binary (both byte orders).
pub fn ply(data: &[u8]) {
    surface(delone_io::read_ply(data));
}

/// Wavefront OBJ.
pub fn obj(data: &[u8]) {
    surface(delone_io::read_obj(data));
}

/// Medit `.mesh`: the surface reader, and the whole mesh written and read
/// back unchanged.
pub fn medit(data: &[u8]) {
    surface(delone_io::read_medit(data));
    if let Ok(m) = delone_io::read_medit_mesh(data) {
        let mut out = Vec::new();
        delone_io::write_medit_mesh(&mut out, &m).expect("a mesh read is a mesh that writes");
        let back = delone_io::read_medit_mesh(&out).expect("a written mesh reads");
        assert!(
            same_bits(&back, &m),
            "a mesh read, written and read again changed"
        );
    }
}

/// Equal, with coordinates compared bit for bit (a NaN read is a NaN
/// written).
fn same_bits(a: &delone_io::MeditMesh, b: &delone_io::MeditMesh) -> bool {
    let coords = |m: &delone_io::MeditMesh| {
        m.points
            .iter()
            .flatten()
            .map(|x| bits(*x))
            .collect::<Vec<_>>()
    };
    let strip = |m: &delone_io::MeditMesh| delone_io::MeditMesh {
        points: Vec::new(),
        ..m.clone()
    };
    coords(a) == coords(b) && strip(a) == strip(b)
}

/// A float's bits, every NaN as one (a file says `NaN` or `-nan`; the
/// writer says `NaN`).
fn bits(x: f64) -> u64 {
    if x.is_nan() {
        f64::NAN.to_bits()
    } else {
        x.to_bits()
    }
}

/// Medit `.sol`: read, written and read back unchanged.
pub fn sol(data: &[u8]) {
    if let Ok(s) = delone_io::read_medit_sol(data) {
        let mut out = Vec::new();
        delone_io::write_medit_sol(&mut out, &s).expect("a solution read is one that writes");
        let back = delone_io::read_medit_sol(&out).expect("a written solution reads");
        let bits = |s: &delone_io::MeditSol| {
            s.fields
                .iter()
                .flat_map(|f| f.values.iter().map(|x| bits(*x)))
                .collect::<Vec<_>>()
        };
        assert_eq!(bits(&back), bits(&s), "values changed");
        assert_eq!(
            (back.dimension, back.vertices, back.fields.len()),
            (s.dimension, s.vertices, s.fields.len())
        );
    }
}

/// A `.poly` file (text, so the corpus's PSLGs seed it) through the
/// constrained Delaunay triangulation, its check, and a refinement with a
/// small Steiner budget. Inputs above [`BUILDER_MAX_POINTS`] are skipped.
pub fn cdt_poly(data: &[u8]) {
    let Ok(f) = delone_io::read_poly(data) else {
        return;
    };
    let (Some(points), Ok(segments)) = (
        f.node.points::<2>(),
        f.segments_zero_based(f.node.first_index),
    ) else {
        return;
    };
    if points.len() > BUILDER_MAX_POINTS || segments.len() > BUILDER_MAX_POINTS {
        return;
    }
    let g = Pslg {
        point_markers: f.node.markers.clone().unwrap_or_default(),
        points,
        segments,
        segment_markers: f.segment_markers.clone().unwrap_or_default(),
        holes: f.holes.iter().take(BUILDER_MAX_POINTS).copied().collect(),
        regions: f
            .regions
            .iter()
            .take(BUILDER_MAX_POINTS)
            .map(|r| Region {
                point: [r[0], r[1]],
                attribute: r[2],
                max_area: r[3],
            })
            .collect(),
    };
    let convex_hull = data.len() % 2 == 1;
    let Ok(cdt) = delone::tri::constrained_triangulation(&g, CdtOptions { convex_hull }) else {
        return;
    };
    if let Err(v) = delone::tri::check_cdt(&g, &cdt) {
        panic!("constrained_triangulation returned a CDT that fails check_cdt: {v:?}");
    }
    let opts = RefineOptions {
        min_angle: Some(20.0 + (data.len() % 11) as f64),
        max_steiner: Some(BUILDER_MAX_STEINER),
        threads: 1,
        ..RefineOptions::default()
    };
    let _ = delone::tri::refine(&cdt, &opts);
}

/// Doubles decoded from bytes: one selector byte picks a special value
/// (0, ±1, NaN, ±inf, ±1e308, ±5e-324, ±1e-300, duplicates of the previous
/// value) or a small integer (many ties and collinearities), or takes the
/// next 8 bytes as a raw double.
struct Doubles<'a> {
    data: &'a [u8],
    last: f64,
}

impl Doubles<'_> {
    fn next(&mut self) -> Option<f64> {
        let (&sel, rest) = self.data.split_first()?;
        self.data = rest;
        let v = match sel {
            0 => 0.0,
            1 => 1.0,
            2 => -1.0,
            3 => f64::NAN,
            4 => f64::INFINITY,
            5 => f64::NEG_INFINITY,
            6 => 1e308,
            7 => -1e308,
            8 => 5e-324,
            9 => 1e-300,
            10 => self.last,
            11 => self.last + f64::EPSILON * self.last.abs(),
            12..=15 => {
                if self.data.len() < 8 {
                    return None;
                }
                let (b, rest) = self.data.split_at(8);
                self.data = rest;
                f64::from_le_bytes(b.try_into().ok()?)
            }
            s => f64::from(s % 16) - 4.0,
        };
        self.last = v;
        Some(v)
    }
}

/// The points of the `delaunay2`/`delaunay3` targets: doubles decoded from
/// the bytes (a selector byte per coordinate: special values, small
/// integers, or a raw double), at most [`BUILDER_MAX_POINTS`].
pub fn decode_points<const D: usize>(data: &[u8]) -> Vec<[f64; D]> {
    let mut d = Doubles { data, last: 0.0 };
    let mut out = Vec::new();
    'outer: while out.len() < BUILDER_MAX_POINTS {
        let mut p = [0.0; D];
        for c in &mut p {
            match d.next() {
                Some(v) => *c = v,
                None => break 'outer,
            }
        }
        out.push(p);
    }
    out
}

/// Delaunay triangulation of points decoded from the bytes (see
/// `Doubles`), checked by [`delone::tri::validate`] when it succeeds.
pub fn delaunay2(data: &[u8]) {
    let pts = decode_points::<2>(data);
    if let Ok(m) = delone::triangulate(&pts) {
        if let Err(v) = delone::tri::validate(&pts, &m) {
            panic!("triangulate returned a mesh that fails validate: {v:?}");
        }
    }
}

/// Delaunay tetrahedralization of points decoded from the bytes, checked by
/// [`delone::tet::validate`] when it succeeds.
pub fn delaunay3(data: &[u8]) {
    let pts = decode_points::<3>(data);
    if let Ok(m) = delone::tetrahedralize(&pts) {
        if let Err(v) = delone::tet::validate(&pts, &m) {
            panic!("tetrahedralize returned a mesh that fails validate: {v:?}");
        }
    }
}

/// An OFF surface (text, so the corpus's surfaces seed it) through boundary
/// recovery with a small Steiner budget, checked by
/// [`delone::tet::recover::check_recovered`] when it succeeds. Surfaces
/// above [`BUILDER_MAX_POINTS`] points or triangles are skipped.
pub fn recover_plc(data: &[u8]) {
    let Ok(s) = delone_io::read_off(data) else {
        return;
    };
    if s.points.len() > BUILDER_MAX_POINTS || s.faces.len() > BUILDER_MAX_POINTS {
        return;
    }
    let tris = s.triangles();
    if tris.len() > BUILDER_MAX_POINTS {
        return;
    }
    let opts = delone::tet::recover::RecoverOptions {
        max_steiner: BUILDER_MAX_STEINER,
        ..Default::default()
    };
    let r = delone::tet::recover::recover(&s.points, &tris, &opts);
    if let Ok(r) = r {
        if let Err(v) = delone::tet::recover::check_recovered(&s.points, &tris, &r) {
            panic!("recover returned a mesh that fails check_recovered: {v:?}");
        }
    }
}

/// Small built-in seeds for `target` (every target has some), so that the
/// property tests and the fuzzer start from valid inputs of every format.
pub fn builtin_seeds(target: &str) -> Vec<Vec<u8>> {
    let s = |t: &str| t.as_bytes().to_vec();
    match target {
        "node" => vec![
            s("4 2 1 1\n1 0 0 0.5 1\n2 1 0 0.5 1\n3 1 1 0.5 0\n4 0 1 0.5 2\n"),
            s("# comment\n3 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n"),
        ],
        "ele" => vec![
            s("2 3 1\n1 1 2 3 7\n2 2 3 4 -1\n"),
            s("1 4 0\n0 0 1 2 3\n"),
            s("1 6 0\n1 1 2 3 4 5 6\n"),
        ],
        "poly" | "cdt_poly" => vec![
            s("4 2 0 1\n1 0 0 1\n2 4 0 1\n3 4 4 1\n4 0 4 1\n4 1\n1 1 2 5\n2 2 3 5\n3 3 4 5\n4 4 1 5\n1\n1 2 2\n1\n1 1 1 7 0.5\n"),
            s("0 2 0 0\n0 0\n0\n"),
            s("6 2 0 0\n1 0 0\n2 3 0\n3 3 3\n4 0 3\n5 1 1\n6 2 2\n5 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n5 5 6\n0\n"),
        ],
        "face" => vec![s("2 1\n1 1 2 3 5\n2 2 3 4 -2\n"), s("1 0\n0 0 1 2\n")],
        "mtr" => vec![s("3 1\n0.5\n0.25\n1e-3\n")],
        "area" => vec![s("2\n1 0.5\n2 -1\n")],
        "poly3d" => vec![s(
            "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n4 1\n1 0 1\n3 1 2 3\n1 0 2\n3 1 2 4\n1 0 3\n3 2 3 4\n1 1 4\n3 1 3 4\n1 0.2 0.0 0.2\n0\n1\n1 0.1 0.1 0.1 5 0.01\n",
        )],
        "smesh" => vec![s(
            "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n4 1\n3 1 2 3 1\n3 1 2 4 2\n3 2 3 4 3\n3 1 3 4 4\n0\n0\n",
        )],
        "off" | "recover_plc" => vec![
            s("OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n"),
            s("OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n"),
        ],
        "stl" => {
            let mut bin = vec![0u8; 80];
            bin.extend_from_slice(&2u32.to_le_bytes());
            for tri in [[[0f32, 0., 0.], [1., 0., 0.], [0., 1., 0.]], [[0., 0., 0.], [0., 1., 0.], [0., 0., 1.]]] {
                bin.extend_from_slice(&[0u8; 12]);
                for p in tri {
                    for c in p {
                        bin.extend_from_slice(&c.to_le_bytes());
                    }
                }
                bin.extend_from_slice(&[0, 0]);
            }
            vec![
                s("solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n"),
                bin,
            ]
        }
        "ply" => {
            let mut bin = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n".to_vec();
            for c in [0f32, 0., 0., 1., 0., 0., 0., 1., 0.] {
                bin.extend_from_slice(&c.to_le_bytes());
            }
            bin.push(3);
            for i in [0i32, 1, 2] {
                bin.extend_from_slice(&i.to_le_bytes());
            }
            let mut big = b"ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\nelement face 1\nproperty list uchar uint vertex_indices\nend_header\n".to_vec();
            for c in [0f64, 0., 0., 1., 0., 0., 0., 1., 0.] {
                big.extend_from_slice(&c.to_be_bytes());
            }
            big.push(3);
            for i in [0u32, 1, 2] {
                big.extend_from_slice(&i.to_be_bytes());
            }
            vec![
                s("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
                bin,
                big,
            ]
        }
        "obj" => vec![s("# t\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1 4//1\nf -1 -2 -3\n")],
        "medit" => vec![s(
            "MeshVersionFormatted 2\nDimension 3\nVertices\n4\n0 0 0 1\n1 0 0 1\n0 1 0 1\n0 0 1 1\nTriangles\n2\n1 2 3 5\n1 2 4 5\nTetrahedra\n1\n1 2 3 4 1\nEnd\n",
        ), s(
            "MeshVersionFormatted 2\nDimension 2\nVertices\n3\n0 0 1\n1 0 1\n0 1 1\nEdges\n2\n1 2 3\n2 3 3\nTriangles\n1\n1 2 3 0\nCorners\n1\n1\nRidges\n1\n2\nEnd\n",
        )],
        "sol" => vec![
            s("MeshVersionFormatted 2\nDimension 2\nSolAtVertices\n2\n1 3\n1 0 1\n2 0.5 2\nEnd\n"),
            s("MeshVersionFormatted 2\nDimension 3\nSolAtVertices\n1\n2 1 3\n0.1 1 0 1 0 0 1\nEnd\n"),
        ],
        "delaunay2" | "delaunay3" => vec![
            vec![16, 17, 18, 16, 16, 18, 18, 18, 20, 21, 10, 10, 0, 1, 1, 0],
            vec![16, 16, 16, 17, 17, 16, 16, 17, 17, 17, 17, 18, 20, 20, 20, 22, 22, 22],
            (0u8..=255).rev().collect(),
        ],
        _ => Vec::new(),
    }
}

/// Seeds of `target`: [`builtin_seeds`] and, from `corpus` (the shared
/// `data` folder, when given), every file with one of the target's
/// extensions up to `max_len` bytes (sorted by path, so runs repeat).
pub fn seeds(target: &Target, corpus: Option<&std::path::Path>, max_len: u64) -> Vec<Vec<u8>> {
    let mut out = builtin_seeds(target.name);
    let Some(dir) = corpus else {
        return out;
    };
    let mut files = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(rd) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in rd.flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if p
                .extension()
                .and_then(|e| e.to_str())
                .is_some_and(|e| target.extensions.iter().any(|x| x.eq_ignore_ascii_case(e)))
                && e.metadata().is_ok_and(|m| m.len() <= max_len)
            {
                files.push(p);
            }
        }
    }
    files.sort();
    out.extend(files.iter().filter_map(|p| std::fs::read(p).ok()));
    out
}

/// A small deterministic pseudo-random generator: the library's
/// [`SplitMix64`](delone::geom::SplitMix64).
#[derive(Debug, Clone)]
pub struct Rng(delone::geom::SplitMix64);

impl Rng {
    /// A generator with the given seed.
    pub fn new(seed: u64) -> Self {
        Rng(delone::geom::SplitMix64::new(seed))
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0.next_u64()
    }

    /// A number in `0..n` (`n > 0`).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n.max(1) as u64) as usize
    }
}

/// Replacement tokens for numbers: huge counts, negative and non-numbers,
/// extreme coordinates.
const NASTY: &[&str] = &[
    "4000000000",
    "4294967295",
    "4294967296",
    "18446744073709551615",
    "99999999999999999999999",
    "-1",
    "0",
    "1",
    "2",
    "3",
    "65",
    "nan",
    "NaN",
    "inf",
    "-inf",
    "1e308",
    "-1e308",
    "1e309",
    "5e-324",
    "1e-300",
    "0x10",
    "1.5",
    "",
    "#",
    "\u{0}",
];

/// One mutation of `seed`: byte flips, truncation, a number replaced by a
/// huge count or an extreme coordinate, a line duplicated or deleted, a
/// binary count field overwritten, or a splice of two places.
pub fn mutate(seed: &[u8], rng: &mut Rng) -> Vec<u8> {
    let mut v = seed.to_vec();
    let rounds = 1 + rng.below(4);
    for _ in 0..rounds {
        match rng.below(9) {
            0 if !v.is_empty() => {
                let i = rng.below(v.len());
                v[i] ^= 1 << rng.below(8);
            }
            1 if !v.is_empty() => {
                let i = rng.below(v.len());
                v[i] = rng.next_u64() as u8;
            }
            2 => v.truncate(rng.below(v.len() + 1)),
            3 | 4 => {
                // Replace the k-th number-like token.
                let toks: Vec<(usize, usize)> = tokens(&v);
                if !toks.is_empty() {
                    let (a, b) = toks[rng.below(toks.len().min(64))];
                    let r = NASTY[rng.below(NASTY.len())].as_bytes();
                    v.splice(a..b, r.iter().copied());
                }
            }
            5 => {
                let lines: Vec<(usize, usize)> = line_spans(&v);
                if !lines.is_empty() {
                    let (a, b) = lines[rng.below(lines.len())];
                    let l = v[a..b].to_vec();
                    let at = lines[rng.below(lines.len())].0;
                    v.splice(at..at, l);
                }
            }
            6 => {
                let lines: Vec<(usize, usize)> = line_spans(&v);
                if !lines.is_empty() {
                    let (a, b) = lines[rng.below(lines.len())];
                    v.drain(a..b);
                }
            }
            7 if v.len() >= 4 => {
                // Binary formats: a 32-bit count (STL's at 80, PLY's after
                // the header) set to something huge.
                let at = if v.len() >= 84 && rng.below(2) == 0 {
                    80
                } else {
                    rng.below(v.len() - 3)
                };
                let n = [u32::MAX, 0x7fff_ffff, 1 << 28, 0][rng.below(4)];
                v[at..at + 4].copy_from_slice(&n.to_le_bytes());
            }
            _ if !v.is_empty() => {
                let a = rng.below(v.len());
                let b = rng.below(v.len());
                let len = rng.below(64).min(v.len() - a);
                let chunk = v[a..a + len].to_vec();
                v.splice(b..b, chunk);
            }
            _ => v.push(rng.next_u64() as u8),
        }
    }
    v
}

fn tokens(v: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < v.len() && out.len() < 4096 {
        if v[i].is_ascii_digit() || v[i] == b'-' || v[i] == b'.' {
            let a = i;
            while i < v.len() && !v[i].is_ascii_whitespace() {
                i += 1;
            }
            out.push((a, i));
        }
        i += 1;
    }
    out
}

fn line_spans(v: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut a = 0;
    for (i, &b) in v.iter().enumerate() {
        if b == b'\n' {
            out.push((a, i + 1));
            a = i + 1;
            if out.len() >= 4096 {
                break;
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_target_has_builtin_seeds_that_its_reader_accepts() {
        for t in TARGETS {
            let seeds = builtin_seeds(t.name);
            assert!(!seeds.is_empty(), "{}", t.name);
            for s in &seeds {
                (t.run)(s);
            }
        }
        for (name, read) in [
            (
                "node",
                (|d: &[u8]| delone_io::read_node(d).is_ok()) as fn(&[u8]) -> bool,
            ),
            ("ele", |d| delone_io::read_ele(d, 0).is_ok()),
            ("poly", |d| delone_io::read_poly(d).is_ok()),
            ("face", |d| delone_io::read_face(d, 0).is_ok()),
            ("mtr", |d| delone_io::read_mtr(d).is_ok()),
            ("area", |d| delone_io::read_area(d).is_ok()),
            ("poly3d", |d| delone_io::read_poly3d(d).is_ok()),
            ("smesh", |d| delone_io::read_smesh(d).is_ok()),
            ("off", |d| delone_io::read_off(d).is_ok()),
            ("stl", |d| delone_io::read_stl(d).is_ok()),
            ("ply", |d| delone_io::read_ply(d).is_ok()),
            ("obj", |d| delone_io::read_obj(d).is_ok()),
            ("medit", |d| delone_io::read_medit_mesh(d).is_ok()),
            ("sol", |d| delone_io::read_medit_sol(d).is_ok()),
        ] {
            for (i, s) in builtin_seeds(name).iter().enumerate() {
                assert!(read(s), "built-in seed {i} of {name} does not read");
            }
        }
    }

    #[test]
    fn mutations_are_deterministic_and_varied() {
        let seed = builtin_seeds("off").remove(0);
        let a: Vec<_> = (0..50)
            .map(|_| ())
            .scan(Rng::new(7), |r, _| Some(mutate(&seed, r)))
            .collect();
        let b: Vec<_> = (0..50)
            .map(|_| ())
            .scan(Rng::new(7), |r, _| Some(mutate(&seed, r)))
            .collect();
        assert_eq!(a, b);
        let distinct: std::collections::HashSet<_> = a.iter().collect();
        assert!(distinct.len() > 40);
    }
}
