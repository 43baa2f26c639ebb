//! Triangle-compatible outputs of `delone tri -p` pinned on a hand-checked
//! example, plus the statistics and picture options.
//!
//! The input: the kite 1 (0,0), 2 (2,0), 3 (3,2), 4 (0,1) with segments 1-2
//! (marker 5), 2-3, 3-4, 4-1 (marker 0) and the diagonal 1-3 (marker 0),
//! point 4 with its own marker 7, one attribute per point, one region
//! (attribute 2.5) in triangle 1-3-4. The diagonal forces the triangles
//! {1,2,3} and {1,3,4}. Triangle's rules give:
//! * vertex markers: 1 → 5 (on the marked segment), 2 → 5, 3 → 1 (boundary,
//!   only unmarked segments), 4 → 7 (its own);
//! * edge markers: 1-2 → 5, 2-3, 3-4, 4-1 → 1 (boundary), 1-3 → 0.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_delone");

const KITE: &str = "4 2 1 1
1 0 0 10 0
2 2 0 20 0
3 3 2 30 0
4 0 1 40 7
5 1
1 1 2 5
2 2 3 0
3 3 4 0
4 4 1 0
5 1 3 0
0
1
1 1 1.2 2.5 -1
";

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("delone-triout-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    std::fs::write(d.join("kite.poly"), KITE).unwrap();
    d
}

fn run(dir: &Path, args: &[&str]) -> Output {
    let o = Command::new(BIN)
        .arg("tri")
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run delone");
    assert!(
        o.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    o
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

/// Triangle corners as a rotation-normalised key (smallest first).
fn canon(t: &[usize]) -> [usize; 3] {
    let k = (0..3).min_by_key(|&i| t[i]).unwrap();
    [t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
}

#[test]
fn node_ele_edge_poly_neigh_follow_triangle() {
    let d = tmp("basic");
    run(&d, &["-pAenQ", "kite.poly"]);
    // .node: 4 points, 1 attribute, markers.
    let node = rows(&d, "kite.1.node");
    assert_eq!(node[0], vec![4.0, 2.0, 1.0, 1.0]);
    let markers: Vec<i64> = node[1..].iter().map(|r| r[4] as i64).collect();
    assert_eq!(markers, vec![5, 5, 1, 7]);
    let attrs: Vec<f64> = node[1..].iter().map(|r| r[3]).collect();
    assert_eq!(attrs, vec![10.0, 20.0, 30.0, 40.0]);
    // .ele: two counterclockwise triangles, numbered from 1, with the
    // regional attribute (-A).
    let ele = rows(&d, "kite.1.ele");
    assert_eq!(ele[0], vec![2.0, 3.0, 1.0]);
    let mut tris = BTreeMap::new();
    for r in &ele[1..] {
        let c: Vec<usize> = r[1..4].iter().map(|&x| x as usize).collect();
        tris.insert(canon(&c), r[4]);
    }
    assert_eq!(tris.get(&[1, 2, 3]), Some(&0.0), "{tris:?}");
    assert_eq!(tris.get(&[1, 3, 4]), Some(&2.5), "{tris:?}");
    // .edge: 5 edges with Triangle's markers.
    let edge = rows(&d, "kite.1.edge");
    assert_eq!(edge[0], vec![5.0, 1.0]);
    let em: BTreeMap<(usize, usize), i64> = edge[1..]
        .iter()
        .map(|r| {
            let (a, b) = (r[1] as usize, r[2] as usize);
            ((a.min(b), a.max(b)), r[3] as i64)
        })
        .collect();
    let want: BTreeMap<(usize, usize), i64> = [
        ((1, 2), 5),
        ((2, 3), 1),
        ((3, 4), 1),
        ((1, 4), 1),
        ((1, 3), 0),
    ]
    .into_iter()
    .collect();
    assert_eq!(em, want);
    // .poly: no points, the 5 segments with the same markers, no holes,
    // the region.
    let poly = rows(&d, "kite.1.poly");
    assert_eq!(poly[0], vec![0.0, 2.0, 0.0, 1.0]);
    assert_eq!(poly[1], vec![5.0, 1.0]);
    let pm: BTreeMap<(usize, usize), i64> = poly[2..7]
        .iter()
        .map(|r| {
            let (a, b) = (r[1] as usize, r[2] as usize);
            ((a.min(b), a.max(b)), r[3] as i64)
        })
        .collect();
    assert_eq!(pm, want);
    assert_eq!(poly[7], vec![0.0]);
    assert_eq!(poly[8], vec![1.0]);
    assert_eq!(poly[9], vec![1.0, 1.0, 1.2, 2.5, -1.0]);
    // .neigh: each triangle sees the other across the diagonal only.
    let neigh = rows(&d, "kite.1.neigh");
    assert_eq!(neigh[0], vec![2.0, 3.0]);
    for (i, r) in neigh[1..].iter().enumerate() {
        let other = if i == 0 { 2.0 } else { 1.0 };
        let mut n = r[1..].to_vec();
        n.sort_by(f64::total_cmp);
        assert_eq!(n, vec![-1.0, -1.0, other]);
    }
}

#[test]
fn zero_based_no_markers_and_suppressed_files() {
    let d = tmp("zb");
    run(&d, &["-pzBPEQ", "-e", "kite.poly"]);
    let node = rows(&d, "kite.1.node");
    assert_eq!(node[0], vec![4.0, 2.0, 1.0, 0.0]);
    assert_eq!(node[1], vec![0.0, 0.0, 0.0, 10.0]);
    assert_eq!(node[4], vec![3.0, 0.0, 1.0, 40.0]);
    let edge = rows(&d, "kite.1.edge");
    assert_eq!(edge[0], vec![5.0, 0.0]);
    assert!(edge[1..].iter().all(|r| r.len() == 3 && r[0] < 5.0));
    assert!(edge[1..].iter().any(|r| r[1] == 0.0 || r[2] == 0.0));
    assert!(!d.join("kite.1.poly").exists());
    assert!(!d.join("kite.1.ele").exists());
    std::fs::remove_file(d.join("kite.1.node")).unwrap();
    run(&d, &["-pNQ", "kite.poly"]);
    assert!(!d.join("kite.1.node").exists());
}

#[test]
fn second_order_nodes_and_vtu() {
    let d = tmp("o2");
    run(&d, &["-po2Q", "--vtu-ascii", "kite.poly"]);
    let node = rows(&d, "kite.1.node");
    // 4 corners + 5 edge midpoints.
    assert_eq!(node[0], vec![9.0, 2.0, 1.0, 1.0]);
    let pt = |i: usize| [node[i][1], node[i][2]];
    let attr = |i: usize| node[i][3];
    let mark = |i: usize| node[i][4] as i64;
    let ele = rows(&d, "kite.1.ele");
    assert_eq!(ele[0], vec![2.0, 6.0, 0.0]);
    let mut seen = std::collections::BTreeSet::new();
    for r in &ele[1..] {
        let v: Vec<usize> = r[1..7].iter().map(|&x| x as usize).collect();
        for k in 0..3 {
            // Node 4+k is the midpoint of the edge opposite corner k.
            let (a, b, m) = (v[(k + 1) % 3], v[(k + 2) % 3], v[3 + k]);
            assert_eq!(
                pt(m),
                [0.5 * (pt(a)[0] + pt(b)[0]), 0.5 * (pt(a)[1] + pt(b)[1])]
            );
            assert_eq!(attr(m), 0.5 * (attr(a) + attr(b)));
            // Midpoint markers: the edge's marker.
            let want = match (a.min(b), a.max(b)) {
                (1, 2) => 5,
                (1, 3) => 0,
                _ => 1,
            };
            assert_eq!(mark(m), want, "midpoint of {a}-{b}");
            assert!(m > 4);
            seen.insert(m);
        }
    }
    assert_eq!(seen.len(), 5, "the diagonal's midpoint is shared");
    let vtu = std::fs::read_to_string(d.join("kite.1.vtu")).unwrap();
    assert!(
        vtu.contains("NumberOfPoints=\"9\" NumberOfCells=\"2\""),
        "{vtu}"
    );
    assert!(vtu.contains("\n22 22 \n"), "{vtu}");
}

#[test]
fn steiner_points_get_interpolated_attributes_and_segment_markers() {
    let d = tmp("q");
    run(&d, &["-pq30a0.05Q", "--warn-unmet", "kite.poly"]);
    let node = rows(&d, "kite.1.node");
    let n = node[0][0] as usize;
    assert!(n > 20, "the area bound needs Steiner points");
    // Attributes are linear in the input (10, 20, 30, 40 at the corners)
    // only inside each triangle of the unrefined mesh; check the bounds and
    // exact linearity on the marked segment 1-2 (y = 0: attribute 10 + 5x).
    for r in &node[1..] {
        let (x, y, a, m) = (r[1], r[2], r[3], r[4] as i64);
        assert!((10.0..=40.0).contains(&a), "{r:?}");
        if y == 0.0 && x > 0.0 && x < 2.0 {
            assert!((a - (10.0 + 5.0 * x)).abs() < 1e-9, "{r:?}");
            assert_eq!(m, 5, "{r:?}");
        }
    }
}

#[test]
fn stats_json_and_png() {
    let d = tmp("pics");
    let out = run(
        &d,
        &[
            "-pqV",
            "--warn-unmet",
            "--stats-json",
            "s.json",
            "--png",
            "k.png",
            "--png-width",
            "100",
            "--svg",
            "k.svg",
            "--svg-quality",
            "kite.poly",
        ],
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("Angle histogram"), "{text}");
    let j = std::fs::read_to_string(d.join("s.json")).unwrap();
    let ele = rows(&d, "kite.1.ele");
    assert!(j.contains(&format!("\"triangles\": {},", ele[0][0])), "{j}");
    assert!(j.contains("\"steiner_points\": {\"crossings\": 0"), "{j}");
    let png = std::fs::read(d.join("k.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    // IHDR: width = 100 + 2 × 10 px margin.
    assert_eq!(u32::from_be_bytes(png[16..20].try_into().unwrap()), 120);
    let svg = std::fs::read_to_string(d.join("k.svg")).unwrap();
    assert!(svg.contains("<text"), "the quality legend");
}

#[test]
fn voronoi_and_lloyd_pictures_as_png_and_help() {
    let d = tmp("vor");
    let mut s = String::from("30 2 0 0\n");
    let mut x = 12345u64;
    for i in 0..30 {
        x = x
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let a = (x >> 11) as f64 / (1u64 << 53) as f64;
        x = x
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let b = (x >> 11) as f64 / (1u64 << 53) as f64;
        s += &format!("{} {a} {b}\n", i + 1);
    }
    std::fs::write(d.join("pts.node"), s).unwrap();
    run(
        &d,
        &[
            "-vQ",
            "--lloyd",
            "2",
            "--png",
            "v.png",
            "--png-width",
            "64",
            "pts",
        ],
    );
    let png = std::fs::read(d.join("v.png")).unwrap();
    assert_eq!(u32::from_be_bytes(png[16..20].try_into().unwrap()), 84);
    let out = run(&d, &["-V", "--stats-json", "p.json", "-o2", "pts"]);
    assert!(String::from_utf8_lossy(&out.stdout).contains("Smallest angle"));
    let j = std::fs::read_to_string(d.join("p.json")).unwrap();
    assert!(j.contains("\"steiner_points\": null"), "{j}");
    let ele = rows(&d, "pts.1.ele");
    assert_eq!(ele[0][1], 6.0);
    let help = run(&d, &["--help"]);
    let h = String::from_utf8_lossy(&help.stdout);
    for l in [
        "-o2",
        "-P",
        "--png",
        "--png-width",
        "--svg-quality",
        "--stats-json",
    ] {
        assert!(h.contains(&format!("    {l} ")), "help lacks {l}");
    }
}

#[test]
fn crossing_vertices_interpolate_along_their_segment() {
    let d = tmp("cross");
    // Segments 1-3 and 2-4 of the square cross at (1, 1); the attribute
    // x + 2y is linear, so interpolating along either segment gives 3.
    std::fs::write(
        d.join("x.poly"),
        "4 2 1 0\n1 0 0 0\n2 2 0 2\n3 2 2 6\n4 0 2 4\n2 1\n1 1 3 4\n2 2 4 6\n0\n",
    )
    .unwrap();
    run(&d, &["-pcQ", "x.poly"]);
    let node = rows(&d, "x.1.node");
    assert_eq!(node[0], vec![5.0, 2.0, 1.0, 1.0]);
    assert_eq!(node[5][..4], [5.0, 1.0, 1.0, 3.0]);
    // On both marked segments: one of their markers.
    assert!(node[5][4] == 4.0 || node[5][4] == 6.0, "{:?}", node[5]);
    // The hull corners: on a marked segment (4 or 6), never 1.
    assert_eq!(node[1][4], 4.0);
    assert_eq!(node[2][4], 6.0);
}
