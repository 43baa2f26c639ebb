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
    }
}
