//! Delaunay refinement of a constrained Delaunay triangulation (Ruppert,
//! Chew, Shewchuk): Triangle's `-q` (minimum angle) and `-a` (maximum area).
//!
//! [`refine`] takes a [`Cdt`] (the output of
//! [`constrained_triangulation`](super::constrain::constrained_triangulation))
//! and inserts Steiner points until every triangle meets the bounds:
//!
//! 1. **Encroached subsegments** are split first. A subsegment is encroached
//!    when the apex of a triangle beside it lies strictly inside its
//!    diametral lens: it sees the subsegment at an angle larger than
//!    180° − 2θ for an angle bound θ ≤ 45° (Chew's and Shewchuk's lens), or
//!    larger than 90° (the diametral circle) otherwise — decided in floating
//!    point with an error bound; a tie within rounding counts as not
//!    encroached.
//!    A subsegment with exactly one end at a vertex of the input CDT is split
//!    on a *concentric shell* (at a power-of-two distance from that end, the
//!    one nearest to half its length), otherwise at its midpoint; split points
//!    are computed from the ends of the original subsegment, so they stay
//!    within a few ulps of the input segment.
//! 2. **Bad triangles** (minimum angle below the bound, or area above the
//!    global or regional bound) are taken worst first from a priority queue
//!    (ties broken by vertex ids, so the result is deterministic) and their
//!    circumcentre is inserted — unless it lies beyond a subsegment (that one is
//!    split instead) or would encroach a subsegment that would become visible
//!    from it (those are split instead; the triangle goes back in the queue).
//! 3. **Small input angles.** A skinny triangle whose shortest edge joins two
//!    vertices on two segments meeting at an input vertex at an angle
//!    smaller than the bound is left alone: its small angle is forced by the
//!    input (splitting it would only crowd the wedge). Such triangles are
//!    listed in [`RefineReport::unfixable`].
//! 4. A Steiner-point budget ([`RefineOptions::max_steiner`], Triangle's `-S`)
//!    stops the refinement; the report says whether every bound was met.
//!
//! Insertion is by Lawson flips that never flip a subsegment, so the result is
//! again a constrained Delaunay triangulation (checked by
//! [`check_cdt`](super::constrain::check_cdt)). All orientation and incircle
//! decisions use exact predicates on coordinates scaled by an exact power of
//! two.
//!
//! # References
//! J. Ruppert, *A Delaunay refinement algorithm for quality 2-dimensional mesh
//! generation*, J. Algorithms 18 (1995).
//! L. P. Chew, *Guaranteed-quality mesh generation for curved surfaces*, SoCG 1993.
//! J. R. Shewchuk, *Delaunay refinement algorithms for triangular mesh
//! generation*, Computational Geometry 22 (2002) (concentric shells, small
//! input angles).
//! A. Üngör, *Off-centers: a new type of Steiner points for computing
//! size-optimal quality-guaranteed Delaunay triangulations*, LATIN 2004.

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap, VecDeque};

use delone_predicates::{incircle, orient2d};

use super::constrain::{Cdt, Subsegment};
use super::topo::{edge, pack, unpack, NEXT, PREV};
use crate::geom::{pow2_scale, scaled};
use crate::{Error, NONE};

/// Options of [`refine`], named by meaning; each names Triangle's switch.
///
/// ```
/// use delone::tri::refine::RefineOptions;
/// let o = RefineOptions { min_angle: Some(30.0), max_area: Some(0.01), ..Default::default() };
/// assert!(!o.regional_areas);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RefineOptions {
    /// Minimum angle in degrees (Triangle's `-q`, whose default is 20).
    /// `None`: no angle bound. Values above 34 may not terminate within the
    /// budget; values are clamped to 60.
    pub min_angle: Option<f64>,
    /// Global maximum triangle area (`-a` with a number). `None`: no bound.
    pub max_area: Option<f64>,
    /// Apply the regions' area bounds ([`Cdt::max_areas`]; Triangle applies
    /// them when `-a` is given, with or without a number). Default false.
    pub regional_areas: bool,
    /// Maximum number of Steiner points to add (`-S`). `None`: no limit
    /// besides the hard cap of `u32` vertex ids.
    pub max_steiner: Option<usize>,
    /// Insert off-centres instead of circumcentres when they are nearer the
    /// shortest edge (Üngör; Triangle's default). Default true.
    pub off_centers: bool,
}

impl Default for RefineOptions {
    fn default() -> Self {
        RefineOptions {
            min_angle: Some(20.0),
            max_area: None,
            regional_areas: false,
            max_steiner: None,
            off_centers: true,
        }
    }
}

/// Why a triangle that violates a bound was left in the mesh.
///
/// ```
/// use delone::tri::refine::UnfixableReason;
/// let r = UnfixableReason::SmallInputAngle { apex: 3, input_angle: 5.0 };
/// assert!(matches!(r, UnfixableReason::SmallInputAngle { apex: 3, .. }));
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum UnfixableReason {
    /// Its shortest edge joins two segments that meet at input vertex `apex`
    /// at `input_angle` degrees, smaller than the bound.
    SmallInputAngle {
        /// The input vertex where the two segments meet (output id).
        apex: u32,
        /// The angle between the two segments, in degrees.
        input_angle: f64,
    },
    /// The Steiner-point budget ran out before it was fixed.
    SteinerLimit,
    /// Floating point could not place a Steiner point for it (a subsegment
    /// too short to split, or a circumcentre that could not be located).
    Precision,
}

/// A triangle of the output that violates a bound.
///
/// ```
/// use delone::tri::refine::{Unfixable, UnfixableReason};
/// let u = Unfixable { triangle: 0, min_angle: 10.0, area: 1.0, reason: UnfixableReason::SteinerLimit };
/// assert_eq!(u.triangle, 0);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Unfixable {
    /// The output triangle.
    pub triangle: u32,
    /// Its minimum angle in degrees.
    pub min_angle: f64,
    /// Its area.
    pub area: f64,
    /// Why it was not fixed.
    pub reason: UnfixableReason,
}

/// What [`refine`] did and what it reached.
///
/// ```
/// let r = delone::tri::refine::RefineReport::default();
/// assert_eq!(r.segment_splits + r.circumcenters, 0);
/// ```
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RefineReport {
    /// Steiner points inserted on subsegments.
    pub segment_splits: usize,
    /// Steiner points inserted at circumcentres.
    pub circumcenters: usize,
    /// Circumcentres not inserted because they encroached a subsegment or lay
    /// beyond one (a subsegment was split instead).
    pub rejected_circumcenters: usize,
    /// Edge flips done.
    pub flips: usize,
    /// The smallest angle of the output, in degrees.
    pub min_angle: f64,
    /// The largest angle of the output, in degrees.
    pub max_angle: f64,
    /// True if every triangle meets every requested bound.
    pub met: bool,
    /// True if the Steiner-point budget stopped the refinement.
    pub limit_reached: bool,
    /// The triangles that violate a bound, with the reason.
    pub unfixable: Vec<Unfixable>,
}

/// A refined mesh: the triangulation (same layout as a [`Cdt`]; its `report`
/// is the constrained triangulation's) and the refinement report.
///
/// ```
/// use delone::{model::pslg::Pslg, tri::{constrain::*, refine::*}};
/// let g = Pslg::new(vec![[0.0, 0.0], [4.0, 0.0], [4.0, 1.0], [0.0, 1.0]],
///                   vec![[0, 1], [1, 2], [2, 3], [3, 0]]);
/// let cdt = constrained_triangulation(&g, CdtOptions::default()).unwrap();
/// let r = refine(&cdt, &RefineOptions { min_angle: Some(30.0), ..Default::default() }).unwrap();
/// assert!(r.report.met && r.report.min_angle >= 30.0);
/// check_cdt(&g, &r.mesh).unwrap();
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Refined {
    /// The refined triangulation.
    pub mesh: Cdt,
    /// What was done.
    pub report: RefineReport,
}

/// A chain of subsegments between two vertices of the input CDT.
#[derive(Clone, Copy)]
struct Parent {
    /// Fixed end vertices (vertices of the input CDT).
    a: u32,
    b: u32,
    /// Index into the input `Cdt::segments`, or `NONE` for a hull edge (`-c`).
    out: u32,
}

#[derive(Clone, Copy)]
struct Sub {
    v: [u32; 2],
    /// Parameters of `v` along the parent (0 at `a`, 1 at `b`).
    t: [f64; 2],
    parent: u32,
    alive: bool,
    /// Gave up splitting it (floating point).
    stuck: bool,
}

/// Where a walk toward a point ended.
enum Walk {
    Inside(usize),
    OnEdge(usize, usize),
    Vertex,
    Blocked(u32),
    Lost,
}

struct Mesh {
    xy: Vec<[f64; 2]>,
    tv: Vec<[u32; 3]>,
    /// Packed adjacency or `NONE` on the boundary.
    ta: Vec<[u32; 3]>,
    /// Subsegment on each half-edge, or `NONE`.
    sb: Vec<[u32; 3]>,
    /// The input triangle a triangle descends from (region, attributes).
    orig: Vec<u32>,
    vt: Vec<u32>,
    /// Parent chain of a Steiner vertex on a subsegment (`NONE` otherwise).
    vpar: Vec<u32>,
    nfixed: usize,
    /// The chains (parents) each fixed vertex is an end of.
    vchains: Vec<Vec<u32>>,
    /// Squared cosine of the encroachment angle (see [`encroaches`]).
    cos2: f64,
    subs: Vec<Sub>,
    parents: Vec<Parent>,
    flips: usize,
}

/// Encroachment of `(u, v)` by `w`: `w` sees the subsegment at an angle
/// larger than the one whose squared cosine is `cos2` (0: the diametral
/// circle, 90°; more: a diametral lens), beyond rounding error.
fn encroaches(u: &[f64; 2], v: &[f64; 2], w: &[f64; 2], cos2: f64) -> bool {
    let (ax, ay) = (u[0] - w[0], u[1] - w[1]);
    let (bx, by) = (v[0] - w[0], v[1] - w[1]);
    let dot = ax * bx + ay * by;
    let err = 8.0 * f64::EPSILON * ((ax * bx).abs() + (ay * by).abs());
    dot < -err && (cos2 == 0.0 || dot * dot > cos2 * (ax * ax + ay * ay) * (bx * bx + by * by))
}

fn dist2(a: &[f64; 2], b: &[f64; 2]) -> f64 {
    (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)
}

/// Circumcentre of a triangle, computed relative to `a`.
fn circumcenter(a: &[f64; 2], b: &[f64; 2], c: &[f64; 2]) -> [f64; 2] {
    let (bx, by) = (b[0] - a[0], b[1] - a[1]);
    let (cx, cy) = (c[0] - a[0], c[1] - a[1]);
    let d = 2.0 * (bx * cy - by * cx);
    let (b2, c2) = (bx * bx + by * by, cx * cx + cy * cy);
    [
        a[0] + (cy * b2 - by * c2) / d,
        a[1] + (bx * c2 - cx * b2) / d,
    ]
}

/// (sin² of the smallest angle, doubled area, index of the shortest edge).
fn shape(a: &[f64; 2], b: &[f64; 2], c: &[f64; 2]) -> (f64, f64, usize) {
    let l = [dist2(b, c), dist2(c, a), dist2(a, b)];
    let d = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    let mut k = 0;
    for i in 1..3 {
        if l[i] < l[k] {
            k = i;
        }
    }
    let (x, y) = (l[NEXT[k]], l[PREV[k]]);
    let s2 = if x > 0.0 && y > 0.0 {
        d * d / (x * y)
    } else {
        0.0
    };
    (s2, d, k)
}

/// Angles (degrees) of a triangle.
fn angles(a: &[f64; 2], b: &[f64; 2], c: &[f64; 2]) -> [f64; 3] {
    let ang = |p: &[f64; 2], q: &[f64; 2], r: &[f64; 2]| {
        let (ux, uy) = (q[0] - p[0], q[1] - p[1]);
        let (vx, vy) = (r[0] - p[0], r[1] - p[1]);
        (ux * vy - uy * vx)
            .abs()
            .atan2(ux * vx + uy * vy)
            .to_degrees()
    };
    [ang(a, b, c), ang(b, c, a), ang(c, a, b)]
}

impl Mesh {
    #[inline]
    fn p(&self, v: u32) -> &[f64; 2] {
        &self.xy[v as usize]
    }

    fn set_vt(&mut self, t: usize) {
        for &x in &self.tv[t] {
            self.vt[x as usize] = t as u32;
        }
    }

    /// Sets the back pointer of the neighbour across edge `w` of `k`.
    fn link(&mut self, k: usize, w: usize) {
        let x = self.ta[k][w];
        if x != NONE {
            let (o, l) = unpack(x);
            self.ta[o][l] = pack(k, w);
        }
    }

    /// Triangles around `u`, starting anywhere.
    fn star(&self, u: u32) -> Vec<usize> {
        let start = self.vt[u as usize] as usize;
        let mut out = vec![start];
        // Counterclockwise.
        let mut t = start;
        let mut closed = false;
        for _ in 0..self.tv.len() {
            let k = self.tv[t].iter().position(|&x| x == u).unwrap_or(0);
            let x = self.ta[t][NEXT[k]];
            if x == NONE {
                break;
            }
            t = unpack(x).0;
            if t == start {
                closed = true;
                break;
            }
            out.push(t);
        }
        if !closed {
            let mut t = start;
            for _ in 0..self.tv.len() {
                let k = self.tv[t].iter().position(|&x| x == u).unwrap_or(0);
                let x = self.ta[t][PREV[k]];
                if x == NONE {
                    break;
                }
                t = unpack(x).0;
                out.push(t);
            }
        }
        out
    }

    /// The half-edge `u -> w` as (triangle, local edge).
    fn find_edge(&self, u: u32, w: u32) -> Option<(usize, usize)> {
        for t in self.star(u) {
            let v = self.tv[t];
            let k = v.iter().position(|&x| x == u)?;
            if v[NEXT[k]] == w {
                return Some((t, PREV[k]));
            }
        }
        None
    }

    /// The half-edge `u -> w` or `w -> u`.
    fn find_either(&self, u: u32, w: u32) -> Option<(usize, usize)> {
        self.find_edge(u, w).or_else(|| self.find_edge(w, u))
    }

    /// Flips edge `i` of `t` (strictly convex quadrilateral, unconstrained).
    fn flip(&mut self, t: usize, i: usize) {
        let (n, j) = unpack(self.ta[t][i]);
        let vt = self.tv[t];
        let vn = self.tv[n];
        let a = vt[i];
        let (x, y) = edge(&vt, i);
        let d = vn[j];
        let t_ax = (self.ta[t][PREV[i]], self.sb[t][PREV[i]]);
        let t_ya = (self.ta[t][NEXT[i]], self.sb[t][NEXT[i]]);
        let n_dy = (self.ta[n][PREV[j]], self.sb[n][PREV[j]]);
        let n_xd = (self.ta[n][NEXT[j]], self.sb[n][NEXT[j]]);
        self.tv[t] = [a, x, d];
        self.tv[n] = [d, y, a];
        self.ta[t] = [n_xd.0, pack(n, 1), t_ax.0];
        self.sb[t] = [n_xd.1, NONE, t_ax.1];
        self.ta[n] = [t_ya.0, pack(t, 1), n_dy.0];
        self.sb[n] = [t_ya.1, NONE, n_dy.1];
        for (k, w) in [(t, 0usize), (t, 2), (n, 0), (n, 2)] {
            self.link(k, w);
        }
        self.set_vt(t);
        self.set_vt(n);
        self.flips += 1;
    }

    /// Lawson flips after inserting `p`: `stack` holds the link edges
    /// `(x, y)` of `p` (triangle `[p, x, y]` counterclockwise).
    fn legalize(&mut self, p: u32, stack: &mut Vec<(u32, u32)>) {
        while let Some((x, y)) = stack.pop() {
            let Some((t, i)) = self.find_edge(x, y) else {
                continue;
            };
            if self.tv[t][i] != p || self.sb[t][i] != NONE || self.ta[t][i] == NONE {
                continue;
            }
            let (n, j) = unpack(self.ta[t][i]);
            let d = self.tv[n][j];
            let v = self.tv[t];
            if incircle(self.p(v[0]), self.p(v[1]), self.p(v[2]), self.p(d)) > 0.0 {
                self.flip(t, i);
                stack.push((x, d));
                stack.push((d, y));
            }
        }
    }

    fn new_tri(&mut self) -> usize {
        self.tv.push([0; 3]);
        self.ta.push([NONE; 3]);
        self.sb.push([NONE; 3]);
        self.orig.push(NONE);
        self.tv.len() - 1
    }

    fn new_vertex(&mut self, x: [f64; 2], t: usize, par: u32) -> u32 {
        let s = self.xy.len() as u32;
        self.xy.push(x);
        self.vt.push(t as u32);
        self.vpar.push(par);
        s
    }

    /// Splits triangle `t` at a point strictly inside it.
    fn split_tri(&mut self, t: usize, x: [f64; 2]) -> u32 {
        let [v0, v1, v2] = self.tv[t];
        let p = self.new_vertex(x, t, NONE);
        let (a0, a1, a2) = (self.ta[t][0], self.ta[t][1], self.ta[t][2]);
        let (s0, s1, s2) = (self.sb[t][0], self.sb[t][1], self.sb[t][2]);
        let t1 = self.new_tri();
        let t2 = self.new_tri();
        let o = self.orig[t];
        self.orig[t1] = o;
        self.orig[t2] = o;
        self.tv[t] = [v0, v1, p];
        self.ta[t] = [pack(t1, 1), pack(t2, 0), a2];
        self.sb[t] = [NONE, NONE, s2];
        self.tv[t1] = [v1, v2, p];
        self.ta[t1] = [pack(t2, 1), pack(t, 0), a0];
        self.sb[t1] = [NONE, NONE, s0];
        self.tv[t2] = [v2, v0, p];
        self.ta[t2] = [pack(t, 1), pack(t1, 0), a1];
        self.sb[t2] = [NONE, NONE, s1];
        for k in [t, t1, t2] {
            self.link(k, 2);
            self.set_vt(k);
        }
        let mut st = vec![(v0, v1), (v1, v2), (v2, v0)];
        self.legalize(p, &mut st);
        p
    }

    /// Whether `x` splits edge `i` of `t` (and its twin) into
    /// counterclockwise triangles.
    fn can_split(&self, t: usize, i: usize, x: &[f64; 2]) -> bool {
        let ok = |t: usize, i: usize| {
            let v = self.tv[t];
            let a = self.p(v[i]);
            let (p, q) = edge(&v, i);
            orient2d(a, self.p(p), x) > 0.0 && orient2d(a, x, self.p(q)) > 0.0
        };
        if !ok(t, i) {
            return false;
        }
        let w = self.ta[t][i];
        w == NONE || {
            let (n, j) = unpack(w);
            ok(n, j)
        }
    }

    /// Splits edge `i` of `t` at `x` (checked by [`Self::can_split`]); the two
    /// halves get labels `l1` (`p` side) and `l2` (`q` side), where `t`
    /// holds the edge as `p -> q`.
    fn split_edge(&mut self, t: usize, i: usize, x: [f64; 2], l: [u32; 2], par: u32) -> u32 {
        let w = self.ta[t][i];
        let vt = self.tv[t];
        let a = vt[i];
        let (p, q) = edge(&vt, i);
        let s = self.new_vertex(x, t, par);
        let t_ap = (self.ta[t][PREV[i]], self.sb[t][PREV[i]]);
        let t_qa = (self.ta[t][NEXT[i]], self.sb[t][NEXT[i]]);
        let t2 = self.new_tri();
        self.orig[t2] = self.orig[t];
        let mut st = vec![(a, p), (q, a)];
        if w == NONE {
            self.tv[t] = [a, p, s];
            self.ta[t] = [NONE, pack(t2, 2), t_ap.0];
            self.sb[t] = [l[0], NONE, t_ap.1];
            self.tv[t2] = [a, s, q];
            self.ta[t2] = [NONE, t_qa.0, pack(t, 1)];
            self.sb[t2] = [l[1], t_qa.1, NONE];
            self.link(t, 2);
            self.link(t2, 1);
            self.set_vt(t);
            self.set_vt(t2);
        } else {
            let (n, j) = unpack(w);
            let vn = self.tv[n];
            let d = vn[j];
            let n_pd = (self.ta[n][NEXT[j]], self.sb[n][NEXT[j]]);
            let n_dq = (self.ta[n][PREV[j]], self.sb[n][PREV[j]]);
            let n2 = self.new_tri();
            self.orig[n2] = self.orig[n];
            self.tv[t] = [a, p, s];
            self.ta[t] = [pack(n2, 0), pack(t2, 2), t_ap.0];
            self.sb[t] = [l[0], NONE, t_ap.1];
            self.tv[t2] = [a, s, q];
            self.ta[t2] = [pack(n, 0), t_qa.0, pack(t, 1)];
            self.sb[t2] = [l[1], t_qa.1, NONE];
            self.tv[n] = [d, q, s];
            self.ta[n] = [pack(t2, 0), pack(n2, 2), n_dq.0];
            self.sb[n] = [l[1], NONE, n_dq.1];
            self.tv[n2] = [d, s, p];
            self.ta[n2] = [pack(t, 0), n_pd.0, pack(n, 1)];
            self.sb[n2] = [l[0], n_pd.1, NONE];
            for (k, e) in [(t, 2usize), (t2, 1), (n, 2), (n2, 1)] {
                self.link(k, e);
            }
            for k in [t, t2, n, n2] {
                self.set_vt(k);
            }
            st.push((d, q));
            st.push((p, d));
        }
        self.legalize(s, &mut st);
        s
    }

    /// Walks from triangle `t` toward `c` along the line from its centroid,
    /// never crossing a subsegment.
    fn walk(&self, mut t: usize, c: &[f64; 2]) -> Walk {
        let v = self.tv[t];
        let (a, b, d) = (self.p(v[0]), self.p(v[1]), self.p(v[2]));
        let g = [(a[0] + b[0] + d[0]) / 3.0, (a[1] + b[1] + d[1]) / 3.0];
        for _ in 0..self.tv.len() + 8 {
            let v = self.tv[t];
            let o: [f64; 3] = std::array::from_fn(|e| {
                let (x, y) = edge(&v, e);
                orient2d(self.p(x), self.p(y), c)
            });
            if o.iter().all(|&x| x > 0.0) {
                return Walk::Inside(t);
            }
            if o.iter().all(|&x| x >= 0.0) {
                let zeros = o.iter().filter(|&&x| x == 0.0).count();
                if zeros > 1 {
                    return Walk::Vertex;
                }
                let e = o.iter().position(|&x| x == 0.0).unwrap_or(0);
                return Walk::OnEdge(t, e);
            }
            let mut exit = None;
            for (e, &oe) in o.iter().enumerate() {
                if oe >= 0.0 {
                    continue;
                }
                let (x, y) = edge(&v, e);
                if orient2d(&g, c, self.p(x)) <= 0.0 && orient2d(&g, c, self.p(y)) >= 0.0 {
                    exit = Some(e);
                    break;
                }
            }
            let e = exit.unwrap_or_else(|| o.iter().position(|&x| x < 0.0).unwrap_or(0));
            if self.sb[t][e] != NONE {
                return Walk::Blocked(self.sb[t][e]);
            }
            if self.ta[t][e] == NONE {
                return Walk::Lost;
            }
            t = unpack(self.ta[t][e]).0;
        }
        Walk::Lost
    }

    /// Subsegments that would become visible from `c` if it were inserted
    /// in `t0` (and `t1`), i.e. on the boundary of its Bowyer–Watson cavity,
    /// and that `c` encroaches.
    fn cavity_encroached(&self, starts: &[usize], c: &[f64; 2], out: &mut Vec<u32>) {
        let mut seen: Vec<usize> = starts.to_vec();
        let mut st: Vec<usize> = starts.to_vec();
        while let Some(t) = st.pop() {
            for e in 0..3 {
                let s = self.sb[t][e];
                if s != NONE {
                    let [u, w] = self.subs[s as usize].v;
                    if encroaches(self.p(u), self.p(w), c, self.cos2) && !out.contains(&s) {
                        out.push(s);
                    }
                    continue;
                }
                let x = self.ta[t][e];
                if x == NONE {
                    continue;
                }
                let n = unpack(x).0;
                if seen.contains(&n) {
                    continue;
                }
                let v = self.tv[n];
                if incircle(self.p(v[0]), self.p(v[1]), self.p(v[2]), c) > 0.0 {
                    seen.push(n);
                    st.push(n);
                }
            }
        }
    }

    /// The point splitting subsegment `s`, and its parameter.
    fn split_point(&self, s: &Sub) -> ([f64; 2], f64) {
        let par = self.parents[s.parent as usize];
        let (pa, pb) = (*self.p(par.a), *self.p(par.b));
        let len = dist2(&pa, &pb).sqrt();
        let fixed = |v: u32| (v as usize) < self.nfixed;
        let (t0, t1) = (s.t[0].min(s.t[1]), s.t[0].max(s.t[1]));
        let lo_fixed = fixed(if s.t[0] <= s.t[1] { s.v[0] } else { s.v[1] });
        let hi_fixed = fixed(if s.t[0] <= s.t[1] { s.v[1] } else { s.v[0] });
        let mut tm = 0.5 * (t0 + t1);
        if lo_fixed != hi_fixed && len > 0.0 {
            // Concentric shells around the fixed end.
            let l = (t1 - t0) * len;
            let d = 2f64.powi((0.5 * l).log2().round() as i32);
            let f = d / len;
            tm = if lo_fixed { t0 + f } else { t1 - f };
            if !(tm > t0 && tm < t1) {
                tm = 0.5 * (t0 + t1);
            }
        }
        // From the nearer fixed end, so the point stays on the segment.
        let x = if tm <= 0.5 {
            [pa[0] + tm * (pb[0] - pa[0]), pa[1] + tm * (pb[1] - pa[1])]
        } else {
            let u = 1.0 - tm;
            [pb[0] + u * (pa[0] - pb[0]), pb[1] + u * (pa[1] - pb[1])]
        };
        (x, tm)
    }

    /// Splits subsegment `s`; returns the new vertex.
    fn split_sub(&mut self, s: u32) -> Option<u32> {
        let sub = self.subs[s as usize];
        if !sub.alive || sub.stuck {
            return None;
        }
        let (x, tm) = self.split_point(&sub);
        let [u, w] = sub.v;
        let Some((t, i)) = self.find_either(u, w) else {
            self.subs[s as usize].stuck = true;
            return None;
        };
        if !self.can_split(t, i, &x) {
            self.subs[s as usize].stuck = true;
            return None;
        }
        let (p, _) = edge(&self.tv[t], i);
        let k = self.subs.len() as u32;
        // Halves: k = u..new, k+1 = new..w.
        let l = if p == u { [k, k + 1] } else { [k + 1, k] };
        self.subs[s as usize].alive = false;
        let nv = self.xy.len() as u32;
        self.subs.push(Sub {
            v: [u, nv],
            t: [sub.t[0], tm],
            parent: sub.parent,
            alive: true,
            stuck: false,
        });
        self.subs.push(Sub {
            v: [nv, w],
            t: [tm, sub.t[1]],
            parent: sub.parent,
            alive: true,
            stuck: false,
        });
        Some(self.split_edge(t, i, x, l, sub.parent))
    }

    /// Skinny triangle whose shortest edge spans a small input angle:
    /// the apex and the input angle (degrees), if `u` and `v` lie on two
    /// segment chains that meet at a vertex other than `u` and `v` at an angle
    /// below `bound` (`w`, the triangle's third vertex, is not used).
    fn small_angle_apex(&self, u: u32, v: u32, w: u32, bound: f64) -> Option<(u32, f64)> {
        let chains = |x: u32| -> &[u32] {
            let p = self.vpar[x as usize];
            if p != NONE {
                std::slice::from_ref(&self.vpar[x as usize])
            } else {
                self.vchains.get(x as usize).map_or(&[], |c| c.as_slice())
            }
        };
        let mut best: Option<(u32, f64)> = None;
        for &pu in chains(u) {
            for &pv in chains(v) {
                if pu == pv {
                    continue;
                }
                let (a, b) = (self.parents[pu as usize], self.parents[pv as usize]);
                for z in [a.a, a.b] {
                    if z == u || z == v || (z != b.a && z != b.b) {
                        continue;
                    }
                    let oa = if a.a == z { a.b } else { a.a };
                    let ob = if b.a == z { b.b } else { b.a };
                    let pz = self.p(z);
                    let (ux, uy) = (self.p(oa)[0] - pz[0], self.p(oa)[1] - pz[1]);
                    let (vx, vy) = (self.p(ob)[0] - pz[0], self.p(ob)[1] - pz[1]);
                    let ang = (ux * vy - uy * vx)
                        .abs()
                        .atan2(ux * vx + uy * vy)
                        .to_degrees();
                    // (Requiring `w` inside the wedge was tried: refinement
                    // then cascades on la.poly at 30°.)
                    let _ = w;
                    if ang < bound && best.is_none_or(|(_, x)| ang < x) {
                        best = Some((z, ang));
                    }
                }
            }
        }
        best
    }
}

/// Criteria in scaled units.
struct Crit {
    /// sin² of the angle bound (0: none).
    sin2: f64,
    angle: f64,
    /// Doubled-area bound (infinite: none).
    area2: f64,
    regional: bool,
    /// Off-centre distance from the shortest edge, in edge lengths (0: none).
    off: f64,
    /// Doubled-area scale factor (scaled² → input units).
    s2: f64,
}

/// Refines a constrained Delaunay triangulation until every triangle meets
/// the angle and area bounds of `options` (see the [module docs](self)).
///
/// The input points keep their ids; Steiner points follow. Subsegments keep
/// their input segment and marker; the triangles their region, attribute and
/// area bound.
///
/// # Errors
/// [`Error::InvalidCoordinate`] if the mesh has a NaN/infinite point (index
/// given). Running out of `u32` vertex ids stops the refinement like the
/// Steiner budget does.
///
/// ```
/// use delone::{model::pslg::Pslg, tri::{constrain::*, refine::*}};
/// let g = Pslg::new(vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
///                   vec![[0, 1], [1, 2], [2, 3], [3, 0]]);
/// let cdt = constrained_triangulation(&g, CdtOptions::default()).unwrap();
/// let opts = RefineOptions { min_angle: Some(30.0), max_area: Some(0.01), ..Default::default() };
/// let r = refine(&cdt, &opts).unwrap();
/// assert!(r.report.met);
/// assert!(r.mesh.triangles.len() >= 100);
/// check_cdt(&g, &r.mesh).unwrap();
/// ```
pub fn refine(cdt: &Cdt, options: &RefineOptions) -> Result<Refined, Error> {
    if let Some(index) = cdt
        .points
        .iter()
        .position(|p| !(p[0].is_finite() && p[1].is_finite()))
    {
        return Err(Error::InvalidCoordinate { index });
    }
    let max_abs = cdt
        .points
        .iter()
        .fold(0.0f64, |m, p| m.max(p[0].abs()).max(p[1].abs()));
    let scale = pow2_scale(max_abs);
    let sf = scale.0 * scale.1;
    let nfixed = cdt.points.len();
    let nt = cdt.triangles.len();
    let mut m = Mesh {
        xy: cdt.points.iter().map(|&p| scaled(p, scale)).collect(),
        tv: cdt.triangles.clone(),
        ta: vec![[NONE; 3]; nt],
        sb: vec![[NONE; 3]; nt],
        orig: (0..nt as u32).collect(),
        vt: vec![0; nfixed],
        vpar: vec![NONE; nfixed],
        nfixed,
        vchains: vec![Vec::new(); nfixed],
        cos2: 0.0,
        subs: Vec::new(),
        parents: Vec::new(),
        flips: 0,
    };
    for t in 0..nt {
        m.set_vt(t);
        for e in 0..3 {
            let n = cdt.neighbors[t][e];
            if n == NONE {
                continue;
            }
            let (a, b) = edge(&cdt.triangles[t], e);
            let Some(j) = (0..3).find(|&j| edge(&cdt.triangles[n as usize], j) == (b, a)) else {
                continue;
            };
            m.ta[t][e] = pack(n as usize, j);
        }
    }
    // Subsegments: the bounding input ones, then hull edges (`-c`).
    let mut seg_of: HashMap<(u32, u32), u32> = HashMap::new();
    for (k, s) in cdt.segments.iter().enumerate() {
        if s.bounding {
            seg_of
                .entry((s.v[0].min(s.v[1]), s.v[0].max(s.v[1])))
                .or_insert(k as u32);
        }
    }
    for t in 0..nt {
        for e in 0..3 {
            if m.sb[t][e] != NONE {
                continue;
            }
            let (a, b) = edge(&m.tv[t], e);
            let out = seg_of.get(&(a.min(b), a.max(b))).copied();
            if out.is_none() && m.ta[t][e] != NONE {
                continue;
            }
            let k = m.subs.len() as u32;
            m.parents.push(Parent {
                a,
                b,
                out: out.unwrap_or(NONE),
            });
            m.subs.push(Sub {
                v: [a, b],
                t: [0.0, 1.0],
                parent: k,
                alive: true,
                stuck: false,
            });
            m.sb[t][e] = k;
            if m.ta[t][e] != NONE {
                let (n, j) = unpack(m.ta[t][e]);
                m.sb[n][j] = k;
            }
        }
    }
    for (k, par) in m.parents.iter().enumerate() {
        m.vchains[par.a as usize].push(k as u32);
        m.vchains[par.b as usize].push(k as u32);
    }
    let angle = options.min_angle.map_or(0.0, |a| a.clamp(0.0, 60.0));
    let crit = Crit {
        sin2: angle.to_radians().sin().powi(2),
        angle,
        area2: options
            .max_area
            .filter(|a| *a > 0.0)
            .map_or(f64::INFINITY, |a| 2.0 * a * sf * sf),
        regional: options.regional_areas,
        off: if options.off_centers && angle > 0.0 {
            0.475 / (0.5 * angle.to_radians()).tan()
        } else {
            0.0
        },
        s2: sf * sf,
    };
    // Diametral lens: with an angle bound θ ≤ 45°, a subsegment is encroached
    // by a vertex that sees it at more than 180° − 2θ (Chew; Shewchuk).
    if angle > 0.0 && angle <= 45.0 {
        m.cos2 = (180.0 - 2.0 * angle).to_radians().cos().powi(2);
    }
    let limit = options.max_steiner.unwrap_or(usize::MAX);
    let mut report = RefineReport::default();

    // Badness key (smaller is worse) of triangle t, if it is to be fixed.
    let bad = |m: &Mesh, t: usize| -> Option<u64> {
        let v = m.tv[t];
        let (s2, d, k) = shape(m.p(v[0]), m.p(v[1]), m.p(v[2]));
        let mut abound = crit.area2;
        let ma = cdt.max_areas[m.orig[t] as usize];
        if crit.regional && ma > 0.0 {
            abound = abound.min(2.0 * ma * crit.s2);
        }
        if d > abound {
            return Some((1.0 + abound / d).to_bits());
        }
        if s2 < crit.sin2 {
            let (u, w) = edge(&v, k);
            if m.small_angle_apex(u, w, v[k], crit.angle).is_some() {
                return None;
            }
            return Some(s2.to_bits());
        }
        None
    };
    let canon = |v: [u32; 3]| {
        let k = (0..3).min_by_key(|&i| v[i]).unwrap_or(0);
        [v[k], v[NEXT[k]], v[PREV[k]]]
    };
    let mut heap: BinaryHeap<Reverse<(u64, [u32; 3])>> = BinaryHeap::new();
    let mut enc: VecDeque<u32> = VecDeque::new();
    for t in 0..nt {
        if let Some(k) = bad(&m, t) {
            heap.push(Reverse((k, canon(m.tv[t]))));
        }
    }
    // Subsegments encroached by an apex.
    let check_sub = |m: &Mesh, t: usize, e: usize, enc: &mut VecDeque<u32>| {
        let s = m.sb[t][e];
        if s == NONE {
            return;
        }
        let [u, w] = m.subs[s as usize].v;
        let apex = m.tv[t][e];
        if encroaches(m.p(u), m.p(w), m.p(apex), m.cos2) {
            enc.push_back(s);
        }
    };
    for t in 0..nt {
        for e in 0..3 {
            check_sub(&m, t, e, &mut enc);
        }
    }
    let after_insert = |m: &Mesh,
                        p: u32,
                        heap: &mut BinaryHeap<Reverse<(u64, [u32; 3])>>,
                        enc: &mut VecDeque<u32>| {
        for t in m.star(p) {
            if let Some(k) = bad(m, t) {
                heap.push(Reverse((k, canon(m.tv[t]))));
            }
            for e in 0..3 {
                check_sub(m, t, e, enc);
                let x = m.ta[t][e];
                if x != NONE && m.sb[t][e] != NONE {
                    let (n, j) = unpack(x);
                    check_sub(m, n, j, enc);
                }
            }
        }
    };
    let mut steiner = 0usize;
    let mut tmp: Vec<u32> = Vec::new();
    loop {
        if enc.is_empty() && heap.is_empty() {
            break;
        }
        if steiner >= limit || m.xy.len() >= (u32::MAX - 8) as usize {
            report.limit_reached = true;
            break;
        }
        if let Some(s) = enc.pop_front() {
            if let Some(p) = m.split_sub(s) {
                steiner += 1;
                report.segment_splits += 1;
                after_insert(&m, p, &mut heap, &mut enc);
            }
            continue;
        }
        let Some(Reverse((_, v))) = heap.pop() else {
            break;
        };
        let Some((t, i)) = m.find_edge(v[1], v[2]) else {
            continue;
        };
        if m.tv[t][i] != v[0] {
            continue;
        }
        let tv = m.tv[t];
        let mut c = circumcenter(m.p(tv[0]), m.p(tv[1]), m.p(tv[2]));
        if crit.off > 0.0 {
            // Üngör's off-centre: on the bisector of the shortest edge, at
            // the apex of an isosceles triangle on it whose apex angle is a
            // little above the bound, if that is nearer than the circumcentre.
            let (_, _, k) = shape(m.p(tv[0]), m.p(tv[1]), m.p(tv[2]));
            let (a, b) = edge(&tv, k);
            let (pa, pb) = (*m.p(a), *m.p(b));
            let mid = [0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1])];
            let want = crit.off * dist2(&pa, &pb).sqrt();
            let have = dist2(&mid, &c).sqrt();
            if have > want {
                let f = want / have;
                c = [mid[0] + f * (c[0] - mid[0]), mid[1] + f * (c[1] - mid[1])];
            }
        }
        if !(c[0].is_finite() && c[1].is_finite()) {
            continue;
        }
        let at = match m.walk(t, &c) {
            Walk::Inside(x) => (x, None),
            Walk::OnEdge(x, e) => (x, Some(e)),
            Walk::Blocked(s) => {
                report.rejected_circumcenters += 1;
                if !m.subs[s as usize].stuck {
                    enc.push_back(s);
                    heap.push(Reverse((0, v)));
                }
                continue;
            }
            Walk::Vertex | Walk::Lost => continue,
        };
        tmp.clear();
        let mut starts = vec![at.0];
        if let Some(e) = at.1 {
            if m.ta[at.0][e] != NONE {
                starts.push(unpack(m.ta[at.0][e]).0);
            }
        }
        m.cavity_encroached(&starts, &c, &mut tmp);
        if !tmp.is_empty() {
            report.rejected_circumcenters += 1;
            let mut any = false;
            for &s in &tmp {
                if !m.subs[s as usize].stuck {
                    enc.push_back(s);
                    any = true;
                }
            }
            if any {
                heap.push(Reverse((0, v)));
            }
            continue;
        }
        let p = match at {
            (x, None) => m.split_tri(x, c),
            (x, Some(e)) => {
                if m.sb[x][e] != NONE || !m.can_split(x, e, &c) {
                    continue;
                }
                m.split_edge(x, e, c, [NONE, NONE], NONE)
            }
        };
        steiner += 1;
        report.circumcenters += 1;
        after_insert(&m, p, &mut heap, &mut enc);
    }
    report.flips = m.flips;
    Ok(finish(cdt, m, &crit, scale, report))
}

/// Builds the output mesh and the final statistics.
fn finish(cdt: &Cdt, m: Mesh, crit: &Crit, scale: (f64, f64), mut report: RefineReport) -> Refined {
    let nt = m.tv.len();
    let mut points = cdt.points.clone();
    points.extend(
        m.xy[m.nfixed..]
            .iter()
            .map(|p| [p[0] / scale.1 / scale.0, p[1] / scale.1 / scale.0]),
    );
    let triangles = m.tv.clone();
    let neighbors: Vec<[u32; 3]> =
        m.ta.iter()
            .map(|a| a.map(|x| if x == NONE { NONE } else { unpack(x).0 as u32 }))
            .collect();
    let o = |t: usize| m.orig[t] as usize;
    let regions = (0..nt).map(|t| cdt.regions[o(t)]).collect();
    let attributes = (0..nt).map(|t| cdt.attributes[o(t)]).collect();
    let max_areas: Vec<f64> = (0..nt).map(|t| cdt.max_areas[o(t)]).collect();
    let mut segments = Vec::new();
    for s in m.subs.iter().filter(|s| s.alive) {
        let par = m.parents[s.parent as usize];
        if par.out == NONE {
            continue;
        }
        let src = cdt.segments[par.out as usize];
        segments.push(Subsegment {
            v: s.v,
            bounding: true,
            ..src
        });
    }
    segments.extend(cdt.segments.iter().filter(|s| !s.bounding).copied());
    report.min_angle = 180.0;
    report.max_angle = 0.0;
    let mut met = true;
    for (t, v) in triangles.iter().enumerate() {
        let (a, b, c) = (m.p(v[0]), m.p(v[1]), m.p(v[2]));
        let ang = angles(a, b, c);
        let lo = ang.iter().copied().fold(180.0f64, f64::min);
        report.min_angle = report.min_angle.min(lo);
        report.max_angle = report
            .max_angle
            .max(ang.iter().copied().fold(0.0, f64::max));
        let (s2, d, k) = shape(a, b, c);
        let mut abound = crit.area2;
        if crit.regional && max_areas[t] > 0.0 {
            abound = abound.min(2.0 * max_areas[t] * crit.s2);
        }
        let angle_bad = s2 < crit.sin2 && lo < crit.angle;
        if !(d > abound || angle_bad) {
            continue;
        }
        met = false;
        let (u, w) = edge(v, k);
        let reason = match m.small_angle_apex(u, w, v[k], crit.angle) {
            Some((apex, input_angle)) if d <= abound => {
                UnfixableReason::SmallInputAngle { apex, input_angle }
            }
            _ if report.limit_reached => UnfixableReason::SteinerLimit,
            _ => UnfixableReason::Precision,
        };
        report.unfixable.push(Unfixable {
            triangle: t as u32,
            min_angle: lo,
            area: 0.5 * d / crit.s2,
            reason,
        });
    }
    if triangles.is_empty() {
        report.min_angle = 0.0;
    }
    report.met = met;
    Refined {
        mesh: Cdt {
            points,
            triangles,
            neighbors,
            regions,
            attributes,
            max_areas,
            segments,
            vertex_map: cdt.vertex_map.clone(),
            report: cdt.report.clone(),
        },
        report,
    }
}
