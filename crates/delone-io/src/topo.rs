//! Derived entities for output: edges of a triangulation, faces and edges of
//! a tetrahedralization, hull vertices.
//!
//! Everything is computed from flat element and neighbour arrays (the
//! convention of `delone::TriMesh` / `delone::TetMesh`: `neighbors[e][i]` is
//! the element across the side opposite local vertex `i`, `u32::MAX` on the
//! hull). Output order is deterministic: by the first element that owns an
//! entity, then by local position in that element.

use crate::IoError;

/// "No neighbour" in neighbour arrays (the same value as `delone::NONE`).
///
/// ```
/// assert_eq!(delone_io::topo::NONE, u32::MAX);
/// ```
pub const NONE: u32 = u32::MAX;

/// Faces of a positively oriented tetrahedron `[a, b, c, d]`
/// (`(b−a)×(c−a)·(d−a) > 0`): face `i` is opposite vertex `i`, listed so that
/// its right-hand normal points out of the tetrahedron.
///
/// ```text
///            3
///           /|\        face 0 = (1 2 3)   face 1 = (0 3 2)
///          / | \       face 2 = (0 1 3)   face 3 = (0 2 1)
///         /  |  \
///        0---|---2     (seen from outside, each face runs counterclockwise)
///         \  |  /
///          \ | /
///            1
/// ```
///
/// ```
/// use delone_io::topo::TET_FACES;
/// // Face i never contains vertex i.
/// assert!((0..4).all(|i| !TET_FACES[i].contains(&i)));
/// ```
pub const TET_FACES: [[usize; 3]; 4] = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];

/// The six edges of a tetrahedron as local vertex pairs.
///
/// ```
/// assert_eq!(delone_io::topo::TET_EDGES[0], [0, 1]);
/// ```
pub const TET_EDGES: [[usize; 2]; 6] = [[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]];

/// Edges or faces together with their boundary flags.
///
/// ```
/// let e = delone_io::topo::tri_edges(&[[0, 1, 2]], &[[u32::MAX; 3]]).unwrap();
/// assert_eq!(e.items.len(), e.boundary.len());
/// ```
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Entities<const K: usize> {
    /// Vertex indices of each entity.
    pub items: Vec<[u32; K]>,
    /// `true` for entities on the boundary (convex hull) of the mesh.
    pub boundary: Vec<bool>,
}

impl<const K: usize> Entities<K> {
    /// Boundary markers as Triangle/TetGen write them: 1 on the boundary, 0
    /// inside.
    ///
    /// ```
    /// let e = delone_io::topo::tri_edges(&[[0, 1, 2]], &[[u32::MAX; 3]]).unwrap();
    /// assert_eq!(e.markers(), vec![1, 1, 1]);
    /// ```
    pub fn markers(&self) -> Vec<i32> {
        self.boundary.iter().map(|&b| i32::from(b)).collect()
    }
}

fn check_lengths(n_el: usize, n_nb: usize) -> Result<(), IoError> {
    if n_el != n_nb {
        return Err(IoError::invalid(format!(
            "{n_el} elements but {n_nb} neighbour entries"
        )));
    }
    Ok(())
}

/// Each undirected edge of a triangulation once, with a hull flag.
///
/// Edge `i` of triangle `t` (opposite vertex `i`) is emitted by `t` when the
/// neighbour across it is [`NONE`] or has a larger index; hull edges keep the
/// orientation of their triangle (counterclockwise around the mesh).
///
/// # Errors
/// [`IoError::InvalidInput`] if the two arrays differ in length.
///
/// ```
/// // Two triangles sharing edge 1-2.
/// let tris = [[0, 1, 2], [2, 1, 3]];
/// let nbrs = [[1, u32::MAX, u32::MAX], [u32::MAX, u32::MAX, 0]];
/// let e = delone_io::topo::tri_edges(&tris, &nbrs).unwrap();
/// assert_eq!(e.items, vec![[1, 2], [2, 0], [0, 1], [1, 3], [3, 2]]);
/// assert_eq!(e.boundary, vec![false, true, true, true, true]);
/// ```
pub fn tri_edges(triangles: &[[u32; 3]], neighbors: &[[u32; 3]]) -> Result<Entities<2>, IoError> {
    check_lengths(triangles.len(), neighbors.len())?;
    let mut out = Entities {
        items: Vec::with_capacity(triangles.len() * 3 / 2 + 2),
        boundary: Vec::with_capacity(triangles.len() * 3 / 2 + 2),
    };
    for (t, (tri, nb)) in triangles.iter().zip(neighbors).enumerate() {
        for i in 0..3 {
            let n = nb[i];
            if n == NONE || n as usize > t {
                out.items.push([tri[(i + 1) % 3], tri[(i + 2) % 3]]);
                out.boundary.push(n == NONE);
            }
        }
    }
    Ok(out)
}

/// Triangular faces of a tetrahedralization with hull flags: only the hull
/// faces (`all == false`, TetGen's default `.face`) or every face once
/// (`all == true`, TetGen's `-f`).
///
/// A face is emitted by the lower-indexed of its two tetrahedra, with the
/// vertex order of [`TET_FACES`] (hull faces thus face outwards).
///
/// # Errors
/// [`IoError::InvalidInput`] if the two arrays differ in length.
///
/// ```
/// let tets = [[0, 1, 2, 3]];
/// let nbrs = [[u32::MAX; 4]];
/// let f = delone_io::topo::tet_faces(&tets, &nbrs, false).unwrap();
/// assert_eq!(f.items, vec![[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]]);
/// ```
pub fn tet_faces(
    tets: &[[u32; 4]],
    neighbors: &[[u32; 4]],
    all: bool,
) -> Result<Entities<3>, IoError> {
    tet_faces_threads(tets, neighbors, all, 1)
}

/// [`tet_faces`] on up to `threads` threads (0 counts as 1): the
/// tetrahedra are scanned in chunks whose faces are joined in chunk
/// order, so the result is the same for every thread count.
///
/// # Errors
/// As [`tet_faces`].
///
/// ```
/// let tets = [[0, 1, 2, 3], [1, 2, 3, 4]];
/// let nbrs = [[1, u32::MAX, u32::MAX, u32::MAX], [u32::MAX, u32::MAX, u32::MAX, 0]];
/// let one = delone_io::topo::tet_faces(&tets, &nbrs, false).unwrap();
/// assert_eq!(delone_io::topo::tet_faces_threads(&tets, &nbrs, false, 2).unwrap(), one);
/// ```
pub fn tet_faces_threads(
    tets: &[[u32; 4]],
    neighbors: &[[u32; 4]],
    all: bool,
    threads: usize,
) -> Result<Entities<3>, IoError> {
    check_lengths(tets.len(), neighbors.len())?;
    let scan = |start: usize, tets: &[[u32; 4]], neighbors: &[[u32; 4]]| {
        let mut out = Entities::default();
        for (j, (tet, nb)) in tets.iter().zip(neighbors).enumerate() {
            // Most tetrahedra have no hull face: one test for all four.
            if !all && !nb.contains(&NONE) {
                continue;
            }
            let t = start + j;
            for (i, f) in TET_FACES.iter().enumerate() {
                let n = nb[i];
                if n == NONE || (all && n as usize > t) {
                    out.items.push([tet[f[0]], tet[f[1]], tet[f[2]]]);
                    out.boundary.push(n == NONE);
                }
            }
        }
        out
    };
    let threads = threads.max(1);
    let chunk = tets.len().div_ceil(threads).max(1 << 16);
    if threads == 1 || tets.len() <= chunk {
        return Ok(scan(0, tets, neighbors));
    }
    let chunks: Vec<_> = tets.chunks(chunk).zip(neighbors.chunks(chunk)).collect();
    let parts = crate::par::scoped_map(chunks.len(), |c| {
        let (t, n) = chunks[c];
        scan(c * chunk, t, n)
    });
    let mut out = Entities::default();
    for p in parts {
        let p = p.unwrap_or_else(|e| std::panic::resume_unwind(e));
        out.items.extend(p.items);
        out.boundary.extend(p.boundary);
    }
    Ok(out)
}

/// Each undirected edge of a tetrahedralization once, with a hull flag
/// (an edge is on the hull when it belongs to a hull face).
///
/// Order: by the first (lowest-indexed) tetrahedron containing the edge, then
/// by its [`TET_EDGES`] position there; the endpoints keep that
/// tetrahedron's local order. The ring of tetrahedra around each edge is
/// walked through `neighbors`, so no extra memory beyond the output is used.
///
/// # Errors
/// [`IoError::InvalidInput`] if the two arrays differ in length or the
/// neighbour relation is inconsistent (a neighbour index out of range, or a
/// neighbour that does not share the face).
///
/// ```
/// let tets = [[0, 1, 2, 3], [1, 2, 3, 4]];
/// let nbrs = [[1, u32::MAX, u32::MAX, u32::MAX], [u32::MAX, u32::MAX, u32::MAX, 0]];
/// let e = delone_io::topo::tet_edges(&tets, &nbrs).unwrap();
/// assert_eq!(e.items.len(), 9);
/// assert!(e.boundary.iter().all(|&b| b)); // every edge of two tets is on the hull
/// ```
pub fn tet_edges(tets: &[[u32; 4]], neighbors: &[[u32; 4]]) -> Result<Entities<2>, IoError> {
    check_lengths(tets.len(), neighbors.len())?;
    let mut out = Entities {
        items: Vec::with_capacity(tets.len() * 6 / 5 + 6),
        boundary: Vec::with_capacity(tets.len() * 6 / 5 + 6),
    };
    for (t, tet) in tets.iter().enumerate() {
        for (j, e) in TET_EDGES.iter().enumerate() {
            let (a, b) = (tet[e[0]], tet[e[1]]);
            // The two other local vertices.
            let o = OTHER[j];
            let (x, y) = (tet[o[0]], tet[o[1]]);
            // Walk one way (crossing the face opposite x first); if the walk
            // reaches the hull, walk the other way too.
            match walk(tets, neighbors, t, a, b, x, y)? {
                Ring::Lower => continue,
                Ring::Closed => {
                    out.items.push([a, b]);
                    out.boundary.push(false);
                }
                Ring::Hull => {
                    if walk(tets, neighbors, t, a, b, y, x)? == Ring::Lower {
                        continue;
                    }
                    out.items.push([a, b]);
                    out.boundary.push(true);
                }
            }
        }
    }
    Ok(out)
}

/// For local edge `j` (of [`TET_EDGES`]), the two local vertices not on it.
const OTHER: [[usize; 2]; 6] = [[2, 3], [1, 3], [1, 2], [0, 3], [0, 2], [0, 1]];

#[derive(Debug, PartialEq, Eq)]
enum Ring {
    /// A tetrahedron with a lower index shares the edge: not the owner.
    Lower,
    /// The walk came back to the start: interior edge.
    Closed,
    /// The walk reached the hull.
    Hull,
}

/// Walks around edge `ab` from tetrahedron `start` (whose other vertices are
/// `x`, `y`), crossing first the face opposite `x`.
fn walk(
    tets: &[[u32; 4]],
    neighbors: &[[u32; 4]],
    start: usize,
    a: u32,
    b: u32,
    mut x: u32,
    mut y: u32,
) -> Result<Ring, IoError> {
    let bad = |t: usize| {
        IoError::invalid(format!(
            "inconsistent neighbours around edge ({a}, {b}) at tetrahedron {t}"
        ))
    };
    let mut cur = start;
    for _ in 0..=tets.len() {
        let px = tets[cur]
            .iter()
            .position(|&v| v == x)
            .ok_or_else(|| bad(cur))?;
        let n = neighbors[cur][px];
        if n == NONE {
            return Ok(Ring::Hull);
        }
        let n = n as usize;
        if n == start {
            return Ok(Ring::Closed);
        }
        if n < start {
            return Ok(Ring::Lower);
        }
        let tn = tets.get(n).ok_or_else(|| bad(cur))?;
        // The new vertex of `n`: the one that is not a, b or y.
        let mut z = None;
        let mut shared = 0;
        for &v in tn {
            if v == a || v == b || v == y {
                shared += 1;
            } else {
                z = Some(v);
            }
        }
        let z = match (shared, z) {
            (3, Some(z)) => z,
            _ => return Err(bad(n)),
        };
        x = y;
        y = z;
        cur = n;
    }
    Err(bad(start))
}

/// Flags the vertices (of `n_points`) that lie on a boundary entity.
///
/// Indices not below `n_points` are ignored.
///
/// ```
/// let e = delone_io::topo::tri_edges(&[[0, 1, 2]], &[[u32::MAX; 3]]).unwrap();
/// assert_eq!(delone_io::topo::boundary_vertices(&e, 4), vec![true, true, true, false]);
/// ```
pub fn boundary_vertices<const K: usize>(entities: &Entities<K>, n_points: usize) -> Vec<bool> {
    let mut on = vec![false; n_points];
    for (item, &b) in entities.items.iter().zip(&entities.boundary) {
        if b {
            for &v in item {
                if let Some(x) = on.get_mut(v as usize) {
                    *x = true;
                }
            }
        }
    }
    on
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An n³ grid of cubes, each cut into the six tetrahedra around its
    /// main diagonal, with neighbours found by matching faces.
    fn cube_grid(n: u32) -> (Vec<[u32; 4]>, Vec<[u32; 4]>) {
        let id = |x: u32, y: u32, z: u32| (z * (n + 1) + y) * (n + 1) + x;
        let mut tets = Vec::new();
        for z in 0..n {
            for y in 0..n {
                for x in 0..n {
                    let c = |b: u32| id(x + (b & 1), y + (b >> 1 & 1), z + (b >> 2));
                    for path in [[1, 3], [1, 5], [2, 3], [2, 6], [4, 5], [4, 6]] {
                        tets.push([c(0), c(path[0]), c(path[1]), c(7)]);
                    }
                }
            }
        }
        let mut seen: std::collections::HashMap<[u32; 3], (usize, usize)> =
            std::collections::HashMap::new();
        let mut nbrs = vec![[NONE; 4]; tets.len()];
        for (t, tet) in tets.iter().enumerate() {
            for (i, f) in TET_FACES.iter().enumerate() {
                let mut key = f.map(|k| tet[k]);
                key.sort_unstable();
                if let Some((u, j)) = seen.remove(&key) {
                    nbrs[t][i] = u as u32;
                    nbrs[u][j] = t as u32;
                } else {
                    seen.insert(key, (t, i));
                }
            }
        }
        (tets, nbrs)
    }

    #[test]
    fn tet_faces_same_for_any_thread_count() {
        // 93,750 tetrahedra: two chunks or more from two threads on.
        let n = 25;
        let (tets, nbrs) = cube_grid(n);
        for all in [false, true] {
            let one = tet_faces(&tets, &nbrs, all).unwrap();
            let hull = 2 * 6 * (n * n) as usize;
            let want = if all {
                (4 * tets.len() + hull) / 2
            } else {
                hull
            };
            assert_eq!(one.items.len(), want);
            assert_eq!(one.boundary.iter().filter(|&&b| b).count(), hull);
            for threads in 0..=4 {
                assert_eq!(tet_faces_threads(&tets, &nbrs, all, threads).unwrap(), one);
            }
        }
        assert!(tet_faces_threads(&tets, &nbrs[1..], false, 2).is_err());
    }

    #[test]
    fn tet_faces_face_outwards() {
        let p = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        let tets = [[0u32, 1, 2, 3]];
        let f = tet_faces(&tets, &[[NONE; 4]], false).unwrap();
        let c = [0.25, 0.25, 0.25];
        for face in &f.items {
            let [a, b, d] = face.map(|v| p[v as usize]);
            let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let v = [d[0] - a[0], d[1] - a[1], d[2] - a[2]];
            let n = [
                u[1] * v[2] - u[2] * v[1],
                u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0],
            ];
            let w = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
            assert!(n[0] * w[0] + n[1] * w[1] + n[2] * w[2] < 0.0, "{face:?}");
        }
    }

    /// Neighbours by brute force (tests only).
    fn brute_neighbors(tets: &[[u32; 4]]) -> Vec<[u32; 4]> {
        let face = |t: &[u32; 4], i: usize| {
            let mut f: Vec<u32> = (0..4).filter(|&k| k != i).map(|k| t[k]).collect();
            f.sort();
            f
        };
        tets.iter()
            .enumerate()
            .map(|(a, ta)| {
                std::array::from_fn(|i| {
                    let fa = face(ta, i);
                    tets.iter()
                        .enumerate()
                        .find(|&(b, tb)| b != a && (0..4).any(|j| face(tb, j) == fa))
                        .map_or(NONE, |(b, _)| b as u32)
                })
            })
            .collect()
    }

    #[test]
    fn tet_edges_unique_and_flagged() {
        // An octahedron split into 4 tets around its vertical axis 0-1: the
        // axis is the only interior edge, the 4 inner faces are interior.
        let tets = [[0u32, 1, 2, 3], [0, 1, 3, 4], [0, 1, 4, 5], [0, 1, 5, 2]];
        let nbrs = brute_neighbors(&tets);
        let e = tet_edges(&tets, &nbrs).unwrap();
        assert_eq!(e.items.len(), 13); // 12 octahedron edges + the axis
        let mut keys: Vec<_> = e.items.iter().map(|&[a, b]| (a.min(b), a.max(b))).collect();
        keys.sort();
        keys.dedup();
        assert_eq!(keys.len(), 13);
        assert_eq!(
            &e.items[..6],
            &[[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]]
        );
        let interior: Vec<_> = (0..13).filter(|&k| !e.boundary[k]).collect();
        assert_eq!(interior, vec![0]);
        let f = tet_faces(&tets, &nbrs, true).unwrap();
        assert_eq!(f.items.len(), 12); // 8 hull + 4 inner
        assert_eq!(f.boundary.iter().filter(|&&b| !b).count(), 4);
        let h = tet_faces(&tets, &nbrs, false).unwrap();
        assert_eq!(h.items.len(), 8);
        assert!(h.boundary.iter().all(|&b| b));
        let on = boundary_vertices(&e, 7);
        assert_eq!(on, vec![true, true, true, true, true, true, false]);
    }

    #[test]
    fn inconsistent_neighbours_are_errors_not_hangs() {
        let tets = [[0u32, 1, 2, 3], [4, 3, 2, 1]];
        // Tet 0 claims tet 1 across face (0 2 3), which tet 1 does not have.
        let nbrs = [[1, 1, NONE, NONE], [0, NONE, NONE, NONE]];
        assert!(tet_edges(&tets, &nbrs).is_err());
        // Out-of-range neighbour.
        let nbrs = [[7, NONE, NONE, NONE], [NONE, NONE, NONE, 0]];
        assert!(tet_edges(&tets, &nbrs).is_err());
    }

    #[test]
    fn length_mismatch_is_an_error() {
        assert!(tri_edges(&[[0, 1, 2]], &[]).is_err());
        assert!(tet_edges(&[], &[[NONE; 4]]).is_err());
    }
}
