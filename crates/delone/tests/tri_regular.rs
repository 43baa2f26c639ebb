//! Regular (weighted Delaunay) triangulations in 2D: zero weights reproduce
//! the Delaunay triangulation bit for bit, outputs pass the independent
//! validator, hidden points agree with a brute-force lower-hull test, and
//! incremental insertion agrees with the one-call builder.

use delone::geom::SplitMix64;
use delone::tri::{regular_triangulation, validate_regular, Delaunay2, Inserted};
use delone::{triangulate, Error, TriMesh, NONE};
use delone_predicates::{incircle_weighted, orient2d};

fn unit(r: &mut SplitMix64) -> f64 {
    (r.next_u64() >> 11) as f64 / (1u64 << 53) as f64
}

fn random(n: usize, seed: u64) -> Vec<[f64; 2]> {
    let mut r = SplitMix64::new(seed);
    (0..n).map(|_| [unit(&mut r), unit(&mut r)]).collect()
}

fn grid(side: usize) -> Vec<[f64; 2]> {
    (0..side * side)
        .map(|k| [(k % side) as f64, (k / side) as f64])
        .collect()
}

fn random_weights(n: usize, scale: f64, seed: u64) -> Vec<f64> {
    let mut r = SplitMix64::new(seed);
    (0..n).map(|_| scale * unit(&mut r)).collect()
}

/// Triangles as a canonical sorted set (each rotated to its smallest vertex).
fn canon(mesh: &TriMesh) -> Vec<[u32; 3]> {
    let mut t: Vec<[u32; 3]> = mesh
        .triangles
        .iter()
        .map(|v| {
            let k = (0..3).min_by_key(|&k| v[k]).unwrap();
            [v[k], v[(k + 1) % 3], v[(k + 2) % 3]]
        })
        .collect();
    t.sort_unstable();
    t
}

#[test]
fn zero_weights_reproduce_delaunay_bit_for_bit() {
    let mut sets = vec![
        random(10, 1),
        random(1000, 2),
        random(20_000, 3),
        grid(30),
        grid(7),
    ];
    // Cocircular points, duplicates and collinear runs.
    let mut ring: Vec<[f64; 2]> = (0..64)
        .map(|k| {
            let a = k as f64 * std::f64::consts::TAU / 64.0;
            [a.cos(), a.sin()]
        })
        .collect();
    ring.extend_from_slice(&[[0.0, 0.0], [1.0, 0.0], [0.5, 0.0], [0.25, 0.0]]);
    sets.push(ring);
    let mut dup = random(300, 4);
    dup.extend_from_within(0..50);
    sets.push(dup);
    // Huge and tiny scales (exact power-of-two rescaling).
    sets.push(
        random(200, 5)
            .iter()
            .map(|p| [p[0] * 1e200, p[1] * 1e200])
            .collect(),
    );
    sets.push(
        random(200, 6)
            .iter()
            .map(|p| [p[0] * 1e-200, p[1] * 1e-200])
            .collect(),
    );
    for pts in &sets {
        let a = triangulate(pts).unwrap();
        let zeros = vec![0.0; pts.len()];
        let b = regular_triangulation(pts, &zeros).unwrap();
        assert_eq!(a, b, "{} points", pts.len());
        assert!(b.hidden.is_empty());
        validate_regular(pts, &zeros, &b).unwrap();
    }
}

#[test]
fn random_weights_validate() {
    for (n, scale, seed) in [
        (50, 0.01, 10),
        (500, 0.001, 11),
        (5000, 1e-4, 12),
        (20_000, 1e-5, 13),
        (2000, 0.05, 14),
        (2000, -0.01, 15),
    ] {
        let pts = random(n, seed);
        let w = random_weights(n, scale, seed + 100);
        let d = Delaunay2::from_weighted_points(&pts, &w).unwrap();
        d.check_topology().unwrap();
        d.check_delaunay().unwrap();
        let mesh = d.into_mesh();
        validate_regular(&pts, &w, &mesh).unwrap_or_else(|v| panic!("n={n}: {v}"));
        if scale.abs() >= 0.01 {
            assert!(!mesh.hidden.is_empty(), "n={n}: expected hidden points");
        }
    }
}

#[test]
fn degenerate_grids_with_integer_weights() {
    // Integer grid, small integer weights: many exact power ties (SoS).
    for side in [5usize, 12, 40] {
        let pts = grid(side);
        let mut r = SplitMix64::new(side as u64);
        for k in [1u32, 2, 3] {
            let w: Vec<f64> = (0..pts.len())
                .map(|_| r.below(k + 1) as f64 * 0.5)
                .collect();
            let d = Delaunay2::from_weighted_points(&pts, &w).unwrap();
            d.check_topology().unwrap();
            d.check_delaunay().unwrap();
            let mesh = d.into_mesh();
            validate_regular(&pts, &w, &mesh).unwrap_or_else(|v| panic!("side {side}: {v}"));
        }
        // Equal weights everywhere: the Delaunay triangulation again (the
        // power test differs from incircle by a constant only).
        let w = vec![0.75; pts.len()];
        let mesh = regular_triangulation(&pts, &w).unwrap();
        assert_eq!(mesh, triangulate(&pts).unwrap());
    }
}

/// Brute force: `i` is hidden iff some triangle of three other points
/// contains it (closed) with its lifted point on or above their lifted
/// plane (Carathéodory on the lower hull), for points in general position.
fn brute_hidden(pts: &[[f64; 2]], w: &[f64]) -> Vec<u32> {
    let n = pts.len();
    let mut out = Vec::new();
    for i in 0..n {
        let q = &pts[i];
        let mut hidden = false;
        'search: for a in 0..n {
            for b in 0..n {
                for c in 0..n {
                    if a == i || b == i || c == i || a == b || b == c || a == c {
                        continue;
                    }
                    let (pa, pb, pc) = (&pts[a], &pts[b], &pts[c]);
                    if orient2d(pa, pb, pc) <= 0.0 {
                        continue;
                    }
                    if orient2d(pa, pb, q) < 0.0
                        || orient2d(pb, pc, q) < 0.0
                        || orient2d(pc, pa, q) < 0.0
                    {
                        continue;
                    }
                    if incircle_weighted(pa, pb, pc, q, w[a], w[b], w[c], w[i]) <= 0.0 {
                        hidden = true;
                        break 'search;
                    }
                }
            }
        }
        if hidden {
            out.push(i as u32);
        }
    }
    out
}

#[test]
fn hidden_points_match_brute_force() {
    let mut total = 0;
    for seed in 0..40u64 {
        let n = 8 + (seed as usize % 13);
        let pts = random(n, 1000 + seed);
        let w = random_weights(n, 0.05 + 0.02 * (seed % 5) as f64, 2000 + seed);
        let mesh = regular_triangulation(&pts, &w).unwrap();
        validate_regular(&pts, &w, &mesh).unwrap();
        let expected = brute_hidden(&pts, &w);
        assert_eq!(mesh.hidden, expected, "seed {seed}");
        total += expected.len();
        for &h in &mesh.hidden {
            assert_eq!(mesh.vertex_map[h as usize], NONE);
        }
    }
    assert!(total > 20, "too few hidden points to be a test ({total})");
}

#[test]
fn incremental_matches_one_call_and_stays_valid() {
    for seed in 0..6u64 {
        let n = 300;
        let pts = random(n, 50 + seed);
        let w = random_weights(n, 0.004, 60 + seed);
        let mut d = Delaunay2::new();
        let mut hidden_now = Vec::new();
        for (k, (&p, &wk)) in pts.iter().zip(&w).enumerate() {
            match d.insert_weighted(p, wk).unwrap() {
                Inserted::Hidden(id) => {
                    assert_eq!(id as usize, k);
                    hidden_now.push(id);
                }
                Inserted::Vertex(id) | Inserted::Pending(id) => assert_eq!(id as usize, k),
                other => panic!("{other:?}"),
            }
            if k % 25 == 0 {
                d.check_topology().unwrap();
                d.check_delaunay().unwrap();
            }
        }
        d.check_topology().unwrap();
        d.check_delaunay().unwrap();
        let hidden = d.hidden();
        for h in &hidden_now {
            assert!(hidden.contains(h));
        }
        let inc = d.into_mesh();
        validate_regular(&pts, &w, &inc).unwrap();
        let one = regular_triangulation(&pts, &w).unwrap();
        assert_eq!(canon(&inc), canon(&one), "seed {seed}");
        assert_eq!(inc.hidden, one.hidden);
    }
}

#[test]
fn coincident_points_with_weights() {
    // Same place: equal weights are duplicates, the lighter one is hidden.
    let pts = [
        [0.0, 0.0],
        [3.0, 0.0],
        [0.0, 3.0],
        [1.0, 1.0],
        [1.0, 1.0],
        [1.0, 1.0],
        [3.0, 0.0],
    ];
    let w = [0.0, 0.0, 0.0, 0.1, 0.1, 0.3, 0.0];
    let mesh = regular_triangulation(&pts, &w).unwrap();
    validate_regular(&pts, &w, &mesh).unwrap();
    assert_eq!(mesh.hidden, vec![3, 4]);
    assert_eq!(mesh.duplicates, vec![(6, 1)]);
    assert_eq!(mesh.vertex_map[5], 5);
    // One by one, heavier last and lighter last.
    let mut d = Delaunay2::new();
    for (p, wk) in pts.iter().zip(w) {
        d.insert_weighted(*p, wk).unwrap();
    }
    assert_eq!(d.hidden(), vec![3, 4]);
    d.check_topology().unwrap();
    let mut d = Delaunay2::new();
    assert_eq!(
        d.insert_weighted([1.0, 1.0], 0.3).unwrap(),
        Inserted::Pending(0)
    );
    assert_eq!(
        d.insert_weighted([1.0, 1.0], 0.1).unwrap(),
        Inserted::Hidden(1)
    );
    assert_eq!(
        d.insert_weighted([3.0, 1.0], 0.0).unwrap(),
        Inserted::Pending(2)
    );
    assert_eq!(
        d.insert_weighted([1.0, 1.0], 0.5).unwrap(),
        Inserted::Pending(3)
    );
    assert_eq!(
        d.insert_weighted([1.0, 4.0], 0.0).unwrap(),
        Inserted::Vertex(4)
    );
    assert_eq!(d.hidden(), vec![0, 1]);
    assert_eq!(d.num_vertices(), 3);
    d.check_topology().unwrap();
}

#[test]
fn heavy_point_hides_many_vertices() {
    // One very heavy point in the middle swallows every interior vertex.
    let mut pts = grid(9);
    let mut w = vec![0.0; pts.len()];
    pts.push([4.1, 3.9]);
    w.push(9.0);
    let mesh = regular_triangulation(&pts, &w).unwrap();
    validate_regular(&pts, &w, &mesh).unwrap();
    assert!(mesh.hidden.len() >= 9, "{:?}", mesh.hidden);
    assert_eq!(mesh.hidden, brute_hidden_grid(&pts, &w));
    // Incrementally, the heavy point last (one big cavity) and first.
    for heavy_first in [false, true] {
        let mut d = Delaunay2::new();
        let order: Vec<usize> = if heavy_first {
            std::iter::once(pts.len() - 1)
                .chain(0..pts.len() - 1)
                .collect()
        } else {
            (0..pts.len()).collect()
        };
        for &k in &order {
            d.insert_weighted(pts[k], w[k]).unwrap();
        }
        d.check_topology().unwrap();
        d.check_delaunay().unwrap();
        assert_eq!(d.hidden().len(), mesh.hidden.len());
    }
}

/// Sampled brute force for the grid plus one heavy point: a point counts as
/// hidden iff no sample of the unit square around it (21 x 21) has it as the
/// strict power-distance minimum (exact enough here: the visible grid
/// points keep most of their unit cell).
#[allow(clippy::needless_range_loop)]
fn brute_hidden_grid(pts: &[[f64; 2]], w: &[f64]) -> Vec<u32> {
    let n = pts.len();
    let pow =
        |x: [f64; 2], j: usize| (x[0] - pts[j][0]).powi(2) + (x[1] - pts[j][1]).powi(2) - w[j];
    let mut out = Vec::new();
    for i in 0..n {
        let mut empty = true;
        'sample: for a in 0..=20 {
            for b in 0..=20 {
                let x = [
                    pts[i][0] - 0.5 + a as f64 / 20.0,
                    pts[i][1] - 0.5 + b as f64 / 20.0,
                ];
                if (0..n).all(|j| j == i || pow(x, i) < pow(x, j)) {
                    empty = false;
                    break 'sample;
                }
            }
        }
        if empty {
            out.push(i as u32);
        }
    }
    out
}

#[test]
fn weight_errors_name_the_point() {
    let pts = random(10, 9);
    let mut w = vec![0.0; 10];
    w[7] = f64::NAN;
    assert_eq!(
        regular_triangulation(&pts, &w).unwrap_err(),
        Error::InvalidWeight { index: 7 }
    );
    w[7] = f64::INFINITY;
    assert_eq!(
        regular_triangulation(&pts, &w).unwrap_err(),
        Error::InvalidWeight { index: 7 }
    );
    assert_eq!(
        regular_triangulation(&pts, &w[..9]).unwrap_err(),
        Error::WeightCount {
            points: 10,
            weights: 9
        }
    );
    let mut d = Delaunay2::new();
    d.insert_weighted([0.0, 0.0], 1.0).unwrap();
    assert_eq!(
        d.insert_weighted([1.0, 0.0], f64::NAN).unwrap_err(),
        Error::InvalidWeight { index: 1 }
    );
    assert_eq!(d.points().len(), 1);
}

#[test]
fn validator_rejects_wrong_regular_meshes() {
    let pts = random(200, 21);
    let w = random_weights(200, 0.02, 22);
    let good = regular_triangulation(&pts, &w).unwrap();
    validate_regular(&pts, &w, &good).unwrap();
    assert!(!good.hidden.is_empty());
    // The Delaunay triangulation is not the regular one for these weights.
    let dt = triangulate(&pts).unwrap();
    assert!(validate_regular(&pts, &w, &dt).is_err());
    // Wrong weights for the mesh.
    let other = random_weights(200, 0.02, 23);
    assert!(validate_regular(&pts, &other, &good).is_err());
    // A hidden point made heavier is not hidden any more.
    let mut heavier = w.clone();
    heavier[good.hidden[0] as usize] += 1.0;
    let v = validate_regular(&pts, &heavier, &good).unwrap_err();
    assert_eq!(v.kind, "hidden", "{v}");
    // The hidden list must be complete.
    let mut bad = good.clone();
    bad.hidden.pop();
    assert!(validate_regular(&pts, &w, &bad).is_err());
}

#[test]
fn huge_and_tiny_scales_with_weights() {
    // Coordinates scaled by s and weights by s²: the same regular
    // triangulation (the kernel rescales by exact powers of two).
    let pts = random(500, 31);
    let w = random_weights(500, 0.002, 32);
    let base = regular_triangulation(&pts, &w).unwrap();
    assert!(!base.hidden.is_empty());
    for s in [2f64.powi(300), 2f64.powi(-300), 1024.0] {
        let p: Vec<[f64; 2]> = pts.iter().map(|q| [q[0] * s, q[1] * s]).collect();
        let ws: Vec<f64> = w.iter().map(|x| x * s * s).collect();
        let mesh = regular_triangulation(&p, &ws).unwrap();
        assert_eq!(mesh, base, "scale {s:e}");
        validate_regular(&p, &ws, &mesh).unwrap();
    }
    // A weight beyond the exact range is refused, naming the point.
    let mut big = w.clone();
    big[3] = 1e300;
    assert_eq!(
        regular_triangulation(&pts, &big).unwrap_err(),
        Error::InvalidWeight { index: 3 }
    );
}
