//! Piecewise linear complexes (3D meshing input).
//!
//! A [`Plc`] is what TetGen's `.poly`/`.smesh` files describe: points,
//! planar facets (each a set of polygons — the outer boundary, hole
//! boundaries, and any segments the facet must contain — plus points inside
//! the facet's holes and a boundary marker), optional free segments, volume
//! holes and regions. [`Plc::validate`] checks it exactly;
//! [`Plc::merge_duplicate_points`] merges exactly coincident points.
//! Self-intersection and closedness checks live in [`crate::tet::intersect`],
//! the triangulation of the facets in [`crate::tet::facets`]: this module
//! holds the data and its validation only.

use super::key;
use crate::error::{Error, FacetDefect};
use crate::geom::check::ids_in_range;
use crate::geom::vec3::collinear;
use delone_predicates::{orient2d, orient3d};
use std::collections::HashMap;

/// One planar facet of a [`Plc`].
///
/// ```
/// let f = delone::model::plc::Facet::polygon(vec![0, 1, 2, 3]);
/// assert_eq!(f.polygons, vec![vec![0, 1, 2, 3]]);
/// assert_eq!(f.marker, 0);
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Facet {
    /// Polygons of the facet (point indices): the outer boundary, the
    /// boundaries of holes, and segments or points the facet must contain
    /// (TetGen's facet polygons). Polygons with 2 corners are segments,
    /// polygons with one corner isolated points of the facet.
    pub polygons: Vec<Vec<u32>>,
    /// One point inside each hole of the facet.
    pub holes: Vec<[f64; 3]>,
    /// Boundary marker, copied to the output faces.
    pub marker: i32,
}

impl Facet {
    /// A facet made of one polygon, no holes, marker 0.
    ///
    /// ```
    /// let f = delone::model::plc::Facet::polygon(vec![0, 1, 2]);
    /// assert!(f.holes.is_empty());
    /// ```
    pub fn polygon(corners: Vec<u32>) -> Self {
        Facet {
            polygons: vec![corners],
            holes: Vec::new(),
            marker: 0,
        }
    }
}

/// A region of a [`Plc`]: a seed point, an attribute given to the
/// tetrahedra of the region, and an optional volume bound.
///
/// ```
/// let r = delone::model::plc::Region { point: [0.5; 3], attribute: 2.0, max_volume: None };
/// assert_eq!(r.attribute, 2.0);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Region {
    /// A point inside the region.
    pub point: [f64; 3],
    /// Regional attribute (TetGen `-A`).
    pub attribute: f64,
    /// Maximum tetrahedron volume inside the region (TetGen `-a` with
    /// regions); `None` for no bound.
    pub max_volume: Option<f64>,
}

/// A piecewise linear complex: the input of 3D constrained meshing.
///
/// ```
/// use delone::model::plc::{Facet, Plc};
/// let mut plc = Plc::new(vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
/// for f in [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]] {
///     plc.facets.push(Facet::polygon(f.to_vec()));
/// }
/// assert!(plc.validate().is_ok());
/// assert_eq!(plc.triangles(), Some(vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]]));
/// // The same tetrahedron from plain arrays: points and triangles.
/// let pts = plc.points.clone();
/// let same = Plc::from_triangles(pts, &[[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]]);
/// assert_eq!(same, plc);
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Plc {
    /// Point coordinates.
    pub points: Vec<[f64; 3]>,
    /// Planar facets.
    pub facets: Vec<Facet>,
    /// Segments that must appear in the mesh (besides facet edges).
    pub segments: Vec<[u32; 2]>,
    /// Volume holes: one point inside each hole.
    pub holes: Vec<[f64; 3]>,
    /// Regions: attributes and volume bounds.
    pub regions: Vec<Region>,
}

impl Plc {
    /// A PLC with these points and nothing else.
    ///
    /// ```
    /// let plc = delone::model::plc::Plc::new(vec![[0.0; 3]]);
    /// assert!(plc.facets.is_empty());
    /// ```
    pub fn new(points: Vec<[f64; 3]>) -> Self {
        Plc {
            points,
            ..Plc::default()
        }
    }

    /// A PLC whose facets are the given triangles (a triangulated surface).
    ///
    /// ```
    /// let plc = delone::model::plc::Plc::from_triangles(vec![[0.0; 3]; 3], &[[0, 1, 2]]);
    /// assert_eq!(plc.facets.len(), 1);
    /// ```
    pub fn from_triangles(points: Vec<[f64; 3]>, triangles: &[[u32; 3]]) -> Self {
        Plc {
            points,
            facets: triangles
                .iter()
                .map(|t| Facet::polygon(t.to_vec()))
                .collect(),
            ..Plc::default()
        }
    }

    /// A PLC whose facets are the given polygons (one polygon each, marker
    /// 0): a polyhedral surface from plain arrays.
    ///
    /// ```
    /// use delone::model::plc::Plc;
    /// // A unit cube from its corners and its six quadrilaterals.
    /// let pts = (0..8).map(|k| [(k & 1) as f64, (k >> 1 & 1) as f64, (k >> 2) as f64]).collect();
    /// let quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    /// let plc = Plc::from_polygons(pts, quads.iter().map(|q| q.to_vec()));
    /// assert_eq!(plc.facets.len(), 6);
    /// plc.validate().unwrap();
    /// ```
    pub fn from_polygons(
        points: Vec<[f64; 3]>,
        polygons: impl IntoIterator<Item = Vec<u32>>,
    ) -> Self {
        Plc {
            points,
            facets: polygons.into_iter().map(Facet::polygon).collect(),
            ..Plc::default()
        }
    }

    /// The facets as triangles, if every facet is a single triangle;
    /// `None` otherwise.
    ///
    /// ```
    /// use delone::model::plc::{Facet, Plc};
    /// let mut plc = Plc::new(vec![[0.0; 3]; 4]);
    /// plc.facets.push(Facet::polygon(vec![0, 1, 2, 3]));
    /// assert_eq!(plc.triangles(), None);
    /// ```
    pub fn triangles(&self) -> Option<Vec<[u32; 3]>> {
        self.facets
            .iter()
            .map(|f| match f.polygons.as_slice() {
                [p] if p.len() == 3 => Some([p[0], p[1], p[2]]),
                _ => None,
            })
            .collect()
    }

    /// Checks the PLC exactly and returns the first problem found, naming the
    /// offending item:
    ///
    /// * [`Error::InvalidCoordinate`] — a point with a NaN/infinite coordinate;
    /// * [`Error::InvalidSeedPoint`] — the same for a hole or region point;
    /// * [`Error::IndexOutOfRange`] — a facet or segment refers to a missing point;
    /// * [`Error::DegenerateFacet`] — a facet with no polygon, an empty
    ///   polygon, or only polygons of fewer than 3 corners (segments and
    ///   isolated points inside a facet, with 2 and 1 corners, are allowed
    ///   next to a boundary polygon), a point repeated in a polygon (by index or by
    ///   coordinates), all points collinear (zero area), or points off the
    ///   facet's plane (exact [`orient3d`]). For a segment (listed by its index
    ///   in [`Plc::segments`]) the defect is `TooFewVertices` when both ends
    ///   are the same point.
    ///
    /// Facets are checked in order, so the error names the first bad one.
    ///
    /// # Errors
    /// As listed above.
    ///
    /// ```
    /// use delone::model::plc::{Facet, Plc};
    /// use delone::{Error, FacetDefect};
    /// let mut plc = Plc::new(vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    /// plc.facets.push(Facet::polygon(vec![0, 1, 3]));
    /// plc.facets.push(Facet::polygon(vec![0, 1, 2]));
    /// assert_eq!(plc.validate(), Err(Error::DegenerateFacet { index: 1, defect: FacetDefect::ZeroArea }));
    /// plc.facets[1] = Facet::polygon(vec![0, 1, 7]);
    /// assert!(matches!(plc.validate(), Err(Error::IndexOutOfRange { item: "facet", index: 1, vertex: 7, .. })));
    /// ```
    pub fn validate(&self) -> Result<(), Error> {
        let n = self.points.len();
        if n > u32::MAX as usize {
            return Err(Error::CapacityExceeded { requested: n });
        }
        super::check_coordinates(
            &self.points,
            &self.holes,
            self.regions.iter().map(|r| r.point),
        )?;
        // The exact tests below run on a copy scaled by a power of two
        // (exact), so that no product over- or underflows at any scale.
        let (sp, _) = crate::geom::rescaled(&self.points);
        let finite = |p: &[f64; 3]| p.iter().all(|c| c.is_finite());
        for (index, s) in self.segments.iter().enumerate() {
            ids_in_range("segment", index, s, n)?;
            if s[0] == s[1] || self.points[s[0] as usize] == self.points[s[1] as usize] {
                return Err(Error::DegenerateFacet {
                    index,
                    defect: FacetDefect::TooFewVertices,
                });
            }
        }
        for (index, f) in self.facets.iter().enumerate() {
            if !f.holes.iter().all(finite) {
                return Err(Error::InvalidSeedPoint {
                    kind: "facet hole",
                    index,
                });
            }
            self.check_facet(&sp, index, f)?;
        }
        Ok(())
    }

    /// Checks facet `index`; `points` are [`Plc::points`] scaled by a power
    /// of two.
    fn check_facet(&self, points: &[[f64; 3]], index: usize, f: &Facet) -> Result<(), Error> {
        let n = points.len();
        // Fast path for the common case, a single valid triangle: corners
        // in range, pairwise distinct points, not collinear (then it is
        // planar). Anything else takes the general checks below, which
        // name the defect.
        if let [p] = &f.polygons[..] {
            if let [a, b, c] = p[..] {
                if [a, b, c].iter().all(|&v| (v as usize) < n) {
                    let [pa, pb, pc] = [a, b, c].map(|v| &points[v as usize]);
                    let [ka, kb, kc] = [pa, pb, pc].map(key);
                    if ka != kb && kb != kc && ka != kc && !collinear(pa, pb, pc) {
                        return Ok(());
                    }
                }
            }
        }
        let bad = |defect| Err(Error::DegenerateFacet { index, defect });
        if f.polygons.is_empty() || f.polygons.iter().all(|p| p.len() < 3) {
            for p in &f.polygons {
                ids_in_range("facet", index, p, n)?;
            }
            return bad(FacetDefect::TooFewVertices);
        }
        let mut sorted: Vec<(u32, [u64; 3])> = Vec::new();
        for p in &f.polygons {
            ids_in_range("facet", index, p, n)?;
            if p.is_empty() {
                return bad(FacetDefect::TooFewVertices);
            }
            // Repeated corners, by index or by (exact) coordinates.
            sorted.clear();
            sorted.extend(p.iter().map(|&v| (v, key(&points[v as usize]))));
            sorted.sort_unstable_by_key(|&(v, k)| (k, v));
            if let Some(w) = sorted.windows(2).find(|w| w[0].1 == w[1].1) {
                return bad(FacetDefect::RepeatedVertex { vertex: w[1].0 });
            }
        }
        // Exact planarity: find three non-collinear corners, test the rest.
        let corners: Vec<u32> = f.polygons.iter().flatten().copied().collect();
        let pt = |v: u32| &points[v as usize];
        let a = corners[0];
        let Some(&b) = corners.iter().find(|&&v| pt(v) != pt(a)) else {
            return bad(FacetDefect::ZeroArea);
        };
        // (A corner equal to `a` or `b` is collinear with them: skipped.)
        let Some(&c) = corners
            .iter()
            .find(|&&v| pt(v) != pt(a) && pt(v) != pt(b) && !collinear(pt(a), pt(b), pt(v)))
        else {
            return bad(FacetDefect::ZeroArea);
        };
        if let Some(&d) = corners.iter().find(|&&v| {
            // The three chosen corners are coplanar with themselves.
            v != a && v != b && v != c && orient3d(pt(a), pt(b), pt(c), pt(v)) != 0.0
        }) {
            return bad(FacetDefect::NonPlanar { vertex: d });
        }
        Ok(())
    }

    /// Merges points with exactly equal coordinates (`0.0` and `-0.0` are
    /// equal), keeping the first occurrence, and renumbers facets and
    /// segments. Deterministic. Returns, for each old point, its new index.
    ///
    /// Merging can make polygons repeat a point; [`Plc::validate`] reports
    /// that afterwards.
    ///
    /// ```
    /// use delone::model::plc::{Facet, Plc};
    /// let mut plc = Plc::new(vec![[0.0; 3], [1.0, 0.0, 0.0], [-0.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    /// plc.facets.push(Facet::polygon(vec![2, 1, 3]));
    /// assert_eq!(plc.merge_duplicate_points(), vec![0, 1, 0, 2]);
    /// assert_eq!(plc.facets[0].polygons, vec![vec![0, 1, 2]]);
    /// assert_eq!(plc.points.len(), 3);
    /// ```
    pub fn merge_duplicate_points(&mut self) -> Vec<u32> {
        let mut seen: HashMap<[u64; 3], u32> = HashMap::with_capacity(self.points.len());
        let mut kept = Vec::with_capacity(self.points.len());
        let map: Vec<u32> = self
            .points
            .iter()
            .map(|p| {
                *seen.entry(key(p)).or_insert_with(|| {
                    kept.push(*p);
                    (kept.len() - 1) as u32
                })
            })
            .collect();
        self.points = kept;
        let re = |v: &mut u32| {
            if let Some(&m) = map.get(*v as usize) {
                *v = m;
            }
        };
        for f in &mut self.facets {
            f.polygons.iter_mut().flatten().for_each(re);
        }
        self.segments.iter_mut().flatten().for_each(re);
        map
    }
}

/// Where a point lies on a (closed) triangle `[a, b, c]`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum OnTriangle {
    /// Strictly inside.
    Inside,
    /// Strictly inside edge `k` (from corner `k` to corner `k + 1`).
    Edge(usize),
    /// At corner `k` (same coordinates).
    Corner(usize),
}

/// Where `p` lies on the closed triangle `a b c`, exactly (`orient3d` on
/// its plane, then `orient2d` in a coordinate projection where the
/// triangle is not degenerate: on the plane that projection is a
/// bijection, so the answer is exact). `None`: off the triangle, or the
/// triangle is degenerate.
pub(crate) fn on_triangle(
    a: &[f64; 3],
    b: &[f64; 3],
    c: &[f64; 3],
    p: &[f64; 3],
) -> Option<OnTriangle> {
    if orient3d(a, b, c, p) != 0.0 {
        return None;
    }
    let (i, j) = crate::geom::vec3::projection_axes(a, b, c)?;
    let pr = |x: &[f64; 3]| [x[i], x[j]];
    let (pa, pb, pc, pp) = (pr(a), pr(b), pr(c), pr(p));
    let s = orient2d(&pa, &pb, &pc);
    let o = [
        orient2d(&pa, &pb, &pp),
        orient2d(&pb, &pc, &pp),
        orient2d(&pc, &pa, &pp),
    ];
    if o.iter().any(|&x| x * s < 0.0) {
        return None;
    }
    let zeros: Vec<usize> = (0..3).filter(|&k| o[k] == 0.0).collect();
    match zeros[..] {
        [] => Some(OnTriangle::Inside),
        [k] => Some(OnTriangle::Edge(k)),
        // Edges k and k + 1 meet at corner k + 1; edges 0 and 2 at 0.
        [0, 1] => Some(OnTriangle::Corner(1)),
        [1, 2] => Some(OnTriangle::Corner(2)),
        [0, 2] => Some(OnTriangle::Corner(0)),
        _ => None,
    }
}

/// The points of `candidates` lying exactly on triangles of `triangles`
/// ([`on_triangle`]): (point, triangle, where), every such pair, sorted.
/// Triangles naming a missing point are skipped. A sweep along the axis of
/// the candidates' largest extent, so the cost is about the number of
/// (triangle, candidate in its bounding box) pairs.
pub(crate) fn points_on_triangles(
    points: &[[f64; 3]],
    triangles: &[[u32; 3]],
    candidates: &[u32],
) -> Vec<(u32, u32, OnTriangle)> {
    let mut out = Vec::new();
    let mut cand: Vec<u32> = candidates
        .iter()
        .copied()
        .filter(|&q| (q as usize) < points.len())
        .collect();
    if cand.is_empty() || triangles.is_empty() {
        return out;
    }
    let pt = |q: u32| &points[q as usize];
    let [lo, hi] = crate::geom::bbox(cand.iter().map(|&q| pt(q)));
    let extent = |k: usize| hi[k] - lo[k];
    let ax = (0..3).fold(0, |m, k| if extent(k) > extent(m) { k } else { m });
    cand.sort_by(|&x, &y| pt(x)[ax].total_cmp(&pt(y)[ax]).then(x.cmp(&y)));
    for (ti, t) in triangles.iter().enumerate() {
        let (Some(a), Some(b), Some(c)) = (
            points.get(t[0] as usize),
            points.get(t[1] as usize),
            points.get(t[2] as usize),
        ) else {
            continue;
        };
        let lo = |k: usize| a[k].min(b[k]).min(c[k]);
        let hi = |k: usize| a[k].max(b[k]).max(c[k]);
        let start = cand.partition_point(|&q| pt(q)[ax] < lo(ax));
        for &q in &cand[start..] {
            let p = pt(q);
            if p[ax] > hi(ax) {
                break;
            }
            if (0..3).any(|k| p[k] < lo(k) || p[k] > hi(k)) {
                continue;
            }
            if let Some(on) = on_triangle(a, b, c, p) {
                out.push((q, ti as u32, on));
            }
        }
    }
    out.sort_unstable_by_key(|&(q, t, _)| (q, t));
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::vec3::{box_corner, BOX_SIDES};

    /// The unit cube; facets bottom, top, front, back, left, right.
    fn cube() -> Plc {
        let mut plc = Plc::new(
            (0..8)
                .map(|k| box_corner(&[[0.0; 3], [1.0; 3]], k))
                .collect(),
        );
        for i in [4, 5, 2, 3, 0, 1] {
            plc.facets
                .push(Facet::polygon(BOX_SIDES[4 * i..4 * i + 4].to_vec()));
        }
        plc
    }

    #[test]
    fn cube_is_valid_and_each_defect_is_named() {
        let plc = cube();
        assert_eq!(plc.validate(), Ok(()));
        assert_eq!(plc.triangles(), None);

        let mut p = cube();
        p.points[7][2] = 1.0 + 1e-15;
        // Facet 1 is [4, 5, 7, 6]: its plane is taken through 4, 5, 7.
        assert_eq!(
            p.validate(),
            Err(Error::DegenerateFacet {
                index: 1,
                defect: FacetDefect::NonPlanar { vertex: 6 }
            })
        );

        let mut p = cube();
        p.facets[3].polygons[0] = vec![2, 6, 2, 3];
        assert_eq!(
            p.validate(),
            Err(Error::DegenerateFacet {
                index: 3,
                defect: FacetDefect::RepeatedVertex { vertex: 2 }
            })
        );

        let mut p = cube();
        p.points.push([1.0, 1.0, 1.0]); // same coordinates as point 7
        p.facets[5].polygons[0] = vec![1, 3, 7, 8, 5];
        assert!(matches!(
            p.validate(),
            Err(Error::DegenerateFacet {
                index: 5,
                defect: FacetDefect::RepeatedVertex { .. }
            })
        ));

        let mut p = cube();
        p.points[3][0] = f64::NAN;
        assert_eq!(p.validate(), Err(Error::InvalidCoordinate { index: 3 }));

        let mut p = cube();
        p.holes.push([0.5, f64::INFINITY, 0.5]);
        assert_eq!(
            p.validate(),
            Err(Error::InvalidSeedPoint {
                kind: "hole",
                index: 0
            })
        );

        let mut p = cube();
        p.segments.push([0, 8]);
        assert!(matches!(
            p.validate(),
            Err(Error::IndexOutOfRange {
                item: "segment",
                vertex: 8,
                ..
            })
        ));

        // An empty polygon is too few vertices; a one-corner polygon (an
        // isolated point of the facet) is allowed.
        let mut p = cube();
        p.facets[2].polygons.push(vec![]);
        assert_eq!(
            p.validate(),
            Err(Error::DegenerateFacet {
                index: 2,
                defect: FacetDefect::TooFewVertices
            })
        );
        let mut p = cube();
        p.facets[2].polygons.push(vec![4]);
        assert_eq!(p.validate(), Ok(()));

        // A facet with a hole polygon and an interior segment is fine.
        let mut p = cube();
        let base = p.points.len() as u32;
        p.points
            .extend([[0.25, 0.25, 0.0], [0.75, 0.25, 0.0], [0.5, 0.75, 0.0]]);
        p.facets[0].polygons.push(vec![base, base + 1, base + 2]);
        p.facets[0].polygons.push(vec![0, base]);
        p.facets[0].holes.push([0.5, 0.4, 0.0]);
        assert_eq!(p.validate(), Ok(()));
    }

    #[test]
    fn merge_renumbers_everything() {
        let mut p = cube();
        let n = p.points.len() as u32;
        p.points.push(p.points[6]);
        p.facets[1].polygons[0] = vec![4, 5, 7, n];
        p.segments.push([n, 0]);
        let map = p.merge_duplicate_points();
        assert_eq!(map[n as usize], 6);
        assert_eq!(p.points.len(), 8);
        assert_eq!(p.facets[1].polygons[0], vec![4, 5, 7, 6]);
        assert_eq!(p.segments, vec![[6, 0]]);
        assert_eq!(p.validate(), Ok(()));
    }
}
