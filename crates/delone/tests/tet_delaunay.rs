//! 3D Delaunay kernel: validity on random, degenerate and hostile inputs.

use delone::geom::SplitMix64;
use delone::tet::{validate, Delaunay3, Inserted};
use delone::{tetrahedralize, Error, NONE};

fn uniform(n: usize, seed: u64) -> Vec<[f64; 3]> {
    let mut r = SplitMix64::new(seed);
    let mut u = || (r.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
    (0..n).map(|_| [u(), u(), u()]).collect()
}

fn grid(k: usize) -> Vec<[f64; 3]> {
    let mut v = Vec::new();
    for x in 0..k {
        for y in 0..k {
            for z in 0..k {
                v.push([x as f64, y as f64, z as f64]);
            }
        }
    }
    v
}

/// Integer points exactly on the sphere x² + y² + z² = r2.
fn lattice_sphere(r2: i64) -> Vec<[f64; 3]> {
    let r = (r2 as f64).sqrt() as i64 + 1;
    let mut v = Vec::new();
    for x in -r..=r {
        for y in -r..=r {
            for z in -r..=r {
                if x * x + y * y + z * z == r2 {
                    v.push([x as f64, y as f64, z as f64]);
                }
            }
        }
    }
    v
}

fn check_all(pts: &[[f64; 3]]) -> delone::TetMesh {
    let dt = Delaunay3::from_points(pts).unwrap();
    dt.check_topology().unwrap();
    dt.check_delaunay().unwrap();
    let mesh = dt.into_mesh();
    validate(pts, &mesh).unwrap();
    mesh
}

#[test]
fn random_points_bulk() {
    for (n, seed) in [(5, 1), (6, 2), (50, 3), (1000, 4), (20_000, 5)] {
        let pts = uniform(n, seed);
        let mesh = check_all(&pts);
        assert!(mesh.duplicates.is_empty());
    }
}

#[test]
fn random_points_incremental_checked_after_every_insertion() {
    let pts = uniform(300, 11);
    let mut dt = Delaunay3::new();
    for (i, &p) in pts.iter().enumerate() {
        let r = dt.insert(p).unwrap();
        assert!(matches!(r, Inserted::Vertex(v) | Inserted::Pending(v) if v == i as u32));
        dt.check_topology().unwrap();
        dt.check_delaunay().unwrap();
    }
    let mesh = dt.into_mesh();
    validate(&pts, &mesh).unwrap();
}

#[test]
fn incremental_and_bulk_agree_on_tet_count() {
    // Random points are in general position: the Delaunay tetrahedralization
    // is unique, whatever the insertion order.
    let pts = uniform(2000, 12);
    let mut dt = Delaunay3::new();
    for &p in &pts {
        dt.insert(p).unwrap();
    }
    assert_eq!(
        tet_set(dt.tets()),
        tet_set(tetrahedralize(&pts).unwrap().tets)
    );
}

/// The tetrahedra as a sorted set of sorted vertex quadruples.
fn tet_set(tets: impl IntoIterator<Item = [u32; 4]>) -> Vec<[u32; 4]> {
    let mut v: Vec<[u32; 4]> = tets
        .into_iter()
        .map(|mut t| {
            t.sort_unstable();
            t
        })
        .collect();
    v.sort_unstable();
    v
}

#[test]
fn grids() {
    for k in [2, 3, 5, 12] {
        let pts = grid(k);
        let mesh = check_all(&pts);
        // A grid cube tetrahedralization has the volume of the cube.
        let vol: f64 = mesh
            .tets
            .iter()
            .map(|t| {
                let p = |i: usize| pts[t[i] as usize];
                let (a, b, c, d) = (p(0), p(1), p(2), p(3));
                let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
                let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
                let w = [d[0] - a[0], d[1] - a[1], d[2] - a[2]];
                (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
                    + u[2] * (v[0] * w[1] - v[1] * w[0]))
                    / 6.0
            })
            .sum();
        let side = (k - 1) as f64;
        assert!(
            (vol - side * side * side).abs() < 1e-9 * side * side * side,
            "k={k} vol={vol}"
        );
    }
}

#[test]
fn grid_incremental_checked_after_every_insertion() {
    let pts = grid(4);
    let mut dt = Delaunay3::new();
    for &p in &pts {
        dt.insert(p).unwrap();
        dt.check_topology().unwrap();
        dt.check_delaunay().unwrap();
    }
    validate(&pts, &dt.into_mesh()).unwrap();
}

#[test]
fn cospherical_lattice_points() {
    for r2 in [3, 9, 50, 4225] {
        let pts = lattice_sphere(r2);
        assert!(pts.len() >= 8, "r2={r2} gives {} points", pts.len());
        check_all(&pts);
        // With the centre added too.
        let mut with_centre = pts.clone();
        with_centre.push([0.0, 0.0, 0.0]);
        check_all(&with_centre);
    }
}

#[test]
fn duplicates_are_merged_and_reported() {
    let mut pts = uniform(500, 21);
    let copies: Vec<[f64; 3]> = pts.iter().step_by(7).copied().collect();
    pts.extend(copies.iter().copied());
    pts.extend(copies.iter().copied());
    let mesh = check_all(&pts);
    assert_eq!(mesh.duplicates.len(), 2 * copies.len());
    for &(d, o) in &mesh.duplicates {
        assert!(o < d);
        assert_eq!(pts[d as usize], pts[o as usize]);
        assert_eq!(mesh.vertex_map[d as usize], o);
    }
    // Duplicates placed *before* their originals in index order.
    let mut rev = copies.clone();
    rev.extend(uniform(500, 21));
    let mesh = check_all(&rev);
    assert_eq!(mesh.duplicates.len(), copies.len());
    assert!(mesh.duplicates.iter().all(|&(d, o)| o < d));
}

#[test]
fn scaled_and_translated_coordinates() {
    let base = uniform(2000, 31);
    for s in [1e-9, 1e-3, 1e9, 1e15] {
        let pts: Vec<[f64; 3]> = base.iter().map(|p| p.map(|c| c * s)).collect();
        check_all(&pts);
    }
    let pts: Vec<[f64; 3]> = base.iter().map(|p| p.map(|c| c + 1e6)).collect();
    check_all(&pts);
    let g: Vec<[f64; 3]> = grid(6).iter().map(|p| p.map(|c| c * 1e-9 + 1e-3)).collect();
    check_all(&g);
}

#[test]
fn degenerate_inputs_are_typed_errors() {
    assert_eq!(
        tetrahedralize(&[]).unwrap_err(),
        Error::TooFewPoints {
            found: 0,
            needed: 4
        }
    );
    let three = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    assert_eq!(
        tetrahedralize(&three).unwrap_err(),
        Error::TooFewPoints {
            found: 3,
            needed: 4
        }
    );
    let same = [[1.0, 2.0, 3.0]; 10];
    assert_eq!(
        tetrahedralize(&same).unwrap_err(),
        Error::TooFewPoints {
            found: 1,
            needed: 4
        }
    );
    let line: Vec<[f64; 3]> = (0..10)
        .map(|i| [i as f64, 2.0 * i as f64, 3.0 * i as f64])
        .collect();
    assert_eq!(
        tetrahedralize(&line).unwrap_err(),
        Error::Degenerate { dimension: 1 }
    );
    let plane: Vec<[f64; 3]> = (0..100)
        .map(|i| [(i % 10) as f64, (i / 10) as f64, 0.0])
        .collect();
    assert_eq!(
        tetrahedralize(&plane).unwrap_err(),
        Error::Degenerate { dimension: 2 }
    );
    let mut nan = uniform(10, 1);
    nan[7][1] = f64::NAN;
    assert_eq!(
        tetrahedralize(&nan).unwrap_err(),
        Error::InvalidCoordinate { index: 7 }
    );
    nan[7][1] = 0.5;
    nan[3][2] = f64::NEG_INFINITY;
    assert_eq!(
        tetrahedralize(&nan).unwrap_err(),
        Error::InvalidCoordinate { index: 3 }
    );
}

#[test]
fn coplanar_then_one_off_plane() {
    let mut pts: Vec<[f64; 3]> = (0..100)
        .map(|i| [(i % 10) as f64, (i / 10) as f64, 0.0])
        .collect();
    pts.push([4.5, 4.5, 1.0]);
    let mesh = check_all(&pts);
    assert!(mesh.tets.len() >= 81);
    // Incrementally, the coplanar points wait until the apex arrives.
    let mut dt = Delaunay3::new();
    for &p in &pts[..100] {
        assert!(matches!(dt.insert(p).unwrap(), Inserted::Pending(_)));
    }
    assert_eq!(dt.num_tets(), 0);
    dt.insert(pts[100]).unwrap();
    dt.check_topology().unwrap();
    dt.check_delaunay().unwrap();
    validate(&pts, &dt.into_mesh()).unwrap();
}

#[test]
fn collinear_and_coplanar_subsets_in_general_input() {
    // Many points on a few lines and planes, plus random ones.
    let mut pts = uniform(200, 41);
    for i in 0..50 {
        let t = i as f64 / 49.0;
        pts.push([t, t, t]);
        pts.push([t, 0.5, 0.0]);
        pts.push([(i % 7) as f64 / 6.0, (i / 7) as f64 / 7.0, 0.5]);
    }
    check_all(&pts);
}

#[test]
fn output_is_deterministic() {
    let pts = uniform(5000, 51);
    let a = tetrahedralize(&pts).unwrap();
    let b = tetrahedralize(&pts).unwrap();
    assert_eq!(a, b);
    let g = grid(6);
    assert_eq!(tetrahedralize(&g).unwrap(), tetrahedralize(&g).unwrap());
}

#[test]
fn neighbours_and_hull() {
    let pts = uniform(1000, 61);
    let mesh = tetrahedralize(&pts).unwrap();
    let hull = mesh
        .neighbors
        .iter()
        .flatten()
        .filter(|&&u| u == NONE)
        .count();
    assert_eq!(hull, mesh.hull_faces().count());
    assert!(hull >= 4);
}

#[test]
fn acceptance_grid_40_cubed() {
    let pts = grid(40);
    let mesh = check_all(&pts);
    assert!(mesh.tets.len() >= 5 * 39 * 39 * 39);
}

#[test]
fn points_on_a_sphere_and_a_cylinder() {
    // Floating-point points on a sphere are nearly cospherical: every
    // in-sphere test is close to zero, which exercises the exact stage.
    let n = 20_000;
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let sphere: Vec<[f64; 3]> = (0..n)
        .map(|i| {
            let z = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
            let r = (1.0 - z * z).sqrt();
            let t = golden * i as f64;
            [r * t.cos(), r * t.sin(), z]
        })
        .collect();
    check_all(&sphere);
    // Rings of cocircular points stacked along an axis.
    let mut cyl = Vec::new();
    for k in 0..20 {
        for (x, y) in [
            (3.0, 4.0),
            (-3.0, 4.0),
            (3.0, -4.0),
            (-3.0, -4.0),
            (5.0, 0.0),
            (-5.0, 0.0),
            (0.0, 5.0),
            (0.0, -5.0),
        ] {
            cyl.push([x, y, k as f64]);
        }
    }
    check_all(&cyl);
}

#[test]
fn huge_and_tiny_grids() {
    for s in [1e-9, 1e9] {
        let pts: Vec<[f64; 3]> = grid(8).iter().map(|p| p.map(|c| c * s)).collect();
        check_all(&pts);
    }
}

#[test]
fn degenerate_inputs_give_the_same_tets_whatever_the_insertion_order() {
    // Ties are broken by input index, not by insertion order: one-call (BRIO
    // order) and point-by-point (input order) builds agree on grids and
    // cospherical sets.
    for pts in [grid(5), lattice_sphere(50), {
        let mut g = grid(4);
        g.reverse();
        g
    }] {
        let mut dt = Delaunay3::new();
        for &p in &pts {
            dt.insert(p).unwrap();
        }
        assert_eq!(
            tet_set(dt.tets()),
            tet_set(tetrahedralize(&pts).unwrap().tets)
        );
    }
}

#[test]
fn extreme_magnitudes() {
    let base = uniform(500, 71);
    for s in [1e-300, 1e-150, 1e-80, 1e80, 1e150, 1e300] {
        let pts: Vec<[f64; 3]> = base.iter().map(|p| p.map(|c| c * s)).collect();
        let mesh = check_all(&pts);
        assert!(!mesh.tets.is_empty(), "scale {s}");
    }
    let g: Vec<[f64; 3]> = grid(5).iter().map(|p| p.map(|c| c * 1e-200)).collect();
    check_all(&g);
}

#[test]
fn random_small_degenerate_lattices() {
    // Points drawn from a 3x3x3 lattice: duplicates, collinear and coplanar
    // subsets and cospherical sets everywhere. Checked after every insertion,
    // and the one-call build validated and compared.
    let mut r = SplitMix64::new(81);
    for case in 0..300 {
        let n = 5 + r.below(36) as usize;
        let mut pts: Vec<[f64; 3]> = (0..n)
            .map(|_| [r.below(3) as f64, r.below(3) as f64, r.below(3) as f64])
            .collect();
        if case % 2 == 0 {
            // Half the cases without duplicates, so the order-independence
            // comparison below runs.
            let mut seen = Vec::new();
            pts.retain(|p| {
                let new = !seen.contains(p);
                seen.push(*p);
                new
            });
        }
        let mut dt = Delaunay3::new();
        for &p in &pts {
            dt.insert(p).unwrap();
            dt.check_topology()
                .unwrap_or_else(|v| panic!("case {case}: {v}"));
            dt.check_delaunay()
                .unwrap_or_else(|v| panic!("case {case}: {v}"));
        }
        let bulk = tetrahedralize(&pts);
        if dt.num_tets() == 0 {
            assert!(bulk.is_err(), "case {case}");
            continue;
        }
        let mesh = bulk.unwrap_or_else(|e| panic!("case {case}: {e}"));
        validate(&pts, &mesh).unwrap_or_else(|v| panic!("case {case}: {v}"));
        let inc = dt.into_mesh();
        validate(&pts, &inc).unwrap_or_else(|v| panic!("case {case}: {v}"));
        if !mesh.duplicates.is_empty() {
            // A duplicate group is perturbed under the id inserted first, which
            // depends on the order when the group is in a cospherical tie.
            continue;
        }
        assert_eq!(
            tet_set(inc.tets),
            tet_set(mesh.tets),
            "case {case}: order-dependent result"
        );
    }
}

#[test]
fn bulk_and_incremental_agree_on_vertex_map_duplicates_and_tets() {
    // The one-call build inserts copies in insertion order and relabels at
    // the end: same vertex map, duplicate list and tetrahedra as inserting
    // the points one by one, with ties (grid) and exact copies.
    let mut pts = grid(4);
    pts.extend(uniform(200, 5));
    pts.extend_from_within(100..130);
    let bulk = tetrahedralize(&pts).unwrap();
    let mut dt = Delaunay3::new();
    for &p in &pts {
        dt.insert(p).unwrap();
    }
    dt.check_topology().unwrap();
    dt.check_delaunay().unwrap();
    let inc = dt.into_mesh();
    assert_eq!(bulk.duplicates.len(), 30);
    assert_eq!(bulk.vertex_map, inc.vertex_map);
    assert_eq!(bulk.duplicates, inc.duplicates);
    assert_eq!(tet_set(bulk.tets), tet_set(inc.tets));
}

/// Large inputs insert their last BRIO round in spatial parts on the given
/// threads: the same mesh for 1 to 4 threads, valid, with the tetrahedra of
/// the point-by-point construction (which never uses parts).
#[test]
fn threads_give_the_same_mesh() {
    let mut cases = vec![uniform(90_000, 17), grid(45)];
    // Integer points on nested spheres: heavily cospherical.
    let mut shells = Vec::new();
    for r2 in [2000, 2500, 3000, 3600, 4100] {
        shells.extend(lattice_sphere(r2));
    }
    cases.push(shells);
    for pts in &cases {
        let one = Delaunay3::from_points_with_threads(pts, 1, &mut |_, _| {})
            .unwrap()
            .into_mesh();
        validate(pts, &one).unwrap();
        for threads in 2..=4 {
            let m = Delaunay3::from_points_with_threads(pts, threads, &mut |_, _| {})
                .unwrap()
                .into_mesh();
            assert!(m == one, "{} points: {threads} threads differ", pts.len());
            // Lent points: the same mesh, the points handed back unchanged.
            let mut lent = pts.clone();
            let dt = Delaunay3::from_points_in_place(&mut lent, threads, &mut |_, _| {}).unwrap();
            dt.check_topology().unwrap();
            dt.check_delaunay().unwrap();
            assert!(
                dt.into_mesh() == one,
                "{} points: in place differs",
                pts.len()
            );
            assert!(lent == *pts);
        }
        let mut inc = Delaunay3::new();
        for p in pts {
            inc.insert(*p).unwrap();
        }
        assert!(
            tet_set(inc.tets()) == tet_set(one.tets.iter().copied()),
            "{} points: not the tetrahedra of the incremental build",
            pts.len()
        );
    }
}

/// The in-place construction on inputs it handles apart: duplicates, extreme
/// magnitudes (copied and scaled), errors (the points are handed back as
/// they came in every case).
#[test]
fn in_place_construction_hands_the_points_back() {
    let mut dups = uniform(3000, 5);
    dups.extend_from_within(100..900);
    let huge: Vec<[f64; 3]> = uniform(2000, 6)
        .iter()
        .map(|p| p.map(|c| c * 1e200))
        .collect();
    let flat: Vec<[f64; 3]> = uniform(500, 7).iter().map(|p| [p[0], p[1], 0.0]).collect();
    let mut nan = uniform(100, 8);
    nan[50][1] = f64::NAN;
    for pts in [dups, huge, flat, nan, grid(12)] {
        let want = Delaunay3::from_points_with_threads(&pts, 2, &mut |_, _| {});
        let mut lent = pts.clone();
        let got = Delaunay3::from_points_in_place(&mut lent, 2, &mut |_, _| {});
        match (want, got) {
            (Ok(a), Ok(b)) => {
                b.check_topology().unwrap();
                assert_eq!(b.points(), a.points());
                let (a, b) = (a.into_mesh(), b.into_mesh());
                validate(&pts, &b).unwrap();
                assert!(a == b);
            }
            (Err(a), Err(b)) => assert_eq!(a, b),
            (a, b) => panic!("{:?} vs {:?}", a.map(|_| ()), b.map(|_| ())),
        }
        assert!(lent
            .iter()
            .zip(&pts)
            .all(|(a, b)| a.map(f64::to_bits) == b.map(f64::to_bits)));
    }
}
