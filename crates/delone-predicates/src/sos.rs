//! Simulation of Simplicity: symbolic perturbations ordered by vertex index.

use crate::{orient2d, orient3d, Point2, Point3};

/// Sign of `x` as `-1, 0, +1` (NaN gives 0).
#[inline]
pub(crate) fn sgn(x: f64) -> i32 {
    if x > 0.0 {
        1
    } else if x < 0.0 {
        -1
    } else {
        0
    }
}

/// `+1` if the permutation sorting `idx` increasingly is even, `-1` if odd.
pub(crate) fn parity(idx: &[u32]) -> i32 {
    let mut inv = 0usize;
    for i in 0..idx.len() {
        for j in i + 1..idx.len() {
            if idx[i] > idx[j] {
                inv += 1;
            }
        }
    }
    if inv & 1 == 0 {
        1
    } else {
        -1
    }
}

/// Row positions `0..N` sorted by decreasing index (ties by position).
#[inline]
pub(crate) fn by_decreasing_index<const N: usize>(idx: &[u32; N]) -> [usize; N] {
    let mut order = [0usize; N];
    for (k, o) in order.iter_mut().enumerate() {
        *o = k;
    }
    // Insertion sort: N <= 5.
    for i in 1..N {
        let mut j = i;
        while j > 0 && idx[order[j - 1]] < idx[order[j]] {
            order.swap(j - 1, j);
            j -= 1;
        }
    }
    order
}

/// Lifting perturbation for the (weighted) in-circle test whose exact value is 0.
///
/// `pts` are the rows `a, b, c, d`; the derivative of the determinant with respect
/// to the lifted coordinate of row `r` is `(-1)^r * orient2d(other rows in order)`.
#[cold]
#[inline(never)]
pub(crate) fn incircle_lifted_sos(pts: [&Point2; 4], idx: [u32; 4]) -> i32 {
    for r in by_decreasing_index(&idx) {
        let mut o = [pts[0]; 3];
        for (slot, k) in o.iter_mut().zip((0..4).filter(|&k| k != r)) {
            *slot = pts[k];
        }
        let s = sgn(orient2d(o[0], o[1], o[2]));
        if s != 0 {
            return if r % 2 == 0 { s } else { -s };
        }
    }
    parity(&idx)
}

/// Lifting perturbation for the (weighted) in-sphere test whose exact value is 0.
///
/// The derivative with respect to the lifted coordinate of row `r` (rows
/// `a, b, c, d, e`) is `-(-1)^r * orient3d(other rows in order)`.
#[cold]
#[inline(never)]
pub(crate) fn insphere_lifted_sos(pts: [&Point3; 5], idx: [u32; 5]) -> i32 {
    for r in by_decreasing_index(&idx) {
        let mut o = [pts[0]; 4];
        for (slot, k) in o.iter_mut().zip((0..5).filter(|&k| k != r)) {
            *slot = pts[k];
        }
        let s = sgn(orient3d(o[0], o[1], o[2], o[3]));
        if s != 0 {
            return if r % 2 == 0 { -s } else { s };
        }
    }
    parity(&idx)
}

/// Sign of the homogeneous orientation minor on `rows` (ascending) and coordinate
/// columns `cols` (ascending) plus the ones column; `rows.len() == cols.len() + 1`.
fn orient_minor<const D: usize>(pts: &[[f64; D]], rows: &[usize], cols: &[usize]) -> i32 {
    match cols.len() {
        0 => 1,
        1 => {
            let u = cols[0];
            let (p, q) = (pts[rows[0]][u], pts[rows[1]][u]);
            // det [p 1; q 1] = p - q.
            if p > q {
                1
            } else if p < q {
                -1
            } else {
                0
            }
        }
        2 => {
            let pr = |r: usize| [pts[r][cols[0]], pts[r][cols[1]]];
            sgn(orient2d(&pr(rows[0]), &pr(rows[1]), &pr(rows[2])))
        }
        _ => {
            // Only reached for D == 3 with no perturbed row, i.e. the plain
            // determinant, which the callers evaluate before.
            let pr = |r: usize| {
                let mut q = [0.0; 3];
                for (s, &c) in q.iter_mut().zip(cols) {
                    *s = pts[r][c];
                }
                q
            };
            sgn(orient3d(
                &pr(rows[0]),
                &pr(rows[1]),
                &pr(rows[2]),
                &pr(rows[3]),
            ))
        }
    }
}

/// Edelsbrunner–Mücke perturbation of a `(D+1) x (D+1)` orientation determinant
/// `det [p_r 1]` whose exact value is 0.
///
/// Variable at position `P = rank * D + j` (rank 0 = largest index) perturbs
/// coordinate `j` of that row by `ε^(2^P)`; the monomials of the perturbed
/// determinant come in increasing order of their bit masks, and the coefficient of
/// a monomial is the determinant with the perturbed rows replaced by unit vectors
/// (generalized Laplace expansion). The first nonzero coefficient decides.
#[cold]
#[inline(never)]
pub(crate) fn orient_sos<const D: usize, const N: usize>(
    pts: &[[f64; D]; N],
    idx: &[u32; N],
) -> i32 {
    let order = by_decreasing_index(idx);
    let nvars = N * D;
    for mask in 1u32..(1u32 << nvars) {
        // Decode (row, column) pairs; reject repeated rows or columns (zero coefficient).
        let mut col_of_row = [usize::MAX; N];
        let mut used_cols = 0u32;
        let mut ok = true;
        let mut bits = mask;
        while bits != 0 {
            let p = bits.trailing_zeros() as usize;
            bits &= bits - 1;
            let (row, col) = (order[p / D], p % D);
            if col_of_row[row] != usize::MAX || used_cols & (1 << col) != 0 {
                ok = false;
                break;
            }
            col_of_row[row] = col;
            used_cols |= 1 << col;
        }
        if !ok {
            continue;
        }
        // Sign (-1)^(sum rows + sum cols) * sgn(pi) of the Laplace expansion.
        let mut sign = 1i32;
        let mut chosen = [0usize; N];
        let mut k = 0;
        for (r, &c) in col_of_row.iter().enumerate() {
            if c != usize::MAX {
                if (r + c) % 2 == 1 {
                    sign = -sign;
                }
                chosen[k] = c;
                k += 1;
            }
        }
        for i in 0..k {
            for j in i + 1..k {
                if chosen[i] > chosen[j] {
                    sign = -sign;
                }
            }
        }
        let mut rows = [0usize; N];
        let mut nr = 0;
        for (r, &c) in col_of_row.iter().enumerate() {
            if c == usize::MAX {
                rows[nr] = r;
                nr += 1;
            }
        }
        let mut cols = [0usize; N];
        let mut nc = 0;
        for c in 0..D {
            if used_cols & (1 << c) == 0 {
                cols[nc] = c;
                nc += 1;
            }
        }
        let m = orient_minor(pts, &rows[..nr], &cols[..nc]);
        if m != 0 {
            return sign * m;
        }
    }
    // Unreachable for pairwise distinct rows (the monomial using D distinct rows and
    // all D columns has coefficient ±1); kept total for safety.
    parity(idx)
}
