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
