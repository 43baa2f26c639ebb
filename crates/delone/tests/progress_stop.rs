//! `progress::stoppable`: a stop flag set from another thread (or from the
//! progress sink) ends a long run at its next report site.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use delone::model::plc::{Facet, Plc};
use delone::model::pslg::Pslg;
use delone::progress::{observe, stop_flag, stop_requested, stoppable, Report};
use delone::tet::TetOptions;
use delone::tri::{check_cdt, TriOptions};

/// Runs `work` with a stop flag that the sink sets at the first report of `stage`.
fn stopped_at<R>(stage: &'static str, work: impl FnOnce() -> R) -> R {
    let stop = Arc::new(AtomicBool::new(false));
    let setter = stop.clone();
    let sink = move |r: &Report| {
        if r.stage == stage {
            setter.store(true, Ordering::Relaxed);
        }
    };
    stoppable(stop, || observe(sink, work))
}

#[test]
fn stop_flags_nest_and_are_seen_when_set_elsewhere() {
    let outer = Arc::new(AtomicBool::new(false));
    let inner = Arc::new(AtomicBool::new(true));
    let seen = stoppable(outer.clone(), || {
        let a = stop_requested();
        let b = stoppable(inner, stop_requested);
        let setter = outer.clone();
        std::thread::spawn(move || setter.store(true, Ordering::Relaxed))
            .join()
            .unwrap();
        (a, b, stop_requested(), stop_flag().load(Ordering::Relaxed))
    });
    assert_eq!(seen, (false, true, true, true));
    assert!(!stop_requested());
    assert!(!stop_flag().load(Ordering::Relaxed));
}

#[test]
fn a_stopped_2d_refinement_ends_early_with_a_valid_mesh() {
    let g = Pslg::new(
        vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
        vec![[0, 1], [1, 2], [2, 3], [3, 0]],
    );
    // Sequential and parallel (the workers see the caller's flag).
    for switches in ["pq30a0.00001", "pq30a0.000001"] {
        let o = TriOptions::from_switches(switches).unwrap();
        let full = delone::tri::mesh(&g, &o).unwrap();
        let stopped = stopped_at("refining", || delone::tri::mesh(&g, &o)).unwrap();
        let (n_full, n_stopped) = (full.mesh.triangles.len(), stopped.mesh.triangles.len());
        assert!(
            n_stopped < n_full / 2,
            "{switches}: {n_stopped} of {n_full}"
        );
        check_cdt(&g, &stopped.mesh).unwrap();
    }
}

#[test]
fn a_stopped_3d_run_ends_early() {
    let pts = (0..8)
        .map(|k| [(k & 1) as f64, (k >> 1 & 1) as f64, (k >> 2) as f64])
        .collect();
    let mut plc = Plc::new(pts);
    for q in [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ] {
        plc.facets.push(Facet::polygon(q.to_vec()));
    }
    let o = TetOptions::from_switches("pq1.414a0.00005").unwrap();
    let full = delone::tet::mesh(&plc, &o).unwrap();
    let stopped = stopped_at("refining", || delone::tet::mesh(&plc, &o)).unwrap();
    let (n_full, n_stopped) = (full.mesh.mesh.tets.len(), stopped.mesh.mesh.tets.len());
    assert!(n_stopped < n_full / 2, "{n_stopped} of {n_full}");
    // A valid mesh of the whole cube.
    let m = &stopped.mesh;
    let vols: Vec<f64> = m
        .mesh
        .tets
        .iter()
        .map(|t| delone::tet::quality::volume(&t.map(|v| m.points[v as usize])))
        .collect();
    assert!(vols.iter().all(|&v| v > 0.0));
    assert!((vols.iter().sum::<f64>() - 1.0).abs() < 1e-9);
    // The optimisation is stopped too: its report says its effort ended early.
    let opt = stopped_at("optimising", || delone::tet::mesh(&plc, &o)).unwrap();
    assert!(opt.optimize.unwrap().effort_exhausted);
}
