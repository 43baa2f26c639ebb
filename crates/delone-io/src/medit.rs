//! Reader for the ASCII Medit `.mesh` format (surface part).

use crate::surface::{found, Surface, Tokens};
use crate::IoError;

/// Reads the `Vertices`, `Triangles` and `Quadrilaterals` sections of an
/// ASCII Medit `.mesh` file (`MeshVersionFormatted`, `Dimension 3`, …,
/// `End`). Every other section (`Tetrahedra`, `Edges`, `Corners`, …) is
/// skipped; element references (the last number of each record) are
/// ignored. Indices are 1-based in the file, 0-based in the result.
///
/// # Errors
/// [`IoError::Syntax`] with the line for a malformed record or an index
/// outside the vertices; [`IoError::Unsupported`] for a dimension other than
/// 3 or a binary `.meshb` file.
///
/// ```
/// let text = b"MeshVersionFormatted 1\nDimension 3\nVertices\n3\n0 0 0 1\n1 0 0 1\n0 1 0 1\nTriangles\n1\n1 2 3 7\nEnd\n";
/// let s = delone_io::read_medit(text).unwrap();
/// assert_eq!(s.faces, vec![vec![0, 1, 2]]);
///
/// let bad = b"Dimension 3\nVertices\n1\n0 0 0 0\nTriangles\n1\n1 1 5 0\n";
/// let e = delone_io::read_medit(bad).unwrap_err();
/// assert_eq!(e.to_string(), "line 7: expected a vertex index between 1 and 1, found 5");
/// ```
pub fn read_medit(input: &[u8]) -> Result<Surface, IoError> {
    if input.iter().take(64).any(|&b| b == 0) {
        return Err(IoError::Unsupported {
            line: 1,
            message: "binary Medit (.meshb) is not supported".into(),
        });
    }
    let mut tk = Tokens::new(input, true);
    let mut points = Vec::new();
    let mut faces: Vec<(Vec<u32>, usize)> = Vec::new();
    let mut raw: Vec<(Vec<i64>, usize)> = Vec::new();
    while let Some((t, line)) = tk.next_tok() {
        match t {
            b"End" => break,
            b"MeshVersionFormatted" => {
                tk.int("a format version")?;
            }
            b"Dimension" => {
                let (d, l) = tk.int("the dimension")?;
                if d != 3 {
                    return Err(IoError::Unsupported {
                        line: l,
                        message: format!("dimension {d} (only 3)"),
                    });
                }
            }
            b"Vertices" => {
                let (n, _) = tk.count("the number of vertices")?;
                points.reserve(crate::surface::cap(n, input.len(), 8));
                for _ in 0..n {
                    let p = [
                        tk.f64("a coordinate")?,
                        tk.f64("a coordinate")?,
                        tk.f64("a coordinate")?,
                    ];
                    tk.int("a vertex reference")?;
                    points.push(p);
                }
            }
            b"Triangles" | b"Quadrilaterals" => {
                let k = if t == b"Triangles" { 3 } else { 4 };
                let (n, _) = tk.count("the number of elements")?;
                raw.reserve(crate::surface::cap(n, input.len(), 8));
                for _ in 0..n {
                    let mut f = Vec::with_capacity(k);
                    let mut l = 0;
                    for _ in 0..k {
                        let (i, li) = tk.int("a vertex index")?;
                        f.push(i);
                        l = li;
                    }
                    tk.int("an element reference")?;
                    raw.push((f, l));
                }
            }
            _ if t[0].is_ascii_alphabetic() => {
                // Unknown section: skip its numbers up to the next keyword.
                while let Some((u, _)) = tk.peek() {
                    if u[0].is_ascii_alphabetic() {
                        break;
                    }
                    tk.next_tok();
                }
            }
            _ => return Err(IoError::syntax(line, "a Medit keyword", found(t))),
        }
    }
    for (f, l) in raw {
        let mut g = Vec::with_capacity(f.len());
        for i in f {
            if i < 1 || i as u64 > points.len() as u64 {
                return Err(IoError::syntax(
                    l,
                    format!("a vertex index between 1 and {}", points.len()),
                    i.to_string(),
                ));
            }
            g.push((i - 1) as u32);
        }
        faces.push((g, l));
    }
    Ok(Surface {
        points,
        faces: faces.into_iter().map(|(f, _)| f).collect(),
    })
}

/// Writes an ASCII Medit `.mesh` file (`MeshVersionFormatted 2`, double
/// precision): `Vertices` (reference 0), `Triangles` with `face_refs`,
/// `Tetrahedra` with `tet_refs` (an empty section is left out), `End`.
/// Indices are 0-based in the arrays, 1-based in the file.
///
/// # Errors
/// [`IoError::InvalidInput`] if a reference array does not match its
/// elements or an element names a missing point; [`IoError::Io`] if the
/// writer fails.
///
/// ```
/// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 0.5]];
/// let mut out = Vec::new();
/// delone_io::write_medit(&mut out, &pts, &[[0, 2, 1]], &[3], &[[0, 1, 2, 3]], &[7]).unwrap();
/// let text = String::from_utf8(out).unwrap();
/// assert_eq!(
///     text,
///     "MeshVersionFormatted 2\nDimension 3\nVertices\n4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 0.5 0\n\
///      Triangles\n1\n1 3 2 3\nTetrahedra\n1\n1 2 3 4 7\nEnd\n"
/// );
/// // Our reader gets the surface part back.
/// let s = delone_io::read_medit(text.as_bytes()).unwrap();
/// assert_eq!((s.points.len(), s.faces.clone()), (4, vec![vec![0, 2, 1]]));
/// ```
pub fn write_medit<W: std::io::Write>(
    out: W,
    points: &[[f64; 3]],
    triangles: &[[u32; 3]],
    face_refs: &[i32],
    tets: &[[u32; 4]],
    tet_refs: &[i32],
) -> Result<(), IoError> {
    check_cells("triangle", triangles, face_refs, points.len())?;
    check_cells("tetrahedron", tets, tet_refs, points.len())?;
    let mut o = crate::out::Out::new(out);
    o.str("MeshVersionFormatted 2\nDimension 3\nVertices\n");
    o.uint(points.len() as u64);
    o.nl()?;
    for p in points {
        for &c in p {
            o.float(c);
            o.byte(b' ');
        }
        o.byte(b'0');
        o.nl()?;
    }
    write_section(&mut o, "Triangles", triangles, face_refs)?;
    write_section(&mut o, "Tetrahedra", tets, tet_refs)?;
    o.str("End");
    o.nl()?;
    Ok(o.finish()?)
}

/// Lengths and indices of one element array of a writer.
pub(crate) fn check_cells<const K: usize>(
    what: &str,
    cells: &[[u32; K]],
    refs: &[i32],
    n_points: usize,
) -> Result<(), IoError> {
    if cells.len() != refs.len() {
        return Err(IoError::invalid(format!(
            "{} {what} references for {} elements",
            refs.len(),
            cells.len()
        )));
    }
    if let Some((i, &v)) = cells
        .iter()
        .enumerate()
        .find_map(|(i, c)| c.iter().find(|&&v| v as usize >= n_points).map(|v| (i, v)))
    {
        return Err(IoError::invalid(format!(
            "{what} {i} names point {v}, but there are {n_points} points"
        )));
    }
    Ok(())
}

fn write_section<W: std::io::Write, const K: usize>(
    o: &mut crate::out::Out<W>,
    name: &str,
    cells: &[[u32; K]],
    refs: &[i32],
) -> Result<(), IoError> {
    if cells.is_empty() {
        return Ok(());
    }
    o.str(name);
    o.nl()?;
    o.uint(cells.len() as u64);
    o.nl()?;
    for (c, &r) in cells.iter().zip(refs) {
        for &v in c {
            o.uint(u64::from(v) + 1);
            o.byte(b' ');
        }
        o.int(i64::from(r));
        o.nl()?;
    }
    Ok(())
}
