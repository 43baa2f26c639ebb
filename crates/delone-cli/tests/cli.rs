//! End-to-end tests of the `delone` binary on small generated inputs.
//!
//! Tests marked "needs kernels" can only pass once the 2D/3D Delaunay
//! kernels are merged (they fail with "only N distinct point(s)" on the stubs).

use std::path::Path;
use std::process::Output;

mod common;
use common::{run, stderr, tmp};

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn read(dir: &Path, name: &str) -> Vec<u8> {
    std::fs::read(dir.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// Simple deterministic generator.
struct Rng(u64);
impl Rng {
    fn f(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A jittered grid of `n*n` 2D points as .node text, numbered from `first`,
/// with one attribute and markers, comments and blank lines sprinkled in.
fn grid2(n: usize, first: usize) -> (String, Vec<[f64; 2]>) {
    let mut r = Rng(99);
    let mut pts = Vec::new();
    for j in 0..n {
        for i in 0..n {
            pts.push([
                i as f64 + 0.3 * (r.f() - 0.5),
                j as f64 + 0.3 * (r.f() - 0.5),
            ]);
        }
    }
    let mut s = format!("# generated grid\n{} 2 1 1\n\n", pts.len());
    for (k, p) in pts.iter().enumerate() {
        s += &format!(
            "{} {} {} {} 0 # pt\n",
            k + first,
            p[0],
            p[1],
            k as f64 * 0.5
        );
    }
    (s, pts)
}

fn cloud3(n: usize) -> (String, Vec<[f64; 3]>) {
    let mut r = Rng(7);
    let pts: Vec<[f64; 3]> = (0..n).map(|_| [r.f(), r.f(), r.f()]).collect();
    let mut s = format!("{n} 3 0 0\n");
    for (k, p) in pts.iter().enumerate() {
        s += &format!("{} {} {} {}\n", k + 1, p[0], p[1], p[2]);
    }
    (s, pts)
}

/// Parses a "<#items> <k>" table file (.edge, .face, .neigh) into rows of
/// integers (index column dropped) and returns (header, rows).
fn table(bytes: &[u8]) -> (Vec<i64>, Vec<Vec<i64>>) {
    let text = String::from_utf8(bytes.to_vec()).unwrap();
    let mut lines = text
        .lines()
        .filter(|l| !l.trim().is_empty() && !l.starts_with('#'));
    let header: Vec<i64> = lines
        .next()
        .unwrap()
        .split_whitespace()
        .map(|t| t.parse().unwrap())
        .collect();
    let rows: Vec<Vec<i64>> = lines
        .map(|l| l.split_whitespace().map(|t| t.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len() as i64, header[0]);
    (header, rows)
}

fn orient2(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

fn vol(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> f64 {
    let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    let w = [d[0] - a[0], d[1] - a[1], d[2] - a[2]];
    u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
        + u[2] * (v[0] * w[1] - v[1] * w[0])
}

// ---------------------------------------------------------------- 2D

/// needs kernels
#[test]
fn tri_writes_triangle_files_that_cover_all_points() {
    let d = tmp("tri-basic");
    let (text, pts) = grid2(12, 1);
    std::fs::write(d.join("g.node"), text).unwrap();
    let o = run(&d, &["tri", "-enC", "g"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    assert!(out.contains("144 points"), "{out}");
    assert!(out.contains("passed"), "{out}");
    assert!(
        out.contains("wrote g.1.node, g.1.ele, g.1.edge, g.1.neigh"),
        "{out}"
    );

    let node = delone_io::read_node(&read(&d, "g.1.node")).unwrap();
    assert_eq!(node.first_index, 1);
    assert_eq!(
        node.points::<2>().unwrap(),
        pts,
        "coordinates must round-trip"
    );
    assert_eq!(node.n_attributes, 1);
    assert_eq!(node.attributes[3], 1.5);
    let marks = node.markers.clone().unwrap();
    let hull = marks.iter().filter(|&&m| m == 1).count();
    assert!((4..=44).contains(&hull), "hull markers {hull}");

    let ele = delone_io::read_ele(&read(&d, "g.1.ele"), 1).unwrap();
    assert_eq!(ele.nodes_per_element, 3);
    let tris: Vec<[usize; 3]> = ele
        .elements
        .chunks(3)
        .map(|c| [c[0] as usize, c[1] as usize, c[2] as usize])
        .collect();
    // Euler for a triangulated convex region: T = 2n - 2 - h.
    assert_eq!(tris.len(), 2 * pts.len() - 2 - hull);
    let mut seen = vec![false; pts.len()];
    let mut area = 0.0;
    for t in &tris {
        let o = orient2(pts[t[0]], pts[t[1]], pts[t[2]]);
        assert!(o > 0.0, "triangle {t:?} not counterclockwise");
        area += o / 2.0;
        for &v in t {
            seen[v] = true;
        }
    }
    assert!(seen.iter().all(|&s| s), "every point is a vertex");
    assert!(area > 0.8 * 11.0 * 11.0 && area < 1.2 * 11.0 * 11.0);

    let (h, edges) = table(&read(&d, "g.1.edge"));
    assert_eq!(h, vec![edges.len() as i64, 1]);
    assert_eq!(edges.len(), pts.len() + tris.len() - 1);
    assert_eq!(edges.iter().filter(|e| e[3] == 1).count(), hull);

    let (h, nb) = table(&read(&d, "g.1.neigh"));
    assert_eq!(h, vec![tris.len() as i64, 3]);
    let none = nb
        .iter()
        .flat_map(|r| &r[1..])
        .filter(|&&x| x == -1)
        .count();
    assert_eq!(none, hull);
    for r in &nb {
        for &n in &r[1..] {
            if n != -1 {
                assert!(
                    nb[(n - 1) as usize][1..].contains(&r[0]),
                    "neighbours symmetric"
                );
            }
        }
    }
}

/// needs kernels
#[test]
fn tri_numbering_follows_input_and_z() {
    let d = tmp("tri-zero");
    let (text, _) = grid2(5, 0);
    std::fs::write(d.join("a.node"), &text).unwrap();
    let o = run(&d, &["tri", "-Q", "a.node"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).is_empty(), "-Q is quiet");
    let ele = String::from_utf8(read(&d, "a.1.ele")).unwrap();
    assert!(ele.lines().nth(1).unwrap().starts_with("0 "));
    let e = delone_io::read_ele(ele.as_bytes(), 0).unwrap();
    assert!(e.elements.contains(&0));

    let (text, _) = grid2(5, 1);
    std::fs::write(d.join("b.node"), &text).unwrap();
    let o = run(&d, &["tri", "-zQ", "b.node"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let node = delone_io::read_node(&read(&d, "b.1.node")).unwrap();
    assert_eq!(node.first_index, 0);
    let ele = delone_io::read_ele(&read(&d, "b.1.ele"), 0).unwrap();
    assert_eq!(ele.first_index, 0);
    assert!(ele.elements.contains(&0) && ele.elements.iter().all(|&v| v < 25));
}

/// needs kernels
#[test]
fn tri_iteration_numbers_and_switches_n_e_b() {
    let d = tmp("tri-iter");
    let (text, _) = grid2(4, 1);
    std::fs::write(d.join("m.1.node"), &text).unwrap();
    let o = run(&d, &["tri", "-QBe", "m.1"]);
    assert!(o.status.success(), "{}", stderr(&o));
    for f in ["m.2.node", "m.2.ele", "m.2.edge"] {
        assert!(d.join(f).exists(), "{f}");
    }
    let node = delone_io::read_node(&read(&d, "m.2.node")).unwrap();
    assert_eq!(node.markers, None, "-B drops markers");
    let (h, _) = table(&read(&d, "m.2.edge"));
    assert_eq!(h[1], 0);

    // -I would overwrite the input .node: refused, nothing written.
    let o = run(&d, &["tri", "-I", "m.1.node"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("would overwrite the input"),
        "{}",
        stderr(&o)
    );
    // With -N it is fine and writes m.1.ele.
    let o = run(&d, &["tri", "-QIN", "m.1.node"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(d.join("m.1.ele").exists());
    // -N -E: nothing but the summary.
    let o = run(&d, &["tri", "-NE", "m.1.node"]);
    assert!(o.status.success());
    assert!(!stdout(&o).contains("wrote"));
    // --output-dir.
    let o = run(&d, &["tri", "-Q", "--output-dir", "sub", "m.1.node"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(d.join("sub/m.2.ele").exists());
}

/// needs kernels
#[test]
fn tri_verbose_reports_duplicates_and_fortune() {
    let d = tmp("tri-dup");
    let text = "5 2 0 0\n1 0 0\n2 1 0\n3 0 1\n4 1 0\n5 1 1\n";
    std::fs::write(d.join("d.node"), text).unwrap();
    let o = run(&d, &["tri", "-VF", "d"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    assert!(out.contains("duplicates: 1"), "{out}");
    assert!(out.contains("point 4 (line 5) duplicates point 2"), "{out}");
    assert!(out.contains("Fortune"), "{out}");
    assert!(out.contains("hull edges: 4"), "{out}");
    let ele = delone_io::read_ele(&read(&d, "d.1.ele"), 1).unwrap();
    assert_eq!(ele.len(), 2);
    assert!(!ele.elements.contains(&3), "the duplicate is not a vertex");
    // The output .node keeps all 5 points; the duplicate has its original's marker.
    let node = delone_io::read_node(&read(&d, "d.1.node")).unwrap();
    assert_eq!(node.len(), 5);
    assert_eq!(node.markers, Some(vec![1, 1, 1, 1, 1]));
}

/// needs kernels
#[test]
fn tri_vtu_output_and_determinism() {
    let d = tmp("tri-vtu");
    let (text, _) = grid2(8, 1);
    std::fs::write(d.join("v.node"), &text).unwrap();
    let o = run(&d, &["tri", "-Q", "-o", "v.vtu", "v"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let vtu = read(&d, "v.vtu");
    assert!(vtu.starts_with(b"<?xml"));
    assert!(vtu.windows(12).any(|w| w == b"AppendedData"));
    let o = run(&d, &["tri", "-Q", "--vtu-ascii", "v"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let a = String::from_utf8(read(&d, "v.1.vtu")).unwrap();
    assert!(a.contains("format=\"ascii\"") && a.contains("Name=\"marker\""));
    let first = read(&d, "v.1.ele");
    let o = run(&d, &["tri", "-Q", "v"]);
    assert!(o.status.success());
    assert_eq!(first, read(&d, "v.1.ele"), "same input, same output");
}

/// needs kernels
#[test]
fn tri_on_shared_data() {
    let Some(data) = delone_testdata::corpus_path(env!("CARGO_MANIFEST_DIR"), "2d/points") else {
        return;
    };
    let d = tmp("tri-shared");
    for name in ["dots", "spiral", "diamond_02_00009"] {
        let src = data.join(format!("{name}.node"));
        assert!(
            src.is_file(),
            "{} is missing from the corpus",
            src.display()
        );
        let o = run(
            &d,
            &["tri", "-QC", "--output-dir", ".", src.to_str().unwrap()],
        );
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        let n = delone_io::read_node(&std::fs::read(&src).unwrap()).unwrap();
        let e = delone_io::read_ele(&read(&d, &format!("{name}.1.ele")), n.first_index).unwrap();
        assert!(e.len() >= n.len() / 2, "{name}");
    }
}

// ---------------------------------------------------------------- 3D

/// needs kernels
#[test]
fn tet_writes_tetgen_files() {
    let d = tmp("tet-basic");
    let (text, pts) = cloud3(150);
    std::fs::write(d.join("c.node"), text).unwrap();
    let o = run(&d, &["tet", "-C", "c.node"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    assert!(out.contains("wrote c.1.node, c.1.ele, c.1.face"), "{out}");
    assert!(!d.join("c.1.edge").exists() && !d.join("c.1.neigh").exists());

    let ele = delone_io::read_ele(&read(&d, "c.1.ele"), 1).unwrap();
    assert_eq!(ele.nodes_per_element, 4);
    let mut seen = vec![false; pts.len()];
    let mut total = 0.0;
    for t in ele.elements.chunks(4) {
        let p = |k: usize| pts[t[k] as usize];
        let v = vol(p(0), p(1), p(2), p(3));
        assert!(v > 0.0, "tet {t:?} has volume {v}");
        total += v / 6.0;
        for &v in t {
            seen[v as usize] = true;
        }
    }
    assert!(seen.iter().all(|&s| s), "every point is a vertex");
    assert!(total > 0.5 && total <= 1.0, "volume {total}");

    // Hull faces: a closed surface, every edge shared by two faces, Euler 2.
    let (h, faces) = table(&read(&d, "c.1.face"));
    assert_eq!(h[1], 1);
    assert!(faces.iter().all(|f| f[4] == 1));
    let mut edges = std::collections::BTreeMap::new();
    let mut verts = std::collections::BTreeSet::new();
    for f in &faces {
        for k in 0..3 {
            let (a, b) = (f[1 + k], f[1 + (k + 1) % 3]);
            *edges.entry((a.min(b), a.max(b))).or_insert(0) += 1;
            verts.insert(a);
        }
    }
    assert!(edges.values().all(|&c| c == 2));
    assert_eq!(
        verts.len() as i64 - edges.len() as i64 + faces.len() as i64,
        2
    );
    let node = delone_io::read_node(&read(&d, "c.1.node")).unwrap();
    let marked = node.markers.unwrap().iter().filter(|&&m| m == 1).count();
    assert_eq!(marked, verts.len(), "hull vertices get marker 1");
}

/// `--threads` reads and writes a point set in parts: the same files for
/// every count (12,000 points: several blocks of `.ele` rows).
#[test]
fn tet_threads_give_the_same_files() {
    let d = tmp("tet-threads");
    std::fs::write(d.join("s.node"), cloud3(12_000).0).unwrap();
    let mut first: Option<Vec<Vec<u8>>> = None;
    for t in ["1", "2", "3"] {
        let o = run(&d, &["tet", "-Qn", "--threads", t, "s"]);
        assert!(o.status.success(), "{}", stderr(&o));
        let files: Vec<Vec<u8>> = ["node", "ele", "face", "neigh"]
            .iter()
            .map(|e| read(&d, &format!("s.1.{e}")))
            .collect();
        let tets = delone_io::read_ele(&files[1], 1).unwrap().len();
        assert!(tets > 1 << 16, "{tets} tetrahedra: several blocks of rows");
        match &first {
            None => first = Some(files),
            Some(f) => assert!(*f == files, "--threads {t} wrote other bytes"),
        }
    }
    let o = run(&d, &["tet", "--threads", "0", "s"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}

/// needs kernels
#[test]
fn tet_switches_f_e_n_k_f_and_vtu() {
    let d = tmp("tet-sw");
    let (text, pts) = cloud3(60);
    std::fs::write(d.join("s.node"), text).unwrap();
    let o = run(&d, &["tet", "-QfenkBz", "-o", "s.vtu", "s"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let ele = delone_io::read_ele(&read(&d, "s.1.ele"), 0).unwrap();
    let t = ele.len() as i64;
    let (fh, faces) = table(&read(&d, "s.1.face"));
    assert_eq!(fh[1], 0, "-B: no markers");
    let (_, edges) = table(&read(&d, "s.1.edge"));
    let (nh, nb) = table(&read(&d, "s.1.neigh"));
    assert_eq!(nh, vec![t, 4]);
    let hull = nb
        .iter()
        .flat_map(|r| &r[1..])
        .filter(|&&x| x == -1)
        .count() as i64;
    // All faces once: 4T = 2F - hull.
    assert_eq!(4 * t, 2 * faces.len() as i64 - hull);
    // Euler for a 3-ball: V - E + F - T = 1.
    assert_eq!(
        pts.len() as i64 - edges.len() as i64 + faces.len() as i64 - t,
        1
    );
    let vtk = String::from_utf8(read(&d, "s.1.vtk")).unwrap();
    assert!(vtk.starts_with("# vtk DataFile Version 2.0\n"));
    assert!(vtk.contains(&format!("CELLS {t} {}", 5 * t)));
    assert!(d.join("s.vtu").exists());

    let o = run(&d, &["tet", "-QF", "s"]);
    assert!(o.status.success());
    let o = run(&d, &["tet", "-F", "s.1"]);
    assert!(
        stdout(&o).contains("wrote s.2.node, s.2.ele\n"),
        "{}",
        stdout(&o)
    );
}

#[test]
fn refine_an_existing_mesh() {
    let d = tmp("remesh");
    std::fs::write(
        d.join("sq.poly"),
        "4 2 0 1\n1 0 0 1\n2 1 0 1\n3 1 1 1\n4 0 1 1\n4 1\n1 1 2 1\n2 2 3 1\n3 3 4 1\n4 4 1 1\n0\n",
    )
    .unwrap();
    let o = run(&d, &["tri", "-pC", "sq.poly"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let o = run(&d, &["tri", "-rq30a0.01C", "sq.1"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(stdout(&o).contains("check: constrained Delaunay triangulation is valid"));
    let ele = std::fs::read_to_string(d.join("sq.2.ele")).unwrap();
    let n: usize = ele.split_whitespace().next().unwrap().parse().unwrap();
    assert!(n > 100, "{n} triangles");
    // -a without a number reads sq.2.area: every triangle at most 0.0005.
    let area: String = std::iter::once(format!("{n}\n"))
        .chain((1..=n).map(|i| format!("{i} 0.0005\n")))
        .collect();
    std::fs::write(d.join("sq.2.area"), area).unwrap();
    let o = run(&d, &["tri", "-raC", "sq.2"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let ele = std::fs::read_to_string(d.join("sq.3.ele")).unwrap();
    let n3: usize = ele.split_whitespace().next().unwrap().parse().unwrap();
    assert!(n3 >= 2000, "{n3} triangles");
    // A missing .area file is an error naming it.
    expect_err(&d, &["tri", "-ra", "sq.1"], 1, "sq.1.area");
    // A clockwise triangle is named.
    std::fs::write(d.join("bad.node"), "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n").unwrap();
    std::fs::write(d.join("bad.ele"), "1 3 0\n1 1 3 2\n").unwrap();
    expect_err(&d, &["tri", "-rq", "bad"], 1, "triangle 0");
}

// ---------------------------------------------------------------- errors

fn expect_err(dir: &Path, args: &[&str], code: i32, needle: &str) {
    let o = run(dir, args);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(code), "{args:?}: {e}");
    assert!(e.starts_with("delone: error: "), "{args:?}: {e}");
    assert_eq!(e.lines().count(), 1, "one line: {e}");
    assert!(e.contains(needle), "{args:?}: {e:?} lacks {needle:?}");
}

#[test]
fn usage_errors() {
    let d = tmp("usage");
    expect_err(
        &d,
        &["tri", "-q", "x"],
        2,
        "-q, -a and -S refine a PSLG (-p) or an existing mesh (-r)",
    );
    expect_err(
        &d,
        &["tri", "-pq61", "x"],
        2,
        "-q61: the minimum angle must be at most 60",
    );
    expect_err(
        &d,
        &["tet", "-q1.4", "x"],
        2,
        "-q, -a, -m and -S refine a PLC or surface (-p) or an existing mesh (-r)",
    );
    expect_err(&d, &["tet", "-a0.1", "x"], 2, "or an existing mesh (-r)");
    expect_err(
        &d,
        &["tri", "-k", "x"],
        2,
        "unknown switch -k for delone tri",
    );
    expect_err(
        &d,
        &["tet", "-u", "x"],
        2,
        "unknown switch -u for delone tet",
    );
    expect_err(&d, &["tri"], 2, "no input file");
    expect_err(&d, &["tri", "a", "b"], 2, "more than one input file");
    expect_err(
        &d,
        &["tri", "--frobnicate", "a"],
        2,
        "unknown option --frobnicate",
    );
    expect_err(&d, &["mesh", "a"], 2, "unknown subcommand");
    expect_err(&d, &["tri", "x.poly"], 2, ".poly input needs -p");
    expect_err(&d, &["tri", "nope"], 1, "cannot read nope.node");
}

#[test]
fn input_errors_name_file_line_and_index() {
    let d = tmp("input");
    let cases: &[(&str, &str, &str, &str)] = &[
        ("tri", "short", "5 2 0 0\n1 0 0\n2 1 0\n3 0 1\n", "short.node: line 1: header says 5 points but the file ends after 3"),
        ("tri", "coords", "3 2 0 0\n1 0 0\n2 1\n3 0 1\n", "coords.node: line 3: expected 2 coordinates, found 1"),
        ("tri", "word", "3 2 0 0\n1 0 0\n2 1 zero\n3 0 1\n", "line 3: expected a coordinate, found \"zero\""),
        ("tri", "index", "3 2 0 0\n1 0 0\n3 1 0\n4 0 1\n", "line 3: expected point index 2, found 3"),
        ("tri", "dim", "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n", "dim.node: line 1: the header gives dimension 3, delone tri needs 2D points (use delone tet)"),
        ("tet", "dim2", "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n", "delone tet needs 3D points (use delone tri)"),
        ("tri", "empty", "", "line 1: expected a header line, found an empty file"),
    ];
    for (mode, name, text, needle) in cases {
        std::fs::write(d.join(format!("{name}.node")), text).unwrap();
        expect_err(&d, &[mode, name], 1, needle);
        assert!(!d.join(format!("{name}.1.ele")).exists());
    }
}

/// needs kernels (the stubs report every input as too small)
#[test]
fn mesh_errors_name_the_point() {
    let d = tmp("mesh");
    let cases: &[(&str, &str, &str, &str)] = &[
        (
            "tri",
            "nan",
            "4 2 0 0\n1 0 0\n2 1 0\n# c\n3 nan 1\n4 1 1\n",
            "nan.node: line 5: point 3 has a NaN or infinite coordinate",
        ),
        (
            "tet",
            "inf",
            "5 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 inf\n4 1 1 1\n",
            "inf.node: line 5: point 3 has a NaN or infinite coordinate",
        ),
        ("tri", "two", "2 2 0 0\n1 0 0\n2 1 0\n", "two.node: only 2"),
        (
            "tri",
            "line",
            "4 2 0 0\n1 0 0\n2 1 1\n3 2 2\n4 3 3\n",
            "collinear",
        ),
        (
            "tet",
            "plane",
            "5 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 1 1 0\n5 2 3 0\n",
            "plane.node",
        ),
        (
            "tet",
            "three",
            "3 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n",
            "three.node",
        ),
    ];
    for (mode, name, text, needle) in cases {
        std::fs::write(d.join(format!("{name}.node")), text).unwrap();
        expect_err(&d, &[mode, name], 1, needle);
    }
}

#[test]
fn help_and_version() {
    let d = tmp("help");
    let o = run(&d, &["--help"]);
    assert!(o.status.success());
    let h = stdout(&o);
    assert!(h.contains("delone tri") && h.contains("delone tet"));
    let o = run(&d, &["tri", "--help"]);
    let h = stdout(&o);
    for l in [
        "-z",
        "-Q",
        "-V",
        "-C",
        "-e",
        "-n",
        "-N",
        "-E",
        "-I",
        "-F",
        "-B",
        "--vtu",
        "--vtu-ascii",
        "--output-dir",
        "--quiet",
    ] {
        assert!(
            h.contains(&format!("    {l}")) || h.contains(&format!(" {l} ")),
            "tri help lacks {l}"
        );
    }
    let o = run(&d, &["tet", "-h"]);
    let h = stdout(&o);
    for l in [
        "-z", "-Q", "-V", "-C", "-e", "-n", "-f", "-N", "-E", "-F", "-I", "-B", "-k",
    ] {
        assert!(h.contains(&format!("    {l}")), "tet help lacks {l}");
    }
    let o = run(&d, &["--version"]);
    assert_eq!(
        stdout(&o).trim(),
        format!("delone {}", env!("CARGO_PKG_VERSION"))
    );
}

/// Random and truncated inputs: the binary answers with success or a
/// one-line error and exit code 1, never a panic (exit code 101) or a hang.
#[test]
fn garbage_inputs_never_panic() {
    let d = tmp("garbage");
    let (valid, _) = grid2(4, 1);
    let valid = valid.into_bytes();
    let mut r = Rng(4242);
    let mut inputs: Vec<Vec<u8>> = (0..valid.len())
        .step_by(7)
        .map(|cut| valid[..cut].to_vec())
        .collect();
    for _ in 0..15 {
        let mut v = valid.clone();
        for _ in 0..4 {
            let at = (r.f() * v.len() as f64) as usize % v.len();
            v[at] = (r.f() * 256.0) as u8;
        }
        inputs.push(v);
    }
    inputs.push(b"99999999999999999999 2\n".to_vec());
    inputs.push(b"4000000000 2 4000000000 1\n1 0 0\n".to_vec());
    inputs.push(vec![0xff; 64]);
    for (k, input) in inputs.iter().enumerate() {
        for mode in ["tri", "tet"] {
            std::fs::write(d.join("g.node"), input).unwrap();
            let o = run(&d, &[mode, "-Q", "g"]);
            let code = o.status.code();
            assert!(
                code == Some(0) || code == Some(1),
                "input {k} ({mode}): exit {code:?}, stderr {}",
                stderr(&o)
            );
            if code == Some(1) {
                let e = stderr(&o);
                assert!(e.starts_with("delone: error: g.node"), "input {k}: {e}");
            }
        }
    }
}

#[test]
fn tri_p_square_with_hole_crossing_and_region() {
    let d = tmp("pslg");
    // A square with a square hole, a diagonal crossing another segment, and
    // two regions; 1-based, markers on.
    let poly = "\
10 2 0 1
1 0 0 1
2 4 0 1
3 4 4 1
4 0 4 1
5 1 1 0
6 2 1 0
7 2 2 0
8 1 2 0
9 3 0.5 0
10 3.5 3.5 0
9 1
1 1 2 5
2 2 3 5
3 3 4 5
4 4 1 5
5 5 6 7
6 6 7 7
7 7 8 7
8 8 5 7
9 9 10 3
1
1 1.5 1.5
2
1 0.5 3.5 10 -1
2 3.9 0.2 20 -1
";
    std::fs::write(d.join("sq.poly"), poly).unwrap();
    let o = run(&d, &["tri", "-pACen", "sq"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("constrained Delaunay triangulation is valid"),
        "{}",
        stdout(&o)
    );
    let ele = String::from_utf8(read(&d, "sq.1.ele")).unwrap();
    let node = String::from_utf8(read(&d, "sq.1.node")).unwrap();
    assert!(node.starts_with("10 2 0 1\n"), "{node}");
    // One attribute per triangle; the diagonal 9-10 does not close a region,
    // so the later region (20) floods the whole domain.
    assert!(ele.lines().next().unwrap().ends_with(" 3 1"), "{ele}");
    assert!(ele.lines().skip(1).all(|l| l.ends_with(" 20")), "{ele}");
    let poly_out = String::from_utf8(read(&d, "sq.1.poly")).unwrap();
    assert!(poly_out.starts_with("0 2 0 1\n9 1\n"), "{poly_out}");
    // The holes, then the regions (as Triangle writes them).
    assert!(
        poly_out.ends_with("1\n1 1.5 1.5\n2\n1 0.5 3.5 10 -1\n2 3.9 0.2 20 -1\n"),
        "{poly_out}"
    );
    for f in ["sq.1.edge", "sq.1.neigh"] {
        assert!(d.join(f).exists(), "{f}");
    }
    // -c keeps the hull, -z numbers from 0.
    let o = run(&d, &["tri", "-pczQ", "sq.poly"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).is_empty());
    // Crossing segments: Steiner vertex appended to the .node output.
    std::fs::write(
        d.join("x.poly"),
        "4 2 0 0\n1 0 0\n2 2 0\n3 2 2\n4 0 2\n2 0\n1 1 3\n2 2 4\n0\n",
    )
    .unwrap();
    let o = run(&d, &["tri", "-pcC", "x"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let node = String::from_utf8(read(&d, "x.1.node")).unwrap();
    assert!(node.starts_with("5 2 0 1\n"), "{node}");
    assert!(node.contains("\n5 1 1 "), "{node}");
    let (_, ele) = table(&read(&d, "x.1.ele"));
    assert_eq!(ele.len(), 4);
    // Errors name the segment's line.
    std::fs::write(
        d.join("bad.poly"),
        "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n1 0\n1 1 7\n0\n",
    )
    .unwrap();
    expect_err(&d, &["tri", "-p", "bad"], 1, "line 6");
}
