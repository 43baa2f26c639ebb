//! Constrained recovery by flips on a [`Journaled`]: missing subsegments and
//! missing input triangles are recovered by 2-3 flips and edge removals,
//! without Steiner points, whenever the flips find a way.
//!
//! **Segments** (walk from one end): the segment `u v` leaves `u` through
//! the interior of the face opposite `u` in some tetrahedron of `u`'s star,
//! or through the interior of an edge of that face (exact `orient3d` signs
//! of `v` against the three planes through `u` and the face's edges). A
//! crossed face is flipped away by a 2-3 flip (which makes the segment's
//! first crossing move one tetrahedron further); when that flip is not
//! valid, or when an edge is crossed, the blocking edge is removed by edge
//! removal, or its ring is first shrunk by 2-3 flips of the faces around
//! it. Both ends are tried alternately; a segment that makes no progress,
//! meets a vertex on its interior, or exceeds its flip budget, fails (the
//! caller then splits it). With
//! [`Effort::cones`] the first step and every [`CONE_STEPS`]th one try
//! [`cone_segment`] first: the cells the
//! open segment crosses, grown past the faces that block it, replaced by
//! the cone from one end (one operation for the whole segment, valid by
//! exact signs; the flips of the previous steps often make it possible).
//! A segment on a flat facet of the convex hull crosses only hull edges in
//! that plane, where no 2-3 flip applies and edge removal meets the
//! coplanar and cospherical configurations of extruded polygons (every two
//! vertical edges of a cylinder are coplanar): its cone is taken over the
//! cells around the crossed edges, ghost cells included, and retriangulates
//! the facet too (a fan from the end).
//! With
//! [`RecoverOptions::stop_circling_flips`](super::RecoverOptions::stop_circling_flips)
//! so does one whose flips go in a circle at both ends (the first crossing
//! from an end is one already worked on, by the unguided flips and then by
//! the guided ones), and the flips are guided by the segment when a step's
//! unguided flips fail or circle: no edge removal or
//! ring-shrinking 2-3 flip may then create more faces meeting the segment
//! than it destroys (the segment's crossings never grow back), and the
//! ring triangulation meeting it least is chosen; and of a crossed face
//! whose 2-3 flip is blocked, the edges where its two tetrahedra are not
//! convex are removed first.
//!
//! **Triangles**: the mesh edges crossing the interior of a missing
//! triangle `T` are found by a breadth-first search from the stars of the
//! vertices on `T` through tetrahedra that touch `T` or have an edge
//! crossing it. Each crossing edge is removed by edge removal choosing the
//! ring triangulation with the fewest new edges crossing `T` (Shewchuk's
//! rule: when the ring holds `T`'s vertices, the triangulation containing
//! `T` has no crossing chord); when no crossing edge can be removed, the
//! rings are shrunk by 2-3 flips. With no crossing edge left and every
//! subsegment present, `T` is a union of mesh faces.
//!
//! Nothing ever destroys a *protected* item: subsegments, the faces already
//! lying on input triangles and their edges are never flipped away (2-3
//! flips destroy only the flipped face, edge removal only the removed edge
//! and the faces around it).

use super::place;
use super::surface::Surface;
use crate::geom::ids::{IdMap, IdSet};
use crate::tet::dmesh::journal::{EdgeCost, Journaled, TriCost};
use crate::tet::local::face;
use crate::tet::local::{ekey, fkey, EDGES};
use crate::tet::local::{DEAD, INF};
use delone_predicates::orient3d;

/// Items flips must keep.
#[derive(Debug, Default)]
pub(crate) struct Protected {
    /// Edges (sorted pairs): subsegments and edges of protected faces.
    pub(crate) edges: IdSet<(u32, u32)>,
    /// Faces (sorted triples) lying on input triangles.
    pub(crate) faces: IdSet<[u32; 3]>,
}

impl Protected {
    fn edge(&self, a: u32, b: u32) -> bool {
        self.edges.contains(&ekey(a, b))
    }
    fn face(&self, f: [u32; 3]) -> bool {
        self.faces.contains(&fkey(f))
    }
    /// True when replacing tetrahedra `old` by `new` (same region) keeps
    /// every protected edge and face of `old` (the test a replayed
    /// operation must pass, [`crate::tet::dmesh::journal::Journaled::replay`]).
    pub(crate) fn kept_by(&self, old: &[[u32; 4]], new: &[[u32; 4]]) -> bool {
        let in_new = |w: &[u32]| new.iter().any(|tv| w.iter().all(|x| tv.contains(x)));
        // The set lookups first: most items of `old` are not protected, and
        // a lookup is cheaper than the scan of `new`.
        for tv in old {
            for (i, j) in EDGES {
                let (a, b) = (tv[i], tv[j]);
                if a != INF && b != INF && self.edge(a, b) && !in_new(&[a, b]) {
                    return false;
                }
            }
            for f in 0..4 {
                let fv = face(*tv, f);
                if !fv.contains(&INF) && self.face(fv) && !in_new(&fv) {
                    return false;
                }
            }
        }
        true
    }

    /// Protects face `f` and its edges.
    pub(crate) fn add_face(&mut self, f: [u32; 3]) {
        self.faces.insert(fkey(f));
        for k in 0..3 {
            self.edges.insert(ekey(f[k], f[(k + 1) % 3]));
        }
    }
}

/// Where segment `s → e` leaves `s`.
enum Hit {
    /// The segment is an edge.
    Done,
    /// Through the interior of the face opposite local vertex `f` of `t`.
    Face(u32, usize),
    /// Through the interior of edge `a b`.
    Edge(u32, u32),
    /// Through a vertex, or lost (inexact data).
    Blocked,
}

fn sgn(x: f64) -> i32 {
    (x > 0.0) as i32 - (x < 0.0) as i32
}

fn first_hit(cm: &Journaled<'_>, s: u32, e: u32) -> Hit {
    let pts = cm.pts();
    let g = |w: u32| &pts[w as usize];
    let core = &cm.m;
    // The signs of `e` against the planes through `s` and the edges of the
    // face opposite `s` in `t`, each times the orientation of `t` itself
    // (`orient3d(s, x, y, z)`: the three rotations of `x y z` are even
    // permutations, so one exact sign serves all three); `None` for a ghost.
    let signs = |t: u32| -> Option<(i32, i32, i32, [u32; 3])> {
        let tv = core.tv[t as usize];
        if tv.contains(&INF) {
            return None;
        }
        let is = tv.iter().position(|&w| w == s).unwrap_or(0);
        let [x, y, z] = face(tv, is);
        let o = sgn(orient3d(g(s), g(x), g(y), g(z)));
        let side = |a: u32, b: u32| sgn(orient3d(g(s), g(a), g(b), g(e))) * o;
        Some((side(x, y), side(y, z), side(z, x), [x, y, z]))
    };
    // The first tetrahedron of the star (breadth first, as `Journaled::star`
    // lists it) holding `e` or whose three signs are all non-negative.
    let found = cm.star_find(s, |t| {
        let tv = core.tv[t as usize];
        tv.contains(&e) || signs(t).is_some_and(|(o1, o2, o3, _)| o1 >= 0 && o2 >= 0 && o3 >= 0)
    });
    let Some(t) = found else {
        return Hit::Blocked;
    };
    if core.tv[t as usize].contains(&e) {
        return Hit::Done;
    }
    let Some((o1, o2, o3, [x, y, z])) = signs(t) else {
        return Hit::Blocked;
    };
    let is = core.tv[t as usize]
        .iter()
        .position(|&w| w == s)
        .unwrap_or(0);
    match (o1 == 0, o2 == 0, o3 == 0) {
        (false, false, false) => Hit::Face(t, is),
        (true, false, false) => Hit::Edge(x, y),
        (false, true, false) => Hit::Edge(y, z),
        (false, false, true) => Hit::Edge(z, x),
        _ => Hit::Blocked,
    }
}

/// The edges of the face opposite local vertex `f` of `t`; with
/// `reflex_first`, those at which the two tetrahedra sharing the face are
/// not convex first (the edges whose tetrahedron of the 2-3 flip would not
/// be positive: the ones that block it, so removing one of them is what
/// can let the flip through).
fn face_edges(cm: &Journaled<'_>, t: u32, f: usize, reflex_first: bool) -> Vec<(u32, u32)> {
    let fv = face(cm.m.tv[t as usize], f);
    let mut out: Vec<(bool, usize, (u32, u32))> = (0..3)
        .map(|k| (true, k, (fv[k], fv[(k + 1) % 3])))
        .collect();
    if !reflex_first {
        return out.into_iter().map(|o| o.2).collect();
    }
    if let Some(blocks) = flip23_blocking(cm, t, f) {
        for (o, b) in out.iter_mut().zip(blocks) {
            o.0 = !b;
        }
    }
    out.sort_by_key(|o| (o.0, o.1));
    out.into_iter().map(|o| o.2).collect()
}

/// Per edge of the face opposite local vertex `f` of `t` (in [`face`]
/// order: `fv[k] fv[k + 1]`), whether it blocks the face's 2-3 flip: the
/// flip's new tetrahedron on that edge (with the two apexes) would not be
/// positive. `None` when a ghost is involved.
fn flip23_blocking(cm: &Journaled<'_>, t: u32, f: usize) -> Option<[bool; 3]> {
    let tv = cm.m.tv[t as usize];
    let fv = face(tv, f);
    let d = tv[f];
    let e = *cm
        .m
        .tv
        .get(cm.m.across(t, f) as usize)?
        .iter()
        .find(|w| !tv.contains(w))?;
    if d == INF || e == INF || fv.contains(&INF) {
        return None;
    }
    Some([0, 1, 2].map(|k| !cm.positive([fv[k], fv[(k + 1) % 3], e, d])))
}

fn zero(_: &[[f64; 3]], _: [u32; 3]) -> i64 {
    0
}

fn zero2(_: &[[f64; 3]], _: u32, _: u32) -> i64 {
    0
}

/// Most edge-removal attempts one [`remove_edge_deep`] call makes.
const WORK: usize = 16;

/// A segment with its bounding box, for the tests of one flip decision
/// whether it meets faces ([`SegTest::meets`]; the box is computed once,
/// not per face).
struct SegTest<'m> {
    u: u32,
    v: u32,
    lo: [f64; 3],
    hi: [f64; 3],
    /// Recent answers (the mesh's [`Journaled::seg_memo`]): the flips
    /// test the same faces again and again. An answer never changes (the
    /// points are only ever appended to).
    memo: &'m SegMemo,
}

/// The memo of [`SegTest::meets`]: the segment's ends and the face, as
/// asked.
type SegMemo = crate::tet::dmesh::memo::Recent<5>;

impl<'m> SegTest<'m> {
    fn new(pts: &[[f64; 3]], (u, v): (u32, u32), memo: &'m SegMemo) -> Self {
        let (pu, pv) = (pts[u as usize], pts[v as usize]);
        let lo = [0, 1, 2].map(|k| if pv[k] < pu[k] { pv[k] } else { pu[k] });
        let hi = [0, 1, 2].map(|k| if pv[k] > pu[k] { pv[k] } else { pu[k] });
        SegTest { u, v, lo, hi, memo }
    }

    /// [`SegTest::meets_exact`], its recent answers remembered.
    fn meets(&self, pts: &[[f64; 3]], f: [u32; 3]) -> i64 {
        let k = [self.u, self.v, f[0], f[1], f[2]];
        i64::from(self.memo.answer(k, || self.meets_exact(pts, f) == 1))
    }

    /// 1 when this segment meets face `f` (on points `pts`) other than at
    /// a shared vertex: its ends strictly on the two sides of the face's
    /// plane and its line through the closed triangle (so also through an
    /// edge or a vertex of it); else 0 (a ghost face, a face at an end of
    /// the segment).
    fn meets_exact(&self, pts: &[[f64; 3]], f: [u32; 3]) -> i64 {
        let (u, v) = (self.u, self.v);
        if f.contains(&INF) || f.contains(&u) || f.contains(&v) {
            return 0;
        }
        let g = |w: u32| &pts[w as usize];
        let [x, y, z] = f;
        // Disjoint bounding boxes: no meeting (no predicate needed).
        let (px, py, pz) = (g(x), g(y), g(z));
        if (0..3).any(|k| {
            (self.hi[k] < px[k] && self.hi[k] < py[k] && self.hi[k] < pz[k])
                || (self.lo[k] > px[k] && self.lo[k] > py[k] && self.lo[k] > pz[k])
        }) {
            return 0;
        }
        let (pu, pv) = (g(u), g(v));
        let (ou, ov) = (sgn(orient3d(px, py, pz, pu)), sgn(orient3d(px, py, pz, pv)));
        if ou * ov >= 0 {
            return 0;
        }
        let s = [(x, y), (y, z), (z, x)].map(|(p, q)| sgn(orient3d(pu, pv, g(p), g(q))));
        i64::from(s.iter().all(|&k| k >= 0) || s.iter().all(|&k| k <= 0))
    }
}

/// Edge removal of `a b` (in `t`) while recovering segment `s`: refused
/// when the faces it creates meet `s` more often than the faces it
/// destroys (the segment's crossings never grow, so the flips cannot go in
/// a circle that brings a crossing back), and on a ring through a ghost;
/// among the allowed ring triangulations, one meeting `s` least.
fn remove_edge_for(cm: &mut Journaled<'_>, t: u32, a: u32, b: u32, s: (u32, u32)) -> bool {
    // (The memo is taken out of the mesh while the removal runs.)
    let memo = std::mem::take(&mut cm.seg_memo);
    let seg = SegTest::new(cm.pts(), s, &memo);
    let limit = |p: &[[f64; 3]], ring: &[u32]| -> Option<i64> {
        if ring.contains(&INF) {
            return None;
        }
        Some(ring.iter().map(|&r| seg.meets(p, [a, b, r])).sum::<i64>() + 1)
    };
    let tri = |p: &[[f64; 3]], f: [u32; 3]| seg.meets(p, f);
    let chord = |p: &[[f64; 3]], x: u32, y: u32| seg.meets(p, [a, x, y]) + seg.meets(p, [b, x, y]);
    let done = cm
        .remove_edge_limited(t, a, b, (&tri, &chord), limit)
        .is_some();
    cm.seg_memo = memo;
    done
}

/// What guides the flips of [`remove_edge_deep`]: the costs of the ring
/// triangulations of its top-level removals (deeper ones cost nothing), or
/// the segment being recovered ([`remove_edge_for`], at every level, and
/// the ring-shrinking 2-3 flips under the same rule).
#[derive(Clone, Copy)]
enum Guide<'c> {
    Costs(TriCost<'c>, EdgeCost<'c>),
    Segment(u32, u32),
}

/// Removes edge `a b` by edge removal; when its ring admits no valid
/// triangulation, first shrinks the ring by 2-3 flips of the faces around
/// it, and when such a flip is not valid (an edge `a r` or `b r` of the face
/// is in the way), removes that edge the same way with `depth - 1`
/// (TetGen's flip-n-m idea, bounded depth, no recursion on the call stack
/// beyond `depth` levels). Each edge-removal attempt, at any depth, takes
/// one unit of `budget` (a call starts with [`WORK`]).
///
/// With `blockers`, the deeper level removes only the edges that block a
/// face's flip ([`flip23_blocking`]), face by face around the ring;
/// without, it tries `a r` and `b r` for every ring vertex `r` in turn.
fn remove_edge_deep(
    cm: &mut Journaled<'_>,
    (a, b): (u32, u32),
    (depth, blockers): (u32, bool),
    prot: &Protected,
    guide: Guide<'_>,
    budget: &mut usize,
) -> bool {
    if prot.edge(a, b) || *budget == 0 {
        return false;
    }
    *budget -= 1;
    let remove = |cm: &mut Journaled<'_>, t: u32| match guide {
        Guide::Costs(tri, chord) => cm.remove_edge(t, a, b, tri, chord).is_some(),
        Guide::Segment(u, v) => remove_edge_for(cm, t, a, b, (u, v)),
    };
    let deeper = match guide {
        Guide::Costs(..) => Guide::Costs(&zero, &zero2),
        g => g,
    };
    let next = (depth.saturating_sub(1), blockers);
    let Some(t) = cm.find_edge(a, b) else {
        return true;
    };
    if remove(cm, t) {
        return true;
    }
    if depth == 0 {
        return false;
    }
    // The ring lists come from the mesh's spare ones and go back to it.
    let mut bufs = cm.ring_buffers();
    let done = shrink_ring(
        cm,
        (t, a, b),
        &mut bufs,
        (depth, next),
        prot,
        (guide, deeper),
        budget,
    );
    cm.give_ring_buffers(bufs);
    done
}

/// The ring-shrinking steps of [`remove_edge_deep`] (`depth` ≥ 1) on edge
/// `a b` of `t` (whose removal just failed), the ring walked into `bufs`
/// at each step; `next` is the deeper calls' level, `guide` guides this
/// level's removals and flips, `deeper` the deeper calls.
fn shrink_ring(
    cm: &mut Journaled<'_>,
    (mut t, a, b): (u32, u32, u32),
    (tets, ring): &mut (Vec<u32>, Vec<u32>),
    (depth, next): (u32, (u32, bool)),
    prot: &Protected,
    (guide, deeper): (Guide<'_>, Guide<'_>),
    budget: &mut usize,
) -> bool {
    let blockers = next.1;
    let remove = |cm: &mut Journaled<'_>, t: u32| match guide {
        Guide::Costs(tri, chord) => cm.remove_edge(t, a, b, tri, chord).is_some(),
        Guide::Segment(u, v) => remove_edge_for(cm, t, a, b, (u, v)),
    };
    // Each step starts from the slot `find_edge` gave before the failed
    // removal that ended the step before (the mesh is as it was then).
    for _ in 0..crate::tet::dmesh::journal::MAX_RING {
        if !cm.edge_ring_again(t, a, b, (tets, ring)) {
            return false;
        }
        let (tets, ring) = (&tets[..], &ring[..]);
        let n = ring.len();
        let mut progress = false;
        // (A 2-3 flip of a face around the edge shrinks its ring by one:
        // none with a ring of three.)
        for i in (0..n).filter(|_| n > 3) {
            // Face (a, b, ring[i]) is opposite ring[i + 1] in tets[i].
            if prot.face([a, b, ring[i]]) {
                continue;
            }
            let x = tets[i];
            let tv = cm.m.tv[x as usize];
            let Some(f) = tv.iter().position(|&w| w == ring[(i + 1) % n]) else {
                continue;
            };
            // Validity first (three exact signs), then the guide's test.
            let Some(plan) = cm.flip23_plan(x, f) else {
                continue;
            };
            if let Guide::Segment(u, v) = guide {
                // The flip's new faces are those around edge p q.
                let (p, q) = (ring[(i + 1) % n], ring[(i + n - 1) % n]);
                let pts = cm.pts();
                let seg = SegTest::new(pts, (u, v), &cm.seg_memo);
                let old = seg.meets(pts, [a, b, ring[i]]);
                let new: i64 = [a, b, ring[i]]
                    .iter()
                    .map(|&w| seg.meets(pts, [p, q, w]))
                    .sum();
                if new > old {
                    continue;
                }
            }
            cm.apply_flip23(plan);
            progress = true;
            break;
        }
        // No face flips: the edges that block them are removed one level
        // deeper (TetGen's flip-n-m recursion), face by face around the
        // ring. A face's flip is blocked by the edges whose new tetrahedron
        // would not be positive; one blocked by `a b` itself cannot shrink
        // the ring, one blocked by `a r` or `b r` can once that edge is
        // gone. Only those edges are tried: the others cannot help, and
        // each try takes work from the budget the deeper levels need (on
        // the 182 held-out CAD shapes, `-p` puts 18% fewer points on the
        // segments in 35% less time; the meshes `-q` refines from the old
        // way are better, so the refinement path keeps it).
        if !progress && depth > 1 && !blockers {
            for &r in ring {
                if *budget == 0 {
                    return false;
                }
                // (True only when the edge is gone.)
                if remove_edge_deep(cm, (a, r), next, prot, deeper, budget)
                    || remove_edge_deep(cm, (b, r), next, prot, deeper, budget)
                {
                    progress = true;
                    break;
                }
            }
        }
        if !progress && depth > 1 && blockers {
            // The cells of the ring as walked at this step: a deeper call
            // that fails may have flipped some of them away. A slot it freed
            // is skipped (dead); a slot it reused is taken with the face of
            // its new cell opposite `ring[i + 1]`, when it has that vertex
            // (every operation is checked, so the mesh stays valid either
            // way). Looking the face `a b ring[i]` up again instead, or
            // skipping reused slots, gave 1.5% more Steiner points on the
            // 182 held-out shapes and made the `-Y` fallback slower on one
            // tube (seed 500: 2.2 s to 5–14 s).
            'faces: for i in 0..n {
                let x = tets[i];
                let Some(f) = cm.m.tv[x as usize]
                    .iter()
                    .position(|&w| w == ring[(i + 1) % n])
                else {
                    continue;
                };
                let Some(blocks) = flip23_blocking(cm, x, f) else {
                    continue;
                };
                let fv = face(cm.m.tv[x as usize], f);
                let edges = [0, 1, 2].map(|k| (fv[k], fv[(k + 1) % 3]));
                let ab = ekey(a, b);
                if (0..3).any(|k| blocks[k] && ekey(edges[k].0, edges[k].1) == ab) {
                    continue;
                }
                for (p, q) in (0..3).filter(|&k| blocks[k]).map(|k| edges[k]) {
                    if *budget == 0 {
                        return false;
                    }
                    // (True only when the edge is gone.)
                    if remove_edge_deep(cm, (p, q), next, prot, deeper, budget) {
                        progress = true;
                        break 'faces;
                    }
                }
            }
        }
        if !progress || *budget == 0 {
            return false;
        }
        *budget -= 1;
        let Some(x) = cm.find_edge(a, b) else {
            return true;
        };
        if remove(cm, x) {
            return true;
        }
        t = x;
    }
    false
}

/// Flip depth of segment and facet recovery.
const DEPTH: u32 = 2;

/// Most flips and edge removals one segment may use in the rounds of the
/// constrained path ([`recover_segment_within`]) before it counts as failed
/// (and is split). Segments recovered on the large corpus models use at
/// most 238 (p99 about 20), while most failing ones run into the bound on
/// flips that are rolled back anyway: the bound saves work on hopeless
/// segments. Measured with 256, 128, 96 and 64:
/// 128 costs, against 256, 2 more Steiner points on the whole `closed_clean` corpus
/// (1254 instead of 1252; 108 → 111 on c3d_nefertiti, 143 → 145 on
/// vtk_turbineblade) and fewer rounds (136 instead of 146), and saves 5–6%
/// of the instructions of `recover` on the large models; 64 saves 10% but
/// costs 12% more Steiner points. Not used with `-Y`, which keeps its
/// flips.
pub(crate) const SEG_OPS: usize = 128;

/// How hard [`recover_segment_within`] tries: the depth and the work
/// budget of each edge removal ([`remove_edge_deep`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Effort {
    pub(crate) depth: u32,
    pub(crate) work: usize,
    /// Every [`CONE_STEPS`] steps try [`cone_segment`] first.
    pub(crate) cones: bool,
    /// With `cones`, a segment whose flips give up tries the cone over a
    /// flat facet of the convex hull last.
    pub(crate) flat: bool,
    /// The deeper levels of edge removal remove only the edges that block
    /// a face's 2-3 flip ([`remove_edge_deep`]).
    pub(crate) blockers: bool,
}

impl Effort {
    /// Every segment's attempts in the rounds.
    pub(crate) const BASE: Effort = Effort {
        depth: DEPTH,
        work: WORK,
        cones: false,
        flat: true,
        blockers: false,
    };

    /// Level `level` ≥ 2 of the escalation for segments that still fail
    /// (TetGen's "auto levels", Si 2015): depth `level`, the work doubled
    /// per level above [`DEPTH`].
    pub(crate) fn level(level: u32) -> Effort {
        Effort {
            depth: level,
            work: WORK << level.saturating_sub(DEPTH),
            ..Effort::BASE
        }
    }

    /// Level `level` ≥ 2 with the work growing linearly
    /// (`WORK · level`): for attempts that keep their flips when they fail,
    /// so each level goes on from where the one before stopped.
    pub(crate) fn linear(level: u32) -> Effort {
        Effort {
            depth: level,
            work: WORK * level as usize,
            ..Effort::BASE
        }
    }
}

/// Recovers subsegment `u v` by flips; false when they fail.
pub(crate) fn recover_segment(cm: &mut Journaled<'_>, u: u32, v: u32, prot: &Protected) -> bool {
    let effort = Effort {
        blockers: true,
        ..Effort::BASE
    };
    recover_segment_within(cm, u, v, prot, usize::MAX / 2, false, effort)
}

/// [`recover_segment`] using at most about `max_ops` flips and edge
/// removals (checked between steps). With `stop_circles`, the unguided
/// flips at an end of the segment are given up when its first crossing is
/// one they already worked on (the flips went in a circle: a later step
/// restored what an earlier one removed), the segment-guided ones the same
/// way (each keeps its own list), and the segment when no flip at either
/// end makes progress: a segment that cycles so would otherwise spend its
/// whole budget on flips that are rolled back anyway. `effort`: the depth
/// and work of its edge removals.
pub(crate) fn recover_segment_within(
    cm: &mut Journaled<'_>,
    u: u32,
    v: u32,
    prot: &Protected,
    max_ops: usize,
    stop_circles: bool,
    effort: Effort,
) -> bool {
    const CAP: usize = 48;
    if cm.find_edge(u, v).is_some() {
        return true;
    }
    let ops0 = cm.flips23 + cm.removals;
    let guide = if stop_circles {
        Guide::Segment(u, v)
    } else {
        Guide::Costs(&zero, &zero2)
    };
    // The first crossings already worked on, per pass (unguided, guided)
    // and end (`stop_circles`).
    let mut seen: [Vec<(u32, [u32; 3])>; 2] = [Vec::new(), Vec::new()];
    // Per end: given up by the guided pass (its flips went in a circle).
    let mut guided_given_up = [false; 2];
    // With `stop_circles`, a step whose unguided flips all fail is tried
    // again with segment-guided ones (guided only, the rule, which counts
    // the faces the segment meets at an edge or a corner too, refuses
    // every way through on coplanar fans: 550 Steiner points instead of 4
    // on a 600-triangle star prism; guided first costs CPU on cgal_anchor
    // and revolved vases). An end whose unguided flips went in a circle
    // is still tried guided, until the guided flips circle there too.
    let guides = if stop_circles {
        &[Guide::Costs(&zero, &zero2), guide][..]
    } else {
        &[guide][..]
    };
    // One edge removal of a step, at the effort's depth and work.
    let remove = |cm: &mut Journaled<'_>, e: (u32, u32), g: Guide<'_>| {
        let level = (effort.depth, effort.blockers);
        remove_edge_deep(cm, e, level, prot, g, &mut { effort.work })
    };
    // When the flips give up, a segment on a flat facet of the convex hull
    // takes the cone over the cells around the hull edges it crosses (only
    // then: where the flips succeed they are left as they were).
    let last = |cm: &mut Journaled<'_>| {
        effort.cones && effort.flat && cone_segment_in(cm, u, v, prot, true)
    };
    for step in 0..CAP {
        if cm.flips23 + cm.removals > ops0 + max_ops {
            return last(cm);
        }
        // Every [`CONE_STEPS`] steps, the segment's cavity cone first (one
        // operation for the whole segment): the flips of the steps between
        // often make its cavity star-shaped from an end.
        if effort.cones && step % CONE_STEPS == 0 && cone_segment(cm, u, v, prot) {
            return true;
        }
        let mut progress = false;
        let mut given_up = [false; 2];
        'passes: for (pass, &g) in guides.iter().enumerate() {
            for (end, (s, e)) in [(u, v), (v, u)].into_iter().enumerate() {
                if (pass == 0 && given_up[end]) || (pass > 0 && guided_given_up[end]) {
                    continue;
                }
                let hit = first_hit(cm, s, e);
                let key = match hit {
                    _ if !stop_circles => None,
                    Hit::Face(t, f) => Some(fkey(face(cm.m.tv[t as usize], f))),
                    Hit::Edge(a, b) => Some(fkey([a, b, INF])),
                    Hit::Done | Hit::Blocked => None,
                };
                if let Some(k) = key {
                    if seen[pass].contains(&(s, k)) {
                        if pass == 0 {
                            given_up[end] = true;
                        } else {
                            guided_given_up[end] = true;
                        }
                        continue;
                    }
                    seen[pass].push((s, k));
                }
                match hit {
                    Hit::Done => return true,
                    Hit::Face(t, f) => {
                        let tv = cm.m.tv[t as usize];
                        let fv = face(tv, f);
                        if !prot.face(fv) && cm.flip23(t, f) {
                            progress = true;
                        } else {
                            for e in face_edges(cm, t, f, stop_circles) {
                                if remove(cm, e, g) {
                                    progress = true;
                                    break;
                                }
                            }
                        }
                    }
                    Hit::Edge(a, b) => {
                        if remove(cm, (a, b), g) {
                            progress = true;
                        }
                    }
                    Hit::Blocked => {}
                }
                if progress {
                    break 'passes;
                }
            }
        }
        if !progress {
            return last(cm);
        }
    }
    cm.find_edge(u, v).is_some() || last(cm)
}

/// Most tetrahedra of the cavity of [`cone_segment`].
const CONE_MAX: usize = 400;

/// Most times [`cone_segment`] grows its cavity from one end.
const CONE_GROW: usize = 32;

/// How often [`recover_segment_within`] tries [`cone_segment`]: at its
/// first step and every third one after. Measured on tubes and turned
/// parts (seeds 500–502 of `cad_shapes.py`, the `w_tube`/`q4` shapes)
/// against every step: 10% more Steiner points, 15% less time.
const CONE_STEPS: usize = 3;

/// A cavity of [`cone_segment`]: its slots in order, and as a set in the
/// mesh's visited stamps ([`Journaled::visit`]: one cavity at a time, so
/// [`Cavity::mark`] makes a cavity the current one again).
#[derive(Clone, Default)]
struct Cavity {
    list: Vec<u32>,
}

impl Cavity {
    /// Makes this cavity the visited set.
    fn mark(&self, cm: &Journaled<'_>) {
        cm.visit_begin();
        for &t in &self.list {
            cm.visit(t);
        }
    }
    fn push(&mut self, cm: &Journaled<'_>, t: u32) {
        if cm.visit(t) {
            self.list.push(t);
        }
    }
    fn has(cm: &Journaled<'_>, t: u32) -> bool {
        cm.visited(t)
    }
}

/// Recovers segment `u v` in one operation: the tetrahedra the open
/// segment crosses (found across the faces it meets, from the star of
/// `u`) form a cavity whose boundary holds both ends; when every boundary
/// face not at one end sees that end strictly on its inner side, the cone
/// from that end over them fills the cavity exactly (each point inside is
/// covered once: the boundary winds once around it and every cone
/// tetrahedron is positive) and has edge `u v`. Where faces block the
/// cone (the end not strictly on their inner side), the tetrahedra behind
/// them join the cavity, [`CONE_GROW`] times at most, for each end in
/// turn (the end with fewer blocking faces first).
///
/// A segment lying on a flat facet of the convex hull (the cap of an
/// extruded polygon, a side rectangle) crosses hull edges only, so no cell
/// has it inside: its cavity is the cells around those edges, ghost cells
/// included ([`hull_channel`]), and the cone from an end also gives the
/// ghosts a fan of new hull faces on the facet (each in its old hull
/// face's plane and facing out, [`ghost_ok`]): the 2D retriangulation of
/// the facet with the segment, made with the 3D one in one operation. Its
/// cavity may then grow into ghost cells too.
///
/// Refused (false, nothing changed) when, from both ends, the cavity
/// reaches a ghost (but on a flat hull facet), a protected face or
/// [`CONE_MAX`] tetrahedra, would remove a protected edge or a vertex, or
/// has a boundary edge not in exactly two boundary faces.
pub(crate) fn cone_segment(cm: &mut Journaled<'_>, u: u32, v: u32, prot: &Protected) -> bool {
    cone_segment_in(cm, u, v, prot, false)
}

/// [`cone_segment`]; with `hull`, only for a segment on a flat facet of the
/// convex hull (its cavity the cells around the hull edges it crosses),
/// else never on one.
fn cone_segment_in(cm: &mut Journaled<'_>, u: u32, v: u32, prot: &Protected, hull: bool) -> bool {
    let pts = cm.pts();
    let seg = SegTest::new(pts, (u, v), &cm.seg_memo);
    let m = &cm.m;
    let finite = |t: u32| (t as usize) < m.tv.len() && !m.tv[t as usize].contains(&INF);
    let mut cav = Cavity::default();
    cm.visit_begin();
    let star = cm.star(u);
    for &t in &star {
        let tv = m.tv[t as usize];
        let Some(i) = tv.iter().position(|&w| w == u) else {
            continue;
        };
        if finite(t) && seg.meets(pts, face(tv, i)) == 1 {
            cav.push(cm, t);
        }
    }
    // The tetrahedra behind the faces the segment meets. A segment on a
    // flat facet of the convex hull touches no cell's interior, only the
    // hull edges it crosses: its cavity is the cells around those edges,
    // ghosts included ([`hull_channel`]).
    let on_hull = star.iter().any(|&t| m.tv[t as usize][3] == INF);
    let flat = (hull && on_hull).then(|| hull_channel(cm, u, v)).flatten();
    if hull && flat.is_none() {
        return false;
    }
    if let Some(ref cells) = flat {
        cav = Cavity::default();
        cm.visit_begin();
        for &t in cells {
            cav.push(cm, t);
        }
    }
    let mut i = 0;
    while flat.is_none() && i < cav.list.len() {
        let t = cav.list[i];
        i += 1;
        let tv = m.tv[t as usize];
        for f in 0..4 {
            let fv = face(tv, f);
            if seg.meets(pts, fv) == 0 {
                continue;
            }
            let n = m.across(t, f);
            if !finite(n) || prot.face(fv) {
                return false;
            }
            cav.push(cm, n);
            if cav.list.len() > CONE_MAX {
                return false;
            }
        }
    }
    if cav.list.is_empty() {
        return false;
    }
    let flat = flat.is_some();
    // May cavity cell `t` take `apex` for its vertex `f`? A finite result
    // must be strictly positive; a ghost (only for a segment on a flat
    // hull facet) must keep its hull face in the old one's plane, facing
    // out ([`ghost_ok`]).
    let cell_ok = |t: u32, f: usize, apex: u32| -> bool {
        let mut tv = m.tv[t as usize];
        tv[f] = apex;
        if !tv.contains(&INF) {
            crate::tet::dmesh::flip::positive(pts, tv)
        } else {
            flat && ghost_ok(cm, t, apex, tv)
        }
    };
    let finite = |t: u32| finite(t) || (flat && m.alive(t));
    // Boundary faces of a cavity: (slot, local face) with the neighbour
    // outside, in the order of the cavity's cells and their faces.
    let boundary = |cav: &Cavity| -> Vec<(u32, usize)> {
        cav.list
            .iter()
            .flat_map(|&t| (0..4).map(move |f| (t, f)))
            .filter(|&(t, f)| !Cavity::has(cm, m.across(t, f)))
            .collect()
    };
    // Does boundary face `f` of cell `t` block the cone from `apex`? Each
    // boundary face carries its answer (0: not asked yet, 1: no, 2: yes),
    // asked once (the mesh does not change while a cavity grows).
    let blocks = |t: u32, f: usize, apex: u32| -> u8 {
        1 + u8::from(!m.tv[t as usize].contains(&apex) && !cell_ok(t, f, apex))
    };
    // The blocking faces among `bnd[from..]`, in order (answers asked
    // for the faces not asked yet).
    let blocking =
        |bnd: &mut [(u32, usize, u8)], from: usize, apex: u32, out: &mut Vec<(u32, usize)>| {
            out.clear();
            for e in &mut bnd[from..] {
                if e.2 == 0 {
                    e.2 = blocks(e.0, e.1, apex);
                }
                if e.2 == 2 {
                    out.push((e.0, e.1));
                }
            }
        };
    let bnd0: Vec<(u32, usize, u8)> = boundary(&cav).into_iter().map(|(t, f)| (t, f, 0)).collect();
    let mut start = [bnd0.clone(), bnd0];
    let mut block = Vec::new();
    blocking(&mut start[0], 0, u, &mut block);
    let nu = block.len();
    blocking(&mut start[1], 0, v, &mut block);
    let mut ends = [(nu, u, 0), (block.len(), v, 1)];
    ends.sort_unstable();
    for (i, (_, apex, k)) in ends.into_iter().enumerate() {
        let mut cav = cav.clone();
        if i > 0 {
            cav.mark(cm);
        }
        // The boundary is kept up to date as cells join: faces whose
        // neighbour joined leave it, the new cells' outer faces are
        // appended (the order `boundary` gives). A blocking face's
        // neighbour joins, so every face blocking after a step is among
        // those appended by it (from `fresh` on; the first step looks at
        // all).
        let mut bnd = std::mem::take(&mut start[k]);
        let mut fresh = 0;
        'grow: for _ in 0..=CONE_GROW {
            blocking(&mut bnd, fresh, apex, &mut block);
            if block.is_empty() {
                let faces: Vec<(u32, usize)> = bnd.iter().map(|e| (e.0, e.1)).collect();
                if let Some(new) = cone_tets(cm, &cav, &faces, apex, prot) {
                    cm.replace(&cav.list, &new);
                    return true;
                }
                break;
            }
            let old = cav.list.len();
            for &(t, f) in &block {
                let n = m.across(t, f);
                if !finite(n) || prot.face(face(m.tv[t as usize], f)) {
                    break 'grow;
                }
                cav.push(cm, n);
            }
            if cav.list.len() > CONE_MAX {
                break;
            }
            bnd.retain(|&(t, f, _)| !Cavity::has(cm, m.across(t, f)));
            fresh = bnd.len();
            for &t in &cav.list[old..] {
                bnd.extend(
                    (0..4)
                        .filter(|&f| !Cavity::has(cm, m.across(t, f)))
                        .map(|f| (t, f, 0)),
                );
            }
        }
    }
    false
}

/// The cone of [`cone_segment`] from `apex` over the boundary faces `bnd`
/// of cavity `cav` not at `apex` (each face's tetrahedron with its inner
/// vertex replaced by `apex`: same orientation); `None` when the cavity
/// has a vertex on no boundary face, a protected edge or face inside, or
/// a boundary edge not in exactly two boundary faces.
fn cone_tets(
    cm: &Journaled<'_>,
    cav: &Cavity,
    bnd: &[(u32, usize)],
    apex: u32,
    prot: &Protected,
) -> Option<Vec<[u32; 4]>> {
    let m = &cm.m;
    let mut bedges: Vec<(u32, u32)> = Vec::with_capacity(3 * bnd.len());
    let mut bverts: Vec<u32> = Vec::with_capacity(3 * bnd.len());
    let mut new = Vec::with_capacity(bnd.len());
    for &(t, f) in bnd {
        let fv = face(m.tv[t as usize], f);
        for k in 0..3 {
            bedges.push(ekey(fv[k], fv[(k + 1) % 3]));
        }
        bverts.extend(fv);
        if !fv.contains(&apex) {
            let mut tv = m.tv[t as usize];
            tv[f] = apex;
            new.push(tv);
        }
    }
    bedges.sort_unstable();
    bverts.sort_unstable();
    bverts.dedup();
    // Every boundary edge in exactly two boundary faces.
    if bedges.chunk_by(|a, b| a == b).any(|run| run.len() != 2) {
        return None;
    }
    for &t in &cav.list {
        let tv = m.tv[t as usize];
        if tv.iter().any(|w| bverts.binary_search(w).is_err()) {
            return None;
        }
        for (a, b) in EDGES {
            let e = ekey(tv[a], tv[b]);
            if bedges.binary_search(&e).is_err() && prot.edges.contains(&e) {
                return None;
            }
        }
        for f in 0..4 {
            if Cavity::has(cm, m.across(t, f)) && prot.face(face(tv, f)) {
                return None;
            }
        }
    }
    Some(new)
}

/// Exact: may ghost cell `t` (hull face `x y z`, [`INF`] last) become
/// ghost `new` (a vertex of the face replaced by `apex`)? Its new hull face
/// must lie in the plane of `x y z` (so on the same facet of the convex
/// hull) and face out: the inner vertex of the finite cell behind `x y z`
/// on its positive side, as for every ghost cell.
fn ghost_ok(cm: &Journaled<'_>, t: u32, apex: u32, new: [u32; 4]) -> bool {
    let (m, pts) = (&cm.m, cm.pts());
    let g = |w: u32| &pts[w as usize];
    let tv = m.tv[t as usize];
    if tv[3] != INF || new[3] != INF || apex == INF {
        return false;
    }
    let Some(&inner) =
        m.tv.get(m.across(t, 3) as usize)
            .and_then(|nv| nv.iter().find(|w| !tv.contains(w)))
    else {
        return false;
    };
    inner != INF
        && orient3d(g(tv[0]), g(tv[1]), g(tv[2]), g(apex)) == 0.0
        && orient3d(g(new[0]), g(new[1]), g(new[2]), g(inner)) > 0.0
}

/// The cells around the hull edges that segment `u v` crosses when it lies
/// on a flat facet of the convex hull (the caps of extruded polygons: the
/// segment touches no cell's interior, only edges), walking in the facet's
/// plane from `u` across ghost cells (exact `orient3d` with a vertex off
/// the plane for the in-plane orientation), and the facet. `None` when the
/// segment leaves the facet, passes through a vertex, or crosses more than
/// [`CONE_MAX`] edges.
fn hull_channel(cm: &Journaled<'_>, u: u32, v: u32) -> Option<Vec<u32>> {
    let pts = cm.pts();
    let g = |w: u32| &pts[w as usize];
    let m = &cm.m;
    // The ghost at `u` whose hull face has `v` in its plane and strictly
    // inside its angle at `u`: (ghost, the face's other two vertices in
    // ghost order, the inner vertex).
    let mut start = None;
    for t in cm.star(u) {
        let tv = m.tv[t as usize];
        if tv[3] != INF {
            continue;
        }
        let Some(iu) = tv[..3].iter().position(|&w| w == u) else {
            continue;
        };
        let (p, q) = (tv[(iu + 1) % 3], tv[(iu + 2) % 3]);
        if orient3d(g(u), g(p), g(q), g(v)) != 0.0 {
            continue;
        }
        let n = m.across(t, 3);
        let Some(&w) =
            m.tv.get(n as usize)
                .and_then(|nv| nv.iter().find(|&&w| w != u && w != p && w != q))
        else {
            continue;
        };
        if w == INF {
            continue;
        }
        let o = |a: u32, b: u32, c: u32| sgn(orient3d(g(a), g(b), g(c), g(w)));
        let s = o(u, p, q);
        if s != 0 && o(u, p, v) == s && o(u, v, q) == s {
            start = Some((t, p, q, w));
            break;
        }
    }
    let (mut t, mut p, mut q, w) = start?;
    let [a, b, c] = [u, p, q].map(g);
    let o = |x: u32, y: u32, z: u32| sgn(orient3d(g(x), g(y), g(z), g(w)));
    let (mut cells, mut set, mut seen) = (Vec::new(), IdSet::default(), 0usize);
    let (mut tets, mut ring) = (Vec::new(), Vec::new());
    loop {
        seen += 1;
        if seen > CONE_MAX {
            return None;
        }
        // The cells around crossed edge `p q` (ghosts included).
        m.ring_into(
            t,
            (p, q),
            (CONE_MAX, false),
            |_, _| true,
            (&mut tets, &mut ring),
        )?;
        for &x in &tets {
            if set.insert(x) {
                cells.push(x);
            }
        }
        if cells.len() > CONE_MAX {
            return None;
        }
        // The ghost across `p q` in the plane: behind the face of `t`
        // opposite its third finite vertex.
        let tv = m.tv[t as usize];
        let ir = tv.iter().position(|&x| x != p && x != q && x != INF)?;
        let n = m.across(t, ir);
        let nv = *m.tv.get(n as usize)?;
        if nv[3] != INF {
            return None;
        }
        let z = *nv[..3].iter().find(|&&x| x != p && x != q)?;
        if orient3d(a, b, c, g(z)) != 0.0 {
            return None;
        }
        t = n;
        if z == v {
            return Some(cells);
        }
        let sz = o(u, v, z);
        if sz == 0 {
            return None;
        }
        if sz == o(u, v, p) {
            p = z;
        } else {
            q = z;
        }
    }
}

/// The vertices lying on input triangle `t`: its corners, chains and inner
/// points.
pub(crate) fn tri_vertices(surf: &Surface, t: usize, extra: &[u32]) -> Vec<u32> {
    let mut out: Vec<u32> = surf.tri_edges[t]
        .iter()
        .flat_map(|&e| surf.chains[e as usize].iter().copied())
        .chain(surf.tris[t])
        .chain(extra.iter().copied())
        .collect();
    out.sort_unstable();
    out.dedup();
    out
}

/// Mesh edges crossing the interior of input triangle `t` (see the module
/// documentation), sorted, each with a tetrahedron containing it.
pub(crate) fn crossing_edges(
    cm: &Journaled<'_>,
    surf: &Surface,
    t: usize,
    inner: &[u32],
) -> Vec<((u32, u32), u32)> {
    let pts = cm.pts();
    let g = |w: u32| &pts[w as usize];
    let [a, b, c] = surf.tris[t].map(g);
    // The side of `t`'s plane of each vertex met (0 also for vertices on
    // `t`, which no crossing edge has), computed once: an edge can cross
    // only if its ends are strictly on opposite sides — the first test of
    // `place::crosses`, whose remaining three tests follow.
    // Per vertex also whether it lies on `t` (2: on `t`, side 0).
    cm.vertex_memo_begin();
    let side_of = |w: u32| -> i8 {
        cm.vertex_memo(w, || {
            if surf.on_triangle(w, t) {
                2
            } else {
                let o = orient3d(a, b, c, g(w));
                i8::from(o > 0.0) - i8::from(o < 0.0)
            }
        })
    };
    let core = &cm.m;
    cm.visit_begin();
    let mut stack: Vec<u32> = Vec::new();
    // One finite tetrahedron per vertex of `t` starts the search: the
    // search crosses every face of a tetrahedron with a vertex on `t`, and
    // the finite tetrahedra around a vertex are face-connected (its link
    // is a sphere, or a disk on the hull), so it reaches the vertex's whole
    // finite star from there.
    for w in tri_vertices(surf, t, inner) {
        if let Some(x) = cm.star_find(w, |x| !core.tv[x as usize].contains(&INF)) {
            if cm.visit(x) {
                stack.push(x);
            }
        }
    }
    let mut out = Vec::new();
    while let Some(x) = stack.pop() {
        let xv = core.tv[x as usize];
        if xv[0] == DEAD || xv.contains(&INF) {
            continue;
        }
        let sides = xv.map(side_of);
        // (Not `contains`: on bytes that is a `memchr` call.)
        let touches = sides.into_iter().any(|s| s == 2);
        let sides = sides.map(|x| if x == 2 { 0 } else { x });
        let mut crossing = false;
        for (i, j) in EDGES {
            if sides[i] * sides[j] >= 0 {
                continue;
            }
            let (p, q) = (g(xv[i]), g(xv[j]));
            let s1 = orient3d(p, q, a, b);
            let s2 = orient3d(p, q, b, c);
            let s3 = orient3d(p, q, c, a);
            if (s1 > 0.0 && s2 > 0.0 && s3 > 0.0) || (s1 < 0.0 && s2 < 0.0 && s3 < 0.0) {
                crossing = true;
                out.push((ekey(xv[i], xv[j]), x));
            }
        }
        if !(touches || crossing) {
            continue;
        }
        for f in 0..4 {
            let n = core.nb[x as usize][f] >> 2;
            if cm.visit(n) {
                stack.push(n);
            }
        }
    }
    out.sort_unstable();
    out.dedup_by_key(|e| e.0);
    out
}

/// [`crossing_edges`] after the operations logged since `mark`, from
/// `cross`, its value before them: the edges those operations removed are
/// dropped, those they created are tested, and each edge is given the
/// lowest slot around it (the one the search keeps). The same list as
/// the search's, without its walk and its predicates on the edges that
/// did not change.
fn crossing_edges_after(
    cm: &Journaled<'_>,
    surf: &Surface,
    t: usize,
    cross: &[((u32, u32), u32)],
    mark: usize,
) -> Vec<((u32, u32), u32)> {
    let pts = cm.pts();
    let [a, b, c] = surf.tris[t].map(|w| pts[w as usize]);
    let mut set: Vec<(u32, u32)> = cross.iter().map(|e| e.0).collect();
    let (mut old_e, mut new_e) = (Vec::new(), Vec::new());
    let edges = |tets: &[[u32; 4]], out: &mut Vec<(u32, u32)>| {
        out.clear();
        for tv in tets {
            for (i, j) in EDGES {
                if tv[i] != INF && tv[j] != INF {
                    out.push(ekey(tv[i], tv[j]));
                }
            }
        }
        out.sort_unstable();
        out.dedup();
    };
    cm.ops_since(mark, |old, new| {
        edges(old, &mut old_e);
        edges(new, &mut new_e);
        for e in &old_e {
            if new_e.binary_search(e).is_err() {
                if let Ok(i) = set.binary_search(e) {
                    set.remove(i);
                }
            }
        }
        for &(p, q) in &new_e {
            if old_e.binary_search(&(p, q)).is_ok()
                || surf.on_triangle(p, t)
                || surf.on_triangle(q, t)
                || !place::crosses(&a, &b, &c, &pts[p as usize], &pts[q as usize])
            {
                continue;
            }
            if let Err(i) = set.binary_search(&(p, q)) {
                set.insert(i, (p, q));
            }
        }
    });
    let hint: IdMap<(u32, u32), u32> = cross.iter().copied().collect();
    let (mut tets, mut ring) = (Vec::new(), Vec::new());
    let mut out = Vec::with_capacity(set.len());
    for (p, q) in set {
        let at = hint
            .get(&(p, q))
            .copied()
            .filter(|&x| {
                cm.m.alive(x)
                    && cm.m.tv[x as usize].contains(&p)
                    && cm.m.tv[x as usize].contains(&q)
            })
            .or_else(|| cm.find_edge(p, q));
        let Some(at) = at else {
            continue;
        };
        let lowest =
            cm.m.ring_into(
                at,
                (p, q),
                (usize::MAX, true),
                |_, _| true,
                (&mut tets, &mut ring),
            )
            .and_then(|_| tets.iter().copied().min())
            .unwrap_or(at);
        out.push(((p, q), lowest));
    }
    out
}

/// Recovers input triangle `t` by flips (no crossing edge left); false when
/// they fail. `inner`: Steiner points inside `t`.
pub(crate) fn recover_facet(
    cm: &mut Journaled<'_>,
    surf: &Surface,
    t: usize,
    inner: &[u32],
    prot: &Protected,
) -> bool {
    recover_facet_within(cm, surf, t, inner, prot, (false, true))
}

/// Most consecutive steps of [`recover_facet_within`] (with
/// `stop_circles`) that may leave the number of crossing edges above the
/// least reached so far.
const FACET_STALL: usize = 8;

/// [`recover_facet`]; after each step the crossing edges are updated
/// from the operations it made ([`crossing_edges_after`], when the mesh
/// logs them) rather than searched again. With `stop_circles`, the flips
/// are given up (false)
/// once [`FACET_STALL`] consecutive steps have not brought the number of
/// edges crossing `t` below the least reached so far: each step removes
/// one crossing edge, and when its ring triangulation creates as many
/// crossing chords as it removes the flips go in a circle (on long thin
/// triangles of coplanar fans, hundreds of steps at a constant count, each
/// with a search of the crossing edges), while the triangle is split
/// anyway when they fail.
pub(crate) fn recover_facet_within(
    cm: &mut Journaled<'_>,
    surf: &Surface,
    t: usize,
    inner: &[u32],
    prot: &Protected,
    (stop_circles, blockers): (bool, bool),
) -> bool {
    // A triangle that is a face of the mesh is recovered (no edge of a
    // tetrahedralization crosses one of its faces): the search of
    // crossing edges would find none.
    let [a, b, c] = surf.tris[t];
    if cm.find_face(a, b, c).is_some() {
        debug_assert!(crossing_edges(cm, surf, t, inner).is_empty());
        return true;
    }
    let mut cross = crossing_edges(cm, surf, t, inner);
    let cap = 16 + 4 * cross.len();
    let tv = surf.tris[t];
    let (mut least, mut stalled) = (cross.len(), 0);
    for _ in 0..cap {
        if cross.is_empty() {
            return true;
        }
        if stop_circles {
            if cross.len() < least {
                (least, stalled) = (cross.len(), 0);
            } else if stalled >= FACET_STALL {
                return false;
            } else {
                stalled += 1;
            }
        }
        let [ta, tb, tc] = tv.map(|w| cm.pts()[w as usize]);
        // New ring chords crossing `t` cost one each.
        let cost = |pts: &[[f64; 3]], a: u32, b: u32| -> i64 {
            let on = |w: u32| surf.on_triangle(w, t);
            i64::from(
                !on(a)
                    && !on(b)
                    && place::crosses(&ta, &tb, &tc, &pts[a as usize], &pts[b as usize]),
            )
        };
        let mut progress = false;
        let mark = cm.log_mark();
        for &((p, q), x) in &cross {
            if prot.edge(p, q) {
                continue;
            }
            if cm.remove_edge(x, p, q, &zero, &cost).is_some() {
                progress = true;
                break;
            }
        }
        if !progress {
            for &((p, q), _) in &cross {
                if remove_edge_deep(
                    cm,
                    (p, q),
                    (DEPTH, blockers),
                    prot,
                    Guide::Costs(&zero, &cost),
                    &mut { WORK },
                ) {
                    progress = true;
                    break;
                }
            }
        }
        if !progress {
            return false;
        }
        cross = if cm.logging() {
            crossing_edges_after(cm, surf, t, &cross, mark)
        } else {
            crossing_edges(cm, surf, t, inner)
        };
        #[cfg(debug_assertions)]
        if cm.logging() {
            debug_assert_eq!(cross, crossing_edges(cm, surf, t, inner));
        }
    }
    cross.is_empty()
}

/// Removes the mesh edges that pierce triangle `t` without crossing it:
/// both ends off `t` and every vertex of their ring on it, next to the
/// edges `holes` around its uncovered part. With Steiner points rounded
/// off `t`'s plane on a thin triangle, the ring (a skew polygon of points
/// on `t`, here two on each long side) can dip across the plane just past
/// a side, so the edge through it meets the plane outside `t`: no edge
/// crosses `t`, and still the part of `t` inside the ring has no face on
/// it. Edge removal (any valid triangulation of the ring) makes the ring's
/// faces, all on `t`. Protected edges are kept (a face on an input
/// triangle has protected edges). True when an edge was removed.
pub(crate) fn remove_piercing(
    cm: &mut Journaled<'_>,
    surf: &Surface,
    t: usize,
    holes: &[(u32, u32)],
    prot: &Protected,
) -> bool {
    let on = |w: u32| w != INF && surf.on_triangle(w, t);
    let mut cand: Vec<(u32, u32)> = Vec::new();
    for &(u, v) in holes {
        let Some((tets, _)) = cm.find_edge(u, v).and_then(|x| cm.edge_ring(x, u, v)) else {
            continue;
        };
        for &c in &tets {
            let tv = cm.m.tv[c as usize];
            let mut pq = tv.iter().copied().filter(|&w| w != u && w != v);
            if let (Some(p), Some(q)) = (pq.next(), pq.next()) {
                if !on(p) && !on(q) && p != INF && q != INF {
                    cand.push(ekey(p, q));
                }
            }
        }
    }
    cand.sort_unstable();
    cand.dedup();
    let mut removed = false;
    for (p, q) in cand {
        if prot.edge(p, q) {
            continue;
        }
        let Some(x) = cm.find_edge(p, q) else {
            continue;
        };
        let all_on = |_: &[[f64; 3]], ring: &[u32]| ring.iter().all(|&w| on(w)).then_some(i64::MAX);
        removed |= cm
            .remove_edge_limited(x, p, q, (&zero, &zero2), all_on)
            .is_some();
    }
    removed
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_segment_meets_a_face_through_its_interior_edges_and_corners() {
        // Face 0 1 2 in the plane z = 0; segments 3-4 (through its
        // interior), 5-6 (through edge 0 1), 7-8 (through corner 0), 9-10
        // (beside it), 3-9 (not crossing the plane) and 0-3 (at a corner).
        let pts = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.25, 0.25, 1.0],
            [0.25, 0.25, -1.0],
            [0.5, 0.0, 1.0],
            [0.5, 0.0, -1.0],
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -1.0],
            [2.0, 2.0, 1.0],
            [2.0, 2.0, -1.0],
        ];
        let f = [0, 1, 2];
        let memo = SegMemo::default();
        let meets = |pts: &[[f64; 3]], s, f| SegTest::new(pts, s, &memo).meets(pts, f);
        assert_eq!(meets(&pts, (3, 4), f), 1);
        assert_eq!(meets(&pts, (4, 3), f), 1);
        assert_eq!(meets(&pts, (5, 6), f), 1);
        assert_eq!(meets(&pts, (7, 8), f), 1);
        assert_eq!(meets(&pts, (9, 10), f), 0);
        assert_eq!(meets(&pts, (3, 9), f), 0);
        assert_eq!(meets(&pts, (0, 3), f), 0);
        assert_eq!(meets(&pts, (3, 4), [0, 1, INF]), 0);
    }

    /// Test point sets: `n` random points in the unit cube (from `seed`),
    /// and `rings` cocircular rings of 16 points, `gap` apart along z (a
    /// degenerate Delaunay tetrahedralization, as of a tube).
    fn random_and_rings(mut seed: u64, n: usize, rings: usize, gap: f64) -> [Vec<[f64; 3]>; 2] {
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let random = (0..n).map(|_| [rnd(), rnd(), rnd()]).collect();
        let tube = (0..16 * rings)
            .map(|k| {
                let a = std::f64::consts::PI * (k % 16) as f64 / 8.0;
                [a.cos(), a.sin(), gap * (k / 16) as f64]
            })
            .collect();
        [random, tube]
    }

    /// A face's 2-3 flip is valid exactly when no edge of it blocks
    /// ([`flip23_blocking`]), on a random and a degenerate (cocircular
    /// rings) Delaunay tetrahedralization.
    #[test]
    fn a_face_flip_is_blocked_exactly_by_its_blocking_edges() {
        for pts in random_and_rings(99, 80, 3, 1.0) {
            let cm = Journaled::new(crate::tet::Delaunay3::from_points(&pts).unwrap());
            let (mut valid, mut blocked) = (0, 0);
            for t in cm.m.live_slots() {
                for f in 0..4 {
                    let Some(blocks) = flip23_blocking(&cm, t, f) else {
                        continue;
                    };
                    let ok = cm.flip23_plan(t, f).is_some();
                    assert_eq!(ok, blocks.iter().all(|&b| !b), "cell {t} face {f}");
                    if ok {
                        valid += 1;
                    } else {
                        blocked += 1;
                    }
                }
            }
            assert!(valid > 0 && blocked > 0, "{valid} {blocked}");
        }
    }

    /// Every ghost cell's hull face has every point on its inner side
    /// (non-negative `orient3d`) and the finite cell behind it strictly: the
    /// ghosts still close a convex hull.
    fn ghosts_close_the_hull(cm: &Journaled<'_>, pts: &[[f64; 3]]) {
        for t in cm.m.live_slots() {
            let tv = cm.m.tv[t as usize];
            if tv[3] != INF {
                continue;
            }
            let [a, b, c] = [tv[0], tv[1], tv[2]].map(|w| &pts[w as usize]);
            for p in pts {
                assert!(orient3d(a, b, c, p) >= 0.0, "ghost {tv:?} faces in");
            }
            let nv = cm.m.tv[cm.m.across(t, 3) as usize];
            let w = nv.iter().find(|w| !tv.contains(w)).unwrap();
            assert!(orient3d(a, b, c, &pts[*w as usize]) > 0.0);
        }
    }

    /// The cone over a missing segment's crossed cells, on random points
    /// and on a tube's two cospherical end circles (a degenerate Delaunay
    /// tetrahedralization; the segments between two vertices of one circle
    /// lie on a flat hull facet and take the cone over the cells around
    /// the hull edges they cross, ghosts included): each call either
    /// leaves the mesh unchanged or makes the segment an edge, the mesh
    /// valid ([`crate::tet::dmesh::DomainMesh::check`]), the ghosts closing
    /// the convex hull and the protected items kept.
    #[test]
    fn segment_cones_keep_the_mesh_valid() {
        for pts in random_and_rings(12345, 60, 2, 3.0) {
            let dt = crate::tet::Delaunay3::from_points(&pts).unwrap();
            let mut cm = Journaled::new(dt);
            let n = pts.len() as u32;
            let (mut done, mut refused, mut on_hull) = (0, 0, 0);
            for u in 0..n {
                for v in (u + 1..n).step_by(3) {
                    if cm.find_edge(u, v).is_some() {
                        continue;
                    }
                    // Protected: an edge and a face of some cell at `u`
                    // away from `v`.
                    let mut prot = Protected::default();
                    let t = cm.star(u).into_iter().find(|&t| {
                        let tv = cm.m.tv[t as usize];
                        !tv.contains(&INF) && !tv.contains(&v)
                    });
                    if let Some(t) = t {
                        let tv = cm.m.tv[t as usize];
                        let f = (0..4).find(|&f| tv[f] != u).unwrap_or(0);
                        prot.add_face(face(tv, f));
                    }
                    let before = cm.m.live_slots().count();
                    let kept: Vec<[u32; 3]> = prot.faces.iter().copied().collect();
                    let flat = hull_channel(&cm, u, v).is_some();
                    if cone_segment_in(&mut cm, u, v, &prot, flat) {
                        done += 1;
                        on_hull += usize::from(flat);
                        ghosts_close_the_hull(&cm, &pts);
                        assert!(cm.find_edge(u, v).is_some());
                        for f in &kept {
                            assert!(cm.find_face(f[0], f[1], f[2]).is_some(), "{f:?} lost");
                        }
                        cm.m.check(&pts).unwrap();
                    } else {
                        refused += 1;
                        assert_eq!(cm.m.live_slots().count(), before);
                    }
                }
            }
            cm.m.check(&pts).unwrap();
            assert!(done > 0, "no cone applied ({refused} refused)");
            // The tube's end circles: cones on its flat hull facets.
            assert!(
                pts.len() != 32 || on_hull > 0,
                "no cone on a hull facet ({done} made)"
            );
        }
    }
}
