//! `delone tri -p`: constrained Delaunay triangulation of a `.poly` PSLG.

use std::path::PathBuf;
use std::time::Instant;

use delone::model::pslg::{Pslg, Region};
use delone::tri::conforming::check_conforming_delaunay;
use delone::tri::constrain::check_cdt;
use delone::tri::quality::SteinerCounts;
use delone::tri::refine::{RefineReport, SegmentSplits, UnfixableReason};
use delone::tri::{TriError, TriOptions};

use crate::args::Opts;
use crate::fail::{input_err, Failure};

/// `FILE` or `FILE.poly` → (`FILE.poly`, `FILE`); the output base gets
/// Triangle's iteration number (`FILE.1`) unless `-I`.
fn names(o: &Opts) -> (PathBuf, PathBuf, PathBuf) {
    let s = o.input.to_string_lossy().to_string();
    let base = s.strip_suffix(".poly").unwrap_or(&s).to_string();
    let poly = PathBuf::from(format!("{base}.poly"));
    let node = PathBuf::from(format!("{base}.node"));
    let out = crate::paths::output_base(&base, o.out().no_iteration, o.output_dir.as_deref());
    (poly, node, out)
}

/// Smallest and largest angle (degrees) of a mesh, measured by
/// [`delone::tri::quality::TriangleQuality`] (on each triangle scaled by a
/// power of two: the same at every coordinate scale).
fn angle_range(p: &[[f64; 2]], tris: &[[u32; 3]]) -> (f64, f64) {
    let mut lo = 180.0f64;
    let mut hi = 0.0f64;
    for v in tris {
        let [a, b, c] = v.map(|q| p[q as usize]);
        let q = delone::tri::quality::TriangleQuality::new(a, b, c);
        lo = lo.min(q.min_angle);
        hi = hi.max(q.max_angle);
    }
    if tris.is_empty() {
        lo = 0.0;
    }
    (lo, hi)
}

/// `-C` with `-D`: every triangle truly Delaunay (exact incircle against
/// every mesh vertex).
pub fn check_conforming(
    o: &Opts,
    points: &[[f64; 2]],
    triangles: &[[u32; 3]],
    lines: &mut Vec<String>,
) -> i32 {
    if !(o.out().check && o.tri.conforming_delaunay) {
        return 0;
    }
    match check_conforming_delaunay(points, triangles) {
        Ok(()) => {
            lines.push("check: conforming Delaunay (every circumcircle empty of vertices)".into());
            0
        }
        Err(v) => {
            lines.push(format!("check FAILED: not conforming Delaunay: {v}"));
            1
        }
    }
}

/// The summary line of `-D` (None without it).
pub fn conforming_line(o: &Opts, r: &RefineReport) -> Option<String> {
    o.tri.conforming_delaunay.then(|| {
        if r.encroached_subsegments == 0 {
            "  conforming Delaunay: every subsegment has an empty diametral circle".to_string()
        } else {
            format!(
                "  conforming Delaunay NOT met: {} subsegments still have a vertex in their diametral circle ({})",
                r.encroached_subsegments,
                if r.limit_reached { "Steiner limit reached" } else if o.tri.segment_splits != SegmentSplits::All { "-Y forbids splitting them" } else { "too short to split" }
            )
        }
    })
}

/// Why carving left no triangle of PSLG `g` (numbered from `first` in
/// its file): no segments, an open boundary, or the holes.
fn why_empty(g: &Pslg, first: u32) -> String {
    let f = first as usize;
    let mut why = Vec::new();
    if g.segments.is_empty() {
        why.push("the file has no segments, so nothing encloses a region".to_string());
    } else {
        let mut degree = vec![0usize; g.points.len()];
        for s in &g.segments {
            if s[0] != s[1] {
                for &v in s {
                    if let Some(d) = degree.get_mut(v as usize) {
                        *d += 1;
                    }
                }
            }
        }
        let open = g.segments.iter().enumerate().find_map(|(k, s)| {
            s.iter()
                .find(|&&v| degree.get(v as usize) == Some(&1))
                .map(|&v| (k, v))
        });
        if let Some((k, v)) = open {
            why.push(format!(
                "the boundary is not closed: segment {}'s endpoint {} has no other segment",
                k + f,
                v as usize + f
            ));
        }
    }
    let hull = if why.is_empty() {
        "move the hole point(s) into the region to remove"
    } else {
        "use -c to keep the convex hull"
    };
    if why.is_empty() {
        // A closed boundary: the holes ate the domain.
        for (k, h) in g.holes.iter().enumerate() {
            let on = g.segments.iter().position(|s| {
                let (a, b) = (g.points[s[0] as usize], g.points[s[1] as usize]);
                let cross = (b[0] - a[0]) * (h[1] - a[1]) - (b[1] - a[1]) * (h[0] - a[0]);
                let within =
                    (h[0] - a[0]) * (h[0] - b[0]) <= 0.0 && (h[1] - a[1]) * (h[1] - b[1]) <= 0.0;
                cross == 0.0 && within
            });
            why.push(match on {
                Some(s) => format!(
                    "hole {} at ({}, {}) lies on segment {}, so it eats the triangles on both sides",
                    k + f,
                    h[0],
                    h[1],
                    s + f
                ),
                None => format!(
                    "hole {} at ({}, {}) removed every triangle it could reach",
                    k + f,
                    h[0],
                    h[1]
                ),
            });
        }
    }
    format!("no triangle left after carving: {}; {hull}", why.join("; "))
}

/// A refinement error: a bound no mesh can meet is a usage error (exit
/// code 2) naming the switch; anything else an input error.
pub fn refine_err(what: &str, e: delone::Error) -> Failure {
    match e {
        delone::Error::InvalidBound { .. } => Failure {
            message: e.to_string(),
            code: 2,
        },
        e => input_err(format!("{what}: {e}")),
    }
}

/// What the run says about the bounds after refinement (see the README's
/// rule "every bound is met, or the run says so"): `(exit code, message
/// for stderr)`. The Steiner budget stopping the refinement before the
/// bounds were met is a failure (exit code 1) whose message names the
/// budget, its memory estimate, the triangles left and `-S`. Triangles of
/// the final mesh left outside the bounds for other reasons (input angles
/// smaller than the bound, `-Y`, floating point, `-D`) give exit code 3
/// and a message counting them by bound and by cause; `--warn-unmet` makes
/// that a warning (exit code 0). With `-Q` only the budget's message is
/// printed (exit code 3 stays).
pub fn bound_status(o: &Opts, r: &RefineReport) -> (i32, Option<String>) {
    if r.met {
        return (0, None);
    }
    let q = o.tri.min_angle.unwrap_or(0.0);
    let below = r
        .unfixable
        .iter()
        .filter(|u| u.min_angle < q && q > 0.0)
        .count();
    let above = r.unfixable.len() - below;
    let count = |reason: fn(&UnfixableReason) -> bool| {
        r.unfixable.iter().filter(|u| reason(&u.reason)).count()
    };
    let small = count(|x| matches!(x, UnfixableReason::SmallInputAngle { .. }));
    if r.limit_reached {
        let miss = format!(
            "{} triangles miss the bounds ({below} below the -q angle, {above} above the area bound)",
            r.unfixable.len()
        );
        let used = r.segment_splits + r.circumcenters;
        let mb = delone::tri::refine::memory_estimate(r.steiner_budget) as f64 / 1e6;
        return (
            1,
            Some(format!(
                "bounds NOT met: refinement stopped at the Steiner budget of {} points (about {mb:.0} MB) after {used} points; {miss}, {small} of them at input angles smaller than the bound; the mesh reached is written. Raise the budget with -S<n> (e.g. -S{}), or ask for a bound refinement can reach (angles up to about 34 degrees terminate)",
                r.steiner_budget,
                r.steiner_budget.saturating_mul(4)
            )),
        );
    }
    if r.unfixable.is_empty() {
        return (0, None);
    }
    let causes = [
        (
            small,
            "at input angles smaller than the bound (forced by the input)",
        ),
        (
            count(|x| matches!(x, UnfixableReason::NoSegmentSplits)),
            "because -Y forbids splitting the segment in the way",
        ),
        (
            count(|x| matches!(x, UnfixableReason::Precision)),
            "because floating point could not place a point for them",
        ),
        (
            count(|x| matches!(x, UnfixableReason::ConformingDelaunay)),
            "because the refinement stopped to finish -D",
        ),
        (
            count(|x| matches!(x, UnfixableReason::SteinerLimit)),
            "at the Steiner budget",
        ),
    ];
    let why: Vec<String> = causes
        .iter()
        .filter(|c| c.0 > 0)
        .map(|(n, w)| format!("{n} {w}"))
        .collect();
    let mut bounds = Vec::new();
    if below > 0 {
        bounds.push(format!("{below} below the -q angle {q}"));
    }
    if above > 0 {
        bounds.push(format!("{above} above their area bound (-a)"));
    }
    let what = format!(
        "{} triangles of the mesh miss the bounds ({}): {}; the mesh is written; -V lists them",
        r.unfixable.len(),
        bounds.join(", "),
        why.join(", ")
    );
    unmet(o, what)
}

/// The bounds missed for reasons of the input or the options (not the
/// budget): exit code 3 and `bounds NOT met: …`, or with `--warn-unmet` a
/// warning and exit code 0; no message with `-Q`.
pub fn unmet(o: &Opts, what: String) -> (i32, Option<String>) {
    let (code, msg) = if o.warn_unmet {
        (0, format!("warning: {what}"))
    } else {
        (
            3,
            format!("bounds NOT met: {what}; exit code 3 (--warn-unmet makes this a warning, exit code 0)"),
        )
    };
    (code, (!o.out().quiet).then_some(msg))
}

/// Combines two exit codes: a failure (1, 2) wins over a missed bound (3),
/// which wins over success (0).
pub fn combine(a: i32, b: i32) -> i32 {
    match (a, b) {
        (0, x) | (x, 0) => x,
        (3, x) | (x, 3) => x,
        (x, y) => x.max(y),
    }
}

/// Runs `delone tri -p`. Returns the exit code (1 when `-C` finds a violation).
pub fn run(o: &Opts) -> Result<i32, Failure> {
    let t_all = Instant::now();
    let (poly_path, node_path, out) = names(o);
    crate::guard::plan(crate::args::Mode::Tri, crate::guard::Kind::Domain, o, &out);
    let bytes = crate::guard::read(&poly_path)
        .map_err(|e| input_err(format!("cannot read {}: {e}", poly_path.display())))?;
    let poly = delone_io::read_poly(&bytes)
        .map_err(|e| input_err(format!("{}: {e}", poly_path.display())))?;
    let node = if poly.node.is_empty() {
        let b = crate::guard::read(&node_path).map_err(|e| {
            input_err(format!(
                "{} has no points and {} cannot be read: {e}",
                poly_path.display(),
                node_path.display()
            ))
        })?;
        delone_io::read_node(&b).map_err(|e| input_err(format!("{}: {e}", node_path.display())))?
    } else {
        poly.node.clone()
    };
    crate::guard::check()?;
    let Some(points) = node.points::<2>() else {
        return Err(input_err(format!(
            "{}: the points are not 2D",
            poly_path.display()
        )));
    };
    let segments = poly
        .segments_zero_based(node.first_index)
        .map_err(|e| input_err(format!("{}: {e}", poly_path.display())))?;
    let g = Pslg {
        point_markers: node.markers.clone().unwrap_or_default(),
        points,
        segments,
        segment_markers: poly.segment_markers.clone().unwrap_or_default(),
        holes: poly.holes.clone(),
        regions: poly
            .regions
            .iter()
            .map(|r| Region {
                point: [r[0], r[1]],
                attribute: r[2],
                max_area: r[3],
            })
            .collect(),
    };
    let t_read = t_all.elapsed();
    let t1 = Instant::now();
    // The unrefined mesh, to interpolate point attributes at Steiner points.
    let opts = TriOptions {
        keep_unrefined: node.n_attributes > 0,
        ..o.tri.clone()
    };
    let name = poly_path.display().to_string();
    let result = delone::tri::mesh(&g, &opts).map_err(|e| match e {
        TriError::Input(e) => {
            let what = match &e {
                delone::Error::SegmentOutOfRange { segment, .. }
                | delone::Error::ZeroLengthSegment { segment }
                | delone::Error::SegmentIntersection { segment, .. } => poly
                    .segment_lines
                    .get(*segment)
                    .map(|l| format!(" (segment on line {l})"))
                    .unwrap_or_default(),
                delone::Error::InvalidCoordinate { index } => node
                    .lines
                    .get(*index)
                    .map(|l| format!(" (point on line {l})"))
                    .unwrap_or_default(),
                _ => String::new(),
            };
            let e = crate::numbering::renumber(e, node.first_index);
            input_err(format!("{name}: {e}{what}"))
        }
        TriError::Empty => input_err(format!("{name}: {}", why_empty(&g, node.first_index))),
        TriError::Refine(e) => refine_err(&name, crate::numbering::renumber(e, node.first_index)),
    })?;
    let delone::tri::TriResult {
        mesh: cdt,
        unrefined: initial,
        refine: rep,
        refine_time: t_refine,
    } = result;
    let t_mesh = t1.elapsed().saturating_sub(t_refine);
    let mut code = 0;
    let mut lines = Vec::new();
    if o.out().check {
        match check_cdt(&g, &cdt) {
            Ok(()) => lines.push("check: constrained Delaunay triangulation is valid".to_string()),
            Err(v) => {
                lines.push(format!("check FAILED: {v}"));
                code = 1;
            }
        }
        if let (Some(r), Some(q)) = (&rep, o.tri.min_angle) {
            let small = r
                .unfixable
                .iter()
                .filter(|u| matches!(u.reason, UnfixableReason::SmallInputAngle { .. }))
                .count();
            if r.unfixable.len() == small {
                lines.push(format!(
                    "check: minimum angle {:.4} (bound {q}); {small} triangles below it, all at input angles smaller than the bound",
                    r.min_angle
                ));
            } else {
                lines.push(format!(
                    "check FAILED: {} triangles violate the bounds for other reasons than small input angles",
                    r.unfixable.len() - small
                ));
                code = 1;
            }
        }
    }
    code = code.max(check_conforming(o, &cdt.points, &cdt.triangles, &mut lines));
    let (bound_code, bound_msg) = rep.as_ref().map_or((0, None), |r| bound_status(o, r));
    code = combine(code, bound_code);
    if let Some(dir) = &o.output_dir {
        std::fs::create_dir_all(dir)
            .map_err(|e| input_err(format!("cannot create directory {}: {e}", dir.display())))?;
    }
    let t2 = Instant::now();
    let first = if o.out().zero { 0 } else { node.first_index };
    let steiner = SteinerCounts {
        crossings: cdt.report.crossings.len(),
        segment_splits: rep.as_ref().map_or(0, |r| r.segment_splits),
        interior: rep.as_ref().map_or(0, |r| r.circumcenters),
    };
    let (written, stats) = crate::tri_out::write_pslg(&crate::tri_out::PslgOut {
        o,
        out: &out,
        g: &g,
        node: &node,
        cdt: &cdt,
        initial: initial.as_ref(),
        first,
        steiner,
    })?;
    if let (Some(path), Some(r)) = (&o.stats_json, &rep) {
        crate::tri_out::add_refinement_json(path, o.tri.min_angle, r)?;
    }
    let bounding: Vec<_> = cdt.segments.iter().filter(|s| s.bounding).collect();
    let t_write = t2.elapsed();
    if !o.out().quiet {
        println!(
            "delone tri -p: {} ({} points, {} segments, {} holes, {} regions)",
            poly_path.display(),
            g.points.len(),
            g.segments.len(),
            g.holes.len(),
            g.regions.len()
        );
        println!(
            "  {} triangles, {} subsegments, {} Steiner vertices at crossings, {} segments split at vertices, {} duplicate points, {} duplicate segments",
            cdt.triangles.len(),
            bounding.len(),
            cdt.report.crossings.len(),
            cdt.report.vertex_splits.len(),
            cdt.report.duplicate_points.len(),
            cdt.report.duplicate_segments.len()
        );
        if let Some(r) = &rep {
            println!(
                "  refinement: {} Steiner points ({} on segments, {} circumcentres/off-centres, {} rejected circumcentres); bounds {}",
                r.segment_splits + r.circumcenters,
                r.segment_splits,
                r.circumcenters,
                r.rejected_circumcenters,
                if r.met { "met" } else if r.limit_reached { "NOT met (Steiner budget reached)" } else { "NOT met" }
            );
            if o.out().verbose > 0 {
                println!(
                    "  Steiner budget {} points (about {:.0} MB; -S raises it){}",
                    r.steiner_budget,
                    delone::tri::refine::memory_estimate(r.steiner_budget) as f64 / 1e6,
                    if r.limit_reached { ", reached" } else { "" }
                );
            }
            if let Some(l) = conforming_line(o, r) {
                println!("{l}");
            }
        }
        if o.out().verbose > 0 {
            println!(
                "  read {:.3} s, mesh {:.3} s ({} flips), refine {:.3} s, write {:.3} s",
                t_read.as_secs_f64(),
                t_mesh.as_secs_f64(),
                cdt.report.flips,
                t_refine.as_secs_f64(),
                t_write.as_secs_f64()
            );
            let (lo, hi) = match &rep {
                Some(r) => (r.min_angle, r.max_angle),
                None => angle_range(&cdt.points, &cdt.triangles),
            };
            println!(
                "  {} vertices, {} triangles; minimum angle {lo:.4}, maximum angle {hi:.4}",
                cdt.points.len(),
                cdt.triangles.len()
            );
            if let Some(r) = &rep {
                for u in r
                    .unfixable
                    .iter()
                    .take(if o.out().verbose > 1 { usize::MAX } else { 10 })
                {
                    let why = match u.reason {
                        UnfixableReason::SmallInputAngle { apex, input_angle } => format!(
                            "input angle {input_angle:.3} at vertex {}",
                            apex as usize + first as usize
                        ),
                        UnfixableReason::SteinerLimit => "Steiner limit".into(),
                        UnfixableReason::Precision => "floating-point precision".into(),
                        UnfixableReason::ConformingDelaunay => {
                            "quality refinement stopped to finish -D".into()
                        }
                        UnfixableReason::NoSegmentSplits => "segment splitting is off".into(),
                    };
                    println!(
                        "  unfixed triangle {}: minimum angle {:.3}, area {:.3e} ({why})",
                        u.triangle as usize + first as usize,
                        u.min_angle,
                        u.area
                    );
                }
                if r.unfixable.len() > 10 && o.out().verbose < 2 {
                    println!("  ... {} more (-VV lists all)", r.unfixable.len() - 10);
                }
            }
        }
        if o.tri.jettison {
            let mut used = vec![false; cdt.points.len()];
            for t in &cdt.triangles {
                for &v in t {
                    used[v as usize] = true;
                }
            }
            println!(
                "  -j: {} unused vertices left out of the .node",
                used.iter().filter(|&&u| !u).count()
            );
        }
        if let Some(st) = &stats {
            for l in st.to_string().lines() {
                println!("  {l}");
            }
        }
        for l in &lines {
            println!("  {l}");
        }
        let list: Vec<String> = written.iter().map(|p| p.display().to_string()).collect();
        println!("  wrote {}", list.join(", "));
    } else if code != 0 {
        for l in &lines {
            eprintln!("{l}");
        }
    }
    if let Some(m) = bound_msg {
        eprintln!("delone: {m}");
    }
    Ok(code)
}
