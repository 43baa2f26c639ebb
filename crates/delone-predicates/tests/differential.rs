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

/// Near-degenerate inputs whose points differ widely in magnitude, so that the
/// coordinate differences are not exact doubles (this exercises the homogeneous
/// exact stage): points on lines, planes, circles and spheres passing near the
/// origin, at parameters from 1e-3 to 1e6.
#[test]
fn near_degenerate_with_inexact_differences() {
    let mut r = Rng(4);
    let mut t = Tally::default();
    let mag = |r: &mut Rng| {
        let m = [1e-3, 0.7, 3.0, 1e2, 1e6][r.int(0, 4) as usize];
        if r.int(0, 1) == 0 {
            m * r.range(0.5, 1.0)
        } else {
            -m * r.range(0.5, 1.0)
        }
    };
    for _ in 0..5_000 {
        let (u, v) = (r.p2(), r.p2());
        let on_line = |r: &mut Rng| {
            let s = mag(r);
            [u[0] + s * v[0], u[1] + s * v[1]]
        };
        t.o2(&on_line(&mut r), &on_line(&mut r), &on_line(&mut r));
        // Circle of radius rad centred at (rad, 0) + tiny: passes near the origin.
        let rad = mag(&mut r).abs();
        let on_circle = |r: &mut Rng| {
            let th = [r.range(3.1, 3.2), r.range(0.0, std::f64::consts::TAU)][r.int(0, 1) as usize];
            [rad + rad * th.cos(), 1e-3 + rad * th.sin()]
        };
        t.ic(
            &on_circle(&mut r),
            &on_circle(&mut r),
            &on_circle(&mut r),
            &on_circle(&mut r),
        );
        let (u3, v3, w3) = (r.p3(), r.p3(), r.p3());
        let on_plane = |r: &mut Rng| {
            let (s, q) = (mag(r), mag(r));
            [
                u3[0] + s * v3[0] + q * w3[0],
                u3[1] + s * v3[1] + q * w3[1],
                u3[2] + s * v3[2] + q * w3[2],
            ]
        };
        t.o3(
            &on_plane(&mut r),
            &on_plane(&mut r),
            &on_plane(&mut r),
            &on_plane(&mut r),
        );
        let on_sphere = |r: &mut Rng| {
            let (th, z) = (
                r.range(0.0, std::f64::consts::TAU),
                [r.range(-1.0, 1.0), r.range(-1.0, -0.999)][r.int(0, 1) as usize],
            );
            let w = (1.0 - z * z).sqrt();
            [rad * w * th.cos(), 0.5 + rad * w * th.sin(), rad + rad * z]
        };
        t.is(
            &on_sphere(&mut r),
            &on_sphere(&mut r),
            &on_sphere(&mut r),
            &on_sphere(&mut r),
            &on_sphere(&mut r),
        );
    }
}

/// Points on axis-parallel planes (CAD faces) with coordinates of mixed
/// magnitudes, so that the differences in the other two coordinates are
/// inexact: orient3d is exactly 0 (a zero column), and stays exact when one
/// point leaves the plane by one ulp or when two points coincide.
#[test]
fn axis_parallel_planes_with_inexact_differences() {
    let mut r = Rng(11);
    let mut t = Tally::default();
    let mag = |r: &mut Rng| {
        let m = [1e-7, 3e-4, 0.7, 3.0, 1e5][r.int(0, 4) as usize];
        m * r.range(-1.0, 1.0)
    };
    for _ in 0..3_000 {
        let k = r.int(0, 2) as usize;
        let c = mag(&mut r);
        let mut pts = [[0.0; 3]; 4];
        for p in &mut pts {
            for (j, x) in p.iter_mut().enumerate() {
                *x = if j == k { c } else { mag(&mut r) };
            }
        }
        let [a, b, cc, d] = pts;
        t.o3(&a, &b, &cc, &d);
        assert_eq!(orient3d(&a, &b, &cc, &d), 0.0);
        // One point one ulp off the plane: no longer a zero column.
        let mut off = pts;
        let i = r.int(0, 3) as usize;
        off[i][k] = ulps(off[i][k], 1);
        t.o3(&off[0], &off[1], &off[2], &off[3]);
        // Two points equal (a zero row), anywhere.
        let mut dup = [r.p3(), r.p3(), r.p3(), r.p3()];
        let (i, j) = (r.int(0, 3) as usize, r.int(0, 3) as usize);
        dup[j] = dup[i];
        t.o3(&dup[0], &dup[1], &dup[2], &dup[3]);
    }
    assert!(t.zeros >= 3_000 * SCALES.len());
}

/// Integer points near circles, spheres, lines and planes whose coordinate
/// differences range around the limits of the "coarse grid" fast exact path
/// (plain floating point is exact there); a limit set too high would make the
/// near-zero determinants round to the wrong sign.
#[test]
fn integer_inputs_around_the_coarse_grid_limits() {
    let mut r = Rng(5);
    let mut t = Tally::default();
    for &rad in &[
        60.0, 127.0, 255.0, 256.0, 300.0, 511.0, 700.0, 2047.0, 4095.0, 5000.0, 40_000.0, 70_000.0,
        3.0e7, 1.0e9,
    ] {
        let near_circle = |r: &mut Rng| {
            let x = (r.range(-1.0, 1.0) * rad).round();
            let y = (rad * rad - x * x).max(0.0).sqrt().round();
            [x, if r.int(0, 1) == 0 { y } else { -y }]
        };
        let near_sphere = |r: &mut Rng| {
            let x = (r.range(-0.7, 0.7) * rad).round();
            let y = (r.range(-0.7, 0.7) * rad).round();
            let z = (rad * rad - x * x - y * y).max(0.0).sqrt().round();
            [x, y, if r.int(0, 1) == 0 { z } else { -z }]
        };
        for _ in 0..300 {
            t.ic(
                &near_circle(&mut r),
                &near_circle(&mut r),
                &near_circle(&mut r),
                &near_circle(&mut r),
            );
            t.is(
                &near_sphere(&mut r),
                &near_sphere(&mut r),
                &near_sphere(&mut r),
                &near_sphere(&mut r),
                &near_sphere(&mut r),
            );
            // Near-collinear / near-coplanar integer points: p + round(s * v).
            let (p, v) = (
                [r.int(-9, 9) as f64, r.int(-9, 9) as f64],
                [r.int(1, 97) as f64, r.int(1, 89) as f64],
            );
            let on = |r: &mut Rng| {
                let s = r.range(-1.0, 1.0) * rad / 100.0;
                [p[0] + (s * v[0]).round(), p[1] + (s * v[1]).round()]
            };
            t.o2(&on(&mut r), &on(&mut r), &on(&mut r));
            let (u, w) = (
                [r.int(1, 9) as f64, r.int(-9, 9) as f64, r.int(1, 9) as f64],
                [r.int(-9, 9) as f64, r.int(1, 9) as f64, r.int(-9, 9) as f64],
            );
            let on3 = |r: &mut Rng| {
                let (s, q) = (
                    r.range(-1.0, 1.0) * rad / 10.0,
                    r.range(-1.0, 1.0) * rad / 10.0,
                );
                [
                    (s * u[0] + q * w[0]).round(),
                    (s * u[1] + q * w[1]).round(),
                    (s * u[2] + q * w[2]).round(),
                ]
            };
            t.o3(&on3(&mut r), &on3(&mut r), &on3(&mut r), &on3(&mut r));
        }
    }
    assert!(t.zeros > 100);
}

/// Exact ties (collinear, cocircular, coplanar, cospherical) with large odd
/// integer coordinates straddling the coarse-grid limits: plain floating point
/// rounds these determinants away from zero once the limits are exceeded.
#[test]
fn exact_ties_with_large_integer_coordinates() {
    let mut r = Rng(6);
    let mut t = Tally::default();
    let pyth2 = [(3.0, 4.0), (4.0, 3.0), (5.0, 0.0), (0.0, 5.0)];
    let pyth3 = [
        (1.0, 2.0, 2.0),
        (2.0, 1.0, 2.0),
        (2.0, 2.0, 1.0),
        (3.0, 0.0, 0.0),
        (0.0, 3.0, 0.0),
        (0.0, 0.0, 3.0),
    ];
    for &k in &[
        101.0, 171.0, 341.0, 683.0, 1365.0, 2731.0, 5461.0, 21845.0, 87381.0, 349525.0, 1398101.0,
    ] {
        let off = [
            r.int(-999, 999) as f64 * 2.0 + 1.0,
            r.int(-999, 999) as f64 * 2.0 + 1.0,
            7.0,
        ];
        for _ in 0..200 {
            let c = |r: &mut Rng| {
                let (x, y) = pyth2[r.int(0, 3) as usize];
                let (sx, sy) = (
                    if r.int(0, 1) == 0 { 1.0 } else { -1.0 },
                    if r.int(0, 1) == 0 { 1.0 } else { -1.0 },
                );
                [off[0] + sx * x * k, off[1] + sy * y * k]
            };
            t.ic(&c(&mut r), &c(&mut r), &c(&mut r), &c(&mut r));
            let s = |r: &mut Rng| {
                let (x, y, z) = pyth3[r.int(0, 5) as usize];
                let sg = |r: &mut Rng| if r.int(0, 1) == 0 { 1.0 } else { -1.0 };
                [
                    off[0] + sg(r) * x * k,
                    off[1] + sg(r) * y * k,
                    off[2] + sg(r) * z * k,
                ]
            };
            t.is(&s(&mut r), &s(&mut r), &s(&mut r), &s(&mut r), &s(&mut r));
            // Collinear and coplanar with parameters around k^2 (up to ~2^41).
            let l = |r: &mut Rng| {
                let s = r.int(-1000, 1000) as f64 * k * 3.0 + 1.0;
                [off[0] + 3.0 * s, off[1] - 5.0 * s]
            };
            t.o2(&l(&mut r), &l(&mut r), &l(&mut r));
            let pl = |r: &mut Rng| {
                let (s, q) = (
                    r.int(-1000, 1000) as f64 * k / 8.0,
                    r.int(-1000, 1000) as f64 * k / 8.0,
                );
                let (s, q) = (s.round() + 1.0, q.round() + 1.0);
                [
                    off[0] + 3.0 * s - q,
                    off[1] + 2.0 * s + 5.0 * q,
                    off[2] - s + 3.0 * q,
                ]
            };
            t.o3(&pl(&mut r), &pl(&mut r), &pl(&mut r), &pl(&mut r));
        }
    }
    assert!(t.zeros > 20_000, "{}", t.zeros);
}

/// Unimodular pairs of consecutive Fibonacci vectors: `orient2d` is ±1 while its
/// two products reach 2^80, far beyond what plain floating point resolves.
#[test]
fn fibonacci_orient2d_is_plus_or_minus_one() {
    let mut t = Tally::default();
    let mut f = [1.0f64, 1.0, 2.0];
    for n in 3..58 {
        let c = [(n as f64) * 3.0 - 7.0, 11.0 - n as f64];
        let a = [c[0] + f[2], c[1] + f[1]];
        let b = [c[0] + f[1], c[1] + f[0]];
        t.o2(&a, &b, &c);
        // With f = (F(n-2), F(n-1), F(n)): F(n) F(n-2) - F(n-1)^2 = (-1)^(n+1).
        assert_eq!(
            sign(orient2d(&a, &b, &c)),
            if n % 2 == 1 { 1 } else { -1 },
            "n = {n}"
        );
        f = [f[1], f[2], f[1] + f[2]];
    }
}

/// The usual exact paths fit in a small thread stack (the worst-case-capacity
/// tiers live in separate, rarely called functions).
#[test]
fn exact_paths_run_on_a_small_stack() {
    let h = std::thread::Builder::new()
        .stack_size(256 * 1024)
        .spawn(|| {
            let mut r = Rng(7);
            let mut t = Tally::default();
            for _ in 0..2_000 {
                // Exact ties with inexact differences: stage B.
                let k = [1e-3, 0.1, 3.0][r.int(0, 2) as usize];
                let s = |r: &mut Rng| {
                    let (x, y, z) = [
                        (1.0, 2.0, 2.0),
                        (2.0, 1.0, 2.0),
                        (3.0, 0.0, 0.0),
                        (0.0, 0.0, 3.0),
                    ][r.int(0, 3) as usize];
                    [x * k + 0.5, y * k - 1.0, z * k + 1e3]
                };
                t.is(&s(&mut r), &s(&mut r), &s(&mut r), &s(&mut r), &s(&mut r));
                t.o3(&s(&mut r), &s(&mut r), &s(&mut r), &s(&mut r));
                let c = |r: &mut Rng| {
                    let (x, y) =
                        [(3.0, 4.0), (-4.0, 3.0), (5.0, 0.0), (0.0, -5.0)][r.int(0, 3) as usize];
                    [x * k + 0.25, y * k - 1e3]
                };
                t.ic(&c(&mut r), &c(&mut r), &c(&mut r), &c(&mut r));
            }
            t.zeros
        })
        .expect("spawn");
    assert!(h.join().expect("no stack overflow") > 0);
}
