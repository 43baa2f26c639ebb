//! `-V` lines of the optimisation: which bound the input puts on the
//! dihedral angles, and what the tetrahedra left below the target are.

use delone::tet::optimize::{OptimizeReport, Stuck};

use crate::args::Opts;

/// The input's bound on the smallest dihedral angle and whether the mesh's
/// minimum is set by it.
pub fn bound_line(_o: &Opts, r: &OptimizeReport) -> String {
    let Some([a, b]) = r.input_min_edge else {
        return "optimization: no surface edge bounds the dihedral angles".into();
    };
    let bound = r.input_min_dihedral;
    let min = r.after.min_dihedral;
    let verdict = if min >= bound - 1e-6 {
        "the mesh's minimum is this bound (set by the input)".to_string()
    } else {
        format!(
            "the mesh's minimum {min:.2} deg is below it (not forced by the input{})",
            if bound < 15.0 {
                "; the input itself is below 15 deg"
            } else {
                ""
            }
        )
    };
    format!(
        "optimization: bound by the input: its smallest dihedral angle is {bound:.2} deg, at surface edge {a}-{b}; {verdict}"
    )
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
