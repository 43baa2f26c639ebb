//! Mesh optimisation (`delone::tet::optimize`): hand-made slivers and
//! refined corpus models keep their boundary and volume, pass
//! `check_recovered`, and reach the dihedral-angle bounds.

use std::path::PathBuf;

use delone::tet::optimize::{optimize, OptimizeOptions, StageStop, BAD_ANGLE};
use delone::tet::quality::TetStats;
use delone::tet::recover::{check_recovered, recover, RecoverOptions, Recovered};
use delone::tet::refine::{refine, RefineOptions};
use delone_predicates::orient3d;

mod solids;
use solids::cube;

/// The corpus folder (`shared/data/surf/off`); `None` when it is missing
/// and `DELONE_NO_CORPUS=1` (see `delone_testdata`).
fn corpus() -> Option<PathBuf> {
    delone_testdata::corpus_path(env!("CARGO_MANIFEST_DIR"), "surf/off")
}

/// Points and triangles of corpus model `name` (`dir/name.off`).
fn read_model(dir: &std::path::Path, name: &str) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let text = std::fs::read_to_string(dir.join(format!("{name}.off"))).unwrap();
    read_off(&text)
}

fn read_off(text: &str) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let mut toks = text
        .lines()
        .map(|l| l.split('#').next().unwrap_or(""))
        .flat_map(str::split_whitespace);
    assert_eq!(toks.next(), Some("OFF"));
    let nv: usize = toks.next().unwrap().parse().unwrap();
    let nf: usize = toks.next().unwrap().parse().unwrap();
    let _ne = toks.next();
    let pts = (0..nv)
        .map(|_| std::array::from_fn(|_| toks.next().unwrap().parse().unwrap()))
        .collect();
    let mut tris = Vec::with_capacity(nf);
    for _ in 0..nf {
        let k: usize = toks.next().unwrap().parse().unwrap();
        let v: Vec<u32> = (0..k)
            .map(|_| toks.next().unwrap().parse().unwrap())
            .collect();
        for i in 1..k - 1 {
            tris.push([v[0], v[i], v[i + 1]]);
        }
    }
    (pts, tris)
}

/// The vertices of the boundary, ascending (the optimisation removes only
/// interior points and renumbers the others in order, so the k-th boundary
/// vertex before is the k-th after).
fn boundary_vertices(r: &Recovered) -> Vec<u32> {
    let mut v: Vec<u32> = r.boundary.iter().flatten().copied().collect();
    v.sort_unstable();
    v.dedup();
    v
}

/// What boundary flips keep: per facet (`surface_origin` of the boundary
/// face's triangle) the number of boundary faces and their vertices (by
/// rank among the boundary vertices).
fn surface(r: &Recovered) -> Vec<(u32, usize, Vec<usize>)> {
    let bv = boundary_vertices(r);
    let rank = |v: u32| bv.binary_search(&v).unwrap();
    let mut per: std::collections::BTreeMap<u32, (usize, Vec<usize>)> = Default::default();
    for (f, &t) in r.boundary.iter().zip(&r.boundary_triangle) {
        let g = r.surface_origin.get(t as usize).copied().unwrap_or(t);
        let e = per.entry(g).or_default();
        e.0 += 1;
        e.1.extend(f.iter().map(|&v| rank(v)));
    }
    per.into_iter()
        .map(|(g, (n, mut v))| {
            v.sort_unstable();
            v.dedup();
            (g, n, v)
        })
        .collect()
}

/// A corpus model's points and triangles, and its refined mesh.
type Model = (Vec<[f64; 3]>, Vec<[u32; 3]>, Recovered);

/// The corpus model `name` (`surf/off/NAME.off`) refined to radius-edge
/// `q`, with its points and triangles; `None` (with a note) when the shared
/// data is missing.
fn refined_model(name: &str, q: f64) -> Option<Model> {
    let dir = corpus()?;
    let (pts, tris) = read_model(&dir, name);
    let ro = RefineOptions {
        max_radius_edge: Some(q),
        ..Default::default()
    };
    let r = refine(&pts, &tris, &ro).unwrap().rec;
    Some((pts, tris, r))
}

/// The tetrahedra of `r` with a dihedral angle below [`BAD_ANGLE`] or
/// above `180 -` it.
fn outside_bounds(r: &Recovered) -> usize {
    r.mesh
        .tets
        .iter()
        .filter(|tv| {
            let d = delone::tet::quality::dihedral_angles(&tv.map(|v| r.points[v as usize]));
            d.iter()
                .any(|&x| !(BAD_ANGLE..=180.0 - BAD_ANGLE).contains(&x))
        })
        .count()
}

fn total_volume(r: &Recovered) -> f64 {
    TetStats::of(&r.points, &r.mesh.tets).total_volume
}

/// Optimises `r` and checks the invariants; returns the report.
fn run(
    pts: &[[f64; 3]],
    tris: &[[u32; 3]],
    r: &mut Recovered,
    opts: &OptimizeOptions,
) -> delone::tet::optimize::OptimizeReport {
    let surf = surface(r);
    let vol = total_volume(r);
    let fixed: Vec<[f64; 3]> = r.points.clone();
    let bv = boundary_vertices(r);
    let opts = OptimizeOptions {
        input_points: Some(pts.len()),
        ..opts.clone()
    };
    let rep = optimize(r, &opts).unwrap();
    check_recovered(pts, tris, r).unwrap();
    assert_eq!(surface(r), surf, "the boundary changed");
    assert!((total_volume(r) - vol).abs() <= 1e-9 * vol.abs());
    // Boundary vertices moved only within their input triangle or along
    // their input edge: exactly when they were exactly there before.
    let bv_after = boundary_vertices(r);
    assert_eq!(bv.len(), bv_after.len());
    for (f, &ti) in r.boundary.iter().zip(&r.boundary_triangle) {
        let [a, b, c] = r.surface[ti as usize].map(|q| r.points[q as usize]);
        for &v in f {
            let was = bv[bv_after.binary_search(&v).unwrap()];
            let (old, new) = (fixed[was as usize], r.points[v as usize]);
            if old != new && orient3d(&a, &b, &c, &old) == 0.0 {
                assert_eq!(orient3d(&a, &b, &c, &new), 0.0, "vertex {v} left its plane");
            }
        }
    }
    assert_eq!(r.points[..pts.len()], *pts);
    // Every Steiner point is a vertex of the mesh (collapsed insertions
    // are left out).
    let mut used = vec![false; r.points.len()];
    for tv in &r.mesh.tets {
        for &v in tv {
            used[v as usize] = true;
        }
    }
    assert!(
        used[pts.len()..].iter().all(|&u| u),
        "a Steiner point is unused"
    );
    assert!(rep.after.min_dihedral >= rep.before.min_dihedral - 1e-9);
    assert_eq!(rep.after.tets, r.mesh.tets.len());
    // The bad cells' classes add up to their count, counted here again.
    let bad = outside_bounds(r);
    assert_eq!(rep.bad.count, bad);
    assert_eq!(
        rep.bad.count,
        rep.bad.sharp_edge + rep.bad.at_feature + rep.bad.free
    );
    assert!(rep.bad.feature_angle < BAD_ANGLE);
    rep
}

#[test]
fn interior_slivers_in_a_cube_are_removed() {
    // A cube with interior points on a nearly flat square: the Delaunay
    // recovery makes slivers between them.
    let (mut pts, tris) = cube();
    let h = 1e-3;
    for (x, y, z) in [
        (0.3, 0.3, 0.5),
        (0.7, 0.3, 0.5 + h),
        (0.7, 0.7, 0.5),
        (0.3, 0.7, 0.5 + h),
        (0.5, 0.5, 0.2),
        (0.5, 0.5, 0.8),
    ] {
        pts.push([x, y, z]);
    }
    // Interior points need an input triangle to be kept: recover the cube,
    // then add the points by Delaunay refinement is not possible here, so
    // use them as isolated vertices of the recovery input.
    let mut r = recover(&pts, &tris, &RecoverOptions::default()).unwrap();
    let before = TetStats::of(&r.points, &r.mesh.tets);
    let rep = run(&pts, &tris, &mut r, &OptimizeOptions::default());
    assert_eq!(rep.before, before);
    assert!(
        rep.after.min_dihedral > before.min_dihedral,
        "{} -> {}",
        before.min_dihedral,
        rep.after.min_dihedral
    );
    // Deterministic.
    let mut r2 = recover(&pts, &tris, &RecoverOptions::default()).unwrap();
    optimize(&mut r2, &OptimizeOptions::default()).unwrap();
    assert_eq!(r2, r);
}

#[test]
fn level_zero_changes_nothing() {
    let (pts, tris) = cube();
    // Every input triangle its own facet (no coplanar merging): the
    // refined cube then has cells for the optimiser to improve (merged, it
    // is already at 54.7°).
    let mut r = refine(
        &pts,
        &tris,
        &RefineOptions {
            max_volume: Some(0.01),
            recover: RecoverOptions {
                merge_coplanar: false,
                ..Default::default()
            },
            ..Default::default()
        },
    )
    .unwrap()
    .rec;
    let copy = r.clone();
    let rep = optimize(&mut r, &OptimizeOptions::level(0)).unwrap();
    assert_eq!(r, copy);
    assert_eq!(rep.before, rep.after);
    let rep = run(&pts, &tris, &mut r, &OptimizeOptions::default());
    assert!(rep.after.min_dihedral > rep.before.min_dihedral);
    // The cube's edges are right angles.
    assert!(
        (rep.input_min_dihedral - 90.0).abs() < 1e-9,
        "{}",
        rep.input_min_dihedral
    );
    assert!(
        rep.after.min_dihedral >= 15.0,
        "{:?}",
        rep.after.min_dihedral
    );
}

#[test]
fn refined_corpus_models_reach_the_bounds() {
    let Some(dir) = corpus() else {
        return;
    };
    let mut multi_face = 0;
    for (name, q, min_want) in [
        ("cgal_sphere", 1.414, 20.0),
        ("cgal_star", 2.0, 20.0),
        ("cgal_blob_closed", 2.0, 20.0),
        ("cgal_knot1", 2.0, 20.0),
        ("igl_bumpy", 2.0, 20.0),
        // Needle input triangles (1.5° on pipe): the last tetrahedra below
        // 15° there need the extra budget of the low stages.
        ("cgal_pipe", 1.414, 15.0),
        ("cgal_spool", 1.414, 15.0),
        ("cgal_eight", 1.414, 15.0),
        ("cgal_helmet", 1.414, 15.0),
    ] {
        let multi_face = &mut multi_face;
        let (pts, tris) = read_model(&dir, name);
        let t0 = std::time::Instant::now();
        let mut r = refine(
            &pts,
            &tris,
            &RefineOptions {
                max_radius_edge: Some(q),
                ..Default::default()
            },
        )
        .unwrap()
        .rec;
        let t_ref = t0.elapsed().as_secs_f64();
        let t1 = std::time::Instant::now();
        let mut o = OptimizeOptions::default();
        if let Some(t) = std::env::var("TETOPT_TARGET")
            .ok()
            .and_then(|s| s.parse().ok())
        {
            o.target_dihedral = t;
        }
        let rep = run(&pts, &tris, &mut r, &o);
        let t_opt = t1.elapsed().as_secs_f64();
        eprintln!(
            "{name} q{q}: {} -> {} tets, dihedral {:.2}..{:.2} -> {:.2}..{:.2}; \
             23:{} 32:{} 44:{} er:{} sm:{} ins:{} (undone {}) passes {}; stuck {:?}; \
             refine {t_ref:.2}s optimise {t_opt:.2}s",
            rep.before.tets,
            rep.after.tets,
            rep.before.min_dihedral,
            rep.before.max_dihedral,
            rep.after.min_dihedral,
            rep.after.max_dihedral,
            rep.flips23,
            rep.flips32,
            rep.flips44,
            rep.edge_removals,
            rep.smoothed,
            rep.inserted,
            rep.insert_undone,
            rep.passes,
            rep.stuck_counts,
        );
        for s in rep.stuck.iter().take(5) {
            eprintln!("  stuck tet {} {:?} {}", s.tet, s.dihedral, s.reason);
        }
        *multi_face += rep.multi_face;
        // No tetrahedron at a surface edge can beat the surface's angle.
        assert!(rep.input_min_dihedral >= rep.after.min_dihedral - 1e-9);
        assert!(
            rep.after.min_dihedral >= min_want,
            "{name}: min dihedral {}",
            rep.after.min_dihedral
        );
        assert!(
            rep.after.max_dihedral <= 180.0 - min_want,
            "{name}: max dihedral {}",
            rep.after.max_dihedral
        );
    }
    assert!(multi_face > 0, "no multi-face removal");
}

#[test]
fn squashed_interior_vertices_are_smoothed_back() {
    // Refine a cube, then drag every interior vertex most of the way to a
    // neighbour (as long as its tetrahedra stay clearly positive): slivers
    // and caps that only smoothing and flips can repair.
    let (pts, tris) = cube();
    let mut r = refine(
        &pts,
        &tris,
        &RefineOptions {
            max_volume: Some(0.005),
            ..Default::default()
        },
    )
    .unwrap()
    .rec;
    let on_surface: std::collections::BTreeSet<u32> =
        r.boundary.iter().flatten().copied().collect();
    let n = r.points.len() as u32;
    let mut moved = 0;
    for v in pts.len() as u32..n {
        if on_surface.contains(&v) {
            continue;
        }
        let star: Vec<usize> = (0..r.mesh.tets.len())
            .filter(|&t| r.mesh.tets[t].contains(&v))
            .collect();
        let Some(&u) = r.mesh.tets[star[0]].iter().find(|&&u| u != v) else {
            continue;
        };
        let (a, b) = (r.points[v as usize], r.points[u as usize]);
        for f in [0.9, 0.8, 0.6, 0.4] {
            let p: [f64; 3] = std::array::from_fn(|k| a[k] + f * (b[k] - a[k]));
            let ok = star.iter().all(|&t| {
                let q = r.mesh.tets[t].map(|w| if w == v { p } else { r.points[w as usize] });
                delone::tet::quality::volume(&q) > 1e-9
            });
            if ok {
                r.points[v as usize] = p;
                moved += 1;
                break;
            }
        }
    }
    assert!(moved > 0);
    check_recovered(&pts, &tris, &r).unwrap();
    let before = TetStats::of(&r.points, &r.mesh.tets);
    assert!(before.min_dihedral < 10.0, "{}", before.min_dihedral);
    let rep = run(&pts, &tris, &mut r, &OptimizeOptions::level(2));
    assert!(rep.smoothed > 0);
    assert!(
        rep.after.min_dihedral >= 15.0,
        "{} -> {}",
        before.min_dihedral,
        rep.after.min_dihedral
    );
}

#[test]
fn surface_steiner_points_slide_within_their_facet_or_edge() {
    // A refined cube: Steiner points on its faces and edges.
    let (pts, tris) = cube();
    let refined = refine(
        &pts,
        &tris,
        &RefineOptions {
            max_volume: Some(0.002),
            ..Default::default()
        },
    )
    .unwrap()
    .rec;
    let on_bounds = |p: &[f64; 3]| p.iter().filter(|&&c| c == 0.0 || c == 1.0).count();
    let moved = |smooth_boundary: bool| {
        let mut r = refined.clone();
        let opts = OptimizeOptions {
            smooth_boundary,
            target_dihedral: 50.0,
            ..Default::default()
        };
        let rep = run(&pts, &tris, &mut r, &opts);
        // (Interior points may be removed: the surface ones are renumbered
        // in order.)
        let (bv0, bv1) = (boundary_vertices(&refined), boundary_vertices(&r));
        let mut n = 0;
        for f in &r.boundary {
            for &v in f {
                let was = bv0[bv1.binary_search(&v).unwrap()];
                let (old, new) = (refined.points[was as usize], r.points[v as usize]);
                if old != new {
                    n += 1;
                    // Still on the same face(s) of the cube, exactly.
                    for k in 0..3 {
                        if old[k] == 0.0 || old[k] == 1.0 {
                            assert_eq!(new[k], old[k], "vertex {v} left its facet");
                        }
                    }
                    assert_eq!(on_bounds(&new), on_bounds(&old));
                }
            }
        }
        (n, rep)
    };
    let (fixed, _) = moved(false);
    assert_eq!(fixed, 0, "surface points moved with smooth_boundary off");
    let (n, rep) = moved(true);
    assert!(n > 0, "no surface Steiner point moved");
    // Faces of the cube's flat sides were flipped (each stays the union of
    // its faces: `run` checks it).
    assert!(rep.boundary_flips > 0, "no boundary flip");
    assert!(rep.after.min_dihedral >= rep.before.min_dihedral);
}

/// Flat tetrahedra of a refined flat-faced model (four surface points on
/// one sheet, or a near-duplicate pair of interior points) are removed by
/// the lifted insertion and the smoothing: before, the minimum was 0°.
/// Deterministic too.
#[test]
fn flat_tetrahedra_along_facets_are_removed() {
    let Some(dir) = corpus() else {
        return;
    };
    for name in ["cgal_dragknob", "cgal_oblong"] {
        let (pts, tris) = read_model(&dir, name);
        let ro = RefineOptions {
            max_radius_edge: Some(1.414),
            ..Default::default()
        };
        let r0 = refine(&pts, &tris, &ro).unwrap().rec;
        let mut r = r0.clone();
        let rep = run(&pts, &tris, &mut r, &OptimizeOptions::level(3));
        eprintln!(
            "{name}: dihedral {:.2}..{:.2} -> {:.2}..{:.2}, {} inserted, surface bound {:.2}",
            rep.before.min_dihedral,
            rep.before.max_dihedral,
            rep.after.min_dihedral,
            rep.after.max_dihedral,
            rep.inserted,
            rep.input_min_dihedral
        );
        assert!(rep.input_min_dihedral >= 15.0, "{name}: sharp input");
        assert!(
            rep.after.min_dihedral >= 10.0 && rep.after.max_dihedral <= 170.0,
            "{name}: dihedral {:.2}..{:.2}",
            rep.after.min_dihedral,
            rep.after.max_dihedral
        );
        let mut again = r0;
        optimize(
            &mut again,
            &OptimizeOptions {
                input_points: Some(pts.len()),
                ..OptimizeOptions::level(3)
            },
        )
        .unwrap();
        assert_eq!(again.points, r.points, "{name}: not deterministic");
        assert_eq!(again.mesh.tets, r.mesh.tets, "{name}: not deterministic");
    }
}

/// The smallest and largest angle (degrees) of input triangle `t`.
fn input_angles(pts: &[[f64; 3]], t: [u32; 3]) -> [f64; 2] {
    let p = t.map(|v| pts[v as usize]);
    let mut a = [0.0; 3];
    for (k, x) in a.iter_mut().enumerate() {
        let (o, b, c) = (p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
        let u: [f64; 3] = std::array::from_fn(|i| b[i] - o[i]);
        let v: [f64; 3] = std::array::from_fn(|i| c[i] - o[i]);
        let d = (0..3).map(|i| u[i] * v[i]).sum::<f64>();
        let n = |w: [f64; 3]| w.iter().map(|c| c * c).sum::<f64>().sqrt();
        *x = (d / (n(u) * n(v))).clamp(-1.0, 1.0).acos().to_degrees();
    }
    [
        a.iter().copied().fold(180.0, f64::min),
        a.iter().copied().fold(0.0, f64::max),
    ]
}

#[test]
fn the_bound_names_the_needle_input_triangle_at_the_worst_tetrahedron() {
    // cgal_u has an input triangle with a 0.07° and a 179.85° angle: the
    // tetrahedra around it are left below 15°, and the report says where.
    let Some((pts, tris, mut r)) = refined_model("cgal_u", 1.414) else {
        return;
    };
    let rep = run(&pts, &tris, &mut r, &OptimizeOptions::level(3));
    // Some inserted vertices were removed again.
    assert!(rep.collapsed > 0);
    // The report's extremes are those of the input triangles it names.
    let t = rep.triangles_min_angle_triangle.unwrap() as usize;
    assert!((input_angles(&pts, tris[t])[0] - rep.triangles_min_angle).abs() < 1e-9);
    let t = rep.triangles_max_angle_triangle.unwrap() as usize;
    assert!((input_angles(&pts, tris[t])[1] - rep.triangles_max_angle).abs() < 1e-9);
    let worst = input_angles(&pts, tris[t]);
    assert!(worst[0] < 1.0 && worst[1] > 179.0, "{worst:?}");
    for tr in &tris {
        let [lo, hi] = input_angles(&pts, *tr);
        assert!(lo >= rep.triangles_min_angle - 1e-9 && hi <= rep.triangles_max_angle + 1e-9);
    }
    // The worst tetrahedron left is below 15° and at that needle.
    let s = &rep.stuck[0];
    assert!(s.dihedral[0] < 15.0);
    assert!(s.dihedral[0] <= rep.after.min_dihedral + 1e-9);
    let near = s.near_triangle.unwrap() as usize;
    assert!(s.near_angles[0] < 1.0, "{:?}", s.near_angles);
    assert_eq!(input_angles(&pts, tris[near]), s.near_angles);
    // It is near the tetrahedron: within its longest edge.
    let p = r.mesh.tets[s.tet].map(|v| r.points[v as usize]);
    let reach = delone::tet::quality::edge_lengths(&p)
        .into_iter()
        .fold(0.0f64, f64::max);
    let c: [f64; 3] = std::array::from_fn(|k| p.iter().map(|q| q[k]).sum::<f64>() / 4.0);
    let d = tris[near]
        .iter()
        .map(|&v| {
            let q = pts[v as usize];
            (0..3).map(|k| (q[k] - c[k]).powi(2)).sum::<f64>().sqrt()
        })
        .fold(f64::INFINITY, f64::min);
    // (A vertex of the triangle is at most its longest edge farther.)
    let tri_len = (0..3)
        .map(|k| {
            let (a, b) = (
                pts[tris[near][k] as usize],
                pts[tris[near][(k + 1) % 3] as usize],
            );
            (0..3).map(|i| (a[i] - b[i]).powi(2)).sum::<f64>().sqrt()
        })
        .fold(0.0f64, f64::max);
    assert!(d <= reach + tri_len, "{d} > {reach} + {tri_len}");
}

/// The tetrahedra of `r` with two boundary faces, one of them thin: its
/// third vertex within a billionth of the shared edge's length of that
/// edge's line (an inexact Steiner point rounded onto a subsegment under a
/// chord). Their dihedral angles are 0° and 180°.
fn chord_slivers(r: &Recovered) -> usize {
    let on: std::collections::HashMap<[u32; 3], u32> = r
        .boundary
        .iter()
        .zip(&r.boundary_triangle)
        .map(|(f, &t)| {
            let mut k = *f;
            k.sort_unstable();
            (k, t)
        })
        .collect();
    let p = |q: u32| r.points[q as usize];
    let thin = |b: u32, c: u32, m: u32| {
        let (pb, pc, pm) = (p(b), p(c), p(m));
        let e: [f64; 3] = std::array::from_fn(|k| pc[k] - pb[k]);
        let d: [f64; 3] = std::array::from_fn(|k| pm[k] - pb[k]);
        let l2: f64 = e.iter().map(|x| x * x).sum();
        let u = e.iter().zip(&d).map(|(x, y)| x * y).sum::<f64>() / l2;
        let off2: f64 = (0..3).map(|k| (d[k] - u * e[k]).powi(2)).sum();
        u > 0.0 && u < 1.0 && off2 <= 1e-18 * l2
    };
    let mut n = 0;
    for (tv, nb) in r.mesh.tets.iter().zip(&r.mesh.neighbors) {
        let open: Vec<usize> = (0..4).filter(|&f| nb[f] == delone::NONE).collect();
        let &[f1, f2] = open.as_slice() else {
            continue;
        };
        let key = |f: usize| {
            let mut k: Vec<u32> = (0..4).filter(|&i| i != f).map(|i| tv[i]).collect();
            k.sort_unstable();
            [k[0], k[1], k[2]]
        };
        if !on.contains_key(&key(f1)) || !on.contains_key(&key(f2)) {
            continue;
        }
        let bc: Vec<u32> = (0..4)
            .filter(|&i| i != f1 && i != f2)
            .map(|i| tv[i])
            .collect();
        if thin(bc[0], bc[1], tv[f1]) || thin(bc[0], bc[1], tv[f2]) {
            n += 1;
        }
    }
    n
}

/// Recovery rounds some Steiner points onto their subsegment inexactly;
/// where the mesh keeps the chord over such a point, the cell between the
/// chord's face and the point's thin face is flat (0° and 180°). Recovery
/// removes it after carving: its other two faces become the triangle's
/// boundary faces. cgal_rotor and cgal_dino have one each.
#[test]
fn chord_slivers_are_removed_by_recovery() {
    let Some(dir) = corpus() else {
        return;
    };
    let mut removed = 0;
    for name in ["cgal_rotor", "cgal_dino"] {
        let (pts, tris) = read_model(&dir, name);
        let r = recover(&pts, &tris, &RecoverOptions::default()).unwrap();
        check_recovered(&pts, &tris, &r).unwrap_or_else(|v| panic!("{name}: {v:?}"));
        assert_eq!(chord_slivers(&r), 0, "{name}");
        assert_eq!(
            r.report.chord_slivers,
            r.report.chord_slivers.min(r.report.inexact_steiner),
            "{name}: more removed than inexact points"
        );
        removed += r.report.chord_slivers;
        let (pts, tris, mut r) = refined_model(name, 1.414).unwrap();
        assert_eq!(chord_slivers(&r), 0, "{name} refined");
        let vol = total_volume(&r);
        let rep = optimize(
            &mut r,
            &OptimizeOptions {
                input_points: Some(pts.len()),
                ..OptimizeOptions::level(3)
            },
        )
        .unwrap();
        check_recovered(&pts, &tris, &r).unwrap_or_else(|v| panic!("{name}: {v:?}"));
        assert!((total_volume(&r) - vol).abs() <= 1e-9 * vol, "{name}");
        assert_eq!(chord_slivers(&r), 0, "{name} optimised");
        assert_eq!(rep.flat_removed, 0, "{name}: left for the optimiser");
    }
    assert!(removed >= 2, "{removed}");
}

/// Refines (q1.414) and optimises (as `delone tet -pq1.414` does) every
/// closed-clean corpus model with `lo < n <= hi` input triangles, skipping
/// those with an input triangle angle below 15° or above 165° when
/// `clean_only`. Each mesh passes the checker with its volume; the report
/// counts exactly the tetrahedra outside 15°..165°; where the input allows
/// it (no surface angle below 15° and no input triangle angle outside
/// 15°..165°) there are none. Returns (models run, models within 15..165,
/// models the input allows, smallest minimum dihedral angle among those).
fn corpus_dihedral_bounds(lo: usize, hi: usize, clean_only: bool) -> Option<[f64; 4]> {
    let dir = corpus()?;
    let list = std::fs::read_to_string(dir.join("../../sets/closed_clean.txt")).unwrap();
    let (mut run, mut met, mut allowed_n, mut worst) = (0, 0, 0, 180f64);
    for line in list.lines() {
        let mut it = line.split_whitespace();
        let (Some(rel), Some(n)) = (it.next(), it.next()) else {
            continue;
        };
        let n = n.parse::<usize>().unwrap();
        if n <= lo || n > hi {
            continue;
        }
        let name = rel.trim_start_matches("surf/off/").trim_end_matches(".off");
        if clean_only {
            let (pts, tris) = read_model(&dir, name);
            if tris.iter().any(|&t| {
                let [a, b] = input_angles(&pts, t);
                a < BAD_ANGLE || b > 180.0 - BAD_ANGLE
            }) {
                continue;
            }
        }
        let (pts, tris, mut r) = refined_model(name, 1.414).unwrap();
        let vol = total_volume(&r);
        let rep = optimize(
            &mut r,
            &OptimizeOptions {
                input_points: Some(pts.len()),
                ..OptimizeOptions::default()
            },
        )
        .unwrap();
        check_recovered(&pts, &tris, &r).unwrap_or_else(|v| panic!("{name}: {v:?}"));
        assert!(
            (total_volume(&r) - vol).abs() <= 1e-9 * vol,
            "{name}: volume"
        );
        let outside = outside_bounds(&r);
        assert_eq!(rep.bad.count, outside, "{name}");
        assert_eq!(
            rep.bad.count,
            rep.bad.sharp_edge + rep.bad.at_feature + rep.bad.free,
            "{name}"
        );
        let allowed = rep.input_min_dihedral >= BAD_ANGLE
            && rep.triangles_min_angle >= BAD_ANGLE
            && rep.triangles_max_angle <= 180.0 - BAD_ANGLE;
        eprintln!(
            "{name}: {} tets, dihedral {:.2}..{:.2}, input allows: {allowed}, outside 15..165: {outside}",
            rep.after.tets, rep.after.min_dihedral, rep.after.max_dihedral
        );
        if allowed {
            assert_eq!(outside, 0, "{name}");
            allowed_n += 1;
            worst = worst.min(rep.after.min_dihedral);
        }
        run += 1;
        met += usize::from(outside == 0);
    }
    Some([run as f64, met as f64, allowed_n as f64, worst])
}

/// Every small closed-clean corpus model (up to 1000 input triangles):
/// see [`corpus_dihedral_bounds`].
#[test]
fn small_corpus_models_meet_the_dihedral_bounds_the_input_allows() {
    let Some([run, met, ..]) = corpus_dihedral_bounds(0, 1000, false) else {
        return;
    };
    assert_eq!(run, 15.0);
    // Today 12 of the 15 (cgal_pipe, cgal_dragknob, wm_supershape1 and
    // cgal_eight among them, whose input has needle triangles).
    assert!(met >= 12.0, "{met} models within 15..165");
}

/// The closed-clean corpus models from 1000 to 8000 input triangles with
/// no input triangle angle below 15° or above 165° (the models with small
/// input angles are run by the benchmark, not here: they take a minute):
/// every dihedral angle within 15°..165° (see [`corpus_dihedral_bounds`]).
/// Today all 7 reach 20° (cgal_cactus 21.0°, the lowest).
#[test]
fn medium_corpus_models_without_small_input_angles_meet_the_dihedral_bounds() {
    let Some([run, met, allowed, worst]) = corpus_dihedral_bounds(1000, 8000, true) else {
        return;
    };
    assert!(run >= 7.0, "{run}");
    assert_eq!(met, run);
    assert_eq!(allowed, run);
    eprintln!("smallest minimum: {worst:.2}");
}

/// An angle option that is not a number of degrees from 0 to 90 is a typed
/// error naming it, and the mesh is left as it was; the dihedral bound is
/// reported back in `BadCells::angle`.
#[test]
fn angle_options_out_of_range_are_errors() {
    use delone::tet::optimize::OptimizeError;
    let (pts, tris) = cube();
    let r0 = recover(&pts, &tris, &RecoverOptions::default()).unwrap();
    for (opts, name) in [
        (
            OptimizeOptions {
                min_dihedral: f64::NAN,
                ..Default::default()
            },
            "min_dihedral",
        ),
        (
            OptimizeOptions {
                min_dihedral: -1.0,
                ..Default::default()
            },
            "min_dihedral",
        ),
        (
            OptimizeOptions {
                target_dihedral: 91.0,
                ..Default::default()
            },
            "target_dihedral",
        ),
    ] {
        let mut r = r0.clone();
        let e = optimize(&mut r, &opts).unwrap_err();
        assert!(
            matches!(e, OptimizeError::InvalidAngle { option, .. } if option == name),
            "{e}"
        );
        assert!(e.to_string().contains(name));
        assert_eq!(r.mesh, r0.mesh);
    }
    let mut r = r0.clone();
    let rep = optimize(
        &mut r,
        &OptimizeOptions {
            min_dihedral: 25.0,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(rep.bad.angle, 25.0);
    assert_eq!(rep.bad.count, {
        r.mesh
            .tets
            .iter()
            .filter(|tv| {
                delone::tet::quality::dihedral_angles(&tv.map(|v| r.points[v as usize]))
                    .iter()
                    .any(|&x| !(25.0..=155.0).contains(&x))
            })
            .count()
    });
    check_recovered(&pts, &tris, &r).unwrap();
}

#[test]
fn stages_report_their_work_and_why_they_ended() {
    // The cube of `interior_slivers_in_a_cube_are_removed`, refined.
    let (pts, tris) = cube();
    let ro = RefineOptions {
        max_volume: Some(0.002),
        ..Default::default()
    };
    let fresh = || refine(&pts, &tris, &ro).unwrap().rec;
    let mut r = fresh();
    let rep = run(&pts, &tris, &mut r, &OptimizeOptions::default());
    assert_eq!(rep.stages.len(), rep.passes);
    assert!(!rep.stages.is_empty());
    // Rising thresholds up to the target, one run (a mesh inside the bound
    // is not optimised twice).
    let th: Vec<f64> = rep.stages.iter().map(|s| s.threshold).collect();
    assert!(th.windows(2).all(|w| w[0] < w[1]), "{th:?}");
    assert!(rep.stages.iter().all(|s| !s.second_run));
    let spent: u64 = rep.stages.iter().map(|s| s.evaluations).sum();
    assert!(spent > 0 && spent <= rep.evaluations);
    for (k, s) in rep.stages.iter().enumerate() {
        assert!(s.undone_evaluations <= s.evaluations);
        assert!(s.worst_reached <= s.evaluations);
        // The worst never falls: a stage that raised it by a degree says
        // when, one that left it says 0.
        if s.worst[1] > s.worst[0] + 1.0 {
            assert!(s.worst_reached > 0, "{s:?}");
        } else if s.worst[1] == s.worst[0] {
            assert_eq!(s.worst_reached, 0, "{s:?}");
        }
        assert!(s.successes <= s.attempts);
        // A stage starts where the one before it ended.
        if k > 0 {
            assert_eq!(s.worst[0], rep.stages[k - 1].worst[1]);
        }
        assert!(s.worst[1] >= s.worst[0] - 1e-9, "{s:?}");
        assert_ne!(s.stop, StageStop::Budget);
    }
    // With almost no effort a stage runs out and says so, and the run ends
    // there.
    let mut r = fresh();
    let tiny = OptimizeOptions {
        effort: Some(1e-3),
        ..Default::default()
    };
    let rep = run(&pts, &tris, &mut r, &tiny);
    assert!(rep.effort_exhausted);
    let last = rep.stages.last().unwrap();
    assert_eq!(last.stop, StageStop::Budget);
    let n = rep.stages.len();
    assert!(rep.stages[..n - 1]
        .iter()
        .all(|s| s.stop != StageStop::Budget));
}

#[test]
fn a_stage_pinned_by_the_input_stops_paying_and_says_so() {
    // cgal_handle at q1.414: the stages below 10° and 15° sit on a
    // tetrahedron pinned at 0° by the input; they end when they stop
    // paying, before the budget is spent.
    let Some((pts, tris, mut r)) = refined_model("cgal_handle", 1.414) else {
        return;
    };
    let rep = run(&pts, &tris, &mut r, &OptimizeOptions::default());
    let stalled: Vec<_> = rep
        .stages
        .iter()
        .filter(|s| s.stop == StageStop::Stalled)
        .collect();
    assert!(!stalled.is_empty(), "{:?}", rep.stages);
    for s in stalled {
        // It stopped because neither its worst nor its count improved
        // over the last half of its work: its worst stayed far below the
        // threshold.
        assert!(s.worst[1] < 0.5 * s.threshold, "{s:?}");
        assert!(s.evaluations > 0);
    }
}

#[test]
fn the_stuck_list_holds_the_worst_tetrahedra_worst_first() {
    // A refined cube optimised toward a target no mesh reaches: nearly
    // every tetrahedron is left below it, many more than the list holds.
    let (pts, tris) = cube();
    let ro = RefineOptions {
        max_radius_edge: Some(2.0),
        max_volume: Some(2e-3),
        ..Default::default()
    };
    let mut r = refine(&pts, &tris, &ro).unwrap().rec;
    let opts = OptimizeOptions {
        target_dihedral: 80.0,
        max_passes: 1,
        ..OptimizeOptions::default()
    };
    let rep = run(&pts, &tris, &mut r, &opts);
    let below: usize = rep.stuck_counts.iter().sum();
    assert!(below > 64, "{below}");
    assert_eq!(rep.stuck.len(), 32);
    // The quality the list is ordered by: the smallest sine of the six
    // dihedral angles.
    let dihedral = |t: usize| {
        delone::tet::quality::dihedral_angles(&r.mesh.tets[t].map(|v| r.points[v as usize]))
    };
    let q = |t: usize| {
        dihedral(t)
            .iter()
            .map(|a| a.to_radians().sin())
            .fold(f64::INFINITY, f64::min)
    };
    let listed: Vec<usize> = rep.stuck.iter().map(|s| s.tet).collect();
    for w in listed.windows(2) {
        assert!(w[0] != w[1] && q(w[0]) <= q(w[1]) + 1e-9, "{w:?}");
    }
    let last = q(listed[31]);
    for t in (0..r.mesh.tets.len()).filter(|t| !listed.contains(t)) {
        assert!(
            q(t) >= last - 1e-9,
            "tetrahedron {t} is worse than the list's last"
        );
    }
    for s in &rep.stuck {
        let d = dihedral(s.tet);
        let lo = d.iter().copied().fold(180.0, f64::min);
        assert!((s.dihedral[0] - lo).abs() < 1e-9);
    }
}

#[test]
fn the_second_run_is_tried_only_where_it_may_win() {
    // cgal_rotor at q1.414 stays below 15°; its first run's stage below
    // 15° runs out of budget. A second run is tried only where the first
    // spent its budget in its lowest stage or its stage at the bound
    // settled; the exhaustive polish tries it whenever the worst is free.
    let Some((pts, tris, r0)) = refined_model("cgal_rotor", 1.414) else {
        return;
    };
    let mut r = r0.clone();
    let def = run(&pts, &tris, &mut r, &OptimizeOptions::default());
    let first: Vec<_> = def.stages.iter().filter(|s| !s.second_run).collect();
    let may_win = first[0].stop == StageStop::Budget
        || first
            .iter()
            .any(|s| s.threshold == BAD_ANGLE && s.stop == StageStop::Settled);
    let second = def.stages.iter().any(|s| s.second_run);
    assert!(!second || may_win, "{:?}", def.stages);
    let mut r = r0;
    let exhaustive = OptimizeOptions {
        exhaustive: true,
        ..Default::default()
    };
    let ex = run(&pts, &tris, &mut r, &exhaustive);
    // No stage of the default run started within the bound: its first run
    // is the exhaustive one's, which keeps the better of its two runs.
    if first.iter().all(|s| s.worst[0] < BAD_ANGLE) {
        assert!(ex.evaluations >= def.evaluations);
        assert!(ex.after.min_dihedral >= def.after.min_dihedral - 1e-9);
    }
}
