//! Removal of the interior Steiner points that the recovered surface no
//! longer needs (`-Y`).
//!
//! The cavities, the interior-point rounds and the fallback's pulled-off
//! surface points leave interior vertices behind, most of them needed
//! only while the surface was being recovered. Once every input triangle
//! is a face, an interior Steiner point `s` can go when its star (every
//! tetrahedron at `s`, all finite) is the cone from one of the star's
//! boundary vertices `v`: the boundary faces not at `v` all seen strictly
//! from inside by `v` (exact `orient3d`), or, where no cone is valid, when
//! the gift-wrapping fill of the star's boundary (`dfill::wrap_fill`)
//! tiles it. The replacement is then checked
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
    /// star can be refilled without them: a cone from one of its boundary
    /// vertices, else a gift-wrapping fill (module documentation). Returns how many were removed; they stay in the
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
                if self.remove_by_refill(cm, s as u32, &prot) {
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
    /// boundary vertices, when one is valid, else by the gift-wrapping
    /// fill when it is valid; true when done.
    fn remove_by_refill(&self, cm: &mut Journaled<'_>, s: u32, prot: &Guard) -> bool {
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
        let wrapped = || super::dfill::wrap_fill(pts, &faces);
        let tets = cands
            .into_iter()
            .map(|c| c.2)
            .find(|tets| valid_replacement(cm, pts, &star, tets, prot))
            .or_else(|| wrapped().filter(|tets| valid_replacement(cm, pts, &star, tets, prot)));
        match tets {
            Some(tets) => {
                cm.replace(&star, &tets);
                true
            }
            None => false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::pull::tests::state;
    use super::*;
    use crate::tet::dmesh::tests::cuboid;
    use crate::tet::Delaunay3;

    /// Every input triangle a face, and the mesh invariants.
    fn assert_valid(cm: &Journaled<'_>, tris: &[[u32; 3]]) {
        cm.m.check(cm.pts()).unwrap();
        for t in tris {
            assert!(cm.find_face(t[0], t[1], t[2]).is_some(), "{t:?}");
        }
    }

    fn used_steiner(cm: &Journaled<'_>, n_in: usize) -> usize {
        let mut used: Vec<u32> =
            cm.m.tv
                .iter()
                .filter(|tv| tv[0] != DEAD)
                .flatten()
                .copied()
                .filter(|&w| w != INF && w as usize >= n_in)
                .collect();
        used.sort_unstable();
        used.dedup();
        used.len()
    }

    /// An octahedron with a point inside: the point's star is the cone
    /// from any corner, so it goes, leaving the four tetrahedra at a
    /// diagonal.
    #[test]
    fn removes_a_point_whose_star_is_a_cone() {
        let mut pts: Vec<P> = crate::tet::dmesh::tests::octahedron_points();
        let tris: Vec<[u32; 3]> = crate::tetrahedralize(&pts).unwrap().hull_faces().collect();
        assert_eq!(tris.len(), 8);
        pts.push([0.1, -0.05, 0.02]);
        let dt = Delaunay3::from_points(&pts).unwrap();
        let mut cm = Journaled::new(dt);
        assert_eq!(used_steiner(&cm, 6), 1);
        let st = state(6, &tris);
        assert_eq!(st.prune_interior(&mut cm, 6), 1);
        assert_valid(&cm, &tris);
        assert_eq!(used_steiner(&cm, 6), 0);
        let finite =
            cm.m.tv
                .iter()
                .filter(|tv| tv[0] != DEAD && !tv.contains(&INF))
                .count();
        assert_eq!(finite, 4);
        // Nothing left to remove: a second call is a no-op.
        assert_eq!(st.prune_interior(&mut cm, 6), 0);
    }

    /// Thin boxes recovered by the fallback (surface points pulled off):
    /// the pruning keeps a valid mesh with every input triangle a face,
    /// and the count it returns is the drop in used Steiner points.
    #[test]
    fn pruning_after_the_fallback_keeps_the_surface() {
        for (w, d, h) in [(10.0, 1.0, 0.001), (1.0, 1.0, 1e-6), (100.0, 0.01, 1.0)] {
            let (pts, tris) = cuboid(w, d, h);
            let st = state(pts.len(), &tris);
            let (st2, mut cm, _) = st.preserve_fallback(&pts).unwrap();
            let before = used_steiner(&cm, pts.len());
            let k = st2.prune_interior(&mut cm, pts.len());
            assert_valid(&cm, &tris);
            assert_eq!(used_steiner(&cm, pts.len()), before - k);
        }
    }
}
