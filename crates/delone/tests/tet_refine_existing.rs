//! Refinement of an existing tetrahedral mesh (`refine_mesh`, TetGen `-r`).

use std::path::PathBuf;

use delone::tet::quality::{radius_edge_ratio, volume};
use delone::tet::recover::{check_recovered, recover, RecoverOptions, Recovered};
use delone::tet::refine::existing::{recovered_from_mesh, refine_mesh, RefineMeshError};
use delone::tet::refine::RefineOptions;

fn data_dir() -> Option<PathBuf> {
    delone_testdata::corpus_dir(env!("CARGO_MANIFEST_DIR"))
}

fn mesh_volume(pts: &[[f64; 3]], tets: &[[u32; 4]]) -> f64 {
    tets.iter()
        .map(|t| volume(&t.map(|q| pts[q as usize])))
        .sum()
}

fn area(pts: &[[f64; 3]], faces: &[[u32; 3]]) -> f64 {
    faces
        .iter()
        .map(|f| {
            let [a, b, c] = f.map(|q| pts[q as usize]);
            let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
            let w = [
                u[1] * v[2] - u[2] * v[1],
                u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0],
            ];
            0.5 * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt()
        })
        .sum()
}

/// `delone tet -p` of a model, then `-rq1.414` of its output.
fn refine_output_of(pts: &[[f64; 3]], tris: &[[u32; 3]], name: &str) {
    let ro = RecoverOptions {
        merge_coplanar: false,
        ..RecoverOptions::default()
    };
    let rec: Recovered = recover(pts, tris, &ro).unwrap();
    let opts = RefineOptions {
        max_radius_edge: Some(1.414),
        ..RefineOptions::default()
    };
    let r = refine_mesh(&rec.points, &rec.mesh.tets, &[], &[], &opts).unwrap();
    let out = &r.refined.rec;
    check_recovered(&rec.points, &r.triangles, out).unwrap();
    // The constraint triangles are the input mesh's boundary faces.
    assert_eq!(r.triangles.len(), rec.boundary.len());
    let (v0, v1) = (
        mesh_volume(&rec.points, &rec.mesh.tets),
        mesh_volume(&out.points, &out.mesh.tets),
    );
    assert!(
        (v0 - v1).abs() <= 1e-9 * v0.abs(),
        "{name}: volume {v0} -> {v1}"
    );
    let (a0, a1) = (
        area(&rec.points, &rec.boundary),
        area(&out.points, &out.boundary),
    );
    assert!((a0 - a1).abs() <= 1e-9 * a0, "{name}: area {a0} -> {a1}");
    let bad_before = rec
        .mesh
        .tets
        .iter()
        .filter(|t| radius_edge_ratio(&t.map(|q| rec.points[q as usize])) > 1.414)
        .count();
    if bad_before > 0 {
        assert!(out.mesh.tets.len() > rec.mesh.tets.len(), "{name}");
    }
    let bad = out
        .mesh
        .tets
        .iter()
        .filter(|t| radius_edge_ratio(&t.map(|q| out.points[q as usize])) > 1.414 + 1e-9)
        .count();
    assert_eq!(bad, r.refined.report.remaining_bad);
    assert!(
        bad <= r.refined.report.skipped + r.refined.report.flat,
        "{name}: {bad} bad cells, report {:?}",
        r.refined.report
    );
    eprintln!(
        "{name}: {} -> {} tets, {bad_before} -> {} above the bound",
        rec.mesh.tets.len(),
        out.mesh.tets.len(),
        bad
    );
}

#[test]
fn refines_the_output_of_tet_p() {
    let Some(dir) = data_dir() else { return };
    // Models the refinement converges on at q1.414 (cgal_hole, cgal_part,
    // cgal_eight run away in the -p path too at this bound: a known
    // limitation of the refinement, not of -r).
    for name in ["cgal_star", "cgal_cubes", "cgal_sphere"] {
        let s =
            delone_io::read_off(&std::fs::read(dir.join(format!("surf/off/{name}.off"))).unwrap())
                .unwrap();
        refine_output_of(&s.points, &s.triangles(), name);
    }
}

fn two_cubes() -> (Vec<[f64; 3]>, Vec<[u32; 4]>) {
    // A 2 x 1 x 1 box of 12 points cut into tetrahedra (Kuhn subdivision of
    // each unit cube).
    let pts: Vec<[f64; 3]> = (0..12)
        .map(|i| [(i % 3) as f64, ((i / 3) % 2) as f64, (i / 6) as f64])
        .collect();
    let id = |x: u32, y: u32, z: u32| x + 3 * y + 6 * z;
    let mut tets = Vec::new();
    for x0 in 0..2 {
        let c = |dx: u32, dy: u32, dz: u32| id(x0 + dx, dy, dz);
        let (o, d) = (c(0, 0, 0), c(1, 1, 1));
        for (a, b) in [
            (c(1, 0, 0), c(1, 1, 0)),
            (c(1, 1, 0), c(0, 1, 0)),
            (c(0, 1, 0), c(0, 1, 1)),
            (c(0, 1, 1), c(0, 0, 1)),
            (c(0, 0, 1), c(1, 0, 1)),
            (c(1, 0, 1), c(1, 0, 0)),
        ] {
            tets.push([o, a, b, d]);
        }
    }
    // Orient them all the same way.
    for t in &mut tets {
        let p = t.map(|q| pts[q as usize]);
        if volume(&p) < 0.0 {
            t.swap(0, 1);
        }
    }
    (pts, tets)
}

#[test]
fn region_attributes_make_interfaces() {
    let (pts, tets) = two_cubes();
    let attrs: Vec<f64> = (0..tets.len())
        .map(|t| if t < 6 { 1.0 } else { 7.0 })
        .collect();
    let m = recovered_from_mesh(&pts, &tets, &attrs, &[]).unwrap();
    // 2 + 2 + 4 * 4 boundary triangles... the Kuhn cubes have 2 per square:
    // 10 squares on the boundary, 1 interface square.
    assert_eq!(m.rec.boundary.len(), 20);
    assert_eq!(m.rec.interior_faces.len(), 2);
    let opts = RefineOptions {
        max_volume: Some(0.005),
        ..RefineOptions::default()
    };
    let r = refine_mesh(&pts, &tets, &attrs, &[], &opts).unwrap();
    let out = &r.refined.rec;
    check_recovered(&pts, &r.triangles, out).unwrap();
    assert_eq!(out.regions.len(), 2);
    assert_eq!(out.regions[0].attribute, 1.0);
    assert_eq!(out.regions[1].attribute, 7.0);
    for g in &out.regions {
        assert!((g.volume - 1.0).abs() < 1e-9, "{g:?}");
        assert!(g.tets > 50);
    }
    // Without attributes there is no interface.
    let plain = recovered_from_mesh(&pts, &tets, &[], &[]).unwrap();
    assert!(plain.rec.interior_faces.is_empty());
    // A listed face inside becomes an internal facet.
    let inner = m.rec.interior_faces[0];
    let listed = recovered_from_mesh(&pts, &tets, &[], &[inner]).unwrap();
    assert_eq!(listed.rec.interior_faces.len(), 1);
    assert_eq!(listed.listed.iter().filter(|&&l| l == 0).count(), 1);
}

#[test]
fn bad_meshes_are_refused_naming_the_item() {
    let (pts, tets) = two_cubes();
    let mut t = tets.clone();
    t[3].swap(1, 2);
    assert_eq!(
        recovered_from_mesh(&pts, &t, &[], &[]).unwrap_err(),
        RefineMeshError::Inverted { tet: 3 }
    );
    let mut t = tets.clone();
    t[5][2] = 99;
    assert_eq!(
        recovered_from_mesh(&pts, &t, &[], &[]).unwrap_err(),
        RefineMeshError::BadIndex { tet: 5 }
    );
    // A copy of a tetrahedron overlaps it.
    let mut t = tets.clone();
    t.push(t[0]);
    assert!(matches!(
        recovered_from_mesh(&pts, &t, &[], &[]).unwrap_err(),
        RefineMeshError::NonManifold { tet: 12 } | RefineMeshError::Overlap { tet: 12 }
    ));
    // Three tetrahedra on one face.
    let fan = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
        [0.2, 0.2, 2.0],
    ];
    let e = recovered_from_mesh(&fan, &[[0, 1, 2, 3], [0, 2, 1, 4], [0, 1, 2, 5]], &[], &[]);
    assert_eq!(e.unwrap_err(), RefineMeshError::NonManifold { tet: 2 });
    let mut p = pts.clone();
    p[4][1] = f64::NAN;
    assert_eq!(
        recovered_from_mesh(&p, &tets, &[], &[]).unwrap_err(),
        RefineMeshError::InvalidCoordinate { index: 4 }
    );
    assert_eq!(
        recovered_from_mesh(&pts, &tets, &[1.0], &[]).unwrap_err(),
        RefineMeshError::AttributeCount {
            expected: 12,
            got: 1
        }
    );
    assert_eq!(
        recovered_from_mesh(&pts, &tets, &[], &[[0, 1, 2], [0, 2, 11]]).unwrap_err(),
        RefineMeshError::FaceNotInMesh { face: 0 }
    );
    // Flat tetrahedron.
    let flat = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
    ];
    assert_eq!(
        recovered_from_mesh(&flat, &[[0, 1, 2, 3]], &[], &[]).unwrap_err(),
        RefineMeshError::Degenerate { tet: 0 }
    );
    // Two tetrahedra on the same side of their common face.
    let over = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.1, 0.1, 0.5],
    ];
    let e = recovered_from_mesh(&over, &[[0, 1, 2, 3], [0, 1, 2, 4]], &[], &[]);
    assert!(
        matches!(
            e,
            Err(RefineMeshError::Overlap { tet: 1 }) | Err(RefineMeshError::Inverted { tet: 1 })
        ),
        "{e:?}"
    );
}
