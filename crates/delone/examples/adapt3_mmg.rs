//! 3D adaptation against MMG: the UGAWG *linear* and *polar-1* metrics on
//! the unit cube, 5 iterations from a structured coarse mesh (the metric
//! re-evaluated at the vertices each time), by `delone::adapt::adapt_tet`
//! and by `mmg3d_O3` (through Medit files), both measured by
//! `delone::adapt::metric_stats` in the analytic metric.
//!
//! `cargo run --release -p delone --example adapt3_mmg -- [MMG3D] [N] [ITERS] [CASE] [HGRAD]`
//! (MMG3D: the `mmg3d_O3` program, skipped when missing; N: cubes per side of
//! the coarse mesh, 10; ITERS: 5; CASE: `linear` or `polar-1`, both when
//! empty; HGRAD: the gradation of both tools, none when absent).

use std::time::Instant;

use delone::adapt::{adapt_tet, metric_stats, AdaptOptions, MetricField, MetricStats, TetMesh};
use delone::metric::Metric;
use delone_io::{MeditMesh, MeditSol, SolField, SolKind};

#[path = "../tests/common/cube.rs"]
mod cube;

/// A metric of sizes `h` along the orthonormal directions `e`.
fn frame(e: [[f64; 3]; 3], h: [f64; 3]) -> Metric<3> {
    let mut m = [[0.0; 3]; 3];
    for k in 0..3 {
        for i in 0..3 {
            for j in 0..3 {
                m[i][j] += e[k][i] * e[k][j] / (h[k] * h[k]);
            }
        }
    }
    Metric::from_medit(&[m[0][0], m[0][1], m[1][1], m[0][2], m[1][2], m[2][2]]).unwrap()
}

const H0: f64 = 0.001;

fn linear(p: &[f64; 3]) -> Metric<3> {
    let hz = H0 + 2.0 * (0.1 - H0) * (p[2] - 0.5).abs();
    frame(
        [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        [0.1, 0.1, hz],
    )
}

fn polar1(p: &[f64; 3]) -> Metric<3> {
    let r = (p[0] * p[0] + p[1] * p[1]).sqrt();
    let (c, s) = if r > 1e-12 {
        (p[0] / r, p[1] / r)
    } else {
        (1.0, 0.0)
    };
    let hr = H0 + 2.0 * (0.1 - H0) * (r - 0.5).abs();
    frame([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]], [hr, 0.1, 0.1])
}

fn to_medit(m: &TetMesh) -> MeditMesh {
    MeditMesh {
        dimension: 3,
        points: m.points.clone(),
        point_refs: if m.point_refs.is_empty() {
            vec![0; m.points.len()]
        } else {
            m.point_refs.clone()
        },
        triangles: m.faces.clone(),
        triangle_refs: m.face_refs.clone(),
        tetrahedra: m.elements.clone(),
        tetrahedron_refs: m.element_refs.clone(),
        corners: m.corners.clone(),
        ..Default::default()
    }
}

fn from_medit(m: &MeditMesh) -> TetMesh {
    TetMesh {
        points: m.points.clone(),
        point_refs: m.point_refs.clone(),
        elements: m.tetrahedra.clone(),
        element_refs: m.tetrahedron_refs.clone(),
        faces: m.triangles.clone(),
        face_refs: m.triangle_refs.clone(),
        corners: m.corners.clone(),
        ..Default::default()
    }
}

fn stats(m: &TetMesh, f: fn(&[f64; 3]) -> Metric<3>) -> MetricStats {
    let met: Vec<Metric<3>> = m.points.iter().map(f).collect();
    metric_stats(&m.points, &m.elements, &met)
}

fn delone_run(
    start: &TetMesh,
    f: fn(&[f64; 3]) -> Metric<3>,
    iters: usize,
    hgrad: Option<f64>,
) -> (TetMesh, f64) {
    let mut mesh = start.clone();
    let mut secs = 0.0;
    for _ in 0..iters {
        let met = mesh.points.iter().map(f).collect();
        let t = Instant::now();
        let o = AdaptOptions {
            hgrad,
            ..Default::default()
        };
        let out = adapt_tet(&mesh, MetricField::AtVertices(met), &o).unwrap();
        secs += t.elapsed().as_secs_f64();
        if std::env::var_os("ADAPT3_VERBOSE").is_some() {
            let r = &out.report;
            eprintln!(
                "{} tets {:.1}% q {:.3}/{:.3}: {} splits {} collapses {} swaps {} moves, {} passes; {:?}",
                out.mesh.elements.len(),
                100.0 * r.after.in_range_share(),
                r.after.quality_min,
                r.after.quality_mean,
                r.splits,
                r.collapses,
                r.swaps,
                r.moves,
                r.passes,
                r.phases
            );
        }
        mesh = out.mesh;
    }
    (mesh, secs)
}

fn mmg_run(
    mmg: &str,
    start: &TetMesh,
    f: fn(&[f64; 3]) -> Metric<3>,
    iters: usize,
    hgrad: Option<f64>,
) -> Option<(TetMesh, f64)> {
    let hgrad = hgrad.map_or("-1".to_string(), |g| g.to_string());
    let dir = std::env::temp_dir().join(format!("adapt3_mmg_{}", std::process::id()));
    std::fs::create_dir_all(&dir).ok()?;
    let (inm, ins, out) = (dir.join("c.mesh"), dir.join("c.sol"), dir.join("o.mesh"));
    let mut mesh = start.clone();
    let mut secs = 0.0;
    for _ in 0..iters {
        delone_io::write_medit_mesh(std::fs::File::create(&inm).ok()?, &to_medit(&mesh)).ok()?;
        let values = mesh.points.iter().flat_map(|p| f(p).medit()).collect();
        let sol = MeditSol {
            dimension: 3,
            vertices: mesh.points.len(),
            fields: vec![SolField {
                kind: SolKind::Tensor,
                values,
            }],
        };
        delone_io::write_medit_sol(std::fs::File::create(&ins).ok()?, &sol).ok()?;
        let t = Instant::now();
        let st = std::process::Command::new(mmg)
            .args([
                "-in",
                inm.to_str()?,
                "-sol",
                ins.to_str()?,
                "-out",
                out.to_str()?,
                "-hgrad",
                &hgrad,
                "-v",
                "-1",
            ])
            .status()
            .ok()?;
        secs += t.elapsed().as_secs_f64();
        if !st.success() {
            return None;
        }
        mesh = from_medit(&delone_io::read_medit_mesh(&std::fs::read(&out).ok()?).ok()?);
    }
    std::fs::remove_dir_all(&dir).ok();
    Some((mesh, secs))
}

fn row(who: &str, case: &str, m: &TetMesh, s: &MetricStats, secs: f64) {
    println!(
        "| {case:8} | {who:6} | {:8} | {:8} | {:5.1}% | {:.3} | {:.3} | {:7.2} |",
        m.points.len(),
        m.elements.len(),
        100.0 * s.in_range_share(),
        s.quality_min,
        s.quality_mean,
        secs
    );
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let mmg = args
        .get(1)
        .cloned()
        .unwrap_or_else(|| "/tmp/mmgvenv/bin/mmg3d_O3".into());
    let n: usize = args.get(2).and_then(|x| x.parse().ok()).unwrap_or(10);
    let iters: usize = args.get(3).and_then(|x| x.parse().ok()).unwrap_or(5);
    let only = args.get(4).cloned().unwrap_or_default();
    let hgrad: Option<f64> = args.get(5).and_then(|x| x.parse().ok());
    let start = cube::cube(n, false);
    println!("| case     | tool   | vertices | tets     | in range | q min | q mean | seconds |");
    println!("|----------|--------|----------|----------|----------|-------|--------|---------|");
    for (case, f) in [
        ("linear", linear as fn(&[f64; 3]) -> Metric<3>),
        ("polar-1", polar1),
    ] {
        if !only.is_empty() && only != case {
            continue;
        }
        let (m, secs) = delone_run(&start, f, iters, hgrad);
        row("delone", case, &m, &stats(&m, f), secs);
        match mmg_run(&mmg, &start, f, iters, hgrad) {
            Some((m, secs)) => row("MMG", case, &m, &stats(&m, f), secs),
            None => println!("| {case:8} | MMG    | ({mmg} did not run)"),
        }
    }
}
