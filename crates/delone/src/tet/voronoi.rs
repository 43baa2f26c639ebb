//! 3D Voronoi diagrams as the dual of a Delaunay tetrahedralization, cells
//! clipped to a box as convex polyhedra, and Lloyd relaxation.
//!
//! * [`Voronoi3::new`] — vertices (circumcentres, one per tetrahedron), edges
//!   (one per Delaunay triangle: a segment, or a ray for a hull triangle),
//!   faces (one per Delaunay edge: the polygon of circumcentres around it)
//!   and cells (the faces around each site).
//! * [`Voronoi3::cells_clipped`] — every cell intersected with a box: the box
//!   clipped by the bisector planes of the site and its Delaunay neighbours.
//! * [`lloyd`] — Lloyd's algorithm in a box.
//!
//! # Costs
//!
//! Circumcentres in mesh order, a Morton counting sort of the tetrahedra,
//! 32-byte walk records, edge numbering by the lower tetrahedron
//! (per-tetrahedron prefix counts of owned facets and a 16-bit word of
//! mirror slots and facet ranks: a facet's number comes from its owner's
//! count and rank, no per-facet id table), ring walks per Delaunay edge (a
//! step tracks the slots of the two vertices off the edge), cells by a
//! counting sort. Every pass runs in chunks taken by free threads
//! (`run_dynamic`), bit-identical for any thread count; the walks write
//! into zero-allocated windows of the final face arrays, compacted in
//! place, and the cells' arrays reuse the pages of scratch tables already
//! dead (page faults cost about 0.5 s/GB). The faces' edges are not stored:
//! [`Voronoi3::vertex_edges`] and the two rays of each open face give them.
//! Measure with `cargo run --release -p delone --example voronoi_timing --
//! 1000000 1 --3d --no-clip [--threads N] [--phases] [--hash]` (`--hash`
//! digests the whole diagram to check a change keeps it bit for bit).
//!
//! # References
//! * F. Aurenhammer, "Voronoi diagrams — a survey of a fundamental geometric
//!   data structure", ACM Computing Surveys 23 (1991).
//! * Q. Du, V. Faber, M. Gunzburger, "Centroidal Voronoi tessellations:
//!   applications and algorithms", SIAM Review 41 (1999).

use crate::geom::vec3::{box_corner, cross, dot, sub, BOX_SIDES};
use crate::par::{run_dynamic, split_mut};
use std::sync::atomic::{AtomicU32, Ordering};

use delone_predicates::orient3d;

use super::local::FACET;
use super::TetMesh;
use crate::{Error, NONE};

/// An axis-aligned box `[min, max]`.
pub type Box3 = [[f64; 3]; 2];

/// The local edges of a tetrahedron as `[i, j, k, l]`, each an even
/// permutation of `[0, 1, 2, 3]`: the tetrahedron fills the wedge from
/// `v_k` to `v_l` counterclockwise around the axis `v_j - v_i`.
const EDGES: [[usize; 4]; 6] = [
    [0, 1, 2, 3],
    [0, 2, 3, 1],
    [0, 3, 1, 2],
    [1, 2, 0, 3],
    [1, 3, 2, 0],
    [2, 3, 0, 1],
];

/// `EDGE_INDEX[i][j]`: the index in [`EDGES`] of the local edge `{i, j}`.
const EDGE_INDEX: [[usize; 4]; 4] = [[0, 0, 1, 2], [0, 0, 3, 4], [1, 3, 0, 5], [2, 4, 5, 0]];

/// One Voronoi edge: the dual of a Delaunay triangle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VoronoiEdge3 {
    /// The three sites of the Delaunay triangle.
    pub sites: [u32; 3],
    /// The Voronoi vertices at its ends (tetrahedron indices); for a ray (a
    /// hull triangle) `vertices[1]` is [`NONE`]; its direction is
    /// [`Voronoi3::direction`].
    pub vertices: [u32; 2],
}

impl VoronoiEdge3 {
    /// Whether the edge is a ray (unbounded).
    ///
    /// ```
    /// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    /// let mesh = delone::tetrahedralize(&pts).unwrap();
    /// let v = delone::tet::Voronoi3::new(&pts, &mesh).unwrap();
    /// assert_eq!(v.edges.iter().filter(|e| e.is_ray()).count(), 4);
    /// ```
    pub fn is_ray(&self) -> bool {
        self.vertices[1] == NONE
    }
}

/// One Voronoi face (the dual of a Delaunay edge), as returned by
/// [`Voronoi3::face`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Face3<'a> {
    /// The two sites of the Delaunay edge; the face separates their cells.
    pub sites: [u32; 2],
    /// The Voronoi vertices (tetrahedron indices) of the face,
    /// counterclockwise around the axis `sites[1] - sites[0]`.
    pub vertices: &'a [u32],
    /// For an unbounded face (a Delaunay hull edge): `[first, last]`, the ray
    /// directions; the boundary arrives from infinity along `-first` at
    /// `vertices[0]` and leaves from the last vertex along `last`.
    pub rays: Option<[[f64; 3]; 2]>,
    /// The boundary edges (indices into [`Voronoi3::edges`]), in the order
    /// of the vertices: for a bounded face edge `k` joins vertex `k` to
    /// vertex `k + 1` (cyclically); an unbounded face starts with its first
    /// ray and ends with its last. A face has as many edges as vertices, one
    /// more if unbounded. Derived from [`Voronoi3::vertex_edges`] along the
    /// vertices (not stored).
    pub edges: FaceEdges<'a>,
}

/// The boundary edges of a face ([`Face3::edges`]): an iterator of edge
/// indices, derived along the face's vertices (the edge joining two
/// consecutive vertices is the one edge their [`Voronoi3::vertex_edges`]
/// share).
///
/// ```
/// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 1.0, 1.0]];
/// let mesh = delone::tetrahedralize(&pts).unwrap();
/// let v = delone::tet::Voronoi3::new(&pts, &mesh).unwrap();
/// for f in 0..v.faces.len() {
///     let face = v.face(f);
///     let edges: Vec<u32> = face.edges.collect();
///     assert_eq!(edges.len(), face.vertices.len() + usize::from(face.rays.is_some()));
///     assert_eq!(face.edges.len(), edges.len());
///     assert_eq!(face.edges.get(0), Some(edges[0]));
/// }
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FaceEdges<'a> {
    vertex_edges: &'a [[u32; 4]],
    vertices: &'a [u32],
    rays: Option<[u32; 2]>,
    at: usize,
    end: usize,
}

impl FaceEdges<'_> {
    /// Edge `i` of the face (counted from the start, whatever was already
    /// iterated), or `None` past the end. An invalid diagram (consecutive
    /// vertices sharing no edge) gives [`NONE`].
    ///
    /// ```
    /// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    /// let mesh = delone::tetrahedralize(&pts).unwrap();
    /// let v = delone::tet::Voronoi3::new(&pts, &mesh).unwrap();
    /// let e = v.face(0).edges;
    /// assert!(v.edges[e.get(0).unwrap() as usize].is_ray());
    /// assert!(e.get(2).is_none());
    /// ```
    pub fn get(&self, i: usize) -> Option<u32> {
        let k = self.vertices.len();
        let (j, rays) = match self.rays {
            Some(r) => {
                if i == 0 {
                    return Some(r[0]);
                }
                if i == k {
                    return Some(r[1]);
                }
                if i > k {
                    return None;
                }
                (i - 1, true)
            }
            None => {
                if i >= k {
                    return None;
                }
                (i, false)
            }
        };
        let a = self.vertices[j] as usize;
        let b = self.vertices[if !rays && j + 1 == k { 0 } else { j + 1 }] as usize;
        let (ea, eb) = match (self.vertex_edges.get(a), self.vertex_edges.get(b)) {
            (Some(x), Some(y)) => (x, y),
            _ => return Some(NONE),
        };
        // The one edge the two vertices share (branch-light: 16 compares).
        let mut out = NONE;
        for &x in ea {
            if eb.contains(&x) {
                out = x;
            }
        }
        Some(out)
    }
}

impl Iterator for FaceEdges<'_> {
    type Item = u32;

    fn next(&mut self) -> Option<u32> {
        if self.at >= self.end {
            return None;
        }
        self.at += 1;
        self.get(self.at - 1)
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let n = self.end - self.at;
        (n, Some(n))
    }
}

impl ExactSizeIterator for FaceEdges<'_> {}

/// Per-face data of a [`Voronoi3`] (the ray directions of unbounded faces
/// are kept apart, in [`Voronoi3::open_faces`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FaceInfo3 {
    /// See [`Face3::sites`].
    pub sites: [u32; 2],
}

/// The Voronoi diagram of a 3D point set, dual of its Delaunay
/// tetrahedralization.
///
/// ```
/// let mut pts = vec![];
/// for k in 0..8 {
///     pts.push([(k & 1) as f64 * 2.0, (k >> 1 & 1) as f64 * 2.0, (k >> 2) as f64 * 2.0]);
/// }
/// pts.push([1.0, 1.1, 0.9]);
/// let mesh = delone::tetrahedralize(&pts).unwrap();
/// let v = delone::tet::Voronoi3::new(&pts, &mesh).unwrap();
/// assert_eq!(v.vertices.len(), mesh.tets.len());
/// assert!(!v.is_unbounded(8)); // the inner site
/// assert_eq!(v.cell_faces(8).len(), 8); // one face per cube corner
/// assert!(v.is_unbounded(0));
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Voronoi3 {
    /// Voronoi vertices: `vertices[t]` is the circumcentre of tetrahedron `t`.
    pub vertices: Vec<[f64; 3]>,
    /// Voronoi edges, one per Delaunay triangle. For meshes under 2^15
    /// tetrahedra they come in the order of `(t, f)` (tetrahedron, local
    /// facet), each triangle taken from its lower tetrahedron; larger meshes
    /// use the same rule with the tetrahedra renumbered along a Morton curve
    /// (for speed; still deterministic). [`Voronoi3::faces`] follow the
    /// same tetrahedron order.
    pub edges: Vec<VoronoiEdge3>,
    /// The rays among [`Voronoi3::edges`], increasing.
    pub ray_edges: Vec<u32>,
    /// `ray_directions[k]` is the direction of ray `ray_edges[k]`: the
    /// outward normal of its hull triangle, of twice the triangle's area.
    pub ray_directions: Vec<[f64; 3]>,
    /// Voronoi faces, one per Delaunay edge.
    pub faces: Vec<FaceInfo3>,
    /// The unbounded faces (Delaunay hull edges), increasing.
    pub open_faces: Vec<u32>,
    /// `open_face_rays[k]` are the rays of face `open_faces[k]` (see
    /// [`Face3::rays`]).
    pub open_face_rays: Vec<[[f64; 3]; 2]>,
    /// `face_offsets[f]..face_offsets[f + 1]` is the range of
    /// [`Voronoi3::face_vertices`] of face `f`.
    pub face_offsets: Vec<u32>,
    /// The faces' vertex ids, face after face.
    pub face_vertices: Vec<u32>,
    /// `open_face_edges[k]` are the first and last edges (rays) of face
    /// `open_faces[k]` (see [`Face3::edges`]).
    pub open_face_edges: Vec<[u32; 2]>,
    /// The edges of every Voronoi vertex: `vertex_edges[t][i]` is the edge
    /// (index into [`Voronoi3::edges`]) dual to the facet of tetrahedron `t`
    /// opposite its vertex `i` (`mesh.tets[t][i]`). The faces' edges are
    /// derived from it ([`Face3::edges`]): two consecutive vertices of a
    /// face share exactly one edge.
    pub vertex_edges: Vec<[u32; 4]>,
    /// `cell_offsets[p]..cell_offsets[p + 1]` is the range of
    /// [`Voronoi3::cell_face_ids`] of input point `p` (empty for duplicates).
    pub cell_offsets: Vec<u32>,
    /// The faces of every cell, cell after cell, in increasing order.
    pub cell_face_ids: Vec<u32>,
    /// Whether each input point's cell is unbounded (its site is on the hull).
    pub unbounded: Vec<bool>,
    /// For every input point, the site whose cell it shares (see
    /// [`TetMesh::vertex_map`]; [`crate::NONE`] for a point hidden in a
    /// power diagram, whose cell is empty).
    pub vertex_map: Vec<u32>,
    /// The sites' weights for a power diagram (empty for a Voronoi diagram).
    pub weights: Vec<f64>,
}

/// Orthocentre (power centre) of the positive tetrahedron `q` with weights
/// `wq`: the point with equal power distance `|x - q_i|² - w_i` to the four
/// weighted corners; zero weights give the circumcentre. Computed relative to
/// the corner with the shortest incident edges (less cancellation for
/// slivers).
///
/// `WEIGHTED = false` ignores `wq`: the circumcentre, the same bits as with
/// zero weights (`x + 0 - 0 = x` for the non-negative squared lengths).
#[inline]
fn centre<const WEIGHTED: bool>(q: [&[f64; 3]; 4], wq: [f64; 4]) -> [f64; 3] {
    // The six edge vectors and their squared lengths, computed once: the
    // vectors from the chosen corner are among them (up to sign, which
    // negation gives exactly).
    let ev = [
        sub(q[1], q[0]),
        sub(q[2], q[0]),
        sub(q[3], q[0]),
        sub(q[2], q[1]),
        sub(q[3], q[1]),
        sub(q[3], q[2]),
    ];
    let l = ev.map(|e| dot(&e, &e));
    let sum = [
        l[0] + l[1] + l[2],
        l[0] + l[3] + l[4],
        l[1] + l[3] + l[5],
        l[2] + l[4] + l[5],
    ];
    let o = (0..4).fold(0, |m, i| if sum[i] < sum[m] { i } else { m });
    // An even permutation putting corner o first keeps the orientation:
    // [o, o ^ 1, o ^ 2, o ^ 3] (a double transposition, or the identity);
    // indexed rather than matched, for no branch to mispredict. `FROM[o]`
    // gives the edge vectors `q[o ^ i] - q[o]` (i = 1, 2, 3) as (index in
    // `ev`, sign).
    const FROM: [[(usize, f64); 3]; 4] = [
        [(0, 1.0), (1, 1.0), (2, 1.0)],
        [(0, -1.0), (4, 1.0), (3, 1.0)],
        [(5, 1.0), (1, -1.0), (3, -1.0)],
        [(5, -1.0), (4, -1.0), (2, -1.0)],
    ];
    let [u, v, w] = FROM[o].map(|(i, s)| ev[i].map(|x| s * x));
    let [lu0, lv0, lw0] = FROM[o].map(|(i, _)| l[i]);
    let a = q[o];
    let (vw, wu, uv) = (cross(&v, &w), cross(&w, &u), cross(&u, &v));
    let mut det = dot(&u, &vw);
    if det <= 0.0 {
        det = -orient3d(a, q[o ^ 1], q[o ^ 2], q[o ^ 3]);
        if det <= 0.0 {
            det = f64::MIN_POSITIVE;
        }
    }
    // Power distances: |x - a|² - wa = |x - b|² - wb, ... relative to a.
    let (lu, lv, lw) = if WEIGHTED {
        let [wa, wb, wc, wd] = [o, o ^ 1, o ^ 2, o ^ 3].map(|i| wq[i]);
        (lu0 + wa - wb, lv0 + wa - wc, lw0 + wa - wd)
    } else {
        (lu0, lv0, lw0)
    };
    let k = 0.5 / det;
    [
        a[0] + (lu * vw[0] + lv * wu[0] + lw * uv[0]) * k,
        a[1] + (lu * vw[1] + lv * wu[1] + lw * uv[1]) * k,
        a[2] + (lu * vw[2] + lv * wu[2] + lw * uv[2]) * k,
    ]
}

/// One tetrahedron's record for the ring walks: `[vertices, neighbours]`
/// (tetrahedra in the walk order), 32 bytes, two per cache line (placed at
/// a 32-byte boundary, see `Voronoi3::build`). What the walk does not steer
/// by (the Voronoi edge of each facet, the tetrahedron's index in the mesh,
/// the swept bits) lives in side arrays. An array, not a struct: a zeroed
/// table of them is allocated zeroed by the system (no fill).
type Rec = [[u32; 4]; 2];

/// Phase wall times, recorded when `on` (see [`Voronoi3::with_phase_times`]).
#[derive(Default)]
struct Phases {
    on: bool,
    at: Option<std::time::Instant>,
    times: Vec<(&'static str, f64)>,
}

impl Phases {
    fn start(&mut self) {
        if self.on {
            self.at = Some(std::time::Instant::now());
        }
    }

    /// Ends phase `name` (and starts the next).
    fn lap(&mut self, name: &'static str) {
        if let Some(t) = self.at {
            let now = std::time::Instant::now();
            self.times.push((name, (now - t).as_secs_f64()));
            self.at = Some(now);
        }
    }
}

/// At least this many tetrahedra per chunk.
const MIN_CHUNK: usize = 1 << 14;

/// The number of chunks (threads) for `nt` tetrahedra and at most `threads`
/// threads (`0`: the default).
fn chunk_count(nt: usize, threads: usize) -> usize {
    let t = if threads == 0 {
        Voronoi3::default_threads()
    } else {
        threads
    };
    t.min(nt / MIN_CHUNK).max(1)
}

/// Moves the parts of `a` written at `starts[i]` (`(length, spill)` each)
/// together after `a[..first]`, adding `add[i]` to the entries of part `i`
/// (by `plus`); `a` is cut to the result. In place (`copy_within`) unless a
/// part spilled.
fn compact<T: Copy>(
    mut a: Vec<T>,
    first: usize,
    starts: &[usize],
    parts: &[(usize, Vec<T>)],
    add: &[u32],
    plus: impl Fn(T, u32) -> T,
) -> Vec<T> {
    let win = |i: usize| starts.get(i + 1).copied().unwrap_or(a.len()) - starts[i];
    if parts.iter().any(|p| !p.1.is_empty()) {
        let mut out = a[..first].to_vec();
        for (i, (len, spill)) in parts.iter().enumerate() {
            let m = (*len).min(win(i));
            out.extend(a[starts[i]..starts[i] + m].iter().map(|&x| plus(x, add[i])));
            out.extend(spill.iter().map(|&x| plus(x, add[i])));
        }
        return out;
    }
    let mut at = first;
    for (i, (len, _)) in parts.iter().enumerate() {
        let (from, d) = (starts[i], add[i]);
        if d == 0 {
            if from != at {
                a.copy_within(from..from + len, at);
            }
        } else if at + len <= from {
            let (lo, hi) = a.split_at_mut(from);
            for (x, &y) in lo[at..at + len].iter_mut().zip(&hi[..*len]) {
                *x = plus(y, d);
            }
        } else {
            for j in 0..*len {
                a[at + j] = plus(a[from + j], d);
            }
        }
        at += len;
    }
    a.truncate(at);
    a.shrink_to_fit();
    a
}

/// The edges (see `edge_pass`).
#[derive(Default)]
struct EdgePart {
    edges: Vec<VoronoiEdge3>,
    ray_edges: Vec<u32>,
    ray_directions: Vec<[f64; 3]>,
}

/// Fills the per-tetrahedron prefix counts `pre` of the chunk
/// `lo..lo + pre.len()` (the number of owned facets before each
/// tetrahedron, from `base` at the chunk's first) and the chunk's `aux`
/// words: the mirror slots (see `mirror`) and owned-facet ranks (see
/// `facet_id`). The owned facets of a tetrahedron are those whose other
/// tetrahedron comes later (hull facets too, as `NONE` is the largest id);
/// the owned facet `(t, f)` is edge `pre[t]` + the number of owned facets of
/// `t` before `f`.
fn aux_pass(recs: &[Rec], pre: &mut [u32], aux: &mut [u16], lo: usize, base: usize) {
    let mut at = base as u32;
    for (j, (x, ax)) in pre.iter_mut().zip(aux.iter_mut()).enumerate() {
        *x = at;
        let t = lo + j;
        let c = &recs[t];
        // The slot in each neighbour of the vertex off the shared facet
        // (0 for a hull facet, or where an invalid mesh has none).
        let mut m = 0u16;
        for (f, &u) in c[1].iter().enumerate() {
            if let Some(cu) = recs.get(u as usize) {
                m |= (pos(&cu[1], t as u32) as u16) << (2 * f);
            }
        }
        // The rank of each slot's facet among the owned ones, 2 bits each.
        let own = owned_mask(c, t as u32);
        at += own.count_ones();
        for f in 1..4 {
            m |= ((own & ((1 << f) - 1)).count_ones() as u16) << (8 + 2 * f);
        }
        *ax = m;
    }
}

/// The edges, in the order of `(t, f)` (walk order): every facet numbered
/// by the lower of its two tetrahedra (hull facets by their only one), as
/// `aux_pass` counts them; `cap` is their number.
fn edge_pass(points: &[[f64; 3]], recs: &[Rec], perm: &[u32], cap: usize) -> EdgePart {
    let p = |v: u32| &points[v as usize];
    let mut out = EdgePart {
        edges: Vec::with_capacity(cap),
        ..EdgePart::default()
    };
    for (t, c) in recs.iter().enumerate() {
        #[allow(clippy::needless_range_loop)] // f indexes c.n, c.v and FACET
        for f in 0..4 {
            let u = c[1][f];
            if u <= t as u32 {
                continue;
            }
            let s = FACET[f].map(|i| c[0][i]);
            let id = out.edges.len() as u32;
            if u == NONE {
                // FACET[f] sees vertex f on its positive side: outward
                // is the opposite normal.
                out.ray_edges.push(id);
                out.ray_directions
                    .push(cross(&sub(p(s[2]), p(s[0])), &sub(p(s[1]), p(s[0]))));
            }
            let far = if u == NONE { NONE } else { perm[u as usize] };
            out.edges.push(VoronoiEdge3 {
                sites: s,
                vertices: [perm[t], far],
            });
        }
    }
    out
}

/// The owned facets of tetrahedron `t` (record `c`) as bits: those whose
/// neighbour comes later (or is `NONE`).
#[inline]
fn owned_mask(c: &Rec, t: u32) -> u32 {
    let n = &c[1];
    (n[0] > t) as u32
        | ((n[1] > t) as u32) << 1
        | ((n[2] > t) as u32) << 2
        | ((n[3] > t) as u32) << 3
}

/// The edge number of the facet of `s` in slot `ps` (the slot of the vertex
/// off the facet), shared with its neighbour `u` (or `NONE`) in whose slot
/// `pu` lies the vertex off the facet: numbered by its owner (`s` if `u`
/// comes later, else `u`) at `pre` of the owner plus its rank among the
/// owner's owned facets. Branch-free (the owner is unpredictable); clamped
/// to `last` (only an invalid mesh needs it).
#[inline]
fn facet_id(aux: &[u16], pre: &[u32], s: u32, u: u32, ps: usize, pu: usize, last: u32) -> u32 {
    let (o, slot) = if u > s { (s, ps) } else { (u, pu) };
    let rank = (aux[o as usize] >> (8 + 2 * slot)) as u32 & 3;
    (pre[o as usize] + rank).min(last)
}

/// The mirror slot of facet `f` of a tetrahedron with `aux` word `m`: the
/// slot, in the neighbour across the facet, of the neighbour's vertex off
/// the facet (bits `2f..2f + 2`; bits `8 + 2f..10 + 2f` are the rank of
/// facet `f` among the tetrahedron's owned facets).
#[inline]
fn mirror(m: u16, f: usize) -> usize {
    (m >> (2 * f)) as usize & 3
}

/// A window of a shared output array (calloc'ed: its untouched pages cost
/// nothing) written by one chunk, with a spill vector for what does not fit.
struct Win<'a, T = u32> {
    buf: &'a mut [T],
    len: usize,
    spill: Vec<T>,
}

impl<'a, T: Copy> Win<'a, T> {
    fn new(buf: &'a mut [T]) -> Win<'a, T> {
        Win {
            buf,
            len: 0,
            spill: Vec::new(),
        }
    }

    /// Appends `xs`.
    fn extend(&mut self, xs: &[T]) {
        let at = self.len.min(self.buf.len());
        let room = self.buf.len() - at;
        let (a, b) = xs.split_at(xs.len().min(room));
        self.buf[at..at + a.len()].copy_from_slice(a);
        self.spill.extend_from_slice(b);
        self.len += xs.len();
    }

    /// The length written and the spill.
    fn done(self) -> (usize, Vec<T>) {
        (self.len, self.spill)
    }
}

/// The faces emitted by one chunk of tetrahedra. The face vertices and the
/// ends of the faces in them (relative to this part) went to the chunk's
/// windows: `(length, spill)` of each.
#[derive(Default)]
struct FacePart {
    /// The faces' sites (window and spill, as `wins`).
    sites: (usize, Vec<[u32; 2]>),
    open_faces: Vec<u32>,
    open_face_rays: Vec<[[f64; 3]; 2]>,
    open_face_edges: Vec<[u32; 2]>,
    /// Face vertices, face ends.
    wins: [(usize, Vec<u32>); 2],
}

/// The two windows of a face chunk (see [`FacePart::wins`]).
type Wins<'a> = [&'a mut [u32]; 2];

/// The faces of the chunk `lo..hi`: tetrahedron by tetrahedron, every local
/// edge not yet swept is swept — the ring of tetrahedra around the Delaunay
/// edge is walked once, marking the edge in every tetrahedron of the chunk
/// it passes. The face is emitted when no tetrahedron of its ring lies in an
/// earlier chunk, i.e. by the lowest tetrahedron of its ring, as with one
/// chunk. `(pre, top)`: the prefix counts of `facet_id` and the last edge
/// number; `wins`: where the chunk writes its face vertices and ends (see
/// [`FacePart::wins`]); `vedges`: the vertices' edges (see
/// [`Voronoi3::vertex_edges`]), written for the chunk's tetrahedra.
#[allow(clippy::too_many_arguments)]
fn face_pass(
    points: &[[f64; 3]],
    recs: &[Rec],
    (pre, top): (&[u32], u32),
    aux: &[u16],
    perm: &[u32],
    lo: usize,
    hi: usize,
    (wins, wsites): (Wins, &mut [[u32; 2]]),
    vedges: &[[AtomicU32; 4]],
) -> FacePart {
    // Checked lookups (`mesh_fits` has checked the vertex ids; cheap).
    let p = |v: u32| points.get(v as usize).unwrap_or(&[0.0; 3]);
    let nt = recs.len();
    let mine = hi - lo;
    let mut out = FacePart::default();
    // The edges of the chunk's tetrahedra, by Voronoi vertex (mesh index).
    for t in lo..hi {
        let (c, a) = (&recs[t], aux[t]);
        if let Some(row) = vedges.get(perm[t] as usize) {
            for (f, x) in row.iter().enumerate() {
                let id = facet_id(aux, pre, t as u32, c[1][f], f, mirror(a, f), top);
                x.store(id, Ordering::Relaxed);
            }
        }
    }
    let [wv, wo] = wins;
    let (mut wv, mut wo) = (Win::new(wv), Win::new(wo));
    let mut ws = Win::new(wsites);
    // Faces emitted so far.
    let mut nf = 0u32;
    // Staging vectors, flushed to the windows every few thousand entries:
    // the walks push (their lengths stay in registers); `(bv, be)` are
    // the lengths flushed so far.
    const FLUSH: usize = 1 << 10;
    let mut bv = 0u32;
    let mut ends: Vec<u32> = Vec::with_capacity(FLUSH + 64);
    let mut sites: Vec<[u32; 2]> = Vec::with_capacity(FLUSH + 64);
    let mut done = vec![0u8; mine];
    let (mut back_v, mut fwd_v) = (vec![], vec![]);
    let limit = nt + 1;
    let mut fv: Vec<u32> = Vec::with_capacity(2 * FLUSH);
    for t in lo..hi {
        if fv.len() >= FLUSH || ends.len() >= FLUSH {
            bv += fv.len() as u32;
            wv.extend(&fv);
            wo.extend(&ends);
            ws.extend(&sites);
            fv.clear();
            ends.clear();
            sites.clear();
        }
        // The edges of t not yet swept: walking a ring through t marks
        // only that ring's edge in t, so this set is fixed up front.
        let mut todo = !done[t - lo] & 63;
        while todo != 0 {
            let k = todo.trailing_zeros() as usize;
            todo &= todo - 1;
            let lk = &EDGES[k];
            let [a, b] = [lk[0], lk[1]].map(|i| recs[t][0][i]);
            let v0 = fv.len();
            // Counterclockwise around a -> b: in tetrahedron s, with the
            // two vertices off the edge (c, d) in slots (pc, pd), cross the
            // facet opposite c, (a, b, d), into the next tetrahedron u,
            // where the vertex off that facet is in the mirror slot (the
            // new d) and d is found by one slot lookup (the new c). The
            // slots (pc, pd) name the edge in s (`off_edge`).
            let (mut s, mut pc, mut pd) = (t as u32, lk[2], lk[3]);
            let mut steps = 0usize;
            let mut foreign = false;
            let hit_hull = loop {
                let su = s as usize;
                let cs = &recs[su];
                // Marked if in this chunk; an earlier one makes it foreign.
                if let Some(x) = done.get_mut(su.wrapping_sub(lo)) {
                    *x |= off_edge(pc, pd);
                }
                foreign |= su < lo;
                fv.push(perm[su]);
                let u = cs[1][pc];
                if u == NONE {
                    break true;
                }
                let m = mirror(aux[su], pc);
                if u == t as u32 || steps > limit {
                    break false;
                }
                steps += 1;
                let d = cs[0][pd];
                (s, pc, pd) = (u, pos(&recs[u as usize][0], d), m);
            };
            if hit_hull {
                // Open ring: the part clockwise from t comes first.
                let (pa, pb) = (p(a), p(b));
                let ab_vec = sub(pb, pa);
                let last = cross(&ab_vec, &sub(p(recs[s as usize][0][pd]), pa));
                // The hull facet crossed last (the last ray).
                let last_edge = facet_id(aux, pre, s, NONE, pc, 0, top);
                fwd_v.clear();
                fwd_v.extend(fv.drain(v0..));
                back_v.clear();
                // Clockwise: cross the facet opposite d, (a, b, c); in the
                // next tetrahedron the vertex off it (the new c) is in the
                // mirror slot and c (the new d) is looked up.
                let (mut s, mut pc, mut pd) = (t as u32, lk[2], lk[3]);
                let mut steps = 0usize;
                loop {
                    let su = s as usize;
                    let cs = &recs[su];
                    let u = cs[1][pd];
                    if u == NONE || steps > limit {
                        break;
                    }
                    let m = mirror(aux[su], pd);
                    steps += 1;
                    let uu = u as usize;
                    let pdu = pos(&recs[uu][0], cs[0][pc]);
                    if let Some(x) = done.get_mut(uu.wrapping_sub(lo)) {
                        *x |= off_edge(m, pdu);
                    }
                    foreign |= uu < lo;
                    back_v.push(perm[uu]);
                    (s, pc, pd) = (u, m, pdu);
                }
                let sc = recs[s as usize][0][pc];
                if foreign {
                    continue;
                }
                let first = cross(&sub(p(sc), pa), &ab_vec);
                // The hull facet the clockwise walk ended on (the first
                // ray; an invalid mesh's overlong walk gives its facet).
                let u = recs[s as usize][1][pd];
                let first_edge = facet_id(aux, pre, s, u, pd, mirror(aux[s as usize], pd), top);
                fv.extend(back_v.iter().rev());
                fv.extend(&fwd_v);
                out.open_faces.push(nf);
                out.open_face_rays.push([first, last]);
                out.open_face_edges.push([first_edge, last_edge]);
            } else if foreign {
                fv.truncate(v0);
                continue;
            }
            ends.push(bv + fv.len() as u32);
            sites.push([a, b]);
            nf += 1;
        }
    }
    wv.extend(&fv);
    wo.extend(&ends);
    ws.extend(&sites);
    out.wins = [wv.done(), wo.done()];
    out.sites = ws.done();
    out
}

/// The Morton grid ordering the walk records of meshes of at least 2^15
/// tetrahedra: the tetrahedra are sorted by the Morton code of the grid cell
/// holding their first vertex (a grid of up to 2^18 cells, about 8 to 32
/// tetrahedra per cell), ties by index — one counting sort, deterministic.
struct Grid {
    lo: [f64; 3],
    scale: [f64; 3],
    cells: f64,
    bits: u32,
    /// `spread[x]`: the 6 bits of x at every third position.
    spread: [u32; 64],
}

impl Grid {
    /// The grid for `nt` tetrahedra over `points` (`None` under 2^15).
    fn new(points: &[[f64; 3]], nt: usize) -> Option<Grid> {
        if nt < 1 << 15 {
            return None;
        }
        let [lo, hi] = crate::geom::bbox(points);
        // `bits` per axis: 2^(3 bits) cells, at least 8 tetrahedra each.
        let bits = ((usize::BITS - nt.leading_zeros()).saturating_sub(3) / 3).clamp(1, 6);
        let cells = (1u32 << bits) as f64;
        let scale: [f64; 3] = std::array::from_fn(|i| {
            let w = hi[i] - lo[i];
            if w > 0.0 && w.is_finite() {
                cells / w
            } else {
                0.0
            }
        });
        let spread =
            std::array::from_fn(|x| (0..6).fold(0, |k, i| k | ((x as u32 >> i) & 1) << (3 * i)));
        Some(Grid {
            lo,
            scale,
            cells,
            bits,
            spread,
        })
    }

    /// The number of keys.
    fn keys(&self) -> usize {
        1 << (3 * self.bits)
    }

    /// The Morton key of the cell holding `q`.
    #[inline]
    #[allow(clippy::needless_range_loop)] // i indexes q, lo and scale
    fn key(&self, q: &[f64; 3]) -> u32 {
        let mut key = 0u32;
        for i in 0..3 {
            // max and min, not clamp (cheaper: no range assertion, no NaN
            // case): the same key, a NaN going to cell 0 either way.
            // `as i32`: a shorter conversion than `as usize` (no unsigned
            // conversion on x86-64), the same value in `0..cells`.
            let c = ((q[i] - self.lo[i]) * self.scale[i])
                .max(0.0)
                .min(self.cells - 1.0) as i32;
            key |= self.spread[(c & 63) as usize] << i;
        }
        key
    }
}

/// Local index of vertex `x` in `tv` (0 if absent, which a valid mesh never
/// asks for; at most 3 in any case).
#[inline]
fn pos(tv: &[u32; 4], x: u32) -> usize {
    // Branch-free (which slot holds `x` is unpredictable): the slots of a
    // valid tetrahedron are distinct, so at most one term is set, and the
    // result is at most 3 whatever `tv` holds.
    (tv[1] == x) as usize | ((tv[2] == x) as usize) << 1 | ((tv[3] == x) as usize * 3)
}

/// `OFF_BIT[4 * x + y]`: the bit of the local edge whose two other vertices
/// are in slots `x` and `y` (`x != y`), i.e. `1 << e` for the index `e` in
/// [`EDGES`] of the complement of `{x, y}`.
const OFF_BIT: [u8; 16] = {
    let mut t = [0u8; 16];
    let mut i = 0;
    while i < 16 {
        t[i] = 1 << (5 - EDGE_INDEX[i / 4][i % 4]);
        i += 1;
    }
    t
};

/// The bit of the local edge whose two other vertices are in slots `x` and
/// `y` (see [`OFF_BIT`]).
#[inline]
fn off_edge(x: usize, y: usize) -> u8 {
    OFF_BIT[(x << 2 | y) & 15]
}

/// [`crate::geom::check::mesh_fits`] for `Voronoi3`, with a fast path: the
/// ids are checked on up to `threads` threads by branch-free maxima (the
/// serial check, a tenth of the extraction's wall time at 1M points on two
/// threads, runs only when something is wrong, for its error).
fn check_mesh(
    points: &[[f64; 3]],
    mesh: &TetMesh,
    weights: Option<usize>,
    threads: usize,
) -> Result<(), Error> {
    let (n, nt) = (points.len(), mesh.tets.len());
    let lengths_ok =
        mesh.neighbors.len() == nt && mesh.vertex_map.len() == n && weights.is_none_or(|w| w == n);
    let fine = lengths_ok && {
        let k = chunk_count(nt, threads);
        let b: Vec<usize> = (0..=k).map(|i| nt * i / k).collect();
        let ok = run_dynamic(k, (0..k).collect(), |_, i| {
            // The largest vertex id, and the largest neighbour id plus one
            // (`NONE` wraps to 0).
            let tv = mesh.tets[b[i]..b[i + 1]].as_flattened().iter();
            let top = tv.fold(0u32, |m, &v| m.max(v));
            let nb = mesh.neighbors[b[i]..b[i + 1]].as_flattened().iter();
            let top_nb = nb.fold(0u32, |m, &u| m.max(u.wrapping_add(1)));
            (top as usize) < n && (top_nb as usize) <= nt
        });
        nt == 0 || ok.iter().all(|&x| x == Some(true))
    };
    if fine {
        return Ok(());
    }
    crate::geom::check::mesh_fits(
        n,
        &mesh.tets,
        &mesh.neighbors,
        mesh.vertex_map.len(),
        weights,
    )
}

impl Voronoi3 {
    /// Builds the Voronoi diagram of `points` from their Delaunay
    /// tetrahedralization `mesh` (as returned by [`crate::tetrahedralize`]).
    ///
    /// ```
    /// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 1.0, 1.0]];
    /// let mesh = delone::tetrahedralize(&pts).unwrap();
    /// let v = delone::tet::Voronoi3::new(&pts, &mesh).unwrap();
    /// assert_eq!(v.faces.len(), 9); // the Delaunay edges
    /// assert_eq!(v.open_faces.len(), 9); // all on the hull
    /// ```
    ///
    /// # Errors
    /// [`Error::InconsistentMesh`] when `mesh` does not belong to `points`.
    pub fn new(points: &[[f64; 3]], mesh: &TetMesh) -> Result<Voronoi3, Error> {
        Self::with_threads(points, mesh, 0)
    }

    /// [`Voronoi3::new`] on at most `threads` threads (`0`: the default,
    /// [`Voronoi3::default_threads`]). Meshes are cut into chunks of at least
    /// 2^14 tetrahedra, one per thread; the result is the same bit for bit
    /// whatever the thread count.
    ///
    /// ```
    /// let pts: Vec<[f64; 3]> = (0..50)
    ///     .map(|i| [(i as f64 * 0.37) % 1.0, (i as f64 * 0.61) % 1.0, (i as f64 * 0.23) % 1.0])
    ///     .collect();
    /// let mesh = delone::tetrahedralize(&pts).unwrap();
    /// let one = delone::tet::Voronoi3::with_threads(&pts, &mesh, 1).unwrap();
    /// assert_eq!(one, delone::tet::Voronoi3::with_threads(&pts, &mesh, 2).unwrap());
    /// ```
    ///
    /// # Errors
    /// [`Error::InconsistentMesh`] when `mesh` does not belong to `points`.
    pub fn with_threads(
        points: &[[f64; 3]],
        mesh: &TetMesh,
        threads: usize,
    ) -> Result<Voronoi3, Error> {
        check_mesh(points, mesh, None, threads)?;
        Ok(Self::build(
            points,
            &[],
            mesh,
            threads,
            &mut Phases::default(),
        ))
    }

    /// [`Voronoi3::with_threads`], also returning the wall time in seconds
    /// of each phase of the extraction, in order (for profiling; the names
    /// are not stable).
    ///
    /// ```
    /// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    /// let mesh = delone::tetrahedralize(&pts).unwrap();
    /// let (v, phases) = delone::tet::Voronoi3::with_phase_times(&pts, &mesh, 1).unwrap();
    /// assert_eq!(v, delone::tet::Voronoi3::new(&pts, &mesh).unwrap());
    /// assert!(phases.iter().all(|p| p.1 >= 0.0));
    /// ```
    ///
    /// # Errors
    /// As [`Voronoi3::new`].
    #[allow(clippy::type_complexity)]
    pub fn with_phase_times(
        points: &[[f64; 3]],
        mesh: &TetMesh,
        threads: usize,
    ) -> Result<(Voronoi3, Vec<(&'static str, f64)>), Error> {
        check_mesh(points, mesh, None, threads)?;
        let mut ph = Phases {
            on: true,
            ..Phases::default()
        };
        let v = Self::build(points, &[], mesh, threads, &mut ph);
        Ok((v, ph.times))
    }

    /// The default thread count of [`Voronoi3::new`]: the available
    /// parallelism, at most 8 (as [`crate::tri::refine::default_threads`]).
    ///
    /// ```
    /// let t = delone::tet::Voronoi3::default_threads();
    /// assert!((1..=8).contains(&t));
    /// ```
    pub fn default_threads() -> usize {
        crate::tri::refine::default_threads()
    }

    /// The power diagram of weighted `points` from their regular
    /// tetrahedralization `mesh` (as returned by
    /// [`crate::tet::regular_tetrahedralization`]): vertices are orthocentres,
    /// faces lie on radical planes, hidden points have empty cells.
    ///
    /// ```
    /// let pts = [[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [0.0, 4.0, 0.0], [0.0, 0.0, 4.0], [1.0, 1.0, 1.0]];
    /// let w = [0.0, 0.0, 0.0, 0.0, -10.0];
    /// let mesh = delone::tet::regular_tetrahedralization(&pts, &w).unwrap();
    /// let v = delone::tet::Voronoi3::new_power(&pts, &w, &mesh).unwrap();
    /// assert!(v.cell_faces(4).is_empty()); // hidden
    /// let c = v.cells_clipped(&pts, [[-1.0; 3], [5.0; 3]]);
    /// assert_eq!(c.volume[4], 0.0);
    /// assert!((c.volume.iter().sum::<f64>() - 216.0).abs() < 1e-9);
    /// ```
    ///
    /// # Errors
    /// [`Error::InconsistentMesh`] when `mesh` does not belong to `points`,
    /// [`Error::WeightCount`] when `weights` has another length.
    pub fn new_power(
        points: &[[f64; 3]],
        weights: &[f64],
        mesh: &TetMesh,
    ) -> Result<Voronoi3, Error> {
        Self::power_with_threads(points, weights, mesh, 0)
    }

    /// [`Voronoi3::new_power`] on at most `threads` threads (`0`: the
    /// default), as [`Voronoi3::with_threads`].
    ///
    /// ```
    /// let pts = [[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [0.0, 4.0, 0.0], [0.0, 0.0, 4.0], [1.0, 1.0, 1.0]];
    /// let w = [0.0, 0.0, 0.0, 0.0, 0.5];
    /// let mesh = delone::tet::regular_tetrahedralization(&pts, &w).unwrap();
    /// let v = delone::tet::Voronoi3::power_with_threads(&pts, &w, &mesh, 1).unwrap();
    /// assert_eq!(v.weights, w);
    /// ```
    ///
    /// # Errors
    /// As [`Voronoi3::new_power`].
    pub fn power_with_threads(
        points: &[[f64; 3]],
        weights: &[f64],
        mesh: &TetMesh,
        threads: usize,
    ) -> Result<Voronoi3, Error> {
        check_mesh(points, mesh, Some(weights.len()), threads)?;
        Ok(Self::build(
            points,
            weights,
            mesh,
            threads,
            &mut Phases::default(),
        ))
    }

    /// Everything, in passes over the tetrahedra cut into contiguous chunks,
    /// on `k` threads (`k = 1` for small meshes), no hash table. The
    /// passes are tasks that each thread takes as it becomes free
    /// (`run_dynamic`: a thread slowed down by other processes takes fewer),
    /// `m = 2k` chunks of the tetrahedra (`4k` in pass A, which has no
    /// seams to pay for), plus an odd task where there is one. (The mesh
    /// check before, `check_mesh`, is a parallel branch-free scan; the
    /// serial `mesh_fits` runs only to name what is wrong.)
    /// * A — circumcentres (mesh order) and, for meshes of 2^15 tetrahedra
    ///   or more, the Morton keys of the tetrahedra (from the first vertex,
    ///   whose coordinates the centre has just loaded) with per-chunk
    ///   histograms; then a stable counting sort gives the walk order, each
    ///   chunk placing its own tetrahedra;
    /// * B — 32-byte walk records (`Rec`: vertices and neighbours, in the
    ///   walk order) with per-tetrahedron prefix counts of owned facets;
    ///   then (`aux_pass`, beside the edge task of C) the global prefix
    ///   counts and a 16-bit word per
    ///   tetrahedron: the mirror slot of each facet (where the neighbour
    ///   across it keeps its vertex off the facet) and the rank of each
    ///   facet among the owned ones. Every facet is numbered by the lower of
    ///   its two tetrahedra (hull facets by their only one); no per-facet id
    ///   table: the walks derive a facet's number from its owner's prefix
    ///   count and rank (`facet_id`, branch-free);
    /// * C — one task writes all the edges (in place: no join; it runs
    ///   beside the `m` tasks of `aux_pass`, about as much work, so that
    ///   the `m` face tasks run alone and alike), `m` tasks the faces:
    ///   tetrahedron by tetrahedron, every local edge not yet
    ///   swept is swept, walking the ring of tetrahedra around the Delaunay
    ///   edge and marking it in every tetrahedron of the chunk it passes;
    ///   the face is emitted when no tetrahedron of the ring lies in an
    ///   earlier chunk — by the lowest tetrahedron of its ring, as with one
    ///   chunk. A walk step tracks the slots of the two vertices off the
    ///   edge: the mirror slot gives one, one slot lookup (`pos`) the other.
    ///   Each chunk writes its face vertices, face edges, face ends and
    ///   face sites into its window of four shared calloc'ed arrays (sized
    ///   from the chunk's share of the tetrahedra, with slack; untouched
    ///   pages cost nothing), staged in small buffers so the walk loop keeps
    ///   pushing;
    /// * D — the windows compacted in place (`compact`; a chunk that
    ///   overflowed its window spills, and then the join copies), the sites
    ///   turned into the faces in place (same size and alignment), the open
    ///   faces appended, then the cells by a counting sort of the faces by
    ///   site, each thread a range of sites, written into the pages of the
    ///   records (`cell_face_ids`) and of `perm` (`cell_offsets`).
    ///
    /// Every part is written in chunk order and numbered from the sizes of
    /// the earlier chunks, so for a valid mesh the result is the same bit
    /// for bit whatever `k`.
    ///
    /// Why it is built this way (measured with the same output, 200k
    /// points on one thread under callgrind, and 1M points on two threads):
    ///
    /// - Each tetrahedron is keyed by its loaded first vertex (no per-point
    ///   key table, whose random reads were a tenth of the extraction's
    ///   samples); keying by the centroid was 1.8% more instructions for no
    ///   clear gain.
    /// - The walks keep the mirror slots and ranks of the two vertices off
    ///   the swept edge, one slot lookup per step instead of three (2.23G
    ///   -> 1.93G instructions in the extraction), and the slot lookups are
    ///   branch-free: which slot holds a vertex is unpredictable (26.2M ->
    ///   6.8M mispredicted branches for 15% more instructions).
    /// - Unweighted circumcentres skip the weight terms (same bits); the
    ///   Morton key comes from the coordinates the centre has just loaded.
    /// - Records live in system-zeroed (calloc'ed) tables and the face
    ///   arrays in windows with 1/24 of slack, so the join copies almost
    ///   nothing; the cells' arrays and prefix counts reuse the pages of
    ///   dead scratch tables; the faces' edges are derived from
    ///   [`Voronoi3::vertex_edges`] and the open faces' rays instead of
    ///   stored (24 bytes per tetrahedron less). Every first touch of a
    ///   page is a page fault (about 0.5 s of system time per GB), so fresh
    ///   pages count: about 1.1 GB at 1M points, 0.87 GB of them the output.
    /// - Cells are counted by face ranges (each thread counts its faces'
    ///   sites, the counters are summed) rather than every thread scanning
    ///   all faces for its sites.
    ///
    /// Measured and rejected: advancing 4 or 8 ring walks in lock-step
    /// (with the Morton order most steps hit the cache); feeding the
    /// tetrahedra in Morton order (3-10% slower); building the records and
    /// numbering the edges in one pass (the interleaved work starves the
    /// gathers of memory-level parallelism); bare handles resolved
    /// afterwards (no gain); circumcentres in walk order (scattered writes
    /// cost more); pre-sized output slices (7% more instructions: the walk
    /// loop runs out of registers); a flat zeroed record buffer (2% more);
    /// branch-free facet numbering (94M more instructions for 2.3M fewer
    /// mispredictions); owned-facet masks in 64-bit prefix counts (twice
    /// the memory); a branch-free cell fill through a spare counter (its
    /// load-add-store chain costs more than the mispredicted branches).
    fn build(
        points: &[[f64; 3]],
        weights: &[f64],
        mesh: &TetMesh,
        threads: usize,
        ph: &mut Phases,
    ) -> Voronoi3 {
        ph.start();
        let tets = &mesh.tets;
        let nt = tets.len();
        let n = points.len();
        let p = |v: u32| &points[v as usize];
        let w = |v: u32| weights.get(v as usize).copied().unwrap_or(0.0);
        let k = chunk_count(nt, threads);
        let grid = Grid::new(points, nt);
        // Finer chunks for the phases run as tasks (`run_dynamic`).
        let m = if k > 1 { 2 * k } else { 1 };
        let fb: Vec<usize> = (0..=m).map(|i| nt * i / m).collect();
        // Pass A runs as `ma = 4k` tasks (no seams to pay for here; finer
        // tasks balance the odd one, the allocation of the records).
        let ma = if k > 1 { 4 * k } else { 1 };
        let ab: Vec<usize> = (0..=ma).map(|i| nt * i / ma).collect();
        // A. Circumcentres, and for large meshes the Morton keys of the
        // tetrahedra (one pass over the mesh, chunk by chunk) with each
        // chunk's key histogram.
        let mut vertices = vec![[0.0f64; 3]; nt];
        let mut inv = vec![0u32; if grid.is_some() { nt } else { 0 }];
        let key_chunks = if grid.is_some() {
            split_mut(&mut inv, &ab)
        } else {
            (0..ma).map(|_| &mut [][..]).collect()
        };
        let jobs: Vec<_> = split_mut(&mut vertices, &ab)
            .into_iter()
            .zip(key_chunks)
            .collect();
        let weighted = !weights.is_empty();
        let centre_of = |tv: &[u32; 4]| {
            if weighted {
                centre::<true>(tv.map(p), tv.map(w))
            } else {
                centre::<false>(tv.map(p), [0.0; 4])
            }
        };
        let hist: Vec<Vec<u32>> = run_dynamic(k, jobs, |i, (vc, kc)| {
            let chunk = &tets[ab[i]..ab[i + 1]];
            let Some(g) = &grid else {
                for (c, tv) in vc.iter_mut().zip(chunk) {
                    *c = centre_of(tv);
                }
                return Vec::new();
            };
            // The key of the first vertex, whose coordinates the centre has
            // just loaded (no lookup table: a random read per tetrahedron).
            let mut hist = vec![0u32; g.keys()];
            for ((c, x), tv) in vc.iter_mut().zip(kc.iter_mut()).zip(chunk) {
                *c = centre_of(tv);
                *x = g.key(p(tv[0]));
                hist[*x as usize] += 1;
            }
            hist
        })
        .into_iter()
        .map(Option::unwrap_or_default)
        .collect();
        ph.lap("centres");
        // The walk order (large meshes): `perm[new] = old`, `inv[old] =
        // new`, a stable counting sort of the keys, each chunk placing its
        // own tetrahedra.
        let perm: Vec<u32> = if let Some(g) = &grid {
            // The histograms become the start positions in place.
            let mut start = hist;
            let mut at = 0u32;
            for c in 0..g.keys() {
                for h in start.iter_mut() {
                    let x = h.get(c).copied().unwrap_or(0);
                    if let Some(y) = h.get_mut(c) {
                        *y = at;
                    }
                    at += x;
                }
            }
            let jobs: Vec<_> = split_mut(&mut inv, &ab).into_iter().zip(start).collect();
            run_dynamic(k, jobs, |_, (kc, mut st)| {
                for x in kc.iter_mut() {
                    let c = *x as usize;
                    *x = st[c];
                    st[c] += 1;
                }
            });
            let mut perm = vec![0u32; nt];
            for (old, &new) in inv.iter().enumerate() {
                perm[new as usize] = old as u32;
            }
            perm
        } else {
            (0..nt as u32).collect()
        };
        ph.lap("order");
        // Records (chunk by chunk of the walk order); per chunk the facets
        // it will number (hull facets and those whose neighbour comes
        // later).
        let inv_ref = &inv;
        // The records, zeroed by the system (no fill: the pass below writes
        // every one), from a 32-byte boundary: the allocator gives 16-byte
        // alignment, so a spare row of 8 words lets the table start at the
        // next multiple of 32 (the address only places the table; the
        // result does not depend on it).
        // A flat `u32` table, so that its pages, once the walks are done,
        // hold the cells' face ids (`cell_face_ids`: no fresh pages).
        let mut rec_words = vec![0u32; 8 * nt + 8];
        let off = ((rec_words.as_ptr() as usize).wrapping_neg() & 31) / 4;
        let recs: &mut [Rec] = rec_words[off..off + 8 * nt]
            .as_chunks_mut::<4>()
            .0
            .as_chunks_mut::<2>()
            .0;
        // As `m` tasks (`run_dynamic`: a thread slowed down by others
        // takes fewer).
        let jobs: Vec<_> = split_mut(&mut *recs, &fb);
        let owned: Vec<usize> = run_dynamic(k, jobs, |i, rc| {
            let lo = fb[i];
            let mut owned = 0;
            for (j, r) in rc.iter_mut().enumerate() {
                let t = lo + j;
                let old = perm[t] as usize;
                let nb = mesh.neighbors[old];
                let nb = if inv_ref.is_empty() {
                    nb
                } else {
                    nb.map(|u| if u == NONE { NONE } else { inv_ref[u as usize] })
                };
                owned += nb.iter().filter(|&&u| u > t as u32).count();
                *r = [tets[old], nb];
            }
            owned
        })
        .into_iter()
        .map(|x| x.unwrap_or(0))
        .collect();
        let recs = &*recs;
        // Per tetrahedron, the number of owned facets before it (filled by
        // `aux_pass`), in the pages of `inv` (no fresh pages: every entry
        // is written).
        let mut pre_vec = inv;
        pre_vec.resize(nt, 0);
        ph.lap("records");
        // B. Global prefix counts of the owned facets and the `aux` words
        // (mirror slots and ranks) for the walks.
        let total: usize = owned.iter().sum();
        let mut base = vec![0usize; m + 1];
        for i in 0..m {
            base[i + 1] = base[i] + owned[i];
        }
        // With them, as one more task, the edges (they need only the
        // records): about as much work as the `aux` words, so the `k`
        // threads stay busy here and the face tasks below are all alike.
        // The `aux` tasks are the chunks of the records.
        let mut aux = vec![0u16; nt];
        let perm_vec = perm;
        let perm = &perm_vec[..];
        let jobs: Vec<_> = std::iter::once(None)
            .chain(
                split_mut(&mut pre_vec, &fb)
                    .into_iter()
                    .zip(split_mut(&mut aux, &fb))
                    .map(Some),
            )
            .collect();
        let edge_part = run_dynamic(k, jobs, |i, job| match job {
            None => Some(edge_pass(points, recs, perm, total)),
            Some((pc, ac)) => {
                let lo = fb[i - 1];
                aux_pass(recs, pc, ac, lo, base[i - 1]);
                None
            }
        })
        .into_iter()
        .next()
        .flatten()
        .flatten();
        ph.lap("aux");
        // C. The edges (one task, written in place) and the faces (the ring
        // walks, in `m` chunks), as tasks taken by `k` threads. Each face
        // chunk writes its face vertices, edges and ends into its window of
        // the four shared arrays (calloc'ed: untouched slack costs nothing),
        // sized from its share of the tetrahedra with slack; what does not
        // fit spills (then the join copies).
        let pre = &pre_vec[..];
        let aux = &aux[..];
        let top = total.saturating_sub(1) as u32;
        // Window sizes per tetrahedron: 6 face vertices; about 7/6 faces
        // (Euler, random points).
        // The first chunk takes the rings across its seam: about 1% more at
        // 200k points in 4 chunks (a spill makes the join copy the whole
        // array into fresh pages), hence 1/4 of slack (untouched, free).
        let wsize = |j: usize, i: usize| {
            let len = fb[i + 1] - fb[i];
            if j < 1 {
                6 * len + len / 4 + 1024
            } else {
                len * 3 / 2 + 256
            }
        };
        // `starts[j][i]`: where chunk i writes in array j (the face ends,
        // j = 1, keep a leading 0; j = 2 are the faces' sites).
        let first = [0usize, 1, 0];
        let starts: Vec<Vec<usize>> = (0..3)
            .map(|j| {
                let mut at = first[j];
                let mut v = Vec::with_capacity(m + 1);
                for i in 0..m {
                    v.push(at);
                    at += wsize(j, i);
                }
                v.push(at);
                v
            })
            .collect();
        let mut arrays: Vec<Vec<u32>> = starts[..2].iter().map(|s| vec![0u32; s[m]]).collect();
        let mut site_array = vec![[0u32; 2]; starts[2][m]];
        let mut wins: Vec<Vec<&mut [u32]>> = arrays
            .iter_mut()
            .zip(&starts)
            .zip(first)
            .map(|((a, st), f)| {
                let rel: Vec<usize> = st.iter().map(|&x| x - f).collect();
                split_mut(&mut a[f..], &rel)
            })
            .collect();
        let mut site_wins = split_mut(&mut site_array, &starts[2]).into_iter();
        let mut tasks: Vec<(Wins, &mut [[u32; 2]])> = Vec::with_capacity(m);
        for _ in 0..m {
            let w: Wins = std::array::from_fn(|j| wins[j].remove(0));
            tasks.push((w, site_wins.next().unwrap_or_default()));
        }
        drop(wins);
        drop(site_wins);
        // The vertices' edges, written by the face tasks (each the rows of
        // its tetrahedra, scattered by `perm`: relaxed atomic stores).
        let vedges: Vec<[AtomicU32; 4]> = (0..nt).map(|_| Default::default()).collect();
        let face_parts: Vec<FacePart> = run_dynamic(k, tasks, |i, w| {
            let (lo, hi) = (fb[i], fb[i + 1]);
            face_pass(points, recs, (pre, top), aux, perm, lo, hi, w, &vedges)
        })
        .into_iter()
        .map(Option::unwrap_or_default)
        .collect();
        let vertex_edges: Vec<[u32; 4]> = vedges
            .into_iter()
            .map(|r| r.map(AtomicU32::into_inner))
            .collect();
        let EdgePart {
            edges,
            ray_edges,
            ray_directions,
        } = edge_part.unwrap_or_default();
        ph.lap("faces");
        // The parts put together: the four arrays compacted in place (on
        // up to k threads; the sites then become the faces in place, same
        // size and alignment), the open faces appended.
        let mut adds = vec![vec![0u32; m]; 3];
        let (mut bv, mut bf) = (0u32, 0u32);
        let mut open_faces = Vec::new();
        let mut open_face_rays = Vec::new();
        let mut open_face_edges = Vec::new();
        for (i, x) in face_parts.iter().enumerate() {
            adds[1][i] = bv;
            bv = bv.wrapping_add(x.wins[0].0 as u32);
            open_faces.extend(x.open_faces.iter().map(|&f| f + bf));
            open_face_rays.extend_from_slice(&x.open_face_rays);
            open_face_edges.extend_from_slice(&x.open_face_edges);
            bf = bf.wrapping_add(x.sites.0 as u32);
        }
        let parts: Vec<Vec<(usize, Vec<u32>)>> = (0..2)
            .map(|j| {
                face_parts
                    .iter()
                    .map(|x| (x.wins[j].0, x.wins[j].1.clone()))
                    .collect()
            })
            .collect();
        let site_parts: Vec<(usize, Vec<[u32; 2]>)> =
            face_parts.into_iter().map(|x| x.sites).collect();
        enum Join {
            Ids(usize, Vec<u32>),
            Sites(Vec<[u32; 2]>),
        }
        let jobs: Vec<Join> = std::iter::once(Join::Sites(site_array))
            .chain(arrays.into_iter().enumerate().map(|(j, a)| Join::Ids(j, a)))
            .collect();
        let mut joined = run_dynamic(k, jobs, |_, job| match job {
            Join::Ids(j, a) => {
                let add = |x: u32, d: u32| x.wrapping_add(d);
                (
                    compact(a, first[j], &starts[j][..m], &parts[j], &adds[j], add),
                    vec![],
                )
            }
            Join::Sites(a) => {
                let a = compact(a, 0, &starts[2][..m], &site_parts, &adds[2], |x, _| x);
                (
                    vec![],
                    a.into_iter().map(|sites| FaceInfo3 { sites }).collect(),
                )
            }
        })
        .into_iter()
        .map(|x| x.unwrap_or_default());
        let faces: Vec<FaceInfo3> = joined.next().unwrap_or_default().1;
        let mut next = || joined.next().unwrap_or_default().0;
        let (face_vertices, face_offsets) = (next(), next());
        ph.lap("join");
        let mut unbounded = vec![false; n];
        for &r in &ray_edges {
            for &s in &edges[r as usize].sites {
                unbounded[s as usize] = true;
            }
        }
        // D. Cells: the faces around each site, a counting sort. Each
        // thread counts the sites of a range of faces (the first in the
        // pages of the prefix counts, dead now), the counts are summed, then
        // each thread fills a range of sites (scanning all faces).
        let sb: Vec<usize> = (0..=k).map(|i| n * i / k).collect();
        let nf = faces.len();
        let fsb: Vec<usize> = (0..=k).map(|i| nf * i / k).collect();
        let fs = &faces[..];
        let mut first_count = Some(pre_vec);
        let items: Vec<Option<Vec<u32>>> = (0..k).map(|_| first_count.take()).collect();
        let site_counts = run_dynamic(k, items, |i, c| {
            // One spare counter at `n` (only an invalid mesh has a site
            // beyond: then it is not counted, as before).
            let mut c = c.unwrap_or_default();
            c.clear();
            c.resize(n + 1, 0);
            for f in &fs[fsb[i]..fsb[i + 1]] {
                for &s in &f.sites {
                    c[(s as usize).min(n)] += 1;
                }
            }
            c
        });
        // In the pages of `perm` (no fresh pages; zeroed).
        let mut count = perm_vec;
        count.clear();
        count.resize(n + 1, 0);
        count.shrink_to_fit();
        for c in site_counts.iter().flatten() {
            for (x, &y) in count[1..].iter_mut().zip(c) {
                *x += y;
            }
        }
        drop(site_counts);
        for i in 0..n {
            count[i + 1] += count[i];
        }
        let cell_offsets = count;
        // In the pages of the records: every entry is written below (each
        // site's range gets exactly as many faces as were counted for it).
        let mut cell_face_ids = rec_words;
        cell_face_ids.resize(*cell_offsets.last().unwrap_or(&0) as usize, 0);
        cell_face_ids.shrink_to_fit();
        let cb: Vec<usize> = sb.iter().map(|&s| cell_offsets[s] as usize).collect();
        let cell_offsets_ref = &cell_offsets;
        run_dynamic(k, split_mut(&mut cell_face_ids, &cb), |i, out| {
            let (lo, hi) = (sb[i], sb[i + 1]);
            let base = cb[i] as u32;
            let mut fill: Vec<u32> = cell_offsets_ref[lo..hi].iter().map(|&o| o - base).collect();
            for (fi, f) in fs.iter().enumerate() {
                for &s in &f.sites {
                    let j = (s as usize).wrapping_sub(lo);
                    if j < fill.len() {
                        out[fill[j] as usize] = fi as u32;
                        fill[j] += 1;
                    }
                }
            }
        });
        ph.lap("cells");
        Voronoi3 {
            vertices,
            edges,
            ray_edges,
            ray_directions,
            faces,
            open_faces,
            open_face_rays,
            face_offsets,
            face_vertices,
            open_face_edges,
            vertex_edges,
            cell_offsets,
            cell_face_ids,
            unbounded,
            vertex_map: mesh.vertex_map.clone(),
            weights: weights.to_vec(),
        }
    }

    /// The direction of edge `e`: for a ray the outward normal of its hull
    /// triangle, of twice the triangle's area; `[0, 0, 0]` for a segment.
    ///
    /// # Panics
    /// If `e` is not an edge index.
    ///
    /// ```
    /// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    /// let mesh = delone::tetrahedralize(&pts).unwrap();
    /// let v = delone::tet::Voronoi3::new(&pts, &mesh).unwrap();
    /// let down = (0..4).find(|&e| v.edges[e].sites.iter().all(|&s| s != 3)).unwrap();
    /// assert_eq!(v.direction(down), [0.0, 0.0, -1.0]);
    /// ```
    pub fn direction(&self, e: usize) -> [f64; 3] {
        match self.ray_edges.binary_search(&(e as u32)) {
            Ok(k) => self.ray_directions[k],
            Err(_) => {
                assert!(e < self.edges.len(), "edge {e} out of range");
                [0.0; 3]
            }
        }
    }

    /// Face `f` (the dual of a Delaunay edge).
    ///
    /// # Panics
    /// If `f` is not a face index.
    ///
    /// ```
    /// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    /// let mesh = delone::tetrahedralize(&pts).unwrap();
    /// let v = delone::tet::Voronoi3::new(&pts, &mesh).unwrap();
    /// let f = v.face(0);
    /// assert_eq!(f.vertices, &[0]);
    /// assert!(f.rays.is_some());
    /// ```
    pub fn face(&self, f: usize) -> Face3<'_> {
        let info = self.faces[f];
        let (lo, hi) = (
            self.face_offsets[f] as usize,
            self.face_offsets[f + 1] as usize,
        );
        let (rays, ray_edges) = match self.open_faces.binary_search(&(f as u32)) {
            Ok(k) => (
                Some(self.open_face_rays[k]),
                Some(self.open_face_edges.get(k).copied().unwrap_or([NONE; 2])),
            ),
            Err(_) => (None, None),
        };
        let vertices = &self.face_vertices[lo..hi];
        Face3 {
            sites: info.sites,
            vertices,
            rays,
            edges: FaceEdges {
                vertex_edges: &self.vertex_edges,
                vertices,
                rays: ray_edges,
                at: 0,
                end: vertices.len() + usize::from(rays.is_some()),
            },
        }
    }

    fn rep(&self, p: usize) -> usize {
        match self.vertex_map.get(p) {
            Some(&r) if r != NONE => r as usize,
            _ => p,
        }
    }

    /// The faces of the cell of input point `p` (a duplicate gets its
    /// original's), by index into [`Voronoi3::faces`].
    ///
    /// # Panics
    /// If `p` is not an index of the input points.
    ///
    /// ```
    /// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.0; 3]];
    /// let mesh = delone::tetrahedralize(&pts).unwrap();
    /// let v = delone::tet::Voronoi3::new(&pts, &mesh).unwrap();
    /// assert_eq!(v.cell_faces(0).len(), 3);
    /// assert_eq!(v.cell_faces(4), v.cell_faces(0));
    /// ```
    pub fn cell_faces(&self, p: usize) -> &[u32] {
        let s = self.rep(p);
        &self.cell_face_ids[self.cell_offsets[s] as usize..self.cell_offsets[s + 1] as usize]
    }

    /// Whether the cell of input point `p` is unbounded.
    ///
    /// # Panics
    /// If `p` is not an index of the input points.
    ///
    /// ```
    /// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    /// let mesh = delone::tetrahedralize(&pts).unwrap();
    /// assert!(delone::tet::Voronoi3::new(&pts, &mesh).unwrap().is_unbounded(2));
    /// ```
    pub fn is_unbounded(&self, p: usize) -> bool {
        self.unbounded[self.rep(p)]
    }

    /// The Delaunay neighbours of input point `p` (the sites across the faces
    /// of its cell), in the order of [`Voronoi3::cell_faces`].
    ///
    /// ```
    /// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    /// let mesh = delone::tetrahedralize(&pts).unwrap();
    /// let v = delone::tet::Voronoi3::new(&pts, &mesh).unwrap();
    /// let mut nb: Vec<u32> = v.neighbors(0).collect();
    /// nb.sort();
    /// assert_eq!(nb, [1, 2, 3]);
    /// ```
    pub fn neighbors(&self, p: usize) -> impl Iterator<Item = u32> + '_ {
        let s = self.rep(p) as u32;
        self.cell_faces(p).iter().map(move |&f| {
            let [a, b] = self.faces[f as usize].sites;
            if a == s {
                b
            } else {
                a
            }
        })
    }

    /// Every cell intersected with the box `bbox = [min, max]`, as convex
    /// polyhedra with volume and centroid, one per input point (duplicates
    /// get a copy of their original's).
    ///
    /// Each cell is computed by clipping the box with the bisector planes of
    /// its site and each Delaunay neighbour (nearest first), which handles
    /// unbounded cells exactly like bounded ones. A cell that misses the box
    /// is empty (volume `0`, centroid = its site).
    ///
    /// ```
    /// let mut pts = vec![];
    /// for k in 0..8 {
    ///     pts.push([0.25 + 0.5 * (k & 1) as f64, 0.25 + 0.5 * (k >> 1 & 1) as f64, 0.25 + 0.5 * (k >> 2) as f64]);
    /// }
    /// let mesh = delone::tetrahedralize(&pts).unwrap();
    /// let v = delone::tet::Voronoi3::new(&pts, &mesh).unwrap();
    /// let c = v.cells_clipped(&pts, [[0.0; 3], [1.0; 3]]);
    /// for p in 0..8 {
    ///     assert!((c.volume[p] - 0.125).abs() < 1e-15);
    ///     assert_eq!(c.cells[p].faces.len(), 6);
    /// }
    /// ```
    pub fn cells_clipped(&self, points: &[[f64; 3]], bbox: Box3) -> ClippedCells3 {
        let n = self.unbounded.len();
        let mut out = ClippedCells3 {
            cells: Vec::with_capacity(n),
            volume: vec![0.0; n],
            centroid: vec![[0.0; 3]; n],
        };
        let mut nb: Vec<(f64, u32)> = Vec::new();
        let mut work = Clipper::default();
        for s in 0..n {
            let r = self.rep(s);
            if r < s {
                let c = out.cells[r].clone();
                out.cells.push(c);
                out.volume[s] = out.volume[r];
                out.centroid[s] = out.centroid[r];
                continue;
            }
            let site = points[s];
            nb.clear();
            nb.extend(self.neighbors(s).map(|q| {
                let d = sub(&points[q as usize], &site);
                (dot(&d, &d), q)
            }));
            nb.sort_unstable_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
            let poly = if self.cell_faces(s).is_empty() {
                Polyhedron::default()
            } else {
                work.reset_box(bbox);
                let w = |v: usize| self.weights.get(v).copied().unwrap_or(0.0);
                for &(_, q) in &nb {
                    if !work.clip(&site, &points[q as usize], w(s) - w(q as usize)) {
                        break;
                    }
                }
                work.extract()
            };
            let (vol, cen) = poly.volume_centroid(&site);
            out.volume[s] = vol;
            out.centroid[s] = cen;
            out.cells.push(poly);
        }
        out
    }
}

/// A convex polyhedron: vertices and faces (vertex ids counterclockwise seen
/// from outside).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Polyhedron {
    /// Corner coordinates.
    pub vertices: Vec<[f64; 3]>,
    /// Faces as lists of vertex ids, counterclockwise seen from outside.
    pub faces: Vec<Vec<u32>>,
}

impl Polyhedron {
    /// Volume and centroid, computed relative to `origin` (a nearby point,
    /// for precision); an empty polyhedron gives `(0, origin)`.
    ///
    /// ```
    /// let pts = [[0.5, 0.5, 0.5], [2.0, 0.5, 0.5], [0.5, 2.0, 0.5], [0.5, 0.5, 2.0]];
    /// let mesh = delone::tetrahedralize(&pts).unwrap();
    /// let v = delone::tet::Voronoi3::new(&pts, &mesh).unwrap();
    /// let c = v.cells_clipped(&pts, [[0.0; 3], [1.0; 3]]);
    /// let (vol, _) = c.cells[0].volume_centroid(&[0.0; 3]);
    /// assert!((vol - 1.0).abs() < 1e-15); // the whole box is closest to site 0
    /// ```
    pub fn volume_centroid(&self, origin: &[f64; 3]) -> (f64, [f64; 3]) {
        let (mut v6, mut c) = (0.0, [0.0; 3]);
        for f in &self.faces {
            if f.len() < 3 {
                continue;
            }
            let a = sub(&self.vertices[f[0] as usize], origin);
            for k in 1..f.len() - 1 {
                let b = sub(&self.vertices[f[k] as usize], origin);
                let d = sub(&self.vertices[f[k + 1] as usize], origin);
                let vol = dot(&a, &cross(&b, &d));
                v6 += vol;
                for i in 0..3 {
                    c[i] += vol * (a[i] + b[i] + d[i]);
                }
            }
        }
        if v6 <= 0.0 {
            return (0.0, *origin);
        }
        (
            v6 / 6.0,
            [
                origin[0] + c[0] / (4.0 * v6),
                origin[1] + c[1] / (4.0 * v6),
                origin[2] + c[2] / (4.0 * v6),
            ],
        )
    }
}

/// Voronoi cells clipped to a box, as returned by [`Voronoi3::cells_clipped`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ClippedCells3 {
    /// The clipped cell of every input point.
    pub cells: Vec<Polyhedron>,
    /// Volume of each clipped cell.
    pub volume: Vec<f64>,
    /// Centroid of each clipped cell (the site itself for an empty cell).
    pub centroid: Vec<[f64; 3]>,
}

/// Half-space clipping of a convex polyhedron, with reusable buffers.
#[derive(Default)]
struct Clipper {
    verts: Vec<[f64; 3]>,
    faces: Vec<Vec<u32>>,
    side: Vec<f64>,
    cut: Vec<((u32, u32), u32)>,
    cap: Vec<(u32, u32)>,
    spare: Vec<Vec<u32>>,
}

impl Clipper {
    fn reset_box(&mut self, b: Box3) {
        self.verts.clear();
        self.verts.extend((0..8).map(|k| box_corner(&b, k)));
        self.spare.append(&mut self.faces);
        for f in BOX_SIDES.chunks(4) {
            let mut v = self.spare.pop().unwrap_or_default();
            v.clear();
            v.extend_from_slice(f);
            self.faces.push(v);
        }
    }

    /// Keeps the part closer to `p` than to `q` in power distance, `dw`
    /// being `w_p - w_q` (0 for the Voronoi diagram): the half-space
    /// `(x - p)·(q - p) <= (|q - p|² + dw) / 2`. Returns false when empty.
    fn clip(&mut self, p: &[f64; 3], q: &[f64; 3], dw: f64) -> bool {
        let nrm = sub(q, p);
        let len2 = dot(&nrm, &nrm);
        if len2 == 0.0 {
            return true;
        }
        let h = 0.5 * (len2 + dw);
        self.side.clear();
        let (mut any_out, mut any_in) = (false, false);
        for x in &self.verts {
            let s = dot(&sub(x, p), &nrm) - h;
            self.side.push(s);
        }
        // Only vertices used by faces count (clipped-away ones linger).
        for f in &self.faces {
            for &v in f {
                if self.side[v as usize] > 0.0 {
                    any_out = true;
                } else {
                    any_in = true;
                }
            }
        }
        if !any_out {
            return true;
        }
        if !any_in {
            self.spare.append(&mut self.faces);
            return false;
        }
        self.cut.clear();
        self.cap.clear();
        let old = std::mem::take(&mut self.faces);
        for f in old {
            let m = f.len();
            if f.iter().all(|&v| self.side[v as usize] <= 0.0) {
                self.faces.push(f);
                continue;
            }
            let mut g = self.spare.pop().unwrap_or_default();
            g.clear();
            let (mut exit, mut entry) = (NONE, NONE);
            for k in 0..m {
                let (a, b) = (f[k], f[(k + 1) % m]);
                let (sa, sb) = (self.side[a as usize], self.side[b as usize]);
                if sa <= 0.0 && g.last() != Some(&a) {
                    g.push(a);
                }
                if (sa <= 0.0) != (sb <= 0.0) {
                    let x = self.crossing(a, b, p, &nrm, h);
                    if g.last() != Some(&x) {
                        g.push(x);
                    }
                    if sa <= 0.0 {
                        exit = x;
                    } else {
                        entry = x;
                    }
                }
            }
            if g.len() > 1 && g.first() == g.last() {
                g.pop();
            }
            if exit != NONE && entry != NONE && exit != entry {
                self.cap.push((entry, exit));
            }
            if g.len() >= 3 {
                self.faces.push(g);
            } else {
                self.spare.push(g);
            }
            self.spare.push(f);
        }
        // The cap: chain entry -> exit links into one polygon.
        if self.cap.len() >= 3 {
            self.cap.sort_unstable();
            let mut g = self.spare.pop().unwrap_or_default();
            g.clear();
            let start = self.cap[0].0;
            let mut v = start;
            loop {
                g.push(v);
                let Ok(k) = self.cap.binary_search_by(|e| e.0.cmp(&v)) else {
                    break;
                };
                v = self.cap[k].1;
                if v == start || g.len() > self.cap.len() {
                    break;
                }
            }
            if g.len() >= 3 {
                self.faces.push(g);
            } else {
                self.spare.push(g);
            }
        }
        !self.faces.is_empty()
    }

    /// The vertex where edge `a`–`b` crosses the plane, created once per
    /// edge; an inside end on the plane is its own crossing.
    fn crossing(&mut self, a: u32, b: u32, p: &[f64; 3], nrm: &[f64; 3], h: f64) -> u32 {
        let key = (a.min(b), a.max(b));
        if let Some(&(_, x)) = self.cut.iter().find(|e| e.0 == key) {
            return x;
        }
        let (i, o) = if self.side[a as usize] <= 0.0 {
            (a, b)
        } else {
            (b, a)
        };
        let (si, so) = (self.side[i as usize], self.side[o as usize]);
        let x = if si == 0.0 {
            i
        } else {
            let t = si / (si - so);
            let (pi, po) = (self.verts[i as usize], self.verts[o as usize]);
            self.verts.push([
                pi[0] + t * (po[0] - pi[0]),
                pi[1] + t * (po[1] - pi[1]),
                pi[2] + t * (po[2] - pi[2]),
            ]);
            let s = dot(&sub(self.verts.last().unwrap_or(&pi), p), nrm) - h;
            self.side.push(s.min(0.0));
            (self.verts.len() - 1) as u32
        };
        self.cut.push((key, x));
        x
    }

    /// The current polyhedron with unused vertices dropped.
    fn extract(&mut self) -> Polyhedron {
        let mut map = vec![NONE; self.verts.len()];
        let mut poly = Polyhedron::default();
        for f in &self.faces {
            let mut g = Vec::with_capacity(f.len());
            for &v in f {
                if map[v as usize] == NONE {
                    map[v as usize] = poly.vertices.len() as u32;
                    poly.vertices.push(self.verts[v as usize]);
                }
                g.push(map[v as usize]);
            }
            poly.faces.push(g);
        }
        poly
    }
}

/// Lloyd relaxation in a box (3D): `iterations` times, tetrahedralize the
/// points, clip their Voronoi cells to `bbox` and move every point to the
/// centroid of its clipped cell. Points outside the box stay; deterministic.
///
/// # Errors
/// The errors of [`crate::tetrahedralize`].
///
/// ```
/// let pts: Vec<[f64; 3]> = (0..30)
///     .map(|i| [(i as f64 * 0.37) % 1.0, (i as f64 * 0.61) % 1.0, (i as f64 * 0.23) % 1.0])
///     .collect();
/// let out = delone::tet::lloyd(&pts, [[0.0; 3], [1.0; 3]], 3).unwrap();
/// assert_eq!(out.len(), 30);
/// ```
pub fn lloyd(points: &[[f64; 3]], bbox: Box3, iterations: usize) -> Result<Vec<[f64; 3]>, Error> {
    crate::geom::lloyd(points, iterations, |pts| {
        let c = Voronoi3::new(pts, &super::tetrahedralize(pts)?)?.cells_clipped(pts, bbox);
        Ok((c.volume, c.centroid))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn local_edges_are_even_permutations() {
        for e in EDGES {
            let mut inv = 0;
            for i in 0..4 {
                for j in i + 1..4 {
                    if e[i] > e[j] {
                        inv += 1;
                    }
                }
            }
            assert_eq!(inv % 2, 0, "{e:?}");
        }
    }

    #[test]
    fn edge_index_inverts_edges() {
        for (k, e) in EDGES.iter().enumerate() {
            assert_eq!(EDGE_INDEX[e[0]][e[1]], k);
            assert_eq!(EDGE_INDEX[e[1]][e[0]], k);
        }
    }

    /// Writes `parts` through windows of the sizes `wins` after a leading
    /// `first` zeros, then compacts: the parts concatenated, plus `add`.
    fn windows_round_trip(first: usize, wins: &[usize], parts: &[Vec<u32>], add: &[u32]) {
        let mut starts = vec![first];
        for w in wins {
            starts.push(starts.last().unwrap() + w);
        }
        let mut a = vec![0u32; *starts.last().unwrap()];
        let rel: Vec<usize> = starts.iter().map(|&x| x - first).collect();
        let mut written = vec![];
        for (buf, part) in split_mut(&mut a[first..], &rel).into_iter().zip(parts) {
            let mut w = Win::new(buf);
            // In two pieces, as the face pass flushes.
            w.extend(&part[..part.len() / 2]);
            w.extend(&part[part.len() / 2..]);
            written.push(w.done());
        }
        let got = compact(
            a,
            first,
            &starts[..wins.len()],
            &written,
            add,
            u32::wrapping_add,
        );
        let mut want = vec![0u32; first];
        for (p, &d) in parts.iter().zip(add) {
            want.extend(p.iter().map(|&x| x + d));
        }
        assert_eq!(got, want);
    }

    #[test]
    fn windows_compact_in_place_and_after_spills() {
        let parts = vec![vec![1, 2, 3], vec![], vec![4, 5, 6, 7, 8], vec![9]];
        // Room to spare: in place.
        windows_round_trip(0, &[4, 2, 6, 3], &parts, &[0; 4]);
        windows_round_trip(1, &[5, 1, 5, 1], &parts, &[0, 3, 3, 8]);
        // Parts 0 and 2 spill.
        windows_round_trip(0, &[2, 2, 1, 3], &parts, &[0; 4]);
        windows_round_trip(1, &[0, 0, 0, 0], &parts, &[10, 20, 30, 40]);
    }

    #[test]
    fn circumcenter_of_a_corner_tet() {
        let q = crate::geom::vec3::corner_tet(2.0);
        let c = centre::<true>([&q[0], &q[1], &q[2], &q[3]], [0.0; 4]);
        assert_eq!(c, [1.0, 1.0, 1.0]);
    }
}
