//! The local operations of metric adaptation on the constrained triangle
//! mesh ([`CMesh`]): building it from triangles and constrained edges, the
//! star of a vertex, edge split, edge collapse and vertex move. Each
//! operation first checks with the exact `orient2d` that every triangle it
//! would make is counterclockwise and changes nothing otherwise; the swap
//! is [`CMesh::flip`]. A vertex → triangle index (`vt`) is kept up to date
//! by every operation; collapsed triangles become dead slots (`DEAD`), which
//! [`CMesh::check`] skips.
//!
//! Constrained edges are subsegment records ([`Sub`]): `parent` is the
//! input edge (or added boundary edge) it lies on and `t` the parameters of
//! its ends along it, so a point on a constrained edge is always computed
//! from its straight input edge.

use delone_predicates::orient2d;

use super::cmesh::{CMesh, Sub, Tri};
use super::topo::{edge, pack, unpack, DEAD, NEXT, PREV};
use crate::{Error, NONE};

/// A mesh built for adaptation, its vertex → triangle index and the edges
/// constrained beyond the faces ([`CMesh::for_adaptation`]).
pub(crate) type Built = (CMesh, Vec<u32>, Vec<[u32; 2]>);

/// A planned edge collapse ([`CMesh::collapse_plan`]).
pub(crate) struct Collapse {
    /// The vertex removed and the one it merges into.
    pub(crate) v: u32,
    pub(crate) w: u32,
    /// The star of `v` (triangle, position of `v`).
    star: Vec<(usize, usize)>,
    /// The triangles that survive, with `v` replaced by `w`.
    pub(crate) kept: Vec<[u32; 3]>,
}

impl CMesh {
    /// The mesh of counterclockwise `tris` on `points` with `faces`
    /// constrained (each face `k` a subsegment of parent `k`), every hull
    /// edge and every edge between triangles of different `regions` too
    /// (parents from `faces.len()` on, in edge order). Returns the mesh, its
    /// vertex → triangle index and the added edges.
    ///
    /// # Errors
    /// [`Error::InconsistentMesh`] naming the triangle or face: a clockwise
    /// or flat triangle, an edge of more than two triangles or used twice
    /// the same way, a face that is not an edge of the mesh.
    pub(crate) fn for_adaptation(
        points: Vec<[f64; 2]>,
        tris: &[[u32; 3]],
        regions: &[i32],
        faces: &[[u32; 2]],
    ) -> Result<Built, Error> {
        let bad = |reason: String| Err(Error::InconsistentMesh { reason });
        let nv = points.len();
        for (t, v) in tris.iter().enumerate() {
            if v.iter().any(|&x| x as usize >= nv) {
                return bad(format!("triangle {t} has a vertex out of range"));
            }
            if orient2d(
                &points[v[0] as usize],
                &points[v[1] as usize],
                &points[v[2] as usize],
            ) <= 0.0
            {
                return bad(format!("triangle {t} {v:?} is clockwise or flat"));
            }
        }
        // Half-edges sorted by their undirected edge: twins are adjacent.
        let mut half: Vec<(u32, u32, u32)> = (0..tris.len())
            .flat_map(|t| (0..3).map(move |e| (t, e)))
            .map(|(t, e)| {
                let (a, b) = edge(&tris[t], e);
                (a.min(b), a.max(b), pack(t, e))
            })
            .collect();
        half.sort_unstable();
        let mut nb = vec![[NONE; 3]; tris.len()];
        let mut k = 0;
        while k < half.len() {
            let mut j = k + 1;
            while j < half.len() && half[j].0 == half[k].0 && half[j].1 == half[k].1 {
                j += 1;
            }
            let (t, e) = unpack(half[k].2);
            if j - k > 2 {
                return bad(format!(
                    "edge {:?} of triangle {t} has more than two triangles",
                    edge(&tris[t], e)
                ));
            }
            if j - k == 2 {
                let (n, f) = unpack(half[k + 1].2);
                if edge(&tris[t], e) == edge(&tris[n], f) {
                    return bad(format!("triangles {t} and {n} use an edge the same way"));
                }
                nb[t][e] = n as u32;
                nb[n][f] = t as u32;
            }
            k = j;
        }
        let mut m = CMesh::from_triangles(points, tris, &nb);
        let find = |a: u32, b: u32| {
            let key = (a.min(b), a.max(b));
            half.binary_search_by(|h| (h.0, h.1).cmp(&key).then(std::cmp::Ordering::Greater))
                .unwrap_err()
        };
        let mut added = Vec::new();
        let constrain = |m: &mut CMesh, at: usize, parent: u32, a: u32, b: u32| {
            let s = m.subs.len() as u32;
            m.subs.push(Sub {
                v: [a, b],
                he: half[at].2,
                t: [0.0, 1.0],
                parent,
                alive: true,
                stuck: false,
                protected: true,
            });
            for h in &half[at..] {
                if (h.0, h.1) != (a.min(b), a.max(b)) {
                    break;
                }
                let (t, e) = unpack(h.2);
                m.set_sub(t, e, s);
            }
        };
        for (f, &[a, b]) in faces.iter().enumerate() {
            let at = find(a, b);
            if half
                .get(at)
                .is_none_or(|h| (h.0, h.1) != (a.min(b), a.max(b)))
            {
                return bad(format!("face {f} ({a}, {b}) is not an edge of the mesh"));
            }
            let (t, e) = unpack(half[at].2);
            if m.sub_at(t, e) == NONE {
                constrain(&mut m, at, f as u32, a, b);
            }
        }
        for at in 0..half.len() {
            let (t, e) = unpack(half[at].2);
            if m.sub_at(t, e) != NONE
                || at > 0 && (half[at - 1].0, half[at - 1].1) == (half[at].0, half[at].1)
            {
                continue;
            }
            let x = m.tr[t].a[e];
            let region = |t: usize| regions.get(t).copied().unwrap_or(0);
            if x == NONE || region(t) != region(unpack(x).0) {
                let (a, b) = edge(&tris[t], e);
                constrain(&mut m, at, (faces.len() + added.len()) as u32, a, b);
                added.push([a, b]);
            }
        }
        let mut vt = vec![NONE; nv];
        for (t, v) in tris.iter().enumerate() {
            for &x in v {
                vt[x as usize] = t as u32;
            }
        }
        Ok((m, vt, added))
    }

    /// The triangles around vertex `v` (triangle, position of `v`),
    /// counterclockwise; on the boundary from the first triangle after the
    /// boundary. Empty for an unused vertex.
    pub(crate) fn star(&self, vt: &[u32], v: u32) -> Vec<(usize, usize)> {
        let t0 = vt[v as usize];
        if t0 == NONE {
            return Vec::new();
        }
        let t0 = t0 as usize;
        let Some(i0) = self.tr[t0].v.iter().position(|&x| x == v) else {
            return Vec::new();
        };
        // Clockwise to the boundary: across edge `v -> next` (PREV[i]),
        // whose twin ends at `v` (position PREV[j]).
        let (mut t, mut i) = (t0, i0);
        loop {
            let x = self.tr[t].a[PREV[i]];
            if x == NONE {
                break;
            }
            let (n, j) = unpack(x);
            if n == t0 {
                break;
            }
            (t, i) = (n, PREV[j]);
        }
        let mut out = vec![(t, i)];
        let start = t;
        loop {
            // Counterclockwise: across edge `prev -> v` (NEXT[i]), whose
            // twin starts at `v` (position NEXT[j]).
            let x = self.tr[t].a[NEXT[i]];
            if x == NONE {
                break;
            }
            let (n, j) = unpack(x);
            if n == start {
                break;
            }
            (t, i) = (n, NEXT[j]);
            out.push((t, i));
        }
        out
    }

    /// The half-edge `a -> b` (triangle, edge), if `a` and `b` are joined;
    /// or `b -> a` when only that side exists (a boundary edge).
    pub(crate) fn find_edge(&self, vt: &[u32], a: u32, b: u32) -> Option<(usize, usize)> {
        let star = self.star(vt, a);
        for &(t, i) in &star {
            if self.tr[t].v[NEXT[i]] == b {
                return Some((t, PREV[i]));
            }
        }
        for &(t, i) in &star {
            if self.tr[t].v[PREV[i]] == b {
                return Some((t, NEXT[i]));
            }
        }
        None
    }

    /// Writes triangle `t` and points its outer neighbours and subsegments
    /// back at it.
    fn put(&mut self, t: usize, v: [u32; 3], a: [u32; 3], s: [u32; 3], orig: u32) {
        self.tr[t] = Tri {
            v,
            a,
            orig,
            mark: 0,
        };
        for e in 0..3 {
            self.set_sub(t, e, s[e]);
            if a[e] != NONE {
                let (o, l) = unpack(a[e]);
                self.tr[o].a[l] = pack(t, e);
            }
            if let Some(sub) = self.subs.get_mut(s[e] as usize) {
                sub.he = pack(t, e);
            }
        }
    }

    /// Splits edge `e` of triangle `t` at `c` (on a subsegment: at
    /// parameter `tc` of its parent, between those of its ends): two
    /// triangles become four (one becomes two on the boundary), the
    /// subsegment two. `None`, with nothing changed, unless every new
    /// triangle is counterclockwise (exact).
    pub(crate) fn split_edge(
        &mut self,
        vt: &mut Vec<u32>,
        t: usize,
        e: usize,
        c: [f64; 2],
        tc: f64,
    ) -> Option<u32> {
        let tv = self.tr[t].v;
        let (x, a, b) = (tv[e], tv[NEXT[e]], tv[PREV[e]]);
        let ok = |p: &[f64; 2], q: &[f64; 2]| orient2d(p, q, &c) > 0.0;
        if !ok(self.p(x), self.p(a)) || !ok(self.p(b), self.p(x)) {
            return None;
        }
        let across = self.tr[t].a[e];
        let other = (across != NONE).then(|| unpack(across));
        if let Some((n, j)) = other {
            let y = self.tr[n].v[j];
            if !ok(self.p(y), self.p(b)) || !ok(self.p(a), self.p(y)) {
                return None;
            }
        }
        let s = self.sub_at(t, e);
        let p = self.xy.len() as u32;
        self.xy.push(c);
        vt.push(t as u32);
        // The subsegment's half `a -> p` keeps its record; `p -> b` is new.
        let (sa, sb) = if s == NONE {
            (NONE, NONE)
        } else {
            let old = self.subs[s as usize];
            let ta = if old.v[0] == a { old.t[0] } else { old.t[1] };
            let tb = if old.v[0] == a { old.t[1] } else { old.t[0] };
            self.subs[s as usize].v = [a, p];
            self.subs[s as usize].t = [ta, tc];
            self.subs.push(Sub {
                v: [p, b],
                t: [tc, tb],
                ..old
            });
            (s, self.subs.len() as u32 - 1)
        };
        let (ox, ob) = (self.tr[t].a[PREV[e]], self.tr[t].a[NEXT[e]]);
        let (sx, so) = (self.sub_at(t, PREV[e]), self.sub_at(t, NEXT[e]));
        let orig = self.tr[t].orig;
        // The other side, read before anything is written.
        let side = other.map(|(n, j)| {
            let (oy, oa) = (self.tr[n].a[PREV[j]], self.tr[n].a[NEXT[j]]);
            let (sy, sz) = (self.sub_at(n, PREV[j]), self.sub_at(n, NEXT[j]));
            (self.tr[n].v[j], oy, oa, sy, sz, self.tr[n].orig)
        });
        let t2 = self.new_tri();
        let (n, n2) = match other {
            Some((n, _)) => (n, self.new_tri()),
            None => (NONE as usize, NONE as usize),
        };
        let link = |k: usize, f: usize| if k == NONE as usize { NONE } else { pack(k, f) };
        // t = [x, a, p], t2 = [x, p, b]; n = [y, b, p], n2 = [y, p, a].
        self.put(
            t,
            [x, a, p],
            [link(n2, 0), pack(t2, 2), ox],
            [sa, NONE, sx],
            orig,
        );
        self.put(
            t2,
            [x, p, b],
            [link(n, 0), ob, pack(t, 1)],
            [sb, so, NONE],
            orig,
        );
        for k in [a, b, x, p] {
            vt[k as usize] = t as u32;
        }
        vt[b as usize] = t2 as u32;
        if let Some((y, oy, oa, sy, sz, orig)) = side {
            self.put(
                n,
                [y, b, p],
                [pack(t2, 0), pack(n2, 2), oy],
                [sb, NONE, sy],
                orig,
            );
            self.put(
                n2,
                [y, p, a],
                [pack(t, 0), oa, pack(n, 1)],
                [sa, sz, NONE],
                orig,
            );
            vt[y as usize] = n as u32;
        }
        Some(p)
    }

    /// Plans collapsing vertex `v` into its neighbour `w` along their edge:
    /// `None` when the edge does not exist, when a constrained edge other
    /// than `vw` ends at `v` on a triangle of `vw` or two constrained edges
    /// would merge, when the link condition fails (the two vertices share
    /// a neighbour not opposite `vw`), or when a surviving triangle would
    /// not be counterclockwise (exact). Subsegment rules (which `v` may go)
    /// are the caller's.
    pub(crate) fn collapse_plan(&self, vt: &[u32], v: u32, w: u32) -> Option<Collapse> {
        let star = self.star(vt, v);
        let mut opposite = Vec::new();
        let mut kept = Vec::new();
        let mut link_v = Vec::new();
        for &(t, i) in &star {
            let tv = self.tr[t].v;
            link_v.extend([tv[NEXT[i]], tv[PREV[i]]]);
            if let Some(iw) = tv.iter().position(|&x| x == w) {
                let ix = 3 - i - iw;
                // Edge opposite w (x - v) and opposite v (w - x).
                if self.sub_at(t, iw) != NONE || self.tr[t].a[iw] == NONE {
                    return None;
                }
                opposite.push(tv[ix]);
            } else {
                let mut nv = tv;
                nv[i] = w;
                if orient2d(self.p(nv[0]), self.p(nv[1]), self.p(nv[2])) <= 0.0 {
                    return None;
                }
                kept.push(nv);
            }
        }
        if opposite.is_empty() {
            return None;
        }
        link_v.sort_unstable();
        link_v.dedup();
        let mut link_w: Vec<u32> = self
            .star(vt, w)
            .iter()
            .flat_map(|&(t, i)| [self.tr[t].v[NEXT[i]], self.tr[t].v[PREV[i]]])
            .collect();
        link_w.sort_unstable();
        link_w.dedup();
        let common = link_v
            .iter()
            .filter(|x| link_w.binary_search(x).is_ok())
            .count();
        if common != opposite.len() {
            return None;
        }
        Some(Collapse { v, w, star, kept })
    }

    /// Commits a [`CMesh::collapse_plan`]: the triangles of `vw` die, the
    /// two edges beside `v` in each are glued into one (keeping the
    /// subsegment of the one beside `w`), `v` becomes `w` in the others, the
    /// subsegment `vw` (if any) dies and the other one at `v` ends at `w`.
    pub(crate) fn collapse(&mut self, vt: &mut [u32], plan: &Collapse) {
        let (v, w) = (plan.v, plan.w);
        let at_v = self.subs_at(&plan.star);
        let mut vw_sub = NONE;
        for &(t, i) in &plan.star {
            let tv = self.tr[t].v;
            let Some(iw) = tv.iter().position(|&x| x == w) else {
                continue;
            };
            let ix = 3 - i - iw;
            if self.sub_at(t, ix) != NONE {
                vw_sub = self.sub_at(t, ix);
            }
            let (xa, xb, sb) = (self.tr[t].a[iw], self.tr[t].a[i], self.sub_at(t, i));
            let (na, ja) = unpack(xa);
            self.tr[na].a[ja] = xb;
            self.set_sub(na, ja, sb);
            if xb != NONE {
                let (nb, jb) = unpack(xb);
                self.tr[nb].a[jb] = xa;
            }
            if let Some(sub) = self.subs.get_mut(sb as usize) {
                sub.he = xa;
            }
            for &x in &tv {
                if x != v {
                    vt[x as usize] = na as u32;
                }
            }
            self.tr[t].v = [DEAD; 3];
            self.tr[t].a = [NONE; 3];
            self.tr[t].mark = 0;
        }
        let mut tw = None;
        for &(t, i) in &plan.star {
            if self.tr[t].v[0] != DEAD {
                self.tr[t].v[i] = w;
                tw = Some(t as u32);
            }
        }
        if let Some(t) = tw {
            vt[w as usize] = t;
        }
        vt[v as usize] = NONE;
        if vw_sub != NONE {
            let gone = self.subs[vw_sub as usize];
            let tw_param = if gone.v[0] == w { gone.t[0] } else { gone.t[1] };
            self.subs[vw_sub as usize].alive = false;
            self.subs[vw_sub as usize].he = NONE;
            for &s in &at_v {
                let s = &mut self.subs[s as usize];
                for k in 0..2 {
                    if s.alive && s.v[k] == v {
                        s.v[k] = w;
                        s.t[k] = tw_param;
                    }
                }
            }
        }
    }

    /// Whether moving vertex `v` to `c` keeps every triangle of its star
    /// counterclockwise (exact).
    pub(crate) fn can_move(&self, star: &[(usize, usize)], c: &[f64; 2]) -> bool {
        star.iter().all(|&(t, i)| {
            let tv = self.tr[t].v;
            orient2d(c, self.p(tv[NEXT[i]]), self.p(tv[PREV[i]])) > 0.0
        })
    }

    /// The subsegments at vertex `v` (at most the first three found).
    pub(crate) fn subs_at(&self, star: &[(usize, usize)]) -> Vec<u32> {
        let mut out = Vec::new();
        for &(t, i) in star {
            for e in [NEXT[i], PREV[i]] {
                let s = self.sub_at(t, e);
                if s != NONE && !out.contains(&s) {
                    out.push(s);
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The adaptation mesh of the Delaunay triangulation of `pts`.
    fn mesh_of(pts: &[[f64; 2]]) -> (CMesh, Vec<u32>) {
        let d = crate::tri::triangulate(pts).unwrap();
        let (m, vt, added) = CMesh::for_adaptation(pts.to_vec(), &d.triangles, &[], &[]).unwrap();
        assert!(!added.is_empty(), "the hull edges are constrained");
        m.check(false).unwrap();
        (m, vt)
    }

    fn area(m: &CMesh) -> f64 {
        m.tr.iter()
            .filter(|t| t.v[0] != DEAD)
            .map(|t| {
                let [a, b, c] = t.v.map(|v| *m.p(v));
                0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
            })
            .sum()
    }

    /// The checker, the vertex index and the star of every vertex.
    fn valid(m: &CMesh, vt: &[u32], what: &str) {
        m.check(false)
            .unwrap_or_else(|e| panic!("after {what}: {e}"));
        for (v, &t) in vt.iter().enumerate() {
            if t == NONE {
                continue;
            }
            let star = m.star(vt, v as u32);
            let all = m.tr.iter().filter(|t| t.v.contains(&(v as u32))).count();
            assert_eq!(star.len(), all, "after {what}: the star of {v}");
        }
    }

    #[test]
    fn splits_collapses_and_moves_keep_the_mesh_valid() {
        let mut s = 0x9e37_79b9_7f4a_7c15u64;
        let mut r = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        // Random points and a grid with collinear hull points.
        let mut pts: Vec<[f64; 2]> = (0..80).map(|_| [r(), r()]).collect();
        pts.extend((0..25).map(|k| [(k % 5) as f64 / 4.0, (k / 5) as f64 / 4.0]));
        let (mut m, mut vt) = mesh_of(&pts);
        let a0 = area(&m);
        let (mut splits, mut collapses, mut moves, mut refused) = (0, 0, 0, 0);
        for step in 0..600 {
            let t = (r() * m.tr.len() as f64) as usize;
            if m.tr[t].v[0] == DEAD {
                continue;
            }
            let e = (r() * 3.0) as usize;
            let (a, b) = edge(&m.tr[t].v, e);
            match step % 3 {
                0 => {
                    let s = m.sub_at(t, e);
                    let x = 0.3 + 0.4 * r();
                    let (pa, pb) = (*m.p(a), *m.p(b));
                    let c = [pa[0] + x * (pb[0] - pa[0]), pa[1] + x * (pb[1] - pa[1])];
                    let tc = if s == NONE { 0.0 } else { x };
                    if m.split_edge(&mut vt, t, e, c, tc).is_some() {
                        splits += 1;
                    }
                }
                1 => {
                    // Only vertices off the boundary (the engine's rules
                    // for constrained vertices are the caller's).
                    let star = m.star(&vt, a);
                    if !m.subs_at(&star).is_empty() {
                        continue;
                    }
                    match m.collapse_plan(&vt, a, b) {
                        Some(plan) => {
                            m.collapse(&mut vt, &plan);
                            collapses += 1;
                        }
                        None => refused += 1,
                    }
                }
                _ => {
                    let star = m.star(&vt, a);
                    if !m.subs_at(&star).is_empty() {
                        continue;
                    }
                    let p = *m.p(a);
                    let c = [p[0] + 0.2 * (r() - 0.5), p[1] + 0.2 * (r() - 0.5)];
                    if m.can_move(&star, &c) {
                        m.xy[a as usize] = c;
                        moves += 1;
                    } else {
                        refused += 1;
                    }
                }
            }
            valid(&m, &vt, &format!("step {step}"));
            assert!((area(&m) - a0).abs() < 1e-12, "step {step}: area");
        }
        assert!(
            splits > 100 && collapses > 50 && moves > 20 && refused > 10,
            "{splits} {collapses} {moves} {refused}"
        );
    }

    #[test]
    fn collapses_that_would_move_a_constrained_edge_are_refused() {
        // A square with a centre vertex: collapsing a corner into the centre
        // would drag the two hull edges at the corner off the hull; the
        // plan refuses it.
        let pts = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.5, 0.5]];
        let (m, vt) = mesh_of(&pts);
        assert!(m.collapse_plan(&vt, 0, 4).is_none());
        // The centre into a corner: two triangles die, two remain.
        let plan = m.collapse_plan(&vt, 4, 0).unwrap();
        assert_eq!(plan.kept.len(), 2);
        // Vertices with no edge between them.
        assert!(m.collapse_plan(&vt, 0, 2).is_none());
    }
}
