//! Small 3D vector helpers (floating point) shared by the 3D modules; every
//! combinatorial decision is made by the exact predicates of
//! `delone_predicates`, never by these.

/// A point or vector in 3D.
pub(crate) type P = [f64; 3];

/// `a - b`.
#[inline]
pub(crate) fn sub(a: &P, b: &P) -> P {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// The dot product.
#[inline]
pub(crate) fn dot(a: &P, b: &P) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The cross product.
#[inline]
pub(crate) fn cross(a: &P, b: &P) -> P {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The Euclidean length.
#[inline]
pub(crate) fn norm(a: &P) -> f64 {
    dot(a, a).sqrt()
}

/// The squared distance between two points.
#[inline]
pub(crate) fn dist2(a: &P, b: &P) -> f64 {
    let d = sub(a, b);
    dot(&d, &d)
}

/// Exact collinearity of three points in 3D: all three coordinate
/// projections are degenerate.
pub(crate) fn collinear(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3]) -> bool {
    (0..3).all(|k| {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        delone_predicates::orient2d(&[a[i], a[j]], &[b[i], b[j]], &[c[i], c[j]]) == 0.0
    })
}

/// Two coordinate axes `(i, j)` onto which triangle `a b c` projects with
/// a non-zero exact orientation (`None`: the triangle is degenerate). On
/// the triangle's plane such a projection is an affine bijection, so exact
/// 2D tests of coplanar points give the same answer in any of them.
pub(crate) fn projection_axes(a: &P, b: &P, c: &P) -> Option<(usize, usize)> {
    [(0, 1), (1, 2), (2, 0)].into_iter().find(|&(i, j)| {
        delone_predicates::orient2d(&[a[i], a[j]], &[b[i], b[j]], &[c[i], c[j]]) != 0.0
    })
}

/// The angle (radians) at `o` between the directions to `x` and `y`; 0
/// when one of them is `o`.
pub(crate) fn angle(o: &P, x: &P, y: &P) -> f64 {
    let (u, v) = (sub(x, o), sub(y, o));
    let den = (dot(&u, &u) * dot(&v, &v)).sqrt();
    if den > 0.0 {
        (dot(&u, &v) / den).clamp(-1.0, 1.0).acos()
    } else {
        0.0
    }
}

/// Corner `k` of box `b = [lower, upper]`: the upper bound in axis `i`
/// when bit `i` of `k` is set.
pub(crate) fn box_corner(b: &[P; 2], k: usize) -> P {
    [b[k & 1][0], b[(k >> 1) & 1][1], b[(k >> 2) & 1][2]]
}

/// The sides of a box (lower and upper x, y, z), four [`box_corner`]
/// indices each, counterclockwise seen from outside.
pub(crate) const BOX_SIDES: [u32; 24] = [
    0, 4, 6, 2, 1, 3, 7, 5, 0, 1, 5, 4, 2, 6, 7, 3, 0, 2, 3, 1, 4, 5, 7, 6,
];

/// A regular tetrahedron, positive: `(x, y, xy)`, `x, y = ±1` (for
/// tests).
#[cfg(test)]
pub(crate) fn regular_tet() -> [P; 4] {
    std::array::from_fn(|i| {
        let (x, y) = (1.0 - 2.0 * (i & 1) as f64, 1.0 - 2.0 * (i >> 1) as f64);
        [x, y, x * y]
    })
}

/// The tetrahedron of the origin and the points at `s` on each axis (for
/// tests).
#[cfg(test)]
pub(crate) fn corner_tet(s: f64) -> [P; 4] {
    std::array::from_fn(|i| std::array::from_fn(|k| if i == k + 1 { s } else { 0.0 }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn products() {
        let (x, y) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        assert_eq!(cross(&x, &y), [0.0, 0.0, 1.0]);
        assert_eq!(dot(&x, &y), 0.0);
        assert_eq!(norm(&[3.0, 4.0, 0.0]), 5.0);
        assert_eq!(dist2(&[1.0, 2.0, 3.0], &[1.0, 2.0, 5.0]), 4.0);
        assert_eq!(sub(&[1.0, 2.0, 3.0], &x), [0.0, 2.0, 3.0]);
        assert_eq!(angle(&[0.0; 3], &x, &y), std::f64::consts::FRAC_PI_2);
        assert_eq!(angle(&[0.0; 3], &[0.0; 3], &y), 0.0);
        assert!(
            collinear(&x, &[2.0, -1.0, 0.0], &[3.0, -2.0, 0.0]) && !collinear(&x, &y, &[0.0; 3])
        );
        assert_eq!(box_corner(&[[0.0; 3], [1.0, 2.0, 3.0]], 6), [0.0, 2.0, 3.0]);
    }
}
