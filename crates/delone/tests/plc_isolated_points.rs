//! Isolated points of a PLC lying exactly on a facet or on a facet edge
//! become vertices of the facets' triangulations (TetGen's rule), so the
//! recovery conforms and the output has them on its boundary; a point of a
//! triangle soup lying on a triangle it is no vertex of is a typed error.

use delone::model::plc::{Facet, Plc};
use delone::tet::recover::{
    check_recovered, recover, recover_marked, Domain, RecoverError, RecoverOptions,
};

/// The unit cube of the issue's `.poly` (0-based): quadrilateral facets,
/// then the extra points.
fn cube_with(extra: &[[f64; 3]]) -> Plc {
    let mut pts = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
        [0.0, 1.0, 1.0],
    ];
    pts.extend_from_slice(extra);
    let mut plc = Plc::new(pts);
    for q in [
        [0, 1, 2, 3],
        [4, 5, 6, 7],
        [0, 1, 5, 4],
        [1, 2, 6, 5],
        [2, 3, 7, 6],
        [3, 0, 4, 7],
    ] {
        plc.facets.push(Facet::polygon(q.to_vec()));
    }
    plc
}

/// Every recovery path: with and without merging, and `-Y`.
fn paths() -> Vec<(&'static str, RecoverOptions)> {
    let d = RecoverOptions::default();
    vec![
        ("default", d.clone()),
        (
            "-M",
            RecoverOptions {
                merge_coplanar: false,
                ..d.clone()
            },
        ),
        (
            "-Y",
            RecoverOptions {
                preserve_surface: true,
                ..d
            },
        ),
    ]
}

/// Triangulates and recovers `plc` on every path, checks the result, and
/// asserts that each point of `on_surface` is a vertex of facet triangles,
/// of boundary faces and of tetrahedra, and each of `inside` a vertex of
/// tetrahedra only. Returns the facet triangles.
fn mesh(plc: &Plc, on_surface: &[u32], inside: &[u32]) -> Vec<[u32; 3]> {
    plc.validate().unwrap();
    let (tris, owner) = plc.triangulate_facets().unwrap();
    for &q in on_surface {
        assert!(
            tris.iter().any(|t| t.contains(&q)),
            "point {q} is no vertex of the facet triangles"
        );
    }
    let markers: Vec<i32> = owner.iter().map(|&f| f as i32 + 1).collect();
    for (name, o) in paths() {
        let r = recover_marked(&plc.points, &tris, &markers, &o, &Domain::default())
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        check_recovered(&plc.points, &tris, &r).unwrap_or_else(|v| panic!("{name}: {v:?}"));
        let vol: f64 = r.regions.iter().map(|g| g.volume).sum();
        assert!((vol - 1.0).abs() < 1e-12, "{name}: volume {vol}");
        for &q in on_surface {
            assert!(
                r.boundary.iter().any(|f| f.contains(&q)),
                "{name}: point {q} is on no boundary face"
            );
        }
        for &q in on_surface.iter().chain(inside) {
            assert!(
                r.mesh.tets.iter().any(|t| t.contains(&q)),
                "{name}: point {q} is no mesh vertex"
            );
        }
        for &q in inside {
            assert!(!r.boundary.iter().any(|f| f.contains(&q)), "{name}: {q}");
        }
    }
    tris
}

#[test]
fn point_inside_a_facet_is_a_vertex_of_it() {
    // The input: (0.5, 0.5, 0) in the middle of the bottom facet.
    let tris = mesh(&cube_with(&[[0.5, 0.5, 0.0]]), &[8], &[]);
    // The bottom square is cut into four triangles around it.
    assert_eq!(tris.iter().filter(|t| t.contains(&8)).count(), 4);
    assert_eq!(tris.len(), 14);
}

#[test]
fn point_on_an_edge_splits_it_in_both_facets() {
    // (0.5, 0, 0): on edge 0-1, shared by the bottom and the front facets.
    let tris = mesh(&cube_with(&[[0.5, 0.0, 0.0]]), &[8], &[]);
    let has_edge = |a: u32, b: u32| {
        tris.iter()
            .any(|t| (0..3).any(|k| [t[k], t[(k + 1) % 3]] == [a, b]))
    };
    // Both halves, in both directions (both facets), and never 0-1 whole.
    for (a, b) in [(0, 8), (8, 0), (8, 1), (1, 8)] {
        assert!(has_edge(a, b), "edge {a}-{b} missing");
    }
    assert!(!has_edge(0, 1) && !has_edge(1, 0));
}

#[test]
fn points_on_the_edges_at_a_cube_corner() {
    // On the vertical edge 0-4 and on edge 1-2, near corners.
    mesh(
        &cube_with(&[[0.0, 0.0, 0.5], [1.0, 0.25, 0.0]]),
        &[8, 9],
        &[],
    );
    // One right next to a corner, on the corner's three edges.
    let e = 1.0 / 1024.0;
    mesh(
        &cube_with(&[[e, 0.0, 0.0], [0.0, e, 0.0], [0.0, 0.0, e]]),
        &[8, 9, 10],
        &[],
    );
}

#[test]
fn point_equal_to_a_facet_corner_is_a_duplicate() {
    // Point 8 has the coordinates of corner 0: a duplicate point, left out
    // of the facets and of the mesh (as duplicates are), never a panic.
    let plc = cube_with(&[[0.0, 0.0, 0.0]]);
    let (tris, owner) = plc.triangulate_facets().unwrap();
    assert!(!tris.iter().flatten().any(|&q| q == 8));
    let markers: Vec<i32> = owner.iter().map(|&f| f as i32 + 1).collect();
    for (name, o) in paths() {
        let r = recover_marked(&plc.points, &tris, &markers, &o, &Domain::default())
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        check_recovered(&plc.points, &tris, &r).unwrap_or_else(|v| panic!("{name}: {v:?}"));
        assert!(!r.mesh.tets.iter().flatten().any(|&q| q == 8), "{name}");
        assert!(r.mesh.tets.iter().flatten().any(|&q| q == 0), "{name}");
    }
}

#[test]
fn several_points_on_one_facet_and_one_inside() {
    let plc = cube_with(&[
        // Three on the bottom's diagonal 0-2 (collinear with two corners).
        [0.25, 0.25, 0.0],
        [0.5, 0.5, 0.0],
        [0.75, 0.75, 0.0],
        // Two more inside the bottom, one on its edge 2-3.
        [0.75, 0.25, 0.0],
        [0.2, 0.6, 0.0],
        [0.5, 1.0, 0.0],
        // A second copy of (0.5, 0.5, 0): a duplicate, left out.
        [0.5, 0.5, 0.0],
        // Inside the cube: a mesh vertex, not on the boundary.
        [0.3, 0.4, 0.6],
        // On the bottom's plane but outside the cube: not inserted.
        [2.0, 0.5, 0.0],
    ]);
    let tris = mesh(&plc, &[8, 9, 10, 11, 12, 13], &[15]);
    assert!(!tris.iter().flatten().any(|&q| q == 14 || q == 16));
    // The triangles on the bottom facet (z = 0) still cover it: area 1.
    let area: f64 = tris
        .iter()
        .filter(|t| t.iter().all(|&q| plc.points[q as usize][2] == 0.0))
        .map(|t| {
            let [a, b, c] = t.map(|q| plc.points[q as usize]);
            ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])).abs() / 2.0
        })
        .sum();
    assert!((area - 1.0).abs() < 1e-12, "area {area}");
}

#[test]
fn stray_point_on_a_triangle_of_a_soup_is_a_typed_error() {
    // A triangle soup (the recover API): point 8 is in no triangle but lies
    // on bottom triangle 0 (inside), then on edge 0-2 (of triangles 0, 1).
    let plc = cube_with(&[]);
    let (tris, _) = plc.triangulate_facets().unwrap();
    let bottom = tris
        .iter()
        .position(|t| t.iter().all(|&q| plc.points[q as usize][2] == 0.0))
        .unwrap();
    let [a, b, c] = tris[bottom].map(|q| plc.points[q as usize]);
    let centroid = [0, 1, 2].map(|k| (a[k] + b[k] + c[k]) / 3.0);
    let mid = [0, 1, 2].map(|k| (a[k] + b[k]) / 2.0);
    for p in [centroid, mid] {
        // (Both have z = 0 exactly: on the triangle's plane.)
        let mut pts = plc.points.clone();
        pts.push(p);
        for (name, o) in paths() {
            match recover(&pts, &tris, &o) {
                Err(RecoverError::PointOnTriangle { point, triangle }) => {
                    assert_eq!(point, 8, "{name}");
                    assert!(tris[triangle].iter().all(|&q| pts[q as usize][2] == 0.0));
                }
                other => panic!("{name}: {other:?}"),
            }
        }
    }
    // Inside the volume or equal to a corner, a stray point is fine.
    for p in [[0.5, 0.5, 0.5], [1.0, 1.0, 1.0]] {
        let mut pts = plc.points.clone();
        pts.push(p);
        let r = recover(&pts, &tris, &RecoverOptions::default()).unwrap();
        check_recovered(&pts, &tris, &r).unwrap();
    }
}
