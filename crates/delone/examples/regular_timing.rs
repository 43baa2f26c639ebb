//! Times the 2D regular triangulation against the unweighted one on the same
//! seeded uniform random points, in one run (ratio, not absolute times).
//!
//! `cargo run --release -p delone --example regular_timing -- [n] [repeats] [weight_scale] [--check]`
//!
//! Weights are uniform in `[0, weight_scale / n)` (default scale 1: about a
//! few percent of the points hidden); `0` gives zero weights.
use std::time::Instant;

use delone::geom::SplitMix64;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args
        .get(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_000_000);
    let reps: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(3);
    let scale: f64 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(1.0);
    let check = args.iter().any(|a| a == "--check");
    let mut rng = SplitMix64::new(42);
    let unit = |r: &mut SplitMix64| (r.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
    let pts: Vec<[f64; 2]> = (0..n).map(|_| [unit(&mut rng), unit(&mut rng)]).collect();
    let w: Vec<f64> = (0..n).map(|_| unit(&mut rng) * scale / n as f64).collect();
    let (mut best_d, mut best_r) = (f64::INFINITY, f64::INFINITY);
    let (mut tris_d, mut tris_r, mut hidden) = (0, 0, 0);
    let mut best_v = f64::INFINITY;
    for _ in 0..reps {
        let t0 = Instant::now();
        let mesh = delone::triangulate(&pts).expect("triangulate");
        best_d = best_d.min(t0.elapsed().as_secs_f64());
        tris_d = mesh.triangles.len();
        drop(mesh);
        let t0 = Instant::now();
        let mesh = delone::tri::regular_triangulation(&pts, &w).expect("regular");
        best_r = best_r.min(t0.elapsed().as_secs_f64());
        tris_r = mesh.triangles.len();
        hidden = mesh.hidden.len();
        let t0 = Instant::now();
        let v = delone::tri::Voronoi2::new_power(&pts, &w, &mesh).unwrap();
        best_v = best_v.min(t0.elapsed().as_secs_f64());
        assert_eq!(v.vertices.len(), tris_r);
        if check {
            delone::tri::validate_regular(&pts, &w, &mesh).expect("valid");
        }
    }
    println!(
        "n={n} delaunay: {tris_d} triangles {best_d:.3}s | regular: {tris_r} triangles, {hidden} hidden, {best_r:.3}s | ratio {:.2} | power diagram {best_v:.3}s ({:.2}x the regular triangulation)",
        best_r / best_d,
        best_v / best_r
    );
}
