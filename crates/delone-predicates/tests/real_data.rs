//! Differential and SoS checks on the real point sets of the shared test data
//! (delaunator robustness fixtures, Triangle .node files, surface-mesh vertices).
//! Skipped with a note when the data directory is absent.

mod common;

use common::*;
use delone_predicates::*;
use std::path::PathBuf;

/// `<checkout>/../shared/data` (see `delone_testdata::corpus_dir`).
fn data_dir() -> Option<PathBuf> {
    delone_testdata::corpus_dir(env!("CARGO_MANIFEST_DIR"))
}

/// Numeric tokens of non-comment lines.
fn rows(text: &str) -> Vec<Vec<f64>> {
    text.lines()
        .map(|l| l.split('#').next().unwrap_or(""))
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            l.split_whitespace()
                .filter_map(|t| t.parse::<f64>().ok())
                .collect()
        })
        .collect()
}

fn read_node(path: &std::path::Path) -> Vec<[f64; 2]> {
    let text = std::fs::read_to_string(path).expect("readable .node");
    let r = rows(&text);
    let n = r[0][0] as usize;
    r[1..=n].iter().map(|v| [v[1], v[2]]).collect()
}

fn read_off(path: &std::path::Path) -> Vec<[f64; 3]> {
    let text = std::fs::read_to_string(path).expect("readable .off");
    let r = rows(&text); // the "OFF" header line parses to an empty row
    let start = r.iter().position(|v| v.len() >= 2).expect("counts line");
    let n = r[start][0] as usize;
    r[start + 1..=start + n]
        .iter()
        .map(|v| [v[0], v[1], v[2]])
        .collect()
}

#[test]
fn node_files_match_robust_and_sos_is_total() {
    let Some(dir) = data_dir() else { return };
    let mut files: Vec<_> = std::fs::read_dir(dir.join("2d/points"))
        .expect("points dir")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "node"))
        .collect();
    files.sort();
    assert!(!files.is_empty());
    let mut r = Rng(31);
    let mut ties = 0;
    for f in &files {
        let pts = read_node(f);
        let n = pts.len();
        if n < 4 {
            continue;
        }
        for _ in 0..20_000 {
            let i: [usize; 4] = std::array::from_fn(|_| r.int(0, n as i64 - 1) as usize);
            let (a, b, c, d) = (&pts[i[0]], &pts[i[1]], &pts[i[2]], &pts[i[3]]);
            let o = sign(orient2d(a, b, c));
            assert_eq!(o, sign(r_orient2d(a, b, c)), "{f:?} orient2d {i:?}");
            let ic = sign(incircle(a, b, c, d));
            assert_eq!(ic, sign(r_incircle(a, b, c, d)), "{f:?} incircle {i:?}");
            ties += (o == 0) as usize + (ic == 0) as usize;
            if i[0] != i[1]
                && i[0] != i[2]
                && i[0] != i[3]
                && i[1] != i[2]
                && i[1] != i[3]
                && i[2] != i[3]
            {
                let id = i.map(|k| k as u32);
                let s = incircle_sos(a, b, c, d, id[0], id[1], id[2], id[3]);
                assert!(s == 1 || s == -1);
                assert!(ic == 0 || s == ic);
                let s = orient2d_sos(a, b, c, id[0], id[1], id[2]);
                assert!(s == 1 || s == -1);
                assert!(o == 0 || s == o);
            }
        }
    }
    println!("{} node files, {ties} exact ties", files.len());
}

#[test]
fn surface_vertices_match_robust() {
    let Some(dir) = data_dir() else { return };
    let mut r = Rng(32);
    for name in [
        "c3d_spot.off",
        "cgal_cubes.off",
        "cgal_star.off",
        "cgal_anchor.off",
    ] {
        let p = dir.join("surf/off").join(name);
        assert!(p.is_file(), "{} is missing from the corpus", p.display());
        let pts = read_off(&p);
        let n = pts.len();
        assert!(n >= 5);
        let mut ties = 0;
        for k in 0..20_000 {
            // Consecutive vertices (often coplanar on CAD faces) and random ones.
            let i: [usize; 5] = if k % 2 == 0 {
                let s = r.int(0, n as i64 - 6) as usize;
                std::array::from_fn(|j| s + j)
            } else {
                std::array::from_fn(|_| r.int(0, n as i64 - 1) as usize)
            };
            let q = i.map(|k| pts[k]);
            let o = sign(orient3d(&q[0], &q[1], &q[2], &q[3]));
            assert_eq!(
                o,
                sign(r_orient3d(&q[0], &q[1], &q[2], &q[3])),
                "{name} orient3d {i:?}"
            );
            let s = sign(insphere(&q[0], &q[1], &q[2], &q[3], &q[4]));
            assert_eq!(
                s,
                sign(r_insphere(&q[0], &q[1], &q[2], &q[3], &q[4])),
                "{name} insphere {i:?}"
            );
            ties += (o == 0) as usize + (s == 0) as usize;
        }
        println!("{name}: {n} vertices, {ties} exact ties");
    }
}
