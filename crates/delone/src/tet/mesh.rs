//! The flat output of the 3D kernel ([`TetMesh`]), its independent
//! validator, and the kernel's own checkers.

use delone_predicates::{insphere, insphere_weighted, orient3d};

use super::delaunay::Delaunay3;
use super::dmesh::DomainMesh;
use super::local::{face, fkey, DEAD, FACET, INF};
use crate::geom::check::check_vertices;
use crate::{Violation, NONE};

pub use super::flat::TetMesh;

/// Why [`input_tets`] refused tetrahedra given as input; each names the
/// offending tetrahedron.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum TetsDefect {
    /// Names a missing point or one point twice.
    BadIndex(usize),
    /// Zero volume.
    Degenerate(usize),
    /// Oriented against the first tetrahedron.
    Inverted(usize),
    /// Has a face shared by more than two tetrahedra.
    NonManifold(usize),
    /// Lies on the same side of a common face as its neighbour there.
    Overlap(usize),
}

/// A neighbour table: per tetrahedron, the one across each face ([`NONE`]
/// if none).
pub(crate) type Neighbors = Vec<[u32; 4]>;

/// Tetrahedra given as input (an existing mesh, a background mesh), checked
/// with exact predicates on `points` and made positive, with their
/// neighbour table (face `f` opposite vertex `f`, paired by sorted face
/// keys). `consistent`: every tetrahedron must have the orientation of the
/// first ([`TetsDefect::Inverted`]), and the two tetrahedra of every common
/// face must lie on opposite sides of it ([`TetsDefect::Overlap`]);
/// otherwise each tetrahedron is turned on its own.
pub(crate) fn input_tets(
    points: &[[f64; 3]],
    tets: &[[u32; 4]],
    consistent: bool,
) -> Result<(Vec<[u32; 4]>, Neighbors), TetsDefect> {
    let n = points.len();
    let mut tv: Vec<[u32; 4]> = Vec::with_capacity(tets.len());
    let mut sign = 0.0f64;
    for (t, x) in tets.iter().enumerate() {
        let distinct = (0..4).all(|i| (i + 1..4).all(|j| x[i] != x[j]));
        if !distinct || x.iter().any(|&q| q as usize >= n) {
            return Err(TetsDefect::BadIndex(t));
        }
        let p = x.map(|q| points[q as usize]);
        let o = orient3d(&p[0], &p[1], &p[2], &p[3]);
        if o == 0.0 {
            return Err(TetsDefect::Degenerate(t));
        }
        if consistent && sign == 0.0 {
            sign = o.signum();
        } else if consistent && o.signum() != sign {
            return Err(TetsDefect::Inverted(t));
        }
        // delone's positive orientation is a negative `orient3d`.
        tv.push(if o > 0.0 {
            [x[1], x[0], x[2], x[3]]
        } else {
            *x
        });
    }
    let mut keys: Vec<([u32; 3], u32, u8)> = Vec::with_capacity(4 * tv.len());
    for (t, x) in tv.iter().enumerate() {
        for f in 0..4 {
            keys.push((fkey(face(*x, f)), t as u32, f as u8));
        }
    }
    keys.sort_unstable();
    let mut nb = vec![[NONE; 4]; tv.len()];
    for run in keys.chunk_by(|a, b| a.0 == b.0) {
        if run.len() > 2 {
            return Err(TetsDefect::NonManifold(run[2].1 as usize));
        }
        if let [(_, t, f), (_, u, g)] = *run {
            if consistent {
                let [a, b, c] = FACET[f as usize].map(|k| &points[tv[t as usize][k] as usize]);
                let d1 = &points[tv[t as usize][f as usize] as usize];
                let d2 = &points[tv[u as usize][g as usize] as usize];
                if orient3d(a, b, c, d1).signum() == orient3d(a, b, c, d2).signum() {
                    return Err(TetsDefect::Overlap(u as usize));
                }
            }
            nb[t as usize][f as usize] = u;
            nb[u as usize][g as usize] = t;
        }
    }
    Ok((tv, nb))
}

/// Checks `mesh` against `points` independently of how it was built, with
/// exact predicates:
///
/// * array sizes agree; vertex ids are in range, distinct within a tet, and
///   not duplicates; duplicates are bit-equal to their originals and every
///   other point is a vertex of some tetrahedron;
/// * every tetrahedron has positive volume;
/// * neighbour links are symmetric and join the same face from both sides;
/// * the hull faces (no neighbour) form a closed surface, each hull edge in
///   exactly two hull faces, and the surface is convex;
/// * the Euler relation `V - E + F - T = 1` holds;
/// * every interior face is locally Delaunay (the opposite apex is not
///   strictly inside the circumsphere).
///
/// Positive volumes with symmetric links and a closed convex boundary mean the
/// tetrahedra tile the convex hull; local Delaunay everywhere then means the
/// tiling is Delaunay.
///
/// ```
/// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
/// let mesh = delone::tetrahedralize(&pts).unwrap();
/// delone::tet::validate(&pts, &mesh).unwrap();
/// let mut bad = mesh.clone();
/// bad.tets[0].swap(0, 1);
/// assert!(delone::tet::validate(&pts, &bad).is_err());
/// ```
pub fn validate(points: &[[f64; 3]], mesh: &TetMesh) -> Result<(), Violation> {
    validate_impl(points, None, mesh)
}

/// [`validate`] for a *regular* (weighted Delaunay) tetrahedralization: the
/// empty-sphere test becomes the power test with `weights`, and every point
/// in [`TetMesh::hidden`] must really have an empty power cell (it lies in a
/// tetrahedron whose orthogonal sphere it does not conflict with — found by a
/// linear search, `O(hidden × tets)`).
///
/// ```
/// let pts = [[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [0.0, 4.0, 0.0], [0.0, 0.0, 4.0], [1.0, 1.0, 1.0]];
/// let w = [0.0, 0.0, 0.0, 0.0, -10.0];
/// let mesh = delone::tet::Delaunay3::from_weighted_points(&pts, &w).unwrap().into_mesh();
/// delone::tet::validate_regular(&pts, &w, &mesh).unwrap();
/// // With weight 0 the fifth point must be a vertex: claiming it hidden is wrong.
/// assert!(delone::tet::validate_regular(&pts, &[0.0; 5], &mesh).is_err());
/// ```
pub fn validate_regular(
    points: &[[f64; 3]],
    weights: &[f64],
    mesh: &TetMesh,
) -> Result<(), Violation> {
    if weights.len() != points.len() {
        return Err(Violation::new(
            "sizes",
            format!("{} weights for {} points", weights.len(), points.len()),
        ));
    }
    validate_impl(points, Some(weights), mesh)
}

fn validate_impl(
    points: &[[f64; 3]],
    weights: Option<&[f64]>,
    mesh: &TetMesh,
) -> Result<(), Violation> {
    // Huge or tiny coordinates are scaled by an exact power of two first, so
    // that the exact predicates neither overflow nor underflow (weights by
    // its square).
    let (points, s) = crate::geom::rescaled(points);
    let points = &points[..];
    let scaled_weights: Option<Vec<f64>> =
        weights.map(|w| w.iter().map(|&x| x * s.0 * s.0 * s.1 * s.1).collect());
    let weights = scaled_weights.as_deref();
    let n = points.len();
    let nt = mesh.tets.len();
    if mesh.neighbors.len() != nt || mesh.vertex_map.len() != n {
        return Err(Violation::new(
            "sizes",
            format!(
                "{nt} tets, {} neighbour rows, {} vertex_map entries for {n} points",
                mesh.neighbors.len(),
                mesh.vertex_map.len()
            ),
        ));
    }
    let mut used = vec![false; n];
    for (t, tv) in mesh.tets.iter().enumerate() {
        for &q in tv {
            if q as usize >= n {
                return Err(Violation::new(
                    "range",
                    format!("tet {t} names vertex {q}, only {n} points"),
                ));
            }
            used[q as usize] = true;
        }
    }
    let (dups, hidden) = (&mesh.duplicates, &mesh.hidden);
    check_vertices(points, weights, &used, &mesh.vertex_map, dups, hidden)?;
    // Positive volumes (distinct vertices) and neighbours across the same
    // face, seen with opposite orientations: the domain mesh's checker,
    // with the boundary faces (no neighbour) as its subfaces.
    let mut m = DomainMesh::from_neighbors(&mesh.tets, &mesh.neighbors, &[], n).map_err(|t| {
        let why = format!("tet {t} has a neighbour that does not share the face");
        Violation::new("adjacency", why)
    })?;
    m.mark_subfaces(&Default::default());
    m.check(points).map_err(|e| Violation::new("topology", e))?;
    let mut faces = 0usize;
    let mut hull_edges: Vec<(u32, u32, u32)> = Vec::new();
    for (t, tv) in mesh.tets.iter().enumerate() {
        for f in 0..4 {
            let w = m.nb[t][f];
            if w == NONE {
                faces += 1;
                // Outward orientation is the reverse of FACET order.
                let [a, b, c] = face(*tv, f);
                for (x, y) in [(a, c), (c, b), (b, a)] {
                    hull_edges.push((x, y, t as u32 * 4 + f as u32));
                }
            } else if (w >> 2) as usize > t {
                faces += 1;
                let (u, apex) = (w >> 2, m.tv[(w >> 2) as usize][(w & 3) as usize]);
                if conflict(points, weights, [tv[1], tv[0], tv[2], tv[3]], apex) {
                    return Err(Violation::new(
                        "delaunay",
                        format!(
                            "vertex {apex} of tet {u} is inside the circumsphere of tet {t} {tv:?}"
                        ),
                    ));
                }
            }
        }
    }
    check_hull(points, mesh, &mut hull_edges)?;
    check_hidden(points, weights, mesh)?;
    let mut edges: Vec<(u32, u32)> = Vec::with_capacity(nt * 6);
    for tv in &mesh.tets {
        for i in 0..4 {
            for j in i + 1..4 {
                edges.push((tv[i].min(tv[j]), tv[i].max(tv[j])));
            }
        }
    }
    edges.sort_unstable();
    edges.dedup();
    let nv = used.iter().filter(|&&u| u).count() as i64;
    let chi = nv - edges.len() as i64 + faces as i64 - nt as i64;
    if nt > 0 && chi != 1 {
        return Err(Violation::new(
            "euler",
            format!(
                "V - E + F - T = {nv} - {} + {faces} - {nt} = {chi}, expected 1",
                edges.len()
            ),
        ));
    }
    Ok(())
}

/// Is `q` strictly in conflict with the (orthogonal) sphere of the
/// tetrahedron `t`, given with `orient3d(t) > 0`?
pub(crate) fn conflict(points: &[[f64; 3]], weights: Option<&[f64]>, t: [u32; 4], q: u32) -> bool {
    let p = |i: u32| &points[i as usize];
    match weights {
        None => insphere(p(t[0]), p(t[1]), p(t[2]), p(t[3]), p(q)) > 0.0,
        Some(w) => {
            let w = |i: u32| w[i as usize];
            insphere_weighted(
                p(t[0]),
                p(t[1]),
                p(t[2]),
                p(t[3]),
                p(q),
                w(t[0]),
                w(t[1]),
                w(t[2]),
                w(t[3]),
                w(q),
            ) > 0.0
        }
    }
}

/// The hidden points (listed as [`check_vertices`] checks) are really
/// hidden: inside some tetrahedron whose sphere they do not conflict with.
fn check_hidden(
    points: &[[f64; 3]],
    weights: Option<&[f64]>,
    mesh: &TetMesh,
) -> Result<(), Violation> {
    let p = |i: u32| &points[i as usize];
    for &h in &mesh.hidden {
        let q = p(h);
        // Not strictly beyond any facet (orient3d > 0 means beyond).
        let inside = |t: &[u32; 4]| {
            FACET
                .iter()
                .all(|fv| orient3d(p(t[fv[0]]), p(t[fv[1]]), p(t[fv[2]]), q) <= 0.0)
        };
        let Some(t) = mesh.tets.iter().find(|t| inside(t)) else {
            return Err(Violation::new(
                "hidden",
                format!("hidden point {h} lies outside the hull"),
            ));
        };
        if conflict(points, weights, [t[1], t[0], t[2], t[3]], h) {
            return Err(Violation::new(
                "hidden",
                format!("point {h} is listed hidden but has a non-empty power cell (tet {t:?})"),
            ));
        }
    }
    Ok(())
}

/// The hull faces form a closed, convex surface: every directed hull edge
/// meets its reverse exactly once, and across every hull edge the far vertex
/// of the other face is not strictly outside.
fn check_hull(
    points: &[[f64; 3]],
    mesh: &TetMesh,
    edges: &mut [(u32, u32, u32)],
) -> Result<(), Violation> {
    edges.sort_unstable();
    for w in edges.windows(2) {
        if w[0].0 == w[1].0 && w[0].1 == w[1].1 {
            return Err(Violation::new(
                "hull",
                format!(
                    "hull edge {}-{} is used twice in one direction",
                    w[0].0, w[0].1
                ),
            ));
        }
    }
    let p = |q: u32| &points[q as usize];
    let outward = |code: u32| {
        let (t, f) = ((code / 4) as usize, (code % 4) as usize);
        let [a, b, c] = FACET[f].map(|i| mesh.tets[t][i]);
        [a, c, b]
    };
    for &(a, b, code) in edges.iter() {
        let k = edges.partition_point(|e| (e.0, e.1) < (b, a));
        if k >= edges.len() || (edges[k].0, edges[k].1) != (b, a) {
            return Err(Violation::new(
                "hull",
                format!("hull edge {a}-{b} has no neighbouring hull face"),
            ));
        }
        let mine = outward(code);
        let other = outward(edges[k].2);
        let far = other
            .iter()
            .copied()
            .find(|&q| q != a && q != b)
            .unwrap_or(a);
        // Strictly outside an outward face means orient3d < 0 (our positive
        // side), so convexity asks for orient3d >= 0.
        if orient3d(p(mine[0]), p(mine[1]), p(mine[2]), p(far)) < 0.0 {
            return Err(Violation::new(
                "convexity",
                format!("vertex {far} lies outside hull face {mine:?}"),
            ));
        }
    }
    Ok(())
}

/// The kernel's checkers, here with the checkers they run.
impl Delaunay3<'_> {
    /// Checks the combinatorial and orientation invariants: the arrays pass
    /// the checker of the constrained domain mesh (`tet::dmesh`: the free list
    /// names exactly the dead slots, every finite tetrahedron is positive
    /// (exact), every ghost has exactly one infinite vertex, last, every
    /// adjacency word is mirrored and joins equal facets with opposite
    /// orientations), the finite count is right, every inserted vertex
    /// belongs to a tetrahedron, and the Euler relation `V - E + F - T = 1`
    /// holds.
    ///
    /// ```
    /// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    /// delone::tet::Delaunay3::from_points(&pts).unwrap().check_topology().unwrap();
    /// ```
    pub fn check_topology(&self) -> Result<(), Violation> {
        let c = &self.core;
        if c.v.is_empty() {
            return Ok(());
        }
        let pts: &[[f64; 3]] = &self.points;
        // A copy of the arrays as a domain mesh without subfaces.
        let m = DomainMesh::from_arrays(c.v.clone(), c.adj.clone(), c.free.clone(), Vec::new());
        m.check(pts).map_err(|e| Violation::new("topology", e))?;
        let finite = (c.v.iter())
            .filter(|tv| tv[0] != DEAD && !tv.contains(&INF))
            .count();
        if finite != c.finite {
            return Err(Violation::new(
                "count",
                format!("{finite} finite tets, counter says {}", c.finite),
            ));
        }
        // Vertices used, and the Euler relation of the finite complex.
        let mut used = vec![false; pts.len()];
        let mut edges: Vec<(u32, u32)> = Vec::with_capacity(finite * 6);
        let mut faces = 0usize;
        for (t, tv) in c.v.iter().enumerate() {
            if tv[0] == DEAD || tv.contains(&INF) {
                continue;
            }
            for &q in tv {
                used[q as usize] = true;
            }
            for i in 0..4 {
                for j in i + 1..4 {
                    edges.push((tv[i].min(tv[j]), tv[i].max(tv[j])));
                }
                let u = (c.adj[t][i] >> 2) as usize;
                // Count each finite-finite facet once, hull facets always.
                if c.v[u].contains(&INF) || u > t {
                    faces += 1;
                }
            }
        }
        edges.sort_unstable();
        edges.dedup();
        for (i, &m) in self.vertex_map.iter().enumerate() {
            let should = m == i as u32 && !self.pending.contains(&(i as u32));
            if should != used[i] {
                return Err(Violation::new(
                    "vertices",
                    if should {
                        format!("vertex {i} is missing from the tetrahedralization")
                    } else {
                        format!("duplicate or pending point {i} is used by a tetrahedron")
                    },
                ));
            }
        }
        let nv = used.iter().filter(|&&u| u).count() as i64;
        let chi = nv - edges.len() as i64 + faces as i64 - finite as i64;
        if chi != 1 {
            return Err(Violation::new(
                "euler",
                format!(
                    "V - E + F - T = {nv} - {} + {faces} - {finite} = {chi}, expected 1",
                    edges.len()
                ),
            ));
        }
        Ok(())
    }

    /// Checks the Delaunay (regular, with weights) property with exact
    /// predicates: the flat output of a copy ([`Delaunay3::into_mesh`])
    /// passes [`validate`] (or [`validate_regular`]): for every facet
    /// between two tetrahedra, the apex of one is not strictly inside the
    /// circumsphere (orthogonal sphere) of the other, the hull is convex,
    /// and the hidden points are really hidden. Together with
    /// [`Delaunay3::check_topology`] this certifies a Delaunay
    /// tetrahedralization of the convex hull.
    ///
    /// ```
    /// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 1.0, 1.0]];
    /// delone::tet::Delaunay3::from_points(&pts).unwrap().check_delaunay().unwrap();
    /// ```
    pub fn check_delaunay(&self) -> Result<(), Violation> {
        if self.core.finite == 0 {
            // No tetrahedron yet (the points may be pending): nothing to check.
            return Ok(());
        }
        let mesh = self.clone().into_mesh();
        match &self.weights {
            None => validate(&self.points, &mesh),
            Some(w) => validate_regular(&self.points, w, &mesh),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn validate_sees_broken_orientation_and_links() {
        let mut pts = crate::geom::vec3::corner_tet(1.0).to_vec();
        pts.push([1.0; 3]);
        let mesh = crate::tetrahedralize(&pts).unwrap();
        assert_eq!(mesh.tets.len(), 2);
        validate(&pts, &mesh).unwrap();
        let (shared, back) = (0..4)
            .find_map(|f| {
                (mesh.neighbors[0][f] == 1)
                    .then(|| (f, mesh.neighbors[1].iter().position(|&u| u == 0).unwrap()))
            })
            .unwrap();
        let broken = |edit: &dyn Fn(&mut TetMesh)| {
            let mut m = mesh.clone();
            edit(&mut m);
            validate(&pts, &m).unwrap_err().kind
        };
        // Inverted (the faces and their neighbours kept together).
        let invert = |m: &mut TetMesh| {
            m.tets[0].swap(0, 1);
            m.neighbors[0].swap(0, 1);
        };
        assert_eq!(broken(&invert), "topology");
        // Links that break the symmetry or the shared face.
        let links: [&dyn Fn(&mut TetMesh); 4] = [
            &|m| m.neighbors[0][shared] = NONE,
            &|m| m.neighbors[1][back] = 1,
            &|m| m.neighbors[0][(shared + 1) % 4] = 1,
            &|m| m.tets[1] = m.tets[0],
        ];
        for edit in links {
            assert!(["adjacency", "topology", "vertex"].contains(&broken(edit)));
        }
        assert_eq!(broken(&|m| m.tets[0][0] = 9), "range");
    }
}
