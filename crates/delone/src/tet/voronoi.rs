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
//! # References
//! * F. Aurenhammer, "Voronoi diagrams — a survey of a fundamental geometric
//!   data structure", ACM Computing Surveys 23 (1991).
//! * Q. Du, V. Faber, M. Gunzburger, "Centroidal Voronoi tessellations:
//!   applications and algorithms", SIAM Review 41 (1999).

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
    /// hull triangle) `vertices[1]` is [`NONE`].
    pub vertices: [u32; 2],
    /// For a ray, its direction: the outward normal of the hull triangle, of
    /// twice its area; `[0, 0, 0]` for a segment.
    pub direction: [f64; 3],
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
    /// The boundary edges (see [`Voronoi3::face_edge_ids`]).
    pub edges: &'a [u32],
}

/// Per-face data of a [`Voronoi3`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaceInfo3 {
    /// See [`Face3::sites`].
    pub sites: [u32; 2],
    /// See [`Face3::rays`].
    pub rays: Option<[[f64; 3]; 2]>,
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
    /// Voronoi edges, one per Delaunay triangle.
    pub edges: Vec<VoronoiEdge3>,
    /// Voronoi faces, one per Delaunay edge.
    pub faces: Vec<FaceInfo3>,
    /// `face_offsets[f]..face_offsets[f + 1]` is the range of
    /// [`Voronoi3::face_vertices`] of face `f`.
    pub face_offsets: Vec<u32>,
    /// The faces' vertex ids, face after face.
    pub face_vertices: Vec<u32>,
    /// `face_edge_offsets[f]..face_edge_offsets[f + 1]` is the range of
    /// [`Voronoi3::face_edge_ids`] of face `f`.
    pub face_edge_offsets: Vec<u32>,
    /// The faces' boundary edges (indices into [`Voronoi3::edges`]), face
    /// after face, in the order of the face's vertices: for a bounded face
    /// edge `k` joins vertex `k` to vertex `k + 1` (cyclically); an unbounded
    /// face starts with its first ray and ends with its last.
    pub face_edge_ids: Vec<u32>,
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

#[inline]
fn sub(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[inline]
fn cross(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

#[inline]
fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Orthocentre (power centre) of the positive tetrahedron `q` with weights
/// `wq`: the point with equal power distance `|x - q_i|² - w_i` to the four
/// weighted corners; zero weights give the circumcentre. Computed relative to
/// the corner with the shortest incident edges (less cancellation for
/// slivers).
pub(crate) fn orthocenter(q: [&[f64; 3]; 4], wq: [f64; 4]) -> [f64; 3] {
    let l2 = |a: &[f64; 3], b: &[f64; 3]| {
        let d = sub(a, b);
        dot(&d, &d)
    };
    let mut sum = [0.0f64; 4];
    for i in 0..4 {
        for j in i + 1..4 {
            let l = l2(q[i], q[j]);
            sum[i] += l;
            sum[j] += l;
        }
    }
    let o = (0..4).fold(0, |m, i| if sum[i] < sum[m] { i } else { m });
    // An even permutation putting corner o first keeps the orientation.
    let perm = match o {
        0 => [0, 1, 2, 3],
        1 => [1, 0, 3, 2],
        2 => [2, 3, 0, 1],
        _ => [3, 2, 1, 0],
    };
    let [a, b, c, d] = perm.map(|i| q[i]);
    let [wa, wb, wc, wd] = perm.map(|i| wq[i]);
    let (u, v, w) = (sub(b, a), sub(c, a), sub(d, a));
    let (vw, wu, uv) = (cross(&v, &w), cross(&w, &u), cross(&u, &v));
    let mut det = dot(&u, &vw);
    if det <= 0.0 {
        det = -orient3d(a, b, c, d);
        if det <= 0.0 {
            det = f64::MIN_POSITIVE;
        }
    }
    // Power distances: |x - a|² - wa = |x - b|² - wb, ... relative to a.
    let (lu, lv, lw) = (
        dot(&u, &u) + wa - wb,
        dot(&v, &v) + wa - wc,
        dot(&w, &w) + wa - wd,
    );
    let k = 0.5 / det;
    [
        a[0] + (lu * vw[0] + lv * wu[0] + lw * uv[0]) * k,
        a[1] + (lu * vw[1] + lv * wu[1] + lw * uv[1]) * k,
        a[2] + (lu * vw[2] + lv * wu[2] + lw * uv[2]) * k,
    ]
}

/// Local index of vertex `x` in `tv` (0 if absent, which a valid mesh never
/// asks for).
#[inline]
fn pos(tv: &[u32; 4], x: u32) -> usize {
    tv.iter().position(|&y| y == x).unwrap_or(0)
}

/// The vertex of `tv` other than `a`, `b`, `c`.
#[inline]
fn other(tv: &[u32; 4], a: u32, b: u32, c: u32) -> u32 {
    tv.iter()
        .copied()
        .find(|&y| y != a && y != b && y != c)
        .unwrap_or(tv[0])
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
    /// assert!(v.faces.iter().all(|f| f.rays.is_some())); // all on the hull
    /// ```
    ///
    /// # Errors
    /// [`Error::InconsistentMesh`] when `mesh` does not belong to `points`.
    pub fn new(points: &[[f64; 3]], mesh: &TetMesh) -> Result<Voronoi3, Error> {
        let ids = mesh.vertex_map.len();
        crate::geom::check::mesh_fits(points.len(), &mesh.tets, &mesh.neighbors, ids, None)?;
        Ok(Self::build(points, &[], mesh))
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
        let ids = mesh.vertex_map.len();
        let n = points.len();
        crate::geom::check::mesh_fits(n, &mesh.tets, &mesh.neighbors, ids, Some(weights.len()))?;
        Ok(Self::build(points, weights, mesh))
    }

    fn build(points: &[[f64; 3]], weights: &[f64], mesh: &TetMesh) -> Voronoi3 {
        let tets = &mesh.tets;
        let p = |v: u32| &points[v as usize];
        let w = |v: u32| weights.get(v as usize).copied().unwrap_or(0.0);
        let centres = || -> Vec<[f64; 3]> {
            tets.iter()
                .map(|tv| orthocenter(tv.map(&p), tv.map(w)))
                .collect()
        };
        // Centres and combinatorics are independent: two threads for large
        // meshes, each writing only its own arrays (same result whatever the
        // thread count).
        let mut v = if tets.len() >= 1 << 15 {
            std::thread::scope(|sc| {
                let job = sc.spawn(centres);
                let mut v = Self::topology(points, mesh);
                v.vertices = job.join().unwrap_or_else(|_| centres());
                v
            })
        } else {
            let mut v = Self::topology(points, mesh);
            v.vertices = centres();
            v
        };
        v.weights = weights.to_vec();
        v
    }

    /// Everything but the vertex coordinates: edges, faces, cells.
    fn topology(points: &[[f64; 3]], mesh: &TetMesh) -> Voronoi3 {
        let n = points.len();
        let tets = &mesh.tets;
        let nbs = &mesh.neighbors;
        let p = |v: u32| &points[v as usize];
        let mut unbounded = vec![false; n];
        let mut edges = Vec::with_capacity(tets.len() * 2 + 4);
        // The Voronoi edge of every (tetrahedron, facet).
        let mut edge_of = vec![NONE; 4 * tets.len()];
        for (t, (tv, nb)) in tets.iter().zip(nbs).enumerate() {
            for f in 0..4 {
                let u = nb[f];
                if u != NONE && u <= t as u32 {
                    continue;
                }
                let s = FACET[f].map(|i| tv[i]);
                let direction = if u == NONE {
                    for &x in &s {
                        unbounded[x as usize] = true;
                    }
                    // FACET[f] sees vertex f on its positive side: outward
                    // is the opposite normal.
                    cross(&sub(p(s[2]), p(s[0])), &sub(p(s[1]), p(s[0])))
                } else {
                    [0.0; 3]
                };
                let id = edges.len() as u32;
                edge_of[4 * t + f] = id;
                if u != NONE {
                    if let Some(g) = nbs[u as usize].iter().position(|&x| x == t as u32) {
                        edge_of[4 * u as usize + g] = id;
                    }
                }
                edges.push(VoronoiEdge3 {
                    sites: s,
                    vertices: [t as u32, u],
                    direction,
                });
            }
        }
        // Faces: each Delaunay edge is built by the lowest-indexed
        // tetrahedron around it.
        let mut faces = Vec::with_capacity(tets.len() + n);
        let mut face_offsets = vec![0u32];
        let mut face_vertices: Vec<u32> = Vec::with_capacity(tets.len() * 6);
        let mut face_edge_offsets = vec![0u32];
        let mut face_edge_ids: Vec<u32> = Vec::with_capacity(tets.len() * 7);
        let crossing = |t: u32, c: u32| edge_of[4 * t as usize + pos(&tets[t as usize], c)];
        let ccw = |t: u32, a: u32, b: u32, c: u32, d: u32| -> Option<(u32, u32, u32)> {
            let tv = &tets[t as usize];
            let u = nbs[t as usize][pos(tv, c)];
            if u == NONE {
                return None;
            }
            Some((u, d, other(&tets[u as usize], a, b, d)))
        };
        let cw = |t: u32, a: u32, b: u32, c: u32, d: u32| -> Option<(u32, u32, u32)> {
            let tv = &tets[t as usize];
            let u = nbs[t as usize][pos(tv, d)];
            if u == NONE {
                return None;
            }
            Some((u, other(&tets[u as usize], a, b, c), c))
        };
        let limit = tets.len() + 1;
        // Bit k of done[t]: local edge k of t already belongs to a face.
        let mut done = vec![0u8; tets.len()];
        let local_edge = |tv: &[u32; 4], a: u32, b: u32| {
            let (i, j) = (pos(tv, a), pos(tv, b));
            EDGE_INDEX[i][j]
        };
        for (t, tv) in tets.iter().enumerate() {
            let t = t as u32;
            for (k, e) in EDGES.iter().enumerate() {
                if done[t as usize] & (1 << k) != 0 {
                    continue;
                }
                let [a, b, c, d] = e.map(|i| tv[i]);
                // Walk counterclockwise from t; if the ring turns out open,
                // start again from its clockwise end.
                let (v0, e0) = (face_vertices.len(), face_edge_ids.len());
                let mut first = (t, c, d);
                let mut closed = true;
                let mut rays = None;
                loop {
                    let mut s = first;
                    let mut steps = 0usize;
                    if !closed {
                        // The first ray: the hull facet opposite d.
                        face_edge_ids.push(crossing(first.0, first.2));
                    }
                    let mut hit_hull = false;
                    loop {
                        face_vertices.push(s.0);
                        let st = &tets[s.0 as usize];
                        done[s.0 as usize] |= 1 << local_edge(st, a, b);
                        // The edge crossed next (the last ray of an open face).
                        face_edge_ids.push(crossing(s.0, s.1));
                        match ccw(s.0, a, b, s.1, s.2) {
                            Some(nx) if nx.0 != first.0 && steps <= limit => s = nx,
                            Some(_) => break,
                            None => {
                                hit_hull = true;
                                break;
                            }
                        }
                        steps += 1;
                    }
                    if !hit_hull {
                        break;
                    }
                    if !closed {
                        let (pa, pb) = (p(a), p(b));
                        let ab = sub(pb, pa);
                        // Hull triangle (a, b, c) of the first tetrahedron and
                        // (a, b, d) of the last, normals pointing away from them.
                        rays = Some([
                            cross(&sub(p(first.1), pa), &ab),
                            cross(&ab, &sub(p(s.2), pa)),
                        ]);
                        break;
                    }
                    closed = false;
                    face_vertices.truncate(v0);
                    face_edge_ids.truncate(e0);
                    steps = 0;
                    while let Some(nx) = cw(first.0, a, b, first.1, first.2) {
                        steps += 1;
                        if steps > limit {
                            break;
                        }
                        first = nx;
                    }
                }
                face_offsets.push(face_vertices.len() as u32);
                face_edge_offsets.push(face_edge_ids.len() as u32);
                faces.push(FaceInfo3 {
                    sites: [a, b],
                    rays,
                });
            }
        }
        // Cells: the faces around each site.
        let mut count = vec![0u32; n + 1];
        for f in &faces {
            for &s in &f.sites {
                count[s as usize + 1] += 1;
            }
        }
        for i in 0..n {
            count[i + 1] += count[i];
        }
        let cell_offsets = count.clone();
        let mut fill = count;
        let mut cell_face_ids = vec![0u32; *cell_offsets.last().unwrap_or(&0) as usize];
        for (fi, f) in faces.iter().enumerate() {
            for &s in &f.sites {
                cell_face_ids[fill[s as usize] as usize] = fi as u32;
                fill[s as usize] += 1;
            }
        }
        Voronoi3 {
            vertices: Vec::new(),
            edges,
            faces,
            face_offsets,
            face_vertices,
            face_edge_offsets,
            face_edge_ids,
            cell_offsets,
            cell_face_ids,
            unbounded,
            vertex_map: mesh.vertex_map.clone(),
            weights: Vec::new(),
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
        Face3 {
            sites: info.sites,
            vertices: &self.face_vertices
                [self.face_offsets[f] as usize..self.face_offsets[f + 1] as usize],
            rays: info.rays,
            edges: &self.face_edge_ids
                [self.face_edge_offsets[f] as usize..self.face_edge_offsets[f + 1] as usize],
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
        for k in 0..8 {
            self.verts
                .push([b[k & 1][0], b[(k >> 1) & 1][1], b[(k >> 2) & 1][2]]);
        }
        self.spare.append(&mut self.faces);
        for f in [
            [0, 4, 6, 2],
            [1, 3, 7, 5],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 2, 3, 1],
            [4, 5, 7, 6],
        ] {
            let mut v = self.spare.pop().unwrap_or_default();
            v.clear();
            v.extend_from_slice(&f);
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
    let mut pts = points.to_vec();
    for _ in 0..iterations {
        let mesh = super::tetrahedralize(&pts)?;
        let v = Voronoi3::new(&pts, &mesh)?;
        let c = v.cells_clipped(&pts, bbox);
        for (p, (&vol, &g)) in pts.iter_mut().zip(c.volume.iter().zip(&c.centroid)) {
            if vol > 0.0 {
                *p = g;
            }
        }
    }
    Ok(pts)
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

    #[test]
    fn circumcenter_of_a_corner_tet() {
        let q = [
            [0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [0.0, 2.0, 0.0],
            [0.0, 0.0, 2.0],
        ];
        let c = orthocenter([&q[0], &q[1], &q[2], &q[3]], [0.0; 4]);
        assert_eq!(c, [1.0, 1.0, 1.0]);
    }
}
