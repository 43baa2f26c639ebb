//! The domain mesh as recovery uses it: with the kernel's ghost cells and a
//! journal.
//!
//! [`Journaled`] holds a [`DomainMesh`] whose arrays are those of the
//! kernel's [`Delaunay3`] (moved in by [`Journaled::new`], kept for
//! carving by [`Journaled::into_parts`]; no copy): ghost cells with [`INF`] in position 3
//! close the convex hull, so no face is on the boundary ([`crate::NONE`]),
//! hull 2-2 flips are replacements like any other, and walks pass outside
//! the domain before carving. Once a flip has been applied, the kernel's
//! Delaunay insertion must no longer be used on the returned structure.
//!
//! Every mesh change goes through [`DomainMesh::replace`]; the star walk,
//! the edge ring, the visit stamps and the invariant checker are the domain
//! mesh's. Added here (all combinatorial decisions by exact `orient3d`; an
//! operation whose result would contain a tetrahedron that is not strictly
//! positive is refused and leaves the mesh untouched):
//!
//! * [`Journaled::flip23`] — two tetrahedra sharing a face become three
//!   sharing the edge between the two apexes (valid iff that edge crosses
//!   the face's interior);
//! * [`Journaled::remove_edge`] — the `n` tetrahedra around an edge become
//!   the `2n - 4` tetrahedra joining a triangulation of the ring polygon to
//!   the edge's two ends, chosen by the shared dynamic program
//!   ([`ring::triangulate`]) among those whose tetrahedra are all positive,
//!   minimising a caller-supplied cost; a convex-hull edge between two
//!   coplanar hull faces is the hull's 2-2 flip. Impossible removals of
//!   long rings are memoized (the answer depends only on exact signs).
//!
//! Nothing here recurses; rings are capped ([`MAX_RING`]).
//!
//! # Journal
//!
//! Every replacement is logged as "these tetrahedra became those":
//! [`Journaled::replay`] re-applies a log where all the removed tetrahedra
//! are still present (the recovery's next round), [`Journaled::rollback`]
//! undoes the operations since a mark (a failed segment), and
//! [`Journaled::removed_vertices_since`] names the vertices whose
//! tetrahedra an operation removed (which failed segments to retry). The
//! faces each replacement removes or creates are collected
//! ([`Journaled::take_touched_raw`]): the recovery's coverage refresh turns
//! them into candidate triangles locally.

use std::cell::RefCell;
use std::mem::take;

use delone_predicates::orient3d;

use super::memo::Recent;
use super::ring;
use super::{DomainMesh, Stamps};
use crate::geom::ids::IdSet;
use crate::tet::local::{face, fkey, DEAD, INF};
use crate::tet::Delaunay3;

/// Cost of a ring triangle in [`Journaled::remove_edge`] (gets the points).
pub(crate) type TriCost<'c> = &'c dyn Fn(&[[f64; 3]], [u32; 3]) -> i64;
/// Cost of a new ring chord in [`Journaled::remove_edge`] (gets the points).
pub(crate) type EdgeCost<'c> = &'c dyn Fn(&[[f64; 3]], u32, u32) -> i64;

/// Whether [`Journaled::replay`] may replace the given tetrahedra (removed,
/// created).
pub(crate) type ReplayTest<'c> = &'c dyn Fn(&[[u32; 4]], &[[u32; 4]]) -> bool;

/// Longest edge ring [`Journaled::remove_edge`] handles.
pub(crate) const MAX_RING: usize = 24;

/// Shortest ring whose failed removal is memoized (shorter ones are
/// cheaper to retry than to remember).
const MEMO_RING: usize = 4;

/// Replacements recorded while logging ([`Journaled::start_log`]): per
/// operation, the tetrahedra it removed and those it created, as vertex
/// tuples. [`Journaled::replay`] applies them to another mesh on (a
/// superset of) the same points.
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

/// A domain mesh with ghost cells and a journal (see the module
/// documentation).
#[derive(Debug, Clone)]
pub(crate) struct Journaled<'a> {
    /// The tetrahedra, ghost cells included (no subface marks, no regions).
    pub(crate) m: DomainMesh,
    /// The kernel structure whose arrays `m` holds: the points and the
    /// kernel's other state, given back by [`Journaled::into_parts`].
    shell: Delaunay3<'a>,
    /// 2-3 flips performed.
    pub(crate) flips23: usize,
    /// Edge removals performed.
    pub(crate) removals: usize,
    /// Finite faces (sorted triples) removed or created by the
    /// replacements since the last [`Journaled::take_touched_raw`] (unsorted,
    /// with repeats; at least one per replacement).
    touched: Vec<[u32; 3]>,
    /// Edge removals known to be impossible (rings of [`MEMO_RING`] or more
    /// vertices): `[a, b, ring…]` with the ring rotated to start at its
    /// least vertex; may be carried over to another mesh on the same points
    /// ([`Journaled::take_failed`], [`Journaled::set_failed`]).
    failed: IdSet<Vec<u32>>,
    /// The replacements since [`Journaled::start_log`], when logging.
    log: Option<OpLog>,
    /// The visited set of [`Journaled::visit`] (the star walks use the
    /// domain mesh's own set).
    visited: RefCell<Stamps>,
    /// The per-vertex memo of [`Journaled::vertex_memo`]: the vertices
    /// set, and their values.
    vmemo: RefCell<(Stamps, Vec<i8>)>,
    /// Scratch of the star searches, of the dynamic program and of the
    /// new slots of an operation.
    buf: RefCell<Vec<u32>>,
    /// The ring (slots, vertices) of the last edge removal attempt (see
    /// `ring_of`; read by [`Journaled::edge_ring_again`]).
    ring: (Vec<u32>, Vec<u32>),
    dp_best: Vec<i64>,
    dp_choice: Vec<usize>,
    ids: Vec<u32>,
    key: Vec<u32>,
    /// The new tetrahedra of an edge removal (scratch).
    new_tets: Vec<[u32; 4]>,
    /// Spare ring lists ([`Journaled::ring_buffers`]).
    ring_pool: Vec<(Vec<u32>, Vec<u32>)>,
    /// Recent answers of [`Journaled::positive`] (vertex tuples as asked).
    orient_memo: Recent<4>,
    /// Recent answers of the segment recovery's segment–face tests (see
    /// [`crate::tet::recover::cdt`]): segment ends and face, as asked.
    pub(crate) seg_memo: Recent<5>,
    /// Replacements made so far (a change stamp).
    changes: u64,
    /// The walk behind `ring`: slot, edge, [`Journaled::changes`] then,
    /// and whether it closed.
    ring_of: Option<(u32, u32, u32, u64, bool)>,
}

impl<'a> Journaled<'a> {
    /// Takes over a tetrahedralization's arrays (ghost cells included);
    /// each vertex hint is the first slot holding the vertex.
    pub(crate) fn new(mut dt: Delaunay3<'a>) -> Self {
        let c = &mut dt.core;
        let mut vt = vec![DEAD; dt.points.len()];
        for (t, tv) in c.v.iter().enumerate() {
            if tv[0] == DEAD {
                continue;
            }
            for &w in tv {
                if w != INF && vt[w as usize] == DEAD {
                    vt[w as usize] = t as u32;
                }
            }
        }
        let (tv, nb, free) = (take(&mut c.v), take(&mut c.adj), take(&mut c.free));
        let m = DomainMesh::from_arrays(tv, nb, free, vt);
        Journaled {
            m,
            shell: dt,
            flips23: 0,
            removals: 0,
            touched: Vec::new(),
            failed: Default::default(),
            log: None,
            visited: Default::default(),
            vmemo: Default::default(),
            buf: Default::default(),
            ring: Default::default(),
            dp_best: Vec::new(),
            dp_choice: Vec::new(),
            ids: Vec::new(),
            key: Vec::new(),
            new_tets: Vec::new(),
            ring_pool: Vec::new(),
            orient_memo: Default::default(),
            seg_memo: Default::default(),
            changes: 0,
            ring_of: None,
        }
    }

    /// The domain mesh, and the kernel structure emptied of its arrays
    /// (its points and duplicates): the end of recovery, which carves the
    /// mesh in place.
    pub(crate) fn into_parts(self) -> (DomainMesh, Delaunay3<'a>) {
        (self.m, self.shell)
    }

    /// The points (input, then inserted).
    #[inline]
    pub(crate) fn pts(&self) -> &[[f64; 3]] {
        &self.shell.points
    }

    /// Appends a point (in no tetrahedron yet).
    pub(crate) fn push_point(&mut self, p: [f64; 3]) {
        self.shell.points.to_mut().push(p);
    }

    /// Starts recording every replacement in a fresh [`OpLog`].
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
        let (mut slots, mut ids) = (Vec::new(), Vec::new());
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
            if !self.locate_tets(old, hint, &mut slots) || !allowed(old, new) {
                continue;
            }
            self.replace_into(&slots, new, &mut ids);
            for (&r, &x) in new_at.iter().zip(&ids) {
                if map.len() <= r as usize {
                    map.resize(r as usize + 1, DEAD);
                }
                map[r as usize] = x;
            }
            self.count(no, nn, 1);
            done += 1;
        }
        done
    }

    /// Adds `by` to the count of the operation replacing `no` tetrahedra by
    /// `nn` (only a 2-3 flip turns two into three).
    fn count(&mut self, no: usize, nn: usize, by: isize) {
        let c = if (no, nn) == (2, 3) {
            &mut self.flips23
        } else {
            &mut self.removals
        };
        *c = c.wrapping_add_signed(by);
    }

    /// Calls `f(op, w)` for every vertex `w` (not [`INF`], with repeats)
    /// of the tetrahedra removed by the operations logged since `mark`
    /// ([`Journaled::log_mark`]), `op` being the operation's index in the
    /// log. The tetrahedra an operation creates have the same vertices.
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

    /// Is every replacement being logged ([`Journaled::start_log`])?
    pub(crate) fn logging(&self) -> bool {
        self.log.is_some()
    }

    /// Calls `f(removed, created)` with the tetrahedra (vertex tuples) of
    /// each operation logged since `mark` ([`Journaled::log_mark`]), in
    /// order; nothing when not logging.
    pub(crate) fn ops_since(&self, mark: usize, mut f: impl FnMut(&[[u32; 4]], &[[u32; 4]])) {
        let Some(log) = &self.log else {
            return;
        };
        for &(s, no, nn) in &log.ops[mark.min(log.ops.len())..] {
            let (s, no, nn) = (s as usize, usize::from(no), usize::from(nn));
            let (old, new) = log.tets[s..s + no + nn].split_at(no);
            f(old, new);
        }
    }

    /// The number of operations logged so far (a mark for
    /// [`Journaled::rollback`]); 0 when not logging.
    pub(crate) fn log_mark(&self) -> usize {
        self.log.as_ref().map_or(0, |l| l.ops.len())
    }

    /// Undoes, newest first, the operations logged since `mark`
    /// ([`Journaled::log_mark`]) and forgets them: each created set of
    /// tetrahedra is replaced back by the removed one (valid for the same
    /// reason as [`Journaled::replay`]).
    pub(crate) fn rollback(&mut self, mark: usize) {
        let Some(mut log) = self.log.take() else {
            return;
        };
        let (mut slots, mut ids) = (Vec::new(), Vec::new());
        for &(s, no, nn) in log.ops[mark.min(log.ops.len())..].iter().rev() {
            let (s, no, nn) = (s as usize, usize::from(no), usize::from(nn));
            let (old, new) = log.tets[s..s + no + nn].split_at(no);
            let new_at = &log.slots[s + no..s + no + nn];
            let found = self.locate_tets(new, |i| new_at[i], &mut slots);
            debug_assert!(found, "rollback: a created tetrahedron is gone");
            if !found {
                break;
            }
            self.replace_into(&slots, old, &mut ids);
            self.count(no, nn, -1);
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
    ) -> bool {
        slots.clear();
        let m = &self.m;
        let same =
            |t: u32, q: &[u32; 4]| m.alive(t) && q.iter().all(|w| m.tv[t as usize].contains(w));
        'next: for (i, q) in old.iter().enumerate() {
            let h = hint(i);
            if same(h, q) {
                slots.push(h);
                continue;
            }
            for j in 0..slots.len() {
                for f in 0..4 {
                    let n = m.nb[slots[j] as usize][f] >> 2;
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
            match self.star_find(w, |t| same(t, q)) {
                Some(t) => slots.push(t),
                None => return false,
            }
        }
        true
    }

    /// The finite faces (sorted triples; unsorted, with repeats: the
    /// caller deduplicates what it derives from them) created or destroyed
    /// by the replacements since the previous call; every tetrahedron
    /// created or destroyed since then has a face in this list (a
    /// replacement removes and creates two or more face-connected
    /// tetrahedra, so each has a face inside it).
    pub(crate) fn take_touched_raw(&mut self) -> Vec<[u32; 3]> {
        std::mem::take(&mut self.touched)
    }

    /// How many faces were logged since the last
    /// [`Journaled::take_touched_raw`] (with repeats).
    pub(crate) fn touched_len(&self) -> usize {
        self.touched.len()
    }

    /// Forgets the faces logged since the last [`Journaled::take_touched_raw`].
    pub(crate) fn clear_touched(&mut self) {
        self.touched.clear();
    }

    /// Takes the known impossible edge removals (see
    /// [`Journaled::set_failed`]).
    pub(crate) fn take_failed(&mut self) -> IdSet<Vec<u32>> {
        std::mem::take(&mut self.failed)
    }

    /// Sets the known impossible edge removals, from
    /// [`Journaled::take_failed`] of a mesh whose points are a prefix of (or
    /// equal to) these points.
    pub(crate) fn set_failed(&mut self, failed: IdSet<Vec<u32>>) {
        self.failed = failed;
    }

    /// True when finite `tv` is strictly positive (exact `orient3d`, its
    /// recent answers remembered: the flips ask about the same tuples
    /// again and again).
    #[inline]
    pub(crate) fn positive(&self, tv: [u32; 4]) -> bool {
        self.orient_memo
            .answer(tv, || super::flip::positive(self.pts(), tv))
    }

    /// Live tetrahedra (ghosts included) containing vertex `u`, breadth
    /// first from its hint.
    pub(crate) fn star(&self, u: u32) -> Vec<u32> {
        self.m.star_with(u, |_, _| true)
    }

    /// Empties the visited set of [`Journaled::visit`].
    pub(crate) fn visit_begin(&self) {
        self.visited.borrow_mut().clear();
    }

    /// Adds slot `x` to the visited set; true when it was not in it. One
    /// set at a time ([`Journaled::visit_begin`]).
    pub(crate) fn visit(&self, x: u32) -> bool {
        self.visited.borrow_mut().insert(x)
    }

    /// Is slot `x` in the visited set of [`Journaled::visit`]?
    pub(crate) fn visited(&self, x: u32) -> bool {
        self.visited.borrow().contains(x)
    }

    /// Empties the per-vertex memo of [`Journaled::vertex_memo`].
    pub(crate) fn vertex_memo_begin(&self) {
        self.vmemo.borrow_mut().0.clear();
    }

    /// The value of vertex `w` in the memo, `f()` stored there the first
    /// time since [`Journaled::vertex_memo_begin`] (a per-search answer
    /// per vertex, without hashing). One memo at a time.
    pub(crate) fn vertex_memo(&self, w: u32, f: impl FnOnce() -> i8) -> i8 {
        {
            let m = self.vmemo.borrow();
            if m.0.contains(w) {
                return m.1[w as usize];
            }
        }
        let x = f();
        let mut m = self.vmemo.borrow_mut();
        m.0.insert(w);
        if m.1.len() <= w as usize {
            m.1.resize(w as usize + 1, 0);
        }
        m.1[w as usize] = x;
        x
    }

    /// The first tetrahedron, in [`Journaled::star`]'s order, of `u`'s star
    /// for which `stop` holds (the walk stops there; no allocation).
    pub(crate) fn star_find(&self, u: u32, stop: impl Fn(u32) -> bool) -> Option<u32> {
        let mut buf = std::mem::take(&mut *self.buf.borrow_mut());
        let r = self.m.star_first(u, &mut buf, stop);
        *self.buf.borrow_mut() = buf;
        r
    }

    /// A live tetrahedron containing edge `u v`.
    pub(crate) fn find_edge(&self, u: u32, v: u32) -> Option<u32> {
        self.star_find(u, |t| self.m.tv[t as usize].contains(&v))
    }

    /// A live tetrahedron (ghosts included) having face `a b c`.
    pub(crate) fn find_face(&self, a: u32, b: u32, c: u32) -> Option<u32> {
        self.star_find(a, |t| {
            let tv = self.m.tv[t as usize];
            tv.contains(&b) && tv.contains(&c)
        })
    }

    /// The tetrahedra around edge `a b` (starting at `t`, which contains it)
    /// and the ring vertices, so that `[a, b, ring[i], ring[i + 1]]` (cyclic)
    /// is `tets[i]`, positively oriented. `None` through a ghost or beyond
    /// [`MAX_RING`].
    pub(crate) fn edge_ring(&self, t: u32, a: u32, b: u32) -> Option<(Vec<u32>, Vec<u32>)> {
        let (mut tets, mut ring) = (Vec::with_capacity(8), Vec::with_capacity(8));
        self.edge_ring_into(t, a, b, (&mut tets, &mut ring))
            .then_some((tets, ring))
    }

    /// [`Journaled::edge_ring`] into `tets` and `ring` (cleared first);
    /// false where that gives `None`.
    pub(crate) fn edge_ring_into(
        &self,
        t: u32,
        a: u32,
        b: u32,
        (tets, ring): (&mut Vec<u32>, &mut Vec<u32>),
    ) -> bool {
        let no_ghost = |c: u32, _| !self.m.tv[c as usize].contains(&INF);
        self.m
            .ring_into(t, (a, b), (MAX_RING, false), no_ghost, (tets, ring))
            .is_some()
    }

    /// [`Journaled::edge_ring_into`], copied from the ring of the last edge
    /// removal attempt when that walked the same edge from the same slot
    /// and nothing has changed since: that walk crosses every face, so it
    /// is this one when it passes no ghost, and fails when this one does.
    pub(crate) fn edge_ring_again(
        &self,
        t: u32,
        a: u32,
        b: u32,
        (tets, ring): (&mut Vec<u32>, &mut Vec<u32>),
    ) -> bool {
        let same = |&(t0, a0, b0, c, _): &(u32, u32, u32, u64, bool)| {
            (t0, a0, b0, c) == (t, a, b, self.changes)
        };
        if let Some((.., closed)) = self.ring_of.filter(same) {
            let (lt, lr) = &self.ring;
            if !closed || lt.iter().any(|&c| self.m.tv[c as usize].contains(&INF)) {
                return false;
            }
            tets.clear();
            tets.extend_from_slice(lt);
            ring.clear();
            ring.extend_from_slice(lr);
            return true;
        }
        self.edge_ring_into(t, a, b, (tets, ring))
    }

    /// A pair of lists for [`Journaled::edge_ring_into`] (spare ones
    /// reused: no allocation per ring); give them back with
    /// [`Journaled::give_ring_buffers`].
    pub(crate) fn ring_buffers(&mut self) -> (Vec<u32>, Vec<u32>) {
        self.ring_pool.pop().unwrap_or_default()
    }

    /// Returns lists taken by [`Journaled::ring_buffers`].
    pub(crate) fn give_ring_buffers(&mut self, bufs: (Vec<u32>, Vec<u32>)) {
        self.ring_pool.push(bufs);
    }

    /// Replaces tetrahedra `old` (a connected set) by `new` filling the same
    /// polyhedron ([`DomainMesh::replace`]), logging the operation and the
    /// faces it removes or creates. Returns the new slots.
    pub(crate) fn replace(&mut self, old: &[u32], new: &[[u32; 4]]) -> Vec<u32> {
        let mut ids = Vec::with_capacity(new.len());
        self.replace_into(old, new, &mut ids);
        ids
    }

    /// [`Journaled::replace`] writing the new slots into `ids` (cleared
    /// first).
    pub(crate) fn replace_into(&mut self, old: &[u32], new: &[[u32; 4]], ids: &mut Vec<u32>) {
        // Touched faces, each once per operation: the faces between two
        // removed tetrahedra and those between two created ones — the faces
        // that disappear or appear. Every removed or created tetrahedron
        // has such a face (both sets are connected and have two or more
        // members), so a tetrahedron whose four vertices lie on some
        // triangle is still seen through one of its faces.
        self.changes += 1;
        let finite = |k: &[u32; 3]| !k.contains(&INF);
        // The first finite outer face (logged when no inner face is).
        let first_outer = old
            .iter()
            .flat_map(|&t| (0..4).map(move |f| (t, f)))
            .filter(|&(t, f)| !old.contains(&(self.m.nb[t as usize][f] >> 2)))
            .map(|(t, f)| fkey(face(self.m.tv[t as usize], f)))
            .find(finite);
        if let Some(log) = &mut self.log {
            let start = log.tets.len() as u32;
            log.tets.extend(old.iter().map(|&t| self.m.tv[t as usize]));
            log.slots.extend_from_slice(old);
            log.ops.push((start, old.len() as u16, new.len() as u16));
        }
        let mut inner = self.m.inner.take().unwrap_or_default();
        inner.clear();
        self.m.inner = Some(inner);
        let gone = self.m.replace(old, new, 0, ids);
        let inner = self.m.inner.as_deref().unwrap_or_default();
        let touched0 = self.touched.len();
        self.touched.extend(inner.iter().filter(|k| finite(k)));
        debug_assert!(
            gone.gone.is_empty() && gone.made.is_empty(),
            "replace: unmatched faces"
        );
        if let Some(log) = &mut self.log {
            log.tets.extend_from_slice(new);
            log.slots.extend_from_slice(ids);
        }
        // Every replacement logs at least one face (`touched_len` is a
        // change stamp for callers).
        if self.touched.len() == touched0 {
            if let Some(k) = first_outer {
                self.touched.push(k);
            }
        }
    }

    /// 2-3 flip of the face opposite local vertex `f` of tetrahedron `t`:
    /// false (nothing changed) when a ghost is involved or the edge between
    /// the two apexes does not cross the face's interior.
    pub(crate) fn flip23(&mut self, t: u32, f: usize) -> bool {
        match self.flip23_plan(t, f) {
            Some(plan) => {
                self.apply_flip23(plan);
                true
            }
            None => false,
        }
    }

    /// The 2-3 flip [`Journaled::flip23`] would make, without making it:
    /// the slot behind the face and the three new tetrahedra; `None` when
    /// it is refused (no allocation: most flips tried are refused).
    pub(crate) fn flip23_plan(&self, t: u32, f: usize) -> Option<(u32, u32, [[u32; 4]; 3])> {
        // The three new tetrahedra hold the five vertices of the two old
        // ones: a ghost among those puts `INF` in one of them.
        let (u, new) = self.m.alive(t).then(|| self.m.flip23_tets(t, f))??;
        if new.iter().any(|n| n.contains(&INF) || !self.positive(*n)) {
            return None;
        }
        Some((t, u, new))
    }

    /// Applies a plan of [`Journaled::flip23_plan`] made on the current
    /// mesh.
    pub(crate) fn apply_flip23(&mut self, (t, u, new): (u32, u32, [[u32; 4]; 3])) {
        let mut ids = std::mem::take(&mut self.ids);
        self.replace_into(&[t, u], &new, &mut ids);
        self.ids = ids;
        self.flips23 += 1;
    }

    /// Removes edge `a b` (contained in `t`): the tetrahedra around it are
    /// replaced by a triangulation of its ring joined to `a` and `b`, the
    /// one of least total cost (`tri_cost` per ring triangle, `edge_cost`
    /// per new ring chord; both get the points) among those whose
    /// tetrahedra are all positive. Returns the cost, or `None` (nothing
    /// changed) when no such triangulation exists or the ring is too long.
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
        self.remove_edge_below(t, a, b, (tri_cost, edge_cost), i64::MAX)
    }

    /// [`Journaled::remove_edge`] refusing (nothing changed) a least cost
    /// of `limit` or more.
    pub(crate) fn remove_edge_below(
        &mut self,
        t: u32,
        a: u32,
        b: u32,
        costs: (TriCost<'_>, EdgeCost<'_>),
        limit: i64,
    ) -> Option<i64> {
        self.remove_edge_limited(t, a, b, costs, |_, _| Some(limit))
    }

    /// [`Journaled::remove_edge_below`] with the limit a function of the
    /// points and the ring (its vertices in order, [`INF`] for a ghost),
    /// computed once the
    /// ring is walked; `None` refuses the removal (nothing changed, not
    /// memoized).
    pub(crate) fn remove_edge_limited(
        &mut self,
        t: u32,
        a: u32,
        b: u32,
        (tri_cost, edge_cost): (TriCost<'_>, EdgeCost<'_>),
        limit: impl FnOnce(&[[f64; 3]], &[u32]) -> Option<i64>,
    ) -> Option<i64> {
        // The ring lists and the memo key are reused scratch (no
        // allocation per call).
        let (mut tets, mut r) = std::mem::take(&mut self.ring);
        let ends = self.m.ring_into(
            t,
            (a, b),
            (MAX_RING, false),
            |_, _| true,
            (&mut tets, &mut r),
        );
        self.ring_of = Some((t, a, b, self.changes, ends.is_some()));
        let mut key = std::mem::take(&mut self.key);
        let out = if ends.is_none() || self.known_failed(a, b, &r, &mut key) {
            None
        } else if let Some(limit) = limit(self.pts(), &r) {
            if r.len() < MEMO_RING {
                self.remove_ring(&tets, &mut r, a, b, (tri_cost, edge_cost), limit)
                    .ok()
            } else {
                // Memoized only when no triangulation at all is valid (a
                // refusal by `limit` depends on the costs).
                match self.remove_ring(&tets, &mut r, a, b, (tri_cost, edge_cost), limit) {
                    Ok(c) => Some(c),
                    Err(none_valid) => {
                        if none_valid {
                            self.failed.insert(key.clone());
                        }
                        None
                    }
                }
            }
        } else {
            None
        };
        self.ring = (tets, r);
        self.key = key;
        out
    }

    /// Is the removal of edge `a b` with ring `r` memoized as impossible?
    /// Writes the memo key (rings of [`MEMO_RING`] or more vertices) into
    /// `key`; false for shorter rings.
    fn known_failed(&self, a: u32, b: u32, r: &[u32], key: &mut Vec<u32>) -> bool {
        key.clear();
        if r.len() < MEMO_RING {
            return false;
        }
        let m = (0..r.len()).min_by_key(|&i| r[i]).unwrap_or(0);
        key.extend([a, b]);
        key.extend(r[m..].iter().chain(&r[..m]));
        self.failed.contains(&key[..])
    }

    /// [`Journaled::remove_edge_below`] once the ring is known: the cost,
    /// or `Err(true)` when the edge cannot be removed whatever the costs (a
    /// ghost ring that is not flat, a ring of fewer than three vertices, no
    /// valid triangulation), `Err(false)` when the least cost is `limit` or
    /// more (the only refusal that is not memoized).
    fn remove_ring(
        &mut self,
        tets: &[u32],
        r: &mut Vec<u32>,
        a: u32,
        b: u32,
        (tri_cost, edge_cost): (TriCost<'_>, EdgeCost<'_>),
        limit: i64,
    ) -> Result<i64, bool> {
        let mut ghosts = Vec::new();
        if let Some(k) = r.iter().position(|&w| w == INF) {
            r.rotate_left(k + 1);
            r.pop();
            let (c0, d0) = (r[0], *r.last().ok_or(true)?);
            let p = self.pts();
            let g = |w: u32| &p[w as usize];
            if r.len() < 3 || orient3d(g(a), g(b), g(c0), g(d0)) != 0.0 {
                return Err(true);
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
            return Err(true);
        }
        const NO: i64 = i64::MAX / 4;
        let (mut best, mut choice) = (
            std::mem::take(&mut self.dp_best),
            std::mem::take(&mut self.dp_choice),
        );
        let rr: &[u32] = r;
        let total = ring::triangulate(
            n,
            (NO, 0),
            &mut best,
            &mut choice,
            // The chord's cost is computed at its first valid split (most
            // chords of a ring that cannot be removed have none).
            |i, j| (i, j, std::cell::Cell::new(None)),
            |i, k, j, l, right, cur, chord| {
                if l >= NO || right >= NO {
                    return None;
                }
                let tri = [rr[i], rr[k], rr[j]];
                if !self.positive([tri[0], tri[1], tri[2], b])
                    || !self.positive([tri[0], tri[2], tri[1], a])
                {
                    return None;
                }
                let (ci, cj, ref cost) = *chord;
                let chord = cost.get().unwrap_or_else(|| {
                    let c = if ci == 0 && cj == n - 1 {
                        0
                    } else {
                        edge_cost(self.pts(), rr[ci], rr[cj])
                    };
                    cost.set(Some(c));
                    c
                });
                let c = l + right + tri_cost(self.pts(), tri) + chord;
                (c < cur).then_some(c)
            },
        );
        let mut new = std::mem::take(&mut self.new_tets);
        let found = total < NO.min(limit);
        if found {
            ring::ring_tets_into(r, &choice, a, b, &mut new);
        }
        self.dp_best = best;
        self.dp_choice = choice;
        if !found {
            self.new_tets = new;
            return Err(total >= NO);
        }
        new.extend(ghosts);
        let mut ids = std::mem::take(&mut self.ids);
        self.replace_into(tets, &new, &mut ids);
        self.ids = ids;
        self.new_tets = new;
        self.removals += 1;
        Ok(total)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tet::dmesh::tests::three_around_an_edge;

    impl Journaled<'_> {
        /// The invariant checker of the domain mesh ([`DomainMesh::check`],
        /// ghost cells included) on these points.
        fn check(&self) -> Result<(), String> {
            self.m.check(self.pts())
        }
    }

    fn finite_tets(m: &Journaled<'_>) -> usize {
        m.m.live_slots()
            .filter(|&t| !m.m.tv[t as usize].contains(&INF))
            .count()
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

    fn has_edge(m: &Journaled<'_>, a: u32, b: u32) -> bool {
        m.find_edge(a, b).is_some()
    }

    #[test]
    fn rings_are_positively_ordered() {
        let pts = scattered(40);
        let m = Journaled::new(Delaunay3::from_points(&pts).unwrap());
        m.check().unwrap();
        let mut rings = 0;
        for (t, tv) in m.m.tv.iter().enumerate() {
            if tv[0] == DEAD || tv.contains(&INF) {
                continue;
            }
            if let Some((tets, r)) = m.edge_ring(t as u32, tv[0], tv[1]) {
                rings += 1;
                for i in 0..r.len() {
                    let q = [tv[0], tv[1], r[i], r[(i + 1) % r.len()]];
                    assert!(m.positive(q));
                    let x = m.m.tv[tets[i] as usize];
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
        let pts = three_around_an_edge();
        let mut m = Journaled::new(Delaunay3::from_points(&pts).unwrap());
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
                let tv = m.m.tv[t as usize];
                !tv.contains(&INF) && tv.contains(&0) && tv.contains(&1) && tv.contains(&2)
            })
            .unwrap();
        let f = m.m.tv[t as usize].iter().position(|&w| w == 3).unwrap();
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
        let mut m2 = Journaled::new(Delaunay3::from_points(&pts2).unwrap());
        let before = m2.m.tv.clone();
        for t in 0..m2.m.tv.len() as u32 {
            for f in 0..4 {
                let tv = m2.m.tv[t as usize];
                if tv[0] == DEAD || tv.contains(&INF) {
                    continue;
                }
                let nb = m2.m.tv[(m2.m.nb[t as usize][f] >> 2) as usize];
                if nb.contains(&INF) {
                    continue;
                }
                // Apexes 3 and 4 around face 0-1-2: 3-4 misses it.
                if face(tv, f).iter().all(|w| [0, 1, 2].contains(w)) {
                    assert!(!m2.flip23(t, f));
                }
            }
        }
        assert_eq!(m2.m.tv, before);
    }

    #[test]
    fn a_removal_at_or_above_its_limit_is_refused() {
        // Edge 3-4 of three tetrahedra: its one ring triangulation (face
        // 0-1-2) costs 5 here; a limit of 5 refuses it (nothing changed),
        // 6 lets it through.
        let pts = three_around_an_edge();
        let mut m = Journaled::new(Delaunay3::from_points(&pts).unwrap());
        let t = m.find_edge(3, 4).unwrap();
        let before = m.m.tv.clone();
        let costs: (TriCost<'_>, EdgeCost<'_>) = (&|_, _| 5, &|_, _, _| 0);
        assert_eq!(m.remove_edge_below(t, 3, 4, costs, 5), None);
        assert_eq!(m.m.tv, before);
        assert_eq!(m.removals, 0);
        m.check().unwrap();
        assert_eq!(m.remove_edge_below(t, 3, 4, costs, 6), Some(5));
        m.check().unwrap();
        assert!(!has_edge(&m, 3, 4));
    }

    #[test]
    fn touched_faces_and_failed_removals_are_logged() {
        let pts = three_around_an_edge();
        let mut m = Journaled::new(Delaunay3::from_points(&pts).unwrap());
        assert!(m.take_touched_raw().is_empty());
        let t = m.find_edge(3, 4).unwrap();
        m.remove_edge(t, 3, 4, &|_, _| 0, &|_, _, _| 0).unwrap();
        m.check().unwrap();
        let touched = m.take_touched_raw();
        // The removed faces around 3-4 and the new face 0-1-2 are logged.
        assert!(touched.contains(&[0, 1, 2]));
        assert!(touched.contains(&[0, 3, 4]) || touched.contains(&[1, 3, 4]));
        assert!(m.take_touched_raw().is_empty());
        // Random points: every interior-edge removal that fails is
        // memoized and fails again; a failure changes nothing.
        let pts = scattered(40);
        let mut m = Journaled::new(Delaunay3::from_points(&pts).unwrap());
        let mut failures = 0;
        for t in 0..m.m.tv.len() as u32 {
            let tv = m.m.tv[t as usize];
            if tv[0] == DEAD || tv.contains(&INF) || m.edge_ring(t, tv[0], tv[1]).is_none() {
                continue;
            }
            let before = m.m.tv.clone();
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
                assert_eq!(m.m.tv, before);
            } else if !long {
                assert_eq!(m.failed.len(), n);
            }
            m.check().unwrap();
        }
        assert!(failures > 0);
        m.check().unwrap();
    }

    /// The tetrahedra as sorted vertex sets, sorted.
    fn tet_sets(m: &Journaled<'_>) -> Vec<[u32; 4]> {
        let mut out: Vec<[u32; 4]> =
            m.m.tv
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
        let base = Journaled::new(Delaunay3::from_points(&pts).unwrap());
        let start = tet_sets(&base);
        let mut m = base.clone();
        m.start_log();
        let mut ops = 0;
        for t in 0..m.m.tv.len() as u32 {
            for f in 0..4 {
                if m.m.tv[t as usize][0] != DEAD && m.flip23(t, f) {
                    m.check().unwrap();
                    ops += 1;
                }
            }
            let tv = m.m.tv[t as usize];
            if tv[0] != DEAD
                && !tv.contains(&INF)
                && m.remove_edge(t, tv[0], tv[1], &|_, _| 0, &|_, _, _| 0)
                    .is_some()
            {
                m.check().unwrap();
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
        q.check().unwrap();
        assert_eq!(tet_sets(&q), start);
        // Rolled back from half way: the mesh of that moment.
        let mut h = base.clone();
        h.start_log();
        let half = h.replay(&log, &|_, _| true);
        assert_eq!(half, ops);
        h.check().unwrap();
        h.rollback(ops / 2);
        h.check().unwrap();
        h.rollback(0);
        h.check().unwrap();
        assert_eq!(tet_sets(&h), start);
        assert_eq!((h.flips23, h.removals), (0, 0));
        assert_eq!(h.log_mark(), 0);
    }

    /// Six points on a circle around the z axis (0..6) and two poles
    /// close to its plane (6 above, 7 below): edge 6-7 has six
    /// tetrahedra around it.
    fn hexagon_and_poles() -> Vec<[f64; 3]> {
        let mut pts: Vec<[f64; 3]> = (0..6)
            .map(|i| {
                let a = i as f64 * std::f64::consts::PI / 3.0;
                [a.cos(), a.sin(), 0.0]
            })
            .collect();
        pts.push([0.0, 0.0, 0.05]);
        pts.push([0.0, 0.0, -0.05]);
        pts
    }

    #[test]
    fn a_flip_plan_is_the_flip_and_changes_nothing() {
        // Every face of a scattered mesh: the plan exists exactly when the
        // 2-3 flip is made, leaves the mesh as it was, and applied gives
        // the flip's mesh.
        let pts = scattered(40);
        let base = Journaled::new(Delaunay3::from_points(&pts).unwrap());
        let (mut made, mut refused) = (0, 0);
        for t in 0..base.m.tv.len() as u32 {
            for f in 0..4 {
                let before = base.m.tv.clone();
                let plan = base.flip23_plan(t, f);
                assert_eq!(base.m.tv, before);
                let mut by_flip = base.clone();
                let flipped = by_flip.flip23(t, f);
                assert_eq!(plan.is_some(), flipped);
                if let Some(plan) = plan {
                    let mut by_plan = base.clone();
                    by_plan.apply_flip23(plan);
                    by_plan.check().unwrap();
                    assert_eq!(by_plan.m.tv, by_flip.m.tv);
                    assert_eq!(by_plan.flips23, 1);
                    made += 1;
                } else {
                    refused += 1;
                }
            }
        }
        assert!(made > 10 && refused > 10);
    }

    #[test]
    fn a_limit_from_the_ring_refuses_or_bounds_the_removal() {
        // Edge 6-7 with a ring of six: every triangulation of the hexagon
        // has three chords, so with one per chord the removal costs 3
        // (chord costs are computed lazily, each still counted once).
        let pts = hexagon_and_poles();
        let mut m = Journaled::new(Delaunay3::from_points(&pts).unwrap());
        let t = m.find_edge(6, 7).unwrap();
        let before = m.m.tv.clone();
        let costs: (TriCost<'_>, EdgeCost<'_>) = (&|_, _| 0, &|_, _, _| 1);
        // Refused by the ring (nothing changed, not memoized), then by a
        // limit of 3, then made under a limit of 4.
        let seen = std::cell::Cell::new(0);
        let refuse = |_: &[[f64; 3]], r: &[u32]| {
            seen.set(r.len());
            None
        };
        assert_eq!(m.remove_edge_limited(t, 6, 7, costs, refuse), None);
        assert_eq!(seen.get(), 6);
        assert!(m.failed.is_empty());
        assert_eq!(m.remove_edge_limited(t, 6, 7, costs, |_, _| Some(3)), None);
        assert_eq!(m.m.tv, before);
        m.check().unwrap();
        assert_eq!(
            m.remove_edge_limited(t, 6, 7, costs, |_, r| Some(r.len() as i64 - 2)),
            Some(3)
        );
        m.check().unwrap();
        assert!(!has_edge(&m, 6, 7));
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
        let mut m = Journaled::new(Delaunay3::from_points(&pts).unwrap());
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
        assert_eq!(finite_tets(&m), 2);
    }

    #[test]
    fn edge_removal_of_larger_rings() {
        // A ring of six points around the z axis: edge 6-7 has six
        // tetrahedra around it; removing it gives 2 * 6 - 4 = 8.
        let pts = hexagon_and_poles();
        let dt = Delaunay3::from_points(&pts).unwrap();
        let mut m = Journaled::new(dt);
        let t = m.find_edge(6, 7).unwrap();
        let (tets, ring) = m.edge_ring(t, 6, 7).unwrap();
        assert_eq!((tets.len(), ring.len()), (6, 6));
        let before = finite_tets(&m);
        m.remove_edge(t, 6, 7, &|_, _| 0, &|_, _, _| 1).unwrap();
        m.check().unwrap();
        assert_eq!(finite_tets(&m), before - 6 + 8);
    }
}
