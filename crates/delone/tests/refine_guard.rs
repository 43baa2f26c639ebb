//! Refinement never runs without bound, and every bound is met or reported:
//! bounds no mesh can meet are typed errors naming the switch; bounds
//! refinement cannot reach stop at the Steiner budget with a valid mesh
//! and a report that says so.

use delone::model::pslg::Pslg;
use delone::tet::recover::check_recovered;
use delone::tri::constrain::{check_cdt, constrained_triangulation, CdtOptions};
use delone::tri::refine::{refine, RefineOptions, UnfixableReason};
use delone::Error;

mod common;
mod solids;

fn square() -> Pslg {
    Pslg::new(
        vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
        vec![[0, 1], [1, 2], [2, 3], [3, 0]],
    )
}

#[test]
fn tri_impossible_bounds_are_typed_errors() {
    let cdt = constrained_triangulation(&square(), CdtOptions::default()).unwrap();
    let cases = [
        (Some(60.0), None, "-q"),
        (Some(75.0), None, "-q"),
        (Some(f64::NAN), None, "-q"),
        (Some(-1.0), None, "-q"),
        (Some(20.0), Some(0.0), "-a"),
        (Some(20.0), Some(-0.5), "-a"),
        (None, Some(f64::NAN), "-a"),
    ];
    for (q, a, opt) in cases {
        let o = RefineOptions {
            min_angle: q,
            max_area: a,
            ..Default::default()
        };
        match refine(&cdt, &o) {
            Err(Error::InvalidBound { option, .. }) => assert_eq!(option, opt, "{q:?} {a:?}"),
            other => panic!("{q:?} {a:?}: expected InvalidBound, got {other:?}"),
        }
    }
    // Just below 60 is not refused: it runs under the budget.
    let o = RefineOptions {
        min_angle: Some(59.0),
        max_steiner: Some(500),
        ..Default::default()
    };
    let r = refine(&cdt, &o).unwrap();
    assert!(r.report.segment_splits + r.report.circumcenters <= 500);
    check_cdt(&square(), &r.mesh).unwrap();
}

/// A.poly at -q40 (above what refinement guarantees): stops at the budget,
/// valid mesh, the report says the budget stopped it.
#[test]
fn tri_a_poly_q40_stops_at_the_budget() {
    let Some(dir) = common::data_dir() else {
        eprintln!("shared data missing: skipped");
        return;
    };
    let g = common::load_poly(&dir.join("2d").join("A.poly"));
    let cdt = constrained_triangulation(&g, CdtOptions::default()).unwrap();
    for threads in [1, 2] {
        let o = RefineOptions {
            min_angle: Some(40.0),
            max_steiner: Some(20_000),
            threads,
            ..Default::default()
        };
        let r = refine(&cdt, &o).unwrap();
        let added = r.report.segment_splits + r.report.circumcenters;
        assert!(added <= 20_000, "{added}");
        assert_eq!(r.mesh.points.len(), cdt.points.len() + added);
        assert!(r.report.limit_reached && !r.report.met);
        assert_eq!(r.report.steiner_budget, 20_000);
        assert!(r
            .report
            .unfixable
            .iter()
            .any(|u| u.reason == UnfixableReason::SteinerLimit && u.min_angle < 40.0));
        check_cdt(&g, &r.mesh).unwrap();
    }
    // Without -S the default budget applies and is reported.
    let o = RefineOptions {
        min_angle: Some(30.0),
        ..Default::default()
    };
    let r = refine(&cdt, &o).unwrap();
    assert!(r.report.met && !r.report.limit_reached);
    assert_eq!(
        r.report.steiner_budget,
        delone::tri::refine::default_budget(cdt.points.len(), 0.0)
    );
}

/// An area bound sets the default budget above what it asks for, so the
/// run it asks for is not stopped.
#[test]
fn tri_area_bound_runs_are_not_stopped() {
    let cdt = constrained_triangulation(&square(), CdtOptions::default()).unwrap();
    let o = RefineOptions {
        min_angle: Some(30.0),
        max_area: Some(1e-5),
        threads: 1,
        ..Default::default()
    };
    let r = refine(&cdt, &o).unwrap();
    assert!(r.report.met && !r.report.limit_reached);
    assert!(r.report.steiner_budget > delone::tri::refine::BUDGET_BASE + 100_000);
}

#[test]
fn tet_impossible_bounds_are_typed_errors() {
    use delone::tet::recover::RecoverError;
    use delone::tet::refine::{refine as refine3, RefineOptions as R3};
    let (p, t) = solids::cuboid(1.0, 1.0, 1.0);
    for (q, v, opt) in [
        (0.5, None, "-q"),
        (0.6, None, "-q"),
        (f64::NAN, None, "-q"),
        (2.0, Some(0.0), "-a"),
        (2.0, Some(f64::NAN), "-a"),
    ] {
        let o = R3 {
            max_radius_edge: Some(q),
            max_volume: v,
            ..Default::default()
        };
        match refine3(&p, &t, &o) {
            Err(RecoverError::Input(Error::InvalidBound { option, .. })) => {
                assert_eq!(option, opt)
            }
            other => panic!("{q} {v:?}: expected InvalidBound, got {other:?}"),
        }
    }
    // sqrt(6)/4 itself is not refused (a regular tetrahedron meets it).
    let o = R3 {
        max_radius_edge: Some(delone::tet::refine::MIN_RADIUS_EDGE),
        max_steiner: Some(50),
        ..Default::default()
    };
    assert!(o.check_bounds().is_ok());
}

/// -q0.8 and a tiny volume bound under a small budget: stop, valid mesh,
/// report; the default budget is derived from the volume bound.
#[test]
fn tet_budget_stops_and_reports() {
    use delone::tet::refine::{default_budget, refine as refine3, RefineOptions as R3};
    let (p, t) = solids::cuboid(1.0, 1.0, 1.0);
    for (q, v) in [(1.1, Some(1e-6)), (2.0, Some(1e-9))] {
        let o = R3 {
            max_radius_edge: Some(q),
            max_volume: v,
            max_steiner: Some(300),
            ..Default::default()
        };
        let r = refine3(&p, &t, &o).unwrap();
        assert!(r.report.budget_exhausted, "{q} {v:?}: {:?}", r.report);
        assert!(r.report.steiner() <= 300);
        assert_eq!(r.report.steiner_budget, 300);
        check_recovered(&p, &t, &r.rec).unwrap();
    }
    let o = R3 {
        max_radius_edge: Some(2.0),
        max_volume: Some(1e-3),
        ..Default::default()
    };
    let r = refine3(&p, &t, &o).unwrap();
    assert!(!r.report.budget_exhausted);
    let want = default_budget(p.len(), 1e3);
    assert!(
        r.report.steiner_budget.abs_diff(want) <= 1,
        "{} {want}",
        r.report.steiner_budget
    );
}

/// A volume bound that needs more points than the largest default budget is
/// refused before any work, naming `-S`; an explicit budget lets it run.
#[test]
fn tet_volume_bound_beyond_the_default_budget_is_refused() {
    use delone::tet::refine::{refine as refine3, RefineOptions as R3, BUDGET_MAX};
    let (p, t) = solids::cuboid(1.0, 1.0, 1.0);
    let o = R3 {
        max_volume: Some(1e-9),
        ..Default::default()
    };
    match refine3(&p, &t, &o) {
        Err(delone::tet::recover::RecoverError::Input(
            e @ delone::Error::BoundNeedsBudget { needed, budget, .. },
        )) => {
            assert_eq!(budget, BUDGET_MAX);
            assert!(needed > BUDGET_MAX, "{needed}");
            assert!(e.to_string().contains("-S"), "{e}");
        }
        other => panic!(
            "expected BoundNeedsBudget, got {:?}",
            other.map(|r| r.report)
        ),
    }
    let o = R3 {
        max_steiner: Some(200),
        ..o
    };
    let r = refine3(&p, &t, &o).unwrap();
    assert!(r.report.budget_exhausted);
}
