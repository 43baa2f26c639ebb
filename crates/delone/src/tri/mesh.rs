//! The flat output of the 2D kernel and its independent validator.

use delone_predicates::{incircle_weighted, orient2d};

use super::cmesh::CMesh;
use crate::geom::brio_order;
use crate::geom::check::check_vertices;
use crate::{Violation, NONE};

/// A triangulation in flat arrays, as returned by [`crate::triangulate`].
///
/// ```
/// let mesh = delone::triangulate(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]]).unwrap();
/// assert_eq!(mesh.triangles.len(), 2);
/// assert_eq!(mesh.neighbors.len(), 2);
/// assert_eq!(mesh.vertex_map, vec![0, 1, 2, 3]);
/// ```
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct TriMesh {
    /// Triangles as counterclockwise vertex triples (indices into the input points).
    pub triangles: Vec<[u32; 3]>,
    /// `neighbors[t][i]` is the triangle across the edge opposite vertex `i` of
    /// triangle `t`, or [`crate::NONE`] on the convex hull.
    pub neighbors: Vec<[u32; 3]>,
    /// For every input point, the vertex that represents it: itself, or the
    /// first earlier point with identical coordinates.
    pub vertex_map: Vec<u32>,
    /// Input points that duplicate an earlier one, as `(duplicate, original)`,
    /// in increasing order of the duplicate.
    pub duplicates: Vec<(u32, u32)>,
    /// Input points left out of a *regular* (weighted) triangulation
    /// because their power cell is empty ("hidden" or redundant points),
    /// sorted; their `vertex_map` entry is [`crate::NONE`]. Always empty for
    /// unweighted input.
    pub hidden: Vec<u32>,
}

/// Triangle `t` (`v`, vertices in range) is strictly counterclockwise
/// (exact orientation).
pub(crate) fn check_ccw(points: &[[f64; 2]], t: usize, v: &[u32; 3]) -> Result<(), Violation> {
    let [a, b, c] = v.map(|x| &points[x as usize]);
    if orient2d(a, b, c) > 0.0 {
        return Ok(());
    }
    err(
        "orientation",
        format!("triangle {t} {v:?} is not counterclockwise"),
    )
}

fn err<T>(kind: &'static str, detail: String) -> Result<T, Violation> {
    Err(Violation::new(kind, detail))
}

/// Checks `triangles` on `points` with their `neighbors`: vertices in
/// range, counterclockwise triangles (exact), no edge used twice in the same
/// direction, and across every edge the triangle holding its twin, or
/// [`NONE`] where there is none. `interior(t, i, u, j)` is called on every
/// edge `i` of triangle `t` whose twin is edge `j` of `u` (so on each
/// interior edge once from each side). Returns the directed edges
/// `(a, b, t, i)`, sorted.
pub(crate) fn check_edges(
    points: &[[f64; 2]],
    triangles: &[[u32; 3]],
    neighbors: &[[u32; 3]],
    mut interior: impl FnMut(u32, u8, u32, u8) -> Result<(), Violation>,
) -> Result<Vec<(u32, u32, u32, u8)>, Violation> {
    let mut edges: Vec<(u32, u32, u32, u8)> = Vec::with_capacity(3 * triangles.len());
    for (t, v) in triangles.iter().enumerate() {
        if let Some(x) = v.iter().find(|&&x| x as usize >= points.len()) {
            return Err(Violation::new(
                "vertex",
                format!("triangle {t} has vertex {x} out of range"),
            ));
        }
        check_ccw(points, t, v)?;
        for i in 0..3 {
            edges.push((v[(i + 1) % 3], v[(i + 2) % 3], t as u32, i as u8));
        }
    }
    edges.sort_unstable();
    for w in edges.windows(2) {
        if (w[0].0, w[0].1) == (w[1].0, w[1].1) {
            return err(
                "manifold",
                format!(
                    "edge ({}, {}) is used in the same direction by triangles {} and {}",
                    w[0].0, w[0].1, w[0].2, w[1].2
                ),
            );
        }
    }
    for &(a, b, t, i) in &edges {
        let nb = neighbors[t as usize][i as usize];
        let twin = find_edge(&edges, b, a);
        if twin.map_or(NONE, |e| e.2) != nb {
            return err(
                "adjacency",
                format!("triangle {t} edge {i} ({a}, {b}) has neighbour {nb}, the twin edge is in {twin:?}"),
            );
        }
        if let Some((_, _, u, j)) = twin {
            interior(t, i, u, j)?;
        }
    }
    Ok(edges)
}

/// The directed edge `a -> b` in the sorted `edges` of [`check_edges`].
pub(crate) fn find_edge(
    edges: &[(u32, u32, u32, u8)],
    a: u32,
    b: u32,
) -> Option<(u32, u32, u32, u8)> {
    let k = edges.binary_search_by(|e| (e.0, e.1).cmp(&(a, b))).ok()?;
    Some(edges[k])
}

/// Checks `mesh` against `points` independently of how it was built (it does
/// not use the kernel), with exact predicates (after an exact power-of-two
/// scaling when the coordinates are huge or tiny):
///
/// * array sizes and vertex ids are in range, triangles are counterclockwise;
/// * neighbours are symmetric and across the shared edge, every edge is used
///   by at most one triangle per direction, hull edges have [`NONE`];
/// * the hull edges form one closed cycle turning left once (convex;
///   collinear hull points allowed);
/// * Euler's relation `V - E + F = 1`;
/// * every input point is either a vertex or listed as a duplicate of the
///   first earlier point with equal coordinates (`vertex_map`, `duplicates`);
/// * every interior edge is locally Delaunay (the opposite apex is not
///   strictly inside the circumcircle).
///
/// # Errors
/// The first [`Violation`] found, naming the triangle, edge or vertex.
///
/// ```
/// let pts = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]];
/// let mut mesh = delone::triangulate(&pts).unwrap();
/// delone::tri::validate(&pts, &mesh).unwrap();
/// mesh.triangles[0].swap(0, 1);
/// assert!(delone::tri::validate(&pts, &mesh).is_err());
/// ```
pub fn validate(points: &[[f64; 2]], mesh: &TriMesh) -> Result<(), Violation> {
    validate_impl(points, None, mesh)
}

/// Checks a *regular* triangulation `mesh` of `points` with `weights` (as
/// returned by [`super::regular_triangulation`]) independently of the kernel,
/// with exact predicates. Everything [`validate`] checks, except that
///
/// * every interior edge is locally *regular* (exact power test: the lifted
///   apex across the edge is not strictly below the lifted triangle's plane);
/// * equal points are duplicates only with equal weights; the points listed
///   in [`TriMesh::hidden`] (sorted) are exactly those not used and not
///   duplicates, their `vertex_map` entry is [`NONE`];
/// * every hidden point is really hidden: it lies in the closed hull, and
///   its lifted point is on or above the lifted triangle containing it
///   (located by a walk; exact orientation and power tests).
///
/// Local regularity of every edge makes the lifted surface convex, so these
/// checks together certify the regular triangulation.
///
/// # Errors
/// The first [`Violation`] found; [`Violation::kind`] `"size"` if
/// `weights.len() != points.len()`.
///
/// ```
/// let pts = [[0.0, 0.0], [4.0, 0.0], [0.0, 4.0], [4.0, 4.0], [2.0, 2.0]];
/// let w = [1.0, 1.0, 1.0, 1.0, -8.0];
/// let mut mesh = delone::tri::regular_triangulation(&pts, &w).unwrap();
/// delone::tri::validate_regular(&pts, &w, &mesh).unwrap();
/// // Claiming that the light centre point is a vertex's duplicate is caught.
/// mesh.hidden.clear();
/// assert!(delone::tri::validate_regular(&pts, &w, &mesh).is_err());
/// ```
pub fn validate_regular(
    points: &[[f64; 2]],
    weights: &[f64],
    mesh: &TriMesh,
) -> Result<(), Violation> {
    if weights.len() != points.len() {
        return err(
            "size",
            format!("{} points but {} weights", points.len(), weights.len()),
        );
    }
    validate_impl(points, Some(weights), mesh)
}

fn validate_impl(
    points: &[[f64; 2]],
    weights: Option<&[f64]>,
    mesh: &TriMesh,
) -> Result<(), Violation> {
    // Huge or tiny coordinates are scaled by an exact power of two first, so
    // that the exact predicates neither overflow nor underflow (weights are
    // scaled by the square of the same factor).
    let (points, s) = crate::geom::rescaled(points);
    let points = &points[..];
    let weights: Option<Vec<f64>> =
        weights.map(|w| w.iter().map(|&x| x * s.0 * s.0 * s.1 * s.1).collect());
    let weights = weights.as_deref();
    let n = points.len();
    let nt = mesh.triangles.len();
    if mesh.neighbors.len() != nt {
        return err(
            "size",
            format!("{nt} triangles but {} neighbour rows", mesh.neighbors.len()),
        );
    }
    if mesh.vertex_map.len() != n {
        return err(
            "size",
            format!(
                "{n} points but vertex_map has {} entries",
                mesh.vertex_map.len()
            ),
        );
    }
    if nt == 0 {
        return err("size", "no triangles".into());
    }
    // Vertices in range, counterclockwise triangles, neighbours across
    // twin edges; every interior edge locally Delaunay (regular).
    let edges = check_edges(
        points,
        &mesh.triangles,
        &mesh.neighbors,
        |_, _, _, _| Ok(()),
    )?;
    let cm = CMesh::from_triangles(points.to_vec(), &mesh.triangles, &mesh.neighbors);
    cm.check_delaunay(weights)?;
    let mut used = vec![false; n];
    for &x in mesh.triangles.iter().flatten() {
        used[x as usize] = true;
    }
    let (dups, hidden) = (&mesh.duplicates, &mesh.hidden);
    check_vertices(points, weights, &used, &mesh.vertex_map, dups, hidden)?;
    // The hull: the edges without a twin, sorted by their start vertex.
    let hull: Vec<(u32, u32)> = edges
        .iter()
        .filter(|e| find_edge(&edges, e.1, e.0).is_none())
        .map(|e| (e.0, e.1))
        .collect();
    // Hull: one closed cycle, convex (left turns, no reversal), winding once.
    // `hull` is sorted by its start vertex (the edges were).
    let next = |a: u32| {
        hull.binary_search_by(|e| e.0.cmp(&a))
            .ok()
            .map(|k| hull[k].1)
    };
    for w in hull.windows(2) {
        if w[0].0 == w[1].0 {
            return err("hull", format!("vertex {} starts two hull edges", w[0].0));
        }
    }
    // Exact throughout: the signs of coordinate differences are exact in
    // floating point, so a closed chain of left turns (each less than a half
    // turn) winds exactly as often as its edge direction passes from the
    // lower half-plane of directions into the upper one.
    let upper = |d: [f64; 2]| d[1] > 0.0 || (d[1] == 0.0 && d[0] > 0.0);
    let dir = |a: u32, b: u32| {
        let (pa, pb) = (&points[a as usize], &points[b as usize]);
        [pb[0] - pa[0], pb[1] - pa[1]]
    };
    let sign = |x: f64| (x > 0.0) as i8 - (x < 0.0) as i8;
    let start = hull[0].0;
    let (mut a, mut b) = hull[0];
    let mut windings = 0usize;
    let mut steps = 0usize;
    loop {
        let Some(c) = next(b) else {
            return err("hull", format!("hull edge ({a}, {b}) has no successor"));
        };
        let [pa, pb, pc] = [a, b, c].map(|x| &points[x as usize]);
        let o = orient2d(pa, pb, pc);
        let (u, v) = (dir(a, b), dir(b, c));
        // Collinear: parallel, so the same direction iff the same signs.
        let back = o == 0.0 && (sign(u[0]) != sign(v[0]) || sign(u[1]) != sign(v[1]));
        if o < 0.0 || back {
            return err(
                "hull",
                format!("hull turns right (or back) at vertex {b} ({a} -> {b} -> {c})"),
            );
        }
        if !upper(u) && upper(v) {
            windings += 1;
        }
        steps += 1;
        a = b;
        b = c;
        if a == start || steps > hull.len() {
            break;
        }
    }
    if steps != hull.len() {
        return err(
            "hull",
            format!(
                "the hull cycle through vertex {start} has {steps} edges; {} hull edges exist",
                hull.len()
            ),
        );
    }
    if windings != 1 {
        return err(
            "hull",
            format!("hull winds {windings} turns instead of one"),
        );
    }
    // Euler: V - E + F = 1 with E = (3F + H) / 2.
    let v = used.iter().filter(|&&u| u).count() as i64;
    let f = nt as i64;
    let h = hull.len() as i64;
    if (3 * f + h) % 2 != 0 || v - (3 * f + h) / 2 + f != 1 {
        return err(
            "euler",
            format!("V={v} F={f} hull edges={h} violate V - E + F = 1"),
        );
    }
    if let Some(w) = weights {
        check_hidden(&cm, w, mesh)?;
    }
    Ok(())
}

/// Every hidden point lies in the closed hull and on or above the lifted
/// triangle that contains it (located by [`CMesh::locate`], visiting the
/// hidden points in [`brio_order`] so that each walk starts near the
/// previous answer) in `cm`, the mesh of `mesh`, whose topology is
/// already validated.
fn check_hidden(cm: &CMesh, w: &[f64], mesh: &TriMesh) -> Result<(), Violation> {
    let points = &cm.xy;
    let hidden: Vec<[f64; 2]> = mesh.hidden.iter().map(|&h| points[h as usize]).collect();
    let (mut t, mut rng) = (0, 0x2545_f491u32);
    for k in brio_order(&hidden) {
        let h = mesh.hidden[k as usize];
        let q = &points[h as usize];
        let Some(found) = cm.locate(t, q, &mut rng) else {
            return err("hidden", format!("hidden point {h} is outside the hull"));
        };
        t = found;
        let v = mesh.triangles[t];
        let [a, b, c] = v.map(|x| &points[x as usize]);
        let [wa, wb, wc] = v.map(|x| w[x as usize]);
        if incircle_weighted(a, b, c, q, wa, wb, wc, w[h as usize]) > 0.0 {
            return err(
                "hidden",
                format!(
                    "hidden point {h} is in power conflict with triangle {t} {v:?} containing it"
                ),
            );
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A square split along the diagonal 0-2, plus a Delaunay-violating
    /// variant: points 0..4 of a kite where only the diagonal 1-3 is Delaunay.
    fn square() -> (Vec<[f64; 2]>, TriMesh) {
        let pts = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let mesh = TriMesh {
            triangles: vec![[0, 1, 2], [0, 2, 3]],
            neighbors: vec![[NONE, 1, NONE], [NONE, NONE, 0]],
            vertex_map: vec![0, 1, 2, 3],
            duplicates: vec![],
            hidden: vec![],
        };
        (pts, mesh)
    }

    #[test]
    fn accepts_a_valid_mesh() {
        let (pts, mesh) = square();
        validate(&pts, &mesh).unwrap();
    }

    #[test]
    fn rejects_broken_neighbours() {
        let (pts, mut mesh) = square();
        mesh.neighbors[0][1] = NONE;
        assert_eq!(validate(&pts, &mesh).unwrap_err().kind, "adjacency");
        let (pts, mut mesh) = square();
        mesh.neighbors[1][0] = 0;
        assert_eq!(validate(&pts, &mesh).unwrap_err().kind, "adjacency");
    }

    #[test]
    fn rejects_non_delaunay_edge() {
        // Flat kite: the diagonal 0-2 is too long; 1-3 would be Delaunay.
        let (mut pts, mesh) = square();
        pts[0] = [-2.0, 0.0];
        pts[1] = [0.0, -0.5];
        pts[2] = [2.0, 0.0];
        pts[3] = [0.0, 0.5];
        let v = validate(&pts, &mesh).unwrap_err();
        assert_eq!(v.kind, "delaunay", "{v}");
    }

    #[test]
    fn rejects_missing_vertex_and_bad_duplicates() {
        let (mut pts, mut mesh) = square();
        pts.push([0.5, 0.25]);
        mesh.vertex_map.push(4);
        assert_eq!(validate(&pts, &mesh).unwrap_err().kind, "vertex");
        // Declared as a duplicate of a point it does not equal.
        mesh.vertex_map[4] = 0;
        mesh.duplicates.push((4, 0));
        assert_eq!(validate(&pts, &mesh).unwrap_err().kind, "vertex_map");
        // A true duplicate, but the list is missing.
        pts[4] = pts[0];
        mesh.duplicates.clear();
        assert_eq!(validate(&pts, &mesh).unwrap_err().kind, "duplicates");
        mesh.duplicates.push((4, 0));
        validate(&pts, &mesh).unwrap();
    }

    #[test]
    fn rejects_non_convex_hull() {
        // Two triangles forming a non-convex quadrilateral (a dart).
        let pts = vec![[0.0, 0.0], [2.0, 1.0], [0.0, 2.0], [0.5, 1.0]];
        let mesh = TriMesh {
            triangles: vec![[0, 1, 3], [3, 1, 2]],
            neighbors: vec![[1, NONE, NONE], [NONE, NONE, 0]],
            vertex_map: vec![0, 1, 2, 3],
            duplicates: vec![],
            hidden: vec![],
        };
        let v = validate(&pts, &mesh).unwrap_err();
        assert_eq!(v.kind, "hull", "{v}");
    }

    #[test]
    fn rejects_overlap() {
        // The same triangle twice: an edge used twice in one direction.
        let (pts, mut mesh) = square();
        mesh.triangles.push([0, 1, 2]);
        mesh.neighbors.push([NONE, NONE, NONE]);
        assert_eq!(validate(&pts, &mesh).unwrap_err().kind, "manifold");
    }
}
