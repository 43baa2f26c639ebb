//! Geometry helpers shared by the 2D and 3D kernels: insertion order
//! (BRIO + Hilbert curve), small vector utilities, bounding boxes, exact
//! two-term sums and products, union-find and the Lloyd iteration.

pub mod check;
pub(crate) mod ids;
pub mod scale;
pub mod sort;
pub(crate) mod vec3;

pub(crate) use scale::bbox;
pub use scale::{max_abs, pow2_scale, rescaled, scaled};
pub use sort::{brio_order, SplitMix64};

/// Lloyd's iteration in `D` dimensions: `iterations` times, `cells(points)`
/// gives the size (area, volume) and centroid of every point's clipped
/// Voronoi cell, and every point with a non-empty cell moves to its
/// centroid (the others stay). The loop of [`crate::tri::lloyd`],
/// [`crate::tri::lloyd_in_domain`] and [`crate::tet::lloyd`].
pub(crate) fn lloyd<const D: usize>(
    points: &[[f64; D]],
    iterations: usize,
    cells: impl Fn(&[[f64; D]]) -> Result<(Vec<f64>, Vec<[f64; D]>), crate::Error>,
) -> Result<Vec<[f64; D]>, crate::Error> {
    let mut pts = points.to_vec();
    for _ in 0..iterations {
        let (size, centroid) = cells(&pts)?;
        for (p, (&a, &g)) in pts.iter_mut().zip(size.iter().zip(&centroid)) {
            if a > 0.0 {
                *p = g;
            }
        }
    }
    Ok(pts)
}

/// A default Steiner budget of either dimension: `base` + 16 per input
/// vertex + 2 per element the size bounds ask for (`elements`; none when
/// not finite and positive), at most `max`.
pub(crate) fn steiner_budget(
    (base, max): (usize, usize),
    input_points: usize,
    elements: f64,
) -> usize {
    let asked = if elements.is_finite() && elements > 0.0 {
        (2.0 * elements).min(max as f64) as usize
    } else {
        0
    };
    base.saturating_add(input_points.saturating_mul(16))
        .saturating_add(asked)
        .min(max)
}

/// Hash/equality key of a point: the bits of its coordinates, with `-0.0`
/// folded onto `0.0` (so equal coordinates give equal keys).
pub(crate) fn key<const D: usize>(p: &[f64; D]) -> [u64; D] {
    p.map(|c| if c == 0.0 { 0 } else { c.to_bits() })
}

/// Compressed rows of `pairs` over rows `0..n`: the row offsets (`n + 1`)
/// and the second members, filed under their first by a counting sort
/// (row `r` is `values[offsets[r]..offsets[r + 1]]`, in the order of
/// `pairs`).
pub(crate) fn rows(n: usize, pairs: &[(u32, u32)]) -> (Vec<u32>, Vec<u32>) {
    let mut offsets = vec![0u32; n + 1];
    for &(r, _) in pairs {
        offsets[r as usize + 1] += 1;
    }
    for r in 0..n {
        offsets[r + 1] += offsets[r];
    }
    let mut fill = offsets.clone();
    let mut values = vec![0u32; pairs.len()];
    for &(r, x) in pairs {
        values[fill[r as usize] as usize] = x;
        fill[r as usize] += 1;
    }
    (offsets, values)
}

/// The root of `x` in the union-find forest `parent` (a root is its own
/// parent), halving the path on the way.
pub(crate) fn union_root(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        let up = parent[parent[x as usize] as usize];
        parent[x as usize] = up;
        x = up;
    }
    x
}

/// Joins the sets of `a` and `b` in the union-find forest `parent`: the
/// larger root goes under the smaller, so each root is its set's smallest
/// member.
pub(crate) fn union_join(parent: &mut [u32], a: u32, b: u32) {
    let (a, b) = (union_root(parent, a), union_root(parent, b));
    parent[a.max(b) as usize] = a.min(b);
}
