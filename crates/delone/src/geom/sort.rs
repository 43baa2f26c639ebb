//! Biased randomized insertion order (BRIO) with Hilbert-curve sorting inside
//! each round.
//!
//! Incremental Delaunay insertion is fast when consecutive points are close
//! (point location walks are short and the caches stay warm) yet random enough
//! at coarse scale that the expected work stays `O(n log n)`. BRIO (Amenta, Choi
//! & Rote 2003) gets both: points are shuffled, split into rounds whose sizes
//! grow geometrically (each round is 7/8 of what is left, the rest recursing in
//! front of it), and each round is sorted along a Hilbert curve.
//!
//! The shuffle uses a fixed-seed [`SplitMix64`], so the order — and therefore
//! the output of every mesher — is identical on every run.
//!
//! # References
//! N. Amenta, S. Choi, G. Rote, *Incremental constructions con BRIO*, SoCG 2003.
//! J. Skilling, *Programming the Hilbert curve*, AIP Conf. Proc. 707 (2004).

/// A tiny deterministic pseudo-random generator (SplitMix64).
///
/// ```
/// let mut r = delone::geom::SplitMix64::new(7);
/// let a = r.next_u64();
/// let mut r2 = delone::geom::SplitMix64::new(7);
/// assert_eq!(a, r2.next_u64());
/// ```
#[derive(Debug, Clone)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    /// A generator with the given seed.
    pub fn new(seed: u64) -> Self {
        SplitMix64(seed)
    }

    /// The next 64 random bits.
    #[inline]
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A uniform integer in `0..n` (`n > 0`), by multiply-shift.
    #[inline]
    pub fn below(&mut self, n: u32) -> u32 {
        (((self.next_u64() >> 32) * u64::from(n)) >> 32) as u32
    }
}

/// Number of BRIO rounds (the last holds ~7/8 of the points, each earlier one
/// ~1/8 of the next).
const BRIO_ROUNDS: u32 = 8;

/// Bits of the Hilbert key per axis: 3 + 2 * 15 or 3 + 3 * 10 bits of sort key.
const fn key_bits(d: usize) -> u32 {
    if d == 2 {
        15
    } else {
        10
    }
}

/// Hilbert index of a point whose coordinates were quantized to `bits` bits per
/// axis, for `D` = 2 or 3 axes: the quadrant-rotation recurrence in 2D (a
/// few operations per level), a state table in 3D (one lookup per level)
/// giving the keys of Skilling's transpose algorithm.
#[inline]
fn hilbert_key<const D: usize>(x: [u32; D], bits: u32) -> u64 {
    if D == 2 {
        hilbert_key_2d(x[0], x[1], bits)
    } else {
        hilbert_key_3d(x[0], x[1], x[2], bits)
    }
}

/// The 3D Hilbert curve of Skilling's transpose algorithm as a state
/// machine: entry `8 * state + octant` (octant `x << 2 | y << 1 | z` of the
/// current level's bits) holds the key digit in its low 3 bits and the
/// next state above them. A state is the orientation of the sub-cube being
/// refined (24 of them); the table was derived from the algorithm's keys
/// on a 2-level grid and is checked against it by the tests.
const HILBERT_3D: [u8; 192] = [
    8, 17, 27, 2, 39, 46, 52, 5, 56, 71, 73, 86, 91, 20, 10, 13, 48, 1, 103, 110, 115, 18, 12, 21,
    126, 129, 29, 26, 79, 80, 140, 3, 148, 43, 37, 34, 127, 128, 78, 81, 156, 45, 35, 42, 31, 6,
    160, 105, 72, 87, 139, 4, 57, 70, 50, 53, 0, 171, 111, 76, 49, 58, 102, 61, 180, 143, 83, 184,
    69, 54, 66, 97, 16, 123, 9, 74, 47, 60, 38, 77, 132, 95, 85, 14, 67, 144, 82, 33, 142, 55, 185,
    96, 93, 116, 90, 11, 188, 107, 175, 176, 101, 98, 62, 65, 164, 109, 119, 22, 99, 106, 152, 41,
    174, 177, 63, 64, 117, 114, 92, 19, 30, 125, 161, 122, 7, 172, 104, 75, 130, 25, 133, 166, 179,
    136, 84, 191, 94, 15, 141, 28, 145, 32, 138, 51, 146, 155, 149, 36, 137, 24, 190, 167, 154,
    157, 147, 44, 169, 182, 120, 135, 162, 165, 121, 134, 187, 108, 168, 183, 118, 173, 23, 124,
    153, 170, 40, 59, 178, 113, 131, 88, 181, 158, 68, 151, 186, 163, 89, 112, 189, 100, 150, 159,
];

/// 3D Hilbert index, one table lookup per level: the same keys as
/// Skilling's transpose algorithm, without its data-dependent branches
/// (about half of them mispredicted on random points).
#[inline]
fn hilbert_key_3d(x: u32, y: u32, z: u32, bits: u32) -> u64 {
    let mut state = 0usize;
    let mut key = 0u64;
    for b in (0..bits).rev() {
        let o = (((x >> b) & 1) << 2 | ((y >> b) & 1) << 1 | ((z >> b) & 1)) as usize;
        let e = HILBERT_3D[8 * state + o];
        key = (key << 3) | u64::from(e & 7);
        state = usize::from(e >> 3);
    }
    key
}

/// 2D Hilbert index: at each level from the top, the quadrant (rx, ry) of the
/// point in the current frame gives the digit `(3 rx) ^ ry`, and the frame is
/// reflected and swapped when `ry = 0` (the classic quadrant-rotation
/// recurrence). The frame is kept as two flags (complement, swap), so each
/// level is a handful of branch-free bit operations.
#[inline]
fn hilbert_key_2d(x: u32, y: u32, bits: u32) -> u64 {
    let (mut c, mut s) = (0u32, 0u32);
    let mut d = 0u64;
    for b in (0..bits).rev() {
        let ax = ((x >> b) & 1) ^ c;
        let ay = ((y >> b) & 1) ^ c;
        let t = s & (ax ^ ay);
        let (qx, qy) = (ax ^ t, ay ^ t);
        d = (d << 2) | u64::from((3 * qx) ^ qy);
        let flip = 1 ^ qy;
        c ^= qx & flip;
        s ^= flip;
    }
    d
}

/// The quadrant-rotation recurrence written out (reference for the tests).
#[cfg(test)]
fn hilbert_key_2d_reference(mut x: u32, mut y: u32, bits: u32) -> u64 {
    let n = 1u32 << bits;
    let mut d = 0u64;
    let mut s = n >> 1;
    while s > 0 {
        let rx = u32::from(x & s != 0);
        let ry = u32::from(y & s != 0);
        d += u64::from(s) * u64::from(s) * u64::from((3 * rx) ^ ry);
        if ry == 0 {
            if rx == 1 {
                x = n - 1 - x;
                y = n - 1 - y;
            }
            std::mem::swap(&mut x, &mut y);
        }
        s >>= 1;
    }
    d
}

/// Skilling's transpose algorithm (any dimension; the reference of the 3D
/// state table in the tests).
#[cfg(test)]
fn hilbert_key_skilling<const D: usize>(mut x: [u32; D], bits: u32) -> u64 {
    let m = 1u32 << (bits - 1);
    // Inverse undo excess work.
    let mut q = m;
    while q > 1 {
        let p = q - 1;
        for i in 0..D {
            if x[i] & q != 0 {
                x[0] ^= p;
            } else {
                let t = (x[0] ^ x[i]) & p;
                x[0] ^= t;
                x[i] ^= t;
            }
        }
        q >>= 1;
    }
    // Gray encode.
    for i in 1..D {
        x[i] ^= x[i - 1];
    }
    let mut t = 0;
    let mut q = m;
    while q > 1 {
        if x[D - 1] & q != 0 {
            t ^= q - 1;
        }
        q >>= 1;
    }
    for xi in x.iter_mut() {
        *xi ^= t;
    }
    // Interleave the transposed bits, most significant first.
    let mut key = 0u64;
    for b in (0..bits).rev() {
        for xi in x.iter() {
            key = (key << 1) | u64::from((xi >> b) & 1);
        }
    }
    key
}

/// Fewest words [`radix_sort_high32`] radix-sorts.
const RADIX_MIN: usize = 256;

/// LSD radix sort of `(key << 32) | payload` words by their high 32 bits
/// (stable). A short run (below [`RADIX_MIN`] words) is sorted whole
/// instead, which is the same order when the payloads ascend in `v` (the
/// point indices of [`brio_order_threads`]): the radix pass's fixed cost
/// (its bucket counts) dominates there, as for the many small 2D
/// triangulations of the coplanar facets.
fn radix_sort_high32(v: &mut Vec<u64>) {
    if v.len() < RADIX_MIN {
        debug_assert!(v.windows(2).all(|w| w[0] as u32 <= w[1] as u32));
        v.sort_unstable();
        return;
    }
    const BITS: u32 = 11;
    const BUCKETS: usize = 1 << BITS;
    let mut tmp = vec![0u64; v.len()];
    let mut shift = 32;
    while shift < 64 {
        let mut count = [0usize; BUCKETS];
        for &w in v.iter() {
            count[((w >> shift) as usize) & (BUCKETS - 1)] += 1;
        }
        let mut sum = 0;
        for c in count.iter_mut() {
            let k = *c;
            *c = sum;
            sum += k;
        }
        for &w in v.iter() {
            let b = ((w >> shift) as usize) & (BUCKETS - 1);
            tmp[count[b]] = w;
            count[b] += 1;
        }
        std::mem::swap(v, &mut tmp);
        shift += BITS;
    }
}

/// The BRIO + Hilbert insertion order of `points`: a permutation of
/// `0..points.len()` as `u32` ids. Deterministic for a given input.
///
/// Each point draws its round from a hash of its index (round `r` from the
/// end with probability 7/8 · 8^-r); the sort key is the round followed by the
/// Hilbert index of the point over the bounding box of all points, and one
/// radix sort orders everything. One sequential pass over the points, no
/// random access.
///
/// Works for `D` = 2 and `D` = 3. Coordinates must be finite.
///
/// ```
/// let pts: Vec<[f64; 2]> = (0..1000).map(|i| [(i % 37) as f64, (i / 37) as f64]).collect();
/// let order = delone::geom::brio_order(&pts);
/// let mut sorted = order.clone();
/// sorted.sort();
/// assert_eq!(sorted, (0..1000).collect::<Vec<u32>>());
/// assert_eq!(order, delone::geom::brio_order(&pts));
/// ```
pub fn brio_order<const D: usize>(points: &[[f64; D]]) -> Vec<u32> {
    brio_order_threads(points, 1)
}

/// [`brio_order`] with the sort keys computed and sorted on up to `threads`
/// threads (the same order for any thread count): each thread sorts the keys
/// of a run of consecutive points, the sorted runs are merged (every key
/// ends with its point's index, so keys are distinct and a merge of sorted
/// runs is the one sorted order).
pub(crate) fn brio_order_threads<const D: usize>(points: &[[f64; D]], threads: usize) -> Vec<u32> {
    let grid = HilbertGrid::new(points);
    let bits = key_bits(D);
    let chunk = points.len().div_ceil(threads.max(1)).max(1 << 16);
    let starts: Vec<usize> = (0..points.len()).step_by(chunk).collect();
    let mut runs: Vec<Vec<u64>> = crate::par::run_dynamic(threads, starts, |_, start| {
        let end = points.len().min(start + chunk);
        let mut keys: Vec<u64> = (start..end)
            .map(|i| {
                let round = u64::from(brio_round(i));
                let key = (round << (bits * D as u32)) | grid.key(&points[i]);
                (key << 32) | i as u64
            })
            .collect();
        radix_sort_high32(&mut keys);
        keys
    })
    .into_iter()
    .map(Option::unwrap_or_default)
    .collect();
    // Merged left to right, the last merge straight into the ids.
    while runs.len() > 2 {
        let b = runs.remove(1);
        let a = std::mem::take(&mut runs[0]);
        let mut out = vec![0u64; a.len() + b.len()];
        merge_sorted(&a, &b, &mut out, threads, |w| w);
        runs[0] = out;
    }
    let (a, b) = match runs.len() {
        0 => return Vec::new(),
        1 => (&runs[0][..], &[][..]),
        _ => (&runs[0][..], &runs[1][..]),
    };
    let mut order = vec![0u32; a.len() + b.len()];
    merge_sorted(a, b, &mut order, threads, |w| w as u32);
    order
}

/// Merges the ascending runs `a` and `b` of distinct words into `out`
/// (`f` of each word), in pieces of the output on up to `threads` threads.
fn merge_sorted<T: Send>(
    a: &[u64],
    b: &[u64],
    out: &mut [T],
    threads: usize,
    f: impl Fn(u64) -> T + Sync,
) {
    let n = out.len().min(a.len() + b.len());
    let pieces = threads.clamp(1, n.div_ceil(1 << 16).max(1));
    // `cut[k]`: the output position of piece k's start, and how many of its
    // words come before it from `a` (the rest from `b`).
    let cut: Vec<(usize, usize)> = (0..=pieces)
        .map(|k| {
            let r = n * k / pieces;
            // The number i of words from `a` among the first r: the largest
            // i with a[i - 1] < b[r - i].
            let (mut lo, mut hi) = (r.saturating_sub(b.len()), r.min(a.len()));
            while lo < hi {
                let i = (lo + hi).div_ceil(2);
                if a[i - 1] < b[r - i] {
                    lo = i;
                } else {
                    hi = i - 1;
                }
            }
            (r, lo)
        })
        .collect();
    let bounds: Vec<usize> = cut.iter().map(|c| c.0).collect();
    let items: Vec<(usize, &mut [T])> = crate::par::split_mut(&mut out[..n], &bounds)
        .into_iter()
        .enumerate()
        .collect();
    crate::par::run_dynamic(threads, items, |_, (k, o)| {
        let (r, mut i) = cut[k];
        let mut j = r - i;
        for x in o.iter_mut() {
            let w = if j >= b.len() || (i < a.len() && a[i] < b[j]) {
                i += 1;
                a[i - 1]
            } else {
                j += 1;
                b[j - 1]
            };
            *x = f(w);
        }
    });
}

/// The BRIO round of the point with index `i` (0 first, [`BRIO_LAST`]
/// last): the number of leading zero 3-bit groups of a hash of the index
/// counts rounds from the end.
#[inline]
pub(crate) fn brio_round(i: usize) -> u32 {
    let h = SplitMix64::new(i as u64 ^ 0x5eed_de10_0e00_0001).next_u64();
    let from_end = (h.leading_zeros() / 3).min(BRIO_ROUNDS - 1);
    BRIO_LAST - from_end
}

/// The last BRIO round (about 7/8 of the points).
const BRIO_LAST: u32 = BRIO_ROUNDS - 1;

/// Where the round of `order[end - 1]` begins in a [`brio_order`]: the
/// longest run of points before `end` (after the first `keep` entries) the
/// sort ranks with that round. The sort key keeps a round's two low bits
/// (rounds 3 and 7 share a rank, so do 2 and 6: a point of round 3, about
/// one in 4000, sorts inside the last round).
pub(crate) fn round_start(order: &[u32], end: usize, keep: usize) -> usize {
    let Some(&last) = order[..end].last() else {
        return end;
    };
    let rank = brio_round(last as usize) & 3;
    let mut l = end;
    while l > keep && brio_round(order[l - 1] as usize) & 3 == rank {
        l -= 1;
    }
    l
}

/// Moves `items[k]` to position `keys[k]` for every `k`, in place: `keys`
/// must be a permutation of `0..n` (it ends sorted). Undoes the gather
/// `items[k] = original[keys[k]]` without a second array.
///
/// Cycle-following alone would wait on a cache miss per item; instead each
/// level moves the items into at most 256 buckets of consecutive target
/// positions (in-place American flag sort: one swap puts one item into its
/// bucket, and the buckets' fill positions are 256 sequential streams),
/// until buckets of at most 4096 items are placed by following cycles
/// within the cache. About n·(levels + 1) swaps. The buckets of the first
/// level are finished on up to `threads` threads (the result is the same:
/// the items in key order).
pub(crate) fn scatter_in_place<T: Send>(items: &mut [T], keys: &mut [u32], threads: usize) {
    debug_assert_eq!(items.len(), keys.len());
    let n = items.len().min(keys.len());
    if threads <= 1 || n <= 1 << 16 {
        scatter_from(items, keys, 0);
        return;
    }
    let shift = distribute(items, keys, 0);
    let bounds: Vec<usize> = (0..n.div_ceil(1 << shift))
        .map(|b| b << shift)
        .chain([n])
        .collect();
    let items: Vec<_> = (crate::par::split_mut(items, &bounds))
        .into_iter()
        .zip(crate::par::split_mut(keys, &bounds))
        .enumerate()
        .collect();
    crate::par::run_dynamic(threads, items, |_, (b, (items, keys))| {
        scatter_from(items, keys, (b << shift) as u32);
    });
}

/// [`scatter_in_place`] of a bucket whose keys are `base..base + n`.
fn scatter_from<T>(items: &mut [T], keys: &mut [u32], base: u32) {
    let n = items.len().min(keys.len());
    let at = |keys: &[u32], i: usize| keys[i].wrapping_sub(base) as usize;
    if n <= 4096 {
        for i in 0..n {
            loop {
                let t = at(keys, i);
                // A key out of range would loop forever: leave it.
                if t == i || t >= n {
                    break;
                }
                items.swap(i, t);
                keys.swap(i, t);
            }
        }
        return;
    }
    let shift = distribute(items, keys, base);
    let buckets = ((n - 1) >> shift) + 1;
    for b in 0..buckets {
        let (lo, hi) = (b << shift, ((b + 1) << shift).min(n));
        scatter_from(&mut items[lo..hi], &mut keys[lo..hi], base + lo as u32);
    }
}

/// One level of [`scatter_in_place`] on a bucket of more than 4096 items
/// whose keys are `base..base + n`: moves the items into at most 256
/// buckets of `2^shift` consecutive target positions; returns `shift`.
fn distribute<T>(items: &mut [T], keys: &mut [u32], base: u32) -> u32 {
    let n = items.len().min(keys.len());
    let at = |keys: &[u32], i: usize| keys[i].wrapping_sub(base) as usize;
    let shift = (usize::BITS - (n - 1).leading_zeros()).saturating_sub(8);
    let buckets = ((n - 1) >> shift) + 1;
    let mut fill: Vec<usize> = (0..buckets).map(|b| b << shift).collect();
    for b in 0..buckets {
        let end = ((b + 1) << shift).min(n);
        while fill[b] < end {
            let i = fill[b];
            let t = (at(keys, i) >> shift).min(buckets - 1);
            if t == b {
                fill[b] += 1;
            } else {
                let j = fill[t];
                items.swap(i, j);
                keys.swap(i, j);
                fill[t] += 1;
            }
        }
    }
    shift
}

/// The Hilbert keys of [`brio_order`]: coordinates quantized on a grid of
/// `2^bits` cells per axis over the bounding box of a point set.
#[derive(Debug, Clone, Copy)]
pub(crate) struct HilbertGrid<const D: usize> {
    lo: [f64; D],
    scale: f64,
    cells: f64,
}

impl<const D: usize> HilbertGrid<D> {
    /// The grid over the bounding box of `points` (finite coordinates).
    pub(crate) fn new(points: &[[f64; D]]) -> Self {
        let [lo, hi] = super::scale::bbox(points);
        let cells = f64::from((1u32 << key_bits(D)) - 1);
        let mut extent = 0.0f64;
        for k in 0..D {
            extent = extent.max(hi[k] - lo[k]);
        }
        let scale = if extent > 0.0 && extent.is_finite() {
            cells / extent
        } else {
            0.0
        };
        HilbertGrid { lo, scale, cells }
    }

    /// The Hilbert key of `p` (clamped to the grid when outside the box).
    #[inline]
    pub(crate) fn key(&self, p: &[f64; D]) -> u64 {
        let mut q = [0u32; D];
        for k in 0..D {
            q[k] = ((p[k] - self.lo[k]) * self.scale).clamp(0.0, self.cells) as u32;
        }
        hilbert_key::<D>(q, key_bits(D))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Short runs (sorted whole) and long ones (radix-sorted) come out in
    /// the stable order by the high 32 bits, ties in payload order.
    #[test]
    fn radix_sort_orders_short_and_long_runs_alike() {
        let mut r = SplitMix64::new(7);
        for n in [0usize, 1, 2, 17, RADIX_MIN - 1, RADIX_MIN, 3000] {
            for wide in [false, true] {
                // Payloads ascending; few distinct keys (many ties) or
                // keys over all 32 bits.
                let mut v: Vec<u64> = (0..n as u64)
                    .map(|i| {
                        let k = r.next_u64();
                        let k = if wide { k & 0xFFFF_FFFF } else { k % 13 };
                        (k << 32) | i
                    })
                    .collect();
                let mut want = v.clone();
                want.sort_by_key(|w| w >> 32);
                radix_sort_high32(&mut v);
                assert_eq!(v, want, "{n} words");
            }
        }
    }

    #[test]
    fn scatter_in_place_undoes_a_gather() {
        for n in [0usize, 1, 2, 5, 4096, 4097, 70_000, 300_001] {
            let original: Vec<u64> = (0..n as u64).map(|i| i * 3 + 1).collect();
            let pts: Vec<[f64; 3]> = (0..n).map(|i| [i as f64, 0.5, -(i as f64)]).collect();
            let order = brio_order(&pts);
            for threads in [2, 3, 4, 7] {
                assert_eq!(order, brio_order_threads(&pts, threads));
            }
            for threads in [1, 2, 3] {
                let mut keys = order.clone();
                let mut items: Vec<u64> = keys.iter().map(|&i| original[i as usize]).collect();
                scatter_in_place(&mut items, &mut keys, threads);
                assert_eq!(items, original);
                assert!(keys.iter().enumerate().all(|(i, &k)| k as usize == i));
            }
        }
    }

    #[test]
    fn hilbert_2d_order_is_continuous() {
        // On a 2^k grid, consecutive Hilbert keys are grid neighbours.
        let bits = 3;
        let mut cells: Vec<(u64, [u32; 2])> = Vec::new();
        for x in 0..8u32 {
            for y in 0..8u32 {
                cells.push((hilbert_key::<2>([x, y], bits), [x, y]));
            }
        }
        cells.sort();
        for w in cells.windows(2) {
            assert_eq!(w[1].0, w[0].0 + 1);
            let d = w[0].1[0].abs_diff(w[1].1[0]) + w[0].1[1].abs_diff(w[1].1[1]);
            assert_eq!(d, 1);
        }
    }

    #[test]
    fn hilbert_2d_state_machine_matches_the_recurrence() {
        let mut r = SplitMix64::new(3);
        for bits in [1, 2, 5, 15, 16] {
            for _ in 0..2000 {
                let x = r.below(1 << bits);
                let y = r.below(1 << bits);
                assert_eq!(
                    hilbert_key_2d(x, y, bits),
                    hilbert_key_2d_reference(x, y, bits)
                );
            }
        }
    }

    #[test]
    fn hilbert_3d_state_table_matches_skilling() {
        // Every point of the grids of 1 to 5 levels, then random points of
        // 10-level grids (the sort's) and deeper ones.
        for bits in 1..=5u32 {
            let n = 1u32 << bits;
            for i in 0..n * n * n {
                let x = [i % n, i / n % n, i / n / n];
                assert_eq!(
                    hilbert_key_3d(x[0], x[1], x[2], bits),
                    hilbert_key_skilling(x, bits),
                    "{x:?} on {bits} levels"
                );
            }
        }
        let mut r = SplitMix64::new(5);
        for bits in [10, 16, 21] {
            for _ in 0..20000 {
                let x = [r.below(1 << bits), r.below(1 << bits), r.below(1 << bits)];
                assert_eq!(
                    hilbert_key_3d(x[0], x[1], x[2], bits),
                    hilbert_key_skilling(x, bits)
                );
            }
        }
    }

    #[test]
    fn hilbert_3d_order_is_continuous() {
        let bits = 2;
        let mut cells: Vec<(u64, [u32; 3])> = Vec::new();
        for x in 0..4u32 {
            for y in 0..4u32 {
                for z in 0..4u32 {
                    cells.push((hilbert_key::<3>([x, y, z], bits), [x, y, z]));
                }
            }
        }
        cells.sort();
        for w in cells.windows(2) {
            assert_eq!(w[1].0, w[0].0 + 1);
            let d: u32 = (0..3).map(|k| w[0].1[k].abs_diff(w[1].1[k])).sum();
            assert_eq!(d, 1);
        }
    }

    #[test]
    fn brio_is_a_permutation() {
        let mut r = SplitMix64::new(1);
        let pts: Vec<[f64; 3]> = (0..5000)
            .map(|_| [r.next_u64() as f64, r.next_u64() as f64, 0.5])
            .collect();
        let mut o = brio_order(&pts);
        o.sort();
        assert_eq!(o, (0..5000).collect::<Vec<u32>>());
        assert!(brio_order::<3>(&[]).is_empty());
    }
}
