//! The optimisation after a refinement keeps the refinement's bounds
//! (`OptimizeOptions::keeping`, and `max_radius_edge` when asked): no
//! tetrahedron above the radius-edge or volume bound, on a cube, a Schönhardt prism and TetGen's two-region
//! example PLC with its own regional volume bounds; a graded sizing.

use delone::tet::optimize::{optimize, OptimizeOptions};
use delone::tet::quality::{radius_edge_ratio, volume, TetStats};
use delone::tet::recover::{check_recovered, recover_marked, Domain, RecoverOptions, Recovered};
use delone::tet::refine::{refine, refine_recovered, RefineOptions};

mod solids;
use solids::{cuboid, schonhardt};

/// Largest radius-edge ratio and, per region, largest volume.
fn worst(r: &Recovered) -> (f64, Vec<f64>) {
    let mut ratio: f64 = 0.0;
    let mut vol = vec![0.0f64; r.regions.len().max(1)];
    for (t, tv) in r.mesh.tets.iter().enumerate() {
        let p = tv.map(|x| r.points[x as usize]);
        ratio = ratio.max(radius_edge_ratio(&p));
        let g = r.tet_region.get(t).copied().unwrap_or(0) as usize;
        vol[g] = vol[g].max(volume(&p).abs());
    }
    (ratio, vol)
}

/// Refines, then optimises with and without keeping the bounds; checks
/// the kept run and returns (kept, free) worst figures.
fn both(
    name: &str,
    pts: &[[f64; 3]],
    tris: &[[u32; 3]],
    ro: &RefineOptions,
) -> ((f64, Vec<f64>), (f64, Vec<f64>)) {
    let r = refine(pts, tris, ro).unwrap_or_else(|e| panic!("{name}: {e}"));
    // Refinement may leave a few cells above the bound near small input
    // angles (reported); the optimisation must not make them worse.
    let (r0, _) = worst(&r.rec);
    assert!(
        r0 <= ro.max_radius_edge.unwrap() * (1.0 + 1e-9) || r.report.remaining_bad > 0,
        "{name}: refinement {r0}"
    );
    let base = OptimizeOptions {
        input_points: Some(pts.len()),
        ..Default::default()
    };
    let mut kept = r.rec.clone();
    let keep = OptimizeOptions {
        max_radius_edge: ro.max_radius_edge,
        ..base.clone().keeping(ro)
    };
    let rep = optimize(&mut kept, &keep).unwrap();
    check_recovered(pts, tris, &kept).unwrap_or_else(|v| panic!("{name}: {v:?}"));
    assert!(
        rep.after.min_dihedral >= rep.before.min_dihedral - 1e-9,
        "{name}"
    );
    let mut free = r.rec.clone();
    optimize(&mut free, &base).unwrap();
    let total = |m: &Recovered| TetStats::of(&m.points, &m.mesh.tets).total_volume;
    assert!(
        (total(&kept) - total(&r.rec)).abs() <= 1e-9 * total(&r.rec),
        "{name}"
    );
    (worst(&kept), worst(&free))
}

#[test]
fn radius_edge_and_volume_bounds_survive_optimisation() {
    let (p, t) = cuboid(1.0, 1.0, 1.0);
    let ro = RefineOptions {
        max_radius_edge: Some(1.414),
        max_volume: Some(0.002),
        ..Default::default()
    };
    let ((ratio, vol), free) = both("cube", &p, &t, &ro);
    // The unconstrained optimisation does exceed them here, so this test
    // exercises the limits (if it stops doing so, pick a harder input).
    assert!(free.0 > 1.414 || free.1[0] > 0.002, "{free:?}");
    assert!(ratio <= 1.414 * (1.0 + 1e-12), "cube: radius-edge {ratio}");
    assert!(vol[0] <= 0.002 * (1.0 + 1e-12), "cube: volume {}", vol[0]);

    let (p, t) = schonhardt(0.5);
    let ro = RefineOptions {
        max_radius_edge: Some(1.414),
        ..Default::default()
    };
    let r0 = worst(&refine(&p, &t, &ro).unwrap().rec).0;
    let ((ratio, _), (free_ratio, _)) = both("schonhardt", &p, &t, &ro);
    assert!(
        ratio <= r0.max(1.414) * (1.0 + 1e-12),
        "schonhardt: radius-edge {ratio}, refinement's {r0} (free {free_ratio})"
    );
}

/// TetGen's example PLC (shared data): two regions with volume bounds 0.001
/// and 0.01, holes, an internal facet.
#[test]
fn regional_volume_bounds_survive_optimisation() {
    let Some(path) =
        delone_testdata::corpus_path(env!("CARGO_MANIFEST_DIR"), "3d_plc/tetgen_example.poly")
    else {
        return;
    };
    let bytes = std::fs::read(path).unwrap();
    let f = delone_io::read_poly3d(&bytes).unwrap();
    let mut plc = delone::model::plc::Plc::new(f.points);
    plc.holes = f.holes;
    plc.regions = f
        .regions
        .into_iter()
        .map(|r| delone::model::plc::Region {
            point: r.point,
            attribute: r.attribute,
            max_volume: r.max_volume,
        })
        .collect();
    plc.facets = f
        .facets
        .into_iter()
        .map(|x| delone::model::plc::Facet {
            polygons: x.polygons,
            holes: x.holes,
            marker: x.marker,
        })
        .collect();
    let (tris, _) = plc.triangulate_facets().unwrap();
    let p = plc.points.clone();
    let domain = Domain {
        holes: plc.holes.clone(),
        regions: plc.regions.clone(),
        convex_hull: false,
    };
    let rec = recover_marked(&p, &tris, &[], &RecoverOptions::default(), &domain).unwrap();
    assert_eq!(rec.regions.len(), 2);
    let ro = RefineOptions {
        max_radius_edge: Some(2.0),
        ..Default::default()
    };
    let r = refine_recovered(&p, &tris, &rec, &ro).unwrap();
    let bound =
        |m: &Recovered| -> Vec<f64> { m.regions.iter().map(|g| g.max_volume.unwrap()).collect() };
    let b = bound(&r.rec);
    let (_, v0) = worst(&r.rec);
    assert!(
        v0.iter().zip(&b).all(|(v, b)| v <= b),
        "refinement {v0:?} {b:?}"
    );
    let o = OptimizeOptions {
        input_points: Some(p.len()),
        ..Default::default()
    };
    let mut kept = r.rec.clone();
    optimize(&mut kept, &o.keeping(&ro)).unwrap();
    check_recovered(&p, &tris, &kept).unwrap_or_else(|v| panic!("{v:?}"));
    let (_, vol) = worst(&kept);
    for (g, b) in b.iter().enumerate() {
        assert!(vol[g] <= b * (1.0 + 1e-12), "region {g}: {} > {b}", vol[g]);
    }
}

/// A graded sizing (`-m`): every tetrahedron's circumradius stays within
/// the refinement's bound 0.612 h at its circumcentre.
#[test]
fn sizing_survives_optimisation() {
    use delone::tet::quality::circumcenter;
    use delone::tet::refine::sizing::{cell_radius_bound, Sizing};
    let h = |x: [f64; 3]| 0.08 + 0.25 * x[0];
    let (p, t) = cuboid(1.0, 1.0, 1.0);
    let ro = RefineOptions {
        max_radius_edge: Some(2.0),
        sizing: Sizing::function(h),
        ..Default::default()
    };
    let r = refine(&p, &t, &ro).unwrap();
    let excess = |m: &Recovered| {
        m.mesh
            .tets
            .iter()
            .map(|tv| {
                let q = tv.map(|x| m.points[x as usize]);
                let c = circumcenter(&q).unwrap();
                let rad = (0..3).map(|k| (c[k] - q[0][k]).powi(2)).sum::<f64>().sqrt();
                rad / cell_radius_bound(h(c))
            })
            .fold(0.0f64, f64::max)
    };
    let e0 = excess(&r.rec);
    let o = OptimizeOptions {
        input_points: Some(p.len()),
        ..Default::default()
    };
    let mut kept = r.rec.clone();
    optimize(&mut kept, &o.clone().keeping(&ro)).unwrap();
    check_recovered(&p, &t, &kept).unwrap_or_else(|v| panic!("{v:?}"));
    let e = excess(&kept);
    assert!(e <= e0.max(1.0) * (1.0 + 1e-9), "kept {e}, refinement {e0}");
    let mut free = r.rec.clone();
    optimize(&mut free, &o).unwrap();
    // Unconstrained, the optimisation does exceed it here.
    assert!(excess(&free) > 1.0 + 1e-6, "{}", excess(&free));
}
