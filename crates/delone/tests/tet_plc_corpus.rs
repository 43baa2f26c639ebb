//! The PLC model and the 3D input checks on the shared corpus:
//! self-intersection flags agree with `sets/self_intersecting.txt` and
//! `sets/closed_clean.txt`, open/non-manifold models are reported as open,
//! every TetGen PLC reads into a valid [`Plc`].

use delone::model::plc::{Facet, Plc, Region};
use delone::tet::intersect::{manifold_report, self_intersections};
use std::path::PathBuf;
use std::time::Instant;

fn data_dir() -> Option<PathBuf> {
    delone_testdata::corpus_dir(env!("CARGO_MANIFEST_DIR"))
}

/// (path relative to data, triangle count) of a set file.
fn set(dir: &std::path::Path, name: &str) -> Vec<(String, usize)> {
    std::fs::read_to_string(dir.join("sets").join(name))
        .unwrap()
        .lines()
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let mut it = l.split_whitespace();
            (
                it.next().unwrap().to_string(),
                it.next().unwrap().parse().unwrap(),
            )
        })
        .collect()
}

fn load(dir: &std::path::Path, rel: &str) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let s = delone_io::read_off(&std::fs::read(dir.join(rel)).unwrap()).unwrap();
    let t = s.triangles();
    (s.points, t)
}

fn run(
    set_name: &str,
    range: std::ops::RangeInclusive<usize>,
    check: impl Fn(&str, &[[f64; 3]], &[[u32; 3]]),
) {
    let Some(dir) = data_dir() else { return };
    let mut n = 0;
    for (rel, nf) in set(&dir, set_name) {
        if !range.contains(&nf) {
            continue;
        }
        let (p, t) = load(&dir, &rel);
        check(&rel, &p, &t);
        n += 1;
    }
    eprintln!("{set_name}: checked {n} models with {range:?} triangles");
}

fn flagged(rel: &str, p: &[[f64; 3]], t: &[[u32; 3]]) {
    let t0 = Instant::now();
    let r = self_intersections(p, t);
    eprintln!(
        "{rel}: {} triangles, {} intersecting pairs, {} zero-area, {:.3} s",
        t.len(),
        r.pairs.len(),
        r.degenerate.len(),
        t0.elapsed().as_secs_f64()
    );
    assert!(
        !r.is_clean(),
        "{rel} is listed as self-intersecting but none was found"
    );
}

fn clean(rel: &str, p: &[[f64; 3]], t: &[[u32; 3]]) {
    let t0 = Instant::now();
    let r = self_intersections(p, t);
    eprintln!(
        "{rel}: {} triangles, {:.3} s",
        t.len(),
        t0.elapsed().as_secs_f64()
    );
    assert!(
        r.is_clean(),
        "{rel}: pairs {:?}, zero-area {:?}",
        &r.pairs[..r.pairs.len().min(10)],
        r.degenerate
    );
    let m = manifold_report(t);
    assert!(m.is_oriented_closed(), "{rel}: {m:?}");
}

fn open(rel: &str, _p: &[[f64; 3]], t: &[[u32; 3]]) {
    let m = manifold_report(t);
    eprintln!(
        "{rel}: {} boundary, {} non-manifold, {} inconsistent edges",
        m.boundary_edges.len(),
        m.nonmanifold_edges.len(),
        m.inconsistent_edges.len()
    );
    assert!(
        !m.is_closed(),
        "{rel} is listed as open or non-manifold but every edge has two faces"
    );
}

#[test]
fn self_intersecting_models_are_flagged() {
    run("self_intersecting.txt", 0..=60_000, flagged);
}

#[test]
#[ignore = "large models: cargo test -p delone --test tet_plc_corpus -- --ignored"]
fn self_intersecting_models_are_flagged_large() {
    run("self_intersecting.txt", 60_001..=usize::MAX, flagged);
}

#[test]
fn closed_clean_models_are_clean_and_closed() {
    run("closed_clean.txt", 0..=60_000, clean);
}

#[test]
#[ignore = "large models: cargo test -p delone --test tet_plc_corpus -- --ignored"]
fn closed_clean_models_are_clean_and_closed_large() {
    run("closed_clean.txt", 60_001..=usize::MAX, clean);
}

#[test]
fn open_models_are_reported_open() {
    run("open_or_nonmanifold.txt", 0..=usize::MAX, open);
}

#[test]
fn tetgen_plcs_are_valid() {
    let Some(dir) = data_dir() else { return };
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir.join("3d_plc"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    for path in files {
        let bytes = std::fs::read(&path).unwrap();
        let f = if path.extension().is_some_and(|e| e == "poly") {
            delone_io::read_poly3d(&bytes)
        } else {
            delone_io::read_smesh(&bytes)
        }
        .unwrap();
        let plc = Plc {
            points: f.points,
            facets: f
                .facets
                .into_iter()
                .map(|fc| Facet {
                    polygons: fc.polygons,
                    holes: fc.holes,
                    marker: fc.marker,
                })
                .collect(),
            segments: Vec::new(),
            holes: f.holes,
            regions: f
                .regions
                .into_iter()
                .map(|r| Region {
                    point: r.point,
                    attribute: r.attribute,
                    max_volume: r.max_volume,
                })
                .collect(),
        };
        plc.validate()
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        // Moving one point of a facet off its plane must be caught.
        let mut bent = plc.clone();
        let fi = bent
            .facets
            .iter()
            .position(|f| f.polygons.iter().flatten().count() >= 4);
        if let Some(fi) = fi {
            let v = bent.facets[fi].polygons[0][0] as usize;
            bent.points[v][2] += 1e-3;
            assert!(
                bent.validate().is_err(),
                "{}: bent facet {fi} not caught",
                path.display()
            );
        }
    }
}

/// Order independence and a planted defect: shuffling the triangles of a
/// clean model keeps it clean; pushing one vertex through the opposite side
/// of a closed model must create intersections, found identically whatever
/// the triangle order.
#[test]
fn planted_intersection_is_found_in_any_order() {
    let Some(dir) = data_dir() else { return };
    let (mut p, t) = load(&dir, "surf/off/cgal_sphere.off");
    assert!(self_intersections(&p, &t).is_clean());
    // Reflect vertex 0 through the centroid: it pokes through the far side.
    let n = p.len() as f64;
    let c = [0, 1, 2].map(|k| p.iter().map(|q| q[k]).sum::<f64>() / n);
    p[0] = [0, 1, 2].map(|k| c[k] + 1.5 * (c[k] - p[0][k]));
    let r = self_intersections(&p, &t);
    assert!(!r.pairs.is_empty());
    for &(i, j) in &r.pairs {
        assert!(i < j);
        assert!(
            t[i as usize].contains(&0) || t[j as usize].contains(&0),
            "pair ({i}, {j}) does not involve the moved vertex"
        );
    }
    // A fixed permutation of the triangles gives the permuted pairs.
    let m = t.len();
    let perm: Vec<usize> = (0..m).map(|i| (i * 7919 + 13) % m).collect();
    let mut seen = vec![false; m];
    assert!(perm.iter().all(|&k| !std::mem::replace(&mut seen[k], true)));
    let t2: Vec<[u32; 3]> = perm.iter().map(|&k| t[k]).collect();
    let r2 = self_intersections(&p, &t2);
    let mut back: Vec<(u32, u32)> = r2
        .pairs
        .iter()
        .map(|&(i, j)| {
            let (a, b) = (perm[i as usize] as u32, perm[j as usize] as u32);
            (a.min(b), a.max(b))
        })
        .collect();
    back.sort_unstable();
    assert_eq!(back, r.pairs);
    assert_eq!(self_intersections(&p, &t), r, "not deterministic");
}
