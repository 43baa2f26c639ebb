//! The refined input surface: input edges split into chains of subsegments,
//! Steiner points and the input triangles they lie on, and the exact test of
//! whether an input triangle is a union of mesh faces.
//!
//! Edges are filed under their smaller endpoint (counting sort, insertion
//! sort per bucket), the triangles of each edge are one flat array, and an
//! edge's chain stays inline until a Steiner point splits it. `TripleIndex`
//! files face keys by their least vertex for lookups over every face of a
//! mesh (no hashing).

use crate::geom::ids::{IdMap, IdSet};

use crate::geom::vec3::{cross, dot, sub};
use crate::tet::local::FACET;
use crate::tet::local::{ekey, fkey};

/// Where a vertex lies on the input surface.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Kind {
    /// An input point (or a point not on the surface).
    Input,
    /// A Steiner point on input edge `e`.
    OnEdge(u32),
    /// A Steiner point inside input triangle `t`.
    OnTri(u32),
}

/// Lists of ids stored back to back: list `i` is
/// `items[start[i]..start[i + 1]]` (indexing gives a slice).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub(crate) struct Lists {
    start: Vec<u32>,
    items: Vec<u32>,
}

impl Lists {
    /// The number of lists.
    #[cfg(test)]
    pub(crate) fn len(&self) -> usize {
        self.start.len().saturating_sub(1)
    }
}

impl std::ops::Index<usize> for Lists {
    type Output = [u32];
    #[inline]
    fn index(&self, i: usize) -> &[u32] {
        &self.items[self.start[i] as usize..self.start[i + 1] as usize]
    }
}

/// The vertices of an input edge in order: its two ends until a Steiner
/// point splits it (no allocation for the many edges never split), then a
/// vector. Reads as a slice.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Chain {
    /// An unsplit edge.
    Two([u32; 2]),
    /// A split edge: ends and Steiner points in order.
    Many(Vec<u32>),
}

impl Chain {
    /// Empties the chain (an edge that is no longer a segment).
    pub(crate) fn clear(&mut self) {
        *self = Chain::Many(Vec::new());
    }

    /// Inserts `id` at position `i` (as [`Vec::insert`]).
    pub(crate) fn insert(&mut self, i: usize, id: u32) {
        if let Chain::Two(ab) = *self {
            *self = Chain::Many(ab.to_vec());
        }
        if let Chain::Many(v) = self {
            v.insert(i, id);
        }
    }
}

impl std::ops::Deref for Chain {
    type Target = [u32];
    #[inline]
    fn deref(&self) -> &[u32] {
        match self {
            Chain::Two(ab) => ab,
            Chain::Many(v) => v,
        }
    }
}

/// A map from sorted vertex triples to values, grouped by the triple's
/// least vertex (compressed rows): a lookup scans the few triples of one
/// vertex, with no hashing — cheaper than a hash map for the passes over
/// every face of a tetrahedralization, where most lookups miss.
#[derive(Debug, Clone, Default)]
pub(crate) struct TripleIndex {
    /// Per least vertex `a`: its entries are `rest[start[a]..start[a + 1]]`.
    start: Vec<u32>,
    /// `(b, c, value)` of each triple `[a, b, c]`, by `a`, then in the
    /// order given.
    rest: Vec<(u32, u32, u32)>,
}

impl TripleIndex {
    /// The index of `items` (sorted triples with values; vertices below
    /// `n`, others are left out), keeping their order within each key.
    pub(crate) fn new(n: usize, items: impl Iterator<Item = ([u32; 3], u32)> + Clone) -> Self {
        let mut start = vec![0u32; n + 1];
        for (k, _) in items.clone() {
            if k.iter().all(|&w| (w as usize) < n) {
                start[k[0] as usize + 1] += 1;
            }
        }
        for i in 0..n {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut rest = vec![(0, 0, 0); start[n] as usize];
        for (k, x) in items {
            if k.iter().all(|&w| (w as usize) < n) {
                let at = &mut fill[k[0] as usize];
                rest[*at as usize] = (k[1], k[2], x);
                *at += 1;
            }
        }
        TripleIndex { start, rest }
    }

    /// The values of sorted triple `k`, in the order given to
    /// [`TripleIndex::new`].
    #[inline]
    pub(crate) fn get(&self, k: &[u32; 3]) -> impl Iterator<Item = u32> + '_ {
        let a = k[0] as usize;
        let row = match (self.start.get(a), self.start.get(a + 1)) {
            (Some(&lo), Some(&hi)) => &self.rest[lo as usize..hi as usize],
            _ => &[][..],
        };
        let (b, c) = (k[1], k[2]);
        row.iter()
            .filter(move |e| e.0 == b && e.1 == c)
            .map(|e| e.2)
    }
}

/// The refined surface.
#[derive(Debug, Clone)]
pub(crate) struct Surface {
    /// Input triangles.
    pub(crate) tris: Vec<[u32; 3]>,
    /// Input edges, `[a, b]` with `a < b`, sorted.
    pub(crate) edges: Vec<[u32; 2]>,
    /// Per input edge: its vertices from `edges[e][0]` to `edges[e][1]`.
    pub(crate) chains: Vec<Chain>,
    /// Per input triangle: the indices of its edges `(t0,t1), (t1,t2), (t2,t0)`.
    pub(crate) tri_edges: Vec<[u32; 3]>,
    /// Per input edge: the triangles that use it (one flat array, no
    /// allocation per edge).
    pub(crate) edge_tris: Lists,
    /// Per vertex: the input triangles it lies on (sorted).
    pub(crate) vtris: Vec<Vec<u32>>,
    /// Per vertex: its kind.
    pub(crate) kind: Vec<Kind>,
    /// Input triangle by sorted vertex triple (the first such triangle).
    tri_index: TripleIndex,
    /// Per input triangle: how many Steiner points lie inside it.
    inner: Vec<u32>,
    /// Whether [`Surface::coverage_local`] keeps one side of *every*
    /// tetrahedron with its four vertices on a triangle, also of one with
    /// three points of one edge chain (`-p` without `-q`, see there).
    pub(crate) every_sliver_one_side: bool,
}

impl Surface {
    pub(crate) fn new(n: usize, tris: &[[u32; 3]]) -> Surface {
        // Edge ids in (min, max) order without a global sort or a map: each
        // side `3 t + k` is filed under its smaller endpoint (counting sort),
        // each small bucket is sorted by (larger endpoint, side), and equal
        // runs are one edge. Sides of one edge stay in triangle order.
        let nv = tris
            .iter()
            .flatten()
            .map(|&v| v as usize + 1)
            .max()
            .unwrap_or(0)
            .max(n);
        let side = |s: usize| {
            let t = &tris[s / 3];
            let k = s % 3;
            ekey(t[k], t[(k + 1) % 3])
        };
        let mut start = vec![0u32; nv + 1];
        for s in 0..3 * tris.len() {
            start[side(s).0 as usize + 1] += 1;
        }
        for v in 0..nv {
            start[v + 1] += start[v];
        }
        let mut fill = start.clone();
        // (larger endpoint << 32 | side) per side, bucketed by smaller one.
        let mut items = vec![0u64; 3 * tris.len()];
        for s in 0..3 * tris.len() {
            let (lo, hi) = side(s);
            items[fill[lo as usize] as usize] = (u64::from(hi) << 32) | s as u64;
            fill[lo as usize] += 1;
        }
        drop(fill);
        let mut keys: Vec<(u32, u32)> = Vec::with_capacity(3 * tris.len() / 2 + 1);
        let mut edge_tris = Lists {
            start: Vec::with_capacity(3 * tris.len() / 2 + 2),
            items: Vec::with_capacity(3 * tris.len()),
        };
        edge_tris.start.push(0);
        let mut tri_edges = vec![[0u32; 3]; tris.len()];
        for v in 0..nv {
            let bucket = &mut items[start[v] as usize..start[v + 1] as usize];
            crate::tet::intersect::sort_bucket(bucket);
            let mut i = 0;
            while i < bucket.len() {
                let hi = (bucket[i] >> 32) as u32;
                let mut j = i + 1;
                while j < bucket.len() && (bucket[j] >> 32) as u32 == hi {
                    j += 1;
                }
                let e = keys.len() as u32;
                keys.push((v as u32, hi));
                for &x in &bucket[i..j] {
                    let s = (x & 0xFFFF_FFFF) as usize;
                    tri_edges[s / 3][s % 3] = e;
                    edge_tris.items.push((s / 3) as u32);
                }
                edge_tris.start.push(edge_tris.items.len() as u32);
                i = j;
            }
        }
        drop(items);
        // Triangles per vertex, in index order (sized by a count first).
        let mut count = vec![0u32; n];
        for t in tris {
            for &w in t {
                count[w as usize] += 1;
            }
        }
        let mut vtris: Vec<Vec<u32>> = count
            .iter()
            .map(|&c| Vec::with_capacity(c as usize))
            .collect();
        drop(count);
        for (ti, t) in tris.iter().enumerate() {
            for &w in t {
                vtris[w as usize].push(ti as u32);
            }
        }
        for l in &mut vtris {
            l.dedup();
        }
        let tri_index = TripleIndex::new(
            n,
            tris.iter().enumerate().map(|(ti, t)| (fkey(*t), ti as u32)),
        );
        Surface {
            tri_index,
            inner: vec![0; tris.len()],
            every_sliver_one_side: false,
            tris: tris.to_vec(),
            edges: keys.iter().map(|&(a, b)| [a, b]).collect(),
            chains: keys.iter().map(|&(a, b)| Chain::Two([a, b])).collect(),
            tri_edges,
            edge_tris,
            vtris,
            kind: vec![Kind::Input; n],
        }
    }

    /// Records Steiner vertex `id` on edge `e` between chain positions `i`
    /// and `i + 1`.
    pub(crate) fn add_on_edge(&mut self, id: u32, e: u32, i: usize) {
        self.grow(id);
        self.chains[e as usize].insert(i + 1, id);
        self.kind[id as usize] = Kind::OnEdge(e);
        self.vtris[id as usize] = self.edge_tris[e as usize].to_vec();
    }

    /// Records Steiner vertex `id` inside triangle `t`.
    pub(crate) fn add_on_tri(&mut self, id: u32, t: u32) {
        self.grow(id);
        self.kind[id as usize] = Kind::OnTri(t);
        self.vtris[id as usize] = vec![t];
        self.inner[t as usize] += 1;
    }

    /// True when no Steiner point lies on input triangle `t` (its sides
    /// are unsplit and nothing was inserted inside it): then the only mesh
    /// face that can lie on `t` is its own three corners.
    #[inline]
    pub(crate) fn plain(&self, t: usize) -> bool {
        self.inner[t] == 0
            && self.tri_edges[t]
                .iter()
                .all(|&e| self.chains[e as usize].len() == 2)
    }

    /// The input triangles whose three corners are the vertices of the
    /// sorted triple `k` (usually none or one), in index order.
    pub(crate) fn triangles_with_key(&self, k: &[u32; 3]) -> impl Iterator<Item = u32> + '_ {
        self.tri_index.get(k)
    }

    fn grow(&mut self, id: u32) {
        let n = id as usize + 1;
        if self.kind.len() < n {
            self.kind.resize(n, Kind::Input);
            self.vtris.resize(n, Vec::new());
        }
    }

    /// Bit `k` set when vertex `w` lies on local edge `k` of triangle `t`.
    fn edge_mask(&self, w: u32, t: usize) -> u8 {
        let tv = self.tris[t];
        match self.kind[w as usize] {
            Kind::Input => {
                let mut m = 0;
                for k in 0..3 {
                    if tv[k] == w || tv[(k + 1) % 3] == w {
                        m |= 1 << k;
                    }
                }
                m
            }
            Kind::OnEdge(e) => {
                let mut m = 0;
                for k in 0..3 {
                    if self.tri_edges[t][k] == e {
                        m |= 1 << k;
                    }
                }
                m
            }
            Kind::OnTri(_) => 0,
        }
    }

    /// The input triangles a mesh face lies on (by vertex membership), the
    /// face not being three points of one edge chain, listing in `flat`
    /// the input triangles on which the face is three points of one edge
    /// chain.
    pub(crate) fn face_triangles_split(
        &self,
        f: [u32; 3],
        out: &mut Vec<u32>,
        flat: &mut Vec<u32>,
    ) {
        out.clear();
        flat.clear();
        let get = |w: u32| self.vtris.get(w as usize).map_or(&[][..], |l| &l[..]);
        let (a, b, c) = (get(f[0]), get(f[1]), get(f[2]));
        for &t in a {
            if b.binary_search(&t).is_ok() && c.binary_search(&t).is_ok() {
                if !self.on_one_edge(f, t as usize) {
                    out.push(t);
                } else {
                    flat.push(t);
                }
            }
        }
    }

    /// Whether the three points `f`, all on input triangle `t`, lie on one
    /// of its edges (symbolically collinear: the input edge's ends and its
    /// Steiner points, whatever their rounded coordinates).
    pub(crate) fn on_one_edge(&self, f: [u32; 3], t: usize) -> bool {
        self.edge_mask(f[0], t) & self.edge_mask(f[1], t) & self.edge_mask(f[2], t) != 0
    }

    /// The subsegments on the boundary of triangle `t`.
    pub(crate) fn boundary(&self, t: usize) -> impl Iterator<Item = (u32, u32)> + '_ {
        self.tri_edges[t]
            .iter()
            .flat_map(move |&e| self.chains[e as usize].windows(2).map(|w| ekey(w[0], w[1])))
    }

    /// The mesh faces lying on input triangle `t` (sorted), and whether
    /// they cover it exactly: the faces' edges used once are exactly the
    /// subsegments of its boundary, every other edge is used twice. (Faces
    /// of a valid tetrahedralization never overlap, so a set of them inside
    /// the triangle whose mod-2 boundary is the triangle's boundary covers
    /// it exactly once.) `tets`: the distinct finite tetrahedra having a
    /// vertex on `t` (every face with its three vertices on `t` is a face
    /// of one of them), so the cost is that of `t`'s neighbourhood only.
    ///
    /// A tetrahedron whose four vertices all lie on `t` (a sliver made by
    /// Steiner points that are not exactly on it) has all its faces "on"
    /// the triangle (but a thin face of three points of one edge chain);
    /// only its faces whose outward normal points to the triangle's
    /// positive side are kept, so the sliver joins the region below the
    /// triangle. With [`Surface::every_sliver_one_side`] (`-p` without
    /// `-q`) this holds for every such tetrahedron; otherwise only for one
    /// whose faces `0 1 2` and `0 1 3` are not three points of one edge
    /// chain. A sliver of a corner of `t` and three points of one side's
    /// chain then has both its sides counted, the corner's subsegment used
    /// twice, and `t` stays uncovered: the splits go on until the sliver is
    /// gone (on thin nearly coplanar strips of turned CAD parts, up to 150
    /// rounds of one point each), which `-q` wants (the sliver, kept, is a
    /// boundary tetrahedron of no volume that refinement cannot remove), and
    /// `-p` alone does not.
    pub(crate) fn coverage_local(
        &self,
        t: usize,
        tets: &[[u32; 4]],
        pts: &[[f64; 3]],
    ) -> (Vec<[u32; 3]>, bool) {
        let tt = t as u32;
        let on_t = |w: u32| self.on_triangle(w, t);
        let mut on = Vec::new();
        let mut flat = Vec::new();
        let mut buf = Vec::new();
        let mut flat_buf = Vec::new();
        for tv in tets {
            for f in 0..4 {
                let k = fkey([tv[(f + 1) % 4], tv[(f + 2) % 4], tv[(f + 3) % 4]]);
                if !k.iter().all(|&w| on_t(w)) {
                    continue;
                }
                self.face_triangles_split(k, &mut buf, &mut flat_buf);
                if buf.contains(&tt) {
                    on.push(k);
                } else if flat_buf.contains(&tt) {
                    flat.push(k);
                }
            }
        }
        on.sort_unstable();
        on.dedup();
        flat.sort_unstable();
        flat.dedup();
        let mut drop: Vec<[u32; 3]> = Vec::new();
        for tv in tets {
            if !tv.iter().all(|&w| on_t(w)) {
                continue;
            }
            if !self.every_sliver_one_side {
                self.face_triangles_split([tv[0], tv[1], tv[2]], &mut buf, &mut flat_buf);
                if !buf.contains(&tt) {
                    continue;
                }
                self.face_triangles_split([tv[0], tv[1], tv[3]], &mut buf, &mut flat_buf);
                if !buf.contains(&tt) {
                    continue;
                }
            }
            let [a, b, c] = self.tris[t].map(|w| pts[w as usize]);
            let nt = cross(&sub(&b, &a), &sub(&c, &a));
            for fv in FACET {
                let [x, y, z] = fv.map(|i| pts[tv[i] as usize]);
                let n = cross(&sub(&z, &x), &sub(&y, &x));
                if dot(&n, &nt) <= 0.0 {
                    drop.push(fkey(fv.map(|i| tv[i])));
                }
            }
        }
        on.retain(|f| !drop.contains(f));
        // Chords: with inexact Steiner points on an edge, a mesh edge
        // joining two vertices of its chain can coexist with the
        // subsegments between them, the thin face of three chain points
        // closing the gap. Such a face joins the triangle whose faces use
        // the chord, until no more apply (a closure, so the order does not
        // matter).
        let mut changed = true;
        while changed && !flat.is_empty() {
            changed = false;
            let mut rest = Vec::new();
            for f in flat {
                let bnd = |e: (u32, u32)| self.boundary(t).any(|b| b == e);
                let uses = |e: (u32, u32)| {
                    on.iter()
                        .any(|g| (0..3).any(|k| ekey(g[k], g[(k + 1) % 3]) == e))
                };
                let chord = (0..3)
                    .map(|k| ekey(f[k], f[(k + 1) % 3]))
                    .any(|e| !bnd(e) && uses(e));
                if chord {
                    on.push(f);
                    changed = true;
                } else {
                    rest.push(f);
                }
            }
            flat = rest;
        }
        let covered = self.covers(t, &on);
        (on, covered)
    }

    /// The edges around the uncovered part of triangle `t`: boundary
    /// subsegments no face on `t` uses, and other edges used by one face
    /// only. Sorted.
    pub(crate) fn hole_edges(&self, t: usize, faces: &[[u32; 3]]) -> Vec<(u32, u32)> {
        let mut count: IdMap<(u32, u32), u32> = IdMap::default();
        for f in faces {
            for k in 0..3 {
                *count.entry(ekey(f[k], f[(k + 1) % 3])).or_insert(0) += 1;
            }
        }
        let bnd: IdSet<(u32, u32)> = self.boundary(t).collect();
        let mut out: Vec<(u32, u32)> = bnd
            .iter()
            .filter(|e| !count.contains_key(e))
            .copied()
            .collect();
        out.extend(
            count
                .iter()
                .filter(|(e, &c)| c == 1 && !bnd.contains(e))
                .map(|(&e, _)| e),
        );
        out.sort_unstable();
        out
    }

    fn covers(&self, t: usize, faces: &[[u32; 3]]) -> bool {
        if faces.is_empty() {
            return false;
        }
        let mut count: IdMap<(u32, u32), u32> = IdMap::default();
        for f in faces {
            for k in 0..3 {
                *count.entry(ekey(f[k], f[(k + 1) % 3])).or_insert(0) += 1;
            }
        }
        let bnd: IdSet<(u32, u32)> = self.boundary(t).collect();
        for b in &bnd {
            if count.get(b) != Some(&1) {
                return false;
            }
        }
        count
            .iter()
            .all(|(e, &c)| if bnd.contains(e) { c == 1 } else { c == 2 })
    }

    /// Vertices lying on triangle `t`: corners, edge Steiner points, inner
    /// Steiner points.
    pub(crate) fn on_triangle(&self, w: u32, t: usize) -> bool {
        self.vtris
            .get(w as usize)
            .is_some_and(|l| l.binary_search(&(t as u32)).is_ok())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Edges, their triangles and the triangles per vertex by a global sort
    /// and a map (the construction `Surface::new` replaced).
    #[allow(clippy::type_complexity)]
    fn reference(
        n: usize,
        tris: &[[u32; 3]],
    ) -> (Vec<[u32; 2]>, Vec<[u32; 3]>, Vec<Vec<u32>>, Vec<Vec<u32>>) {
        let mut keys: Vec<(u32, u32)> = tris
            .iter()
            .flat_map(|t| (0..3).map(move |k| ekey(t[k], t[(k + 1) % 3])))
            .collect();
        keys.sort_unstable();
        keys.dedup();
        let index: std::collections::HashMap<(u32, u32), u32> = keys
            .iter()
            .enumerate()
            .map(|(i, &k)| (k, i as u32))
            .collect();
        let mut edge_tris = vec![Vec::new(); keys.len()];
        let mut tri_edges = Vec::new();
        let mut vtris = vec![Vec::new(); n];
        for (ti, t) in tris.iter().enumerate() {
            let mut te = [0u32; 3];
            for k in 0..3 {
                let e = index[&ekey(t[k], t[(k + 1) % 3])];
                te[k] = e;
                edge_tris[e as usize].push(ti as u32);
                vtris[t[k] as usize].push(ti as u32);
            }
            tri_edges.push(te);
        }
        for l in &mut vtris {
            l.sort_unstable();
            l.dedup();
        }
        let edges = keys.iter().map(|&(a, b)| [a, b]).collect();
        (edges, tri_edges, edge_tris, vtris)
    }

    #[test]
    fn bucketed_edges_match_sorted_edges() {
        let mut s = 0x9e37_79b9_7f4a_7c15u64;
        let mut r = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s
        };
        for round in 0..30 {
            let n = 5 + round;
            // Random triangles (repeated edges, repeated triangles, unused
            // vertices) over n points.
            let tris: Vec<[u32; 3]> = (0..2 * n)
                .map(|_| [0, 1, 2].map(|_| (r() % n as u64) as u32))
                .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
                .collect();
            let surf = Surface::new(n, &tris);
            let (edges, tri_edges, edge_tris, vtris) = reference(n, &tris);
            assert_eq!(surf.edges, edges);
            assert_eq!(surf.tri_edges, tri_edges);
            assert_eq!(surf.edge_tris.len(), edge_tris.len());
            for (e, l) in edge_tris.iter().enumerate() {
                assert_eq!(&surf.edge_tris[e], &l[..]);
            }
            assert_eq!(surf.vtris, vtris);
            assert_eq!(surf.chains.len(), edges.len());
            for (c, e) in surf.chains.iter().zip(&edges) {
                assert_eq!(&c[..], &e[..]);
            }
        }
    }
}
