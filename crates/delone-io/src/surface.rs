//! The plain polygon-surface data returned by the surface readers (OFF, STL,
//! PLY, OBJ, Medit), and the small lexer they share.

use crate::read::show;
use crate::IoError;
use std::collections::HashMap;

/// A polygon surface: points and faces (each a list of 0-based point
/// indices, in the order the file gives them).
///
/// Readers check that every index is in range, so a `Surface` from a reader
/// never refers to a missing point. Faces keep the polygons as read; use
/// [`Surface::triangles`] for a fan triangulation.
///
/// ```
/// let s = delone_io::read_off(b"OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n").unwrap();
/// assert_eq!(s.points.len(), 4);
/// assert_eq!(s.faces, vec![vec![0, 1, 2, 3]]);
/// assert_eq!(s.triangles(), vec![[0, 1, 2], [0, 2, 3]]);
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Surface {
    /// Point coordinates.
    pub points: Vec<[f64; 3]>,
    /// Faces: polygons of 0-based point indices.
    pub faces: Vec<Vec<u32>>,
}

impl Surface {
    /// Fan triangulation of every face: a polygon `v0 v1 … vk` gives
    /// `(v0, v1, v2), (v0, v2, v3), …`; faces with fewer than 3 corners are
    /// dropped.
    ///
    /// ```
    /// let s = delone_io::Surface { points: vec![[0.0; 3]; 5], faces: vec![vec![0, 1, 2, 3, 4], vec![1, 2]] };
    /// assert_eq!(s.triangles(), vec![[0, 1, 2], [0, 2, 3], [0, 3, 4]]);
    /// ```
    pub fn triangles(&self) -> Vec<[u32; 3]> {
        let mut out = Vec::with_capacity(self.faces.len());
        for f in &self.faces {
            for k in 1..f.len().saturating_sub(1) {
                out.push([f[0], f[k], f[k + 1]]);
            }
        }
        out
    }

    /// Merges points with bit-identical coordinates (no tolerance; `0.0` and
    /// `-0.0` stay distinct) and renumbers the faces. The first occurrence of
    /// a point keeps its place; the result is deterministic. Returns, for
    /// each old point, its new index.
    ///
    /// ```
    /// let mut s = delone_io::Surface {
    ///     points: vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0; 3], [0.0, 1.0, 0.0]],
    ///     faces: vec![vec![2, 1, 3]],
    /// };
    /// assert_eq!(s.merge_exact_duplicates(), vec![0, 1, 0, 2]);
    /// assert_eq!(s.points.len(), 3);
    /// assert_eq!(s.faces, vec![vec![0, 1, 2]]);
    /// ```
    pub fn merge_exact_duplicates(&mut self) -> Vec<u32> {
        let mut seen: HashMap<[u64; 3], u32> = HashMap::with_capacity(self.points.len());
        let mut map = Vec::with_capacity(self.points.len());
        let mut kept = Vec::with_capacity(self.points.len());
        for p in &self.points {
            let key = [p[0].to_bits(), p[1].to_bits(), p[2].to_bits()];
            let id = *seen.entry(key).or_insert_with(|| {
                kept.push(*p);
                (kept.len() - 1) as u32
            });
            map.push(id);
        }
        self.points = kept;
        for f in &mut self.faces {
            for v in f.iter_mut() {
                if let Some(&m) = map.get(*v as usize) {
                    *v = m;
                }
            }
        }
        map
    }

    /// Drops points no face refers to and renumbers the faces (kept points
    /// stay in their order). Returns, for each old point, its new index or
    /// `u32::MAX` when dropped.
    ///
    /// ```
    /// let mut s = delone_io::Surface {
    ///     points: vec![[9.0; 3], [0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
    ///     faces: vec![vec![1, 2, 3]],
    /// };
    /// assert_eq!(s.remove_unreferenced(), vec![u32::MAX, 0, 1, 2]);
    /// assert_eq!(s.faces, vec![vec![0, 1, 2]]);
    /// ```
    pub fn remove_unreferenced(&mut self) -> Vec<u32> {
        let mut used = vec![false; self.points.len()];
        for f in &self.faces {
            for &v in f {
                if let Some(u) = used.get_mut(v as usize) {
                    *u = true;
                }
            }
        }
        let mut map = vec![u32::MAX; self.points.len()];
        let mut kept = Vec::with_capacity(self.points.len());
        for (i, p) in self.points.iter().enumerate() {
            if used[i] {
                map[i] = kept.len() as u32;
                kept.push(*p);
            }
        }
        self.points = kept;
        for f in &mut self.faces {
            for v in f.iter_mut() {
                if let Some(&m) = map.get(*v as usize) {
                    *v = m;
                }
            }
        }
        map
    }
}

/// Reads a surface, choosing the reader from the file extension (`off`,
/// `stl`, `ply`, `obj`, `mesh`; any case).
///
/// # Errors
/// [`IoError::Unsupported`] (line 0) for an unknown extension, otherwise the
/// chosen reader's errors.
///
/// ```
/// let s = delone_io::read_surface(b"OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "off").unwrap();
/// assert_eq!(s.faces.len(), 1);
/// assert!(delone_io::read_surface(b"", "xyz").is_err());
/// ```
pub fn read_surface(input: &[u8], extension: &str) -> Result<Surface, IoError> {
    match extension.to_ascii_lowercase().as_str() {
        "off" => crate::read_off(input),
        "stl" => crate::read_stl(input),
        "ply" => crate::read_ply(input),
        "obj" => crate::read_obj(input),
        "mesh" => crate::read_medit(input),
        other => Err(IoError::Unsupported {
            line: 0,
            message: format!(
                "unknown surface format \"{other}\" (expected off, stl, ply, obj or mesh)"
            ),
        }),
    }
}

/// A stream of whitespace-separated tokens with their 1-based line numbers;
/// `#` starts a comment to the end of the line.
pub(crate) struct Tokens<'a> {
    rest: &'a [u8],
    line: usize,
    comments: bool,
}

impl<'a> Tokens<'a> {
    pub(crate) fn new(input: &'a [u8], comments: bool) -> Self {
        Tokens {
            rest: input,
            line: 1,
            comments,
        }
    }

    /// Current line (of the next unread byte).
    pub(crate) fn line(&self) -> usize {
        self.line
    }

    /// The next token without consuming it.
    pub(crate) fn peek(&mut self) -> Option<(&'a [u8], usize)> {
        self.skip_space();
        if self.rest.is_empty() {
            return None;
        }
        let end = self
            .rest
            .iter()
            .position(|b| b.is_ascii_whitespace() || (self.comments && *b == b'#'))
            .unwrap_or(self.rest.len());
        Some((&self.rest[..end], self.line))
    }

    pub(crate) fn next_tok(&mut self) -> Option<(&'a [u8], usize)> {
        let (t, l) = self.peek()?;
        self.rest = &self.rest[t.len()..];
        Some((t, l))
    }

    fn skip_space(&mut self) {
        loop {
            match self.rest.first() {
                Some(b'\n') => {
                    self.line += 1;
                    self.rest = &self.rest[1..];
                }
                Some(b) if b.is_ascii_whitespace() => self.rest = &self.rest[1..],
                Some(b'#') if self.comments => {
                    let p = self
                        .rest
                        .iter()
                        .position(|&b| b == b'\n')
                        .unwrap_or(self.rest.len());
                    self.rest = &self.rest[p..];
                }
                _ => return,
            }
        }
    }

    /// The next token, or a syntax error naming `what` at end of input.
    pub(crate) fn expect(&mut self, what: &str) -> Result<(&'a [u8], usize), IoError> {
        let l = self.line;
        self.next_tok()
            .ok_or_else(|| IoError::syntax(l, what.to_string(), "the end of the file"))
    }

    pub(crate) fn f64(&mut self, what: &str) -> Result<f64, IoError> {
        let (t, l) = self.expect(what)?;
        crate::read::parse_f64(t, l, what)
    }

    pub(crate) fn count(&mut self, what: &str) -> Result<(usize, usize), IoError> {
        let (t, l) = self.expect(what)?;
        Ok((crate::read::parse_count(t, l, what)?, l))
    }

    pub(crate) fn int(&mut self, what: &str) -> Result<(i64, usize), IoError> {
        let (t, l) = self.expect(what)?;
        Ok((crate::read::parse_int(t, l, what)?, l))
    }
}

/// Checks a 0-based index `i` (as read, possibly negative after shifting)
/// against `n` points.
pub(crate) fn index(i: i64, n: usize, line: usize) -> Result<u32, IoError> {
    if i < 0 || i as u64 >= n as u64 {
        return Err(IoError::syntax(
            line,
            format!("a point index below {n}"),
            i.to_string(),
        ));
    }
    Ok(i as u32)
}

/// Capacity hint that never trusts a header beyond the input size.
pub(crate) fn cap(declared: usize, input_len: usize, min_bytes_per_item: usize) -> usize {
    declared.min(input_len / min_bytes_per_item.max(1) + 1)
}

pub(crate) fn found(t: &[u8]) -> String {
    show(t)
}
