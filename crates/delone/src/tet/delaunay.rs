//! The incremental 3D Delaunay kernel.
//!
//! Points are inserted in BRIO + Hilbert order ([`crate::geom::brio_order`]).
//! Each insertion
//!
//! 1. **locates** the new point by a visibility walk from the last created
//!    tetrahedron (stochastic facet order from a fixed-seed generator, so the
//!    walk cannot cycle and every run is identical);
//! 2. grows the **Bowyer–Watson cavity** — the tetrahedra whose circumsphere
//!    contains the point — by a breadth-first search that writes nothing but
//!    marks, recording the cavity's boundary facets;
//! 3. **stellates** the cavity: one new tetrahedron per boundary facet,
//!    glued to the new tetrahedra made before it as it is made, through a
//!    tiny hash table of the cavity boundary's edges, reusing dead slots.
//!
//! The insertion (`insert_in`) is written once over the cells it may touch
//! (`Cells`): the whole arrays, or the slots of one group of parts of a
//! parallel insertion, where a point whose walk or cavity reaches a cell
//! outside them is left for later and nothing is changed.
//!
//! Every decision is an exact predicate. Cospherical configurations are
//! resolved by [`delone_predicates::insphere_sos`] (symbolic perturbation of the
//! lifted coordinate ordered by vertex index), which makes the result the
//! regular triangulation of a generically perturbed weighted set: always a
//! valid triangulation, never a flat tetrahedron, and a function of the input
//! only. A point on the plane of a hull facet conflicts with the ghost cell of
//! that facet exactly when it conflicts with the finite cell behind it (the
//! limit of the circumsphere as its fourth vertex goes to infinity).
//!
//! Storage is flat: `v: Vec<[u32; 4]>`, `adj: Vec<[u32; 4]>` (packed
//! `4 * tet + facet`, see [`super::local`]) and a free list: 32 bytes per
//! tetrahedron.
//!
//! # Details
//!
//! * Ghost cells keep the infinite vertex in position 3 (new cells are
//!   evenly permuted), so the ghost test is one comparison.
//! * The cavity search marks cells in the two high bits of their first
//!   vertex (the cache line the conflict test reads anyway); the marks are
//!   cleared from the cavity and rejected lists, never by a sweep; the
//!   edge table of the stellation (keyed by the unordered pair, met exactly
//!   twice) uses generation stamps.
//! * The one-call constructor inserts copies of the points in insertion
//!   order (consecutive insertions read neighbouring memory) and relabels
//!   the tetrahedra with input ids at the end; ties are broken by input id
//!   throughout, so the copies change no decision.
//!   [`Delaunay3::from_points_in_place`] reorders the caller's slice
//!   instead of copying it (`crate::geom::sort::scatter_in_place`, before
//!   and after): one copy of the points at the peak, not two.
//! * The one-call constructor borrows the caller's points (`Cow`), reserves
//!   about 6.75 cells per point and grows by steps of 1/8; `into_mesh`
//!   compacts in place (no second copy).
//! * **Parallel insertion** (Delaunay, one-call constructor, every BRIO round
//!   of at least 65,536 points, one after the other: on 1M points the last
//!   two): the round's points fall in four parts, the quarters of their box
//!   cut at the medians of its two longest axes `x` and `y`; every cell goes
//!   to the quarter holding its centroid and the cells are copied so that
//!   each part owns one block of slots with room for what it will create
//!   (zeroed memory: slots never used are never touched); the centroids and
//!   the copy run on the threads too. Two passes insert the points in
//!   groups of two parts side by side on up to `threads` threads
//!   (`crate::par::run_dynamic`): first the halves `x-` and `x+`, which also
//!   leave the points within 1.5 point spacings of their border, then the
//!   halves `y+` and `y-`, which split those between them; the few left
//!   (near the line where the medians' planes cross: 0.4% of 1M uniform
//!   points) are inserted serially. A group reads and writes only its own
//!   blocks and leaves a point as soon as it would touch another group's
//!   cell, so its result does not depend on the other group's progress:
//!   the arrays, hence the output, are the same for every thread count.
//! * Duplicates are found at location time (bit-equal to a vertex of the
//!   containing cell) and mapped to the lowest index of their group.
//! * Regular triangulations run the same code monomorphised on a const flag:
//!   the power test (`insphere_weighted_sos`) replaces the in-sphere test; a
//!   new point not in power conflict with its containing cell is hidden;
//!   vertices of cavity cells that do not reach the cavity boundary become
//!   hidden (found with a per-vertex stamp that exists only for weighted
//!   input).
//! * Ties (cospherical points) are broken by input index, so the one-call
//!   and the point-by-point builds give the same tetrahedra even on grids.
//!   Exception: a group of exact duplicates is perturbed under the id
//!   inserted first, so when such a group is part of a cospherical tie the
//!   tie-break can depend on the order (the output is valid and
//!   deterministic either way).
//!
//! # References
//! A. Bowyer (1981), D. F. Watson (1981); N. Amenta, S. Choi, G. Rote,
//! *Incremental constructions con BRIO* (2003); O. Devillers, S. Pion,
//! M. Teillaud, *Walking in a triangulation* (2002); C. Marot, J. Pellerin,
//! J.-F. Remacle, *One machine, one minute, three billion tetrahedra* (2019).

use std::borrow::Cow;

use delone_predicates::{insphere, insphere_tie_sos, insphere_weighted, orient3d};

use super::local::{DEAD, FACET, INF};
use super::TetMesh;
pub use crate::Inserted;
use crate::{Error, NONE};

/// Where a query point lies, as answered by [`Delaunay3::locate`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Location {
    /// Inside or on the boundary of the finite tetrahedron with this slot id.
    InTet(u32),
    /// Exactly at this vertex.
    OnVertex(u32),
    /// Outside the convex hull, beyond the hull triangle of this ghost slot.
    OutsideHull(u32),
    /// No tetrahedron exists yet.
    Empty,
}

/// Marks of a slot during an insertion, kept in the two high bits of its
/// first vertex (vertex ids stay below [`MAX_POINTS`] < 2^30; a live cell's
/// first vertex is never [`INF`], a marked one is never [`DEAD`]): the mark
/// is read from the cache line the conflict test loads anyway.
const MARK_CAVITY: u32 = 1 << 31;
const MARK_KEEP: u32 = 1 << 30;
/// The vertex bits of a possibly marked first vertex.
const UNMARK: u32 = MARK_KEEP - 1;

/// Number of parts a BRIO round is inserted in (see `Core::insert_parts`)
/// when it has at least [`PARALLEL_MIN_POINTS`] points: the quarters of
/// the points' box cut at the medians of its two longest axes, `x` and
/// `y`, numbered around the centre: `(x-, y-)`, `(x-, y+)`, `(x+, y+)`,
/// `(x+, y-)` (their blocks of slots in this order).
const PARTS: usize = 4;

/// The passes of a parallel insertion: groups of parts inserted side by
/// side. First the halves `x-` and `x+` (the first pass also leaves the
/// points near their border), then the halves `y+` and `y-`, which split
/// the points left near `x`'s median between them (`y-` owns two blocks
/// of slots, the first and the last).
const PASSES: [&[&[usize]]; 2] = [&[&[0, 1], &[2, 3]], &[&[1, 2], &[3, 0]]];

/// How far from its group's borders, in spacings of the points inserted
/// before the round, the first pass leaves points for the second.
const DEFER_SPACINGS: f64 = 1.5;

/// Smallest BRIO round inserted in parts.
const PARALLEL_MIN_POINTS: usize = 1 << 16;

/// How a one-call construction may split its work: the threads, and the
/// smallest BRIO round inserted in parts (the parts do not depend on
/// the threads).
#[derive(Debug, Clone, Copy)]
struct Split {
    threads: usize,
    min_points: usize,
}

impl Split {
    /// One point at a time, no parts: the numbering the recovery and
    /// every pipeline build on, whatever the input's size.
    fn serial() -> Self {
        Split {
            threads: 1,
            min_points: usize::MAX,
        }
    }

    fn threads(threads: usize) -> Self {
        Split {
            threads,
            min_points: PARALLEL_MIN_POINTS,
        }
    }
}

/// How many insertions between two progress callbacks.
const PROGRESS_STEP: usize = 1 << 16;

/// A small open-addressing table from edges of the cavity boundary to
/// new-tet facets, used to glue the stellated cavity. An entry is live
/// when its stamp is the table's: all are invalidated by bumping `stamp`.
/// An entry's key, value and stamp share one 16-byte slot (one bounds
/// check and one cache line per probe).
#[derive(Debug, Clone, Default)]
struct EdgeTable {
    /// Per slot: the key, the value, the stamp.
    slots: Vec<(u64, u32, u32)>,
    stamp: u32,
}

impl EdgeTable {
    fn reset(&mut self, edges: usize) {
        let want = (edges * 2).next_power_of_two().max(64);
        if self.slots.len() < want {
            self.slots = vec![(0, 0, 0); want];
            self.stamp = 0;
        }
        self.stamp = self.stamp.wrapping_add(1);
        if self.stamp == 0 {
            self.slots.iter_mut().for_each(|s| s.2 = 0);
            self.stamp = 1;
        }
    }

    /// Pairs the two new-cell facets through the cavity boundary's edge
    /// `{a, b}` (the boundary is a closed surface: each of its edges is met
    /// exactly twice, once from each of its two triangles): the value stored
    /// by the first meeting, or `None` after storing `val`. The key is the
    /// unordered pair, so one probe sequence serves both meetings.
    #[inline(always)]
    fn pair(&mut self, a: u32, b: u32, val: u32) -> Option<u32> {
        let mask = self.slots.len() - 1;
        let key = (u64::from(a.min(b)) << 32) | u64::from(a.max(b));
        let mut i = (key.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 40) as usize & mask;
        loop {
            let e = &mut self.slots[i];
            if e.2 != self.stamp {
                *e = (key, val, self.stamp);
                return None;
            }
            if e.0 == key {
                return Some(e.1);
            }
            i = (i + 1) & mask;
        }
    }
}

/// What an insertion reads: coordinates and weights by id (`wts` empty for a
/// Delaunay triangulation), and the input id of each id, which orders the
/// symbolic perturbation (`ids` empty: the ids are input ids).
#[derive(Clone, Copy)]
struct Geo<'p> {
    pts: &'p [[f64; 3]],
    wts: &'p [f64],
    ids: &'p [u32],
}

/// The combinatorial part of the kernel: tetrahedra, adjacency, marks and
/// scratch space. Geometry enters only through the `pts` argument.
#[derive(Debug, Clone, Default)]
pub(crate) struct Core {
    /// Vertices of every slot (`DEAD` in `[0]` for a free slot).
    pub(crate) v: Vec<[u32; 4]>,
    /// Packed adjacency words `4 * tet + facet`.
    pub(crate) adj: Vec<[u32; 4]>,
    /// Free slots.
    pub(crate) free: Vec<u32>,
    /// Number of finite live cells.
    pub(crate) finite: usize,
    /// Start cell of the next walk.
    pub(crate) last: u32,
    rng: u32,
    /// Set once an insertion ran out of index space; the structure then
    /// refuses further insertions.
    overflow: bool,
    scratch: Scratch,
    /// Threads for the whole-array passes of [`Core::into_arrays`] (0 or 1:
    /// this one).
    threads: usize,
}

/// The scratch space of one insertion (one per part of a parallel
/// insertion).
#[derive(Debug, Clone, Default)]
struct Scratch {
    cavity: Vec<u32>,
    kept: Vec<u32>,
    /// The cavity's boundary facets met by the search: the new cell (the
    /// facet and the new point, evenly permuted), the local index of the
    /// facet in it, and the adjacency word of the cell outside.
    bnd: Vec<([u32; 4], u32, u32)>,
    /// Vertices hidden by the last weighted insertion.
    hidden_now: Vec<u32>,
    /// Per-vertex stamps for `find_hidden` (weighted triangulations only).
    vstamp: Vec<u32>,
    vstamp_next: u32,
    edges: EdgeTable,
}

/// Read access to the cells an insertion may touch: this kernel's arrays,
/// recovery's domain mesh ([`Arrays`]), or the slot range of one part of a
/// parallel insertion (which does not own the cells of the other parts).
pub(crate) trait Cells {
    /// Whether slot `t` may be read (and, for an insertion, written).
    fn owns(&self, t: u32) -> bool;
    /// The vertices of owned slot `t`.
    fn v(&self, t: u32) -> &[u32; 4];
    /// The packed neighbour words of owned slot `t`.
    fn adj(&self, t: u32) -> &[u32; 4];
}

/// The cells an insertion writes.
trait CellsMut: Cells {
    fn v_mut(&mut self, t: u32) -> &mut [u32; 4];
    fn adj_mut(&mut self, t: u32) -> &mut [u32; 4];
    /// Whether `k` more slots can be allocated.
    fn room(&mut self, k: usize) -> bool;
    /// A slot for a new cell (after `room`).
    fn alloc(&mut self, tv: [u32; 4]) -> u32;
    /// Frees owned live slot `t`.
    fn release(&mut self, t: u32);
    /// The walk's start cell and random state.
    fn hint(&mut self) -> (&mut u32, &mut u32);
}

impl Cells for Arrays<'_> {
    #[inline(always)]
    fn owns(&self, _: u32) -> bool {
        true
    }
    #[inline(always)]
    fn v(&self, t: u32) -> &[u32; 4] {
        &self.0[t as usize]
    }
    #[inline(always)]
    fn adj(&self, t: u32) -> &[u32; 4] {
        &self.1[t as usize]
    }
}

impl Cells for Core {
    #[inline(always)]
    fn owns(&self, _: u32) -> bool {
        true
    }
    #[inline(always)]
    fn v(&self, t: u32) -> &[u32; 4] {
        &self.v[t as usize]
    }
    #[inline(always)]
    fn adj(&self, t: u32) -> &[u32; 4] {
        &self.adj[t as usize]
    }
}

impl CellsMut for Core {
    #[inline(always)]
    fn v_mut(&mut self, t: u32) -> &mut [u32; 4] {
        &mut self.v[t as usize]
    }
    #[inline(always)]
    fn adj_mut(&mut self, t: u32) -> &mut [u32; 4] {
        &mut self.adj[t as usize]
    }
    #[inline(always)]
    fn room(&mut self, _: usize) -> bool {
        true
    }
    #[inline(always)]
    fn alloc(&mut self, tv: [u32; 4]) -> u32 {
        Core::alloc(self, tv)
    }
    #[inline(always)]
    fn release(&mut self, t: u32) {
        Core::release(self, t)
    }
    #[inline(always)]
    fn hint(&mut self) -> (&mut u32, &mut u32) {
        (&mut self.last, &mut self.rng)
    }
}

/// The slots of one part of a parallel insertion: `lo..hi`, of which
/// `used..hi` were never used, and its free slots.
#[derive(Debug, Default)]
struct Block {
    lo: u32,
    hi: u32,
    used: u32,
    free: Vec<u32>,
}

/// The slot range `base..base + v.len()` of the shared arrays (with `TWO`,
/// also `base2..base2 + v2.len()`), owned by one group of parts of a
/// parallel insertion: their blocks (which tile the ranges), the block new
/// cells go to, the walk state.
struct Part<'c, const TWO: bool> {
    base: u32,
    v: &'c mut [[u32; 4]],
    adj: &'c mut [[u32; 4]],
    base2: u32,
    v2: &'c mut [[u32; 4]],
    adj2: &'c mut [[u32; 4]],
    blocks: Vec<Block>,
    /// The block of the part the point being inserted belongs to: its
    /// new cells go there.
    cur: usize,
    /// Finite cells created minus finite cells removed.
    finite: isize,
    last: u32,
    rng: u32,
}

/// The vertex and neighbour slots of one part's range.
type Slots<'c> = (&'c mut [[u32; 4]], &'c mut [[u32; 4]]);

impl<const TWO: bool> Part<'_, TWO> {
    /// Whether slot `t` is in the first range, and its index there.
    #[inline(always)]
    fn first(&self, t: u32) -> (bool, usize) {
        let i = t.wrapping_sub(self.base) as usize;
        (!TWO || i < self.v.len(), i)
    }
}

impl<const TWO: bool> Cells for Part<'_, TWO> {
    #[inline(always)]
    fn owns(&self, t: u32) -> bool {
        (t.wrapping_sub(self.base) as usize) < self.v.len()
            || (TWO && (t.wrapping_sub(self.base2) as usize) < self.v2.len())
    }
    #[inline(always)]
    fn v(&self, t: u32) -> &[u32; 4] {
        match self.first(t) {
            (true, i) => &self.v[i],
            (false, _) => &self.v2[(t - self.base2) as usize],
        }
    }
    #[inline(always)]
    fn adj(&self, t: u32) -> &[u32; 4] {
        match self.first(t) {
            (true, i) => &self.adj[i],
            (false, _) => &self.adj2[(t - self.base2) as usize],
        }
    }
}

impl<const TWO: bool> CellsMut for Part<'_, TWO> {
    #[inline(always)]
    fn v_mut(&mut self, t: u32) -> &mut [u32; 4] {
        match self.first(t) {
            (true, i) => &mut self.v[i],
            (false, _) => &mut self.v2[(t - self.base2) as usize],
        }
    }
    #[inline(always)]
    fn adj_mut(&mut self, t: u32) -> &mut [u32; 4] {
        match self.first(t) {
            (true, i) => &mut self.adj[i],
            (false, _) => &mut self.adj2[(t - self.base2) as usize],
        }
    }
    #[inline(always)]
    fn room(&mut self, k: usize) -> bool {
        (self.blocks.iter())
            .map(|b| b.free.len() + (b.hi - b.used) as usize)
            .sum::<usize>()
            >= k
    }
    #[inline(always)]
    fn alloc(&mut self, tv: [u32; 4]) -> u32 {
        // A free slot is dead or was never used (zeroed memory): either
        // way it holds no cell. From the current block while it has one,
        // then from another.
        let full = |b: &Block| b.free.is_empty() && b.used == b.hi;
        let mut k = self.cur;
        if full(&self.blocks[k]) {
            k = self.blocks.iter().position(|b| !full(b)).unwrap_or(k);
        }
        let b = &mut self.blocks[k];
        let t = match b.free.pop() {
            Some(t) => t,
            None => {
                b.used += 1;
                b.used - 1
            }
        };
        *self.v_mut(t) = tv;
        self.finite += isize::from(tv[3] != INF);
        t
    }
    #[inline(always)]
    fn release(&mut self, t: u32) {
        let tv = self.v_mut(t);
        let finite = tv[3] != INF;
        tv[0] = DEAD;
        self.finite -= isize::from(finite);
        let k = (self.blocks.iter())
            .position(|b| (b.lo..b.hi).contains(&t))
            .unwrap_or(0);
        self.blocks[k].free.push(t);
    }
    #[inline(always)]
    fn hint(&mut self) -> (&mut u32, &mut u32) {
        (&mut self.last, &mut self.rng)
    }
}

/// Incremental 3D Delaunay tetrahedralization.
///
/// Points are identified by their index in the order given (the one-call
/// constructor borrows the caller's slice, so nothing is copied).
///
/// ```
/// use delone::tet::{Delaunay3, Inserted};
/// let mut dt = Delaunay3::new();
/// for p in [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]] {
///     dt.insert(p).unwrap();
/// }
/// assert_eq!(dt.num_tets(), 1);
/// assert_eq!(dt.insert([0.25, 0.25, 0.25]).unwrap(), Inserted::Vertex(4));
/// assert_eq!(dt.num_tets(), 4);
/// dt.check_topology().unwrap();
/// dt.check_delaunay().unwrap();
/// ```
#[derive(Debug, Clone, Default)]
pub struct Delaunay3<'a> {
    /// The points by id: the caller's (borrowed by `from_points`, owned when
    /// inserting one by one), multiplied by `scale` when their magnitudes are
    /// extreme.
    pub(crate) points: Cow<'a, [[f64; 3]]>,
    /// Exact power-of-two factors applied to the caller's coordinates (see
    /// [`crate::geom::pow2_scale`]); chosen from the first point when
    /// inserting one by one.
    pub(crate) scale: Option<(f64, f64)>,
    /// Weights by id (scaled by the square of `scale`) for a regular
    /// triangulation; `None` for a Delaunay triangulation.
    pub(crate) weights: Option<Cow<'a, [f64]>>,
    /// Points left out of the regular triangulation (empty power cell).
    hidden: Vec<u32>,
    pub(crate) core: Core,
    /// Per point: itself when inserted, its original when a duplicate, NONE
    /// while pending.
    pub(crate) vertex_map: Vec<u32>,
    duplicates: Vec<(u32, u32)>,
    /// Points waiting for the first tetrahedron (incremental use only).
    pub(crate) pending: Vec<u32>,
    /// Up to three affinely independent pending points.
    basis: Vec<u32>,
}

/// Most tetrahedron slots: adjacency words are `4 * tet + facet` in a `u32`.
const MAX_TETS: usize = (1 << 30) - 1;

/// Most points: vertex ids leave the two high bits free for the insertion
/// marks (more points than tetrahedron slots could not be triangulated anyway).
const MAX_POINTS: usize = (1 << 30) - 1;

fn check_coords(points: &[[f64; 3]]) -> Result<(), Error> {
    if points.len() > MAX_POINTS {
        return Err(Error::CapacityExceeded {
            requested: points.len(),
        });
    }
    match points.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
        Some(index) => Err(Error::InvalidCoordinate { index }),
        None => crate::geom::scale::check_range(points, crate::geom::scale::RANGE_3D),
    }
}

/// Tries to extend an affinely independent `basis` (0..=3 points) with `id`.
/// Returns true when `id` was added.
fn extends_basis(pts: &[[f64; 3]], basis: &[u32], id: u32) -> bool {
    let p = &pts[id as usize];
    let b = |i: usize| &pts[basis[i] as usize];
    match basis.len() {
        0 => true,
        1 => p != b(0),
        2 => !crate::geom::vec3::collinear(b(0), b(1), p),
        3 => orient3d(b(0), b(1), b(2), p) != 0.0,
        _ => false,
    }
}

impl Delaunay3<'static> {
    /// An empty triangulation for incremental insertion.
    ///
    /// ```
    /// let dt = delone::tet::Delaunay3::new();
    /// assert_eq!(dt.num_tets(), 0);
    /// ```
    pub fn new() -> Self {
        Self::default()
    }
}

impl<'a> Delaunay3<'a> {
    /// Builds the Delaunay tetrahedralization of `points` (borrowed, not
    /// copied) in BRIO + Hilbert order.
    ///
    /// # Errors
    /// [`Error::InvalidCoordinate`] (NaN or infinite), [`Error::TooFewPoints`]
    /// (fewer than 4 distinct points), [`Error::Degenerate`] (all points
    /// collinear or coplanar), [`Error::CapacityExceeded`].
    ///
    /// ```
    /// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 1.0, 1.0]];
    /// let dt = delone::tet::Delaunay3::from_points(&pts).unwrap();
    /// assert_eq!(dt.num_tets(), 2);
    /// ```
    pub fn from_points(points: &'a [[f64; 3]]) -> Result<Self, Error> {
        Self::from_points_with_progress(points, &mut |_, _| {})
    }

    /// Like [`Delaunay3::from_points`], calling `progress(inserted, total)`
    /// every 65536 insertions and once at the end.
    ///
    /// ```
    /// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    /// let mut last = (0, 0);
    /// delone::tet::Delaunay3::from_points_with_progress(&pts, &mut |d, t| last = (d, t)).unwrap();
    /// assert_eq!(last, (4, 4));
    /// ```
    pub fn from_points_with_progress(
        points: &'a [[f64; 3]],
        progress: &mut dyn FnMut(usize, usize),
    ) -> Result<Self, Error> {
        Self::build(points, None, Split::serial(), progress)
    }

    /// Like [`Delaunay3::from_points_with_progress`], on up to `threads`
    /// threads (0 counts as 1). The result is the same for every thread
    /// count: large inputs are inserted in a fixed number of spatial parts
    /// whatever the number of threads running them. Its tetrahedra are
    /// those of [`Delaunay3::from_points`]; their numbering differs when
    /// the input is large enough for parts (75k points or more).
    ///
    /// ```
    /// let pts: Vec<[f64; 3]> = (0..1000u32)
    ///     .map(|i| [(i % 10) as f64, (i / 10 % 10) as f64, (i / 100) as f64])
    ///     .collect();
    /// let one = delone::tet::Delaunay3::from_points_with_threads(&pts, 1, &mut |_, _| {}).unwrap();
    /// let two = delone::tet::Delaunay3::from_points_with_threads(&pts, 2, &mut |_, _| {}).unwrap();
    /// assert_eq!(one.into_mesh(), two.into_mesh());
    /// ```
    pub fn from_points_with_threads(
        points: &'a [[f64; 3]],
        threads: usize,
        progress: &mut dyn FnMut(usize, usize),
    ) -> Result<Self, Error> {
        Self::build(points, None, Split::threads(threads), progress)
    }

    /// The regular (weighted Delaunay) tetrahedralization of `points` with
    /// `weights`: the dual of their power diagram. Points whose power cell is
    /// empty are left out and listed by [`Delaunay3::hidden`]. With all
    /// weights zero the result is exactly the Delaunay tetrahedralization.
    ///
    /// # Errors
    /// As [`Delaunay3::from_points`], plus [`Error::InvalidWeight`] for a NaN
    /// or infinite weight and [`Error::WeightCount`] when the lengths differ.
    ///
    /// ```
    /// let pts = [[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [0.0, 4.0, 0.0], [0.0, 0.0, 4.0], [1.0, 1.0, 1.0]];
    /// // The last point is light: its power cell is empty.
    /// let dt = delone::tet::Delaunay3::from_weighted_points(&pts, &[0.0, 0.0, 0.0, 0.0, -10.0]).unwrap();
    /// assert_eq!(dt.hidden(), &[4]);
    /// assert_eq!(dt.num_tets(), 1);
    /// ```
    pub fn from_weighted_points(points: &'a [[f64; 3]], weights: &'a [f64]) -> Result<Self, Error> {
        Self::build(points, Some(weights), Split::serial(), &mut |_, _| {})
    }

    /// [`Delaunay3::from_weighted_points`] with a progress callback.
    ///
    /// ```
    /// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    /// let mut calls = 0;
    /// delone::tet::Delaunay3::from_weighted_points_with_progress(&pts, &[0.0; 4], &mut |_, _| calls += 1).unwrap();
    /// assert!(calls >= 1);
    /// ```
    pub fn from_weighted_points_with_progress(
        points: &'a [[f64; 3]],
        weights: &'a [f64],
        progress: &mut dyn FnMut(usize, usize),
    ) -> Result<Self, Error> {
        Self::build(points, Some(weights), Split::serial(), progress)
    }

    /// Like [`Delaunay3::from_points_with_threads`] (the same result), with
    /// one copy of the points instead of two: the construction reads the
    /// points in insertion order, so it reorders the caller's slice in
    /// place while it runs and restores it before returning — also on
    /// error. Inputs of extreme magnitude (scaled by a power of two for the
    /// predicates) are copied as by [`Delaunay3::from_points_with_threads`].
    ///
    /// ```
    /// let mut pts: Vec<[f64; 3]> = (0..1000u32)
    ///     .map(|i| [(i % 10) as f64, (i / 10 % 10) as f64, (i / 100) as f64 + 0.5])
    ///     .collect();
    /// let copy = pts.clone();
    /// let two = delone::tet::Delaunay3::from_points_with_threads(&copy, 2, &mut |_, _| {}).unwrap();
    /// let one = delone::tet::Delaunay3::from_points_in_place(&mut pts, 2, &mut |_, _| {}).unwrap();
    /// assert_eq!(one.into_mesh(), two.into_mesh());
    /// assert_eq!(pts, copy);
    /// ```
    pub fn from_points_in_place(
        points: &'a mut [[f64; 3]],
        threads: usize,
        progress: &mut dyn FnMut(usize, usize),
    ) -> Result<Self, Error> {
        let split = Split::threads(threads);
        check_coords(points)?;
        if crate::geom::pow2_scale(crate::geom::max_abs(points)) != (1.0, 1.0) {
            return Self::build(points, None, split, progress);
        }
        let mut order = insertion_order(points, split.threads)?;
        // The point of input id order[k] moves to k.
        let mut rank = vec![0u32; order.len()];
        for (k, &i) in order.iter().enumerate() {
            rank[i as usize] = k as u32;
        }
        crate::geom::sort::scatter_in_place(points, &mut rank, split.threads);
        drop(rank);
        let built = Self::insert_ordered(points, &[], &order, split, progress);
        crate::geom::sort::scatter_in_place(points, &mut order, split.threads);
        drop(order);
        let mut dt = built?;
        dt.map_vertices(points.len());
        let points: &'a [[f64; 3]] = points;
        dt.points = Cow::Borrowed(points);
        dt.scale = Some((1.0, 1.0));
        progress(points.len(), points.len());
        Ok(dt)
    }

    fn build(
        points: &'a [[f64; 3]],
        weights: Option<&'a [f64]>,
        split: Split,
        progress: &mut dyn FnMut(usize, usize),
    ) -> Result<Self, Error> {
        check_coords(points)?;
        if let Some(w) = weights {
            if w.len() != points.len() {
                return Err(Error::WeightCount {
                    points: points.len(),
                    weights: w.len(),
                });
            }
            if let Some(index) = w.iter().position(|x| !x.is_finite()) {
                return Err(Error::InvalidWeight { index });
            }
        }
        // Extreme magnitudes are scaled by an exact power of two (a copy);
        // ordinary inputs are borrowed as they are.
        let (cow, scale) = crate::geom::rescaled(points);
        let points: &[[f64; 3]] = &cow;
        // Power distances scale with the square of the coordinates.
        let wcow: Option<Cow<'a, [f64]>> = weights.map(|w| {
            if scale == (1.0, 1.0) {
                Cow::Borrowed(w)
            } else {
                Cow::Owned(
                    w.iter()
                        .map(|&x| x * scale.0 * scale.0 * scale.1 * scale.1)
                        .collect(),
                )
            }
        });
        let wts: &[f64] = wcow.as_deref().unwrap_or(&[]);
        let n = points.len();
        let order = insertion_order(points, split.threads)?;
        // The insertion works on copies in insertion order, so that
        // consecutive insertions read neighbouring memory.
        let local: Vec<[f64; 3]> = order.iter().map(|&i| points[i as usize]).collect();
        let local_w: Vec<f64> = match wts.is_empty() {
            true => Vec::new(),
            false => order.iter().map(|&i| wts[i as usize]).collect(),
        };
        let mut dt = Self::insert_ordered(&local, &local_w, &order, split, progress)?;
        // The vertex map after the copies are gone: a smaller peak.
        drop((local, local_w, order));
        dt.map_vertices(n);
        dt.points = cow;
        dt.scale = Some(scale);
        dt.weights = wcow;
        progress(n, n);
        Ok(dt)
    }

    /// The triangulation of `local` (weighted by `local_w` unless empty),
    /// the points in insertion order: `order[k]` is the input id of
    /// `local[k]`, the id the result uses. Its `points`, `scale`,
    /// `weights` and vertex map are left for the caller to fill.
    fn insert_ordered(
        local: &[[f64; 3]],
        local_w: &[f64],
        order: &[u32],
        split: Split,
        progress: &mut dyn FnMut(usize, usize),
    ) -> Result<Self, Error> {
        let n = local.len();
        let mut dt = Delaunay3 {
            points: Cow::Borrowed(&[]),
            scale: None,
            weights: None,
            hidden: Vec::new(),
            core: Core::default(),
            vertex_map: Vec::new(),
            duplicates: Vec::new(),
            pending: Vec::new(),
            basis: Vec::new(),
        };
        // Expected ~6.8 tetrahedra per point for uniform points; growth past
        // this is by 1/8 steps (see `Core::alloc`).
        let cap = n + n * 27 / 4 + 64;
        dt.core.v.reserve_exact(cap);
        dt.core.adj.reserve_exact(cap);
        dt.core.threads = split.threads;
        // Ids are insertion ranks (`order` maps them back) until the
        // relabelling below. Ties are still broken by input id
        // (`Geo::ids`), so the result is the same tetrahedra in the same
        // slots as with input ids.
        let geo = Geo {
            pts: local,
            wts: local_w,
            ids: order,
        };
        let input = |k: u32| order[k as usize];
        dt.core.start(local, [0, 1, 2, 3]);
        // The BRIO rounds of a large Delaunay triangulation with at least
        // `split.min_points` points are inserted in parts
        // (`Core::insert_parts`), the earlier ones one by one; which rounds
        // and their parts depend on the points only, so the output is the
        // same for every thread count.
        let mut rounds = Vec::new();
        if local_w.is_empty() {
            let mut end = n;
            while end > 4 {
                let start = crate::geom::sort::round_start(order, end, 4);
                if end - start < split.min_points {
                    break;
                }
                rounds.push(start..end);
                end = start;
            }
            rounds.reverse();
        }
        let note = |dt: &mut Self, r: Inserted| match r {
            Inserted::Duplicate { id, original } => {
                dt.duplicates.push((input(id), input(original)));
            }
            Inserted::Hidden(id) => dt.hidden.push(input(id)),
            _ => {}
        };
        let serial_end = rounds.first().map_or(n, |r| r.start);
        for k in 4..serial_end {
            let r = dt.core.insert_any(geo, k as u32)?;
            note(&mut dt, r);
            dt.hidden.extend(
                dt.core
                    .scratch
                    .hidden_now
                    .drain(..)
                    .map(|q| order[q as usize]),
            );
            if (k + 1) % PROGRESS_STEP == 0 {
                progress(k + 1, n);
            }
        }
        if !rounds.is_empty() {
            for round in rounds {
                let end = round.end;
                let (left, dups) =
                    dt.core
                        .insert_parts(geo, round.start as u32..end as u32, split.threads.max(1));
                for r in dups {
                    note(&mut dt, r);
                }
                progress(end - left.len(), n);
                for id in left {
                    let r = dt.core.insert_any(geo, id)?;
                    note(&mut dt, r);
                }
                dt.core.finish_parts();
            }
        }
        // Back to input ids, in chunks on the threads.
        let threads = split.threads.max(1);
        let chunk = dt.core.v.len().div_ceil(threads).max(1 << 16);
        let items: Vec<&mut [[u32; 4]]> = dt.core.v.chunks_mut(chunk).collect();
        crate::par::run_dynamic(threads, items, |_, vs| {
            for tv in vs.iter_mut().filter(|tv| tv[0] != DEAD) {
                for q in tv.iter_mut().filter(|q| **q != INF) {
                    *q = order[*q as usize];
                }
            }
        });
        Ok(dt)
    }

    /// Fills the vertex map of a one-call construction of `n` points from
    /// its duplicate and hidden lists.
    fn map_vertices(&mut self, n: usize) {
        self.duplicates.sort_unstable();
        self.vertex_map = (0..n as u32).collect();
        for &(d, o) in &self.duplicates {
            self.vertex_map[d as usize] = o;
        }
        for &h in &self.hidden {
            self.vertex_map[h as usize] = NONE;
        }
    }

    /// Inserts one point and returns what became of it.
    ///
    /// A triangulation built by [`Delaunay3::from_points`] borrows the caller's
    /// slice; the first `insert` copies it.
    ///
    /// # Errors
    /// [`Error::InvalidCoordinate`] when a coordinate is NaN or infinite
    /// (the point is not stored); [`Error::CapacityExceeded`].
    ///
    /// ```
    /// use delone::tet::{Delaunay3, Inserted};
    /// let mut dt = Delaunay3::new();
    /// assert_eq!(dt.insert([0.0, 0.0, 0.0]).unwrap(), Inserted::Pending(0));
    /// assert_eq!(dt.insert([0.0, 0.0, 0.0]).unwrap(), Inserted::Duplicate { id: 1, original: 0 });
    /// assert!(dt.insert([f64::NAN, 0.0, 0.0]).is_err());
    /// ```
    pub fn insert(&mut self, p: [f64; 3]) -> Result<Inserted, Error> {
        self.insert_impl(p, None)
    }

    /// Inserts one weighted point into a regular triangulation (earlier
    /// points inserted without a weight have weight 0). The point may turn
    /// out hidden, and it may hide existing vertices (see
    /// [`Delaunay3::hidden`]).
    ///
    /// # Errors
    /// As [`Delaunay3::insert`], plus [`Error::InvalidWeight`].
    ///
    /// ```
    /// use delone::{tet::Delaunay3, Inserted};
    /// let mut dt = Delaunay3::new();
    /// for p in [[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [0.0, 4.0, 0.0], [0.0, 0.0, 4.0]] {
    ///     dt.insert_weighted(p, 0.0).unwrap();
    /// }
    /// assert_eq!(dt.insert_weighted([1.0, 1.0, 1.0], -10.0).unwrap(), Inserted::Hidden(4));
    /// // A heavy point hides the light vertex at its place.
    /// assert_eq!(dt.insert_weighted([0.0, 0.0, 0.0], 1.0).unwrap(), Inserted::Vertex(5));
    /// assert_eq!(dt.hidden(), &[0, 4]);
    /// dt.check_topology().unwrap();
    /// dt.check_delaunay().unwrap();
    /// ```
    pub fn insert_weighted(&mut self, p: [f64; 3], w: f64) -> Result<Inserted, Error> {
        self.insert_impl(p, Some(w))
    }

    fn insert_impl(&mut self, p: [f64; 3], w: Option<f64>) -> Result<Inserted, Error> {
        let id = self.points.len();
        if !p.iter().all(|c| c.is_finite()) {
            return Err(Error::InvalidCoordinate { index: id });
        }
        if w.is_some_and(|w| !w.is_finite()) {
            return Err(Error::InvalidWeight { index: id });
        }
        if id >= MAX_POINTS {
            return Err(Error::CapacityExceeded { requested: id + 1 });
        }
        let s = *self
            .scale
            .get_or_insert_with(|| crate::geom::pow2_scale(crate::geom::max_abs(&[p])));
        let p = crate::geom::scaled(p, s);
        if w.is_some() && self.weights.is_none() {
            self.weights = Some(Cow::Owned(vec![0.0; id]));
        }
        if let Some(ws) = self.weights.as_mut() {
            ws.to_mut().push(w.unwrap_or(0.0) * s.0 * s.0 * s.1 * s.1);
        }
        self.points.to_mut().push(p);
        self.vertex_map.push(NONE);
        let id = id as u32;
        let pts: &[[f64; 3]] = &self.points;
        let wts: &[f64] = self.weights.as_deref().unwrap_or(&[]);
        let geo = Geo { pts, wts, ids: &[] };
        let same = |q: u32| {
            pts[q as usize] == p && (wts.is_empty() || wts[q as usize] == wts[id as usize])
        };
        let mut results = Vec::new();
        let r = if !self.core.v.is_empty() {
            let r = self.core.insert_any(geo, id)?;
            results.push(r);
            r
        } else if let Some(&orig) = self.pending.iter().find(|&&q| same(q)) {
            // No tetrahedron yet: keep the point, catch duplicates by comparison.
            let r = Inserted::Duplicate { id, original: orig };
            results.push(r);
            r
        } else {
            self.pending.push(id);
            self.vertex_map[id as usize] = id;
            if extends_basis(pts, &self.basis, id) {
                self.basis.push(id);
            }
            if self.basis.len() < 4 {
                return Ok(Inserted::Pending(id));
            }
            let b = [self.basis[0], self.basis[1], self.basis[2], self.basis[3]];
            self.core.start(pts, b);
            self.basis.clear();
            for q in std::mem::take(&mut self.pending) {
                if !b.contains(&q) {
                    results.push(self.core.insert_any(geo, q)?);
                }
            }
            Inserted::Vertex(id)
        };
        for r in results {
            record(&mut self.vertex_map, &mut self.duplicates, r);
            if let Inserted::Hidden(q) = r {
                self.hidden.push(q);
            }
        }
        for &q in &self.core.scratch.hidden_now {
            self.vertex_map[q as usize] = NONE;
            self.hidden.push(q);
        }
        self.core.scratch.hidden_now.clear();
        self.hidden.sort_unstable();
        Ok(r)
    }

    /// Locates `p`: the finite tetrahedron containing it (closed), the vertex
    /// it coincides with, or the ghost cell of a hull facet it lies beyond.
    ///
    /// ```
    /// use delone::tet::{Delaunay3, Location};
    /// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    /// let dt = Delaunay3::from_points(&pts).unwrap();
    /// assert!(matches!(dt.locate(&[0.1, 0.1, 0.1]), Location::InTet(_)));
    /// assert_eq!(dt.locate(&[1.0, 0.0, 0.0]), Location::OnVertex(1));
    /// assert!(matches!(dt.locate(&[5.0, 5.0, 5.0]), Location::OutsideHull(_)));
    /// ```
    pub fn locate(&self, p: &[f64; 3]) -> Location {
        if self.core.v.is_empty() {
            return Location::Empty;
        }
        let p = &crate::geom::scaled(*p, self.scale.unwrap_or((1.0, 1.0)));
        let mut rng = self.core.rng;
        let t = self.core.walk(&self.points, p, self.core.last, &mut rng);
        let tv = self.core.v[t as usize];
        if tv.contains(&INF) {
            return Location::OutsideHull(t);
        }
        match tv.iter().find(|&&q| self.points[q as usize] == *p) {
            Some(&q) => Location::OnVertex(q),
            None => Location::InTet(t),
        }
    }

    /// All points given so far (inserted, duplicate or pending), by id, as the
    /// kernel works on them: the caller's coordinates, multiplied by an exact
    /// power of two when their magnitudes are extreme (beyond 2^±60).
    ///
    /// ```
    /// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    /// let dt = delone::tet::Delaunay3::from_points(&pts).unwrap();
    /// assert_eq!(dt.points().len(), 4);
    /// ```
    pub fn points(&self) -> &[[f64; 3]] {
        &self.points
    }

    /// Number of vertices of the tetrahedralization (points given minus
    /// duplicates minus pending ones).
    ///
    /// ```
    /// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, 1.0]];
    /// let dt = delone::tet::Delaunay3::from_points(&pts).unwrap();
    /// assert_eq!(dt.num_vertices(), 4);
    /// ```
    pub fn num_vertices(&self) -> usize {
        if self.core.v.is_empty() {
            return 0;
        }
        self.points.len() - self.duplicates.len()
    }

    /// Number of finite tetrahedra.
    ///
    /// ```
    /// let dt = delone::tet::Delaunay3::new();
    /// assert_eq!(dt.num_tets(), 0);
    /// ```
    pub fn num_tets(&self) -> usize {
        self.core.finite
    }

    /// The duplicate points found so far, as `(duplicate, original)` sorted by
    /// duplicate id.
    ///
    /// ```
    /// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]];
    /// let dt = delone::tet::Delaunay3::from_points(&pts).unwrap();
    /// assert_eq!(dt.duplicates(), &[(4, 1)]);
    /// ```
    pub fn duplicates(&self) -> &[(u32, u32)] {
        &self.duplicates
    }

    /// Points left out of a regular triangulation because their power cell
    /// is empty, sorted (always empty without weights).
    ///
    /// ```
    /// let dt = delone::tet::Delaunay3::new();
    /// assert!(dt.hidden().is_empty());
    /// ```
    pub fn hidden(&self) -> &[u32] {
        &self.hidden
    }

    /// The finite tetrahedra, positively oriented.
    ///
    /// ```
    /// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    /// let dt = delone::tet::Delaunay3::from_points(&pts).unwrap();
    /// let tets: Vec<[u32; 4]> = dt.tets().collect();
    /// assert_eq!(tets.len(), 1);
    /// ```
    pub fn tets(&self) -> impl Iterator<Item = [u32; 4]> + '_ {
        self.core
            .v
            .iter()
            .copied()
            .filter(|t| t[0] != DEAD && !t.contains(&INF))
    }

    /// Drops the ghost cells, compacts the arrays in place and returns the
    /// flat output.
    ///
    /// ```
    /// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    /// let mesh = delone::tet::Delaunay3::from_points(&pts).unwrap().into_mesh();
    /// assert_eq!(mesh.neighbors, vec![[delone::NONE; 4]]);
    /// ```
    pub fn into_mesh(self) -> TetMesh {
        let mut vertex_map = self.vertex_map;
        for &q in &self.pending {
            // Pending points never made it into a tetrahedron.
            vertex_map[q as usize] = NONE;
        }
        // Copies of a point that was later hidden are hidden too.
        let mut hidden = self.hidden;
        let mut duplicates = self.duplicates;
        if !hidden.is_empty() {
            duplicates.retain(|&(d, o)| {
                let gone = vertex_map[o as usize] == NONE;
                if gone {
                    vertex_map[d as usize] = NONE;
                    hidden.push(d);
                }
                !gone
            });
            hidden.sort_unstable();
        }
        let (mut tets, neighbors) = self.core.into_arrays();
        let duplicates = lowest_representatives(&mut vertex_map, duplicates, &mut tets);
        TetMesh {
            tets,
            neighbors,
            vertex_map,
            duplicates,
            hidden,
        }
    }
}

/// Notes what became of a point in the vertex map and duplicate list.
fn record(vertex_map: &mut [u32], duplicates: &mut Vec<(u32, u32)>, r: Inserted) {
    match r {
        Inserted::Vertex(id) | Inserted::Pending(id) => vertex_map[id as usize] = id,
        Inserted::Hidden(id) => vertex_map[id as usize] = NONE,
        Inserted::Duplicate { id, original } => {
            vertex_map[id as usize] = original;
            let at = duplicates.partition_point(|d| d.0 < id);
            duplicates.insert(at, (id, original));
        }
    }
}

/// Makes the lowest index of every group of equal points its representative
/// (insertion order may have inserted a higher one first): rewrites
/// `vertex_map`, the tetrahedra, and returns the new duplicate list.
pub(crate) fn lowest_representatives<const K: usize>(
    vertex_map: &mut [u32],
    mut duplicates: Vec<(u32, u32)>,
    cells: &mut [[u32; K]],
) -> Vec<(u32, u32)> {
    if duplicates.iter().all(|&(d, o)| o < d) {
        return duplicates;
    }
    // Group by original; the representative is the group's minimum.
    let mut relabel = vec![NONE; vertex_map.len()];
    duplicates.sort_unstable_by_key(|&(d, o)| (o, d));
    let mut out = Vec::with_capacity(duplicates.len());
    let mut k = 0;
    while k < duplicates.len() {
        let o = duplicates[k].1;
        let end = k + duplicates[k..].partition_point(|e| e.1 == o);
        let rep = duplicates[k].0.min(o);
        for &(d, _) in &duplicates[k..end] {
            if d != rep {
                out.push((d, rep));
            }
        }
        if rep != o {
            out.push((o, rep));
            relabel[o as usize] = rep;
        }
        k = end;
    }
    out.sort_unstable();
    for &(d, rep) in &out {
        vertex_map[d as usize] = rep;
    }
    for &(_, rep) in &out {
        vertex_map[rep as usize] = rep;
    }
    for cell in cells.iter_mut() {
        for q in cell.iter_mut() {
            if *q != NONE && (*q as usize) < relabel.len() && relabel[*q as usize] != NONE {
                *q = relabel[*q as usize];
            }
        }
    }
    out
}

/// The error for a point set without four affinely independent points,
/// given how large an independent subset was found.
/// The insertion order of a one-call construction: BRIO + Hilbert
/// ([`crate::geom::brio_order`]) with the first four affinely independent
/// points, the first tetrahedron, moved to its front.
fn insertion_order(points: &[[f64; 3]], threads: usize) -> Result<Vec<u32>, Error> {
    let mut order = crate::geom::sort::brio_order_threads(points, threads);
    let mut basis: Vec<u32> = Vec::with_capacity(4);
    let mut basis_pos: Vec<usize> = Vec::with_capacity(4);
    for (pos, &id) in order.iter().enumerate() {
        if extends_basis(points, &basis, id) {
            basis.push(id);
            basis_pos.push(pos);
            if basis.len() == 4 {
                break;
            }
        }
    }
    if basis.len() < 4 {
        return Err(degenerate_error(points, basis.len()));
    }
    for (k, &pos) in basis_pos.iter().enumerate() {
        order[k..=pos].rotate_right(1);
    }
    debug_assert_eq!(&order[..4], &basis[..]);
    Ok(order)
}

fn degenerate_error(points: &[[f64; 3]], independent: usize) -> Error {
    // `+ 0.0` turns -0.0 into 0.0: equal points compare equal.
    let mut distinct: Vec<[u64; 3]> = points
        .iter()
        .map(|p| p.map(|c| (c + 0.0).to_bits()))
        .collect();
    distinct.sort_unstable();
    distinct.dedup();
    if distinct.len() < 4 {
        Error::TooFewPoints {
            found: distinct.len(),
            needed: 4,
        }
    } else {
        Error::Degenerate {
            dimension: independent.saturating_sub(1).max(1),
        }
    }
}

impl Core {
    #[inline]
    fn next_rand(rng: &mut u32) -> u32 {
        // xorshift32: deterministic, never zero once seeded non-zero.
        let mut x = *rng;
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        *rng = x;
        x
    }

    /// A slot for a new tetrahedron.
    #[inline(always)]
    pub(crate) fn alloc(&mut self, tv: [u32; 4]) -> u32 {
        self.finite += usize::from(tv[3] != INF);
        if let Some(t) = self.free.pop() {
            self.v[t as usize] = tv;
            return t;
        }
        self.push_slot(tv)
    }

    /// A new slot at the end of the arrays (the free list is empty).
    #[inline(never)]
    fn push_slot(&mut self, tv: [u32; 4]) -> u32 {
        if self.v.len() == self.v.capacity() {
            // Grow by 1/8 instead of doubling: memory is a requirement.
            let extra = (self.v.len() / 8).max(1024);
            self.v.reserve_exact(extra);
            self.adj.reserve_exact(extra);
        }
        self.v.push(tv);
        self.adj.push([NONE; 4]);
        (self.v.len() - 1) as u32
    }

    #[inline(always)]
    pub(crate) fn release(&mut self, t: u32) {
        let tv = &mut self.v[t as usize];
        if tv[3] != INF {
            self.finite -= 1;
        }
        tv[0] = DEAD;
        self.free.push(t);
    }

    #[inline]
    pub(crate) fn link(&mut self, t: u32, f: usize, u: u32, g: usize) {
        self.adj[t as usize][f] = 4 * u + g as u32;
        self.adj[u as usize][g] = 4 * t + f as u32;
    }

    /// Creates the first tetrahedron from four affinely independent points
    /// and its four ghost cells.
    fn start(&mut self, pts: &[[f64; 3]], b: [u32; 4]) {
        self.rng = 0x2545_F491;
        let p = |i: usize| &pts[b[i] as usize];
        let tv = if orient3d(p(0), p(1), p(2), p(3)) < 0.0 {
            b
        } else {
            [b[1], b[0], b[2], b[3]]
        };
        let t = self.alloc(tv);
        let mut ghosts = [0u32; 4];
        for f in 0..4 {
            let [x, y, z] = FACET[f].map(|i| tv[i]);
            ghosts[f] = self.alloc([x, z, y, INF]);
            self.link(t, f, ghosts[f], 3);
        }
        // Glue the ghosts along the hull edges.
        for f in 0..4 {
            for h in f + 1..4 {
                let (gf, gh) = (ghosts[f] as usize, ghosts[h] as usize);
                // The shared facet of two ghosts is opposite the vertex each
                // has that the other lacks.
                let df = (0..3)
                    .find(|&i| !self.v[gh].contains(&self.v[gf][i]))
                    .unwrap_or(0);
                let dh = (0..3)
                    .find(|&i| !self.v[gf].contains(&self.v[gh][i]))
                    .unwrap_or(0);
                self.link(gf as u32, df, gh as u32, dh);
            }
        }
        self.last = t;
    }

    /// Visibility walk from `start` towards `p` ([`walk_cells`] on this
    /// structure's arrays).
    pub(crate) fn walk(&self, pts: &[[f64; 3]], p: &[f64; 3], start: u32, rng: &mut u32) -> u32 {
        walk_cells((&self.v, &self.adj), pts, p, start, rng)
    }

    /// Inserts point `id` ([`insert_in`] on the whole arrays), refusing
    /// insertions once the index space could overflow.
    fn insert_any(&mut self, g: Geo<'_>, id: u32) -> Result<Inserted, Error> {
        if self.v.len() + (1 << 20) > MAX_TETS || self.overflow {
            // No insertion creates a million cells on realistic input; past this
            // point packed adjacency words could overflow.
            self.overflow = true;
            return Err(Error::CapacityExceeded {
                requested: g.pts.len(),
            });
        }
        let mut s = std::mem::take(&mut self.scratch);
        let r = if g.wts.is_empty() {
            insert_in::<_, false>(self, &mut s, g, id)
        } else {
            if s.vstamp.len() < g.pts.len() {
                s.vstamp.resize(g.pts.len(), 0);
            }
            insert_in::<_, true>(self, &mut s, g, id)
        };
        self.scratch = s;
        if self.v.len() > MAX_TETS {
            self.overflow = true;
            return Err(Error::CapacityExceeded {
                requested: g.pts.len(),
            });
        }
        // The whole arrays are owned: an insertion is never deferred.
        Ok(r.unwrap_or(Inserted::Vertex(id)))
    }
}

/// Does the circumsphere of finite tet `t` (possibly marked) contain point
/// `id`? With `W`, the power test: is `id` closer, in power distance, to the
/// orthogonal sphere of `t`'s weighted vertices than orthogonal to it? Exact
/// ties are broken by the input ids `ids[i]` (`i` itself when `ids` is
/// empty).
#[inline(always)]
fn finite_conflict<C: Cells, const W: bool>(c: &C, g: Geo<'_>, t: u32, id: u32) -> bool {
    finite_conflict_v::<W>(g, *c.v(t), id, &g.pts[id as usize])
}

/// [`finite_conflict`] of the finite cell with vertices `tv` (possibly
/// marked); `p` is point `id` (loaded once per insertion).
#[inline(always)]
fn finite_conflict_v<const W: bool>(g: Geo<'_>, tv: [u32; 4], id: u32, p: &[f64; 3]) -> bool {
    let [a, b, c, d] = tv;
    let a = a & UNMARK;
    let q = |i: u32| &g.pts[i as usize];
    let w = |i: u32| if W { g.wts[i as usize] } else { 0.0 };
    // Swap a and b: insphere's convention wants orient3d > 0.
    let s = if W {
        insphere_weighted(q(b), q(a), q(c), q(d), p, w(b), w(a), w(c), w(d), w(id))
    } else {
        insphere(q(b), q(a), q(c), q(d), p)
    };
    if s != 0.0 {
        return s > 0.0;
    }
    // An exact tie (zero weights: the in-sphere tie): the perturbation
    // by input id decides (`insphere_weighted_sos` past the determinant
    // just computed).
    let o = |i: u32| g.ids.get(i as usize).copied().unwrap_or(i);
    insphere_tie_sos(
        [q(b), q(a), q(c), q(d), q(id)],
        [o(b), o(a), o(c), o(d), o(id)],
    ) > 0
}

/// Whether owned cell `t`, with vertices `tv`, conflicts with point `id`;
/// `None` when the answer needs a cell `c` does not own.
#[inline(always)]
fn in_conflict<C: Cells, const W: bool>(
    c: &C,
    g: Geo<'_>,
    t: u32,
    tv: [u32; 4],
    id: u32,
    p: &[f64; 3],
) -> Option<bool> {
    if tv[3] != INF {
        return Some(finite_conflict_v::<W>(g, tv, id, p));
    }
    // A ghost: its hull facet (vertices 0, 1, 2, outside on the positive
    // side, i.e. orient3d < 0) conflicts with points strictly beyond it,
    // and with points on its plane iff the finite cell behind does.
    let [a, b, d] = FACET[3].map(|i| &g.pts[(tv[i] & UNMARK) as usize]);
    let o = orient3d(a, b, d, p);
    if o != 0.0 {
        return Some(o < 0.0);
    }
    let behind = c.adj(t)[3] >> 2;
    match c.owns(behind) {
        true => Some(finite_conflict::<C, W>(c, g, behind, id)),
        false => None,
    }
}

/// Inserts point `id` into the cells `c`: locate, cavity, stellate. With `W`
/// (weights in `g.wts`), the power test decides conflicts: the new point may
/// turn out hidden, and vertices whose whole star falls in the cavity become
/// hidden (listed in `s.hidden_now`).
///
/// `None` (nothing changed) when the walk or the cavity meets a cell `c` does
/// not own, or when `c` has no room for the new cells: the point is left for
/// a later insertion.
fn insert_in<C: CellsMut, const W: bool>(
    c: &mut C,
    s: &mut Scratch,
    g: Geo<'_>,
    id: u32,
) -> Option<Inserted> {
    let (pts, wts) = (g.pts, g.wts);
    let p = &pts[id as usize];
    let (&mut start, &mut mut rng) = c.hint();
    let t0 = walk_owned(&*c, pts, p, start, &mut rng);
    *c.hint().1 = rng;
    let t0 = t0.ok()?;
    let tv0 = *c.v(t0);
    if tv0[3] != INF {
        let same = |q: u32| pts[q as usize] == *p && (!W || wts[q as usize] == wts[id as usize]);
        if let Some(&q) = tv0.iter().find(|&&q| same(q)) {
            return Some(Inserted::Duplicate { id, original: q });
        }
        // Inside the hull, a weighted point below no power sphere of the
        // cell containing it has an empty power cell.
        if W && !finite_conflict::<C, W>(c, g, t0, id) {
            return Some(Inserted::Hidden(id));
        }
    }
    // Grow the cavity breadth-first (the cavity list is the queue). t0
    // contains p (or sees it beyond its hull facet), so it conflicts
    // without a test. Each boundary facet met is recorded with its new cell;
    // nothing but marks is written until the search ends, so a search that
    // meets a cell it may not touch is undone by clearing the marks.
    let Scratch {
        cavity, kept, bnd, ..
    } = s;
    cavity.clear();
    kept.clear();
    bnd.clear();
    c.v_mut(t0)[0] |= MARK_CAVITY;
    cavity.push(t0);
    let mut k = 0;
    let mut complete = true;
    'search: while k < cavity.len() {
        let t = cavity[k];
        k += 1;
        let adj_t = *c.adj(t);
        let [t0, t1, t2, t3] = *c.v(t);
        let tv = [t0 & UNMARK, t1, t2, t3];
        for (f, &w) in adj_t.iter().enumerate() {
            let u = w >> 2;
            if !c.owns(u) {
                complete = false;
                break 'search;
            }
            let tu = *c.v(u);
            let mark = tu[0];
            if mark & MARK_CAVITY != 0 {
                continue;
            }
            if mark & MARK_KEEP == 0 {
                match in_conflict::<C, W>(c, g, u, tu, id, p) {
                    Some(true) => {
                        c.v_mut(u)[0] |= MARK_CAVITY;
                        cavity.push(u);
                        continue;
                    }
                    Some(false) => {}
                    None => {
                        complete = false;
                        break 'search;
                    }
                }
                c.v_mut(u)[0] |= MARK_KEEP;
                kept.push(u);
            }
            let [a, b, d] = FACET[f].map(|i| tv[i]);
            // Keep INF in position 3 with an even permutation (only a
            // ghost has it).
            let (cell, fp) = if t3 != INF {
                ([a, b, d, id], 3)
            } else if a == INF {
                ([id, d, b, a], 0)
            } else if b == INF {
                ([d, id, a, b], 1)
            } else if d == INF {
                ([b, a, id, d], 2)
            } else {
                ([a, b, d, id], 3)
            };
            bnd.push((cell, fp, w));
        }
    }
    for &u in kept.iter() {
        c.v_mut(u)[0] &= UNMARK;
    }
    // Every new cell is allocated before the cavity's cells are freed: a
    // part needs a slot for each (with fewer it would write past its range).
    if !complete || !c.room(bnd.len()) {
        for &u in cavity.iter() {
            c.v_mut(u)[0] &= UNMARK;
        }
        return None;
    }
    if W {
        find_hidden(&*c, s, id);
    }
    let Scratch {
        cavity, bnd, edges, ..
    } = s;
    // The new cells, in free slots (the last insertion's cavity, mostly),
    // then the cavity's slots are freed. (Reusing the cavity's own slots
    // first measured no faster, and would renumber the cells of every mesh
    // built on this kernel.) Each new cell is glued to the cell outside its
    // boundary facet, and to the new cells before it that share one of
    // that facet's edges: in new cell `n` with the new point at local
    // position `fp`, facet `k != fp` holds the new point and the edge of
    // the two other vertices (see `SIDES`).
    edges.reset(bnd.len() * 3);
    let mut newest = NONE;
    for &(cell, fp, w) in bnd.iter() {
        let n = c.alloc(cell);
        c.adj_mut(n)[fp as usize] = w;
        c.adj_mut(w >> 2)[(w & 3) as usize] = 4 * n + fp;
        for (k, i, j) in SIDES[fp as usize] {
            if let Some(x) = edges.pair(cell[i], cell[j], 4 * n + k as u32) {
                c.adj_mut(n)[k] = x;
                c.adj_mut(x >> 2)[(x & 3) as usize] = 4 * n + k as u32;
            }
        }
        if cell[3] != INF {
            newest = n;
        }
    }
    for &t in cavity.iter() {
        c.release(t);
    }
    // Inserting a vertex always creates finite tetrahedra; the walk
    // steps off a ghost start by itself anyway.
    if newest != NONE {
        *c.hint().0 = newest;
    }
    Some(Inserted::Vertex(id))
}

/// Per local position `fp` of the new point in a new cell: its three other
/// facets `k` and the local positions `i`, `j` of the edge each shares with
/// the cavity boundary (the two vertices other than `k` and `fp`).
const SIDES: [[(usize, usize, usize); 3]; 4] = [
    [(1, 2, 3), (2, 1, 3), (3, 1, 2)],
    [(0, 2, 3), (2, 0, 3), (3, 0, 2)],
    [(0, 1, 3), (1, 0, 3), (3, 0, 1)],
    [(0, 1, 2), (1, 0, 2), (2, 0, 1)],
];

/// Regular triangulations: the vertices of the cavity cells that are not on
/// the cavity boundary lose their whole star, so their power cell is now
/// empty. Collected into `s.hidden_now` (cavity cells still intact), with a
/// per-vertex stamp (weighted triangulations only).
fn find_hidden<C: Cells>(c: &C, s: &mut Scratch, id: u32) {
    s.hidden_now.clear();
    if s.vstamp_next > u32::MAX - 4 {
        s.vstamp.iter_mut().for_each(|x| *x = 0);
        s.vstamp_next = 0;
    }
    let rim = s.vstamp_next + 1;
    let seen = rim + 1;
    s.vstamp_next = seen;
    for (cell, _, _) in &s.bnd {
        for &q in cell {
            if q != INF && q != id {
                s.vstamp[q as usize] = rim;
            }
        }
    }
    for &t in &s.cavity {
        let [a, b, d, e] = *c.v(t);
        for q in [a & UNMARK, b, d, e] {
            if q != INF && q != id && s.vstamp[q as usize] < rim {
                s.vstamp[q as usize] = seen;
                s.hidden_now.push(q);
            }
        }
    }
}

impl Core {
    /// Inserts the points `ids` (Delaunay, no weights: a BRIO round, in
    /// Hilbert order) in the [`PARTS`] quarters of their box on up to
    /// `threads` threads (the medians from a sample).
    ///
    /// Every live cell goes to the quarter holding its centroid, and the
    /// cells are moved so that each part owns one block of slots (with room
    /// for the cells its points will create). The passes ([`PASSES`])
    /// insert groups of parts side by side, each touching only its own
    /// blocks ([`insert_in`] on a [`Part`]; a new cell goes to the block of
    /// its point's part): a point whose walk or cavity reaches a cell of
    /// another group is left to the next pass. The first pass splits the
    /// points across `x`'s median and leaves those within about a point
    /// spacing of it; the second splits them across `y`'s median, so that
    /// few are left for the caller's serial pass (those near where the
    /// medians' planes cross). A group's result depends only on its own
    /// cells and points, so the arrays are the same for every thread count.
    /// Returns the points left after the last pass (in order) and the
    /// duplicates found.
    fn insert_parts(
        &mut self,
        g: Geo<'_>,
        ids: std::ops::Range<u32>,
        threads: usize,
    ) -> (Vec<u32>, Vec<Inserted>) {
        let first = ids.start;
        let parts = PARTS;
        let round = &g.pts[ids.start as usize..ids.end as usize];
        // The two longest axes of the box, and the medians of every 16th
        // point's coordinates.
        let [lo, hi] = crate::geom::bbox(round);
        let extent = |a: usize| hi[a] - lo[a];
        let mut axes = [0usize, 1, 2];
        axes.sort_by(|&a, &b| extent(b).total_cmp(&extent(a)));
        let [ax, ay, _] = axes;
        let median = |a: usize| {
            let mut sample: Vec<f64> = round.iter().step_by(16).map(|p| p[a]).collect();
            sample.sort_unstable_by(f64::total_cmp);
            sample[sample.len() / 2]
        };
        let (xmid, ymid) = (median(ax), median(ay));
        let part_of = |p: &[f64; 3]| match (p[ax] >= xmid, p[ay] >= ymid) {
            (false, false) => 0,
            (false, true) => 1,
            (true, true) => 2,
            (true, false) => 3,
        };
        // About the spacing of the points inserted before the round.
        let volume: f64 = (0..3).map(|a| extent(a).max(0.0)).product();
        let spacing = (volume / f64::from(first.max(1))).cbrt();
        let defer = if spacing.is_finite() {
            DEFER_SPACINGS * spacing
        } else {
            0.0
        };
        let mut pcount = vec![0usize; parts];
        for p in round {
            pcount[part_of(p)] += 1;
        }
        // Each live cell's part, from its centroid (NONE for a dead slot),
        // in chunks on up to `threads` threads.
        let len = self.v.len();
        let mut slot = vec![NONE; len];
        let chunk = len.div_ceil(threads).max(1 << 14);
        let items: Vec<(&[[u32; 4]], &mut [u32])> =
            self.v.chunks(chunk).zip(slot.chunks_mut(chunk)).collect();
        let chunk_counts = crate::par::run_dynamic(threads, items, |_, (vs, ss)| {
            let mut count = vec![0usize; parts];
            for (tv, s) in vs.iter().zip(ss) {
                if tv[0] == DEAD {
                    continue;
                }
                let mut c = [0.0f64; 3];
                let mut k = 0.0;
                for &q in tv.iter().filter(|&&q| q != INF) {
                    let p = &g.pts[q as usize];
                    c = [c[0] + p[0], c[1] + p[1], c[2] + p[2]];
                    k += 1.0;
                }
                let part = part_of(&c.map(|x| x / k));
                *s = part as u32;
                count[part] += 1;
            }
            count
        });
        let chunk_counts: Vec<Vec<usize>> = chunk_counts
            .into_iter()
            .map(|c| c.unwrap_or_else(|| vec![0; parts]))
            .collect();
        let count: Vec<usize> = (0..parts)
            .map(|k| chunk_counts.iter().map(|c| c[k]).sum())
            .collect();
        // Room per part: its cells plus the cells per inserted point so far
        // (ghosts included) for each of its points, with a margin.
        let live = len - self.free.len();
        let inserted = (first as usize).max(1);
        let mut bounds = vec![0usize];
        for k in 0..parts {
            let room = (pcount[k] * live).div_ceil(inserted) / 100 * 101 + 1024;
            bounds.push(bounds[k] + count[k] + room);
        }
        let total = bounds[parts];
        if total + (1 << 20) > MAX_TETS {
            return (ids.collect(), Vec::new());
        }
        // Destinations: part k's cells in slot order from bounds[k]; a
        // chunk's cells of part k follow those of the chunks before it.
        let mut next: Vec<usize> = bounds[..parts].to_vec();
        let items: Vec<(Vec<usize>, &mut [u32])> = (slot.chunks_mut(chunk).zip(&chunk_counts))
            .map(|(ss, c)| {
                let at = next.clone();
                for (n, c) in next.iter_mut().zip(c) {
                    *n += c;
                }
                (at, ss)
            })
            .collect();
        crate::par::run_dynamic(threads, items, |_, (mut at, ss)| {
            for d in ss.iter_mut().filter(|d| **d != NONE) {
                let k = *d as usize;
                *d = at[k] as u32;
                at[k] += 1;
            }
        });
        // Fresh arrays from zeroed memory: the pages of slots no part ever
        // uses are never touched (the unused tail is cut off at the end,
        // other unused slots are marked free by `Core::finish_parts`). Each
        // part's range is filled on its own thread.
        let mut v = zeroed_slots(total);
        let mut adj = zeroed_slots(total);
        {
            let items: Vec<(usize, Slots<'_>)> = (bounds.iter().copied())
                .zip(
                    crate::par::split_mut(&mut v, &bounds)
                        .into_iter()
                        .zip(crate::par::split_mut(&mut adj, &bounds)),
                )
                .collect();
            let (old_v, old_adj, slot) = (&self.v, &self.adj, &slot);
            crate::par::run_dynamic(threads, items, |_, (lo, (v, adj))| {
                let range = lo as u32..(lo + v.len()) as u32;
                for (t, &d) in slot.iter().enumerate() {
                    if range.contains(&d) {
                        let i = d as usize - lo;
                        v[i] = old_v[t];
                        adj[i] = old_adj[t].map(|w| 4 * slot[(w >> 2) as usize] + (w & 3));
                    }
                }
            });
        }
        self.v = v;
        self.adj = adj;
        self.last = slot[self.last as usize];
        self.free.clear();
        drop(slot);
        // Per part: its block and walk state. A part's walks start from the
        // cell holding its first point when its block has that cell, else
        // from the block's first finite cell.
        let mut slabs: Vec<(Block, u32, u32)> = (0..parts)
            .map(|k| {
                let (lo, hi) = (bounds[k], bounds[k] + count[k]);
                let start = match ids.clone().find(|&id| part_of(&g.pts[id as usize]) == k) {
                    Some(id) => {
                        let mut rng = 0x2545_F491;
                        let p = &g.pts[id as usize];
                        walk_cells((&self.v, &self.adj), g.pts, p, self.last, &mut rng) as usize
                    }
                    None => usize::MAX,
                };
                let start = if (lo..hi).contains(&start) {
                    start as u32
                } else {
                    (lo..hi)
                        .find(|&t| self.v[t][3] != INF)
                        .map_or(NONE, |t| t as u32)
                };
                let block = Block {
                    lo: lo as u32,
                    hi: bounds[k + 1] as u32,
                    used: hi as u32,
                    free: Vec::new(),
                };
                (
                    block,
                    start,
                    0x2545_F491 ^ (k as u32).wrapping_mul(0x9E37_79B9),
                )
            })
            .collect();
        let mut dups = Vec::new();
        let mut finite = 0isize;
        // The points each pass is to insert (the first pass: all of them).
        let mut todo: Option<Vec<u32>> = None;
        for (pass, groups) in PASSES.iter().enumerate() {
            // The group of each block, and the runs of consecutive blocks
            // of one group: a group owns one run, or two.
            let mut group_of = [0usize; PARTS];
            for (gi, grp) in groups.iter().enumerate() {
                for &k in grp.iter() {
                    group_of[k] = gi;
                }
            }
            let starts: Vec<usize> = (0..parts)
                .filter(|&k| k == 0 || group_of[k] != group_of[k - 1])
                .collect();
            let at: Vec<usize> = (starts.iter().map(|&k| slabs[k].0.lo as usize))
                .chain([total])
                .collect();
            let vs = crate::par::split_mut(&mut self.v, &at);
            let adjs = crate::par::split_mut(&mut self.adj, &at);
            let mut runs: Vec<Vec<(u32, Slots<'_>)>> =
                (0..groups.len()).map(|_| Vec::new()).collect();
            for ((&k, v), adj) in starts.iter().zip(vs).zip(adjs) {
                runs[group_of[k]].push((slabs[k].0.lo, (v, adj)));
            }
            let mut own: Vec<Option<(Block, u32, u32)>> =
                std::mem::take(&mut slabs).into_iter().map(Some).collect();
            let items: Vec<_> = (groups.iter().zip(runs))
                .map(|(grp, r)| {
                    let mine: Vec<(Block, u32, u32)> =
                        grp.iter().filter_map(|&k| own[k].take()).collect();
                    (*grp, mine, r)
                })
                .collect();
            let (todo_ref, part_of) = (&todo, &part_of);
            let results = crate::par::run_dynamic(threads, items, |_, (grp, mine, mut r)| {
                let of = |p: &[f64; 3]| grp.iter().position(|&k| k == part_of(p));
                // The first pass leaves the points near `x`'s median.
                let near = |p: &[f64; 3]| pass == 0 && (p[ax] - xmid).abs() < defer;
                let (b1, (v, adj)) = r.remove(0);
                let (left, dups, finite, blocks, walk) = match r.pop() {
                    None => {
                        let part = Part::<false> {
                            base: b1,
                            v,
                            adj,
                            base2: 0,
                            v2: &mut [],
                            adj2: &mut [],
                            blocks: Vec::new(),
                            cur: 0,
                            finite: 0,
                            last: NONE,
                            rng: 0,
                        };
                        insert_group(part, mine, g, todo_ref.as_deref(), ids.clone(), &of, &near)
                    }
                    Some((b2, (v2, adj2))) => {
                        let part = Part::<true> {
                            base: b1,
                            v,
                            adj,
                            base2: b2,
                            v2,
                            adj2,
                            blocks: Vec::new(),
                            cur: 0,
                            finite: 0,
                            last: NONE,
                            rng: 0,
                        };
                        insert_group(part, mine, g, todo_ref.as_deref(), ids.clone(), &of, &near)
                    }
                };
                (grp, left, dups, finite, blocks, walk)
            });
            let mut left = Vec::new();
            for res in results {
                // Every item runs (`run_dynamic` runs a left-behind item on
                // this thread); a missing result means a group's thread
                // panicked, which `run_dynamic` has re-raised already.
                let Some((grp, l, d, f, blocks, walk)) = res else {
                    continue;
                };
                for (i, (&k, b)) in grp.iter().zip(blocks).enumerate() {
                    let (last, rng) = walk[i];
                    own[k] = Some((b, last, rng));
                }
                left.extend(l);
                dups.extend(d);
                finite += f;
            }
            slabs = own.into_iter().flatten().collect();
            left.sort_unstable();
            todo = Some(left);
        }
        self.finite = self.finite.saturating_add_signed(finite);
        // Free slots: every block's, and the never used slots of all but
        // the last block, whose never used tail ends the arrays: cut off.
        let end = slabs.last().map_or(total, |b| b.0.used as usize);
        let mut free = Vec::new();
        let n = slabs.len();
        for (k, (b, _, _)) in slabs.iter_mut().enumerate() {
            free.append(&mut b.free);
            if k + 1 < n {
                free.extend((b.used..b.hi).rev());
            }
        }
        self.free = free;
        self.v.truncate(end);
        self.adj.truncate(end);
        if let Some(t) = (slabs.iter().map(|o| o.1))
            .find(|&t| (t as usize) < end && self.v[t as usize][0] != DEAD)
        {
            self.last = t;
        }
        (todo.unwrap_or_default(), dups)
    }

    /// After the serial tail of a parallel insertion: free slots that were
    /// never used (zeroed memory) become `DEAD` like the others.
    fn finish_parts(&mut self) {
        for &t in &self.free {
            self.v[t as usize][0] = DEAD;
        }
    }

    /// Removes ghosts and dead slots in place; returns tets and plain
    /// neighbour indices (NONE on the hull). The scans for ghosts and dead
    /// slots and the unpacking of the neighbour words run on the threads;
    /// the changes are made in slot order as on one thread.
    fn into_arrays(mut self) -> (Vec<[u32; 4]>, Vec<[u32; 4]>) {
        let len = self.v.len();
        let threads = self.threads.max(1);
        let chunk = len.div_ceil(threads).max(1 << 16);
        let items: Vec<(usize, &[[u32; 4]])> = self.v.chunks(chunk).enumerate().collect();
        let found = crate::par::run_dynamic(threads, items, |_, (c, vs)| {
            let (mut ghosts, mut dead) = (Vec::new(), Vec::new());
            for (k, tv) in vs.iter().enumerate() {
                let t = (c * chunk + k) as u32;
                if tv[0] == DEAD {
                    dead.push(t);
                } else if tv.contains(&INF) {
                    ghosts.push(t);
                }
            }
            (ghosts, dead)
        });
        let (mut ghosts, mut holes) = (Vec::new(), Vec::new());
        for (g, d) in found.into_iter().flatten() {
            ghosts.extend(g);
            holes.extend(d);
        }
        // Cut the links to ghost cells.
        for &t in &ghosts {
            let t = t as usize;
            for f in 0..4 {
                let w = self.adj[t][f];
                let u = (w >> 2) as usize;
                if !self.v[u].contains(&INF) {
                    self.adj[u][(w & 3) as usize] = NONE;
                }
            }
            self.v[t][0] = DEAD;
        }
        holes.extend(ghosts);
        holes.sort_unstable();
        // Fill the holes, first to last, with the last live tetrahedra:
        // `j - 1` is the last slot that may be live.
        let mut j = len;
        for &h in &holes {
            let i = h as usize;
            while j > i && self.v[j - 1][0] == DEAD {
                j -= 1;
            }
            if i >= j {
                break;
            }
            let src = j - 1;
            self.v[i] = self.v[src];
            self.adj[i] = self.adj[src];
            self.v[src][0] = DEAD;
            for f in 0..4 {
                let w = self.adj[i][f];
                if w != NONE {
                    self.adj[(w >> 2) as usize][(w & 3) as usize] = (4 * i + f) as u32;
                }
            }
            j -= 1;
        }
        self.v.truncate(j);
        self.adj.truncate(j);
        let items: Vec<&mut [[u32; 4]]> = self.adj.chunks_mut(chunk).collect();
        crate::par::run_dynamic(threads, items, |_, a| {
            for w in a.iter_mut().flatten() {
                if *w != NONE {
                    *w >>= 2;
                }
            }
        });
        (self.v, self.adj)
    }
}

/// One group of a pass of [`Core::insert_parts`]: inserts into `part`
/// (its arrays set, the rest filled here from `mine`, the blocks and walk
/// states of the group's parts) the points of `todo` (all of `ids` when
/// `None`) whose part is in the group (`of`: its position there), but
/// those `near` a border of the pass. Returns the points left (in order),
/// the duplicates found, the count of finite cells made minus removed,
/// and the parts' blocks and walk states.
#[allow(clippy::type_complexity)]
fn insert_group<const TWO: bool>(
    mut part: Part<'_, TWO>,
    mine: Vec<(Block, u32, u32)>,
    g: Geo<'_>,
    todo: Option<&[u32]>,
    ids: std::ops::Range<u32>,
    of: &dyn Fn(&[f64; 3]) -> Option<usize>,
    near: &dyn Fn(&[f64; 3]) -> bool,
) -> (Vec<u32>, Vec<Inserted>, isize, Vec<Block>, Vec<(u32, u32)>) {
    let mut walk: Vec<(u32, u32)> = mine.iter().map(|o| (o.1, o.2)).collect();
    part.blocks = mine.into_iter().map(|o| o.0).collect();
    // The walk starts from the first part's cell, else from another's (any
    // live cell of the group will do).
    part.last = (walk.iter().map(|w| w.0))
        .find(|&t| part.owns(t) && part.v(t)[0] != DEAD)
        .unwrap_or(NONE);
    part.rng = walk[0].1;
    let mut left = Vec::new();
    let mut dups = Vec::new();
    let mut s = Scratch::default();
    let mut one = |id: u32| {
        let p = &g.pts[id as usize];
        let Some(k) = of(p) else {
            return;
        };
        if near(p) || part.last == NONE {
            left.push(id);
            return;
        }
        part.cur = k;
        match insert_in::<_, false>(&mut part, &mut s, g, id) {
            None => left.push(id),
            Some(d @ Inserted::Duplicate { .. }) => dups.push(d),
            Some(_) => {}
        }
    };
    match todo {
        None => ids.for_each(&mut one),
        Some(list) => list.iter().for_each(|&id| one(id)),
    }
    walk[0] = (part.last, part.rng);
    (left, dups, part.finite, part.blocks, walk)
}

/// `n` zeroed slots for [`Core::insert_parts`]. Large arrays come from
/// zeroed memory (a page is cleared when first written, on the thread that
/// writes it); below 32 MiB they are cleared here in an allocation of at
/// least 32 MiB capacity: glibc raises its mmap threshold to the size of a
/// freed mapped block of up to 32 MiB, and the buffers of several MiB
/// allocated after that (the later passes, the output) come from the heap
/// and fragment it (18 MB more peak memory on 1M points).
fn zeroed_slots(n: usize) -> Vec<[u32; 4]> {
    const MIN_BYTES: usize = (32 << 20) + 4096;
    let min = MIN_BYTES / std::mem::size_of::<[u32; 4]>();
    if n >= min {
        return vec![[0u32; 4]; n];
    }
    let mut v = Vec::with_capacity(min);
    v.resize(n, [0u32; 4]);
    v
}

/// The vertices and packed neighbour words per slot of a mesh with ghost
/// cells (this kernel's, or recovery's domain mesh
/// [`crate::tet::dmesh::journal::Journaled`]): what the walks the two share
/// read ([`walk_cells`], the edge ring, carving).
pub(crate) type Arrays<'c> = (&'c [[u32; 4]], &'c [[u32; 4]]);

/// Visibility walk from `start` towards `p` over the vertices `v` and
/// packed neighbour words `adj` of a tetrahedralization with ghost cells
/// (the kernel's, or recovery's domain mesh). Returns a finite tetrahedron
/// whose closure contains `p`, or a ghost whose hull facet has `p`
/// strictly on its outer side.
pub(crate) fn walk_cells(
    arrays: Arrays<'_>,
    pts: &[[f64; 3]],
    p: &[f64; 3],
    start: u32,
    rng: &mut u32,
) -> u32 {
    match walk_owned(&arrays, pts, p, start, rng) {
        Ok(t) | Err(t) => t,
    }
}

/// [`walk_cells`] over the cells `c` owns: `Err` with the last owned cell
/// when the walk would step into a cell `c` does not own.
#[inline]
fn walk_owned<C: Cells>(
    c: &C,
    pts: &[[f64; 3]],
    p: &[f64; 3],
    start: u32,
    rng: &mut u32,
) -> Result<u32, u32> {
    let mut t = start;
    if !c.owns(t) {
        return Err(t);
    }
    if c.v(t)[3] == INF {
        let u = c.adj(t)[3] >> 2;
        if !c.owns(u) {
            return Err(t);
        }
        t = u;
    }
    let mut from = 4usize;
    'walk: loop {
        let tv = *c.v(t);
        if tv[3] == INF {
            return Ok(t);
        }
        let r = Core::next_rand(rng) as usize;
        for k in 0..4 {
            let f = (r + k) & 3;
            if f == from {
                continue;
            }
            let [a, b, d] = FACET[f].map(|i| &pts[tv[i] as usize]);
            // orient3d > 0: p is on the negative side of the facet, i.e.
            // beyond it.
            if orient3d(a, b, d, p) > 0.0 {
                let w = c.adj(t)[f];
                if !c.owns(w >> 2) {
                    return Err(t);
                }
                t = w >> 2;
                from = (w & 3) as usize;
                continue 'walk;
            }
        }
        return Ok(t);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tetrahedra as sorted vertex tuples, sorted.
    fn tet_set(m: &TetMesh) -> Vec<[u32; 4]> {
        let mut t: Vec<[u32; 4]> = m
            .tets
            .iter()
            .map(|t| {
                let mut t = *t;
                t.sort_unstable();
                t
            })
            .collect();
        t.sort_unstable();
        t
    }

    /// Builds `pts` with every BRIO round in parts (whatever its size) on 1
    /// to 4 threads, and with the rounds of 600 points or more in parts on
    /// 1 and 2 threads: each build passes the checkers, the builds of one
    /// setting give the same mesh, and the tetrahedra are those of the serial build (unless
    /// `pts` has exact duplicates: a duplicate group's tie-break follows the
    /// insertion order, see the module notes).
    fn same_for_any_thread_count(pts: &[[f64; 3]], no_duplicates: bool) {
        let serial = Delaunay3::from_points(pts).unwrap().into_mesh();
        let mut first: Option<TetMesh> = None;
        // Every round in parts, or the last two rounds of 6000 points.
        for (threads, min_points) in [(1, 0), (2, 0), (3, 0), (4, 0), (1, 600), (2, 600)] {
            if threads == 1 {
                first = None;
            }
            let split = Split {
                threads,
                min_points,
            };
            let dt = Delaunay3::build(pts, None, split, &mut |_, _| {}).unwrap();
            dt.check_topology().unwrap();
            dt.check_delaunay().unwrap();
            let m = dt.into_mesh();
            assert!(
                !no_duplicates || tet_set(&m) == tet_set(&serial),
                "{} points, {threads} threads: not the serial tetrahedra",
                pts.len()
            );
            assert_eq!(m.duplicates, serial.duplicates);
            assert_eq!(m.vertex_map, serial.vertex_map);
            match &first {
                None => first = Some(m),
                Some(f) => assert!(
                    &m == f,
                    "{} points, {threads} threads: not the 1-thread mesh",
                    pts.len()
                ),
            }
        }
    }

    fn uniform(n: usize, seed: u64) -> Vec<[f64; 3]> {
        let mut r = crate::geom::SplitMix64::new(seed);
        let mut u = || (r.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        (0..n).map(|_| [u(), u(), u()]).collect()
    }

    /// A tetrahedron's corners and point 4 inside it.
    const CORNERS_AND_INSIDE: [[f64; 3]; 5] = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.1, 0.1, 0.1],
    ];

    /// The tetrahedralization of the five points `pts` after a part
    /// inserted point 4 into `core` (its free slots `free`): checked.
    fn checked_with_point_4(pts: &[[f64; 3]], mut core: Core, free: Vec<u32>) {
        core.finite = 4;
        core.free = free;
        let dt = Delaunay3 {
            points: Cow::Borrowed(pts),
            scale: Some((1.0, 1.0)),
            weights: None,
            hidden: Vec::new(),
            core,
            vertex_map: vec![0, 1, 2, 3, 4],
            duplicates: Vec::new(),
            pending: Vec::new(),
            basis: Vec::new(),
        };
        dt.check_topology().unwrap();
        dt.check_delaunay().unwrap();
    }

    /// A part with fewer free slots than the new cells of an insertion
    /// leaves the point and changes nothing, also when it has enough slots
    /// for the net growth (the new cells are allocated before the
    /// cavity's are freed).
    #[test]
    fn a_part_short_of_slots_leaves_the_point() {
        let pts = CORNERS_AND_INSIDE;
        let g = Geo {
            pts: &pts,
            wts: &[],
            ids: &[],
        };
        // The point is inside the one tetrahedron: a cavity of one cell,
        // four new cells.
        for extra in [0usize, 3, 4] {
            let mut core = Core::default();
            core.start(&pts, [0, 1, 2, 3]);
            let live = core.v.len();
            core.v.resize(live + extra, [0; 4]);
            core.adj.resize(live + extra, [0; 4]);
            let before = (core.v.clone(), core.adj.clone());
            let last = core.last;
            let hi = core.v.len() as u32;
            let mut part = Part::<false> {
                base: 0,
                v: &mut core.v,
                adj: &mut core.adj,
                base2: 0,
                v2: &mut [],
                adj2: &mut [],
                blocks: vec![Block {
                    lo: 0,
                    hi,
                    used: live as u32,
                    free: Vec::new(),
                }],
                cur: 0,
                finite: 0,
                last,
                rng: 0x2545_F491,
            };
            let r = insert_in::<_, false>(&mut part, &mut Scratch::default(), g, 4);
            let (finite, free) = (part.finite, std::mem::take(&mut part.blocks[0].free));
            if extra < 4 {
                assert_eq!(r, None, "{extra} free slots");
                assert_eq!((core.v.clone(), core.adj.clone()), before);
            } else {
                assert_eq!(r, Some(Inserted::Vertex(4)));
                assert_eq!(finite, 3);
                checked_with_point_4(&pts, core, free);
            }
        }
    }

    /// A group owning two ranges of slots (the first and the last block of
    /// a pass) puts new cells in the block of the point's part, then in the
    /// other when that one is full; with too few slots in both it leaves
    /// the point and changes nothing.
    #[test]
    fn a_group_of_two_ranges_allocates_from_both() {
        let pts = CORNERS_AND_INSIDE;
        let g = Geo {
            pts: &pts,
            wts: &[],
            ids: &[],
        };
        // Never used slots in the first block and in the second (after two
        // slots of another group): four new cells are needed.
        for (a, b) in [(1usize, 2usize), (1, 3), (0, 4), (4, 0), (2, 5)] {
            let mut core = Core::default();
            core.start(&pts, [0, 1, 2, 3]);
            let live = core.v.len();
            let (end1, lo2) = (live + a, live + a + 2);
            core.v.resize(lo2 + b, [0; 4]);
            core.adj.resize(lo2 + b, [0; 4]);
            for t in end1..lo2 {
                core.v[t][0] = DEAD;
            }
            let before = (core.v.clone(), core.adj.clone());
            let last = core.last;
            let (v1, v2) = core.v.split_at_mut(lo2);
            let (adj1, adj2) = core.adj.split_at_mut(lo2);
            let mut part = Part::<true> {
                base: 0,
                v: &mut v1[..end1],
                adj: &mut adj1[..end1],
                base2: lo2 as u32,
                v2,
                adj2,
                blocks: vec![
                    Block {
                        lo: 0,
                        hi: end1 as u32,
                        used: live as u32,
                        free: Vec::new(),
                    },
                    Block {
                        lo: lo2 as u32,
                        hi: (lo2 + b) as u32,
                        used: lo2 as u32,
                        free: Vec::new(),
                    },
                ],
                cur: 0,
                finite: 0,
                last,
                rng: 0x2545_F491,
            };
            let r = insert_in::<_, false>(&mut part, &mut Scratch::default(), g, 4);
            let finite = part.finite;
            let used: Vec<u32> = part.blocks.iter().map(|b| b.used - b.lo).collect();
            let mut free: Vec<u32> = (part.blocks.iter_mut())
                .flat_map(|b| {
                    let mut f = std::mem::take(&mut b.free);
                    f.extend(b.used..b.hi);
                    f
                })
                .collect();
            if a + b < 4 {
                assert_eq!(r, None, "{a} + {b} free slots");
                assert_eq!((core.v.clone(), core.adj.clone()), before);
                continue;
            }
            assert_eq!(r, Some(Inserted::Vertex(4)));
            assert_eq!(finite, 3);
            // The first block first, the rest from the second.
            assert_eq!(used, [(live + a.min(4)) as u32, (4 - a.min(4)) as u32]);
            for &t in &free {
                core.v[t as usize][0] = DEAD;
            }
            free.extend(end1 as u32..lo2 as u32);
            checked_with_point_4(&pts, core, free);
        }
    }

    #[test]
    fn parts_random_points() {
        same_for_any_thread_count(&uniform(6000, 1), true);
        same_for_any_thread_count(&uniform(700, 2), true);
    }

    #[test]
    fn parts_grid_cospherical_and_duplicates() {
        let mut g: Vec<[f64; 3]> = Vec::new();
        for i in 0..14 {
            for j in 0..13 {
                for k in 0..12 {
                    g.push([i as f64, j as f64, k as f64]);
                }
            }
        }
        same_for_any_thread_count(&g, true);
        // Every point twice, the copies after the originals.
        let twice: Vec<[f64; 3]> = g.iter().chain(g.iter()).copied().collect();
        same_for_any_thread_count(&twice, false);
    }

    #[test]
    fn parts_sphere_and_plane() {
        // Cospherical points (Fibonacci sphere, exact-ish) plus the centre,
        // and a flat slab of points (many coplanar hull facets).
        let n = 3000;
        let mut s: Vec<[f64; 3]> = (0..n)
            .map(|i| {
                let z = 1.0 - (2 * i + 1) as f64 / n as f64;
                let r = (1.0 - z * z).sqrt();
                let a = i as f64 * 2.399_963_229_728_653;
                [r * a.cos(), r * a.sin(), z]
            })
            .collect();
        s.push([0.0, 0.0, 0.0]);
        same_for_any_thread_count(&s, true);
        let mut slab = uniform(4000, 3);
        for p in slab.iter_mut() {
            p[2] = (p[2] * 2.0).floor();
        }
        same_for_any_thread_count(&slab, true);
    }
}
