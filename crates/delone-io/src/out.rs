//! A small buffered text/binary emitter used by every writer.
//!
//! Integers are formatted by hand (no `fmt` machinery), floats with Rust's
//! shortest round-trip formatting (`{}` for ordinary magnitudes, `{:e}` for
//! very large or very small ones so that `1e300` does not print 301 digits).

use std::io::Write;

const FLUSH_AT: usize = 1 << 16;

/// "00" "01" … "99".
const PAIRS: [u8; 200] = {
    let mut t = [0u8; 200];
    let mut k = 0;
    while k < 100 {
        t[2 * k] = b'0' + (k / 10) as u8;
        t[2 * k + 1] = b'0' + (k % 10) as u8;
        k += 1;
    }
    t
};

/// 0, then the powers of ten 10^1 … 10^19.
const POW10: [u64; 20] = {
    let mut t = [0u64; 20];
    let mut k = 1;
    let mut p = 1u64;
    while k < 20 {
        p *= 10;
        t[k] = p;
        k += 1;
    }
    t
};

/// The number of decimal digits of `v` (1 for 0): the bit length gives
/// the digit count or one more, a comparison with a power of ten decides.
#[inline(always)]
fn decimal_len(v: u64) -> usize {
    let t = (((64 - (v | 1).leading_zeros()) * 1233) >> 12) as usize;
    t + usize::from(v >= POW10[t])
}

/// The four decimal digits of each `k < 10^4` (with leading zeros) as
/// ASCII in the bytes of a `u32`, first digit lowest (40 KB).
static DIGITS4: [u32; 10_000] = {
    let mut t = [0u32; 10_000];
    let mut k = 0;
    while k < 10_000 {
        let d = [k / 1000, k / 100 % 10, k / 10 % 10, k % 10];
        let mut word = 0u32;
        let mut i = 0;
        while i < 4 {
            word |= (b'0' as u32 + d[i] as u32) << (8 * i);
            i += 1;
        }
        t[k] = word;
        k += 1;
    }
    t
};

/// The eight decimal digits of `v < 10^8` (with leading zeros) as ASCII
/// in the bytes of a `u64`, most significant digit in the lowest byte (the
/// first in memory of `to_le_bytes`): the digits of `v / 10^4` and of
/// `v % 10^4` from [`DIGITS4`] (two loads where computing the digits
/// takes about 25 operations; `v` is capped, so larger values never
/// index past the table).
#[inline(always)]
fn eight_digits(v: u32) -> u64 {
    let hi = (v / 10_000).min(9_999) as usize;
    let lo = (v % 10_000) as usize;
    u64::from(DIGITS4[hi]) | u64::from(DIGITS4[lo]) << 32
}

/// The digits of `v < 10^8` without leading zeros, as ASCII in the low
/// bytes of the result (first digit lowest), and their count. The leading
/// zeros are the `'0'` bytes at the low end of [`eight_digits`], counted
/// by the trailing zero bits of the digit values (the last digit's byte
/// is flagged so that `0` keeps one digit).
#[inline(always)]
fn short_digits(v: u32) -> (u64, usize) {
    let w = eight_digits(v);
    let skip = ((w ^ 0x3030_3030_3030_3030) | 1 << 56).trailing_zeros() & !7;
    (w >> skip, 8 - (skip / 8) as usize)
}

pub(crate) struct Out<W: Write> {
    w: W,
    pub(crate) buf: Vec<u8>,
}

impl<W: Write> Out<W> {
    pub(crate) fn new(w: W) -> Self {
        Out {
            w,
            buf: Vec::with_capacity(FLUSH_AT + 4096),
        }
    }

    #[inline]
    pub(crate) fn str(&mut self, s: &str) {
        self.buf.extend_from_slice(s.as_bytes());
    }

    #[inline]
    pub(crate) fn byte(&mut self, b: u8) {
        self.buf.push(b);
    }

    /// Decimal digits. Below 10^8 all eight digit places are looked up at
    /// once into the bytes of a `u64` ([`eight_digits`]) and the leading
    /// zeros shifted out; above, two digits at a time from a table. The
    /// digits are appended as a fixed-size array cut back to their count:
    /// a copy the compiler inlines, where a copy of the digits alone calls
    /// `memcpy` for every number. Always inlined: called from the row
    /// formatters of [`Out::rows`] it otherwise stays a call.
    #[inline(always)]
    pub(crate) fn uint(&mut self, v: u64) {
        if v < 100_000_000 {
            let (d, len) = short_digits(v as u32);
            let end = self.buf.len() + len;
            self.buf.extend_from_slice(&d.to_le_bytes());
            self.buf.truncate(end);
            return;
        }
        let len = decimal_len(v);
        let end = self.buf.len() + len;
        let mut tmp = [0u8; 20];
        let (mut v, mut i) = (v, len);
        while v >= 100 {
            let r = (v % 100) as usize * 2;
            v /= 100;
            i -= 2;
            tmp[i..i + 2].copy_from_slice(&PAIRS[r..r + 2]);
        }
        if v >= 10 {
            let r = v as usize * 2;
            tmp[..2].copy_from_slice(&PAIRS[r..r + 2]);
        } else {
            tmp[0] = b'0' + v as u8;
        }
        self.buf.extend_from_slice(&tmp);
        self.buf.truncate(end);
    }

    /// A space, then [`Out::uint`]: below 10^7 one eight-byte copy.
    #[inline(always)]
    pub(crate) fn space_uint(&mut self, v: u64) {
        if v < 10_000_000 {
            let (d, len) = short_digits(v as u32);
            let end = self.buf.len() + len + 1;
            self.buf
                .extend_from_slice(&(d << 8 | u64::from(b' ')).to_le_bytes());
            self.buf.truncate(end);
        } else {
            self.buf.push(b' ');
            self.uint(v);
        }
    }

    /// [`Out::space_uint`] of `v + add` for every `v` of `vals`. Four
    /// values below 10^7 at a time (a space and at most seven digits:
    /// eight bytes each) are laid out in a 32-byte array, appended as one
    /// fixed-size copy cut back to their length: one capacity check for
    /// the four instead of one per value (an `.ele` row's vertices).
    #[inline(always)]
    pub(crate) fn space_uints(&mut self, vals: &[u32], add: u64) {
        let mut quads = vals.chunks_exact(4);
        for q in quads.by_ref() {
            let v = [0, 1, 2, 3].map(|k| u64::from(q[k]) + add);
            if v.iter().any(|&x| x >= 10_000_000) {
                v.iter().for_each(|&x| self.space_uint(x));
                continue;
            }
            let mut tmp = [0u8; 40];
            let mut pos = 0;
            for x in v {
                let (d, len) = short_digits(x as u32);
                tmp[pos..pos + 8].copy_from_slice(&(d << 8 | u64::from(b' ')).to_le_bytes());
                pos += len + 1;
            }
            let end = self.buf.len() + pos;
            self.buf.extend_from_slice(&tmp[..32]);
            self.buf.truncate(end);
        }
        for &x in quads.remainder() {
            self.space_uint(u64::from(x) + add);
        }
    }

    #[inline]
    pub(crate) fn int(&mut self, v: i64) {
        if v < 0 {
            self.buf.push(b'-');
        }
        self.uint(v.unsigned_abs());
    }

    #[inline]
    pub(crate) fn float(&mut self, x: f64) {
        push_float(&mut self.buf, x);
    }

    /// Ends a line and flushes the buffer when it is large.
    #[inline]
    pub(crate) fn nl(&mut self) -> std::io::Result<()> {
        self.buf.push(b'\n');
        self.maybe_flush()
    }

    #[inline]
    pub(crate) fn maybe_flush(&mut self) -> std::io::Result<()> {
        if self.buf.len() >= FLUSH_AT {
            self.w.write_all(&self.buf)?;
            self.buf.clear();
        }
        Ok(())
    }

    pub(crate) fn finish(mut self) -> std::io::Result<()> {
        self.w.write_all(&self.buf)?;
        self.buf.clear();
        self.w.flush()
    }
}

/// Rows per block of [`Out::rows`].
const BLOCK_ROWS: usize = 1 << 13;

/// The decimal text of consecutive row numbers, counted up in place (the
/// number of a row is its predecessor's plus one: no division).
struct RowNumber {
    /// The digits, first digit at 0; `len..` is zeros.
    digits: [u8; 24],
    len: usize,
}

impl RowNumber {
    fn new(v: u64) -> Self {
        let text = v.to_string();
        let mut digits = [0u8; 24];
        digits[..text.len()].copy_from_slice(text.as_bytes());
        RowNumber {
            digits,
            len: text.len(),
        }
    }

    /// Appends the number, then counts up.
    #[inline(always)]
    fn push_next(&mut self, buf: &mut Vec<u8>) {
        let end = buf.len() + self.len;
        if self.len <= 16 {
            // A fixed-size copy cut back (no `memcpy` call).
            buf.extend_from_slice(&self.digits[..16]);
            buf.truncate(end);
        } else {
            buf.extend_from_slice(&self.digits[..self.len]);
        }
        let mut k = self.len;
        loop {
            if k == 0 {
                // All nines: now a one and zeros, one digit longer.
                self.digits[0] = b'1';
                self.digits[self.len] = b'0';
                self.len += 1;
                return;
            }
            k -= 1;
            if self.digits[k] != b'9' {
                self.digits[k] += 1;
                return;
            }
            self.digits[k] = b'0';
        }
    }
}

impl<W: Write> Out<W> {
    /// Writes rows `0..n`, each its number `i + first`, then what `row`
    /// appends, then a newline, after what is buffered. With more than one thread, blocks of rows
    /// are formatted on up to `threads` threads (block `k` on thread
    /// `k mod threads`, at most two blocks ahead of the writer per thread)
    /// while this thread writes the finished blocks in order: the bytes do
    /// not depend on the thread count, the memory is a few blocks.
    pub(crate) fn rows(
        &mut self,
        n: usize,
        first: u64,
        threads: usize,
        row: impl Fn(&mut Out<Vec<u8>>, usize) + Sync,
    ) -> std::io::Result<()> {
        use std::sync::mpsc;
        let blocks = n.div_ceil(BLOCK_ROWS);
        let fill = |b: &mut Out<Vec<u8>>, k: usize| {
            b.buf.clear();
            let mut number = RowNumber::new((k * BLOCK_ROWS) as u64 + first);
            for i in k * BLOCK_ROWS..n.min((k + 1) * BLOCK_ROWS) {
                number.push_next(&mut b.buf);
                row(b, i);
                b.buf.push(b'\n');
            }
        };
        self.w.write_all(&self.buf)?;
        self.buf.clear();
        let workers = threads.min(blocks);
        let mut own = Out::new(Vec::new());
        if workers <= 1 {
            for k in 0..blocks {
                fill(&mut own, k);
                self.w.write_all(&own.buf)?;
            }
            return Ok(());
        }
        std::thread::scope(|s| {
            // Per worker: its finished blocks, and the written buffers going
            // back to it. A worker that cannot start leaves its blocks to
            // this thread; one whose writer is gone (an error) stops.
            let lanes: Vec<_> = (0..workers)
                .map(|j| {
                    let (done, blocks_rx) = mpsc::sync_channel::<Out<Vec<u8>>>(1);
                    let (back, spare) = mpsc::channel::<Out<Vec<u8>>>();
                    let fill = &fill;
                    let job = move || {
                        for k in (j..blocks).step_by(workers) {
                            let mut b = spare.try_recv().unwrap_or_else(|_| Out::new(Vec::new()));
                            fill(&mut b, k);
                            if done.send(b).is_err() {
                                return;
                            }
                        }
                    };
                    std::thread::Builder::new()
                        .spawn_scoped(s, job)
                        .ok()
                        .map(|_| (blocks_rx, back))
                })
                .collect();
            for k in 0..blocks {
                match lanes[k % workers]
                    .as_ref()
                    .map(|(rx, back)| (rx.recv(), back))
                {
                    Some((Ok(b), back)) => {
                        self.w.write_all(&b.buf)?;
                        // The worker may be done: then the buffer is dropped.
                        let _ = back.send(b);
                    }
                    // No worker, or it died (its panic resurfaces when the
                    // scope ends).
                    _ => {
                        fill(&mut own, k);
                        self.w.write_all(&own.buf)?;
                    }
                }
            }
            Ok(())
        })
    }
}

/// Appends the shortest text that parses back to exactly `x`: Rust's
/// `{x}` when `x` is zero, not finite or of magnitude in `[1e-5, 1e16)`,
/// else `{x:e}` — byte for byte, without the `fmt` machinery: the shortest
/// correctly rounded digits come from `zmij` (Schubfach) and are laid out
/// here, see [`shortest_digits`].
pub(crate) fn push_float(buf: &mut Vec<u8>, x: f64) {
    if x == 0.0 || !x.is_finite() {
        // `write!` into a Vec<u8> cannot fail.
        let _ = write!(buf, "{x}");
        return;
    }
    let mut z = zmij::Buffer::new();
    let s = z.format_finite(x).as_bytes();
    // Fast path: `zmij`'s fixed notation is Rust's `{x}` but for the
    // ".0" of integers and the ties of `shortest_digits`, which need the
    // last digit to weigh 2^(q+1) for the lowest set bit 2^q of |x|.
    // In this range an exponent has at most two digits and a sign: an
    // 'e' would be among the last four bytes.
    let n = s.len();
    if (1e-5..1e16).contains(&x.abs()) && (n < 5 || (s[n - 3] != b'e' && s[n - 4] != b'e')) {
        let (int, frac) = match s.iter().position(|&c| c == b'.') {
            Some(p) => (&s[..p], &s[p + 1..]),
            None => (s, &s[s.len()..]),
        };
        if frac == b"0" {
            buf.extend_from_slice(int);
            return;
        }
        if odd_parts(x).1 != -(frac.len() as i32) - 1 {
            push_bytes(buf, s);
            return;
        }
    }
    let (d, exp) = shortest_digits(x, s);
    // The digits of `d` (at most 17), right-aligned in `tmp`.
    let mut tmp = [0u8; 24];
    let len = decimal_len(d);
    tmp[16..].copy_from_slice(&eight_digits((d % 100_000_000) as u32).to_le_bytes());
    let hi = d / 100_000_000;
    tmp[8..16].copy_from_slice(&eight_digits((hi % 100_000_000) as u32).to_le_bytes());
    tmp[7] = b'0' + (hi / 100_000_000) as u8;
    let digits = &tmp[24 - len..];
    // Digits before the decimal point (none or fewer than zero: leading
    // zeros after it).
    let point = exp + len as i32;
    if x < 0.0 {
        buf.push(b'-');
    }
    if (1e-5..1e16).contains(&x.abs()) {
        if point <= 0 {
            buf.extend_from_slice(b"0.");
            buf.resize(buf.len() + point.unsigned_abs() as usize, b'0');
            buf.extend_from_slice(digits);
        } else if point as usize >= len {
            buf.extend_from_slice(digits);
            buf.resize(buf.len() + point as usize - len, b'0');
        } else {
            let (a, b) = digits.split_at(point as usize);
            buf.extend_from_slice(a);
            buf.push(b'.');
            buf.extend_from_slice(b);
        }
    } else {
        buf.push(digits[0]);
        if len > 1 {
            buf.push(b'.');
            buf.extend_from_slice(&digits[1..]);
        }
        buf.push(b'e');
        let e = point - 1;
        if e < 0 {
            buf.push(b'-');
        }
        let e = e.unsigned_abs() as usize;
        if e >= 100 {
            buf.push(b'0' + (e / 100) as u8);
        }
        if e >= 10 {
            buf.extend_from_slice(&PAIRS[e % 100 * 2..e % 100 * 2 + 2]);
        } else {
            buf.push(b'0' + e as u8);
        }
    }
}

/// Appends `s`: from 8 to 24 bytes as overlapping eight-byte copies (the
/// last one cut back first), which the compiler inlines where a copy of
/// variable length calls `memcpy`.
#[inline(always)]
fn push_bytes(buf: &mut Vec<u8>, s: &[u8]) {
    let n = s.len();
    if !(8..=24).contains(&n) {
        buf.extend_from_slice(s);
        return;
    }
    let end = buf.len() + n;
    let eight = |k: usize| -> [u8; 8] { s[k..k + 8].try_into().unwrap_or_default() };
    buf.extend_from_slice(&eight(0));
    if n > 16 {
        buf.extend_from_slice(&eight(8));
    }
    buf.truncate(end - 8);
    buf.extend_from_slice(&eight(n - 8));
}

/// `(m, q)` with `m` odd and `|x| = m·2^q` (`x` finite, nonzero).
fn odd_parts(x: f64) -> (u64, i32) {
    let bits = x.abs().to_bits();
    let (biased, frac_bits) = ((bits >> 52) as i32, bits & ((1 << 52) - 1));
    let (m, q) = match biased {
        0 => (frac_bits, -1074),
        _ => (frac_bits | 1 << 52, biased - 1075),
    };
    (m >> m.trailing_zeros(), q + m.trailing_zeros() as i32)
}

/// The shortest decimal `d·10^exp` (`d` without trailing zeros) that reads
/// back as `|x|` (finite, nonzero; `s` its text from `zmij`), as Rust's
/// own formatting chooses it:
/// `zmij`'s digits, except that where two candidates of that length are
/// equally close (`|x|` exactly halfway), Rust takes the upper and `zmij`
/// the even one.
fn shortest_digits(x: f64, s: &[u8]) -> (u64, i32) {
    // `zmij` writes `-?digits(.digits)?(e[+-]?digits)?`.
    let (mut d, mut exp, mut frac) = (0u64, 0i32, false);
    let mut i = usize::from(x < 0.0);
    while let Some(&c) = s.get(i) {
        match c {
            b'.' => frac = true,
            b'0'..=b'9' => {
                d = d.wrapping_mul(10).wrapping_add(u64::from(c - b'0'));
                exp -= i32::from(frac);
            }
            _ => break,
        }
        i += 1;
    }
    if s.get(i) == Some(&b'e') {
        let (neg, start) = match s.get(i + 1) {
            Some(b'-') => (true, i + 2),
            Some(b'+') => (false, i + 2),
            _ => (false, i + 1),
        };
        let e = (s.get(start..).unwrap_or_default().iter())
            .fold(0i32, |e, &c| e * 10 + i32::from(c.wrapping_sub(b'0')));
        exp += if neg { -e } else { e };
    }
    let strip = |d: &mut u64, exp: &mut i32| {
        while *d != 0 && (*d).is_multiple_of(10) {
            *d /= 10;
            *exp += 1;
        }
    };
    strip(&mut d, &mut exp);
    // |x| = m·2^q with m odd equals (d + 1/2)·10^exp = (2d + 1)·5^exp·2^(exp-1)
    // exactly when q = exp - 1 and m·5^-exp = 2d + 1 (exp < 0) or
    // m = (2d + 1)·5^exp (exp >= 0), both sides odd.
    let (m, q) = odd_parts(x);
    let odd = 2 * u128::from(d) + 1;
    let tie = q == exp - 1 && exp.unsigned_abs() <= 24 && {
        let p = 5u128.pow(exp.unsigned_abs());
        if exp < 0 {
            u128::from(m) * p == odd
        } else {
            u128::from(m) == odd * p
        }
    };
    if tie {
        d += 1;
        strip(&mut d, &mut exp);
    }
    (d, exp)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floats_round_trip() {
        let vals = [
            0.0,
            -0.0,
            1.0,
            -2.5,
            0.1,
            1e-5,
            1e-6,
            1e16,
            1e300,
            -1e-300,
            f64::MIN_POSITIVE,
            f64::MAX,
            5e-324,
            std::f64::consts::PI,
            123_456_789.123_456_79,
        ];
        for &v in &vals {
            let mut b = Vec::new();
            push_float(&mut b, v);
            let s = String::from_utf8(b).unwrap();
            let back: f64 = s.parse().unwrap();
            assert_eq!(back.to_bits(), v.to_bits(), "{v} printed as {s}");
            assert!(s.len() <= 24, "{s} too long");
        }
    }

    /// The text `push_float` must produce, from `fmt`.
    fn std_text(x: f64) -> String {
        let a = x.abs();
        if a == 0.0 || (1e-5..1e16).contains(&a) || !a.is_finite() {
            format!("{x}")
        } else {
            format!("{x:e}")
        }
    }

    fn same_as_std(x: f64) {
        let mut b = Vec::new();
        push_float(&mut b, x);
        assert_eq!(
            String::from_utf8(b).unwrap(),
            std_text(x),
            "{:#x}",
            x.to_bits()
        );
    }

    #[test]
    fn floats_as_std_formats_them() {
        // Random bit patterns (every exponent), random doubles in [0, 1)
        // and [0, 1000) as written by generators, short decimals, integers,
        // powers of two and ten, and the neighbours of every switch point.
        let mut s: u64 = 0x853c_49e6_748f_ea9b;
        let mut next = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            s ^ (s >> 29)
        };
        for _ in 0..300_000 {
            let r = next();
            same_as_std(f64::from_bits(r));
            same_as_std((r >> 11) as f64 / (1u64 << 53) as f64);
            same_as_std((r >> 11) as f64 / (1u64 << 53) as f64 * 1000.0 - 500.0);
            same_as_std((r % 100_000) as f64 / 1000.0);
            same_as_std((r >> 20) as f64);
        }
        for e in -1074..=1023 {
            same_as_std(2f64.powi(e));
            same_as_std(-3.0 * 2f64.powi(e));
        }
        for e in -324..=308 {
            let p: f64 = format!("1e{e}").parse().unwrap();
            for x in [p, p.next_up(), p.next_down(), 1.5 * p, -7.25 * p] {
                same_as_std(x);
            }
        }
        // Exact ties between two shortest candidates (odd multiples of
        // small powers of two at 15-17 significant digits): Rust takes
        // the upper one.
        for k in 0..60 {
            for _ in 0..2000 {
                let r = next();
                for sh in [0, 20, 35, 45] {
                    let x = (((r >> 11) >> sh) | 1) as f64 * 2f64.powi(k - 82 + sh);
                    same_as_std(x);
                    same_as_std(-x);
                }
            }
        }
        for x in [
            0.0,
            -0.0,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            f64::MAX,
            f64::MIN,
            f64::MIN_POSITIVE,
            5e-324,
            1e-5,
            1e16,
            9_999_999_999_999_998.0,
            0.1 + 0.2,
            5.444310685350916e14,
            3.439070283483335e35,
        ] {
            same_as_std(x);
        }
    }

    #[test]
    fn decimal_lengths() {
        for k in 0..20u32 {
            let p = 10u64.pow(k);
            assert_eq!(decimal_len(p), k as usize + 1);
            assert_eq!(decimal_len(p - 1), (k as usize).max(1));
            assert_eq!(decimal_len(p + 1), k as usize + 1);
        }
        assert_eq!(decimal_len(u64::MAX), 20);
        for v in (0..100_000u64).chain((0..64).map(|b| 1u64 << b)) {
            assert_eq!(decimal_len(v), v.to_string().len(), "{v}");
        }
    }

    #[test]
    fn eight_digits_of_every_count() {
        let mut s: u64 = 7;
        let vals = (0..200_000u32)
            .chain((0..8).map(|k| 10u32.pow(k)))
            .chain((1..=8).map(|k| 10u32.pow(k) - 1))
            .chain((0..1_000_000).map(|_| {
                s = s.wrapping_mul(6364136223846793005).wrapping_add(1);
                ((s >> 33) % 100_000_000) as u32
            }));
        for v in vals {
            assert_eq!(eight_digits(v).to_le_bytes(), *format!("{v:08}").as_bytes());
        }
    }

    #[test]
    fn ints() {
        let mut o = Out::new(Vec::new());
        for v in [0i64, 7, -1, 10, 1234567890, i64::MIN, i64::MAX] {
            o.int(v);
            o.byte(b' ');
        }
        let mut o2 = Out::new(Vec::new());
        for v in (0..2000u64).chain([99, 100, 101, 999_999, 1_000_000, u64::MAX]) {
            o2.buf.clear();
            o2.uint(v);
            assert_eq!(o2.buf, v.to_string().as_bytes());
        }
        let s = String::from_utf8(o.buf.clone()).unwrap();
        assert_eq!(
            s,
            format!("0 7 -1 10 1234567890 {} {} ", i64::MIN, i64::MAX)
        );
    }

    /// Every digit count of `uint` and `space_uint`, around each power of
    /// ten (where the count changes) and at random.
    #[test]
    fn uint_and_space_uint_digit_counts() {
        let mut s: u64 = 11;
        let vals = (0..20u32)
            .flat_map(|k| {
                let p = 10u64.pow(k);
                [
                    p - 1,
                    p,
                    p + 1,
                    p.saturating_mul(2) - 1,
                    p.saturating_mul(5),
                ]
            })
            .chain([0, u64::MAX, u64::MAX - 1, u64::from(u32::MAX)])
            .chain((0..200_000).map(|_| {
                s = s.wrapping_mul(6364136223846793005).wrapping_add(1);
                (s >> 33) >> (s & 31)
            }));
        let mut o = Out::new(Vec::new());
        for v in vals {
            o.buf.clear();
            o.buf.push(b'x');
            o.uint(v);
            o.space_uint(v);
            assert_eq!(o.buf, format!("x{v} {v}").as_bytes());
        }
    }

    /// Rows of values laid out four at a time: the bytes of one
    /// `space_uint` per value, for every digit count up to 10^7 and past
    /// it (one large value sends its four to `space_uint`), every row
    /// length (a remainder of one to three values), and offsets.
    #[test]
    fn space_uints_as_space_uint() {
        let mut s: u64 = 5;
        let mut pool: Vec<u32> = (0..8u32)
            .flat_map(|k| {
                let p = 10u32.pow(k);
                [p - 1, p, p + 1, 2 * p]
            })
            .chain([u32::MAX, u32::MAX - 1, 9_999_998, 10_000_001])
            .collect();
        pool.extend((0..4000).map(|_| {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1);
            ((s >> 33) >> (s & 31)) as u32
        }));
        for add in [0u64, 1, 3] {
            for len in 0..=9 {
                for row in pool.windows(len.max(1)).step_by(3).take(1500) {
                    let row = &row[..len];
                    let (mut a, mut b) = (Out::new(Vec::new()), Out::new(Vec::new()));
                    a.buf.push(b'x');
                    b.buf.push(b'x');
                    a.space_uints(row, add);
                    row.iter().for_each(|&v| b.space_uint(u64::from(v) + add));
                    assert_eq!(a.buf, b.buf, "{row:?} + {add}");
                }
            }
        }
    }

    /// Row numbers counted up across carries and digit counts, from any
    /// start, as `rows` lays them out.
    #[test]
    fn row_numbers_count_up() {
        for start in [
            0u64,
            1,
            8,
            9,
            98,
            99_990,
            9_999_999_990,
            10u64.pow(16) - 5,
            u64::MAX - 30,
        ] {
            let mut n = RowNumber::new(start);
            let mut buf = b"x".to_vec();
            let mut want = "x".to_string();
            for k in 0..30 {
                n.push_next(&mut buf);
                buf.push(b' ');
                want += &format!("{} ", start + k);
            }
            assert_eq!(String::from_utf8(buf).unwrap(), want);
        }
    }

    /// Rows written on one and several threads: numbered from `first`,
    /// the same bytes, across several blocks.
    #[test]
    fn rows_numbered_on_threads() {
        let n = 3 * BLOCK_ROWS + 17;
        let want: String = (0..n).map(|i| format!("{} {}\n", i + 7, i * 3)).collect();
        for threads in [1, 2, 3] {
            let mut out = Vec::new();
            let mut o = Out::new(&mut out);
            o.rows(n, 7, threads, |o, i| o.space_uint(i as u64 * 3))
                .unwrap();
            o.finish().unwrap();
            assert_eq!(String::from_utf8(out).unwrap(), want);
        }
    }

    /// Floats whose text has 1 to 24 bytes, through `push_bytes`.
    #[test]
    fn pushed_bytes_of_every_length() {
        let text: Vec<u8> = (0..30u8).map(|k| b'a' + k).collect();
        for n in 0..=30 {
            let mut buf = b"xy".to_vec();
            push_bytes(&mut buf, &text[..n]);
            assert_eq!(&buf[2..], &text[..n]);
            assert_eq!(&buf[..2], b"xy");
        }
    }
}
