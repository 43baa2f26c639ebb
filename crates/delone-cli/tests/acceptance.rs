//! Acceptance of `delone tri FILE.node` and `delone tet FILE.node`: the files
//! the binary writes are read back here and handed to the independent
//! validators (`delone::tri::validate`, `delone::tet::validate`): every element
//! positively oriented, manifold adjacency, union = convex hull, empty
//! circumcircles/spheres by exact predicates, every non-duplicate point used.
//!
//! Inputs: every point set in `shared/data/2d/points`, a 300×300 grid, a 40³
//! grid, exactly cospherical/cocircular lattice points, duplicates, and
//! coordinates scaled by 1e-9 and 1e9.

use std::path::{Path, PathBuf};
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_delone");

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("delone-acc-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Writes `points` as a 1-based .node file.
fn write_node<const D: usize>(path: &Path, points: &[[f64; D]]) {
    let mut s = format!("{} {D} 0 0\n", points.len());
    for (i, p) in points.iter().enumerate() {
        s.push_str(&(i + 1).to_string());
        for c in p {
            s.push_str(&format!(" {c:?}"));
        }
        s.push('\n');
    }
    std::fs::write(path, s).unwrap();
}

/// Rows of integers of a Triangle/TetGen table file, index column dropped.
fn rows(path: &Path) -> Vec<Vec<i64>> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text
        .lines()
        .map(|l| l.split('#').next().unwrap_or(""))
        .filter(|l| !l.trim().is_empty());
    let n: usize = lines
        .next()
        .unwrap()
        .split_whitespace()
        .next()
        .unwrap()
        .parse()
        .unwrap();
    let r: Vec<Vec<i64>> = lines
        .map(|l| {
            l.split_whitespace()
                .skip(1)
                .map(|t| t.parse().unwrap())
                .collect()
        })
        .collect();
    assert_eq!(r.len(), n, "{}", path.display());
    r
}

/// Vertex map of an input, computed here: each point maps to the first
/// point with the same coordinates.
fn vertex_map<const D: usize>(points: &[[f64; D]]) -> (Vec<u32>, Vec<(u32, u32)>) {
    let mut order: Vec<u32> = (0..points.len() as u32).collect();
    let key = |i: u32| points[i as usize].map(|c| (c + 0.0).to_bits());
    order.sort_by_key(|&i| (key(i), i));
    let mut map: Vec<u32> = (0..points.len() as u32).collect();
    let mut dups = Vec::new();
    for w in 0..order.len() {
        if w > 0 && key(order[w]) == key(order[w - 1]) {
            map[order[w] as usize] = map[order[w - 1] as usize];
            dups.push((order[w], map[order[w] as usize]));
        }
    }
    dups.sort_unstable();
    (map, dups)
}

/// Cells and neighbours read back from FILE.1.ele / FILE.1.neigh (1-based).
fn cells<const K: usize>(dir: &Path, stem: &str) -> (Vec<[u32; K]>, Vec<[u32; K]>) {
    let conv = |r: &Vec<i64>| -> [u32; K] {
        std::array::from_fn(|k| {
            if r[k] < 0 {
                u32::MAX
            } else {
                (r[k] - 1) as u32
            }
        })
    };
    let ele = rows(&dir.join(format!("{stem}.1.ele")));
    let neigh = rows(&dir.join(format!("{stem}.1.neigh")));
    (
        ele.iter().map(conv).collect(),
        neigh.iter().map(conv).collect(),
    )
}

fn run(dir: &Path, args: &[&str]) {
    let out = Command::new(BIN)
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "delone {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn accept_2d(name: &str, points: &[[f64; 2]]) {
    let dir = tmp(name);
    write_node(&dir.join("in.node"), points);
    run(&dir, &["tri", "-nQ", "in.node"]);
    let (triangles, neighbors) = cells::<3>(&dir, "in");
    let (vertex_map, duplicates) = vertex_map(points);
    let mesh = delone::TriMesh {
        triangles,
        neighbors,
        vertex_map,
        duplicates,
        hidden: vec![],
    };
    delone::tri::validate(points, &mesh).unwrap_or_else(|v| panic!("{name}: {v}"));
    let _ = std::fs::remove_dir_all(&dir);
}

fn accept_3d(name: &str, points: &[[f64; 3]]) {
    let dir = tmp(name);
    write_node(&dir.join("in.node"), points);
    run(&dir, &["tet", "-nQ", "in.node"]);
    let (tets, neighbors) = cells::<4>(&dir, "in");
    let (vertex_map, duplicates) = vertex_map(points);
    let mesh = delone::TetMesh {
        tets,
        neighbors,
        vertex_map,
        duplicates,
        hidden: vec![],
    };
    delone::tet::validate(points, &mesh).unwrap_or_else(|v| panic!("{name}: {v}"));
    let _ = std::fs::remove_dir_all(&dir);
}

fn shared_points_dir() -> Option<PathBuf> {
    delone_testdata::corpus_path(env!("CARGO_MANIFEST_DIR"), "2d/points")
}

fn grid2(k: usize) -> Vec<[f64; 2]> {
    (0..k * k)
        .map(|i| [(i % k) as f64, (i / k) as f64])
        .collect()
}

fn grid3(k: usize) -> Vec<[f64; 3]> {
    (0..k * k * k)
        .map(|i| [(i % k) as f64, (i / k % k) as f64, (i / k / k) as f64])
        .collect()
}

#[test]
fn tri_on_every_shared_point_set() {
    let Some(dir) = shared_points_dir() else {
        return;
    };
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.retain(|p| p.extension().is_some_and(|e| e == "node"));
    files.sort();
    assert!(files.len() >= 10);
    for f in files {
        let node = delone_io::read_node(&std::fs::read(&f).unwrap()).unwrap();
        let pts = node.points::<2>().unwrap();
        accept_2d(f.file_stem().unwrap().to_str().unwrap(), &pts);
    }
}

#[test]
fn tri_grid_cocircular_duplicates_and_scales() {
    accept_2d("grid300", &grid2(300));
    // Exactly cocircular: integer points on x² + y² = 5^2 · 13^2 · 17^2.
    let r2: i64 = 5 * 5 * 13 * 13 * 17 * 17;
    let r = (r2 as f64).sqrt() as i64;
    let circle: Vec<[f64; 2]> = (-r..=r)
        .flat_map(|x| {
            let y2 = r2 - x * x;
            let y = (y2 as f64).sqrt() as i64;
            (y * y == y2).then(|| [[x as f64, y as f64], [x as f64, -y as f64]])
        })
        .flatten()
        .collect();
    assert!(circle.len() > 20);
    accept_2d("circle", &circle);
    let mut dups = grid2(30);
    dups.extend(grid2(30).iter().step_by(3));
    accept_2d("dups", &dups);
    for (name, s) in [("tiny", 1e-9), ("huge", 1e9)] {
        let pts: Vec<[f64; 2]> = grid2(40)
            .iter()
            .map(|p| p.map(|c| c * s + 0.1 * s))
            .collect();
        accept_2d(name, &pts);
    }
}

#[test]
fn tet_grid_cospherical_duplicates_and_scales() {
    accept_3d("grid40", &grid3(40));
    let mut sphere = Vec::new();
    for x in -8i64..=8 {
        for y in -8i64..=8 {
            for z in -8i64..=8 {
                if x * x + y * y + z * z == 50 {
                    sphere.push([x as f64, y as f64, z as f64]);
                }
            }
        }
    }
    assert!(sphere.len() > 20);
    accept_3d("sphere", &sphere);
    let mut dups = grid3(8);
    dups.extend(grid3(8).iter().step_by(5));
    accept_3d("dups", &dups);
    for (name, s) in [("tiny", 1e-9), ("huge", 1e9)] {
        let pts: Vec<[f64; 3]> = grid3(10)
            .iter()
            .map(|p| p.map(|c| c * s + 0.1 * s))
            .collect();
        accept_3d(name, &pts);
    }
}
