//! Voronoi and power cells clipped to a polygonal domain (outer boundaries
//! and holes), and Lloyd relaxation inside such a domain.
//!
//! A domain is a set of closed rings. Nesting decides their role: a ring
//! inside an even number of other rings bounds material (made
//! counterclockwise), one inside an odd number bounds a hole (made
//! clockwise), so the domain is the sum of the rings' signed interiors.
//!
//! Each (convex) cell is intersected with every ring whose bounding box meets
//! the cell's by Sutherland–Hodgman clipping of the ring against the cell's
//! edges. For a non-convex ring the result may contain zero-width bridges
//! along the cell boundary; they carry no area, so signed areas and first
//! moments — what Lloyd relaxation needs — are exact up to rounding, and the
//! pieces draw correctly with the non-zero fill rule.

use super::voronoi::{clip_half, moments, Voronoi2};
use crate::geom::bbox;
use crate::Error;

/// Cells intersected with a polygonal domain ([`Voronoi2::cells_in_domain`]).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct DomainCells2 {
    /// Area of each site's cell inside the domain.
    pub area: Vec<f64>,
    /// Centroid of that part (the site itself when it is empty).
    pub centroid: Vec<[f64; 2]>,
    /// For each site, the clipped pieces (one per ring it meets; hole pieces
    /// clockwise), to be filled with the non-zero rule.
    pub pieces: Vec<Vec<Vec<[f64; 2]>>>,
}

/// Twice the signed area of `ring` (positive when counterclockwise).
fn signed_area2(ring: &[[f64; 2]]) -> f64 {
    moments(ring, &[0.0; 2]).0
}

/// Winding number of `ring` around `x` (non-zero: inside).
fn winding(ring: &[[f64; 2]], x: &[f64; 2]) -> i32 {
    let m = ring.len();
    let mut w = 0;
    for k in 0..m {
        let (a, b) = (ring[k], ring[(k + 1) % m]);
        let cross = (b[0] - a[0]) * (x[1] - a[1]) - (x[0] - a[0]) * (b[1] - a[1]);
        if a[1] <= x[1] {
            if b[1] > x[1] && cross > 0.0 {
                w += 1;
            }
        } else if b[1] <= x[1] && cross < 0.0 {
            w -= 1;
        }
    }
    w
}

/// The rings oriented by nesting depth (even: counterclockwise, odd:
/// clockwise), with their bounding boxes; rings of fewer than 3 corners are
/// dropped.
/// A ring's corners and its bounding box.
type Ring = (Vec<[f64; 2]>, [[f64; 2]; 2]);

fn oriented(rings: &[Vec<[f64; 2]>]) -> Vec<Ring> {
    let rings: Vec<&Vec<[f64; 2]>> = rings.iter().filter(|r| r.len() >= 3).collect();
    rings
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let depth = rings
                .iter()
                .enumerate()
                .filter(|&(j, o)| j != i && winding(o, &r[0]) != 0)
                .count();
            let mut r = r.to_vec();
            if (signed_area2(&r) > 0.0) != (depth % 2 == 0) {
                r.reverse();
            }
            let bb = bbox(&r);
            (r, bb)
        })
        .collect()
}

/// Sutherland–Hodgman: `subject` clipped to the convex counterclockwise
/// polygon `clip`, edge by edge ([`clip_half`]).
fn clip_to_convex(
    subject: &[[f64; 2]],
    clip: &[[f64; 2]],
    tmp: &mut Vec<[f64; 2]>,
) -> Vec<[f64; 2]> {
    let mut out = subject.to_vec();
    let m = clip.len();
    for k in 0..m {
        if out.is_empty() {
            break;
        }
        let (a, b) = (clip[k], clip[(k + 1) % m]);
        // Outside: right of a -> b.
        clip_half(&mut out, tmp, |x| {
            (x[0] - a[0]) * (b[1] - a[1]) - (b[0] - a[0]) * (x[1] - a[1])
        });
    }
    out
}

impl Voronoi2 {
    /// Every cell intersected with the polygonal domain bounded by `rings`
    /// (outer boundaries and holes, any orientation: nesting decides), with
    /// area, centroid and the clipped pieces — Detri2-style clipped cells for
    /// meshing inside a PSLG. Works for power diagrams too.
    ///
    /// ```
    /// // A unit square with a square hole, four sites.
    /// let outer = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
    /// let hole = vec![[0.4, 0.4], [0.6, 0.4], [0.6, 0.6], [0.4, 0.6]];
    /// let pts = [[0.25, 0.25], [0.75, 0.25], [0.25, 0.75], [0.75, 0.75]];
    /// let mesh = delone::triangulate(&pts).unwrap();
    /// let v = delone::tri::Voronoi2::new(&pts, &mesh).unwrap();
    /// let c = v.cells_in_domain(&pts, &[outer, hole]);
    /// let total: f64 = c.area.iter().sum();
    /// assert!((total - 0.96).abs() < 1e-12);
    /// assert!((c.area[0] - 0.24).abs() < 1e-12);
    /// ```
    pub fn cells_in_domain(&self, points: &[[f64; 2]], rings: &[Vec<[f64; 2]>]) -> DomainCells2 {
        let rings = oriented(rings);
        let n = points.len();
        let mut out = DomainCells2 {
            area: vec![0.0; n],
            centroid: points.to_vec(),
            pieces: vec![Vec::new(); n],
        };
        if rings.is_empty() {
            return out;
        }
        let bb = bbox(rings.iter().flat_map(|(_, rb)| rb));
        let boxed = self.cells_clipped(points, bb);
        let mut tmp = Vec::new();
        for (s, &site) in points.iter().enumerate() {
            let cell = boxed.polygon(s);
            if cell.len() < 3 {
                continue;
            }
            let cb = bbox(cell);
            let (mut a2, mut cx, mut cy) = (0.0, 0.0, 0.0);
            for (ring, rb) in &rings {
                let overlap = (0..2).all(|k| rb[0][k] <= cb[1][k] && cb[0][k] <= rb[1][k]);
                if !overlap {
                    continue;
                }
                let piece = clip_to_convex(ring, cell, &mut tmp);
                if piece.len() < 3 {
                    continue;
                }
                let (a, x, y) = moments(&piece, &site);
                if a == 0.0 {
                    continue;
                }
                a2 += a;
                cx += x;
                cy += y;
                out.pieces[s].push(piece);
            }
            if a2 > 0.0 {
                out.area[s] = 0.5 * a2;
                out.centroid[s] = [site[0] + cx / (3.0 * a2), site[1] + cy / (3.0 * a2)];
            }
        }
        out
    }
}

/// The boundary of a triangle mesh (edges without a neighbour) chained into
/// closed rings of coordinates — e.g. the domain of a carved constrained
/// triangulation ([`crate::tri::Cdt`]), to clip Voronoi cells to a PSLG's
/// domain with [`Voronoi2::cells_in_domain`]. `neighbors[t][i]` is the
/// triangle across the edge opposite vertex `i` ([`crate::NONE`] if none).
/// A vertex where the boundary pinches may split or join rings; signed
/// areas, and therefore clipped areas and centroids, are right either way.
///
/// ```
/// use delone::{model::pslg::Pslg, tri};
/// // A square with a square hole.
/// let mut g = Pslg::new(
///     vec![[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0], [1.0, 1.0], [3.0, 1.0], [3.0, 3.0], [1.0, 3.0]],
///     vec![[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4]],
/// );
/// g.holes.push([2.0, 2.0]);
/// let cdt = tri::constrained_triangulation(&g, tri::CdtOptions::default()).unwrap();
/// let rings = tri::boundary_rings(&cdt.points, &cdt.triangles, &cdt.neighbors);
/// assert_eq!(rings.len(), 2);
/// let sites = [[0.5, 0.5], [3.5, 3.5], [3.5, 0.5]];
/// let v = tri::Voronoi2::new(&sites, &delone::triangulate(&sites).unwrap()).unwrap();
/// let cells = v.cells_in_domain(&sites, &rings);
/// assert!((cells.area.iter().sum::<f64>() - 12.0).abs() < 1e-12);
/// ```
pub fn boundary_rings(
    points: &[[f64; 2]],
    triangles: &[[u32; 3]],
    neighbors: &[[u32; 3]],
) -> Vec<Vec<[f64; 2]>> {
    // Directed boundary edges a -> b (counterclockwise around the mesh).
    let mut next: Vec<(u32, u32)> = Vec::new();
    for (t, nb) in triangles.iter().zip(neighbors) {
        for i in 0..3 {
            if nb[i] == crate::NONE {
                next.push((t[(i + 1) % 3], t[(i + 2) % 3]));
            }
        }
    }
    next.sort_unstable();
    let mut used = vec![false; next.len()];
    let mut rings = Vec::new();
    for start in 0..next.len() {
        if used[start] {
            continue;
        }
        let mut ring = Vec::new();
        let mut k = start;
        loop {
            used[k] = true;
            let (a, b) = next[k];
            ring.push(points[a as usize]);
            // The first unused edge leaving b.
            let from = next.partition_point(|e| e.0 < b);
            match (from..next.len())
                .take_while(|&j| next[j].0 == b)
                .find(|&j| !used[j])
            {
                Some(j) => k = j,
                None => break,
            }
        }
        if ring.len() >= 3 {
            rings.push(ring);
        }
    }
    rings
}

/// Lloyd relaxation inside a polygonal domain (outer rings and holes, see
/// [`Voronoi2::cells_in_domain`]): `iterations` times, triangulate, clip the
/// cells to the domain and move each site to the centroid of its part.
/// Sites whose cell misses the domain stay; deterministic.
///
/// # Errors
/// The errors of [`crate::triangulate`].
///
/// ```
/// let outer = vec![[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]];
/// let pts: Vec<[f64; 2]> = (0..40).map(|i| [0.05 + (i as f64 * 0.37) % 1.9, 0.05 + (i as f64 * 0.61) % 0.9]).collect();
/// let out = delone::tri::lloyd_in_domain(&pts, &[outer], 5).unwrap();
/// assert!(out.iter().all(|p| p[0] > 0.0 && p[0] < 2.0 && p[1] > 0.0 && p[1] < 1.0));
/// ```
pub fn lloyd_in_domain(
    points: &[[f64; 2]],
    rings: &[Vec<[f64; 2]>],
    iterations: usize,
) -> Result<Vec<[f64; 2]>, Error> {
    crate::geom::lloyd(points, iterations, |pts| {
        let c = Voronoi2::new(pts, &super::triangulate(pts)?)?.cells_in_domain(pts, rings);
        Ok((c.area, c.centroid))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nesting_orients_rings() {
        let sq = |o: f64, s: f64| vec![[o, o], [o, o + s], [o + s, o + s], [o + s, o]]; // clockwise
        let r = oriented(&[sq(0.0, 10.0), sq(1.0, 8.0), sq(2.0, 6.0)]);
        assert!(signed_area2(&r[0].0) > 0.0);
        assert!(signed_area2(&r[1].0) < 0.0);
        assert!(signed_area2(&r[2].0) > 0.0);
    }

    #[test]
    fn clipping_a_concave_ring_keeps_exact_area() {
        // A U shape clipped by a square crossing both arms.
        let u = vec![
            [0.0, 0.0],
            [3.0, 0.0],
            [3.0, 3.0],
            [2.0, 3.0],
            [2.0, 1.0],
            [1.0, 1.0],
            [1.0, 3.0],
            [0.0, 3.0],
        ];
        let clip = vec![[-1.0, 2.0], [4.0, 2.0], [4.0, 4.0], [-1.0, 4.0]];
        let piece = clip_to_convex(&u, &clip, &mut Vec::new());
        let (a2, _, _) = moments(&piece, &[0.0, 0.0]);
        assert!((0.5 * a2 - 2.0).abs() < 1e-12, "area {}", 0.5 * a2);
    }
}
