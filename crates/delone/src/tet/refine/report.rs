//! What the refinement did: its report, the bad cells it left, and its result.

use crate::tet::recover::{RecoverReport, Recovered};

/// What [`refine`](crate::tet::refine::refine) did.
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
    /// Why the points on segments and facets were inserted: which rule
    /// asked for each split.
    pub causes: SplitCauses,
    /// Circumcentres rejected because they encroached the boundary.
    pub rejected: usize,
    /// Bad cells left alone: splitting the boundary they encroach would
    /// have made much shorter edges (small input angles, thin features), or
    /// their circumcentre could not be placed.
    pub skipped: usize,
    /// Of [`Self::skipped`]: nearly flat cells (radius-edge ratio above
    /// 10⁶) or cells without a circumcentre.
    pub skipped_flat: usize,
    /// Of [`Self::skipped`]: the circumcentre lies behind a subface it does
    /// not encroach (the mesh is not constrained Delaunay there).
    pub skipped_behind: usize,
    /// Of [`Self::skipped`]: the encroached boundary pieces are much smaller
    /// than the cell (small input angles, thin features).
    pub skipped_small: usize,
    /// Of [`Self::skipped_small`]: the circumcentre lies closer to a vertex
    /// of its cavity than the cell's shortest edge (the cell's circumsphere
    /// reaches round a subface, at a reflex or sharp input feature);
    /// inserting it would start a cascade of ever shorter edges.
    pub skipped_close: usize,
    /// Of [`Self::skipped_small`]: cells spanning a sharp wedge of the
    /// input (their vertices on two input triangles sharing an edge at a
    /// dihedral angle below 30°): splitting either facet for them would refine the
    /// wedge towards its edge without end.
    pub skipped_wedge: usize,
    /// Of [`Self::skipped_small`]: a piece the circumcentre encroaches
    /// would have been split at a point closer to a vertex than the cell's
    /// shortest edge (the insertion-radius rule), so nothing was split.
    pub skipped_radius: usize,
    /// Of [`Self::skipped_small`]: cells with a vertex on a degenerate
    /// (zero-angle) input triangle.
    pub skipped_degenerate: usize,
    /// Of [`Self::skipped_small`]: cells whose shortest edge joins two
    /// concentric-shell points at a small input angle between segments.
    pub skipped_shell: usize,
    /// Of [`Self::skipped`]: the insertion plan was refused (no valid
    /// cavity, or the point could not be located).
    pub skipped_refused: usize,
    /// Of [`Self::skipped`]: with [`RefineOptions::keep_surface`](crate::tet::refine::RefineOptions::keep_surface), every
    /// point tried would have encroached the surface.
    pub skipped_surface: usize,
    /// Of [`Self::interior`]: points inside a cell's circumball other than
    /// its circumcentre (cells too big whose circumcentre could not be
    /// used, and cells kept off the surface by
    /// [`RefineOptions::keep_surface`](crate::tet::refine::RefineOptions::keep_surface)).
    pub inside: usize,
    /// Why the cells of [`Self::remaining_bad`] were left, and near which
    /// input features they lie.
    pub left: LeftBad,
    /// Of [`Self::remaining_bad`]: cells with a face on a subface or an
    /// edge on a subsegment (next to the input surface).
    pub remaining_at_boundary: usize,
    /// Subsegments too short to split in floating point.
    pub unsplittable: usize,
    /// The Steiner budget ran out before every bad cell was split.
    pub budget_exhausted: bool,
    /// The Steiner budget the refinement ran under
    /// ([`RefineOptions::max_steiner`](crate::tet::refine::RefineOptions::max_steiner) or [`default_budget`](crate::tet::refine::default_budget)).
    pub steiner_budget: usize,
    /// Output cells whose radius-edge ratio is above the bound.
    pub remaining_bad: usize,
    /// Output cells bigger than the sizing allows ([`RefineOptions::sizing`](crate::tet::refine::RefineOptions::sizing)).
    pub remaining_too_big: usize,
    /// Output cells above their volume bound ([`RefineOptions::max_volume`](crate::tet::refine::RefineOptions::max_volume)
    /// or their region's); 0 unless the Steiner budget ran out.
    pub remaining_over_volume: usize,
    /// Of [`Self::remaining_bad`], the nearly flat cells (radius-edge
    /// ratio above 10⁶: four points a hair off one plane, or a wedge at a
    /// sharp input edge); they are not split, since their circumcentres lie
    /// far away and splitting the boundary for them would run away.
    pub flat: usize,
}

/// Which rule asked for the refinement's points on subsegments and
/// subfaces ([`RefineReport::on_segments`], [`RefineReport::on_facets`]):
/// an existing vertex encroaching a subsegment (R1) or a subface (R2), or
/// a bad cell (R3: its circumcentre encroaches them, or it is too big).
/// A subsegment split while R2 splits a subface (the subface's
/// circumcentre lies beyond it or encroaches it, or the fallback splits
/// the subface's longest edge) counts for whatever asked for the subface.
/// The segment fields sum to [`RefineReport::on_segments`], the facet
/// fields to [`RefineReport::on_facets`].
///
/// ```
/// let c = delone::tet::refine::SplitCauses { segments_for_cells: 2, facets_for_cells: 1,
///     ..Default::default() };
/// assert_eq!(c.segments(), 2);
/// assert_eq!(c.facets(), 1);
/// ```
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct SplitCauses {
    /// Subsegments split for a vertex inside their diametral ball.
    pub segments_for_vertices: usize,
    /// Subsegments split for a subface that a vertex encroaches (or that
    /// is bigger than the sizing allows).
    pub segments_for_subfaces: usize,
    /// Subsegments split for a bad cell, directly (its circumcentre
    /// encroaches them) or through a subface split for it.
    pub segments_for_cells: usize,
    /// Subfaces split for a vertex inside their equatorial ball (or for
    /// the sizing).
    pub facets_for_vertices: usize,
    /// Subfaces split for a bad cell (its circumcentre encroaches them).
    pub facets_for_cells: usize,
}

impl SplitCauses {
    /// Points put on subsegments, over the causes.
    pub fn segments(&self) -> usize {
        self.segments_for_vertices + self.segments_for_subfaces + self.segments_for_cells
    }

    /// Points put on subfaces, over the causes.
    pub fn facets(&self) -> usize {
        self.facets_for_vertices + self.facets_for_cells
    }
}

/// The cells left above the radius-edge bound by the refinement, by the
/// reason the last attempt to split each gave up (every cell is counted in
/// exactly one of the reason fields), and by the input features near them
/// (those two counts overlap each other and the reasons).
///
/// ```
/// let l = delone::tet::refine::LeftBad::default();
/// assert_eq!(l.total(), 0);
/// ```
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct LeftBad {
    /// Nearly flat (radius-edge ratio above 10⁶, or four vertices on one
    /// plane of the input).
    pub flat: usize,
    /// Circumcentre behind a subface it does not encroach.
    pub behind: usize,
    /// Circumcentre closer to a vertex of its cavity than the cell's
    /// shortest edge ([`RefineReport::skipped_close`](crate::tet::refine::RefineReport::skipped_close)).
    pub close: usize,
    /// Splitting the encroached piece would have broken the
    /// insertion-radius rule ([`RefineReport::skipped_radius`](crate::tet::refine::RefineReport::skipped_radius)).
    pub radius: usize,
    /// The encroached pieces are shorter than the cell's shortest edge, or
    /// their splits failed.
    pub small: usize,
    /// Spanning a sharp input wedge ([`RefineReport::skipped_wedge`](crate::tet::refine::RefineReport::skipped_wedge)).
    pub wedge: usize,
    /// A vertex on a degenerate (zero-angle) input triangle.
    pub degenerate: usize,
    /// Shortest edge between concentric-shell points at a small input
    /// angle.
    pub shell: usize,
    /// Insertion plan refused or circumcentre not located.
    pub refused: usize,
    /// Every point tried would have encroached the surface, which
    /// [`RefineOptions::keep_surface`](crate::tet::refine::RefineOptions::keep_surface) keeps.
    pub surface: usize,
    /// Never split for another reason: the Steiner budget ran out, or the
    /// cell was made by the last insertions' flips after its checks.
    pub other: usize,
    /// Of all left cells: those with a vertex on an input triangle whose
    /// smallest angle is below 5° (needles and caps of scanned surfaces).
    pub near_needle: usize,
    /// Of all left cells: those with a vertex on an input edge whose two
    /// triangles meet at an angle below 60° (measured between half-planes:
    /// sharp ridges and deep notches alike).
    pub near_sharp: usize,
}

impl LeftBad {
    /// Cells counted over the reasons (equals
    /// [`RefineReport::remaining_bad`](crate::tet::refine::RefineReport::remaining_bad)).
    ///
    /// ```
    /// let l = delone::tet::refine::LeftBad { close: 2, radius: 1, ..Default::default() };
    /// assert_eq!(l.total(), 3);
    /// ```
    pub fn total(&self) -> usize {
        self.flat
            + self.behind
            + self.close
            + self.radius
            + self.small
            + self.wedge
            + self.degenerate
            + self.shell
            + self.refused
            + self.surface
            + self.other
    }
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

/// The result of [`refine`](crate::tet::refine::refine): a [`Recovered`] mesh (so
/// [`super::recover::check_recovered`](crate::tet::recover::check_recovered) applies to it) and the report.
#[derive(Debug, Clone, PartialEq)]
pub struct Refined {
    /// Points, inside tetrahedra, boundary faces with their input triangle,
    /// inexact Steiner points; `rec.report` is the recovery's report with
    /// `max_deviation` covering the refinement's points too.
    pub rec: Recovered,
    /// Counts.
    pub report: RefineReport,
}
