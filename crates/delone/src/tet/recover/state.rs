//! The recovery's working state (one run of [`super::recover_marked`]):
//! the refined surface, the report so far, the merged groups recovered as
//! polygons and the bookkeeping of the `-Y` fallbacks. Its methods live
//! with the steps that use them (`mod.rs`, `polygon.rs`).

use std::collections::HashSet;

use super::cdt;
use super::surface::Surface;
use super::types::{RecoverOptions, RecoverReport};
use crate::geom::ids::IdMap;

/// Per input triangle, the mesh faces lying on it.
pub(super) type FacesOn = Vec<Vec<[u32; 3]>>;

/// What a round of the constrained recovery hands to the next one: the
/// coverage of the Delaunay tetrahedralization it started from, and how
/// many points it had.
pub(super) struct RoundState {
    pub(super) on: FacesOn,
    pub(super) covered: Vec<bool>,
    pub(super) old_len: usize,
    /// Its missing subsegments.
    pub(super) subs: Vec<(u32, u32, u32)>,
    /// Its protected items (see [`State::protected`]).
    pub(super) prot: Option<cdt::Protected>,
}

/// Rounds after which surface preservation gives up.
pub(super) const MAX_INTERIOR_ROUNDS: usize = 64;

pub(super) struct State {
    pub(super) surf: Surface,
    pub(super) report: RecoverReport,
    pub(super) inexact: Vec<u32>,
    pub(super) max_dev_scaled: f64,
    pub(super) opts: RecoverOptions,
    /// Per input triangle: the Steiner points inside it.
    pub(super) tri_inner: IdMap<u32, Vec<u32>>,
    /// Per input triangle: how many of its facet points encroached a
    /// boundary subsegment (`insert_in_facet`: the first `MAX_REDIRECTS`
    /// split it instead).
    pub(super) redirected: IdMap<u32, u32>,
    /// Per input triangle: interior points tried for it (`-Y`).
    pub(super) interior_tries: IdMap<u32, usize>,
    /// Groups of failing triangles whose centroid was tried (`-Y`).
    pub(super) group_tries: HashSet<Vec<usize>>,
    /// Unfinished cavity retriangulation calls (`-Y`, the `cavity` module).
    pub(super) cavity_fails: usize,
    /// Whether the fallback that always applies (`-Y`) was tried (and
    /// failed, else the recovery is over).
    pub(super) fallback_tried: bool,
    /// Triangles left missing by the last unfinished cavity call (`-Y`).
    pub(super) cavity_left: Vec<usize>,
    /// Tetrahedra found by the cavity searches of the cavity calls so far
    /// (`-Y`): their work, which bounds a call while the fallback is
    /// still untried (the `cavity` module's `VISITS_PER_CELL`).
    pub(super) cavity_work: std::cell::Cell<u64>,
    /// `-Y`: no cavity retriangulation before the first interior point
    /// ([`State::cavities_now`]).
    pub(super) points_first: bool,
    /// What the first failing round of [`State::points_first`] left missing.
    pub(super) first_missing: Option<(u8, usize)>,
    /// Merged groups recovered as polygons (constrained path).
    pub(super) poly: Polygons,
    /// Flip budget per segment attempt of the `-p` path
    /// ([`cdt::SEG_OPS`]; the `-Y` fallback retries with others).
    pub(super) seg_ops: usize,
    /// The `-p` recovery of the `-Y` fallback (`cavity/pull.rs`): facet
    /// points split the subsegments they encroach without limit
    /// (`MAX_REDIRECTS`), and segments try the cones of
    /// `cdt::cone_segment` as with `stop_circling_flips`.
    pub(super) y_fallback: bool,
    /// Whether a segment whose flips give up tries the cone over a flat
    /// facet of the convex hull (`cdt::Effort::flat`): not in the `-Y`
    /// fallback's later runs.
    pub(super) flat_cones: bool,
    /// The segments still failing after a round's passes are tried again
    /// with deeper edge removals (levels 3 to `MAX_LEVEL`): the second and
    /// third runs of the `-Y` fallback's recovery.
    pub(super) escalate: bool,
    /// `-p` without `-q`: splits no longer go into the flipped mesh in
    /// place (`State::split_in_place` met pieces that keep failing twice).
    pub(super) in_place_off: bool,
    /// When `State::split_in_place` meets its bounds, and after
    /// `in_place_off`, the segment splits of a round also go into the
    /// flipped mesh, which the next round goes on in (`-p` and `-pM`, and
    /// the `-Y` fallback's guided runs; its later runs start each such
    /// round from the Delaunay tetrahedralization).
    pub(super) carry_splits: bool,
    /// How many rounds went on in the flipped mesh after their segment
    /// splits were mirrored into it (`MAX_CARRIED_SPLITS`).
    pub(super) carried_splits: u32,
    /// `State::split_in_place` met pieces that keep failing once (its
    /// round then ended; the next one splits in place again).
    pub(super) split_bounds_met: bool,
    /// Per merged group: the last coverage the global pass computed and
    /// what it was computed from (`State::groups_global`).
    pub(super) cover_memo: std::cell::RefCell<Vec<CoverMemo>>,
    /// When `State::run_cdt` gives up (the unguided recovery of
    /// `recover_mesh`); `None`: never (but on its Steiner budget).
    pub(super) give_up: Option<GiveUp>,
}

/// A group's coverage ([`Polygons::cover`]) with its inputs that change
/// during the recovery: the tetrahedra given, and the chains of the
/// group's boundary edges. Everything else it reads is fixed per point id
/// within one [`State`] (coordinates, the triangles a point lies on, its
/// kind), so the same inputs give the same coverage.
#[derive(Default)]
pub(super) struct CoverMemo {
    /// Per boundary edge use of the group: its chain's length, then the
    /// chain.
    pub(super) chains: Vec<u32>,
    /// The tetrahedra, as given.
    pub(super) tets: Vec<[u32; 4]>,
    /// The coverage found (`None`: none yet).
    pub(super) cover: Option<Cover>,
}

/// One merged group.
#[derive(Debug, Clone)]
pub(crate) struct Group {
    /// Its triangles (surface indices, ascending); the first is the
    /// representative.
    pub(crate) tris: Vec<u32>,
    /// Its boundary edge uses: (surface edge, whether a triangle of the
    /// group runs along it from `edges[e][0]` to `edges[e][1]`). The
    /// group lies on the left of each use, in its orientation.
    pub(crate) bnd: Vec<(u32, bool)>,
    /// Axis dropped by the projection to the plane, and the sign of the
    /// projected orientation of the group's triangles.
    pub(super) k: usize,
    pub(super) sign: f64,
}

/// The merged groups of a surface (see the module notes).
#[derive(Debug, Clone, Default)]
pub(crate) struct Polygons {
    /// Per surface triangle: its group, or `u32::MAX`.
    pub(crate) of_tri: Vec<u32>,
    /// The groups.
    pub(crate) groups: Vec<Group>,
}

/// What [`Polygons::cover`] found for one group.
#[derive(Clone)]
pub(crate) struct Cover {
    /// The faces reached by the flood fill (sorted triples, sorted).
    pub(crate) faces: Vec<[u32; 3]>,
    /// Whether they cover the polygon exactly.
    pub(crate) covered: bool,
    /// Boundary subsegments with no face on their inner side: (edge, and
    /// its ends in chain order).
    pub(crate) bare: Vec<(u32, u32, u32)>,
}

/// When `State::run_cdt` gives up ([`State::give_up`]), at the start of a
/// round.
#[derive(Debug, Clone, Copy)]
pub(super) struct GiveUp {
    /// After this many rounds in a row that left no fewer items missing
    /// than the best round before them.
    pub(super) rounds: usize,
    /// Once it has inserted more Steiner points than this.
    pub(super) steiner: usize,
}
