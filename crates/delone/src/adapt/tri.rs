//! 2D adaptation on the constrained triangle mesh ([`CMesh`]): passes of
//! edge splits (longest first), edge collapses (shortest first), edge swaps
//! and vertex smoothing, each a local operation of `tri::adapt_ops` checked
//! by exact orientation before it is committed, until a pass changes
//! nothing or [`AdaptOptions::max_passes`] is reached.
//!
//! Qualities are [`mean_ratio`] in the log-Euclidean mean of the corner
//! metrics, as [`metric_stats`] measures them. Lengths are
//! [`Metric::edge_length_turning`]: [`Metric::edge_length`], which
//! [`metric_stats`] reports, where the ends' metrics share their
//! eigenvectors, and through the interpolated metric at the edge's midpoint
//! where the metric turns along the edge (the chords of a curved
//! anisotropic layer, which the ends' metrics alone measure up to about
//! twice too long and would split into more elements than a unit mesh has).
//! Every constrained edge (input faces, the hull, edges between
//! regions) keeps its straight input edge: its new points are computed
//! from that edge's ends and their parameter along it, and its vertices
//! slide only along it. Everything is sequential and in index order:
//! the output depends only on the input.

use std::f64::consts::{FRAC_1_SQRT_2, SQRT_2};
use std::time::Instant;

use super::{metric_stats, AdaptOptions, AdaptReport, Adapted, MetricField, TriMesh};
use crate::metric::{edges, gradate, mean_ratio, Metric};
use crate::tri::cmesh::CMesh;
use crate::tri::topo::{edge, unpack, DEAD, NEXT, PREV};
use crate::{Error, NONE};

/// Edges longer than this are split and edges shorter than that collapsed
/// while the mesh grows: splitting only clearly long edges keeps the mesh
/// from filling with short ones (mean metric length near 1, MMG's element
/// count). Once that settles, the passes go on with the bounds of the range,
/// [`FINAL`], so that no edge stays above √2 (the diagonals of a uniform
/// isotropic grid, about 1.47, for instance).
const GROW: (f64, f64) = (1.6, 0.8);
/// The split and collapse bounds once the mesh has settled: the range
/// `[1/√2, √2]` itself.
const FINAL: (f64, f64) = (SQRT_2, FRAC_1_SQRT_2);
/// Worst quality a collapse may leave when the star was better than it.
const COLLAPSE_FLOOR: f64 = 0.3;
/// Least gain in worst quality for a swap or a move to count.
const GAIN: f64 = 1e-3;

/// Adapts a triangle mesh to a metric field: the output has edges of
/// length about 1 (most in `[1/√2, √2]`) and triangles close to regular in
/// the metric, the same boundary edges (split, never moved off their
/// line), corners, required vertices and element references.
///
/// A metric at the vertices is bounded by `hmin`/`hmax` and graded by
/// `hgrad` first, and interpolated (log-Euclidean) at new vertices; a
/// function metric is evaluated (and bounded) at every new or moved vertex.
///
/// # Errors
/// [`Error::InvalidCoordinate`] for a point that is not finite;
/// [`Error::MetricCount`] for a metric field of another length than the
/// points; [`Error::InvalidBound`] for `-hmin`, `-hmax` or `-hgrad` out of
/// range; [`Error::InconsistentMesh`] naming the triangle, face or array
/// that does not fit (a clockwise or flat triangle, a non-manifold edge, a
/// face that is not an edge, a reference array of another length).
///
/// ```
/// use delone::adapt::{adapt_tri, AdaptOptions, MetricField, TriMesh};
/// use delone::metric::Metric;
/// let square = TriMesh {
///     points: vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
///     elements: vec![[0, 1, 2], [0, 2, 3]],
///     ..Default::default()
/// };
/// // Sizes 0.1 along x and 0.3 along y.
/// let m = Metric::<2>::from_medit(&[100.0, 0.0, 1.0 / 0.09]).unwrap();
/// let out = adapt_tri(&square, MetricField::AtVertices(vec![m; 4]), &AdaptOptions::default()).unwrap();
/// assert!(out.report.after.in_range_share() > 0.8);
/// assert!(out.report.after.quality_min > 0.3);
/// ```
pub fn adapt_tri(
    mesh: &TriMesh,
    metric: MetricField<'_, 2>,
    options: &AdaptOptions,
) -> Result<Adapted<2, 3>, Error> {
    let clock = Instant::now();
    check_input(mesh, options)?;
    let (hmin, hmax) = (
        options.hmin.unwrap_or(0.0),
        options.hmax.unwrap_or(f64::INFINITY),
    );
    let bound = |m: Metric<2>| {
        if options.hmin.is_some() || options.hmax.is_some() {
            m.bounded(hmin, hmax)
        } else {
            m
        }
    };
    let (met, field) = match metric {
        MetricField::AtVertices(v) => {
            if v.len() != mesh.points.len() {
                return Err(Error::MetricCount {
                    vertices: mesh.points.len(),
                    metrics: v.len(),
                });
            }
            let mut met: Vec<Metric<2>> = v.into_iter().map(bound).collect();
            if let Some(g) = options.hgrad {
                gradate(&mesh.points, &edges(&mesh.elements), &mut met, g);
            }
            (met, None)
        }
        MetricField::Function(f) => (mesh.points.iter().map(|p| bound(f(p))).collect(), Some(f)),
    };
    let (m, vt, added) = CMesh::for_adaptation(
        mesh.points.clone(),
        &mesh.elements,
        &mesh.element_refs,
        &mesh.faces,
    )?;
    let before = metric_stats(&mesh.points, &mesh.elements, &met);
    let mut fixed = vec![false; mesh.points.len()];
    for &v in mesh.corners.iter().chain(&mesh.required) {
        if let Some(f) = fixed.get_mut(v as usize) {
            *f = true;
        }
    }
    let refs: Vec<i32> = (0..mesh.faces.len() + added.len())
        .map(|k| mesh.face_refs.get(k).copied().unwrap_or(0))
        .collect();
    let mut m = m;
    let parents = straight_chains(&mut m, &fixed, &refs);
    let mut run = Run {
        m,
        vt,
        logs: met.iter().map(Metric::log).collect(),
        met,
        field,
        bound: &bound,
        fixed,
        parents,
        point_refs: mesh.point_refs.clone(),
        report: AdaptReport::default(),
        bounds: GROW,
        settled: vec![false; mesh.points.len()],
        #[cfg(test)]
        areas: Vec::new(),
        #[cfg(test)]
        regions: mesh.element_refs.clone(),
    };
    #[cfg(test)]
    {
        run.areas = run.region_areas();
        run.verify("start");
    }
    let mut phases = [0.0; 5];
    phases[0] = clock.elapsed().as_secs_f64();
    let (mut best, mut stall, mut splits) = (usize::MAX, 0, 0);
    for pass in 0..options.max_passes {
        crate::progress::report(
            "adapting",
            pass as u64,
            Some(options.max_passes as u64),
            "passes",
        );
        if crate::progress::stop_requested() {
            return Err(Error::Interrupted);
        }
        // Topological changes (splits, collapses, swaps) of this pass.
        let mut changed = 0;
        let t = Instant::now();
        if options.insert {
            changed += run.split_pass(options.max_vertices);
        }
        phases[1] += t.elapsed().as_secs_f64();
        let t = Instant::now();
        if options.insert {
            changed += run.collapse_pass();
        }
        phases[2] += t.elapsed().as_secs_f64();
        let t = Instant::now();
        if options.swap {
            changed += run.swap_pass();
        }
        phases[3] += t.elapsed().as_secs_f64();
        let t = Instant::now();
        let moves = if options.smooth { run.smooth_pass() } else { 0 };
        phases[4] += t.elapsed().as_secs_f64();
        run.report.passes += 1;
        // Done when nothing changes, or when the mesh has stopped growing
        // (splits under 5% of the vertices) and its edges out of range have
        // not become fewer for three passes (edges that no operation brings
        // into range, split and collapsed again).
        let bad = run
            .edges_where(|l| !(FRAC_1_SQRT_2..=SQRT_2).contains(&l))
            .len();
        let grew = (run.report.splits - splits) * 20 > run.live_vertices();
        splits = run.report.splits;
        if bad < best || grew {
            (best, stall) = (bad, 0);
        } else {
            stall += 1;
        }
        let settled = changed == 0 && moves == 0 || stall >= 3;
        if settled && run.bounds != FINAL && !run.report.budget_reached {
            (run.bounds, best, stall) = (FINAL, usize::MAX, 0);
        } else if settled || run.report.budget_reached {
            break;
        }
    }
    let t = Instant::now();
    let mut out = run.output(mesh);
    out.report.before = before;
    out.report.after = metric_stats(&out.mesh.points, &out.mesh.elements, &out.metric);
    let names = ["prepare", "split", "collapse", "swap", "smooth"];
    out.report.phases = names.iter().copied().zip(phases).collect();
    out.report
        .phases
        .push(("output", t.elapsed().as_secs_f64()));
    Ok(out)
}

/// Joins the constrained edges into maximal straight chains of one
/// reference (through vertices of exactly two such edges, neither fixed,
/// collinear up to rounding and pointing apart): each chain becomes the
/// parent of its subsegments, with the parameters of their ends along it.
/// Returns each chain's ends and reference. A subsegment's `parent` is its
/// face index (into `refs`) on entry.
fn straight_chains(m: &mut CMesh, fixed: &[bool], refs: &[i32]) -> Vec<([f64; 2], [f64; 2], i32)> {
    let nv = m.xy.len();
    // The constrained edges at each vertex (at most 2 kept; 3 = more).
    let mut at: Vec<Vec<u32>> = vec![Vec::new(); nv];
    for (s, sub) in m.subs.iter().enumerate() {
        for &v in &sub.v {
            at[v as usize].push(s as u32);
        }
    }
    let joint = |v: u32, m: &CMesh| {
        let e = &at[v as usize];
        if e.len() != 2 || fixed.get(v as usize).copied().unwrap_or(false) {
            return false;
        }
        let (s, r) = (&m.subs[e[0] as usize], &m.subs[e[1] as usize]);
        if refs[s.parent as usize] != refs[r.parent as usize] {
            return false;
        }
        let other = |x: &crate::tri::cmesh::Sub| if x.v[0] == v { x.v[1] } else { x.v[0] };
        let (p, a, b) = (*m.p(v), *m.p(other(s)), *m.p(other(r)));
        let (d1, d2) = ([a[0] - p[0], a[1] - p[1]], [b[0] - p[0], b[1] - p[1]]);
        let cross = d1[0] * d2[1] - d1[1] * d2[0];
        let dot = d1[0] * d2[0] + d1[1] * d2[1];
        dot < 0.0 && cross.abs() <= 1e-12 * d1[0].hypot(d1[1]) * d2[0].hypot(d2[1])
    };
    let n = m.subs.len();
    let mut chain = vec![NONE; n];
    let mut out = Vec::new();
    for s0 in 0..n {
        if chain[s0] != NONE {
            continue;
        }
        let id = out.len() as u32;
        let r = refs[m.subs[s0].parent as usize];
        chain[s0] = id;
        // Walk from each end of `s0` through joints; the far ends are the
        // chain's ends.
        let mut ends = m.subs[s0].v;
        for end in &mut ends {
            let (mut s, mut v) = (s0, *end);
            while joint(v, m) {
                let e = &at[v as usize];
                let next = if e[0] as usize == s { e[1] } else { e[0] } as usize;
                if chain[next] != NONE {
                    break;
                }
                chain[next] = id;
                let sub = &m.subs[next];
                v = if sub.v[0] == v { sub.v[1] } else { sub.v[0] };
                s = next;
            }
            *end = v;
        }
        out.push((*m.p(ends[0]), *m.p(ends[1]), r));
    }
    for (s, &c) in chain.iter().enumerate() {
        let (p0, p1, _) = out[c as usize];
        let d = [p1[0] - p0[0], p1[1] - p0[1]];
        let sub = &mut m.subs[s];
        sub.parent = c;
        for k in 0..2 {
            let p = m.xy[sub.v[k] as usize];
            sub.t[k] =
                ((p[0] - p0[0]) * d[0] + (p[1] - p0[1]) * d[1]) / (d[0] * d[0] + d[1] * d[1]);
        }
    }
    out
}

/// The input checks: finite points, references as long as their items,
/// corners and required vertices in range, option bounds.
fn check_input(mesh: &TriMesh, o: &AdaptOptions) -> Result<(), Error> {
    if let Some(index) = mesh
        .points
        .iter()
        .position(|p| p.iter().any(|x| !x.is_finite()))
    {
        return Err(Error::InvalidCoordinate { index });
    }
    let nv = mesh.points.len();
    for (name, got, want) in [
        ("point_refs", mesh.point_refs.len(), nv),
        ("element_refs", mesh.element_refs.len(), mesh.elements.len()),
        ("face_refs", mesh.face_refs.len(), mesh.faces.len()),
    ] {
        if got != 0 && got != want {
            return Err(Error::InconsistentMesh {
                reason: format!("{name} has {got} entries for {want} items"),
            });
        }
    }
    let out_of_range = mesh
        .faces
        .iter()
        .flatten()
        .chain(&mesh.corners)
        .chain(&mesh.required)
        .find(|&&v| v as usize >= nv);
    if let Some(v) = out_of_range {
        return Err(Error::InconsistentMesh {
            reason: format!("vertex {v} of a face, corner or required list is out of range"),
        });
    }
    let bad = |option: &'static str, value: f64, reason: &'static str| {
        Err(Error::InvalidBound {
            option,
            value,
            reason,
        })
    };
    if let Some(h) = o.hmin.filter(|h| !(*h > 0.0 && h.is_finite())) {
        return bad("-hmin", h, "the smallest size must be positive and finite");
    }
    if let Some(h) = o
        .hmax
        .filter(|h| h.is_nan() || *h <= 0.0 || o.hmin.is_some_and(|l| *h < l))
    {
        return bad(
            "-hmax",
            h,
            "the largest size must be positive and at least -hmin",
        );
    }
    if let Some(g) = o.hgrad.filter(|g| !(*g > 1.0 && g.is_finite())) {
        return bad("-hgrad", g, "the gradation must be finite and above 1");
    }
    Ok(())
}

/// A metric given as a function of the point.
type MetricFn<'a> = dyn Fn(&[f64; 2]) -> Metric<2> + Sync + 'a;

/// The working state of one adaptation.
struct Run<'a> {
    m: CMesh,
    /// A triangle of each vertex (`NONE`: removed or unused).
    vt: Vec<u32>,
    met: Vec<Metric<2>>,
    /// The logarithm of each vertex's metric ([`Metric::log`]), for the
    /// qualities' interpolation.
    logs: Vec<[[f64; 2]; 2]>,
    field: Option<&'a MetricFn<'a>>,
    bound: &'a dyn Fn(Metric<2>) -> Metric<2>,
    /// Corners and required vertices (input numbering; new vertices are
    /// never fixed).
    fixed: Vec<bool>,
    /// Each constrained edge's straight input edge: ends and reference.
    parents: Vec<([f64; 2], [f64; 2], i32)>,
    point_refs: Vec<i32>,
    report: AdaptReport,
    /// Edges longer than `bounds.0` are split, shorter than `bounds.1`
    /// collapsed ([`GROW`], then [`FINAL`]).
    bounds: (f64, f64),
    /// Vertices whose last smoothing moved nothing and around which nothing
    /// has changed since (no move, split, collapse or swap in their star):
    /// smoothing them again would move nothing either.
    settled: Vec<bool>,
    /// Area of each region at the start (the tests' checker compares).
    #[cfg(test)]
    areas: Vec<(i32, f64)>,
    /// The input's element references.
    #[cfg(test)]
    regions: Vec<i32>,
}

/// How a vertex may move: freely, along the input edge of its two
/// subsegments (same parent), or not at all.
enum Freedom {
    Free,
    Slide(u32, [u32; 2]),
    Fixed,
}

impl Run<'_> {
    /// The metric length of edge `ab`, with the metric turning along it
    /// ([`Metric::edge_length_turning`]).
    fn len(&self, a: u32, b: u32) -> f64 {
        let (pa, pb) = (self.m.p(a), self.m.p(b));
        let (a, b) = (a as usize, b as usize);
        self.met[a].edge_length_turning(
            &self.met[b],
            &self.logs[a],
            &self.logs[b],
            [pb[0] - pa[0], pb[1] - pa[1]],
        )
    }

    fn quality(&self, t: [u32; 3]) -> f64 {
        let c = t.map(|v| *self.m.p(v));
        let items = t.map(|v| (1.0, self.logs[v as usize]));
        Metric::from_logs(&items).map_or(0.0, |m| mean_ratio(&c, &m))
    }

    fn metric_at(&self, c: &[f64; 2], items: &[(f64, Metric<2>)]) -> Metric<2> {
        match self.field {
            Some(f) => (self.bound)(f(c)),
            None => Metric::interpolate(items).unwrap_or(items[0].1),
        }
    }

    /// Marks `v` and its neighbours as not settled: their stars changed.
    fn stir(&mut self, v: u32) {
        for (t, _) in self.m.star(&self.vt, v) {
            for x in self.m.tr[t].v {
                self.settled[x as usize] = false;
            }
        }
    }

    fn live_vertices(&self) -> usize {
        self.vt.iter().filter(|&&t| t != NONE).count()
    }

    /// Every edge once, `(length, a, b)`, for which `keep` holds.
    fn edges_where(&self, keep: impl Fn(f64) -> bool) -> Vec<(f64, u32, u32)> {
        let mut out = Vec::new();
        for (t, tri) in self.m.tr.iter().enumerate() {
            if tri.v[0] == DEAD {
                continue;
            }
            for e in 0..3 {
                let (a, b) = edge(&tri.v, e);
                if a < b || tri.a[e] == NONE {
                    let l = self.len(a, b);
                    if keep(l) {
                        out.push((l, a, b));
                    }
                }
                let _ = t;
            }
        }
        out
    }

    fn freedom(&self, v: u32, star: &[(usize, usize)]) -> Freedom {
        if self.fixed.get(v as usize).copied().unwrap_or(false) || star.is_empty() {
            return Freedom::Fixed;
        }
        let subs = self.m.subs_at(star);
        match subs[..] {
            [] => Freedom::Free,
            [s, r] if self.m.subs[s as usize].parent == self.m.subs[r as usize].parent => {
                Freedom::Slide(self.m.subs[s as usize].parent, [s, r])
            }
            _ => Freedom::Fixed,
        }
    }

    /// Splits every edge longer than `bounds.0`, longest first, at its metric
    /// midpoint.
    fn split_pass(&mut self, budget: Option<usize>) -> usize {
        let long = self.bounds.0;
        let mut cand = self.edges_where(|l| l > long);
        cand.sort_by(|x, y| y.0.total_cmp(&x.0).then((x.1, x.2).cmp(&(y.1, y.2))));
        let mut live = self.live_vertices();
        let mut done = 0;
        for (l, a, b) in cand {
            if budget.is_some_and(|n| live >= n) {
                self.report.budget_reached = true;
                break;
            }
            let Some((t, e)) = self.m.find_edge(&self.vt, a, b) else {
                continue;
            };
            let (a, b) = edge(&self.m.tr[t].v, e);
            // Where half the metric length is reached, the size varying
            // geometrically from a to b.
            let (pa, pb) = (*self.m.p(a), *self.m.p(b));
            let d = [pb[0] - pa[0], pb[1] - pa[1]];
            let r = self.met[b as usize].length(d) / self.met[a as usize].length(d);
            let s = if (r - 1.0).abs() < 1e-6 {
                0.5
            } else {
                ((1.0 + r) / 2.0).ln() / r.ln()
            }
            .clamp(0.25, 0.75);
            let _ = l;
            let sub = self.m.sub_at(t, e);
            let (c, tc, pref) = if sub == NONE {
                ([pa[0] + s * d[0], pa[1] + s * d[1]], 0.0, 0)
            } else {
                let rec = &self.m.subs[sub as usize];
                let (ta, tb) = if rec.v[0] == a {
                    (rec.t[0], rec.t[1])
                } else {
                    (rec.t[1], rec.t[0])
                };
                let tc = ta + s * (tb - ta);
                let (p0, p1, r) = self.parents[rec.parent as usize];
                (
                    [p0[0] + tc * (p1[0] - p0[0]), p0[1] + tc * (p1[1] - p0[1])],
                    tc,
                    r,
                )
            };
            let mc = self.metric_at(
                &c,
                &[(1.0 - s, self.met[a as usize]), (s, self.met[b as usize])],
            );
            if let Some(p) = self.m.split_edge(&mut self.vt, t, e, c, tc) {
                self.met.push(mc);
                self.logs.push(mc.log());
                self.settled.push(false);
                self.stir(p);
                if !self.point_refs.is_empty() {
                    self.point_refs.push(pref);
                }
                live += 1;
                done += 1;
                #[cfg(test)]
                self.verify("split");
            }
        }
        self.report.splits += done;
        done
    }

    /// Collapses every edge shorter than `bounds.1`, shortest first, removing
    /// an end that may go (not fixed; on a constrained edge only along it)
    /// when no new edge is longer than `bounds.0` and the worst quality of the
    /// star stays above `min(COLLAPSE_FLOOR, its worst before)`.
    fn collapse_pass(&mut self) -> usize {
        let short = self.bounds.1;
        let mut cand = self.edges_where(|l| l < short);
        cand.sort_by(|x, y| x.0.total_cmp(&y.0).then((x.1, x.2).cmp(&(y.1, y.2))));
        let mut done = 0;
        for (_, a, b) in cand {
            for (v, w) in [(a, b), (b, a)] {
                if self.vt[v as usize] == NONE || self.vt[w as usize] == NONE {
                    break;
                }
                let star = self.m.star(&self.vt, v);
                match self.freedom(v, &star) {
                    Freedom::Fixed => continue,
                    Freedom::Slide(_, [s, r]) => {
                        let along = |s: u32| self.m.subs[s as usize].v.contains(&w);
                        if !along(s) && !along(r) {
                            continue;
                        }
                    }
                    Freedom::Free => {}
                }
                let Some(plan) = self.m.collapse_plan(&self.vt, v, w) else {
                    continue;
                };
                let long = plan.kept.iter().any(|t| {
                    let i = t.iter().position(|&x| x == w).unwrap_or(0);
                    self.len(w, t[NEXT[i]]) > self.bounds.0
                        || self.len(w, t[PREV[i]]) > self.bounds.0
                });
                if long {
                    continue;
                }
                let old = star
                    .iter()
                    .map(|&(t, _)| self.quality(self.m.tr[t].v))
                    .fold(f64::INFINITY, f64::min);
                let new = plan
                    .kept
                    .iter()
                    .map(|&t| self.quality(t))
                    .fold(f64::INFINITY, f64::min);
                if new < old.min(COLLAPSE_FLOOR) {
                    continue;
                }
                self.m.collapse(&mut self.vt, &plan);
                self.stir(w);
                done += 1;
                #[cfg(test)]
                self.verify("collapse");
                break;
            }
        }
        self.report.collapses += done;
        done
    }

    /// Flips every unconstrained edge whose flip raises the worse quality
    /// of its two triangles (convex quadrilaterals only); a few sweeps.
    fn swap_pass(&mut self) -> usize {
        let mut done = 0;
        // Triangles flipped in the last sweep and in this one: an edge
        // between two triangles flipped in neither was refused last time
        // and would be again (nothing moves in this pass).
        let mut last = vec![true; self.m.tr.len()];
        for _ in 0..4 {
            let mut flips = 0;
            let mut now = vec![false; self.m.tr.len()];
            for t in 0..self.m.tr.len() {
                for e in 0..3 {
                    let tri = self.m.tr[t];
                    if tri.v[0] == DEAD || tri.a[e] == NONE || self.m.sub_at(t, e) != NONE {
                        continue;
                    }
                    let (n, j) = unpack(tri.a[e]);
                    if n < t || !(last[t] || last[n] || now[t] || now[n]) {
                        continue;
                    }
                    let (x, a, b) = (tri.v[e], tri.v[NEXT[e]], tri.v[PREV[e]]);
                    let y = self.m.tr[n].v[j];
                    let o = |p: u32, q: u32, r: u32| {
                        delone_predicates::orient2d(self.m.p(p), self.m.p(q), self.m.p(r))
                    };
                    if o(x, a, y) <= 0.0 || o(y, b, x) <= 0.0 {
                        continue;
                    }
                    let old = self.quality(tri.v).min(self.quality(self.m.tr[n].v));
                    let new = self.quality([x, a, y]).min(self.quality([y, b, x]));
                    if new > old + GAIN {
                        self.m.flip(t, e);
                        (now[t], now[n]) = (true, true);
                        for (k, s) in [(x, t), (a, t), (y, t), (b, n)] {
                            self.vt[k as usize] = s as u32;
                            self.settled[k as usize] = false;
                        }
                        flips += 1;
                        #[cfg(test)]
                        self.verify("swap");
                    }
                }
            }
            done += flips;
            if flips == 0 {
                break;
            }
            last = now;
        }
        self.report.swaps += done;
        done
    }

    /// Moves each vertex that may move toward the mean of the points at
    /// unit metric length from its neighbours (a vertex on a constrained
    /// edge along its input edge, between its two neighbours there), when
    /// its star stays counterclockwise (exact) and its worst quality rises.
    fn smooth_pass(&mut self) -> usize {
        let mut done = 0;
        for v in 0..self.vt.len() as u32 {
            if self.vt[v as usize] == NONE || self.settled[v as usize] {
                continue;
            }
            let star = self.m.star(&self.vt, v);
            let freedom = self.freedom(v, &star);
            if matches!(freedom, Freedom::Fixed) {
                continue;
            }
            let pv = *self.m.p(v);
            let mut ideal = [0.0; 2];
            let mut count = 0.0;
            for &(t, i) in &star {
                for u in [self.m.tr[t].v[NEXT[i]], self.m.tr[t].v[PREV[i]]] {
                    let pu = *self.m.p(u);
                    let l = self.len(u, v).max(1e-300);
                    ideal[0] += pu[0] + (pv[0] - pu[0]) / l;
                    ideal[1] += pu[1] + (pv[1] - pu[1]) / l;
                    count += 1.0;
                }
            }
            ideal = ideal.map(|x| x / count);
            // On a constrained edge: the parameter along its input edge,
            // strictly between the two neighbours there.
            let slide = if let Freedom::Slide(parent, [s, r]) = freedom {
                let (p0, p1, _) = self.parents[parent as usize];
                let d = [p1[0] - p0[0], p1[1] - p0[1]];
                let param = |x: [f64; 2]| {
                    ((x[0] - p0[0]) * d[0] + (x[1] - p0[1]) * d[1]) / (d[0] * d[0] + d[1] * d[1])
                };
                let at = |s: u32| {
                    let rec = &self.m.subs[s as usize];
                    if rec.v[0] == v {
                        (rec.t[0], rec.t[1])
                    } else {
                        (rec.t[1], rec.t[0])
                    }
                };
                let ((tv, t1), (_, t2)) = (at(s), at(r));
                let (lo, hi) = (t1.min(t2), t1.max(t2));
                let margin = 0.05 * (hi - lo);
                Some((
                    p0,
                    d,
                    tv,
                    param(ideal).clamp(lo + margin, hi - margin),
                    [s, r],
                ))
            } else {
                None
            };
            let old = star
                .iter()
                .map(|&(t, _)| self.quality(self.m.tr[t].v))
                .fold(f64::INFINITY, f64::min);
            let mv = self.met[v as usize];
            let lv = self.logs[v as usize];
            let mut moved = false;
            for omega in [1.0, 0.5, 0.25] {
                let (c, tc) = match slide {
                    Some((p0, d, tv, target, _)) => {
                        let tc = tv + omega * (target - tv);
                        ([p0[0] + tc * d[0], p0[1] + tc * d[1]], tc)
                    }
                    None => (
                        [
                            pv[0] + omega * (ideal[0] - pv[0]),
                            pv[1] + omega * (ideal[1] - pv[1]),
                        ],
                        0.0,
                    ),
                };
                if c == pv || !self.m.can_move(&star, &c) {
                    continue;
                }
                let mc = self.metric_at(&c, &[(1.0, mv)]);
                self.m.xy[v as usize] = c;
                self.met[v as usize] = mc;
                self.logs[v as usize] = mc.log();
                let new = star
                    .iter()
                    .map(|&(t, _)| self.quality(self.m.tr[t].v))
                    .fold(f64::INFINITY, f64::min);
                if new > old + GAIN {
                    if let Some((.., subs)) = slide {
                        for s in subs {
                            let rec = &mut self.m.subs[s as usize];
                            let k = usize::from(rec.v[0] != v);
                            rec.t[k] = tc;
                        }
                    }
                    done += 1;
                    moved = true;
                    #[cfg(test)]
                    self.verify("move");
                    break;
                }
                self.m.xy[v as usize] = pv;
                self.met[v as usize] = mv;
                self.logs[v as usize] = lv;
            }
            if moved {
                self.stir(v);
            } else {
                self.settled[v as usize] = true;
            }
        }
        self.report.moves += done;
        done
    }

    /// The area of each region (element reference), in reference order.
    #[cfg(test)]
    fn region_areas(&self) -> Vec<(i32, f64)> {
        let mut a: Vec<(i32, f64)> = Vec::new();
        for t in self.m.tr.iter().filter(|t| t.v[0] != DEAD) {
            let r = self.regions.get(t.orig as usize).copied().unwrap_or(0);
            let c = t.v.map(|v| *self.m.p(v));
            let area = 0.5
                * ((c[1][0] - c[0][0]) * (c[2][1] - c[0][1])
                    - (c[1][1] - c[0][1]) * (c[2][0] - c[0][0]));
            match a.iter_mut().find(|x| x.0 == r) {
                Some(x) => x.1 += area,
                None => a.push((r, area)),
            }
        }
        a.sort_by_key(|x| x.0);
        a
    }

    /// The adaptation's invariants, checked by the tests after every
    /// operation: the mesh's own ([`CMesh::check`]: counterclockwise
    /// triangles, adjacency, subsegments); every vertex's triangle holds
    /// it; every vertex of a subsegment lies on its input edge (up to
    /// rounding) at its parameter; every region keeps its area.
    #[cfg(test)]
    fn verify(&self, after: &str) {
        self.m
            .check(false)
            .unwrap_or_else(|e| panic!("after {after}: {e}"));
        for (v, &t) in self.vt.iter().enumerate() {
            if t != NONE {
                assert!(
                    self.m.tr[t as usize].v.contains(&(v as u32)),
                    "after {after}: vertex {v} is not in its triangle {t}"
                );
            }
        }
        for s in self.m.subs.iter().filter(|s| s.alive) {
            let (p0, p1, _) = self.parents[s.parent as usize];
            let scale = (p1[0] - p0[0]).abs().max((p1[1] - p0[1]).abs());
            for k in 0..2 {
                let want = [
                    p0[0] + s.t[k] * (p1[0] - p0[0]),
                    p0[1] + s.t[k] * (p1[1] - p0[1]),
                ];
                let got = self.m.p(s.v[k]);
                let off = (got[0] - want[0]).abs().max((got[1] - want[1]).abs());
                assert!(
                    off <= 1e-12 * scale,
                    "after {after}: vertex {} is {off} off its input edge",
                    s.v[k]
                );
            }
        }
        let now = self.region_areas();
        assert_eq!(
            now.len(),
            self.areas.len(),
            "after {after}: a region vanished"
        );
        for (x, y) in now.iter().zip(&self.areas) {
            assert!(
                x.0 == y.0 && (x.1 - y.1).abs() <= 1e-12 * y.1.abs(),
                "after {after}: region {} area {} was {}",
                y.0,
                x.1,
                y.1
            );
        }
    }

    /// The mesh with compact numbering (vertices in index order, triangles
    /// in slot order, live subsegments in record order).
    fn output(self, input: &TriMesh) -> Adapted<2, 3> {
        let mut id = vec![NONE; self.vt.len()];
        let mut points = Vec::new();
        let mut metric = Vec::new();
        let mut point_refs = Vec::new();
        for (v, &t) in self.vt.iter().enumerate() {
            if t != NONE {
                id[v] = points.len() as u32;
                points.push(self.m.xy[v]);
                metric.push(self.met[v]);
                if let Some(&r) = self.point_refs.get(v) {
                    point_refs.push(r);
                }
            }
        }
        let mut elements = Vec::new();
        let mut element_refs = Vec::new();
        for tri in self.m.tr.iter().filter(|t| t.v[0] != DEAD) {
            elements.push(tri.v.map(|v| id[v as usize]));
            if let Some(&r) = input.element_refs.get(tri.orig as usize) {
                element_refs.push(r);
            }
        }
        let mut faces = Vec::new();
        let mut face_refs = Vec::new();
        for s in self.m.subs.iter().filter(|s| s.alive) {
            faces.push(s.v.map(|v| id[v as usize]));
            if !input.face_refs.is_empty() {
                face_refs.push(self.parents[s.parent as usize].2);
            }
        }
        let keep = |list: &[u32]| {
            list.iter()
                .map(|&v| id[v as usize])
                .filter(|&v| v != NONE)
                .collect()
        };
        Adapted {
            mesh: TriMesh {
                points,
                point_refs,
                elements,
                element_refs,
                faces,
                face_refs,
                corners: keep(&input.corners),
                ridges: Vec::new(),
                required: keep(&input.required),
            },
            metric,
            report: self.report,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit square (scaled by `scale`) as an `n × n` grid of cells
    /// split into two triangles each; sides as faces with references 1–4,
    /// the four corners as corners; the left half region 1, the right 2.
    pub(crate) fn square(n: usize, scale: f64) -> TriMesh {
        let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
        let mut m = TriMesh::default();
        for j in 0..=n {
            for i in 0..=n {
                m.points
                    .push([scale * i as f64 / n as f64, scale * j as f64 / n as f64]);
            }
        }
        for j in 0..n {
            for i in 0..n {
                let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
                m.elements.extend([[a, b, c], [a, c, d]]);
                let r = if 2 * i < n { 1 } else { 2 };
                m.element_refs.extend([r, r]);
            }
        }
        for k in 0..n {
            m.faces.extend([
                [id(k, 0), id(k + 1, 0)],
                [id(n, k), id(n, k + 1)],
                [id(k + 1, n), id(k, n)],
                [id(0, k + 1), id(0, k)],
            ]);
            m.face_refs.extend([1, 2, 3, 4]);
        }
        m.corners = vec![id(0, 0), id(n, 0), id(n, n), id(0, n)];
        m
    }

    /// The UGAWG linear metric: h_x = 0.1, h_y = h0 + 2 (0.1 − h0) |y − 0.5|.
    fn linear(p: &[f64; 2]) -> Metric<2> {
        let h0 = 1e-3;
        let hy = h0 + 2.0 * (0.1 - h0) * (p[1] - 0.5).abs();
        Metric::from_medit(&[100.0, 0.0, 1.0 / (hy * hy)]).unwrap()
    }

    /// The UGAWG polar-1 metric: a layer along the circle r = 0.5 about
    /// the origin, h_r = h0 + 2 (0.1 − h0) |r − 0.5| across it, 0.1 along it.
    fn polar(p: &[f64; 2]) -> Metric<2> {
        let h0 = 1e-3;
        let r = p[0].hypot(p[1]);
        let hr = h0 + 2.0 * (0.1 - h0) * (r - 0.5).abs();
        let (c, s) = if r > 0.0 {
            (p[0] / r, p[1] / r)
        } else {
            (1.0, 0.0)
        };
        Metric::from_matrix(crate::metric::compose(
            &[1.0 / (hr * hr), 100.0],
            &[[c, -s], [s, c]],
        ))
        .unwrap()
    }

    /// The edges along a curved anisotropic layer are chords that cross
    /// the layer at their ends: they are measured through the metric
    /// turning along them, not split as if each end's metric held along the
    /// whole chord.
    #[test]
    fn a_curved_layer_is_not_over_refined() {
        let out = adapt_checked(
            &square(10, 1.0),
            MetricField::Function(&polar),
            &AdaptOptions::default(),
        );
        // The elements of a unit mesh: ∫ √det M over the area of the unit
        // equilateral triangle, by the metric at each centroid.
        let m = &out.mesh;
        let unit: f64 = m
            .elements
            .iter()
            .map(|t| {
                let c = t.map(|v| m.points[v as usize]);
                let g = [
                    (c[0][0] + c[1][0] + c[2][0]) / 3.0,
                    (c[0][1] + c[1][1] + c[2][1]) / 3.0,
                ];
                let a = 0.5
                    * ((c[1][0] - c[0][0]) * (c[2][1] - c[0][1])
                        - (c[1][1] - c[0][1]) * (c[2][0] - c[0][0]));
                a * polar(&g).det().sqrt()
            })
            .sum::<f64>()
            / (3f64.sqrt() / 4.0);
        // Measured by the ends' metrics alone, the chords along the layer
        // are split until about 1.41 times that many elements; measured
        // through the turning metric about 1.30.
        let n = m.elements.len() as f64;
        assert!(n < 1.35 * unit, "{n} elements for a unit count of {unit}");
        let s = &out.report.after;
        assert!(s.in_range_share() > 0.85 && s.quality_min > 0.3, "{s:?}");
    }

    fn area(m: &TriMesh) -> f64 {
        m.elements
            .iter()
            .map(|t| {
                let c = t.map(|v| m.points[v as usize]);
                0.5 * ((c[1][0] - c[0][0]) * (c[2][1] - c[0][1])
                    - (c[1][1] - c[0][1]) * (c[2][0] - c[0][0]))
            })
            .sum()
    }

    #[test]
    fn linear_metric_meets_its_bounds() {
        let input = square(4, 1.0);
        let out = adapt_tri(
            &input,
            MetricField::Function(&linear),
            &AdaptOptions::default(),
        )
        .unwrap();
        let s = &out.report.after;
        assert!(s.in_range_share() >= 0.9, "{s:?}");
        assert!(s.quality_min >= 0.4, "{s:?}");
        assert!((area(&out.mesh) - 1.0).abs() < 1e-12);
        // The same again: bit for bit.
        let again = adapt_tri(
            &input,
            MetricField::Function(&linear),
            &AdaptOptions::default(),
        )
        .unwrap();
        assert_eq!(out.mesh, again.mesh);
        // Four corners, every boundary edge with its side's reference.
        assert_eq!(out.mesh.corners.len(), 4);
        for (f, r) in out.mesh.faces.iter().zip(&out.mesh.face_refs) {
            let [a, b] = f.map(|v| out.mesh.points[v as usize]);
            let on = match r {
                1 => a[1] == 0.0 && b[1] == 0.0,
                2 => a[0] == 1.0 && b[0] == 1.0,
                3 => a[1] == 1.0 && b[1] == 1.0,
                4 => a[0] == 0.0 && b[0] == 0.0,
                0 => (a[0] - 0.5).abs() < 1e-15 && (b[0] - 0.5).abs() < 1e-15,
                _ => false,
            };
            assert!(on, "face {f:?} ref {r}: {a:?} {b:?}");
        }
    }

    /// A deterministic pseudo-random sequence in [0, 1).
    fn rng(mut s: u64) -> impl FnMut() -> f64 {
        move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// The Delaunay mesh of `pts` (hull edges become faces by themselves).
    fn delaunay(pts: Vec<[f64; 2]>) -> TriMesh {
        let d = crate::tri::triangulate(&pts).unwrap();
        TriMesh {
            points: pts,
            elements: d.triangles,
            ..Default::default()
        }
    }

    /// Adapts with the invariant checker after every operation (the
    /// `verify` hook) and checks the output: counterclockwise triangles
    /// (exact), the same area, metric and points of the same length.
    fn adapt_checked(mesh: &TriMesh, field: MetricField<'_, 2>, o: &AdaptOptions) -> Adapted<2, 3> {
        let out = adapt_tri(mesh, field, o).unwrap();
        let m = &out.mesh;
        for t in &m.elements {
            let c = t.map(|v| m.points[v as usize]);
            assert!(
                delone_predicates::orient2d(&c[0], &c[1], &c[2]) > 0.0,
                "{t:?} inverted"
            );
        }
        let (a0, a1) = (area(mesh), area(m));
        assert!((a1 - a0).abs() <= 1e-12 * a0.abs(), "area {a1} was {a0}");
        assert_eq!(out.metric.len(), m.points.len());
        out
    }

    #[test]
    fn random_meshes_and_anisotropic_metrics_stay_valid() {
        for seed in 1..6u64 {
            let mut r = rng(seed * 7919);
            let pts: Vec<[f64; 2]> = (0..60).map(|_| [r(), r()]).collect();
            let mesh = delaunay(pts);
            // A rotating anisotropic metric, different per seed.
            let k = seed as f64;
            let f = move |p: &[f64; 2]| {
                let (c, s) = ((k * p[0]).cos(), (k * p[1]).sin());
                let (h1, h2) = (0.02 + 0.1 * p[0], 0.15);
                let (l1, l2) = (1.0 / (h1 * h1), 1.0 / (h2 * h2));
                Metric::from_matrix([
                    [l1 * c * c + l2 * s * s, (l1 - l2) * c * s],
                    [(l1 - l2) * c * s, l1 * s * s + l2 * c * c],
                ])
                .unwrap_or(Metric::isotropic(0.1))
            };
            let out = adapt_checked(&mesh, MetricField::Function(&f), &AdaptOptions::default());
            let s = &out.report.after;
            assert!(s.in_range_share() > 0.7, "seed {seed}: {s:?}");
            assert!(
                out.report.splits > 0
                    && out.report.collapses > 0
                    && out.report.swaps > 0
                    && out.report.moves > 0,
                "seed {seed}: {:?}",
                out.report
            );
            // A metric at the vertices (log-Euclidean at new ones).
            let at: Vec<Metric<2>> = mesh
                .points
                .iter()
                .map(|p| Metric::isotropic(0.05 + 0.2 * p[0]))
                .collect();
            adapt_checked(&mesh, MetricField::AtVertices(at), &AdaptOptions::default());
        }
    }

    #[test]
    fn collinear_boundary_points_slide_and_collapse_along_their_line() {
        // A strip whose bottom side holds 40 unevenly spaced points and a
        // region boundary at x = 1.
        let mut r = rng(3);
        let mut pts: Vec<[f64; 2]> = (0..40)
            .map(|k| [2.0 * (k as f64 + 0.8 * r()) / 40.0, 0.0])
            .collect();
        pts.extend([
            [0.0, 0.0],
            [2.0, 0.0],
            [0.0, 0.3],
            [2.0, 0.3],
            [1.0, 0.0],
            [1.0, 0.3],
            [0.5, 0.3],
            [1.5, 0.3],
        ]);
        let mut mesh = delaunay(pts);
        mesh.element_refs = mesh
            .elements
            .iter()
            .map(|t| {
                let x: f64 = t.iter().map(|&v| mesh.points[v as usize][0]).sum::<f64>() / 3.0;
                1 + i32::from(x > 1.0)
            })
            .collect();
        let out = adapt_checked(
            &mesh,
            MetricField::AtVertices(vec![Metric::isotropic(0.2); mesh.points.len()]),
            &AdaptOptions::default(),
        );
        assert!(out.report.collapses > 10, "{:?}", out.report);
        // Each output triangle on its side of x = 1.
        for (t, r) in out.mesh.elements.iter().zip(&out.mesh.element_refs) {
            let x: f64 = t
                .iter()
                .map(|&v| out.mesh.points[v as usize][0])
                .sum::<f64>()
                / 3.0;
            assert_eq!(*r, 1 + i32::from(x > 1.0));
        }
    }

    #[test]
    fn tiny_and_huge_coordinates() {
        for scale in [1e-60, 1e60] {
            let input = square(3, scale);
            let f = move |p: &[f64; 2]| {
                let h = scale * (0.03 + 0.2 * p[0] / scale);
                Metric::from_medit(&[1.0 / (h * h), 0.0, 1.0 / (0.1 * scale * 0.1 * scale)])
                    .unwrap()
            };
            let out = adapt_checked(&input, MetricField::Function(&f), &AdaptOptions::default());
            assert!(
                out.report.after.in_range_share() > 0.85,
                "{scale}: {:?}",
                out.report.after
            );
        }
    }

    #[test]
    fn options_off_and_budget() {
        let input = square(4, 1.0);
        let none = AdaptOptions {
            insert: false,
            swap: false,
            smooth: false,
            ..Default::default()
        };
        let out = adapt_checked(&input, MetricField::Function(&linear), &none);
        assert_eq!(out.mesh.elements.len(), input.elements.len());
        assert_eq!(out.report.before, out.report.after);
        let budget = AdaptOptions {
            max_vertices: Some(60),
            ..Default::default()
        };
        let out = adapt_checked(&input, MetricField::Function(&linear), &budget);
        assert!(out.report.budget_reached);
        assert!(out.mesh.points.len() <= 60 + 1);
    }

    #[test]
    fn bad_input_is_an_error_naming_it() {
        let good = square(2, 1.0);
        let o = AdaptOptions::default();
        let iso = |n| MetricField::AtVertices(vec![Metric::isotropic(0.3); n]);
        let err = |m: &TriMesh, f, o: &AdaptOptions| adapt_tri(m, f, o).unwrap_err().to_string();
        assert!(err(&good, iso(3), &o).contains("3 value(s) for a mesh of 9 vertices"));
        let mut cw = good.clone();
        cw.elements[1].swap(0, 1);
        assert!(err(&cw, iso(9), &o).contains("triangle 1"));
        let mut face = good.clone();
        face.faces[0] = [0, 8];
        assert!(err(&face, iso(9), &o).contains("face 0"));
        let mut nan = good.clone();
        nan.points[4][0] = f64::NAN;
        assert!(err(&nan, iso(9), &o).contains("point 4"));
        let mut refs = good.clone();
        refs.element_refs.pop();
        assert!(err(&refs, iso(9), &o).contains("element_refs"));
        let bad = AdaptOptions {
            hmin: Some(-1.0),
            ..Default::default()
        };
        assert!(err(&good, iso(9), &bad).contains("-hmin"));
        let bad = AdaptOptions {
            hgrad: Some(0.5),
            ..Default::default()
        };
        assert!(err(&good, iso(9), &bad).contains("-hgrad"));
    }
}
