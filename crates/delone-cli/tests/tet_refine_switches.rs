//! `delone tet` refinement switches that must be honoured: the volume bound
//! `-a` on every tetrahedron, `-pqY` (refinement keeping the recovered
//! surface), `-pcq` (refinement of the kept convex hull); the report's
//! counts are checked against a recount from the written mesh.

use std::collections::{BTreeSet, HashMap};
use std::path::{Path, PathBuf};
use std::process::Output;

mod common;
use common::{run, tmp};

/// `run`, with `--warn-unmet` when the switches ask for a -q ratio: these
/// tests are about the volume bound, -Y and -c, not the ratio's exit code 3.
fn runq(dir: &Path, args: &[&str]) -> Output {
    let mut a = args.to_vec();
    if a.get(1).is_some_and(|s| s.contains('q')) {
        a.insert(2, "--warn-unmet");
    }
    run(dir, &a)
}

fn ok(o: &Output) -> String {
    let out = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(
        o.status.success(),
        "{out}\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(
        out.contains("check (-C):") && !out.contains("check FAILED"),
        "{out}"
    );
    out
}

/// The rows of a TetGen output file (header skipped), as numbers.
fn table(path: &Path) -> Vec<Vec<f64>> {
    std::fs::read_to_string(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .lines()
        .skip(1)
        .map(|l| l.split('#').next().unwrap_or(""))
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.split_whitespace().map(|t| t.parse().unwrap()).collect())
        .collect()
}

type P = [f64; 3];

/// Points and tetrahedra (0-based) of `base.node` / `base.ele`, and the
/// tetrahedra's first attribute when written.
fn mesh(dir: &Path, base: &str) -> (Vec<P>, Vec<[usize; 4]>, Vec<f64>) {
    let nodes = table(&dir.join(format!("{base}.node")));
    let first = nodes[0][0] as usize;
    let pts = nodes.iter().map(|r| [r[1], r[2], r[3]]).collect();
    let ele = table(&dir.join(format!("{base}.ele")));
    let tets = ele
        .iter()
        .map(|r| std::array::from_fn(|k| r[k + 1] as usize - first))
        .collect();
    let attr = ele
        .iter()
        .map(|r| r.get(5).copied().unwrap_or(0.0))
        .collect();
    (pts, tets, attr)
}

fn sub(a: &P, b: &P) -> P {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: &P, b: &P) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: &P, b: &P) -> P {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Volume and radius-edge ratio of a tetrahedron (computed here, not by
/// the library).
fn measure(p: [&P; 4]) -> (f64, f64) {
    let (u, v, w) = (sub(p[1], p[0]), sub(p[2], p[0]), sub(p[3], p[0]));
    let det = dot(&u, &cross(&v, &w));
    let (a, b, c) = (cross(&v, &w), cross(&w, &u), cross(&u, &v));
    let x: P =
        std::array::from_fn(|k| dot(&u, &u) * a[k] + dot(&v, &v) * b[k] + dot(&w, &w) * c[k]);
    let r = dot(&x, &x).sqrt() / (2.0 * det.abs());
    let e = [u, v, w, sub(p[2], p[1]), sub(p[3], p[1]), sub(p[3], p[2])];
    let lmin = e
        .iter()
        .map(|e| dot(e, e).sqrt())
        .fold(f64::INFINITY, f64::min);
    (det.abs() / 6.0, r / lmin)
}

/// (tetrahedra above `ratio`, above `volume`, largest volume, total volume)
/// recounted from the written mesh.
fn recount(pts: &[P], tets: &[[usize; 4]], ratio: f64, volume: f64) -> (usize, usize, f64, f64) {
    let (mut r, mut v, mut big, mut tot) = (0, 0, 0.0f64, 0.0);
    for t in tets {
        let (vol, q) = measure(t.map(|i| &pts[i]));
        r += (q > ratio) as usize;
        v += (vol > volume) as usize;
        big = big.max(vol);
        tot += vol;
    }
    (r, v, big, tot)
}

/// The number before `what` on the `bounds (final mesh):` line.
fn reported(out: &str, what: &str) -> usize {
    let line = out
        .lines()
        .find(|l| l.contains("bounds (final mesh):"))
        .unwrap_or_else(|| panic!("no bounds line in\n{out}"));
    let i = line
        .find(what)
        .unwrap_or_else(|| panic!("no '{what}' in {line}"));
    line[..i]
        .split([':', ';'])
        .next_back()
        .unwrap()
        .trim()
        .parse()
        .unwrap_or_else(|e| panic!("{line}: {e}"))
}

/// The boundary faces of a tetrahedral mesh (faces of one tetrahedron
/// only), by the coordinates of their vertices.
fn boundary(pts: &[P], tets: &[[usize; 4]]) -> BTreeSet<[[u64; 3]; 3]> {
    let mut count: HashMap<[usize; 3], usize> = HashMap::new();
    for t in tets {
        for skip in 0..4 {
            let mut f = [0; 3];
            let mut k = 0;
            for (i, &q) in t.iter().enumerate() {
                if i != skip {
                    f[k] = q;
                    k += 1;
                }
            }
            f.sort_unstable();
            *count.entry(f).or_default() += 1;
        }
    }
    count
        .into_iter()
        .filter(|e| e.1 == 1)
        .map(|(f, _)| {
            let mut c = f.map(|q| pts[q].map(f64::to_bits));
            c.sort_unstable();
            c
        })
        .collect()
}

/// A 2-degree wedge (as the corpus' td_wedge_2): its cells are left by the
/// quality rules near the sharp edge, which must not stop `-a`.
const WEDGE: &str = "6 3 0 0
0 0 0 0
1 0 1 0
2 1 0 0
3 1 1 0
4 1 0 0.034899496702500969
5 1 1 0.034899496702500969
5 1
4 0 2 3 1 1
4 0 4 5 1 2
3 0 2 4 3
3 1 3 5 4
4 2 3 5 4 5
0
0
";

#[test]
fn volume_bound_is_met_on_every_tetrahedron_and_reported_truly() {
    let dir = tmp("wedge");
    std::fs::write(dir.join("w.smesh"), WEDGE).unwrap();
    for (sw, ratio) in [("-pa0.001VC", f64::INFINITY), ("-pq1.414a0.0005VC", 1.414)] {
        let out = ok(&runq(&dir, &["tet", sw, "w.smesh"]));
        let bound = if ratio.is_finite() { 0.0005 } else { 0.001 };
        let (pts, tets, _) = mesh(&dir, "w.1");
        let (above_r, above_v, big, tot) = recount(&pts, &tets, ratio, bound);
        assert!(big <= bound, "{sw}: largest volume {big} in\n{out}");
        assert_eq!(above_v, 0, "{sw}");
        assert_eq!(reported(&out, "tetrahedra above the volume bound"), above_v);
        if ratio.is_finite() {
            assert_eq!(
                reported(&out, "tetrahedra above the radius-edge bound"),
                above_r,
                "{out}"
            );
        }
        assert!((tot - 2f64.to_radians().sin() / 2.0).abs() < 1e-12);
    }
}

/// `shared/data/<sub>` (None: the corpus is opted out with
/// `DELONE_NO_CORPUS=1`; missing, it fails the test).
fn corpus(sub: &str) -> Option<PathBuf> {
    delone_testdata::corpus_path(env!("CARGO_MANIFEST_DIR"), sub)
}

#[test]
fn volume_bound_on_the_corpus_plcs() {
    let Some(data) = corpus("3d_plc") else {
        return;
    };
    let dir = tmp("tdplc");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&data)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.file_name().unwrap().to_str().unwrap().starts_with("td_"))
        .collect();
    files.sort();
    assert!(files.len() >= 17);
    for f in files {
        let stem = f.file_stem().unwrap().to_str().unwrap().to_string();
        for (sw, ratio, bound) in [
            ("-pa0.001VC", f64::INFINITY, 0.001),
            ("-pq1.414a0.0002VC", 1.414, 0.0002),
        ] {
            let out = ok(&runq(
                &dir,
                &["tet", sw, "--output-dir", ".", f.to_str().unwrap()],
            ));
            let (pts, tets, _) = mesh(&dir, &format!("{stem}.1"));
            let (above_r, above_v, big, _) = recount(&pts, &tets, ratio, bound);
            assert!(big <= bound, "{stem} {sw}: largest volume {big}");
            assert_eq!(above_v, 0);
            assert_eq!(reported(&out, "tetrahedra above the volume bound"), 0);
            if ratio.is_finite() {
                assert_eq!(
                    reported(&out, "tetrahedra above the radius-edge bound"),
                    above_r,
                    "{stem}"
                );
            }
        }
    }
}

#[test]
fn pqy_keeps_the_recovered_surface_and_improves_the_inside() {
    let Some(data) = corpus("surf/off") else {
        return;
    };
    let dir = tmp("pqy");
    for m in ["cgal_eight", "cgal_knot", "c3d_spot"] {
        let f = data.join(format!("{m}.off"));
        let f = f.to_str().unwrap();
        let out = ok(&runq(&dir, &["tet", "-pYC", "--output-dir", ".", f]));
        let (p0, t0, _) = mesh(&dir, &format!("{m}.1"));
        let surface = boundary(&p0, &t0);
        let (bad0, ..) = recount(&p0, &t0, 2.0, f64::INFINITY);
        let out = ok(&runq(&dir, &["tet", "-pqYVC", "--output-dir", ".", f])) + &out;
        let (p1, t1, _) = mesh(&dir, &format!("{m}.1"));
        // Same boundary faces: no point put on the surface.
        assert_eq!(boundary(&p1, &t1), surface, "{m}");
        let (bad1, ..) = recount(&p1, &t1, 2.0, f64::INFINITY);
        assert!(bad1 < bad0, "{m}: {bad0} -> {bad1}");
        assert_eq!(
            reported(&out, "tetrahedra above the radius-edge bound"),
            bad1,
            "{m}"
        );
        // With a volume bound too: it is met on every tetrahedron.
        let out = ok(&runq(
            &dir,
            &["tet", "-pqYa0.0005VC", "--output-dir", ".", f],
        ));
        let (p2, t2, _) = mesh(&dir, &format!("{m}.1"));
        assert_eq!(boundary(&p2, &t2), surface, "{m}");
        let (_, above_v, big, _) = recount(&p2, &t2, 2.0, 0.0005);
        assert!(big <= 0.0005 && above_v == 0, "{m}: {big}");
        assert_eq!(reported(&out, "tetrahedra above the volume bound"), 0);
    }
}

#[test]
fn pqy_on_a_cube_adds_no_surface_point() {
    // A cube whose surface is fine for -Y: refinement with a tight ratio
    // adds interior points only.
    let dir = tmp("cube");
    let mut s = String::from("8 3 0 0\n");
    for i in 0..8 {
        s += &format!("{i} {} {} {}\n", i & 1, (i >> 1) & 1, (i >> 2) & 1);
    }
    s += "6 0\n4 0 2 3 1\n4 4 5 7 6\n4 0 1 5 4\n4 2 6 7 3\n4 0 4 6 2\n4 1 3 7 5\n0\n0\n";
    std::fs::write(dir.join("c.smesh"), s).unwrap();
    let out = ok(&runq(&dir, &["tet", "-pqYa0.01VC", "c.smesh"]));
    let (pts, tets, _) = mesh(&dir, "c.1");
    let b = boundary(&pts, &tets);
    // Every boundary face has its vertices at the cube's corners.
    for f in &b {
        for v in f {
            assert!(v
                .iter()
                .all(|&c| c == 0f64.to_bits() || c == 1f64.to_bits()));
        }
    }
    assert!(pts.len() > 8);
    let (above_r, above_v, big, tot) = recount(&pts, &tets, 2.0, 0.01);
    assert!(big <= 0.01 && above_v == 0);
    assert!((tot - 1.0).abs() < 1e-12);
    assert_eq!(
        reported(&out, "tetrahedra above the radius-edge bound"),
        above_r
    );
}

/// An L-shaped prism: the square [0,2]² less [1,2]², times [0,1]. Its
/// convex hull is the pentagon (0,0) (2,0) (2,1) (1,2) (0,2) times [0,1].
fn l_prism() -> String {
    let xy = [[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]];
    let mut s = String::from("12 3 0 0\n");
    for z in 0..2 {
        for (i, p) in xy.iter().enumerate() {
            s += &format!("{} {} {} {z}\n", 6 * z + i, p[0], p[1]);
        }
    }
    s += "8 1\n6 5 4 3 2 1 0 1\n6 6 7 8 9 10 11 2\n";
    for i in 0..6 {
        let j = (i + 1) % 6;
        s += &format!("4 {i} {j} {} {} 3\n", j + 6, i + 6);
    }
    s + "0\n0\n"
}

/// The volume of the convex hull of the L prism, from the shoelace formula
/// of its hull polygon (independent of the mesher).
fn l_hull_volume() -> f64 {
    let h = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [1.0, 2.0], [0.0, 2.0]];
    let mut a = 0.0;
    for i in 0..h.len() {
        let (p, q) = (h[i], h[(i + 1) % h.len()]);
        a += p[0] * q[1] - q[0] * p[1];
    }
    a / 2.0
}

#[test]
fn pcq_refines_the_whole_convex_hull() {
    let dir = tmp("pcq");
    std::fs::write(dir.join("l.smesh"), l_prism()).unwrap();
    let hull = l_hull_volume();
    assert_eq!(hull, 3.5);
    for (sw, bound) in [("-pcqAVC", f64::INFINITY), ("-pcq1.414a0.01AVC", 0.01)] {
        let out = ok(&runq(&dir, &["tet", sw, "l.smesh"]));
        let ratio = if bound.is_finite() { 1.414 } else { 2.0 };
        let (pts, tets, attr) = mesh(&dir, "l.1");
        let (above_r, above_v, _, tot) = recount(&pts, &tets, ratio, bound);
        assert!((tot - hull).abs() < 1e-9, "{sw}: volume {tot}");
        // The exterior (attribute 0) fills the notch, the inside the L.
        let ext: f64 = tets
            .iter()
            .zip(&attr)
            .filter(|(_, &a)| a == 0.0)
            .map(|(t, _)| measure(t.map(|i| &pts[i])).0)
            .sum();
        assert!((ext - 0.5).abs() < 1e-9, "{sw}: exterior {ext}");
        assert_eq!(
            reported(&out, "tetrahedra above the radius-edge bound"),
            above_r,
            "{out}"
        );
        assert_eq!(above_v, 0, "{sw}");
        // The hull facets are refined: points on the notch's hull face
        // x + y = 3 other than its corners.
        let on_hull = pts
            .iter()
            .filter(|p| (p[0] + p[1] - 3.0).abs() < 1e-12)
            .count();
        if bound.is_finite() {
            assert!(on_hull > 4, "{sw}: {on_hull} points on the hull face");
        }
    }
}

#[test]
fn pcq_on_a_corpus_model() {
    let Some(data) = corpus("surf/off") else {
        return;
    };
    let dir = tmp("pcqcorpus");
    let f = data.join("cgal_eight.off");
    let f = f.to_str().unwrap();
    let out = ok(&runq(&dir, &["tet", "-pcVC", "--output-dir", ".", f]));
    let (p0, t0, _) = mesh(&dir, "cgal_eight.1");
    let (.., v0) = recount(&p0, &t0, 2.0, f64::INFINITY);
    let out = ok(&runq(&dir, &["tet", "-pcqVC", "--output-dir", ".", f])) + &out;
    let (p1, t1, _) = mesh(&dir, "cgal_eight.1");
    let (above, .., v1) = recount(&p1, &t1, 2.0, f64::INFINITY);
    assert!((v1 - v0).abs() < 1e-9 * v0, "{v0} {v1}");
    assert_eq!(
        reported(&out, "tetrahedra above the radius-edge bound"),
        above
    );
}
