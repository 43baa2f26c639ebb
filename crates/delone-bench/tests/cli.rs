//! End-to-end runs of the bench binary on tiny cases.

use std::process::Command;

fn bench(args: &[&str], env: &[(&str, &str)]) -> (String, String, bool) {
    let out = Command::new(env!("CARGO_BIN_EXE_delone-bench"))
        .args(args)
        .envs(env.iter().copied())
        .output()
        .expect("bench binary runs");
    (
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
        out.status.success(),
    )
}

/// The table rows (cells split on runs of two or more spaces) for `case`.
fn rows<'a>(table: &'a str, case: &str) -> Vec<Vec<&'a str>> {
    table
        .lines()
        .filter(|l| l.starts_with(case))
        .map(|l| {
            l.split("  ")
                .map(str::trim)
                .filter(|c| !c.is_empty())
                .collect()
        })
        .collect()
}

#[test]
fn plain_table_has_every_program_and_consistent_counts() {
    let (out, err, ok) = bench(
        &[
            "--cases",
            "2d-uniform-3000,3d-uniform-2000",
            "--repeat",
            "2",
        ],
        &[],
    );
    assert!(ok, "stderr: {err}");
    let r2 = rows(&out, "2d-uniform-3000");
    let r3 = rows(&out, "3d-uniform-2000");
    let progs: Vec<&str> = r2.iter().map(|r| r[2]).collect();
    assert_eq!(progs, ["delone", "triangle", "spade", "delaunator"]);
    assert_eq!(
        r3.iter().map(|r| r[2]).collect::<Vec<_>>(),
        ["delone", "tetgen"]
    );
    // The three 2D references agree on the element count (column 8).
    let count = |r: &Vec<&str>| r[7].parse::<usize>().expect("element count");
    let c = count(&r2[1]);
    assert!(c > 5900 && c < 5998, "{c}");
    assert_eq!(count(&r2[2]), c);
    assert_eq!(count(&r2[3]), c);
    // delone either reports an error or agrees with the references and
    // passes the determinism check.
    for (r, reference) in [(&r2[0], c), (&r3[0], count(&r3[1]))] {
        if r.iter().any(|c| c.starts_with("error:")) {
            assert!(out.contains("deterministic:"));
        } else {
            assert_eq!(count(r), reference);
            assert_eq!(r[10], "yes");
            assert_eq!(r[11], "yes");
        }
    }
    assert!(out.lines().any(|l| l.starts_with("deterministic:")));
    assert!(out.lines().any(|l| l.starts_with("valid:")));
}

#[test]
fn crashing_child_gives_failed_row_and_run_goes_on() {
    let (out, err, ok) = bench(
        &[
            "--cases",
            "2d-circle-1000",
            "--programs",
            "spade,delaunator",
            "--markdown",
        ],
        &[("DELONE_BENCH_ABORT_PROGRAM", "spade")],
    );
    assert!(ok, "stderr: {err}");
    let spade = out
        .lines()
        .find(|l| l.contains("| spade |"))
        .expect("spade row");
    assert!(spade.contains("failed: killed by signal 6"), "{spade}");
    let dl = out
        .lines()
        .find(|l| l.contains("| delaunator |"))
        .expect("delaunator row");
    assert!(!dl.contains("failed"), "{dl}");
    // Markdown: header, rule, two rows, each a complete table line.
    let table: Vec<&str> = out.lines().filter(|l| l.starts_with('|')).collect();
    assert_eq!(table.len(), 4);
    assert!(table[1].contains("---:"));
}

#[test]
fn bad_arguments_are_rejected() {
    let (_, err, ok) = bench(&["--cases", "5d-uniform-10"], &[]);
    assert!(!ok);
    assert!(err.contains("bad case name"), "{err}");
    let (out, _, ok) = bench(&["--list"], &[]);
    assert!(ok && out.contains("3d-grid-1e6") && out.contains("tetgen"));
}
