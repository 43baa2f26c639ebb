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
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::InvalidCoordinate { index } => {
                write!(f, "point {index} has a NaN or infinite coordinate")
            }
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
