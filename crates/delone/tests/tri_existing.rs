//! Refining an existing mesh (`-r`): `Cdt::from_mesh` on the output of a
//! constrained triangulation, refined again, checked by `check_cdt`; `.area`
//! bounds per triangle; typed errors naming the bad triangle or segment.

use delone::model::pslg::Pslg;
use delone::tri::constrain::{check_cdt, constrained_triangulation, Cdt, CdtOptions};
use delone::tri::existing::ExistingMesh;
use delone::tri::refine::{refine, RefineOptions};
use delone::Error;

mod common;
use common::{data_dir, load_poly};

fn area(p: &[[f64; 2]], v: &[u32; 3]) -> f64 {
    let [a, b, c] = v.map(|i| p[i as usize]);
    0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
}

/// The mesh a `-p` run writes (points, kept triangles, bounding segments).
fn as_written(cdt: &Cdt) -> (ExistingMesh, Pslg) {
    let segs: Vec<[u32; 2]> = cdt
        .segments
        .iter()
        .filter(|s| s.bounding)
        .map(|s| s.v)
        .collect();
    let m = ExistingMesh {
        points: cdt.points.clone(),
        triangles: cdt.triangles.clone(),
        segments: segs.clone(),
        segment_markers: cdt
            .segments
            .iter()
            .filter(|s| s.bounding)
            .map(|s| s.marker)
            .collect(),
        ..Default::default()
    };
    (m, Pslg::new(cdt.points.clone(), segs))
}

fn square_with_slit() -> Pslg {
    Pslg::new(
        vec![
            [0.0, 0.0],
            [1.0, 0.0],
            [1.0, 1.0],
            [0.0, 1.0],
            [0.3, 0.5],
            [0.7, 0.5],
        ],
        vec![[0, 1], [1, 2], [2, 3], [3, 0], [4, 5]],
    )
}

#[test]
fn refine_a_p_output_again() {
    let g = square_with_slit();
    let cdt = constrained_triangulation(&g, CdtOptions::default()).unwrap();
    let (m, g2) = as_written(&cdt);
    let again = Cdt::from_mesh(m).unwrap();
    assert_eq!(again.triangles, cdt.triangles);
    assert_eq!(again.neighbors, cdt.neighbors);
    check_cdt(&g2, &again).unwrap();
    let r = refine(
        &again,
        &RefineOptions {
            min_angle: Some(30.0),
            max_area: Some(0.01),
            ..Default::default()
        },
    )
    .unwrap();
    assert!(r.report.met);
    assert!(r.report.min_angle >= 30.0);
    assert!(r.mesh.triangles.len() > 100);
    check_cdt(&g2, &r.mesh).unwrap();
    // Twice: refine the refined mesh with a smaller area.
    let (m3, g3) = as_written(&r.mesh);
    let r3 = refine(
        &Cdt::from_mesh(m3).unwrap(),
        &RefineOptions {
            min_angle: Some(30.0),
            max_area: Some(0.002),
            ..Default::default()
        },
    )
    .unwrap();
    check_cdt(&g3, &r3.mesh).unwrap();
    assert!(r3.mesh.triangles.len() > 3 * r.mesh.triangles.len());
    for v in &r3.mesh.triangles {
        assert!(area(&r3.mesh.points, v) <= 0.002 * (1.0 + 1e-12));
    }
}

#[test]
fn area_file_bounds_per_triangle() {
    let g = square_with_slit();
    let cdt = constrained_triangulation(&g, CdtOptions::default()).unwrap();
    let (mut m, g2) = as_written(&cdt);
    // Left triangles (centroid x < 0.5): 0.001; the others: no bound.
    m.max_areas = m
        .triangles
        .iter()
        .map(|v| {
            let cx = v.iter().map(|&i| m.points[i as usize][0]).sum::<f64>() / 3.0;
            if cx < 0.5 {
                0.001
            } else {
                -1.0
            }
        })
        .collect();
    let bounded = m.max_areas.iter().filter(|&&a| a > 0.0).count();
    assert!(bounded > 0 && bounded < m.triangles.len());
    let r = refine(
        &Cdt::from_mesh(m).unwrap(),
        &RefineOptions {
            min_angle: None,
            regional_areas: true,
            ..Default::default()
        },
    )
    .unwrap();
    check_cdt(&g2, &r.mesh).unwrap();
    let mut small = 0;
    for (t, v) in r.mesh.triangles.iter().enumerate() {
        let b = r.mesh.max_areas[t];
        if b > 0.0 {
            assert!(area(&r.mesh.points, v) <= b * (1.0 + 1e-12), "triangle {t}");
            small += 1;
        }
    }
    assert!(small > 200, "{small} bounded triangles");
    // Without the regional switch the bounds are ignored.
    let (m, _) = as_written(&cdt);
    let plain = Cdt::from_mesh(ExistingMesh {
        max_areas: vec![0.001; m.triangles.len()],
        ..m
    })
    .unwrap();
    let r2 = refine(
        &plain,
        &RefineOptions {
            min_angle: None,
            ..Default::default()
        },
    )
    .unwrap();
    assert!(r2
        .mesh
        .triangles
        .iter()
        .any(|v| area(&r2.mesh.points, v) > 0.001));
}

#[test]
fn bad_meshes_are_named() {
    let pts = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [2.0, 2.0]];
    let mk = |triangles: Vec<[u32; 3]>, segments: Vec<[u32; 2]>| ExistingMesh {
        points: pts.clone(),
        triangles,
        segments,
        ..Default::default()
    };
    let e = Cdt::from_mesh(mk(vec![[0, 1, 2], [0, 3, 2]], vec![])).unwrap_err();
    assert!(e.to_string().contains("triangle 1"), "{e}");
    let e = Cdt::from_mesh(mk(vec![[0, 1, 2], [0, 1, 3]], vec![])).unwrap_err();
    assert!(e.to_string().contains("triangles 0 and 1"), "{e}");
    let e = Cdt::from_mesh(mk(vec![[0, 1, 2], [0, 2, 9]], vec![])).unwrap_err();
    assert!(matches!(
        e,
        Error::IndexOutOfRange {
            item: "triangle",
            index: 1,
            vertex: 9,
            ..
        }
    ));
    let e = Cdt::from_mesh(mk(vec![[0, 1, 2], [0, 2, 3]], vec![[1, 3]])).unwrap_err();
    assert!(e.to_string().contains("segment 0"), "{e}");
    // Two triangles touching at vertex 2 only.
    let e = Cdt::from_mesh(mk(vec![[0, 1, 2], [2, 4, 3]], vec![])).unwrap_err();
    assert!(e.to_string().contains("vertex 2"), "{e}");
    let e = Cdt::from_mesh(ExistingMesh {
        attributes: vec![1.0],
        ..mk(vec![[0, 1, 2], [0, 2, 3]], vec![])
    })
    .unwrap_err();
    assert!(matches!(e, Error::InconsistentMesh { .. }));
}

#[test]
fn shared_polys_refined_again() {
    let Some(dir) = data_dir() else {
        println!("note: shared/data not found; skipping");
        return;
    };
    for name in ["box", "double_hex", "la"] {
        let p = dir.join("2d").join(format!("{name}.poly"));
        assert!(p.is_file(), "{} is missing from the corpus", p.display());
        let g = load_poly(&p);
        let cdt = constrained_triangulation(&g, CdtOptions { convex_hull: true }).unwrap();
        let first = refine(&cdt, &RefineOptions::default()).unwrap();
        let (m, g2) = as_written(&first.mesh);
        let r = refine(
            &Cdt::from_mesh(m).unwrap(),
            &RefineOptions {
                min_angle: Some(30.0),
                ..Default::default()
            },
        )
        .unwrap();
        check_cdt(&g2, &r.mesh).unwrap_or_else(|v| panic!("{name}: {v}"));
        assert!(r.mesh.triangles.len() >= first.mesh.triangles.len());
    }
}
