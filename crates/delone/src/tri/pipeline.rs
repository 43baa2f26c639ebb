//! The 2D pipeline in one call, [`mesh()`]: the constrained Delaunay
//! triangulation of a PSLG with its holes and outside carved
//! ([`constrained_triangulation`](crate::tri::constrained_triangulation)),
//! then quality or conforming refinement ([`refine`](crate::tri::refine()))
//! of the same mesh when the options ask for it. It is the whole job of
//! `delone tri -p`, which only reads the input, calls [`mesh()`] and writes
//! the [`TriResult`].

use std::fmt;
use std::time::{Duration, Instant};

use crate::model::pslg::Pslg;
use crate::tri::constrain::{constrain, Cdt, CdtOptions};
use crate::tri::options::TriOptions;
use crate::tri::refine::{refine_mesh, RefineReport};
use crate::{Error, NONE};

/// What [`mesh()`] made.
///
/// ```
/// use delone::{model::pslg::Pslg, tri::{mesh, TriOptions}};
/// let g = Pslg::new(vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
///                   vec![[0, 1], [1, 2], [2, 3], [3, 0]]);
/// let r = mesh(&g, &TriOptions::from_switches("p").unwrap()).unwrap();
/// assert_eq!(r.mesh.triangles.len(), 2);
/// assert!(r.refine.is_none());
/// ```
#[derive(Debug, Clone)]
pub struct TriResult {
    /// The mesh: points (the input's first, then Steiner points),
    /// triangles, neighbours, the region and attribute of each triangle,
    /// the subsegments with their markers, the map of input points to
    /// vertices, and the triangulation's report (crossings, duplicates).
    pub mesh: Cdt,
    /// The mesh before refinement, when [`TriOptions::keep_unrefined`] and
    /// the mesh was refined.
    pub unrefined: Option<Cdt>,
    /// The refinement's report (with `-q`, `-a`, `-S` or `-D`): Steiner
    /// points, angles reached, triangles left outside the bounds and why.
    pub refine: Option<RefineReport>,
    /// Time spent in the refinement (for reports; zero when it did not
    /// run).
    pub refine_time: Duration,
}

impl TriResult {
    /// The output marker of every vertex of the mesh ([`vertex_markers`]):
    /// the input point's marker from `pslg`, else the marker of a segment
    /// through it, else 1 on the boundary, else 0.
    ///
    /// ```
    /// use delone::{model::pslg::Pslg, tri::{mesh, TriOptions}};
    /// let mut g = Pslg::new(vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.5, 0.5]],
    ///                       vec![[0, 1], [1, 2], [2, 3], [3, 0]]);
    /// g.segment_markers = vec![4, 0, 0, 0];
    /// let r = mesh(&g, &TriOptions::from_switches("p").unwrap()).unwrap();
    /// assert_eq!(r.vertex_markers(&g), vec![4, 4, 1, 1, 0]);
    /// ```
    pub fn vertex_markers(&self, pslg: &Pslg) -> Vec<i32> {
        let m = &self.mesh;
        let input: Vec<i32> = (0..pslg.points.len())
            .map(|i| pslg.point_marker(i))
            .collect();
        vertex_markers(
            m.points.len(),
            &input,
            &self.subsegments(),
            &m.triangles,
            &m.neighbors,
        )
    }

    /// The subsegments on the domain's boundary or inside it (those the
    /// output lists), with their markers.
    ///
    /// ```
    /// use delone::{model::pslg::Pslg, tri::{mesh, TriOptions}};
    /// let g = Pslg::new(vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]], vec![[0, 1], [1, 2], [2, 0]]);
    /// let r = mesh(&g, &TriOptions::from_switches("p").unwrap()).unwrap();
    /// assert_eq!(r.subsegments().len(), 3);
    /// ```
    pub fn subsegments(&self) -> Vec<([u32; 2], i32)> {
        self.mesh
            .segments
            .iter()
            .filter(|s| s.bounding)
            .map(|s| (s.v, s.marker))
            .collect()
    }
}

/// The key of the edge between vertices `a` and `b` (either order): the
/// smaller id in the high 32 bits.
///
/// ```
/// assert_eq!(delone::tri::pipeline::edge_key(2, 1), (1 << 32) | 2);
/// ```
#[inline]
pub fn edge_key(a: u32, b: u32) -> u64 {
    (u64::from(a.min(b)) << 32) | u64::from(a.max(b))
}

/// The edges of a triangulation with one triangle ([`edge_key`]s, sorted):
/// its boundary, holes included.
///
/// ```
/// let k = delone::tri::pipeline::hull_edge_keys(&[[0, 1, 2]], &[[delone::NONE; 3]]);
/// assert_eq!(k.len(), 3);
/// ```
pub fn hull_edge_keys(tris: &[[u32; 3]], nbrs: &[[u32; 3]]) -> Vec<u64> {
    let mut b: Vec<u64> = tris
        .iter()
        .zip(nbrs)
        .flat_map(|(t, n)| {
            (0..3)
                .filter(move |&k| n[k] == NONE)
                .map(move |k| edge_key(t[(k + 1) % 3], t[(k + 2) % 3]))
        })
        .collect();
    b.sort_unstable();
    b.dedup();
    b
}

/// Output vertex markers, Triangle's documented rule: an input point's own
/// nonzero marker; else the nonzero marker of a segment it lies on (the
/// first such subsegment in order); else 1 on the boundary of the
/// triangulation (holes included); else 0.
///
/// `input` holds the input points' markers (fewer entries than points: the
/// Steiner points have none).
///
/// ```
/// use delone::NONE;
/// // Two triangles; segment 1-2 with marker 5; point 3 with its own marker 7.
/// let tris = [[0, 1, 2], [2, 1, 3]];
/// let nbrs = [[1, NONE, NONE], [NONE, NONE, 0]];
/// let m = delone::tri::pipeline::vertex_markers(4, &[0, 0, 0, 7], &[([1, 2], 5)], &tris, &nbrs);
/// assert_eq!(m, vec![1, 5, 5, 7]);
/// ```
pub fn vertex_markers(
    n: usize,
    input: &[i32],
    subsegs: &[([u32; 2], i32)],
    tris: &[[u32; 3]],
    nbrs: &[[u32; 3]],
) -> Vec<i32> {
    let mut m = vec![0i32; n];
    for (i, &x) in input.iter().enumerate().take(n) {
        m[i] = x;
    }
    for &(s, mk) in subsegs {
        if mk != 0 {
            for v in s {
                if m[v as usize] == 0 {
                    m[v as usize] = mk;
                }
            }
        }
    }
    for k in hull_edge_keys(tris, nbrs) {
        for v in [(k >> 32) as usize, (k & 0xffff_ffff) as usize] {
            if m[v] == 0 {
                m[v] = 1;
            }
        }
    }
    m
}

/// Why [`mesh()`] failed, with the stage's own error.
///
/// ```
/// use delone::{model::pslg::Pslg, tri::{mesh, TriError, TriOptions}};
/// let g = Pslg::new(vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]], vec![[0, 7]]);
/// let e = mesh(&g, &TriOptions::from_switches("p").unwrap()).unwrap_err();
/// assert!(matches!(e, TriError::Input(delone::Error::SegmentOutOfRange { segment: 0, point: 7 })));
/// ```
#[derive(Debug, Clone, PartialEq)]
pub enum TriError {
    /// The PSLG cannot be triangulated (a bad coordinate, a segment end out
    /// of range, crossing segments the triangulation cannot split, ...);
    /// the error names the point or segment (0-based).
    Input(Error),
    /// Carving removed every triangle (no segments enclose a region, an
    /// open boundary, or holes that reach everything).
    Empty,
    /// The refinement refused its bounds ([`Error::InvalidBound`]) or
    /// failed.
    Refine(Error),
}

impl fmt::Display for TriError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TriError::Input(e) | TriError::Refine(e) => e.fmt(f),
            TriError::Empty => f.write_str("no triangle left after carving"),
        }
    }
}

impl std::error::Error for TriError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            TriError::Input(e) | TriError::Refine(e) => Some(e),
            TriError::Empty => None,
        }
    }
}

/// Meshes `pslg` as `delone tri` does with `opts`: the constrained
/// Delaunay triangulation (with `-p` its segments are kept and the holes
/// and, unless `-c`, the outside removed; without `-p` the points alone are
/// triangulated up to their convex hull), then refinement when `-q`, `-a`
/// ([`TriOptions::max_area`] or [`TriOptions::regional_areas`]), `-S` or
/// `-D` asks for it (off-centres, `-Y` segment rules,
/// [`TriOptions::threads`]). The result depends only on the input and the
/// options (see [`crate::tri::refine::RefineOptions::threads`] for the
/// thread count).
///
/// # Errors
/// A [`TriError`] naming the stage and, through its cause, the offending
/// input item.
///
/// ```
/// use delone::{model::pslg::Pslg, tri::{mesh, TriOptions}};
/// let g = Pslg::new(vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
///                   vec![[0, 1], [1, 2], [2, 3], [3, 0]]);
/// let r = mesh(&g, &TriOptions::from_switches("pq30a0.01").unwrap()).unwrap();
/// let rep = r.refine.unwrap();
/// assert!(rep.met && rep.min_angle >= 30.0);
/// assert!(r.mesh.triangles.len() >= 100);
/// delone::tri::check_cdt(&g, &r.mesh).unwrap();
/// // Without -p the points alone are triangulated (segments are not used).
/// let r = mesh(&g, &TriOptions::default()).unwrap();
/// assert_eq!(r.mesh.triangles.len(), 2);
/// ```
pub fn mesh(pslg: &Pslg, opts: &TriOptions) -> Result<TriResult, TriError> {
    let c = if opts.pslg {
        constrain(
            pslg,
            CdtOptions {
                convex_hull: opts.convex_hull,
            },
        )
    } else {
        let points = Pslg::new(pslg.points.clone(), Vec::new());
        constrain(&points, CdtOptions { convex_hull: true })
    }
    .map_err(TriError::Input)?;
    if c.cm.tr.is_empty() && !pslg.points.is_empty() {
        return Err(TriError::Empty);
    }
    let refining = opts.min_angle.is_some()
        || opts.max_area.is_some()
        || opts.regional_areas
        || opts.max_steiner.is_some()
        || opts.conforming_delaunay;
    if !refining {
        return Ok(TriResult {
            mesh: c.into_cdt(),
            unrefined: None,
            refine: None,
            refine_time: Duration::ZERO,
        });
    }
    let unrefined = opts.keep_unrefined.then(|| c.to_cdt());
    let t = Instant::now();
    // Refinement continues on the constrained triangulation's mesh.
    let r = refine_mesh(&c.cdt, c.cm, &opts.refine_options(), None).map_err(TriError::Refine)?;
    Ok(TriResult {
        mesh: r.mesh,
        unrefined,
        refine: Some(r.report),
        refine_time: t.elapsed(),
    })
}
