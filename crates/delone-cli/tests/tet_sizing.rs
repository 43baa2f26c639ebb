//! `delone tet -m` (.mtr sizes) and `-r` (refine an existing mesh).

use std::path::PathBuf;
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_delone");

const CUBE: &str = "OFF\n8 12 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 0 1\n1 0 1\n0 1 1\n1 1 1\n\
3 0 2 1\n3 1 2 3\n3 4 5 6\n3 5 7 6\n3 0 1 4\n3 1 5 4\n3 2 6 3\n3 3 6 7\n3 0 4 2\n3 2 4 6\n3 1 3 5\n3 3 7 5\n";

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("delone-sizing-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn run(dir: &PathBuf, args: &[&str]) -> (bool, String) {
    let o = Command::new(BIN)
        .current_dir(dir)
        .args(args)
        .output()
        .unwrap();
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stdout).to_string() + &String::from_utf8_lossy(&o.stderr),
    )
}

fn count(path: &PathBuf) -> usize {
    let s = std::fs::read_to_string(path).unwrap();
    s.split_whitespace().next().unwrap().parse().unwrap()
}

#[test]
fn mtr_sizes_refine_and_r_refines_the_output() {
    let d = tmp("mtr");
    std::fs::write(d.join("cube.off"), CUBE).unwrap();
    let (ok, out) = run(&d, &["tet", "-p", "cube.off"]);
    assert!(ok, "{out}");
    let plain = count(&d.join("cube.1.ele"));
    // Small at point 0, large elsewhere, no constraint (0) at point 7.
    std::fs::write(
        d.join("cube.mtr"),
        "8 1\n0.1\n0.9\n0.9\n0.9\n0.9\n0.9\n0.9\n0\n",
    )
    .unwrap();
    let (ok, out) = run(&d, &["tet", "-pmC", "cube.off"]);
    assert!(ok && out.contains("check (-C): every"), "{out}");
    let sized = count(&d.join("cube.1.ele"));
    assert!(sized > 5 * plain, "{plain} -> {sized}");
    // -r on that output, with sizes for its points (uniform 0.3).
    let n = count(&d.join("cube.1.node"));
    let mtr: String = format!("{n} 1\n") + &"0.3\n".repeat(n);
    std::fs::write(d.join("cube.1.mtr"), mtr).unwrap();
    let (ok, out) = run(&d, &["tet", "-rq1.414mC", "--warn-unmet", "cube.1"]);
    assert!(ok && out.contains("check (-C): every"), "{out}");
    assert!(count(&d.join("cube.2.ele")) > sized, "{out}");
    assert!(d.join("cube.2.face").is_file());
    // A bad .mtr names its line.
    std::fs::write(d.join("cube.mtr"), "8 1\n0.1\nabc\n").unwrap();
    let (ok, out) = run(&d, &["tet", "-pm", "cube.off"]);
    assert!(!ok && out.contains("cube.mtr: line 3"), "{out}");
    std::fs::write(d.join("cube.mtr"), "3 1\n1\n1\n1\n").unwrap();
    let (ok, out) = run(&d, &["tet", "-pm", "cube.off"]);
    assert!(!ok && out.contains("3 sizes for 8 input points"), "{out}");
    // -m without -p/-r is a usage error; -m without a file an input error.
    let (ok, _) = run(&d, &["tet", "-m", "cube.1"]);
    assert!(!ok);
    std::fs::remove_file(d.join("cube.mtr")).unwrap();
    let (ok, out) = run(&d, &["tet", "-pm", "cube.off"]);
    assert!(!ok && out.contains("-m: neither"), "{out}");
    // An inverted tetrahedron in -r input is named.
    let ele = std::fs::read_to_string(d.join("cube.1.ele")).unwrap();
    let mut lines: Vec<String> = ele.lines().map(String::from).collect();
    let f: Vec<&str> = lines[2].split_whitespace().collect();
    lines[2] = format!("{} {} {} {} {}", f[0], f[2], f[1], f[3], f[4]);
    std::fs::write(d.join("cube.1.ele"), lines.join("\n") + "\n").unwrap();
    let (ok, out) = run(&d, &["tet", "-rq", "cube.1"]);
    assert!(!ok && out.contains("tetrahedron 1 is inverted"), "{out}");
    let _ = std::fs::remove_dir_all(&d);
}
