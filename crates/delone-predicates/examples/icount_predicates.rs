//! Fixed-work driver for counting instructions per predicate call with callgrind
//! (repeatable, unlike wall time on a loaded machine).
//!
//! `icount_predicates NAME REPS` evaluates predicate `NAME` (`orient2d`, `incircle`,
//! `orient3d`, `insphere`, `insphere_sos`, `orient3d_sos`, or `robust_` + one of the
//! first four) `REPS` times over 4096 random inputs in `[-1, 1]` (all decided by the
//! filter), or over 4096 near-degenerate inputs rounded from exact configurations
//! (`orient2d_line`, `orient3d_plane`, `incircle_circle`, `insphere_sphere`: points on
//! a random line / plane / circle / sphere, so every determinant is within rounding
//! of zero and the filters fail), or over exact ties whose coordinate differences
//! are not representable (`orient2d_tie`, `incircle_tie`: random points on the
//! x axis; `orient3d_tie`, `insphere_tie`: random points in the plane z = 0 — every
//! stage but the homogeneous expansion one must defer). Instructions per call are
//! `(Ir(REPS) − Ir(0)) / (REPS · 4096)`:
//!
//! ```text
//! valgrind --tool=callgrind target/release/examples/icount_predicates insphere 0
//! valgrind --tool=callgrind target/release/examples/icount_predicates insphere 50
//! ```

use delone_predicates::*;
use robust::{Coord, Coord3D};
use std::hint::black_box;

const N: usize = 4096;

fn main() {
    let mut args = std::env::args().skip(1);
    let name = args.next().unwrap_or_else(|| "insphere".into());
    let reps: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(10);
    let mut s = 7u64;
    let mut f = move || {
        s = s.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = s;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let pts: Vec<[[f64; 3]; 5]> = (0..N)
        .map(|_| {
            [
                [f(), f(), f()],
                [f(), f(), f()],
                [f(), f(), f()],
                [f(), f(), f()],
                [f(), f(), f()],
            ]
        })
        .collect();
    // Near-degenerate sets: each tuple on a random line / plane / circle / sphere.
    let near: Vec<[[f64; 3]; 5]> = (0..N)
        .map(|_| {
            let o = [f(), f(), f()];
            let rad = 0.25 + f().abs();
            let mut q = [[0.0; 3]; 5];
            for p in &mut q {
                // On the sphere of radius `rad` around `o` (direction by rejection-free
                // normalisation of a random vector).
                let d = [f(), f(), f()];
                let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                *p = [
                    o[0] + rad * d[0] / n,
                    o[1] + rad * d[1] / n,
                    o[2] + rad * d[2] / n,
                ];
            }
            q
        })
        .collect();
    let lines: Vec<[[f64; 2]; 3]> = (0..N)
        .map(|_| {
            let (o, d) = ([f(), f()], [f(), f()]);
            std::array::from_fn(|_| {
                let t = f();
                [o[0] + t * d[0], o[1] + t * d[1]]
            })
        })
        .collect();
    let planes: Vec<[[f64; 3]; 4]> = (0..N)
        .map(|_| {
            let (o, u, v) = ([f(), f(), f()], [f(), f(), f()], [f(), f(), f()]);
            std::array::from_fn(|_| {
                let (s, t) = (f(), f());
                std::array::from_fn(|k| o[k] + s * u[k] + t * v[k])
            })
        })
        .collect();
    let circles: Vec<[[f64; 2]; 4]> = (0..N)
        .map(|_| {
            let (o, rad) = ([f(), f()], 0.25 + f().abs());
            std::array::from_fn(|_| {
                let th = std::f64::consts::PI * f();
                [o[0] + rad * th.cos(), o[1] + rad * th.sin()]
            })
        })
        .collect();
    // Exact ties with inexact differences: z = 0 (and y = 0 for the 2D tests).
    let flat: Vec<[[f64; 3]; 5]> = pts
        .iter()
        .map(|q| q.map(|p| [p[0] * 1e3, p[1] * 1e-3, 0.0]))
        .collect();
    let p2 = |p: &[f64; 3]| [p[0], p[1]];
    let x2 = |p: &[f64; 3]| [p[0], 0.0];
    let c2 = |p: &[f64; 3]| Coord { x: p[0], y: p[1] };
    let d2 = |p: &[f64; 2]| Coord { x: p[0], y: p[1] };
    let c3 = |p: &[f64; 3]| Coord3D {
        x: p[0],
        y: p[1],
        z: p[2],
    };
    let mut acc = 0usize;
    macro_rules! run {
        ($q:ident => $e:expr) => {
            run!(pts, $q => $e)
        };
        ($set:ident, $q:ident => $e:expr) => {
            for _ in 0..reps {
                for $q in &$set {
                    let $q = black_box($q);
                    acc += ($e > 0.0) as usize;
                }
            }
        };
    }
    match name.as_str() {
        "orient2d" => run!(q => orient2d(&p2(&q[0]), &p2(&q[1]), &p2(&q[2]))),
        "incircle" => run!(q => incircle(&p2(&q[0]), &p2(&q[1]), &p2(&q[2]), &p2(&q[3]))),
        "orient3d" => run!(q => orient3d(&q[0], &q[1], &q[2], &q[3])),
        "insphere" => run!(q => insphere(&q[0], &q[1], &q[2], &q[3], &q[4])),
        "orient3d_sos" => run!(q => orient3d_sos(&q[0], &q[1], &q[2], &q[3], 0, 1, 2, 3) as f64),
        "insphere_sos" => {
            run!(q => insphere_sos(&q[0], &q[1], &q[2], &q[3], &q[4], 3, 1, 4, 0, 2) as f64)
        }
        "orient2d_line" => run!(lines, q => orient2d(&q[0], &q[1], &q[2])),
        "orient3d_plane" => run!(planes, q => orient3d(&q[0], &q[1], &q[2], &q[3])),
        "incircle_circle" => run!(circles, q => incircle(&q[0], &q[1], &q[2], &q[3])),
        "insphere_sphere" => run!(near, q => insphere(&q[0], &q[1], &q[2], &q[3], &q[4])),
        "orient2d_tie" => run!(flat, q => orient2d(&x2(&q[0]), &x2(&q[1]), &x2(&q[2]))),
        "incircle_tie" => {
            run!(flat, q => incircle(&x2(&q[0]), &x2(&q[1]), &x2(&q[2]), &x2(&q[3])))
        }
        "orient3d_tie" => run!(flat, q => orient3d(&q[0], &q[1], &q[2], &q[3])),
        "insphere_tie" => run!(flat, q => insphere(&q[0], &q[1], &q[2], &q[3], &q[4])),
        "robust_orient2d_line" => {
            run!(lines, q => robust::orient2d(d2(&q[0]), d2(&q[1]), d2(&q[2])))
        }
        "robust_orient3d_plane" => {
            run!(planes, q => robust::orient3d(c3(&q[0]), c3(&q[1]), c3(&q[2]), c3(&q[3])))
        }
        "robust_incircle_circle" => {
            run!(circles, q => robust::incircle(d2(&q[0]), d2(&q[1]), d2(&q[2]), d2(&q[3])))
        }
        "robust_insphere_sphere" => {
            run!(near, q => robust::insphere(c3(&q[0]), c3(&q[1]), c3(&q[2]), c3(&q[3]), c3(&q[4])))
        }
        "robust_orient2d" => run!(q => robust::orient2d(c2(&q[0]), c2(&q[1]), c2(&q[2]))),
        "robust_incircle" => {
            run!(q => robust::incircle(c2(&q[0]), c2(&q[1]), c2(&q[2]), c2(&q[3])))
        }
        "robust_orient3d" => {
            run!(q => robust::orient3d(c3(&q[0]), c3(&q[1]), c3(&q[2]), c3(&q[3])))
        }
        "robust_insphere" => {
            run!(q => robust::insphere(c3(&q[0]), c3(&q[1]), c3(&q[2]), c3(&q[3]), c3(&q[4])))
        }
        other => {
            eprintln!("unknown predicate {other}");
            std::process::exit(2);
        }
    }
    println!("{name} x {reps}: {acc}");
}
