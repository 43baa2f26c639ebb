//! `delone tet --png FILE`: a cut-away picture of the tetrahedral mesh
//! (delone-io's own renderer), the faces the cut exposes coloured by the
//! minimum dihedral angle of their tetrahedron:
//!
//! | colour | minimum dihedral angle |
//! | --- | --- |
//! | dark red | below 5° |
//! | red | 5°–10° |
//! | orange | 10°–15° |
//! | yellow | 15°–20° |
//! | light green | 20°–30° |
//! | green | 30° and above |
//!
//! `--cut x|y|z[=F]` cuts at fraction `F` (default 0.5) of the bounding box
//! along that axis and keeps the lower side; `--cut none` shows the whole
//! boundary. `--view AZ,EL` sets the camera's azimuth and elevation in
//! degrees (default -60,25); `--png-width` the width (the height is 3/4
//! of it).

use std::path::{Path, PathBuf};

use crate::args::Opts;
use crate::fail::Failure;
use crate::guard::write;

/// The colour of a tetrahedron whose minimum dihedral angle is `deg`.
pub fn dihedral_colour(deg: f64) -> [u8; 3] {
    match deg {
        d if d < 5.0 => [140, 0, 0],
        d if d < 10.0 => [220, 40, 30],
        d if d < 15.0 => [245, 140, 40],
        d if d < 20.0 => [245, 215, 60],
        d if d < 30.0 => [160, 215, 110],
        _ => [60, 160, 90],
    }
}

/// Writes the cut-away picture to `path` (pushed onto `written`).
pub fn write_png(
    o: &Opts,
    path: &Path,
    points: &[[f64; 3]],
    tets: &[[u32; 4]],
    written: &mut Vec<PathBuf>,
) -> Result<(), Failure> {
    let colours: Vec<[u8; 3]> = tets
        .iter()
        .map(|t| {
            let p = t.map(|v| points[v as usize]);
            let min = delone::tet::quality::dihedral_angles(&p)
                .into_iter()
                .fold(f64::INFINITY, f64::min);
            dihedral_colour(min)
        })
        .collect();
    let width = o.png_width.unwrap_or(800);
    let d = delone_io::CutawayStyle::default();
    let (azimuth, elevation) = o.view.unwrap_or((d.azimuth, d.elevation));
    let style = delone_io::CutawayStyle {
        width,
        height: (width * 3 / 4).max(16),
        azimuth,
        elevation,
        cut: o.cut.unwrap_or(d.cut),
        ..d
    };
    let img = delone_io::render_tets(points, tets, Some(&colours), &style)
        .map_err(|e| crate::fail::input_err(format!("{}: {e}", path.display())))?;
    write(path, |f| {
        delone_io::write_raster_png(std::io::BufWriter::new(f), &img)
    })?;
    written.push(path.to_path_buf());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colours_get_better_with_the_angle() {
        let greens: Vec<u8> = [1.0, 7.0, 12.0, 17.0, 25.0, 45.0]
            .iter()
            .map(|&d| dihedral_colour(d)[1])
            .collect();
        assert!(greens.windows(2).take(3).all(|w| w[0] < w[1]), "{greens:?}");
        assert_eq!(dihedral_colour(30.0), dihedral_colour(70.0));
    }
}
