//! The refinement loop and the mesh it works on: the constrained triangle
//! mesh with the subsegment chains, the bucket queue of bad triangles, the
//! criteria in scaled units, and [`run`], shared by the sequential and the
//! parallel refinement (see the parent module's docs).

use std::collections::VecDeque;
use std::sync::Arc;

use super::options::{RefineOptions, RefineReport, UserTest};
use crate::tri::cmesh::{encroaches, CMesh, Ins, Sub};
use crate::tri::topo::{edge, pack, NEXT, PREV};
use crate::NONE;

/// A chain of subsegments between two vertices of the input CDT.
#[derive(Clone, Copy)]
pub(super) struct Parent {
    /// Fixed end vertices (vertices of the input CDT).
    pub(super) a: u32,
    pub(super) b: u32,
    /// Index into the input `Cdt::segments`, or `NONE` for a hull edge (`-c`).
    pub(super) out: u32,
    /// Split on concentric shells around `a` / `b`: another chain meets the
    /// end at an angle below [`SHELL_ANGLE`].
    pub(super) shell: [bool; 2],
}

/// Input angle (degrees) below which the subsegments at a vertex are split
/// on concentric shells around it. Elsewhere midpoints are better: a shell
/// split of a chain's end subsegment may cut it at 0.35 of its length, and
/// the short piece seeds a cascade of small triangles at 34°.
pub(super) const SHELL_ANGLE: f64 = 60.0;

/// The refinement's mesh: the constrained triangle mesh and what
/// refinement keeps beside it (subsegment chains, fixed vertices).
#[derive(Clone)]
pub(super) struct Mesh {
    pub(super) cm: CMesh,
    /// Parent chain of a Steiner vertex on a subsegment (`NONE` otherwise).
    pub(super) vpar: Vec<u32>,
    pub(super) nfixed: usize,
    /// The chains (parents) each fixed vertex is an end of.
    pub(super) vchains: Arc<Vec<Vec<u32>>>,
    pub(super) parents: Arc<Vec<Parent>>,
}

impl std::ops::Deref for Mesh {
    type Target = CMesh;
    fn deref(&self) -> &CMesh {
        &self.cm
    }
}

impl std::ops::DerefMut for Mesh {
    fn deref_mut(&mut self) -> &mut CMesh {
        &mut self.cm
    }
}

pub(super) fn dist2(a: &[f64; 2], b: &[f64; 2]) -> f64 {
    (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)
}

/// Circumcentre of a triangle, computed relative to `a`.
pub(super) fn circumcenter(a: &[f64; 2], b: &[f64; 2], c: &[f64; 2]) -> [f64; 2] {
    let (bx, by) = (b[0] - a[0], b[1] - a[1]);
    let (cx, cy) = (c[0] - a[0], c[1] - a[1]);
    let d = 2.0 * (bx * cy - by * cx);
    let (b2, c2) = (bx * bx + by * by, cx * cx + cy * cy);
    [
        a[0] + (cy * b2 - by * c2) / d,
        a[1] + (bx * c2 - cx * b2) / d,
    ]
}

/// (sin² of the smallest angle, doubled area, index of the shortest edge).
pub(super) fn shape(a: &[f64; 2], b: &[f64; 2], c: &[f64; 2]) -> (f64, f64, usize) {
    let l = [dist2(b, c), dist2(c, a), dist2(a, b)];
    let d = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    let mut k = 0;
    for i in 1..3 {
        if l[i] < l[k] {
            k = i;
        }
    }
    let (x, y) = (l[NEXT[k]], l[PREV[k]]);
    let s2 = if x > 0.0 && y > 0.0 {
        d * d / (x * y)
    } else {
        0.0
    };
    (s2, d, k)
}

/// The angle (degrees) at `p` between the directions to `q` and `r`.
pub(super) fn angle(p: &[f64; 2], q: &[f64; 2], r: &[f64; 2]) -> f64 {
    let (ux, uy) = (q[0] - p[0], q[1] - p[1]);
    let (vx, vy) = (r[0] - p[0], r[1] - p[1]);
    (ux * vy - uy * vx)
        .abs()
        .atan2(ux * vx + uy * vy)
        .to_degrees()
}

/// Angles (degrees) of a triangle.
pub(super) fn angles(a: &[f64; 2], b: &[f64; 2], c: &[f64; 2]) -> [f64; 3] {
    [angle(a, b, c), angle(b, c, a), angle(c, a, b)]
}

impl Mesh {
    /// Reserves room for the triangles an area bound will make (about
    /// 1.6 per bound's worth of area; twice that is reserved, at most 2²⁴):
    /// the 32-byte aligned records are copied, not reallocated in place,
    /// when the vector grows. Untouched capacity costs no resident memory.
    /// `part`: only these triangles will be refined (all when `None`).
    pub(super) fn reserve_for_areas(
        &mut self,
        crit: &Crit,
        max_areas: &[f64],
        limit: usize,
        part: Option<&[u32]>,
    ) {
        if !crit.area2.is_finite() && !crit.regional {
            return;
        }
        let ratio = match part {
            Some(ts) => ts
                .iter()
                .map(|&t| self.area_ratio(crit, max_areas, t as usize))
                .sum(),
            None => (0..self.tr.len())
                .map(|t| self.area_ratio(crit, max_areas, t))
                .sum::<f64>(),
        };
        let base = if part.is_some() { 0 } else { self.tr.len() };
        let nt = (3.2 * ratio).min((1u64 << 24) as f64) as usize;
        let nt = nt.min(limit.saturating_mul(2));
        if nt > base {
            let more = nt - base;
            // Best effort: without the room the vectors grow as usual.
            let _ = self.tr.try_reserve_exact(more);
            let _ = self.sides.try_reserve_exact(more);
            let _ = self.xy.try_reserve_exact(more / 2);
            let _ = self.vpar.try_reserve_exact(more / 2);
        }
    }

    /// Area of triangle `t` over its area bound (0 without one).
    pub(super) fn area_ratio(&self, crit: &Crit, max_areas: &[f64], t: usize) -> f64 {
        let t = &self.tr[t];
        {
            let (a, b, c) = (self.p(t.v[0]), self.p(t.v[1]), self.p(t.v[2]));
            let d = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
            let mut bound = crit.area2;
            if crit.regional {
                let ma = max_areas[t.orig as usize];
                if ma > 0.0 {
                    bound = bound.min(2.0 * ma * crit.s2);
                }
            }
            if bound.is_finite() && bound > 0.0 {
                d / bound
            } else {
                0.0
            }
        }
    }

    /// The point splitting subsegment `s`, and its parameter.
    pub(super) fn split_point(&self, s: &Sub) -> ([f64; 2], f64) {
        let par = self.parents[s.parent as usize];
        let (pa, pb) = (*self.p(par.a), *self.p(par.b));
        let len = dist2(&pa, &pb).sqrt();
        let fixed = |v: u32| (v as usize) < self.nfixed;
        let (t0, t1) = (s.t[0].min(s.t[1]), s.t[0].max(s.t[1]));
        let lo_fixed = fixed(if s.t[0] <= s.t[1] { s.v[0] } else { s.v[1] });
        let hi_fixed = fixed(if s.t[0] <= s.t[1] { s.v[1] } else { s.v[0] });
        let mut tm = 0.5 * (t0 + t1);
        // The fixed end (parameter 0 at `a`, 1 at `b`) and its shell flag.
        let shell = if lo_fixed {
            par.shell[usize::from(t0 != 0.0)]
        } else {
            par.shell[usize::from(t1 == 1.0)]
        };
        if lo_fixed != hi_fixed && shell && len > 0.0 {
            // Concentric shells around the fixed end.
            let l = (t1 - t0) * len;
            let d = 2f64.powi((0.5 * l).log2().round() as i32);
            let f = d / len;
            tm = if lo_fixed { t0 + f } else { t1 - f };
            if !(tm > t0 && tm < t1) {
                tm = 0.5 * (t0 + t1);
            }
        }
        // From the nearer fixed end, so the point stays on the segment.
        let x = if tm <= 0.5 {
            [pa[0] + tm * (pb[0] - pa[0]), pa[1] + tm * (pb[1] - pa[1])]
        } else {
            let u = 1.0 - tm;
            [pb[0] + u * (pa[0] - pb[0]), pb[1] + u * (pa[1] - pb[1])]
        };
        (x, tm)
    }

    /// Splits subsegment `s`; returns the new vertex.
    pub(super) fn split_sub(&mut self, s: u32) -> Option<u32> {
        let sub = self.subs[s as usize];
        if !sub.alive || sub.stuck {
            return None;
        }
        let (x, tm) = self.split_point(&sub);
        let [u, w] = sub.v;
        let Some(t) = self.tri_of_sub(s) else {
            self.subs[s as usize].stuck = true;
            return None;
        };
        // Halves: k = u..new, k+1 = new..w.
        let k = self.subs.len() as u32;
        let Ins::Done(nv) = self.cm.insert(t, x, s, [u, k, w, k + 1], false) else {
            self.subs[s as usize].stuck = true;
            return None;
        };
        self.vpar.push(sub.parent);
        self.subs[s as usize].alive = false;
        for (v, t) in [([u, nv], [sub.t[0], tm]), ([nv, w], [tm, sub.t[1]])] {
            self.subs.push(Sub {
                v,
                he: NONE,
                t,
                parent: sub.parent,
                alive: true,
                stuck: false,
                protected: false,
            });
        }
        // The halves lie on fan edges 1 and 2.
        for i in 0..self.fan.len() {
            let f = self.fan[i] as usize;
            for e in 1..3 {
                let x = self.sub_at(f, e);
                if x == k || x == k + 1 {
                    self.subs[x as usize].he = pack(f, e);
                }
            }
        }
        Some(nv)
    }

    /// Conforming Delaunay: queues the live subsegments (with `stuck`, also
    /// those that cannot be split) whose diametral circle strictly holds a
    /// mesh vertex; returns how many.
    pub(super) fn scan_encroached(&self, stuck: bool, enc: &mut VecDeque<u32>) -> usize {
        let ids: Vec<u32> = (0..self.subs.len() as u32)
            .filter(|&s| {
                let x = &self.subs[s as usize];
                x.alive && (stuck || !x.stuck)
            })
            .collect();
        let pairs: Vec<[u32; 2]> = ids.iter().map(|&s| self.subs[s as usize].v).collect();
        let tris: Vec<[u32; 3]> = self.tr.iter().map(|t| t.v).collect();
        let hit = crate::tri::conforming::encroached(&self.xy, &tris, &pairs);
        enc.extend(hit.iter().map(|&k| ids[k]));
        hit.len()
    }

    /// Skinny triangle whose shortest edge spans a small input angle:
    /// the apex and the input angle (degrees), if `u` and `v` lie on two
    /// segment chains that meet at a vertex other than `u` and `v` at an angle
    /// below `bound`.
    pub(super) fn small_angle_apex(&self, u: u32, v: u32, bound: f64) -> Option<(u32, f64)> {
        let chains = |x: u32| -> &[u32] {
            let p = self.vpar[x as usize];
            if p != NONE {
                std::slice::from_ref(&self.vpar[x as usize])
            } else {
                self.vchains.get(x as usize).map_or(&[], |c| c.as_slice())
            }
        };
        let mut best: Option<(u32, f64)> = None;
        for &pu in chains(u) {
            for &pv in chains(v) {
                if pu == pv {
                    continue;
                }
                let (a, b) = (self.parents[pu as usize], self.parents[pv as usize]);
                for z in [a.a, a.b] {
                    if z == u || z == v || (z != b.a && z != b.b) {
                        continue;
                    }
                    let oa = if a.a == z { a.b } else { a.a };
                    let ob = if b.a == z { b.b } else { b.a };
                    let ang = angle(self.p(z), self.p(oa), self.p(ob));
                    // (Requiring `w` inside the wedge cascades on la.poly
                    // at 30°.)
                    if ang < bound && best.is_none_or(|(_, x)| ang < x) {
                        best = Some((z, ang));
                    }
                }
            }
        }
        best
    }
}

/// Bad triangles waiting, in buckets by badness: bucket 0 for triangles
/// whose circumcentre was rejected (retried right after the subsegment
/// splits), then angle buckets (worst first, by sin² of the smallest angle
/// over the bound's), then area buckets (largest area ratio first, quarter
/// octaves). Within an angle bucket the oldest triangle comes first (first
/// in, first out: at 34° on double_hex this keeps the count within a few
/// per cent of Triangle's, where newest-first made 12% more); within the
/// other buckets the newest comes first: it was just made, so it is still
/// in cache. Either order costs the same cache misses on the large shared
/// inputs (callgrind).
///
/// An entry is (triangle, its first vertex): a triangle record is reused
/// only by a fan around a new vertex, which becomes the first vertex of
/// every fan triangle, so a changed first vertex marks a stale entry.
pub(super) struct Queue {
    pub(super) buckets: Vec<Vec<(u32, u32)>>,
    /// No non-empty bucket below this one.
    pub(super) lo: usize,
    pub(super) len: usize,
    /// Angle buckets: the next entry to pop (first in, first out).
    pub(super) head: Vec<usize>,
}

pub(super) const ANGLE_BUCKETS: u32 = 64;
pub(super) const AREA_BUCKETS: u32 = 160;

impl Queue {
    pub(super) fn new() -> Self {
        Queue {
            buckets: vec![Vec::new(); (1 + ANGLE_BUCKETS + AREA_BUCKETS) as usize],
            lo: 0,
            len: 0,
            head: vec![0; (1 + ANGLE_BUCKETS + AREA_BUCKETS) as usize],
        }
    }

    /// `q` = sin² of the smallest angle over sin² of the bound, in [0, 1).
    pub(super) fn angle_bucket(q: f64) -> u32 {
        1 + ((q * ANGLE_BUCKETS as f64) as u32).min(ANGLE_BUCKETS - 1)
    }

    /// `r` = area over the bound, above 1.
    pub(super) fn area_bucket(r: f64) -> u32 {
        // Quarter octaves from the exponent and the top two mantissa bits.
        let k = ((r.to_bits() >> 50) as u32)
            .saturating_sub(1023 << 2)
            .min(AREA_BUCKETS - 1);
        1 + ANGLE_BUCKETS + (AREA_BUCKETS - 1 - k)
    }

    pub(super) fn push(&mut self, b: u32, t: u32, v0: u32) {
        let b = b as usize;
        self.buckets[b].push((t, v0));
        self.lo = self.lo.min(b);
        self.len += 1;
    }

    pub(super) fn pop(&mut self) -> Option<(u32, u32)> {
        while self.lo < self.buckets.len() {
            let b = self.lo;
            if (1..=ANGLE_BUCKETS as usize).contains(&b) {
                // First in, first out.
                let (q, h) = (&mut self.buckets[b], &mut self.head[b]);
                if *h < q.len() {
                    let x = q[*h];
                    *h += 1;
                    self.len -= 1;
                    if *h >= 4096 && 2 * *h >= q.len() {
                        q.drain(..*h);
                        *h = 0;
                    }
                    return Some(x);
                }
                q.clear();
                *h = 0;
            } else if let Some(x) = self.buckets[b].pop() {
                self.len -= 1;
                return Some(x);
            }
            self.lo += 1;
        }
        None
    }

    pub(super) fn is_empty(&self) -> bool {
        self.len == 0
    }
}

/// Criteria in scaled units: the user's test and the plain [`Bounds`]
/// (read through `Deref`).
#[derive(Clone, Copy)]
pub(super) struct Crit<'a> {
    /// The user's test, if any.
    pub(super) user: Option<UserTest<'a>>,
    pub(super) b: Bounds,
}

/// The plain values of a [`Crit`]: everything but the user's test (which
/// need not be `Sync`), so another thread can rebuild it.
#[derive(Clone, Copy)]
pub(super) struct Bounds {
    /// Scale factors of the coordinates (divide by both for input units).
    pub(super) scale: (f64, f64),
    /// sin² of the angle bound (0: none).
    pub(super) sin2: f64,
    pub(super) angle: f64,
    /// Doubled-area bound (infinite: none).
    pub(super) area2: f64,
    pub(super) regional: bool,
    /// Off-centre distance from the shortest edge, in edge lengths (0: none).
    pub(super) off: f64,
    /// Doubled-area scale factor (scaled² → input units).
    pub(super) s2: f64,
    /// Factor on every area bound (1; more for the coarse stage of the
    /// parallel refinement).
    pub(super) coarse: f64,
}

impl std::ops::Deref for Crit<'_> {
    type Target = Bounds;
    fn deref(&self) -> &Bounds {
        &self.b
    }
}

/// Queue bucket (smaller is worse) of triangle `t`, if it is to be fixed.
#[inline]
pub(super) fn bad_bucket(m: &Mesh, crit: &Crit, max_areas: &[f64], t: usize) -> Option<u32> {
    let v = m.tr[t].v;
    let (a, b, c) = (m.p(v[0]), m.p(v[1]), m.p(v[2]));
    let d = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    let mut abound = crit.area2;
    if crit.regional {
        let ma = max_areas[m.tr[t].orig as usize];
        if ma > 0.0 {
            abound = abound.min(2.0 * ma * crit.s2);
        }
    }
    abound *= crit.coarse;
    if d > abound {
        return Some(Queue::area_bucket(d / abound));
    }
    if crit.sin2 > 0.0 {
        let l = [dist2(b, c), dist2(c, a), dist2(a, b)];
        let k = if l[0] <= l[1] && l[0] <= l[2] {
            0
        } else if l[1] <= l[2] {
            1
        } else {
            2
        };
        let xy = l[NEXT[k]] * l[PREV[k]];
        // sin² of the smallest angle, d² / xy, below the bound's?
        if d * d < crit.sin2 * xy {
            let (u, w) = edge(&v, k);
            if m.small_angle_apex(u, w, crit.angle).is_none() {
                let s2 = if xy > 0.0 { d * d / xy } else { 0.0 };
                return Some(Queue::angle_bucket(s2 / crit.sin2));
            }
        }
    }
    if let Some(f) = crit.user {
        if f(&crit.input(m, &v), 0.5 * d / crit.s2) {
            // Last, with the least oversized triangles.
            return Some(Queue::area_bucket(1.0));
        }
    }
    None
}

impl Crit<'_> {
    /// A triangle's corners in input units.
    pub(super) fn input(&self, m: &Mesh, v: &[u32; 3]) -> [[f64; 2]; 3] {
        v.map(|x| {
            let p = m.p(x);
            [
                p[0] / self.scale.1 / self.scale.0,
                p[1] / self.scale.1 / self.scale.0,
            ]
        })
    }
}

/// The refinement loop: queues the bad triangles and encroached
/// subsegments among `scan` (all triangles when `None`), then splits and
/// inserts until both queues are empty (or the budget `limit` on
/// `*steiner` runs out). Returns false if quality refinement was stopped
/// for the conforming-Delaunay splits. Bad triangles given up on (no
/// point could be inserted for them) are pushed on `dropped`.
#[allow(clippy::too_many_arguments)]
pub(super) fn run(
    m: &mut Mesh,
    crit: &Crit,
    max_areas: &[f64],
    options: &RefineOptions,
    limit: usize,
    steiner: &mut usize,
    report: &mut RefineReport,
    scan: Option<&[u32]>,
    mut dropped: Option<&mut Vec<u32>>,
) -> bool {
    let bad = |m: &Mesh, t: usize| bad_bucket(m, crit, max_areas, t);
    type Heap = Queue;
    let mut heap = Queue::new();
    let mut enc: VecDeque<u32> = VecDeque::new();
    // Subsegments encroached by an apex.
    let check_sub = |m: &Mesh, t: usize, e: usize, enc: &mut VecDeque<u32>| {
        let s = m.sub_at(t, e);
        if s == NONE {
            return;
        }
        let [u, w] = m.subs[s as usize].v;
        let apex = m.tr[t].v[e];
        if encroaches(m.p(u), m.p(w), m.p(apex), m.cos2) {
            enc.push_back(s);
        }
    };
    let mut all = 0..m.tr.len() as u32;
    let seeds: &mut dyn Iterator<Item = u32> = match scan {
        Some(ts) => &mut ts.iter().copied(),
        None => &mut all,
    };
    for t in seeds {
        let t = t as usize;
        if let Some(k) = bad(m, t) {
            heap.push(k, t as u32, m.tr[t].v[0]);
        }
        for e in 0..3 {
            check_sub(m, t, e, &mut enc);
        }
    }
    // The new triangles: bad ones are queued, their subsegments checked.
    let after_insert = |m: &Mesh, heap: &mut Heap, enc: &mut VecDeque<u32>| {
        for &t in &m.fan {
            let t = t as usize;
            if let Some(k) = bad(m, t) {
                heap.push(k, t as u32, m.tr[t].v[0]);
            }
            let tri = &m.tr[t];
            for e in 0..3 {
                let s = m.sub_at(t, e);
                if s != NONE {
                    let [u, w] = m.subs[s as usize].v;
                    if encroaches(m.p(u), m.p(w), m.p(tri.v[e]), m.cos2) {
                        enc.push_back(s);
                    }
                }
            }
        }
    };
    // Rounds of -D splits after the queues ran empty. Past 64 rounds, or
    // when quality refinement after the first round has added 8 times the
    // points there were, bad triangles are no longer fixed: near small input
    // angles and with high angle bounds the two can feed each other.
    const GABRIEL_ROUNDS: usize = 64;
    let mut gabriel_rounds = 0usize;
    let mut quality_cap = usize::MAX;
    let mut quality = true;
    let mut turns: u64 = 0;
    loop {
        turns += 1;
        if turns.is_multiple_of(8192) {
            crate::progress::report("refining", *steiner as u64, None, "Steiner points");
        }
        if enc.is_empty() && (heap.is_empty() || !quality) {
            // -D: split the subsegments any vertex encroaches, until none.
            if options.conforming_delaunay && m.scan_encroached(false, &mut enc) > 0 {
                gabriel_rounds += 1;
                if gabriel_rounds == 1 {
                    quality_cap = *steiner + 8 * (*steiner + m.nfixed) + 1024;
                }
                if gabriel_rounds > GABRIEL_ROUNDS {
                    // Splits and quality refinement keep feeding each other
                    // (high angle bounds near small input angles): finish
                    // with splits alone, which terminate (concentric shells).
                    quality = false;
                }
                continue;
            }
            break;
        }
        let stop = turns.is_multiple_of(8192) && crate::progress::stop_requested();
        if stop || *steiner >= limit || m.xy.len() >= (u32::MAX - 8) as usize {
            report.limit_reached = true;
            break;
        }
        if let Some(s) = enc.pop_front() {
            if m.split_sub(s).is_some() {
                *steiner += 1;
                report.segment_splits += 1;
                after_insert(m, &mut heap, &mut enc);
            }
            continue;
        }
        if *steiner > quality_cap {
            quality = false;
            continue;
        }
        let Some((t, v0)) = heap.pop() else {
            break;
        };
        let t = t as usize;
        if m.tr[t].v[0] != v0 {
            continue;
        }
        let v = m.tr[t].v;
        let tv = v;
        let mut c = circumcenter(m.p(tv[0]), m.p(tv[1]), m.p(tv[2]));
        if crit.off > 0.0 {
            // Üngör's off-centre: on the bisector of the shortest edge, at
            // the apex of an isosceles triangle on it whose apex angle is a
            // little above the bound, if that is nearer than the circumcentre.
            let (_, _, k) = shape(m.p(tv[0]), m.p(tv[1]), m.p(tv[2]));
            let (a, b) = edge(&tv, k);
            let (pa, pb) = (*m.p(a), *m.p(b));
            let mid = [0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1])];
            let want = crit.off * dist2(&pa, &pb).sqrt();
            let have = dist2(&mid, &c).sqrt();
            if have > want {
                let f = want / have;
                c = [mid[0] + f * (c[0] - mid[0]), mid[1] + f * (c[1] - mid[1])];
            }
        }
        if !(c[0].is_finite() && c[1].is_finite()) {
            if let Some(d) = dropped.as_deref_mut() {
                d.push(t as u32);
            }
            continue;
        }
        // The triangle's circumcircle contains `c`, so the cavity can grow
        // from it: no point location needed.
        match m.cm.insert(t, c, NONE, [NONE; 4], true) {
            Ins::Done(_) => {
                m.vpar.push(NONE);
                *steiner += 1;
                report.circumcenters += 1;
                after_insert(m, &mut heap, &mut enc);
            }
            Ins::Encroached => {
                report.rejected_circumcenters += 1;
                let mut any = false;
                for &s in &m.hit {
                    if !m.subs[s as usize].stuck {
                        enc.push_back(s);
                        any = true;
                    }
                }
                if any {
                    heap.push(0, t as u32, v0);
                } else if let Some(d) = dropped.as_deref_mut() {
                    d.push(t as u32);
                }
            }
            Ins::Blocked(s) => {
                report.rejected_circumcenters += 1;
                if !m.subs[s as usize].stuck {
                    enc.push_back(s);
                    heap.push(0, t as u32, v0);
                } else if let Some(d) = dropped.as_deref_mut() {
                    d.push(t as u32);
                }
            }
            Ins::Failed => {
                if let Some(d) = dropped.as_deref_mut() {
                    d.push(t as u32);
                }
            }
        }
    }
    drop(heap);
    drop(enc);
    quality
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn queue_buckets_are_ordered_worst_first() {
        // Angle buckets: a smaller sin² ratio is worse (a smaller bucket).
        let qs = [0.0, 0.01, 0.2, 0.5, 0.9, 0.999];
        for w in qs.windows(2) {
            assert!(Queue::angle_bucket(w[0]) <= Queue::angle_bucket(w[1]));
        }
        assert!(Queue::angle_bucket(0.0) < Queue::angle_bucket(0.999));
        // Area buckets: a larger area ratio is worse, and after every angle
        // bucket.
        let rs = [1.0, 1.3, 2.0, 17.0, 1e6, 1e300];
        for w in rs.windows(2) {
            assert!(Queue::area_bucket(w[0]) >= Queue::area_bucket(w[1]));
        }
        assert!(Queue::area_bucket(4.0) < Queue::area_bucket(1.5));
        assert!(Queue::area_bucket(1e300) > Queue::angle_bucket(0.999));
        // Pop: lowest bucket first; oldest first within an angle bucket,
        // newest first within the others.
        let mut q = Queue::new();
        let area = Queue::area_bucket(2.0);
        q.push(5, 1, 1);
        q.push(area, 5, 9);
        q.push(3, 2, 4);
        q.push(5, 3, 7);
        q.push(area, 6, 9);
        q.push(0, 4, 0);
        q.push(0, 7, 0);
        let order: Vec<u32> = std::iter::from_fn(|| q.pop().map(|x| x.0)).collect();
        assert_eq!(order, vec![7, 4, 2, 1, 3, 6, 5]);
        assert!(q.is_empty());
        // A long angle bucket drops its popped front.
        for t in 0..10_000 {
            q.push(7, t, 0);
        }
        for t in 0..9_000 {
            assert_eq!(q.pop(), Some((t, 0)));
        }
        assert!(q.buckets[7].len() < 10_000);
        q.push(7, 42, 0);
        let rest: Vec<u32> = std::iter::from_fn(|| q.pop().map(|x| x.0)).collect();
        assert_eq!(rest.len(), 1_001);
        assert_eq!(rest[..2], [9_000, 9_001]);
        assert_eq!(rest[1_000], 42);
    }
}
