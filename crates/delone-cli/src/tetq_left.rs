//! The `-V` line telling why the refinement left cells above the
//! radius-edge bound ([`delone::tet::refine::LeftBad`]).

use delone::tet::refine::RefineReport;

/// The reasons the refinement gave up on the cells it left above the
/// bound, with their counts (`3 sharp wedge, 1 flat`), and the input
/// features near them.
pub fn causes(r: &RefineReport) -> String {
    let l = &r.left;
    let mut s = reasons(r).join(", ");
    if l.near_needle > 0 || l.near_sharp > 0 {
        s.push_str(&format!(
            "; {} near an input triangle with an angle below 5 deg, {} near input triangles meeting below 60 deg",
            l.near_needle, l.near_sharp
        ));
    }
    s
}

fn reasons(r: &RefineReport) -> Vec<String> {
    let l = &r.left;
    let causes = [
        (l.close, "circumcentre near a vertex"),
        (l.radius, "insertion radius"),
        (l.small, "small pieces"),
        (l.behind, "behind a subface"),
        (l.wedge, "sharp wedge"),
        (l.degenerate, "zero-angle triangle"),
        (l.shell, "shell pair"),
        (l.flat, "flat"),
        (l.refused, "refused"),
        (l.surface, "kept surface (-Y)"),
        (l.other, "other"),
    ];
    causes
        .iter()
        .filter(|c| c.0 > 0)
        .map(|(n, what)| format!("{n} {what}"))
        .collect()
}

/// `left above the bound: …` — the cells left by the refinement, by the
/// reason it gave up on each and by the input features near them.
pub fn left_line(r: &RefineReport) -> String {
    let l = &r.left;
    format!(
        "left above the bound: {} ({}); {} near an input triangle with an angle below 5 deg, {} near input triangles meeting below 60 deg",
        r.remaining_bad,
        reasons(r).join(", "),
        l.near_needle,
        l.near_sharp
    )
}
