//! Restoring the constrained Delaunay property of the refinement's mesh by
//! flips (Joe's flip algorithm restricted to faces that are not subfaces,
//! as in Shewchuk's *Updating and constructing constrained Delaunay and
//! constrained regular triangulations by flips*, 2003).
//!
//! A face shared by two tetrahedra of the domain, not a subface, is
//! *locally Delaunay* when the apex of either tetrahedron is not strictly
//! inside the other's circumsphere (exact `insphere`). A face that is not
//! is flipped:
//!
//! * **2-3** when the segment between the two apexes crosses the face's
//!   interior (the three new tetrahedra around it are strictly positive by
//!   exact `orient3d`);
//! * **3-2** when an edge of the face has exactly three tetrahedra around
//!   it, none of their faces through it a subface, and the two tetrahedra
//!   replacing them are strictly positive.
//!
//! Otherwise the face is left (a degenerate or unflippable configuration;
//! rare). Every flip strictly lowers the lifted (paraboloid) volume, so the
//! process terminates. Subfaces are never flipped and no edge of a subface
//! is removed (3-2 flips need the three faces around the removed edge to be
//! unconstrained), so the constraints and the regions stay intact.

use delone_predicates::orient3d;

use super::Cdr;
use crate::tet::local::DEAD;
use crate::tet::local::{face, fkey};
use crate::NONE;

/// A face waiting for the flip test: tetrahedron, its vertices when
/// queued (stale entries are dropped), local face.
type Item = (u32, [u32; 4], usize);

impl Cdr {
    /// Is tetrahedron `[a, b, c, d]` strictly positive (the orientation of
    /// the mesh)?
    fn positive(&self, t: [u32; 4]) -> bool {
        let g = |q: u32| &self.p[q as usize];
        orient3d(g(t[0]), g(t[1]), g(t[2]), g(t[3])) < 0.0
    }

    /// Flips every non-locally-Delaunay face reachable from the faces of
    /// `seeds` (all tetrahedra when `seeds` is `None`); returns the new
    /// tetrahedra (possibly dead by the end) for the caller to re-check.
    pub(super) fn flip_delaunay(&mut self, seeds: Option<&[u32]>) -> Vec<u32> {
        let mut stack: Vec<Item> = Vec::new();
        let push_all = |st: &Cdr, stack: &mut Vec<Item>, t: u32| {
            let tv = st.tv[t as usize];
            if tv[0] != DEAD {
                for f in 0..4 {
                    stack.push((t, tv, f));
                }
            }
        };
        match seeds {
            Some(s) => {
                for &t in s {
                    push_all(self, &mut stack, t);
                }
            }
            None => {
                for t in (0..self.tv.len() as u32).rev() {
                    push_all(self, &mut stack, t);
                }
            }
        }
        let mut made = Vec::new();
        let mut steps = 0usize;
        let max_steps = 50 * self.tv.len() + 10_000;
        while let Some((t, tv, f)) = stack.pop() {
            steps += 1;
            if steps > max_steps {
                break;
            }
            if self.tv[t as usize] != tv {
                continue;
            }
            if let Some(new) = self.try_flip(t, f) {
                for &n in &new {
                    push_all(self, &mut stack, n);
                }
                made.extend(new);
            }
        }
        made.retain(|&t| self.tv[t as usize][0] != DEAD);
        made.sort_unstable();
        made.dedup();
        made
    }

    /// Flips face `f` of `t` when it is not locally Delaunay and a 2-3 or
    /// 3-2 flip applies; returns the new tetrahedra.
    fn try_flip(&mut self, t: u32, f: usize) -> Option<Vec<u32>> {
        let w = self.nb[t as usize][f];
        if w == NONE || self.mask[t as usize] >> f & 1 == 1 {
            return None;
        }
        let (u, g) = (w >> 2, (w & 3) as usize);
        let tv = self.tv[t as usize];
        let e = self.tv[u as usize][g];
        if !self.in_sphere(t, &self.pt(e)) {
            return None;
        }
        if self.reg[t as usize] != self.reg[u as usize] {
            return None;
        }
        let d = tv[f];
        let [x, y, z] = face(tv, f);
        // 2-3: the three tetrahedra around the new edge d e.
        let cand = [[x, y, d, e], [y, z, d, e], [z, x, d, e]];
        let sgn: Vec<f64> = cand
            .iter()
            .map(|c| {
                let g = |q: u32| &self.p[q as usize];
                orient3d(g(c[0]), g(c[1]), g(c[2]), g(c[3]))
            })
            .collect();
        if cand.iter().any(|&c| self.flat(c, None)) {
            return None;
        }
        if sgn.iter().all(|&s| s < 0.0) {
            return Some(self.replace(&[t, u], &cand));
        }
        if sgn.iter().all(|&s| s > 0.0) {
            let c = cand.map(|c| [c[1], c[0], c[2], c[3]]);
            return Some(self.replace(&[t, u], &c));
        }
        // 3-2 across an edge of the face with three tetrahedra around it.
        for (a, b, c) in [(x, y, z), (y, z, x), (z, x, y)] {
            // The tetrahedron of `t` across face a b d (opposite c).
            let ic = tv.iter().position(|&q| q == c)?;
            if self.mask[t as usize] >> ic & 1 == 1 {
                continue;
            }
            let wv = self.nb[t as usize][ic];
            if wv == NONE {
                continue;
            }
            let v = wv >> 2;
            let vv = self.tv[v as usize];
            if !vv.contains(&e) || self.reg[v as usize] != self.reg[t as usize] {
                continue;
            }
            // Face a b e of `v` (opposite d) must be u's neighbour and free.
            let Some(id) = vv.iter().position(|&q| q == d) else {
                continue;
            };
            if self.mask[v as usize] >> id & 1 == 1 || self.nb[v as usize][id] >> 2 != u {
                continue;
            }
            let mut n1 = [d, e, c, a];
            let mut n2 = [d, e, c, b];
            if !self.positive(n1) {
                n1.swap(0, 1);
            }
            if !self.positive(n2) {
                n2.swap(0, 1);
            }
            if self.positive(n1)
                && self.positive(n2)
                && !self.flat(n1, None)
                && !self.flat(n2, None)
            {
                return Some(self.replace(&[t, u, v], &[n1, n2]));
            }
        }
        None
    }

    /// Replaces the tetrahedra `old` (one region, no subface between them)
    /// by `new` (positive, filling the same polyhedron): the outer faces keep
    /// their neighbours and subface marks.
    fn replace(&mut self, old: &[u32], new: &[[u32; 4]]) -> Vec<u32> {
        let reg = self.reg[old[0] as usize];
        // Outer faces of the old tetrahedra: key, neighbour word, subface.
        let mut outer: Vec<([u32; 3], u32, bool)> = Vec::with_capacity(2 * old.len() + 2);
        for &t in old {
            let tv = self.tv[t as usize];
            for f in 0..4 {
                let w = self.nb[t as usize][f];
                if w != NONE && old.contains(&(w >> 2)) {
                    continue;
                }
                outer.push((fkey(face(tv, f)), w, self.mask[t as usize] >> f & 1 == 1));
            }
        }
        for &t in old {
            self.tv[t as usize][0] = DEAD;
            self.free.push(t);
        }
        let mut ids = Vec::with_capacity(new.len());
        for &tv in new {
            let id = self.new_tet(tv, reg);
            for &q in &tv {
                self.vt[q as usize] = id;
            }
            ids.push(id);
        }
        let mut inner: Vec<([u32; 3], u32, usize)> = Vec::new();
        for &id in &ids {
            let tv = self.tv[id as usize];
            for f in 0..4 {
                let k = fkey(face(tv, f));
                if let Some(&(_, w, sub)) = outer.iter().find(|o| o.0 == k) {
                    self.nb[id as usize][f] = w;
                    if w != NONE {
                        self.nb[(w >> 2) as usize][(w & 3) as usize] = 4 * id + f as u32;
                    }
                    if sub {
                        self.mask[id as usize] |= 1 << f;
                    }
                } else if let Some(pos) = inner.iter().position(|o| o.0 == k) {
                    let (_, o, g) = inner.swap_remove(pos);
                    self.nb[id as usize][f] = 4 * o + g as u32;
                    self.nb[o as usize][g] = 4 * id + f as u32;
                } else {
                    inner.push((k, id, f));
                }
            }
        }
        debug_assert!(inner.is_empty());
        ids
    }
}
