//! Facet triangulation: each planar facet of a [`Plc`] triangulated in its
//! own plane by the 2D constrained Delaunay triangulation, the first stage
//! of the 3D pipeline ([`crate::tet::mesh()`]). It lives here, not in
//! [`crate::model`], so that the input model holds data and validation
//! only and does not depend on the 2D mesher.

use crate::error::{Error, FacetDefect};
use crate::geom::key;
use crate::model::plc::{points_on_triangles, Facet, OnTriangle, Plc};

impl Plc {
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
        let (tris, owner) = self.all_facet_triangles(&points, s, &[])?;
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
        if isolated.is_empty() {
            return Ok((tris, owner));
        }
        let mut extra: Vec<Vec<u32>> = vec![Vec::new(); self.facets.len()];
        for (q, t, on) in points_on_triangles(&points, &tris, &isolated) {
            // A point equal to a corner is a duplicate point: left alone.
            if !matches!(on, OnTriangle::Corner(_)) {
                extra[owner[t as usize] as usize].push(q);
            }
        }
        if extra.iter().all(Vec::is_empty) {
            return Ok((tris, owner));
        }
        for ex in &mut extra {
            // One point per location (the first): the others are
            // duplicates.
            ex.sort_unstable();
            ex.dedup();
            let mut seen = std::collections::HashSet::new();
            ex.retain(|&q| seen.insert(key(&self.points[q as usize])));
        }
        self.all_facet_triangles(&points, s, &extra)
    }

    /// The triangles of every facet ([`facet_triangles`] with the points
    /// `extra[fi]` of facet `fi`, none when `extra` is shorter), with each
    /// triangle's facet. A facet that is one triangle with no point to add
    /// is taken as it is, without a list of its own.
    fn all_facet_triangles(
        &self,
        points: &[[f64; 3]],
        s: (f64, f64),
        extra: &[Vec<u32>],
    ) -> Result<(Vec<[u32; 3]>, Vec<u32>), Error> {
        let mut tris = Vec::with_capacity(self.facets.len());
        let mut owner = Vec::with_capacity(self.facets.len());
        for (fi, f) in self.facets.iter().enumerate() {
            let ex = extra.get(fi).map_or(&[][..], |e| &e[..]);
            if let [p] = f.polygons.as_slice() {
                if p.len() == 3 && f.holes.is_empty() && ex.is_empty() {
                    tris.push([p[0], p[1], p[2]]);
                    owner.push(fi as u32);
                    continue;
                }
            }
            let ts = facet_triangles(points, s, fi, f, ex)?;
            tris.extend_from_slice(&ts);
            owner.extend(std::iter::repeat_n(fi as u32, ts.len()));
        }
        Ok((tris, owner))
    }
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
    crate::geom::check::ids_in_range("facet", fi, &ids, points.len())?;
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
