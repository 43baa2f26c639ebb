//! 2D Voronoi diagrams as the dual of a Delaunay triangulation, cells clipped
//! to a box, and Lloyd relaxation towards a centroidal Voronoi tessellation.
//!
//! * [`Voronoi2::new`] — vertices (circumcentres, one per triangle), edges
//!   (one per Delaunay edge: a segment, or a ray for a hull edge) and cells
//!   (one per input point, counterclockwise).
//! * [`Voronoi2::cells_clipped`] — every cell intersected with an
//!   axis-aligned box, with area and centroid.
//! * [`lloyd`] — Lloyd's algorithm in a box.
//! * [`Voronoi2::new_power`] — the power diagram of weighted points, dual of
//!   their regular triangulation: vertices are the power centres
//!   (orthocentres) of the triangles, edges lie on radical axes, hidden
//!   points have empty cells.
//!
//! # Costs
//!
//! Centres and edges on a second thread, then the stars: the tail (the last
//! 12/64 of the triangles, `HEAD_64THS`) on that thread, the rest on the
//! caller's, the tail's cells appended to the head's
//! ([`Voronoi2::with_threads`]); the circumcentre's rotation and the walk's
//! corner lookup are branch-free.
//!
//! # References
//! * G. Voronoi (1908); B. Delaunay (1934) — the duality used here.
//! * S. Lloyd, "Least squares quantization in PCM", IEEE Trans. Inf. Theory 28 (1982).
//! * F. Aurenhammer, "Power diagrams: properties, algorithms and
//!   applications", SIAM J. Comput. 16 (1987).
//! * Q. Du, V. Faber, M. Gunzburger, "Centroidal Voronoi tessellations:
//!   applications and algorithms", SIAM Review 41 (1999).

use delone_predicates::orient2d;

use super::topo::{NEXT, PREV};
use super::TriMesh;
use crate::{Error, NONE};

/// An axis-aligned box `[min, max]`.
pub type Box2 = [[f64; 2]; 2];

/// One Voronoi edge: the dual of a Delaunay edge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VoronoiEdge2 {
    /// The two sites (input point indices) whose cells the edge separates:
    /// `sites[0] → sites[1]` is the Delaunay edge seen counterclockwise from
    /// the triangle `vertices[0]`.
    pub sites: [u32; 2],
    /// The Voronoi vertices at its ends (triangle indices). For a ray
    /// (a Delaunay hull edge) `vertices[1]` is [`NONE`].
    pub vertices: [u32; 2],
}

impl VoronoiEdge2 {
    /// For a ray, its direction: the outward normal of the hull edge
    /// `sites[0] → sites[1]`, of the hull edge's length (exact:
    /// `(b.y - a.y, a.x - b.x)`); `[0, 0]` for a segment. `points` are the
    /// input points of the diagram.
    ///
    /// # Panics
    /// If the sites are not indices of `points`.
    ///
    /// ```
    /// let pts = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
    /// let mesh = delone::triangulate(&pts).unwrap();
    /// let v = delone::tri::Voronoi2::new(&pts, &mesh).unwrap();
    /// let bottom = v.edges.iter().find(|e| e.sites == [0, 1]).unwrap();
    /// assert_eq!(bottom.direction(&pts), [0.0, -1.0]);
    /// ```
    pub fn direction(&self, points: &[[f64; 2]]) -> [f64; 2] {
        if self.is_ray() {
            let [a, b] = self.sites.map(|s| &points[s as usize]);
            outward(a, b)
        } else {
            [0.0, 0.0]
        }
    }

    /// Whether the edge is a ray (unbounded).
    ///
    /// ```
    /// let pts = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
    /// let mesh = delone::triangulate(&pts).unwrap();
    /// let v = delone::tri::Voronoi2::new(&pts, &mesh).unwrap();
    /// assert!(v.edges.iter().all(|e| e.is_ray()));
    /// ```
    pub fn is_ray(&self) -> bool {
        self.vertices[1] == NONE
    }
}

/// One Voronoi cell, as returned by [`Voronoi2::cell`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cell2<'a> {
    /// The Voronoi vertices (triangle indices) of the cell, counterclockwise
    /// around the site. Degenerate (cocircular) inputs may repeat a position
    /// under different ids.
    pub vertices: &'a [u32],
    /// For an unbounded cell (a hull site): `[first, last]`, the directions of
    /// the two rays. The boundary arrives from infinity along `-first` at
    /// `vertices[0]` and leaves from the last vertex to infinity along `last`.
    /// `None` for a bounded cell.
    pub rays: Option<[[f64; 2]; 2]>,
    /// The Delaunay neighbours of the site, i.e. the sites across the cell's
    /// edges, counterclockwise: `neighbors[k]` is across the edge arriving at
    /// `vertices[k]` (for an unbounded cell, `neighbors[0]` is across the
    /// first ray).
    pub neighbors: &'a [u32],
    /// For an unbounded cell, the neighbour across its last ray (completing
    /// [`Cell2::neighbors`]); [`NONE`] for a bounded cell.
    pub ray_neighbor: u32,
}

impl Cell2<'_> {
    /// Whether the cell is unbounded (its site is on the convex hull).
    ///
    /// ```
    /// let pts = [[0.0, 0.0], [2.0, 0.0], [0.0, 2.0], [2.0, 2.0], [1.0, 0.9]];
    /// let mesh = delone::triangulate(&pts).unwrap();
    /// let v = delone::tri::Voronoi2::new(&pts, &mesh).unwrap();
    /// assert!(v.cell(0).is_unbounded());
    /// assert!(!v.cell(4).is_unbounded());
    /// ```
    pub fn is_unbounded(&self) -> bool {
        self.rays.is_some()
    }
}

/// The Voronoi diagram of a point set, dual of its Delaunay triangulation.
///
/// ```
/// let pts = [[0.0, 0.0], [2.0, 0.0], [0.0, 2.0], [2.0, 2.0], [1.0, 0.9]];
/// let mesh = delone::triangulate(&pts).unwrap();
/// let v = delone::tri::Voronoi2::new(&pts, &mesh).unwrap();
/// assert_eq!(v.vertices.len(), mesh.triangles.len());
/// assert_eq!(v.edges.len(), 8); // one per Delaunay edge
/// let c = v.cell(4); // the inner site: a bounded quadrilateral
/// assert_eq!(c.vertices.len(), 4);
/// assert!(c.rays.is_none());
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Voronoi2 {
    /// Voronoi vertices: `vertices[t]` is the circumcentre of triangle `t`.
    pub vertices: Vec<[f64; 2]>,
    /// Voronoi edges, one per Delaunay edge, in order of their first triangle.
    pub edges: Vec<VoronoiEdge2>,
    /// `cell_ranges[p][0]..cell_ranges[p][1]` is the range of
    /// [`Voronoi2::cell_vertices`] of input point `p` (empty for duplicates;
    /// use [`Voronoi2::cell`], which resolves them). Cells are stored in an
    /// order that follows the triangles (for speed), not the points.
    pub cell_ranges: Vec<[u32; 2]>,
    /// The cells' vertex ids, cell after cell (see [`Cell2::vertices`]).
    pub cell_vertices: Vec<u32>,
    /// The cells' neighbour sites, parallel to [`Voronoi2::cell_vertices`]
    /// (see [`Cell2::neighbors`]).
    pub cell_neighbors: Vec<u32>,
    /// The unbounded cells, sorted by site: `(site, [first, last], site
    /// across the last ray)` (see [`Cell2::rays`], [`Cell2::ray_neighbor`]).
    pub hull_cells: Vec<(u32, [[f64; 2]; 2], u32)>,
    /// For every input point, the site whose cell it shares (itself unless it
    /// duplicates an earlier point), as in [`TriMesh::vertex_map`]; [`NONE`]
    /// for a hidden point of a power diagram (its cell is empty).
    pub vertex_map: Vec<u32>,
    /// The weights of a power diagram (by input point; empty for a Voronoi
    /// diagram). Used by [`Voronoi2::cells_clipped`] for the radical axes.
    pub weights: Vec<f64>,
}

/// Power centre (orthocentre) of the weighted triangle `q` (counterclockwise)
/// with weights `w`: the point with equal power distance `|x - p|² - w_p` to
/// the three weighted corners; zero weights give the circumcentre (the same
/// bits: `|d|² + (0 - 0) = |d|²`). Computed relative to the corner opposite
/// the longest edge (no cancellation for slivers).
#[inline]
pub(crate) fn centre(q: [&[f64; 2]; 3], w: [f64; 3]) -> [f64; 2] {
    let l2 = |p: &[f64; 2], q: &[f64; 2]| (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2);
    let (la, lb, lc) = (l2(q[1], q[2]), l2(q[2], q[0]), l2(q[0], q[1]));
    // Rotate (keeping the orientation) so that `a` is opposite the longest
    // edge: rotation 0 if `la >= lb && la >= lc`, else 1 if `lb >= lc`, else
    // 2 — chosen by index, not by branches (which one is unpredictable).
    let (first, second) = ((la >= lb) & (la >= lc), lb >= lc);
    let r = usize::from(!first) * (2 - usize::from(second));
    let (a, b, c) = (q[r], q[NEXT[r]], q[PREV[r]]);
    // 2 (x - a)·d = |d|² + w_a - w_b and 2 (x - a)·e = |e|² + w_a - w_c.
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let (ex, ey) = (c[0] - a[0], c[1] - a[1]);
    let d2 = (dx * dx + dy * dy) + (w[r] - w[NEXT[r]]);
    let e2 = (ex * ex + ey * ey) + (w[r] - w[PREV[r]]);
    // Relative to the corner between the two shorter edges the plain
    // determinant is accurate (orient2d's magnitude need not be); its sign
    // comes from the exact predicate when rounding leaves it in doubt.
    let mut det = dx * ey - dy * ex;
    if det <= 0.0 {
        det = orient2d(a, b, c);
        if det <= 0.0 {
            // Only for a degenerate (collinear) triangle, never in a TriMesh.
            det = f64::MIN_POSITIVE;
        }
    }
    let k = 0.5 / det;
    [
        a[0] + (ey * d2 - dy * e2) * k,
        a[1] + (dx * e2 - ex * d2) * k,
    ]
}

/// The part of the triangles (in 64ths) whose stars the calling thread walks
/// when [`Voronoi2`] runs on two threads; the other thread first computes
/// the centres and edges. Balanced by instruction counts at 1M points
/// (callgrind, one count per thread).
const HEAD_64THS: usize = 52;

/// The cells walked from one range of triangles.
#[derive(Default)]
struct WalkPart {
    cell_vertices: Vec<u32>,
    cell_neighbors: Vec<u32>,
    hull_cells: Vec<(u32, [[f64; 2]; 2], u32)>,
}

/// The start corner of every vertex's star, marked per triangle (bit `i` of
/// `marks[t]`: the star of corner `i` of triangle `t` starts there): any
/// corner (plain stores, the last one wins), for hull vertices the
/// clockwise-most triangle (whose edge v -> next is on the hull).
fn start_marks(n: usize, mesh: &TriMesh) -> Vec<u8> {
    let tris = &mesh.triangles;
    let nbs = &mesh.neighbors;
    let mut start = vec![u64::MAX; n];
    for (t, tv) in tris.iter().enumerate() {
        for i in 0..3 {
            start[tv[i] as usize] = 4 * t as u64 + i as u64;
        }
    }
    for (t, (tv, nb)) in tris.iter().zip(nbs).enumerate() {
        if nb.contains(&NONE) {
            for i in 0..3 {
                if nb[PREV[i]] == NONE {
                    start[tv[i] as usize] = 4 * t as u64 + i as u64;
                }
            }
        }
    }
    let mut marks = vec![0u8; tris.len()];
    for &st in &start {
        if st != u64::MAX {
            marks[(st >> 2) as usize] |= 1 << (st & 3);
        }
    }
    marks
}

/// Walks the stars starting in the triangles `lo..lo + marks.len()` (in
/// triangle order, each from its marked corner), appending the cells;
/// `range(v, [a, b])` gets each site's range in the part's arrays. `cap`
/// reserves room.
fn walk(
    points: &[[f64; 2]],
    mesh: &TriMesh,
    marks: &[u8],
    lo: usize,
    cap: usize,
    mut range: impl FnMut(u32, [u32; 2]),
) -> WalkPart {
    let tris = &mesh.triangles;
    let nbs = &mesh.neighbors;
    let p = |v: u32| &points[v as usize];
    let mut cell_vertices = Vec::with_capacity(cap);
    let mut cell_neighbors = Vec::with_capacity(cap);
    let mut hull_cells = Vec::new();
    let limit = 3 * tris.len();
    for (j, &m) in marks.iter().enumerate() {
        if m == 0 {
            continue;
        }
        let t0 = lo + j;
        let tv0 = &tris[t0];
        for i0 in 0..3 {
            if m & (1 << i0) == 0 {
                continue;
            }
            let v = tv0[i0] as usize;
            let t0 = t0 as u32;
            let first_at = cell_vertices.len();
            let (mut t, mut i) = (t0, i0);
            loop {
                let tv = &tris[t as usize];
                let nx = NEXT[i];
                cell_vertices.push(t);
                cell_neighbors.push(tv[nx]);
                // Counterclockwise around v: across the edge (v, tv[i + 2]).
                let u = nbs[t as usize][nx];
                if u == NONE {
                    // Hull: the boundary leaves along the normal of (prev, v).
                    let first = outward(p(tv0[i0]), p(tv0[NEXT[i0]]));
                    let last = outward(p(tv[PREV[i]]), p(tv[i]));
                    hull_cells.push((v as u32, [first, last], tv[PREV[i]]));
                    break;
                }
                if u == t0 || cell_vertices.len() >= limit {
                    break;
                }
                // The corner of v in u, branch-free (which corner is
                // unpredictable); at most 2 whatever an invalid mesh holds.
                let uv = &tris[u as usize];
                let vv = v as u32;
                i = ((uv[1] == vv) as usize | ((uv[2] == vv) as usize) << 1).min(2);
                t = u;
            }
            range(v as u32, [first_at as u32, cell_vertices.len() as u32]);
        }
    }
    WalkPart {
        cell_vertices,
        cell_neighbors,
        hull_cells,
    }
}

/// Outward normal of the hull edge `a → b` (interior on the left), of the
/// edge's length.
#[inline]
fn outward(a: &[f64; 2], b: &[f64; 2]) -> [f64; 2] {
    [b[1] - a[1], a[0] - b[0]]
}

impl Voronoi2 {
    /// Builds the Voronoi diagram of `points` from their Delaunay
    /// triangulation `mesh` (as returned by [`crate::triangulate`]).
    ///
    /// Runs in linear time. A `mesh` that does not belong to `points` gives a
    /// meaningless (but memory-safe, panic-free for in-range ids) result;
    /// check it with [`super::validate`] when in doubt.
    ///
    /// ```
    /// let pts = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]];
    /// let mesh = delone::triangulate(&pts).unwrap();
    /// let v = delone::tri::Voronoi2::new(&pts, &mesh).unwrap();
    /// // Both triangles of the square share its centre as circumcentre.
    /// assert!(v.vertices.iter().all(|c| (c[0] - 0.5).abs() < 1e-15 && (c[1] - 0.5).abs() < 1e-15));
    /// ```
    ///
    /// # Errors
    /// [`Error::InconsistentMesh`] when `mesh` does not belong to `points`.
    pub fn new(points: &[[f64; 2]], mesh: &TriMesh) -> Result<Voronoi2, Error> {
        let ids = mesh.vertex_map.len();
        crate::geom::check::mesh_fits(points.len(), &mesh.triangles, &mesh.neighbors, ids, None)?;
        Ok(Self::build(points, None, mesh, 0))
    }

    /// [`Voronoi2::new`] on at most `threads` threads (`0`: the default,
    /// two for meshes of 2^16 triangles or more). The result is the same
    /// bit for bit whatever the thread count.
    ///
    /// ```
    /// let pts: Vec<[f64; 2]> = (0..50)
    ///     .map(|i| [(i as f64 * 0.37) % 1.0, (i as f64 * 0.61) % 1.0])
    ///     .collect();
    /// let mesh = delone::triangulate(&pts).unwrap();
    /// let one = delone::tri::Voronoi2::with_threads(&pts, &mesh, 1).unwrap();
    /// assert_eq!(one, delone::tri::Voronoi2::new(&pts, &mesh).unwrap());
    /// ```
    ///
    /// # Errors
    /// As [`Voronoi2::new`].
    pub fn with_threads(
        points: &[[f64; 2]],
        mesh: &TriMesh,
        threads: usize,
    ) -> Result<Voronoi2, Error> {
        let ids = mesh.vertex_map.len();
        crate::geom::check::mesh_fits(points.len(), &mesh.triangles, &mesh.neighbors, ids, None)?;
        Ok(Self::build(points, None, mesh, threads))
    }

    /// Builds the power diagram of `points` with `weights` from their regular
    /// triangulation `mesh` (as returned by
    /// [`super::regular_triangulation`]): the cell of site `p` is the set of
    /// points `x` where the power distance `|x - p|² - w_p` is smallest.
    /// Vertices are the power centres of the triangles, edges lie on the
    /// radical axes of Delaunay-adjacent sites (rays for hull edges, along
    /// the hull edge's outward normal), hidden points have empty cells
    /// (their [`Voronoi2::vertex_map`] entry is [`NONE`]). With all weights
    /// zero it equals [`Voronoi2::new`] except for the stored weights.
    ///
    /// Missing weights (a shorter slice) count as zero.
    ///
    /// ```
    /// use delone::tri::{regular_triangulation, Voronoi2};
    /// let pts = [[0.0, 0.0], [2.0, 0.0], [0.0, 2.0], [2.0, 2.0]];
    /// let w = [1.0, 0.0, 0.0, 0.0];
    /// let mesh = regular_triangulation(&pts, &w).unwrap();
    /// let v = Voronoi2::new_power(&pts, &w, &mesh).unwrap();
    /// // The heavier site 0 pushes the radical axes away from itself.
    /// let c = v.cells_clipped(&pts, [[0.0, 0.0], [2.0, 2.0]]);
    /// assert!(c.area[0] > 1.0 && c.area[3] < 1.0);
    /// assert!((c.area.iter().sum::<f64>() - 4.0).abs() < 1e-12);
    /// ```
    ///
    /// # Errors
    /// [`Error::InconsistentMesh`] when `mesh` does not belong to `points`,
    /// [`Error::WeightCount`] when `weights` has another length.
    pub fn new_power(
        points: &[[f64; 2]],
        weights: &[f64],
        mesh: &TriMesh,
    ) -> Result<Voronoi2, Error> {
        let ids = mesh.vertex_map.len();
        let n = points.len();
        crate::geom::check::mesh_fits(
            n,
            &mesh.triangles,
            &mesh.neighbors,
            ids,
            Some(weights.len()),
        )?;
        Ok(Self::build(points, Some(weights), mesh, 0))
    }

    fn build(
        points: &[[f64; 2]],
        weights: Option<&[f64]>,
        mesh: &TriMesh,
        threads: usize,
    ) -> Voronoi2 {
        let tris = &mesh.triangles;
        let p = |v: u32| &points[v as usize];
        let centres = || -> Vec<[f64; 2]> {
            match weights {
                None => tris.iter().map(|t| centre(t.map(p), [0.0; 3])).collect(),
                Some(w) => tris
                    .iter()
                    .map(|t| centre(t.map(p), t.map(|x| w[x as usize])))
                    .collect(),
            }
        };
        // Three independent parts, each writing only its own arrays (so the
        // result is the same whatever the thread count): the centres (random
        // point reads, arithmetic), the edges (one sequential pass) and the
        // cells (star walks). For large meshes a second thread computes the
        // centres and the edges, then walks the stars starting in the last
        // `1 - HEAD` of the triangles, while this thread finds the start
        // corners and walks the stars starting in the first part: the two
        // loads are about equal (1M points, callgrind). The tail's cells are
        // appended to the head's (their ranges shifted), so the cells come
        // in the same order as on one thread.
        let weights = weights.map_or_else(Vec::new, <[f64]>::to_vec);
        let nt = tris.len();
        if nt >= 1 << 16 && threads != 1 {
            let mid = nt / 64 * HEAD_64THS;
            let (tx, rx) = std::sync::mpsc::sync_channel::<Vec<u8>>(1);
            return std::thread::scope(|sc| {
                let job = std::thread::Builder::new()
                    .spawn_scoped(sc, move || {
                        let (c, e) = (centres(), Self::edges(mesh));
                        let tail = rx.recv().ok().map(|marks| {
                            let mut ranges = Vec::new();
                            let part =
                                walk(points, mesh, &marks, mid, 3 * (nt - mid) + 64, |v, r| {
                                    ranges.push((v, r));
                                });
                            (part, ranges)
                        });
                        (c, e, tail)
                    })
                    .ok();
                let mut marks = start_marks(points.len(), mesh);
                let mut tail_marks = None;
                if job.is_some() {
                    let t = marks.split_off(mid);
                    if let Err(back) = tx.send(t) {
                        tail_marks = Some(back.0);
                    }
                }
                drop(tx);
                let mut cell_ranges = vec![[0u32; 2]; points.len()];
                let mut head = walk(points, mesh, &marks, 0, 3 * nt, |v, r| {
                    cell_ranges[v as usize] = r;
                });
                let done = job.and_then(|h| h.join().ok());
                let (vertices, edges, tail) = match done {
                    Some(x) => x,
                    None => (centres(), Self::edges(mesh), None),
                };
                let tail = match (tail, tail_marks) {
                    (Some(t), _) => Some(t),
                    // The second thread never got the tail: walk it here.
                    (None, Some(m)) => {
                        let mut ranges = Vec::new();
                        let part = walk(points, mesh, &m, mid, 3 * (nt - mid) + 64, |v, r| {
                            ranges.push((v, r));
                        });
                        Some((part, ranges))
                    }
                    (None, None) => None,
                };
                if let Some((part, ranges)) = tail {
                    let shift = head.cell_vertices.len() as u32;
                    for (v, r) in ranges {
                        cell_ranges[v as usize] = r.map(|x| x + shift);
                    }
                    head.cell_vertices.extend_from_slice(&part.cell_vertices);
                    head.cell_neighbors.extend_from_slice(&part.cell_neighbors);
                    head.hull_cells.extend_from_slice(&part.hull_cells);
                }
                head.hull_cells.sort_unstable_by_key(|h| h.0);
                Voronoi2 {
                    vertices,
                    edges,
                    cell_ranges,
                    cell_vertices: head.cell_vertices,
                    cell_neighbors: head.cell_neighbors,
                    hull_cells: head.hull_cells,
                    vertex_map: mesh.vertex_map.clone(),
                    weights,
                }
            });
        }
        let marks = start_marks(points.len(), mesh);
        let mut cell_ranges = vec![[0u32; 2]; points.len()];
        let mut part = walk(points, mesh, &marks, 0, 3 * nt, |v, r| {
            cell_ranges[v as usize] = r;
        });
        part.hull_cells.sort_unstable_by_key(|h| h.0);
        Voronoi2 {
            vertices: centres(),
            edges: Self::edges(mesh),
            cell_ranges,
            cell_vertices: part.cell_vertices,
            cell_neighbors: part.cell_neighbors,
            hull_cells: part.hull_cells,
            vertex_map: mesh.vertex_map.clone(),
            weights,
        }
    }

    /// The edges: interior ones once (from the lower triangle), hull ones
    /// as rays.
    fn edges(mesh: &TriMesh) -> Vec<VoronoiEdge2> {
        let tris = &mesh.triangles;
        let mut edges = Vec::with_capacity(tris.len() * 3 / 2 + 3);
        for (t, (tv, nb)) in tris.iter().zip(&mesh.neighbors).enumerate() {
            for i in 0..3 {
                let u = nb[i];
                if u != NONE && u <= t as u32 {
                    continue;
                }
                let (a, b) = (tv[NEXT[i]], tv[PREV[i]]);
                edges.push(VoronoiEdge2 {
                    sites: [a, b],
                    vertices: [t as u32, u],
                });
            }
        }
        edges
    }

    /// The cell of input point `p` (a duplicate gets its original's cell).
    ///
    /// # Panics
    /// If `p` is not an index of the input points.
    ///
    /// ```
    /// let pts = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 0.0]];
    /// let mesh = delone::triangulate(&pts).unwrap();
    /// let v = delone::tri::Voronoi2::new(&pts, &mesh).unwrap();
    /// assert_eq!(v.cell(3), v.cell(1));
    /// assert!(v.cell(0).is_unbounded());
    /// ```
    pub fn cell(&self, p: usize) -> Cell2<'_> {
        let s = self.vertex_map.get(p).map_or(p, |&r| r as usize);
        if s == NONE as usize {
            // A hidden point of a power diagram.
            return Cell2 {
                vertices: &[],
                rays: None,
                neighbors: &[],
                ray_neighbor: NONE,
            };
        }
        let hull = self
            .hull_cells
            .binary_search_by_key(&(s as u32), |h| h.0)
            .ok()
            .map(|k| &self.hull_cells[k]);
        let [lo, hi] = self.cell_ranges[s].map(|x| x as usize);
        Cell2 {
            vertices: &self.cell_vertices[lo..hi],
            rays: hull.map(|h| h.1),
            neighbors: &self.cell_neighbors[lo..hi],
            ray_neighbor: hull.map_or(NONE, |h| h.2),
        }
    }

    /// Every cell intersected with the box `bbox = [min, max]`, as convex
    /// polygons with area and centroid, one per input point (duplicates get
    /// a copy of their original's polygon).
    ///
    /// A bounded cell inside the box is its Voronoi polygon; any other cell is
    /// computed by clipping the box with the bisectors of its site and each
    /// Delaunay neighbour, so unbounded cells need no artificial far points.
    /// A cell that misses the box is empty (area `0`, centroid = its site).
    /// For a power diagram the clipping lines are the radical axes, and
    /// hidden points get empty cells.
    ///
    /// ```
    /// let pts = [[0.25, 0.25], [0.75, 0.25], [0.25, 0.75], [0.75, 0.75]];
    /// let mesh = delone::triangulate(&pts).unwrap();
    /// let v = delone::tri::Voronoi2::new(&pts, &mesh).unwrap();
    /// let c = v.cells_clipped(&pts, [[0.0, 0.0], [1.0, 1.0]]);
    /// for p in 0..4 {
    ///     assert!((c.area[p] - 0.25).abs() < 1e-15);
    ///     assert!((c.centroid[p][0] - pts[p][0]).abs() < 1e-15);
    /// }
    /// ```
    pub fn cells_clipped(&self, points: &[[f64; 2]], bbox: Box2) -> ClippedCells2 {
        let n = self.cell_ranges.len();
        let mut out = ClippedCells2 {
            offsets: Vec::with_capacity(n + 1),
            polygon_points: Vec::with_capacity(self.cell_vertices.len() + 4 * n),
            area: vec![0.0; n],
            centroid: vec![[0.0; 2]; n],
        };
        out.offsets.push(0);
        let [lo, hi] = bbox;
        let inside =
            |q: &[f64; 2]| q[0] >= lo[0] && q[0] <= hi[0] && q[1] >= lo[1] && q[1] <= hi[1];
        let mut poly: Vec<[f64; 2]> = Vec::with_capacity(32);
        let mut tmp: Vec<[f64; 2]> = Vec::with_capacity(32);
        for s in 0..n {
            let r = self.vertex_map.get(s).map_or(s, |&r| r as usize);
            if r != s && r < s {
                let (a, b) = (out.offsets[r] as usize, out.offsets[r + 1] as usize);
                out.polygon_points.extend_from_within(a..b);
                out.area[s] = out.area[r];
                out.centroid[s] = out.centroid[r];
                out.offsets.push(out.polygon_points.len() as u32);
                continue;
            }
            let site = points[s];
            let cell = self.cell(s);
            poly.clear();
            if cell.vertices.is_empty() {
                // Not a vertex of the mesh: no cell.
            } else if cell.rays.is_none()
                && cell
                    .vertices
                    .iter()
                    .all(|&t| inside(&self.vertices[t as usize]))
            {
                poly.extend(cell.vertices.iter().map(|&t| self.vertices[t as usize]));
            } else {
                poly.extend_from_slice(&[lo, [hi[0], lo[1]], hi, [lo[0], hi[1]]]);
                let extra = (cell.ray_neighbor != NONE).then_some(&cell.ray_neighbor);
                let ws = self.weights.get(s).copied().unwrap_or(0.0);
                for &q in cell.neighbors.iter().chain(extra) {
                    let wq = self.weights.get(q as usize).copied().unwrap_or(0.0);
                    clip_bisector(&mut poly, &mut tmp, &site, &points[q as usize], ws - wq);
                    if poly.is_empty() {
                        break;
                    }
                }
            }
            let (area, centroid) = area_centroid(&poly, &site);
            out.area[s] = area;
            out.centroid[s] = centroid;
            out.polygon_points.extend_from_slice(&poly);
            out.offsets.push(out.polygon_points.len() as u32);
        }
        out
    }
}

/// Voronoi cells clipped to a box, as returned by [`Voronoi2::cells_clipped`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ClippedCells2 {
    /// `offsets[p]..offsets[p + 1]` is the range of
    /// [`ClippedCells2::polygon_points`] of input point `p`.
    pub offsets: Vec<u32>,
    /// The corners of the clipped cells, counterclockwise, cell after cell.
    pub polygon_points: Vec<[f64; 2]>,
    /// Area of each clipped cell.
    pub area: Vec<f64>,
    /// Centroid of each clipped cell (the site itself for an empty cell).
    pub centroid: Vec<[f64; 2]>,
}

impl ClippedCells2 {
    /// The clipped polygon of input point `p` (counterclockwise).
    ///
    /// # Panics
    /// If `p` is not an index of the input points.
    ///
    /// ```
    /// let pts = [[0.25, 0.5], [0.75, 0.5], [0.5, 0.9]];
    /// let mesh = delone::triangulate(&pts).unwrap();
    /// let v = delone::tri::Voronoi2::new(&pts, &mesh).unwrap();
    /// let c = v.cells_clipped(&pts, [[0.0, 0.0], [1.0, 1.0]]);
    /// assert!(c.polygon(0).len() >= 4);
    /// ```
    pub fn polygon(&self, p: usize) -> &[[f64; 2]] {
        &self.polygon_points[self.offsets[p] as usize..self.offsets[p + 1] as usize]
    }
}

/// Keeps the part of convex polygon `poly` closer to `p` than to `q` in
/// power distance, where `dw = w_p - w_q` (0 for the bisector; otherwise
/// the radical axis).
fn clip_bisector(
    poly: &mut Vec<[f64; 2]>,
    tmp: &mut Vec<[f64; 2]>,
    p: &[f64; 2],
    q: &[f64; 2],
    dw: f64,
) {
    // Side of x: (x - p)·(q - p) - (|q - p|² + w_p - w_q)/2  (<= 0 keeps x).
    let (nx, ny) = (q[0] - p[0], q[1] - p[1]);
    let n2 = nx * nx + ny * ny;
    if n2 != 0.0 {
        let h = 0.5 * (n2 + dw);
        clip_half(poly, tmp, |x| (x[0] - p[0]) * nx + (x[1] - p[1]) * ny - h);
    }
}

/// Keeps the part of polygon `poly` where `side <= 0` (Sutherland–Hodgman
/// against one half-plane; `tmp` is scratch).
pub(crate) fn clip_half(
    poly: &mut Vec<[f64; 2]>,
    tmp: &mut Vec<[f64; 2]>,
    side: impl Fn(&[f64; 2]) -> f64,
) {
    let mut any_out = false;
    let mut any_in = false;
    for x in poly.iter() {
        if side(x) > 0.0 {
            any_out = true;
        } else {
            any_in = true;
        }
    }
    if !any_out {
        return;
    }
    if !any_in {
        poly.clear();
        return;
    }
    tmp.clear();
    let m = poly.len();
    for k in 0..m {
        let a = poly[k];
        let b = poly[(k + 1) % m];
        let (sa, sb) = (side(&a), side(&b));
        if sa <= 0.0 {
            tmp.push(a);
        }
        if (sa <= 0.0) != (sb <= 0.0) {
            // Crossing point, computed from the inside end (so that the two
            // cells sharing the edge compute it alike up to rounding).
            let (x, y, sx, sy) = if sa <= 0.0 {
                (a, b, sa, sb)
            } else {
                (b, a, sb, sa)
            };
            if sx < 0.0 {
                let t = sx / (sx - sy);
                tmp.push([x[0] + t * (y[0] - x[0]), x[1] + t * (y[1] - x[1])]);
            }
        }
    }
    std::mem::swap(poly, tmp);
}

/// Twice the signed area of a polygon and its first moments relative to
/// `origin` (each times six): the centroid is `origin + (cx, cy) / (3 a2)`.
pub(crate) fn moments(poly: &[[f64; 2]], origin: &[f64; 2]) -> (f64, f64, f64) {
    let m = poly.len();
    let (mut a2, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for k in 0..m {
        let (p, q) = (poly[k], poly[(k + 1) % m]);
        let (px, py) = (p[0] - origin[0], p[1] - origin[1]);
        let (qx, qy) = (q[0] - origin[0], q[1] - origin[1]);
        let c = px * qy - qx * py;
        a2 += c;
        cx += (px + qx) * c;
        cy += (py + qy) * c;
    }
    (a2, cx, cy)
}

/// Area and centroid of a counterclockwise polygon, computed relative to
/// `origin` (a nearby point, for precision). An empty or degenerate polygon
/// gives area `0` and `origin` as centroid.
pub(crate) fn area_centroid(poly: &[[f64; 2]], origin: &[f64; 2]) -> (f64, [f64; 2]) {
    if poly.len() < 3 {
        return (0.0, *origin);
    }
    let (a2, cx, cy) = moments(poly, origin);
    if a2 <= 0.0 {
        return (0.0, *origin);
    }
    (
        0.5 * a2,
        [origin[0] + cx / (3.0 * a2), origin[1] + cy / (3.0 * a2)],
    )
}

/// Lloyd relaxation in a box: `iterations` times, triangulate the points,
/// clip their Voronoi cells to `bbox` and move every point to the centroid
/// of its clipped cell. Points outside the box (empty cells) stay where they
/// are; duplicates move together. Deterministic.
///
/// # Errors
/// The errors of [`crate::triangulate`] (on the input or, for degenerate
/// inputs, on an intermediate iterate).
///
/// ```
/// let pts: Vec<[f64; 2]> = (0..20).map(|i| [(i as f64 * 0.37) % 1.0, (i as f64 * 0.61) % 1.0]).collect();
/// let out = delone::tri::lloyd(&pts, [[0.0, 0.0], [1.0, 1.0]], 10).unwrap();
/// assert_eq!(out.len(), 20);
/// assert!(out.iter().all(|p| (0.0..=1.0).contains(&p[0]) && (0.0..=1.0).contains(&p[1])));
/// ```
pub fn lloyd(points: &[[f64; 2]], bbox: Box2, iterations: usize) -> Result<Vec<[f64; 2]>, Error> {
    crate::geom::lloyd(points, iterations, |pts| {
        let c = Voronoi2::new(pts, &super::triangulate(pts)?)?.cells_clipped(pts, bbox);
        Ok((c.area, c.centroid))
    })
}
