//! Floating-point expansion arithmetic (Priest 1991, Shewchuk 1997) on fixed-size
//! stack arrays.
//!
//! An *expansion* is a sum of `f64` components, stored in increasing order of
//! magnitude, pairwise strongly nonoverlapping; its value is the exact
//! mathematical sum. The operations below are exact barring overflow and
//! underflow; zero components are eliminated so that the true length stays small
//! on typical inputs, while the capacity `N` (a const generic) is the worst case,
//! checked at compile time by `const` assertions. No operation allocates.

/// Splitter for Dekker/Veltkamp splitting: `2^27 + 1`.
#[cfg(not(target_feature = "fma"))]
const SPLITTER: f64 = 134_217_729.0;

/// `a + b = x + y` exactly, `x = fl(a + b)` (Knuth's branch-free two-sum).
///
/// ```
/// let (x, y) = delone_predicates::two_sum(1.0, 1e-20);
/// assert_eq!((x, y), (1.0, 1e-20));
/// ```
#[inline(always)]
pub fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let x = a + b;
    let bv = x - a;
    let av = x - bv;
    let br = b - bv;
    let ar = a - av;
    (x, ar + br)
}

/// `a - b = x + y` exactly, `x = fl(a - b)`.
#[inline(always)]
pub(crate) fn two_diff(a: f64, b: f64) -> (f64, f64) {
    let x = a - b;
    let bv = a - x;
    let av = x + bv;
    let br = bv - b;
    let ar = a - av;
    (x, ar + br)
}

/// Veltkamp split of `a` into two 26-bit halves.
#[cfg(not(target_feature = "fma"))]
#[inline(always)]
fn split(a: f64) -> (f64, f64) {
    let c = SPLITTER * a;
    let big = c - a;
    let hi = c - big;
    (hi, a - hi)
}

/// `a * b = x + y` exactly, `x = fl(a * b)`.
///
/// ```
/// let a = 1.0 + f64::EPSILON;
/// let (x, y) = delone_predicates::two_product(a, a);
/// assert_eq!((x, y), (1.0 + 2.0 * f64::EPSILON, f64::EPSILON * f64::EPSILON));
/// ```
#[cfg(target_feature = "fma")]
#[inline(always)]
pub fn two_product(a: f64, b: f64) -> (f64, f64) {
    let x = a * b;
    (x, a.mul_add(b, -x))
}

/// `a * b = x + y` exactly, `x = fl(a * b)` (Dekker's product).
///
/// ```
/// let a = 1.0 + f64::EPSILON;
/// let (x, y) = delone_predicates::two_product(a, a);
/// assert_eq!((x, y), (1.0 + 2.0 * f64::EPSILON, f64::EPSILON * f64::EPSILON));
/// ```
#[cfg(not(target_feature = "fma"))]
#[inline(always)]
pub fn two_product(a: f64, b: f64) -> (f64, f64) {
    let x = a * b;
    let (ah, al) = split(a);
    let (bh, bl) = split(b);
    let e1 = x - ah * bh;
    let e2 = e1 - al * bh;
    let e3 = e2 - ah * bl;
    (x, al * bl - e3)
}

/// `h = e + sf * f` with `sf = ±1`; returns the length of `h` (zero components
/// eliminated, at least 1). `h.len() >= e.len() + f.len()` is required
/// (guaranteed by the callers' checks).
#[inline]
fn sum_into(e: &[f64], f: &[f64], sf: f64, h: &mut [f64]) -> usize {
    // Short inputs (the common case on degenerate inputs) without the merge loop.
    if e.len() == 1 && f.len() == 1 {
        let (x, y) = two_sum(e[0], sf * f[0]);
        if y != 0.0 {
            h[0] = y;
            h[1] = x;
            return 2;
        }
        h[0] = x;
        return 1;
    }
    let (mut i, mut j, mut n) = (0usize, 0usize, 0usize);
    // Merge by increasing magnitude, folding into the running sum `q`.
    let mut q;
    if f[0].abs() > e[0].abs() {
        q = e[0];
        i = 1;
    } else {
        q = sf * f[0];
        j = 1;
    }
    while i < e.len() && j < f.len() {
        let g = if f[j].abs() > e[i].abs() {
            i += 1;
            e[i - 1]
        } else {
            j += 1;
            sf * f[j - 1]
        };
        let (s, t) = two_sum(q, g);
        q = s;
        if t != 0.0 {
            h[n] = t;
            n += 1;
        }
    }
    for &g in &e[i..] {
        let (s, t) = two_sum(q, g);
        q = s;
        if t != 0.0 {
            h[n] = t;
            n += 1;
        }
    }
    for &g in &f[j..] {
        let (s, t) = two_sum(q, sf * g);
        q = s;
        if t != 0.0 {
            h[n] = t;
            n += 1;
        }
    }
    if q != 0.0 || n == 0 {
        h[n] = q;
        n += 1;
    }
    n
}

/// `h = b * e`; returns the length of `h` (zero components eliminated, at least 1).
/// `h.len() >= 2 * e.len()` is required.
fn scale_into(e: &[f64], b: f64, h: &mut [f64]) -> usize {
    let mut n = 0usize;
    let (mut q, t) = two_product(e[0], b);
    if t != 0.0 {
        h[n] = t;
        n += 1;
    }
    for &c in &e[1..] {
        let (p1, p0) = two_product(c, b);
        let (s, t) = two_sum(q, p0);
        if t != 0.0 {
            h[n] = t;
            n += 1;
        }
        let (s2, t2) = two_sum(p1, s);
        q = s2;
        if t2 != 0.0 {
            h[n] = t2;
            n += 1;
        }
    }
    if q != 0.0 || n == 0 {
        h[n] = q;
        n += 1;
    }
    n
}

/// An expansion with capacity `N` on the stack.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Exp<const N: usize> {
    len: usize,
    c: [f64; N],
}

impl<const N: usize> Exp<N> {
    /// The components, smallest magnitude first.
    #[inline]
    pub(crate) fn comps(&self) -> &[f64] {
        &self.c[..self.len]
    }

    /// The expansion holding the single value `a`.
    #[inline]
    pub(crate) fn from_f64(a: f64) -> Self {
        const { assert!(N >= 1) };
        let mut c = [0.0; N];
        c[0] = a;
        Exp { len: 1, c }
    }

    /// The expansion `hi + lo` from an exact two-term result `(hi, lo)` with `lo`
    /// the roundoff of `hi` (so they do not overlap).
    #[inline]
    pub(crate) fn from_pair((hi, lo): (f64, f64)) -> Self {
        const { assert!(N >= 2) };
        let mut c = [0.0; N];
        if lo == 0.0 {
            c[0] = hi;
            Exp { len: 1, c }
        } else {
            c[0] = lo;
            c[1] = hi;
            Exp { len: 2, c }
        }
    }

    /// `a * b` exactly.
    #[inline]
    pub(crate) fn product(a: f64, b: f64) -> Self {
        Self::from_pair(two_product(a, b))
    }

    /// `a - b` exactly.
    #[inline]
    pub(crate) fn diff(a: f64, b: f64) -> Self {
        Self::from_pair(two_diff(a, b))
    }

    /// `self + o`.
    #[inline]
    pub(crate) fn add<const M: usize, const K: usize>(&self, o: &Exp<M>) -> Exp<K> {
        const { assert!(N + M <= K) };
        let mut c = [0.0; K];
        let len = sum_into(self.comps(), o.comps(), 1.0, &mut c);
        Exp { len, c }
    }

    /// `self - o`.
    #[inline]
    pub(crate) fn sub<const M: usize, const K: usize>(&self, o: &Exp<M>) -> Exp<K> {
        const { assert!(N + M <= K) };
        let mut c = [0.0; K];
        let len = sum_into(self.comps(), o.comps(), -1.0, &mut c);
        Exp { len, c }
    }

    /// `self * b`.
    #[inline]
    pub(crate) fn scale<const K: usize>(&self, b: f64) -> Exp<K> {
        const { assert!(2 * N <= K) };
        let mut c = [0.0; K];
        let len = scale_into(self.comps(), b, &mut c);
        Exp { len, c }
    }

    /// `self + o` if the result fits in `K` components (checked at run time).
    #[inline]
    pub(crate) fn try_add<const M: usize, const K: usize>(&self, o: &Exp<M>) -> Option<Exp<K>> {
        self.try_sum(o, 1.0)
    }

    /// `self - o` if the result fits in `K` components (checked at run time).
    #[inline]
    pub(crate) fn try_sub<const M: usize, const K: usize>(&self, o: &Exp<M>) -> Option<Exp<K>> {
        self.try_sum(o, -1.0)
    }

    #[inline]
    fn try_sum<const M: usize, const K: usize>(&self, o: &Exp<M>, sf: f64) -> Option<Exp<K>> {
        if self.len + o.len > K {
            return None;
        }
        let mut c = [0.0; K];
        let len = sum_into(self.comps(), o.comps(), sf, &mut c);
        Some(Exp { len, c })
    }

    /// `self * o` if the result fits in `K` components (checked at run time).
    pub(crate) fn try_mul<const M: usize, const K: usize>(&self, o: &Exp<M>) -> Option<Exp<K>> {
        if 2 * self.len * o.len > K {
            return None;
        }
        let oc = o.comps();
        let mut out = Exp {
            len: 0,
            c: [0.0; K],
        };
        if oc.len() == 1 {
            out.len = scale_into(self.comps(), oc[0], &mut out.c);
            return Some(out);
        }
        // Accumulate the partial products ping-ponging between two buffers (no
        // copies); `part` only needs the `2·len(self)` components of one partial.
        let mut other = [0.0; K];
        let mut part = [0.0; K];
        let mut len = scale_into(self.comps(), oc[0], &mut out.c);
        let (mut cur, mut nxt) = (&mut out.c, &mut other);
        for &b in &oc[1..] {
            let pl = scale_into(self.comps(), b, &mut part[..2 * self.len]);
            len = sum_into(&cur[..len], &part[..pl], 1.0, &mut nxt[..]);
            std::mem::swap(&mut cur, &mut nxt);
        }
        // `cur` holds the result; it is `out.c` after an even number of swaps.
        if oc.len().is_multiple_of(2) {
            out.c[..len].copy_from_slice(&other[..len]);
        }
        out.len = len;
        Some(out)
    }

    /// An approximation of the value with the exact sign: the largest component.
    #[inline]
    pub(crate) fn approx(&self) -> f64 {
        self.c[self.len - 1]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn products_and_sums_are_exact() {
        let a = 1.0 + f64::EPSILON;
        let p = Exp::<2>::product(a, a); // 1 + 2eps + eps^2
        assert_eq!(
            p.comps(),
            &[f64::EPSILON * f64::EPSILON, 1.0 + 2.0 * f64::EPSILON]
        );
        let one = Exp::<1>::from_f64(1.0);
        let d: Exp<3> = p.sub(&one);
        assert_eq!(
            d.comps(),
            &[f64::EPSILON * f64::EPSILON, 2.0 * f64::EPSILON]
        );
        let z: Exp<6> = d.sub(&d);
        assert_eq!(z.comps(), &[0.0]);
        let m: Exp<12> = d.try_mul(&p).unwrap();
        // (2e + e^2)(1 + 2e + e^2) = 2e + 5e^2 + 4e^3 + e^4, each term a double.
        let e = f64::EPSILON;
        let w1: Exp<2> =
            Exp::<1>::from_f64(e * e * e * e).add(&Exp::<1>::from_f64(4.0 * e * e * e));
        let w2: Exp<3> = w1.add(&Exp::<1>::from_f64(5.0 * e * e));
        let w3: Exp<4> = w2.add(&Exp::<1>::from_f64(2.0 * e));
        let zero: Exp<16> = m.sub(&w3);
        assert_eq!(zero.comps(), &[0.0]);
        let one_off: Exp<16> = m.sub(&w2);
        assert_eq!(one_off.comps(), &[2.0 * e]);
        assert!((m.approx() - 2.0 * e).abs() < 8.0 * e * e);
    }
}
