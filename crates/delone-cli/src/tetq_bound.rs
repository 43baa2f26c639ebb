//! `-V` lines of the optimisation: which bound the input puts on the
//! dihedral angles, and what the tetrahedra left below the target are.

use delone::tet::optimize::{OptimizeReport, Stuck};

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
    let bound = r.input_min_dihedral.min(r.triangles_min_dihedral);
    let verdict = if min >= bound - 1e-6 {
        if r.triangles_min_dihedral <= r.input_min_dihedral + 1e-6 {
            "the mesh's minimum is the input's own angle"
        } else {
            "the mesh's minimum is set by the meshed surface, not by the input"
        }
    } else if bound < 15.0 {
        "the mesh's minimum is below both; the bound is below 15 deg"
    } else {
        "the mesh's minimum is below both (not forced by the input)"
    };
    format!("optimization: bound: {input}; {meshed}; {verdict}")
}

/// One tetrahedron left below the target: angles, why, its shape, and how
/// its vertices and faces sit on the surface.
pub fn stuck_line(s: &Stuck) -> String {
    format!(
        "  tet {} left at {:.2}..{:.2} deg: {}; {}, {} surface faces, {} input and {} fixed vertices",
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
