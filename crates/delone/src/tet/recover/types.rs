//! The recovery's public types: options, result, report and error.

use std::fmt;

use crate::tet::TetMesh;
use crate::Error;

/// Options of [`recover`](crate::tet::recover::recover).
///
/// ```
/// let o = delone::tet::recover::RecoverOptions::default();
/// assert!(o.max_steiner > 0 && !o.preserve_surface);
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RecoverOptions {
    /// Most Steiner points allowed; [`RecoverError::SteinerBudget`] beyond.
    /// Default 100 000.
    pub max_steiner: usize,
    /// Split a missing subsegment at the projection of the vertex that
    /// encroaches it most (Si & Gärtner's reference point) rather than at
    /// its midpoint. Default true.
    pub reference_points: bool,
    /// Surface preservation (TetGen's `-Y`): no Steiner point on any input
    /// edge or triangle; where flips fail, Steiner points go inside the
    /// domain only. Default false.
    pub preserve_surface: bool,
    /// Merge edge-adjacent, exactly coplanar, consistently oriented input
    /// triangles (with equal markers, see [`recover_marked`](crate::tet::recover::recover_marked)) into facets
    /// and re-triangulate each facet before recovery, reusing the edges of
    /// the Delaunay tetrahedralization on its plane (the private `merge`
    /// module; TetGen's default, its `-M` turns it off). The mesh then
    /// conforms to [`Recovered::surface`], which covers exactly the same
    /// surface. Ignored (no merging) with `preserve_surface`. Default true.
    pub merge_coplanar: bool,
    /// Without `preserve_surface`: a segment's flip attempt gives up an end
    /// of the segment whose first crossing comes round again (its flips went
    /// in a circle: a later step restored what an earlier one removed), and
    /// the segment when both ends are given up, instead of spending its
    /// whole flip budget on flips that are rolled back anyway; and the
    /// segment guides the flips of a step whose unguided flips fail (none
    /// may make more faces meet the segment than it removes), and the
    /// blocking edges of a crossed face go first (the private `cdt`
    /// module). Fewer segments fail, so fewer Steiner points
    /// and rounds, on thin strips and fans above all. False: unguided
    /// attempts that run until their flip budget is spent; that recovery
    /// gives up when 8 rounds in a row leave no fewer items missing than
    /// its best one, or once it has inserted more than three Steiner points
    /// per input point (it then splits the same thin triangles round after
    /// round), and where it gives up or fails the guided one recovers the
    /// surface from the Delaunay tetrahedralization again
    /// ([`RecoverReport::unguided_rounds`]). Default false: a refinement's
    /// smallest dihedral angles depend on where recovery put its points, and
    /// were measured with the full attempts (with this on, `-pq1.414` minima
    /// moved by up to ±3° on corpus models); [`crate::tet::mesh()`] turns it
    /// on when no refinement follows (`-p`), and the `-Y` fallback's runs of
    /// this path keep it off (and never give up that way).
    pub stop_circling_flips: bool,
}

impl Default for RecoverOptions {
    fn default() -> Self {
        RecoverOptions {
            max_steiner: 100_000,
            reference_points: true,
            preserve_surface: false,
            merge_coplanar: true,
            stop_circling_flips: false,
        }
    }
}

/// What [`recover`](crate::tet::recover::recover) did.
///
/// ```
/// let r = delone::tet::recover::RecoverReport::default();
/// assert_eq!(r.steiner(), 0);
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RecoverReport {
    /// Steiner points inserted on input edges.
    pub steiner_on_edges: usize,
    /// Steiner points inserted inside input triangles.
    pub steiner_on_facets: usize,
    /// Steiner points inserted off the surface (none at this stage).
    pub steiner_interior: usize,
    /// Steiner points whose rounded coordinates are not exactly on their
    /// edge's line or triangle's plane.
    pub inexact_steiner: usize,
    /// Largest distance of an inexact Steiner point to its line or plane
    /// (in the input's units; 0 when all are exact).
    pub max_deviation: f64,
    /// 2-3 flips performed by the constrained recovery (final round).
    pub flips23: usize,
    /// Edge removals (3-2, 4-4, n to 2n-4 flips) performed by the
    /// constrained recovery (final round).
    pub edge_removals: usize,
    /// Subsegments recovered by flips (final round).
    pub segments_by_flips: usize,
    /// Input triangles recovered by flips (final round).
    pub triangles_by_flips: usize,
    /// Rounds of the segment/facet loop.
    pub rounds: usize,
    /// Rounds the unguided recovery ran before it gave up
    /// ([`RecoverOptions::stop_circling_flips`] off: it stopped leaving fewer
    /// items missing, or failed) and the guided one recovered the surface
    /// from the Delaunay tetrahedralization again (whose rounds are
    /// [`Self::rounds`]); 0 when it finished or did not run.
    pub unguided_rounds: usize,
    /// Tetrahedra of the whole (convex hull) tetrahedralization before carving.
    pub hull_tets: usize,
    /// Components removed because a hole point lies in them.
    pub holes_removed: usize,
    /// Groups of coplanar input triangles merged and re-triangulated
    /// ([`RecoverOptions::merge_coplanar`](crate::tet::recover::RecoverOptions::merge_coplanar)).
    pub coplanar_groups: usize,
    /// Groups of coplanar input triangles kept as given because their
    /// re-triangulation failed.
    pub coplanar_kept: usize,
    /// Flat cells removed from the domain after carving: a cell with two
    /// boundary faces on one input triangle, one of them the thin face of
    /// an inexact Steiner point rounded onto a subsegment under a chord
    /// (the private `carve` module's `drop_chord_slivers`).
    pub chord_slivers: usize,
}

impl RecoverReport {
    /// All Steiner points.
    ///
    /// ```
    /// let mut r = delone::tet::recover::RecoverReport::default();
    /// r.steiner_on_edges = 2;
    /// r.steiner_on_facets = 1;
    /// assert_eq!(r.steiner(), 3);
    /// ```
    pub fn steiner(&self) -> usize {
        self.steiner_on_edges + self.steiner_on_facets + self.steiner_interior
    }
}

/// The result of [`recover`](crate::tet::recover::recover).
#[derive(Debug, Clone, PartialEq)]
pub struct Recovered {
    /// The input points followed by the Steiner points.
    pub points: Vec<[f64; 3]>,
    /// The tetrahedra of the domain, positively oriented; neighbours
    /// across the domain's boundary are [`crate::NONE`] (tetrahedra on both
    /// sides of an internal facet stay neighbours).
    pub mesh: TetMesh,
    /// The triangles the mesh conforms to: the input triangles, except
    /// that each group of coplanar input triangles merged by
    /// [`RecoverOptions::merge_coplanar`](crate::tet::recover::RecoverOptions::merge_coplanar) is replaced by another
    /// triangulation of the same region (same vertices and boundary).
    /// Without merging, a copy of the input triangles.
    pub surface: Vec<[u32; 3]>,
    /// For each triangle of `surface`: an input triangle of its group (so of
    /// the same facet, e.g. for markers); itself when not merged.
    pub surface_origin: Vec<u32>,
    /// The boundary faces, oriented outward (counterclockwise seen from
    /// outside), each a refinement piece of a triangle of `surface` (or,
    /// with [`Domain::convex_hull`](crate::tet::recover::Domain::convex_hull), a convex hull face off the surface).
    pub boundary: Vec<[u32; 3]>,
    /// For each boundary face, the index **in `surface`** of the triangle
    /// it lies on ([`crate::NONE`] for a hull face off the surface); the
    /// input triangle is `surface_origin[boundary_triangle[i]]`. With the
    /// constrained recovery, a merged coplanar group is recovered as one
    /// polygon: its faces need not lie inside single triangles of the
    /// group, and all name the group's first triangle in `surface`.
    pub boundary_triangle: Vec<u32>,
    /// Faces on input triangles between two tetrahedra of the domain
    /// (internal facets, region interfaces), each once, oriented outward
    /// from the lower-numbered of its two tetrahedra.
    pub interior_faces: Vec<[u32; 3]>,
    /// For each interior face, the index in `surface` of the triangle it
    /// lies on (see `boundary_triangle`).
    pub interior_triangle: Vec<u32>,
    /// Per tetrahedron: its region (index into `regions`).
    pub tet_region: Vec<u32>,
    /// The regions of the domain.
    pub regions: Vec<MeshRegion>,
    /// Steiner points (ids) not exactly on their edge or triangle.
    pub inexact: Vec<u32>,
    /// Counts.
    pub report: RecoverReport,
}

impl Recovered {
    /// The faces on input triangles, each with the index in
    /// [`Self::surface`] of the triangle it lies on ([`crate::NONE`] for a
    /// hull face): the boundary faces, then the interior faces.
    pub(crate) fn surface_faces(&self) -> impl Iterator<Item = (&[u32; 3], u32)> + '_ {
        let boundary = self.boundary.iter().zip(&self.boundary_triangle);
        let interior = self.interior_faces.iter().zip(&self.interior_triangle);
        boundary.chain(interior).map(|(f, &t)| (f, t))
    }
}

/// Why [`recover`](crate::tet::recover::recover) failed.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum RecoverError {
    /// The input is invalid (bad index or coordinate, degenerate triangle,
    /// self-intersection, duplicate vertex).
    Input(Error),
    /// The surface is not closed: `edge` is in fewer than two triangles.
    OpenSurface {
        /// The first offending edge `[min, max]`.
        edge: [u32; 2],
        /// How many offending edges there are.
        count: usize,
    },
    /// The Steiner budget ran out.
    SteinerBudget {
        /// The budget.
        limit: usize,
        /// Subsegments missing when it ran out.
        missing_subsegments: usize,
        /// Input triangles not yet recovered when it ran out.
        missing_triangles: usize,
    },
    /// A missing subsegment of input edge `edge` is too short to hold a
    /// Steiner point between its ends in floating point.
    SegmentTooShort {
        /// The input edge `[min, max]`.
        edge: [u32; 2],
    },
    /// These input triangles could not be recovered (neither a Steiner point
    /// nor a flip made progress).
    Unrecovered {
        /// Input triangle indices, ascending (for a merged coplanar group,
        /// an input triangle of the group, see [`Recovered::surface_origin`]).
        triangles: Vec<usize>,
        /// Steiner points inserted before giving up.
        steiner: usize,
    },
    /// Hole or region point `index` lies on the input surface (on a face,
    /// edge or vertex of the recovered facets), so its region is ambiguous.
    SeedOnSurface {
        /// `"hole"` or `"region"`.
        kind: &'static str,
        /// Index of the point in [`Domain::holes`](crate::tet::recover::Domain::holes) or [`Domain::regions`](crate::tet::recover::Domain::regions).
        index: usize,
    },
    /// [`recover_marked`](crate::tet::recover::recover_marked): the markers are neither empty nor one per
    /// triangle.
    MarkerCount {
        /// The number of triangles.
        expected: usize,
        /// The number of markers.
        got: usize,
    },
    /// Input point `point`, a vertex of no input triangle, lies exactly on
    /// input triangle `triangle` (inside it or on one of its edges): the
    /// surface cannot be recovered without it as a vertex. Make it a vertex
    /// of the triangles it lies on ([`crate::model::plc::Plc::triangulate_facets`]
    /// does so for the isolated points of a PLC), or remove it.
    PointOnTriangle {
        /// The point index.
        point: usize,
        /// The (lowest) input triangle it lies on.
        triangle: usize,
    },
    /// The input asks for something this version cannot do yet.
    Unsupported {
        /// What is missing.
        what: &'static str,
    },
}

impl From<Error> for RecoverError {
    fn from(e: Error) -> Self {
        RecoverError::Input(e)
    }
}

impl fmt::Display for RecoverError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RecoverError::Input(e) => write!(f, "invalid input: {e}"),
            RecoverError::OpenSurface { edge, count } => write!(
                f,
                "surface is not closed: edge {}-{} is in only one triangle ({count} such edges)",
                edge[0], edge[1]
            ),
            RecoverError::SteinerBudget {
                limit,
                missing_subsegments,
                missing_triangles,
            } => write!(
                f,
                "Steiner budget of {limit} points exhausted with {missing_subsegments} subsegments and {missing_triangles} triangles missing"
            ),
            RecoverError::SegmentTooShort { edge } => write!(
                f,
                "a subsegment of edge {}-{} is too short to split in floating point",
                edge[0], edge[1]
            ),
            RecoverError::Unrecovered { triangles, steiner } => write!(
                f,
                "{} triangle(s) could not be recovered (first: {}) after {steiner} Steiner points",
                triangles.len(),
                triangles.first().copied().unwrap_or(0)
            ),
            RecoverError::SeedOnSurface { kind, index } => write!(
                f,
                "{kind} point {index} lies on the input surface (its region is ambiguous)"
            ),
            RecoverError::MarkerCount { expected, got } => {
                write!(f, "{got} triangle markers for {expected} triangles")
            }
            RecoverError::PointOnTriangle { point, triangle } => write!(
                f,
                "point {point} lies on triangle {triangle} but is a vertex of no triangle"
            ),
            RecoverError::Unsupported { what } => write!(f, "not implemented yet: {what}"),
        }
    }
}

impl std::error::Error for RecoverError {}

/// One region of a carved mesh (a component of the domain bounded by input
/// facets).
///
/// ```
/// let r = delone::tet::recover::MeshRegion {
///     attribute: 1.0, max_volume: None, seed: None, exterior: false, tets: 5, volume: 1.0,
/// };
/// assert_eq!(r.tets, 5);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct MeshRegion {
    /// Regional attribute (TetGen `-A`).
    pub attribute: f64,
    /// Volume bound of the region's seed, if it has a positive one.
    pub max_volume: Option<f64>,
    /// The index of the region point (in [`Domain::regions`](crate::tet::recover::Domain::regions)) that names it.
    pub seed: Option<usize>,
    /// The region outside the surface, kept by [`Domain::convex_hull`](crate::tet::recover::Domain::convex_hull).
    pub exterior: bool,
    /// Number of tetrahedra.
    pub tets: usize,
    /// Sum of the tetrahedra's volumes (input units).
    pub volume: f64,
}
