//! `delone tet --stats-json FILE`: the mesh's quality statistics
//! ([`TetStats::to_json`]) and, in the same object, what the recovery,
//! the refinement and the optimisation did — Steiner points by kind,
//! cells left above the bound, dihedral angles before and after the
//! optimisation, the input's own bounds, and the worst tetrahedra left
//! with the reason they could not be improved.

use std::fmt::Write as _;

use delone::tet::optimize::OptimizeReport;
use delone::tet::quality::TetStats;
use delone::tet::recover::Recovered;
use delone::tet::refine::RefineReport;

/// A JSON number (`null` for NaN and infinities).
fn num(x: f64) -> String {
    if x.is_finite() {
        format!("{x:?}")
    } else {
        "null".to_string()
    }
}

/// `{"k": v, ...}` from already encoded values.
fn object(fields: &[(&str, String)]) -> String {
    let body: Vec<String> = fields
        .iter()
        .map(|(k, v)| format!("\"{k}\": {v}"))
        .collect();
    format!("{{{}}}", body.join(", "))
}

/// A JSON string of `s` (only `"` and `\` need escaping in our texts;
/// control characters are dropped).
fn string(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if c.is_control() => {}
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

fn opt_u32(x: Option<u32>) -> String {
    x.map_or_else(|| "null".to_string(), |v| v.to_string())
}

fn range(s: &TetStats) -> String {
    object(&[
        ("min_dihedral", num(s.min_dihedral)),
        ("max_dihedral", num(s.max_dihedral)),
        ("max_radius_edge", num(s.max_radius_edge)),
        ("tets", s.tets.to_string()),
        (
            "dihedral_histogram",
            format!(
                "[{}]",
                s.dihedral_histogram
                    .iter()
                    .map(|n| n.to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        ),
    ])
}

/// The whole `--stats-json` document.
pub fn document(
    s: &TetStats,
    rec: &Recovered,
    refined: Option<&RefineReport>,
    optimized: Option<&OptimizeReport>,
) -> String {
    let mut out = s.to_json();
    // `to_json` ends with "}\n" or "}": reopen the object.
    while out.ends_with(['\n', ' ']) {
        out.pop();
    }
    out.pop();
    while out.ends_with(['\n', ' ']) {
        out.pop();
    }
    let r = &rec.report;
    let mut steiner = vec![(
        "recovery",
        object(&[
            ("on_edges", r.steiner_on_edges.to_string()),
            ("on_facets", r.steiner_on_facets.to_string()),
            ("interior", r.steiner_interior.to_string()),
            ("inexact", r.inexact_steiner.to_string()),
            ("max_deviation", num(r.max_deviation)),
            ("chord_slivers_removed", r.chord_slivers.to_string()),
        ]),
    )];
    if let Some(f) = refined {
        steiner.push((
            "refinement",
            object(&[
                ("on_segments", f.on_segments.to_string()),
                ("on_facets", f.on_facets.to_string()),
                ("interior", f.interior.to_string()),
                (
                    "segments_for_vertices",
                    f.causes.segments_for_vertices.to_string(),
                ),
                (
                    "segments_for_subfaces",
                    f.causes.segments_for_subfaces.to_string(),
                ),
                (
                    "segments_for_cells",
                    f.causes.segments_for_cells.to_string(),
                ),
                (
                    "facets_for_vertices",
                    f.causes.facets_for_vertices.to_string(),
                ),
                ("facets_for_cells", f.causes.facets_for_cells.to_string()),
            ]),
        ));
    }
    let _ = write!(out, ",\n  \"steiner\": {}", object(&steiner));
    if let Some(f) = refined {
        let _ = write!(
            out,
            ",\n  \"refinement\": {}",
            object(&[
                ("circumcentres_rejected", f.rejected.to_string()),
                ("skipped", f.skipped.to_string()),
                ("skipped_flat", f.skipped_flat.to_string()),
                ("skipped_behind", f.skipped_behind.to_string()),
                ("skipped_small", f.skipped_small.to_string()),
                ("skipped_refused", f.skipped_refused.to_string()),
                ("skipped_kept_surface", f.skipped_surface.to_string()),
                ("points_off_circumcentre", f.inside.to_string()),
                ("left_above_bound", f.remaining_bad.to_string()),
                ("left_flat_on_input_plane", f.flat.to_string()),
                ("left_at_boundary", f.remaining_at_boundary.to_string()),
                ("left_too_big", f.remaining_too_big.to_string()),
                (
                    "left_above_volume_bound",
                    f.remaining_over_volume.to_string()
                ),
                ("budget_exhausted", f.budget_exhausted.to_string()),
                (
                    "left_by_cause",
                    object(&[
                        ("flat", f.left.flat.to_string()),
                        ("behind_subface", f.left.behind.to_string()),
                        ("close_to_vertex", f.left.close.to_string()),
                        ("insertion_radius", f.left.radius.to_string()),
                        ("small_pieces", f.left.small.to_string()),
                        ("sharp_wedge", f.left.wedge.to_string()),
                        ("zero_angle_triangle", f.left.degenerate.to_string()),
                        ("shell_pair", f.left.shell.to_string()),
                        ("refused", f.left.refused.to_string()),
                        ("kept_surface", f.left.surface.to_string()),
                        ("other", f.left.other.to_string()),
                        ("near_needle_triangle", f.left.near_needle.to_string()),
                        ("near_sharp_edge", f.left.near_sharp.to_string()),
                    ]),
                ),
            ])
        );
    }
    if let Some(o) = optimized {
        let stuck: Vec<String> = o
            .stuck
            .iter()
            .map(|t| {
                object(&[
                    ("tet", t.tet.to_string()),
                    ("min_dihedral", num(t.dihedral[0])),
                    ("max_dihedral", num(t.dihedral[1])),
                    ("reason", string(&t.reason.to_string())),
                    ("shape", string(&format!("{:?}", t.shape).to_lowercase())),
                    ("surface_faces", t.surface_faces.to_string()),
                    ("input_vertices", t.input_vertices.to_string()),
                    ("fixed_vertices", t.fixed_vertices.to_string()),
                    ("near_input_triangle", opt_u32(t.near_triangle)),
                    ("near_triangle_min_angle", num(t.near_angles[0])),
                    ("near_triangle_max_angle", num(t.near_angles[1])),
                ])
            })
            .collect();
        let stages: Vec<String> = o
            .stages
            .iter()
            .map(|s| {
                object(&[
                    ("threshold", num(s.threshold)),
                    ("second_run", s.second_run.to_string()),
                    ("evaluations", s.evaluations.to_string()),
                    ("undone_evaluations", s.undone_evaluations.to_string()),
                    ("worst_reached", s.worst_reached.to_string()),
                    ("tries", s.attempts.to_string()),
                    ("successes", s.successes.to_string()),
                    ("worst_before", num(s.worst[0])),
                    ("worst_after", num(s.worst[1])),
                    ("below_before", s.below[0].to_string()),
                    ("below_after", s.below[1].to_string()),
                    ("ended", string(&s.stop.to_string())),
                ])
            })
            .collect();
        let _ = write!(
            out,
            ",\n  \"optimization\": {}",
            object(&[
                ("before", range(&o.before)),
                ("after", range(&o.after)),
                // The input triangles' own bound, then the meshed surface's
                // (after the refinement split it): see `OptimizeReport`.
                ("input_min_dihedral", num(o.triangles_min_dihedral)),
                ("meshed_surface_min_dihedral", num(o.input_min_dihedral)),
                ("input_triangles_min_angle", num(o.triangles_min_angle)),
                (
                    "input_triangles_min_angle_triangle",
                    opt_u32(o.triangles_min_angle_triangle),
                ),
                ("input_triangles_max_angle", num(o.triangles_max_angle)),
                (
                    "input_triangles_max_angle_triangle",
                    opt_u32(o.triangles_max_angle_triangle),
                ),
                ("flips23", o.flips23.to_string()),
                ("flips32", o.flips32.to_string()),
                ("flips44", o.flips44.to_string()),
                ("edge_removals", o.edge_removals.to_string()),
                ("multi_face_removals", o.multi_face.to_string()),
                ("boundary_flips", o.boundary_flips.to_string()),
                ("vertex_moves", o.smoothed.to_string()),
                ("inserted", o.inserted.to_string()),
                ("collapsed", o.collapsed.to_string()),
                ("refinement_points_removed", o.removed.to_string()),
                ("flat_boundary_removed", o.flat_removed.to_string()),
                (
                    "below_15",
                    object(&[
                        ("angle", num(o.bad.angle)),
                        ("count", o.bad.count.to_string()),
                        ("at_sharp_input_edge", o.bad.sharp_edge.to_string()),
                        ("at_needle_or_cap_triangle", o.bad.at_feature.to_string()),
                        ("feature_angle", num(o.bad.feature_angle)),
                        ("free", o.bad.free.to_string()),
                    ]),
                ),
                ("effort_exhausted", o.effort_exhausted.to_string()),
                ("below_target_surface_faces", o.stuck_counts[0].to_string()),
                ("below_target_all_fixed", o.stuck_counts[1].to_string()),
                ("below_target_not_improved", o.stuck_counts[2].to_string()),
                ("worst_left", format!("[{}]", stuck.join(", "))),
                ("stages", format!("[{}]", stages.join(", "))),
            ])
        );
    }
    out.push_str("\n}\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strings_and_numbers_are_json() {
        assert_eq!(string("a\"b\\c\n"), "\"a\\\"b\\\\c\"");
        assert_eq!(num(f64::NAN), "null");
        assert_eq!(num(1.5), "1.5");
        assert_eq!(
            object(&[("a", "1".into()), ("b", "null".into())]),
            "{\"a\": 1, \"b\": null}"
        );
    }
}
