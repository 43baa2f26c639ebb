//! 3D metric adaptation ([`delone::adapt::adapt_tet`]) on the unit cube:
//! the UGAWG linear metric from a structured coarse mesh, bad input.

use delone::adapt::{adapt_tet, AdaptOptions, MetricField, TetMesh};
use delone::metric::Metric;
use delone::Error;
use delone_predicates::orient3d;

/// The unit cube as `n³` cubes of six tetrahedra each (positive), region
/// 1 below z = 1/2 and 2 above (n even), the six sides as triangles with
/// references 1..=6, the interface z = 1/2 with reference 7, the eight
/// corners and the twelve edges as ridges.
pub fn cube(n: usize) -> TetMesh {
    let id = |i: usize, j: usize, k: usize| (i + (n + 1) * (j + (n + 1) * k)) as u32;
    let mut m = TetMesh::default();
    for k in 0..=n {
        for j in 0..=n {
            for i in 0..=n {
                m.points.push([i, j, k].map(|x| x as f64 / n as f64));
            }
        }
    }
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let c = |b: usize| id(i + (b & 1), j + (b >> 1 & 1), k + (b >> 2));
                // Kuhn's six tetrahedra on the diagonal 0-7.
                for path in [[1, 3], [1, 5], [2, 3], [2, 6], [4, 5], [4, 6]] {
                    let mut t = [c(0), c(path[0]), c(path[1]), c(7)];
                    let g = |q: u32| &m.points[q as usize];
                    if orient3d(g(t[0]), g(t[1]), g(t[2]), g(t[3])) > 0.0 {
                        t.swap(0, 1);
                    }
                    m.elements.push(t);
                    m.element_refs.push(if 2 * k < n { 1 } else { 2 });
                }
            }
        }
    }
    // Faces: every element face on a side or on the interface.
    let mut faces: Vec<([u32; 3], i32)> = Vec::new();
    for t in &m.elements {
        for f in 0..4 {
            let mut k: Vec<u32> = (0..4).filter(|&i| i != f).map(|i| t[i]).collect();
            k.sort_unstable();
            let p: Vec<[f64; 3]> = k.iter().map(|&q| m.points[q as usize]).collect();
            let on = |axis: usize, v: f64| p.iter().all(|x| x[axis] == v);
            let r = (0..3)
                .flat_map(|a| [(a, 0.0), (a, 1.0)])
                .position(|(a, v)| on(a, v))
                .map(|i| i as i32 + 1)
                .or_else(|| on(2, 0.5).then_some(7));
            if let Some(r) = r {
                let key = [k[0], k[1], k[2]];
                if !faces.iter().any(|f| f.0 == key) {
                    faces.push((key, r));
                }
            }
        }
    }
    m.faces = faces.iter().map(|f| f.0).collect();
    m.face_refs = faces.iter().map(|f| f.1).collect();
    m.corners = (0..8)
        .map(|b| id(n * (b & 1), n * (b >> 1 & 1), n * (b >> 2)))
        .collect();
    for a in 0..3 {
        for (u, v) in [(0, 0), (0, n), (n, 0), (n, n)] {
            for s in 0..n {
                let at = |s: usize| {
                    let mut x = [u, v, 0];
                    x.rotate_right(a);
                    x[a] = s;
                    id(x[0], x[1], x[2])
                };
                m.ridges.push([at(s), at(s + 1)]);
            }
        }
    }
    m
}

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
    let mut mesh = cube(2);
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
    let mesh = cube(1);
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
