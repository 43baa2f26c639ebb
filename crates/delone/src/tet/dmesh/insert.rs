//! Point insertion into a [`Journaled`] mesh as the flips left it:
//! constrained Bowyer–Watson.
//!
//! [`Journaled::insert_constrained`] puts a new point into the mesh without
//! going back to the Delaunay tetrahedralization: the cavity is grown from
//! the cells holding the point across the faces that are not protected,
//! into the cells whose circumsphere holds the point strictly, then shrunk
//! until the cone from the point over its boundary is a valid
//! replacement:
//!
//! * no protected face inside the cavity (between two of its cells), no
//!   protected edge inside it (every cell around the edge in the cavity),
//!   no vertex inside it (every vertex of its cells on a boundary face);
//! * every boundary face strictly seen from the point (each cone cell
//!   strictly positive, exact `orient3d`), every boundary edge in exactly
//!   two boundary faces, the cavity connected to the cells holding the
//!   point.
//!
//! A cell violating one of these is dropped (never one holding the point);
//! dropping repeats until nothing is violated, so the cavity shrinks to at
//! worst the cells holding the point, whose cone is always valid. Ghost
//! cells enter the cavity only when the point is strictly inside a hull
//! face (the ghost cell on it then holds the point: its cone splits the
//! hull face at the point); a point on a hull edge is refused, as is a
//! point on a protected face or edge or on a vertex. The
//! replacement is one logged operation ([`Journaled::replace`]): rollback
//! undoes it, and a replay re-applies it only where the point is not a
//! vertex yet (a region holding a vertex strictly inside is no set of
//! cells of a mesh having that vertex).

use delone_predicates::{insphere, orient3d};

use super::journal::Journaled;
use crate::geom::ids::{IdMap, IdSet};
use crate::tet::local::{ekey, face, fkey, EDGES, INF};

/// Most cells of a cavity of [`Journaled::insert_constrained`] (beyond it
/// the growth stops; the shrinking still applies).
const MAX_CAVITY: usize = 2048;

/// Most steps of the walk locating the point.
const WALK_STEPS: usize = 1 << 14;

impl Journaled<'_> {
    /// Inserts point `p` (already pushed, [`Journaled::push_point`], and in
    /// no cell) by the constrained Bowyer–Watson of the module notes,
    /// locating it by a walk from slot `start`; `keep_face` (sorted
    /// triple) and `keep_edge` (sorted pair) name the protected items.
    /// Returns the new slots, or `None` with nothing changed (see the
    /// module notes for when).
    pub(crate) fn insert_constrained(
        &mut self,
        p: u32,
        start: u32,
        keep_face: &dyn Fn([u32; 3]) -> bool,
        keep_edge: &dyn Fn(u32, u32) -> bool,
    ) -> Option<Vec<u32>> {
        let required = self.cells_holding(p, start, keep_face, keep_edge)?;
        let pts = self.pts();
        let g = |w: u32| &pts[w as usize];
        let m = &self.m;
        let tvs = |t: u32| m.tv[t as usize];
        // Growth: cells whose circumsphere holds `p` strictly, across
        // unprotected faces, no ghosts.
        let mut cav: Vec<u32> = required.clone();
        let mut inside: IdSet<u32> = cav.iter().copied().collect();
        let mut i = 0;
        while i < cav.len() && cav.len() < MAX_CAVITY {
            let t = cav[i];
            i += 1;
            let tv = tvs(t);
            for f in 0..4 {
                let n = m.across(t, f);
                if inside.contains(&n) || !m.alive(n) {
                    continue;
                }
                let nv = tvs(n);
                if nv.contains(&INF) || keep_face(fkey(face(tv, f))) {
                    continue;
                }
                // Positive cells have `orient3d < 0`: `insphere` is then
                // negative for a point strictly inside.
                if insphere(g(nv[0]), g(nv[1]), g(nv[2]), g(nv[3]), g(p)) < 0.0 {
                    inside.insert(n);
                    cav.push(n);
                }
            }
        }
        let req: IdSet<u32> = required.iter().copied().collect();
        // Shrinking.
        loop {
            let inside: IdSet<u32> = cav.iter().copied().collect();
            let mut drop: IdSet<u32> = IdSet::default();
            // Boundary faces, and the edges and vertices on them.
            let mut bedges: IdMap<(u32, u32), u32> = IdMap::default();
            let mut bverts: IdSet<u32> = IdSet::default();
            for &t in &cav {
                let tv = tvs(t);
                for f in 0..4 {
                    let n = m.across(t, f);
                    let fv = face(tv, f);
                    if inside.contains(&n) {
                        if keep_face(fkey(fv)) {
                            drop.insert(t);
                            drop.insert(n);
                        }
                        continue;
                    }
                    let mut q = tv;
                    q[f] = p;
                    if !q.contains(&INF) {
                        let [a, b, c, d] = q.map(g);
                        if orient3d(a, b, c, d) >= 0.0 {
                            drop.insert(t);
                        }
                    }
                    for k in 0..3 {
                        *bedges.entry(ekey(fv[k], fv[(k + 1) % 3])).or_default() += 1;
                    }
                    bverts.extend(fv);
                }
            }
            // Interior protected edges and vertices are looked at once
            // every boundary face is seen (a cavity whose boundary faces
            // are all strictly seen from `p` inside it is star-shaped: its
            // boundary is a sphere, every edge on two boundary faces).
            let mut pinched = false;
            if drop.is_empty() {
                for &t in &cav {
                    let tv = tvs(t);
                    if tv.iter().any(|w| !bverts.contains(w)) {
                        drop.insert(t);
                    }
                    for (a, b) in EDGES {
                        let e = ekey(tv[a], tv[b]);
                        match bedges.get(&e) {
                            None if e.1 != INF && keep_edge(e.0, e.1) => {
                                drop.insert(t);
                            }
                            Some(&k) if k != 2 => pinched = true,
                            _ => {}
                        }
                    }
                }
                if drop.is_empty() && pinched {
                    return None;
                }
            }
            if drop.is_empty() {
                break;
            }
            if drop.iter().any(|t| req.contains(t)) {
                // What the required cells need dropped is refused: the
                // required cells alone, else nothing.
                if cav.len() == required.len() {
                    return None;
                }
                drop.retain(|t| !req.contains(t));
                if drop.is_empty() {
                    cav.clone_from(&required);
                    continue;
                }
            }
            cav.retain(|t| !drop.contains(t));
            // Only the part connected to the required cells stays.
            let left: IdSet<u32> = cav.iter().copied().collect();
            let mut keep: Vec<u32> = required.clone();
            let mut seen: IdSet<u32> = keep.iter().copied().collect();
            let mut j = 0;
            while j < keep.len() {
                let t = keep[j];
                j += 1;
                for f in 0..4 {
                    let n = m.across(t, f);
                    if left.contains(&n) && seen.insert(n) {
                        keep.push(n);
                    }
                }
            }
            cav = keep;
        }
        let mut new: Vec<[u32; 4]> = Vec::with_capacity(2 * cav.len() + 4);
        let inside: IdSet<u32> = cav.iter().copied().collect();
        for &t in &cav {
            let tv = tvs(t);
            for f in 0..4 {
                if !inside.contains(&m.across(t, f)) {
                    let mut q = tv;
                    q[f] = p;
                    new.push(q);
                }
            }
        }
        Some(self.replace(&cav, &new))
    }

    /// The cells whose closure holds point `p`, found by a walk from
    /// slot `start`: one cell, the two cells of a face (the second a ghost
    /// when the face is on the hull), or the ring of an edge. `None` when
    /// the walk meets a ghost or does not end, when `p`
    /// is on a vertex, on a protected face or edge, or on an edge whose
    /// ring has a ghost or more than [`super::journal::MAX_RING`] cells.
    fn cells_holding(
        &self,
        p: u32,
        start: u32,
        keep_face: &dyn Fn([u32; 3]) -> bool,
        keep_edge: &dyn Fn(u32, u32) -> bool,
    ) -> Option<Vec<u32>> {
        let pts = self.pts();
        let g = |w: u32| &pts[w as usize];
        let m = &self.m;
        // Per face `i` of positive `tv`: the orientation of `tv` with
        // vertex `i` replaced by `p` (negative: `p` strictly on `tv[i]`'s
        // side of face `i`; positive: strictly beyond).
        let signs = |tv: [u32; 4]| -> [f64; 4] {
            [0, 1, 2, 3].map(|i| {
                let mut q = tv;
                q[i] = p;
                orient3d(g(q[0]), g(q[1]), g(q[2]), g(q[3]))
            })
        };
        let mut t = start;
        for step in 0..WALK_STEPS {
            if !m.alive(t) {
                return None;
            }
            let tv = m.tv[t as usize];
            if tv.contains(&INF) {
                return None;
            }
            let s = signs(tv);
            // Leave through a face `p` is strictly beyond, the first from
            // a rotating start (a walk in a mesh that is not Delaunay could
            // otherwise circle).
            if let Some(i) = (0..4).map(|k| (k + step) % 4).find(|&i| s[i] > 0.0) {
                t = m.across(t, i);
                continue;
            }
            let zeros: Vec<usize> = (0..4).filter(|&i| s[i] == 0.0).collect();
            return match zeros[..] {
                [] => Some(vec![t]),
                [i] => {
                    let n = m.across(t, i);
                    let fv = face(tv, i);
                    // (`n` is a ghost when `p` is on a hull face: its
                    // cone is the hull face split at `p`, valid as `p` is
                    // strictly inside it.)
                    (m.alive(n) && !keep_face(fkey(fv))).then(|| vec![t, n])
                }
                [i, j] => {
                    let e: Vec<u32> = (0..4).filter(|&k| k != i && k != j).map(|k| tv[k]).collect();
                    if keep_edge(e[0].min(e[1]), e[0].max(e[1])) {
                        return None;
                    }
                    let (tets, _) = self.edge_ring(t, e[0], e[1])?;
                    Some(tets)
                }
                _ => None,
            };
        }
        None
    }
}
