//! Typed errors and invariant violations.

use std::fmt;

/// Errors returned by delone on invalid input or unsatisfiable requests.
///
/// Every variant names the offending input item (by its 0-based index in the
/// caller's point array).
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Error {
    /// A coordinate of input point `index` is NaN or infinite.
    InvalidCoordinate {
        /// 0-based index of the point.
        index: usize,
    },
    /// A nonzero coordinate so much smaller than the largest coordinate
    /// magnitude that the exact predicates would underflow on it (see
    /// [`crate::geom::scale::check_range`]).
    CoordinateRange {
        /// 0-based index of the point.
        index: usize,
        /// The axis (0 = x, 1 = y, 2 = z).
        axis: usize,
        /// The coordinate.
        value: f64,
        /// The largest coordinate magnitude of the input.
        max: f64,
    },
    /// Fewer distinct points than the dimension needs (3 in 2D, 4 in 3D).
    TooFewPoints {
        /// Number of distinct points found.
        found: usize,
        /// Number needed.
        needed: usize,
    },
    /// All input points lie in a lower-dimensional affine subspace
    /// (collinear in 2D, coplanar in 3D), so no triangle/tetrahedron exists.
    Degenerate {
        /// `1` for collinear, `2` for coplanar.
        dimension: usize,
    },
    /// More points than the `u32` index space allows.
    CapacityExceeded {
        /// Number of points requested.
        requested: usize,
    },
    /// A mesh handed to a function together with points does not belong to
    /// them (vertex ids out of range, array lengths that differ).
    InconsistentMesh {
        /// What does not fit, naming the element.
        reason: String,
    },
    /// Weight `index` of a weighted point set is NaN or infinite.
    InvalidWeight {
        /// 0-based index of the point.
        index: usize,
    },
    /// A weighted point set has a different number of weights than points.
    WeightCount {
        /// Number of points.
        points: usize,
        /// Number of weights.
        weights: usize,
    },
    /// A hole or region seed point (of a PSLG or PLC) has a NaN or infinite coordinate.
    InvalidSeedPoint {
        /// `"hole"`, `"region"` or `"facet hole"` (PLC), `"hole"` or `"region"` (PSLG).
        kind: &'static str,
        /// 0-based index in its list (for a facet hole: the facet index).
        index: usize,
    },
    /// An input item refers to a point that does not exist.
    IndexOutOfRange {
        /// `"facet"`, `"segment"` or `"triangle"`.
        item: &'static str,
        /// 0-based index of the item.
        index: usize,
        /// The offending point index.
        vertex: u32,
        /// Number of points.
        points: usize,
    },
    /// A facet (or segment) of a PLC is degenerate.
    DegenerateFacet {
        /// 0-based index of the facet (or segment).
        index: usize,
        /// What is wrong with it.
        defect: FacetDefect,
    },
    /// Two facets of the input intersect other than as the input topology
    /// says (sharing exactly a vertex or an edge).
    SelfIntersection {
        /// The first offending pair (0-based facet indices, smaller first).
        facets: (usize, usize),
        /// How many offending pairs were found in total.
        count: usize,
    },
    /// Segment `segment` names point `point`, which does not exist.
    SegmentOutOfRange {
        /// 0-based index of the segment.
        segment: usize,
        /// The point index it names.
        point: usize,
    },
    /// Segment `segment` joins a point to itself (or to an exact copy of it).
    ZeroLengthSegment {
        /// 0-based index of the segment.
        segment: usize,
    },
    /// Points `index` and `original` have the same coordinates.
    DuplicateVertex {
        /// 0-based index of the later point.
        index: usize,
        /// 0-based index of the first point with those coordinates.
        original: usize,
    },
    /// Segments `index` and `original` join the same two points.
    DuplicateSegment {
        /// 0-based index of the later segment.
        index: usize,
        /// 0-based index of the first segment.
        original: usize,
    },
    /// Two segments intersect in a way the constrained triangulation could not
    /// resolve (the rounded intersection point does not fit between its
    /// neighbours, e.g. in a needle-thin configuration).
    SegmentIntersection {
        /// The segment being inserted (0-based input index).
        segment: usize,
        /// The segment it crosses (0-based input index).
        other: usize,
    },
    /// A refinement bound no mesh can meet, or not a bound at all (NaN,
    /// zero or negative where a positive number is needed). Nothing is
    /// meshed.
    ///
    /// ```
    /// let e = delone::Error::InvalidBound { option: "-q", value: 61.0, reason: "no triangle has all angles above 60 degrees" };
    /// assert!(e.to_string().starts_with("-q61: "));
    /// ```
    InvalidBound {
        /// The option, as the command line spells it (`"-q"`, `"-a"`,
        /// `"-hmin"`; a name longer than two characters is shown with a
        /// space before the value).
        option: &'static str,
        /// The value given.
        value: f64,
        /// Why no mesh can meet it.
        reason: &'static str,
    },
    /// A size bound that asks for more Steiner points than the largest
    /// default budget allows: refused before any work, since the run would
    /// stop at the budget after a long time. An explicit budget (`-S`,
    /// `max_steiner`) lets it run.
    ///
    /// ```
    /// let e = delone::Error::BoundNeedsBudget { option: "-a", value: 1e-9, needed: 300_000_000, budget: 4_194_304 };
    /// assert!(e.to_string().contains("-S"));
    /// ```
    BoundNeedsBudget {
        /// The option, as the command line spells it (`"-a"`).
        option: &'static str,
        /// The value given (NaN: the regional bounds of the input).
        value: f64,
        /// About how many Steiner points the bound needs.
        needed: usize,
        /// The largest default budget.
        budget: usize,
    },
    /// The run was stopped through its stop flag
    /// ([`crate::progress::stoppable`]) before it could finish.
    ///
    /// ```
    /// assert_eq!(delone::Error::Interrupted.to_string(), "interrupted");
    /// ```
    Interrupted,
    /// The metric at vertex `vertex` is not a metric (not positive
    /// definite, not finite).
    ///
    /// ```
    /// use delone::metric::MetricDefect;
    /// let e = delone::Error::InvalidMetric { vertex: 7, defect: MetricDefect::NotPositiveDefinite };
    /// assert!(e.to_string().starts_with("the metric at vertex 7"));
    /// ```
    InvalidMetric {
        /// 0-based index of the vertex.
        vertex: usize,
        /// What is wrong with it.
        defect: MetricDefect,
    },
    /// A metric field has a different number of values than the mesh has
    /// vertices.
    MetricCount {
        /// Vertices of the mesh.
        vertices: usize,
        /// Metrics given.
        metrics: usize,
    },
}

/// Why a facet of a PLC is degenerate (see [`Error::DegenerateFacet`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum FacetDefect {
    /// A polygon has fewer than 3 corners (a segment: its two ends are the
    /// same point), or the facet has no polygon.
    TooFewVertices,
    /// A polygon visits the same point twice (by index or by coordinates).
    RepeatedVertex {
        /// The repeated point index.
        vertex: u32,
    },
    /// All points of the facet are collinear: the facet has zero area.
    ZeroArea,
    /// The points of the facet do not lie in one plane (exact test).
    NonPlanar {
        /// A point off the plane of the facet's first three non-collinear
        /// points.
        vertex: u32,
    },
    /// A point of the facet (a corner, or an isolated point given as a
    /// one-corner polygon) lies outside the facet's outer boundary or in one
    /// of its holes.
    PointOutside {
        /// The point.
        vertex: u32,
    },
}

impl fmt::Display for FacetDefect {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FacetDefect::TooFewVertices => write!(f, "has too few vertices"),
            FacetDefect::RepeatedVertex { vertex } => write!(f, "repeats point {vertex}"),
            FacetDefect::ZeroArea => write!(f, "has zero area (all points collinear)"),
            FacetDefect::NonPlanar { vertex } => {
                write!(f, "is not planar (point {vertex} is off its plane)")
            }
            FacetDefect::PointOutside { vertex } => {
                write!(f, "has point {vertex} outside its boundary or in a hole")
            }
        }
    }
}

/// What is wrong with the components of a metric.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MetricDefect {
    /// Not `D(D+1)/2` components (3 in 2D, 6 in 3D).
    ComponentCount,
    /// A component is NaN or infinite.
    NotFinite,
    /// An eigenvalue is zero or negative.
    NotPositiveDefinite,
}

impl fmt::Display for MetricDefect {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            MetricDefect::ComponentCount => "has the wrong number of components",
            MetricDefect::NotFinite => "has a NaN or infinite component",
            MetricDefect::NotPositiveDefinite => "is not positive definite",
        })
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Interrupted => f.write_str("interrupted"),
            Error::InvalidMetric { vertex, defect } => {
                write!(f, "the metric at vertex {vertex} {defect}")
            }
            Error::MetricCount { vertices, metrics } => write!(
                f,
                "the metric field has {metrics} value(s) for a mesh of {vertices} vertices"
            ),
            Error::InvalidCoordinate { index } => {
                write!(f, "point {index} has a NaN or infinite coordinate")
            }
            Error::CoordinateRange {
                index,
                axis,
                value,
                max,
            } => write!(
                f,
                "point {index} has {} = {value:e}, nonzero but too small next to the largest coordinate magnitude {max:e} for exact arithmetic (the dynamic range must stay within 2^162 in 3D, 2^216 in 2D; set it to 0 or rescale that part)",
                ["x", "y", "z"].get(*axis).unwrap_or(&"?")
            ),
            Error::TooFewPoints { found, needed } => write!(
                f,
                "only {found} distinct point(s); at least {needed} affinely independent points are needed"
            ),
            Error::Degenerate { dimension: 1 } => {
                write!(f, "all points are collinear; no triangle exists")
            }
            Error::Degenerate { dimension: 2 } => {
                write!(f, "all points are coplanar; no tetrahedron exists")
            }
            Error::Degenerate { dimension } => write!(
                f,
                "all points lie in a {dimension}-dimensional subspace; no full-dimensional element exists"
            ),
            Error::CapacityExceeded { requested } => write!(
                f,
                "{requested} points exceed the u32 index space of delone"
            ),
            Error::InconsistentMesh { reason } => {
                write!(f, "the mesh does not belong to these points: {reason}")
            }
            Error::InvalidWeight { index } => {
                write!(f, "the weight of point {index} is NaN or infinite")
            }
            Error::WeightCount { points, weights } => {
                write!(f, "{points} points but {weights} weights")
            }
            Error::InvalidSeedPoint { kind, index } => {
                write!(f, "{kind} {index} has a NaN or infinite coordinate")
            }
            Error::IndexOutOfRange {
                item,
                index,
                vertex,
                points,
            } => write!(
                f,
                "{item} {index} refers to point {vertex}, but there are only {points} points"
            ),
            Error::DegenerateFacet { index, defect } => write!(f, "facet {index} {defect}"),
            Error::SelfIntersection { facets, count } => write!(
                f,
                "facets {} and {} intersect ({count} intersecting pair(s) in total)",
                facets.0, facets.1
            ),
            Error::SegmentOutOfRange { segment, point } => {
                write!(f, "segment {segment} names point {point}, which does not exist")
            }
            Error::ZeroLengthSegment { segment } => {
                write!(f, "segment {segment} has zero length")
            }
            Error::DuplicateVertex { index, original } => {
                write!(f, "point {index} duplicates point {original}")
            }
            Error::DuplicateSegment { index, original } => {
                write!(f, "segment {index} duplicates segment {original}")
            }
            Error::SegmentIntersection { segment, other } => write!(
                f,
                "the crossing of segments {segment} and {other} could not be resolved"
            ),
            Error::InvalidBound {
                option,
                value,
                reason,
            } => {
                // A switch letter takes its value glued (`-q70`), a long
                // option after a space.
                let gap = if option.len() <= 2 { "" } else { " " };
                write!(f, "{option}{gap}{value}: {reason}")
            }
            Error::BoundNeedsBudget {
                option,
                value,
                needed,
                budget,
            } => {
                if value.is_nan() {
                    write!(f, "the regional bounds of {option} ask")?;
                } else {
                    write!(f, "{option}{value:e} asks")?;
                }
                write!(
                    f,
                    " for about {needed} Steiner points, more than the largest default budget of {budget}; give -S<n> (max_steiner) to allow that many"
                )
            }
        }
    }
}

impl std::error::Error for Error {}

/// A broken invariant found by a checker (`check_topology`, `check_delaunay`, ...).
///
/// Produced by the invariant checkers; a violation on output built by delone
/// is a bug in delone.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Violation {
    /// Which invariant failed, e.g. `"adjacency"`, `"orientation"`, `"delaunay"`.
    pub kind: &'static str,
    /// Human-readable detail naming the elements involved.
    pub detail: String,
}

impl Violation {
    /// Builds a violation.
    ///
    /// ```
    /// let v = delone::Violation::new("orientation", "triangle 3 is clockwise");
    /// assert_eq!(v.kind, "orientation");
    /// ```
    pub fn new(kind: &'static str, detail: impl Into<String>) -> Self {
        Violation {
            kind,
            detail: detail.into(),
        }
    }
}

impl fmt::Display for Violation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} violated: {}", self.kind, self.detail)
    }
}

impl std::error::Error for Violation {}
