//! Draws a quality mesh: a gear-like plate with an off-centre hole and a thin
//! slit (our own geometry), meshed with `-pq30`-style refinement, triangles
//! shaded by their smallest angle.
//!
//! `cargo run --release -p delone --example quality_svg -- out.svg [min_angle=30]`
use delone::model::pslg::Pslg;
use delone::tri::{constrained_triangulation, refine, CdtOptions, RefineOptions};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let Some(path) = args.get(1) else {
        eprintln!("usage: quality_svg OUT.svg [min_angle=30]");
        std::process::exit(2);
    };
    let angle: f64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(30.0);
    // Outer boundary: 12 teeth on a disc, plus a narrow notch.
    let mut pts: Vec<[f64; 2]> = Vec::new();
    let teeth = 12;
    for k in 0..teeth * 4 {
        let a = std::f64::consts::TAU * k as f64 / (teeth * 4) as f64;
        let r = if (k / 2) % 2 == 0 { 1.0 } else { 0.85 };
        if k == 5 {
            // A thin slit reaching towards the centre.
            pts.push([0.45 * a.cos(), 0.45 * a.sin()]);
        }
        pts.push([r * a.cos(), r * a.sin()]);
    }
    let outer = pts.len() as u32;
    let mut segs: Vec<[u32; 2]> = (0..outer).map(|i| [i, (i + 1) % outer]).collect();
    // An off-centre circular hole.
    let m = 24u32;
    for k in 0..m {
        let a = std::f64::consts::TAU * f64::from(k) / f64::from(m);
        pts.push([-0.3 + 0.25 * a.cos(), -0.2 + 0.25 * a.sin()]);
    }
    segs.extend((0..m).map(|k| [outer + k, outer + (k + 1) % m]));
    let mut g = Pslg::new(pts, segs);
    g.holes.push([-0.3, -0.2]);
    let cdt = constrained_triangulation(&g, CdtOptions::default())?;
    let opts = RefineOptions {
        min_angle: Some(angle),
        max_area: Some(0.004),
        ..RefineOptions::default()
    };
    let refined = refine(&cdt, &opts)?;
    let mesh = &refined.mesh;
    // Shade by the smallest angle: darker = closer to the bound.
    let min_angle = |t: &[u32; 3]| {
        let p = t.map(|v| mesh.points[v as usize]);
        (0..3)
            .map(|i| {
                let (a, b, c) = (p[i], p[(i + 1) % 3], p[(i + 2) % 3]);
                let u = [b[0] - a[0], b[1] - a[1]];
                let v = [c[0] - a[0], c[1] - a[1]];
                (u[0] * v[1] - u[1] * v[0])
                    .abs()
                    .atan2(u[0] * v[0] + u[1] * v[1])
                    .to_degrees()
            })
            .fold(180.0, f64::min)
    };
    let mut offsets = vec![0u32];
    let mut polys: Vec<[f64; 2]> = Vec::new();
    let mut fills = Vec::new();
    for t in &mesh.triangles {
        polys.extend(t.map(|v| mesh.points[v as usize]));
        offsets.push(polys.len() as u32);
        let q = ((min_angle(t) - angle) / (60.0 - angle)).clamp(0.0, 1.0);
        let shade = |lo: f64, hi: f64| (lo + (hi - lo) * q) as u8;
        fills.push([
            shade(0x9e as f64, 0xe8 as f64),
            shade(0xc5 as f64, 0xf1 as f64),
            shade(0xe8 as f64, 0xfa as f64),
        ]);
    }
    let layers = [delone_io::SvgLayer::Polygons {
        points: &polys,
        offsets: &offsets,
        fills: &fills,
        stroke: "#2a3f54",
        width: 0.5,
    }];
    let bbox = [[-1.05, -1.05], [1.05, 1.05]];
    let file = std::fs::File::create(path)?;
    delone_io::write_svg(file, bbox, &layers, &delone_io::SvgStyle::default())?;
    let r = &refined.report;
    println!(
        "wrote {path}: {} triangles, min angle {:.2}° (bound {angle}°), {} left next to small input angles",
        mesh.triangles.len(),
        r.min_angle,
        r.unfixable.len()
    );
    Ok(())
}
