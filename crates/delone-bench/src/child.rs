//! The child side: generate one case, run one program on it, measure, and
//! print one machine-readable result line on stdout.

use std::hint::black_box;
use std::time::Instant;

use crate::cases::{fnv1a, Case, Input, Kind, PlcInput, Points, PolyInput, SurfInput};
use crate::result::{Outcome, RunResult};

/// The programs the bench knows, with the dimension each one handles.
/// `tetgen…` are TetGen 1.6's executable, `tetgen15…` the modified TetGen
/// 1.5 bundled in `tritet` (see `refbin`).
pub const PROGRAMS: &[(&str, usize)] = &[
    ("delone", 2),
    ("triangle", 2),
    ("spade", 2),
    ("delaunator", 2),
    ("delone", 3),
    ("tetgen", 3),
    ("tetgen-p", 3),
    ("triangle-p", 2),
    ("tetgen-pq", 3),
    ("tetgen-pq-keep", 3),
    ("tetgen-pY", 3),
    ("tetgen15", 3),
    ("tetgen15-p", 3),
    ("tetgen15-pq", 3),
    ("tetgen15-pq-keep", 3),
    ("tetgen15-pY", 3),
];

/// The secondary programs, run only when named: TetGen 1.5 (`tetgen15…`)
/// and TetGen without its facet merging (`…-pq-keep`, up to 10x more
/// tetrahedra on the corpus: slow).
pub fn only_when_named(program: &str) -> bool {
    program.starts_with("tetgen15") || program.ends_with("-keep")
}

/// The reference executables of the file cases (`…-p`, `…-pY`, `…-pq`,
/// `…-pq-keep`), which do not handle generated point sets.
fn file_case_program(program: &str) -> bool {
    program.starts_with("tetgen-") || program.starts_with("tetgen15-") || program == "triangle-p"
}

/// Whether `program` handles `dim`-dimensional input.
pub fn supports(program: &str, dim: usize) -> bool {
    PROGRAMS.iter().any(|&(p, d)| p == program && d == dim)
}

/// Whether `program` handles `case`: by dimension for the point sets; only
/// delone and Triangle for `2d-poly-…`, delone and TetGen's executables for
/// `3d-surf…` and `3d-plc…` (and `tetgen15`, TetGen 1.5 through `tritet`'s
/// library, for `3d-surf-…`).
pub fn handles(program: &str, case: &Case) -> bool {
    match case.kind {
        Kind::Poly | Kind::Segs | Kind::Holes => {
            matches!(program, "delone" | "triangle" | "triangle-p")
        }
        Kind::Surf if case.quality.is_some() => matches!(
            program,
            "delone" | "tetgen-pq" | "tetgen-pq-keep" | "tetgen15-pq" | "tetgen15-pq-keep"
        ),
        Kind::Surf if case.name.starts_with("3d-surfY-") => {
            matches!(program, "delone" | "tetgen-pY" | "tetgen15-pY")
        }
        Kind::Surf => matches!(program, "delone" | "tetgen-p" | "tetgen15" | "tetgen15-p"),
        Kind::Plc if case.quality.is_some() => {
            matches!(program, "delone" | "tetgen-pq" | "tetgen15-pq")
        }
        Kind::Plc => matches!(program, "delone" | "tetgen-p" | "tetgen15-p"),
        _ if file_case_program(program) => false,
        _ => supports(program, case.dim),
    }
}

/// Sizes up to this many points are "small": warm-up run plus the median of
/// `repeat` timed runs. Larger ones are timed once, without warm-up.
pub const SMALL: usize = 200_000;

/// A warm-up run longer than this (seconds) is taken as the single timed
/// run instead of being repeated.
pub const SLOW: f64 = 2.0;

/// CPU time of the whole process in seconds, all threads together
/// (including threads that have already ended), or `None` where
/// unavailable. The 3D surface cases compare with TetGen's printed phase
/// seconds, which are CPU time (`clock()`) of a single-threaded program: on
/// a busy machine wall time would charge delone for the other processes,
/// and the calling thread's time alone would hide the work delone does on
/// its other threads.
fn process_cpu_seconds() -> Option<f64> {
    cpu_time::ProcessTime::try_now()
        .ok()
        .map(|t| t.as_duration().as_secs_f64())
}

/// Measures `f`: CPU seconds of the whole process (all threads) when
/// available, else wall; and the wall seconds.
fn cpu_timed<R>(f: impl FnOnce() -> R) -> (R, f64, f64) {
    let (c0, t) = (process_cpu_seconds(), Instant::now());
    let r = f();
    let wall = t.elapsed().as_secs_f64();
    match (c0, process_cpu_seconds()) {
        (Some(a), Some(b)) => (r, b - a, wall),
        _ => (r, wall, wall),
    }
}

/// Memory figures from `/proc/self/status`, in kB.
fn proc_status_kb(key: &str) -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    s.lines().find_map(|l| {
        let rest = l.strip_prefix(key)?.strip_prefix(':')?;
        rest.trim().trim_end_matches("kB").trim().parse().ok()
    })
}

fn vm_rss() -> Option<u64> {
    proc_status_kb("VmRSS")
}

fn vm_hwm() -> Option<u64> {
    proc_status_kb("VmHWM")
}

/// Resets the peak-RSS counter (Linux ≥ 4.0: write `5` to clear_refs).
fn reset_hwm() -> bool {
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
}

/// What one run of a program produced.
struct Run {
    seconds: f64,
    elements: usize,
    /// Hash of the full output (delone only; used by the determinism check).
    hash: Option<u64>,
    /// Outcome of delone's independent validator, when asked for.
    valid: Option<Result<(), String>>,
    /// Extra figures (see [`RunResult::info`]).
    info: String,
    /// Peak resident memory of an external program's process (kB), which
    /// replaces this process's own figure.
    external_peak_kb: Option<u64>,
}

fn hash_points<const D: usize>(points: &[[f64; D]]) -> u64 {
    fnv1a(
        points
            .iter()
            .flat_map(|p| p.iter().flat_map(|c| c.to_bits().to_le_bytes())),
    )
}

fn hash_u32s<'a>(groups: impl Iterator<Item = &'a [u32]>) -> u64 {
    fnv1a(groups.flat_map(|g| g.iter().flat_map(|v| v.to_le_bytes())))
}

/// Builds the program's input (untimed), then times only the
/// triangulation call. `on_ready` runs between the two (used to reset
/// and sample the memory counters). With `check`, delone's output is also
/// run through delone's own validator (untimed).
fn run_once(
    program: &str,
    input: &Input,
    on_ready: &mut dyn FnMut(),
    check: bool,
) -> Result<Run, String> {
    match input {
        Input::Points(p) => run_points(program, p, on_ready, check),
        Input::Poly(p) => run_poly(program, p, on_ready, check),
        Input::Surf(s) => run_surf(program, s, on_ready, check),
        Input::Plc(p) => run_plc(program, p, on_ready, check),
    }
}

/// CPU time of the calling thread so far, in nanoseconds (Linux
/// `/proc/thread-self/schedstat`), if available.
fn thread_cpu_ns() -> Option<u64> {
    schedstat_ns("/proc/thread-self/schedstat")
}

/// The first field of a `schedstat` file: nanoseconds spent on a CPU.
pub(crate) fn schedstat_ns(path: &str) -> Option<u64> {
    std::fs::read_to_string(path)
        .ok()?
        .split_whitespace()
        .next()?
        .parse()
        .ok()
}

/// The `2d-poly` note fields: CPU seconds of the timed work (when known),
/// and wall seconds of its two phases (constrained triangulation with
/// holes; refinement).
fn phase_info(cpu: Option<f64>, cdt: f64, refine: f64) -> String {
    let cpu = cpu.map_or(String::new(), |c| format!(",cpu={c:.3}"));
    format!("{cpu},cdt_s={cdt:.3},refine_s={refine:.3}")
}

/// `2d-poly-…`: delone's constrained triangulation (+ refinement) against
/// Triangle's `-p` (+ quality) through tritet.
fn run_poly(
    program: &str,
    input: &PolyInput,
    on_ready: &mut dyn FnMut(),
    check: bool,
) -> Result<Run, String> {
    use delone::tri::constrain::check_cdt;
    use delone::tri::TriOptions;
    let g = &input.pslg;
    match program {
        "delone" => {
            on_ready();
            // `delone tri -p` / `-pq…a…` (a global area bound alone, as the
            // cases give it, without the regions' bounds).
            let opts = TriOptions {
                pslg: true,
                min_angle: input.quality.and_then(|q| q.min_angle),
                max_area: input.quality.and_then(|q| q.max_area),
                ..TriOptions::default()
            };
            let cpu0 = thread_cpu_ns();
            let t = Instant::now();
            let r = delone::tri::mesh(black_box(g), &opts);
            let seconds = t.elapsed().as_secs_f64();
            let cpu = cpu0
                .zip(thread_cpu_ns())
                .map(|(a, b)| b.saturating_sub(a) as f64 * 1e-9);
            let r = r.map_err(|e| e.to_string())?;
            let refine_seconds = r.refine_time.as_secs_f64();
            let cdt_seconds = seconds - refine_seconds;
            let (m, report) = (r.mesh, r.refine);
            let hash = hash_u32s(
                m.triangles
                    .iter()
                    .map(|t| &t[..])
                    .chain(m.neighbors.iter().map(|t| &t[..])),
            ) ^ hash_points(&m.points).rotate_left(17);
            let valid = check.then(|| check_cdt(g, &m).map_err(|v| v.to_string()));
            let mut info = format!("steiner={}", m.points.len() - g.points.len());
            if let Some(r) = report {
                info.push_str(&format!(
                    ",min_angle={:.2},met={}",
                    r.min_angle,
                    if r.met { "yes" } else { "no" }
                ));
            }
            info.push_str(&phase_info(cpu, cdt_seconds, refine_seconds));
            Ok(Run {
                seconds,
                elements: m.triangles.len(),
                hash: Some(hash),
                valid,
                info,
                external_peak_kb: None,
            })
        }
        "triangle" => {
            let e = |m: &str| m.to_string();
            let (np, ns, nr, nh) = (
                g.points.len(),
                g.segments.len(),
                g.regions.len(),
                g.holes.len(),
            );
            let some = |n: usize| (n > 0).then_some(n);
            let mut tg = tritet::Trigen::new(np, some(ns), some(nr), some(nh)).map_err(e)?;
            for (i, p) in g.points.iter().enumerate() {
                let marker = g.point_markers.get(i).copied().unwrap_or(0);
                tg.set_point(i, marker, p[0], p[1]).map_err(e)?;
            }
            for (i, s) in g.segments.iter().enumerate() {
                let marker = g.segment_markers.get(i).copied().unwrap_or(0);
                tg.set_segment(i, marker, s[0] as usize, s[1] as usize)
                    .map_err(e)?;
            }
            for (i, h) in g.holes.iter().enumerate() {
                tg.set_hole(i, h[0], h[1]).map_err(e)?;
            }
            for (i, r) in g.regions.iter().enumerate() {
                let area = (r.max_area > 0.0).then_some(r.max_area);
                tg.set_region(i, r.attribute as i32, r.point[0], r.point[1], area)
                    .map_err(e)?;
            }
            let (area, angle) = input
                .quality
                .map_or((None, None), |q| (q.max_area, q.min_angle));
            on_ready();
            let t = Instant::now();
            let r = tg.generate_mesh(false, false, true, area, angle);
            let seconds = t.elapsed().as_secs_f64();
            r.map_err(e)?;
            Ok(Run {
                seconds,
                elements: tg.out_ncell(),
                hash: None,
                valid: None,
                info: format!("steiner={}", tg.out_npoint().saturating_sub(np)),
                external_peak_kb: None,
            })
        }
        "triangle-p" => {
            on_ready();
            let q = input.quality;
            let r = crate::refbin::run_triangle_p(
                g,
                q.and_then(|q| q.min_angle),
                q.and_then(|q| q.max_area),
            )?;
            let info = format!("steiner={}", r.steiner)
                + &phase_info(r.cpu_seconds, r.phase_ms[0] / 1e3, r.phase_ms[1] / 1e3);
            Ok(Run {
                seconds: r.seconds,
                elements: r.triangles,
                hash: None,
                valid: None,
                info,
                external_peak_kb: r.peak_kb,
            })
        }
        _ => Err(format!("program `{program}` does not handle .poly input")),
    }
}

/// `3d-surf-…`: delone's boundary recovery against TetGen's `-p`
/// executable (`tetgen-p`, `tetgen15-p`) and `tetgen15`, TetGen 1.5 through
/// tritet's library (which always adds `-q`, see the README).
fn run_surf(
    program: &str,
    input: &SurfInput,
    on_ready: &mut dyn FnMut(),
    check: bool,
) -> Result<Run, String> {
    use delone::tet::recover::{check_recovered, recover, RecoverOptions};
    let (p, tris) = (&input.points, &input.triangles);
    if let Some(q) = input.ratio {
        return run_surfq(program, p, tris, q, on_ready, check);
    }
    match program {
        "delone" => {
            let opts = RecoverOptions {
                preserve_surface: input.preserve,
                ..RecoverOptions::default()
            };
            on_ready();
            let (r, seconds, wall) = cpu_timed(|| recover(black_box(p), black_box(tris), &opts));
            let r = r.map_err(|e| e.to_string())?;
            let m = &r.mesh;
            let hash = hash_u32s(
                m.tets
                    .iter()
                    .map(|t| &t[..])
                    .chain(m.neighbors.iter().map(|t| &t[..]))
                    .chain(r.boundary.iter().map(|t| &t[..])),
            ) ^ hash_points(&r.points).rotate_left(17);
            let valid = check.then(|| check_recovered(p, tris, &r).map_err(|v| v.to_string()));
            Ok(Run {
                seconds,
                elements: m.tets.len(),
                hash: Some(hash),
                valid,
                info: format!("steiner={},wall={wall:.3}", r.report.steiner()),
                external_peak_kb: None,
            })
        }
        "tetgen15" => {
            let e = |m: &str| m.to_string();
            let mut g =
                tritet::Tetgen::new(p.len(), Some(vec![3; tris.len()]), None, None).map_err(e)?;
            for (i, q) in p.iter().enumerate() {
                g.set_point(i, 0, q[0], q[1], q[2]).map_err(e)?;
            }
            for (i, t) in tris.iter().enumerate() {
                for (m, &v) in t.iter().enumerate() {
                    g.set_facet_point(i, m, v as usize).map_err(e)?;
                }
            }
            on_ready();
            let t = Instant::now();
            let r = g.generate_mesh(false, false, None, None);
            let seconds = t.elapsed().as_secs_f64();
            r.map_err(e)?;
            if g.out_ncell() == 0 {
                // TetGen reports some inputs it rejects (e.g. intersecting
                // facets) only on its console and returns an empty mesh.
                return Err("TetGen produced no tetrahedra (input rejected?)".into());
            }
            Ok(Run {
                seconds,
                elements: g.out_ncell(),
                hash: None,
                valid: None,
                info: format!("steiner={}", g.out_npoint().saturating_sub(p.len())),
                external_peak_kb: None,
            })
        }
        "tetgen-p" | "tetgen-pY" | "tetgen15-p" | "tetgen15-pY" => {
            on_ready();
            let build = crate::refbin::Tetgen::of(program);
            let r = if program.ends_with("-pY") {
                crate::refbin::run_tetgen_py(build, p, tris)?
            } else {
                crate::refbin::run_tetgen_p(build, p, tris)?
            };
            Ok(Run {
                seconds: r.seconds,
                elements: r.tets,
                hash: None,
                valid: None,
                info: format!("steiner={}", r.steiner),
                external_peak_kb: r.peak_kb,
            })
        }
        _ => Err(format!("program `{program}` does not handle surface input")),
    }
}

/// `3d-surfq-…-qB`: delone's refinement and optimisation (`-pqB`, with
/// its default `-O`) against TetGen's
/// `-pqB` executable; the info column gives the Steiner points and the
/// minimum dihedral angle of the output.
/// delone's quality mesh of a closed surface (`plc`, its triangles as
/// facets) at radius-edge bound `q`: what `delone tet -pqQ` does
/// ([`delone::tet::mesh()`]: recovery, refinement, then the default `-O`
/// optimisation), the timed arm and the dihedral chart.
pub fn delone_quality(
    plc: &delone::model::plc::Plc,
    q: f64,
) -> Result<delone::tet::TetResult, String> {
    let opts = delone::tet::TetOptions {
        plc: true,
        max_radius_edge: Some(q),
        ..Default::default()
    };
    delone::tet::mesh(plc, &opts).map_err(|e| e.to_string())
}

/// [`delone_quality`]'s points and tetrahedra.
pub fn delone_quality_mesh(
    points: &[[f64; 3]],
    triangles: &[[u32; 3]],
    q: f64,
) -> Result<crate::refbin::NodeEle, String> {
    let plc = delone::model::plc::Plc::from_triangles(points.to_vec(), triangles);
    let r = delone_quality(&plc, q)?;
    Ok((r.mesh.points, r.mesh.mesh.tets))
}

fn run_surfq(
    program: &str,
    p: &[[f64; 3]],
    tris: &[[u32; 3]],
    q: f64,
    on_ready: &mut dyn FnMut(),
    check: bool,
) -> Result<Run, String> {
    use delone::tet::quality::TetStats;
    use delone::tet::recover::check_recovered;
    match program {
        "delone" => {
            let plc = delone::model::plc::Plc::from_triangles(p.to_vec(), tris);
            on_ready();
            // `-pqB` optimises by default (`-O`), as the CLI does: see
            // `delone_quality`.
            let (r, seconds, wall) = cpu_timed(|| delone_quality(black_box(&plc), q));
            let r = r?;
            let refined = r.refine.unwrap_or_default();
            let rec = &r.mesh;
            let m = &rec.mesh;
            let hash = hash_u32s(m.tets.iter().map(|t| &t[..])) ^ hash_points(&rec.points);
            let valid = check.then(|| check_recovered(p, tris, rec).map_err(|v| v.to_string()));
            let s = TetStats::of(&rec.points, &m.tets);
            Ok(Run {
                seconds,
                elements: m.tets.len(),
                hash: Some(hash),
                valid,
                info: format!(
                    "steiner={} mindih={:.2} bad={} wall={wall:.3}",
                    rec.report.steiner() + refined.steiner(),
                    s.min_dihedral,
                    refined.remaining_bad
                ),
                external_peak_kb: None,
            })
        }
        "tetgen-pq" | "tetgen-pq-keep" | "tetgen15-pq" | "tetgen15-pq-keep" => {
            on_ready();
            let build = crate::refbin::Tetgen::of(program);
            let r = crate::refbin::run_tetgen_pq(build, p, tris, q, program.ends_with("-keep"))?;
            Ok(Run {
                seconds: r.run.seconds,
                elements: r.run.tets,
                hash: None,
                valid: None,
                info: format!(
                    "steiner={} mindih={}",
                    r.run.steiner,
                    r.min_dihedral
                        .map_or_else(|| "?".to_string(), |d| format!("{d:.2}"))
                ),
                external_peak_kb: r.run.peak_kb,
            })
        }
        _ => Err(format!(
            "program `{program}` does not handle 3d-surfq cases"
        )),
    }
}

/// delone's mesh of a PLC as `delone tet -p` / `-pqB` makes it
/// ([`delone::tet::mesh()`]: facets triangulated, recovery with the facets'
/// markers, holes and regions; with a bound, refinement and the default
/// optimisation). Returns the mesh, the facets' triangles and the Steiner
/// points of recovery and refinement.
fn delone_plc(
    plc: &delone::model::plc::Plc,
    ratio: Option<f64>,
) -> Result<(delone::tet::recover::Recovered, Vec<[u32; 3]>, usize), String> {
    let opts = delone::tet::TetOptions {
        plc: true,
        max_radius_edge: ratio,
        ..Default::default()
    };
    let r = delone::tet::mesh(plc, &opts).map_err(|e| e.to_string())?;
    let steiner = r.mesh.report.steiner() + r.refine.map_or(0, |x| x.steiner());
    Ok((r.mesh, r.triangles, steiner))
}

/// `3d-plc-NAME` / `3d-plcq-NAME-qB`: delone against the `tetgen`
/// executable run on the same file (`-p` / `-pqB`); the note gives the
/// Steiner points and, when refining, the minimum dihedral angle.
fn run_plc(
    program: &str,
    input: &PlcInput,
    on_ready: &mut dyn FnMut(),
    check: bool,
) -> Result<Run, String> {
    use delone::tet::quality::TetStats;
    use delone::tet::recover::check_recovered;
    let dihedral = |d: Option<f64>| match (input.ratio, d) {
        (None, _) => String::new(),
        (Some(_), Some(d)) => format!(" mindih={d:.2}"),
        (Some(_), None) => " mindih=?".to_string(),
    };
    match program {
        "delone" => {
            on_ready();
            let (r, seconds, wall) = cpu_timed(|| delone_plc(black_box(&input.plc), input.ratio));
            let (rec, triangles, steiner) = r?;
            let m = &rec.mesh;
            let hash = hash_u32s(m.tets.iter().map(|t| &t[..])) ^ hash_points(&rec.points);
            let valid = check.then(|| {
                check_recovered(&input.plc.points, &triangles, &rec).map_err(|v| v.to_string())
            });
            let d = TetStats::of(&rec.points, &m.tets).min_dihedral;
            Ok(Run {
                seconds,
                elements: m.tets.len(),
                hash: Some(hash),
                valid,
                info: format!("steiner={steiner}{} wall={wall:.3}", dihedral(Some(d))),
                external_peak_kb: None,
            })
        }
        "tetgen-p" | "tetgen-pq" | "tetgen15-p" | "tetgen15-pq" => {
            on_ready();
            let build = crate::refbin::Tetgen::of(program);
            let r = crate::refbin::run_tetgen_plc(build, &input.bytes, input.ext, input.ratio)?;
            Ok(Run {
                seconds: r.run.seconds,
                elements: r.run.tets,
                hash: None,
                valid: None,
                info: format!("steiner={}{}", r.run.steiner, dihedral(r.min_dihedral)),
                external_peak_kb: r.run.peak_kb,
            })
        }
        _ => Err(format!("program `{program}` does not handle PLC input")),
    }
}

/// The generated point-set cases.
fn run_points(
    program: &str,
    pts: &Points,
    on_ready: &mut dyn FnMut(),
    check: bool,
) -> Result<Run, String> {
    match (program, pts) {
        ("delone", Points::D2(p)) => {
            on_ready();
            let t = Instant::now();
            let r = delone::triangulate(black_box(p));
            let seconds = t.elapsed().as_secs_f64();
            let m = r.map_err(|e| e.to_string())?;
            let hash = hash_u32s(
                m.triangles
                    .iter()
                    .map(|t| &t[..])
                    .chain(m.neighbors.iter().map(|t| &t[..]))
                    .chain(std::iter::once(&m.vertex_map[..])),
            );
            let valid = check.then(|| delone::tri::validate(p, &m).map_err(|v| v.to_string()));
            Ok(Run {
                seconds,
                elements: m.triangles.len(),
                hash: Some(hash),
                valid,
                info: String::new(),
                external_peak_kb: None,
            })
        }
        ("delone", Points::D3(p)) => {
            on_ready();
            let t = Instant::now();
            let r = delone::tetrahedralize(black_box(p));
            let seconds = t.elapsed().as_secs_f64();
            let m = r.map_err(|e| e.to_string())?;
            let hash = hash_u32s(
                m.tets
                    .iter()
                    .map(|t| &t[..])
                    .chain(m.neighbors.iter().map(|t| &t[..]))
                    .chain(std::iter::once(&m.vertex_map[..])),
            );
            let valid = check.then(|| delone::tet::validate(p, &m).map_err(|v| v.to_string()));
            Ok(Run {
                seconds,
                elements: m.tets.len(),
                hash: Some(hash),
                valid,
                info: String::new(),
                external_peak_kb: None,
            })
        }
        ("triangle", Points::D2(p)) => {
            let mut g = tritet::Trigen::new(p.len(), None, None, None).map_err(str::to_string)?;
            for (i, q) in p.iter().enumerate() {
                g.set_point(i, 0, q[0], q[1]).map_err(str::to_string)?;
            }
            on_ready();
            let t = Instant::now();
            let r = g.generate_delaunay(false);
            let seconds = t.elapsed().as_secs_f64();
            r.map_err(str::to_string)?;
            Ok(Run {
                seconds,
                elements: g.out_ncell(),
                hash: None,
                valid: None,
                info: String::new(),
                external_peak_kb: None,
            })
        }
        ("tetgen", Points::D3(p)) => {
            on_ready();
            let r = crate::refbin::run_tetgen_points(crate::refbin::Tetgen::V16, p)?;
            Ok(Run {
                seconds: r.seconds,
                elements: r.tets,
                hash: None,
                valid: None,
                info: String::new(),
                external_peak_kb: r.peak_kb,
            })
        }
        ("tetgen15", Points::D3(p)) => {
            let mut g = tritet::Tetgen::new(p.len(), None, None, None).map_err(str::to_string)?;
            for (i, q) in p.iter().enumerate() {
                g.set_point(i, 0, q[0], q[1], q[2])
                    .map_err(str::to_string)?;
            }
            on_ready();
            let t = Instant::now();
            let r = g.generate_delaunay(false);
            let seconds = t.elapsed().as_secs_f64();
            r.map_err(str::to_string)?;
            Ok(Run {
                seconds,
                elements: g.out_ncell(),
                hash: None,
                valid: None,
                info: String::new(),
                external_peak_kb: None,
            })
        }
        ("spade", Points::D2(p)) => {
            use spade::{DelaunayTriangulation, Point2, Triangulation};
            let v: Vec<Point2<f64>> = p.iter().map(|q| Point2::new(q[0], q[1])).collect();
            on_ready();
            let t = Instant::now();
            let r = DelaunayTriangulation::<Point2<f64>>::bulk_load(v);
            let seconds = t.elapsed().as_secs_f64();
            let d = r.map_err(|e| format!("{e:?}"))?;
            Ok(Run {
                seconds,
                elements: d.num_inner_faces(),
                hash: None,
                valid: None,
                info: String::new(),
                external_peak_kb: None,
            })
        }
        ("delaunator", Points::D2(p)) => {
            let v: Vec<delaunator::Point> = p
                .iter()
                .map(|q| delaunator::Point { x: q[0], y: q[1] })
                .collect();
            on_ready();
            let t = Instant::now();
            let d = delaunator::triangulate(black_box(&v));
            let seconds = t.elapsed().as_secs_f64();
            Ok(Run {
                seconds,
                elements: d.triangles.len() / 3,
                hash: None,
                valid: None,
                info: String::new(),
                external_peak_kb: None,
            })
        }
        _ => Err(format!(
            "program `{program}` does not handle {}D input",
            match pts {
                Points::D2(_) => 2,
                Points::D3(_) => 3,
            }
        )),
    }
}

/// Median of a non-empty list (mean of the middle two for even lengths).
pub fn median(xs: &[f64]) -> f64 {
    let mut v = xs.to_vec();
    v.sort_by(f64::total_cmp);
    let m = v.len() / 2;
    if v.is_empty() {
        f64::NAN
    } else if v.len() % 2 == 1 {
        v[m]
    } else {
        0.5 * (v[m - 1] + v[m])
    }
}

/// Runs `program` on `case` and returns the measured result.
pub fn run_child(case: &Case, program: &str, repeat: usize) -> RunResult {
    let loaded = case.load();
    let n = loaded.as_ref().map_or(0, Input::len);
    let base_kb = vm_rss();
    let mut res = RunResult {
        case: case.name.clone(),
        program: program.to_string(),
        n,
        seconds: f64::NAN,
        runs: 0,
        peak_kb: None,
        base_kb,
        call_kb: None,
        elements: 0,
        deterministic: None,
        valid: None,
        info: String::new(),
        outcome: Outcome::Ok,
    };
    let pts = match loaded {
        Ok(p) => p,
        Err(e) => {
            res.outcome = Outcome::Error(e);
            return res;
        }
    };
    if !handles(program, case) {
        res.outcome = Outcome::Error(format!(
            "program `{program}` does not handle {}D input",
            case.dim
        ));
        return res;
    }

    let small = n <= SMALL;
    let timed = if small { repeat.max(1) } else { 1 };
    let warmup = usize::from(small);

    // Memory figures come from the first run, in the still-fresh process:
    // later runs would inherit heap pages the allocator kept from earlier
    // ones, which distorts both the peak and the per-call rise.
    let mut peak_kb = base_kb;
    let mut call_kb: Option<u64> = None;
    let mut times = Vec::with_capacity(timed);
    // The note of each timed run: the median run's is reported.
    let mut infos: Vec<(f64, String)> = Vec::with_capacity(timed);
    let mut hashes = Vec::new();

    for i in 0..warmup + timed {
        let first = i == 0;
        let mut pre_kb = None;
        let mut reset = false;
        let mut on_ready = || {
            if first {
                // The peak so far (input generation and conversion), then a
                // reset so that the call's own peak can be seen.
                peak_kb = peak_kb.max(vm_hwm());
                reset = reset_hwm();
                pre_kb = vm_rss();
            }
        };
        let run = run_once(program, &pts, &mut on_ready, false);
        if first {
            let hwm = vm_hwm();
            peak_kb = peak_kb.max(hwm);
            if let (true, Some(h), Some(p)) = (reset, hwm, pre_kb) {
                call_kb = Some(h.saturating_sub(p));
            }
            if let Some(ext) = run.as_ref().ok().and_then(|r| r.external_peak_kb) {
                peak_kb = Some(ext);
                call_kb = Some(ext);
            }
            res.peak_kb = peak_kb;
            res.call_kb = call_kb;
        }
        match run {
            Ok(r) => {
                // A warm-up run this slow (a small input with a huge
                // output, e.g. a tiny area bound) counts as the one timed
                // run: repeating it would only multiply the wait.
                let slow_warmup = i < warmup && r.seconds > SLOW;
                if i >= warmup || slow_warmup {
                    times.push(r.seconds);
                    infos.push((r.seconds, r.info.clone()));
                }
                hashes.extend(r.hash);
                res.elements = r.elements;
                res.info = r.info;
                if slow_warmup {
                    break;
                }
            }
            Err(e) => {
                res.outcome = Outcome::Error(e);
                return res;
            }
        }
    }
    res.seconds = median(&times);
    res.runs = times.len();
    if let Some((_, info)) = infos.iter().min_by(|a, b| {
        (a.0 - res.seconds)
            .abs()
            .total_cmp(&(b.0 - res.seconds).abs())
    }) {
        res.info.clone_from(info);
    }

    // One more, untimed run of delone (the memory figures are already
    // taken): its output goes through delone's validator, and the full
    // output of every run must hash the same (determinism).
    if program == "delone" {
        let mut nothing = || {};
        match run_once(program, &pts, &mut nothing, true) {
            Ok(r) => {
                hashes.extend(r.hash);
                match r.valid {
                    Some(Ok(())) => res.valid = Some(true),
                    Some(Err(v)) => {
                        res.valid = Some(false);
                        res.outcome = Outcome::Invalid(v);
                    }
                    None => {}
                }
            }
            Err(e) => res.outcome = Outcome::Error(format!("check run: {e}")),
        }
        if hashes.len() >= 2 {
            res.deterministic = Some(hashes.iter().all(|&h| h == hashes[0]));
        }
    }
    res
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Mutex;

    /// Triangle and TetGen are not thread-safe, and the memory counters are
    /// per process: run the tests that call programs one at a time.
    static SERIAL: Mutex<()> = Mutex::new(());

    fn serial() -> std::sync::MutexGuard<'static, ()> {
        SERIAL.lock().unwrap_or_else(|e| e.into_inner())
    }

    #[test]
    fn median_odd_even() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), 2.5);
        assert_eq!(median(&[5.0]), 5.0);
        assert!(median(&[]).is_nan());
    }

    #[test]
    fn references_agree_on_small_random_input() {
        let _g = serial();
        // For points in general position all 2D references must produce
        // the same number of triangles, 2n - 2 - h.
        let c = Case::parse("2d-uniform-2000").unwrap();
        let counts: Vec<usize> = ["triangle", "spade", "delaunator"]
            .iter()
            .map(|p| {
                let r = run_child(&c, p, 1);
                assert_eq!(r.outcome, Outcome::Ok, "{p}");
                assert!(r.seconds >= 0.0);
                r.elements
            })
            .collect();
        assert!(counts[0] > 3900 && counts[0] < 3998, "{counts:?}");
        assert!(counts.iter().all(|&c| c == counts[0]), "{counts:?}");
    }

    #[test]
    fn tetgen_runs() {
        let _g = serial();
        let c = Case::parse("3d-uniform-1000").unwrap();
        let r = run_child(&c, "tetgen15", 1);
        assert_eq!(r.outcome, Outcome::Ok);
        // Uniform random points: about 6.5 tets per point.
        assert!(r.elements > 5000 && r.elements < 8000, "{}", r.elements);
    }

    #[test]
    fn wrong_dimension_is_an_error_not_a_crash() {
        let _g = serial();
        let c = Case::parse("3d-uniform-100").unwrap();
        let r = run_child(&c, "spade", 1);
        assert!(matches!(r.outcome, Outcome::Error(_)));
    }

    #[test]
    fn file_families_run_only_their_programs() {
        let poly = Case::parse("2d-poly-la-q30").unwrap();
        let surf = Case::parse("3d-surf-c3d_spot").unwrap();
        assert!(handles("delone", &poly) && handles("triangle", &poly));
        assert!(!handles("spade", &poly) && !handles("delaunator", &poly));
        assert!(!handles("tetgen", &poly));
        assert!(handles("delone", &surf) && handles("tetgen-p", &surf));
        assert!(handles("tetgen15", &surf) && handles("tetgen15-p", &surf));
        assert!(!handles("triangle", &surf) && !handles("tetgen", &surf));
        let pts = Case::parse("2d-uniform-100").unwrap();
        assert!(handles("spade", &pts) && !handles("tetgen", &pts));
        let pts3 = Case::parse("3d-uniform-100").unwrap();
        assert!(handles("tetgen", &pts3) && handles("tetgen15", &pts3));
        assert!(!handles("tetgen-p", &pts3) && !handles("tetgen15-pq", &pts3));
        let q = Case::parse("3d-surfq-c3d_spot-q1.414").unwrap();
        assert!(handles("tetgen-pq", &q) && handles("tetgen15-pq-keep", &q));
        assert!(!handles("tetgen-p", &q) && !handles("tetgen15", &q));
    }

    fn info_value(info: &str, key: &str) -> Option<f64> {
        info.split(',')
            .find_map(|kv| kv.strip_prefix(key)?.strip_prefix('='))
            .and_then(|v| v.parse().ok())
    }

    #[test]
    fn poly_case_runs_delone_and_triangle() {
        if crate::cases::data_dir().is_none() {
            println!("note: shared data directory not found; skipping");
            return;
        }
        let _g = serial();
        let c = Case::parse("2d-poly-double_hex-q30").unwrap();
        let d = run_child(&c, "delone", 1);
        assert_eq!(d.outcome, Outcome::Ok, "{d:?}");
        assert_eq!((d.valid, d.deterministic), (Some(true), Some(true)));
        assert!(
            info_value(&d.info, "min_angle").unwrap() >= 30.0,
            "{}",
            d.info
        );
        assert!(info_value(&d.info, "steiner").unwrap() > 0.0, "{}", d.info);
        let t = run_child(&c, "triangle", 1);
        assert_eq!(t.outcome, Outcome::Ok, "{t:?}");
        // Both refine the same domain to the same angle bound: the triangle
        // counts should be close (they differ by where Steiner points go).
        let (a, b) = (d.elements as f64, t.elements as f64);
        assert!(a > 0.0 && (a / b - 1.0).abs() < 0.3, "{a} vs {b}");
        // The CDT alone adds no Steiner point to this input.
        let p = run_child(&Case::parse("2d-poly-double_hex-p").unwrap(), "delone", 1);
        assert_eq!(p.outcome, Outcome::Ok);
        assert!(p.elements > 0 && p.elements < d.elements);
        assert_eq!(info_value(&p.info, "steiner"), Some(0.0));
    }

    #[test]
    fn surf_case_runs_delone_and_tetgen() {
        if crate::cases::data_dir().is_none() {
            println!("note: shared data directory not found; skipping");
            return;
        }
        let _g = serial();
        let c = Case::parse("3d-surf-cgal_blob_closed").unwrap();
        let d = run_child(&c, "delone", 1);
        assert_eq!(d.outcome, Outcome::Ok, "{d:?}");
        assert_eq!((d.valid, d.deterministic), (Some(true), Some(true)));
        assert!(d.elements >= d.n / 2, "{d:?}");
        let t = run_child(&c, "tetgen15", 1);
        assert_eq!(t.outcome, Outcome::Ok, "{t:?}");
        assert!(t.elements > 0);
        // A self-intersecting surface is an error for both, not a crash.
        let bad = Case::parse("3d-surf-c3d_suzanne").unwrap();
        assert!(matches!(
            run_child(&bad, "delone", 1).outcome,
            Outcome::Error(_)
        ));
        assert!(matches!(
            run_child(&bad, "tetgen15", 1).outcome,
            Outcome::Error(_)
        ));
    }

    #[test]
    fn memory_counters_readable_on_linux() {
        if cfg!(target_os = "linux") {
            let rss = vm_rss().unwrap();
            let hwm = vm_hwm().unwrap();
            assert!(rss > 0 && hwm >= rss);
        }
    }
}
