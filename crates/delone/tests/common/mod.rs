//! Helpers shared by the integration tests that read `../shared/data`.

use std::path::{Path, PathBuf};

use delone::model::pslg::{Pslg, Region};

/// `shared/data`, found by walking up from the crate directory; panics when
/// it is missing unless `DELONE_NO_CORPUS=1` (see `delone_testdata`).
pub fn data_dir() -> Option<PathBuf> {
    delone_testdata::corpus_dir(env!("CARGO_MANIFEST_DIR"))
}

/// A Triangle `.poly` file as a [`Pslg`] (points inline in the file).
pub fn load_poly(path: &Path) -> Pslg {
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
