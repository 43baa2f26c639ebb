//! Parallel refinement in spatial parts (see the parent module's docs,
//! "Parallel refinement").
//!
//! 1. **Coarse stage** (one thread): the mesh is refined with every area
//!    bound multiplied by [`COARSE_FACTOR`] (the angle bound unchanged), to
//!    about 1/[`COARSE_FACTOR`] of the predicted final size.
//! 2. **Partition**: the coarse triangles are split into `T` parts of about
//!    equal predicted work (area over the area bound) by recursive
//!    bisection of their centroids along the longer side of the parts'
//!    bounding boxes (ties by triangle id): geometry only, never timing.
//! 3. **Parts** (one thread each, `std::thread::scope`; part 0 in the mesh
//!    itself, the others in copies of the coarse mesh): each part refines
//!    from its own triangles, with the edges between parts (*cuts*) as
//!    subsegments that may not be split and have nothing across them: a
//!    cavity never crosses one, so a part only changes its own triangles. A
//!    point beyond a cut, or encroaching one, is not inserted: the triangle
//!    is left for the finish (so no slivers pile up along the cuts).
//! 4. **Stitch** (one thread): the other parts' new vertices, triangles and
//!    subsegments are appended in part order, renumbered, the cuts linked
//!    again (ordinary edges, or the input subsegment they carry), and
//!    Lawson flips from them restore the constrained Delaunay property.
//! 5. **Finish** (one thread): the ordinary refinement loop, seeded with
//!    the triangles the parts left, those beside the cuts and those the
//!    flips made (on la.poly at `-q30a0.001`, 2 parts: 51 cuts, 2,234
//!    triangles to look at, 1,500 points inserted, out of 368,000).
//!
//! The output depends only on the input, the options and `T`.
//!
//! No shared mutable state and no locks. One part (`T = 1`), or a predicted
//! size below [`RefineOptions::parallel_min_triangles`] (50,000 by default),
//! is the sequential code path, bit for bit.

use delone_predicates::incircle;

use super::{run, Crit, Mesh, RefineOptions, RefineReport, Sub, Tri, FLAGS};
use crate::tri::topo::{edge, pack, unpack, NEXT, PREV};
use crate::NONE;

/// Area bounds are multiplied by this in the coarse stage.
const COARSE_FACTOR: f64 = 64.0;

/// Predicted triangles per unit of (area / area bound).
const PER_RATIO: f64 = 1.6;

/// Threads to use for this refinement (1: the sequential path).
pub(super) fn threads_for(
    m: &Mesh,
    crit: &Crit,
    max_areas: &[f64],
    options: &RefineOptions,
) -> usize {
    let t = options.threads.min(64);
    if t <= 1 || options.conforming_delaunay || options.max_steiner.is_some() || crit.user.is_some()
    {
        return 1;
    }
    let min = options.parallel_min_triangles;
    if min > 0 && predicted(m, crit, max_areas) < min as f64 {
        1
    } else {
        t
    }
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

/// Refines `m` with `threads` parts; returns as [`run`] does. The
/// Steiner budget `limit` is shared: the coarse stage spends from it, each
/// part gets an equal share of what is left, the finish the rest (so the
/// result still depends only on the input, the options and `threads`).
pub(super) fn refine_parallel(
    m: &mut Mesh,
    crit: &Crit,
    max_areas: &[f64],
    options: &RefineOptions,
    threads: usize,
    limit: usize,
    report: &mut RefineReport,
) -> bool {
    // 1. Coarse stage.
    let coarse = Crit {
        coarse: COARSE_FACTOR,
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
        bisect(&mut ids, &cen, &w, threads, 0, &mut part);
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
    let mut lists: Vec<Vec<u32>> = vec![Vec::new(); threads];
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

    // 3. Parts: part 0 in `m` itself, the others in copies.
    let mut copies: Vec<Mesh> = Vec::with_capacity(threads - 1);
    for p in 1..threads as u32 {
        let mut pm = m.clone();
        cut_part(&mut pm, p, &cuts);
        copies.push(pm);
    }
    cut_part(m, 0, &cuts);
    // Room for everything (untouched capacity costs no resident memory):
    // the stitch then appends without moving the arrays.
    m.reserve_for_areas(crit, max_areas, usize::MAX, None);
    let detached = crit.detached();
    let share = limit.saturating_sub(steiner) / threads;
    let mut drops = Vec::new();
    let results: Vec<(Mesh, RefineReport, Vec<u32>)> = std::thread::scope(|sc| {
        let handles: Vec<_> = copies
            .into_iter()
            .zip(&lists[1..])
            .map(|(mut pm, list)| {
                sc.spawn(move || {
                    let crit = detached.crit();
                    pm.reserve_for_areas(&crit, max_areas, usize::MAX, Some(list));
                    let mut rep = RefineReport::default();
                    let mut st = 0usize;
                    let mut dr = Vec::new();
                    run(
                        &mut pm,
                        &crit,
                        max_areas,
                        options,
                        share,
                        &mut st,
                        &mut rep,
                        Some(list),
                        Some(&mut dr),
                    );
                    (pm, rep, dr)
                })
            })
            .collect();
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
        handles
            .into_iter()
            .map(|h| h.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
            .collect()
    });

    // 4. Stitch.
    let (mut nv, mut nt, mut ns) = (m.xy.len(), m.tr.len(), m.subs.len());
    let mut offs = Vec::with_capacity(threads);
    for (pm, _, _) in &results {
        offs.push((nv, nt, ns));
        nv += pm.xy.len() - nv0;
        nt += pm.tr.len() - nt0;
        ns += pm.subs.len() - ns0 - np;
    }
    m.xy.reserve_exact(nv - m.xy.len());
    m.vpar.reserve_exact(nv - m.vpar.len());
    m.tr.reserve_exact(nt - m.tr.len());
    m.sides.reserve_exact(nt - m.sides.len());
    m.subs.reserve_exact(ns - m.subs.len());
    // Merged half-edges of each cut: [side of `t`, side of `n`].
    let mut cut_he = vec![[NONE; 2]; np];
    for (j, c) in cuts.iter().enumerate() {
        let he = m.subs[ns0 + j].he;
        if c.pt == 0 {
            cut_he[j][0] = he;
        } else if c.pn == 0 {
            cut_he[j][1] = he;
        }
    }
    for (i, (pm, rep, dr)) in results.into_iter().enumerate() {
        let p = i + 1;
        let (vo, to, so) = offs[i];
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
        for &t in &lists[p] {
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
        for (j, c) in cuts.iter().enumerate() {
            let he = ra(pm.subs[ns0 + j].he);
            if c.pt == p as u32 {
                cut_he[j][0] = he;
            } else if c.pn == p as u32 {
                cut_he[j][1] = he;
            }
        }
        for (s, &o) in owner.iter().enumerate() {
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
        steiner += rep.segment_splits + rep.circumcenters;
        report.rejected_circumcenters += rep.rejected_circumcenters;
        // `pm` is dropped here (peak memory: one part at a time).
    }
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
            stack.push(h0);
        }
        drops.extend([t0 as u32, t1 as u32]);
    }
    m.restore_delaunay(&mut stack, &mut drops);

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
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for &t in ids.iter() {
        let c = cen[t as usize];
        for k in 0..2 {
            lo[k] = lo[k].min(c[k]);
            hi[k] = hi[k].max(c[k]);
        }
    }
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

/// The plain values of a [`Crit`] without the user's test (which need not
/// be `Sync`), to rebuild it in another thread.
#[derive(Clone, Copy)]
pub(super) struct Detached {
    scale: (f64, f64),
    sin2: f64,
    angle: f64,
    area2: f64,
    regional: bool,
    off: f64,
    s2: f64,
    coarse: f64,
}

impl From<&Crit<'_>> for Detached {
    fn from(c: &Crit<'_>) -> Self {
        c.detached()
    }
}

impl Detached {
    pub(super) fn crit(self) -> Crit<'static> {
        Crit {
            user: None,
            scale: self.scale,
            sin2: self.sin2,
            angle: self.angle,
            area2: self.area2,
            regional: self.regional,
            off: self.off,
            s2: self.s2,
            coarse: self.coarse,
        }
    }
}

impl Crit<'_> {
    fn detached(&self) -> Detached {
        Detached {
            scale: self.scale,
            sin2: self.sin2,
            angle: self.angle,
            area2: self.area2,
            regional: self.regional,
            off: self.off,
            s2: self.s2,
            coarse: self.coarse,
        }
    }
}

impl Mesh {
    /// Lawson flips from the half-edges on `stack` until every edge without
    /// a subsegment is locally Delaunay (exact incircle).
    /// The flipped triangles are pushed on `touched`.
    fn restore_delaunay(&mut self, stack: &mut Vec<u32>, touched: &mut Vec<u32>) {
        while let Some(h) = stack.pop() {
            let (t, e) = unpack(h);
            if self.sub_at(t, e) != NONE {
                continue;
            }
            let x = self.tr[t].a[e];
            if x == NONE {
                continue;
            }
            let (n, j) = unpack(x);
            let v = self.tr[t].v;
            let vn = self.tr[n].v[j];
            if incircle(self.p(v[0]), self.p(v[1]), self.p(v[2]), self.p(vn)) > 0.0 {
                self.flip(t, e);
                touched.extend([t as u32, n as u32]);
                stack.extend([pack(t, 0), pack(t, 2), pack(n, 0), pack(n, 2)]);
            }
        }
    }

    /// Flips edge `e` of triangle `t` (it must have a neighbour and no
    /// subsegment, and the two triangles must form a convex quadrilateral).
    /// `t` becomes `[vt, a, vn]` and its neighbour `n` becomes `[vn, b, vt]`,
    /// where `t` was `[vt, a, b]` (rotated) and `vn` is opposite in `n`.
    fn flip(&mut self, t: usize, e: usize) {
        let (n, j) = unpack(self.tr[t].a[e]);
        let tv = self.tr[t].v;
        let (vt, a, b) = (tv[e], tv[NEXT[e]], tv[PREV[e]]);
        let vn = self.tr[n].v[j];
        let (ea, eb) = (NEXT[e], PREV[e]);
        let (ec, ed) = (NEXT[j], PREV[j]);
        let (xa, sa) = (self.tr[t].a[ea], self.sub_at(t, ea));
        let (xb, sb) = (self.tr[t].a[eb], self.sub_at(t, eb));
        let (xc, sc) = (self.tr[n].a[ec], self.sub_at(n, ec));
        let (xd, sd) = (self.tr[n].a[ed], self.sub_at(n, ed));
        let (ot, on) = (self.tr[t].orig, self.tr[n].orig);
        self.tr[t] = Tri {
            v: [vt, a, vn],
            a: [xc, pack(n, 1), xb],
            orig: ot,
            mark: 0,
        };
        self.tr[n] = Tri {
            v: [vn, b, vt],
            a: [xa, pack(t, 1), xd],
            orig: on,
            mark: 0,
        };
        for (tt, ee, x, s) in [
            (t, 0, xc, sc),
            (t, 2, xb, sb),
            (n, 0, xa, sa),
            (n, 2, xd, sd),
        ] {
            self.set_sub(tt, ee, s);
            if x != NONE {
                let (o, l) = unpack(x);
                self.tr[o].a[l] = pack(tt, ee);
            }
            if s != NONE {
                self.subs[s as usize].he = pack(tt, ee);
            }
        }
        self.set_sub(t, 1, NONE);
        self.set_sub(n, 1, NONE);
    }
}
