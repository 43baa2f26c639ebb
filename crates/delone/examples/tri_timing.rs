//! Times `delone::triangulate` on seeded uniform random points.
//!
//! `cargo run --release -p delone --example tri_timing -- [n] [repeats] [--check] [--grid]`
//!
//! `--grid` uses a square integer grid of about `n` points instead (every cell
//! is cocircular: the exact and symbolic-perturbation paths are exercised).
use std::time::Instant;

use delone::geom::SplitMix64;

fn peak_rss_kib() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args
        .get(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_000_000);
    let reps: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(3);
    let check = args.iter().any(|a| a == "--check");
    let mut rng = SplitMix64::new(42);
    let unit = |r: &mut SplitMix64| (r.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
    let pts: Vec<[f64; 2]> = if args.iter().any(|a| a == "--grid") {
        let side = (n as f64).sqrt().round() as usize;
        (0..side * side)
            .map(|k| [(k % side) as f64, (k / side) as f64])
            .collect()
    } else {
        (0..n).map(|_| [unit(&mut rng), unit(&mut rng)]).collect()
    };
    let n = pts.len();
    let rss0 = peak_rss_kib().unwrap_or(0);
    let mut best = f64::INFINITY;
    let mut tris = 0;
    for _ in 0..reps {
        let t0 = Instant::now();
        let mesh = delone::triangulate(&pts).expect("triangulate");
        let dt = t0.elapsed().as_secs_f64();
        best = best.min(dt);
        tris = mesh.triangles.len();
        if check {
            delone::tri::validate(&pts, &mesh).expect("valid");
        }
    }
    let rss1 = peak_rss_kib().unwrap_or(0);
    let mut brio = f64::INFINITY;
    for _ in 0..reps {
        let t0 = Instant::now();
        let order = delone::geom::brio_order(&pts);
        brio = brio.min(t0.elapsed().as_secs_f64());
        assert_eq!(order.len(), n);
    }
    println!("brio_order alone: {brio:.3}s");
    println!(
        "n={n} triangles={tris} best={best:.3}s ({:.0} ns/point) peak RSS={} MiB (before: {} MiB, {:.0} B/point incl. input)",
        best * 1e9 / n as f64,
        rss1 / 1024,
        rss0 / 1024,
        rss1 as f64 * 1024.0 / n as f64
    );
}
