//! Constrained Delaunay triangulation of a planar straight-line graph.
//!
//! The pipeline of [`constrained_triangulation`]:
//!
//! 1. the Delaunay triangulation of the points ([`Delaunay2`]; exact
//!    duplicates are merged and reported), taken over as the records of
//!    the constrained mesh (`tri::cmesh`, ghost triangles included; the
//!    label on a constrained half-edge is its input segment), whose walk,
//!    insertion, edge flip and Lawson loop every step below uses;
//! 2. segment insertion by **flips** (Sloan 1993): walk from one end of the
//!    segment to the other collecting the edges it crosses, then flip them
//!    (an edge whose quadrilateral is not convex waits at the back of the
//!    queue; a flipped edge that still crosses the segment goes back in),
//!    then restore the Delaunay property of the new edges by Lawson flips that
//!    never flip a constrained edge. The walk stops at the first *event*:
//!    a vertex exactly on the segment splits the segment there; a crossed
//!    constrained edge is split at a new Steiner vertex at the intersection
//!    (computed in floating point and inserted by constrained Bowyer–Watson,
//!    which refuses a point that would make a triangle that is not
//!    counterclockwise), and the two halves are inserted in turn. Every
//!    split is reported;
//! 3. carving: flood fills across unconstrained edges from the hull (unless
//!    `convex_hull`), from every hole point (removal) and from every region
//!    point (attribute and area bound; later regions win);
//! 4. the records are compacted in place (output vertex ids, no ghosts):
//!    refinement continues on them, and the [`Cdt`] is a view of them.
//!
//! Every combinatorial decision uses exact predicates, on coordinates scaled
//! by an exact power of two (as the kernel does).
//!
//! # References
//! S. W. Sloan, *A fast algorithm for generating constrained Delaunay
//! triangulations*, Computers & Structures 47 (1993).
//! L. P. Chew, *Constrained Delaunay triangulations*, Algorithmica 4 (1989).
//! C. L. Lawson, *Software for C1 surface interpolation*, 1977.

use std::collections::{HashMap, HashSet, VecDeque};

use delone_predicates::{incircle, orient2d};

use super::cmesh::{CMesh, Ins, Tri, FLAGS, LABEL};
use super::conforming::Grid;
use super::mesh::{check_edges, find_edge};
use super::topo::{edge, is_ghost, pack, unpack, DEAD, INF, NEXT, PREV};
use super::Delaunay2;
use crate::geom::{pow2_scale, scaled};
use crate::model::pslg::Pslg;
use crate::{Error, Violation, NONE};
use delone_predicates::{two_product, two_sum};

/// Options of [`constrained_triangulation`].
///
/// ```
/// let o = delone::tri::constrain::CdtOptions { convex_hull: true };
/// assert!(o.convex_hull);
/// ```
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct CdtOptions {
    /// Keep every triangle of the convex hull instead of removing those
    /// outside the outer segments (Triangle's `-c`; default `false`).
    pub convex_hull: bool,
}

/// A piece of an input segment in the output mesh.
///
/// ```
/// let s = delone::tri::constrain::Subsegment { v: [0, 1], marker: 2, segment: 0, bounding: true };
/// assert_eq!(s.marker, 2);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Subsegment {
    /// Its two vertices (output ids).
    pub v: [u32; 2],
    /// The marker of the input segment.
    pub marker: i32,
    /// The input segment it belongs to (the first one, for overlapping
    /// collinear segments).
    pub segment: u32,
    /// True if at least one side is a kept triangle (false: inside a hole or
    /// outside the domain; Triangle does not write those).
    pub bounding: bool,
}

/// A Steiner vertex created where two segments cross.
///
/// ```
/// let c = delone::tri::constrain::Crossing { vertex: 4, segments: [0, 1] };
/// assert_eq!(c.segments, [0, 1]);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Crossing {
    /// The new vertex (output id, at least the number of input points).
    pub vertex: u32,
    /// The segment being inserted and the one it crossed.
    pub segments: [u32; 2],
}

/// What the constrained triangulation did besides triangulating.
///
/// ```
/// let r = delone::tri::constrain::CdtReport::default();
/// assert!(r.crossings.is_empty());
/// ```
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct CdtReport {
    /// Steiner vertices at segment crossings.
    pub crossings: Vec<Crossing>,
    /// `(vertex, segment)`: an existing vertex lies inside a segment, which
    /// was split there; also a vertex within rounding distance of a segment
    /// crossing (usually an earlier Steiner vertex), through which the
    /// segment is routed instead of creating a second crossing next to it.
    pub vertex_splits: Vec<(u32, u32)>,
    /// `(duplicate, original)` input points that coincide (merged).
    pub duplicate_points: Vec<(u32, u32)>,
    /// Segments whose two ends coincide after merging duplicates (ignored).
    pub skipped_segments: Vec<u32>,
    /// `(duplicate, original)` segments joining the same two vertices (the
    /// duplicate is not inserted again; its subsegments carry the original's
    /// index).
    pub duplicate_segments: Vec<(u32, u32)>,
    /// Edge flips done while inserting segments and restoring Delaunay.
    pub flips: usize,
}

/// A constrained Delaunay triangulation of a [`Pslg`], carved.
///
/// ```
/// use delone::{model::pslg::Pslg, tri::constrain::*};
/// let g = Pslg::new(vec![[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]],
///                   vec![[0, 1], [1, 2], [2, 3], [3, 0], [0, 2]]);
/// let cdt = constrained_triangulation(&g, CdtOptions::default()).unwrap();
/// assert_eq!(cdt.triangles.len(), 2);
/// check_cdt(&g, &cdt).unwrap();
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Cdt {
    /// The input points followed by the Steiner points.
    pub points: Vec<[f64; 2]>,
    /// Counterclockwise triangles (output vertex ids).
    pub triangles: Vec<[u32; 3]>,
    /// `neighbors[t][i]`: the triangle across edge `i` (opposite vertex `i`),
    /// or [`NONE`].
    pub neighbors: Vec<[u32; 3]>,
    /// The region (index into `Pslg::regions`) of every triangle, or [`NONE`].
    pub regions: Vec<u32>,
    /// The regional attribute of every triangle (0 outside every region).
    pub attributes: Vec<f64>,
    /// The region's area bound of every triangle (negative: none).
    pub max_areas: Vec<f64>,
    /// The subsegments (pieces of input segments), in a deterministic order.
    pub segments: Vec<Subsegment>,
    /// For every input point: the input point whose vertex represents it
    /// (itself, or the first equal point).
    pub vertex_map: Vec<u32>,
    /// What was done.
    pub report: CdtReport,
}

/// Working state: the constrained triangle mesh ([`CMesh`], here with the
/// kernel's ghost triangles and dead slots, and with no subsegment records:
/// the label on a constrained half-edge is the index of its input segment)
/// and a triangle holding each vertex.
struct Work {
    cm: CMesh,
    /// A triangle slot holding each vertex.
    vt: Vec<u32>,
    flips: usize,
    /// The walk's pseudo-random state ([`CMesh::locate`]).
    rng: u32,
    /// Scratch of [`Work::legalize`].
    lawson: Vec<(u32, u32, u32)>,
    touched: Vec<u32>,
}

impl Work {
    /// The working mesh of the kernel's arrays (vertices, packed adjacency).
    fn new(xy: Vec<[f64; 2]>, mut tv: Vec<[u32; 3]>, mut ta: Vec<[u32; 3]>) -> Work {
        // The records are made from the back while the kernel's arrays
        // shrink (in sixteenths), then put in slot order: the two never
        // take their full size at once (peak memory).
        let step = (tv.len() / 16).max(1 << 16);
        // The labels get the kernel's capacity (untouched capacity costs no
        // resident memory; refinement grows the columns from there).
        let cap = ta.capacity();
        let mut tr = Vec::with_capacity(tv.len());
        while let (Some(v), Some(a)) = (tv.pop(), ta.pop()) {
            tr.push(Tri {
                v,
                a,
                orig: NONE,
                mark: 0,
            });
            if tv.len().is_multiple_of(step) {
                tv.shrink_to_fit();
                ta.shrink_to_fit();
            }
        }
        drop((tv, ta));
        tr.reverse();
        let mut cm = CMesh::new(xy, Vec::new());
        cm.sides = Vec::with_capacity(cap);
        cm.sides.resize(tr.len(), [NONE; 3]);
        cm.tr = tr;
        let mut w = Work {
            vt: vec![NONE; cm.xy.len()],
            cm,
            flips: 0,
            rng: 0x1234_5678,
            lawson: Vec::new(),
            touched: Vec::new(),
        };
        for t in 0..w.cm.tr.len() {
            if w.v(t)[0] != DEAD {
                w.set_vt(t);
            }
        }
        w
    }

    #[inline]
    fn p(&self, v: u32) -> &[f64; 2] {
        self.cm.p(v)
    }

    /// The vertices of triangle `t`.
    #[inline]
    fn v(&self, t: usize) -> [u32; 3] {
        self.cm.tr[t].v
    }

    /// The packed neighbour across edge `e` of `t`.
    #[inline]
    fn a(&self, t: usize, e: usize) -> u32 {
        self.cm.tr[t].a[e]
    }

    /// The input segment on edge `e` of `t`, or `NONE`.
    #[inline]
    fn con(&self, t: usize, e: usize) -> u32 {
        self.cm.sub_at(t, e)
    }

    /// The triangles around vertex `u`, each with `u`'s corner, from the
    /// one in `vt` counterclockwise (across the edge `v[k+2] -> u`).
    fn star(&self, u: u32) -> impl Iterator<Item = (usize, usize)> + '_ {
        let start = self.vt[u as usize] as usize;
        let corner = move |t: usize| self.v(t).iter().position(|&x| x == u).map(|k| (t, k));
        std::iter::successors(corner(start), move |&(t, k)| {
            let n = unpack(self.a(t, NEXT[k])).0;
            if n == start {
                None
            } else {
                corner(n)
            }
        })
        .take(self.cm.tr.len() + 1)
    }

    /// The half-edge `u -> w` as (triangle, local edge), by rotating around `u`.
    fn find_edge(&self, u: u32, w: u32) -> Option<(usize, usize)> {
        let (t, k) = self.star(u).find(|&(t, k)| self.v(t)[NEXT[k]] == w)?;
        Some((t, PREV[k]))
    }

    fn set_vt(&mut self, t: usize) {
        for &x in &self.v(t) {
            if x != INF {
                self.vt[x as usize] = t as u32;
            }
        }
    }

    /// Flips edge `i` of `t` ([`CMesh::flip`]; its quadrilateral must be
    /// strictly convex).
    fn flip(&mut self, t: usize, i: usize) {
        let (n, _) = unpack(self.a(t, i));
        self.cm.flip(t, i);
        self.set_vt(t);
        self.set_vt(n);
        self.flips += 1;
    }

    /// Lawson flips ([`CMesh::restore_delaunay`]) from the given edges
    /// (vertex pairs; those that are not edges are skipped), keeping the
    /// vertex-to-triangle map and the flip count up to date.
    fn legalize(&mut self, pairs: &mut Vec<(u32, u32)>) {
        let mut stack = std::mem::take(&mut self.lawson);
        let mut touched = std::mem::take(&mut self.touched);
        stack.clear();
        touched.clear();
        for (u, w) in pairs.drain(..) {
            if let Some((t, i)) = self.find_edge(u, w) {
                stack.push(self.cm.half(t, i));
            }
        }
        self.cm.restore_delaunay(&mut stack, &mut touched);
        self.flips += touched.len() / 2;
        for &t in &touched {
            self.set_vt(t as usize);
        }
        self.lawson = stack;
        self.touched = touched;
    }
}

/// The first event on the way from `a` to `b`.
enum Start {
    /// The edge `a - b` exists.
    Done,
    /// Vertex strictly inside the segment, adjacent to `a`.
    Vertex(u32),
    /// The segment leaves `a` through edge `i` of `t`.
    Edge(usize, usize),
}

/// Constrained Delaunay triangulation of `pslg`, carved by its holes and (if
/// not `convex_hull`) its outer segments; regional attributes by flood fill.
///
/// Duplicate points are merged (reported in `report.duplicate_points`);
/// segments whose ends coincide are skipped (reported); crossing segments are
/// split at new Steiner vertices and segments through vertices at those
/// vertices (reported).
///
/// # Errors
/// [`Error::InvalidCoordinate`] (NaN/infinite point), [`Error::InvalidSeedPoint`]
/// (NaN/infinite hole or region point), [`Error::SegmentOutOfRange`], the
/// kernel's [`Error::TooFewPoints`] / [`Error::Degenerate`] /
/// [`Error::CapacityExceeded`], and [`Error::SegmentIntersection`] when a
/// crossing cannot be resolved in floating point.
///
/// ```
/// use delone::{model::pslg::Pslg, tri::constrain::*};
/// // Two crossing diagonals of a square: one Steiner vertex in the middle.
/// let g = Pslg::new(vec![[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]],
///                   vec![[0, 2], [1, 3]]);
/// let cdt = constrained_triangulation(&g, CdtOptions { convex_hull: true }).unwrap();
/// assert_eq!(cdt.report.crossings.len(), 1);
/// assert_eq!(cdt.points[4], [1.0, 1.0]);
/// assert_eq!(cdt.triangles.len(), 4);
/// check_cdt(&g, &cdt).unwrap();
/// ```
pub fn constrained_triangulation(pslg: &Pslg, options: CdtOptions) -> Result<Cdt, Error> {
    constrain(pslg, options).map(Constrained::into_cdt)
}

/// A carved constrained Delaunay triangulation as the constrained mesh that
/// refinement continues on: the records compacted in place (output vertex
/// ids, triangle `t`'s `orig` is `t`, `NONE` across the boundary, the label
/// of a half-edge on a subsegment is `LABEL | k` for `cdt.segments[k]`; no
/// coordinates: they are `cdt.points`), and every other column of the
/// [`Cdt`] (`triangles` and `neighbors` are left empty: they are a view of
/// the records, [`Constrained::into_cdt`]).
pub(super) struct Constrained {
    pub(super) cm: CMesh,
    pub(super) cdt: Cdt,
}

impl Constrained {
    /// The [`Cdt`] view of the mesh (a copy of the other columns).
    pub(super) fn to_cdt(&self) -> Cdt {
        Constrained {
            cm: CMesh::new(Vec::new(), self.cm.tr.clone()),
            cdt: self.cdt.clone(),
        }
        .into_cdt()
    }

    /// The [`Cdt`]: the triangles and neighbours of the records (the
    /// triangles reuse the side table's storage).
    pub(super) fn into_cdt(self) -> Cdt {
        let Constrained { cm, mut cdt } = self;
        let mut triangles = cm.sides;
        triangles.clear();
        triangles.extend(cm.tr.iter().map(|r| r.v));
        cdt.neighbors = cm
            .tr
            .iter()
            .map(|r| {
                r.a.map(|x| if x == NONE { NONE } else { unpack(x).0 as u32 })
            })
            .collect();
        cdt.triangles = triangles;
        cdt
    }
}

/// [`constrained_triangulation`] as the mesh refinement continues on.
pub(super) fn constrain(pslg: &Pslg, options: CdtOptions) -> Result<Constrained, Error> {
    pslg.check_values()?;
    let n = pslg.points.len();
    let (xy, scale, ids, vmap, tv, ta) = Delaunay2::from_points(&pslg.points)?.into_raw();
    let mut w = Work::new(xy, tv, ta);
    // Internal vertex -> output id (its input point's representative), and
    // input index -> internal vertex.
    let out: Vec<u32> = ids[..n].iter().map(|&i| vmap[i as usize]).collect();
    drop(ids);
    let mut ext2int = vec![NONE; n];
    for x in 0..n {
        if w.vt[x] != NONE {
            ext2int[out[x] as usize] = x as u32;
        }
    }
    let mut report = CdtReport::default();
    for (i, &r) in vmap.iter().enumerate() {
        if r as usize != i {
            report.duplicate_points.push((i as u32, r));
        }
    }
    let out_id = |x: u32| -> u32 {
        if (x as usize) < n {
            out[x as usize]
        } else {
            x
        }
    };
    let mut pending: Vec<(u32, u32, u32)> = Vec::new();
    let mut crossed: VecDeque<(u32, u32)> = VecDeque::new();
    let mut newe: Vec<(u32, u32)> = Vec::new();
    let budget = 64usize
        .saturating_mul(pslg.segments.len())
        .saturating_mul(pslg.segments.len().max(16))
        .saturating_add(1 << 20);
    let mut steps = 0usize;
    // Labels beyond the first of edges shared by several segments.
    let mut multi: HashMap<(u32, u32), Vec<u32>> = HashMap::new();
    // Internal end vertices of every segment (for exact crossing lines).
    let seg_ends: Vec<(u32, u32)> = pslg
        .segments
        .iter()
        .map(|seg| {
            (
                ext2int[vmap[seg[0] as usize] as usize],
                ext2int[vmap[seg[1] as usize] as usize],
            )
        })
        .collect();
    drop(ext2int);
    let first = first_segments(&seg_ends, w.cm.xy.len());
    for (s, &(a, b)) in seg_ends.iter().enumerate() {
        if a == b {
            report.skipped_segments.push(s as u32);
            continue;
        }
        let orig = first[s];
        if orig != s as u32 {
            report.duplicate_segments.push((s as u32, orig));
        }
    }
    let unresolved = |s: u32, o: u32| Error::SegmentIntersection {
        segment: s as usize,
        other: o as usize,
    };
    // Segments in input order; the pieces a segment is split into are
    // pushed on `pending` and inserted before the next segment.
    let mut next_seg = 0usize;
    while let Some((a, b, s)) = pending.pop().or_else(|| {
        while next_seg < seg_ends.len() {
            let s = next_seg;
            next_seg += 1;
            let (a, b) = seg_ends[s];
            if a != b && first[s] == s as u32 {
                return Some((a, b, s as u32));
            }
        }
        None
    }) {
        steps += 1;
        if steps > budget {
            return Err(unresolved(s, s));
        }
        if steps % 4096 == 1 {
            // Input segments taken so far (pieces of split segments do not count).
            let total = seg_ends.len() as u64;
            crate::progress::report(
                "inserting segments",
                next_seg as u64,
                Some(total),
                "segments",
            );
            if crate::progress::stop_requested() {
                return Err(Error::Interrupted);
            }
        }
        if a == b {
            continue;
        }
        // Already an edge (the common case): label it, no predicate needed.
        if let Some((t, i)) = w.find_edge(a, b) {
            label_half_edge(&mut w, &mut multi, t, i, a, b, s);
            continue;
        }
        let (pa, pb) = (*w.p(a), *w.p(b));
        // The wedge at `a` that the segment leaves through.
        let on_ray = |x: u32| {
            x != INF && orient2d(&pa, &pb, w.p(x)) == 0.0 && {
                let px = w.p(x);
                (px[0] - pa[0]) * (pb[0] - pa[0]) + (px[1] - pa[1]) * (pb[1] - pa[1]) > 0.0
            }
        };
        let start = w.star(a).find_map(|(t, k)| {
            let v = w.v(t);
            let (p, q) = (v[NEXT[k]], v[PREV[k]]);
            if p == b || q == b {
                Some(Start::Done)
            } else if on_ray(p) {
                Some(Start::Vertex(p))
            } else if on_ray(q) {
                Some(Start::Vertex(q))
            } else if p != INF
                && q != INF
                && orient2d(&pa, &pb, w.p(p)) < 0.0
                && orient2d(&pa, &pb, w.p(q)) > 0.0
            {
                Some(Start::Edge(t, k))
            } else {
                None
            }
        });
        let Some(start) = start else {
            return Err(unresolved(s, s));
        };
        let (mut t, mut i) = match start {
            Start::Done => {
                constrain_label(&mut w, &mut multi, a, b, s);
                continue;
            }
            Start::Vertex(p) => {
                report.vertex_splits.push((out_id(p), s));
                constrain_label(&mut w, &mut multi, a, p, s);
                pending.push((p, b, s));
                continue;
            }
            Start::Edge(t, i) => (t, i),
        };
        // Walk to `b`, collecting the crossed edges, up to the first event.
        crossed.clear();
        let mut end = b;
        let mut steiner = false;
        loop {
            let (p, q) = edge(&w.v(t), i);
            let other = w.con(t, i);
            if other != NONE {
                // A constrained edge crosses the segment: a vertex at the
                // crossing splits both (see `resolve_crossing`).
                let mut cx = Crossings {
                    multi: &mut multi,
                    report: &mut report,
                    pending: &mut pending,
                    seg_ends: &seg_ends,
                    out_id: &out_id,
                };
                if !cx.resolve(&mut w, s, a, b, t, i) {
                    return Err(unresolved(s, other));
                }
                steiner = true;
                break;
            }
            crossed.push_back((p, q));
            let (nn, j) = unpack(w.a(t, i));
            let r = w.v(nn)[j];
            if r == b {
                break;
            }
            if r == INF {
                return Err(unresolved(s, s));
            }
            let sr = orient2d(&pa, &pb, w.p(r));
            if sr == 0.0 {
                report.vertex_splits.push((out_id(r), s));
                pending.push((r, b, s));
                end = r;
                break;
            }
            t = nn;
            i = if sr < 0.0 { PREV[j] } else { NEXT[j] };
        }
        if steiner {
            continue;
        }
        // Flip the crossed edges away (Sloan).
        let pe = *w.p(end);
        let crosses = |w: &Work, x: u32, y: u32| -> bool {
            if x == a || x == end || y == a || y == end {
                return false;
            }
            let (px, py) = (w.p(x), w.p(y));
            let s1 = orient2d(&pa, &pe, px);
            let s2 = orient2d(&pa, &pe, py);
            let s3 = orient2d(px, py, &pa);
            let s4 = orient2d(px, py, &pe);
            s1 * s2 < 0.0 && s3 * s4 < 0.0
        };
        newe.clear();
        let mut idle = 0usize;
        while let Some((u, v)) = crossed.pop_front() {
            steps += 1;
            if steps > budget || idle > 2 * crossed.len() + 8 {
                return Err(unresolved(s, s));
            }
            let Some((t, i)) = w.find_edge(u, v) else {
                return Err(unresolved(s, s));
            };
            let (nn, j) = unpack(w.a(t, i));
            let x = w.v(t)[i];
            let d = w.v(nn)[j];
            if x == INF || d == INF {
                return Err(unresolved(s, s));
            }
            let convex =
                orient2d(w.p(x), w.p(u), w.p(d)) > 0.0 && orient2d(w.p(d), w.p(v), w.p(x)) > 0.0;
            if !convex {
                crossed.push_back((u, v));
                idle += 1;
                continue;
            }
            idle = 0;
            w.flip(t, i);
            if crosses(&w, x, d) {
                crossed.push_back((x, d));
            } else {
                newe.push((x, d));
            }
        }
        if !constrain_label(&mut w, &mut multi, a, end, s) {
            return Err(unresolved(s, s));
        }
        // The new edges (but the segment) seed the Lawson flips; the
        // buffer is reused from segment to segment.
        newe.retain(|&(x, y)| !((x == a && y == end) || (x == end && y == a)));
        w.legalize(&mut newe);
    }
    report.flips = w.flips;

    // Carving.
    let nt = w.cm.tr.len();
    let mut alive: Vec<bool> =
        w.cm.tr
            .iter()
            .map(|r| r.v[0] != DEAD && !is_ghost(&r.v))
            .collect();
    let mut stack: Vec<usize> = Vec::new();
    // Flood fill across unconstrained edges from the triangles on `stack`
    // into every neighbour that `enter` takes.
    let flood = |w: &Work, stack: &mut Vec<usize>, enter: &mut dyn FnMut(usize) -> bool| {
        while let Some(t) = stack.pop() {
            for e in 0..3 {
                if w.con(t, e) == NONE && enter(unpack(w.a(t, e)).0) {
                    stack.push(unpack(w.a(t, e)).0);
                }
            }
        }
    };
    let carve = |alive: &mut Vec<bool>, t: usize| std::mem::replace(&mut alive[t], false);
    if !options.convex_hull {
        for t in 0..nt {
            let v = w.v(t);
            // Ghost edge 2 is the hull edge.
            if v[0] != DEAD && is_ghost(&v) && w.con(t, 2) == NONE {
                let (f, _) = unpack(w.a(t, 2));
                if carve(&mut alive, f) {
                    stack.push(f);
                }
            }
        }
        flood(&w, &mut stack, &mut |n| carve(&mut alive, n));
    }
    let sc = |p: [f64; 2]| [p[0] * scale.0 * scale.1, p[1] * scale.0 * scale.1];
    // Each seed's walk starts where the previous one ended (seeds listed
    // in a spatially coherent order cost O(1) walks each).
    let mut last = 0usize;
    for h in &pslg.holes {
        let found = w.cm.locate(last, &sc(*h), &mut w.rng);
        if let Some(t) = found {
            last = t;
            if carve(&mut alive, t) {
                stack.push(t);
                flood(&w, &mut stack, &mut |n| carve(&mut alive, n));
            }
        }
    }
    let mut region = vec![NONE; nt];
    for (ri, r) in pslg.regions.iter().enumerate() {
        let Some(t0) = w.cm.locate(last, &sc(r.point), &mut w.rng) else {
            continue;
        };
        if !alive[t0] {
            continue;
        }
        let mut seen = HashSet::from([t0]);
        region[t0] = ri as u32;
        stack.push(t0);
        flood(&w, &mut stack, &mut |n| {
            let new = alive[n] && seen.insert(n);
            if new {
                region[n] = ri as u32;
            }
            new
        });
    }

    // Output. The subsegments first (the index of a bounding one becomes
    // the label of its edge), then the records are compacted in place:
    // carved, ghost and dead slots dropped, output vertex ids, `NONE`
    // across the boundary.
    drop(pending);
    drop(first);
    drop(seg_ends);
    drop(multi);
    w.vt = Vec::new();
    let ghost: Vec<bool> =
        w.cm.tr
            .iter()
            .map(|r| r.v[0] != DEAD && is_ghost(&r.v))
            .collect();
    let mut segments = Vec::new();
    for t in 0..nt {
        let v = w.v(t);
        if v[0] == DEAD || is_ghost(&v) {
            continue;
        }
        for e in 0..3 {
            let c = w.con(t, e);
            if c == NONE {
                continue;
            }
            let (nn, j) = unpack(w.a(t, e));
            if nn < t && !ghost[nn] {
                continue;
            }
            let bounding = alive[t] || alive[nn];
            if bounding {
                let k = LABEL | segments.len() as u32;
                w.cm.set_sub(t, e, k);
                w.cm.set_sub(nn, j, k);
            }
            let (x, y) = edge(&v, e);
            segments.push(Subsegment {
                v: [out_id(x), out_id(y)],
                marker: pslg.segment_marker(c as usize),
                segment: c,
                bounding,
            });
        }
    }
    drop(ghost);
    // Old slot -> output triangle.
    let mut map = vec![NONE; nt];
    let mut k = 0u32;
    for t in 0..nt {
        if alive[t] {
            map[t] = k;
            k += 1;
        }
    }
    let mut points = pslg.points.clone();
    points.extend(
        w.cm.xy[n..]
            .iter()
            .map(|p| [p[0] / scale.1 / scale.0, p[1] / scale.1 / scale.0]),
    );
    w.cm.xy = Vec::new();
    let k = k as usize;
    let mut regions = Vec::with_capacity(k);
    let mut attributes = Vec::with_capacity(k);
    let mut max_areas = Vec::with_capacity(k);
    let mut cm = w.cm;
    for t in 0..nt {
        if !alive[t] {
            continue;
        }
        let kk = regions.len();
        let r = cm.tr[t];
        cm.tr[kk] = Tri {
            v: r.v.map(out_id),
            a: r.a.map(|x| {
                let (o, j) = unpack(x);
                if map[o] == NONE {
                    NONE
                } else {
                    pack(map[o] as usize, j)
                }
            }),
            orig: kk as u32,
            mark: r.mark & FLAGS,
        };
        cm.sides[kk] = cm.sides[t];
        let r = region[t];
        regions.push(r);
        let reg = pslg.regions.get(r as usize);
        attributes.push(reg.map_or(0.0, |g| g.attribute));
        max_areas.push(reg.map_or(-1.0, |g| g.max_area));
    }
    cm.tr.truncate(k);
    cm.sides.truncate(k);
    Ok(Constrained {
        cm,
        cdt: Cdt {
            points,
            triangles: Vec::new(),
            neighbors: Vec::new(),
            regions,
            attributes,
            max_areas,
            segments,
            vertex_map: vmap,
            report,
        },
    })
}

/// For every query point, the lowest-numbered triangle that contains it
/// strictly (the triangles in order, each testing the points in the cells
/// of a [`Grid`] over the query points that its bounding box meets).
fn first_containing(pts: &[[f64; 2]], tris: &[[u32; 3]], q: &[[f64; 2]]) -> Vec<Option<usize>> {
    let grid = Grid::new(q, &(0..q.len() as u32).collect::<Vec<_>>());
    let mut found = vec![None; q.len()];
    for (t, v) in tris.iter().enumerate() {
        let [lo, hi] = crate::geom::bbox(v.iter().map(|&x| &pts[x as usize]));
        grid.any_in(lo, hi, |k| {
            let k = k as usize;
            if found[k].is_none() && strictly_inside(pts, v, &q[k]) {
                found[k] = Some(t);
            }
            false
        });
    }
    found
}

/// Strictly inside triangle `v`?
fn strictly_inside(pts: &[[f64; 2]], v: &[u32; 3], p: &[f64; 2]) -> bool {
    (0..3).all(|e| {
        let (a, b) = edge(v, e);
        orient2d(&pts[a as usize], &pts[b as usize], p) > 0.0
    })
}

/// Independent checker of a [`Cdt`] against its input, with exact
/// predicates: counterclockwise triangles, symmetric adjacency across
/// matching edges, every bounding subsegment an edge of the mesh, every input
/// segment a chain of subsegments from one end to the other through vertices
/// recorded as splitting it (`report.crossings` and `report.vertex_splits`,
/// or subsegments labelled with it, which is how refinement splits), every
/// recorded vertex strictly between the ends of its segment and within
/// [`STEINER_ULPS`] ulps (of the largest coordinate involved) of its line —
/// a crossing is the exact intersection of the two input lines rounded to
/// the nearest doubles (half an ulp per coordinate), so no tolerance relative
/// to the input's extent is needed — , the constrained
/// Delaunay property (the apex across an edge that is not a subsegment is
/// never strictly inside the circumcircle), hole points not strictly inside
/// any triangle, and regions constant across unconstrained edges, each region
/// point's triangle carrying that region or a later one.
///
/// # Errors
/// The first [`Violation`] found.
///
/// ```
/// use delone::{model::pslg::Pslg, tri::constrain::*};
/// let g = Pslg::new(vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]], vec![[0, 3]]);
/// let mut cdt = constrained_triangulation(&g, CdtOptions { convex_hull: true }).unwrap();
/// check_cdt(&g, &cdt).unwrap();
/// cdt.triangles[0].swap(0, 1);
/// assert!(check_cdt(&g, &cdt).is_err());
/// ```
pub fn check_cdt(pslg: &Pslg, cdt: &Cdt) -> Result<(), Violation> {
    // Exact power-of-two scaling keeps the predicates exact at any scale.
    // Only the mesh's points take part in the predicates: a hole or region
    // point far away (of another magnitude) must not set the scale, or the
    // products of the mesh's coordinates could underflow.
    let max_abs = crate::geom::max_abs(&cdt.points);
    let scale = pow2_scale(max_abs);
    let pts: &Vec<[f64; 2]> = &cdt.points.iter().map(|&p| scaled(p, scale)).collect();
    let nt = cdt.triangles.len();
    if cdt.neighbors.len() != nt || cdt.regions.len() != nt {
        return Err(Violation::new("storage", "column lengths differ"));
    }
    let segset: HashSet<(u32, u32)> = cdt.segments.iter().map(|s| ukey(s.v[0], s.v[1])).collect();
    // Counterclockwise triangles with symmetric adjacency; across each
    // unconstrained edge, the constrained Delaunay property and one region.
    let edges = check_edges(pts, &cdt.triangles, &cdt.neighbors, |t, i, n, j| {
        let v = cdt.triangles[t as usize];
        let (a, b) = edge(&v, i as usize);
        if n < t || segset.contains(&ukey(a, b)) {
            return Ok(());
        }
        let d = cdt.triangles[n as usize][j as usize];
        let [pa, pb, pc] = v.map(|x| &pts[x as usize]);
        if incircle(pa, pb, pc, &pts[d as usize]) > 0.0 {
            return Err(Violation::new(
                "delaunay",
                format!("vertex {d} is inside the circumcircle of triangle {t} {v:?} across unconstrained edge ({a},{b})"),
            ));
        }
        if cdt.regions[t as usize] != cdt.regions[n as usize] {
            return Err(Violation::new(
                "region",
                format!(
                    "triangles {t} and {n} differ in region across unconstrained edge ({a},{b})"
                ),
            ));
        }
        Ok(())
    })?;
    // Subsegments: bounding ones are mesh edges.
    let mut adj: HashMap<u32, Vec<(u32, u32)>> = HashMap::new();
    for (k, s) in cdt.segments.iter().enumerate() {
        let [a, b] = s.v;
        if s.bounding
            && find_edge(&edges, a, b)
                .or(find_edge(&edges, b, a))
                .is_none()
        {
            return Err(Violation::new(
                "conformity",
                format!("subsegment {k} ({a},{b}) is not a mesh edge"),
            ));
        }
        adj.entry(a).or_default().push((b, s.segment));
        adj.entry(b).or_default().push((a, s.segment));
    }
    // Every vertex recorded as splitting a segment (crossings and vertex
    // splits) lies within `STEINER_ULPS` ulps of that segment's line and
    // strictly between its ends.
    let recorded: HashSet<(u32, u32)> = cdt
        .report
        .crossings
        .iter()
        .flat_map(|c| [(c.vertex, c.segments[0]), (c.vertex, c.segments[1])])
        .chain(cdt.report.vertex_splits.iter().copied())
        .collect();
    let vm = |i: u32| cdt.vertex_map.get(i as usize).copied().unwrap_or(i);
    let mut rec_sorted: Vec<(u32, u32)> = recorded.iter().copied().collect();
    rec_sorted.sort_unstable();
    for &(x, g) in &rec_sorted {
        let Some(seg) = pslg.segments.get(g as usize) else {
            return Err(Violation::new(
                "conformity",
                format!("vertex {x} is recorded for segment {g}, which does not exist"),
            ));
        };
        let (a, b) = (vm(seg[0]) as usize, vm(seg[1]) as usize);
        if x as usize >= pts.len() || a >= pts.len() || b >= pts.len() {
            return Err(Violation::new(
                "vertex",
                format!("vertex {x} recorded for segment {g} out of range"),
            ));
        }
        if !near_segment(&pts[a], &pts[b], &pts[x as usize]) {
            return Err(Violation::new(
                "conformity",
                format!(
                    "vertex {x} recorded as splitting segment {g} ({a},{b}) is not within {STEINER_ULPS} ulps of it"
                ),
            ));
        }
    }
    // Segments with the same two ends (after merging duplicate points) share
    // their subsegments and crossings.
    let key = |seg: &[u32; 2]| {
        let (a, b) = (vm(seg[0]), vm(seg[1]));
        (a.min(b), a.max(b))
    };
    let mut group: HashMap<(u32, u32), Vec<u32>> = HashMap::new();
    for (s, seg) in pslg.segments.iter().enumerate() {
        group.entry(key(seg)).or_default().push(s as u32);
    }
    for (s, seg) in pslg.segments.iter().enumerate() {
        let (a, b) = (vm(seg[0]), vm(seg[1]));
        if a == b {
            continue;
        }
        // A chain of subsegments from `a` to `b` through vertices recorded
        // as splitting this segment (or a duplicate of it).
        let same = &group[&key(seg)];
        let mut seen = HashSet::new();
        let mut st = vec![a];
        seen.insert(a);
        let mut ok = false;
        while let Some(c) = st.pop() {
            if c == b {
                ok = true;
                break;
            }
            for &(x, lab) in adj.get(&c).map(|v| v.as_slice()).unwrap_or(&[]) {
                // Refinement splits subsegments without recording the new
                // vertices: a subsegment labelled with the segment counts.
                let good = x == b || same.iter().any(|&g| lab == g || recorded.contains(&(x, g)));
                if good && seen.insert(x) {
                    st.push(x);
                }
            }
        }
        if !ok {
            return Err(Violation::new(
                "conformity",
                format!("input segment {s} ({a},{b}) is not a chain of subsegments"),
            ));
        }
    }
    let seeds: Vec<[f64; 2]> = pslg
        .holes
        .iter()
        .chain(pslg.regions.iter().map(|r| &r.point))
        .map(|p| scaled(*p, scale))
        .collect();
    let found = first_containing(pts, &cdt.triangles, &seeds);
    for (h, _) in pslg.holes.iter().enumerate() {
        if let Some(t) = found[h] {
            return Err(Violation::new(
                "hole",
                format!("hole {h} lies inside kept triangle {t}"),
            ));
        }
    }
    for (r, _) in pslg.regions.iter().enumerate() {
        if let Some(t) = found[pslg.holes.len() + r] {
            let got = cdt.regions[t];
            if got == NONE || (got as usize) < r {
                return Err(Violation::new(
                    "region",
                    format!("region {r}'s point lies in triangle {t}, which has region {got}"),
                ));
            }
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------
// Double-double arithmetic for segment crossings.
//
// The crossing of the lines `A + t (B - A)` and `C + u (D - C)` is computed
// with ~104-bit intermediate precision: the differences are exact (TwoDiff),
// the cross products are accumulated from exact TwoProducts, and the point is
// formed on the line A-B. The relative error of the result before the final
// rounding is below 2^-100 of the magnitude of the terms, so the double that
// comes out is within half an ulp (per coordinate) of the exact crossing plus
// a negligible amount: its distance from either line is at most
// `ulp(M) / sqrt(2) + O(2^-100 M)`, where `M` is the largest coordinate
// magnitude involved. `check_cdt` accepts Steiner vertices within
// `STEINER_ULPS` ulps of each of their lines.

/// Double-double sum.
#[inline]
fn dd_add(a: (f64, f64), b: (f64, f64)) -> (f64, f64) {
    let (s, e) = two_sum(a.0, b.0);
    let e = e + a.1 + b.1;
    two_sum(s, e)
}

/// Double-double product.
#[inline]
fn dd_mul(a: (f64, f64), b: (f64, f64)) -> (f64, f64) {
    let (p, e) = two_product(a.0, b.0);
    let e = e + (a.0 * b.1 + a.1 * b.0);
    two_sum(p, e)
}

/// Double-double cross product `u x v` of double-double vectors.
#[inline]
fn dd_cross(u: [(f64, f64); 2], v: [(f64, f64); 2]) -> (f64, f64) {
    let l = dd_mul(u[0], v[1]);
    let r = dd_mul(u[1], v[0]);
    dd_add(l, (-r.0, -r.1))
}

/// Exact difference `b - a` as a double-double vector.
#[inline]
fn dd_diff(a: &[f64; 2], b: &[f64; 2]) -> [(f64, f64); 2] {
    let x = two_sum(b[0], -a[0]);
    let y = two_sum(b[1], -a[1]);
    [x, y]
}

/// The crossing of the lines `a-b` and `c-d`, rounded to doubles, or `None`
/// when they are parallel (or the result is not finite). The point is
/// measured along the segment of the smaller coordinates, so its error is
/// relative to that segment's magnitude (a segment reaching 1e23 crossing
/// one near 1 would otherwise leave the point many ulps off the short one).
fn line_crossing(a: &[f64; 2], b: &[f64; 2], c: &[f64; 2], d: &[f64; 2]) -> Option<[f64; 2]> {
    let mag =
        |p: &[f64; 2], q: &[f64; 2]| p[0].abs().max(p[1].abs()).max(q[0].abs()).max(q[1].abs());
    let (a, b, c, d) = if mag(c, d) < mag(a, b) {
        (c, d, a, b)
    } else {
        (a, b, c, d)
    };
    let u = dd_diff(a, b);
    let v = dd_diff(c, d);
    let w = dd_diff(a, c);
    let den = dd_cross(u, v);
    if den.0 == 0.0 {
        return None;
    }
    let num = dd_cross(w, v);
    // t = num / den in double-double (one Newton correction).
    let th = num.0 / den.0;
    let r = dd_add(num, {
        let p = dd_mul((th, 0.0), den);
        (-p.0, -p.1)
    });
    let t = two_sum(th, r.0 / den.0);
    let x = dd_add((a[0], 0.0), dd_mul(t, u[0]));
    let y = dd_add((a[1], 0.0), dd_mul(t, u[1]));
    let p = [x.0 + x.1, y.0 + y.1];
    (p[0].is_finite() && p[1].is_finite()).then_some(p)
}

/// Unit in the last place of the largest magnitude `m` (for `m > 0`).
fn ulp_of(m: f64) -> f64 {
    if m == 0.0 || !m.is_finite() {
        return f64::MIN_POSITIVE;
    }
    let e = ((m.abs().to_bits() >> 52) & 0x7ff) as i32 - 1023;
    (2.0f64).powi(e - 52).max(f64::MIN_POSITIVE)
}

/// Distance bound (in ulps of the largest coordinate magnitude involved)
/// within which a Steiner vertex must lie of every segment it splits.
pub const STEINER_ULPS: f64 = 4.0;

/// True if `x` is within [`STEINER_ULPS`] ulps of the line `a-b` and
/// projects strictly inside the segment (double-double evaluation; the
/// evaluation error is below 2^-100 of the terms).
fn near_segment(a: &[f64; 2], b: &[f64; 2], x: &[f64; 2]) -> bool {
    let m = [a, b, x]
        .iter()
        .fold(0.0f64, |m, p| m.max(p[0].abs()).max(p[1].abs()));
    let u = dd_diff(a, b);
    let v = dd_diff(a, x);
    let cr = dd_cross(u, v);
    let len = (b[0] - a[0]).hypot(b[1] - a[1]);
    let tol = STEINER_ULPS * ulp_of(m) * len * (1.0 + 1e-12);
    (cr.0 + cr.1).abs() <= tol && strictly_between(a, b, x)
}

/// For a point `x` on (or within ulps of) the line `a-b`: whether it lies
/// strictly between the ends along the segment's dominant axis. Only
/// comparisons, so exact at any coordinate spread (a dot product against a
/// segment 1e43 long cannot tell a point near one end from the end).
fn strictly_between(a: &[f64; 2], b: &[f64; 2], x: &[f64; 2]) -> bool {
    let k = usize::from((b[1] - a[1]).abs() > (b[0] - a[0]).abs());
    (a[k] < x[k] && x[k] < b[k]) || (b[k] < x[k] && x[k] < a[k])
}

/// Result of inserting a crossing point.
enum Placed {
    /// The point equals this existing vertex.
    Existing(u32),
    /// A new vertex; if it fell exactly on a constrained edge, that edge's
    /// two ends (the edge was split, both halves keep its labels).
    New(u32, Option<(u32, u32)>),
}

/// Segment crossings and the vertex insertion they need.
impl Work {
    /// Inserts the point `x` into the constrained triangulation (near
    /// triangle `hint`) by constrained Bowyer–Watson ([`CMesh::insert`]).
    /// `None` if `x` is outside the hull or on a hull edge, or if the
    /// rounded point would make a triangle that is not counterclockwise.
    fn insert_point(&mut self, hint: usize, x: [f64; 2]) -> Option<Placed> {
        let t = self.cm.locate(hint, &x, &mut self.rng)?;
        let v = self.v(t);
        for &u in &v {
            if *self.p(u) == x {
                return Some(Placed::Existing(u));
            }
        }
        if !(x[0].is_finite() && x[1].is_finite()) {
            return None;
        }
        // On an edge: its two halves keep its label.
        let on = (0..3).find(|&e| {
            let (a, b) = edge(&v, e);
            orient2d(self.p(a), self.p(b), &x) == 0.0
        });
        let (c, ends) = match on {
            Some(e) if is_ghost(&self.v(unpack(self.a(t, e)).0)) => return None,
            Some(e) if self.con(t, e) != NONE => (self.con(t, e), Some(edge(&v, e))),
            _ => (NONE, None),
        };
        let (p, q) = ends.unwrap_or((NONE, NONE));
        let Ins::Done(s) = self.cm.insert(t, x, c, [p, c, q, c], false) else {
            return None;
        };
        self.vt.push(t as u32);
        for k in 0..self.cm.fan.len() {
            self.set_vt(self.cm.fan[k] as usize);
        }
        Some(Placed::New(s, ends))
    }

    /// Removes the constraint label of edge `u - w` (if it is an edge) and
    /// restores the Delaunay property around it.
    fn unconstrain(&mut self, u: u32, w: u32) {
        if let Some((t, i)) = self.find_edge(u, w) {
            let (n, j) = unpack(self.a(t, i));
            self.cm.set_sub(t, i, NONE);
            self.cm.set_sub(n, j, NONE);
            self.legalize(&mut vec![(u, w)]);
        }
    }
}

/// Key of the undirected edge `u - w`.
#[inline]
fn ukey(u: u32, w: u32) -> (u32, u32) {
    (u.min(w), u.max(w))
}

/// Marks the edge `u - v` as part of segment `s`: the first label goes in
/// the half-edges, further ones in `multi`. False if `u - v` is not an edge.
fn constrain_label(
    w: &mut Work,
    multi: &mut HashMap<(u32, u32), Vec<u32>>,
    u: u32,
    v: u32,
    s: u32,
) -> bool {
    let Some((t, i)) = w.find_edge(u, v) else {
        return false;
    };
    label_half_edge(w, multi, t, i, u, v, s);
    true
}

/// Marks edge `i` of `t` (the edge `u - v`) as part of segment `s`.
#[inline]
fn label_half_edge(
    w: &mut Work,
    multi: &mut HashMap<(u32, u32), Vec<u32>>,
    t: usize,
    i: usize,
    u: u32,
    v: u32,
    s: u32,
) {
    let (n, j) = unpack(w.a(t, i));
    let c = w.con(t, i);
    if c == NONE {
        w.cm.set_sub(t, i, s);
        w.cm.set_sub(n, j, s);
    } else if c != s {
        let e = multi.entry(ukey(u, v)).or_default();
        if !e.contains(&s) {
            e.push(s);
        }
    }
}

/// For every segment `(a, b)` (internal vertex ids below `nv`), the first
/// segment with the same two ends (itself if none earlier). Linear time:
/// segments are bucketed by their lower end (counting sort), each bucket
/// sorted by (upper end, index).
fn first_segments(ends: &[(u32, u32)], nv: usize) -> Vec<u32> {
    let mut head = vec![0u32; nv + 1];
    for &(a, b) in ends {
        head[a.min(b) as usize + 1] += 1;
    }
    for k in 0..nv {
        head[k + 1] += head[k];
    }
    let mut fill = head.clone();
    let mut ord = vec![0u64; ends.len()];
    for (s, &(a, b)) in ends.iter().enumerate() {
        let lo = a.min(b) as usize;
        ord[fill[lo] as usize] = (u64::from(a.max(b)) << 32) | s as u64;
        fill[lo] += 1;
    }
    drop(fill);
    let mut first: Vec<u32> = (0..ends.len() as u32).collect();
    for k in 0..nv {
        let bucket = &mut ord[head[k] as usize..head[k + 1] as usize];
        if bucket.len() < 2 {
            continue;
        }
        bucket.sort_unstable();
        let mut run = bucket[0];
        for &x in &bucket[1..] {
            if x >> 32 == run >> 32 {
                first[(x & 0xffff_ffff) as usize] = (run & 0xffff_ffff) as u32;
            } else {
                run = x;
            }
        }
    }
    first
}

/// The bookkeeping a crossing touches.
struct Crossings<'a, F: Fn(u32) -> u32> {
    multi: &'a mut HashMap<(u32, u32), Vec<u32>>,
    report: &'a mut CdtReport,
    pending: &'a mut Vec<(u32, u32, u32)>,
    seg_ends: &'a [(u32, u32)],
    out_id: &'a F,
}

impl<F: Fn(u32) -> u32> Crossings<'_, F> {
    /// All labels of the constrained edge `u - v` (first the one in the
    /// half-edges), removing the extra ones from `multi`.
    fn take_labels(&mut self, u: u32, v: u32, first: u32) -> Vec<u32> {
        let mut l = vec![first];
        if let Some(more) = self.multi.remove(&ukey(u, v)) {
            l.extend(more.into_iter().filter(|&x| x != first));
        }
        l
    }

    /// The piece `a - b` of segment `s` crosses the constrained edge `i` of
    /// triangle `t` (`p - q`). Puts a vertex `v` at the crossing (computed
    /// from the input lines of the two segments in double-double precision,
    /// inserted as a vertex of the constrained triangulation; an existing
    /// vertex if the rounded point coincides with one, or the nearest end
    /// when the rounded point does not fall strictly inside both pieces),
    /// takes the constraint off `p - q` and queues `a - v`, `v - b` for `s`
    /// and `p - v`, `v - q` for every segment `p - q` belonged to. The new
    /// pieces are inserted like any segment, so a piece that the rounding
    /// made cross another constraint is split again: the process only ever
    /// adds vertices, and the caller's step budget bounds it.
    fn resolve(&mut self, w: &mut Work, s: u32, a: u32, b: u32, t: usize, i: usize) -> bool {
        let (p, q) = edge(&w.v(t), i);
        let other = w.con(t, i);
        let (pa, pb, pp, pq) = (*w.p(a), *w.p(b), *w.p(p), *w.p(q));
        // Strictly inside both pieces, by exact comparisons (a dot product
        // against a piece 1e23 long rounds the point onto its end).
        let inside = |x: &[f64; 2]| strictly_between(&pa, &pb, x) && strictly_between(&pp, &pq, x);
        let (sa, sb) = self.seg_ends[s as usize];
        let (oa, ob) = self.seg_ends[other as usize];
        let from_input = line_crossing(w.p(sa), w.p(sb), w.p(oa), w.p(ob));
        let from_pieces = line_crossing(&pa, &pb, &pp, &pq);
        let cand = [from_input, from_pieces]
            .into_iter()
            .flatten()
            .find(|x| inside(x));
        let mut created = None;
        let mut split_other = None;
        let mut fallback = false;
        // An existing vertex close to the crossing that is within the
        // Steiner bound of both input segments (typically the crossing of
        // a collinear overlapping segment, a few ulps away) is reused:
        // without this, nearly coincident crossings creep along the line.
        let (n, j) = unpack(w.a(t, i));
        let near_both = |w: &Work, v: u32| {
            v != INF
                && (v == a || v == b || near_segment(w.p(sa), w.p(sb), w.p(v)))
                && (v == p || v == q || near_segment(w.p(oa), w.p(ob), w.p(v)))
        };
        let snap = cand.and_then(|x| {
            let d2 = |u: &[f64; 2]| (u[0] - x[0]).powi(2) + (u[1] - x[1]).powi(2);
            [a, b, p, q, w.v(t)[i], w.v(n)[j]]
                .into_iter()
                .filter(|&v| near_both(w, v))
                .min_by(|&u, &v| d2(w.p(u)).total_cmp(&d2(w.p(v))))
        });
        let placed = match snap {
            Some(v) => Some(Placed::Existing(v)),
            None => cand.and_then(|x| w.insert_point(t, x)),
        };
        let v = match placed {
            Some(Placed::Existing(v)) => v,
            Some(Placed::New(v, split)) => {
                created = Some(v);
                split_other = split;
                v
            }
            None => {
                fallback = true;
                // Nearest end of the two pieces to the crossing.
                let Some(x) = cand.or(from_pieces).or(from_input) else {
                    return false;
                };
                let d2 = |u: &[f64; 2]| (u[0] - x[0]).powi(2) + (u[1] - x[1]).powi(2);
                let mut best = p;
                for c in [q, a, b] {
                    if d2(w.p(c)) < d2(w.p(best)) {
                        best = c;
                    }
                }
                best
            }
        };
        // The edge the new vertex fell on exactly, if not p - q: its
        // pieces keep its labels; the vertex splits every one of them.
        if let Some((e0, e1)) = split_other {
            if ukey(e0, e1) != ukey(p, q) {
                if let Some((tt, ii)) = w.find_edge(e0, v) {
                    let c = w.con(tt, ii);
                    let labels = self.take_labels(e0, e1, c);
                    for &l in &labels {
                        self.report.vertex_splits.push(((self.out_id)(v), l));
                        if l != c {
                            for (x, y) in [(e0, v), (v, e1)] {
                                self.multi.entry(ukey(x, y)).or_default().push(l);
                            }
                        }
                    }
                }
            }
        }
        // Take p - q out (if it still exists) and queue its pieces.
        let labels = self.take_labels(p, q, other);
        if w.find_edge(p, q).is_some() {
            w.unconstrain(p, q);
        }
        for &l in &labels {
            // A segment sharing p - q goes through `v` only if `v` is within
            // the Steiner bound of it; otherwise it is inserted again whole
            // (and crosses the new pieces at its own vertex).
            let (la, lb) = self.seg_ends[l as usize];
            if (l != other || !fallback)
                && v != p
                && v != q
                && !near_segment(w.p(la), w.p(lb), w.p(v))
            {
                self.pending.push((p, q, l));
                continue;
            }
            if v != p && v != q {
                if created.is_some() && l == other {
                    self.report.crossings.push(Crossing {
                        vertex: v,
                        segments: [s, other],
                    });
                } else {
                    self.report.vertex_splits.push(((self.out_id)(v), l));
                }
            }
            self.pending.push((v, q, l));
            self.pending.push((p, v, l));
        }
        // A new vertex records `s` in its crossing.
        if v != a && v != b && created.is_none() {
            self.report.vertex_splits.push(((self.out_id)(v), s));
        }
        self.pending.push((v, b, s));
        self.pending.push((a, v, s));
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The working mesh of the Delaunay triangulation of `pts`.
    fn work_of(pts: &[[f64; 2]]) -> Work {
        let (xy, _, _, _, tv, ta) = Delaunay2::from_points(pts).unwrap().into_raw();
        let w = Work::new(xy, tv, ta);
        w.cm.check(true).unwrap();
        w
    }

    /// Every interior edge as (triangle, edge), in slot order.
    fn interior(w: &Work) -> Vec<(usize, usize)> {
        (0..w.cm.tr.len())
            .filter(|&t| w.v(t)[0] != DEAD && !is_ghost(&w.v(t)))
            .flat_map(|t| (0..3).map(move |e| (t, e)))
            .filter(|&(t, e)| !is_ghost(&w.v(unpack(w.a(t, e)).0)))
            .collect()
    }

    fn grid(n: usize, step: f64, origin: f64) -> Vec<[f64; 2]> {
        (0..n * n)
            .map(|k| {
                [
                    origin + step * (k % n) as f64,
                    origin + step * (k / n) as f64,
                ]
            })
            .collect()
    }

    /// Flips every convex interior edge once, labels some edges, splits
    /// edges and triangles and legalizes, checking the mesh after each.
    fn exercise(pts: &[[f64; 2]]) {
        let mut w = work_of(pts);
        let mut flips = 0;
        for (t, e) in interior(&w) {
            let (n, j) = unpack(w.a(t, e));
            if is_ghost(&w.v(t)) || is_ghost(&w.v(n)) {
                continue; // (the list predates the flips)
            }
            let (x, d) = (w.v(t)[e], w.v(n)[j]);
            let (u, v) = edge(&w.v(t), e);
            if orient2d(w.p(x), w.p(u), w.p(d)) > 0.0 && orient2d(w.p(d), w.p(v), w.p(x)) > 0.0 {
                w.flip(t, e);
                flips += 1;
                w.cm.check(false)
                    .unwrap_or_else(|v| panic!("flip {flips}: {v}"));
            }
        }
        assert!(flips > 0);
        // Lawson flips from every edge restore the Delaunay property.
        let mut st: Vec<(u32, u32)> = interior(&w)
            .iter()
            .map(|&(t, e)| edge(&w.v(t), e))
            .collect();
        w.legalize(&mut st);
        w.cm.check(true).unwrap();
        // A label on every third interior edge; they are never flipped.
        for (k, (t, e)) in interior(&w).into_iter().enumerate().step_by(3) {
            let (u, v) = edge(&w.v(t), e);
            if w.con(t, e) == NONE {
                label_half_edge(&mut w, &mut HashMap::new(), t, e, u, v, k as u32);
            }
        }
        w.cm.check(true).unwrap();
        // Edge midpoints and triangle centroids.
        for (k, (t, e)) in interior(&w).into_iter().enumerate().step_by(7) {
            if w.v(t)[0] == DEAD || is_ghost(&w.v(t)) {
                continue;
            }
            let v = w.v(t);
            let (a, b) = edge(&v, e);
            let (pa, pb, pc) = (*w.p(a), *w.p(b), *w.p(v[e]));
            let x = if k % 2 == 0 {
                [0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1])]
            } else {
                [(pa[0] + pb[0] + pc[0]) / 3.0, (pa[1] + pb[1] + pc[1]) / 3.0]
            };
            let before = w.cm.xy.len();
            if let Some(Placed::New(s, _)) = w.insert_point(t, x) {
                assert_eq!(s as usize, before);
            }
            w.cm.check(true)
                .unwrap_or_else(|v| panic!("after inserting {x:?}: {v}"));
        }
        assert!(w.cm.xy.len() > pts.len());
    }

    #[test]
    fn operations_keep_the_working_mesh_valid() {
        exercise(&grid(7, 1.0, 0.0));
        exercise(&grid(6, 1e-200, 1e-199));
        exercise(&grid(6, 1e150, -3e150));
        let mut pts: Vec<[f64; 2]> = (0..15).map(|k| [k as f64, 0.0]).collect();
        pts.extend([
            [7.5, 1e-3],
            [3.25, -2e-3],
            [11.0, 5.0],
            [2.0, 2.0],
            [2.0, 2.0],
        ]);
        exercise(&pts);
    }

    #[test]
    fn the_checker_sees_a_one_sided_label() {
        let mut w = work_of(&grid(4, 1.0, 0.0));
        let (t, e) = interior(&w)[0];
        w.cm.set_sub(t, e, 0);
        assert_eq!(w.cm.check(false).unwrap_err().kind, "subsegment");
    }
}
