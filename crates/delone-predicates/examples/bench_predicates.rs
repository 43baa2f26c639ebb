//! Micro-benchmark: ns/call of each predicate next to the `robust` crate, on
//! random inputs (decided by the filter), on exactly degenerate integer inputs
//! (exact stage, short translated determinant) and on near-degenerate inputs with
//! points of mixed magnitudes (exact stage, homogeneous determinant).
//!
//! Run with `cargo run --release -p delone-predicates --example bench_predicates`.

use delone_predicates::*;
use robust::{Coord, Coord3D};
use std::hint::black_box;
use std::time::Instant;

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn f(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn int(&mut self, n: u64) -> f64 {
        (self.next() % n) as f64
    }
}

const N: usize = 4096;

thread_local! {
    static CURRENT: std::cell::RefCell<String> = const { std::cell::RefCell::new(String::new()) };
}

/// Whether the current row matches the optional command-line filter.
fn selected() -> bool {
    match std::env::args().nth(1) {
        None => true,
        Some(f) => CURRENT.with(|c| c.borrow().contains(&f)),
    }
}

fn set(name: &str, kind: &str) {
    CURRENT.with(|c| *c.borrow_mut() = format!("{name}/{kind}"));
}

/// Time `f` over all inputs, repeated until ~`budget` ms; returns ns per call.
fn time<T>(inputs: &[T], f: impl Fn(&T) -> f64) -> f64 {
    // Optional filter: `bench_predicates orient2d/degenerate` runs the matching rows.
    if !selected() {
        return f64::NAN;
    }
    let mut reps = 1u64;
    loop {
        let t = Instant::now();
        // Consume the results the way a kernel does: through their sign.
        let mut acc = 0usize;
        for _ in 0..reps {
            for x in inputs {
                acc += (f(black_box(x)) > 0.0) as usize;
            }
        }
        black_box(acc);
        let el = t.elapsed().as_secs_f64();
        if el > 0.15 {
            return el * 1e9 / (reps as f64 * inputs.len() as f64);
        }
        reps *= 2;
    }
}

fn row(name: &str, kind: &str, ours: f64, theirs: Option<f64>) {
    if ours.is_nan() {
        return;
    }
    match theirs {
        Some(t) => println!(
            "{name:<22} {kind:<16} {ours:>9.1} {t:>9.1} {:>7.2}",
            ours / t
        ),
        None => println!("{name:<22} {kind:<16} {ours:>9.1} {:>9} {:>7}", "-", "-"),
    }
}

fn c2(p: &[f64; 2]) -> Coord<f64> {
    Coord { x: p[0], y: p[1] }
}
fn c3(p: &[f64; 3]) -> Coord3D<f64> {
    Coord3D {
        x: p[0],
        y: p[1],
        z: p[2],
    }
}

fn main() {
    let mut r = Rng(7);
    let p2 = |r: &mut Rng| [r.f() * 2.0 - 1.0, r.f() * 2.0 - 1.0];
    let p3 = |r: &mut Rng| [r.f() * 2.0 - 1.0, r.f() * 2.0 - 1.0, r.f() * 2.0 - 1.0];

    // Random (filter) inputs.
    let rnd2: Vec<[[f64; 2]; 4]> = (0..N)
        .map(|_| [p2(&mut r), p2(&mut r), p2(&mut r), p2(&mut r)])
        .collect();
    let rnd3: Vec<[[f64; 3]; 5]> = (0..N)
        .map(|_| [p3(&mut r), p3(&mut r), p3(&mut r), p3(&mut r), p3(&mut r)])
        .collect();
    // Exactly degenerate integer inputs: collinear / cocircular, coplanar / cospherical.
    let circle: Vec<[f64; 2]> = [(3.0, 4.0), (4.0, 3.0), (5.0, 0.0), (0.0, 5.0)]
        .iter()
        .flat_map(|&(x, y): &(f64, f64)| [[x, y], [-x, y], [x, -y], [-x, -y]])
        .map(|p| [p[0] + 10.0, p[1] - 7.0])
        .collect();
    let mut sphere = Vec::new();
    for x in -3i32..=3 {
        for y in -3i32..=3 {
            for z in -3i32..=3 {
                if x * x + y * y + z * z == 9 {
                    sphere.push([x as f64 + 5.0, y as f64, z as f64 - 2.0]);
                }
            }
        }
    }
    let pick = |r: &mut Rng, n: usize| r.next() as usize % n;
    let deg2: Vec<[[f64; 2]; 4]> = (0..N)
        .map(|_| {
            let mut q = [[0.0; 2]; 4];
            for p in &mut q {
                *p = circle[pick(&mut r, circle.len())];
            }
            // Make a, b, c collinear for orient2d: c on segment ab's line.
            q
        })
        .collect();
    let line2: Vec<[[f64; 2]; 3]> = (0..N)
        .map(|_| {
            let (t1, t2, t3) = (r.int(100), r.int(100), r.int(100));
            [
                [t1, 2.0 * t1 + 1.0],
                [t2, 2.0 * t2 + 1.0],
                [t3, 2.0 * t3 + 1.0],
            ]
        })
        .collect();
    let deg3: Vec<[[f64; 3]; 5]> = (0..N)
        .map(|_| {
            let mut q = [[0.0; 3]; 5];
            for p in &mut q {
                *p = sphere[pick(&mut r, sphere.len())];
            }
            q
        })
        .collect();
    let plane3: Vec<[[f64; 3]; 4]> = (0..N)
        .map(|_| {
            let mut q = [[0.0; 3]; 4];
            for p in &mut q {
                let (u, v) = (r.int(50), r.int(50));
                *p = [u, v, 3.0 * u - 2.0 * v + 7.0];
            }
            q
        })
        .collect();
    // Near-degenerate with mixed magnitudes (inexact differences): points on a line /
    // plane through scaled parameters, rounded; the sphere/circle through the origin.
    let mag = |r: &mut Rng| [1e-3, 0.7, 3.0, 1e2, 1e5][pick(r, 5)] * (0.5 + r.f());
    let near2: Vec<[[f64; 2]; 4]> = (0..N)
        .map(|_| {
            let rad = mag(&mut r);
            let on = |r: &mut Rng| {
                let th = if r.next() & 1 == 0 {
                    3.1 + 0.1 * r.f()
                } else {
                    std::f64::consts::TAU * r.f()
                };
                [rad + rad * th.cos(), rad * th.sin()]
            };
            [on(&mut r), on(&mut r), on(&mut r), on(&mut r)]
        })
        .collect();
    let near3: Vec<[[f64; 3]; 5]> = (0..N)
        .map(|_| {
            let rad = mag(&mut r);
            let on = |r: &mut Rng| {
                let (th, z) = (
                    std::f64::consts::TAU * r.f(),
                    if r.next() & 1 == 0 {
                        -1.0 + 1e-3 * r.f()
                    } else {
                        2.0 * r.f() - 1.0
                    },
                );
                let w = (1.0 - z * z).sqrt();
                [rad * w * th.cos(), rad * w * th.sin(), rad + rad * z]
            };
            [on(&mut r), on(&mut r), on(&mut r), on(&mut r), on(&mut r)]
        })
        .collect();
    let nline2: Vec<[[f64; 2]; 3]> = (0..N)
        .map(|_| {
            let (u, v) = ([r.f(), r.f()], [r.f(), r.f()]);
            let on = |r: &mut Rng| {
                let s = mag(r);
                [u[0] + s * v[0], u[1] + s * v[1]]
            };
            [on(&mut r), on(&mut r), on(&mut r)]
        })
        .collect();
    let nplane3: Vec<[[f64; 3]; 4]> = (0..N)
        .map(|_| {
            let (u, v, w) = (
                [r.f(), r.f(), r.f()],
                [r.f(), r.f(), r.f()],
                [r.f(), r.f(), r.f()],
            );
            let on = |r: &mut Rng| {
                let (s, t) = (mag(r), mag(r));
                [
                    u[0] + s * v[0] + t * w[0],
                    u[1] + s * v[1] + t * w[1],
                    u[2] + s * v[2] + t * w[2],
                ]
            };
            [on(&mut r), on(&mut r), on(&mut r), on(&mut r)]
        })
        .collect();

    println!(
        "{:<22} {:<16} {:>9} {:>9} {:>7}",
        "predicate", "inputs", "delone", "robust", "ratio"
    );
    println!(
        "{:<22} {:<16} {:>9} {:>9} {:>7}",
        "", "", "ns/call", "ns/call", ""
    );
    // orient2d
    let o2 = |q: &[[f64; 2]]| orient2d(&q[0], &q[1], &q[2]);
    let o2r = |q: &[[f64; 2]]| robust::orient2d(c2(&q[0]), c2(&q[1]), c2(&q[2]));
    set("orient2d", "random");
    row(
        "orient2d",
        "random",
        time(&rnd2, |q| o2(q)),
        Some(time(&rnd2, |q| o2r(q))),
    );
    set("orient2d", "degenerate");
    row(
        "orient2d",
        "degenerate",
        time(&line2, |q| o2(q)),
        Some(time(&line2, |q| o2r(q))),
    );
    set("orient2d", "near-degenerate");
    row(
        "orient2d",
        "near-degenerate",
        time(&nline2, |q| o2(q)),
        Some(time(&nline2, |q| o2r(q))),
    );
    // incircle
    let ic = |q: &[[f64; 2]; 4]| incircle(&q[0], &q[1], &q[2], &q[3]);
    let icr = |q: &[[f64; 2]; 4]| robust::incircle(c2(&q[0]), c2(&q[1]), c2(&q[2]), c2(&q[3]));
    set("incircle", "random");
    row(
        "incircle",
        "random",
        time(&rnd2, ic),
        Some(time(&rnd2, icr)),
    );
    set("incircle", "degenerate");
    row(
        "incircle",
        "degenerate",
        time(&deg2, ic),
        Some(time(&deg2, icr)),
    );
    set("incircle", "near-degenerate");
    row(
        "incircle",
        "near-degenerate",
        time(&near2, ic),
        Some(time(&near2, icr)),
    );
    // orient3d
    let o3 = |q: &[[f64; 3]]| orient3d(&q[0], &q[1], &q[2], &q[3]);
    let o3r = |q: &[[f64; 3]]| robust::orient3d(c3(&q[0]), c3(&q[1]), c3(&q[2]), c3(&q[3]));
    set("orient3d", "random");
    row(
        "orient3d",
        "random",
        time(&rnd3, |q| o3(q)),
        Some(time(&rnd3, |q| o3r(q))),
    );
    set("orient3d", "degenerate");
    row(
        "orient3d",
        "degenerate",
        time(&plane3, |q| o3(q)),
        Some(time(&plane3, |q| o3r(q))),
    );
    set("orient3d", "near-degenerate");
    row(
        "orient3d",
        "near-degenerate",
        time(&nplane3, |q| o3(q)),
        Some(time(&nplane3, |q| o3r(q))),
    );
    // insphere
    let is = |q: &[[f64; 3]; 5]| insphere(&q[0], &q[1], &q[2], &q[3], &q[4]);
    let isr =
        |q: &[[f64; 3]; 5]| robust::insphere(c3(&q[0]), c3(&q[1]), c3(&q[2]), c3(&q[3]), c3(&q[4]));
    set("insphere", "random");
    row(
        "insphere",
        "random",
        time(&rnd3, is),
        Some(time(&rnd3, isr)),
    );
    set("insphere", "degenerate");
    row(
        "insphere",
        "degenerate",
        time(&deg3, is),
        Some(time(&deg3, isr)),
    );
    set("insphere", "near-degenerate");
    row(
        "insphere",
        "near-degenerate",
        time(&near3, is),
        Some(time(&near3, isr)),
    );
    // Weighted and SoS (no robust counterpart).
    let icw = |q: &[[f64; 2]; 4]| incircle_weighted(&q[0], &q[1], &q[2], &q[3], 0.0, 0.0, 0.0, 0.0);
    set("incircle_weighted", "random");
    row("incircle_weighted", "random", time(&rnd2, icw), None);
    set("incircle_weighted", "degenerate");
    row("incircle_weighted", "degenerate", time(&deg2, icw), None);
    set("incircle_weighted", "near-degenerate");
    row(
        "incircle_weighted",
        "near-degenerate",
        time(&near2, icw),
        None,
    );
    let isw = |q: &[[f64; 3]; 5]| {
        insphere_weighted(&q[0], &q[1], &q[2], &q[3], &q[4], 0.0, 0.0, 0.0, 0.0, 0.0)
    };
    set("insphere_weighted", "random");
    row("insphere_weighted", "random", time(&rnd3, isw), None);
    set("insphere_weighted", "degenerate");
    row("insphere_weighted", "degenerate", time(&deg3, isw), None);
    set("insphere_weighted", "near-degenerate");
    row(
        "insphere_weighted",
        "near-degenerate",
        time(&near3, isw),
        None,
    );
    let o2s = |q: &[[f64; 2]]| orient2d_sos(&q[0], &q[1], &q[2], 0, 1, 2) as f64;
    set("orient2d_sos", "degenerate");
    row("orient2d_sos", "degenerate", time(&line2, |q| o2s(q)), None);
    let o3s = |q: &[[f64; 3]]| orient3d_sos(&q[0], &q[1], &q[2], &q[3], 0, 1, 2, 3) as f64;
    set("orient3d_sos", "degenerate");
    row(
        "orient3d_sos",
        "degenerate",
        time(&plane3, |q| o3s(q)),
        None,
    );
    let ics = |q: &[[f64; 2]; 4]| incircle_sos(&q[0], &q[1], &q[2], &q[3], 3, 1, 2, 0) as f64;
    set("incircle_sos", "random");
    row("incircle_sos", "random", time(&rnd2, ics), None);
    set("incircle_sos", "degenerate");
    row("incircle_sos", "degenerate", time(&deg2, ics), None);
    let iss =
        |q: &[[f64; 3]; 5]| insphere_sos(&q[0], &q[1], &q[2], &q[3], &q[4], 3, 1, 4, 0, 2) as f64;
    set("insphere_sos", "random");
    row("insphere_sos", "random", time(&rnd3, iss), None);
    set("insphere_sos", "degenerate");
    row("insphere_sos", "degenerate", time(&deg3, iss), None);
}
