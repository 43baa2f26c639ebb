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
    /// Pushes `q` as the next point and inserts it by
    /// [`Journaled::insert_constrained`], the walk starting at a finite
    /// cell of vertex `near`. `None` (the point stays pushed, in no cell)
    /// when `near` has no finite cell or the insertion is refused.
    pub(crate) fn push_and_insert(
        &mut self,
        q: [f64; 3],
        near: u32,
        keep_face: &dyn Fn([u32; 3]) -> bool,
        keep_edge: &dyn Fn(u32, u32) -> bool,
    ) -> Option<Vec<u32>> {
        let id = self.pts().len() as u32;
        self.push_point(q);
        let start = self.star_find(near, |x| !self.m.tv[x as usize].contains(&INF))?;
        self.insert_constrained(id, start, keep_face, keep_edge)
    }

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
        // Each cell adjacent to an earlier one (the journal finds them so
        // for rollback and replay): breadth first over the faces at `p`.
        let mut by_face: IdMap<[u32; 3], Vec<usize>> = IdMap::default();
        for (i, q) in new.iter().enumerate() {
            for f in 0..4 {
                let k = fkey(face(*q, f));
                if k.contains(&p) {
                    by_face.entry(k).or_default().push(i);
                }
            }
        }
        let mut order: Vec<usize> = vec![0];
        let mut seen = vec![false; new.len()];
        seen[0] = true;
        let mut j = 0;
        while j < order.len() {
            let q = new[order[j]];
            j += 1;
            for f in 0..4 {
                let k = fkey(face(q, f));
                for &i in by_face.get(&k).into_iter().flatten() {
                    if !std::mem::replace(&mut seen[i], true) {
                        order.push(i);
                    }
                }
            }
        }
        if order.len() != new.len() {
            return None;
        }
        let new: Vec<[u32; 4]> = order.into_iter().map(|i| new[i]).collect();
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
                    let e: Vec<u32> = (0..4)
                        .filter(|&k| k != i && k != j)
                        .map(|k| tv[k])
                        .collect();
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tet::local::DEAD;
    use crate::tet::Delaunay3;

    /// `n` points of a 4 x 4 x 4 grid jittered by irrational strides, and
    /// the cube's corners (a hull with coplanar faces).
    fn cloud(n: usize) -> Vec<[f64; 3]> {
        let mut p: Vec<[f64; 3]> = (0..n)
            .map(|i| {
                let f = |a: f64| (i as f64 * a).fract();
                [
                    0.1 + 0.8 * f(0.618_034),
                    0.1 + 0.8 * f(0.414_213_5),
                    0.1 + 0.8 * f(0.732_050_8),
                ]
            })
            .collect();
        for i in 0..8 {
            p.push([(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64]);
        }
        p
    }

    fn edges_of(m: &Journaled<'_>) -> Vec<(u32, u32)> {
        let mut out: Vec<(u32, u32)> =
            m.m.tv
                .iter()
                .filter(|tv| tv[0] != DEAD && !tv.contains(&INF))
                .flat_map(|tv| EDGES.map(|(i, j)| ekey(tv[i], tv[j])))
                .collect();
        out.sort_unstable();
        out.dedup();
        out
    }

    /// Points inside cells, on faces, on edges and on hull faces go in;
    /// the mesh stays valid ([`crate::tet::dmesh::DomainMesh::check`])
    /// after every insertion, every protected edge and face stays, and a
    /// rollback gives the mesh back.
    #[test]
    fn constrained_insertions_keep_the_mesh_and_the_protected_items() {
        let pts = cloud(60);
        let mut m = Journaled::new(Delaunay3::from_points(&pts).unwrap());
        m.start_log();
        let before = m.m.tv.clone();
        // Every third edge is protected, with the faces on two of them.
        let prot_edges: IdSet<(u32, u32)> = edges_of(&m).into_iter().step_by(3).collect();
        let mut prot_faces: IdSet<[u32; 3]> = IdSet::default();
        for tv in
            m.m.tv
                .iter()
                .filter(|tv| tv[0] != DEAD && !tv.contains(&INF))
        {
            for f in 0..4 {
                let k = fkey(face(*tv, f));
                let on = |a: u32, b: u32| prot_edges.contains(&ekey(a, b));
                if on(k[0], k[1]) && on(k[1], k[2]) {
                    prot_faces.insert(k);
                }
            }
        }
        let mut placed = 0;
        let edges = edges_of(&m);
        for (i, &(a, b)) in edges.iter().enumerate().step_by(7) {
            let (pa, pb) = (m.pts()[a as usize], m.pts()[b as usize]);
            let p = match i % 3 {
                // An edge's midpoint (on the edge, or near it).
                0 => [0, 1, 2].map(|k| 0.5 * (pa[k] + pb[k])),
                // A point off the edge, inside some cell or on a face.
                1 => [0, 1, 2].map(|k| 0.3 * pa[k] + 0.7 * pb[k] + 0.01),
                _ => [0, 1, 2].map(|k| 0.25 * pa[k] + 0.75 * pb[k]),
            };
            if !(0.0..=1.0).contains(&p[0]) || !(0.0..=1.0).contains(&p[1]) {
                continue;
            }
            let id = m.pts().len() as u32;
            m.push_point(p);
            let start = m
                .star_find(a, |x| !m.m.tv[x as usize].contains(&INF))
                .unwrap();
            let kf = |f: [u32; 3]| prot_faces.contains(&f);
            let ke = |x: u32, y: u32| prot_edges.contains(&(x, y));
            if let Some(new) = m.insert_constrained(id, start, &kf, &ke) {
                placed += 1;
                assert!(new.iter().all(|&t| m.m.tv[t as usize].contains(&id)));
                m.m.check(m.pts()).unwrap();
                let now: IdSet<(u32, u32)> = edges_of(&m).into_iter().collect();
                for e in &prot_edges {
                    assert!(now.contains(e), "protected edge {e:?} lost");
                }
                for f in &prot_faces {
                    assert!(m.find_face(f[0], f[1], f[2]).is_some(), "face {f:?} lost");
                }
            } else {
                // Refused: nothing changed but the point list; the
                // mesh keeps no cell at it.
                assert!(m.m.slot_of_vertex(id).is_none());
                m.m.check(m.pts()).unwrap();
            }
        }
        assert!(placed >= 5, "{placed} points placed");
        // A point on a hull face (the cube's bottom) goes in too.
        let id = m.pts().len() as u32;
        m.push_point([0.37, 0.41, 0.0]);
        let corner = 60; // (0, 0, 0)
        let start = m
            .star_find(corner, |x| !m.m.tv[x as usize].contains(&INF))
            .unwrap();
        assert!(m
            .insert_constrained(id, start, &|_| false, &|_, _| false)
            .is_some());
        m.m.check(m.pts()).unwrap();
        m.rollback(0);
        m.m.check(m.pts()).unwrap();
        let mut a: Vec<[u32; 4]> = before.into_iter().filter(|t| t[0] != DEAD).collect();
        let mut b: Vec<[u32; 4]> = m.m.tv.iter().copied().filter(|t| t[0] != DEAD).collect();
        for t in a.iter_mut().chain(b.iter_mut()) {
            t.sort_unstable();
        }
        a.sort_unstable();
        b.sort_unstable();
        assert_eq!(a, b);
    }
}
