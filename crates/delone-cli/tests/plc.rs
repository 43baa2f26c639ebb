//! `delone tet -p`: closed PLCs and surface meshes.

use std::path::{Path, PathBuf};

mod common;
use common::{run, tmp};

/// A cube with a cubic cavity, as a TetGen .poly with quadrilateral facets
/// (markers 1 outside, 2 inside).
const CUBE_WITH_CAVITY: &str = "\
# outer cube, inner cavity
16 3 0 0
1 0 0 0
2 4 0 0
3 4 4 0
4 0 4 0
5 0 0 4
6 4 0 4
7 4 4 4
8 0 4 4
9 1 1 1
10 3 1 1
11 3 3 1
12 1 3 1
13 1 1 3
14 3 1 3
15 3 3 3
16 1 3 3
12 1
1 0 1
4 1 2 3 4
1 0 1
4 5 6 7 8
1 0 1
4 1 2 6 5
1 0 1
4 2 3 7 6
1 0 1
4 3 4 8 7
1 0 1
4 4 1 5 8
1 0 2
4 9 10 11 12
1 0 2
4 13 14 15 16
1 0 2
4 9 10 14 13
1 0 2
4 10 11 15 14
1 0 2
4 11 12 16 15
1 0 2
4 12 9 13 16
0
0
";

fn table(path: &Path) -> Vec<Vec<f64>> {
    let text = std::fs::read_to_string(path).unwrap();
    text.lines()
        .map(|l| l.split('#').next().unwrap_or(""))
        .filter(|l| !l.trim().is_empty())
        .skip(1)
        .map(|l| l.split_whitespace().map(|t| t.parse().unwrap()).collect())
        .collect()
}

#[test]
fn cube_with_cavity_poly() {
    let dir = tmp("cavity");
    std::fs::write(dir.join("box.poly"), CUBE_WITH_CAVITY).unwrap();
    let o = run(&dir, &["tet", "-pC", "box"]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "{out}\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(out.contains("volume preserved"), "{out}");
    // The mesh fills the shell: volume 64 - 8, computed here from the files.
    let nodes = table(&dir.join("box.1.node"));
    let ele = table(&dir.join("box.1.ele"));
    let p = |i: f64| &nodes[i as usize - 1][1..4];
    let vol: f64 = ele
        .iter()
        .map(|t| {
            let (a, b, c, d) = (p(t[1]), p(t[2]), p(t[3]), p(t[4]));
            let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
            let w = [d[0] - a[0], d[1] - a[1], d[2] - a[2]];
            (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
                + u[2] * (v[0] * w[1] - v[1] * w[0]))
                / 6.0
        })
        .sum();
    assert!((vol - 56.0).abs() < 1e-9, "volume {vol}");
    assert!(ele.iter().all(|t| {
        let (a, b, c, d) = (p(t[1]), p(t[2]), p(t[3]), p(t[4]));
        let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
        let w = [d[0] - a[0], d[1] - a[1], d[2] - a[2]];
        u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
            + u[2] * (v[0] * w[1] - v[1] * w[0])
            > 0.0
    }));
    // Boundary faces carry their facet's marker: 12 outer + 12 inner
    // triangles at least, markers 1 and 2.
    let face = table(&dir.join("box.1.face"));
    assert!(face.iter().any(|f| f[4] == 1.0) && face.iter().any(|f| f[4] == 2.0));
}

#[test]
fn cutaway_png_of_the_cavity_cube() {
    let dir = tmp("png");
    std::fs::write(dir.join("box.poly"), CUBE_WITH_CAVITY).unwrap();
    let o = run(
        &dir,
        &[
            "tet", "-pQ", "--png", "cut.png", "--cut", "y=0.4", "--view", "20,30", "box",
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let png = std::fs::read(dir.join("cut.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    // Same command, same bytes.
    let o = run(
        &dir,
        &[
            "tet", "-pQ", "--png", "cut2.png", "--cut", "y=0.4", "--view", "20,30", "box",
        ],
    );
    assert!(o.status.success());
    assert_eq!(png, std::fs::read(dir.join("cut2.png")).unwrap());
    // A bad cut is a usage error naming the option.
    let o = run(&dir, &["tet", "-p", "--png", "x.png", "--cut", "w", "box"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--cut"));
}

#[test]
fn open_surface_is_a_clear_error() {
    let dir = tmp("open");
    std::fs::write(
        dir.join("o.off"),
        "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1 3\n",
    )
    .unwrap();
    let o = run(&dir, &["tet", "-p", "o.off"]);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("not closed"), "{err}");
    let o = run(&dir, &["tet", "-p", "missing"]);
    assert_eq!(o.status.code(), Some(1));
}

#[test]
fn shared_plcs_recover_and_pass_the_check() {
    let Some(data) = delone_testdata::corpus_path(env!("CARGO_MANIFEST_DIR"), "3d_plc") else {
        return;
    };
    let dir = tmp("shared");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&data)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.retain(|p| p.extension().is_some_and(|e| e == "smesh"));
    files.sort();
    assert!(files.len() >= 17);
    for f in files {
        let o = run(
            &dir,
            &[
                "tet",
                "-pCQ",
                "--output-dir",
                dir.to_str().unwrap(),
                f.to_str().unwrap(),
            ],
        );
        assert!(
            o.status.success(),
            "{}: {}",
            f.display(),
            String::from_utf8_lossy(&o.stderr)
        );
    }
}

/// The unit cube with an isolated point 9 in the middle of its bottom
/// facet (in no facet polygon): it becomes a vertex of that facet.
const CUBE_POINT_ON_FACET: &str = "\
9 3 0 0
1 0 0 0
2 1 0 0
3 1 1 0
4 0 1 0
5 0 0 1
6 1 0 1
7 1 1 1
8 0 1 1
9 0.5 0.5 0
6 0
1
4 1 2 3 4
1
4 5 6 7 8
1
4 1 2 6 5
1
4 2 3 7 6
1
4 3 4 8 7
1
4 4 1 5 8
0
0
";

#[test]
fn isolated_point_on_a_facet_is_a_boundary_vertex() {
    let dir = tmp("pointonfacet");
    std::fs::write(dir.join("hc.poly"), CUBE_POINT_ON_FACET).unwrap();
    for sw in ["-pC", "-pMC", "-pYC", "-pqC"] {
        let o = run(&dir, &["tet", sw, "hc"]);
        let out = String::from_utf8_lossy(&o.stdout);
        assert!(
            o.status.success(),
            "{sw}: {out}\n{}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert!(out.contains("volume preserved"), "{sw}: {out}");
        // Point 9 is a corner of boundary faces (four at least).
        let face = table(&dir.join("hc.1.face"));
        let at9 = face.iter().filter(|f| f[1..4].contains(&9.0)).count();
        assert!(at9 >= 4, "{sw}: {at9} faces at point 9");
        for f in ["hc.1.node", "hc.1.ele", "hc.1.face"] {
            std::fs::remove_file(dir.join(f)).unwrap();
        }
    }
    // With a hole point inside, the only region is removed: an error
    // saying so, not a crash.
    let holed = CUBE_POINT_ON_FACET.replacen("\n0\n0\n", "\n1\n1 0.5 0.5 0.5\n0\n", 1);
    std::fs::write(dir.join("holed.poly"), holed).unwrap();
    let o = run(&dir, &["tet", "-pC", "holed"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("no tetrahedron left"), "{err}");
}
