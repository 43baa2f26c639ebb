//! The 3D pipeline in one call, [`mesh()`]: validate the PLC, triangulate its
//! facets ([`crate::tet::facets`]), recover them in a Delaunay
//! tetrahedralization and carve holes and the outside
//! ([`recover_marked`](crate::tet::recover::recover_marked)), refine ([`refine_recovered`](crate::tet::refine::refine_recovered), with `-q`, `-a` or
//! `-m`) and optimise ([`optimize`], by default after refinement), all in
//! one domain mesh carved by recovery and handed from stage to stage. It is
//! the whole job of `delone tet -p`, which only reads the input, calls
//! [`mesh()`] and writes the [`TetResult`].

use std::fmt;
use std::time::{Duration, Instant};

use crate::model::plc::{Plc, Region};
use crate::tet::optimize::{
    optimize, optimize_in_place, OptimizeError, OptimizeOptions, OptimizeReport,
};
use crate::tet::options::TetOptions;
use crate::tet::recover::{recover_mesh, Domain, RecoverError, RecoverOptions, Recovered};
use crate::tet::refine::{refine_in_place, RefineOptions, RefineReport};
use crate::{Error, NONE};

/// What [`mesh()`] made: the mesh with its points, tetrahedra, neighbours,
/// regions ([`Recovered`]), the faces on input facets with their markers,
/// and the report of each stage.
///
/// ```
/// use delone::{model::plc::Plc, tet::{mesh, TetOptions}};
/// let pts = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
/// let plc = Plc::from_triangles(pts, &[[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]]);
/// let r = mesh(&plc, &TetOptions::from_switches("p").unwrap()).unwrap();
/// assert_eq!(r.mesh.mesh.tets.len(), 1);
/// assert_eq!(r.faces.len(), 4);
/// assert!(r.refine.is_none() && r.optimize.is_none());
/// ```
#[derive(Debug, Clone)]
pub struct TetResult {
    /// The mesh: `points` (the input's first, then Steiner points),
    /// `mesh.tets`, `mesh.neighbors`, the regions and the region of each
    /// tetrahedron, and the recovery's report (`report`).
    pub mesh: Recovered,
    /// The facets triangulated (input point ids): the surface recovered.
    pub triangles: Vec<[u32; 3]>,
    /// Per triangle of [`Self::triangles`]: its input facet.
    pub facet_of: Vec<u32>,
    /// Per triangle of [`Self::triangles`]: its facet's marker.
    pub triangle_markers: Vec<i32>,
    /// The faces on input facets (the boundary first, then faces inside
    /// the domain) and, with `-c`, the hull faces.
    pub faces: Vec<[u32; 3]>,
    /// Per face of [`Self::faces`]: its facet's marker (0 for a hull face).
    pub face_markers: Vec<i32>,
    /// Per face of [`Self::faces`]: the input triangle it lies on
    /// ([`NONE`] for a hull face).
    pub face_triangles: Vec<u32>,
    /// The refinement's report (with `-q`, `-a` or `-m`).
    pub refine: Option<RefineReport>,
    /// The optimisation's report (when it ran: `-O`).
    pub optimize: Option<OptimizeReport>,
    /// Time spent in the optimisation (for reports; zero when it did not
    /// run).
    pub optimize_time: Duration,
}

impl TetResult {
    /// Per tetrahedron: its region's attribute (TetGen's `-A`).
    ///
    /// ```
    /// use delone::{model::plc::Plc, tet::{mesh, TetOptions}};
    /// let pts = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    /// let plc = Plc::from_triangles(pts, &[[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]]);
    /// let r = mesh(&plc, &TetOptions::from_switches("pA").unwrap()).unwrap();
    /// assert_eq!(r.attributes(), vec![r.mesh.regions[0].attribute]);
    /// ```
    pub fn attributes(&self) -> Vec<f64> {
        self.mesh
            .tet_region
            .iter()
            .map(|&g| self.mesh.regions[g as usize].attribute)
            .collect()
    }
}

/// The faces of `rec` on input triangles (boundary first, then interior
/// faces, as [`Recovered`] lists them) with their input triangle (via
/// [`Recovered::surface_origin`]; [`NONE`] for hull faces) and the marker
/// `triangle_markers` gives that triangle (0 for hull faces).
///
/// ```
/// use delone::tet::{pipeline::marked_faces, recover::{recover, RecoverOptions}};
/// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
/// let tris = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];
/// let rec = recover(&pts, &tris, &RecoverOptions::default()).unwrap();
/// let (faces, markers, of) = marked_faces(&rec, &[5, 6, 7, 8]);
/// assert_eq!(faces.len(), 4);
/// assert_eq!(markers.iter().sum::<i32>(), 26);
/// assert!(of.iter().all(|&t| t < 4));
/// ```
pub fn marked_faces(
    rec: &Recovered,
    triangle_markers: &[i32],
) -> (Vec<[u32; 3]>, Vec<i32>, Vec<u32>) {
    let n = rec.boundary.len() + rec.interior_faces.len();
    let (mut faces, mut of) = (Vec::with_capacity(n), Vec::with_capacity(n));
    for (f, t) in rec.surface_faces() {
        faces.push(*f);
        // Faces name triangles of `rec.surface`; markers come from the
        // input triangle (facet) each of those replaces.
        of.push(if t == NONE {
            NONE
        } else {
            rec.surface_origin.get(t as usize).copied().unwrap_or(t)
        });
    }
    let markers = of
        .iter()
        .map(|&t| triangle_markers.get(t as usize).copied().unwrap_or(0))
        .collect();
    (faces, markers, of)
}

/// Why [`mesh()`] failed, with the stage's own error.
///
/// ```
/// use delone::{model::plc::{Facet, Plc}, tet::{mesh, TetError, TetOptions}};
/// let mut plc = Plc::new(vec![[0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]]);
/// plc.facets.push(Facet::polygon(vec![0, 1, 2]));
/// let e = mesh(&plc, &TetOptions::from_switches("p").unwrap()).unwrap_err();
/// assert!(matches!(e, TetError::Input(delone::Error::DegenerateFacet { index: 0, .. })));
/// assert!(e.to_string().starts_with("facet 0"));
/// ```
#[derive(Debug, Clone, PartialEq)]
pub enum TetError {
    /// The PLC is invalid ([`Plc::validate`]) or a facet cannot be
    /// triangulated ([`Plc::triangulate_facets`]); the error names the
    /// point, facet or segment (0-based).
    Input(Error),
    /// A `-q`/`-a` bound no mesh can meet
    /// ([`Error::InvalidBound`], [`TetOptions::check_bounds`]).
    Bound(Error),
    /// Recovery, carving or refinement failed.
    Recover(RecoverError),
    /// Carving removed every tetrahedron: the holes (this many) or the
    /// outside took the whole domain.
    Empty {
        /// Hole points of the PLC.
        holes: usize,
    },
    /// The optimisation found the mesh inconsistent.
    Optimize(OptimizeError),
}

impl fmt::Display for TetError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TetError::Input(e) | TetError::Bound(e) => e.fmt(f),
            TetError::Recover(e) => e.fmt(f),
            TetError::Empty { holes } => write!(
                f,
                "no tetrahedron left after carving ({holes} hole point(s); a hole point in the only region, on a facet or outside the surface removes the whole domain)"
            ),
            TetError::Optimize(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for TetError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            TetError::Input(e) | TetError::Bound(e) => Some(e),
            TetError::Recover(e) => Some(e),
            TetError::Optimize(e) => Some(e),
            TetError::Empty { .. } => None,
        }
    }
}

/// Meshes the inside of `plc` as `delone tet` does with `opts`: validate,
/// triangulate the facets, recover them and carve (holes, regions, the
/// outside unless `-c`), refine with `-q`/`-a`/`-m`, optimise (by default
/// after refinement; `-O` sets the level). Regional volume bounds apply
/// only with `-a` (TetGen's rule). The PLC is always meshed as with `-p`
/// ([`TetOptions::plc`] is implied; a point set alone is
/// [`crate::tet::tetrahedralize`]'s job). Deterministic: the same PLC and
/// options give the same result bit for bit.
///
/// # Errors
/// A [`TetError`] naming the stage and, through its cause, the offending
/// input item.
///
/// ```
/// use delone::{model::plc::{Facet, Plc}, tet::{mesh, TetOptions}};
/// // A unit cube with quadrilateral facets, meshed with TetGen's -pq1.414a0.01.
/// let mut plc = Plc::new((0..8).map(|k| [(k & 1) as f64, (k >> 1 & 1) as f64, (k >> 2) as f64]).collect());
/// for q in [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]] {
///     plc.facets.push(Facet::polygon(q.to_vec()));
/// }
/// let r = mesh(&plc, &TetOptions::from_switches("pq1.414a0.01").unwrap()).unwrap();
/// let volume: f64 = r.mesh.regions.iter().map(|g| g.volume).sum();
/// assert!((volume - 1.0).abs() < 1e-9);
/// assert!(r.mesh.mesh.tets.len() >= 100);
/// assert!(r.refine.is_some() && r.optimize.is_some());
/// delone::tet::recover::check_recovered(&plc.points, &r.triangles, &r.mesh).unwrap();
/// ```
pub fn mesh(plc: &Plc, opts: &TetOptions) -> Result<TetResult, TetError> {
    plc.validate().map_err(TetError::Input)?;
    let (triangles, facet_of) = plc.triangulate_facets().map_err(TetError::Input)?;
    let triangle_markers: Vec<i32> = facet_of
        .iter()
        .map(|&f| plc.facets[f as usize].marker)
        .collect();
    opts.check_bounds().map_err(TetError::Bound)?;
    let domain = Domain {
        holes: plc.holes.clone(),
        regions: plc
            .regions
            .iter()
            .map(|r| Region {
                max_volume: r.max_volume.filter(|_| opts.regional_volumes),
                ..r.clone()
            })
            .collect(),
        convex_hull: opts.convex_hull,
    };
    let ropts = RecoverOptions {
        preserve_surface: opts.preserve_surface,
        merge_coplanar: !opts.no_merge,
        // On for recovery alone; a refinement's smallest dihedral angles
        // depend on where recovery put its points (see the option).
        stop_circling_flips: !opts.refining(),
        ..Default::default()
    };
    let points = &plc.points;
    // One domain mesh from the end of recovery (carved there) through
    // refinement and optimisation; `rec` is its output view, rewritten by
    // each stage.
    // The unguided flips (kept for a refinement) give up where they stop
    // making progress or fail, and the guided ones of recovery alone take
    // over (`recover_mesh`).
    let recovered = recover_mesh(points, &triangles, &triangle_markers, &ropts, &domain);
    let (rec, domain_mesh) = recovered.map_err(|e| TetError::Recover(name_facets(e, &facet_of)))?;
    let (mut rec, mut domain_mesh, refined) = if opts.refining() {
        let ro = RefineOptions {
            keep_surface: opts.preserve_surface,
            max_radius_edge: opts.max_radius_edge,
            max_volume: opts.max_volume,
            max_steiner: opts.max_steiner,
            sizing: opts.size_field.clone().unwrap_or_default(),
            diagnostics: !opts.no_diagnostics,
            ..RefineOptions::default()
        };
        let (r, domain_mesh) = refine_in_place(points, &triangles, &rec, Some(domain_mesh), &ro)
            .map_err(TetError::Recover)?;
        // Recovery's output view is replaced by refinement's: not held
        // through optimisation.
        drop(rec);
        (r.rec, domain_mesh, Some((r.report, ro)))
    } else {
        (rec, domain_mesh, None)
    };
    if rec.mesh.tets.is_empty() {
        return Err(TetError::Empty {
            holes: plc.holes.len(),
        });
    }
    let t_opt = Instant::now();
    let (refine_report, ro) = refined.unzip();
    let optimized = match optimize_options(opts, points.len(), ro.as_ref()) {
        Some(o) => {
            // The optimisation reads subfaces from the marks and keeps its
            // own boundary map: the refinement's tables would only be
            // copied and maintained.
            domain_mesh.drop_tables();
            Some(optimize_in_place(&mut rec, domain_mesh, &o).map_err(TetError::Optimize)?)
        }
        None => {
            drop(domain_mesh);
            None
        }
    };
    let optimize_time = t_opt.elapsed();
    let (faces, face_markers, face_triangles) = marked_faces(&rec, &triangle_markers);
    Ok(TetResult {
        mesh: rec,
        triangles,
        facet_of,
        triangle_markers,
        faces,
        face_markers,
        face_triangles,
        refine: refine_report,
        optimize: optimized,
        optimize_time,
    })
}

/// The optimisation stage of [`mesh()`] (and of `delone tet -r`): on by
/// default after refinement (`refined`: its options, whose size bounds the
/// optimisation keeps, and with [`TetOptions::keep_ratio`] its ratio), on
/// request (`-O`) after plain recovery; `None` when off. `input_points`:
/// how many of the mesh's points are input points (never moved).
///
/// # Errors
/// [`TetError::Optimize`] when the mesh is inconsistent.
///
/// ```
/// use delone::tet::{pipeline::optimize_stage, recover::{recover, RecoverOptions}, TetOptions};
/// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
/// let tris = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];
/// let mut rec = recover(&pts, &tris, &RecoverOptions::default()).unwrap();
/// let o = TetOptions::from_switches("p").unwrap();
/// assert!(optimize_stage(&o, 4, &mut rec, None).unwrap().is_none());
/// let o = TetOptions::from_switches("pO2").unwrap();
/// assert!(optimize_stage(&o, 4, &mut rec, None).unwrap().is_some());
/// ```
pub fn optimize_stage(
    opts: &TetOptions,
    input_points: usize,
    rec: &mut Recovered,
    refined: Option<&RefineOptions>,
) -> Result<Option<OptimizeReport>, TetError> {
    match optimize_options(opts, input_points, refined) {
        Some(o) => optimize(rec, &o).map(Some).map_err(TetError::Optimize),
        None => Ok(None),
    }
}

/// The options of [`optimize_stage`]; `None` when the stage is off.
fn optimize_options(
    opts: &TetOptions,
    input_points: usize,
    refined: Option<&RefineOptions>,
) -> Option<OptimizeOptions> {
    let level = opts
        .optimize
        .unwrap_or(if refined.is_some() { 3 } else { 0 });
    if level == 0 {
        return None;
    }
    let mut o = OptimizeOptions {
        input_points: Some(input_points),
        diagnostics: !opts.no_diagnostics,
        ..OptimizeOptions::level(level)
    };
    if let Some(d) = opts.min_dihedral {
        o.min_dihedral = d;
    }
    // -Y keeps the surface as recovered: no point slides on it.
    if opts.preserve_surface {
        o.smooth_boundary = false;
    }
    if let Some(r) = refined {
        o = o.keeping(r);
        if opts.keep_ratio {
            o.max_radius_edge = r.max_radius_edge.filter(|b| b.is_finite());
        }
    }
    Some(o)
}

/// A recovery error that names triangles of the facets' triangulation
/// (`facet_of[t]` is triangle `t`'s facet), renamed to name the PLC's
/// facets where its message speaks of facets: self-intersecting and
/// degenerate facets.
fn name_facets(e: RecoverError, facet_of: &[u32]) -> RecoverError {
    let facet = |t: usize| facet_of.get(t).map_or(t, |&f| f as usize);
    match e {
        RecoverError::Input(Error::SelfIntersection { facets, count }) => {
            let (a, b) = (facet(facets.0), facet(facets.1));
            RecoverError::Input(Error::SelfIntersection {
                facets: (a.min(b), a.max(b)),
                count,
            })
        }
        RecoverError::Input(Error::DegenerateFacet { index, defect }) => {
            RecoverError::Input(Error::DegenerateFacet {
                index: facet(index),
                defect,
            })
        }
        e => e,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::plc::Facet;

    #[test]
    fn errors_name_the_plc_facets_not_their_triangles() {
        let mut pts: Vec<[f64; 3]> = (0..8)
            .map(|k| [(k & 1) as f64, (k >> 1 & 1) as f64, (k >> 2) as f64])
            .collect();
        pts.extend([[0.5, 0.5, 0.5], [1.5, 0.4, 0.5], [1.5, 0.6, 0.6]]);
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
        // Facet 6 pierces facet 5 (x = 1), whose triangles are 10 and 11.
        plc.facets.push(Facet::polygon(vec![8, 9, 10]));
        let e = mesh(&plc, &TetOptions::from_switches("p").unwrap()).unwrap_err();
        assert!(
            matches!(
                e,
                TetError::Recover(RecoverError::Input(Error::SelfIntersection {
                    facets: (5, 6),
                    ..
                }))
            ),
            "{e:?}"
        );
    }
}
