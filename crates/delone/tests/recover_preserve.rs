//! Surface preservation (`-Y`): hard hand-made cases (Schönhardt prisms,
//! a thin box, a notched box) and the small closed clean corpus models are
//! recovered with interior Steiner points only; every Steiner point is
//! checked exactly to lie on no input triangle.

use std::path::PathBuf;
use std::time::Instant;

use delone::tet::recover::{check_recovered, recover, RecoverOptions, Recovered};
use delone_predicates::{orient2d, orient3d};

mod solids;
use solids::{cuboid as boxed, schonhardt};

fn preserve() -> RecoverOptions {
    RecoverOptions {
        preserve_surface: true,
        ..Default::default()
    }
}

/// Exact: `p` lies on the closed triangle `a b c`.
fn on_triangle(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], p: &[f64; 3]) -> bool {
    if orient3d(a, b, c, p) != 0.0 {
        return false;
    }
    // Project along an axis on which the triangle does not degenerate.
    for ax in 0..3 {
        let pr = |q: &[f64; 3]| match ax {
            0 => [q[1], q[2]],
            1 => [q[2], q[0]],
            _ => [q[0], q[1]],
        };
        let (a2, b2, c2, p2) = (pr(a), pr(b), pr(c), pr(p));
        let s = orient2d(&a2, &b2, &c2);
        if s == 0.0 {
            continue;
        }
        let s1 = orient2d(&a2, &b2, &p2) * s;
        let s2 = orient2d(&b2, &c2, &p2) * s;
        let s3 = orient2d(&c2, &a2, &p2) * s;
        return s1 >= 0.0 && s2 >= 0.0 && s3 >= 0.0;
    }
    false
}

/// Recovers with `-Y`, checks the result and that the surface is exactly
/// the input (no Steiner point on it, one boundary face per triangle).
fn check_y(name: &str, pts: &[[f64; 3]], tris: &[[u32; 3]]) -> Recovered {
    let t0 = Instant::now();
    let r = recover(pts, tris, &preserve()).unwrap_or_else(|e| panic!("{name}: {e}"));
    let ms = t0.elapsed().as_secs_f64() * 1e3;
    check_recovered(pts, tris, &r).unwrap_or_else(|v| panic!("{name}: {v:?}"));
    let p = &r.report;
    assert_eq!((p.steiner_on_edges, p.steiner_on_facets), (0, 0), "{name}");
    assert_eq!(r.points.len(), pts.len() + p.steiner_interior, "{name}");
    for (i, q) in r.points[pts.len()..].iter().enumerate() {
        for t in tris {
            let [a, b, c] = t.map(|w| &pts[w as usize]);
            assert!(
                !on_triangle(a, b, c, q),
                "{name}: Steiner point {i} {q:?} lies on triangle {t:?}"
            );
        }
    }
    assert_eq!(r.boundary.len(), tris.len(), "{name}");
    let v_in = delone::tet::recover::surface_volume(pts, tris).abs();
    let v_out: f64 = r.regions.iter().map(|g| g.volume).sum();
    assert!(
        (v_in - v_out).abs() <= 1e-9 * v_in,
        "{name}: {v_in} vs {v_out}"
    );
    println!(
        "{name}: -Y ok, {} tris, {} tets, interior Steiner {}, flips23 {}, removals {}, rounds {}, {ms:.1} ms",
        tris.len(),
        r.mesh.tets.len(),
        p.steiner_interior,
        p.flips23,
        p.edge_removals,
        p.rounds
    );
    r
}

/// A Chazelle-style box: `n` thin wedge notches cut into the top along x
/// and `n` into the bottom along y, their edges nearly touching inside, as
/// a closed triangulated surface (a height field on top and bottom).
fn notched_box(n: usize) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    // Top: z = 1 except along the lines x = (i + 0.5) / n, where a notch
    // reaches down to z = 0.55; bottom: z = 0 except along y = (j + 0.5) / n
    // where a notch reaches up to z = 0.45. Grid columns: 0, notch, ... 1.
    let mut xs = vec![0.0];
    for i in 0..n {
        let c = (i as f64 + 0.5) / n as f64;
        xs.extend([c - 0.1 / n as f64, c, c + 0.1 / n as f64]);
    }
    xs.push(1.0);
    let ys = xs.clone();
    let m = xs.len();
    let mut pts: Vec<[f64; 3]> = Vec::new();
    let is_notch = |k: usize| k % 3 == 2 && k + 1 < m;
    // Top grid vertices (ids i * m + j), bottom grid (m * m + ...).
    for &x in &xs {
        for (j, &y) in ys.iter().enumerate() {
            let _ = j;
            pts.push([x, y, 1.0]);
        }
    }
    for &x in &xs {
        for &y in &ys {
            pts.push([x, y, 0.0]);
        }
    }
    for i in 0..m {
        for j in 0..m {
            if is_notch(i) && j > 0 && j + 1 < m {
                pts[i * m + j][2] = 0.55;
            }
            if is_notch(j) && i > 0 && i + 1 < m {
                pts[m * m + i * m + j][2] = 0.45;
            }
        }
    }
    let top = |i: usize, j: usize| (i * m + j) as u32;
    let bot = |i: usize, j: usize| (m * m + i * m + j) as u32;
    let mut tris = Vec::new();
    for i in 0..m - 1 {
        for j in 0..m - 1 {
            // Top faces outward (+z): counterclockwise seen from above.
            tris.push([top(i, j), top(i + 1, j), top(i + 1, j + 1)]);
            tris.push([top(i, j), top(i + 1, j + 1), top(i, j + 1)]);
            tris.push([bot(i, j), bot(i + 1, j + 1), bot(i + 1, j)]);
            tris.push([bot(i, j), bot(i, j + 1), bot(i + 1, j + 1)]);
        }
    }
    // Sides: the boundary rows of both grids are flat (z = 1 and z = 0).
    let ring: Vec<(usize, usize)> = (0..m - 1)
        .map(|k| (k, 0))
        .chain((0..m - 1).map(|k| (m - 1, k)))
        .chain((0..m - 1).map(|k| (m - 1 - k, m - 1)))
        .chain((0..m - 1).map(|k| (0, m - 1 - k)))
        .collect();
    for k in 0..ring.len() {
        let (i0, j0) = ring[k];
        let (i1, j1) = ring[(k + 1) % ring.len()];
        tris.push([bot(i0, j0), bot(i1, j1), top(i1, j1)]);
        tris.push([bot(i0, j0), top(i1, j1), top(i0, j0)]);
    }
    (pts, tris)
}

#[test]
fn schonhardt_prisms() {
    for twist in [10.0, 20.0, 30.0, 45.0, 55.0] {
        let (pts, tris) = schonhardt(twist);
        let r = check_y(&format!("schonhardt {twist}"), &pts, &tris);
        assert!(r.report.steiner_interior >= 1);
    }
}

#[test]
fn thin_and_notched_boxes() {
    for (w, d, h) in [(10.0, 1.0, 0.001), (1.0, 1.0, 1e-6), (100.0, 0.01, 1.0)] {
        let (pts, tris) = boxed(w, d, h);
        check_y(&format!("box {w}x{d}x{h}"), &pts, &tris);
    }
    for n in [1, 2, 3] {
        let (pts, tris) = notched_box(n);
        check_y(&format!("notched box {n}"), &pts, &tris);
    }
}

/// A prism over a regular `n`-gon (radius 1, height 1) whose caps are
/// fans from vertex `n - 1` (long thin triangles, as ear clipping of a
/// CAD cap leaves them): all its vertices are cospherical, every face is
/// on the convex hull.
fn fanned_cylinder(n: u32) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let mut pts = Vec::new();
    for z in [0.0, 1.0] {
        for k in 0..n {
            let a = 2.0 * std::f64::consts::PI * f64::from(k) / f64::from(n);
            pts.push([a.cos(), a.sin(), z]);
        }
    }
    let mut tris = Vec::new();
    for i in 0..n {
        let j = (i + 1) % n;
        tris.push([i, j, j + n]);
        tris.push([i, j + n, i + n]);
    }
    for k in 0..n - 2 {
        tris.push([n - 1, k + 1, k]);
        tris.push([2 * n - 1, n + k, n + k + 1]);
    }
    (pts, tris)
}

/// The cospherical vertices of a fanned cylinder leave most of its
/// subsegments to cavities after the flips of the Delaunay
/// tetrahedralization; one interior point (the centroid of the failing
/// triangles) lets the flips recover everything.
#[test]
fn fanned_cylinders_need_one_interior_point() {
    for n in [24, 50, 100] {
        let (pts, tris) = fanned_cylinder(n);
        let r = check_y(&format!("cylinder {n}"), &pts, &tris);
        assert_eq!(r.report.steiner_interior, 1, "cylinder {n}");
    }
}

fn data_dir() -> Option<PathBuf> {
    delone_testdata::corpus_dir(env!("CARGO_MANIFEST_DIR"))
}

/// The closed clean corpus models whose triangle count is in `range`:
/// with `all`, every one must be recovered under `-Y`; otherwise the
/// outcomes are tallied (a failure must be a typed error, a success must
/// pass every check).
fn corpus(range: std::ops::RangeInclusive<usize>, all: bool) {
    let Some(dir) = data_dir() else { return };
    let list = std::fs::read_to_string(dir.join("sets/closed_clean.txt")).unwrap();
    let (mut ok, mut failed, mut steiner) = (0, Vec::new(), 0);
    for l in list.lines().filter(|l| !l.trim().is_empty()) {
        let mut it = l.split_whitespace();
        let rel = it.next().unwrap();
        let nf: usize = it.next().unwrap().parse().unwrap();
        if !range.contains(&nf) {
            continue;
        }
        // DELONE_Y_MODEL=name[,name...] restricts the run to the models
        // matching one of the names.
        if std::env::var("DELONE_Y_MODEL").is_ok_and(|m| !m.split(',').any(|n| rel.contains(n))) {
            continue;
        }
        let s = delone_io::read_off(&std::fs::read(dir.join(rel)).unwrap()).unwrap();
        let tris = s.triangles();
        if all {
            steiner += check_y(rel, &s.points, &tris).report.steiner_interior;
            ok += 1;
            continue;
        }
        match recover(&s.points, &tris, &preserve()) {
            Ok(_) => {
                steiner += check_y(rel, &s.points, &tris).report.steiner_interior;
                ok += 1;
            }
            Err(e) => {
                println!("{rel}: -Y failed: {e}");
                failed.push(rel.to_string());
            }
        }
    }
    println!(
        "-Y: {ok} closed clean models recovered and checked ({steiner} interior Steiner points), {} failed: {failed:?}",
        failed.len()
    );
}

#[test]
fn small_closed_clean_models() {
    corpus(0..=700, true);
}

/// Models whose `-Y` recovery needs missing edges recovered together with
/// their triangles (patch cavities) and faces at edges with many
/// tetrahedra found; each takes about a second.
#[test]
fn medium_models_recovered_by_patches() {
    let Some(dir) = data_dir() else { return };
    for name in ["cgal_fandisk", "cgal_anchor_dense", "cgal_homer"] {
        let path = dir.join(format!("surf/off/{name}.off"));
        let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let s = delone_io::read_off(&bytes).unwrap();
        check_y(name, &s.points, &s.triangles());
    }
}

/// Every closed clean model above 700 triangles must be recovered under
/// `-Y` (cgal_anchor, cgal_rotor and vtk_vase need the pull-off fallback:
/// clusters, thin gap faces, tangent-cone points).
#[test]
#[ignore = "medium and large models: cargo test --release -p delone --test recover_preserve -- --ignored"]
fn larger_closed_clean_models() {
    corpus(701..=usize::MAX, true);
}

/// 2D orientation sign helper of [`plate_with_holes`] (floating point:
/// the generator only needs it away from degeneracies).
fn turn(o: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
}

/// A CAD-like plate: the unit `n`-gon extruded to height 0.2 with `holes`
/// round holes (`m`-gons of radius 0.07 on the circle of radius 0.7),
/// its top and bottom triangulated by ear clipping of the outline bridged
/// to each hole (long thin fans, not Delaunay), its walls by two
/// triangles per quadrilateral. Top and bottom are flat parts of the
/// convex hull.
fn plate_with_holes(n: usize, holes: usize, m: usize) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    use std::f64::consts::TAU;
    let mut p2: Vec<[f64; 2]> = (0..n)
        .map(|k| {
            let a = TAU * k as f64 / n as f64;
            [a.cos(), a.sin()]
        })
        .collect();
    let mut poly: Vec<usize> = (0..n).collect();
    let mut hole_ids: Vec<Vec<usize>> = Vec::new();
    for j in 0..holes {
        let a = TAU * j as f64 / holes as f64 + 0.1;
        let c = [0.7 * a.cos(), 0.7 * a.sin()];
        let ids: Vec<usize> = (p2.len()..p2.len() + m).collect();
        for k in 0..m {
            let b = a + TAU * k as f64 / m as f64;
            p2.push([c[0] + 0.07 * b.cos(), c[1] + 0.07 * b.sin()]);
        }
        // Bridge the hole's outermost vertex to the nearest outline vertex.
        let h0 = p2[ids[0]];
        let d2 = |k: usize| (p2[k][0] - h0[0]).powi(2) + (p2[k][1] - h0[1]).powi(2);
        let best = (0..n).min_by(|&x, &y| d2(x).total_cmp(&d2(y))).unwrap();
        let i = poly.iter().position(|&v| v == best).unwrap();
        let mut around = vec![ids[0]];
        around.extend(ids[1..].iter().rev());
        around.extend([ids[0], best]);
        poly.splice(i + 1..i + 1, around);
        hole_ids.push(ids);
    }
    // Ear clipping (the bridged polygon is counterclockwise).
    let mut tris2: Vec<[usize; 3]> = Vec::new();
    let mut v = poly;
    while v.len() > 3 {
        let k = v.len();
        let ear = (0..k).find(|&i| {
            let (a, b, c) = (v[(i + k - 1) % k], v[i], v[(i + 1) % k]);
            let (pa, pb, pc) = (p2[a], p2[b], p2[c]);
            turn(pa, pb, pc) > 0.0
                && !v.iter().any(|&w| {
                    let q = p2[w];
                    q != pa
                        && q != pb
                        && q != pc
                        && turn(pa, pb, q) >= 0.0
                        && turn(pb, pc, q) >= 0.0
                        && turn(pc, pa, q) >= 0.0
                })
        });
        let i = ear.expect("the bridged outline has an ear");
        tris2.push([v[(i + k - 1) % k], v[i], v[(i + 1) % k]]);
        v.remove(i);
    }
    tris2.push([v[0], v[1], v[2]]);
    let nn = p2.len() as u32;
    let mut pts: Vec<[f64; 3]> = p2.iter().map(|q| [q[0], q[1], 0.0]).collect();
    pts.extend(p2.iter().map(|q| [q[0], q[1], 0.2]));
    let mut tris: Vec<[u32; 3]> = Vec::new();
    for t in &tris2 {
        let [a, b, c] = t.map(|w| w as u32);
        tris.push([a, c, b]);
        tris.push([a + nn, b + nn, c + nn]);
    }
    let mut wall = |a: usize, b: usize| {
        let (a, b) = (a as u32, b as u32);
        tris.push([a, b, b + nn]);
        tris.push([a, b + nn, a + nn]);
    };
    for k in 0..n {
        wall(k, (k + 1) % n);
    }
    for ids in &hole_ids {
        for k in 0..m {
            wall(ids[(k + 1) % m], ids[k]);
        }
    }
    (pts, tris)
}

/// Plates with holes whose flat tops and bottoms (parts of the convex
/// hull, fan-triangulated) miss many input edges after the flips: the
/// hull edges crossing them are flipped in the plane (cavity module).
#[test]
fn plates_with_holes() {
    for (n, holes, m) in [(48, 4, 12), (32, 6, 12), (24, 4, 8)] {
        let (pts, tris) = plate_with_holes(n, holes, m);
        check_y(&format!("plate {n}/{holes}/{m}"), &pts, &tris);
    }
}

/// A CSG pipe tee whose flat faces are fans of exactly coplanar triangles
/// (`tests/data/README.md`): the `-Y` fallback's surface Steiner points
/// on edges between two coplanar triangles are pulled off through wedges
/// that no point beside them sees (flat tetrahedra in their stars); the
/// gift-wrapping fill of such a wedge needs no such point. Recovered,
/// checked, with the same output twice.
#[test]
fn pipe_tee_with_coplanar_fans() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/pipe_tee.off");
    let s = delone_io::read_off(&std::fs::read(path).unwrap()).unwrap();
    let tris = s.triangles();
    let a = check_y("pipe_tee", &s.points, &tris);
    let b = recover(&s.points, &tris, &preserve()).unwrap();
    assert_eq!(a.points, b.points);
    assert_eq!(a.mesh.tets, b.mesh.tets);
}
