//! Reader for Wavefront OBJ (geometry only: `v` and `f`).

use crate::read::{parse_f64, parse_int, Records};
use crate::surface::{found, Surface};
use crate::IoError;

/// Reads the vertices (`v x y z [w]`) and faces (`f …`) of a Wavefront OBJ
/// file. Face corners may be written `i`, `i/t`, `i//n` or `i/t/n` (texture
/// and normal indices are ignored); indices are 1-based, negative indices
/// count back from the last vertex read so far. Every other statement
/// (`vt`, `vn`, `g`, `o`, `s`, `usemtl`, `mtllib`, `l`, …) is ignored.
///
/// # Errors
/// [`IoError::Syntax`] with the line for a malformed vertex, a face with
/// fewer than 3 corners, index 0 or an index outside the vertices read so
/// far.
///
/// ```
/// let text = b"# quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 2//1 3 -1\n";
/// let s = delone_io::read_obj(text).unwrap();
/// assert_eq!(s.faces, vec![vec![0, 1, 2, 3]]);
///
/// let e = delone_io::read_obj(b"v 0 0 0\nf 1 2 0\n").unwrap_err();
/// assert_eq!(e.to_string(), "line 2: expected a vertex index (1-based or negative) between -1 and 1, found 2");
/// ```
pub fn read_obj(input: &[u8]) -> Result<Surface, IoError> {
    let mut rec = Records::new(input);
    let mut toks = Vec::with_capacity(16);
    let mut points = Vec::new();
    let mut faces = Vec::new();
    while let Some(line) = rec.next(&mut toks) {
        match toks[0] {
            b"v" => {
                if toks.len() < 4 {
                    return Err(IoError::syntax(
                        line,
                        "3 coordinates after \"v\"",
                        (toks.len() - 1).to_string(),
                    ));
                }
                if points.len() >= u32::MAX as usize {
                    return Err(IoError::Unsupported {
                        line,
                        message: "more than 2^32 - 1 vertices".into(),
                    });
                }
                points.push([
                    parse_f64(toks[1], line, "a coordinate")?,
                    parse_f64(toks[2], line, "a coordinate")?,
                    parse_f64(toks[3], line, "a coordinate")?,
                ]);
            }
            b"f" => {
                if toks.len() < 4 {
                    return Err(IoError::syntax(
                        line,
                        "at least 3 corners after \"f\"",
                        (toks.len() - 1).to_string(),
                    ));
                }
                let n = points.len() as i64;
                let mut f = Vec::with_capacity(toks.len() - 1);
                for t in &toks[1..] {
                    let head = t.split(|&b| b == b'/').next().unwrap_or(t);
                    let i = parse_int(head, line, "a vertex index")?;
                    let z = if i > 0 { i - 1 } else { n + i };
                    if i == 0 || z < 0 || z >= n {
                        return Err(IoError::syntax(
                            line,
                            format!("a vertex index (1-based or negative) between -{n} and {n}"),
                            found(head).trim_matches('"').to_string(),
                        ));
                    }
                    f.push(z as u32);
                }
                faces.push(f);
            }
            _ => {}
        }
    }
    Ok(Surface { points, faces })
}
