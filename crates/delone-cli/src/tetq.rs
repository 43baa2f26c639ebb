//! `delone tet -pq[B] -a[V] -S[n]`: Delaunay refinement after recovery, and
//! the quality statistics (`-V`, `--stats-json FILE`).

use delone::tet::optimize::OptimizeReport;
use delone::tet::quality::{TetStats, DIHEDRAL_BINS};
use delone::tet::recover::Recovered;
use delone::tet::refine::RefineReport;

use crate::args::Opts;

/// What the run says about the bounds after refinement and optimisation:
/// `(exit code, message for stderr)`. The Steiner budget stopping the
/// refinement is a failure (exit code 1) naming the budget, its memory
/// estimate, the tetrahedra left above the bound and `-S`. Otherwise the
/// bounds of the final mesh are counted ([`Missed`]); any missed gives
/// exit code 3 and a message by bound and cause (`--warn-unmet`: a warning,
/// exit code 0; `-Q`: no message).
pub fn bound_status(
    o: &Opts,
    rec: &Recovered,
    r: &RefineReport,
    optimized: Option<&OptimizeReport>,
) -> (i32, Option<String>) {
    let m = Missed::of(o, rec, r, optimized);
    if r.budget_exhausted {
        let mb = delone::tet::refine::memory_estimate(r.steiner_budget) as f64 / 1e6;
        return (
            1,
            Some(format!(
                "bounds NOT met: refinement stopped at the Steiner budget of {} points (about {mb:.0} MB) after {} points; {} tetrahedra above the -q bound, {} above the -a volume, {} above the size bound (-m); the mesh reached is written (optimised). Raise the budget with -S<n> (e.g. -S{}), or ask for a bound refinement can reach (radius-edge ratios of about 1.1 and more terminate)",
                r.steiner_budget,
                r.steiner(),
                r.remaining_bad,
                m.volume,
                r.remaining_too_big,
                r.steiner_budget.saturating_mul(4)
            )),
        );
    }
    let mut parts = Vec::new();
    if m.ratio > 0 {
        let why = crate::tetq_left::causes(r);
        parts.push(format!(
            "{} above the -q radius-edge ratio {} ({})",
            m.ratio,
            o.tet.max_radius_edge.unwrap_or(f64::INFINITY),
            if m.ratio_final {
                why
            } else {
                format!("left by the refinement: {why}")
            }
        ));
    }
    if m.volume > 0 {
        parts.push(format!(
            "{} above their volume bound (-a; floating point)",
            m.volume
        ));
    }
    if r.remaining_too_big > 0 {
        parts.push(format!(
            "{} above the size bound (-m; sharp input features)",
            r.remaining_too_big
        ));
    }
    if let Some((n, why)) = &m.dihedral {
        if *n > 0 {
            parts.push(format!(
                "{n} with a dihedral angle below {} deg or above {} deg ({why})",
                o.tet.min_dihedral.unwrap_or(0.0),
                180.0 - o.tet.min_dihedral.unwrap_or(0.0)
            ));
        }
    }
    if parts.is_empty() {
        return (0, None);
    }
    let mut what = format!(
        "tetrahedra of the mesh miss the bounds: {}; the mesh is written",
        parts.join("; ")
    );
    if m.raised > 0 {
        what.push_str(&format!("; {}", raised_line(m.raised)));
    }
    crate::pslg::unmet(o, what)
}

/// The tetrahedra the optimisation raised above the `-q` ratio (not a
/// missed bound: the default optimisation trades it for dihedral angles).
pub fn raised_line(n: usize) -> String {
    format!("{n} raised above the -q ratio by the optimisation, which trades it for dihedral angles; --keep-ratio keeps it")
}

/// The bounds of the final mesh, counted: how many tetrahedra miss each.
pub struct Missed {
    /// Tetrahedra counted as missing the `-q` ratio: all those above it
    /// with `--keep-ratio` or `-O0` (`ratio_final`), else at most those the
    /// refinement left above it.
    pub ratio: usize,
    /// Whether `ratio` counts the final mesh's ratio (`--keep-ratio`, `-O0`).
    pub ratio_final: bool,
    /// Tetrahedra above the ratio that the optimisation raised there.
    pub raised: usize,
    /// Tetrahedra above their volume bound (`-a`, global or regional).
    pub volume: usize,
    /// With an explicit `/D`: the tetrahedra with a dihedral angle below it
    /// or above 180 minus it, and why.
    pub dihedral: Option<(usize, String)>,
}

impl Missed {
    /// Counts the bounds on the final mesh `rec`.
    pub fn of(
        o: &Opts,
        rec: &Recovered,
        r: &RefineReport,
        optimized: Option<&OptimizeReport>,
    ) -> Missed {
        use delone::tet::quality::dihedral_angles;
        let (above_ratio, volume, _) = final_counts(o, rec);
        let ratio_final = o.tet.keep_ratio || optimized.is_none();
        let ratio = if ratio_final {
            above_ratio
        } else {
            above_ratio.min(r.remaining_bad)
        };
        let dihedral = o.tet.min_dihedral.map(|d| match optimized {
            Some(x) if (x.bad.angle - d).abs() < 1e-12 => {
                let b = &x.bad;
                let mut why = Vec::new();
                if b.sharp_edge > 0 {
                    why.push(format!(
                        "{} at sharp input edges whose own angle is below it",
                        b.sharp_edge
                    ));
                }
                if b.at_feature > 0 {
                    why.push(format!("{} at needle or cap input triangles", b.at_feature));
                }
                if b.free > 0 {
                    why.push(format!("{} not forced by the input", b.free));
                }
                (b.count, why.join(", "))
            }
            _ => {
                let n = rec
                    .mesh
                    .tets
                    .iter()
                    .filter(|t| {
                        let a = dihedral_angles(&t.map(|q| rec.points[q as usize]));
                        a.iter().any(|&x| x < d || x > 180.0 - d)
                    })
                    .count();
                (n, "no optimisation ran (-O0)".to_string())
            }
        });
        Missed {
            ratio,
            ratio_final,
            raised: above_ratio - ratio,
            volume,
            dihedral,
        }
    }
}

/// Summary lines of the optimisation (dihedral angles before and after
/// with `-V`).
pub fn optimize_lines(o: &Opts, r: &OptimizeReport) -> Vec<String> {
    let mut lines = vec![format!(
        "optimization: {} passes; flips 2-3 {}, 3-2 {}, 4-4 {}, edge removals {}, multi-face removals {}, boundary flips {}; {} vertex moves, {} vertices inserted ({} tried and undone, {} collapsed again), {} refinement points removed, {} flat boundary tetrahedra removed; {} tetrahedra below the target ({} with two faces on the surface, {} with four surface vertices, {} not improved)",
        r.passes,
        r.flips23,
        r.flips32,
        r.flips44,
        r.edge_removals,
        r.multi_face,
        r.boundary_flips,
        r.smoothed,
        r.inserted,
        r.insert_undone,
        r.collapsed,
        r.removed,
        r.flat_removed,
        r.stuck_counts.iter().sum::<usize>(),
        r.stuck_counts[0],
        r.stuck_counts[1],
        r.stuck_counts[2],
    )];
    if o.out().verbose > 0 {
        lines.push(format!(
            "optimization: dihedral {:.2}..{:.2} deg -> {:.2}..{:.2} deg, shape min {:.4} -> {:.4}, {} -> {} tetrahedra",
            r.before.min_dihedral,
            r.before.max_dihedral,
            r.after.min_dihedral,
            r.after.max_dihedral,
            r.before.min_shape,
            r.after.min_shape,
            r.before.tets,
            r.after.tets
        ));
        lines.push(format!(
            "optimization: smallest dihedral angle of the input surface {:.2} deg (the bound at its edges); {} quality evaluations{}",
            r.input_min_dihedral,
            r.evaluations,
            if r.effort_exhausted { ", effort budget spent" } else { "" }
        ));
        lines.push(crate::tetq_bound::bound_line(o, r));
        for st in &r.stages {
            lines.push(crate::tetq_bound::stage_line(st));
        }
        let mut lo = 0.0;
        let mut h = String::from("dihedral histogram before optimization:");
        for (b, n) in DIHEDRAL_BINS.iter().zip(&r.before.dihedral_histogram) {
            h.push_str(&format!(" {lo}-{b}:{n}"));
            lo = *b;
        }
        lines.push(h);
        for s in r
            .stuck
            .iter()
            .take(if o.out().verbose > 1 { 32 } else { 3 })
        {
            lines.push(crate::tetq_bound::stuck_line(s));
        }
    }
    lines
}

/// Report lines for `-V` (and the refinement summary; none of the counts
/// behind them with `-Q`, which prints no lines), and the JSON file.
pub fn report(
    o: &Opts,
    rec: &Recovered,
    refined: Option<&RefineReport>,
    optimized: Option<&OptimizeReport>,
) -> Result<Vec<String>, String> {
    let mut lines = Vec::new();
    if let Some(r) = refined {
        lines.push(format!(
            "refinement: {} points (on segments {}, on facets {}, interior {}, of which {} off the circumcentre); {} circumcentres rejected, {} bad tetrahedra skipped ({} flat, {} behind a subface, {} near small pieces, {} refused, {} kept surface), {} above the bound ({} flat on a plane of the input, {} at the boundary), {} above the volume bound{}",
            r.steiner(),
            r.on_segments,
            r.on_facets,
            r.interior,
            r.inside,
            r.rejected,
            r.skipped,
            r.skipped_flat,
            r.skipped_behind,
            r.skipped_small,
            r.skipped_refused,
            r.skipped_surface,
            r.remaining_bad,
            r.flat,
            r.remaining_at_boundary,
            r.remaining_over_volume,
            if r.budget_exhausted { "; Steiner budget exhausted" } else { "" }
        ));
        if o.out().verbose > 0 {
            let c = &r.causes;
            lines.push(format!(
                "refinement points by cause: on segments {} for encroaching vertices, {} for encroached subfaces, {} for bad tetrahedra; on facets {} for encroaching vertices, {} for bad tetrahedra",
                c.segments_for_vertices,
                c.segments_for_subfaces,
                c.segments_for_cells,
                c.facets_for_vertices,
                c.facets_for_cells
            ));
            lines.push(format!(
                "Steiner budget {} points (about {:.0} MB; -S raises it){}",
                r.steiner_budget,
                delone::tet::refine::memory_estimate(r.steiner_budget) as f64 / 1e6,
                if r.budget_exhausted { ", reached" } else { "" }
            ));
        }
        if r.remaining_bad > 0 && o.out().verbose > 0 {
            lines.push(crate::tetq_left::left_line(r));
        }
        // With -Q the lines are not printed: the counts on the final mesh
        // are left to `bound_status`, which needs them for the exit code.
        if !o.out().quiet {
            lines.push(bounds_line(o, rec));
        }
        if o.out().verbose > 0 && !o.out().quiet && o.tet.max_radius_edge.is_some() {
            let m = Missed::of(o, rec, r, optimized);
            if m.raised > 0 {
                lines.push(raised_line(m.raised));
            }
        }
    }
    let printed = o.out().verbose > 0 && !o.out().quiet;
    if !printed && o.stats_json.is_none() {
        return Ok(lines);
    }
    let s = TetStats::of(&rec.points, &rec.mesh.tets);
    if printed {
        lines.push(format!(
            "quality: dihedral {:.2}..{:.2} deg, radius-edge {:.3}..{:.3} (mean {:.3}), shape min {:.4} mean {:.4}, volume {:.4e}..{:.4e} (total {:.6e})",
            s.min_dihedral,
            s.max_dihedral,
            s.min_radius_edge,
            s.max_radius_edge,
            s.mean_radius_edge,
            s.min_shape,
            s.mean_shape,
            s.min_volume,
            s.max_volume,
            s.total_volume
        ));
        let mut lo = 0.0;
        let mut h = String::from("dihedral histogram:");
        for (b, n) in DIHEDRAL_BINS.iter().zip(&s.dihedral_histogram) {
            h.push_str(&format!(" {lo}-{b}:{n}"));
            lo = *b;
        }
        lines.push(h);
    }
    if let Some(p) = &o.stats_json {
        let doc = crate::tetjson::document(&s, rec, refined, optimized);
        crate::guard::write_bytes(p, doc.as_bytes()).map_err(|f| f.message)?;
    }
    Ok(lines)
}

/// On the final mesh: the tetrahedra above the radius-edge bound (`-q`),
/// above their volume bound (`-a`, global or regional), and the largest
/// volume.
fn final_counts(o: &Opts, rec: &Recovered) -> (usize, usize, f64) {
    use delone::tet::quality::{radius_edge_ratio, volume};
    let ratio = o.tet.max_radius_edge.unwrap_or(f64::INFINITY);
    let (mut above_ratio, mut above_volume, mut largest) = (0usize, 0usize, 0.0f64);
    for (tv, &g) in rec.mesh.tets.iter().zip(&rec.tet_region) {
        let p = tv.map(|q| rec.points[q as usize]);
        let v = volume(&p).abs();
        largest = largest.max(v);
        if radius_edge_ratio(&p) > ratio {
            above_ratio += 1;
        }
        let regional = rec
            .regions
            .get(g as usize)
            .and_then(|r| r.max_volume)
            .filter(|&b| b > 0.0 && o.area());
        let bound = match (o.max_area(), regional) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        };
        if bound.is_some_and(|b| v > b) {
            above_volume += 1;
        }
    }
    (above_ratio, above_volume, largest)
}

/// `bounds (final mesh): …` — the bounds asked for, counted on the final
/// mesh (after the optimisation): tetrahedra above the radius-edge bound
/// (`-q`) and above their volume bound (`-a`, global or regional), and the
/// largest volume.
pub fn bounds_line(o: &Opts, rec: &Recovered) -> String {
    let ratio = o.tet.max_radius_edge.unwrap_or(f64::INFINITY);
    let (above_ratio, above_volume, largest) = final_counts(o, rec);
    let mut l = String::from("bounds (final mesh):");
    if ratio.is_finite() {
        l.push_str(&format!(
            " {above_ratio} tetrahedra above the radius-edge bound {ratio};"
        ));
    }
    if o.area() {
        l.push_str(&format!(
            " {above_volume} tetrahedra above the volume bound;"
        ));
    }
    l.push_str(&format!(" largest volume {largest:.6e}"));
    l
}

/// `-C`: runs `check` and adds its line to `lines` (exit code 1 when it
/// fails, else 0); then creates `--output-dir` if given.
pub fn check_and_prepare<E: std::fmt::Display>(
    o: &Opts,
    check: impl FnOnce() -> Result<(), E>,
    what: &str,
    lines: &mut Vec<String>,
) -> Result<i32, crate::fail::Failure> {
    let mut code = 0;
    if o.out().check {
        match check() {
            Ok(()) => lines.push(format!(
                "check (-C): {what}, tetrahedra positive, volume preserved"
            )),
            Err(v) => {
                lines.push(format!("check FAILED: {v}"));
                code = 1;
            }
        }
    }
    if let Some(dir) = &o.output_dir {
        std::fs::create_dir_all(dir).map_err(|e| {
            crate::fail::input_err(format!("cannot create directory {}: {e}", dir.display()))
        })?;
    }
    Ok(code)
}

/// The end of a `tet -p/-q/-r` summary: the report `lines`, the timing line
/// and the files written on stdout; with `-Q` only a failed `-C` check, on
/// stderr.
pub fn print_tail(
    quiet: bool,
    lines: &[String],
    time: impl FnOnce() -> String,
    written: &[std::path::PathBuf],
) {
    if quiet {
        for l in lines.iter().filter(|l| l.starts_with("check FAILED")) {
            eprintln!("delone: {l}");
        }
        return;
    }
    for l in lines {
        println!("  {l}");
    }
    println!("  {}", time());
    let w: Vec<String> = written.iter().map(|p| p.display().to_string()).collect();
    println!("  wrote {}", w.join(", "));
}
