//! The constrained triangle mesh of the CDT and of refinement (sequential
//! and parallel): compact 32-byte triangle records (vertices, packed
//! adjacency, the input triangle they descend from, subsegment flags and a
//! cavity stamp), the subsegment on each constrained half-edge, the
//! subsegment records, and its local operations — the walk
//! ([`CMesh::locate`]), constrained Bowyer–Watson insertion
//! ([`CMesh::insert`]), the edge flip ([`CMesh::flip`]) and Lawson flips
//! ([`CMesh::restore_delaunay`]) — with
//! the invariant checker [`CMesh::check`] that the tests run after every
//! operation.
//!
//! In refinement the boundary of the domain has no neighbour (`NONE`) and
//! always carries a subsegment. The CDT (`constrain`) works on the same
//! records with the kernel's ghost triangles and dead slots still in place
//! and no subsegment records: the label on a constrained half-edge is the
//! index of its input segment (once carved and compacted, `LABEL | k` for
//! its output subsegment `k`, which refinement turns into records). The numbering conventions are the `topo`
//! module's. Every orientation and incircle decision is exact.

use delone_predicates::{incircle, incircle_weighted, orient2d};

use super::topo::{edge, is_ghost, pack, unpack, DEAD, NEXT, PREV};
use crate::{Violation, NONE};

#[derive(Clone, Copy)]
pub(crate) struct Sub {
    pub(crate) v: [u32; 2],
    /// A packed half-edge carrying it (kept up to date by every fan that
    /// borders it).
    pub(crate) he: u32,
    /// Parameters of `v` along the parent (0 at `a`, 1 at `b`).
    pub(crate) t: [f64; 2],
    pub(crate) parent: u32,
    pub(crate) alive: bool,
    /// Gave up splitting it (floating point), or it is protected.
    pub(crate) stuck: bool,
    /// The options forbid splitting it (it is never encroached).
    pub(crate) protected: bool,
}

/// The constrained triangle mesh: points, triangle records with packed
/// adjacency, the subsegment on each constrained half-edge, and the
/// subsegment records.
#[derive(Clone)]
pub(crate) struct CMesh {
    pub(crate) xy: Vec<[f64; 2]>,
    /// The triangles, one 32-byte aligned record each (half a cache line
    /// for everything a cavity search reads).
    pub(crate) tr: Vec<Tri>,
    /// Subsegment on each half-edge of a triangle (meaningful only where
    /// the triangle's flag bit says there is one; see [`Tri::mark`]).
    pub(crate) sides: Vec<[u32; 3]>,
    pub(crate) subs: Vec<Sub>,
    /// Squared cosine of the encroachment angle (see [`encroaches`]).
    pub(crate) cos2: f64,
    pub(crate) stamp: u32,
    /// Scratch of [`CMesh::insert`]: cavity, its boundary, encroached
    /// subsegments, new triangles.
    pub(crate) cav: Vec<u32>,
    pub(crate) bnd: Vec<Bnd>,
    pub(crate) hit: Vec<u32>,
    /// Depth-first stack: triangle, next edge, edges left.
    pub(crate) stack: Vec<(u32, u8, u8)>,
    pub(crate) fan: Vec<u32>,
    /// Triangles replaced by cavities.
    pub(crate) replaced: usize,
}

/// A triangle of the working mesh: 32 bytes, aligned, so that one record
/// never straddles two cache lines.
#[derive(Clone, Copy)]
#[repr(C, align(32))]
pub(crate) struct Tri {
    /// Counterclockwise vertices.
    pub(crate) v: [u32; 3],
    /// Packed adjacency or `NONE` on the boundary.
    pub(crate) a: [u32; 3],
    /// The input triangle it descends from (region, attributes).
    pub(crate) orig: u32,
    /// Bits 0–2: half-edge `e` carries a subsegment (its id is in
    /// [`Mesh::sides`]); the other bits: cavity stamp (a multiple of
    /// [`STAMP_STEP`]).
    pub(crate) mark: u32,
}

/// Marks a half-edge label that names an output subsegment of the CDT
/// (`LABEL | k`) rather than a subsegment record: the form in which the
/// CDT hands its mesh to refinement, which makes the records.
pub(crate) const LABEL: u32 = 1 << 31;

/// Stamps step over the three subsegment flag bits of [`Tri::mark`].
pub(crate) const STAMP_STEP: u32 = 8;
pub(crate) const FLAGS: u32 = STAMP_STEP - 1;

/// A cavity boundary edge `a -> b` (counterclockwise around the cavity).
#[derive(Clone, Copy)]
pub(crate) struct Bnd {
    pub(crate) a: u32,
    pub(crate) b: u32,
    /// Packed neighbour outside the cavity, or `NONE`.
    pub(crate) adj: u32,
    /// Its subsegment, or `NONE`.
    pub(crate) sb: u32,
    pub(crate) orig: u32,
}

/// Outcome of [`Mesh::insert`].
pub(crate) enum Ins {
    Done(u32),
    Encroached,
    /// The point lies beyond (or on) this subsegment of the cavity boundary.
    Blocked(u32),
    Failed,
}

/// Encroachment of `(u, v)` by `w`: `w` sees the subsegment at an angle
/// larger than the one whose squared cosine is `cos2` (0: the diametral
/// circle, 90°; more: a diametral lens), beyond rounding error.
pub(crate) fn encroaches(u: &[f64; 2], v: &[f64; 2], w: &[f64; 2], cos2: f64) -> bool {
    let (ax, ay) = (u[0] - w[0], u[1] - w[1]);
    let (bx, by) = (v[0] - w[0], v[1] - w[1]);
    let dot = ax * bx + ay * by;
    let err = 8.0 * f64::EPSILON * ((ax * bx).abs() + (ay * by).abs());
    dot < -err && (cos2 == 0.0 || dot * dot > cos2 * (ax * ax + ay * ay) * (bx * bx + by * by))
}

impl CMesh {
    /// A mesh of `tr` on `xy` with no subsegment yet.
    pub(crate) fn new(xy: Vec<[f64; 2]>, tr: Vec<Tri>) -> Self {
        let nt = tr.len();
        CMesh {
            xy,
            tr,
            sides: vec![[NONE; 3]; nt],
            subs: Vec::new(),
            cos2: 0.0,
            stamp: 0,
            cav: Vec::new(),
            bnd: Vec::new(),
            hit: Vec::new(),
            stack: Vec::new(),
            fan: Vec::new(),
            replaced: 0,
        }
    }

    /// The mesh of `triangles` on `xy` (triangle `t` descends from input
    /// triangle `t`), linked across `neighbors` (triangle indices, `NONE`
    /// on the boundary), with no subsegment yet.
    pub(crate) fn from_triangles(
        xy: Vec<[f64; 2]>,
        triangles: &[[u32; 3]],
        neighbors: &[[u32; 3]],
    ) -> Self {
        let tr = triangles.iter().enumerate().map(|(t, &v)| Tri {
            v,
            a: [NONE; 3],
            orig: t as u32,
            mark: 0,
        });
        let mut m = CMesh::new(xy, tr.collect());
        for (t, (v, nb)) in triangles.iter().zip(neighbors).enumerate() {
            for (e, &n) in nb.iter().enumerate() {
                let Some(w) = triangles.get(n as usize) else {
                    continue;
                };
                let (a, b) = edge(v, e);
                if let Some(j) = (0..3).find(|&j| edge(w, j) == (b, a)) {
                    m.tr[t].a[e] = pack(n as usize, j);
                }
            }
        }
        m
    }

    #[inline]
    pub(crate) fn p(&self, v: u32) -> &[f64; 2] {
        &self.xy[v as usize]
    }

    /// A triangle beside live subsegment `s` ([`Sub::he`], checked).
    pub(crate) fn tri_of_sub(&self, s: u32) -> Option<usize> {
        let he = self.subs[s as usize].he;
        if he == NONE {
            return None;
        }
        let (t, e) = unpack(he);
        (t < self.tr.len() && self.sub_at(t, e) == s).then_some(t)
    }

    pub(crate) fn new_tri(&mut self) -> usize {
        self.tr.push(Tri {
            v: [0; 3],
            a: [NONE; 3],
            orig: NONE,
            mark: 0,
        });
        self.sides.push([NONE; 3]);
        self.tr.len() - 1
    }

    /// The subsegment on half-edge `e` of triangle `t`, or `NONE`.
    #[inline]
    pub(crate) fn sub_at(&self, t: usize, e: usize) -> u32 {
        if self.tr[t].mark >> e & 1 != 0 {
            self.sides[t][e]
        } else {
            NONE
        }
    }

    /// Sets the subsegment on half-edge `e` of triangle `t` (`NONE`: none).
    #[inline]
    pub(crate) fn set_sub(&mut self, t: usize, e: usize, s: u32) {
        self.sides[t][e] = s;
        let bit = 1 << e;
        if s == NONE {
            self.tr[t].mark &= !bit;
        } else {
            self.tr[t].mark |= bit;
        }
    }

    pub(crate) fn next_stamp(&mut self) -> u32 {
        if self.stamp > u32::MAX - 2 * STAMP_STEP {
            for t in &mut self.tr {
                t.mark &= FLAGS;
            }
            self.stamp = 0;
        }
        self.stamp += STAMP_STEP;
        self.stamp
    }

    /// Bowyer–Watson insertion of `c` in the constrained triangulation: the
    /// cavity is grown from triangle `start` across unconstrained edges (and
    /// across subsegment `split`, the one `c` splits) to every triangle whose
    /// circumcircle strictly contains `c` (exact test), then replaced by a fan
    /// around `c`. With `check_enc`, subsegments on the cavity boundary that
    /// `c` encroaches are collected in `self.hit` and nothing is inserted.
    /// Nothing is changed either unless `c` sees every boundary edge strictly
    /// on its left and the boundary is one simple cycle (or one chain, when
    /// `split` is a boundary subsegment): the result is always a valid mesh.
    /// `halves`: `(u, label, w, label)` of the two pieces of `split`.
    /// The new triangles are left in `self.fan`.
    pub(crate) fn insert(
        &mut self,
        start: usize,
        c: [f64; 2],
        split: u32,
        halves: [u32; 4],
        check_enc: bool,
    ) -> Ins {
        let stamp = self.next_stamp();
        self.cav.clear();
        self.bnd.clear();
        self.hit.clear();
        self.stack.clear();
        self.tr[start].mark = (self.tr[start].mark & FLAGS) | stamp;
        self.cav.push(start as u32);
        // A split starts across its subsegment, so the other side is reached
        // first.
        let e0 = (0..3)
            .position(|e| self.splits(start, e, split, halves))
            .unwrap_or(0);
        self.stack.push((start as u32, e0 as u8, 3));
        // Where the chain starts when `split` is a boundary subsegment.
        let mut gap = usize::MAX;
        // Depth-first, each triangle's edges counterclockwise from the one
        // after its entry edge: the boundary comes out in counterclockwise
        // order.
        while let Some(top) = self.stack.last_mut() {
            if top.2 == 0 {
                self.stack.pop();
                continue;
            }
            let (t, e) = (top.0 as usize, top.1 as usize);
            top.1 = NEXT[e] as u8;
            top.2 -= 1;
            let tri = &self.tr[t];
            let s = if tri.mark >> e & 1 != 0 {
                self.sides[t][e]
            } else {
                NONE
            };
            let x = tri.a[e];
            // Crossing the subsegment being split?
            let crossing = s != NONE && self.splits(t, e, split, halves);
            if s == NONE || crossing {
                if x == NONE {
                    if crossing {
                        gap = self.bnd.len();
                        continue;
                    }
                } else {
                    let (n, j) = unpack(x);
                    let nm = self.tr[n].mark;
                    if nm & !FLAGS == stamp {
                        continue;
                    }
                    let v = self.tr[n].v;
                    if crossing
                        || !is_ghost(&v)
                            && incircle(self.p(v[0]), self.p(v[1]), self.p(v[2]), &c) > 0.0
                    {
                        self.tr[n].mark = (nm & FLAGS) | stamp;
                        self.cav.push(n as u32);
                        self.stack.push((n as u32, NEXT[j] as u8, 2));
                        continue;
                    }
                }
            } else if check_enc {
                let sub = &self.subs[s as usize];
                let [u, w] = sub.v;
                if !sub.protected
                    && encroaches(self.p(u), self.p(w), &c, self.cos2)
                    && !self.hit.contains(&s)
                {
                    self.hit.push(s);
                }
            }
            let (a, b) = edge(&tri.v, e);
            self.bnd.push(Bnd {
                a,
                b,
                adj: x,
                sb: s,
                orig: tri.orig,
            });
        }
        if !self.hit.is_empty() {
            return Ins::Encroached;
        }
        // Validity of the star: one boundary cycle (or chain) around `c`,
        // seen counterclockwise, with no vertex inside the cavity.
        let nb = self.bnd.len();
        for k in 0..nb {
            let b = self.bnd[k];
            if orient2d(self.p(b.a), self.p(b.b), &c) <= 0.0 {
                // Beyond (or on) a subsegment: that one is in the way.
                return if check_enc && b.sb != NONE {
                    Ins::Blocked(b.sb)
                } else {
                    Ins::Failed
                };
            }
        }
        let open = usize::from(gap != usize::MAX);
        if nb + open != self.cav.len() + 2 || nb < 2 {
            return Ins::Failed;
        }
        if open == 1 {
            self.bnd.rotate_left(gap);
        }
        for k in 0..nb - 1 {
            if self.bnd[k].b != self.bnd[k + 1].a {
                return Ins::Failed;
            }
        }
        if open == 0 && self.bnd[nb - 1].b != self.bnd[0].a {
            return Ins::Failed;
        }
        // The fan: triangle k = [p, a_k, b_k], linked to k + 1 across
        // `b_k -> p`.
        let p = self.xy.len() as u32;
        self.xy.push(c);
        self.replaced += self.cav.len();
        self.fan.clear();
        for k in 0..nb {
            let s = if k < self.cav.len() {
                self.cav[k] as usize
            } else {
                self.new_tri()
            };
            self.fan.push(s as u32);
        }
        let label = |x: u32| {
            if x == halves[0] {
                halves[1]
            } else if x == halves[2] {
                halves[3]
            } else {
                NONE
            }
        };
        for k in 0..nb {
            let b = self.bnd[k];
            let s = self.fan[k] as usize;
            let next = if k + 1 < nb {
                pack(self.fan[k + 1] as usize, 2)
            } else if open == 0 {
                pack(self.fan[0] as usize, 2)
            } else {
                NONE
            };
            let prev = if k > 0 {
                pack(self.fan[k - 1] as usize, 1)
            } else if open == 0 {
                pack(self.fan[nb - 1] as usize, 1)
            } else {
                NONE
            };
            let sides = if split == NONE {
                [b.sb, NONE, NONE]
            } else {
                [b.sb, label(b.b), label(b.a)]
            };
            let flags = (0..3).fold(0, |f, e| f | u32::from(sides[e] != NONE) << e);
            if flags != 0 {
                // (Read only where a flag is set.)
                self.sides[s] = sides;
            }
            let tri = &mut self.tr[s];
            tri.v = [p, b.a, b.b];
            tri.a = [b.adj, next, prev];
            // The cavity's stamp stays (no search is under way).
            tri.mark = (tri.mark & !FLAGS) | flags;
            tri.orig = b.orig;
            // (A label with no record, the CDT's, has nothing to update.)
            if let Some(sub) = self.subs.get_mut(b.sb as usize) {
                sub.he = pack(s, 0);
            }
            if b.adj != NONE {
                let (o, l) = unpack(b.adj);
                self.tr[o].a[l] = pack(s, 0);
            }
        }
        Ins::Done(p)
    }

    /// Is edge `e` of `t` the one [`CMesh::insert`] splits: it carries
    /// `split` and joins `halves[0]` and `halves[2]` (the CDT's labels are
    /// shared by every piece of an input segment)?
    #[inline]
    fn splits(&self, t: usize, e: usize, split: u32, halves: [u32; 4]) -> bool {
        let (a, b) = edge(&self.tr[t].v, e);
        split != NONE
            && self.sub_at(t, e) == split
            && ((a, b) == (halves[0], halves[2]) || (a, b) == (halves[2], halves[0]))
    }

    /// Lawson flips from the half-edges on `stack`, each given with its
    /// two ends (an entry whose slot no longer holds that edge is stale and
    /// skipped: every flip that moves an edge pushes it again), until every
    /// edge without a subsegment between two finite triangles is locally
    /// Delaunay (exact incircle). After a flip of `t` with neighbour `n`
    /// the four outer edges are pushed so that `n`'s are checked first.
    /// The flipped triangles are pushed on `touched`, `t` before `n`.
    pub(crate) fn restore_delaunay(
        &mut self,
        stack: &mut Vec<(u32, u32, u32)>,
        touched: &mut Vec<u32>,
    ) {
        while let Some((h, a, b)) = stack.pop() {
            let (t, e) = unpack(h);
            let v = self.tr[t].v;
            let x = self.tr[t].a[e];
            if edge(&v, e) != (a, b) || x == NONE || self.sub_at(t, e) != NONE {
                continue;
            }
            let (n, j) = unpack(x);
            let vn = self.tr[n].v;
            if is_ghost(&v) || is_ghost(&vn) {
                continue;
            }
            if incircle(self.p(v[0]), self.p(v[1]), self.p(v[2]), self.p(vn[j])) > 0.0 {
                self.flip(t, e);
                touched.extend([t as u32, n as u32]);
                for (k, f) in [(t, 2), (t, 0), (n, 2), (n, 0)] {
                    stack.push(self.half(k, f));
                }
            }
        }
    }

    /// Half-edge `e` of `t` as a [`CMesh::restore_delaunay`] entry.
    #[inline]
    pub(crate) fn half(&self, t: usize, e: usize) -> (u32, u32, u32) {
        let (a, b) = edge(&self.tr[t].v, e);
        (pack(t, e), a, b)
    }

    /// The finite triangle whose closure contains `p`, by a stochastic
    /// visibility walk from `start` (from the first live triangle when
    /// `start` is dead or a ghost); `None` when the walk leaves the mesh
    /// (across a ghost or a boundary edge). `rng` is the walk's
    /// pseudo-random edge choice.
    pub(crate) fn locate(&self, start: usize, p: &[f64; 2], rng: &mut u32) -> Option<usize> {
        let live = |t: &usize| {
            let v = self.tr[*t].v;
            v[0] != DEAD && !is_ghost(&v)
        };
        let mut t = Some(start)
            .filter(|t| *t < self.tr.len() && live(t))
            .or_else(|| (0..self.tr.len()).find(live))?;
        let limit = 4 * self.tr.len() + 64;
        'walk: for _ in 0..limit {
            let v = self.tr[t].v;
            *rng = rng.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            let r = ((*rng >> 16) % 3) as usize;
            for k in 0..3 {
                let e = (r + k) % 3;
                let (a, b) = edge(&v, e);
                if orient2d(self.p(a), self.p(b), p) < 0.0 {
                    let x = self.tr[t].a[e];
                    if x == NONE || is_ghost(&self.tr[unpack(x).0].v) {
                        return None;
                    }
                    t = unpack(x).0;
                    continue 'walk;
                }
            }
            return Some(t);
        }
        // Safety net (not reached with exact predicates on a valid mesh).
        (0..self.tr.len()).filter(live).find(|&t| {
            let v = self.tr[t].v;
            (0..3).all(|e| {
                let (a, b) = edge(&v, e);
                orient2d(self.p(a), self.p(b), p) >= 0.0
            })
        })
    }

    /// Flips edge `e` of triangle `t` (it must have a neighbour and no
    /// subsegment, and the two triangles must form a convex quadrilateral).
    /// `t` becomes `[vt, a, vn]` and its neighbour `n` becomes `[vn, b, vt]`,
    /// where `t` was `[vt, a, b]` (rotated) and `vn` is opposite in `n`.
    pub(crate) fn flip(&mut self, t: usize, e: usize) {
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
            // (A label with no record, the CDT's, has nothing to update.)
            if let Some(sub) = self.subs.get_mut(s as usize) {
                sub.he = pack(tt, ee);
            }
        }
        self.set_sub(t, 1, NONE);
        self.set_sub(n, 1, NONE);
    }

    /// Checks the invariants of the mesh: every triangle has vertices in
    /// range and is counterclockwise (exact); adjacency is symmetric, never
    /// reaches a dead slot, and each twin is the same edge reversed; an edge
    /// carries the same subsegment on both sides, and an edge with no
    /// neighbour carries one; every subsegment on a half-edge is alive and
    /// has the edge's ends, and every live subsegment's [`Sub::he`] is a
    /// half-edge carrying it. With `delaunay`, also
    /// [`CMesh::check_delaunay`]: the mesh is a constrained Delaunay
    /// triangulation. The CDT's working mesh and the kernel's arrays pass
    /// too: dead slots (`DEAD`) are skipped, ghost triangles (`INF` in
    /// position 2 only, never a ghost across their hull edge) are not
    /// oriented, and with no subsegment records a label is an input segment
    /// index that only has to agree on both sides of its edge.
    pub(crate) fn check(&self, delaunay: bool) -> Result<(), Violation> {
        let bad = |kind: &'static str, detail: String| Err(Violation::new(kind, detail));
        if self.sides.len() != self.tr.len() {
            return bad("storage", "sides and triangles differ in length".into());
        }
        let nv = self.xy.len();
        let labels = self.subs.is_empty();
        for (t, tri) in self.tr.iter().enumerate() {
            let v = tri.v;
            let ghost = is_ghost(&v);
            if v[0] == DEAD {
                continue;
            }
            if (0..3).any(|k| v[k] as usize >= nv && !(ghost && k == 2)) || v[0] == v[1] {
                return bad(
                    "vertex",
                    format!("triangle {t} {v:?} out of range or repeated"),
                );
            }
            if !ghost && orient2d(self.p(v[0]), self.p(v[1]), self.p(v[2])) <= 0.0 {
                return bad("orientation", format!("triangle {t} {v:?}"));
            }
            for e in 0..3 {
                let (a, b) = edge(&v, e);
                let s = self.sub_at(t, e);
                if s != NONE && !labels {
                    let sub = self.subs.get(s as usize);
                    if !sub.is_some_and(|x| x.alive && (x.v == [a, b] || x.v == [b, a])) {
                        return bad(
                            "subsegment",
                            format!("edge {e} of triangle {t} ({a}, {b}) carries {s}"),
                        );
                    }
                }
                let x = tri.a[e];
                if x == NONE {
                    if s == NONE {
                        return bad("boundary", format!("edge {e} of {t} has no subsegment"));
                    }
                    continue;
                }
                let (n, j) = unpack(x);
                if n >= self.tr.len() || self.tr[n].v[0] == DEAD || self.tr[n].a[j] != pack(t, e) {
                    return bad("adjacency", format!("edge {e} of {t} -> ({n}, {j})"));
                }
                if edge(&self.tr[n].v, j) != (b, a) {
                    return bad(
                        "adjacency",
                        format!("edge {e} of {t} and ({n}, {j}) differ"),
                    );
                }
                if ghost && e == 2 && is_ghost(&self.tr[n].v) {
                    return bad(
                        "ghost",
                        format!("ghost {t} has a ghost across its hull edge"),
                    );
                }
                if self.sub_at(n, j) != s {
                    return bad("subsegment", format!("edge {e} of {t}: sides disagree"));
                }
            }
        }
        for (s, sub) in self.subs.iter().enumerate() {
            if !sub.alive || sub.he == NONE {
                continue;
            }
            let (t, e) = unpack(sub.he);
            if t >= self.tr.len() || self.sub_at(t, e) != s as u32 {
                return bad(
                    "subsegment",
                    format!("{s}: its half-edge does not carry it"),
                );
            }
        }
        if delaunay {
            self.check_delaunay(None)?;
        }
        Ok(())
    }

    /// Checks that every edge without a subsegment between two finite
    /// triangles is locally Delaunay (exact incircle; cocircular neighbours
    /// are allowed) or, with the weights `w` of the vertices, locally
    /// regular (exact power test). The adjacency must be valid
    /// ([`CMesh::check`]).
    pub(crate) fn check_delaunay(&self, w: Option<&[f64]>) -> Result<(), Violation> {
        for (t, tri) in self.tr.iter().enumerate() {
            let v = tri.v;
            if v[0] == DEAD || is_ghost(&v) {
                continue;
            }
            for e in 0..3 {
                if tri.a[e] == NONE || self.sub_at(t, e) != NONE {
                    continue;
                }
                let (n, j) = unpack(tri.a[e]);
                if n < t || is_ghost(&self.tr[n].v) {
                    continue;
                }
                let d = self.tr[n].v[j];
                let [a, b, c] = v.map(|x| self.p(x));
                let det = match w {
                    Some(w) => {
                        let [wa, wb, wc] = v.map(|x| w[x as usize]);
                        incircle_weighted(a, b, c, self.p(d), wa, wb, wc, w[d as usize])
                    }
                    None => incircle(a, b, c, self.p(d)),
                };
                if det > 0.0 {
                    return Err(Violation::new(
                        "delaunay",
                        format!("vertex {d} of triangle {n} is inside the circumcircle of triangle {t} {v:?}"),
                    ));
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The mesh of the Delaunay triangulation of `pts`, hull edges as
    /// subsegments.
    fn mesh_of(pts: &[[f64; 2]]) -> CMesh {
        let d = crate::tri::triangulate(pts).unwrap();
        let mut m = CMesh::from_triangles(pts.to_vec(), &d.triangles, &d.neighbors);
        for t in 0..m.tr.len() {
            for e in 0..3 {
                if m.tr[t].a[e] == NONE {
                    new_sub(&mut m, t, e);
                }
            }
        }
        m.check(true).unwrap();
        m
    }

    /// Makes edge `e` of triangle `t` a whole input subsegment (marked on
    /// `t`'s side only); its id.
    fn new_sub(m: &mut CMesh, t: usize, e: usize) -> u32 {
        let k = m.subs.len() as u32;
        m.subs.push(Sub {
            v: edge(&m.tr[t].v, e).into(),
            he: pack(t, e),
            t: [0.0, 1.0],
            parent: 0,
            alive: true,
            stuck: false,
            protected: false,
        });
        m.set_sub(t, e, k);
        k
    }

    /// A triangle whose closed interior holds `c`.
    fn containing(m: &CMesh, c: &[f64; 2]) -> Option<usize> {
        (0..m.tr.len()).find(|&t| {
            let v = m.tr[t].v;
            (0..3).all(|e| {
                let (a, b) = edge(&v, e);
                orient2d(m.p(a), m.p(b), c) >= 0.0
            })
        })
    }

    fn grid(n: usize) -> Vec<[f64; 2]> {
        (0..n * n)
            .map(|k| [(k % n) as f64, (k / n) as f64])
            .collect()
    }

    /// Inserts each point of `cs` (checked after every call): a point
    /// inside gives a new vertex, one on the boundary is refused and
    /// leaves the mesh as it was.
    fn insert_all(m: &mut CMesh, cs: &[[f64; 2]]) -> usize {
        let mut done = 0;
        for c in cs {
            let Some(t) = containing(m, c) else { continue };
            let nt = m.tr.len();
            match m.insert(t, *c, NONE, [NONE; 4], false) {
                Ins::Done(p) => {
                    done += 1;
                    assert_eq!(m.xy[p as usize], *c);
                    assert_eq!(m.tr.len(), nt + 2, "one vertex, two more triangles");
                }
                Ins::Failed => assert_eq!(m.tr.len(), nt),
                _ => unreachable!("no encroachment test asked for"),
            }
            m.check(true)
                .unwrap_or_else(|v| panic!("after inserting {c:?}: {v}"));
        }
        done
    }

    #[test]
    fn the_checker_finds_each_broken_invariant() {
        let m = mesh_of(&grid(4));
        let t = (0..m.tr.len()).find(|&t| m.tr[t].a[0] != NONE).unwrap();
        let mut x = m.clone();
        x.tr[0].v.swap(0, 1);
        assert_eq!(x.check(false).unwrap_err().kind, "orientation");
        let mut x = m.clone();
        x.tr[t].a[0] = pack(t, 0);
        assert_eq!(x.check(false).unwrap_err().kind, "adjacency");
        let mut x = m.clone();
        x.set_sub(t, 0, 0);
        assert_eq!(x.check(false).unwrap_err().kind, "subsegment");
        let mut x = m.clone();
        let (b, e) = (0..x.tr.len())
            .flat_map(|t| (0..3).map(move |e| (t, e)))
            .find(|&(t, e)| x.tr[t].a[e] == NONE)
            .unwrap();
        x.set_sub(b, e, NONE);
        assert_eq!(x.check(false).unwrap_err().kind, "boundary");
        let mut x = m.clone();
        x.subs[0].he = pack(t, 0);
        assert!(x.check(false).is_err());
        let mut x = mesh_of(&[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 0.8]]);
        let t = (0..2)
            .find(|&t| x.tr[t].a.iter().any(|&a| a != NONE))
            .unwrap();
        let e = (0..3).find(|&e| x.tr[t].a[e] != NONE).unwrap();
        x.flip(t, e);
        x.check(false).unwrap();
        assert_eq!(x.check(true).unwrap_err().kind, "delaunay");
    }

    #[test]
    fn the_walk_finds_the_containing_triangle() {
        let m = mesh_of(&grid(6));
        let mut rng = 1;
        for k in 0..100 {
            let c = [
                0.05 * (k % 10) as f64 * 5.0 + 0.1,
                0.049 * (k / 10) as f64 * 5.0,
            ];
            let t = m.locate(k % m.tr.len(), &c, &mut rng).unwrap();
            assert!((0..3).all(|e| {
                let (a, b) = edge(&m.tr[t].v, e);
                orient2d(m.p(a), m.p(b), &c) >= 0.0
            }));
        }
        // Outside the mesh: the walk leaves it.
        assert_eq!(m.locate(0, &[-1.0, 2.0], &mut rng), None);
    }

    #[test]
    fn insert_on_a_grid_cocircular_centres_and_edges() {
        let mut m = mesh_of(&grid(6));
        // Cell centres (cocircular with the cell's corners), then edge
        // midpoints (on an edge), then points on the boundary (refused).
        let centres: Vec<[f64; 2]> = (0..25)
            .map(|k| [(k % 5) as f64 + 0.5, (k / 5) as f64 + 0.5])
            .collect();
        assert_eq!(insert_all(&mut m, &centres), 25);
        let mids: Vec<[f64; 2]> = (0..5).map(|k| [k as f64 + 0.5, 2.0]).collect();
        assert_eq!(insert_all(&mut m, &mids), 5);
        let nt = m.tr.len();
        assert_eq!(insert_all(&mut m, &[[2.5, 0.0], [0.0, 0.0]]), 0);
        assert_eq!(m.tr.len(), nt);
    }

    #[test]
    fn insert_near_collinear_points() {
        // Points on a line and two off it: long thin triangles.
        let mut pts: Vec<[f64; 2]> = (0..12).map(|k| [k as f64, 0.0]).collect();
        pts.extend([[5.5, 1e-3], [3.25, -2e-3]]);
        let mut m = mesh_of(&pts);
        let cs: Vec<[f64; 2]> = (0..20)
            .map(|k| [0.3 + 0.55 * k as f64, if k % 2 == 0 { 1e-4 } else { -1e-4 }])
            .collect();
        assert!(insert_all(&mut m, &cs) > 10);
    }

    #[test]
    fn flips_and_lawson_restore_a_delaunay_mesh() {
        // Random points: flip every flippable edge once (convex
        // quadrilateral), checking the mesh after each flip, then restore
        // the Delaunay property by Lawson flips from all edges.
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut rnd = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut pts: Vec<[f64; 2]> = (0..200).map(|_| [rnd(), rnd()]).collect();
        pts.extend(grid(5).iter().map(|p| [p[0] / 4.0, p[1] / 4.0]));
        let mut m = mesh_of(&pts);
        let mut flips = 0;
        for t in 0..m.tr.len() {
            for e in 0..3 {
                let x = m.tr[t].a[e];
                if x == NONE || m.sub_at(t, e) != NONE {
                    continue;
                }
                let (n, j) = unpack(x);
                let v = m.tr[t].v;
                let (vt, a, b, vn) = (v[e], v[NEXT[e]], v[PREV[e]], m.tr[n].v[j]);
                let convex = orient2d(m.p(vt), m.p(a), m.p(vn)) > 0.0
                    && orient2d(m.p(vn), m.p(b), m.p(vt)) > 0.0;
                if !convex {
                    continue;
                }
                m.flip(t, e);
                flips += 1;
                m.check(false)
                    .unwrap_or_else(|v| panic!("after flip {flips}: {v}"));
                assert_eq!(m.tr[t].v, [vt, a, vn]);
                assert_eq!(m.tr[n].v, [vn, b, vt]);
            }
        }
        assert!(flips > 100);
        assert!(m.check(true).is_err(), "the flips left non-Delaunay edges");
        let mut stack: Vec<_> = (0..m.tr.len())
            .flat_map(|t| (0..3).map(move |e| (t, e)))
            .map(|(t, e)| m.half(t, e))
            .collect();
        let mut touched = Vec::new();
        m.restore_delaunay(&mut stack, &mut touched);
        assert!(!touched.is_empty());
        m.check(true).unwrap();
        // Inserting into the restored mesh keeps it valid.
        let cs: Vec<[f64; 2]> = (0..100).map(|_| [rnd(), rnd()]).collect();
        assert_eq!(insert_all(&mut m, &cs), 100);
    }

    #[test]
    fn a_split_point_beyond_a_subsegment_is_blocked() {
        // A subsegment across the square's diagonal: a point beyond it, seen
        // from a triangle on the other side, is refused with the
        // subsegment named when encroachment is checked.
        let mut m = mesh_of(&grid(3));
        let t = containing(&m, &[0.6, 0.4]).unwrap();
        let e = (0..3).find(|&e| m.tr[t].a[e] != NONE).unwrap();
        let (a, b) = edge(&m.tr[t].v, e);
        let k = new_sub(&mut m, t, e);
        let (n, j) = unpack(m.tr[t].a[e]);
        m.set_sub(n, j, k);
        m.check(true).unwrap();
        // The point beyond the new subsegment, seen from `t`.
        let (pa, pb) = (*m.p(a), *m.p(b));
        let mid = [0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1])];
        let inner = m.tr[t].v[e];
        let pi = *m.p(inner);
        let beyond = [
            mid[0] + 0.1 * (mid[0] - pi[0]),
            mid[1] + 0.1 * (mid[1] - pi[1]),
        ];
        let nt = m.tr.len();
        match m.insert(t, beyond, NONE, [NONE; 4], true) {
            Ins::Blocked(s) if s == k => {}
            Ins::Encroached => assert!(m.hit.contains(&k)),
            Ins::Blocked(s) => panic!("blocked by {s}, not {k}"),
            _ => panic!("inserted beyond a subsegment"),
        }
        assert_eq!(m.tr.len(), nt);
        m.check(true).unwrap();
    }
}
