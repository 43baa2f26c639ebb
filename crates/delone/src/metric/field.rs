//! Metric fields on a simplicial mesh: a solution's Hessian recovered at
//! the vertices, the metric that minimises the interpolation error for a
//! given complexity (Loseille & Alauzet 2011, *Continuous mesh framework*),
//! and size gradation along the edges (Alauzet 2010).
//!
//! Recovery fits `u(x) ≈ u(xᵥ) + g·d + ½ dᵀ H d` (`d = x − xᵥ`) by least
//! squares over the vertex's patch: its neighbours, grown ring by ring
//! until the fit is determined with some redundancy (`2 × unknowns`
//! points), solved by Householder QR on coordinates scaled by the patch
//! radius. Quadratic fields are recovered exactly (up to rounding).
#![allow(clippy::needless_range_loop)] // matrix code: indices address rows and columns of several matrices at once

use super::tensor::{compose, eigen, simplex_volume, Metric, Sym};

/// The vertex neighbours of a simplicial mesh (`K` corners per element,
/// checked by [`check_mesh`]), sorted.
fn neighbours<const K: usize>(n: usize, elements: &[[u32; K]]) -> Vec<Vec<u32>> {
    let mut adj = vec![Vec::new(); n];
    for e in elements {
        for &a in e {
            adj[a as usize].extend(e.iter().copied().filter(|&b| b != a));
        }
    }
    for l in &mut adj {
        l.sort_unstable();
        l.dedup();
    }
    adj
}

/// Checks that elements have `K = D + 1` corners naming points below
/// `n`, and that a per-point array (`what`, of length `len`) has one entry
/// per point.
fn check_mesh<const D: usize, const K: usize>(
    n: usize,
    elements: &[[u32; K]],
    len: usize,
    what: &str,
) -> Result<(), crate::Error> {
    let bad = |reason: String| Err(crate::Error::InconsistentMesh { reason });
    if K != D + 1 {
        return bad(format!("elements of {K} corners in {D} dimensions"));
    }
    if len != n {
        return bad(format!("{len} {what} for {n} points"));
    }
    if let Some((i, v)) = elements
        .iter()
        .enumerate()
        .find_map(|(i, e)| e.iter().find(|&&v| v as usize >= n).map(|&v| (i, v)))
    {
        return bad(format!(
            "element {i} names point {v}, but there are {n} points"
        ));
    }
    Ok(())
}

/// The edges of a simplicial mesh, each once as `[a, b]` with `a < b`,
/// sorted.
///
/// ```
/// let e = delone::metric::edges(&[[0u32, 1, 2], [2, 1, 3]]);
/// assert_eq!(e, vec![[0, 1], [0, 2], [1, 2], [1, 3], [2, 3]]);
/// ```
pub fn edges<const K: usize>(elements: &[[u32; K]]) -> Vec<[u32; 2]> {
    // Each edge as one word, so that the keys sort as integers.
    let mut e: Vec<u64> = Vec::with_capacity(elements.len() * K * (K - 1) / 2);
    for t in elements {
        for i in 0..K {
            for j in i + 1..K {
                e.push((u64::from(t[i].min(t[j])) << 32) | u64::from(t[i].max(t[j])));
            }
        }
    }
    e.sort_unstable();
    e.dedup();
    e.into_iter()
        .map(|k| [(k >> 32) as u32, k as u32])
        .collect()
}

/// Least squares `min |A x − b|` by Householder QR (`A`: `rows × cols`,
/// row-major). `None` when a column is (numerically) dependent.
fn least_squares(a: &mut [f64], b: &mut [f64], rows: usize, cols: usize) -> Option<Vec<f64>> {
    let scale = a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    for k in 0..cols {
        let norm = (k..rows)
            .map(|i| a[i * cols + k] * a[i * cols + k])
            .sum::<f64>()
            .sqrt();
        if norm.is_nan() || norm <= 1e-10 * scale {
            return None;
        }
        let alpha = if a[k * cols + k] > 0.0 { -norm } else { norm };
        let mut v: Vec<f64> = (k..rows).map(|i| a[i * cols + k]).collect();
        v[0] -= alpha;
        let vv: f64 = v.iter().map(|x| x * x).sum();
        if vv == 0.0 {
            continue;
        }
        for j in k..cols {
            let s: f64 = (k..rows).map(|i| v[i - k] * a[i * cols + j]).sum::<f64>() * 2.0 / vv;
            for i in k..rows {
                a[i * cols + j] -= s * v[i - k];
            }
        }
        let s: f64 = (k..rows).map(|i| v[i - k] * b[i]).sum::<f64>() * 2.0 / vv;
        for i in k..rows {
            b[i] -= s * v[i - k];
        }
    }
    let mut x = vec![0.0; cols];
    for k in (0..cols).rev() {
        let s: f64 = (k + 1..cols).map(|j| a[k * cols + j] * x[j]).sum();
        x[k] = (b[k] - s) / a[k * cols + k];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// The Hessian of a scalar field at every vertex, recovered by a quadratic
/// least-squares fit over the vertex's patch (see the module docs). A
/// vertex whose patch cannot determine a fit (too few or degenerate
/// neighbours after 3 rings) gets the zero matrix. `K` must be `D + 1`.
///
/// # Errors
/// [`crate::Error::InconsistentMesh`] naming the element or array that does
/// not fit the points.
///
/// ```
/// use delone::metric::hessians;
/// // u = x² + 3xy on a small fan: exact for a quadratic.
/// let pts = [[0.0, 0.0], [1.0, 0.0], [0.5, 0.9], [-0.5, 0.8], [-1.0, 0.1], [-0.4, -0.9], [0.6, -0.8]];
/// let tris: Vec<[u32; 3]> = (1..7).map(|i| [0, i, i % 6 + 1]).collect();
/// let u: Vec<f64> = pts.iter().map(|p| p[0] * p[0] + 3.0 * p[0] * p[1]).collect();
/// let h = hessians(&pts, &tris, &u).unwrap();
/// assert!((h[0][0][0] - 2.0).abs() < 1e-9 && (h[0][0][1] - 3.0).abs() < 1e-9 && h[0][1][1].abs() < 1e-9);
/// ```
pub fn hessians<const D: usize, const K: usize>(
    points: &[[f64; D]],
    elements: &[[u32; K]],
    values: &[f64],
) -> Result<Vec<Sym<D>>, crate::Error> {
    check_mesh::<D, K>(points.len(), elements, values.len(), "values")?;
    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
        return Err(crate::Error::InconsistentMesh {
            reason: format!("value {i} is not finite"),
        });
    }
    let adj = neighbours(points.len(), elements);
    let nh = D * (D + 1) / 2;
    let cols = D + nh;
    let mut out = Vec::with_capacity(points.len());
    let mut patch: Vec<u32> = Vec::new();
    let mut seen: Vec<u32> = vec![u32::MAX; points.len()];
    for (v, p) in points.iter().enumerate() {
        patch.clear();
        patch.push(v as u32);
        seen[v] = v as u32;
        let mut start = 0;
        let mut h = [[0.0; D]; D];
        for ring in 0..RINGS {
            let end = patch.len();
            for k in start..end {
                for &w in &adj[patch[k] as usize] {
                    if seen[w as usize] != v as u32 {
                        seen[w as usize] = v as u32;
                        patch.push(w);
                    }
                }
            }
            start = end;
            // Grow while the fit is short of redundancy and the last ring
            // added vertices; the last ring fits with what it has.
            if patch.len() - 1 < 2 * cols && start < patch.len() && ring + 1 < RINGS {
                continue;
            }
            let rows = patch.len() - 1;
            if rows < cols {
                break;
            }
            let r = patch[1..]
                .iter()
                .map(|&w| {
                    (0..D)
                        .map(|i| (points[w as usize][i] - p[i]).powi(2))
                        .sum::<f64>()
                })
                .fold(0.0f64, f64::max)
                .sqrt();
            if r.is_nan() || r <= 0.0 {
                break;
            }
            let mut a = vec![0.0; rows * cols];
            let mut b = vec![0.0; rows];
            for (row, &w) in patch[1..].iter().enumerate() {
                let d: Vec<f64> = (0..D).map(|i| (points[w as usize][i] - p[i]) / r).collect();
                let line = &mut a[row * cols..(row + 1) * cols];
                line[..D].copy_from_slice(&d);
                let mut c = D;
                for i in 0..D {
                    for j in i..D {
                        line[c] = if i == j {
                            0.5 * d[i] * d[i]
                        } else {
                            d[i] * d[j]
                        };
                        c += 1;
                    }
                }
                b[row] = values[w as usize] - values[v];
            }
            if let Some(x) = least_squares(&mut a, &mut b, rows, cols) {
                let mut c = D;
                for i in 0..D {
                    for j in i..D {
                        h[i][j] = x[c] / (r * r);
                        h[j][i] = h[i][j];
                        c += 1;
                    }
                }
                break;
            }
        }
        out.push(h);
    }
    Ok(out)
}

/// Most rings of neighbours in a vertex's fitting patch.
const RINGS: usize = 3;

/// The interpolation error constant of P1 elements (`‖u − Πu‖∞ ≤ c ·
/// max eᵀ|H|e` over the element's edges): 2/9 in 2D, 9/32 in 3D.
fn error_constant(d: usize) -> f64 {
    if d == 2 {
        2.0 / 9.0
    } else {
        9.0 / 32.0
    }
}

/// What a metric built from Hessians aims at.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Target {
    /// The metric's complexity `C = ∫ √det M` (the continuous counterpart
    /// of the number of vertices: a mesh unit in the metric has about
    /// `C / (√3/2)` vertices in 2D and `C / 0.77` in 3D), with the error
    /// measured in the L^p norm `p` (≥ 1; 2 is usual). Optimal for the
    /// interpolation error at that complexity (Loseille & Alauzet 2011).
    Complexity {
        /// `C` (> 0).
        complexity: f64,
        /// The norm's exponent `p` (≥ 1, finite).
        p: f64,
    },
    /// An interpolation error of at most `error` (> 0) in the L^∞ norm:
    /// `M = c |H| / error` with the P1 error constant `c`.
    Error(f64),
}

/// The complexity `∫ √det M` of a metric field given at the vertices,
/// by the vertex average on each element (`K = D + 1` corners).
///
/// # Errors
/// [`crate::Error::InconsistentMesh`] naming the element or array that does
/// not fit the points.
///
/// ```
/// use delone::metric::{complexity, Metric};
/// let pts = [[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]];
/// let m = vec![Metric::isotropic(0.5); 3];
/// assert!((complexity(&pts, &[[0, 1, 2]], &m).unwrap() - 8.0).abs() < 1e-12);
/// ```
pub fn complexity<const D: usize, const K: usize>(
    points: &[[f64; D]],
    elements: &[[u32; K]],
    metrics: &[Metric<D>],
) -> Result<f64, crate::Error> {
    check_mesh::<D, K>(points.len(), elements, metrics.len(), "metrics")?;
    let dens: Vec<f64> = metrics.iter().map(|m| m.det().sqrt()).collect();
    Ok(element_integral(points, elements, &dens))
}

fn element_integral<const D: usize, const K: usize>(
    points: &[[f64; D]],
    elements: &[[u32; K]],
    f: &[f64],
) -> f64 {
    elements
        .iter()
        .map(|e| {
            let c: Vec<[f64; D]> = e.iter().map(|&v| points[v as usize]).collect();
            simplex_volume::<D>(&c).abs() * e.iter().map(|&v| f[v as usize]).sum::<f64>() / K as f64
        })
        .sum()
}

/// The isotropic metric of the mesh's own sizes, the one MMG adapts to
/// when no metric is given: each vertex's size is the mean length of its
/// incident edges (a vertex on no element gets the mean over all edges),
/// clamped to `[hmin, hmax]` (`0` and `f64::INFINITY` for no bound).
///
/// # Errors
/// [`crate::Error::InvalidBound`] for `hmin` negative or `hmax` below it;
/// [`crate::Error::InconsistentMesh`] naming an element that names a
/// missing point (or for `K ≠ D + 1`).
///
/// ```
/// use delone::metric::metric_from_mesh;
/// let pts = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]];
/// let tris = [[0u32, 1, 2], [1, 3, 2]];
/// let m = metric_from_mesh(&pts, &tris, 0.0, f64::INFINITY).unwrap();
/// // Vertex 0: edges of length 1 and 1.
/// assert!((m[0].sizes()[0] - 1.0).abs() < 1e-12);
/// // Vertex 1: lengths 1, 1 and √2; bounded by hmax = 1 it gets 1.
/// assert!((m[1].sizes()[0] - (2.0 + 2f64.sqrt()) / 3.0).abs() < 1e-12);
/// let b = metric_from_mesh(&pts, &tris, 0.0, 1.0).unwrap();
/// assert!((b[1].sizes()[0] - 1.0).abs() < 1e-12);
/// ```
pub fn metric_from_mesh<const D: usize, const K: usize>(
    points: &[[f64; D]],
    elements: &[[u32; K]],
    hmin: f64,
    hmax: f64,
) -> Result<Vec<Metric<D>>, crate::Error> {
    let bad = |option: &'static str, value: f64| crate::Error::InvalidBound {
        option,
        value,
        reason: "must be a number with 0 ≤ hmin ≤ hmax",
    };
    if !(hmin >= 0.0 && hmin.is_finite()) {
        return Err(bad("-hmin", hmin));
    }
    if hmax.is_nan() || hmax < hmin {
        return Err(bad("-hmax", hmax));
    }
    check_mesh::<D, K>(points.len(), elements, points.len(), "points")?;
    let mut sum = vec![(0.0, 0u32); points.len()];
    let (mut total, mut count) = (0.0, 0.0);
    for [a, b] in edges(elements) {
        let (p, q) = (points[a as usize], points[b as usize]);
        let l = (0..D).map(|k| (p[k] - q[k]).powi(2)).sum::<f64>().sqrt();
        for v in [a, b] {
            sum[v as usize].0 += l;
            sum[v as usize].1 += 1;
        }
        total += l;
        count += 1.0;
    }
    let fallback = if total > 0.0 { total / count } else { 1.0 };
    Ok(sum
        .iter()
        .map(|&(s, n)| {
            let h = s / f64::from(n.max(1));
            let h = if h > 0.0 && h.is_finite() {
                h
            } else {
                fallback
            };
            Metric::isotropic(h.clamp(hmin, hmax))
        })
        .collect())
}

/// The metric at every vertex from the field's Hessians (see [`hessians`]):
/// `|H|` (absolute eigenvalues) scaled for the [`Target`], its sizes
/// clamped to `[hmin, hmax]` (so a direction without curvature gets
/// `hmax`). `K` must be `D + 1`.
///
/// # Errors
/// [`crate::Error::InvalidBound`] for a target (`-complexity`, `-p`,
/// `-err`), `-hmin` or `-hmax` out of range;
/// [`crate::Error::InconsistentMesh`] naming the element or array that does
/// not fit the points.
///
/// ```
/// use delone::metric::{complexity, metric_from_hessians, Target};
/// let pts = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]];
/// let tris = [[0u32, 1, 2], [1, 3, 2]];
/// let h = vec![[[2.0, 0.0], [0.0, 0.5]]; 4];
/// let t = Target::Complexity { complexity: 100.0, p: 2.0 };
/// let m = metric_from_hessians(&pts, &tris, &h, t, 1e-6, 1e6).unwrap();
/// assert!((complexity(&pts, &tris, &m).unwrap() - 100.0).abs() < 1e-9);
/// ```
pub fn metric_from_hessians<const D: usize, const K: usize>(
    points: &[[f64; D]],
    elements: &[[u32; K]],
    hessians: &[Sym<D>],
    target: Target,
    hmin: f64,
    hmax: f64,
) -> Result<Vec<Metric<D>>, crate::Error> {
    let bound = |name: &'static str, value: f64, ok: bool| {
        if ok {
            Ok(())
        } else {
            Err(crate::Error::InvalidBound {
                option: name,
                value,
                reason: "must be a positive finite number (hmin ≤ hmax; p ≥ 1)",
            })
        }
    };
    bound("-hmin", hmin, hmin > 0.0 && hmin.is_finite())?;
    bound("-hmax", hmax, hmax >= hmin && hmax.is_finite())?;
    match target {
        Target::Complexity { complexity, p } => {
            bound(
                "complexity",
                complexity,
                complexity > 0.0 && complexity.is_finite(),
            )?;
            bound("-p", p, (1.0..f64::INFINITY).contains(&p))?;
        }
        Target::Error(e) => bound("-err", e, e > 0.0 && e.is_finite())?,
    }
    check_mesh::<D, K>(points.len(), elements, hessians.len(), "Hessians")?;
    let abs: Vec<([f64; D], Sym<D>)> = hessians
        .iter()
        .map(|h| {
            let (l, v) = eigen(*h);
            (l.map(f64::abs), v)
        })
        .collect();
    let dd = D as f64;
    // Eigenvalues scaled for the target, then clamped to the size bounds.
    let scaled: Vec<([f64; D], Sym<D>)> = match target {
        Target::Error(e) => {
            let c = error_constant(D) / e;
            abs.into_iter()
                .map(|(l, v)| (l.map(|x| c * x), v))
                .collect()
        }
        Target::Complexity { complexity, p } => {
            // A flat direction would make the determinant 0: floor the
            // eigenvalues at 1e-12 of the field's largest (a field without
            // curvature anywhere gets a uniform metric).
            let top = abs
                .iter()
                .flat_map(|(l, _)| l.iter())
                .fold(0.0f64, |m, &x| m.max(x));
            let floor = if top > 0.0 { top * 1e-12 } else { 1.0 };
            let abs: Vec<([f64; D], Sym<D>)> = abs
                .into_iter()
                .map(|(l, v)| (l.map(|x| x.max(floor)), v))
                .collect();
            let det: Vec<f64> = abs.iter().map(|(l, _)| l.iter().product()).collect();
            let f: Vec<f64> = det.iter().map(|d| d.powf(p / (2.0 * p + dd))).collect();
            let integral = element_integral(points, elements, &f);
            if integral.is_nan() || integral <= 0.0 {
                return Err(crate::Error::InconsistentMesh {
                    reason: "the elements have no volume".into(),
                });
            }
            let global = (complexity / integral).powf(2.0 / dd);
            abs.into_iter()
                .zip(&det)
                .map(|((l, v), d)| {
                    let s = global * d.powf(-1.0 / (2.0 * p + dd));
                    (l.map(|x| s * x), v)
                })
                .collect()
        }
    };
    let (lo, hi) = (1.0 / (hmax * hmax), 1.0 / (hmin * hmin));
    scaled
        .into_iter()
        .enumerate()
        .map(|(i, (l, v))| {
            Metric::from_matrix(compose(&l.map(|x| x.clamp(lo, hi)), &v)).map_err(|_| {
                crate::Error::InconsistentMesh {
                    reason: format!("the metric at vertex {i} is not finite"),
                }
            })
        })
        .collect()
}

/// Size gradation: along every edge `pq`, the metric at `q` is intersected
/// with the metric of `p` grown linearly with the distance
/// (`M_p / (1 + (β − 1) l_p(pq))²`), so sizes grow by at most a factor of
/// about `β` (`hgrad`, > 1) per unit edge; repeated until nothing changes
/// by more than 1e-6 (at most 100 passes over the edges). Returns the
/// number of passes made.
///
/// ```
/// use delone::metric::{gradate, Metric};
/// let pts = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]];
/// let mut m = vec![Metric::<2>::isotropic(0.1), Metric::isotropic(10.0), Metric::isotropic(10.0)];
/// gradate(&pts, &[[0, 1], [1, 2]], &mut m, 1.5);
/// // From 0.1 at x = 0, sizes grow by at most (1 + 0.5 · 1/0.1)·0.1 = 0.6 at x = 1.
/// assert!((m[1].sizes()[0] - 0.6).abs() < 1e-9);
/// ```
pub fn gradate<const D: usize>(
    points: &[[f64; D]],
    edges: &[[u32; 2]],
    metrics: &mut [Metric<D>],
    beta: f64,
) -> usize {
    if beta.is_nan() || beta <= 1.0 || beta.is_infinite() {
        return 0;
    }
    for pass in 1..=100 {
        let mut changed = false;
        for &[a, b] in edges {
            let (a, b) = (a as usize, b as usize);
            if a.max(b) >= metrics.len().min(points.len()) {
                continue;
            }
            let mut e = [0.0; D];
            for (k, x) in e.iter_mut().enumerate() {
                *x = points[b][k] - points[a][k];
            }
            for (p, q) in [(a, b), (b, a)] {
                let l = metrics[p].length(e);
                let grown = metrics[p].scaled(1.0 + (beta - 1.0) * l);
                let new = metrics[q].intersect(&grown);
                let old = metrics[q].matrix();
                let m = new.matrix();
                let norm: f64 = old.iter().flatten().map(|x| x * x).sum::<f64>().sqrt();
                let diff: f64 = old
                    .iter()
                    .flatten()
                    .zip(m.iter().flatten())
                    .map(|(x, y)| (x - y) * (x - y))
                    .sum::<f64>()
                    .sqrt();
                if diff > 1e-6 * norm {
                    metrics[q] = new;
                    changed = true;
                }
            }
        }
        if !changed {
            return pass;
        }
    }
    100
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lcg(s: &mut u64) -> f64 {
        *s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*s >> 11) as f64 / (1u64 << 53) as f64
    }

    #[test]
    fn quadratic_fields_are_recovered_exactly_in_2d_and_3d() {
        let mut s = 7;
        let p2: Vec<[f64; 2]> = (0..400).map(|_| [lcg(&mut s), lcg(&mut s)]).collect();
        let t2 = crate::triangulate(&p2).unwrap().triangles;
        let u2: Vec<f64> = p2
            .iter()
            .map(|p| p[0] * p[0] + 3.0 * p[0] * p[1] - 2.0 * p[1] * p[1] + p[0])
            .collect();
        for h in hessians(&p2, &t2, &u2).unwrap() {
            let want = [[2.0, 3.0], [3.0, -4.0]];
            assert!(
                (0..2).all(|i| (0..2).all(|j| (h[i][j] - want[i][j]).abs() < 1e-6)),
                "{h:?}"
            );
        }
        let p3: Vec<[f64; 3]> = (0..600)
            .map(|_| [lcg(&mut s), lcg(&mut s), lcg(&mut s)])
            .collect();
        let t3 = crate::tetrahedralize(&p3).unwrap().tets;
        let u3: Vec<f64> = p3
            .iter()
            .map(|p| p[0] * p[0] + p[1] * p[2] + 2.0 * p[2] * p[2] - p[1])
            .collect();
        let want = [[2.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 4.0]];
        for h in hessians(&p3, &t3, &u3).unwrap() {
            assert!(
                (0..3).all(|i| (0..3).all(|j| (h[i][j] - want[i][j]).abs() < 1e-6)),
                "{h:?}"
            );
        }
    }

    #[test]
    fn a_patch_short_of_redundancy_after_every_ring_still_fits() {
        // A strip of triangles: the end vertex sees 2, 4, then 6 vertices
        // in its three rings (fewer than 2 × 5 unknowns), enough for a fit.
        let pts: Vec<[f64; 2]> = (0..8)
            .map(|i| {
                [
                    (i / 2) as f64 + 0.3 * (i % 2) as f64,
                    (i % 2) as f64 + 0.1 * (i * i) as f64 / 8.0,
                ]
            })
            .collect();
        let tris: Vec<[u32; 3]> = (0..6u32)
            .map(|i| {
                if i % 2 == 0 {
                    [i, i + 2, i + 1]
                } else {
                    [i, i + 1, i + 2]
                }
            })
            .collect();
        let u: Vec<f64> = pts
            .iter()
            .map(|p| p[0] * p[0] - p[0] * p[1] + 0.5 * p[1] * p[1])
            .collect();
        let h = hessians(&pts, &tris, &u).unwrap();
        let want = [[2.0, -1.0], [-1.0, 1.0]];
        assert!(
            (0..2).all(|i| (0..2).all(|j| (h[0][i][j] - want[i][j]).abs() < 1e-6)),
            "{:?}",
            h[0]
        );
    }

    #[test]
    fn bad_inputs_are_errors_naming_the_item() {
        let pts = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        let e = metric_from_mesh(&pts, &[[0u32, 1, 5]], 0.0, 1.0).unwrap_err();
        assert!(
            matches!(e, crate::Error::InconsistentMesh { reason } if reason.contains("point 5"))
        );
        for (lo, hi, option) in [
            (-1.0, 1.0, "-hmin"),
            (f64::NAN, 1.0, "-hmin"),
            (0.5, 0.1, "-hmax"),
        ] {
            let e = metric_from_mesh(&pts, &[[0u32, 1, 2]], lo, hi).unwrap_err();
            assert!(
                matches!(e, crate::Error::InvalidBound { option: o, .. } if o == option),
                "{lo} {hi}"
            );
        }
        let e = hessians(&pts, &[[0u32, 1, 5]], &[0.0; 3]).unwrap_err();
        assert_eq!(
            e,
            crate::Error::InconsistentMesh {
                reason: "element 0 names point 5, but there are 3 points".into()
            }
        );
        let e = hessians(&pts, &[[0u32, 1, 2]], &[0.0, f64::NAN, 0.0]).unwrap_err();
        assert_eq!(
            e,
            crate::Error::InconsistentMesh {
                reason: "value 1 is not finite".into()
            }
        );
        let e = hessians(&pts, &[[0u32, 1]], &[0.0; 3]).unwrap_err();
        assert!(matches!(e, crate::Error::InconsistentMesh { .. }));
        let h = vec![[[1.0, 0.0], [0.0, 1.0]]; 3];
        let e = metric_from_hessians(&pts, &[[0u32, 3, 2]], &h, Target::Error(0.1), 0.1, 1.0)
            .unwrap_err();
        assert_eq!(
            e,
            crate::Error::InconsistentMesh {
                reason: "element 0 names point 3, but there are 3 points".into()
            }
        );
        let m = vec![Metric::<2>::isotropic(1.0); 2];
        let e = complexity(&pts, &[[0u32, 1, 2]], &m).unwrap_err();
        assert_eq!(
            e,
            crate::Error::InconsistentMesh {
                reason: "2 metrics for 3 points".into()
            }
        );
        assert_eq!(super::super::mean_ratio(&pts[..2], &m[0]), 0.0);
        let e = metric_from_hessians(&pts, &[[0u32, 1, 2]], &h, Target::Error(0.0), 0.1, 1.0)
            .unwrap_err();
        assert!(matches!(
            e,
            crate::Error::InvalidBound { option: "-err", .. }
        ));
        let e = metric_from_hessians(&pts, &[[0u32, 1, 2]], &h, Target::Error(0.1), 1.0, 0.1)
            .unwrap_err();
        assert!(matches!(
            e,
            crate::Error::InvalidBound {
                option: "-hmax",
                ..
            }
        ));
    }

    #[test]
    fn error_target_and_flat_fields() {
        let pts = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        let tris = [[0u32, 1, 2]];
        // |H| = diag(2, 8), error 0.01: M = (2/9)/0.01 · diag(2, 8).
        let h = vec![[[2.0, 0.0], [0.0, -8.0]]; 3];
        let m = metric_from_hessians(&pts, &tris, &h, Target::Error(0.01), 1e-9, 1e9).unwrap();
        let c = 2.0 / 9.0 / 0.01;
        assert!(
            (m[0].matrix()[0][0] - 2.0 * c).abs() < 1e-9
                && (m[0].matrix()[1][1] - 8.0 * c).abs() < 1e-9
        );
        // A linear field: no curvature anywhere, the bound hmax decides.
        let zero = vec![[[0.0; 2]; 2]; 3];
        let m = metric_from_hessians(&pts, &tris, &zero, Target::Error(0.01), 0.01, 0.5).unwrap();
        assert!(m.iter().all(|m| (m.sizes()[0] - 0.5).abs() < 1e-12));
    }

    #[test]
    fn gradation_bounds_the_growth_along_every_edge() {
        let mut s = 3;
        let p: Vec<[f64; 2]> = (0..300).map(|_| [lcg(&mut s), lcg(&mut s)]).collect();
        let t = crate::triangulate(&p).unwrap().triangles;
        let e = edges(&t);
        let mut m: Vec<Metric<2>> = p
            .iter()
            .map(|q| Metric::isotropic(if q[0] < 0.5 { 0.001 } else { 1.0 }))
            .collect();
        let passes = gradate(&p, &e, &mut m, 1.3);
        assert!(passes > 1 && passes < 100);
        for &[a, b] in &e {
            let (a, b) = (a as usize, b as usize);
            let d = [p[b][0] - p[a][0], p[b][1] - p[a][1]];
            for (x, y) in [(a, b), (b, a)] {
                let bound = m[x].sizes()[0] * (1.0 + 0.3 * m[x].length(d));
                assert!(m[y].sizes()[1] <= bound * (1.0 + 1e-5), "edge {a}-{b}");
            }
        }
    }
}
