//! Parallel refinement in spatial parts (see the parent module's docs,
//! "Parallel refinement").
//!
//! 1. **Coarse stage** (one thread): the mesh is refined with every area
//!    bound multiplied by [`COARSE_FACTOR`] (the angle bound unchanged), to
//!    about 1/[`COARSE_FACTOR`] of the predicted final size.
//! 2. **Partition**: the coarse triangles are split into `P` parts of about
//!    equal predicted work (area over the area bound) by recursive
//!    bisection of their centroids along the longer side of the parts'
//!    bounding boxes (ties by triangle id): geometry only, never timing.
//!    `P` ([`parts_for`]) comes from the predicted output size alone: the
//!    smallest power of two from 2 to [`MAX_PARTS`] that leaves at most
//!    [`PART_TRIANGLES`] to a part.
//! 3. **Parts** (`std::thread::scope`; part 0 in the mesh itself, the
//!    others in copies of the coarse mesh, handed out in turn to the
//!    threads, so that one thread runs them all one after the other): each
//!    part refines from its own triangles, with the edges between parts
//!    (*cuts*) as subsegments that may not be split and have nothing across
//!    them: a cavity never crosses one, so a part only changes its own
//!    triangles. A point beyond a cut, or encroaching one, is not inserted:
//!    the triangle is left for the finish (so no slivers pile up along the
//!    cuts).
//! 4. **Stitch** (the calling thread, as the parts arrive): each part's new
//!    vertices, triangles and subsegments are appended in part order,
//!    renumbered; then the cuts are linked again (ordinary edges, or the
//!    input subsegment they carry), and Lawson flips from them restore the
//!    constrained Delaunay property.
//! 5. **Finish** (one thread): the ordinary refinement loop, seeded with
//!    the triangles the parts left, those beside the cuts and those the
//!    flips made.
//!
//! A part's result depends only on the coarse mesh and its number, and the
//! stitch takes the parts in order: the output depends only on the input
//! and the options, never on the number of threads or their timing.
//!
//! No shared mutable state beyond the counter that hands out the parts and
//! the channel that brings them back. A predicted size below
//! [`RefineOptions::parallel_min_triangles`] (50,000 by default) is the
//! sequential code path.

use std::sync::atomic::{AtomicUsize, Ordering};

use super::engine::{run, Bounds, Crit, Mesh};
use super::options::{RefineOptions, RefineReport};
use crate::tri::cmesh::FLAGS;
use crate::tri::cmesh::{Sub, Tri};
use crate::tri::topo::{edge, pack, unpack};
use crate::NONE;

/// Area bounds are multiplied by this in the coarse stage.
const COARSE_FACTOR: f64 = 64.0;

/// Predicted triangles per unit of (area / area bound).
const PER_RATIO: f64 = 1.6;

/// Predicted output triangles per part: the part count is the smallest
/// power of two, at least 2, that leaves at most this many to a part (on
/// la.poly at `-q30a0.0005`, 1.5 M triangles, 8 parts take less time than
/// 2 or 4 even on one thread: a part's working set stays in cache).
pub(super) const PART_TRIANGLES: f64 = 200_000.0;

/// At most this many parts.
pub(super) const MAX_PARTS: usize = 16;

/// Parts to refine in (1: the sequential path), from the input and the
/// options only, never from the thread count or the machine.
pub(super) fn parts_for(
    m: &Mesh,
    crit: &Crit,
    max_areas: &[f64],
    options: &RefineOptions,
) -> usize {
    if options.conforming_delaunay || options.max_steiner.is_some() || crit.user.is_some() {
        return 1;
    }
    let n = predicted(m, crit, max_areas);
    let min = options.parallel_min_triangles;
    if min > 0 && n < min as f64 {
        return 1;
    }
    let mut parts = 2;
    while parts < MAX_PARTS && n > parts as f64 * PART_TRIANGLES {
        parts *= 2;
    }
    parts
}

/// Predicted number of output triangles (from the area bounds only).
pub(super) fn predicted(m: &Mesh, crit: &Crit, max_areas: &[f64]) -> f64 {
    PER_RATIO
        * (0..m.tr.len())
            .map(|t| m.area_ratio(crit, max_areas, t))
            .sum::<f64>()
}

/// An edge between two parts: half-edge `(t, e)` in part `pt`, its twin
/// `(n, j)` in part `pn`, and the input subsegment it carries (or `NONE`).
#[derive(Clone, Copy)]
struct Cut {
    t: usize,
    e: usize,
    n: usize,
    j: usize,
    pt: u32,
    pn: u32,
    sub: u32,
}

/// What part `p` made: the refined copy of the coarse mesh, its report
/// and the triangles it gave up on.
struct PartOut {
    pm: Mesh,
    report: RefineReport,
    drops: Vec<u32>,
}

/// The parts 1.. of a parallel refinement, handed out in turn to workers.
struct Job<'a> {
    /// The coarse mesh (each part refines a copy).
    base: &'a Mesh,
    bounds: Bounds,
    max_areas: &'a [f64],
    options: &'a RefineOptions,
    /// Steiner budget of each part.
    share: usize,
    cuts: &'a [Cut],
    /// The coarse triangles of each part.
    lists: &'a [Vec<u32>],
    next: AtomicUsize,
    parts: usize,
}

impl Job<'_> {
    /// The next part nobody has taken.
    fn take(&self) -> Option<usize> {
        let p = self.next.fetch_add(1, Ordering::Relaxed);
        (p < self.parts).then_some(p)
    }

    /// Refines part `p` in a copy of the coarse mesh.
    fn part(&self, p: usize) -> PartOut {
        let list = &self.lists[p];
        let mut pm = self.base.clone();
        cut_part(&mut pm, p as u32, self.cuts);
        let crit = Crit {
            user: None,
            b: self.bounds,
        };
        pm.reserve_for_areas(&crit, self.max_areas, usize::MAX, Some(list));
        let mut report = RefineReport::default();
        let mut steiner = 0usize;
        let mut drops = Vec::new();
        run(
            &mut pm,
            &crit,
            self.max_areas,
            self.options,
            self.share,
            &mut steiner,
            &mut report,
            Some(list),
            Some(&mut drops),
        );
        PartOut { pm, report, drops }
    }
}

/// Refines `m` in `parts` parts run by `threads` threads; returns as
/// [`run`] does. The Steiner budget `limit` is shared: the coarse stage
/// spends from it, each part gets an equal share of what is left, the
/// finish the rest (so the result depends only on the input, the options
/// and `parts`, never on `threads`).
#[allow(clippy::too_many_arguments)]
pub(super) fn refine_parallel(
    m: &mut Mesh,
    crit: &Crit,
    max_areas: &[f64],
    options: &RefineOptions,
    parts: usize,
    threads: usize,
    limit: usize,
    report: &mut RefineReport,
) -> bool {
    // 1. Coarse stage.
    let coarse = Crit {
        b: Bounds {
            coarse: COARSE_FACTOR,
            ..crit.b
        },
        ..*crit
    };
    let mut steiner = 0usize;
    run(
        m,
        &coarse,
        max_areas,
        options,
        limit,
        &mut steiner,
        report,
        None,
        None,
    );
    if report.limit_reached {
        return true;
    }

    // 2. Partition.
    let nt0 = m.tr.len();
    let nv0 = m.xy.len();
    let ns0 = m.subs.len();
    let mut part = vec![0u32; nt0];
    {
        let cen: Vec<[f64; 2]> =
            m.tr.iter()
                .map(|t| {
                    let (a, b, c) = (m.p(t.v[0]), m.p(t.v[1]), m.p(t.v[2]));
                    [(a[0] + b[0] + c[0]) / 3.0, (a[1] + b[1] + c[1]) / 3.0]
                })
                .collect();
        let w: Vec<f64> = (0..nt0)
            .map(|t| m.area_ratio(crit, max_areas, t).max(0.05))
            .collect();
        let mut ids: Vec<u32> = (0..nt0 as u32).collect();
        bisect(&mut ids, &cen, &w, parts, 0, &mut part);
    }
    let mut cuts = Vec::new();
    for t in 0..nt0 {
        for e in 0..3 {
            let x = m.tr[t].a[e];
            if x == NONE {
                continue;
            }
            let (n, j) = unpack(x);
            if t < n && part[t] != part[n] {
                cuts.push(Cut {
                    t,
                    e,
                    n,
                    j,
                    pt: part[t],
                    pn: part[n],
                    sub: m.sub_at(t, e),
                });
            }
        }
    }
    let np = cuts.len();
    let mut lists: Vec<Vec<u32>> = vec![Vec::new(); parts];
    for (t, &p) in part.iter().enumerate() {
        lists[p as usize].push(t as u32);
    }
    // The part that owns each coarse subsegment (`NONE`: on a cut).
    let mut owner: Vec<u32> = m
        .subs
        .iter()
        .map(|s| {
            let (t, _) = unpack(s.he);
            if s.he == NONE || t >= nt0 {
                NONE
            } else {
                part[t]
            }
        })
        .collect();
    for c in &cuts {
        if c.sub != NONE {
            owner[c.sub as usize] = NONE;
        }
    }

    // 3. Parts: part 0 in `m` itself, the others in copies of the coarse
    // mesh, taken in turn by `threads` workers (the main thread, after part
    // 0, is one of them). A part's result depends on the coarse mesh and
    // its number only, so who runs it does not matter.
    // 4. Stitch: the main thread appends each part to `m` in part order as
    // soon as it and the parts before it are done (the copies are dropped
    // one by one, so few are alive at a time).
    let base = m.clone();
    cut_part(m, 0, &cuts);
    // Room for everything (untouched capacity costs no resident memory):
    // the stitch then appends without moving the arrays.
    m.reserve_for_areas(crit, max_areas, usize::MAX, None);
    let share = limit.saturating_sub(steiner) / parts;
    let job = Job {
        base: &base,
        bounds: crit.b,
        max_areas,
        options,
        share,
        cuts: &cuts,
        lists: &lists,
        next: AtomicUsize::new(1),
        parts,
    };
    let mut drops = Vec::new();
    // Merged half-edges of each cut: [side of `t`, side of `n`].
    let mut cut_he = vec![[NONE; 2]; np];
    let stitch = Stitch {
        cuts: &cuts,
        lists: &lists,
        owner: &owner,
        nt0,
        nv0,
        ns0,
    };
    let stop = crate::progress::stop_flag();
    std::thread::scope(|sc| {
        let (tx, rx) = std::sync::mpsc::channel();
        let handles: Vec<_> = (1..threads.clamp(1, parts))
            .map(|_| {
                let (tx, stop) = (tx.clone(), stop.clone());
                let job = &job;
                sc.spawn(move || {
                    crate::progress::stoppable(stop, || {
                        while let Some(p) = job.take() {
                            if tx.send((p, job.part(p))).is_err() {
                                return;
                            }
                        }
                    })
                })
            })
            .collect();
        drop(tx);
        run(
            m,
            crit,
            max_areas,
            options,
            steiner + share,
            &mut steiner,
            report,
            Some(&lists[0]),
            Some(&mut drops),
        );
        for (j, c) in cuts.iter().enumerate() {
            let he = m.subs[ns0 + j].he;
            if c.pt == 0 {
                cut_he[j][0] = he;
            } else if c.pn == 0 {
                cut_he[j][1] = he;
            }
        }
        let mut pending: Vec<Option<PartOut>> = (0..parts).map(|_| None).collect();
        for p in 1..parts {
            while pending[p].is_none() {
                let (k, out) = match job.take() {
                    Some(k) => (k, job.part(k)),
                    None => match rx.recv() {
                        Ok(x) => x,
                        // A worker stopped without its part: it panicked.
                        Err(_) => break,
                    },
                };
                pending[k] = Some(out);
            }
            let Some(out) = pending[p].take() else {
                break;
            };
            steiner += stitch.part(m, p, out, &mut cut_he, &mut drops, report);
        }
        for h in handles {
            h.join().unwrap_or_else(|e| std::panic::resume_unwind(e));
        }
    });
    drop(base);
    // The cut subsegments of part 0 are gone.
    for s in &mut m.subs[ns0..ns0 + np] {
        s.alive = false;
        s.he = NONE;
    }
    let mut stack = Vec::with_capacity(np);
    for (j, c) in cuts.iter().enumerate() {
        let [h0, h1] = cut_he[j];
        let (t0, e0) = unpack(h0);
        let (t1, e1) = unpack(h1);
        m.tr[t0].a[e0] = h1;
        m.tr[t1].a[e1] = h0;
        m.set_sub(t0, e0, c.sub);
        m.set_sub(t1, e1, c.sub);
        if c.sub != NONE {
            m.subs[c.sub as usize].he = h0;
        } else {
            stack.push(m.half(t0, e0));
        }
        drops.extend([t0 as u32, t1 as u32]);
    }
    m.restore_delaunay(&mut stack, &mut drops);
    debug_assert_eq!(m.check(false), Ok(()), "stitched mesh");

    // 5. Finish: the triangles the parts gave up on, those beside the cuts
    // and those the flips made.
    run(
        m,
        crit,
        max_areas,
        options,
        limit,
        &mut steiner,
        report,
        Some(&drops),
        None,
    )
}

/// What the stitch needs to know of the partition.
struct Stitch<'a> {
    cuts: &'a [Cut],
    lists: &'a [Vec<u32>],
    /// The part owning each coarse subsegment (`NONE`: on a cut).
    owner: &'a [u32],
    /// Triangles, vertices and subsegments of the coarse mesh.
    nt0: usize,
    nv0: usize,
    ns0: usize,
}

impl Stitch<'_> {
    /// Appends part `p` to `m`: its coarse triangles and subsegments are
    /// copied over `m`'s, its new vertices, triangles and subsegments
    /// appended and renumbered; its sides of the cuts go in `cut_he`, the
    /// triangles it gave up on in `drops`. Returns its Steiner points.
    fn part(
        &self,
        m: &mut Mesh,
        p: usize,
        out: PartOut,
        cut_he: &mut [[u32; 2]],
        drops: &mut Vec<u32>,
        report: &mut RefineReport,
    ) -> usize {
        let PartOut {
            pm,
            report: rep,
            drops: dr,
        } = out;
        let (nt0, nv0, ns0, np) = (self.nt0, self.nv0, self.ns0, self.cuts.len());
        let (vo, to, so) = (m.xy.len(), m.tr.len(), m.subs.len());
        let rv = |x: u32| {
            if (x as usize) < nv0 {
                x
            } else {
                (x as usize - nv0 + vo) as u32
            }
        };
        let rt = |x: usize| if x < nt0 { x } else { x - nt0 + to };
        let ra = |x: u32| {
            if x == NONE {
                NONE
            } else {
                let (t, e) = unpack(x);
                pack(rt(t), e)
            }
        };
        let rs = |x: u32| {
            let x = x as usize;
            if x < ns0 {
                x as u32
            } else if x < ns0 + np {
                NONE
            } else {
                (x - ns0 - np + so) as u32
            }
        };
        let copy = |src: &Tri, sd: &[u32; 3]| {
            let mut flags = src.mark & FLAGS;
            let mut sides = [NONE; 3];
            for (e, side) in sides.iter_mut().enumerate() {
                if flags >> e & 1 != 0 {
                    let x = rs(sd[e]);
                    if x == NONE {
                        flags &= !(1 << e);
                    } else {
                        *side = x;
                    }
                }
            }
            (
                Tri {
                    v: src.v.map(rv),
                    a: src.a.map(ra),
                    orig: src.orig,
                    mark: flags,
                },
                sides,
            )
        };
        for &t in &self.lists[p] {
            let t = t as usize;
            let (tri, sd) = copy(&pm.tr[t], &pm.sides[t]);
            m.tr[t] = tri;
            m.sides[t] = sd;
        }
        for t in nt0..pm.tr.len() {
            let (tri, sd) = copy(&pm.tr[t], &pm.sides[t]);
            m.tr.push(tri);
            m.sides.push(sd);
        }
        for (j, c) in self.cuts.iter().enumerate() {
            let he = ra(pm.subs[ns0 + j].he);
            if c.pt == p as u32 {
                cut_he[j][0] = he;
            } else if c.pn == p as u32 {
                cut_he[j][1] = he;
            }
        }
        for (s, &o) in self.owner.iter().enumerate() {
            if o == p as u32 {
                let x = pm.subs[s];
                m.subs[s] = Sub { he: ra(x.he), ..x };
            }
        }
        for x in &pm.subs[ns0 + np..] {
            m.subs.push(Sub {
                v: x.v.map(rv),
                he: ra(x.he),
                ..*x
            });
        }
        m.xy.extend_from_slice(&pm.xy[nv0..]);
        m.vpar.extend_from_slice(&pm.vpar[nv0..]);
        m.replaced += pm.replaced;
        drops.extend(dr.iter().map(|&t| rt(t as usize) as u32));
        report.segment_splits += rep.segment_splits;
        report.circumcenters += rep.circumcenters;
        report.limit_reached |= rep.limit_reached;
        report.rejected_circumcenters += rep.rejected_circumcenters;
        rep.segment_splits + rep.circumcenters
    }
}

/// Makes the cuts of part `p` protected subsegments of `pm` (ids from
/// `pm.subs.len()`, one per cut, dead where the cut does not touch `p`)
/// with no neighbour across.
fn cut_part(pm: &mut Mesh, p: u32, cuts: &[Cut]) {
    pm.subs.reserve(cuts.len());
    for c in cuts {
        let (t, e, alive) = if c.pt == p {
            (c.t, c.e, true)
        } else if c.pn == p {
            (c.n, c.j, true)
        } else {
            (c.t, c.e, false)
        };
        let k = pm.subs.len() as u32;
        let (a, b) = edge(&pm.tr[t].v, e);
        pm.subs.push(Sub {
            v: [a, b],
            he: if alive { pack(t, e) } else { NONE },
            t: [0.0, 1.0],
            parent: 0,
            alive,
            stuck: true,
            protected: false,
        });
        if alive {
            pm.tr[t].a[e] = NONE;
            pm.set_sub(t, e, k);
        }
    }
}

/// Splits `ids` into `parts` parts of about equal weight `w`, numbered from
/// `first`, by recursive bisection along the longer side of the bounding box
/// of their centroids `cen`.
fn bisect(ids: &mut [u32], cen: &[[f64; 2]], w: &[f64], parts: usize, first: u32, out: &mut [u32]) {
    if parts <= 1 || ids.len() < 2 {
        for &t in ids.iter() {
            out[t as usize] = first;
        }
        return;
    }
    let [lo, hi] = crate::geom::bbox(ids.iter().map(|&t| &cen[t as usize]));
    let axis = usize::from(hi[1] - lo[1] > hi[0] - lo[0]);
    ids.sort_unstable_by(|&a, &b| {
        cen[a as usize][axis]
            .total_cmp(&cen[b as usize][axis])
            .then(a.cmp(&b))
    });
    let total: f64 = ids.iter().map(|&t| w[t as usize]).sum();
    let left = parts / 2;
    let target = total * left as f64 / parts as f64;
    let mut acc = 0.0;
    let mut k = 0;
    while k < ids.len() - 1 && acc + w[ids[k] as usize] <= target {
        acc += w[ids[k] as usize];
        k += 1;
    }
    let k = k.max(1);
    let (a, b) = ids.split_at_mut(k);
    bisect(a, cen, w, left, first, out);
    bisect(b, cen, w, parts - left, first + left as u32, out);
}
