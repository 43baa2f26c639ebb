//! Sizing functions of the refinement: a local target edge length `h(x)`
//! from a user closure, or from sizes at the vertices of a *background*
//! tetrahedral mesh interpolated linearly (TetGen's `-m`, `.mtr` files).
//!
//! **The rule.** `h` is read as the edge length wanted near `x`. A
//! tetrahedron with circumcentre `c` and circumradius `R` is *too big* when
//!
//! ```text
//! R > (√6 / 4) · h(c)        (√6/4 ≈ 0.612: the circumradius of the regular tetrahedron of edge h)
//! ```
//!
//! so a well-shaped tetrahedron meets the rule exactly when its edges are
//! about `h` or shorter, and a mesh that meets it has every edge ≤ 2R ≤
//! 1.22 h(c). The circumradius (not the longest edge) is tested because it
//! is what Delaunay refinement controls: the cell is split at `c`, and the
//! empty circumsphere puts every other vertex at distance ≥ R from `c`, so
//! a size split never creates an edge shorter than 0.61 h(c) — refinement
//! cannot run below the asked size, and the number of points stays
//! bounded by about the integral of `h⁻³` (plus what the geometry needs).
//! The size is read at the circumcentre because that is where the new
//! vertex goes.
//!
//! The boundary obeys the same size: a subface whose circumradius exceeds
//! `h / √3` at its circumcentre (the circumradius of the equilateral
//! triangle of edge `h`) is split at its circumcentre (rule R2, new spacing
//! ≥ 0.58 h). Subsegments follow from it: every subsegment is an edge of a
//! subface, so once the subfaces meet the rule it is no longer than
//! `2h/√3 ≈ 1.15 h` (at the subface's circumcentre). An explicit
//! "subsegment longer than h" rule was tried and dropped: splitting
//! unencroached subsegments first leaves the adjacent facets' subfaces
//! non-Delaunay (only the subfaces holding the segment are re-cut), and the
//! cells behind them then cannot place their circumcentres (many skipped
//! cells, runaway refinement with `-q`); splitting the subfaces first keeps
//! each facet Delaunay and the subsegments get split by encroachment.
//!
//! A size that is not a positive finite number means "no constraint" at
//! that point.

use std::fmt;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::Arc;

use delone_predicates::orient3d;

use super::geom::tri_circumcenter;

use crate::geom::vec3::{dist2, P};
use crate::tet::local::FACET;
use crate::tet::mesh::{input_tets, TetsDefect};
use crate::tet::quality;
use crate::NONE;

/// A target edge length function `h(x)`, in the input's units.
pub type SizeFn = dyn Fn([f64; 3]) -> f64 + Send + Sync;

/// The sizing of a refinement ([`super::RefineOptions::sizing`]); see the
/// [module documentation](self) for the rule.
///
/// ```
/// use delone::tet::refine::sizing::Sizing;
/// let s = Sizing::function(|p| 0.1 + p[0]);
/// assert_eq!(s.size_at([1.0, 0.0, 0.0]), Some(1.1));
/// assert_eq!(Sizing::None.size_at([1.0, 0.0, 0.0]), None);
/// assert_eq!(Sizing::function(|_| -1.0).size_at([0.0; 3]), None); // no constraint
/// ```
#[derive(Clone, Default)]
pub enum Sizing {
    /// No sizing (the default).
    #[default]
    None,
    /// A user closure giving the target edge length at a point.
    Function(Arc<SizeFn>),
    /// Sizes at the vertices of a background mesh, interpolated linearly.
    Background(Arc<Background>),
}

impl Sizing {
    /// Wraps a closure `x ↦ h(x)`.
    ///
    /// ```
    /// let s = delone::tet::refine::sizing::Sizing::function(|_| 0.5);
    /// assert!(!s.is_none());
    /// ```
    pub fn function(f: impl Fn([f64; 3]) -> f64 + Send + Sync + 'static) -> Sizing {
        Sizing::Function(Arc::new(f))
    }

    /// `true` for [`Sizing::None`].
    ///
    /// ```
    /// assert!(delone::tet::refine::sizing::Sizing::default().is_none());
    /// ```
    pub fn is_none(&self) -> bool {
        matches!(self, Sizing::None)
    }

    /// The target edge length at `x`, or `None` when there is no
    /// constraint there (no sizing, or a size that is not positive and
    /// finite).
    ///
    /// ```
    /// use delone::tet::refine::sizing::{Background, Sizing};
    /// let pts = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    /// let bg = Background::new(pts, vec![[0, 1, 2, 3]], vec![1.0, 3.0, 1.0, 1.0]).unwrap();
    /// let s = Sizing::Background(std::sync::Arc::new(bg));
    /// assert!((s.size_at([0.5, 0.0, 0.0]).unwrap() - 2.0).abs() < 1e-12);
    /// ```
    pub fn size_at(&self, x: [f64; 3]) -> Option<f64> {
        let h = match self {
            Sizing::None => return None,
            Sizing::Function(f) => f(x),
            Sizing::Background(b) => b.size_at(x)?,
        };
        (h.is_finite() && h > 0.0).then_some(h)
    }
}

impl fmt::Debug for Sizing {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Sizing::None => f.write_str("None"),
            Sizing::Function(_) => f.write_str("Function(..)"),
            Sizing::Background(b) => f
                .debug_struct("Background")
                .field("points", &b.points.len())
                .field("tets", &b.tets.len())
                .finish(),
        }
    }
}

impl PartialEq for Sizing {
    /// Equal when both are `None` or share the same closure / background.
    fn eq(&self, other: &Self) -> bool {
        match (self, other) {
            (Sizing::None, Sizing::None) => true,
            (Sizing::Function(a), Sizing::Function(b)) => Arc::ptr_eq(a, b),
            (Sizing::Background(a), Sizing::Background(b)) => Arc::ptr_eq(a, b),
            _ => false,
        }
    }
}

/// Why a [`Background`] mesh was refused.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum SizingError {
    /// The number of sizes differs from the number of points.
    SizeCount {
        /// Points.
        expected: usize,
        /// Sizes.
        got: usize,
    },
    /// A coordinate of point `index` is not finite.
    InvalidCoordinate {
        /// The point.
        index: usize,
    },
    /// Tetrahedron `tet` names a point that does not exist, or one point
    /// twice.
    BadIndex {
        /// The tetrahedron.
        tet: usize,
    },
    /// Tetrahedron `tet` is flat (zero volume).
    Degenerate {
        /// The tetrahedron.
        tet: usize,
    },
    /// A face of tetrahedron `tet` is shared by more than two tetrahedra.
    NonManifold {
        /// The tetrahedron.
        tet: usize,
    },
}

impl fmt::Display for SizingError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SizingError::SizeCount { expected, got } => {
                write!(f, "background mesh: {got} sizes for {expected} points")
            }
            SizingError::InvalidCoordinate { index } => {
                write!(
                    f,
                    "background mesh: point {index} has a non-finite coordinate"
                )
            }
            SizingError::BadIndex { tet } => {
                write!(
                    f,
                    "background mesh: tetrahedron {tet} has a bad vertex index"
                )
            }
            SizingError::Degenerate { tet } => {
                write!(f, "background mesh: tetrahedron {tet} is flat")
            }
            SizingError::NonManifold { tet } => write!(
                f,
                "background mesh: a face of tetrahedron {tet} is shared by more than two tetrahedra"
            ),
        }
    }
}

impl std::error::Error for SizingError {}

/// A background mesh: tetrahedra with a size at every vertex, interpolated
/// linearly (barycentric weights) inside each tetrahedron. A point is
/// located by a visibility walk from the last tetrahedron found; outside
/// the mesh the walk stops at a boundary tetrahedron and the weights are
/// clamped to that tetrahedron (a nearby value). Vertices whose size is not
/// positive impose nothing: the weights of the others are renormalised.
///
/// ```
/// use delone::tet::refine::sizing::Background;
/// // Sizes at the points only: the background is their Delaunay tetrahedralization.
/// let pts = vec![[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 2.0], [2.0, 2.0, 2.0]];
/// let bg = Background::from_points(pts, vec![1.0, 1.0, 1.0, 1.0, 0.0]).unwrap();
/// assert_eq!(bg.size_at([0.1, 0.1, 0.1]), Some(1.0));
/// ```
#[derive(Debug)]
pub struct Background {
    points: Vec<[f64; 3]>,
    /// Tetrahedra, oriented so that `orient3d` is negative (delone's
    /// positive volume).
    tets: Vec<[u32; 4]>,
    /// Neighbour across face `f` (opposite vertex `f`), [`NONE`] outside.
    nb: Vec<[u32; 4]>,
    sizes: Vec<f64>,
    hint: AtomicU32,
}

impl Background {
    /// A background mesh of `tets` (either orientation, made consistent per
    /// tetrahedron) over `points`, with `sizes[i]` at point `i`.
    ///
    /// # Errors
    /// [`SizingError`] naming the offending point or tetrahedron.
    ///
    /// ```
    /// use delone::tet::refine::sizing::{Background, SizingError};
    /// let pts = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    /// let e = Background::new(pts.clone(), vec![[0, 1, 2, 7]], vec![1.0; 4]).unwrap_err();
    /// assert_eq!(e, SizingError::BadIndex { tet: 0 });
    /// assert!(Background::new(pts, vec![[0, 2, 1, 3]], vec![1.0; 4]).is_ok());
    /// ```
    pub fn new(
        points: Vec<[f64; 3]>,
        tets: Vec<[u32; 4]>,
        sizes: Vec<f64>,
    ) -> Result<Background, SizingError> {
        if sizes.len() != points.len() {
            return Err(SizingError::SizeCount {
                expected: points.len(),
                got: sizes.len(),
            });
        }
        if let Some(index) = points.iter().position(|p| p.iter().any(|c| !c.is_finite())) {
            return Err(SizingError::InvalidCoordinate { index });
        }
        let (tets, nb) = input_tets(&points, &tets, false).map_err(|d| match d {
            TetsDefect::BadIndex(tet) => SizingError::BadIndex { tet },
            TetsDefect::Degenerate(tet) => SizingError::Degenerate { tet },
            // Orientation and overlap are not asked for here.
            TetsDefect::NonManifold(tet) | TetsDefect::Inverted(tet) | TetsDefect::Overlap(tet) => {
                SizingError::NonManifold { tet }
            }
        })?;
        Ok(Background {
            points,
            tets,
            nb,
            sizes,
            hint: AtomicU32::new(0),
        })
    }

    /// Sizes at scattered points: the background mesh is their Delaunay
    /// tetrahedralization (points in a plane or fewer than four: the size
    /// of the nearest point with a size).
    ///
    /// # Errors
    /// [`SizingError::SizeCount`], [`SizingError::InvalidCoordinate`].
    ///
    /// ```
    /// use delone::tet::refine::sizing::Background;
    /// let bg = Background::from_points(vec![[0.0; 3], [1.0, 0.0, 0.0]], vec![1.0, 2.0]).unwrap();
    /// assert_eq!(bg.size_at([0.9, 0.0, 0.0]), Some(2.0));
    /// ```
    pub fn from_points(points: Vec<[f64; 3]>, sizes: Vec<f64>) -> Result<Background, SizingError> {
        if sizes.len() != points.len() {
            return Err(SizingError::SizeCount {
                expected: points.len(),
                got: sizes.len(),
            });
        }
        let tets = match crate::tet::Delaunay3::from_points(&points) {
            Ok(d) => d.into_mesh().tets,
            Err(crate::Error::InvalidCoordinate { index }) => {
                return Err(SizingError::InvalidCoordinate { index })
            }
            Err(_) => Vec::new(),
        };
        Background::new(points, tets, sizes)
    }

    /// The interpolated size at `x` (`None` where no vertex around has a
    /// positive size).
    ///
    /// ```
    /// use delone::tet::refine::sizing::Background;
    /// let pts = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    /// let bg = Background::new(pts, vec![[0, 1, 2, 3]], vec![0.0; 4]).unwrap();
    /// assert_eq!(bg.size_at([0.1, 0.1, 0.1]), None);
    /// ```
    pub fn size_at(&self, x: [f64; 3]) -> Option<f64> {
        let ok = |s: f64| s.is_finite() && s > 0.0;
        if self.tets.is_empty() {
            return self
                .points
                .iter()
                .zip(&self.sizes)
                .filter(|(_, &s)| ok(s))
                .min_by(|a, b| dist2(a.0, &x).total_cmp(&dist2(b.0, &x)))
                .map(|(_, &s)| s);
        }
        let t = self.locate(x);
        let tv = self.tets[t as usize];
        let p = tv.map(|q| self.points[q as usize]);
        let vol = quality::volume(&p);
        let mut wsum = 0.0;
        let mut acc = 0.0;
        for i in 0..4 {
            let s = self.sizes[tv[i] as usize];
            if !ok(s) {
                continue;
            }
            let mut q = p;
            q[i] = x;
            let w = (quality::volume(&q) / vol).max(0.0);
            wsum += w;
            acc += w * s;
        }
        if wsum > 0.0 {
            return Some(acc / wsum);
        }
        tv.iter()
            .map(|&q| self.sizes[q as usize])
            .filter(|&s| ok(s))
            .min_by(f64::total_cmp)
    }

    /// The tetrahedron holding `x`, or the boundary tetrahedron where the
    /// walk leaves the mesh.
    fn locate(&self, x: [f64; 3]) -> u32 {
        let n = self.tets.len() as u32;
        let mut t = self.hint.load(Ordering::Relaxed).min(n - 1);
        let limit = 4 * self.tets.len() + 64;
        for step in 0..limit {
            let tv = self.tets[t as usize];
            let p = tv.map(|q| self.points[q as usize]);
            let mut next = None;
            for k in 0..4 {
                let f = (k + step) % 4;
                let [a, b, c] = FACET[f].map(|i| p[i]);
                // The tetrahedron is negative by orient3d: `x` beyond face
                // `f` makes the face's cone with `x` positive.
                if orient3d(&a, &b, &c, &x) > 0.0 {
                    next = Some(f);
                    break;
                }
            }
            match next {
                None => {
                    self.hint.store(t, Ordering::Relaxed);
                    return t;
                }
                Some(f) => {
                    let u = self.nb[t as usize][f];
                    if u == NONE {
                        self.hint.store(t, Ordering::Relaxed);
                        return t;
                    }
                    t = u;
                }
            }
        }
        // The walk cycled (a non-Delaunay background mesh): the nearest
        // centroid.
        let cen = |tv: &[u32; 4]| {
            let mut c = [0.0; 3];
            for &q in tv {
                for (ck, pk) in c.iter_mut().zip(self.points[q as usize]) {
                    *ck += 0.25 * pk;
                }
            }
            c
        };
        (0..n)
            .min_by(|&a, &b| {
                dist2(&cen(&self.tets[a as usize]), &x)
                    .total_cmp(&dist2(&cen(&self.tets[b as usize]), &x))
            })
            .unwrap_or(0)
    }
}

/// The sizing as the refinement uses it, on rescaled coordinates.
pub(super) struct Sizer {
    sizing: Sizing,
    /// Rescaling factor of the refinement's points.
    s: f64,
}

/// `√6 / 4`: circumradius of the regular tetrahedron of unit edge.
const CELL: f64 = 0.612_372_435_695_794_5;
/// `1 / √3`: circumradius of the equilateral triangle of unit edge.
const FACE: f64 = 0.577_350_269_189_625_8;

impl Sizer {
    pub(super) fn new(sizing: &Sizing, s: f64) -> Sizer {
        Sizer {
            sizing: sizing.clone(),
            s,
        }
    }

    /// The size at rescaled point `x`, rescaled (infinite: no constraint).
    fn h(&self, x: &P) -> f64 {
        self.sizing
            .size_at(x.map(|c| c / self.s))
            .map_or(f64::INFINITY, |h| h * self.s)
    }

    /// How much too big a cell is: `R / (0.612 h(c))` when above 1, else 0.
    pub(super) fn cell(&self, p: &[P; 4]) -> f64 {
        if self.sizing.is_none() {
            return 0.0;
        }
        let Some(c) = quality::circumcenter(p) else {
            return 0.0;
        };
        let r = dist2(&c, &p[0]).sqrt();
        let x = r / (CELL * self.h(&c));
        if x > 1.0 {
            x
        } else {
            0.0
        }
    }

    /// Is the subface `a b c` bigger than the size at its circumcentre?
    pub(super) fn face(&self, a: &P, b: &P, c: &P) -> bool {
        if self.sizing.is_none() {
            return false;
        }
        tri_circumcenter(a, b, c).is_some_and(|(x, r2)| r2.sqrt() > FACE * self.h(&x))
    }
}

/// Circumradius bound of a tetrahedron at size `h` (see the module
/// documentation): `√6/4 · h`.
///
/// ```
/// let b = delone::tet::refine::sizing::cell_radius_bound(1.0);
/// assert!((b - 6f64.sqrt() / 4.0).abs() < 1e-15);
/// ```
pub fn cell_radius_bound(h: f64) -> f64 {
    CELL * h
}
