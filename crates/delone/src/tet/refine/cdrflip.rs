//! Restoring the constrained Delaunay property of the refinement's mesh by
//! flips (Joe's flip algorithm restricted to faces that are not subfaces,
//! as in Shewchuk's *Updating and constructing constrained Delaunay and
//! constrained regular triangulations by flips*, 2003).
//!
//! A face shared by two tetrahedra of the domain, not a subface, is
//! *locally Delaunay* when the apex of either tetrahedron is not strictly
//! inside the other's circumsphere (exact `insphere`). A face that is not
//! is flipped 2-3 or 3-2
//! ([`DomainMesh::flip_face`](crate::tet::dmesh::DomainMesh::flip_face): positive new
//! tetrahedra, no subface destroyed, no region crossed), unless a new
//! tetrahedron would be flat on an input facet; otherwise it is left (a
//! degenerate or unflippable configuration; rare). Every flip strictly
//! lowers the lifted (paraboloid) volume, so the process terminates.

use super::Cdr;
use crate::tet::local::DEAD;
use crate::NONE;

/// A face waiting for the flip test: tetrahedron, its vertices when
/// queued (stale entries are dropped), local face.
type Item = (u32, [u32; 4], u8);

impl Cdr {
    /// Flips every non-locally-Delaunay face reachable from the faces of
    /// `seeds` (all tetrahedra when `seeds` is `None`); returns the new
    /// tetrahedra (possibly dead by the end) for the caller to re-check.
    ///
    /// The faces wait on a stack (last queued, first tested). With `seeds`
    /// `None` its bottom is every face of every tetrahedron, tested in
    /// order of tetrahedron and from face 3 down to 0: that part is not
    /// stored as items but read from a copy of the vertex lists taken at
    /// the start (16 bytes a tetrahedron instead of four items).
    pub(super) fn flip_delaunay(&mut self, seeds: Option<&[u32]>) -> Vec<u32> {
        let mut stack: Vec<Item> = Vec::with_capacity(4 * seeds.map_or(0, |s| s.len()) + 16);
        let push_all = |st: &Cdr, stack: &mut Vec<Item>, t: u32| {
            let tv = st.m.tv[t as usize];
            if tv[0] != DEAD {
                for f in 0..4 {
                    stack.push((t, tv, f));
                }
            }
        };
        // The bottom of the stack with `seeds` `None`: the vertex lists at
        // the start and the next face to test, (tetrahedron, face + 1).
        let mut bottom = Vec::new();
        let mut next = (0usize, 0u8);
        match seeds {
            Some(s) => {
                // A face between two seeds is queued from the later seed
                // only, whose entry pops first: the earlier seed's entry
                // would test the same face again (the in-sphere test gives
                // one answer from either side) or, if a flip has changed
                // its neighbour since, a face that the new neighbour's own
                // entries have already tested.
                let mut skip = vec![0u8; s.len()];
                self.m.mark_begin();
                for (i, &t) in s.iter().enumerate().rev() {
                    for f in 0..4 {
                        let w = self.m.nb[t as usize][f];
                        if w != NONE && self.m.marked(w >> 2) {
                            skip[i] |= 1 << f;
                        }
                    }
                    self.m.mark(t);
                }
                for (&t, &k) in s.iter().zip(&skip) {
                    let tv = self.m.tv[t as usize];
                    if tv[0] != DEAD {
                        for f in 0..4 {
                            if k >> f & 1 == 0 {
                                stack.push((t, tv, f));
                            }
                        }
                    }
                }
            }
            None => bottom.clone_from(&self.m.tv),
        }
        let mut made = Vec::with_capacity(16);
        let mut steps = 0usize;
        let max_steps = 50 * self.m.tv.len() + 10_000;
        loop {
            let (t, tv, f) = match stack.pop() {
                Some(item) => item,
                None => {
                    while next.1 == 0 && next.0 < bottom.len() {
                        if bottom[next.0][0] == DEAD {
                            next.0 += 1;
                        } else {
                            next.1 = 4;
                        }
                    }
                    if next.1 == 0 {
                        break;
                    }
                    next.1 -= 1;
                    let item = (next.0 as u32, bottom[next.0], next.1);
                    if next.1 == 0 {
                        next.0 += 1;
                    }
                    item
                }
            };
            steps += 1;
            if steps > max_steps {
                break;
            }
            if self.m.tv[t as usize] != tv {
                continue;
            }
            if let Some(new) = self.try_flip(t, usize::from(f)) {
                for &n in &new {
                    push_all(self, &mut stack, n);
                }
                made.extend(new);
            }
        }
        made.retain(|&t| self.m.tv[t as usize][0] != DEAD);
        made.sort_unstable();
        made.dedup();
        made
    }

    /// Flips face `f` of `t` when it is not locally Delaunay and a 2-3 or
    /// 3-2 flip (`DomainMesh::flip_face`) makes no flat tetrahedron;
    /// returns the new tetrahedra.
    fn try_flip(&mut self, t: u32, f: usize) -> Option<Vec<u32>> {
        if !self.m.open_face(t, f) {
            return None;
        }
        let w = self.m.nb[t as usize][f];
        let e = self.m.tv[(w >> 2) as usize][(w & 3) as usize];
        if !self.in_sphere(t, &self.pt(e)) {
            return None;
        }
        let mut fl = self.m.flip_face(&self.p, t, f, |new| {
            !new.iter().any(|&n| self.flat(n, None))
        })?;
        if fl.old.len() == 2 {
            // The refinement lists a 2-3 flip's tetrahedra as `[y, x, d, e]`
            // (an even permutation: the same tetrahedra, the same
            // orientation), which its output and later choices follow.
            for n in &mut fl.new {
                *n = [n[1], n[0], n[3], n[2]];
            }
        }
        Some(self.replace(&fl.old, &fl.new))
    }

    /// Replaces the tetrahedra `old` (one region, no subface between them)
    /// by `new` (positive, filling the same polyhedron): the outer faces keep
    /// their neighbours and subface marks.
    fn replace(&mut self, old: &[u32], new: &[[u32; 4]]) -> Vec<u32> {
        let reg = self.m.reg[old[0] as usize];
        let mut ids = Vec::with_capacity(new.len());
        let left = self.m.replace(old, new, reg, &mut ids);
        debug_assert!(left.gone.is_empty() && left.made.is_empty());
        self.m.debug_check(&self.p, "refinement flip");
        ids
    }
}
