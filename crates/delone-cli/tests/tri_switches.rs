//! Triangle switches -D (conforming Delaunay), -Y / -YY (no segment splits),
//! -u (refused), -j (jettison unused vertices) and plain -c (hull as .poly),
//! pinned on small inputs.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_delone");

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("delone-triswitch-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn run(dir: &Path, args: &[&str]) -> Output {
    Command::new(BIN)
        .arg("tri")
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run delone")
}

fn ok(dir: &Path, args: &[&str]) -> String {
    let o = run(dir, args);
    assert!(
        o.status.success(),
        "{args:?}: {}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Data lines of a Triangle file as number rows (comments dropped).
fn rows(dir: &Path, name: &str) -> Vec<Vec<f64>> {
    let text = std::fs::read_to_string(dir.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
    text.lines()
        .map(|l| l.split('#').next().unwrap().trim())
        .filter(|l| !l.is_empty())
        .map(|l| l.split_whitespace().map(|x| x.parse().unwrap()).collect())
        .collect()
}

/// Points (by 1-based id) and triangles of FILE.node / FILE.ele.
fn mesh(dir: &Path, base: &str) -> (Vec<[f64; 2]>, Vec<[usize; 3]>) {
    let n = rows(dir, &format!("{base}.node"));
    let e = rows(dir, &format!("{base}.ele"));
    let pts = n[1..].iter().map(|r| [r[1], r[2]]).collect();
    let tris = e[1..]
        .iter()
        .map(|r| [r[1] as usize - 1, r[2] as usize - 1, r[3] as usize - 1])
        .collect();
    (pts, tris)
}

/// Independent check (floating point with a relative tolerance): no vertex
/// strictly inside any triangle's circumcircle.
fn assert_delaunay(pts: &[[f64; 2]], tris: &[[usize; 3]]) {
    for t in tris {
        let [a, b, c] = t.map(|v| pts[v]);
        let (bx, by, cx, cy) = (b[0] - a[0], b[1] - a[1], c[0] - a[0], c[1] - a[1]);
        let d = 2.0 * (bx * cy - by * cx);
        assert!(d > 0.0, "triangle {t:?} not counterclockwise");
        let (b2, c2) = (bx * bx + by * by, cx * cx + cy * cy);
        let o = [
            a[0] + (cy * b2 - by * c2) / d,
            a[1] + (bx * c2 - cx * b2) / d,
        ];
        let r2 = (a[0] - o[0]).powi(2) + (a[1] - o[1]).powi(2);
        for (i, p) in pts.iter().enumerate() {
            if t.contains(&i) {
                continue;
            }
            let d2 = (p[0] - o[0]).powi(2) + (p[1] - o[1]).powi(2);
            assert!(
                d2 >= r2 * (1.0 - 1e-9),
                "vertex {i} inside the circumcircle of {t:?}"
            );
        }
    }
}

/// A 10 x 1 rectangle cut lengthwise, a point just above the cut: its
/// constrained Delaunay triangulation is not Delaunay.
const THIN: &str = "7 2 0 0
1 0 0
2 10 0
3 10 1
4 0 1
5 0 0.5
6 10 0.5
7 5 0.6
7 0
1 1 2
2 2 6
3 6 3
4 3 4
5 4 5
6 5 1
7 5 6
0
";

#[test]
fn conforming_delaunay_d() {
    let d = tmp("D");
    std::fs::write(d.join("thin.poly"), THIN).unwrap();
    // Plain -p: not Delaunay (the cut's diametral circle holds vertex 7).
    ok(&d, &["-pQ", "thin.poly"]);
    let (p, t) = mesh(&d, "thin.1");
    assert_eq!(p.len(), 7);
    assert!(std::panic::catch_unwind(|| assert_delaunay(&p, &t)).is_err());
    // -pD: segments split until every triangle is Delaunay; no interior points.
    let out = ok(&d, &["-pDC", "thin.poly"]);
    assert!(
        out.contains("conforming Delaunay: every subsegment has an empty diametral circle"),
        "{out}"
    );
    assert!(out.contains("check: conforming Delaunay"), "{out}");
    assert!(out.contains("0 circumcentres"), "{out}");
    let (p, t) = mesh(&d, "thin.1");
    assert!(p.len() > 7);
    assert_delaunay(&p, &t);
    // Every Steiner point lies on an input segment (y = 0, 0.5 or 1, or x = 0 or 10).
    for q in &p[7..] {
        assert!(
            [0.0, 0.5, 1.0].contains(&q[1]) || q[0] == 0.0 || q[0] == 10.0,
            "{q:?} is not on a segment"
        );
    }
    // -pqD: quality and conforming Delaunay together.
    let out = ok(&d, &["-pq25DC", "thin.poly"]);
    assert!(out.contains("bounds met"), "{out}");
    let (p, t) = mesh(&d, "thin.1");
    assert_delaunay(&p, &t);
    // -D needs segments.
    let o = run(&d, &["-D", "thin.node"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("-D and -Y apply to segments"));
}

const SQUARE: &str = "4 2 0 0
1 0 0
2 4 0
3 4 4
4 0 4
4 0
1 1 2
2 2 3
3 3 4
4 4 1
0
";

#[test]
fn no_boundary_splits_y_yy() {
    let d = tmp("Y");
    std::fs::write(d.join("sq.poly"), SQUARE).unwrap();
    for sw in ["-pq30a0.5Y", "-pq30a0.5YY"] {
        // -Y leaves the triangles at the boundary above the area bound:
        // exit code 3, the message names -Y as the cause.
        let o = run(&d, &[sw, "sq.poly"]);
        let (out, err) = (
            String::from_utf8_lossy(&o.stdout).into_owned(),
            String::from_utf8_lossy(&o.stderr).into_owned(),
        );
        assert_eq!(o.status.code(), Some(3), "{sw}: {out}{err}");
        assert!(err.contains("-Y forbids splitting"), "{sw}: {err}");
        assert!(out.contains("0 on segments"), "{sw}: {out}");
        let poly = rows(&d, "sq.1.poly");
        assert_eq!(poly[1][0], 4.0, "{sw}: the boundary keeps its 4 segments");
        let (p, t) = mesh(&d, "sq.1");
        assert!(p.len() > 4);
        let area: f64 = t
            .iter()
            .map(|v| {
                let [a, b, c] = v.map(|i| p[i]);
                0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
            })
            .sum();
        assert!((area - 16.0).abs() < 1e-9);
        for q in &p[4..] {
            assert!(
                q[0] > 0.0 && q[0] < 4.0 && q[1] > 0.0 && q[1] < 4.0,
                "{sw}: {q:?}"
            );
        }
    }
    // Without -Y the boundary is split.
    ok(&d, &["-pq30a0.5", "sq.poly"]);
    assert!(rows(&d, "sq.1.poly")[1][0] > 4.0);
}

#[test]
fn user_test_is_refused_with_a_pointer_to_the_api() {
    let d = tmp("u");
    std::fs::write(d.join("sq.poly"), SQUARE).unwrap();
    let o = run(&d, &["-pqu", "sq.poly"]);
    assert_eq!(o.status.code(), Some(2));
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        e.contains("-u (user-defined triangle test) needs the library API refine_with"),
        "{e}"
    );
}

/// Five points, the fourth a duplicate of the second.
const DUP: &str = "5 2 1 0
1 0 0 10
2 2 0 20
3 0 2 30
4 2 0 40
5 2 2 50
";

#[test]
fn jettison_plain_and_convex_hull_poly() {
    let d = tmp("j");
    std::fs::write(d.join("a.node"), DUP).unwrap();
    let out = ok(&d, &["-jc", "a.node"]);
    assert!(
        out.contains("-j: 1 unused vertices left out of the .node"),
        "{out}"
    );
    assert_eq!(
        std::fs::read_to_string(d.join("a.1.node")).unwrap(),
        "4 2 1 1\n1 0 0 10 1\n2 2 0 20 1\n3 0 2 30 1\n4 2 2 50 1\n"
    );
    let ele = rows(&d, "a.1.ele");
    assert_eq!(ele[0][0], 2.0);
    let mut used: Vec<usize> = ele[1..]
        .iter()
        .flat_map(|r| r[1..4].iter().map(|&x| x as usize))
        .collect();
    used.sort();
    used.dedup();
    assert_eq!(used, vec![1, 2, 3, 4]);
    // -c: the convex hull as segments with marker 1, no holes.
    let poly = rows(&d, "a.1.poly");
    assert_eq!(poly[0], vec![0.0, 2.0, 0.0, 1.0]);
    assert_eq!(poly[1], vec![4.0, 1.0]);
    let mut segs: Vec<[usize; 2]> = poly[2..6]
        .iter()
        .map(|r| {
            assert_eq!(r[3], 1.0);
            let (a, b) = (r[1] as usize, r[2] as usize);
            [a.min(b), a.max(b)]
        })
        .collect();
    segs.sort();
    assert_eq!(segs, vec![[1, 2], [1, 3], [2, 4], [3, 4]]);
    assert_eq!(poly[6], vec![0.0]);
    // Without -j the duplicate stays (numbered as in the input).
    ok(&d, &["-Q", "a.node"]);
    assert_eq!(rows(&d, "a.1.node")[0][0], 5.0);
    assert!(!d.join("a.1.poly").exists() || std::fs::remove_file(d.join("a.1.poly")).is_ok());
}

/// A square with a square hole holding an isolated point (9), and point 10 a
/// duplicate of point 1.
const HOLE: &str = "10 2 0 0
1 0 0
2 6 0
3 6 6
4 0 6
5 2 2
6 4 2
7 4 4
8 2 4
9 3 3
10 0 0
8 0
1 1 2
2 2 3
3 3 4
4 4 1
5 5 6
6 6 7
7 7 8
8 8 5
1
1 2.5 3.5
";

#[test]
fn jettison_with_a_pslg() {
    let d = tmp("pj");
    std::fs::write(d.join("h.poly"), HOLE).unwrap();
    ok(&d, &["-pQ", "h.poly"]);
    assert_eq!(rows(&d, "h.1.node")[0][0], 10.0);
    let out = ok(&d, &["-pjeC", "h.poly"]);
    assert!(
        out.contains("-j: 2 unused vertices left out of the .node"),
        "{out}"
    );
    let node = rows(&d, "h.1.node");
    assert_eq!(node[0][0], 8.0);
    assert!(node[1..].iter().all(|r| !(r[1] == 3.0 && r[2] == 3.0)));
    let ele = rows(&d, "h.1.ele");
    assert_eq!(ele[0][0], 8.0);
    let mut used: Vec<usize> = ele[1..]
        .iter()
        .flat_map(|r| r[1..4].iter().map(|&x| x as usize))
        .collect();
    used.sort();
    used.dedup();
    assert_eq!(used, (1..=8).collect::<Vec<_>>());
    for f in ["h.1.poly", "h.1.edge"] {
        let r = rows(&d, f);
        let skip = if f.ends_with("poly") { 2 } else { 1 };
        let n = r[skip - 1][0] as usize;
        assert_eq!(n, if skip == 2 { 8 } else { 16 }, "{f}");
        for s in &r[skip..skip + n] {
            assert!(
                (1.0..=8.0).contains(&s[1]) && (1.0..=8.0).contains(&s[2]),
                "{f}: {s:?}"
            );
        }
    }
    // With refinement (Steiner points follow, renumbered after the dropped ones).
    ok(&d, &["-pjq30Q", "h.poly"]);
    let (p, t) = mesh(&d, "h.1");
    let mut used: Vec<usize> = t.iter().flatten().copied().collect();
    used.sort();
    used.dedup();
    assert_eq!(used, (0..p.len()).collect::<Vec<_>>());
}
