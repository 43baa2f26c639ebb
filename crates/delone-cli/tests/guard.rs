//! Refinement never runs without bound: bounds no mesh can meet are
//! refused (exit code 2, the switch named), bounds refinement cannot reach
//! stop at the Steiner budget (exit code 1, a message naming `-S`, the mesh
//! reached written), and `-S` raises the budget.

use std::path::Path;

mod common;
use common::{run, stderr, tmp};

/// The shared 2D corpus file `name` copied into `dir` (None: the corpus is
/// opted out with `DELONE_NO_CORPUS=1`; missing, it fails the test).
fn corpus_2d(dir: &Path, name: &str) -> Option<()> {
    let src = delone_testdata::corpus_path(env!("CARGO_MANIFEST_DIR"), &format!("2d/{name}"))?;
    std::fs::copy(src, dir.join(name)).unwrap();
    Some(())
}

/// Number of points in a `.node` file (its header's first number).
fn node_count(path: &Path) -> usize {
    let text = std::fs::read_to_string(path).unwrap();
    let header = text
        .lines()
        .find(|l| !l.trim().is_empty() && !l.trim_start().starts_with('#'))
        .unwrap();
    header.split_whitespace().next().unwrap().parse().unwrap()
}

/// Points of A.poly's own `.node` part (the input vertex count).
fn input_points(dir: &Path) -> usize {
    node_count(&dir.join("A.poly"))
}

#[test]
fn tri_q40_stops_at_the_default_budget() {
    let d = tmp("q40");
    let Some(()) = corpus_2d(&d, "A.poly") else {
        return;
    };
    let n = input_points(&d);
    let o = run(&d, &["tri", "-pq40", "A.poly"]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(e.contains("Steiner budget of") && e.contains("-S"), "{e}");
    assert!(e.contains("MB"), "{e}");
    let budget = 2_000_000 + 16 * n;
    let got = node_count(&d.join("A.1.node"));
    assert!(got <= n + budget, "{got} points, budget {budget}");
    assert!(got > n + budget / 2, "{got} points: stopped early?");
}

#[test]
fn tri_s_raises_the_budget_and_stats_json_reports_it() {
    let d = tmp("s");
    let Some(()) = corpus_2d(&d, "A.poly") else {
        return;
    };
    let n = input_points(&d);
    let mut counts = Vec::new();
    for s in [5000usize, 20000] {
        let sw = format!("-pq40S{s}");
        let o = run(&d, &["tri", &sw, "A.poly", "--stats-json", "s.json"]);
        assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
        assert!(stderr(&o).contains(&format!("Steiner budget of {s} points")));
        let got = node_count(&d.join("A.1.node"));
        assert!(got <= n + s, "{got} > {n} + {s}");
        counts.push(got);
        let j = std::fs::read_to_string(d.join("s.json")).unwrap();
        assert!(j.contains("\"budget_exhausted\": true"), "{j}");
        assert!(j.contains(&format!("\"steiner_budget\": {s}")), "{j}");
    }
    assert!(counts[1] > counts[0] + 10_000, "{counts:?}");
    // A reachable bound: met, exit 0, no budget message.
    let o = run(&d, &["tri", "-pq30", "A.poly", "--stats-json", "s.json"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(!stderr(&o).contains("budget"));
    let j = std::fs::read_to_string(d.join("s.json")).unwrap();
    assert!(j.contains("\"met\": true") && j.contains("\"budget_exhausted\": false"));
}

#[test]
fn tri_q60_is_refused() {
    let d = tmp("q60");
    let Some(()) = corpus_2d(&d, "A.poly") else {
        return;
    };
    let o = run(&d, &["tri", "-pq60", "A.poly"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("-q60"), "{}", stderr(&o));
    assert!(!d.join("A.1.node").exists());
}

/// A unit cube as an OFF surface.
fn cube(dir: &Path) {
    let mut s = String::from("OFF\n8 12 0\n");
    for i in 0..8 {
        s += &format!("{} {} {}\n", i & 1, (i >> 1) & 1, (i >> 2) & 1);
    }
    for t in [
        [0, 2, 1],
        [1, 2, 3],
        [4, 5, 6],
        [5, 7, 6],
        [0, 1, 4],
        [1, 5, 4],
        [2, 6, 3],
        [3, 6, 7],
        [0, 4, 2],
        [2, 4, 6],
        [1, 3, 5],
        [3, 7, 5],
    ] {
        s += &format!("3 {} {} {}\n", t[0], t[1], t[2]);
    }
    std::fs::write(dir.join("cube.off"), s).unwrap();
}

#[test]
fn tet_q05_is_refused() {
    let d = tmp("tq");
    cube(&d);
    for q in ["-pq0.5", "-pq0.6"] {
        let o = run(&d, &["tet", q, "cube.off"]);
        assert_eq!(o.status.code(), Some(2), "{q}: {}", stderr(&o));
        let e = stderr(&o);
        assert!(e.contains(&q[2..]) && e.contains("sqrt(6)/4"), "{e}");
        assert!(!d.join("cube.1.node").exists());
    }
    let o = run(&d, &["tet", "-pq0.62S100", "cube.off"]);
    assert_ne!(o.status.code(), Some(2), "{}", stderr(&o));
}

#[test]
fn tet_budget_stop_exits_nonzero_and_s_raises_it() {
    let d = tmp("ta");
    cube(&d);
    let o = run(&d, &["tet", "-pa0.000001S300", "cube.off", "-V"]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("Steiner budget of 300 points") && e.contains("-S"),
        "{e}"
    );
    let out = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(out.contains("Steiner budget exhausted"), "{out}");
    // A budget large enough: the bound is met, exit 0.
    let o = run(&d, &["tet", "-pa0.01S100000", "cube.off"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(!stderr(&o).contains("budget"));
}

/// A volume bound beyond the largest default budget is refused at once
/// (instead of a run of many minutes that stops at the budget), naming -S.
#[test]
fn tet_tiny_volume_bound_is_refused_without_s() {
    let d = tmp("tv");
    cube(&d);
    let o = run(&d, &["tet", "-pa1e-9", "cube.off"]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("-a1e-9 asks for about") && e.contains("Steiner points") && e.contains("-S"),
        "{e}"
    );
    assert!(!d.join("cube.1.node").exists());
}

/// A volume bound of zero is refused (it was dropped, meshing without it).
#[test]
fn tet_zero_volume_bound_is_refused() {
    let d = tmp("a0");
    cube(&d);
    let o = run(&d, &["tet", "-pa0", "cube.off"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("-a0: the maximum volume must be positive"));
    assert!(!d.join("cube.1.node").exists());
}
