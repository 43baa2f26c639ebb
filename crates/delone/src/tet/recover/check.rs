//! An independent checker of a [`Recovered`] tetrahedralization.

use std::collections::HashMap;

use delone_predicates::orient3d;

use super::place::{collinear, inside_triangle, line_distance, plane_distance};
use super::types::Recovered;
use crate::geom::vec3::{cross, dot, sub};
use crate::tet::dmesh::DomainMesh;
use crate::tet::local::{ekey, fkey};
use crate::{Violation, NONE};

/// The volume enclosed by a closed triangulated surface, by the divergence
/// theorem: the sum over triangles `a b c` of `a · (b × c) / 6` (positive
/// when the triangles are oriented counterclockwise seen from outside).
///
/// ```
/// use delone::tet::recover::surface_volume;
/// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
/// let v = surface_volume(&pts, &[[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]]);
/// assert!((v - 1.0 / 6.0).abs() < 1e-15);
/// ```
pub fn surface_volume(points: &[[f64; 3]], triangles: &[[u32; 3]]) -> f64 {
    triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|w| points[w as usize]);
            dot(&a, &cross(&b, &c)) / 6.0
        })
        .sum()
}

pub(crate) fn tet_volume(p: [[f64; 3]; 4]) -> f64 {
    dot(
        &sub(&p[1], &p[0]),
        &cross(&sub(&p[2], &p[0]), &sub(&p[3], &p[0])),
    ) / 6.0
}

/// Checks a [`Recovered`] result against its input surface, independently of
/// how it was built:
///
/// * every tetrahedron has distinct in-range vertices and positive volume
///   (exact);
/// * neighbour links are symmetric and join equal faces; the faces without
///   neighbour are exactly `boundary`, oriented outward (exact);
/// * every boundary face lies on the input triangle it names: its vertices
///   exactly on the triangle's plane (within the reported deviation for the
///   listed inexact Steiner points) and inside it;
/// * every facet is the union of its faces (boundary faces, or
///   interior faces between two tetrahedra on internal facets, never both):
///   their edges used once lie on the facet's sides and chain each side
///   from end to end, every other edge is used twice, and the areas add up.
///   A facet is a triangle of `rec.surface` (the input triangles when
///   empty), or all of them with one `surface_origin` (a merged coplanar
///   group, which refinement may re-triangulate across its inner edges);
///   each face lies inside one of its facet's triangles.
///   A triangle may have no face only when a hole removed a region or the
///   input has internal facets (both its sides are then outside the domain);
/// * regions: every tetrahedron names one, the regions' volumes add up;
/// * the tetrahedra's volume equals the volume bounded by the input
///   triangles on the boundary, each oriented like its boundary faces (so
///   holes and cavities are subtracted), plus the hull faces kept by `-c`,
///   up to rounding.
///
/// ```
/// use delone::tet::recover::{check_recovered, recover, RecoverOptions};
/// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
/// let tris = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];
/// let mut r = recover(&pts, &tris, &RecoverOptions::default()).unwrap();
/// check_recovered(&pts, &tris, &r).unwrap();
/// r.mesh.tets[0].swap(0, 1);
/// assert!(check_recovered(&pts, &tris, &r).is_err());
/// ```
pub fn check_recovered(
    points: &[[f64; 3]],
    triangles: &[[u32; 3]],
    rec: &Recovered,
) -> Result<(), Violation> {
    // The mesh conforms to `rec.surface`, which must cover the input.
    let triangles: &[[u32; 3]] = if rec.surface.is_empty() && rec.surface_origin.is_empty() {
        triangles
    } else {
        super::merge::check_surface(points, triangles, rec)?;
        &rec.surface
    };
    let (scaled, s) = crate::geom::rescaled(&rec.points);
    let sp = &scaled[..];
    let n = sp.len();
    let m = &rec.mesh;
    let bad = |kind, d: String| Err(Violation::new(kind, d));
    if m.neighbors.len() != m.tets.len() || rec.boundary.len() != rec.boundary_triangle.len() {
        return bad("sizes", "array lengths disagree".into());
    }
    if points.len() > n || rec.points[..points.len()] != *points {
        return bad(
            "points",
            "the input points are not a prefix of the output points".into(),
        );
    }
    if let Some(i) = triangles
        .iter()
        .position(|t| t.iter().any(|&q| q as usize >= points.len()))
    {
        return bad("range", format!("input triangle {i} names a missing point"));
    }
    // Tetrahedra: positive, neighbours across the same face seen with
    // opposite orientations (the domain mesh's checker, with the boundary
    // faces as its subfaces).
    if let Some(t) = m
        .tets
        .iter()
        .position(|tv| tv.iter().any(|&q| q as usize >= n))
    {
        return bad("range", format!("tet {t} names a missing point"));
    }
    let Ok(mut dm) = DomainMesh::from_neighbors(&m.tets, &m.neighbors, &[], n) else {
        return bad("adjacency", "a neighbour does not share the face".into());
    };
    dm.mark_subfaces(&Default::default());
    dm.check(sp).map_err(|e| Violation::new("topology", e))?;
    // The boundary: the free faces, each once.
    let face = |tv: [u32; 4], i: usize| fkey([tv[(i + 1) % 4], tv[(i + 2) % 4], tv[(i + 3) % 4]]);
    let mut free: HashMap<[u32; 3], (usize, usize)> = HashMap::new();
    for (t, (tv, nb)) in m.tets.iter().zip(&m.neighbors).enumerate() {
        for i in (0..4).filter(|&i| nb[i] == NONE) {
            let k = face(*tv, i);
            if free.insert(k, (t, i)).is_some() {
                return bad("boundary", format!("face {k:?} is on the boundary twice"));
            }
        }
    }
    if free.len() != rec.boundary.len() {
        return bad(
            "boundary",
            format!(
                "{} free faces, {} boundary faces",
                free.len(),
                rec.boundary.len()
            ),
        );
    }
    // The reported deviation is measured from one side's line or plane in
    // one order of its points; measured from another side or order it may
    // differ by rounding, so the tolerance has a floor of a few units in the
    // last place of the (rescaled) coordinates.
    let span = sp.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    let tol_dev = 4.0 * rec.report.max_deviation * s.0 * s.1 + 16.0 * f64::EPSILON * span;
    let inexact = |q: u32| rec.inexact.binary_search(&q).is_ok() || rec.inexact.contains(&q);
    // Faces are checked per facet: the surface triangles of one merged
    // group (same `surface_origin`) together, since refinement may
    // re-triangulate a planar facet across its surface triangles.
    let (facet_of, members) = facets(triangles, &rec.surface_origin);
    let mut per_tri: Vec<Vec<[u32; 3]>> = vec![Vec::new(); triangles.len()];
    // Per input triangle: 1 on the boundary, 2 interior.
    let mut side = vec![0u8; triangles.len()];
    let hull_kept = rec.regions.iter().any(|r| r.exterior);
    // Divergence-theorem terms of the boundary faces off the surface.
    let mut hull_volume = 0.0;
    if m.tets.len() != rec.tet_region.len()
        || rec.interior_faces.len() != rec.interior_triangle.len()
    {
        return bad("sizes", "region or interior face arrays disagree".into());
    }
    if let Some(t) = rec
        .tet_region
        .iter()
        .position(|&g| g as usize >= rec.regions.len())
    {
        return bad("regions", format!("tet {t} names a missing region"));
    }
    let mut inner: HashMap<[u32; 3], usize> = rec
        .interior_faces
        .iter()
        .enumerate()
        .map(|(k, f)| (fkey(*f), k))
        .collect();
    if inner.len() != rec.interior_faces.len() {
        return bad("interior", "an interior face is listed twice".into());
    }
    for (tv, nb) in m.tets.iter().zip(&m.neighbors) {
        for (i, &nbi) in nb.iter().enumerate() {
            if nbi != NONE {
                inner.remove(&face(*tv, i));
            }
        }
    }
    if let Some((f, _)) = inner.iter().min_by_key(|(_, &k)| k) {
        return bad(
            "interior",
            format!("interior face {f:?} is not between two tetrahedra"),
        );
    }
    let faces_on = rec
        .boundary
        .iter()
        .zip(&rec.boundary_triangle)
        .map(|(f, t)| (f, t, true))
        .chain(
            rec.interior_faces
                .iter()
                .zip(&rec.interior_triangle)
                .map(|(f, t)| (f, t, false)),
        );
    for (bi, (&f, &ti, on_boundary)) in faces_on.enumerate() {
        if on_boundary {
            let Some(&(t, i)) = free.get(&fkey(f)) else {
                return bad(
                    "boundary",
                    format!("boundary face {bi} {f:?} is not a free face"),
                );
            };
            let w = m.tets[t][i];
            let [a, b, c] = f.map(|q| sp[q as usize]);
            if orient3d(&a, &b, &c, &sp[w as usize]) <= 0.0 {
                return bad(
                    "boundary",
                    format!("boundary face {bi} is not oriented outward"),
                );
            }
            if ti == NONE && hull_kept {
                let [a, b, c] = f.map(|q| sp[q as usize]);
                hull_volume += dot(&a, &cross(&b, &c)) / 6.0;
                continue;
            }
        }
        let want_side = if on_boundary { 1 } else { 2 };
        if let Some(sd) = facet_of
            .get(ti as usize)
            .and_then(|&g| side.get_mut(g as usize))
        {
            if *sd != 0 && *sd != want_side {
                return bad(
                    "constraint",
                    format!("input triangle {ti} has faces both on the boundary and inside"),
                );
            }
            *sd = want_side;
        }
        let Some(tri) = triangles.get(ti as usize) else {
            return bad(
                "constraint",
                format!("boundary face {bi} names no input triangle"),
            );
        };
        let [ta, tb, tc] = tri.map(|q| sp[q as usize]);
        let fac = &members[facet_of[ti as usize] as usize];
        for &q in &f {
            let p = sp[q as usize];
            // An inexact point is within the reported deviation of the
            // plane, or (for a point on a side, which is the better
            // conditioned test on needle-shaped triangles) of a side's line.
            let on = orient3d(&ta, &tb, &tc, &p) == 0.0
                || (inexact(q)
                    && (plane_distance(&ta, &tb, &tc, &p) <= tol_dev
                        || line_distance(&ta, &tb, &p) <= tol_dev
                        || line_distance(&tb, &tc, &p) <= tol_dev
                        || line_distance(&tc, &ta, &p) <= tol_dev));
            if !on {
                return bad(
                    "constraint",
                    format!("boundary face {bi}: vertex {q} is off the plane of triangle {ti}"),
                );
            }
            let inside = |t: &u32| {
                let tt = triangles[*t as usize];
                let [a, b, c] = tt.map(|w| sp[w as usize]);
                tt.contains(&q) || inside_closed(&a, &b, &c, &p)
            };
            if !fac.iter().any(inside) {
                return bad(
                    "constraint",
                    format!("boundary face {bi}: vertex {q} is outside triangle {ti}"),
                );
            }
        }
        per_tri[facet_of[ti as usize] as usize].push(f);
    }
    // Each input triangle is the union of its faces.
    // A triangle with no face at all lies outside the domain (between two
    // removed parts), which needs a hole or internal facets.
    let man = crate::tet::intersect::manifold_report(triangles);
    let may_vanish = rec.report.holes_removed > 0 || !man.nonmanifold_edges.is_empty();
    for (ti, faces) in per_tri.iter().enumerate() {
        if members[ti].is_empty() || faces.is_empty() && may_vanish {
            continue;
        }
        let mut count: HashMap<(u32, u32), u32> = HashMap::new();
        // Areas in floating point, with the rounding bound of each cross
        // product (a few ulps of |b - a| |c - a|: needles of a tiny area
        // between far points would otherwise look uncovered).
        let area_of = |t: [u32; 3]| {
            let [a, b, c] = t.map(|q| sp[q as usize]);
            let (u, v) = (sub(&b, &a), sub(&c, &a));
            let n = cross(&u, &v);
            let err = 8.0 * f64::EPSILON * (dot(&u, &u) * dot(&v, &v)).sqrt();
            (0.5 * dot(&n, &n).sqrt(), err)
        };
        let mut area = 0.0;
        let mut slack = 0.0;
        for f in faces {
            for k in 0..3 {
                *count.entry(ekey(f[k], f[(k + 1) % 3])).or_insert(0) += 1;
            }
            let (x, e) = area_of(*f);
            area += x;
            slack += e;
        }
        let mut want = 0.0;
        for &t in &members[ti] {
            let (x, e) = area_of(triangles[t as usize]);
            want += x;
            slack += e;
        }
        if (area - want).abs() > 1e-9 * want + slack {
            return bad(
                "constraint",
                format!("triangle {ti}: faces' area {area} differs from {want}"),
            );
        }
        let mut once: Vec<(u32, u32)> = Vec::new();
        for (&e, &c) in &count {
            match c {
                1 => once.push(e),
                2 => {}
                _ => {
                    return bad(
                        "constraint",
                        format!("triangle {ti}: edge {e:?} in {c} faces"),
                    )
                }
            }
        }
        once.sort_unstable();
        let mut used = 0;
        for (x, y) in facet_sides(triangles, &members[ti]) {
            let (px, py) = (sp[x as usize], sp[y as usize]);
            let d = sub(&py, &px);
            let on_side = |q: u32| {
                let p = sp[q as usize];
                let along = dot(&sub(&p, &px), &d);
                q == x
                    || q == y
                    // (between x and y: a facet may have collinear sides)
                    || (0.0..=dot(&d, &d)).contains(&along)
                        && (collinear(&px, &py, &p)
                            || (inexact(q) && line_distance(&px, &py, &p) <= tol_dev))
            };
            let side: Vec<(u32, u32)> = once
                .iter()
                .copied()
                .filter(|&(u, v)| on_side(u) && on_side(v))
                .collect();
            // Walk from x to y along the side's edges, never stepping back.
            let mut prev = NONE;
            let mut cur = x;
            let mut steps = 0;
            while cur != y {
                let next = side.iter().find_map(|&(u, v)| match () {
                    _ if u == cur && v != prev => Some(v),
                    _ if v == cur && u != prev => Some(u),
                    _ => None,
                });
                let Some(nx) = next else {
                    return bad(
                        "constraint",
                        format!("facet {ti}: side {x}-{y} breaks at {cur}"),
                    );
                };
                steps += 1;
                if steps > side.len() {
                    return bad(
                        "constraint",
                        format!("facet {ti}: side {x}-{y} does not chain"),
                    );
                }
                prev = cur;
                cur = nx;
            }
            used += steps;
        }
        if used != once.len() {
            return bad(
                "constraint",
                format!(
                    "triangle {ti}: {} edges used once but its sides have {used}",
                    once.len()
                ),
            );
        }
    }
    // Volume: the tetrahedra fill exactly the part bounded by the input
    // triangles on the boundary (each oriented like its boundary faces, so
    // holes and cavities count negatively), plus hull faces under `-c`.
    // Measured on the scaled points: no over- or underflow at any scale.
    let vol: f64 = m
        .tets
        .iter()
        .map(|tv| tet_volume(tv.map(|q| sp[q as usize])))
        .sum();
    let mut want = hull_volume;
    let mut scale = hull_volume.abs();
    for (ti, faces) in per_tri.iter().enumerate() {
        if side[ti] != 1 {
            continue;
        }
        // The orientation of the facet's boundary faces, by their summed
        // (area-weighted) normals: tiny faces next to inexact Steiner
        // points may lean either way.
        let n = normal(&triangles[ti], sp);
        let d: f64 = faces.iter().map(|f| dot(&n, &normal(f, sp))).sum();
        let sign = if d > 0.0 { 1.0 } else { -1.0 };
        for &t in &members[ti] {
            let [a, b, c] = triangles[t as usize].map(|q| sp[q as usize]);
            let term = dot(&a, &cross(&b, &c)) / 6.0;
            want += sign * term;
            scale += term.abs();
        }
    }
    // Region volumes are in input units: compared with the total brought
    // back to input units, allowing for the subnormal spacing when it
    // underflows (one unit per tetrahedron and region).
    let region_sum: f64 = rec.regions.iter().map(|r| r.volume).sum();
    let vol_in = crate::geom::scale::unscale_cubic(vol, s);
    let granule = 5e-324 * (m.tets.len() + rec.regions.len()) as f64;
    let regions_ok = if vol_in.is_finite() {
        (region_sum - vol_in).abs() <= 1e-9 * vol_in.abs() + granule
    } else {
        region_sum == vol_in
    };
    if (vol - want).abs() > 1e-9 * scale.max(vol.abs()).max(f64::MIN_POSITIVE) || !regions_ok {
        return bad(
            "volume",
            format!(
                "tetrahedra volume {vol_in:e} (regions {region_sum:e}) differs from enclosed volume {:e}",
                crate::geom::scale::unscale_cubic(want, s)
            ),
        );
    }
    Ok(())
}

/// Per surface triangle its facet (the first surface triangle with the same
/// `origin`; itself when `origin` does not match the surface), and per
/// facet its surface triangles (empty for a triangle that is not first).
pub(crate) fn facets(triangles: &[[u32; 3]], origin: &[u32]) -> (Vec<u32>, Vec<Vec<u32>>) {
    let n = triangles.len();
    let mut facet_of: Vec<u32> = (0..n as u32).collect();
    if origin.len() == n {
        let mut first: HashMap<u32, u32> = HashMap::new();
        for (t, &o) in origin.iter().enumerate() {
            facet_of[t] = *first.entry(o).or_insert(t as u32);
        }
    }
    let mut members = vec![Vec::new(); n];
    for (t, &g) in facet_of.iter().enumerate() {
        members[g as usize].push(t as u32);
    }
    (facet_of, members)
}

/// The sides of a facet (its surface triangles `members`): the directed
/// edges whose reverse is not in the facet, sorted.
pub(crate) fn facet_sides(triangles: &[[u32; 3]], members: &[u32]) -> Vec<(u32, u32)> {
    let mut es: Vec<(u32, u32)> = members
        .iter()
        .flat_map(|&t| {
            let v = triangles[t as usize];
            [(v[0], v[1]), (v[1], v[2]), (v[2], v[0])]
        })
        .collect();
    es.sort_unstable();
    es.iter()
        .copied()
        .filter(|&(a, b)| es.binary_search(&(b, a)).is_err())
        .collect()
}

fn normal(t: &[u32; 3], pts: &[[f64; 3]]) -> [f64; 3] {
    let [a, b, c] = t.map(|q| pts[q as usize]);
    cross(&sub(&b, &a), &sub(&c, &a))
}

/// `p` (on the plane of `a b c`) inside the closed triangle.
fn inside_closed(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], p: &[f64; 3]) -> bool {
    inside_triangle(a, b, c, p)
        || on_segment_line(a, b, p)
        || on_segment_line(b, c, p)
        || on_segment_line(c, a, p)
}

fn on_segment_line(a: &[f64; 3], b: &[f64; 3], p: &[f64; 3]) -> bool {
    let d = sub(b, a);
    let s = dot(&sub(p, a), &d);
    s >= 0.0 && s <= dot(&d, &d) && line_distance(a, b, p) <= 1e-12 * dot(&d, &d).sqrt()
}
