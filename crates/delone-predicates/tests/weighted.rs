//! Weighted (power) predicates: zero weights reproduce the unweighted signs,
//! invariances of the power test hold exactly, and the signs agree with an
//! independent big-integer evaluator.

mod common;

use common::*;
use delone_predicates::{incircle, incircle_weighted, insphere, insphere_weighted};

fn iw2(p: [&[f64; 2]; 4], w: [f64; 4]) -> i32 {
    sign(incircle_weighted(
        p[0], p[1], p[2], p[3], w[0], w[1], w[2], w[3],
    ))
}
fn iw3(p: [&[f64; 3]; 5], w: [f64; 5]) -> i32 {
    sign(insphere_weighted(
        p[0], p[1], p[2], p[3], p[4], w[0], w[1], w[2], w[3], w[4],
    ))
}

#[test]
fn zero_weights_match_unweighted() {
    let mut r = Rng(11);
    for i in 0..20_000 {
        let (a, b, c, d) = if i % 2 == 0 {
            (r.p2(), r.p2(), r.p2(), r.p2())
        } else {
            let g = |r: &mut Rng| [r.int(-2, 2) as f64 * 1e-9, r.int(-2, 2) as f64 * 1e-9];
            (g(&mut r), g(&mut r), g(&mut r), g(&mut r))
        };
        assert_eq!(
            iw2([&a, &b, &c, &d], [0.0; 4]),
            sign(incircle(&a, &b, &c, &d))
        );
        let (a, b, c, d, e) = if i % 2 == 0 {
            (r.p3(), r.p3(), r.p3(), r.p3(), r.p3())
        } else {
            let g = |r: &mut Rng| {
                [
                    r.int(-1, 1) as f64 * 1e9,
                    r.int(-1, 1) as f64 * 1e9,
                    r.int(-1, 1) as f64 * 1e9,
                ]
            };
            (g(&mut r), g(&mut r), g(&mut r), g(&mut r), g(&mut r))
        };
        assert_eq!(
            iw3([&a, &b, &c, &d, &e], [0.0; 5]),
            sign(insphere(&a, &b, &c, &d, &e))
        );
    }
}

/// The power test is invariant under (a) translating all points, (b) adding a
/// common constant to all weights and (c) adding an affine function of the
/// position to the weights (it only tilts the lifted plane). All shifts are
/// chosen exactly representable so the invariance is exact.
#[test]
fn invariances_hold_exactly() {
    let mut r = Rng(12);
    let mut degenerate = 0;
    for _ in 0..5_000 {
        let g2 = |r: &mut Rng| [r.int(-4, 4) as f64, r.int(-4, 4) as f64];
        let p = [g2(&mut r), g2(&mut r), g2(&mut r), g2(&mut r)];
        let w: [f64; 4] = std::array::from_fn(|_| r.int(-6, 6) as f64 * 0.25);
        let s0 = iw2([&p[0], &p[1], &p[2], &p[3]], w);
        degenerate += (s0 == 0) as usize;
        let t = [r.int(-1000, 1000) as f64, r.int(-1000, 1000) as f64];
        // Translating p by t changes |p|² by 2 p·t + |t|², an affine function: to keep the
        // lifted configuration affinely equivalent no weight change is needed.
        let q: Vec<[f64; 2]> = p.iter().map(|x| [x[0] + t[0], x[1] + t[1]]).collect();
        assert_eq!(iw2([&q[0], &q[1], &q[2], &q[3]], w), s0);
        let c = r.int(-100, 100) as f64 * 0.5;
        assert_eq!(iw2([&p[0], &p[1], &p[2], &p[3]], w.map(|x| x + c)), s0);
        let (al, be) = (r.int(-9, 9) as f64, r.int(-9, 9) as f64);
        let wa: [f64; 4] = std::array::from_fn(|k| w[k] + al * p[k][0] + be * p[k][1] + c);
        assert_eq!(iw2([&p[0], &p[1], &p[2], &p[3]], wa), s0);

        let g3 = |r: &mut Rng| {
            [
                r.int(-3, 3) as f64,
                r.int(-3, 3) as f64,
                r.int(-3, 3) as f64,
            ]
        };
        let p = [g3(&mut r), g3(&mut r), g3(&mut r), g3(&mut r), g3(&mut r)];
        let w: [f64; 5] = std::array::from_fn(|_| r.int(-6, 6) as f64 * 0.5);
        let pr = |p: &[[f64; 3]], w| iw3([&p[0], &p[1], &p[2], &p[3], &p[4]], w);
        let s0 = pr(&p, w);
        degenerate += (s0 == 0) as usize;
        let t = [r.int(-1000, 1000) as f64 * 0.125, 3.0, -r.int(0, 99) as f64];
        let q: Vec<[f64; 3]> = p
            .iter()
            .map(|x| [x[0] + t[0], x[1] + t[1], x[2] + t[2]])
            .collect();
        assert_eq!(pr(&q, w), s0);
        let (al, be, ga) = (
            r.int(-9, 9) as f64,
            r.int(-9, 9) as f64,
            r.int(-9, 9) as f64,
        );
        let wa: [f64; 5] =
            std::array::from_fn(|k| w[k] + al * p[k][0] + be * p[k][1] + ga * p[k][2] + c);
        assert_eq!(pr(&p, wa), s0);
    }
    assert!(
        degenerate > 50,
        "the inputs must include exact ties ({degenerate})"
    );
}

/// Points and weights for one 2D and one 3D power test.
type Case = ([[f64; 2]; 4], [f64; 4], [[f64; 3]; 5], [f64; 5]);

#[test]
fn agrees_with_independent_big_integer_evaluator() {
    let mut r = Rng(13);
    let mut zeros = 0;
    for i in 0..3_000 {
        // Mix: small integers with quarter weights (many ties), random doubles with
        // random weights, and huge offsets with tiny features (inexact differences).
        let (p2, w2, p3, w3): Case = match i % 3 {
            0 => (
                std::array::from_fn(|_| [r.int(-3, 3) as f64, r.int(-3, 3) as f64]),
                std::array::from_fn(|_| r.int(-8, 8) as f64 * 0.25),
                std::array::from_fn(|_| {
                    [
                        r.int(-2, 2) as f64,
                        r.int(-2, 2) as f64,
                        r.int(-2, 2) as f64,
                    ]
                }),
                std::array::from_fn(|_| r.int(-8, 8) as f64 * 0.5),
            ),
            1 => (
                std::array::from_fn(|_| r.p2()),
                std::array::from_fn(|_| r.range(-0.5, 0.5)),
                std::array::from_fn(|_| r.p3()),
                std::array::from_fn(|_| r.range(-0.5, 0.5)),
            ),
            _ => {
                let off = 1e6 + r.int(0, 1000) as f64;
                (
                    std::array::from_fn(|_| {
                        [
                            off + r.int(0, 2) as f64 * 0.1,
                            -off + r.int(0, 2) as f64 * 0.1,
                        ]
                    }),
                    std::array::from_fn(|_| r.int(-2, 2) as f64 * 0.01),
                    std::array::from_fn(|_| {
                        [
                            off + r.int(0, 2) as f64 * 0.1,
                            0.1 * r.int(0, 2) as f64,
                            -off + r.int(0, 2) as f64 * 0.1,
                        ]
                    }),
                    std::array::from_fn(|_| r.int(-2, 2) as f64 * 0.01),
                )
            }
        };
        let want = exact_power_sign(&p2, &w2);
        assert_eq!(
            iw2([&p2[0], &p2[1], &p2[2], &p2[3]], w2),
            want,
            "incircle_weighted {p2:?} {w2:?}"
        );
        let want3 = exact_power_sign(&p3, &w3);
        assert_eq!(
            iw3([&p3[0], &p3[1], &p3[2], &p3[3], &p3[4]], w3),
            want3,
            "insphere_weighted {p3:?} {w3:?}"
        );
        zeros += (want == 0) as usize + (want3 == 0) as usize;
        // The unweighted predicates against the same evaluator.
        assert_eq!(
            sign(incircle(&p2[0], &p2[1], &p2[2], &p2[3])),
            exact_power_sign(&p2, &[0.0; 4])
        );
        assert_eq!(
            sign(insphere(&p3[0], &p3[1], &p3[2], &p3[3], &p3[4])),
            exact_power_sign(&p3, &[0.0; 5])
        );
    }
    assert!(zeros > 20, "ties must be exercised ({zeros})");
}
