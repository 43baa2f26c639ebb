//! The 3D kernel on real-world point sets: the vertices of every surface
//! model in `../shared/data/surf/off` (scans, CAD parts — many coplanar and
//! cocircular subsets), each checked by the independent validator.

use std::path::PathBuf;

/// `shared/data/surf/off`, found by walking up from the crate (the checkout
/// may sit at any depth beside `shared/`).
fn data_dir() -> Option<PathBuf> {
    delone_testdata::corpus_path(env!("CARGO_MANIFEST_DIR"), "surf/off")
}

/// The vertices of an OFF file (header `OFF`, then `nv nf ne`, then vertices).
fn off_vertices(text: &str) -> Vec<[f64; 3]> {
    let mut tokens = text
        .lines()
        .map(|l| l.split('#').next().unwrap_or(""))
        .flat_map(str::split_whitespace);
    let first = tokens.next().expect("empty OFF file");
    let nv: usize = if first == "OFF" {
        tokens
            .next()
            .expect("no counts")
            .parse()
            .expect("bad vertex count")
    } else {
        first
            .trim_start_matches("OFF")
            .parse()
            .expect("bad vertex count")
    };
    tokens.next();
    tokens.next();
    (0..nv)
        .map(|_| {
            let mut c = [0.0; 3];
            for x in c.iter_mut() {
                *x = tokens
                    .next()
                    .expect("truncated OFF")
                    .parse()
                    .expect("bad coordinate");
            }
            c
        })
        .collect()
}

fn run(limit: std::ops::Range<usize>) {
    let Some(dir) = data_dir() else { return };
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "off"))
        .collect();
    files.sort();
    let mut checked = 0;
    for f in files {
        let pts = off_vertices(&std::fs::read_to_string(&f).unwrap());
        if !limit.contains(&pts.len()) {
            continue;
        }
        let mesh = delone::tetrahedralize(&pts).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        delone::tet::validate(&pts, &mesh).unwrap_or_else(|v| panic!("{}: {v}", f.display()));
        checked += 1;
    }
    eprintln!("checked {checked} models with {limit:?} vertices");
}

#[test]
fn surface_model_vertices_small_and_medium() {
    run(0..50_001);
}

#[test]
#[ignore = "large models: cargo test -p delone --test tet_shared_data -- --ignored"]
fn surface_model_vertices_large() {
    run(50_001..usize::MAX);
}
