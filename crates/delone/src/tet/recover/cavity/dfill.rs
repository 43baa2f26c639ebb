//! Filling a polyhedron with no new point by **gift-wrapping the
//! constrained Delaunay tetrahedralization of its vertices** (as for a
//! half-cavity in Si & Gärtner 2005 and Diazzi et al. 2023), see
//! [`wrap_fill`]. The `prune` module uses it to retriangulate the star of
//! an interior Steiner point without that point when no cone from one of
//! the star's vertices does; the `pull` module fills a wedge with it when
//! no cone does, before it tries a kernel point. Such a tetrahedralization need not exist
//! when the boundary faces are not Delaunay (Schönhardt's prism; the fan
//! triangles of the flat faces of CAD models): the wrapping then reports
//! failure and the point stays.
//!
//! Nothing here is trusted: the caller validates the result exactly (all
//! tetrahedra positive, the chain of their faces bounded by the removed
//! set's boundary, protected items kept).

use super::{okey, rev, sees, P};
use crate::geom::ids::IdMap;
use crate::tet::intersect::triangles_intersect;
use crate::tet::local::face;
use delone_predicates::insphere_sos;

/// Largest polyhedron (in vertices) filled by [`wrap_fill`].
const WRAP_VERTS: usize = 96;

/// The tetrahedra (mesh ids, positively oriented) filling the polyhedron
/// bounded by the inward faces `faces` with no new vertex, built by
/// **gift-wrapping** its constrained Delaunay tetrahedralization: a front
/// of inward faces starts as the boundary; each step takes a front face
/// `f` and, among the front vertices strictly on its inner side, the one
/// whose sphere through `f` holds no other (exact `insphere`, ties broken
/// by symbolic perturbation ordered by vertex id) among those whose
/// tetrahedron with `f` crosses no front face and holds no front vertex
/// (exact triangle-pair tests, [`triangles_intersect`]); the tetrahedron's
/// faces close the front faces they match and open the others. `None`
/// when a front face has no such vertex (the polyhedron may have no
/// tetrahedralization without a new point, e.g. Schönhardt's prism), or
/// past a step budget.
pub(super) fn wrap_fill(pts: &[P], faces: &[[u32; 3]]) -> Option<Vec<[u32; 4]>> {
    let mut verts: Vec<u32> = faces.iter().flatten().copied().collect();
    verts.sort_unstable();
    verts.dedup();
    if verts.len() < 4 || verts.len() > WRAP_VERTS {
        return None;
    }
    // Live front faces by rotated key (inward orientation), and how many
    // live front faces each vertex is on.
    let mut front: IdMap<[u32; 3], ()> = IdMap::default();
    let mut on_front: IdMap<u32, u32> = IdMap::default();
    let mut queue: std::collections::VecDeque<[u32; 3]> = std::collections::VecDeque::new();
    for &f in faces {
        if front.insert(okey(f), ()).is_some() {
            return None;
        }
        for w in f {
            *on_front.entry(w).or_insert(0) += 1;
        }
        queue.push_back(okey(f));
    }
    let mut out: Vec<[u32; 4]> = Vec::new();
    let budget = 8 * verts.len() + 64;
    while let Some(f) = queue.pop_front() {
        if !front.contains_key(&f) {
            continue;
        }
        if out.len() >= budget {
            return None;
        }
        let p = |w: u32| &pts[w as usize];
        let mut cands: Vec<u32> = verts
            .iter()
            .copied()
            .filter(|&v| {
                !f.contains(&v) && on_front.get(&v).is_some_and(|&n| n > 0) && sees(pts, f, p(v))
            })
            .collect();
        let live: Vec<[u32; 3]> = front.keys().copied().collect();
        let chosen = loop {
            // The Delaunay choice among the candidates left.
            let mut best: Option<u32> = None;
            for &v in &cands {
                best = match best {
                    None => Some(v),
                    // `[f, b]` has orient3d < 0: swapping two vertices
                    // gives insphere's orientation.
                    Some(b) => {
                        let inside = insphere_sos(
                            p(f[1]),
                            p(f[0]),
                            p(f[2]),
                            p(b),
                            p(v),
                            f[1],
                            f[0],
                            f[2],
                            b,
                            v,
                        ) > 0;
                        Some(if inside { v } else { b })
                    }
                };
            }
            let v = best?;
            if tet_clear(pts, &live, f, v) {
                break v;
            }
            cands.retain(|&w| w != v);
        };
        let tv = [f[0], f[1], f[2], chosen];
        out.push(tv);
        for k in 0..4 {
            let g = okey(face(tv, k));
            if front.remove(&g).is_some() {
                for w in g {
                    if let Some(n) = on_front.get_mut(&w) {
                        *n -= 1;
                    }
                }
            } else {
                let r = rev(g);
                front.insert(r, ());
                for w in r {
                    *on_front.entry(w).or_insert(0) += 1;
                }
                queue.push_back(r);
            }
        }
    }
    front.is_empty().then_some(out)
}

/// Whether the tetrahedron `[f, v]` crosses no face of `front` (other than
/// those it shares and closes from their inner side) and holds no vertex
/// of one (exact).
fn tet_clear(pts: &[P], front: &[[u32; 3]], f: [u32; 3], v: u32) -> bool {
    let tv = [f[0], f[1], f[2], v];
    let p = |w: u32| &pts[w as usize];
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for w in tv {
        for k in 0..3 {
            lo[k] = lo[k].min(p(w)[k]);
            hi[k] = hi[k].max(p(w)[k]);
        }
    }
    let own: [[u32; 3]; 4] = std::array::from_fn(|k| okey(face(tv, k)));
    let new_faces = [[v, f[0], f[1]], [v, f[1], f[2]], [v, f[2], f[0]]];
    for &g in front {
        let gk = okey(g);
        if gk == okey(f) {
            continue;
        }
        if own.contains(&gk) {
            // Closed from its inner side: fine.
            continue;
        }
        if own.contains(&rev(gk)) {
            // The tetrahedron would lie behind this front face.
            return false;
        }
        let out = (0..3)
            .any(|k| g.iter().all(|&w| p(w)[k] < lo[k]) || g.iter().all(|&w| p(w)[k] > hi[k]));
        if out {
            continue;
        }
        // A vertex of `g` strictly inside the tetrahedron.
        for w in g {
            if tv.contains(&w) {
                continue;
            }
            if (0..4).all(|k| sees(pts, face(tv, k), p(w))) {
                return false;
            }
        }
        if new_faces.iter().any(|&nf| triangles_intersect(pts, nf, g)) {
            return false;
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::super::{all_positive, fills_bounded};
    use super::*;
    use crate::geom::ids::IdSet;
    use delone_predicates::orient3d;

    /// `tris` oriented so that `inside` sees each strictly.
    fn inward(pts: &[P], tris: &[[u32; 3]], inside: &P) -> Vec<[u32; 3]> {
        tris.iter()
            .map(|&t| {
                let [a, b, c] = t.map(|w| &pts[w as usize]);
                if orient3d(a, b, c, inside) < 0.0 {
                    t
                } else {
                    [t[0], t[2], t[1]]
                }
            })
            .collect()
    }

    /// The tetrahedra are positive and tile exactly the region bounded by
    /// `faces` (the exact check every cavity replacement passes).
    fn tiles(pts: &[P], faces: &[[u32; 3]], tets: &[[u32; 4]]) -> bool {
        let bset: IdSet<[u32; 3]> = faces.iter().map(|&f| okey(f)).collect();
        all_positive(pts, tets) && fills_bounded(tets, &bset).is_some()
    }

    /// A prism over an `n`-gon (ellipse or regular): its points, the side
    /// quads split (every diagonal at vertex 0's side of the last quad, so
    /// the diagonals are not cyclic and the cone from vertex 0 fills it),
    /// each cap a fan from its first vertex.
    fn prism(n: u32, ellipse: f64, twist: f64) -> (Vec<P>, Vec<[u32; 3]>) {
        let mut pts = Vec::new();
        for z in 0..2 {
            for i in 0..n {
                let a =
                    2.0 * std::f64::consts::PI * f64::from(i) / f64::from(n) + twist * f64::from(z);
                pts.push([ellipse * a.cos(), a.sin(), f64::from(z)]);
            }
        }
        let mut tris = Vec::new();
        for i in 0..n {
            let j = (i + 1) % n;
            if j == 0 {
                tris.push([i, j, n + i]);
                tris.push([j, n + j, n + i]);
            } else {
                tris.push([i, j, n + j]);
                tris.push([i, n + j, n + i]);
            }
        }
        for i in 1..n - 1 {
            tris.push([0, i, i + 1]);
            tris.push([n, n + i, n + i + 1]);
        }
        (pts, tris)
    }

    /// Prisms with fan caps, over a regular polygon (cocircular points,
    /// ties decided by the perturbation) and over an ellipse (the fan
    /// triangles are not Delaunay: the Delaunay fill names faces it
    /// lacks): gift-wrapping either fills them exactly or reports failure
    /// (a constrained Delaunay tetrahedralization need not exist), never
    /// a wrong tiling; the triangular prism (its diagonals not cyclic) is
    /// filled.
    #[test]
    fn wraps_a_prism_or_refuses() {
        let (pts, tris) = prism(3, 1.0, 0.0);
        let faces = inward(&pts, &tris, &[0.0, 0.0, 0.5]);
        let tets = wrap_fill(&pts, &faces).expect("triangular prism");
        assert!(tiles(&pts, &faces, &tets));
        for n in [5, 8, 13] {
            for ellipse in [1.0, 4.0] {
                let (pts, tris) = prism(n, ellipse, 0.0);
                let faces = inward(&pts, &tris, &[0.0, 0.0, 0.5]);
                if let Some(tets) = wrap_fill(&pts, &faces) {
                    assert!(tiles(&pts, &faces, &tets), "n = {n}");
                }
            }
        }
    }

    /// A cube (eight cospherical points): the symbolic perturbation picks
    /// one Delaunay tetrahedralization; the fill succeeds when the cube's
    /// diagonals agree with it, and either way gift-wrapping fills it.
    #[test]
    fn fills_a_cube() {
        let (pts, tris) = crate::tet::dmesh::tests::cuboid(1.0, 1.0, 1.0);
        let faces = inward(&pts, &tris, &[0.5; 3]);
        let tets = wrap_fill(&pts, &faces).unwrap();
        assert!(tiles(&pts, &faces, &tets));
    }

    /// Schönhardt's twisted triangular prism has no tetrahedralization
    /// without a new point: both fills report failure instead of a wrong
    /// answer.
    #[test]
    fn schonhardt_prism_is_refused() {
        let (pts, mut tris) = prism(3, 1.0, 0.5);
        // Split each side quad along the diagonal that makes it reflex.
        for i in 0..3u32 {
            let j = (i + 1) % 3;
            tris[2 * i as usize] = [i, j, 3 + i];
            tris[2 * i as usize + 1] = [j, 3 + j, 3 + i];
        }
        let faces = inward(&pts, &tris, &[0.0, 0.0, 0.5]);
        if let Some(tets) = wrap_fill(&pts, &faces) {
            // Only a valid tiling may come back.
            assert!(tiles(&pts, &faces, &tets));
        }
    }
}
