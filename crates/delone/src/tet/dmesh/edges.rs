//! Edge split and edge collapse on the [`DomainMesh`], with the subface
//! table `ftri` carried along: the two operations that change the vertex
//! set of a mesh in place (metric adaptation, [`crate::adapt`]). Both build
//! the new tetrahedra of a cavity, refuse any that is not strictly
//! positive by exact `orient3d`, and commit through
//! [`DomainMesh::replace`]; regions stay per tetrahedron and subfaces keep
//! their input triangle, so interfaces between regions are kept too.

use super::flip::positive;
use super::DomainMesh;
use crate::tet::local::{face, fkey};
use crate::NONE;

/// The face key of `k` with vertex `from` replaced by `to`.
fn swap_key(k: [u32; 3], from: u32, to: u32) -> [u32; 3] {
    fkey(k.map(|q| if q == from { to } else { q }))
}

impl DomainMesh {
    /// A live slot holding edge `a b` (a walk of the star of `a`).
    pub(crate) fn edge_slot(&self, a: u32, b: u32) -> Option<u32> {
        let mut out = Vec::new();
        self.star_first(a, &mut out, |t| self.tv[t as usize].contains(&b))
    }

    /// The slots around edge `a b` (its shell, crossing subfaces and
    /// region changes), at most `cap`.
    pub(crate) fn edge_shell(&self, a: u32, b: u32, cap: usize) -> Option<Vec<u32>> {
        let t = self.edge_slot(a, b)?;
        self.edge_ring(t, (a, b), cap, true, |_, _| true)
            .map(|(tets, _, _)| tets)
    }

    /// The subfaces (sorted keys, each once) of slots `tets` holding vertex
    /// `v`, with their entry in the subface table ([`NONE`] when absent).
    pub(crate) fn subfaces_at(&self, tets: &[u32], v: u32) -> Vec<([u32; 3], u32)> {
        let mut out: Vec<([u32; 3], u32)> = Vec::new();
        for &t in tets {
            let tv = self.tv[t as usize];
            for f in 0..4 {
                if tv[f] != v && self.is_sub(t, f) {
                    let k = fkey(face(tv, f));
                    if !out.iter().any(|x| x.0 == k) {
                        out.push((k, self.ftri.get(&k).copied().unwrap_or(NONE)));
                    }
                }
            }
        }
        out
    }

    /// Replaces slots `old` by tetrahedra `new` of regions `regs` (one per
    /// tetrahedron; see [`DomainMesh::replace`]), after the subface table
    /// has been updated: the subface bits of the new tetrahedra's faces are
    /// set from it (both sides), so a face inside the cavity can be a
    /// subface (an interface). Returns the new slots.
    fn commit(&mut self, old: &[u32], new: &[[u32; 4]], regs: &[u32]) -> Vec<u32> {
        let mut ids = Vec::with_capacity(new.len());
        self.replace(old, new, regs[0], &mut ids);
        for (&id, &r) in ids.iter().zip(regs) {
            if let Some(x) = self.reg.get_mut(id as usize) {
                *x = r;
            }
        }
        for &id in &ids {
            let tv = self.tv[id as usize];
            for f in 0..4 {
                let w = self.nb[id as usize][f];
                let sub = w == NONE || self.ftri.contains_key(&fkey(face(tv, f)));
                let bit = |m: u8, f: usize| (m & !(1 << f)) | (u8::from(sub) << f);
                self.mask[id as usize] = bit(self.mask[id as usize], f);
                if w != NONE {
                    let (u, g) = ((w >> 2) as usize, (w & 3) as usize);
                    self.mask[u] = bit(self.mask[u], g);
                }
            }
        }
        ids
    }

    /// Splits edge `a b` at vertex `m` (already among points `p`): every
    /// tetrahedron of the edge's shell becomes the two with `a`, resp.
    /// `b`, replaced by `m`, in its region; every subface through `a b`
    /// becomes the two halves, with its input triangle. Nothing changes
    /// and `None` is returned when the edge is missing or a new
    /// tetrahedron is not strictly positive (exact); else the new slots.
    pub(crate) fn split_edge(
        &mut self,
        p: &[[f64; 3]],
        (a, b): (u32, u32),
        m: u32,
    ) -> Option<Vec<u32>> {
        let shell = self.edge_shell(a, b, 256)?;
        let mut new = Vec::with_capacity(2 * shell.len());
        let mut regs = Vec::with_capacity(2 * shell.len());
        for &t in &shell {
            let tv = self.tv[t as usize];
            for q in [a, b] {
                new.push(tv.map(|x| if x == q { m } else { x }));
                regs.push(self.reg.get(t as usize).copied().unwrap_or(0));
            }
        }
        if !new.iter().all(|&n| positive(p, n)) {
            return None;
        }
        for (k, tri) in self.subfaces_at(&shell, a) {
            if k.contains(&b) {
                self.ftri.remove(&k);
                self.ftri.insert(swap_key(k, a, m), tri);
                self.ftri.insert(swap_key(k, b, m), tri);
            }
        }
        Some(self.commit(&shell, &new, &regs))
    }

    /// Collapses vertex `v` onto its neighbour `w`: the tetrahedra of `v`'s
    /// star `ball` holding `w` disappear, the others take `w` for `v` (in
    /// their regions), and so do the subfaces through `v` (those through
    /// `v w` disappear): `subs` is [`DomainMesh::subfaces_at`] of `ball`
    /// and `v`, which the caller has already. Nothing changes and `None` is returned when a new
    /// tetrahedron is not strictly positive (exact) or `accept` refuses the
    /// new tetrahedra; else the new slots. Which collapses keep the domain's
    /// boundary (a vertex on a facet collapsing inside it) is the caller's
    /// to decide.
    pub(crate) fn collapse_edge(
        &mut self,
        p: &[[f64; 3]],
        ball: &[u32],
        subs: &[([u32; 3], u32)],
        (v, w): (u32, u32),
        accept: impl FnOnce(&[[u32; 4]]) -> bool,
    ) -> Option<Vec<u32>> {
        let mut new = Vec::with_capacity(ball.len());
        let mut regs = Vec::with_capacity(ball.len());
        for &t in ball {
            let tv = self.tv[t as usize];
            if !tv.contains(&w) {
                new.push(tv.map(|x| if x == v { w } else { x }));
                regs.push(self.reg.get(t as usize).copied().unwrap_or(0));
            }
        }
        if new.is_empty() || !new.iter().all(|&n| positive(p, n)) || !accept(&new) {
            return None;
        }
        for (k, _) in subs {
            self.ftri.remove(k);
        }
        for &(k, tri) in subs {
            if !k.contains(&w) {
                self.ftri.insert(swap_key(k, v, w), tri);
            }
        }
        Some(self.commit(ball, &new, &regs))
    }
}
