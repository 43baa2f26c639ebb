//! 3D domains: hole and region points, internal facets (several closed
//! regions), the convex hull kept with `-c`, and the volume check extended
//! to regions.

use delone::model::plc::{Facet, Plc, Region};
use delone::tet::recover::{
    check_recovered, recover_domain, Domain, RecoverError, RecoverOptions, Recovered,
};

mod solids;
use solids::add_box;

fn volume(r: &Recovered) -> f64 {
    r.regions.iter().map(|g| g.volume).sum()
}

fn run(pts: &[[f64; 3]], tris: &[[u32; 3]], d: &Domain) -> Recovered {
    let r = recover_domain(pts, tris, &RecoverOptions::default(), d).unwrap();
    check_recovered(pts, tris, &r).unwrap();
    assert_eq!(r.tet_region.len(), r.mesh.tets.len());
    let counted: usize = r.regions.iter().map(|g| g.tets).sum();
    assert_eq!(counted, r.mesh.tets.len());
    r
}

fn region(point: [f64; 3], attribute: f64) -> Region {
    Region {
        point,
        attribute,
        max_volume: None,
    }
}

/// A 3-cube with a unit cubic cavity in the middle.
fn cube_with_cavity() -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let (mut pts, mut tris) = (Vec::new(), Vec::new());
    add_box(&mut pts, &mut tris, [0.0; 3], [3.0; 3]);
    add_box(&mut pts, &mut tris, [1.0; 3], [2.0; 3]);
    (pts, tris)
}

#[test]
fn hole_point_removes_the_cavity_and_a_region_point_keeps_it() {
    let (pts, tris) = cube_with_cavity();
    // Parity alone: the nested surface bounds a cavity.
    let r = run(&pts, &tris, &Domain::default());
    assert_eq!(r.regions.len(), 1);
    assert!((volume(&r) - 26.0).abs() < 1e-9);
    // A hole point there: the same, and it is counted.
    let d = Domain {
        holes: vec![[1.5, 1.5, 1.5]],
        ..Domain::default()
    };
    let r = run(&pts, &tris, &d);
    assert_eq!(r.report.holes_removed, 1);
    assert!((volume(&r) - 26.0).abs() < 1e-9);
    // A region point in the inner cube makes it material: two regions.
    let d = Domain {
        regions: vec![region([1.5, 1.5, 1.5], 4.0)],
        ..Domain::default()
    };
    let r = run(&pts, &tris, &d);
    assert_eq!(r.regions.len(), 2);
    assert!((volume(&r) - 27.0).abs() < 1e-9);
    let inner = r.regions.iter().find(|g| g.seed == Some(0)).unwrap();
    assert_eq!(inner.attribute, 4.0);
    assert!((inner.volume - 1.0).abs() < 1e-12);
    let outer = r.regions.iter().find(|g| g.seed.is_none()).unwrap();
    assert_eq!(outer.attribute, 5.0);
    // The cavity's 12 triangles are now interior faces.
    assert!(r.interior_faces.len() >= 12);
    // A hole point in the shell removes the shell: nothing left.
    let d = Domain {
        holes: vec![[0.5, 0.5, 0.5]],
        ..Domain::default()
    };
    let r = recover_domain(&pts, &tris, &RecoverOptions::default(), &d).unwrap();
    assert!(r.mesh.tets.is_empty() && r.regions.is_empty());
}

#[test]
fn seeds_on_the_surface_are_typed_errors() {
    let (pts, tris) = cube_with_cavity();
    for (p, kind) in [
        ([1.0, 1.5, 1.5], "hole"),    // on an inner face
        ([1.0, 1.0, 1.7], "hole"),    // on an inner edge
        ([2.0, 2.0, 2.0], "region"),  // on an inner vertex
        ([3.0, 0.25, 0.5], "region"), // on an outer face
    ] {
        let mut d = Domain::default();
        if kind == "hole" {
            d.holes = vec![[9.0, 9.0, 9.0], p];
        } else {
            d.regions = vec![region([0.5; 3], 1.0), region(p, 2.0)];
        }
        let e = recover_domain(&pts, &tris, &RecoverOptions::default(), &d).unwrap_err();
        assert_eq!(e, RecoverError::SeedOnSurface { kind, index: 1 }, "{p:?}");
        assert!(e.to_string().contains(&format!("{kind} point 1")));
    }
    // Seeds outside the convex hull lie in the exterior: harmless.
    let d = Domain {
        holes: vec![[-5.0, 0.0, 0.0]],
        regions: vec![region([9.0, 9.0, 9.0], 3.0)],
        convex_hull: false,
    };
    let r = run(&pts, &tris, &d);
    assert!((volume(&r) - 26.0).abs() < 1e-9);
}

#[test]
fn two_cubes_sharing_a_face_are_two_regions() {
    // The shared square x = 1 is an internal facet: its edges are in three
    // facets. As a PLC with quadrilateral facets.
    let mut pts = Vec::new();
    for z in [0.0, 1.0] {
        for y in [0.0, 1.0] {
            for x in [0.0, 1.0, 2.0] {
                pts.push([x, y, z]);
            }
        }
    }
    let id = |x: u32, y: u32, z: u32| x + 3 * y + 6 * z;
    let mut plc = Plc::new(pts);
    let mut quad = |q: [u32; 4], marker: i32| {
        let mut f = Facet::polygon(q.to_vec());
        f.marker = marker;
        plc.facets.push(f);
    };
    for x in 0..2 {
        quad(
            [id(x, 0, 0), id(x + 1, 0, 0), id(x + 1, 1, 0), id(x, 1, 0)],
            1,
        );
        quad(
            [id(x, 0, 1), id(x + 1, 0, 1), id(x + 1, 1, 1), id(x, 1, 1)],
            1,
        );
        quad(
            [id(x, 0, 0), id(x + 1, 0, 0), id(x + 1, 0, 1), id(x, 0, 1)],
            1,
        );
        quad(
            [id(x, 1, 0), id(x + 1, 1, 0), id(x + 1, 1, 1), id(x, 1, 1)],
            1,
        );
    }
    for x in 0..3 {
        quad(
            [id(x, 0, 0), id(x, 1, 0), id(x, 1, 1), id(x, 0, 1)],
            2 + x as i32,
        );
    }
    plc.validate().unwrap();
    let (tris, _) = plc.triangulate_facets().unwrap();
    let r = run(&plc.points, &tris, &Domain::default());
    assert_eq!(r.regions.len(), 2);
    for g in &r.regions {
        assert!((g.volume - 1.0).abs() < 1e-12, "{g:?}");
        assert!(g.seed.is_none() && !g.exterior);
    }
    // Unseeded regions get their own attributes 1, 2.
    let mut attrs: Vec<f64> = r.regions.iter().map(|g| g.attribute).collect();
    attrs.sort_by(f64::total_cmp);
    assert_eq!(attrs, vec![1.0, 2.0]);
    // The internal square is covered by interior faces on both sides' tets,
    // and every tetrahedron's region matches the side of x = 1 it is on.
    let area: f64 = r
        .interior_faces
        .iter()
        .map(|f| {
            let [a, b, c] = f.map(|q| r.points[q as usize]);
            let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
            let n = [
                u[1] * v[2] - u[2] * v[1],
                u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0],
            ];
            0.5 * (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt()
        })
        .sum();
    assert!((area - 1.0).abs() < 1e-12);
    let side = |t: usize| {
        let cx: f64 = r.mesh.tets[t]
            .iter()
            .map(|&q| r.points[q as usize][0])
            .sum::<f64>()
            / 4.0;
        cx > 1.0
    };
    for t in 0..r.mesh.tets.len() {
        for u in 0..r.mesh.tets.len() {
            if side(t) == side(u) {
                assert_eq!(r.tet_region[t], r.tet_region[u]);
            } else {
                assert_ne!(r.tet_region[t], r.tet_region[u]);
            }
        }
    }
    // Tetrahedra across the internal facet stay neighbours.
    let across = r.mesh.neighbors.iter().enumerate().any(|(t, nb)| {
        nb.iter()
            .any(|&u| u != delone::NONE && r.tet_region[t] != r.tet_region[u as usize])
    });
    assert!(across);
}

#[test]
fn convex_hull_is_kept_with_c() {
    // An L-shaped prism: the unit-square notch [1,2]x[1,2] is missing from
    // the 2x2 square, height 1. Its convex hull has volume 3.5.
    let xy = [
        [0.0, 0.0],
        [2.0, 0.0],
        [2.0, 1.0],
        [1.0, 1.0],
        [1.0, 2.0],
        [0.0, 2.0],
    ];
    let mut pts = Vec::new();
    for z in [0.0, 1.0] {
        for p in xy {
            pts.push([p[0], p[1], z]);
        }
    }
    let mut plc = Plc::new(pts);
    plc.facets.push(Facet::polygon((0..6).collect()));
    plc.facets.push(Facet::polygon((6..12).collect()));
    for i in 0..6u32 {
        let j = (i + 1) % 6;
        plc.facets.push(Facet::polygon(vec![i, j, j + 6, i + 6]));
    }
    let (tris, _) = plc.triangulate_facets().unwrap();
    let r = run(&plc.points, &tris, &Domain::default());
    assert!((volume(&r) - 3.0).abs() < 1e-12);
    let d = Domain {
        convex_hull: true,
        ..Domain::default()
    };
    let r = run(&plc.points, &tris, &d);
    assert!((volume(&r) - 3.5).abs() < 1e-12);
    assert_eq!(r.regions.len(), 2);
    let ext = &r.regions[0];
    assert!(ext.exterior && ext.attribute == 0.0);
    assert!((ext.volume - 0.5).abs() < 1e-12);
    // Hull faces off the surface name no triangle.
    assert!(r.boundary_triangle.contains(&delone::NONE));
    // A hole point in the notch removes it again.
    let d = Domain {
        convex_hull: true,
        holes: vec![[1.9, 1.1, 0.5]],
        ..Domain::default()
    };
    let r = run(&plc.points, &tris, &d);
    assert!((volume(&r) - 3.0).abs() < 1e-12);
    assert!(r.regions.iter().all(|g| !g.exterior));
}

#[test]
fn tetgen_example_meshes_with_regions_and_holes() {
    let Some(dir) = delone_testdata::corpus_path(env!("CARGO_MANIFEST_DIR"), "3d_plc") else {
        return;
    };
    let f =
        delone_io::read_poly3d(&std::fs::read(dir.join("tetgen_example.poly")).unwrap()).unwrap();
    let mut plc = Plc::new(f.points);
    for facet in f.facets {
        plc.facets.push(Facet {
            polygons: facet.polygons,
            holes: facet.holes,
            marker: facet.marker,
        });
    }
    plc.validate().unwrap();
    let (tris, _) = plc.triangulate_facets().unwrap();
    let d = Domain {
        holes: f.holes.clone(),
        regions: f
            .regions
            .iter()
            .map(|r| Region {
                point: r.point,
                attribute: r.attribute,
                max_volume: r.max_volume,
            })
            .collect(),
        convex_hull: false,
    };
    let r = run(&plc.points, &tris, &d);
    // Two regions, named by their points, with their volume bounds; the
    // two holes (the cavity box and the notch cut from the front) removed.
    assert_eq!(r.regions.len(), 2);
    assert_eq!(r.report.holes_removed, 2);
    let lower = r.regions.iter().find(|g| g.seed == Some(0)).unwrap();
    let upper = r.regions.iter().find(|g| g.seed == Some(1)).unwrap();
    assert_eq!((lower.attribute, lower.max_volume), (10.0, Some(0.001)));
    assert_eq!((upper.attribute, upper.max_volume), (20.0, Some(0.01)));
    // Box 2 x 2 x 5 cut by the slanted facet z = 4 - y/2; the cavity
    // 1.5 x 1.25 x 0.5 and the notch 1.5 x 1.5 x 0.5 are holes below it.
    assert!((upper.volume - 6.0).abs() < 1e-12, "{upper:?}");
    assert!(
        (lower.volume - (14.0 - 0.9375 - 1.125)).abs() < 1e-12,
        "{lower:?}"
    );
    // Without the hole points the notch box (closed by facet 20, one facet
    // from the outside) is a third region; the cavity (two facets deep) is
    // still removed by the parity rule.
    let d2 = Domain {
        holes: Vec::new(),
        ..d.clone()
    };
    let r2 = run(&plc.points, &tris, &d2);
    assert!((volume(&r2) - (20.0 - 0.9375)).abs() < 1e-9);
    assert_eq!(r2.regions.len(), 3);
}
