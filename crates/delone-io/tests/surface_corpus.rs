//! Every surface in `shared/data/surf/orig` read by its own reader gives the
//! same mesh as its ASCII OFF conversion in `surf/off` and the counts of
//! `surf/stats.json`; every TetGen PLC in `shared/data/3d_plc` reads.

use std::path::{Path, PathBuf};

fn data_dir() -> Option<PathBuf> {
    delone_testdata::corpus_dir(env!("CARGO_MANIFEST_DIR"))
}

/// (name, orig path, V, F) from stats.json (a tiny scanner, no JSON crate).
fn stats(dir: &Path) -> Vec<(String, String, usize, usize)> {
    let text = std::fs::read_to_string(dir.join("surf/stats.json")).unwrap();
    let field = |block: &str, key: &str| -> String {
        let k = format!("\"{key}\":");
        let i = block.find(&k).unwrap_or_else(|| panic!("no {key}")) + k.len();
        let rest = block[i..].trim_start();
        let end = rest.find([',', '\n', '}']).unwrap();
        rest[..end].trim().trim_matches('"').to_string()
    };
    text.split("\n {")
        .skip(1)
        .map(|b| {
            (
                field(b, "name"),
                field(b, "orig"),
                field(b, "V").parse().unwrap(),
                field(b, "F").parse().unwrap(),
            )
        })
        .collect()
}

fn normalized(mut s: delone_io::Surface) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    s.merge_exact_duplicates();
    s.remove_unreferenced();
    let t = s.triangles();
    (s.points, t)
}

fn sorted_bits(p: &[[f64; 3]]) -> Vec<[u64; 3]> {
    let mut v: Vec<[u64; 3]> = p.iter().map(|q| q.map(f64::to_bits)).collect();
    v.sort_unstable();
    v
}

fn check(max_faces: usize, min_faces: usize) {
    let Some(dir) = data_dir() else { return };
    let mut checked = 0;
    for (name, orig, nv, nf) in stats(&dir) {
        if nf > max_faces || nf < min_faces {
            continue;
        }
        let ext = orig.rsplit('.').next().unwrap();
        if ext == "zip" {
            eprintln!("note: {name}: {orig} is a zip archive; not read");
            continue;
        }
        let Ok(bytes) = std::fs::read(dir.join(&orig)) else {
            eprintln!("note: {name}: {orig} is not in the corpus; skipped");
            continue;
        };
        let s = delone_io::read_surface(&bytes, ext).unwrap_or_else(|e| panic!("{orig}: {e}"));
        let (p, t) = normalized(s);
        assert_eq!(
            (p.len(), t.len()),
            (nv, nf),
            "{orig}: (V, F) differ from stats.json"
        );
        let off_path = dir.join(format!("surf/off/{name}.off"));
        let off = delone_io::read_off(&std::fs::read(&off_path).unwrap())
            .unwrap_or_else(|e| panic!("{}: {e}", off_path.display()));
        assert_eq!(off.points.len(), nv, "{name}.off: V");
        assert_eq!(off.triangles().len(), nf, "{name}.off: F");
        assert_eq!(
            sorted_bits(&p),
            sorted_bits(&off.points),
            "{name}: point sets differ"
        );
        checked += 1;
    }
    eprintln!("checked {checked} models with {min_faces}..={max_faces} faces");
    assert!(checked > 0 || min_faces > 0);
}

#[test]
fn originals_match_off_and_stats() {
    check(60_000, 0);
}

#[test]
#[ignore = "large models: cargo test -p delone-io --test surface_corpus -- --ignored"]
fn originals_match_off_and_stats_large() {
    check(usize::MAX, 60_001);
}

#[test]
fn every_off_reads() {
    let Some(dir) = data_dir() else { return };
    let mut n = 0;
    for e in std::fs::read_dir(dir.join("surf/off")).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_none_or(|x| x != "off") {
            continue; // e.g. mesher outputs someone wrote next to the models
        }
        if std::fs::metadata(&p).unwrap().len() > 4_000_000 {
            continue;
        }
        let s = delone_io::read_off(&std::fs::read(&p).unwrap())
            .unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        assert!(!s.faces.is_empty(), "{}", p.display());
        n += 1;
    }
    assert!(n > 50);
}

#[test]
fn every_tetgen_plc_reads() {
    let Some(dir) = data_dir() else { return };
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir.join("3d_plc"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    for p in &files {
        let bytes = std::fs::read(p).unwrap();
        let f = match p.extension().and_then(|e| e.to_str()) {
            Some("poly") => delone_io::read_poly3d(&bytes),
            Some("smesh") => delone_io::read_smesh(&bytes),
            _ => continue,
        }
        .unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        assert!(
            f.points.len() >= 4 && f.facets.len() >= 4,
            "{}",
            p.display()
        );
        for fc in &f.facets {
            assert!(!fc.polygons.is_empty());
            for poly in &fc.polygons {
                assert!(poly.iter().all(|&i| (i as usize) < f.points.len()));
            }
        }
        if p.file_name().unwrap() == "tetgen_example.poly" {
            assert_eq!((f.points.len(), f.facets.len()), (28, 23));
            assert_eq!(f.first_index, 1);
            // Facet 3 has two polygons and one hole.
            assert_eq!(f.facets[2].polygons.len(), 2);
            assert_eq!(f.facets[2].holes, vec![[1.0, 0.0, 2.25]]);
            assert!(!f.regions.is_empty());
        }
    }
    assert_eq!(files.len(), 18);
}
