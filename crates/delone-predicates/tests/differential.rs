//! Differential tests: the signs of orient2d / incircle / orient3d / insphere must
//! equal those of the `robust` crate (Shewchuk's adaptive predicates) on uniform,
//! near-degenerate, exactly degenerate and scaled inputs.

mod common;

use common::*;
use delone_predicates::{incircle, insphere, orient2d, orient3d};

/// Scales applied to every generated input: exact predicates must be scale-proof.
const SCALES: [f64; 5] = [1.0, 1e-9, 1e9, 3.0e-9, 7.0e9];

fn scale2(p: &[f64; 2], s: f64) -> [f64; 2] {
    [p[0] * s, p[1] * s]
}
fn scale3(p: &[f64; 3], s: f64) -> [f64; 3] {
    [p[0] * s, p[1] * s, p[2] * s]
}

/// Counts (zero results, total) and asserts every sign agrees with robust.
#[derive(Default)]
struct Tally {
    zeros: usize,
    total: usize,
}

impl Tally {
    fn o2(&mut self, a: &[f64; 2], b: &[f64; 2], c: &[f64; 2]) {
        for s in SCALES {
            let (a, b, c) = (scale2(a, s), scale2(b, s), scale2(c, s));
            let got = sign(orient2d(&a, &b, &c));
            assert_eq!(
                got,
                sign(r_orient2d(&a, &b, &c)),
                "orient2d {a:?} {b:?} {c:?}"
            );
            self.total += 1;
            self.zeros += (got == 0) as usize;
        }
    }
    fn ic(&mut self, a: &[f64; 2], b: &[f64; 2], c: &[f64; 2], d: &[f64; 2]) {
        for s in SCALES {
            let (a, b, c, d) = (scale2(a, s), scale2(b, s), scale2(c, s), scale2(d, s));
            let got = sign(incircle(&a, &b, &c, &d));
            assert_eq!(
                got,
                sign(r_incircle(&a, &b, &c, &d)),
                "incircle {a:?} {b:?} {c:?} {d:?}"
            );
            self.total += 1;
            self.zeros += (got == 0) as usize;
        }
    }
    fn o3(&mut self, a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], d: &[f64; 3]) {
        for s in SCALES {
            let (a, b, c, d) = (scale3(a, s), scale3(b, s), scale3(c, s), scale3(d, s));
            let got = sign(orient3d(&a, &b, &c, &d));
            assert_eq!(
                got,
                sign(r_orient3d(&a, &b, &c, &d)),
                "orient3d {a:?} {b:?} {c:?} {d:?}"
            );
            self.total += 1;
            self.zeros += (got == 0) as usize;
        }
    }
    fn is(&mut self, a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], d: &[f64; 3], e: &[f64; 3]) {
        for s in SCALES {
            let (a, b, c, d, e) = (
                scale3(a, s),
                scale3(b, s),
                scale3(c, s),
                scale3(d, s),
                scale3(e, s),
            );
            let got = sign(insphere(&a, &b, &c, &d, &e));
            assert_eq!(
                got,
                sign(r_insphere(&a, &b, &c, &d, &e)),
                "insphere {a:?} {b:?} {c:?} {d:?} {e:?}"
            );
            self.total += 1;
            self.zeros += (got == 0) as usize;
        }
    }
}

#[test]
fn uniform_random() {
    let mut r = Rng(1);
    let mut t = Tally::default();
    for _ in 0..20_000 {
        t.o2(&r.p2(), &r.p2(), &r.p2());
        t.ic(&r.p2(), &r.p2(), &r.p2(), &r.p2());
        t.o3(&r.p3(), &r.p3(), &r.p3(), &r.p3());
        t.is(&r.p3(), &r.p3(), &r.p3(), &r.p3(), &r.p3());
    }
    assert_eq!(t.zeros, 0);
}

/// The classic test: `a` runs over a 64x64 grid of ulps around (0.5, 0.5) and
/// `b, c` lie on the diagonal; about half the answers are each sign and the
/// diagonal itself is exactly zero.
#[test]
fn orient2d_ulp_grid_near_line() {
    let mut t = Tally::default();
    let (b, c) = ([12.0, 12.0], [24.0, 24.0]);
    for i in 0..64 {
        for j in 0..64 {
            let a = [ulps(0.5, i - 32), ulps(0.5, j - 32)];
            t.o2(&a, &b, &c);
            t.o2(&b, &c, &a);
            // A line with an irrational-ish slope.
            let a2 = [ulps(0.1, i - 32), ulps(0.3, j - 32)];
            t.o2(&a2, &[1.1, 3.3], &[2.1, 6.3]);
        }
    }
    assert!(t.zeros > 0, "the diagonal gives exact zeros");
}

#[test]
fn near_degenerate_circles_and_spheres() {
    let mut r = Rng(2);
    let mut t = Tally::default();
    for _ in 0..3_000 {
        // Four points on (roughly) the unit circle around a random center, nudged by ulps.
        let ctr = [r.range(-10.0, 10.0), r.range(-10.0, 10.0)];
        let on = |r: &mut Rng| {
            let th = r.range(0.0, std::f64::consts::TAU);
            [
                ulps(ctr[0] + th.cos(), r.int(-3, 3)),
                ulps(ctr[1] + th.sin(), r.int(-3, 3)),
            ]
        };
        let (a, b, c, d) = (on(&mut r), on(&mut r), on(&mut r), on(&mut r));
        t.ic(&a, &b, &c, &d);
        // Three nearly collinear points.
        let p = r.p2();
        let q = r.p2();
        let s = r.f64();
        let m = [
            ulps(p[0] + s * (q[0] - p[0]), r.int(-2, 2)),
            ulps(p[1] + s * (q[1] - p[1]), r.int(-2, 2)),
        ];
        t.o2(&p, &q, &m);
        // Nearly coplanar and nearly cospherical.
        let ctr3 = [
            r.range(-10.0, 10.0),
            r.range(-10.0, 10.0),
            r.range(-10.0, 10.0),
        ];
        let on3 = |r: &mut Rng| {
            let (u, v) = (r.range(0.0, std::f64::consts::TAU), r.range(-1.0, 1.0));
            let w = (1.0 - v * v).sqrt();
            [
                ulps(ctr3[0] + w * u.cos(), r.int(-3, 3)),
                ulps(ctr3[1] + w * u.sin(), r.int(-3, 3)),
                ulps(ctr3[2] + v, r.int(-3, 3)),
            ]
        };
        t.is(
            &on3(&mut r),
            &on3(&mut r),
            &on3(&mut r),
            &on3(&mut r),
            &on3(&mut r),
        );
        let (p, q, w) = (r.p3(), r.p3(), r.p3());
        let (s1, s2) = (r.f64(), r.f64());
        let m = [
            ulps(p[0] + s1 * (q[0] - p[0]) + s2 * (w[0] - p[0]), r.int(-2, 2)),
            ulps(p[1] + s1 * (q[1] - p[1]) + s2 * (w[1] - p[1]), r.int(-2, 2)),
            ulps(p[2] + s1 * (q[2] - p[2]) + s2 * (w[2] - p[2]), r.int(-2, 2)),
        ];
        t.o3(&p, &q, &w, &m);
    }
}

#[test]
fn exactly_degenerate_integer_inputs() {
    let mut r = Rng(3);
    let mut t = Tally::default();
    // Pythagorean cocircular points on the circle of radius 5 (and 25, 65).
    let circle5: Vec<[f64; 2]> = [(3, 4), (4, 3), (5, 0), (0, 5)]
        .iter()
        .flat_map(|&(x, y)| {
            [
                [x as f64, y as f64],
                [-x as f64, y as f64],
                [x as f64, -y as f64],
                [-x as f64, -y as f64],
            ]
        })
        .collect();
    for a in &circle5 {
        for b in &circle5 {
            for c in &circle5 {
                for d in circle5.iter().step_by(3) {
                    t.ic(a, b, c, d);
                }
                t.o2(a, b, c);
            }
        }
    }
    let zeros_2d = t.zeros;
    assert!(zeros_2d > 1000, "cocircular inputs must give exact zeros");
    // Cospherical integer points: x²+y²+z² = 9 (permutations/signs of (1,2,2), (0,0,3)).
    let mut sphere3 = Vec::new();
    for x in -3i32..=3 {
        for y in -3i32..=3 {
            for z in -3i32..=3 {
                if x * x + y * y + z * z == 9 {
                    sphere3.push([x as f64 + 0.5, y as f64 - 1.0, z as f64 + 2.0]);
                }
            }
        }
    }
    assert_eq!(sphere3.len(), 30);
    for _ in 0..4_000 {
        let pick = |r: &mut Rng| sphere3[r.int(0, 29) as usize];
        t.is(
            &pick(&mut r),
            &pick(&mut r),
            &pick(&mut r),
            &pick(&mut r),
            &pick(&mut r),
        );
        t.o3(&pick(&mut r), &pick(&mut r), &pick(&mut r), &pick(&mut r));
    }
    // Small integer grids: many collinear / coplanar / cocircular / cospherical tuples.
    for _ in 0..20_000 {
        let g2 = |r: &mut Rng| [r.int(0, 3) as f64, r.int(0, 3) as f64];
        let g3 = |r: &mut Rng| [r.int(0, 2) as f64, r.int(0, 2) as f64, r.int(0, 2) as f64];
        t.o2(&g2(&mut r), &g2(&mut r), &g2(&mut r));
        t.ic(&g2(&mut r), &g2(&mut r), &g2(&mut r), &g2(&mut r));
        t.o3(&g3(&mut r), &g3(&mut r), &g3(&mut r), &g3(&mut r));
        t.is(
            &g3(&mut r),
            &g3(&mut r),
            &g3(&mut r),
            &g3(&mut r),
            &g3(&mut r),
        );
    }
    assert!(t.zeros > zeros_2d + 10_000);
}

/// Inputs whose coordinate differences are not exact doubles (large offsets with
/// small features) exercise the homogeneous exact stage.
#[test]
fn offset_inputs_with_inexact_differences() {
    let mut r = Rng(4);
    let mut t = Tally::default();
    for _ in 0..5_000 {
        let off = r.range(1e3, 1e6);
        let g2 = |r: &mut Rng| {
            [
                off + r.int(0, 3) as f64 * 0.1,
                off + r.int(0, 3) as f64 * 0.1,
            ]
        };
        let g3 = |r: &mut Rng| {
            [
                off + r.int(0, 2) as f64 * 0.1,
                off * 0.5 + r.int(0, 2) as f64 * 0.1,
                -off + r.int(0, 2) as f64 * 0.1,
            ]
        };
        t.o2(&g2(&mut r), &g2(&mut r), &g2(&mut r));
        t.ic(&g2(&mut r), &g2(&mut r), &g2(&mut r), &g2(&mut r));
        t.o3(&g3(&mut r), &g3(&mut r), &g3(&mut r), &g3(&mut r));
        t.is(
            &g3(&mut r),
            &g3(&mut r),
            &g3(&mut r),
            &g3(&mut r),
            &g3(&mut r),
        );
        // Tiny-vs-huge mixtures.
        let m2 = |r: &mut Rng| {
            [
                r.range(-1.0, 1.0) * 1e-7 + 1.0,
                r.range(-1.0, 1.0) * 1e-7 - 3.0,
            ]
        };
        t.o2(&m2(&mut r), &m2(&mut r), &m2(&mut r));
        t.ic(&m2(&mut r), &m2(&mut r), &m2(&mut r), &m2(&mut r));
    }
}
