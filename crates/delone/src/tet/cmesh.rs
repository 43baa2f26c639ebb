//! A mutable tetrahedral mesh that need not stay Delaunay: flips, edge
//! removal, star-shaped (constrained) insertion, and an invariant checker.
//!
//! It wraps the kernel's [`Delaunay3`] (same flat arrays: `v`, packed
//! adjacency `adj` with words `4 * tet + facet`, ghost cells with
//! [`INF`] in position 3, a free list) and adds a vertex → tetrahedron hint
//! table so that stars and edge rings are found locally. Once a flip has
//! been applied, the kernel's own Delaunay insertion must no longer be used
//! on the wrapped structure; insert through [`CMesh::insert_constrained`]
//! or [`CMesh::cone`] instead.
//!
//! Operations (all combinatorial decisions by exact `orient3d`/`insphere`;
//! an operation whose result would contain a tetrahedron that is not
//! strictly positive is refused and leaves the mesh untouched):
//!
//! * [`CMesh::flip23`] — two tetrahedra sharing a face become three
//!   sharing the edge between the two apexes (valid iff that edge crosses
//!   the face's interior);
//! * [`CMesh::remove_edge`] — the `n` tetrahedra around an edge become the
//!   `2n - 4` tetrahedra joining a triangulation of the ring polygon to the
//!   edge's two ends (Shewchuk's edge removal; `n = 3` is the 3-2 flip,
//!   `n = 4` the 4-4 flip). The triangulation is chosen by dynamic
//!   programming over the ring (O(n³)) among those whose tetrahedra are all
//!   positive, minimising a caller-supplied cost (e.g. new edges crossing a
//!   facet to recover);
//! * [`CMesh::cone`] — replaces a set of tetrahedra by the cone of its
//!   boundary to a new point, if that point sees every boundary face;
//! * [`CMesh::insert_constrained`] — Bowyer–Watson insertion whose cavity
//!   grows only across faces the caller does not protect, shrunk until it
//!   is star-shaped from the new point and keeps every protected edge;
//! * [`CMesh::check`] — topology, orientation and the vertex hints.
//!
//! Nothing here recurses; rings are capped ([`MAX_RING`]).
//!
//! # Journal
//!
//! Every operation is logged as "these tetrahedra became those":
//! [`CMesh::replay`] re-applies a log where all the removed tetrahedra are
//! still present (the recovery's next round), [`CMesh::rollback`] undoes the
//! operations since a mark (a failed segment), and
//! [`CMesh::removed_vertices_since`] names the vertices whose tetrahedra an
//! operation removed (which failed segments to retry).
//!
//! # Costs
//!
//! Star walks mark visited slots with a per-slot generation stamp (no
//! linear `contains`, no hash set) and reuse one list, so `find_edge` and
//! `find_face` allocate nothing; the segment walk's `first_hit` stops at the
//! hit, with one `orient3d` per cell for its orientation. Edge removal reuses
//! its ring lists and dynamic-programming tables. `replace` matches the faces
//! of the removed and created tetrahedra (keys sorted by a three-element
//! network and packed into one `u128`) by linear search in two short reused
//! lists (an operation has at most `2 * MAX_RING` outer faces), and logs the
//! faces an operation removes or creates. The recovery's coverage refresh
//! turns the touched faces into candidate triangles with one flag per
//! triangle, locally unless that would cost more than the global pass;
//! face-key lookups over the whole mesh use the `surface` module's
//! `TripleIndex` (triples filed by their least vertex, no hashing).

use crate::tet::local::{face, fkey};
use std::cell::RefCell;

use delone_predicates::{insphere, orient3d};

use super::delaunay::Core;
use super::local::{DEAD, INF};
use super::Delaunay3;

/// Cost of a ring triangle in [`CMesh::remove_edge`] (gets the points).
pub(crate) type TriCost<'c> = &'c dyn Fn(&[[f64; 3]], [u32; 3]) -> i64;
/// Cost of a new ring chord in [`CMesh::remove_edge`] (gets the points).
pub(crate) type EdgeCost<'c> = &'c dyn Fn(&[[f64; 3]], u32, u32) -> i64;

/// Whether [`CMesh::replay`] may replace the given tetrahedra (removed,
/// created).
pub(crate) type ReplayTest<'c> = &'c dyn Fn(&[[u32; 4]], &[[u32; 4]]) -> bool;

/// Longest edge ring [`CMesh::remove_edge`] handles.
pub(crate) const MAX_RING: usize = 24;

/// Shortest ring whose failed removal is memoized (shorter ones are
/// cheaper to retry than to remember).
const MEMO_RING: usize = 6;

/// The `2n - 4` tetrahedra of an edge removal: the triangulation of the ring
/// `r` (`n` vertices) that the dynamic program chose (`choice[i * n + j]` is
/// the apex `k` of the triangle on chord `i j`), each triangle joined to the
/// edge's two ends `a` and `b`.
pub(crate) fn ring_tets(r: &[u32], choice: &[usize], a: u32, b: u32) -> Vec<[u32; 4]> {
    let n = r.len();
    let mut new = Vec::with_capacity(2 * n.saturating_sub(2));
    let mut stack = vec![(0usize, n - 1)];
    while let Some((i, j)) = stack.pop() {
        if j < i + 2 {
            continue;
        }
        let k = choice[i * n + j];
        new.push([r[i], r[k], r[j], b]);
        new.push([r[i], r[j], r[k], a]);
        stack.push((i, k));
        stack.push((k, j));
    }
    new
}

/// Replacements recorded by a [`CMesh`] while logging
/// ([`CMesh::start_log`]): per operation, the tetrahedra it removed and
/// those it created, as vertex tuples. [`CMesh::replay`] applies them to
/// another mesh on (a superset of) the same points.
#[derive(Debug, Default, Clone)]
pub(crate) struct OpLog {
    /// The removed, then the created tetrahedra of each operation.
    tets: Vec<[u32; 4]>,
    /// The slot of each tetrahedron of `tets` where it was recorded (a
    /// hint for finding it again).
    slots: Vec<u32>,
    /// Per operation: start in `tets`, removed count, created count.
    ops: Vec<(u32, u16, u16)>,
}

/// True when `q` is an even permutation of `tv` (same orientation).
fn even(tv: [u32; 4], q: [u32; 4]) -> bool {
    let pos = q.map(|x| tv.iter().position(|&y| y == x).unwrap_or(0));
    let mut inv = 0;
    for i in 0..4 {
        for j in i + 1..4 {
            inv += usize::from(pos[i] > pos[j]);
        }
    }
    inv % 2 == 0
}

/// A mutable tetrahedralization (see the module documentation).
#[derive(Debug, Clone)]
pub(crate) struct CMesh<'a> {
    /// The wrapped arrays and points.
    pub(crate) dt: Delaunay3<'a>,
    /// Per vertex: a live tetrahedron containing it (or `DEAD`).
    vt: Vec<u32>,
    /// 2-3 flips performed.
    pub(crate) flips23: usize,
    /// Edge removals performed.
    pub(crate) removals: usize,
    /// Finite faces (sorted triples) removed or created by the
    /// replacements since the last [`CMesh::take_touched`] (unsorted, with
    /// repeats; at least one per replacement).
    touched: Vec<[u32; 3]>,
    /// Edge removals known to be impossible (rings of [`MEMO_RING`] or more
    /// vertices): `[a, b, ring…]` with the ring rotated to start at its
    /// least vertex. Whether a removal is possible
    /// depends only on this (exact signs), so a failure is never retried;
    /// the set may be carried over to another mesh on the same points
    /// ([`CMesh::take_failed`], [`CMesh::set_failed`]).
    failed: crate::geom::ids::IdSet<Vec<u32>>,
    /// The replacements since [`CMesh::start_log`], when logging.
    log: Option<OpLog>,
    /// Scratch of the star walks (a per-slot visit stamp, so a walk is
    /// linear in the star's size, and a reusable list).
    walk: RefCell<Walk>,
    /// Scratch of [`CMesh::replace`]: open outer faces and open new faces.
    outer: Vec<(u128, u32)>,
    open: Vec<(u128, u32)>,
    /// Scratch of [`CMesh::remove_edge`]: the ring's tetrahedra and
    /// vertices, and the dynamic program's tables.
    ring_tets: Vec<u32>,
    ring_verts: Vec<u32>,
    dp_best: Vec<i64>,
    dp_choice: Vec<usize>,
    /// Scratch of the new slots of a flip or edge removal.
    ids: Vec<u32>,
}

/// Scratch of [`CMesh::star_until`]: visit stamps per slot (equal to `gen`
/// when visited by the current walk) and a list for
/// [`CMesh::find_edge`]/[`CMesh::find_face`].
#[derive(Debug, Default, Clone)]
struct Walk {
    stamp: Vec<u32>,
    gen: u32,
    buf: Vec<u32>,
    /// The visited set of [`CMesh::visit`] (stamps equal to `vgen`).
    vstamp: Vec<u32>,
    vgen: u32,
}

impl<'a> CMesh<'a> {
    /// Wraps a tetrahedralization.
    pub(crate) fn new(dt: Delaunay3<'a>) -> Self {
        let mut vt = vec![DEAD; dt.points().len()];
        for (t, tv) in dt.core.v.iter().enumerate() {
            if tv[0] == DEAD {
                continue;
            }
            for &w in tv {
                if w != INF && vt[w as usize] == DEAD {
                    vt[w as usize] = t as u32;
                }
            }
        }
        CMesh {
            dt,
            vt,
            flips23: 0,
            removals: 0,
            touched: Vec::new(),
            failed: Default::default(),
            log: None,
            walk: RefCell::new(Walk::default()),
            outer: Vec::new(),
            open: Vec::new(),
            ring_tets: Vec::new(),
            ring_verts: Vec::new(),
            dp_best: Vec::new(),
            dp_choice: Vec::new(),
            ids: Vec::new(),
        }
    }

    /// Starts recording every replacement (flip, edge removal) in a fresh
    /// [`OpLog`].
    pub(crate) fn start_log(&mut self) {
        self.log = Some(OpLog::default());
    }

    /// Stops recording and returns what was recorded.
    pub(crate) fn take_log(&mut self) -> Option<OpLog> {
        self.log.take()
    }

    /// Re-applies the operations of `log` (recorded on another mesh of a
    /// prefix of these points), in order, each only when every tetrahedron
    /// it removed is a tetrahedron of this mesh (same vertex set) and
    /// `allowed(removed, created)` holds; the others are skipped. Such a
    /// replacement is valid here exactly as it was there: the removed
    /// tetrahedra are the same geometric cells, so the created ones fill the
    /// same region with the same (exact) orientations and the same
    /// boundary faces. Counts as the flips and removals it re-applies;
    /// returns how many it re-applied.
    pub(crate) fn replay(&mut self, log: &OpLog, allowed: ReplayTest<'_>) -> usize {
        let mut done = 0;
        let (mut slots, mut buf, mut ids) = (Vec::new(), Vec::new(), Vec::new());
        // Recorded slot -> slot here of the same tetrahedron (when a
        // replayed operation created it; else the recorded slot is tried).
        let mut map: Vec<u32> = Vec::new();
        for &(s, no, nn) in &log.ops {
            let (s, no, nn) = (s as usize, usize::from(no), usize::from(nn));
            let (old, new) = log.tets[s..s + no + nn].split_at(no);
            let (old_at, new_at) = log.slots[s..s + no + nn].split_at(no);
            let hint = |i: usize| {
                let r = old_at[i];
                map.get(r as usize)
                    .copied()
                    .filter(|&x| x != DEAD)
                    .unwrap_or(r)
            };
            if !self.locate_tets(old, hint, &mut slots, &mut buf) || !allowed(old, new) {
                continue;
            }
            self.replace_into(&slots, new, &mut ids);
            for (&r, &x) in new_at.iter().zip(&ids) {
                if map.len() <= r as usize {
                    map.resize(r as usize + 1, DEAD);
                }
                map[r as usize] = x;
            }
            // Only a 2-3 flip turns two tetrahedra into three.
            if (no, nn) == (2, 3) {
                self.flips23 += 1;
            } else {
                self.removals += 1;
            }
            done += 1;
        }
        done
    }

    /// Calls `f(op, w)` for every vertex `w` (not [`INF`], with repeats)
    /// of the tetrahedra removed by the operations logged since `mark`
    /// ([`CMesh::log_mark`]), `op` being the operation's index in the log.
    /// The tetrahedra an operation creates have the same vertices.
    pub(crate) fn removed_vertices_since(&self, mark: usize, mut f: impl FnMut(usize, u32)) {
        let Some(log) = &self.log else {
            return;
        };
        for (i, &(s, no, _)) in log.ops.iter().enumerate().skip(mark) {
            let s = s as usize;
            for tv in &log.tets[s..s + usize::from(no)] {
                for &w in tv {
                    if w != INF {
                        f(i, w);
                    }
                }
            }
        }
    }

    /// The number of operations logged so far (a mark for
    /// [`CMesh::rollback`]); 0 when not logging.
    pub(crate) fn log_mark(&self) -> usize {
        self.log.as_ref().map_or(0, |l| l.ops.len())
    }

    /// Undoes, newest first, the operations logged since `mark`
    /// ([`CMesh::log_mark`]) and forgets them: each created set of
    /// tetrahedra is replaced back by the removed one (valid for the same
    /// reason as [`CMesh::replay`]).
    pub(crate) fn rollback(&mut self, mark: usize) {
        let Some(mut log) = self.log.take() else {
            return;
        };
        let (mut slots, mut buf, mut ids) = (Vec::new(), Vec::new(), Vec::new());
        for &(s, no, nn) in log.ops[mark.min(log.ops.len())..].iter().rev() {
            let (s, no, nn) = (s as usize, usize::from(no), usize::from(nn));
            let (old, new) = log.tets[s..s + no + nn].split_at(no);
            let new_at = &log.slots[s + no..s + no + nn];
            let found = self.locate_tets(new, |i| new_at[i], &mut slots, &mut buf);
            debug_assert!(found, "rollback: a created tetrahedron is gone");
            if !found {
                break;
            }
            self.replace_into(&slots, old, &mut ids);
            if (no, nn) == (2, 3) {
                self.flips23 -= 1;
            } else {
                self.removals -= 1;
            }
        }
        if let Some(&(s, _, _)) = log.ops.get(mark) {
            log.tets.truncate(s as usize);
            log.slots.truncate(s as usize);
            log.ops.truncate(mark);
        }
        self.log = Some(log);
    }

    /// The slots of tetrahedra `old` (vertex tuples, each adjacent to an
    /// earlier one) into `slots`, trying slot `hint(i)` for `old[i]` first;
    /// false when one is not in the mesh.
    fn locate_tets(
        &self,
        old: &[[u32; 4]],
        hint: impl Fn(usize) -> u32,
        slots: &mut Vec<u32>,
        buf: &mut Vec<u32>,
    ) -> bool {
        slots.clear();
        let c = self.core();
        let same = |t: u32, q: &[u32; 4]| {
            let tv = c.v.get(t as usize).copied().unwrap_or([DEAD; 4]);
            tv[0] != DEAD && q.iter().all(|w| tv.contains(w))
        };
        'next: for (i, q) in old.iter().enumerate() {
            let h = hint(i);
            if same(h, q) {
                slots.push(h);
                continue;
            }
            for j in 0..slots.len() {
                for f in 0..4 {
                    let n = c.adj[slots[j] as usize][f] >> 2;
                    if same(n, q) {
                        slots.push(n);
                        continue 'next;
                    }
                }
            }
            if i > 0 {
                return false;
            }
            let Some(&w) = q.iter().find(|&&w| w != INF) else {
                return false;
            };
            if self.vt.get(w as usize).is_none_or(|&t| t == DEAD) {
                return false;
            }
            match self.star_until(w, buf, |t| same(t, q)) {
                Some(t) => slots.push(t),
                None => return false,
            }
        }
        true
    }

    /// The finite faces (sorted triples; sorted, distinct) created or
    /// destroyed by the replacements since the previous call; every
    /// tetrahedron created or destroyed since then has a face in this list
    /// (a replacement removes and creates two or more face-connected
    /// tetrahedra, so each has a face inside it).
    #[cfg_attr(not(test), allow(dead_code))]
    pub(crate) fn take_touched(&mut self) -> Vec<[u32; 3]> {
        let mut out = std::mem::take(&mut self.touched);
        out.sort_unstable();
        out.dedup();
        out
    }

    /// [`CMesh::take_touched`] unsorted, with repeats (cheaper when the
    /// caller deduplicates what it derives from the faces).
    pub(crate) fn take_touched_raw(&mut self) -> Vec<[u32; 3]> {
        std::mem::take(&mut self.touched)
    }

    /// How many faces were logged since the last [`CMesh::take_touched`]
    /// (with repeats).
    pub(crate) fn touched_len(&self) -> usize {
        self.touched.len()
    }

    /// Forgets the faces logged since the last [`CMesh::take_touched`].
    pub(crate) fn clear_touched(&mut self) {
        self.touched.clear();
    }

    /// Takes the known impossible edge removals (see [`CMesh::set_failed`]).
    pub(crate) fn take_failed(&mut self) -> crate::geom::ids::IdSet<Vec<u32>> {
        std::mem::take(&mut self.failed)
    }

    /// Sets the known impossible edge removals, from [`CMesh::take_failed`]
    /// of a mesh whose points are a prefix of (or equal to) these points.
    pub(crate) fn set_failed(&mut self, failed: crate::geom::ids::IdSet<Vec<u32>>) {
        self.failed = failed;
    }

    /// The points (input, then inserted).
    #[inline]
    pub(crate) fn pts(&self) -> &[[f64; 3]] {
        self.dt.points()
    }

    #[inline]
    fn core(&self) -> &Core {
        &self.dt.core
    }

    /// True when finite `tv` is strictly positive.
    #[inline]
    pub(crate) fn positive(&self, tv: [u32; 4]) -> bool {
        let p = self.pts();
        let g = |i: usize| &p[tv[i] as usize];
        orient3d(g(0), g(1), g(2), g(3)) < 0.0
    }

    /// Live tetrahedra (ghosts included) containing vertex `u`.
    pub(crate) fn star(&self, u: u32) -> Vec<u32> {
        let mut out = Vec::with_capacity(32);
        self.star_until(u, &mut out, |_| false);
        out
    }

    /// Walks the star of `u` into `out` (breadth first from the hint),
    /// stopping early at the first tetrahedron for which `stop` holds;
    /// returns it.
    fn star_until(&self, u: u32, out: &mut Vec<u32>, stop: impl Fn(u32) -> bool) -> Option<u32> {
        let c = self.core();
        let mut start = self.vt.get(u as usize).copied().unwrap_or(DEAD);
        if start == DEAD || c.v[start as usize][0] == DEAD || !c.v[start as usize].contains(&u) {
            match c.v.iter().position(|tv| tv[0] != DEAD && tv.contains(&u)) {
                Some(t) => start = t as u32,
                None => return None,
            }
        }
        out.clear();
        out.push(start);
        // Visited slots carry this walk's stamp (no search, no set).
        let mut w = self.walk.borrow_mut();
        let w = &mut *w;
        w.gen = w.gen.wrapping_add(1);
        if w.gen == 0 {
            w.stamp.fill(0);
            w.gen = 1;
        }
        if w.stamp.len() < c.v.len() {
            w.stamp.resize(c.v.len(), 0);
        }
        let gen = w.gen;
        let stamp = &mut w.stamp;
        stamp[start as usize] = gen;
        let mut i = 0;
        while i < out.len() {
            let t = out[i];
            i += 1;
            if stop(t) {
                return Some(t);
            }
            let tv = c.v[t as usize];
            for (f, &x) in tv.iter().enumerate() {
                if x == u {
                    continue;
                }
                let n = c.adj[t as usize][f] >> 2;
                if stamp[n as usize] != gen {
                    stamp[n as usize] = gen;
                    out.push(n);
                }
            }
        }
        None
    }

    /// Empties the visited set of [`CMesh::visit`].
    pub(crate) fn visit_begin(&self) {
        let mut w = self.walk.borrow_mut();
        w.vgen = w.vgen.wrapping_add(1);
        if w.vgen == 0 {
            w.vstamp.fill(0);
            w.vgen = 1;
        }
    }

    /// Adds slot `x` to the visited set; true when it was not in it (a
    /// stamp per slot: no hashing). One set at a time
    /// ([`CMesh::visit_begin`]).
    pub(crate) fn visit(&self, x: u32) -> bool {
        let mut w = self.walk.borrow_mut();
        let w = &mut *w;
        let n = self.dt.core.v.len();
        if w.vstamp.len() < n {
            w.vstamp.resize(n, 0);
        }
        let s = &mut w.vstamp[x as usize];
        let new = *s != w.vgen;
        *s = w.vgen;
        new
    }

    /// The first tetrahedron, in [`CMesh::star`]'s order, of `u`'s star for
    /// which `stop` holds (the walk stops there; no allocation).
    pub(crate) fn star_find(&self, u: u32, stop: impl Fn(u32) -> bool) -> Option<u32> {
        let mut buf = std::mem::take(&mut self.walk.borrow_mut().buf);
        let r = self.star_until(u, &mut buf, stop);
        self.walk.borrow_mut().buf = buf;
        r
    }

    /// A live tetrahedron containing edge `u v`.
    pub(crate) fn find_edge(&self, u: u32, v: u32) -> Option<u32> {
        let c = self.core();
        self.star_find(u, |t| c.v[t as usize].contains(&v))
    }

    /// A live tetrahedron (ghosts included) having face `a b c`.
    pub(crate) fn find_face(&self, a: u32, b: u32, c: u32) -> Option<u32> {
        let core = self.core();
        self.star_find(a, |t| {
            let tv = core.v[t as usize];
            tv.contains(&b) && tv.contains(&c)
        })
    }

    /// The tetrahedra around edge `a b` (starting at `t`, which contains it)
    /// and the ring vertices, so that `[a, b, ring[i], ring[i + 1]]` (cyclic)
    /// is `tets[i]`, positively oriented. `None` through a ghost or beyond
    /// [`MAX_RING`].
    pub(crate) fn edge_ring(&self, t: u32, a: u32, b: u32) -> Option<(Vec<u32>, Vec<u32>)> {
        self.edge_ring_with(t, a, b, false)
    }

    /// [`CMesh::edge_ring`]; with `ghosts`, rings through ghost cells are
    /// returned too ([`INF`] then appears in the ring).
    pub(crate) fn edge_ring_with(
        &self,
        t: u32,
        a: u32,
        b: u32,
        ghosts: bool,
    ) -> Option<(Vec<u32>, Vec<u32>)> {
        let mut tets = Vec::with_capacity(8);
        let mut ring = Vec::with_capacity(8);
        self.edge_ring_into(t, a, b, ghosts, &mut tets, &mut ring)
            .then_some((tets, ring))
    }

    /// [`CMesh::edge_ring_with`] into the given lists (cleared first);
    /// false (lists unspecified) where that returns `None`.
    fn edge_ring_into(
        &self,
        t: u32,
        a: u32,
        b: u32,
        ghosts: bool,
        tets: &mut Vec<u32>,
        ring: &mut Vec<u32>,
    ) -> bool {
        tets.clear();
        ring.clear();
        let c = self.core();
        let tv = c.v[t as usize];
        if tv[0] == DEAD || !tv.contains(&a) || !tv.contains(&b) {
            return false;
        }
        let mut o = tv.iter().copied().filter(|&w| w != a && w != b);
        let (Some(c0), Some(d0)) = (o.next(), o.next()) else {
            return false;
        };
        let (mut x, mut y) = if even(tv, [a, b, c0, d0]) {
            (c0, d0)
        } else {
            (d0, c0)
        };
        let mut cur = t;
        loop {
            let cv = c.v[cur as usize];
            if (!ghosts && cv.contains(&INF)) || tets.len() >= MAX_RING {
                return false;
            }
            tets.push(cur);
            ring.push(x);
            let Some(ix) = cv.iter().position(|&w| w == x) else {
                return false;
            };
            let next = c.adj[cur as usize][ix] >> 2;
            if next == t {
                return true;
            }
            let nv = c.v[next as usize];
            let Some(&z) = nv.iter().find(|&&w| w != a && w != b && w != y) else {
                return false;
            };
            cur = next;
            x = y;
            y = z;
        }
    }

    /// Replaces tetrahedra `old` (a connected set) by `new`, relinking
    /// everything by face keys. Returns the new slots.
    pub(crate) fn replace(&mut self, old: &[u32], new: &[[u32; 4]]) -> Vec<u32> {
        let mut ids = Vec::with_capacity(new.len());
        self.replace_into(old, new, &mut ids);
        ids
    }

    /// [`CMesh::replace`] writing the new slots into `ids` (cleared first;
    /// no allocation when it has room).
    pub(crate) fn replace_into(&mut self, old: &[u32], new: &[[u32; 4]], ids: &mut Vec<u32>) {
        // Faces are matched by linear search in two short lists (an
        // operation has at most 2 * MAX_RING outer faces): cheaper than
        // hashing for the 2-3 flips and small rings that dominate.
        let mut outer = std::mem::take(&mut self.outer);
        let mut open = std::mem::take(&mut self.open);
        outer.clear();
        open.clear();
        // Touched faces, each once per operation: the faces between two
        // removed tetrahedra and those between two created ones (below) —
        // the faces that disappear or appear. The outer faces (shared by
        // the removed and the created tetrahedra) stay; but every removed or
        // created tetrahedron has a face inside the operation (both sets
        // are connected and have two or more members), so a tetrahedron
        // whose four vertices lie on some triangle is still seen through
        // one of its faces.
        let finite = |k: &[u32; 3]| !k.contains(&INF);
        // A sorted triple as one integer (one comparison per candidate).
        let pack = |k: [u32; 3]| u128::from(k[0]) << 64 | u128::from(k[1]) << 32 | u128::from(k[2]);
        let touched0 = self.touched.len();
        let mut first_outer = None;
        {
            let c = &self.dt.core;
            for &t in old {
                let tv = c.v[t as usize];
                for f in 0..4 {
                    let w = c.adj[t as usize][f];
                    let k = fkey(face(tv, f));
                    if !old.contains(&(w >> 2)) {
                        if first_outer.is_none() && finite(&k) {
                            first_outer = Some(k);
                        }
                        outer.push((pack(k), w));
                    } else if w >> 2 > t && finite(&k) {
                        self.touched.push(k);
                    }
                }
            }
        }
        let c = &mut self.dt.core;
        if let Some(log) = &mut self.log {
            let start = log.tets.len() as u32;
            log.tets.extend(old.iter().map(|&t| c.v[t as usize]));
            log.slots.extend_from_slice(old);
            log.ops.push((start, old.len() as u16, new.len() as u16));
        }
        for &t in old {
            c.release(t);
        }
        ids.clear();
        ids.extend(new.iter().map(|&tv| c.alloc(tv)));
        if let Some(log) = &mut self.log {
            log.tets.extend_from_slice(new);
            log.slots.extend_from_slice(ids);
        }
        for (&x, &tv) in ids.iter().zip(new) {
            for f in 0..4 {
                let k = fkey(face(tv, f));
                let pk = pack(k);
                if let Some(i) = outer.iter().position(|e| e.0 == pk) {
                    let w = outer.swap_remove(i).1;
                    c.link(x, f, w >> 2, (w & 3) as usize);
                } else if let Some(i) = open.iter().position(|e| e.0 == pk) {
                    let w = open.swap_remove(i).1;
                    c.link(x, f, w >> 2, (w & 3) as usize);
                    if finite(&k) {
                        self.touched.push(k);
                    }
                } else {
                    open.push((pk, 4 * x + f as u32));
                }
            }
        }
        debug_assert!(
            outer.is_empty() && open.is_empty(),
            "replace: unmatched faces"
        );
        // Every replacement logs at least one face (`touched_len` is a
        // change stamp for callers).
        if self.touched.len() == touched0 {
            if let Some(k) = first_outer {
                self.touched.push(k);
            }
        }
        self.outer = outer;
        self.open = open;
        if let Some(&x) = ids.first() {
            c.last = x;
        }
        for (&x, tv) in ids.iter().zip(new) {
            for &w in tv {
                if w != INF {
                    if self.vt.len() <= w as usize {
                        self.vt.resize(w as usize + 1, DEAD);
                    }
                    self.vt[w as usize] = x;
                }
            }
        }
    }

    /// 2-3 flip of the face opposite local vertex `f` of tetrahedron `t`:
    /// false (nothing changed) when a ghost is involved or the edge between
    /// the two apexes does not cross the face's interior.
    pub(crate) fn flip23(&mut self, t: u32, f: usize) -> bool {
        let c = self.core();
        let tv = c.v[t as usize];
        if tv[0] == DEAD {
            return false;
        }
        let w = c.adj[t as usize][f];
        let (u, g) = (w >> 2, (w & 3) as usize);
        let uv = c.v[u as usize];
        if tv.contains(&INF) || uv.contains(&INF) {
            return false;
        }
        let (p, q) = (tv[f], uv[g]);
        let [x, y, z] = face(tv, f);
        let new = [[x, y, q, p], [y, z, q, p], [z, x, q, p]];
        if !new.iter().all(|&n| self.positive(n)) {
            return false;
        }
        let mut ids = std::mem::take(&mut self.ids);
        self.replace_into(&[t, u], &new, &mut ids);
        self.ids = ids;
        self.flips23 += 1;
        true
    }

    /// Removes edge `a b` (contained in `t`): the tetrahedra around it are
    /// replaced by a triangulation of its ring joined to `a` and `b`, the
    /// one of least total cost (`tri_cost` per ring triangle, `edge_cost`
    /// per new ring chord; both get the points) among those whose tetrahedra are all positive.
    /// Returns the cost, or `None` (nothing changed) when no such
    /// triangulation exists or the ring is too long.
    ///
    /// A convex-hull edge `a b` whose two hull faces `a b c`, `a b d` are
    /// coplanar is removed too (the hull's 2-2 flip): the ring minus the
    /// infinite vertex is an open chain `c … d` closed by the new hull edge
    /// `c d`, and the two new hull faces `c d a`, `c d b` get ghost cells.
    pub(crate) fn remove_edge(
        &mut self,
        t: u32,
        a: u32,
        b: u32,
        tri_cost: TriCost<'_>,
        edge_cost: EdgeCost<'_>,
    ) -> Option<i64> {
        // The ring lists are reused scratch (no allocation per call).
        let (mut tets, mut r) = (
            std::mem::take(&mut self.ring_tets),
            std::mem::take(&mut self.ring_verts),
        );
        let out = if !self.edge_ring_into(t, a, b, true, &mut tets, &mut r) {
            None
        } else if r.len() < MEMO_RING {
            self.remove_ring(&tets, &mut r, a, b, tri_cost, edge_cost)
        } else {
            let key = {
                let m = (0..r.len()).min_by_key(|&i| r[i]).unwrap_or(0);
                let mut k = Vec::with_capacity(r.len() + 2);
                k.extend([a, b]);
                k.extend(r[m..].iter().chain(&r[..m]));
                k
            };
            if self.failed.contains(&key) {
                None
            } else {
                let out = self.remove_ring(&tets, &mut r, a, b, tri_cost, edge_cost);
                if out.is_none() {
                    self.failed.insert(key);
                }
                out
            }
        };
        self.ring_tets = tets;
        self.ring_verts = r;
        out
    }

    /// [`CMesh::remove_edge`] once the ring is known.
    fn remove_ring(
        &mut self,
        tets: &[u32],
        r: &mut Vec<u32>,
        a: u32,
        b: u32,
        tri_cost: TriCost<'_>,
        edge_cost: EdgeCost<'_>,
    ) -> Option<i64> {
        let mut ghosts = Vec::new();
        if let Some(k) = r.iter().position(|&w| w == INF) {
            r.rotate_left(k + 1);
            r.pop();
            let (c0, d0) = (r[0], *r.last()?);
            let p = self.pts();
            let g = |w: u32| &p[w as usize];
            if r.len() < 3 || orient3d(g(a), g(b), g(c0), g(d0)) != 0.0 {
                return None;
            }
            let inner = g(r[1]);
            for e in [a, b] {
                let f = if orient3d(g(c0), g(d0), g(e), inner) > 0.0 {
                    [c0, d0, e, INF]
                } else {
                    [d0, c0, e, INF]
                };
                ghosts.push(f);
            }
        }
        let n = r.len();
        if n < 3 {
            return None;
        }
        const NO: i64 = i64::MAX / 4;
        let (mut best, mut choice) = (
            std::mem::take(&mut self.dp_best),
            std::mem::take(&mut self.dp_choice),
        );
        best.clear();
        best.resize(n * n, NO);
        choice.clear();
        choice.resize(n * n, 0);
        for i in 0..n - 1 {
            best[i * n + i + 1] = 0;
        }
        for len in 2..n {
            for i in 0..n - len {
                let j = i + len;
                let chord = if i == 0 && j == n - 1 {
                    0
                } else {
                    edge_cost(self.pts(), r[i], r[j])
                };
                for k in i + 1..j {
                    let (l, rr) = (best[i * n + k], best[k * n + j]);
                    if l >= NO || rr >= NO {
                        continue;
                    }
                    let tri = [r[i], r[k], r[j]];
                    if !self.positive([tri[0], tri[1], tri[2], b])
                        || !self.positive([tri[0], tri[2], tri[1], a])
                    {
                        continue;
                    }
                    let c = l + rr + tri_cost(self.pts(), tri) + chord;
                    if c < best[i * n + j] {
                        best[i * n + j] = c;
                        choice[i * n + j] = k;
                    }
                }
            }
        }
        let total = best[n - 1];
        let new = (total < NO).then(|| ring_tets(r, &choice, a, b));
        self.dp_best = best;
        self.dp_choice = choice;
        let mut new = new?;
        new.extend(ghosts);
        let mut ids = std::mem::take(&mut self.ids);
        self.replace_into(tets, &new, &mut ids);
        self.ids = ids;
        self.removals += 1;
        Some(total)
    }

    /// Replaces the finite tetrahedra `cavity` (a connected set) by the cone
    /// of its boundary faces to the new point `p`, which must see every
    /// boundary face strictly from inside; `None` (nothing changed)
    /// otherwise. Returns the new vertex id.
    // Used by the tests today and by 3D refinement next.
    #[cfg_attr(not(test), allow(dead_code))]
    pub(crate) fn cone(&mut self, cavity: &[u32], p: [f64; 3]) -> Option<u32> {
        let id = self.pts().len() as u32;
        let new = {
            let c = self.core();
            let pts = self.pts();
            let mut new = Vec::new();
            for &t in cavity {
                let tv = c.v[t as usize];
                if tv[0] == DEAD || tv.contains(&INF) {
                    return None;
                }
                for f in 0..4 {
                    if cavity.contains(&(c.adj[t as usize][f] >> 2)) {
                        continue;
                    }
                    let [x, y, z] = face(tv, f);
                    let g = |w: u32| &pts[w as usize];
                    if orient3d(g(x), g(y), g(z), &p) >= 0.0 {
                        return None;
                    }
                    new.push([x, y, z, id]);
                }
            }
            new
        };
        self.dt.points.to_mut().push(p);
        self.vt.push(DEAD);
        self.replace(cavity, &new);
        Some(id)
    }

    /// Inserts `p` by a constrained Bowyer–Watson cavity: the tetrahedra
    /// whose circumsphere strictly contains `p`, connected to the one
    /// containing it across faces for which `protected_face` is false;
    /// tetrahedra are then dropped from the cavity until every protected
    /// edge (`protected_edge`) survives and `p` sees every boundary face.
    /// `None` (nothing changed) when `p` is outside the hull, on a vertex,
    /// or the containing tetrahedron itself must be dropped.
    // Used by the tests today and by 3D refinement next.
    #[cfg_attr(not(test), allow(dead_code))]
    pub(crate) fn insert_constrained(
        &mut self,
        p: [f64; 3],
        protected_face: &dyn Fn([u32; 3]) -> bool,
        protected_edge: &dyn Fn(u32, u32) -> bool,
    ) -> Option<u32> {
        let mut rng = 0x2545_F491u32;
        let c = self.core();
        let pts = self.pts();
        let t0 = c.walk(pts, &p, c.last, &mut rng);
        let tv0 = c.v[t0 as usize];
        if tv0.contains(&INF) || tv0.iter().any(|&w| pts[w as usize] == p) {
            return None;
        }
        let inside = |t: u32| {
            let tv = c.v[t as usize];
            if tv.contains(&INF) {
                return false;
            }
            let g = |i: usize| &pts[tv[i] as usize];
            insphere(g(1), g(0), g(2), g(3), &p) > 0.0
        };
        let mut cav = vec![t0];
        let mut i = 0;
        while i < cav.len() {
            let t = cav[i];
            i += 1;
            let tv = c.v[t as usize];
            for f in 0..4 {
                let n = c.adj[t as usize][f] >> 2;
                if cav.contains(&n) || protected_face(fkey(face(tv, f))) || !inside(n) {
                    continue;
                }
                cav.push(n);
            }
        }
        // Shrink: drop a tetrahedron owning an invisible boundary face or a
        // protected edge that would become interior, until none is left.
        loop {
            let mut drop = None;
            'scan: for &t in &cav {
                let tv = c.v[t as usize];
                for f in 0..4 {
                    if cav.contains(&(c.adj[t as usize][f] >> 2)) {
                        continue;
                    }
                    let [x, y, z] = face(tv, f).map(|w| &pts[w as usize]);
                    if orient3d(x, y, z, &p) >= 0.0 {
                        drop = Some(t);
                        break 'scan;
                    }
                }
                for (i, j) in [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)] {
                    let (a, b) = (tv[i], tv[j]);
                    if !protected_edge(a, b) {
                        continue;
                    }
                    // Interior iff every tetrahedron around it is in the cavity.
                    let interior = match self.edge_ring(t, a, b) {
                        Some((ring, _)) => ring.iter().all(|x| cav.contains(x)),
                        None => false,
                    };
                    if interior {
                        drop = Some(t);
                        break 'scan;
                    }
                }
            }
            match drop {
                None => break,
                Some(t) if t == t0 => return None,
                Some(t) => cav.retain(|&x| x != t),
            }
        }
        self.cone(&cav, p)
    }

    /// Checks the invariants: the kernel's topology and orientation checks,
    /// and that every vertex hint names a live tetrahedron containing it.
    // Used by the tests today and by 3D refinement next.
    #[cfg_attr(not(test), allow(dead_code))]
    pub(crate) fn check(&self) -> Result<(), String> {
        self.dt.check_topology().map_err(|e| format!("{e:?}"))?;
        let c = self.core();
        for (w, &t) in self.vt.iter().enumerate() {
            if t == DEAD {
                continue;
            }
            let tv = c.v[t as usize];
            if tv[0] == DEAD || !tv.contains(&(w as u32)) {
                return Err(format!("vertex {w}: hint {t} does not contain it"));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn finite_tets(m: &CMesh<'_>) -> usize {
        m.dt.num_tets()
    }

    /// `n` points scattered in the unit cube (irrational strides).
    fn scattered(n: usize) -> Vec<[f64; 3]> {
        (0..n)
            .map(|i| {
                let x = (i as f64 * 0.618_034).fract();
                let y = (i as f64 * 0.414_213_5).fract();
                let z = (i as f64 * 0.732_050_8).fract();
                [x, y, z]
            })
            .collect()
    }

    fn has_edge(m: &CMesh<'_>, a: u32, b: u32) -> bool {
        m.find_edge(a, b).is_some()
    }

    #[test]
    fn rings_are_positively_ordered() {
        let pts = scattered(40);
        let m = CMesh::new(Delaunay3::from_points(&pts).unwrap());
        m.check().unwrap();
        let mut rings = 0;
        for (t, tv) in m.dt.core.v.iter().enumerate() {
            if tv[0] == DEAD || tv.contains(&INF) {
                continue;
            }
            if let Some((tets, r)) = m.edge_ring(t as u32, tv[0], tv[1]) {
                rings += 1;
                for i in 0..r.len() {
                    let q = [tv[0], tv[1], r[i], r[(i + 1) % r.len()]];
                    assert!(m.positive(q));
                    let x = m.dt.core.v[tets[i] as usize];
                    assert!(q.iter().all(|w| x.contains(w)));
                }
            }
        }
        assert!(rings > 10);
    }

    #[test]
    fn flips_and_edge_removal_keep_the_mesh_valid() {
        // Three points around the z axis and two poles: edge 3-4 has three
        // tetrahedra around it; removing it is the 3-2 flip, and the 2-3
        // flip of the new face brings it back.
        let s = 3f64.sqrt() / 2.0;
        let pts = [
            [1.0, 0.0, 0.0],
            [-0.5, s, 0.0],
            [-0.5, -s, 0.0],
            [0.0, 0.0, 0.1],
            [0.0, 0.0, -0.1],
        ];
        let mut m = CMesh::new(Delaunay3::from_points(&pts).unwrap());
        assert_eq!(finite_tets(&m), 3);
        let t = m.find_edge(3, 4).unwrap();
        assert!(m.find_face(0, 1, 2).is_none() && m.find_face(0, 3, 4).is_some());
        assert_eq!(m.remove_edge(t, 3, 4, &|_, _| 0, &|_, _, _| 0), Some(0));
        m.check().unwrap();
        assert_eq!(finite_tets(&m), 2);
        assert!(m.find_face(2, 0, 1).is_some() && m.find_face(0, 3, 4).is_none());
        assert!(!has_edge(&m, 3, 4));
        let t = m
            .star(3)
            .into_iter()
            .find(|&t| {
                let tv = m.dt.core.v[t as usize];
                !tv.contains(&INF) && tv.contains(&0) && tv.contains(&1) && tv.contains(&2)
            })
            .unwrap();
        let f = m.dt.core.v[t as usize]
            .iter()
            .position(|&w| w == 3)
            .unwrap();
        assert!(m.flip23(t, f));
        m.check().unwrap();
        assert_eq!(finite_tets(&m), 3);
        assert!(has_edge(&m, 3, 4));
        // A 2-3 flip whose apex edge misses the face is refused.
        let pts2 = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.2, 0.2, 1.0],
            [3.0, 3.0, -0.1],
        ];
        let mut m2 = CMesh::new(Delaunay3::from_points(&pts2).unwrap());
        let before = m2.dt.core.v.clone();
        for t in 0..m2.dt.core.v.len() as u32 {
            for f in 0..4 {
                let tv = m2.dt.core.v[t as usize];
                if tv[0] == DEAD || tv.contains(&INF) {
                    continue;
                }
                let nb = m2.dt.core.v[(m2.dt.core.adj[t as usize][f] >> 2) as usize];
                if nb.contains(&INF) {
                    continue;
                }
                // Apexes 3 and 4 around face 0-1-2: 3-4 misses it.
                if face(tv, f).iter().all(|w| [0, 1, 2].contains(w)) {
                    assert!(!m2.flip23(t, f));
                }
            }
        }
        assert_eq!(m2.dt.core.v, before);
    }

    #[test]
    fn touched_faces_and_failed_removals_are_logged() {
        let s = 3f64.sqrt() / 2.0;
        let pts = [
            [1.0, 0.0, 0.0],
            [-0.5, s, 0.0],
            [-0.5, -s, 0.0],
            [0.0, 0.0, 0.1],
            [0.0, 0.0, -0.1],
        ];
        let mut m = CMesh::new(Delaunay3::from_points(&pts).unwrap());
        assert!(m.take_touched().is_empty());
        let t = m.find_edge(3, 4).unwrap();
        m.remove_edge(t, 3, 4, &|_, _| 0, &|_, _, _| 0).unwrap();
        let touched = m.take_touched();
        // The removed faces around 3-4 and the new face 0-1-2 are logged.
        assert!(touched.contains(&[0, 1, 2]));
        assert!(touched.contains(&[0, 3, 4]) || touched.contains(&[1, 3, 4]));
        assert!(m.take_touched().is_empty());
        // Random points: every interior-edge removal that fails is
        // memoized and fails again; a failure changes nothing.
        let pts = scattered(40);
        let mut m = CMesh::new(Delaunay3::from_points(&pts).unwrap());
        let mut failures = 0;
        for t in 0..m.dt.core.v.len() as u32 {
            let tv = m.dt.core.v[t as usize];
            if tv[0] == DEAD || tv.contains(&INF) || m.edge_ring(t, tv[0], tv[1]).is_none() {
                continue;
            }
            let before = m.dt.core.v.clone();
            let n = m.failed.len();
            let long = m
                .edge_ring(t, tv[0], tv[1])
                .is_some_and(|(_, r)| r.len() >= MEMO_RING);
            if m.remove_edge(t, tv[0], tv[1], &|_, _| 0, &|_, _, _| 0)
                .is_none()
                && long
            {
                // One new key, or the same edge seen from another slot.
                failures += 1;
                let k = m.failed.len();
                assert!(k == n + 1 || k == n && n > 0);
                assert!(m
                    .remove_edge(t, tv[0], tv[1], &|_, _| 0, &|_, _, _| 0)
                    .is_none());
                assert_eq!(m.failed.len(), k);
                assert_eq!(m.dt.core.v, before);
            } else if !long {
                assert_eq!(m.failed.len(), n);
            }
        }
        assert!(failures > 0);
        m.check().unwrap();
    }

    /// The tetrahedra as sorted vertex sets, sorted.
    fn tet_sets(m: &CMesh<'_>) -> Vec<[u32; 4]> {
        let mut out: Vec<[u32; 4]> =
            m.dt.core
                .v
                .iter()
                .filter(|tv| tv[0] != DEAD)
                .map(|tv| {
                    let mut k = *tv;
                    k.sort_unstable();
                    k
                })
                .collect();
        out.sort_unstable();
        out
    }

    #[test]
    fn logged_operations_replay_and_roll_back() {
        let pts = scattered(60);
        let base = CMesh::new(Delaunay3::from_points(&pts).unwrap());
        let start = tet_sets(&base);
        let mut m = base.clone();
        m.start_log();
        let mut ops = 0;
        for t in 0..m.dt.core.v.len() as u32 {
            for f in 0..4 {
                if m.dt.core.v[t as usize][0] != DEAD && m.flip23(t, f) {
                    ops += 1;
                }
            }
            let tv = m.dt.core.v[t as usize];
            if tv[0] != DEAD
                && !tv.contains(&INF)
                && m.remove_edge(t, tv[0], tv[1], &|_, _| 0, &|_, _, _| 0)
                    .is_some()
            {
                ops += 1;
            }
        }
        assert!(ops > 10);
        m.check().unwrap();
        let flipped = tet_sets(&m);
        assert_ne!(flipped, start);
        let log = m.take_log().unwrap();
        // Replayed on the starting mesh: every operation applies, same result.
        let mut r = base.clone();
        assert_eq!(r.replay(&log, &|_, _| true), ops);
        r.check().unwrap();
        assert_eq!(tet_sets(&r), flipped);
        assert_eq!((r.flips23, r.removals), (m.flips23, m.removals));
        // Refused operations are skipped (and those depending on them).
        let mut q = base.clone();
        assert_eq!(q.replay(&log, &|_, _| false), 0);
        assert_eq!(tet_sets(&q), start);
        // Rolled back from half way: the mesh of that moment.
        let mut h = base.clone();
        h.start_log();
        let half = h.replay(&log, &|_, _| true);
        assert_eq!(half, ops);
        h.rollback(ops / 2);
        h.check().unwrap();
        h.rollback(0);
        h.check().unwrap();
        assert_eq!(tet_sets(&h), start);
        assert_eq!((h.flips23, h.removals), (0, 0));
        assert_eq!(h.log_mark(), 0);
    }

    #[test]
    fn hull_diagonal_of_a_flat_quad_is_flipped() {
        let pts = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.5, 0.5, 1.0],
        ];
        let mut m = CMesh::new(Delaunay3::from_points(&pts).unwrap());
        let (a, b, c, d) = if has_edge(&m, 0, 2) {
            (0, 2, 1, 3)
        } else {
            (1, 3, 0, 2)
        };
        let t = m.find_edge(a, b).unwrap();
        assert!(m.edge_ring(t, a, b).is_none());
        assert!(m.remove_edge(t, a, b, &|_, _| 0, &|_, _, _| 0).is_some());
        m.check().unwrap();
        assert!(!has_edge(&m, a, b) && has_edge(&m, c, d));
        assert_eq!(finite_tets(&m), 2);
        // A hull edge between non-coplanar hull faces is kept.
        let t = m.find_edge(0, 4).unwrap();
        assert!(m.remove_edge(t, 0, 4, &|_, _| 0, &|_, _, _| 0).is_none());
        m.check().unwrap();
    }

    #[test]
    fn edge_removal_of_larger_rings_and_constrained_insertion() {
        // A ring of six points around the z axis: edge 6-7 has six
        // tetrahedra around it; removing it gives 2 * 6 - 4 = 8.
        let mut pts: Vec<[f64; 3]> = (0..6)
            .map(|i| {
                let a = i as f64 * std::f64::consts::PI / 3.0;
                [a.cos(), a.sin(), 0.0]
            })
            .collect();
        pts.push([0.0, 0.0, 0.05]);
        pts.push([0.0, 0.0, -0.05]);
        let dt = Delaunay3::from_points(&pts).unwrap();
        let mut m = CMesh::new(dt);
        let t = m.find_edge(6, 7).unwrap();
        let (tets, ring) = m.edge_ring(t, 6, 7).unwrap();
        assert_eq!((tets.len(), ring.len()), (6, 6));
        let before = finite_tets(&m);
        m.remove_edge(t, 6, 7, &|_, _| 0, &|_, _, _| 1).unwrap();
        m.check().unwrap();
        assert_eq!(finite_tets(&m), before - 6 + 8);
        // Insert the centre back with the face 0-2-4 protected (if
        // present) and edge 0-3 protected: the mesh stays valid and the
        // protected items survive.
        let prot: Vec<[u32; 3]> = vec![fkey([0, 2, 4])];
        let had =
            m.dt.tets()
                .any(|tv| (0..4).any(|f| fkey(face(tv, f)) == prot[0]));
        let id = m
            .insert_constrained([0.01, 0.02, 0.0], &|k| prot.contains(&k), &|a, b| {
                (a.min(b), a.max(b)) == (0, 3)
            })
            .unwrap();
        m.check().unwrap();
        assert_eq!(id, 8);
        if had {
            assert!(m
                .dt
                .tets()
                .any(|tv| (0..4).any(|f| fkey(face(tv, f)) == prot[0])));
        }
        // Cone refused when the point does not see the cavity's faces.
        let t = m
            .star(0)
            .into_iter()
            .find(|&t| !m.dt.core.v[t as usize].contains(&INF))
            .unwrap();
        let n = m.pts().len();
        assert!(m.cone(&[t], [50.0, 50.0, 50.0]).is_none());
        assert_eq!(m.pts().len(), n);
        m.check().unwrap();
    }
}
