//! Times constrained triangulation + quality refinement of a `.poly` file.
//!
//! `cargo run --release -p delone --example refine_timing -- FILE.poly [ANGLE] [AREA] [MAX_STEINER] [-c]`
//!
//! Environment: `REFINE_NO_OFF` (circumcentres only), `REFINE_REGIONAL`, `REFINE_Y=1|2`
//! (`-Y`, `-YY`), `REFINE_PRE=ANGLE` (refine at ANGLE first), `REFINE_HIST`,
//! `REFINE_THREADS=N` (threads; default all), `REFINE_PAR_MIN=N` (parallel from N
//! predicted triangles), `REFINE_DUMP=FILE` (points, triangles, subsegments as text).

use std::time::Instant;

use delone::model::pslg::{Pslg, Region};
use delone::tri::constrain::{constrained_triangulation, CdtOptions};
use delone::tri::refine::{refine, RefineOptions, SegmentSplits};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(path) = args.first() else {
        eprintln!("usage: refine_timing FILE.poly [ANGLE] [AREA] [MAX_STEINER] [-c]");
        std::process::exit(2);
    };
    let num = |i: usize| {
        args.get(i)
            .and_then(|s| s.parse::<f64>().ok())
            .filter(|x| *x > 0.0)
    };
    let f = delone_io::read_poly(&std::fs::read(path).expect("read")).expect("parse");
    let g = Pslg {
        point_markers: f.node.markers.clone().unwrap_or_default(),
        points: f.node.points::<2>().expect("2D"),
        segments: f.segments_zero_based(f.node.first_index).expect("segments"),
        segment_markers: f.segment_markers.clone().unwrap_or_default(),
        holes: f.holes.clone(),
        regions: f
            .regions
            .iter()
            .map(|r| Region {
                point: [r[0], r[1]],
                attribute: r[2],
                max_area: r[3],
            })
            .collect(),
    };
    let convex_hull = args.iter().any(|a| a == "-c");
    let t0 = Instant::now();
    let cdt = constrained_triangulation(&g, CdtOptions { convex_hull }).expect("cdt");
    let t1 = Instant::now();
    let opts = RefineOptions {
        min_angle: num(1),
        max_area: num(2),
        max_steiner: num(3).map(|x| x as usize),
        regional_areas: std::env::var_os("REFINE_REGIONAL").is_some(),
        off_centers: std::env::var_os("REFINE_NO_OFF").is_none(),
        segment_splits: match std::env::var("REFINE_Y").as_deref() {
            Ok("1") => SegmentSplits::Interior,
            Ok("2") => SegmentSplits::None,
            _ => SegmentSplits::All,
        },
        conforming_delaunay: std::env::var_os("REFINE_D").is_some(),
        threads: std::env::var("REFINE_THREADS")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or_else(delone::tri::refine::default_threads),
        parallel_min_triangles: std::env::var("REFINE_PAR_MIN")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(delone::tri::refine::PARALLEL_MIN_TRIANGLES),
    };
    let r = if let Some(pre) = std::env::var("REFINE_PRE")
        .ok()
        .and_then(|s| s.parse::<f64>().ok())
    {
        let r0 = refine(
            &cdt,
            &RefineOptions {
                min_angle: Some(pre),
                ..opts
            },
        )
        .expect("refine");
        refine(&r0.mesh, &opts).expect("refine")
    } else {
        refine(&cdt, &opts).expect("refine")
    };
    let t2 = Instant::now();
    println!(
        "{path}: cdt {} triangles {:.3} s; refined {} triangles, {} points ({} segment splits, {} circumcentres, {} rejected), min angle {:.3}, max angle {:.3}, met {}, limit {}, {} unfixable, {:.3} s",
        cdt.triangles.len(),
        (t1 - t0).as_secs_f64(),
        r.mesh.triangles.len(),
        r.mesh.points.len(),
        r.report.segment_splits,
        r.report.circumcenters,
        r.report.rejected_circumcenters,
        r.report.min_angle,
        r.report.max_angle,
        r.report.met,
        r.report.limit_reached,
        r.report.unfixable.len(),
        (t2 - t1).as_secs_f64()
    );
    if std::env::var_os("REFINE_HIST").is_some() {
        let n = cdt.points.len();
        let mut count = vec![0usize; n];
        for q in &r.mesh.points[n..] {
            let (k, _) = cdt
                .points
                .iter()
                .enumerate()
                .fold((0, f64::MAX), |b, (i, p)| {
                    let d = (p[0] - q[0]).hypot(p[1] - q[1]);
                    if d < b.1 {
                        (i, d)
                    } else {
                        b
                    }
                });
            count[k] += 1;
        }
        let mut idx: Vec<usize> = (0..n).collect();
        idx.sort_by_key(|&i| std::cmp::Reverse(count[i]));
        for &i in idx.iter().take(6) {
            println!(
                "  near input vertex {i} {:?}: {} Steiner points",
                cdt.points[i], count[i]
            );
            let z = cdt.points[i];
            let mut rads = Vec::new();
            for k in 0..12 {
                let rad = 10f64.powi(-k);
                let c = r.mesh.points[n..]
                    .iter()
                    .filter(|q| (q[0] - z[0]).hypot(q[1] - z[1]) < rad)
                    .count();
                rads.push(c);
            }
            println!("    within 1, 0.1, ...: {rads:?}");
        }
    }
    if let Some(out) = std::env::var_os("REFINE_DUMP") {
        // Plain text: points, then triangles (for drawing while debugging).
        let mut s = String::new();
        for p in &r.mesh.points {
            s.push_str(&format!("p {} {}\n", p[0], p[1]));
        }
        for t in &r.mesh.triangles {
            s.push_str(&format!("t {} {} {}\n", t[0], t[1], t[2]));
        }
        for g in &r.mesh.segments {
            s.push_str(&format!("s {} {}\n", g.v[0], g.v[1]));
        }
        std::fs::write(out, s).expect("write dump");
    }
    for u in r.report.unfixable.iter().take(10) {
        println!("  unfixable {:?}", u);
    }
}
