//! Readers for the Triangle/TetGen `.node` and `.ele` formats.
//!
//! Both formats are whitespace-separated text: comments run from `#` to the
//! end of the line, blank lines are skipped, the first record is a header.
//! Readers never panic, whatever the bytes; they return an [`IoError`]
//! naming the line.
//!
//! # Parsing
//!
//! One pass per line for tokens; integers without `str`; floats by Clinger's
//! fast path (at most 2^53, |e| ≤ 22), exact `u128` products (e ≥ 0) or
//! quotients with a sticky bit (17-digit `%.17g` coordinates), `str::parse`
//! otherwise — always the same double as `str::parse` (randomised tests).

use crate::IoError;

/// Splits the input into records (non-empty lines after comment removal),
/// each with its 1-based line number.
pub(crate) struct Records<'a> {
    rest: &'a [u8],
    line: usize,
}

impl<'a> Records<'a> {
    pub(crate) fn new(input: &'a [u8]) -> Self {
        Records {
            rest: input,
            line: 0,
        }
    }

    /// Fills `toks` with the tokens of the next non-empty record and returns
    /// its line number, or `None` at the end of the input.
    ///
    /// One pass over the bytes of each line: tokens are runs of bytes that
    /// are neither ASCII whitespace nor `#`; a `#` ends the record. Each
    /// byte is classified by a table ([`CLASS`]): a run of blanks, then a
    /// run of token bytes, until a newline or `#`.
    pub(crate) fn next(&mut self, toks: &mut Vec<&'a [u8]>) -> Option<usize> {
        let rest = self.rest;
        let class = |i: usize| rest.get(i).map_or(END, |&b| CLASS[usize::from(b)]);
        let mut i = 0;
        loop {
            if i >= rest.len() {
                self.rest = &rest[rest.len()..];
                return None;
            }
            self.line += 1;
            toks.clear();
            // Scan the line up to its newline (or a comment).
            loop {
                while class(i) == BLANK {
                    i += 1;
                }
                if class(i) != TOKEN {
                    break;
                }
                let start = i;
                i = token_end(rest, i + 1);
                toks.push(&rest[start..i]);
            }
            // Skip a comment, then the newline.
            if i < rest.len() && rest[i] == b'#' {
                i += rest[i..]
                    .iter()
                    .position(|&b| b == b'\n')
                    .unwrap_or(rest.len() - i);
            }
            i += 1;
            if !toks.is_empty() {
                self.rest = &rest[i.min(rest.len())..];
                return Some(self.line);
            }
        }
    }
}

/// The end of the token run from `i`: the first byte at or after `i`
/// that is not a token byte ([`CLASS`]), or `rest.len()`. Eight bytes at
/// a time: every byte that ends a token (whitespace, `#`) is below
/// `0x24`, and the bytes below `0x24` of a word are flagged in their high
/// bits by one subtraction (the lowest flag is exact: a false flag needs
/// a borrow from a true one below it); a flagged byte that is a token byte
/// after all (a control character, `!`, `"`) is stepped over.
#[inline(always)]
fn token_end(rest: &[u8], mut i: usize) -> usize {
    const ONES: u64 = 0x0101_0101_0101_0101;
    const HIGH: u64 = 0x8080_8080_8080_8080;
    loop {
        if let Some(w) = rest.get(i..i + 8) {
            let w = u64::from_le_bytes(w.try_into().unwrap_or_default());
            let below = w.wrapping_sub(0x24 * ONES) & !w & HIGH;
            if below == 0 {
                i += 8;
                continue;
            }
            i += (below.trailing_zeros() / 8) as usize;
        }
        match rest.get(i) {
            Some(&b) if CLASS[usize::from(b)] == TOKEN => i += 1,
            _ => return i,
        }
    }
}

/// [`CLASS`] of a byte inside a token.
const TOKEN: u8 = 0;
/// [`CLASS`] of ASCII whitespace other than the newline.
const BLANK: u8 = 1;
/// [`CLASS`] of the newline and `#` (the end of a record's text); also
/// the class of the end of the input.
const END: u8 = 2;

/// The class of each byte for [`Records::next`]: [`BLANK`] for the ASCII
/// whitespace of `u8::is_ascii_whitespace` but the newline, [`END`] for
/// the newline and `#`, [`TOKEN`] for every other byte.
const CLASS: [u8; 256] = {
    let mut t = [TOKEN; 256];
    t[b' ' as usize] = BLANK;
    t[b'\t' as usize] = BLANK;
    t[0x0C] = BLANK;
    t[b'\r' as usize] = BLANK;
    t[b'\n' as usize] = END;
    t[b'#' as usize] = END;
    t
};

/// Plain decimal integers (`[+-]?[0-9]{1,18}`) without the `str` machinery;
/// `None` for anything else (the caller falls back to `str::parse`).
#[inline]
fn fast_int(tok: &[u8]) -> Option<i64> {
    let (neg, digits) = match tok.first()? {
        b'-' => (true, &tok[1..]),
        b'+' => (false, &tok[1..]),
        _ => (false, tok),
    };
    if digits.is_empty() || digits.len() > 18 {
        return None;
    }
    let mut v: i64 = 0;
    for &b in digits {
        let d = b.wrapping_sub(b'0');
        if d > 9 {
            return None;
        }
        v = v * 10 + i64::from(d);
    }
    Some(if neg { -v } else { v })
}

/// Exact powers of ten representable in an `f64`.
const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// Clinger's fast path for `[+-]?digits[.digits][(e|E)[+-]?digits]`: when
/// the decimal significand `m` is at most 2^53 and the decimal exponent `e`
/// at most 22 in magnitude, both `m` and `10^|e|` are exact doubles, so one
/// IEEE multiplication or division gives the correctly rounded value — the
/// same double as `str::parse`. `None` for anything else (more digits,
/// larger exponents, `inf`/`nan`, malformed text): the caller falls back to
/// `str::parse`.
#[inline]
fn fast_f64(tok: &[u8]) -> Option<f64> {
    let (neg, s) = match tok.first()? {
        b'-' => (true, &tok[1..]),
        b'+' => (false, &tok[1..]),
        _ => (false, tok),
    };
    // The digits before and after the point, eight at a time where they
    // can; at most 19 digits in all fit `m` whatever their values.
    let (mut m, mut i) = digit_run(s, 0, 0);
    let mut exp: i64 = 0;
    let mut any = i > 0;
    let point = i < s.len() && s[i] == b'.';
    if point {
        let (m2, j) = digit_run(s, i + 1, m);
        exp = -((j - i - 1) as i64);
        any |= j > i + 1;
        m = m2;
        i = j;
    }
    if !any {
        return None;
    }
    if i - usize::from(point) > 19 {
        // More digits: only the significant ones (after leading zeros)
        // count towards the 19.
        let nd = s[..i]
            .iter()
            .filter(|c| c.is_ascii_digit())
            .skip_while(|&&c| c == b'0')
            .count();
        if nd > 19 {
            return None;
        }
    }
    if i < s.len() && (s[i] == b'e' || s[i] == b'E') {
        i += 1;
        let eneg = match s.get(i) {
            Some(b'-') => {
                i += 1;
                true
            }
            Some(b'+') => {
                i += 1;
                false
            }
            _ => false,
        };
        let start = i;
        let mut e: i64 = 0;
        while i < s.len() && s[i].is_ascii_digit() && i - start < 6 {
            e = e * 10 + i64::from(s[i] - b'0');
            i += 1;
        }
        if i == start {
            return None;
        }
        exp += if eneg { -e } else { e };
    }
    if i != s.len() {
        return None;
    }
    let v = if m == 0 {
        0.0
    } else if m <= (1u64 << 53) && (-22..=22).contains(&exp) {
        let x = m as f64;
        if exp >= 0 {
            x * POW10[exp as usize]
        } else {
            x / POW10[(-exp) as usize]
        }
    } else if (0..=19).contains(&exp) {
        // m·10^e < 2^64·10^19 < 2^128 is an exact integer; the conversion
        // rounds it to nearest.
        (u128::from(m) * 10u128.pow(exp as u32)) as f64
    } else if (-19..0).contains(&exp) {
        match nearest_quotient(m, (-exp) as u32) {
            Some(v) => v,
            None => quotient(m, (-exp) as u32)?,
        }
    } else if (-27..0).contains(&exp) {
        quotient(m, (-exp) as u32)?
    } else {
        return None;
    };
    Some(if neg { -v } else { v })
}

/// Appends the digits of `s` from `i` on to `m` (wrapping): eight at a
/// time while eight digits follow (`m·10^8 + value`, the eight bytes
/// converted at once), then one by one. Returns `m` and the index after
/// the digits.
#[inline(always)]
fn digit_run(s: &[u8], mut i: usize, mut m: u64) -> (u64, usize) {
    while let Some(chunk) = s.get(i..i + 8) {
        let w = u64::from_le_bytes(chunk.try_into().unwrap_or_default());
        // All eight bytes in '0'..='9': high nibbles 3, and adding 6 to
        // each keeps them there.
        let all_digits = ((w & 0xF0F0_F0F0_F0F0_F0F0)
            | (((w.wrapping_add(0x0606_0606_0606_0606)) & 0xF0F0_F0F0_F0F0_F0F0) >> 4))
            == 0x3333_3333_3333_3333;
        if !all_digits {
            break;
        }
        // Pairs, then quads, then the eight-digit value.
        let v = w - 0x3030_3030_3030_3030;
        let v = v.wrapping_mul(10).wrapping_add(v >> 8);
        let v = ((v & 0x0000_00FF_0000_00FF)
            .wrapping_mul(100 + (1_000_000 << 32))
            .wrapping_add(((v >> 16) & 0x0000_00FF_0000_00FF).wrapping_mul(1 + (10_000 << 32))))
            >> 32;
        m = m.wrapping_mul(100_000_000).wrapping_add(v & 0xFFFF_FFFF);
        i += 8;
    }
    while let Some(&c) = s.get(i) {
        let d = c.wrapping_sub(b'0');
        if d > 9 {
            break;
        }
        m = m.wrapping_mul(10).wrapping_add(u64::from(d));
        i += 1;
    }
    (m, i)
}

/// `m / 10^k` correctly rounded (`0 < m < 2^64`, `k ≤ 19`) without
/// dividing integers: the quotient of the rounded doubles is within two
/// units in the last place of the exact one; from it, the walk towards
/// `m / 10^k` stops at the double whose rounding interval holds it, found
/// by exact integer comparisons with the interval's ends (`y = M·2^E`, ends
/// `(2M ± 1)·2^(E-1)`, compared as `m·2^(1-E)` with `(2M ± 1)·10^k`;
/// a tie goes to the even significand). `None` when the result is below
/// 2^-10 or not below 2^53 (the shift would not fit) or not found within
/// four steps.
fn nearest_quotient(m: u64, k: u32) -> Option<f64> {
    let p = 10u64.pow(k);
    let mut y = m as f64 / POW10[k as usize];
    for _ in 0..4 {
        let bits = y.to_bits();
        let biased = (bits >> 52) as i32;
        // Normal values in [2^-10, 2^53) only.
        if !(1013..1076).contains(&biased) {
            return None;
        }
        let big_m = (bits & ((1 << 52) - 1)) | 1 << 52;
        let e = biased - 1075; // y = big_m·2^e, -62 <= e <= 0
        let lhs = u128::from(m) << (1 - e);
        let hi = u128::from(2 * big_m + 1) * u128::from(p);
        // At a power of two the lower neighbour is half as far.
        let lo = if big_m == 1 << 52 {
            u128::from(4 * big_m - 1) * u128::from(p)
        } else {
            u128::from(2 * big_m - 1) * u128::from(p)
        };
        let lhs_lo = if big_m == 1 << 52 { lhs << 1 } else { lhs };
        let even = big_m & 1 == 0;
        let above_lo = lhs_lo > lo || (lhs_lo == lo && even);
        let below_hi = lhs < hi || (lhs == hi && even);
        if above_lo && below_hi {
            return Some(y);
        }
        // Towards the exact quotient (the next interval is adjacent).
        y = if below_hi { y.next_down() } else { y.next_up() };
    }
    None
}

/// `m / 10^k` correctly rounded (`m > 0`, `k ≤ 27`), by integer division:
/// `q = ⌊m·2^s / 10^k⌋` with `m·2^s` as large as fits below 2^127, the
/// remainder folded into bit 0 as a sticky bit. With at least 55
/// significant bits in `q`, bit 0 lies below the rounding bit of a 53-bit
/// significand, so rounding `q | sticky` to nearest (the `u128 → f64`
/// conversion) rounds the exact quotient, and the scaling by `2^-s` is
/// exact. `None` when `q` is too short (the caller falls back).
fn quotient(m: u64, k: u32) -> Option<f64> {
    let d = 10u128.pow(k);
    let s = 127 - (64 - m.leading_zeros());
    let num = u128::from(m) << s;
    let (q, r) = (num / d, num % d);
    if 128 - q.leading_zeros() < 55 {
        return None;
    }
    let q = q | u128::from(r != 0);
    // 2^-s exactly (s ≤ 127: a normal double).
    let scale = f64::from_bits(u64::from(1023 - s) << 52);
    Some(q as f64 * scale)
}

pub(crate) fn show(tok: &[u8]) -> String {
    let s = String::from_utf8_lossy(tok);
    let mut s: String = s.chars().take(40).collect();
    if tok.len() > 40 {
        s.push('…');
    }
    format!("\"{s}\"")
}

pub(crate) fn parse_int(tok: &[u8], line: usize, what: &str) -> Result<i64, IoError> {
    if let Some(v) = fast_int(tok) {
        return Ok(v);
    }
    std::str::from_utf8(tok)
        .ok()
        .and_then(|s| s.parse::<i64>().ok())
        .ok_or_else(|| IoError::syntax(line, what.to_string(), show(tok)))
}

pub(crate) fn parse_count(tok: &[u8], line: usize, what: &str) -> Result<usize, IoError> {
    if let Some(v) = fast_int(tok).filter(|&v| v >= 0 && tok[0] != b'-') {
        return Ok(v as usize);
    }
    std::str::from_utf8(tok)
        .ok()
        .and_then(|s| s.parse::<usize>().ok())
        .ok_or_else(|| IoError::syntax(line, what.to_string(), show(tok)))
}

/// Parses a real number; `nan`, `inf`, `infinity` (any case, with sign) are
/// accepted so that the mesher can report which point carries them.
pub(crate) fn parse_f64(tok: &[u8], line: usize, what: &str) -> Result<f64, IoError> {
    if let Some(v) = fast_f64(tok) {
        return Ok(v);
    }
    std::str::from_utf8(tok)
        .ok()
        .and_then(|s| s.parse::<f64>().ok())
        .ok_or_else(|| IoError::syntax(line, what.to_string(), show(tok)))
}

/// Checks the index of item `k` (0-based position in the file) and, for the
/// first item, detects whether the file numbers from 0 or 1.
pub(crate) fn check_index(
    tok: &[u8],
    line: usize,
    k: usize,
    first: &mut Option<u32>,
    what: &str,
) -> Result<(), IoError> {
    // The message is formatted only when the fast path fails.
    let idx = match fast_int(tok) {
        Some(i) => i,
        None => parse_int(tok, line, &format!("{what} index"))?,
    };
    match *first {
        None => {
            if idx != 0 && idx != 1 {
                return Err(IoError::syntax(
                    line,
                    format!("first {what} index 0 or 1"),
                    idx.to_string(),
                ));
            }
            *first = Some(idx as u32);
        }
        Some(f) => {
            let want = f as i64 + k as i64;
            if idx != want {
                return Err(IoError::syntax(
                    line,
                    format!("{what} index {want}"),
                    idx.to_string(),
                ));
            }
        }
    }
    Ok(())
}

/// The content of a Triangle/TetGen `.node` file, as returned by [`read_node`].
///
/// ```
/// let f = delone_io::read_node(b"1 3 0 0\n0 1 2 3\n").unwrap();
/// assert_eq!((f.dim, f.first_index, f.header_line), (3, 0, 1));
/// assert_eq!(f.coords, vec![1.0, 2.0, 3.0]);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct NodeFile {
    /// Dimension from the header: 2 or 3.
    pub dim: usize,
    /// Coordinates, `dim` per point, point after point.
    pub coords: Vec<f64>,
    /// Number of attributes per point.
    pub n_attributes: usize,
    /// Attributes, `n_attributes` per point, point after point.
    pub attributes: Vec<f64>,
    /// Boundary markers, one per point, if the header announces them.
    pub markers: Option<Vec<i32>>,
    /// Index of the first point in the file (0 or 1); later indices must be
    /// consecutive.
    pub first_index: u32,
    /// Line number of the header (1-based, for messages).
    pub header_line: usize,
    /// Line number of each point record (1-based, for messages; 4 bytes a
    /// point, saturating at `u32::MAX` in files of more than 4 billion lines).
    pub lines: Vec<u32>,
}

impl NodeFile {
    /// Number of points.
    ///
    /// ```
    /// let f = delone_io::read_node(b"2 2 0 0\n1 0 0\n2 1 0\n").unwrap();
    /// assert_eq!(f.len(), 2);
    /// ```
    pub fn len(&self) -> usize {
        self.lines.len()
    }

    /// `true` when the file holds no point.
    ///
    /// ```
    /// let f = delone_io::read_node(b"0 2 0 0\n").unwrap();
    /// assert!(f.is_empty());
    /// ```
    pub fn is_empty(&self) -> bool {
        self.lines.is_empty()
    }

    /// The points as fixed-size arrays, if the file's dimension is `D`.
    ///
    /// ```
    /// let f = delone_io::read_node(b"2 2 0 0\n1 0 0.5\n2 1 2\n").unwrap();
    /// assert_eq!(f.points::<2>(), Some(vec![[0.0, 0.5], [1.0, 2.0]]));
    /// assert_eq!(f.points::<3>(), None);
    /// ```
    pub fn points<const D: usize>(&self) -> Option<Vec<[f64; D]>> {
        self.points_threads(1)
    }

    /// [`NodeFile::points`] copied in runs of at least 64Ki points on up to
    /// `threads` threads.
    ///
    /// ```
    /// let f = delone_io::read_node(b"2 2 0 0\n1 0 0\n2 1 0.5\n").unwrap();
    /// assert_eq!(f.points_threads::<2>(2), f.points::<2>());
    /// ```
    pub fn points_threads<const D: usize>(&self, threads: usize) -> Option<Vec<[f64; D]>> {
        if D != self.dim || D == 0 {
            return None;
        }
        let mut pts = vec![[0.0; D]; self.coords.len() / D];
        let run = pts.len().div_ceil(threads.max(1)).max(1 << 16);
        let runs: Vec<(&mut [[f64; D]], &[f64])> = pts
            .chunks_mut(run)
            .zip(self.coords.chunks(run * D))
            .collect();
        let runs: Vec<_> = runs.into_iter().map(std::sync::Mutex::new).collect();
        let copied = crate::par::scoped_map(runs.len(), |k| {
            if let Ok(mut r) = runs[k].lock() {
                let (p, c) = &mut *r;
                for (p, c) in p.iter_mut().zip(c.chunks_exact(D)) {
                    p.copy_from_slice(c);
                }
            }
        });
        for r in copied {
            r.unwrap_or_else(|e| std::panic::resume_unwind(e));
        }
        Some(pts)
    }
}

/// Reads a Triangle/TetGen `.node` file from bytes.
///
/// Header: `<#points> <dimension> [<#attributes> [<#boundary markers (0|1)>]]`
/// (missing trailing header fields default to 0); then one line per point:
/// `<index> <x> <y> [<z>] [attributes…] [marker]`. The first index (0 or 1)
/// is detected from the first point; later indices must be consecutive.
/// A missing marker at the end of a point line reads as 0 and extra fields
/// are ignored, as Triangle and TetGen do; missing coordinates or attributes
/// are an error. `nan` and `inf` parse as numbers (the mesher rejects them,
/// naming the point).
///
/// # Errors
/// [`IoError::Syntax`] for a malformed field (with line, expectation and
/// finding), [`IoError::UnexpectedEnd`] when there are fewer points than the
/// header says, [`IoError::Unsupported`] for a dimension other than 2 or 3.
///
/// ```
/// let text = b"# a square\n4 2 1 1\n1 0 0 7.5 1\n2 1 0 7.5 1\n3 1 1 7.5 1\n4 0 1 7.5 1\n";
/// let f = delone_io::read_node(text).unwrap();
/// assert_eq!((f.dim, f.len(), f.first_index), (2, 4, 1));
/// assert_eq!(f.attributes, vec![7.5; 4]);
/// assert_eq!(f.markers, Some(vec![1; 4]));
///
/// let err = delone_io::read_node(b"3 2 0 0\n1 0 0\n2 1\n").unwrap_err();
/// assert_eq!(err.to_string(), "line 3: expected 2 coordinates, found 1");
/// ```
pub fn read_node(input: &[u8]) -> Result<NodeFile, IoError> {
    read_node_threads(input, 1)
}

/// [`read_node`] with the point records parsed on up to `threads` threads:
/// the text after the header is cut into that many runs of whole lines (of
/// 1 MiB at least), parsed side by side and joined in order. The result is the same for any
/// thread count, errors included (an input any run finds fault with is read
/// again on one thread, which reports the first error of the file).
///
/// ```
/// let text = b"3 3 0 0\n0 0 0 0\n1 1 0 0\n# a comment\n2 0 1 0\n";
/// assert_eq!(delone_io::read_node_threads(text, 2).unwrap(), delone_io::read_node(text).unwrap());
/// ```
pub fn read_node_threads(input: &[u8], threads: usize) -> Result<NodeFile, IoError> {
    read_node_split(input, threads, 1 << 20)
}

/// [`read_node_threads`] with runs of at least about `min_run` bytes: a
/// small file is not worth a thread.
fn read_node_split(input: &[u8], threads: usize, min_run: usize) -> Result<NodeFile, IoError> {
    let threads = threads.min(input.len() / min_run.max(1) + 1);
    let mut rec = Records::new(input);
    let mut toks = Vec::with_capacity(8);
    let Some(hline) = rec.next(&mut toks) else {
        return Err(IoError::syntax(1, "a header line", "an empty file"));
    };
    if threads > 1 {
        let (head, n) = node_header(&toks, hline, input.len())?;
        if let Some(f) = node_runs(&head, n, rec.rest, hline, threads) {
            return Ok(f);
        }
    }
    read_node_body(&mut rec, &mut toks, hline, input.len())
}

/// The point records of `body` (the text after the header at line `hline`)
/// parsed as `threads` runs of whole lines on as many threads; `None` when a
/// run finds an error or the runs do not join into `n` consecutively
/// numbered points (the caller then reads on one thread for the message).
fn node_runs(
    head: &NodeFile,
    n: usize,
    body: &[u8],
    hline: usize,
    threads: usize,
) -> Option<NodeFile> {
    let mut runs = Vec::with_capacity(threads);
    let mut rest = body;
    for left in (1..threads).rev() {
        let cut = rest.len() / (left + 1);
        let end = rest[cut..]
            .iter()
            .position(|&b| b == b'\n')
            .map_or(rest.len(), |p| cut + p + 1);
        let (a, b) = rest.split_at(end);
        runs.push(a);
        rest = b;
    }
    runs.push(rest);
    // Each run: its points (`first_index` = the index of its first point)
    // and its number of lines; the first run numbers its lines on from the
    // header and its first index must be 0 or 1.
    let parse = |k: usize| {
        let run = runs[k];
        let cap = if k == 0 {
            n.min(body.len() / 6 + 1)
        } else {
            n.min(run.len() / 6 + 1)
        };
        let mut f = head.empty(cap);
        let mut rec = Records {
            rest: run,
            line: if k == 0 { hline } else { 0 },
        };
        let mut first = None;
        let toks = &mut Vec::with_capacity(8);
        let ok = node_records(&mut rec, toks, n, &mut f, &mut first, k > 0).is_ok();
        // Complete records only (an error may leave part of one behind).
        f.truncate(f.len());
        f.first_index = first.unwrap_or(0);
        (f, rec.line, ok)
    };
    let parsed: Vec<Option<(NodeFile, usize, bool)>> = crate::par::scoped_map(runs.len(), parse)
        .into_iter()
        .map(Result::ok)
        .collect();
    // Joined in order; an error counts only before the n-th point.
    let mut parsed = parsed.into_iter();
    let (mut f, mut lines, ok) = parsed.next()??;
    if f.is_empty() || !ok && f.len() < n {
        return None;
    }
    for part in parsed {
        if f.len() >= n {
            break;
        }
        let (g, g_lines, ok) = part?;
        if !g.is_empty() && g.first_index as usize != f.first_index as usize + f.len() {
            return None;
        }
        let at = u32::try_from(lines).unwrap_or(u32::MAX);
        f.coords.extend_from_slice(&g.coords);
        f.attributes.extend_from_slice(&g.attributes);
        if let (Some(m), Some(gm)) = (f.markers.as_mut(), &g.markers) {
            m.extend_from_slice(gm);
        }
        f.lines
            .extend(g.lines.iter().map(|&l| l.saturating_add(at)));
        lines += g_lines;
        if !ok && f.len() < n {
            return None;
        }
    }
    if f.len() < n {
        return None;
    }
    f.truncate(n);
    Some(f)
}

/// The header of a `.node` section (its tokens in `toks`, at line `hline`):
/// an empty [`NodeFile`] with its layout, and the number of points.
fn node_header(
    toks: &[&[u8]],
    hline: usize,
    input_len: usize,
) -> Result<(NodeFile, usize), IoError> {
    let n = parse_count(toks[0], hline, "the number of points")?;
    let dim = match toks.get(1) {
        Some(t) => parse_count(t, hline, "the dimension (2 or 3)")?,
        None => return Err(IoError::syntax(hline, "the dimension (2 or 3)", "nothing")),
    };
    if dim != 2 && dim != 3 {
        return Err(IoError::Unsupported {
            line: hline,
            message: format!("dimension {dim} is not supported (only 2 and 3)"),
        });
    }
    let nattr = match toks.get(2) {
        Some(t) => parse_count(t, hline, "the number of attributes")?,
        None => 0,
    };
    let nmark = match toks.get(3) {
        Some(t) => parse_count(t, hline, "the number of boundary markers (0 or 1)")?,
        None => 0,
    };
    if nmark > 1 {
        return Err(IoError::syntax(
            hline,
            "the number of boundary markers (0 or 1)",
            nmark.to_string(),
        ));
    }
    let head = NodeFile {
        dim,
        coords: Vec::new(),
        n_attributes: nattr,
        attributes: Vec::new(),
        markers: (nmark == 1).then(Vec::new),
        first_index: 1,
        header_line: hline,
        lines: Vec::new(),
    };
    // Never trust the header for allocation: a point needs at least 6 bytes.
    let f = head.empty(n.min(input_len / 6 + 1));
    Ok((f, n))
}

impl NodeFile {
    /// Keeps the first `n` points (and no partly read one).
    fn truncate(&mut self, n: usize) {
        self.coords.truncate(n * self.dim);
        self.attributes.truncate(n * self.n_attributes);
        if let Some(m) = self.markers.as_mut() {
            m.truncate(n);
        }
        self.lines.truncate(n);
    }

    /// No points, this file's layout, room for `cap` points.
    fn empty(&self, cap: usize) -> NodeFile {
        NodeFile {
            coords: Vec::with_capacity(cap.saturating_mul(self.dim)),
            // A header may announce absurdly many attributes: at most a
            // few per point are reserved up front.
            attributes: Vec::with_capacity(cap.saturating_mul(self.n_attributes.min(4))),
            markers: self.markers.as_ref().map(|_| Vec::with_capacity(cap)),
            lines: Vec::with_capacity(cap),
            ..*self
        }
    }
}

/// Parses up to `n` point records from `rec` into `f` and returns how many
/// it found. The first record's index must be 0 or 1 (any, when
/// `any_start`: a run that starts inside the file) and sets `first`; the
/// next ones count on from it.
fn node_records<'a>(
    rec: &mut Records<'a>,
    toks: &mut Vec<&'a [u8]>,
    n: usize,
    f: &mut NodeFile,
    first: &mut Option<u32>,
    any_start: bool,
) -> Result<usize, IoError> {
    let (dim, nattr) = (f.dim, f.n_attributes);
    for k in 0..n {
        let Some(line) = rec.next(toks) else {
            return Ok(k);
        };
        if any_start && k == 0 {
            *first = fast_int(toks[0]).and_then(|i| u32::try_from(i).ok());
        }
        check_index(toks[0], line, k, first, "point")?;
        let have = toks.len() - 1;
        if have < dim {
            return Err(IoError::syntax(
                line,
                format!("{dim} coordinates"),
                have.to_string(),
            ));
        }
        for t in &toks[1..=dim] {
            f.coords.push(parse_f64(t, line, "a coordinate")?);
        }
        if have < dim.saturating_add(nattr) {
            return Err(IoError::syntax(
                line,
                format!("{nattr} attribute(s) after the coordinates"),
                (have - dim).to_string(),
            ));
        }
        for t in &toks[1 + dim..1 + dim + nattr] {
            f.attributes.push(parse_f64(t, line, "an attribute")?);
        }
        if let Some(m) = f.markers.as_mut() {
            m.push(match toks.get(1 + dim + nattr) {
                Some(t) => {
                    let v = parse_int(t, line, "a boundary marker (integer)")?;
                    i32::try_from(v).map_err(|_| {
                        IoError::syntax(line, "a boundary marker in the i32 range", v.to_string())
                    })?
                }
                None => 0,
            });
        }
        f.lines.push(u32::try_from(line).unwrap_or(u32::MAX));
    }
    Ok(n)
}

/// The `.node` section after its header record (in `toks`, at line `hline`);
/// shared with the `.poly` reader.
pub(crate) fn read_node_body<'a>(
    rec: &mut Records<'a>,
    toks: &mut Vec<&'a [u8]>,
    hline: usize,
    input_len: usize,
) -> Result<NodeFile, IoError> {
    let (mut f, n) = node_header(toks, hline, input_len)?;
    let mut first = None;
    let found = node_records(rec, toks, n, &mut f, &mut first, false)?;
    if found < n {
        return Err(IoError::UnexpectedEnd {
            line: hline,
            what: "points",
            declared: n,
            found,
        });
    }
    f.first_index = first.unwrap_or(1);
    Ok(f)
}

/// The content of a Triangle/TetGen `.ele` file, as returned by [`read_ele`].
///
/// ```
/// let f = delone_io::read_ele(b"1 4 0\n1 1 2 3 4\n", 1).unwrap();
/// assert_eq!((f.nodes_per_element, f.elements.clone()), (4, vec![0, 1, 2, 3]));
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct EleFile {
    /// Nodes per element (3 for triangles, 4 for tetrahedra, 6/10 for
    /// second-order elements).
    pub nodes_per_element: usize,
    /// Vertex indices, `nodes_per_element` per element, converted to 0-based.
    pub elements: Vec<u32>,
    /// Number of attributes per element.
    pub n_attributes: usize,
    /// Attributes, `n_attributes` per element.
    pub attributes: Vec<f64>,
    /// Index of the first element in the file (0 or 1).
    pub first_index: u32,
}

impl EleFile {
    /// Number of elements.
    ///
    /// ```
    /// let f = delone_io::read_ele(b"1 3 0\n1 1 2 3\n", 1).unwrap();
    /// assert_eq!(f.len(), 1);
    /// ```
    pub fn len(&self) -> usize {
        self.elements
            .len()
            .checked_div(self.nodes_per_element)
            .unwrap_or(0)
    }

    /// `true` when the file holds no element.
    ///
    /// ```
    /// let f = delone_io::read_ele(b"0 3 0\n", 1).unwrap();
    /// assert!(f.is_empty());
    /// ```
    pub fn is_empty(&self) -> bool {
        self.elements.is_empty()
    }
}

/// Reads a Triangle/TetGen `.ele` file; node indices are converted to
/// 0-based by subtracting `node_first_index` (the numbering of the matching
/// `.node` file, see [`NodeFile::first_index`]).
///
/// Header: `<#elements> <nodes per element> [<#attributes>]`; then
/// `<index> <node>… [attributes…]`.
///
/// # Errors
/// As [`read_node`]; a node index below `node_first_index` is a
/// [`IoError::Syntax`] error.
///
/// ```
/// let f = delone_io::read_ele(b"2 3 0\n0 0 1 2\n1 2 1 3\n", 0).unwrap();
/// assert_eq!(f.elements, vec![0, 1, 2, 2, 1, 3]);
/// ```
pub fn read_ele(input: &[u8], node_first_index: u32) -> Result<EleFile, IoError> {
    let mut rec = Records::new(input);
    let mut toks = Vec::with_capacity(8);
    let Some(hline) = rec.next(&mut toks) else {
        return Err(IoError::syntax(1, "a header line", "an empty file"));
    };
    let n = parse_count(toks[0], hline, "the number of elements")?;
    let k = match toks.get(1) {
        Some(t) => parse_count(t, hline, "the number of nodes per element")?,
        None => {
            return Err(IoError::syntax(
                hline,
                "the number of nodes per element",
                "nothing",
            ))
        }
    };
    if !(2..=64).contains(&k) {
        return Err(IoError::Unsupported {
            line: hline,
            message: format!("{k} nodes per element is not supported"),
        });
    }
    let nattr = match toks.get(2) {
        Some(t) => parse_count(t, hline, "the number of attributes")?,
        None => 0,
    };
    let cap = n.min(input.len() / 8 + 1);
    let mut elements = Vec::with_capacity(cap * k);
    let mut attributes = Vec::with_capacity(cap.saturating_mul(nattr).min(input.len()));
    let mut first = None;
    for e in 0..n {
        let Some(line) = rec.next(&mut toks) else {
            return Err(IoError::UnexpectedEnd {
                line: hline,
                what: "elements",
                declared: n,
                found: e,
            });
        };
        check_index(toks[0], line, e, &mut first, "element")?;
        let have = toks.len() - 1;
        if have < k {
            return Err(IoError::syntax(
                line,
                format!("{k} node indices"),
                have.to_string(),
            ));
        }
        for t in &toks[1..=k] {
            let v = parse_int(t, line, "a node index")?;
            let z = v - node_first_index as i64;
            let z = u32::try_from(z).map_err(|_| {
                IoError::syntax(
                    line,
                    format!("a node index >= {node_first_index}"),
                    v.to_string(),
                )
            })?;
            elements.push(z);
        }
        if have < k.saturating_add(nattr) {
            return Err(IoError::syntax(
                line,
                format!("{nattr} attribute(s) after the node indices"),
                (have - k).to_string(),
            ));
        }
        for t in &toks[1 + k..1 + k + nattr] {
            attributes.push(parse_f64(t, line, "an attribute")?);
        }
    }
    Ok(EleFile {
        nodes_per_element: k,
        elements,
        n_attributes: nattr,
        attributes,
        first_index: first.unwrap_or(1),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The old tokenizer: split at newlines, cut comments, split at ASCII
    /// whitespace.
    fn records_ref(input: &[u8]) -> Vec<(usize, Vec<&[u8]>)> {
        let mut out = Vec::new();
        let mut rest = input;
        let mut line = 0;
        while !rest.is_empty() {
            line += 1;
            let (l, r) = match rest.iter().position(|&b| b == b'\n') {
                Some(p) => (&rest[..p], &rest[p + 1..]),
                None => (rest, &rest[rest.len()..]),
            };
            rest = r;
            let l = &l[..l.iter().position(|&b| b == b'#').unwrap_or(l.len())];
            let toks: Vec<&[u8]> = l
                .split(|b| b.is_ascii_whitespace())
                .filter(|t| !t.is_empty())
                .collect();
            if !toks.is_empty() {
                out.push((line, toks));
            }
        }
        out
    }

    fn xorshift(seed: u64) -> impl FnMut() -> u64 {
        let mut s = seed;
        move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s
        }
    }

    #[test]
    fn one_pass_tokenizer_matches_split() {
        let mut r = xorshift(0x1234_5678_9abc_def1);
        let alphabet = b"ab1.# \t\r\n\n\x0c-e";
        for round in 0..300 {
            let len = (r() % 60) as usize + round % 3;
            let input: Vec<u8> = (0..len)
                .map(|_| alphabet[(r() % alphabet.len() as u64) as usize])
                .collect();
            records_match_split(&input);
        }
    }

    /// The records `Records` yields for `input` are those of `records_ref`.
    fn records_match_split(input: &[u8]) {
        let mut rec = Records::new(input);
        let mut toks = Vec::new();
        let mut got = Vec::new();
        while let Some(l) = rec.next(&mut toks) {
            got.push((l, toks.clone()));
        }
        assert_eq!(
            got,
            records_ref(input),
            "{:?}",
            String::from_utf8_lossy(input)
        );
    }

    /// Long tokens (the eight-byte steps of `token_end`) with the bytes
    /// next to its threshold: token bytes below it (control characters,
    /// `!`, `"`), `$` at it, bytes above 0x7F, and every separator.
    #[test]
    fn long_tokens_match_split() {
        let mut r = xorshift(0x0bad_cafe_f00d_1234);
        let tokens = b"0123456789.e-+$!\"\x01\x1f\x7f\x80\xff";
        let seps = b" \t\r\n\x0c#";
        for round in 0..2000 {
            let len = (r() % 200) as usize + round % 9;
            let input: Vec<u8> = (0..len)
                .map(|_| match r() % 16 {
                    0 => seps[(r() % seps.len() as u64) as usize],
                    _ => tokens[(r() % tokens.len() as u64) as usize],
                })
                .collect();
            records_match_split(&input);
        }
    }

    #[test]
    fn long_significands_take_the_integer_paths() {
        // 17 significant digits (more than 2^53): the quotient path.
        for t in [
            "-0.16766200000000001",
            "-0.0073921400000000002",
            "106.10069274902344",
        ] {
            let got = fast_f64(t.as_bytes()).expect("fast path");
            assert_eq!(got.to_bits(), t.parse::<f64>().unwrap().to_bits(), "{t}");
        }
        // Large integers: the product path.
        for t in ["1234567890123456789", "98765432109876543e2"] {
            let got = fast_f64(t.as_bytes()).expect("fast path");
            assert_eq!(got.to_bits(), t.parse::<f64>().unwrap().to_bits(), "{t}");
        }
        assert_eq!(quotient(1, 27), None);
    }

    /// The quotient by comparisons gives `str::parse`'s double (or none):
    /// random significands and scales, `repr`-style coordinates, exact
    /// ties (to even) and the ends of the binades.
    #[test]
    fn nearest_quotient_rounds_as_str_parse() {
        let mut r = xorshift(0x5eed_00f0_c0ff_ee00);
        let check = |m: u64, k: u32| {
            let want: f64 = format!("{m}e-{k}").parse().unwrap();
            if let Some(got) = nearest_quotient(m, k) {
                assert_eq!(got.to_bits(), want.to_bits(), "{m}e-{k}");
            }
        };
        let mut found = 0;
        for _ in 0..300_000 {
            let m = (r() >> (r() % 40)).max(1);
            let k = (r() % 19) as u32 + 1;
            check(m, k);
            found += usize::from(nearest_quotient(m, k).is_some());
        }
        assert!(found > 100_000, "{found}");
        // Ties: (2M + 1)·2^-k, and below a power of two (4M - 1)·2^-k.
        for k in 1..=4u32 {
            for _ in 0..20_000 {
                let big_m = (1u64 << 52) | (r() >> 12);
                check((2 * big_m + 1) * 5u64.pow(k), k);
                check((2 * big_m) * 5u64.pow(k), k);
            }
            check(((1u64 << 54) - 1) * 5u64.pow(k), k);
            check(((1u64 << 54) + 1) * 5u64.pow(k), k);
        }
        // Python's `repr` of uniform doubles in [0, 1): 16 or 17 digits.
        for _ in 0..100_000 {
            let x = (r() >> 11) as f64 / (1u64 << 53) as f64;
            let t = format!("{x:?}");
            let got = parse_f64(t.as_bytes(), 1, "x").ok();
            assert_eq!(got.map(f64::to_bits), Some(x.to_bits()), "{t}");
        }
    }

    #[test]
    fn fast_number_paths_match_str_parse() {
        let mut r = xorshift(0xfeed_beef_0123_4567);
        let fixed = [
            "0",
            "-0",
            "+0",
            "-0.0",
            "1.",
            ".5",
            "-.5",
            "1e22",
            "1e23",
            "9007199254740993",
            "9007199254740992",
            "0.1",
            "123456789012345678",
            "1234567890123456789",
            "12345678901234567890",
            "4.35e-22",
            "1e-22",
            "1e-23",
            "0.000000000000000000000001",
            "2.2250738585072014e-308",
            "1e",
            "e5",
            ".",
            "-",
            "+",
            "1e+5",
            "1E-5",
            "1.5e0007",
            "1.0000000000000000000001",
            "00000000000000000000000012.5",
            "1_0",
            "0x10",
            "inf",
            "-nan",
            "1.2.3",
            "1e5.0",
            "--1",
            "+-1",
            "5e1000000",
        ];
        let mut toks: Vec<String> = fixed.iter().map(|s| s.to_string()).collect();
        for _ in 0..20_000 {
            let digits = (r() % 20) as usize + 1;
            let mut t = String::new();
            match r() % 3 {
                0 => t.push('-'),
                1 => t.push('+'),
                _ => {}
            }
            let dot = (r() % (digits as u64 + 2)) as usize;
            for k in 0..digits {
                if k == dot {
                    t.push('.');
                }
                t.push(char::from(b'0' + (r() % 10) as u8));
            }
            if r().is_multiple_of(3) {
                t.push(if r().is_multiple_of(2) { 'e' } else { 'E' });
                if r().is_multiple_of(2) {
                    t.push('-');
                }
                t.push_str(&(r() % 40).to_string());
            }
            toks.push(t);
        }
        for _ in 0..20_000 {
            // Printed like `%.17g` and `%.9g` (the corpus files).
            let mant = (r() >> 11) as f64 / (1u64 << 53) as f64;
            let e = (r() % 40) as i32 - 25;
            let x = mant * 10f64.powi(e) * if r().is_multiple_of(2) { -1.0 } else { 1.0 };
            toks.push(format!("{x:.17}"));
            toks.push(format!("{:.17e}", x));
            toks.push(format!("{x:.9}"));
            toks.push(format!("{x}"));
        }
        for t in &toks {
            let want = t.parse::<f64>().ok();
            let got = parse_f64(t.as_bytes(), 1, "x").ok();
            assert_eq!(got.map(f64::to_bits), want.map(f64::to_bits), "{t}");
            assert_eq!(
                parse_int(t.as_bytes(), 1, "x").ok(),
                t.parse::<i64>().ok(),
                "{t}"
            );
            assert_eq!(
                parse_count(t.as_bytes(), 1, "x").ok(),
                t.parse::<usize>().ok(),
                "{t}"
            );
        }
    }

    #[test]
    fn comments_blank_lines_and_whitespace() {
        let t =
            b"# c\n\n  3\t2  0 1 # hdr\r\n0 0 0 5\n\n# mid\n1 1.5 -2e3 0\r\n2\t.5\t1.  3  extra\n";
        let f = read_node(t).unwrap();
        assert_eq!(f.first_index, 0);
        assert_eq!(f.coords, vec![0.0, 0.0, 1.5, -2000.0, 0.5, 1.0]);
        assert_eq!(f.markers, Some(vec![5, 0, 3]));
        assert_eq!(f.lines, vec![4, 7, 8]);
    }

    #[test]
    fn header_defaults_and_nan() {
        let f = read_node(b"2 3\n1 nan inf -inf\n2 1 2 3\n").unwrap();
        assert_eq!(f.dim, 3);
        assert!(f.coords[0].is_nan());
        assert_eq!(f.coords[1], f64::INFINITY);
        assert_eq!(f.markers, None);
        assert_eq!(f.n_attributes, 0);
    }

    #[test]
    fn errors_name_line_expectation_and_finding() {
        let cases: &[(&[u8], &str)] = &[
            (b"", "line 1: expected a header line, found an empty file"),
            (
                b"# only\n",
                "line 1: expected a header line, found an empty file",
            ),
            (
                b"5 2 0 0\n1 0 0\n2 1 0\n3 0 1\n",
                "line 1: header says 5 points but the file ends after 3",
            ),
            (
                b"x 2\n",
                "line 1: expected the number of points, found \"x\"",
            ),
            (
                b"3 4 0 0\n",
                "line 1: dimension 4 is not supported (only 2 and 3)",
            ),
            (
                b"2 2\n1 0 0\n3 1 1\n",
                "line 3: expected point index 2, found 3",
            ),
            (
                b"2 2\n5 0 0\n6 1 1\n",
                "line 2: expected first point index 0 or 1, found 5",
            ),
            (
                b"2 3\n1 0 0 0\n\n\n2 1 1\n",
                "line 5: expected 3 coordinates, found 2",
            ),
            (
                b"1 2\n1 0 abc\n",
                "line 2: expected a coordinate, found \"abc\"",
            ),
            (
                b"1 2 0 1\n1 0 0 x\n",
                "line 2: expected a boundary marker (integer), found \"x\"",
            ),
            (
                b"1 2 0 2\n",
                "line 1: expected the number of boundary markers (0 or 1), found 2",
            ),
        ];
        for (input, msg) in cases {
            let e = read_node(input).unwrap_err();
            assert_eq!(
                &e.to_string(),
                msg,
                "input {:?}",
                String::from_utf8_lossy(input)
            );
        }
    }

    #[test]
    fn ele_reader() {
        let f = read_ele(b"2 4 1\n1 1 2 3 4 7\n2 2 3 4 5 -1\n", 1).unwrap();
        assert_eq!(f.elements, vec![0, 1, 2, 3, 1, 2, 3, 4]);
        assert_eq!(f.attributes, vec![7.0, -1.0]);
        let e = read_ele(b"1 4 1\n1 1 2 3 4\n", 1).unwrap_err();
        assert_eq!(
            e.to_string(),
            "line 2: expected 1 attribute(s) after the node indices, found 0"
        );
        assert_eq!(f.len(), 2);
        let e = read_ele(b"1 3\n1 0 1 2\n", 1).unwrap_err();
        assert_eq!(e.to_string(), "line 2: expected a node index >= 1, found 0");
        let e = read_ele(b"2 3\n1 1 2 3\n", 1).unwrap_err();
        assert_eq!(
            e.to_string(),
            "line 1: header says 2 elements but the file ends after 1"
        );
    }

    /// Fuzz-style: random bytes, random token soups and every truncation of
    /// a valid file must give `Ok` or `Err`, never a panic.
    #[test]
    fn never_panics() {
        let valid =
            b"# x\n4 3 2 1\n1 0 0 0 1 2 1\n2 1 0 0 1 2 0\n3 0 1 0 1 2 1\n4 0 0 1 nan 2 -3\n";
        for cut in 0..=valid.len() {
            let _ = read_node(&valid[..cut]);
            let _ = read_ele(&valid[..cut], 1);
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
            b"\t",
            b"\r",
            b"x",
            b"\xff",
            b"18446744073709551616",
            b"99999999999",
            b"0.5",
            b"-",
            b"4",
        ];
        let mut s: u64 = 0x9E37_79B9_7F4A_7C15;
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
            let one = format!("{:?}", read_node(&buf));
            let many = format!("{:?}", read_node_split(&buf, 2 + (next() % 3) as usize, 1));
            assert_eq!(one, many, "{:?}", String::from_utf8_lossy(&buf));
            let _ = read_ele(&buf, (next() % 2) as u32);
        }
    }

    #[test]
    fn threaded_reading_matches_one_thread() {
        // Comments, blank lines, attributes, markers, a missing marker, and
        // text after the last point; then every prefix (the errors too).
        let mut text = String::from("# points\n40 3 1 1\n");
        for i in 1..=40 {
            let extra = match i % 7 {
                0 => "\n\n# between\n",
                3 => " # trailing\n",
                _ => "\n",
            };
            let mark = if i % 5 == 0 {
                String::new()
            } else {
                format!(" {}", i % 3)
            };
            text += &format!("{i} {}.25 -{i}e-3 0.{i} 7{mark}{extra}", i * 3);
        }
        text += "junk after the points\n";
        let b = text.as_bytes();
        for threads in 1..=6 {
            assert_eq!(
                read_node_split(b, threads, 1).unwrap(),
                read_node(b).unwrap()
            );
        }
        // A valid file is read in runs (no fall-back to one thread).
        let head: &[&[u8]] = &[b"40", b"3", b"1", b"1"];
        let (f, n) = node_header(head, 2, b.len()).unwrap();
        let body = &b[b"# points\n40 3 1 1\n".len()..];
        assert_eq!(node_runs(&f, n, body, 2, 3).unwrap(), read_node(b).unwrap());
        for cut in 0..=b.len() {
            let one = format!("{:?}", read_node(&b[..cut]));
            for threads in [2, 3, 5] {
                assert_eq!(format!("{:?}", read_node_split(&b[..cut], threads, 1)), one);
            }
        }
    }
}
