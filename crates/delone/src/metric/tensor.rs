//! One metric tensor: a symmetric positive definite `D × D` matrix `M`
//! that measures a vector `e` as `√(eᵀ M e)`. A mesh is *unit* in a metric
//! field when its edges measure about 1: sizes `1/√λ` along the
//! eigenvectors, with `λ` the eigenvalues.
//!
//! Every operation goes through the eigen-decomposition (cyclic Jacobi
//! rotations: deterministic, accurate for the small matrices here):
//! log-Euclidean interpolation (`exp(Σ wᵢ log Mᵢ)`, Arsigny et al.), the
//! intersection of two metrics by simultaneous reduction (the largest
//! metric that both allow: the smaller size in every direction), bounds on
//! the sizes, and lengths of edges whose ends carry different metrics
//! (sizes varying geometrically along the edge).
#![allow(clippy::needless_range_loop)] // matrix code: indices address rows and columns of several matrices at once

use crate::error::MetricDefect;

/// A symmetric `D × D` matrix (full storage).
pub(crate) type Sym<const D: usize> = [[f64; D]; D];

/// Eigenvalues and eigenvectors of a symmetric matrix by cyclic Jacobi
/// rotations: `(λ, v)` with `v[i][k]` the `i`th component of the `k`th
/// eigenvector (unit, mutually orthogonal).
pub(crate) fn eigen<const D: usize>(mut a: Sym<D>) -> ([f64; D], Sym<D>) {
    let mut v = [[0.0; D]; D];
    for (i, r) in v.iter_mut().enumerate() {
        r[i] = 1.0;
    }
    let norm2: f64 = a.iter().flatten().map(|x| x * x).sum();
    for _sweep in 0..64 {
        let off: f64 = (0..D)
            .flat_map(|p| (p + 1..D).map(move |q| (p, q)))
            .map(|(p, q)| a[p][q] * a[p][q])
            .sum();
        if off <= 1e-32 * norm2 || off == 0.0 {
            break;
        }
        for p in 0..D {
            for q in p + 1..D {
                if a[p][q] == 0.0 {
                    continue;
                }
                let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                for k in 0..D {
                    let (akp, akq) = (a[k][p], a[k][q]);
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for k in 0..D {
                    let (apk, aqk) = (a[p][k], a[q][k]);
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for row in v.iter_mut() {
                    let (vp, vq) = (row[p], row[q]);
                    row[p] = c * vp - s * vq;
                    row[q] = s * vp + c * vq;
                }
            }
        }
    }
    let mut lambda = [0.0; D];
    for (i, l) in lambda.iter_mut().enumerate() {
        *l = a[i][i];
    }
    (lambda, v)
}

/// `v diag(λ) vᵀ`.
pub(crate) fn compose<const D: usize>(lambda: &[f64; D], v: &Sym<D>) -> Sym<D> {
    let mut m = [[0.0; D]; D];
    for i in 0..D {
        for j in i..D {
            let x: f64 = (0..D).map(|k| v[i][k] * lambda[k] * v[j][k]).sum();
            m[i][j] = x;
            m[j][i] = x;
        }
    }
    m
}

/// `f` applied to the eigenvalues.
fn map_eigen<const D: usize>(m: &Sym<D>, f: impl Fn(f64) -> f64) -> Sym<D> {
    let (mut l, v) = eigen(*m);
    for x in &mut l {
        *x = f(*x);
    }
    compose(&l, &v)
}

/// A metric tensor in `D` dimensions (2 or 3): symmetric positive
/// definite, with finite eigenvalues.
///
/// ```
/// use delone::metric::Metric;
/// // Sizes 0.1 along x and 1 along y.
/// let m = Metric::<2>::from_medit(&[100.0, 0.0, 1.0]).unwrap();
/// assert!((m.length([0.1, 0.0]) - 1.0).abs() < 1e-12);
/// assert!((m.length([0.0, 1.0]) - 1.0).abs() < 1e-12);
/// let s = m.sizes();
/// assert!((s[0] - 0.1).abs() < 1e-12 && (s[1] - 1.0).abs() < 1e-12);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Metric<const D: usize> {
    m: Sym<D>,
}

impl<const D: usize> Metric<D> {
    /// The isotropic metric of size `h` (> 0): `I / h²`.
    ///
    /// ```
    /// let m = delone::metric::Metric::<3>::isotropic(0.5);
    /// assert_eq!(m.length([0.5, 0.0, 0.0]), 1.0);
    /// ```
    pub fn isotropic(h: f64) -> Self {
        let mut m = [[0.0; D]; D];
        for (i, r) in m.iter_mut().enumerate() {
            r[i] = 1.0 / (h * h);
        }
        Metric { m }
    }

    /// A metric from a symmetric matrix (its upper triangle is read),
    /// checked finite and positive definite.
    ///
    /// # Errors
    /// [`MetricDefect::NotFinite`] or [`MetricDefect::NotPositiveDefinite`].
    ///
    /// ```
    /// use delone::metric::{Metric, MetricDefect};
    /// assert!(Metric::from_matrix([[2.0, 1.0], [1.0, 2.0]]).is_ok());
    /// assert_eq!(Metric::from_matrix([[1.0, 2.0], [2.0, 1.0]]).unwrap_err(), MetricDefect::NotPositiveDefinite);
    /// ```
    pub fn from_matrix(m: Sym<D>) -> Result<Self, MetricDefect> {
        let mut s = m;
        for i in 0..D {
            for j in 0..i {
                s[i][j] = s[j][i];
            }
        }
        if s.iter().flatten().any(|x| !x.is_finite()) {
            return Err(MetricDefect::NotFinite);
        }
        let (l, _) = eigen(s);
        if l.iter().any(|&x| x.is_nan() || x <= 0.0) {
            return Err(MetricDefect::NotPositiveDefinite);
        }
        Ok(Metric { m: s })
    }

    /// A metric from its components in Medit's `.sol` order: `m11 m12 m22`
    /// in 2D, `m11 m12 m22 m13 m23 m33` in 3D.
    ///
    /// # Errors
    /// A [`MetricDefect`].
    ///
    /// ```
    /// use delone::metric::Metric;
    /// let m = Metric::<3>::from_medit(&[1.0, 0.0, 4.0, 0.0, 0.0, 9.0]).unwrap();
    /// assert_eq!(m.matrix()[2][2], 9.0);
    /// assert_eq!(m.medit(), vec![1.0, 0.0, 4.0, 0.0, 0.0, 9.0]);
    /// ```
    pub fn from_medit(c: &[f64]) -> Result<Self, MetricDefect> {
        if c.len() != D * (D + 1) / 2 {
            return Err(MetricDefect::ComponentCount);
        }
        let mut m = [[0.0; D]; D];
        let mut k = 0;
        for j in 0..D {
            for i in 0..=j {
                m[i][j] = c[k];
                k += 1;
            }
        }
        Self::from_matrix(m)
    }

    /// The components in Medit's `.sol` order (see [`Metric::from_medit`]).
    pub fn medit(&self) -> Vec<f64> {
        let mut out = Vec::with_capacity(D * (D + 1) / 2);
        for j in 0..D {
            for i in 0..=j {
                out.push(self.m[i][j]);
            }
        }
        out
    }

    /// The matrix.
    pub fn matrix(&self) -> Sym<D> {
        self.m
    }

    /// Eigenvalues and unit eigenvectors (`v[i][k]`: component `i` of the
    /// `k`th vector).
    pub fn eigen(&self) -> ([f64; D], Sym<D>) {
        eigen(self.m)
    }

    /// The sizes `1/√λ`, smallest first.
    pub fn sizes(&self) -> [f64; D] {
        let (l, _) = self.eigen();
        let mut s = l.map(|x| 1.0 / x.sqrt());
        s.sort_by(f64::total_cmp);
        s
    }

    /// `det M`: `1/(h₁ ⋯ h_D)²`; `√det M` is the density of unit elements.
    pub fn det(&self) -> f64 {
        self.eigen().0.iter().product()
    }

    /// The length of `e` in the metric: `√(eᵀ M e)`.
    pub fn length(&self, e: [f64; D]) -> f64 {
        let mut s = 0.0;
        for i in 0..D {
            for j in 0..D {
                s += e[i] * self.m[i][j] * e[j];
            }
        }
        s.max(0.0).sqrt()
    }

    /// The metric with every size multiplied by `f` (> 0): `M / f²`.
    pub fn scaled(&self, f: f64) -> Self {
        Metric {
            m: self.m.map(|r| r.map(|x| x / (f * f))),
        }
    }

    /// Sizes clamped to `[hmin, hmax]` (eigenvalues to `[1/hmax², 1/hmin²]`).
    ///
    /// ```
    /// use delone::metric::Metric;
    /// let m = Metric::<2>::from_medit(&[1e6, 0.0, 1e-6]).unwrap().bounded(0.01, 10.0);
    /// let s = m.sizes();
    /// assert!((s[0] - 0.01).abs() < 1e-12 && (s[1] - 10.0).abs() < 1e-9);
    /// ```
    pub fn bounded(&self, hmin: f64, hmax: f64) -> Self {
        let (lo, hi) = (1.0 / (hmax * hmax), 1.0 / (hmin * hmin));
        Metric {
            m: map_eigen(&self.m, |x| x.clamp(lo, hi)),
        }
    }

    /// The intersection: the largest metric inside both unit balls, i.e.
    /// in every direction at most the smaller of the two sizes (simultaneous
    /// reduction through the Cholesky factor of `self`).
    ///
    /// ```
    /// use delone::metric::Metric;
    /// let a = Metric::<2>::from_medit(&[1.0, 0.0, 4.0]).unwrap();
    /// let b = Metric::<2>::from_medit(&[4.0, 0.0, 1.0]).unwrap();
    /// let c = a.intersect(&b).matrix();
    /// assert!((c[0][0] - 4.0).abs() < 1e-12 && (c[1][1] - 4.0).abs() < 1e-12 && c[0][1].abs() < 1e-12);
    /// ```
    pub fn intersect(&self, other: &Self) -> Self {
        // self = L Lᵀ; A = L⁻¹ other L⁻ᵀ = Q Σ Qᵀ; result L Q max(1, Σ) Qᵀ Lᵀ.
        let l = cholesky(&self.m);
        let li = lower_inverse(&l);
        let a = sandwich(&li, &other.m);
        let (mut s, q) = eigen(a);
        for x in &mut s {
            *x = x.max(1.0);
        }
        let inner = compose(&s, &q);
        let mut out = sandwich(&l, &inner);
        for i in 0..D {
            for j in 0..i {
                let x = 0.5 * (out[i][j] + out[j][i]);
                out[i][j] = x;
                out[j][i] = x;
            }
        }
        Metric { m: out }
    }

    /// Log-Euclidean interpolation `exp(Σ wᵢ log Mᵢ / Σ wᵢ)` of weighted
    /// metrics (weights ≥ 0, not all zero); `None` for an empty list or zero
    /// total weight.
    ///
    /// ```
    /// use delone::metric::Metric;
    /// // Halfway between sizes 1 and 4: size 2 (the geometric mean).
    /// let m = Metric::<2>::interpolate(&[(0.5, Metric::isotropic(1.0)), (0.5, Metric::isotropic(4.0))]).unwrap();
    /// assert!((m.sizes()[0] - 2.0).abs() < 1e-12);
    /// ```
    pub fn interpolate(items: &[(f64, Metric<D>)]) -> Option<Self> {
        let logs: Vec<(f64, Sym<D>)> = items.iter().map(|(w, m)| (*w, m.log())).collect();
        Self::from_logs(&logs)
    }

    /// The matrix logarithm of the metric: the term of [`Metric::interpolate`],
    /// kept per vertex where the same metric is interpolated many times.
    pub(crate) fn log(&self) -> Sym<D> {
        map_eigen(&self.m, f64::ln)
    }

    /// [`Metric::interpolate`] of metrics given by their logarithms
    /// ([`Metric::log`]), with the same result.
    pub(crate) fn from_logs(items: &[(f64, Sym<D>)]) -> Option<Self> {
        let total: f64 = items.iter().map(|x| x.0).sum();
        if items.is_empty() || total.is_nan() || total <= 0.0 {
            return None;
        }
        let mut acc = [[0.0; D]; D];
        for (w, lg) in items {
            for i in 0..D {
                for j in 0..D {
                    acc[i][j] += w / total * lg[i][j];
                }
            }
        }
        Some(Metric {
            m: map_eigen(&acc, f64::exp),
        })
    }

    /// The arithmetic mean of metrics (positive definite as a convex
    /// combination of positive definite matrices): the cheap element metric
    /// of the adaptation's quality tests, where the log-Euclidean
    /// [`Metric::interpolate`] would cost an eigendecomposition per corner.
    /// `None` for an empty list.
    pub(crate) fn mean(items: &[Metric<D>]) -> Option<Self> {
        let w = 1.0 / items.len() as f64;
        let mut acc = [[0.0; D]; D];
        for m in items {
            for i in 0..D {
                for j in 0..D {
                    acc[i][j] += w * m.m[i][j];
                }
            }
        }
        (!items.is_empty()).then_some(Metric { m: acc })
    }

    /// The length of the edge `e` from a vertex with metric `self` to one
    /// with metric `other`, the size varying geometrically along it:
    /// `(l_b − l_a) / ln(l_b / l_a)` with `l_a`, `l_b` its lengths in the
    /// two metrics.
    ///
    /// ```
    /// use delone::metric::Metric;
    /// let (a, b) = (Metric::<2>::isotropic(1.0), Metric::<2>::isotropic(0.5));
    /// let l = a.edge_length(&b, [1.0, 0.0]);
    /// assert!((l - 1.0 / 2f64.ln()).abs() < 1e-12);
    /// assert_eq!(a.edge_length(&a, [3.0, 0.0]), 3.0);
    /// ```
    pub fn edge_length(&self, other: &Self, e: [f64; D]) -> f64 {
        let (la, lb) = (self.length(e), other.length(e));
        let r = lb / la;
        if la.is_nan() || la <= 0.0 || (r - 1.0).abs() < 1e-6 {
            return 0.5 * (la + lb);
        }
        (lb - la) / r.ln()
    }

    /// The length of the edge `e` from a vertex with metric `self` to one
    /// with metric `other` (their logarithms `log_a`, `log_b`,
    /// [`Metric::log`]), the metric interpolated log-Euclidean along it:
    /// [`Metric::edge_length`] on each half, with the interpolated metric at
    /// the midpoint.
    ///
    /// When the two metrics commute (the same eigenvectors: only the sizes
    /// vary along the edge) the midpoint length is the geometric mean of the
    /// ends' and this is [`Metric::edge_length`] itself (returned as is).
    /// When the metric turns along the edge, [`Metric::edge_length`] takes
    /// the edge's length in each end metric as if it held halfway: the chord
    /// of a curved anisotropic layer, tangent to the layer at its middle and
    /// across it by its half-angle at each end, measures up to about twice
    /// its length through the interpolated field there.
    pub(crate) fn edge_length_turning(
        &self,
        other: &Self,
        log_a: &Sym<D>,
        log_b: &Sym<D>,
        e: [f64; D],
    ) -> f64 {
        // The commutator of the two logarithms, against their sizes.
        let (mut c, mut na, mut nb) = (0.0f64, 0.0f64, 0.0f64);
        for i in 0..D {
            for j in 0..D {
                let ab: f64 = (0..D).map(|k| log_a[i][k] * log_b[k][j]).sum();
                let ba: f64 = (0..D).map(|k| log_b[i][k] * log_a[k][j]).sum();
                c = c.max((ab - ba).abs());
                na = na.max(log_a[i][j].abs());
                nb = nb.max(log_b[i][j].abs());
            }
        }
        if c <= 1e-9 * na * nb {
            return self.edge_length(other, e);
        }
        let Some(mid) = Self::from_logs(&[(0.5, *log_a), (0.5, *log_b)]) else {
            return self.edge_length(other, e);
        };
        let h = e.map(|x| 0.5 * x);
        self.edge_length(&mid, h) + mid.edge_length(other, h)
    }
}

/// The Cholesky factor `L` (lower) of a positive definite matrix.
fn cholesky<const D: usize>(m: &Sym<D>) -> Sym<D> {
    let mut l = [[0.0; D]; D];
    for j in 0..D {
        let d = m[j][j] - (0..j).map(|k| l[j][k] * l[j][k]).sum::<f64>();
        l[j][j] = d.max(f64::MIN_POSITIVE).sqrt();
        for i in j + 1..D {
            l[i][j] = (m[i][j] - (0..j).map(|k| l[i][k] * l[j][k]).sum::<f64>()) / l[j][j];
        }
    }
    l
}

/// The inverse of a lower triangular matrix.
fn lower_inverse<const D: usize>(l: &Sym<D>) -> Sym<D> {
    let mut x = [[0.0; D]; D];
    for c in 0..D {
        for i in c..D {
            let rhs = if i == c { 1.0 } else { 0.0 };
            let s: f64 = (c..i).map(|k| l[i][k] * x[k][c]).sum();
            x[i][c] = (rhs - s) / l[i][i];
        }
    }
    x
}

/// `a m aᵀ`.
fn sandwich<const D: usize>(a: &Sym<D>, m: &Sym<D>) -> Sym<D> {
    let mut am = [[0.0; D]; D];
    for i in 0..D {
        for j in 0..D {
            am[i][j] = (0..D).map(|k| a[i][k] * m[k][j]).sum();
        }
    }
    let mut out = [[0.0; D]; D];
    for i in 0..D {
        for j in 0..D {
            out[i][j] = (0..D).map(|k| am[i][k] * a[j][k]).sum();
        }
    }
    out
}

/// Volume of the regular simplex of unit edges in `d` dimensions.
fn unit_simplex_volume(d: usize) -> f64 {
    match d {
        2 => 3f64.sqrt() / 4.0,
        _ => 1.0 / (6.0 * 2f64.sqrt()),
    }
}

/// The signed volume of a simplex (`D + 1` corners).
pub(crate) fn simplex_volume<const D: usize>(p: &[[f64; D]]) -> f64 {
    let at = |k: usize| [p[k][0], p[k][1], if D > 2 { p[k][2] } else { 0.0 }];
    match D {
        2 => {
            let e = |k: usize, i: usize| p[k][i] - p[0][i];
            0.5 * (e(1, 0) * e(2, 1) - e(1, 1) * e(2, 0))
        }
        _ => crate::tet::quality::volume_raw(&[at(0), at(1), at(2), at(3)]),
    }
}

/// The mean ratio of a simplex (`D + 1` corners, `D` = 2 or 3) in the
/// constant metric `m`: `c · vol_M^{2/D} / Σ l_M²`, normalised to 1 for the
/// regular simplex of the metric and ≤ 1 for every other; 0 for a flat
/// simplex (and for a slice that does not hold `D + 1` corners), negative
/// for an inverted one.
///
/// ```
/// use delone::metric::{mean_ratio, Metric};
/// let eq = [[0.0, 0.0], [1.0, 0.0], [0.5, 3f64.sqrt() / 2.0]];
/// assert!((mean_ratio(&eq, &Metric::isotropic(1.0)) - 1.0).abs() < 1e-12);
/// // Squashed 10× along y, it is regular in the metric that stretches y 10×.
/// let flat = [[0.0, 0.0], [1.0, 0.0], [0.5, 3f64.sqrt() / 20.0]];
/// let m = Metric::<2>::from_medit(&[1.0, 0.0, 100.0]).unwrap();
/// assert!((mean_ratio(&flat, &m) - 1.0).abs() < 1e-12);
/// ```
pub fn mean_ratio<const D: usize>(p: &[[f64; D]], m: &Metric<D>) -> f64 {
    if p.len() != D + 1 || !(2..=3).contains(&D) {
        return 0.0;
    }
    if D == 3 {
        let (mut q, mut a) = ([[0.0; 3]; 4], [[0.0; 3]; 3]);
        for i in 0..D {
            for k in 0..4 {
                q[k][i] = p[k][i];
            }
            for j in 0..D {
                a[i][j] = m.m[i][j];
            }
        }
        return tet_mean_ratio(&q, &a);
    }
    // In 2D the eigenvalue product, which the 2D adaptation's results rest
    // on.
    let vol = simplex_volume::<D>(p) * m.det().sqrt();
    let mut sum = 0.0;
    for i in 0..=D {
        for j in i + 1..=D {
            let mut e = [0.0; D];
            for (k, x) in e.iter_mut().enumerate() {
                *x = p[j][k] - p[i][k];
            }
            let l = m.length(e);
            sum += l * l;
        }
    }
    if sum.is_nan() || sum <= 0.0 {
        return 0.0;
    }
    let d = 2.0 / D as f64;
    let c = (D * (D + 1) / 2) as f64 / unit_simplex_volume(D).powf(d);
    vol.signum() * c * vol.abs().powf(d) / sum
}

/// [`mean_ratio`] of tetrahedron `p` in the metric of the symmetric matrix
/// `a`: the determinant in closed form, the squared lengths as quadratic
/// forms `eᵀ a e` (not squares of roots) and `|vol|^{2/3}` by [`cbrt`], since
/// the adaptation evaluates this for every candidate tetrahedron.
fn tet_mean_ratio(p: &[[f64; 3]; 4], a: &Sym<3>) -> f64 {
    let det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
        - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
        + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    let vol = crate::tet::quality::volume_raw(p) * det.sqrt();
    let mut sum = 0.0;
    for i in 0..4 {
        for j in i + 1..4 {
            let e = [0, 1, 2].map(|k| p[j][k] - p[i][k]);
            sum += a[0][0] * e[0] * e[0]
                + a[1][1] * e[1] * e[1]
                + a[2][2] * e[2] * e[2]
                + 2.0 * (a[0][1] * e[0] * e[1] + a[0][2] * e[0] * e[2] + a[1][2] * e[1] * e[2]);
        }
    }
    if sum.is_nan() || sum <= 0.0 {
        return 0.0;
    }
    // 6 / (1 / (6√2))^{2/3} = 6 · 72^{1/3}.
    vol.signum() * 24.961_005_876_622_85 * cbrt(vol * vol) / sum
}

/// The quality of the adaptation's tetrahedra: [`mean_ratio`] of
/// tetrahedron `p` in [`Metric::mean`] of its corners' metrics `m`, that
/// mean summed over the six distinct entries of the symmetric tensors
/// without copying them (the same value).
pub(crate) fn tet_quality(p: &[[f64; 3]; 4], m: [&Metric<3>; 4]) -> f64 {
    let mut a = [[0.0; 3]; 3];
    for (i, j) in [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)] {
        let mut s = 0.0;
        for x in m {
            s += 0.25 * x.m[i][j];
        }
        a[i][j] = s;
        a[j][i] = s;
    }
    tet_mean_ratio(p, &a)
}

/// The cube root of `x` ≥ 0 to a few units in the last place: three
/// Halley steps `y ← y (y³ + 2x) / (2y³ + x)` from a first guess that
/// divides the exponent by three in the bits (the error falls from a few
/// percent to below the rounding). Several times cheaper than the
/// correctly rounded `f64::cbrt`, which dominated the 3D mean ratio;
/// zero, subnormal and non-finite `x` go to `f64::cbrt`.
fn cbrt(x: f64) -> f64 {
    if !(f64::MIN_POSITIVE..f64::INFINITY).contains(&x) {
        return x.cbrt();
    }
    let mut y = f64::from_bits(x.to_bits() / 3 + (0x2A9F_7893_u64 << 32));
    for _ in 0..3 {
        let y3 = y * y * y;
        y *= (y3 + 2.0 * x) / (2.0 * y3 + x);
    }
    y
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rand_spd3(seed: u64) -> Sym<3> {
        let mut s = seed;
        let mut r = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        };
        let a = [[r(), r(), r()], [r(), r(), r()], [r(), r(), r()]];
        let mut m = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                m[i][j] =
                    (0..3).map(|k| a[i][k] * a[j][k]).sum::<f64>() + if i == j { 0.1 } else { 0.0 };
            }
        }
        m
    }

    /// The length of `e` through the log-Euclidean interpolation of `a` and
    /// `b` along it, by the midpoint rule on `n` pieces.
    fn interpolated_length(a: &Metric<2>, b: &Metric<2>, e: [f64; 2], n: usize) -> f64 {
        let (la, lb) = (a.log(), b.log());
        (0..n)
            .map(|k| {
                let t = (k as f64 + 0.5) / n as f64;
                let m = Metric::from_logs(&[(1.0 - t, la), (t, lb)]).unwrap();
                m.length(e) / n as f64
            })
            .sum()
    }

    /// A layer of size `hn` across the unit normal at angle `theta`, 0.1
    /// along it.
    fn layer(theta: f64, hn: f64) -> Metric<2> {
        let (c, s) = (theta.cos(), theta.sin());
        Metric::from_matrix(compose(&[1.0 / (hn * hn), 100.0], &[[c, -s], [s, c]])).unwrap()
    }

    #[test]
    fn turning_edge_length_follows_the_interpolated_metric() {
        // Metrics with the same eigenvectors: the geometric formula itself.
        let (a, b) = (layer(0.0, 0.001), layer(0.0, 0.05));
        for e in [[0.01, 0.0], [0.003, 0.07], [0.0, 0.2]] {
            assert_eq!(
                a.edge_length_turning(&b, &a.log(), &b.log(), e),
                a.edge_length(&b, e)
            );
        }
        // A chord (0.05 long) of a circular layer of radius 0.5 (size about
        // 0.001 across it, 0.1 along it) over 0.1 rad: its ends' normals
        // turn by 0.1 rad and the chord crosses each by half of that. With
        // sizes 0.001 at both ends the geometric formula measures it 2.55,
        // the interpolated field 1.39.
        for (h0, h1) in [(0.001, 0.001), (0.001, 0.003), (0.002, 0.0015)] {
            let (t0, t1) = (0.3f64, 0.4f64);
            let p0 = [0.5 * t0.cos(), 0.5 * t0.sin()];
            let p1 = [0.5 * t1.cos(), 0.5 * t1.sin()];
            let e = [p1[0] - p0[0], p1[1] - p0[1]];
            let (a, b) = (layer(t0, h0), layer(t1, h1));
            let exact = interpolated_length(&a, &b, e, 4000);
            let turning = a.edge_length_turning(&b, &a.log(), &b.log(), e);
            let ends = a.edge_length(&b, e);
            assert!(
                (turning - exact).abs() < 0.25 * (ends - exact).abs(),
                "{h0} {h1}: turning {turning}, ends {ends}, interpolated {exact}"
            );
            assert!(turning < 0.7 * ends, "{turning} {ends}");
        }
    }

    #[test]
    fn eigen_reconstructs_and_is_orthonormal() {
        for seed in 0..50 {
            let m = rand_spd3(seed);
            let (l, v) = eigen(m);
            let back = compose(&l, &v);
            for i in 0..3 {
                for j in 0..3 {
                    assert!((back[i][j] - m[i][j]).abs() < 1e-12, "seed {seed}");
                    let dot: f64 = (0..3).map(|k| v[k][i] * v[k][j]).sum();
                    assert!((dot - if i == j { 1.0 } else { 0.0 }).abs() < 1e-12);
                }
            }
        }
    }

    #[test]
    fn intersection_is_inside_both_and_the_largest_such() {
        for seed in 0..50 {
            let a = Metric::from_matrix(rand_spd3(seed)).unwrap();
            let b = Metric::from_matrix(rand_spd3(seed + 1000)).unwrap();
            let c = a.intersect(&b);
            // c ≥ a and c ≥ b (every direction measures at least as long).
            for k in 0..200 {
                let t = k as f64 * 0.1;
                let e = [
                    t.cos() * (2.0 * t).sin(),
                    t.sin() * (2.0 * t).sin(),
                    (2.0 * t).cos(),
                ];
                let (la, lb, lc) = (a.length(e), b.length(e), c.length(e));
                assert!(
                    lc >= la.max(lb) * (1.0 - 1e-9),
                    "seed {seed}: {lc} < max({la}, {lb})"
                );
            }
            // Symmetric in its arguments up to rounding.
            let d = b.intersect(&a);
            for i in 0..3 {
                for j in 0..3 {
                    assert!((c.m[i][j] - d.m[i][j]).abs() < 1e-9 * (1.0 + c.m[i][j].abs()));
                }
            }
            // Intersection with itself changes nothing.
            let s = a.intersect(&a);
            assert!((0..3)
                .all(|i| (0..3)
                    .all(|j| (s.m[i][j] - a.m[i][j]).abs() < 1e-10 * (1.0 + a.m[i][j].abs()))));
        }
    }

    #[test]
    fn interpolation_of_one_metric_is_itself_and_medit_round_trips() {
        for seed in 0..20 {
            let a = Metric::from_matrix(rand_spd3(seed)).unwrap();
            let i = Metric::interpolate(&[(0.3, a), (0.7, a)]).unwrap();
            assert!((0..3)
                .all(|r| (0..3)
                    .all(|c| (i.m[r][c] - a.m[r][c]).abs() < 1e-10 * (1.0 + a.m[r][c].abs()))));
            assert_eq!(Metric::<3>::from_medit(&a.medit()).unwrap(), a);
        }
        assert!(Metric::<2>::interpolate(&[]).is_none());
        assert_eq!(
            Metric::<2>::from_medit(&[1.0, 0.0]).unwrap_err(),
            MetricDefect::ComponentCount
        );
        assert_eq!(
            Metric::<2>::from_medit(&[1.0, f64::NAN, 1.0]).unwrap_err(),
            MetricDefect::NotFinite
        );
        assert_eq!(
            Metric::<2>::from_medit(&[0.0, 0.0, 1.0]).unwrap_err(),
            MetricDefect::NotPositiveDefinite
        );
    }

    #[test]
    fn mean_ratio_of_the_regular_tetrahedron_is_one_and_sign_follows_orientation() {
        let t = [
            [1.0, 1.0, 1.0],
            [1.0, -1.0, -1.0],
            [-1.0, 1.0, -1.0],
            [-1.0, -1.0, 1.0],
        ];
        let q = mean_ratio(&t, &Metric::isotropic(1.0));
        assert!((q.abs() - 1.0).abs() < 1e-12);
        let u = [t[1], t[0], t[2], t[3]];
        assert!((mean_ratio(&u, &Metric::isotropic(1.0)) + q).abs() < 1e-12);
        let flat = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
        ];
        assert_eq!(mean_ratio(&flat, &Metric::isotropic(1.0)), 0.0);
    }

    #[test]
    fn the_fast_cube_root_is_within_a_few_ulps() {
        let mut x = 1e-300;
        while x < 1e300 {
            for f in [1.0, 1.37, 2.9, 7.77] {
                let (y, want) = (cbrt(x * f), (x * f).cbrt());
                assert!(
                    (y - want).abs() <= 4.0 * f64::EPSILON * want,
                    "{} {y} {want}",
                    x * f
                );
            }
            x *= 3.1;
        }
        assert_eq!(cbrt(0.0), 0.0);
        assert_eq!(cbrt(8.0), 2.0);
    }
}
