//! The mutable working mesh of [`super::optimize`]: flat arrays of a finished
//! domain mesh (no ghost cells: a face without neighbour is on the domain's
//! boundary, destroyed only by a boundary flip within one flat facet), the
//! protected interface faces, and the local operations — 2-3 flip,
//! multi-face removal, edge removal by a max-min dynamic programme (3-2 and
//! 4-4 flips included; on the boundary, 2-2 flips and their
//! generalisation), vertex smoothing, vertex insertion and its undo.
//!
//! Every operation is judged in floating point by [`quality`] and, before it
//! is applied, checked by exact `orient3d` on every tetrahedron it creates:
//! a result that is not strictly positive is refused and nothing changes.

use super::limits::Limits;
use crate::geom::ids::{IdMap, IdSet};
use crate::geom::vec3::{collinear, cross, dot, norm, sub};
use crate::tet::dmesh::flip::positive;
use crate::tet::dmesh::{ring, DomainMesh, RingEnd};
use crate::tet::local::{face, fkey};
use delone_predicates::orient3d;

use crate::NONE;

/// Value of `tv[0]` of a free slot.
pub(super) use crate::tet::local::DEAD;

/// Star tetrahedra whose quality is this much above the worst are left out
/// of the line search of [`Work::smooth`] (checked once at the end).
const FAR: f64 = 0.2;

/// Longest edge ring tried by [`Work::plan_edge_removal`].
pub(super) const MAX_RING: usize = 16;

/// The squared length of `a`.
#[inline(always)]
fn sq(a: [f64; 3]) -> f64 {
    dot(&a, &a)
}

/// The two faces (by opposite vertex) that meet at each edge, in
/// [`crate::tet::quality::EDGES`] order.
const EDGE_FACES: [(usize, usize); 6] = [(2, 3), (1, 3), (1, 2), (0, 3), (0, 2), (0, 1)];

/// The quality of a tetrahedron: the smallest sine of its six dihedral
/// angles (scale invariant; 0.9428 for the regular tetrahedron, near 0 for
/// slivers, needles, caps and wedges alike — an angle near 0° or near 180°),
/// or -1 when it is flat or inverted (floating point).
#[inline]
pub(super) fn quality(p: [&[f64; 3]; 4]) -> f64 {
    Moving::new([*p[0], *p[1], *p[2], *p[3]], 0).quality(p[0])
}

/// [`quality`] from [`Moving::terms`].
#[inline(always)]
fn quality_of(det: f64, n: [f64; 4], l: [f64; 6]) -> f64 {
    // One square root: the smallest `|e|² / (|N_k|² |N_l|²)` (all checked
    // before the divisions, which then run in parallel).
    let d = EDGE_FACES.map(|(k, m)| n[k] * n[m]);
    if d.iter().any(|&x| x.is_nan() || x <= 0.0) {
        return -1.0;
    }
    let q2 = (0..6).map(|i| l[i] / d[i]).fold(f64::INFINITY, f64::min);
    let q = det * q2.sqrt();
    if q.is_finite() {
        q
    } else {
        -1.0
    }
}

/// The sines of the six dihedral angles of a positive tetrahedron, at the
/// edges in [`crate::tet::quality::EDGES`] order (see [`Moving::terms`]);
/// `None` when it is flat or inverted (floating point).
pub(super) fn sines(p: [&[f64; 3]; 4]) -> Option<[f64; 6]> {
    let (det, n, l) = Moving::new([*p[0], *p[1], *p[2], *p[3]], 0).terms(p[0])?;
    let mut out = [0.0; 6];
    for (o, (len2, (k, m))) in out.iter_mut().zip(l.into_iter().zip(EDGE_FACES)) {
        let d = n[k] * n[m];
        let s = det * (len2 / d).sqrt();
        if !(d > 0.0 && s.is_finite()) {
            return None;
        }
        *o = s;
    }
    Some(out)
}

/// A tetrahedron whose vertex `k` may move, with the terms of its dihedral
/// angles that do not depend on that vertex (the squared area normal of the
/// face opposite it, the squared lengths of the three edges away from it
/// and the edge vectors of the formulas that do not involve it), computed
/// once: [`Work::smooth`] evaluates the tetrahedra of a star at many trial
/// positions of its vertex. [`quality`] and [`sines`] are the same
/// computation with vertex 0 given, so an evaluation here is theirs to the
/// bit.
#[derive(Debug, Clone, Copy)]
struct Moving {
    pts: [[f64; 3]; 4],
    k: usize,
    /// `|N_k|²`.
    nk: f64,
    /// The squared edge lengths in [`crate::tet::quality::EDGES`] order;
    /// those of the edges at `k` are unused (0).
    l: [f64; 6],
    /// The vectors of [`Moving::terms`] that do not depend on vertex `k`
    /// (`e_ij = p_j - p_i`, `c23 = e_02 × e_03`): for `k = 1` `e_02`,
    /// `e_03`, `c23`; for `k = 2` `e_01`, `e_03`, `e_13`; for `k = 3`
    /// `e_01`, `e_02`, `e_12`; unused for `k = 0`.
    c: [[f64; 3]; 3],
}

impl Moving {
    /// The tetrahedron `pts` whose vertex `k` (0 to 3) moves.
    #[inline(always)]
    fn new(pts: [[f64; 3]; 4], k: usize) -> Moving {
        let p = &pts;
        let e = |i: usize, j: usize| sq(sub(&p[j], &p[i]));
        let v = |i: usize, j: usize| sub(&p[j], &p[i]);
        let z = [0.0; 3];
        let (nk, l, c) = match k {
            0 => (
                sq(cross(&sub(&p[2], &p[1]), &sub(&p[3], &p[1]))),
                [0.0, 0.0, 0.0, e(1, 2), e(1, 3), e(2, 3)],
                [z; 3],
            ),
            1 => {
                let c23 = cross(&v(0, 2), &v(0, 3));
                (
                    sq(c23),
                    [0.0, e(0, 2), e(0, 3), 0.0, 0.0, e(2, 3)],
                    [v(0, 2), v(0, 3), c23],
                )
            }
            2 => (
                sq(cross(&sub(&p[1], &p[0]), &sub(&p[3], &p[0]))),
                [e(0, 1), 0.0, e(0, 3), 0.0, e(1, 3), 0.0],
                [v(0, 1), v(0, 3), v(1, 3)],
            ),
            _ => (
                sq(cross(&sub(&p[1], &p[0]), &sub(&p[2], &p[0]))),
                [e(0, 1), e(0, 2), 0.0, e(1, 2), 0.0, 0.0],
                [v(0, 1), v(0, 2), v(1, 2)],
            ),
        };
        Moving {
            pts,
            k: k.min(3),
            nk,
            l,
            c,
        }
    }

    /// [`quality`] with the moving vertex at `x`.
    #[inline(always)]
    fn quality(&self, x: &[f64; 3]) -> f64 {
        match self.terms(x) {
            Some((det, n, l)) => quality_of(det, n, l),
            None => -1.0,
        }
    }

    /// With the moving vertex at `x`: six times the volume, the squared
    /// area normals `|N|²` of the four faces (by opposite vertex) and the
    /// squared edge lengths (in [`crate::tet::quality::EDGES`] order; the
    /// faces at each edge are [`EDGE_FACES`]); `None` when it is flat or
    /// inverted (floating point). The dihedral sine at an edge is
    /// `6V · |e| / (|N_k| |N_l|)`. With `e_ij = p_j - p_i`: `6V = e_01 ·
    /// (e_02 × e_03)`, `N_0 = e_12 × e_13`, `N_1 = e_02 × e_03`, `N_2 =
    /// e_01 × e_03`, `N_3 = e_01 × e_02` — the same operations whichever
    /// vertex moves, those without it taken from [`Moving::c`].
    #[inline(always)]
    #[allow(clippy::type_complexity)]
    fn terms(&self, x: &[f64; 3]) -> Option<(f64, [f64; 4], [f64; 6])> {
        let p = &self.pts;
        let l = self.l;
        let [c0, c1, c2] = &self.c;
        match self.k {
            0 => {
                let e1 = sub(&p[1], x);
                let e2 = sub(&p[2], x);
                let e3 = sub(&p[3], x);
                let c23 = cross(&e2, &e3);
                let det = dot(&e1, &c23);
                if det.is_nan() || det <= 0.0 {
                    return None;
                }
                Some((
                    det,
                    [self.nk, sq(c23), sq(cross(&e1, &e3)), sq(cross(&e1, &e2))],
                    [sq(e1), sq(e2), sq(e3), l[3], l[4], l[5]],
                ))
            }
            1 => {
                // c0 = e_02, c1 = e_03, c2 = e_02 × e_03.
                let e1 = sub(x, &p[0]);
                let det = dot(&e1, c2);
                if det.is_nan() || det <= 0.0 {
                    return None;
                }
                let e12 = sub(&p[2], x);
                let e13 = sub(&p[3], x);
                Some((
                    det,
                    [
                        sq(cross(&e12, &e13)),
                        self.nk,
                        sq(cross(&e1, c1)),
                        sq(cross(&e1, c0)),
                    ],
                    [sq(e1), l[1], l[2], sq(e12), sq(e13), l[5]],
                ))
            }
            2 => {
                // c0 = e_01, c1 = e_03, c2 = e_13.
                let e2 = sub(x, &p[0]);
                let c23 = cross(&e2, c1);
                let det = dot(c0, &c23);
                if det.is_nan() || det <= 0.0 {
                    return None;
                }
                let e12 = sub(x, &p[1]);
                Some((
                    det,
                    [sq(cross(&e12, c2)), sq(c23), self.nk, sq(cross(c0, &e2))],
                    [l[0], sq(e2), l[2], sq(e12), l[4], sq(sub(&p[3], x))],
                ))
            }
            _ => {
                // c0 = e_01, c1 = e_02, c2 = e_12.
                let e3 = sub(x, &p[0]);
                let c23 = cross(c1, &e3);
                let det = dot(c0, &c23);
                if det.is_nan() || det <= 0.0 {
                    return None;
                }
                let e13 = sub(x, &p[1]);
                Some((
                    det,
                    [sq(cross(c2, &e13)), sq(c23), sq(cross(c0, &e3)), self.nk],
                    [l[0], l[1], sq(e3), l[3], sq(e13), sq(sub(x, &p[2]))],
                ))
            }
        }
    }
}

/// How a vertex may move in [`Work::smooth`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Slide {
    /// Anywhere (an interior vertex).
    Free,
    /// Never (an input point, or a surface point without a planar or
    /// straight neighbourhood).
    Fixed,
    /// Within the plane of surface triangle `[a, b, c]` (a Steiner point
    /// inside that triangle: all its surface faces lie on it).
    Plane([u32; 3]),
    /// Along the line of input edge `[a, b]` (a Steiner point on it).
    Line([u32; 2]),
}

/// A planned change: tetrahedra to remove and their replacement, with the
/// worst quality of the replacement. The planners (`Work::plan_*`) write
/// into a given plan, reusing its buffers.
#[derive(Debug, Clone, Default)]
pub(super) struct Plan {
    /// Slots removed.
    pub old: Vec<u32>,
    /// New tetrahedra.
    pub new: Vec<[u32; 4]>,
    /// The smallest quality of `new`.
    pub q: f64,
    /// Size of the edge ring (0 for a 2-3 flip, 1 for the removal of an
    /// edge on the boundary, 2 for a multi-face removal).
    pub ring: usize,
}

/// The working mesh.
#[derive(Debug, Clone)]
pub(super) struct Work {
    /// Points (rescaled coordinates).
    pub p: Vec<[f64; 3]>,
    /// The refinement's bounds that every operation keeps.
    pub limits: Limits,
    /// The constrained domain mesh (tetrahedra, neighbours, regions; the
    /// boundary and interface faces are its subfaces).
    pub m: DomainMesh,
    /// Cached [`quality`] per slot.
    pub q: Vec<f64>,
    /// Per vertex: on the boundary or an interface (never removed; moved
    /// only as its [`Slide`] allows).
    pub fixed: Vec<bool>,
    /// Per vertex: how it may move (`Free` for interior vertices).
    pub slide: Vec<Slide>,
    /// Per vertex: it already lies off its plane or line by rounding (a
    /// listed inexact Steiner point), so a move may leave it off by at most
    /// [`Work::tol`]; every other sliding vertex stays exactly on it.
    pub inexact: Vec<bool>,
    /// Largest distance (rescaled) of an inexact point to its plane or line.
    pub tol: f64,
    /// Interface faces (sorted keys): never destroyed.
    prot: IdSet<[u32; 3]>,
    /// Boundary faces (sorted keys) that may be flipped, with the index in
    /// `Recovered::surface` of the triangle each lies on (see
    /// [`Work::set_boundary`]); empty: no boundary flips.
    pub bnd: IdMap<[u32; 3], u32>,
    /// Per triangle of `Recovered::surface`: its facet (the merged coplanar
    /// group, named by `surface_origin`).
    pub facet: Vec<u32>,
    /// Boundary faces created by boundary flips (sorted keys, in order).
    pub bnd_new: Vec<[u32; 3]>,
    /// Per vertex: the [`Work::clock`] of the last change of its star
    /// (a tetrahedron created or removed, a vertex of it moved).
    pub stamp: Vec<u64>,
    /// Counts changes.
    pub clock: u64,
    /// Per vertex: the clock of its last failed smoothing (retried only
    /// once its star has changed since).
    smooth_fail: Vec<u64>,
    /// The open transaction's undo log ([`Work::begin`]).
    log: Option<Vec<Undo>>,
    /// The clock when the open transaction began.
    clock0: u64,
    /// The open transaction's vertices with their `stamp` and `smooth_fail`
    /// before it: [`Work::rollback`] restores them, so that an undone trial
    /// leaves its surroundings unchanged for [`Work::stamp`] too (else
    /// every failed trial insertion would make its neighbours' earlier
    /// failures count as stale, and they would be tried again for
    /// nothing).
    saved: Vec<(u32, u64, u64)>,
    /// Tetrahedra created, or whose shape changed, in the open
    /// transaction, with the slot each got (some may be gone since: a slot
    /// holds its tetrahedron while it reads the same vertices; one made
    /// again is listed again with its new slot).
    pub touched: Vec<(u32, [u32; 4])>,
    /// Smallest quality, before the transaction, of the tetrahedra it
    /// destroyed or reshaped.
    pub lost: f64,
    /// Settle a trial insertion fully even when its worst new tetrahedron
    /// resists the first attempt (see `try_insert_at`).
    pub thorough: bool,
    /// Set of `touched`.
    touched_set: IdSet<[u32; 4]>,
    /// Quality evaluations so far (the work measure of the effort budget;
    /// a quality known exactly from an earlier evaluation — a smoothing's
    /// accepted step, an undone move — is counted without being computed
    /// again).
    pub evals: std::cell::Cell<u64>,
    /// Of them, those spent in trial insertions that were undone.
    pub undone: u64,
    /// Slots created or reshaped since the caller last drained it.
    pub dirty: Vec<u32>,
    /// Points of the mesh before the optimisation (those at or above may
    /// be removed again).
    pub n0: usize,
    /// See [`SmoothBuf`].
    smooth_buf: SmoothBuf,
    /// The tables of the edge-removal programme
    /// ([`Work::plan_edge_removal`]), kept between calls.
    dp: std::cell::RefCell<(Vec<f64>, Vec<usize>)>,
    /// The slots and vertices of an edge ring
    /// ([`Work::plan_edge_removal`]), kept between calls.
    ring_buf: std::cell::RefCell<(Vec<u32>, Vec<u32>)>,
    /// See [`MultiFaceBuf`].
    mf_buf: std::cell::RefCell<MultiFaceBuf>,
    /// The best plan so far and the candidate of `best_flip`, kept between
    /// calls (their buffers reused).
    pub plans: std::cell::RefCell<(Plan, Plan)>,
}

/// The buffers of [`Work::plan_multi_face`], kept between calls: the ring,
/// its sides, the removed slots and the new qualities as it grows, the best
/// ring and removed slots so far, and a star walk's slots.
#[derive(Debug, Clone, Default)]
struct MultiFaceBuf {
    ring: Vec<u32>,
    side: Vec<(u32, u32, u32)>,
    old: Vec<u32>,
    q: Vec<f64>,
    best_ring: Vec<u32>,
    best_old: Vec<u32>,
    seen: Vec<u32>,
}

/// The buffers of [`Work::smooth`], kept between calls (a star's
/// tetrahedra, their points, qualities at home and at a trial position, the
/// search order, the gradients, which qualities are those at the current
/// position).
#[derive(Debug, Clone, Default)]
struct SmoothBuf {
    star: Vec<u32>,
    local: Vec<Option<Moving>>,
    qs: Vec<f64>,
    qy: Vec<f64>,
    order: Vec<usize>,
    grads: Vec<[f64; 3]>,
    fresh: Vec<bool>,
}

/// How a vertex may slide ([`Slide`]) with the points, the normal `n` of
/// its plane or the direction `u` of its line and its squared length,
/// computed once per smoothing.
#[derive(Debug, Clone, Copy)]
enum Frame {
    Free,
    Fixed,
    Plane([[f64; 3]; 3], [f64; 3], f64),
    Line([[f64; 3]; 2], [f64; 3], f64),
}

impl Frame {
    /// The part of direction `g` along which the vertex may slide.
    fn tangent(&self, g: [f64; 3]) -> [f64; 3] {
        match *self {
            Frame::Free | Frame::Fixed => g,
            Frame::Plane(_, n, nn) => {
                let s = dot(&g, &n) / nn;
                [g[0] - s * n[0], g[1] - s * n[1], g[2] - s * n[2]]
            }
            Frame::Line(_, u, uu) => {
                let s = dot(&g, &u) / uu;
                [s * u[0], s * u[1], s * u[2]]
            }
        }
    }
}

/// One undoable step of a transaction.
#[derive(Debug, Clone)]
enum Undo {
    /// `old` (of `region`) was replaced by `new`, which got `slots` (where
    /// the undo looks for them first).
    Replace {
        old: Vec<[u32; 4]>,
        new: Vec<[u32; 4]>,
        slots: Vec<u32>,
        region: u32,
    },
    /// Vertex `v` moved from `from`; its star's tetrahedra had these
    /// cached qualities there (restored by the undo, which counts them as
    /// evaluated again).
    Move {
        v: u32,
        from: [f64; 3],
        star: Vec<([u32; 4], f64)>,
    },
    /// A point was added.
    AddPoint,
}

impl Work {
    /// Works on mesh `m` (live slots only) with points `p`; `interior` are
    /// the protected interface faces (marked as subfaces, like the
    /// boundary's). Vertices of boundary and interface faces are fixed.
    pub(super) fn new(p: Vec<[f64; 3]>, mut m: DomainMesh, interior: &[[u32; 3]]) -> Work {
        let n = p.len();
        let mut fixed = vec![false; n];
        for (tv, nb) in m.tv.iter().zip(&m.nb) {
            for (f, &w) in nb.iter().enumerate() {
                if w == NONE {
                    for q in face(*tv, f) {
                        fixed[q as usize] = true;
                    }
                }
            }
        }
        for f in interior {
            for &w in f {
                fixed[w as usize] = true;
            }
        }
        let prot: IdSet<[u32; 3]> = interior.iter().map(|&f| fkey(f)).collect();
        m.mark_subfaces(&prot);
        let slide = fixed
            .iter()
            .map(|&f| if f { Slide::Fixed } else { Slide::Free })
            .collect();
        let q =
            m.tv.iter()
                .map(|tv| quality(tv.map(|w| &p[w as usize])))
                .collect();
        Work {
            p,
            limits: Limits::none(),
            m,
            q,
            fixed,
            slide,
            inexact: vec![false; n],
            tol: 0.0,
            prot,
            bnd: IdMap::default(),
            facet: Vec::new(),
            bnd_new: Vec::new(),
            stamp: vec![0; n],
            clock: 1,
            smooth_fail: vec![0; n],
            log: None,
            clock0: 0,
            saved: Vec::new(),
            touched: Vec::new(),
            lost: f64::INFINITY,
            thorough: false,
            touched_set: IdSet::default(),
            dirty: Vec::new(),
            evals: Default::default(),
            undone: 0,
            n0: n,
            smooth_buf: SmoothBuf::default(),
            dp: Default::default(),
            ring_buf: Default::default(),
            mf_buf: Default::default(),
            plans: Default::default(),
        }
    }

    /// True when slot `t` is live.
    #[inline]
    pub(super) fn live(&self, t: u32) -> bool {
        self.m.tv[t as usize][0] != DEAD
    }

    /// Quality of `tv` from the current points.
    #[inline]
    pub(super) fn qual(&self, tv: [u32; 4]) -> f64 {
        self.evals.set(self.evals.get() + 1);
        quality(tv.map(|w| &self.p[w as usize]))
    }

    /// The worst [`Limits`] excess of tetrahedra `tvs` of `region`, with
    /// vertex `at.0` (if any) placed at `at.1`.
    fn excess(&self, tvs: &[[u32; 4]], region: u32, at: Option<(u32, [f64; 3])>) -> f64 {
        let pt = |w: u32| match at {
            Some((v, x)) if v == w => x,
            _ => self.p[w as usize],
        };
        tvs.iter()
            .map(|tv| self.limits.excess(&tv.map(pt), region))
            .fold(0.0, f64::max)
    }

    /// The worst excess of live slots `slots`.
    fn slots_excess(&self, slots: &[u32]) -> f64 {
        slots
            .iter()
            .map(|&t| self.excess(&[self.m.tv[t as usize]], self.m.reg[t as usize], None))
            .fold(0.0, f64::max)
    }

    /// Exact: `tv` is strictly positive.
    #[inline]
    pub(super) fn positive(&self, tv: [u32; 4]) -> bool {
        positive(&self.p, tv)
    }

    /// True when sorted face `k` is a protected interface face.
    #[inline]
    pub(super) fn is_protected(&self, k: [u32; 3]) -> bool {
        // A protected face has three fixed vertices (cheap tests first).
        !self.prot.is_empty() && k.iter().all(|&v| self.fixed[v as usize]) && self.prot.contains(&k)
    }

    /// Marks vertex `v` as in no tetrahedron any more (after its collapse).
    pub(super) fn forget(&mut self, v: u32) {
        self.m.vt[v as usize] = DEAD;
    }

    /// The live slots containing vertex `v`.
    pub(super) fn star(&self, v: u32) -> Vec<u32> {
        self.m.star_with(v, |_, _| true)
    }

    /// The best removal of edge `a b` of slot `t`, into `out`: the
    /// triangulation of its ring maximising the smallest quality of the
    /// `2n - 4` new tetrahedra (dynamic programming over the ring, O(n³)).
    /// The ring around the edge is `[a, b, ring[i], ring[i + 1]]` for slot
    /// `i`: cyclic for an interior edge, open for an edge on the boundary
    /// (`[a, b, ring[0]]` and `[a, b, ring[last]]` boundary faces; only
    /// when [`Work::bnd`] is set). False (and `out` unspecified) when the
    /// edge cannot be removed: across an interface or region change, a
    /// ring beyond [`MAX_RING`], no valid triangulation.
    pub(super) fn plan_edge_removal(&self, t: u32, a: u32, b: u32, out: &mut Plan) -> bool {
        let mut rb = self.ring_buf.borrow_mut();
        let (tets, r) = &mut *rb;
        let Some(end) = self.m.ring_into(
            t,
            (a, b),
            (MAX_RING, !self.bnd.is_empty()),
            |c, f| self.m.open_face(c, f),
            (tets, r),
        ) else {
            return false;
        };
        let open = end == RingEnd::Open;
        let n = r.len();
        if n < 3 || open && !self.boundary_flippable(a, b, r[0], r[n - 1]) {
            return false;
        }
        // Only a result better than the worst of the ring's tetrahedra is
        // of use: sub-polygons and triangles at or below it are pruned.
        let need = self.min_q(tets).max(0.0);
        let mut dp = self.dp.borrow_mut();
        let (best, choice) = &mut *dp;
        let Some((q, new)) = ring::max_min(r, (a, b), need, (best, choice), |t| self.qual(t))
        else {
            return false;
        };
        out.old.clear();
        out.old.extend_from_slice(tets);
        out.new = new;
        out.q = q;
        out.ring = if open { 1 } else { n };
        true
    }

    /// True when the boundary faces `a b c` and `a b d` may be flipped to
    /// `c d a` and `c d b` (the removal of boundary edge `a b`): both lie
    /// on triangles of one facet, and the four points are exactly
    /// coplanar. (That the new faces cover the old ones — a convex
    /// quadrilateral — follows from the new tetrahedra being positive,
    /// checked by [`Work::apply`].)
    fn boundary_flippable(&self, a: u32, b: u32, c: u32, d: u32) -> bool {
        let tri = |f: [u32; 3]| self.bnd.get(&fkey(f)).copied();
        let (Some(t1), Some(t2)) = (tri([a, b, c]), tri([a, b, d])) else {
            return false;
        };
        let fc = |t: u32| self.facet.get(t as usize).copied();
        if t1 != t2 && (fc(t1).is_none() || fc(t1) != fc(t2)) {
            return false;
        }
        let g = |w: u32| &self.p[w as usize];
        orient3d(g(a), g(b), g(c), g(d)) == 0.0
    }

    /// The 2-3 flip of the face opposite `f` in `t`
    /// ([`DomainMesh::flip23`]) into `out`, if its new tetrahedra have
    /// positive quality (else false, `out` unspecified).
    pub(super) fn plan_flip23(&self, t: u32, f: usize, out: &mut Plan) -> bool {
        let Some((u, new)) = self.m.flip23_tets(t, f) else {
            return false;
        };
        let qm = new
            .iter()
            .map(|&n| self.qual(n))
            .fold(f64::INFINITY, f64::min);
        if qm.is_nan() || qm <= 0.0 {
            return false;
        }
        out.old.clear();
        out.old.extend([t, u]);
        out.new.clear();
        out.new.extend_from_slice(&new);
        out.q = qm;
        out.ring = 0;
        true
    }

    /// Multi-face removal (Klingner & Shewchuk 2007) from the face opposite
    /// `f` in `t`: the apexes `a` (of `t`) and `b` (across the face) and a
    /// set of faces sandwiched between them (each with a tetrahedron on `a`
    /// and one on `b`, forming a polygon of faces whose vertices are all on
    /// its boundary ring) are replaced by the tetrahedra around the new
    /// edge `a b`: `2k` tetrahedra become `k + 2`. Grown greedily from the
    /// face, each time across the ring edge of the worst new tetrahedron;
    /// the best set whose new tetrahedra beat the removed ones is planned.
    /// With one face it is the 2-3 flip (not planned here). Into `out`;
    /// false (`out` unspecified) when there is none.
    pub(super) fn plan_multi_face(&self, t: u32, f: usize, out: &mut Plan) -> bool {
        if !self.m.open_face(t, f) {
            return false;
        }
        let mut buf = self.mf_buf.borrow_mut();
        let MultiFaceBuf {
            ring,
            side,
            old,
            q,
            best_ring,
            best_old,
            seen,
        } = &mut *buf;
        let tv = self.m.tv[t as usize];
        let u = self.m.across(t, f);
        let a = tv[f];
        let Some(&b) = self.m.tv[u as usize].iter().find(|w| !tv.contains(w)) else {
            return false;
        };
        // Edge `a b` must not exist already. It cannot when it crosses the
        // face's interior (exact; `a` and `b` are on either side of it),
        // which needs no walk of the star of `a`.
        let [x, y, z] = face(tv, f);
        let g = |w: u32| &self.p[w as usize];
        let o = [(x, y), (y, z), (z, x)].map(|(c, d)| orient3d(g(a), g(b), g(c), g(d)));
        let crosses = o.iter().all(|&s| s > 0.0) || o.iter().all(|&s| s < 0.0);
        let has_b = |s: u32| self.m.tv[s as usize].contains(&b);
        if !crosses && self.m.star_first(a, seen, has_b).is_some() {
            return false;
        }
        // The ring (cyclic, `[a, b, ring[i], ring[i + 1]]` positive) and,
        // per ring edge, the removed tetrahedra on `a` and `b` at it and the
        // third vertex of its face.
        ring.clear();
        ring.extend([x, z, y]);
        side.clear();
        side.extend([(t, u, y), (t, u, x), (t, u, z)]);
        old.clear();
        old.extend([t, u]);
        q.clear();
        q.extend((0..3).map(|i| self.qual([a, b, ring[i], ring[(i + 1) % 3]])));
        let mut best: Option<f64> = None;
        loop {
            let qm = q.iter().copied().fold(f64::INFINITY, f64::min);
            if qm > self.min_q(old) && best.is_none_or(|b| qm > b) {
                best = Some(qm);
                best_ring.clone_from(ring);
                best_old.clone_from(old);
            }
            if ring.len() >= MAX_RING {
                break;
            }
            // Grow across the ring edge of the worst new tetrahedron.
            let i = (0..q.len())
                .min_by(|&i, &j| q[i].total_cmp(&q[j]).then(i.cmp(&j)))
                .unwrap_or(0);
            let j = (i + 1) % ring.len();
            let (rx, ry) = (ring[i], ring[j]);
            let (sa, sb, rz) = side[i];
            let across = |s: u32, apex: u32| -> Option<(u32, u32)> {
                let sv = self.m.tv[s as usize];
                let k = sv.iter().position(|&w| w == rz)?;
                if !self.m.open_face(s, k) {
                    return None;
                }
                let n = self.m.across(s, k);
                let w = *self.m.tv[n as usize]
                    .iter()
                    .find(|&&w| w != apex && w != rx && w != ry)?;
                Some((n, w))
            };
            let (Some((na, wa)), Some((nb, wb))) = (across(sa, a), across(sb, b)) else {
                break;
            };
            if wa != wb || wa == a || wa == b || ring.contains(&wa) {
                break;
            }
            // The face `rx ry w` between `na` and `nb` must be open too.
            let Some(k) = self.m.tv[na as usize].iter().position(|&w| w == a) else {
                return false;
            };
            if !self.m.open_face(na, k) || self.m.across(na, k) != nb {
                break;
            }
            ring.insert(i + 1, wa);
            side[i] = (na, nb, ry);
            side.insert(i + 1, (na, nb, rx));
            q[i] = self.qual([a, b, rx, wa]);
            q.insert(i + 1, self.qual([a, b, wa, ry]));
            old.push(na);
            old.push(nb);
        }
        let Some(qb) = best else {
            return false;
        };
        if best_old.len() == 2 {
            return false; // the 2-3 flip, planned on its own
        }
        let n = best_ring.len();
        out.old.clone_from(best_old);
        out.new.clear();
        out.new
            .extend((0..n).map(|i| [a, b, best_ring[i], best_ring[(i + 1) % n]]));
        out.q = qb;
        out.ring = 2;
        true
    }

    /// Smallest cached quality of `slots`.
    pub(super) fn min_q(&self, slots: &[u32]) -> f64 {
        slots
            .iter()
            .map(|&t| self.q[t as usize])
            .fold(f64::INFINITY, f64::min)
    }

    /// Records that the star of vertex `w` changed now ([`Work::stamp`]),
    /// saving its marks first when a transaction is open.
    fn mark(&mut self, w: u32) {
        self.save(w);
        self.stamp[w as usize] = self.clock;
    }

    /// Saves the marks of vertex `w` for [`Work::rollback`], the first
    /// time the open transaction changes them.
    fn save(&mut self, w: u32) {
        let (s, f) = (self.stamp[w as usize], self.smooth_fail[w as usize]);
        if self.log.is_some() && s.max(f) <= self.clock0 {
            self.saved.push((w, s, f));
        }
    }

    /// Applies `plan` if every new tetrahedron is exactly positive; returns
    /// the new slots.
    pub(super) fn apply(&mut self, plan: &Plan) -> Option<Vec<u32>> {
        if !plan.new.iter().all(|&tv| self.positive(tv)) {
            return None;
        }
        let region = self.m.reg[plan.old[0] as usize];
        if !self.limits.is_none()
            && !Limits::allows(
                self.excess(&plan.new, region, None),
                self.slots_excess(&plan.old),
            )
        {
            return None;
        }
        Some(self.replace(&plan.old, &plan.new, region))
    }

    /// Replaces slots `old` (connected, one region) by `new`, relinking by
    /// face keys.
    pub(super) fn replace(&mut self, old: &[u32], new: &[[u32; 4]], region: u32) -> Vec<u32> {
        self.clock += 1;
        if let Some(log) = &mut self.log {
            for &t in old {
                let tv = self.m.tv[t as usize];
                if !self.touched_set.contains(&tv) {
                    self.lost = self.lost.min(self.q[t as usize]);
                }
            }
            log.push(Undo::Replace {
                old: old.iter().map(|&t| self.m.tv[t as usize]).collect(),
                new: new.to_vec(),
                slots: Vec::new(),
                region,
            });
            self.touched_set.extend(new.iter().copied());
        }
        let mut ids = Vec::with_capacity(new.len());
        let left = self.m.replace(old, new, region, &mut ids);
        if let Some(log) = &mut self.log {
            if let Some(Undo::Replace { slots, .. }) = log.last_mut() {
                slots.clone_from(&ids);
            }
            self.touched
                .extend(ids.iter().copied().zip(new.iter().copied()));
        }
        self.q.resize(self.m.tv.len(), 0.0);
        for &x in &ids {
            let tv = self.m.tv[x as usize];
            self.q[x as usize] = self.qual(tv);
            for &w in &tv {
                self.mark(w);
            }
        }
        // A boundary flip (see [`Work::plan_edge_removal`]) replaces
        // boundary faces of one facet by others: they keep its triangle.
        if !left.gone.is_empty() {
            self.m.move_subfaces(&left.gone, &left.made);
            let mut tri = None;
            for k in &left.gone {
                tri = tri.or(self.bnd.remove(k));
            }
            debug_assert!(
                left.made.len() == left.gone.len() && tri.is_some(),
                "replace: unmatched"
            );
            if let Some(tri) = tri {
                for &k in &left.made {
                    self.bnd.insert(k, tri);
                    self.bnd_new.push(k);
                }
            }
        } else {
            debug_assert!(left.made.is_empty(), "replace: unmatched");
        }
        self.dirty.extend_from_slice(&ids);
        self.m.debug_check(&self.p, "optimisation replace");
        ids
    }

    /// Removes slot `t` when it is a flat tetrahedron `a b c m` with two
    /// boundary faces, `a b c` on a surface triangle and `b c m` of zero
    /// area: `m` is a Steiner point on the edge `b c`, rounded off it (a
    /// listed inexact point, within [`Work::tol`] of the line, strictly
    /// between `b` and `c`). Such a tetrahedron sits under a chord `b c`
    /// over the rounded point (the recovery removes those it makes, in
    /// `recover::carve::drop_chord_slivers`; this is a guard); its dihedral
    /// angles are 0° and 180°, and no flip, smoothing or insertion can
    /// change a tetrahedron two of whose faces are fixed. Its other faces
    /// `a b m`, `a m c` become boundary faces on the triangle of `a b c`
    /// (which they cover, up to `m`'s rounding). Outside transactions only.
    /// Returns true when it removed `t`.
    pub(super) fn drop_flat_boundary(&mut self, t: u32) -> bool {
        if self.log.is_some() || !self.live(t) {
            return false;
        }
        let tv = self.m.tv[t as usize];
        let nb = self.m.nb[t as usize];
        let open: Vec<usize> = (0..4).filter(|&f| nb[f] == NONE).collect();
        let &[f1, f2] = open.as_slice() else {
            return false;
        };
        let shared: Vec<usize> = (0..4).filter(|&k| k != f1 && k != f2).collect();
        let (b, c) = (tv[shared[0]], tv[shared[1]]);
        // `shared` names `b` and `c`, and the two faces opposite them (the
        // inner ones, which become boundary faces).
        if shared.iter().any(|&f| self.is_protected(fkey(face(tv, f)))) {
            return false;
        }
        // Face `f1` (opposite `tv[f1]`) holds `tv[f2]`, and the other way.
        for (m, fm, fa) in [(tv[f2], f1, f2), (tv[f1], f2, f1)] {
            if !self.inexact.get(m as usize).copied().unwrap_or(false) {
                continue;
            }
            let (pb, pc, pm) = (self.p[b as usize], self.p[c as usize], self.p[m as usize]);
            let e = sub(&pc, &pb);
            let l2 = dot(&e, &e);
            let u = dot(&sub(&pm, &pb), &e) / l2;
            let off = sub(&sub(&pm, &pb), &e.map(|x| x * u));
            if !(u > 0.0 && u < 1.0 && norm(&off) <= self.tol) {
                continue;
            }
            let (ka, km) = (fkey(face(tv, fa)), fkey(face(tv, fm)));
            let Some(&tri) = self.bnd.get(&ka) else {
                continue;
            };
            if !self.bnd.contains_key(&km) {
                continue;
            }
            self.clock += 1;
            self.bnd.remove(&ka);
            self.bnd.remove(&km);
            let made: Vec<[u32; 3]> = shared.iter().map(|&f| fkey(face(tv, f))).collect();
            self.m.move_subfaces(&[ka, km], &made);
            for f in shared.iter().copied() {
                // Face `f` (opposite `b` or `c`) holds `a` and `m`.
                let w = nb[f];
                let n = w >> 2;
                self.m.link(n, (w & 3) as usize, NONE);
                self.m.mask[n as usize] |= 1 << (w & 3);
                let k = fkey(face(tv, f));
                self.bnd.insert(k, tri);
                self.bnd_new.push(k);
                for &w in &face(tv, f) {
                    self.m.vt[w as usize] = n;
                    self.stamp[w as usize] = self.clock;
                }
                self.dirty.push(n);
            }
            self.m.release(t);
            self.m
                .debug_check(&self.p, "optimisation flat boundary removal");
            return true;
        }
        false
    }

    /// Moves free vertex `v` to raise the smallest quality of its star
    /// (optimisation-based smoothing: a search direction from the gradients
    /// of the near-worst tetrahedra, a backtracking line search, exact
    /// orientation of the result). Returns true when it moved.
    pub(super) fn smooth(&mut self, v: u32) -> bool {
        if self.slide[v as usize] == Slide::Fixed
            || self.smooth_fail[v as usize] > self.stamp[v as usize]
        {
            return false;
        }
        let moved = self.smooth_once(v);
        if !moved {
            self.clock += 1;
            self.save(v);
            self.smooth_fail[v as usize] = self.clock;
        }
        moved
    }

    /// [`Work::smooth`] without the memo.
    fn smooth_once(&mut self, v: u32) -> bool {
        let mut buf = std::mem::take(&mut self.smooth_buf);
        let moved = self.smooth_with(v, &mut buf);
        self.smooth_buf = buf;
        moved
    }

    /// [`Work::smooth_once`] in the buffers `buf`.
    fn smooth_with(&mut self, v: u32, buf: &mut SmoothBuf) -> bool {
        let SmoothBuf {
            star,
            local,
            qs,
            qy,
            order,
            grads,
            fresh,
        } = buf;
        self.m.star_walk(v, star, |_, _| true);
        if star.is_empty() {
            return false;
        }
        let home = self.p[v as usize];
        // Length scale: the shortest edge at v, but at least a fifth of
        // their mean (a near-duplicate neighbour, left by rounding, would
        // otherwise pin v to steps of its own tiny distance).
        let (mut len, mut sum, mut cnt) = (f64::INFINITY, 0.0, 0.0);
        for &t in star.iter() {
            for &w in &self.m.tv[t as usize] {
                if w != v {
                    let l = norm(&sub(&self.p[w as usize], &home));
                    len = len.min(l);
                    sum += l;
                    cnt += 1.0;
                }
            }
        }
        len = len.max(0.2 * sum / cnt);
        if !(len > 0.0 && len.is_finite()) {
            return false;
        }
        // Each star tetrahedron's points, with the slot of `v`: made when
        // it is first evaluated (the search leaves out those far above the
        // worst, and a search that fails never evaluates them).
        local.clear();
        local.resize(star.len(), None);
        let evals = &self.evals;
        let (tvs, pts) = (&self.m.tv, &self.p);
        let stars = &*star;
        // The quality of star tetrahedron `i` with `v` at `x` (a macro:
        // inlined where the search evaluates).
        macro_rules! at {
            ($i:expr, $x:expr) => {{
                let i: usize = $i;
                evals.set(evals.get() + 1);
                local[i]
                    .get_or_insert_with(|| {
                        let tv = tvs[stars[i] as usize];
                        let k = tv.iter().position(|&u| u == v).unwrap_or(0);
                        Moving::new(tv.map(|u| pts[u as usize]), k)
                    })
                    .quality($x)
            }};
        }
        let mut x = home;
        let frame = self.frame(v);
        // At home: the cached qualities.
        qs.clear();
        qs.extend(star.iter().map(|&t| self.q[t as usize]));
        let mut cur = qs.iter().copied().fold(f64::INFINITY, f64::min);
        let q_home = cur;
        let mut moved = false;
        let h = 1e-7 * len;
        qy.clear();
        qy.extend_from_slice(qs);
        grads.clear();
        for _ in 0..6 {
            // Gradients of the near-active tetrahedra (forward differences).
            grads.clear();
            for (i, &qi) in qs.iter().enumerate() {
                if qi > cur + 1e-3 {
                    continue;
                }
                let mut g = [0.0; 3];
                for (k, gk) in g.iter_mut().enumerate() {
                    let mut y = x;
                    y[k] += h;
                    *gk = (at!(i, &y) - qi) / h;
                }
                grads.push(frame.tangent(g));
            }
            let d = min_norm_point(grads);
            let dn = norm(&d);
            if dn.is_nan() || dn <= 0.0 || !dn.is_finite() {
                break;
            }
            // Worst first, so that a failing step is seen early.
            // The near-active ones first.
            // Those far above the worst are not evaluated during the search
            // (a step rarely changes them much); the final check does.
            order.clear();
            order.extend((0..qs.len()).filter(|&i| qs[i] <= cur + 1e-3));
            order.extend((0..qs.len()).filter(|&i| qs[i] > cur + 1e-3 && qs[i] <= cur + FAR));
            // Backtracking line search from a step of len/4.
            let mut step = 0.25 * len / dn;
            let mut accepted = false;
            'search: for _ in 0..7 {
                let y = [x[0] + step * d[0], x[1] + step * d[1], x[2] + step * d[2]];
                step *= 0.5;
                let Some(y) = self.snap(v, &frame, y) else {
                    continue 'search;
                };
                let mut m = f64::INFINITY;
                for &i in order.iter() {
                    let q = at!(i, &y);
                    if q <= cur + 1e-6 {
                        continue 'search;
                    }
                    qy[i] = q;
                    m = m.min(q);
                }
                x = y;
                std::mem::swap(qs, qy);
                fresh.clear();
                fresh.resize(qs.len(), false);
                for &i in order.iter() {
                    fresh[i] = true;
                }
                cur = m;
                accepted = true;
                break;
            }
            if !accepted {
                break;
            }
            moved = true;
        }
        // Only a worthwhile gain counts (no endless micro-moves).
        if !moved || cur < q_home + 1e-3 {
            return false;
        }
        // The whole star at the new place (those the accepted step
        // evaluated there are known: counted, not computed again).
        for (i, q) in qs.iter_mut().enumerate() {
            if fresh[i] {
                evals.set(evals.get() + 1);
            } else {
                *q = at!(i, &x);
            }
        }
        if qs.iter().any(|&q| q < q_home + 1e-3) {
            return false;
        }
        // The refinement's bounds (see `limits`): per region of the star.
        if !self.limits.is_none() {
            let (mut old, mut new) = (0.0f64, 0.0f64);
            for &t in star.iter() {
                let (tv, r) = (self.m.tv[t as usize], self.m.reg[t as usize]);
                old = old.max(self.excess(&[tv], r, None));
                new = new.max(self.excess(&[tv], r, Some((v, x))));
            }
            if !Limits::allows(new, old) {
                return false;
            }
        }
        // Exact check of the moved star.
        self.p[v as usize] = x;
        if !star.iter().all(|&t| self.positive(self.m.tv[t as usize])) {
            self.p[v as usize] = home;
            return false;
        }
        self.clock += 1;
        if let Some(log) = &mut self.log {
            for &t in star.iter() {
                let tv = self.m.tv[t as usize];
                if !self.touched_set.contains(&tv) {
                    self.lost = self.lost.min(self.q[t as usize]);
                }
            }
            log.push(Undo::Move {
                v,
                from: home,
                star: star
                    .iter()
                    .map(|&t| (self.m.tv[t as usize], self.q[t as usize]))
                    .collect(),
            });
            for &t in star.iter() {
                let tv = self.m.tv[t as usize];
                if self.touched_set.insert(tv) {
                    self.touched.push((t, tv));
                }
            }
        }
        self.dirty.extend_from_slice(star);
        for (i, &t) in star.iter().enumerate() {
            self.q[t as usize] = qs[i];
            for w in self.m.tv[t as usize] {
                self.mark(w);
            }
        }
        self.m.debug_check(&self.p, "optimisation smoothing");
        true
    }

    /// How vertex `v` may slide (see [`Frame`]).
    fn frame(&self, v: u32) -> Frame {
        let pt = |w: u32| self.p[w as usize];
        match self.slide[v as usize] {
            Slide::Free => Frame::Free,
            Slide::Fixed => Frame::Fixed,
            Slide::Plane([a, b, c]) => {
                let (pa, pb, pc) = (pt(a), pt(b), pt(c));
                let n = cross(&sub(&pb, &pa), &sub(&pc, &pa));
                let nn = dot(&n, &n);
                Frame::Plane([pa, pb, pc], n, nn)
            }
            Slide::Line([a, b]) => {
                let (pa, pb) = (pt(a), pt(b));
                let u = sub(&pb, &pa);
                let uu = dot(&u, &u);
                Frame::Line([pa, pb], u, uu)
            }
        }
    }

    /// Where vertex `v`, sliding in `frame` ([`Work::frame`]), lands when
    /// asked to move to `y`: `y` itself for a
    /// free vertex; for a sliding one, `y` projected to its plane or line
    /// and rounded, accepted only when it lies there exactly (exact
    /// `orient3d` / collinearity) or, for an already inexact point, within
    /// [`Work::tol`] of it — so the surface stays the input's as exactly as
    /// it was. `None` when refused.
    fn snap(&self, v: u32, frame: &Frame, y: [f64; 3]) -> Option<[f64; 3]> {
        let loose = self.inexact[v as usize];
        match *frame {
            Frame::Free => Some(y),
            Frame::Fixed => None,
            Frame::Plane([pa, pb, pc], n, nn) => {
                let s = dot(&n, &sub(&y, &pa)) / nn;
                let mut x = [y[0] - s * n[0], y[1] - s * n[1], y[2] - s * n[2]];
                for k in 0..3 {
                    if pa[k] == pb[k] && pb[k] == pc[k] {
                        x[k] = pa[k];
                    }
                }
                let ok = orient3d(&pa, &pb, &pc, &x) == 0.0
                    || (loose && dot(&n, &sub(&x, &pa)).abs() / nn.sqrt() <= self.tol);
                ok.then_some(x)
            }
            Frame::Line([pa, pb], u, uu) => {
                let s = dot(&u, &sub(&y, &pa)) / uu;
                let mut x = [0, 1, 2].map(|k| s.mul_add(u[k], pa[k]));
                for k in 0..3 {
                    if pa[k] == pb[k] {
                        x[k] = pa[k];
                    }
                }
                let ok = collinear(&pa, &pb, &x) || {
                    let c = cross(&u, &sub(&x, &pa));
                    loose && (dot(&c, &c) / uu).sqrt() <= self.tol
                };
                ok.then_some(x)
            }
        }
    }

    /// Inserts a new point `x` inside the cavity `cav` (live slots of one
    /// region, connected across open faces) as the cone of the cavity's
    /// boundary; `None` unless `x` sees every boundary face strictly.
    /// Returns the new vertex and slots; [`Work::undo_insert`] reverts it.
    pub(super) fn insert(&mut self, cav: &[u32], x: [f64; 3]) -> Option<(u32, Vec<u32>)> {
        let id = self.p.len() as u32;
        let mut new = Vec::new();
        for &t in cav {
            let tv = self.m.tv[t as usize];
            for f in 0..4 {
                let n = self.m.across(t, f);
                if n != NONE && cav.contains(&n) {
                    continue;
                }
                let [a, b, c] = face(tv, f);
                let g = |w: u32| &self.p[w as usize];
                if orient3d(g(a), g(b), g(c), &x) >= 0.0 {
                    return None;
                }
                new.push([a, b, c, id]);
            }
        }
        // No vertex may be swallowed (all its tetrahedra in the cavity).
        for &t in cav {
            for v in self.m.tv[t as usize] {
                if !new.iter().any(|n| n[..3].contains(&v)) {
                    return None;
                }
            }
        }
        let region = self.m.reg[cav[0] as usize];
        if !self.limits.is_none()
            && !Limits::allows(
                self.excess(&new, region, Some((id, x))),
                self.slots_excess(cav),
            )
        {
            return None;
        }
        if let Some(log) = &mut self.log {
            log.push(Undo::AddPoint);
        }
        self.p.push(x);
        self.fixed.push(false);
        self.slide.push(Slide::Free);
        self.inexact.push(false);
        self.m.vt.push(DEAD);
        self.stamp.push(0);
        self.smooth_fail.push(0);
        let ids = self.replace(cav, &new, region);
        Some((id, ids))
    }

    /// The Delaunay cavity of point `x` from slot `t`: `t` and the
    /// tetrahedra of its region, reached across open faces, whose
    /// circumsphere holds `x` (floating point; [`Work::insert`] checks the
    /// result exactly). `None` when it would exceed `max` tetrahedra.
    pub(super) fn sphere_cavity(&self, t: u32, x: [f64; 3], max: usize) -> Option<Vec<u32>> {
        let mut cav = vec![t];
        self.grow_by_spheres(&mut cav, x, max).then_some(cav)
    }

    /// Grows `cav` (in place, breadth first from its first slot) by the
    /// tetrahedra of its region, reached across open faces, whose
    /// circumsphere holds `x`. `false` when it would exceed `max`.
    fn grow_by_spheres(&self, cav: &mut Vec<u32>, x: [f64; 3], max: usize) -> bool {
        let mut i = 0;
        while i < cav.len() {
            let c = cav[i];
            i += 1;
            for f in 0..4 {
                let n = self.m.across(c, f);
                if n == NONE || cav.contains(&n) || !self.m.open_face(c, f) {
                    continue;
                }
                let p = self.m.tv[n as usize].map(|v| self.p[v as usize]);
                let Some(o) = crate::tet::quality::circumcenter(&p) else {
                    continue;
                };
                let r2 = dot(&sub(&p[0], &o), &sub(&p[0], &o));
                if dot(&sub(&x, &o), &sub(&x, &o)) < r2 {
                    if cav.len() >= max {
                        return false;
                    }
                    cav.push(n);
                }
            }
        }
        true
    }

    /// The cavity of a point `x` off slot `t` (see `try_lifted`): the
    /// slots walked through from `t` to the one holding `x`, grown by the
    /// tetrahedra whose circumsphere holds `x`, then by the neighbour
    /// behind every face that `x` does not see strictly (exact
    /// `orient3d`) until `x` sees them all. `None` when the walk or the
    /// growth needs a boundary, interface or region-changing face, or more
    /// than `max` tetrahedra.
    pub(super) fn lifted_cavity(&self, t: u32, x: [f64; 3], max: usize) -> Option<Vec<u32>> {
        // Sign of `x` against face `f` of slot `c` (positive: beyond it).
        let side = |c: u32, f: usize| {
            let [a, b, d] = face(self.m.tv[c as usize], f);
            let g = |w: u32| &self.p[w as usize];
            orient3d(g(a), g(b), g(d), &x)
        };
        let beyond = |c: u32, f: usize| side(c, f) >= 0.0;
        // The walk: across the first face `x` lies strictly beyond (a
        // visibility walk; a face strictly seen from `x` is never crossed
        // back).
        let mut cav = vec![t];
        let mut cur = t;
        loop {
            let next = (0..4).find(|&f| side(cur, f) > 0.0);
            let Some(f) = next else { break };
            if !self.m.open_face(cur, f) || cav.len() >= max {
                return None;
            }
            cur = self.m.across(cur, f);
            if cav.contains(&cur) {
                return None;
            }
            cav.push(cur);
        }
        // Delaunay growth.
        if !self.grow_by_spheres(&mut cav, x, max) {
            return None;
        }
        // Visibility closure: one pass over the growing list suffices, as a
        // face only stops being a boundary face when its neighbour joins,
        // and every joining slot is visited later in the same pass.
        let mut k = 0;
        while k < cav.len() {
            let c = cav[k];
            k += 1;
            for f in 0..4 {
                let n = self.m.across(c, f);
                if (n != NONE && cav.contains(&n)) || !beyond(c, f) {
                    continue;
                }
                if n == NONE || !self.m.open_face(c, f) || cav.len() >= max {
                    return None;
                }
                cav.push(n);
            }
        }
        Some(cav)
    }

    /// Opens a transaction: every change until [`Work::commit`] or
    /// [`Work::rollback`] is logged (no nesting).
    pub(super) fn begin(&mut self) {
        self.log = Some(Vec::new());
        self.clock0 = self.clock;
        self.saved.clear();
        self.touched.clear();
        self.touched_set.clear();
        self.lost = f64::INFINITY;
    }

    /// Keeps the transaction's changes.
    pub(super) fn commit(&mut self) {
        self.log = None;
        self.saved.clear();
        self.touched.clear();
        self.touched_set.clear();
    }

    /// The live slot holding exactly `tv`, if any: `hint` (a slot that
    /// held it, or [`NONE`]), a vertex's slot, else the first found by a
    /// walk of the star of `tv[0]`.
    pub(super) fn slot_of(&self, tv: [u32; 4], hint: u32) -> Option<u32> {
        let vt = |w: u32| self.m.vt.get(w as usize).copied().unwrap_or(DEAD);
        for h in std::iter::once(hint).chain(tv.map(vt)) {
            if self.m.tv.get(h as usize) == Some(&tv) {
                return Some(h);
            }
        }
        let mut out = Vec::with_capacity(32);
        self.m
            .star_first(tv[0], &mut out, |t| self.m.tv[t as usize] == tv)
    }

    /// The transaction's touched tetrahedra that are live, with their
    /// slots (a tetrahedron made more than once may be listed twice).
    pub(super) fn live_touched(&self) -> impl Iterator<Item = (u32, [u32; 4])> + '_ {
        let live = |&(s, tv): &(u32, [u32; 4])| self.m.tv[s as usize] == tv;
        self.touched.iter().copied().filter(live)
    }

    /// Undoes the transaction's changes, newest first.
    pub(super) fn rollback(&mut self) {
        let Some(log) = self.log.take() else {
            return;
        };
        self.touched.clear();
        self.touched_set.clear();
        for u in log.into_iter().rev() {
            match u {
                Undo::Replace {
                    old,
                    new,
                    slots,
                    region,
                } => {
                    let slots: Option<Vec<u32>> = new
                        .iter()
                        .zip(&slots)
                        .map(|(&tv, &s)| self.slot_of(tv, s))
                        .collect();
                    if let Some(slots) = slots {
                        self.replace(&slots, &old, region);
                    } else {
                        debug_assert!(false, "rollback: a tetrahedron is missing");
                    }
                }
                Undo::Move { v, from, star } => {
                    self.p[v as usize] = from;
                    // (The marks of its star are restored below.) The
                    // star is the one it had when `v` moved (every later
                    // change is undone), so are its points: the qualities
                    // it had then are its qualities now. (Usually met in
                    // the same order.)
                    for (i, t) in self.star(v).into_iter().enumerate() {
                        self.dirty.push(t);
                        let tv = self.m.tv[t as usize];
                        let known = match star.get(i) {
                            Some(&(s, q)) if s == tv => Some(q),
                            _ => star.iter().find(|x| x.0 == tv).map(|x| x.1),
                        };
                        self.q[t as usize] = match known {
                            Some(q) => {
                                self.evals.set(self.evals.get() + 1);
                                q
                            }
                            None => self.qual(tv),
                        };
                    }
                }
                Undo::AddPoint => {
                    self.p.pop();
                    self.fixed.pop();
                    self.slide.pop();
                    self.inexact.pop();
                    self.m.vt.pop();
                    self.stamp.pop();
                    self.smooth_fail.pop();
                }
            }
        }
        // The mesh is as it was: so are its vertices' marks.
        for (v, s, f) in std::mem::take(&mut self.saved) {
            if let Some(x) = self.stamp.get_mut(v as usize) {
                *x = s;
                self.smooth_fail[v as usize] = f;
            }
        }
    }
}

/// The point of least norm in the convex hull of `g` (Gilbert's
/// algorithm, a few iterations): the steepest ascent direction of the
/// minimum of the functions whose gradients these are.
fn min_norm_point(g: &[[f64; 3]]) -> [f64; 3] {
    let Some(&first) = g.first() else {
        return [0.0; 3];
    };
    let mut x = first;
    for _ in 0..32 {
        // The first gradient least along `x` (each product once).
        let mut low: Option<(f64, &[f64; 3])> = None;
        for a in g {
            let da = dot(a, &x);
            if low.is_none_or(|(b, _)| da.total_cmp(&b).is_lt()) {
                low = Some((da, a));
            }
        }
        let Some((_, &s)) = low else {
            break;
        };
        let xx = dot(&x, &x);
        if xx - dot(&s, &x) <= 1e-12 * xx {
            break;
        }
        let d = sub(&s, &x);
        let dd = dot(&d, &d);
        if dd == 0.0 {
            break;
        }
        let lam = (-dot(&x, &d) / dd).clamp(0.0, 1.0);
        x = [x[0] + lam * d[0], x[1] + lam * d[1], x[2] + lam * d[2]];
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tet::dmesh::tests::{neighbors_by_faces, octahedron_points};

    #[test]
    fn quality_of_regular_and_flat() {
        let reg = crate::geom::vec3::regular_tet();
        let want = (1.0f64 / 3.0).acos().sin();
        let q = quality([&reg[0], &reg[1], &reg[2], &reg[3]]);
        assert!((q - want).abs() < 1e-12, "{q}");
        let inv = quality([&reg[1], &reg[0], &reg[2], &reg[3]]);
        assert_eq!(inv, -1.0);
        let d = crate::tet::quality::dihedral_angles(&[reg[0], reg[1], reg[2], reg[3]]);
        let m = d
            .iter()
            .map(|a| a.to_radians().sin())
            .fold(f64::INFINITY, f64::min);
        assert!((m - q).abs() < 1e-12);
    }

    /// [`quality`] and [`sines`] as first written, each term computed from
    /// the four points: the oracles of [`Moving`], which shares them.
    #[allow(clippy::type_complexity)]
    fn terms_reference(p: [&[f64; 3]; 4]) -> Option<(f64, [f64; 4], [(f64, usize, usize); 6])> {
        let e1 = sub(p[1], p[0]);
        let e2 = sub(p[2], p[0]);
        let e3 = sub(p[3], p[0]);
        let det = dot(&e1, &cross(&e2, &e3));
        if det.is_nan() || det <= 0.0 {
            return None;
        }
        let e12 = sub(p[2], p[1]);
        let e13 = sub(p[3], p[1]);
        let sq = |a: [f64; 3]| dot(&a, &a);
        let n = [
            sq(cross(&e12, &e13)),
            sq(cross(&e2, &e3)),
            sq(cross(&e1, &e3)),
            sq(cross(&e1, &e2)),
        ];
        let l = [
            (sq(e1), 2, 3),
            (sq(e2), 1, 3),
            (sq(e3), 1, 2),
            (sq(e12), 0, 3),
            (sq(e13), 0, 2),
            (sq(sub(p[3], p[2])), 0, 1),
        ];
        Some((det, n, l))
    }

    fn quality_reference(p: [&[f64; 3]; 4]) -> f64 {
        let Some((det, n, l)) = terms_reference(p) else {
            return -1.0;
        };
        let d = l.map(|(_, k, m)| n[k] * n[m]);
        if d.iter().any(|&x| x.is_nan() || x <= 0.0) {
            return -1.0;
        }
        let q2 = (0..6).map(|i| l[i].0 / d[i]).fold(f64::INFINITY, f64::min);
        let q = det * q2.sqrt();
        if q.is_finite() {
            q
        } else {
            -1.0
        }
    }

    fn sines_reference(p: [&[f64; 3]; 4]) -> Option<[f64; 6]> {
        let (det, n, l) = terms_reference(p)?;
        let mut out = [0.0; 6];
        for (o, (len2, k, m)) in out.iter_mut().zip(l) {
            let d = n[k] * n[m];
            let s = det * (len2 / d).sqrt();
            if !(d > 0.0 && s.is_finite()) {
                return None;
            }
            *o = s;
        }
        Some(out)
    }

    /// [`quality`], [`sines`] and the smoothing's evaluations with any one
    /// vertex moved ([`Moving`], from the terms cached without it) give the
    /// bits of the reference formulas, on fair, flat, inverted, needle and
    /// sliver-like tetrahedra and at extreme scales.
    #[test]
    fn moving_vertex_quality_is_the_reference_to_the_bit() {
        // A small deterministic generator (xorshift).
        let mut s = 0x9e37_79b9_7f4a_7c15u64;
        let mut rnd = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let bits = |x: Option<[f64; 6]>| x.map(|a| a.map(f64::to_bits));
        let mut positive = 0;
        for case in 0..8000 {
            let scale = [1.0, 1e-120, 1e120, 1e-60][case % 4];
            let mut pts = [[0.0; 3]; 4];
            for p in &mut pts {
                *p = [rnd(), rnd(), rnd()].map(|x| x * scale);
            }
            match case % 5 {
                // Nearly flat: the last point close to the others' plane.
                1 => {
                    let c = [0, 1, 2].map(|k| (pts[0][k] + pts[1][k] + pts[2][k]) / 3.0);
                    pts[3] = [c[0] + 1e-9 * scale * rnd(), c[1], c[2]];
                }
                // Two points the same.
                2 => pts[2] = pts[1],
                // Needle: two points very close.
                3 => pts[1] = pts[0].map(|x| x * (1.0 + 1e-12)),
                _ => {}
            }
            let r = [&pts[0], &pts[1], &pts[2], &pts[3]];
            assert_eq!(quality(r).to_bits(), quality_reference(r).to_bits());
            assert_eq!(bits(sines(r)), bits(sines_reference(r)));
            for k in 0..4 {
                let m = Moving::new(pts, k);
                for _ in 0..3 {
                    let x = [rnd(), rnd(), rnd()].map(|v| v * scale);
                    let mut r = [&pts[0], &pts[1], &pts[2], &pts[3]];
                    r[k] = &x;
                    let want = quality_reference(r);
                    positive += usize::from(want > 0.0);
                    assert_eq!(m.quality(&x).to_bits(), want.to_bits(), "{pts:?} {k} {x:?}");
                }
                assert_eq!(m.quality(&pts[k]).to_bits(), quality_reference(r).to_bits());
            }
        }
        assert!(positive > 10000, "{positive}");
    }

    /// The octahedron `±x, ±y, ±z` as 8 tetrahedra around its centre
    /// (vertex 6), positive, with neighbours.
    fn octahedron() -> Work {
        let mut p = octahedron_points();
        p.push([0.0, 0.0, 0.0]);
        let mut tets = Vec::new();
        for x in [0, 1] {
            for y in [2, 3] {
                for z in [4, 5] {
                    let mut tv = [x, y, z, 6u32];
                    if quality(tv.map(|v| &p[v as usize])) < 0.0 {
                        tv.swap(0, 1);
                    }
                    tets.push(tv);
                }
            }
        }
        let nbs = neighbors_by_faces(&tets);
        let m = DomainMesh::from_neighbors(&tets, &nbs, &[0; 8], p.len()).unwrap();
        Work::new(p, m, &[])
    }

    #[test]
    fn sphere_cavity_and_insert_keep_every_vertex() {
        let mut w = octahedron();
        assert!((0..8).all(|t| w.positive(w.m.tv[t])));
        let x = [0.1, 0.1, 0.1];
        let t0 = (0..8u32)
            .find(|&t| {
                w.m.tv[t as usize]
                    .iter()
                    .all(|&v| [0, 2, 4, 6].contains(&v))
            })
            .unwrap();
        // The circumsphere of an octant's tetrahedron (centre at (±½, ±½,
        // ±½), radius √3/2) holds x only for the octants with at most one
        // negative coordinate: x's own and its three face neighbours.
        let cav = w.sphere_cavity(t0, x, 48).unwrap();
        assert_eq!(cav.len(), 4);
        assert_eq!(cav[0], t0);
        for &t in &cav {
            let neg = w.m.tv[t as usize]
                .iter()
                .filter(|&&v| [1, 3, 5].contains(&v))
                .count();
            assert!(neg <= 1, "{:?}", w.m.tv[t as usize]);
        }
        assert!(w.sphere_cavity(t0, x, 3).is_none());
        // The whole octahedron would swallow the centre: refused.
        let all: Vec<u32> = (0..8).collect();
        assert!(w.insert(&all, x).is_none());
        assert_eq!(w.p.len(), 7);
        // The Delaunay cavity keeps it.
        let (id, new) = w.insert(&cav, x).unwrap();
        assert_eq!(id, 7);
        assert!(new.iter().all(|&t| w.positive(w.m.tv[t as usize])));
        assert!(!w.star(6).is_empty() && !w.star(7).is_empty());
    }

    #[test]
    fn lifted_cavity_walks_to_the_point_and_is_visible_from_it() {
        let mut w = octahedron();
        let octant = |w: &Work, o: [u32; 3]| {
            (0..8u32)
                .find(|&t| o.iter().all(|v| w.m.tv[t as usize].contains(v)))
                .unwrap()
        };
        let t0 = octant(&w, [0, 2, 4]);
        // A point in the next octant: the walk reaches it, the Delaunay
        // growth adds the octants whose circumsphere holds it (x's own and
        // its three face neighbours, `t0` among them), and `x` sees every
        // face of the result.
        let x = [-0.2, 0.2, 0.2];
        let cav = w.lifted_cavity(t0, x, 48).unwrap();
        assert_eq!(cav.len(), 4);
        assert!(cav.contains(&t0) && cav.contains(&octant(&w, [1, 2, 4])));
        let (id, new) = w.insert(&cav, x).unwrap();
        assert_eq!(id, 7);
        assert!(new.iter().all(|&t| w.positive(w.m.tv[t as usize])));
        // Outside the domain: the walk meets the boundary.
        let w2 = octahedron();
        assert!(w2.lifted_cavity(t0, [2.0, 0.1, 0.1], 48).is_none());
        // Too small a limit.
        assert!(w2.lifted_cavity(t0, x, 1).is_none());
    }

    #[test]
    fn rollback_restores_the_marks_of_an_undone_insertion() {
        let mut w = octahedron();
        // A failed smoothing before the trial: its mark must survive.
        w.clock += 1;
        w.smooth_fail[6] = w.clock;
        let (stamp, fail) = (w.stamp.clone(), w.smooth_fail.clone());
        let clock = w.clock;
        w.begin();
        let cav = w.sphere_cavity(0, [0.1, 0.1, 0.1], 48).unwrap();
        w.insert(&cav, [0.1, 0.1, 0.1]).unwrap();
        w.smooth(w.p.len() as u32 - 1);
        assert!(w.stamp.iter().any(|&s| s > clock));
        w.rollback();
        assert_eq!(w.p.len(), 7);
        assert!(w.clock > clock);
        assert_eq!((w.stamp.clone(), w.smooth_fail.clone()), (stamp, fail));
        // A kept change marks its vertices.
        let octant = (0..w.m.tv.len() as u32)
            .find(|&t| w.live(t) && [0, 2, 4].iter().all(|v| w.m.tv[t as usize].contains(v)))
            .unwrap();
        let cav = w.sphere_cavity(octant, [0.1, 0.1, 0.1], 48).unwrap();
        w.begin();
        let (id, _) = w.insert(&cav, [0.1, 0.1, 0.1]).unwrap();
        w.commit();
        assert!(w.stamp[id as usize] > clock && w.stamp[6] > clock);
    }

    /// Every live slot's cached quality is, bit for bit, its quality now.
    fn cache_exact(w: &Work) -> bool {
        (0..w.m.tv.len() as u32).filter(|&t| w.live(t)).all(|t| {
            w.q[t as usize].to_bits()
                == quality(w.m.tv[t as usize].map(|v| &w.p[v as usize])).to_bits()
        })
    }

    #[test]
    fn smoothing_and_its_undo_keep_the_cached_qualities() {
        let mut w = octahedron();
        // The centre off-centre, its star's qualities cached.
        w.p[6] = [0.3, -0.2, 0.25];
        for t in 0..8 {
            w.q[t] = quality(w.m.tv[t].map(|v| &w.p[v as usize]));
        }
        assert!(cache_exact(&w));
        let q0 = w.q.clone();
        w.begin();
        let e0 = w.evals.get();
        assert!(w.smooth(6));
        assert!(cache_exact(&w));
        assert!(
            w.min_q(&(0..8).collect::<Vec<_>>()) > q0.iter().copied().fold(f64::INFINITY, f64::min)
        );
        let e1 = w.evals.get();
        assert!(e1 > e0);
        w.rollback();
        // Back where it was, with the qualities it had (its star evaluated
        // again: one evaluation per tetrahedron).
        assert_eq!(w.p[6], [0.3, -0.2, 0.25]);
        assert!(cache_exact(&w));
        assert_eq!(w.q, q0);
        assert_eq!(w.evals.get(), e1 + 8);
    }

    #[test]
    fn planners_write_the_same_plan_into_a_used_buffer() {
        let key = |p: &Plan| (p.old.clone(), p.new.clone(), p.q.to_bits(), p.ring);
        // A buffer left full of another plan.
        let mut used = Plan {
            old: vec![99; 40],
            new: vec![[7; 4]; 40],
            q: 5.0,
            ring: 9,
        };
        let mut found = [0; 3];
        let mut applications = 0;
        for centre in [[0.3, -0.2, 0.25], [0.05, 0.04, 0.03], [-0.1, 0.02, 0.07]] {
            let mut w = octahedron();
            w.p[6] = centre;
            for t in 0..8 {
                w.q[t] = quality(w.m.tv[t].map(|v| &w.p[v as usize]));
            }
            for t in 0..8u32 {
                let tv = w.m.tv[t as usize];
                for (i, j) in crate::tet::quality::EDGES {
                    let mut fresh = Plan::default();
                    let ok = w.plan_edge_removal(t, tv[i], tv[j], &mut fresh);
                    assert_eq!(ok, w.plan_edge_removal(t, tv[i], tv[j], &mut used));
                    if ok {
                        found[0] += 1;
                        assert_eq!(key(&fresh), key(&used));
                        assert_eq!(fresh.new.len(), 2 * fresh.ring - 4);
                    }
                }
                for f in 0..4 {
                    let mut fresh = Plan::default();
                    let ok = w.plan_flip23(t, f, &mut fresh);
                    assert_eq!(ok, w.plan_flip23(t, f, &mut used));
                    if ok {
                        found[1] += 1;
                        assert_eq!(key(&fresh), key(&used));
                        assert_eq!((fresh.old.len(), fresh.new.len()), (2, 3));
                    }
                    let mut fresh = Plan::default();
                    let ok = w.plan_multi_face(t, f, &mut fresh);
                    assert_eq!(ok, w.plan_multi_face(t, f, &mut used));
                    if ok {
                        found[2] += 1;
                        assert_eq!(key(&fresh), key(&used));
                    }
                }
            }
            // A 2-3 flip that applies keeps the mesh and its cached
            // qualities exact; the removal of its new edge (the 3-2 flip
            // back) is planned alike into both buffers.
            let mut p = Plan::default();
            let made = (0..8u32).find_map(|t| {
                (0..4).find_map(|f| {
                    w.plan_flip23(t, f, &mut p).then_some(())?;
                    w.apply(&p)
                })
            });
            if let Some(slots) = made {
                applications += 1;
                assert!(w.m.check(&w.p).is_ok());
                assert!(cache_exact(&w));
                let (t, tv) = (slots[0], w.m.tv[slots[0] as usize]);
                let (e, d) = (tv[2], tv[3]);
                let mut fresh = Plan::default();
                let ok = w.plan_edge_removal(t, e, d, &mut fresh);
                assert_eq!(ok, w.plan_edge_removal(t, e, d, &mut used));
                if ok {
                    found[0] += 1;
                    assert_eq!(key(&fresh), key(&used));
                    assert_eq!((fresh.old.len(), fresh.new.len()), (3, 2));
                }
            }
        }
        assert!(found[0] > 0 && found[1] > 0, "{found:?}");
        assert!(applications > 0);
    }

    #[test]
    fn min_norm_point_of_opposite_gradients() {
        let x = min_norm_point(&[[1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]]);
        assert!((x[0]).abs() < 1e-12 && (x[1] - 1.0).abs() < 1e-12);
        let y = min_norm_point(&[[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]]);
        assert!(norm(&y) < 1e-12);
    }
}
