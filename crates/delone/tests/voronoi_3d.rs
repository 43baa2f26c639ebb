//! 3D Voronoi diagrams, clipped cells and Lloyd relaxation, checked against
//! brute force.
#![allow(clippy::needless_range_loop)]

use delone::geom::SplitMix64;
use delone::tet::voronoi::{Box3, ClippedCells3, Polyhedron};
use delone::tet::{lloyd, regular_tetrahedralization, Voronoi3};
use delone::NONE;

fn unit(r: &mut SplitMix64) -> f64 {
    (r.next_u64() >> 11) as f64 / (1u64 << 53) as f64
}

fn random(n: usize, seed: u64, lo: f64, hi: f64) -> Vec<[f64; 3]> {
    let mut r = SplitMix64::new(seed);
    (0..n)
        .map(|_| {
            [
                lo + (hi - lo) * unit(&mut r),
                lo + (hi - lo) * unit(&mut r),
                lo + (hi - lo) * unit(&mut r),
            ]
        })
        .collect()
}

fn sub(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn dist(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    let d = sub(a, b);
    dot(&d, &d).sqrt()
}

/// Newell normal of a polygon (twice its vector area).
fn newell(pts: &[[f64; 3]]) -> [f64; 3] {
    let mut n = [0.0; 3];
    for k in 0..pts.len() {
        let (a, b) = (pts[k], pts[(k + 1) % pts.len()]);
        n[0] += (a[1] - b[1]) * (a[2] + b[2]);
        n[1] += (a[2] - b[2]) * (a[0] + b[0]);
        n[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    n
}

/// Smallest signed distance from `x` to the faces' planes (positive inside).
fn inside_margin(poly: &Polyhedron, x: &[f64; 3]) -> f64 {
    let mut worst = f64::INFINITY;
    for f in &poly.faces {
        let pts: Vec<[f64; 3]> = f.iter().map(|&v| poly.vertices[v as usize]).collect();
        let n = newell(&pts);
        let len = dot(&n, &n).sqrt();
        if len < 1e-12 {
            continue;
        }
        worst = worst.min(-dot(&sub(x, &pts[0]), &n) / len);
    }
    worst
}

/// Volume by the divergence theorem, independent of the library.
fn volume(poly: &Polyhedron) -> f64 {
    poly.faces
        .iter()
        .map(|f| {
            let pts: Vec<[f64; 3]> = f.iter().map(|&v| poly.vertices[v as usize]).collect();
            dot(&newell(&pts), &pts[0]) / 6.0
        })
        .sum()
}

fn box_volume(b: Box3) -> f64 {
    (0..3).map(|k| b[1][k] - b[0][k]).product()
}

/// CVT energy: sum over cells of the integral of |x - site|² (tetrahedron
/// fans from the site, exact quadrature).
fn energy(sites: &[[f64; 3]], cells: &ClippedCells3) -> f64 {
    let mut e = 0.0;
    for (s, site) in sites.iter().enumerate() {
        let poly = &cells.cells[s];
        for f in &poly.faces {
            let v: Vec<[f64; 3]> = f
                .iter()
                .map(|&i| sub(&poly.vertices[i as usize], site))
                .collect();
            for k in 1..v.len() - 1 {
                let (a, b, c) = (v[0], v[k], v[k + 1]);
                let cr = [
                    b[1] * c[2] - b[2] * c[1],
                    b[2] * c[0] - b[0] * c[2],
                    b[0] * c[1] - b[1] * c[0],
                ];
                let vol = dot(&a, &cr) / 6.0;
                e += vol / 10.0
                    * (dot(&a, &a)
                        + dot(&b, &b)
                        + dot(&c, &c)
                        + dot(&a, &b)
                        + dot(&a, &c)
                        + dot(&b, &c));
            }
        }
    }
    e
}

fn check(pts: &[[f64; 3]], bbox: Box3, samples: usize) -> ClippedCells3 {
    let mesh = delone::tetrahedralize(pts).unwrap();
    let v = Voronoi3::new(pts, &mesh).unwrap();
    let size = (0..3).map(|k| bbox[1][k] - bbox[0][k]).fold(0.0, f64::max);
    // Voronoi vertices are equidistant from their tetrahedron's corners.
    for (t, tv) in mesh.tets.iter().enumerate() {
        let c = v.vertices[t];
        let d = tv.map(|q| dist(&c, &pts[q as usize]));
        for k in 1..4 {
            assert!((d[k] - d[0]).abs() <= 1e-9 * d[0], "tet {t}: {d:?}");
        }
    }
    // Counts: one edge per Delaunay triangle, one face per Delaunay edge.
    let hull = mesh
        .neighbors
        .iter()
        .flatten()
        .filter(|&&u| u == NONE)
        .count();
    assert_eq!(v.edges.len(), (4 * mesh.tets.len() + hull) / 2);
    assert_eq!(v.edges.iter().filter(|e| e.is_ray()).count(), hull);
    let mut dedges: Vec<(u32, u32)> = mesh
        .tets
        .iter()
        .flat_map(|tv| {
            (0..4).flat_map(move |i| (i + 1..4).map(move |j| (tv[i].min(tv[j]), tv[i].max(tv[j]))))
        })
        .collect();
    dedges.sort_unstable();
    dedges.dedup();
    let mut vedges: Vec<(u32, u32)> = v
        .faces
        .iter()
        .map(|f| (f.sites[0].min(f.sites[1]), f.sites[0].max(f.sites[1])))
        .collect();
    vedges.sort_unstable();
    assert_eq!(vedges, dedges);
    let on_hull: Vec<bool> = {
        let mut h = vec![false; pts.len()];
        for f in mesh.hull_faces() {
            for q in f {
                h[q as usize] = true;
            }
        }
        h
    };
    // Faces: vertices around the Delaunay edge, on its bisector, in counterclockwise order.
    for fi in 0..v.faces.len() {
        let f = v.face(fi);
        let [a, b] = f.sites.map(|s| pts[s as usize]);
        let axis = sub(&b, &a);
        for &t in f.vertices {
            let c = v.vertices[t as usize];
            let (da, db) = (dist(&c, &a), dist(&c, &b));
            assert!((da - db).abs() <= 1e-9 * da, "face {fi}");
        }
        assert_eq!(
            f.rays.is_some(),
            on_hull[f.sites[0] as usize] && on_hull[f.sites[1] as usize] && {
                // a hull edge has a hull triangle through it
                mesh.hull_faces()
                    .any(|h| h.contains(&f.sites[0]) && h.contains(&f.sites[1]))
            }
        );
        if f.rays.is_none() && f.vertices.len() >= 3 {
            let poly: Vec<[f64; 3]> = f.vertices.iter().map(|&t| v.vertices[t as usize]).collect();
            let n = newell(&poly);
            assert!(
                dot(&n, &axis) >= -1e-9 * dot(&axis, &axis) * size,
                "face {fi} orientation"
            );
        }
        if let Some([r0, r1]) = f.rays {
            // Rays point away from the Delaunay edge's other tetrahedra: outward.
            for r in [r0, r1] {
                assert!(
                    dot(&r, &axis).abs() <= 1e-9 * dot(&r, &r).sqrt() * dot(&axis, &axis).sqrt()
                );
                // Every point lies behind the outward hull plane through a.
                for p in pts {
                    assert!(
                        dot(&r, &sub(p, &a)) <= 1e-9 * dot(&r, &r).sqrt() * size,
                        "face {fi}: ray not outward"
                    );
                }
            }
        }
    }
    // Cells: bounded iff interior; bounded cells are convex (every Voronoi
    // vertex of the cell is on the site's side of every bisector).
    for s in 0..pts.len() {
        let r = mesh.vertex_map[s] as usize;
        assert_eq!(v.is_unbounded(s), on_hull[r]);
        if on_hull[r] {
            continue;
        }
        let nbs: Vec<u32> = v.neighbors(s).collect();
        for &f in v.cell_faces(s) {
            let face = v.face(f as usize);
            assert!(face.rays.is_none());
            for &t in face.vertices {
                let c = v.vertices[t as usize];
                let ds = dist(&c, &pts[r]);
                for &q in &nbs {
                    assert!(
                        ds <= dist(&c, &pts[q as usize]) + 1e-9 * size,
                        "cell {s} not convex"
                    );
                }
            }
        }
    }
    // Clipped cells tile the box.
    let c = v.cells_clipped(pts, bbox);
    let mut total = 0.0;
    for s in 0..pts.len() {
        let vol = volume(&c.cells[s]);
        assert!(
            (vol - c.volume[s]).abs() <= 1e-9 * box_volume(bbox),
            "cell {s}: {vol} vs {}",
            c.volume[s]
        );
        if mesh.vertex_map[s] as usize == s {
            total += c.volume[s];
        }
        if c.volume[s] > 0.0 {
            assert!(inside_margin(&c.cells[s], &c.centroid[s]) >= -1e-9 * size);
        }
    }
    let rel = (total - box_volume(bbox)).abs() / box_volume(bbox);
    assert!(
        rel <= 1e-9,
        "volumes sum to {total}, box {}",
        box_volume(bbox)
    );
    // Samples lie in the clipped cell of a nearest site.
    let mut rng = SplitMix64::new(9);
    for _ in 0..samples {
        let x: [f64; 3] =
            std::array::from_fn(|k| bbox[0][k] + (bbox[1][k] - bbox[0][k]) * unit(&mut rng));
        let best = pts
            .iter()
            .map(|p| dist(p, &x))
            .fold(f64::INFINITY, f64::min);
        let mut found = false;
        for s in 0..pts.len() {
            if mesh.vertex_map[s] as usize != s || c.cells[s].faces.is_empty() {
                continue;
            }
            let m = inside_margin(&c.cells[s], &x);
            let d = dist(&x, &pts[s]);
            if m > 1e-9 * size {
                assert!(
                    d - best <= 1e-9 * size,
                    "sample {x:?} in cell {s} but a site is closer"
                );
            }
            if m >= -1e-9 * size && d - best <= 1e-9 * size {
                found = true;
            }
        }
        assert!(found, "sample {x:?} is in no nearest site's cell");
    }
    c
}

#[test]
fn random_points_in_cube() {
    check(&random(300, 1, 0.0, 1.0), [[0.0; 3], [1.0; 3]], 1000);
}

#[test]
fn sites_outside_and_offset_box() {
    check(&random(200, 2, -0.5, 1.5), [[0.0; 3], [1.0; 3]], 500);
    check(
        &random(200, 3, 10.0, 11.0),
        [[9.8, 10.2, 10.0], [11.5, 10.9, 10.7]],
        500,
    );
}

#[test]
fn grid_is_cospherical() {
    let pts: Vec<[f64; 3]> = (0..216)
        .map(|k| [(k % 6) as f64, (k / 6 % 6) as f64, (k / 36) as f64])
        .collect();
    let bbox = [[-0.5; 3], [5.5; 3]];
    let c = check(&pts, bbox, 300);
    for s in 0..pts.len() {
        assert!(
            (c.volume[s] - 1.0).abs() < 1e-12,
            "cell {s}: {}",
            c.volume[s]
        );
        assert!(dist(&c.centroid[s], &pts[s]) < 1e-12);
    }
}

#[test]
fn cospherical_with_centre_and_duplicates() {
    // Cube corners and octahedron vertices on one sphere, its centre, duplicates.
    let mut pts: Vec<[f64; 3]> = (0..8)
        .map(|k| {
            let s = 1.0 / 3f64.sqrt();
            [
                if k & 1 == 0 { -s } else { s },
                if k & 2 == 0 { -s } else { s },
                if k & 4 == 0 { -s } else { s },
            ]
        })
        .collect();
    for k in 0..3 {
        for sgn in [-1.0, 1.0] {
            let mut p = [0.0; 3];
            p[k] = sgn;
            pts.push(p);
        }
    }
    pts.push([0.0; 3]);
    pts.push(pts[2]);
    pts.push([0.0; 3]);
    let c = check(&pts, [[-2.0; 3], [2.0; 3]], 1000);
    assert_eq!(c.cells[15], c.cells[2]);
    assert_eq!(c.volume[16], c.volume[14]);
}

#[test]
fn lloyd_energy_decreases() {
    let bbox = [[0.0; 3], [1.0; 3]];
    let mut pts = random(100, 11, 0.0, 1.0);
    let mut prev = f64::INFINITY;
    let mut first = 0.0;
    for it in 0..10 {
        let mesh = delone::tetrahedralize(&pts).unwrap();
        let e = energy(
            &pts,
            &Voronoi3::new(&pts, &mesh)
                .unwrap()
                .cells_clipped(&pts, bbox),
        );
        if it == 0 {
            first = e;
        }
        assert!(e <= prev * (1.0 + 1e-12), "iteration {it}: {e} > {prev}");
        prev = e;
        pts = lloyd(&pts, bbox, 1).unwrap();
    }
    assert!(prev < 0.95 * first, "energy {first} -> {prev}");
}

// Power diagrams (duals of regular tetrahedralizations).

#[test]
fn power_cells_tile_the_box_and_contain_their_points() {
    for (n, seed, spread) in [(40, 1, 0.2), (300, 2, 0.05), (2000, 3, 0.01)] {
        let mut r = SplitMix64::new(seed);
        let pts: Vec<[f64; 3]> = (0..n)
            .map(|_| [unit(&mut r), unit(&mut r), unit(&mut r)])
            .collect();
        let ws: Vec<f64> = (0..n).map(|_| spread * unit(&mut r)).collect();
        let mesh = regular_tetrahedralization(&pts, &ws).unwrap();
        assert!(
            !mesh.hidden.is_empty() || n > 1000,
            "n={n}: expect hidden points"
        );
        let v = Voronoi3::new_power(&pts, &ws, &mesh).unwrap();
        let bbox = [[-0.5; 3], [1.5; 3]];
        let cells = v.cells_clipped(&pts, bbox);
        let total: f64 = cells.volume.iter().sum();
        assert!(
            (total - 8.0).abs() < 1e-9 * 8.0,
            "n={n}: volumes sum to {total}"
        );
        for &h in &mesh.hidden {
            assert_eq!(cells.volume[h as usize], 0.0, "hidden {h} has a cell");
            assert!(v.cell_faces(h as usize).is_empty());
        }
        // Sampled points lie in the cell of a site of least power distance.
        let power = |x: &[f64; 3], i: usize| {
            let d = sub(x, &pts[i]);
            dot(&d, &d) - ws[i]
        };
        for _ in 0..300 {
            let x = [
                -0.5 + 2.0 * unit(&mut r),
                -0.5 + 2.0 * unit(&mut r),
                -0.5 + 2.0 * unit(&mut r),
            ];
            let best = (0..n).map(|i| power(&x, i)).fold(f64::INFINITY, f64::min);
            let found = (0..n)
                .filter(|&i| power(&x, i) <= best + 1e-9)
                .any(|i| inside_margin(&cells.cells[i], &x) > -1e-9);
            assert!(found, "n={n}: sample {x:?} is in no cell of least power");
        }
    }
}

#[test]
fn zero_weights_give_the_voronoi_diagram() {
    let mut r = SplitMix64::new(9);
    let pts: Vec<[f64; 3]> = (0..200)
        .map(|_| [unit(&mut r), unit(&mut r), unit(&mut r)])
        .collect();
    let zero = vec![0.0; pts.len()];
    let mesh = regular_tetrahedralization(&pts, &zero).unwrap();
    let a = Voronoi3::new_power(&pts, &zero, &mesh).unwrap();
    let b = Voronoi3::new(&pts, &delone::tetrahedralize(&pts).unwrap()).unwrap();
    assert_eq!(a.vertices, b.vertices);
    assert_eq!(a.faces, b.faces);
    let bbox = [[0.0; 3], [1.0; 3]];
    assert_eq!(
        a.cells_clipped(&pts, bbox).volume,
        b.cells_clipped(&pts, bbox).volume
    );
}

#[test]
fn a_mesh_of_other_points_is_an_error_not_a_panic() {
    let pts = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
    ];
    let mesh = delone::tetrahedralize(&pts).unwrap();
    let err = Voronoi3::new(&pts[..4], &mesh).unwrap_err();
    assert!(
        matches!(err, delone::Error::InconsistentMesh { .. }),
        "{err}"
    );
    let mut broken = mesh.clone();
    broken.neighbors.pop();
    assert!(Voronoi3::new(&pts, &broken).is_err());
}

/// A bad vertex or neighbour id deep inside a mesh big enough for two
/// threads: the same error as the serial check (cell and id named), for the
/// plain and the power diagram, whatever the thread count.
#[test]
fn bad_ids_in_a_large_mesh_are_named() {
    let pts = random(6000, 17, 0.0, 1.0);
    let mesh = delone::tetrahedralize(&pts).unwrap();
    let nt = mesh.tets.len();
    assert!(nt >= 1 << 15, "{nt} tetrahedra: too few for two chunks");
    let w = vec![0.0; pts.len()];
    let t = nt - 5;
    let mut bad_vertex = mesh.clone();
    bad_vertex.tets[t][2] = pts.len() as u32;
    let mut bad_neighbour = mesh.clone();
    bad_neighbour.neighbors[t][1] = nt as u32;
    for (m, want) in [
        (&bad_vertex, format!("cell {t} names point {}", pts.len())),
        (&bad_neighbour, format!("cell {t} names neighbour {nt}")),
    ] {
        for threads in [1, 2] {
            let e = Voronoi3::with_threads(&pts, m, threads).unwrap_err();
            assert!(e.to_string().contains(&want), "{e}");
            let e = Voronoi3::power_with_threads(&pts, &w, m, threads).unwrap_err();
            assert!(e.to_string().contains(&want), "{e}");
        }
        let e = Voronoi3::with_phase_times(&pts, m, 2).unwrap_err();
        assert!(e.to_string().contains(&want), "{e}");
    }
    // A NONE neighbour is fine, and the intact mesh passes.
    assert!(Voronoi3::with_threads(&pts, &mesh, 2).is_ok());
}

/// Meshes of 2^15 tetrahedra or more are walked in Morton order: the same
/// checks, plus the face–edge incidences and the edge ends.
#[test]
fn large_mesh_in_morton_order() {
    let pts = random(6000, 11, 0.0, 1.0);
    let mesh = delone::tetrahedralize(&pts).unwrap();
    assert!(mesh.tets.len() >= 1 << 15, "{} tets", mesh.tets.len());
    check(&pts, [[0.0; 3], [1.0; 3]], 60);
    let v = Voronoi3::new(&pts, &mesh).unwrap();
    // Edge e joins the two tetrahedra sharing its triangle.
    for (e, ed) in v.edges.iter().enumerate() {
        let mut s = ed.sites;
        s.sort_unstable();
        for &t in &ed.vertices {
            if t == NONE {
                continue;
            }
            let tv = mesh.tets[t as usize];
            assert!(s.iter().all(|x| tv.contains(x)), "edge {e}");
        }
        if ed.vertices[1] != NONE {
            let [a, b] = ed.vertices.map(|t| t as usize);
            assert!(mesh.neighbors[a].contains(&(b as u32)), "edge {e}");
        }
    }
    // Every vertex's edges are the duals of its tetrahedron's facets, in
    // slot order (the edge's triangle is the facet off slot i, and the
    // tetrahedron is one of its ends).
    assert_eq!(v.vertex_edges.len(), mesh.tets.len());
    for (t, row) in v.vertex_edges.iter().enumerate() {
        for (i, &e) in row.iter().enumerate() {
            let ed = v.edges[e as usize];
            let mut want: Vec<u32> = (0..4)
                .filter(|&j| j != i)
                .map(|j| mesh.tets[t][j])
                .collect();
            let mut got = ed.sites.to_vec();
            want.sort_unstable();
            got.sort_unstable();
            assert_eq!(got, want, "vertex {t} slot {i}");
            assert!(ed.vertices.contains(&(t as u32)), "vertex {t} slot {i}");
        }
    }
    // Face edges join consecutive face vertices; open faces start and end with rays.
    for f in 0..v.faces.len() {
        let face = v.face(f);
        let m = face.vertices.len();
        let open = face.rays.is_some();
        assert_eq!(face.edges.len(), m + usize::from(open));
        let all: Vec<u32> = face.edges.collect();
        assert_eq!(all.len(), m + usize::from(open));
        let inner = if open { &all[1..m] } else { &all[..] };
        for (k, &e) in inner.iter().enumerate() {
            let ends = v.edges[e as usize].vertices;
            let (x, y) = (face.vertices[k], face.vertices[(k + 1) % m]);
            assert!(ends == [x, y] || ends == [y, x], "face {f} edge {k}");
        }
        if open {
            let (a, b) = (all[0] as usize, all[m] as usize);
            assert_eq!(v.edges[a].vertices, [face.vertices[0], NONE]);
            assert_eq!(v.edges[b].vertices, [face.vertices[m - 1], NONE]);
            assert_ne!(v.direction(a), [0.0; 3]);
        }
    }
}

/// The chunked multi-thread extraction gives the same diagram bit for bit
/// whatever the thread count, and the same as one thread: for Voronoi and
/// power diagrams, on meshes large enough to be cut into several chunks
/// (2^14 tetrahedra each at least), with and without the Morton order.
#[test]
fn any_thread_count_gives_the_same_diagram() {
    for (n, seed) in [(3000, 5), (9000, 6)] {
        let pts = random(n, seed, -1.0, 2.0);
        let mesh = delone::tetrahedralize(&pts).unwrap();
        let one = Voronoi3::with_threads(&pts, &mesh, 1).unwrap();
        assert_eq!(one.vertices.len(), mesh.tets.len());
        for threads in [2, 3, 5] {
            let many = Voronoi3::with_threads(&pts, &mesh, threads).unwrap();
            assert!(one == many, "n {n}, {threads} threads");
            assert_eq!(
                one.vertices
                    .iter()
                    .map(|x| x.map(f64::to_bits))
                    .collect::<Vec<_>>(),
                many.vertices
                    .iter()
                    .map(|x| x.map(f64::to_bits))
                    .collect::<Vec<_>>()
            );
        }
        let mut r = SplitMix64::new(seed + 100);
        let ws: Vec<f64> = (0..n).map(|_| 0.01 * unit(&mut r)).collect();
        let reg = regular_tetrahedralization(&pts, &ws).unwrap();
        let one = Voronoi3::power_with_threads(&pts, &ws, &reg, 1).unwrap();
        for threads in [2, 4] {
            let many = Voronoi3::power_with_threads(&pts, &ws, &reg, threads).unwrap();
            assert!(one == many, "power, n {n}, {threads} threads");
        }
    }
}

/// A mesh whose neighbour links are broken (not a tetrahedralization, but
/// within range) gives some diagram, deterministically for each thread
/// count, and no panic. (Bit-identity across thread counts is promised for
/// valid meshes only.)
#[test]
fn broken_neighbour_links_do_not_panic() {
    let pts = random(9000, 8, 0.0, 1.0);
    let mut mesh = delone::tetrahedralize(&pts).unwrap();
    let nt = mesh.tets.len() as u32;
    let mut r = SplitMix64::new(3);
    for _ in 0..200 {
        let t = (r.next_u64() % nt as u64) as usize;
        let f = (r.next_u64() % 4) as usize;
        mesh.neighbors[t][f] = (r.next_u64() % nt as u64) as u32;
    }
    for threads in [1, 2, 3] {
        let a = Voronoi3::with_threads(&pts, &mesh, threads).unwrap();
        let b = Voronoi3::with_threads(&pts, &mesh, threads).unwrap();
        assert!(a == b, "{threads} threads");
        assert_eq!(a.vertices.len(), mesh.tets.len());
    }
}
