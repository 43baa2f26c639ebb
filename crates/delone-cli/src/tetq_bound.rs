//! `-V` lines of the optimisation: which bound the input puts on the
//! dihedral angles, and what the tetrahedra left below the target are.

use delone::tet::optimize::{OptimizeReport, StageReport, Stuck};

use crate::args::Opts;

/// The input's bound on the smallest dihedral angle (from the input
/// triangles, and from the meshed surface after refinement) and whether the
/// mesh's minimum is set by it.
pub fn bound_line(_o: &Opts, r: &OptimizeReport) -> String {
    let min = r.after.min_dihedral;
    let input = match r.triangles_min_edge {
        Some([a, b]) => format!(
            "input triangles' smallest dihedral angle {:.2} deg at input edge {a}-{b}",
            r.triangles_min_dihedral
        ),
        None => "no input edge between two boundary triangles".to_string(),
    };
    let meshed = match r.input_min_edge {
        Some([a, b]) => format!(
            "meshed surface's {:.2} deg at edge {a}-{b}",
            r.input_min_dihedral
        ),
        None => "no meshed surface edge".to_string(),
    };
    let tri = |t: Option<u32>| t.map_or_else(|| "-".to_string(), |t| t.to_string());
    let angles = format!(
        "input triangles' angles {:.2} deg (triangle {}) to {:.2} deg (triangle {})",
        r.triangles_min_angle,
        tri(r.triangles_min_angle_triangle),
        r.triangles_max_angle,
        tri(r.triangles_max_angle_triangle)
    );
    let bound = r.input_min_dihedral.min(r.triangles_min_dihedral);
    // The worst tetrahedron left, when it sits at a needle or cap input
    // triangle (a feature smaller than the mesh around it).
    let at_feature = r.stuck.first().and_then(|s| {
        let [lo, hi] = s.near_angles;
        let t = s.near_triangle?;
        (lo < r.bad.angle || hi > 180.0 - r.bad.angle).then(|| {
            format!(
                "the worst tetrahedron ({:.2}..{:.2} deg) is at input triangle {t} with angles {lo:.2}..{hi:.2} deg, a feature smaller than the mesh there",
                s.dihedral[0], s.dihedral[1]
            )
        })
    });
    let a = r.bad.angle;
    let below = min < a || r.after.max_dihedral > 180.0 - a;
    let verdict = if min >= bound - 1e-6 {
        if r.triangles_min_dihedral <= r.input_min_dihedral + 1e-6 {
            "the mesh's minimum is the input's own angle"
        } else {
            "the mesh's minimum is set by the meshed surface, not by the input"
        }
    } else if bound < a {
        "the mesh's minimum is below both, and the input's own bound is below the dihedral bound asked for"
    } else if let (true, Some(f)) = (below, &at_feature) {
        f
    } else {
        "the mesh's minimum is below both (not forced by the input)"
    };
    format!(
        "optimization: bound: {input}; {meshed}; {angles}; {verdict}; {}",
        bad_cells(r)
    )
}

/// What the tetrahedra left below the dihedral bound (or above 180° minus it) are at
/// ([`OptimizeReport::bad`]).
fn bad_cells(r: &OptimizeReport) -> String {
    let b = &r.bad;
    let a = b.angle;
    if b.count == 0 {
        return format!("no tetrahedron below {a} deg or above {} deg", 180.0 - a);
    }
    let mut parts = Vec::new();
    if b.sharp_edge > 0 {
        parts.push(format!(
            "{} at input edges whose own angle is below {a} deg (forced by the input)",
            b.sharp_edge
        ));
    }
    if b.at_feature > 0 {
        parts.push(format!(
            "{} at input triangles with an angle below {:.2} deg or above {:.2} deg (needles and caps the mesh does not resolve)",
            b.at_feature,
            b.feature_angle,
            180.0 - b.feature_angle
        ));
    }
    if b.free > 0 {
        parts.push(format!("{} elsewhere (not forced by the input)", b.free));
    }
    let all = if parts.len() == 1 && b.free == 0 {
        "all "
    } else {
        ""
    };
    format!(
        "{} tetrahedra below {a} deg or above {} deg: {all}{}",
        b.count,
        180.0 - a,
        parts.join(", ")
    )
}

/// The `-V` line of one optimisation stage: threshold, work, gain and why
/// it ended.
pub fn stage_line(s: &StageReport) -> String {
    format!(
        "optimization: stage {:.0} deg{}: {} evaluations ({} in undone insertions), {} of {} tries succeeded; worst {:.2} -> {:.2} deg (last raised after {} evaluations), below {} -> {}; ended: {}",
        s.threshold,
        if s.second_run { " (second run)" } else { "" },
        s.evaluations,
        s.undone_evaluations,
        s.successes,
        s.attempts,
        s.worst[0],
        s.worst[1],
        s.worst_reached,
        s.below[0],
        s.below[1],
        s.stop
    )
}

/// One tetrahedron left below the target: angles, why, its shape, and how
/// its vertices and faces sit on the surface.
pub fn stuck_line(s: &Stuck) -> String {
    let near = s.near_triangle.map_or_else(String::new, |t| {
        format!(
            "; at input triangle {t} (angles {:.2}..{:.2} deg)",
            s.near_angles[0], s.near_angles[1]
        )
    });
    format!(
        "  tet {} left at {:.2}..{:.2} deg: {}; {}, {} surface faces, {} input and {} fixed vertices{near}",
        s.tet,
        s.dihedral[0],
        s.dihedral[1],
        s.reason,
        s.shape,
        s.surface_faces,
        s.input_vertices,
        s.fixed_vertices
    )
}
