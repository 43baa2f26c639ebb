//! Recovery of a missing input edge together with the input triangles
//! around it, as one **patch** (`-Y`).
//!
//! When flips cannot make an input edge `a b` an edge of the mesh, the
//! triangles using it are missing too. The patch is the connected set of
//! missing input triangles reached from `a b` across missing input edges
//! (at most [`MAX_PATCH`]); every edge on its border is then a mesh edge.
//! The cavity is every tetrahedron meeting the patch: those with an edge
//! crossing the interior of a patch triangle (exact `place::crosses`)
//! and those meeting a missing edge ([`segment_cavity`], a superset).
//!
//! **Two sides.** The boundary faces of the cavity form a closed surface
//! through which the patch's border runs. Cut along the patch's edges
//! (flood fill across boundary faces, never across an edge of the patch),
//! every piece that touches the border says on which side of the patch it
//! lies by orientation alone: a boundary face (oriented inward) that uses
//! the border edge `p → q` closes with the patch triangle that uses
//! `q → p`. No plane and no geometric side test is involved, so patches
//! that fold (an edge with a reflex dihedral angle, nearly coplanar
//! triangles) are handled like flat ones; a piece touching no border edge,
//! or with conflicting votes, makes the attempt fail (nothing assumed).
//!
//! **Filling** each side (its pieces plus the patch, consistently
//! oriented) is the same as for a single triangle: a cone from one of its
//! vertices, else from an exact point strictly inside its kernel, else the
//! side grows by the tetrahedra behind the faces the best point found does
//! not see (bounded, see the parent module). Growing needs no side test: a
//! tetrahedron outside the cavity does not meet the patch. The parent's
//! exact validation then decides: all new tetrahedra positive and tiling
//! exactly the removed region, every vertex, protected edge and face
//! kept, new points off the surface. On success every patch triangle is a
//! face and `a b` an edge.
//!
//! Why this recovers edges the single-edge cavity cannot: a cone from `a`
//! or `b` must see the whole cavity around the segment, and a kernel point
//! does not put `a b` in the mesh at all. Filling the two sides of the
//! *surface* instead makes `a b` an edge of the patch triangles, and the
//! kernel of each side is not empty near the patch when the cavity is
//! small (at a missing edge, the open half-spaces of the two triangles on
//! one side always meet, whatever the dihedral angle), so a kernel point
//! exists in the cases where growth keeps the cavity local.

use super::super::place;
use super::super::State;
use super::{boundary_of, facet_cavity, fill_side, segment_cavity, Fill, Guard, Memo, Region};
use crate::geom::ids::IdMap;
use crate::tet::dmesh::journal::Journaled;
use crate::tet::dmesh::ring::{self, RingEnd};
use crate::tet::local::{ekey, fkey};
use crate::tet::local::{DEAD, INF};

/// Most input triangles in a patch.
const MAX_PATCH: usize = 4096;

impl State {
    /// The patch of missing triangles around missing input edge `e`
    /// (index into the surface's edges), consistently oriented (from the
    /// first triangle's input orientation); `None` when it is too large,
    /// not orientable, or its border is not made of mesh edges.
    pub(super) fn patch_of(&self, cm: &Journaled<'_>, e: usize) -> Option<Vec<[u32; 3]>> {
        let surf = &self.surf;
        let missing_edge = |k: usize| {
            let [a, b] = surf.edges[k];
            cm.find_edge(a, b).is_none()
        };
        let mut seen: Vec<u32> = Vec::new();
        let mut stack: Vec<u32> = surf.edge_tris[e].to_vec();
        stack.sort_unstable();
        let mut out: Vec<u32> = Vec::new();
        while let Some(t) = stack.pop() {
            if seen.contains(&t) {
                continue;
            }
            seen.push(t);
            out.push(t);
            if out.len() > MAX_PATCH {
                return None;
            }
            for &k in &surf.tri_edges[t as usize] {
                if missing_edge(k as usize) {
                    for &n in &surf.edge_tris[k as usize] {
                        if !seen.contains(&n) {
                            stack.push(n);
                        }
                    }
                } else if k as usize == e {
                    return None;
                }
            }
        }
        out.sort_unstable();
        // Consistent orientation by a walk across shared edges.
        let tris: Vec<[u32; 3]> = out.iter().map(|&t| surf.tris[t as usize]).collect();
        let mut or: Vec<Option<[u32; 3]>> = vec![None; tris.len()];
        or[0] = Some(tris[0]);
        let mut queue = vec![0usize];
        while let Some(i) = queue.pop() {
            let ti = or[i]?;
            for (j, &tj) in tris.iter().enumerate() {
                let shared: Vec<u32> = ti.iter().copied().filter(|w| tj.contains(w)).collect();
                if j == i || shared.len() != 2 {
                    continue;
                }
                // `ti` uses p → q; a consistent `tj` uses q → p.
                let (p, q) = directed(ti, shared[0], shared[1]);
                let want = if directed(tj, p, q) == (q, p) {
                    tj
                } else {
                    [tj[0], tj[2], tj[1]]
                };
                match or[j] {
                    None => {
                        or[j] = Some(want);
                        queue.push(j);
                    }
                    Some(have) if have != want => return None,
                    Some(_) => {}
                }
            }
        }
        or.into_iter().collect()
    }

    /// Recovers missing input edge `e` with its patch of missing triangles
    /// by filling the two sides of the patch (module documentation).
    /// `Some((points added, the patch))` on success (every patch triangle
    /// a face).
    pub(super) fn patch_by_cavity(
        &self,
        cm: &mut Journaled<'_>,
        e: usize,
        prot: &Guard,
        steiner: bool,
        memo: &mut Memo,
    ) -> Option<(usize, Vec<[u32; 3]>)> {
        let patch = self.patch_of(cm, e)?;
        memo.sync(cm);
        let mut key: Vec<[u32; 3]> = patch.iter().map(|t| fkey(*t)).collect();
        key.sort_unstable();
        let key = (steiner, key);
        if memo.failed.contains(&key) {
            return None;
        }
        let r = self.patch_attempt(cm, patch, prot, steiner);
        if r.is_none() {
            memo.failed.insert(key);
        }
        r
    }

    /// [`State::patch_by_cavity`] on the patch `patch` (not known to
    /// fail).
    fn patch_attempt(
        &self,
        cm: &mut Journaled<'_>,
        patch: Vec<[u32; 3]>,
        prot: &Guard,
        steiner: bool,
    ) -> Option<(usize, Vec<[u32; 3]>)> {
        // Flat on the convex hull: the hull faces give way to the patch.
        if let Some(flat) = self.flat_hull(cm, &patch) {
            let mut all = vec![patch.clone()];
            if let Some(k) = self.hull_patch(cm, &all, prot, false, None) {
                return Some((k, patch));
            }
            // With its flat hull neighbours at once: two hull quads
            // meeting at a hull edge may form a Schönhardt prism
            // together, which a joint replacement avoids.
            all.extend(self.flat_neighbours(cm, &flat));
            if all.len() > 1 {
                if let Some(k) = self.hull_patch(cm, &all, prot, false, None) {
                    return Some((k, all.concat()));
                }
            }
            if steiner {
                if let Some(k) = self.hull_patch(cm, &all[..1], prot, true, None) {
                    return Some((k, patch));
                }
            }
        }
        // Edge uses: border edges (one triangle) and interior ones.
        let mut uses: IdMap<(u32, u32), Vec<(u32, u32)>> = IdMap::default();
        for t in &patch {
            for i in 0..3 {
                let (p, q) = (t[i], t[(i + 1) % 3]);
                uses.entry(ekey(p, q)).or_default().push((p, q));
            }
        }
        let mut set: Vec<u32> = Vec::new();
        for t in &patch {
            set.extend(self.counted(facet_cavity(cm, *t)));
        }
        let mut keys: Vec<(u32, u32)> = uses.keys().copied().collect();
        keys.sort_unstable();
        for &(p, q) in &keys {
            if cm.find_edge(p, q).is_none() {
                set.extend(self.counted(segment_cavity(cm, p, q)));
            }
        }
        set.sort_unstable();
        set.dedup();
        if set.is_empty() {
            return None;
        }
        let bnd = boundary_of(cm, &set);
        // Pieces of the cavity boundary cut along the patch edges.
        let n = bnd.faces.len();
        let mut by_edge: IdMap<(u32, u32), Vec<usize>> = IdMap::default();
        for (i, f) in bnd.faces.iter().enumerate() {
            for k in 0..3 {
                let key = ekey(f.0[k], f.0[(k + 1) % 3]);
                if !uses.contains_key(&key) {
                    by_edge.entry(key).or_default().push(i);
                }
            }
        }
        let mut piece = vec![usize::MAX; n];
        let mut pieces = 0;
        for s in 0..n {
            if piece[s] != usize::MAX {
                continue;
            }
            piece[s] = pieces;
            let mut stack = vec![s];
            while let Some(i) = stack.pop() {
                let f = bnd.faces[i].0;
                for k in 0..3 {
                    let key = ekey(f[k], f[(k + 1) % 3]);
                    if let Some(nb) = by_edge.get(&key) {
                        for &j in nb {
                            if piece[j] == usize::MAX {
                                piece[j] = pieces;
                                stack.push(j);
                            }
                        }
                    }
                }
            }
            pieces += 1;
        }
        // Votes: +1 when the piece closes with the patch as oriented. At
        // a border edge `p q` only the two boundary faces that enclose the
        // patch triangle in the ring of tetrahedra around `p q` vote (the
        // cavity may touch `p q` again elsewhere in the ring).
        let at: IdMap<(u32, [u32; 3]), usize> = bnd
            .faces
            .iter()
            .enumerate()
            .map(|(i, f)| ((f.1, fkey(f.0)), i))
            .collect();
        let mut vote = vec![0i8; pieces];
        for t in &patch {
            for k in 0..3 {
                let (p, q) = (t[k], t[(k + 1) % 3]);
                if uses.get(&ekey(p, q)).map_or(0, Vec::len) != 1 {
                    continue;
                }
                let r = t[(k + 2) % 3];
                let exits = ring_exits(cm, &set, p, q, r);
                let mut voters: Vec<usize> = Vec::new();
                match exits {
                    Some(ex) => {
                        for (owner, x) in ex {
                            voters.push(*at.get(&(owner, fkey([p, q, x])))?);
                        }
                    }
                    // No ring (a ghost, or too many tetrahedra): every
                    // boundary face at `p q` votes.
                    None => voters.extend(
                        bnd.faces
                            .iter()
                            .enumerate()
                            .filter(|(_, f)| f.0.contains(&p) && f.0.contains(&q))
                            .map(|(i, _)| i),
                    ),
                }
                for fi in voters {
                    let f = bnd.faces[fi].0;
                    let v = if directed(f, p, q) == (q, p) { 1 } else { -1 };
                    let w = &mut vote[piece[fi]];
                    if *w == -v {
                        return None;
                    }
                    *w = v;
                }
            }
        }
        if vote.contains(&0) {
            return None;
        }
        let mut sides = [Region::default(), Region::default()];
        for (i, f) in bnd.faces.iter().enumerate() {
            sides[usize::from(vote[piece[i]] < 0)].faces.push(*f);
        }
        for t in &patch {
            sides[0].faces.push((*t, DEAD, 0));
            sides[1].faces.push(([t[0], t[2], t[1]], DEAD, 0));
        }
        let mut fills: Vec<Fill> = Vec::new();
        let mut next_id = cm.pts().len() as u32;
        for reg in sides.iter_mut() {
            let f = fill_side(cm, reg, &mut set, None, prot, steiner, next_id)?;
            if f.point.is_some() {
                next_id += 1;
            }
            fills.push(f);
        }
        let k = self.apply(cm, &set, fills, prot)?;
        Some((k, patch))
    }
}

/// The direction in which triangle `t` uses edge `{p, q}`.
fn directed(t: [u32; 3], p: u32, q: u32) -> (u32, u32) {
    for i in 0..3 {
        if t[i] == p && t[(i + 1) % 3] == q {
            return (p, q);
        }
    }
    (q, p)
}

/// The two boundary faces of the tetrahedron set `set` (sorted) that
/// enclose the direction of triangle `p q r` in the ring around mesh edge
/// `p q`, as (owning tetrahedron, third vertex); `None` when the ring is
/// not available or the direction is not inside `set`.
fn ring_exits(cm: &Journaled<'_>, set: &[u32], p: u32, q: u32, r: u32) -> Option<Vec<(u32, u32)>> {
    let pts = cm.pts();
    let (tets, ring) = edge_ring(cm, p, q)?;
    let m = ring.len();
    let [tp, tq, tr] = [p, q, r].map(|w| &pts[w as usize]);
    let inside = |j: usize| set.binary_search(&tets[j % m]).is_ok();
    let i = (0..m).find(|&j| {
        inside(j)
            && ring[j] != INF
            && ring[(j + 1) % m] != INF
            && place::crosses(
                tp,
                tq,
                tr,
                &pts[ring[j] as usize],
                &pts[ring[(j + 1) % m] as usize],
            )
    })?;
    // Forward exit: face (p, q, ring[j + 1]) of tets[j]; backward exit:
    // face (p, q, ring[j]) of tets[j].
    let mut exits = Vec::new();
    if let Some(j) = (i..i + m).find(|&j| !inside(j + 1)) {
        exits.push((tets[j % m], ring[(j + 1) % m]));
    }
    if let Some(j) = (i + 1..=i + m).rev().find(|&j| !inside(j - 1)) {
        exits.push((tets[j % m], ring[j % m]));
    }
    (exits.len() == 2).then_some(exits)
}

/// The tetrahedra around mesh edge `p q` (ghosts included) and the ring
/// vertices, `tets[i]` having `ring[i]` and `ring[i + 1]` (cyclic); no cap
/// on the ring's length but the mesh's size.
fn edge_ring(cm: &Journaled<'_>, p: u32, q: u32) -> Option<(Vec<u32>, Vec<u32>)> {
    let c = &cm.m;
    let t0 = cm.find_edge(p, q)?;
    let mut o = c.tv[t0 as usize].into_iter().filter(|&w| w != p && w != q);
    let xy = (o.next()?, o.next()?);
    let (mut tets, mut ring) = (Vec::new(), Vec::new());
    let cap = c.tv.len() + 1;
    let verts = |t: u32| c.tv[t as usize];
    let cross = |t: u32, i: usize| Ok(Some(c.nb[t as usize][i] >> 2));
    let end = ring::walk(t0, xy, (p, q), cap, (&mut tets, &mut ring), verts, cross)?;
    (end == RingEnd::Closed).then_some((tets, ring))
}
