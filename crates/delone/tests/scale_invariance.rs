//! Coordinates at every scale: corpus models scaled by powers of two (and
//! of ten) across the double range give the same mesh, pass the checkers
//! and have the same statistics (angles bit for bit, volumes and areas
//! scaled), in 2D (points, `-p`, `-pq`) and 3D (points, `-p`, `-pq`).
//! Needs `../shared/data` (the corpus); says so and fails when it is
//! missing, instead of passing without testing anything.

mod common;

use delone::tet::quality::TetStats;
use delone::tet::recover::{check_recovered, recover, RecoverOptions};
use delone::tri::quality::TriStats;
use delone::tri::{check_cdt, constrained_triangulation, CdtOptions};

fn data() -> std::path::PathBuf {
    common::data_dir().expect("../shared/data (the test corpus) not found above the crate")
}

/// Powers of two spanning the double range (exact scalings).
const POW2: [i32; 8] = [-1000, -500, -333, -100, 0, 100, 400, 990];
/// Powers of ten (inexact scalings: accepted, checkers pass, counts may
/// differ only where rounding changes a predicate; on these models it does
/// not).
const POW10: [f64; 7] = [1e-150, 1e-100, 1e-30, 1.0, 1e30, 1e120, 1e300];

fn sphere() -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let s = delone_io::read_off(&std::fs::read(data().join("surf/off/cgal_sphere.off")).unwrap())
        .unwrap();
    (s.points.clone(), s.triangles())
}

fn scale3(p: &[[f64; 3]], f: f64) -> Vec<[f64; 3]> {
    p.iter().map(|q| q.map(|c| c * f)).collect()
}

fn scale2(p: &[[f64; 2]], f: f64) -> Vec<[f64; 2]> {
    p.iter().map(|q| q.map(|c| c * f)).collect()
}

/// The volume `v` measured at scale 1, at scale `2^k` (exact unless it
/// leaves the normal range).
fn pow2_cubed(v: f64, k: i32) -> f64 {
    let mut v = v;
    for _ in 0..3 {
        v *= 2f64.powi(k);
    }
    v
}

#[test]
fn tet_plc_same_mesh_checks_and_stats_at_every_power_of_two_scale() {
    let (pts, tris) = sphere();
    let base = recover(&pts, &tris, &RecoverOptions::default()).unwrap();
    let st1 = TetStats::of(&base.points, &base.mesh.tets);
    for k in POW2 {
        let f = 2f64.powi(k);
        let p = scale3(&pts, f);
        assert!(p.iter().flatten().all(|c| c.is_finite()));
        delone::tet::intersect::check_self_intersections(&p, &tris)
            .unwrap_or_else(|e| panic!("2^{k}: {e}"));
        let r =
            recover(&p, &tris, &RecoverOptions::default()).unwrap_or_else(|e| panic!("2^{k}: {e}"));
        check_recovered(&p, &tris, &r).unwrap_or_else(|v| panic!("2^{k}: {v}"));
        assert_eq!(r.mesh.tets, base.mesh.tets, "2^{k}: connectivity");
        let st = TetStats::of(&r.points, &r.mesh.tets);
        assert_eq!(st.min_dihedral, st1.min_dihedral, "2^{k}");
        assert_eq!(st.max_dihedral, st1.max_dihedral, "2^{k}");
        assert_eq!(st.dihedral_histogram, st1.dihedral_histogram, "2^{k}");
        assert_eq!(st.min_radius_edge, st1.min_radius_edge, "2^{k}");
        assert_eq!(st.min_shape, st1.min_shape, "2^{k}");
        assert_eq!(st.mean_shape, st1.mean_shape, "2^{k}");
        let want = pow2_cubed(st1.min_volume, k);
        if want.is_normal() {
            assert_eq!(st.min_volume, want, "2^{k}");
        }
        let want = pow2_cubed(base.regions[0].volume, k);
        if want.is_normal() {
            assert!(
                (r.regions[0].volume - want).abs() <= 1e-12 * want.abs(),
                "2^{k}: region volume {} vs {want}",
                r.regions[0].volume
            );
        }
    }
}

#[test]
fn tet_plc_accepted_and_checked_at_every_power_of_ten_scale() {
    let (pts, tris) = sphere();
    let base = recover(&pts, &tris, &RecoverOptions::default()).unwrap();
    let st1 = TetStats::of(&base.points, &base.mesh.tets);
    for f in POW10 {
        let p = scale3(&pts, f);
        let r =
            recover(&p, &tris, &RecoverOptions::default()).unwrap_or_else(|e| panic!("{f:e}: {e}"));
        check_recovered(&p, &tris, &r).unwrap_or_else(|v| panic!("{f:e}: {v}"));
        assert_eq!(r.mesh.tets.len(), base.mesh.tets.len(), "{f:e}");
        let st = TetStats::of(&r.points, &r.mesh.tets);
        assert!((st.min_dihedral - st1.min_dihedral).abs() < 1e-6, "{f:e}");
        assert!((st.max_dihedral - st1.max_dihedral).abs() < 1e-6, "{f:e}");
        assert!(st.mean_shape.is_finite() && st.total_volume >= 0.0, "{f:e}");
        let want = st1.total_volume * f * f * f;
        if want.is_normal() {
            assert!((st.total_volume - want).abs() < 1e-9 * want, "{f:e}");
        }
    }
}

#[test]
fn tet_refine_same_mesh_at_power_of_two_scales() {
    use delone::tet::refine::{refine, RefineOptions};
    let (pts, tris) = sphere();
    let opts = RefineOptions {
        max_radius_edge: Some(2.0),
        ..Default::default()
    };
    let base = refine(&pts, &tris, &opts).unwrap();
    let mut bad = Vec::new();
    for k in [-1000, -500, -333, -100, -60, -30, 30, 100, 400, 990] {
        let p = scale3(&pts, 2f64.powi(k));
        let r = refine(&p, &tris, &opts).unwrap_or_else(|e| panic!("2^{k}: {e}"));
        check_recovered(&p, &tris, &r.rec).unwrap_or_else(|v| panic!("2^{k}: {v}"));
        if r.rec.mesh.tets != base.rec.mesh.tets {
            bad.push((k, r.rec.mesh.tets.len(), r.rec.points.len()));
        }
    }
    assert!(
        bad.is_empty(),
        "base {} tets; differing (k, tets, points): {bad:?}",
        base.rec.mesh.tets.len()
    );
}

#[test]
fn tet_points_same_mesh_at_every_scale() {
    let (pts, _) = sphere();
    let base = delone::tetrahedralize(&pts).unwrap();
    for k in POW2 {
        let p = scale3(&pts, 2f64.powi(k));
        let m = delone::tetrahedralize(&p).unwrap_or_else(|e| panic!("2^{k}: {e}"));
        delone::tet::validate(&p, &m).unwrap_or_else(|v| panic!("2^{k}: {v}"));
        assert_eq!(m.tets, base.tets, "2^{k}");
    }
    for f in POW10 {
        let p = scale3(&pts, f);
        let m = delone::tetrahedralize(&p).unwrap_or_else(|e| panic!("{f:e}: {e}"));
        delone::tet::validate(&p, &m).unwrap_or_else(|v| panic!("{f:e}: {v}"));
    }
}

#[test]
fn tri_pslg_same_mesh_checks_and_stats_at_every_scale() {
    for name in ["A.poly", "la.poly"] {
        let g = common::load_poly(&data().join("2d").join(name));
        let base = constrained_triangulation(&g, CdtOptions::default()).unwrap();
        let st1 = TriStats::new(&base.points, &base.triangles).unwrap();
        let refined = |g: &delone::model::pslg::Pslg| {
            let c = constrained_triangulation(g, CdtOptions::default()).unwrap();
            let o = delone::tri::RefineOptions {
                min_angle: Some(25.0),
                ..Default::default()
            };
            delone::tri::refine(&c, &o).unwrap().mesh
        };
        let base_q = refined(&g);
        for k in POW2 {
            let f = 2f64.powi(k);
            // Only the mesh's points are scaled: the region and hole
            // points keep theirs where it matters not (regions) or are
            // scaled alike (holes).
            let mut h = g.clone();
            h.points = scale2(&g.points, f);
            h.holes = scale2(&g.holes, f);
            for r in &mut h.regions {
                r.point = r.point.map(|c| c * f);
            }
            let c = constrained_triangulation(&h, CdtOptions::default())
                .unwrap_or_else(|e| panic!("{name} 2^{k}: {e}"));
            check_cdt(&h, &c).unwrap_or_else(|v| panic!("{name} 2^{k}: {v}"));
            assert_eq!(c.triangles, base.triangles, "{name} 2^{k}");
            let st = TriStats::new(&c.points, &c.triangles).unwrap();
            assert_eq!(st.min_angle, st1.min_angle, "{name} 2^{k}");
            assert_eq!(st.max_angle, st1.max_angle, "{name} 2^{k}");
            assert_eq!(st.angle_histogram, st1.angle_histogram, "{name} 2^{k}");
            let want = st1.total_area * f * f;
            if want.is_normal() {
                assert!((st.total_area - want).abs() <= 1e-12 * want, "{name} 2^{k}");
            }
            let q = refined(&h);
            check_cdt(&h, &q).unwrap_or_else(|v| panic!("{name} -q 2^{k}: {v}"));
            assert_eq!(q.triangles, base_q.triangles, "{name} -q 2^{k}");
        }
        for f in POW10 {
            let mut h = g.clone();
            h.points = scale2(&g.points, f);
            h.holes = scale2(&g.holes, f);
            let c = constrained_triangulation(&h, CdtOptions::default())
                .unwrap_or_else(|e| panic!("{name} {f:e}: {e}"));
            // The region points keep scale 1: they must not upset the
            // checker (they are not mesh points).
            check_cdt(&h, &c).unwrap_or_else(|v| panic!("{name} {f:e}: {v}"));
            assert_eq!(c.triangles.len(), base.triangles.len(), "{name} {f:e}");
            let st = TriStats::new(&c.points, &c.triangles).unwrap();
            assert!((st.min_angle - st1.min_angle).abs() < 1e-6, "{name} {f:e}");
        }
    }
}

#[test]
fn tri_points_same_mesh_at_every_scale() {
    let (pts, _) = sphere();
    let pts: Vec<[f64; 2]> = pts.iter().map(|p| [p[0], p[1]]).collect();
    let base = delone::triangulate(&pts).unwrap();
    for k in POW2 {
        let p = scale2(&pts, 2f64.powi(k));
        let m = delone::triangulate(&p).unwrap_or_else(|e| panic!("2^{k}: {e}"));
        delone::tri::validate(&p, &m).unwrap_or_else(|v| panic!("2^{k}: {v}"));
        assert_eq!(m.triangles, base.triangles, "2^{k}");
    }
}

#[test]
fn dynamic_range_beyond_exact_arithmetic_is_refused_naming_the_coordinate() {
    let (mut pts, tris) = sphere();
    pts[7][1] = 1e-60;
    let e = recover(&pts, &tris, &RecoverOptions::default()).unwrap_err();
    assert!(e.to_string().contains("point 7"), "{e}");
    let mut plc = delone::model::plc::Plc::from_triangles(pts.clone(), &tris);
    assert!(matches!(
        plc.validate(),
        Err(delone::Error::CoordinateRange {
            index: 7,
            axis: 1,
            ..
        })
    ));
    plc.points[7][1] = 1e-40;
    assert!(plc.validate().is_ok());
    let e = delone::tetrahedralize(&[
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1e-50, 0.0, 0.0],
    ]);
    assert!(matches!(
        e,
        Err(delone::Error::CoordinateRange {
            index: 3,
            axis: 0,
            ..
        })
    ));
    let e = delone::triangulate(&[[1.0, 0.0], [0.0, 1.0], [0.0, 0.0], [1e-70, 0.5]]);
    assert!(matches!(
        e,
        Err(delone::Error::CoordinateRange {
            index: 3,
            axis: 0,
            ..
        })
    ));
    assert!(delone::triangulate(&[[1.0, 0.0], [0.0, 1.0], [0.0, 0.0], [1e-60, 0.5]]).is_ok());
}
