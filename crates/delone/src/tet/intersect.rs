//! Input validation for 3D boundary recovery: exact self-intersection
//! detection and closedness/manifoldness of triangulated surfaces.
//!
//! * [`self_intersections`] — every pair of triangles that meet other than
//!   as the topology says (sharing exactly one vertex or one edge), found
//!   with a uniform-grid broad phase and exact predicates
//!   ([`orient3d`], and [`orient2d`] in a coordinate projection for coplanar
//!   configurations); plus the zero-area triangles.
//! * [`check_self_intersections`] — the same as a typed [`Error`].
//! * [`manifold_report`] — boundary, non-manifold and inconsistently
//!   oriented edges.
//!
//! # Which contacts are legal
//!
//! Vertices are identified by coordinates (exact duplicates are the same
//! vertex). Two triangles sharing three vertices (a duplicate face) always
//! intersect. Sharing two vertices (an edge `uv`): they intersect iff they
//! are coplanar and their third vertices lie on the same side of `uv`.
//! Sharing one vertex `v`: they intersect iff the edge opposite `v` in either
//! triangle meets the other (closed) triangle — every other point of a
//! larger intersection would be a vertex of the convex set `T1 ∩ T2`, and
//! each such vertex lies on one of those two edges. Sharing nothing: they
//! intersect iff an edge of one meets the other. Everything is decided by
//! signs of exact determinants, so the result does not depend on rounding.
//!
//! # Costs
//!
//! The broad phase is a uniform grid: each cell's boxes are copied side by
//! side and tested pairwise, the lowest-common-cell test (each pair once)
//! only for overlapping boxes. The narrow phase allocates nothing: a 9-bit
//! mask of equal canonical vertex ids picks the case; with one shared vertex,
//! two side tests of the other triangle's far vertices settle almost every
//! pair of a closed surface. Side tests use a per-triangle plane (normal and
//! the magnitudes of its products) with the error bound of `orient3d`'s
//! floating-point stage, falling back to exact `orient3d`; the plane also
//! certifies the triangle's 2D projection axes for the coplanar tests. Two
//! triangles of one group of exactly coplanar edge neighbours
//! (`coplanar_groups`, one exact test per shared edge) skip the side tests,
//! which would all take that exact fallback (the planar faces of CAD
//! models), and their 2D test first looks for an edge line of one triangle
//! with the other's unshared vertices strictly beyond it (settling most
//! pairs of a face with a few orientations), then computes the 18
//! orientations of each one's vertices against the other's edges once. An
//! exact side fallback is remembered per (coplanar group, vertex): all
//! triangles of a group share their plane and normal direction, so the
//! vertices of adjacent faces lying on a planar face's plane are decided
//! exactly once per face. Canonical ids
//! (exact duplicate points) come from a sort, not a hash map.
//! [`manifold_report`] files edges under their smaller endpoint (counting
//! sort, insertion sort per bucket): no global sort, no edge map.
//!
//! # References
//! O. Devillers, P. Guigue, *Faster triangle-triangle intersection tests*,
//! INRIA RR-4488, 2002 (orientation-only classification).

use crate::error::Error;
use crate::geom::ids::IdMap;
use crate::geom::vec3::{collinear, projection_axes};
use crate::geom::{union_join, union_root};
use crate::model::canonical_ids;
use crate::tet::local::ekey;
use delone_predicates::{orient2d, orient3d};
use std::cell::RefCell;

type P = [f64; 3];

/// What [`self_intersections`] found.
///
/// ```
/// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.2, 0.2, -1.0], [0.2, 0.2, 1.0], [0.3, 0.3, 1.0]];
/// let r = delone::tet::intersect::self_intersections(&pts, &[[0, 1, 2], [3, 4, 5]]);
/// assert_eq!(r.pairs, vec![(0, 1)]);
/// assert!(r.degenerate.is_empty() && !r.is_clean());
/// ```
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct SelfIntersections {
    /// Intersecting pairs `(i, j)`, `i < j`, sorted: indices into the
    /// triangle array.
    pub pairs: Vec<(u32, u32)>,
    /// Triangles with zero area (three collinear points), sorted. They are
    /// left out of the pair tests.
    pub degenerate: Vec<u32>,
}

impl SelfIntersections {
    /// `true` when no pair intersects and no triangle is degenerate.
    ///
    /// ```
    /// assert!(delone::tet::intersect::SelfIntersections::default().is_clean());
    /// ```
    pub fn is_clean(&self) -> bool {
        self.pairs.is_empty() && self.degenerate.is_empty()
    }
}

/// Finds every pair of triangles of the surface `(points, triangles)` that
/// intersect other than as their shared vertices/edges allow, and every
/// zero-area triangle (see the [module docs](self) for the rules).
///
/// Triangles referring to a missing point are ignored (use
/// [`check_self_intersections`] to have them reported). Runs in about
/// `O(n)` for well-spread surfaces (a uniform grid with about one cell per
/// triangle); the result is sorted and deterministic.
///
/// ```
/// use delone::tet::intersect::self_intersections;
/// // Two triangles sharing edge 0-1, folded onto each other (coplanar, same side).
/// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.5, 0.5, 0.0]];
/// assert_eq!(self_intersections(&pts, &[[0, 1, 2], [1, 0, 3]]).pairs, vec![(0, 1)]);
/// // The same on opposite sides: legal.
/// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.5, -0.5, 0.0]];
/// assert!(self_intersections(&pts, &[[0, 1, 2], [1, 0, 3]]).is_clean());
/// ```
pub fn self_intersections(points: &[P], triangles: &[[u32; 3]]) -> SelfIntersections {
    self_intersections_grouped(points, triangles).0
}

/// [`self_intersections`], and the [`coplanar_groups`] (no markers) of
/// `triangles` the tests used when every triangle took part in them and
/// no two of their vertices are exact duplicates (else `None`): then they
/// are those of the input as given, since the tests' copy of the points
/// is scaled exactly (a power of two) and keeps every sign.
fn self_intersections_grouped(
    points: &[P],
    triangles: &[[u32; 3]],
) -> (SelfIntersections, Option<Vec<u32>>) {
    // Every test below runs on a copy scaled by a power of two (exact, so
    // the same signs), which keeps the predicates' products and the side
    // filter clear of overflow and underflow at any scale.
    let (points, _) = crate::geom::rescaled(points);
    let points: &[P] = &points;
    let n = points.len();
    let canon = canonical_ids(points);
    let mut out = SelfIntersections::default();
    // Triangles taking part in the pair tests.
    let mut live: Vec<u32> = Vec::with_capacity(triangles.len());
    for (t, tri) in triangles.iter().enumerate() {
        if tri.iter().any(|&v| v as usize >= n) {
            continue;
        }
        let [a, b, c] = tri.map(|v| &points[v as usize]);
        if !(a.iter().chain(b).chain(c).all(|x| x.is_finite())) {
            continue;
        }
        if collinear(a, b, c) {
            out.degenerate.push(t as u32);
        } else {
            live.push(t as u32);
        }
    }
    if live.len() < 2 {
        return (out, None);
    }
    // Per live triangle: canonical vertex ids and its plane.
    let tri_c: Vec<[u32; 3]> = live
        .iter()
        .map(|&t| triangles[t as usize].map(|v| canon[v as usize]))
        .collect();
    let mut planes: Vec<Plane> = tri_c
        .iter()
        .map(|t| Plane::new(t.map(|v| &points[v as usize])))
        .collect();
    // Pairs in one coplanar group need no side test (all signs are zero).
    let group = coplanar_groups(points, &tri_c, &[]);
    for (pl, &g) in planes.iter_mut().zip(&group) {
        pl.group = g;
    }
    let memo = RefCell::new(IdMap::default());
    // Bounding boxes and the grid.
    let bb: Vec<(P, P)> = live
        .iter()
        .map(|&t| {
            let [a, b, c] = triangles[t as usize].map(|v| points[v as usize]);
            let lo = [0, 1, 2].map(|k| a[k].min(b[k]).min(c[k]));
            let hi = [0, 1, 2].map(|k| a[k].max(b[k]).max(c[k]));
            (lo, hi)
        })
        .collect();
    let mut glo = bb[0].0;
    let mut ghi = bb[0].1;
    for (lo, hi) in &bb {
        for k in 0..3 {
            glo[k] = glo[k].min(lo[k]);
            ghi[k] = ghi[k].max(hi[k]);
        }
    }
    let ext = [0, 1, 2].map(|k| (ghi[k] - glo[k]).max(0.0));
    let m = live.len() as f64;
    // Cell size: about one triangle per cell on a surface (cells ~ n^(3/2)
    // would be one per triangle in a volume; surfaces fill ~ cells^(2/3)).
    let vol: f64 = ext.iter().filter(|&&e| e > 0.0).product();
    let dims_nonzero = ext.iter().filter(|&&e| e > 0.0).count().max(1) as f64;
    // Twice that edge: fewer cells per triangle and fewer copies of one
    // pair in several cells outweigh the longer cell lists (measured: about
    // a quarter fewer instructions in the broad phase on closed models).
    let mut h = 2.0 * (vol / (m * 2.0)).powf(1.0 / dims_nonzero);
    if !(h.is_finite() && h > 0.0) {
        h = ext.iter().cloned().fold(0.0, f64::max).max(1.0);
    }
    // The grid's size follows the number of triangles (a few cells each),
    // and so does the number of (cell, triangle) entries: boxes spanning
    // many cells (far-apart points, needles) coarsen the grid instead of
    // filling memory. A single cell holds every triangle once, so this ends.
    let max_cells = (8 * live.len() as u64).clamp(64, 1 << 24);
    let max_entries = 32 * live.len() as u64 + 1024;
    let mut dims = [0usize; 3];
    loop {
        for k in 0..3 {
            dims[k] = ((ext[k] / h).floor() as usize).clamp(1, 1 << 20);
        }
        let ncell = (dims[0] as u64) * (dims[1] as u64) * (dims[2] as u64);
        if ncell == 1 {
            break;
        }
        if ncell <= max_cells {
            let span = |lo: f64, hi: f64, k: usize| {
                let c =
                    |x: f64| (((x - glo[k]) / h).floor().max(0.0) as u64).min(dims[k] as u64 - 1);
                c(hi) - c(lo) + 1
            };
            let entries: u64 = bb
                .iter()
                .map(|(lo, hi)| (0..3).map(|k| span(lo[k], hi[k], k)).product::<u64>())
                .fold(0u64, u64::saturating_add);
            if entries <= max_entries {
                break;
            }
        }
        h *= 1.5;
    }
    // Monotone cell coordinate: equal or ordered inputs give ordered cells,
    // so two overlapping boxes always share a cell.
    let cell = |x: f64, k: usize| -> usize {
        let c = ((x - glo[k]) / h).floor();
        if c.is_nan() || c < 0.0 {
            0
        } else {
            (c as usize).min(dims[k] - 1)
        }
    };
    let ranges: Vec<([u32; 3], [u32; 3])> = bb
        .iter()
        .map(|(lo, hi)| {
            (
                [0, 1, 2].map(|k| cell(lo[k], k) as u32),
                [0, 1, 2].map(|k| cell(hi[k], k) as u32),
            )
        })
        .collect();
    let cid = |c: [u32; 3]| (c[2] as usize * dims[1] + c[1] as usize) * dims[0] + c[0] as usize;
    let ncell = dims[0] * dims[1] * dims[2];
    let mut start = vec![0u32; ncell + 1];
    for (lo, hi) in &ranges {
        for z in lo[2]..=hi[2] {
            for y in lo[1]..=hi[1] {
                for x in lo[0]..=hi[0] {
                    start[cid([x, y, z]) + 1] += 1;
                }
            }
        }
    }
    for i in 0..ncell {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut items = vec![0u32; start[ncell] as usize];
    for (li, (lo, hi)) in ranges.iter().enumerate() {
        for z in lo[2]..=hi[2] {
            for y in lo[1]..=hi[1] {
                for x in lo[0]..=hi[0] {
                    let c = cid([x, y, z]);
                    items[fill[c] as usize] = li as u32;
                    fill[c] += 1;
                }
            }
        }
    }
    drop(fill);
    // Narrow phase: each pair is tested in the lowest cell both occupy.
    // A cell's boxes are first copied side by side (one pass over the
    // cell's list), so the all-pairs box test reads contiguous memory; the
    // lowest-common-cell test runs only for overlapping boxes.
    let mut cell_bb: Vec<(P, P)> = Vec::new();
    let mut cell_lo: Vec<[u32; 3]> = Vec::new();
    for z in 0..dims[2] as u32 {
        for y in 0..dims[1] as u32 {
            for x in 0..dims[0] as u32 {
                let c = cid([x, y, z]);
                let here = &items[start[c] as usize..start[c + 1] as usize];
                if here.len() < 2 {
                    continue;
                }
                cell_bb.clear();
                cell_lo.clear();
                for &i in here {
                    cell_bb.push(bb[i as usize]);
                    cell_lo.push(ranges[i as usize].0);
                }
                for (k, (bi, ri)) in cell_bb.iter().zip(&cell_lo).enumerate() {
                    for (l, bj) in cell_bb.iter().enumerate().skip(k + 1) {
                        if bi.1[0] < bj.0[0]
                            || bj.1[0] < bi.0[0]
                            || bi.1[1] < bj.0[1]
                            || bj.1[1] < bi.0[1]
                            || bi.1[2] < bj.0[2]
                            || bj.1[2] < bi.0[2]
                        {
                            continue;
                        }
                        let rj = &cell_lo[l];
                        if ri[0].max(rj[0]) != x || ri[1].max(rj[1]) != y || ri[2].max(rj[2]) != z {
                            continue;
                        }
                        let (li, lj) = (here[k] as usize, here[l] as usize);
                        let (ti, tj) = (live[li], live[lj]);
                        let pl = (&planes[li], &planes[lj]);
                        let flat = group[li] == group[lj];
                        let m = Some(&memo);
                        if intersect_with_planes(points, tri_c[li], tri_c[lj], pl, flat, m) {
                            out.pairs.push((ti.min(tj), ti.max(tj)));
                        }
                    }
                }
            }
        }
    }
    out.pairs.sort_unstable();
    out.pairs.dedup();
    let as_given = live.len() == triangles.len() && tri_c[..] == triangles[..];
    (out, as_given.then_some(group))
}

/// Per triangle: its group of exactly coplanar, consistently oriented
/// neighbours (the lowest triangle index in it): the connected components
/// of "shares an edge that is in exactly these two triangles, the fourth
/// point is on the first's plane (exact `orient3d`), the two lie on
/// opposite sides of the edge and, when `marker` (empty or one per
/// triangle) is given, carry the same marker". Every triangle of a group
/// lies on one plane. The recovery merges these groups into facets; the
/// pair test of [`self_intersections`] knows their pairs coplanar.
pub(crate) fn coplanar_groups(
    points: &[[f64; 3]],
    triangles: &[[u32; 3]],
    marker: &[i32],
) -> Vec<u32> {
    // The triangles of each edge side by side: (larger end, triangle)
    // filed under the smaller end by a counting sort, each (short) bucket
    // then sorted (no map of lists, no global sort). Union-find links roots
    // to the lower one, so the groups do not depend on the visiting order.
    let nv = triangles
        .iter()
        .flat_map(|tv| tv.iter())
        .map(|&q| q as usize + 1)
        .max()
        .unwrap_or(0);
    let mut start = vec![0u32; nv + 1];
    for tv in triangles {
        for k in 0..3 {
            start[ekey(tv[k], tv[(k + 1) % 3]).0 as usize + 1] += 1;
        }
    }
    for i in 0..nv {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut by_edge: Vec<(u32, u32)> = vec![(0, 0); 3 * triangles.len()];
    for (t, tv) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (lo, hi) = ekey(tv[k], tv[(k + 1) % 3]);
            by_edge[fill[lo as usize] as usize] = (hi, t as u32);
            fill[lo as usize] += 1;
        }
    }
    drop(fill);
    let mut parent: Vec<u32> = (0..triangles.len() as u32).collect();
    let g = |q: u32| &points[q as usize];
    let mut runs: Vec<(u32, u32, u32, usize)> = Vec::new();
    for u in 0..nv {
        let bucket = &mut by_edge[start[u] as usize..start[u + 1] as usize];
        bucket.sort_unstable();
        let mut i = 0;
        while i < bucket.len() {
            let mut j = i + 1;
            while j < bucket.len() && bucket[j].0 == bucket[i].0 {
                j += 1;
            }
            if j - i == 2 {
                runs.push((u as u32, bucket[i].0, bucket[i].1, bucket[i + 1].1 as usize));
            }
            i = j;
        }
    }
    for (u, v, t1, t2) in runs {
        if t1 as usize == t2 {
            continue;
        }
        let (t1, t2) = (t1 as usize, t2);
        if !marker.is_empty() && marker.get(t1) != marker.get(t2) {
            continue;
        }
        let (a, b) = (triangles[t1], triangles[t2]);
        // Directed use of u -> v in each.
        let dir = |tv: [u32; 3]| (0..3).any(|k| tv[k] == u && tv[(k + 1) % 3] == v);
        if dir(a) == dir(b) {
            continue;
        }
        let Some(&c) = a.iter().find(|&&q| q != u && q != v) else {
            continue;
        };
        let Some(&d) = b.iter().find(|&&q| q != u && q != v) else {
            continue;
        };
        if orient3d(g(a[0]), g(a[1]), g(a[2]), g(d)) != 0.0 {
            continue;
        }
        let Some((x, y)) = projection_axes(g(a[0]), g(a[1]), g(a[2])) else {
            continue;
        };
        let q = |w: u32| [g(w)[x], g(w)[y]];
        let (oc, od) = (orient2d(&q(u), &q(v), &q(c)), orient2d(&q(u), &q(v), &q(d)));
        // Opposite sides of the edge: same normal (the edge is used in
        // opposite directions).
        if oc == 0.0 || od == 0.0 || (oc > 0.0) == (od > 0.0) {
            continue;
        }
        union_join(&mut parent, t1 as u32, t2 as u32);
    }
    (0..triangles.len() as u32)
        .map(|t| union_root(&mut parent, t))
        .collect()
}

/// [`self_intersections`] as a typed result.
///
/// # Errors
/// [`Error::IndexOutOfRange`] (item `"triangle"`) for a triangle referring
/// to a missing point; [`Error::InvalidCoordinate`] for a NaN/infinite
/// point used by a triangle; [`Error::DegenerateFacet`] with
/// [`crate::FacetDefect::ZeroArea`] for the first zero-area triangle;
/// [`Error::SelfIntersection`] naming the first intersecting pair and the
/// number of pairs.
///
/// ```
/// use delone::tet::intersect::check_self_intersections;
/// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
/// assert_eq!(check_self_intersections(&pts, &[[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]]), Ok(()));
/// let e = check_self_intersections(&pts, &[[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2], [0, 1, 2]]);
/// assert_eq!(e, Err(delone::Error::SelfIntersection { facets: (0, 4), count: 1 }));
/// ```
pub fn check_self_intersections(points: &[P], triangles: &[[u32; 3]]) -> Result<(), Error> {
    check_self_intersections_grouped(points, triangles).map(|_| ())
}

/// [`check_self_intersections`], giving on success the coplanar groups the
/// tests found (see [`self_intersections_grouped`]), so that the recovery's
/// merging need not find them again.
pub(crate) fn check_self_intersections_grouped(
    points: &[P],
    triangles: &[[u32; 3]],
) -> Result<Option<Vec<u32>>, Error> {
    crate::geom::check::corners_valid("triangle", points, triangles)?;
    let (r, group) = self_intersections_grouped(points, triangles);
    if let Some(&t) = r.degenerate.first() {
        return Err(Error::DegenerateFacet {
            index: t as usize,
            defect: crate::FacetDefect::ZeroArea,
        });
    }
    match r.pairs.first() {
        Some(&(i, j)) => Err(Error::SelfIntersection {
            facets: (i as usize, j as usize),
            count: r.pairs.len(),
        }),
        None => Ok(group),
    }
}

/// Exact intersection test of two non-degenerate triangles given by
/// canonical vertex ids (equal id = same point), excluding the contacts
/// their shared vertices allow.
///
/// The sides of each triangle's vertices with respect to the other's plane
/// are computed once (a shared vertex is on the plane without a predicate
/// call). When the unshared vertices of one triangle lie strictly on one
/// side of the other's plane, the triangles meet at most in their shared
/// vertices: that settles almost every pair of a closed surface with two or
/// four predicate calls. The rest reuse those signs in the edge tests.
pub(crate) fn triangles_intersect(pts: &[P], a: [u32; 3], b: [u32; 3]) -> bool {
    let plane = |t: [u32; 3]| Plane::new(t.map(|v| &pts[v as usize]));
    intersect_with_planes(pts, a, b, (&plane(a), &plane(b)), false, None)
}

/// The plane of a triangle `(o, p1, p2)` for a cheap filtered side test:
/// the normal `n = (p1 − o) × (p2 − o)` and, per component, the sum of the
/// magnitudes of its two products; and the triangle's
/// [`projection_axes`] when the normal certifies them.
#[derive(Debug, Clone, Copy)]
struct Plane {
    o: P,
    n: [f64; 3],
    nabs: [f64; 3],
    axes: Option<(usize, usize)>,
    /// The triangle's coplanar group, `u32::MAX` when not known.
    group: u32,
}

/// The error bound factor of `orient2d`'s floating-point stage,
/// `(4 + 64u)·u`, `u = 2⁻⁵³`.
const PROJ_BOUND: f64 = (4.0 + 64.0 * f64::EPSILON / 2.0) * (f64::EPSILON / 2.0);

/// The error bound factor of the side test: the one of
/// [`delone_predicates::orient3d`]'s filter, `(8 + 256u)·u`, `u = 2⁻⁵³`.
const SIDE_BOUND: f64 = (8.0 + 256.0 * f64::EPSILON / 2.0) * (f64::EPSILON / 2.0);

impl Plane {
    fn new([o, p1, p2]: [&P; 3]) -> Plane {
        let e1 = [p1[0] - o[0], p1[1] - o[1], p1[2] - o[2]];
        let e2 = [p2[0] - o[0], p2[1] - o[1], p2[2] - o[2]];
        let (x1, x2) = (e1[1] * e2[2], e1[2] * e2[1]);
        let (y1, y2) = (e1[2] * e2[0], e1[0] * e2[2]);
        let (z1, z2) = (e1[0] * e2[1], e1[1] * e2[0]);
        let n = [x1 - x2, y1 - y2, z1 - z2];
        let nabs = [
            x1.abs() + x2.abs(),
            y1.abs() + y2.abs(),
            z1.abs() + z2.abs(),
        ];
        // `projection_axes` takes the first of the projections (0, 1),
        // (1, 2), (2, 0) with a nonzero exact orientation. Normal component
        // `k` is that orientation for the projection dropping axis `k`,
        // computed as `orient2d(p1, p2, o)`'s floating-point stage: nonzero
        // for certain beyond that filter's bound, zero for certain when both
        // triangle edges have no extent along one of the projection's axes
        // (a rounded difference is 0 only when it is exactly 0). The same
        // choice, or `None` (left to `projection_axes`) when in doubt.
        let mut axes = None;
        for (k, (i, j)) in [(2, (0, 1)), (0, (1, 2)), (1, (2, 0))] {
            if n[k].abs() > PROJ_BOUND * nabs[k] {
                axes = Some((i, j));
                break;
            }
            let flat = |a: usize| e1[a] == 0.0 && e2[a] == 0.0;
            if !(flat(i) || flat(j)) {
                break;
            }
        }
        Plane {
            o: *o,
            n,
            nabs,
            axes,
            group: u32::MAX,
        }
    }

    /// [`projection_axes`] of the triangle `t` this plane was made from
    /// (any rotation of it).
    #[inline]
    fn axes(&self, [a, b, c]: [&P; 3]) -> (usize, usize) {
        self.axes
            .or_else(|| projection_axes(a, b, c))
            .unwrap_or((0, 1))
    }

    /// The sign of `orient3d(t[0], t[1], t[2], q)` for the triangle `t`
    /// this plane was made from (same vertex order). `det = (q − o)·n` is
    /// the 3×3 determinant `[q − o; p1 − o; p2 − o]` expanded along its
    /// first row: every factor is a rounded coordinate difference and each
    /// term a difference of two products, the same shape as `orient3d`'s
    /// floating-point stage, so the same bound on `|det̂ − det|` (the
    /// factor times the permanent) certifies the sign. Subtracting the
    /// first row from the others shows `orient3d(o, p1, p2, q) = −det`.
    /// Uncertain cases (and tiny or non-finite bounds) take the exact
    /// predicate, through `memo` for vertex `v` at `q` (see
    /// [`exact_side_memo`]).
    #[inline(always)]
    fn side(&self, t: [&P; 3], (v, q): (u32, &P), memo: Option<&RefCell<IdMap<u64, i8>>>) -> i8 {
        match self.side_filtered(q) {
            Some(s) => s,
            None => exact_side_memo(self, t, (v, q), memo),
        }
    }

    /// The floating-point stage of [`Plane::side`]: the sign when certain.
    #[inline(always)]
    fn side_filtered(&self, q: &P) -> Option<i8> {
        let m = [q[0] - self.o[0], q[1] - self.o[1], q[2] - self.o[2]];
        let det = m[0] * self.n[0] + m[1] * self.n[1] + m[2] * self.n[2];
        let perm =
            m[0].abs() * self.nabs[0] + m[1].abs() * self.nabs[1] + m[2].abs() * self.nabs[2];
        let bound = SIDE_BOUND * perm;
        (det.abs() > bound && bound > 1e-280).then(|| -sign(det))
    }
}

/// The exact fallback of [`Plane::side`], out of line.
#[cold]
#[inline(never)]
fn exact_side(t: [&P; 3], q: &P) -> i8 {
    sign(orient3d(t[0], t[1], t[2], q))
}

/// [`exact_side`] of vertex `v` (at `q`) for the plane `pl` of `t`,
/// through `memo` (see [`intersect_with_planes`]).
#[cold]
#[inline(never)]
fn exact_side_memo(
    pl: &Plane,
    t: [&P; 3],
    (v, q): (u32, &P),
    memo: Option<&RefCell<IdMap<u64, i8>>>,
) -> i8 {
    match memo {
        Some(m) if pl.group != u32::MAX => {
            let key = u64::from(pl.group) << 32 | u64::from(v);
            if let Some(&s) = m.borrow().get(&key) {
                return s;
            }
            let s = exact_side(t, q);
            m.borrow_mut().insert(key, s);
            s
        }
        _ => exact_side(t, q),
    }
}

/// The triangle-pair test (`triangles_intersect`) with the planes of `a`
/// and `b` given; `flat`: the two are known to lie on one plane (every
/// side test is zero, [`coplanar_groups`]).
#[inline]
fn intersect_with_planes(
    pts: &[P],
    a: [u32; 3],
    b: [u32; 3],
    (pl_a, pl_b): (&Plane, &Plane),
    flat: bool,
    memo: Option<&RefCell<IdMap<u64, i8>>>,
) -> bool {
    // The side of vertex `v` of the plane of `t`. An exact fallback's
    // result is remembered per (group of `t`, vertex) when `memo` is
    // given: every triangle of a coplanar group has one plane and one
    // normal direction, hence the same sign for `v` (the vertices of a CAD
    // model's adjacent faces that lie on a planar face's plane take that
    // fallback once per face instead of once per pair).
    let side = |pl: &Plane, t: [&P; 3], vq: (u32, &P)| -> i8 {
        if flat {
            0
        } else {
            pl.side(t, vq, memo)
        }
    };
    // Bit 3i + j: a[i] == b[j]. The vertices of a non-degenerate triangle
    // are distinct points, so each vertex matches at most once.
    let eq = u32::from(a[0] == b[0])
        | u32::from(a[0] == b[1]) << 1
        | u32::from(a[0] == b[2]) << 2
        | u32::from(a[1] == b[0]) << 3
        | u32::from(a[1] == b[1]) << 4
        | u32::from(a[1] == b[2]) << 5
        | u32::from(a[2] == b[0]) << 6
        | u32::from(a[2] == b[1]) << 7
        | u32::from(a[2] == b[2]) << 8;
    let p = |v: u32| &pts[v as usize];
    if flat && eq.count_ones() < 2 {
        let axes = pl_a.axes(a.map(p));
        return flat_intersect(pts, a, b, axes, eq);
    }
    match eq.count_ones() {
        0 => disjoint_vertices_intersect(pts, a, b, side, (pl_a, pl_b)),
        1 => {
            // One shared vertex a[i] = b[j]: the triangles meet elsewhere
            // only if the edge opposite it in one meets the other (see the
            // module docs). If the other two vertices of one triangle lie
            // strictly on one side of the other's plane, they cannot.
            let k = eq.trailing_zeros() as usize;
            let (i, j) = (k / 3, k % 3);
            let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
            let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
            let (pa, pb) = (a.map(p), b.map(p));
            let (sb1, sb2) = (
                side(pl_a, pa, (b[j1], pb[j1])),
                side(pl_a, pa, (b[j2], pb[j2])),
            );
            if sb1 == sb2 && sb1 != 0 {
                return false;
            }
            let (sa1, sa2) = (
                side(pl_b, pb, (a[i1], pa[i1])),
                side(pl_b, pb, (a[i2], pa[i2])),
            );
            if sa1 == sa2 && sa1 != 0 {
                return false;
            }
            seg_tri_signs(pa[i1], pa[i2], sa1, sa2, pb, pl_b)
                || seg_tri_signs(pb[j1], pb[j2], sb1, sb2, pa, pl_a)
        }
        2 => {
            // The shared edge uv; c and f the third vertices of a and b.
            let k1 = eq.trailing_zeros() as usize;
            let k2 = (eq & (eq - 1)).trailing_zeros() as usize;
            let ic = 3 - k1 / 3 - k2 / 3;
            let jf = 3 - k1 % 3 - k2 % 3;
            let (u, v) = (a[(ic + 1) % 3], a[(ic + 2) % 3]);
            let (c, f) = (a[ic], b[jf]);
            // (u, v, c) is a rotation of a: zero exactly when f is on a's
            // plane.
            if side(pl_a, a.map(p), (f, p(f))) != 0 {
                return false;
            }
            let (x, y) = pl_a.axes([p(u), p(v), p(c)]);
            let q = |w: u32| [p(w)[x], p(w)[y]];
            let sc = orient2d(&q(u), &q(v), &q(c));
            let sf = orient2d(&q(u), &q(v), &q(f));
            // sc != 0 (a is non-degenerate); f on the line uv would make b
            // degenerate, which the caller excludes.
            sc.signum() == sf.signum()
        }
        _ => true,
    }
}

/// The pair test of two triangles on one plane sharing at most one vertex
/// (`eq` as in [`intersect_with_planes`]), in the projection `(x, y)` of
/// that plane: the same formula as the coplanar edge-against-triangle tests
/// of [`seg_tri_signs`] the general path makes (any projection that keeps
/// the plane non-degenerate gives the same verdicts), with the 18
/// orientations of each triangle's vertices against the other's edges
/// computed once instead of once per test. Most pairs of a planar face
/// (neighbours in a fan or strip) are settled before that by
/// [`edge_line_separates`].
fn flat_intersect(pts: &[P], a: [u32; 3], b: [u32; 3], (x, y): (usize, usize), eq: u32) -> bool {
    let q = |v: u32| [pts[v as usize][x], pts[v as usize][y]];
    let (qa, qb) = (a.map(q), b.map(q));
    if edge_line_separates(&qa, &qb, eq) {
        return false;
    }
    // s(e, p)[j]: the side of p of edge j (e[j] -> e[j + 1]) of e.
    let s = |e: &[Q; 3], p: &Q| [0, 1, 2].map(|j| sign(orient2d(&e[j], &e[(j + 1) % 3], p)));
    let (sab, sba) = (qb.map(|p| s(&qa, &p)), qa.map(|p| s(&qb, &p)));
    let inside = |s: &[i8; 3]| !(s.contains(&1) && s.contains(&-1));
    // Edge j of a against edge k of b.
    let cross = |j: usize, k: usize| {
        let (j1, k1) = ((j + 1) % 3, (k + 1) % 3);
        let d = [sab[k][j], sab[k1][j], sba[j][k], sba[j1][k]];
        seg_seg_2d_signs(&qa[j], &qa[j1], &qb[k], &qb[k1], d)
    };
    if eq == 0 {
        // Every edge of each against the other triangle.
        return sba.iter().any(inside)
            || sab.iter().any(inside)
            || (0..3).any(|j| (0..3).any(|k| cross(j, k)));
    }
    // One shared vertex a[i] = b[j]: the edges opposite it.
    let k = eq.trailing_zeros() as usize;
    let (i, j) = (k / 3, k % 3);
    let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
    let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
    inside(&sba[i1])
        || inside(&sba[i2])
        || (0..3).any(|k| cross(i1, k))
        || inside(&sab[j1])
        || inside(&sab[j2])
        || (0..3).any(|k| cross(k, j1))
}

/// Two triangles of one plane (projected, `eq` as in
/// [`intersect_with_planes`], at most one shared vertex) meet at most in
/// their shared vertex because the line of an edge of one has the other's
/// unshared vertices strictly on its far side (away from the first
/// triangle's third vertex). Only edges through the shared vertex can do
/// that when there is one. A sufficient test, exact: `false` decides
/// nothing.
fn edge_line_separates(qa: &[Q; 3], qb: &[Q; 3], eq: u32) -> bool {
    // Every point of `far` is strictly outside edge `j` of triangle `t`
    // (whose orientation is `o`).
    let outside = |t: &[Q; 3], o: f64, j: usize, far: &[&Q]| {
        let (p, r) = (&t[j], &t[(j + 1) % 3]);
        far.iter().all(|f| {
            let s = orient2d(p, r, f);
            s != 0.0 && (s > 0.0) != (o > 0.0)
        })
    };
    let oa = orient2d(&qa[0], &qa[1], &qa[2]);
    let ob = orient2d(&qb[0], &qb[1], &qb[2]);
    if oa == 0.0 || ob == 0.0 {
        return false;
    }
    if eq == 0 {
        let (fa, fb) = (qa.each_ref(), qb.each_ref());
        return (0..3).any(|j| outside(qa, oa, j, &fb)) || (0..3).any(|j| outside(qb, ob, j, &fa));
    }
    // Shared vertex a[i] = b[j]: the edges i and i + 2 of a (and j, j + 2
    // of b) pass through it.
    let k = eq.trailing_zeros() as usize;
    let (i, j) = (k / 3, k % 3);
    let fb = [&qb[(j + 1) % 3], &qb[(j + 2) % 3]];
    let fa = [&qa[(i + 1) % 3], &qa[(i + 2) % 3]];
    outside(qa, oa, i, &fb)
        || outside(qa, oa, (i + 2) % 3, &fb)
        || outside(qb, ob, j, &fa)
        || outside(qb, ob, (j + 2) % 3, &fa)
}

/// The triangle-pair test for two triangles without a common vertex.
fn disjoint_vertices_intersect(
    pts: &[P],
    a: [u32; 3],
    b: [u32; 3],
    side: impl Fn(&Plane, [&P; 3], (u32, &P)) -> i8,
    (pl_a, pl_b): (&Plane, &Plane),
) -> bool {
    let (pa, pb) = (a.map(|v| &pts[v as usize]), b.map(|v| &pts[v as usize]));
    let sb = [0, 1, 2].map(|k| side(pl_a, pa, (b[k], pb[k])));
    if sb[0] == sb[1] && sb[1] == sb[2] && sb[0] != 0 {
        return false;
    }
    let sa = [0, 1, 2].map(|k| side(pl_b, pb, (a[k], pa[k])));
    if sa[0] == sa[1] && sa[1] == sa[2] && sa[0] != 0 {
        return false;
    }
    (0..3).any(|k| seg_tri_signs(pa[k], pa[(k + 1) % 3], sa[k], sa[(k + 1) % 3], pb, pl_b))
        || (0..3).any(|k| seg_tri_signs(pb[k], pb[(k + 1) % 3], sb[k], sb[(k + 1) % 3], pa, pl_a))
}

fn sign(x: f64) -> i8 {
    if x > 0.0 {
        1
    } else if x < 0.0 {
        -1
    } else {
        0
    }
}

/// Does the closed segment `pq` meet the closed non-degenerate triangle
/// `abc`? Exact.
#[cfg(test)]
fn seg_tri(p: &P, q: &P, a: &P, b: &P, c: &P) -> bool {
    let op = sign(orient3d(a, b, c, p));
    let oq = sign(orient3d(a, b, c, q));
    seg_tri_signs(p, q, op, oq, [a, b, c], &Plane::new([a, b, c]))
}

/// [`seg_tri`] given `op`, `oq`: the signs of `orient3d(a, b, c, p)` and
/// `orient3d(a, b, c, q)`, and the plane of `abc`.
fn seg_tri_signs(p: &P, q: &P, op: i8, oq: i8, [a, b, c]: [&P; 3], pl: &Plane) -> bool {
    if op == oq && op != 0 {
        return false;
    }
    if op == 0 && oq == 0 {
        // Coplanar: a 2D test in a projection that keeps abc non-degenerate.
        let (x, y) = pl.axes([a, b, c]);
        let f = |u: &P| [u[x], u[y]];
        return seg_tri_2d(&f(p), &f(q), &f(a), &f(b), &f(c));
    }
    // The line pq crosses the plane once, inside [p, q]: the crossing is in
    // the closed triangle iff pq "sees" its edges all on one side.
    let s = [
        sign(orient3d(p, q, a, b)),
        sign(orient3d(p, q, b, c)),
        sign(orient3d(p, q, c, a)),
    ];
    !(s.contains(&1) && s.contains(&-1))
}

type Q = [f64; 2];

fn in_tri_2d(p: &Q, a: &Q, b: &Q, c: &Q) -> bool {
    let s = [
        sign(orient2d(a, b, p)),
        sign(orient2d(b, c, p)),
        sign(orient2d(c, a, p)),
    ];
    !(s.contains(&1) && s.contains(&-1))
}

/// Closed segments `pq` and `rs` in the plane intersect. Exact.
fn seg_seg_2d(p: &Q, q: &Q, r: &Q, s: &Q) -> bool {
    let d = [
        sign(orient2d(p, q, r)),
        sign(orient2d(p, q, s)),
        sign(orient2d(r, s, p)),
        sign(orient2d(r, s, q)),
    ];
    seg_seg_2d_signs(p, q, r, s, d)
}

/// [`seg_seg_2d`] given the signs of `orient2d(p, q, r)`,
/// `orient2d(p, q, s)`, `orient2d(r, s, p)` and `orient2d(r, s, q)`.
fn seg_seg_2d_signs(p: &Q, q: &Q, r: &Q, s: &Q, [d1, d2, d3, d4]: [i8; 4]) -> bool {
    if d1 * d2 < 0 && d3 * d4 < 0 {
        return true;
    }
    let on = |a: &Q, b: &Q, c: &Q| {
        a[0].min(b[0]) <= c[0]
            && c[0] <= a[0].max(b[0])
            && a[1].min(b[1]) <= c[1]
            && c[1] <= a[1].max(b[1])
    };
    (d1 == 0 && on(p, q, r))
        || (d2 == 0 && on(p, q, s))
        || (d3 == 0 && on(r, s, p))
        || (d4 == 0 && on(r, s, q))
}

fn seg_tri_2d(p: &Q, q: &Q, a: &Q, b: &Q, c: &Q) -> bool {
    in_tri_2d(p, a, b, c)
        || in_tri_2d(q, a, b, c)
        || seg_seg_2d(p, q, a, b)
        || seg_seg_2d(p, q, b, c)
        || seg_seg_2d(p, q, c, a)
}

/// Edges of a triangulated surface that keep it from being a closed,
/// consistently oriented 2-manifold, as found by [`manifold_report`]. Each
/// edge is `[min, max]` by point index, lists sorted.
///
/// ```
/// let r = delone::tet::intersect::manifold_report(&[[0, 1, 2]]);
/// assert_eq!(r.boundary_edges, vec![[0, 1], [0, 2], [1, 2]]);
/// assert!(!r.is_closed());
/// ```
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct ManifoldReport {
    /// Edges in exactly one triangle.
    pub boundary_edges: Vec<[u32; 2]>,
    /// Edges in more than two triangles.
    pub nonmanifold_edges: Vec<[u32; 2]>,
    /// Edges in exactly two triangles that traverse them in the same
    /// direction (inconsistent orientation).
    pub inconsistent_edges: Vec<[u32; 2]>,
}

impl ManifoldReport {
    /// Every edge is in exactly two triangles.
    ///
    /// ```
    /// let tet = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];
    /// assert!(delone::tet::intersect::manifold_report(&tet).is_closed());
    /// ```
    pub fn is_closed(&self) -> bool {
        self.boundary_edges.is_empty() && self.nonmanifold_edges.is_empty()
    }

    /// Closed and consistently oriented.
    ///
    /// ```
    /// let tet = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 2, 3]];
    /// let r = delone::tet::intersect::manifold_report(&tet);
    /// assert!(r.is_closed() && !r.is_oriented_closed());
    /// assert_eq!(r.inconsistent_edges, vec![[0, 2], [0, 3], [2, 3]]);
    /// ```
    pub fn is_oriented_closed(&self) -> bool {
        self.is_closed() && self.inconsistent_edges.is_empty()
    }
}

/// Classifies the edges of a triangulated surface (by point index; merge
/// duplicate points first if the input has them). Deterministic (sorting, no
/// hashing).
///
/// ```
/// // Two tetrahedra glued along edge 0-1 (and nothing else): non-manifold.
/// let t = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2], [0, 4, 1], [0, 1, 5], [1, 4, 5], [0, 5, 4]];
/// let r = delone::tet::intersect::manifold_report(&t);
/// assert_eq!(r.nonmanifold_edges, vec![[0, 1]]);
/// ```
pub fn manifold_report(triangles: &[[u32; 3]]) -> ManifoldReport {
    // Every edge is filed under its smaller endpoint as `max << 1 | dir`
    // (dir 1: traversed min -> max); a counting sort by the smaller
    // endpoint, then an insertion sort of each (small) bucket, lists the
    // edges in (min, max) order without a global sort.
    let len = 3 * triangles.len();
    let nv = triangles
        .iter()
        .flatten()
        .max()
        .map_or(0, |&m| m as usize + 1);
    if nv > 4 * len + 1024 {
        // Sparse vertex ids: buckets would waste memory; sort instead.
        let mut e: Vec<u64> = Vec::with_capacity(len);
        for t in triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                let (lo, hi) = (a.min(b), a.max(b));
                e.push((u64::from(lo) << 33) | (u64::from(hi) << 1) | u64::from(a < b));
            }
        }
        e.sort_unstable();
        let mut r = ManifoldReport::default();
        classify(&e, |x| ((x >> 33) as u32, (x >> 1) as u32), &mut r);
        return r;
    }
    let mut start = vec![0u32; nv + 1];
    for t in triangles {
        for k in 0..3 {
            start[t[k].min(t[(k + 1) % 3]) as usize + 1] += 1;
        }
    }
    for v in 0..nv {
        start[v + 1] += start[v];
    }
    let mut fill = start.clone();
    let mut items = vec![0u64; len];
    for t in triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let lo = a.min(b) as usize;
            items[fill[lo] as usize] = (u64::from(a.max(b)) << 1) | u64::from(a < b);
            fill[lo] += 1;
        }
    }
    drop(fill);
    let mut r = ManifoldReport::default();
    for v in 0..nv {
        let bucket = &mut items[start[v] as usize..start[v + 1] as usize];
        sort_bucket(bucket);
        classify(bucket, |x| (v as u32, (x >> 1) as u32), &mut r);
    }
    r
}

/// Adds the edges of `e` (sorted, equal edges adjacent; `edge` gives the
/// `(min, max)` of an entry, bit 0 its direction) to the report.
/// Sorts a per-vertex bucket of edge keys in place (insertion sort: the
/// buckets hold a vertex's few incident edges).
pub(crate) fn sort_bucket(bucket: &mut [u64]) {
    for i in 1..bucket.len() {
        let x = bucket[i];
        let mut j = i;
        while j > 0 && bucket[j - 1] > x {
            bucket[j] = bucket[j - 1];
            j -= 1;
        }
        bucket[j] = x;
    }
}

fn classify(e: &[u64], edge: impl Fn(u64) -> (u32, u32), r: &mut ManifoldReport) {
    for run in e.chunk_by(|&a, &b| edge(a) == edge(b)) {
        let (lo, hi) = edge(run[0]);
        match *run {
            [_] => r.boundary_edges.push([lo, hi]),
            [a, b] => {
                if (a & 1) == (b & 1) {
                    r.inconsistent_edges.push([lo, hi]);
                }
            }
            _ => r.nonmanifold_edges.push([lo, hi]),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::key;

    /// Brute force over all pairs: the grid must find the same pairs.
    fn brute(points: &[P], tris: &[[u32; 3]]) -> Vec<(u32, u32)> {
        let mut v = Vec::new();
        let deg: Vec<bool> = tris
            .iter()
            .map(|t| {
                collinear(
                    &points[t[0] as usize],
                    &points[t[1] as usize],
                    &points[t[2] as usize],
                )
            })
            .collect();
        let canon = |v: u32| {
            points
                .iter()
                .position(|q| key(q) == key(&points[v as usize]))
                .unwrap() as u32
        };
        let tris: Vec<[u32; 3]> = tris.iter().map(|t| t.map(canon)).collect();
        for i in 0..tris.len() {
            for j in i + 1..tris.len() {
                if !deg[i] && !deg[j] && triangles_intersect(points, tris[i], tris[j]) {
                    v.push((i as u32, j as u32));
                }
            }
        }
        v
    }

    fn rng(seed: u64) -> impl FnMut() -> u64 {
        let mut s = seed;
        move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s
        }
    }

    #[test]
    fn grid_matches_brute_force_on_random_soups() {
        let mut r = rng(0x1234_5678_9abc_def1);
        for round in 0..30 {
            // Points on a small integer lattice: many exact coplanar,
            // collinear and touching configurations.
            let np = 12 + round;
            let pts: Vec<P> = (0..np)
                .map(|_| [0, 1, 2].map(|_| (r() % 5) as f64))
                .collect();
            let tris: Vec<[u32; 3]> = (0..25)
                .map(|_| [0, 1, 2].map(|_| (r() % np as u64) as u32))
                .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
                .collect();
            let got = self_intersections(&pts, &tris);
            assert_eq!(got.pairs, brute(&pts, &tris), "round {round}");
        }
    }

    /// The narrow phase as it was before the side filter (one shared
    /// vertex list per pair, every edge test from scratch): the reference
    /// the filtered version must agree with.
    fn triangles_intersect_ref(pts: &[P], a: [u32; 3], b: [u32; 3]) -> bool {
        let p = |v: u32| &pts[v as usize];
        let shared: Vec<(usize, usize)> = (0..3)
            .flat_map(|i| (0..3).map(move |j| (i, j)))
            .filter(|&(i, j)| a[i] == b[j])
            .collect();
        match shared.len() {
            0 => {
                (0..3).any(|k| seg_tri(p(a[k]), p(a[(k + 1) % 3]), p(b[0]), p(b[1]), p(b[2])))
                    || (0..3)
                        .any(|k| seg_tri(p(b[k]), p(b[(k + 1) % 3]), p(a[0]), p(a[1]), p(a[2])))
            }
            1 => {
                let (i, j) = shared[0];
                let (a1, a2) = (a[(i + 1) % 3], a[(i + 2) % 3]);
                let (b1, b2) = (b[(j + 1) % 3], b[(j + 2) % 3]);
                seg_tri(p(a1), p(a2), p(b[0]), p(b[1]), p(b[2]))
                    || seg_tri(p(b1), p(b2), p(a[0]), p(a[1]), p(a[2]))
            }
            2 => {
                let (u, v) = (a[shared[0].0], a[shared[1].0]);
                let c = a[3 - shared[0].0 - shared[1].0];
                let f = b[3 - shared[0].1 - shared[1].1];
                if orient3d(p(u), p(v), p(c), p(f)) != 0.0 {
                    return false;
                }
                let (x, y) = projection_axes(p(u), p(v), p(c)).unwrap_or((0, 1));
                let q = |w: u32| [p(w)[x], p(w)[y]];
                orient2d(&q(u), &q(v), &q(c)).signum() == orient2d(&q(u), &q(v), &q(f)).signum()
            }
            _ => true,
        }
    }

    #[test]
    fn side_filter_agrees_with_reference_on_every_pair() {
        let mut r = rng(0x0bad_cafe_dead_beef);
        let mut pairs = [0usize; 2];
        for round in 0..40 {
            // Small lattices (many exact coplanar, collinear, touching and
            // shared-vertex configurations) and a finer one.
            let span = if round % 2 == 0 { 3 } else { 7 };
            let np = 8 + round / 2;
            let pts: Vec<P> = (0..np)
                .map(|_| [0, 1, 2].map(|_| (r() % span) as f64 * 0.5))
                .collect();
            let canon = canonical_ids(&pts);
            let tris: Vec<[u32; 3]> = (0..30)
                .map(|_| [0, 1, 2].map(|_| (r() % np as u64) as u32))
                .filter(|t| {
                    let [a, b, c] = t.map(|v| &pts[v as usize]);
                    !collinear(a, b, c)
                })
                .map(|t| t.map(|v| canon[v as usize]))
                .collect();
            for i in 0..tris.len() {
                for j in i + 1..tris.len() {
                    let want = triangles_intersect_ref(&pts, tris[i], tris[j]);
                    assert_eq!(
                        triangles_intersect(&pts, tris[i], tris[j]),
                        want,
                        "round {round}: {:?} {:?}",
                        tris[i],
                        tris[j]
                    );
                    pairs[usize::from(want)] += 1;
                }
            }
        }
        // Both outcomes were exercised.
        assert!(pairs[0] > 100 && pairs[1] > 100, "{pairs:?}");
    }

    #[test]
    fn plane_side_is_the_orient3d_sign() {
        let mut r = rng(0x0123_4567_89ab_cdef);
        let mut f = || (r() >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
        for round in 0..20_000 {
            let t = [[f(), f(), f()], [f(), f(), f()], [f(), f(), f()]];
            let tr = [&t[0], &t[1], &t[2]];
            // Random points, points near the plane, and points exactly on
            // it (an affine combination with dyadic weights when exact).
            let q = match round % 3 {
                0 => [f(), f(), f()],
                1 => {
                    let (u, v) = (f(), f());
                    [0, 1, 2].map(|k| t[0][k] + u * (t[1][k] - t[0][k]) + v * (t[2][k] - t[0][k]))
                }
                _ => [0, 1, 2].map(|k| 0.5 * (t[0][k] + t[1][k])),
            };
            let pl = Plane::new(tr);
            assert_eq!(
                pl.side(tr, (0, &q), None),
                sign(orient3d(&t[0], &t[1], &t[2], &q))
            );
        }
    }

    #[test]
    fn plane_axes_are_the_projection_axes() {
        let mut r = rng(0x005e_ed0f_a4e5);
        let mut f = || (r() >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
        let (mut known, mut left) = (0, 0);
        for round in 0..30_000 {
            let mut t = [[f(), f(), f()], [f(), f(), f()], [f(), f(), f()]];
            // Axis-parallel triangles (one or two coordinates shared), and
            // triangles whose projections are nearly or exactly degenerate:
            // the third point on (or next to) the line of the first two in
            // one projection.
            let k = round % 3;
            match round % 4 {
                0 => {}
                1 => (t[1][k], t[2][k]) = (t[0][k], t[0][k]),
                2 => {
                    let u = f();
                    let (i, j) = ((k + 1) % 3, (k + 2) % 3);
                    for a in [i, j] {
                        t[2][a] = t[0][a] + u * (t[1][a] - t[0][a]);
                    }
                    if round % 8 == 2 {
                        t[2][i] = f64::from_bits(t[2][i].to_bits() + 1);
                    }
                }
                _ => (t[1][k], t[2][k]) = (t[0][k], t[0][k] + 1e-17),
            }
            let tr = [&t[0], &t[1], &t[2]];
            let pl = Plane::new(tr);
            if collinear(tr[0], tr[1], tr[2]) {
                continue;
            }
            let want = projection_axes(tr[0], tr[1], tr[2]);
            if pl.axes.is_some() {
                known += 1;
                assert_eq!(pl.axes, want, "{t:?}");
            } else {
                left += 1;
            }
            assert_eq!(Some(pl.axes(tr)), want, "{t:?}");
        }
        // Both the certified choice and the fallback were exercised.
        assert!(known > 10_000 && left > 100, "{known} {left}");
    }

    #[test]
    fn canonical_ids_name_the_first_equal_point() {
        let pts = [
            [1.0, 0.0, 0.0],
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [-0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
        ];
        assert_eq!(canonical_ids(&pts), vec![0, 1, 0, 1, 4]);
    }

    /// The edge classification by one global sort of `(min, max, dir)`.
    fn manifold_ref(triangles: &[[u32; 3]]) -> ManifoldReport {
        let mut e: Vec<(u32, u32, i8)> = Vec::new();
        for t in triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                e.push(if a < b { (a, b, 1) } else { (b, a, -1) });
            }
        }
        e.sort_unstable();
        let mut r = ManifoldReport::default();
        for g in e.chunk_by(|x, y| (x.0, x.1) == (y.0, y.1)) {
            let edge = [g[0].0, g[0].1];
            match g.len() {
                1 => r.boundary_edges.push(edge),
                2 if g[0].2 == g[1].2 => r.inconsistent_edges.push(edge),
                2 => {}
                _ => r.nonmanifold_edges.push(edge),
            }
        }
        r
    }

    #[test]
    fn manifold_report_matches_a_global_sort() {
        let mut r = rng(0x05ee_d0fe_d9e5);
        for round in 0..40 {
            // Dense ids (bucket path) and, every fourth round, sparse huge
            // ids (sort path).
            let np = 6 + round as u64;
            let sparse = round % 4 == 3;
            let tris: Vec<[u32; 3]> = (0..3 * np)
                .map(|_| {
                    [0, 1, 2].map(|_| {
                        let v = (r() % np) as u32;
                        if sparse {
                            v * 97_003 + 1_000_000
                        } else {
                            v
                        }
                    })
                })
                .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
                .collect();
            assert_eq!(manifold_report(&tris), manifold_ref(&tris), "round {round}");
        }
        // A closed octahedron and its flipped copy.
        let oct = [
            [0, 2, 4],
            [2, 1, 4],
            [1, 3, 4],
            [3, 0, 4],
            [2, 0, 5],
            [1, 2, 5],
            [3, 1, 5],
            [0, 3, 5],
        ];
        assert!(manifold_report(&oct).is_oriented_closed());
        assert_eq!(manifold_report(&oct), manifold_ref(&oct));
    }

    #[test]
    fn classification_cases() {
        let o = [0.0, 0.0, 0.0];
        let x = [1.0, 0.0, 0.0];
        let y = [0.0, 1.0, 0.0];
        // 0..3: base triangle in z = 0.
        let mut pts = vec![o, x, y];
        let base = [0u32, 1, 2];
        let mut case = |extra: &[P], t: [u32; 3]| -> bool {
            pts.truncate(3);
            pts.extend_from_slice(extra);
            !self_intersections(&pts, &[base, t]).pairs.is_empty()
        };
        // Proper crossing.
        assert!(case(
            &[[0.2, 0.2, -1.0], [0.2, 0.2, 1.0], [0.3, 0.2, 1.0]],
            [3, 4, 5]
        ));
        // Vertex touching the interior of the other triangle.
        assert!(case(
            &[[0.2, 0.2, 0.0], [0.2, 0.2, 1.0], [0.3, 0.2, 1.0]],
            [3, 4, 5]
        ));
        // Edge-edge crossing (an edge of T2 passes through edge o-x).
        assert!(case(
            &[[0.5, -1.0, -1.0], [0.5, 1.0, 1.0], [0.5, -1.0, 1.0]],
            [3, 4, 5]
        ));
        // Coplanar overlap without shared vertices.
        assert!(case(
            &[[0.1, 0.1, 0.0], [2.0, 0.1, 0.0], [0.1, 2.0, 0.0]],
            [3, 4, 5]
        ));
        // Disjoint: parallel plane.
        assert!(!case(
            &[[0.1, 0.1, 1.0], [2.0, 0.1, 1.0], [0.1, 2.0, 1.0]],
            [3, 4, 5]
        ));
        // Shared vertex only: legal.
        assert!(!case(&[[-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]], [0, 3, 4]));
        // Shared vertex, other triangle pierces: illegal.
        assert!(case(&[[0.3, 0.3, -1.0], [0.3, 0.3, 1.0]], [0, 3, 4]));
        // Shared vertex, coplanar and overlapping wedge: illegal.
        assert!(case(&[[1.0, 1.0, 0.0], [2.0, 0.5, 0.0]], [0, 3, 4]));
        // Shared vertex, collinear edges overlapping (o-x and o-(2,0,0)).
        assert!(case(&[[2.0, 0.0, 0.0], [0.0, -1.0, 0.0]], [0, 3, 4]));
        // Shared edge, non-coplanar: legal.
        assert!(!case(&[[0.3, 0.3, 1.0]], [1, 0, 3]));
        // Shared edge, coplanar opposite side: legal; same side: illegal.
        assert!(!case(&[[0.5, -0.5, 0.0]], [1, 0, 3]));
        assert!(case(&[[0.2, 0.2, 0.0]], [1, 0, 3]));
        // Duplicate triangle (other orientation).
        assert!(case(&[], [0, 2, 1]));
        // Duplicate by coordinates: point 3 == point 0.
        assert!(case(&[o], [3, 2, 1]));
    }

    #[test]
    fn degenerate_triangles_are_listed_not_paired() {
        let pts = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        let r = self_intersections(&pts, &[[0, 1, 3], [0, 1, 2]]);
        assert_eq!(r.degenerate, vec![1]);
        assert!(r.pairs.is_empty());
        assert_eq!(
            check_self_intersections(&pts, &[[0, 1, 3], [0, 1, 2]]),
            Err(Error::DegenerateFacet {
                index: 1,
                defect: crate::FacetDefect::ZeroArea
            })
        );
        assert!(matches!(
            check_self_intersections(&pts, &[[0, 1, 9]]),
            Err(Error::IndexOutOfRange {
                item: "triangle",
                index: 0,
                vertex: 9,
                ..
            })
        ));
    }

    /// The pair test of triangles known to lie on one plane (the shared
    /// orientations of `flat_intersect`) against the reference, on planes
    /// of each projection, with shared vertices, touching and overlapping
    /// triangles.
    #[test]
    fn flat_pairs_match_the_reference() {
        let mut r = rng(0xf1a7);
        let planes: [fn(f64, f64) -> P; 3] = [
            |u, v| [u, v, 0.5 * u + 0.25 * v],
            |u, v| [0.75, u, v],
            |u, v| [u, 0.5 * u - 2.0, v],
        ];
        let mut seen = [0usize; 2];
        for on in planes {
            // A small pool of points on a coarse grid: many shared,
            // collinear and touching configurations.
            let pts: Vec<P> = (0..12)
                .map(|_| on((r() % 7) as f64 * 0.5, (r() % 7) as f64 * 0.5))
                .collect();
            for _ in 0..20_000 {
                let mut tri = || [0, 1, 2].map(|_| (r() % 12) as u32);
                let (a, b) = (tri(), tri());
                let p = |v: u32| &pts[v as usize];
                let distinct = |t: [u32; 3]| !collinear(p(t[0]), p(t[1]), p(t[2]));
                let shared = (0..3).filter(|&i| b.contains(&a[i])).count();
                // Equal points have equal ids here only if they are the
                // same entry: keep pools of distinct points.
                let unique = a
                    .iter()
                    .chain(&b)
                    .all(|&v| (0..12).all(|w| w == v || pts[w as usize] != pts[v as usize]));
                if !distinct(a) || !distinct(b) || shared > 1 || !unique {
                    continue;
                }
                let pl = (&Plane::new(a.map(p)), &Plane::new(b.map(p)));
                let want = triangles_intersect_ref(&pts, a, b);
                assert_eq!(
                    intersect_with_planes(&pts, a, b, pl, true, None),
                    want,
                    "{a:?} {b:?}"
                );
                seen[usize::from(want)] += 1;
            }
        }
        assert!(seen[0] > 500 && seen[1] > 500, "{seen:?}");
    }

    #[test]
    fn remembered_sides_match_brute_force_on_faceted_soups() {
        // The faces of the cube [0, 4]^3, each 2x2 squares split in two
        // (six coplanar groups of 8), and random triangles on or next to
        // the lattice {0, ..., 4}^3: many of their vertices lie on or
        // just off the faces' planes, so the exact sides remembered per
        // (group, vertex) are reused across the triangles of a face.
        let mut r = rng(0xface);
        let mut pts: Vec<P> = Vec::new();
        let mut tris: Vec<[u32; 3]> = Vec::new();
        for k in 0..3 {
            for side in [0.0, 4.0] {
                let base = pts.len() as u32;
                for j in 0..3 {
                    for i in 0..3 {
                        let mut q = [0.0; 3];
                        q[k] = side;
                        q[(k + 1) % 3] = 2.0 * f64::from(i);
                        q[(k + 2) % 3] = 2.0 * f64::from(j);
                        pts.push(q);
                    }
                }
                let at = |i: u32, j: u32| base + 3 * j + i;
                for j in 0..2 {
                    for i in 0..2 {
                        let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                        if side > 0.0 {
                            tris.extend([[a, b, c], [a, c, d]]);
                        } else {
                            tris.extend([[a, c, b], [a, d, c]]);
                        }
                    }
                }
            }
        }
        let group = coplanar_groups(&pts, &tris, &[]);
        for f in 0..6 {
            assert!(group[8 * f..8 * f + 8].iter().all(|&g| g == group[8 * f]));
        }
        let (cube_pts, cube_tris) = (pts.len(), tris.len());
        for round in 0..40 {
            pts.truncate(cube_pts);
            tris.truncate(cube_tris);
            for _ in 0..6 {
                // Some coordinates a few units in the last place off the
                // lattice: sides the filter cannot certify that are not 0.
                let t = [0, 1, 2].map(|_| {
                    let c = [0, 1, 2].map(|_| {
                        let x = (r() % 5) as f64;
                        match r() % 4 {
                            0 => x + 4.0 * f64::EPSILON,
                            1 => x - 4.0 * f64::EPSILON,
                            _ => x,
                        }
                    });
                    pts.push(c);
                    pts.len() as u32 - 1
                });
                tris.push(t);
            }
            let got = self_intersections(&pts, &tris);
            assert_eq!(got.pairs, brute(&pts, &tris), "round {round}");
        }
    }

    #[test]
    fn edge_lines_separate_only_disjoint_flat_pairs() {
        // Random pairs of triangles on a coarse grid of the plane z = 0
        // (shared vertices, touching and collinear cases): the shortcut
        // never settles a pair that meets, and settles most that do not.
        let mut r = rng(0x5e9a);
        let pts: Vec<P> = (0..12)
            .map(|_| [(r() % 7) as f64 * 0.5, (r() % 7) as f64 * 0.5, 0.0])
            .collect();
        let (mut settled, mut open) = (0usize, 0usize);
        for _ in 0..20_000 {
            let mut tri = || [0, 1, 2].map(|_| (r() % 12) as u32);
            let (a, b) = (tri(), tri());
            let p = |v: u32| &pts[v as usize];
            let distinct = |t: [u32; 3]| !collinear(p(t[0]), p(t[1]), p(t[2]));
            let unique = a
                .iter()
                .chain(&b)
                .all(|&v| (0..12).all(|w| w == v || pts[w as usize] != pts[v as usize]));
            let eq = (0..9)
                .filter(|&k| a[k / 3] == b[k % 3])
                .fold(0u32, |m, k| m | 1 << k);
            if !distinct(a) || !distinct(b) || eq.count_ones() > 1 || !unique {
                continue;
            }
            let q = |v: u32| [pts[v as usize][0], pts[v as usize][1]];
            let meet = triangles_intersect_ref(&pts, a, b);
            if edge_line_separates(&a.map(q), &b.map(q), eq) {
                assert!(!meet, "{a:?} {b:?}");
                settled += 1;
            } else if !meet {
                open += 1;
            }
        }
        assert!(settled > 400 && open * 10 < settled, "{settled} {open}");
    }

    #[test]
    fn pairs_in_a_coplanar_group_match_brute_force() {
        // A 4x4 grid of squares on a slanted plane (one coplanar group of
        // 32 triangles), a coplanar triangle overlapping it, one crossing
        // it and one above it.
        let on = |x: f64, y: f64| [x, y, 0.5 * x + 0.25 * y];
        let mut pts: Vec<P> = (0..25)
            .map(|i| on(f64::from(i % 5), f64::from(i / 5)))
            .collect();
        let mut tris: Vec<[u32; 3]> = Vec::new();
        for j in 0..4 {
            for i in 0..4 {
                let c = 5 * j + i;
                tris.push([c, c + 1, c + 6]);
                tris.push([c, c + 6, c + 5]);
            }
        }
        pts.extend([on(0.5, 0.25), on(1.75, 0.5), on(1.0, 1.5)]);
        pts.extend([[2.5, 2.5, -5.0], [2.6, 2.5, 5.0], [2.5, 2.6, 5.0]]);
        pts.extend([[0.5, 0.5, 9.0], [1.5, 0.5, 9.0], [0.5, 1.5, 9.0]]);
        tris.extend([[25, 26, 27], [28, 29, 30], [31, 32, 33]]);
        let group = coplanar_groups(&pts, &tris, &[]);
        assert!(group[..32].iter().all(|&g| g == 0) && group[32] != 0);
        let got = self_intersections(&pts, &tris).pairs;
        assert_eq!(got, brute(&pts, &tris));
        // The overlapping triangle meets some grid triangles, the
        // crossing one some others; grid triangles meet none of each other.
        assert!(got.iter().any(|&(_, j)| j == 32) && got.iter().any(|&(_, j)| j == 33));
        assert!(got.iter().all(|&(i, j)| i < 32 && j >= 32 && j != 34));
    }
}
