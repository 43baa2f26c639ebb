//! Options, reports and budgets of the refinement (re-exported by the
//! parent module).

use crate::tri::constrain::Cdt;

/// Options of [`refine`](super::refine), named by meaning; each names Triangle's switch.
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
    /// values and 60 or more are refused ([`Error::InvalidBound`](crate::Error::InvalidBound)).
    pub min_angle: Option<f64>,
    /// Global maximum triangle area (`-a` with a number). `None`: no bound.
    /// NaN, zero and negative values are refused ([`Error::InvalidBound`](crate::Error::InvalidBound)).
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
    /// [`check_conforming_delaunay`](crate::tri::conforming::check_conforming_delaunay)).
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
    /// [module docs](super#parallel-refinement)), which these threads run;
    /// the number of parts, and so the result, does not depend on it: any
    /// thread count gives the same mesh. Parts are not used with
    /// [`Self::conforming_delaunay`], [`Self::max_steiner`] or a user's test
    /// ([`refine_with`](super::refine_with)). 0 counts as 1.
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
/// guarantees (about 34°, see the [module docs](super#termination-and-the-budget))
/// stops after at most 2 M points + 16 per input vertex, a few hundred MB.
///
/// ```
/// use delone::tri::refine::{default_budget, BUDGET_BASE, BUDGET_MAX};
/// assert_eq!(default_budget(100, 0.0), BUDGET_BASE + 1600);
/// assert_eq!(default_budget(100, 1e6), BUDGET_BASE + 1600 + 2_000_000);
/// assert_eq!(default_budget(100, 1e12), BUDGET_MAX);
/// ```
pub fn default_budget(input_points: usize, predicted_triangles: f64) -> usize {
    crate::geom::steiner_budget((BUDGET_BASE, BUDGET_MAX), input_points, predicted_triangles)
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

/// What [`refine`](super::refine) did and what it reached.
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

/// A user's test of a triangle (its corners counterclockwise and its area,
/// in input units): true if it must be refined (Triangle's `-u`).
pub type UserTest<'a> = &'a dyn Fn(&[[f64; 2]; 3], f64) -> bool;
