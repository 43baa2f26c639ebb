//! Piecewise linear complexes (3D meshing input).
//!
//! A [`Plc`] is what TetGen's `.poly`/`.smesh` files describe: points,
//! planar facets (each a set of polygons — the outer boundary, hole
//! boundaries, and any segments the facet must contain — plus points inside
//! the facet's holes and a boundary marker), optional free segments, volume
//! holes and regions. [`Plc::validate`] checks it exactly;
//! [`Plc::merge_duplicate_points`] merges exactly coincident points.
//! Self-intersection and closedness checks live in [`crate::tet::intersect`].

use crate::error::{Error, FacetDefect};
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

    /// Triangulates every facet in its own plane with the 2D constrained
    /// Delaunay triangulation (facet polygons, interior segments and facet
    /// holes respected, the outside of the outer polygon removed), without
    /// new points. Returns the triangles and, for each, its facet index.
    ///
    /// An isolated point of the PLC (a corner of no facet polygon) lying
    /// exactly on a facet (exact `orient3d` and `orient2d`) becomes a vertex
    /// of that facet's triangles, as TetGen does; one lying on an edge
    /// splits it in every facet sharing the edge, so the facets stay
    /// conforming. An isolated point with the same coordinates as a facet
    /// corner is a duplicate and is left out (so are later copies of an
    /// isolated point already inserted).
    ///
    /// # Errors
    /// [`Error::DegenerateFacet`] (with [`FacetDefect::ZeroArea`]) for a facet
    /// whose polygons span no plane; the errors of
    /// [`crate::tri::constrained_triangulation`] (e.g. crossing edges inside
    /// a facet), and [`Error::DegenerateFacet`] with
    /// [`FacetDefect::TooFewVertices`] when a facet would need new points,
    /// [`FacetDefect::PointOutside`] when one of its points is left out of
    /// its triangles (outside the boundary or in a hole).
    ///
    /// ```
    /// use delone::model::plc::{Facet, Plc};
    /// // A unit cube with quadrilateral facets.
    /// let mut plc = Plc::new((0..8).map(|k| [(k & 1) as f64, (k >> 1 & 1) as f64, (k >> 2) as f64]).collect());
    /// for q in [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]] {
    ///     plc.facets.push(Facet::polygon(q.to_vec()));
    /// }
    /// let (tris, facet) = plc.triangulate_facets().unwrap();
    /// assert_eq!(tris.len(), 12);
    /// assert_eq!(facet[11], 5);
    /// // An isolated point in the middle of the bottom side: a vertex of
    /// // its four triangles.
    /// plc.points.push([0.5, 0.5, 0.0]);
    /// let (tris, _) = plc.triangulate_facets().unwrap();
    /// assert_eq!(tris.len(), 14);
    /// assert_eq!(tris.iter().filter(|t| t.contains(&8)).count(), 4);
    /// ```
    pub fn triangulate_facets(&self) -> Result<(Vec<[u32; 3]>, Vec<u32>), Error> {
        // Normals, projections and the point-on-facet tests on a copy scaled
        // by a power of two (exact): no overflow or underflow at any scale.
        let (points, s) = crate::geom::rescaled(&self.points);
        let mut per: Vec<Vec<[u32; 3]>> = Vec::with_capacity(self.facets.len());
        for (fi, f) in self.facets.iter().enumerate() {
            per.push(facet_triangles(&points, s, fi, f, &[])?);
        }
        // Isolated points (corners of no facet polygon) lying exactly on a
        // facet become vertices of its triangulation; on a facet edge, of
        // every facet sharing that edge (each one finds the point on one
        // of its triangles), so the facets stay conforming.
        let mut referenced = vec![false; self.points.len()];
        for &q in self.facets.iter().flat_map(|f| f.polygons.iter().flatten()) {
            if let Some(r) = referenced.get_mut(q as usize) {
                *r = true;
            }
        }
        let isolated: Vec<u32> = (0..self.points.len() as u32)
            .filter(|&q| !referenced[q as usize])
            .collect();
        if !isolated.is_empty() {
            let (tris, owner) = flatten(&per);
            let mut extra: Vec<Vec<u32>> = vec![Vec::new(); self.facets.len()];
            for (q, t, on) in points_on_triangles(&points, &tris, &isolated) {
                // A point equal to a corner is a duplicate point: left alone.
                if !matches!(on, OnTriangle::Corner(_)) {
                    extra[owner[t as usize] as usize].push(q);
                }
            }
            for (fi, ex) in extra.iter_mut().enumerate() {
                if ex.is_empty() {
                    continue;
                }
                // One point per location (the first): the others are
                // duplicates.
                ex.sort_unstable();
                ex.dedup();
                let mut seen = std::collections::HashSet::new();
                ex.retain(|&q| seen.insert(key(&self.points[q as usize])));
                per[fi] = facet_triangles(&points, s, fi, &self.facets[fi], ex)?;
            }
        }
        Ok(flatten(&per))
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
        if let Some(index) = self
            .points
            .iter()
            .position(|p| !p.iter().all(|c| c.is_finite()))
        {
            return Err(Error::InvalidCoordinate { index });
        }
        crate::geom::scale::check_range(&self.points, crate::geom::scale::RANGE_3D)?;
        // The exact tests below run on a copy scaled by a power of two
        // (exact), so that no product over- or underflows at any scale.
        let (sp, _) = crate::geom::rescaled(&self.points);
        let finite = |p: &[f64; 3]| p.iter().all(|c| c.is_finite());
        if let Some(index) = self.holes.iter().position(|p| !finite(p)) {
            return Err(Error::InvalidSeedPoint {
                kind: "hole",
                index,
            });
        }
        if let Some(index) = self.regions.iter().position(|r| !finite(&r.point)) {
            return Err(Error::InvalidSeedPoint {
                kind: "region",
                index,
            });
        }
        for (index, s) in self.segments.iter().enumerate() {
            for &v in s {
                if v as usize >= n {
                    return Err(Error::IndexOutOfRange {
                        item: "segment",
                        index,
                        vertex: v,
                        points: n,
                    });
                }
            }
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
                if let Some(&v) = p.iter().find(|&&v| v as usize >= n) {
                    return Err(Error::IndexOutOfRange {
                        item: "facet",
                        index,
                        vertex: v,
                        points: n,
                    });
                }
            }
            return bad(FacetDefect::TooFewVertices);
        }
        let mut sorted: Vec<(u32, [u64; 3])> = Vec::new();
        for p in &f.polygons {
            for &v in p {
                if v as usize >= n {
                    return Err(Error::IndexOutOfRange {
                        item: "facet",
                        index,
                        vertex: v,
                        points: n,
                    });
                }
            }
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

/// The triangles per facet flattened, with each triangle's facet.
fn flatten(per: &[Vec<[u32; 3]>]) -> (Vec<[u32; 3]>, Vec<u32>) {
    let mut tris = Vec::new();
    let mut owner = Vec::new();
    for (fi, ts) in per.iter().enumerate() {
        tris.extend_from_slice(ts);
        owner.extend(std::iter::repeat_n(fi as u32, ts.len()));
    }
    (tris, owner)
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
    let (pa, pb, pc, pp, s) = (0..3).find_map(|k| {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        let pr = |x: &[f64; 3]| [x[i], x[j]];
        let (pa, pb, pc) = (pr(a), pr(b), pr(c));
        let s = orient2d(&pa, &pb, &pc);
        (s != 0.0).then(|| (pa, pb, pc, pr(p), s))
    })?;
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
    let extent = |k: usize| {
        let (lo, hi) = cand
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &q| {
                (l.min(pt(q)[k]), h.max(pt(q)[k]))
            });
        hi - lo
    };
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

/// Hash/equality key of a point: the bits of its coordinates, with `-0.0`
/// folded onto `0.0` (so equal coordinates give equal keys).
pub(crate) fn key(p: &[f64; 3]) -> [u64; 3] {
    p.map(|c| if c == 0.0 { 0 } else { c.to_bits() })
}

/// Exact collinearity of three points in 3D: all three coordinate
/// projections are degenerate.
pub(crate) fn collinear(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3]) -> bool {
    (0..3).all(|k| {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        orient2d(&[a[i], a[j]], &[b[i], b[j]], &[c[i], c[j]]) == 0.0
    })
}

/// The triangles of facet `fi` (see [`Plc::triangulate_facets`]), with
/// the points `extra` (lying on the facet) as vertices too.
fn facet_triangles(
    points: &[[f64; 3]],
    s: (f64, f64),
    fi: usize,
    f: &Facet,
    extra: &[u32],
) -> Result<Vec<[u32; 3]>, Error> {
    use crate::model::pslg::Pslg;
    use crate::tri::{constrained_triangulation, CdtOptions};
    if let [p] = f.polygons.as_slice() {
        if p.len() == 3 && f.holes.is_empty() && extra.is_empty() {
            return Ok(vec![[p[0], p[1], p[2]]]);
        }
    }
    let zero = Error::DegenerateFacet {
        index: fi,
        defect: FacetDefect::ZeroArea,
    };
    // Newell normal over all polygons; drop its largest axis.
    let mut n = [0.0f64; 3];
    for poly in &f.polygons {
        let m = poly.len();
        for k in 0..m {
            let a = points.get(poly[k] as usize).ok_or(zero.clone())?;
            let b = points.get(poly[(k + 1) % m] as usize).ok_or(zero.clone())?;
            n[0] += (a[1] - b[1]) * (a[2] + b[2]);
            n[1] += (a[2] - b[2]) * (a[0] + b[0]);
            n[2] += (a[0] - b[0]) * (a[1] + b[1]);
        }
    }
    let axis = (0..3).fold(0, |m, k| if n[k].abs() > n[m].abs() { k } else { m });
    if n[axis] == 0.0 {
        return Err(zero);
    }
    let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
    let mut ids: Vec<u32> = f.polygons.iter().flatten().copied().collect();
    ids.extend(extra);
    ids.sort_unstable();
    ids.dedup();
    if let Some(&q) = ids.iter().find(|&&q| q as usize >= points.len()) {
        return Err(Error::IndexOutOfRange {
            item: "facet",
            index: fi,
            vertex: q,
            points: points.len(),
        });
    }
    let local = |q: u32| ids.binary_search(&q).unwrap_or(0) as u32;
    let mut g = Pslg::new(
        ids.iter()
            .map(|&q| {
                let p = points[q as usize];
                [p[u], p[v]]
            })
            .collect(),
        Vec::new(),
    );
    for poly in &f.polygons {
        let m = poly.len();
        if m < 2 {
            continue;
        }
        let edges = if m == 2 { 1 } else { m };
        for k in 0..edges {
            g.segments.push([local(poly[k]), local(poly[(k + 1) % m])]);
        }
    }
    g.holes = f
        .holes
        .iter()
        .map(|&h| {
            let h = crate::geom::scaled(h, s);
            [h[u], h[v]]
        })
        .collect();
    let cdt = constrained_triangulation(&g, CdtOptions::default())?;
    if cdt.points.len() != ids.len() {
        return Err(Error::DegenerateFacet {
            index: fi,
            defect: FacetDefect::TooFewVertices,
        });
    }
    let mut used = vec![false; ids.len()];
    let mut tris = Vec::with_capacity(cdt.triangles.len());
    for t in &cdt.triangles {
        tris.push(t.map(|q| ids[q as usize]));
        for &q in t {
            used[q as usize] = true;
        }
    }
    if let Some(k) = used.iter().position(|&u| !u) {
        return Err(Error::DegenerateFacet {
            index: fi,
            defect: FacetDefect::PointOutside { vertex: ids[k] },
        });
    }
    Ok(tris)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube() -> Plc {
        let mut pts = Vec::new();
        for z in [0.0, 1.0] {
            for y in [0.0, 1.0] {
                for x in [0.0, 1.0] {
                    pts.push([x, y, z]);
                }
            }
        }
        let mut plc = Plc::new(pts);
        for q in [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ] {
            plc.facets.push(Facet::polygon(q.to_vec()));
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
