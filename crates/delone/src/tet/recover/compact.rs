//! Removal of unused Steiner points from a [`Recovered`] mesh.
//!
//! Surface preservation (`-Y`) inserts interior points into the Delaunay
//! tetrahedralization where flips and cavities fail; some of them end up
//! outside the domain (carved away) or are not needed by the final mesh.
//! They would stay in [`Recovered::points`] as isolated vertices. Every
//! Steiner point (id at or past the number of input points) that no
//! tetrahedron uses is dropped here and the later ones are renumbered,
//! keeping their order (deterministic); input points always keep their
//! ids. A Steiner point on the surface is a vertex of a boundary or
//! interior face, so of a tetrahedron: only interior points can be unused,
//! and [`super::RecoverReport::steiner_interior`] is reduced accordingly.

use super::types::Recovered;
use crate::tet::dmesh::DomainMesh;
use crate::NONE;

/// Drops the Steiner points (ids `n_input..`) no tetrahedron of `rec`
/// uses and renumbers the rest, in `rec` and in its domain mesh `mesh`;
/// returns how many were dropped.
pub(crate) fn drop_unused_steiner(
    rec: &mut Recovered,
    mesh: &mut DomainMesh,
    n_input: usize,
) -> usize {
    let n = rec.points.len();
    if n <= n_input {
        return 0;
    }
    let mut used = vec![false; n];
    for &w in rec.mesh.tets.iter().flatten() {
        if let Some(u) = used.get_mut(w as usize) {
            *u = true;
        }
    }
    if used[n_input..].iter().all(|&u| u) {
        return 0;
    }
    let mut new_id = vec![NONE; n];
    let mut next = 0u32;
    for (i, id) in new_id.iter_mut().enumerate() {
        if i < n_input || used[i] {
            *id = next;
            next += 1;
        }
    }
    let map = |w: &mut u32| {
        if let Some(&x) = new_id.get(*w as usize) {
            if x != NONE {
                *w = x;
            }
        }
    };
    let dropped = n - next as usize;
    let mut i = 0;
    rec.points.retain(|_| {
        let keep = new_id[i] != NONE;
        i += 1;
        keep
    });
    rec.mesh.tets.iter_mut().flatten().for_each(map);
    mesh.tv.iter_mut().flatten().for_each(map);
    // The vertex hints, for the new ids.
    mesh.compact(rec.points.len());
    rec.boundary.iter_mut().flatten().for_each(map);
    rec.interior_faces.iter_mut().flatten().for_each(map);
    rec.inexact
        .retain(|&w| new_id.get(w as usize).is_some_and(|&x| x != NONE));
    rec.inexact.iter_mut().for_each(map);
    let mut i = 0;
    rec.mesh.vertex_map.retain(|_| {
        let keep = new_id.get(i).is_none_or(|&x| x != NONE);
        i += 1;
        keep
    });
    rec.mesh.vertex_map.iter_mut().for_each(map);
    rec.mesh
        .hidden
        .retain(|&w| new_id.get(w as usize).is_none_or(|&x| x != NONE));
    rec.mesh.hidden.iter_mut().for_each(map);
    rec.report.steiner_interior = rec.report.steiner_interior.saturating_sub(dropped);
    dropped
}
