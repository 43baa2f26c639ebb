//! Merging of coplanar input triangles into facets before recovery
//! (TetGen's default; `-M` turns it off).
//!
//! **Groups.** Two input triangles are merged when they share an edge that
//! is in exactly these two triangles, lie exactly on one plane (exact
//! `orient3d = 0`), are consistently oriented (the edge is used in opposite
//! directions and the triangles lie on opposite sides of it, so their
//! normals agree) and carry the same marker (when markers are given: the
//! facet markers of a PLC). Groups are the connected components of this
//! relation (union–find), named by their lowest triangle index.
//!
//! **Re-triangulation.** A group of two or more triangles covers a planar
//! polygon, maybe with holes. It is triangulated again so that the
//! recovery has the easiest job: every vertex of the group stays, and so
//! does every *kept* edge — each edge of the group except those shared by
//! exactly two of its triangles (the group's boundary, plus non-manifold
//! edges inside it). Inside, the edges of the Delaunay tetrahedralization
//! (the one the recovery starts from) joining two vertices of the group and
//! crossing no kept edge are imposed as well, so the mesh already holds
//! those edges (and the Delaunay faces on the plane); a 2D constrained
//! Delaunay triangulation ([`crate::tri::constrain::constrained_triangulation`],
//! on the two coordinates of the plane's dominant normal axis, kept and
//! Delaunay edges as segments) completes the rest. Its triangles inside the
//! region are found by flood fill from the group's oriented boundary edges
//! (a triangle on the left of a boundary edge, in the group's orientation,
//! is inside; on its right, outside), across the edges that are not
//! boundary edges. Every decision uses exact predicates.
//!
//! Whenever anything is unexpected (the 2D triangulation adds or merges a
//! point, a component is both inside and outside, the triangle count or
//! the area differs), the group keeps its original triangles.
//!
//! **After recovery.** The rest of the pipeline runs on the new triangle
//! list, `Recovered::surface`; `boundary_triangle` / `interior_triangle`
//! index it and `surface_origin` maps each of its triangles back to an input
//! triangle of the group (for facet markers). `check_recovered` checks the
//! mesh against `surface` per facet (the surface triangles sharing one
//! `surface_origin`: a recovered or refined planar facet may cross its
//! group's inner edges) and that each coplanar group of the input has the
//! same plane, orientation, oriented boundary and area in `surface`. The
//! refinement keeps the merging: a merged group is one facet there too, and
//! a split on it re-triangulates the facet Delaunay in its own plane, which
//! keeps `-q1.414` from halving subsegments towards their input vertices.
//! Merging is always off with `-Y`.

use std::collections::HashMap;

use delone_predicates::{orient2d, orient3d};

use super::types::Recovered;
use crate::geom::vec3::{cross, sub};
use crate::model::pslg::Pslg;
use crate::tet::intersect::coplanar_groups;
use crate::tet::local::ekey;
use crate::tet::local::{DEAD, INF};
use crate::tet::Delaunay3;
use crate::tri::constrain::{constrained_triangulation, CdtOptions};
use crate::{Violation, NONE};

/// The surface the recovery conforms to.
pub(crate) struct Merged {
    /// Triangles (input ones and re-triangulated groups).
    pub tris: Vec<[u32; 3]>,
    /// Per triangle: an input triangle of the same group.
    pub origin: Vec<u32>,
    /// Groups of two or more triangles re-triangulated.
    pub groups: usize,
    /// Groups of two or more triangles kept as given (re-triangulation
    /// failed).
    pub kept: usize,
}

impl Merged {
    /// The input triangles unchanged.
    pub fn identity(triangles: &[[u32; 3]]) -> Self {
        Merged {
            tris: triangles.to_vec(),
            origin: (0..triangles.len() as u32).collect(),
            groups: 0,
            kept: 0,
        }
    }
}

/// The axis dropped to project the plane of `a b c` (the largest normal
/// component whose projected orientation is exactly nonzero) and the sign
/// of that orientation; `None` for a degenerate triangle.
pub(super) fn projection(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3]) -> Option<(usize, f64)> {
    let n = cross(&sub(b, a), &sub(c, a));
    let mut axes = [0usize, 1, 2];
    axes.sort_by(|&i, &j| n[j].abs().total_cmp(&n[i].abs()).then(i.cmp(&j)));
    for k in axes {
        let o = orient2d(&proj(a, k), &proj(b, k), &proj(c, k));
        if o != 0.0 {
            return Some((k, o.signum()));
        }
    }
    None
}

/// `p` without coordinate `k` (a right-handed frame of the other two).
pub(super) fn proj(p: &[f64; 3], k: usize) -> [f64; 2] {
    [p[(k + 1) % 3], p[(k + 2) % 3]]
}

/// Merges the coplanar groups of (`points`, `triangles`) and
/// re-triangulates each (see the module notes), using the edges of `dt`
/// (a Delaunay tetrahedralization of `points`, same ids). The surface is
/// closed (validated): `nonmanifold`, sorted, are its edges in more than
/// two triangles, every other edge is in exactly two. `unmarked`, when
/// given, are the triangles' [`coplanar_groups`] without markers (found by
/// the input validation): the groups are those where every triangle
/// carries one marker, else they are found again with the markers.
pub(crate) fn merge(
    points: &[[f64; 3]],
    triangles: &[[u32; 3]],
    marker: &[i32],
    (unmarked, nonmanifold): (Option<Vec<u32>>, &[[u32; 2]]),
    dt: &Delaunay3<'_>,
) -> Merged {
    let group = match unmarked {
        Some(g) if g.len() == triangles.len() && one_marker_each(&g, marker) => g,
        _ => coplanar_groups(points, triangles, marker),
    };
    let mut size = vec![0u32; triangles.len()];
    for &r in &group {
        size[r as usize] += 1;
    }
    // Groups of two or more triangles: dense ids, and per vertex the
    // groups holding it.
    let big: Vec<u32> = (0..triangles.len() as u32)
        .filter(|&r| size[r as usize] >= 2)
        .collect();
    if big.is_empty() {
        return Merged::identity(triangles);
    }
    // Members of those groups only (no list per single triangle).
    let mut members: Vec<Vec<u32>> = vec![Vec::new(); triangles.len()];
    for (t, &r) in group.iter().enumerate() {
        if size[r as usize] >= 2 {
            members[r as usize].push(t as u32);
        }
    }
    let mut vgroups: Vec<Vec<u32>> = vec![Vec::new(); points.len()];
    for (gi, &r) in big.iter().enumerate() {
        for &t in &members[r as usize] {
            for q in triangles[t as usize] {
                let l = &mut vgroups[q as usize];
                if l.last() != Some(&(gi as u32)) {
                    l.push(gi as u32);
                }
            }
        }
    }
    // Delaunay edges between two vertices of one group, ordered by (group,
    // u, v): each edge once (ascending `u << 32 | v`; an edge is in several
    // tetrahedra), then filed under its groups by a stable counting sort.
    // The edges of the tetrahedra, (u, v) with u < v, are filed under u by
    // a counting sort (no global sort); each bucket keeps each v once (a
    // stamp per vertex) and is sorted. `last[u]`: the v last filed from u
    // (the tetrahedra around an edge are often consecutive slots, so many
    // repeats are dropped at once).
    let core = &dt.core;
    let nv = vgroups.len();
    let grouped: Vec<bool> = vgroups.iter().map(|l| !l.is_empty()).collect();
    let mut last = vec![u32::MAX; nv];
    let mut raw: Vec<(u32, u32)> = Vec::new();
    for tv in &core.v {
        if tv[0] == DEAD || tv.contains(&INF) {
            continue;
        }
        let on = tv.map(|w| grouped.get(w as usize).copied().unwrap_or(false));
        if on.iter().filter(|&&b| b).count() < 2 {
            continue;
        }
        for (i, j) in crate::tet::local::EDGES {
            if on[i] && on[j] {
                let (u, v) = ekey(tv[i], tv[j]);
                if last[u as usize] != v {
                    last[u as usize] = v;
                    raw.push((u, v));
                }
            }
        }
    }
    drop(last);
    let (from, mut other) = crate::geom::rows(nv, &raw);
    drop(raw);
    let mut seen = vec![u32::MAX; nv];
    let mut edges: Vec<u64> = Vec::new();
    for u in 0..nv {
        let bucket = &mut other[from[u] as usize..from[u + 1] as usize];
        let mut k = 0;
        for i in 0..bucket.len() {
            let v = bucket[i];
            if seen[v as usize] != u as u32 {
                seen[v as usize] = u as u32;
                bucket[k] = v;
                k += 1;
            }
        }
        let bucket = &mut bucket[..k];
        bucket.sort_unstable();
        edges.extend(bucket.iter().map(|&v| (u as u64) << 32 | u64::from(v)));
    }
    let vg = &vgroups;
    let common = |e: u64| {
        let (u, v) = ((e >> 32) as usize, e as u32 as usize);
        vg[u].iter().filter(move |g| vg[v].contains(g))
    };
    let mut at = vec![0usize; big.len() + 1];
    for &e in &edges {
        for &g in common(e) {
            at[g as usize + 1] += 1;
        }
    }
    for g in 0..big.len() {
        at[g + 1] += at[g];
    }
    let mut cand: Vec<(u32, u32, u32)> = vec![(0, 0, 0); at[big.len()]];
    for &e in &edges {
        for &g in common(e) {
            cand[at[g as usize]] = (g, (e >> 32) as u32, e as u32);
            at[g as usize] += 1;
        }
    }
    let mut new_tris: Vec<Option<Vec<[u32; 3]>>> = vec![None; big.len()];
    let mut start = 0;
    let mut kept = 0;
    for (gi, &r) in big.iter().enumerate() {
        let mut end = start;
        while end < cand.len() && cand[end].0 == gi as u32 {
            end += 1;
        }
        let dt_edges: Vec<(u32, u32)> = cand[start..end].iter().map(|c| (c.1, c.2)).collect();
        start = end;
        let tris: Vec<[u32; 3]> = members[r as usize]
            .iter()
            .map(|&t| triangles[t as usize])
            .collect();
        let out = retriangulate(points, &tris, &dt_edges, &|e| {
            nonmanifold.binary_search(&[e.0, e.1]).is_ok()
        });
        match out {
            Some(o) => new_tris[gi] = Some(o),
            None => kept += 1,
        }
    }
    // Per group root: its dense id.
    let mut gidx: Vec<u32> = vec![u32::MAX; triangles.len()];
    for (gi, &r) in big.iter().enumerate() {
        gidx[r as usize] = gi as u32;
    }
    let mut out = Merged {
        tris: Vec::with_capacity(triangles.len()),
        origin: Vec::with_capacity(triangles.len()),
        groups: big.len() - kept,
        kept,
    };
    for (t, tv) in triangles.iter().enumerate() {
        let r = group[t];
        match new_tris
            .get(gidx[r as usize] as usize)
            .and_then(Option::as_ref)
        {
            Some(nt) => {
                if r as usize == t {
                    out.tris.extend_from_slice(nt);
                    out.origin.extend(std::iter::repeat_n(r, nt.len()));
                }
            }
            None => {
                out.tris.push(*tv);
                out.origin.push(t as u32);
            }
        }
    }
    out
}

/// Whether every group of `group` (triangle -> lowest triangle of its
/// group) carries one marker of `marker` (empty: no markers). Then the
/// groups with markers are these: every edge joining two triangles of a
/// group joins equal markers.
fn one_marker_each(group: &[u32], marker: &[i32]) -> bool {
    marker.is_empty()
        || (marker.len() == group.len()
            && group
                .iter()
                .zip(marker)
                .all(|(&r, m)| marker[r as usize] == *m))
}

/// Directed edges of `tris` whose reverse is not among them (the oriented
/// boundary of the group), sorted, with multiplicity.
pub(super) fn oriented_boundary(tris: &[[u32; 3]]) -> Vec<(u32, u32)> {
    // The sides by undirected edge (a sort, no map): an edge's uses from
    // its smaller end minus those towards it are its multiplicity in the
    // boundary, directed by the sign.
    let mut sides: Vec<(u32, u32, bool)> = tris
        .iter()
        .flat_map(|tv| {
            (0..3).map(move |k| {
                let (u, v) = (tv[k], tv[(k + 1) % 3]);
                (u.min(v), u.max(v), u < v)
            })
        })
        .filter(|s| s.0 != s.1)
        .collect();
    sides.sort_unstable();
    let mut out = Vec::new();
    for run in sides.chunk_by(|a, b| (a.0, a.1) == (b.0, b.1)) {
        let up = run.iter().filter(|s| s.2).count() as i64;
        let c = 2 * up - run.len() as i64;
        let e = if c > 0 {
            (run[0].0, run[0].1)
        } else {
            (run[0].1, run[0].0)
        };
        out.extend(std::iter::repeat_n(e, c.unsigned_abs() as usize));
    }
    out.sort_unstable();
    out
}

/// Re-triangulates one group (`tris`, coplanar and consistently oriented)
/// with the Delaunay edges `dt_edges` between its vertices; `None` when
/// anything is unexpected.
fn retriangulate(
    points: &[[f64; 3]],
    tris: &[[u32; 3]],
    dt_edges: &[(u32, u32)],
    nonmanifold: &dyn Fn((u32, u32)) -> bool,
) -> Option<Vec<[u32; 3]>> {
    let g = |q: u32| &points[q as usize];
    let [a, b, c] = tris[0];
    let (k, sign) = projection(g(a), g(b), g(c))?;
    let mut verts: Vec<u32> = tris.iter().flatten().copied().collect();
    verts.sort_unstable();
    verts.dedup();
    let local = |q: u32| verts.binary_search(&q).ok().map(|i| i as u32);
    let xy: Vec<[f64; 2]> = verts.iter().map(|&q| proj(g(q), k)).collect();
    // Kept edges: the oriented boundary's, and every edge of the group not
    // in exactly two input triangles (`nonmanifold`, global ids). Sets are
    // sorted lists (local ids follow global ones, so the order carries
    // over).
    let mut uses: Vec<(u32, u32)> = tris
        .iter()
        .flat_map(|tv| (0..3).map(move |i| ekey(tv[i], tv[(i + 1) % 3])))
        .collect();
    uses.sort_unstable();
    // Oriented boundary, normalised to counterclockwise in the projection.
    let mut boundary: Vec<(u32, u32)> = oriented_boundary(tris)
        .into_iter()
        .map(|(u, v)| if sign > 0.0 { (u, v) } else { (v, u) })
        .filter_map(|(u, v)| Some((local(u)?, local(v)?)))
        .collect();
    boundary.sort_unstable();
    boundary.dedup();
    let on_boundary = |e: (u32, u32)| boundary.binary_search(&e).is_ok();
    let mut kept: Vec<(u32, u32)> = Vec::new();
    for run in uses.chunk_by(|a, b| a == b) {
        let e = run[0];
        let (u, v) = (local(e.0)?, local(e.1)?);
        if run.len() != 2 || on_boundary((u, v)) || on_boundary((v, u)) || nonmanifold(e) {
            kept.push(ekey(u, v));
        }
    }
    let is_kept = |e: (u32, u32)| kept.binary_search(&e).is_ok();
    let bbox = |(u, v): (u32, u32)| {
        let (p, q) = (xy[u as usize], xy[v as usize]);
        [
            p[0].min(q[0]),
            p[1].min(q[1]),
            p[0].max(q[0]),
            p[1].max(q[1]),
        ]
    };
    let kept_boxes: Vec<[f64; 4]> = kept.iter().map(|&e| bbox(e)).collect();
    let mut segments: Vec<[u32; 2]> = kept.iter().map(|&(u, v)| [u, v]).collect();
    for &(u, v) in dt_edges {
        let (u, v) = ekey(local(u)?, local(v)?);
        if is_kept((u, v)) {
            continue;
        }
        let bx = bbox((u, v));
        let (pu, pv) = (xy[u as usize], xy[v as usize]);
        let crosses = kept.iter().zip(&kept_boxes).any(|(&(x, y), b)| {
            if x == u || x == v || y == u || y == v {
                return false;
            }
            if b[0] > bx[2] || bx[0] > b[2] || b[1] > bx[3] || bx[1] > b[3] {
                return false;
            }
            let (px, py) = (xy[x as usize], xy[y as usize]);
            let (o1, o2) = (orient2d(&px, &py, &pu), orient2d(&px, &py, &pv));
            let (o3, o4) = (orient2d(&pu, &pv, &px), orient2d(&pu, &pv, &py));
            // Proper crossings and touchings both exclude the edge.
            (o1 * o2 <= 0.0) && (o3 * o4 <= 0.0)
        });
        if !crosses {
            segments.push([u, v]);
        }
    }
    let pslg = Pslg::new(xy.clone(), segments);
    let cdt = constrained_triangulation(&pslg, CdtOptions { convex_hull: true }).ok()?;
    let r = &cdt.report;
    if cdt.points.len() != verts.len()
        || !r.crossings.is_empty()
        || !r.vertex_splits.is_empty()
        || !r.duplicate_points.is_empty()
    {
        return None;
    }
    // Flood fill from the oriented boundary edges.
    let nt = cdt.triangles.len();
    let mut label = vec![0u8; nt];
    let mut stack: Vec<usize> = Vec::new();
    for (t, tv) in cdt.triangles.iter().enumerate() {
        for i in 0..3 {
            let (x, y) = (tv[(i + 1) % 3], tv[(i + 2) % 3]);
            let want = if on_boundary((x, y)) {
                1
            } else if on_boundary((y, x)) {
                2
            } else {
                continue;
            };
            if label[t] != 0 && label[t] != want {
                return None;
            }
            if label[t] == 0 {
                label[t] = want;
                stack.push(t);
            }
        }
    }
    while let Some(t) = stack.pop() {
        let tv = cdt.triangles[t];
        for i in 0..3 {
            let (x, y) = (tv[(i + 1) % 3], tv[(i + 2) % 3]);
            if on_boundary((x, y)) || on_boundary((y, x)) {
                continue;
            }
            let n = cdt.neighbors[t][i];
            if n == NONE {
                continue;
            }
            let n = n as usize;
            if label[n] == 0 {
                label[n] = label[t];
                stack.push(n);
            } else if label[n] != label[t] {
                return None;
            }
        }
    }
    let mut out = Vec::new();
    let mut area_new = 0.0;
    for (t, tv) in cdt.triangles.iter().enumerate() {
        if label[t] != 1 {
            continue;
        }
        let [x, y, z] = tv.map(|q| verts[q as usize]);
        let [p, q, s] = tv.map(|q| xy[q as usize]);
        area_new += orient2d(&p, &q, &s).abs();
        out.push(if sign > 0.0 { [x, y, z] } else { [x, z, y] });
    }
    let area_old: f64 = tris
        .iter()
        .map(|tv| {
            let [p, q, s] = tv.map(|w| proj(g(w), k));
            orient2d(&p, &q, &s).abs()
        })
        .sum();
    if out.len() != tris.len() || (area_new - area_old).abs() > 1e-9 * area_old {
        return None;
    }
    Some(out)
}

/// Checks that `rec.surface` replaces the input triangles faithfully: in
/// range, `surface_origin` naming input triangles, and for every coplanar
/// group of the input (merged regardless of markers), the surface triangles
/// of that group lie exactly on its plane, are oriented like it (same sign
/// of the projected orientation, never degenerate), have the same oriented
/// boundary (directed edges whose reverse is absent) and the same area.
/// Together these make the group's new triangles cover exactly its region
/// once.
pub(crate) fn check_surface(
    points: &[[f64; 3]],
    triangles: &[[u32; 3]],
    rec: &Recovered,
) -> Result<(), Violation> {
    let bad = |d: String| Err(Violation::new("surface", d));
    // On a copy scaled by a power of two (exact), as recovery sees them:
    // the products of the predicates and areas neither over- nor underflow.
    let (points, _) = crate::geom::rescaled(points);
    let points: &[[f64; 3]] = &points;
    if rec.surface.len() != rec.surface_origin.len() {
        return bad("surface and surface_origin lengths differ".into());
    }
    if let Some(i) = rec
        .surface
        .iter()
        .position(|t| t.iter().any(|&q| q as usize >= points.len()))
    {
        return bad(format!("surface triangle {i} names a missing point"));
    }
    if let Some(i) = rec
        .surface_origin
        .iter()
        .position(|&o| o as usize >= triangles.len())
    {
        return bad(format!(
            "surface triangle {i} names a missing input triangle"
        ));
    }
    let group = coplanar_groups(points, triangles, &[]);
    let mut old: HashMap<u32, Vec<[u32; 3]>> = HashMap::new();
    for (t, &r) in group.iter().enumerate() {
        old.entry(r).or_default().push(triangles[t]);
    }
    let mut new: HashMap<u32, Vec<[u32; 3]>> = HashMap::new();
    for (s, &o) in rec.surface.iter().zip(&rec.surface_origin) {
        new.entry(group[o as usize]).or_default().push(*s);
    }
    let mut roots: Vec<u32> = old.keys().copied().collect();
    roots.sort_unstable();
    let g = |q: u32| &points[q as usize];
    for r in roots {
        let ot = &old[&r];
        let Some(nt) = new.get(&r) else {
            return bad(format!(
                "the group of input triangle {r} has no surface triangle"
            ));
        };
        if ot.len() == 1 && nt.len() == 1 {
            let (mut x, mut y) = (ot[0], nt[0]);
            let rot = |t: &mut [u32; 3]| {
                let i = (0..3).min_by_key(|&i| t[i]).unwrap_or(0);
                t.rotate_left(i);
            };
            rot(&mut x);
            rot(&mut y);
            if x != y {
                return bad(format!("input triangle {r} is replaced by {y:?}"));
            }
            continue;
        }
        let [a, b, c] = ot[0];
        let Some((k, sign)) = projection(g(a), g(b), g(c)) else {
            return bad(format!("input triangle {r} is degenerate"));
        };
        let mut area_new = 0.0;
        for tv in nt {
            if tv.iter().any(|&q| orient3d(g(a), g(b), g(c), g(q)) != 0.0) {
                return bad(format!(
                    "surface triangle {tv:?} is off the plane of input triangle {r}"
                ));
            }
            let [p, q, s] = tv.map(|w| proj(g(w), k));
            let o = orient2d(&p, &q, &s);
            if o == 0.0 || o.signum() != sign {
                return bad(format!(
                    "surface triangle {tv:?} is degenerate or flipped in the group of input triangle {r}"
                ));
            }
            area_new += o.abs();
        }
        let area_old: f64 = ot
            .iter()
            .map(|tv| {
                let [p, q, s] = tv.map(|w| proj(g(w), k));
                orient2d(&p, &q, &s).abs()
            })
            .sum();
        if oriented_boundary(ot) != oriented_boundary(nt) {
            return bad(format!(
                "the surface triangles of the group of input triangle {r} have another boundary"
            ));
        }
        if (area_new - area_old).abs() > 1e-9 * area_old {
            return bad(format!(
                "the surface triangles of the group of input triangle {r}: area {area_new} instead of {area_old}"
            ));
        }
    }
    if new.keys().any(|r| !old.contains_key(r)) {
        return bad("a surface triangle names an unknown group".into());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube, each side an n × n grid of squares, two triangles
    /// each, oriented outward.
    fn grid_cube(n: u32) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
        let mut pts = Vec::new();
        let mut id: HashMap<[u32; 3], u32> = HashMap::new();
        let mut tris = Vec::new();
        let mut vid = |p: [u32; 3], pts: &mut Vec<[f64; 3]>| {
            *id.entry(p).or_insert_with(|| {
                pts.push(p.map(|c| f64::from(c) / f64::from(n)));
                pts.len() as u32 - 1
            })
        };
        for axis in 0..3 {
            for side in [0, n] {
                for i in 0..n {
                    for j in 0..n {
                        let q = |di: u32, dj: u32| {
                            let mut p = [0; 3];
                            p[axis] = side;
                            p[(axis + 1) % 3] = i + di;
                            p[(axis + 2) % 3] = j + dj;
                            p
                        };
                        let c = [q(0, 0), q(1, 0), q(1, 1), q(0, 1)].map(|p| vid(p, &mut pts));
                        let (t1, t2) = if side == n {
                            ([c[0], c[1], c[2]], [c[0], c[2], c[3]])
                        } else {
                            ([c[0], c[2], c[1]], [c[0], c[3], c[2]])
                        };
                        tris.push(t1);
                        tris.push(t2);
                    }
                }
            }
        }
        (pts, tris)
    }

    #[test]
    fn groups_of_a_grid_cube_are_its_six_sides() {
        let (pts, tris) = grid_cube(3);
        let g = coplanar_groups(&pts, &tris, &[]);
        let mut roots: Vec<u32> = g.clone();
        roots.sort_unstable();
        roots.dedup();
        assert_eq!(roots.len(), 6);
        // Markers split a side in two.
        let mut mk = vec![0; tris.len()];
        mk[0] = 1;
        let g2 = coplanar_groups(&pts, &tris, &mk);
        let mut r2 = g2.clone();
        r2.sort_unstable();
        r2.dedup();
        assert_eq!(r2.len(), 7);
    }

    /// The validation's unmarked groups give the merge of the groups
    /// found afresh, also with markers (one marker each, or a side split).
    #[test]
    fn validation_groups_serve_the_merge_unless_markers_split_them() {
        let (pts, tris) = grid_cube(3);
        let dt = Delaunay3::from_points(&pts).unwrap();
        let g = crate::tet::intersect::check_self_intersections_grouped(&pts, &tris)
            .unwrap()
            .unwrap();
        assert_eq!(g, coplanar_groups(&pts, &tris, &[]));
        let mut split = vec![0; tris.len()];
        split[0] = 1;
        for mk in [vec![], vec![3; tris.len()], split] {
            let fresh = merge(&pts, &tris, &mk, (None, &[]), &dt);
            let given = merge(&pts, &tris, &mk, (Some(g.clone()), &[]), &dt);
            assert_eq!(given.groups, 6);
            assert_eq!(
                (given.tris, given.origin, given.kept),
                (fresh.tris, fresh.origin, fresh.kept)
            );
        }
    }

    /// An edge of a group in more than two input triangles stays in its
    /// re-triangulation, though not Delaunay: the flat square below, with
    /// edge 4-5 between points 6 and 7 just off its middle, as if a
    /// closed surface met the square along 4-5.
    #[test]
    fn a_nonmanifold_edge_inside_a_group_is_kept() {
        let pts = [
            [0.0, 0.0, 0.0],
            [4.0, 0.0, 0.0],
            [4.0, 4.0, 0.0],
            [0.0, 4.0, 0.0],
            [1.0, 2.0, 0.0],
            [3.0, 2.0, 0.0],
            [2.0, 1.8, 0.0],
            [2.0, 2.2, 0.0],
            [2.0, 2.0, 1.0],
        ];
        let tris = [
            [0, 1, 6],
            [1, 5, 6],
            [6, 5, 4],
            [0, 6, 4],
            [0, 4, 3],
            [1, 2, 5],
            [4, 5, 7],
            [5, 2, 7],
            [7, 2, 3],
            [4, 7, 3],
        ];
        let dt = Delaunay3::from_points(&pts).unwrap();
        let has_45 = |m: &Merged| m.tris.iter().any(|t| t.contains(&4) && t.contains(&5));
        let plain = merge(&pts, &tris, &[], (None, &[]), &dt);
        assert_eq!((plain.groups, plain.tris.len()), (1, 10));
        assert!(!has_45(&plain));
        let nm = merge(&pts, &tris, &[], (None, &[[4, 5]]), &dt);
        assert_eq!((nm.groups, nm.tris.len()), (1, 10));
        assert!(has_45(&nm));
    }

    /// The oriented boundary counts each directed edge's uses against its
    /// reverse's.
    #[test]
    fn oriented_boundary_is_directed_and_counted() {
        let square = [[0, 1, 2], [0, 2, 3]];
        assert_eq!(
            oriented_boundary(&square),
            vec![(0, 1), (1, 2), (2, 3), (3, 0)]
        );
        assert_eq!(
            oriented_boundary(&[[0, 1, 2], [0, 1, 2], [2, 1, 3]]),
            vec![(0, 1), (0, 1), (1, 2), (1, 3), (2, 0), (2, 0), (3, 2)]
        );
        assert!(oriented_boundary(&[[0, 1, 2], [0, 2, 1]]).is_empty());
    }

    #[test]
    fn a_fold_is_not_merged() {
        // Two triangles sharing an edge, bent (not coplanar), then flat.
        let pts = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 1.0, 0.5],
        ];
        let tris = [[0, 1, 2], [1, 3, 2]];
        assert_eq!(coplanar_groups(&pts, &tris, &[]), vec![0, 1]);
        let flat = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
        ];
        assert_eq!(coplanar_groups(&flat, &tris, &[]), vec![0, 0]);
        // Same plane but inconsistent orientation.
        assert_eq!(
            coplanar_groups(&flat, &[[0, 1, 2], [1, 2, 3]], &[]),
            vec![0, 1]
        );
    }
}
