//! The command line's own promises: no output overwrites an
//! input, every switch is honoured or refused, `tet -d` exits 1 on any
//! finding, empty results are errors, numbers in switches may use
//! scientific notation, the help lists every switch, and errors use the
//! file's own numbering.

use std::collections::BTreeMap;
use std::path::Path;
use std::process::Output;

mod common;
use common::{run, stderr, tmp};

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Every file of `dir` with its bytes.
fn snapshot(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            (
                e.file_name().to_string_lossy().into_owned(),
                std::fs::read(e.path()).unwrap(),
            )
        })
        .collect()
}

/// A unit square with a square hole as a 1-based .poly.
const SQUARE_POLY: &str = "8 2 0 1\n1 0 0 1\n2 4 0 1\n3 4 4 1\n4 0 4 1\n\
5 1 1 0\n6 3 1 0\n7 3 3 0\n8 1 3 0\n\
8 1\n1 1 2 1\n2 2 3 1\n3 3 4 1\n4 4 1 1\n5 5 6 0\n6 6 7 0\n7 7 8 0\n8 8 5 0\n\
1\n1 2 2\n";

/// The unit cube as a Medit surface (outward triangles).
const CUBE_MESH: &str = "MeshVersionFormatted 1\nDimension 3\nVertices\n8\n\
0 0 0 0\n1 0 0 0\n1 1 0 0\n0 1 0 0\n0 0 1 0\n1 0 1 0\n1 1 1 0\n0 1 1 0\n\
Triangles\n12\n1 4 3 1\n1 3 2 1\n5 6 7 1\n5 7 8 1\n1 2 6 1\n1 6 5 1\n\
4 8 7 1\n4 7 3 1\n1 5 8 1\n1 8 4 1\n2 3 7 1\n2 7 6 1\nEnd\n";

/// The unit cube as OFF (0-based, outward triangles).
const CUBE_OFF: &str = "OFF\n8 12 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n\
3 0 3 2\n3 0 2 1\n3 4 5 6\n3 4 6 7\n3 0 1 5\n3 0 5 4\n\
3 3 7 6\n3 3 6 2\n3 0 4 7\n3 0 7 3\n3 1 2 6\n3 1 6 5\n";

/// Runs `args` in a directory holding `files`; the run must fail naming
/// `needles`, and leave the directory exactly as it was (nothing written,
/// inputs unchanged).
fn refused_untouched(name: &str, files: &[(&str, &str)], args: &[&str], needles: &[&str]) {
    let dir = tmp(name);
    for (f, text) in files {
        std::fs::write(dir.join(f), text).unwrap();
    }
    let before = snapshot(&dir);
    let out = run(&dir, args);
    let err = stderr(&out);
    assert!(
        !out.status.success(),
        "{args:?} succeeded:\n{}{err}",
        stdout(&out)
    );
    for n in needles {
        assert!(err.contains(n), "{args:?}: {n:?} not in {err:?}");
    }
    assert_eq!(
        snapshot(&dir).keys().collect::<Vec<_>>(),
        before.keys().collect::<Vec<_>>(),
        "{args:?} wrote files"
    );
    assert!(snapshot(&dir) == before, "{args:?} changed an input");
}

#[test]
fn no_output_overwrites_an_input() {
    let poly = [("face.poly", SQUARE_POLY)];
    refused_untouched(
        "g1",
        &poly,
        &["tri", "-pI", "face.poly"],
        &["face.poly", "-I", "nothing was written"],
    );
    refused_untouched(
        "g2",
        &poly,
        &["tri", "-pq", "face.poly", "--stats-json", "face.poly"],
        &["--stats-json", "face.poly"],
    );
    refused_untouched(
        "g3",
        &poly,
        &["tri", "-p", "face.poly", "-o", "face.poly"],
        &["-o/--vtu", "face.poly"],
    );
    refused_untouched(
        "g4",
        &poly,
        &["tri", "-p", "face.poly", "--svg", "face.poly"],
        &["--svg"],
    );
    refused_untouched(
        "g5",
        &poly,
        &["tri", "-p", "face.poly", "--png=./face.poly"],
        &["--png"],
    );
    let mesh = [("model.mesh", CUBE_MESH)];
    refused_untouched(
        "g6",
        &mesh,
        &["tet", "-pq1.2gI", "model.mesh"],
        &["model.mesh", "-g", "-I"],
    );
    refused_untouched(
        "g7",
        &mesh,
        &["tet", "-p", "model.mesh", "--medit", "model.mesh"],
        &["--medit"],
    );
    refused_untouched(
        "g8",
        &mesh,
        &["tet", "-p", "model.mesh", "--gmsh", "model.mesh"],
        &["--gmsh"],
    );
    let off = [("cube.off", CUBE_OFF)];
    refused_untouched(
        "g9",
        &off,
        &["tet", "-p", "cube.off", "--vtu", "cube.off"],
        &["-o/--vtu"],
    );
    refused_untouched(
        "g10",
        &off,
        &["tet", "-pq", "cube.off", "--stats-json=cube.off"],
        &["--stats-json"],
    );
    refused_untouched(
        "g11",
        &off,
        &["tet", "-p", "cube.off", "--png", "cube.off"],
        &["--png"],
    );
    // Companions: the .node of a .poly without points, the .area of -r.
    let node = "4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n";
    let hollow = "0 2 0 0\n4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n";
    refused_untouched(
        "g12",
        &[("sq.poly", hollow), ("sq.node", node)],
        &["tri", "-pI", "sq.poly", "-P"],
        &["sq.node", ".node output"],
    );
    let ele = "2 3 0\n1 1 2 3\n2 1 3 4\n";
    refused_untouched(
        "g13",
        &[
            ("m.node", node),
            ("m.ele", ele),
            ("m.poly", "0 2 0 0\n4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n"),
        ],
        &["tri", "-rNEI", "m"],
        &["m.poly", "-I"],
    );
    refused_untouched(
        "g14",
        &[("m.node", node), ("m.ele", ele)],
        &["tri", "-rI", "m"],
        &["m.node", "-I"],
    );
    // Points: the .node and -w's .weight.
    refused_untouched(
        "g15",
        &[("p.node", node)],
        &["tri", "-I", "p.node"],
        &["p.node"],
    );
    refused_untouched(
        "g16",
        &[("p.node", node), ("p.weight", "4 0\n1 0\n2 0\n3 0\n4 0\n")],
        &["tri", "-w", "p", "--svg", "p.weight"],
        &["p.weight", "--svg"],
    );
    // A symbolic link to the input is the input.
    #[cfg(unix)]
    {
        let dir = tmp("g17");
        std::fs::write(dir.join("face.poly"), SQUARE_POLY).unwrap();
        std::os::unix::fs::symlink("face.poly", dir.join("link.vtu")).unwrap();
        let out = run(&dir, &["tri", "-p", "face.poly", "--vtu", "link.vtu"]);
        assert!(!out.status.success());
        assert_eq!(
            std::fs::read_to_string(dir.join("face.poly")).unwrap(),
            SQUARE_POLY
        );
        assert!(!dir.join("face.1.node").exists());
    }
    // Without a collision the same runs write.
    let dir = tmp("g18");
    std::fs::write(dir.join("model.mesh"), CUBE_MESH).unwrap();
    let out = run(&dir, &["tet", "-pgI", "model.mesh", "--output-dir", "out"]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(dir.join("out/model.mesh").is_file());
    assert_eq!(
        std::fs::read_to_string(dir.join("model.mesh")).unwrap(),
        CUBE_MESH
    );
}

/// The number of elements in the header of a `.ele` file.
fn ele_count(path: &Path) -> usize {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    text.split_whitespace().next().unwrap().parse().unwrap()
}

/// A legacy `.vtk` and an ASCII `.vtu` with `cells` cells each.
fn check_vtk(path: &Path, cells: usize) {
    let t = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    assert!(t.starts_with("# vtk DataFile"), "{path:?}");
    let line = t.lines().find(|l| l.starts_with("CELLS ")).unwrap();
    assert_eq!(
        line.split_whitespace().nth(1),
        Some(cells.to_string().as_str()),
        "{path:?}"
    );
}

fn check_vtu_ascii(path: &Path, cells: usize) {
    let t = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    assert!(
        t.contains("<VTKFile") && t.trim_end().ends_with("</VTKFile>"),
        "{path:?}"
    );
    assert!(t.contains("format=\"ascii\""), "{path:?}");
    assert!(
        t.contains(&format!("NumberOfCells=\"{cells}\"")),
        "{path:?}"
    );
}

/// `-k` and `--vtu-ascii` write their files on every tet path.
#[test]
fn tet_k_and_vtu_ascii_on_every_path() {
    let dir = tmp("kvtu");
    std::fs::write(dir.join("cube.off"), CUBE_OFF).unwrap();
    let node = "8 3 0 0\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 0 0 1\n6 1 0 1\n7 1 1 1\n8 0 1 1\n9 0.5 0.5 0.5\n"
        .replacen("8 3", "9 3", 1);
    std::fs::write(dir.join("pts.node"), node).unwrap();
    let ok = |args: &[&str]| {
        let out = run(&dir, args);
        assert!(out.status.success(), "{args:?}: {}", stderr(&out));
    };
    for (args, base) in [
        (vec!["tet", "-Qk", "--vtu-ascii", "pts"], "pts.1"),
        (vec!["tet", "-Qpk", "--vtu-ascii", "cube.off"], "cube.1"),
        (vec!["tet", "-Qpq1.5k", "--vtu-ascii", "cube.off"], "cube.1"),
        (vec!["tet", "-Qrq1.5k", "--vtu-ascii", "cube.1"], "cube.2"),
    ] {
        for ext in ["vtk", "vtu"] {
            let _ = std::fs::remove_file(dir.join(format!("{base}.{ext}")));
        }
        ok(&args);
        let n = ele_count(&dir.join(format!("{base}.ele")));
        assert!(n > 0);
        check_vtk(&dir.join(format!("{base}.vtk")), n);
        check_vtu_ascii(&dir.join(format!("{base}.vtu")), n);
    }
    // --vtu FILE with --vtu-ascii: FILE in ASCII.
    ok(&[
        "tet",
        "-Qp",
        "--vtu",
        "named.vtu",
        "--vtu-ascii",
        "cube.off",
    ]);
    check_vtu_ascii(&dir.join("named.vtu"), ele_count(&dir.join("cube.1.ele")));
}

/// (mode and switches, the switch a refusal names): each accepted switch
/// that would have no effect in the run is refused naming it and why.
#[test]
fn switches_without_effect_are_refused() {
    let dir = tmp("refuse");
    std::fs::write(dir.join("face.poly"), SQUARE_POLY).unwrap();
    std::fs::write(dir.join("cube.off"), CUBE_OFF).unwrap();
    let pts2 = "4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1.2\n";
    std::fs::write(dir.join("p2.node"), pts2).unwrap();
    let pts3 = "5 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 1 1\n";
    std::fs::write(dir.join("p3.node"), pts3).unwrap();
    for a in [
        &["tri", "-pQ", "face.poly"][..],
        &["tet", "-pQ", "cube.off"],
    ] {
        let out = run(&dir, a);
        assert!(out.status.success(), "{a:?}: {}", stderr(&out));
    }
    let rows: &[(&[&str], &str, &str)] = &[
        (&["tet", "-dk", "cube.off"], "-k", "-d"),
        (
            &["tet", "-d", "--vtu-ascii", "cube.off"],
            "--vtu-ascii",
            "-d",
        ),
        (
            &["tet", "-d", "--vtu", "x.vtu", "cube.off"],
            "-o/--vtu",
            "-d",
        ),
        (&["tet", "-dg", "cube.off"], "-g", "-d"),
        (&["tet", "-de", "cube.off"], "-e", "-d"),
        (&["tet", "-dC", "cube.off"], "-C", "-d"),
        (&["tet", "-pdq", "cube.off"], "-q", "-d"),
        (
            &["tet", "-d", "--stats-json", "s.json", "cube.off"],
            "--stats-json",
            "-d",
        ),
        (&["tet", "-O2", "p3"], "-O", "without -p or -r"),
        (&["tet", "-M", "p3"], "-M", "without -p or -r"),
        (
            &["tet", "--stats-json", "s.json", "p3"],
            "--stats-json",
            "without -p or -r",
        ),
        (
            &["tet", "-p", "--keep-ratio", "cube.off"],
            "--keep-ratio",
            "without -q",
        ),
        (
            &["tet", "-p", "--cells-vtu", "c.vtu", "cube.off"],
            "--cells-vtu",
            "with -p",
        ),
        (&["tet", "-rv", "cube.1"], "-v", "with -r"),
        (&["tet", "-rM", "cube.1"], "-M", "with -r"),
        (&["tet", "-p", "--cut", "x", "cube.off"], "--cut", "--png"),
        (
            &["tet", "-p", "--view", "10,20", "cube.off"],
            "--view",
            "--png",
        ),
        (&["tri", "-re", "face.1"], "-e", "with -r"),
        (&["tri", "-rn", "face.1"], "-n", "with -r"),
        (
            &["tri", "-r", "--vtu", "a.vtu", "face.1"],
            "-o/--vtu",
            "with -r",
        ),
        (
            &["tri", "-r", "--stats-json", "s.json", "face.1"],
            "--stats-json",
            "with -r",
        ),
        (
            &["tri", "-r", "--svg", "a.svg", "face.1"],
            "--svg",
            "with -r",
        ),
        (&["tri", "-ro2", "face.1"], "-o2", "with -r"),
        (&["tri", "-rv", "face.1"], "-v", "with -r"),
        (
            &["tri", "-p", "--threads", "2", "face.poly"],
            "--threads",
            "refinement",
        ),
        (&["tri", "--threads", "2", "p2"], "--threads", "refinement"),
        (
            &["tet", "-p", "--threads", "2", "cube.off"],
            "--threads",
            "only point sets",
        ),
        (
            &["tri", "-p", "--svg-quality", "face.poly"],
            "--svg-quality",
            "--svg",
        ),
        (&["tri", "--png-width", "100", "p2"], "--png-width", "--svg"),
    ];
    for (args, switch, why) in rows {
        let before = snapshot(&dir);
        let out = run(&dir, args);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(
            err.contains(&format!("{switch} has no effect")) && err.contains(why),
            "{args:?}: {err}"
        );
        assert!(snapshot(&dir) == before, "{args:?} wrote files");
    }
    // -P is honoured where a .poly would be written: -r and plain -c.
    let out = run(&dir, &["tri", "-rqPQ", "face.1"]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(dir.join("face.2.node").is_file() && !dir.join("face.2.poly").exists());
    let out = run(&dir, &["tri", "-cPQ", "p2"]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(dir.join("p2.1.ele").is_file() && !dir.join("p2.1.poly").exists());
    let out = run(&dir, &["tri", "-cQ", "p2"]);
    assert!(out.status.success() && dir.join("p2.1.poly").is_file());
}

/// Scientific notation in switch numbers, and `e`/`E` as switches after a
/// number: the exponent belongs to the number only when a digit (or a sign
/// and a digit) follows.
#[test]
fn scientific_notation_in_switches() {
    let dir = tmp("sci");
    std::fs::write(dir.join("face.poly"), SQUARE_POLY).unwrap();
    std::fs::write(dir.join("cube.off"), CUBE_OFF).unwrap();
    let ok = |args: &[&str]| {
        let out = run(&dir, args);
        assert!(out.status.success(), "{args:?}: {}", stderr(&out));
        stdout(&out)
    };
    let count = |f: &str| ele_count(&dir.join(f));
    // tri -a1e-1 is -a0.1: the same mesh.
    ok(&["tri", "-pa1e-1Q", "face.poly"]);
    let a = std::fs::read(dir.join("face.1.ele")).unwrap();
    ok(&["tri", "-pa0.1Q", "face.poly"]);
    assert_eq!(a, std::fs::read(dir.join("face.1.ele")).unwrap());
    ok(&["tri", "-pq2.5E1a1E-1Q", "face.poly"]);
    assert!(count("face.1.ele") > 8);
    // -pq1.2e: q1.2 then -e (edges); -pq30ea1e-1: q30, -e, a0.1.
    let _ = std::fs::remove_file(dir.join("face.1.edge"));
    ok(&["tri", "-pq20eQ", "face.poly"]);
    assert!(dir.join("face.1.edge").is_file());
    let _ = std::fs::remove_file(dir.join("face.1.edge"));
    ok(&["tri", "-pq20ea1e-1Q", "face.poly"]);
    assert!(dir.join("face.1.edge").is_file());
    // -pq20E: -E (no .ele).
    let _ = std::fs::remove_file(dir.join("face.1.ele"));
    ok(&["tri", "-pq20EQ", "face.poly"]);
    assert!(!dir.join("face.1.ele").exists());
    // tet: -q1.2/1e1, -a1e-3, -pq1.2a1E-3; -pq1.2e is q1.2 then -e.
    ok(&["tet", "-pq1.2/1e1Q", "cube.off"]);
    ok(&["tet", "-pa1e-2Q", "cube.off"]);
    let n1 = count("cube.1.ele");
    ok(&["tet", "-pa0.01Q", "cube.off"]);
    assert_eq!(n1, count("cube.1.ele"));
    assert!(n1 >= 100, "{n1} tetrahedra for volume bound 0.01");
    ok(&["tet", "-pq1.2a1E-2Q", "cube.off"]);
    let _ = std::fs::remove_file(dir.join("cube.1.edge"));
    ok(&["tet", "-pq1.2eQ", "cube.off"]);
    assert!(dir.join("cube.1.edge").is_file());
    // An exponent without digits is no exponent: `-a1e+` is -a1, -e, then
    // the unknown switch -+; a second exponent is not a number.
    let out = run(&dir, &["tri", "-pa1e+Q", "face.poly"]);
    assert!(
        stderr(&out).contains("unknown switch -+"),
        "{}",
        stderr(&out)
    );
    let out = run(&dir, &["tri", "-pq1e1e1", "face.poly"]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
}

/// The cube as a 1-based TetGen .poly with one more facet, `extra`
/// (a facet line and polygon), over 9 points (point 9 at `p9`).
fn cube_poly(p9: &str, extra: &str, holes: &str) -> String {
    let mut s = String::from(
        "9 3 0 0\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 0 0 1\n6 1 0 1\n7 1 1 1\n8 0 1 1\n",
    );
    s += &format!("9 {p9}\n");
    let facets = [
        "4 1 2 3 4",
        "4 5 6 7 8",
        "4 1 2 6 5",
        "4 2 3 7 6",
        "4 3 4 8 7",
        "4 4 1 5 8",
    ];
    s += &format!("{} 0\n", facets.len() + usize::from(!extra.is_empty()));
    for f in facets {
        s += &format!("1\n{f}\n");
    }
    if !extra.is_empty() {
        s += &format!("1\n{extra}\n");
    }
    s += holes;
    s += "0\n";
    s
}

/// `tet -d`: exit 1 on any finding, degenerate facets reported (not
/// fatal), numbering as the file's and as `-p`'s.
#[test]
fn tet_d_findings_and_numbering() {
    let dir = tmp("tetd");
    let d = |args: &[&str]| {
        let out = run(&dir, args);
        (out.status.code(), stdout(&out), stderr(&out))
    };
    // Clean: exit 0.
    std::fs::write(dir.join("cube.off"), CUBE_OFF).unwrap();
    let (code, out, _) = d(&["tet", "-d", "cube.off"]);
    assert_eq!(code, Some(0), "{out}");
    // Open: the cube without its last triangle.
    let open = CUBE_OFF
        .replacen("8 12 0", "8 11 0", 1)
        .replacen("3 1 6 5\n", "", 1);
    std::fs::write(dir.join("open.off"), open).unwrap();
    let (code, out, _) = d(&["tet", "-d", "open.off"]);
    assert_eq!(code, Some(1), "{out}");
    assert!(out.contains("edge 1-5 has only one facet"), "{out}");
    // Non-manifold: a fin on edge 0-1.
    let fin =
        CUBE_OFF
            .replacen("8 12 0", "9 13 0", 1)
            .replacen("0 1 1\n3", "0 1 1\n0.5 -1 0.5\n3", 1)
            + "3 0 1 8\n";
    std::fs::write(dir.join("fin.off"), fin).unwrap();
    let (code, out, _) = d(&["tet", "-d", "fin.off"]);
    assert_eq!(code, Some(1), "{out}");
    assert!(out.contains("edge 0-1 has more than two facets"), "{out}");
    // -Q: the exit code alone, a count on stderr.
    let (code, out, err) = d(&["tet", "-dQ", "fin.off"]);
    assert_eq!((code, out.is_empty()), (Some(1), true), "{err}");
    // Zero area: OFF facet 12 (0-based, as the file and -p count).
    let zero = CUBE_OFF
        .replacen("8 12 0", "9 13 0", 1)
        .replacen("0 1 1\n3", "0 1 1\n2 0 0\n3", 1)
        + "3 0 1 8\n";
    std::fs::write(dir.join("zero.off"), zero).unwrap();
    let (code, out, err) = d(&["tet", "-d", "zero.off"]);
    assert_eq!(code, Some(1), "{out}{err}");
    assert!(out.contains("facet 12 has zero area"), "{out}");
    let (code, _, err) = d(&["tet", "-p", "zero.off"]);
    assert_eq!(code, Some(1));
    assert!(err.contains("facet 12 has zero area"), "{err}");
    // A 1-based .poly: facet 7 (its 7th facet) in both.
    std::fs::write(dir.join("z.poly"), cube_poly("0.5 0 0", "3 1 9 2", "0\n")).unwrap();
    let (code, out, err) = d(&["tet", "-d", "z.poly"]);
    assert_eq!(code, Some(1), "{out}{err}");
    assert!(out.contains("facet 7 has zero area"), "{out}");
    let (code, _, err) = d(&["tet", "-p", "z.poly"]);
    assert_eq!(code, Some(1));
    assert!(err.contains("facet 7 has zero area"), "{err}");
    // A repeated point, named as the file names it.
    std::fs::write(
        dir.join("r.poly"),
        cube_poly("0.5 0.5 0", "4 1 2 3 2", "0\n"),
    )
    .unwrap();
    let (_, _, err) = d(&["tet", "-p", "r.poly"]);
    assert!(err.contains("facet 7 repeats point 2"), "{err}");
}

/// An empty mesh from a non-empty input is an error saying why.
#[test]
fn empty_results_are_errors() {
    let dir = tmp("empty");
    let files = [
        // box.poly's shape: an open outer boundary.
        ("box.poly", "8 2 0 0\n1 0 0\n2 0 3\n3 3 0\n4 3 3\n5 1 1\n6 1 2\n7 2 1\n8 2 2\n5 0\n1 1 2\n2 5 7\n3 7 8\n4 8 6\n5 6 5\n1\n1 1.5 1.5\n", "segment 1's endpoint 1"),
        ("hseg.poly", "4 2 0 0\n1 0 0\n2 4 0\n3 4 4\n4 0 4\n4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n1\n1 2 0\n", "hole 1 at (2, 0) lies on segment 1"),
        ("noseg.poly", "4 2 0 0\n1 0 0\n2 4 0\n3 4 4\n4 0 4\n0 0\n0\n", "no segments"),
    ];
    for (name, text, why) in files {
        std::fs::write(dir.join(name), text).unwrap();
        let before = snapshot(&dir);
        let out = run(&dir, &["tri", "-p", name]);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(1), "{name}: {err}");
        assert!(
            err.contains("no triangle left after carving") && err.contains(why),
            "{name}: {err}"
        );
        assert!(snapshot(&dir) == before, "{name}: files written");
        // -c keeps the hull where the boundary is at fault.
        if name != "hseg.poly" {
            assert!(err.contains("use -c"), "{err}");
            let out = run(&dir, &["tri", "-pcQ", name]);
            assert!(out.status.success(), "{name}: {}", stderr(&out));
        }
    }
    // tet: a hole point at the centre of a closed cube.
    std::fs::write(
        dir.join("hc.poly"),
        cube_poly("0.25 0.25 0.25", "", "1\n1 0.5 0.5 0.5\n"),
    )
    .unwrap();
    let out = run(&dir, &["tet", "-p", "hc.poly"]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("no tetrahedron left after carving")
            && err.contains("hole 1 at (0.5, 0.5, 0.5)"),
        "{err}"
    );
}

/// Errors about 1-based files use the file's numbering.
#[test]
fn errors_use_the_files_numbering() {
    let dir = tmp("numbering");
    let bad = "4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 99\n0\n";
    std::fs::write(dir.join("bad.poly"), bad).unwrap();
    let err = stderr(&run(&dir, &["tri", "-p", "bad.poly"]));
    assert!(err.contains("segment 4 names point 99"), "{err}");
    let zero_based = "4 2 0 0\n0 0 0\n1 1 0\n2 1 1\n3 0 1\n4 0\n0 0 1\n1 1 2\n2 2 3\n3 3 98\n0\n";
    std::fs::write(dir.join("bad0.poly"), zero_based).unwrap();
    let err = stderr(&run(&dir, &["tri", "-p", "bad0.poly"]));
    assert!(
        err.contains("segment 3 names point 98"),
        "{zero_based}\n{err}"
    );
    // tri -r: a 1-based mesh whose .poly names a missing point.
    std::fs::write(dir.join("m.node"), "4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n").unwrap();
    std::fs::write(dir.join("m.ele"), "2 3 0\n1 1 2 3\n2 1 3 4\n").unwrap();
    std::fs::write(dir.join("m.poly"), "0 2 0 0\n2 0\n1 1 2\n2 2 7\n0\n").unwrap();
    let err = stderr(&run(&dir, &["tri", "-rq", "m"]));
    assert!(
        err.contains("segment 2") && err.contains("point 7"),
        "{err}"
    );
}

/// `delone --help` names the commands and points to their full help;
/// `delone tri --help` documents -p and the switch rules.
#[test]
fn help_points_to_the_full_lists() {
    let dir = tmp("help");
    let main = stdout(&run(&dir, &["--help"]));
    assert!(main.contains("delone tri --help") && main.contains("delone tet --help"));
    assert!(main.contains("honoured or refused") && main.contains("scientific notation"));
    let tri = stdout(&run(&dir, &["tri", "--help"]));
    assert!(tri.lines().any(|l| l.starts_with("    -p ")), "{tri}");
    let tet = stdout(&run(&dir, &["tet", "--help"]));
    assert!(tet.contains("OFF/STL/PLY/OBJ from 0"), "{tet}");
}
