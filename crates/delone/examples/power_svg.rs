//! Draws a 2D power diagram: 200 seeded random points in the unit square
//! with random weights, their power cells clipped to the square (filled, a
//! lighter shade for lighter sites), the regular triangulation, the visible
//! sites (dark dots) and the hidden ones (red rings: empty power cells).
//!
//! `cargo run --release -p delone --example power_svg -- out.svg [points] [weight_scale]`
//!
//! Weights are uniform in `[0, weight_scale / points)` (default scale 2).
use delone::geom::SplitMix64;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let Some(path) = args.get(1) else {
        eprintln!("usage: power_svg OUT.svg [points=200] [weight_scale=2]");
        std::process::exit(2);
    };
    let n: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(200);
    let scale: f64 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(2.0);
    let mut rng = SplitMix64::new(2026);
    let mut unit = || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
    let pts: Vec<[f64; 2]> = (0..n).map(|_| [unit(), unit()]).collect();
    let weights: Vec<f64> = (0..n).map(|_| unit() * scale / n as f64).collect();
    let bbox = [[0.0, 0.0], [1.0, 1.0]];
    let mesh = delone::tri::regular_triangulation(&pts, &weights)?;
    delone::tri::validate_regular(&pts, &weights, &mesh)?;
    let cells = delone::tri::Voronoi2::new_power(&pts, &weights, &mesh)
        .unwrap()
        .cells_clipped(&pts, bbox);
    // Heavier sites get deeper blues.
    let wmax = weights.iter().cloned().fold(f64::MIN_POSITIVE, f64::max);
    let fills: Vec<[u8; 3]> = weights
        .iter()
        .map(|&w| {
            let t = (w / wmax).clamp(0.0, 1.0);
            let c = |lo: f64, hi: f64| (hi + (lo - hi) * t) as u8;
            [c(150.0, 235.0), c(190.0, 242.0), c(235.0, 250.0)]
        })
        .collect();
    let visible: Vec<[f64; 2]> = (0..n)
        .filter(|&i| mesh.vertex_map[i] == i as u32)
        .map(|i| pts[i])
        .collect();
    let hidden: Vec<[f64; 2]> = mesh.hidden.iter().map(|&h| pts[h as usize]).collect();
    // Hidden sites as red rings: a red dot with a smaller white dot on top.
    let layers = [
        delone_io::SvgLayer::Polygons {
            points: &cells.polygon_points,
            offsets: &cells.offsets,
            fills: &fills,
            stroke: "#334455",
            width: 1.2,
        },
        delone_io::SvgLayer::Triangles {
            points: &pts,
            triangles: &mesh.triangles,
            stroke: "#99aabb",
            width: 0.4,
        },
        delone_io::SvgLayer::Points {
            points: &visible,
            radius: 2.2,
            fill: "#223344",
        },
        delone_io::SvgLayer::Points {
            points: &hidden,
            radius: 3.2,
            fill: "#cc2222",
        },
        delone_io::SvgLayer::Points {
            points: &hidden,
            radius: 1.8,
            fill: "white",
        },
    ];
    let file = std::fs::File::create(path)?;
    delone_io::write_svg(file, bbox, &layers, &delone_io::SvgStyle::default())?;
    let area: f64 = cells.area.iter().sum();
    println!(
        "wrote {path}: {n} weighted sites, {} hidden (red rings), {} triangles, cell areas sum to {area}",
        mesh.hidden.len(),
        mesh.triangles.len()
    );
    Ok(())
}
