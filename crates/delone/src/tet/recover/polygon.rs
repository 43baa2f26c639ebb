//! Merged coplanar groups recovered as **polygon facets** (constrained
//! path).
//!
//! A group of coplanar input triangles merged by the `merge` module covers
//! a planar polygon `P` (maybe with holes). Only the polygon matters, not
//! how it is triangulated, so:
//!
//! * **segments** are the group's *boundary* edges only — edges of its
//!   triangles not shared by exactly two of them (shared with a triangle
//!   off the plane, or non-manifold). The edges inside the group are
//!   *soft*: their chains are emptied ([`Polygons::new`]), so they are
//!   never missing subsegments, never protected from flips and never
//!   split. Steiner points on a group's boundary split a segment, exactly
//!   as on any other input edge (the `place` module);
//! * the group is **recovered** when the mesh faces on its plane inside
//!   `P` cover `P` exactly ([`Polygons::cover`]): the faces whose three
//!   vertices lie on the group (corners of its triangles, Steiner points
//!   on its boundary, Steiner points inside its triangles) are the
//!   candidates; a flood fill starts, for every boundary subsegment, from
//!   the candidate face on its inner side (exact `orient2d` in the plane's
//!   projection) and crosses only edges that are not boundary
//!   subsegments. `P` is covered when every boundary subsegment has its
//!   inner face and every other edge of a reached face has exactly one
//!   other candidate face: the reached faces then form a 2-chain whose
//!   boundary (mod 2) is `∂P`, so (faces of a tetrahedralization never
//!   overlap) they cover `P` exactly once. A reached face cannot leave
//!   `P`: `∂P` is then made of mesh edges, and no mesh face is crossed by
//!   a mesh edge;
//! * the faces on a covered group are all listed on the group's first
//!   triangle (its *representative*): the output names that triangle
//!   ([`super::Recovered::boundary_triangle`]), whose input triangle
//!   (`surface_origin`) carries the group's marker, and
//!   [`super::check_recovered`] checks the union per group.
//!
//! When the flips cannot cover a group, points are inserted where a mesh
//! edge still crosses one of its triangles (the rounds of the constrained
//! recovery, `place::facet_point`, Shewchuk's rule: a point encroaching a
//! boundary subsegment splits the subsegment instead, at most twice per
//! triangle except in the `-Y` fallback). Such a point is on
//! the plane up to rounding only (a rational point of the plane is not
//! representable in `f64` in general); it is recorded as inexact with its
//! deviation, like every Steiner point inside an input triangle. Points on
//! boundary segments are placed by `place::edge_point` (exact when the
//! segment allows it). On the corpus, the flips make interior points rare.

use delone_predicates::orient2d;

use super::merge::{proj, projection};
use super::state::{Cover, CoverMemo, Group, Polygons, State};
use super::surface::{Kind, Surface};
use super::types::RecoverError;
use crate::geom::ids::{IdMap, IdSet};
use crate::geom::vec3::{cross, dot, sub};
use crate::tet::dmesh::journal::Journaled;
use crate::tet::local::{ekey, fkey};
use crate::tet::local::{DEAD, FACET, INF};
use crate::tet::Delaunay3;

impl Polygons {
    /// The groups of `surf` given `origin` (per surface triangle, the
    /// input triangle naming its group: groups are the sets of two or more
    /// triangles with one origin), with `pts` the (scaled) points. Empties
    /// the chains of the soft edges of `surf`.
    pub(crate) fn new(surf: &mut Surface, origin: &[u32], pts: &[[f64; 3]]) -> Polygons {
        let n = surf.tris.len();
        let mut order: Vec<u32> = (0..n as u32).collect();
        order.sort_by_key(|&t| (origin.get(t as usize).copied().unwrap_or(t), t));
        let mut of_tri = vec![u32::MAX; n];
        let mut groups: Vec<Group> = Vec::new();
        let mut i = 0;
        while i < order.len() {
            let o = |t: u32| origin.get(t as usize).copied().unwrap_or(t);
            let mut j = i + 1;
            while j < order.len() && o(order[j]) == o(order[i]) {
                j += 1;
            }
            if j - i >= 2 {
                let tris: Vec<u32> = order[i..j].to_vec();
                let [a, b, c] = surf.tris[tris[0] as usize].map(|w| &pts[w as usize]);
                if let Some((k, sign)) = projection(a, b, c) {
                    let g = groups.len() as u32;
                    for &t in &tris {
                        of_tri[t as usize] = g;
                    }
                    groups.push(Group {
                        tris,
                        bnd: Vec::new(),
                        k,
                        sign,
                    });
                }
            }
            i = j;
        }
        // Soft edges: in exactly two triangles, both of one group.
        let mut soft = vec![false; surf.edges.len()];
        for (e, s) in soft.iter_mut().enumerate() {
            let ts = &surf.edge_tris[e];
            if ts.len() == 2 {
                let g = of_tri[ts[0] as usize];
                *s = g != u32::MAX && g == of_tri[ts[1] as usize] && ts[0] != ts[1];
            }
        }
        for (g, grp) in groups.iter_mut().enumerate() {
            for &t in &grp.tris {
                let tv = surf.tris[t as usize];
                // Edge k of `t` runs from tv[k] to tv[k + 1].
                for (&e, &from) in surf.tri_edges[t as usize].iter().zip(&tv) {
                    if !soft[e as usize] {
                        grp.bnd.push((e, from == surf.edges[e as usize][0]));
                    }
                }
            }
            grp.bnd.sort_unstable();
            debug_assert!(grp.tris.iter().all(|&t| of_tri[t as usize] == g as u32));
        }
        for (e, s) in soft.iter().enumerate() {
            if *s {
                surf.chains[e].clear();
            }
        }
        Polygons { of_tri, groups }
    }

    /// The group of surface triangle `t`.
    #[inline]
    pub(crate) fn group(&self, t: usize) -> Option<u32> {
        self.of_tri.get(t).copied().filter(|&g| g != u32::MAX)
    }

    /// True when there is no group.
    pub(crate) fn is_empty(&self) -> bool {
        self.groups.is_empty()
    }

    /// The groups vertex `w` lies on (pushed to `out`, maybe repeated).
    pub(crate) fn vertex_groups(&self, surf: &Surface, w: u32, out: &mut Vec<u32>) {
        if let Some(l) = surf.vtris.get(w as usize) {
            out.extend(l.iter().filter_map(|&t| self.group(t as usize)));
        }
    }

    /// The groups on which all three vertices of face `f` lie, ascending.
    pub(crate) fn face_groups(&self, surf: &Surface, f: [u32; 3]) -> Vec<u32> {
        let mut a = Vec::new();
        self.vertex_groups(surf, f[0], &mut a);
        if a.is_empty() {
            return a;
        }
        a.sort_unstable();
        a.dedup();
        let mut b = Vec::new();
        for &w in &f[1..] {
            b.clear();
            self.vertex_groups(surf, w, &mut b);
            a.retain(|g| b.contains(g));
            if a.is_empty() {
                break;
            }
        }
        a
    }

    /// True when vertex `w` lies on group `g`.
    pub(crate) fn on_group(&self, surf: &Surface, w: u32, g: u32) -> bool {
        surf.vtris
            .get(w as usize)
            .is_some_and(|l| l.iter().any(|&t| self.group(t as usize) == Some(g)))
    }

    /// The vertices of group `g`: the corners of its triangles, the chains
    /// of its boundary edges and `inner(t)` of its triangles. Sorted.
    pub(crate) fn vertices(
        &self,
        surf: &Surface,
        g: u32,
        inner: &IdMap<u32, Vec<u32>>,
    ) -> Vec<u32> {
        let grp = &self.groups[g as usize];
        let mut out: Vec<u32> = Vec::new();
        for &t in &grp.tris {
            out.extend(surf.tris[t as usize]);
            if let Some(l) = inner.get(&t) {
                out.extend(l);
            }
        }
        for &(e, _) in &grp.bnd {
            out.extend(surf.chains[e as usize].iter());
        }
        out.sort_unstable();
        out.dedup();
        out
    }

    /// Some corner of group `g`'s triangles or vertex of its boundary
    /// chains is not among `n` points.
    fn missing_vertex(&self, surf: &Surface, g: u32, n: usize) -> bool {
        let grp = &self.groups[g as usize];
        let corners = grp.tris.iter().flat_map(|&t| surf.tris[t as usize]);
        let chains = grp
            .bnd
            .iter()
            .flat_map(|&(e, _)| surf.chains[e as usize].iter());
        corners.chain(chains.copied()).any(|w| w as usize >= n)
    }

    /// Face `f` is three points of one boundary chain of the group.
    fn flat(surf: &Surface, f: [u32; 3]) -> bool {
        f.iter().any(|&w| match surf.kind.get(w as usize) {
            Some(Kind::OnEdge(e)) => f.iter().all(|&x| on_edge(surf, x, *e)),
            _ => false,
        })
    }

    /// The coverage of group `g` (see the module notes) from `tets`: finite
    /// tetrahedra including every one with a face on the group (repeats
    /// allowed).
    pub(crate) fn cover(
        &self,
        surf: &Surface,
        g: u32,
        tets: &[[u32; 4]],
        pts: &[[f64; 3]],
    ) -> Cover {
        self.cover_with(surf, g, tets, pts, |w| self.on_group(surf, w, g))
    }

    /// [`Polygons::cover`] given `on`, the answer of
    /// [`Polygons::on_group`] for group `g` (a caller that has the groups
    /// of every vertex at hand answers it without scanning triangles).
    fn cover_with(
        &self,
        surf: &Surface,
        g: u32,
        tets: &[[u32; 4]],
        pts: &[[f64; 3]],
        on: impl Fn(u32) -> bool,
    ) -> Cover {
        let grp = &self.groups[g as usize];
        if self.missing_vertex(surf, g, pts.len()) {
            // A vertex `pts` does not have (not expected: the callers pass
            // the points of the mesh the surface was refined with): not
            // covered, nothing to split.
            return Cover {
                faces: Vec::new(),
                covered: false,
                bare: Vec::new(),
            };
        }
        let mut faces: Vec<[u32; 3]> = Vec::new();
        let mut flat: Vec<[u32; 3]> = Vec::new();
        let mut drop: Vec<[u32; 3]> = Vec::new();
        let [a, b, c] = surf.tris[grp.tris[0] as usize].map(|w| pts[w as usize]);
        let nt = cross(&sub(&b, &a), &sub(&c, &a));
        for tv in tets {
            let ons = tv.map(&on);
            if ons.iter().filter(|&&x| x).count() < 3 {
                continue;
            }
            for (f, idx) in FACET.iter().enumerate() {
                if !ons[(f + 1) % 4] || !ons[(f + 2) % 4] || !ons[(f + 3) % 4] {
                    continue;
                }
                let k = fkey(idx.map(|i| tv[i]));
                if Self::flat(surf, k) {
                    flat.push(k);
                } else {
                    faces.push(k);
                }
            }
            if ons.iter().all(|&x| x) {
                // A flat tetrahedron (inexact Steiner points): only its
                // faces looking to the group's positive side count.
                for fv in FACET {
                    let [x, y, z] = fv.map(|i| pts[tv[i] as usize]);
                    let n = cross(&sub(&z, &x), &sub(&y, &x));
                    if dot(&n, &nt) <= 0.0 {
                        drop.push(fkey(fv.map(|i| tv[i])));
                    }
                }
            }
        }
        faces.sort_unstable();
        faces.dedup();
        drop.sort_unstable();
        drop.dedup();
        faces.retain(|f| drop.binary_search(f).is_err());
        flat.sort_unstable();
        flat.dedup();
        // Boundary subsegments, directed with the group on their left.
        let mut subs: Vec<(u32, u32, u32, bool)> = Vec::new();
        for &(e, fwd) in &grp.bnd {
            for w in surf.chains[e as usize].windows(2) {
                subs.push(if fwd {
                    (e, w[0], w[1], fwd)
                } else {
                    (e, w[1], w[0], fwd)
                });
            }
        }
        let bset: IdSet<(u32, u32)> = subs.iter().map(|&(_, u, v, _)| ekey(u, v)).collect();
        // Chords (inexact Steiner points, see `Surface::coverage_local`): a flat
        // face joins when one of its edges is a non-boundary edge of a face.
        let mut edge_faces = EdgeFaces::with_capacity(faces.len() * 3 / 2 + 4);
        let add = |edge_faces: &mut EdgeFaces, f: [u32; 3], i: u32| {
            for k in 0..3 {
                edge_faces.push(ekey(f[k], f[(k + 1) % 3]), i);
            }
        };
        for (i, f) in faces.iter().enumerate() {
            add(&mut edge_faces, *f, i as u32);
        }
        let n_plain = faces.len();
        let mut changed = true;
        while changed && !flat.is_empty() {
            changed = false;
            let mut rest = Vec::new();
            for f in flat {
                let chord = (0..3)
                    .map(|k| ekey(f[k], f[(k + 1) % 3]))
                    .any(|e| !bset.contains(&e) && edge_faces.has(e));
                if chord {
                    let i = faces.len() as u32;
                    faces.push(f);
                    add(&mut edge_faces, f, i);
                    changed = true;
                } else {
                    rest.push(f);
                }
            }
            flat = rest;
        }
        let p2 = |w: u32| proj(&pts[w as usize], grp.k);
        let mut reached = vec![false; faces.len()];
        let mut stack: Vec<u32> = Vec::new();
        let mut bare = Vec::new();
        let mut covered = true;
        for &(e, u, v, fwd) in &subs {
            let (pu, pv) = (p2(u), p2(v));
            let seed = edge_faces.faces(ekey(u, v)).find(|&i| {
                let f = faces[i as usize];
                let w = f.iter().copied().find(|&x| x != u && x != v).unwrap_or(u);
                let o = orient2d(&pu, &pv, &p2(w));
                o * grp.sign > 0.0 || (i as usize >= n_plain && o == 0.0)
            });
            match seed {
                Some(i) => {
                    if !reached[i as usize] {
                        reached[i as usize] = true;
                        stack.push(i);
                    }
                }
                None => {
                    covered = false;
                    bare.push(if fwd { (e, u, v) } else { (e, v, u) });
                }
            }
        }
        while let Some(i) = stack.pop() {
            let f = faces[i as usize];
            for k in 0..3 {
                let e = ekey(f[k], f[(k + 1) % 3]);
                if bset.contains(&e) {
                    continue;
                }
                let Some(j) = edge_faces.other(e, i) else {
                    covered = false;
                    continue;
                };
                if !reached[j as usize] {
                    reached[j as usize] = true;
                    stack.push(j);
                }
            }
        }
        let mut out: Vec<[u32; 3]> = faces
            .iter()
            .zip(&reached)
            .filter(|(_, &r)| r)
            .map(|(f, _)| *f)
            .collect();
        covered &= !out.is_empty();
        if !covered {
            // With a gap in the boundary the fill may have left the
            // polygon: keep only faces inside one of its triangles (these
            // are protected from flips by the recovery).
            out.retain(|f| {
                let l = |w: u32| surf.vtris.get(w as usize).map_or(&[][..], |l| &l[..]);
                l(f[0]).iter().any(|t| {
                    self.group(*t as usize) == Some(g)
                        && l(f[1]).binary_search(t).is_ok()
                        && l(f[2]).binary_search(t).is_ok()
                })
            });
        }
        out.sort_unstable();
        Cover {
            covered,
            faces: out,
            bare,
        }
    }
}

/// The faces at each edge, by index, in the order added: the first two
/// in the map, any more (a non-manifold fan) in `more` — no list
/// allocated per edge.
struct EdgeFaces {
    /// Per edge: how many faces, the first and the second.
    map: IdMap<(u32, u32), [u32; 3]>,
    /// The third and later faces of the edges that have them.
    more: Vec<((u32, u32), u32)>,
}

impl EdgeFaces {
    fn with_capacity(n: usize) -> Self {
        let mut map = IdMap::default();
        map.reserve(n);
        EdgeFaces {
            map,
            more: Vec::new(),
        }
    }

    /// Adds face `i` at edge `e`.
    fn push(&mut self, e: (u32, u32), i: u32) {
        let x = self.map.entry(e).or_insert([0, i, u32::MAX]);
        match x[0] {
            0 => {}
            1 => x[2] = i,
            _ => self.more.push((e, i)),
        }
        x[0] += 1;
    }

    /// True when some face is at edge `e`.
    fn has(&self, e: (u32, u32)) -> bool {
        self.map.contains_key(&e)
    }

    /// The faces at edge `e`, in the order added.
    fn faces(&self, e: (u32, u32)) -> impl Iterator<Item = u32> + '_ {
        let x = self.map.get(&e).copied().unwrap_or([0; 3]);
        let more = if x[0] > 2 { &self.more[..] } else { &[][..] };
        [x[1], x[2]]
            .into_iter()
            .take(x[0].min(2) as usize)
            .chain(more.iter().filter(move |m| m.0 == e).map(|m| m.1))
    }

    /// The other face at edge `e` when it has exactly two, one of them `i`.
    fn other(&self, e: (u32, u32), i: u32) -> Option<u32> {
        let x = self.map.get(&e)?;
        (x[0] == 2).then(|| if x[1] == i { x[2] } else { x[1] })
    }
}

/// Vertex `w` lies on input edge `e` (an end or a Steiner point on it).
fn on_edge(surf: &Surface, w: u32, e: u32) -> bool {
    match surf.kind.get(w as usize) {
        Some(Kind::OnEdge(x)) => *x == e,
        Some(Kind::Input) | None => surf.edges[e as usize].contains(&w),
        Some(Kind::OnTri(_)) => false,
    }
}

/// The recovery's use of the groups (hooks called from the rounds).
impl State {
    /// The finite tetrahedra of `cm` around the vertices of group `g`.
    fn group_tets(&self, cm: &Journaled<'_>, g: u32) -> Vec<[u32; 4]> {
        let mut slots: Vec<u32> = Vec::new();
        for w in self.poly.vertices(&self.surf, g, &self.tri_inner) {
            slots.extend(cm.star(w));
        }
        slots.sort_unstable();
        slots.dedup();
        let core = &cm.m;
        slots
            .iter()
            .map(|&x| core.tv[x as usize])
            .filter(|tv| tv[0] != DEAD && !tv.contains(&INF))
            .collect()
    }

    /// Recomputes the coverage of `groups` (repeats allowed) on `cm`,
    /// locally.
    pub(super) fn groups_local(
        &self,
        cm: &Journaled<'_>,
        mut groups: Vec<u32>,
        on: &mut [Vec<[u32; 3]>],
        covered: &mut [bool],
    ) {
        groups.sort_unstable();
        groups.dedup();
        for g in groups {
            let c = self
                .poly
                .cover(&self.surf, g, &self.group_tets(cm, g), cm.pts());
            self.set_group(g, c, on, covered);
        }
    }

    /// Stores the coverage of group `g`: its faces on its first triangle,
    /// its verdict on all of them.
    pub(super) fn set_group(
        &self,
        g: u32,
        c: Cover,
        on: &mut [Vec<[u32; 3]>],
        covered: &mut [bool],
    ) {
        let tris = &self.poly.groups[g as usize].tris;
        for &t in tris {
            on[t as usize].clear();
            covered[t as usize] = c.covered;
        }
        on[tris[0] as usize] = c.faces;
    }

    /// The coverage of every group, from all finite tetrahedra `tets`.
    pub(super) fn groups_global(
        &self,
        tets: impl Iterator<Item = [u32; 4]>,
        pts: &[[f64; 3]],
        on: &mut [Vec<[u32; 3]>],
        covered: &mut [bool],
    ) {
        if self.poly.is_empty() {
            return;
        }
        let mut bucket: Vec<Vec<[u32; 4]>> = vec![Vec::new(); self.poly.groups.len()];
        // The groups of each surface vertex, ascending, found once for the
        // pass (`at[w]..at[w + 1]` in `list`).
        let nv = self.surf.vtris.len();
        let mut at = Vec::with_capacity(nv + 1);
        let (mut list, mut one): (Vec<u32>, Vec<u32>) = (Vec::new(), Vec::new());
        at.push(0);
        for w in 0..nv {
            one.clear();
            self.poly.vertex_groups(&self.surf, w as u32, &mut one);
            one.sort_unstable();
            one.dedup();
            list.extend_from_slice(&one);
            at.push(list.len());
        }
        let groups_of = |w: u32| -> &[u32] {
            let w = w as usize;
            if w < nv {
                &list[at[w]..at[w + 1]]
            } else {
                &[]
            }
        };
        // Per vertex: bit `g % 64` set for each of its groups `g`. A
        // group on three vertices of a tetrahedron has its bit in three of
        // their masks, so a tetrahedron whose masks share no bit three
        // times has no face on a group (most of them).
        let mask: Vec<u64> = (0..nv)
            .map(|w| {
                groups_of(w as u32)
                    .iter()
                    .fold(0, |m, &g| m | 1 << (g % 64))
            })
            .collect();
        let mask_of = |w: u32| mask.get(w as usize).copied().unwrap_or(0);
        let mut gs: Vec<u32> = Vec::new();
        for tv in tets {
            let [a, b, c, d] = tv.map(mask_of);
            if (a & b & (c | d)) | (c & d & (a | b)) == 0 {
                continue;
            }
            // Every face holds the first or the second vertex.
            gs.clear();
            gs.extend_from_slice(groups_of(tv[0]));
            gs.extend_from_slice(groups_of(tv[1]));
            if gs.is_empty() {
                continue;
            }
            gs.sort_unstable();
            gs.dedup();
            for &g in &gs {
                let bit = 1 << (g % 64);
                if [a, b, c, d].iter().filter(|&&m| m & bit != 0).count() < 3 {
                    continue;
                }
                let n = tv
                    .iter()
                    .filter(|&&w| groups_of(w).binary_search(&g).is_ok())
                    .count();
                if n >= 3 {
                    bucket[g as usize].push(tv);
                }
            }
        }
        // A group whose tetrahedra and boundary chains are those of the
        // last pass has the coverage found then (most groups: the flips
        // and points of a round change few of them).
        let mut memo = self.cover_memo.borrow_mut();
        memo.resize_with(bucket.len(), CoverMemo::default);
        let mut chains: Vec<u32> = Vec::new();
        for (g, (tets, m)) in bucket.into_iter().zip(memo.iter_mut()).enumerate() {
            let g = g as u32;
            if self.poly.missing_vertex(&self.surf, g, pts.len()) {
                let c = self.poly.cover(&self.surf, g, &tets, pts);
                self.set_group(g, c, on, covered);
                continue;
            }
            chains.clear();
            for &(e, _) in &self.poly.groups[g as usize].bnd {
                let ch = &self.surf.chains[e as usize];
                chains.push(ch.len() as u32);
                chains.extend_from_slice(ch);
            }
            let c = match &m.cover {
                Some(c) if m.tets == tets && m.chains == chains => c.clone(),
                _ => {
                    let bit = 1 << (g % 64);
                    let on_g =
                        |w: u32| mask_of(w) & bit != 0 && groups_of(w).binary_search(&g).is_ok();
                    let c = self.poly.cover_with(&self.surf, g, &tets, pts, on_g);
                    m.cover = Some(c.clone());
                    m.tets = tets;
                    std::mem::swap(&mut m.chains, &mut chains);
                    c
                }
            };
            self.set_group(g, c, on, covered);
        }
    }

    /// Steiner points for merged group `g`, which the flips on `cm` could
    /// not cover (`dt_covered`: it was covered in `dt`): where a mesh edge
    /// of `cm` still crosses one of its triangles (or the boundary
    /// subsegment that point encroaches); else a boundary subsegment with
    /// no face on its inner side, else its longest boundary subsegment.
    pub(super) fn split_group(
        &mut self,
        dt: &mut Delaunay3<'_>,
        cm: &Journaled<'_>,
        g: u32,
        dt_covered: bool,
    ) -> Result<bool, RecoverError> {
        // A group sharing a boundary edge with a group split earlier in
        // this round may already hold points `cm` does not have: it has
        // changed since `cm`, so the next round looks at it again (`cm`'s
        // coverage says nothing about its new subsegments).
        let known = cm.pts().len();
        if self
            .poly
            .vertices(&self.surf, g, &self.tri_inner)
            .iter()
            .any(|&w| w as usize >= known)
        {
            return Ok(true);
        }
        let tris = self.poly.groups[g as usize].tris.clone();
        let mut progress = false;
        if !dt_covered {
            for &t in &tris {
                let t = t as usize;
                let inner = self.tri_inner.get(&(t as u32)).cloned().unwrap_or_default();
                let cross = super::cdt::crossing_edges(cm, &self.surf, t, &inner);
                let Some(&((p, q), _)) = cross.first() else {
                    continue;
                };
                let pts = cm.pts();
                let [a, b, c] = self.surf.tris[t].map(|w| pts[w as usize]);
                let (x, dev) =
                    super::place::facet_point(&a, &b, &c, &pts[p as usize], &pts[q as usize]);
                progress |= self.insert_in_facet(dt, t, x, dev)?;
            }
            if progress {
                return Ok(true);
            }
            let c = self
                .poly
                .cover(&self.surf, g, &self.group_tets(cm, g), cm.pts());
            if let Some(&(e, u, v)) = c.bare.first() {
                return self.split_edge(dt, e, u, v);
            }
        }
        let pts = dt.points();
        let mut best: Option<(f64, u32, u32, u32)> = None;
        for &(e, _) in &self.poly.groups[g as usize].bnd {
            for w in self.surf.chains[e as usize].windows(2) {
                let d = sub(&pts[w[0] as usize], &pts[w[1] as usize]);
                let l = dot(&d, &d);
                if best.is_none_or(|b| l > b.0) {
                    best = Some((l, e, w[0], w[1]));
                }
            }
        }
        match best {
            Some((_, e, u, v)) => self.split_edge(dt, e, u, v),
            None => Ok(false),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The faces of an edge come back in the order added, however the
    /// edges' pushes interleave; `other` answers for two-face edges only.
    #[test]
    fn edge_faces_keep_the_order_added() {
        let (e, f, d) = ((1, 2), (4, 5), (2, 3));
        let mut ef = EdgeFaces::with_capacity(4);
        for (k, i) in [
            (e, 5),
            (e, 3),
            (f, 1),
            (f, 2),
            (e, 9),
            (f, 8),
            (e, 4),
            (d, 7),
            (d, 1),
        ] {
            ef.push(k, i);
        }
        assert_eq!(ef.faces(e).collect::<Vec<_>>(), [5, 3, 9, 4]);
        assert_eq!(ef.faces(f).collect::<Vec<_>>(), [1, 2, 8]);
        assert_eq!(ef.faces(d).collect::<Vec<_>>(), [7, 1]);
        assert!(ef.faces((0, 1)).next().is_none());
        assert!(ef.has(d) && !ef.has((0, 1)));
        assert_eq!((ef.other(d, 7), ef.other(d, 1)), (Some(1), Some(7)));
        assert_eq!((ef.other(e, 5), ef.other(f, 1)), (None, None));
        assert_eq!(ef.other((0, 1), 0), None);
    }
}
