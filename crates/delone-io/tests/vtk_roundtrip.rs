//! Parses back the VTK files the writers produce (a minimal independent
//! reader of exactly the subset they emit) and checks every value.

use delone_io::{write_vtk_legacy, write_vtu, DataArray, Values, VtuFormat};

/// Attribute `key="..."` inside `tag`.
fn attr<'a>(tag: &'a str, key: &str) -> &'a str {
    let pat = format!(" {key}=\"");
    let s = tag
        .find(&pat)
        .unwrap_or_else(|| panic!("{key} missing in {tag}"))
        + pat.len();
    let e = s + tag[s..].find('"').unwrap();
    &tag[s..e]
}

#[derive(Debug, PartialEq)]
struct Parsed {
    points: Vec<[f64; 3]>,
    connectivity: Vec<i64>,
    offsets: Vec<i64>,
    types: Vec<u8>,
    ints: Vec<(String, Vec<i32>)>,
    floats: Vec<(String, Vec<f64>)>,
}

/// Reads a .vtu as written by `write_vtu`, in either format.
fn parse_vtu(bytes: &[u8]) -> Parsed {
    // XML part ends where the raw data starts (after '_'), or at the end.
    let xml_end = bytes
        .windows(b"<AppendedData".len())
        .position(|w| w == b"<AppendedData")
        .unwrap_or(bytes.len());
    let xml = std::str::from_utf8(&bytes[..xml_end]).unwrap();
    let raw_start = if xml_end < bytes.len() {
        xml_end + bytes[xml_end..].iter().position(|&b| b == b'_').unwrap() + 1
    } else {
        0
    };
    assert!(xml.starts_with("<?xml"));
    assert!(xml.contains(r#"header_type="UInt64""#));
    let piece_at = xml.find("<Piece ").unwrap();
    let piece = &xml[piece_at..piece_at + xml[piece_at..].find('>').unwrap()];
    let n: usize = attr(piece, "NumberOfPoints").parse().unwrap();
    let m: usize = attr(piece, "NumberOfCells").parse().unwrap();
    let mut p = Parsed {
        points: vec![],
        connectivity: vec![],
        offsets: vec![],
        types: vec![],
        ints: vec![],
        floats: vec![],
    };
    let mut rest = xml;
    while let Some(at) = rest.find("<DataArray ") {
        let tag_end = at + rest[at..].find('>').unwrap();
        let tag = &rest[at..tag_end];
        let ty = attr(tag, "type");
        let name = attr(tag, "Name").to_string();
        // Values as text tokens or raw bytes.
        let (text, raw): (Vec<&str>, &[u8]) = if attr(tag, "format") == "ascii" {
            let close = tag_end + rest[tag_end..].find("</DataArray>").unwrap();
            (rest[tag_end + 1..close].split_whitespace().collect(), &[])
        } else {
            assert_eq!(attr(tag, "format"), "appended");
            let off: usize = attr(tag, "offset").parse().unwrap();
            let s = raw_start + off;
            let len = u64::from_le_bytes(bytes[s..s + 8].try_into().unwrap()) as usize;
            (vec![], &bytes[s + 8..s + 8 + len])
        };
        let f64s = || -> Vec<f64> {
            if raw.is_empty() {
                text.iter().map(|t| t.parse().unwrap()).collect()
            } else {
                raw.chunks_exact(8)
                    .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
                    .collect()
            }
        };
        let i64s = || -> Vec<i64> {
            if raw.is_empty() {
                text.iter().map(|t| t.parse().unwrap()).collect()
            } else {
                raw.chunks_exact(8)
                    .map(|c| i64::from_le_bytes(c.try_into().unwrap()))
                    .collect()
            }
        };
        match (ty, name.as_str()) {
            ("Float64", "Points") => {
                assert_eq!(attr(tag, "NumberOfComponents"), "3");
                p.points = f64s().chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
            }
            ("Int64", "connectivity") => p.connectivity = i64s(),
            ("Int64", "offsets") => p.offsets = i64s(),
            ("UInt8", "types") => {
                p.types = if raw.is_empty() {
                    text.iter().map(|t| t.parse().unwrap()).collect()
                } else {
                    raw.to_vec()
                }
            }
            ("Int32", _) => {
                let v = if raw.is_empty() {
                    text.iter().map(|t| t.parse().unwrap()).collect()
                } else {
                    raw.chunks_exact(4)
                        .map(|c| i32::from_le_bytes(c.try_into().unwrap()))
                        .collect()
                };
                p.ints.push((name, v));
            }
            ("Float64", _) => {
                let v = f64s();
                p.floats.push((name, v));
            }
            other => panic!("unexpected array {other:?}"),
        }
        rest = &rest[tag_end..];
    }
    assert_eq!(p.points.len(), n);
    assert_eq!(p.types.len(), m);
    assert_eq!(p.offsets.len(), m);
    p
}

type Sample = (Vec<[f64; 3]>, Vec<[u32; 4]>, Vec<i32>, Vec<f64>);

fn sample3() -> Sample {
    let pts: Vec<[f64; 3]> = (0..50)
        .map(|i| {
            let t = i as f64 * 0.37;
            [t.sin() * 1e-7, t.cos() * 3.5e12, -t / 7.0]
        })
        .collect();
    let tets: Vec<[u32; 4]> = (0..40).map(|i| [i, i + 1, i + 5, i + 9]).collect();
    let marks: Vec<i32> = (0..50).map(|i| i % 3 - 1).collect();
    let vol: Vec<f64> = (0..40).map(|i| 1.0 / (i as f64 + 3.0)).collect();
    (pts, tets, marks, vol)
}

#[test]
fn vtu_tets_round_trip_both_formats() {
    let (pts, tets, marks, vol) = sample3();
    let pd = [DataArray {
        name: "marker",
        values: Values::Int32(&marks),
    }];
    let cd = [DataArray {
        name: "volume <&\">",
        values: Values::Float64(&vol),
    }];
    let mut outputs = Vec::new();
    for fmt in [VtuFormat::Ascii, VtuFormat::Binary] {
        let mut buf = Vec::new();
        write_vtu(&mut buf, &pts, &tets, &pd, &cd, fmt).unwrap();
        let p = parse_vtu(&buf);
        assert_eq!(p.points, pts);
        assert_eq!(
            p.connectivity,
            tets.iter()
                .flatten()
                .map(|&v| i64::from(v))
                .collect::<Vec<_>>()
        );
        assert_eq!(p.offsets, (1..=40).map(|i| 4 * i).collect::<Vec<i64>>());
        assert_eq!(p.types, vec![10u8; 40]);
        assert_eq!(p.ints, vec![("marker".to_string(), marks.clone())]);
        assert_eq!(p.floats.len(), 1);
        assert_eq!(p.floats[0].1, vol);
        outputs.push(p);
    }
    assert_eq!(outputs[0], outputs[1]);
}

#[test]
fn vtu_triangles_2d_get_zero_z() {
    let pts = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]];
    let tris = [[0u32, 1, 2], [2, 1, 3]];
    for fmt in [VtuFormat::Ascii, VtuFormat::Binary] {
        let mut buf = Vec::new();
        write_vtu(&mut buf, &pts, &tris, &[], &[], fmt).unwrap();
        let p = parse_vtu(&buf);
        assert_eq!(p.points, pts.map(|[x, y]| [x, y, 0.0]).to_vec());
        assert_eq!(p.types, vec![5, 5]);
        assert_eq!(p.connectivity, vec![0, 1, 2, 2, 1, 3]);
        assert_eq!(p.offsets, vec![3, 6]);
    }
}

#[test]
fn vtu_rejects_bad_input() {
    let pts = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
    let e = write_vtu(
        Vec::new(),
        &pts,
        &[[0u32, 1, 3]],
        &[],
        &[],
        VtuFormat::Binary,
    )
    .unwrap_err();
    assert_eq!(
        e.to_string(),
        "cell 0 refers to point 3, but there are only 3 points"
    );
    let m = [1];
    let e = write_vtu(
        Vec::new(),
        &pts,
        &[[0u32, 1, 2]],
        &[DataArray {
            name: "marker",
            values: Values::Int32(&m),
        }],
        &[],
        VtuFormat::Ascii,
    )
    .unwrap_err();
    assert_eq!(
        e.to_string(),
        "point data \"marker\" has 1 values, expected 3"
    );
}

/// Legacy VTK: parse the sections back.
#[test]
fn legacy_vtk_round_trip() {
    let (pts, tets, marks, vol) = sample3();
    let mut buf = Vec::new();
    write_vtk_legacy(
        &mut buf,
        &pts,
        &tets,
        &[DataArray {
            name: "marker",
            values: Values::Int32(&marks),
        }],
        &[DataArray {
            name: "vol ume",
            values: Values::Float64(&vol),
        }],
        "delone\nmesh",
    )
    .unwrap();
    let text = String::from_utf8(buf).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "# vtk DataFile Version 2.0");
    assert_eq!(lines[1], "delone mesh");
    assert_eq!(lines[2], "ASCII");
    assert_eq!(lines[3], "DATASET UNSTRUCTURED_GRID");
    assert_eq!(lines[4], "POINTS 50 double");
    let mut toks = text
        .split_whitespace()
        .skip_while(|&t| t != "POINTS")
        .skip(3);
    let got: Vec<[f64; 3]> = (0..50)
        .map(|_| std::array::from_fn(|_| toks.next().unwrap().parse().unwrap()))
        .collect();
    assert_eq!(got, pts);
    assert_eq!(toks.next(), Some("CELLS"));
    assert_eq!(toks.next(), Some("40"));
    assert_eq!(toks.next(), Some("200"));
    for t in &tets {
        assert_eq!(toks.next(), Some("4"));
        for &v in t {
            assert_eq!(toks.next().unwrap().parse::<u32>().unwrap(), v);
        }
    }
    assert_eq!(toks.next(), Some("CELL_TYPES"));
    assert_eq!(toks.next(), Some("40"));
    for _ in 0..40 {
        assert_eq!(toks.next(), Some("10"));
    }
    let rest: Vec<&str> = toks.collect();
    assert_eq!(
        &rest[..8],
        &[
            "POINT_DATA",
            "50",
            "SCALARS",
            "marker",
            "int",
            "1",
            "LOOKUP_TABLE",
            "default"
        ]
    );
    let m: Vec<i32> = rest[8..58].iter().map(|t| t.parse().unwrap()).collect();
    assert_eq!(m, marks);
    assert_eq!(
        &rest[58..66],
        &[
            "CELL_DATA",
            "40",
            "SCALARS",
            "vol_ume",
            "double",
            "1",
            "LOOKUP_TABLE",
            "default"
        ]
    );
    let v: Vec<f64> = rest[66..].iter().map(|t| t.parse().unwrap()).collect();
    assert_eq!(v, vol);
}

/// Throughput figure (not a pass/fail threshold): run with
/// `cargo test --release -p delone-io --test vtk_roundtrip -- --ignored --nocapture`.
#[test]
#[ignore]
fn write_speed_one_million_tets() {
    use std::time::Instant;
    let n = 170_000u32;
    let pts: Vec<[f64; 3]> = (0..n)
        .map(|i| {
            let t = f64::from(i);
            [
                (t * 0.618).fract(),
                (t * 0.414).fract(),
                (t * 0.732).fract(),
            ]
        })
        .collect();
    let tets: Vec<[u32; 4]> = (0..1_000_000u32)
        .map(|i| [i % n, (i + 1) % n, (i + 7) % n, (i + 13) % n])
        .collect();
    let nbrs: Vec<[u32; 4]> = (0..1_000_000u32)
        .map(|i| [i ^ 1, u32::MAX, (i + 3) % 1_000_000, (i + 9) % 1_000_000])
        .collect();
    let time = |what: &str, f: &mut dyn FnMut() -> usize| {
        let t = Instant::now();
        let bytes = f();
        println!(
            "{what}: {:.3} s, {:.1} MB",
            t.elapsed().as_secs_f64(),
            bytes as f64 / 1e6
        );
    };
    time(".node", &mut || {
        let mut b = Vec::new();
        delone_io::write_node(&mut b, &pts, &[], 0, None, 1).unwrap();
        b.len()
    });
    time(".ele 1M tets", &mut || {
        let mut b = Vec::new();
        delone_io::write_ele(&mut b, &tets, &[], 0, 1).unwrap();
        b.len()
    });
    time(".neigh 1M tets", &mut || {
        let mut b = Vec::new();
        delone_io::write_neigh(&mut b, &nbrs, 1).unwrap();
        b.len()
    });
    time(".vtu binary 1M tets", &mut || {
        let mut b = Vec::new();
        write_vtu(&mut b, &pts, &tets, &[], &[], VtuFormat::Binary).unwrap();
        b.len()
    });
    time(".vtu ascii 1M tets", &mut || {
        let mut b = Vec::new();
        write_vtu(&mut b, &pts, &tets, &[], &[], VtuFormat::Ascii).unwrap();
        b.len()
    });
}
