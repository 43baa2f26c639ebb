//! Readers for TetGen's `.mtr` (sizes at points) and `.face` (triangular
//! faces with boundary markers) files.

use crate::read::{check_index, parse_count, parse_f64, parse_int, Records};
use crate::IoError;

/// Reads a `.mtr` file: header `<#points> <#sizes per point>`, then one
/// record per point whose first value is the point's size (a size ≤ 0
/// means "no constraint" at that point; extra values are ignored). Returns
/// the first size of every point.
///
/// # Errors
/// [`IoError`] naming the line: a bad header, a value that is not a number,
/// fewer records than announced, or zero sizes per point.
///
/// ```
/// let s = delone_io::read_mtr(b"3 1\n0.5\n0\n# comment\n1e-2\n").unwrap();
/// assert_eq!(s, vec![0.5, 0.0, 0.01]);
/// let e = delone_io::read_mtr(b"2 1\n0.5\n").unwrap_err();
/// assert_eq!(e.to_string().contains("line 1"), true);
/// ```
pub fn read_mtr(input: &[u8]) -> Result<Vec<f64>, IoError> {
    let mut rec = Records::new(input);
    let mut toks = Vec::with_capacity(4);
    let Some(hline) = rec.next(&mut toks) else {
        return Err(IoError::syntax(1, "a header line", "an empty file"));
    };
    let n = parse_count(toks[0], hline, "the number of points")?;
    let k = match toks.get(1) {
        Some(t) => parse_count(t, hline, "the number of sizes per point")?,
        None => 1,
    };
    if k == 0 {
        return Err(IoError::syntax(hline, "at least 1 size per point", "0"));
    }
    let mut sizes = Vec::with_capacity(n.min(input.len() / 2 + 1));
    for i in 0..n {
        let Some(line) = rec.next(&mut toks) else {
            return Err(IoError::UnexpectedEnd {
                line: hline,
                what: "sizes",
                declared: n,
                found: i,
            });
        };
        let s = parse_f64(toks[0], line, "a size")?;
        if s.is_nan() {
            return Err(IoError::syntax(line, "a size", "NaN"));
        }
        sizes.push(s);
    }
    Ok(sizes)
}

/// The content of a TetGen `.face` file, as returned by [`read_face`].
///
/// ```
/// let f = delone_io::read_face(b"1 1\n1 1 2 3 5\n", 1).unwrap();
/// assert_eq!((f.faces.clone(), f.markers.clone()), (vec![[0, 1, 2]], Some(vec![5])));
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct FaceFile {
    /// Faces, 0-based vertex indices.
    pub faces: Vec<[u32; 3]>,
    /// Boundary markers, one per face, when the header announces them.
    pub markers: Option<Vec<i32>>,
}

/// Reads a TetGen `.face` file: header `<#faces> [<boundary markers 0|1>]`,
/// then `<index> <n1> <n2> <n3> [marker]`; node indices are made 0-based
/// by subtracting `node_first_index`.
///
/// # Errors
/// [`IoError`] naming the line.
///
/// ```
/// let f = delone_io::read_face(b"2 0\n0 0 1 2\n1 1 2 3\n", 0).unwrap();
/// assert_eq!(f.faces, vec![[0, 1, 2], [1, 2, 3]]);
/// assert!(delone_io::read_face(b"1 0\n0 0 1\n", 0).is_err());
/// ```
pub fn read_face(input: &[u8], node_first_index: u32) -> Result<FaceFile, IoError> {
    let mut rec = Records::new(input);
    let mut toks = Vec::with_capacity(8);
    let Some(hline) = rec.next(&mut toks) else {
        return Err(IoError::syntax(1, "a header line", "an empty file"));
    };
    let n = parse_count(toks[0], hline, "the number of faces")?;
    let has_markers = match toks.get(1) {
        Some(t) => match parse_count(t, hline, "0 or 1 (boundary markers)")? {
            0 => false,
            1 => true,
            m => {
                return Err(IoError::syntax(
                    hline,
                    "0 or 1 (boundary markers)",
                    m.to_string(),
                ))
            }
        },
        None => false,
    };
    let cap = n.min(input.len() / 8 + 1);
    let mut faces = Vec::with_capacity(cap);
    let mut markers = has_markers.then(|| Vec::with_capacity(cap));
    let mut first = None;
    for i in 0..n {
        let Some(line) = rec.next(&mut toks) else {
            return Err(IoError::UnexpectedEnd {
                line: hline,
                what: "faces",
                declared: n,
                found: i,
            });
        };
        check_index(toks[0], line, i, &mut first, "face")?;
        let need = 4 + usize::from(has_markers);
        if toks.len() < need {
            return Err(IoError::syntax(
                line,
                format!("{} values", need),
                toks.len().to_string(),
            ));
        }
        let mut f = [0u32; 3];
        for (k, t) in toks[1..4].iter().enumerate() {
            let v = parse_int(t, line, "a node index")?;
            f[k] = u32::try_from(v - node_first_index as i64).map_err(|_| {
                IoError::syntax(
                    line,
                    format!("a node index >= {node_first_index}"),
                    v.to_string(),
                )
            })?;
        }
        faces.push(f);
        if let Some(m) = markers.as_mut() {
            let v = parse_int(toks[4], line, "a boundary marker")?;
            let v = i32::try_from(v)
                .map_err(|_| IoError::syntax(line, "a 32-bit boundary marker", v.to_string()))?;
            m.push(v);
        }
    }
    Ok(FaceFile { faces, markers })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mtr_errors_name_the_line() {
        let e = read_mtr(b"2 1\n0.5\nabc\n").unwrap_err();
        assert_eq!(e.line(), Some(3));
        assert!(e.to_string().contains("size"), "{e}");
        let e = read_mtr(b"x 1\n").unwrap_err();
        assert_eq!(e.line(), Some(1));
        let e = read_mtr(b"1 0\n1\n").unwrap_err();
        assert_eq!(e.line(), Some(1));
        let e = read_mtr(b"\n\n3 1\n1\n2\n").unwrap_err();
        assert!(matches!(
            e,
            IoError::UnexpectedEnd {
                line: 3,
                declared: 3,
                found: 2,
                ..
            }
        ));
        assert!(read_mtr(b"").is_err());
        assert!(read_mtr(b"1 1\nnan\n").is_err());
        // Several sizes per point: the first one counts.
        assert_eq!(read_mtr(b"2 2\n1 9\n-1 9\n").unwrap(), vec![1.0, -1.0]);
    }

    #[test]
    fn face_errors_name_the_line() {
        let e = read_face(b"2 1\n1 1 2 3 0\n2 1 2\n", 1).unwrap_err();
        assert_eq!(e.line(), Some(3));
        let e = read_face(b"1 1\n1 0 2 3 1\n", 1).unwrap_err();
        assert_eq!(e.line(), Some(2));
        let e = read_face(b"1 3\n", 1).unwrap_err();
        assert_eq!(e.line(), Some(1));
        let e = read_face(b"2 0\n1 1 2 3\n3 1 2 3\n", 1).unwrap_err();
        assert_eq!(e.line(), Some(3));
        let e = read_face(b"1 1\n1 1 2 3 x\n", 1).unwrap_err();
        assert_eq!(e.line(), Some(2));
        let f = read_face(b"# faces\n1 1\n0 4 5 6 -2 # c\n", 0).unwrap();
        assert_eq!(f.faces, vec![[4, 5, 6]]);
        assert_eq!(f.markers, Some(vec![-2]));
    }
}
