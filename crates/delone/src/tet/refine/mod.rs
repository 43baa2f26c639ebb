//! Delaunay refinement of a recovered (conforming Delaunay) tetrahedralization.
//!
//! The input of [`refine`] is a closed triangulated surface. It is first
//! recovered by [`super::recover::recover`] without flips, so the recovered
//! mesh is the Delaunay tetrahedralization of the input points plus the
//! Steiner points, every input triangle a union of mesh faces. The
//! refinement rebuilds that Delaunay tetrahedralization with the kernel and
//! keeps three structures next to it:
//!
//! * **subsegments** — each input edge as a chain of vertices (all its
//!   points, ordered); consecutive pairs are subsegments;
//! * **subfaces** — the mesh faces whose three vertices lie on one input
//!   triangle ("facet"), keyed by sorted vertex triple. After every
//!   insertion the faces of the removed cells that are not faces of the new
//!   cells are lost; their facet is marked for a coverage check, and the
//!   new cells' faces on a facet become subfaces;
//! * **inside flags** per cell slot, updated on every insertion (a new cell
//!   inherits the flag of the old cell behind its facet opposite the new
//!   vertex, flipped when that facet is a subface).
//!
//! Rules, in priority order (Shewchuk 1998):
//!
//! 1. **R1** — a subsegment whose diametral ball strictly contains a vertex
//!    (checked on the cells around it after each insertion: in a Delaunay
//!    tetrahedralization an encroached edge or face has an encroaching
//!    vertex among its neighbours) or that went missing is split at its
//!    midpoint, or on a concentric shell (a power-of-two distance) around
//!    an input vertex at one of its ends, which stops the mutual
//!    encroachment of segments meeting at small angles;
//! 2. **R2** — an encroached subface is split at its circumcentre, unless
//!    that point encroaches a subsegment of its facet (then those are
//!    split) or lies outside the facet (the nearest subsegment is split);
//! 3. **coverage** — a facet that lost subfaces is checked (edges used once
//!    must be exactly its boundary subsegments); a hole is closed by
//!    splitting its longest edge (a subsegment, or a midpoint on the facet);
//! 4. **R3** — an inside tetrahedron with radius-edge ratio above the
//!    bound, or volume above the bound, worst first, is split at its
//!    circumcentre. The would-be cavity is computed first (exact in-sphere
//!    tests); the circumcentre is rejected when it encroaches a subsegment or
//!    subface of the cavity or would delete a subface (which is the case
//!    whenever it lies outside the domain: the cavity, grown from the bad
//!    cell, must cross the surface to reach it). The encroached boundary
//!    pieces are then split instead — but only when they are not much
//!    smaller than the bad cell's shortest edge; otherwise the cell is
//!    left as it is and counted in [`RefineReport::skipped`] (its quality is
//!    forced by a small input angle or a thin feature).
//!
//! Every queue is processed in a deterministic order (FIFO for boundary
//! pieces, worst-first with vertex ids as tie-break for cells). The
//! Steiner budget bounds the number of points, so memory stays bounded; when
//! it runs out the refinement stops and the mesh is returned with the
//! boundary still conforming ([`RefineReport::budget_exhausted`]).

#![allow(clippy::needless_range_loop)] // local facet indices address several arrays at once

mod cdr;
mod geom;

use std::collections::{BTreeSet, BinaryHeap, HashMap, HashSet, VecDeque};

use delone_predicates::insphere;

use self::geom::*;
use super::local::{DEAD, FACET, INF};
use super::quality;
use super::recover::{recover, MeshRegion, RecoverError, RecoverOptions, RecoverReport, Recovered};
use super::{Delaunay3, TetMesh};
use crate::{Inserted, NONE};

/// Options of [`refine`].
///
/// ```
/// let o = delone::tet::refine::RefineOptions::default();
/// assert_eq!(o.max_radius_edge, 2.0);
/// assert!(o.max_volume.is_none());
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct RefineOptions {
    /// Largest radius-edge ratio allowed (`-q`); default 2.0. Values below
    /// about 1.1 may not terminate before the budget; `f64::INFINITY`
    /// disables the quality rule.
    pub max_radius_edge: f64,
    /// Largest tetrahedron volume (`-a`), in the input's units; default none.
    pub max_volume: Option<f64>,
    /// Most Steiner points the refinement may add (after recovery);
    /// default 1 000 000.
    pub max_steiner: usize,
    /// Options of the recovery stage (`flips` is forced off).
    pub recover: RecoverOptions,
}

impl Default for RefineOptions {
    fn default() -> Self {
        RefineOptions {
            max_radius_edge: 2.0,
            max_volume: None,
            max_steiner: 1_000_000,
            recover: RecoverOptions::default(),
        }
    }
}

/// What [`refine`] did.
///
/// ```
/// let r = delone::tet::refine::RefineReport::default();
/// assert_eq!(r.steiner(), 0);
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RefineReport {
    /// The recovery stage's report.
    pub recover: RecoverReport,
    /// Points inserted on input edges by the refinement.
    pub on_segments: usize,
    /// Points inserted inside input triangles by the refinement.
    pub on_facets: usize,
    /// Points inserted inside the domain (circumcentres of bad cells).
    pub interior: usize,
    /// Circumcentres rejected because they encroached the boundary.
    pub rejected: usize,
    /// Bad cells left alone: splitting the boundary they encroach would
    /// have made much shorter edges (small input angles, thin features), or
    /// their circumcentre could not be placed.
    pub skipped: usize,
    /// Subsegments too short to split in floating point.
    pub unsplittable: usize,
    /// The Steiner budget ran out before every bad cell was split.
    pub budget_exhausted: bool,
    /// Output cells whose radius-edge ratio is above the bound.
    pub remaining_bad: usize,
    /// Of [`Self::remaining_bad`], the nearly flat cells whose four
    /// vertices all lie on one plane of coplanar input triangles (inexact
    /// Steiner points on that plane, a hair off it); they are not split,
    /// since their circumcentres lie far outside and splitting the boundary
    /// for them would run away.
    pub flat: usize,
}

impl RefineReport {
    /// Points inserted by the refinement (recovery's not included).
    ///
    /// ```
    /// let mut r = delone::tet::refine::RefineReport::default();
    /// r.interior = 3;
    /// r.on_facets = 1;
    /// assert_eq!(r.steiner(), 4);
    /// ```
    pub fn steiner(&self) -> usize {
        self.on_segments + self.on_facets + self.interior
    }
}

/// The result of [`refine`]: a [`Recovered`] mesh (so
/// [`super::recover::check_recovered`] applies to it) and the report.
#[derive(Debug, Clone, PartialEq)]
pub struct Refined {
    /// Points, inside tetrahedra, boundary faces with their input triangle,
    /// inexact Steiner points; `rec.report` is the recovery's report with
    /// `max_deviation` covering the refinement's points too.
    pub rec: Recovered,
    /// Counts.
    pub report: RefineReport,
}

/// Recovers the closed surface (`points`, `triangles`) and refines the
/// inside until every tetrahedron meets the bounds of `opts` (see the
/// [module documentation](self)).
///
/// # Errors
/// Every error of [`recover`]; [`RecoverError::Unrecovered`] when a facet
/// could not be covered again after a refinement step.
///
/// ```
/// use delone::tet::recover::check_recovered;
/// use delone::tet::refine::{refine, RefineOptions};
/// use delone::tet::quality::radius_edge_ratio;
/// let pts: Vec<[f64; 3]> = (0..8)
///     .map(|i| [(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64])
///     .collect();
/// let tris = [
///     [0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
///     [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5],
/// ];
/// let opts = RefineOptions { max_volume: Some(0.01), ..Default::default() };
/// let r = refine(&pts, &tris, &opts).unwrap();
/// check_recovered(&pts, &tris, &r.rec).unwrap();
/// assert!(r.rec.mesh.tets.len() >= 100);
/// for t in &r.rec.mesh.tets {
///     let p = t.map(|q| r.rec.points[q as usize]);
///     assert!(radius_edge_ratio(&p) <= 2.0 + 1e-9);
/// }
/// ```
pub fn refine(
    points: &[[f64; 3]],
    triangles: &[[u32; 3]],
    opts: &RefineOptions,
) -> Result<Refined, RecoverError> {
    let rec = recover(points, triangles, &opts.recover)?;
    refine_recovered(points, triangles, &rec, opts)
}

/// Refines a [`Recovered`] mesh of (`points`, `triangles`) made by
/// [`recover`] (best without flips: the refinement rebuilds the Delaunay
/// tetrahedralization of `rec.points`, and faces that flips made are missing
/// from it and must be recovered again by splitting).
///
/// # Errors
/// [`RecoverError::Input`] when the points cannot be tetrahedralized,
/// [`RecoverError::Unrecovered`] when a facet could not be covered.
///
/// ```
/// use delone::tet::recover::{recover, RecoverOptions};
/// use delone::tet::refine::{refine_recovered, RefineOptions};
/// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
/// let tris = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];
/// let ro = RecoverOptions { flips: false, ..Default::default() };
/// let rec = recover(&pts, &tris, &ro).unwrap();
/// let r = refine_recovered(&pts, &tris, &rec, &RefineOptions::default()).unwrap();
/// assert_eq!(r.rec.mesh.tets.len(), 1); // the regular-ish corner tet is good
/// ```
pub fn refine_recovered(
    points: &[[f64; 3]],
    triangles: &[[u32; 3]],
    rec: &Recovered,
    opts: &RefineOptions,
) -> Result<Refined, RecoverError> {
    let mut st = cdr::Cdr::new(points, triangles, rec, opts)?;
    st.run();
    st.finish(rec)
}

/// The previous (conforming, rebuild-the-Delaunay) refinement, kept for
/// comparison until the constrained one replaces it everywhere.
#[allow(dead_code)]
fn refine_recovered_old(
    points: &[[f64; 3]],
    triangles: &[[u32; 3]],
    rec: &Recovered,
    opts: &RefineOptions,
) -> Result<Refined, RecoverError> {
    if rec.regions.len() > 1 || !rec.interior_faces.is_empty() {
        return Err(RecoverError::Unsupported {
            what: "refinement of a domain with several regions or internal facets",
        });
    }
    let (cow, scale) = crate::geom::rescaled(&rec.points);
    let scaled: Vec<[f64; 3]> = cow.into_owned();
    let mut dt = Delaunay3::from_points(&scaled)?;
    dt.core.removed = Some(Vec::new());
    let s = scale.0 * scale.1;
    let mut st = State::new(points.len(), triangles, rec, &dt, s, opts);
    st.run(&mut dt);
    st.finish(&dt, points, triangles, rec, s)
}

fn fkey(mut f: [u32; 3]) -> [u32; 3] {
    f.sort_unstable();
    f
}

fn ekey(a: u32, b: u32) -> (u32, u32) {
    (a.min(b), a.max(b))
}

/// Subsegments shorter than this fraction of their input edge are not split
/// (protection against runaway refinement at small input angles).
const SEGMENT_FLOOR: f64 = 1.0 / 4096.0;

/// Radius-edge ratio above which a rejected cell counts as flat (see
/// [`State::split_cell`]).
const FLAT_RATIO: f64 = 1e6;

const TET_EDGES: [(usize, usize); 6] = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)];

/// A bad cell in the priority queue: worst first, then by vertices.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
struct Bad {
    /// Bits of a non-negative badness (monotone as an integer).
    key: u64,
    verts: std::cmp::Reverse<[u32; 4]>,
    slot: u32,
}

struct State {
    n_in: usize,
    tris: Vec<[u32; 3]>,
    /// Facets (input triangles) each vertex lies on.
    vfacets: Vec<Vec<u32>>,
    /// Input edges: ends, the two triangles, the chain of points.
    edge_tris: Vec<[u32; 2]>,
    chains: Vec<Vec<u32>>,
    tri_edges: Vec<[u32; 3]>,
    /// Plane group of each input triangle (coplanar neighbours share one).
    plane: Vec<u32>,
    subsegs: HashMap<(u32, u32), u32>,
    subfaces: HashMap<[u32; 3], u32>,
    facet_faces: Vec<BTreeSet<[u32; 3]>>,
    dirty: BTreeSet<u32>,
    inside: Vec<bool>,
    segq: VecDeque<(u32, u32)>,
    faceq: VecDeque<[u32; 3]>,
    badq: BinaryHeap<Bad>,
    bound: f64,
    max_vol: f64,
    budget: usize,
    report: RefineReport,
    inexact: Vec<u32>,
    max_dev: f64,
}

impl State {
    fn new(
        n_in: usize,
        triangles: &[[u32; 3]],
        rec: &Recovered,
        dt: &Delaunay3<'_>,
        s: f64,
        opts: &RefineOptions,
    ) -> State {
        let n = rec.points.len();
        let mut vfacets: Vec<Vec<u32>> = vec![Vec::new(); n];
        for (f, &t) in rec.boundary.iter().zip(&rec.boundary_triangle) {
            if t == NONE {
                continue;
            }
            for &q in f {
                if !vfacets[q as usize].contains(&t) {
                    vfacets[q as usize].push(t);
                }
            }
        }
        for (t, tri) in triangles.iter().enumerate() {
            for &q in tri {
                if !vfacets[q as usize].contains(&(t as u32)) {
                    vfacets[q as usize].push(t as u32);
                }
            }
        }
        for l in &mut vfacets {
            l.sort_unstable();
        }
        // Input edges and their two triangles.
        let mut emap: HashMap<(u32, u32), u32> = HashMap::new();
        let mut edge_ends: Vec<[u32; 2]> = Vec::new();
        let mut edge_tris: Vec<[u32; 2]> = Vec::new();
        let mut tri_edges = vec![[0u32; 3]; triangles.len()];
        for (t, tri) in triangles.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                let e = *emap.entry(ekey(a, b)).or_insert_with(|| {
                    edge_ends.push([a.min(b), a.max(b)]);
                    edge_tris.push([t as u32, t as u32]);
                    (edge_ends.len() - 1) as u32
                });
                edge_tris[e as usize][1] = t as u32;
                tri_edges[t][k] = e;
            }
        }
        // Chains: the points on both triangles of an edge, along the edge.
        let pts = dt.points();
        let mut on_edge: Vec<Vec<u32>> = vec![Vec::new(); edge_ends.len()];
        for (q, fs) in vfacets.iter().enumerate() {
            if fs.len() < 2 || q < n_in {
                continue;
            }
            for &t in fs {
                for &e in &tri_edges[t as usize] {
                    let [t1, t2] = edge_tris[e as usize];
                    if fs.contains(&t1)
                        && fs.contains(&t2)
                        && !on_edge[e as usize].contains(&(q as u32))
                    {
                        on_edge[e as usize].push(q as u32);
                    }
                }
            }
        }
        let mut chains = Vec::with_capacity(edge_ends.len());
        let mut subsegs = HashMap::new();
        for (e, &[a, b]) in edge_ends.iter().enumerate() {
            let (pa, pb) = (pts[a as usize], pts[b as usize]);
            let mut mid: Vec<(f64, u32)> = on_edge[e]
                .iter()
                .map(|&q| (param(&pa, &pb, &pts[q as usize]), q))
                .collect();
            mid.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
            let mut chain = vec![a];
            chain.extend(mid.iter().map(|m| m.1));
            chain.push(b);
            for w in chain.windows(2) {
                subsegs.insert(ekey(w[0], w[1]), e as u32);
            }
            chains.push(chain);
        }
        let max_vol = opts
            .max_volume
            .filter(|v| *v > 0.0)
            .map_or(f64::INFINITY, |v| v * s * s * s);
        let plane = plane_groups(&rec.points, triangles, &edge_tris, &tri_edges);
        let mut st = State {
            n_in,
            tris: triangles.to_vec(),
            vfacets,
            edge_tris,
            chains,
            plane,
            tri_edges,
            subsegs,
            subfaces: HashMap::new(),
            facet_faces: vec![BTreeSet::new(); triangles.len()],
            dirty: BTreeSet::new(),
            inside: Vec::new(),
            segq: VecDeque::new(),
            faceq: VecDeque::new(),
            badq: BinaryHeap::new(),
            bound: opts.max_radius_edge,
            max_vol,
            budget: opts.max_steiner,
            report: RefineReport {
                recover: rec.report.clone(),
                ..RefineReport::default()
            },
            inexact: rec.inexact.clone(),
            max_dev: rec.report.max_deviation * s,
        };
        st.init(dt);
        st
    }

    fn common_facet(&self, f: [u32; 3]) -> Option<u32> {
        let [a, b, c] = f.map(|q| self.vfacets.get(q as usize));
        let (a, b, c) = (a?, b?, c?);
        let mut common = a.iter().copied().filter(|t| b.contains(t) && c.contains(t));
        let first = common.next();
        // Three points of one input edge (a thin face next to an inexact
        // Steiner point on the edge): on no facet.
        match common.next() {
            Some(_) => None,
            None => first,
        }
    }

    fn add_subface(&mut self, f: [u32; 3]) {
        let k = fkey(f);
        if self.subfaces.contains_key(&k) {
            return;
        }
        if let Some(t) = self.common_facet(k) {
            self.subfaces.insert(k, t);
            self.facet_faces[t as usize].insert(k);
        }
    }

    /// Subfaces, inside flags, and the first queues.
    fn init(&mut self, dt: &Delaunay3<'_>) {
        let core = &dt.core;
        for tv in core.v.iter() {
            if tv[0] == DEAD || tv[3] == INF {
                continue;
            }
            for fv in FACET {
                self.add_subface(fv.map(|i| tv[i]));
            }
        }
        // Every facet must be covered at the start; the check runs on all.
        self.dirty = (0..self.tris.len() as u32).collect();
        self.inside = carve(core, &self.subfaces);
        for t in 0..core.v.len() {
            self.check_cell(dt, t as u32);
        }
    }

    /// Does vertex `p` lie on a facet sharing an input vertex with one of
    /// `facets`? Such a vertex encroaching a boundary piece of those facets
    /// is not acted on: near an input edge or corner where facets meet at a
    /// small angle, splitting for it would run away towards the edge. The
    /// piece is then present in the mesh all the same (a piece that goes
    /// missing is split by the coverage rule), and circumcentres that
    /// encroach it are still rejected.
    fn near_facets(&self, p: u32, facets: &[u32]) -> bool {
        let Some(pf) = self.vfacets.get(p as usize) else {
            return false;
        };
        pf.iter().any(|&a| {
            let ta = self.tris[a as usize];
            facets
                .iter()
                .any(|&b| self.tris[b as usize].iter().any(|q| ta.contains(q)))
        })
    }

    /// Do the four vertices of a cell lie on one plane of coplanar input
    /// triangles (each on a triangle of that plane)?
    fn flat_on_plane(&self, tv: [u32; 4]) -> bool {
        let groups = |q: u32| {
            self.vfacets
                .get(q as usize)
                .into_iter()
                .flatten()
                .map(|&t| self.plane[t as usize])
        };
        groups(tv[0]).any(|g| tv[1..].iter().all(|&q| groups(q).any(|h| h == g)))
    }

    /// Queues what cell `t` shows: encroached subsegments and subfaces
    /// (by its own vertices), and itself when bad.
    fn check_cell(&mut self, dt: &Delaunay3<'_>, t: u32) {
        let tv = dt.core.v[t as usize];
        if tv[0] == DEAD || tv[3] == INF {
            return;
        }
        let pts = dt.points();
        let g = |q: u32| &pts[q as usize];
        for (f, fv) in FACET.iter().enumerate() {
            let k = fkey(fv.map(|i| tv[i]));
            if let Some(&ft) = self.subfaces.get(&k) {
                if !self.near_facets(tv[f], &[ft])
                    && encroaches_face(g(k[0]), g(k[1]), g(k[2]), g(tv[f]))
                {
                    self.faceq.push_back(k);
                }
            }
        }
        for (i, j) in TET_EDGES {
            let e = ekey(tv[i], tv[j]);
            if let Some(&se) = self.subsegs.get(&e) {
                let ts = self.edge_tris[se as usize];
                let others = (0..4).filter(|&k| k != i && k != j);
                if others.into_iter().any(|k| {
                    !self.near_facets(tv[k], &ts) && encroaches_segment(g(e.0), g(e.1), g(tv[k]))
                }) {
                    self.segq.push_back(e);
                }
            }
        }
        if self.inside.get(t as usize) == Some(&true) && !self.flat_on_plane(tv) {
            let p = tv.map(|q| *g(q));
            let r = quality::radius_edge_ratio(&p);
            let v = quality::volume(&p);
            let over_q = r > self.bound;
            let over_v = v > self.max_vol;
            if over_q || over_v {
                // Quality first (ratio), then volume excess.
                let bad = if over_q {
                    1e6 + r.min(1e12)
                } else {
                    (v / self.max_vol).min(1e6)
                };
                self.badq.push(Bad {
                    key: bad.to_bits(),
                    verts: std::cmp::Reverse(tv),
                    slot: t,
                });
            }
        }
    }

    /// Updates the structures after vertex `id` was inserted.
    fn after_insert(&mut self, dt: &Delaunay3<'_>, id: u32) {
        let core = &dt.core;
        let created: Vec<u32> = core.created.clone();
        let removed: Vec<[u32; 4]> = core.removed.clone().unwrap_or_default();
        let mut cfaces: HashSet<[u32; 3]> = HashSet::new();
        let mut cedges: HashSet<(u32, u32)> = HashSet::new();
        for &n in &created {
            let tv = core.v[n as usize];
            if tv[3] == INF {
                continue;
            }
            for fv in FACET {
                cfaces.insert(fkey(fv.map(|i| tv[i])));
            }
            for (i, j) in TET_EDGES {
                cedges.insert(ekey(tv[i], tv[j]));
            }
        }
        for tv in &removed {
            if tv[3] == INF || tv[0] == DEAD {
                continue;
            }
            for fv in FACET {
                let k = fkey(fv.map(|i| tv[i]));
                if cfaces.contains(&k) {
                    continue;
                }
                if let Some(t) = self.subfaces.remove(&k) {
                    self.facet_faces[t as usize].remove(&k);
                    self.dirty.insert(t);
                }
            }
            for (i, j) in TET_EDGES {
                let e = ekey(tv[i], tv[j]);
                if !cedges.contains(&e) && self.subsegs.contains_key(&e) {
                    self.segq.push_back(e);
                }
            }
        }
        if self.inside.len() < core.v.len() {
            self.inside.resize(core.v.len(), false);
        }
        for &n in &created {
            let tv = core.v[n as usize];
            if tv[3] == INF {
                self.inside[n as usize] = false;
                continue;
            }
            for fv in FACET {
                let f = fv.map(|i| tv[i]);
                if f.contains(&id) {
                    self.add_subface(f);
                }
            }
        }
        for &n in &created {
            let tv = core.v[n as usize];
            if tv[3] == INF {
                continue;
            }
            let Some(f) = tv.iter().position(|&q| q == id) else {
                continue;
            };
            let u = (core.adj[n as usize][f] >> 2) as usize;
            let k = fkey(FACET[f].map(|i| tv[i]));
            let behind = self.inside.get(u).copied().unwrap_or(false) && core.v[u][3] != INF;
            self.inside[n as usize] = behind ^ self.subfaces.contains_key(&k);
        }
        for &n in &created {
            self.check_cell(dt, n);
        }
    }

    fn out_of_budget(&mut self) -> bool {
        if self.report.steiner() >= self.budget {
            self.report.budget_exhausted = true;
            true
        } else {
            false
        }
    }

    /// Inserts `p` (scaled coordinates); `None` for a duplicate.
    fn insert(
        &mut self,
        dt: &mut Delaunay3<'_>,
        p: [f64; 3],
        facets: Vec<u32>,
        dev: f64,
    ) -> Option<u32> {
        match dt.insert(p) {
            Ok(Inserted::Vertex(id)) => {
                if self.vfacets.len() <= id as usize {
                    self.vfacets.resize(id as usize + 1, Vec::new());
                }
                self.vfacets[id as usize] = facets;
                if dev > 0.0 {
                    self.inexact.push(id);
                    self.max_dev = self.max_dev.max(dev);
                }
                self.after_insert(dt, id);
                Some(id)
            }
            _ => None,
        }
    }

    /// Deviation to report for a point meant to be on line `a b` or plane.
    fn deviation(d: f64, p: &P) -> f64 {
        let m = p.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        d.max(m * f64::EPSILON)
    }

    /// Splits subsegment `u v` (R1). False when it is not one any more or is
    /// too short.
    fn split_segment(&mut self, dt: &mut Delaunay3<'_>, (u, v): (u32, u32)) -> bool {
        let Some(&e) = self.subsegs.get(&ekey(u, v)) else {
            return false;
        };
        let chain = &self.chains[e as usize];
        let Some(i) = chain
            .windows(2)
            .position(|w| ekey(w[0], w[1]) == ekey(u, v))
        else {
            return false;
        };
        let (u, v) = (chain[i], chain[i + 1]);
        let (a, b) = (chain[0], *chain.last().unwrap_or(&v));
        let pts = dt.points();
        let (pu, pv) = (pts[u as usize], pts[v as usize]);
        let (pa, pb) = (pts[a as usize], pts[b as usize]);
        let (su, sv) = (param(&pa, &pb, &pu), param(&pa, &pb, &pv));
        let su = if u == a { 0.0 } else { su };
        let sv = if v == b { 1.0 } else { sv };
        let len = dist2(&pa, &pb).sqrt();
        if (sv - su).abs() * len < len * SEGMENT_FLOOR {
            self.report.unsplittable += 1;
            return false;
        }
        let input = |q: u32| (q as usize) < self.n_in;
        // Concentric shells around an input vertex at one end.
        let s = match (input(u), input(v)) {
            (true, false) | (false, true) => {
                let (from_u, l) = (input(u), (sv - su) * len);
                let mut d = 2f64.powi((l * 0.5).log2().round() as i32);
                if !(d >= l / 3.0 && d <= 2.0 * l / 3.0) {
                    d = 0.5 * l;
                }
                if from_u {
                    su + d / len
                } else {
                    sv - d / len
                }
            }
            _ => 0.5 * (su + sv),
        };
        let p: P = std::array::from_fn(|k| pa[k] + s * (pb[k] - pa[k]));
        let (lo, hi) = (su.min(sv), su.max(sv));
        let sp = param(&pa, &pb, &p);
        if !(sp > lo && sp < hi) || p == pu || p == pv {
            self.report.unsplittable += 1;
            self.subsegs.remove(&ekey(u, v));
            return false;
        }
        let dev = Self::deviation(line_distance(&pa, &pb, &p), &p);
        let facets = {
            let [t1, t2] = self.edge_tris[e as usize];
            let mut f = vec![t1, t2];
            f.sort_unstable();
            f.dedup();
            f
        };
        // Chain first, so the new subfaces see the new subsegments.
        let id = dt.points().len() as u32;
        self.subsegs.remove(&ekey(u, v));
        self.subsegs.insert(ekey(u, id), e);
        self.subsegs.insert(ekey(id, v), e);
        self.chains[e as usize].insert(i + 1, id);
        if self.insert(dt, p, facets, dev).is_none() {
            self.chains[e as usize].remove(i + 1);
            self.subsegs.remove(&ekey(u, id));
            self.subsegs.remove(&ekey(id, v));
            self.subsegs.insert(ekey(u, v), e);
            self.report.unsplittable += 1;
            self.subsegs.remove(&ekey(u, v));
            return false;
        }
        self.report.on_segments += 1;
        true
    }

    /// The subsegments of facet `t`'s sides.
    fn facet_subsegs(&self, t: u32) -> Vec<(u32, u32)> {
        let mut out = Vec::new();
        for &e in &self.tri_edges[t as usize] {
            for w in self.chains[e as usize].windows(2) {
                out.push(ekey(w[0], w[1]));
            }
        }
        out
    }

    /// Inserts `x` on facet `t` unless it encroaches subsegments of `t` (they
    /// are queued) or is not strictly inside `t` (the nearest subsegment is
    /// split).
    fn insert_on_facet(&mut self, dt: &mut Delaunay3<'_>, t: u32, x: P) -> bool {
        let pts = dt.points();
        let g = |q: u32| pts[q as usize];
        let segs = self.facet_subsegs(t);
        let enc: Vec<(u32, u32)> = segs
            .iter()
            .copied()
            .filter(|&(u, v)| encroaches_segment(&g(u), &g(v), &x))
            .collect();
        if !enc.is_empty() {
            let mut progress = false;
            for e in enc {
                progress |= self.split_segment(dt, e);
            }
            return progress;
        }
        let [a, b, c] = self.tris[t as usize].map(g);
        if in_triangle(&a, &b, &c, &x) != Some(true) {
            let near = segs.iter().copied().min_by(|&(u1, v1), &(u2, v2)| {
                let m = |u: u32, v: u32| {
                    let (pu, pv) = (g(u), g(v));
                    dist2(&std::array::from_fn(|k| 0.5 * (pu[k] + pv[k])), &x)
                };
                m(u1, v1)
                    .total_cmp(&m(u2, v2))
                    .then((u1, v1).cmp(&(u2, v2)))
            });
            return near.is_some_and(|e| self.split_segment(dt, e));
        }
        // Shewchuk's rule: a facet point that encroaches (or would delete)
        // a subsegment anywhere is not inserted; the subsegment is split.
        let start = match dt.locate(&x) {
            super::Location::InTet(s) => s,
            _ => return false,
        };
        let (segs, _, _) = self.probe(dt, start, &x, Some(t));
        if !segs.is_empty() {
            let mut progress = false;
            for e in segs {
                progress |= self.split_segment(dt, e);
            }
            return progress;
        }
        let dev = Self::deviation(plane_distance(&a, &b, &c, &x), &x);
        if self.insert(dt, x, vec![t], dev).is_some() {
            self.report.on_facets += 1;
            true
        } else {
            false
        }
    }

    /// Splits subface `k` (R2).
    fn split_face(&mut self, dt: &mut Delaunay3<'_>, k: [u32; 3]) -> bool {
        let Some(&t) = self.subfaces.get(&k) else {
            return false;
        };
        let pts = dt.points();
        let [a, b, c] = k.map(|q| pts[q as usize]);
        let Some((x, _)) = tri_circumcenter(&a, &b, &c) else {
            return false;
        };
        self.insert_on_facet(dt, t, x)
    }

    /// Coverage check of facet `t`; closes a hole by one split. Returns
    /// `Some(progress)` when the facet is not covered.
    fn fix_facet(&mut self, dt: &mut Delaunay3<'_>, t: u32) -> Option<bool> {
        let mut count: HashMap<(u32, u32), u32> = HashMap::new();
        for f in &self.facet_faces[t as usize] {
            for i in 0..3 {
                *count.entry(ekey(f[i], f[(i + 1) % 3])).or_insert(0) += 1;
            }
        }
        let segs = self.facet_subsegs(t);
        let segset: HashSet<(u32, u32)> = segs.iter().copied().collect();
        let mut holes: Vec<(u32, u32)> = Vec::new();
        for &s in &segs {
            if count.get(&s) != Some(&1) {
                holes.push(s);
            }
        }
        for (&e, &c) in &count {
            if !segset.contains(&e) && c != 2 {
                holes.push(e);
            }
        }
        if holes.is_empty() {
            return None;
        }
        let pts = dt.points();
        let g = |q: u32| pts[q as usize];
        holes.sort_unstable();
        let (u, v) = *holes
            .iter()
            .max_by(|&&(a, b), &&(c, d)| {
                dist2(&g(a), &g(b))
                    .total_cmp(&dist2(&g(c), &g(d)))
                    .then((c, d).cmp(&(a, b)))
            })
            .unwrap_or(&holes[0]);
        if segset.contains(&(u, v)) {
            return Some(self.split_segment(dt, (u, v)));
        }
        let (pu, pv) = (g(u), g(v));
        let m: P = std::array::from_fn(|k| 0.5 * (pu[k] + pv[k]));
        Some(self.insert_on_facet(dt, t, m))
    }

    /// Would-be cavity of `c` grown from cell `start`, crossing only the
    /// subfaces of facet `own` (a point inserted on a facet replaces its
    /// subfaces around it). Returns the subsegments it encroaches or would
    /// delete, the subfaces of other facets it encroaches or would delete,
    /// and whether it leaks outside the domain.
    fn probe(
        &self,
        dt: &Delaunay3<'_>,
        start: u32,
        c: &P,
        own: Option<u32>,
    ) -> (Vec<(u32, u32)>, Vec<[u32; 3]>, bool) {
        let core = &dt.core;
        let pts = dt.points();
        let g = |q: u32| &pts[q as usize];
        let conflict = |t: usize| {
            let tv = core.v[t];
            tv[0] != DEAD
                && tv[3] != INF
                && insphere(g(tv[1]), g(tv[0]), g(tv[2]), g(tv[3]), c) > 0.0
        };
        let mut seen: HashSet<u32> = HashSet::new();
        let mut stack = vec![start];
        seen.insert(start);
        let mut cav = Vec::new();
        let (mut segs, mut faces, mut leak) = (Vec::new(), Vec::new(), false);
        while let Some(t) = stack.pop() {
            cav.push(t);
            let tv = core.v[t as usize];
            for f in 0..4 {
                let u = core.adj[t as usize][f] >> 2;
                let k = fkey(FACET[f].map(|i| tv[i]));
                let sub = self.subfaces.get(&k).copied();
                if sub.is_some() && sub != own {
                    if encroaches_face(g(k[0]), g(k[1]), g(k[2]), c) || conflict(u as usize) {
                        faces.push(k);
                    }
                    continue;
                }
                if seen.contains(&u) || !conflict(u as usize) {
                    continue;
                }
                if own.is_none() && !self.inside.get(u as usize).copied().unwrap_or(false) {
                    leak = true;
                    continue;
                }
                seen.insert(u);
                stack.push(u);
            }
            if cav.len() > 100_000 {
                leak = true;
                break;
            }
        }
        for &t in &cav {
            let tv = core.v[t as usize];
            for (i, j) in TET_EDGES {
                let e = ekey(tv[i], tv[j]);
                if self.subsegs.contains_key(&e)
                    && (encroaches_segment(g(e.0), g(e.1), c) || ring_inside(core, t, e, &seen))
                {
                    segs.push(e);
                }
            }
        }
        segs.sort_unstable();
        segs.dedup();
        faces.sort_unstable();
        faces.dedup();
        (segs, faces, leak)
    }

    /// R3 on cell `b`.
    fn split_cell(&mut self, dt: &mut Delaunay3<'_>, b: Bad) {
        let tv = b.verts.0;
        if dt.core.v.get(b.slot as usize) != Some(&tv) || !self.inside[b.slot as usize] {
            return;
        }
        let pts = dt.points();
        let p = tv.map(|q| pts[q as usize]);
        let Some(c) = quality::circumcenter(&p) else {
            self.report.skipped += 1;
            return;
        };
        let lmin = quality::edge_lengths(&p)
            .into_iter()
            .fold(f64::INFINITY, f64::min);
        let (segs, faces, leak) = self.probe(dt, b.slot, &c, None);
        if segs.is_empty() && faces.is_empty() {
            if leak {
                self.report.skipped += 1;
                return;
            }
            if self.insert(dt, c, Vec::new(), 0.0).is_some() {
                self.report.interior += 1;
            } else {
                self.report.skipped += 1;
            }
            return;
        }
        self.report.rejected += 1;
        if quality::radius_edge_ratio(&p) > FLAT_RATIO {
            // A nearly flat cell (four points a hair off one plane): its
            // circumcentre is far away, and splitting the boundary it
            // encroaches there would run away.
            self.report.skipped += 1;
            return;
        }
        // Split the encroached pieces that are not much smaller than the
        // cell's shortest edge.
        let g = |q: u32| pts[q as usize];
        let segs: Vec<(u32, u32)> = segs
            .into_iter()
            .filter(|e| dist2(&g(e.0), &g(e.1)).sqrt() >= lmin)
            .collect();
        let faces: Vec<[u32; 3]> = faces
            .into_iter()
            .filter(|k| {
                let r2 = tri_circumcenter(&g(k[0]), &g(k[1]), &g(k[2])).map_or(0.0, |x| x.1);
                2.0 * r2.sqrt() >= lmin
            })
            .collect();
        let mut progress = false;
        for e in segs {
            if !self.out_of_budget() {
                progress |= self.split_segment(dt, e);
            }
        }
        for k in faces {
            if !self.out_of_budget() {
                progress |= self.split_face(dt, k);
            }
        }
        if progress {
            self.badq.push(b);
        } else {
            self.report.skipped += 1;
        }
    }

    fn run(&mut self, dt: &mut Delaunay3<'_>) {
        let mut guard: usize = 0;
        let guard_max = 64 * (self.budget + dt.points().len()) + 1_000_000;
        loop {
            guard += 1;
            if guard > guard_max {
                self.report.budget_exhausted = true;
                return;
            }
            if let Some(e) = self.segq.pop_front() {
                if self.subsegs.contains_key(&e) && !self.out_of_budget() {
                    self.split_segment(dt, e);
                }
                continue;
            }
            if let Some(k) = self.faceq.pop_front() {
                if self.subfaces.contains_key(&k) && !self.out_of_budget() {
                    self.split_face(dt, k);
                }
                continue;
            }
            if let Some(&t) = self.dirty.iter().next() {
                if self.out_of_budget() {
                    return;
                }
                match self.fix_facet(dt, t) {
                    None => {
                        self.dirty.remove(&t);
                    }
                    Some(true) => {}
                    Some(false) => {
                        // No progress possible here: leave it to the final check.
                        self.dirty.remove(&t);
                    }
                }
                continue;
            }
            let Some(b) = self.badq.pop() else {
                return;
            };
            if self.out_of_budget() {
                return;
            }
            self.split_cell(dt, b);
        }
    }

    /// Carves and builds the output.
    fn finish(
        mut self,
        dt: &Delaunay3<'_>,
        input: &[[f64; 3]],
        triangles: &[[u32; 3]],
        rec: &Recovered,
        s: f64,
    ) -> Result<Refined, RecoverError> {
        // Every facet covered?
        let mut uncovered = Vec::new();
        for t in 0..triangles.len() as u32 {
            let mut count: HashMap<(u32, u32), u32> = HashMap::new();
            for f in &self.facet_faces[t as usize] {
                for i in 0..3 {
                    *count.entry(ekey(f[i], f[(i + 1) % 3])).or_insert(0) += 1;
                }
            }
            let segs: HashSet<(u32, u32)> = self.facet_subsegs(t).into_iter().collect();
            let ok = segs.iter().all(|e| count.get(e) == Some(&1))
                && count.iter().all(|(e, &c)| segs.contains(e) || c == 2);
            if !ok {
                uncovered.push(t as usize);
            }
        }
        if !uncovered.is_empty() {
            return Err(RecoverError::Unrecovered {
                triangles: uncovered,
                steiner: self.report.recover.steiner() + self.report.steiner(),
            });
        }
        let core = &dt.core;
        let inside = carve(core, &self.subfaces);
        let mut new_id = vec![NONE; core.v.len()];
        let mut tets = Vec::new();
        for (t, id) in new_id.iter_mut().enumerate() {
            if inside[t] {
                *id = tets.len() as u32;
                tets.push(core.v[t]);
            }
        }
        let mut neighbors = Vec::with_capacity(tets.len());
        let mut boundary = Vec::new();
        let mut boundary_triangle = Vec::new();
        for t in 0..core.v.len() {
            if !inside[t] {
                continue;
            }
            let tv = core.v[t];
            let mut nb = [NONE; 4];
            for (f, n) in nb.iter_mut().enumerate() {
                let u = (core.adj[t][f] >> 2) as usize;
                if inside[u] {
                    *n = new_id[u];
                } else {
                    let [x, y, z] = FACET[f].map(|i| tv[i]);
                    let face = [x, z, y];
                    boundary.push(face);
                    boundary_triangle.push(self.subfaces.get(&fkey(face)).copied().unwrap_or(NONE));
                }
            }
            neighbors.push(nb);
        }
        let pts = dt.points();
        let unscale = 1.0 / s;
        let points: Vec<[f64; 3]> = (0..pts.len())
            .map(|i| {
                if i < rec.points.len() {
                    rec.points[i]
                } else {
                    pts[i].map(|c| c * unscale)
                }
            })
            .collect();
        debug_assert!(input.len() <= rec.points.len());
        let mut vertex_map: Vec<u32> = (0..points.len() as u32).collect();
        for &(d, o) in dt.duplicates() {
            vertex_map[d as usize] = o;
        }
        // Quality count.
        for tv in &tets {
            let p = tv.map(|q| pts[q as usize]);
            if quality::radius_edge_ratio(&p) > self.bound {
                self.report.remaining_bad += 1;
                if self.flat_on_plane(*tv) {
                    self.report.flat += 1;
                }
            }
        }
        self.inexact.sort_unstable();
        self.inexact.dedup();
        let mut region = rec.regions.first().cloned().unwrap_or(MeshRegion {
            attribute: 1.0,
            max_volume: None,
            seed: None,
            exterior: false,
            tets: 0,
            volume: 0.0,
        });
        region.tets = tets.len();
        region.volume = tets
            .iter()
            .map(|tv| quality::volume(&tv.map(|q| points[q as usize])))
            .sum();
        let mut report = rec.report.clone();
        report.max_deviation = self.max_dev * unscale;
        report.hull_tets = core.finite;
        let tets_len = tets.len();
        Ok(Refined {
            rec: Recovered {
                points,
                mesh: TetMesh {
                    tets,
                    neighbors,
                    vertex_map,
                    duplicates: dt.duplicates().to_vec(),
                    hidden: Vec::new(),
                },
                boundary,
                boundary_triangle,
                interior_faces: Vec::new(),
                interior_triangle: Vec::new(),
                tet_region: vec![0; tets_len],
                regions: vec![region],
                inexact: self.inexact,
                report,
            },
            report: self.report,
        })
    }
}

/// Are all the cells around edge `e` (of cell `t`) in `set`?
fn ring_inside(core: &super::delaunay::Core, t: u32, e: (u32, u32), set: &HashSet<u32>) -> bool {
    let mut stack = vec![t];
    let mut seen: HashSet<u32> = HashSet::new();
    seen.insert(t);
    while let Some(x) = stack.pop() {
        if !set.contains(&x) {
            return false;
        }
        let tv = core.v[x as usize];
        for f in 0..4 {
            if tv[f] == e.0 || tv[f] == e.1 {
                continue;
            }
            let u = core.adj[x as usize][f] >> 2;
            if seen.insert(u) {
                if seen.len() > 10_000 {
                    return false;
                }
                stack.push(u);
            }
        }
    }
    true
}

/// Inside flags per slot: a 0-1 breadth-first search from the ghost cells
/// counting the subfaces crossed; odd counts are inside.
fn carve(core: &super::delaunay::Core, subfaces: &HashMap<[u32; 3], u32>) -> Vec<bool> {
    let n = core.v.len();
    let mut depth = vec![u32::MAX; n];
    let mut dq = VecDeque::new();
    for (t, tv) in core.v.iter().enumerate() {
        if tv[0] != DEAD && tv[3] == INF {
            depth[t] = 0;
            dq.push_back(t as u32);
        }
    }
    while let Some(t) = dq.pop_front() {
        let tv = core.v[t as usize];
        let d = depth[t as usize];
        for f in 0..4 {
            let u = (core.adj[t as usize][f] >> 2) as usize;
            let k = fkey(FACET[f].map(|i| tv[i]));
            let cost = u32::from(!k.contains(&INF) && subfaces.contains_key(&k));
            let nd = d + cost;
            if nd < depth[u] {
                depth[u] = nd;
                if cost == 0 {
                    dq.push_front(u as u32);
                } else {
                    dq.push_back(u as u32);
                }
            }
        }
    }
    core.v
        .iter()
        .zip(&depth)
        .map(|(tv, &d)| tv[0] != DEAD && tv[3] != INF && d != u32::MAX && d % 2 == 1)
        .collect()
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
    fn find(p: &mut [u32], mut x: u32) -> u32 {
        while p[x as usize] != x {
            let up = p[p[x as usize] as usize];
            p[x as usize] = up;
            x = up;
        }
        x
    }
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
                let (a, b) = (find(&mut parent, t as u32), find(&mut parent, u));
                let (lo, hi) = (a.min(b), a.max(b));
                parent[hi as usize] = lo;
            }
        }
    }
    (0..triangles.len() as u32)
        .map(|t| find(&mut parent, t))
        .collect()
}
