//! Probes the tetrahedral mesh optimiser on a refined surface model.
//!
//! `cargo run --release -p delone --example opt_probe -- FILE.off RATIO [EFFORT...]`
//!
//! Refines `FILE.off` to radius-edge `RATIO` once, then optimises a copy per
//! effort value (default 100), printing the evaluations, CPU time (of this
//! thread), the dihedral range and the low tail of the histogram.

use std::time::Instant;

use delone::tet::optimize::{optimize, OptimizeOptions};
use delone::tet::quality::dihedral_angles;
use delone::tet::refine::{refine, RefineOptions};

#[path = "common/cpu.rs"]
mod cpu;
use cpu::cpu;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (Some(path), Some(ratio)) = (args.first(), args.get(1)) else {
        eprintln!("usage: opt_probe FILE.off RATIO [EFFORT...]");
        std::process::exit(2);
    };
    let s = delone_io::read_off(&std::fs::read(path).expect("read")).expect("parse");
    let tris = s.triangles();
    let ropts = RefineOptions {
        max_radius_edge: Some(ratio.parse().expect("ratio")),
        ..RefineOptions::default()
    };
    let (c0, t0) = (cpu(), Instant::now());
    let r = refine(&s.points, &tris, &ropts).expect("refine");
    println!(
        "refine: {} tets, cpu {:.2} s, wall {:.2} s",
        r.rec.mesh.tets.len(),
        cpu() - c0,
        t0.elapsed().as_secs_f64()
    );
    let efforts: Vec<f64> = if args.len() > 2 {
        args[2..]
            .iter()
            .map(|x| x.parse().expect("effort"))
            .collect()
    } else {
        vec![100.0]
    };
    for e in efforts {
        let mut rec = r.rec.clone();
        let opts = OptimizeOptions {
            input_points: Some(s.points.len()),
            effort: Some(e),
            ..OptimizeOptions::level(3)
        };
        let (c0, t0) = (cpu(), Instant::now());
        let rep = optimize(&mut rec, &opts).expect("optimize");
        let (c, w) = (cpu() - c0, t0.elapsed().as_secs_f64());
        let h = &rep.after.dihedral_histogram;
        // Tetrahedra with an angle below 10° / 15° (or above 170° / 165°).
        let below = |d: f64| {
            rec.mesh
                .tets
                .iter()
                .filter(|tv| {
                    let a = dihedral_angles(&tv.map(|v| rec.points[v as usize]));
                    a.iter().any(|&x| x < d || x > 180.0 - d)
                })
                .count()
        };
        println!(
            "effort {e}: evals {} ({}) cpu {c:.2} s wall {w:.2} s  dihedral {:.2}..{:.2}  tets {}  <10:{} <15:{}  0-20:{} 20-30:{} 30-40:{} 150+:{}  stuck {:?}  ins {} sm {}",
            rep.evaluations,
            if rep.effort_exhausted { "spent" } else { "done" },
            rep.after.min_dihedral,
            rep.after.max_dihedral,
            rep.after.tets,
            below(10.0),
            below(15.0),
            h[..6].iter().sum::<usize>(),
            h[6],
            h[7],
            h[18..].iter().sum::<usize>(),
            rep.stuck_counts,
            rep.inserted,
            rep.smoothed,
        );
        for st in rep.stuck.iter().take(6) {
            println!(
                "  stuck {:.2}..{:.2} {} {}: {} surface faces, {} input, {} fixed",
                st.dihedral[0],
                st.dihedral[1],
                st.shape,
                st.reason,
                st.surface_faces,
                st.input_vertices,
                st.fixed_vertices
            );
        }
        if std::env::var_os("PROBE_CHECK").is_some() {
            delone::tet::recover::check_recovered(&s.points, &tris, &rec).expect("check");
        }
    }
}
