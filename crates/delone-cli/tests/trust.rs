//! The command line's own promises (issue 19): no output overwrites an
//! input, every switch is honoured or refused, `tet -d` exits 1 on any
//! finding, empty results are errors, numbers in switches may use
//! scientific notation, the help lists every switch, and errors use the
//! file's own numbering.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_delone");

/// A fresh, empty directory for one test.
fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("delone-trust-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn run(dir: &Path, args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run delone")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

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
            ("m.area", "2\n1 0.1\n2 0.1\n"),
        ],
        &["tri", "-ra", "m", "--stats-json", "m.area"],
        &["m.area", "--stats-json"],
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
