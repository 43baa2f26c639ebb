//! Sizing functions of the 3D refinement (closure and background mesh).

use std::sync::Arc;

use delone::tet::quality::{circumcenter, volume};
use delone::tet::recover::check_recovered;
use delone::tet::refine::sizing::{cell_radius_bound, Background, Sizing};
use delone::tet::refine::{refine, RefineOptions};

mod solids;
use solids::cube;

fn norm(p: [f64; 3]) -> f64 {
    (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt()
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    norm([a[0] - b[0], a[1] - b[1], a[2] - b[2]])
}

/// Mean edge length of the mesh edges whose midpoint is within `[lo, hi)`
/// of the origin.
fn mean_edge(pts: &[[f64; 3]], tets: &[[u32; 4]], lo: f64, hi: f64) -> (f64, usize) {
    let mut edges: Vec<(u32, u32)> = tets
        .iter()
        .flat_map(|t| {
            [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)].map(|(i, j)| {
                let (a, b) = (t[i], t[j]);
                (a.min(b), a.max(b))
            })
        })
        .collect();
    edges.sort_unstable();
    edges.dedup();
    let (mut sum, mut n) = (0.0, 0);
    for (a, b) in edges {
        let (pa, pb) = (pts[a as usize], pts[b as usize]);
        let m = [0, 1, 2].map(|k| 0.5 * (pa[k] + pb[k]));
        let d = norm(m);
        if d >= lo && d < hi {
            sum += dist(pa, pb);
            n += 1;
        }
    }
    (sum / n.max(1) as f64, n)
}

#[test]
fn closure_small_near_a_corner_grades_the_mesh() {
    let (pts, tris) = cube();
    let h = |p: [f64; 3]| 0.06 + 0.5 * norm(p);
    let opts = RefineOptions {
        sizing: Sizing::function(h),
        ..RefineOptions::default()
    };
    let r = refine(&pts, &tris, &opts).unwrap();
    check_recovered(&pts, &tris, &r.rec).unwrap();
    let rp = &r.rec.points;
    let tets = &r.rec.mesh.tets;
    let total: f64 = tets
        .iter()
        .map(|t| volume(&t.map(|q| rp[q as usize])))
        .sum();
    assert!((total - 1.0).abs() < 1e-9, "volume {total}");
    assert_eq!(r.report.remaining_too_big, 0, "{:?}", r.report);
    // Every cell meets the rule R <= 0.612 h(c).
    for t in tets {
        let p = t.map(|q| rp[q as usize]);
        let c = circumcenter(&p).unwrap();
        let rad = dist(c, p[0]);
        assert!(
            rad <= cell_radius_bound(h(c)) * (1.0 + 1e-9),
            "tet {t:?}: R = {rad}, h(c) = {}",
            h(c)
        );
    }
    let (near, n_near) = mean_edge(rp, tets, 0.0, 0.2);
    let (far, n_far) = mean_edge(rp, tets, 1.2, 2.0);
    eprintln!(
        "{} tets; near mean edge {near:.4} ({n_near}), far {far:.4} ({n_far})",
        tets.len()
    );
    assert!(n_near > 20 && n_far > 20);
    assert!(far > 3.0 * near, "near {near}, far {far}");
    // Edges near the corner are about the size asked there (not far
    // below it: refinement never goes under 0.61 h).
    assert!(near > 0.5 * h([0.1, 0.0, 0.0]) && near < 2.0 * h([0.2, 0.0, 0.0]));
    // Without sizing the cube stays coarse.
    let plain = refine(&pts, &tris, &RefineOptions::default()).unwrap();
    assert!(plain.rec.mesh.tets.len() * 10 < tets.len());
}

#[test]
fn subsegments_and_subfaces_obey_the_size() {
    let (pts, tris) = cube();
    // Uniform size 0.3: no boundary edge may stay longer than 0.3.
    let opts = RefineOptions {
        sizing: Sizing::function(|_| 0.3),
        max_radius_edge: None,
        ..RefineOptions::default()
    };
    let r = refine(&pts, &tris, &opts).unwrap();
    check_recovered(&pts, &tris, &r.rec).unwrap();
    let rp = &r.rec.points;
    for f in &r.rec.boundary {
        for k in 0..3 {
            let l = dist(rp[f[k] as usize], rp[f[(k + 1) % 3] as usize]);
            assert!(l <= 0.3 * 1.1548, "boundary edge {l}");
        }
    }
}

#[test]
fn background_mesh_sizes_interpolate_and_refine() {
    let (pts, tris) = cube();
    // Sizes at the cube's corners: small at the origin, large elsewhere,
    // interpolated over their Delaunay tetrahedralization.
    let sizes: Vec<f64> = (0..8).map(|i| if i == 0 { 0.08 } else { 0.8 }).collect();
    let bg = Arc::new(Background::from_points(pts.clone(), sizes).unwrap());
    assert!((bg.size_at([0.0, 0.0, 0.0]).unwrap() - 0.08).abs() < 1e-12);
    assert!((bg.size_at([1.0, 1.0, 1.0]).unwrap() - 0.8).abs() < 1e-12);
    // Outside: clamped to a boundary cell.
    assert!(bg.size_at([-5.0, 0.5, 0.5]).is_some());
    let opts = RefineOptions {
        sizing: Sizing::Background(bg.clone()),
        ..RefineOptions::default()
    };
    let r = refine(&pts, &tris, &opts).unwrap();
    check_recovered(&pts, &tris, &r.rec).unwrap();
    assert_eq!(r.report.remaining_too_big, 0);
    let rp = &r.rec.points;
    for t in &r.rec.mesh.tets {
        let p = t.map(|q| rp[q as usize]);
        let c = circumcenter(&p).unwrap();
        let h = bg.size_at(c).unwrap();
        assert!(dist(c, p[0]) <= cell_radius_bound(h) * (1.0 + 1e-9));
    }
    let (near, _) = mean_edge(rp, &r.rec.mesh.tets, 0.0, 0.25);
    let (far, _) = mean_edge(rp, &r.rec.mesh.tets, 1.2, 2.0);
    assert!(far > 2.0 * near, "near {near}, far {far}");
}

#[test]
fn sizes_of_zero_mean_no_constraint() {
    let (pts, tris) = cube();
    let bg = Background::from_points(pts.clone(), vec![0.0; 8]).unwrap();
    let opts = RefineOptions {
        sizing: Sizing::Background(Arc::new(bg)),
        ..RefineOptions::default()
    };
    let r = refine(&pts, &tris, &opts).unwrap();
    let plain = refine(&pts, &tris, &RefineOptions::default()).unwrap();
    assert_eq!(r.rec.mesh.tets, plain.rec.mesh.tets);
}
