//! A constrained triangulation built from an existing mesh (Triangle's
//! `-r`): the triangles are taken as they are, validated, and handed to
//! [`refine`](super::refine::refine) like the output of
//! [`constrained_triangulation`](super::constrain::constrained_triangulation).

use std::collections::HashMap;

use delone_predicates::orient2d;

use super::constrain::{Cdt, CdtReport, Subsegment};
use super::topo::edge;
use crate::geom::{pow2_scale, scaled};
use crate::{Error, NONE};

/// A triangulation to refine: points, counterclockwise triangles, and the
/// segments that must stay edges (boundary edges of the mesh are kept as
/// subsegments in any case).
///
/// ```
/// let m = delone::tri::existing::ExistingMesh {
///     points: vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
///     triangles: vec![[0, 1, 2]],
///     ..Default::default()
/// };
/// assert!(m.segments.is_empty());
/// ```
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ExistingMesh {
    /// Vertex coordinates.
    pub points: Vec<[f64; 2]>,
    /// Counterclockwise triangles (0-based vertex ids).
    pub triangles: Vec<[u32; 3]>,
    /// Segments (0-based vertex ids); each must be an edge of the mesh.
    pub segments: Vec<[u32; 2]>,
    /// Segment markers (missing entries: 1 for boundary edges, else 0).
    pub segment_markers: Vec<i32>,
    /// One attribute per triangle (empty: all 0).
    pub attributes: Vec<f64>,
    /// One maximum area per triangle, zero or negative for none (Triangle's
    /// `.area` file; empty: none).
    pub max_areas: Vec<f64>,
}

impl Cdt {
    /// Builds the triangulation of an existing mesh, checking that it is
    /// one: vertex ids in range, every triangle strictly counterclockwise
    /// (exact orientation test), every edge used at most once in each
    /// direction (conforming: neighbours share whole edges), no vertex
    /// where two fans touch, every segment an edge. Its subsegments are the
    /// segments, then the other boundary edges (marker 1), in a
    /// deterministic order. The mesh is not flipped: refining a mesh that is
    /// not constrained Delaunay gives a valid but not Delaunay result.
    ///
    /// # Errors
    /// [`Error::InvalidCoordinate`], [`Error::IndexOutOfRange`] (`"triangle"`
    /// or `"segment"`), [`Error::InconsistentMesh`] naming the triangle,
    /// edge, vertex or segment at fault (and column lengths that differ).
    ///
    /// ```
    /// use delone::tri::{existing::ExistingMesh, Cdt};
    /// let pts = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
    /// let m = ExistingMesh { points: pts.clone(), triangles: vec![[0, 1, 2], [0, 2, 3]], ..Default::default() };
    /// let cdt = Cdt::from_mesh(m).unwrap();
    /// assert_eq!((cdt.neighbors[0][1], cdt.neighbors[1][2]), (1, 0));
    /// assert_eq!(cdt.segments.len(), 4);
    /// // A clockwise triangle is named.
    /// let bad = ExistingMesh { points: pts, triangles: vec![[0, 1, 2], [0, 3, 2]], ..Default::default() };
    /// assert!(Cdt::from_mesh(bad).unwrap_err().to_string().contains("triangle 1"));
    /// ```
    pub fn from_mesh(m: ExistingMesh) -> Result<Cdt, Error> {
        let np = m.points.len();
        crate::geom::check::finite(&m.points)?;
        let nt = m.triangles.len();
        let lens = |what: &str, n: usize| {
            if n != 0 && n != nt {
                Err(Error::InconsistentMesh {
                    reason: format!("{n} {what} for {nt} triangles"),
                })
            } else {
                Ok(())
            }
        };
        lens("attributes", m.attributes.len())?;
        lens("area bounds", m.max_areas.len())?;
        let scale = pow2_scale(crate::geom::max_abs(&m.points));
        let pts: Vec<[f64; 2]> = m.points.iter().map(|&p| scaled(p, scale)).collect();
        let in_range =
            |item, index, v: &[u32]| crate::geom::check::ids_in_range(item, index, v, np);
        let mut half: HashMap<(u32, u32), u32> = HashMap::with_capacity(3 * nt);
        for (t, v) in m.triangles.iter().enumerate() {
            in_range("triangle", t, v)?;
            if orient2d(
                &pts[v[0] as usize],
                &pts[v[1] as usize],
                &pts[v[2] as usize],
            ) <= 0.0
            {
                return Err(Error::InconsistentMesh {
                    reason: format!("triangle {t} {v:?} is not counterclockwise (or degenerate)"),
                });
            }
            for e in 0..3 {
                if let Some(o) = half.insert(edge(v, e), t as u32) {
                    return Err(Error::InconsistentMesh {
                        reason: format!(
                            "triangles {o} and {t} both use edge {:?} in the same direction (overlap or inconsistent orientation)",
                            edge(v, e)
                        ),
                    });
                }
            }
        }
        let mut neighbors = vec![[NONE; 3]; nt];
        let mut out_boundary = vec![0u8; np];
        for (t, (v, nb)) in m.triangles.iter().zip(neighbors.iter_mut()).enumerate() {
            for (e, slot) in nb.iter_mut().enumerate() {
                let (a, b) = edge(v, e);
                match half.get(&(b, a)) {
                    Some(&n) => *slot = n,
                    None => {
                        out_boundary[a as usize] += 1;
                        if out_boundary[a as usize] > 1 {
                            return Err(Error::InconsistentMesh {
                                reason: format!(
                                    "vertex {a} is where two parts of the mesh touch (triangle {t})"
                                ),
                            });
                        }
                    }
                }
            }
        }
        let mut segments = Vec::new();
        let mut seen: HashMap<(u32, u32), ()> = HashMap::new();
        for (k, s) in m.segments.iter().enumerate() {
            in_range("segment", k, s)?;
            let (a, b) = (s[0], s[1]);
            if !half.contains_key(&(a, b)) && !half.contains_key(&(b, a)) {
                return Err(Error::InconsistentMesh {
                    reason: format!("segment {k} ({a},{b}) is not an edge of the mesh"),
                });
            }
            if seen.insert((a.min(b), a.max(b)), ()).is_some() {
                continue;
            }
            segments.push(Subsegment {
                v: [a, b],
                marker: m.segment_markers.get(k).copied().unwrap_or(0),
                segment: k as u32,
                bounding: true,
            });
        }
        for v in &m.triangles {
            for e in 0..3 {
                let (a, b) = edge(v, e);
                if !half.contains_key(&(b, a)) && !seen.contains_key(&(a.min(b), a.max(b))) {
                    segments.push(Subsegment {
                        v: [a, b],
                        marker: 1,
                        segment: NONE,
                        bounding: true,
                    });
                }
            }
        }
        Ok(Cdt {
            points: m.points,
            regions: vec![NONE; nt],
            attributes: if m.attributes.is_empty() {
                vec![0.0; nt]
            } else {
                m.attributes
            },
            max_areas: if m.max_areas.is_empty() {
                vec![-1.0; nt]
            } else {
                m.max_areas
            },
            triangles: m.triangles,
            neighbors,
            segments,
            vertex_map: (0..np as u32).collect(),
            report: CdtReport::default(),
        })
    }
}
