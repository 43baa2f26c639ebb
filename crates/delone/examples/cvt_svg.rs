//! Draws a centroidal Voronoi tessellation: 300 seeded random points in the
//! unit square after 50 Lloyd iterations, with their Delaunay triangulation.
//!
//! `cargo run --release -p delone --example cvt_svg -- out.svg [points] [iterations]`
use delone::geom::SplitMix64;

/// Pastel fill by number of sides (a CVT is mostly hexagons).
fn fill_for(sides: usize) -> [u8; 3] {
    match sides {
        0..=3 => [0xff, 0xf2, 0xcc],
        4 => [0xf4, 0xcc, 0xcc],
        5 => [0xfc, 0xe5, 0xcd],
        6 => [0xd9, 0xea, 0xd3],
        7 => [0xcf, 0xe2, 0xf3],
        _ => [0xd9, 0xd2, 0xe9],
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let Some(path) = args.get(1) else {
        eprintln!("usage: cvt_svg OUT.svg [points=300] [iterations=50]");
        std::process::exit(2);
    };
    let n: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(300);
    let iterations: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(50);
    let mut rng = SplitMix64::new(2026);
    let mut unit = || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
    let pts: Vec<[f64; 2]> = (0..n).map(|_| [unit(), unit()]).collect();
    let bbox = [[0.0, 0.0], [1.0, 1.0]];
    let cvt = delone::tri::lloyd(&pts, bbox, iterations)?;
    let mesh = delone::triangulate(&cvt)?;
    let cells = delone::tri::Voronoi2::new(&cvt, &mesh)
        .unwrap()
        .cells_clipped(&cvt, bbox);
    // Colour cells by their number of sides (hexagons dominate in a CVT).
    let fills: Vec<[u8; 3]> = (0..cvt.len())
        .map(|p| fill_for(cells.polygon(p).len()))
        .collect();
    let layers = [
        delone_io::SvgLayer::Polygons {
            points: &cells.polygon_points,
            offsets: &cells.offsets,
            fills: &fills,
            stroke: "#334455",
            width: 1.2,
        },
        delone_io::SvgLayer::Triangles {
            points: &cvt,
            triangles: &mesh.triangles,
            stroke: "#99aabb",
            width: 0.4,
        },
        delone_io::SvgLayer::Points {
            points: &cvt,
            radius: 2.2,
            fill: "#223344",
        },
    ];
    let file = std::fs::File::create(path)?;
    delone_io::write_svg(file, bbox, &layers, &delone_io::SvgStyle::default())?;
    println!(
        "wrote {path}: {} sites after {iterations} Lloyd iterations",
        cvt.len()
    );
    Ok(())
}
