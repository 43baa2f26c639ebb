//! Edge lengths and element quality of a mesh in a metric.

use crate::metric::{edges, mean_ratio, Metric};

/// Upper bounds of the edge-length histogram's bins
/// ([`MetricStats::length_histogram`]); the last bin holds the rest.
pub const LENGTH_BINS: [f64; 8] = [
    0.3,
    0.6,
    std::f64::consts::FRAC_1_SQRT_2,
    0.9,
    1.3,
    std::f64::consts::SQRT_2,
    2.0,
    5.0,
];

/// Number of bins of the quality histogram, each `1 / QUALITY_BINS` wide.
pub const QUALITY_BINS: usize = 10;

/// A mesh measured in a metric: edge lengths (with the size varying
/// geometrically along each edge, [`Metric::edge_length`]) and element
/// mean ratio ([`mean_ratio`] in the log-Euclidean mean of the corner
/// metrics; 1 for the regular simplex of the metric).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MetricStats {
    /// Vertices (all points, used or not).
    pub vertices: usize,
    /// Elements.
    pub elements: usize,
    /// Edges.
    pub edges: usize,
    /// Shortest edge in the metric.
    pub length_min: f64,
    /// Longest edge in the metric.
    pub length_max: f64,
    /// Mean edge length in the metric.
    pub length_mean: f64,
    /// Edges with length in `[1/√2, √2]`.
    pub in_range: usize,
    /// Edges per length bin ([`LENGTH_BINS`], then the rest).
    pub length_histogram: [usize; 9],
    /// Worst element quality (negative for an inverted element).
    pub quality_min: f64,
    /// Mean element quality.
    pub quality_mean: f64,
    /// Elements per quality bin (`[0, 0.1)`, …, `[0.9, 1]`; inverted
    /// elements count in the first).
    pub quality_histogram: [usize; QUALITY_BINS],
}

impl MetricStats {
    /// The share of edges with length in `[1/√2, √2]` (0 without edges).
    pub fn in_range_share(&self) -> f64 {
        if self.edges == 0 {
            0.0
        } else {
            self.in_range as f64 / self.edges as f64
        }
    }
}

/// Measures a mesh (`K = D + 1` corners per element) in the metric given at
/// its vertices. Element ids and metric count must match the points (the
/// adaptation checks its inputs before measuring); out-of-range corners
/// are skipped.
///
/// ```
/// use delone::adapt::metric_stats;
/// use delone::metric::Metric;
/// // Two triangles of a unit square, measured with size 0.5: edges of length 2 and 2√2.
/// let p = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
/// let s = metric_stats(&p, &[[0, 1, 2], [0, 2, 3]], &[Metric::isotropic(0.5); 4]);
/// assert_eq!((s.edges, s.in_range), (5, 0));
/// assert!((s.length_max - 2.0 * 2f64.sqrt()).abs() < 1e-12);
/// ```
pub fn metric_stats<const D: usize, const K: usize>(
    points: &[[f64; D]],
    elements: &[[u32; K]],
    metric: &[Metric<D>],
) -> MetricStats {
    let n = points.len().min(metric.len());
    let ok = |v: u32| (v as usize) < n;
    let mut s = MetricStats {
        vertices: points.len(),
        elements: elements.len(),
        length_min: f64::INFINITY,
        length_max: 0.0,
        quality_min: f64::INFINITY,
        ..Default::default()
    };
    let (lo, hi) = (std::f64::consts::FRAC_1_SQRT_2, std::f64::consts::SQRT_2);
    let mut sum = 0.0;
    for [a, b] in edges(elements) {
        if !ok(a) || !ok(b) {
            continue;
        }
        let (pa, pb) = (points[a as usize], points[b as usize]);
        let e: [f64; D] = std::array::from_fn(|k| pb[k] - pa[k]);
        let l = metric[a as usize].edge_length(&metric[b as usize], e);
        s.edges += 1;
        sum += l;
        s.length_min = s.length_min.min(l);
        s.length_max = s.length_max.max(l);
        if (lo..=hi).contains(&l) {
            s.in_range += 1;
        }
        let bin = LENGTH_BINS
            .iter()
            .position(|&u| l < u)
            .unwrap_or(LENGTH_BINS.len());
        s.length_histogram[bin] += 1;
    }
    if s.edges > 0 {
        s.length_mean = sum / s.edges as f64;
    } else {
        s.length_min = 0.0;
    }
    let mut qsum = 0.0;
    let mut counted = 0usize;
    // [`Metric::interpolate`] of the corners, from each vertex's logarithm
    // computed once.
    let logs: Vec<_> = metric[..n].iter().map(Metric::log).collect();
    for t in elements {
        if !t.iter().all(|&v| ok(v)) {
            continue;
        }
        let corners = t.map(|v| points[v as usize]);
        let items = t.map(|v| (1.0, logs[v as usize]));
        let q = Metric::from_logs(&items).map_or(0.0, |m| mean_ratio(&corners, &m));
        counted += 1;
        qsum += q;
        s.quality_min = s.quality_min.min(q);
        let bin = ((q.max(0.0) * QUALITY_BINS as f64) as usize).min(QUALITY_BINS - 1);
        s.quality_histogram[bin] += 1;
    }
    if counted > 0 {
        s.quality_mean = qsum / counted as f64;
    } else {
        s.quality_min = 0.0;
    }
    s
}
