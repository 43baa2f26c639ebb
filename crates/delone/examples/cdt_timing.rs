//! Timing of the constrained triangulation on a random star-shaped polygon
//! (`cargo run --release --example cdt_timing -- N`).
use delone::model::pslg::Pslg;
use delone::tri::constrain::{constrained_triangulation, CdtOptions};

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(100_000);
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut rnd = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let points: Vec<[f64; 2]> = (0..n)
        .map(|i| {
            let a = std::f64::consts::TAU * (i as f64 + 0.5 * rnd()) / n as f64;
            let r = 0.5 + 0.5 * rnd();
            [r * a.cos(), r * a.sin()]
        })
        .collect();
    let segments: Vec<[u32; 2]> = (0..n as u32).map(|i| [i, (i + 1) % n as u32]).collect();
    let g = Pslg::new(points, segments);
    let t = std::time::Instant::now();
    let dt = delone::triangulate(&g.points).unwrap();
    let t_dt = t.elapsed();
    let t = std::time::Instant::now();
    let cdt = constrained_triangulation(&g, CdtOptions::default()).unwrap();
    let t_cdt = t.elapsed();
    println!(
        "n={n}: DT {:.3} s ({} tris), CDT+carve {:.3} s ({} tris, {} flips)",
        t_dt.as_secs_f64(),
        dt.triangles.len(),
        t_cdt.as_secs_f64(),
        cdt.triangles.len(),
        cdt.report.flips
    );
}
