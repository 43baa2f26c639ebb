//! Quality measures of 2D triangles and summary statistics of a mesh (what
//! Triangle prints with `-V`, plus histograms as numbers).
//!
//! Measures of one triangle ([`TriangleQuality`]):
//!
//! * the three angles, from `atan2(|cross|, dot)` of the two edges at each
//!   corner (accurate for needles and caps alike, unlike `acos`);
//! * the signed area (positive for counterclockwise triangles);
//! * the **aspect ratio**: longest edge / shortest altitude. The shortest
//!   altitude is the one onto the longest edge, so this is
//!   `longest² / (2 |area|)`; `2/√3 ≈ 1.1547` for the equilateral triangle,
//!   infinite for a degenerate one. It grows with both needles and caps;
//! * the **radius-edge ratio**: circumradius / shortest edge, the measure
//!   Delaunay refinement bounds (`1/√3 ≈ 0.577` at best; a minimum angle
//!   `θ` means a ratio of at most `1 / (2 sin θ)`).
//!
//! [`TriStats`] summarises a mesh: counts, extreme areas, edge lengths and
//! angles, an angle histogram in 10° bins (every angle of every triangle,
//! as Triangle's `-V` counts them), an aspect-ratio histogram over
//! [`ASPECT_BINS`], and optionally the Steiner points by kind. Its
//! [`Display`](std::fmt::Display) form is the `-V` report of `delone tri`.
//!
//! ```
//! use delone::tri::quality::{TriStats, TriangleQuality};
//! let q = TriangleQuality::new([0.0, 0.0], [1.0, 0.0], [0.0, 1.0]);
//! assert!((q.min_angle - 45.0).abs() < 1e-12 && (q.max_angle - 90.0).abs() < 1e-12);
//! assert!((q.aspect_ratio - 2.0).abs() < 1e-12); // longest √2, altitude √2/2
//! let s = TriStats::new(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]], &[[0, 1, 2]]).unwrap();
//! assert_eq!(s.angle_histogram[4], 2); // the two 45° angles
//! assert_eq!(s.angle_histogram[8], 0); // 90° falls in 90–100
//! assert_eq!(s.angle_histogram[9], 1);
//! ```

use crate::geom::scale::unscale;
use std::fmt;

use crate::Error;

/// Upper bounds of the aspect-ratio histogram bins of [`TriStats`]: bin `k`
/// counts triangles with `ASPECT_BINS[k-1] <= ratio < ASPECT_BINS[k]` (bin 0
/// starts at the equilateral value 2/√3, the last bin is unbounded).
///
/// ```
/// assert_eq!(delone::tri::quality::ASPECT_BINS.len(), 10);
/// ```
pub const ASPECT_BINS: [f64; 10] = [
    1.5,
    2.0,
    3.0,
    5.0,
    10.0,
    20.0,
    50.0,
    100.0,
    1000.0,
    f64::INFINITY,
];

/// Shape and size of one triangle (see the [module](self) docs for the
/// definitions).
///
/// ```
/// let q = delone::tri::quality::TriangleQuality::new([0.0, 0.0], [2.0, 0.0], [1.0, 3f64.sqrt()]);
/// assert!((q.min_angle - 60.0).abs() < 1e-9);
/// assert!((q.radius_edge - 1.0 / 3f64.sqrt()).abs() < 1e-12);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TriangleQuality {
    /// The angles at the three corners, in degrees.
    pub angles: [f64; 3],
    /// The smallest angle, in degrees.
    pub min_angle: f64,
    /// The largest angle, in degrees.
    pub max_angle: f64,
    /// Signed area (positive when the corners are counterclockwise).
    pub area: f64,
    /// Shortest edge length.
    pub shortest_edge: f64,
    /// Longest edge length.
    pub longest_edge: f64,
    /// Longest edge / shortest altitude (infinite when the area is zero).
    pub aspect_ratio: f64,
    /// Circumradius / shortest edge (infinite when the area is zero).
    pub radius_edge: f64,
}

impl TriangleQuality {
    /// The measures of the triangle `a, b, c`.
    ///
    /// ```
    /// let q = delone::tri::quality::TriangleQuality::new([0.0, 0.0], [1.0, 0.0], [2.0, 0.0]);
    /// assert_eq!(q.area, 0.0);
    /// assert!(q.aspect_ratio.is_infinite());
    /// assert_eq!(q.max_angle, 180.0);
    /// ```
    pub fn new(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Self {
        // Measured on the triangle scaled by a power of two (exact): no
        // overflow or underflow at any scale, angles and ratios the same
        // bit for bit at every power-of-two scale; area and lengths are
        // brought back to the input's units.
        let (p, s) = crate::geom::scale::local([a, b, c]);
        let [a, b, c] = p;
        let mut angles = [0.0; 3];
        let mut len2 = [0.0; 3]; // len2[k]: squared length of the edge opposite corner k
        for k in 0..3 {
            let o = p[k];
            let u = [p[(k + 1) % 3][0] - o[0], p[(k + 1) % 3][1] - o[1]];
            let v = [p[(k + 2) % 3][0] - o[0], p[(k + 2) % 3][1] - o[1]];
            let cross = u[0] * v[1] - u[1] * v[0];
            let dot = u[0] * v[0] + u[1] * v[1];
            angles[k] = cross.abs().atan2(dot).to_degrees();
            let w = [v[0] - u[0], v[1] - u[1]];
            len2[k] = w[0] * w[0] + w[1] * w[1];
        }
        let cross = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        let area = 0.5 * cross;
        let lmin = len2.iter().copied().fold(f64::INFINITY, f64::min).sqrt();
        let lmax = len2.iter().copied().fold(0.0, f64::max).sqrt();
        let (aspect_ratio, radius_edge) = if area == 0.0 {
            (f64::INFINITY, f64::INFINITY)
        } else {
            let two_a = cross.abs();
            let r = len2.iter().map(|l| l.sqrt()).product::<f64>() / (2.0 * two_a);
            (lmax * lmax / two_a, r / lmin)
        };
        TriangleQuality {
            angles,
            min_angle: angles.iter().copied().fold(180.0, f64::min),
            max_angle: angles.iter().copied().fold(0.0, f64::max),
            area: unscale(area, s, 2),
            shortest_edge: unscale(lmin, s, 1),
            longest_edge: unscale(lmax, s, 1),
            aspect_ratio,
            radius_edge,
        }
    }
}

/// Steiner points added by the mesher, by kind (reported by [`TriStats`]
/// when given).
///
/// ```
/// let s = delone::tri::quality::SteinerCounts { crossings: 1, segment_splits: 2, interior: 3 };
/// assert_eq!(s.total(), 6);
/// ```
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SteinerCounts {
    /// Vertices created where two input segments cross.
    pub crossings: usize,
    /// Vertices inserted on subsegments (refinement splits).
    pub segment_splits: usize,
    /// Vertices inserted inside the domain (circumcentres / off-centres).
    pub interior: usize,
}

impl SteinerCounts {
    /// All Steiner points.
    ///
    /// ```
    /// assert_eq!(delone::tri::quality::SteinerCounts::default().total(), 0);
    /// ```
    pub fn total(&self) -> usize {
        self.crossings + self.segment_splits + self.interior
    }
}

/// Summary statistics of a 2D mesh.
///
/// ```
/// use delone::tri::quality::TriStats;
/// let pts = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
/// let s = TriStats::new(&pts, &[[0, 1, 2], [0, 2, 3]]).unwrap();
/// assert_eq!((s.vertices, s.triangles, s.edges, s.boundary_edges), (4, 2, 5, 4));
/// assert_eq!(s.min_area, 0.5);
/// assert!((s.longest_edge - 2f64.sqrt()).abs() < 1e-15);
/// assert_eq!(s.aspect_histogram[2], 2); // ratio 2 is in [2, 3)
/// assert!(s.to_string().contains("Angle histogram"));
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct TriStats {
    /// Number of points referenced by at least one triangle.
    pub vertices: usize,
    /// Number of triangles.
    pub triangles: usize,
    /// Number of distinct edges.
    pub edges: usize,
    /// Edges with one triangle (the domain boundary, holes included).
    pub boundary_edges: usize,
    /// Smallest triangle area (absolute value; 0 without triangles).
    pub min_area: f64,
    /// Largest triangle area.
    pub max_area: f64,
    /// Sum of the triangle areas.
    pub total_area: f64,
    /// Shortest edge length.
    pub shortest_edge: f64,
    /// Longest edge length.
    pub longest_edge: f64,
    /// Shortest altitude of any triangle.
    pub shortest_altitude: f64,
    /// Smallest angle, degrees.
    pub min_angle: f64,
    /// Largest angle, degrees.
    pub max_angle: f64,
    /// Smallest aspect ratio (longest edge / shortest altitude).
    pub min_aspect_ratio: f64,
    /// Largest aspect ratio.
    pub max_aspect_ratio: f64,
    /// Largest radius-edge ratio (circumradius / shortest edge).
    pub max_radius_edge: f64,
    /// Angles (3 per triangle) in 10° bins: bin `k` counts
    /// `10k <= angle < 10(k+1)` (180° goes into the last bin).
    pub angle_histogram: [usize; 18],
    /// Triangles per aspect-ratio bin (see [`ASPECT_BINS`]).
    pub aspect_histogram: [usize; 10],
    /// Steiner points by kind, when the caller knows them.
    pub steiner: Option<SteinerCounts>,
}

impl TriStats {
    /// Statistics of the triangles `triangles` over `points`.
    ///
    /// # Errors
    /// [`Error::IndexOutOfRange`] (item `"triangle"`) naming the first
    /// triangle with a vertex id past `points`, [`Error::InvalidCoordinate`]
    /// naming a used point with a NaN or infinite coordinate.
    ///
    /// ```
    /// use delone::tri::quality::TriStats;
    /// let e = TriStats::new(&[[0.0, 0.0]], &[[0, 1, 2]]).unwrap_err();
    /// assert!(matches!(e, delone::Error::IndexOutOfRange { index: 0, vertex: 1, .. }));
    /// let empty = TriStats::new(&[], &[]).unwrap();
    /// assert_eq!(empty.triangles, 0);
    /// ```
    pub fn new(points: &[[f64; 2]], triangles: &[[u32; 3]]) -> Result<TriStats, Error> {
        let n = points.len();
        crate::geom::check::corners_valid("triangle", points, triangles)?;
        let mut used = vec![false; n];
        for &v in triangles.iter().flatten() {
            used[v as usize] = true;
        }
        // Edges: every directed edge as (min, max, direction); an undirected
        // edge seen twice is interior. Sorting keeps this deterministic.
        let mut keys: Vec<u64> = Vec::with_capacity(3 * triangles.len());
        for tri in triangles {
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                keys.push((u64::from(a.min(b)) << 32) | u64::from(a.max(b)));
            }
        }
        keys.sort_unstable();
        let edges = keys.chunk_by(|a, b| a == b).count();
        let boundary_edges = keys
            .chunk_by(|a, b| a == b)
            .filter(|r| r.len() == 1)
            .count();
        let empty = triangles.is_empty();
        let mut s = TriStats {
            vertices: used.iter().filter(|&&u| u).count(),
            triangles: triangles.len(),
            edges,
            boundary_edges,
            min_area: if empty { 0.0 } else { f64::INFINITY },
            max_area: 0.0,
            total_area: 0.0,
            shortest_edge: if empty { 0.0 } else { f64::INFINITY },
            longest_edge: 0.0,
            shortest_altitude: if empty { 0.0 } else { f64::INFINITY },
            min_angle: if empty { 0.0 } else { 180.0 },
            max_angle: 0.0,
            min_aspect_ratio: if empty { 0.0 } else { f64::INFINITY },
            max_aspect_ratio: 0.0,
            max_radius_edge: 0.0,
            angle_histogram: [0; 18],
            aspect_histogram: [0; 10],
            steiner: None,
        };
        for tri in triangles {
            // Measured on the triangle scaled by a power of two (see
            // TriangleQuality::new), the altitude too, then in input units.
            let (p, sc) = crate::geom::scale::local(tri.map(|v| points[v as usize]));
            let [a, b, c] = p;
            let q = TriangleQuality::new(a, b, c);
            let area = unscale(q.area.abs(), sc, 2);
            s.min_area = s.min_area.min(area);
            s.max_area = s.max_area.max(area);
            s.total_area += area;
            s.shortest_edge = s.shortest_edge.min(unscale(q.shortest_edge, sc, 1));
            s.longest_edge = s.longest_edge.max(unscale(q.longest_edge, sc, 1));
            let alt = if q.longest_edge > 0.0 {
                unscale(2.0 * q.area.abs() / q.longest_edge, sc, 1)
            } else {
                0.0
            };
            s.shortest_altitude = s.shortest_altitude.min(alt);
            s.min_angle = s.min_angle.min(q.min_angle);
            s.max_angle = s.max_angle.max(q.max_angle);
            s.min_aspect_ratio = s.min_aspect_ratio.min(q.aspect_ratio);
            s.max_aspect_ratio = s.max_aspect_ratio.max(q.aspect_ratio);
            s.max_radius_edge = s.max_radius_edge.max(q.radius_edge);
            for &ang in &q.angles {
                s.angle_histogram[angle_bin(ang)] += 1;
            }
            s.aspect_histogram[aspect_bin(q.aspect_ratio)] += 1;
        }
        Ok(s)
    }

    /// The same statistics with the Steiner points by kind attached.
    ///
    /// ```
    /// use delone::tri::quality::{SteinerCounts, TriStats};
    /// let s = TriStats::new(&[], &[]).unwrap()
    ///     .with_steiner(SteinerCounts { crossings: 1, ..Default::default() });
    /// assert_eq!(s.steiner.unwrap().total(), 1);
    /// ```
    pub fn with_steiner(mut self, steiner: SteinerCounts) -> Self {
        self.steiner = Some(steiner);
        self
    }
}

/// The 10° bin of an angle in degrees (180 in the last bin; NaN in bin 0).
fn angle_bin(deg: f64) -> usize {
    if deg.is_nan() || deg <= 0.0 {
        0
    } else {
        ((deg / 10.0) as usize).min(17)
    }
}

/// The [`ASPECT_BINS`] bin of an aspect ratio.
fn aspect_bin(r: f64) -> usize {
    ASPECT_BINS
        .iter()
        .position(|&b| r < b)
        .unwrap_or(ASPECT_BINS.len() - 1)
}

impl fmt::Display for TriStats {
    /// The `-V` report: counts, extremes, then the two histograms side by
    /// side in two columns.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "Mesh quality statistics:")?;
        writeln!(
            f,
            "  {} vertices, {} triangles, {} edges, {} boundary edges",
            self.vertices, self.triangles, self.edges, self.boundary_edges
        )?;
        if let Some(st) = &self.steiner {
            writeln!(
                f,
                "  Steiner points: {} ({} at segment crossings, {} on segments, {} interior)",
                st.total(),
                st.crossings,
                st.segment_splits,
                st.interior
            )?;
        }
        writeln!(
            f,
            "  Smallest area: {:>14.6e}   |  Largest area: {:>14.6e}   |  Total area: {:.6e}",
            self.min_area, self.max_area, self.total_area
        )?;
        writeln!(
            f,
            "  Shortest edge: {:>14.6e}   |  Longest edge: {:>14.6e}",
            self.shortest_edge, self.longest_edge
        )?;
        writeln!(
            f,
            "  Shortest altitude: {:>10.6e}   |  Largest aspect ratio: {:.6}",
            self.shortest_altitude, self.max_aspect_ratio
        )?;
        writeln!(
            f,
            "  Smallest angle: {:>13.6}   |  Largest angle: {:>13.6}",
            self.min_angle, self.max_angle
        )?;
        writeln!(
            f,
            "  Aspect ratio histogram (longest edge / shortest altitude):"
        )?;
        let label = |k: usize| -> String {
            let lo = if k == 0 {
                "1.1547".to_string()
            } else {
                format!("{}", ASPECT_BINS[k - 1])
            };
            let hi = if ASPECT_BINS[k].is_finite() {
                format!("{}", ASPECT_BINS[k])
            } else {
                "inf".to_string()
            };
            format!("{lo:>6} - {hi:<6}")
        };
        let half = ASPECT_BINS.len() / 2;
        for k in 0..half {
            writeln!(
                f,
                "    {}: {:>10}   |  {}: {:>10}",
                label(k),
                self.aspect_histogram[k],
                label(k + half),
                self.aspect_histogram[k + half]
            )?;
        }
        writeln!(f, "  Angle histogram (degrees; 3 angles per triangle):")?;
        for k in 0..9 {
            writeln!(
                f,
                "    {:>3} - {:>3}: {:>10}   |  {:>3} - {:>3}: {:>10}",
                10 * k,
                10 * k + 10,
                self.angle_histogram[k],
                10 * (k + 9),
                10 * (k + 10),
                self.angle_histogram[k + 9]
            )?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn right_isosceles_by_hand() {
        // Legs 2: area 2, hypotenuse 2√2, altitude onto it √2, R = √2.
        let q = TriangleQuality::new([0.0, 0.0], [2.0, 0.0], [0.0, 2.0]);
        assert_eq!(q.area, 2.0);
        assert!((q.angles[0] - 90.0).abs() < 1e-12);
        assert!((q.angles[1] - 45.0).abs() < 1e-12);
        assert!((q.longest_edge - 8f64.sqrt()).abs() < 1e-15);
        assert_eq!(q.shortest_edge, 2.0);
        assert!((q.aspect_ratio - 2.0).abs() < 1e-12);
        assert!((q.radius_edge - 2f64.sqrt() / 2.0).abs() < 1e-12);
        // Clockwise: negative area, same shape.
        let r = TriangleQuality::new([0.0, 0.0], [0.0, 2.0], [2.0, 0.0]);
        assert_eq!(r.area, -2.0);
        assert_eq!(r.aspect_ratio, q.aspect_ratio);
    }

    #[test]
    fn needle_and_cap() {
        // Needle: 10 × 0.1 right triangle. Smallest angle atan(0.01)...
        let q = TriangleQuality::new([0.0, 0.0], [10.0, 0.0], [0.0, 0.1]);
        assert!((q.min_angle - 0.01f64.atan().to_degrees()).abs() < 1e-10);
        // Cap: 170° apex.
        let h = (5f64).to_radians().tan();
        let c = TriangleQuality::new([-1.0, 0.0], [1.0, 0.0], [0.0, h]);
        assert!((c.max_angle - 170.0).abs() < 1e-9);
        assert!((c.aspect_ratio - 4.0 / (2.0 * h)).abs() < 1e-9);
    }

    #[test]
    fn mesh_stats_by_hand() {
        // A 2×1 rectangle split into a right isosceles triangle (legs 1)
        // and a trapezoid-free fan: vertices (0,0),(2,0),(2,1),(0,1),(1,1).
        let pts = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0], [1.0, 1.0]];
        let tris = [[0, 1, 4], [1, 2, 4], [0, 4, 3]];
        let s = TriStats::new(&pts, &tris).unwrap();
        assert_eq!(s.vertices, 5);
        assert_eq!(s.triangles, 3);
        assert_eq!(s.edges, 7);
        assert_eq!(s.boundary_edges, 5);
        assert_eq!(s.total_area, 2.0);
        assert_eq!(s.min_area, 0.5);
        assert_eq!(s.max_area, 1.0);
        assert_eq!(s.shortest_edge, 1.0);
        assert_eq!(s.longest_edge, 2.0);
        // Triangles 1 and 2 are right isosceles with legs 1 (angles 90, 45,
        // 45); triangle 0 is isosceles with base 2 and apex 90° at (1, 1).
        assert_eq!(s.angle_histogram[4], 6);
        assert_eq!(s.angle_histogram[9], 3);
        assert_eq!(s.angle_histogram.iter().sum::<usize>(), 9);
        assert!((s.min_angle - 45.0).abs() < 1e-12);
        assert!((s.max_angle - 90.0).abs() < 1e-12);
        assert_eq!(s.aspect_histogram[2], 3, "{s:?}"); // ratio 2: bin [2, 3)
        assert!((s.shortest_altitude - 0.5f64.sqrt()).abs() < 1e-15);
    }

    #[test]
    fn bins() {
        assert_eq!(angle_bin(0.0), 0);
        assert_eq!(angle_bin(9.999), 0);
        assert_eq!(angle_bin(10.0), 1);
        assert_eq!(angle_bin(180.0), 17);
        assert_eq!(angle_bin(f64::NAN), 0);
        assert_eq!(aspect_bin(1.2), 0);
        assert_eq!(aspect_bin(1.5), 1);
        assert_eq!(aspect_bin(f64::INFINITY), 9);
    }

    #[test]
    fn bad_input() {
        let e = TriStats::new(&[[0.0, 0.0], [1.0, f64::NAN], [0.0, 1.0]], &[[0, 1, 2]]);
        assert_eq!(e, Err(Error::InvalidCoordinate { index: 1 }));
    }
}
