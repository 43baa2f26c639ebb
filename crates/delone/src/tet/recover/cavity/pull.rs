//! The `-Y` fallback that always applies: recover with Steiner points on
//! the surface, then **pull every surface Steiner point off the surface**.
//!
//! When the cavity retriangulation of the parent module and the interior
//! point rounds leave items missing ([`RecoverError::Unrecovered`]), the
//! recovery is run again without surface preservation (the constrained
//! `-p` path, which recovers every closed non-self-intersecting surface
//! by splitting subsegments and triangles), and each Steiner point `s`
//! that path put on an input triangle or edge is then removed from the
//! surface, one at a time, in increasing id order (deterministic):
//!
//! 1. The star of `s` (every tetrahedron at `s`, ghosts included) is cut
//!    by the mesh faces on input triangles (the faces at `s` in the
//!    coverage) into **wedges**: connected sets of tetrahedra across faces
//!    at `s` that are not on the surface. `s` interior to input triangle
//!    `T` gives two wedges (the two sides of `T`); `s` on an input edge
//!    shared by `k` triangles gives `k`.
//! 2. For each input triangle `T` at `s`, the faces of `T`'s refinement at
//!    `s` form a fan whose union is a polygon `R` (a disk around `s`, or a
//!    half-disk when `s` is on an edge of `T`: then the polygon closes by
//!    the chord between the two neighbours of `s` on that edge, on which
//!    `s` lies). `R` is triangulated **without** `s` by ear clipping in
//!    the projection along `T`'s dominant axis (exact `orient2d`; a simple
//!    polygon always has an ear whose triangle holds no other vertex).
//!    Three points of one edge of `T` (its ends and the Steiner points on
//!    it) are collinear by construction, whatever their rounded
//!    coordinates: such an ear is never cut ([`Surface::on_one_edge`]), so
//!    no new triangle is a sliver whose plane rounding tilts at will (a
//!    polygon with a straight run still has ears of positive area).
//!    A fan that is a single thin face `u s w` of three points of one
//!    edge (the `-p` coverage accepts such faces next to a chord `u w`
//!    when the points are rounded) leaves an empty polygon: the segment
//!    `u w`, already covered by the chord's faces.
//! 3. Each wedge `W` is refilled by the cone from a **new interior point**
//!    `p = s + h d` over its new boundary — the faces opposite `s` (kept)
//!    and the new triangles of the polygons bounding it. `d` is the sum of
//!    the unit normals of `W`'s surface faces towards `W` (it points
//!    strictly into the open half-spaces of all of them, the planes of at
//!    most two triangles at an edge, unless the wedge is flat), and `h`
//!    is halved until `p` sees every boundary face strictly (exact
//!    `orient3d`). Such an `h` exists: `s` itself sees every face opposite
//!    it strictly (its star's tetrahedra are positive), which stays true
//!    near `s` by continuity, and the new triangles lie in the planes of
//!    their input triangles, which `p` is strictly off. When the star has
//!    nearly flat tetrahedra (a face opposite `s` whose plane passes
//!    within rounding of `s`, nearly parallel to the surface) the points
//!    that see everything form a thin wedge that no normal direction
//!    enters; one more direction is then tried, into the tangent cone of
//!    the faces whose planes pass (nearly) through `s`, found by
//!    relaxation. Of all candidates the one **farthest from every face**
//!    is taken (along each ray the clearance rises, then falls): a point
//!    barely off the surface would make the stars of the next surface
//!    points nearly flat. When no ray works, the point of the ball
//!    around `s` (radius: the distance to its nearest vertex) farthest
//!    inside every face's half-space is computed (the ellipsoid method,
//!    `deepest_point` of the parent module) and taken if it sees every
//!    face exactly: on twisted or nearly coplanar surfaces the flat
//!    tetrahedra at `s` leave a kernel too thin for any of the rays.
//!    When nothing works, the wedge grows by the
//!    tetrahedra behind the faces the candidates do not see (the deepest
//!    point's when no ray gave fewer; never across the surface), then it is filled like a cavity of the parent module
//!    (a cone from one of its vertices, else the gift-wrapping fill of its
//!    faces with no new point — `dfill::wrap_fill`, exact tests with
//!    symbolic perturbation, which needs no point to see every face and
//!    so fills the wedges that flat tetrahedra of exactly coplanar input
//!    triangles leave at `s` —, else a kernel point, growing towards the
//!    faces the best point does not see). A wedge with a
//!    ghost (it reaches the convex hull, so it is outside the domain) is
//!    not filled: it becomes outside the hull, ghosts on the new triangles
//!    and on its faces opposite `s` (a face that is on the hull already
//!    takes the ghost behind it along); the interior Steiner points it
//!    swallows go unused. Nothing there is geometric, so nothing there
//!    depends on rounding; carving floods from the ghosts as before.
//!    Such a removal is refused when it would pinch the outside region
//!    (the hull faces at a vertex of its new ghosts not one cycle, or two
//!    hull sheets meeting along an edge, which no new cells close): then
//!    a single point's wedges are all filled as in step 3, the wedge
//!    reaching the hull included — its faces through the point at
//!    infinity become ghosts at the new point, the hull stays as it was
//!    around it — so no removal leaves a pinch for a later one.
//! 4. The replacement of the whole star is validated exactly before it is
//!    applied (every new finite tetrahedron strictly positive; the new
//!    tetrahedra's oriented faces forming a chain whose boundary is exactly
//!    the star's boundary, so — winding number — they tile the star; every
//!    vertex but `s` kept, except interior Steiner points swallowed by a
//!    wedge outside the hull; no new edge that exists elsewhere in the
//!    mesh).
//!
//! **Clusters.** A point whose removal fails (after every other point has
//! been tried again, as long as a pass removes one) is removed together
//! with its nearest surface Steiner points — breadth first over the
//! surface edges, ties by id, 2 to [`MAX_CLUSTER`] points: the star is the
//! union of their stars, each polygon is the fan of all of them with the
//! points on the triangle's edges cut out (their neighbours joined by
//! chords), so the polygon's vertices are further from the rounded
//! points, and each wedge is filled as in step 3 (general fill).
//!
//! **What is guaranteed, and what is checked.** By construction: no
//! point is ever placed on the surface (every new point is tested
//! exactly against every input triangle), the mesh is never invalid
//! (every replacement is validated exactly, else nothing changes), the
//! loop terminates (each success removes at least one surface point and
//! adds none, each failure is final once a pass removes nothing), and
//! the result is deterministic. When the surface Steiner points and the
//! polygon vertices lie exactly on their triangles, a removal exists in
//! exact arithmetic (step 3); it is found in floating point when the set
//! of points that see every face holds a representable point — it is an
//! open set with `s` on its boundary, and the thin wedge of nearly flat
//! tetrahedra is reached by the tangent-cone direction. Rounded (inexact)
//! surface points bend the polygons by a few units in the last place;
//! then only the exact validation vouches for a removal, and what it
//! refuses after every cluster has been tried makes the whole pull-off
//! start again from a new `-p` recovery with another per-segment flip
//! budget (128, then 256, then 64: the surface points land elsewhere);
//! what the last of them refuses is reported as
//! [`RecoverError::Unrecovered`]. On the corpus that never happens: all
//! 40 closed clean models are recovered (cgal_rotor only with a budget
//! other than the first).
//!
//! **Termination**: each removal takes at least one surface Steiner point
//! away and adds none on the surface, so there are at most as many
//! removals as surface Steiner points; a point no removal or cluster can
//! take away leaves an [`RecoverError::Unrecovered`] error naming the
//! triangles at that point. When every surface Steiner point is gone, the
//! refinement of each input triangle has only the triangle's corners as
//! vertices, so the triangle is exactly one mesh face.
//!
//! **No point on the surface**: every new point `p` is strictly inside its
//! wedge (it sees every boundary face of the wedge strictly), and the
//! interior of a wedge meets no input triangle (the surface faces at `s`
//! bound the wedges, the others are faces opposite `s`, on the boundary);
//! each `p` is moreover tested exactly against every input triangle
//! (closed) before use. Points in outer wedges end outside the domain and
//! are dropped by carving and compaction.
//!
//! A point that still fails is removed together with its nearest surface
//! points (`pull_cluster`, at most 12: the union of their stars, edge points
//! cut out of the polygons by chords). One surface point fewer per step, so
//! the loop terminates.

use super::super::surface::Surface;
use super::super::{FacesOn, RecoverError, State};
use super::cdt::{Protected, SEG_OPS};
use super::{fill, grow, okey, Fill, Region};
use crate::geom::ids::{IdMap, IdSet};
use crate::geom::vec3::{cross, dot, sub};
use crate::tet::dmesh::journal::Journaled;
use crate::tet::local::face;
use crate::tet::local::fkey;
use crate::tet::local::{DEAD, INF};
use crate::tet::Delaunay3;
use delone_predicates::{orient2d, orient3d};

type P = [f64; 3];
/// A face kept from a removed star, with the tetrahedron owning it and
/// its local index.
type LinkFace = ([u32; 3], u32, usize);

/// Halvings of the step `h` tried for a new point.
const HALVINGS: usize = 60;
/// Most growth steps of a wedge in the search near its point.
const MAX_GROW: usize = 4;
/// Most surface Steiner points removed together ([`State::pull_cluster`]).
const MAX_CLUSTER: usize = 12;

impl State {
    /// The `-Y` fallback (module documentation): recovers `scaled` (the
    /// input points as scaled by the caller) without surface preservation,
    /// then pulls every surface Steiner point off the surface. Returns the
    /// state (its report updated for `-Y`), the mesh and the one face on
    /// each input triangle.
    pub(in crate::tet::recover) fn preserve_fallback<'a>(
        &self,
        scaled: &'a [[f64; 3]],
    ) -> Result<(State, Journaled<'a>, FacesOn), RecoverError> {
        let mut opts = self.opts.clone();
        opts.preserve_surface = false;
        opts.merge_coplanar = false;
        // Whether every surface point comes off depends on where the `-p`
        // path put them (rounded points, nearly flat neighbours): when the
        // exact validation refuses a removal, the `-p` path is run again,
        // which places the surface points differently. The first two runs
        // are `-p`'s own recovery (`stop_circling_flips`: guided flips,
        // deeper flip levels that keep their progress, splits in the
        // flipped mesh, which the rounds go on in: `carry_splits`), with
        // and without the cones over flat hull facets: it leaves far fewer
        // points to pull off than the refinement's (the 86 held-out
        // shapes: 15.5 → 7.5 s; the bundled `tube_rings_pierced` 8.6 →
        // 0.84 s with the carried rounds). The last two are the
        // refinement's recovery with other flip budgets per segment and
        // their failing segments tried at deeper flip levels (at up to
        // twice the time and three times the memory of a run). Each runs
        // only where the one before did not get its points off
        // (cgal_anchor needs the second); deterministic order; the last
        // error stands.
        let mut last = None;
        for (ops, escalate, flat, guided, carry) in [
            (SEG_OPS, false, true, true, true),
            (SEG_OPS, false, false, true, true),
            (2 * SEG_OPS, true, false, false, false),
            (SEG_OPS / 2, true, false, false, false),
        ] {
            opts.stop_circling_flips = guided;
            let mut st = State::new(self.surf.clone(), opts.clone());
            st.seg_ops = ops;
            st.y_fallback = true;
            st.escalate = escalate;
            st.flat_cones = flat;
            st.carry_splits = carry;
            let mut dt = Delaunay3::from_points(scaled)?;
            let (mut cm, on) = st.run_cdt(&mut dt, None)?;
            // `self.surf` is the unrefined surface (`st`'s has the points
            // the `-p` path added).
            match self.pull_off(&mut cm, &on, st.report.steiner(), &st.surf) {
                Ok(added) => return Ok(Self::pulled(st, cm, added)),
                Err(e @ RecoverError::Unrecovered { .. }) => last = Some(e),
                Err(e) => return Err(e),
            }
        }
        Err(last.unwrap_or(RecoverError::Unrecovered {
            triangles: Vec::new(),
            steiner: 0,
        }))
    }

    /// The state and mesh of a successful [`State::preserve_fallback`]:
    /// the report counts the pulled-off points as interior ones.
    fn pulled(mut st: State, cm: Journaled<'_>, added: usize) -> (State, Journaled<'_>, FacesOn) {
        st.opts.preserve_surface = true;
        let r = &mut st.report;
        // The removed surface points stay unused in the points and are
        // dropped (and subtracted) by compaction with the outer ones.
        let removed = r.steiner_on_edges + r.steiner_on_facets;
        r.steiner_interior += added + removed;
        r.steiner_on_edges = 0;
        r.steiner_on_facets = 0;
        r.inexact_steiner = 0;
        st.inexact.clear();
        st.max_dev_scaled = 0.0;
        let on1: FacesOn = st.surf.tris.iter().map(|&t| vec![fkey(t)]).collect();
        (st, cm, on1)
    }

    /// Removes every surface Steiner point of `cm` (`on`: the faces on
    /// each input triangle); returns the number of interior points added.
    fn pull_off(
        &self,
        cm: &mut Journaled<'_>,
        on: &FacesOn,
        before: usize,
        refined: &Surface,
    ) -> Result<usize, RecoverError> {
        let n_in = self.n_fixed();
        let mut face_tri: IdMap<[u32; 3], u32> = IdMap::default();
        let mut surface_pts: Vec<u32> = Vec::new();
        for (t, fs) in on.iter().enumerate() {
            for &f in fs {
                face_tri.insert(f, t as u32);
                surface_pts.extend(f.iter().copied().filter(|&w| w as usize >= n_in));
            }
        }
        surface_pts.sort_unstable();
        surface_pts.dedup();
        let mut added = 0;
        // A point that fails is retried after the others (their removal
        // changes its star), as long as a pass removes one; then with its
        // nearest surface Steiner points as a cluster.
        let mut pending = surface_pts;
        loop {
            loop {
                let before_len = pending.len();
                let mut failed = Vec::new();
                for &s in &pending {
                    match self.pull_set(cm, &[s], &mut face_tri, refined) {
                        Some(k) => added += k,
                        None => failed.push(s),
                    }
                }
                pending = failed;
                if pending.is_empty() || pending.len() == before_len {
                    break;
                }
            }
            let before_len = pending.len();
            let mut gone: Vec<u32> = Vec::new();
            for &s in &pending {
                if gone.binary_search(&s).is_ok() {
                    continue;
                }
                if let Some((k, set)) = self.pull_cluster(cm, s, n_in, &mut face_tri, refined) {
                    added += k;
                    gone.extend(set);
                    gone.sort_unstable();
                }
            }
            pending.retain(|s| gone.binary_search(s).is_err());
            if pending.is_empty() || pending.len() == before_len {
                break;
            }
        }
        if let Some(&s) = pending.first() {
            let mut tris: Vec<usize> = cm
                .star(s)
                .iter()
                .flat_map(|&t| {
                    let tv = cm.m.tv[t as usize];
                    (0..4).map(move |f| fkey(face(tv, f)))
                })
                .filter_map(|k| face_tri.get(&k).map(|&t| t as usize))
                .collect();
            tris.sort_unstable();
            tris.dedup();
            return Err(RecoverError::Unrecovered {
                triangles: tris,
                steiner: before + added,
            });
        }
        let left: Vec<usize> = (0..self.surf.tris.len())
            .filter(|&t| {
                let [a, b, c] = self.surf.tris[t];
                cm.find_face(a, b, c).is_none()
            })
            .collect();
        if !left.is_empty() {
            return Err(RecoverError::Unrecovered {
                triangles: left,
                steiner: before + added,
            });
        }
        Ok(added)
    }

    /// Removes surface Steiner point `s` together with its nearest
    /// surface Steiner points (breadth first over the surface edges,
    /// ties by id), trying clusters of 2 to [`MAX_CLUSTER`] points;
    /// `Some((points added, the cluster))` on the first that succeeds.
    fn pull_cluster(
        &self,
        cm: &mut Journaled<'_>,
        s: u32,
        n_in: usize,
        face_tri: &mut IdMap<[u32; 3], u32>,
        refined: &Surface,
    ) -> Option<(usize, Vec<u32>)> {
        let mut order = vec![s];
        let mut next = 0;
        while next < order.len() && order.len() < MAX_CLUSTER {
            let v = order[next];
            next += 1;
            let c = &cm.m;
            let mut nb: Vec<u32> = cm
                .star(v)
                .iter()
                .flat_map(|&t| {
                    let tv = c.tv[t as usize];
                    (0..4).map(move |f| face(tv, f))
                })
                .filter(|f| f.contains(&v) && face_tri.contains_key(&fkey(*f)))
                .flatten()
                .filter(|&w| w as usize >= n_in && w != INF && !order.contains(&w))
                .collect();
            nb.sort_unstable();
            nb.dedup();
            order.extend(nb);
        }
        order.truncate(MAX_CLUSTER);
        for k in 2..=order.len() {
            let mut set = order[..k].to_vec();
            set.sort_unstable();
            if let Some(a) = self.pull_set(cm, &set, face_tri, refined) {
                return Some((a, set));
            }
        }
        None
    }

    /// Removes the surface Steiner points `sset` (sorted; module
    /// documentation: the star is the union of their stars);
    /// `Some(points added)`, or `None` (nothing changed). A wedge
    /// reaching the hull is made outside the hull; when that replacement
    /// is refused, a single point's wedges are all filled by cones from
    /// new points instead ([`State::pull_set_with`]).
    fn pull_set(
        &self,
        cm: &mut Journaled<'_>,
        sset: &[u32],
        face_tri: &mut IdMap<[u32; 3], u32>,
        refined: &Surface,
    ) -> Option<usize> {
        let mut ghosts = false;
        self.pull_set_with(cm, sset, face_tri, refined, false, &mut ghosts)
            .or_else(|| {
                (ghosts && sset.len() == 1)
                    .then(|| self.pull_set_with(cm, sset, face_tri, refined, true, &mut ghosts))
                    .flatten()
            })
    }

    /// [`State::pull_set`] with the choice for wedges reaching the hull
    /// (`had_ghosts` set when there is one): made outside the hull
    /// (`cone_ghosts` false), or (single point) filled by the cone from a
    /// new point near `s` like any other wedge, its ghosts becoming
    /// ghosts at that point. Making a wedge outside the hull takes along
    /// the ghosts behind its hull faces; where two of them meet other
    /// hull faces along one edge (the outside region pinched there by
    /// earlier removals) no set of new cells closes the boundary, while
    /// the cone keeps every face of the wedge's boundary.
    fn pull_set_with(
        &self,
        cm: &mut Journaled<'_>,
        sset: &[u32],
        face_tri: &mut IdMap<[u32; 3], u32>,
        refined: &Surface,
        cone_ghosts: bool,
        had_ghosts: &mut bool,
    ) -> Option<usize> {
        let c = &cm.m;
        let pts = cm.pts();
        let in_s = |w: u32| sset.binary_search(&w).is_ok();
        let touches = |f: &[u32; 3]| f.iter().any(|&w| in_s(w));
        let mut star: Vec<u32> = sset.iter().flat_map(|&s| cm.star(s)).collect();
        star.sort_unstable();
        star.dedup();
        let at = |t: u32| star.binary_search(&t).ok();
        // The input triangles with a surface face at a point of `sset`.
        let mut tris_s: Vec<u32> = Vec::new();
        for &t in &star {
            let tv = c.tv[t as usize];
            for f in 0..4 {
                let fv = face(tv, f);
                if touches(&fv) {
                    if let Some(&ti) = face_tri.get(&fkey(fv)) {
                        tris_s.push(ti);
                    }
                }
            }
        }
        tris_s.sort_unstable();
        tris_s.dedup();
        if tris_s.is_empty() {
            return None;
        }
        // The new triangulation of each polygon, as 2D-counterclockwise
        // triangles, with the projection axis and the polygon's faces.
        let mut polys: IdMap<u32, (usize, Vec<[u32; 3]>)> = IdMap::default();
        let mut fan_count: IdMap<u32, usize> = IdMap::default();
        for &ti in &tris_s {
            let fan: Vec<[u32; 3]> = star
                .iter()
                .flat_map(|&t| {
                    let tv = c.tv[t as usize];
                    (0..4).map(move |f| face(tv, f))
                })
                .filter(|f| touches(f))
                .map(fkey)
                .filter(|k| face_tri.get(k) == Some(&ti))
                .collect::<IdSet<_>>()
                .into_iter()
                .collect();
            let [a, b, cc] = self.surf.tris[ti as usize].map(|w| pts[w as usize]);
            let ax = super::super::place::dominant_axis(&a, &b, &cc);
            let flat = |f: [u32; 3]| refined.on_one_edge(f, ti as usize);
            let tri = polygon_without(pts, &fan, sset, ax, flat)?;
            fan_count.insert(ti, fan.len());
            polys.insert(ti, (ax, tri));
        }
        // Wedges: union-find across the faces inside the star that are not
        // on the surface.
        let mut parent: Vec<usize> = (0..star.len()).collect();
        fn root(p: &mut [usize], mut i: usize) -> usize {
            while p[i] != i {
                p[i] = p[p[i]];
                i = p[i];
            }
            i
        }
        for (i, &t) in star.iter().enumerate() {
            let tv = c.tv[t as usize];
            for f in 0..4 {
                let fv = face(tv, f);
                if face_tri.contains_key(&fkey(fv)) {
                    continue;
                }
                let Some(j) = at(c.nb[t as usize][f] >> 2) else {
                    continue;
                };
                let (ri, rj) = (root(&mut parent, i), root(&mut parent, j));
                parent[ri.max(rj)] = ri.min(rj);
            }
        }
        // Per wedge: its tetrahedra.
        let mut wedges: Vec<Vec<usize>> = Vec::new();
        let mut wid: IdMap<usize, usize> = IdMap::default();
        for i in 0..star.len() {
            let r = root(&mut parent, i);
            let w = *wid.entry(r).or_insert_with(|| {
                wedges.push(Vec::new());
                wedges.len() - 1
            });
            wedges[w].push(i);
        }
        let mut all_pts: Vec<P> = pts.to_vec();
        let mut new: Vec<[u32; 4]> = Vec::new();
        let mut added = 0;
        // The removed tetrahedra: the star and what wedges grew by.
        let mut removed: Vec<u32> = star.clone();
        // Surface faces, never grown across.
        let mut prot = Protected::default();
        for w in &wedges {
            let ghosts = w
                .iter()
                .filter(|&&i| c.tv[star[i] as usize].contains(&INF))
                .count();
            // Faces of the wedge's boundary kept: those at no point of
            // `sset` (on the surface or towards the rest of the mesh).
            let mut link: Vec<LinkFace> = Vec::new();
            // Surface faces of the wedge (inward) at a point of `sset`.
            let mut fans: Vec<([u32; 3], u32)> = Vec::new();
            for &i in w {
                let t = star[i];
                let tv = c.tv[t as usize];
                for f in 0..4 {
                    let fv = face(tv, f);
                    let k = fkey(fv);
                    if touches(&fv) {
                        if let Some(&ti) = face_tri.get(&k) {
                            if !polys[&ti].1.is_empty() {
                                fans.push((fv, ti));
                            }
                        }
                    } else if face_tri.contains_key(&k) || at(c.nb[t as usize][f] >> 2).is_none() {
                        link.push((fv, t, f));
                    }
                }
            }
            // The new triangles of the wedge's polygons, oriented like its
            // old surface faces there; the wedge must hold each polygon's
            // whole fan.
            let mut bound: Vec<[u32; 3]> = Vec::new();
            let mut seen: Vec<u32> = Vec::new();
            for &(fv, ti) in &fans {
                if seen.contains(&ti) {
                    continue;
                }
                seen.push(ti);
                if fans.iter().filter(|x| x.1 == ti).count() != fan_count[&ti] {
                    return None;
                }
                let (ax, tris) = polys.get(&ti)?;
                let pr = |w: u32| project(&pts[w as usize], *ax);
                let [x, y, z] = fv.map(pr);
                let sign = orient2d(&x, &y, &z);
                if sign == 0.0 {
                    return None;
                }
                for t in tris {
                    bound.push(if sign > 0.0 { *t } else { [t[0], t[2], t[1]] });
                }
            }
            *had_ghosts |= ghosts > 0;
            // Faces opposite `s` through the point at infinity (the
            // wedge's ghosts), coned from the new point like the others.
            let mut ghost_link: Vec<[u32; 3]> = Vec::new();
            if ghosts > 0 && cone_ghosts {
                ghost_link.extend(link.iter().map(|l| l.0).filter(|f| f.contains(&INF)));
                link.retain(|l| !l.0.contains(&INF));
            }
            if ghosts > 0 && !cone_ghosts {
                // A wedge reaching the convex hull is outside the domain:
                // it becomes outside the hull, ghosts on the new triangles
                // and on its finite faces kept (a face kept that is on the
                // hull takes the ghost behind it along instead), oriented
                // like the wedge's faces there. Nothing here is geometric:
                // ghosts have no orientation, and the chain check of
                // `valid_star` vouches for the gluing.
                let ghost = |t: [u32; 3]| {
                    let g = [t[0], t[1], t[2], INF];
                    if okey(face(g, 3)) == okey(t) {
                        g
                    } else {
                        [t[0], t[2], t[1], INF]
                    }
                };
                new.extend(bound.into_iter().map(ghost));
                for (fv, t, f) in link {
                    if fv.contains(&INF) {
                        continue;
                    }
                    let n = c.nb[t as usize][f] >> 2;
                    if at(n).is_none() && c.tv[n as usize].contains(&INF) {
                        if let Err(pos) = removed.binary_search(&n) {
                            removed.insert(pos, n);
                        }
                    } else {
                        new.push(ghost(fv));
                    }
                }
                continue;
            }
            let id = all_pts.len() as u32;
            if !ghost_link.is_empty() && sset.len() != 1 {
                return None;
            }
            let near = match sset {
                [s] => self.near_point(
                    cm,
                    *s,
                    &fans,
                    &bound,
                    &link,
                    &all_pts,
                    &mut removed,
                    face_tri,
                ),
                _ => None,
            };
            let tets = match near {
                Some((p, link)) => {
                    if !self.off_surface(&all_pts, &p) {
                        return None;
                    }
                    all_pts.push(p);
                    added += 1;
                    bound
                        .into_iter()
                        .chain(link.into_iter().map(|l| l.0))
                        .chain(ghost_link.iter().copied())
                        .map(|f| inf_last([f[0], f[1], f[2], id]))
                        .collect()
                }
                // A wedge with ghosts is filled by a cone or not at all.
                None if !ghost_link.is_empty() => return None,
                None => {
                    if prot.faces.is_empty() {
                        prot.faces.extend(face_tri.keys().copied());
                    }
                    let f = fill_wedge(cm, &all_pts, &bound, link, &mut removed, &prot, id)?;
                    if let Some(p) = f.point {
                        if !self.off_surface(&all_pts, &p) {
                            return None;
                        }
                        all_pts.push(p);
                        added += 1;
                    }
                    f.tets
                }
            };
            new.extend(tets);
        }
        // Interior Steiner points (not on the surface) that the removed
        // region swallows whole (a wedge outside the hull) may go unused.
        let n_in = self.n_fixed();
        let may_lose = |w: u32| {
            w as usize >= n_in
                && refined
                    .kind
                    .get(w as usize)
                    .is_none_or(|k| *k == super::super::surface::Kind::Input)
        };
        // A wedge made outside the hull must not pinch the outside region
        // at a vertex (two sheets of hull faces meeting there): a later
        // removal at that vertex could close no boundary. A single
        // point's wedges are then coned instead (see `pull_set`).
        if *had_ghosts
            && !cone_ghosts
            && sset.len() == 1
            && !hull_manifold_after(cm, &removed, &new)
        {
            return None;
        }
        if !valid_star(cm, &all_pts, &removed, &new, sset, may_lose) {
            return None;
        }
        // Update the surface faces: the fans give way to the polygons.
        for &t in &star {
            let tv = c.tv[t as usize];
            for f in 0..4 {
                let fv = face(tv, f);
                if touches(&fv) {
                    face_tri.remove(&fkey(fv));
                }
            }
        }
        for (&ti, (_, tris)) in &polys {
            for t in tris {
                face_tri.insert(fkey(*t), ti);
            }
        }
        for p in &all_pts[cm.pts().len()..] {
            cm.push_point(*p);
        }
        cm.replace(&removed, &new);
        Some(added)
    }

    /// A new point `p = s + h d` near surface point `s` that sees every
    /// face of a wedge strictly (module documentation, step 3): `bound`
    /// its new triangles, `link` its faces opposite `s`, `fans` its old
    /// surface faces; the wedge may grow by the tetrahedra behind faces
    /// opposite `s` (added to `removed`, sorted). The point and the faces
    /// opposite `s` of the grown wedge, or `None` (`removed` unchanged).
    #[allow(clippy::too_many_arguments)]
    fn near_point(
        &self,
        cm: &Journaled<'_>,
        s: u32,
        fans: &[([u32; 3], u32)],
        bound: &[[u32; 3]],
        link: &[LinkFace],
        all_pts: &[P],
        removed: &mut Vec<u32>,
        face_tri: &IdMap<[u32; 3], u32>,
    ) -> Option<(P, Vec<LinkFace>)> {
        let c = &cm.m;
        let pts = cm.pts();
        let mut link = link.to_vec();
        // Into the wedge: the unit normals of its input triangles,
        // oriented towards it, one per triangle (their sum points
        // strictly into every one's open half-space); then other
        // directions, each checked exactly.
        let sp = pts[s as usize];
        let mut normals: Vec<P> = Vec::new();
        let mut done: Vec<u32> = Vec::new();
        for &(fv, ti) in fans {
            if done.contains(&ti) {
                continue;
            }
            done.push(ti);
            let [a, b, cc] = fv.map(|w| pts[w as usize]);
            let nf = cross(&sub(&b, &a), &sub(&cc, &a));
            let [a, b, cc] = self.surf.tris[ti as usize].map(|w| pts[w as usize]);
            let mut n = cross(&sub(&b, &a), &sub(&cc, &a));
            let l = dot(&n, &n).sqrt();
            if l == 0.0 || !l.is_finite() {
                return None;
            }
            let sg = if dot(&n, &nf) < 0.0 { -1.0 } else { 1.0 };
            n = n.map(|x| sg * x / l);
            normals.push(n);
        }
        let mut reach = f64::INFINITY;
        let mut centre = [0.0; 3];
        let mut nc: f64 = 0.0;
        for f in bound.iter().chain(link.iter().map(|l| &l.0)) {
            for &x in f {
                if x != s {
                    let e = sub(&pts[x as usize], &sp);
                    reach = reach.min(dot(&e, &e).sqrt());
                    for k in 0..3 {
                        centre[k] += e[k];
                    }
                    nc += 1.0;
                }
            }
        }
        if !reach.is_finite() || reach == 0.0 {
            return None;
        }
        let mut dirs: Vec<P> = vec![normals
            .iter()
            .fold([0.0; 3], |d, n| [d[0] + n[0], d[1] + n[1], d[2] + n[2]])];
        dirs.push(centre.map(|x| x / nc.max(1.0)));
        dirs.extend(normals.iter().copied());
        // Growth: the tetrahedra behind the faces opposite `s` that the
        // best candidate does not see (nearly flat tetrahedra of
        // inexact surface points), never across the surface.
        let mut grown: Vec<u32> = Vec::new();
        let mut wedge: Vec<u32> = link.iter().map(|l| l.1).collect();
        wedge.sort_unstable();
        wedge.dedup();
        for _ in 0..=MAX_GROW {
            let nb = bound.len();
            let all: Vec<[u32; 3]> = bound
                .iter()
                .copied()
                .chain(link.iter().map(|l| l.0))
                .collect();
            let mut fewest: Option<Vec<usize>> = None;
            // Last, a direction into the tangent cone at `s` of the faces
            // whose planes pass (nearly) through it: the new triangles and
            // the faces of flat tetrahedra at `s`.
            let tangent = tangent_dir(pts, &sp, &all, reach);
            // Planes of the faces (floating), for the clearance of a
            // candidate: the one farthest from every face is taken, so
            // that later removals nearby do not meet nearly flat
            // tetrahedra at this point.
            let planes: Vec<(P, P)> = all
                .iter()
                .map(|f| {
                    let [a, b, cc] = f.map(|w| all_pts[w as usize]);
                    let n = cross(&sub(&b, &a), &sub(&cc, &a));
                    let l = dot(&n, &n).sqrt();
                    (a, n.map(|x| x / l))
                })
                .collect();
            let clearance = |p: &P| {
                planes
                    .iter()
                    .map(|(a, n)| dot(n, &sub(p, a)))
                    .fold(f64::INFINITY, f64::min)
            };
            // The faces a candidate does not see strictly (exact).
            let unseen = |p: &P| -> Vec<usize> {
                (0..all.len())
                    .filter(|&k| {
                        let [a, b, cc] = all[k].map(|w| &all_pts[w as usize]);
                        orient3d(a, b, cc, p) >= 0.0
                    })
                    .collect()
            };
            let mut best: Option<(P, f64)> = None;
            for d in dirs.iter().chain(tangent.iter()) {
                let dl = dot(d, d).sqrt();
                if dl == 0.0 || !dl.is_finite() {
                    continue;
                }
                let mut h = 0.25 * reach;
                let mut last = f64::NEG_INFINITY;
                for _ in 0..HALVINGS {
                    let p = [0, 1, 2].map(|k| sp[k] + h * d[k] / dl);
                    let bad = unseen(&p);
                    if bad.is_empty() {
                        // Along a ray the clearance rises, then falls.
                        let cl = clearance(&p);
                        if cl < last {
                            break;
                        }
                        last = cl;
                        if best.is_none_or(|b| cl > b.1) {
                            best = Some((p, cl));
                        }
                    } else if last > f64::NEG_INFINITY {
                        break;
                    } else if bad.iter().all(|&k| k >= nb)
                        && fewest.as_ref().is_none_or(|f| bad.len() < f.len())
                    {
                        fewest = Some(bad);
                    }
                    h *= 0.5;
                }
            }
            if best.is_none() {
                // No ray from `s` enters: the deepest point of the wedge's
                // kernel near `s` (thin slivers between nearly parallel
                // faces of flat tetrahedra at `s`); the faces it does not
                // see are the ones to grow across.
                if let Some((p, _)) = super::deepest_point(&planes, &sp, reach) {
                    let bad = unseen(&p);
                    if bad.is_empty() {
                        best = Some((p, 0.0));
                    } else if bad.iter().all(|&k| k >= nb)
                        && fewest.as_ref().is_none_or(|f| bad.len() < f.len())
                    {
                        fewest = Some(bad);
                    }
                }
            }
            if let Some((p, _)) = best {
                for &g in &grown {
                    if let Err(pos) = removed.binary_search(&g) {
                        removed.insert(pos, g);
                    }
                }
                return Some((p, link));
            }
            let bad = fewest?;
            let mut more = false;
            for k in bad {
                let (fv, t, f) = link[k - nb];
                let n = c.nb[t as usize][f] >> 2;
                let nv = c.tv[n as usize];
                if face_tri.contains_key(&fkey(fv))
                    || nv[0] == DEAD
                    || nv.contains(&INF)
                    || removed.binary_search(&n).is_ok()
                    || grown.contains(&n)
                {
                    continue;
                }
                grown.push(n);
                more = true;
            }
            if !more {
                return None;
            }
            // The wedge's faces opposite `s`, with the grown tetrahedra.
            let mut set: Vec<u32> = wedge.clone();
            set.extend(&grown);
            link.clear();
            for &t in &set {
                let tv = c.tv[t as usize];
                for f in 0..4 {
                    let fv = face(tv, f);
                    // Faces at `s` are its surface faces (new triangles).
                    if !set.contains(&(c.nb[t as usize][f] >> 2)) && !fv.contains(&s) {
                        link.push((fv, t, f));
                    }
                }
            }
        }
        None
    }
}

/// A unit direction `d` with `d·n > 0` for the inward unit normal `n` of
/// every face of `faces` whose plane passes within a small multiple of
/// `reach` of `s` (floating; the caller checks exactly), found by
/// relaxation (Agmon–Motzkin) with shrinking margins: near a surface
/// point whose star has nearly flat tetrahedra the points that see every
/// face lie in a thin wedge along such a direction, not along the
/// surface normals.
fn tangent_dir(pts: &[P], s: &P, faces: &[[u32; 3]], reach: f64) -> Option<P> {
    let mut ns: Vec<P> = Vec::new();
    for f in faces {
        let [a, b, c] = f.map(|w| pts[w as usize]);
        let n = cross(&sub(&b, &a), &sub(&c, &a));
        let l = dot(&n, &n).sqrt();
        if l == 0.0 || !l.is_finite() {
            return None;
        }
        let n = n.map(|x| x / l);
        if dot(&n, &sub(s, &a)) <= 1e-9 * reach {
            ns.push(n);
        }
    }
    let unit = |d: P| {
        let l = dot(&d, &d).sqrt();
        (l > 0.0 && l.is_finite()).then(|| d.map(|x| x / l))
    };
    let mut d = unit(
        ns.iter()
            .fold([0.0; 3], |d, n| [d[0] + n[0], d[1] + n[1], d[2] + n[2]]),
    )?;
    for round in 0..10 {
        let margin = 0.1 / f64::from(1u32 << (3 * round));
        for _ in 0..64 {
            let Some((i, m)) = ns
                .iter()
                .map(|n| dot(n, &d))
                .enumerate()
                .min_by(|a, b| a.1.total_cmp(&b.1))
            else {
                return Some(d);
            };
            if m >= margin {
                return Some(d);
            }
            let n = ns[i];
            d = unit([0, 1, 2].map(|k| d[k] + 1.5 * (margin - m) * n[k]))?;
        }
    }
    ns.iter().all(|n| dot(n, &d) > 0.0).then_some(d)
}

/// Projection of `p` dropping coordinate `ax`.
pub(super) fn project(p: &P, ax: usize) -> [f64; 2] {
    match ax {
        0 => [p[1], p[2]],
        1 => [p[2], p[0]],
        _ => [p[0], p[1]],
    }
}

/// The polygon covered by the `fan` of faces at the points `sset`
/// (sorted; unoriented keys), as a cycle without them, triangulated by
/// ear clipping in the projection along `ax`: 2D-counterclockwise
/// triangles, or `None`. The fan's boundary (its edges used once) is a
/// cycle through the points of `sset` on the triangle's edges; each of
/// those is cut out (its two neighbours joined by a chord, on the edge's
/// line), so the polygon's vertices are the fan's other vertices.
fn polygon_without(
    pts: &[P],
    fan: &[[u32; 3]],
    sset: &[u32],
    ax: usize,
    flat: impl Fn([u32; 3]) -> bool,
) -> Option<Vec<[u32; 3]>> {
    let in_s = |w: u32| sset.binary_search(&w).is_ok();
    // Boundary edges and the adjacency of their vertices.
    let mut count: IdMap<(u32, u32), u32> = IdMap::default();
    for f in fan {
        for (i, j) in [(0, 1), (0, 2), (1, 2)] {
            *count.entry((f[i], f[j])).or_insert(0) += 1;
        }
    }
    let mut adj: IdMap<u32, Vec<u32>> = IdMap::default();
    for f in fan {
        for (i, j) in [(0, 1), (0, 2), (1, 2)] {
            if count[&(f[i], f[j])] == 1 {
                adj.entry(f[i]).or_default().push(f[j]);
                adj.entry(f[j]).or_default().push(f[i]);
            }
        }
    }
    // Cut out the points of `sset` on the boundary.
    let mut chords: Vec<(u32, u32)> = Vec::new();
    for &s in sset {
        let Some(ns) = adj.remove(&s) else { continue };
        if ns.len() != 2 || ns[0] == ns[1] {
            return None;
        }
        let (x, y) = (ns[0], ns[1]);
        if adj.get(&x)?.contains(&y) {
            // Only `x s y` left (a thin face of points on one edge): the
            // polygon is the segment `x y`, no triangle.
            let only = adj.len() == 2 && adj[&x].len() == 2 && adj.get(&y)?.len() == 2;
            let inside = fan.iter().flatten().all(|&w| in_s(w) || w == x || w == y);
            return (only && inside).then(Vec::new);
        }
        for (a, b) in [(x, y), (y, x)] {
            let l = adj.get_mut(&a)?;
            let pos = l.iter().position(|&w| w == s)?;
            l[pos] = b;
        }
        chords.retain(|&(a, b)| a != s && b != s);
        chords.push((x.min(y), x.max(y)));
    }
    let mut verts: Vec<u32> = adj.keys().copied().collect();
    verts.sort_unstable();
    if verts.len() < 3 || adj.values().any(|v| v.len() != 2) {
        return None;
    }
    if fan
        .iter()
        .flatten()
        .any(|&w| !in_s(w) && verts.binary_search(&w).is_err())
    {
        return None;
    }
    // The cycle: from the least chord end along the polygon (not the
    // chord) first, else from the least vertex.
    let is_chord = |a: u32, b: u32| chords.contains(&(a.min(b), a.max(b)));
    let start = chords.iter().map(|c| c.0).min().unwrap_or(verts[0]);
    let first = adj[&start]
        .iter()
        .copied()
        .find(|&x| !is_chord(start, x))
        .unwrap_or(adj[&start][0]);
    let mut cyc = vec![start];
    let (mut prev, mut cur) = (start, first);
    while cur != start {
        if cyc.contains(&cur) {
            return None;
        }
        cyc.push(cur);
        let n = &adj[&cur];
        let next = if n[0] != prev { n[0] } else { n[1] };
        prev = cur;
        cur = next;
    }
    if cyc.len() != verts.len() {
        return None;
    }
    let p2: Vec<[f64; 2]> = cyc.iter().map(|&w| project(&pts[w as usize], ax)).collect();
    // Counterclockwise.
    let mut area = 0.0;
    for i in 0..p2.len() {
        let (a, b) = (p2[i], p2[(i + 1) % p2.len()]);
        area += a[0] * b[1] - a[1] * b[0];
    }
    let mut idx: Vec<usize> = (0..cyc.len()).collect();
    if area < 0.0 {
        idx.reverse();
    }
    let mut out = Vec::new();
    while idx.len() > 3 {
        let n = idx.len();
        // Of the ears, the roundest (twice its area over its longest edge
        // squared): thin ears tilt out of the triangle's plane.
        let ear = (0..n)
            .filter(|&i| {
                let (u, v, w) = (idx[(i + n - 1) % n], idx[i], idx[(i + 1) % n]);
                if orient2d(&p2[u], &p2[v], &p2[w]) <= 0.0 || flat([cyc[u], cyc[v], cyc[w]]) {
                    return false;
                }
                // A diagonal along an input edge must pass no vertex of
                // that edge (it would leave a triangle of three of them).
                let d = [p2[w][0] - p2[u][0], p2[w][1] - p2[u][1]];
                let dd = d[0] * d[0] + d[1] * d[1];
                let between = |x: usize| {
                    let t = (p2[x][0] - p2[u][0]) * d[0] + (p2[x][1] - p2[u][1]) * d[1];
                    t > 0.0 && t < dd
                };
                if idx.iter().any(|&x| {
                    x != u && x != v && x != w && flat([cyc[u], cyc[w], cyc[x]]) && between(x)
                }) {
                    return false;
                }
                idx.iter().all(|&x| {
                    x == u
                        || x == v
                        || x == w
                        || orient2d(&p2[u], &p2[v], &p2[x]) < 0.0
                        || orient2d(&p2[v], &p2[w], &p2[x]) < 0.0
                        || orient2d(&p2[w], &p2[u], &p2[x]) < 0.0
                })
            })
            .map(|i| {
                let (u, v, w) = (idx[(i + n - 1) % n], idx[i], idx[(i + 1) % n]);
                (roundness(&p2[u], &p2[v], &p2[w]), i)
            })
            .max_by(|a, b| a.0.total_cmp(&b.0).then(b.1.cmp(&a.1)))?
            .1;
        let (u, v, w) = (idx[(ear + n - 1) % n], idx[ear], idx[(ear + 1) % n]);
        out.push([cyc[u], cyc[v], cyc[w]]);
        idx.remove(ear);
    }
    let (u, v, w) = (idx[0], idx[1], idx[2]);
    if orient2d(&p2[u], &p2[v], &p2[w]) <= 0.0 || flat([cyc[u], cyc[v], cyc[w]]) {
        return None;
    }
    out.push([cyc[u], cyc[v], cyc[w]]);
    Some(out)
}

/// Twice the area of `a b c` over its longest edge squared.
fn roundness(a: &[f64; 2], b: &[f64; 2], c: &[f64; 2]) -> f64 {
    let d2 = |p: &[f64; 2], q: &[f64; 2]| (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2);
    let area2 = ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])).abs();
    let l = d2(a, b).max(d2(b, c)).max(d2(c, a));
    if l > 0.0 {
        area2 / l
    } else {
        0.0
    }
}

/// Whether, once the cells `removed` (sorted) are replaced by `new`, the
/// hull faces at every vertex of a new ghost cell form one cycle around
/// it (or there are none): the hull stays a manifold there.
fn hull_manifold_after(cm: &Journaled<'_>, removed: &[u32], new: &[[u32; 4]]) -> bool {
    // Ghost cells hold the point at infinity last (the mesh invariant;
    // the new ones are made so): their first three vertices are the hull
    // face.
    let mut verts: Vec<u32> = new
        .iter()
        .filter(|tv| tv[3] == INF)
        .flat_map(|tv| [tv[0], tv[1], tv[2]])
        .collect();
    verts.sort_unstable();
    verts.dedup();
    for &v in &verts {
        // The link of `v` in the hull: one edge per hull face at `v`.
        let mut edges: Vec<(u32, u32)> = cm
            .star(v)
            .into_iter()
            .filter(|t| removed.binary_search(t).is_err())
            .map(|t| cm.m.tv[t as usize])
            .chain(new.iter().copied())
            .filter(|tv| tv[3] == INF && tv[..3].contains(&v))
            .map(|tv| match tv[..3].iter().position(|&w| w == v) {
                // The other two hull-face vertices, in cell order.
                Some(0) => (tv[1], tv[2]),
                Some(1) => (tv[0], tv[2]),
                _ => (tv[0], tv[1]),
            })
            .collect();
        if edges.is_empty() {
            continue;
        }
        // One cycle: walk it from the first edge; every edge is met once.
        let n = edges.len();
        let (start, mut cur) = edges.swap_remove(0);
        let mut walked = 1;
        while cur != start {
            let Some(i) = edges.iter().position(|e| e.0 == cur || e.1 == cur) else {
                return false;
            };
            let e = edges.swap_remove(i);
            cur = if e.0 == cur { e.1 } else { e.0 };
            walked += 1;
        }
        if walked != n {
            return false;
        }
    }
    true
}

/// `tv` with the point at infinity (if any) moved last by an even
/// permutation (same orientation): ghost cells hold it last.
fn inf_last(mut tv: [u32; 4]) -> [u32; 4] {
    if let Some(i) = tv[..3].iter().position(|&w| w == INF) {
        tv.swap(i, 3);
        let (j, k) = match i {
            0 => (1, 2),
            1 => (0, 2),
            _ => (0, 1),
        };
        tv.swap(j, k);
    }
    tv
}

/// Fills a wedge bounded by `bound` (its new triangles) and `link` (its
/// faces kept, with the tetrahedron behind each) by a cone from one of
/// its vertices, else by gift-wrapping (`dfill::wrap_fill`, no new
/// point), else from a kernel point (id `id`), growing it by the
/// tetrahedra behind the faces the best point found does not see (never
/// across a surface face of `prot`, a ghost, or a tetrahedron of
/// `removed`) until it fills or would exceed [`super::MAX_CAVITY`]
/// tetrahedra (each step adds one at least); the grown tetrahedra are
/// added to `removed` (sorted) on success. Unlike the cavities of the
/// parent module, whose growth stops after [`super::MAX_GROW`] steps
/// (the interior point rounds come after them), a wedge that does not
/// fill here leaves its surface point on the surface, and the whole
/// fallback starts again from a new recovery: on a held-out tube
/// (`cad_shapes.py` seed 501) the last of 309 points filled after
/// growing by 83 tetrahedra, and `-pY` took 1.1 s instead of 1.9.
fn fill_wedge(
    cm: &Journaled<'_>,
    pts: &[P],
    bound: &[[u32; 3]],
    link: Vec<LinkFace>,
    removed: &mut Vec<u32>,
    prot: &Protected,
    id: u32,
) -> Option<Fill> {
    let mut reg = Region {
        faces: bound.iter().map(|&f| (f, DEAD, 0)).chain(link).collect(),
    };
    let taken: IdSet<u32> = removed.iter().copied().collect();
    let mut set: Vec<u32> = Vec::new();
    for _ in 0..=super::MAX_CAVITY {
        let tris = reg.tris();
        let got = match fill(pts, &tris, &reg.vertices(), false, id) {
            Ok(f) => Ok(f),
            // No cone: the gift-wrapping fill (no new point; exact tests
            // with symbolic perturbation), else a kernel point.
            Err(_) => match super::dfill::wrap_fill(pts, &tris) {
                Some(tets) => Ok(Fill { tets, point: None }),
                None => fill(pts, &tris, &[], true, id),
            },
        };
        match got {
            Ok(f) => {
                removed.extend(set);
                removed.sort_unstable();
                return Some(f);
            }
            Err(best) => {
                if !grow(cm, &mut reg, &mut set, &taken, Some(&best), None, prot) {
                    return None;
                }
            }
        }
    }
    None
}

/// Exact validation of replacing the star `old` (sorted) of the points
/// `sset` (sorted) by `new` (module documentation).
fn valid_star(
    cm: &Journaled<'_>,
    pts: &[P],
    old: &[u32],
    new: &[[u32; 4]],
    sset: &[u32],
    may_lose: impl Fn(u32) -> bool,
) -> bool {
    let c = &cm.m;
    let in_s = |w: u32| sset.binary_search(&w).is_ok();
    for tv in new {
        if tv.iter().any(|&w| in_s(w)) || tv.iter().any(|&w| w != INF && w as usize >= pts.len()) {
            return false;
        }
        if !tv.contains(&INF) {
            let g = |i: usize| &pts[tv[i] as usize];
            if orient3d(g(0), g(1), g(2), g(3)) >= 0.0 {
                return false;
            }
        }
    }
    let Some(super::NewParts {
        verts: new_verts,
        edges: new_edges,
        ..
    }) = super::fills(cm, old, new)
    else {
        return false;
    };
    let mut old_edges: IdSet<(u32, u32)> = IdSet::default();
    for &t in old {
        let tv = c.tv[t as usize];
        if tv[0] == DEAD {
            return false;
        }
        for i in 0..4 {
            if !in_s(tv[i]) && !new_verts.contains(&tv[i]) && (tv[i] == INF || !may_lose(tv[i])) {
                return false;
            }
            for j in i + 1..4 {
                old_edges.insert((tv[i].min(tv[j]), tv[i].max(tv[j])));
            }
        }
    }
    // A new edge between old vertices must not exist outside the star.
    let n_old = cm.pts().len();
    new_edges.iter().all(|&(x, y)| {
        old_edges.contains(&(x, y))
            || y == INF
            || x as usize >= n_old
            || y as usize >= n_old
            || cm.find_edge(x, y).is_none()
    })
}

#[cfg(test)]
pub(super) mod tests {
    use super::super::super::surface::Surface;
    use super::super::super::RecoverOptions;
    use super::*;
    use crate::tet::dmesh::tests::cuboid;

    /// A `-Y` state for the surface `tris` on `n` points.
    pub(in crate::tet::recover::cavity) fn state(n: usize, tris: &[[u32; 3]]) -> State {
        State::new(
            Surface::new(n, tris),
            RecoverOptions {
                preserve_surface: true,
                ..Default::default()
            },
        )
    }

    /// The hull-manifold test of the pull-off: the ghost cells at a
    /// hull vertex replaced by themselves keep one cycle of hull faces
    /// there; one of them left out (a gap) or one more sheet of hull
    /// faces at the vertex (a pinch) is refused.
    #[test]
    fn hull_manifold_after_sees_gaps_and_pinches() {
        let (mut pts, _) = cuboid(2.0, 1.0, 1.5);
        pts.push([1.0, 0.5, 0.75]);
        let dt = Delaunay3::from_points(&pts).unwrap();
        let cm = Journaled::new(dt);
        for v in 0..8u32 {
            let mut ghosts: Vec<u32> = cm
                .star(v)
                .into_iter()
                .filter(|&t| cm.m.tv[t as usize].contains(&INF))
                .collect();
            ghosts.sort_unstable();
            assert!(ghosts.len() >= 3, "vertex {v}");
            let cells: Vec<[u32; 4]> = ghosts.iter().map(|&t| cm.m.tv[t as usize]).collect();
            assert!(hull_manifold_after(&cm, &ghosts, &cells), "vertex {v}");
            assert!(hull_manifold_after(&cm, &[], &[]), "vertex {v}");
            assert!(
                !hull_manifold_after(&cm, &ghosts, &cells[1..]),
                "vertex {v}"
            );
            // A second sheet at `v`: a ghost on an inner face at it.
            let mut more = cells.clone();
            more.push(inf_last([v, 8, (v + 1) % 8, INF]));
            assert!(!hull_manifold_after(&cm, &ghosts, &more), "vertex {v}");
        }
    }

    /// Moving the point at infinity last keeps the orientation (an even
    /// permutation of the cell's vertices).
    #[test]
    fn inf_last_is_an_even_permutation() {
        let parity = |a: [u32; 4], b: [u32; 4]| {
            let pos: Vec<usize> = b
                .iter()
                .map(|x| a.iter().position(|y| y == x).unwrap())
                .collect();
            let mut inv = 0;
            for i in 0..4 {
                for j in i + 1..4 {
                    inv += usize::from(pos[i] > pos[j]);
                }
            }
            inv % 2
        };
        for i in 0..4 {
            let mut tv = [1, 2, 3, 4];
            tv[i] = INF;
            let g = inf_last(tv);
            assert_eq!(g[3], INF);
            assert_eq!(parity(tv, g), 0, "{tv:?} -> {g:?}");
        }
    }

    /// Schönhardt's twisted prism, each side split by its reflex diagonal.
    fn schonhardt(twist: f64) -> (Vec<P>, Vec<[u32; 3]>) {
        let mut pts = Vec::new();
        for (k, z) in [(0.0, 0.0), (twist, 1.0)] {
            for i in 0..3 {
                let a = (120.0 * f64::from(i) + k).to_radians();
                pts.push([a.cos(), a.sin(), z]);
            }
        }
        let hull: Vec<[u32; 3]> = crate::tetrahedralize(&pts).unwrap().hull_faces().collect();
        let hull_edge = |a: u32, b: u32| hull.iter().any(|f| f.contains(&a) && f.contains(&b));
        let mut tris = vec![[0, 2, 1], [3, 4, 5]];
        for i in 0..3u32 {
            let j = (i + 1) % 3;
            let (a0, a1, b0, b1) = (i, j, i + 3, j + 3);
            if hull_edge(a0, b1) {
                tris.push([a0, a1, b0]);
                tris.push([a1, b1, b0]);
            } else {
                tris.push([a0, a1, b1]);
                tris.push([a0, b1, b0]);
            }
        }
        (pts, tris)
    }

    /// The polygon left by a surface point `s` whose fan reaches an input
    /// edge with three rounded Steiner points on it, the middle one a
    /// unit in the last place off the line (convex in floating point):
    /// with the points of that edge collinear by construction, no new
    /// triangle has three of them, and the triangles tile the polygon.
    #[test]
    fn polygon_without_cuts_no_ear_of_one_edge() {
        for dy in [-1e-15, -3e-16, 1e-15] {
            // 0..=4 on the edge y = 0 (ends 0 and 4), 5 the third corner.
            let mut pts: Vec<P> = vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [2.0, dy, 0.0],
                [3.0, 0.0, 0.0],
                [4.0, 0.0, 0.0],
                [0.0, 4.0, 0.0],
            ];
            // `s` = 6, inside; its fan over the cycle 0 1 2 3 4 5.
            pts.push([1.5, 1.0, 0.0]);
            let fan: Vec<[u32; 3]> = (0..6u32).map(|i| [6, i, (i + 1) % 6]).collect();
            let on_edge = |w: u32| w <= 4;
            let flat = |f: [u32; 3]| f.iter().all(|&w| on_edge(w));
            let tris = polygon_without(&pts, &fan, &[6], 2, flat).unwrap();
            assert_eq!(tris.len(), 4, "{tris:?}");
            let mut area = 0.0;
            for t in &tris {
                assert!(!flat(*t), "sliver {t:?}");
                let [a, b, c] = t.map(|w| project(&pts[w as usize], 2));
                let o = orient2d(&a, &b, &c);
                assert!(o > 0.0, "{t:?}");
                area += o;
            }
            // Twice the polygon's area: 4 * 4 (up to the bump at 2).
            assert!((area - 16.0).abs() < 1e-9, "{area}");
        }
    }

    /// Models on which the `-p` path splits edges and triangles (and thin
    /// boxes, on which it may not); the fallback must leave every input
    /// triangle one face, a valid mesh, and no used point on the surface
    /// but the input vertices.
    #[test]
    fn fallback_pulls_points_off_the_surface() {
        let mut total = 0;
        let mut models: Vec<(Vec<P>, Vec<[u32; 3]>)> = [10.0, 30.0, 55.0].map(schonhardt).to_vec();
        for (w, d, h) in [(10.0, 1.0, 0.001), (1.0, 1.0, 1e-6), (100.0, 0.01, 1.0)] {
            models.push(cuboid(w, d, h));
        }
        for (pts, tris) in models {
            let st = state(pts.len(), &tris);
            let (st2, cm, on) = st.preserve_fallback(&pts).unwrap();
            // Valid mesh: positive finite tetrahedra, symmetric adjacency
            // with matching faces (the removed points are left unused).
            let c = &cm.m;
            for (t, tv) in c.tv.iter().enumerate() {
                if tv[0] == DEAD {
                    continue;
                }
                assert!(tv.contains(&INF) || cm.positive(*tv), "{tv:?}");
                for f in 0..4 {
                    let w = c.nb[t][f];
                    let (n, g) = ((w >> 2) as usize, (w & 3) as usize);
                    assert_eq!(c.nb[n][g] >> 2, t as u32);
                    assert_eq!(fkey(face(*tv, f)), fkey(face(c.tv[n], g)));
                }
            }
            assert_eq!(on.len(), tris.len());
            for t in &tris {
                assert!(cm.find_face(t[0], t[1], t[2]).is_some(), "{t:?}");
            }
            let c = &cm.m;
            for tv in &c.tv {
                if tv[0] == DEAD {
                    continue;
                }
                for &w in tv {
                    if w != INF && w as usize >= pts.len() {
                        assert!(st2.off_surface(cm.pts(), &cm.pts()[w as usize]));
                    }
                }
            }
            assert_eq!(
                st2.report.steiner_on_edges + st2.report.steiner_on_facets,
                0
            );
            total += st2.report.steiner_interior;
        }
        assert!(total > 0, "the -p path put no point on the surface");
    }
}
