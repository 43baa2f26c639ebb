//! The constrained domain mesh: the tetrahedra of a carved domain with
//! their constraints, held by recovery ([`crate::tet::recover`], with
//! ghost cells and a journal: [`journal`]), refinement
//! ([`crate::tet::refine`]) and optimisation ([`crate::tet::optimize`]),
//! and the local operations they share.
//!
//! # Where it starts and how it flows
//!
//! Recovery takes over the kernel's arrays (ghost cells included, no copy:
//! [`journal::Journaled`]) and flips and removes edges in them with a
//! journal for replay and rollback; carving marks the domain in the same
//! arrays and [`DomainMesh::carve`] keeps it (boundary faces [`NONE`],
//! subface marks, regions), handing it over with the output view
//! [`crate::tet::recover::Recovered`]. Refinement inserts points, flips and
//! records subfaces / subsegments in it; optimisation flips, removes edges
//! and faces, smooths and inserts in it. Each stage adds only its own
//! queues, caches and report. [`DomainMesh::from_neighbors`] builds it from
//! a `Recovered` for the public entries that start from one.
//!
//! # Layout
//!
//! Topology apart from coordinates (the points belong to the stage, which
//! rescales them):
//!
//! * `tv` — four vertices per slot, positively oriented (exact `orient3d`
//!   negative, the crate's convention); a free slot has [`DEAD`] vertices;
//! * `nb` — per face (opposite local vertex `f`) the packed word
//!   `4 * tet + facet` of the face seen from its other side, or
//!   [`NONE`] across the domain's boundary;
//! * `mask` — per slot, bit `f` set when face `f` is a *subface* (on the
//!   domain's boundary or on an interface between regions / an internal
//!   facet): never flipped, never crossed by a cavity;
//! * `reg` — region per slot (empty before carving); `free` — free slots (reused last freed
//!   first); `vt` — per vertex a live slot holding it (a hint);
//! * `ftri` — subface (sorted key) → input triangle ([`NONE`] for a hull
//!   face off the surface), `sedges` — edge → the subfaces holding it,
//!   `segs` — subsegment → input edge (filled by the stages that need
//!   them; [`DomainMesh::check`] checks them against the marks).
//!
//! Operations here: [`DomainMesh::replace`] (any set of tetrahedra by any
//! other filling the same polyhedron, adjacency and marks rebuilt: the
//! common end of flips, edge and face removal and insertion),
//! [`DomainMesh::star_walk`] (the star of a vertex, with visit stamps)
//! and [`DomainMesh::star_first`] (its first slot that holds something),
//! [`DomainMesh::edge_ring`] (the ordered ring around an edge, on
//! [`ring::walk`]) and the edge-removal dynamic program
//! [`ring::triangulate`] (objective as a parameter, used by recovery and
//! optimisation). [`DomainMesh::check`] is the invariant checker the tests
//! call after every operation.

#![allow(clippy::needless_range_loop)] // local face indices address several arrays at once

pub(crate) mod edges;
pub(crate) mod flip;
pub(crate) mod insert;
pub(crate) mod journal;
pub(crate) mod memo;
pub(crate) mod ring;

use crate::geom::ids::IdMap;
use std::cell::RefCell;

use delone_predicates::orient3d;

use crate::tet::local::{ekey, face, fkey, DEAD, INF};
use crate::NONE;

pub(crate) use ring::RingEnd;

pub(crate) use crate::tet::delaunay::Arrays;

/// The constrained domain mesh (see the [module documentation](self)).
#[derive(Debug, Clone, Default)]
pub(crate) struct DomainMesh {
    /// Vertices per slot ([`DEAD`] for a free slot).
    pub(crate) tv: Vec<[u32; 4]>,
    /// Packed neighbour words `4 * tet + facet`, [`NONE`] on the boundary.
    pub(crate) nb: Vec<[u32; 4]>,
    /// Subface bits per slot.
    pub(crate) mask: Vec<u8>,
    /// Region per slot; empty for a mesh without regions (recovery's,
    /// before carving: every slot in region 0).
    pub(crate) reg: Vec<u32>,
    /// Free slots.
    pub(crate) free: Vec<u32>,
    /// Per vertex: a live slot holding it, or [`DEAD`] (a vertex in no
    /// tetrahedron; see [`DomainMesh::slot_of_vertex`]).
    pub(crate) vt: Vec<u32>,
    /// Subface → input triangle.
    pub(crate) ftri: IdMap<[u32; 3], u32>,
    /// Edge → the subfaces holding it.
    pub(crate) sedges: IdMap<(u32, u32), Vec<[u32; 3]>>,
    /// Subsegment → input edge.
    pub(crate) segs: IdMap<(u32, u32), u32>,
    /// The slots of the current visit (see [`DomainMesh::mark_begin`]).
    marks: RefCell<Stamps>,
    /// Scratch of [`DomainMesh::replace`]: outer faces, open new faces and
    /// the removed tetrahedra's vertices (no allocation per call).
    scratch: Scratch,
    /// When kept (recovery's journal): the faces each
    /// [`DomainMesh::replace`] removes (between two old tetrahedra) and
    /// creates (between two new ones), in the order met.
    pub(crate) inner: Option<Vec<[u32; 3]>>,
}

/// The faces of an output view: see [`DomainMesh::output_faces`].
#[derive(Debug, Default)]
pub(crate) struct OutputFaces {
    /// Per tetrahedron: its neighbours ([`NONE`] across the boundary).
    pub(crate) neighbors: Vec<[u32; 4]>,
    /// Boundary faces, and the input triangle of each.
    pub(crate) boundary: Vec<[u32; 3]>,
    pub(crate) boundary_triangle: Vec<u32>,
    /// Subfaces between two tetrahedra, and the input triangle of each.
    pub(crate) interior_faces: Vec<[u32; 3]>,
    pub(crate) interior_triangle: Vec<u32>,
}

/// Scratch of [`DomainMesh::replace`]: outer faces (key, neighbour word,
/// subface bit), open new faces (key, word), removed vertices, and the
/// removed slots sorted (membership by binary search in large cavities).
/// Keys are packed ([`pack`]): one comparison of a word pair per face.
type Scratch = (Vec<(u128, u32, bool)>, Vec<(u128, u32)>, Vec<u32>, Vec<u32>);

/// A sorted face key packed in one integer (smallest vertex highest: the
/// integers order as the keys do).
#[inline]
fn pack(k: [u32; 3]) -> u128 {
    u128::from(k[0]) << 64 | u128::from(k[1]) << 32 | u128::from(k[2])
}

/// One bit of 64 chosen by a hash of face key `k` (a filter: faces with
/// different bits differ).
#[inline]
fn face_bit(k: [u32; 3]) -> u64 {
    let h = k[0].wrapping_mul(0x9E37_79B1)
        ^ k[1].wrapping_mul(0x85EB_CA77)
        ^ k[2].wrapping_mul(0xC2B2_AE3D);
    1 << (h >> 26)
}

/// The face key [`pack`] packed.
#[inline]
fn unpack(x: u128) -> [u32; 3] {
    [(x >> 64) as u32, (x >> 32) as u32, x as u32]
}

/// A set of slots as a stamp per slot: emptied in O(1) by a new epoch (a
/// visit of a walk or a cavity, without hashing).
#[derive(Debug, Clone, Default)]
pub(crate) struct Stamps {
    stamp: Vec<u32>,
    epoch: u32,
}

impl Stamps {
    /// Empties the set.
    pub(crate) fn clear(&mut self) {
        self.epoch = self.epoch.wrapping_add(1);
        if self.epoch == 0 {
            self.stamp.fill(0);
            self.epoch = 1;
        }
    }

    /// Adds `t`; true when it was not in the set.
    #[inline]
    pub(crate) fn insert(&mut self, t: u32) -> bool {
        if self.stamp.len() <= t as usize {
            self.stamp.resize(t as usize + 1, 0);
        }
        let s = &mut self.stamp[t as usize];
        let fresh = *s != self.epoch;
        *s = self.epoch;
        fresh
    }

    /// Is `t` in the set?
    #[inline]
    pub(crate) fn contains(&self, t: u32) -> bool {
        self.stamp.get(t as usize) == Some(&self.epoch)
    }
}

/// What a [`DomainMesh::replace`] left unmatched: old outer faces no new
/// tetrahedron took (boundary faces a boundary flip or a cone over them
/// removed) and new faces matching no old face (new boundary faces, given
/// [`NONE`] and a subface bit), in the order met (deterministic).
#[derive(Debug, Default)]
pub(crate) struct Unmatched {
    pub(crate) gone: Vec<[u32; 3]>,
    pub(crate) made: Vec<[u32; 3]>,
}

/// Outer faces above which [`DomainMesh::replace`] matches by hashing
/// instead of linear search.
const LINEAR: usize = 48;

/// Above this many removed slots, [`DomainMesh::replace`] tells an old
/// slot by binary search in a sorted copy rather than by a scan.
const LINEAR_OLD: usize = 16;

impl DomainMesh {
    /// The structure over a tetrahedralization's arrays (vertices `tv`, ghost
    /// cells included, packed neighbour words `nb`, free slots `free`) with
    /// vertex hints `vt` and no subface.
    pub(crate) fn from_arrays(
        tv: Vec<[u32; 4]>,
        nb: Vec<[u32; 4]>,
        free: Vec<u32>,
        vt: Vec<u32>,
    ) -> DomainMesh {
        let mask = vec![0; tv.len()];
        DomainMesh {
            tv,
            nb,
            mask,
            free,
            vt,
            ..DomainMesh::default()
        }
    }

    /// Builds the structure from tetrahedra `tets` (positive), their
    /// neighbour slots `neighbors` ([`NONE`] on the boundary) and regions
    /// `reg`, on `n_points` vertices. No subface marks yet (see
    /// [`DomainMesh::mark_face`]). `Err(t)` when tetrahedron `t` has a
    /// neighbour that does not share the face, or a vertex or neighbour out
    /// of range.
    pub(crate) fn from_neighbors(
        tets: &[[u32; 4]],
        neighbors: &[[u32; 4]],
        reg: &[u32],
        n_points: usize,
    ) -> Result<DomainMesh, usize> {
        let nt = tets.len();
        let mut nb = vec![[NONE; 4]; nt];
        for t in 0..nt {
            for i in 0..4 {
                let u = *neighbors.get(t).and_then(|n| n.get(i)).ok_or(t)?;
                if u == NONE {
                    continue;
                }
                let k = fkey(face(tets[t], i));
                let uv = *tets.get(u as usize).ok_or(t)?;
                let j = (0..4).find(|&j| fkey(face(uv, j)) == k).ok_or(t)?;
                nb[t][i] = 4 * u + j as u32;
            }
        }
        let mut vt = vec![DEAD; n_points];
        for (t, x) in tets.iter().enumerate() {
            for &q in x {
                *vt.get_mut(q as usize).ok_or(t)? = t as u32;
            }
        }
        let mut reg = reg.to_vec();
        reg.resize(nt, 0);
        Ok(DomainMesh {
            tv: tets.to_vec(),
            nb,
            mask: vec![0; nt],
            reg,
            vt,
            ..DomainMesh::default()
        })
    }

    /// Marks every face on the domain's boundary ([`NONE`] neighbour) and
    /// every face of `faces` (sorted keys, e.g. interfaces) as a subface.
    pub(crate) fn mark_subfaces(&mut self, faces: &crate::geom::ids::IdSet<[u32; 3]>) {
        for t in 0..self.tv.len() {
            if self.tv[t][0] == DEAD {
                continue;
            }
            for f in 0..4 {
                if self.nb[t][f] == NONE
                    || (!faces.is_empty() && faces.contains(&fkey(face(self.tv[t], f))))
                {
                    self.mask[t] |= 1 << f;
                }
            }
        }
    }

    /// Renumbers the live slots in their order (no free slot left), and
    /// resets each vertex hint to the last slot holding it (as
    /// [`DomainMesh::from_neighbors`] sets them) for `n_points` vertices:
    /// the structure [`DomainMesh::from_neighbors`] builds from the live
    /// tetrahedra listed in order.
    pub(crate) fn compact(&mut self, n_points: usize) {
        let mut map = vec![NONE; self.tv.len()];
        let mut k = 0u32;
        for (t, tv) in self.tv.iter().enumerate() {
            if tv[0] != DEAD {
                map[t] = k;
                k += 1;
            }
        }
        let mut w = 0;
        for t in 0..self.tv.len() {
            if map[t] == NONE {
                continue;
            }
            self.tv[w] = self.tv[t];
            self.nb[w] = self.nb[t].map(|x| {
                if x == NONE {
                    NONE
                } else {
                    4 * map[(x >> 2) as usize] + (x & 3)
                }
            });
            self.mask[w] = self.mask[t];
            if let Some(&r) = self.reg.get(t) {
                self.reg[w] = r;
            }
            w += 1;
        }
        self.tv.truncate(w);
        self.nb.truncate(w);
        self.mask.truncate(w);
        self.reg.truncate(w);
        self.free.clear();
        self.vt.clear();
        self.vt.resize(n_points, DEAD);
        for (t, x) in self.tv.iter().enumerate() {
            for &q in x {
                if let Some(h) = self.vt.get_mut(q as usize) {
                    *h = t as u32;
                }
            }
        }
    }

    /// Carves the mesh in place: keeps the live slots whose `region` is
    /// not [`NONE`] (ghost cells and removed cells have none), each in that
    /// region and with the subface bits `mask` (both per slot); the faces
    /// towards a removed slot become the boundary ([`NONE`]). The removed
    /// slots are dropped and the rest renumbered in slot order
    /// ([`DomainMesh::compact`], for `n_points` vertices), and the storage
    /// is trimmed to the domain.
    pub(crate) fn carve(&mut self, region: Vec<u32>, mask: Vec<u8>, n_points: usize) {
        let kept = |t: usize| region.get(t).is_some_and(|&r| r != NONE);
        for t in 0..self.tv.len() {
            if !kept(t) {
                self.tv[t] = [DEAD; 4];
                continue;
            }
            for w in &mut self.nb[t] {
                if !kept((*w >> 2) as usize) {
                    *w = NONE;
                }
            }
        }
        (self.reg, self.mask) = (region, mask);
        self.inner = None;
        self.marks = RefCell::default();
        self.compact(n_points);
        for v in [&mut self.tv, &mut self.nb] {
            v.shrink_to_fit();
        }
        self.mask.shrink_to_fit();
        self.reg.shrink_to_fit();
    }

    /// The faces of the output view ([`crate::tet::recover::Recovered`]) of
    /// a compacted mesh (every slot live, see [`DomainMesh::compact`]): per
    /// tetrahedron its neighbours (tetrahedron indices, [`NONE`] across the
    /// boundary); the boundary faces and the subfaces between two
    /// tetrahedra (once, from the lower-numbered one), in tetrahedron and
    /// face order, each seen from outside its tetrahedron, with
    /// `tri(tet, face, key)`, the input triangle of each.
    pub(crate) fn output_faces(&self, tri: impl Fn(usize, usize, [u32; 3]) -> u32) -> OutputFaces {
        let mut out = OutputFaces {
            neighbors: Vec::with_capacity(self.tv.len()),
            ..OutputFaces::default()
        };
        for (t, &tv) in self.tv.iter().enumerate() {
            let mut nbr = [NONE; 4];
            for (f, x) in nbr.iter_mut().enumerate() {
                let w = self.nb[t][f];
                let [a, b, c] = face(tv, f);
                let k = fkey([a, b, c]);
                if w == NONE {
                    out.boundary.push([a, c, b]);
                    out.boundary_triangle.push(tri(t, f, k));
                } else {
                    *x = w >> 2;
                    if self.mask[t] >> f & 1 == 1 && (t as u32) < *x {
                        out.interior_faces.push([a, c, b]);
                        out.interior_triangle.push(tri(t, f, k));
                    }
                }
            }
            out.neighbors.push(nbr);
        }
        out
    }

    /// Drops the subface and subsegment tables (the subface marks stay)
    /// and trims the cell arrays' spare capacity: for a stage that reads
    /// subfaces from the marks only, such as the optimisation, which would
    /// otherwise copy and maintain them.
    pub(crate) fn drop_tables(&mut self) {
        self.ftri = IdMap::default();
        self.sedges = IdMap::default();
        self.segs = IdMap::default();
        // The cell arrays leave refinement with up to half their capacity
        // unused (growth by doubling); optimisation changes the cell count
        // little, so it starts from an eighth of headroom.
        let keep = self.tv.len() + self.tv.len() / 8;
        self.tv.shrink_to(keep);
        self.nb.shrink_to(keep);
        self.mask.shrink_to(keep);
        self.reg.shrink_to(keep);
    }

    /// Moves the subface-table entries of boundary faces `gone` to `made`
    /// (a boundary flip, or a removal, within one facet): the new faces take
    /// the input triangle of the first old one. Nothing when the table is
    /// not kept.
    pub(crate) fn move_subfaces(&mut self, gone: &[[u32; 3]], made: &[[u32; 3]]) {
        if self.ftri.is_empty() {
            return;
        }
        let mut tri = None;
        for k in gone {
            tri = tri.or(self.ftri.remove(k));
            for e in [(k[0], k[1]), (k[0], k[2]), (k[1], k[2])] {
                if let Some(l) = self.sedges.get_mut(&e) {
                    l.retain(|x| x != k);
                    if l.is_empty() {
                        self.sedges.remove(&e);
                    }
                }
            }
        }
        let tri = tri.unwrap_or(NONE);
        for &k in made {
            self.ftri.insert(k, tri);
            for e in [(k[0], k[1]), (k[0], k[2]), (k[1], k[2])] {
                self.sedges.entry(e).or_default().push(k);
            }
        }
    }

    /// Is slot `t` live?
    #[inline]
    pub(crate) fn alive(&self, t: u32) -> bool {
        self.tv.get(t as usize).is_some_and(|x| x[0] != DEAD)
    }

    /// Is face `f` of slot `t` a subface?
    #[inline]
    pub(crate) fn is_sub(&self, t: u32, f: usize) -> bool {
        self.mask[t as usize] >> f & 1 == 1
    }

    /// The slot behind face `f` of `t` ([`NONE`] on the boundary).
    #[inline]
    pub(crate) fn across(&self, t: u32, f: usize) -> u32 {
        let w = self.nb[t as usize][f];
        if w == NONE {
            NONE
        } else {
            w >> 2
        }
    }

    /// Marks face `f` of `t` as a subface, on both sides.
    pub(crate) fn mark_face(&mut self, t: u32, f: usize) {
        self.mask[t as usize] |= 1 << f;
        let w = self.nb[t as usize][f];
        if w != NONE {
            self.mask[(w >> 2) as usize] |= 1 << (w & 3);
        }
    }

    /// Starts a new visit: no slot is marked.
    pub(crate) fn mark_begin(&self) {
        self.marks.borrow_mut().clear();
    }

    /// Marks slot `t` in the current visit; true when it was not marked.
    #[inline]
    pub(crate) fn mark(&self, t: u32) -> bool {
        self.marks.borrow_mut().insert(t)
    }

    /// Is slot `t` marked in the current visit?
    #[inline]
    pub(crate) fn marked(&self, t: u32) -> bool {
        self.marks.borrow().contains(t)
    }

    /// A new slot holding `tv` of region `reg` (no marks, no neighbours):
    /// the last freed slot, else a new one.
    pub(crate) fn new_tet(&mut self, tv: [u32; 4], reg: u32) -> u32 {
        match self.free.pop() {
            Some(t) => {
                self.tv[t as usize] = tv;
                if let Some(r) = self.reg.get_mut(t as usize) {
                    *r = reg;
                }
                self.mask[t as usize] = 0;
                self.nb[t as usize] = [NONE; 4];
                t
            }
            None => {
                let regions = self.reg.len() == self.tv.len();
                self.tv.push(tv);
                if regions {
                    self.reg.push(reg);
                }
                self.mask.push(0);
                self.nb.push([NONE; 4]);
                (self.tv.len() - 1) as u32
            }
        }
    }

    /// Frees slot `t`.
    pub(crate) fn release(&mut self, t: u32) {
        self.tv[t as usize] = [DEAD; 4];
        self.nb[t as usize] = [NONE; 4];
        self.mask[t as usize] = 0;
        self.free.push(t);
    }

    /// Links face `f` of `t` and face `g` of `u` (or `t`'s face to the
    /// boundary when `u` is [`NONE`]).
    #[inline]
    pub(crate) fn link(&mut self, t: u32, f: usize, w: u32) {
        self.nb[t as usize][f] = w;
        if w != NONE {
            self.nb[(w >> 2) as usize][(w & 3) as usize] = 4 * t + f as u32;
        }
    }

    /// Replaces slots `old` (connected) by the tetrahedra `new` of region
    /// `reg`, filling the same polyhedron but for boundary faces (see
    /// [`Unmatched`]): old slots are freed in order, new ones taken in
    /// order ([`DomainMesh::new_tet`]); a new face on an old outer face
    /// takes its neighbour and subface bit; new faces meeting each other
    /// are linked. The new slots are written to `ids` (cleared first).
    pub(crate) fn replace(
        &mut self,
        old: &[u32],
        new: &[[u32; 4]],
        reg: u32,
        ids: &mut Vec<u32>,
    ) -> Unmatched {
        // Outer faces: key, neighbour word, subface bit.
        let (mut outer, mut open, mut old_verts, mut sorted) = std::mem::take(&mut self.scratch);
        outer.clear();
        open.clear();
        old_verts.clear();
        // Is slot `u` one of `old`? A scan for small cavities, a binary
        // search in a sorted copy for large ones (same answers).
        sorted.clear();
        if old.len() > LINEAR_OLD {
            sorted.extend_from_slice(old);
            sorted.sort_unstable();
        }
        let is_old = |u: u32| {
            if old.len() > LINEAR_OLD {
                sorted.binary_search(&u).is_ok()
            } else {
                old.contains(&u)
            }
        };
        // The largest vertex of an outer face: a new face with a larger
        // one (through a new point) matches none. And a bit per outer face
        // ([`face_bit`]): a new face whose bit is not set matches none.
        let (mut top, mut bits) = (0, 0u64);
        for &t in old {
            let (tv, nb, mask) = (
                self.tv[t as usize],
                self.nb[t as usize],
                self.mask[t as usize],
            );
            old_verts.extend_from_slice(&tv);
            for f in 0..4 {
                let w = nb[f];
                if w != NONE && is_old(w >> 2) {
                    if let Some(l) = self.inner.as_mut().filter(|_| w >> 2 > t) {
                        l.push(fkey(face(tv, f)));
                    }
                    continue;
                }
                let k = fkey(face(tv, f));
                top = top.max(k[2]);
                bits |= face_bit(k);
                outer.push((pack(k), w, mask >> f & 1 == 1));
            }
        }
        for &t in old {
            self.release(t);
        }
        ids.clear();
        for &tv in new {
            let id = self.new_tet(tv, reg);
            // (A ghost cell's INF has no hint.)
            for &q in tv.iter().filter(|&&q| q != INF) {
                if self.vt.len() <= q as usize {
                    self.vt.resize(q as usize + 1, DEAD);
                }
                self.vt[q as usize] = id;
            }
            ids.push(id);
        }
        // A vertex left in no new tetrahedron (a collapse) keeps no hint.
        for &q in old_verts.iter().filter(|&&q| q != INF) {
            let h = self.vt[q as usize];
            if h != DEAD && !self.tv[h as usize].contains(&q) {
                self.vt[q as usize] = DEAD;
            }
        }
        let mut made = Vec::new();
        if outer.len() <= LINEAR {
            for &id in ids.iter() {
                let tv = self.tv[id as usize];
                for f in 0..4 {
                    let k = fkey(face(tv, f));
                    let x = pack(k);
                    let o = if k[2] > top || bits & face_bit(k) == 0 {
                        None
                    } else {
                        outer.iter().position(|o| o.0 == x)
                    };
                    if let Some(i) = o {
                        let (_, w, sub) = outer.swap_remove(i);
                        self.link(id, f, w);
                        self.mask[id as usize] |= u8::from(sub) << f;
                    } else if let Some(i) = open.iter().position(|o| o.0 == x) {
                        let (_, w) = open.swap_remove(i);
                        self.link(id, f, w);
                        if let Some(l) = &mut self.inner {
                            l.push(k);
                        }
                    } else {
                        open.push((x, 4 * id + f as u32));
                    }
                }
            }
            for (x, w) in open.drain(..) {
                self.mask[(w >> 2) as usize] |= 1 << (w & 3);
                made.push(unpack(x));
            }
        } else {
            let mut out: IdMap<[u32; 3], (u32, bool)> = outer
                .drain(..)
                .map(|(x, w, s)| (unpack(x), (w, s)))
                .collect();
            let mut open: IdMap<[u32; 3], u32> = IdMap::default();
            for &id in ids.iter() {
                let tv = self.tv[id as usize];
                for f in 0..4 {
                    let k = fkey(face(tv, f));
                    if let Some((w, sub)) = out.remove(&k) {
                        self.link(id, f, w);
                        self.mask[id as usize] |= u8::from(sub) << f;
                    } else if let Some(w) = open.remove(&k) {
                        self.link(id, f, w);
                        if let Some(l) = &mut self.inner {
                            l.push(k);
                        }
                    } else {
                        open.insert(k, 4 * id + f as u32);
                    }
                }
            }
            for (k, w) in open {
                self.mask[(w >> 2) as usize] |= 1 << (w & 3);
                made.push(k);
            }
            made.sort_unstable();
            outer.extend(out.into_iter().map(|(k, (w, s))| (pack(k), w, s)));
            outer.sort_unstable();
        }
        let gone: Vec<[u32; 3]> = outer.drain(..).map(|o| unpack(o.0)).collect();
        self.scratch = (outer, open, old_verts, sorted);
        Unmatched { gone, made }
    }

    /// The slots holding vertex `v` (its star), from the hint `vt[v]`;
    /// `cross(t, f)` tells whether the walk may pass face `f` of `t`.
    /// Empty when `v` is in no live slot.
    pub(crate) fn star_with(&self, v: u32, cross: impl Fn(u32, usize) -> bool) -> Vec<u32> {
        let mut out = Vec::with_capacity(32);
        self.star_walk(v, &mut out, cross);
        out
    }

    /// Walks the star of `v` into `out` (cleared first; breadth first from
    /// the hint, faces in local order, visited slots stamped), passing face
    /// `f` of `t` only when `cross(t, f)`. To find one slot of the star,
    /// [`DomainMesh::star_first`].
    pub(crate) fn star_walk(&self, v: u32, out: &mut Vec<u32>, cross: impl Fn(u32, usize) -> bool) {
        self.star_search(v, out, cross, |_| false);
    }

    /// The first slot of `v`'s star, in the breadth-first order of
    /// [`DomainMesh::star_walk`] with every face crossable, for which
    /// `stop` holds. A slot is tested when it joins the queue (the queue's
    /// order is the walk's, so the first found is the same), and the walk
    /// ends there: the slots still queued before it are not expanded.
    /// `out` is scratch (the slots reached); `stop` must not start another
    /// visit.
    pub(crate) fn star_first(
        &self,
        v: u32,
        out: &mut Vec<u32>,
        stop: impl Fn(u32) -> bool,
    ) -> Option<u32> {
        self.star_search(v, out, |_, _| true, stop)
    }

    /// The walk of [`DomainMesh::star_walk`] (faces passed when `cross`
    /// holds) that ends at the first slot for which `stop` holds, tested
    /// as it joins the queue ([`DomainMesh::star_first`]); `out` holds the
    /// slots reached before it. One borrow of the visit stamps for the
    /// walk: neither closure may start another visit.
    fn star_search(
        &self,
        v: u32,
        out: &mut Vec<u32>,
        cross: impl Fn(u32, usize) -> bool,
        stop: impl Fn(u32) -> bool,
    ) -> Option<u32> {
        out.clear();
        let start = self.slot_of_vertex(v)?;
        if stop(start) {
            return Some(start);
        }
        let mut marks = self.marks.borrow_mut();
        marks.clear();
        out.push(start);
        marks.insert(start);
        let mut i = 0;
        while i < out.len() {
            let t = out[i];
            i += 1;
            let tv = self.tv[t as usize];
            for (f, &u) in tv.iter().enumerate() {
                if u == v {
                    continue;
                }
                let n = self.across(t, f);
                if n != NONE && cross(t, f) && marks.insert(n) {
                    if stop(n) {
                        return Some(n);
                    }
                    out.push(n);
                }
            }
        }
        None
    }

    /// A live slot holding vertex `v`: the hint, else a scan.
    pub(crate) fn slot_of_vertex(&self, v: u32) -> Option<u32> {
        let t = *self.vt.get(v as usize)?;
        if t == DEAD {
            return None;
        }
        if self.alive(t) && self.tv[t as usize].contains(&v) {
            return Some(t);
        }
        self.tv
            .iter()
            .position(|x| x[0] != DEAD && x.contains(&v))
            .map(|t| t as u32)
    }

    /// The ordered ring around edge `a b` of slot `t` (see [`ring::walk`]):
    /// the slots, the ring vertices (`[a, b, ring[i], ring[i + 1]]` is slot
    /// `i`) and whether it is open (the edge is on the boundary: then the
    /// walk starts at one boundary face and ends at the other, and `ring`
    /// has one vertex more). `pass(t, f)` tells whether face `f` of `t` may
    /// be crossed; with `open_ok` false an open ring gives `None`. `None`
    /// beyond `cap` slots too, and when `t` is not a live slot holding the
    /// edge.
    pub(crate) fn edge_ring(
        &self,
        t: u32,
        ab: (u32, u32),
        cap: usize,
        open_ok: bool,
        pass: impl Fn(u32, usize) -> bool,
    ) -> Option<(Vec<u32>, Vec<u32>, RingEnd)> {
        // Room for a ring of up to 16 (the optimiser's cap) at once.
        let room = cap.min(16) + 1;
        let (mut tets, mut ring) = (Vec::with_capacity(room), Vec::with_capacity(room));
        let end = self.ring_into(t, ab, (cap, open_ok), pass, (&mut tets, &mut ring))?;
        Some((tets, ring, end))
    }

    /// [`DomainMesh::edge_ring`] into `tets` and `ring` (cleared first;
    /// reused scratch), returning how the ring ends.
    pub(crate) fn ring_into(
        &self,
        t: u32,
        (a, b): (u32, u32),
        (cap, open_ok): (usize, bool),
        pass: impl Fn(u32, usize) -> bool,
        (tets, ring): (&mut Vec<u32>, &mut Vec<u32>),
    ) -> Option<RingEnd> {
        tets.clear();
        ring.clear();
        let tv = *self.tv.get(t as usize)?;
        if tv[0] == DEAD || !tv.contains(&a) || !tv.contains(&b) {
            return None;
        }
        let (x0, y0) = ring::opposite(tv, a, b)?;
        let verts = |t: u32| self.tv[t as usize];
        let cross = |t: u32, f: usize| {
            let w = self.nb[t as usize][f];
            if w == NONE {
                Ok(None)
            } else if pass(t, f) {
                Ok(Some(w >> 2))
            } else {
                Err(())
            }
        };
        let end = ring::walk(t, (x0, y0), (a, b), cap, (tets, ring), verts, cross)?;
        if end == RingEnd::Closed {
            return Some(end);
        }
        if !open_ok {
            return None;
        }
        // On the boundary: back to the other end (across the faces
        // opposite `y`), then forward from there.
        let (mut c, mut cx, mut cy) = (t, x0, y0);
        let mut steps = 0;
        loop {
            let iy = self.tv[c as usize].iter().position(|&w| w == cy)?;
            let prev = self.nb[c as usize][iy];
            if prev == NONE {
                break;
            }
            steps += 1;
            if !pass(c, iy) || steps >= cap {
                return None;
            }
            let prev = prev >> 2;
            let z = self.tv[prev as usize]
                .into_iter()
                .find(|&w| w != a && w != b && w != cx)?;
            c = prev;
            cy = cx;
            cx = z;
        }
        tets.clear();
        ring.clear();
        // From a boundary end the walk cannot come back to its start.
        match ring::walk(c, (cx, cy), (a, b), cap, (tets, ring), verts, cross)? {
            RingEnd::Open => Some(RingEnd::Open),
            RingEnd::Closed => None,
        }
    }

    /// In the crate's unit tests: [`DomainMesh::check`] on points `p`,
    /// panicking with `what` on a violation (the stages call it after every
    /// operation). Nothing otherwise.
    #[inline]
    pub(crate) fn debug_check(&self, _p: &[[f64; 3]], _what: &str) {
        #[cfg(test)]
        if let Err(e) = self.check(_p) {
            panic!("{_what}: {e}");
        }
    }

    /// The live slots.
    pub(crate) fn live_slots(&self) -> impl Iterator<Item = u32> + '_ {
        (0..self.tv.len() as u32).filter(|&t| self.tv[t as usize][0] != DEAD)
    }

    /// Checks the invariants on points `p`: array lengths; free slots dead
    /// and live ones not free; every live tetrahedron strictly positive
    /// (exact `orient3d`) on distinct vertices, but for ghost cells (one
    /// [`INF`], last); neighbour words symmetric
    /// and on the same face; subface bits equal on both sides; regions
    /// equal across faces that are not subfaces; every vertex hint a live
    /// slot holding it; when `ftri` is filled, its keys exactly the
    /// subfaces; `sedges` and `segs` on edges of subfaces / live edges.
    pub(crate) fn check(&self, p: &[[f64; 3]]) -> Result<(), String> {
        let n = self.tv.len();
        let regions = !self.reg.is_empty();
        if self.nb.len() != n || self.mask.len() != n || (regions && self.reg.len() != n) {
            return Err("array lengths differ".into());
        }
        let mut is_free = vec![false; n];
        for &t in &self.free {
            let t = t as usize;
            if t >= n || self.tv[t][0] != DEAD || is_free[t] {
                return Err(format!("free slot {t} is live or listed twice"));
            }
            is_free[t] = true;
        }
        let mut subfaces: Vec<[u32; 3]> = Vec::new();
        let mut edges: Vec<(u32, u32)> = Vec::new();
        for t in 0..n {
            let tv = self.tv[t];
            if tv[0] == DEAD {
                if !is_free[t] {
                    return Err(format!("dead slot {t} is not free"));
                }
                continue;
            }
            if tv.iter().any(|&q| q != INF && q as usize >= p.len()) {
                return Err(format!("tet {t} {tv:?}: vertex out of range"));
            }
            let ghost = tv.contains(&INF);
            if ghost && tv[..3].contains(&INF) {
                return Err(format!("ghost cell {t} {tv:?}: INF not last, or twice"));
            }
            let g = |i: usize| &p[tv[i] as usize];
            if !ghost && orient3d(g(0), g(1), g(2), g(3)) >= 0.0 {
                return Err(format!("tet {t} {tv:?} is not strictly positive"));
            }
            for (i, j) in crate::tet::local::EDGES {
                edges.push(ekey(tv[i], tv[j]));
            }
            for f in 0..4 {
                let k = fkey(face(tv, f));
                let w = self.nb[t][f];
                let sub = self.mask[t] >> f & 1 == 1;
                if sub && (w == NONE || (w >> 2) as usize > t) {
                    subfaces.push(k);
                }
                if w == NONE {
                    if !sub {
                        return Err(format!("tet {t} face {f}: boundary face without a mark"));
                    }
                    continue;
                }
                let (u, g) = ((w >> 2) as usize, (w & 3) as usize);
                if u >= n || self.tv[u][0] == DEAD {
                    return Err(format!("tet {t} face {f}: neighbour {u} is not live"));
                }
                if self.nb[u][g] != 4 * t as u32 + f as u32 {
                    return Err(format!(
                        "tet {t} face {f}: neighbour {u} does not link back"
                    ));
                }
                // The same face seen from the other side: theirs is a
                // rotation of mine reversed.
                let (mine, theirs) = (face(tv, f), face(self.tv[u], g));
                if !(0..3).any(|s| (0..3).all(|i| theirs[(i + s) % 3] == mine[(3 - i) % 3])) {
                    return Err(format!(
                        "tet {t} face {f}: neighbour {u} has another face, or the same orientation"
                    ));
                }
                if self.tv[u][g] == tv[f] {
                    return Err(format!("tet {t} face {f}: same apex on both sides"));
                }
                if (self.mask[u] >> g & 1 == 1) != sub {
                    return Err(format!("tet {t} face {f}: subface mark on one side only"));
                }
                if !sub && regions && self.reg[u] != self.reg[t] {
                    return Err(format!(
                        "tet {t} face {f}: region changes across a free face"
                    ));
                }
            }
        }
        for (v, &t) in self.vt.iter().enumerate() {
            if t != DEAD
                && !self
                    .tv
                    .get(t as usize)
                    .is_some_and(|x| x.contains(&(v as u32)))
            {
                return Err(format!("vertex {v}: hint {t} does not hold it"));
            }
        }
        if !self.ftri.is_empty() {
            subfaces.sort_unstable();
            let mut keys: Vec<[u32; 3]> = self.ftri.keys().copied().collect();
            keys.sort_unstable();
            if keys != subfaces {
                return Err(format!(
                    "{} subfaces marked, {} in the subface table",
                    subfaces.len(),
                    keys.len()
                ));
            }
            for (e, l) in &self.sedges {
                if l.iter()
                    .any(|k| !self.ftri.contains_key(k) || !k.contains(&e.0) || !k.contains(&e.1))
                {
                    return Err(format!(
                        "edge {e:?}: listed with a face that is not its subface"
                    ));
                }
            }
        }
        edges.sort_unstable();
        for e in self.segs.keys() {
            if edges.binary_search(e).is_err() {
                return Err(format!("subsegment {e:?} is not an edge of the mesh"));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
pub(crate) mod tests;
