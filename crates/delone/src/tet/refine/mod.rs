//! Delaunay refinement of a recovered tetrahedralization, as *constrained*
//! refinement on the mesh of the default (flip-based) recovery.
//!
//! [`refine`] recovers the surface with [`recover`](super::recover::recover) (constrained path: flips
//! first, few Steiner points) and refines the carved domain mesh in place
//! (the private `cdr` module) on the crate's constrained domain mesh
//! (`tet::dmesh`: packed adjacency, subface marks, regions,
//! subface and subsegment tables), the very mesh recovery carved
//! ([`refine_recovered`] builds it from a [`Recovered`] mesh's lists).
//! The crate-internal `refine_in_place` hands that mesh over, compacted, for
//! optimisation to continue on it (`optimize_in_place`). Nothing is rebuilt,
//! and constraints are *topological*:
//!
//! * **subfaces** — the mesh faces marked as constraints: the boundary
//!   faces and the interior (internal facet, region interface) faces of
//!   the [`Recovered`] mesh, each with its input triangle. The mark is a
//!   4-bit face mask per tetrahedron; a side table maps a subface to its
//!   input triangle and an edge to the subfaces holding it;
//! * **facets** — the recovery merges exactly coplanar input triangles
//!   into planar groups ([`RecoverOptions::merge_coplanar`](crate::tet::recover::RecoverOptions::merge_coplanar), on by
//!   default, as in TetGen) and re-triangulates each; a facet of the
//!   refinement is such a group (the surface triangles with the same
//!   [`Recovered::surface_origin`]), or one input triangle when not
//!   merged. [`super::recover::check_recovered`] checks coverage per
//!   facet, so subfaces may cross the group's inner edges;
//! * **subsegments** — every mesh edge on a facet's side (the edges used
//!   once by the subfaces of a facet), *ridges and flat edges between
//!   distinct facets alike*; the inner edges of a merged facet are not
//!   constraints, so R2's facet-local Delaunay cavity (below) re-triangulates
//!   a planar facet across them, keeping it Delaunay in its plane. The
//!   plane groups of nearly coplanar triangles serve only to recognise
//!   flat cones (below);
//! * **regions** — each tetrahedron carries its region; new tetrahedra
//!   inherit the region of the cavity tetrahedron whose boundary face they
//!   cone, and a plan whose new tetrahedra of different regions meet across
//!   a face that is not a subface is refused. Multi-region domains and
//!   internal facets are refined like single ones; volume bounds are per
//!   region ([`MeshRegion::max_volume`](super::recover::MeshRegion), with
//!   [`RefineOptions::max_volume`] as the global one).
//!
//! **Constrained Delaunay.** Before refinement the mesh is flipped to
//! constrained Delaunay (2-3 and 3-2 flips of faces that are not
//! subfaces, exact `insphere`; Shewchuk 2003), and again around every new
//! point (its cavity may have been shrunk). Degenerate configurations that
//! would need 4-4 flips are left.
//!
//! **Insertion.** A point `m` is inserted with a Bowyer–Watson cavity
//! (exact `insphere`) grown from *required* tetrahedra only across faces
//! that are not subfaces; the cavity is replaced by the cone of its
//! boundary from `m`. Some subfaces may be *dissolved*: they are removed
//! and the cone of their boundary edges from `m` becomes the new subfaces
//! (with the dissolved faces' input triangle). The three rules:
//!
//! 1. **R1** — a subsegment `a b` is split at its midpoint, or on a
//!    concentric shell (a power-of-two distance) around an input vertex at
//!    one of its ends; the required tetrahedra are all those around `a b`
//!    and on both sides of the dissolved subfaces. The dissolved subfaces
//!    are, per facet holding `a b`, its facet-local Delaunay cavity of `m`
//!    (the subfaces holding `a b` and those reached from them, never across
//!    a subsegment, whose circumcircle holds `m`), so each facet stays
//!    Delaunay in its plane; if that plan is refused, only the subfaces
//!    holding `a b` (every side of the segment, any number of facets). A
//!    facet left non-Delaunay keeps skinny subfaces whose circumcentres
//!    fall beyond their own subsegment, and R2 would halve that subsegment
//!    towards its input vertex forever. Encroachment: a vertex of a
//!    tetrahedron around it strictly inside its diametral ball;
//! 2. **R2** — an encroached subface is split at its circumcentre `c`: a
//!    walk over the subfaces of its facet finds the one holding
//!    `c`, or the subsegment in the way (then that subsegment is split, if
//!    not much shorter than the subface); the facet-local Delaunay cavity
//!    (subfaces of the same facet whose circumcircle holds `c`,
//!    never across a subsegment) must be a disk with `c` strictly inside
//!    (exact test per boundary edge); the tetrahedra on both sides of it
//!    are required. A circumcentre encroaching a subsegment of the 3D
//!    cavity splits that subsegment instead. When the insertion is refused
//!    the fallback is the subface's longest edge when it is a subsegment;
//!    otherwise the subface is left (counted in [`RefineReport::skipped`]);
//! 3. **R3** — a tetrahedron with radius-edge ratio above the bound, or
//!    volume above its region's bound, worst first, is split at its
//!    circumcentre: a visibility walk locates it; a subface in the way that
//!    it encroaches, or subsegments / subfaces of its cavity whose
//!    diametral / equatorial ball holds it, reject it and are split
//!    instead, but only when they are not much smaller than the cell's
//!    shortest edge (near small input angles the cell is left and counted
//!    in [`RefineReport::skipped`]). Of several encroached subfaces only
//!    the one encroached most deeply (circumcentre nearest to its centre,
//!    relative to its radius) is split, then the cell is checked again.
//!    No split on behalf of a cell bad by shape may put a point closer to
//!    a vertex of its cavity than the cell's shortest edge (Shewchuk's
//!    insertion-radius argument: in a Delaunay mesh the split point of a
//!    piece encroached by the circumcentre of a cell of radius-edge ratio
//!    √2 is at least that far from every vertex); closer means the
//!    circumball reaches round a constraint or into a small input angle,
//!    where the split starts a cascade of ever shorter edges, so the
//!    piece is not split and the cell is left (counted in
//!    [`RefineReport::skipped_small`] and [`RefineReport::skipped_radius`];
//!    cells only too big are exempt). A subface in the way that it does not
//!    encroach leaves the cell ([`RefineReport::skipped_behind`]: wedges at
//!    ridges, or where the flips could not restore constrained Delaunay).
//!    Nearly flat cells (radius-edge ratio above 10⁶), and cells whose four
//!    vertices lie on one plane group of (nearly) coplanar input triangles,
//!    are left: splitting their boundary leaves flat cells again. So is a
//!    cell whose shortest edge joins two concentric-shell points of one
//!    input vertex on two of its input edges meeting at less than 30°:
//!    splitting anything there only makes shorter shell pairs (Shewchuk's
//!    rule at small input angles in 2D, here for segments in 3D).
//!    Three more protections at sharp input features (Shewchuk & Si 2014:
//!    where a bound cannot be met, stop there and report it), each counted
//!    in [`RefineReport::skipped_small`]:
//!    * a cell whose circumcentre lies closer to a vertex of its cavity
//!      than the cell's shortest edge ([`RefineReport::skipped_close`]):
//!      its circumsphere reaches round a subface (reflex or sharp input
//!      features), and inserting the point would make an edge shorter than
//!      any of the cell's, the seed of a cascade of ever shorter edges
//!      (cells bad only by size are split regardless);
//!    * a cell whose four vertices lie on two input triangles sharing an
//!      edge and meeting at a dihedral angle below 30°
//!      ([`RefineReport::skipped_wedge`]; the angle is measured between
//!      the half-planes, since a PLC's facets come in any orientation): its
//!      circumcentre lies beyond one facet, and splitting that facet makes
//!      a narrower cell deeper in the wedge, forever;
//!    * a cell with a vertex on a degenerate input triangle (a zero-angle
//!      sliver, height below 10⁻⁴ of its longest side): every cell there
//!      is bad, and R2 on the sliver would refine its whole length down to
//!      its height. Such triangles are never split by R2.
//!
//!    A subsegment or subface whose split failed with the mesh unchanged
//!    is not tried again, and each is queued at most once (a refused
//!    subface retried for every cell showing it spun for minutes).
//!
//!    **Size before shape.** A cell above its volume bound (or the
//!    sizing) is split whatever the protections above say (they are for
//!    cells bad by shape): no flat, shell, degenerate, wedge, close or
//!    insertion-radius rule, and the encroached pieces are split whatever
//!    their size. When that makes no progress (a piece at the segment
//!    floor, a refused plan, no circumcentre), a point inside the cell's
//!    circumball is inserted with the cell in its cavity (3/4, 1/2, 1/4 of
//!    the way from the centroid to the circumcentre, then the centroid;
//!    [`RefineReport::inside`]), so the volume bound is met everywhere
//!    ([`RefineReport::remaining_over_volume`] is 0 unless the budget ran
//!    out).
//!
//!    **Kept surface** ([`RefineOptions::keep_surface`], `-pqY`): R1 and
//!    R2 are off and R3 splits no piece. A cell whose circumcentre
//!    encroaches a subface or subsegment (or lies behind one) gets the
//!    first of the points above that encroaches nothing in its cavity and
//!    lies no closer to a vertex than the cell's shortest edge; if none,
//!    it is left ([`LeftBad::surface`]). Each cell is tried once per
//!    change, so refinement ends.
//!
//!    **Convex hull** (`-c`): the hull faces off the surface are added as
//!    triangles, exactly coplanar neighbours grouped into one facet, and
//!    refined like input facets; the output names them as hull faces
//!    again.
//!
//!    Every cell R3 leaves is remembered with the reason; the cells still
//!    above the bound at the end are counted per reason in
//!    [`RefineReport::left`] ([`LeftBad`]), with how many lie next to a
//!    needle input triangle (an angle below 5°) or a sharp input edge
//!    (half-planes meeting below 60°). A cell whose circumcentre was
//!    inserted but which stayed out of the cavity (a subface between
//!    them, or dropped by the cavity correction) is looked at again.
//!
//! **Cavity correction.** Before an insertion is planned, the cavity is
//! shrunk in passes: every tetrahedron that is not required and has a
//! boundary face the new point does not strictly see (or a subface on the
//! point's own plane, or a face whose cone would be flat) is dropped, and
//! again for the faces this exposes. Near-cospherical points (a cylinder)
//! give cavities spanning most of the mesh, which dropping one cell per
//! retry could not fix. Plans and Delaunay flips also never build a
//! tetrahedron whose four vertices lie on one plane group: positive only
//! by the rounding of new points, it would lie flat on its facet.
//!
//! Queues are processed in a fixed order (subsegments, subfaces, then bad
//! cells), each item checked again when it is taken. Encroachment by a
//! *circumcentre* is geometric (no protection). Encroachment by an
//! existing vertex is not acted on when the vertex lies on a surface
//! triangle sharing a vertex with the encroached piece's triangles, unless
//! both are on the same merged planar facet (protection at small input
//! angles and at the needle triangles of curved surfaces, where every
//! input triangle is its own facet).
//!
//! **Why every new tetrahedron is positive and no subface is lost.** The
//! plan of an insertion is computed before anything changes and refused
//! (the mesh untouched) unless all of these hold, each by exact predicates
//! or by combinatorics:
//!
//! * every cone tetrahedron `[x, y, z, m]` is strictly positive by
//!   `orient3d` (a tetrahedron whose boundary face fails is dropped from
//!   the cavity and the plan retried; a required one cannot be dropped and
//!   the insertion is refused);
//! * no cone is built on a subface lying on the plane (group) of the input
//!   triangles the new point lies on: `m` is a rounded point, a hair off
//!   its facet, and such a cone would be flat, positive or not by the
//!   accident of rounding. `m` is *topologically* on its facet: it only
//!   ever becomes a vertex of the subfaces cut out of the dissolved ones;
//! * the cavity never crosses a subface (growth stops there); a subface
//!   with the cavity on both sides would vanish, so one side is dropped;
//!   dissolved subfaces must have the cavity on every side;
//! * every vertex and every subsegment of the cavity (but the one split)
//!   is on its boundary, so nothing is deleted;
//! * the faces through `m` pair up (at most two cone tetrahedra per face);
//!   a face met once must be on the dissolved subfaces' boundary (it is a
//!   new domain-boundary subface), and every boundary edge of the dissolved
//!   subfaces gets its face, so the new subfaces cover exactly the
//!   dissolved ones: the input triangle stays a union of subfaces.
//!
//! Ghost-free: the structure holds only the domain, so a cavity never
//! reaches outside it. Points are kept rescaled by a power of two (exact)
//! as in [`recover`](super::recover::recover); new points on input edges or triangles that are not
//! exactly on them are listed in [`Recovered::inexact`] with the largest
//! deviation in the report. The Steiner budget bounds the number of points
//! ([`RefineReport::budget_exhausted`]); the result is a valid mesh at any
//! stop.
//!
//! **Every bound is met or reported.** Bounds no mesh can meet are refused
//! before any work ([`Error::InvalidBound`](crate::Error::InvalidBound)):
//! a radius-edge ratio below √6/4 ([`MIN_RADIUS_EDGE`]), a volume bound
//! that is not positive. Delaunay refinement is guaranteed to terminate
//! for radius-edge bounds above 2 (Shewchuk) and does in practice down to
//! about 1.1; below that, and for tiny volume bounds, it may add points
//! until memory runs out. Every run therefore has a Steiner budget,
//! by default [`default_budget`] (from the input size and the volume the
//! bounds ask for, never from the machine). When it runs out the mesh
//! reached is returned with [`RefineReport::budget_exhausted`]; the cells
//! still above the bound are counted in [`RefineReport::remaining_bad`]
//! and, by reason, in [`RefineReport::left`] (small input angles, sharp
//! wedges and the other input features that force a bad cell are reasons
//! of their own).
//!
//! # References
//! J. R. Shewchuk, *Tetrahedral mesh generation by Delaunay refinement*
//! (1998); H. Si, *Constrained Delaunay tetrahedral mesh generation and
//! refinement* (2010); J. R. Shewchuk, H. Si, *Higher-quality
//! tetrahedral mesh generation for domains with small angles by
//! constrained Delaunay refinement* (2014).

mod cdr;
pub mod existing;
mod geom;
mod options;
mod queue;
mod report;
pub mod sizing;

pub(crate) use options::volume_bounds;
pub use options::{
    default_budget, memory_estimate, RefineOptions, BUDGET_BASE, BUDGET_MAX, BYTES_PER_POINT,
    MIN_RADIUS_EDGE,
};
pub use report::{LeftBad, RefineReport, Refined, SplitCauses};

use super::recover::{recover_mesh, Domain, RecoverError, Recovered};
use crate::geom::{union_join, union_root};
use crate::tet::dmesh::DomainMesh;
use crate::NONE;

/// Recovers the closed surface (`points`, `triangles`) and refines the
/// inside until every tetrahedron meets the bounds of `opts` (see the
/// [module documentation](self)).
///
/// # Errors
/// Every error of [`recover`](super::recover::recover);
/// [`RecoverError::Input`] with [`Error::InvalidBound`](crate::Error::InvalidBound)
/// for a bound no mesh can meet (checked before any work).
///
/// ```
/// use delone::tet::recover::check_recovered;
/// use delone::tet::refine::{refine, RefineOptions};
/// use delone::tet::quality::radius_edge_ratio;
/// let pts: Vec<[f64; 3]> = (0..8)
///     .map(|i| [(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64])
///     .collect();
/// let tris = [
///     [0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
///     [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5],
/// ];
/// let opts = RefineOptions { max_volume: Some(0.01), ..Default::default() };
/// let r = refine(&pts, &tris, &opts).unwrap();
/// check_recovered(&pts, &tris, &r.rec).unwrap();
/// assert!(r.rec.mesh.tets.len() >= 100);
/// for t in &r.rec.mesh.tets {
///     let p = t.map(|q| r.rec.points[q as usize]);
///     assert!(radius_edge_ratio(&p) <= 2.0 + 1e-9);
/// }
/// ```
pub fn refine(
    points: &[[f64; 3]],
    triangles: &[[u32; 3]],
    opts: &RefineOptions,
) -> Result<Refined, RecoverError> {
    opts.check_bounds().map_err(RecoverError::Input)?;
    let (rec, mesh) = recover_mesh(points, triangles, &[], &opts.recover, &Domain::default())?;
    refine_in_place(points, triangles, &rec, Some(mesh), opts).map(|(r, _)| r)
}

/// Refines a [`Recovered`] mesh of (`points`, `triangles`) made by
/// [`recover`](super::recover::recover) or [`recover_domain`](super::recover::recover_domain) (any path; holes, regions and internal
/// facets included): the mesh is refined in place, its boundary and
/// interior faces kept as constraints (see the [module documentation](self)).
///
/// # Errors
/// [`RecoverError::Unsupported`] when the mesh's neighbour links disagree
/// with its tetrahedra; [`RecoverError::Input`] with
/// [`Error::InvalidBound`](crate::Error::InvalidBound) for a bound no mesh
/// can meet.
///
/// ```
/// use delone::model::plc::Region;
/// use delone::tet::recover::{check_recovered, recover_domain, Domain, RecoverOptions};
/// use delone::tet::refine::{refine_recovered, RefineOptions};
/// // Two unit cubes sharing the square x = 1 (an internal facet).
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
///     regions: vec![Region { point: [1.5, 0.5, 0.5], attribute: 2.0, max_volume: None }],
///     ..Domain::default()
/// };
/// let rec = recover_domain(&pts, &tris, &RecoverOptions::default(), &dom).unwrap();
/// let opts = RefineOptions { max_radius_edge: Some(1.414), ..Default::default() };
/// let r = refine_recovered(&pts, &tris, &rec, &opts).unwrap();
/// check_recovered(&pts, &tris, &r.rec).unwrap();
/// assert_eq!(r.rec.regions.len(), 2);
/// assert!(r.rec.regions.iter().all(|g| (g.volume - 1.0).abs() < 1e-9));
/// assert_eq!(r.report.remaining_bad, 0);
/// ```
pub fn refine_recovered(
    points: &[[f64; 3]],
    triangles: &[[u32; 3]],
    rec: &Recovered,
    opts: &RefineOptions,
) -> Result<Refined, RecoverError> {
    refine_in_place(points, triangles, rec, None, opts).map(|(r, _)| r)
}

/// [`refine_recovered`] in `mesh`, the domain mesh of `rec` as recovery
/// hands it over ([`crate::tet::recover::recover_mesh`]; `None`: built
/// from `rec`'s neighbour lists), handing over the refined domain mesh
/// too: its tetrahedra are those of the result's `rec.mesh.tets` in that
/// order, with their neighbours, regions, subface marks and the subface /
/// subsegment tables, for optimisation to continue on it
/// ([`crate::tet::optimize::optimize_in_place`]).
pub(crate) fn refine_in_place(
    points: &[[f64; 3]],
    triangles: &[[u32; 3]],
    rec: &Recovered,
    mesh: Option<DomainMesh>,
    opts: &RefineOptions,
) -> Result<(Refined, DomainMesh), RecoverError> {
    // `rec` conforms to its own surface (coplanar input triangles may have
    // been merged and re-triangulated); its faces name those triangles.
    let triangles: &[[u32; 3]] = if rec.surface.is_empty() {
        triangles
    } else {
        &rec.surface
    };
    opts.check_bounds().map_err(RecoverError::Input)?;
    let mesh = match mesh {
        Some(m) => m,
        None => DomainMesh::from_neighbors(
            &rec.mesh.tets,
            &rec.mesh.neighbors,
            &rec.tet_region,
            rec.points.len(),
        )
        .map_err(|_| RecoverError::Unsupported {
            what: "refinement of a mesh whose neighbour links disagree",
        })?,
    };
    if rec.boundary_triangle.contains(&NONE) {
        // The convex hull is kept (`-c`): its faces off the surface become
        // facets of their own for the refinement.
        let (ext, n) = with_hull(triangles, rec);
        let mut st = cdr::Cdr::new(points, &ext.surface, &ext, mesh, opts)?;
        st.run();
        let (mut out, mut mesh) = st.finish(&ext);
        for t in out
            .rec
            .boundary_triangle
            .iter_mut()
            .chain(out.rec.interior_triangle.iter_mut())
            .chain(mesh.ftri.values_mut())
        {
            if *t as usize >= n {
                *t = NONE;
            }
        }
        out.rec.surface.clone_from(&rec.surface);
        out.rec.surface_origin.clone_from(&rec.surface_origin);
        return Ok((out, mesh));
    }
    let mut st = cdr::Cdr::new(points, triangles, rec, mesh, opts)?;
    st.run();
    Ok(st.finish(rec))
}

/// `rec` (with the convex hull kept) with its hull faces off the surface
/// appended to its surface as triangles, those of one plane that share
/// edges grouped into one facet (same `surface_origin`), and its boundary
/// faces naming them; and the number of surface triangles before them.
/// The hull facets are then refined like input facets: their sides
/// (the hull's edges and the input edges they meet) are subsegments.
fn with_hull(triangles: &[[u32; 3]], rec: &Recovered) -> (Recovered, usize) {
    let n = triangles.len();
    let mut ext = rec.clone();
    ext.surface = triangles.to_vec();
    ext.surface_origin = if rec.surface_origin.len() == n {
        rec.surface_origin.clone()
    } else {
        (0..n as u32).collect()
    };
    let hull: Vec<usize> = (0..rec.boundary.len())
        .filter(|&i| rec.boundary_triangle[i] == NONE)
        .collect();
    // Union-find over the hull faces: neighbours across an edge whose
    // fourth vertex lies exactly on the face's plane.
    let mut parent: Vec<u32> = (0..hull.len() as u32).collect();
    let mut by_edge: std::collections::HashMap<(u32, u32), Vec<usize>> = Default::default();
    for (k, &i) in hull.iter().enumerate() {
        let f = rec.boundary[i];
        for j in 0..3 {
            let (a, b) = (f[j], f[(j + 1) % 3]);
            by_edge.entry((a.min(b), a.max(b))).or_default().push(k);
        }
    }
    let pt = |q: u32| &rec.points[q as usize];
    let mut edges: Vec<_> = by_edge.into_iter().collect();
    edges.sort_unstable();
    for (_, l) in edges {
        if let [x, y] = l[..] {
            let (fx, fy) = (rec.boundary[hull[x]], rec.boundary[hull[y]]);
            let Some(&d) = fy.iter().find(|q| !fx.contains(q)) else {
                continue;
            };
            if delone_predicates::orient3d(pt(fx[0]), pt(fx[1]), pt(fx[2]), pt(d)) == 0.0 {
                union_join(&mut parent, x as u32, y as u32);
            }
        }
    }
    for (k, &i) in hull.iter().enumerate() {
        let root = union_root(&mut parent, k as u32) as usize;
        ext.surface.push(rec.boundary[i]);
        ext.surface_origin.push((n + root) as u32);
        ext.boundary_triangle[i] = (n + k) as u32;
    }
    (ext, n)
}
