//! `delone adapt`: a 2D run with its outputs, measure-only mode, the
//! `.sol` round trip with MMG (when `mmg2d_O3` is installed), and the error
//! paths (a metric that is not positive definite, a wrong count of values,
//! a `.sol` of another dimension, two metrics, an unknown option), and the
//! metric without a `.sol` (`-hsiz`, or the mesh's own edge lengths).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_delone");

/// A 4 × 4 grid of the unit square with its sides as edges (references
/// 1–4) and the four corners.
fn square_mesh() -> String {
    let n = 4;
    let id = |i: usize, j: usize| j * (n + 1) + i + 1;
    let mut s = format!(
        "MeshVersionFormatted 2\nDimension 2\nVertices\n{}\n",
        (n + 1) * (n + 1)
    );
    for j in 0..=n {
        for i in 0..=n {
            s += &format!("{} {} 0\n", i as f64 / n as f64, j as f64 / n as f64);
        }
    }
    s += &format!("Edges\n{}\n", 4 * n);
    for k in 0..n {
        s += &format!(
            "{} {} 1\n{} {} 2\n",
            id(k, 0),
            id(k + 1, 0),
            id(n, k),
            id(n, k + 1)
        );
        s += &format!(
            "{} {} 3\n{} {} 4\n",
            id(k + 1, n),
            id(k, n),
            id(0, k + 1),
            id(0, k)
        );
    }
    s += &format!("Triangles\n{}\n", 2 * n * n);
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            s += &format!("{a} {b} {c} 0\n{a} {c} {d} 0\n");
        }
    }
    s += &format!(
        "Corners\n4\n{}\n{}\n{}\n{}\nEnd\n",
        id(0, 0),
        id(n, 0),
        id(n, n),
        id(0, n)
    );
    s
}

/// A tensor `.sol` with `values` per vertex line.
fn sol(dim: u8, lines: &[&str]) -> String {
    let kind = if lines[0].split_whitespace().count() == 1 {
        1
    } else {
        3
    };
    format!(
        "MeshVersionFormatted 2\nDimension {dim}\nSolAtVertices\n{}\n1 {kind}\n{}\nEnd\n",
        lines.len(),
        lines.join("\n")
    )
}

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("delone-adapt-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn run(args: &[&str], cwd: &Path) -> Output {
    Command::new(BIN)
        .arg("adapt")
        .args(args)
        .current_dir(cwd)
        .output()
        .unwrap()
}

/// [`run`], which must succeed (the failure names the arguments and shows
/// stderr).
fn run_ok(args: &[&str], cwd: &Path) -> Output {
    let out = run(args, cwd);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

fn anisotropic() -> String {
    // Sizes 0.05 along x and 0.2 along y.
    sol(2, &vec!["400 0 25"; 25])
}

#[test]
fn adapts_writes_mesh_and_metric_and_reports() {
    let d = dir("run");
    std::fs::write(d.join("sq.mesh"), square_mesh()).unwrap();
    std::fs::write(d.join("sq.sol"), anisotropic()).unwrap();
    let out = run_ok(
        &[
            "sq.mesh",
            "--metric",
            "sq.sol",
            "-o",
            "out.mesh",
            "-V",
            "--stats-json",
            "s.json",
        ],
        &d,
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("after:") && text.contains("in [1/sqrt2, sqrt2]") && text.contains("time:"),
        "{text}"
    );
    let mesh = delone_io::read_medit_mesh(&std::fs::read(d.join("out.mesh")).unwrap()).unwrap();
    let met = delone_io::read_medit_sol(&std::fs::read(d.join("out.sol")).unwrap()).unwrap();
    assert_eq!(met.vertices, mesh.points.len());
    assert!(mesh.points.len() > 60, "{} vertices", mesh.points.len());
    assert_eq!(mesh.corners.len(), 4);
    assert!(mesh.edge_refs.iter().all(|r| (1..=4).contains(r)));
    let json = std::fs::read_to_string(d.join("s.json")).unwrap();
    assert!(
        json.contains("\"after\": {\"vertices\": ") && json.contains("\"splits\": "),
        "{json}"
    );
    // The default metric is IN.sol; the same run gives the same bytes.
    let again = run(&["sq.mesh", "-o", "again.mesh", "-Q"], &d);
    assert!(again.status.success());
    assert_eq!(
        std::fs::read(d.join("out.mesh")).unwrap(),
        std::fs::read(d.join("again.mesh")).unwrap()
    );
    // Measure only: the adapted mesh in its own metric, nothing written.
    let m = run(
        &[
            "out.mesh",
            "--metric",
            "out.sol",
            "-noinsert",
            "-noswap",
            "-nomove",
            "-V",
        ],
        &d,
    );
    assert!(m.status.success());
    assert!(String::from_utf8_lossy(&m.stdout).starts_with("mesh: "));
    assert!(!d.join("out.o.mesh").exists());
}

/// delone adapts `mesh` to `metric` (written as `NAME.mesh`/`NAME.sol` in a
/// folder `tag`), MMG's `program` reads delone's mesh and metric and adapts
/// again, and delone reads MMG's: the final mesh, or `None` (skipped, with
/// a message) when the program is not installed.
fn mmg_round_trip(
    program: &str,
    tag: &str,
    name: &str,
    mesh: &str,
    metric: &str,
) -> Option<delone_io::MeditMesh> {
    let venv = format!("/tmp/mmgvenv/bin/{program}");
    let Some(mmg) = [venv.as_str(), program]
        .into_iter()
        .find(|m| Command::new(m).arg("-h").output().is_ok())
    else {
        eprintln!("skipped: {program} is not installed (/tmp/mmgvenv/bin or PATH)");
        return None;
    };
    let d = dir(tag);
    std::fs::write(d.join(format!("{name}.mesh")), mesh).unwrap();
    std::fs::write(d.join(format!("{name}.sol")), metric).unwrap();
    let a = run(&[&format!("{name}.mesh"), "-o", "a.mesh", "-Q"], &d);
    assert!(a.status.success(), "{}", String::from_utf8_lossy(&a.stderr));
    // MMG reads delone's mesh and metric ...
    let m = Command::new(mmg)
        .args([
            "-in", "a.mesh", "-sol", "a.sol", "-out", "b.mesh", "-v", "-1",
        ])
        .current_dir(&d)
        .output()
        .unwrap();
    assert!(m.status.success(), "{}", String::from_utf8_lossy(&m.stdout));
    // ... and delone reads MMG's.
    let back = run(&["b.mesh", "--metric", "b.sol", "-o", "c.mesh", "-V"], &d);
    assert!(
        back.status.success(),
        "{}",
        String::from_utf8_lossy(&back.stderr)
    );
    Some(delone_io::read_medit_mesh(&std::fs::read(d.join("c.mesh")).unwrap()).unwrap())
}

#[test]
fn sol_files_round_trip_with_mmg() {
    if let Some(c) = mmg_round_trip("mmg2d_O3", "mmg", "sq", &square_mesh(), &anisotropic()) {
        assert_eq!(c.dimension, 2);
        assert!(!c.triangles.is_empty());
    }
}

#[test]
fn bad_input_is_a_clear_error() {
    let d = dir("bad");
    std::fs::write(d.join("sq.mesh"), square_mesh()).unwrap();
    let mut lines = vec!["1 0 1"; 25];
    lines[6] = "1 2 1";
    std::fs::write(d.join("indef.sol"), sol(2, &lines)).unwrap();
    std::fs::write(d.join("short.sol"), sol(2, &["1 0 1"; 24])).unwrap();
    std::fs::write(d.join("three.sol"), sol(3, &vec!["1 0 1 0 0 1"; 25])).unwrap();
    std::fs::write(
        d.join("neg.sol"),
        sol(2, &{
            let mut l = vec!["0.1"; 25];
            l[3] = "-1";
            l
        }),
    )
    .unwrap();
    for (args, want) in [
        (
            &["sq.mesh", "--metric", "indef.sol"][..],
            "the metric at vertex 7 (1-based) is not positive definite",
        ),
        (
            &["sq.mesh", "--metric", "short.sol"],
            "24 values for a mesh of 25 vertices",
        ),
        (
            &["sq.mesh", "--metric", "three.sol"],
            "a 3D solution for a 2D mesh",
        ),
        (&["sq.mesh", "--metric", "neg.sol"], "vertex 4 (1-based)"),
        (
            &["sq.mesh", "-hsiz", "0.1", "--metric", "neg.sol"],
            "exclude each other",
        ),
        (&["sq.mesh", "-hsiz", "0"], "-hsiz: 0 is not positive"),
        (
            &["sq.mesh", "--metric", "short.sol", "-zz"],
            "unknown option",
        ),
        (
            &["sq.mesh", "--metric", "sq.mesh", "-o", "sq.mesh"],
            "sq.mesh",
        ),
    ] {
        let out = run(args, &d);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && err.contains(want),
            "{args:?}: {err}"
        );
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
}

/// Vertices, elements and edge share in range after adapting `args`.
fn counts_after(args: &[&str], d: &Path) -> (f64, f64, f64) {
    let json = d.join(format!("{}.json", args.join("_").replace(['-', '.'], "")));
    let mut all = args.to_vec();
    all.extend(["-Q", "--stats-json", json.to_str().unwrap()]);
    run_ok(&all, d);
    let text = std::fs::read_to_string(json).unwrap();
    let after = &text[text.find("\"after\"").unwrap()..];
    let field = |key: &str| -> f64 {
        let at = after.find(&format!("\"{key}\":")).unwrap() + key.len() + 3;
        let rest = after[at..].trim_start();
        let end = rest.find([',', '\n', '}']).unwrap();
        rest[..end].trim().parse().unwrap()
    };
    (
        field("vertices"),
        field("elements"),
        field("in_range_share"),
    )
}

#[test]
fn metric_from_hsiz_or_the_mesh() {
    let d = dir("nometric");
    std::fs::write(d.join("sq.mesh"), square_mesh()).unwrap();
    // No metric: the grid's own sizes (edges 0.25 and diagonals 0.35), so
    // about as many vertices as the 25 of the input.
    let (v, _, share) = counts_after(&["sq.mesh", "-o", "a.mesh"], &d);
    assert!(
        (15.0..=45.0).contains(&v) && share > 0.8,
        "{v} vertices, {share} in range"
    );
    // -hsiz 0.1: a uniform mesh of edges about 0.1 (area 1 / (0.1² √3/4)
    // ≈ 230 triangles).
    let (v, t, share) = counts_after(&["sq.mesh", "-hsiz", "0.1", "-o", "b.mesh"], &d);
    assert!(
        (150.0..=320.0).contains(&t) && v > 80.0 && share > 0.9,
        "{v} {t} {share}"
    );
    // An input .sol next to the mesh gives way to -hsiz.
    std::fs::write(d.join("sq.sol"), anisotropic()).unwrap();
    assert_eq!(
        counts_after(&["sq.mesh", "-hsiz", "0.1", "-o", "c.mesh"], &d),
        (v, t, share)
    );
}

#[test]
fn vtu_and_msh_in_and_out() {
    let d = dir("formats");
    std::fs::write(d.join("sq.mesh"), square_mesh()).unwrap();
    std::fs::write(d.join("sq.sol"), anisotropic()).unwrap();
    let ok = |args: &[&str]| run_ok(args, &d);
    // .vtu out: the metric as point arrays, the elements and the boundary
    // edges with their references as cell data.
    ok(&["sq.mesh", "-o", "a.vtu", "-Q"]);
    let (a, arrays) = delone_io::read_vtu(&std::fs::read(d.join("a.vtu")).unwrap()).unwrap();
    assert_eq!(a.dimension, 2);
    let mut sides = a.edge_refs.clone();
    sides.sort_unstable();
    sides.dedup();
    assert_eq!(sides, [1, 2, 3, 4], "boundary edges of the .vtu");
    assert!(a.edges.len() >= 16 && a.triangle_refs.iter().all(|&r| r == 0));
    let names: Vec<&str> = arrays.iter().map(|x| x.name.as_str()).collect();
    assert_eq!(names, ["m11", "m12", "m22"]);
    assert!(arrays[0].values.iter().all(|&v| (v - 400.0).abs() < 1e-6));
    assert!(!d.join("a.sol").exists());
    // .vtu in, its own arrays as the metric; .msh out with its .sol.
    ok(&["a.vtu", "--metric", ":m11,m12,m22", "-o", "b.msh", "-Q"]);
    let b = delone_io::read_gmsh(&std::fs::read(d.join("b.msh")).unwrap()).unwrap();
    assert_eq!(b.dimension, 2);
    assert!(!b.triangles.is_empty());
    let mut sides = b.edge_refs.clone();
    sides.sort_unstable();
    sides.dedup();
    assert_eq!(sides, [1, 2, 3, 4], "boundary lines of the .msh");
    // .msh in; -hausd is met by construction; a .vtu's arrays named by file.
    let out = ok(&[
        "b.msh", "--metric", "b.sol", "-o", "c.mesh", "-hausd", "0.01", "-V",
    ]);
    assert!(String::from_utf8_lossy(&out.stdout).contains("-hausd 0.01: met by construction"));
    let measure = ["-noinsert", "-noswap", "-nomove", "-V"];
    let out = ok(&[&["a.vtu", "--metric", "a.vtu:m11"][..], &measure].concat());
    assert!(!out.stdout.is_empty());
    for (args, want) in [
        (
            &["a.vtu", "--metric", ":zz"][..],
            "no point array \"zz\" (point arrays: m11, m12, m22)",
        ),
        (&["a.vtu", "--metric", ":m11,m12"], "2 components per point"),
        (
            &["sq.mesh", "--metric", "a.vtu:m11"],
            "for a mesh of 25 vertices",
        ),
        (&["sq.mesh", "-hausd", "-1"], "-hausd"),
    ] {
        let out = run(args, &d);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && err.contains(want),
            "{args:?}: {err}"
        );
    }
}

/// A Python with meshio (the MMG venv's, else `python3`), if any.
fn meshio_python() -> Option<&'static str> {
    ["/tmp/mmgvenv/bin/python3", "python3"]
        .into_iter()
        .find(|p| {
            Command::new(p)
                .args(["-c", "import meshio"])
                .output()
                .is_ok_and(|o| o.status.success())
        })
}

#[test]
fn reads_vtu_and_msh_written_by_meshio() {
    let Some(python) = meshio_python() else {
        eprintln!("skipped: no Python with meshio (pip install meshio)");
        return;
    };
    let d = dir("meshio");
    let script = r#"
import meshio, numpy as np
n = 4
pts = np.array([[i / n, j / n, 0.0] for j in range(n + 1) for i in range(n + 1)])
tri = []
for j in range(n):
    for i in range(n):
        a, b, c, e = j*(n+1)+i, j*(n+1)+i+1, (j+1)*(n+1)+i+1, (j+1)*(n+1)+i
        tri += [[a, b, c], [a, c, e]]
tri = np.array(tri)
u = pts[:, 0] ** 2 + 0.5 * pts[:, 1] ** 2
ref = [np.full(len(tri), 3, dtype=np.int32)]
m = meshio.Mesh(pts, [("triangle", tri)], point_data={"u": u}, cell_data={"ref": ref})
m.write("binary.vtu", binary=True, compression=None)
m.write("ascii.vtu", binary=False)
m.write("zlib.vtu", binary=True)
g = meshio.Mesh(pts, [("triangle", tri)], cell_data={"gmsh:physical": ref, "gmsh:geometrical": ref})
g.write("sq.msh", file_format="gmsh", binary=False)
"#;
    let made = Command::new(python)
        .args(["-c", script])
        .current_dir(&d)
        .output()
        .unwrap();
    assert!(
        made.status.success(),
        "{}",
        String::from_utf8_lossy(&made.stderr)
    );
    for input in ["binary.vtu", "ascii.vtu"] {
        let (m, arrays) = delone_io::read_vtu(&std::fs::read(d.join(input)).unwrap()).unwrap();
        assert_eq!((m.points.len(), m.triangles.len()), (25, 32), "{input}");
        assert!(m.triangle_refs.iter().all(|&r| r == 3), "{input}");
        let u = &arrays.iter().find(|a| a.name == "u").unwrap().values;
        assert_eq!(u[6], 0.25f64.powi(2) + 0.5 * 0.25f64.powi(2), "{input}");
        run_ok(
            &[
                input,
                "--field",
                ":u",
                "--complexity",
                "40",
                "-o",
                "out.vtu",
                "-Q",
            ],
            &d,
        );
    }
    let m = delone_io::read_gmsh(&std::fs::read(d.join("sq.msh")).unwrap()).unwrap();
    assert_eq!(
        (m.dimension, m.points.len(), m.triangles.len()),
        (2, 25, 32)
    );
    run_ok(
        &[
            "sq.msh",
            "--field",
            "binary.vtu:u",
            "--complexity",
            "40",
            "-o",
            "o.mesh",
        ],
        &d,
    );
    let out = run(&["zlib.vtu", "--field", ":u"], &d);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("compressed"), "{err}");
}

/// The unit cube as six tetrahedra around its diagonal 0–7, with its
/// twelve boundary triangles (reference 1), in Medit format.
fn cube_mesh() -> String {
    let p = |b: usize| [b & 1, b >> 1 & 1, b >> 2].map(|x| x as f64);
    let mut tets = Vec::new();
    for path in [[1, 3], [1, 5], [2, 3], [2, 6], [4, 5], [4, 6]] {
        let mut t = [0, path[0], path[1], 7];
        let [a, b, c, d] = t.map(p);
        let e = |x: [f64; 3]| [x[0] - a[0], x[1] - a[1], x[2] - a[2]];
        let (u, v, w) = (e(b), e(c), e(d));
        let det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
            + u[2] * (v[0] * w[1] - v[1] * w[0]);
        if det < 0.0 {
            t.swap(0, 1);
        }
        tets.push(t);
    }
    let mut faces: Vec<[usize; 3]> = Vec::new();
    for t in &tets {
        for f in [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]] {
            let tri = f.map(|i| t[i]);
            let mut key = tri;
            key.sort_unstable();
            match faces.iter().position(|g| {
                let mut k = *g;
                k.sort_unstable();
                k == key
            }) {
                Some(i) => {
                    faces.remove(i);
                }
                None => faces.push(tri),
            }
        }
    }
    let mut s = "MeshVersionFormatted 2\nDimension 3\nVertices\n8\n".to_string();
    for b in 0..8 {
        let x = p(b);
        s += &format!("{} {} {} 0\n", x[0], x[1], x[2]);
    }
    s += &format!("Triangles\n{}\n", faces.len());
    for f in &faces {
        s += &format!("{} {} {} 1\n", f[0] + 1, f[1] + 1, f[2] + 1);
    }
    s += "Tetrahedra\n6\n";
    for t in &tets {
        s += &format!("{} {} {} {} 0\n", t[0] + 1, t[1] + 1, t[2] + 1, t[3] + 1);
    }
    s + "Corners\n8\n1\n2\n3\n4\n5\n6\n7\n8\nEnd\n"
}

#[test]
fn sol_files_round_trip_with_mmg3d() {
    // Sizes 0.25 along x and y, 0.5 along z.
    let metric = sol(3, &["16 0 16 0 0 4"; 8]);
    if let Some(c) = mmg_round_trip("mmg3d_O3", "mmg3", "cube", &cube_mesh(), &metric) {
        assert_eq!(c.dimension, 3);
        assert!(!c.tetrahedra.is_empty());
    }
}
