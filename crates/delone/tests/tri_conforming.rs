//! Conforming Delaunay refinement (Triangle's `-D`): on random PSLGs (with
//! crossings and tiny angles) and on every shared `.poly`, with and without
//! an angle bound, the result is a valid CDT of the input, every triangle is
//! truly Delaunay (exact incircle against every mesh vertex), and the report
//! says the property was met.

use delone::model::pslg::Pslg;
use delone::tri::conforming::check_conforming_delaunay;
use delone::tri::constrain::{check_cdt, constrained_triangulation, Cdt, CdtOptions};
use delone::tri::refine::{refine, RefineOptions, Refined, SegmentSplits, UnfixableReason};

mod common;
use common::{data_dir, load_poly};

/// A deterministic generator (SplitMix64).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn conforming(cdt: &Cdt, min_angle: Option<f64>) -> Refined {
    refine(
        cdt,
        &RefineOptions {
            min_angle,
            conforming_delaunay: true,
            max_steiner: Some(200_000),
            ..Default::default()
        },
    )
    .unwrap()
}

fn verify(name: &str, g: &Pslg, r: &Refined) {
    check_cdt(g, &r.mesh).unwrap_or_else(|v| panic!("{name}: not a valid CDT: {v}"));
    check_conforming_delaunay(&r.mesh.points, &r.mesh.triangles)
        .unwrap_or_else(|v| panic!("{name}: not Delaunay: {v}"));
    assert!(!r.report.limit_reached, "{name}: budget reached");
    assert_eq!(r.report.encroached_subsegments, 0, "{name}");
}

#[test]
fn plain_cdt_is_often_not_delaunay_and_d_fixes_it() {
    // A thin rectangle cut in two lengthwise, a point close above the cut.
    let g = Pslg::new(
        vec![
            [0.0, 0.0],
            [10.0, 0.0],
            [10.0, 1.0],
            [0.0, 1.0],
            [0.0, 0.5],
            [10.0, 0.5],
            [5.0, 0.6],
        ],
        vec![[0, 1], [1, 5], [5, 2], [2, 3], [3, 4], [4, 0], [4, 5]],
    );
    let cdt = constrained_triangulation(&g, CdtOptions::default()).unwrap();
    assert!(check_conforming_delaunay(&cdt.points, &cdt.triangles).is_err());
    let r = conforming(&cdt, None);
    verify("thin", &g, &r);
    assert_eq!(r.report.circumcenters, 0, "-D alone only splits segments");
    assert!(r.report.segment_splits > 0);
}

#[test]
fn random_pslgs_with_crossings() {
    let mut rng = Rng(7);
    for case in 0..30 {
        let n = 6 + case % 20;
        let mut pts: Vec<[f64; 2]> = (0..n).map(|_| [rng.next(), rng.next()]).collect();
        // A box around everything, then random (crossing) segments.
        let b = pts.len() as u32;
        pts.extend([[-0.1, -0.1], [1.1, -0.1], [1.1, 1.1], [-0.1, 1.1]]);
        let mut segs = vec![[b, b + 1], [b + 1, b + 2], [b + 2, b + 3], [b + 3, b]];
        for _ in 0..n / 2 {
            let i = (rng.next() * n as f64) as u32;
            let j = (rng.next() * n as f64) as u32;
            if i != j {
                segs.push([i, j]);
            }
        }
        let g = Pslg::new(pts, segs);
        let cdt = constrained_triangulation(&g, CdtOptions::default()).unwrap();
        for q in [None, Some(20.0)] {
            let r = conforming(&cdt, q);
            verify(&format!("random {case} q{q:?}"), &g, &r);
            // Only triangles at small input angles may miss the bound.
            assert!(
                r.report
                    .unfixable
                    .iter()
                    .all(|u| matches!(u.reason, UnfixableReason::SmallInputAngle { .. })),
                "random {case}: {:?}",
                r.report.unfixable
            );
        }
    }
}

#[test]
fn tiny_input_angles_terminate() {
    for deg in [0.1f64, 1.0, 5.0, 15.0] {
        // A fan of segments from the origin, `deg` apart, inside a box.
        let mut pts = vec![
            [0.0, 0.0],
            [-2.0, -2.0],
            [3.0, -2.0],
            [3.0, 3.0],
            [-2.0, 3.0],
        ];
        let mut segs = vec![[1, 2], [2, 3], [3, 4], [4, 1]];
        for k in 0..4 {
            let a = (deg * k as f64).to_radians();
            pts.push([2.0 * a.cos(), 2.0 * a.sin()]);
            segs.push([0, pts.len() as u32 - 1]);
        }
        let g = Pslg::new(pts, segs);
        let cdt = constrained_triangulation(&g, CdtOptions::default()).unwrap();
        for q in [None, Some(25.0)] {
            let r = conforming(&cdt, q);
            verify(&format!("fan {deg} q{q:?}"), &g, &r);
        }
    }
}

#[test]
fn protected_segments_are_reported() {
    let g = Pslg::new(
        vec![[0.0, 0.0], [10.0, 0.0], [10.0, 1.0], [0.0, 1.0], [5.0, 0.5]],
        vec![[0, 1], [1, 2], [2, 3], [3, 0]],
    );
    let cdt = constrained_triangulation(&g, CdtOptions::default()).unwrap();
    let r = refine(
        &cdt,
        &RefineOptions {
            min_angle: None,
            conforming_delaunay: true,
            segment_splits: SegmentSplits::None,
            ..Default::default()
        },
    )
    .unwrap();
    assert!(!r.report.met);
    assert!(r.report.encroached_subsegments > 0);
    assert_eq!(r.mesh.points.len(), 5);
}

#[test]
fn deterministic() {
    let g = Pslg::new(
        vec![[0.0, 0.0], [7.0, 0.0], [7.0, 0.3], [0.0, 1.0], [3.0, 0.1]],
        vec![[0, 1], [1, 2], [2, 3], [3, 0], [3, 4]],
    );
    let cdt = constrained_triangulation(&g, CdtOptions::default()).unwrap();
    let a = conforming(&cdt, Some(20.0));
    let b = conforming(&cdt, Some(20.0));
    assert_eq!(a.mesh, b.mesh);
}

#[test]
fn shared_polys() {
    let Some(dir) = data_dir() else {
        println!("shared data not found; skipped");
        return;
    };
    let mut names: Vec<_> = std::fs::read_dir(dir.join("2d"))
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "poly"))
        .collect();
    names.sort();
    assert!(!names.is_empty());
    for path in names {
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let g = load_poly(&path);
        let convex_hull = name == "box.poly";
        let cdt = constrained_triangulation(&g, CdtOptions { convex_hull }).unwrap();
        for q in [None, Some(20.0), Some(34.0)] {
            let r = conforming(&cdt, q);
            // At 34° (beyond the guarantees) la.poly stops its quality
            // refinement to let the splits finish; the reason says so.
            assert!(
                r.report.unfixable.iter().all(|u| matches!(
                    u.reason,
                    UnfixableReason::SmallInputAngle { .. } | UnfixableReason::ConformingDelaunay
                )),
                "{name} q{q:?}"
            );
            if q == Some(20.0) {
                assert!(r
                    .report
                    .unfixable
                    .iter()
                    .all(|u| matches!(u.reason, UnfixableReason::SmallInputAngle { .. })));
            }
            println!(
                "{name} -D q{q:?}: {} -> {} triangles, {} segment splits, {} circumcentres",
                cdt.triangles.len(),
                r.mesh.triangles.len(),
                r.report.segment_splits,
                r.report.circumcenters
            );
            verify(&format!("{name} q{q:?}"), &g, &r);
        }
    }
}
