//! Regular (weighted Delaunay) tetrahedralizations.

use delone::geom::SplitMix64;
use delone::tet::{regular_tetrahedralization, validate_regular, Delaunay3};
use delone::{tetrahedralize, Error, Inserted, NONE};

fn uniform(n: usize, seed: u64) -> Vec<[f64; 3]> {
    let mut r = SplitMix64::new(seed);
    let mut u = || (r.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
    (0..n).map(|_| [u(), u(), u()]).collect()
}

fn weights(n: usize, seed: u64, scale: f64) -> Vec<f64> {
    let mut r = SplitMix64::new(seed);
    (0..n)
        .map(|_| scale * ((r.next_u64() >> 11) as f64 / (1u64 << 53) as f64))
        .collect()
}

fn grid(k: usize) -> Vec<[f64; 3]> {
    (0..k * k * k)
        .map(|i| [(i % k) as f64, (i / k % k) as f64, (i / k / k) as f64])
        .collect()
}

fn canon(mut t: [u32; 4]) -> [u32; 4] {
    t.sort_unstable();
    t
}

#[test]
fn zero_weights_reproduce_the_delaunay_tetrahedralization_bit_for_bit() {
    for pts in [uniform(3000, 1), grid(7)] {
        let zero = vec![0.0; pts.len()];
        let a = regular_tetrahedralization(&pts, &zero).unwrap();
        let b = tetrahedralize(&pts).unwrap();
        assert_eq!(a, b);
        validate_regular(&pts, &zero, &a).unwrap();
    }
}

#[test]
fn random_weights_are_valid_and_hide_points() {
    // Weights spread over many squared neighbour distances: plenty hidden.
    for (n, seed, w) in [
        (50, 2, 0.3),
        (500, 3, 0.1),
        (5000, 4, 0.02),
        (2000, 5, 0.05),
    ] {
        let pts = uniform(n, seed);
        let ws = weights(n, seed + 100, w);
        let dt = Delaunay3::from_weighted_points(&pts, &ws).unwrap();
        dt.check_topology().unwrap();
        dt.check_delaunay().unwrap();
        let mesh = dt.into_mesh();
        validate_regular(&pts, &ws, &mesh).unwrap();
        for &h in &mesh.hidden {
            assert_eq!(mesh.vertex_map[h as usize], NONE);
        }
        assert!(!mesh.hidden.is_empty(), "n={n}: expected hidden points");
    }
}

#[test]
fn incremental_weighted_insertion_checked_every_step_matches_bulk() {
    let pts = uniform(300, 7);
    let ws = weights(300, 8, 0.1);
    let mut dt = Delaunay3::new();
    for (&p, &w) in pts.iter().zip(&ws) {
        dt.insert_weighted(p, w).unwrap();
        dt.check_topology().unwrap();
        dt.check_delaunay().unwrap();
    }
    let inc = dt.into_mesh();
    validate_regular(&pts, &ws, &inc).unwrap();
    let bulk = regular_tetrahedralization(&pts, &ws).unwrap();
    assert_eq!(inc.hidden, bulk.hidden);
    let mut a: Vec<_> = inc.tets.into_iter().map(canon).collect();
    let mut b: Vec<_> = bulk.tets.into_iter().map(canon).collect();
    a.sort_unstable();
    b.sort_unstable();
    assert_eq!(a, b);
}

#[test]
fn heavy_points_hide_light_vertices_including_coincident_ones() {
    let mut pts = grid(4);
    let mut ws = vec![0.0; pts.len()];
    // A heavy point at the centre hides the inner vertices around it...
    pts.push([1.5, 1.5, 1.5]);
    ws.push(3.0);
    // ...and a coincident heavier copy of a corner hides that corner.
    pts.push([0.0, 0.0, 0.0]);
    ws.push(0.5);
    // An exact copy (same weight) is a duplicate, not a hidden point.
    pts.push([3.0, 3.0, 3.0]);
    ws.push(0.0);
    let mesh = regular_tetrahedralization(&pts, &ws).unwrap();
    validate_regular(&pts, &ws, &mesh).unwrap();
    for inner in [21u32, 22, 25, 26, 37, 38, 41, 42] {
        assert!(
            mesh.hidden.contains(&inner),
            "inner vertex {inner} not hidden: {:?}",
            mesh.hidden
        );
    }
    assert!(mesh.hidden.contains(&0));
    assert_eq!(mesh.duplicates, vec![(66, 63)]);
    // The same incrementally, checking after each insertion.
    let mut dt = Delaunay3::new();
    for (k, (&p, &w)) in pts.iter().zip(&ws).enumerate() {
        let r = dt.insert_weighted(p, w).unwrap();
        if k == 66 {
            assert_eq!(
                r,
                Inserted::Duplicate {
                    id: 66,
                    original: 63
                }
            );
        }
        dt.check_topology().unwrap();
        dt.check_delaunay().unwrap();
    }
    assert_eq!(dt.hidden(), &mesh.hidden[..]);
}

#[test]
fn weight_errors_are_typed() {
    let pts = uniform(10, 9);
    assert_eq!(
        regular_tetrahedralization(&pts, &[0.0; 9]).unwrap_err(),
        Error::WeightCount {
            points: 10,
            weights: 9
        }
    );
    let mut w = vec![0.0; 10];
    w[6] = f64::NAN;
    assert_eq!(
        regular_tetrahedralization(&pts, &w).unwrap_err(),
        Error::InvalidWeight { index: 6 }
    );
    let mut dt = Delaunay3::new();
    assert_eq!(
        dt.insert_weighted([0.0; 3], f64::INFINITY).unwrap_err(),
        Error::InvalidWeight { index: 0 }
    );
}

#[test]
fn extreme_scales_keep_weights_consistent() {
    let base = uniform(300, 10);
    let bw = weights(300, 11, 0.01);
    let reference = regular_tetrahedralization(&base, &bw).unwrap();
    for s in [
        1.0f64 / 1024.0 / 1024.0 / 1024.0 / 1024.0 / 1024.0 / 1024.0 / 1024.0 / 1024.0,
        1099511627776.0
            * 1099511627776.0
            * 1099511627776.0
            * 1099511627776.0
            * 1099511627776.0
            * 1099511627776.0,
    ] {
        // Powers of two: scaling points by s and weights by s² is exact, so
        // the combinatorics must not change.
        let pts: Vec<[f64; 3]> = base.iter().map(|p| p.map(|c| c * s)).collect();
        let ws: Vec<f64> = bw.iter().map(|w| w * s * s).collect();
        let mesh = regular_tetrahedralization(&pts, &ws).unwrap();
        validate_regular(&pts, &ws, &mesh).unwrap();
        assert_eq!(mesh.hidden, reference.hidden);
        assert_eq!(mesh.tets.len(), reference.tets.len());
    }
}

/// Hidden points by a different route: point `i` is hidden iff, in the
/// regular tetrahedralization of all the *other* points, `i` lies inside the
/// hull and does not conflict with the tetrahedron containing it.
fn hidden_by_removal(pts: &[[f64; 3]], ws: &[f64]) -> Vec<u32> {
    use delone_predicates::{insphere_weighted, orient3d};
    let mut hidden = Vec::new();
    for i in 0..pts.len() {
        let others: Vec<[f64; 3]> = (0..pts.len()).filter(|&j| j != i).map(|j| pts[j]).collect();
        let ow: Vec<f64> = (0..pts.len()).filter(|&j| j != i).map(|j| ws[j]).collect();
        let m = regular_tetrahedralization(&others, &ow).unwrap();
        let q = &pts[i];
        let p = |k: u32| &others[k as usize];
        const FACET: [[usize; 3]; 4] = [[1, 3, 2], [0, 2, 3], [0, 3, 1], [0, 1, 2]];
        let containing = m.tets.iter().find(|t| {
            FACET
                .iter()
                .all(|f| orient3d(p(t[f[0]]), p(t[f[1]]), p(t[f[2]]), q) <= 0.0)
        });
        if let Some(t) = containing {
            let w = |k: u32| ow[k as usize];
            let s = insphere_weighted(
                p(t[1]),
                p(t[0]),
                p(t[2]),
                p(t[3]),
                q,
                w(t[1]),
                w(t[0]),
                w(t[2]),
                w(t[3]),
                ws[i],
            );
            if s < 0.0 {
                hidden.push(i as u32);
            }
        }
    }
    hidden
}

#[test]
fn hidden_points_agree_with_removal_on_small_random_sets() {
    for seed in 0..20u64 {
        let n = 30 + (seed as usize % 5) * 10;
        let pts = uniform(n, 200 + seed);
        let ws = weights(n, 300 + seed, 0.3);
        let mesh = regular_tetrahedralization(&pts, &ws).unwrap();
        validate_regular(&pts, &ws, &mesh).unwrap();
        let brute = hidden_by_removal(&pts, &ws);
        assert!(!brute.is_empty());
        assert_eq!(mesh.hidden, brute, "seed {seed}");
    }
}
