//! Constrained Delaunay triangulation of every shared `.poly` PSLG, checked by
//! `check_cdt`.

use std::path::PathBuf;

use delone::tri::constrain::{check_cdt, constrained_triangulation, CdtOptions};

mod common;
use common::{data_dir, load_poly as load};

#[test]
fn every_shared_poly() {
    let Some(dir) = data_dir() else {
        println!("note: shared/data not found; skipping");
        return;
    };
    let mut names: Vec<PathBuf> = std::fs::read_dir(dir.join("2d"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "poly"))
        .collect();
    names.sort();
    assert!(names.len() >= 8, "expected the shared .poly files");
    for p in &names {
        let g = load(p);
        let open_outer = p.file_name().unwrap() == "box.poly";
        for convex_hull in [false, true] {
            let cdt = constrained_triangulation(&g, CdtOptions { convex_hull })
                .unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            check_cdt(&g, &cdt).unwrap_or_else(|v| panic!("{} -c={convex_hull}: {v}", p.display()));
            if convex_hull || !open_outer {
                assert!(!cdt.triangles.is_empty(), "{}", p.display());
            }
            println!(
                "{} c={convex_hull}: {} triangles, {} subsegments, {} crossings, {} vertex splits",
                p.file_name().unwrap().to_string_lossy(),
                cdt.triangles.len(),
                cdt.segments.len(),
                cdt.report.crossings.len(),
                cdt.report.vertex_splits.len()
            );
            // Deterministic.
            let again = constrained_triangulation(&g, CdtOptions { convex_hull }).unwrap();
            assert_eq!(cdt, again);
        }
    }
}
