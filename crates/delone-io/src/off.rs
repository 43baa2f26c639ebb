//! Reader for the ASCII OFF format (Geomview Object File Format).

use crate::read::{parse_count, parse_f64, parse_int, Records};
use crate::surface::{cap, index, Surface};
use crate::IoError;

/// Reads an ASCII OFF file.
///
/// Header: a keyword ending in `OFF` (`OFF`, `COFF`, `NOFF`, `STOFF`, …; the
/// keyword may be omitted), then `<#vertices> <#faces> [<#edges>]` on the
/// same or the next line; then one vertex per line (`x y z`, extra fields
/// such as normals or colours ignored) and one face per line
/// (`n i1 … in`, 0-based, extra fields such as colours ignored). `#` starts a
/// comment.
///
/// # Errors
/// [`IoError::Syntax`] with the line and what was expected;
/// [`IoError::UnexpectedEnd`] when the file holds fewer vertices or faces
/// than the header says; [`IoError::Unsupported`] for binary OFF or a
/// dimension other than 3 (`nOFF`).
///
/// ```
/// let s = delone_io::read_off(b"OFF\n# tetrahedron\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n").unwrap();
/// assert_eq!((s.points.len(), s.faces.len()), (4, 4));
///
/// let e = delone_io::read_off(b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n").unwrap_err();
/// assert_eq!(e.to_string(), "line 6: expected a point index below 3, found 7");
/// ```
pub fn read_off(input: &[u8]) -> Result<crate::Surface, IoError> {
    let mut rec = Records::new(input);
    let mut toks = Vec::with_capacity(16);
    let Some(mut hline) = rec.next(&mut toks) else {
        return Err(IoError::syntax(1, "an OFF header", "an empty file"));
    };
    let mut counts: Vec<&[u8]> = Vec::with_capacity(3);
    let first = toks[0];
    let kw_end = first
        .windows(3)
        .position(|w| w == b"OFF")
        .map(|p| p + 3)
        .filter(|_| first[0].is_ascii_alphabetic());
    match kw_end {
        Some(end) => {
            let kw = &first[..end];
            if kw.first() == Some(&b'n') || kw.contains(&b'4') {
                return Err(IoError::Unsupported {
                    line: hline,
                    message: format!(
                        "OFF variant {} is not supported (only 3D)",
                        crate::surface::found(kw)
                    ),
                });
            }
            if end < first.len() {
                counts.push(&first[end..]);
            }
            counts.extend_from_slice(&toks[1..]);
            if counts.first() == Some(&&b"BINARY"[..]) {
                return Err(IoError::Unsupported {
                    line: hline,
                    message: "binary OFF is not supported".into(),
                });
            }
            if counts.is_empty() {
                let Some(l) = rec.next(&mut toks) else {
                    return Err(IoError::syntax(
                        hline + 1,
                        "the vertex and face counts",
                        "the end of the file",
                    ));
                };
                hline = l;
                counts.extend_from_slice(&toks);
            }
        }
        None => {
            if first[0].is_ascii_alphabetic() {
                return Err(IoError::syntax(
                    hline,
                    "the keyword OFF",
                    crate::surface::found(first),
                ));
            }
            counts.extend_from_slice(&toks);
        }
    }
    let nv = parse_count(counts[0], hline, "the number of vertices")?;
    let nf = match counts.get(1) {
        Some(t) => parse_count(t, hline, "the number of faces")?,
        None => return Err(IoError::syntax(hline, "the number of faces", "nothing")),
    };
    let mut points = Vec::with_capacity(cap(nv, input.len(), 6));
    for k in 0..nv {
        let Some(line) = rec.next(&mut toks) else {
            return Err(IoError::UnexpectedEnd {
                line: hline,
                what: "vertices",
                declared: nv,
                found: k,
            });
        };
        if toks.len() < 3 {
            return Err(IoError::syntax(
                line,
                "3 coordinates",
                toks.len().to_string(),
            ));
        }
        points.push([
            parse_f64(toks[0], line, "a coordinate")?,
            parse_f64(toks[1], line, "a coordinate")?,
            parse_f64(toks[2], line, "a coordinate")?,
        ]);
    }
    let mut faces = Vec::with_capacity(cap(nf, input.len(), 8));
    for k in 0..nf {
        let Some(line) = rec.next(&mut toks) else {
            return Err(IoError::UnexpectedEnd {
                line: hline,
                what: "faces",
                declared: nf,
                found: k,
            });
        };
        let n = parse_count(toks[0], line, "the number of corners of a face")?;
        if toks.len() <= n {
            return Err(IoError::syntax(
                line,
                format!("{n} point indices"),
                (toks.len() - 1).to_string(),
            ));
        }
        let mut f = Vec::with_capacity(n);
        for t in &toks[1..=n] {
            f.push(index(parse_int(t, line, "a point index")?, nv, line)?);
        }
        faces.push(f);
    }
    Ok(Surface { points, faces })
}
