//! Missing input edges on **flat parts of the convex hull** (`-Y`).
//!
//! When coplanar input triangles lie on the convex hull, the Delaunay
//! tetrahedralization triangulates their polygon with its own diagonals,
//! and no interior point or interior flip changes a hull face: the input
//! edge is missing however many points are added inside. The two sides of
//! such a patch are not two polyhedra: the outer side is flat (the patch
//! and the hull faces on it cover the same polygon), so the patch cavity
//! of the parent module cannot fill it.
//!
//! Here the hull faces on the patch are replaced by the patch triangles
//! (a 2-2 flip of flat hull faces when the patch is two triangles, its
//! generalisation otherwise): the removed set is every finite tetrahedron
//! having an edge of those hull faces that is not a patch edge, or a face
//! on the hull there, plus the ghost tetrahedra on those hull faces. The
//! finite part is refilled like one side of a patch (cone from one of its
//! vertices, else from a kernel point strictly inside, checked exactly off
//! the surface) bounded by the patch triangles instead of the old hull
//! faces, and new ghosts close the patch triangles.
//!
//! A missing edge there is first recovered by 2D flips in the plane
//! ([`State::hull_edge_by_flips`]), each one such replacement with a patch
//! of two triangles.
//!
//! Exactness: the patch triangles must all lie in one plane (exact
//! `orient3d`), the old hull faces must use only patch vertices and lie in
//! that plane, and the edges used once by the hull faces must be exactly
//! the patch's border edges — two triangulations of one planar polygon
//! with the same vertices, so they cover the same region. The new finite
//! tetrahedra are validated like every other replacement (all strictly
//! positive, their oriented faces forming a chain whose boundary is
//! exactly the old boundary with the hull faces swapped for the patch,
//! every vertex and protected item kept).

use super::super::State;
use super::pull::project;
use super::{all_positive, fill_side, fills_bounded, keeps_guarded, okey, Guard, Region};
use crate::geom::ids::{IdMap, IdSet};
use crate::geom::vec3::{cross, dot, sub};
use crate::tet::dmesh::journal::Journaled;
use crate::tet::local::face;
use crate::tet::local::{ekey, fkey};
use crate::tet::local::{DEAD, INF};
use delone_predicates::{orient2d, orient3d};

/// Most tetrahedra removed by one flat hull replacement.
const MAX_SET: usize = 512;

/// A patch lying flat on the convex hull: the finite tetrahedra to
/// remove, the ghosts on its hull faces, and its triangles oriented inward.
pub(super) struct Flat {
    set: Vec<u32>,
    ghosts: Vec<u32>,
    inward: Vec<[u32; 3]>,
}

impl State {
    /// The flat hull data of `patch` (consistently oriented triangles), or
    /// `None` when it does not lie flat on the convex hull.
    pub(super) fn flat_hull(&self, cm: &Journaled<'_>, patch: &[[u32; 3]]) -> Option<Flat> {
        let pts = cm.pts();
        let c = &cm.m;
        let p0 = patch.first()?.map(|w| pts[w as usize]);
        let mut pv: Vec<u32> = patch.iter().flat_map(|t| *t).collect();
        pv.sort_unstable();
        pv.dedup();
        if pv
            .iter()
            .any(|&w| orient3d(&p0[0], &p0[1], &p0[2], &pts[w as usize]) != 0.0)
        {
            return None;
        }
        // Patch edge uses: the border is the edges used once.
        let mut uses: IdMap<(u32, u32), u32> = IdMap::default();
        for t in patch {
            for i in 0..3 {
                *uses.entry(ekey(t[i], t[(i + 1) % 3])).or_insert(0) += 1;
            }
        }
        // Ghosts whose hull face uses patch vertices only (the plane
        // follows: every patch vertex is on it).
        let mut ghosts: Vec<u32> = Vec::new();
        for &w in &pv {
            for t in cm.star(w) {
                let tv = c.tv[t as usize];
                if tv[0] != DEAD
                    && tv[3] == INF
                    && tv[..3].iter().all(|x| pv.binary_search(x).is_ok())
                {
                    ghosts.push(t);
                }
            }
        }
        ghosts.sort_unstable();
        ghosts.dedup();
        let mut huses: IdMap<(u32, u32), u32> = IdMap::default();
        for &g in &ghosts {
            let tv = c.tv[g as usize];
            for i in 0..3 {
                *huses.entry(ekey(tv[i], tv[(i + 1) % 3])).or_insert(0) += 1;
            }
        }
        let border = |m: &IdMap<(u32, u32), u32>| {
            let mut b: Vec<(u32, u32)> =
                m.iter().filter(|(_, &n)| n == 1).map(|(k, _)| *k).collect();
            b.sort_unstable();
            b
        };
        if ghosts.is_empty() || border(&uses) != border(&huses) {
            return None;
        }
        // Finite tetrahedra: those on the hull faces and those around the
        // hull faces' inner edges that are not patch edges.
        let mut set: Vec<u32> = Vec::new();
        for &g in &ghosts {
            set.push(c.nb[g as usize][3] >> 2);
        }
        let inner: Vec<(u32, u32)> = {
            let mut v: Vec<(u32, u32)> = huses
                .iter()
                .filter(|(k, &n)| n == 2 && !uses.contains_key(*k))
                .map(|(k, _)| *k)
                .collect();
            v.sort_unstable();
            v
        };
        for &(p, q) in &inner {
            for t in cm.star(p) {
                let tv = c.tv[t as usize];
                if tv[0] != DEAD && !tv.contains(&INF) && tv.contains(&q) {
                    set.push(t);
                }
            }
        }
        set.sort_unstable();
        set.dedup();
        if set.len() > MAX_SET {
            return None;
        }
        // The patch, oriented inward: seen positively from the vertex of a
        // hull tetrahedron off the plane.
        let tv = c.tv[set[0] as usize];
        let x = tv
            .into_iter()
            .find(|&w| orient3d(&p0[0], &p0[1], &p0[2], &pts[w as usize]) != 0.0)?;
        let t0 = patch[0].map(|w| &pts[w as usize]);
        let flip = orient3d(t0[0], t0[1], t0[2], &pts[x as usize]) > 0.0;
        let inward: Vec<[u32; 3]> = patch
            .iter()
            .map(|t| if flip { [t[0], t[2], t[1]] } else { *t })
            .collect();
        Some(Flat {
            set,
            ghosts,
            inward,
        })
    }

    /// The flat hull patches next to `flat` (sharing one of its
    /// tetrahedra's hull faces' vertices, through a missing input edge).
    pub(super) fn flat_neighbours(&self, cm: &Journaled<'_>, flat: &Flat) -> Vec<Vec<[u32; 3]>> {
        let c = &cm.m;
        let mut out: Vec<Vec<[u32; 3]>> = Vec::new();
        let mut tried: IdSet<usize> = IdSet::default();
        let mut own: Vec<[u32; 3]> = flat.inward.iter().map(|t| fkey(*t)).collect();
        own.sort_unstable();
        for &t in &flat.set {
            for f in 0..4 {
                let n = c.nb[t as usize][f] >> 2;
                if c.tv[n as usize][3] != INF || flat.ghosts.contains(&n) {
                    continue;
                }
                for w in face(c.tv[t as usize], f) {
                    let Some(ts) = self.surf.vtris.get(w as usize) else {
                        continue;
                    };
                    for &it in ts {
                        for &k in &self.surf.tri_edges[it as usize] {
                            let [a, b] = self.surf.edges[k as usize];
                            if !tried.insert(k as usize) || cm.find_edge(a, b).is_some() {
                                continue;
                            }
                            if let Some(p) = self.patch_of(cm, k as usize) {
                                let mut key = p.iter().map(|t| fkey(*t)).collect::<Vec<_>>();
                                key.sort_unstable();
                                let dup = out.iter().any(|q| {
                                    let mut k2 = q.iter().map(|t| fkey(*t)).collect::<Vec<_>>();
                                    k2.sort_unstable();
                                    k2 == key
                                });
                                if !dup && key != own && out.len() < 8 {
                                    out.push(p);
                                }
                            }
                        }
                    }
                }
            }
        }
        out
    }

    /// Recovers the `patches` (each consistently oriented) when each lies
    /// flat on the convex hull, in one replacement. `Some(points added)`
    /// on success. With `apex`, the finite part is refilled by the cone
    /// from that new point only.
    pub(super) fn hull_patch(
        &self,
        cm: &mut Journaled<'_>,
        patches: &[Vec<[u32; 3]>],
        prot: &Guard,
        steiner: bool,
        apex: Option<[f64; 3]>,
    ) -> Option<usize> {
        let mut set: Vec<u32> = Vec::new();
        let mut ghosts: Vec<u32> = Vec::new();
        let mut inward: Vec<[u32; 3]> = Vec::new();
        for p in patches {
            let f = self.flat_hull(cm, p)?;
            set.extend(f.set);
            ghosts.extend(f.ghosts);
            inward.extend(f.inward);
        }
        set.sort_unstable();
        set.dedup();
        ghosts.sort_unstable();
        ghosts.dedup();
        let c = &cm.m;
        let pts = cm.pts();
        let hull_faces: IdSet<[u32; 3]> = ghosts
            .iter()
            .map(|&g| {
                let tv = c.tv[g as usize];
                fkey([tv[0], tv[1], tv[2]])
            })
            .collect();
        if hull_faces.len() != ghosts.len() {
            return None;
        }
        let bnd = super::boundary_of(cm, &set);
        let mut reg = Region::default();
        for f in &bnd.faces {
            if hull_faces.contains(&fkey(f.0)) {
                continue;
            }
            if f.0.contains(&INF) {
                return None;
            }
            reg.faces.push(*f);
        }
        for t in &inward {
            reg.faces.push((*t, DEAD, 0));
        }
        let id = pts.len() as u32;
        let f = match apex {
            None => fill_side(cm, &mut reg, &mut set, None, prot, steiner, id)?,
            Some(p) => {
                let mut all: Vec<[f64; 3]> = pts.to_vec();
                all.push(p);
                let tets = super::cone_from(&all, &reg.tris(), id)?;
                super::Fill {
                    tets,
                    point: Some(p),
                }
            }
        };
        let pts = cm.pts();
        let outer: Vec<[u32; 3]> = reg.faces.iter().map(|f| okey(f.0)).collect();
        // Validation (see the module documentation).
        let mut all: Vec<[f64; 3]> = pts.to_vec();
        if let Some(p) = f.point {
            if !self.off_surface(&all, &p) {
                return None;
            }
            all.push(p);
        }
        let oset: IdSet<[u32; 3]> = outer.iter().copied().collect();
        if oset.len() != outer.len() || !all_positive(&all, &f.tets) {
            return None;
        }
        let parts = fills_bounded(&f.tets, &oset)?;
        if !keeps_guarded(cm, &set, prot, &parts, &hull_faces) {
            return None;
        }
        // Protected hull faces would be lost (they are replaced).
        if hull_faces.iter().any(|k| prot.faces.contains(k)) {
            return None;
        }
        let added = usize::from(f.point.is_some());
        if let Some(p) = f.point {
            cm.push_point(p);
        }
        let mut old = set;
        old.extend(&ghosts);
        old.sort_unstable();
        let mut new = f.tets;
        // New ghosts: the patch triangles with the outside on their
        // positive side (the reverse of the inward orientation).
        for t in &inward {
            new.push([t[0], t[2], t[1], INF]);
        }
        cm.replace(&old, &new);
        Some(added)
    }
}

/// Most 2-2 flips of one [`State::hull_edge_by_flips`] call.
const MAX_FLIPS: usize = 512;
/// Most flippable edges tried per flip (in their order of preference).
const MAX_TRIED: usize = 4;

/// The hull faces of the plane through `a` and `b` (a flat part of the
/// convex hull holding both) that meet the segment `a b`, with the axis
/// along which the plane projects injectively; `None` when no hull face
/// at `a` lies in a plane through `b`, or when a vertex lies on the open
/// segment (then no flips can make `a b` an edge).
fn faces_along(cm: &Journaled<'_>, a: u32, b: u32) -> Option<(Vec<[u32; 3]>, usize)> {
    let pts = cm.pts();
    let c = &cm.m;
    let g = |w: u32| &pts[w as usize];
    let hull = |t: u32| {
        let tv = c.tv[t as usize];
        (tv[0] != DEAD && tv[3] == INF).then(|| [tv[0], tv[1], tv[2]])
    };
    let start = cm.star(a).into_iter().find_map(|t| {
        let f = hull(t)?;
        (orient3d(g(f[0]), g(f[1]), g(f[2]), g(b)) == 0.0).then_some((t, f))
    })?;
    let plane = start.1.map(|w| *g(w));
    let ax = (0..3).find(|&ax| {
        let [p, q, r] = plane.map(|x| project(&x, ax));
        orient2d(&p, &q, &r) != 0.0
    })?;
    let p2 = |w: u32| project(g(w), ax);
    let (pa, pb) = (p2(a), p2(b));
    // The closed segment a b and the open segment u v cross (exact, 2D).
    let crosses = |u: u32, v: u32| {
        let (pu, pv) = (p2(u), p2(v));
        let s1 = orient2d(&pa, &pb, &pu);
        let s2 = orient2d(&pa, &pb, &pv);
        let s3 = orient2d(&pu, &pv, &pa);
        let s4 = orient2d(&pu, &pv, &pb);
        s1 * s2 < 0.0 && s3 * s4 < 0.0
    };
    // A vertex other than `a`, `b` on the closed segment.
    let on_segment = |w: u32| {
        let pw = p2(w);
        w != a
            && w != b
            && orient2d(&pa, &pb, &pw) == 0.0
            && super::super::place::strictly_between(g(a), g(b), g(w))
    };
    let mut seen: IdSet<u32> = IdSet::default();
    let mut stack = vec![start.0];
    seen.insert(start.0);
    let mut out = Vec::new();
    while let Some(t) = stack.pop() {
        let f = hull(t)?;
        if f.iter()
            .any(|&w| orient3d(&plane[0], &plane[1], &plane[2], g(w)) != 0.0)
        {
            continue;
        }
        if f.iter().any(|&w| on_segment(w)) {
            return None;
        }
        let on_way =
            f.contains(&a) || f.contains(&b) || (0..3).any(|i| crosses(f[i], f[(i + 1) % 3]));
        if !on_way {
            continue;
        }
        out.push(f);
        for i in 0..3 {
            let n = c.nb[t as usize][i] >> 2;
            if hull(n).is_some() && seen.insert(n) {
                stack.push(n);
            }
        }
        if out.len() > MAX_SET {
            return None;
        }
    }
    Some((out, ax))
}

impl State {
    /// Recovers the missing input edge `a b` lying on a flat part of the
    /// convex hull by 2D edge flips in that plane (Lawson): while `a b` is
    /// missing, a hull edge `c d` crossing it whose two hull faces
    /// `c d x`, `d c y` form a strictly convex quadrilateral is flipped to
    /// `x y` — preferring flips whose new edge does not cross `a b` — each
    /// flip done by [`State::hull_patch`] on the two new triangles (the
    /// tetrahedra around `c d` refilled by a cone from one of their
    /// vertices, else, with `steiner`, from a kernel point; the point just
    /// inside the hull above the middle of `c d` sees every face of that
    /// ring strictly, so such a kernel point exists). In a planar
    /// triangulation some edge crossing a missing segment is always
    /// flippable, so only the Steiner budget and [`MAX_FLIPS`] bound
    /// this. Returns the points added and whether `a b` is an edge.
    pub(super) fn hull_edge_by_flips(
        &self,
        cm: &mut Journaled<'_>,
        a: u32,
        b: u32,
        prot: &Guard,
        steiner: bool,
    ) -> (usize, bool) {
        let mut added = 0;
        for _ in 0..MAX_FLIPS {
            if cm.find_edge(a, b).is_some() {
                return (added, true);
            }
            let Some((faces, ax)) = faces_along(cm, a, b) else {
                return (added, false);
            };
            let pts = cm.pts();
            let p2 = |w: u32| project(&pts[w as usize], ax);
            let (pa, pb) = (p2(a), p2(b));
            // Per edge (sorted), the vertices opposite it in the faces.
            let mut opp: IdMap<(u32, u32), Vec<u32>> = IdMap::default();
            for f in &faces {
                for i in 0..3 {
                    let (u, v) = (f[i], f[(i + 1) % 3]);
                    opp.entry(ekey(u, v)).or_default().push(f[(i + 2) % 3]);
                }
            }
            let cross = |u: u32, v: u32| {
                let (pu, pv) = (p2(u), p2(v));
                orient2d(&pa, &pb, &pu) * orient2d(&pa, &pb, &pv) < 0.0
                    && orient2d(&pu, &pv, &pa) * orient2d(&pu, &pv, &pb) < 0.0
            };
            let mut cands: Vec<(bool, (u32, u32), u32, u32)> = Vec::new();
            for (&(c, d), xs) in &opp {
                if xs.len() != 2 || !cross(c, d) {
                    continue;
                }
                let (x, y) = (xs[0], xs[1]);
                let (px, py) = (p2(x), p2(y));
                if orient2d(&px, &py, &p2(c)) * orient2d(&px, &py, &p2(d)) >= 0.0 {
                    continue;
                }
                cands.push((cross(x, y), (c, d), x, y));
            }
            if cands.is_empty() {
                return (added, false);
            }
            // Deterministic: flips that end a crossing first, then by edge.
            cands.sort_unstable();
            let mut flipped = false;
            for &(_, (c, d), x, y) in cands.iter().take(MAX_TRIED) {
                // `x c y`, `y d x`: consistently oriented (`c`, `d` on
                // opposite sides of `x y`).
                let patch = [vec![[x, c, y], [y, d, x]]];
                if self.hull_patch(cm, &patch, prot, false, None).is_some() {
                    flipped = true;
                    break;
                }
                if !steiner {
                    continue;
                }
                if let Some(k) = self.hull_patch(cm, &patch, prot, true, None) {
                    added += k;
                    flipped = true;
                    break;
                }
                if let Some(k) = self.hull_flip_point(cm, &patch, (c, d, x), prot) {
                    added += k;
                    flipped = true;
                    break;
                }
            }
            if !flipped {
                return (added, false);
            }
        }
        (added, false)
    }
}

impl State {
    /// The 2-2 flip of hull edge `c d` (faces `c d x` and the other one of
    /// `patch`) by the cone from a new point: the middle `m` of `c d`
    /// moved into the hull along the plane's normal by `|c d| / 2^k`,
    /// `k = 2, 3, …` — every face of the ring of `c d` not on `c` or `d`'s
    /// side is seen strictly from `m` (the ring's tetrahedra are positive
    /// and `m` is inside the edge) and the two new flat faces from any
    /// point strictly inside, so a small enough move is accepted by the
    /// exact checks of [`State::hull_patch`]. `Some(1)` on success.
    fn hull_flip_point(
        &self,
        cm: &mut Journaled<'_>,
        patch: &[Vec<[u32; 3]>],
        (c, d, x): (u32, u32, u32),
        prot: &Guard,
    ) -> Option<usize> {
        let pts = cm.pts();
        let g = |w: u32| pts[w as usize];
        let (pc, pd, px) = (g(c), g(d), g(x));
        let mut n = cross(&sub(&pd, &pc), &sub(&px, &pc));
        // Towards the inside: the side of a finite tetrahedron at `c`.
        let apex = cm.star(c).into_iter().find_map(|t| {
            let tv = cm.m.tv[t as usize];
            if tv[0] == DEAD || tv.contains(&INF) {
                return None;
            }
            tv.into_iter()
                .find(|&w| orient3d(&pc, &pd, &px, &pts[w as usize]) != 0.0)
        })?;
        if dot(&n, &sub(&g(apex), &pc)) < 0.0 {
            n = n.map(|v| -v);
        }
        let nl = dot(&n, &n).sqrt();
        let cd = sub(&pd, &pc);
        let len = dot(&cd, &cd).sqrt();
        if nl == 0.0 || len == 0.0 || !nl.is_finite() {
            return None;
        }
        let m: [f64; 3] = [0, 1, 2].map(|k| 0.5 * (pc[k] + pd[k]));
        for k in (2..32).step_by(5) {
            let h = len * 0.5f64.powi(k);
            let p: [f64; 3] = [0, 1, 2].map(|i| m[i] + h * n[i] / nl);
            if let Some(added) = self.hull_patch(cm, patch, prot, true, Some(p)) {
                return Some(added);
            }
        }
        None
    }
}
