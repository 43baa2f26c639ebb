//! 2D power diagrams, checked against brute force: cells tile the box,
//! sampled points lie in the cell of the site of least power distance,
//! hidden points are exactly the sites with empty cells (each cell computed
//! independently by clipping with all radical axes), zero weights give the
//! Voronoi diagram.

use delone::geom::SplitMix64;
use delone::tri::{regular_triangulation, Voronoi2};
use delone::{triangulate, NONE};

fn unit(r: &mut SplitMix64) -> f64 {
    (r.next_u64() >> 11) as f64 / (1u64 << 53) as f64
}

fn weighted(n: usize, wscale: f64, seed: u64) -> (Vec<[f64; 2]>, Vec<f64>) {
    let mut r = SplitMix64::new(seed);
    let pts: Vec<[f64; 2]> = (0..n).map(|_| [unit(&mut r), unit(&mut r)]).collect();
    let w: Vec<f64> = (0..n).map(|_| wscale * unit(&mut r)).collect();
    (pts, w)
}

fn power(x: &[f64; 2], p: &[f64; 2], w: f64) -> f64 {
    (x[0] - p[0]).powi(2) + (x[1] - p[1]).powi(2) - w
}

/// Independent cell: the box clipped by `pow_i <= pow_j` for every other
/// site (Sutherland–Hodgman against each half-plane), O(n) per cell.
fn brute_cell(pts: &[[f64; 2]], w: &[f64], i: usize, b: [[f64; 2]; 2]) -> Vec<[f64; 2]> {
    let [lo, hi] = b;
    let mut poly = vec![lo, [hi[0], lo[1]], hi, [lo[0], hi[1]]];
    for j in 0..pts.len() {
        if j == i || poly.is_empty() {
            continue;
        }
        // pow_i(x) - pow_j(x) = 2 x·(pj - pi) + |pi|² - |pj|² - wi + wj  (<= 0 keeps x)
        let (p, q) = (pts[i], pts[j]);
        let f = |x: &[f64; 2]| power(x, &p, w[i]) - power(x, &q, w[j]);
        let mut out = Vec::new();
        for k in 0..poly.len() {
            let a = poly[k];
            let c = poly[(k + 1) % poly.len()];
            let (fa, fc) = (f(&a), f(&c));
            if fa <= 0.0 {
                out.push(a);
            }
            if (fa <= 0.0) != (fc <= 0.0) {
                let t = fa / (fa - fc);
                out.push([a[0] + t * (c[0] - a[0]), a[1] + t * (c[1] - a[1])]);
            }
        }
        poly = out;
    }
    poly
}

fn area(poly: &[[f64; 2]]) -> f64 {
    let m = poly.len();
    if m < 3 {
        return 0.0;
    }
    0.5 * (0..m)
        .map(|k| {
            let (p, q) = (poly[k], poly[(k + 1) % m]);
            p[0] * q[1] - q[0] * p[1]
        })
        .sum::<f64>()
}

fn contains(poly: &[[f64; 2]], x: &[f64; 2], tol: f64) -> bool {
    let m = poly.len();
    m >= 3
        && (0..m).all(|k| {
            let (a, b) = (poly[k], poly[(k + 1) % m]);
            let len = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
            (b[0] - a[0]) * (x[1] - a[1]) - (b[1] - a[1]) * (x[0] - a[0]) >= -tol * len
        })
}

#[test]
fn power_cells_tile_the_box() {
    for (n, ws, seed) in [
        (30, 0.05, 1),
        (500, 0.002, 2),
        (5000, 1e-4, 3),
        (2000, 0.01, 4),
    ] {
        let (pts, w) = weighted(n, ws, seed);
        let mesh = regular_triangulation(&pts, &w).unwrap();
        let v = Voronoi2::new_power(&pts, &w, &mesh).unwrap();
        for bbox in [[[0.0, 0.0], [1.0, 1.0]], [[-0.5, 0.2], [1.5, 0.7]]] {
            let c = v.cells_clipped(&pts, bbox);
            let box_area = (bbox[1][0] - bbox[0][0]) * (bbox[1][1] - bbox[0][1]);
            let sum: f64 = c.area.iter().sum();
            assert!(
                (sum - box_area).abs() <= 1e-12 * box_area * n as f64,
                "n={n}: area sum {sum} vs {box_area}"
            );
            for &h in &mesh.hidden {
                assert_eq!(c.area[h as usize], 0.0);
                assert!(c.polygon(h as usize).is_empty());
            }
        }
    }
}

#[test]
fn samples_lie_in_the_cell_of_least_power() {
    let (pts, w) = weighted(300, 0.01, 7);
    let mesh = regular_triangulation(&pts, &w).unwrap();
    assert!(!mesh.hidden.is_empty());
    let v = Voronoi2::new_power(&pts, &w, &mesh).unwrap();
    let bbox = [[-0.1, -0.1], [1.1, 1.1]];
    let c = v.cells_clipped(&pts, bbox);
    let mut r = SplitMix64::new(8);
    let mut checked = 0;
    for _ in 0..3000 {
        let x = [-0.1 + 1.2 * unit(&mut r), -0.1 + 1.2 * unit(&mut r)];
        let mut d: Vec<(f64, usize)> = (0..pts.len())
            .map(|j| (power(&x, &pts[j], w[j]), j))
            .collect();
        d.sort_by(|a, b| a.0.total_cmp(&b.0));
        if d[1].0 - d[0].0 < 1e-9 {
            continue; // too close to a cell boundary to decide in floating point
        }
        let best = d[0].1;
        assert!(
            contains(c.polygon(best), &x, 1e-12),
            "sample {x:?} not in the cell of site {best}"
        );
        assert_ne!(
            mesh.vertex_map[best], NONE,
            "a hidden site has least power at {x:?}"
        );
        checked += 1;
    }
    assert!(checked > 2900);
}

#[test]
fn hidden_points_are_exactly_the_empty_cells() {
    let mut hidden_total = 0;
    for seed in 0..30u64 {
        let n = 10 + (seed as usize % 25);
        let (pts, w) = weighted(n, 0.03 + 0.01 * (seed % 4) as f64, 100 + seed);
        let mesh = regular_triangulation(&pts, &w).unwrap();
        let v = Voronoi2::new_power(&pts, &w, &mesh).unwrap();
        // A box far larger than every power centre: clipped cells are the
        // cells (restricted to the box), nonempty iff the site is visible.
        let big = [[-1e4, -1e4], [1e4, 1e4]];
        let c = v.cells_clipped(&pts, big);
        for i in 0..n {
            let brute = brute_cell(&pts, &w, i, big);
            let a = area(&brute);
            let is_hidden = mesh.hidden.binary_search(&(i as u32)).is_ok();
            assert_eq!(
                a == 0.0,
                is_hidden,
                "seed {seed} site {i}: brute-force area {a}"
            );
            assert!(
                (c.area[i] - a).abs() <= 1e-6 * a.max(1.0),
                "seed {seed} site {i}: {} vs brute {a}",
                c.area[i]
            );
        }
        hidden_total += mesh.hidden.len();
    }
    assert!(hidden_total > 20, "only {hidden_total} hidden points");
}

#[test]
fn zero_weights_give_the_voronoi_diagram() {
    let (pts, _) = weighted(2000, 0.0, 9);
    let zeros = vec![0.0; pts.len()];
    let vor = Voronoi2::new(&pts, &triangulate(&pts).unwrap()).unwrap();
    let mut pow =
        Voronoi2::new_power(&pts, &zeros, &regular_triangulation(&pts, &zeros).unwrap()).unwrap();
    assert_eq!(pow.weights, zeros);
    let bbox = [[0.0, 0.0], [1.0, 1.0]];
    assert_eq!(vor.cells_clipped(&pts, bbox), pow.cells_clipped(&pts, bbox));
    pow.weights.clear();
    assert_eq!(vor, pow);
}

#[test]
fn power_vertices_are_equidistant() {
    let (pts, w) = weighted(1000, 0.005, 11);
    let mesh = regular_triangulation(&pts, &w).unwrap();
    let v = Voronoi2::new_power(&pts, &w, &mesh).unwrap();
    for (t, tv) in mesh.triangles.iter().enumerate() {
        let x = v.vertices[t];
        let d = tv.map(|s| power(&x, &pts[s as usize], w[s as usize]));
        let scale = d.iter().map(|z| z.abs()).fold(1.0, f64::max);
        assert!((d[0] - d[1]).abs() < 1e-9 * scale && (d[0] - d[2]).abs() < 1e-9 * scale);
    }
    // Every hidden point's cell is empty, every other cell is not.
    for i in 0..pts.len() {
        let hidden = mesh.vertex_map[i] == NONE;
        assert_eq!(v.cell(i).vertices.is_empty(), hidden, "site {i}");
    }
}
