//! Voronoi cells clipped to a polygonal domain with holes; Lloyd inside it.

use delone::geom::SplitMix64;
use delone::tri::{lloyd_in_domain, Voronoi2};

/// An L-shaped outer boundary (area 3) with a square hole (area 0.25).
fn domain() -> Vec<Vec<[f64; 2]>> {
    vec![
        vec![
            [0.0, 0.0],
            [2.0, 0.0],
            [2.0, 1.0],
            [1.0, 1.0],
            [1.0, 2.0],
            [0.0, 2.0],
        ],
        vec![[0.25, 0.25], [0.25, 0.75], [0.75, 0.75], [0.75, 0.25]],
    ]
}

fn winding(ring: &[[f64; 2]], x: &[f64; 2]) -> i32 {
    let m = ring.len();
    let mut w = 0;
    for k in 0..m {
        let (a, b) = (ring[k], ring[(k + 1) % m]);
        let cross = (b[0] - a[0]) * (x[1] - a[1]) - (x[0] - a[0]) * (b[1] - a[1]);
        if a[1] <= x[1] {
            if b[1] > x[1] && cross > 0.0 {
                w += 1;
            }
        } else if b[1] <= x[1] && cross < 0.0 {
            w -= 1;
        }
    }
    w
}

fn in_domain(x: &[f64; 2]) -> bool {
    let d = domain();
    winding(&d[0], x) != 0 && winding(&d[1], x) == 0
}

fn sites(n: usize, seed: u64) -> Vec<[f64; 2]> {
    let mut r = SplitMix64::new(seed);
    let mut out = Vec::new();
    while out.len() < n {
        let x = [
            2.0 * (r.next_u64() >> 11) as f64 / (1u64 << 53) as f64,
            2.0 * (r.next_u64() >> 11) as f64 / (1u64 << 53) as f64,
        ];
        if in_domain(&x) {
            out.push(x);
        }
    }
    out
}

#[test]
fn cells_tile_the_domain_and_contain_their_points() {
    for (n, seed) in [(10, 1), (200, 2), (3000, 3)] {
        let pts = sites(n, seed);
        let mesh = delone::triangulate(&pts).unwrap();
        let v = Voronoi2::new(&pts, &mesh).unwrap();
        let c = v.cells_in_domain(&pts, &domain());
        let total: f64 = c.area.iter().sum();
        assert!((total - 2.75).abs() < 1e-9, "n={n}: {total}");
        let mut r = SplitMix64::new(seed + 50);
        for _ in 0..500 {
            let x = [
                2.0 * (r.next_u64() >> 11) as f64 / (1u64 << 53) as f64,
                2.0 * (r.next_u64() >> 11) as f64 / (1u64 << 53) as f64,
            ];
            if !in_domain(&x) {
                continue;
            }
            let d = |i: usize| (pts[i][0] - x[0]).powi(2) + (pts[i][1] - x[1]).powi(2);
            let best = (0..n).map(d).fold(f64::INFINITY, f64::min);
            let found = (0..n)
                .filter(|&i| d(i) <= best * (1.0 + 1e-12))
                .any(|i| c.pieces[i].iter().map(|p| winding(p, &x)).sum::<i32>() != 0);
            assert!(found, "n={n}: {x:?} is in no nearest site's clipped cell");
        }
        for (i, g) in c.centroid.iter().enumerate() {
            if c.area[i] > 0.0 {
                assert!(g.iter().all(|v| v.is_finite()));
            }
        }
    }
}

#[test]
fn lloyd_in_the_domain_lowers_the_energy_and_stays_inside() {
    let rings = domain();
    let energy = |pts: &[[f64; 2]]| {
        // CVT energy estimated on a fixed sample of domain points.
        let mut r = SplitMix64::new(77);
        let mut e = 0.0;
        let mut k = 0;
        while k < 4000 {
            let x = [
                2.0 * (r.next_u64() >> 11) as f64 / (1u64 << 53) as f64,
                2.0 * (r.next_u64() >> 11) as f64 / (1u64 << 53) as f64,
            ];
            if !in_domain(&x) {
                continue;
            }
            k += 1;
            e += pts
                .iter()
                .map(|p| (p[0] - x[0]).powi(2) + (p[1] - x[1]).powi(2))
                .fold(f64::INFINITY, f64::min);
        }
        e
    };
    let mut pts = sites(150, 5);
    let mut last = energy(&pts);
    for _ in 0..8 {
        pts = lloyd_in_domain(&pts, &rings, 1).unwrap();
        let e = energy(&pts);
        assert!(e <= last * (1.0 + 1e-3), "energy rose from {last} to {e}");
        last = e;
    }
    // Centroids of cells of a domain with a hole can fall in the hole only
    // for non-convex pieces; with these sizes every site stays in the L.
    let inside = pts.iter().filter(|p| in_domain(p)).count();
    assert!(inside >= 148, "{inside} of 150 inside");
}
