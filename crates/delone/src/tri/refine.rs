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
//!    A subsegment with exactly one end at a vertex of the input CDT where
//!    another segment meets it at less than 60° is split on a *concentric
//!    shell* (at a power-of-two distance from that end, the one nearest to
//!    half its length), otherwise at its midpoint; split points
//!    are computed from the ends of the original subsegment, so they stay
//!    within a few ulps of the input segment.
//! 2. **Bad triangles** (minimum angle below the bound, or area above the
//!    global or regional bound) are taken from a bucket queue: skinny ones
//!    before large ones, worst bucket first (64 buckets by sin² of the
//!    smallest angle, quarter octaves of the area ratio); oldest first
//!    within an angle bucket, newest first within an area bucket (it was
//!    just made, so it is in cache; deterministic). Their
//!    circumcentre (or off-centre) is located by a walk from the triangle and
//!    inserted — unless it lies beyond a subsegment (that one is
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
//! # Termination and the budget
//!
//! Every bound is met, or the [`RefineReport`] says which triangles miss it
//! and why ([`RefineReport::met`], [`RefineReport::unfixable`] with an
//! [`UnfixableReason`]):
//!
//! * bounds no mesh can meet are refused before any work
//!   ([`Error::InvalidBound`]): a minimum angle of 60° or more (see
//!   [`RefineOptions::min_angle`]), a NaN or negative one, an area bound that
//!   is not positive;
//! * Ruppert/Chew refinement with off-centres terminates for angle bounds up
//!   to about 33–34° (Triangle's manual says the same of Triangle); above
//!   that it may add points forever. Every run therefore has a Steiner
//!   budget, by default [`default_budget`] (from the input size and the
//!   number of triangles the area bounds ask for, never from the machine).
//!   When it runs out, the refinement stops with a valid constrained
//!   Delaunay triangulation, [`RefineReport::limit_reached`] is set and the
//!   triangles still bad are listed with [`UnfixableReason::SteinerLimit`];
//! * triangles whose small angle is forced by a smaller input angle are
//!   listed with [`UnfixableReason::SmallInputAngle`] (no mesh of that
//!   input meets the bound there).
//!
//! # Parallel refinement
//!
//! When the area bounds predict at least
//! [`RefineOptions::parallel_min_triangles`] triangles, the mesh is refined
//! sequentially to about 1/64 of its final size (area bounds × 64), its
//! triangles are split by recursive coordinate bisection into parts of
//! equal predicted work, each part is refined with the edges between parts
//! fixed (never split; a point beyond or encroaching one is not inserted),
//! the parts are stitched back (Lawson flips across the former part edges
//! restore the constrained Delaunay property), and the triangles left near
//! the part edges are refined sequentially. The number of parts comes from
//! the predicted size alone (2 up to about 400,000 triangles, then one
//! more power of two per doubling, at most 16); [`RefineOptions::threads`]
//! threads run the parts. The result depends on the input and the options
//! only: 1, 2 or 8 threads give the same mesh, on every machine. The
//! triangle count stays within a fraction of a per cent of the one-part
//! refinement on the large shared PSLGs.
//!
//! Insertion is Bowyer–Watson: the cavity of a new point (the triangles whose
//! circumcircle strictly contains it, reached without crossing a subsegment)
//! is found once — for a circumcentre, its boundary subsegments are the ones
//! tested for encroachment — and replaced by a fan. The depth-first cavity
//! search meets the boundary in counterclockwise order, so the fan is linked
//! in sequence; a cavity that is not one simple cycle seen counterclockwise
//! from the new point (possible only through rounding of a split point) is
//! refused and nothing changes. The result is
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

use std::collections::{HashMap, VecDeque};
use std::sync::Arc;

use super::cmesh::{encroaches, CMesh, Ins, Sub, Tri};
use super::constrain::{Cdt, Subsegment};
use super::topo::{edge, pack, unpack, NEXT, PREV};
use crate::geom::{pow2_scale, scaled};
use crate::{Error, NONE};

mod par;

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
    /// `None`: no angle bound. Values above about 34 may not terminate and
    /// stop at the Steiner budget ([`Self::max_steiner`]); NaN, negative
    /// values and 60 or more are refused ([`Error::InvalidBound`]).
    pub min_angle: Option<f64>,
    /// Global maximum triangle area (`-a` with a number). `None`: no bound.
    /// NaN, zero and negative values are refused ([`Error::InvalidBound`]).
    pub max_area: Option<f64>,
    /// Apply the regions' area bounds ([`Cdt::max_areas`]; Triangle applies
    /// them when `-a` is given, with or without a number). Default false.
    pub regional_areas: bool,
    /// Maximum number of Steiner points to add (`-S`). `None`: the default
    /// budget [`default_budget`], derived from the input and the area
    /// bounds. When it runs out the refinement stops with a valid mesh and
    /// [`RefineReport::limit_reached`]. An explicit budget also keeps the
    /// refinement in one part (sequential), so it stops where a sequential
    /// refinement would.
    pub max_steiner: Option<usize>,
    /// Insert off-centres instead of circumcentres when they are nearer the
    /// shortest edge (Üngör; Triangle's default). Default true.
    pub off_centers: bool,
    /// Which subsegments may be split (Triangle's `-Y`, `-YY`). Default
    /// [`SegmentSplits::All`].
    pub segment_splits: SegmentSplits,
    /// Conforming Delaunay (Triangle's `-D`): also split every subsegment
    /// whose diametral circle strictly contains a mesh vertex (not only the
    /// apex of a triangle beside it), with the concentric-shell rule, until
    /// none does; every triangle of the result is then truly Delaunay (its
    /// circumcircle holds no mesh vertex; see
    /// [`check_conforming_delaunay`](super::conforming::check_conforming_delaunay)).
    /// Encroachment uses the diametral circle, not the lens. With no angle or
    /// area bound only subsegments are split. Protected subsegments
    /// ([`Self::segment_splits`]) are never split, so the property may then
    /// be unmet ([`RefineReport::met`] false). Default false.
    ///
    /// ```
    /// use delone::{model::pslg::Pslg, tri::{constrain::*, refine::*}};
    /// // A thin rectangle and a point inside: its long sides are not Gabriel.
    /// let g = Pslg::new(vec![[0.0, 0.0], [10.0, 0.0], [10.0, 1.0], [0.0, 1.0], [5.0, 0.5]],
    ///                   vec![[0, 1], [1, 2], [2, 3], [3, 0]]);
    /// let cdt = constrained_triangulation(&g, CdtOptions::default()).unwrap();
    /// let o = RefineOptions { min_angle: None, conforming_delaunay: true, ..Default::default() };
    /// let r = refine(&cdt, &o).unwrap();
    /// assert!(r.report.met && r.report.circumcenters == 0 && r.report.segment_splits > 0);
    /// delone::tri::conforming::check_conforming_delaunay(&r.mesh.points, &r.mesh.triangles).unwrap();
    /// ```
    pub conforming_delaunay: bool,
    /// Threads to refine with (see [`default_threads`], the default). A
    /// large refinement (an area bound predicting at least
    /// [`Self::parallel_min_triangles`] triangles) is done in parts (see the
    /// [module docs](self#parallel-refinement)), which these threads run;
    /// the number of parts, and so the result, does not depend on it: any
    /// thread count gives the same mesh. Parts are not used with
    /// [`Self::conforming_delaunay`], [`Self::max_steiner`] or a user's test
    /// ([`refine_with`]). 0 counts as 1.
    ///
    /// ```
    /// use delone::{model::pslg::Pslg, tri::{constrain::*, refine::*}};
    /// let g = Pslg::new(vec![[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]],
    ///                   vec![[0, 1], [1, 2], [2, 3], [3, 0]]);
    /// let cdt = constrained_triangulation(&g, CdtOptions::default()).unwrap();
    /// // (`parallel_min_triangles: 0`: in parallel although the mesh is small.)
    /// let o = RefineOptions { min_angle: Some(30.0), max_area: Some(0.05), threads: 2,
    ///                         parallel_min_triangles: 0, ..Default::default() };
    /// let a = refine(&cdt, &o).unwrap();
    /// assert!(a.report.met && a.mesh.triangles.len() > 2000);
    /// check_cdt(&g, &a.mesh).unwrap();
    /// // The same mesh with any number of threads.
    /// assert_eq!(a, refine(&cdt, &RefineOptions { threads: 1, ..o }).unwrap());
    /// ```
    pub threads: usize,
    /// Predicted output size (triangles, from the area bounds) below which
    /// refinement is done in one part (sequentially). Default
    /// [`PARALLEL_MIN_TRIANGLES`]; 0 refines every mesh in parts (tests).
    pub parallel_min_triangles: usize,
}

/// The default [`RefineOptions::threads`]: the available parallelism,
/// at most 8.
///
/// ```
/// let t = delone::tri::refine::default_threads();
/// assert!((1..=8).contains(&t));
/// ```
pub fn default_threads() -> usize {
    std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(8)
}

/// The default [`RefineOptions::parallel_min_triangles`]: below this size
/// parts do not pay (measured on the shared PSLGs).
pub const PARALLEL_MIN_TRIANGLES: usize = 50_000;

/// Smallest default Steiner budget ([`default_budget`]): about 400 MB of
/// refinement ([`memory_estimate`]).
pub const BUDGET_BASE: usize = 2_000_000;

/// Largest default Steiner budget ([`default_budget`]): about 3.4 GB of
/// refinement (32 M triangles). A bigger run needs an explicit
/// [`RefineOptions::max_steiner`] (`-S`).
pub const BUDGET_MAX: usize = 1 << 24;

/// Peak bytes per vertex of a refinement, input and output included
/// (measured: `tri -pq30a0.0005 la.poly`, 0.74 M Steiner points, 143 MB).
pub const BYTES_PER_POINT: u64 = 200;

/// The Steiner budget used when [`RefineOptions::max_steiner`] is `None`:
/// [`BUDGET_BASE`] + 16 per input vertex + 2 per triangle the area bounds
/// ask for (`predicted_triangles`: 1.6 × the domain's area over the area
/// bound, summed over the triangles of the constrained triangulation), at
/// most [`BUDGET_MAX`].
///
/// The rule depends on the input and the options only (never on the
/// machine), so a run stops at the same point everywhere. A run whose area
/// bound asks for `N` triangles adds about `N / 2` points: the budget leaves
/// four times that, so area-driven runs finish (`tri -pq30a0.0005 la.poly`,
/// 0.74 M points, has a budget of 5 M). What it stops is refinement that
/// does not converge: an angle bound above what Delaunay refinement
/// guarantees (about 34°, see the [module docs](self#termination-and-the-budget))
/// stops after at most 2 M points + 16 per input vertex, a few hundred MB.
///
/// ```
/// use delone::tri::refine::{default_budget, BUDGET_BASE, BUDGET_MAX};
/// assert_eq!(default_budget(100, 0.0), BUDGET_BASE + 1600);
/// assert_eq!(default_budget(100, 1e6), BUDGET_BASE + 1600 + 2_000_000);
/// assert_eq!(default_budget(100, 1e12), BUDGET_MAX);
/// ```
pub fn default_budget(input_points: usize, predicted_triangles: f64) -> usize {
    let area = if predicted_triangles.is_finite() && predicted_triangles > 0.0 {
        (2.0 * predicted_triangles).min(BUDGET_MAX as f64) as usize
    } else {
        0
    };
    BUDGET_BASE
        .saturating_add(input_points.saturating_mul(16))
        .saturating_add(area)
        .min(BUDGET_MAX)
}

/// Estimated peak memory, in bytes, of a refinement that ends with
/// `points` vertices ([`BYTES_PER_POINT`] each).
///
/// ```
/// assert_eq!(delone::tri::refine::memory_estimate(1_000_000), 200_000_000);
/// ```
pub fn memory_estimate(points: usize) -> u64 {
    points as u64 * BYTES_PER_POINT
}

/// Refuses bounds no mesh can meet: a minimum angle that is NaN, negative
/// or 60° or more; an area bound that is NaN, zero or negative.
///
/// Every triangle has an angle of at most 60°, and exactly 60° only when it
/// is equilateral. No equilateral triangle has all three corners at
/// rational coordinates (its area would be both rational, by the shoelace
/// formula, and √3/4 times a rational squared side), and floating-point
/// numbers are rationals: so no mesh delone can output has a minimum angle
/// of 60°, and `-q60` is refused with `-q61`. Every bound below 60° can be
/// met by some domains (one near-equilateral triangle); whether refinement
/// meets it on a given domain is decided by running, under the Steiner
/// budget.
fn check_bounds(options: &RefineOptions) -> Result<(), Error> {
    if let Some(a) = options.min_angle {
        let reason = if a.is_nan() || a < 0.0 {
            Some("the minimum angle must be a number of degrees, 0 or more")
        } else if a >= 60.0 {
            Some("no mesh meets a minimum angle of 60 degrees or more (only equilateral triangles reach 60, and none has corners at floating-point coordinates)")
        } else {
            None
        };
        if let Some(reason) = reason {
            return Err(Error::InvalidBound {
                option: "-q",
                value: a,
                reason,
            });
        }
    }
    if let Some(a) = options.max_area {
        if a.is_nan() || a <= 0.0 {
            return Err(Error::InvalidBound {
                option: "-a",
                value: a,
                reason: "the maximum area must be positive",
            });
        }
    }
    Ok(())
}

/// Which subsegments refinement may split.
///
/// A subsegment that may not be split is never encroached (a point may be
/// inserted near it), but a point beyond it cannot be inserted: triangles
/// that only such a point would fix are reported with
/// [`UnfixableReason::NoSegmentSplits`].
///
/// ```
/// use delone::tri::refine::{RefineOptions, SegmentSplits};
/// let o = RefineOptions { segment_splits: SegmentSplits::Interior, ..Default::default() };
/// assert_ne!(o, RefineOptions::default());
/// ```
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum SegmentSplits {
    /// Every subsegment (the default).
    #[default]
    All,
    /// Only subsegments with triangles on both sides: no Steiner point on the
    /// boundary of the domain (Triangle's `-Y`).
    Interior,
    /// None: no Steiner point on any segment (Triangle's `-YY`).
    None,
}

impl Default for RefineOptions {
    fn default() -> Self {
        RefineOptions {
            min_angle: Some(20.0),
            max_area: None,
            regional_areas: false,
            max_steiner: None,
            off_centers: true,
            segment_splits: SegmentSplits::All,
            conforming_delaunay: false,
            threads: default_threads(),
            parallel_min_triangles: PARALLEL_MIN_TRIANGLES,
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
    /// The options forbid splitting the subsegment that is in the way
    /// ([`RefineOptions::segment_splits`]; reported instead of
    /// [`Self::Precision`] whenever splits are restricted).
    NoSegmentSplits,
    /// With [`RefineOptions::conforming_delaunay`]: quality refinement was
    /// stopped so that the conforming-Delaunay splits could finish (they and
    /// a high angle bound kept feeding each other near small input angles).
    ConformingDelaunay,
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
    /// Triangles replaced by Bowyer–Watson cavities (the work done).
    pub cavity_triangles: usize,
    /// The smallest angle of the output, in degrees.
    pub min_angle: f64,
    /// The largest angle of the output, in degrees.
    pub max_angle: f64,
    /// True if every triangle meets every requested bound.
    pub met: bool,
    /// True if the Steiner-point budget stopped the refinement.
    pub limit_reached: bool,
    /// The Steiner-point budget the refinement ran under
    /// ([`RefineOptions::max_steiner`] or [`default_budget`]).
    pub steiner_budget: usize,
    /// The triangles that violate a bound, with the reason.
    pub unfixable: Vec<Unfixable>,
    /// With [`RefineOptions::conforming_delaunay`]: subsegments left whose
    /// diametral circle holds a mesh vertex (protected, too short to split,
    /// or the budget ran out); 0 means the mesh is conforming Delaunay.
    pub encroached_subsegments: usize,
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
    /// Split on concentric shells around `a` / `b`: another chain meets the
    /// end at an angle below [`SHELL_ANGLE`].
    shell: [bool; 2],
}

/// Input angle (degrees) below which the subsegments at a vertex are split
/// on concentric shells around it. Elsewhere midpoints are better: a shell
/// split of a chain's end subsegment may cut it at 0.35 of its length, and
/// the short piece seeds a cascade of small triangles at 34°.
const SHELL_ANGLE: f64 = 60.0;

/// The refinement's mesh: the constrained triangle mesh and what
/// refinement keeps beside it (subsegment chains, fixed vertices).
#[derive(Clone)]
struct Mesh {
    cm: CMesh,
    /// Parent chain of a Steiner vertex on a subsegment (`NONE` otherwise).
    vpar: Vec<u32>,
    nfixed: usize,
    /// The chains (parents) each fixed vertex is an end of.
    vchains: Arc<Vec<Vec<u32>>>,
    parents: Arc<Vec<Parent>>,
}

impl std::ops::Deref for Mesh {
    type Target = CMesh;
    fn deref(&self) -> &CMesh {
        &self.cm
    }
}

impl std::ops::DerefMut for Mesh {
    fn deref_mut(&mut self) -> &mut CMesh {
        &mut self.cm
    }
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
    /// Reserves room for the triangles an area bound will make (about
    /// 1.6 per bound's worth of area; twice that is reserved, at most 2²⁴):
    /// the 32-byte aligned records are copied, not reallocated in place,
    /// when the vector grows. Untouched capacity costs no resident memory.
    /// `part`: only these triangles will be refined (all when `None`).
    fn reserve_for_areas(
        &mut self,
        crit: &Crit,
        max_areas: &[f64],
        limit: usize,
        part: Option<&[u32]>,
    ) {
        if !crit.area2.is_finite() && !crit.regional {
            return;
        }
        let ratio = match part {
            Some(ts) => ts
                .iter()
                .map(|&t| self.area_ratio(crit, max_areas, t as usize))
                .sum(),
            None => (0..self.tr.len())
                .map(|t| self.area_ratio(crit, max_areas, t))
                .sum::<f64>(),
        };
        let base = if part.is_some() { 0 } else { self.tr.len() };
        let nt = (3.2 * ratio).min((1u64 << 24) as f64) as usize;
        let nt = nt.min(limit.saturating_mul(2));
        if nt > base {
            let more = nt - base;
            // Best effort: without the room the vectors grow as usual.
            let _ = self.tr.try_reserve_exact(more);
            let _ = self.sides.try_reserve_exact(more);
            let _ = self.xy.try_reserve_exact(more / 2);
            let _ = self.vpar.try_reserve_exact(more / 2);
        }
    }

    /// Area of triangle `t` over its area bound (0 without one).
    fn area_ratio(&self, crit: &Crit, max_areas: &[f64], t: usize) -> f64 {
        let t = &self.tr[t];
        {
            let (a, b, c) = (self.p(t.v[0]), self.p(t.v[1]), self.p(t.v[2]));
            let d = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
            let mut bound = crit.area2;
            if crit.regional {
                let ma = max_areas[t.orig as usize];
                if ma > 0.0 {
                    bound = bound.min(2.0 * ma * crit.s2);
                }
            }
            if bound.is_finite() && bound > 0.0 {
                d / bound
            } else {
                0.0
            }
        }
    }

    /// [`CMesh::insert`], with no parent chain for the new vertex.
    fn insert(
        &mut self,
        start: usize,
        c: [f64; 2],
        split: u32,
        halves: [u32; 4],
        check_enc: bool,
    ) -> Ins {
        let r = self.cm.insert(start, c, split, halves, check_enc);
        if let Ins::Done(_) = r {
            self.vpar.push(NONE);
        }
        r
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
        // The fixed end (parameter 0 at `a`, 1 at `b`) and its shell flag.
        let shell = if lo_fixed {
            par.shell[usize::from(t0 != 0.0)]
        } else {
            par.shell[usize::from(t1 == 1.0)]
        };
        if lo_fixed != hi_fixed && shell && len > 0.0 {
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
        let Some(t) = self.tri_of_sub(s) else {
            self.subs[s as usize].stuck = true;
            return None;
        };
        // Halves: k = u..new, k+1 = new..w.
        let k = self.subs.len() as u32;
        let Ins::Done(nv) = self.insert(t, x, s, [u, k, w, k + 1], false) else {
            self.subs[s as usize].stuck = true;
            return None;
        };
        self.vpar[nv as usize] = sub.parent;
        self.subs[s as usize].alive = false;
        self.subs.push(Sub {
            v: [u, nv],
            he: NONE,
            t: [sub.t[0], tm],
            parent: sub.parent,
            alive: true,
            stuck: false,
            protected: false,
        });
        self.subs.push(Sub {
            v: [nv, w],
            he: NONE,
            t: [tm, sub.t[1]],
            parent: sub.parent,
            alive: true,
            stuck: false,
            protected: false,
        });
        // The halves lie on fan edges 1 and 2.
        for i in 0..self.fan.len() {
            let f = self.fan[i] as usize;
            for e in 1..3 {
                let x = self.sub_at(f, e);
                if x == k || x == k + 1 {
                    self.subs[x as usize].he = pack(f, e);
                }
            }
        }
        Some(nv)
    }

    /// Conforming Delaunay: queues the live subsegments (with `stuck`, also
    /// those that cannot be split) whose diametral circle strictly holds a
    /// mesh vertex; returns how many.
    fn scan_encroached(&self, stuck: bool, enc: &mut VecDeque<u32>) -> usize {
        let ids: Vec<u32> = (0..self.subs.len() as u32)
            .filter(|&s| {
                let x = &self.subs[s as usize];
                x.alive && (stuck || !x.stuck)
            })
            .collect();
        let pairs: Vec<[u32; 2]> = ids.iter().map(|&s| self.subs[s as usize].v).collect();
        let tris: Vec<[u32; 3]> = self.tr.iter().map(|t| t.v).collect();
        let hit = super::conforming::encroached(&self.xy, &tris, &pairs);
        enc.extend(hit.iter().map(|&k| ids[k]));
        hit.len()
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

/// Bad triangles waiting, in buckets by badness: bucket 0 for triangles
/// whose circumcentre was rejected (retried right after the subsegment
/// splits), then angle buckets (worst first, by sin² of the smallest angle
/// over the bound's), then area buckets (largest area ratio first, quarter
/// octaves). Within an angle bucket the oldest triangle comes first (first
/// in, first out: at 34° on double_hex this keeps the count within a few
/// per cent of Triangle's, where newest-first made 12% more); within the
/// other buckets the newest comes first: it was just made, so it is still
/// in cache. Either order costs the same cache misses on the large shared
/// inputs (callgrind).
///
/// An entry is (triangle, its first vertex): a triangle record is reused
/// only by a fan around a new vertex, which becomes the first vertex of
/// every fan triangle, so a changed first vertex marks a stale entry.
struct Queue {
    buckets: Vec<Vec<(u32, u32)>>,
    /// No non-empty bucket below this one.
    lo: usize,
    len: usize,
    /// Angle buckets: the next entry to pop (first in, first out).
    head: Vec<usize>,
}

const ANGLE_BUCKETS: u32 = 64;
const AREA_BUCKETS: u32 = 160;

impl Queue {
    fn new() -> Self {
        Queue {
            buckets: vec![Vec::new(); (1 + ANGLE_BUCKETS + AREA_BUCKETS) as usize],
            lo: 0,
            len: 0,
            head: vec![0; (1 + ANGLE_BUCKETS + AREA_BUCKETS) as usize],
        }
    }

    /// `q` = sin² of the smallest angle over sin² of the bound, in [0, 1).
    fn angle_bucket(q: f64) -> u32 {
        1 + ((q * ANGLE_BUCKETS as f64) as u32).min(ANGLE_BUCKETS - 1)
    }

    /// `r` = area over the bound, above 1.
    fn area_bucket(r: f64) -> u32 {
        // Quarter octaves from the exponent and the top two mantissa bits.
        let k = ((r.to_bits() >> 50) as u32)
            .saturating_sub(1023 << 2)
            .min(AREA_BUCKETS - 1);
        1 + ANGLE_BUCKETS + (AREA_BUCKETS - 1 - k)
    }

    fn push(&mut self, b: u32, t: u32, v0: u32) {
        let b = b as usize;
        self.buckets[b].push((t, v0));
        self.lo = self.lo.min(b);
        self.len += 1;
    }

    fn pop(&mut self) -> Option<(u32, u32)> {
        while self.lo < self.buckets.len() {
            let b = self.lo;
            if (1..=ANGLE_BUCKETS as usize).contains(&b) {
                // First in, first out.
                let (q, h) = (&mut self.buckets[b], &mut self.head[b]);
                if *h < q.len() {
                    let x = q[*h];
                    *h += 1;
                    self.len -= 1;
                    if *h >= 4096 && 2 * *h >= q.len() {
                        q.drain(..*h);
                        *h = 0;
                    }
                    return Some(x);
                }
                q.clear();
                *h = 0;
            } else if let Some(x) = self.buckets[b].pop() {
                self.len -= 1;
                return Some(x);
            }
            self.lo += 1;
        }
        None
    }

    fn is_empty(&self) -> bool {
        self.len == 0
    }
}

/// A user's test of a triangle (its corners counterclockwise and its area,
/// in input units): true if it must be refined (Triangle's `-u`).
pub type UserTest<'a> = &'a dyn Fn(&[[f64; 2]; 3], f64) -> bool;

/// Criteria in scaled units.
#[derive(Clone, Copy)]
struct Crit<'a> {
    /// The user's test, if any.
    user: Option<UserTest<'a>>,
    /// Scale factors of the coordinates (divide by both for input units).
    scale: (f64, f64),
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
    /// Factor on every area bound (1; more for the coarse stage of the
    /// parallel refinement).
    coarse: f64,
}

/// Queue bucket (smaller is worse) of triangle `t`, if it is to be fixed.
#[inline]
fn bad_bucket(m: &Mesh, crit: &Crit, max_areas: &[f64], t: usize) -> Option<u32> {
    let v = m.tr[t].v;
    let (a, b, c) = (m.p(v[0]), m.p(v[1]), m.p(v[2]));
    let d = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    let mut abound = crit.area2;
    if crit.regional {
        let ma = max_areas[m.tr[t].orig as usize];
        if ma > 0.0 {
            abound = abound.min(2.0 * ma * crit.s2);
        }
    }
    abound *= crit.coarse;
    if d > abound {
        return Some(Queue::area_bucket(d / abound));
    }
    if crit.sin2 > 0.0 {
        let l = [dist2(b, c), dist2(c, a), dist2(a, b)];
        let k = if l[0] <= l[1] && l[0] <= l[2] {
            0
        } else if l[1] <= l[2] {
            1
        } else {
            2
        };
        let xy = l[NEXT[k]] * l[PREV[k]];
        // sin² of the smallest angle, d² / xy, below the bound's?
        if d * d < crit.sin2 * xy {
            let (u, w) = edge(&v, k);
            if m.small_angle_apex(u, w, v[k], crit.angle).is_none() {
                let s2 = if xy > 0.0 { d * d / xy } else { 0.0 };
                return Some(Queue::angle_bucket(s2 / crit.sin2));
            }
        }
    }
    if let Some(f) = crit.user {
        if f(&crit.input(m, &v), 0.5 * d / crit.s2) {
            // Last, with the least oversized triangles.
            return Some(Queue::area_bucket(1.0));
        }
    }
    None
}

impl Crit<'_> {
    /// A triangle's corners in input units.
    fn input(&self, m: &Mesh, v: &[u32; 3]) -> [[f64; 2]; 3] {
        v.map(|x| {
            let p = m.p(x);
            [
                p[0] / self.scale.1 / self.scale.0,
                p[1] / self.scale.1 / self.scale.0,
            ]
        })
    }
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
/// given); [`Error::InvalidBound`] for a bound no mesh can meet (see
/// [`RefineOptions::min_angle`], [`RefineOptions::max_area`]). Running out
/// of `u32` vertex ids stops the refinement like the Steiner budget does.
///
/// ```
/// use delone::{model::pslg::Pslg, tri::{constrain::*, refine::*}, Error};
/// let g = Pslg::new(vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]], vec![[0, 1], [1, 2], [2, 0]]);
/// let cdt = constrained_triangulation(&g, CdtOptions::default()).unwrap();
/// let o = RefineOptions { min_angle: Some(60.0), ..Default::default() };
/// assert!(matches!(refine(&cdt, &o), Err(Error::InvalidBound { option: "-q", .. })));
/// ```
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
    refine_inner(cdt, options, None)
}

/// [`refine`] with a user's test as well (Triangle's `-u`): a triangle is
/// also refined while `unsuitable(corners, area)` says so (corners
/// counterclockwise, in input units). The test must be deterministic for
/// the result to be; one that never accepts small triangles only stops at
/// [`RefineOptions::max_steiner`]. Triangles it still rejects at the end are
/// listed as unfixable.
///
/// # Errors
/// As [`refine`].
///
/// ```
/// use delone::{model::pslg::Pslg, tri::{constrain::*, refine::*}};
/// let g = Pslg::new(vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
///                   vec![[0, 1], [1, 2], [2, 3], [3, 0]]);
/// let cdt = constrained_triangulation(&g, CdtOptions::default()).unwrap();
/// // Small triangles at the corner (0, 0) only.
/// let near = |t: &[[f64; 2]; 3], area: f64| {
///     t.iter().any(|p| p[0] * p[0] + p[1] * p[1] < 0.1) && area > 1e-3
/// };
/// let r = refine_with(&cdt, &RefineOptions::default(), &near).unwrap();
/// assert!(r.report.met);
/// check_cdt(&g, &r.mesh).unwrap();
/// let plain = refine(&cdt, &RefineOptions::default()).unwrap();
/// assert!(r.mesh.triangles.len() > plain.mesh.triangles.len() + 20);
/// ```
pub fn refine_with(
    cdt: &Cdt,
    options: &RefineOptions,
    unsuitable: UserTest<'_>,
) -> Result<Refined, Error> {
    refine_inner(cdt, options, Some(unsuitable))
}

fn refine_inner(
    cdt: &Cdt,
    options: &RefineOptions,
    user: Option<UserTest<'_>>,
) -> Result<Refined, Error> {
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
    let xy = cdt.points.iter().map(|&p| scaled(p, scale)).collect();
    let tr = (0..nt)
        .map(|t| Tri {
            v: cdt.triangles[t],
            a: [NONE; 3],
            orig: t as u32,
            mark: 0,
        })
        .collect();
    let mut m = Mesh {
        cm: CMesh::new(xy, tr),
        vpar: vec![NONE; nfixed],
        nfixed,
        vchains: Arc::new(vec![Vec::new(); nfixed]),
        parents: Arc::new(Vec::new()),
    };
    for t in 0..nt {
        for e in 0..3 {
            let n = cdt.neighbors[t][e];
            if n == NONE {
                continue;
            }
            let (a, b) = edge(&cdt.triangles[t], e);
            let Some(j) = (0..3).find(|&j| edge(&cdt.triangles[n as usize], j) == (b, a)) else {
                continue;
            };
            m.tr[t].a[e] = pack(n as usize, j);
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
            if m.sub_at(t, e) != NONE {
                continue;
            }
            let (a, b) = edge(&m.tr[t].v, e);
            let out = seg_of.get(&(a.min(b), a.max(b))).copied();
            if out.is_none() && m.tr[t].a[e] != NONE {
                continue;
            }
            let k = m.subs.len() as u32;
            Arc::make_mut(&mut m.parents).push(Parent {
                a,
                b,
                out: out.unwrap_or(NONE),
                shell: [false; 2],
            });
            let protected = match options.segment_splits {
                SegmentSplits::All => false,
                SegmentSplits::Interior => m.tr[t].a[e] == NONE,
                SegmentSplits::None => true,
            };
            m.subs.push(Sub {
                v: [a, b],
                he: pack(t, e),
                t: [0.0, 1.0],
                parent: k,
                alive: true,
                stuck: protected,
                protected,
            });
            m.set_sub(t, e, k);
            if m.tr[t].a[e] != NONE {
                let (n, j) = unpack(m.tr[t].a[e]);
                m.set_sub(n, j, k);
            }
        }
    }
    {
        let vchains = Arc::make_mut(&mut m.vchains);
        for (k, par) in m.parents.iter().enumerate() {
            vchains[par.a as usize].push(k as u32);
            vchains[par.b as usize].push(k as u32);
        }
    }
    for k in 0..m.parents.len() {
        let par = m.parents[k];
        for (i, (z, o)) in [(par.a, par.b), (par.b, par.a)].into_iter().enumerate() {
            let pz = *m.p(z);
            let (ux, uy) = (m.p(o)[0] - pz[0], m.p(o)[1] - pz[1]);
            let shell = m.vchains[z as usize].iter().any(|&j| {
                let q = m.parents[j as usize];
                let o2 = if q.a == z { q.b } else { q.a };
                let (vx, vy) = (m.p(o2)[0] - pz[0], m.p(o2)[1] - pz[1]);
                let ang = (ux * vy - uy * vx)
                    .abs()
                    .atan2(ux * vx + uy * vy)
                    .to_degrees();
                j as usize != k && ang < SHELL_ANGLE
            });
            Arc::make_mut(&mut m.parents)[k].shell[i] = shell;
        }
    }
    check_bounds(options)?;
    let angle = options.min_angle.unwrap_or(0.0);
    let crit = Crit {
        user,
        scale,
        sin2: angle.to_radians().sin().powi(2),
        angle,
        area2: options
            .max_area
            .filter(|a| *a > 0.0)
            .map_or(f64::INFINITY, |a| 2.0 * a * sf * sf),
        regional: options.regional_areas,
        // 0.9 of the distance giving the bound exactly: measured at 34° on
        // face, double_hex(2, 3), la and A.poly (with first-in-first-out
        // angle buckets), it keeps the counts within 10% of Triangle's
        // (0.95 let cascades of small triangles start on double_hex and la
        // at 34°; the count is chaotic in this factor: la at 34° cascades
        // with 0.455 and gives twice the triangles with 0.445).
        off: if options.off_centers && angle > 0.0 {
            0.45 / (0.5 * angle.to_radians()).tan()
        } else {
            0.0
        },
        s2: sf * sf,
        coarse: 1.0,
    };
    // Diametral lens: with an angle bound θ ≤ 45°, a subsegment is encroached
    // by a vertex that sees it at more than 180° − 2θ (Chew; Shewchuk).
    if angle > 0.0 && angle <= 45.0 {
        m.cos2 = (180.0 - 2.0 * angle).to_radians().cos().powi(2);
    }
    let limit = options
        .max_steiner
        .unwrap_or_else(|| default_budget(nfixed, par::predicted(&m, &crit, &cdt.max_areas)));
    let mut report = RefineReport {
        steiner_budget: limit,
        ..RefineReport::default()
    };
    let threads = options.threads.clamp(1, 64);
    let parts = par::parts_for(&m, &crit, &cdt.max_areas, options);
    let quality = if parts > 1 {
        par::refine_parallel(
            &mut m,
            &crit,
            &cdt.max_areas,
            options,
            parts,
            threads,
            limit,
            &mut report,
        )
    } else {
        m.reserve_for_areas(&crit, &cdt.max_areas, limit, None);
        let mut steiner = 0;
        run(
            &mut m,
            &crit,
            &cdt.max_areas,
            options,
            limit,
            &mut steiner,
            &mut report,
            None,
            None,
        )
    };
    debug_assert_eq!(m.check(true), Ok(()), "refined mesh");
    report.cavity_triangles = m.replaced;
    let restricted = options.segment_splits != SegmentSplits::All;
    let left = if options.conforming_delaunay {
        m.scan_encroached(true, &mut VecDeque::new())
    } else {
        0
    };
    let mut r = finish(cdt, m, &crit, scale, restricted, report, threads);
    if !quality {
        for u in &mut r.report.unfixable {
            if u.reason == UnfixableReason::Precision {
                u.reason = UnfixableReason::ConformingDelaunay;
            }
        }
    }
    r.report.encroached_subsegments = left;
    r.report.met &= left == 0;
    Ok(r)
}

/// The refinement loop: queues the bad triangles and encroached
/// subsegments among `scan` (all triangles when `None`), then splits and
/// inserts until both queues are empty (or the budget `limit` on
/// `*steiner` runs out). Returns false if quality refinement was stopped
/// for the conforming-Delaunay splits. Bad triangles given up on (no
/// point could be inserted for them) are pushed on `dropped`.
#[allow(clippy::too_many_arguments)]
fn run(
    m: &mut Mesh,
    crit: &Crit,
    max_areas: &[f64],
    options: &RefineOptions,
    limit: usize,
    steiner: &mut usize,
    report: &mut RefineReport,
    scan: Option<&[u32]>,
    mut dropped: Option<&mut Vec<u32>>,
) -> bool {
    let bad = |m: &Mesh, t: usize| bad_bucket(m, crit, max_areas, t);
    type Heap = Queue;
    let mut heap = Queue::new();
    let mut enc: VecDeque<u32> = VecDeque::new();
    let all = 0..m.tr.len() as u32;
    let seeds: &mut dyn Iterator<Item = u32> = match scan {
        Some(ts) => &mut ts.iter().copied(),
        None => &mut all.clone(),
    };
    for t in seeds {
        let t = t as usize;
        if let Some(k) = bad(m, t) {
            heap.push(k, t as u32, m.tr[t].v[0]);
        }
    }
    // Subsegments encroached by an apex.
    let check_sub = |m: &Mesh, t: usize, e: usize, enc: &mut VecDeque<u32>| {
        let s = m.sub_at(t, e);
        if s == NONE {
            return;
        }
        let [u, w] = m.subs[s as usize].v;
        let apex = m.tr[t].v[e];
        if encroaches(m.p(u), m.p(w), m.p(apex), m.cos2) {
            enc.push_back(s);
        }
    };
    let seeds: &mut dyn Iterator<Item = u32> = match scan {
        Some(ts) => &mut ts.iter().copied(),
        None => &mut all.clone(),
    };
    for t in seeds {
        for e in 0..3 {
            check_sub(m, t as usize, e, &mut enc);
        }
    }
    // The new triangles: bad ones are queued, their subsegments checked.
    let after_insert = |m: &Mesh, heap: &mut Heap, enc: &mut VecDeque<u32>| {
        for &t in &m.fan {
            let t = t as usize;
            if let Some(k) = bad(m, t) {
                heap.push(k, t as u32, m.tr[t].v[0]);
            }
            let tri = &m.tr[t];
            for e in 0..3 {
                let s = m.sub_at(t, e);
                if s != NONE {
                    let [u, w] = m.subs[s as usize].v;
                    if encroaches(m.p(u), m.p(w), m.p(tri.v[e]), m.cos2) {
                        enc.push_back(s);
                    }
                }
            }
        }
    };
    // Rounds of -D splits after the queues ran empty. Past 64 rounds, or
    // when quality refinement after the first round has added 8 times the
    // points there were, bad triangles are no longer fixed: near small input
    // angles and with high angle bounds the two can feed each other.
    const GABRIEL_ROUNDS: usize = 64;
    let mut gabriel_rounds = 0usize;
    let mut quality_cap = usize::MAX;
    let mut quality = true;
    let mut turns: u64 = 0;
    loop {
        turns += 1;
        if turns.is_multiple_of(8192) {
            crate::progress::report("refining", *steiner as u64, None, "Steiner points");
        }
        if enc.is_empty() && (heap.is_empty() || !quality) {
            // -D: split the subsegments any vertex encroaches, until none.
            if options.conforming_delaunay && m.scan_encroached(false, &mut enc) > 0 {
                gabriel_rounds += 1;
                if gabriel_rounds == 1 {
                    quality_cap = *steiner + 8 * (*steiner + m.nfixed) + 1024;
                }
                if gabriel_rounds > GABRIEL_ROUNDS {
                    // Splits and quality refinement keep feeding each other
                    // (high angle bounds near small input angles): finish
                    // with splits alone, which terminate (concentric shells).
                    quality = false;
                }
                continue;
            }
            break;
        }
        if *steiner >= limit || m.xy.len() >= (u32::MAX - 8) as usize {
            report.limit_reached = true;
            break;
        }
        if let Some(s) = enc.pop_front() {
            if m.split_sub(s).is_some() {
                *steiner += 1;
                report.segment_splits += 1;
                after_insert(m, &mut heap, &mut enc);
            }
            continue;
        }
        if *steiner > quality_cap {
            quality = false;
            continue;
        }
        let Some((t, v0)) = heap.pop() else {
            break;
        };
        let t = t as usize;
        if m.tr[t].v[0] != v0 {
            continue;
        }
        let v = m.tr[t].v;
        let tv = v;
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
            if let Some(d) = dropped.as_deref_mut() {
                d.push(t as u32);
            }
            continue;
        }
        // The triangle's circumcircle contains `c`, so the cavity can grow
        // from it: no point location needed.
        match m.insert(t, c, NONE, [NONE; 4], true) {
            Ins::Done(_) => {
                *steiner += 1;
                report.circumcenters += 1;
                after_insert(m, &mut heap, &mut enc);
            }
            Ins::Encroached => {
                report.rejected_circumcenters += 1;
                let mut any = false;
                for &s in &m.hit {
                    if !m.subs[s as usize].stuck {
                        enc.push_back(s);
                        any = true;
                    }
                }
                if any {
                    heap.push(0, t as u32, v0);
                } else if let Some(d) = dropped.as_deref_mut() {
                    d.push(t as u32);
                }
            }
            Ins::Blocked(s) => {
                report.rejected_circumcenters += 1;
                if !m.subs[s as usize].stuck {
                    enc.push_back(s);
                    heap.push(0, t as u32, v0);
                } else if let Some(d) = dropped.as_deref_mut() {
                    d.push(t as u32);
                }
            }
            Ins::Failed => {
                if let Some(d) = dropped.as_deref_mut() {
                    d.push(t as u32);
                }
            }
        }
    }
    drop(heap);
    drop(enc);
    quality
}

/// The extreme angles and the bad triangles among `triangles[from..]`
/// (see [`finish`]).
struct Assessed {
    /// (sin² of the smallest angle, triangle), first of the smallest.
    lo: (f64, usize),
    /// (cosine of the largest angle, triangle), first of the smallest.
    hi: (f64, usize),
    met: bool,
    unfixable: Vec<Unfixable>,
}

fn assess(
    m: &Mesh,
    crit: &Crit,
    triangles: &[[u32; 3]],
    max_areas: &[f64],
    from: usize,
    limit_reached: bool,
    restricted: bool,
) -> Assessed {
    let mut unfixable = Vec::new();
    let mut lo_t = (f64::INFINITY, usize::MAX);
    let mut hi_t = (f64::INFINITY, usize::MAX);
    let mut met = true;
    for (t, v) in triangles.iter().enumerate().skip(from) {
        let (a, b, c) = (m.p(v[0]), m.p(v[1]), m.p(v[2]));
        let (s2, d, k) = shape(a, b, c);
        if s2 < lo_t.0 {
            lo_t = (s2, t);
        }
        let l = [dist2(b, c), dist2(c, a), dist2(a, b)];
        let j = if l[0] >= l[1] && l[0] >= l[2] {
            0
        } else if l[1] >= l[2] {
            1
        } else {
            2
        };
        let (x, y) = (l[NEXT[j]], l[PREV[j]]);
        let cos = (x + y - l[j]) / (2.0 * (x * y).sqrt());
        if cos < hi_t.0 {
            hi_t = (cos, t);
        }
        let mut abound = crit.area2;
        if crit.regional && max_areas[t] > 0.0 {
            abound = abound.min(2.0 * max_areas[t] * crit.s2);
        }
        let too_big = d > abound;
        let lo = if s2 < crit.sin2 || too_big {
            angles(a, b, c).iter().copied().fold(180.0f64, f64::min)
        } else {
            180.0
        };
        let angle_bad = s2 < crit.sin2 && lo < crit.angle;
        let user_bad = !(too_big || angle_bad)
            && crit
                .user
                .is_some_and(|f| f(&crit.input(m, v), 0.5 * d / crit.s2));
        if !(too_big || angle_bad || user_bad) {
            continue;
        }
        met = false;
        let (u, w) = edge(v, k);
        let reason = match m.small_angle_apex(u, w, v[k], crit.angle) {
            Some((apex, input_angle)) if d <= abound && !user_bad => {
                UnfixableReason::SmallInputAngle { apex, input_angle }
            }
            _ if limit_reached => UnfixableReason::SteinerLimit,
            _ if restricted => UnfixableReason::NoSegmentSplits,
            _ => UnfixableReason::Precision,
        };
        unfixable.push(Unfixable {
            triangle: t as u32,
            min_angle: lo,
            area: 0.5 * d / crit.s2,
            reason,
        });
    }
    Assessed {
        lo: lo_t,
        hi: hi_t,
        met,
        unfixable,
    }
}

/// Builds the output mesh and the final statistics.
fn finish(
    cdt: &Cdt,
    m: Mesh,
    crit: &Crit,
    scale: (f64, f64),
    restricted: bool,
    mut report: RefineReport,
    threads: usize,
) -> Refined {
    let mut m = m;
    // What the output no longer needs goes first (peak memory).
    m.sides = Vec::new();
    m.cav = Vec::new();
    m.bnd = Vec::new();
    m.fan = Vec::new();
    m.stack = Vec::new();
    let nt = m.tr.len();
    let mut points = Vec::with_capacity(m.xy.len());
    points.extend_from_slice(&cdt.points);
    points.extend(
        m.xy[m.nfixed..]
            .iter()
            .map(|p| [p[0] / scale.1 / scale.0, p[1] / scale.1 / scale.0]),
    );
    // One pass over the triangle records for every per-triangle output.
    let mut triangles: Vec<[u32; 3]> = Vec::with_capacity(nt);
    let mut neighbors: Vec<[u32; 3]> = Vec::with_capacity(nt);
    let mut regions = Vec::with_capacity(nt);
    let mut attributes = Vec::with_capacity(nt);
    let mut max_areas: Vec<f64> = Vec::with_capacity(nt);
    for tri in &m.tr {
        let o = tri.orig as usize;
        triangles.push(tri.v);
        neighbors.push(
            tri.a
                .map(|x| if x == NONE { NONE } else { unpack(x).0 as u32 }),
        );
        regions.push(cdt.regions[o]);
        attributes.push(cdt.attributes[o]);
        max_areas.push(cdt.max_areas[o]);
    }
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
    // The extreme angles: the triangles with the smallest sin² of the
    // smallest angle and the smallest cosine of the largest angle, measured
    // exactly at the end (atan2 only there). In `threads` chunks, combined
    // in order (the same result for any number of chunks).
    let limit_reached = report.limit_reached;
    let chunks = if threads > 1 && crit.user.is_none() && triangles.len() >= 1 << 13 {
        threads
    } else {
        1
    };
    let step = triangles.len().div_ceil(chunks).max(1);
    let parts: Vec<Assessed> = if chunks == 1 {
        vec![assess(
            &m,
            crit,
            &triangles,
            &max_areas,
            0,
            limit_reached,
            restricted,
        )]
    } else {
        let detached = par::Detached::from(crit);
        let (mr, tr, ma) = (&m, &triangles, &max_areas);
        std::thread::scope(|sc| {
            let handles: Vec<_> = (1..chunks)
                .map(|k| {
                    sc.spawn(move || {
                        let crit = detached.crit();
                        let end = ((k + 1) * step).min(tr.len());
                        let lo = (k * step).min(end);
                        assess(mr, &crit, &tr[..end], ma, lo, limit_reached, restricted)
                    })
                })
                .collect();
            let mut v = vec![assess(
                mr,
                crit,
                &tr[..step.min(tr.len())],
                ma,
                0,
                limit_reached,
                restricted,
            )];
            v.extend(
                handles
                    .into_iter()
                    .map(|h| h.join().unwrap_or_else(|e| std::panic::resume_unwind(e))),
            );
            v
        })
    };
    let mut lo_t = (f64::INFINITY, usize::MAX);
    let mut hi_t = (f64::INFINITY, usize::MAX);
    let mut met = true;
    for p in parts {
        if p.lo.0 < lo_t.0 {
            lo_t = p.lo;
        }
        if p.hi.0 < hi_t.0 {
            hi_t = p.hi;
        }
        met &= p.met;
        report.unfixable.extend(p.unfixable);
    }
    let ang = |t: usize| {
        let v = triangles[t];
        angles(m.p(v[0]), m.p(v[1]), m.p(v[2]))
    };
    report.min_angle = if lo_t.1 == usize::MAX {
        180.0
    } else {
        ang(lo_t.1).iter().copied().fold(180.0f64, f64::min)
    };
    report.max_angle = if hi_t.1 == usize::MAX {
        0.0
    } else {
        ang(hi_t.1).iter().copied().fold(0.0f64, f64::max)
    };
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn queue_buckets_are_ordered_worst_first() {
        // Angle buckets: a smaller sin² ratio is worse (a smaller bucket).
        let qs = [0.0, 0.01, 0.2, 0.5, 0.9, 0.999];
        for w in qs.windows(2) {
            assert!(Queue::angle_bucket(w[0]) <= Queue::angle_bucket(w[1]));
        }
        assert!(Queue::angle_bucket(0.0) < Queue::angle_bucket(0.999));
        // Area buckets: a larger area ratio is worse, and after every angle
        // bucket.
        let rs = [1.0, 1.3, 2.0, 17.0, 1e6, 1e300];
        for w in rs.windows(2) {
            assert!(Queue::area_bucket(w[0]) >= Queue::area_bucket(w[1]));
        }
        assert!(Queue::area_bucket(4.0) < Queue::area_bucket(1.5));
        assert!(Queue::area_bucket(1e300) > Queue::angle_bucket(0.999));
        // Pop: lowest bucket first; oldest first within an angle bucket,
        // newest first within the others.
        let mut q = Queue::new();
        let area = Queue::area_bucket(2.0);
        q.push(5, 1, 1);
        q.push(area, 5, 9);
        q.push(3, 2, 4);
        q.push(5, 3, 7);
        q.push(area, 6, 9);
        q.push(0, 4, 0);
        q.push(0, 7, 0);
        let order: Vec<u32> = std::iter::from_fn(|| q.pop().map(|x| x.0)).collect();
        assert_eq!(order, vec![7, 4, 2, 1, 3, 6, 5]);
        assert!(q.is_empty());
        // A long angle bucket drops its popped front.
        for t in 0..10_000 {
            q.push(7, t, 0);
        }
        for t in 0..9_000 {
            assert_eq!(q.pop(), Some((t, 0)));
        }
        assert!(q.buckets[7].len() < 10_000);
        q.push(7, 42, 0);
        let rest: Vec<u32> = std::iter::from_fn(|| q.pop().map(|x| x.0)).collect();
        assert_eq!(rest.len(), 1_001);
        assert_eq!(rest[..2], [9_000, 9_001]);
        assert_eq!(rest[1_000], 42);
    }
}
