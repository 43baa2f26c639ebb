//! Quality refinement on synthetic PSLGs: tiny input angles terminate with
//! the small angles reported, the Steiner budget is honoured, results are
//! deterministic, and every result is a valid constrained Delaunay mesh.

use delone::model::pslg::Pslg;
use delone::tri::constrain::{check_cdt, constrained_triangulation, CdtOptions};
use delone::tri::refine::{refine, RefineOptions, UnfixableReason};

fn min_angle(p: &[[f64; 2]], v: &[u32; 3]) -> f64 {
    let mut lo = 180.0f64;
    for k in 0..3 {
        let a = p[v[k] as usize];
        let b = p[v[(k + 1) % 3] as usize];
        let c = p[v[(k + 2) % 3] as usize];
        let (ux, uy) = (b[0] - a[0], b[1] - a[1]);
        let (vx, vy) = (c[0] - a[0], c[1] - a[1]);
        lo = lo.min(
            (ux * vy - uy * vx)
                .abs()
                .atan2(ux * vx + uy * vy)
                .to_degrees(),
        );
    }
    lo
}

/// A square with two segments from one corner, `deg` degrees apart (the
/// other angles at that corner are at least 37.5°).
fn wedge(deg: f64) -> Pslg {
    let a = (45.0 - 0.5 * deg).to_radians();
    let b = a + deg.to_radians();
    Pslg::new(
        vec![
            [0.0, 0.0],
            [4.0, 0.0],
            [4.0, 4.0],
            [0.0, 4.0],
            [3.0 * a.cos(), 3.0 * a.sin()],
            [3.0 * b.cos(), 3.0 * b.sin()],
        ],
        vec![[0, 1], [1, 2], [2, 3], [3, 0], [0, 4], [0, 5]],
    )
}

#[test]
fn tiny_input_angles_terminate() {
    for deg in [0.1, 1.0, 5.0, 15.0] {
        let g = wedge(deg);
        let cdt = constrained_triangulation(&g, CdtOptions::default()).unwrap();
        for q in [20.0, 30.0, 34.0] {
            let opts = RefineOptions {
                min_angle: Some(q),
                ..Default::default()
            };
            let r = refine(&cdt, &opts).unwrap();
            check_cdt(&g, &r.mesh).unwrap_or_else(|v| panic!("{deg}° q{q}: {v}"));
            assert!(!r.report.limit_reached, "{deg}° q{q}");
            println!(
                "{deg}° q{q}: {} triangles, min angle {:.3}, {} unfixable",
                r.mesh.triangles.len(),
                r.report.min_angle,
                r.report.unfixable.len()
            );
            // Every triangle below the bound is reported, at the small angle
            // at vertex 0 (the only input angle below 45°).
            let low: Vec<usize> = (0..r.mesh.triangles.len())
                .filter(|&t| min_angle(&r.mesh.points, &r.mesh.triangles[t]) < q - 1e-9)
                .collect();
            assert_eq!(low.len(), r.report.unfixable.len());
            for u in &r.report.unfixable {
                assert!(low.contains(&(u.triangle as usize)));
                match u.reason {
                    UnfixableReason::SmallInputAngle { apex, input_angle } => {
                        assert_eq!(apex, 0);
                        assert!((input_angle - deg).abs() < 1e-6, "{input_angle} vs {deg}");
                    }
                    other => panic!("{deg}° q{q}: {other:?}"),
                }
            }
            if deg >= q {
                assert!(r.report.met);
            }
        }
    }
}

#[test]
fn steiner_budget_and_determinism() {
    let g = wedge(3.0);
    let cdt = constrained_triangulation(&g, CdtOptions::default()).unwrap();
    let opts = RefineOptions {
        min_angle: Some(30.0),
        max_area: Some(0.001),
        max_steiner: Some(50),
        ..Default::default()
    };
    let r = refine(&cdt, &opts).unwrap();
    assert!(r.report.limit_reached && !r.report.met);
    assert_eq!(r.report.segment_splits + r.report.circumcenters, 50);
    assert_eq!(r.mesh.points.len(), cdt.points.len() + 50);
    assert!(r
        .report
        .unfixable
        .iter()
        .any(|u| u.reason == UnfixableReason::SteinerLimit));
    check_cdt(&g, &r.mesh).unwrap();
    let full = RefineOptions {
        max_steiner: None,
        ..opts
    };
    let a = refine(&cdt, &full).unwrap();
    let b = refine(&cdt, &full).unwrap();
    assert_eq!(a, b);
    assert!(a.report.segment_splits + a.report.circumcenters > 50);
}

#[test]
fn random_pslgs_refine_validly() {
    // Random segments (crossing ones too) inside a box, with a xorshift generator.
    let mut s = 0x9e37_79b9_7f4a_7c15u64;
    let mut rnd = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    for case in 0..20 {
        let mut pts = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let mut segs = vec![[0, 1], [1, 2], [2, 3], [3, 0]];
        for _ in 0..6 {
            let n = pts.len() as u32;
            pts.push([0.05 + 0.9 * rnd(), 0.05 + 0.9 * rnd()]);
            pts.push([0.05 + 0.9 * rnd(), 0.05 + 0.9 * rnd()]);
            segs.push([n, n + 1]);
        }
        let g = Pslg::new(pts, segs);
        let cdt = constrained_triangulation(&g, CdtOptions::default()).unwrap();
        let r = refine(
            &cdt,
            &RefineOptions {
                min_angle: Some(25.0),
                max_steiner: Some(200_000),
                ..Default::default()
            },
        )
        .unwrap();
        check_cdt(&g, &r.mesh).unwrap_or_else(|v| panic!("case {case}: {v}"));
        assert!(!r.report.limit_reached, "case {case}");
        for u in &r.report.unfixable {
            assert!(
                matches!(u.reason, UnfixableReason::SmallInputAngle { .. }),
                "case {case}: {u:?}"
            );
        }
    }
}

#[test]
fn cavity_insertion_report_and_interior_segments() {
    // A rectangle split by a slanted interior segment: both sides of it are
    // refined (its splits open cavities on both sides), its pieces stay
    // edges, and the report's figures agree with the mesh.
    let g = Pslg::new(
        vec![
            [0.0, 0.0],
            [2.0, 0.0],
            [2.0, 1.0],
            [0.0, 1.0],
            [1.0, 0.0],
            [1.1, 1.0],
        ],
        vec![[0, 4], [4, 1], [1, 2], [2, 5], [5, 3], [3, 0], [4, 5]],
    );
    let cdt = constrained_triangulation(&g, CdtOptions::default()).unwrap();
    let opts = RefineOptions {
        min_angle: Some(32.0),
        max_area: Some(0.002),
        ..Default::default()
    };
    let r = refine(&cdt, &opts).unwrap();
    check_cdt(&g, &r.mesh).unwrap();
    assert!(r.report.met, "{:?}", r.report.unfixable.first());
    let steiner = r.mesh.points.len() - cdt.points.len();
    assert_eq!(steiner, r.report.segment_splits + r.report.circumcenters);
    // Every insertion replaces at least one triangle; each adds two.
    assert!(r.report.cavity_triangles >= steiner);
    // Euler for a disc: T = 2V - B - 2 (B boundary edges = boundary vertices).
    let b = r
        .mesh
        .neighbors
        .iter()
        .flatten()
        .filter(|&&n| n == delone::NONE)
        .count();
    assert_eq!(r.mesh.triangles.len(), 2 * r.mesh.points.len() - b - 2);
    for (t, v) in r.mesh.triangles.iter().enumerate() {
        assert!(min_angle(&r.mesh.points, v) >= 32.0, "triangle {t}");
    }
}

#[test]
fn user_test_refines_where_asked() {
    use delone::tri::refine::refine_with;
    // Fine triangles left of x = 1 only; the angle bound everywhere.
    let g = Pslg::new(
        vec![[0.0, 0.0], [3.0, 0.0], [3.0, 1.0], [0.0, 1.0]],
        vec![[0, 1], [1, 2], [2, 3], [3, 0]],
    );
    let cdt = constrained_triangulation(&g, CdtOptions::default()).unwrap();
    let opts = RefineOptions {
        min_angle: Some(25.0),
        ..Default::default()
    };
    let left = |t: &[[f64; 2]; 3], area: f64| t.iter().any(|p| p[0] < 1.0) && area > 0.002;
    let r = refine_with(&cdt, &opts, &left).unwrap();
    check_cdt(&g, &r.mesh).unwrap();
    assert!(r.report.met, "{:?}", r.report.unfixable.first());
    let p = &r.mesh.points;
    let (mut n_left, mut n_right) = (0, 0);
    for v in &r.mesh.triangles {
        let t = [p[v[0] as usize], p[v[1] as usize], p[v[2] as usize]];
        let area = 0.5
            * ((t[1][0] - t[0][0]) * (t[2][1] - t[0][1])
                - (t[1][1] - t[0][1]) * (t[2][0] - t[0][0]));
        assert!(!left(&t, area), "{t:?} still unsuitable");
        assert!(min_angle(p, v) >= 25.0);
        if t.iter().all(|q| q[0] > 2.0) {
            n_right += 1;
        } else if t.iter().all(|q| q[0] < 1.0) {
            n_left += 1;
        }
    }
    // The left third is much finer than the right third.
    assert!(n_left > 10 * n_right.max(1), "{n_left} vs {n_right}");
    // Same input, same output.
    assert_eq!(refine_with(&cdt, &opts, &left).unwrap(), r);
    // A test that is never satisfied stops at the budget and is reported.
    let never = |_: &[[f64; 2]; 3], _: f64| true;
    let capped = RefineOptions {
        max_steiner: Some(40),
        ..opts
    };
    let r = refine_with(&cdt, &capped, &never).unwrap();
    assert!(r.report.limit_reached && !r.report.met);
    assert_eq!(r.report.unfixable.len(), r.mesh.triangles.len());
}

#[test]
fn segment_splits_can_be_forbidden() {
    use delone::tri::refine::SegmentSplits;
    // A rectangle with an interior segment.
    let g = Pslg::new(
        vec![
            [0.0, 0.0],
            [3.0, 0.0],
            [3.0, 1.0],
            [0.0, 1.0],
            [1.0, 0.3],
            [2.0, 0.6],
        ],
        vec![[0, 1], [1, 2], [2, 3], [3, 0], [4, 5]],
    );
    let cdt = constrained_triangulation(&g, CdtOptions::default()).unwrap();
    let n = cdt.points.len() as u32;
    for (mode, boundary_whole, interior_whole) in [
        (SegmentSplits::All, false, false),
        (SegmentSplits::Interior, true, false),
        (SegmentSplits::None, true, true),
    ] {
        let opts = RefineOptions {
            min_angle: Some(28.0),
            max_area: Some(0.01),
            segment_splits: mode,
            ..Default::default()
        };
        let r = refine(&cdt, &opts).unwrap();
        check_cdt(&g, &r.mesh).unwrap();
        // Boundary edges (one triangle) and subsegments of the interior
        // segment: split only where allowed.
        let boundary_steiner = r
            .mesh
            .triangles
            .iter()
            .zip(&r.mesh.neighbors)
            .flat_map(|(v, nb)| {
                (0..3)
                    .filter(move |&e| nb[e] == delone::NONE)
                    .map(move |e| v[(e + 1) % 3].max(v[(e + 2) % 3]))
            })
            .any(|x| x >= n);
        let interior_pieces = r.mesh.segments.iter().filter(|s| s.segment == 4).count();
        assert_eq!(!boundary_steiner, boundary_whole, "{mode:?}");
        if interior_whole {
            assert_eq!(interior_pieces, 1, "{mode:?}");
        }
        if mode == SegmentSplits::All {
            assert!(boundary_steiner && interior_pieces > 1);
        }
        assert!(r.report.circumcenters > 0, "{mode:?}");
        // What could not be met is reported, with the reason.
        assert_eq!(r.report.met, r.report.unfixable.is_empty());
        if mode != SegmentSplits::All {
            for u in &r.report.unfixable {
                assert_eq!(u.reason, UnfixableReason::NoSegmentSplits, "{mode:?}");
            }
        } else {
            assert!(r.report.met);
        }
    }
}
