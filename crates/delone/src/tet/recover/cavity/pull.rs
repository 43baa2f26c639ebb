//! The `-Y` fallback that always applies: recover with Steiner points on
//! the surface, then **pull every surface Steiner point off the surface**.
//!
//! When the cavity retriangulation of the parent module and the interior
//! point rounds leave items missing ([`RecoverError::Unrecovered`]), the
//! recovery is run again without surface preservation (the constrained
//! `-p` path, which recovers every closed non-self-intersecting surface
//! by splitting subsegments and triangles), and each Steiner point `s`
//! that path put on an input triangle or edge is then removed from the
//! surface, one at a time, in increasing id order (deterministic):
//!
//! 1. The star of `s` (every tetrahedron at `s`, ghosts included) is cut
//!    by the mesh faces on input triangles (the faces at `s` in the
//!    coverage) into **wedges**: connected sets of tetrahedra across faces
//!    at `s` that are not on the surface. `s` interior to input triangle
//!    `T` gives two wedges (the two sides of `T`); `s` on an input edge
//!    shared by `k` triangles gives `k`.
//! 2. For each input triangle `T` at `s`, the faces of `T`'s refinement at
//!    `s` form a fan whose union is a polygon `R` (a disk around `s`, or a
//!    half-disk when `s` is on an edge of `T`: then the polygon closes by
//!    the chord between the two neighbours of `s` on that edge, on which
//!    `s` lies). `R` is triangulated **without** `s` by ear clipping in
//!    the projection along `T`'s dominant axis (exact `orient2d`; a simple
//!    polygon always has an ear whose triangle holds no other vertex).
//! 3. Each wedge `W` is refilled by the cone from a **new interior point**
//!    `p = s + h d` over its new boundary — the faces opposite `s` (kept)
//!    and the new triangles of the polygons bounding it. `d` is the sum of
//!    the unit normals of `W`'s surface faces towards `W` (it points
//!    strictly into the open half-spaces of all of them, the planes of at
//!    most two triangles at an edge, unless the wedge is flat), and `h`
//!    is halved until `p` sees every boundary face strictly (exact
//!    `orient3d`). Such an `h` exists: `s` itself sees every face opposite
//!    it strictly (its star's tetrahedra are positive), which stays true
//!    near `s` by continuity, and the new triangles lie in the planes of
//!    their input triangles, which `p` is strictly off. A ghost wedge (the
//!    outside of a triangle on the convex hull) gets ghosts on the new
//!    triangles instead.
//! 4. The replacement of the whole star is validated exactly before it is
//!    applied (every new finite tetrahedron strictly positive; the new
//!    tetrahedra's oriented faces forming a chain whose boundary is exactly
//!    the star's boundary, so — winding number — they tile the star; every
//!    vertex but `s` kept; no new edge that exists elsewhere in the mesh).
//!
//! **Termination**: each removal takes one surface Steiner point away and
//! adds none on the surface, so there are at most as many removals as
//! surface Steiner points; a removal that fails validation (possible only
//! through rounding of inexact surface Steiner points) leaves an
//! [`RecoverError::Unrecovered`] error naming the triangles at that point.
//! When every surface Steiner point is gone, the refinement of each input
//! triangle has only the triangle's corners as vertices, so the triangle
//! is exactly one mesh face.
//!
//! **No point on the surface**: every new point `p` is strictly inside its
//! wedge (it sees every boundary face of the wedge strictly), and the
//! interior of a wedge meets no input triangle (the surface faces at `s`
//! bound the wedges, the others are faces opposite `s`, on the boundary);
//! each `p` is moreover tested exactly against every input triangle
//! (closed) before use. Points in outer wedges end outside the domain and
//! are dropped by carving and compaction.

use super::super::missing::fkey;
use super::super::place::{cross, dot, sub};
use super::super::surface::{IdMap, IdSet};
use super::super::{FacesOn, RecoverError, State};
use super::okey;
use crate::tet::cmesh::{face, CMesh};
use crate::tet::local::{DEAD, INF};
use crate::tet::Delaunay3;
use delone_predicates::{orient2d, orient3d};

type P = [f64; 3];

/// Halvings of the step `h` tried for a new point.
const HALVINGS: usize = 60;
/// Most growth steps of a wedge.
const MAX_GROW: usize = 4;

impl State {
    /// The `-Y` fallback (module documentation): recovers `scaled` (the
    /// input points as scaled by the caller) without surface preservation,
    /// then pulls every surface Steiner point off the surface. Returns the
    /// state (its report updated for `-Y`), the mesh and the one face on
    /// each input triangle.
    pub(in crate::tet::recover) fn preserve_fallback<'a>(
        &self,
        scaled: &'a [[f64; 3]],
    ) -> Result<(State, CMesh<'a>, FacesOn), RecoverError> {
        let mut opts = self.opts.clone();
        opts.preserve_surface = false;
        opts.merge_coplanar = false;
        opts.constrained = true;
        let mut st = State::new(self.surf.clone(), opts);
        let mut dt = Delaunay3::from_points(scaled)?;
        let (mut cm, on) = st.run_cdt(&mut dt)?;
        // `self.surf` is the unrefined surface (`st`'s has the points the
        // `-p` path added).
        let added = self.pull_off(&mut cm, &on, st.report.steiner())?;
        st.opts.preserve_surface = true;
        let r = &mut st.report;
        // The removed surface points stay unused in the points and are
        // dropped (and subtracted) by compaction with the outer ones.
        let removed = r.steiner_on_edges + r.steiner_on_facets;
        r.steiner_interior += added + removed;
        r.steiner_on_edges = 0;
        r.steiner_on_facets = 0;
        r.inexact_steiner = 0;
        st.inexact.clear();
        st.max_dev_scaled = 0.0;
        let on1: FacesOn = st.surf.tris.iter().map(|&t| vec![fkey(t)]).collect();
        Ok((st, cm, on1))
    }

    /// Removes every surface Steiner point of `cm` (`on`: the faces on
    /// each input triangle); returns the number of interior points added.
    fn pull_off(
        &self,
        cm: &mut CMesh<'_>,
        on: &FacesOn,
        before: usize,
    ) -> Result<usize, RecoverError> {
        let n_in = self.n_fixed();
        let mut face_tri: IdMap<[u32; 3], u32> = IdMap::default();
        let mut surface_pts: Vec<u32> = Vec::new();
        for (t, fs) in on.iter().enumerate() {
            for &f in fs {
                face_tri.insert(f, t as u32);
                surface_pts.extend(f.iter().copied().filter(|&w| w as usize >= n_in));
            }
        }
        surface_pts.sort_unstable();
        surface_pts.dedup();
        let mut added = 0;
        // A point that fails is retried after the others (their removal
        // changes its star), as long as a pass removes one.
        let mut pending = surface_pts;
        loop {
            let before_len = pending.len();
            let mut failed = Vec::new();
            for &s in &pending {
                match self.pull_one(cm, s, &mut face_tri) {
                    Some(k) => added += k,
                    None => failed.push(s),
                }
            }
            pending = failed;
            if pending.is_empty() || pending.len() == before_len {
                break;
            }
        }
        if let Some(&s) = pending.first() {
            let mut tris: Vec<usize> = cm
                .star(s)
                .iter()
                .flat_map(|&t| {
                    let tv = cm.dt.core.v[t as usize];
                    (0..4).map(move |f| fkey(face(tv, f)))
                })
                .filter_map(|k| face_tri.get(&k).map(|&t| t as usize))
                .collect();
            tris.sort_unstable();
            tris.dedup();
            return Err(RecoverError::Unrecovered {
                triangles: tris,
                steiner: before + added,
            });
        }
        let left: Vec<usize> = (0..self.surf.tris.len())
            .filter(|&t| {
                let [a, b, c] = self.surf.tris[t];
                cm.find_face(a, b, c).is_none()
            })
            .collect();
        if !left.is_empty() {
            return Err(RecoverError::Unrecovered {
                triangles: left,
                steiner: before + added,
            });
        }
        Ok(added)
    }

    /// Removes surface Steiner point `s` (module documentation);
    /// `Some(points added)`, or `None` (nothing changed).
    fn pull_one(
        &self,
        cm: &mut CMesh<'_>,
        s: u32,
        face_tri: &mut IdMap<[u32; 3], u32>,
    ) -> Option<usize> {
        let c = &cm.dt.core;
        let pts = cm.pts();
        let mut star = cm.star(s);
        star.sort_unstable();
        let at = |t: u32| star.binary_search(&t).ok();
        // Wedges: union-find across non-surface faces at `s`.
        let mut parent: Vec<usize> = (0..star.len()).collect();
        fn root(p: &mut [usize], mut i: usize) -> usize {
            while p[i] != i {
                p[i] = p[p[i]];
                i = p[i];
            }
            i
        }
        let mut tris_s: Vec<u32> = Vec::new();
        for (i, &t) in star.iter().enumerate() {
            let tv = c.v[t as usize];
            for f in 0..4 {
                if tv[f] == s {
                    continue;
                }
                let k = fkey(face(tv, f));
                if let Some(&ti) = face_tri.get(&k) {
                    tris_s.push(ti);
                    continue;
                }
                let j = at(c.adj[t as usize][f] >> 2)?;
                let (ri, rj) = (root(&mut parent, i), root(&mut parent, j));
                parent[ri.max(rj)] = ri.min(rj);
            }
        }
        tris_s.sort_unstable();
        tris_s.dedup();
        if tris_s.is_empty() {
            return None;
        }
        // The new triangulation of each polygon, as 2D-counterclockwise
        // triangles, with the projection axis.
        let mut polys: IdMap<u32, (usize, Vec<[u32; 3]>)> = IdMap::default();
        for &ti in &tris_s {
            let fan: Vec<[u32; 3]> = star
                .iter()
                .flat_map(|&t| {
                    let tv = c.v[t as usize];
                    (0..4)
                        .filter(move |&f| tv[f] != s)
                        .map(move |f| fkey(face(tv, f)))
                })
                .filter(|k| face_tri.get(k) == Some(&ti))
                .collect::<IdSet<_>>()
                .into_iter()
                .collect();
            let [a, b, cc] = self.surf.tris[ti as usize].map(|w| pts[w as usize]);
            let ax = super::super::place::dominant_axis(&a, &b, &cc);
            let tri = polygon_without(pts, &fan, s, ax)?;
            polys.insert(ti, (ax, tri));
        }
        // Per wedge: its tetrahedra.
        let mut wedges: Vec<Vec<usize>> = Vec::new();
        let mut wid: IdMap<usize, usize> = IdMap::default();
        for i in 0..star.len() {
            let r = root(&mut parent, i);
            let w = *wid.entry(r).or_insert_with(|| {
                wedges.push(Vec::new());
                wedges.len() - 1
            });
            wedges[w].push(i);
        }
        let mut all_pts: Vec<P> = pts.to_vec();
        let mut new: Vec<[u32; 4]> = Vec::new();
        let mut added = 0;
        // Tetrahedra outside the star that wedges grew by.
        let mut extra: Vec<u32> = Vec::new();
        for w in &wedges {
            let ghosts = w
                .iter()
                .filter(|&&i| c.v[star[i] as usize].contains(&INF))
                .count();
            let mut link: Vec<([u32; 3], u32, usize)> = Vec::new();
            // Surface faces of the wedge (inward), per input triangle.
            let mut fans: Vec<([u32; 3], u32)> = Vec::new();
            for &i in w {
                let tv = c.v[star[i] as usize];
                for f in 0..4 {
                    let fv = face(tv, f);
                    if tv[f] == s {
                        link.push((fv, star[i], f));
                    } else if let Some(&ti) = face_tri.get(&fkey(fv)) {
                        fans.push((fv, ti));
                    }
                }
            }
            // The new triangles of the wedge's polygons, oriented like its
            // old surface faces there.
            let mut bound: Vec<[u32; 3]> = Vec::new();
            let mut seen: Vec<u32> = Vec::new();
            for &(fv, ti) in &fans {
                if seen.contains(&ti) {
                    continue;
                }
                seen.push(ti);
                let (ax, tris) = polys.get(&ti)?;
                let pr = |w: u32| project(&pts[w as usize], *ax);
                let [x, y, z] = fv.map(pr);
                let sign = orient2d(&x, &y, &z);
                if sign == 0.0 {
                    return None;
                }
                for t in tris {
                    bound.push(if sign > 0.0 { *t } else { [t[0], t[2], t[1]] });
                }
            }
            if ghosts == w.len() {
                // Outside a hull triangle: ghosts on the new triangles,
                // oriented like the old ghosts' hull faces.
                for t in bound {
                    let g = [t[0], t[1], t[2], INF];
                    new.push(if okey(face(g, 3)) == okey(t) {
                        g
                    } else {
                        [t[0], t[2], t[1], INF]
                    });
                }
                continue;
            }
            if ghosts > 0 {
                return None;
            }
            // Into the wedge: the unit normals of its input triangles,
            // oriented towards it, one per triangle (their sum points
            // strictly into every one's open half-space); then other
            // directions, each checked exactly.
            let sp = pts[s as usize];
            let mut normals: Vec<P> = Vec::new();
            let mut done: Vec<u32> = Vec::new();
            for &(fv, ti) in &fans {
                if done.contains(&ti) {
                    continue;
                }
                done.push(ti);
                let [a, b, cc] = fv.map(|w| pts[w as usize]);
                let nf = cross(&sub(&b, &a), &sub(&cc, &a));
                let [a, b, cc] = self.surf.tris[ti as usize].map(|w| pts[w as usize]);
                let mut n = cross(&sub(&b, &a), &sub(&cc, &a));
                let l = dot(&n, &n).sqrt();
                if l == 0.0 || !l.is_finite() {
                    return None;
                }
                let sg = if dot(&n, &nf) < 0.0 { -1.0 } else { 1.0 };
                n = n.map(|x| sg * x / l);
                normals.push(n);
            }
            let mut reach = f64::INFINITY;
            let mut centre = [0.0; 3];
            let mut nc: f64 = 0.0;
            for f in bound.iter().chain(link.iter().map(|l| &l.0)) {
                for &x in f {
                    if x != s {
                        let e = sub(&pts[x as usize], &sp);
                        reach = reach.min(dot(&e, &e).sqrt());
                        for k in 0..3 {
                            centre[k] += e[k];
                        }
                        nc += 1.0;
                    }
                }
            }
            if !reach.is_finite() || reach == 0.0 {
                return None;
            }
            let mut dirs: Vec<P> = vec![normals
                .iter()
                .fold([0.0; 3], |d, n| [d[0] + n[0], d[1] + n[1], d[2] + n[2]])];
            dirs.push(centre.map(|x| x / nc.max(1.0)));
            dirs.extend(normals.iter().copied());
            let id = all_pts.len() as u32;
            let mut found = None;
            // Growth: the tetrahedra behind the faces opposite `s` that the
            // best candidate does not see (nearly flat tetrahedra of
            // inexact surface points), never across the surface.
            let mut grown: Vec<u32> = Vec::new();
            for _ in 0..=MAX_GROW {
                let nb = bound.len();
                let all: Vec<[u32; 3]> = bound
                    .iter()
                    .copied()
                    .chain(link.iter().map(|l| l.0))
                    .collect();
                let mut fewest: Option<Vec<usize>> = None;
                'dirs: for d in &dirs {
                    let dl = dot(d, d).sqrt();
                    if dl == 0.0 || !dl.is_finite() {
                        continue;
                    }
                    let mut h = 0.25 * reach;
                    for _ in 0..HALVINGS {
                        let p = [0, 1, 2].map(|k| sp[k] + h * d[k] / dl);
                        let bad: Vec<usize> = (0..all.len())
                            .filter(|&k| {
                                let [a, b, cc] = all[k].map(|w| &all_pts[w as usize]);
                                orient3d(a, b, cc, &p) >= 0.0
                            })
                            .collect();
                        if bad.is_empty() {
                            found = Some(p);
                            break 'dirs;
                        }
                        if bad.iter().all(|&k| k >= nb)
                            && fewest.as_ref().is_none_or(|f| bad.len() < f.len())
                        {
                            fewest = Some(bad);
                        }
                        h *= 0.5;
                    }
                }
                if found.is_some() {
                    break;
                }
                let bad = fewest?;
                let mut more = false;
                for k in bad {
                    let (fv, t, f) = link[k - nb];
                    let n = c.adj[t as usize][f] >> 2;
                    let nv = c.v[n as usize];
                    if face_tri.contains_key(&fkey(fv))
                        || nv[0] == DEAD
                        || nv.contains(&INF)
                        || star.binary_search(&n).is_ok()
                        || grown.contains(&n)
                        || extra.contains(&n)
                    {
                        continue;
                    }
                    grown.push(n);
                    more = true;
                }
                if !more {
                    return None;
                }
                // The wedge's faces opposite `s`, with the grown tetrahedra.
                let mut set: Vec<u32> = w.iter().map(|&i| star[i]).collect();
                set.extend(&grown);
                link.clear();
                for &t in &set {
                    let tv = c.v[t as usize];
                    for f in 0..4 {
                        let fv = face(tv, f);
                        // Faces at `s` are its surface faces (new triangles).
                        if !set.contains(&(c.adj[t as usize][f] >> 2)) && !fv.contains(&s) {
                            link.push((fv, t, f));
                        }
                    }
                }
            }
            extra.extend(&grown);
            let p = found?;
            if !self.off_surface(&all_pts, &p) {
                return None;
            }
            all_pts.push(p);
            added += 1;
            for f in bound.into_iter().chain(link.into_iter().map(|l| l.0)) {
                new.push([f[0], f[1], f[2], id]);
            }
        }
        let mut old: Vec<u32> = star.clone();
        old.extend(&extra);
        old.sort_unstable();
        if old.windows(2).any(|x| x[0] == x[1]) {
            return None;
        }
        if !valid_star(cm, &all_pts, &old, &new, s) {
            return None;
        }
        // Update the surface faces: the fans give way to the polygons.
        for &t in &old {
            let tv = c.v[t as usize];
            for f in 0..4 {
                if tv[f] != s {
                    face_tri.remove(&fkey(face(tv, f)));
                }
            }
        }
        for (&ti, (_, tris)) in &polys {
            for t in tris {
                face_tri.insert(fkey(*t), ti);
            }
        }
        for p in &all_pts[cm.pts().len()..] {
            cm.dt.points.to_mut().push(*p);
        }
        cm.replace(&old, &new);
        Some(added)
    }
}

/// Projection of `p` dropping coordinate `ax`.
fn project(p: &P, ax: usize) -> [f64; 2] {
    match ax {
        0 => [p[1], p[2]],
        1 => [p[2], p[0]],
        _ => [p[0], p[1]],
    }
}

/// The polygon covered by the `fan` of faces at `s` (unoriented keys), as
/// a cycle without `s`, triangulated by ear clipping in the projection
/// along `ax`: 2D-counterclockwise triangles, or `None`.
fn polygon_without(pts: &[P], fan: &[[u32; 3]], s: u32, ax: usize) -> Option<Vec<[u32; 3]>> {
    // Link edges (opposite `s`) and the degree of each link vertex.
    let mut adj: IdMap<u32, Vec<u32>> = IdMap::default();
    for f in fan {
        let o: Vec<u32> = f.iter().copied().filter(|&w| w != s).collect();
        if o.len() != 2 {
            return None;
        }
        adj.entry(o[0]).or_default().push(o[1]);
        adj.entry(o[1]).or_default().push(o[0]);
    }
    let mut verts: Vec<u32> = adj.keys().copied().collect();
    verts.sort_unstable();
    if adj.values().any(|v| v.len() > 2) {
        return None;
    }
    // A path (s on an edge: from one end of degree 1) or a cycle.
    let start = verts
        .iter()
        .copied()
        .find(|w| adj[w].len() == 1)
        .or_else(|| verts.first().copied())?;
    let mut cyc = vec![start];
    let mut prev = u32::MAX;
    let mut cur = start;
    loop {
        let next = adj[&cur]
            .iter()
            .copied()
            .find(|&x| x != prev && !cyc.contains(&x));
        match next {
            Some(x) => {
                cyc.push(x);
                prev = cur;
                cur = x;
            }
            None => break,
        }
    }
    if cyc.len() != verts.len() || cyc.len() < 3 {
        return None;
    }
    let p2: Vec<[f64; 2]> = cyc.iter().map(|&w| project(&pts[w as usize], ax)).collect();
    // Counterclockwise.
    let mut area = 0.0;
    for i in 0..p2.len() {
        let (a, b) = (p2[i], p2[(i + 1) % p2.len()]);
        area += a[0] * b[1] - a[1] * b[0];
    }
    let mut idx: Vec<usize> = (0..cyc.len()).collect();
    if area < 0.0 {
        idx.reverse();
    }
    let mut out = Vec::new();
    while idx.len() > 3 {
        let n = idx.len();
        // Of the ears, the roundest (twice its area over its longest edge
        // squared): thin ears tilt out of the triangle's plane.
        let ear = (0..n)
            .filter(|&i| {
                let (u, v, w) = (idx[(i + n - 1) % n], idx[i], idx[(i + 1) % n]);
                if orient2d(&p2[u], &p2[v], &p2[w]) <= 0.0 {
                    return false;
                }
                idx.iter().all(|&x| {
                    x == u
                        || x == v
                        || x == w
                        || orient2d(&p2[u], &p2[v], &p2[x]) < 0.0
                        || orient2d(&p2[v], &p2[w], &p2[x]) < 0.0
                        || orient2d(&p2[w], &p2[u], &p2[x]) < 0.0
                })
            })
            .map(|i| {
                let (u, v, w) = (idx[(i + n - 1) % n], idx[i], idx[(i + 1) % n]);
                (roundness(&p2[u], &p2[v], &p2[w]), i)
            })
            .max_by(|a, b| a.0.total_cmp(&b.0).then(b.1.cmp(&a.1)))?
            .1;
        let (u, v, w) = (idx[(ear + n - 1) % n], idx[ear], idx[(ear + 1) % n]);
        out.push([cyc[u], cyc[v], cyc[w]]);
        idx.remove(ear);
    }
    let (u, v, w) = (idx[0], idx[1], idx[2]);
    if orient2d(&p2[u], &p2[v], &p2[w]) <= 0.0 {
        return None;
    }
    out.push([cyc[u], cyc[v], cyc[w]]);
    Some(out)
}

/// Twice the area of `a b c` over its longest edge squared.
fn roundness(a: &[f64; 2], b: &[f64; 2], c: &[f64; 2]) -> f64 {
    let d2 = |p: &[f64; 2], q: &[f64; 2]| (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2);
    let area2 = ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])).abs();
    let l = d2(a, b).max(d2(b, c)).max(d2(c, a));
    if l > 0.0 {
        area2 / l
    } else {
        0.0
    }
}

/// Exact validation of replacing the star `old` (sorted) of `s` by `new`
/// (module documentation).
fn valid_star(cm: &CMesh<'_>, pts: &[P], old: &[u32], new: &[[u32; 4]], s: u32) -> bool {
    let c = &cm.dt.core;
    for tv in new {
        if tv.contains(&s) || tv.iter().any(|&w| w != INF && w as usize >= pts.len()) {
            return false;
        }
        if !tv.contains(&INF) {
            let g = |i: usize| &pts[tv[i] as usize];
            if orient3d(g(0), g(1), g(2), g(3)) >= 0.0 {
                return false;
            }
        }
    }
    let mut count: IdMap<[u32; 3], u32> = IdMap::default();
    let mut new_verts: IdSet<u32> = IdSet::default();
    let mut new_edges: IdSet<(u32, u32)> = IdSet::default();
    for &tv in new {
        for f in 0..4 {
            *count.entry(okey(face(tv, f))).or_insert(0) += 1;
        }
        for i in 0..4 {
            new_verts.insert(tv[i]);
            for j in i + 1..4 {
                new_edges.insert((tv[i].min(tv[j]), tv[i].max(tv[j])));
            }
        }
    }
    if count.values().any(|&n| n != 1) {
        return false;
    }
    if !super::fills_boundary(cm, old, &count) {
        return false;
    }
    let mut old_edges: IdSet<(u32, u32)> = IdSet::default();
    for &t in old {
        let tv = c.v[t as usize];
        if tv[0] == DEAD {
            return false;
        }
        for i in 0..4 {
            if tv[i] != s && !new_verts.contains(&tv[i]) {
                return false;
            }
            for j in i + 1..4 {
                old_edges.insert((tv[i].min(tv[j]), tv[i].max(tv[j])));
            }
        }
    }
    // A new edge between old vertices must not exist outside the star.
    let n_old = cm.pts().len();
    new_edges.iter().all(|&(x, y)| {
        old_edges.contains(&(x, y))
            || y == INF
            || x as usize >= n_old
            || y as usize >= n_old
            || cm.find_edge(x, y).is_none()
    })
}

#[cfg(test)]
mod tests {
    use super::super::super::surface::Surface;
    use super::super::super::RecoverOptions;
    use super::*;

    fn state(n: usize, tris: &[[u32; 3]]) -> State {
        State::new(
            Surface::new(n, tris),
            RecoverOptions {
                preserve_surface: true,
                ..Default::default()
            },
        )
    }

    /// The box `[0,w]×[0,d]×[0,h]`, two outward triangles per side.
    fn cuboid(w: f64, d: f64, h: f64) -> (Vec<P>, Vec<[u32; 3]>) {
        let pts = (0..8)
            .map(|i| {
                [
                    f64::from(i & 1) * w,
                    f64::from((i >> 1) & 1) * d,
                    f64::from((i >> 2) & 1) * h,
                ]
            })
            .collect();
        let tris = vec![
            [0, 2, 1],
            [1, 2, 3],
            [4, 5, 6],
            [5, 7, 6],
            [0, 1, 4],
            [1, 5, 4],
            [2, 6, 3],
            [3, 6, 7],
            [0, 4, 2],
            [2, 4, 6],
            [1, 3, 5],
            [3, 7, 5],
        ];
        (pts, tris)
    }

    /// Schönhardt's twisted prism, each side split by its reflex diagonal.
    fn schonhardt(twist: f64) -> (Vec<P>, Vec<[u32; 3]>) {
        let mut pts = Vec::new();
        for (k, z) in [(0.0, 0.0), (twist, 1.0)] {
            for i in 0..3 {
                let a = (120.0 * f64::from(i) + k).to_radians();
                pts.push([a.cos(), a.sin(), z]);
            }
        }
        let hull: Vec<[u32; 3]> = crate::tetrahedralize(&pts).unwrap().hull_faces().collect();
        let hull_edge = |a: u32, b: u32| hull.iter().any(|f| f.contains(&a) && f.contains(&b));
        let mut tris = vec![[0, 2, 1], [3, 4, 5]];
        for i in 0..3u32 {
            let j = (i + 1) % 3;
            let (a0, a1, b0, b1) = (i, j, i + 3, j + 3);
            if hull_edge(a0, b1) {
                tris.push([a0, a1, b0]);
                tris.push([a1, b1, b0]);
            } else {
                tris.push([a0, a1, b1]);
                tris.push([a0, b1, b0]);
            }
        }
        (pts, tris)
    }

    /// Models on which the `-p` path splits edges and triangles (and thin
    /// boxes, on which it may not); the fallback must leave every input
    /// triangle one face, a valid mesh, and no used point on the surface
    /// but the input vertices.
    #[test]
    fn fallback_pulls_points_off_the_surface() {
        let mut total = 0;
        let mut models: Vec<(Vec<P>, Vec<[u32; 3]>)> = [10.0, 30.0, 55.0].map(schonhardt).to_vec();
        for (w, d, h) in [(10.0, 1.0, 0.001), (1.0, 1.0, 1e-6), (100.0, 0.01, 1.0)] {
            models.push(cuboid(w, d, h));
        }
        for (pts, tris) in models {
            let st = state(pts.len(), &tris);
            let (st2, cm, on) = st.preserve_fallback(&pts).unwrap();
            // Valid mesh: positive finite tetrahedra, symmetric adjacency
            // with matching faces (the removed points are left unused).
            let c = &cm.dt.core;
            for (t, tv) in c.v.iter().enumerate() {
                if tv[0] == DEAD {
                    continue;
                }
                assert!(tv.contains(&INF) || cm.positive(*tv), "{tv:?}");
                for f in 0..4 {
                    let w = c.adj[t][f];
                    let (n, g) = ((w >> 2) as usize, (w & 3) as usize);
                    assert_eq!(c.adj[n][g] >> 2, t as u32);
                    assert_eq!(fkey(face(*tv, f)), fkey(face(c.v[n], g)));
                }
            }
            assert_eq!(on.len(), tris.len());
            for t in &tris {
                assert!(cm.find_face(t[0], t[1], t[2]).is_some(), "{t:?}");
            }
            let c = &cm.dt.core;
            for tv in &c.v {
                if tv[0] == DEAD {
                    continue;
                }
                for &w in tv {
                    if w != INF && w as usize >= pts.len() {
                        assert!(st2.off_surface(cm.pts(), &cm.pts()[w as usize]));
                    }
                }
            }
            assert_eq!(
                st2.report.steiner_on_edges + st2.report.steiner_on_facets,
                0
            );
            total += st2.report.steiner_interior;
        }
        assert!(total > 0, "the -p path put no point on the surface");
    }
}
