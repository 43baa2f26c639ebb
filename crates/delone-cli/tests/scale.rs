//! Coordinates at every scale through the binary: the four cases of the
//! issue (a closed sphere at 1e120/1e-150 refused as self-intersecting,
//! `-C` failing at 1e-100 in 3D and at 1e-200 in 2D, statistics of NaN at
//! 1e300), the dynamic-range refusal, and the non-manifold corpus models.
//! The sphere and the non-manifold models come from `../shared/data`
//! (these tests fail when it is missing).

use std::path::{Path, PathBuf};
use std::process::Output;

mod common;
use common::{run, tmp};

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// `shared/data/surf/off/<name>` (the corpus is required here).
fn surf(name: &str) -> PathBuf {
    delone_testdata::corpus_path(env!("CARGO_MANIFEST_DIR"), &format!("surf/off/{name}"))
        .unwrap_or_else(|| panic!("surf/off/{name}: these tests need the shared corpus"))
}

/// An OFF file with every vertex coordinate multiplied by `f`.
fn scaled_off(src: &Path, f: f64) -> String {
    let t = std::fs::read_to_string(src).unwrap();
    let mut lines = t.lines();
    let mut out = vec![lines.next().unwrap().to_string()];
    let counts = lines.next().unwrap();
    let nv: usize = counts.split_whitespace().next().unwrap().parse().unwrap();
    out.push(counts.to_string());
    for _ in 0..nv {
        let l = lines.next().unwrap();
        let c: Vec<String> = l
            .split_whitespace()
            .map(|x| format!("{:?}", x.parse::<f64>().unwrap() * f))
            .collect();
        out.push(c.join(" "));
    }
    out.extend(lines.map(str::to_string));
    out.join("\n") + "\n"
}

/// The `quality:` line of `tet -V`.
fn quality(o: &Output) -> String {
    text(o)
        .lines()
        .find(|l| l.trim_start().starts_with("quality:"))
        .unwrap_or_else(|| panic!("no quality line:\n{}", text(o)))
        .to_string()
}

#[test]
fn sphere_at_extreme_scales_is_meshed_checked_and_measured() {
    let src = surf("cgal_sphere.off");
    let d = tmp("sphere");
    std::fs::copy(&src, d.join("s1.off")).unwrap();
    let o = run(&d, &["tet", "-pCV", "s1.off"]);
    assert!(o.status.success(), "{}", text(&o));
    let q1 = quality(&o);
    let dihedral = |q: &str| q.split(" deg").next().unwrap().to_string();
    for f in [1e120, 1e-150, 1e-100, 1e300, 1e-300] {
        let name = format!("s{f:e}.off");
        std::fs::write(d.join(&name), scaled_off(&src, f)).unwrap();
        let o = run(&d, &["tet", "-pCV", &name]);
        let t = text(&o);
        assert!(o.status.success(), "{f:e}: {t}");
        assert!(!t.contains("intersect"), "{f:e}: {t}");
        assert!(t.contains("check (-C): every input facet"), "{f:e}: {t}");
        assert!(!t.contains("FAILED") && !t.contains("NaN"), "{f:e}: {t}");
        // Same tetrahedra count and the same dihedral angles as at scale 1.
        assert!(t.contains("tetrahedra: 446 "), "{f:e}: {t}");
        assert_eq!(dihedral(&quality(&o)), dihedral(&q1), "{f:e}");
    }
}

#[test]
fn tri_check_at_1e_minus_200_with_a_region_point_of_another_magnitude() {
    // The mesh's points at 1e-200, the region point at scale 1 (outside
    // the domain): it must not set the checker's scale.
    let d = tmp("tri200");
    let poly = "4 2 0 0\n1 0 0\n2 1e-200 0\n3 1e-200 1e-200\n4 0 1e-200\n\
                4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n1\n1 25 0.5 7 0\n";
    std::fs::write(d.join("sq.poly"), poly).unwrap();
    let o = run(&d, &["tri", "-pqAC", "sq.poly"]);
    let t = text(&o);
    assert!(o.status.success(), "{t}");
    assert!(!t.contains("FAILED"), "{t}");
    // The statistics: angles of the right isosceles halves, area 1e-400
    // underflows to zero only in the total (it is below the doubles).
    let o = run(&d, &["tri", "-pV", "sq.poly"]);
    let t = text(&o);
    assert!(
        t.contains("minimum angle 45.0000, maximum angle 90.0000"),
        "{t}"
    );
}

#[test]
fn dynamic_range_beyond_exact_arithmetic_is_refused_naming_the_point() {
    let d = tmp("range");
    let node = "5 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 0.5 1e-60 0.5\n";
    std::fs::write(d.join("r.node"), node).unwrap();
    let o = run(&d, &["tet", "r.node"]);
    let t = text(&o);
    assert!(!o.status.success(), "{t}");
    assert!(t.contains("point 4 has y = 1e-60"), "{t}");
}

#[test]
fn non_manifold_models_are_regions_and_said_so() {
    for (name, regions) in [("cgal_cubes.off", 2), ("wm_thingi37989.off", 94)] {
        let d = tmp(name);
        std::fs::copy(surf(name), d.join(name)).unwrap();
        let o = run(&d, &["tet", "-pCV", name]);
        let t = text(&o);
        assert!(o.status.success(), "{name}: {t}");
        assert!(t.contains("non-manifold surface:"), "{name}: {t}");
        assert!(t.contains(&format!("regions: {regions} ")), "{name}: {t}");
        assert!(t.contains("check (-C): every input facet"), "{name}: {t}");
    }
}
