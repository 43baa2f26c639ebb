//! Triangle's `.poly` format (planar straight-line graphs): reader and writer.
//!
//! Sections, in order: a `.node` section (header `<#points> 2 <#attr>
//! <#markers>`, or `0 2 0 0` meaning the points are in a separate `.node`
//! file); segments (`<#segments> <#markers>`, then `<index> <a> <b>
//! [marker]`); holes (`<#holes>`, then `<index> <x> <y>`); optionally regions
//! (`<#regions>`, then `<index> <x> <y> <attribute> [<max area>]`).

use std::io::Write;

use crate::out::Out;
use crate::read::{
    check_index, parse_count, parse_f64, parse_int, read_node_body, NodeFile, Records,
};
use crate::IoError;

/// The content of a `.poly` file, as returned by [`read_poly`].
///
/// ```
/// let f = delone_io::read_poly(b"3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n1 1\n1 1 2 5\n0\n").unwrap();
/// assert_eq!(f.segments_zero_based(f.node.first_index).unwrap(), vec![[0, 1]]);
/// assert_eq!(f.segment_markers, Some(vec![5]));
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct PolyFile {
    /// The points section (empty with `node.is_empty()` when the points are
    /// in a separate `.node` file).
    pub node: NodeFile,
    /// Segment ends as written in the file (not yet shifted to 0-based: see
    /// [`PolyFile::segments_zero_based`]).
    pub segments: Vec<[u64; 2]>,
    /// Segment markers, if the segment header announces them (missing
    /// markers read as 0).
    pub segment_markers: Option<Vec<i32>>,
    /// Line number of each segment record.
    pub segment_lines: Vec<usize>,
    /// Hole points.
    pub holes: Vec<[f64; 2]>,
    /// Regions: `[x, y, attribute, max_area]` (`max_area` is -1 when absent).
    pub regions: Vec<[f64; 4]>,
}

impl PolyFile {
    /// The segments with 0-based point indices, given the first point index
    /// of the points they refer to (the `.node` section's or the separate
    /// `.node` file's).
    ///
    /// # Errors
    /// [`IoError::Syntax`] naming the line of a segment end below
    /// `first_index` or beyond `u32`.
    ///
    /// ```
    /// let f = delone_io::read_poly(b"0 2 0 0\n1 0\n0 4 7\n0\n").unwrap();
    /// assert_eq!(f.segments_zero_based(0).unwrap(), vec![[4, 7]]);
    /// assert!(f.segments_zero_based(5).is_err());
    /// ```
    pub fn segments_zero_based(&self, first_index: u32) -> Result<Vec<[u32; 2]>, IoError> {
        self.segments
            .iter()
            .zip(&self.segment_lines)
            .map(|(s, &line)| {
                let mut r = [0u32; 2];
                for k in 0..2 {
                    let v = s[k]
                        .checked_sub(u64::from(first_index))
                        .and_then(|v| u32::try_from(v).ok())
                        .ok_or_else(|| {
                            IoError::syntax(
                                line,
                                format!("a point index from {first_index}"),
                                s[k].to_string(),
                            )
                        })?;
                    r[k] = v;
                }
                Ok(r)
            })
            .collect()
    }
}

/// Reads a Triangle `.poly` file from bytes.
///
/// A missing hole section reads as no holes; the region section is optional.
///
/// # Errors
/// [`IoError::Syntax`] (with line, expectation and finding),
/// [`IoError::UnexpectedEnd`] when a section is shorter than its header says,
/// [`IoError::Unsupported`] for a dimension other than 2.
///
/// ```
/// let text = b"4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n1\n1 0.5 0.5\n";
/// let f = delone_io::read_poly(text).unwrap();
/// assert_eq!((f.node.len(), f.segments.len(), f.holes.len()), (4, 4, 1));
/// let err = delone_io::read_poly(b"2 2 0 0\n1 0 0\n2 1 0\n1 0\n1 1\n").unwrap_err();
/// assert_eq!(err.to_string(), "line 5: expected 2 segment ends, found 1");
/// ```
pub fn read_poly(input: &[u8]) -> Result<PolyFile, IoError> {
    let mut rec = Records::new(input);
    let mut toks = Vec::with_capacity(8);
    let Some(hline) = rec.next(&mut toks) else {
        return Err(IoError::syntax(1, "a header line", "an empty file"));
    };
    let node = read_node_body(&mut rec, &mut toks, hline, input.len())?;
    if node.dim != 2 {
        return Err(IoError::Unsupported {
            line: hline,
            message: format!(
                "a .poly file of dimension {} (only 2 is read here)",
                node.dim
            ),
        });
    }
    let Some(sline) = rec.next(&mut toks) else {
        return Err(IoError::syntax(
            hline,
            "a segment header after the points",
            "the end of the file",
        ));
    };
    let ns = parse_count(toks[0], sline, "the number of segments")?;
    let smark = match toks.get(1) {
        Some(t) => parse_count(t, sline, "the number of segment markers (0 or 1)")?,
        None => 0,
    };
    if smark > 1 {
        return Err(IoError::syntax(
            sline,
            "the number of segment markers (0 or 1)",
            smark.to_string(),
        ));
    }
    let cap = ns.min(input.len() / 6 + 1);
    let mut segments = Vec::with_capacity(cap);
    let mut segment_lines = Vec::with_capacity(cap);
    let mut markers = (smark == 1).then(|| Vec::with_capacity(cap));
    let mut first = None;
    for k in 0..ns {
        let Some(line) = rec.next(&mut toks) else {
            return Err(IoError::UnexpectedEnd {
                line: sline,
                what: "segments",
                declared: ns,
                found: k,
            });
        };
        check_index(toks[0], line, k, &mut first, "segment")?;
        if toks.len() < 3 {
            return Err(IoError::syntax(
                line,
                "2 segment ends",
                (toks.len() - 1).to_string(),
            ));
        }
        let a = parse_count(toks[1], line, "a segment end (point index)")? as u64;
        let b = parse_count(toks[2], line, "a segment end (point index)")? as u64;
        segments.push([a, b]);
        segment_lines.push(line);
        if let Some(m) = markers.as_mut() {
            m.push(match toks.get(3) {
                Some(t) => {
                    let v = parse_int(t, line, "a segment marker (integer)")?;
                    i32::try_from(v).map_err(|_| {
                        IoError::syntax(line, "a segment marker in the i32 range", v.to_string())
                    })?
                }
                None => 0,
            });
        }
    }
    let mut holes = Vec::new();
    let mut regions = Vec::new();
    if let Some(hl) = rec.next(&mut toks) {
        let nh = parse_count(toks[0], hl, "the number of holes")?;
        let mut first = None;
        for k in 0..nh {
            let Some(line) = rec.next(&mut toks) else {
                return Err(IoError::UnexpectedEnd {
                    line: hl,
                    what: "holes",
                    declared: nh,
                    found: k,
                });
            };
            check_index(toks[0], line, k, &mut first, "hole")?;
            if toks.len() < 3 {
                return Err(IoError::syntax(
                    line,
                    "2 hole coordinates",
                    (toks.len() - 1).to_string(),
                ));
            }
            holes.push([
                parse_f64(toks[1], line, "a coordinate")?,
                parse_f64(toks[2], line, "a coordinate")?,
            ]);
        }
        if let Some(rl) = rec.next(&mut toks) {
            let nr = parse_count(toks[0], rl, "the number of regions")?;
            let mut first = None;
            for k in 0..nr {
                let Some(line) = rec.next(&mut toks) else {
                    return Err(IoError::UnexpectedEnd {
                        line: rl,
                        what: "regions",
                        declared: nr,
                        found: k,
                    });
                };
                check_index(toks[0], line, k, &mut first, "region")?;
                if toks.len() < 4 {
                    return Err(IoError::syntax(
                        line,
                        "2 coordinates and an attribute",
                        (toks.len() - 1).to_string(),
                    ));
                }
                let area = match toks.get(4) {
                    Some(t) => parse_f64(t, line, "a maximum area")?,
                    None => -1.0,
                };
                regions.push([
                    parse_f64(toks[1], line, "a coordinate")?,
                    parse_f64(toks[2], line, "a coordinate")?,
                    parse_f64(toks[3], line, "a regional attribute")?,
                    area,
                ]);
            }
        }
    }
    Ok(PolyFile {
        node,
        segments,
        segment_markers: markers,
        segment_lines,
        holes,
        regions,
    })
}

/// Writes a `.poly` file as Triangle writes its output: header `0 2 0 1`
/// when `points` is empty (the points are in the `.node` file), else the
/// points inline; then the segments with markers (if given), the holes and,
/// if any, the regions. Indices start at `first_index`.
///
/// # Errors
/// [`IoError::InvalidInput`] if `segment_markers` does not match the
/// segments; [`IoError::Io`] if the writer fails.
///
/// ```
/// let mut out = Vec::new();
/// delone_io::write_poly(&mut out, &[], &[[0, 1]], Some(&[2]), &[[0.5, 0.5]], &[], 1).unwrap();
/// assert_eq!(String::from_utf8(out).unwrap(), "0 2 0 1\n1 1\n1 1 2 2\n1\n1 0.5 0.5\n");
/// ```
pub fn write_poly<W: Write>(
    out: W,
    points: &[[f64; 2]],
    segments: &[[u32; 2]],
    segment_markers: Option<&[i32]>,
    holes: &[[f64; 2]],
    regions: &[[f64; 4]],
    first_index: u32,
) -> Result<(), IoError> {
    if let Some(m) = segment_markers {
        if m.len() != segments.len() {
            return Err(IoError::InvalidInput {
                message: format!(
                    "the segment marker array has {} entries, expected {}",
                    m.len(),
                    segments.len()
                ),
            });
        }
    }
    let mut o = Out::new(out);
    let f = u64::from(first_index);
    if points.is_empty() {
        o.str("0 2 0 1");
        o.nl()?;
    } else {
        o.uint(points.len() as u64);
        o.str(" 2 0 0");
        o.nl()?;
        for (i, p) in points.iter().enumerate() {
            o.uint(i as u64 + f);
            o.byte(b' ');
            o.float(p[0]);
            o.byte(b' ');
            o.float(p[1]);
            o.nl()?;
        }
    }
    o.uint(segments.len() as u64);
    o.str(if segment_markers.is_some() {
        " 1"
    } else {
        " 0"
    });
    o.nl()?;
    for (i, s) in segments.iter().enumerate() {
        o.uint(i as u64 + f);
        o.byte(b' ');
        o.uint(u64::from(s[0]) + f);
        o.byte(b' ');
        o.uint(u64::from(s[1]) + f);
        if let Some(m) = segment_markers {
            o.byte(b' ');
            o.int(i64::from(m[i]));
        }
        o.nl()?;
    }
    o.uint(holes.len() as u64);
    o.nl()?;
    for (i, h) in holes.iter().enumerate() {
        o.uint(i as u64 + f);
        o.byte(b' ');
        o.float(h[0]);
        o.byte(b' ');
        o.float(h[1]);
        o.nl()?;
    }
    if !regions.is_empty() {
        o.uint(regions.len() as u64);
        o.nl()?;
        for (i, r) in regions.iter().enumerate() {
            o.uint(i as u64 + f);
            for &x in r {
                o.byte(b' ');
                o.float(x);
            }
            o.nl()?;
        }
    }
    Ok(o.finish()?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_with_regions() {
        let pts = [[0.0, 0.0], [1.5, 0.0], [0.0, 1e-7]];
        let segs = [[0u32, 1], [1, 2], [2, 0]];
        let mut out = Vec::new();
        write_poly(
            &mut out,
            &pts,
            &segs,
            Some(&[1, 2, 3]),
            &[[0.1, 0.1]],
            &[[0.2, 0.2, 7.0, 0.5]],
            0,
        )
        .unwrap();
        let f = read_poly(&out).unwrap();
        assert_eq!(f.node.points::<2>().unwrap(), pts.to_vec());
        assert_eq!(
            f.segments_zero_based(f.node.first_index).unwrap(),
            segs.to_vec()
        );
        assert_eq!(f.segment_markers, Some(vec![1, 2, 3]));
        assert_eq!(f.holes, vec![[0.1, 0.1]]);
        assert_eq!(f.regions, vec![[0.2, 0.2, 7.0, 0.5]]);
    }

    #[test]
    fn errors_name_lines_and_never_panic() {
        let e = read_poly(b"1 2 0 0\n1 0 0\n2 0\n1 1 1\n").unwrap_err();
        assert!(
            matches!(
                e,
                IoError::UnexpectedEnd {
                    what: "segments",
                    ..
                }
            ),
            "{e}"
        );
        let e = read_poly(b"1 2 0 0\n1 0 0\n1 0\n1 1 x\n").unwrap_err();
        assert_eq!(e.line(), Some(4));
        let e = read_poly(b"1 2 0 0\n1 0 0\n0 0\n2\n1 0 0\n").unwrap_err();
        assert!(
            matches!(e, IoError::UnexpectedEnd { what: "holes", .. }),
            "{e}"
        );
        // Truncations of a valid file never panic.
        let text = b"3 2 1 1\n1 0 0 4 1\n2 1 0 4 1\n3 0 1 4 1\n3 1\n1 1 2 1\n2 2 3 1\n3 3 1 1\n1\n1 0.2 0.2\n1\n1 0.1 0.1 3 0.5\n";
        for k in 0..text.len() {
            let _ = read_poly(&text[..k]);
        }
        assert!(read_poly(text).is_ok());
    }
}
