//! 3D adaptation on the constrained tetrahedral mesh
//! ([`crate::tet::dmesh::DomainMesh`]): worst-first passes of edge split,
//! edge collapse, swaps (2-3 flips and edge removal by the shared dynamic
//! program, [`crate::tet::dmesh::ring::triangulate`]), vertex smoothing
//! and the reshaping of slivers ([`Engine::reshape_pass`]), each judged by
//! edge lengths and mean ratio in the metric and committed
//! only when every new tetrahedron is strictly positive by exact
//! `orient3d`. While the mesh grows, only edges longer than 1.6 are split
//! and shorter than 0.8 collapsed ([`GROW`]): splitting every edge above √2
//! on a coarse mesh, whose interpolated metric is far from the field's,
//! fills it with short edges that the collapses then have to remove. Once
//! the changes settle, the passes go on with the range's own bounds.
//!
//! The boundary is kept: the input's boundary and interface triangles are
//! the mesh's subfaces (each remembers its input triangle, hence its
//! reference), grouped into planar *facets* (coplanar neighbours with one
//! reference, not across a ridge). A vertex on one facet collapses only
//! along a subface edge of it, a vertex on two (a ridge) only along the
//! ridge; corners, required vertices and vertices on three facets or more
//! never move. Splits put the new vertex on the edge (at its middle in the
//! metric), so on the edge's facet or ridge; smoothing moves a facet vertex
//! in its facet's plane and a ridge vertex along its ridge, only to points
//! exactly on the planes of its subfaces.

#![allow(clippy::needless_range_loop)] // local face indices address several arrays at once

use std::time::Instant;

use delone_predicates::orient3d;

use super::{metric_stats, AdaptOptions, AdaptReport, Adapted, MetricField, TetMesh};
use crate::metric::{edges, gradate, tet_quality, Metric};
use crate::tet::dmesh::flip::positive;
use crate::tet::dmesh::{ring, DomainMesh};
use crate::tet::local::{ekey, face, fkey, EDGES, FACET};
use crate::tet::mesh::{input_tets, TetsDefect};
use crate::{Error, NONE};

/// Edges longer than this (in the metric) are split and edges shorter than
/// that collapsed while the mesh grows: splitting only clearly long edges
/// keeps the mesh from filling with short ones. Once that settles the passes
/// go on with [`FINAL`].
const GROW: (f64, f64) = (1.6, 0.8);
/// The split and collapse bounds once the mesh has settled: the range
/// `[1/√2, √2]` itself.
const FINAL: (f64, f64) = (std::f64::consts::SQRT_2, std::f64::consts::FRAC_1_SQRT_2);
/// How far from the geometric midpoint (as a fraction of the edge) a split
/// may put its vertex to halve the edge's metric length.
const SPLIT_AT: f64 = 0.3;
/// A pass that splits and collapses fewer than one edge in `QUIET` per
/// live vertex is quiet: two quiet passes end the growth bounds, two more
/// the adaptation. The passes after the last few changes cost a full sweep
/// each and gain little.
const QUIET: usize = 50;
/// Tetrahedra below this quality are swapped worst first.
const SWAP_BELOW: f64 = 0.5;
/// Tetrahedra below this quality are reshaped after each smoothing sweep
/// ([`Engine::reshape_pass`]).
const RESHAPE_BELOW: f64 = 0.45;
/// A collapse may not leave a tetrahedron below this quality (or below the
/// worst of the star it replaces, when that is lower).
const COLLAPSE_FLOOR: f64 = 0.25;
/// Largest edge shell split or removed.
const MAX_SHELL: usize = 64;
/// Longest edge ring an edge removal tries.
const MAX_RING: usize = 12;

/// Adapts a tetrahedral mesh to a metric field: the metric is bounded by
/// `hmin`/`hmax` and graded by `hgrad`, then split, collapse, swap and
/// smoothing passes run until a pass splits and collapses nothing (or
/// `max_passes`, or `max_vertices`). Every region keeps its volume and
/// reference, every boundary and interface triangle's reference is kept on
/// the triangles that cover it.
///
/// # Errors
/// [`Error::InvalidCoordinate`], [`Error::IndexOutOfRange`] (a
/// tetrahedron, face, corner, ridge or required vertex naming a missing
/// point), [`Error::InconsistentMesh`] (reference arrays of the wrong
/// length, a tetrahedron not positively oriented, overlapping or
/// non-manifold tetrahedra, a face that is not a face of the mesh),
/// [`Error::MetricCount`].
///
/// ```
/// use delone::adapt::{adapt_tet, AdaptOptions, MetricField, TetMesh};
/// use delone::metric::Metric;
/// // One tetrahedron, adapted to size 0.5: split into a few dozen.
/// let mesh = TetMesh {
///     points: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
///     elements: vec![[0, 1, 2, 3]],
///     ..Default::default()
/// };
/// let size = |_: &[f64; 3]| Metric::isotropic(0.5);
/// let out = adapt_tet(&mesh, MetricField::Function(&size), &AdaptOptions::default()).unwrap();
/// assert!(out.mesh.elements.len() > 4);
/// assert_eq!(out.mesh.faces.len() % 2, 0);
/// assert!(out.report.after.quality_min > 0.0);
/// ```
pub fn adapt_tet(
    mesh: &TetMesh,
    metric: MetricField<'_, 3>,
    options: &AdaptOptions,
) -> Result<Adapted<3, 4>, Error> {
    let clock = Instant::now();
    let (mut e, input) = Engine::new(mesh, metric, options)?;
    e.report
        .phases
        .push(("input", clock.elapsed().as_secs_f64()));
    e.run()?;
    Ok(e.output(mesh, &input))
}

/// The checked input: the domain mesh with its subfaces, the faces kept
/// (the input's, then boundary faces it lacks, reference 0), their facets
/// and each facet's unit normal, the regions' references, the facet pairs
/// of the input's ridges.
struct Input {
    dm: DomainMesh,
    faces: Vec<([u32; 3], i32)>,
    facet: Vec<u32>,
    normal: Vec<[f64; 3]>,
    regions: Vec<i32>,
    ridge_pairs: Vec<(u32, u32)>,
}

impl Input {
    fn check(mesh: &TetMesh) -> Result<Input, Error> {
        let n = mesh.points.len();
        if let Some(i) = mesh
            .points
            .iter()
            .position(|p| p.iter().any(|x| !x.is_finite()))
        {
            return Err(Error::InvalidCoordinate { index: i });
        }
        let bad = |what: &str, len: usize, of: usize| Error::InconsistentMesh {
            reason: format!("{len} {what} references for {of} items"),
        };
        for (what, len, of) in [
            ("vertex", mesh.point_refs.len(), n),
            ("tetrahedron", mesh.element_refs.len(), mesh.elements.len()),
            ("face", mesh.face_refs.len(), mesh.faces.len()),
        ] {
            if len != 0 && len != of {
                return Err(bad(what, len, of));
            }
        }
        let lists: [(&'static str, Vec<&[u32]>); 5] = [
            (
                "tetrahedron",
                mesh.elements.iter().map(|x| &x[..]).collect(),
            ),
            ("triangle", mesh.faces.iter().map(|x| &x[..]).collect()),
            ("ridge", mesh.ridges.iter().map(|x| &x[..]).collect()),
            ("corner", mesh.corners.chunks(1).collect()),
            ("required vertex", mesh.required.chunks(1).collect()),
        ];
        for (item, list) in lists {
            for (index, x) in list.iter().enumerate() {
                if let Some(&vertex) = x.iter().find(|&&v| v as usize >= n) {
                    return Err(Error::IndexOutOfRange {
                        item,
                        index,
                        vertex,
                        points: n,
                    });
                }
            }
        }
        for (t, x) in mesh.elements.iter().enumerate() {
            let g = |i: usize| &mesh.points[x[i] as usize];
            if orient3d(g(0), g(1), g(2), g(3)) >= 0.0 {
                return Err(Error::InconsistentMesh {
                    reason: format!("tetrahedron {t} {x:?} is not positively oriented"),
                });
            }
        }
        let (tv, nb) = input_tets(&mesh.points, &mesh.elements, true).map_err(|d| {
            let (t, what) = match d {
                TetsDefect::BadIndex(t) => (t, "repeats a vertex"),
                TetsDefect::Degenerate(t) | TetsDefect::Inverted(t) => {
                    (t, "is not positively oriented")
                }
                TetsDefect::NonManifold(t) => (t, "shares a face with two others"),
                TetsDefect::Overlap(t) => (t, "overlaps its neighbour"),
            };
            Error::InconsistentMesh {
                reason: format!("tetrahedron {t} {what}"),
            }
        })?;
        let mut regions: Vec<i32> = mesh.element_refs.clone();
        regions.sort_unstable();
        regions.dedup();
        if regions.is_empty() {
            regions.push(0);
        }
        let reg: Vec<u32> = (0..tv.len())
            .map(|t| {
                let r = mesh.element_refs.get(t).copied().unwrap_or(0);
                regions.binary_search(&r).unwrap_or(0) as u32
            })
            .collect();
        let mut dm =
            DomainMesh::from_neighbors(&tv, &nb, &reg, n).map_err(|t| Error::InconsistentMesh {
                reason: format!("tetrahedron {t} does not fit its neighbours"),
            })?;
        // The faces: the input's, then the boundary faces it lacks.
        let mut slot_of: Vec<([u32; 3], u32, u8)> = Vec::with_capacity(4 * tv.len());
        for (t, x) in tv.iter().enumerate() {
            for f in 0..4 {
                slot_of.push((fkey(face(*x, f)), t as u32, f as u8));
            }
        }
        slot_of.sort_unstable();
        let mut faces: Vec<([u32; 3], i32)> = Vec::new();
        for (i, x) in mesh.faces.iter().enumerate() {
            let k = fkey(*x);
            let j = slot_of.partition_point(|s| s.0 < k);
            if slot_of.get(j).is_none_or(|s| s.0 != k) {
                return Err(Error::InconsistentMesh {
                    reason: format!("face {i} {x:?} is not a face of a tetrahedron"),
                });
            }
            let (t, f) = (slot_of[j].1, slot_of[j].2 as usize);
            if dm.ftri.contains_key(&k) {
                continue;
            }
            dm.mark_face(t, f);
            dm.ftri.insert(k, faces.len() as u32);
            faces.push((*x, mesh.face_refs.get(i).copied().unwrap_or(0)));
        }
        for (t, x) in tv.iter().enumerate() {
            for f in 0..4 {
                let k = fkey(face(*x, f));
                if nb[t][f] == NONE && !dm.ftri.contains_key(&k) {
                    dm.mark_face(t as u32, f);
                    dm.ftri.insert(k, faces.len() as u32);
                    faces.push((k, 0));
                }
            }
        }
        // Facets: faces joined across edges of exactly two faces with one
        // reference and one plane, not across a ridge.
        let p = &mesh.points;
        let unit = |k: [u32; 3]| {
            let [a, b, c] = k.map(|v| p[v as usize]);
            let (u, w) = (sub(b, a), sub(c, a));
            let x = [
                u[1] * w[2] - u[2] * w[1],
                u[2] * w[0] - u[0] * w[2],
                u[0] * w[1] - u[1] * w[0],
            ];
            let l = (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
            x.map(|c| c / l)
        };
        let mut by_edge: Vec<((u32, u32), u32)> = Vec::with_capacity(3 * faces.len());
        for (i, (k, _)) in faces.iter().enumerate() {
            for (a, b) in [(k[0], k[1]), (k[1], k[2]), (k[0], k[2])] {
                by_edge.push((ekey(a, b), i as u32));
            }
        }
        by_edge.sort_unstable();
        let mut ridges: Vec<(u32, u32)> = mesh.ridges.iter().map(|r| ekey(r[0], r[1])).collect();
        ridges.sort_unstable();
        let mut parent: Vec<u32> = (0..faces.len() as u32).collect();
        fn root(parent: &mut [u32], mut x: u32) -> u32 {
            while parent[x as usize] != x {
                parent[x as usize] = parent[parent[x as usize] as usize];
                x = parent[x as usize];
            }
            x
        }
        for run in by_edge.chunk_by(|a, b| a.0 == b.0) {
            if let [(e, i), (_, j)] = *run {
                let (fi, fj) = (&faces[i as usize], &faces[j as usize]);
                let (ni, nj) = (unit(fi.0), unit(fj.0));
                let d = ni[0] * nj[0] + ni[1] * nj[1] + ni[2] * nj[2];
                if fi.1 == fj.1 && d.abs() > 1.0 - 1e-9 && ridges.binary_search(&e).is_err() {
                    let (ri, rj) = (root(&mut parent, i), root(&mut parent, j));
                    parent[ri.max(rj) as usize] = ri.min(rj);
                }
            }
        }
        let mut facet = vec![0u32; faces.len()];
        let mut normal = Vec::new();
        let mut id = vec![NONE; faces.len()];
        for i in 0..faces.len() {
            let r = root(&mut parent, i as u32) as usize;
            if id[r] == NONE {
                id[r] = normal.len() as u32;
                normal.push(unit(faces[r].0));
            }
            facet[i] = id[r];
        }
        let mut ridge_pairs = Vec::new();
        for run in by_edge.chunk_by(|a, b| a.0 == b.0) {
            if ridges.binary_search(&run[0].0).is_ok() {
                let mut fs: Vec<u32> = run.iter().map(|x| facet[x.1 as usize]).collect();
                fs.sort_unstable();
                fs.dedup();
                if let [a, b] = fs[..] {
                    ridge_pairs.push((a, b));
                }
            }
        }
        ridge_pairs.sort_unstable();
        ridge_pairs.dedup();
        dm.debug_check(p, "adaptation input");
        Ok(Input {
            dm,
            faces,
            facet,
            normal,
            regions,
            ridge_pairs,
        })
    }
}

/// The metric length of edge `a b`.
fn length(p: &[[f64; 3]], met: &[Metric<3>], a: u32, b: u32) -> f64 {
    let (a, b) = (a as usize, b as usize);
    met[a].edge_length(&met[b], sub(p[b], p[a]))
}

/// The quality of `tv`: its mean ratio in the mean metric of its corners.
fn quality(p: &[[f64; 3]], met: &[Metric<3>], tv: [u32; 4]) -> f64 {
    tet_quality(&tv.map(|v| p[v as usize]), tv.map(|v| &met[v as usize]))
}

/// [`quality`] of slot `t` holding `tv`, from `cache` when it is valid
/// (see [`Engine::cache`]).
fn cached_quality(
    cache: &std::cell::RefCell<Vec<([u32; 4], f64)>>,
    (p, met): (&[[f64; 3]], &[Metric<3>]),
    t: u32,
    tv: [u32; 4],
) -> f64 {
    let mut c = cache.borrow_mut();
    if c.len() <= t as usize {
        c.resize(t as usize + 1, ([NONE; 4], 0.0));
    }
    if c[t as usize].0 != tv {
        c[t as usize] = (tv, quality(p, met, tv));
    }
    c[t as usize].1
}

/// True when every edge of tetrahedra `new` that is not an edge of `old`
/// has metric length at most `long`: an operation must not make an edge
/// that the next split pass would cut.
fn no_long_edge(
    p: &[[f64; 3]],
    met: &[Metric<3>],
    long: f64,
    old: &[[u32; 4]],
    new: &[[u32; 4]],
) -> bool {
    // Edge `a b` (a < b) as one word, so that the keys sort as integers.
    let keys = |tets: &[[u32; 4]]| {
        tets.iter()
            .flat_map(|tv| EDGES.map(|(i, j)| ekey(tv[i], tv[j])))
            .map(|(a, b)| (u64::from(a) << 32) | u64::from(b))
            .collect::<Vec<u64>>()
    };
    let mut before = keys(old);
    before.sort_unstable();
    let mut checked: Vec<u64> = Vec::new();
    keys(new).into_iter().all(|k| {
        if before.binary_search(&k).is_ok() || checked.contains(&k) {
            return true;
        }
        checked.push(k);
        length(p, met, (k >> 32) as u32, k as u32) <= long
    })
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// Where a vertex may go.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Class {
    /// Never moved or removed.
    Fixed,
    /// Inside the domain (no subface).
    Interior,
    /// On one facet.
    Surface(u32),
    /// On the ridge between two facets.
    Ridge(u32, u32),
}

/// Reused buffers of [`Engine::plan_removal`]: the ring's slots and
/// vertices, the dynamic program's tables.
type RingScratch = (Vec<u32>, Vec<u32>, Vec<f64>, Vec<usize>);

/// A metric given as a function of the point.
type MetricFn<'a> = dyn Fn(&[f64; 3]) -> Metric<3> + Sync + 'a;

/// The adaptation's state.
struct Engine<'a> {
    m: DomainMesh,
    p: Vec<[f64; 3]>,
    met: Vec<Metric<3>>,
    fixed: Vec<bool>,
    /// Facet per kept face (the subface table's values).
    facet: Vec<u32>,
    normal: Vec<[f64; 3]>,
    /// The metric at a point, for a metric given as a function.
    field: Option<&'a MetricFn<'a>>,
    opt: &'a AdaptOptions,
    report: AdaptReport,
    /// Live vertices.
    live: usize,
    /// Quality per slot with the vertices it was computed for: valid while
    /// the slot holds them and none of them has moved (a move rewrites its
    /// star's entries).
    cache: std::cell::RefCell<Vec<([u32; 4], f64)>>,
    /// Per vertex: bumped whenever its star changes (a tetrahedron through
    /// it replaced, or a vertex of its star moved), so that an operation
    /// refused on a star is not tried again before the star changes.
    version: Vec<u32>,
    /// Collapses refused: `v`, `w` and `v`'s version then.
    refused: crate::geom::ids::IdSet<(u32, u32, u32)>,
    /// Edges longer than `bounds.0` are split, shorter than `bounds.1`
    /// collapsed ([`GROW`], then [`FINAL`]).
    bounds: (f64, f64),
    /// Per slot: the vertices and their versions when no swap was found.
    unswappable: Vec<([u32; 4], [u32; 4])>,
    /// Per vertex: its version when it last failed to smooth (it fails
    /// again until its star changes).
    unsmoothable: Vec<Option<u32>>,
}

impl<'a> Engine<'a> {
    /// The engine on a checked input, with the metric at its vertices
    /// bounded and graded.
    fn new(
        mesh: &TetMesh,
        metric: MetricField<'a, 3>,
        opt: &'a AdaptOptions,
    ) -> Result<(Engine<'a>, Input), Error> {
        let mut input = Input::check(mesh)?;
        let n = mesh.points.len();
        let (field, met) = match metric {
            MetricField::AtVertices(m) if m.len() != n => {
                return Err(Error::MetricCount {
                    vertices: n,
                    metrics: m.len(),
                })
            }
            MetricField::AtVertices(m) => (None, m),
            MetricField::Function(f) => (Some(f), mesh.points.iter().map(f).collect()),
        };
        let mut e = Engine {
            m: std::mem::take(&mut input.dm),
            p: mesh.points.clone(),
            met,
            fixed: vec![false; n],
            facet: std::mem::take(&mut input.facet),
            normal: std::mem::take(&mut input.normal),
            field,
            opt,
            report: AdaptReport::default(),
            live: n,
            cache: Default::default(),
            version: vec![0; n],
            refused: Default::default(),
            bounds: GROW,
            unswappable: Vec::new(),
            unsmoothable: Vec::new(),
        };
        e.met = e.met.iter().map(|&m| e.bound(m)).collect();
        if let Some(g) = opt.hgrad {
            gradate(&mesh.points, &edges(&mesh.elements), &mut e.met, g);
        }
        e.report.before = metric_stats(&mesh.points, &mesh.elements, &e.met);
        for &v in mesh.corners.iter().chain(&mesh.required) {
            e.fixed[v as usize] = true;
        }
        Ok((e, input))
    }

    /// `m` within the options' `hmin` and `hmax`.
    fn bound(&self, m: Metric<3>) -> Metric<3> {
        match (self.opt.hmin, self.opt.hmax) {
            (None, None) => m,
            (lo, hi) => m.bounded(lo.unwrap_or(0.0), hi.unwrap_or(f64::INFINITY)),
        }
    }

    /// The metric at point `x` of a metric given as a function.
    fn field_at(&self, x: &[f64; 3]) -> Option<Metric<3>> {
        self.field.map(|f| self.bound(f(x)))
    }

    fn len(&self, a: u32, b: u32) -> f64 {
        length(&self.p, &self.met, a, b)
    }

    fn qual(&self, tv: [u32; 4]) -> f64 {
        quality(&self.p, &self.met, tv)
    }

    /// The quality of live slot `t`, from the cache when it is valid.
    fn slot_q(&self, t: u32) -> f64 {
        let tv = self.m.tv[t as usize];
        cached_quality(&self.cache, (&self.p, &self.met), t, tv)
    }

    /// Caches qualities `q` of live slots `slots` (computed as they are).
    fn remember(&self, slots: &[u32], q: &[f64]) {
        let mut c = self.cache.borrow_mut();
        for (&t, &x) in slots.iter().zip(q) {
            if c.len() <= t as usize {
                c.resize(t as usize + 1, ([NONE; 4], 0.0));
            }
            c[t as usize] = (self.m.tv[t as usize], x);
        }
    }

    /// Bumps the versions of the vertices of slots `slots`.
    fn touch(&mut self, slots: &[u32]) {
        for &t in slots {
            for v in self.m.tv[t as usize] {
                self.version[v as usize] = self.version[v as usize].wrapping_add(1);
            }
        }
    }

    /// The worst quality of live slots `slots`.
    fn min_slot_q(&self, slots: &[u32]) -> f64 {
        slots
            .iter()
            .map(|&t| self.slot_q(t))
            .fold(f64::INFINITY, f64::min)
    }

    /// The metric of a new vertex at `x`, a fraction `t` of the way from
    /// `a` to `b`.
    fn metric_at(&self, x: &[f64; 3], a: u32, b: u32, t: f64) -> Metric<3> {
        match self.field_at(x) {
            Some(m) => m,
            None => {
                Metric::interpolate(&[(1.0 - t, self.met[a as usize]), (t, self.met[b as usize])])
                    .unwrap_or(self.met[a as usize])
            }
        }
    }

    /// The facets of subfaces `subs` (those of a star through its centre,
    /// [`DomainMesh::subfaces_at`]) through `w` too, when given, sorted,
    /// each once.
    fn facets(&self, subs: &[([u32; 3], u32)], w: Option<u32>) -> Vec<u32> {
        let mut fs: Vec<u32> = subs
            .iter()
            .filter(|(k, _)| w.is_none_or(|w| k.contains(&w)))
            .map(|&(_, tri)| self.facet.get(tri as usize).copied().unwrap_or(NONE))
            .collect();
        fs.sort_unstable();
        fs.dedup();
        fs
    }

    /// The class of vertex `v`, whose star's subfaces through it are
    /// `subs`.
    fn class(&self, subs: &[([u32; 3], u32)], v: u32) -> Class {
        if self.fixed[v as usize] {
            return Class::Fixed;
        }
        match self.facets(subs, None)[..] {
            [] => Class::Interior,
            [f] if f != NONE => Class::Surface(f),
            [f, g] if g != NONE => {
                let (a, b) = (self.normal[f as usize], self.normal[g as usize]);
                let d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
                // Two coplanar facets meet along a polyline, not a line.
                if d.abs() > 1.0 - 1e-9 {
                    Class::Fixed
                } else {
                    Class::Ridge(f, g)
                }
            }
            _ => Class::Fixed,
        }
    }

    fn star(&self, v: u32) -> Vec<u32> {
        self.m.star_with(v, |_, _| true)
    }

    /// The passes; [`Error::Interrupted`] when the stop flag is set
    /// ([`crate::progress::stoppable`]).
    fn run(&mut self) -> Result<(), Error> {
        let phase = |r: &mut AdaptReport, name: &'static str, t: Instant| {
            let s = t.elapsed().as_secs_f64();
            match r.phases.iter_mut().find(|x| x.0 == name) {
                Some(x) => x.1 += s,
                None => r.phases.push((name, s)),
            }
        };
        let mut quiet = 0;
        // Smoothing (and the swaps after it) wait until the splits and
        // collapses have settled: before, most of the moved vertices go.
        let mut settled = false;
        while self.report.passes < self.opt.max_passes {
            crate::progress::report(
                "adapting",
                self.report.passes as u64,
                Some(self.opt.max_passes as u64),
                "passes",
            );
            if crate::progress::stop_requested() {
                return Err(Error::Interrupted);
            }
            self.report.passes += 1;
            let (s0, c0) = (self.report.splits, self.report.collapses);
            let t = Instant::now();
            if self.opt.insert && !self.report.budget_reached {
                self.split_pass();
            }
            phase(&mut self.report, "split", t);
            let t = Instant::now();
            self.collapse_pass();
            phase(&mut self.report, "collapse", t);
            let t = Instant::now();
            if self.opt.swap {
                self.swap_pass();
            }
            phase(&mut self.report, "swap", t);
            if settled && self.opt.smooth {
                let t = Instant::now();
                self.smooth_pass();
                self.reshape_pass();
                phase(&mut self.report, "smooth", t);
                let t = Instant::now();
                if self.opt.swap {
                    self.swap_pass();
                }
                phase(&mut self.report, "swap", t);
            }
            let changed = self.report.splits + self.report.collapses - s0 - c0;
            settled |= changed * 20 < self.live;
            // A few passes of swaps and smoothing after the last topology
            // change, or stop when the changes have become marginal.
            if changed * QUIET < self.live {
                quiet += 1;
                if quiet >= 2 && self.bounds != FINAL {
                    (self.bounds, quiet) = (FINAL, 0);
                    self.refused.clear();
                } else if quiet >= 2 {
                    break;
                }
            } else {
                quiet = 0;
            }
        }
        Ok(())
    }

    /// The live edges with their metric lengths, those `keep` takes, each
    /// once, grouped by their smaller end (the passes sort them fully):
    /// the edges of the live slots bucketed by their smaller end (a
    /// counting sort), then each other end kept once per bucket.
    fn edge_list(&self, keep: impl Fn(f64) -> bool) -> Vec<(f64, u32, u32)> {
        let n = self.p.len();
        let mut start = vec![0u32; n + 2];
        for t in self.m.live_slots() {
            let tv = self.m.tv[t as usize];
            for (i, j) in EDGES {
                start[tv[i].min(tv[j]) as usize + 2] += 1;
            }
        }
        for a in 2..n + 2 {
            start[a] += start[a - 1];
        }
        // Bucket `a` fills from `start[a + 1]`, which ends at its end.
        let mut other = vec![0u32; start[n + 1] as usize];
        for t in self.m.live_slots() {
            let tv = self.m.tv[t as usize];
            for (i, j) in EDGES {
                let (a, b) = ekey(tv[i], tv[j]);
                let at = &mut start[a as usize + 1];
                other[*at as usize] = b;
                *at += 1;
            }
        }
        let mut seen = vec![NONE; n];
        let mut out = Vec::new();
        for a in 0..n {
            for &b in &other[start[a] as usize..start[a + 1] as usize] {
                if seen[b as usize] != a as u32 {
                    seen[b as usize] = a as u32;
                    let l = self.len(a as u32, b);
                    if keep(l) {
                        out.push((l, a as u32, b));
                    }
                }
            }
        }
        out
    }

    /// Splits the edges longer than `bounds.0`, longest first.
    fn split_pass(&mut self) {
        let long = self.bounds.0;
        let mut es = self.edge_list(|l| l > long);
        es.sort_unstable_by(|x, y| y.0.total_cmp(&x.0).then((x.1, x.2).cmp(&(y.1, y.2))));
        for (_, a, b) in es {
            if self.opt.max_vertices.is_some_and(|m| self.live >= m) {
                self.report.budget_reached = true;
                return;
            }
            self.split(a, b);
        }
    }

    /// Splits edge `a b` at its middle in the metric (on the edge's ridge
    /// or facet when it has one): with the size varying geometrically
    /// along the edge (lengths `l_a`, `l_b` in the end metrics, `r = l_b /
    /// l_a`), the point a fraction `ln((1 + r) / 2) / ln r` of the way from
    /// `a`, kept within [`SPLIT_AT`] of the geometric midpoint. Split at
    /// the geometric midpoint, an edge across a steep size gradient leaves
    /// a short half that the next collapse pass removes again.
    fn split(&mut self, a: u32, b: u32) -> bool {
        let (pa, pb) = (self.p[a as usize], self.p[b as usize]);
        let e = sub(pb, pa);
        let r = self.met[b as usize].length(e) / self.met[a as usize].length(e);
        let t = if r.is_finite() && r > 0.0 && (r - 1.0).abs() > 1e-6 {
            ((0.5 + 0.5 * r).ln() / r.ln()).clamp(0.5 - SPLIT_AT, 0.5 + SPLIT_AT)
        } else {
            0.5
        };
        let x = [0, 1, 2].map(|k| pa[k] + t * e[k]);
        let mx = self.metric_at(&x, a, b, t);
        let v = self.p.len() as u32;
        self.p.push(x);
        self.met.push(mx);
        self.fixed.push(false);
        self.version.push(0);
        let Some(ids) = self.m.split_edge(&self.p, (a, b), v) else {
            self.p.pop();
            self.met.pop();
            self.fixed.pop();
            self.version.pop();
            return false;
        };
        self.touch(&ids);
        self.report.splits += 1;
        self.live += 1;
        self.m.debug_check(&self.p, "adaptation split");
        true
    }

    /// Collapses the edges shorter than `bounds.1`, shortest first.
    fn collapse_pass(&mut self) {
        let short = self.bounds.1;
        let mut es = self.edge_list(|l| l < short);
        es.sort_unstable_by(|x, y| x.0.total_cmp(&y.0).then((x.1, x.2).cmp(&(y.1, y.2))));
        let version = &self.version;
        self.refused.retain(|&(v, _, x)| version[v as usize] == x);
        let mut gone = vec![false; self.p.len()];
        for (_, a, b) in es {
            if gone[a as usize] || gone[b as usize] {
                continue;
            }
            for (v, w) in [(a, b), (b, a)] {
                if self.collapse(v, w) {
                    gone[v as usize] = true;
                    break;
                }
            }
        }
    }

    /// Collapses `v` onto `w` when that keeps the boundary, leaves no edge
    /// longer than `bounds.0` and no tetrahedron below the quality floor.
    fn collapse(&mut self, v: u32, w: u32) -> bool {
        let key = (v, w, self.version[v as usize]);
        if self.refused.contains(&key) {
            return false;
        }
        let done = self.try_collapse(v, w);
        if !done {
            self.refused.insert(key);
        }
        done
    }

    /// [`Engine::collapse`] without the memory of refusals.
    fn try_collapse(&mut self, v: u32, w: u32) -> bool {
        if self.fixed[v as usize] {
            return false;
        }
        let ball = self.star(v);
        if ball.is_empty() || !ball.iter().any(|&t| self.m.tv[t as usize].contains(&w)) {
            return false;
        }
        let subs = self.m.subfaces_at(&ball, v);
        let along = match self.class(&subs, v) {
            Class::Fixed => return false,
            Class::Interior => true,
            Class::Surface(f) => self.facets(&subs, Some(w)).contains(&f),
            Class::Ridge(f, g) => {
                let fs = self.facets(&subs, Some(w));
                fs.contains(&f) && fs.contains(&g)
            }
        };
        if !along {
            return false;
        }
        let tets: Vec<[u32; 4]> = ball.iter().map(|&t| self.m.tv[t as usize]).collect();
        let (p, met, long, cache) = (&self.p, &self.met, self.bounds.0, &self.cache);
        let mut made = Vec::with_capacity(ball.len());
        // Asked only once every new tetrahedron is positive.
        let accept = |new: &[[u32; 4]]| {
            let floor = ball
                .iter()
                .zip(&tets)
                .map(|(&t, &tv)| cached_quality(cache, (p, met), t, tv))
                .fold(COLLAPSE_FLOOR, f64::min);
            if !new.iter().all(|&t| {
                made.push(quality(p, met, t));
                made[made.len() - 1] >= floor
            }) {
                return false;
            }
            // [`no_long_edge`] of the collapse: the old tetrahedra through
            // `w` are those of the shell of `v w`, so the new edges are
            // those from `w` to the vertices off that shell.
            let mut seen: Vec<u32> = Vec::with_capacity(64);
            for tv in tets.iter().filter(|tv| tv.contains(&w)) {
                seen.extend(tv);
            }
            new.iter().flatten().all(|&x| {
                if seen.contains(&x) {
                    return true;
                }
                seen.push(x);
                let (a, b) = ekey(w, x);
                length(p, met, a, b) <= long
            })
        };
        let Some(ids) = self.m.collapse_edge(&self.p, &ball, &subs, (v, w), accept) else {
            return false;
        };
        self.remember(&ids, &made);
        // Every vertex of the old star: one whose only tetrahedra there
        // held `v w` is in no new one, and its star changed too.
        for v in tets.iter().flatten() {
            self.version[*v as usize] = self.version[*v as usize].wrapping_add(1);
        }
        self.report.collapses += 1;
        self.live -= 1;
        self.m.debug_check(&self.p, "adaptation collapse");
        true
    }

    /// The live tetrahedra (slot, vertices) of quality below `limit`, worst
    /// first (ties by slot).
    fn worst_below(&self, limit: f64) -> Vec<(u32, [u32; 4])> {
        let mut bad: Vec<(f64, u32, [u32; 4])> = self
            .m
            .live_slots()
            .map(|t| (self.slot_q(t), t, self.m.tv[t as usize]))
            .filter(|x| x.0 < limit)
            .collect();
        bad.sort_unstable_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
        bad.into_iter().map(|(_, t, tv)| (t, tv)).collect()
    }

    /// Swaps around the tetrahedra below [`SWAP_BELOW`], worst first.
    fn swap_pass(&mut self) {
        for (t, tv) in self.worst_below(SWAP_BELOW) {
            if self.m.tv[t as usize] != tv {
                continue;
            }
            self.swap(t);
        }
    }

    /// The best swap of tetrahedron `t`: a 2-3 flip of a face or the
    /// removal of an edge, raising the worst quality of the tetrahedra it
    /// replaces.
    fn swap(&mut self, t: u32) -> bool {
        let tv = self.m.tv[t as usize];
        let key = (tv, tv.map(|v| self.version[v as usize]));
        if self.unswappable.get(t as usize) == Some(&key) {
            return false;
        }
        let done = self.try_swap(t);
        if !done {
            if self.unswappable.len() <= t as usize {
                self.unswappable
                    .resize(self.m.tv.len(), ([NONE; 4], [0; 4]));
            }
            self.unswappable[t as usize] = key;
        }
        done
    }

    /// [`Engine::swap`] without the memory of failures.
    fn try_swap(&mut self, t: u32) -> bool {
        let tv = self.m.tv[t as usize];
        let mut best: Option<(f64, Vec<u32>, Vec<[u32; 4]>)> = None;
        let mut consider = |gain: f64, old: Vec<u32>, new: Vec<[u32; 4]>| {
            if best.as_ref().is_none_or(|b| gain > b.0) {
                best = Some((gain, old, new));
            }
        };
        for f in 0..4 {
            if let Some(fl) = self.m.flip23(t, f) {
                let before = self.min_slot_q(&fl.old);
                // The smallest new quality, or the first not above `before`.
                let mut after = f64::INFINITY;
                for &n in &fl.new {
                    after = after.min(self.qual(n));
                    if after <= before + 1e-6 {
                        break;
                    }
                }
                let old =
                    || -> Vec<[u32; 4]> { fl.old.iter().map(|&u| self.m.tv[u as usize]).collect() };
                if after > before + 1e-6
                    && fl.new.iter().all(|&n| positive(&self.p, n))
                    && no_long_edge(&self.p, &self.met, self.bounds.0, &old(), &fl.new)
                {
                    consider(after - before, fl.old, fl.new);
                }
            }
        }
        let mut scratch = Default::default();
        for (i, j) in EDGES {
            if let Some((old, new, gain)) = self.plan_removal(t, (tv[i], tv[j]), &mut scratch) {
                consider(gain, old, new);
            }
        }
        let Some((_, old, new)) = best else {
            return false;
        };
        let mut ids = Vec::new();
        let r = self.m.reg[t as usize];
        self.m.replace(&old, &new, r, &mut ids);
        self.touch(&ids);
        self.report.swaps += 1;
        self.m.debug_check(&self.p, "adaptation swap");
        true
    }

    /// The removal of interior edge `a b` of `t` (every face around it
    /// open) by the edge-removal dynamic program maximising the smallest
    /// quality: the slots, the new tetrahedra and the gain in worst
    /// quality, when positive.
    fn plan_removal(
        &self,
        t: u32,
        (a, b): (u32, u32),
        (tets, r, best, choice): &mut RingScratch,
    ) -> Option<(Vec<u32>, Vec<[u32; 4]>, f64)> {
        let pass = |c: u32, f: usize| self.m.open_face(c, f);
        self.m
            .ring_into(t, (a, b), (MAX_RING, false), pass, (tets, r))?;
        if r.len() < 3 {
            return None;
        }
        let need = self.min_slot_q(tets).max(0.0);
        let (q, new) = ring::max_min(r, (a, b), need, (best, choice), |t| self.qual(t))?;
        if q <= need + 1e-6 {
            return None;
        }
        let old: Vec<[u32; 4]> = tets.iter().map(|&u| self.m.tv[u as usize]).collect();
        if !new.iter().all(|&x| positive(&self.p, x))
            || !no_long_edge(&self.p, &self.met, self.bounds.0, &old, &new)
        {
            return None;
        }
        Some((tets.clone(), new, q - need))
    }

    /// Reshapes the tetrahedra below [`RESHAPE_BELOW`], worst first: each
    /// vertex in turn, until one moves, towards the apex that makes the
    /// tetrahedron regular in its metric over the opposite face
    /// ([`Engine::move_towards`]: only when the worst quality of the
    /// vertex's star rises). The sweeps towards unit edge lengths leave a
    /// few flat tetrahedra (slivers) whose edges all have about unit length.
    fn reshape_pass(&mut self) {
        for (t, tv) in self.worst_below(RESHAPE_BELOW) {
            for i in 0..4 {
                if self.m.tv[t as usize] != tv {
                    break;
                }
                if let Some(x) = self.regular_apex(tv, i) {
                    if self.move_towards(tv[i], Some(x)) {
                        break;
                    }
                }
            }
        }
    }

    /// The point that makes `tv` with corner `i` moved there the regular
    /// tetrahedron of the mean metric of its corners over the opposite face
    /// (that face's mean edge length, on the side of corner `i`).
    fn regular_apex(&self, tv: [u32; 4], i: usize) -> Option<[f64; 3]> {
        let m = Metric::mean(&tv.map(|v| self.met[v as usize]))?;
        // Metric coordinates y = Λ^{1/2} Vᵀ x, back x = V Λ^{-1/2} y.
        let (l, q) = m.eigen();
        let to = |x: [f64; 3]| {
            [0, 1, 2].map(|k| l[k].sqrt() * (q[0][k] * x[0] + q[1][k] * x[1] + q[2][k] * x[2]))
        };
        let y = tv.map(|v| to(self.p[v as usize]));
        let f: Vec<[f64; 3]> = (0..4).filter(|&j| j != i).map(|j| y[j]).collect();
        let c = [0, 1, 2].map(|k| (f[0][k] + f[1][k] + f[2][k]) / 3.0);
        let (u, w) = (sub(f[1], f[0]), sub(f[2], f[0]));
        let mut n = [
            u[1] * w[2] - u[2] * w[1],
            u[2] * w[0] - u[0] * w[2],
            u[0] * w[1] - u[1] * w[0],
        ];
        let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let norm = dot(n, n).sqrt();
        if norm == 0.0 {
            return None;
        }
        let side = if dot(n, sub(y[i], c)) < 0.0 {
            -1.0
        } else {
            1.0
        };
        let edge = |a: [f64; 3], b: [f64; 3]| dot(sub(a, b), sub(a, b)).sqrt();
        let h =
            (2.0f64 / 3.0).sqrt() * (edge(f[0], f[1]) + edge(f[1], f[2]) + edge(f[0], f[2])) / 3.0;
        n = n.map(|x| side * h * x / norm);
        let apex = [0, 1, 2].map(|k| c[k] + n[k]);
        let x = [0, 1, 2].map(|r| (0..3).map(|k| q[r][k] * apex[k] / l[k].sqrt()).sum::<f64>());
        x.iter().all(|x| x.is_finite()).then_some(x)
    }

    /// One sweep of smoothing over the vertices that may move.
    fn smooth_pass(&mut self) {
        for v in 0..self.p.len() as u32 {
            if !self.fixed[v as usize]
                && self
                    .m
                    .vt
                    .get(v as usize)
                    .is_some_and(|&t| t != crate::tet::local::DEAD)
            {
                self.smooth(v);
            }
        }
    }

    /// Moves vertex `v` towards unit metric lengths of its edges (each
    /// edge pulls or pushes by `1 - 1/l`), the full step or a half or a
    /// quarter of it, when that raises the worst quality of its star and
    /// keeps every tetrahedron strictly positive. A vertex on a facet moves
    /// in the facet's plane, one on a ridge along it, and only to a point
    /// exactly on the planes of its subfaces (exact `orient3d`), so that
    /// every region keeps its volume; corners do not move.
    ///
    /// A vertex that failed is not tried again before its star changes
    /// (the same star gives the same answer).
    fn smooth(&mut self, v: u32) -> bool {
        let version = Some(self.version[v as usize]);
        if self.unsmoothable.get(v as usize) == Some(&version) {
            return false;
        }
        let done = self.move_towards(v, None);
        if !done {
            if self.unsmoothable.len() <= v as usize {
                self.unsmoothable.resize(self.p.len(), None);
            }
            self.unsmoothable[v as usize] = version;
        }
        done
    }

    /// [`Engine::smooth`] towards point `target` when given (projected on
    /// the vertex's facet or ridge), else towards unit edge lengths.
    fn move_towards(&mut self, v: u32, target: Option<[f64; 3]>) -> bool {
        let ball = self.star(v);
        if ball.is_empty() {
            return false;
        }
        if self.fixed[v as usize] {
            return false;
        }
        let subs = self.m.subfaces_at(&ball, v);
        let class = self.class(&subs, v);
        if class == Class::Fixed {
            return false;
        }
        let tets: Vec<[u32; 4]> = ball.iter().map(|&t| self.m.tv[t as usize]).collect();
        let home = self.p[v as usize];
        let mut d = [0.0; 3];
        if let Some(x) = target {
            d = sub(x, home);
        } else {
            let mut link: Vec<u32> = Vec::with_capacity(32);
            for &x in tets.iter().flatten() {
                if x != v && !link.contains(&x) {
                    link.push(x);
                }
            }
            link.sort_unstable();
            for &x in &link {
                let l = self.len(v, x);
                let e = sub(self.p[x as usize], home);
                for k in 0..3 {
                    d[k] += e[k] * (1.0 - 1.0 / l.max(1e-3)) / link.len() as f64;
                }
            }
        }
        let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let along = |d: [f64; 3], t: [f64; 3], s: f64| [0, 1, 2].map(|k| d[k] + s * t[k]);
        let d = match class {
            Class::Surface(f) => {
                let n = self.normal[f as usize];
                along(d, n, -dot(d, n))
            }
            Class::Ridge(f, g) => {
                let (a, b) = (self.normal[f as usize], self.normal[g as usize]);
                let t = [
                    a[1] * b[2] - a[2] * b[1],
                    a[2] * b[0] - a[0] * b[2],
                    a[0] * b[1] - a[1] * b[0],
                ];
                let t = t.map(|c| c / dot(t, t).sqrt());
                along([0.0; 3], t, dot(d, t))
            }
            _ => d,
        };
        // The worst tetrahedron (its quality `old`) is tested first: the
        // one a move most often fails to raise.
        let (worst, old) = (ball.iter().map(|&t| self.slot_q(t)).enumerate())
            .fold((0, f64::INFINITY), |b, x| if x.1 < b.1 { x } else { b });
        let order: Vec<usize> = std::iter::once(worst)
            .chain((0..tets.len()).filter(|&i| i != worst))
            .collect();
        let home_m = self.met[v as usize];
        let mut q = vec![0.0; tets.len()];
        for w in [1.0, 0.5, 0.25] {
            let x = [home[0] + w * d[0], home[1] + w * d[1], home[2] + w * d[2]];
            let on_planes = subs.iter().all(|(k, _)| {
                let mut o = k.iter().filter(|&&q| q != v);
                let (Some(&y), Some(&z)) = (o.next(), o.next()) else {
                    return false;
                };
                let (b, c) = (self.p[y as usize], self.p[z as usize]);
                // Four points with one coordinate in common are coplanar
                // (exactly: `orient3d` of them is 0), without the exact
                // arithmetic that certifying a zero otherwise takes.
                (0..3).any(|k| home[k] == b[k] && home[k] == c[k] && home[k] == x[k])
                    || orient3d(&home, &b, &c, &x) == 0.0
            });
            if !on_planes {
                continue;
            }
            self.p[v as usize] = x;
            if let Some(m) = self.field_at(&x) {
                self.met[v as usize] = m;
            }
            if order.iter().all(|&i| {
                positive(&self.p, tets[i]) && {
                    q[i] = self.qual(tets[i]);
                    q[i] > old + 1e-6
                }
            }) {
                self.report.moves += 1;
                self.remember(&ball, &q);
                self.touch(&ball);
                self.m.debug_check(&self.p, "adaptation smoothing");
                return true;
            }
        }
        self.p[v as usize] = home;
        self.met[v as usize] = home_m;
        false
    }

    /// The adapted mesh: live vertices renumbered in order, tetrahedra in
    /// slot order, subfaces once each (outward from the first tetrahedron
    /// met) with their references.
    fn output(mut self, mesh: &TetMesh, input: &Input) -> Adapted<3, 4> {
        let (faces, regions, ridge_pairs) = (&input.faces, &input.regions, &input.ridge_pairs);
        let clock = Instant::now();
        let mut map = vec![NONE; self.p.len()];
        let slots: Vec<u32> = self.m.live_slots().collect();
        for &t in &slots {
            for &v in &self.m.tv[t as usize] {
                map[v as usize] = 0;
            }
        }
        let mut out = TetMesh::default();
        let mut metric = Vec::new();
        for v in 0..self.p.len() {
            if map[v] == NONE {
                continue;
            }
            map[v] = out.points.len() as u32;
            out.points.push(self.p[v]);
            metric.push(self.met[v]);
            out.point_refs
                .push(mesh.point_refs.get(v).copied().unwrap_or(0));
        }
        let with_regions = !mesh.element_refs.is_empty();
        let mut ridge_edges: Vec<(u32, u32)> = Vec::new();
        for &t in &slots {
            let tv = self.m.tv[t as usize];
            out.elements.push(tv.map(|v| map[v as usize]));
            if with_regions {
                out.element_refs
                    .push(regions[self.m.reg[t as usize] as usize]);
            }
            for f in 0..4 {
                let w = self.m.nb[t as usize][f];
                if !self.m.is_sub(t, f) || (w != NONE && w >> 2 < t) {
                    continue;
                }
                let k = fkey(face(tv, f));
                let tri = self.m.ftri.get(&k).copied().unwrap_or(NONE);
                let [a, b, c] = FACET[f].map(|i| map[tv[i] as usize]);
                out.faces.push([a, c, b]);
                out.face_refs
                    .push(faces.get(tri as usize).map_or(0, |x| x.1));
                if !ridge_pairs.is_empty() {
                    for (x, y) in [(k[0], k[1]), (k[1], k[2]), (k[0], k[2])] {
                        ridge_edges.push(ekey(x, y));
                    }
                }
            }
        }
        // Ridges: subface edges between two facets that an input ridge
        // separated.
        ridge_edges.sort_unstable();
        ridge_edges.dedup();
        for (a, b) in ridge_edges {
            let Some(s) = self.m.edge_shell(a, b, MAX_SHELL) else {
                continue;
            };
            let fs = self.facets(&self.m.subfaces_at(&s, a), Some(b));
            if let [f, g] = fs[..] {
                if ridge_pairs.binary_search(&(f, g)).is_ok() {
                    out.ridges.push([map[a as usize], map[b as usize]]);
                }
            }
        }
        let keep = |vs: &[u32]| {
            vs.iter()
                .map(|&v| map[v as usize])
                .filter(|&v| v != NONE)
                .collect()
        };
        out.corners = keep(&mesh.corners);
        out.required = keep(&mesh.required);
        self.report.after = metric_stats(&out.points, &out.elements, &metric);
        self.report
            .phases
            .push(("output", clock.elapsed().as_secs_f64()));
        Adapted {
            mesh: out,
            metric,
            report: self.report,
        }
    }
}

#[cfg(test)]
#[path = "../../tests/common/cube.rs"]
mod cube;

#[cfg(test)]
mod tests {
    use super::*;

    /// The adaptation-level invariants on top of [`DomainMesh::check`]:
    /// each region of the cube has volume 1/2, each side and the
    /// interface area 1 in subfaces of its reference.
    fn invariants(e: &Engine<'_>, input: &Input, what: &str) {
        e.m.check(&e.p).unwrap_or_else(|x| panic!("{what}: {x}"));
        let mut vol = [0.0; 2];
        let mut area = [0.0; 8];
        for t in e.m.live_slots() {
            let tv = e.m.tv[t as usize];
            let p = tv.map(|v| e.p[v as usize]);
            vol[e.m.reg[t as usize] as usize] += crate::tet::quality::volume(&p);
            for f in 0..4 {
                let w = e.m.nb[t as usize][f];
                if e.m.is_sub(t, f) && (w == NONE || w >> 2 > t) {
                    let k = fkey(face(tv, f));
                    let r = input.faces[e.m.ftri[&k] as usize].1;
                    let [a, b, c] = k.map(|v| e.p[v as usize]);
                    let (u, w) = (sub(b, a), sub(c, a));
                    let x = [
                        u[1] * w[2] - u[2] * w[1],
                        u[2] * w[0] - u[0] * w[2],
                        u[0] * w[1] - u[1] * w[0],
                    ];
                    area[r as usize] += 0.5 * (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
                }
            }
        }
        for v in vol {
            assert!((v - 0.5).abs() < 1e-12, "{what}: region volumes {vol:?}");
        }
        for a in &area[1..] {
            assert!((a - 1.0).abs() < 1e-12, "{what}: areas {area:?}");
        }
    }

    /// Splits, collapses, swaps and moves one at a time on the cube with
    /// an interface, the invariants checked after each; boundary vertices
    /// stay on their facets and corners stay.
    #[test]
    fn each_operation_keeps_the_mesh() {
        let mesh = cube::cube(2, true);
        let size = |x: &[f64; 3]| Metric::isotropic(0.15 + 0.2 * x[0]);
        let opt = AdaptOptions::default();
        let (mut e, input) = Engine::new(&mesh, MetricField::Function(&size), &opt).unwrap();
        invariants(&e, &input, "input");
        let (mut splits, mut collapses, mut swaps, mut moves) = (0, 0, 0, 0);
        let (mut side_moves, mut reshapes) = (0, 0);
        for round in 0..3 {
            for (_, a, b) in e.edge_list(|l| l > FINAL.0) {
                if e.m.edge_slot(a, b).is_some() && e.split(a, b) {
                    splits += 1;
                    invariants(&e, &input, "split");
                }
            }
            for (_, a, b) in e.edge_list(|l| l < FINAL.1 * (1.0 + round as f64)) {
                for (v, w) in [(a, b), (b, a)] {
                    if e.m.vt[v as usize] != crate::tet::local::DEAD && e.collapse(v, w) {
                        collapses += 1;
                        invariants(&e, &input, "collapse");
                        break;
                    }
                }
            }
            for t in e.m.live_slots().collect::<Vec<_>>() {
                if e.m.alive(t) && e.qual(e.m.tv[t as usize]) < SWAP_BELOW && e.swap(t) {
                    swaps += 1;
                    invariants(&e, &input, "swap");
                }
            }
            for v in 0..e.p.len() as u32 {
                let home = e.p[v as usize];
                if e.m.vt[v as usize] != crate::tet::local::DEAD && e.smooth(v) {
                    moves += 1;
                    side_moves += usize::from(home.iter().any(|&x| x == 0.0 || x == 1.0));
                    assert_ne!(home, e.p[v as usize]);
                    invariants(&e, &input, "smoothing");
                }
            }
            for t in e.m.live_slots().collect::<Vec<_>>() {
                let tv = e.m.tv[t as usize];
                if !e.m.alive(t) || e.qual(tv) >= RESHAPE_BELOW {
                    continue;
                }
                for i in 0..4 {
                    if let Some(x) = e.regular_apex(tv, i) {
                        if e.m.tv[t as usize] == tv && e.move_towards(tv[i], Some(x)) {
                            reshapes += 1;
                            invariants(&e, &input, "reshaping");
                        }
                    }
                }
            }
        }
        assert!(
            splits > 100 && collapses > 10 && swaps > 0 && moves > 10 && side_moves > 5,
            "{splits} {collapses} {swaps} {moves} {side_moves}"
        );
        assert!(reshapes > 0, "no tetrahedron reshaped");
        // Corners and the vertices of the sides never left them.
        let out = e.output(&mesh, &input);
        for (f, r) in out.mesh.faces.iter().zip(&out.mesh.face_refs) {
            let (axis, at) = match r {
                1..=6 => ((r - 1) as usize / 2, ((r - 1) % 2) as f64),
                _ => (2, 0.5),
            };
            assert!(
                f.iter().all(|&v| out.mesh.points[v as usize][axis] == at),
                "face {f:?} ref {r}"
            );
        }
        // The ridges cover the cube's 12 edges and nothing else.
        let mut length = 0.0;
        for r in &out.mesh.ridges {
            let [a, b] = r.map(|v| out.mesh.points[v as usize]);
            let on = (0..3).filter(|&k| a[k] == b[k] && (a[k] == 0.0 || a[k] == 1.0));
            assert_eq!(on.count(), 2, "ridge {a:?} {b:?}");
            length += (0..3).map(|k| (a[k] - b[k]).abs()).sum::<f64>();
        }
        assert!(out.mesh.ridges.len() >= 24);
        assert!((length - 12.0).abs() < 1e-12, "ridge length {length}");
    }

    /// The regular apex over a face makes the tetrahedron regular in its
    /// metric: here a flat tetrahedron over the unit equilateral triangle,
    /// in a metric that stretches z 4×.
    #[test]
    fn the_regular_apex_makes_a_regular_tetrahedron() {
        let h = 3f64.sqrt() / 2.0;
        let mesh = TetMesh {
            points: vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.5, h, 0.0],
                [0.4, 0.3, 0.001],
            ],
            elements: vec![[0, 1, 2, 3]],
            ..Default::default()
        };
        let m = Metric::from_medit(&[1.0, 0.0, 1.0, 0.0, 0.0, 16.0]).unwrap();
        let opt = AdaptOptions::default();
        let (mut e, _) = Engine::new(&mesh, MetricField::AtVertices(vec![m; 4]), &opt).unwrap();
        assert!(e.qual([0, 1, 2, 3]) < 0.1);
        let x = e.regular_apex([0, 1, 2, 3], 3).unwrap();
        let want = [0.5, h / 3.0, (2f64 / 3.0).sqrt() / 4.0];
        assert!((0..3).all(|k| (x[k] - want[k]).abs() < 1e-12), "{x:?}");
        e.p[3] = x;
        assert!((e.qual([0, 1, 2, 3]) - 1.0).abs() < 1e-12);
    }

    /// A collapse that would move a vertex off its facet, off its ridge or
    /// a corner is refused.
    #[test]
    fn boundary_vertices_collapse_only_within_their_facet() {
        let mesh = cube::cube(2, true);
        let size = |_: &[f64; 3]| Metric::isotropic(10.0);
        let opt = AdaptOptions::default();
        let (mut e, input) = Engine::new(&mesh, MetricField::Function(&size), &opt).unwrap();
        let id = |i: u32, j: u32, k: u32| i + 3 * (j + 3 * k);
        // A corner.
        assert!(!e.collapse(id(0, 0, 0), id(1, 0, 0)));
        // The middle of side x = 0 onto the interior vertex: off its facet.
        assert!(!e.collapse(id(0, 1, 1), id(1, 1, 1)));
        // The middle of a cube edge onto the middle of a side: off its ridge.
        assert!(!e.collapse(id(1, 0, 0), id(1, 1, 0)));
        // Along the ridge, to the corner, it goes.
        assert!(e.collapse(id(1, 0, 0), id(0, 0, 0)));
        invariants(&e, &input, "ridge collapse");
        // The interior vertex onto a corner would flatten the tetrahedra
        // on the sides through it.
        assert!(!e.collapse(id(1, 1, 1), id(0, 0, 0)));
        invariants(&e, &input, "refused collapse");
    }
}
