//! Mesh optimisation of a finished tetrahedral mesh (`-O`): slivers and
//! other poorly shaped tetrahedra are removed by local operations, after
//! Klingner & Shewchuk ("Aggressive tetrahedral mesh improvement", 2007) and
//! Freitag & Ollivier-Gooch (1997).
//!
//! The operations work on the crate's constrained domain mesh
//! (`tet::dmesh`; the boundary and interface faces are its
//! subfaces, never destroyed but by boundary flips within one flat facet):
//! [`optimize`] builds it from the [`Recovered`] mesh's neighbour lists;
//! after refinement the crate-internal `optimize_in_place` continues on the
//! mesh the refinement handed over. Edge removal's ring walk and dynamic
//! program (here maximising the smallest quality) are the ones recovery
//! and the domain mesh share.
//!
//! The quality of a tetrahedron is the smallest sine of its six dihedral
//! angles (scale invariant, small for an angle near 0° *or* near 180°).
//! Tetrahedra below the target (`sin` of [`OptimizeOptions::target_dihedral`])
//! are visited worst first, and for each one the first of these that raises
//! the worst quality of the tetrahedra it touches is applied (hill climbing):
//!
//! 1. **topological**: removal of each of its six edges (the `n`
//!    tetrahedra around the edge become `2n - 4`, the triangulation of the
//!    ring chosen by dynamic programming to maximise the *minimum* quality;
//!    `n = 3` is the 3-2 flip, `n = 4` the 4-4 flip) or the 2-3 flip of each
//!    of its faces — the best of them;
//! 2. **smoothing** of each of its free vertices: the vertex moves along
//!    the steepest ascent direction of the minimum quality of its star (the
//!    least-norm point of the near-active gradients) with a backtracking
//!    line search, never inverting a tetrahedron (exact `orient3d` on the
//!    result);
//! 3. **insertion** of a vertex at the tetrahedron's centroid, in its
//!    Delaunay cavity (the tetrahedra of the region, reached across open
//!    faces, whose circumsphere holds it; at most 48) or else the cavity
//!    made of it and its neighbours, followed by smoothing of the new
//!    vertex and flips and smoothing of the worst new tetrahedra; undone
//!    unless the cavity's worst quality improves. This is what removes
//!    slivers whose four vertices are fixed. A flat tetrahedron whose four
//!    vertices are on the surface (a layer of them along a facet, where
//!    every centroid or midpoint is on the sheet too) gets a point *lifted*
//!    off its largest face along the normal, in the cavity reached by a
//!    visibility walk and closed under visibility; for the flattest (below
//!    about 3°) this is tried before anything else.
//! 4. **collapse** of a free vertex that the optimisation itself inserted
//!    onto the neighbour that gives its star the best worst quality (the
//!    tetrahedra around the edge vanish; valid when the new tetrahedra are
//!    exactly positive and the link condition holds): an inserted point
//!    that settled badly among fixed ones is taken out again.
//!
//! The topological step also tries **multi-face removal** (the `2k`
//! tetrahedra on both sides of `k` faces sandwiched between two vertices
//! become the `k + 2` around the new edge between them) and, for an edge
//! on the boundary inside a flat facet, **boundary edge removal** (its two
//! boundary faces flipped to the other diagonal of their quadrilateral —
//! exactly coplanar, on one facet — and the tetrahedra of its fan
//! re-triangulated by the same dynamic programme: the 2-2 flip and its
//! generalisation).
//!
//! Interior points (of the refinement too, never input points) are also
//! collapsed in a sweep before the stages where that raises their star's
//! worst quality, and the points the optimisation inserted in a sweep
//! after them where every new tetrahedron stays above 25° and the mesh's
//! minimum — fewer tetrahedra for the same bound.
//! Removed points are left out of the result and the others renumbered in
//! order ([`OptimizeReport::removed`]).
//!
//! The work is organised in stages of rising thresholds (10°, 15°, 20°,
//! 30°, then the target): each stage keeps a queue of the tetrahedra below
//! its threshold, worst first, pushes the tetrahedra each success creates
//! or reshapes, and skips a tetrahedron that failed until the star of one
//! of its vertices changes; a stage ends when a round over its queue
//! succeeds nowhere or its attempts ([`OptimizeOptions::max_passes`] per
//! queued tetrahedron) are spent. A trial insertion is settled (flips and
//! smoothing around the new vertex) cheaply at first: it is given up as
//! soon as its worst new tetrahedron resists; when a round succeeds
//! nowhere, the tetrahedra left get a round with every insertion settled
//! fully. A mesh of up to 40,000 tetrahedra left below 15° (or above 165°)
//! may be optimised once more from the start with every insertion settled
//! fully, and the better of the two results is kept (see the rules
//! below for when). A stage also ends
//! when it stops paying: checked every 10 evaluations per tetrahedron
//! (of at most 50,000 counted, plus 2000: the tries that make progress
//! are local, so the window does not grow with the mesh), it
//! ends once neither its worst quality nor its count of tetrahedra below
//! the threshold improved over the last half of its evaluations (and two
//! such windows); a stage above the lowest that starts with the mesh
//! within the bound ([`OptimizeOptions::min_dihedral`]) waits for the last
//! quarter only (not in a second run, nor an exhaustive one:
//! [`OptimizeOptions::exhaustive`]). Measured at `-pq1.414` on the closed
//! corpus models, the stages above 10° reached their final worst angle
//! after 10–70% of their evaluations and then spent the rest lifting a
//! few tetrahedra near the threshold at 10,000–30,000 evaluations each,
//! most of it in trial insertions that were undone; but a wait of two
//! windows cost cgal_homer 2.3° (a dry spell of a million evaluations
//! in its stage below 15°, then 600 tetrahedra lifted), cgal_pipe its
//! 15° and the lowest stage 1,000 more tetrahedra below 10° on
//! cgal_handle. While
//! the worst is below half the threshold (held by the input, as a rule),
//! the count improves only when a window lifts at least 1% of the count
//! the stage started with: on cgal_handle the stage below 10° otherwise
//! spends its whole budget at about 9,000 evaluations per tetrahedron
//! lifted, its minimum pinned at 0°. Each stage's work, gain, the work it
//! had spent when its worst last rose ([`StageReport::worst_reached`]) and
//! its reason for ending are reported ([`OptimizeReport::stages`]). On the
//! closed corpus models whose minimum ends above 20° at `-pq1.414`, the
//! stage below 30° (which spends most of their evaluations) raises its
//! worst until its budget runs out (cgal_oblong 20.0° → 24.8°, cgal_knot1
//! 20.0° → 25.6°): there the budget decides the minimum. The
//! whole run stops when its budget of quality
//! evaluations ([`OptimizeOptions::effort`]) is spent: the worst are
//! treated first, so the budget cuts the least useful work. The stages up
//! to 20°, which decide the minimum, may spend four times the budget, and
//! as much again for meshes up to 50,000 tetrahedra (a
//! refined mesh with many flat tetrahedra left near small input features
//! spends the plain budget before its worst are settled; a fair mesh
//! finishes them well within it). The stages
//! above 20° (which mostly thin the histogram's tail once the worst are
//! settled) may spend at most `0.4 effort` per tetrahedron (plus 8000
//! evaluations' worth), and nothing beyond the plain budget, which bounds
//! the time on large meshes. Quality is
//! cached per slot; the edge-removal programme prunes every sub-polygon
//! that cannot beat the ring's worst tetrahedron, and the smoothing line
//! search leaves out the star tetrahedra far above the worst (checked once
//! at the end).
//! The domain's boundary and internal facets keep their shape: interface
//! faces are never destroyed, boundary faces only by a boundary flip
//! within one flat facet (each facet stays the union of its faces), input
//! points never move, and a
//! Steiner point of the surface moves only within its input triangle's
//! plane or along its input edge, landing exactly on it (or, if the
//! refinement had already rounded it off, within the reported deviation;
//! see [`OptimizeOptions::smooth_boundary`]); every tetrahedron keeps its
//! region, so the surface, the volume, the regions and
//! [`super::recover::check_recovered`] are preserved. The order of work is
//! deterministic (ties broken by slot).
//!
//! # More rules
//!
//! * The second run of a small mesh is tried only where it may win: where
//!   the first run spent its budget in its lowest stage (which never
//!   settled: cgal_part at `-pq1.414`, 6.2° → 8.2°) or its stage at the
//!   bound ended with nothing left to improve, so that a second path costs
//!   no more than the first (cgal_am at `-pq1.414/20`, 17.9° → 18.9°;
//!   cgal_dragknob then meets 20°). Where the first run's stages up to the
//!   bound ran out of budget or stopped paying, the second one ran out too
//!   and lost or tied on every measured model (cgal_rotor 8.9° against
//!   9.8°, cgal_pipe, meshlab_knot, cgal_spool, wm_supershape1) at twice
//!   the time. [`OptimizeOptions::exhaustive`] tries it whenever the worst
//!   is not pinned (the next rule).
//! * The second run of a small mesh is skipped when the first run's worst
//!   tetrahedron is held by the input — two of its faces on the surface, or
//!   its four vertices fixed ([`StuckReason`]) — or sits at a nearly
//!   degenerate input triangle (an angle below 0.1° or above 179.9°,
//!   `RETRY_FEATURE_ANGLE`): it is pinned there, and a second run only
//!   doubles the time.
//! * The extra budget of the stages up to 20° on meshes up to 50,000
//!   tetrahedra applies once the mesh's minimum is above 10° (`LOW_CAP`,
//!   `EXTRA_ABOVE`): below 10° the minimum is mostly held by needle input
//!   triangles and the extra only adds vertices.
//! * A tetrahedron `a b c m` with two boundary faces, `a b c` and a
//!   zero-area `b c m` through a Steiner point `m` rounded onto the edge
//!   `b c`, is one no flip, smoothing or insertion can touch; before the
//!   stages it is removed when `m` is a listed inexact point strictly
//!   between `b` and `c`, its faces `a b m`, `a m c` becoming boundary faces
//!   ([`OptimizeReport::flat_removed`]). The recovery removes such cells
//!   after carving, so this pass is a guard.
//! * The report gives the statistics before and after, the stuck
//!   tetrahedra with their reasons, shape, surface faces and the input
//!   triangle at each (`Stuck::near_triangle`), and the bounds no mesh can
//!   beat: `input_min_dihedral` (the smallest angle of the surface, per edge
//!   of the boundary, interfaces and regions) and the extreme angles of the
//!   input triangles. [`OptimizeReport::bad`] splits the tetrahedra left
//!   below the dihedral bound D (`-qB/D`, default 15°) into forced (the
//!   small angle at a surface edge whose own angle is below D), next to a
//!   needle or cap input triangle, and free. D is also a stage (with the
//!   budget of the stages that decide the minimum), the target is raised to
//!   it, and the second run is decided against it. The refinement does not
//!   use D: splitting slivers at their circumcentres makes new ones.
//! * Keeping the radius-edge bound by default (`--keep-ratio` asks for it)
//!   costs most of the dihedral gain (cgal_knot at q1.414: 19.8° → 4.7°),
//!   so the size bounds are kept and the radius-edge bound is traded for
//!   dihedral angles.

mod limits;
mod work;

use std::cmp::Ordering;
use std::collections::BinaryHeap;
use std::fmt;

use super::dmesh::DomainMesh;
use super::quality::TetStats;
use super::recover::Recovered;
use crate::geom::ids::{IdMap, IdSet};
use crate::geom::vec3::{cross, dot, norm, sub};
use crate::tet::local::{face, fkey};
use crate::NONE;
use work::{Plan, Slide, Work, DEAD};

/// Thresholds (degrees) of the stages below the target.
const STAGES: [f64; 4] = [10.0, 15.0, 20.0, 30.0];

/// Share of [`OptimizeOptions::effort`] per tetrahedron that the stages
/// above 20° may spend (plus a fixed 8000 evaluations' worth).
const POLISH: f64 = 0.4;

/// Multiple of the budget ([`OptimizeOptions::effort`]) that the stages up
/// to 20° may spend.
const LOW: f64 = 4.0;

/// Most tetrahedra (plus 2000) for which the stages up to 20° get their
/// budget twice (see [`optimize`]).
const LOW_CAP: usize = 50_000;

/// Smallest dihedral angle (degrees) of the mesh above which the stages up
/// to 20° get that extra budget.
const EXTRA_ABOVE: f64 = 10.0;

/// Dihedral angle (degrees) below which the polishing stages (above 20°)
/// still insert vertices: above it they only flip, smooth and collapse (an
/// insertion there buys a few degrees of the histogram's tail for more
/// tetrahedra).
const POLISH_INSERT: f64 = 30.0;

/// Evaluations per tetrahedron (plus 2000) between two checks of a stage's
/// progress (see [`optimize`]).
const WINDOW: f64 = 10.0;

/// Most tetrahedra counted in a stage's window (see [`WINDOW`]): a
/// stage's progress is made by local tries (a flip, a smoothing, a trial
/// insertion of a few thousand evaluations each), so the work that shows
/// whether a stage still pays does not grow with the mesh. Uncapped, a
/// window of a 600,000-tetrahedron mesh held about 300 tries, and each
/// stage above 10° on c3d_nefertiti at `-pq1.5/20` spent 12–18 million
/// evaluations on tries at tetrahedra pinned by needle input triangles
/// (85% of them in undone insertions) while its count below the threshold
/// rose.
const WINDOW_CAP: usize = 50_000;

/// Windows without progress that always leave a stage going.
const PATIENCE: u64 = 2;

/// A stage above the lowest that starts with the mesh within the bound
/// stops paying once the last `1 / UPPER_SHARE` of its evaluations (or
/// [`PATIENCE`] windows) brought no progress (see [`optimize`]); the
/// others wait for the last half.
const UPPER_SHARE: u64 = 4;

/// Share of a stage's starting count below its threshold that a window
/// must lift while the worst tetrahedron is below half the threshold
/// (see [`optimize`]).
const MIN_LIFT: f64 = 0.01;

/// Most tetrahedra in the Delaunay cavity of an inserted vertex.
const MAX_CAVITY: usize = 48;

/// Most tetrahedra in the cavity of a lifted point (see `try_lifted`):
/// the layers of flat tetrahedra above a sheet can be many.
const MAX_LIFTED_CAVITY: usize = 128;

/// A queued tetrahedron: quality, slot, vertices; the heap pops the worst
/// (ties by slot).
struct Entry(f64, u32, [u32; 4]);

impl PartialEq for Entry {
    fn eq(&self, o: &Self) -> bool {
        self.cmp(o) == Ordering::Equal
    }
}
impl Eq for Entry {}
impl PartialOrd for Entry {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Entry {
    fn cmp(&self, o: &Self) -> Ordering {
        o.0.total_cmp(&self.0).then(o.1.cmp(&self.1))
    }
}

/// Options of [`optimize`].
///
/// ```
/// use delone::tet::optimize::OptimizeOptions;
/// let o = OptimizeOptions { target_dihedral: 30.0, ..Default::default() };
/// assert!(o.flips && o.smooth && o.insert);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct OptimizeOptions {
    /// Dihedral angle target (degrees): tetrahedra with an angle below it
    /// or above `180 -` it are worked on. Default 40.
    pub target_dihedral: f64,
    /// Attempts per tetrahedron queued at the start of a stage (0: do
    /// nothing). Default 6.
    pub max_passes: usize,
    /// Use edge removal and 2-3 / 3-2 / 4-4 flips. Default true.
    pub flips: bool,
    /// Use vertex smoothing. Default true.
    pub smooth: bool,
    /// Let smoothing move the Steiner points of the surface too: one inside
    /// an input triangle within that triangle's plane, one on an input edge
    /// along the edge (input points never move). A moved point lies exactly
    /// on its plane or line (exact `orient3d` / collinearity) — or, when it
    /// was already off it by rounding (listed in
    /// [`Recovered::inexact`](super::recover::Recovered::inexact)), within
    /// the reported deviation — else the move is refused. Default true.
    pub smooth_boundary: bool,
    /// Insert vertices where nothing else helps. Default true.
    pub insert: bool,
    /// Most vertices inserted (in addition to the mesh's). Default: a
    /// tenth of the number of tetrahedra.
    pub max_inserted: Option<usize>,
    /// Work allowed, in quality evaluations per tetrahedron of the input
    /// mesh plus 2000 (a deterministic measure of time: the worst tetrahedra are
    /// worked on first, so a budget cuts where it matters least).
    /// Default `Some(100.0)`; `None`: no limit.
    pub effort: Option<f64>,
    /// How many of the mesh's points are input points: those never move
    /// (`check_recovered` wants them unchanged), even when they are not on
    /// a face of the surface. `None`: every point that is not a Steiner
    /// point of the recovery (`points.len() - report.steiner()`) — pass
    /// the input's count for a refined mesh, whose refinement points would
    /// otherwise stay in place.
    pub input_points: Option<usize>,
    /// A radius-edge bound to keep (`-q` with `--keep-ratio`): no
    /// operation makes a tetrahedron above it (or worse than the worst it
    /// removes). Default `None` (see [`OptimizeOptions::keeping`] for its
    /// cost).
    pub max_radius_edge: Option<f64>,
    /// The refinement's global volume bound to keep (`-a`). The regions'
    /// own bounds ([`MeshRegion::max_volume`](crate::tet::recover::MeshRegion))
    /// are always kept. Default `None`.
    pub max_volume: Option<f64>,
    /// The refinement's sizing to keep (`-m`): no operation makes a
    /// tetrahedron whose circumradius exceeds the refinement's bound
    /// 0.612 h at its circumcentre. Default none.
    pub sizing: crate::tet::refine::sizing::Sizing,
    /// The dihedral bound asked for (degrees; `delone tet -qB/D`): the
    /// tetrahedra left with an angle below it or above `180 -` it are
    /// counted and explained in [`OptimizeReport::bad`]; it is one of the
    /// optimisation's stages (the target is raised to it when lower), and a
    /// small mesh left outside it may be optimised a second time (see
    /// [`optimize`]). Default [`BAD_ANGLE`] (15°).
    pub min_dihedral: f64,
    /// Gather the report's diagnostics, which only explain the result: the
    /// statistics before ([`OptimizeReport::before`]), the tetrahedra left
    /// below the target ([`OptimizeReport::stuck`],
    /// [`OptimizeReport::stuck_counts`]), the input surface's bounds
    /// (`input_min_dihedral`, `triangles_*`) and the split of the
    /// tetrahedra outside the bound ([`OptimizeReport::bad`]): passes over
    /// the mesh and its surface, about 5% of a large `-pq` run. Default
    /// true; false leaves them at their defaults (but for the stuck
    /// tetrahedra of a mesh small enough for a second run, which decide
    /// it; `after`, the counters and the stages are always given) and the
    /// mesh is the same.
    pub diagnostics: bool,
    /// The exhaustive polish: every stage waits for half its evaluations
    /// without progress before it stops paying, and a small mesh left
    /// outside [`OptimizeOptions::min_dihedral`] is optimised a second time
    /// whenever its worst tetrahedron is not pinned by the input (see
    /// [`optimize`]). On the closed corpus models below 8000 triangles at
    /// `-pq1.414` it spends 7% more quality evaluations than the default
    /// (all of them on cgal_rotor's second run, which it throws away);
    /// at `-pq1.414/20` it wins on no model where the default does not try
    /// it. Default false; true from [`OptimizeOptions::level`] 4 on (with
    /// more passes and effort).
    pub exhaustive: bool,
}

impl Default for OptimizeOptions {
    fn default() -> Self {
        OptimizeOptions {
            target_dihedral: 40.0,
            max_passes: 6,
            flips: true,
            smooth: true,
            smooth_boundary: true,
            insert: true,
            max_inserted: None,
            effort: Some(100.0),
            input_points: None,
            max_radius_edge: None,
            max_volume: None,
            sizing: crate::tet::refine::sizing::Sizing::None,
            min_dihedral: BAD_ANGLE,
            diagnostics: true,
            exhaustive: false,
        }
    }
}

impl OptimizeOptions {
    /// These options keeping the size bounds of a refinement with `r`
    /// (its global `max_volume` and its sizing; the regions' own volume
    /// bounds are always kept), so that `-O` after `-a` or `-m` never
    /// leaves a tetrahedron the refinement would have split for its size. The radius-edge bound is **not** kept unless
    /// [`OptimizeOptions::max_radius_edge`] is set as well: keeping it
    /// costs much of what the optimisation gains (on the closed corpus
    /// models at `-q1.414` the smallest dihedral angle fell from
    /// 19.8° to 4.7° on cgal_knot, 24.3° to 6.0° on cgal_oblong), since
    /// removing a sliver often needs a slightly longer tetrahedron.
    ///
    /// ```
    /// use delone::tet::optimize::OptimizeOptions;
    /// use delone::tet::refine::RefineOptions;
    /// let r = RefineOptions { max_radius_edge: Some(1.414), max_volume: Some(0.1), ..Default::default() };
    /// let o = OptimizeOptions::default().keeping(&r);
    /// assert_eq!((o.max_radius_edge, o.max_volume), (None, Some(0.1)));
    /// let strict = OptimizeOptions { max_radius_edge: r.max_radius_edge, ..o };
    /// assert_eq!(strict.max_radius_edge, Some(1.414));
    /// ```
    pub fn keeping(self, r: &crate::tet::refine::RefineOptions) -> Self {
        OptimizeOptions {
            max_volume: r.max_volume.filter(|v| *v > 0.0),
            sizing: r.sizing.clone(),
            ..self
        }
    }

    /// Options for a TetGen-like level (`-O<level>`): 0 does nothing, 1
    /// flips only, 2 flips and smoothing, 3 and above everything; 4 and
    /// above the exhaustive polish ([`OptimizeOptions::exhaustive`]) with
    /// more passes and effort for higher levels.
    ///
    /// ```
    /// use delone::tet::optimize::OptimizeOptions;
    /// assert_eq!(OptimizeOptions::level(0).max_passes, 0);
    /// assert!(!OptimizeOptions::level(1).smooth);
    /// assert!(OptimizeOptions::level(3).insert);
    /// assert!(!OptimizeOptions::level(3).exhaustive && OptimizeOptions::level(4).exhaustive);
    /// ```
    pub fn level(level: u32) -> Self {
        let d = OptimizeOptions::default();
        match level {
            0 => OptimizeOptions { max_passes: 0, ..d },
            1 => OptimizeOptions {
                smooth: false,
                insert: false,
                ..d
            },
            2 => OptimizeOptions { insert: false, ..d },
            3 => d,
            l => OptimizeOptions {
                max_passes: d.max_passes + 5 * (l as usize - 3),
                effort: d.effort.map(|e| e * f64::from(1 + 2 * (l - 3))),
                exhaustive: true,
                ..d
            },
        }
    }
}

/// Why a tetrahedron is still below the target after [`optimize`].
///
/// ```
/// use delone::tet::optimize::StuckReason;
/// assert_eq!(StuckReason::SurfaceFaces.to_string(), "two faces on the fixed surface");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
#[non_exhaustive]
pub enum StuckReason {
    /// Two or more of its faces are on the boundary or an internal facet:
    /// its worst angle is (nearly) an angle of the input surface.
    SurfaceFaces,
    /// All four vertices are on the fixed surface (none can move) and no
    /// flip or insertion helped.
    AllVerticesFixed,
    /// No operation improved it.
    NoImprovement,
}

impl fmt::Display for StuckReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            StuckReason::SurfaceFaces => "two faces on the fixed surface",
            StuckReason::AllVerticesFixed => "all four vertices on the fixed surface",
            StuckReason::NoImprovement => "no operation improved it",
        })
    }
}

/// A tetrahedron left below the target.
///
/// ```
/// use delone::tet::optimize::{Stuck, StuckReason};
/// use delone::tet::quality::TetShape;
/// let s = Stuck {
///     tet: 3,
///     dihedral: [4.0, 170.0],
///     reason: StuckReason::NoImprovement,
///     shape: TetShape::Sliver,
///     surface_faces: 0,
///     input_vertices: 2,
///     fixed_vertices: 3,
///     near_triangle: Some(7),
///     near_angles: [2.5, 170.0],
/// };
/// assert!(s.dihedral[0] < 15.0);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Stuck {
    /// Its index in the optimised mesh.
    pub tet: usize,
    /// Its smallest and largest dihedral angles (degrees).
    pub dihedral: [f64; 2],
    /// Why it could not be improved.
    pub reason: StuckReason,
    /// Its kind ([`tet_shape`](super::quality::tet_shape)).
    pub shape: super::quality::TetShape,
    /// How many of its faces are on the boundary or an internal facet.
    pub surface_faces: usize,
    /// How many of its vertices are input points.
    pub input_vertices: usize,
    /// How many of its vertices could not move (input points, and surface
    /// points with neither a planar nor a straight neighbourhood).
    pub fixed_vertices: usize,
    /// The input triangle at the tetrahedron: of the triangles of
    /// [`Recovered::surface`] within its longest edge of its centroid, the
    /// one with the smallest angle (else the nearest one), named by its
    /// input triangle (`surface_origin`); `None` without a surface. A
    /// small or flat angle there is a feature of the input smaller than
    /// the mesh around it: the cause of most tetrahedra left below 15°.
    pub near_triangle: Option<u32>,
    /// The smallest and largest angle (degrees) of that triangle (of
    /// `surface`: for a merged coplanar group, of its re-triangulation).
    pub near_angles: [f64; 2],
}

/// The tetrahedra left with a dihedral angle below `angle`
/// ([`OptimizeOptions::min_dihedral`], default [`BAD_ANGLE`]; or above
/// `180 -` it), by what is at them: the input's own angle, a needle or cap
/// input triangle, or nothing the input forces.
///
/// ```
/// use delone::tet::optimize::BadCells;
/// let b = BadCells { angle: 15.0, count: 5, sharp_edge: 2, at_feature: 3, free: 0, feature_angle: 4.5 };
/// assert_eq!(b.count, b.sharp_edge + b.at_feature + b.free);
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
pub struct BadCells {
    /// The bound (degrees).
    pub angle: f64,
    /// How many tetrahedra have an angle below `angle` or above `180 -`
    /// it.
    pub count: usize,
    /// Of them: those with such a small angle at an edge of the surface
    /// where the input's own angle (of their region, the sum of the
    /// tetrahedra's angles there) is below `angle` — forced by the
    /// input.
    pub sharp_edge: usize,
    /// Of the others: those with a vertex on a boundary face that lies on
    /// an input triangle with an angle below `angle` or above `180 -`
    /// it (a needle or cap: a feature smaller than the mesh around it, which
    /// the refinement does not resolve).
    pub at_feature: usize,
    /// The rest: not at anything of the input that explains them.
    pub free: usize,
    /// The largest, over the `at_feature` tetrahedra, of their input
    /// triangle's deviation (its smallest angle, or 180 minus its largest,
    /// whichever is smaller; degrees): all of them are at input triangles
    /// with an angle below it or above `180 -` it. 0 when there are none.
    pub feature_angle: f64,
}

/// The default dihedral bound (degrees; [`OptimizeOptions::min_dihedral`]):
/// below it (or above `180 -` it) a tetrahedron is counted in [`BadCells`].
pub const BAD_ANGLE: f64 = 15.0;

/// What [`optimize`] did.
///
/// ```
/// use delone::tet::optimize::OptimizeReport;
/// let r = OptimizeReport::default();
/// assert_eq!(r.flips23 + r.flips32 + r.flips44 + r.edge_removals, 0);
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
pub struct OptimizeReport {
    /// Quality before.
    pub before: TetStats,
    /// Quality after.
    pub after: TetStats,
    /// Stages run (thresholds 10°, 20°, 30°, then the target).
    pub passes: usize,
    /// The smallest dihedral angle of the input surface (degrees): at each
    /// edge of the boundary or of an internal facet, the angle of each
    /// region around it (the sum of its tetrahedra's angles there). No
    /// tetrahedron at that edge can have a smaller angle, so the mesh's
    /// minimum cannot exceed it; 360 when there is no such edge.
    pub input_min_dihedral: f64,
    /// The surface edge (point ids, smaller first) where
    /// `input_min_dihedral` is found; `None` when there is no such edge.
    pub input_min_edge: Option<[u32; 2]>,
    /// The smallest dihedral angle inside the domain between two input
    /// triangles (of `Recovered::surface`) on the boundary that share an
    /// edge (degrees; 360 when there is none): the input's own bound,
    /// whatever the refinement did to the surface. Edges with more than two
    /// triangles are left out.
    pub triangles_min_dihedral: f64,
    /// The input edge (point ids, smaller first) where
    /// `triangles_min_dihedral` is found.
    pub triangles_min_edge: Option<[u32; 2]>,
    /// The smallest angle (degrees) of the triangles the mesh conforms to
    /// ([`Recovered::surface`]: the input triangles, a merged coplanar
    /// group re-triangulated); 180 when there are none. A needle (small
    /// angle) or a cap (an angle near 180°) is a feature that the
    /// refinement must resolve to reach the target near it; an angle of
    /// (nearly) 0° forces a flat tetrahedron on it.
    pub triangles_min_angle: f64,
    /// The input triangle with that angle (`surface_origin` of the
    /// surface triangle).
    pub triangles_min_angle_triangle: Option<u32>,
    /// The largest angle (degrees) of those triangles; 0 when there are
    /// none. Near 180° it forces a dihedral angle near 180° on a
    /// tetrahedron on it, unless its long edge is split.
    pub triangles_max_angle: f64,
    /// The input triangle with that angle.
    pub triangles_max_angle_triangle: Option<u32>,
    /// Quality evaluations spent (by both runs when a small mesh is
    /// optimised twice).
    pub evaluations: u64,
    /// True when [`OptimizeOptions::effort`] ran out.
    pub effort_exhausted: bool,
    /// 2-3 flips.
    pub flips23: usize,
    /// 3-2 flips (edge removals with 3 tetrahedra around the edge).
    pub flips32: usize,
    /// 4-4 flips.
    pub flips44: usize,
    /// Edge removals with 5 or more tetrahedra around the edge.
    pub edge_removals: usize,
    /// Removals of an edge on the boundary inside a flat facet (the
    /// boundary faces on either side flipped to the other diagonal: a 2-2
    /// flip with two tetrahedra around the edge, else the tetrahedra of
    /// the edge's fan re-triangulated).
    pub boundary_flips: usize,
    /// Multi-face removals (`2k` tetrahedra on both sides of `k` faces
    /// replaced by the `k + 2` around a new edge; `k >= 2`).
    pub multi_face: usize,
    /// Accepted vertex moves.
    pub smoothed: usize,
    /// Vertices inserted.
    pub inserted: usize,
    /// Insertions tried and undone.
    pub insert_undone: usize,
    /// Vertices inserted by the optimisation and removed again (collapsed
    /// onto a neighbour) where that improved their star.
    pub collapsed: usize,
    /// Interior points of the mesh given (Steiner points of the refinement
    /// or recovery, never input points) removed by collapsing them onto a
    /// neighbour before the stages, where that improves their star. The
    /// points after them are renumbered down.
    pub removed: usize,
    /// Flat tetrahedra removed from the boundary: two boundary faces, one
    /// of them of zero area (a Steiner point rounded off the edge it
    /// splits, under a chord of that edge); their other two faces became
    /// boundary faces on the same input triangle. The recovery removes the
    /// ones it makes (`RecoverReport::chord_slivers`), so this is a guard.
    pub flat_removed: usize,
    /// Tetrahedra below the target afterwards, per reason (in
    /// [`StuckReason`] order: surface faces, all vertices fixed, no
    /// improvement).
    pub stuck_counts: [usize; 3],
    /// The worst of them (at most 32), worst first.
    pub stuck: Vec<Stuck>,
    /// The tetrahedra left below 15° (or above 165°), by cause.
    pub bad: BadCells,
    /// The stages run, in order (of both runs when a small mesh is
    /// optimised twice).
    pub stages: Vec<StageReport>,
}

/// Why a stage of [`optimize`] ended.
///
/// ```
/// use delone::tet::optimize::StageStop;
/// assert_eq!(StageStop::Stalled.to_string(), "stopped paying");
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum StageStop {
    /// A round over its queue succeeded nowhere (or the queue was empty).
    #[default]
    Settled,
    /// Its attempts ([`OptimizeOptions::max_passes`] per queued
    /// tetrahedron) were spent.
    Attempts,
    /// It stopped paying: neither its worst quality nor its count below the
    /// threshold improved over the last half of its evaluations (a quarter
    /// for a stage above the lowest that started within the bound; see
    /// [`optimize`]).
    Stalled,
    /// The effort budget ([`OptimizeOptions::effort`]) ran out; the run
    /// ends.
    Budget,
    /// A stop was requested (`progress::stop_requested`); the run ends.
    Interrupted,
}

impl fmt::Display for StageStop {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            StageStop::Settled => "nothing left to improve",
            StageStop::Attempts => "attempts spent",
            StageStop::Stalled => "stopped paying",
            StageStop::Budget => "effort budget spent",
            StageStop::Interrupted => "interrupted",
        })
    }
}

/// What one stage of [`optimize`] did: its threshold, the work it spent and
/// what it gained.
///
/// ```
/// use delone::tet::optimize::{StageReport, StageStop};
/// let s = StageReport { threshold: 10.0, stop: StageStop::Stalled, ..Default::default() };
/// assert_eq!(s.evaluations, 0);
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StageReport {
    /// Its threshold (degrees): it works on the tetrahedra with a dihedral
    /// angle below it or above `180 -` it.
    pub threshold: f64,
    /// True for a stage of the second run of a small mesh (every trial
    /// insertion settled fully).
    pub second_run: bool,
    /// Quality evaluations it spent.
    pub evaluations: u64,
    /// Of them, those spent in trial insertions that were undone.
    pub undone_evaluations: u64,
    /// Of them, those spent until its worst quality last rose (seen at
    /// each check of its progress and at its end; 0 when it never rose):
    /// the rest went to the tetrahedra above the worst (its count below
    /// the threshold) or to tries that failed.
    pub worst_reached: u64,
    /// Tetrahedra it tried to improve, and how many of the tries succeeded.
    pub attempts: u64,
    /// Successful tries.
    pub successes: u64,
    /// The mesh's worst angle (the smaller of its smallest dihedral angle
    /// and 180° minus its largest; degrees) at its start and at its end.
    pub worst: [f64; 2],
    /// Tetrahedra below its threshold at its start and at its end.
    pub below: [usize; 2],
    /// Why it ended.
    pub stop: StageStop,
}

/// Why [`optimize`] refused its input.
///
/// ```
/// use delone::tet::optimize::{optimize, OptimizeError, OptimizeOptions};
/// use delone::tet::recover::{recover, RecoverOptions};
/// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
/// let tris = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];
/// let mut r = recover(&pts, &tris, &RecoverOptions::default()).unwrap();
/// r.mesh.tets[0][0] = 99;
/// let e = optimize(&mut r, &OptimizeOptions::default()).unwrap_err();
/// assert!(matches!(e, OptimizeError::InvalidMesh { tet: 0, .. }));
/// ```
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum OptimizeError {
    /// The mesh is inconsistent: array sizes, a vertex or neighbour out of
    /// range, or a tetrahedron that is not positive.
    InvalidMesh {
        /// The offending tetrahedron (or the array length for size errors).
        tet: usize,
        /// What is wrong.
        what: &'static str,
    },
    /// An angle option is not a number of degrees from 0 to 90
    /// ([`OptimizeOptions::min_dihedral`], [`OptimizeOptions::target_dihedral`]).
    InvalidAngle {
        /// The option's name.
        option: &'static str,
        /// Its value.
        value: f64,
    },
}

impl fmt::Display for OptimizeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            OptimizeError::InvalidMesh { tet, what } => {
                write!(f, "cannot optimise: tetrahedron {tet}: {what}")
            }
            OptimizeError::InvalidAngle { option, value } => {
                write!(
                    f,
                    "cannot optimise: {option} = {value} is not an angle from 0 to 90 degrees"
                )
            }
        }
    }
}

impl std::error::Error for OptimizeError {}

/// Improves the tetrahedra of `rec` in place (see the [module
/// documentation](self)): the boundary, internal facets, regions and volume
/// are kept; points may be moved (interior ones only) and added.
///
/// # Errors
/// [`OptimizeError::InvalidMesh`] when `rec` is not a consistent mesh;
/// [`OptimizeError::InvalidAngle`] when `opts.min_dihedral` or
/// `opts.target_dihedral` is not within 0..=90 degrees (NaN included).
///
/// ```
/// use delone::tet::optimize::{optimize, OptimizeOptions};
/// use delone::tet::recover::{check_recovered, RecoverOptions};
/// use delone::tet::refine::{refine, RefineOptions};
/// // A unit cube refined to small volumes (every input triangle its own
/// // facet), then optimised.
/// let pts: Vec<[f64; 3]> = (0..8)
///     .map(|i| [(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64])
///     .collect();
/// let tris = [
///     [0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
///     [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5],
/// ];
/// let recover = RecoverOptions { merge_coplanar: false, ..Default::default() };
/// let ro = RefineOptions { max_volume: Some(0.01), recover, ..Default::default() };
/// let mut r = refine(&pts, &tris, &ro).unwrap().rec;
/// let opts = OptimizeOptions { input_points: Some(pts.len()), ..Default::default() };
/// let rep = optimize(&mut r, &opts).unwrap();
/// check_recovered(&pts, &tris, &r).unwrap();
/// assert!(rep.after.min_dihedral > rep.before.min_dihedral);
/// ```
pub fn optimize(
    rec: &mut Recovered,
    opts: &OptimizeOptions,
) -> Result<OptimizeReport, OptimizeError> {
    let mesh = validate_input(rec)?;
    optimize_in_place(rec, mesh, opts)
}

/// [`optimize`] continuing on `mesh`, the domain mesh of `rec` (its
/// tetrahedra in the order of `rec.mesh.tets`, as refinement hands it over:
/// see [`crate::tet::refine::refine_in_place`]), without building it again
/// from `rec`'s neighbour lists. `rec` (points, boundary and interface
/// faces, surface, regions) is read for the side data and gets the result.
pub(crate) fn optimize_in_place(
    rec: &mut Recovered,
    mesh: DomainMesh,
    opts: &OptimizeOptions,
) -> Result<OptimizeReport, OptimizeError> {
    for (option, value) in [
        ("min_dihedral", opts.min_dihedral),
        ("target_dihedral", opts.target_dihedral),
    ] {
        if !(0.0..=90.0).contains(&value) {
            return Err(OptimizeError::InvalidAngle { option, value });
        }
    }
    // A small mesh left below the bound (`min_dihedral`, default 15°; or
    // above 180° minus it) may be optimised once more
    // from the start with every trial insertion settled fully: the worst
    // angle of a run hangs on a few tetrahedra near needle input triangles
    // and on the path taken, and either way of settling wins on some
    // models. The better result is kept (better worst angle, then fewer
    // tetrahedra). Not when the worst tetrahedron sits at an input triangle
    // with an angle below RETRY_FEATURE_ANGLE (or above 180° minus it):
    // there it is pinned near 0° whatever the path; and, unless
    // exhaustive, only where it may win (see the module doc).
    let retry = rec.mesh.tets.len() <= RETRY_CAP && opts.max_passes > 0;
    // The second run starts from a copy of `rec`; its mesh is rebuilt from
    // the copy's neighbour lists only if that run happens (the same mesh as
    // `mesh`, without holding a second one through the first run).
    let original = retry.then(|| rec.clone());
    // (The stuck tetrahedra decide the second run.)
    let report = optimize_once(rec, mesh, opts, false, opts.diagnostics || retry);
    let Some(mut other) = original else {
        return Ok(report);
    };
    // The worst angle either way (near 0° or near 180°), as the quality.
    let worst = |r: &OptimizeReport| r.after.min_dihedral.min(180.0 - r.after.max_dihedral);
    let pinned = report.stuck.first().is_some_and(|s| {
        s.reason != StuckReason::NoImprovement
            || s.near_triangle.is_some()
                && (s.near_angles[0] < RETRY_FEATURE_ANGLE
                    || s.near_angles[1] > 180.0 - RETRY_FEATURE_ANGLE)
    });
    // Unless exhaustive: only when the first run spent its budget in its
    // lowest stage, or its stage at the bound ended with nothing left to
    // improve (see `optimize`).
    let bound = opts.min_dihedral.clamp(0.0, 90.0);
    let stuck_low = report
        .stages
        .first()
        .is_some_and(|s| s.stop == StageStop::Budget);
    let settled_at_bound = report
        .stages
        .iter()
        .any(|s| s.threshold == bound && s.stop == StageStop::Settled);
    let may_win = opts.exhaustive || stuck_low || settled_at_bound;
    if worst(&report) >= opts.min_dihedral || report.after.tets == 0 || pinned || !may_win {
        return Ok(report);
    }
    let other_mesh = validate_input(&other)?;
    let mut second = optimize_once(&mut other, other_mesh, opts, true, opts.diagnostics);
    second.evaluations += report.evaluations;
    let stages = [report.stages.as_slice(), &second.stages].concat();
    let key = |r: &OptimizeReport| (worst(r), std::cmp::Reverse(r.after.tets));
    if key(&second) > key(&report) {
        *rec = other;
        Ok(OptimizeReport { stages, ..second })
    } else {
        Ok(OptimizeReport {
            evaluations: second.evaluations,
            stages,
            ..report
        })
    }
}

/// Most tetrahedra of a mesh that may be optimised a second time when its
/// worst angle stays outside [`OptimizeOptions::min_dihedral`] (see
/// [`optimize`]).
const RETRY_CAP: usize = 40_000;

/// Input triangle angle (degrees) below which (or above 180° minus which)
/// the worst tetrahedron at that triangle is taken as pinned by it (a
/// nearly degenerate input triangle), and the second run is skipped.
/// Measured at q1.414: the second run changes nothing on
/// cgal_u, cgal_triceratops and cgal_anchor_dense (worst at triangles of
/// 0.07°, 0.00°, 0.00°) and doubles their time; with the worst at a 0.45°
/// triangle it still raises cgal_part 6.2 → 7.8° (and cgal_rotor 8.7 →
/// 9.7°, meshlab_knot 7.3 → 10.8° at 2.6°..4.1° triangles).
const RETRY_FEATURE_ANGLE: f64 = 0.1;

/// One run of [`optimize`] on a validated mesh; `thorough`: every trial
/// insertion settled fully from the start; `list_stuck`: the stuck tetrahedra
/// are listed (with [`OptimizeOptions::diagnostics`], the rest of the
/// diagnostics too).
fn optimize_once(
    rec: &mut Recovered,
    mesh: DomainMesh,
    opts: &OptimizeOptions,
    thorough: bool,
    list_stuck: bool,
) -> OptimizeReport {
    let idle = opts.max_passes == 0 || rec.mesh.tets.is_empty();
    let mut report = OptimizeReport::default();
    if opts.diagnostics || idle {
        report.before = TetStats::of(&rec.points, &rec.mesh.tets);
    }
    if idle {
        report.after = report.before.clone();
        if opts.diagnostics {
            surface_bounds(rec, opts.min_dihedral, &mut report);
        }
        return report;
    }
    let (scaled, s) = crate::geom::rescaled(&rec.points);
    let mut w = Work::new(scaled.into_owned(), mesh, &rec.interior_faces);
    let n_in = opts
        .input_points
        .unwrap_or(rec.points.len().saturating_sub(rec.report.steiner()))
        .min(rec.points.len());
    for f in &mut w.fixed[..n_in] {
        *f = true;
    }
    w.n0 = rec.points.len();
    w.limits = limits(rec, opts, s);
    if opts.flips {
        set_boundary(rec, &mut w);
    }
    if opts.smooth_boundary {
        set_slides(rec, n_in, &mut w, s);
    }
    for v in &mut w.slide[..n_in] {
        *v = Slide::Fixed;
    }
    let bound = opts.min_dihedral.clamp(0.0, 90.0);
    let target = opts.target_dihedral.clamp(0.0, 90.0).max(bound);
    let thr_insert = (0.6 * target).to_radians().sin();
    // The output view's cell arrays are rewritten by `write_back` at the
    // end: released while the work mesh stands for them (peak memory).
    let n_tets = rec.mesh.tets.len();
    rec.mesh.tets = Vec::new();
    rec.mesh.neighbors = Vec::new();
    rec.tet_region = Vec::new();
    let budget = opts.max_inserted.unwrap_or(n_tets / 10);
    // Per tetrahedron (sorted vertices): the clock of its last failed
    // attempt; it is not retried until a star of one of its vertices
    // changes.
    let mut failed: IdMap<[u32; 4], u64> = Default::default();
    // Stages of rising thresholds: the worst tetrahedra first, so that the
    // effort goes where the minimum is decided.
    let mut stages: Vec<f64> = STAGES.iter().copied().filter(|&d| d < target).collect();
    if bound > 0.0 && bound < target && !stages.contains(&bound) {
        stages.push(bound);
        stages.sort_by(f64::total_cmp);
    }
    stages.push(target);
    let lowest = stages[0];
    // (Small meshes get the budget of 2000 more tetrahedra: cheap anyway.)
    let effort = opts.effort.unwrap_or(f64::INFINITY);
    let allowed = effort * (n_tets + 2000) as f64;
    // The polishing stages (above 20°, which mostly thin the histogram's
    // tail once the worst are settled) get at most this much more.
    let polish = effort * (POLISH * n_tets as f64 + 8000.0);
    // The stages up to 20° decide the minimum: they may spend `LOW` times
    // the budget (a mesh that the refinement left with many flat
    // tetrahedra needs it; a fair one does not reach it).
    // On meshes up to `LOW_CAP` tetrahedra they may spend as much again
    // once the minimum is above `EXTRA_ABOVE`: cheap there, and the last
    // tetrahedra below 15° of a small mesh near needle input triangles
    // often need it (cgal_pipe, cgal_spool); on large meshes it would
    // mostly go to tetrahedra forced by the input.
    let extra = LOW * effort * (n_tets + 2000).min(LOW_CAP) as f64;
    let mut extended = false;
    let mut stop;
    let mut pops: u64 = 0;
    // Flat tetrahedra under a chord over a rounded edge point go first (see
    // `Work::drop_flat_boundary`): no other operation can touch them.
    if opts.flips {
        for t in 0..w.m.tv.len() as u32 {
            if w.live(t) && w.q[t as usize] < LIFT_BELOW && w.drop_flat_boundary(t) {
                report.flat_removed += 1;
            }
        }
    }
    // Interior points the refinement left where their star is better
    // without them go first: fewer and better tetrahedra to work on.
    if opts.insert {
        collapse_sweep(&mut w, n_in, f64::INFINITY, &mut report);
    }
    // The stages that decide the minimum: up to 20°, or up to the bound
    // asked for when higher.
    let low_max = bound.max(20.0);
    for deg in stages {
        let thr = deg.to_radians().sin();
        if deg <= low_max {
            stop = LOW * allowed + if extended { extra } else { 0.0 };
        } else {
            let now = w.evals.get() as f64;
            stop = now + polish.min((allowed - now).max(0.0));
        }
        report.passes += 1;
        // Rounds: the queue of the bad tetrahedra not known to be stuck,
        // worst first, grown by the tetrahedra each success makes; until a
        // round succeeds nowhere, the stage's attempts are spent or it
        // stops paying: every `window` evaluations the worst quality and
        // the count below the threshold are compared with their best so
        // far, and the stage ends when neither improved over `PATIENCE`
        // windows or the last `share` of its evaluations, whichever is
        // longer; below half the
        // threshold a window must lift `MIN_LIFT` of the starting count.
        let mut attempts = None;
        w.thorough = thorough;
        // (The window counts at most `WINDOW_CAP` tetrahedra; below half
        // the threshold it must still lift `MIN_LIFT` of the starting
        // count, which on a large mesh ends a stage pinned by the input
        // sooner.)
        let window = stage_window(n_tets);
        let mut check = w.evals.get() + window;
        let mut best = standing(&w, thr);
        let (start, mut paid) = (w.evals.get(), w.evals.get());
        let lift = (MIN_LIFT * best.1 as f64) as usize;
        // The share of the stage's work it waits for: half in the lowest
        // stage (whose count is of the worst tetrahedra), while the mesh
        // misses the bound, in a second run and in an exhaustive one, else
        // a quarter (see `optimize`).
        let missing = best.0 < bound.to_radians().sin();
        let share = if opts.exhaustive || thorough || deg <= lowest || missing {
            2
        } else {
            UPPER_SHARE
        };
        let mut stage = StageReport {
            threshold: deg,
            second_run: thorough,
            worst: [worst_angle(best.0); 2],
            below: [best.1; 2],
            ..StageReport::default()
        };
        let undone0 = w.undone;
        let mut end_run = false;
        'rounds: loop {
            let mut heap: BinaryHeap<Entry> = (0..w.m.tv.len() as u32)
                .filter(|&t| w.live(t) && w.q[t as usize] < thr && !blocked(&w, &failed, t))
                .map(|t| Entry(w.q[t as usize], t, w.m.tv[t as usize]))
                .collect();
            let left = attempts.get_or_insert(opts.max_passes * heap.len());
            let mut any = false;
            w.dirty.clear();
            while let Some(Entry(q, t, tv)) = heap.pop() {
                pops += 1;
                if pops.is_multiple_of(1024) {
                    let total = allowed.is_finite().then_some(allowed as u64);
                    let done = w.evals.get().min(total.unwrap_or(u64::MAX));
                    crate::progress::report("optimising", done, total, "evaluations");
                    if crate::progress::stop_requested() {
                        report.effort_exhausted = true;
                        stage.stop = StageStop::Interrupted;
                        end_run = true;
                        break 'rounds;
                    }
                }
                // Stale entries: the slot changed since it was queued.
                if w.m.tv[t as usize] != tv || w.q[t as usize] != q || blocked(&w, &failed, t) {
                    continue;
                }
                if *left == 0 {
                    stage.stop = StageStop::Attempts;
                    break;
                }
                let e = w.evals.get();
                if e >= check {
                    let now = standing(&w, thr);
                    let lifted = lift * usize::from(now.0 < (0.5 * deg).to_radians().sin());
                    if now.0 > best.0 + 1e-4 {
                        stage.worst_reached = e - start;
                    }
                    if now.0 > best.0 + 1e-4 || now.1 + lifted < best.1 {
                        paid = e;
                    } else if e - paid >= (PATIENCE * window).max((e - start) / share) {
                        stage.stop = StageStop::Stalled;
                        break 'rounds;
                    }
                    best = (best.0.max(now.0), best.1.min(now.1));
                    check = e + window;
                }
                if e as f64 > stop {
                    // The extra budget of the stages up to 20° only where
                    // the minimum is already above 10°: below, it is mostly
                    // held by needle input triangles, which more work
                    // rarely lifts (it only adds vertices).
                    if deg <= low_max
                        && !extended
                        && standing(&w, 0.0).0 >= EXTRA_ABOVE.to_radians().sin()
                    {
                        extended = true;
                        stop += extra;
                    } else {
                        report.effort_exhausted = true;
                        stage.stop = StageStop::Budget;
                        end_run = true;
                        break 'rounds;
                    }
                }
                *left -= 1;
                stage.attempts += 1;
                if improve(
                    &mut w,
                    t,
                    1.0,
                    opts,
                    budget,
                    thr_insert.max(thr.min(POLISH_INSERT.to_radians().sin())),
                    &mut report,
                ) {
                    any = true;
                    stage.successes += 1;
                    for u in std::mem::take(&mut w.dirty) {
                        if w.live(u) && w.q[u as usize] < thr {
                            heap.push(Entry(w.q[u as usize], u, w.m.tv[u as usize]));
                        }
                    }
                } else {
                    w.dirty.clear();
                    w.clock += 1;
                    failed.insert(sorted(tv), w.clock);
                }
            }
            if *left == 0 || !any && w.thorough {
                if *left > 0 {
                    stage.stop = StageStop::Settled;
                }
                break;
            }
            // Trial insertions were first settled cheaply (given up as soon
            // as their worst new tetrahedron resisted); when a round
            // succeeds nowhere, the tetrahedra left get one more round with
            // every insertion settled fully.
            if !any {
                w.thorough = true;
                failed.clear();
            }
        }
        let end = standing(&w, thr);
        stage.worst[1] = worst_angle(end.0);
        stage.below[1] = end.1;
        stage.evaluations = w.evals.get() - start;
        if end.0 > best.0 + 1e-4 {
            stage.worst_reached = stage.evaluations;
        }
        stage.undone_evaluations = w.undone - undone0;
        report.stages.push(stage);
        if end_run {
            break;
        }
    }
    // Last, the points the optimisation inserted are taken out where the
    // collapse leaves every new tetrahedron fair (above `CLEANUP` and the
    // mesh's minimum) or better than their star was: fewer tetrahedra for
    // the same bound. (Over the refinement's points too it saves a few
    // per cent more tetrahedra but costs ~10% of the time on large meshes.)
    if opts.insert {
        let floor = CLEANUP.to_radians().sin().max(standing(&w, 0.0).0);
        let n0 = w.n0;
        collapse_sweep(&mut w, n0, floor, &mut report);
    }
    report.evaluations = w.evals.get();
    let old_id = write_back(rec, &w, s, n_in);
    report.after = TetStats::of(&rec.points, &rec.mesh.tets);
    if list_stuck {
        stuck(
            rec,
            &w,
            &old_id,
            n_in,
            target.to_radians().sin(),
            &mut report,
        );
    }
    // The work mesh is done with before the surface's statistics are
    // gathered (peak memory).
    drop(w);
    if opts.diagnostics {
        surface_bounds(rec, opts.min_dihedral, &mut report);
    }
    report
}

/// The report's bounds of the input surface (its smallest dihedral angles,
/// its triangles' angles) and the tetrahedra of `rec` outside `min_dihedral`.
fn surface_bounds(rec: &Recovered, min_dihedral: f64, report: &mut OptimizeReport) {
    let sums = surface_angles(rec);
    (report.input_min_dihedral, report.input_min_edge) = input_min_dihedral(&sums);
    (report.triangles_min_dihedral, report.triangles_min_edge) = triangles_min_dihedral(rec);
    triangle_angles(rec, report);
    report.bad = bad_cells(rec, &sums, min_dihedral);
}

/// The worst quality of the live tetrahedra of `w` and how many are below
/// `thr`.
fn standing(w: &Work, thr: f64) -> (f64, usize) {
    let live = (0..w.m.tv.len()).filter(|&t| w.live(t as u32));
    live.map(|t| w.q[t]).fold((f64::INFINITY, 0), |(m, n), q| {
        (m.min(q), n + usize::from(q < thr))
    })
}

/// The evaluations between two checks of a stage's progress on a mesh of
/// `n` tetrahedra: [`WINDOW`] per tetrahedron, at most [`WINDOW_CAP`]
/// counted, plus 2000.
fn stage_window(n: usize) -> u64 {
    (WINDOW * (n.min(WINDOW_CAP) + 2000) as f64) as u64
}

/// The worst angle (degrees) of a tetrahedron of quality `q` (the
/// smaller of its smallest dihedral angle and 180° minus its largest).
fn worst_angle(q: f64) -> f64 {
    if q.is_finite() {
        q.clamp(0.0, 1.0).asin().to_degrees()
    } else {
        90.0
    }
}

/// The vertices of `tv`, sorted.
fn sorted(mut tv: [u32; 4]) -> [u32; 4] {
    tv.sort_unstable();
    tv
}

/// True when slot `t` failed before and none of its vertices' stars
/// changed since.
fn blocked(w: &Work, failed: &IdMap<[u32; 4], u64>, t: u32) -> bool {
    let tv = w.m.tv[t as usize];
    failed
        .get(&sorted(tv))
        .is_some_and(|&at| tv.iter().all(|&v| w.stamp[v as usize] < at))
}

/// One attempt on slot `t`: topological, then smoothing, then insertion.
fn improve(
    w: &mut Work,
    t: u32,
    edge_below: f64,
    opts: &OptimizeOptions,
    budget: usize,
    insert_below: f64,
    report: &mut OptimizeReport,
) -> bool {
    // A flat tetrahedron on the surface (its four vertices fixed or
    // sliding: neither smoothing nor flips among surface points lift it):
    // a point off its sheet first, unless a flip already makes it fair
    // (that adds no vertex).
    let mut t = t;
    let tv0 = w.m.tv[t as usize];
    let mut plan = if opts.flips {
        best_flip(w, t, edge_below)
    } else {
        None
    };
    if opts.insert
        && report.inserted < budget
        && w.q[t as usize] < LIFT_BELOW
        && tv0.iter().all(|&v| w.fixed[v as usize])
        && plan.as_ref().is_none_or(|p| p.q < LIFT_FLIP_OK)
    {
        if try_lifted(w, tv0, opts, report) {
            return true;
        }
        // (Undone: the tetrahedron may be back in another slot.)
        match w.slot_of(tv0, t) {
            Some(s) => t = s,
            None => return false,
        }
        if opts.flips {
            plan = best_flip(w, t, edge_below);
        }
    }
    if let Some(p) = plan {
        if w.apply(&p).is_some() {
            match p.ring {
                0 => report.flips23 += 1,
                1 => report.boundary_flips += 1,
                2 => report.multi_face += 1,
                3 => report.flips32 += 1,
                4 => report.flips44 += 1,
                _ => report.edge_removals += 1,
            }
            return true;
        }
    }
    if opts.smooth {
        let tv = w.m.tv[t as usize];
        let mut any = false;
        for v in tv {
            if w.smooth(v) {
                report.smoothed += 1;
                any = true;
            }
        }
        if any {
            return true;
        }
    }
    // Insertion (the most expensive try) only for the really bad ones.
    let tv = w.m.tv[t as usize];
    if opts.insert
        && report.inserted < budget
        && w.q[t as usize] < insert_below
        && try_insert(w, t, opts, report)
    {
        return true;
    }
    // Last, removal of a vertex the optimiser inserted, by collapsing it
    // onto a neighbour (a point that settled badly among fixed ones).
    if opts.insert && w.slot_of(tv, t).is_some() {
        for v in tv {
            if try_collapse(w, v, f64::INFINITY, w.n0) {
                report.collapsed += 1;
                return true;
            }
        }
    }
    false
}

/// The best of the removals of `t`'s edges with a dihedral sine below
/// `edge_below` and the 2-3 flips of its faces: the one whose new
/// tetrahedra's worst quality is highest, if it beats the old ones'.
fn best_flip(w: &Work, t: u32, edge_below: f64) -> Option<Plan> {
    let tv = w.m.tv[t as usize];
    // The planners write into `cand`; a better one is swapped into `best`
    // (no allocation once the buffers have grown).
    let mut plans = w.plans.borrow_mut();
    let (best, cand) = &mut *plans;
    let mut have = false;
    let mut consider = |ok: bool, best: &mut Plan, cand: &mut Plan| {
        if ok {
            let old = w.min_q(&cand.old);
            if cand.q > old + 1e-12 && (!have || cand.q > best.q) {
                std::mem::swap(best, cand);
                have = true;
            }
        }
    };
    // Only the edges with a bad dihedral angle (the others are rarely
    // worth removing, and each removal plan costs O(n³) qualities).
    let s = work::sines(tv.map(|v| &w.p[v as usize])).unwrap_or([0.0; 6]);
    for (e, (i, j)) in super::quality::EDGES.into_iter().enumerate() {
        if s[e] < edge_below {
            let ok = w.plan_edge_removal(t, tv[i], tv[j], cand);
            consider(ok, best, cand);
        }
    }
    for f in 0..4 {
        let ok = w.plan_flip23(t, f, cand);
        consider(ok, best, cand);
        let ok = w.plan_multi_face(t, f, cand);
        consider(ok, best, cand);
    }
    have.then(|| best.clone())
}

/// The bounds of `opts` (radius-edge; global volume with the regions' own)
/// in the optimiser's coordinates, rescaled by `s` (see [`limits`]).
fn limits(rec: &Recovered, opts: &OptimizeOptions, s: (f64, f64)) -> limits::Limits {
    let mut l = limits::Limits::none();
    l.ratio = opts
        .max_radius_edge
        .filter(|b| *b > 0.0)
        .unwrap_or(f64::INFINITY);
    let f = s.0 * s.1;
    l.sizing = opts.sizing.clone();
    l.scale = f;
    let global = opts.max_volume.filter(|v| *v > 0.0);
    // Scaled by f³ (an overflow to infinity means no volume this small is
    // representable in the input's units: no bound).
    l.vol = crate::tet::refine::volume_bounds(&rec.regions, global)
        .map(|v| v.map_or(f64::INFINITY, |v| v * f * f * f))
        .collect();
    if l.vol.is_empty() {
        if let Some(g) = global {
            l.vol = vec![g * f * f * f];
        }
    }
    if l.vol.iter().all(|v| !v.is_finite()) {
        l.vol.clear();
    }
    l
}

/// Collapses (see [`try_collapse`]) each interior vertex from `from` on,
/// in order, where the new tetrahedra beat `floor` or the star's worst;
/// counts them in `report`.
fn collapse_sweep(w: &mut Work, from: usize, floor: f64, report: &mut OptimizeReport) {
    for v in from as u32..w.p.len() as u32 {
        if try_collapse(w, v, floor, from) {
            if (v as usize) < w.n0 {
                report.removed += 1;
            } else {
                report.collapsed += 1;
            }
        }
    }
}

/// Dihedral angle (degrees) that every tetrahedron made by the final
/// collapse of an inserted vertex must keep (see [`optimize`]).
const CLEANUP: f64 = 25.0;

/// Most tetrahedra in the star of a collapsed vertex.
const MAX_COLLAPSE_STAR: usize = 64;

/// Removes vertex `v` — a free (interior) vertex, numbered `from` or
/// higher — by
/// collapsing its edge to the neighbour `u` that gives the best result:
/// the tetrahedra around the edge vanish and `u` replaces `v` in the
/// others (a cone from `u` over the faces of the star polyhedron). Valid
/// when every new tetrahedron is exactly positive and the link condition
/// holds (a vertex, edge or triangle in the links of both `u` and `v` is in
/// the link of the edge), so that no tetrahedron is made twice; applied
/// when the worst quality of the star rises above `floor` or its old worst
/// (whichever is lower).
fn try_collapse(w: &mut Work, v: u32, floor: f64, from: usize) -> bool {
    if (v as usize) < from || w.fixed[v as usize] {
        return false;
    }
    let star = w.star(v);
    if star.is_empty() || star.len() > MAX_COLLAPSE_STAR {
        return false;
    }
    let region = w.m.reg[star[0] as usize];
    if star.iter().any(|&t| w.m.reg[t as usize] != region) {
        return false;
    }
    let old_q = w.min_q(&star).min(floor);
    // The other three vertices of `t` (a tetrahedron of the star of `x`),
    // sorted.
    let others = |w: &Work, x: u32, t: u32| {
        let tv = w.m.tv[t as usize];
        let i = tv.iter().position(|&y| y == x).unwrap_or(3);
        let mut o = [tv[(i + 1) % 4], tv[(i + 2) % 4], tv[(i + 3) % 4]];
        o.sort_unstable();
        o
    };
    // The link of a vertex: its vertices, edges and triangles (sorted).
    let link = |w: &Work, x: u32, star: &[u32]| {
        let mut vs = Vec::with_capacity(3 * star.len());
        let mut es = Vec::with_capacity(3 * star.len());
        let mut fs = Vec::with_capacity(star.len());
        for &t in star {
            let o = others(w, x, t);
            vs.extend_from_slice(&o);
            es.extend([[o[0], o[1]], [o[0], o[2]], [o[1], o[2]]]);
            fs.push(o);
        }
        vs.sort_unstable();
        vs.dedup();
        es.sort_unstable();
        es.dedup();
        fs.sort_unstable();
        (vs, es, fs)
    };
    // The candidates: the vertices of the link (its edges and triangles
    // only when a candidate passes the quality test).
    let mut lv: Vec<u32> = star.iter().flat_map(|&t| others(w, v, t)).collect();
    lv.sort_unstable();
    lv.dedup();
    // The edges and triangles of the link of `v`, made on first use.
    type EdgesFaces = (Vec<[u32; 2]>, Vec<[u32; 3]>);
    let mut vlink: Option<EdgesFaces> = None;
    let mut best: Option<Plan> = None;
    let mut new: Vec<[u32; 4]> = Vec::with_capacity(star.len());
    for &u in &lv {
        // The new tetrahedra (those of the star without `u`, `u` for `v`):
        // positive and better, before the costlier link condition.
        new.clear();
        let mut q = f64::INFINITY;
        let bar = best.as_ref().map_or(old_q, |b| b.q.max(old_q));
        let mut ok = true;
        for &t in &star {
            let tv = w.m.tv[t as usize];
            if tv.contains(&u) {
                continue;
            }
            let nt = tv.map(|y| if y == v { u } else { y });
            q = q.min(w.qual(nt));
            if q <= bar + 1e-12 || !w.positive(nt) {
                ok = false;
                break;
            }
            new.push(nt);
        }
        if !ok {
            continue;
        }
        // The link of the edge: the other two vertices of its tetrahedra.
        let mut ev = Vec::with_capacity(2 * star.len());
        let mut ee = Vec::with_capacity(star.len());
        for &t in &star {
            let tv = w.m.tv[t as usize];
            if tv.contains(&u) {
                let mut o: Vec<u32> = tv.into_iter().filter(|&y| y != u && y != v).collect();
                o.sort_unstable();
                ev.extend_from_slice(&o);
                ee.push([o[0], o[1]]);
            }
        }
        ev.sort_unstable();
        ev.dedup();
        ee.sort_unstable();
        let ustar = w.star(u);
        let (uv, ue, uf) = link(w, u, &ustar);
        let (le, lf) = vlink.get_or_insert_with(|| {
            let (_, le, lf) = link(w, v, &star);
            (le, lf)
        });
        let shared_ok = uv
            .iter()
            .filter(|&&x| x != v && lv.binary_search(&x).is_ok())
            .all(|x| ev.binary_search(x).is_ok())
            && ue
                .iter()
                .filter(|e| !e.contains(&v) && le.binary_search(e).is_ok())
                .all(|e| ee.binary_search(e).is_ok())
            && !uf
                .iter()
                .any(|f| !f.contains(&v) && lf.binary_search(f).is_ok());
        if shared_ok {
            best = Some(Plan {
                old: star.clone(),
                new: new.clone(),
                q,
                ring: 0,
            });
        }
    }
    let done = best.is_some_and(|p| w.apply(&p).is_some());
    if done {
        w.forget(v);
    }
    done
}

/// A flip whose worst new tetrahedron has a dihedral sine above this (20°)
/// is preferred to a lifted insertion (see [`improve`]).
const LIFT_FLIP_OK: f64 = 0.342;

/// Inserts the centroid of `t` in the cavity of `t` and its neighbours
/// across open faces, smooths it, and keeps it when the worst quality
/// improved (else undoes it).
fn try_insert(w: &mut Work, t: u32, opts: &OptimizeOptions, report: &mut OptimizeReport) -> bool {
    let tv = w.m.tv[t as usize];
    let p = tv.map(|x| w.p[x as usize]);
    let c = std::array::from_fn(|k| (p[0][k] + p[1][k] + p[2][k] + p[3][k]) / 4.0);
    // First in the small cavity (it and its neighbours), then in the
    // point's Delaunay cavity.
    if try_insert_at(w, t, c, Cavity::Near, opts, report) {
        return true;
    }
    match w.slot_of(tv, t) {
        Some(t) if try_insert_at(w, t, c, Cavity::Sphere, opts, report) => return true,
        Some(_) => {}
        None => return false,
    }
    // Then the midpoints of its two edges with the worst dihedral angles
    // (a sliver's diagonals, a cap's or wedge's bad edge), each in its
    // Delaunay cavity, which holds every tetrahedron around that edge.
    let Some(s) = work::sines([&p[0], &p[1], &p[2], &p[3]]) else {
        return false;
    };
    // A flat tetrahedron whose four vertices are on the surface (a layer
    // of them between surface points, left by the refinement along a flat
    // or gently curved facet) has every point above on its own sheet:
    // first a point lifted off it.
    // (The flattest of them were tried first, by `improve`.)
    let on_surface = tv.iter().all(|&v| w.fixed[v as usize]);
    if on_surface
        && s.iter().all(|&x| x >= LIFT_BELOW)
        && s.iter().any(|&x| x < LIFT_SURFACE_BELOW)
        && try_lifted(w, tv, opts, report)
    {
        return true;
    }
    let mut e: Vec<usize> = (0..6).collect();
    e.sort_by(|&a, &b| s[a].total_cmp(&s[b]).then(a.cmp(&b)));
    for &k in &e[..2] {
        let Some(t) = w.slot_of(tv, t) else {
            return false;
        };
        let (i, j) = super::quality::EDGES[k];
        let m = std::array::from_fn(|d| 0.5 * (p[i][d] + p[j][d]));
        if try_insert_at(w, t, m, Cavity::Sphere, opts, report) {
            return true;
        }
    }
    // Last, a point lifted off a flat tetrahedron with a free vertex too.
    !on_surface && s.iter().any(|&x| x < LIFT_BELOW) && try_lifted(w, tv, opts, report)
}

/// Tetrahedra on the surface with a dihedral sine below this (20°) get
/// the lifted points of [`try_lifted`] after the centroid (above it they
/// would mostly add vertices for little gain).
const LIFT_SURFACE_BELOW: f64 = 0.342;

/// Tetrahedra with a dihedral sine below this (about 3°) that the other
/// insertions did not help get the lifted points of [`try_lifted`].
const LIFT_BELOW: f64 = 0.05;

/// Inserts a point off the plane of the flat tetrahedron `tv`: above the
/// centroid of its largest face, on either side, at 0.6 and 0.3 times the
/// face's mean edge length, each in its Delaunay cavity (the insertion and
/// its undo as in [`try_insert_at`]). A point on the outer side fails at
/// once (it does not see the boundary faces of its cavity).
fn try_lifted(
    w: &mut Work,
    tv: [u32; 4],
    opts: &OptimizeOptions,
    report: &mut OptimizeReport,
) -> bool {
    let p = tv.map(|x| w.p[x as usize]);
    // The largest face: its normal is the sheet's.
    let mut best = (0.0, [0.0; 3], [0.0; 3], 0.0);
    for f in 0..4 {
        let [a, b, c] = face([0, 1, 2, 3], f).map(|i| p[i as usize]);
        let (u, v) = (sub(&b, &a), sub(&c, &a));
        let n = cross(&u, &v);
        let area = norm(&n);
        if area > best.0 {
            let g = std::array::from_fn(|k| (a[k] + b[k] + c[k]) / 3.0);
            let s = (norm(&u) + norm(&v) + norm(&sub(&c, &b))) / 3.0;
            best = (area, n.map(|x| x / area), g, s);
        }
    }
    let (area, n, g, s) = best;
    if !(area > 0.0 && s > 0.0) {
        return false;
    }
    for h in [0.6, -0.6, 0.3, -0.3, 0.12, -0.12, 0.05, -0.05].map(|k| k * s) {
        let x = std::array::from_fn(|k| h.mul_add(n[k], g[k]));
        let Some(t) = w.slot_of(tv, NONE) else {
            return false;
        };
        let Some(cav) = w.lifted_cavity(t, x, MAX_LIFTED_CAVITY) else {
            continue;
        };
        if try_insert_at(w, t, x, Cavity::Given(cav), opts, report) {
            return true;
        }
    }
    false
}

/// The cavity of an insertion by [`try_insert_at`].
enum Cavity {
    /// The tetrahedron and its neighbours across open faces, else the
    /// tetrahedron alone.
    Near,
    /// The point's Delaunay cavity from the tetrahedron.
    Sphere,
    /// This one.
    Given(Vec<u32>),
}

/// Inserts point `c` in `t` and its neighbours, else in `t` (with
/// `near`), or in its Delaunay cavity from `t` (without), smooths it and
/// improves the worst new tetrahedra; keeps it when the worst quality
/// improved.
fn try_insert_at(
    w: &mut Work,
    t: u32,
    c: [f64; 3],
    cavity: Cavity,
    opts: &OptimizeOptions,
    report: &mut OptimizeReport,
) -> bool {
    let near = matches!(cavity, Cavity::Near);
    let mut cav = vec![t];
    for f in 0..4 {
        let n = w.m.across(t, f);
        if n != NONE
            && w.m.reg[n as usize] == w.m.reg[t as usize]
            && !w.m.is_sub(t, f)
            && !cav.contains(&n)
        {
            cav.push(n);
        }
    }
    // Without `near`: the Delaunay cavity of the point (the tetrahedra of
    // the region whose circumsphere holds it, grown across open faces): the
    // new vertex then gets a star of fair size to be smoothed in.
    let big = match cavity {
        Cavity::Near => None,
        Cavity::Sphere => w.sphere_cavity(t, c, MAX_CAVITY),
        Cavity::Given(b) => Some(b),
    };
    let e0 = w.evals.get();
    w.begin();
    // The centroid may not see every face of the larger cavity (a sliver's
    // neighbours); it always sees the faces of `t` itself.
    let got = if near {
        w.insert(&cav, c).or_else(|| w.insert(&[t], c))
    } else {
        big.and_then(|b| w.insert(&b, c))
    };
    let Some((id, _)) = got else {
        w.rollback();
        w.undone += w.evals.get() - e0;
        return false;
    };
    // Settle the new vertex: smooth it, then improve the worst of the new
    // tetrahedra by flips and smoothing (no nested insertion).
    let mut scratch = OptimizeReport::default();
    let local = OptimizeOptions {
        insert: false,
        ..opts.clone()
    };
    if opts.smooth {
        w.smooth(id);
    }
    'settle: for _ in 0..3 {
        let mut bad: Vec<(f64, u32, [u32; 4])> = w
            .live_touched()
            .map(|(s, tv)| (w.q[s as usize], s, tv))
            // Only those at or below the bar decide the outcome.
            .filter(|x| x.0 <= w.lost + SETTLE_MARGIN)
            .collect();
        bad.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.2.cmp(&b.2)));
        bad.dedup_by_key(|x| x.2);
        let mut any = false;
        for (k, (q, s, tv)) in bad.into_iter().enumerate() {
            if let Some(s) = w.slot_of(tv, s) {
                let ok = improve(w, s, 1.0, &local, 0, 0.0, &mut scratch);
                // Unless `thorough`: the worst new tetrahedron, below the
                // bar, resists flips and smoothing — the insertion fails.
                // (Such failures cost ~20× a success in evaluations: on
                // cgal_pipe they took 70% of the budget.)
                if k == 0 && !ok && q <= w.lost + 1e-9 && !w.thorough {
                    break 'settle;
                }
                any |= ok;
            }
        }
        if !any {
            break;
        }
    }
    let touched = w.live_touched().map(|(s, _)| w.q[s as usize]);
    if touched.fold(f64::INFINITY, f64::min) > w.lost + 1e-9 {
        w.commit();
        report.inserted += 1;
        report.flips23 += scratch.flips23;
        report.flips32 += scratch.flips32;
        report.flips44 += scratch.flips44;
        report.edge_removals += scratch.edge_removals;
        report.boundary_flips += scratch.boundary_flips;
        report.multi_face += scratch.multi_face;
        report.smoothed += scratch.smoothed;
        true
    } else {
        w.rollback();
        w.undone += w.evals.get() - e0;
        report.insert_undone += 1;
        false
    }
}

/// Checks sizes, ranges and neighbour links of the input; its domain mesh.
fn validate_input(rec: &Recovered) -> Result<DomainMesh, OptimizeError> {
    let m = &rec.mesh;
    let n = rec.points.len();
    let bad = |tet, what| Err(OptimizeError::InvalidMesh { tet, what });
    if m.neighbors.len() != m.tets.len() || rec.tet_region.len() != m.tets.len() {
        return bad(
            m.tets.len(),
            "tets, neighbors and tet_region differ in length",
        );
    }
    for (t, (tv, nb)) in m.tets.iter().zip(&m.neighbors).enumerate() {
        if tv.iter().any(|&v| v as usize >= n) {
            return bad(t, "names a missing point");
        }
        if nb.iter().any(|&x| x != NONE && x as usize >= m.tets.len()) {
            return bad(t, "names a missing neighbour");
        }
    }
    if rec
        .interior_faces
        .iter()
        .flatten()
        .any(|&v| v as usize >= n)
    {
        return bad(0, "an interior face names a missing point");
    }
    DomainMesh::from_neighbors(&m.tets, &m.neighbors, &rec.tet_region, n).map_err(|t| {
        OptimizeError::InvalidMesh {
            tet: t,
            what: "has a neighbour that does not share the face",
        }
    })
}

/// Writes the live tetrahedra (in slot order) and the points back.
/// Returns, per point of the result, its id in `w`.
fn write_back(rec: &mut Recovered, w: &Work, s: (f64, f64), n_in: usize) -> Vec<u32> {
    let mut map = vec![NONE; w.m.tv.len()];
    let mut k = 0u32;
    for (t, tv) in w.m.tv.iter().enumerate() {
        if tv[0] != DEAD {
            map[t] = k;
            k += 1;
        }
    }
    // Points collapsed away (interior ones of the refinement or the
    // optimisation) are left out; the others keep their order.
    let n0 = rec.points.len();
    let mut used = vec![false; w.p.len().saturating_sub(n_in)];
    for tv in w.m.tv.iter().filter(|tv| tv[0] != DEAD) {
        for &v in tv {
            if let Some(u) = (v as usize).checked_sub(n_in) {
                used[u] = true;
            }
        }
    }
    // (A point of the surface stays, used or not.)
    for (u, x) in used.iter_mut().enumerate() {
        *x |= w.fixed[n_in + u];
    }
    let mut renum: Vec<u32> = Vec::with_capacity(used.len());
    let mut next = n_in as u32;
    for &u in &used {
        renum.push(if u { next } else { NONE });
        next += u32::from(u);
    }
    let id = |v: u32| (v as usize).checked_sub(n_in).map_or(v, |u| renum[u]);
    let mut tets = Vec::with_capacity(k as usize);
    let mut nbs = Vec::with_capacity(k as usize);
    let mut reg = Vec::with_capacity(k as usize);
    for (t, tv) in w.m.tv.iter().enumerate() {
        if tv[0] == DEAD {
            continue;
        }
        tets.push(tv.map(id));
        nbs.push(w.m.nb[t].map(|x| {
            if x == NONE {
                NONE
            } else {
                map[(x >> 2) as usize]
            }
        }));
        reg.push(w.m.reg[t]);
    }
    // Points: moved interior points and new ones, scaled back (exact
    // powers of two).
    let unscale = |p: [f64; 3]| {
        if s == (1.0, 1.0) {
            p
        } else {
            p.map(|c| c / s.0 / s.1)
        }
    };
    let mut points = Vec::with_capacity(next as usize);
    points.extend_from_slice(&rec.points[..n_in]);
    for (i, p) in w.p.iter().enumerate().skip(n_in) {
        if !used[i - n_in] {
            continue;
        }
        points.push(if i < n0 && w.slide[i] == Slide::Fixed {
            rec.points[i]
        } else {
            unscale(*p)
        });
    }
    rec.points = points;
    if renum
        .iter()
        .enumerate()
        .any(|(u, &r)| r != (n_in + u) as u32)
    {
        for f in rec.boundary.iter_mut().chain(rec.interior_faces.iter_mut()) {
            *f = f.map(id);
        }
        rec.inexact = rec
            .inexact
            .iter()
            .map(|&v| id(v))
            .filter(|&v| v != NONE)
            .collect();
    }
    // Interface faces: outward from the lower-numbered of their two
    // tetrahedra.
    // (Only faces with three fixed vertices can be interface faces.)
    let mut owner: IdMap<[u32; 3], (usize, usize)> = Default::default();
    let mut fixed = vec![false; rec.points.len()];
    for (i, &f) in w.fixed.iter().enumerate() {
        if let Some(x) = fixed.get_mut(id(i as u32) as usize) {
            *x = f;
        }
    }
    if !rec.interior_faces.is_empty() {
        for (t, (tv, nb)) in tets.iter().zip(&nbs).enumerate() {
            for (f, &n) in nb.iter().enumerate() {
                let fc = face(*tv, f);
                if n != NONE && fc.iter().all(|&v| fixed[v as usize]) {
                    owner.entry(fkey(fc)).or_insert((t, f));
                }
            }
        }
    }
    for f in rec.interior_faces.iter_mut() {
        if let Some(&(t, i)) = owner.get(&fkey(*f)) {
            // FACET order sees the opposite vertex on its positive side, so
            // the reversed face is outward from `t`.
            let [a, b, c] = face(tets[t], i);
            *f = [a, c, b];
        }
    }
    // Boundary faces, after boundary flips: those left in their order, then
    // the new ones (outward: reversed FACET order).
    if !w.bnd_new.is_empty() {
        let mut free: IdMap<[u32; 3], [u32; 3]> = Default::default();
        for (tv, nb) in tets.iter().zip(&nbs) {
            for (f, &n) in nb.iter().enumerate() {
                if n == NONE {
                    let [a, b, c] = face(*tv, f);
                    free.insert(fkey([a, b, c]), [a, c, b]);
                }
            }
        }
        let mut faces = Vec::with_capacity(rec.boundary.len());
        let mut tris = Vec::with_capacity(rec.boundary.len());
        // (`rec.boundary` is renumbered already, `bnd_new` not.)
        for (f, &t) in rec.boundary.iter().zip(&rec.boundary_triangle) {
            if free.remove(&fkey(*f)).is_some() {
                faces.push(*f);
                tris.push(t);
            }
        }
        for k in &w.bnd_new {
            if let (Some(f), Some(&t)) = (free.remove(&fkey(k.map(id))), w.bnd.get(k)) {
                faces.push(f);
                tris.push(t);
            }
        }
        rec.boundary = faces;
        rec.boundary_triangle = tris;
    }
    // Region counts and volumes.
    for r in rec.regions.iter_mut() {
        r.tets = 0;
        r.volume = 0.0;
    }
    for (tv, &g) in tets.iter().zip(&reg) {
        if let Some(r) = rec.regions.get_mut(g as usize) {
            r.tets += 1;
            r.volume += super::quality::volume(&tv.map(|v| rec.points[v as usize]));
        }
    }
    rec.mesh.tets = tets;
    rec.mesh.neighbors = nbs;
    rec.tet_region = reg;
    let mut old_id: Vec<u32> = (0..n_in as u32).collect();
    old_id.extend(
        (n_in..w.p.len())
            .filter(|&i| used[i - n_in])
            .map(|i| i as u32),
    );
    old_id
}

/// Lets [`Work`] flip boundary faces within a facet: the boundary faces
/// on a surface triangle, and the facet of each surface triangle.
fn set_boundary(rec: &Recovered, w: &mut Work) {
    if rec.boundary.len() != rec.boundary_triangle.len() {
        return;
    }
    for (f, &t) in rec.boundary.iter().zip(&rec.boundary_triangle) {
        if (t as usize) < rec.surface.len() && f.iter().all(|&v| (v as usize) < w.p.len()) {
            w.bnd.insert(fkey(*f), t);
        }
    }
    w.facet = if rec.surface_origin.len() == rec.surface.len() {
        rec.surface_origin.clone()
    } else {
        (0..rec.surface.len() as u32).collect()
    };
}

/// The sliding freedom of the Steiner points on the surface (see
/// [`OptimizeOptions::smooth_boundary`]): a point whose surface faces all
/// lie on one triangle of `rec.surface` slides in its plane, one on the
/// common edge of all the triangles its faces lie on slides along it, any
/// other stays fixed.
fn set_slides(rec: &Recovered, n_in: usize, w: &mut Work, s: (f64, f64)) {
    let n = rec.points.len();
    // Per surface vertex: the surface triangles of its faces, and the other
    // vertices of those faces (each twice when the faces close around it).
    let mut on: Vec<Vec<u32>> = vec![Vec::new(); n];
    let mut link: Vec<Vec<u32>> = vec![Vec::new(); n];
    for (f, t) in rec.surface_faces() {
        for (k, &v) in f.iter().enumerate() {
            if (v as usize) < n_in || v as usize >= n {
                continue;
            }
            let l = &mut on[v as usize];
            if !l.contains(&t) {
                l.push(t);
            }
            link[v as usize].extend([f[(k + 1) % 3], f[(k + 2) % 3]]);
        }
    }
    for (v, l) in on.iter().enumerate().skip(n_in) {
        if !w.fixed[v] || l.is_empty() {
            continue;
        }
        // Only a closed fan of faces (not the free edge of an internal
        // facet, nor a non-manifold point) may slide.
        let mut k = std::mem::take(&mut link[v]);
        k.sort_unstable();
        if k.len() < 6 || k.chunks(2).any(|c| c[0] != c[1]) || k.windows(3).any(|c| c[0] == c[2]) {
            continue;
        }
        let tri = |t: u32| rec.surface.get(t as usize).copied();
        let Some(tris) = l.iter().map(|&t| tri(t)).collect::<Option<Vec<_>>>() else {
            continue; // a hull face off the surface
        };
        w.slide[v] = if let [t] = tris[..] {
            Slide::Plane(t)
        } else {
            let common: Vec<u32> = tris[0]
                .iter()
                .copied()
                .filter(|c| tris.iter().all(|t| t.contains(c)))
                .collect();
            match common[..] {
                [a, b] => Slide::Line([a, b]),
                _ => Slide::Fixed,
            }
        };
    }
    for &v in &rec.inexact {
        let Some(x) = w.inexact.get_mut(v as usize) else {
            continue;
        };
        *x = true;
        // An inexact point that is nevertheless exactly on the plane of one
        // of its surface triangles stays exactly there: it may not move
        // within the rounding tolerance (off that plane).
        let p = rec.points[v as usize];
        let exact_on = on[v as usize].iter().any(|&t| {
            rec.surface.get(t as usize).is_some_and(|tri| {
                let [a, b, c] = tri.map(|q| rec.points[q as usize]);
                delone_predicates::orient3d(&a, &b, &c, &p) == 0.0
            })
        });
        if exact_on {
            match w.slide[v as usize] {
                Slide::Line(_) => w.slide[v as usize] = Slide::Fixed,
                Slide::Plane(_) => *x = false,
                _ => {}
            }
        }
    }
    w.tol = rec.report.max_deviation * s.0 * s.1;
}

/// See [`OptimizeReport::triangles_min_dihedral`].
fn triangles_min_dihedral(rec: &Recovered) -> (f64, Option<[u32; 2]>) {
    let pt = |v: u32| rec.points[v as usize];
    let normal = |f: [u32; 3]| {
        let [a, b, c] = f.map(pt);
        cross(&sub(&b, &a), &sub(&c, &a))
    };
    // Outward orientation of each surface triangle on the boundary: that of
    // its boundary faces.
    let mut sign = vec![0.0f64; rec.surface.len()];
    for (f, &t) in rec.boundary.iter().zip(&rec.boundary_triangle) {
        if let Some(tri) = rec.surface.get(t as usize) {
            if sign[t as usize] == 0.0 {
                sign[t as usize] = dot(&normal(*f), &normal(*tri)).signum();
            }
        }
    }
    // The triangles at each edge: (edge, triangle) pairs sorted, so each
    // edge's triangles follow one another in increasing order.
    let mut at: Vec<([u32; 2], u32)> = Vec::new();
    for (t, tri) in rec.surface.iter().enumerate() {
        if sign[t] != 0.0 {
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                at.push(([a.min(b), a.max(b)], t as u32));
            }
        }
    }
    at.sort_unstable();
    let mut best: (f64, Option<[u32; 2]>) = (360.0, None);
    for l in at.chunk_by(|x, y| x.0 == y.0).filter(|l| l.len() == 2) {
        let (e, t1, t2) = (l[0].0, l[0].1 as usize, l[1].1 as usize);
        let unit = |t: usize| {
            let n = normal(rec.surface[t]).map(|x| x * sign[t]);
            let m = norm(&n);
            n.map(|x| x / m)
        };
        let (n1, n2) = (unit(t1), unit(t2));
        let mut ang = (-dot(&n1, &n2)).clamp(-1.0, 1.0).acos().to_degrees();
        // Reflex when the far vertex of the second triangle is outside the
        // first one's plane.
        let d = rec.surface[t2]
            .into_iter()
            .find(|v| !e.contains(v))
            .map_or([0.0; 3], pt);
        let a = pt(e[0]);
        if dot(&n1, &sub(&d, &a)) > 0.0 {
            ang = 360.0 - ang;
        }
        if ang.is_finite() && ang < best.0 {
            best = (ang, Some(e));
        }
    }
    best
}

/// The angle of each region at each edge of the surface (boundary and
/// interface faces): the sum of its tetrahedra's dihedral angles there
/// (degrees).
fn surface_angles(rec: &Recovered) -> IdMap<([u32; 2], u32), f64> {
    let m = &rec.mesh;
    let prot: IdSet<[u32; 3]> = rec.interior_faces.iter().map(|&f| fkey(f)).collect();
    let mut edges: IdSet<[u32; 2]> = IdSet::default();
    for (tv, nb) in m.tets.iter().zip(&m.neighbors) {
        for (f, &n) in nb.iter().enumerate() {
            let fc = face(*tv, f);
            if n == NONE || (!prot.is_empty() && prot.contains(&fkey(fc))) {
                for k in 0..3 {
                    let (a, b) = (fc[k], fc[(k + 1) % 3]);
                    edges.insert([a.min(b), a.max(b)]);
                }
            }
        }
    }
    // Only tetrahedra with two vertices on the surface can have such an
    // edge (a cheap filter before the hash lookups).
    let mut on = vec![false; rec.points.len()];
    for e in &edges {
        on[e[0] as usize] = true;
        on[e[1] as usize] = true;
    }
    let mut sum: IdMap<([u32; 2], u32), f64> = IdMap::default();
    for (tv, &g) in m.tets.iter().zip(&rec.tet_region) {
        if tv.iter().filter(|&&v| on[v as usize]).count() < 2 {
            continue;
        }
        let mut d = None;
        for (e, (i, j)) in super::quality::EDGES.into_iter().enumerate() {
            let (a, b) = (tv[i], tv[j]);
            if !(on[a as usize] && on[b as usize]) {
                continue;
            }
            let k = [a.min(b), a.max(b)];
            if edges.contains(&k) {
                let d = d.get_or_insert_with(|| {
                    super::quality::dihedral_angles(&tv.map(|v| rec.points[v as usize]))
                });
                *sum.entry((k, g)).or_insert(0.0) += d[e];
            }
        }
    }
    sum
}

/// See [`OptimizeReport::input_min_dihedral`].
fn input_min_dihedral(sum: &IdMap<([u32; 2], u32), f64>) -> (f64, Option<[u32; 2]>) {
    // The smallest sum, ties by edge (deterministic).
    sum.iter()
        .map(|(&(e, _), &a)| (a, e))
        .min_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)))
        .map_or((360.0, None), |(a, e)| (a, Some(e)))
}

/// Margin of the dihedral sine above which [`bad_cells`] takes a
/// tetrahedron as within the bound without computing its angles (far above
/// the rounding of either computation).
const BAD_MARGIN: f64 = 1e-6;

/// See [`BadCells`].
fn bad_cells(rec: &Recovered, sums: &IdMap<([u32; 2], u32), f64>, angle: f64) -> BadCells {
    let mut out = BadCells {
        angle,
        ..BadCells::default()
    };
    // Per point: the deviation (see `BadCells::feature_angle`) of the
    // most needle- or cap-like input triangle under its boundary faces.
    let dev: Vec<f64> = rec
        .surface
        .iter()
        .map(|t| {
            let [lo, hi] = tri_angles(t.map(|v| rec.points[v as usize]));
            lo.min(180.0 - hi)
        })
        .collect();
    let mut at = vec![f64::INFINITY; rec.points.len()];
    for (f, t) in rec.surface_faces() {
        if let Some(&d) = dev.get(t as usize) {
            for &v in f {
                if let Some(a) = at.get_mut(v as usize) {
                    *a = a.min(d);
                }
            }
        }
    }
    // A tetrahedron whose smallest dihedral sine is clearly above the
    // bound's is within it (the angles are computed only near the bound).
    let clear = angle.to_radians().sin() + BAD_MARGIN;
    for (tv, &g) in rec.mesh.tets.iter().zip(&rec.tet_region) {
        let p = tv.map(|v| rec.points[v as usize]);
        if work::quality([&p[0], &p[1], &p[2], &p[3]]) > clear {
            continue;
        }
        let d = super::quality::dihedral_angles(&p);
        if d.iter().all(|&x| (angle..=180.0 - angle).contains(&x)) {
            continue;
        }
        out.count += 1;
        let sharp = super::quality::EDGES
            .iter()
            .enumerate()
            .any(|(e, &(i, j))| {
                let (a, b) = (tv[i], tv[j]);
                d[e] < angle
                    && sums
                        .get(&([a.min(b), a.max(b)], g))
                        .is_some_and(|&s| s < angle)
            });
        let near = tv
            .iter()
            .map(|&v| at[v as usize])
            .fold(f64::INFINITY, f64::min);
        if sharp {
            out.sharp_edge += 1;
        } else if near < angle {
            out.at_feature += 1;
            out.feature_angle = out.feature_angle.max(near);
        } else {
            out.free += 1;
        }
    }
    out
}

/// Fills the stuck counts and list.
fn stuck(
    rec: &Recovered,
    w: &Work,
    old_id: &[u32],
    n_in: usize,
    thr: f64,
    report: &mut OptimizeReport,
) {
    let slide = |v: u32| w.slide[old_id[v as usize] as usize];
    // The list keeps the worst `LISTED` (by quality, then index): sorted and
    // cut whenever it holds twice as many, so it stays small however many
    // tetrahedra are below the threshold.
    const LISTED: usize = 32;
    let mut list = Vec::with_capacity(2 * LISTED);
    let cut = |list: &mut Vec<(f64, Stuck)>| {
        list.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.tet.cmp(&b.1.tet)));
        list.truncate(LISTED);
    };
    // Once `LISTED` are kept, the quality of the last one: a later
    // tetrahedron (higher index) at or above it cannot enter the list, and
    // only its counts are taken.
    let mut bar = f64::INFINITY;
    for (t, (tv, nb)) in rec.mesh.tets.iter().zip(&rec.mesh.neighbors).enumerate() {
        let p = tv.map(|v| rec.points[v as usize]);
        let q = work::quality([&p[0], &p[1], &p[2], &p[3]]);
        if q >= thr {
            continue;
        }
        let surface_faces = (0..4)
            .filter(|&f| {
                nb[f] == NONE || w.is_protected(fkey(face(*tv, f).map(|v| old_id[v as usize])))
            })
            .count();
        let reason = if surface_faces >= 2 {
            StuckReason::SurfaceFaces
        } else if tv.iter().all(|&v| slide(v) == Slide::Fixed) {
            StuckReason::AllVerticesFixed
        } else {
            StuckReason::NoImprovement
        };
        report.stuck_counts[reason as usize] += 1;
        if q.total_cmp(&bar).is_ge() {
            continue;
        }
        let d = super::quality::dihedral_angles(&p);
        let lo = d.iter().copied().fold(180.0, f64::min);
        let hi = d.iter().copied().fold(0.0, f64::max);
        if list.len() == 2 * LISTED {
            cut(&mut list);
            bar = list[LISTED - 1].0;
        }
        list.push((
            q,
            Stuck {
                tet: t,
                dihedral: [lo, hi],
                reason,
                shape: super::quality::tet_shape(&p),
                surface_faces,
                input_vertices: tv.iter().filter(|&&v| (v as usize) < n_in).count(),
                fixed_vertices: tv.iter().filter(|&&v| slide(v) == Slide::Fixed).count(),
                near_triangle: None,
                near_angles: [0.0; 2],
            },
        ));
    }
    cut(&mut list);
    report.stuck = list.into_iter().map(|x| x.1).collect();
    let angles: Vec<[f64; 2]> = rec
        .surface
        .iter()
        .map(|t| tri_angles(t.map(|v| rec.points[v as usize])))
        .collect();
    for st in &mut report.stuck {
        let p = rec.mesh.tets[st.tet].map(|v| rec.points[v as usize]);
        if let Some(i) = near_triangle(rec, &angles, &p) {
            st.near_triangle = rec.surface_origin.get(i).copied().or(Some(i as u32));
            st.near_angles = angles[i];
        }
    }
}

/// The smallest and largest angle (degrees) of a triangle (0 and 180 when
/// it is degenerate).
fn tri_angles(t: [[f64; 3]; 3]) -> [f64; 2] {
    let mut lo = 180.0f64;
    let mut hi = 0.0f64;
    for k in 0..3 {
        let x = crate::geom::vec3::angle(&t[k], &t[(k + 1) % 3], &t[(k + 2) % 3]).to_degrees();
        lo = lo.min(x);
        hi = hi.max(x);
    }
    if hi == 0.0 {
        return [0.0, 180.0];
    }
    [lo, hi]
}

/// Fills the triangle-angle fields of the report.
fn triangle_angles(rec: &Recovered, report: &mut OptimizeReport) {
    report.triangles_min_angle = 180.0;
    report.triangles_max_angle = 0.0;
    for (i, t) in rec.surface.iter().enumerate() {
        let [lo, hi] = tri_angles(t.map(|v| rec.points[v as usize]));
        let origin = rec.surface_origin.get(i).copied().or(Some(i as u32));
        if lo < report.triangles_min_angle {
            report.triangles_min_angle = lo;
            report.triangles_min_angle_triangle = origin;
        }
        if hi > report.triangles_max_angle {
            report.triangles_max_angle = hi;
            report.triangles_max_angle_triangle = origin;
        }
    }
}

/// The closest point of triangle `t` to `x` (Voronoi regions of its
/// vertices, edges and interior).
fn closest_on_triangle(x: [f64; 3], t: [[f64; 3]; 3]) -> [f64; 3] {
    let at = |a: [f64; 3], d: [f64; 3], s: f64| std::array::from_fn(|k| s.mul_add(d[k], a[k]));
    let [a, b, c] = t;
    let (ab, ac, ap) = (sub(&b, &a), sub(&c, &a), sub(&x, &a));
    let (d1, d2) = (dot(&ab, &ap), dot(&ac, &ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = sub(&x, &b);
    let (d3, d4) = (dot(&ab, &bp), dot(&ac, &bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return at(a, ab, d1 / (d1 - d3));
    }
    let cp = sub(&x, &c);
    let (d5, d6) = (dot(&ab, &cp), dot(&ac, &cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return at(a, ac, d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        return at(b, sub(&c, &b), (d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let den = va + vb + vc;
    if den.abs() < f64::MIN_POSITIVE {
        return a;
    }
    let (v, w) = (vb / den, vc / den);
    std::array::from_fn(|k| a[k] + ab[k] * v + ac[k] * w)
}

/// See [`Stuck::near_triangle`]: the index in `rec.surface`.
fn near_triangle(rec: &Recovered, angles: &[[f64; 2]], p: &[[f64; 3]; 4]) -> Option<usize> {
    let c: [f64; 3] = std::array::from_fn(|k| (p[0][k] + p[1][k] + p[2][k] + p[3][k]) / 4.0);
    let reach = super::quality::edge_lengths(p)
        .into_iter()
        .fold(0.0f64, f64::max);
    let mut nearest: Option<(f64, usize)> = None;
    let mut worst: Option<(f64, usize)> = None;
    for (i, t) in rec.surface.iter().enumerate() {
        let q = t.map(|v| rec.points[v as usize]);
        // The distance to its bounding box first (a lower bound).
        let gap = (0..3)
            .map(|k| {
                let lo = q[0][k].min(q[1][k]).min(q[2][k]);
                let hi = q[0][k].max(q[1][k]).max(q[2][k]);
                (lo - c[k]).max(c[k] - hi).max(0.0)
            })
            .fold(0.0f64, f64::max);
        if gap > reach && nearest.is_some_and(|(e, _)| gap >= e) {
            continue;
        }
        let y = closest_on_triangle(c, q);
        let d = crate::geom::vec3::dist2(&y, &c).sqrt();
        if nearest.is_none_or(|(e, _)| d < e) {
            nearest = Some((d, i));
        }
        if d <= reach && worst.is_none_or(|(a, _)| angles[i][0] < a) {
            worst = Some((angles[i][0], i));
        }
    }
    worst.or(nearest).map(|x| x.1)
}

/// Tetrahedra of an insertion's cavity at most this much (dihedral sine)
/// above the worst one it replaced are improved while the new vertex
/// settles (only those at or below it decide the outcome).
const SETTLE_MARGIN: f64 = 0.1;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_stage_window_stops_growing_with_the_mesh() {
        // Up to the cap: WINDOW evaluations per tetrahedron (plus 2000).
        assert_eq!(stage_window(0), 20_000);
        assert_eq!(stage_window(WINDOW_CAP / 2), 270_000);
        assert_eq!(stage_window(WINDOW_CAP), 520_000);
        // Above it the window stays.
        assert_eq!(stage_window(10 * WINDOW_CAP), 520_000);
    }

    #[test]
    fn worst_angle_of_a_quality() {
        assert_eq!(worst_angle(f64::INFINITY), 90.0);
        assert_eq!(worst_angle(-1.0), 0.0);
        assert!((worst_angle(0.5) - 30.0).abs() < 1e-12);
    }
}
