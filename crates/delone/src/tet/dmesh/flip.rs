//! The 2-3 and 3-2 flips of the [`DomainMesh`]: which faces and edges may
//! be flipped and which tetrahedra result. Refinement
//! ([`crate::tet::refine`], Delaunay flips: the criterion is `insphere`)
//! and optimisation ([`crate::tet::optimize`], quality flips) both take
//! their flips from here and judge them with their own criterion; the
//! flip is then applied by [`DomainMesh::replace`].
//!
//! A flip never destroys a subface or crosses a region change: every face
//! it removes is *open* ([`DomainMesh::open_face`]).

use delone_predicates::orient3d;

use super::{ring, DomainMesh};
use crate::tet::local::face;
use crate::NONE;

/// A flip: the slots it removes and the tetrahedra that replace them.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Flip {
    /// Slots removed (connected, one region).
    pub old: Vec<u32>,
    /// The new tetrahedra, oriented as the mesh when the flip is valid.
    pub new: Vec<[u32; 4]>,
}

/// Exact: is `tv` strictly positive on points `p` (the mesh's orientation,
/// `orient3d` negative)?
#[inline]
pub(crate) fn positive(p: &[[f64; 3]], tv: [u32; 4]) -> bool {
    let g = |i: usize| &p[tv[i] as usize];
    orient3d(g(0), g(1), g(2), g(3)) < 0.0
}

impl DomainMesh {
    /// May face `f` of `t` be destroyed: it has a tetrahedron behind it,
    /// is not a subface, and both sides are in one region (always, in a
    /// mesh without regions)?
    #[inline]
    pub(crate) fn open_face(&self, t: u32, f: usize) -> bool {
        let n = self.across(t, f);
        n != NONE && !self.is_sub(t, f) && self.reg.get(n as usize) == self.reg.get(t as usize)
    }

    /// The 2-3 flip of open face `f` of `t`: `t` and the slot `u` behind
    /// it become the three tetrahedra `[x, y, e, d]` around the new edge
    /// between the apexes `d` (of `t`) and `e` (of `u`), `x y` running over
    /// the face's edges. They are positive exactly when segment `d e`
    /// crosses the face's interior (not checked here). `None` when the face
    /// is not open.
    pub(crate) fn flip23(&self, t: u32, f: usize) -> Option<Flip> {
        let (u, new) = self.flip23_tets(t, f)?;
        Some(Flip {
            old: vec![t, u],
            new: new.to_vec(),
        })
    }

    /// [`DomainMesh::flip23`] without allocating: the slot `u` behind the
    /// face (the flip removes `t` and `u`) and the three new tetrahedra.
    pub(crate) fn flip23_tets(&self, t: u32, f: usize) -> Option<(u32, [[u32; 4]; 3])> {
        if !self.open_face(t, f) {
            return None;
        }
        let w = self.nb[t as usize][f];
        let (u, g) = (w >> 2, (w & 3) as usize);
        let tv = self.tv[t as usize];
        let d = tv[f];
        // The vertex of `u` off the shared face: the one opposite its side
        // of the face (the first of `u` not in `t`).
        let uv = self.tv[u as usize];
        let e = if tv.contains(&uv[g]) {
            *uv.iter().find(|w| !tv.contains(w))?
        } else {
            uv[g]
        };
        let [x, y, z] = face(tv, f);
        Some((u, [[x, y, e, d], [y, z, e, d], [z, x, e, d]]))
    }

    /// The 3-2 flip of edge `a b` of open face `f` of `t` (`c` the face's
    /// third vertex, `d` the apex of `t`, `e` the apex across the face):
    /// the three slots around the edge (`t`, `u` across the face, `v`
    /// across face `a b d`; every face through the edge open) become
    /// `{d, e, c, a}` and `{d, e, c, b}`. Those are `t` with `b`, resp. `a`,
    /// replaced by `e`, so they have its orientation whenever the flip is
    /// valid (edge `a b` crosses triangle `c d e`; not checked here).
    /// `None` when the edge has not exactly these three tetrahedra around
    /// it.
    pub(crate) fn flip32(&self, t: u32, f: usize, (a, b): (u32, u32)) -> Option<Flip> {
        let tv = self.tv[t as usize];
        let (d, u) = (tv[f], self.across(t, f));
        let e = *self.tv[u as usize].iter().find(|w| !tv.contains(w))?;
        let c = *tv.iter().find(|&&q| q != a && q != b && q != d)?;
        let ic = tv.iter().position(|&q| q == c)?;
        if !self.open_face(t, ic) {
            return None;
        }
        let v = self.across(t, ic);
        let vv = self.tv[v as usize];
        let id = vv.iter().position(|&q| q == d)?;
        if !vv.contains(&e) || !self.open_face(v, id) || self.across(v, id) != u {
            return None;
        }
        let like = |gone: u32, mut n: [u32; 4]| {
            if !ring::even(tv.map(|q| if q == gone { e } else { q }), n) {
                n.swap(0, 1);
            }
            n
        };
        Some(Flip {
            old: vec![t, u, v],
            new: vec![like(b, [d, e, c, a]), like(a, [d, e, c, b])],
        })
    }

    /// The flip of open face `f` of `t` on points `p` that criterion
    /// `accept` takes: the 2-3 flip when its tetrahedra are strictly
    /// positive, else the first 3-2 flip through an edge of the face whose
    /// two tetrahedra are. When `accept` refuses the 2-3 tetrahedra, the
    /// face is left.
    pub(crate) fn flip_face(
        &self,
        p: &[[f64; 3]],
        t: u32,
        f: usize,
        accept: impl Fn(&[[u32; 4]]) -> bool,
    ) -> Option<Flip> {
        let fl = self.flip23(t, f)?;
        if !accept(&fl.new) {
            return None;
        }
        let ok = |fl: &Flip| fl.new.iter().all(|&n| positive(p, n));
        if ok(&fl) {
            return Some(fl);
        }
        let [x, y, z] = face(self.tv[t as usize], f);
        [(x, y), (y, z), (z, x)]
            .into_iter()
            .filter_map(|ab| self.flip32(t, f, ab))
            .find(|fl| ok(fl) && accept(&fl.new))
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::{neighbors_by_faces, three_around_an_edge};
    use super::*;

    /// The three tetrahedra around the edge 3 4 of
    /// [`three_around_an_edge`], made positive; the hull faces are subfaces.
    fn around() -> (Vec<[f64; 3]>, DomainMesh) {
        let p = three_around_an_edge().to_vec();
        let tets: Vec<[u32; 4]> = [[0, 1, 3, 4], [1, 2, 3, 4], [2, 0, 3, 4]]
            .into_iter()
            .map(|mut tv| {
                if !positive(&p, tv) {
                    tv.swap(0, 1);
                }
                tv
            })
            .collect();
        let nbs = neighbors_by_faces(&tets);
        let mut m = DomainMesh::from_neighbors(&tets, &nbs, &[0, 0, 0], p.len()).unwrap();
        for t in 0..3 {
            for f in 0..4 {
                if m.nb[t as usize][f] == NONE {
                    m.mark_face(t, f);
                }
            }
        }
        m.check(&p).unwrap();
        (p, m)
    }

    #[test]
    fn three_two_then_two_three() {
        let (p, mut m) = around();
        // Face 1 3 4 of slot 0 (opposite 0) is open, but segment 0 2 misses
        // it (its 2-3 flip would invert a tetrahedron): the 3-2 flip
        // through its edge 3 4 is chosen.
        let f = m.tv[0].iter().position(|&q| q == 0).unwrap();
        assert!(m.open_face(0, f));
        let fl = m.flip_face(&p, 0, f, |_| true).unwrap();
        assert_eq!(fl.old.len(), 3);
        assert_eq!(fl.new.len(), 2);
        let mut ids = Vec::new();
        m.replace(&fl.old, &fl.new, 0, &mut ids);
        m.check(&p).unwrap();
        // Back: the face 0 1 2 between the two is open and flips 2-3.
        let t = ids[0];
        let f = m.tv[t as usize]
            .iter()
            .position(|&q| q == 3 || q == 4)
            .unwrap();
        assert!(m.flip32(t, f, (0, 1)).is_none());
        let fl = m.flip23(t, f).unwrap();
        assert!(fl.new.iter().all(|&n| positive(&p, n)));
        m.replace(&fl.old, &fl.new, 0, &mut ids);
        m.check(&p).unwrap();
        assert_eq!(m.live_slots().count(), 3);
        // An open face: a criterion that refuses everything flips nothing,
        // and once the face is a subface, no flip is offered.
        let t = ids[0];
        let f = (0..4).find(|&f| m.open_face(t, f)).unwrap();
        assert!(m.flip_face(&p, t, f, |_| true).is_some());
        assert!(m.flip_face(&p, t, f, |_| false).is_none());
        m.mark_face(t, f);
        assert!(m.flip23(t, f).is_none());
        assert!(m.flip_face(&p, t, f, |_| true).is_none());
    }
}
