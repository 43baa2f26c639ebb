//! Small geometric helpers of the refinement (floating point; the exact
//! decisions use `delone_predicates`).

pub(crate) use crate::geom::vec3::P;
pub(crate) use crate::geom::vec3::{cross, dist2, dot, sub};

/// Relative slack of the strict "inside a ball" tests: a point on the
/// sphere up to rounding (cospherical and cocircular configurations, grids)
/// does not encroach.
const SLACK: f64 = 1e-10;

/// Is `p` strictly inside the diametral ball of segment `u v`?
pub(crate) fn encroaches_segment(u: &P, v: &P, p: &P) -> bool {
    let (a, b) = (sub(u, p), sub(v, p));
    dot(&a, &b) < -SLACK * (dot(&a, &a) + dot(&b, &b))
}

/// Circumcentre of triangle `a b c` (in its plane) and squared radius.
pub(crate) fn tri_circumcenter(a: &P, b: &P, c: &P) -> Option<(P, f64)> {
    let (ab, ac) = (sub(b, a), sub(c, a));
    let n = cross(&ab, &ac);
    let den = 2.0 * dot(&n, &n);
    if den == 0.0 || !den.is_finite() {
        return None;
    }
    let t1 = cross(&n, &ab);
    let t2 = cross(&ac, &n);
    let (l1, l2) = (dot(&ac, &ac), dot(&ab, &ab));
    let o: P = std::array::from_fn(|k| (l1 * t1[k] + l2 * t2[k]) / den);
    let x = [a[0] + o[0], a[1] + o[1], a[2] + o[2]];
    x.iter().all(|v| v.is_finite()).then_some((x, dot(&o, &o)))
}

/// Is `p` strictly inside the equatorial ball of triangle `a b c`?
pub(crate) fn encroaches_face(a: &P, b: &P, c: &P, p: &P) -> bool {
    match tri_circumcenter(a, b, c) {
        Some((x, r2)) => dist2(&x, p) < r2 * (1.0 - SLACK),
        None => false,
    }
}

/// Distance of `p` to the line `a b`.
pub(crate) fn line_distance(a: &P, b: &P, p: &P) -> f64 {
    let d = sub(b, a);
    let l = dot(&d, &d).sqrt();
    if l == 0.0 {
        return dist2(a, p).sqrt();
    }
    (cross(&d, &sub(p, a)).iter().map(|x| x * x).sum::<f64>()).sqrt() / l
}

/// Distance of `p` to the plane of `a b c`.
pub(crate) fn plane_distance(a: &P, b: &P, c: &P, p: &P) -> f64 {
    let n = cross(&sub(b, a), &sub(c, a));
    let l = dot(&n, &n).sqrt();
    if l == 0.0 {
        return 0.0;
    }
    (dot(&n, &sub(p, a)) / l).abs()
}
