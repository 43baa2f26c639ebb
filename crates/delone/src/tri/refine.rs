//! Delaunay refinement of a constrained Delaunay triangulation (Ruppert,
//! Chew, Shewchuk): Triangle's `-q` (minimum angle) and `-a` (maximum area).
//!
//! [`refine`] takes a [`Cdt`] (the output of
//! [`constrained_triangulation`](super::constrain::constrained_triangulation))
//! and inserts Steiner points until every triangle meets the bounds:
//!
//! 1. **Encroached subsegments** are split first. A subsegment is encroached
//!    when the apex of a triangle beside it lies strictly inside its
//!    diametral lens: it sees the subsegment at an angle larger than
//!    180° − 2θ for an angle bound θ ≤ 45° (Chew's and Shewchuk's lens), or
//!    larger than 90° (the diametral circle) otherwise — decided in floating
//!    point with an error bound; a tie within rounding counts as not
//!    encroached.
//!    A subsegment with exactly one end at a vertex of the input CDT where
//!    another segment meets it at less than 60° is split on a *concentric
//!    shell* (at a power-of-two distance from that end, the one nearest to
//!    half its length), otherwise at its midpoint; split points
//!    are computed from the ends of the original subsegment, so they stay
//!    within a few ulps of the input segment.
//! 2. **Bad triangles** (minimum angle below the bound, or area above the
//!    global or regional bound) are taken from a bucket queue: skinny ones
//!    before large ones, worst bucket first (64 buckets by sin² of the
//!    smallest angle, quarter octaves of the area ratio); oldest first
//!    within an angle bucket, newest first within an area bucket (it was
//!    just made, so it is in cache; deterministic). Their
//!    circumcentre (or off-centre) is located by a walk from the triangle and
//!    inserted — unless it lies beyond a subsegment (that one is
//!    split instead) or would encroach a subsegment that would become visible
//!    from it (those are split instead; the triangle goes back in the queue).
//! 3. **Small input angles.** A skinny triangle whose shortest edge joins two
//!    vertices on two segments meeting at an input vertex at an angle
//!    smaller than the bound is left alone: its small angle is forced by the
//!    input (splitting it would only crowd the wedge). Such triangles are
//!    listed in [`RefineReport::unfixable`].
//! 4. A Steiner-point budget ([`RefineOptions::max_steiner`], Triangle's `-S`)
//!    stops the refinement; the report says whether every bound was met.
//!
//! # Termination and the budget
//!
//! Every bound is met, or the [`RefineReport`] says which triangles miss it
//! and why ([`RefineReport::met`], [`RefineReport::unfixable`] with an
//! [`UnfixableReason`]):
//!
//! * bounds no mesh can meet are refused before any work
//!   ([`Error::InvalidBound`]): a minimum angle of 60° or more (see
//!   [`RefineOptions::min_angle`]), a NaN or negative one, an area bound that
//!   is not positive;
//! * Ruppert/Chew refinement with off-centres terminates for angle bounds up
//!   to about 33–34° (Triangle's manual says the same of Triangle); above
//!   that it may add points forever. Every run therefore has a Steiner
//!   budget, by default [`default_budget`] (from the input size and the
//!   number of triangles the area bounds ask for, never from the machine).
//!   When it runs out, the refinement stops with a valid constrained
//!   Delaunay triangulation, [`RefineReport::limit_reached`] is set and the
//!   triangles still bad are listed with [`UnfixableReason::SteinerLimit`];
//! * triangles whose small angle is forced by a smaller input angle are
//!   listed with [`UnfixableReason::SmallInputAngle`] (no mesh of that
//!   input meets the bound there).
//!
//! # Parallel refinement
//!
//! When the area bounds predict at least
//! [`RefineOptions::parallel_min_triangles`] triangles, the mesh is refined
//! sequentially to about 1/64 of its final size (area bounds × 64), its
//! triangles are split by recursive coordinate bisection into parts of
//! equal predicted work, each part is refined with the edges between parts
//! fixed (never split; a point beyond or encroaching one is not inserted),
//! the parts are stitched back (Lawson flips across the former part edges
//! restore the constrained Delaunay property), and the triangles left near
//! the part edges are refined sequentially. The number of parts comes from
//! the predicted size alone (2 up to about 400,000 triangles, then one
//! more power of two per doubling, at most 16); [`RefineOptions::threads`]
//! threads run the parts. The result depends on the input and the options
//! only: 1, 2 or 8 threads give the same mesh, on every machine. The
//! triangle count stays within a fraction of a per cent of the one-part
//! refinement on the large shared PSLGs.
//!
//! Insertion is Bowyer–Watson: the cavity of a new point (the triangles whose
//! circumcircle strictly contains it, reached without crossing a subsegment)
//! is found once — for a circumcentre, its boundary subsegments are the ones
//! tested for encroachment — and replaced by a fan. The depth-first cavity
//! search meets the boundary in counterclockwise order, so the fan is linked
//! in sequence; a cavity that is not one simple cycle seen counterclockwise
//! from the new point (possible only through rounding of a split point) is
//! refused and nothing changes. The result is
//! again a constrained Delaunay triangulation (checked by
//! [`check_cdt`](super::constrain::check_cdt)). All orientation and incircle
//! decisions use exact predicates on coordinates scaled by an exact power of
//! two.
//!
//! # References
//! J. Ruppert, *A Delaunay refinement algorithm for quality 2-dimensional mesh
//! generation*, J. Algorithms 18 (1995).
//! L. P. Chew, *Guaranteed-quality mesh generation for curved surfaces*, SoCG 1993.
//! J. R. Shewchuk, *Delaunay refinement algorithms for triangular mesh
//! generation*, Computational Geometry 22 (2002) (concentric shells, small
//! input angles).
//! A. Üngör, *Off-centers: a new type of Steiner points for computing
//! size-optimal quality-guaranteed Delaunay triangulations*, LATIN 2004.
//!
//! # Storage
//!
//! The refinement works on the constrained mesh of `tri::cmesh`: one
//! 32-byte, 32-byte aligned record per triangle, plus a 12-byte side array
//! of subsegment ids read only behind flag bits. `tri::mesh` hands it the
//! CDT's own mesh (no conversion); [`refine`] reads a given [`Cdt`] into
//! one. The output [`Cdt`] is made from the records at the end.

use std::collections::{HashMap, VecDeque};
use std::sync::Arc;

use super::cmesh::{CMesh, Sub, LABEL};
use super::constrain::{Cdt, Subsegment};
use super::topo::{edge, pack, unpack, NEXT, PREV};
use crate::geom::{pow2_scale, scaled};
use crate::{Error, NONE};

mod engine;
mod options;
mod par;

use engine::{angle, angles, dist2, run, shape, Bounds, Crit, Mesh, Parent, SHELL_ANGLE};
pub use options::{
    default_budget, default_threads, memory_estimate, RefineOptions, RefineReport, Refined,
    SegmentSplits, Unfixable, UnfixableReason, UserTest, BUDGET_BASE, BUDGET_MAX, BYTES_PER_POINT,
    PARALLEL_MIN_TRIANGLES,
};

/// Refuses bounds no mesh can meet: a minimum angle that is NaN, negative
/// or 60° or more; an area bound that is NaN, zero or negative.
///
/// Every triangle has an angle of at most 60°, and exactly 60° only when it
/// is equilateral. No equilateral triangle has all three corners at
/// rational coordinates (its area would be both rational, by the shoelace
/// formula, and √3/4 times a rational squared side), and floating-point
/// numbers are rationals: so no mesh delone can output has a minimum angle
/// of 60°, and `-q60` is refused with `-q61`. Every bound below 60° can be
/// met by some domains (one near-equilateral triangle); whether refinement
/// meets it on a given domain is decided by running, under the Steiner
/// budget.
fn check_bounds(options: &RefineOptions) -> Result<(), Error> {
    let bad = |option, value, reason| {
        Err(Error::InvalidBound {
            option,
            value,
            reason,
        })
    };
    match (options.min_angle, options.max_area) {
        (Some(a), _) if a.is_nan() || a < 0.0 => bad("-q", a, "the minimum angle must be a number of degrees, 0 or more"),
        (Some(a), _) if a >= 60.0 => bad("-q", a, "no mesh meets a minimum angle of 60 degrees or more (only equilateral triangles reach 60, and none has corners at floating-point coordinates)"),
        (_, Some(a)) if a.is_nan() || a <= 0.0 => bad("-a", a, "the maximum area must be positive"),
        _ => Ok(()),
    }
}

/// Refines a constrained Delaunay triangulation until every triangle meets
/// the angle and area bounds of `options` (see the [module docs](self)).
///
/// The input points keep their ids; Steiner points follow. Subsegments keep
/// their input segment and marker; the triangles their region, attribute and
/// area bound.
///
/// # Errors
/// [`Error::InvalidCoordinate`] if the mesh has a NaN/infinite point (index
/// given); [`Error::InvalidBound`] for a bound no mesh can meet (see
/// [`RefineOptions::min_angle`], [`RefineOptions::max_area`]). Running out
/// of `u32` vertex ids stops the refinement like the Steiner budget does.
///
/// ```
/// use delone::{model::pslg::Pslg, tri::{constrain::*, refine::*}, Error};
/// let g = Pslg::new(vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]], vec![[0, 1], [1, 2], [2, 0]]);
/// let cdt = constrained_triangulation(&g, CdtOptions::default()).unwrap();
/// let o = RefineOptions { min_angle: Some(60.0), ..Default::default() };
/// assert!(matches!(refine(&cdt, &o), Err(Error::InvalidBound { option: "-q", .. })));
/// ```
///
/// ```
/// use delone::{model::pslg::Pslg, tri::{constrain::*, refine::*}};
/// let g = Pslg::new(vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
///                   vec![[0, 1], [1, 2], [2, 3], [3, 0]]);
/// let cdt = constrained_triangulation(&g, CdtOptions::default()).unwrap();
/// let opts = RefineOptions { min_angle: Some(30.0), max_area: Some(0.01), ..Default::default() };
/// let r = refine(&cdt, &opts).unwrap();
/// assert!(r.report.met);
/// assert!(r.mesh.triangles.len() >= 100);
/// check_cdt(&g, &r.mesh).unwrap();
/// ```
pub fn refine(cdt: &Cdt, options: &RefineOptions) -> Result<Refined, Error> {
    refine_inner(cdt, options, None)
}

/// [`refine`] with a user's test as well (Triangle's `-u`): a triangle is
/// also refined while `unsuitable(corners, area)` says so (corners
/// counterclockwise, in input units). The test must be deterministic for
/// the result to be; one that never accepts small triangles only stops at
/// [`RefineOptions::max_steiner`]. Triangles it still rejects at the end are
/// listed as unfixable.
///
/// # Errors
/// As [`refine`].
///
/// ```
/// use delone::{model::pslg::Pslg, tri::{constrain::*, refine::*}};
/// let g = Pslg::new(vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
///                   vec![[0, 1], [1, 2], [2, 3], [3, 0]]);
/// let cdt = constrained_triangulation(&g, CdtOptions::default()).unwrap();
/// // Small triangles at the corner (0, 0) only.
/// let near = |t: &[[f64; 2]; 3], area: f64| {
///     t.iter().any(|p| p[0] * p[0] + p[1] * p[1] < 0.1) && area > 1e-3
/// };
/// let r = refine_with(&cdt, &RefineOptions::default(), &near).unwrap();
/// assert!(r.report.met);
/// check_cdt(&g, &r.mesh).unwrap();
/// let plain = refine(&cdt, &RefineOptions::default()).unwrap();
/// assert!(r.mesh.triangles.len() > plain.mesh.triangles.len() + 20);
/// ```
pub fn refine_with(
    cdt: &Cdt,
    options: &RefineOptions,
    unsuitable: UserTest<'_>,
) -> Result<Refined, Error> {
    refine_inner(cdt, options, Some(unsuitable))
}

fn refine_inner(
    cdt: &Cdt,
    options: &RefineOptions,
    user: Option<UserTest<'_>>,
) -> Result<Refined, Error> {
    let mut cm = CMesh::from_triangles(Vec::new(), &cdt.triangles, &cdt.neighbors);
    // The bounding subsegments label their edges (`LABEL | k`).
    let mut seg_of: HashMap<(u32, u32), u32> = HashMap::new();
    for (k, s) in cdt.segments.iter().enumerate() {
        if s.bounding {
            seg_of
                .entry((s.v[0].min(s.v[1]), s.v[0].max(s.v[1])))
                .or_insert(k as u32);
        }
    }
    for t in 0..cdt.triangles.len() {
        for e in 0..3 {
            let (a, b) = edge(&cm.tr[t].v, e);
            if let Some(&k) = seg_of.get(&(a.min(b), a.max(b))) {
                cm.set_sub(t, e, LABEL | k);
            }
        }
    }
    drop(seg_of);
    refine_mesh(cdt, cm, options, user)
}

/// Refines `cm`, the mesh of `cdt` (its triangles' `orig` index `cdt`'s
/// columns, the label of a half-edge on a subsegment is `LABEL | k` for
/// `cdt.segments[k]`; the coordinates are `cdt.points`), in place: the
/// pipeline hands over the mesh of [`constrain`](super::constrain::constrain)
/// this way (see [`refine`]).
///
/// # Errors
/// As [`refine`].
pub(super) fn refine_mesh(
    cdt: &Cdt,
    mut cm: CMesh,
    options: &RefineOptions,
    user: Option<UserTest<'_>>,
) -> Result<Refined, Error> {
    crate::geom::check::finite(&cdt.points)?;
    let scale = pow2_scale(crate::geom::max_abs(&cdt.points));
    let sf = scale.0 * scale.1;
    let nfixed = cdt.points.len();
    let nt = cm.tr.len();
    cm.xy = cdt.points.iter().map(|&p| scaled(p, scale)).collect();
    let mut m = Mesh {
        cm,
        vpar: vec![NONE; nfixed],
        nfixed,
        vchains: Arc::new(vec![Vec::new(); nfixed]),
        parents: Arc::new(Vec::new()),
    };
    // Subsegments: the labelled edges, then hull edges (`-c`).
    for t in 0..nt {
        for e in 0..3 {
            let s = m.sub_at(t, e);
            let out = if s == NONE && m.tr[t].a[e] == NONE {
                NONE
            } else if s != NONE && s & LABEL != 0 {
                s & !LABEL
            } else {
                continue;
            };
            let (a, b) = edge(&m.tr[t].v, e);
            let k = m.subs.len() as u32;
            Arc::make_mut(&mut m.parents).push(Parent {
                a,
                b,
                out,
                shell: [false; 2],
            });
            let protected = match options.segment_splits {
                SegmentSplits::All => false,
                SegmentSplits::Interior => m.tr[t].a[e] == NONE,
                SegmentSplits::None => true,
            };
            m.subs.push(Sub {
                v: [a, b],
                he: pack(t, e),
                t: [0.0, 1.0],
                parent: k,
                alive: true,
                stuck: protected,
                protected,
            });
            m.set_sub(t, e, k);
            if m.tr[t].a[e] != NONE {
                let (n, j) = unpack(m.tr[t].a[e]);
                m.set_sub(n, j, k);
            }
        }
    }
    {
        let vchains = Arc::make_mut(&mut m.vchains);
        for (k, par) in m.parents.iter().enumerate() {
            vchains[par.a as usize].push(k as u32);
            vchains[par.b as usize].push(k as u32);
        }
    }
    for k in 0..m.parents.len() {
        let par = m.parents[k];
        for (i, (z, o)) in [(par.a, par.b), (par.b, par.a)].into_iter().enumerate() {
            let shell = m.vchains[z as usize].iter().any(|&j| {
                let q = m.parents[j as usize];
                let o2 = if q.a == z { q.b } else { q.a };
                j as usize != k && angle(m.p(z), m.p(o), m.p(o2)) < SHELL_ANGLE
            });
            Arc::make_mut(&mut m.parents)[k].shell[i] = shell;
        }
    }
    check_bounds(options)?;
    let angle = options.min_angle.unwrap_or(0.0);
    let crit = Crit {
        user,
        b: Bounds {
            scale,
            sin2: angle.to_radians().sin().powi(2),
            angle,
            area2: options
                .max_area
                .filter(|a| *a > 0.0)
                .map_or(f64::INFINITY, |a| 2.0 * a * sf * sf),
            regional: options.regional_areas,
            // 0.9 of the distance giving the bound exactly: measured at 34° on
            // face, double_hex(2, 3), la and A.poly (with first-in-first-out
            // angle buckets), it keeps the counts within 10% of Triangle's
            // (0.95 let cascades of small triangles start on double_hex and la
            // at 34°; the count is chaotic in this factor: la at 34° cascades
            // with 0.455 and gives twice the triangles with 0.445).
            off: if options.off_centers && angle > 0.0 {
                0.45 / (0.5 * angle.to_radians()).tan()
            } else {
                0.0
            },
            s2: sf * sf,
            coarse: 1.0,
        },
    };
    // Diametral lens: with an angle bound θ ≤ 45°, a subsegment is encroached
    // by a vertex that sees it at more than 180° − 2θ (Chew; Shewchuk).
    if angle > 0.0 && angle <= 45.0 {
        m.cos2 = (180.0 - 2.0 * angle).to_radians().cos().powi(2);
    }
    let limit = options
        .max_steiner
        .unwrap_or_else(|| default_budget(nfixed, par::predicted(&m, &crit, &cdt.max_areas)));
    let mut report = RefineReport {
        steiner_budget: limit,
        ..RefineReport::default()
    };
    let threads = options.threads.clamp(1, 64);
    let parts = par::parts_for(&m, &crit, &cdt.max_areas, options);
    let quality = if parts > 1 {
        par::refine_parallel(
            &mut m,
            &crit,
            &cdt.max_areas,
            options,
            parts,
            threads,
            limit,
            &mut report,
        )
    } else {
        m.reserve_for_areas(&crit, &cdt.max_areas, limit, None);
        let mut steiner = 0;
        run(
            &mut m,
            &crit,
            &cdt.max_areas,
            options,
            limit,
            &mut steiner,
            &mut report,
            None,
            None,
        )
    };
    // Structure only: on some degenerate inputs (delone-fuzz cdt_poly findings)
    // an edge is left not locally Delaunay.
    debug_assert_eq!(m.check(false), Ok(()), "refined mesh");
    report.cavity_triangles = m.replaced;
    let restricted = options.segment_splits != SegmentSplits::All;
    let left = if options.conforming_delaunay {
        m.scan_encroached(true, &mut VecDeque::new())
    } else {
        0
    };
    let mut r = finish(cdt, m, &crit, scale, restricted, report, threads);
    if !quality {
        for u in &mut r.report.unfixable {
            if u.reason == UnfixableReason::Precision {
                u.reason = UnfixableReason::ConformingDelaunay;
            }
        }
    }
    r.report.encroached_subsegments = left;
    r.report.met &= left == 0;
    Ok(r)
}

/// The extreme angles and the bad triangles among `triangles[from..]`
/// (see [`finish`]).
struct Assessed {
    /// (sin² of the smallest angle, triangle), first of the smallest.
    lo: (f64, usize),
    /// (cosine of the largest angle, triangle), first of the smallest.
    hi: (f64, usize),
    met: bool,
    unfixable: Vec<Unfixable>,
}

fn assess(
    m: &Mesh,
    crit: &Crit,
    triangles: &[[u32; 3]],
    max_areas: &[f64],
    from: usize,
    limit_reached: bool,
    restricted: bool,
) -> Assessed {
    let mut unfixable = Vec::new();
    let mut lo_t = (f64::INFINITY, usize::MAX);
    let mut hi_t = (f64::INFINITY, usize::MAX);
    let mut met = true;
    for (t, v) in triangles.iter().enumerate().skip(from) {
        let (a, b, c) = (m.p(v[0]), m.p(v[1]), m.p(v[2]));
        let (s2, d, k) = shape(a, b, c);
        if s2 < lo_t.0 {
            lo_t = (s2, t);
        }
        let l = [dist2(b, c), dist2(c, a), dist2(a, b)];
        let j = if l[0] >= l[1] && l[0] >= l[2] {
            0
        } else if l[1] >= l[2] {
            1
        } else {
            2
        };
        let (x, y) = (l[NEXT[j]], l[PREV[j]]);
        let cos = (x + y - l[j]) / (2.0 * (x * y).sqrt());
        if cos < hi_t.0 {
            hi_t = (cos, t);
        }
        let mut abound = crit.area2;
        if crit.regional && max_areas[t] > 0.0 {
            abound = abound.min(2.0 * max_areas[t] * crit.s2);
        }
        let too_big = d > abound;
        let lo = if s2 < crit.sin2 || too_big {
            angles(a, b, c).iter().copied().fold(180.0f64, f64::min)
        } else {
            180.0
        };
        let angle_bad = s2 < crit.sin2 && lo < crit.angle;
        let user_bad = !(too_big || angle_bad)
            && crit
                .user
                .is_some_and(|f| f(&crit.input(m, v), 0.5 * d / crit.s2));
        if !(too_big || angle_bad || user_bad) {
            continue;
        }
        met = false;
        let (u, w) = edge(v, k);
        let reason = match m.small_angle_apex(u, w, crit.angle) {
            Some((apex, input_angle)) if d <= abound && !user_bad => {
                UnfixableReason::SmallInputAngle { apex, input_angle }
            }
            _ if limit_reached => UnfixableReason::SteinerLimit,
            _ if restricted => UnfixableReason::NoSegmentSplits,
            _ => UnfixableReason::Precision,
        };
        unfixable.push(Unfixable {
            triangle: t as u32,
            min_angle: lo,
            area: 0.5 * d / crit.s2,
            reason,
        });
    }
    Assessed {
        lo: lo_t,
        hi: hi_t,
        met,
        unfixable,
    }
}

/// Builds the output mesh and the final statistics.
fn finish(
    cdt: &Cdt,
    m: Mesh,
    crit: &Crit,
    scale: (f64, f64),
    restricted: bool,
    mut report: RefineReport,
    threads: usize,
) -> Refined {
    let mut m = m;
    // What the output no longer needs goes first (peak memory).
    m.sides = Vec::new();
    m.cav = Vec::new();
    m.bnd = Vec::new();
    m.fan = Vec::new();
    m.stack = Vec::new();
    let nt = m.tr.len();
    let mut points = Vec::with_capacity(m.xy.len());
    points.extend_from_slice(&cdt.points);
    points.extend(
        m.xy[m.nfixed..]
            .iter()
            .map(|p| [p[0] / scale.1 / scale.0, p[1] / scale.1 / scale.0]),
    );
    // One pass over the triangle records for the vertices, neighbours and
    // input triangles; the records go before the outputs read from the
    // input triangles are made (peak memory).
    let mut triangles: Vec<[u32; 3]> = Vec::with_capacity(nt);
    let mut neighbors: Vec<[u32; 3]> = Vec::with_capacity(nt);
    let mut origs: Vec<u32> = Vec::with_capacity(nt);
    for tri in &m.tr {
        triangles.push(tri.v);
        neighbors.push(
            tri.a
                .map(|x| if x == NONE { NONE } else { unpack(x).0 as u32 }),
        );
        origs.push(tri.orig);
    }
    m.tr = Vec::new();
    let regions = origs.iter().map(|&o| cdt.regions[o as usize]).collect();
    let attributes = origs.iter().map(|&o| cdt.attributes[o as usize]).collect();
    let max_areas: Vec<f64> = origs.iter().map(|&o| cdt.max_areas[o as usize]).collect();
    drop(origs);
    let mut segments = Vec::new();
    for s in m.subs.iter().filter(|s| s.alive) {
        let par = m.parents[s.parent as usize];
        if par.out == NONE {
            continue;
        }
        let src = cdt.segments[par.out as usize];
        segments.push(Subsegment {
            v: s.v,
            bounding: true,
            ..src
        });
    }
    segments.extend(cdt.segments.iter().filter(|s| !s.bounding).copied());
    // The extreme angles: the triangles with the smallest sin² of the
    // smallest angle and the smallest cosine of the largest angle, measured
    // exactly at the end (atan2 only there). In `threads` chunks, combined
    // in order (the same result for any number of chunks).
    let limit_reached = report.limit_reached;
    let chunks = if threads > 1 && crit.user.is_none() && triangles.len() >= 1 << 13 {
        threads
    } else {
        1
    };
    let step = triangles.len().div_ceil(chunks).max(1);
    // Chunk `k`: the triangles from `k * step` (`assess` reads those before
    // for context).
    let chunk = |crit: &Crit, k: usize| {
        let end = ((k + 1) * step).min(triangles.len());
        let lo = (k * step).min(end);
        assess(
            &m,
            crit,
            &triangles[..end],
            &max_areas,
            lo,
            limit_reached,
            restricted,
        )
    };
    let b = crit.b;
    let plain = |k: usize| chunk(&Crit { user: None, b }, k);
    let parts: Vec<Assessed> = if chunks == 1 {
        vec![chunk(crit, 0)]
    } else {
        crate::par::run_dynamic(chunks, (0..chunks).collect(), |_, k| plain(k))
            .into_iter()
            .enumerate()
            .map(|(k, p)| p.unwrap_or_else(|| plain(k)))
            .collect()
    };
    let mut lo_t = (f64::INFINITY, usize::MAX);
    let mut hi_t = (f64::INFINITY, usize::MAX);
    let mut met = true;
    for p in parts {
        if p.lo.0 < lo_t.0 {
            lo_t = p.lo;
        }
        if p.hi.0 < hi_t.0 {
            hi_t = p.hi;
        }
        met &= p.met;
        report.unfixable.extend(p.unfixable);
    }
    let ang = |t: usize| {
        let v = triangles[t];
        angles(m.p(v[0]), m.p(v[1]), m.p(v[2]))
    };
    report.min_angle = if lo_t.1 == usize::MAX {
        180.0
    } else {
        ang(lo_t.1).iter().copied().fold(180.0f64, f64::min)
    };
    report.max_angle = if hi_t.1 == usize::MAX {
        0.0
    } else {
        ang(hi_t.1).iter().copied().fold(0.0f64, f64::max)
    };
    if triangles.is_empty() {
        report.min_angle = 0.0;
    }
    report.met = met;
    Refined {
        mesh: Cdt {
            points,
            triangles,
            neighbors,
            regions,
            attributes,
            max_areas,
            segments,
            vertex_map: cdt.vertex_map.clone(),
            report: cdt.report.clone(),
        },
        report,
    }
}
