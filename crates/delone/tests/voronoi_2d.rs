//! 2D Voronoi diagrams, clipped cells and Lloyd relaxation, checked against
//! brute force.
#![allow(clippy::needless_range_loop)]

use std::path::PathBuf;

use delone::geom::SplitMix64;
use delone::tri::voronoi::{Box2, ClippedCells2};
use delone::tri::{lloyd, Voronoi2};
use delone::NONE;

fn unit(r: &mut SplitMix64) -> f64 {
    (r.next_u64() >> 11) as f64 / (1u64 << 53) as f64
}

fn random(n: usize, seed: u64, lo: f64, hi: f64) -> Vec<[f64; 2]> {
    let mut r = SplitMix64::new(seed);
    (0..n)
        .map(|_| [lo + (hi - lo) * unit(&mut r), lo + (hi - lo) * unit(&mut r)])
        .collect()
}

fn dist2(a: &[f64; 2], b: &[f64; 2]) -> f64 {
    (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)
}

/// Signed distance-like test: `>= -tol` iff `x` is inside the ccw polygon
/// (up to `tol`), computed as the minimum normalised cross product. Edges
/// too short to have a meaningful direction after rounding are skipped.
fn inside_margin(poly: &[[f64; 2]], x: &[f64; 2]) -> f64 {
    let size = poly
        .iter()
        .map(|q| q[0].abs().max(q[1].abs()))
        .fold(0.0, f64::max);
    let m = poly.len();
    let mut worst = f64::INFINITY;
    for k in 0..m {
        let a = poly[k];
        let b = poly[(k + 1) % m];
        let (ex, ey) = (b[0] - a[0], b[1] - a[1]);
        let len = (ex * ex + ey * ey).sqrt();
        if len <= 1e-12 * size {
            continue;
        }
        let c = (ex * (x[1] - a[1]) - ey * (x[0] - a[0])) / len;
        worst = worst.min(c);
    }
    worst
}

/// Polygon area by the shoelace formula, independent of the library.
fn shoelace(poly: &[[f64; 2]]) -> f64 {
    let m = poly.len();
    (0..m)
        .map(|k| {
            let (a, b) = (poly[k], poly[(k + 1) % m]);
            a[0] * b[1] - a[1] * b[0]
        })
        .sum::<f64>()
        * 0.5
}

fn box_area(b: Box2) -> f64 {
    (b[1][0] - b[0][0]) * (b[1][1] - b[0][1])
}

/// The CVT energy: sum over clipped cells of the integral of |x - site|²,
/// computed independently (triangle fans, exact quadrature of quadratics).
fn energy(sites: &[[f64; 2]], cells: &ClippedCells2, vmap: &[u32]) -> f64 {
    let mut e = 0.0;
    for (s, site) in sites.iter().enumerate() {
        if vmap[s] as usize != s {
            continue;
        }
        let poly = cells.polygon(s);
        for k in 0..poly.len() {
            // Triangle (site, a, b): integral of |x - site|² over it is
            // area/6 * (|a'|² + |b'|² + a'·b') with a' = a - site, b' = b - site.
            let a = [poly[k][0] - site[0], poly[k][1] - site[1]];
            let b = [
                poly[(k + 1) % poly.len()][0] - site[0],
                poly[(k + 1) % poly.len()][1] - site[1],
            ];
            let area = 0.5 * (a[0] * b[1] - a[1] * b[0]);
            e += area / 6.0
                * (a[0] * a[0]
                    + a[1] * a[1]
                    + b[0] * b[0]
                    + b[1] * b[1]
                    + a[0] * b[0]
                    + a[1] * b[1]);
        }
    }
    e
}

/// Every property of the brief on one point set and box.
fn check(pts: &[[f64; 2]], bbox: Box2, samples: usize) {
    let mesh = delone::triangulate(pts).unwrap();
    let v = Voronoi2::new(pts, &mesh).unwrap();
    // Voronoi vertices are equidistant from their triangle's corners.
    for (t, tv) in mesh.triangles.iter().enumerate() {
        let c = v.vertices[t];
        let d = tv.map(|q| dist2(&c, &pts[q as usize]).sqrt());
        // Rounding the centre to floats costs up to an ulp of its coordinates.
        let scale = d[0] + 1e-6 * c[0].abs().max(c[1].abs());
        for k in 1..3 {
            assert!(
                (d[k] - d[0]).abs() <= 1e-9 * scale,
                "triangle {t}: circumradius {d:?}"
            );
        }
    }
    // Edge count: one per Delaunay edge; rays exactly on hull edges.
    let hull_edges = mesh
        .neighbors
        .iter()
        .flatten()
        .filter(|&&u| u == NONE)
        .count();
    assert_eq!(v.edges.iter().filter(|e| e.is_ray()).count(), hull_edges);
    assert_eq!(v.edges.len(), (3 * mesh.triangles.len() + hull_edges) / 2);
    // Hull sites, found independently from the mesh.
    let mut on_hull = vec![false; pts.len()];
    for (tv, nb) in mesh.triangles.iter().zip(&mesh.neighbors) {
        for i in 0..3 {
            if nb[i] == NONE {
                on_hull[tv[(i + 1) % 3] as usize] = true;
                on_hull[tv[(i + 2) % 3] as usize] = true;
            }
        }
    }
    for s in 0..pts.len() {
        let r = mesh.vertex_map[s] as usize;
        let cell = v.cell(s);
        assert_eq!(cell, v.cell(r));
        assert_eq!(cell.is_unbounded(), on_hull[r], "site {s}");
        assert_eq!(cell.neighbors.len(), cell.vertices.len());
        assert_eq!(cell.ray_neighbor != NONE, on_hull[r]);
        // The neighbours are exactly the Delaunay neighbours.
        let mut nb: Vec<u32> = cell.neighbors.to_vec();
        if on_hull[r] {
            nb.push(cell.ray_neighbor);
        }
        nb.sort_unstable();
        let mut expect: Vec<u32> = mesh
            .triangles
            .iter()
            .filter(|tv| tv.contains(&(r as u32)))
            .flatten()
            .copied()
            .filter(|&q| q as usize != r)
            .collect();
        expect.sort_unstable();
        expect.dedup();
        assert_eq!(nb, expect, "site {s}");
        if let Some(rays) = cell.rays {
            // Both rays point outward: every point lies behind them.
            for d in rays {
                let len = (d[0] * d[0] + d[1] * d[1]).sqrt();
                assert!(len > 0.0);
                for q in pts {
                    let x = (q[0] - pts[r][0]) * d[0] + (q[1] - pts[r][1]) * d[1];
                    assert!(
                        x <= 1e-9 * len * len.max(1.0),
                        "site {s}: ray {d:?} not outward"
                    );
                }
            }
        }
        if !on_hull[r] {
            // Bounded and convex (non-strictly: cocircular vertices repeat).
            let poly: Vec<[f64; 2]> = cell
                .vertices
                .iter()
                .map(|&t| v.vertices[t as usize])
                .collect();
            let m = poly.len();
            let scale = poly
                .iter()
                .map(|q| dist2(q, &pts[r]).sqrt())
                .fold(0.0, f64::max);
            for k in 0..m {
                let (a, b, c) = (poly[k], poly[(k + 1) % m], poly[(k + 2) % m]);
                let cross = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]);
                assert!(cross >= -1e-9 * scale * scale, "site {s} not convex");
            }
            // Circumcentres of nearly flat triangles are far and inexact:
            // allow rounding relative to the cell's size.
            let m = inside_margin(&poly, &pts[r]);
            assert!(
                m > -1e-9 * scale,
                "site {s} outside its cell by {m} (size {scale})"
            );
        }
    }
    // Clipped cells tile the box.
    let c = v.cells_clipped(pts, bbox);
    let mut total = 0.0;
    for s in 0..pts.len() {
        let poly = c.polygon(s);
        let a = shoelace(poly);
        assert!((a - c.area[s]).abs() <= 1e-9 * box_area(bbox), "site {s}");
        if mesh.vertex_map[s] as usize == s {
            total += c.area[s];
        }
        for q in poly {
            let tol = 1e-9 * (bbox[1][0] - bbox[0][0]);
            assert!(q[0] >= bbox[0][0] - tol && q[0] <= bbox[1][0] + tol);
            assert!(q[1] >= bbox[0][1] - tol && q[1] <= bbox[1][1] + tol);
        }
        if c.area[s] > 0.0 {
            assert!(inside_margin(poly, &c.centroid[s]) >= -1e-9);
        }
    }
    let rel = (total - box_area(bbox)).abs() / box_area(bbox);
    assert!(rel <= 1e-9, "areas sum to {total}, box {}", box_area(bbox));
    // Sampled points of the box lie in the clipped cell of their nearest site.
    let mut r = SplitMix64::new(7);
    let w = [bbox[1][0] - bbox[0][0], bbox[1][1] - bbox[0][1]];
    for _ in 0..samples {
        let x = [
            bbox[0][0] + w[0] * unit(&mut r),
            bbox[0][1] + w[1] * unit(&mut r),
        ];
        let best = (0..pts.len())
            .map(|s| dist2(&x, &pts[s]))
            .fold(f64::INFINITY, f64::min);
        let mut found = false;
        for s in 0..pts.len() {
            if mesh.vertex_map[s] as usize != s || c.polygon(s).len() < 3 {
                continue;
            }
            let m = inside_margin(c.polygon(s), &x);
            if m > 1e-9 * w[0] {
                // Strictly inside: s must be a nearest site.
                let d = dist2(&x, &pts[s]);
                assert!(
                    d.sqrt() - best.sqrt() <= 1e-9 * w[0],
                    "sample {x:?} in cell {s} but a site is closer"
                );
            }
            if m >= -1e-9 * w[0] && (dist2(&x, &pts[s]).sqrt() - best.sqrt()) <= 1e-9 * w[0] {
                found = true;
            }
        }
        assert!(found, "sample {x:?} is in no nearest site's cell");
    }
}

#[test]
fn random_points_in_box() {
    check(&random(400, 1, 0.0, 1.0), [[0.0, 0.0], [1.0, 1.0]], 2000);
}

#[test]
fn sites_outside_the_box_and_offset_box() {
    check(&random(300, 2, -0.5, 1.5), [[0.0, 0.0], [1.0, 1.0]], 2000);
    check(
        &random(300, 3, 100.0, 101.0),
        [[99.0, 100.2], [101.5, 100.9]],
        1000,
    );
}

#[test]
fn grid_is_cocircular() {
    let pts: Vec<[f64; 2]> = (0..400)
        .map(|k| [(k % 20) as f64, (k / 20) as f64])
        .collect();
    check(&pts, [[-0.5, -0.5], [19.5, 19.5]], 1000);
    let mesh = delone::triangulate(&pts).unwrap();
    let v = Voronoi2::new(&pts, &mesh).unwrap();
    let c = v.cells_clipped(&pts, [[-0.5, -0.5], [19.5, 19.5]]);
    for s in 0..pts.len() {
        assert!(
            (c.area[s] - 1.0).abs() < 1e-12,
            "grid cell {s}: {}",
            c.area[s]
        );
        assert!(dist2(&c.centroid[s], &pts[s]) < 1e-24);
    }
}

#[test]
fn cocircular_with_centre_and_duplicates() {
    let mut pts: Vec<[f64; 2]> = (0..16)
        .map(|k| {
            let a = k as f64 * std::f64::consts::TAU / 16.0;
            [a.cos(), a.sin()]
        })
        .collect();
    pts.push([0.0, 0.0]);
    pts.push(pts[3]);
    pts.push([0.0, 0.0]);
    check(&pts, [[-2.0, -2.0], [2.0, 2.0]], 2000);
    let mesh = delone::triangulate(&pts).unwrap();
    let v = Voronoi2::new(&pts, &mesh).unwrap();
    let c = v.cells_clipped(&pts, [[-2.0, -2.0], [2.0, 2.0]]);
    assert_eq!(c.polygon(17), c.polygon(3));
    assert_eq!(c.area[18], c.area[16]);
    assert!(!v.cell(16).is_unbounded());
}

#[test]
fn shared_node_files() {
    let Some(data) = delone_testdata::corpus_path(env!("CARGO_MANIFEST_DIR"), "2d/points") else {
        return;
    };
    let mut files: Vec<PathBuf> = std::fs::read_dir(data)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "node"))
        .collect();
    files.sort();
    for f in files {
        let node = delone_io::read_node(&std::fs::read(&f).unwrap()).unwrap();
        let pts = node.points::<2>().unwrap();
        if pts.len() > 3000 {
            continue;
        }
        let Ok(_) = delone::triangulate(&pts) else {
            continue;
        };
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in &pts {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let pad = [(hi[0] - lo[0]) * 0.1, (hi[1] - lo[1]) * 0.1];
        println!("{}: {} points", f.display(), pts.len());
        check(
            &pts,
            [
                [lo[0] - pad[0], lo[1] - pad[1]],
                [hi[0] + pad[0], hi[1] + pad[1]],
            ],
            300,
        );
    }
}

#[test]
fn lloyd_energy_decreases() {
    let bbox = [[0.0, 0.0], [1.0, 1.0]];
    let mut pts = random(200, 11, 0.0, 1.0);
    let mut prev = f64::INFINITY;
    let mut first = 0.0;
    for it in 0..30 {
        let mesh = delone::triangulate(&pts).unwrap();
        let v = Voronoi2::new(&pts, &mesh).unwrap();
        let e = energy(&pts, &v.cells_clipped(&pts, bbox), &mesh.vertex_map);
        if it == 0 {
            first = e;
        }
        assert!(
            e <= prev * (1.0 + 1e-12),
            "iteration {it}: energy {e} > {prev}"
        );
        prev = e;
        pts = lloyd(&pts, bbox, 1).unwrap();
    }
    assert!(prev < 0.9 * first, "energy {first} -> {prev}");
    // Deterministic, and iterating 1 + 1 equals iterating 2.
    let a = lloyd(&random(50, 5, 0.0, 1.0), bbox, 2).unwrap();
    let b = lloyd(&lloyd(&random(50, 5, 0.0, 1.0), bbox, 1).unwrap(), bbox, 1).unwrap();
    assert_eq!(a, b);
}

#[test]
fn a_mesh_of_other_points_is_an_error_not_a_panic() {
    let pts = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]];
    let mesh = delone::triangulate(&pts).unwrap();
    let err = delone::tri::Voronoi2::new(&pts[..3], &mesh).unwrap_err();
    assert!(
        matches!(err, delone::Error::InconsistentMesh { .. }),
        "{err}"
    );
    let err = delone::tri::Voronoi2::new_power(&pts, &[0.0; 3], &mesh).unwrap_err();
    assert_eq!(
        err,
        delone::Error::WeightCount {
            points: 4,
            weights: 3
        }
    );
}

#[test]
fn any_thread_count_gives_the_same_diagram() {
    // Over 2^16 triangles: the default splits the work over two threads.
    let pts = random(40_000, 11, 0.0, 1.0);
    let mesh = delone::triangulate(&pts).unwrap();
    assert!(mesh.triangles.len() >= 1 << 16);
    let one = delone::tri::Voronoi2::with_threads(&pts, &mesh, 1).unwrap();
    let two = delone::tri::Voronoi2::with_threads(&pts, &mesh, 2).unwrap();
    assert_eq!(one, two);
    assert_eq!(one, delone::tri::Voronoi2::new(&pts, &mesh).unwrap());
    // The parts really are there: one vertex per triangle, one edge per
    // Delaunay edge, every site's cell closing around it.
    assert_eq!(one.vertices.len(), mesh.triangles.len());
    let hull = mesh
        .neighbors
        .iter()
        .flatten()
        .filter(|&&u| u == NONE)
        .count();
    assert_eq!(one.edges.len(), (3 * mesh.triangles.len() + hull) / 2);
    let total: usize = (0..pts.len()).map(|p| one.cell(p).vertices.len()).sum();
    assert_eq!(total, 3 * mesh.triangles.len());
    // Power diagram with zero weights: the same, plus the weights.
    let w = vec![0.0; pts.len()];
    let rmesh = delone::tri::regular_triangulation(&pts, &w).unwrap();
    let mut p = delone::tri::Voronoi2::new_power(&pts, &w, &rmesh).unwrap();
    assert_eq!(p.weights, w);
    p.weights.clear();
    assert_eq!(p, delone::tri::Voronoi2::new(&pts, &rmesh).unwrap());
}
