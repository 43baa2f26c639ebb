//! The results table, as aligned plain text or Markdown.

use crate::result::{Outcome, RunResult};

/// Column headers.
pub const HEADERS: &[&str] = &[
    "case",
    "n",
    "program",
    "time (s)",
    "peak RSS (MB)",
    "B/pt",
    "call B/pt",
    "elements",
    "delone/this time",
    "delone/this mem",
    "det",
    "valid",
    "note",
];

/// Right-aligned columns (numbers) in the plain table.
const NUMERIC: &[bool] = &[
    false, true, false, true, true, true, true, true, true, true, false, false, false,
];

fn fmt_time(t: f64) -> String {
    if !t.is_finite() {
        "-".into()
    } else if t >= 100.0 {
        format!("{t:.1}")
    } else if t >= 1.0 {
        format!("{t:.3}")
    } else {
        format!("{t:.4}")
    }
}

fn fmt_opt(v: Option<f64>, decimals: usize) -> String {
    v.filter(|x| x.is_finite())
        .map_or_else(|| "-".into(), |x| format!("{x:.decimals$}"))
}

fn ratio(a: Option<f64>, b: Option<f64>) -> String {
    match (a, b) {
        (Some(a), Some(b)) if a.is_finite() && b.is_finite() && b > 0.0 => {
            format!("{:.2}x", a / b)
        }
        _ => "-".into(),
    }
}

fn ok_time(r: &RunResult) -> Option<f64> {
    (r.outcome == Outcome::Ok).then_some(r.seconds)
}

fn ok_bpp(r: &RunResult) -> Option<f64> {
    (r.outcome == Outcome::Ok)
        .then(|| r.bytes_per_point())
        .flatten()
}

fn yes_no(v: Option<bool>) -> String {
    match v {
        Some(true) => "yes".into(),
        Some(false) => "NO".into(),
        None => "-".into(),
    }
}

/// One table row of cells per result, in the given order. Ratio columns
/// compare the delone row of the same case with this row (delone ÷ this).
pub fn rows(results: &[RunResult]) -> Vec<Vec<String>> {
    results
        .iter()
        .map(|r| {
            let delone = results
                .iter()
                .find(|d| d.case == r.case && d.program == "delone");
            let (tr, mr) = match delone {
                Some(d) if r.program != "delone" => {
                    (ratio(ok_time(d), ok_time(r)), ratio(ok_bpp(d), ok_bpp(r)))
                }
                _ => ("-".into(), "-".into()),
            };
            // Figures are shown for invalid results too (they are real
            // measurements), but ratios only between valid ones.
            let ok = matches!(r.outcome, Outcome::Ok | Outcome::Invalid(_));
            let mut note = match &r.outcome {
                Outcome::Ok if r.runs > 1 => format!("median of {}", r.runs),
                Outcome::Ok => String::new(),
                Outcome::Error(m) => format!("error: {m}"),
                Outcome::Invalid(m) => format!("INVALID: {m}"),
                Outcome::Failed(m) => format!("failed: {m}"),
            };
            if !r.info.is_empty() {
                if !note.is_empty() {
                    note.push_str("; ");
                }
                note.push_str(&r.info);
            }
            // Every triangulation of a 2D point set has the same number of
            // triangles, and the Delaunay tetrahedralization of points in
            // general position is unique: a differing count is worth a look.
            // (Not for the meshing cases: there the counts depend on where
            // each program puts its Steiner points.)
            let meshing = r.case.starts_with("2d-poly-") || r.case.starts_with("3d-surf-");
            if let Some(d) = delone.filter(|_| !meshing) {
                if r.program != "delone"
                    && ok
                    && matches!(d.outcome, Outcome::Ok | Outcome::Invalid(_))
                    && d.elements != r.elements
                {
                    if !note.is_empty() {
                        note.push_str("; ");
                    }
                    note.push_str(&format!("elements differ from delone ({})", d.elements));
                }
            }
            vec![
                r.case.clone(),
                r.n.to_string(),
                r.program.clone(),
                if ok { fmt_time(r.seconds) } else { "-".into() },
                fmt_opt(r.peak_kb.map(|k| k as f64 / 1024.0), 1),
                if ok {
                    fmt_opt(r.bytes_per_point(), 0)
                } else {
                    "-".into()
                },
                if ok {
                    fmt_opt(r.call_bytes_per_point(), 0)
                } else {
                    "-".into()
                },
                if ok {
                    r.elements.to_string()
                } else {
                    "-".into()
                },
                tr,
                mr,
                yes_no(r.deterministic),
                yes_no(r.valid),
                note,
            ]
        })
        .collect()
}

/// Aligned plain-text table.
pub fn plain(results: &[RunResult]) -> String {
    let rows = rows(results);
    let mut w: Vec<usize> = HEADERS.iter().map(|h| h.chars().count()).collect();
    for r in &rows {
        for (i, c) in r.iter().enumerate() {
            w[i] = w[i].max(c.chars().count());
        }
    }
    let line = |cells: &[String]| {
        let mut s = String::new();
        for (i, c) in cells.iter().enumerate() {
            if i > 0 {
                s.push_str("  ");
            }
            let pad = w[i] - c.chars().count();
            let last = i + 1 == cells.len();
            if NUMERIC[i] {
                s.push_str(&" ".repeat(pad));
                s.push_str(c);
            } else {
                s.push_str(c);
                if !last {
                    s.push_str(&" ".repeat(pad));
                }
            }
        }
        s.trim_end().to_string() + "\n"
    };
    let head: Vec<String> = HEADERS.iter().map(|h| h.to_string()).collect();
    let mut out = line(&head);
    let total: usize = w.iter().sum::<usize>() + 2 * (w.len() - 1);
    out.push_str(&"-".repeat(total.min(160)));
    out.push('\n');
    let mut prev_case: Option<&str> = None;
    for (r, cells) in results.iter().zip(&rows) {
        if prev_case.is_some_and(|p| p != r.case) {
            out.push('\n');
        }
        prev_case = Some(&r.case);
        out.push_str(&line(cells));
    }
    out
}

/// Markdown table.
pub fn markdown(results: &[RunResult]) -> String {
    let esc = |s: &str| s.replace('|', "\\|");
    let mut out = format!("| {} |\n", HEADERS.join(" | "));
    out.push('|');
    for (i, _) in HEADERS.iter().enumerate() {
        out.push_str(if NUMERIC[i] { " ---: |" } else { " --- |" });
    }
    out.push('\n');
    for cells in rows(results) {
        let cells: Vec<String> = cells.iter().map(|c| esc(c)).collect();
        out.push_str(&format!("| {} |\n", cells.join(" | ")));
    }
    out
}

/// The determinism summary line(s).
pub fn determinism(results: &[RunResult]) -> String {
    let checked: Vec<&RunResult> = results
        .iter()
        .filter(|r| r.deterministic.is_some())
        .collect();
    if checked.is_empty() {
        return "deterministic: not checked (no successful delone run)".into();
    }
    let bad: Vec<&str> = checked
        .iter()
        .filter(|r| r.deterministic == Some(false))
        .map(|r| r.case.as_str())
        .collect();
    if bad.is_empty() {
        format!(
            "deterministic: yes (delone output bit-identical across repeated runs in {} case(s))",
            checked.len()
        )
    } else {
        format!(
            "deterministic: NO (outputs differ between runs in: {})",
            bad.join(", ")
        )
    }
}

/// The validation summary line.
pub fn validity(results: &[RunResult]) -> String {
    let checked: Vec<&RunResult> = results.iter().filter(|r| r.valid.is_some()).collect();
    if checked.is_empty() {
        return "valid: not checked (no successful delone run)".into();
    }
    let bad: Vec<&str> = checked
        .iter()
        .filter(|r| r.valid == Some(false))
        .map(|r| r.case.as_str())
        .collect();
    if bad.is_empty() {
        format!(
            "valid: yes (delone output accepted by delone's validator in {} case(s))",
            checked.len()
        )
    } else {
        format!(
            "valid: NO (validator rejects delone's output in: {})",
            bad.join(", ")
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn r(case: &str, program: &str, seconds: f64, peak_kb: u64, outcome: Outcome) -> RunResult {
        RunResult {
            case: case.into(),
            program: program.into(),
            n: 1024,
            seconds,
            runs: 3,
            peak_kb: Some(peak_kb),
            base_kb: Some(1000),
            call_kb: Some(peak_kb - 1000),
            elements: 2000,
            deterministic: (program == "delone").then_some(true),
            valid: (program == "delone").then_some(true),
            info: String::new(),
            outcome,
        }
    }

    #[test]
    fn ratios_are_delone_over_reference() {
        let res = vec![
            r("c", "delone", 2.0, 1100, Outcome::Ok),
            r("c", "triangle", 1.0, 1200, Outcome::Ok),
            r("c", "spade", 1.0, 1200, Outcome::Failed("signal 11".into())),
        ];
        let rows = rows(&res);
        assert_eq!(rows[0][8], "-");
        assert_eq!(rows[1][8], "2.00x");
        // 100 kB vs 200 kB above baseline.
        assert_eq!(rows[1][9], "0.50x");
        assert_eq!(rows[1][5], "200");
        assert_eq!(rows[2][3], "-");
        assert_eq!(rows[2][8], "-");
        assert_eq!(rows[2][12], "failed: signal 11");
        assert_eq!(rows[0][10], "yes");
        assert_eq!(rows[0][11], "yes");
        assert_eq!(rows[1][11], "-");
        assert_eq!(rows[1][12], "median of 3");
    }

    #[test]
    fn invalid_delone_shows_figures_but_no_ratio() {
        let mut res = vec![
            r(
                "c",
                "delone",
                2.0,
                1100,
                Outcome::Invalid("tet 3 inverted".into()),
            ),
            r("c", "tetgen", 1.0, 1200, Outcome::Ok),
        ];
        res[0].valid = Some(false);
        let rows = rows(&res);
        assert_eq!(rows[0][3], "2.000");
        assert_eq!(rows[0][11], "NO");
        assert_eq!(rows[0][12], "INVALID: tet 3 inverted");
        assert_eq!(rows[1][8], "-");
        assert_eq!(rows[1][9], "-");
    }

    #[test]
    fn differing_element_count_is_flagged() {
        let mut res = vec![
            r("c", "delone", 2.0, 1100, Outcome::Ok),
            r("c", "tetgen", 1.0, 1200, Outcome::Ok),
        ];
        res[1].elements = 1999;
        let rows = rows(&res);
        assert_eq!(
            rows[1][12],
            "median of 3; elements differ from delone (2000)"
        );
        assert_eq!(rows[0][12], "median of 3");
    }

    #[test]
    fn delone_error_gives_no_ratio() {
        let res = vec![
            r(
                "c",
                "delone",
                f64::NAN,
                1100,
                Outcome::Error("not implemented".into()),
            ),
            r("c", "triangle", 1.0, 1200, Outcome::Ok),
        ];
        let rows = rows(&res);
        assert_eq!(rows[1][8], "-");
        assert_eq!(rows[0][12], "error: not implemented");
        let t = plain(&res);
        assert!(t.contains("error: not implemented"));
        let m = markdown(&res);
        assert_eq!(m.lines().count(), 4);
        assert!(m.lines().all(|l| l.starts_with('|') && l.ends_with('|')));
    }

    #[test]
    fn determinism_summary() {
        let mut res = vec![r("a", "delone", 1.0, 1100, Outcome::Ok)];
        assert!(determinism(&res).starts_with("deterministic: yes"));
        res.push(r("b", "delone", 1.0, 1100, Outcome::Ok));
        res[1].deterministic = Some(false);
        assert!(determinism(&res).contains("NO"));
        assert!(determinism(&res).contains('b'));
        assert!(determinism(&[]).contains("not checked"));
    }

    #[test]
    fn validity_summary() {
        let mut res = vec![r("a", "delone", 1.0, 1100, Outcome::Ok)];
        assert!(validity(&res).starts_with("valid: yes"));
        res.push(r("b", "delone", 1.0, 1100, Outcome::Invalid("x".into())));
        res[1].valid = Some(false);
        assert_eq!(
            validity(&res),
            "valid: NO (validator rejects delone's output in: b)"
        );
        assert!(validity(&[]).contains("not checked"));
    }
}
