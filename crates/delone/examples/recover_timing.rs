//! Times `delone::tet::recover::recover` on an OFF surface.
//!
//! `cargo run --release -p delone --example recover_timing -- FILE.off`
use std::time::Instant;

fn main() {
    let path = std::env::args()
        .nth(1)
        .expect("usage: recover_timing FILE.off");
    let text = std::fs::read_to_string(&path).expect("read");
    let mut it = text
        .lines()
        .map(|l| l.split('#').next().unwrap_or("").trim())
        .filter(|l| !l.is_empty());
    let first = it.next().expect("header");
    let counts = if first == "OFF" {
        it.next().expect("counts")
    } else {
        first.trim_start_matches("OFF")
    };
    let c: Vec<usize> = counts
        .split_whitespace()
        .map(|s| s.parse().unwrap())
        .collect();
    let pts: Vec<[f64; 3]> = (0..c[0])
        .map(|_| {
            let v: Vec<f64> = it
                .next()
                .unwrap()
                .split_whitespace()
                .map(|s| s.parse().unwrap())
                .collect();
            [v[0], v[1], v[2]]
        })
        .collect();
    let mut tris = Vec::new();
    for _ in 0..c[1] {
        let v: Vec<u32> = it
            .next()
            .unwrap()
            .split_whitespace()
            .map(|s| s.parse().unwrap())
            .collect();
        for k in 2..v[0] as usize {
            tris.push([v[1], v[k], v[k + 1]]);
        }
    }
    let t = Instant::now();
    let r = delone::tet::recover::recover(
        &pts,
        &tris,
        &delone::tet::recover::RecoverOptions::default(),
    );
    let dt = t.elapsed().as_secs_f64();
    match r {
        Ok(r) => {
            println!("time={dt:.3}s tets={} {:?}", r.mesh.tets.len(), r.report);
            if std::env::var("CHECK").is_ok() {
                delone::tet::recover::check_recovered(&pts, &tris, &r).expect("check");
                println!("check ok");
            }
        }
        Err(e) => println!("time={dt:.3}s error {e}"),
    }
}
