//! Constrained Delaunay triangulation of every shared `.poly` PSLG, checked by
//! `check_cdt`.

use std::path::PathBuf;

use delone::model::pslg::{Pslg, Region};
use delone::tri::constrain::{check_cdt, constrained_triangulation, CdtOptions};

/// `shared/data`, found by walking up from the crate directory.
fn data_dir() -> Option<PathBuf> {
    let mut d = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    loop {
        let c = d.join("shared/data");
        if c.is_dir() {
            return Some(c);
        }
        if !d.pop() {
            return None;
        }
    }
}

fn load(path: &std::path::Path) -> Pslg {
    let f = delone_io::read_poly(&std::fs::read(path).unwrap()).unwrap();
    let points = f.node.points::<2>().unwrap();
    let segments = f.segments_zero_based(f.node.first_index).unwrap();
    Pslg {
        point_markers: f.node.markers.clone().unwrap_or_default(),
        points,
        segments,
        segment_markers: f.segment_markers.clone().unwrap_or_default(),
        holes: f.holes.clone(),
        regions: f
            .regions
            .iter()
            .map(|r| Region {
                point: [r[0], r[1]],
                attribute: r[2],
                max_area: r[3],
            })
            .collect(),
    }
}

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
