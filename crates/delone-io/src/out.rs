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

    /// Decimal digits, two at a time from a table (a division by 100 per
    /// pair instead of by 10 per digit). Always inlined: called from the
    /// row formatters of [`Out::rows`] it otherwise stays a call (+15%
    /// instructions writing an `.ele`).
    #[inline(always)]
    pub(crate) fn uint(&mut self, mut v: u64) {
        let mut tmp = [0u8; 20];
        let mut i = tmp.len();
        while v >= 100 {
            let r = (v % 100) as usize * 2;
            v /= 100;
            i -= 2;
            tmp[i..i + 2].copy_from_slice(&PAIRS[r..r + 2]);
        }
        if v >= 10 {
            let r = v as usize * 2;
            i -= 2;
            tmp[i..i + 2].copy_from_slice(&PAIRS[r..r + 2]);
        } else {
            i -= 1;
            tmp[i] = b'0' + v as u8;
        }
        self.buf.extend_from_slice(&tmp[i..]);
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
const BLOCK_ROWS: usize = 1 << 15;

impl<W: Write> Out<W> {
    /// Writes rows `0..n`, each formatted by `row` and ended by a newline,
    /// after what is buffered. Blocks of rows are formatted on up to
    /// `threads` threads, one round of consecutive blocks at a time, and
    /// written in order: the bytes do not depend on the thread count.
    pub(crate) fn rows(
        &mut self,
        n: usize,
        threads: usize,
        row: impl Fn(&mut Out<Vec<u8>>, usize) + Sync,
    ) -> std::io::Result<()> {
        let blocks = n.div_ceil(BLOCK_ROWS);
        let threads = threads.clamp(1, blocks.max(1));
        let fill = |b: &mut Out<Vec<u8>>, k: usize| {
            b.buf.clear();
            for i in k * BLOCK_ROWS..n.min((k + 1) * BLOCK_ROWS) {
                row(b, i);
                b.buf.push(b'\n');
            }
        };
        let mut bufs: Vec<Out<Vec<u8>>> = (0..threads).map(|_| Out::new(Vec::new())).collect();
        self.w.write_all(&self.buf)?;
        self.buf.clear();
        let mut k = 0;
        while k < blocks {
            let round = threads.min(blocks - k);
            let (mine, others) = bufs[..round].split_at_mut(1);
            // A thread that cannot start leaves its block to this one.
            let failed: Vec<usize> = std::thread::scope(|s| {
                let failed = others
                    .iter_mut()
                    .enumerate()
                    .filter_map(|(j, b)| {
                        let fill = &fill;
                        let job = move || fill(b, k + 1 + j);
                        std::thread::Builder::new()
                            .spawn_scoped(s, job)
                            .err()
                            .map(|_| j)
                    })
                    .collect();
                fill(&mut mine[0], k);
                failed
            });
            for j in failed {
                fill(&mut others[j], k + 1 + j);
            }
            for b in &bufs[..round] {
                self.w.write_all(&b.buf)?;
            }
            k += round;
        }
        Ok(())
    }
}

/// Appends the shortest text that parses back to exactly `x`.
pub(crate) fn push_float(buf: &mut Vec<u8>, x: f64) {
    let a = x.abs();
    // `write!` into a Vec<u8> cannot fail.
    if a == 0.0 || (1e-5..1e16).contains(&a) || !a.is_finite() {
        let _ = write!(buf, "{x}");
    } else {
        let _ = write!(buf, "{x:e}");
    }
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
}
