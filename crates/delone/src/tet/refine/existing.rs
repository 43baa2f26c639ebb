//! Refinement of an existing tetrahedral mesh (TetGen's `-r`).
//!
//! The mesh (points, tetrahedra, optional per-tetrahedron region
//! attributes, optional listed faces) is validated and turned into a
//! [`Recovered`] whose constraint surface is made of mesh faces:
//!
//! * every boundary face (a face of one tetrahedron only);
//! * every face between two tetrahedra of different attributes (region
//!   interfaces);
//! * every listed face (a `.face` file: internal facets kept as such).
//!
//! Each of those faces is one *input triangle* of the refinement, so its
//! three edges are subsegments: the refinement splits them and the faces,
//! but never moves or flips them away, and [`check_recovered`] holds on
//! the result with the triangles of [`MeshConstraints::triangles`]. Regions
//! are the distinct attribute values (ascending), so per-region outputs
//! (`-A`) keep the attributes.
//!
//! [`check_recovered`]: crate::tet::recover::check_recovered

#![allow(clippy::needless_range_loop)] // local face indices address several arrays

use crate::tet::local::fkey;
use std::fmt;

use super::{refine_recovered, RefineOptions, Refined};
use crate::tet::local::FACET;
use crate::tet::mesh::{input_tets, TetsDefect};
use crate::tet::quality;
use crate::tet::recover::{MeshRegion, RecoverError, RecoverReport, Recovered};
use crate::tet::TetMesh;
use crate::NONE;

/// Why an existing mesh was refused by [`recovered_from_mesh`] /
/// [`refine_mesh`].
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum RefineMeshError {
    /// A coordinate of point `index` is NaN or infinite.
    InvalidCoordinate {
        /// The point.
        index: usize,
    },
    /// Tetrahedron `tet` names a missing point or one point twice.
    BadIndex {
        /// The tetrahedron.
        tet: usize,
    },
    /// Tetrahedron `tet` has zero volume.
    Degenerate {
        /// The tetrahedron.
        tet: usize,
    },
    /// Tetrahedron `tet` is oriented against the first tetrahedron.
    Inverted {
        /// The tetrahedron.
        tet: usize,
    },
    /// A face of tetrahedron `tet` is shared by more than two tetrahedra.
    NonManifold {
        /// The tetrahedron.
        tet: usize,
    },
    /// Tetrahedron `tet` overlaps its neighbour: both lie on the same side
    /// of their common face.
    Overlap {
        /// The tetrahedron.
        tet: usize,
    },
    /// The attributes are neither empty nor one per tetrahedron.
    AttributeCount {
        /// Tetrahedra.
        expected: usize,
        /// Attributes.
        got: usize,
    },
    /// Listed face `face` is not a face of the mesh (or names a bad point).
    FaceNotInMesh {
        /// Index in the listed faces.
        face: usize,
    },
    /// The refinement itself failed.
    Refine(RecoverError),
}

impl fmt::Display for RefineMeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RefineMeshError::InvalidCoordinate { index } => {
                write!(f, "point {index} has a non-finite coordinate")
            }
            RefineMeshError::BadIndex { tet } => {
                write!(
                    f,
                    "tetrahedron {tet} names a missing point or a point twice"
                )
            }
            RefineMeshError::Degenerate { tet } => write!(f, "tetrahedron {tet} is flat"),
            RefineMeshError::Inverted { tet } => write!(
                f,
                "tetrahedron {tet} is inverted (oriented against tetrahedron 0)"
            ),
            RefineMeshError::NonManifold { tet } => write!(
                f,
                "a face of tetrahedron {tet} is shared by more than two tetrahedra"
            ),
            RefineMeshError::Overlap { tet } => write!(
                f,
                "tetrahedron {tet} overlaps its neighbour across a common face"
            ),
            RefineMeshError::AttributeCount { expected, got } => write!(
                f,
                "{got} attributes for {expected} tetrahedra (give none or one each)"
            ),
            RefineMeshError::FaceNotInMesh { face } => {
                write!(f, "listed face {face} is not a face of the mesh")
            }
            RefineMeshError::Refine(e) => write!(f, "refinement: {e}"),
        }
    }
}

impl std::error::Error for RefineMeshError {}

/// An existing mesh as a [`Recovered`] with its constraint triangles.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshConstraints {
    /// The mesh (tetrahedra positively oriented).
    pub rec: Recovered,
    /// The constraint faces, each an input triangle of the refinement
    /// (boundary faces oriented outward).
    pub triangles: Vec<[u32; 3]>,
    /// Per triangle: its index in the listed faces, or [`NONE`].
    pub listed: Vec<u32>,
}

/// The result of [`refine_mesh`].
#[derive(Debug, Clone, PartialEq)]
pub struct RefinedMesh {
    /// The refined mesh and the report.
    pub refined: Refined,
    /// The constraint triangles (see [`MeshConstraints::triangles`]); pass
    /// them to [`check_recovered`](crate::tet::recover::check_recovered).
    pub triangles: Vec<[u32; 3]>,
    /// Per triangle: its index in the listed faces, or [`NONE`].
    pub listed: Vec<u32>,
}

/// Validates an existing mesh and builds its [`Recovered`] form (see the
/// [module documentation](self)). `attributes`: empty or one per
/// tetrahedron; `faces`: listed constraint faces (any orientation), may be
/// empty. Tetrahedra may come in either orientation, the same for all.
///
/// # Errors
/// [`RefineMeshError`] naming the offending point, tetrahedron or face.
///
/// ```
/// use delone::tet::refine::existing::{recovered_from_mesh, RefineMeshError};
/// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 1.0, 1.0]];
/// let m = recovered_from_mesh(&pts, &[[0, 1, 2, 3], [1, 2, 3, 4]], &[], &[]).unwrap();
/// assert_eq!(m.triangles.len(), 6);
/// let e = recovered_from_mesh(&pts, &[[0, 1, 2, 3], [1, 3, 2, 4]], &[], &[]).unwrap_err();
/// assert_eq!(e, RefineMeshError::Inverted { tet: 1 });
/// ```
pub fn recovered_from_mesh(
    points: &[[f64; 3]],
    tets: &[[u32; 4]],
    attributes: &[f64],
    faces: &[[u32; 3]],
) -> Result<MeshConstraints, RefineMeshError> {
    if let Some(index) = points.iter().position(|p| p.iter().any(|c| !c.is_finite())) {
        return Err(RefineMeshError::InvalidCoordinate { index });
    }
    if !attributes.is_empty() && attributes.len() != tets.len() {
        return Err(RefineMeshError::AttributeCount {
            expected: tets.len(),
            got: attributes.len(),
        });
    }
    let (sp, _) = crate::geom::rescaled(points);
    let n = points.len();
    let (tv, nb) = input_tets(&sp, tets, true).map_err(|d| match d {
        TetsDefect::BadIndex(tet) => RefineMeshError::BadIndex { tet },
        TetsDefect::Degenerate(tet) => RefineMeshError::Degenerate { tet },
        TetsDefect::Inverted(tet) => RefineMeshError::Inverted { tet },
        TetsDefect::NonManifold(tet) => RefineMeshError::NonManifold { tet },
        TetsDefect::Overlap(tet) => RefineMeshError::Overlap { tet },
    })?;
    let mut keys: Vec<[u32; 3]> = tv
        .iter()
        .flat_map(|x| FACET.map(|f| fkey(f.map(|i| x[i]))))
        .collect();
    keys.sort_unstable();
    // Listed faces.
    let mut listed_of: std::collections::HashMap<[u32; 3], u32> =
        std::collections::HashMap::with_capacity(faces.len());
    for (i, f) in faces.iter().enumerate() {
        let k = fkey(*f);
        if keys.binary_search(&k).is_err() {
            return Err(RefineMeshError::FaceNotInMesh { face: i });
        }
        listed_of.entry(k).or_insert(i as u32);
    }
    // Regions: distinct attributes, ascending.
    let attr = |t: usize| attributes.get(t).copied().unwrap_or(0.0);
    let mut values: Vec<f64> = (0..tv.len()).map(attr).collect();
    values.sort_by(f64::total_cmp);
    values.dedup_by(|a, b| a.total_cmp(b).is_eq());
    if values.is_empty() {
        values.push(0.0);
    }
    let tet_region: Vec<u32> = (0..tv.len())
        .map(|t| {
            values
                .binary_search_by(|v| v.total_cmp(&attr(t)))
                .unwrap_or(0) as u32
        })
        .collect();
    let mut regions: Vec<MeshRegion> = values
        .iter()
        .map(|&a| MeshRegion {
            attribute: a,
            max_volume: None,
            seed: None,
            exterior: false,
            tets: 0,
            volume: 0.0,
        })
        .collect();
    for (t, x) in tv.iter().enumerate() {
        let r = &mut regions[tet_region[t] as usize];
        r.tets += 1;
        r.volume += quality::volume(&x.map(|q| points[q as usize]));
    }
    // Constraint faces.
    let mut triangles = Vec::new();
    let mut listed = Vec::new();
    let mut boundary = Vec::new();
    let mut boundary_triangle = Vec::new();
    let mut interior_faces = Vec::new();
    let mut interior_triangle = Vec::new();
    for (t, x) in tv.iter().enumerate() {
        for f in 0..4 {
            let [a, b, c] = FACET[f].map(|i| x[i]);
            let out = [a, c, b];
            let l = listed_of.get(&fkey(out)).copied().unwrap_or(NONE);
            let u = nb[t][f];
            if u == NONE {
                boundary.push(out);
                boundary_triangle.push(triangles.len() as u32);
            } else if (u as usize) > t && (l != NONE || tet_region[u as usize] != tet_region[t]) {
                interior_faces.push(out);
                interior_triangle.push(triangles.len() as u32);
            } else {
                continue;
            }
            triangles.push(out);
            listed.push(l);
        }
    }
    let rec = Recovered {
        points: points.to_vec(),
        mesh: TetMesh {
            tets: tv,
            neighbors: nb,
            vertex_map: (0..n as u32).collect(),
            duplicates: Vec::new(),
            hidden: Vec::new(),
        },
        surface: triangles.clone(),
        surface_origin: (0..triangles.len() as u32).collect(),
        boundary,
        boundary_triangle,
        interior_faces,
        interior_triangle,
        tet_region,
        regions,
        inexact: Vec::new(),
        report: RecoverReport::default(),
    };
    Ok(MeshConstraints {
        rec,
        triangles,
        listed,
    })
}

/// Refines an existing tetrahedral mesh (TetGen `-r`): [`recovered_from_mesh`]
/// then [`refine_recovered`] with `opts` (quality, volume, sizing, budget).
///
/// # Errors
/// [`RefineMeshError`] naming the offending item.
///
/// ```
/// use delone::tet::recover::check_recovered;
/// use delone::tet::refine::existing::refine_mesh;
/// use delone::tet::refine::RefineOptions;
/// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 1.0, 1.0]];
/// let opts = RefineOptions { max_volume: Some(0.01), ..Default::default() };
/// let r = refine_mesh(&pts, &[[0, 1, 2, 3], [1, 2, 3, 4]], &[], &[], &opts).unwrap();
/// check_recovered(&pts, &r.triangles, &r.refined.rec).unwrap();
/// assert!(r.refined.rec.mesh.tets.len() > 20);
/// ```
pub fn refine_mesh(
    points: &[[f64; 3]],
    tets: &[[u32; 4]],
    attributes: &[f64],
    faces: &[[u32; 3]],
    opts: &RefineOptions,
) -> Result<RefinedMesh, RefineMeshError> {
    let m = recovered_from_mesh(points, tets, attributes, faces)?;
    let refined =
        refine_recovered(points, &m.triangles, &m.rec, opts).map_err(RefineMeshError::Refine)?;
    Ok(RefinedMesh {
        refined,
        triangles: m.triangles,
        listed: m.listed,
    })
}
