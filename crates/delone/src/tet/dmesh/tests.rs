//! Each operation of [`DomainMesh`] on small hand-made meshes and on
//! degenerate ones (cospherical points, grid points, coplanar faces), with
//! [`DomainMesh::check`] after every operation.

use super::ring::{self, RingEnd};
use super::DomainMesh;
use crate::tet::local::{face, fkey, DEAD};
use crate::NONE;
use delone_predicates::orient3d;

/// The box `[0,w]×[0,d]×[0,h]`, two outward triangles per side.
pub(crate) fn cuboid(w: f64, d: f64, h: f64) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let pts = (0..8)
        .map(|i| {
            [
                f64::from(i & 1) * w,
                f64::from((i >> 1) & 1) * d,
                f64::from((i >> 2) & 1) * h,
            ]
        })
        .collect();
    let tris = vec![
        [0, 2, 1],
        [1, 2, 3],
        [4, 5, 6],
        [5, 7, 6],
        [0, 1, 4],
        [1, 5, 4],
        [2, 6, 3],
        [3, 6, 7],
        [0, 4, 2],
        [2, 4, 6],
        [1, 3, 5],
        [3, 7, 5],
    ];
    (pts, tris)
}

/// The octahedron `±x, ±y, ±z` (six cospherical points).
pub(crate) fn octahedron_points() -> Vec<[f64; 3]> {
    vec![
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
    ]
}

/// Three points around the z axis and two poles close to their plane: the
/// Delaunay tetrahedralization has exactly the three tetrahedra around the
/// edge between the poles (3 4), whose removal is the 3-2 flip.
pub(crate) fn three_around_an_edge() -> [[f64; 3]; 5] {
    let s = 3f64.sqrt() / 2.0;
    [
        [1.0, 0.0, 0.0],
        [-0.5, s, 0.0],
        [-0.5, -s, 0.0],
        [0.0, 0.0, 0.1],
        [0.0, 0.0, -0.1],
    ]
}

/// Per tetrahedron of `tets`, the tetrahedron across each face (found by
/// face keys), or [`NONE`].
pub(crate) fn neighbors_by_faces(tets: &[[u32; 4]]) -> Vec<[u32; 4]> {
    tets.iter()
        .enumerate()
        .map(|(t, tv)| {
            std::array::from_fn(|f| {
                let k = fkey(face(*tv, f));
                (0..tets.len())
                    .find(|&u| u != t && (0..4).any(|g| fkey(face(tets[u], g)) == k))
                    .map_or(NONE, |u| u as u32)
            })
        })
        .collect()
}

/// `tv` reordered to be positive on `p` (exact).
fn positive(p: &[[f64; 3]], mut tv: [u32; 4]) -> [u32; 4] {
    let g = |q: u32| &p[q as usize];
    if orient3d(g(tv[0]), g(tv[1]), g(tv[2]), g(tv[3])) > 0.0 {
        tv.swap(0, 1);
    }
    tv
}

/// A domain mesh of `tets` (made positive) in region 0, neighbours found by
/// face keys, every boundary face a subface.
fn mesh(p: &[[f64; 3]], tets: &[[u32; 4]]) -> DomainMesh {
    let tets: Vec<[u32; 4]> = tets.iter().map(|&t| positive(p, t)).collect();
    let nbs = neighbors_by_faces(&tets);
    let mut m = DomainMesh::from_neighbors(&tets, &nbs, &vec![0; tets.len()], p.len()).unwrap();
    for t in 0..tets.len() as u32 {
        for f in 0..4 {
            if m.nb[t as usize][f] == NONE {
                m.mark_face(t, f);
            }
        }
    }
    m.check(p).unwrap();
    m
}

/// The cone to vertex `c` of the boundary faces of `cav` (the whole mesh).
fn cone(m: &DomainMesh, cav: &[u32], c: u32) -> Vec<[u32; 4]> {
    let mut new = Vec::new();
    for &t in cav {
        for f in 0..4 {
            if m.nb[t as usize][f] == NONE {
                let [x, y, z] = face(m.tv[t as usize], f);
                new.push([x, y, z, c]);
            }
        }
    }
    new
}

/// The live tetrahedra as sorted vertex sets, sorted.
fn sets(m: &DomainMesh) -> Vec<[u32; 4]> {
    let mut v: Vec<[u32; 4]> = m
        .live_slots()
        .map(|t| {
            let mut x = m.tv[t as usize];
            x.sort_unstable();
            x
        })
        .collect();
    v.sort_unstable();
    v
}

/// Two tetrahedra on the triangle 0 1 2, apexes 3 (above) and 4 (below).
fn bipyramid() -> (Vec<[f64; 3]>, DomainMesh) {
    let p = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.3, 0.3, 1.0],
        [0.3, 0.3, -1.0],
    ];
    let m = mesh(&p, &[[0, 1, 2, 3], [0, 1, 2, 4]]);
    (p, m)
}

/// The live slot holding exactly the vertex set of `tv`.
fn slot(m: &DomainMesh, mut tv: [u32; 4]) -> u32 {
    tv.sort_unstable();
    m.live_slots()
        .find(|&t| {
            let mut x = m.tv[t as usize];
            x.sort_unstable();
            x == tv
        })
        .unwrap()
}

#[test]
fn flip23_then_32_by_replace() {
    let (p, mut m) = bipyramid();
    let t = slot(&m, [0, 1, 2, 3]);
    let f = m.tv[t as usize].iter().position(|&q| q == 3).unwrap();
    let u = m.across(t, f);
    assert_ne!(u, NONE);
    assert!(!m.is_sub(t, f));
    // 2-3: the three tetrahedra around the new edge 3 4.
    let [x, y, z] = face(m.tv[t as usize], f);
    let new: Vec<[u32; 4]> = [[x, y, 4, 3], [y, z, 4, 3], [z, x, 4, 3]]
        .iter()
        .map(|&n| positive(&p, n))
        .collect();
    let mut ids = Vec::new();
    let left = m.replace(&[t, u], &new, 0, &mut ids);
    assert!(left.gone.is_empty() && left.made.is_empty());
    assert_eq!(ids, vec![u, t, 2]);
    m.check(&p).unwrap();
    assert_eq!(m.live_slots().count(), 3);
    // 3-2 back: the ring of edge 3 4 and the DP's triangulation.
    let (tets, r, end) = m.edge_ring(ids[0], (3, 4), 16, false, |_, _| true).unwrap();
    assert_eq!(end, RingEnd::Closed);
    assert_eq!(tets.len(), 3);
    let (mut best, mut choice) = (Vec::new(), Vec::new());
    let v = ring::triangulate(
        r.len(),
        (i64::MAX, 0),
        &mut best,
        &mut choice,
        |_, _| (),
        |_, _, _, l, rr, cur, _| (l < i64::MAX && rr < i64::MAX && 1 < cur).then_some(1),
    );
    assert_eq!(v, 1);
    let back = ring::ring_tets(&r, &choice, 3, 4);
    assert_eq!(back.len(), 2);
    m.replace(&tets, &back, 0, &mut ids);
    m.check(&p).unwrap();
    assert_eq!(sets(&m), vec![[0, 1, 2, 3], [0, 1, 2, 4]]);
}

/// The octahedron `±x, ±y, ±z` (six cospherical points) as the four
/// tetrahedra around its axis 4 5: the 4-4 flip to the axis 0 1 (the DP
/// over the ring), then to the axis 2 3.
#[test]
fn four_four_flips_on_cospherical_points() {
    let p = octahedron_points();
    let mut m = mesh(
        &p,
        &[[0, 2, 4, 5], [2, 1, 4, 5], [1, 3, 4, 5], [3, 0, 4, 5]],
    );
    let (tets, r, end) = m.edge_ring(0, (4, 5), 16, false, |_, _| true).unwrap();
    assert_eq!((end, tets.len(), r.len()), (RingEnd::Closed, 4, 4));
    // Objective: forbid the chord 2 3 (keep the triangulation by 0 1).
    let (mut best, mut choice) = (Vec::new(), Vec::new());
    let rr = r.clone();
    let cost = ring::triangulate(
        4,
        (i64::MAX, 0),
        &mut best,
        &mut choice,
        |i, j| {
            let mut e = [rr[i], rr[j]];
            e.sort_unstable();
            i64::from(e == [2, 3])
        },
        |_, _, _, l, right, cur, &c| {
            if l == i64::MAX || right == i64::MAX {
                return None;
            }
            let v = l + right + c;
            (v < cur).then_some(v)
        },
    );
    assert_eq!(cost, 0);
    let new: Vec<[u32; 4]> = ring::ring_tets(&r, &choice, 4, 5)
        .into_iter()
        .map(|t| positive(&p, t))
        .collect();
    let mut ids = Vec::new();
    m.replace(&tets, &new, 0, &mut ids);
    m.check(&p).unwrap();
    assert!(sets(&m).iter().all(|t| t.contains(&0) && t.contains(&1)));
    // Every boundary face is still a subface, the octahedron's 8 faces.
    let bfaces: usize = m
        .live_slots()
        .map(|t| (0..4).filter(|&f| m.nb[t as usize][f] == NONE).count())
        .sum();
    assert_eq!(bfaces, 8);
}

/// Points of a 2×2×2 grid block (cube corners, coplanar in many ways): a
/// cone from the centre replaces the five tetrahedra of the cube, then a
/// visit marks and a star walk see all of them.
#[test]
fn cone_insertion_on_grid_points_and_star() {
    let mut p = cuboid(1.0, 1.0, 1.0).0;
    // The cube as five tetrahedra: the middle one 1 2 4 7 and four corners.
    let tets = [
        [1, 2, 4, 7],
        [0, 1, 2, 4],
        [3, 1, 2, 7],
        [5, 1, 4, 7],
        [6, 2, 4, 7],
    ];
    let mut m = mesh(&p, &tets);
    assert_eq!(m.live_slots().count(), 5);
    let cav: Vec<u32> = m.live_slots().collect();
    p.push([0.5, 0.5, 0.5]);
    let c = 8u32;
    let new = cone(&m, &cav, c);
    let mut ids = Vec::new();
    let left = m.replace(&cav, &new, 0, &mut ids);
    assert!(left.gone.is_empty() && left.made.is_empty());
    m.check(&p).unwrap();
    assert_eq!(m.live_slots().count(), 12);
    // Boundary subface bits carried over.
    assert!(ids.iter().all(|&t| m.is_sub(t, 3)));
    let star = m.star_with(c, |_, _| true);
    assert_eq!(star.len(), 12);
    // A star that may not cross anything is one tetrahedron.
    assert_eq!(m.star_with(c, |_, _| false).len(), 1);
    // Slots are reused last freed first.
    assert_eq!(&ids[..5], &[4, 3, 2, 1, 0]);
    assert!(m.free.is_empty());
}

/// Two tetrahedra on a flat square (coplanar boundary faces 0 1 2, 0 2 3
/// under the apex 4): the boundary 2-2 flip of the square's diagonal
/// replaces them by two on the other diagonal; the unmatched faces are
/// reported and the new ones marked.
#[test]
fn boundary_flip_on_coplanar_faces() {
    // The unit square (a cube's bottom, in order around it), the apex.
    let cube = cuboid(1.0, 1.0, 1.0).0;
    let mut p: Vec<[f64; 3]> = [0, 1, 3, 2].iter().map(|&i| cube[i]).collect();
    p.push([0.5, 0.4, 1.0]);
    let mut m = mesh(&p, &[[0, 1, 2, 4], [0, 2, 3, 4]]);
    let t = slot(&m, [0, 1, 2, 4]);
    let (tets, r, end) = m.edge_ring(t, (0, 2), 16, true, |_, _| true).unwrap();
    assert_eq!(end, RingEnd::Open);
    assert_eq!((tets.len(), r.len()), (2, 3));
    // Closed rings only: refused.
    assert!(m.edge_ring(t, (0, 2), 16, false, |_, _| true).is_none());
    let new = [positive(&p, [1, 3, 4, 0]), positive(&p, [1, 3, 4, 2])];
    let mut ids = Vec::new();
    let left = m.replace(&tets, &new, 0, &mut ids);
    let (mut gone, mut made) = (left.gone, left.made);
    gone.sort_unstable();
    made.sort_unstable();
    assert_eq!(gone, vec![[0, 1, 2], [0, 2, 3]]);
    assert_eq!(made, vec![[0, 1, 3], [1, 2, 3]]);
    m.check(&p).unwrap();
}

/// Subface tables: marks on both sides of an interface, the tables must
/// agree with the marks; the checker sees each kind of broken invariant.
#[test]
fn check_sees_broken_invariants() {
    let (p, m) = bipyramid();
    let t = slot(&m, [0, 1, 2, 3]);
    let f = m.tv[t as usize].iter().position(|&q| q == 3).unwrap();
    // An interface between two regions: marked on both sides.
    let mut a = m.clone();
    let u = a.across(t, f) as usize;
    a.reg[u] = 1;
    assert!(a.check(&p).unwrap_err().contains("region"));
    a.mark_face(t, f);
    a.check(&p).unwrap();
    // Tables: every subface listed, with its triangle.
    for s in a.live_slots().collect::<Vec<_>>() {
        for g in 0..4 {
            if a.is_sub(s, g) {
                a.ftri.insert(fkey(face(a.tv[s as usize], g)), 0);
            }
        }
    }
    a.check(&p).unwrap();
    a.segs.insert((0, 1), 0);
    a.check(&p).unwrap();
    a.segs.insert((3, 4), 0);
    assert!(a.check(&p).unwrap_err().contains("subsegment"));
    a.segs.remove(&(3, 4));
    a.ftri.remove(&[0, 1, 2]);
    assert!(a.check(&p).unwrap_err().contains("subface"));
    // A mark on one side only.
    let mut b = m.clone();
    b.mask[t as usize] |= 1 << f;
    assert!(b.check(&p).unwrap_err().contains("one side"));
    // A broken link.
    let mut c = m.clone();
    c.nb[t as usize][f] = NONE;
    assert!(c.check(&p).is_err());
    // An inverted tetrahedron.
    let mut d = m.clone();
    d.tv[t as usize].swap(0, 1);
    assert!(d.check(&p).is_err());
    // A dead slot not on the free list; a stale vertex hint.
    let mut e = m.clone();
    e.tv.push([DEAD; 4]);
    e.nb.push([NONE; 4]);
    e.mask.push(0);
    e.reg.push(0);
    assert!(e.check(&p).unwrap_err().contains("not free"));
    let mut h = m.clone();
    h.vt[3] = m.across(t, f);
    assert!(h.check(&p).unwrap_err().contains("hint"));
}

/// Large cavities match faces by hashing: the same mesh as by linear
/// search (a fan of many tetrahedra around an axis replaced by a cone).
#[test]
fn large_replace_matches_by_hashing() {
    let n = 40usize;
    let mut p: Vec<[f64; 3]> = vec![[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]];
    for i in 0..n {
        let a = std::f64::consts::TAU * i as f64 / n as f64;
        p.push([a.cos(), a.sin(), 0.0]);
    }
    let tets: Vec<[u32; 4]> = (0..n)
        .map(|i| [0, 1, 2 + i as u32, 2 + ((i + 1) % n) as u32])
        .collect();
    let mut m = mesh(&p, &tets);
    let cav: Vec<u32> = m.live_slots().collect();
    p.push([0.0, 0.0, 0.1]);
    let c = p.len() as u32 - 1;
    let new = cone(&m, &cav, c);
    assert!(new.len() > super::LINEAR);
    let mut ids = Vec::new();
    let left = m.replace(&cav, &new, 0, &mut ids);
    assert!(left.gone.is_empty() && left.made.is_empty());
    m.check(&p).unwrap();
    assert_eq!(m.star_with(c, |_, _| true).len(), 2 * n);
}

/// Refinement and optimisation of small closed surfaces, with the
/// structure's checker after every flip, insertion, replacement and move
/// ([`DomainMesh::debug_check`] runs in unit tests): a cube (merged
/// coplanar facets and not), the octahedron (cospherical points) and a box
/// whose faces are split at grid points.
#[test]
fn stages_keep_the_mesh_valid_after_every_operation() {
    use crate::tet::optimize::{optimize, optimize_in_place, OptimizeOptions};
    use crate::tet::recover::{
        check_recovered, recover_domain, recover_mesh, Domain, RecoverOptions, Recovered,
    };
    use crate::tet::refine::{refine, refine_in_place, RefineOptions};
    let (cube, cube_tris) = cuboid(1.0, 1.0, 1.0);
    let octa = octahedron_points();
    let mut octa_tris = Vec::new();
    for (x, y) in [(0u32, 2u32), (2, 1), (1, 3), (3, 0)] {
        octa_tris.push([x, y, 4]);
        octa_tris.push([y, x, 5]);
    }
    // A 2 × 1 × 1 box: the points of its long faces at x = 0, 1, 2.
    let mut boxp: Vec<[f64; 3]> = Vec::new();
    for x in 0..3 {
        for i in 0..4 {
            boxp.push([x as f64, (i & 1) as f64, ((i >> 1) & 1) as f64]);
        }
    }
    let id = |x: u32, i: u32| 4 * x + i;
    let mut box_tris = vec![
        [id(0, 0), id(0, 2), id(0, 1)],
        [id(0, 1), id(0, 2), id(0, 3)],
    ];
    box_tris.push([id(2, 0), id(2, 1), id(2, 2)]);
    box_tris.push([id(2, 1), id(2, 3), id(2, 2)]);
    for x in 0..2 {
        // The four long sides, as a cube's (0-1, 1-3, 3-2, 2-0 rings).
        for (i, j) in [(0, 1), (1, 3), (3, 2), (2, 0)] {
            let (a, b, c, d) = (id(x, i), id(x, j), id(x + 1, i), id(x + 1, j));
            box_tris.push([a, b, c]);
            box_tris.push([b, d, c]);
        }
    }
    for merge in [false, true] {
        for (pts, tris, vol) in [
            (&cube, &cube_tris, 0.01),
            (&octa, &octa_tris, 0.02),
            (&boxp, &box_tris, 0.02),
        ] {
            let recover = RecoverOptions {
                merge_coplanar: merge,
                ..Default::default()
            };
            let ro = RefineOptions {
                max_volume: Some(vol),
                recover,
                ..Default::default()
            };
            let mut r = refine(pts, tris, &ro).unwrap().rec;
            check_recovered(pts, tris, &r).unwrap();
            assert!(r.mesh.tets.len() > 20, "{}", r.mesh.tets.len());
            let opts = OptimizeOptions {
                input_points: Some(pts.len()),
                ..Default::default()
            };
            // In place: the mesh recovery carves and the refined mesh handed
            // over are the ones the next stage would build from the output's
            // lists, and going on in them gives the same result.
            let built = |r: &Recovered| {
                let mut m = DomainMesh::from_neighbors(
                    &r.mesh.tets,
                    &r.mesh.neighbors,
                    &r.tet_region,
                    r.points.len(),
                )
                .unwrap();
                m.mark_subfaces(&r.interior_faces.iter().map(|&f| fkey(f)).collect());
                m
            };
            let same = |m: &DomainMesh, b: &DomainMesh| {
                assert_eq!(
                    (&m.tv, &m.nb, &m.mask, &m.reg, &m.vt),
                    (&b.tv, &b.nb, &b.mask, &b.reg, &b.vt)
                );
                assert!(m.free.is_empty());
            };
            let rec0 = recover_domain(pts, tris, &ro.recover, &Domain::default()).unwrap();
            let (rec1, carved) =
                recover_mesh(pts, tris, &[], &ro.recover, &Domain::default()).unwrap();
            assert_eq!(rec1, rec0);
            carved.check(&rec1.points).unwrap();
            same(&carved, &built(&rec0));
            let (a0, _) = refine_in_place(pts, tris, &rec0, None, &ro).unwrap();
            let (mut a, mesh) = refine_in_place(pts, tris, &rec0, Some(carved), &ro).unwrap();
            assert_eq!(a.rec, r);
            assert_eq!(a0.rec, r);
            mesh.check(&a.rec.points).unwrap();
            same(&mesh, &built(&r));
            let ra = optimize_in_place(&mut a.rec, mesh, &opts).unwrap();
            let rb = optimize(&mut r, &opts).unwrap();
            check_recovered(pts, tris, &r).unwrap();
            assert_eq!((ra, &a.rec), (rb, &r));
        }
    }
}
