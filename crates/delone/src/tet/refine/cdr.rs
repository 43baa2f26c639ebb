//! Constrained Delaunay refinement on the domain mesh of a [`Recovered`]
//! (see the [module documentation](super) for the rules and why every
//! step keeps the mesh valid).
//!
//! The structure is the carved domain only: flat arrays of tetrahedra,
//! neighbour words `4 * tet + facet` ([`NONE`] across the domain
//! boundary), a 4-bit mask per tetrahedron telling which of its faces are
//! subfaces, the region per tetrahedron, and side tables keyed by sorted
//! vertex triples / pairs (subface → input triangle, edge → subfaces,
//! subsegment → input edge) consulted only when a constraint is touched.

#![allow(clippy::needless_range_loop)] // local face indices address several arrays at once

use super::queue::Heap;
use crate::geom::ids::{IdMap, IdSet};
use crate::tet::local::{ekey, face, fkey};
use std::cmp::Reverse;
use std::collections::VecDeque;

use delone_predicates::{insphere, orient3d};

use super::geom::{
    encroaches_face, encroaches_segment, line_distance, plane_distance, tri_circumcenter,
};

use super::options::{default_budget, volume_bounds, RefineOptions, BUDGET_MAX};
use super::report::{RefineReport, Refined};
use crate::geom::vec3::{angle, cross, dist2, dot, sub, P};
use crate::geom::{union_join, union_root};
use crate::tet::dmesh::{DomainMesh, Stamps};
use crate::tet::local::DEAD;
use crate::tet::quality;
use crate::tet::recover::{RecoverError, Recovered};
use crate::tet::TetMesh;
use crate::NONE;

#[path = "cdrflip.rs"]
mod flip;

use crate::tet::local::EDGES;

/// Subsegments shorter than this fraction of their input edge are not split
/// (protection against runaway refinement at small input angles).
const SEGMENT_FLOOR: f64 = 1.0 / 4096.0;

/// Radius-edge ratio above which a bad cell counts as flat and is left (its
/// circumcentre is far away; splitting the boundary for it would run away).
const FLAT_RATIO: f64 = 1e6;

/// A bad cell in the priority queue: worst first, then by vertices.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
struct Bad {
    /// Bits of a non-negative badness (monotone as an integer).
    key: u64,
    verts: std::cmp::Reverse<[u32; 4]>,
    slot: u32,
}

/// Relative distance below which a neighbour's fourth vertex counts as on
/// the plane of a triangle (input coordinates printed with 7 digits make
/// flat regions a few 1e-8 off).
const COPLANAR_TOL: f64 = 1e-6;

/// Groups the input triangles into planes: neighbours across an input edge
/// whose fourth vertex is coplanar (exactly, or within [`COPLANAR_TOL`] of
/// the triangle's size) share a group (union-find; the
/// group id is the smallest triangle index of the group).
fn plane_groups(
    pts: &[[f64; 3]],
    triangles: &[[u32; 3]],
    edge_tris: &[[u32; 2]],
    tri_edges: &[[u32; 3]],
) -> Vec<u32> {
    let mut parent: Vec<u32> = (0..triangles.len() as u32).collect();
    for (t, tri) in triangles.iter().enumerate() {
        for &e in &tri_edges[t] {
            let [t1, t2] = edge_tris[e as usize];
            let u = if t1 as usize == t { t2 } else { t1 };
            if u as usize == t {
                continue;
            }
            let other = triangles[u as usize];
            let Some(&d) = other.iter().find(|q| !tri.contains(q)) else {
                continue;
            };
            let g = |q: u32| &pts[q as usize];
            let (pa, pb, pc, pd) = (g(tri[0]), g(tri[1]), g(tri[2]), g(d));
            let span = [pb, pc, pd]
                .iter()
                .fold(0.0f64, |m, q| m.max(dist2(pa, q)))
                .sqrt();
            if delone_predicates::orient3d(pa, pb, pc, pd) == 0.0
                || plane_distance(pa, pb, pc, pd) <= COPLANAR_TOL * span
            {
                union_join(&mut parent, t as u32, u);
            }
        }
    }
    (0..triangles.len() as u32)
        .map(|t| union_root(&mut parent, t))
        .collect()
}

/// Input angle (degrees) below which a bad cell whose shortest edge joins
/// two concentric-shell points of the angle is left (see `Cdr::shell_pair`).
const SHELL_ANGLE: f64 = 30.0;

/// Dihedral input angle (degrees) below which a bad cell spanning the wedge
/// between the two facets is left (see `Cdr::wedge`).
const WEDGE_ANGLE: f64 = 30.0;

/// Height / longest side below which an input triangle counts as
/// degenerate (see `Cdr::degenerate`).
const DEGENERATE: f64 = 1e-4;

/// Smallest input-triangle angle (degrees) below which a left bad cell
/// counts as near a needle ([`LeftBad::near_needle`]).
const NEEDLE_ANGLE: f64 = 5.0;

/// Angle between input half-planes (degrees) below which a left bad cell
/// counts as near a sharp edge ([`LeftBad::near_sharp`]).
const SHARP_ANGLE: f64 = 60.0;

/// Length of the queue of bad cells below which it is never compacted
/// (see [`Cdr::run`]).
const COMPACT_MIN: usize = 1 << 16;

/// Largest cavity grown for one insertion.
const MAX_CAVITY: usize = 50_000;

/// A planned re-triangulation of a cavity (see [`Cdr::plan`]).
struct Plan {
    /// New tetrahedra `[x, y, z, new]` (face 3 on the cavity's boundary,
    /// which keeps its neighbour and subface mark) and their region.
    tets: Vec<([u32; 4], u32)>,
    /// New subfaces: the edge of the dissolved subfaces' boundary and the
    /// input triangle.
    subs: Vec<((u32, u32), u32)>,
}

/// Why a plan failed: drop this (non-required) tetrahedron and retry, or
/// give up.
type PlanErr = Option<u32>;

/// Why R3 last gave up on a bad cell (see [`LeftBad`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Left {
    Flat,
    Behind,
    Close,
    Radius,
    Small,
    Wedge,
    Degenerate,
    Shell,
    Refused,
    /// The circumcentre (and every other point tried) would encroach a
    /// subface or subsegment, which [`RefineOptions::keep_surface`] forbids
    /// splitting.
    Surface,
}

pub(super) struct Cdr {
    /// Points (rescaled): input, recovery's Steiner points, then new ones.
    p: Vec<P>,
    n_in: usize,
    /// The constrained domain mesh: tetrahedra, subface marks, regions,
    /// subface → input triangle ([`NONE`] for a hull face off the
    /// surface), subsegment → input edge.
    pub(super) m: DomainMesh,
    iedges: Vec<[u32; 2]>,
    tris: Vec<[u32; 3]>,
    normals: Vec<P>,
    /// Plane group of each input triangle (coplanar neighbours share one).
    group: Vec<u32>,
    /// Facet of each surface triangle: the surface triangles of one merged
    /// coplanar group share one (R2 works on the whole facet).
    facet: Vec<u32>,
    /// Per facet id: does it hold two or more surface triangles?
    merged: Vec<bool>,
    /// Input triangles each vertex lies on.
    vtris: Vec<Vec<u32>>,
    /// Per input triangle: degenerate (a sliver of zero angle, its height
    /// below [`DEGENERATE`] times its longest side)?
    degenerate: Vec<bool>,
    segq: VecDeque<(u32, u32)>,
    faceq: VecDeque<[u32; 3]>,
    /// Subsegments / subfaces in `segq` / `faceq` (each queued once).
    queued_s: IdSet<(u32, u32)>,
    queued_f: IdSet<[u32; 3]>,
    /// Subsegments / subfaces whose split failed with the mesh unchanged:
    /// not tried again (an unchanged neighbourhood fails the same way, and
    /// retrying them for every cell that shows them spun for minutes).
    failed_s: IdSet<(u32, u32)>,
    failed_f: IdSet<[u32; 3]>,
    badq: Heap<Bad>,
    /// Length of [`Cdr::badq`] at which its entries for cells gone since
    /// they were queued are dropped (see [`Cdr::run`]).
    compact_at: usize,
    bound: f64,
    /// Per region: the volume bound (rescaled).
    max_vol: Vec<f64>,
    budget: usize,
    pub(super) report: RefineReport,
    inexact: Vec<u32>,
    /// Input edge of each point put on a segment by refinement.
    vedge: IdMap<u32, u32>,
    /// Per point: is (or was) it an end of a subsegment? Both ends of
    /// every subsegment are marked (a cheap test before the lookups in
    /// `DomainMesh::segs`).
    on_seg: Vec<bool>,
    /// Largest deviation of a new point from its line or plane (rescaled).
    max_dev: f64,
    s: f64,
    sizer: super::sizing::Sizer,
    /// While R3 splits the pieces a rejected circumcentre encroaches: the
    /// shortest edge the split may create (the bad cell's shortest edge),
    /// else 0.
    min_ir: f64,
    /// Set when [`Cdr::insert`] refused a point for [`Cdr::min_ir`] (the
    /// piece is not marked as failed: it may be split for another reason).
    ir_refused: bool,
    /// The bad cells R3 gave up on (by vertices, as stored), and why.
    left: IdMap<[u32; 4], Left>,
    /// [`RefineOptions::keep_surface`]: no point on a subface or
    /// subsegment.
    keep_surface: bool,
    /// [`RefineOptions::diagnostics`]: the cells left are counted and
    /// explained.
    diagnostics: bool,
    /// Scratch of [`Cdr::grow`]: the cells whose in-sphere test was made.
    outside: Stamps,
    /// Scratch of [`Cdr::plan`]: the vertices of the cavity's boundary.
    vstamp: Stamps,
    /// Which queue the split in progress serves (for
    /// [`RefineReport::causes`]).
    asker: Asker,
}

/// The rule that asked for the split in progress ([`Cdr::asker`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Asker {
    /// A vertex encroaching a subsegment (R1).
    Segment,
    /// A vertex encroaching a subface, or the sizing (R2).
    Subface,
    /// A bad cell (R3).
    Cell,
}

impl Cdr {
    /// Refinement of `rec` in `m`, its domain mesh (see
    /// [`super::refine_in_place`]).
    pub(super) fn new(
        points: &[[f64; 3]],
        triangles: &[[u32; 3]],
        rec: &Recovered,
        mut m: DomainMesh,
        opts: &RefineOptions,
    ) -> Result<Cdr, RecoverError> {
        let (cow, scale) = crate::geom::rescaled(&rec.points);
        let s = scale.0 * scale.1;
        let p: Vec<P> = cow.into_owned();
        let nt = m.tv.len();
        let mut ftri: IdMap<[u32; 3], u32> = IdMap::default();
        let mut sedges: IdMap<(u32, u32), Vec<[u32; 3]>> = IdMap::default();
        let mut per_tri: Vec<Vec<[u32; 3]>> = vec![Vec::new(); triangles.len()];
        let mut vtris: Vec<Vec<u32>> = vec![Vec::new(); p.len()];
        for (f, t) in rec.surface_faces() {
            let k = fkey(*f);
            if ftri.insert(k, t).is_some() {
                continue;
            }
            for (a, b) in [(k[0], k[1]), (k[0], k[2]), (k[1], k[2])] {
                sedges.entry((a, b)).or_default().push(k);
            }
            if let Some(l) = per_tri.get_mut(t as usize) {
                l.push(k);
                for &q in &k {
                    if !vtris[q as usize].contains(&t) {
                        vtris[q as usize].push(t);
                    }
                }
            }
        }
        for (t, tri) in triangles.iter().enumerate() {
            for &q in tri {
                if !vtris[q as usize].contains(&(t as u32)) {
                    vtris[q as usize].push(t as u32);
                }
            }
        }
        for t in 0..nt {
            for i in 0..4 {
                if ftri.contains_key(&fkey(face(m.tv[t], i))) {
                    m.mask[t] |= 1 << i;
                }
            }
        }
        // Input edges, and the subsegments: the edges of a triangle's faces
        // used once lie on its sides.
        let mut emap: IdMap<(u32, u32), u32> = IdMap::default();
        let mut iedges = Vec::new();
        let mut edge_tris: Vec<[u32; 2]> = Vec::new();
        let mut tri_edges = vec![[0u32; 3]; triangles.len()];
        for (t, tri) in triangles.iter().enumerate() {
            for k in 0..3 {
                let e = ekey(tri[k], tri[(k + 1) % 3]);
                let i = *emap.entry(e).or_insert_with(|| {
                    iedges.push([e.0, e.1]);
                    edge_tris.push([t as u32, t as u32]);
                    (iedges.len() - 1) as u32
                });
                edge_tris[i as usize][1] = t as u32;
                tri_edges[t][k] = i;
            }
        }
        let group = plane_groups(&p, triangles, &edge_tris, &tri_edges);
        let origin: &[u32] = if rec.surface.is_empty() {
            &[]
        } else {
            &rec.surface_origin
        };
        let (facet, members) = crate::tet::recover::facets(triangles, origin);
        let merged = members.iter().map(|m| m.len() >= 2).collect();
        let mut segs: IdMap<(u32, u32), u32> = IdMap::default();
        for mem in &members {
            if mem.is_empty() {
                continue;
            }
            // A merged group's faces all name its first triangle
            // (`Recovered::boundary_triangle`): its subsegments lie on the
            // sides of any of its triangles.
            let sides: Vec<[u32; 2]> = mem
                .iter()
                .flat_map(|&u| {
                    let tri = triangles[u as usize];
                    (0..3).map(move |k| [tri[k], tri[(k + 1) % 3]])
                })
                .collect();
            // Edges used once by the faces of the facet lie on its sides.
            let mut es: Vec<((u32, u32), u32)> = mem
                .iter()
                .flat_map(|&t| per_tri[t as usize].iter().map(move |k| (k, t)))
                .flat_map(|(k, t)| [((k[0], k[1]), t), ((k[0], k[2]), t), ((k[1], k[2]), t)])
                .collect();
            es.sort_unstable();
            for g in es.chunk_by(|x, y| x.0 == y.0) {
                if let [(e, _)] = *g {
                    // Distance to the side's line (relative), plus 1 when
                    // off the side's extent (collinear sides of a polygon).
                    let score = |k: usize| {
                        let [a, b] = sides[k];
                        let (pa, pb) = (p[a as usize], p[b as usize]);
                        let l = dist2(&pa, &pb).sqrt();
                        [e.0, e.1]
                            .iter()
                            .map(|&q| {
                                if q == a || q == b {
                                    0.0
                                } else {
                                    let pq = p[q as usize];
                                    let s = dot(&sub(&pq, &pa), &sub(&pb, &pa)) / (l * l);
                                    let off = if (0.0..=1.0).contains(&s) { 0.0 } else { 1.0 };
                                    line_distance(&pa, &pb, &pq) / l + off
                                }
                            })
                            .fold(0.0, f64::max)
                    };
                    // The first side of least score (as `min_by`), each
                    // score computed once.
                    let mut k = 0;
                    let mut best = f64::NAN;
                    for x in 0..sides.len() {
                        let sx = score(x);
                        if x == 0 || best.total_cmp(&sx).is_gt() {
                            (k, best) = (x, sx);
                        }
                    }
                    let ie = emap[&ekey(sides[k][0], sides[k][1])];
                    segs.entry(e).or_insert(ie);
                }
            }
        }
        let degenerate = triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|q| p[q as usize]);
                let n = cross(&sub(&b, &a), &sub(&c, &a));
                let l2 = dist2(&a, &b).max(dist2(&b, &c)).max(dist2(&a, &c));
                // height = |n| / longest side
                dot(&n, &n).sqrt() < DEGENERATE * l2
            })
            .collect();
        let normals = triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|q| p[q as usize]);
                cross(&sub(&b, &a), &sub(&c, &a))
            })
            .collect();
        let s3 = s * s * s;
        let max_vol = volume_bounds(&rec.regions, opts.max_volume)
            .map(|v| v.map_or(f64::INFINITY, |v| v * s3))
            .collect();
        let mut on_seg = vec![false; p.len()];
        for &(a, b) in segs.keys() {
            on_seg[a as usize] = true;
            on_seg[b as usize] = true;
        }
        (m.ftri, m.sedges, m.segs) = (ftri, sedges, segs);
        let mut st = Cdr {
            n_in: points.len(),
            m,
            iedges,
            tris: triangles.to_vec(),
            normals,
            group,
            facet,
            merged,
            vtris,
            degenerate,
            segq: VecDeque::new(),
            faceq: VecDeque::new(),
            queued_s: IdSet::default(),
            queued_f: IdSet::default(),
            failed_s: IdSet::default(),
            failed_f: IdSet::default(),
            badq: Heap::new(),
            compact_at: COMPACT_MIN,
            bound: opts.max_radius_edge.unwrap_or(f64::INFINITY),
            max_vol,
            budget: 0,
            report: RefineReport {
                recover: rec.report.clone(),
                ..RefineReport::default()
            },
            inexact: rec.inexact.clone(),
            vedge: IdMap::default(),
            on_seg,
            max_dev: rec.report.max_deviation * s,
            s,
            sizer: super::sizing::Sizer::new(&opts.sizing, s),
            p,
            min_ir: 0.0,
            ir_refused: false,
            left: IdMap::default(),
            keep_surface: opts.keep_surface,
            diagnostics: opts.diagnostics,
            outside: Stamps::default(),
            vstamp: Stamps::default(),
            asker: Asker::Cell,
        };
        st.budget = if let Some(n) = opts.max_steiner {
            n
        } else {
            // Volume over the bound, summed over the tetrahedra (both
            // rescaled alike).
            let ratio: f64 = (0..st.m.tv.len())
                .filter(|&t| st.m.alive(t as u32))
                .map(|t| {
                    let bound = st
                        .max_vol
                        .get(st.m.reg[t] as usize)
                        .copied()
                        .unwrap_or(f64::INFINITY);
                    if bound.is_finite() && bound > 0.0 {
                        quality::volume(&st.m.tv[t].map(|q| st.p[q as usize])).abs() / bound
                    } else {
                        0.0
                    }
                })
                .sum();
            // A volume bound is met with about a third of `ratio` points: one
            // that needs more than the largest default budget would only stop
            // at it, after a long run. Refuse it now.
            if ratio / 3.0 > BUDGET_MAX as f64 {
                return Err(crate::Error::BoundNeedsBudget {
                    option: "-a",
                    value: opts.max_volume.unwrap_or(f64::NAN),
                    needed: (ratio / 3.0).min(u64::MAX as f64) as usize,
                    budget: BUDGET_MAX,
                }
                .into());
            }
            default_budget(points.len(), ratio)
        };
        st.report.steiner_budget = st.budget;
        // The recovered mesh is not constrained Delaunay (recovery flips and
        // carves): restore the property, so cavities are Delaunay cavities.
        st.m.debug_check(&st.p, "refinement start");
        st.flip_delaunay(None);
        for t in 0..st.m.tv.len() as u32 {
            if !st.m.alive(t) {
                continue;
            }
            st.check_tet(t);
        }
        Ok(st)
    }

    #[inline]
    fn pt(&self, q: u32) -> P {
        self.p[q as usize]
    }

    /// Is `e` (sorted) a subsegment?
    #[inline]
    fn is_seg(&self, e: (u32, u32)) -> bool {
        self.on_seg[e.0 as usize] && self.on_seg[e.1 as usize] && self.m.segs.contains_key(&e)
    }

    fn out_of_budget(&mut self) -> bool {
        if self.report.steiner() >= self.budget {
            self.report.budget_exhausted = true;
            true
        } else {
            false
        }
    }

    /// Does vertex `w` lie on a surface triangle that shares a vertex with
    /// one of `tris`, other than a triangle of the same merged planar facet?
    /// Then its encroachment is not acted on (protection at small input
    /// angles, see the module documentation): on a curved surface every
    /// input triangle is its own facet, and acting on the vertices of
    /// needle-shaped neighbours would refine the surface down to their
    /// width. Inside a merged planar facet there is no angle to protect.
    fn near(&self, w: u32, tris: &[u32]) -> bool {
        let Some(wt) = self.vtris.get(w as usize) else {
            return false;
        };
        wt.iter().any(|&a| {
            let ta = self.tris[a as usize];
            tris.iter().any(|&b| {
                let Some(tb) = self.tris.get(b as usize) else {
                    return false;
                };
                let same = self.facet[a as usize] == self.facet[b as usize]
                    && self.merged[self.facet[a as usize] as usize];
                !same && tb.iter().any(|q| ta.contains(q))
            })
        })
    }

    fn seg_tris(&self, e: (u32, u32)) -> Vec<u32> {
        self.m
            .sedges
            .get(&e)
            .map(|l| {
                l.iter()
                    .filter_map(|k| self.m.ftri.get(k).copied())
                    .collect()
            })
            .unwrap_or_default()
    }

    fn seg_encroached_by(&self, e: (u32, u32), w: u32) -> bool {
        let g = |q: u32| &self.p[q as usize];
        encroaches_segment(g(e.0), g(e.1), g(w)) && !self.near(w, &self.seg_tris(e))
    }

    fn face_encroached_by(&self, k: [u32; 3], w: u32) -> bool {
        let g = |q: u32| &self.p[q as usize];
        // (The geometry first: it is cheaper than the table.)
        encroaches_face(g(k[0]), g(k[1]), g(k[2]), g(w))
            && self
                .m
                .ftri
                .get(&k)
                .is_some_and(|&t| t != NONE && !self.near(w, &[t]))
    }

    /// Badness key of tetrahedron `t`, when it breaks a bound.
    fn badness(&self, t: u32) -> Option<u64> {
        let tv = self.m.tv[t as usize];
        let p = tv.map(|q| self.p[q as usize]);
        let r = quality::radius_edge_ratio(&p);
        let mv = self
            .max_vol
            .get(self.m.reg[t as usize] as usize)
            .copied()
            .unwrap_or(f64::INFINITY);
        // (No volume can exceed an infinite bound.)
        let v = if mv < f64::INFINITY {
            quality::volume(&p).abs()
        } else {
            0.0
        };
        let big = if v > mv { v / mv } else { 0.0 }.max(self.sizer.cell(&p));
        if r > self.bound {
            Some((1e6 + r.min(1e12)).to_bits())
        } else if big > 1.0 {
            Some(big.min(1e6).to_bits())
        } else {
            None
        }
    }

    /// Queues what tetrahedron `t` shows: encroached subfaces and
    /// subsegments (by its own vertices), and itself when bad.
    fn check_tet(&mut self, t: u32) {
        let tv = self.m.tv[t as usize];
        if self.keep_surface {
            // Nothing on the surface is split: only bad cells are queued.
            if let Some(key) = self.badness(t) {
                self.badq.push(Bad {
                    key,
                    verts: Reverse(tv),
                    slot: t,
                });
            }
            return;
        }
        for f in 0..4 {
            if self.m.mask[t as usize] >> f & 1 == 1 {
                let k = fkey(face(tv, f));
                if (self.face_encroached_by(k, tv[f]) || self.face_too_big(k))
                    && !self.queued_f.contains(&k)
                    && !self.failed_f.contains(&k)
                {
                    self.queued_f.insert(k);
                    self.faceq.push_back(k);
                }
            }
        }
        for (i, j) in EDGES {
            let e = ekey(tv[i], tv[j]);
            if self.is_seg(e)
                && (0..4)
                    .filter(|&k| k != i && k != j)
                    .any(|k| self.seg_encroached_by(e, tv[k]))
                && !self.queued_s.contains(&e)
                && !self.failed_s.contains(&e)
            {
                self.queued_s.insert(e);
                self.segq.push_back(e);
            }
        }
        if let Some(key) = self.badness(t) {
            self.badq.push(Bad {
                key,
                verts: Reverse(tv),
                slot: t,
            });
        }
    }

    /// The tetrahedra holding edge `a b` (those reachable around it).
    fn around_edge(&self, a: u32, b: u32) -> Vec<u32> {
        // Walk the star of `a` to a tetrahedron holding `b`.
        let holds_b = |t: u32| self.m.tv[t as usize].contains(&b);
        let mut walk = Vec::with_capacity(64);
        let Some(t0) = self.m.star_first(a, &mut walk, holds_b) else {
            return Vec::new();
        };
        let mut out = Vec::with_capacity(16);
        out.push(t0);
        let mut i = 0;
        while i < out.len() {
            let t = out[i];
            i += 1;
            let tv = self.m.tv[t as usize];
            for f in 0..4 {
                let w = self.m.nb[t as usize][f];
                if tv[f] != a && tv[f] != b && w != NONE && !out.contains(&(w >> 2)) {
                    out.push(w >> 2);
                }
            }
        }
        out
    }

    /// The tetrahedra (one or two) with face `k`.
    fn face_tets(&self, k: [u32; 3]) -> Vec<u32> {
        let mut v = self.around_edge(k[0], k[1]);
        v.retain(|&t| self.m.tv[t as usize].contains(&k[2]));
        v
    }

    fn in_sphere(&self, t: u32, m: &P) -> bool {
        let tv = self.m.tv[t as usize];
        let g = |i: usize| &self.p[tv[i] as usize];
        insphere(g(1), g(0), g(2), g(3), m) > 0.0
    }

    /// The Bowyer–Watson cavity of `m` grown from `seeds` across faces that
    /// are not subfaces.
    fn grow(&mut self, seeds: &[u32], m: &P) -> Vec<u32> {
        self.m.mark_begin();
        // Cells found outside the sphere: tested once (a cell next to
        // several cavity cells is reached several times).
        self.outside.clear();
        let mut cav: Vec<u32> = Vec::with_capacity(64);
        for &t in seeds {
            if self.m.mark(t) {
                cav.push(t);
            }
        }
        let mut i = 0;
        while i < cav.len() && cav.len() < MAX_CAVITY {
            let t = cav[i];
            i += 1;
            for f in 0..4 {
                let w = self.m.nb[t as usize][f];
                if w == NONE || self.m.mask[t as usize] >> f & 1 == 1 {
                    continue;
                }
                let u = w >> 2;
                if self.m.marked(u) || !self.outside.insert(u) || !self.in_sphere(u, m) {
                    continue;
                }
                self.m.mark(u);
                cav.push(u);
            }
        }
        cav
    }

    /// Plans the cone of the cavity's boundary to the new point `m`, the
    /// subfaces `dis` (faces of the cavity) replaced by the cone of their
    /// boundary edges; `split` is the subsegment being split (its edge
    /// disappears). Every check of the module documentation is made here;
    /// `seen`: [`Cdr::shrink`] has just passed `cav` as it is, so every
    /// boundary face is known to be seen by `m` and to make no flat cone
    /// (those tests are not made again).
    #[allow(clippy::too_many_arguments)]
    fn plan(
        &mut self,
        cav: &[u32],
        required: &[u32],
        dis: &[[u32; 3]],
        split: Option<(u32, u32)>,
        m: &P,
        tris: &[u32],
        seen: bool,
    ) -> Result<Plan, PlanErr> {
        self.m.mark_begin();
        for &t in cav {
            self.m.mark(t);
        }
        let drop = |t: u32| {
            if required.contains(&t) {
                None
            } else {
                Some(t)
            }
        };
        // Boundary edges of the dissolved subfaces.
        let mut dedges: Vec<((u32, u32), u32)> = Vec::new();
        for k in dis {
            let tri = self.m.ftri.get(k).copied().unwrap_or(NONE);
            for e in [(k[0], k[1]), (k[0], k[2]), (k[1], k[2])] {
                dedges.push((e, tri));
            }
        }
        dedges.sort_unstable();
        let mut bd: Vec<((u32, u32), u32)> = Vec::new();
        for g in dedges.chunk_by(|a, b| a.0 == b.0) {
            if let [x] = g {
                bd.push(*x);
            }
        }
        let mut tets = Vec::with_capacity(2 * cav.len() + 4);
        let mid = self.p.len() as u32;
        for &t in cav {
            let tv = self.m.tv[t as usize];
            for f in 0..4 {
                let w = self.m.nb[t as usize][f];
                let sub = self.m.mask[t as usize] >> f & 1 == 1;
                let k = fkey(face(tv, f));
                let is_dis = sub && dis.contains(&k);
                if w != NONE && self.m.marked(w >> 2) {
                    if sub && !is_dis {
                        // A subface inside the cavity would be lost.
                        return Err(drop(t).or_else(|| drop(w >> 2)));
                    }
                    continue;
                }
                if is_dis {
                    if w != NONE {
                        return Err(None);
                    }
                    continue;
                }
                let [x, y, z] = face(tv, f);
                let g = |q: u32| &self.p[q as usize];
                if !seen && sub && self.coplanar(&k, tris) {
                    // The new point is (topologically) on this subface's
                    // plane: its cone would be flat.
                    return Err(drop(t));
                }
                if !seen
                    && (orient3d(g(x), g(y), g(z), m) >= 0.0
                        || self.flat([x, y, z, mid], Some((mid, tris))))
                {
                    return Err(drop(t));
                }
                tets.push(([x, y, z, mid], self.m.reg[t as usize]));
            }
        }
        // The vertices of the cone's base (stamped) and its edges (packed
        // and sorted when the first subsegment of the cavity asks).
        self.vstamp.clear();
        for x in &tets {
            for &q in &x.0[..3] {
                self.vstamp.insert(q);
            }
        }
        let pack = |(a, b): (u32, u32)| u64::from(a) << 32 | u64::from(b);
        let mut bedges: Option<Vec<u64>> = None;
        let mut on_base = |e: (u32, u32)| {
            let b = bedges.get_or_insert_with(|| {
                let mut b: Vec<u64> = tets
                    .iter()
                    .flat_map(|x| {
                        let [a, b, c, _] = x.0;
                        [pack(ekey(a, b)), pack(ekey(b, c)), pack(ekey(a, c))]
                    })
                    .collect();
                b.sort_unstable();
                b.dedup();
                b
            });
            b.binary_search(&pack(e)).is_ok()
        };
        for &t in cav {
            let tv = self.m.tv[t as usize];
            for &v in &tv {
                if !self.vstamp.contains(v) {
                    let o = cav
                        .iter()
                        .copied()
                        .find(|&u| !required.contains(&u) && self.m.tv[u as usize].contains(&v));
                    return Err(o);
                }
            }
            for (i, j) in EDGES {
                let e = ekey(tv[i], tv[j]);
                if Some(e) != split && self.is_seg(e) && !on_base(e) {
                    let o = cav.iter().copied().find(|&u| {
                        let x = self.m.tv[u as usize];
                        !required.contains(&u) && x.contains(&e.0) && x.contains(&e.1)
                    });
                    return Err(o);
                }
            }
        }
        // Faces through the new point: matched at most twice; unmatched
        // only on the dissolved subfaces' boundary; every boundary edge
        // present; regions agree across faces that are not subfaces.
        // (Sorted by the edge alone, packed in a word: the order within a
        // group does not change the verdict.)
        let mut fm: Vec<(u64, usize)> = Vec::with_capacity(3 * tets.len());
        for (n, x) in tets.iter().enumerate() {
            let [a, b, c, _] = x.0;
            fm.extend([
                (pack(ekey(a, b)), n),
                (pack(ekey(b, c)), n),
                (pack(ekey(a, c)), n),
            ]);
        }
        fm.sort_unstable_by_key(|x| x.0);
        let mut seen_bd = 0;
        for g in fm.chunk_by(|a, b| a.0 == b.0) {
            let on_bd = bd.iter().any(|x| pack(x.0) == g[0].0);
            seen_bd += usize::from(on_bd);
            match g {
                [_] if !on_bd => return Err(None),
                [x, y] if !on_bd && tets[x.1].1 != tets[y.1].1 => return Err(None),
                [_] | [_, _] => {}
                _ => return Err(None),
            }
        }
        if seen_bd != bd.len() {
            return Err(None);
        }
        Ok(Plan { tets, subs: bd })
    }

    /// Applies a plan: returns the new vertex and tetrahedra.
    fn commit(&mut self, cav: &[u32], dis: &[[u32; 3]], plan: Plan, m: P) -> (u32, Vec<u32>) {
        let mid = self.p.len() as u32;
        self.p.push(m);
        self.on_seg.push(false);
        self.m.vt.push(DEAD);
        for k in dis {
            self.m.ftri.remove(k);
            for e in [(k[0], k[1]), (k[0], k[2]), (k[1], k[2])] {
                if let Some(l) = self.m.sedges.get_mut(&e) {
                    l.retain(|x| x != k);
                    if l.is_empty() {
                        self.m.sedges.remove(&e);
                    }
                }
            }
        }
        let new: Vec<[u32; 4]> = plan.tets.iter().map(|x| x.0).collect();
        let mut ids = Vec::with_capacity(new.len());
        self.m.replace(cav, &new, 0, &mut ids);
        for (&id, x) in ids.iter().zip(&plan.tets) {
            self.m.reg[id as usize] = x.1;
            // Faces through the new point on the dissolved subfaces'
            // boundary are the new subfaces.
            let tv = self.m.tv[id as usize];
            for f in 0..3 {
                let k = fkey(face(tv, f));
                // The new vertex is the largest id.
                if plan.subs.iter().any(|x| x.0 == (k[0], k[1])) {
                    self.m.mark_face(id, f);
                }
            }
        }
        for &((a, b), tri) in &plan.subs {
            let k = [a, b, mid];
            self.m.ftri.insert(k, tri);
            for e in [(a, b), (a, mid), (b, mid)] {
                self.m.sedges.entry(e).or_default().push(k);
            }
        }
        (mid, ids)
    }

    /// Inserts `m`: cavity grown from `required` (which must all stay;
    /// `grown`: that cavity when the caller has just grown it, on the mesh
    /// as it is), subfaces `dis` dissolved, subsegment `split` split.
    /// `None` (nothing changed) when no valid cavity exists.
    fn insert(
        &mut self,
        m: P,
        required: &[u32],
        dis: &[[u32; 3]],
        split: Option<(u32, u32)>,
        tris: Vec<u32>,
        grown: Option<Vec<u32>>,
    ) -> Option<u32> {
        if required.is_empty() {
            return None;
        }
        let mut cav = grown.unwrap_or_else(|| self.grow(required, &m));
        if cav.len() >= MAX_CAVITY {
            return None;
        }
        if !self.shrink(&mut cav, required, dis, &m, &tris) {
            return None;
        }
        if self.min_ir > 0.0 && self.too_close(&cav, &m, self.min_ir) {
            self.ir_refused = true;
            return None;
        }
        for round in 0..64 {
            match self.plan(&cav, required, dis, split, &m, &tris, round == 0) {
                Ok(plan) => {
                    let (mid, mut ids) = self.commit(&cav, dis, plan, m);
                    self.vtris.push(tris);
                    debug_assert_eq!(self.vtris.len(), self.p.len());
                    // The cavity may have been shrunk: flip back to
                    // constrained Delaunay around the new point.
                    ids.extend(self.flip_delaunay(Some(&ids)));
                    ids.sort_unstable();
                    ids.dedup();
                    for t in ids {
                        if self.m.alive(t) {
                            self.check_tet(t);
                        }
                    }
                    return Some(mid);
                }
                Err(Some(t)) => cav.retain(|&x| x != t),
                Err(None) => return None,
            }
        }
        None
    }

    /// Do the four vertices of `t` lie on one plane group (each on an input
    /// triangle of that group, new points by the triangles they were put
    /// on)? Such a tetrahedron is flat in exact arithmetic: its positive
    /// orientation would only be an accident of rounding new points, and
    /// it would lie on the facet, sandwiched between its subfaces. Plans
    /// and flips never build one, and R3 leaves one it finds (splitting its
    /// boundary would make flat cells again).
    pub(super) fn flat(&self, t: [u32; 4], extra: Option<(u32, &[u32])>) -> bool {
        // (A new interior point decides at once.)
        if extra.is_some_and(|(v, l)| l.is_empty() && t.contains(&v)) {
            return false;
        }
        let tris_of = |q: u32| -> &[u32] {
            match extra {
                Some((v, l)) if v == q => l,
                _ => self.vtris.get(q as usize).map_or(&[], |l| l.as_slice()),
            }
        };
        // A plane group common to the four vertices' triangles. Interior
        // points (no triangles) decide at once; the shortest list leads.
        let lists = t.map(tris_of);
        let Some(lead) = (0..4).min_by_key(|&i| lists[i].len()) else {
            return false;
        };
        if lists[lead].is_empty() {
            return false;
        }
        lists[lead].iter().any(|&a| {
            let Some(&g) = self.group.get(a as usize) else {
                return false;
            };
            (0..4).filter(|&i| i != lead).all(|i| {
                lists[i]
                    .iter()
                    .any(|&b| self.group.get(b as usize) == Some(&g))
            })
        })
    }

    /// Cavity correction before planning: drops, pass after pass, every
    /// tetrahedron that is not required and has a face on the cavity's
    /// boundary that the new point `m` does not strictly see (or that is a
    /// subface on `m`'s own plane, or would make a flat cone). The plan
    /// drops such cells one at a time too; doing it in passes here keeps a
    /// cavity that spans most of the mesh (points on a cylinder are nearly
    /// cospherical) from failing after a fixed number of retries. `false`
    /// when a required tetrahedron would have to go.
    fn shrink(
        &mut self,
        cav: &mut Vec<u32>,
        required: &[u32],
        dis: &[[u32; 3]],
        m: &P,
        tris: &[u32],
    ) -> bool {
        let mid = self.p.len() as u32;
        loop {
            self.m.mark_begin();
            for &t in cav.iter() {
                self.m.mark(t);
            }
            let mut drop: Vec<u32> = Vec::new();
            for &t in cav.iter() {
                let tv = self.m.tv[t as usize];
                let hidden = (0..4).any(|f| {
                    let w = self.m.nb[t as usize][f];
                    if w != NONE && self.m.marked(w >> 2) {
                        return false;
                    }
                    let sub = self.m.mask[t as usize] >> f & 1 == 1;
                    let k = fkey(face(tv, f));
                    if sub && dis.contains(&k) {
                        return false;
                    }
                    let [x, y, z] = face(tv, f);
                    let g = |q: u32| &self.p[q as usize];
                    (sub && self.coplanar(&k, tris))
                        || orient3d(g(x), g(y), g(z), m) >= 0.0
                        || self.flat([x, y, z, mid], Some((mid, tris)))
                });
                if hidden {
                    if required.contains(&t) {
                        return false;
                    }
                    drop.push(t);
                }
            }
            if drop.is_empty() {
                return true;
            }
            drop.sort_unstable();
            cav.retain(|t| drop.binary_search(t).is_err());
        }
    }

    /// Is subface `k` on the plane of one of `tris`?
    fn coplanar(&self, k: &[u32; 3], tris: &[u32]) -> bool {
        if tris.is_empty() {
            return false;
        }
        let Some(&t) = self.m.ftri.get(k) else {
            return false;
        };
        t != NONE
            && tris.iter().any(|&u| {
                self.group.get(u as usize).is_some()
                    && self.group[u as usize] == self.group[t as usize]
            })
    }

    /// The subfaces of the facet of surface triangle `tri` holding edge `e`.
    fn faces_on(&self, e: (u32, u32), tri: u32) -> Vec<[u32; 3]> {
        let f = self.facet.get(tri as usize).copied();
        self.m
            .sedges
            .get(&e)
            .map(|l| {
                l.iter()
                    .copied()
                    .filter(|k| {
                        self.m
                            .ftri
                            .get(k)
                            .is_some_and(|&t| self.facet.get(t as usize).copied() == f)
                    })
                    .collect()
            })
            .unwrap_or_default()
    }

    /// Records the deviation of a new point on input edge `ie`.
    fn on_line(&mut self, id: u32, ie: u32) {
        let [a, b] = self.iedges[ie as usize];
        let d = line_distance(
            &self.p[a as usize],
            &self.p[b as usize],
            &self.p[id as usize],
        );
        self.max_dev = self.max_dev.max(d);
        self.inexact.push(id);
        self.vedge.insert(id, ie);
    }

    /// Is `u v` an edge between two points that concentric-shell splits put
    /// at the same distance from an input vertex on two of its input edges?
    /// Such an edge is as short as the input angle between the two edges
    /// makes it: a cell that is bad because of it cannot be repaired by
    /// splitting anything (the splits would halve the shells towards the
    /// vertex forever), so it is left (Shewchuk's rule at small input
    /// angles, as in Triangle's 2D refinement).
    fn shell_pair(&self, u: u32, v: u32) -> bool {
        let (Some(&eu), Some(&ev)) = (self.vedge.get(&u), self.vedge.get(&v)) else {
            return false;
        };
        if eu == ev {
            return false;
        }
        let (a, b) = (self.iedges[eu as usize], self.iedges[ev as usize]);
        let Some(&s) = a.iter().find(|q| b.contains(q)) else {
            return false;
        };
        let ps = self.p[s as usize];
        let du = dist2(&ps, &self.p[u as usize]).sqrt();
        let dv = dist2(&ps, &self.p[v as usize]).sqrt();
        if (du - dv).abs() > 0.01 * du.max(dv) {
            return false;
        }
        // Only at a small input angle: the pair is closer than the shell
        // radius times 2 sin(θ/2) for θ = SHELL_ANGLE. (At larger angles the
        // shells do not cascade and the cells are refined as usual.)
        let uv = dist2(&self.p[u as usize], &self.p[v as usize]).sqrt();
        uv < 2.0 * (SHELL_ANGLE.to_radians() / 2.0).sin() * du.max(dv)
    }

    /// Records the deviation of a new point on input triangle `t`.
    fn on_plane(&mut self, id: u32, t: u32) {
        let [a, b, c] = self.tris[t as usize].map(|q| self.p[q as usize]);
        let x = self.p[id as usize];
        if orient3d(&a, &b, &c, &x) != 0.0 {
            self.max_dev = self.max_dev.max(plane_distance(&a, &b, &c, &x));
            self.inexact.push(id);
        }
    }

    /// R1: splits subsegment `e` (midpoint, or a concentric shell around
    /// an input vertex at one end).
    fn split_segment(&mut self, e: (u32, u32)) -> bool {
        self.attempt(e, |st| &mut st.failed_s, |st| st.split_segment_at(e))
    }

    /// Runs the split of `key` unless it is in the set `failed` gives:
    /// whether it inserted. A split that fails with the mesh unchanged (not
    /// for [`Cdr::min_ir`]) puts `key` in that set, so that it is not tried
    /// again.
    fn attempt<K: std::hash::Hash + Eq>(
        &mut self,
        key: K,
        failed: fn(&mut Self) -> &mut IdSet<K>,
        split: impl FnOnce(&mut Self) -> bool,
    ) -> bool {
        if failed(self).contains(&key) {
            return false;
        }
        let n = self.p.len();
        self.ir_refused = false;
        let done = split(self);
        if !done && self.p.len() == n && !self.ir_refused {
            failed(self).insert(key);
        }
        done
    }

    fn split_segment_at(&mut self, e: (u32, u32)) -> bool {
        let Some(&ie) = self.m.segs.get(&e) else {
            return false;
        };
        let (a, b) = e;
        let (pa, pb) = (self.p[a as usize], self.p[b as usize]);
        let l = dist2(&pa, &pb).sqrt();
        let [ia, ib] = self.iedges[ie as usize];
        let li = dist2(&self.p[ia as usize], &self.p[ib as usize]).sqrt();
        if l < SEGMENT_FLOOR * li {
            self.report.unsplittable += 1;
            return false;
        }
        let (ina, inb) = ((a as usize) < self.n_in, (b as usize) < self.n_in);
        let mut t = 0.5;
        if ina != inb {
            let d = 2f64.powi((l / 2.0).log2().round() as i32);
            t = if ina { d / l } else { 1.0 - d / l };
            if !(0.2..=0.8).contains(&t) {
                t = 0.5;
            }
        }
        let mut m: P = std::array::from_fn(|k| {
            if pa[k] == pb[k] {
                pa[k]
            } else {
                pa[k] + t * (pb[k] - pa[k])
            }
        });
        if m == pa || m == pb {
            self.report.unsplittable += 1;
            return false;
        }
        for k in 0..3 {
            if !(pa[k].min(pb[k])..=pa[k].max(pb[k])).contains(&m[k]) {
                m[k] = 0.5 * (pa[k] + pb[k]);
            }
        }
        let dis = self.m.sedges.get(&e).cloned().unwrap_or_default();
        let req = self.around_edge(a, b);
        let tris: Vec<u32> = {
            let mut v = self.seg_tris(e);
            v.sort_unstable();
            v.dedup();
            v.retain(|&t| t != NONE);
            v
        };
        // Each facet at the subsegment re-triangulated Delaunay in its plane
        // (facet-local cavities); failing that, only the subfaces holding it.
        let mut grown: Vec<[u32; 3]> = Vec::new();
        for &tri in &tris {
            let seeds: Vec<[u32; 3]> = dis
                .iter()
                .copied()
                .filter(|k| self.m.ftri.get(k) == Some(&tri))
                .collect();
            grown.extend(self.facet_cavity(seeds, tri, &m));
        }
        grown.extend(
            dis.iter()
                .filter(|k| self.m.ftri.get(*k).is_none_or(|t| !tris.contains(t))),
        );
        grown.sort_unstable();
        grown.dedup();
        let mut done = None;
        if grown.len() > dis.len() {
            let mut req2: Vec<u32> = grown.iter().flat_map(|&f| self.face_tets(f)).collect();
            req2.extend(&req);
            req2.sort_unstable();
            req2.dedup();
            done = self.insert(m, &req2, &grown, Some(e), tris.clone(), None);
        }
        let done = match done {
            Some(id) => Some(id),
            None => self.insert(m, &req, &dis, Some(e), tris, None),
        };
        match done {
            Some(id) => {
                self.m.segs.remove(&e);
                self.m.segs.insert(ekey(a, id), ie);
                self.m.segs.insert(ekey(id, b), ie);
                self.on_seg[id as usize] = true;
                self.on_line(id, ie);
                self.report.on_segments += 1;
                let c = &mut self.report.causes;
                match self.asker {
                    Asker::Segment => c.segments_for_vertices += 1,
                    Asker::Subface => c.segments_for_subfaces += 1,
                    Asker::Cell => c.segments_for_cells += 1,
                }
                true
            }
            None => {
                self.report.unsplittable += 1;
                false
            }
        }
    }

    /// Snaps `m` to an axis-parallel input triangle's plane.
    fn snap(&self, m: &mut P, tri: u32) {
        let [a, b, c] = self.tris[tri as usize].map(|q| self.p[q as usize]);
        for k in 0..3 {
            if a[k] == b[k] && b[k] == c[k] {
                m[k] = a[k];
            }
        }
    }

    /// Subface `k` of triangle `tri` with its vertices ordered
    /// counterclockwise seen along the triangle's normal.
    fn oriented(&self, k: [u32; 3], tri: u32) -> [u32; 3] {
        let n = self.normals[tri as usize];
        let [a, b, c] = k.map(|q| self.p[q as usize]);
        if dot(&cross(&sub(&b, &a), &sub(&c, &a)), &n) >= 0.0 {
            k
        } else {
            [k[0], k[2], k[1]]
        }
    }

    /// Walks the subfaces of `tri` from `start` towards `m`: the subface
    /// holding it, or `Err(Some(e))` when a subsegment `e` is in the way.
    fn locate_on_facet(&self, start: [u32; 3], tri: u32, m: &P) -> Result<[u32; 3], PlanSeg> {
        let n = self.normals[tri as usize];
        let mut cur = start;
        let mut prev: Option<[u32; 3]> = None;
        for _ in 0..100_000 {
            let o = self.oriented(cur, tri);
            let mut next = None;
            for i in 0..3 {
                let (x, y) = (o[i], o[(i + 1) % 3]);
                let (px, py) = (self.p[x as usize], self.p[y as usize]);
                if dot(&cross(&sub(&py, &px), &sub(m, &px)), &n) < 0.0 {
                    let e = ekey(x, y);
                    if self.is_seg(e) {
                        return Err(Some(e));
                    }
                    let nx = self.faces_on(e, tri).into_iter().find(|&f| f != cur);
                    match nx {
                        Some(f) if Some(f) != prev => {
                            next = Some(f);
                            break;
                        }
                        Some(_) => continue,
                        None => return Err(None),
                    }
                }
            }
            match next {
                None => return Ok(cur),
                Some(f) => {
                    prev = Some(cur);
                    cur = f;
                }
            }
        }
        Err(None)
    }

    /// Is `m` strictly inside the polygon bounded by the oriented edges of
    /// the subfaces `d`' boundary? (Exact sign against a plane through each
    /// edge along the triangle's normal, compared with the third vertex.)
    fn inside_cavity(&self, d: &[[u32; 3]], tri: u32, m: &P) -> bool {
        let n = self.normals[tri as usize];
        let nl = dot(&n, &n).sqrt();
        let mut es: Vec<((u32, u32), u32)> = Vec::new();
        for k in d {
            for (x, y, z) in [(k[0], k[1], k[2]), (k[0], k[2], k[1]), (k[1], k[2], k[0])] {
                es.push(((x, y), z));
            }
        }
        es.sort_unstable();
        let mut deg: Vec<u32> = Vec::new();
        let mut verts: Vec<u32> = d.iter().flatten().copied().collect();
        verts.sort_unstable();
        verts.dedup();
        for g in es.chunk_by(|a, b| a.0 == b.0) {
            if let [((x, y), z)] = *g {
                deg.extend([x, y]);
                let (px, py) = (self.p[x as usize], self.p[y as usize]);
                let l = dist2(&px, &py).sqrt();
                let q: P = std::array::from_fn(|k| px[k] + n[k] / nl * l);
                let sz = orient3d(&px, &py, &q, &self.p[z as usize]);
                let sm = orient3d(&px, &py, &q, m);
                if sz == 0.0 || sm == 0.0 || (sz > 0.0) != (sm > 0.0) {
                    return false;
                }
            }
        }
        deg.sort_unstable();
        // A disk: every vertex on the boundary, twice.
        let runs = deg.chunk_by(|a, b| a == b);
        runs.clone().all(|r| r.len() == 2) && runs.count() == verts.len()
    }

    /// The facet-local Delaunay cavity of a point `c` on input triangle
    /// `tri`: the subfaces of `tri` reached from `seeds` across edges that
    /// are not subsegments whose circumcircle holds `c` (the seeds always
    /// belong). Keeps the subfaces of a facet Delaunay in its plane, which
    /// R1 needs as much as R2: dissolving only the subfaces holding a split
    /// subsegment leaves skinny subfaces whose circumcentres fall beyond
    /// the subsegment again, halving it towards its input vertex forever.
    fn facet_cavity(&self, seeds: Vec<[u32; 3]>, tri: u32, c: &P) -> Vec<[u32; 3]> {
        let mut d = seeds;
        let mut i = 0;
        while i < d.len() {
            let f = d[i];
            i += 1;
            for e in [(f[0], f[1]), (f[0], f[2]), (f[1], f[2])] {
                if self.is_seg(e) {
                    continue;
                }
                for h in self.faces_on(e, tri) {
                    if d.contains(&h) {
                        continue;
                    }
                    let Some((x, r2)) =
                        tri_circumcenter(&self.pt(h[0]), &self.pt(h[1]), &self.pt(h[2]))
                    else {
                        continue;
                    };
                    if dist2(&x, c) < r2 * (1.0 - 1e-12) {
                        d.push(h);
                    }
                }
            }
        }
        d
    }

    /// R2: splits subface `k` at its circumcentre (or the subsegment it
    /// encroaches, or, failing that, its longest edge).
    fn split_face(&mut self, k: [u32; 3]) -> bool {
        self.attempt(k, |st| &mut st.failed_f, |st| st.split_face_at(k))
    }

    fn split_face_at(&mut self, k: [u32; 3]) -> bool {
        let Some(&tri) = self.m.ftri.get(&k) else {
            return false;
        };
        if tri == NONE || self.degenerate[tri as usize] {
            return false;
        }
        let Some((mut c, _)) = tri_circumcenter(&self.pt(k[0]), &self.pt(k[1]), &self.pt(k[2]))
        else {
            return false;
        };
        self.snap(&mut c, tri);
        let s0 = match self.locate_on_facet(k, tri, &c) {
            Ok(f) => f,
            Err(Some(e)) => {
                // The circumcentre lies outside the facet, beyond `e`:
                // split `e` (Ruppert's rule; the facet's triangulation need
                // not be Delaunay, so `e` may not be encroached by it).
                let short = [(k[0], k[1]), (k[0], k[2]), (k[1], k[2])]
                    .iter()
                    .map(|x| dist2(&self.pt(x.0), &self.pt(x.1)))
                    .fold(f64::INFINITY, f64::min);
                if dist2(&self.pt(e.0), &self.pt(e.1)) >= short {
                    return self.split_segment(e);
                }
                // Much smaller than the subface: a small input angle or a
                // thin feature; leave the subface.
                self.report.skipped += 1;
                self.report.skipped_small += 1;
                return false;
            }
            Err(None) => {
                return self.face_fallback(k);
            }
        };
        // The facet-local cavity.
        let mut d = self.facet_cavity(vec![s0], tri, &c);
        if !self.inside_cavity(&d, tri, &c) {
            d = vec![s0];
            if !self.inside_cavity(&d, tri, &c) {
                return self.face_fallback(k);
            }
        }
        let mut req: Vec<u32> = d.iter().flat_map(|&f| self.face_tets(f)).collect();
        req.sort_unstable();
        req.dedup();
        // Encroached subsegments: split them instead.
        let cav = self.grow(&req, &c);
        let mut enc: Vec<(u32, u32)> = Vec::new();
        for &t in &cav {
            let tv = self.m.tv[t as usize];
            for (a, b) in EDGES {
                let e = ekey(tv[a], tv[b]);
                if self.is_seg(e) && encroaches_segment(&self.pt(e.0), &self.pt(e.1), &c) {
                    enc.push(e);
                }
            }
        }
        if !enc.is_empty() {
            enc.sort_unstable();
            enc.dedup();
            let mut progress = false;
            for e in enc {
                if !self.out_of_budget() {
                    progress |= self.split_segment(e);
                }
            }
            return progress;
        }
        // (The cavity just grown is the insertion's: the mesh has not
        // changed.)
        match self.insert(c, &req, &d, None, vec![tri], Some(cav)) {
            Some(id) => {
                self.on_plane(id, tri);
                self.report.on_facets += 1;
                if self.asker == Asker::Cell {
                    self.report.causes.facets_for_cells += 1;
                } else {
                    self.report.causes.facets_for_vertices += 1;
                }
                true
            }
            None => self.face_fallback(k),
        }
    }

    /// The fallback of R2 when the circumcentre cannot be inserted: the
    /// longest edge of subface `k` is split when it is a subsegment (R1 is
    /// robust); otherwise the subface is left (counted as skipped: a
    /// midpoint inside the facet next to a non-Delaunay facet triangulation
    /// makes flat cells).
    fn face_fallback(&mut self, k: [u32; 3]) -> bool {
        let g = |q: u32| self.p[q as usize];
        let e = [(k[0], k[1]), (k[0], k[2]), (k[1], k[2])]
            .into_iter()
            .max_by(|x, y| {
                dist2(&g(x.0), &g(x.1))
                    .total_cmp(&dist2(&g(y.0), &g(y.1)))
                    .then(y.cmp(x))
            })
            .unwrap_or((k[0], k[1]));
        if self.m.segs.contains_key(&e) {
            self.split_segment(e)
        } else {
            self.report.skipped += 1;
            self.report.skipped_refused += 1;
            false
        }
    }

    /// Walks from `t` towards `c`: `Ok(t)` the tetrahedron holding it,
    /// `Err(Some(face))` the subface in the way, `Err(None)` lost.
    fn locate(&self, mut t: u32, c: &P) -> Result<u32, Option<[u32; 3]>> {
        let mut prev = NONE;
        for step in 0..200_000usize {
            let tv = self.m.tv[t as usize];
            let mut next = None;
            for j in 0..4 {
                let f = (j + step) % 4;
                let [x, y, z] = face(tv, f).map(|q| &self.p[q as usize]);
                if orient3d(x, y, z, c) > 0.0 {
                    let w = self.m.nb[t as usize][f];
                    if w == NONE || self.m.mask[t as usize] >> f & 1 == 1 {
                        return Err(Some(fkey(face(tv, f))));
                    }
                    if w >> 2 == prev {
                        continue;
                    }
                    next = Some(w >> 2);
                    break;
                }
            }
            match next {
                None => return Ok(t),
                Some(u) => {
                    prev = t;
                    t = u;
                }
            }
        }
        Err(None)
    }

    /// R3 on a bad tetrahedron: its circumcentre (or the pieces it
    /// encroaches); when that fails for a cell too big (volume or sizing
    /// bound), or with [`RefineOptions::keep_surface`], a point inside its
    /// circumball ([`Cdr::split_inside`]); else the cell is left.
    fn split_cell(&mut self, b: Bad) {
        let tv = b.verts.0;
        if self.m.tv.get(b.slot as usize) != Some(&tv) {
            return;
        }
        let big = self.too_big(b.slot);
        let Some(why) = self.split_circumcentre(b, big) else {
            return;
        };
        if (big || self.keep_surface) && self.split_inside(b, big) {
            return;
        }
        self.leave(tv, why);
    }

    /// Is live tetrahedron `t` above its region's volume bound or the
    /// sizing?
    fn too_big(&self, t: u32) -> bool {
        let p = self.m.tv[t as usize].map(|q| self.p[q as usize]);
        let mv = self
            .max_vol
            .get(self.m.reg[t as usize] as usize)
            .copied()
            .unwrap_or(f64::INFINITY);
        quality::volume(&p).abs() > mv || self.sizer.cell(&p) > 1.0
    }

    /// The subsegments and subfaces of the tetrahedra `cav` that `c`
    /// encroaches (geometrically), sorted and deduplicated.
    fn encroached(&self, cav: &[u32], c: &P) -> (Vec<(u32, u32)>, Vec<[u32; 3]>) {
        let mut segs = Vec::new();
        let mut faces = Vec::new();
        for &u in cav {
            let uv = self.m.tv[u as usize];
            for f in 0..4 {
                if self.m.mask[u as usize] >> f & 1 == 1 {
                    let k = fkey(face(uv, f));
                    if encroaches_face(&self.pt(k[0]), &self.pt(k[1]), &self.pt(k[2]), c) {
                        faces.push(k);
                    }
                }
            }
            for (i, j) in EDGES {
                let e = ekey(uv[i], uv[j]);
                if self.is_seg(e) && encroaches_segment(&self.pt(e.0), &self.pt(e.1), c) {
                    segs.push(e);
                }
            }
        }
        segs.sort_unstable();
        segs.dedup();
        faces.sort_unstable();
        faces.dedup();
        (segs, faces)
    }

    /// The fallback of R3: a point inside the circumball of cell `b`, on
    /// the way from its centroid to its circumcentre (at 3/4, 1/2, 1/4 of
    /// the way, then the centroid itself), inserted with `b` in its
    /// cavity, so the cell is gone. For a cell bad by shape only (with
    /// [`RefineOptions::keep_surface`]) the point must encroach no subface
    /// or subsegment of its cavity and lie no closer to a vertex than the
    /// cell's shortest edge (no cascade of ever shorter edges); a cell too
    /// big takes the first point that can be inserted (the volume bound is
    /// always met). False when none could be inserted (nothing changed).
    fn split_inside(&mut self, b: Bad, big: bool) -> bool {
        let tv = b.verts.0;
        if self.out_of_budget() {
            return false;
        }
        let p = tv.map(|q| self.p[q as usize]);
        let g: P = std::array::from_fn(|k| p.iter().map(|x| x[k]).sum::<f64>() / 4.0);
        let lmin = quality::edge_lengths(&p)
            .into_iter()
            .fold(f64::INFINITY, f64::min);
        let mut cand = Vec::new();
        if let Some(c) =
            quality::circumcenter(&p).filter(|_| quality::radius_edge_ratio(&p) <= FLAT_RATIO)
        {
            for f in [0.75, 0.5, 0.25] {
                cand.push(std::array::from_fn(|k| g[k] + f * (c[k] - g[k])));
            }
        }
        cand.push(g);
        for m in cand {
            let Ok(t0) = self.locate(b.slot, &m) else {
                continue;
            };
            let mut grown = None;
            if !big {
                let cav = self.grow(&[t0], &m);
                let (segs, faces) = self.encroached(&cav, &m);
                if !segs.is_empty() || !faces.is_empty() || self.too_close(&cav, &m, lmin) {
                    continue;
                }
                grown = Some(cav);
            }
            let req: Vec<u32> = if t0 == b.slot {
                vec![t0]
            } else {
                vec![t0, b.slot]
            };
            // (The cavity just grown from `t0` alone is the insertion's.)
            let grown = grown.filter(|_| t0 == b.slot);
            if self.insert(m, &req, &[], None, Vec::new(), grown).is_some() {
                self.report.interior += 1;
                self.report.inside += 1;
                return true;
            }
        }
        false
    }

    /// R3 at the circumcentre of bad cell `b` (`big`: above its volume or
    /// size bound, so the protections for cells bad by shape are off):
    /// `None` when it inserted the circumcentre or split a piece it
    /// encroaches (the cell is queued again), else why it gave up.
    fn split_circumcentre(&mut self, b: Bad, big: bool) -> Option<Left> {
        let tv = b.verts.0;
        if !big && self.flat(tv, None) {
            // Four vertices on (nearly) coplanar input triangles: the cell
            // is as flat as the input there; splitting the boundary would
            // make flat cells again, down to the segment floor.
            return Some(Left::Flat);
        }
        let p = tv.map(|q| self.p[q as usize]);
        let circ = quality::circumcenter(&p);
        let Some(c) = circ.filter(|_| quality::radius_edge_ratio(&p) <= FLAT_RATIO) else {
            // A flat cell (four points a hair off one plane, or a wedge at
            // a ridge between nearly coplanar facets): splitting its
            // boundary pieces leaves flat cells again, so it is left.
            return Some(Left::Flat);
        };
        let lmin = quality::edge_lengths(&p)
            .into_iter()
            .fold(f64::INFINITY, f64::min);
        if !big {
            let short = EDGES.iter().map(|&(i, j)| (tv[i], tv[j])).min_by(|x, y| {
                dist2(&self.pt(x.0), &self.pt(x.1))
                    .total_cmp(&dist2(&self.pt(y.0), &self.pt(y.1)))
                    .then(x.cmp(y))
            });
            if short.is_some_and(|(u, v)| self.shell_pair(u, v)) {
                return Some(Left::Shell);
            }
        }
        if !big && tv.iter().any(|&q| self.on_degenerate(q)) {
            return Some(Left::Degenerate);
        }
        if !big && self.wedge(tv) {
            return Some(Left::Wedge);
        }
        let (segs, faces) = match self.locate(b.slot, &c) {
            Err(None) => return Some(Left::Refused),
            Err(Some(k)) => {
                let [a, b, d] = k.map(|q| self.pt(q));
                if !encroaches_face(&a, &b, &d, &c) {
                    // Outside, behind a subface it does not encroach (near
                    // a cell the flips could not make constrained
                    // Delaunay, or a wedge at a ridge): leave the cell.
                    // (Splitting the subface when a vertex of the cell
                    // encroaches it was tried: it refines fandisk -pq2
                    // further without fewer bad cells, and runs away on
                    // cgal_hole -pq1.414.)
                    return Some(Left::Behind);
                }
                (Vec::new(), vec![k])
            }
            Ok(t) => {
                let cav = self.grow(&[t], &c);
                let (segs, faces) = self.encroached(&cav, &c);
                // A vertex of the cavity closer to the circumcentre than
                // the cell's shortest edge: the cell is not Delaunay (its
                // circumsphere reaches round a subface, near a reflex or
                // sharp input feature), and the insertion would make an
                // edge shorter than any of the cell's, the start of a
                // cascade of ever shorter edges. Leave the cell (only when
                // its shape is bad: a cell too big is split regardless).
                if !big
                    && segs.is_empty()
                    && faces.is_empty()
                    && quality::radius_edge_ratio(&p) > self.bound
                    && self.too_close(&cav, &c, lmin)
                {
                    return Some(Left::Close);
                }
                if segs.is_empty() && faces.is_empty() {
                    // (The cavity just grown is the insertion's: the mesh
                    // has not changed.)
                    if self
                        .insert(c, &[t], &[], None, Vec::new(), Some(cav))
                        .is_some()
                    {
                        self.report.interior += 1;
                        // The cell itself may have stayed out of the
                        // cavity (a subface between it and its
                        // circumcentre, or dropped by the cavity
                        // correction): look at it again.
                        if self.m.tv.get(b.slot as usize) == Some(&tv) {
                            self.badq.push(b);
                        }
                        return None;
                    }
                    return Some(Left::Refused);
                }
                (segs, faces)
            }
        };
        self.report.rejected += 1;
        if self.keep_surface {
            // Nothing on the surface may be split.
            return Some(Left::Surface);
        }
        // Split the encroached pieces not much smaller than the cell's
        // shortest edge.
        let segs: Vec<(u32, u32)> = segs
            .into_iter()
            .filter(|e| big || dist2(&self.pt(e.0), &self.pt(e.1)).sqrt() >= lmin)
            .collect();
        // Of the subfaces, only the one the circumcentre encroaches most
        // deeply (nearest to its circumcentre relative to its radius): a
        // circumcentre near a curved surface encroaches a fan of them
        // (thingi37322: 14 pieces for one cell), and one split usually
        // removes the cell; it is checked again afterwards.
        let depth = |k: &[u32; 3]| {
            tri_circumcenter(&self.pt(k[0]), &self.pt(k[1]), &self.pt(k[2]))
                .filter(|x| big || 2.0 * x.1.sqrt() >= lmin)
                .map(|(x, r2)| dist2(&x, &c) / r2)
        };
        let faces: Vec<[u32; 3]> = faces
            .into_iter()
            .filter_map(|k| depth(&k).map(|d| (d, k)))
            .min_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)))
            .map(|x| x.1)
            .into_iter()
            .collect();
        // No split on behalf of this cell may make an edge shorter than
        // the cell's shortest edge (Shewchuk's insertion-radius argument:
        // in a Delaunay mesh a piece encroached by the circumcentre of a
        // cell of radius-edge ratio B is split at a point whose nearest
        // vertex is at least the cell's circumradius / sqrt 2 away, i.e.
        // its shortest edge for B = sqrt 2). Closer means the circumball
        // reaches round a constraint or a small input angle: the split
        // would start a cascade of ever shorter edges (before this rule,
        // 2-6x the points on curved and sharp models, and more bad cells
        // left, not fewer). The cell is left instead. (A cell only too big
        // is split regardless: volume and sizing bounds are the user's.)
        // Cells with two or more faces on the surface follow the rule too:
        // exempting them makes 3-10% more points on the spiky
        // and curved models and lowers the optimised minimum dihedral
        // angle on cgal_eight (18.7° → 12.7°) and cgal_helmet (16.4° →
        // 12.4°); the optimiser copes with the cells left.
        if !big && quality::radius_edge_ratio(&p) > self.bound {
            self.min_ir = lmin;
        }
        let mut progress = false;
        let mut radius = false;
        for e in segs {
            if !self.out_of_budget() {
                progress |= self.split_segment(e);
                radius |= self.ir_refused;
            }
        }
        for k in faces {
            if !self.out_of_budget() {
                progress |= self.split_face(k);
                radius |= self.ir_refused;
            }
        }
        self.min_ir = 0.0;
        if progress {
            self.badq.push(b);
            None
        } else if radius {
            Some(Left::Radius)
        } else {
            Some(Left::Small)
        }
    }

    /// Records that R3 leaves bad cell `tv`, and why (the skip counters).
    fn leave(&mut self, tv: [u32; 4], why: Left) {
        let r = &mut self.report;
        r.skipped += 1;
        match why {
            Left::Flat => r.skipped_flat += 1,
            Left::Behind => r.skipped_behind += 1,
            Left::Refused => r.skipped_refused += 1,
            Left::Surface => r.skipped_surface += 1,
            _ => r.skipped_small += 1,
        }
        match why {
            Left::Close => r.skipped_close += 1,
            Left::Wedge => r.skipped_wedge += 1,
            Left::Radius => r.skipped_radius += 1,
            Left::Degenerate => r.skipped_degenerate += 1,
            Left::Shell => r.skipped_shell += 1,
            _ => {}
        }
        if self.diagnostics {
            self.left.insert(tv, why);
        }
    }

    /// The opening angle between input triangles `a` and `b` sharing an
    /// edge, as `(d, n)` with `d / n` its cosine (`n > 0`): the angle
    /// between the half-planes bounded by the shared edge (the dihedral
    /// angle, measured from the edge towards each centroid without the
    /// component along the edge; independent of the triangles'
    /// orientation, as a PLC's facets come in any). `None` unless they
    /// share an edge.
    fn opening(&self, a: u32, b: u32) -> Option<(f64, f64)> {
        let (ta, tb) = (self.tris[a as usize], self.tris[b as usize]);
        let mut shared = ta.iter().copied().filter(|q| tb.contains(q));
        let (Some(s0), Some(s1)) = (shared.next(), shared.next()) else {
            return None;
        };
        let (p0, e) = (self.pt(s0), sub(&self.pt(s1), &self.pt(s0)));
        let dir = |tr: [u32; 3]| -> P {
            let c: P = std::array::from_fn(|k| {
                tr.iter().map(|&q| self.p[q as usize][k]).sum::<f64>() / 3.0
            });
            let d = sub(&c, &p0);
            let f = dot(&d, &e) / dot(&e, &e);
            std::array::from_fn(|k| d[k] - f * e[k])
        };
        let (da, db) = (dir(ta), dir(tb));
        let den = (dot(&da, &da) * dot(&db, &db)).sqrt();
        (den > 0.0).then_some((dot(&da, &db), den))
    }

    /// The smallest angle (radians) of input triangle `t`.
    fn tri_min_angle(&self, t: u32) -> f64 {
        let [a, b, c] = self.tris[t as usize].map(|q| self.pt(q));
        angle(&a, &b, &c)
            .min(angle(&b, &c, &a))
            .min(angle(&c, &a, &b))
    }

    /// Is a vertex of `tv` on an input triangle with an angle below
    /// [`NEEDLE_ANGLE`], and is one on two input triangles sharing an edge
    /// at an angle below [`SHARP_ANGLE`]?
    fn near_features(&self, tv: [u32; 4]) -> (bool, bool) {
        let (mut needle, mut sharp) = (false, false);
        let (na, sa) = (NEEDLE_ANGLE.to_radians(), SHARP_ANGLE.to_radians().cos());
        for &q in &tv {
            let Some(l) = self.vtris.get(q as usize) else {
                continue;
            };
            needle |= l.iter().any(|&t| self.tri_min_angle(t) < na);
            for (i, &a) in l.iter().enumerate() {
                sharp |= l[i + 1..]
                    .iter()
                    .any(|&b| self.opening(a, b).is_some_and(|(d, n)| d > sa * n));
            }
        }
        (needle, sharp)
    }

    /// Do the four vertices of `t` lie on two input triangles of different
    /// plane groups that share an edge and meet at a dihedral angle below
    /// [`WEDGE_ANGLE`]? (Triangles sharing only a vertex are not tested:
    /// the opening angle of a fan of needles on a smooth surface is small
    /// too, and leaving cells there left thousands of bad cells.) Such a cell spans a sharp
    /// wedge of the input: its circumcentre lies beyond one of the two
    /// facets, and splitting that facet makes a narrower cell deeper in
    /// the wedge, towards its edge, forever (Shewchuk & Si's small input
    /// angles, here the dihedral ones). It is left.
    fn wedge(&self, t: [u32; 4]) -> bool {
        let tris = |q: u32| -> &[u32] { self.vtris.get(q as usize).map_or(&[], |l| l.as_slice()) };
        if t.iter().any(|&q| tris(q).is_empty()) {
            return false;
        }
        let on = |q: u32, g: u32| tris(q).iter().any(|&x| self.group[x as usize] == g);
        let lim = WEDGE_ANGLE.to_radians().cos();
        let mut cand: Vec<u32> = t.iter().flat_map(|&q| tris(q).iter().copied()).collect();
        cand.sort_unstable();
        cand.dedup();
        for (i, &a) in cand.iter().enumerate() {
            let ga = self.group[a as usize];
            for &b in &cand[i + 1..] {
                let gb = self.group[b as usize];
                if ga == gb {
                    continue;
                }
                if self.opening(a, b).is_some_and(|(d, den)| d > lim * den)
                    && t.iter().all(|&q| on(q, ga) || on(q, gb))
                {
                    return true;
                }
            }
        }
        false
    }

    /// Does vertex `q` lie on a degenerate input triangle (a sliver of zero
    /// angle)? Its subfaces are slivers too: every cell there is bad, and
    /// splitting anything for them refines the sliver's whole length down
    /// to its height. Such cells are left and the sliver is never split.
    fn on_degenerate(&self, q: u32) -> bool {
        self.vtris
            .get(q as usize)
            .is_some_and(|l| l.iter().any(|&t| self.degenerate[t as usize]))
    }

    /// Is a vertex of the tetrahedra `cav` closer than `lim` to `c`?
    fn too_close(&self, cav: &[u32], c: &P, lim: f64) -> bool {
        let l2 = lim * lim;
        cav.iter().any(|&u| {
            self.m.tv[u as usize]
                .iter()
                .any(|&q| dist2(&self.pt(q), c) < l2)
        })
    }

    /// Is subsegment `e` still encroached by a vertex next to it?
    fn seg_still_encroached(&self, e: (u32, u32)) -> bool {
        self.m.segs.contains_key(&e)
            && self.around_edge(e.0, e.1).into_iter().any(|t| {
                self.m.tv[t as usize]
                    .iter()
                    .any(|&w| w != e.0 && w != e.1 && self.seg_encroached_by(e, w))
            })
    }

    /// Is subface `k` (on an input triangle) bigger than the sizing allows?
    fn face_too_big(&self, k: [u32; 3]) -> bool {
        self.sizer
            .face(&self.pt(k[0]), &self.pt(k[1]), &self.pt(k[2]))
            && self.m.ftri.get(&k).is_some_and(|&t| t != NONE)
    }

    fn face_still_encroached(&self, k: [u32; 3]) -> bool {
        self.face_too_big(k)
            || self.m.ftri.contains_key(&k)
                && self.face_tets(k).into_iter().any(|t| {
                    self.m.tv[t as usize]
                        .iter()
                        .any(|&w| !k.contains(&w) && self.face_encroached_by(k, w))
                })
    }

    pub(super) fn run(&mut self) {
        let mut guard: usize = 0;
        let guard_max = self
            .budget
            .saturating_add(self.p.len())
            .saturating_mul(64)
            .saturating_add(1_000_000);
        loop {
            // After every split (with its table updates) and its flips.
            self.m.debug_check(&self.p, "refinement split");
            guard += 1;
            if guard.is_multiple_of(4096) {
                crate::progress::report("refining", self.p.len() as u64, None, "points");
            }
            if guard > guard_max || guard.is_multiple_of(4096) && crate::progress::stop_requested()
            {
                self.report.budget_exhausted = true;
                return;
            }
            if let Some(e) = self.segq.pop_front() {
                self.queued_s.remove(&e);
                self.asker = Asker::Segment;
                if self.seg_still_encroached(e) && !self.out_of_budget() {
                    self.split_segment(e);
                }
                continue;
            }
            if let Some(k) = self.faceq.pop_front() {
                self.queued_f.remove(&k);
                self.asker = Asker::Subface;
                if self.face_still_encroached(k) && !self.out_of_budget() {
                    self.split_face(k);
                }
                continue;
            }
            // Most queued cells are gone by the time they would be popped
            // (the cavity of a worse neighbour took them: nine in ten on
            // vtk_turbineblade at q1.5), and each pop of a stale entry
            // walks the heap's levels. Whenever the queue has doubled since
            // the last time, the entries of cells gone are dropped at once
            // (the rest pop in the same order).
            if self.badq.len() >= self.compact_at {
                let tv = &self.m.tv;
                self.badq
                    .retain(|b| tv.get(b.slot as usize) == Some(&b.verts.0));
                self.compact_at = (2 * self.badq.len()).max(COMPACT_MIN);
            }
            let Some(b) = self.badq.pop() else {
                return;
            };
            if self.out_of_budget() {
                return;
            }
            self.asker = Asker::Cell;
            self.split_cell(b);
        }
    }

    /// The output, and the domain mesh compacted to its tetrahedra's order
    /// (to continue in place: see [`super::refine_in_place`]).
    pub(super) fn finish(mut self, rec: &Recovered) -> (Refined, DomainMesh) {
        // The queues and their sets are done with: released before the
        // output is made (peak memory).
        self.badq = Heap::new();
        self.segq = VecDeque::new();
        self.faceq = VecDeque::new();
        self.queued_s = IdSet::default();
        self.queued_f = IdSet::default();
        self.failed_s = IdSet::default();
        self.failed_f = IdSet::default();
        self.vedge = IdMap::default();
        self.outside = Stamps::default();
        self.vstamp = Stamps::default();
        let unscale = 1.0 / self.s;
        let points = crate::geom::scale::unscaled_points(&rec.points, &self.p, unscale);
        self.m.compact(points.len());
        let ftri = &self.m.ftri;
        let faces = self
            .m
            .output_faces(|_, _, k| ftri.get(&k).copied().unwrap_or(NONE));
        let (tets, tet_region) = (self.m.tv.clone(), self.m.reg.clone());
        let mut regions = rec.regions.clone();
        for r in &mut regions {
            r.tets = 0;
            r.volume = 0.0;
        }
        for (t, &tv) in tets.iter().enumerate() {
            let ps = tv.map(|q| self.p[q as usize]);
            // On the scaled points (in input units for the region's sum).
            let vol = quality::volume(&ps);
            if let Some(g) = regions.get_mut(tet_region[t] as usize) {
                g.tets += 1;
                g.volume += crate::geom::scale::unscale_cubic(vol, (self.s, 1.0));
            }
            if !self.diagnostics {
                continue;
            }
            if self.sizer.cell(&ps) > 1.0 {
                self.report.remaining_too_big += 1;
            }
            let r = quality::radius_edge_ratio(&tv.map(|q| points[q as usize]));
            let mv = self.max_vol.get(self.m.reg[t] as usize).copied();
            if mv.is_some_and(|mv| vol.abs() > mv) {
                self.report.remaining_over_volume += 1;
            }
            if r > self.bound {
                self.report.remaining_bad += 1;
                if r > FLAT_RATIO {
                    self.report.flat += 1;
                }
                let on_seg = EDGES.iter().any(|&(i, j)| self.is_seg(ekey(tv[i], tv[j])));
                if self.m.mask[t] != 0 || on_seg {
                    self.report.remaining_at_boundary += 1;
                }
                let l = &mut self.report.left;
                match self.left.get(&tv) {
                    Some(Left::Flat) => l.flat += 1,
                    Some(Left::Behind) => l.behind += 1,
                    Some(Left::Close) => l.close += 1,
                    Some(Left::Radius) => l.radius += 1,
                    Some(Left::Small) => l.small += 1,
                    Some(Left::Wedge) => l.wedge += 1,
                    Some(Left::Degenerate) => l.degenerate += 1,
                    Some(Left::Shell) => l.shell += 1,
                    Some(Left::Refused) => l.refused += 1,
                    Some(Left::Surface) => l.surface += 1,
                    None => l.other += 1,
                }
                let (needle, sharp) = self.near_features(tv);
                self.report.left.near_needle += needle as usize;
                self.report.left.near_sharp += sharp as usize;
            }
        }
        let mut vertex_map = rec.mesh.vertex_map.clone();
        vertex_map.extend(vertex_map.len() as u32..points.len() as u32);
        self.inexact.sort_unstable();
        self.inexact.dedup();
        let mut report = rec.report.clone();
        report.max_deviation = self.max_dev * unscale;
        let refined = Refined {
            rec: Recovered {
                points,
                mesh: TetMesh {
                    tets,
                    neighbors: faces.neighbors,
                    vertex_map,
                    duplicates: rec.mesh.duplicates.clone(),
                    hidden: rec.mesh.hidden.clone(),
                },
                boundary: faces.boundary,
                boundary_triangle: faces.boundary_triangle,
                interior_faces: faces.interior_faces,
                interior_triangle: faces.interior_triangle,
                tet_region,
                regions,
                inexact: self.inexact,
                surface: rec.surface.clone(),
                surface_origin: rec.surface_origin.clone(),
                report,
            },
            report: self.report,
        };
        (refined, self.m)
    }
}

/// `Err` of [`Cdr::locate_on_facet`]: the subsegment in the way, or lost.
type PlanSeg = Option<(u32, u32)>;
