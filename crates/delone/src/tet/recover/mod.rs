//! Boundary recovery: a tetrahedralization of the inside of a closed
//! triangulated surface whose faces include (a refinement of) every input
//! triangle.
//!
//! The pipeline of [`recover`]:
//!
//! 1. **validation** — indices, coordinates, degenerate triangles and exact
//!    self-intersections ([`super::intersect::check_self_intersections`]),
//!    closedness ([`super::intersect::manifold_report`]) — for large inputs
//!    on a second thread while step 2 builds the Delaunay
//!    tetrahedralization (its verdict is checked first: same errors);
//! 2. **Delaunay** tetrahedralization of the surface vertices
//!    ([`super::Delaunay3`]); then, with [`RecoverOptions::merge_coplanar`],
//!    groups of coplanar input triangles are re-triangulated using the
//!    Delaunay edges on their plane (the private `merge` module); the
//!    result, [`Recovered::surface`], is what the next steps recover
//!    ("input triangles" below); [`missing`] tells which edges and
//!    triangles are absent;
//! 3. **recovery by flips, splits where they fail** — each round copies
//!    the Delaunay tetrahedralization into a mesh that need not stay
//!    Delaunay (the domain mesh with ghost cells and a journal of the
//!    private `tet::dmesh` module) and recovers missing subsegments, then
//!    missing triangles, by 2-3 flips and edge removals (n-to-2n-4 flips,
//!    chosen by dynamic programming over the edge ring; coplanar hull faces
//!    by the hull 2-2 flip; the private `cdt` module); with
//!    [`RecoverOptions::stop_circling_flips`] (`-p` without `-q`) and with
//!    [`RecoverOptions::preserve_surface`] (`-Y`, and its fallback's
//!    recovery), a segment's flips try first, at their
//!    first step and every third one, one cone from an end over the cells
//!    the segment crosses, grown
//!    past the faces blocking the cone (the flips alone go in circles on
//!    the degenerate cells of tubes and turned parts), and an edge whose
//!    faces cannot be flipped has, one level deeper, only the edges that
//!    block those flips removed (TetGen's flip-n-m recursion; the `-q`
//!    path tries both ring edges of every face). Flips never destroy a
//!    subsegment or a face already on an input triangle. Only the items the
//!    flips cannot recover are split in the Delaunay tetrahedralization, and
//!    the round starts again (without `stop_circling_flips`, the recovery
//!    that comes before a refinement, until it stops making progress or
//!    splits too much: the guided recovery then starts over, see
//!    `STALL_ROUNDS` and `CASCADE`):
//!    - a missing subsegment is split by a Steiner point on it (the notes
//!      of the private `place` module explain where, and how exactness is
//!      checked), inserted by the Delaunay kernel, and the input triangles
//!      sharing that edge are refined with it;
//!    - for a missing input triangle (recovered when the mesh faces on it
//!      cover it exactly, see below) the mesh edges crossing its interior
//!      are found exactly (first among the tetrahedra around the edges
//!      bounding its uncovered part, then among all edges) and a Steiner
//!      point is inserted where one crosses it (or, when that point
//!      encroaches a boundary subsegment of the triangle, the subsegment is
//!      split instead, Shewchuk's rule — at most twice per triangle except
//!      in the `-Y` fallback: every point of an obtuse sliver encroaches
//!      its long side, and on nearly coplanar slivers the splits alone
//!      never end). When no crossing edge is found
//!      (possible only because of inexact Steiner points), the longest edge
//!      around the uncovered part is split.
//!
//!    Each round either finishes, splits at least one item, or fails with a
//!    typed error ([`RecoverError::SteinerBudget`] when the Steiner budget
//!    is exhausted, [`RecoverError::Unrecovered`] naming the triangles by
//!    index when no progress is possible — never looped on), so the loop is
//!    bounded by the Steiner budget;
//! 4. **carving** — the constraint faces cut the cells into components;
//!    the exterior, hole components and even-depth cavities are removed,
//!    the rest are regions ([`Domain`], the `carve` module's notes).
//!
//! The input must have every edge in two or more triangles: a closed
//! surface, or facets that divide space into several closed parts
//! (internal facets, non-manifold edges), each then a region of its own.
//!
//! Rounds after the first do not redo the flips from scratch: the mesh
//! records every flip and edge removal as "these tetrahedra (vertex sets)
//! became those", and the next round first replays that log on its new
//! Delaunay tetrahedralization. An operation is re-applied only when all
//! the tetrahedra it removed are present (same vertex sets, so the same
//! cells: the replacement is valid as it was) and it destroys nothing
//! protected in the new round; the Delaunay tetrahedralization changed only
//! around the points inserted since, so nearly all apply and only the
//! items still missing there are searched. The flips of a segment whose
//! recovery fails are rolled back, so the log holds no useless flips; it
//! is retried once the round's other segments are done, as long as a pass
//! recovers one, when their flips removed a tetrahedron at one of its
//! vertices (its failed flips' vertices included): they often clear its
//! way, and each segment recovered so is a split, and often a round,
//! saved. With [`RecoverOptions::stop_circling_flips`] the segments still
//! failing then go through deeper levels of flips (levels 3 to
//! `P_MAX_LEVEL`, the work growing linearly), where a failed attempt keeps
//! its flips, so each level goes on from where the last one left the
//! segment (TetGen's flip levels); the levels stop at the first that
//! recovers no segment, whose flips are rolled back (kept, they make the
//! triangles harder). On tubes with rings of holes this recovers nearly
//! every segment the passes miss (the bundled `tube_rings_pierced`: 1535
//! Steiner points in 26 rounds without the levels, 106 in one round with
//! them). The
//! coverage, the missing subsegments and the protected items are updated
//! near the new points instead of recomputed.
//!
//! With [`RecoverOptions::stop_circling_flips`] (`-p` without `-q`) a
//! split does not undo the round's flips: a Delaunay insertion redoes every
//! cell whose circumsphere holds the point — on a tube all of them, as the
//! points of its two end circles are cospherical — so replay re-applied
//! only a fraction of the log and the segments recovered in one round were
//! missing again in the next (w_tube_a: 133 of 201 in round 2), giving a
//! cascade of rounds and splits. Instead the point of a failing subsegment
//! goes, besides the Delaunay tetrahedralization, into the flipped mesh by
//! a constrained Bowyer–Watson insertion (the cells whose circumsphere
//! holds it, not crossing a protected face, shrunk until its cone is valid
//! and no protected edge or vertex is inside:
//! `Journaled::insert_constrained`), and its halves are recovered by flips
//! in the same round, each failing half split in turn (at most
//! `MAX_SPLIT_DEPTH` times per subsegment and `IN_PLACE_PER_SEGMENT`
//! points per failing subsegment and round). The triangles are then
//! recovered in the same mesh; when their splits go into it in place too,
//! the next round goes on in it (no copy of the Delaunay
//! tetrahedralization, no replay) and its facet points are placed where its
//! own edges cross the triangles. The point is located by a walk, and
//! where the flips left cells the walk cannot cross towards it (it
//! circles in a mesh that is not Delaunay), by a scan of the cells. Where
//! a point is refused (on a hull edge,
//! a protected item, or a cavity that shrinks to nothing valid) the round
//! ends and the next starts from the Delaunay tetrahedralization as above;
//! when pieces keep failing past the bounds, or `MAX_STALLED` carried
//! rounds leave as many triangles missing, the next round starts from the
//! Delaunay tetrahedralization (with every point so far) and the rounds
//! after it split and carry in place again; the second time of each, the
//! segment splits stay with the Delaunay insertions (their points give the
//! flips more room on nearly coplanar slivers, where halves split in place
//! and recovered at once keep failing). From then on a round's segment
//! splits go into both meshes (the flipped one by the same constrained
//! insertion) and the next round goes on in the flipped mesh, where the
//! halves get a round's passes and levels; starting each such round from
//! the Delaunay tetrahedralization instead, the replay re-applied a third
//! of the log or less and the levels redid their work every round.
//!
//! With [`RecoverOptions::preserve_surface`] (`-Y`) nothing is split.
//! The first round whose flips fail adds one interior point (the centroid
//! of the failing triangles' vertices) and the flips run again: on a
//! degenerate Delaunay tetrahedralization (cospherical vertices, as on an
//! extruded polygon) that point is what the flips need. When the next
//! round leaves not at least a quarter fewer items missing, the recovery
//! starts again from the Delaunay tetrahedralization without it, and then,
//! where the flips fail, the private `cavity` module retriangulates the
//! cavity of each missing edge or triangle (Si & Gärtner's cavity
//! retriangulation: the tetrahedra crossing a missing triangle, split by it
//! into an upper and a lower polyhedron, each filled by a cone from one of
//! its vertices or from a new point strictly inside its kernel, growing the
//! cavity a bounded number of times), with exact validation and Steiner
//! points strictly off the surface. When one call of it cannot finish,
//! the `cavity` module's fallback runs (recover with surface Steiner
//! points, by `-p`'s own recovery first, then pull each of them off the
//! surface: TetGen's way, cheaper
//! than more cavity rounds on flat CAD faces whose fan triangles leave
//! hundreds of edges to the cavities). Only when that fails too (a pulled
//! point the exact validation refuses) does the recovery go on with
//! points off the failing triangles (along their normals) inserted in the
//! Delaunay tetrahedralization and more cavity calls, at most
//! `MAX_INTERIOR_ROUNDS` rounds and three unfinished cavity calls; what
//! is still missing then is reported as [`RecoverError::Unrecovered`].
//!
//! Finally (`-Y`) every interior Steiner point whose star can be
//! retriangulated without it — by the cone from one of the star's
//! vertices, else by gift-wrapping — is removed (exact validation; the
//! `cavity` module's `prune`), as TetGen removes the points it no longer
//! needs: the cavities and the pulled-off surface points leave many
//! that only the recovery needed.
//!
//! Without `-Y`, each group of coplanar triangles merged by
//! [`RecoverOptions::merge_coplanar`] is recovered as **one polygon
//! facet** (the private `polygon` module): only its boundary edges are
//! segments, the edges inside it need not be mesh edges, and it is covered
//! when the mesh faces on its plane inside it cover it exactly (a flood
//! fill bounded by its boundary subsegments).
//!
//! Exact coverage test: the mesh faces whose three vertices all lie on input
//! triangle `T` (as recorded when they were created) and are not three
//! points of one edge of `T` are the faces on `T`. `T` is covered when the
//! edges of these faces used once are exactly the subsegments of `T`'s
//! boundary and every other edge is used twice: faces of a tetrahedralization
//! do not overlap, so such a set covers `T` exactly once. Two consequences
//! of inexact Steiner points are handled explicitly: a flat tetrahedron with
//! all four vertices on `T` contributes only its faces looking to `T`'s
//! positive side (with `-p` alone also one with three points of one side's
//! chain, which otherwise leaves `T` uncovered for good: the private
//! `surface` module's `coverage_local`), and a mesh edge joining two
//! non-consecutive points of a
//! side's chain (a chord) is accepted together with the thin faces of chain
//! points that close the gap. After carving, a kept cell between such a
//! chord's face and a thin face (two boundary faces on one triangle, flat)
//! is removed, its other two faces becoming the boundary
//! ([`RecoverReport::chord_slivers`]). With `-p` alone, an edge whose ring
//! is all points of an uncovered `T` (rounded off its plane, so the edge
//! meets the plane outside `T`) is removed by edge removal, which makes the
//! ring's faces on `T` (`cdt::remove_piercing`); no split would.
//!
//! # Costs
//!
//! A retried segment gets a quarter of the per-segment flip budget
//! (`cdt::SEG_OPS`, 128 flips). The global crossing-edge fallback filters
//! every edge and sorts only the crossing ones. The validation of step 1
//! runs on a second thread for inputs of 4096 or more triangles: the total
//! CPU time is unchanged, the gain is wall time on an idle second core.
//!
//! # References
//! J. R. Shewchuk, *Constrained Delaunay tetrahedralizations and provably good
//! boundary recovery* (2002); H. Si, K. Gärtner, *Meshing piecewise linear
//! complexes by constrained Delaunay tetrahedralizations* (2005);
//! L. Diazzi, D. Panozzo, A. Vaxman, M. Attene, *Constrained Delaunay
//! tetrahedrization: a robust and practical approach* (2023);
//! J. Ruppert, *A Delaunay refinement algorithm for quality 2-dimensional
//! mesh generation* (1995).

mod carve;
mod cavity;
mod cdt;
mod check;
mod compact;
mod merge;
mod missing;
mod place;
mod polygon;
mod state;
mod surface;
mod types;

use std::collections::HashSet;

pub use carve::Domain;
pub(crate) use check::facets;
pub use check::{check_recovered, surface_volume};
pub use missing::{missing, Missing};
pub use types::{MeshRegion, RecoverError, RecoverOptions, RecoverReport, Recovered};

use self::state::{FacesOn, GiveUp, RoundState, State, MAX_INTERIOR_ROUNDS};

use crate::geom::ids::{IdMap, IdSet};
use crate::tet::local::ekey;

use self::surface::{Kind, Surface};
use super::dmesh::journal::{Journaled, OpLog};
use super::dmesh::{Arrays, DomainMesh};
use super::intersect::{check_self_intersections_grouped, manifold_report};
use super::local::{DEAD, FACET, INF};
use super::{Delaunay3, TetMesh};
use crate::{Error, Inserted};

/// Tetrahedralizes the inside of the closed triangulated surface
/// (`points`, `triangles`), recovering every input triangle as a union of
/// mesh faces (see the [module documentation](self)).
///
/// # Errors
/// [`RecoverError::Input`] for invalid input (with the offending items),
/// [`RecoverError::OpenSurface`], [`RecoverError::SteinerBudget`],
/// [`RecoverError::SegmentTooShort`], [`RecoverError::Unrecovered`],
/// [`RecoverError::PointOnTriangle`] for a point of no triangle lying on
/// one.
///
/// ```
/// use delone::tet::recover::{check_recovered, recover, RecoverOptions};
/// // A unit cube, two triangles per side.
/// let pts: Vec<[f64; 3]> = (0..8)
///     .map(|i| [(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64])
///     .collect();
/// let tris = [
///     [0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
///     [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5],
/// ];
/// let r = recover(&pts, &tris, &RecoverOptions::default()).unwrap();
/// check_recovered(&pts, &tris, &r).unwrap();
/// assert_eq!(r.boundary.len(), 12 + 2 * r.report.steiner());
/// ```
pub fn recover(
    points: &[[f64; 3]],
    triangles: &[[u32; 3]],
    opts: &RecoverOptions,
) -> Result<Recovered, RecoverError> {
    recover_domain(points, triangles, opts, &Domain::default())
}

/// [`recover`] with hole and region points and the `-c` choice: the
/// triangles may also divide space into several closed parts (every edge
/// in two or more triangles), each a region (see [`Domain`]).
///
/// # Errors
/// As [`recover`], and [`RecoverError::SeedOnSurface`] for a hole or region
/// point on the surface.
///
/// ```
/// use delone::model::plc::Region;
/// use delone::tet::recover::{check_recovered, recover_domain, Domain, RecoverOptions};
/// // Two unit cubes side by side sharing the square x = 1 (an internal facet).
/// let pts: Vec<[f64; 3]> = (0..12)
///     .map(|i| [(i % 3) as f64, ((i / 3) % 2) as f64, (i / 6) as f64])
///     .collect();
/// let q = |a: u32, b: u32, c: u32, d: u32| [[a, b, c], [a, c, d]];
/// let mut tris = Vec::new();
/// for f in [q(0, 3, 4, 1), q(1, 4, 5, 2), q(6, 7, 10, 9), q(7, 8, 11, 10), q(0, 1, 7, 6),
///           q(1, 2, 8, 7), q(3, 9, 10, 4), q(4, 10, 11, 5), q(0, 6, 9, 3), q(2, 5, 11, 8),
///           q(1, 4, 10, 7)] {
///     tris.extend(f);
/// }
/// let dom = Domain {
///     regions: vec![Region { point: [1.5, 0.5, 0.5], attribute: 7.0, max_volume: None }],
///     ..Domain::default()
/// };
/// let r = recover_domain(&pts, &tris, &RecoverOptions::default(), &dom).unwrap();
/// check_recovered(&pts, &tris, &r).unwrap();
/// assert_eq!(r.regions.len(), 2);
/// // The seeded cube has attribute 7, the other one the next free number.
/// assert!(r.regions.iter().any(|g| g.seed == Some(0) && g.attribute == 7.0));
/// assert!(r.regions.iter().any(|g| g.seed.is_none() && g.attribute == 8.0));
/// assert!(r.regions.iter().all(|g| (g.volume - 1.0).abs() < 1e-12));
/// assert!(r.interior_faces.len() >= 2); // the square x = 1, maybe refined
/// ```
pub fn recover_domain(
    points: &[[f64; 3]],
    triangles: &[[u32; 3]],
    opts: &RecoverOptions,
    domain: &Domain,
) -> Result<Recovered, RecoverError> {
    recover_marked(points, triangles, &[], opts, domain)
}

/// [`recover_domain`] with a marker per input triangle (for a PLC, the
/// marker of its facet): coplanar triangles with different markers are
/// never merged ([`RecoverOptions::merge_coplanar`]). `markers` empty: no
/// markers.
///
/// # Errors
/// As [`recover_domain`]; [`RecoverError::MarkerCount`] when `markers` is
/// neither empty nor one per triangle.
///
/// ```
/// use delone::tet::recover::{check_recovered, recover_marked, Domain, RecoverOptions};
/// // A unit cube, two triangles per side; the bottom's two triangles carry
/// // different markers, so only the five other sides are merged.
/// let pts: Vec<[f64; 3]> = (0..8)
///     .map(|i| [(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64])
///     .collect();
/// let tris = [
///     [0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
///     [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5],
/// ];
/// let mut markers = vec![1; 12];
/// markers[0] = 2;
/// let r = recover_marked(&pts, &tris, &markers, &RecoverOptions::default(), &Domain::default())
///     .unwrap();
/// check_recovered(&pts, &tris, &r).unwrap();
/// assert_eq!(r.report.coplanar_groups, 5);
/// assert_eq!(r.surface.len(), 12);
/// ```
pub fn recover_marked(
    points: &[[f64; 3]],
    triangles: &[[u32; 3]],
    markers: &[i32],
    opts: &RecoverOptions,
    domain: &Domain,
) -> Result<Recovered, RecoverError> {
    recover_mesh(points, triangles, markers, opts, domain).map(|(rec, _)| rec)
}

/// [`recover_marked`], handing over the carved domain mesh too (its
/// tetrahedra those of the output's `mesh.tets` in order, with their
/// regions and subface marks): refinement and optimisation go on in it
/// ([`crate::tet::refine::refine_in_place`]) instead of building it again
/// from the output's neighbour lists.
pub(crate) fn recover_mesh(
    points: &[[f64; 3]],
    triangles: &[[u32; 3]],
    markers: &[i32],
    opts: &RecoverOptions,
    domain: &Domain,
) -> Result<(Recovered, DomainMesh), RecoverError> {
    if !markers.is_empty() && markers.len() != triangles.len() {
        return Err(RecoverError::MarkerCount {
            expected: triangles.len(),
            got: markers.len(),
        });
    }
    let (cow, scale) = crate::geom::rescaled(points);
    let scaled: Vec<[f64; 3]> = cow.into_owned();
    let (mut dt, (group, nonmanifold)) = validate_and_build(points, triangles, &scaled)?;
    let mut used = vec![false; points.len()];
    for &w in triangles.iter().flatten() {
        used[w as usize] = true;
    }
    if let Some(&(d, o)) = dt.duplicates().iter().find(|(d, _)| used[*d as usize]) {
        return Err(Error::DuplicateVertex {
            index: d as usize,
            original: o as usize,
        }
        .into());
    }
    // A point of no triangle lying on one (not on a corner: a duplicate,
    // ignored like the duplicates above) would be a mesh vertex inside
    // that triangle's faces.
    let mut dup = vec![false; points.len()];
    for &(d, _) in dt.duplicates() {
        if let Some(x) = dup.get_mut(d as usize) {
            *x = true;
        }
    }
    let stray: Vec<u32> = (0..points.len() as u32)
        .filter(|&w| !used[w as usize] && !dup[w as usize])
        .collect();
    if let Some(&(p, t, _)) = crate::model::plc::points_on_triangles(points, triangles, &stray)
        .iter()
        .find(|h| !matches!(h.2, crate::model::plc::OnTriangle::Corner(_)))
    {
        return Err(RecoverError::PointOnTriangle {
            point: p as usize,
            triangle: t as usize,
        });
    }
    let unscale = 1.0 / (scale.0 * scale.1);
    let merged = if opts.merge_coplanar && !opts.preserve_surface {
        merge::merge(points, triangles, markers, (group, &nonmanifold), &dt)
    } else {
        merge::Merged::identity(triangles)
    };
    let triangles = &merged.tris[..];
    let mut st = State::new(Surface::new(points.len(), triangles), opts.clone());
    if !opts.preserve_surface {
        // Each merged group is recovered as one polygon facet.
        st.poly = state::Polygons::new(&mut st.surf, &merged.origin, dt.points());
    }
    // Unrecovered triangles are named by input index.
    let origin = |e: RecoverError| match e {
        RecoverError::Unrecovered { triangles, steiner } => {
            let mut t: Vec<usize> = triangles
                .iter()
                .map(|&t| merged.origin.get(t).map_or(t, |&o| o as usize))
                .collect();
            t.sort_unstable();
            t.dedup();
            RecoverError::Unrecovered {
                triangles: t,
                steiner,
            }
        }
        e => e,
    };
    st.points_first = opts.preserve_surface;
    // The unguided recovery (kept for a refinement, whose smallest
    // dihedral angles depend on where it puts its points) gives up after
    // `STALL_ROUNDS` rounds without progress or past `CASCADE` Steiner
    // points per input point, and where it gives up or fails the guided
    // one recovers the surface from the Delaunay tetrahedralization again.
    let unguided = !opts.preserve_surface && !opts.stop_circling_flips;
    if unguided {
        st.give_up = Some(GiveUp {
            rounds: STALL_ROUNDS,
            steiner: CASCADE * points.len(),
        });
    }
    let dt0 = opts.preserve_surface.then(|| dt.clone());
    let mut run = st.run_cdt(&mut dt, Some(&scaled));
    if unguided
        && matches!(
            run,
            Err(RecoverError::Unrecovered { .. } | RecoverError::SegmentTooShort { .. })
        )
    {
        // The Delaunay tetrahedralization is built again (the same one:
        // the kernel is deterministic) rather than kept aside, which would
        // hold a second copy through every recovery that finishes.
        drop(dt);
        dt = Delaunay3::from_points(&scaled)?;
        let guided = RecoverOptions {
            stop_circling_flips: true,
            ..opts.clone()
        };
        let unguided_rounds = st.report.rounds;
        st = State::new(Surface::new(points.len(), triangles), guided);
        st.poly = state::Polygons::new(&mut st.surf, &merged.origin, dt.points());
        st.report.unguided_rounds = unguided_rounds;
        run = st.run_cdt(&mut dt, Some(&scaled));
    }
    if let (Err(RecoverError::Unrecovered { .. }), Some(dt0)) = (&run, dt0) {
        // `-Y`: the cavities first, from the Delaunay tetrahedralization again.
        let tried = st.fallback_tried;
        st = State::new(Surface::new(points.len(), triangles), opts.clone());
        st.fallback_tried = tried;
        dt = dt0;
        run = st.run_cdt(&mut dt, Some(&scaled));
    }
    let (mut cm, on) = match run {
        // `-Y`: the fallback that always applies (the `cavity` module),
        // unless it already failed.
        Err(RecoverError::Unrecovered { .. }) if opts.preserve_surface && !st.fallback_tried => {
            let (st2, cm, on) = st.preserve_fallback(&scaled).map_err(origin)?;
            st = st2;
            (cm, on)
        }
        r => r.map_err(origin)?,
    };
    if opts.preserve_surface {
        // The interior points the recovered surface no longer needs.
        st.prune_interior(&mut cm, points.len());
    }
    // The Delaunay tetrahedralization is not needed any more (carving
    // works on `cm`): freed before the output is built.
    drop(dt);
    st.report.max_deviation = st.max_dev_scaled * unscale;
    st.report.hull_tets =
        cm.m.live_slots()
            .filter(|&t| cm.m.tv[t as usize][3] != INF)
            .count();
    st.report.coplanar_groups = merged.groups;
    st.report.coplanar_kept = merged.kept;
    let (mut rec, mut mesh) = st.finish(cm, on, points, scale, domain)?;
    rec.surface = merged.tris;
    rec.surface_origin = merged.origin;
    compact::drop_unused_steiner(&mut rec, &mut mesh, points.len());
    Ok((rec, mesh))
}

/// Most rounds in a row the unguided recovery ([`RecoverOptions::stop_circling_flips`]
/// off: the recovery before a refinement) may go without leaving fewer
/// items missing than its best round before it gives up and the guided
/// one takes over (`recover_mesh`). On the 47 closed corpus models under
/// 30,000 triangles at `-pq1.414` it finishes at most 4 rounds after its
/// best one (cgal_part), so their outputs do not depend on the limit. On
/// generated CAD shapes (turned gear keys, tubes with rings of holes) it
/// could otherwise split for hundreds of rounds, adding a few points to
/// the same triangles each round: the seed-805 gear key 1,194 rounds and
/// 50 s before failing, where the guided recovery takes 15 ms.
const STALL_ROUNDS: usize = 8;

/// The unguided recovery ([`RecoverOptions::stop_circling_flips`] off)
/// gives up once it has inserted more than this many Steiner points per
/// input point, and the guided one takes over (`recover_mesh`). On the 47
/// closed corpus models under 30,000 triangles at `-pq1.414` it inserts at
/// most 0.37 per input point (cgal_anchor), so their outputs do not depend
/// on the limit. Generated CAD parts whose unguided recovery finishes
/// with one to three points per input point keep it: the bundled pipe
/// tee (1.06; its smallest dihedral angle after `-pq1.414` is 0.41°, 0.00°
/// from the guided recovery), two turned gear keys of `cad_shapes.py`
/// (2.2; 8.6° and 8.2°, against 0.00° and 5.6°). On turned gear keys and
/// tubes with rings of holes it also splits
/// the same long thin triangles round after round, 3.7–8 points per input
/// point before it finished or failed; the guided recovery needs far
/// fewer (0–106 on the bundled ones, see `recover3d_hard`). The bundled
/// `tube_rings_pierced` at `-pq1.414`: 31.6 → 3.8 s and 264,408 → 76,352
/// tetrahedra.
const CASCADE: usize = 3;

/// The deepest level of edge removal tried on the segments the `-Y`
/// fallback's `-p` recovery still misses after a round's passes
/// ([`cdt::Effort::level`]). 6: on tubes with radial holes, the `-p`
/// recovery then puts 35–42% fewer points on the surface than with level 2
/// alone (w_tube_c 406 → 234) at about 4× its time; level 10 takes another
/// third away at 8× more.
const MAX_LEVEL: u32 = 6;

/// The deepest level of edge removal tried by `-p`'s recovery (also the
/// `-Y` fallback's first runs) on the segments a round's passes still
/// miss ([`cdt::Effort::linear`]). Each level starts where the one before
/// left the segment, since failed attempts keep their flips there; the
/// levels stop at the first one that recovers no segment. On 182
/// generated CAD shapes, against level 2 alone with failed attempts
/// rolled back: 13,020 → 1,118 Steiner points and 4.87 → 3.28 s; up to
/// level 19: 885 points at 4.4 s (twisted prisms, whose segments need
/// points anyway, pay for every level tried).
const P_MAX_LEVEL: u32 = 10;

/// Most rounds that go on in the flipped mesh after their segment splits
/// were mirrored into it (`State::run_cdt`): a safety bound (on the 182
/// generated CAD shapes and the 52 corpus models, under `-p`, `-pM` and
/// `-pY`, no recovery takes more than one).
const MAX_CARRIED_SPLITS: u32 = 8;

/// What a round of [`State::run_cdt`] left missing, for its stall limit
/// (`State::give_up`): any segment missing counts as more than any
/// number of triangles (the triangles come after the segments).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Progress {
    /// Every subsegment recovered; this many triangles missing.
    Triangles(usize),
    /// This many subsegments left to split.
    Segments(usize),
}

impl Progress {
    const MAX: Progress = Progress::Segments(usize::MAX);
}

/// Why [`State::split_in_place`] ended its round early.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum SplitStop {
    /// Pieces kept failing past `MAX_SPLIT_DEPTH` or the round's budget.
    Bounds,
    /// The flipped mesh refused a split point.
    Refused,
}

/// How many times [`State::split_in_place`] splits the pieces of one
/// subsegment whose halves keep failing before it leaves them to the
/// Delaunay tetrahedralization's insertion (the round then ends).
const MAX_SPLIT_DEPTH: u32 = 12;

/// How many points per failing subsegment [`State::split_in_place`] puts
/// in place in one call, at most, before it leaves the rest to the
/// Delaunay tetrahedralization's insertion.
const IN_PLACE_PER_SEGMENT: usize = 8;

/// How many rounds in a carried mesh may leave as many triangles missing
/// as the best round before (`State::run_cdt`). The first time, the next
/// round starts from the Delaunay tetrahedralization (with every point
/// inserted so far) and the rounds after it carry on again; the second
/// time the recovery stays with the Delaunay insertions. A stall is
/// typically one thin triangle whose facet points keep landing in the
/// uncovered part left by rounded points, which one Delaunay round
/// recovers; staying with the Delaunay insertions from there made the
/// rounds cascade on turned CAD parts (the generated gear key of
/// `cad_shapes.py` seed 600: 41 rounds and 0.57 s, against 11 rounds and
/// 0.10 s).
const MAX_STALLED: usize = 4;

/// How many facet points of one input triangle may be replaced by the
/// split of a boundary subsegment they encroach ([`State::insert_in_facet`]).
/// Two: no triangle of the corpus needs more (cgal_oblong's `-pq1.414`
/// refinement depends on a triangle's second split). The `-Y` fallback's
/// recovery keeps the rule without limit: it pulls every surface point of
/// a tube with radial holes (w_tube_c) off only when the facet points stay
/// off the slivers.
const MAX_REDIRECTS: u32 = 2;

/// What the input validation found that [`merge::merge`] uses: the
/// coplanar groups (no markers) the self-intersection tests found, when
/// they are those of the triangles as given, and the edges in more than
/// two triangles (sorted).
type Validated = (Option<Vec<u32>>, Vec<[u32; 2]>);

/// The input validation of [`recover_marked`]: exact self-intersections,
/// then closedness.
fn validate(points: &[[f64; 3]], triangles: &[[u32; 3]]) -> Result<Validated, RecoverError> {
    let group = check_self_intersections_grouped(points, triangles)?;
    let man = manifold_report(triangles);
    if !man.boundary_edges.is_empty() {
        let mut bad: Vec<[u32; 2]> = man.boundary_edges.clone();
        bad.sort_unstable();
        return Err(RecoverError::OpenSurface {
            edge: bad[0],
            count: bad.len(),
        });
    }
    Ok((group, man.nonmanifold_edges))
}

/// Inputs with at least this many triangles are validated on a second
/// thread (see [`validate_and_build`]).
const PARALLEL_VALIDATION: usize = 4096;

/// [`validate`] and the Delaunay tetrahedralization of `scaled` (the
/// rescaled points). The Delaunay build needs only the points, so for
/// large inputs ([`PARALLEL_VALIDATION`]) the validation runs on a second
/// thread meanwhile (when one can be started; else one after the other).
/// The validation's verdict is checked first, so the errors are those of
/// running validation, then build; nothing depends on the threads. Also
/// gives what the validation found ([`Validated`]).
fn validate_and_build<'a>(
    points: &[[f64; 3]],
    triangles: &[[u32; 3]],
    scaled: &'a [[f64; 3]],
) -> Result<(Delaunay3<'a>, Validated), RecoverError> {
    if triangles.len() >= PARALLEL_VALIDATION {
        let both = std::thread::scope(|sc| {
            let job = std::thread::Builder::new()
                .name("delone-validate".into())
                .spawn_scoped(sc, || validate(points, triangles))
                .ok()?;
            let built = Delaunay3::from_points(scaled);
            let valid = job.join().unwrap_or_else(|e| std::panic::resume_unwind(e));
            Some((valid, built))
        });
        if let Some((valid, built)) = both {
            let group = valid?;
            return Ok((built?, group));
        }
    }
    let group = validate(points, triangles)?;
    Ok((Delaunay3::from_points(scaled)?, group))
}

/// A mesh with ghost cells as the read-only searches see it: vertices and
/// packed neighbour words per slot, and the points. Both the kernel's
/// tetrahedralization ([`cells`]) and recovery's domain mesh
/// ([`Journaled`]) give it, so one search serves both.
type Cells<'c> = (Arrays<'c>, &'c [[f64; 3]]);

/// The [`Cells`] of the kernel's tetrahedralization.
fn cells<'c>(dt: &'c Delaunay3<'_>) -> Cells<'c> {
    ((&dt.core.v, &dt.core.adj), dt.points())
}

/// The vertex next to `u` or `v` (in their stars) strictly inside the
/// diametral ball of `u v` that sees it under the largest angle.
fn encroacher(dt: &Delaunay3<'_>, u: u32, v: u32) -> Option<u32> {
    let core = &dt.core;
    let pts = dt.points();
    let mut best: Option<(f64, u32)> = None;
    let (pu, pv) = (pts[u as usize], pts[v as usize]);
    let mut rng = 0x9E37_79B9u32;
    for w in [u, v] {
        let start = core.walk(pts, &pts[w as usize], core.last, &mut rng);
        star_cells(cells(dt).0, &[w], start, &mut IdSet::default(), |_, xv| {
            for q in xv {
                if q == w || q == INF || q == u || q == v {
                    continue;
                }
                let p = pts[q as usize];
                let (du, dv) = (
                    crate::geom::vec3::sub(&pu, &p),
                    crate::geom::vec3::sub(&pv, &p),
                );
                let d = crate::geom::vec3::dot(&du, &dv);
                if d < 0.0 {
                    let c = d
                        / (crate::geom::vec3::dot(&du, &du) * crate::geom::vec3::dot(&dv, &dv))
                            .sqrt();
                    if best.is_none_or(|(bc, bq)| c < bc || (c == bc && q < bq)) {
                        best = Some((c, q));
                    }
                }
            }
        });
    }
    best.map(|(_, q)| q)
}

/// Visits (`visit(slot, vertices)`) the cells of `c` holding every vertex
/// of `around` (the star of a vertex, the ring of an edge; ghost cells
/// included) reached from `start` across the faces holding them, depth
/// first in face order, each cell once: `seen` (shared by successive
/// walks) holds the cells already visited.
fn star_cells(
    (v, adj): Arrays<'_>,
    around: &[u32],
    start: u32,
    seen: &mut IdSet<u32>,
    mut visit: impl FnMut(u32, [u32; 4]),
) {
    let mut stack = vec![start];
    while let Some(x) = stack.pop() {
        let xv = v[x as usize];
        if xv[0] == DEAD || around.iter().any(|w| !xv.contains(w)) || !seen.insert(x) {
            continue;
        }
        visit(x, xv);
        for (f, w) in xv.iter().enumerate() {
            if !around.contains(w) {
                stack.push(adj[x as usize][f] >> 2);
            }
        }
    }
}

/// Coverage is recomputed globally when the local recomputation of the
/// triangles that need it would cost more than the global pass, with each
/// input triangle's share of the global pass as unit
/// ([`State::local_cost`]): a plain triangle costs about one unit (one
/// face lookup in a vertex star), the others about [`LOCAL_COST`] (their
/// vertices' stars). The global pass is chosen past `1 / GLOBAL_FRACTION`
/// of its cost.
const GLOBAL_FRACTION: usize = 2;

/// Cost, in units of a plain triangle, of recomputing a triangle that is
/// not plain, or belongs to a merged group, locally.
const LOCAL_COST: usize = 8;

impl State {
    /// A state with nothing recovered yet.
    fn new(mut surf: Surface, opts: RecoverOptions) -> State {
        surf.every_sliver_one_side = opts.stop_circling_flips;
        State {
            surf,
            report: RecoverReport::default(),
            inexact: Vec::new(),
            max_dev_scaled: 0.0,
            opts,
            tri_inner: IdMap::default(),
            redirected: IdMap::default(),
            interior_tries: IdMap::default(),
            group_tries: HashSet::new(),
            cavity_fails: 0,
            cavity_left: Vec::new(),
            cavity_work: std::cell::Cell::new(0),
            poly: state::Polygons::default(),
            seg_ops: cdt::SEG_OPS,
            y_fallback: false,
            flat_cones: true,
            escalate: false,
            fallback_tried: false,
            points_first: false,
            first_missing: None,
            in_place_off: false,
            carry_splits: true,
            carried_splits: 0,
            split_bounds_met: false,
            cover_memo: std::cell::RefCell::default(),
            give_up: None,
        }
    }

    fn steiner_left(&self) -> bool {
        self.report.steiner() < self.opts.max_steiner
    }

    fn budget_error(&self, sub: usize, tri: usize) -> RecoverError {
        RecoverError::SteinerBudget {
            limit: self.opts.max_steiner,
            missing_subsegments: sub,
            missing_triangles: tri,
        }
    }

    /// Inserts a Steiner point; `None` when it coincides with a vertex.
    fn insert(
        &mut self,
        dt: &mut Delaunay3<'_>,
        p: [f64; 3],
        dev: f64,
    ) -> Result<Option<u32>, RecoverError> {
        match dt.insert(p)? {
            Inserted::Vertex(id) => {
                if dev > 0.0 {
                    self.inexact.push(id);
                    self.report.inexact_steiner += 1;
                    self.max_dev_scaled = self.max_dev_scaled.max(dev);
                }
                Ok(Some(id))
            }
            _ => Ok(None),
        }
    }

    /// Splits subsegment `u → v` of input edge `e` (in chain order). Returns
    /// false when it is no longer a subsegment (split earlier this round).
    fn split_edge(
        &mut self,
        dt: &mut Delaunay3<'_>,
        e: u32,
        u: u32,
        v: u32,
    ) -> Result<bool, RecoverError> {
        let chain = &self.surf.chains[e as usize];
        let Some(i) = chain.iter().position(|&w| w == u) else {
            return Ok(false);
        };
        if chain.get(i + 1) != Some(&v) {
            return Ok(false);
        }
        let [a, b] = self.surf.edges[e as usize];
        let ends = |w: u32| w == a || w == b;
        let shell = match (ends(u), ends(v)) {
            (true, false) => Some(true),
            (false, true) => Some(false),
            _ => None,
        };
        let reference = if shell.is_none() && self.opts.reference_points {
            encroacher(dt, u, v)
        } else {
            None
        };
        let pts = dt.points();
        let g = |w: u32| pts[w as usize];
        let too_short = RecoverError::SegmentTooShort { edge: [a, b] };
        let rp = reference.map(g);
        let Some((p, dev)) = place::edge_point(&g(a), &g(b), &g(u), &g(v), shell, rp.as_ref())
        else {
            return Err(too_short);
        };
        let Some(id) = self.insert(dt, p, dev)? else {
            return Err(too_short);
        };
        self.surf.add_on_edge(id, e, i);
        self.report.steiner_on_edges += 1;
        Ok(true)
    }

    /// Splits the subsegments of `queue` (edge, ends in chain order) that
    /// the flips could not recover in the flipped mesh `cm` as well as in
    /// `dt` (same point, same id): the point goes where [`Self::split_edge`]
    /// puts it, into `cm` by the constrained Bowyer–Watson of
    /// [`Journaled::insert_constrained`] (the protected faces and
    /// subsegments stay, so what the flips recovered stays recovered), and
    /// `recover(cm, prot, a, b)` recovers each half by flips (rolling back
    /// when it fails); a half that fails is split in turn. Returns the
    /// subsegments left to split in `dt` and why the round must end:
    /// [`SplitStop::Refused`] from the first point `cm` refuses (it is then
    /// in `dt` only, and `cm`'s ids would no longer be `dt`'s), the rest of
    /// the queue; [`SplitStop::Bounds`] when pieces keep failing past the
    /// bounds, those and the rest of the queue (their points may still go
    /// into `cm`, see `run_cdt`). `(empty, None)`: every subsegment is
    /// recovered in `cm`, whose round goes on to the triangles.
    #[allow(clippy::type_complexity)]
    fn split_in_place(
        &mut self,
        dt: &mut Delaunay3<'_>,
        cm: &mut Journaled<'_>,
        prot: &mut cdt::Protected,
        queue: Vec<(u32, u32, u32)>,
        mut recover: impl FnMut(&mut Journaled<'_>, &cdt::Protected, u32, u32) -> bool,
    ) -> Result<(Vec<(u32, u32, u32)>, Option<SplitStop>), RecoverError> {
        let mut queue: std::collections::VecDeque<((u32, u32, u32), u32)> =
            queue.into_iter().map(|s| (s, 0)).collect();
        // In-place splits this call may make (see `IN_PLACE_PER_SEGMENT`).
        let budget = IN_PLACE_PER_SEGMENT * queue.len() + IN_PLACE_PER_SEGMENT;
        let mut splits = 0;
        while let Some(((e, u, v), depth)) = queue.pop_front() {
            if cm.find_edge(u, v).is_some() {
                continue;
            }
            if depth >= MAX_SPLIT_DEPTH || splits >= budget {
                // Pieces that keep failing go to `dt`'s insertion (and, with
                // `carry_splits`, into this mesh too: the next round goes on
                // here) and the round ends. The first time, the next round
                // splits in place again: on tubes with rings of radial holes
                // the halves that kept failing are then often recovered.
                // The second time, every split from then on goes to `dt`
                // first (its points give the flips more room on nearly
                // coplanar slivers, where the halves of points put in place
                // and recovered at once keep failing).
                self.in_place_off |= self.split_bounds_met;
                self.split_bounds_met = true;
                let mut rest = vec![(e, u, v)];
                rest.extend(queue.into_iter().map(|x| x.0));
                return Ok((rest, Some(SplitStop::Bounds)));
            }
            if !self.steiner_left() {
                return Err(self.budget_error(queue.len() + 1, 0));
            }
            let id = dt.points().len() as u32;
            debug_assert_eq!(cm.pts().len(), id as usize);
            if !self.split_edge(dt, e, u, v)? {
                continue;
            }
            if dt.points().len() as u32 != id + 1 {
                return Err(RecoverError::SegmentTooShort {
                    edge: self.surf.edges[e as usize],
                });
            }
            splits += 1;
            let pr = &*prot;
            let placed = cm.push_and_insert(
                dt.points()[id as usize],
                u,
                &|f| pr.faces.contains(&f),
                &|a, b| pr.edges.contains(&(a, b)),
            );
            if placed.is_none() {
                // The round ends: the queue's other subsegments are split
                // in `dt` only.
                return Ok((
                    queue.into_iter().map(|x| x.0).collect(),
                    Some(SplitStop::Refused),
                ));
            }
            prot.edges.remove(&ekey(u, v));
            prot.edges.insert(ekey(u, id));
            prot.edges.insert(ekey(id, v));
            for (a, b) in [(u, id), (id, v)] {
                if !recover(cm, prot, a, b) {
                    queue.push_back(((e, a, b), depth + 1));
                }
            }
        }
        Ok((Vec::new(), None))
    }

    /// Inserts the points of `dt` from id `from` on (put there by this
    /// round's splits of triangles) into `cm` too, in order and with the
    /// same ids, each by the constrained Bowyer–Watson of
    /// [`Journaled::insert_constrained`] keeping the faces of `on` (the
    /// coverage of `cm`) and every subsegment. False at the first point
    /// `cm` refuses (the next round then starts from `dt`).
    fn mirror_points(
        &self,
        dt: &Delaunay3<'_>,
        cm: &mut Journaled<'_>,
        from: usize,
        on: &FacesOn,
    ) -> bool {
        if cm.pts().len() != from {
            return false;
        }
        let prot = self.protected(on);
        self.mirror_with(dt, cm, from, &prot)
    }

    /// [`Self::mirror_points`] keeping the protected items `prot` of `cm`.
    fn mirror_with(
        &self,
        dt: &Delaunay3<'_>,
        cm: &mut Journaled<'_>,
        from: usize,
        prot: &cdt::Protected,
    ) -> bool {
        for id in from..dt.points().len() {
            // A point on a subsegment `u v` that is a mesh edge splits it
            // and the faces on it.
            let (near, split) = match self.surf.kind.get(id) {
                Some(Kind::OnEdge(e)) => {
                    let chain = &self.surf.chains[*e as usize];
                    let Some(i) = chain.iter().position(|&w| w as usize == id) else {
                        return false;
                    };
                    let (u, v) = (chain[i - 1], chain[i + 1]);
                    (u, Some(ekey(u, v)))
                }
                Some(Kind::OnTri(t)) => (self.surf.tris[*t as usize][0], None),
                _ => return false,
            };
            let holds = |f: &[u32; 3]| split.is_some_and(|(u, v)| f.contains(&u) && f.contains(&v));
            let placed = cm.push_and_insert(
                dt.points()[id],
                near,
                &|f| prot.faces.contains(&f) && !holds(&f),
                &|a, b| prot.edges.contains(&(a, b)) && split != Some((a, b)),
            );
            if placed.is_none() {
                return false;
            }
        }
        true
    }

    /// Mesh edges crossing the interior of input triangle `t`, sorted,
    /// searched among the tetrahedra around the edges bounding its
    /// uncovered part (any tetrahedron meeting the uncovered part next to
    /// such an edge has an edge crossing `t`); `start(u, v)` gives a
    /// tetrahedron slot containing edge `u v` (`u < v`), if any.
    fn find_crossing_from(
        &self,
        c: Cells<'_>,
        start: &dyn Fn(u32, u32) -> Option<u32>,
        t: usize,
        faces: &[[u32; 3]],
    ) -> Vec<((u32, u32), u32)> {
        let (arrays, pts) = c;
        let mut local: Vec<((u32, u32), u32)> = Vec::new();
        let mut seen: IdSet<u32> = IdSet::default();
        for (u, v) in self.surf.hole_edges(t, faces) {
            let Some(start) = start(u, v) else {
                continue;
            };
            star_cells(arrays, &[u, v], start, &mut seen, |x, xv| {
                if !xv.contains(&INF) {
                    for (i, j) in crate::tet::local::EDGES {
                        local.push((ekey(xv[i], xv[j]), x));
                    }
                }
            });
        }
        local.sort_unstable();
        local.dedup_by_key(|e| e.0);
        self.crossing_edges(pts, &local, t)
    }

    /// [`Self::find_crossing_from`], then, if it finds nothing, every
    /// finite edge.
    fn find_crossing_lazy(
        &self,
        dt: &Delaunay3<'_>,
        vt: &[u32],
        t: usize,
        faces: &[[u32; 3]],
    ) -> Vec<((u32, u32), u32)> {
        let core = &dt.core;
        // A tetrahedron with edge `u v`: the star of `u` walked from
        // `vt[u]` (nothing when that slot no longer holds `u`).
        let start = |u: u32, v: u32| -> Option<u32> {
            let s = *vt.get(u as usize)?;
            let sv = core.v.get(s as usize)?;
            if sv[0] == DEAD || !sv.contains(&u) {
                return None;
            }
            let mut seen: Vec<u32> = vec![s];
            let mut i = 0;
            while i < seen.len() {
                let x = seen[i];
                i += 1;
                let xv = core.v[x as usize];
                if xv.contains(&v) {
                    return Some(x);
                }
                for (f, &w) in xv.iter().enumerate() {
                    let n = core.adj[x as usize][f] >> 2;
                    if w != u && !seen.contains(&n) {
                        seen.push(n);
                    }
                }
            }
            None
        };
        let found = self.find_crossing_from(cells(dt), &start, t, faces);
        if !found.is_empty() {
            return found;
        }
        // Every finite edge, each tested once per tetrahedron holding it
        // (no list of all edges is built); the crossing ones are sorted
        // and each kept with its lowest slot.
        let pts = dt.points();
        let [a, b, c] = self.surf.tris[t].map(|w| pts[w as usize]);
        let lo = [0, 1, 2].map(|k| a[k].min(b[k]).min(c[k]));
        let hi = [0, 1, 2].map(|k| a[k].max(b[k]).max(c[k]));
        let mut list: Vec<((u32, u32), u32)> = Vec::new();
        let mut found = Vec::new();
        for (x, tv) in core.v.iter().enumerate() {
            if tv[0] == DEAD || tv.contains(&INF) {
                continue;
            }
            // A tetrahedron wholly on one side of `t`'s box has no edge
            // meeting it (the test `crossing_edges` makes per edge).
            let q = tv.map(|w| &pts[w as usize]);
            if (0..3).any(|k| q.iter().all(|p| p[k] < lo[k]) || q.iter().all(|p| p[k] > hi[k])) {
                continue;
            }
            list.clear();
            for (i, j) in crate::tet::local::EDGES {
                list.push((ekey(tv[i], tv[j]), x as u32));
            }
            found.extend(self.crossing_edges(pts, &list, t));
        }
        found.sort_unstable();
        found.dedup_by_key(|e| e.0);
        found
    }

    /// Mesh edges of `list` crossing the interior of input triangle `t`.
    fn crossing_edges(
        &self,
        pts: &[[f64; 3]],
        list: &[((u32, u32), u32)],
        t: usize,
    ) -> Vec<((u32, u32), u32)> {
        let tv = self.surf.tris[t];
        let [a, b, c] = tv.map(|w| pts[w as usize]);
        let mut lo = a;
        let mut hi = a;
        for p in [b, c] {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        // Edges with an end on `t` cannot cross its interior (exactly); with
        // inexact Steiner points on its sides they could seem to, so they
        // are left out.
        list.iter()
            .filter(|((p, q), _)| {
                if self.surf.on_triangle(*p, t) || self.surf.on_triangle(*q, t) {
                    return false;
                }
                let (p, q) = (&pts[*p as usize], &pts[*q as usize]);
                (0..3).all(|k| p[k].max(q[k]) >= lo[k] && p[k].min(q[k]) <= hi[k])
                    && place::crosses(&a, &b, &c, p, q)
            })
            .copied()
            .collect()
    }

    /// The recovery (see the `cdt` module): each round copies the Delaunay
    /// tetrahedralization into a [`Journaled`] and recovers the missing
    /// subsegments, then the missing triangles, by flips. Items the flips
    /// cannot recover are split in the Delaunay tetrahedralization (same
    /// placement, protection and encroachment rules for every split) and the
    /// round starts again from it — so Steiner points go only where flips
    /// failed, and the number of rounds is bounded (each round splits at
    /// least one item or fails with a typed error). With
    /// `stop_circling_flips` the splits also go into the flipped mesh in
    /// place and the round goes on in it ([`Self::split_in_place`],
    /// [`Self::mirror_points`]; the module notes).
    ///
    /// `scaled` (`-Y`): the scaled input points, for the fallback that
    /// always applies after the first unfinished cavity call
    /// ([`State::fallback_once`]).
    fn run_cdt<'a>(
        &mut self,
        dt: &mut Delaunay3<'a>,
        scaled: Option<&'a [[f64; 3]]>,
    ) -> Result<(Journaled<'a>, FacesOn), RecoverError> {
        // From the second round on, the coverage and the missing
        // subsegments of `dt` are updated near the points the previous round
        // inserted (see `Self::update_round`) instead of recomputed.
        let mut prev: Option<RoundState> = None;
        // Edge removals found impossible in earlier rounds (same points).
        let mut failed_removals = IdSet::default();
        // The flips and edge removals of the previous round, re-applied
        // first where they still apply (see below).
        let mut prev_log: Option<OpLog> = None;
        // On a non-manifold surface (an edge in more than two triangles:
        // touching solids, internal walls) the incremental update of the
        // protected items can miss some; they are recomputed every round.
        let nonmanifold = (0..self.surf.edges.len()).any(|e| self.surf.edge_tris[e].len() > 2);
        // The previous round's mesh, when every point it added went into it
        // in place (see `Self::split_in_place` and `Self::mirror_points`):
        // this round flips on in it instead of starting again from `dt`.
        let mut carried: Option<Journaled<'a>> = None;
        // Triangles the previous round's flips left missing.
        let mut last_uncovered = usize::MAX;
        let mut stalled = 0;
        // Whether the carried rounds stalled once already.
        let mut went_back = false;
        // The fewest items a round left missing (segments count above
        // triangles: `Progress`), the round that did, and the input
        // triangles at what the last round left missing (`State::give_up`).
        let mut best = Progress::MAX;
        let mut best_round = 0;
        let mut missing_now: Vec<usize> = Vec::new();
        loop {
            if let Some(g) = self.give_up {
                if self.report.rounds - best_round > g.rounds || self.report.steiner() > g.steiner {
                    return Err(RecoverError::Unrecovered {
                        triangles: missing_now,
                        steiner: self.report.steiner(),
                    });
                }
            }
            self.report.rounds += 1;
            let r = self.report.rounds as u64;
            crate::progress::report("recovering the surface", r, None, "rounds");
            if crate::progress::stop_requested() {
                return Err(Error::Interrupted.into());
            }
            let mut cm = Journaled::new(dt.clone());
            cm.set_failed(std::mem::take(&mut failed_removals));
            // The protected items, when `update_round` kept them up to date.
            let mut kept_prot: Option<cdt::Protected> = None;
            let (on, covered, subs) = match prev.take() {
                None => {
                    let (on, covered) = self.coverage_all(&cm);
                    let subs = self.missing_subsegments_cm(&cm, &covered);
                    #[cfg(debug_assertions)]
                    self.debug_same_coverage(&cm, &on, &covered, Some(&subs));
                    (on, covered, subs)
                }
                Some(mut st) => {
                    let mut p = st.prot.take();
                    let r = self.update_round(&cm, st, &mut p);
                    kept_prot = p;
                    r
                }
            };
            let mut prot = match kept_prot.take() {
                Some(p) if !nonmanifold => p,
                _ => self.protected(&on),
            };
            #[cfg(debug_assertions)]
            {
                let fresh = self.protected(&on);
                assert!(fresh.faces == prot.faces && fresh.edges == prot.edges);
            }
            // `on`, `covered`, `subs` and `prot` stay those of `dt` (the
            // next round updates them); a carried mesh has its own.
            let carried_round = carried.is_some();
            let (on_start, cov_start, subs_work, mut prot_work) = match carried.take() {
                Some(c) => {
                    cm = c;
                    let (on_c, cov_c) = self.coverage_all(&cm);
                    let subs_c = self.missing_subsegments_cm(&cm, &cov_c);
                    let prot_c = self.protected(&on_c);
                    (Some(on_c), Some(cov_c), subs_c, prot_c)
                }
                None => (None, None, subs.clone(), std::mem::take(&mut prot)),
            };
            // The previous round's operations are replayed on this round's
            // Delaunay tetrahedralization: it differs from the previous one
            // only around the points inserted since, so nearly every
            // operation finds the very tetrahedra it replaced and is re-applied
            // (valid by construction, see `Journaled::replay`) unless it would
            // destroy an item protected now; only what is left missing is
            // searched and flipped again.
            if !self.opts.preserve_surface {
                cm.start_log();
                if let Some(log) = prev_log.take().filter(|_| !carried_round) {
                    cm.replay(&log, &|o, n| prot_work.kept_by(o, n));
                }
            }
            let old_len = dt.points().len();
            let mut failed = Vec::new();
            // A bounded effort per segment (rolled back when it fails),
            // except under `-Y`.
            let max_ops = if self.opts.preserve_surface {
                usize::MAX / 2
            } else {
                self.seg_ops
            };
            // Per failed segment: the log length after its rollback and
            // its range in `near_fail` (its ends and the vertices of the
            // tetrahedra its flips removed before they were rolled back).
            let mut fail_at: Vec<(usize, usize, usize)> = Vec::new();
            let stop_circles = self.opts.stop_circling_flips && !self.opts.preserve_surface;
            let mut near_fail: Vec<u32> = Vec::new();
            // Segment cones: `-p` without `-q`, and `-Y` (both its flips
            // and its fallback's recovery).
            let cones = stop_circles || self.y_fallback || self.opts.preserve_surface;
            // `-p` alone (and the `-Y` fallback's first runs, which take
            // its recovery): the segments still failing after the passes go
            // through deeper levels of flips (see below), in every round.
            // Once the splits stay with the Delaunay insertions
            // (`in_place_off`) the rounds go on in the flipped mesh with the
            // split points mirrored into it (`carry_splits`, below), so the
            // levels do not redo their work from the Delaunay
            // tetrahedralization each round.
            let deep = stop_circles;
            let flat = self.flat_cones;
            let attempt = |cm: &mut Journaled<'_>,
                           prot: &cdt::Protected,
                           u: u32,
                           v: u32,
                           near: &mut Vec<u32>,
                           ops: usize,
                           (effort, keep): (cdt::Effort, bool)| {
                let mark = cm.log_mark();
                let effort = cdt::Effort {
                    cones,
                    flat,
                    blockers: cones,
                    ..effort
                };
                if cdt::recover_segment_within(cm, u, v, prot, ops, stop_circles, effort) {
                    return None;
                }
                let s = near.len();
                near.extend([u, v]);
                cm.removed_vertices_since(mark, |_, w| near.push(w));
                if !keep {
                    cm.rollback(mark);
                }
                Some((cm.log_mark(), s, near.len()))
            };
            for &(e, u, v) in &subs_work {
                if let Some(at) = attempt(
                    &mut cm,
                    &prot_work,
                    u,
                    v,
                    &mut near_fail,
                    max_ops,
                    (cdt::Effort::BASE, false),
                ) {
                    failed.push((e, u, v));
                    fail_at.push(at);
                }
            }
            let retry_ops = max_ops.min(self.seg_ops / 4);
            // Failed segments are retried, in order, while a pass recovers
            // at least one, each only when a later operation removed a
            // tetrahedron at one of its vertices (else the same flips would
            // fail the same way): the flips of the segments recovered after
            // a failing one often clear its way, and each segment recovered
            // so is a split (and often a round) saved.
            while !failed.is_empty() && !self.opts.preserve_surface {
                let lo = fail_at.iter().map(|a| a.0).min().unwrap_or(0);
                // Per vertex: 1 + the last operation since `lo` that
                // removed a tetrahedron at it (0: none).
                let mut last = vec![0usize; cm.pts().len()];
                cm.removed_vertices_since(lo, |op, w| last[w as usize] = op + 1);
                let before = failed.len();
                let (old_failed, old_at) =
                    (std::mem::take(&mut failed), std::mem::take(&mut fail_at));
                for (&(e, u, v), &(mark, s, t)) in old_failed.iter().zip(&old_at) {
                    let changed = near_fail[s..t].iter().any(|&w| last[w as usize] > mark);
                    if !changed {
                        failed.push((e, u, v));
                        fail_at.push((mark, s, t));
                    } else if let Some(at) = attempt(
                        &mut cm,
                        &prot_work,
                        u,
                        v,
                        &mut near_fail,
                        retry_ops,
                        (cdt::Effort::BASE, false),
                    ) {
                        failed.push((e, u, v));
                        fail_at.push(at);
                    }
                }
                if failed.len() == before {
                    break;
                }
            }
            // The `-Y` fallback: the segments still failing are tried at
            // deeper levels of edge removal, work and budget doubling per
            // level (TetGen's escalation): each one recovered is a surface
            // point fewer for the pull-off, whose stars on these long thin
            // nearly coplanar strips are made of flat tetrahedra.
            //
            // `-p`'s recovery (`deep`) goes deeper too, but a failed attempt there keeps
            // its flips (each valid and keeping every protected item), so
            // the next level goes on from where the last one stopped, as
            // TetGen's flip levels do, with the work growing linearly. The
            // levels stop at the first one that recovers no segment, whose
            // flips are rolled back: kept flips that recover nothing only
            // make the triangles harder (vtk_vase: 27 → 100 Steiner points
            // when they stay). Failed attempts elsewhere (the passes, the
            // refinement's recovery, the fallback's last runs) are rolled
            // back: kept in every attempt, they gave vtk_vase 73 points and
            // the `-Y` fallback's runs without the guided flips 5× their
            // time on the held-out tubes.
            if deep {
                for level in 3..=P_MAX_LEVEL {
                    if failed.is_empty() {
                        break;
                    }
                    let before = failed.len();
                    let mark = cm.log_mark();
                    let effort = (cdt::Effort::linear(level), true);
                    let ops = max_ops * level as usize;
                    failed.retain(|&(_, u, v)| {
                        attempt(&mut cm, &prot_work, u, v, &mut near_fail, ops, effort).is_some()
                    });
                    if failed.len() == before {
                        cm.rollback(mark);
                        break;
                    }
                }
            } else if self.escalate && !self.opts.preserve_surface {
                for level in 3..=MAX_LEVEL {
                    if failed.is_empty() {
                        break;
                    }
                    let effort = (cdt::Effort::level(level), false);
                    let ops = max_ops << (level - 2);
                    failed.retain(|&(_, u, v)| {
                        attempt(&mut cm, &prot_work, u, v, &mut near_fail, ops, effort).is_some()
                    });
                }
            }
            // `-p` without `-q`: the failing subsegments are split in the
            // flipped mesh and their halves recovered in the same round
            // (see `Self::split_in_place`); what it leaves is split in the
            // Delaunay tetrahedralization only, as with `-q`.
            let mut stop = None;
            let mut carry = false;
            if stop_circles && !failed.is_empty() && !self.in_place_off {
                let queue = std::mem::take(&mut failed);
                (failed, stop) =
                    self.split_in_place(dt, &mut cm, &mut prot_work, queue, |cm, prot, u, v| {
                        attempt(
                            cm,
                            prot,
                            u,
                            v,
                            &mut Vec::new(),
                            max_ops,
                            (cdt::Effort::BASE, false),
                        )
                        .is_none()
                    })?;
            }
            let restart = stop.is_some();
            if !failed.is_empty() || restart {
                let now = Progress::Segments(failed.len());
                if now < best {
                    (best, best_round) = (now, self.report.rounds);
                }
                if self.give_up.is_some() {
                    missing_now = self.edge_triangles(&failed);
                }
                if self.opts.preserve_surface {
                    self.points_first_check((0, failed.len()))?;
                    if self.cavities_now() {
                        if let Some(done) = self.preserve_by_cavities(&cm)? {
                            return Ok(self.cavity_done(done));
                        }
                        if let Some(done) = self.fallback_once(scaled)? {
                            return Ok(done);
                        }
                    }
                    let tris = self.edge_triangles(&failed);
                    let tris = self.fallback_targets(tris);
                    self.interior_points(dt, tris)?;
                } else {
                    let from = dt.points().len();
                    for &(e, u, v) in &failed {
                        if !self.steiner_left() {
                            return Err(self.budget_error(failed.len(), 0));
                        }
                        self.split_edge(dt, e, u, v)?;
                    }
                    // When `Self::split_in_place` met its bounds, and from
                    // then on (`in_place_off`), the split points also go
                    // into the flipped mesh (the constrained insertion of
                    // `Self::mirror_points`) and the next round goes on
                    // there: starting again from the Delaunay
                    // tetrahedralization, its replay re-applies a fraction
                    // of the log (under 1% after the first round on tubes
                    // with rings of holes, whose split points change most
                    // cells; a third or less later) and the deeper levels
                    // redo their work. The bundled `tube_rings_pierced`
                    // under `-pM`: 13 rounds, 2.2 s and 1,351 points → 2
                    // rounds, 0.48 s and 248 points; under `-pY` (the
                    // fallback's first run does so): 8.6 → 0.84 s.
                    // At most `MAX_CARRIED_SPLITS` such rounds: a flipped
                    // mesh is not Delaunay, so pieces split there need not
                    // appear however short they get, while from the Delaunay
                    // tetrahedralization they do once short enough (the
                    // rounds after that bound start there, as before).
                    carry = stop_circles
                        && self.carry_splits
                        && self.carried_splits < MAX_CARRIED_SPLITS
                        && (self.in_place_off || stop == Some(SplitStop::Bounds))
                        && cm.pts().len() == from
                        && self.mirror_with(dt, &mut cm, from, &prot_work);
                    self.carried_splits += u32::from(carry);
                }
            } else {
                let segments_by_flips = subs_work.len();
                // Coverage on `cm`, updated only where the flips changed faces.
                let mut on_cm = on_start.unwrap_or_else(|| on.clone());
                let mut covered_cm = cov_start.unwrap_or_else(|| covered.clone());
                let dt_uncovered: Vec<usize> =
                    (0..covered_cm.len()).filter(|&t| !covered_cm[t]).collect();
                self.refresh_coverage(&mut cm, &dt_uncovered, &mut on_cm, &mut covered_cm);
                let mut uncovered: Vec<usize> =
                    (0..covered_cm.len()).filter(|&t| !covered_cm[t]).collect();
                let by_flips = uncovered.len();
                if !uncovered.is_empty() {
                    for &t in &uncovered {
                        let inner = self.tri_inner.get(&(t as u32)).cloned().unwrap_or_default();
                        cdt::recover_facet_within(
                            &mut cm,
                            &self.surf,
                            t,
                            &inner,
                            &prot_work,
                            (stop_circles, cones),
                        );
                    }
                    self.refresh_coverage(&mut cm, &uncovered, &mut on_cm, &mut covered_cm);
                    uncovered = (0..covered_cm.len()).filter(|&t| !covered_cm[t]).collect();
                }
                // `-p` alone: edges piercing a triangle through a ring of
                // its points (rounded off its plane) are removed, which
                // splits would not fix (`cdt::remove_piercing`).
                if stop_circles && !uncovered.is_empty() {
                    let mut removed = false;
                    for &t in &uncovered {
                        let holes = self.surf.hole_edges(t, &on_cm[t]);
                        removed |= cdt::remove_piercing(&mut cm, &self.surf, t, &holes, &prot_work);
                    }
                    if removed {
                        self.refresh_coverage(&mut cm, &uncovered, &mut on_cm, &mut covered_cm);
                        uncovered = (0..covered_cm.len()).filter(|&t| !covered_cm[t]).collect();
                    }
                }
                let now = Progress::Triangles(uncovered.len());
                if now < best {
                    (best, best_round) = (now, self.report.rounds);
                }
                if self.give_up.is_some() {
                    missing_now.clone_from(&uncovered);
                }
                if uncovered.is_empty() {
                    self.report.flips23 = cm.flips23;
                    self.report.edge_removals = cm.removals;
                    self.report.segments_by_flips = segments_by_flips;
                    self.report.triangles_by_flips = by_flips;
                    return Ok((cm, on_cm));
                }
                if self.opts.preserve_surface {
                    self.points_first_check((1, uncovered.len()))?;
                    if self.cavities_now() {
                        if let Some(done) = self.preserve_by_cavities(&cm)? {
                            return Ok(self.cavity_done(done));
                        }
                        if let Some(done) = self.fallback_once(scaled)? {
                            return Ok(done);
                        }
                    }
                    let uncovered = self.fallback_targets(uncovered);
                    self.interior_points(dt, uncovered)?;
                } else {
                    // Split the triangles the flips could not recover, in the
                    // Delaunay tetrahedralization (`on`, `covered`: its coverage).
                    // Per vertex: a tetrahedron holding it (a start for the local
                    // searches; no map of all edges, see `find_crossing_lazy`).
                    let mut vt = vec![DEAD; dt.points().len()];
                    for (x, tv) in dt.core.v.iter().enumerate() {
                        if tv[0] != DEAD {
                            for &w in tv {
                                if w != INF && vt[w as usize] == DEAD {
                                    vt[w as usize] = x as u32;
                                }
                            }
                        }
                    }
                    let facet_from = cm.pts().len();
                    let mut progress = false;
                    let mut group_done = vec![false; self.poly.groups.len()];
                    for &t in &uncovered {
                        if !self.steiner_left() {
                            return Err(self.budget_error(0, uncovered.len()));
                        }
                        // A carried mesh is its own reference: the
                        // points go where its edges cross the triangle.
                        let in_dt = covered[t] && !carried_round;
                        if let Some(g) = self.poly.group(t) {
                            if !std::mem::replace(&mut group_done[g as usize], true) {
                                progress |= self.split_group(dt, &cm, g, in_dt)?;
                            }
                            continue;
                        }
                        if in_dt {
                            progress |= self.split_longest_subsegment(dt, t)?;
                            continue;
                        }
                        let mut found = None;
                        if carried_round {
                            let start = |u: u32, v: u32| cm.find_edge(u, v);
                            let c = ((&cm.m.tv[..], &cm.m.nb[..]), cm.pts());
                            let cross = self.find_crossing_from(c, &start, t, &on_cm[t]);
                            if !cross.is_empty() {
                                found = Some((cross, &on_cm[t]));
                            }
                        }
                        let (cross, faces) = found.unwrap_or_else(|| {
                            (self.find_crossing_lazy(dt, &vt, t, &on[t]), &on[t])
                        });
                        progress |= if cross.is_empty() {
                            self.split_hole(dt, t, faces)?
                        } else {
                            self.split_facet(dt, t, cross[0].0)?
                        };
                    }
                    if !progress && !carried_round {
                        return Err(RecoverError::Unrecovered {
                            triangles: uncovered,
                            steiner: self.report.steiner(),
                        });
                    }
                    // `-p` without `-q`: the next round goes on in `cm`
                    // when the points go into it in place too.
                    // A carried mesh whose triangles left missing do not
                    // get fewer in `MAX_STALLED` rounds goes back to `dt`
                    // for one round (with every point so far), after which
                    // the rounds carry on again; the second time, for good
                    // (see `MAX_STALLED`).
                    let mut back = false;
                    if carried_round && uncovered.len() >= last_uncovered {
                        stalled += 1;
                        if stalled >= MAX_STALLED {
                            back = true;
                            self.in_place_off |= went_back;
                            went_back = true;
                            stalled = 0;
                            last_uncovered = usize::MAX;
                        }
                    } else {
                        stalled = 0;
                        last_uncovered = uncovered.len();
                    }
                    carry = stop_circles
                        && !back
                        && !self.in_place_off
                        && progress
                        && !restart
                        && self.mirror_points(dt, &mut cm, facet_from, &on_cm);
                }
            }
            prev_log = cm.take_log();
            if carry {
                carried = Some(cm);
            } else {
                failed_removals = cm.take_failed();
            }
            prev = Some(RoundState {
                on,
                covered,
                old_len,
                subs,
                prot: Some(if carried_round { prot } else { prot_work }),
            });
        }
    }

    /// The coverage and the missing subsegments of the Delaunay
    /// tetrahedralization wrapped (unflipped) in `cm`, from those of the
    /// previous round (`st`) and the points inserted since (ids from
    /// `st.old_len`). A Delaunay insertion changes only tetrahedra whose
    /// vertices end up adjacent to an inserted point, so only the triangles
    /// at the vertices of the inserted points' stars (which include the
    /// triangles whose sides were split) and those uncovered before can
    /// change; the missing subsegments then follow from the coverage
    /// ([`Self::missing_subsegments_cm`]).
    ///
    /// `prot`: the previous round's protected items, updated to
    /// [`Self::protected`] of the new coverage (or `None` when that is
    /// cheaper to build afresh).
    fn update_round(
        &self,
        cm: &Journaled<'_>,
        st: RoundState,
        prot: &mut Option<cdt::Protected>,
    ) -> (FacesOn, Vec<bool>, Vec<(u32, u32, u32)>) {
        let RoundState {
            mut on,
            mut covered,
            old_len,
            subs,
            ..
        } = st;
        let core = &cm.m;
        let mut near: Vec<u32> = Vec::new();
        for p in old_len as u32..cm.pts().len() as u32 {
            near.push(p);
            for x in cm.star(p) {
                near.extend(core.tv[x as usize].iter().filter(|&&w| w != INF));
            }
        }
        near.sort_unstable();
        near.dedup();
        let mut tris: Vec<usize> = Vec::new();
        for &w in &near {
            if let Some(l) = self.surf.vtris.get(w as usize) {
                tris.extend(l.iter().map(|&t| t as usize));
            }
        }
        tris.sort_unstable();
        tris.dedup();
        if self.local_cost(&tris) * GLOBAL_FRACTION > self.surf.tris.len() {
            *prot = None;
        }
        // Items that may stop being protected: the faces on the triangles
        // recomputed, and the subsegments split since.
        let mut faces: Vec<[u32; 3]> = Vec::new();
        let mut edges: Vec<(u32, u32)> = Vec::new();
        let mut chains: Vec<u32> = Vec::new();
        if prot.is_some() {
            for &t in &tris {
                faces.extend(on[t].iter().map(|f| crate::tet::local::fkey(*f)));
            }
            chains = (old_len..cm.pts().len())
                .filter_map(|p| match self.surf.kind.get(p) {
                    Some(Kind::OnEdge(e)) => Some(*e),
                    _ => None,
                })
                .collect();
            chains.sort_unstable();
            chains.dedup();
            for &e in &chains {
                let old: Vec<u32> = self.surf.chains[e as usize]
                    .iter()
                    .copied()
                    .filter(|&w| (w as usize) < old_len)
                    .collect();
                edges.extend(old.windows(2).map(|w| ekey(w[0], w[1])));
            }
        }
        self.recompute(cm, &tris, &mut on, &mut covered);
        if let Some(p) = prot {
            for f in &faces {
                edges.extend([(f[0], f[1]), (f[0], f[2]), (f[1], f[2])]);
                if !self.face_on_some(&on, *f) {
                    p.faces.remove(f);
                }
            }
            edges.sort_unstable();
            edges.dedup();
            for e in &edges {
                if !self.edge_protected(&on, *e) {
                    p.edges.remove(e);
                }
            }
            for &t in &tris {
                for f in &on[t] {
                    p.add_face(*f);
                }
            }
            for &e in &chains {
                for w in self.surf.chains[e as usize].windows(2) {
                    p.edges.insert(ekey(w[0], w[1]));
                }
            }
        }
        let subs = self.missing_subsegments_near(cm, &covered, &subs, &near);
        #[cfg(debug_assertions)]
        self.debug_same_coverage(cm, &on, &covered, Some(&subs));
        (on, covered, subs)
    }

    /// The items the flips must keep, given the coverage `on` of the
    /// Delaunay tetrahedralization: the faces on input triangles with their
    /// edges, and every subsegment.
    fn protected(&self, on: &FacesOn) -> cdt::Protected {
        let mut prot = cdt::Protected::default();
        let nf: usize = on.iter().map(Vec::len).sum();
        prot.faces.reserve(nf);
        prot.edges.reserve(nf * 3 / 2 + self.surf.edges.len());
        for f in on.iter().flatten() {
            prot.add_face(*f);
        }
        for chain in &self.surf.chains {
            for w in chain.windows(2) {
                prot.edges.insert(ekey(w[0], w[1]));
            }
        }
        prot
    }

    /// True when face `f` (sorted) is in `on` of an input triangle its
    /// vertices lie on.
    fn face_on_some(&self, on: &FacesOn, f: [u32; 3]) -> bool {
        self.common_triangles(f[0], f[1]).any(|t| {
            on[t as usize]
                .iter()
                .any(|g| crate::tet::local::fkey(*g) == f)
        })
    }

    /// The input triangles both `a` and `b` lie on.
    fn common_triangles(&self, a: u32, b: u32) -> impl Iterator<Item = u32> + '_ {
        let get = |w: u32| self.surf.vtris.get(w as usize).map_or(&[][..], |l| &l[..]);
        let lb = get(b);
        get(a)
            .iter()
            .copied()
            .filter(move |t| lb.binary_search(t).is_ok())
    }

    /// True when edge `e` (sorted) is protected by [`Self::protected`] of
    /// `on`: a subsegment, or an edge of a face on an input triangle.
    fn edge_protected(&self, on: &FacesOn, (a, b): (u32, u32)) -> bool {
        let sub = [a, b].iter().any(|&w| {
            let Some(Kind::OnEdge(e)) = self.surf.kind.get(w as usize).copied() else {
                return false;
            };
            self.surf.chains[e as usize]
                .windows(2)
                .any(|x| ekey(x[0], x[1]) == (a, b))
        });
        let input = || {
            self.surf
                .edges
                .binary_search(&[a, b])
                .is_ok_and(|e| self.surf.chains[e].len() == 2)
        };
        sub || input()
            || self.common_triangles(a, b).any(|t| {
                on[t as usize]
                    .iter()
                    .any(|f| f.contains(&a) && f.contains(&b))
            })
    }

    /// Debug builds: the incrementally kept coverage (and missing
    /// subsegments) equal the computation from scratch.
    #[cfg(debug_assertions)]
    fn debug_same_coverage(
        &self,
        cm: &Journaled<'_>,
        on: &[Vec<[u32; 3]>],
        covered: &[bool],
        subs: Option<&[(u32, u32, u32)]>,
    ) {
        let (g_on, g_covered) = self.coverage_all(cm);
        assert_eq!(g_covered, covered, "incremental coverage verdicts differ");
        for (t, (a, b)) in g_on.iter().zip(on).enumerate() {
            let (mut a, mut b) = (a.clone(), b.clone());
            a.sort_unstable();
            b.sort_unstable();
            assert_eq!(a, b, "incremental coverage faces differ on triangle {t}");
        }
        if let Some(subs) = subs {
            assert_eq!(
                self.missing_subsegments_cm(cm, &g_covered),
                subs,
                "missing subsegments differ"
            );
        }
    }

    /// Surface preservation: for each of the triangles `tris` (which flips
    /// could not recover, or whose edges they could not), inserts into the
    /// Delaunay tetrahedralization the two points at distance `h` (a fraction
    /// of its shortest edge, another one at each try) from its centroid along its normal, when they
    /// are inside the convex hull and not within `h` of a vertex of the
    /// triangle's neighbourhood — never a point on the surface. Points
    /// outside the domain are harmless (carving drops their tetrahedra).
    /// Fails with [`RecoverError::Unrecovered`] when nothing can be added
    /// or after [`MAX_INTERIOR_ROUNDS`] rounds, so it never loops.
    fn interior_points(
        &mut self,
        dt: &mut Delaunay3<'_>,
        tris: Vec<usize>,
    ) -> Result<(), RecoverError> {
        let give_up = |st: &Self, tris: Vec<usize>| RecoverError::Unrecovered {
            triangles: tris,
            steiner: st.report.steiner(),
        };
        if self.report.rounds > MAX_INTERIOR_ROUNDS {
            return Err(give_up(self, tris));
        }
        let mut added = 0;
        // First try for a group: the centroid of all its triangles'
        // vertices (the kernel of a Schönhardt-like twisted prism).
        if self.group_tries.insert(tris.clone()) {
            let pts = dt.points();
            let mut vs: Vec<u32> = tris.iter().flat_map(|&t| self.surf.tris[t]).collect();
            vs.sort_unstable();
            vs.dedup();
            let mut p = [0.0; 3];
            for &w in &vs {
                for k in 0..3 {
                    p[k] += pts[w as usize][k] / vs.len() as f64;
                }
            }
            if matches!(dt.locate(&p), super::Location::InTet(_)) {
                if let Inserted::Vertex(_) = dt.insert(p)? {
                    self.report.steiner_interior += 1;
                    return Ok(());
                }
            }
        }
        for &t in tris.iter().take(256) {
            if !self.steiner_left() {
                return Err(self.budget_error(0, tris.len()));
            }
            let pts = dt.points();
            let [a, b, c] = self.surf.tris[t].map(|w| pts[w as usize]);
            let n = crate::geom::vec3::cross(
                &crate::geom::vec3::sub(&b, &a),
                &crate::geom::vec3::sub(&c, &a),
            );
            let nl = crate::geom::vec3::dot(&n, &n).sqrt();
            let e = [
                crate::geom::vec3::sub(&b, &a),
                crate::geom::vec3::sub(&c, &b),
                crate::geom::vec3::sub(&a, &c),
            ]
            .map(|d| crate::geom::vec3::dot(&d, &d).sqrt());
            // Another distance each time the triangle comes back, so a
            // new point is tried (1/3, 2/3, 1/6, 1, 1/12, … of its
            // shortest edge), until one lands inside the hull.
            for _ in 0..10 {
                let k = self.interior_tries.entry(t as u32).or_insert(0);
                let f = [1.0 / 3.0, 2.0 / 3.0, 1.0 / 6.0, 1.0, 1.0 / 12.0][*k % 5]
                    / f64::from(1u32 << (*k / 5).min(20));
                *k += 1;
                let h = e[0].min(e[1]).min(e[2]) * f;
                if nl == 0.0 || h == 0.0 {
                    break;
                }
                let before = added;
                for sign in [1.0, -1.0] {
                    let p: [f64; 3] =
                        [0, 1, 2].map(|k| (a[k] + b[k] + c[k]) / 3.0 + sign * h * n[k] / nl);
                    if !matches!(dt.locate(&p), super::Location::InTet(_)) {
                        continue;
                    }
                    if let Inserted::Vertex(_) = dt.insert(p)? {
                        self.report.steiner_interior += 1;
                        added += 1;
                    }
                }
                if added > before {
                    break;
                }
            }
        }
        if added == 0 {
            return Err(give_up(self, tris));
        }
        Ok(())
    }

    /// Whether a `-Y` round whose flips fail runs the cavity
    /// retriangulation before its interior points: not with
    /// [`State::points_first`] until an interior point is in. A
    /// degenerate Delaunay tetrahedralization (the cospherical vertices of
    /// an extruded polygon: every cap and side face a convex-hull face)
    /// leaves most subsegments to cavities there, while one point at the
    /// centroid of the failing triangles lets the flips recover them.
    fn cavities_now(&self) -> bool {
        !self.points_first || self.report.steiner_interior > 0
    }

    /// With [`State::points_first`], at a round whose flips fail,
    /// `missing` = (0, failed subsegments) or (1, missing triangles): the
    /// first such round is recorded; the next one, after the interior
    /// point(s), must have reached the triangles or cut the count by a
    /// quarter (cylinders: to none; gears: by 46–60%; cgal_oblong, where
    /// the point does not help: by 2%), else the error makes
    /// [`recover_mesh`] start again with cavities first.
    fn points_first_check(&mut self, missing: (u8, usize)) -> Result<(), RecoverError> {
        if !self.points_first {
            return Ok(());
        }
        let Some(first) = self.first_missing else {
            self.first_missing = Some(missing);
            return Ok(());
        };
        self.points_first = false;
        if missing.0 > first.0 || (missing.0 == first.0 && 4 * missing.1 <= 3 * first.1) {
            Ok(())
        } else {
            Err(RecoverError::Unrecovered {
                triangles: Vec::new(),
                steiner: self.report.steiner(),
            })
        }
    }

    /// Updates the coverage `on`, `covered` (exact for `cm` before the
    /// operations logged since the last [`Journaled::take_touched_raw`]) for `cm`
    /// now: recomputes, locally, the triangles of `extra` and those on
    /// which a face created or removed since lies (the others kept every
    /// face and tetrahedron with its vertices on them: a tetrahedron
    /// created or removed has such a face, [`Journaled::take_touched_raw`]).
    fn refresh_coverage(
        &self,
        cm: &mut Journaled<'_>,
        extra: &[usize],
        on: &mut [Vec<[u32; 3]>],
        covered: &mut [bool],
    ) {
        if cm.touched_len() > 2 * cm.m.tv.len() {
            // Many flips: the global pass is cheaper than sorting and
            // looking up every logged face.
            cm.clear_touched();
            self.coverage_all_into(cm, on, covered);
            #[cfg(debug_assertions)]
            self.debug_same_coverage(cm, on, covered, None);
            return;
        }
        // The logged faces (with repeats) are not sorted: each names its
        // triangles directly, deduplicated by a flag per triangle.
        let touched = cm.take_touched_raw();
        let mut seen = vec![false; covered.len()];
        let mut cands: Vec<usize> = Vec::new();
        let mut add = |t: usize, cands: &mut Vec<usize>| {
            if !std::mem::replace(&mut seen[t], true) {
                cands.push(t);
            }
        };
        for &t in extra {
            add(t, &mut cands);
        }
        let (mut out, mut flat) = (Vec::new(), Vec::new());
        // Past this cost `recompute` goes global anyway: the rest of the
        // logged faces need not be looked up.
        let global = self.surf.tris.len() / GLOBAL_FRACTION + 1;
        let mut cost = self.local_cost(&cands);
        for &f in &touched {
            if cost >= global {
                break;
            }
            self.surf.face_triangles_split(f, &mut out, &mut flat);
            let before = cands.len();
            for &t in out.iter().chain(&flat) {
                add(t as usize, &mut cands);
            }
            if !self.poly.is_empty() {
                for g in self.poly.face_groups(&self.surf, f) {
                    add(self.poly.groups[g as usize].tris[0] as usize, &mut cands);
                }
            }
            cost += self.local_cost(&cands[before..]);
        }
        cands.sort_unstable();
        self.recompute(cm, &cands, on, covered);
        #[cfg(debug_assertions)]
        self.debug_same_coverage(cm, on, covered, None);
    }

    /// Recomputes the coverage of triangles `cands` on `cm`: locally, or
    /// globally when they are many (same result, cheaper then).
    fn recompute(
        &self,
        cm: &Journaled<'_>,
        cands: &[usize],
        on: &mut [Vec<[u32; 3]>],
        covered: &mut [bool],
    ) {
        if self.local_cost(cands) * GLOBAL_FRACTION > self.surf.tris.len() {
            self.coverage_all_into(cm, on, covered);
            return;
        }
        self.recompute_local(cm, cands, on, covered);
    }

    /// The estimated cost of [`Self::recompute_local`] of triangles
    /// `cands`, in units of one triangle's share of the global pass (see
    /// [`GLOBAL_FRACTION`]).
    fn local_cost(&self, cands: &[usize]) -> usize {
        cands
            .iter()
            .map(|&t| {
                if self.surf.plain(t) && self.poly.group(t).is_none() {
                    1
                } else {
                    LOCAL_COST
                }
            })
            .sum()
    }

    /// The coverage of every input triangle on `cm`
    /// ([`Surface::coverage_local`]'s faces, as sets, and verdicts). A *plain*
    /// triangle (no Steiner point on it, [`Surface::plain`]) can have only
    /// its own three corners as a face on it, and is covered exactly when
    /// that face exists: one pass over the faces of the tetrahedra with a
    /// hash lookup each finds them. The others (few: those next to Steiner
    /// points) are computed locally, from the stars of their vertices.
    fn coverage_all(&self, cm: &Journaled<'_>) -> (FacesOn, Vec<bool>) {
        let n = self.surf.tris.len();
        let mut on: FacesOn = vec![Vec::new(); n];
        let mut covered = vec![false; n];
        self.coverage_all_into(cm, &mut on, &mut covered);
        (on, covered)
    }

    /// [`Self::coverage_all`] written over `on` and `covered` (one entry
    /// per input triangle), reusing the lists' storage.
    fn coverage_all_into(
        &self,
        cm: &Journaled<'_>,
        on: &mut [Vec<[u32; 3]>],
        covered: &mut [bool],
    ) {
        let n = self.surf.tris.len();
        for f in on.iter_mut() {
            f.clear();
        }
        covered.fill(false);
        let core = &cm.m;
        for (x, tv) in core.tv.iter().enumerate() {
            if tv[0] == DEAD || tv.contains(&INF) {
                continue;
            }
            for (f, idx) in FACET.iter().enumerate() {
                // Each interior face once (from its lower slot).
                let u = (core.nb[x][f] >> 2) as usize;
                if u < x && !core.tv[u].contains(&INF) {
                    continue;
                }
                let k = crate::tet::local::fkey(idx.map(|i| tv[i]));
                for t in self.surf.triangles_with_key(&k) {
                    let t = t as usize;
                    if self.surf.plain(t) {
                        on[t].clear();
                        on[t].push(k);
                        covered[t] = true;
                    }
                }
            }
        }
        let rest: Vec<usize> = (0..n)
            .filter(|&t| !self.surf.plain(t) && self.poly.group(t).is_none())
            .collect();
        self.recompute_local(cm, &rest, on, covered);
        let tets = core
            .tv
            .iter()
            .filter(|tv| tv[0] != DEAD && !tv.contains(&INF))
            .copied();
        self.groups_global(tets, cm.pts(), on, covered);
    }

    /// The subsegments that are not edges of `cm`, by input edge and along
    /// its chain, given the coverage of `cm`: a
    /// subsegment of an input edge with a covered triangle is an edge of a
    /// face on it; only the chains of edges with no covered triangle are
    /// searched (locally, around their vertices).
    fn missing_subsegments_cm(&self, cm: &Journaled<'_>, covered: &[bool]) -> Vec<(u32, u32, u32)> {
        let mut out = Vec::new();
        for (e, chain) in self.surf.chains.iter().enumerate() {
            if self.surf.edge_tris[e].iter().any(|&t| covered[t as usize]) {
                continue;
            }
            for w in chain.windows(2) {
                if cm.find_edge(w[0], w[1]).is_none() {
                    out.push((e as u32, w[0], w[1]));
                }
            }
        }
        out
    }

    /// [`Self::missing_subsegments_cm`] from the missing subsegments `prev`
    /// of the previous round's Delaunay tetrahedralization, when the stars
    /// of only the vertices `near` (sorted) changed since (a Delaunay
    /// insertion joins every vertex of the tetrahedra it removes to the new
    /// point): a subsegment with no end in `near` is an edge now exactly
    /// when it was one then, so only the others are looked up.
    fn missing_subsegments_near(
        &self,
        cm: &Journaled<'_>,
        covered: &[bool],
        prev: &[(u32, u32, u32)],
        near: &[u32],
    ) -> Vec<(u32, u32, u32)> {
        let was: IdSet<(u32, u32)> = prev.iter().map(|&(_, u, v)| (u, v)).collect();
        let mut es: Vec<u32> = prev.iter().map(|s| s.0).collect();
        for &w in near {
            if let Some(l) = self.surf.vtris.get(w as usize) {
                for &t in l {
                    es.extend(&self.surf.tri_edges[t as usize]);
                }
            }
        }
        es.sort_unstable();
        es.dedup();
        let is_near = |w: u32| near.binary_search(&w).is_ok();
        let mut out = Vec::new();
        for e in es {
            if self.surf.edge_tris[e as usize]
                .iter()
                .any(|&t| covered[t as usize])
            {
                continue;
            }
            for w in self.surf.chains[e as usize].windows(2) {
                let (u, v) = (w[0], w[1]);
                let missing = if is_near(u) || is_near(v) {
                    cm.find_edge(u, v).is_none()
                } else {
                    was.contains(&(u, v))
                };
                if missing {
                    out.push((e, u, v));
                }
            }
        }
        out
    }

    /// [`Self::recompute`] of triangles `cands`, each from the stars of its
    /// vertices.
    fn recompute_local(
        &self,
        cm: &Journaled<'_>,
        cands: &[usize],
        on: &mut [Vec<[u32; 3]>],
        covered: &mut [bool],
    ) {
        let core = &cm.m;
        let mut slots: Vec<u32> = Vec::new();
        let mut groups: Vec<u32> = Vec::new();
        for &t in cands {
            if let Some(g) = self.poly.group(t) {
                groups.push(g);
                continue;
            }
            if self.surf.plain(t) {
                // Only its own corners can make a face on it.
                let [a, b, c] = self.surf.tris[t];
                let found = cm.find_face(a, b, c).is_some();
                on[t].clear();
                if found {
                    on[t].push(crate::tet::local::fkey([a, b, c]));
                }
                covered[t] = found;
                continue;
            }
            let inner = self.tri_inner.get(&(t as u32)).map_or(&[][..], |v| &v[..]);
            slots.clear();
            for w in cdt::tri_vertices(&self.surf, t, inner) {
                slots.extend(cm.star(w));
            }
            slots.sort_unstable();
            slots.dedup();
            let tets: Vec<[u32; 4]> = slots
                .iter()
                .map(|&x| core.tv[x as usize])
                .filter(|tv| tv[0] != DEAD && !tv.contains(&INF))
                .collect();
            let (f, c) = self.surf.coverage_local(t, &tets, cm.pts());
            on[t] = f;
            covered[t] = c;
        }
        self.groups_local(cm, groups, on, covered);
    }

    /// The input triangles using the input edges of `subs`, ascending.
    fn edge_triangles(&self, subs: &[(u32, u32, u32)]) -> Vec<usize> {
        let mut out: Vec<usize> = subs
            .iter()
            .flat_map(|&(e, _, _)| self.surf.edge_tris[e as usize].iter().map(|&t| t as usize))
            .collect();
        out.sort_unstable();
        out.dedup();
        out
    }

    /// Splits the longest boundary subsegment of triangle `t`.
    fn split_longest_subsegment(
        &mut self,
        dt: &mut Delaunay3<'_>,
        t: usize,
    ) -> Result<bool, RecoverError> {
        let pts = dt.points();
        let mut best: Option<(f64, u32, u32, u32)> = None;
        for &e in &self.surf.tri_edges[t] {
            for w in self.surf.chains[e as usize].windows(2) {
                let d = crate::geom::vec3::sub(&pts[w[0] as usize], &pts[w[1] as usize]);
                let l = crate::geom::vec3::dot(&d, &d);
                if best.is_none_or(|b| l > b.0) {
                    best = Some((l, e, w[0], w[1]));
                }
            }
        }
        match best {
            Some((_, e, u, v)) => self.split_edge(dt, e, u, v),
            None => Ok(false),
        }
    }

    /// Splits missing triangle `t` where mesh edge `k` crosses it, or the
    /// boundary subsegment that point encroaches. False when neither works.
    fn split_facet(
        &mut self,
        dt: &mut Delaunay3<'_>,
        t: usize,
        k: (u32, u32),
    ) -> Result<bool, RecoverError> {
        let pts = dt.points();
        let g = |w: u32| pts[w as usize];
        let tv = self.surf.tris[t];
        let [a, b, c] = tv.map(g);
        let (x, dev) = place::facet_point(&a, &b, &c, &g(k.0), &g(k.1));
        self.insert_in_facet(dt, t, x, dev)
    }

    /// Splits the longest edge around the uncovered part of triangle `t`
    /// (used when no mesh edge is found crossing it, which inexact Steiner
    /// points on its sides can cause): a boundary subsegment is split on its
    /// edge, another edge at its midpoint as a point of `t`.
    fn split_hole(
        &mut self,
        dt: &mut Delaunay3<'_>,
        t: usize,
        faces: &[[u32; 3]],
    ) -> Result<bool, RecoverError> {
        let holes = self.surf.hole_edges(t, faces);
        let pts = dt.points();
        let g = |w: u32| pts[w as usize];
        let len2 = |(u, v): (u32, u32)| {
            let d = crate::geom::vec3::sub(&g(u), &g(v));
            crate::geom::vec3::dot(&d, &d)
        };
        let Some(&(u, v)) = holes
            .iter()
            .max_by(|&&x, &&y| len2(x).total_cmp(&len2(y)).then(y.cmp(&x)))
        else {
            return Ok(false);
        };
        for &e in &self.surf.tri_edges[t] {
            let chain = &self.surf.chains[e as usize];
            if let Some(w) = chain.windows(2).find(|w| ekey(w[0], w[1]) == (u, v)) {
                let (a, b) = (w[0], w[1]);
                return self.split_edge(dt, e, a, b);
            }
        }
        let tv = self.surf.tris[t];
        let [a, b, c] = tv.map(g);
        let (pu, pv) = (g(u), g(v));
        let mut x = [0, 1, 2].map(|k| 0.5 * (pu[k] + pv[k]));
        for k in 0..3 {
            if a[k] == b[k] && b[k] == c[k] {
                x[k] = a[k];
            }
        }
        let dev = if delone_predicates::orient3d(&a, &b, &c, &x) == 0.0 {
            0.0
        } else {
            place::plane_distance(&a, &b, &c, &x).max(f64::MIN_POSITIVE)
        };
        self.insert_in_facet(dt, t, x, dev)
    }

    /// Inserts `x` (on triangle `t` up to `dev`), or splits a boundary
    /// subsegment of `t` that `x` encroaches (Shewchuk's rule). The split
    /// is taken the first [`MAX_REDIRECTS`] times a point of `t` encroaches
    /// (always in the `-Y` fallback's recovery), and afterwards only when
    /// `x` cannot be inserted: every point inside an obtuse sliver
    /// encroaches its long side, so on nearly coplanar sliver triangles
    /// (CAD faces stored in single precision and turned) splits alone go
    /// on round after round while a vertex just off the plane keeps an edge
    /// across the triangle. False when neither works.
    fn insert_in_facet(
        &mut self,
        dt: &mut Delaunay3<'_>,
        t: usize,
        x: [f64; 3],
        dev: f64,
    ) -> Result<bool, RecoverError> {
        let pts = dt.points();
        let g = |w: u32| pts[w as usize];
        let encroached = self.surf.tri_edges[t].iter().find_map(|&e| {
            let chain = &self.surf.chains[e as usize];
            chain
                .windows(2)
                .find(|w| place::encroaches(&g(w[0]), &g(w[1]), &x))
                .map(|w| (e, w[0], w[1]))
        });
        if let Some((e, u, v)) = encroached {
            let n = self.redirected.entry(t as u32).or_default();
            *n += 1;
            if *n <= MAX_REDIRECTS || self.y_fallback {
                return self.split_edge(dt, e, u, v);
            }
        }
        let [a, b, c] = self.surf.tris[t].map(g);
        if place::inside_triangle(&a, &b, &c, &x) {
            if let Some(id) = self.insert(dt, x, dev)? {
                self.surf.add_on_tri(id, t as u32);
                self.tri_inner.entry(t as u32).or_default().push(id);
                self.report.steiner_on_facets += 1;
                return Ok(true);
            }
        }
        match encroached {
            Some((e, u, v)) => self.split_edge(dt, e, u, v),
            None => Ok(false),
        }
    }

    /// Carves the recovered mesh `cm` in place and builds the output view
    /// of it; `on`: the faces on each input triangle. Returns the output and the carved domain mesh (its
    /// tetrahedra those of the output, in order, with their regions and
    /// subface marks).
    fn finish(
        mut self,
        cm: Journaled<'_>,
        on: FacesOn,
        input: &[[f64; 3]],
        scale: (f64, f64),
        domain: &Domain,
    ) -> Result<(Recovered, DomainMesh), RecoverError> {
        let unscale = 1.0 / (scale.0 * scale.1);
        let (mut m, dt) = cm.into_parts();
        let pts = dt.points();
        // Face key -> input triangle (the last one listing it).
        let face_tri = surface::TripleIndex::new(
            pts.len(),
            on.iter()
                .enumerate()
                .flat_map(|(t, fs)| fs.iter().map(move |&f| (f, t as u32))),
        );
        // Per slot and face: the input triangle it lies on (one lookup per
        // face, then flags instead of hashing in carving and output).
        let mut marks = vec![[crate::NONE; 4]; m.tv.len()];
        for (t, tv) in m.tv.iter().enumerate() {
            if tv[0] == DEAD {
                continue;
            }
            for f in 0..4 {
                let w = m.nb[t][f];
                let (u, g) = ((w >> 2) as usize, (w & 3) as usize);
                if u < t {
                    continue;
                }
                let k = crate::tet::local::fkey(FACET[f].map(|i| tv[i]));
                if k.contains(&INF) {
                    continue;
                }
                if let Some(ti) = face_tri.get(&k).last() {
                    marks[t][f] = ti;
                    marks[u][g] = ti;
                }
            }
        }
        drop(face_tri);
        let cells = (&m.tv[..], &m.nb[..]);
        let mut carved = carve::carve(cells, pts, &marks, domain, scale)?;
        self.report.holes_removed = carved.holes_removed;
        self.report.chord_slivers =
            carve::drop_chord_slivers(cells, pts, &mut marks, &mut carved, &self.inexact);
        let mut regions = carved.regions;
        let region = carved.region;
        let inside = |t: usize| region[t] != u32::MAX;
        // A face listed on an input triangle that also has boundary faces,
        // with the same region on both sides, is not a separator: with
        // rounded (inexact) Steiner points, faces of points recorded on a
        // triangle can lie inside the domain next to it. Only faces on
        // internal facets (triangles with no boundary face) or between two
        // regions are interior faces (subfaces).
        // Per surface triangle: has a boundary face (a flag, no hashing).
        let mut has_boundary = vec![false; self.surf.tris.len()];
        let kept: Vec<usize> = (0..m.tv.len()).filter(|&t| inside(t)).collect();
        for &t in &kept {
            for (f, w) in m.nb[t].iter().enumerate() {
                if !inside((w >> 2) as usize) {
                    if let Some(h) = has_boundary.get_mut(marks[t][f] as usize) {
                        *h = true;
                    }
                }
            }
        }
        let mut mask = vec![0u8; m.tv.len()];
        for &t in &kept {
            for (f, &w) in m.nb[t].iter().enumerate() {
                let u = (w >> 2) as usize;
                let ti = marks[t][f];
                // Subface bits on both sides: boundary faces, and faces on
                // an input triangle between two regions or on an internal
                // facet.
                let sub = !inside(u)
                    || (ti != crate::NONE
                        && (region[t] != region[u]
                            || !has_boundary.get(ti as usize).copied().unwrap_or(false)));
                if sub {
                    mask[t] |= 1 << f;
                }
            }
        }
        let points = crate::geom::scale::unscaled_points(input, pts, unscale);
        let mut vertex_map: Vec<u32> = (0..points.len() as u32).collect();
        for &(d, o) in dt.duplicates() {
            vertex_map[d as usize] = o;
        }
        m.carve(region, mask, points.len());
        // The carved mesh keeps the slots `kept`, in order.
        let faces = m.output_faces(|t, f, _| marks[kept[t]][f]);
        let (tets, tet_region) = (m.tv.clone(), m.reg.clone());
        for (tv, &g) in tets.iter().zip(&tet_region) {
            // Measured on the scaled points (no under- or overflow), then
            // brought back to input units.
            regions[g as usize].volume += crate::geom::scale::unscale_cubic(
                check::tet_volume(tv.map(|q| pts[q as usize])),
                scale,
            );
        }
        let rec = Recovered {
            points,
            mesh: TetMesh {
                tets,
                neighbors: faces.neighbors,
                vertex_map,
                duplicates: dt.duplicates().to_vec(),
                hidden: Vec::new(),
            },
            surface: Vec::new(),
            surface_origin: Vec::new(),
            boundary: faces.boundary,
            boundary_triangle: faces.boundary_triangle,
            interior_faces: faces.interior_faces,
            interior_triangle: faces.interior_triangle,
            tet_region,
            regions,
            inexact: self.inexact,
            report: self.report,
        };
        Ok((rec, m))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tet::dmesh::tests::three_around_an_edge;

    #[test]
    fn recovery_flips_the_ring_face() {
        // A bipyramid over triangle 0 1 2 with poles 3 and 4 close to its
        // plane, the triangle an internal facet: edge 3 4 has three
        // tetrahedra around it, and removing it (a 3-2 flip, the invariant
        // checker runs after it) makes 0 1 2 a face, with no Steiner point.
        let pts = three_around_an_edge();
        let mut tris: Vec<[u32; 3]> = (0..3).map(|i| [i, (i + 1) % 3, 3]).collect();
        tris.extend((0..3).map(|i| [(i + 1) % 3, i, 4]));
        tris.push([0, 1, 2]);
        let opts = RecoverOptions {
            merge_coplanar: false,
            ..Default::default()
        };
        let r = recover(&pts, &tris, &opts).unwrap();
        check_recovered(&pts, &tris, &r).unwrap();
        assert_eq!(r.report.edge_removals, 1);
        assert_eq!(r.report.steiner(), 0);
        assert_eq!(r.mesh.tets.len(), 2);
    }
}
