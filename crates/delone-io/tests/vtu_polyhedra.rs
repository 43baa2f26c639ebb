//! VTK_POLYHEDRON output read back.

use delone_io::{write_vtu_polyhedra, DataArray, Values, VtuFormat};

fn cube(o: [f64; 3]) -> (Vec<[f64; 3]>, Vec<Vec<u32>>) {
    let v: Vec<[f64; 3]> = (0..8)
        .map(|k| {
            [
                o[0] + (k & 1) as f64,
                o[1] + (k >> 1 & 1) as f64,
                o[2] + (k >> 2) as f64,
            ]
        })
        .collect();
    let f = vec![
        vec![0, 4, 6, 2],
        vec![1, 3, 7, 5],
        vec![0, 1, 5, 4],
        vec![2, 6, 7, 3],
        vec![0, 2, 3, 1],
        vec![4, 5, 7, 6],
    ];
    (v, f)
}

/// The whitespace-separated values of the ASCII `<DataArray Name="name">`.
fn array(text: &str, name: &str) -> Vec<f64> {
    let start = text.find(&format!("Name=\"{name}\"")).unwrap();
    let body = &text[start..];
    let open = body.find('>').unwrap() + 1;
    let close = body.find("</DataArray>").unwrap();
    body[open..close]
        .split_whitespace()
        .map(|t| t.parse().unwrap())
        .collect()
}

#[test]
fn ascii_polyhedra_read_back() {
    let (v1, f1) = cube([0.0; 3]);
    let (v2, f2) = cube([2.0, 0.0, 0.0]);
    let empty: (Vec<[f64; 3]>, Vec<Vec<u32>>) = (vec![], vec![]);
    let ids = [7, 9];
    let polys = [
        (&v1[..], &f1[..]),
        (&empty.0[..], &empty.1[..]),
        (&v2[..], &f2[..]),
    ];
    let mut out = Vec::new();
    write_vtu_polyhedra(
        &mut out,
        &polys,
        &[DataArray {
            name: "site",
            values: Values::Int32(&ids),
        }],
        VtuFormat::Ascii,
    )
    .unwrap();
    let text = String::from_utf8(out).unwrap();
    assert!(text.contains("NumberOfPoints=\"16\" NumberOfCells=\"2\""));
    assert_eq!(array(&text, "types"), vec![42.0, 42.0]);
    assert_eq!(array(&text, "offsets"), vec![8.0, 16.0]);
    let faces = array(&text, "faces");
    assert_eq!(faces.len(), 2 * (1 + 6 * 5));
    assert_eq!(faces[0], 6.0);
    assert_eq!(&faces[1..6], &[4.0, 0.0, 4.0, 6.0, 2.0]);
    assert_eq!(faces[31], 6.0);
    assert_eq!(&faces[32..37], &[4.0, 8.0, 12.0, 14.0, 10.0]);
    assert_eq!(array(&text, "faceoffsets"), vec![31.0, 62.0]);
    assert_eq!(array(&text, "site"), vec![7.0, 9.0]);
}

#[test]
fn binary_polyhedra_have_consistent_offsets() {
    let (v1, f1) = cube([0.0; 3]);
    let mut out = Vec::new();
    write_vtu_polyhedra(&mut out, &[(&v1[..], &f1[..])], &[], VtuFormat::Binary).unwrap();
    let start = out.windows(2).position(|w| w == b"\n_").unwrap() + 2;
    let head = String::from_utf8_lossy(&out[..start]).into_owned();
    // Walk the appended blocks by their UInt64 size headers, in the order
    // of the offsets the header declares.
    let offsets: Vec<usize> = head
        .match_indices("offset=\"")
        .map(|(i, _)| {
            let rest = &head[i + 8..];
            rest[..rest.find('"').unwrap()].parse().unwrap()
        })
        .collect();
    assert_eq!(offsets.len(), 6);
    let mut pos = 0usize;
    for &o in &offsets {
        assert_eq!(o, pos);
        let size =
            u64::from_le_bytes(out[start + pos..start + pos + 8].try_into().unwrap()) as usize;
        pos += 8 + size;
    }
    assert!(out[start + pos..].starts_with(b"\n</AppendedData>"));
}

#[test]
fn bad_face_index_is_an_error() {
    let (v1, mut f1) = cube([0.0; 3]);
    f1[2][1] = 99;
    let mut out = Vec::new();
    assert!(write_vtu_polyhedra(&mut out, &[(&v1[..], &f1[..])], &[], VtuFormat::Ascii).is_err());
}
