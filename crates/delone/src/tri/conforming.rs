//! Conforming Delaunay (Triangle's `-D`): exact diametral-circle tests, a
//! uniform grid over the mesh vertices, and an independent checker that
//! every triangle is truly Delaunay.
//!
//! Refinement with [`RefineOptions::conforming_delaunay`](super::refine::RefineOptions::conforming_delaunay)
//! splits every subsegment whose diametral circle strictly contains a mesh
//! vertex. When no subsegment is so encroached, every subsegment is an edge
//! of the Delaunay triangulation of the vertices (the Gabriel property), so
//! the constrained Delaunay triangulation is the Delaunay triangulation, and
//! [`check_conforming_delaunay`] holds.

use delone_predicates::incircle;

use crate::Violation;
use delone_predicates::{two_product, two_sum};

/// Sign of `(u - p)·(w - p)`, exactly (floating-point filter, then an
/// expansion sum of the error-free products).
fn dot_sign(u: &[f64; 2], w: &[f64; 2], p: &[f64; 2]) -> f64 {
    let (ax, ay) = (u[0] - p[0], u[1] - p[1]);
    let (bx, by) = (w[0] - p[0], w[1] - p[1]);
    let dot = ax * bx + ay * by;
    let err = 8.0 * f64::EPSILON * ((ax * bx).abs() + (ay * by).abs());
    if dot.abs() > err {
        return dot;
    }
    let mut e = [0.0f64; 40];
    let mut n = 0;
    let mut grow = |t: f64| {
        let mut q = t;
        for h in e.iter_mut().take(n) {
            let (s, l) = two_sum(q, *h);
            *h = l;
            q = s;
        }
        e[n] = q;
        n += 1;
    };
    for k in 0..2 {
        let (h1, l1) = two_sum(u[k], -p[k]);
        let (h2, l2) = two_sum(w[k], -p[k]);
        for (x, y) in [(h1, h2), (h1, l2), (l1, h2), (l1, l2)] {
            let (a, b) = two_product(x, y);
            grow(b);
            grow(a);
        }
    }
    e[..n]
        .iter()
        .rev()
        .copied()
        .find(|&x| x != 0.0)
        .unwrap_or(0.0)
}

/// True if `p` lies strictly inside the circle with diameter `u w`
/// (exact).
///
/// ```
/// use delone::tri::conforming::in_diametral_circle;
/// assert!(in_diametral_circle(&[0.0, 0.0], &[2.0, 0.0], &[1.0, 0.5]));
/// assert!(!in_diametral_circle(&[0.0, 0.0], &[2.0, 0.0], &[1.0, 1.0])); // on it
/// ```
pub fn in_diametral_circle(u: &[f64; 2], w: &[f64; 2], p: &[f64; 2]) -> bool {
    dot_sign(u, w, p) < 0.0
}

/// A uniform grid over a subset of points (about one point per cell).
pub(crate) struct Grid {
    x0: [f64; 2],
    inv: f64,
    n: [usize; 2],
    start: Vec<u32>,
    ids: Vec<u32>,
}

impl Grid {
    pub(crate) fn new(points: &[[f64; 2]], ids: &[u32]) -> Grid {
        let [lo, hi] = match ids {
            [] => [[0.0; 2]; 2],
            _ => crate::geom::bbox(ids.iter().map(|&i| &points[i as usize])),
        };
        let w = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(f64::MIN_POSITIVE);
        let area = (hi[0] - lo[0]).max(w * 1e-6) * (hi[1] - lo[1]).max(w * 1e-6);
        let h = (area / ids.len().max(1) as f64).sqrt().max(w / 4096.0);
        let inv = 1.0 / h;
        let n = [
            ((hi[0] - lo[0]) * inv) as usize + 1,
            ((hi[1] - lo[1]) * inv) as usize + 1,
        ];
        let cell = |p: &[f64; 2]| {
            let i = (((p[0] - lo[0]) * inv) as usize).min(n[0] - 1);
            let j = (((p[1] - lo[1]) * inv) as usize).min(n[1] - 1);
            j * n[0] + i
        };
        let mut start = vec![0u32; n[0] * n[1] + 1];
        for &i in ids {
            start[cell(&points[i as usize]) + 1] += 1;
        }
        for c in 1..start.len() {
            start[c] += start[c - 1];
        }
        let mut fill = start.clone();
        let mut out = vec![0u32; ids.len()];
        for &i in ids {
            let c = cell(&points[i as usize]);
            out[fill[c] as usize] = i;
            fill[c] += 1;
        }
        Grid {
            x0: lo,
            inv,
            n,
            start,
            ids: out,
        }
    }

    /// Calls `f` on every point in the cells meeting the box `lo..hi` until
    /// `f` returns true; returns whether it did.
    pub(crate) fn any_in(
        &self,
        lo: [f64; 2],
        hi: [f64; 2],
        mut f: impl FnMut(u32) -> bool,
    ) -> bool {
        let idx = |x: f64, k: usize| -> usize {
            let v = (x - self.x0[k]) * self.inv;
            if v <= 0.0 {
                0
            } else {
                (v as usize).min(self.n[k] - 1)
            }
        };
        if !(lo[0] <= hi[0] && lo[1] <= hi[1]) {
            return false;
        }
        let (i0, i1) = (idx(lo[0], 0), idx(hi[0], 0));
        let (j0, j1) = (idx(lo[1], 1), idx(hi[1], 1));
        for j in j0..=j1 {
            let row = j * self.n[0];
            let (a, b) = (self.start[row + i0], self.start[row + i1 + 1]);
            for &v in &self.ids[a as usize..b as usize] {
                if f(v) {
                    return true;
                }
            }
        }
        false
    }
}

/// The vertices used by `triangles`, in increasing order.
fn used(n: usize, triangles: &[[u32; 3]]) -> Vec<u32> {
    let mut u = vec![false; n];
    for t in triangles {
        for &v in t {
            if let Some(x) = u.get_mut(v as usize) {
                *x = true;
            }
        }
    }
    (0..n as u32).filter(|&i| u[i as usize]).collect()
}

/// The indices of the edges `subs` (vertex pairs) whose diametral circle
/// strictly contains a vertex of `triangles` (exact test).
pub(crate) fn encroached(
    points: &[[f64; 2]],
    triangles: &[[u32; 3]],
    subs: &[[u32; 2]],
) -> Vec<usize> {
    let ids = used(points.len(), triangles);
    let grid = Grid::new(points, &ids);
    let mut out = Vec::new();
    for (k, s) in subs.iter().enumerate() {
        let (u, w) = (&points[s[0] as usize], &points[s[1] as usize]);
        let c = [0.5 * (u[0] + w[0]), 0.5 * (u[1] + w[1])];
        let r = 0.5 * ((u[0] - w[0]).hypot(u[1] - w[1])) * (1.0 + 1e-9);
        let hit = grid.any_in([c[0] - r, c[1] - r], [c[0] + r, c[1] + r], |v| {
            v != s[0] && v != s[1] && in_diametral_circle(u, w, &points[v as usize])
        });
        if hit {
            out.push(k);
        }
    }
    out
}

/// Checks that every triangle is truly Delaunay: no vertex of the mesh (a
/// point used by some triangle) lies strictly inside any triangle's
/// circumcircle (exact `incircle`), and no triangle is degenerate or
/// clockwise. Candidates are found with a uniform grid, so the check takes
/// about linear time on meshes with bounded circumcircles.
///
/// # Errors
/// A [`Violation`] of kind `"delaunay"` naming the triangle and the vertex,
/// or `"orientation"` / `"index"` for a malformed triangle.
///
/// ```
/// use delone::tri::conforming::check_conforming_delaunay;
/// let p = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
/// check_conforming_delaunay(&p, &[[0, 1, 2], [0, 2, 3]]).unwrap();
/// // A thin pair of triangles across the wrong diagonal:
/// let q = [[0.0, 0.0], [2.0, -0.1], [4.0, 0.0], [2.0, 0.1]];
/// assert!(check_conforming_delaunay(&q, &[[0, 1, 2], [0, 2, 3]]).is_err());
/// ```
pub fn check_conforming_delaunay(
    points: &[[f64; 2]],
    triangles: &[[u32; 3]],
) -> Result<(), Violation> {
    for (t, v) in triangles.iter().enumerate() {
        if v.iter().any(|&x| x as usize >= points.len()) {
            return Err(Violation::new(
                "index",
                format!("triangle {t} has a vertex out of range"),
            ));
        }
        super::mesh::check_ccw(points, t, v)?;
    }
    let ids = used(points.len(), triangles);
    let grid = Grid::new(points, &ids);
    for (t, v) in triangles.iter().enumerate() {
        let (a, b, c) = (
            &points[v[0] as usize],
            &points[v[1] as usize],
            &points[v[2] as usize],
        );
        // Circumcentre in floating point; the box is enlarged so that no
        // vertex inside the circle is missed.
        let o = super::voronoi::centre([a, b, c], [0.0; 3]);
        let r = (o[0] - a[0]).hypot(o[1] - a[1]);
        let (lo, hi) = if r.is_finite() {
            let m = r * (1.0 + 1e-6) + 1e-12 * (a[0].abs() + a[1].abs());
            ([o[0] - m, o[1] - m], [o[0] + m, o[1] + m])
        } else {
            ([f64::NEG_INFINITY; 2], [f64::INFINITY; 2])
        };
        let mut bad = None;
        grid.any_in(lo, hi, |p| {
            if !v.contains(&p) && incircle(a, b, c, &points[p as usize]) > 0.0 {
                bad = Some(p);
                return true;
            }
            false
        });
        if let Some(p) = bad {
            return Err(Violation::new(
                "delaunay",
                format!("vertex {p} lies inside the circumcircle of triangle {t} {v:?}"),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_dot_sign_on_ties_and_near_ties() {
        assert_eq!(dot_sign(&[0.0, 0.0], &[2.0, 0.0], &[1.0, 1.0]), 0.0);
        assert!(dot_sign(&[0.0, 0.0], &[2.0, 0.0], &[1.0, 1.0 - 1e-17]) >= 0.0);
        // 1 - 2^-53 is representable: strictly inside.
        let y = 1.0 - f64::EPSILON / 2.0;
        assert!(dot_sign(&[0.0, 0.0], &[2.0, 0.0], &[1.0, y]) < 0.0);
        let y = 1.0 + f64::EPSILON;
        assert!(dot_sign(&[0.0, 0.0], &[2.0, 0.0], &[1.0, y]) > 0.0);
    }

    #[test]
    fn grid_finds_every_point_in_a_box() {
        let pts: Vec<[f64; 2]> = (0..400)
            .map(|i| {
                [
                    ((i * 37) % 101) as f64 * 0.13,
                    ((i * 53) % 97) as f64 * 0.07,
                ]
            })
            .collect();
        let ids: Vec<u32> = (0..400).collect();
        let g = Grid::new(&pts, &ids);
        let (lo, hi) = ([2.0, 1.0], [5.5, 3.25]);
        let mut seen = Vec::new();
        g.any_in(lo, hi, |v| {
            seen.push(v);
            false
        });
        for (i, p) in pts.iter().enumerate() {
            if p[0] >= lo[0] && p[0] <= hi[0] && p[1] >= lo[1] && p[1] <= hi[1] {
                assert!(seen.contains(&(i as u32)), "point {i} missed");
            }
        }
    }

    #[test]
    fn encroached_finds_a_vertex_in_the_circle() {
        let p = [[0.0, 0.0], [4.0, 0.0], [2.0, 1.0], [2.0, 3.0]];
        let t = [[0, 1, 2], [0, 2, 3], [2, 1, 3]];
        assert_eq!(encroached(&p, &t, &[[0, 1], [0, 2], [0, 3]]), vec![0, 2]);
    }
}
