//! Removal of the interior Steiner points that the recovered surface no
//! longer needs (`-Y`).
//!
//! The cavities, the interior-point rounds and the fallback's pulled-off
//! surface points leave interior vertices behind, most of them needed
//! only while the surface was being recovered. Once every input triangle
//! is a face, an interior Steiner point `s` can go when its star (every
//! tetrahedron at `s`, all finite) is the cone from one of the star's
//! boundary vertices `v`: the boundary faces not at `v` all seen strictly
//! from inside by `v` (exact `orient3d`). The replacement is then checked
//! like every cavity fill ([`valid_replacement`]: strictly positive
//! tetrahedra whose oriented faces have exactly the star's boundary as
//! boundary, and every input edge and face kept) before it is applied.
//! The star's inner faces and edges are all at `s`, so no input face or
//! edge lies inside it, and removing `s` changes nothing of the surface.
//!
//! Points are tried in increasing id order, and again while a pass
//! removes one (a removal changes its neighbours' stars): the result does
//! not depend on anything but the mesh. Of the boundary vertices, the one
//! whose cone's flattest tetrahedron is the fullest (the smallest
//! `6 V / (sum of squared edge lengths)^(3/2)`, floating point, ties by id)
//! is tried first, so the removal keeps the mesh as well shaped as it can.

use super::{boundary_of, cone_from, valid_replacement, Guard, P};
use crate::geom::vec3::{cross, dot, sub};
use crate::tet::dmesh::journal::Journaled;
use crate::tet::local::{DEAD, INF};

use super::super::State;

/// Passes over the interior Steiner points (each removes at least one, or
/// the pruning stops).
const MAX_PASSES: usize = 8;

/// Floating shape measure of tetrahedron `t` (0 for a flat one).
fn shape(pts: &[P], t: &[u32; 4]) -> f64 {
    let [a, b, c, d] = t.map(|w| pts[w as usize]);
    let (ab, ac, ad) = (sub(&b, &a), sub(&c, &a), sub(&d, &a));
    let v = dot(&cross(&ab, &ac), &ad).abs();
    let (bc, bd, cd) = (sub(&c, &b), sub(&d, &b), sub(&d, &c));
    let l: f64 = [ab, ac, ad, bc, bd, cd].iter().map(|e| dot(e, e)).sum();
    if l > 0.0 {
        v / (l * l.sqrt())
    } else {
        0.0
    }
}

impl State {
    /// Removes the interior Steiner points (ids from `n_in`) of `cm`, a
    /// mesh on which every input triangle of `self.surf` is a face, whose
    /// star is the cone from one of its boundary vertices (module
    /// documentation). Returns how many were removed; they stay in the
    /// points, unused (dropped by compaction).
    pub(in crate::tet::recover) fn prune_interior(
        &self,
        cm: &mut Journaled<'_>,
        n_in: usize,
    ) -> usize {
        let n = cm.pts().len();
        if n <= n_in {
            return 0;
        }
        let mut prot = Guard {
            prot: Default::default(),
            n_fixed: n_in,
        };
        for &t in &self.surf.tris {
            prot.add_face(t);
        }
        for e in &self.surf.edges {
            prot.edges.insert(crate::tet::local::ekey(e[0], e[1]));
        }
        // The Steiner points some live tetrahedron uses (a vertex no
        // tetrahedron holds has no star to walk).
        let mut live = vec![false; n - n_in];
        for tv in &cm.m.tv {
            if tv[0] == DEAD {
                continue;
            }
            for &w in tv {
                if w != INF && w as usize >= n_in {
                    live[w as usize - n_in] = true;
                }
            }
        }
        let mut removed = 0;
        for _ in 0..MAX_PASSES {
            let mut any = false;
            for s in n_in..n {
                if !live[s - n_in] {
                    continue;
                }
                if self.remove_by_cone(cm, s as u32, &prot) {
                    live[s - n_in] = false;
                    removed += 1;
                    any = true;
                }
            }
            if !any {
                break;
            }
        }
        removed
    }

    /// Replaces the star of interior point `s` by the cone from one of its
    /// boundary vertices, when one is valid; true when done.
    fn remove_by_cone(&self, cm: &mut Journaled<'_>, s: u32, prot: &Guard) -> bool {
        let mut star = cm.star(s);
        if star.is_empty()
            || star.iter().any(|&t| {
                let tv = cm.m.tv[t as usize];
                tv[0] == DEAD || tv.contains(&INF)
            })
        {
            return false;
        }
        star.sort_unstable();
        let reg = boundary_of(cm, &star);
        let faces = reg.tris();
        let pts = cm.pts();
        let mut cands: Vec<(f64, u32, Vec<[u32; 4]>)> = reg
            .vertices()
            .into_iter()
            .filter_map(|v| {
                let tets = cone_from(pts, &faces, v)?;
                let q = tets
                    .iter()
                    .map(|t| shape(pts, t))
                    .fold(f64::INFINITY, f64::min);
                Some((q, v, tets))
            })
            .collect();
        cands.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
        for (_, _, tets) in cands {
            if valid_replacement(cm, pts, &star, &tets, prot) {
                cm.replace(&star, &tets);
                return true;
            }
        }
        false
    }
}
