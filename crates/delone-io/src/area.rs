//! Triangle's `.area` files: one maximum area per triangle of a mesh being
//! refined (`-r -a`).

use crate::read::{check_index, parse_count, parse_f64, Records};
use crate::IoError;

/// Reads a `.area` file: header `<#triangles>`, then `<index> <maximum
/// area>` per triangle (numbered from 0 or 1 like the `.ele` file). A
/// bound that is zero or negative means "no bound" (Triangle's convention);
/// it is returned as read.
///
/// # Errors
/// [`IoError`] naming the line: a bad number, an index out of sequence, or
/// fewer records than the header declares.
///
/// ```
/// let a = delone_io::read_area(b"2\n1 0.5\n2 -1\n").unwrap();
/// assert_eq!(a, vec![0.5, -1.0]);
/// assert!(delone_io::read_area(b"2\n1 0.5\n").is_err());
/// ```
pub fn read_area(input: &[u8]) -> Result<Vec<f64>, IoError> {
    let mut rec = Records::new(input);
    let mut toks = Vec::with_capacity(4);
    let Some(hline) = rec.next(&mut toks) else {
        return Err(IoError::syntax(1, "a header line", "an empty file"));
    };
    let n = parse_count(toks[0], hline, "the number of triangles")?;
    let mut out = Vec::with_capacity(n.min(input.len() / 4 + 1));
    let mut first = None;
    for k in 0..n {
        let Some(line) = rec.next(&mut toks) else {
            return Err(IoError::UnexpectedEnd {
                line: hline,
                what: "area bounds",
                declared: n,
                found: k,
            });
        };
        check_index(toks[0], line, k, &mut first, "triangle")?;
        let Some(t) = toks.get(1) else {
            return Err(IoError::syntax(line, "a maximum area", "nothing"));
        };
        out.push(parse_f64(t, line, "a maximum area")?);
    }
    Ok(out)
}
