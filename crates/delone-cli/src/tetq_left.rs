//! The `-V` line telling why the refinement left cells above the
//! radius-edge bound ([`delone::tet::refine::LeftBad`]).

use delone::tet::refine::RefineReport;

/// `left above the bound: …` — the cells left by the refinement, by the
/// reason it gave up on each and by the input features near them.
pub fn left_line(r: &RefineReport) -> String {
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
    let list: Vec<String> = causes
        .iter()
        .filter(|c| c.0 > 0)
        .map(|(n, what)| format!("{n} {what}"))
        .collect();
    format!(
        "left above the bound: {} ({}); {} near an input triangle with an angle below 5 deg, {} near input triangles meeting below 60 deg",
        r.remaining_bad,
        list.join(", "),
        l.near_needle,
        l.near_sharp
    )
}
