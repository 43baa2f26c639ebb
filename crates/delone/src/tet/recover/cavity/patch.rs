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

use super::super::cdt::Protected;
use super::super::missing::ekey;
use super::super::surface::{IdMap, IdSet};
use super::super::State;
use super::{boundary_of, facet_cavity, fill, grow, segment_cavity, Fill, Region, MAX_GROW};
use crate::tet::cmesh::CMesh;
use crate::tet::local::DEAD;

/// Most input triangles in a patch.
const MAX_PATCH: usize = 24;

impl State {
    /// The patch of missing triangles around missing input edge `e`
    /// (index into the surface's edges), consistently oriented (from the
    /// first triangle's input orientation); `None` when it is too large,
    /// not orientable, or its border is not made of mesh edges.
    fn patch_of(&self, cm: &CMesh<'_>, e: usize) -> Option<Vec<[u32; 3]>> {
        let surf = &self.surf;
        let missing_edge = |k: usize| {
            let [a, b] = surf.edges[k];
            cm.find_edge(a, b).is_none()
        };
        let mut seen: Vec<u32> = Vec::new();
        let mut stack: Vec<u32> = surf.edge_tris[e].clone();
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
        cm: &mut CMesh<'_>,
        e: usize,
        prot: &Protected,
        steiner: bool,
    ) -> Option<(usize, Vec<[u32; 3]>)> {
        let patch = self.patch_of(cm, e)?;
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
            set.extend(facet_cavity(cm, *t));
        }
        let mut keys: Vec<(u32, u32)> = uses.keys().copied().collect();
        keys.sort_unstable();
        for &(p, q) in &keys {
            if cm.find_edge(p, q).is_none() {
                set.extend(segment_cavity(cm, p, q));
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
        // Votes: +1 when the piece closes with the patch as oriented.
        let mut vote = vec![0i8; pieces];
        for (i, f) in bnd.faces.iter().enumerate() {
            for k in 0..3 {
                let (p, q) = (f.0[k], f.0[(k + 1) % 3]);
                let Some(u) = uses.get(&ekey(p, q)) else {
                    continue;
                };
                if u.len() != 1 {
                    continue;
                }
                let v = if u[0] == (q, p) { 1 } else { -1 };
                let w = &mut vote[piece[i]];
                if *w == -v {
                    return None;
                }
                *w = v;
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
        let none: IdSet<u32> = IdSet::default();
        for reg in sides.iter_mut() {
            let mut done = None;
            for _ in 0..=MAX_GROW {
                let apexes = reg.vertices();
                match fill(cm.pts(), &reg.tris(), &apexes, steiner, next_id) {
                    Ok(f) => {
                        done = Some(f);
                        break;
                    }
                    Err(best) => {
                        if !grow(cm, reg, &mut set, &none, &best, None, prot) {
                            break;
                        }
                    }
                }
            }
            let f = done?;
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
