//! 3D metric adaptation ([`delone::adapt::adapt_tet`]) on the unit cube:
//! the UGAWG linear metric from a structured coarse mesh, bad input.

use delone::adapt::{adapt_tet, AdaptOptions, MetricField, TetMesh};
use delone::metric::Metric;
use delone::Error;
use delone_predicates::orient3d;

#[path = "common/cube.rs"]
mod cube;
use cube::cube;

/// UGAWG's linear metric with sizes `h` in x and y and from `h0` at
/// z = 1/2 to `h` at the top and bottom in z.
fn linear(h: f64, h0: f64) -> impl Fn(&[f64; 3]) -> Metric<3> {
    move |p: &[f64; 3]| {
        let hz = h0 + 2.0 * (h - h0) * (p[2] - 0.5).abs();
        let d = |x: f64| 1.0 / (x * x);
        Metric::from_medit(&[d(h), 0.0, d(h), 0.0, 0.0, d(hz)]).unwrap()
    }
}

fn volume(m: &TetMesh, t: [u32; 4]) -> f64 {
    let p = t.map(|q| m.points[q as usize]);
    -orient3d(&p[0], &p[1], &p[2], &p[3]) / 6.0
}

/// Checks an adapted cube: every tetrahedron positive, each region of
/// volume 1/2, each side and the interface of area 1 in triangles of its
/// reference, the corners kept.
pub fn check_cube(m: &TetMesh) {
    let mut vol = [0.0; 3];
    for (t, r) in m.elements.iter().zip(&m.element_refs) {
        let v = volume(m, *t);
        assert!(v > 0.0, "tetrahedron {t:?} is not positive");
        vol[*r as usize] += v;
    }
    assert!(
        (vol[1] - 0.5).abs() < 1e-12 && (vol[2] - 0.5).abs() < 1e-12,
        "{vol:?}"
    );
    let mut area = [0.0; 8];
    for (f, r) in m.faces.iter().zip(&m.face_refs) {
        let [a, b, c] = f.map(|q| m.points[q as usize]);
        let (u, w) = (
            [0, 1, 2].map(|i| b[i] - a[i]),
            [0, 1, 2].map(|i| c[i] - a[i]),
        );
        let x = [
            u[1] * w[2] - u[2] * w[1],
            u[2] * w[0] - u[0] * w[2],
            u[0] * w[1] - u[1] * w[0],
        ];
        area[*r as usize] += 0.5 * (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
    }
    for (r, a) in area.iter().enumerate().skip(1) {
        assert!((a - 1.0).abs() < 1e-12, "reference {r}: area {a}");
    }
    assert_eq!(m.corners.len(), 8);
    for &c in &m.corners {
        assert!(m.points[c as usize].iter().all(|&x| x == 0.0 || x == 1.0));
    }
}

#[test]
fn linear_metric_on_the_cube() {
    let f = linear(0.25, 0.025);
    let mut mesh = cube(2, true);
    let mut last = None;
    for _ in 0..5 {
        let met: Vec<Metric<3>> = mesh.points.iter().map(&f).collect();
        let out = adapt_tet(
            &mesh,
            MetricField::AtVertices(met),
            &AdaptOptions::default(),
        )
        .unwrap();
        check_cube(&out.mesh);
        let r = &out.report;
        eprintln!(
            "{} tets, {:.1}% in range, quality min {:.3} mean {:.3}; {} splits {} collapses {} swaps {} moves, {} passes",
            out.mesh.elements.len(),
            100.0 * r.after.in_range_share(),
            r.after.quality_min,
            r.after.quality_mean,
            r.splits,
            r.collapses,
            r.swaps,
            r.moves,
            r.passes
        );
        mesh = out.mesh;
        last = Some(out.report);
    }
    let r = last.unwrap();
    assert!(r.after.in_range_share() >= 0.85, "{:?}", r.after);
    assert!(r.after.quality_min > 0.1, "{:?}", r.after);
}

#[test]
fn bad_input_is_refused_naming_the_item() {
    let mesh = cube(1, false);
    let ok = || MetricField::AtVertices(vec![Metric::isotropic(0.5); 8]);
    let o = AdaptOptions::default();
    let mut m = mesh.clone();
    m.elements[3].swap(0, 1);
    let e = adapt_tet(&m, ok(), &o).unwrap_err();
    assert!(e.to_string().contains("tetrahedron 3"), "{e}");
    let mut m = mesh.clone();
    m.elements[2][1] = 99;
    assert!(matches!(
        adapt_tet(&m, ok(), &o),
        Err(Error::IndexOutOfRange {
            index: 2,
            vertex: 99,
            ..
        })
    ));
    let mut m = mesh.clone();
    m.faces.push([1, 2, 4]);
    m.face_refs.push(1);
    let e = adapt_tet(&m, ok(), &o).unwrap_err();
    assert!(e.to_string().contains("face 12"), "{e}");
    let e = adapt_tet(
        &mesh,
        MetricField::AtVertices(vec![Metric::isotropic(0.5); 7]),
        &o,
    )
    .unwrap_err();
    assert!(matches!(
        e,
        Error::MetricCount {
            vertices: 8,
            metrics: 7
        }
    ));
}

#[test]
fn same_input_same_output() {
    let f = linear(0.3, 0.05);
    let mesh = cube(2, true);
    let run = || {
        let size = |p: &[f64; 3]| f(p);
        adapt_tet(
            &mesh,
            MetricField::Function(&size),
            &AdaptOptions::default(),
        )
        .unwrap()
        .mesh
    };
    let a = run();
    check_cube(&a);
    assert_eq!(a, run());
}

/// A set stop flag ends the adaptation with [`Error::Interrupted`] (both
/// dimensions), never with a partial mesh.
#[test]
fn a_set_stop_flag_interrupts_the_adaptation() {
    use std::sync::atomic::Ordering;
    let stop = delone::progress::stop_flag();
    stop.store(true, Ordering::Relaxed);
    let size = |_: &[f64; 3]| Metric::isotropic(0.1);
    let r = delone::progress::stoppable(stop.clone(), || {
        adapt_tet(
            &cube(2, false),
            MetricField::Function(&size),
            &AdaptOptions::default(),
        )
    });
    assert_eq!(r.unwrap_err(), Error::Interrupted);
    let square = delone::adapt::TriMesh {
        points: vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
        elements: vec![[0, 1, 2], [0, 2, 3]],
        ..Default::default()
    };
    let size2 = |_: &[f64; 2]| Metric::isotropic(0.1);
    let r = delone::progress::stoppable(stop, || {
        delone::adapt::adapt_tri(
            &square,
            MetricField::Function(&size2),
            &AdaptOptions::default(),
        )
    });
    assert_eq!(r.unwrap_err(), Error::Interrupted);
}
