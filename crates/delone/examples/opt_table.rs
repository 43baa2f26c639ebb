//! The optimiser's table: per surface model, the input's bound
//! on the smallest dihedral angle against the optimised mesh's range, and
//! what the worst tetrahedra left are.
//!
//! `cargo run --release -p delone --example opt_table -- [--ratio R] [--max-tris N] [--timeout S] [--worst K] [--effort E] LIST_OR_OFF...`
//!
//! Each argument is an `.off` file or a list of them (a text file whose
//! lines start with a path relative to the shared data directory, such as
//! `sets/closed_clean.txt`; models above `--max-tris` triangles, default
//! 8000, are left out). Each model is refined to radius-edge `--ratio`
//! (default 1.414) and optimised as `delone tet -pq` does (level 3), in a
//! child process stopped after `--timeout` seconds (default 60). One
//! markdown row per model: triangles, the input triangles' smallest
//! dihedral angle, the meshed surface's (the refined boundary's) bound,
//! the input triangles' smallest and largest angle, the dihedral range
//! before and after, the input triangle at the worst tetrahedron left and
//! its angles ([`Stuck::near_triangle`](delone::tet::optimize::Stuck)),
//! tetrahedra, CPU seconds of the refinement and of the optimisation, and
//! a mark `<15` when the output is below 15° (or above 165°) although the
//! input's dihedral angles are not (`<15 at-feature` when the worst
//! tetrahedron is at a needle or cap input triangle, below 15° or above
//! 165°). Then, for those models, the `--worst` (default 4) worst
//! tetrahedra: angles, shape, surface faces, input and fixed vertices,
//! input triangle. `--effort` overrides the optimiser's budget
//! ([`OptimizeOptions::effort`], `inf` for none). Not part of CI (it needs
//! the shared data and minutes).
//! With `TABLE_CHECK=1` each output is also checked by `check_recovered`
//! (`ok` at the end of the row).

use std::io::{BufRead, Write};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use delone::tet::optimize::{optimize, OptimizeOptions};
use delone::tet::refine::{refine, RefineOptions};

#[path = "common/cpu.rs"]
mod cpu;
use cpu::cpu;

/// The shared data directory of list file `list` (the parent of its
/// directory, as for `sets/closed_clean.txt`).
fn data_dir(list: &str) -> std::path::PathBuf {
    let p = std::path::Path::new(list);
    p.parent()
        .and_then(|d| d.parent())
        .map_or_else(|| ".".into(), |d| d.to_path_buf())
}

/// One model, in this process: prints the row, then `#`-lines with the
/// worst tetrahedra.
fn one(path: &str, ratio: f64, worst: usize, effort: Option<f64>) {
    let s = match std::fs::read(path)
        .map_err(|e| e.to_string())
        .and_then(|b| delone_io::read_off(&b).map_err(|e| e.to_string()))
    {
        Ok(s) => s,
        Err(e) => {
            println!("ERR {e}");
            return;
        }
    };
    let tris = s.triangles();
    let ropts = RefineOptions {
        max_radius_edge: Some(ratio),
        ..RefineOptions::default()
    };
    let c0 = cpu();
    let r = match refine(&s.points, &tris, &ropts) {
        Ok(r) => r,
        Err(e) => {
            println!("ERR refine: {e}");
            return;
        }
    };
    let c_ref = cpu() - c0;
    let mut rec = r.rec;
    let opts = OptimizeOptions {
        input_points: Some(s.points.len()),
        effort: effort.or(OptimizeOptions::level(3).effort),
        ..OptimizeOptions::level(3)
    };
    let c0 = cpu();
    let rep = match optimize(&mut rec, &opts) {
        Ok(r) => r,
        Err(e) => {
            println!("ERR optimize: {e}");
            return;
        }
    };
    let c_opt = cpu() - c0;
    let check = if std::env::var_os("TABLE_CHECK").is_some() {
        match delone::tet::recover::check_recovered(&s.points, &tris, &rec) {
            Ok(()) => " ok",
            Err(_) => " CHECK-FAILED",
        }
    } else {
        ""
    };
    let a = &rep.after;
    let worst_at = rep
        .stuck
        .first()
        .and_then(|w| {
            w.near_triangle
                .map(|t| format!("{t}: {:.2}..{:.2}", w.near_angles[0], w.near_angles[1]))
        })
        .unwrap_or_else(|| "-".into());
    println!(
        "ROW {} | {:.2} | {:.2} | {:.2}..{:.2} | {:.2}..{:.2} | {:.2}..{:.2} | {} | {} | {:.2} | {:.2} | {}{}",
        tris.len(),
        rep.triangles_min_dihedral,
        rep.input_min_dihedral,
        rep.triangles_min_angle,
        rep.triangles_max_angle,
        rep.before.min_dihedral,
        rep.before.max_dihedral,
        a.min_dihedral,
        a.max_dihedral,
        worst_at,
        a.tets,
        c_ref,
        c_opt,
        rep.stuck_counts
            .iter()
            .map(|x| x.to_string())
            .collect::<Vec<_>>()
            .join("/"),
        check
    );
    for st in rep.stuck.iter().take(worst) {
        println!(
            "# {:.2}..{:.2} {}, {}; {} surface faces, {} input, {} fixed vertices; at input triangle {} ({:.2}..{:.2})",
            st.dihedral[0],
            st.dihedral[1],
            st.shape,
            st.reason,
            st.surface_faces,
            st.input_vertices,
            st.fixed_vertices,
            st.near_triangle.map_or(-1, i64::from),
            st.near_angles[0],
            st.near_angles[1]
        );
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut ratio = 1.414;
    let mut max_tris = 8000usize;
    let mut timeout = 60.0;
    let mut worst = 4;
    let mut effort = None;
    let mut files = Vec::new();
    let mut it = args.iter();
    while let Some(a) = it.next() {
        let mut val = || {
            it.next()
                .expect("a value")
                .parse::<f64>()
                .expect("a number")
        };
        match a.as_str() {
            "--ratio" => ratio = val(),
            "--max-tris" => max_tris = val() as usize,
            "--timeout" => timeout = val(),
            "--worst" => worst = val() as usize,
            "--effort" => effort = Some(val()),
            "--one" => {
                let p = it.next().expect("a file");
                one(p, ratio, worst, effort);
                return;
            }
            _ if a.ends_with(".off") => files.push(a.clone()),
            _ => {
                let f = std::fs::File::open(a).expect("open list");
                for line in std::io::BufReader::new(f).lines().map_while(Result::ok) {
                    let mut w = line.split_whitespace();
                    let (Some(p), n) = (w.next(), w.next()) else {
                        continue;
                    };
                    if n.and_then(|n| n.parse::<usize>().ok()).unwrap_or(0) <= max_tris {
                        files.push(data_dir(a).join(p).to_string_lossy().into_owned());
                    }
                }
            }
        }
    }
    let me = std::env::current_exe().expect("own path");
    println!(
        "| model | tris | input tris min | meshed bound | tri angles | before | after | worst at tri: angles | tets | refine s | opt s | stuck surf/fixed/none |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    let mut notes = Vec::new();
    for f in &files {
        let name = std::path::Path::new(f)
            .file_stem()
            .map_or(f.clone(), |s| s.to_string_lossy().into_owned());
        let mut child = Command::new(&me)
            .args([
                "--ratio",
                &ratio.to_string(),
                "--worst",
                &worst.to_string(),
                "--effort",
                &effort
                    .or(OptimizeOptions::level(3).effort)
                    .unwrap_or(f64::INFINITY)
                    .to_string(),
                "--one",
                f,
            ])
            .stdout(Stdio::piped())
            .spawn()
            .expect("spawn");
        let t0 = Instant::now();
        let status = loop {
            if let Some(s) = child.try_wait().expect("wait") {
                break Some(s);
            }
            if t0.elapsed().as_secs_f64() > timeout {
                let _ = child.kill();
                let _ = child.wait();
                break None;
            }
            std::thread::sleep(Duration::from_millis(50));
        };
        let mut out = String::new();
        if let Some(mut so) = child.stdout.take() {
            let _ = std::io::Read::read_to_string(&mut so, &mut out);
        }
        let Some(_) = status else {
            println!("| {name} | timeout {timeout} s |||||||||||");
            continue;
        };
        let mut bad = false;
        for line in out.lines() {
            if let Some(row) = line.strip_prefix("ROW ") {
                let c: Vec<&str> = row.split(" | ").collect();
                let num = |s: &str| s.trim().parse::<f64>().unwrap_or(0.0);
                let input = num(c[1]).min(num(c[2]));
                let out_min = c[5].split("..").next().map_or(0.0, num);
                let out_max = c[5].split("..").nth(1).map_or(180.0, num);
                bad = input >= 15.0 && (out_min < 15.0 || out_max > 165.0);
                // At a needle or cap input triangle: a feature smaller
                // than the mesh there.
                let near = c[6].split(": ").nth(1).unwrap_or("");
                let lo = near.split("..").next().map_or(90.0, num);
                let hi = near.split("..").nth(1).map_or(90.0, num);
                let feature = lo < 15.0 || hi > 165.0;
                let mark = match (bad, feature) {
                    (true, true) => " <15 at-feature",
                    (true, false) => " <15",
                    _ => "",
                };
                println!("| {name}{mark} | {row} |");
            } else if let Some(e) = line.strip_prefix("ERR ") {
                println!("| {name} | error: {e} |||||||||||");
            } else if bad {
                notes.push(format!("{name}: {}", line.trim_start_matches("# ")));
            }
        }
        let _ = std::io::stdout().flush();
    }
    if !notes.is_empty() {
        println!("\nWorst tetrahedra of the models below 15° with an input at or above it:");
        for n in notes {
            println!("- {n}");
        }
    }
}
