//! Tests of the 2D Delaunay kernel: every output goes through the independent
//! `validate`, incremental builds through `check_topology`/`check_delaunay`.

use std::path::PathBuf;

use delone::geom::SplitMix64;
use delone::tri::{validate, Delaunay2, Inserted, Location, TriMesh};
use delone::{triangulate, Error};

fn unit(r: &mut SplitMix64) -> f64 {
    (r.next_u64() >> 11) as f64 / (1u64 << 53) as f64
}

fn random_points(n: usize, seed: u64) -> Vec<[f64; 2]> {
    let mut r = SplitMix64::new(seed);
    (0..n).map(|_| [unit(&mut r), unit(&mut r)]).collect()
}

fn grid(nx: usize, ny: usize) -> Vec<[f64; 2]> {
    let mut v = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            v.push([i as f64, j as f64]);
        }
    }
    v
}

fn shuffle<T>(v: &mut [T], seed: u64) {
    let mut r = SplitMix64::new(seed);
    for i in (1..v.len()).rev() {
        let j = r.below(i as u32 + 1) as usize;
        v.swap(i, j);
    }
}

/// Triangulates, validates independently, and checks the kernel's own
/// invariants on the same input.
fn check_all(points: &[[f64; 2]]) -> TriMesh {
    let d = Delaunay2::from_points(points).expect("triangulation");
    d.check_topology().expect("topology");
    d.check_delaunay().expect("delaunay");
    let nt = d.num_triangles();
    let mesh = d.into_mesh();
    assert_eq!(mesh.triangles.len(), nt);
    validate(points, &mesh).expect("validate");
    mesh
}

/// Triangles with their smallest vertex first, sorted: comparable across
/// builds whatever the slot order.
fn canonical(tris: impl IntoIterator<Item = [u32; 3]>) -> Vec<[u32; 3]> {
    let mut v: Vec<[u32; 3]> = tris
        .into_iter()
        .map(|t| {
            let k = (0..3).min_by_key(|&k| t[k]).unwrap();
            [t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
        })
        .collect();
    v.sort_unstable();
    v
}

/// Finds `shared/data` above the crate (the main checkout has it three levels
/// up, a worktree deeper).
fn data_dir() -> Option<PathBuf> {
    delone_testdata::corpus_dir(env!("CARGO_MANIFEST_DIR"))
}

/// A minimal reader of Triangle's `.node` format (comments, header, then
/// `index x y [attributes] [marker]`).
fn parse_node(text: &str) -> Vec<[f64; 2]> {
    let mut lines = text
        .lines()
        .map(|l| l.split('#').next().unwrap().trim())
        .filter(|l| !l.is_empty());
    let header: Vec<usize> = lines
        .next()
        .expect("header")
        .split_whitespace()
        .map(|w| w.parse().expect("header number"))
        .collect();
    let n = header[0];
    assert_eq!(header[1], 2, "2D .node expected");
    let pts: Vec<[f64; 2]> = lines
        .take(n)
        .map(|l| {
            let w: Vec<f64> = l
                .split_whitespace()
                .skip(1)
                .take(2)
                .map(|x| x.parse().expect("coordinate"))
                .collect();
            [w[0], w[1]]
        })
        .collect();
    assert_eq!(pts.len(), n);
    pts
}

#[test]
fn shared_node_files() {
    let Some(dir) = data_dir() else {
        println!("note: shared/data not found; skipping the .node inputs");
        return;
    };
    // Every .node of 2d/points, the vertex sections of the 2d .poly files
    // (same layout), and the repository's own example.
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir.join("2d/points"))
        .expect("2d/points")
        .chain(std::fs::read_dir(dir.join("2d")).expect("2d"))
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "node" || e == "poly"))
        .collect();
    files.sort();
    let example = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/spiral_grid.node");
    if example.is_file() {
        files.push(example);
    }
    assert!(!files.is_empty());
    for f in files {
        let pts = parse_node(&std::fs::read_to_string(&f).unwrap());
        let mesh = check_all(&pts);
        println!(
            "{}: {} points, {} triangles",
            f.display(),
            pts.len(),
            mesh.triangles.len()
        );
    }
}

#[test]
fn uniform_random() {
    for (n, seed) in [(10, 1), (100, 2), (1000, 3), (20_000, 4)] {
        let pts = random_points(n, seed);
        let mesh = check_all(&pts);
        assert!(mesh.duplicates.is_empty());
    }
}

#[test]
fn matches_brute_force_empty_circles() {
    // Every triangle's circumcircle is empty of all points (not only the
    // neighbours' apexes), and the count matches Euler for points in general
    // position.
    let pts = random_points(300, 11);
    let mesh = check_all(&pts);
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|x| pts[x as usize]);
        for (k, p) in pts.iter().enumerate() {
            if t.contains(&(k as u32)) {
                continue;
            }
            assert!(
                delone_predicates::incircle(&a, &b, &c, p) <= 0.0,
                "{t:?} contains {k}"
            );
        }
    }
}

#[test]
fn big_grid() {
    let pts = grid(300, 300);
    let mesh = check_all(&pts);
    assert_eq!(mesh.triangles.len(), 2 * 299 * 299);
}

#[test]
fn small_grid_one_by_one() {
    for (seed, shuffled) in [(0, false), (5, true), (6, true)] {
        let mut pts = grid(12, 9);
        if shuffled {
            shuffle(&mut pts, seed);
        }
        let mut d = Delaunay2::new();
        for (k, &p) in pts.iter().enumerate() {
            let r = d.insert(p).unwrap();
            if d.num_triangles() == 0 {
                assert_eq!(r, Inserted::Pending(k as u32));
            } else {
                assert_eq!(r, Inserted::Vertex(k as u32));
            }
            d.check_topology()
                .unwrap_or_else(|v| panic!("after point {k}: {v}"));
            d.check_delaunay()
                .unwrap_or_else(|v| panic!("after point {k}: {v}"));
        }
        assert_eq!(d.num_triangles(), 2 * 11 * 8);
        let mesh = d.into_mesh();
        validate(&pts, &mesh).unwrap();
    }
}

/// All integer points on the circle of radius 5^2*13*17*29*37 (1620 points):
/// exactly cocircular, and too large for non-exact arithmetic.
fn lattice_circle() -> Vec<[f64; 2]> {
    let r: i64 = 25 * 13 * 17 * 29 * 37;
    let r2 = r * r;
    let mut pts = Vec::new();
    for x in -r..=r {
        let y2 = r2 - x * x;
        let y = (y2 as f64).sqrt() as i64;
        for y in [y - 1, y, y + 1] {
            if y >= 0 && y * y == y2 {
                pts.push([x as f64, y as f64]);
                if y != 0 {
                    pts.push([x as f64, -(y as f64)]);
                }
            }
        }
    }
    pts
}

#[test]
fn cocircular_points() {
    let pts = lattice_circle();
    assert_eq!(pts.len(), 1620);
    let mesh = check_all(&pts);
    assert_eq!(mesh.triangles.len(), pts.len() - 2);
    // With the centre added, every triangle uses it.
    let mut with_centre = pts.clone();
    with_centre.push([0.0, 0.0]);
    let mesh = check_all(&with_centre);
    assert_eq!(mesh.triangles.len(), pts.len());
    let c = pts.len() as u32;
    assert!(mesh.triangles.iter().all(|t| t.contains(&c)));
}

#[test]
fn cocircular_small_circle_one_by_one() {
    // 8 points on a circle of radius 5 (all integer), inserted in every
    // rotation and reversed, with checks after every insertion.
    let base = [
        [5.0, 0.0],
        [4.0, 3.0],
        [0.0, 5.0],
        [-3.0, 4.0],
        [-5.0, 0.0],
        [-4.0, -3.0],
        [0.0, -5.0],
        [3.0, -4.0],
    ];
    for rot in 0..8 {
        for rev in [false, true] {
            let mut pts: Vec<[f64; 2]> = (0..8).map(|k| base[(k + rot) % 8]).collect();
            if rev {
                pts.reverse();
            }
            let mut d = Delaunay2::new();
            for &p in &pts {
                d.insert(p).unwrap();
                d.check_topology().unwrap();
                d.check_delaunay().unwrap();
            }
            validate(&pts, &d.into_mesh()).unwrap();
        }
    }
}

#[test]
fn collinear_inputs() {
    let line: Vec<[f64; 2]> = (0..50)
        .map(|i| [i as f64 * 0.5, i as f64 * 1.5 + 1.0])
        .collect();
    assert_eq!(triangulate(&line), Err(Error::Degenerate { dimension: 1 }));
    let two = [[1.0, 2.0], [3.0, 4.0], [1.0, 2.0], [3.0, 4.0]];
    assert_eq!(
        triangulate(&two),
        Err(Error::TooFewPoints {
            found: 2,
            needed: 3
        })
    );
    assert_eq!(
        triangulate(&[[1.0, 1.0], [1.0, 1.0]]),
        Err(Error::TooFewPoints {
            found: 1,
            needed: 3
        })
    );
    assert_eq!(
        triangulate(&[]),
        Err(Error::TooFewPoints {
            found: 0,
            needed: 3
        })
    );
    // A line plus one point off it: a fan, whatever the insertion order.
    for k in [0, 7, 25, 50] {
        let mut pts = line.clone();
        pts.insert(k, [2.0, 0.0]);
        let mesh = check_all(&pts);
        assert_eq!(mesh.triangles.len(), line.len() - 1);
    }
    // Incrementally: no triangle while collinear, then a fan.
    let mut d = Delaunay2::new();
    for &p in &line {
        d.insert(p).unwrap();
    }
    assert_eq!(d.num_triangles(), 0);
    assert_eq!(d.num_vertices(), 0);
    assert_eq!(d.locate(&[0.0, 0.0]), Location::Empty);
    assert_eq!(
        d.insert(line[3]).unwrap(),
        Inserted::Duplicate {
            id: line.len() as u32,
            original: 3
        }
    );
    d.insert([-1.0, 5.0]).unwrap();
    d.check_topology().unwrap();
    d.check_delaunay().unwrap();
    assert_eq!(d.num_triangles(), line.len() - 1);
    let pts = d.points().to_vec();
    validate(&pts, &d.into_mesh()).unwrap();
}

#[test]
fn points_on_hull_edges() {
    // Points added exactly on hull edges and on their extensions.
    let pts = [
        [0.0, 0.0],
        [4.0, 0.0],
        [0.0, 4.0],
        [2.0, 0.0],
        [6.0, 0.0],
        [-2.0, 0.0],
        [0.0, 2.0],
        [0.0, 6.0],
        [2.0, 2.0],
        [3.0, 3.0],
        [1.0, 0.0],
    ];
    let mut d = Delaunay2::new();
    for (k, &p) in pts.iter().enumerate() {
        d.insert(p).unwrap();
        d.check_topology()
            .unwrap_or_else(|v| panic!("after {k}: {v}"));
        d.check_delaunay()
            .unwrap_or_else(|v| panic!("after {k}: {v}"));
    }
    validate(&pts, &d.into_mesh()).unwrap();
    check_all(&pts);
}

#[test]
fn many_duplicates() {
    let base = random_points(400, 21);
    let mut pts: Vec<[f64; 2]> = base.iter().flat_map(|&p| [p; 5]).collect();
    shuffle(&mut pts, 22);
    pts.push([-0.0, 0.25]);
    pts.push([0.0, 0.25]);
    let d = Delaunay2::from_points(&pts).unwrap();
    let dups = d.duplicates().to_vec();
    drop(d);
    let mesh = check_all(&pts);
    assert_eq!(mesh.duplicates, dups);
    assert_eq!(mesh.duplicates.len(), 4 * 400 + 1);
    for &(dup, orig) in &mesh.duplicates {
        assert!(orig < dup);
        assert_eq!(pts[dup as usize], pts[orig as usize]);
    }
    // The same through `insert`.
    let mut d = Delaunay2::new();
    for (k, &p) in pts.iter().enumerate() {
        match d.insert(p).unwrap() {
            Inserted::Vertex(v) | Inserted::Pending(v) => assert_eq!(v, k as u32),
            Inserted::Duplicate { id, original } => {
                assert_eq!(id, k as u32);
                assert!(original < id);
                assert_eq!(pts[original as usize], p);
            }
            Inserted::Hidden(v) => panic!("unweighted point {v} reported hidden"),
        }
    }
    d.check_topology().unwrap();
    assert_eq!(d.num_vertices(), 401);
    let m2 = d.into_mesh();
    validate(&pts, &m2).unwrap();
    assert_eq!(m2.duplicates, mesh.duplicates);
}

#[test]
fn scaled_and_translated() {
    let base = random_points(3000, 31);
    let g = grid(20, 20);
    for (s, t) in [
        (1e-9, 0.0),
        (1e9, 0.0),
        (1.0, 1e6),
        (1e-9, 1e6),
        (1e9, -1e6),
    ] {
        for set in [&base, &g] {
            let pts: Vec<[f64; 2]> = set.iter().map(|p| [p[0] * s + t, p[1] * s - t]).collect();
            check_all(&pts);
        }
    }
}

#[test]
fn tiny_sets_all_orders() {
    let sets: [&[[f64; 2]]; 4] = [
        &[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
        &[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]],
        &[[0.0, 0.0], [2.0, 0.0], [1.0, 2.0], [1.0, 0.5]],
        &[[0.0, 0.0], [2.0, 0.0], [4.0, 0.0], [1.0, 1.0]],
    ];
    for set in sets {
        let n = set.len();
        let mut perm: Vec<usize> = (0..n).collect();
        // Heap's algorithm over all orders.
        let mut c = vec![0; n];
        let run = |perm: &[usize]| {
            let pts: Vec<[f64; 2]> = perm.iter().map(|&k| set[k]).collect();
            let mesh = check_all(&pts);
            let mut d = Delaunay2::new();
            for &p in &pts {
                d.insert(p).unwrap();
                d.check_topology().unwrap();
                d.check_delaunay().unwrap();
            }
            assert_eq!(d.num_triangles(), mesh.triangles.len());
        };
        run(&perm);
        let mut i = 0;
        while i < n {
            if c[i] < i {
                perm.swap(if i % 2 == 0 { 0 } else { c[i] }, i);
                run(&perm);
                c[i] += 1;
                i = 0;
            } else {
                c[i] = 0;
                i += 1;
            }
        }
    }
}

#[test]
fn invalid_coordinates() {
    let mut pts = random_points(10, 41);
    pts[7][1] = f64::NAN;
    assert_eq!(
        triangulate(&pts),
        Err(Error::InvalidCoordinate { index: 7 })
    );
    pts[7][1] = 0.5;
    pts[3][0] = f64::INFINITY;
    assert_eq!(
        triangulate(&pts),
        Err(Error::InvalidCoordinate { index: 3 })
    );
    let mut d = Delaunay2::new();
    d.insert([0.0, 0.0]).unwrap();
    assert_eq!(
        d.insert([f64::NEG_INFINITY, 0.0]),
        Err(Error::InvalidCoordinate { index: 1 })
    );
    assert_eq!(d.points().len(), 1);
}

#[test]
fn incremental_matches_one_call() {
    // Points in general position have a unique Delaunay triangulation.
    let pts = random_points(3000, 51);
    let mesh = check_all(&pts);
    let mut d = Delaunay2::new();
    for (k, &p) in pts.iter().enumerate() {
        d.insert(p).unwrap();
        if k % 500 == 0 {
            d.check_topology().unwrap();
            d.check_delaunay().unwrap();
        }
    }
    assert_eq!(
        canonical(d.triangles()),
        canonical(mesh.triangles.iter().copied())
    );
    // Inserting after `from_points`.
    let (first, second) = pts.split_at(2000);
    let mut d = Delaunay2::from_points(first).unwrap();
    for &p in second {
        d.insert(p).unwrap();
    }
    d.check_topology().unwrap();
    assert_eq!(d.points(), &pts[..]);
    let m2 = d.into_mesh();
    validate(&pts, &m2).unwrap();
    assert_eq!(canonical(m2.triangles), canonical(mesh.triangles));
}

#[test]
fn locate_answers() {
    let pts = random_points(500, 61);
    let d = Delaunay2::from_points(&pts).unwrap();
    for (k, p) in pts.iter().enumerate() {
        assert_eq!(d.locate(p), Location::OnVertex(k as u32));
    }
    let mut r = SplitMix64::new(62);
    for _ in 0..500 {
        let q = [unit(&mut r) * 1.4 - 0.2, unit(&mut r) * 1.4 - 0.2];
        match d.locate(&q) {
            Location::InTriangle(t) => {
                let v = d.triangle(t).unwrap().map(|x| pts[x as usize]);
                for e in 0..3 {
                    assert!(delone_predicates::orient2d(&v[e], &v[(e + 1) % 3], &q) > 0.0);
                }
            }
            Location::OutsideHull([a, b]) => {
                let (a, b) = (pts[a as usize], pts[b as usize]);
                assert!(delone_predicates::orient2d(&a, &b, &q) < 0.0);
            }
            other => panic!("unexpected {other:?} for a random point"),
        }
    }
    // On an edge: the midpoint of two grid points.
    let g = grid(4, 4);
    let d = Delaunay2::from_points(&g).unwrap();
    match d.locate(&[1.5, 0.0]) {
        Location::OnEdge(t, i) => {
            let v = d.triangle(t).unwrap();
            let e = [v[(i as usize + 1) % 3], v[(i as usize + 2) % 3]];
            assert!(e.contains(&1) && e.contains(&2), "{e:?}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn progress_is_reported() {
    let pts = random_points(70_000, 71);
    let mut calls = Vec::new();
    let d = Delaunay2::from_points_with_progress(&pts, &mut |k, n| calls.push((k, n))).unwrap();
    assert_eq!(calls.first(), Some(&(0, 70_000)));
    assert_eq!(calls.last(), Some(&(70_000, 70_000)));
    assert!(calls.contains(&(65_536, 70_000)));
    assert!(calls.windows(2).all(|w| w[0].0 <= w[1].0));
    validate(&pts, &d.into_mesh()).unwrap();
}

fn digest(mesh: &TriMesh) -> u64 {
    // FNV-1a over the triangle and neighbour arrays.
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for w in mesh.triangles.iter().chain(&mesh.neighbors).flatten() {
        for b in w.to_le_bytes() {
            h = (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3);
        }
    }
    h
}

fn determinism_input() -> Vec<[f64; 2]> {
    let mut pts = random_points(5000, 81);
    pts.extend(grid(30, 30).iter().map(|p| [p[0] / 29.0, p[1] / 29.0]));
    pts.extend_from_within(..100);
    pts
}

#[test]
fn deterministic_within_and_across_runs() {
    let pts = determinism_input();
    let a = triangulate(&pts).unwrap();
    let b = triangulate(&pts).unwrap();
    assert_eq!(a, b);
    let h = digest(&a);
    if std::env::var_os("DELONE_TRI_DIGEST_CHILD").is_some() {
        println!("DIGEST={h}");
        return;
    }
    // A second process (different hash seeds, different allocations).
    let out = std::process::Command::new(std::env::current_exe().unwrap())
        .args([
            "--exact",
            "deterministic_within_and_across_runs",
            "--nocapture",
        ])
        .env("DELONE_TRI_DIGEST_CHILD", "1")
        .output()
        .expect("child process");
    let text = String::from_utf8_lossy(&out.stdout);
    let child: u64 = text
        .lines()
        .find_map(|l| l.strip_prefix("DIGEST="))
        .expect("child digest")
        .trim()
        .parse()
        .unwrap();
    assert_eq!(child, h);
}

#[test]
fn degenerate_stress_small_lattices() {
    // Many small sets drawn from tiny lattices: collinear runs, cocircular
    // quadruples, duplicates, collinear hulls. Checked after every insertion
    // and through the one-call path.
    for seed in 0..300u64 {
        let mut r = SplitMix64::new(1000 + seed);
        let side = 2 + r.below(5);
        let n = 3 + r.below(40) as usize;
        let pts: Vec<[f64; 2]> = (0..n)
            .map(|_| [r.below(side) as f64, r.below(side) as f64 * 0.5])
            .collect();
        let mut d = Delaunay2::new();
        for (k, &p) in pts.iter().enumerate() {
            d.insert(p).unwrap();
            if let Err(v) = d.check_topology().and_then(|_| d.check_delaunay()) {
                panic!("seed {seed}, after point {k} of {pts:?}: {v}");
            }
        }
        match triangulate(&pts) {
            Ok(mesh) => {
                validate(&pts, &mesh).unwrap_or_else(|v| panic!("seed {seed}: {v}"));
                assert_eq!(mesh.triangles.len(), d.num_triangles());
                assert_eq!(mesh.duplicates, d.duplicates());
                validate(&pts, &d.into_mesh()).unwrap();
            }
            Err(Error::Degenerate { .. }) | Err(Error::TooFewPoints { .. }) => {
                assert_eq!(d.num_triangles(), 0, "seed {seed}");
            }
            Err(e) => panic!("seed {seed}: {e}"),
        }
    }
}

#[test]
fn degenerate_inputs_have_one_answer_whatever_the_order() {
    // Symbolic perturbation by input index makes the triangulation of
    // cocircular sets unique: one-call (BRIO order) and incremental (input
    // order) builds agree exactly.
    let mut grid_pts = grid(25, 25);
    shuffle(&mut grid_pts, 91);
    let mut circle = lattice_circle();
    circle.truncate(400);
    circle.push([0.0, 0.0]);
    for pts in [grid(25, 25), grid_pts, circle] {
        let mesh = check_all(&pts);
        let mut d = Delaunay2::new();
        for &p in &pts {
            d.insert(p).unwrap();
        }
        assert_eq!(
            canonical(d.triangles()),
            canonical(mesh.triangles.iter().copied())
        );
    }
}
