//! Options of the refinement, its Steiner-point budget and memory estimate.

use super::sizing;
use crate::tet::recover::{MeshRegion, RecoverOptions};

/// Per region of `regions`, its volume bound: the smaller of its own and
/// `global` (a bound that is not positive counts as none).
pub(crate) fn volume_bounds(
    regions: &[MeshRegion],
    global: Option<f64>,
) -> impl Iterator<Item = Option<f64>> + '_ {
    let global = global.filter(|v| *v > 0.0);
    regions
        .iter()
        .map(move |r| match (global, r.max_volume.filter(|v| *v > 0.0)) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        })
}

/// Options of [`refine`](crate::tet::refine::refine).
///
/// ```
/// let o = delone::tet::refine::RefineOptions::default();
/// assert_eq!(o.max_radius_edge, Some(2.0));
/// assert!(o.max_steiner.is_none()); // the default budget
/// assert!(o.max_volume.is_none());
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct RefineOptions {
    /// Largest radius-edge ratio allowed (`-q`); default 2.0. Values below
    /// about 1.1 may not terminate and stop at the budget
    /// ([`Self::max_steiner`]); values below √6/4 (the regular
    /// tetrahedron's, the smallest of any tetrahedron) and NaN are refused
    /// ([`Error::InvalidBound`](crate::Error::InvalidBound)).
    /// `None`: no quality rule.
    pub max_radius_edge: Option<f64>,
    /// Largest tetrahedron volume (`-a`), in the input's units; default none.
    /// NaN, zero and negative values are refused.
    pub max_volume: Option<f64>,
    /// Most Steiner points the refinement may add (after recovery; TetGen's
    /// `-S`). `None` (the default): [`default_budget`](crate::tet::refine::default_budget) of the
    /// input. When it runs out the refinement stops with a valid mesh and
    /// [`RefineReport::budget_exhausted`](crate::tet::refine::RefineReport::budget_exhausted).
    pub max_steiner: Option<usize>,
    /// Options of the recovery stage of [`refine`](crate::tet::refine::refine).
    pub recover: RecoverOptions,
    /// Local target edge length (`-m`): a closure or a background mesh;
    /// default none. See [`sizing`] for the rule.
    pub sizing: sizing::Sizing,
    /// Keep the recovered surface as it is (`-Y` with `-q`/`-a`, TetGen's
    /// meaning): no point is put on a subface or subsegment, so the
    /// boundary and interior faces of the output are those of the input
    /// mesh. A bad cell whose circumcentre encroaches the surface is split
    /// at a point inside its circumball that does not (see the module
    /// documentation), or left and counted in [`LeftBad::surface`](crate::tet::refine::LeftBad::surface); a cell
    /// above a volume bound is always split. Default false.
    pub keep_surface: bool,
    /// Count the output's cells left outside the bounds in the report
    /// ([`RefineReport::remaining_bad`](crate::tet::refine::RefineReport::remaining_bad)
    /// and the other `remaining_*` counts, `flat`, and why and where they
    /// were left, [`RefineReport::left`](crate::tet::refine::RefineReport::left)):
    /// a pass over every output cell that only explains the result. Default
    /// true; false leaves those counts at 0 (the mesh is the same).
    pub diagnostics: bool,
}

impl Default for RefineOptions {
    fn default() -> Self {
        RefineOptions {
            max_radius_edge: Some(2.0),
            max_volume: None,
            max_steiner: None,
            recover: RecoverOptions::default(),
            sizing: sizing::Sizing::None,
            keep_surface: false,
            diagnostics: true,
        }
    }
}

/// Smallest default Steiner budget ([`default_budget`](crate::tet::refine::default_budget)): about 500 MB of
/// refinement ([`memory_estimate`]).
pub const BUDGET_BASE: usize = 500_000;

/// Largest default Steiner budget ([`default_budget`](crate::tet::refine::default_budget)): about 4 GB. A
/// bigger run needs an explicit [`RefineOptions::max_steiner`](crate::tet::refine::RefineOptions::max_steiner) (`-S`).
pub const BUDGET_MAX: usize = 1 << 22;

/// Peak bytes per vertex of a refinement, optimisation included (measured:
/// `tet -pq1.2a0.00001 cgal_sphere.off`, 18 500 vertices in 20 MB, of which
/// about 4 MB are the program's own).
pub const BYTES_PER_POINT: u64 = 1000;

/// The smallest radius-edge ratio of any tetrahedron, √6/4 ≈ 0.612 (the
/// regular tetrahedron's): a smaller [`RefineOptions::max_radius_edge`](crate::tet::refine::RefineOptions::max_radius_edge) is
/// refused.
pub const MIN_RADIUS_EDGE: f64 = 0.612_372_435_695_794_5;

/// The Steiner budget used when [`RefineOptions::max_steiner`](crate::tet::refine::RefineOptions::max_steiner) is
/// `None`: [`BUDGET_BASE`] + 16 per input vertex + 2 per unit of
/// volume over the volume bound (`volume_ratio`: the sum over the recovered
/// tetrahedra of their volume over their region's bound), at most
/// [`BUDGET_MAX`]. It depends on the input and the options only, never on
/// the machine. A volume bound `V` is met with about `volume_ratio / 3`
/// points, so volume-driven runs have six times the room they need; a
/// radius-edge bound below what refinement guarantees (about 1.1 and less)
/// stops after at most half a million points + 16 per input vertex.
///
/// ```
/// use delone::tet::refine::{default_budget, BUDGET_BASE, BUDGET_MAX};
/// assert_eq!(default_budget(10, 0.0), BUDGET_BASE + 160);
/// assert_eq!(default_budget(10, 1000.0), BUDGET_BASE + 2160);
/// assert_eq!(default_budget(10, 1e15), BUDGET_MAX);
/// ```
pub fn default_budget(input_points: usize, volume_ratio: f64) -> usize {
    crate::geom::steiner_budget((BUDGET_BASE, BUDGET_MAX), input_points, volume_ratio)
}

/// Estimated peak memory, in bytes, of a refinement that ends with
/// `points` vertices ([`BYTES_PER_POINT`] each).
///
/// ```
/// assert_eq!(delone::tet::refine::memory_estimate(2_000), 2_000_000);
/// ```
pub fn memory_estimate(points: usize) -> u64 {
    points as u64 * BYTES_PER_POINT
}

impl RefineOptions {
    /// Refuses bounds no mesh can meet (what [`refine`](crate::tet::refine::refine) and
    /// [`refine_recovered`](crate::tet::refine::refine_recovered) check first; callers may check before a long
    /// recovery): a radius-edge ratio that is NaN or below
    /// [`MIN_RADIUS_EDGE`], a volume bound that is NaN, zero or negative.
    ///
    /// # Errors
    /// [`Error::InvalidBound`](crate::Error::InvalidBound) naming the
    /// switch (`-q`, `-a`) and the value.
    ///
    /// ```
    /// use delone::tet::refine::RefineOptions;
    /// let o = RefineOptions { max_radius_edge: Some(0.5), ..Default::default() };
    /// assert!(matches!(o.check_bounds(), Err(delone::Error::InvalidBound { option: "-q", .. })));
    /// let o = RefineOptions { max_radius_edge: Some(0.62), max_volume: Some(0.0), ..Default::default() };
    /// assert!(matches!(o.check_bounds(), Err(delone::Error::InvalidBound { option: "-a", .. })));
    /// assert!(RefineOptions::default().check_bounds().is_ok());
    /// ```
    pub fn check_bounds(&self) -> Result<(), crate::Error> {
        let q = self.max_radius_edge.unwrap_or(f64::INFINITY);
        if q.is_nan() || q < MIN_RADIUS_EDGE {
            return Err(crate::Error::InvalidBound {
                option: "-q",
                value: q,
                reason: "no tetrahedron has a radius-edge ratio below sqrt(6)/4 = 0.612 (the regular tetrahedron's), so no mesh meets it",
            });
        }
        if let Some(v) = self.max_volume {
            if v.is_nan() || v <= 0.0 {
                return Err(crate::Error::InvalidBound {
                    option: "-a",
                    value: v,
                    reason: "the maximum volume must be positive",
                });
            }
        }
        Ok(())
    }
}
