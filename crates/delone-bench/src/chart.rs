//! `delone-bench --dihedral-chart MODEL RATIO OUT.svg`: the dihedral-angle
//! distributions of delone's and TetGen's quality meshes of one corpus
//! model (`surf/off/MODEL.off`, `-pqRATIO` on both sides) as an SVG bar
//! chart — 5° bins, percentage of all dihedral angles per mesh, the
//! extreme angles in the legend.

use std::fmt::Write as _;

use delone::tet::quality::{dihedral_angles, TetStats};

use crate::cases::{Case, Input};

/// Width of a histogram bin, degrees.
const BIN: f64 = 5.0;
/// Number of bins over 0°–180°.
const NBINS: usize = 36;

/// One mesh's distribution: the share of its dihedral angles per bin.
struct Series {
    name: String,
    colour: &'static str,
    share: Vec<f64>,
    stats: TetStats,
}

fn series(name: String, colour: &'static str, pts: &[[f64; 3]], tets: &[[u32; 4]]) -> Series {
    let mut counts = vec![0usize; NBINS];
    for t in tets {
        for a in dihedral_angles(&t.map(|v| pts[v as usize])) {
            counts[((a / BIN) as usize).min(NBINS - 1)] += 1;
        }
    }
    let total = counts.iter().sum::<usize>().max(1) as f64;
    Series {
        name,
        colour,
        share: counts.iter().map(|&c| 100.0 * c as f64 / total).collect(),
        stats: TetStats::of(pts, tets),
    }
}

/// Runs both meshers on MODEL at radius-edge bound `ratio` and writes the
/// chart to `out`; returns a one-line summary.
pub fn run(model: &str, ratio: &str, out: &str) -> Result<String, String> {
    let case = Case::parse(&format!("3d-surfq-{model}-q{ratio}")).map_err(|e| e.to_string())?;
    let Input::Surf(s) = case.load()? else {
        return Err(format!("{model}: not a surface case"));
    };
    let q: f64 = ratio
        .parse()
        .map_err(|_| format!("bad radius-edge bound {ratio:?}"))?;
    let (dp, dt) = crate::child::delone_quality_mesh(&s.points, &s.triangles, q)?;
    let (tp, tt) = crate::refbin::tetgen_pq_mesh(&s.points, &s.triangles, q)?;
    let all = [
        series(format!("delone -pq{ratio}"), "#2f7fc1", &dp, &dt),
        series(format!("TetGen 1.6 -pq{ratio}"), "#e07b39", &tp, &tt),
    ];
    let svg = draw(&format!("{model}: dihedral angles"), &all);
    std::fs::write(out, svg).map_err(|e| format!("cannot write {out}: {e}"))?;
    Ok(all
        .iter()
        .map(|s| {
            format!(
                "{}: {} tets, dihedral {:.2}°–{:.2}°",
                s.name, s.stats.tets, s.stats.min_dihedral, s.stats.max_dihedral
            )
        })
        .collect::<Vec<_>>()
        .join("; "))
}

/// The SVG text of the grouped bar chart.
fn draw(title: &str, all: &[Series]) -> String {
    let (w, h) = (760.0, 360.0);
    let (l, r, t, b) = (56.0, 16.0, 40.0, 44.0);
    let ymax = all
        .iter()
        .flat_map(|s| s.share.iter().copied())
        .fold(1.0f64, f64::max);
    let ystep = [1.0, 2.0, 5.0, 10.0, 20.0]
        .into_iter()
        .find(|&s| ymax / s <= 6.0)
        .unwrap_or(25.0);
    let ytop = (ymax / ystep).ceil() * ystep;
    let x = |deg: f64| l + (w - l - r) * deg / 180.0;
    let y = |pc: f64| h - b - (h - t - b) * pc / ytop;
    let mut o = String::new();
    let _ = write!(
        o,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" \
         viewBox=\"0 0 {w} {h}\" font-family=\"sans-serif\" font-size=\"12\">\n\
         <rect width=\"{w}\" height=\"{h}\" fill=\"white\"/>\n\
         <text x=\"{}\" y=\"22\" text-anchor=\"middle\" font-size=\"15\">{title}</text>\n",
        w / 2.0
    );
    let mut k = 0.0;
    while k <= ytop + 1e-9 {
        let _ = writeln!(
            o,
            "<line x1=\"{l}\" x2=\"{}\" y1=\"{yy:.1}\" y2=\"{yy:.1}\" stroke=\"#ddd\"/>\
             <text x=\"{}\" y=\"{:.1}\" text-anchor=\"end\">{k}%</text>",
            w - r,
            l - 6.0,
            y(k) + 4.0,
            yy = y(k)
        );
        k += ystep;
    }
    for deg in (0..=180).step_by(30) {
        let _ = writeln!(
            o,
            "<text x=\"{:.1}\" y=\"{}\" text-anchor=\"middle\">{deg}°</text>",
            x(f64::from(deg)),
            h - b + 16.0
        );
    }
    let _ = writeln!(
        o,
        "<text x=\"{:.1}\" y=\"{}\" text-anchor=\"middle\">dihedral angle (5° bins; share of all angles of the mesh)</text>",
        (l + w - r) / 2.0,
        h - 8.0
    );
    let bw = (x(BIN) - x(0.0)) / all.len() as f64;
    for (si, s) in all.iter().enumerate() {
        for (i, &pc) in s.share.iter().enumerate() {
            if pc <= 0.0 {
                continue;
            }
            let x0 = x(i as f64 * BIN) + si as f64 * bw;
            let _ = writeln!(
                o,
                "<rect x=\"{x0:.2}\" y=\"{:.2}\" width=\"{:.2}\" height=\"{:.2}\" fill=\"{}\"/>",
                y(pc),
                bw * 0.92,
                (y(0.0) - y(pc)).max(0.5),
                s.colour
            );
        }
        let ly = t + 8.0 + 18.0 * si as f64;
        let _ = writeln!(
            o,
            "<rect x=\"{}\" y=\"{:.1}\" width=\"12\" height=\"12\" fill=\"{}\"/>\
             <text x=\"{}\" y=\"{:.1}\">{}: {} tetrahedra, dihedral angles {:.1}°–{:.1}°</text>",
            w - r - 380.0,
            ly,
            s.colour,
            w - r - 362.0,
            ly + 10.5,
            s.name,
            s.stats.tets,
            s.stats.min_dihedral,
            s.stats.max_dihedral
        );
    }
    let _ = writeln!(
        o,
        "<line x1=\"{l}\" x2=\"{}\" y1=\"{yy}\" y2=\"{yy}\" stroke=\"black\"/>\n</svg>",
        w - r,
        yy = y(0.0)
    );
    o
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shares_add_up_and_the_chart_names_both() {
        let pts = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        let a = series("a".into(), "#000", &pts, &[[0, 1, 2, 3]]);
        assert!((a.share.iter().sum::<f64>() - 100.0).abs() < 1e-9);
        // Three right angles (bin 18) and three of 54.7° (bin 10).
        assert!((a.share[18] - 50.0).abs() < 1e-9);
        assert!((a.share[10] - 50.0).abs() < 1e-9);
        let b = series("b".into(), "#fff", &pts, &[]);
        let svg = draw("t", &[a, b]);
        assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
        assert!(svg.contains("a: 1 tetrahedra") && svg.contains("b: 0 tetrahedra"));
    }
}
