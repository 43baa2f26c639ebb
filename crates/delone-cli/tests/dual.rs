//! End-to-end tests of `delone tri -v / -w / --lloyd / --svg` and
//! `delone tet -v`: the files are read back and checked against the library
//! and independent invariants.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use delone::geom::SplitMix64;
use delone::NONE;

const BIN: &str = env!("CARGO_BIN_EXE_delone");

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("delone-dual-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn run(dir: &Path, args: &[&str]) -> Output {
    let o = Command::new(BIN)
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run delone");
    o
}

fn ok(o: &Output) {
    assert!(
        o.status.success(),
        "stdout: {}\nstderr: {}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
}

fn lines(dir: &Path, name: &str) -> Vec<Vec<String>> {
    std::fs::read_to_string(dir.join(name))
        .unwrap_or_else(|e| panic!("{name}: {e}"))
        .lines()
        .filter(|l| !l.trim_start().starts_with('#') && !l.trim().is_empty())
        .map(|l| l.split_whitespace().map(String::from).collect())
        .collect()
}

fn unit(r: &mut SplitMix64) -> f64 {
    (r.next_u64() >> 11) as f64 / (1u64 << 53) as f64
}

/// Writes `name.node` with 2D points and optional one attribute column.
fn write_node2(dir: &Path, name: &str, pts: &[[f64; 2]], attr: Option<&[f64]>) {
    let mut s = format!("{} 2 {} 0\n", pts.len(), usize::from(attr.is_some()));
    for (i, p) in pts.iter().enumerate() {
        s += &format!("{} {:e} {:e}", i + 1, p[0], p[1]);
        if let Some(a) = attr {
            s += &format!(" {:e}", a[i]);
        }
        s += "\n";
    }
    std::fs::write(dir.join(format!("{name}.node")), s).unwrap();
}

fn random2(n: usize, seed: u64) -> Vec<[f64; 2]> {
    let mut r = SplitMix64::new(seed);
    (0..n).map(|_| [unit(&mut r), unit(&mut r)]).collect()
}

fn read_ele(dir: &Path, name: &str) -> Vec<[u32; 3]> {
    lines(dir, name)[1..]
        .iter()
        .map(|w| [1, 2, 3].map(|k| w[k].parse::<u32>().unwrap() - 1))
        .collect()
}

#[test]
fn voronoi_files_match_the_library() {
    let dir = tmp("v");
    let pts = random2(300, 1);
    write_node2(&dir, "pts", &pts, None);
    ok(&run(&dir, &["tri", "-vQ", "pts"]));
    let mesh = delone::triangulate(&pts).unwrap();
    let v = delone::tri::Voronoi2::new(&pts, &mesh).unwrap();
    let node = lines(&dir, "pts.1.v.node");
    assert_eq!(node[0][0], v.vertices.len().to_string());
    for (k, w) in node[1..].iter().enumerate() {
        assert_eq!(w[0], (k + 1).to_string());
        let x: [f64; 2] = [w[1].parse().unwrap(), w[2].parse().unwrap()];
        assert_eq!(x, v.vertices[k]);
    }
    let edge = lines(&dir, "pts.1.v.edge");
    assert_eq!(edge[0], [v.edges.len().to_string(), "0".into()]);
    let mut rays = 0;
    for (w, e) in edge[1..].iter().zip(&v.edges) {
        assert_eq!(w[1], (e.vertices[0] + 1).to_string());
        if e.is_ray() {
            rays += 1;
            assert_eq!(w[2], "-1");
            let d: Vec<f64> = w[3..].iter().map(|x| x.parse().unwrap()).collect();
            assert_eq!(d, e.direction(&pts));
        } else {
            assert_eq!(w[2], (e.vertices[1] + 1).to_string());
        }
    }
    // One ray per hull edge; Euler on the Delaunay side.
    let hull = mesh
        .neighbors
        .iter()
        .flatten()
        .filter(|&&u| u == NONE)
        .count();
    assert_eq!(rays, hull);
}

#[test]
fn weights_from_attribute_and_weight_file() {
    let dir = tmp("w");
    let pts = random2(400, 2);
    let mut r = SplitMix64::new(3);
    let w: Vec<f64> = (0..pts.len()).map(|_| 0.01 * unit(&mut r)).collect();
    write_node2(&dir, "a", &pts, Some(&w));
    let o = run(&dir, &["tri", "-wvC", "a"]);
    ok(&o);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("weights from attribute 1"), "{out}");
    assert!(out.contains("hidden points"), "{out}");
    let mesh = delone::tri::regular_triangulation(&pts, &w).unwrap();
    assert!(!mesh.hidden.is_empty());
    let tris = read_ele(&dir, "a.1.ele");
    assert_eq!(tris, mesh.triangles);
    // The hidden points appear in no triangle; the power diagram's vertices
    // are the library's.
    for t in &tris {
        for x in t {
            assert!(mesh.hidden.binary_search(x).is_err());
        }
    }
    let v = delone::tri::Voronoi2::new_power(&pts, &w, &mesh).unwrap();
    assert_eq!(lines(&dir, "a.1.v.node").len(), v.vertices.len() + 1);
    // A .weight file wins over the attribute (here: weights negated, in
    // shuffled `index weight` lines, with comments).
    let w2: Vec<f64> = w.iter().map(|x| 0.01 - x).collect();
    let mut s = format!("{} 1 # count\n", pts.len());
    for i in (0..pts.len()).rev() {
        s += &format!("{} {:e}\n", i + 1, w2[i]);
    }
    std::fs::write(dir.join("a.weight"), s).unwrap();
    let o = run(&dir, &["tri", "-wC", "a"]);
    ok(&o);
    assert!(String::from_utf8_lossy(&o.stdout).contains("a.weight"));
    let mesh2 = delone::tri::regular_triangulation(&pts, &w2).unwrap();
    assert_eq!(read_ele(&dir, "a.1.ele"), mesh2.triangles);
    assert_ne!(mesh2.triangles, mesh.triangles);
    // Zero weights: the Delaunay triangulation, bit for bit.
    let zeros = vec![0.0; pts.len()];
    write_node2(&dir, "z", &pts, Some(&zeros));
    ok(&run(&dir, &["tri", "-wQ", "z"]));
    ok(&run(&dir, &["tri", "-Q", "--output-dir", "plain", "z"]));
    assert_eq!(
        std::fs::read(dir.join("z.1.ele")).unwrap(),
        std::fs::read(dir.join("plain/z.1.ele")).unwrap()
    );
}

#[test]
fn weight_errors() {
    let dir = tmp("werr");
    let pts = random2(10, 4);
    write_node2(&dir, "p", &pts, None);
    let o = run(&dir, &["tri", "-w", "p"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("-w needs weights"));
    std::fs::write(dir.join("p.weight"), "10\n1 0\n2 inf\n").unwrap();
    let o = run(&dir, &["tri", "-w", "p"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("line 3"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

#[test]
fn lloyd_relaxes_the_points() {
    let dir = tmp("lloyd");
    let pts = random2(200, 5);
    write_node2(&dir, "p", &pts, None);
    ok(&run(&dir, &["tri", "-Q", "--lloyd", "20", "p"]));
    let node = lines(&dir, "p.1.node");
    let out: Vec<[f64; 2]> = node[1..]
        .iter()
        .map(|w| [w[1].parse().unwrap(), w[2].parse().unwrap()])
        .collect();
    let b = [[0.0f64, 0.0f64], [1.0, 1.0]];
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for p in &pts {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let expected = delone::tri::lloyd(&pts, [lo, hi], 20).unwrap();
    assert_eq!(out.len(), expected.len());
    for (a, e) in out.iter().zip(&expected) {
        assert!((a[0] - e[0]).abs() <= 1e-15 && (a[1] - e[1]).abs() <= 1e-15);
    }
    // Relaxed points are more evenly spread: the smallest pairwise distance grows.
    let min_dist = |p: &[[f64; 2]]| {
        let mut m = f64::INFINITY;
        for i in 0..p.len() {
            for j in 0..i {
                m = m.min((p[i][0] - p[j][0]).hypot(p[i][1] - p[j][1]));
            }
        }
        m
    };
    assert!(min_dist(&out) > 3.0 * min_dist(&pts));
    assert!(out
        .iter()
        .all(|p| p[0] >= b[0][0] && p[0] <= b[1][0] && p[1] >= b[0][1] && p[1] <= b[1][1]));
    // The .ele refers to the relaxed points.
    let tris = read_ele(&dir, "p.1.ele");
    assert_eq!(tris, delone::triangulate(&out).unwrap().triangles);
}

#[test]
fn svg_picture() {
    let dir = tmp("svg");
    let pts = random2(100, 6);
    let mut r = SplitMix64::new(7);
    let w: Vec<f64> = (0..pts.len()).map(|_| 0.02 * unit(&mut r)).collect();
    write_node2(&dir, "p", &pts, Some(&w));
    ok(&run(&dir, &["tri", "-Q", "--svg", "mesh.svg", "p"]));
    let svg = std::fs::read_to_string(dir.join("mesh.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    let mesh = delone::triangulate(&pts).unwrap();
    assert_eq!(svg.matches("<circle").count(), pts.len());
    ok(&run(&dir, &["tri", "-wvQ", "--svg=power.svg", "p"]));
    let svg = std::fs::read_to_string(dir.join("power.svg")).unwrap();
    let reg = delone::tri::regular_triangulation(&pts, &w).unwrap();
    assert!(!reg.hidden.is_empty());
    // Every point is drawn (hidden ones in red), plus one path per cell
    // meeting the points' bounding box and one for the triangles.
    assert_eq!(svg.matches("<circle").count(), pts.len());
    assert!(svg.contains("red"));
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in &pts {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let cells = delone::tri::Voronoi2::new_power(&pts, &w, &reg)
        .unwrap()
        .cells_clipped(&pts, [lo, hi]);
    let nonempty = (0..pts.len())
        .filter(|&i| cells.polygon(i).len() >= 2)
        .count();
    assert!(nonempty + 10 >= pts.len() - reg.hidden.len());
    assert_eq!(svg.matches("<path").count(), nonempty + 1);
    assert!(mesh.triangles.len() > reg.triangles.len());
}

#[test]
fn tet_voronoi_files() {
    let dir = tmp("tetv");
    let mut r = SplitMix64::new(8);
    let pts: Vec<[f64; 3]> = (0..120)
        .map(|_| [unit(&mut r), unit(&mut r), unit(&mut r)])
        .collect();
    let mut s = format!("{} 3 0 0\n", pts.len());
    for (i, p) in pts.iter().enumerate() {
        s += &format!("{} {:e} {:e} {:e}\n", i + 1, p[0], p[1], p[2]);
    }
    std::fs::write(dir.join("c.node"), s).unwrap();
    ok(&run(&dir, &["tet", "-vQ", "c"]));
    let mesh = delone::tetrahedralize(&pts).unwrap();
    let v = delone::tet::Voronoi3::new(&pts, &mesh).unwrap();
    let node = lines(&dir, "c.1.v.node");
    assert_eq!(node.len(), v.vertices.len() + 1);
    let edge = lines(&dir, "c.1.v.edge");
    assert_eq!(edge.len(), v.edges.len() + 1);
    let face = lines(&dir, "c.1.v.face");
    assert_eq!(face.len(), v.faces.len() + 1);
    // Each face names two distinct cells (sites) and lists its edges.
    for (f, w) in face[1..].iter().enumerate() {
        let a: usize = w[1].parse().unwrap();
        let b: usize = w[2].parse().unwrap();
        assert!(a != b && a >= 1 && b >= 1 && a <= pts.len() && b <= pts.len());
        let k: usize = w[3].parse().unwrap();
        assert_eq!(w.len(), 4 + k, "face {f}");
    }
    let cell = lines(&dir, "c.1.v.cell");
    assert_eq!(cell[0], [pts.len().to_string()]);
    // Every face bounds exactly the two cells it names.
    // (TetGen's layout: an unbounded cell's list ends with -1, counted.)
    let mut count = vec![0usize; v.faces.len()];
    for (p, w) in cell[1..].iter().enumerate() {
        let k: usize = w[1].parse().unwrap();
        assert_eq!(w.len(), 2 + k, "cell {p}");
        assert_eq!(
            w.last().map(|x| x == "-1"),
            Some(v.is_unbounded(p)),
            "cell {p}"
        );
        for x in &w[2..] {
            if x != "-1" {
                count[x.parse::<usize>().unwrap() - 1] += 1;
            }
        }
    }
    assert!(count.iter().all(|&c| c == 2));
    // An unbounded face's edge list ends with -1 too.
    for (f, w) in face[1..].iter().enumerate() {
        assert_eq!(
            w.last().map(|x| x == "-1"),
            Some(v.face(f).rays.is_some()),
            "face {f}"
        );
    }
}

/// The TetGen `-v` layout on one tetrahedron, checked by hand: one Voronoi
/// vertex (the circumcentre (1, 1, 1)), four rays with unit outward
/// directions, six unbounded faces (two rays and the closing -1 each), four
/// unbounded cells (three faces and -1 each).
#[test]
fn tet_voronoi_layout_of_one_tetrahedron() {
    let dir = tmp("tet1");
    std::fs::write(
        dir.join("t.node"),
        "4 3 0 0\n1 0 0 0\n2 2 0 0\n3 0 2 0\n4 0 0 2\n",
    )
    .unwrap();
    ok(&run(&dir, &["tet", "-vQ", "t"]));
    assert_eq!(
        lines(&dir, "t.1.v.node"),
        [vec!["1", "3", "0", "0"], vec!["1", "1", "1", "1"]]
    );
    let edge = lines(&dir, "t.1.v.edge");
    assert_eq!(edge[0], ["4", "0"]);
    let mut dirs: Vec<Vec<String>> = edge[1..]
        .iter()
        .map(|w| {
            assert_eq!(&w[1..3], ["1", "-1"]);
            w[3..]
                .iter()
                .map(|x| format!("{:.12}", x.parse::<f64>().unwrap()))
                .collect()
        })
        .collect();
    dirs.sort();
    let s = format!("{:.12}", (1.0f64 / 3.0).sqrt());
    let m = format!("{:.12}", -1.0);
    let z = format!("{:.12}", 0.0);
    let expect = [
        vec![m.clone(), z.clone(), z.clone()],
        vec![z.clone(), m.clone(), z.clone()],
        vec![z.clone(), z.clone(), m.clone()],
        vec![s.clone(), s.clone(), s.clone()],
    ];
    let mut expect = expect.to_vec();
    expect.sort();
    assert_eq!(dirs, expect);
    let face = lines(&dir, "t.1.v.face");
    assert_eq!(face[0], ["6", "0"]);
    for w in &face[1..] {
        assert_eq!(w.len(), 7, "{w:?}");
        assert_eq!(w[3], "3");
        assert_eq!(w[6], "-1");
    }
    let cell = lines(&dir, "t.1.v.cell");
    assert_eq!(cell[0], ["4"]);
    for w in &cell[1..] {
        assert_eq!(w.len(), 6, "{w:?}");
        assert_eq!(w[1], "4");
        assert_eq!(w[5], "-1");
    }
}

#[test]
fn options_refused_with_pslg() {
    let dir = tmp("pslg");
    let o = run(&dir, &["tri", "-pv", "x.poly"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("not supported with -p"));
}

#[test]
fn tet_weighted_with_power_diagram_and_check() {
    let dir = tmp("tetw");
    let mut r = SplitMix64::new(9);
    let pts: Vec<[f64; 3]> = (0..200)
        .map(|_| [unit(&mut r), unit(&mut r), unit(&mut r)])
        .collect();
    let ws: Vec<f64> = (0..200).map(|_| 0.05 * unit(&mut r)).collect();
    let mut s = format!("{} 3 1 0\n", pts.len());
    for (i, p) in pts.iter().enumerate() {
        s += &format!("{} {:e} {:e} {:e} {:e}\n", i + 1, p[0], p[1], p[2], ws[i]);
    }
    std::fs::write(dir.join("w.node"), s).unwrap();
    let o = run(&dir, &["tet", "-wvC", "w"]);
    ok(&o);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("hidden points"), "{out}");
    assert!(out.contains("passed"), "{out}");
    // The .ele matches the library's regular tetrahedralization (with the
    // weights as parsed back from the file).
    let parsed: Vec<f64> = ws
        .iter()
        .map(|w| format!("{w:e}").parse().unwrap())
        .collect();
    let mesh = delone::tet::regular_tetrahedralization(&pts, &parsed).unwrap();
    let ele = lines(&dir, "w.1.ele");
    assert_eq!(ele.len(), mesh.tets.len() + 1);
    let v = delone::tet::Voronoi3::new_power(&pts, &parsed, &mesh).unwrap();
    assert_eq!(lines(&dir, "w.1.v.node").len(), v.vertices.len() + 1);
    // Zero weights: byte-identical .ele to the unweighted run.
    let mut z = format!("{} 3 1 0\n", pts.len());
    for (i, p) in pts.iter().enumerate() {
        z += &format!("{} {:e} {:e} {:e} 0\n", i + 1, p[0], p[1], p[2]);
    }
    std::fs::write(dir.join("z.node"), z).unwrap();
    ok(&run(&dir, &["tet", "-wQ", "z"]));
    let weighted = std::fs::read(dir.join("z.1.ele")).unwrap();
    ok(&run(&dir, &["tet", "-Q", "z"]));
    assert_eq!(weighted, std::fs::read(dir.join("z.1.ele")).unwrap());
}

#[test]
fn tet_cells_as_vtk_polyhedra() {
    let dir = tmp("tetcells");
    let mut r = SplitMix64::new(10);
    let pts: Vec<[f64; 3]> = (0..100)
        .map(|_| [unit(&mut r), unit(&mut r), unit(&mut r)])
        .collect();
    let mut s = format!("{} 3 0 0\n", pts.len());
    for (i, p) in pts.iter().enumerate() {
        s += &format!("{} {:e} {:e} {:e}\n", i + 1, p[0], p[1], p[2]);
    }
    std::fs::write(dir.join("c.node"), s).unwrap();
    ok(&run(&dir, &["tet", "-Q", "--cells-vtu", "cells.vtu", "c"]));
    let text = String::from_utf8_lossy(&std::fs::read(dir.join("cells.vtu")).unwrap()).into_owned();
    assert!(
        text.contains("NumberOfCells=\"100\""),
        "{}",
        &text[..300.min(text.len())]
    );
    assert!(text.contains("Name=\"faceoffsets\""));
    // Not a tri option.
    let o = run(&dir, &["tri", "--cells-vtu", "x.vtu", "c"]);
    assert_eq!(o.status.code(), Some(2));
}
