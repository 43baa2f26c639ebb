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
use super::{all_positive, fill_side, fills_bounded, keeps_guarded, okey, Guard, Region};
use crate::geom::ids::{IdMap, IdSet};
use crate::tet::dmesh::journal::Journaled;
use crate::tet::local::face;
use crate::tet::local::{ekey, fkey};
use crate::tet::local::{DEAD, INF};
use delone_predicates::orient3d;

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
    /// on success.
    pub(super) fn hull_patch(
        &self,
        cm: &mut Journaled<'_>,
        patches: &[Vec<[u32; 3]>],
        prot: &Guard,
        steiner: bool,
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
        let f = fill_side(cm, &mut reg, &mut set, None, prot, steiner, id)?;
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
