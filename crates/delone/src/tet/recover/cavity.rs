//! Surface preservation (`-Y`) by cavity retriangulation, in the spirit of
//! Si & Gärtner (2005): missing input edges and triangles are recovered
//! without any Steiner point on the surface, on the flipped mesh
//! ([`Journaled`]) of the last constrained round.
//!
//! **Missing triangle** `T = a b c` whose three edges are mesh edges: the
//! cavity `C` is the set of tetrahedra having an edge that crosses the
//! interior of `T` (exact [`place::crosses`]). Because `T`'s edges are mesh
//! edges and no vertex lies inside `T` (every Steiner point of `-Y` is off
//! the surface), a tetrahedron meets the interior of `T` iff it has such an
//! edge, the plane section of every cavity tetrahedron lies inside `T`, and
//! every boundary face of `C` has all its vertices on one closed side of
//! `T`'s plane. So `T` splits `C` into an upper and a lower polyhedron, each
//! bounded by its boundary faces of `C` and by `T` (a face whose vertices are
//! on both sides makes the attempt fail; nothing is assumed).
//!
//! **Missing edge** `a b`: the cavity is the set of tetrahedra meeting the
//! open segment (a superset is harmless), and the goal is a
//! retriangulation in which `a b` is an edge.
//!
//! **Filling a polyhedron** from its boundary faces, tried in order:
//! 1. the cone from one of its vertices `v` (no new point), when `v` sees
//!    every boundary face not incident to it strictly from inside — for an
//!    edge cavity only the ends `a`, `b`, whose cone contains `a b`;
//! 2. the cone from a new point `p` strictly inside the kernel (every
//!    boundary face seen strictly from inside, exact `orient3d`), found in
//!    floating point by relaxation towards the half-spaces with a shrinking
//!    margin (Agmon–Motzkin) and accepted only after the exact test. `p` is
//!    then strictly inside the polyhedron, so on no cavity face, and it is
//!    also tested exactly against every input triangle near it (closed
//!    triangle, `orient3d` and `orient2d`): a Steiner point never lies on
//!    the surface;
//! 3. otherwise the polyhedron grows by the tetrahedra behind the boundary
//!    faces that the best point found does not see (never across an input
//!    face, never through a ghost, and for a triangle cavity only by
//!    tetrahedra on the same closed side of `T`'s plane), at most
//!    [`MAX_GROW`] steps and [`MAX_CAVITY`] tetrahedra — the bounded form of
//!    cavity expansion; when nothing is left to try the item stays missing
//!    and the caller falls back to its interior-point rounds, then to the
//!    fallback that always applies (below).
//!
//! **Validation** before anything changes: every new tetrahedron strictly
//! positive (exact); the oriented faces of the new tetrahedra, as a chain,
//! have exactly the removed set's boundary as boundary (each inner face used
//! once in each orientation, each boundary face once in its own
//! orientation) — with all tetrahedra positive, the winding number of that
//! boundary then says every point of the removed region is covered exactly
//! once, so the new tetrahedra tile it; every vertex and every protected
//! edge and face of the removed tetrahedra survives.
//!
//! Everything is bounded: [`PASSES`] passes over the missing items (the
//! first without new points), at most two new points per item per pass,
//! the Steiner budget, and [`MAX_FAILED_CALLS`] unfinished calls per
//! recovery: then `-Y` fails with [`RecoverError::Unrecovered`] naming
//! what is left. After the first unfinished call the fallback that always
//! applies (below) is tried at once ([`State::fallback_once`]); the
//! interior-point rounds and the next calls run only when it fails. After an
//! unfinished call the interior points of the next round are placed only
//! at the items that call left missing ([`State::fallback_targets`]).
//!
//! **Attempts.** Each call runs up to two attempts on copies of the mesh
//! ([`ATTEMPTS`]): first with every vertex kept, then allowing a cavity
//! to swallow interior Steiner points (those of earlier rounds and the
//! attempt's own kernel points: vertices from [`State::n_fixed`] on,
//! unused ones dropped at the end). Keeping them keeps cavities small and
//! the kernels those points make (cgal_couplingdown needs it); swallowing
//! frees a cavity from points the Delaunay rounds put in the way (the
//! generated gear of 40 teeth needs it). The first attempt that recovers
//! everything wins; otherwise what the first attempt left missing guides
//! the next round's interior points. While the fallback is untried, each
//! attempt is bounded by the work of its cavity searches
//! ([`VISITS_PER_CELL`]): on tubes and turned gears an attempt that fails
//! takes 10–100× the fallback's time. Within an attempt a patch
//! known to fail on the unchanged mesh is not computed again ([`Memo`]:
//! the patch of every missing edge of one patch is the same cavity).
//!
//! **Missing edges on flat parts of the convex hull** (the `hull`
//! submodule) are first recovered by 2D flips in their plane: the hull
//! faces there form a planar triangulation, in which some edge crossing
//! a missing segment always has a strictly convex quadrilateral; its flip
//! replaces the tetrahedra around it by a cone from a vertex, a kernel
//! point, or a point just inside the hull above its middle (which sees
//! every face of that ring strictly, so moving it close enough is
//! accepted by the exact validation).
//!
//! **Missing edges come with their triangles** (the `patch` submodule):
//! when flips cannot recover an input edge, the connected set of missing
//! input triangles around it is recovered at once, the two sides of that
//! surface patch being filled like the two sides of one triangle; only
//! when that fails is the edge's own cavity tried (cones from its ends,
//! or a kernel point left to the flips of the next pass).
//!
//! **Cavity expansion without the failure Diazzi et al. (2023) describe.**
//! Naive expansion adds the tetrahedra behind faces that block a fill
//! and retries until a fill exists; it can swallow input faces already
//! recovered, cross to the other side of the missing facet, or grow
//! without end. Here growth never crosses a protected (already recovered)
//! face, a ghost, or — for a single triangle — the triangle's plane; a
//! patch's cavity already holds every tetrahedron meeting the patch, so
//! a tetrahedron added beside it cannot meet the patch; growth is bounded
//! by [`MAX_GROW`] steps and [`MAX_CAVITY`] tetrahedra; and nothing is
//! applied unless the exact validation above passes, so a bad growth
//! costs an attempt, never the mesh.
//!
//! **The fallback that always applies** (the `pull` submodule): when the
//! cavities and the interior-point rounds give up
//! ([`RecoverError::Unrecovered`]), the surface is recovered again
//! without preservation (Steiner points on its edges and triangles, which
//! always succeeds on a closed surface free of self-intersections), and
//! every surface Steiner point is then removed from the surface: its star
//! is split by the surface into wedges, the refinement of each input
//! triangle around it is retriangulated without it (ear clipping), and
//! each wedge is refilled by the cone from a new point just inside it
//! (exact `orient3d`: a point near the removed one sees every face of
//! the wedge strictly, by continuity; the point farthest from every face
//! is taken, and thin wedges of nearly flat tetrahedra are entered along
//! their tangent cone), else by a cone from a wedge vertex or a kernel
//! point of the grown wedge; a point that still fails is removed together
//! with its nearest surface points (a cluster). One surface point fewer
//! per step, none added on the surface: it terminates with every input
//! triangle a single face. Only what no removal can validate exactly
//! (rounding of inexact surface points) is reported as
//! [`RecoverError::Unrecovered`]; on the corpus nothing is.
//!
//! The face and edge lookups used to decide what is missing search a
//! vertex's star, not an edge ring, so edges with many tetrahedra around
//! them (above the flip code's ring cap) are not mistaken for missing.

use super::cdt::{self, Protected};
use super::place;
use super::{FacesOn, RecoverError, State};
use crate::geom::ids::{IdMap, IdSet};
use crate::geom::vec3::{cross, dot, sub};
use crate::tet::dmesh::journal::Journaled;
use crate::tet::local::face;
use crate::tet::local::{ekey, fkey};
use crate::tet::local::{DEAD, INF};
use delone_predicates::{orient2d, orient3d};
use std::cell::RefCell;

mod dfill;
mod hull;
mod patch;
mod prune;
mod pull;

type P = [f64; 3];

/// The attempts of [`State::preserve_by_cavities`], in order: whether
/// cavities may swallow interior Steiner points of earlier rounds.
/// Neither choice is better on every model: swallowing frees a cavity
/// from points the Delaunay rounds put in the way (the generated 40-tooth
/// gear), keeping them keeps cavities small and the kernels those points
/// make (cgal_couplingdown).
const ATTEMPTS: [bool; 2] = [false, true];
/// Passes over the missing edges and triangles.
const PASSES: usize = 24;
/// Unfinished calls of [`State::preserve_by_cavities`] after which the
/// interior-point rounds give up ([`RecoverError::Unrecovered`]); the
/// fallback that always applies runs after the first
/// ([`State::fallback_once`]), and when it fails the rounds go on. On the corpus and the
/// generated hard models a successful call is the first, second or third.
const MAX_FAILED_CALLS: usize = 3;
/// While the fallback that always applies is untried, an attempt of
/// [`State::preserve_by_cavities`] stops once its cavity searches have
/// found this many tetrahedra per tetrahedron of the mesh
/// ([`State::cavity_work`]); the call then ends unfinished (the other
/// attempt is not tried) and the fallback runs. Attempts that fail on
/// tubes, turned gears and flanges find 70–2,300 per tetrahedron, in up to
/// 30 s where the fallback succeeds in 0.1–9 s; attempts that succeed find
/// up to 38 (stacked plates), but there the fallback, whose first run
/// cones flat hull facets, is as fast. With 8 every corpus model and each
/// of 86 generated CAD models (`cad_shapes.py` seeds 21, 22, 31, 32, 500,
/// 501 and 600–602, `hard_surfaces.py`) still recovers, in 7–11% less time
/// summed than with 24. When the fallback fails, the later calls have no
/// such bound.
const VISITS_PER_CELL: u64 = 8;
/// Most growth steps of a cavity (each adds every tetrahedron behind a
/// face the best point found does not see).
const MAX_GROW: usize = 8;
/// Most whole layers a side grows by in its cones-only attempt.
const MAX_LAYERS: usize = 2;
/// Largest cavity grown by whole layers (small sides only: the layers
/// are for Schönhardt-like prisms of a few tetrahedra, and cost time on
/// large failing sides).
const LAYER_CAVITY: usize = 24;
/// Most tetrahedra in a grown cavity.
const MAX_CAVITY: usize = 128;

/// The items a replacement must keep: the protected edges and faces,
/// and every vertex below `n_fixed` (see [`State::preserve_attempt`]).
#[derive(Debug, Default)]
struct Guard {
    prot: Protected,
    n_fixed: usize,
}

impl std::ops::Deref for Guard {
    type Target = Protected;
    fn deref(&self) -> &Protected {
        &self.prot
    }
}

impl std::ops::DerefMut for Guard {
    fn deref_mut(&mut self) -> &mut Protected {
        &mut self.prot
    }
}

/// Patch attempts known to fail on the mesh as it is: keyed by the
/// Steiner flag and the patch's sorted face keys, valid while the mesh's
/// count of touched faces ([`Journaled::touched_len`], which every
/// replacement increases) stays at `stamp`. A patch reached again from
/// another of its missing edges, on an unchanged mesh, is not computed
/// again (the same cavity, the same failure).
#[derive(Debug, Default)]
struct Memo {
    stamp: usize,
    failed: IdSet<(bool, Vec<[u32; 3]>)>,
    /// Input edges whose flips on the convex hull failed.
    hull_failed: IdSet<(u32, u32)>,
}

impl Memo {
    /// Forgets everything when `cm` changed since the last call.
    fn sync(&mut self, cm: &Journaled<'_>) {
        if cm.touched_len() != self.stamp {
            self.stamp = cm.touched_len();
            self.failed.clear();
            self.hull_failed.clear();
        }
    }
}

/// A polyhedron being filled: its boundary faces, each oriented inward
/// (`[f, x]` positive for `x` inside), with the removed tetrahedron owning
/// it and its local index (`DEAD` for the missing triangle itself).
#[derive(Debug, Clone, Default)]
struct Region {
    faces: Vec<([u32; 3], u32, usize)>,
}

impl Region {
    fn tris(&self) -> Vec<[u32; 3]> {
        self.faces.iter().map(|f| f.0).collect()
    }

    fn vertices(&self) -> Vec<u32> {
        let mut v: Vec<u32> = self.faces.iter().flat_map(|f| f.0).collect();
        v.sort_unstable();
        v.dedup();
        v
    }
}

/// `f` rotated so that its least vertex comes first (same orientation).
fn okey(f: [u32; 3]) -> [u32; 3] {
    let m = (0..3).min_by_key(|&i| f[i]).unwrap_or(0);
    [f[m], f[(m + 1) % 3], f[(m + 2) % 3]]
}

fn rev(f: [u32; 3]) -> [u32; 3] {
    okey([f[0], f[2], f[1]])
}

/// Exact: `x` sees face `f` (inward oriented) strictly from inside.
fn sees(pts: &[P], f: [u32; 3], x: &P) -> bool {
    let [a, b, c] = f.map(|w| &pts[w as usize]);
    orient3d(a, b, c, x) < 0.0
}

/// Boundary faces of the tetrahedron set `set` (sorted ids), inward.
fn boundary_of(cm: &Journaled<'_>, set: &[u32]) -> Region {
    let c = &cm.m;
    let mut r = Region::default();
    for &t in set {
        let tv = c.tv[t as usize];
        for f in 0..4 {
            let n = c.nb[t as usize][f] >> 2;
            if set.binary_search(&n).is_err() {
                r.faces.push((face(tv, f), t, f));
            }
        }
    }
    r
}

/// A point strictly inside the kernel of the polyhedron bounded by the
/// inward faces `faces` (exactly checked), or `None` with the best point
/// tried.
fn kernel_point(pts: &[P], faces: &[[u32; 3]]) -> (Option<P>, P) {
    let mut planes: Vec<(P, P)> = Vec::with_capacity(faces.len());
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    let mut centre = [0.0; 3];
    let mut n: f64 = 0.0;
    for f in faces {
        let [x, y, z] = f.map(|w| pts[w as usize]);
        let nv = cross(&sub(&y, &x), &sub(&z, &x));
        let l = dot(&nv, &nv).sqrt();
        for p in [x, y, z] {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
                centre[k] += p[k];
            }
            n += 1.0;
        }
        if l > 0.0 && l.is_finite() {
            planes.push((x, nv.map(|c| c / l)));
        }
    }
    let centre = centre.map(|c| c / n.max(1.0));
    let d = sub(&hi, &lo);
    let diam = dot(&d, &d).sqrt();
    let ok = |p: &P| faces.iter().all(|&f| sees(pts, f, p));
    let slack = |p: &P| {
        planes
            .iter()
            .map(|(x, nv)| dot(&sub(p, x), nv))
            .enumerate()
            .min_by(|a, b| a.1.total_cmp(&b.1))
    };
    let mut best = centre;
    let mut best_s = slack(&centre).map_or(f64::NEG_INFINITY, |s| s.1);
    if planes.len() != faces.len() || diam == 0.0 {
        return (None, best);
    }
    let iters = (2 * planes.len()).clamp(32, 256);
    for round in 0..6 {
        let margin = diam * 0.1 / f64::from(1u32 << (2 * round));
        let mut q = centre;
        for _ in 0..iters {
            let Some((i, s)) = slack(&q) else { break };
            if s > best_s {
                best_s = s;
                best = q;
            }
            if s >= margin {
                break;
            }
            let nv = planes[i].1;
            for k in 0..3 {
                q[k] += 1.5 * (margin - s) * nv[k];
            }
        }
        if let Some((_, s)) = slack(&q) {
            if s > best_s {
                best_s = s;
                best = q;
            }
        }
        if ok(&q) {
            return (Some(q), q);
        }
    }
    if ok(&best) {
        return (Some(best), best);
    }
    (None, best)
}

/// Iterations of [`deepest_point`]: the ellipsoid's volume shrinks by
/// `exp(-1/8)` per step, so 480 steps shrink its radius by about 1e-9.
const ELLIPSOID_STEPS: usize = 480;

/// The point of the ball of radius `radius` around `centre` farthest
/// inside the half-spaces `n·(x - a) > 0` of `planes` (`(a, n)`, `n`
/// unit): it maximises the smallest clearance `min n·(x - a)`, a concave
/// function, by the central-cut ellipsoid method (each step cuts the
/// ellipsoid through its centre by a supergradient, or by the ball when
/// the centre is outside it). `Some((point, clearance))` for the best
/// centre visited (floating; the caller checks exactly), `None` when
/// there is no plane or the radius is not positive and finite.
pub(super) fn deepest_point(planes: &[(P, P)], centre: &P, radius: f64) -> Option<(P, f64)> {
    if planes.is_empty() || !(radius > 0.0 && radius.is_finite()) {
        return None;
    }
    let clearance = |x: &P| {
        planes
            .iter()
            .enumerate()
            .map(|(i, (a, n))| (i, dot(n, &sub(x, a))))
            .min_by(|a, b| a.1.total_cmp(&b.1))
    };
    // The ellipsoid {x : (x - c)ᵀ Q⁻¹ (x - c) <= 1}, first the ball of
    // radius `radius` (scaled by sqrt 3 to hold the whole ball's box).
    let mut c = *centre;
    let r2 = 3.0 * radius * radius;
    let mut q = [[r2, 0.0, 0.0], [0.0, r2, 0.0], [0.0, 0.0, r2]];
    let mut best: Option<(P, f64)> = None;
    let dim = 3.0;
    for _ in 0..ELLIPSOID_STEPS {
        let off = sub(&c, centre);
        let out = dot(&off, &off) > radius * radius;
        // The cut keeps {x : g·(x - c) <= 0}.
        let g = if out {
            off
        } else {
            let (i, s) = clearance(&c)?;
            if best.is_none_or(|b| s > b.1) {
                best = Some((c, s));
            }
            planes[i].1.map(|x| -x)
        };
        let qg = [0, 1, 2].map(|k| dot(&q[k], &g));
        let gqg = dot(&g, &qg);
        if !(gqg > 0.0 && gqg.is_finite()) {
            break;
        }
        let b = qg.map(|x| x / gqg.sqrt());
        let step = 1.0 / (dim + 1.0);
        let nc = [0, 1, 2].map(|k| c[k] - step * b[k]);
        if nc == c {
            break;
        }
        c = nc;
        let f = dim * dim / (dim * dim - 1.0);
        let w = 2.0 / (dim + 1.0);
        for i in 0..3 {
            for j in 0..3 {
                q[i][j] = f * (q[i][j] - w * b[i] * b[j]);
            }
        }
    }
    best
}

/// The tetrahedra filling `faces` as the cone from vertex `v` (every face
/// not incident to `v` seen strictly), or `None`.
fn cone_from(pts: &[P], faces: &[[u32; 3]], v: u32) -> Option<Vec<[u32; 4]>> {
    let p = &pts[v as usize];
    let mut out = Vec::new();
    for &f in faces {
        if f.contains(&v) {
            continue;
        }
        if !sees(pts, f, p) {
            return None;
        }
        out.push([f[0], f[1], f[2], v]);
    }
    Some(out)
}

/// How a region was filled.
struct Fill {
    tets: Vec<[u32; 4]>,
    /// The new point (id `tets` use), if any.
    point: Option<P>,
}

/// Fills `faces` by a cone from one of `apexes`, else (when `steiner`) from
/// a new kernel point with id `new_id`. `Err(best point)` otherwise.
fn fill(
    pts: &[P],
    faces: &[[u32; 3]],
    apexes: &[u32],
    steiner: bool,
    new_id: u32,
) -> Result<Fill, P> {
    for &v in apexes {
        if let Some(tets) = cone_from(pts, faces, v) {
            return Ok(Fill { tets, point: None });
        }
    }
    let (p, best) = kernel_point(pts, faces);
    match p {
        Some(p) if steiner => Ok(Fill {
            tets: faces.iter().map(|f| [f[0], f[1], f[2], new_id]).collect(),
            point: Some(p),
        }),
        _ => Err(best),
    }
}

/// Fills one side `reg` of a cavity (removed set `set`, both grown in
/// place on success): first cones from its vertices only, growing towards
/// the faces the best point found does not see, so no point is added
/// where a larger cavity has a cone; then, with `steiner`, from the
/// original region again with kernel points (new id `id`).
fn fill_side(
    cm: &Journaled<'_>,
    reg: &mut Region,
    set: &mut Vec<u32>,
    side: Option<(&[P; 3], f64)>,
    prot: &Protected,
    steiner: bool,
    id: u32,
) -> Option<Fill> {
    let none: IdSet<u32> = IdSet::default();
    for with_point in [false, true] {
        if with_point && !steiner {
            break;
        }
        let (mut r2, mut s2) = (reg.clone(), set.clone());
        let mut layers = 0;
        for _ in 0..=MAX_GROW {
            match fill(cm.pts(), &r2.tris(), &r2.vertices(), with_point, id) {
                Ok(f) => {
                    *reg = r2;
                    *set = s2;
                    return Some(f);
                }
                Err(best) => {
                    // Cones only: when the best point sees every face (a
                    // Schönhardt-like side), grow by a whole layer — a
                    // vertex behind it may see the larger region.
                    if !grow(cm, &mut r2, &mut s2, &none, Some(&best), side, prot)
                        && (with_point
                            || layers >= MAX_LAYERS
                            || s2.len() > LAYER_CAVITY
                            || !grow(cm, &mut r2, &mut s2, &none, None, side, prot))
                    {
                        break;
                    }
                    if !with_point {
                        layers += 1;
                    }
                }
            }
        }
    }
    None
}

/// Exact validation of replacing the tetrahedra `old` (sorted) by `new`
/// (see the module documentation); vertices from `prot.n_fixed` on
/// (interior Steiner points of earlier rounds) may disappear.
fn valid_replacement(
    cm: &Journaled<'_>,
    pts: &[P],
    old: &[u32],
    new: &[[u32; 4]],
    prot: &Guard,
) -> bool {
    if new
        .iter()
        .any(|tv| tv.iter().any(|&w| w == INF || w as usize >= pts.len()))
    {
        return false;
    }
    all_positive(pts, new)
        && fills(cm, old, new)
            .is_some_and(|parts| keeps_guarded(cm, old, prot, &parts, &IdSet::default()))
}

/// Whether every tetrahedron of `new` is positively oriented on `pts`.
fn all_positive(pts: &[P], new: &[[u32; 4]]) -> bool {
    new.iter().all(|tv| {
        let g = |i: usize| &pts[tv[i] as usize];
        orient3d(g(0), g(1), g(2), g(3)) < 0.0
    })
}

/// Whether replacing the tetrahedra `old` by tetrahedra with the parts
/// `new` keeps every vertex below `prot.n_fixed` and every protected edge,
/// and every protected face not in `spare`.
fn keeps_guarded(
    cm: &Journaled<'_>,
    old: &[u32],
    prot: &Guard,
    new: &NewParts,
    spare: &IdSet<[u32; 3]>,
) -> bool {
    old.iter().all(|&t| {
        let tv = cm.m.tv[t as usize];
        (0..4).all(|i| (tv[i] as usize) >= prot.n_fixed || new.verts.contains(&tv[i]))
            && (0..4).all(|i| {
                (i + 1..4).all(|j| {
                    let e = ekey(tv[i], tv[j]);
                    !prot.edges.contains(&e) || new.edges.contains(&e)
                })
            })
            && (0..4).all(|f| {
                let k = fkey(face(tv, f));
                !prot.faces.contains(&k) || spare.contains(&k) || new.faces.contains(&k)
            })
    })
}

/// Finite live tetrahedra around vertex `w` (ghosts excluded).
fn finite_star(cm: &Journaled<'_>, w: u32) -> Vec<u32> {
    let c = &cm.m;
    cm.star(w)
        .into_iter()
        .filter(|&t| {
            let tv = c.tv[t as usize];
            tv[0] != DEAD && !tv.contains(&INF)
        })
        .collect()
}

/// True when closed segment `p q` may meet closed triangle `a b c`
/// (exact signs; coplanar configurations count as meeting).
fn seg_meets_tri(a: &P, b: &P, c: &P, p: &P, q: &P) -> bool {
    let op = orient3d(a, b, c, p);
    let oq = orient3d(a, b, c, q);
    if (op > 0.0 && oq > 0.0) || (op < 0.0 && oq < 0.0) {
        return false;
    }
    if op == 0.0 && oq == 0.0 {
        return true;
    }
    let s1 = orient3d(p, q, a, b);
    let s2 = orient3d(p, q, b, c);
    let s3 = orient3d(p, q, c, a);
    (s1 >= 0.0 && s2 >= 0.0 && s3 >= 0.0) || (s1 <= 0.0 && s2 <= 0.0 && s3 <= 0.0)
}

/// The tetrahedra meeting the open segment `a b` (a superset; sorted).
/// Each face is tested once (a face is shared by two tetrahedra).
fn segment_cavity(cm: &Journaled<'_>, a: u32, b: u32) -> Vec<u32> {
    let c = &cm.m;
    let pts = cm.pts();
    let (pa, pb) = (pts[a as usize], pts[b as usize]);
    let met: RefCell<IdMap<[u32; 3], bool>> = RefCell::default();
    let meets = |t: u32| -> bool {
        let tv = c.tv[t as usize];
        if tv[0] == DEAD || tv.contains(&INF) {
            return false;
        }
        for (s, e) in [(a, b), (b, a)] {
            if let Some(i) = tv.iter().position(|&w| w == s) {
                // In the closed cone at `s` towards `e`.
                let pe = &pts[e as usize];
                return (0..4).filter(|&f| f != i).all(|f| {
                    let [x, y, z] = face(tv, f).map(|w| &pts[w as usize]);
                    orient3d(x, y, z, pe) <= 0.0
                });
            }
        }
        (0..4).any(|f| {
            let fv = face(tv, f);
            *met.borrow_mut().entry(fkey(fv)).or_insert_with(|| {
                let [x, y, z] = fv.map(|w| &pts[w as usize]);
                seg_meets_tri(x, y, z, &pa, &pb)
            })
        })
    };
    flood(cm, &[a], meets)
}

/// The tetrahedra with an edge crossing the interior of triangle `tri`
/// (sorted). The side of `tri`'s plane of each vertex is computed once,
/// and an edge is tested only when its ends are strictly on both sides.
fn facet_cavity(cm: &Journaled<'_>, tri: [u32; 3]) -> Vec<u32> {
    let c = &cm.m;
    let pts = cm.pts();
    let [a, b, cc] = tri.map(|w| &pts[w as usize]);
    let sign: RefCell<IdMap<u32, i8>> = RefCell::default();
    let side = |w: u32| -> i8 {
        if tri.contains(&w) {
            return 0;
        }
        *sign.borrow_mut().entry(w).or_insert_with(|| {
            let o = orient3d(a, b, cc, &pts[w as usize]);
            i8::from(o > 0.0) - i8::from(o < 0.0)
        })
    };
    let crossed: RefCell<IdMap<(u32, u32), bool>> = RefCell::default();
    let crossing = |t: u32| -> bool {
        let tv = c.tv[t as usize];
        if tv[0] == DEAD || tv.contains(&INF) {
            return false;
        }
        crate::tet::local::EDGES.iter().any(|&(i, j)| {
            let (p, q) = (tv[i], tv[j]);
            if side(p) * side(q) >= 0 {
                return false;
            }
            *crossed
                .borrow_mut()
                .entry(ekey(p, q))
                .or_insert_with(|| place::crosses(a, b, cc, &pts[p as usize], &pts[q as usize]))
        })
    };
    flood(cm, &tri, crossing)
}

/// The tetrahedra for which `keep` holds reached from the finite stars of
/// `verts` through such tetrahedra (sorted; the walk stops past 4096).
fn flood(cm: &Journaled<'_>, verts: &[u32], keep: impl Fn(u32) -> bool) -> Vec<u32> {
    cm.visit_begin();
    let mut stack = Vec::new();
    for &w in verts {
        for t in finite_star(cm, w) {
            if cm.visit(t) && keep(t) {
                stack.push(t);
            }
        }
    }
    let mut out = Vec::new();
    while let Some(t) = stack.pop() {
        out.push(t);
        if out.len() > 4096 {
            break;
        }
        for f in 0..4 {
            let n = cm.m.nb[t as usize][f] >> 2;
            if cm.visit(n) && keep(n) {
                stack.push(n);
            }
        }
    }
    out.sort_unstable();
    out
}

/// A face of the mesh with these vertices exists (searched in the star of
/// a vertex: no cap on the number of tetrahedra around an edge).
fn has_face(cm: &Journaled<'_>, f: [u32; 3]) -> bool {
    cm.find_face(f[0], f[1], f[2]).is_some()
}

/// Grows `reg` (and `set`, sorted) by the tetrahedra behind the boundary
/// faces not seen from `from` that can grow;
/// `side`: keep to this closed side of the plane of these points. False
/// when nothing can grow.
fn grow(
    cm: &Journaled<'_>,
    reg: &mut Region,
    set: &mut Vec<u32>,
    taken: &IdSet<u32>,
    from: Option<&P>,
    side: Option<(&[P; 3], f64)>,
    prot: &Protected,
) -> bool {
    let c = &cm.m;
    let pts = cm.pts();
    let mut cands: Vec<([u32; 3], usize, u32)> = Vec::new();
    for (i, &(f, t, k)) in reg.faces.iter().enumerate() {
        if t == DEAD || from.is_some_and(|p| sees(pts, f, p)) || prot.faces.contains(&fkey(f)) {
            continue;
        }
        let n = c.nb[t as usize][k] >> 2;
        let nv = c.tv[n as usize];
        if nv[0] == DEAD || nv.contains(&INF) || taken.contains(&n) || set.binary_search(&n).is_ok()
        {
            continue;
        }
        if let Some((tri, s)) = side {
            let ok = nv.iter().all(|&w| {
                let o = orient3d(&tri[0], &tri[1], &tri[2], &pts[w as usize]);
                o == 0.0 || (o > 0.0) == (s > 0.0)
            });
            if !ok {
                continue;
            }
        }
        cands.push((fkey(f), i, n));
    }
    if set.len() + cands.len() > MAX_CAVITY {
        return false;
    }
    cands.sort_unstable();
    let mut grown = false;
    for (_, _, n) in cands {
        let Err(pos) = set.binary_search(&n) else {
            continue;
        };
        set.insert(pos, n);
        grown = true;
        let nv = c.tv[n as usize];
        for g in 0..4 {
            let gf = face(nv, g);
            let r = rev(gf);
            if let Some(pos) = reg.faces.iter().position(|x| okey(x.0) == r) {
                reg.faces.swap_remove(pos);
            } else {
                reg.faces.push((gf, n, g));
            }
        }
    }
    grown
}

impl State {
    /// Vertices below this id must survive a replacement: the input points
    /// (and any point registered on the surface); interior Steiner points
    /// of `-Y` come after and may be swallowed by a cavity (unused ones
    /// are dropped at the end, `compact`).
    fn n_fixed(&self) -> usize {
        self.surf.vtris.len()
    }

    /// Exact: `p` lies on no input triangle (closed).
    fn off_surface(&self, pts: &[P], p: &P) -> bool {
        for tv in &self.surf.tris {
            let [a, b, c] = tv.map(|w| &pts[w as usize]);
            if (0..3).any(|k| p[k] < a[k].min(b[k]).min(c[k]) || p[k] > a[k].max(b[k]).max(c[k])) {
                continue;
            }
            if orient3d(a, b, c, p) != 0.0 {
                continue;
            }
            let ax = place::dominant_axis(a, b, c);
            let pr = |q: &P| match ax {
                0 => [q[1], q[2]],
                1 => [q[2], q[0]],
                _ => [q[0], q[1]],
            };
            let (a2, b2, c2, p2) = (pr(a), pr(b), pr(c), pr(p));
            let s = orient2d(&a2, &b2, &c2);
            let s1 = orient2d(&a2, &b2, &p2) * s;
            let s2 = orient2d(&b2, &c2, &p2) * s;
            let s3 = orient2d(&c2, &a2, &p2) * s;
            if s1 >= 0.0 && s2 >= 0.0 && s3 >= 0.0 {
                return false;
            }
        }
        true
    }

    /// Applies fills for the regions of the removed set `set`: validates,
    /// adds the new points, replaces. Returns the number of new points, or
    /// `None` (nothing changed).
    fn apply(
        &self,
        cm: &mut Journaled<'_>,
        set: &[u32],
        fills: Vec<Fill>,
        prot: &Guard,
    ) -> Option<usize> {
        let mut pts: Vec<P> = cm.pts().to_vec();
        let mut new = Vec::new();
        let mut added = 0;
        for f in fills {
            if let Some(p) = f.point {
                if !self.off_surface(&pts, &p) {
                    return None;
                }
                pts.push(p);
                added += 1;
            }
            new.extend(f.tets);
        }
        if !valid_replacement(cm, &pts, set, &new, prot) {
            return None;
        }
        for p in &pts[cm.pts().len()..] {
            cm.push_point(*p);
        }
        cm.replace(set, &new);
        Some(added)
    }

    /// Retriangulates the cavity of missing edge `a b`. `Some(points added)`
    /// on a change.
    fn edge_by_cavity(
        &self,
        cm: &mut Journaled<'_>,
        a: u32,
        b: u32,
        prot: &Guard,
        steiner: bool,
    ) -> Option<usize> {
        let mut set = self.counted(segment_cavity(cm, a, b));
        if set.is_empty() {
            return None;
        }
        let mut reg = boundary_of(cm, &set);
        let none = IdSet::default();
        // First the cones from the ends (they contain `a b`), growing the
        // cavity towards the faces the end does not see.
        for apex in [a, b] {
            let (mut s2, mut r2) = (set.clone(), reg.clone());
            for _ in 0..=MAX_GROW {
                if let Some(tets) = cone_from(cm.pts(), &r2.tris(), apex) {
                    let fills = vec![Fill { tets, point: None }];
                    if let Some(k) = self.apply(cm, &s2, fills, prot) {
                        return Some(k);
                    }
                    break;
                }
                let from = cm.pts()[apex as usize];
                if !grow(cm, &mut r2, &mut s2, &none, Some(&from), None, prot) {
                    break;
                }
            }
        }
        if !steiner {
            return None;
        }
        let id = cm.pts().len() as u32;
        for _ in 0..=MAX_GROW {
            match fill(cm.pts(), &reg.tris(), &[], true, id) {
                Ok(f) => return self.apply(cm, &set, vec![f], prot),
                Err(best) => {
                    if !grow(cm, &mut reg, &mut set, &none, Some(&best), None, prot) {
                        return None;
                    }
                }
            }
        }
        None
    }

    /// Retriangulates the cavity of missing triangle `tri` (its edges
    /// present) so that it becomes a face. `Some(points added)` on success.
    fn facet_by_cavity(
        &self,
        cm: &mut Journaled<'_>,
        tri: [u32; 3],
        prot: &Guard,
        steiner: bool,
    ) -> Option<usize> {
        let mut set = self.counted(facet_cavity(cm, tri));
        if set.is_empty() {
            return None;
        }
        let pts = cm.pts();
        let tp = tri.map(|w| pts[w as usize]);
        let side_of = |w: u32| orient3d(&tp[0], &tp[1], &tp[2], &pts[w as usize]);
        let bnd = boundary_of(cm, &set);
        let mut sides = [Region::default(), Region::default()];
        for &(f, t, k) in &bnd.faces {
            let mut s = 0.0;
            for w in f {
                if tri.contains(&w) {
                    continue;
                }
                // A vertex on the plane (outside `T`: a coplanar
                // neighbour's) says nothing; the others decide.
                let o = side_of(w);
                if o == 0.0 {
                    continue;
                }
                if s != 0.0 && (o > 0.0) != (s > 0.0) {
                    return None;
                }
                s = o;
            }
            if s == 0.0 {
                return None;
            }
            sides[usize::from(s > 0.0)].faces.push((f, t, k));
        }
        // The triangle, inward for each side: [a, b, c, x] is positive for
        // x with orient3d < 0 (side 0).
        sides[0].faces.push((tri, DEAD, 0));
        sides[1].faces.push(([tri[0], tri[2], tri[1]], DEAD, 0));
        let mut fills = Vec::new();
        let mut next_id = pts.len() as u32;
        for (si, reg) in sides.iter_mut().enumerate() {
            let sign = if si == 0 { -1.0 } else { 1.0 };
            let f = fill_side(cm, reg, &mut set, Some((&tp, sign)), prot, steiner, next_id)?;
            if f.point.is_some() {
                next_id += 1;
            }
            fills.push(f);
        }
        self.apply(cm, &set, fills, prot)
    }

    /// One attempt of [`State::preserve_by_cavities`]: with `swallow`, a
    /// cavity may remove interior Steiner points (vertices from
    /// [`State::n_fixed`] on, its own kernel points included), else no
    /// vertex may disappear. With `budget`, it stops (unfinished) at the
    /// first item after its cavity searches have found more tetrahedra
    /// than that ([`State::cavity_work`]). `Ok((mesh, faces, points
    /// added))`, or the mesh reached.
    fn preserve_attempt<'a>(
        &self,
        cm: &Journaled<'a>,
        swallow: bool,
        budget: Option<u64>,
    ) -> Result<(Journaled<'a>, FacesOn, usize), Box<Journaled<'a>>> {
        let start = self.cavity_work.get();
        let spent = || budget.is_some_and(|b| self.cavity_work.get() - start > b);
        let mut w = cm.clone();
        let mut prot = Guard {
            prot: Protected::default(),
            n_fixed: if swallow { self.n_fixed() } else { usize::MAX },
        };
        for e in &self.surf.edges {
            prot.edges.insert(ekey(e[0], e[1]));
        }
        let tris = self.surf.tris.clone();
        for &t in &tris {
            if has_face(&w, t) {
                prot.add_face(t);
            }
        }
        // Only the items missing now are visited: the surface edges are
        // all protected and the faces present are, so no operation below
        // destroys one (the lists shrink pass by pass).
        let edges = &self.surf.edges;
        let mut todo_edges: Vec<usize> = (0..edges.len())
            .filter(|&e| w.find_edge(edges[e][0], edges[e][1]).is_none())
            .collect();
        let mut todo_tris: Vec<usize> = (0..tris.len())
            .filter(|&t| !prot.faces.contains(&fkey(tris[t])))
            .collect();
        let mut added = 0usize;
        let (mut best_left, mut stalled) = (usize::MAX, 0);
        // Steiner points only in a pass that follows a pass without
        // progress: cones from existing vertices are tried until they stop
        // helping (one recovered item often makes its neighbour's cone
        // possible), then one pass with kernel points, then cones again.
        let mut steiner_on = false;
        let mut memo = Memo::default();
        for _pass in 0..PASSES {
            let steiner = steiner_on && self.report.steiner() + added < self.opts.max_steiner;
            let mut progress = false;
            let mut missing_edges = false;
            for &e in &todo_edges {
                if spent() {
                    return Err(Box::new(w));
                }
                let [a, b] = edges[e];
                if w.find_edge(a, b).is_some() {
                    continue;
                }
                if cdt::recover_segment(&mut w, a, b, &prot) {
                    progress = true;
                    continue;
                }
                // On a flat part of the convex hull: 2D flips there (not
                // again on an unchanged mesh once they failed).
                memo.sync(&w);
                if !memo.hull_failed.contains(&(a, b)) {
                    let budget = self.report.steiner() + added < self.opts.max_steiner;
                    let (k, done) = self.hull_edge_by_flips(&mut w, a, b, &prot, budget);
                    added += k;
                    if done {
                        progress = true;
                        continue;
                    }
                    memo.sync(&w);
                    memo.hull_failed.insert((a, b));
                }
                // First the patch with its triangles, then the edge's own
                // cavity (cones from its ends, else a kernel point).
                if let Some((k, patch)) = self.patch_by_cavity(&mut w, e, &prot, steiner, &mut memo)
                {
                    added += k;
                    progress = true;
                    for t in patch {
                        prot.add_face(t);
                    }
                    continue;
                }
                match self.edge_by_cavity(&mut w, a, b, &prot, steiner) {
                    Some(k) => {
                        added += k;
                        progress = true;
                        if w.find_edge(a, b).is_none() {
                            missing_edges = true;
                        }
                    }
                    None => missing_edges = true,
                }
            }
            if missing_edges {
                // Give up when two passes in a row leave as many edges
                // missing (new points alone are no progress).
                todo_edges.retain(|&e| w.find_edge(edges[e][0], edges[e][1]).is_none());
                let left = todo_edges.len();
                stalled = if left < best_left { 0 } else { stalled + 1 };
                best_left = best_left.min(left);
                if (!progress && steiner_on) || stalled >= 3 {
                    break;
                }
                steiner_on = !progress;
                continue;
            }
            let mut missing_tris = false;
            for &t in &todo_tris {
                if spent() {
                    return Err(Box::new(w));
                }
                let tri = tris[t];
                if has_face(&w, tri) {
                    continue;
                }
                cdt::recover_facet(&mut w, &self.surf, t, &[], &prot);
                if has_face(&w, tri) {
                    prot.add_face(tri);
                    progress = true;
                    continue;
                }
                match self.facet_by_cavity(&mut w, tri, &prot, steiner) {
                    Some(k) if has_face(&w, tri) => {
                        added += k;
                        prot.add_face(tri);
                        progress = true;
                    }
                    Some(k) => {
                        added += k;
                        progress = true;
                        missing_tris = true;
                    }
                    None => missing_tris = true,
                }
            }
            todo_tris.retain(|&t| !has_face(&w, tris[t]));
            if !missing_tris {
                let on: FacesOn = tris.iter().map(|&t| vec![fkey(t)]).collect();
                return Ok((w, on, added));
            }
            if !progress && steiner_on {
                break;
            }
            steiner_on = !progress;
        }
        Err(Box::new(w))
    }

    /// Surface preservation on the flipped mesh `cm`: recovers the missing
    /// input edges and triangles by flips and cavity retriangulation with
    /// interior Steiner points only. `Some` (the mesh and the face on each
    /// input triangle) when everything is recovered; `None` leaves the
    /// caller's fallback to act (nothing of `cm` is changed).
    pub(super) fn preserve_by_cavities<'a>(
        &mut self,
        cm: &Journaled<'a>,
    ) -> Result<Option<(Journaled<'a>, FacesOn)>, RecoverError> {
        // The [`ATTEMPTS`]: none is better on every model (each recovers
        // models another does not). What is left missing is taken from
        // the first.
        let mut first: Option<Box<Journaled<'a>>> = None;
        let budget = (!self.fallback_tried && self.cavity_fails == 0)
            .then(|| VISITS_PER_CELL * cm.m.tv.len() as u64);
        for swallow in ATTEMPTS {
            let start = self.cavity_work.get();
            match self.preserve_attempt(cm, swallow, budget) {
                Ok((done, on, added)) => {
                    self.report.steiner_interior += added;
                    return Ok(Some((done, on)));
                }
                Err(reached) => {
                    first.get_or_insert(reached);
                }
            }
            // An attempt that spent its budget ends the call: on the
            // models where it does, the other attempt spends it too.
            if budget.is_some_and(|b| self.cavity_work.get() - start > b) {
                break;
            }
        }
        let left = self.left_missing(first.as_deref().unwrap_or(cm));
        self.cavity_fails += 1;
        // Give up (typed error, no more rounds): the fallback that always
        // applies takes over.
        if self.cavity_fails >= MAX_FAILED_CALLS {
            return Err(RecoverError::Unrecovered {
                triangles: left,
                steiner: self.report.steiner(),
            });
        }
        self.cavity_left = left;
        Ok(None)
    }

    /// What `w` still misses, for the fallback's interior points: the
    /// input triangles at a missing input edge, else (every edge present)
    /// the missing input triangles (sorted).
    fn left_missing(&self, w: &Journaled<'_>) -> Vec<usize> {
        let tris = &self.surf.tris;
        let mut left: Vec<usize> = Vec::new();
        for (e, &[a, b]) in self.surf.edges.iter().enumerate() {
            if w.find_edge(a, b).is_none() {
                left.extend(self.surf.edge_tris[e].iter().map(|&t| t as usize));
            }
        }
        if left.is_empty() {
            left.extend((0..tris.len()).filter(|&t| !has_face(w, tris[t])));
        }
        left.sort_unstable();
        left.dedup();
        left
    }

    /// The triangles the `-Y` fallback should place interior points at:
    /// those the last unfinished [`State::preserve_by_cavities`] call left
    /// missing (or next to a missing edge), else `default`.
    pub(super) fn fallback_targets(&mut self, default: Vec<usize>) -> Vec<usize> {
        let left = std::mem::take(&mut self.cavity_left);
        if left.is_empty() {
            default
        } else {
            left
        }
    }
}

impl State {
    /// After the first unfinished cavity call, once per recovery: the
    /// fallback that always applies ([`State::preserve_fallback`] on the
    /// scaled input points `scaled`). `Some` (this state replaced by the
    /// fallback's) when it recovered everything; `None` when it failed or
    /// does not apply now, and the interior-point rounds go on.
    pub(super) fn fallback_once<'a>(
        &mut self,
        scaled: Option<&'a [P]>,
    ) -> Result<Option<(Journaled<'a>, FacesOn)>, RecoverError> {
        let Some(scaled) = scaled else {
            return Ok(None);
        };
        if self.cavity_fails != 1 || self.fallback_tried {
            return Ok(None);
        }
        self.fallback_tried = true;
        match self.preserve_fallback(scaled) {
            Ok((st, cm, on)) => {
                *self = st;
                Ok(Some((cm, on)))
            }
            Err(RecoverError::Unrecovered { .. }) => Ok(None),
            Err(e) => Err(e),
        }
    }

    /// `set` (tetrahedra found by a cavity search), its size added to
    /// [`State::cavity_work`].
    fn counted(&self, set: Vec<u32>) -> Vec<u32> {
        self.cavity_work
            .set(self.cavity_work.get() + set.len() as u64);
        set
    }

    /// Records the flip counts of a mesh finished by
    /// [`State::preserve_by_cavities`] and hands it on.
    pub(super) fn cavity_done<'a>(
        &mut self,
        done: (Journaled<'a>, FacesOn),
    ) -> (Journaled<'a>, FacesOn) {
        self.report.flips23 = done.0.flips23;
        self.report.edge_removals = done.0.removals;
        done
    }
}

/// The vertices, edges and faces (sorted keys) of the tetrahedra `new`.
struct NewParts {
    verts: IdSet<u32>,
    edges: IdSet<(u32, u32)>,
    faces: IdSet<[u32; 3]>,
}

/// [`fills_bounded`] for the region of the `old` cells.
fn fills(cm: &Journaled<'_>, old: &[u32], new: &[[u32; 4]]) -> Option<NewParts> {
    let bset = boundary_of(cm, old)
        .faces
        .iter()
        .map(|f| okey(f.0))
        .collect();
    fills_bounded(new, &bset)
}

/// The parts of `new` when its tetrahedra (each oriented face counted
/// once) fill exactly the region bounded by the oriented faces `bset`:
/// every boundary face is a new face not matched from the other side, and
/// every new face off the boundary is matched by its reverse.
fn fills_bounded(new: &[[u32; 4]], bset: &IdSet<[u32; 3]>) -> Option<NewParts> {
    let mut count: IdMap<[u32; 3], u32> = IdMap::default();
    let mut parts = NewParts {
        verts: IdSet::default(),
        edges: IdSet::default(),
        faces: IdSet::default(),
    };
    for &tv in new {
        for f in 0..4 {
            let k = okey(face(tv, f));
            *count.entry(k).or_insert(0) += 1;
            parts.faces.insert(fkey(k));
        }
        for i in 0..4 {
            parts.verts.insert(tv[i]);
            for j in i + 1..4 {
                parts.edges.insert(ekey(tv[i], tv[j]));
            }
        }
    }
    let filled = count.values().all(|&n| n == 1)
        && bset
            .iter()
            .all(|k| count.contains_key(k) && !count.contains_key(&rev(*k)))
        && count
            .keys()
            .all(|k| bset.contains(k) || count.contains_key(&rev(*k)));
    filled.then_some(parts)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plane(a: P, b: P, c: P) -> (P, P) {
        let n = cross(&sub(&b, &a), &sub(&c, &a));
        let l = dot(&n, &n).sqrt();
        (a, n.map(|x| x / l))
    }

    /// A thin wedge: the half-spaces above `z = 0` and below a plane
    /// through the x axis tilted by `tilt`, closed by two side planes;
    /// its deepest point sees every face exactly (the inner side of a
    /// face `a b c` is where `orient3d(a, b, c, x) < 0`).
    #[test]
    fn deepest_point_enters_thin_wedges() {
        for tilt in [1e-2, 1e-5, 1e-8] {
            let pts: Vec<P> = vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 1.0, tilt],
                [0.2, 0.0, 0.0],
                [0.2, 1.0, 0.0],
                [0.8, 0.0, 0.0],
                [0.8, 1.0, 0.0],
            ];
            // Above z = 0, below the tilted plane, 0.2 < x < 0.8.
            let faces: [[u32; 3]; 4] = [[0, 1, 2], [0, 3, 1], [4, 5, 0], [6, 2, 7]];
            let faces = faces.map(|f| {
                // Orient each face so that a point of the wedge sees it.
                let inside = [0.5, 0.5, 0.25 * tilt];
                let [a, b, c] = f.map(|w| &pts[w as usize]);
                if orient3d(a, b, c, &inside) < 0.0 {
                    f
                } else {
                    [f[0], f[2], f[1]]
                }
            });
            let planes: Vec<(P, P)> = faces
                .iter()
                .map(|f| plane(pts[f[0] as usize], pts[f[1] as usize], pts[f[2] as usize]))
                .collect();
            let (p, clear) = deepest_point(&planes, &[0.5, 0.5, 0.0], 1.0).unwrap();
            assert!(clear > 0.0, "tilt {tilt}: clearance {clear}");
            assert!(
                faces.iter().all(|&f| sees(&pts, f, &p)),
                "tilt {tilt}: {p:?}"
            );
        }
    }

    /// A flanged plate's points (an outer ring and an off-centre inner
    /// ring on two planes, a hub ring above, rings below and above the
    /// annulus): the fan triangles of the top annulus, long and thin, are
    /// mostly missing from the Delaunay tetrahedralization, which crosses
    /// their plane.
    fn flange_points() -> (Vec<P>, Vec<[u32; 3]>) {
        let mut pts: Vec<P> = Vec::new();
        let ring = |pts: &mut Vec<P>, n: usize, r: f64, cx: f64, z: f64| {
            for i in 0..n {
                let a = 2.0 * std::f64::consts::PI * i as f64 / n as f64;
                pts.push([cx + r * a.cos(), r * a.sin(), z]);
            }
        };
        ring(&mut pts, 16, 1.0, 0.0, 0.0);
        ring(&mut pts, 16, 1.0, 0.0, 0.2);
        ring(&mut pts, 8, 0.35, 0.03, 0.2);
        ring(&mut pts, 8, 0.35, 0.03, 1.5);
        // Rings below and above the annulus's middle: Delaunay
        // tetrahedra between them cross its plane.
        ring(&mut pts, 10, 0.65, 0.0, -0.05);
        ring(&mut pts, 10, 0.7, 0.01, 0.5);
        // The top annulus (z = 0.2) as a fan: each outer edge to an inner
        // vertex, each inner edge to an outer vertex.
        let mut fan = Vec::new();
        for i in 0..16u32 {
            fan.push([16 + i, 16 + (i + 1) % 16, 32 + i / 2]);
        }
        for j in 0..8u32 {
            fan.push([32 + j, 32 + (j + 1) % 8, 16 + (2 * j + 2) % 16]);
        }
        (pts, fan)
    }

    /// An attempt whose cavity searches have spent its budget stops
    /// unfinished, with a valid mesh, at the first item after the budget
    /// ran out; without a budget the same attempt recovers more items.
    /// The work is counted in [`State::cavity_work`].
    #[test]
    fn an_attempt_stops_when_its_search_budget_is_spent() {
        let (pts, fan) = flange_points();
        let opts = crate::tet::recover::RecoverOptions {
            preserve_surface: true,
            ..Default::default()
        };
        let st = State::new(crate::tet::recover::Surface::new(pts.len(), &fan), opts);
        let cm = Journaled::new(crate::tet::Delaunay3::from_points(&pts).unwrap());
        let missing = |w: &Journaled<'_>| fan.iter().filter(|&&t| !has_face(w, t)).count();
        let before = missing(&cm);
        assert!(before > 0);
        let Err(stopped) = st.preserve_attempt(&cm, false, Some(0)) else {
            panic!("finished although its budget was spent");
        };
        stopped.m.check(stopped.pts()).unwrap();
        let spent = st.cavity_work.get();
        assert!(spent > 0);
        let left_stopped = missing(&stopped);
        let full = st.preserve_attempt(&cm, false, None);
        let total = st.cavity_work.get();
        assert!(total > spent, "work {spent} stopped, {total} in all");
        let left_full = match &full {
            Ok((w, _, _)) => {
                w.m.check(w.pts()).unwrap();
                missing(w)
            }
            Err(w) => missing(w),
        };
        assert!(
            left_full < left_stopped,
            "{before} missing: {left_stopped} left when stopped, {left_full} without a budget"
        );
    }

    /// The cavities of the fan triangles and of their edges are what a
    /// test of every tetrahedron finds: `facet_cavity` exactly the
    /// tetrahedra with an edge crossing the triangle's interior (off its
    /// vertices), `segment_cavity` exactly the live tetrahedra the segment
    /// test accepts, reached from the segment's end.
    #[test]
    fn cavities_match_a_test_of_every_tetrahedron() {
        let (pts, fan) = flange_points();
        let cm = Journaled::new(crate::tet::Delaunay3::from_points(&pts).unwrap());
        cm.m.check(cm.pts()).unwrap();
        let live: Vec<u32> = (0..cm.m.tv.len() as u32)
            .filter(|&t| {
                let tv = cm.m.tv[t as usize];
                tv[0] != DEAD && !tv.contains(&INF)
            })
            .collect();
        let (mut crossed, mut missing) = (0, 0);
        for &tri in &fan {
            let [a, b, c] = tri.map(|w| &pts[w as usize]);
            let brute: Vec<u32> = live
                .iter()
                .copied()
                .filter(|&t| {
                    let tv = cm.m.tv[t as usize];
                    crate::tet::local::EDGES.iter().any(|&(i, j)| {
                        !tri.contains(&tv[i])
                            && !tri.contains(&tv[j])
                            && place::crosses(a, b, c, &pts[tv[i] as usize], &pts[tv[j] as usize])
                    })
                })
                .collect();
            let got = facet_cavity(&cm, tri);
            let edges_in = (0..3).all(|k| cm.find_edge(tri[k], tri[(k + 1) % 3]).is_some());
            if edges_in {
                assert_eq!(got, brute, "{tri:?}");
            } else {
                assert!(
                    got.iter().all(|t| brute.binary_search(t).is_ok()),
                    "{tri:?}"
                );
            }
            crossed += usize::from(!got.is_empty());
            for k in 0..3 {
                let (u, v) = (tri[k], tri[(k + 1) % 3]);
                if cm.find_edge(u, v).is_some() {
                    continue;
                }
                missing += 1;
                let got = segment_cavity(&cm, u, v);
                assert!(!got.is_empty(), "{u}-{v}");
                // Each tetrahedron found meets the closed segment.
                let (pu, pv) = (pts[u as usize], pts[v as usize]);
                for &t in &got {
                    let tv = cm.m.tv[t as usize];
                    let meets = tv.contains(&u)
                        || tv.contains(&v)
                        || (0..4).any(|f| {
                            let [x, y, z] = face(tv, f).map(|w| &pts[w as usize]);
                            seg_meets_tri(x, y, z, &pu, &pv)
                        });
                    assert!(meets, "{u}-{v}: {tv:?}");
                }
            }
        }
        // The Delaunay tetrahedralization crosses the annulus.
        assert!(crossed > 0 && missing > 0, "{crossed} {missing}");
    }

    /// Two opposite half-spaces leave no kernel: the clearance found is
    /// negative, and no point is claimed inside.
    #[test]
    fn deepest_point_of_an_empty_kernel_has_negative_clearance() {
        let planes = vec![
            ([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]),
            ([0.0, 0.0, -1.0], [0.0, 0.0, -1.0]),
        ];
        let (_, clear) = deepest_point(&planes, &[0.0; 3], 1.0).unwrap();
        assert!(clear < 0.0);
        assert!(deepest_point(&[], &[0.0; 3], 1.0).is_none());
        assert!(deepest_point(&planes, &[0.0; 3], 0.0).is_none());
    }
}
