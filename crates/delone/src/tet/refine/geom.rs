//! Small geometric helpers of the refinement (floating point; the exact
//! decisions use `delone_predicates`).

pub(crate) use crate::geom::vec3::P;
pub(crate) use crate::geom::vec3::{cross, dist2, dot, sub};

/// Relative slack of the strict "inside a ball" tests: a point on the
/// sphere up to rounding (cospherical and cocircular configurations, grids)
/// does not encroach.
const SLACK: f64 = 1e-10;

/// Cosine of the angle at which a point on the boundary of a segment's
/// diametral lens sees the segment: 120°, the lens whose arcs meet the
/// segment at 30° (Shewchuk's diametral lens).
const LENS_COS: f64 = -0.5;

/// Is `p` strictly inside the diametral lens of segment `u v`: does it see
/// the segment at an angle above 120°? The lens lies inside the diametral
/// ball (the points that see it at more than 90°), squeezed towards the
/// segment: a point in the ball but off the lens is at least
/// `|u v| / (2 √3)` from the segment's line and, when it is a bad cell's
/// circumcentre, is inserted rather than splitting the segment
/// (J. R. Shewchuk, *Delaunay refinement algorithms for triangular mesh
/// generation*, 2002: diametral lenses instead of diametral circles
/// make fewer vertices with the same angle bound).
pub(crate) fn encroaches_segment(u: &P, v: &P, p: &P) -> bool {
    let (a, b) = (sub(u, p), sub(v, p));
    let d = dot(&a, &b);
    d < 0.0 && d * d > LENS_COS * LENS_COS * dot(&a, &a) * dot(&b, &b) * (1.0 + SLACK)
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The diametral lens is the part of the diametral ball whose points
    /// see the segment at more than 120°.
    #[test]
    fn lens_inside_the_ball() {
        let (u, v) = ([-1.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
        // On the bisector, at the height where the segment is seen at
        // `deg` degrees (2 atan(1 / h)), in a tilted plane through it.
        let at = |deg: f64| {
            let h = 1.0 / (deg.to_radians() / 2.0).tan();
            [0.0, 0.6 * h, 0.8 * h]
        };
        assert!(encroaches_segment(&u, &v, &at(150.0)));
        assert!(encroaches_segment(&u, &v, &at(121.0)));
        for deg in [119.0, 110.0, 95.0] {
            let p = at(deg);
            assert!(dot(&p, &p) < 1.0, "{deg}: in the ball");
            assert!(!encroaches_segment(&u, &v, &p), "{deg}: off the lens");
        }
        assert!(!encroaches_segment(&u, &v, &at(80.0)));
        // Off the bisector the angle decides: about 152° and 117°.
        assert!(encroaches_segment(&u, &v, &[0.9, 0.05, 0.0]));
        let q = [0.5, 0.5, 0.0];
        assert!(dot(&q, &q) < 1.0 && !encroaches_segment(&u, &v, &q));
        // The ends, and points on the line beyond the segment, never do.
        assert!(!encroaches_segment(&u, &v, &u));
        assert!(!encroaches_segment(&u, &v, &[2.0, 0.0, 0.0]));
    }
}
