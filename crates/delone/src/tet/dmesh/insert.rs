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

/// The protected faces (sorted triples) and edges (sorted pairs) of an
/// insertion.
type Keep<'k> = (&'k dyn Fn([u32; 3]) -> bool, &'k dyn Fn(u32, u32) -> bool);

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
        // unprotected faces, no ghosts. `local`: slot -> index in the grown
        // cells (the required cells first).
        let mut cells: Vec<u32> = required.clone();
        let mut local: IdMap<u32, u32> = IdMap::default();
        for (i, &t) in cells.iter().enumerate() {
            local.insert(t, i as u32);
        }
        let mut i = 0;
        while i < cells.len() && cells.len() < MAX_CAVITY {
            let t = cells[i];
            i += 1;
            let tv = tvs(t);
            for f in 0..4 {
                let n = m.across(t, f);
                if local.contains_key(&n) || !m.alive(n) {
                    continue;
                }
                let nv = tvs(n);
                if nv.contains(&INF) || keep_face(fkey(face(tv, f))) {
                    continue;
                }
                // Positive cells have `orient3d < 0`: `insphere` is then
                // negative for a point strictly inside.
                if insphere(g(nv[0]), g(nv[1]), g(nv[2]), g(nv[3]), g(p)) < 0.0 {
                    local.insert(n, cells.len() as u32);
                    cells.push(n);
                }
            }
        }
        // The shrinking works on local indices: per grown cell its
        // neighbours (`NO`: not grown), whether it is in the cavity now,
        // and per face the verdicts that do not change while it shrinks
        // (0: not known yet, 1: no, 2: yes): the face is protected, the
        // cone cell on it is not strictly positive.
        const NO: u32 = u32::MAX;
        let nreq = required.len();
        let nbr: Vec<[u32; 4]> = cells
            .iter()
            .map(|&t| [0, 1, 2, 3].map(|f| local.get(&m.across(t, f)).copied().unwrap_or(NO)))
            .collect();
        let mut live = vec![true; cells.len()];
        let mut kept = vec![[0u8; 4]; cells.len()];
        let mut flat = vec![[0u8; 4]; cells.len()];
        let mut dropped = vec![false; cells.len()];
        let mut cav: Vec<u32> = (0..cells.len() as u32).collect();
        let is_in = |live: &[bool], j: u32| j != NO && live[j as usize];
        loop {
            let mut drop: Vec<u32> = Vec::new();
            let mut mark = |i: u32, drop: &mut Vec<u32>| {
                if !std::mem::replace(&mut dropped[i as usize], true) {
                    drop.push(i);
                }
            };
            for &i in &cav {
                let tv = tvs(cells[i as usize]);
                for f in 0..4 {
                    let j = nbr[i as usize][f];
                    if is_in(&live, j) {
                        let k = &mut kept[i as usize][f];
                        if *k == 0 {
                            *k = 1 + keep_face(fkey(face(tv, f))) as u8;
                        }
                        if *k == 2 {
                            mark(i, &mut drop);
                            mark(j, &mut drop);
                        }
                        continue;
                    }
                    let cone = &mut flat[i as usize][f];
                    if *cone == 0 {
                        let mut q = tv;
                        q[f] = p;
                        let bad = !q.contains(&INF) && {
                            let [a, b, c, d] = q.map(g);
                            orient3d(a, b, c, d) >= 0.0
                        };
                        *cone = 1 + bad as u8;
                    }
                    if *cone == 2 {
                        mark(i, &mut drop);
                    }
                }
            }
            // Interior protected edges and vertices are looked at once
            // every boundary face is seen (a cavity whose boundary faces
            // are all strictly seen from `p` inside it is star-shaped: its
            // boundary is a sphere, every edge on two boundary faces).
            if drop.is_empty() {
                // Boundary faces: the edges and vertices on them.
                let mut bedges: IdMap<(u32, u32), u32> = IdMap::default();
                let mut bverts: IdSet<u32> = IdSet::default();
                for &i in &cav {
                    let tv = tvs(cells[i as usize]);
                    for f in 0..4 {
                        if is_in(&live, nbr[i as usize][f]) {
                            continue;
                        }
                        let fv = face(tv, f);
                        for k in 0..3 {
                            *bedges.entry(ekey(fv[k], fv[(k + 1) % 3])).or_default() += 1;
                        }
                        bverts.extend(fv);
                    }
                }
                let mut pinched = false;
                for &i in &cav {
                    let tv = tvs(cells[i as usize]);
                    if tv.iter().any(|w| !bverts.contains(w)) {
                        mark(i, &mut drop);
                    }
                    for (a, b) in EDGES {
                        let e = ekey(tv[a], tv[b]);
                        match bedges.get(&e) {
                            None if e.1 != INF && keep_edge(e.0, e.1) => {
                                mark(i, &mut drop);
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
            for &i in &drop {
                dropped[i as usize] = false;
            }
            let is_req = |i: &u32| (*i as usize) < nreq;
            if drop.iter().any(is_req) {
                // What the required cells need dropped is refused: the
                // required cells alone, else nothing.
                if cav.len() == nreq {
                    return None;
                }
                drop.retain(|i| !is_req(i));
                if drop.is_empty() {
                    cav = (0..nreq as u32).collect();
                    live.fill(false);
                    live[..nreq].fill(true);
                    continue;
                }
            }
            for &i in &drop {
                live[i as usize] = false;
            }
            // Only the part connected to the required cells stays.
            let mut seen = vec![false; cells.len()];
            seen[..nreq].fill(true);
            let mut keep: Vec<u32> = (0..nreq as u32).collect();
            let mut j = 0;
            while j < keep.len() {
                let i = keep[j] as usize;
                j += 1;
                for &n in &nbr[i] {
                    if is_in(&live, n) && !std::mem::replace(&mut seen[n as usize], true) {
                        keep.push(n);
                    }
                }
            }
            live = seen;
            cav = keep;
        }
        let mut new: Vec<[u32; 4]> = Vec::with_capacity(2 * cav.len() + 4);
        for &i in &cav {
            let tv = tvs(cells[i as usize]);
            for f in 0..4 {
                if !is_in(&live, nbr[i as usize][f]) {
                    let mut q = tv;
                    q[f] = p;
                    new.push(q);
                }
            }
        }
        let cav: Vec<u32> = cav.iter().map(|&i| cells[i as usize]).collect();
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
    /// no finite cell holds `p` (a walk, else a scan of the cells), when `p`
    /// is on a vertex, on a protected face or edge, or on an edge whose
    /// ring has a ghost or more than [`super::journal::MAX_RING`] cells.
    fn cells_holding(
        &self,
        p: u32,
        start: u32,
        keep_face: &dyn Fn([u32; 3]) -> bool,
        keep_edge: &dyn Fn(u32, u32) -> bool,
    ) -> Option<Vec<u32>> {
        self.cells_holding_within(p, start, (keep_face, keep_edge), WALK_STEPS)
    }

    /// [`Self::cells_holding`] with a walk of at most `steps` steps.
    fn cells_holding_within(
        &self,
        p: u32,
        start: u32,
        (keep_face, keep_edge): Keep<'_>,
        steps: usize,
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
        // The walk: leave through a face `p` is strictly beyond, the first
        // from a rotating start (a walk in a mesh that is not Delaunay
        // could otherwise circle); it ends in a cell with no such face.
        let walk = || -> Option<(u32, [f64; 4])> {
            let mut t = start;
            for step in 0..steps {
                if !m.alive(t) || m.tv[t as usize].contains(&INF) {
                    return None;
                }
                let s = signs(m.tv[t as usize]);
                match (0..4).map(|k| (k + step) % 4).find(|&i| s[i] > 0.0) {
                    Some(i) => t = m.across(t, i),
                    None => return Some((t, s)),
                }
            }
            None
        };
        // Where the flips left cells a walk cannot cross towards `p` (it
        // circles, or leaves the hull past a flat hull facet), the first
        // finite cell in slot order whose closure holds `p`.
        let scan = || {
            (0..m.tv.len() as u32)
                .filter(|&t| m.alive(t) && !m.tv[t as usize].contains(&INF))
                .map(|t| (t, signs(m.tv[t as usize])))
                .find(|(_, s)| s.iter().all(|&x| x <= 0.0))
        };
        let (t, s) = walk().or_else(scan)?;
        let tv = m.tv[t as usize];
        let zeros: Vec<usize> = (0..4).filter(|&i| s[i] == 0.0).collect();
        match zeros[..] {
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
        }
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

    /// A point the walk does not reach (no step at all here; in a flipped
    /// mesh the walk can circle) is found by the scan of the cells: the
    /// same cells as the walk finds, inside a cell, on a hull face and near
    /// an edge's midpoint; a point on a hull edge, a vertex and a point
    /// outside the hull are refused both ways.
    #[test]
    fn the_scan_finds_what_the_walk_finds() {
        let pts = cloud(60);
        let mut m = Journaled::new(Delaunay3::from_points(&pts).unwrap());
        let edges = edges_of(&m);
        let (a, b) = edges[edges.len() / 2];
        let (pa, pb) = (m.pts()[a as usize], m.pts()[b as usize]);
        let c = m.m.tv[m
            .star_find(a, |x| !m.m.tv[x as usize].contains(&INF))
            .unwrap() as usize];
        let centre = [0, 1, 2].map(|k| c.iter().map(|&w| pts[w as usize][k]).sum::<f64>() / 4.0);
        // Expected cell counts (`None`: any; 0: refused).
        let queries = [
            (centre, Some(1)),
            // Inside a hull triangle of the cube's bottom (its diagonals
            // are x = y and x + y = 1): a cell and the ghost on it.
            ([0.25, 0.5, 0.0], Some(2)),
            // On a hull edge: refused.
            ([0.5, 0.0, 0.0], Some(0)),
            ([0, 1, 2].map(|k| 0.5 * (pa[k] + pb[k])), None),
            (pa, Some(0)),
            ([2.0, 0.5, 0.5], Some(0)),
        ];
        let no_f = |_: [u32; 3]| false;
        let no_e = |_: u32, _: u32| false;
        let far = (0..m.m.tv.len() as u32)
            .rev()
            .find(|&x| m.m.alive(x) && !m.m.tv[x as usize].contains(&INF))
            .unwrap();
        for (q, count) in queries {
            let id = m.pts().len() as u32;
            m.push_point(q);
            let walked = m.cells_holding_within(id, far, (&no_f, &no_e), WALK_STEPS);
            let scanned = m.cells_holding_within(id, far, (&no_f, &no_e), 0);
            let sorted = |c: Option<Vec<u32>>| {
                c.map(|mut c| {
                    c.sort_unstable();
                    c
                })
            };
            assert_eq!(sorted(walked.clone()), sorted(scanned), "{q:?}");
            match count {
                Some(0) => assert!(walked.is_none(), "{q:?}"),
                Some(n) => assert_eq!(walked.map(|c| c.len()), Some(n), "{q:?}"),
                None => assert!(walked.is_some(), "{q:?}"),
            }
        }
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
