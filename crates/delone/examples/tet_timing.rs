//! Times `delone::tetrahedralize` on seeded uniform random points.
//!
//! `cargo run --release -p delone --example tet_timing -- [N]`
use std::time::Instant;

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_000_000);
    let mut r = delone::geom::SplitMix64::new(42);
    let mut u = || (r.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
    let pts: Vec<[f64; 3]> = if std::env::var("SPHERE").is_ok() {
        (0..n)
            .map(|_| {
                let z = 2.0 * u() - 1.0;
                let t = std::f64::consts::TAU * u();
                let r = (1.0 - z * z).sqrt();
                [r * t.cos(), r * t.sin(), z]
            })
            .collect()
    } else if std::env::var("GRID").is_ok() {
        let k = (n as f64).cbrt().round() as usize;
        (0..k * k * k)
            .map(|i| [(i % k) as f64, (i / k % k) as f64, (i / k / k) as f64])
            .collect()
    } else {
        (0..n).map(|_| [u(), u(), u()]).collect()
    };
    let n = pts.len();
    let t = Instant::now();
    let order = delone::geom::brio_order(&pts);
    let sort = t.elapsed().as_secs_f64();
    let pts: Vec<[f64; 3]> = if std::env::var("PRESORT").is_ok() {
        order.iter().map(|&i| pts[i as usize]).collect()
    } else {
        pts
    };
    drop(order);
    let weights: Option<Vec<f64>> = std::env::var("WEIGHTS").ok().map(|_| {
        (0..n)
            .map(|_| 0.01 * (n as f64).powf(-2.0 / 3.0) * u())
            .collect()
    });
    let t = Instant::now();
    let mesh = match &weights {
        Some(w) => delone::tet::regular_tetrahedralization(&pts, w).unwrap(),
        None => delone::tetrahedralize(&pts).unwrap(),
    };
    let total = t.elapsed().as_secs_f64();
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let hwm = status
        .lines()
        .find(|l| l.starts_with("VmHWM"))
        .unwrap_or("VmHWM: ?")
        .to_string();
    println!(
        "n={n} hidden={} tets={} time={total:.3}s (sort {sort:.3}s) tets/point={:.2} {hwm}",
        mesh.hidden.len(),
        mesh.tets.len(),
        mesh.tets.len() as f64 / n as f64
    );
}
