//! Quality measures of tetrahedra and a summary of a whole mesh.
//!
//! * [`dihedral_angles`] — the six dihedral angles (degrees), computed from
//!   inward face normals with `atan2(|n_k × n_l|, -n_k · n_l)`, which stays
//!   accurate near 0° and 180° (an `acos` of a dot product does not);
//! * [`radius_edge_ratio`] — circumradius over shortest edge (√6/4 ≈ 0.612
//!   for the regular tetrahedron, unbounded for slivers only through the
//!   circumradius: slivers can have a small ratio, which is why the dihedral
//!   angles are reported too);
//! * [`volume`] — signed volume (positive for positively oriented
//!   tetrahedra, [`super::local`] convention);
//! * [`shape_quality`] — `6√2 · volume / rms_edge³`, scale invariant, 1 for
//!   the regular tetrahedron and 0 for a flat one;
//! * [`TetStats`] — counts, extremes, dihedral-angle and radius-edge
//!   histograms of a list of tetrahedra, with a JSON rendering.
//!
//! Every measure is computed on the element's points scaled by a power of
//! two ([`crate::geom::scale::local`], exact): nothing overflows or
//! underflows at any coordinate scale, angles and ratios are the same bit
//! for bit at every power-of-two scale, and lengths and volumes are
//! brought back to the input's units (infinite or zero only when the value
//! itself is beyond the range of `f64`).

use crate::geom::scale::{local, unscale};
use crate::geom::vec3::{cross, dot, norm, sub};
use std::fmt::Write as _;

/// The local vertex pairs of the six edges, in the order of
/// [`dihedral_angles`]' result.
pub use super::local::EDGES;

/// Signed volume of tetrahedron `p` (positive when `(p1-p0)×(p2-p0)·(p3-p0) > 0`).
///
/// ```
/// use delone::tet::quality::volume;
/// let t = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
/// assert!((volume(&t) - 1.0 / 6.0).abs() < 1e-15);
/// ```
pub fn volume(p: &[[f64; 3]; 4]) -> f64 {
    let (p, s) = local(*p);
    unscale(volume_raw(&p), s, 3)
}

/// [`volume`] without the rescaling (no guard against overflow for
/// coordinates beyond about 1e100).
pub(crate) fn volume_raw(p: &[[f64; 3]; 4]) -> f64 {
    let (a, b, c) = (sub(&p[1], &p[0]), sub(&p[2], &p[0]), sub(&p[3], &p[0]));
    dot(&a, &cross(&b, &c)) / 6.0
}

/// The circumcentre of tetrahedron `p` (`None` when it is flat).
///
/// ```
/// use delone::tet::quality::circumcenter;
/// let t = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 2.0]];
/// let c = circumcenter(&t).unwrap();
/// assert!(c.iter().all(|&x| (x - 1.0).abs() < 1e-15));
/// ```
pub fn circumcenter(p: &[[f64; 3]; 4]) -> Option<[f64; 3]> {
    let (p, s) = local(*p);
    let c = circumcenter_raw(&p)?.map(|x| unscale(x, s, 1));
    c.iter().all(|x| x.is_finite()).then_some(c)
}

/// [`circumcenter`] without the rescaling.
fn circumcenter_raw(p: &[[f64; 3]; 4]) -> Option<[f64; 3]> {
    let (a, b, c) = (sub(&p[1], &p[0]), sub(&p[2], &p[0]), sub(&p[3], &p[0]));
    let bc = cross(&b, &c);
    let ca = cross(&c, &a);
    let ab = cross(&a, &b);
    let den = 2.0 * dot(&a, &bc);
    if den == 0.0 || !den.is_finite() {
        return None;
    }
    let (la, lb, lc) = (dot(&a, &a), dot(&b, &b), dot(&c, &c));
    let o: [f64; 3] = std::array::from_fn(|k| (la * bc[k] + lb * ca[k] + lc * ab[k]) / den);
    let r = [p[0][0] + o[0], p[0][1] + o[1], p[0][2] + o[2]];
    r.iter().all(|x| x.is_finite()).then_some(r)
}

/// Lengths of the six edges, in [`EDGES`] order.
///
/// ```
/// use delone::tet::quality::edge_lengths;
/// let t = [[0.0, 0.0, 0.0], [3.0, 0.0, 0.0], [0.0, 4.0, 0.0], [0.0, 0.0, 1.0]];
/// assert_eq!(edge_lengths(&t)[3], 5.0);
/// ```
pub fn edge_lengths(p: &[[f64; 3]; 4]) -> [f64; 6] {
    let (p, s) = local(*p);
    edge_lengths_raw(&p).map(|l| unscale(l, s, 1))
}

/// [`edge_lengths`] without the rescaling.
fn edge_lengths_raw(p: &[[f64; 3]; 4]) -> [f64; 6] {
    EDGES.map(|(i, j)| norm(&sub(&p[j], &p[i])))
}

/// Circumradius over shortest edge (infinite for a flat tetrahedron).
///
/// ```
/// use delone::tet::quality::radius_edge_ratio;
/// let s = 1.0 / 2f64.sqrt();
/// let reg = [[1.0, 1.0, 1.0], [1.0, -1.0, -1.0], [-1.0, 1.0, -1.0], [-1.0, -1.0, 1.0]]
///     .map(|v: [f64; 3]| v.map(|x| x * s));
/// assert!((radius_edge_ratio(&reg) - 6f64.sqrt() / 4.0).abs() < 1e-12);
/// ```
pub fn radius_edge_ratio(p: &[[f64; 3]; 4]) -> f64 {
    // Scale invariant: measured on the element scaled by a power of two.
    let (p, _) = local(*p);
    radius_edge_ratio_raw(&p, &edge_lengths_raw(&p))
}

/// [`radius_edge_ratio`] of points in a local frame with their
/// [`edge_lengths_raw`] `l`.
fn radius_edge_ratio_raw(p: &[[f64; 3]; 4], l: &[f64; 6]) -> f64 {
    let Some(c) = circumcenter_raw(p) else {
        return f64::INFINITY;
    };
    let r = norm(&sub(&c, &p[0]));
    let e = l.iter().copied().fold(f64::INFINITY, f64::min);
    if e > 0.0 {
        r / e
    } else {
        f64::INFINITY
    }
}

/// The six dihedral angles in degrees, at the edges in [`EDGES`] order.
/// A flat tetrahedron has angles 0° and 180°.
///
/// ```
/// use delone::tet::quality::dihedral_angles;
/// let t = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
/// let d = dihedral_angles(&t);
/// assert!((d[0] - 90.0).abs() < 1e-12); // edge 0-1 (the x axis)
/// assert!((d[3] - 54.735_610_317_245_35).abs() < 1e-9); // edge 1-2
/// ```
pub fn dihedral_angles(p: &[[f64; 3]; 4]) -> [f64; 6] {
    dihedral_sin_cos(p).map(|(s, c)| s.atan2(c).to_degrees())
}

/// The six dihedral angles as `(s, c)` pairs proportional to their sine
/// (non-negative) and cosine, in [`EDGES`] order: the angle is
/// `s.atan2(c)` ([`dihedral_angles`]).
fn dihedral_sin_cos(p: &[[f64; 3]; 4]) -> [(f64, f64); 6] {
    // Scale invariant: measured on the element scaled by a power of two.
    let (p, _) = local(*p);
    dihedral_sin_cos_raw(&p)
}

/// [`dihedral_sin_cos`] of points in a local frame.
fn dihedral_sin_cos_raw(p: &[[f64; 3]; 4]) -> [(f64, f64); 6] {
    // Inward normal of the face opposite vertex k.
    let normal = |k: usize| {
        let [a, b, c] = [(k + 1) % 4, (k + 2) % 4, (k + 3) % 4].map(|i| p[i]);
        let n = cross(&sub(&b, &a), &sub(&c, &a));
        if dot(&n, &sub(&p[k], &a)) < 0.0 {
            n.map(|x| -x)
        } else {
            n
        }
    };
    let n = [normal(0), normal(1), normal(2), normal(3)];
    EDGES.map(|(i, j)| {
        // The faces at edge i-j are those opposite the other two vertices
        // (`k < l`).
        let k = (0..4).find(|&v| v != i && v != j).unwrap_or(0);
        let l = 6 - i - j - k;
        (norm(&cross(&n[k], &n[l])), -dot(&n[k], &n[l]))
    })
}

/// Margin on a cosine within which [`DihedralTally`] measures the angle
/// itself (`atan2`): far above the rounding of `c / sqrt(s² + c²)`.
const COS_MARGIN: f64 = 1e-9;

/// The dihedral angles' minimum, maximum and histogram over
/// [`DIHEDRAL_BINS`], the same as from [`dihedral_angles`], with an
/// `atan2` only for the angles whose cosine is within [`COS_MARGIN`] of a
/// bin bound or of the extremes so far.
struct DihedralTally {
    /// Cosines of the bin bounds.
    bounds: [f64; DIHEDRAL_BINS.len()],
    min: f64,
    max: f64,
    /// Cosines of `min` and `max`.
    cos_min: f64,
    cos_max: f64,
}

impl DihedralTally {
    fn new() -> Self {
        DihedralTally {
            bounds: DIHEDRAL_BINS.map(|b| b.to_radians().cos()),
            min: 180.0,
            max: 0.0,
            cos_min: -1.0,
            cos_max: 1.0,
        }
    }

    /// Adds the angle `s.atan2(c)` to `histogram`.
    fn add(&mut self, (s, c): (f64, f64), histogram: &mut [usize]) {
        let r2 = s * s + c * c;
        let u = c / r2.sqrt();
        // Far from every bin bound and the extremes: the bin from the
        // cosine (the angle is below bound b when its cosine is above b's).
        if r2 > 1e-200 && r2.is_finite() && u.is_finite() {
            let last = self.bounds.len() - 1;
            let k = self.bounds.iter().position(|&b| u > b).unwrap_or(last);
            // The bounds are decreasing: the nearest are those at k - 1 and k.
            let clear = (u - self.bounds[k]).abs() > COS_MARGIN
                && (k == 0 || (u - self.bounds[k - 1]).abs() > COS_MARGIN);
            if clear && u < self.cos_min - COS_MARGIN && u > self.cos_max + COS_MARGIN {
                histogram[k] += 1;
                return;
            }
        }
        let a = s.atan2(c).to_degrees();
        if a < self.min {
            self.min = a;
            self.cos_min = a.to_radians().cos();
        }
        if a > self.max {
            self.max = a;
            self.cos_max = a.to_radians().cos();
        }
        histogram[bin(&DIHEDRAL_BINS, a)] += 1;
    }
}

/// The kind of a poorly shaped tetrahedron (after Cheng, Dey & Shewchuk,
/// *Delaunay Mesh Generation*, §1.4).
///
/// ```
/// use delone::tet::quality::{tet_shape, TetShape};
/// assert_eq!(TetShape::Sliver.to_string(), "sliver");
/// let _ = tet_shape(&[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[non_exhaustive]
pub enum TetShape {
    /// No short edge, four vertices near a circle: two opposite edges
    /// with dihedral angles near 180°.
    Sliver,
    /// No short edge, one vertex near the opposite face: the three edges
    /// at that vertex have obtuse dihedral angles.
    Cap,
    /// One short edge (two vertices close together).
    Wedge,
    /// Two or more short edges (three vertices close together, or one
    /// far from the other three).
    Needle,
}

impl std::fmt::Display for TetShape {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            TetShape::Sliver => "sliver",
            TetShape::Cap => "cap",
            TetShape::Wedge => "wedge",
            TetShape::Needle => "needle",
        })
    }
}

/// Classifies a tetrahedron as one of the [`TetShape`]s (meaningful for a
/// poorly shaped one): an edge is short when it is below 0.3 times the
/// longest; without short edges, a cap when the three edges at one vertex
/// have dihedral angles above 90°, else a sliver.
///
/// ```
/// use delone::tet::quality::{tet_shape, TetShape};
/// // Four points near the square's circle, lifted alternately: a sliver.
/// let s = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.01], [1.0, 1.0, 0.0], [0.0, 1.0, 0.01]];
/// assert_eq!(tet_shape(&s), TetShape::Sliver);
/// // A vertex just above the middle of a triangle: a cap.
/// let c = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.35, 0.3, 0.01]];
/// assert_eq!(tet_shape(&c), TetShape::Cap);
/// // Two vertices close together: a wedge.
/// let w = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.05, 0.0, 0.05]];
/// assert_eq!(tet_shape(&w), TetShape::Wedge);
/// // One vertex far from the other three: a needle.
/// let n = [[0.0, 0.0, 0.0], [0.1, 0.0, 0.0], [0.0, 0.1, 0.0], [0.0, 0.0, 1.0]];
/// assert_eq!(tet_shape(&n), TetShape::Needle);
/// ```
pub fn tet_shape(p: &[[f64; 3]; 4]) -> TetShape {
    let (p, _) = local(*p);
    let p = &p;
    let l = edge_lengths_raw(p);
    let longest = l.iter().copied().fold(0.0, f64::max);
    match l.iter().filter(|&&x| x < 0.3 * longest).count() {
        0 => {}
        1 => return TetShape::Wedge,
        _ => return TetShape::Needle,
    }
    let d = dihedral_angles(p);
    // A vertex near the opposite face: its three edges (between the nearly
    // coplanar side faces) have angles near 180°.
    let cap = (0..4).any(|k| {
        EDGES
            .iter()
            .zip(&d)
            .filter(|((i, j), _)| *i == k || *j == k)
            .all(|(_, &a)| a > 90.0)
    });
    if cap {
        TetShape::Cap
    } else {
        TetShape::Sliver
    }
}

/// `6√2 · volume / rms_edge³`: 1 for the regular tetrahedron, 0 for a flat
/// one, negative for an inverted one; invariant under scaling.
///
/// ```
/// use delone::tet::quality::shape_quality;
/// let reg = [[1.0, 1.0, 1.0], [-1.0, 1.0, -1.0], [1.0, -1.0, -1.0], [-1.0, -1.0, 1.0]];
/// assert!((shape_quality(&reg) - 1.0).abs() < 1e-12);
/// let flat = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]];
/// assert_eq!(shape_quality(&flat), 0.0);
/// ```
pub fn shape_quality(p: &[[f64; 3]; 4]) -> f64 {
    let (p, _) = local(*p);
    shape_quality_raw(&p, &edge_lengths_raw(&p))
}

/// [`shape_quality`] of points in a local frame with their
/// [`edge_lengths_raw`] `l`.
fn shape_quality_raw(p: &[[f64; 3]; 4], l: &[f64; 6]) -> f64 {
    let rms = (l.iter().map(|x| x * x).sum::<f64>() / 6.0).sqrt();
    if rms == 0.0 {
        return 0.0;
    }
    6.0 * std::f64::consts::SQRT_2 * volume_raw(p) / (rms * rms * rms)
}

/// Upper ends of the dihedral-angle histogram bins, degrees (the first bin
/// starts at 0). Fine bins near 0° and 180°, where slivers and caps live.
pub const DIHEDRAL_BINS: [f64; 22] = [
    1.0, 2.0, 3.0, 5.0, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 80.0, 90.0, 100.0, 110.0, 120.0,
    130.0, 140.0, 150.0, 160.0, 170.0, 180.0,
];

/// Upper ends of the radius-edge ratio histogram bins (the last is open).
pub const RATIO_BINS: [f64; 10] = [
    0.7,
    0.8,
    1.0,
    1.2,
    1.414,
    1.6,
    2.0,
    3.0,
    10.0,
    f64::INFINITY,
];

/// A summary of the quality of a set of tetrahedra.
///
/// ```
/// use delone::tet::quality::TetStats;
/// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
/// let s = TetStats::of(&pts, &[[0, 1, 2, 3]]);
/// assert_eq!(s.tets, 1);
/// assert!((s.min_dihedral - 54.7356).abs() < 1e-3);
/// assert_eq!(s.max_dihedral, 90.0);
/// assert_eq!(s.dihedral_histogram.iter().sum::<usize>(), 6);
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TetStats {
    /// Number of tetrahedra.
    pub tets: usize,
    /// Smallest dihedral angle (degrees); 180 when there are no tetrahedra.
    pub min_dihedral: f64,
    /// Largest dihedral angle (degrees); 0 when there are no tetrahedra.
    pub max_dihedral: f64,
    /// Dihedral angles per bin of [`DIHEDRAL_BINS`] (six per tetrahedron).
    pub dihedral_histogram: Vec<usize>,
    /// Smallest radius-edge ratio.
    pub min_radius_edge: f64,
    /// Largest radius-edge ratio.
    pub max_radius_edge: f64,
    /// Mean radius-edge ratio.
    pub mean_radius_edge: f64,
    /// Tetrahedra per bin of [`RATIO_BINS`].
    pub radius_edge_histogram: Vec<usize>,
    /// Smallest volume.
    pub min_volume: f64,
    /// Largest volume.
    pub max_volume: f64,
    /// Sum of the volumes.
    pub total_volume: f64,
    /// Smallest [`shape_quality`].
    pub min_shape: f64,
    /// Mean [`shape_quality`].
    pub mean_shape: f64,
    /// Shortest edge length (over all tetrahedra).
    pub min_edge: f64,
    /// Longest edge length.
    pub max_edge: f64,
}

fn bin(bins: &[f64], x: f64) -> usize {
    bins.iter().position(|&b| x < b).unwrap_or(bins.len() - 1)
}

impl TetStats {
    /// The statistics of `tets` (vertex ids into `points`).
    ///
    /// Tetrahedra naming a missing point are skipped.
    ///
    /// ```
    /// use delone::tet::quality::TetStats;
    /// let s = TetStats::of(&[], &[]);
    /// assert_eq!(s.tets, 0);
    /// ```
    pub fn of(points: &[[f64; 3]], tets: &[[u32; 4]]) -> TetStats {
        let mut s = TetStats {
            min_dihedral: 180.0,
            dihedral_histogram: vec![0; DIHEDRAL_BINS.len()],
            radius_edge_histogram: vec![0; RATIO_BINS.len()],
            min_radius_edge: f64::INFINITY,
            min_volume: f64::INFINITY,
            max_volume: f64::NEG_INFINITY,
            min_shape: f64::INFINITY,
            min_edge: f64::INFINITY,
            ..TetStats::default()
        };
        let (mut sum_ratio, mut sum_shape) = (0.0, 0.0);
        let mut tally = DihedralTally::new();
        for tv in tets {
            if tv.iter().any(|&q| q as usize >= points.len()) {
                continue;
            }
            // One local frame for every measure (each public function
            // makes the same one: the values are theirs).
            let (p, sc) = local(tv.map(|q| points[q as usize]));
            s.tets += 1;
            for x in dihedral_sin_cos_raw(&p) {
                tally.add(x, &mut s.dihedral_histogram);
            }
            let l = edge_lengths_raw(&p);
            let r = radius_edge_ratio_raw(&p, &l);
            s.min_radius_edge = s.min_radius_edge.min(r);
            s.max_radius_edge = s.max_radius_edge.max(r);
            sum_ratio += r;
            s.radius_edge_histogram[bin(&RATIO_BINS, r)] += 1;
            let v = unscale(volume_raw(&p), sc, 3);
            s.min_volume = s.min_volume.min(v);
            s.max_volume = s.max_volume.max(v);
            s.total_volume += v;
            let q = shape_quality_raw(&p, &l);
            s.min_shape = s.min_shape.min(q);
            sum_shape += q;
            for l in l.map(|l| unscale(l, sc, 1)) {
                s.min_edge = s.min_edge.min(l);
                s.max_edge = s.max_edge.max(l);
            }
        }
        (s.min_dihedral, s.max_dihedral) = (tally.min, tally.max);
        if s.tets > 0 {
            s.mean_radius_edge = sum_ratio / s.tets as f64;
            s.mean_shape = sum_shape / s.tets as f64;
        } else {
            s.min_radius_edge = 0.0;
            s.min_volume = 0.0;
            s.max_volume = 0.0;
            s.min_shape = 0.0;
            s.min_edge = 0.0;
        }
        s
    }

    /// The statistics as a JSON object (numbers with `f64`'s shortest
    /// round-trip form; infinities as `null`).
    ///
    /// ```
    /// use delone::tet::quality::TetStats;
    /// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    /// let j = TetStats::of(&pts, &[[0, 1, 2, 3]]).to_json();
    /// assert!(j.starts_with('{') && j.contains("\"tets\": 1"));
    /// ```
    pub fn to_json(&self) -> String {
        let num = |x: f64| {
            if x.is_finite() {
                format!("{x:?}")
            } else {
                "null".to_string()
            }
        };
        let list = |v: &[f64]| v.iter().map(|&x| num(x)).collect::<Vec<_>>().join(", ");
        let counts = |v: &[usize]| {
            v.iter()
                .map(|x| x.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        };
        let mut s = String::from("{\n");
        let _ = writeln!(s, "  \"tets\": {},", self.tets);
        for (k, x) in [
            ("min_dihedral", self.min_dihedral),
            ("max_dihedral", self.max_dihedral),
            ("min_radius_edge", self.min_radius_edge),
            ("max_radius_edge", self.max_radius_edge),
            ("mean_radius_edge", self.mean_radius_edge),
            ("min_volume", self.min_volume),
            ("max_volume", self.max_volume),
            ("total_volume", self.total_volume),
            ("min_shape", self.min_shape),
            ("mean_shape", self.mean_shape),
            ("min_edge", self.min_edge),
            ("max_edge", self.max_edge),
        ] {
            let _ = writeln!(s, "  \"{k}\": {},", num(x));
        }
        let lists = [
            ("dihedral_bins", list(&DIHEDRAL_BINS)),
            ("dihedral_histogram", counts(&self.dihedral_histogram)),
            ("radius_edge_bins", list(&RATIO_BINS)),
            ("radius_edge_histogram", counts(&self.radius_edge_histogram)),
        ];
        for (i, (k, v)) in lists.iter().enumerate() {
            let comma = if i + 1 < lists.len() { "," } else { "" };
            let _ = writeln!(s, "  \"{k}\": [{v}]{comma}");
        }
        s.push('}');
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The statistics' dihedral minimum, maximum and histogram equal those
    /// of every angle from [`dihedral_angles`], on random tetrahedra, ones
    /// with angles at bin bounds (right angles, 60°, flat) and degenerate
    /// ones.
    #[test]
    fn dihedral_tally_matches_angles() {
        let mut rng = crate::geom::SplitMix64::new(0x9e37_79b9_7f4a_7c15);
        let mut next = || (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        let mut pts = Vec::new();
        let mut tets = Vec::new();
        for i in 0..4000u32 {
            let p: [[f64; 3]; 4] = match i % 5 {
                // Corner tetrahedra: 90° and 60° / 45° angles.
                0 => [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
                1 => {
                    let h = next() * 1e-12;
                    [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.3, 0.4, h]]
                }
                2 => [
                    [0.0; 3],
                    [1.0, 0.0, 0.0],
                    [2.0, 0.0, 0.0],
                    [next(), next(), 0.0],
                ],
                _ => std::array::from_fn(|_| [next(), next(), next() * 1e-3f64.powf(next())]),
            };
            let b = pts.len() as u32;
            pts.extend(p);
            tets.push([b, b + 1, b + 2, b + 3]);
            // Regular-ish: a tetrahedron of the sheared corner family.
            let k = next() * 4.0;
            let q = [
                [0.0; 3],
                [1.0, 0.0, 0.0],
                [0.5, 0.75f64.sqrt(), 0.0],
                [0.5, k, 1.0],
            ];
            let b = pts.len() as u32;
            pts.extend(q);
            tets.push([b, b + 1, b + 2, b + 3]);
        }
        let st = TetStats::of(&pts, &tets);
        let (mut lo, mut hi) = (180.0f64, 0.0f64);
        let mut hist = vec![0usize; DIHEDRAL_BINS.len()];
        for t in &tets {
            for a in dihedral_angles(&t.map(|q| pts[q as usize])) {
                lo = lo.min(a);
                hi = hi.max(a);
                hist[bin(&DIHEDRAL_BINS, a)] += 1;
            }
        }
        assert_eq!(st.min_dihedral.to_bits(), lo.to_bits());
        assert_eq!(st.max_dihedral.to_bits(), hi.to_bits());
        assert_eq!(st.dihedral_histogram, hist);
        assert!(hist[0] > 0 && hist[DIHEDRAL_BINS.len() - 1] > 0);
    }

    #[test]
    fn regular_tet_angles() {
        let reg = crate::geom::vec3::regular_tet();
        let want = (1.0f64 / 3.0).acos().to_degrees(); // 70.5288°
        for a in dihedral_angles(&reg) {
            assert!((a - want).abs() < 1e-10, "{a}");
        }
        assert!((volume(&reg) - 8.0 / 3.0).abs() < 1e-12); // positively oriented
    }

    #[test]
    fn sliver_angles() {
        // Four points near a square's corners, slightly lifted alternately:
        // dihedral angles near 0 and 180 degrees, radius-edge ratio ~0.707.
        let h = 1e-3;
        let s = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, h],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, h],
        ];
        let s = if volume(&s) < 0.0 {
            [s[1], s[0], s[2], s[3]]
        } else {
            s
        };
        let d = dihedral_angles(&s);
        let min = d.iter().cloned().fold(180.0, f64::min);
        let max = d.iter().cloned().fold(0.0, f64::max);
        assert!(min < 1.0 && max > 179.0, "{d:?}");
        assert!((radius_edge_ratio(&s) - 0.5f64.sqrt()).abs() < 1e-3);
        assert!(shape_quality(&s).abs() < 1e-2);
        // Angles of a tetrahedron: at each vertex, the three dihedral angles
        // at its edges sum to more than 180 degrees.
        let at0 = d[0] + d[1] + d[2];
        assert!(at0 > 180.0 - 1e-9);
    }

    #[test]
    fn histogram_bins() {
        assert_eq!(bin(&DIHEDRAL_BINS, 0.5), 0);
        assert_eq!(bin(&DIHEDRAL_BINS, 90.0), 13);
        assert_eq!(bin(&DIHEDRAL_BINS, 180.0), DIHEDRAL_BINS.len() - 1);
        assert_eq!(bin(&RATIO_BINS, 2.5), 7);
    }
}
