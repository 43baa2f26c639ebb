//! Unit and fuzz-style tests of the surface and PLC readers: hand-built
//! files in every variant, errors naming lines/offsets, and no panic on
//! random or truncated bytes.

use delone_io::*;

fn tet_ply_binary(big: bool) -> Vec<u8> {
    let fmt = if big {
        "binary_big_endian"
    } else {
        "binary_little_endian"
    };
    let mut b = format!(
        "ply\nformat {fmt} 1.0\nelement vertex 4\nproperty double x\nproperty float y\nproperty float z\nproperty short extra\nelement face 4\nproperty list uchar uint vertex_indices\nproperty list uchar float texcoord\nelement other 1\nproperty list int int junk\nend_header\n"
    )
    .into_bytes();
    let pts = [
        [0.0f64, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    for p in pts {
        let (x, y, z) = (p[0], p[1] as f32, p[2] as f32);
        if big {
            b.extend(x.to_be_bytes());
            b.extend(y.to_be_bytes());
            b.extend(z.to_be_bytes());
            b.extend((-3i16).to_be_bytes());
        } else {
            b.extend(x.to_le_bytes());
            b.extend(y.to_le_bytes());
            b.extend(z.to_le_bytes());
            b.extend((-3i16).to_le_bytes());
        }
    }
    for f in [[0u32, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]] {
        b.push(3);
        for i in f {
            b.extend(if big {
                i.to_be_bytes()
            } else {
                i.to_le_bytes()
            });
        }
        b.push(1);
        b.extend(if big {
            0.5f32.to_be_bytes()
        } else {
            0.5f32.to_le_bytes()
        });
    }
    b
}

#[test]
fn ply_binary_both_endians() {
    for big in [false, true] {
        let b = tet_ply_binary(big);
        let s = read_ply(&b).unwrap();
        assert_eq!(
            s.points,
            vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0]
            ]
        );
        assert_eq!(s.faces[3], vec![0, 3, 2]);
        // Truncated in the face element: a byte offset, never a panic.
        let e = read_ply(&b[..b.len() - 3]).unwrap_err();
        assert_eq!(e.offset(), Some(b.len() - 3), "{e}");
    }
}

#[test]
fn ply_errors() {
    let e = read_ply(b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n")
        .unwrap_err();
    assert!(e.to_string().contains("x, y and z"), "{e}");
    let e = read_ply(b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n3 0 0 1\n").unwrap_err();
    assert_eq!(e.line(), Some(11), "{e}");
    let e = read_ply(b"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n").unwrap_err();
    assert_eq!(e.line(), Some(8), "{e}");
    assert!(read_ply(b"ply\nformat foo 1.0\nend_header\n").is_err());
}

#[test]
fn stl_ascii_and_binary_agree() {
    let text = b"solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 0 1 0\n  endloop\n endfacet\n facet normal 0 0 1\n  outer loop\n   vertex 1 0 0\n   vertex 1 1 0\n   vertex 0 1 0\n  endloop\n endfacet\nendsolid x\n";
    let a = read_stl(text).unwrap();
    assert_eq!(a.points.len(), 4);
    assert_eq!(a.faces, vec![vec![0, 1, 2], vec![1, 3, 2]]);
    // The same triangles in binary, with a header starting with "solid".
    let mut b = b"solid but binary".to_vec();
    b.resize(80, b' ');
    b.extend(2u32.to_le_bytes());
    for t in [
        [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        [[1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
    ] {
        b.extend([0u8; 12]);
        for p in t {
            for c in p {
                b.extend(c.to_le_bytes());
            }
        }
        b.extend([0u8; 2]);
    }
    assert_eq!(read_stl(&b).unwrap(), a);
    let e = read_stl(b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0\n").unwrap_err();
    assert_eq!(
        e.to_string(),
        "line 4: expected 3 coordinates after \"vertex\", found 2"
    );
    let e = read_stl(b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n").unwrap_err();
    assert_eq!(e.line(), Some(4), "{e}");
}

#[test]
fn off_variants() {
    let s = read_off(b"OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 255 0 0\n").unwrap();
    assert_eq!(s.faces, vec![vec![0, 1, 2]]);
    let s =
        read_off(b"COFF\n3 1 0\n0 0 0 1 1 1 1\n1 0 0 1 1 1 1\n0 1 0 1 1 1 1\n3 0 1 2\n").unwrap();
    assert_eq!(s.points[1], [1.0, 0.0, 0.0]);
    let s = read_off(b"OFF3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").unwrap();
    assert_eq!(s.points.len(), 3);
    let e = read_off(b"OFF\n3 1 0\n0 0 0\n1 0 0\n").unwrap_err();
    assert!(
        matches!(
            e,
            IoError::UnexpectedEnd {
                declared: 3,
                found: 2,
                ..
            }
        ),
        "{e}"
    );
    let e = read_off(b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n").unwrap_err();
    assert_eq!(e.to_string(), "line 6: expected 4 point indices, found 3");
    assert!(read_off(b"OFF BINARY\n").is_err());
}

#[test]
fn obj_and_medit() {
    let s = read_obj(b"o x\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf -3/1 -2/2 -1/3\ng y\nv 1 1 0\nf 2 4 3\n")
        .unwrap();
    assert_eq!(s.faces, vec![vec![0, 1, 2], vec![1, 3, 2]]);
    assert!(read_obj(b"v 0 0 0\nf 1 1\n").is_err());
    let e = read_obj(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n").unwrap_err();
    assert_eq!(e.line(), Some(4));
    let text = b"MeshVersionFormatted 2\n# c\nDimension\n3\nVertices\n4\n0 0 0 0\n1 0 0 0\n1 1 0 0\n0 1 0 0\nEdges\n1\n1 2 0\nQuadrilaterals\n1\n1 2 3 4 1\nTetrahedra\n0\nEnd\n";
    let s = read_medit(text).unwrap();
    assert_eq!(s.faces, vec![vec![0, 1, 2, 3]]);
    let e = read_medit(b"Dimension 3\nVertices\n1\n0 0 0 0\nTriangles\n1\n1 1 5 0\n").unwrap_err();
    assert_eq!(e.line(), Some(7), "{e}");
}

#[test]
fn read_surface_dispatch() {
    let off = b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    assert_eq!(read_surface(off, "OFF").unwrap().faces.len(), 1);
    assert!(matches!(
        read_surface(off, "vtk"),
        Err(IoError::Unsupported { .. })
    ));
}

/// Random bytes, token soups and every truncation of valid files: `Ok` or
/// `Err`, never a panic.
#[test]
fn never_panics() {
    let valid: Vec<Vec<u8>> = vec![
        b"OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n4 0 1 3 2\n".to_vec(),
        b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid\n".to_vec(),
        b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n".to_vec(),
        tet_ply_binary(false),
        tet_ply_binary(true),
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1 2//3 -1\n".to_vec(),
        b"MeshVersionFormatted 1\nDimension 3\nVertices\n3\n0 0 0 0\n1 0 0 0\n0 1 0 0\nTriangles\n1\n1 2 3 0\nEnd\n".to_vec(),
        b"4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n2 1\n2 1 1\n3 1 2 3\n4 1 2 4 3\n1 0.2 0.2 0\n1 0 2\n3 1 2 4\n1\n1 9 9 9\n1\n1 0.1 0.1 0.1 1 0.5\n".to_vec(),
        b"4 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n2 1\n3 0 1 2 5\n3 0 1 3 5\n0\n0\n".to_vec(),
    ];
    let all = |b: &[u8]| {
        let _ = read_off(b);
        let _ = read_stl(b);
        let _ = read_ply(b);
        let _ = read_obj(b);
        let _ = read_medit(b);
        let _ = read_poly3d(b);
        let _ = read_smesh(b);
    };
    for v in &valid {
        for cut in 0..=v.len() {
            all(&v[..cut]);
        }
    }
    let alphabet: &[&[u8]] = &[
        b"0",
        b"1",
        b"2",
        b"3",
        b"-1",
        b"1e999",
        b"nan",
        b"#",
        b"\n",
        b" ",
        b"\r",
        b"x",
        b"\xff",
        b"/",
        b"//",
        b"18446744073709551616",
        b"4294967295",
        b"0.5",
        b"-",
        b"v",
        b"f",
        b"OFF",
        b"ply\n",
        b"format ascii 1.0\n",
        b"format binary_big_endian 1.0\n",
        b"element vertex 2\n",
        b"element face 9\n",
        b"property float x\n",
        b"property list uchar int vertex_indices\n",
        b"end_header\n",
        b"solid",
        b"facet",
        b"vertex",
        b"endfacet",
        b"Vertices",
        b"Triangles",
        b"End",
    ];
    let mut s: u64 = 0x2545_F491_4F6C_DD1D;
    let mut next = || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        s
    };
    for _ in 0..20_000 {
        let len = (next() % 40) as usize;
        let mut buf = Vec::new();
        for _ in 0..len {
            if next() % 5 == 0 {
                buf.push((next() % 256) as u8);
            } else {
                buf.extend_from_slice(alphabet[(next() % alphabet.len() as u64) as usize]);
            }
        }
        all(&buf);
    }
    // Byte-level mutations of the valid files.
    for _ in 0..5_000 {
        let v = &valid[(next() % valid.len() as u64) as usize];
        let mut b = v.clone();
        for _ in 0..1 + next() % 4 {
            let i = (next() % b.len() as u64) as usize;
            b[i] = (next() % 256) as u8;
        }
        all(&b);
    }
}
