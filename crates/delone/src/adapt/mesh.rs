//! The adaptation's input and output types and options.

use super::stats::MetricStats;
use crate::metric::Metric;

/// A simplicial mesh with Medit-style references, the input and output of
/// adaptation: triangles in 2D (`D = 2`, `K = 3`), tetrahedra in 3D
/// (`D = 3`, `K = 4`).
///
/// `faces` are the boundary and interface faces that adaptation keeps:
/// edges (`[u32; 2]`) in 2D, triangles (`[u32; 3]`) in 3D. Every `*_refs`
/// array is either empty (all references 0) or as long as its items.
///
/// ```
/// use delone::adapt::TriMesh;
/// let m = TriMesh {
///     points: vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
///     elements: vec![[0, 1, 2]],
///     faces: vec![[0, 1], [1, 2], [2, 0]],
///     ..Default::default()
/// };
/// assert_eq!(m.elements.len(), 1);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct SimplexMesh<const D: usize, const K: usize> {
    /// Vertex coordinates.
    pub points: Vec<[f64; D]>,
    /// A reference per vertex (or empty).
    pub point_refs: Vec<i32>,
    /// Elements, positively oriented.
    pub elements: Vec<[u32; K]>,
    /// A reference (region) per element (or empty).
    pub element_refs: Vec<i32>,
    /// Boundary and interface faces: edges in 2D, triangles in 3D.
    pub faces: Vec<[u32; D]>,
    /// A reference per face (or empty).
    pub face_refs: Vec<i32>,
    /// Corner vertices: never moved or removed.
    pub corners: Vec<u32>,
    /// Ridge edges (3D feature edges): their vertices move and split only
    /// along them.
    pub ridges: Vec<[u32; 2]>,
    /// Required vertices: never moved or removed.
    pub required: Vec<u32>,
}

impl<const D: usize, const K: usize> Default for SimplexMesh<D, K> {
    fn default() -> Self {
        SimplexMesh {
            points: Vec::new(),
            point_refs: Vec::new(),
            elements: Vec::new(),
            element_refs: Vec::new(),
            faces: Vec::new(),
            face_refs: Vec::new(),
            corners: Vec::new(),
            ridges: Vec::new(),
            required: Vec::new(),
        }
    }
}

/// A triangle mesh for 2D adaptation.
pub type TriMesh = SimplexMesh<2, 3>;
/// A tetrahedral mesh for 3D adaptation.
pub type TetMesh = SimplexMesh<3, 4>;

/// The metric to adapt to.
pub enum MetricField<'a, const D: usize> {
    /// One metric per input vertex, interpolated (log-Euclidean) at new
    /// vertices.
    AtVertices(Vec<Metric<D>>),
    /// A metric at any point, evaluated at every vertex the adaptation
    /// makes or moves.
    Function(&'a (dyn Fn(&[f64; D]) -> Metric<D> + Sync)),
}

/// Options of an adaptation. `None` turns a bound off.
///
/// ```
/// let o = delone::adapt::AdaptOptions { hmax: Some(0.5), ..Default::default() };
/// assert_eq!(o.hgrad, Some(1.3));
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct AdaptOptions {
    /// Smallest edge size: every metric is bounded so that no size is
    /// below it (MMG's `-hmin`).
    pub hmin: Option<f64>,
    /// Largest edge size (MMG's `-hmax`).
    pub hmax: Option<f64>,
    /// Gradation: the size may grow by at most this factor per unit of
    /// metric length along an edge (MMG's `-hgrad`); `None` keeps the
    /// metric as given.
    pub hgrad: Option<f64>,
    /// Edge splits and insertions (MMG's `-noinsert` turns them off).
    pub insert: bool,
    /// Edge swaps / flips (MMG's `-noswap`).
    pub swap: bool,
    /// Vertex smoothing (MMG's `-nomove`).
    pub smooth: bool,
    /// Most passes of split/collapse/swap/smooth before the adaptation
    /// stops and reports.
    pub max_passes: usize,
    /// Most vertices of the output; reaching it ends the adaptation with
    /// the mesh so far (reported in [`AdaptReport::budget_reached`]).
    pub max_vertices: Option<usize>,
}

impl Default for AdaptOptions {
    fn default() -> Self {
        AdaptOptions {
            hmin: None,
            hmax: None,
            hgrad: Some(1.3),
            insert: true,
            swap: true,
            smooth: true,
            max_passes: 30,
            max_vertices: None,
        }
    }
}

/// An adapted mesh with its metric and report.
#[derive(Clone, Debug)]
pub struct Adapted<const D: usize, const K: usize> {
    /// The mesh.
    pub mesh: SimplexMesh<D, K>,
    /// The metric at each of its vertices.
    pub metric: Vec<Metric<D>>,
    /// What the adaptation did.
    pub report: AdaptReport,
}

/// What an adaptation did and how good its result is in the metric.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AdaptReport {
    /// The input mesh in the (bounded, graded) metric.
    pub before: MetricStats,
    /// The output mesh in its metric.
    pub after: MetricStats,
    /// Passes run.
    pub passes: usize,
    /// Edges split.
    pub splits: usize,
    /// Edges collapsed.
    pub collapses: usize,
    /// Swaps (2D edge flips; 3D 2-3, 3-2 and edge removals).
    pub swaps: usize,
    /// Vertex moves.
    pub moves: usize,
    /// The vertex budget ended the adaptation.
    pub budget_reached: bool,
    /// Seconds per phase, in order.
    pub phases: Vec<(&'static str, f64)>,
}
