//! "Every bound is met, or the run says so": elements of the final mesh
//! left outside a bound asked for give exit code 3 and a message by bound
//! and cause; `--warn-unmet` makes that a warning with exit code 0.

use std::path::Path;

mod common;
use common::{run, stderr, tmp};

/// A triangle with a 5° angle at the origin (and two of about 85° and 90°).
fn sharp_poly(dir: &Path) {
    let h = 10.0 * 5f64.to_radians().tan();
    std::fs::write(
        dir.join("sharp.poly"),
        format!("3 2 0 0\n1 0 0\n2 10 0\n3 10 {h}\n3 0\n1 1 2\n2 2 3\n3 3 1\n0\n"),
    )
    .unwrap();
}

/// The shared corpus file `rel` copied into `dir` (a file missing from the
/// corpus fails the test), or `None` when the corpus is missing and
/// `DELONE_NO_CORPUS` is set.
fn corpus(dir: &Path, rel: &str) -> Option<String> {
    let src = delone_testdata::corpus_path(env!("CARGO_MANIFEST_DIR"), rel)?;
    let bytes = std::fs::read(&src).unwrap_or_else(|e| panic!("{}: {e}", src.display()));
    let name = Path::new(rel)
        .file_name()
        .unwrap()
        .to_string_lossy()
        .into_owned();
    std::fs::write(dir.join(&name), bytes).unwrap();
    Some(name)
}

#[test]
fn tri_small_input_angle_exits_3_and_names_the_cause() {
    let d = tmp("tri3");
    sharp_poly(&d);
    let o = run(&d, &["tri", "-pq30", "sharp.poly"]);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(e.contains("bounds NOT met"), "{e}");
    assert!(e.contains("below the -q angle 30"), "{e}");
    assert!(e.contains("at input angles smaller than the bound"), "{e}");
    assert!(e.contains("--warn-unmet"), "{e}");
    // The mesh is written all the same.
    assert!(d.join("sharp.1.ele").is_file());
    // -Q: no message, the exit code stays.
    let q = run(&d, &["tri", "-Qpq30", "sharp.poly"]);
    assert_eq!(q.status.code(), Some(3));
    assert!(stderr(&q).is_empty(), "{}", stderr(&q));
}

#[test]
fn tri_warn_unmet_makes_it_a_warning() {
    let d = tmp("triw");
    sharp_poly(&d);
    let o = run(&d, &["tri", "-pq30", "--warn-unmet", "sharp.poly"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(e.contains("warning:"), "{e}");
    assert!(e.contains("at input angles smaller than the bound"), "{e}");
    assert!(!e.contains("bounds NOT met"), "{e}");
}

#[test]
fn tri_without_small_angles_meets_q30() {
    let d = tmp("tri0");
    std::fs::write(
        d.join("sq.poly"),
        "4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n",
    )
    .unwrap();
    let o = run(&d, &["tri", "-pq30a0.01", "sq.poly"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(stderr(&o).is_empty(), "{}", stderr(&o));
}

#[test]
fn warn_unmet_without_a_bound_is_refused() {
    let d = tmp("refuse");
    sharp_poly(&d);
    let o = run(&d, &["tri", "-p", "--warn-unmet", "sharp.poly"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--warn-unmet"), "{}", stderr(&o));
    assert!(!d.join("sharp.1.ele").exists());
    let o = run(&d, &["tet", "-p", "--warn-unmet", "sharp.smesh"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--warn-unmet"), "{}", stderr(&o));
}

#[test]
fn tet_sharp_input_exits_3_unless_warn_unmet() {
    let d = tmp("tet3");
    let Some(f) = corpus(&d, "3d_plc/td_spike_10_4.smesh") else {
        return;
    };
    let o = run(&d, &["tet", "-pq1.414/25", &f]);
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(e.contains("bounds NOT met"), "{e}");
    assert!(e.contains("dihedral angle below 25 deg"), "{e}");
    assert!(e.contains("needle or cap input triangles"), "{e}");
    assert!(d.join("td_spike_10_4.1.ele").is_file());
    let w = run(&d, &["tet", "-pq1.414/25", "--warn-unmet", &f]);
    assert_eq!(w.status.code(), Some(0), "{}", stderr(&w));
    assert!(stderr(&w).contains("warning:"), "{}", stderr(&w));
}

#[test]
fn tet_smooth_model_meets_the_ratio_and_the_volume() {
    let d = tmp("tet0");
    let Some(f) = corpus(&d, "surf/off/cgal_sphere.off") else {
        return;
    };
    for sw in ["-pq1.414", "-pa0.01"] {
        let o = run(&d, &["tet", sw, &f]);
        assert_eq!(o.status.code(), Some(0), "{sw}: {}", stderr(&o));
        assert!(!stderr(&o).contains("bounds NOT met"), "{}", stderr(&o));
    }
    // The optimisation raises some tetrahedra above the ratio: reported
    // with -V, not a missed bound.
    let v = run(&d, &["tet", "-pq1.414", "-V", &f]);
    assert_eq!(v.status.code(), Some(0));
    let out = String::from_utf8_lossy(&v.stdout);
    assert!(
        out.contains("raised above the -q ratio by the optimisation"),
        "{out}"
    );
    // With --keep-ratio the ratio is a bound of the final mesh.
    let k = run(&d, &["tet", "-pq1.414", "--keep-ratio", "-V", &f]);
    assert!(matches!(k.status.code(), Some(0) | Some(3)));
    let out = String::from_utf8_lossy(&k.stdout);
    let above: usize = out
        .split("bounds (final mesh): ")
        .nth(1)
        .and_then(|s| s.split_whitespace().next())
        .and_then(|n| n.parse().ok())
        .expect("bounds line");
    assert_eq!(k.status.code() == Some(3), above > 0, "{out}");
}
