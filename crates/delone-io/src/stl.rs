//! Reader for STL, ASCII and binary.

use crate::read::{parse_f64, Records};
use crate::surface::{found, Surface};
use crate::IoError;

/// Reads an STL file, ASCII or binary (detected from the content: a file
/// whose size is exactly `84 + 50 n` for the `n` its binary header gives is
/// binary, even if it starts with `solid`; otherwise a file starting with
/// `solid` is ASCII; anything else is binary).
///
/// STL stores each triangle with its own corners: bit-identical corners are
/// merged (deterministically, first occurrence first; see
/// [`Surface::merge_exact_duplicates`]), so the result shares vertices.
/// Normals and attribute bytes are ignored. ASCII facets with more than three
/// `vertex` lines become polygons.
///
/// # Errors
/// ASCII: [`IoError::Syntax`] with the line. Binary: [`IoError::Binary`]
/// with the byte offset when the file is shorter than its triangle count
/// says.
///
/// ```
/// let text = b"solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
/// let s = delone_io::read_stl(text).unwrap();
/// assert_eq!((s.points.len(), s.faces.len()), (3, 1));
///
/// let mut bin = vec![0u8; 80];
/// bin.extend_from_slice(&2u32.to_le_bytes());
/// bin.extend_from_slice(&[0u8; 50]);
/// let e = delone_io::read_stl(&bin).unwrap_err();
/// assert_eq!(e.to_string(), "byte 134: expected triangle 1 (50 bytes), found the end of the file");
/// ```
pub fn read_stl(input: &[u8]) -> Result<Surface, IoError> {
    let binary_len = input
        .get(80..84)
        .map(|b| 84 + 50 * u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as u64);
    let starts_solid = {
        let p = input
            .iter()
            .position(|b| !b.is_ascii_whitespace())
            .unwrap_or(input.len());
        input[p..].len() >= 5 && input[p..p + 5].eq_ignore_ascii_case(b"solid")
    };
    let mut s = if binary_len == Some(input.len() as u64) || !starts_solid {
        read_binary(input)?
    } else {
        read_ascii(input)?
    };
    s.merge_exact_duplicates();
    Ok(s)
}

fn read_binary(input: &[u8]) -> Result<Surface, IoError> {
    let Some(h) = input.get(80..84) else {
        return Err(IoError::Binary {
            offset: input.len(),
            expected: "an 80-byte header and a 4-byte triangle count".into(),
            found: "the end of the file".into(),
        });
    };
    let n = u32::from_le_bytes([h[0], h[1], h[2], h[3]]) as usize;
    let avail = (input.len() - 84) / 50;
    let mut points = Vec::with_capacity(3 * n.min(avail));
    let mut faces = Vec::with_capacity(n.min(avail));
    for k in 0..n {
        let off = 84 + 50 * k;
        let Some(rec) = input.get(off..off + 50) else {
            return Err(IoError::Binary {
                offset: input.len(),
                expected: format!("triangle {k} (50 bytes)"),
                found: "the end of the file".into(),
            });
        };
        let f = |i: usize| {
            let b = &rec[4 * i..4 * i + 4];
            f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64
        };
        let base = points.len() as u32;
        for c in 0..3 {
            points.push([f(3 + 3 * c), f(4 + 3 * c), f(5 + 3 * c)]);
        }
        faces.push(vec![base, base + 1, base + 2]);
    }
    Ok(Surface { points, faces })
}

fn read_ascii(input: &[u8]) -> Result<Surface, IoError> {
    let mut rec = Records::new(input);
    let mut toks = Vec::with_capacity(8);
    let mut points = Vec::new();
    let mut faces = Vec::new();
    // None outside a facet; Some(corners) inside one.
    let mut cur: Option<Vec<u32>> = None;
    let mut last_line = 1;
    let kw = |t: &[u8], k: &str| t.eq_ignore_ascii_case(k.as_bytes());
    while let Some(line) = rec.next(&mut toks) {
        last_line = line;
        let t = toks[0];
        if kw(t, "vertex") {
            let Some(c) = cur.as_mut() else {
                return Err(IoError::syntax(
                    line,
                    "\"facet\" before \"vertex\"",
                    found(t),
                ));
            };
            if toks.len() < 4 {
                return Err(IoError::syntax(
                    line,
                    "3 coordinates after \"vertex\"",
                    (toks.len() - 1).to_string(),
                ));
            }
            if points.len() >= u32::MAX as usize {
                return Err(IoError::Unsupported {
                    line,
                    message: "more than 2^32 - 1 vertices".into(),
                });
            }
            c.push(points.len() as u32);
            points.push([
                parse_f64(toks[1], line, "a coordinate")?,
                parse_f64(toks[2], line, "a coordinate")?,
                parse_f64(toks[3], line, "a coordinate")?,
            ]);
        } else if kw(t, "facet") {
            if cur.is_some() {
                return Err(IoError::syntax(line, "\"endfacet\"", found(t)));
            }
            cur = Some(Vec::with_capacity(3));
        } else if kw(t, "endfacet") {
            match cur.take() {
                Some(c) if c.len() >= 3 => faces.push(c),
                Some(c) => {
                    return Err(IoError::syntax(
                        line,
                        "at least 3 vertices in the facet",
                        c.len().to_string(),
                    ))
                }
                None => {
                    return Err(IoError::syntax(
                        line,
                        "\"facet\" before \"endfacet\"",
                        found(t),
                    ))
                }
            }
        } else if kw(t, "outer") || kw(t, "endloop") || kw(t, "endsolid") {
            if kw(t, "endsolid") && cur.is_some() {
                return Err(IoError::syntax(line, "\"endfacet\"", found(t)));
            }
        } else if kw(t, "solid") {
            if cur.is_some() {
                return Err(IoError::syntax(line, "\"endfacet\"", found(t)));
            }
        } else {
            return Err(IoError::syntax(
                line,
                "an STL keyword (solid, facet, outer, vertex, endloop, endfacet, endsolid)",
                found(t),
            ));
        }
    }
    if cur.is_some() {
        return Err(IoError::syntax(
            last_line,
            "\"endfacet\"",
            "the end of the file",
        ));
    }
    Ok(Surface { points, faces })
}
