//! Carving: which tetrahedra of the recovered tetrahedralization form the
//! domain, and which region each belongs to.
//!
//! The constraint faces (mesh faces lying on input triangles) cut the cells
//! of the whole tetrahedralization (ghosts included) into **components**:
//! the classes of cells connected across non-constraint faces, found by a
//! flood fill in slot order (so the numbering is deterministic). Every
//! component also gets its **depth**, the least number of constraint faces
//! crossed from outside (the same for all cells of a component, since
//! crossing a non-constraint face costs nothing: a breadth-first search on
//! the graph of components, one edge per constraint face between two).
//!
//! Which components are kept:
//!
//! * the **exterior** (the component of the ghost cells, depth 0) only with
//!   [`Domain::convex_hull`] (TetGen's `-c`), and then as a region of its own;
//! * a component holding a **hole point** never;
//! * a component holding a **region point** always (even at even depth);
//! * any other component when its depth is odd. For one closed surface this
//!   is the usual "inside"; a closed surface nested in another (a cavity of a
//!   solid, as surface meshes describe it) is removed by this parity rule,
//!   unless a region point says it is material. Facets that divide the
//!   inside into several closed parts (internal facets: every edge in two or
//!   more input triangles) give several components at depth 1, each a region.
//!
//! Seeds (hole and region points) are located exactly: a visibility walk to
//! the closed tetrahedron containing the point, then the star of the point
//! (the tetrahedra whose closure contains it, gathered across the faces that
//! contain it, all tested by [`orient3d`]). A seed on a constraint face,
//! edge or vertex is ambiguous and rejected with
//! [`RecoverError::SeedOnSurface`](super::RecoverError::SeedOnSurface); a
//! seed outside the convex hull of the input lies in the exterior. Holes take
//! precedence over regions; of several region points in one component the
//! first listed wins. Seeds are scaled by the same exact power of two as the
//! input points (inexact only if a seed is many orders of magnitude outside
//! the input's range).
//!
//! Region attributes: a seeded region has its seed's attribute; the kept
//! exterior has 0; any other region without a seed is numbered
//! `m + 1, m + 2, …` in component order, where `m` is the floor of the
//! largest seed attribute (0 when there is none or it is negative), so every
//! region gets its own attribute.

use delone_predicates::orient3d;

use super::place;
use super::types::{MeshRegion, RecoverError};
use crate::geom::ids::IdSet;
use crate::model::plc::Region;
use crate::tet::delaunay::walk_cells;
use crate::tet::dmesh::Arrays;
use crate::tet::local::{DEAD, FACET, INF};

/// What to keep of the tetrahedralization of a PLC: hole points, region
/// points (with their attributes and volume bounds), and whether the part
/// outside the surface up to the convex hull is kept (TetGen's `-c`).
///
/// ```
/// use delone::model::plc::Region;
/// use delone::tet::recover::Domain;
/// let d = Domain {
///     holes: vec![[0.5, 0.5, 0.5]],
///     regions: vec![Region { point: [2.0, 0.5, 0.5], attribute: 7.0, max_volume: None }],
///     convex_hull: false,
/// };
/// assert_eq!(d.regions.len(), 1);
/// assert!(!Domain::default().convex_hull);
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Domain {
    /// One point inside each volume hole.
    pub holes: Vec<[f64; 3]>,
    /// Region points with their attributes and optional volume bounds.
    pub regions: Vec<Region>,
    /// Keep the tetrahedra outside the surface (up to the convex hull).
    pub convex_hull: bool,
}

/// The carving of a whole tetrahedralization.
pub(crate) struct Carved {
    /// Per slot: the region index of a kept finite cell, else `u32::MAX`.
    pub(crate) region: Vec<u32>,
    /// The regions (volume left 0, tets counted).
    pub(crate) regions: Vec<MeshRegion>,
    /// Components removed because a hole point lies in them.
    pub(crate) holes_removed: usize,
}

/// Is face `f` of cell `t` a constraint face? (`marks`: per slot and
/// face, the input triangle the face lies on, `u32::MAX` for none.)
#[inline]
fn is_constraint(marks: &[[u32; 4]], t: usize, f: usize) -> bool {
    marks[t][f] != u32::MAX
}

/// Per slot: the component (`u32::MAX` for dead slots), and the number of
/// components.
fn components((v, adj): Arrays<'_>, marks: &[[u32; 4]]) -> (Vec<u32>, usize) {
    let n = v.len();
    let mut comp = vec![u32::MAX; n];
    let mut count = 0u32;
    let mut stack = Vec::new();
    for s in 0..n {
        if v[s][0] == DEAD || comp[s] != u32::MAX {
            continue;
        }
        comp[s] = count;
        stack.push(s);
        while let Some(t) = stack.pop() {
            for (f, w) in adj[t].iter().enumerate() {
                let u = (w >> 2) as usize;
                if comp[u] == u32::MAX && !is_constraint(marks, t, f) {
                    comp[u] = count;
                    stack.push(u);
                }
            }
        }
        count += 1;
    }
    (comp, count as usize)
}

/// Per component: the least number of constraint faces crossed from
/// outside (`u32::MAX` when unreachable). Crossing a non-constraint face
/// costs nothing, so every cell of a component has the same depth: a
/// breadth-first search on the graph of components (an edge per constraint
/// face between two of them) from those holding a ghost cell gives it
/// without a pass over the cells per level.
fn component_depths(
    (v, adj): Arrays<'_>,
    marks: &[[u32; 4]],
    comp: &[u32],
    ncomp: usize,
) -> Vec<u32> {
    // Component adjacency across constraint faces, as compressed rows.
    let mut pairs: Vec<(u32, u32)> = Vec::new();
    for (t, m) in marks.iter().enumerate() {
        let ct = comp[t];
        if ct == u32::MAX {
            continue;
        }
        for (f, &mk) in m.iter().enumerate() {
            if mk == u32::MAX {
                continue;
            }
            let cu = comp[(adj[t][f] >> 2) as usize];
            if cu != ct && cu != u32::MAX {
                pairs.push((ct, cu));
            }
        }
    }
    let (start, next) = crate::geom::rows(ncomp, &pairs);
    let mut depth = vec![u32::MAX; ncomp];
    let mut queue: Vec<u32> = Vec::new();
    for (t, tv) in v.iter().enumerate() {
        if tv[0] != DEAD && tv.contains(&INF) {
            let c = comp[t] as usize;
            if depth[c] != 0 {
                depth[c] = 0;
                queue.push(c as u32);
            }
        }
    }
    let mut i = 0;
    while i < queue.len() {
        let c = queue[i] as usize;
        i += 1;
        for &d in &next[start[c] as usize..start[c + 1] as usize] {
            if depth[d as usize] == u32::MAX {
                depth[d as usize] = depth[c] + 1;
                queue.push(d);
            }
        }
    }
    depth
}

/// The component of seed point `p` (scaled like `pts`), or `Err(())` when
/// `p` lies on a constraint face (or edge or vertex).
fn locate(
    (v, adj): Arrays<'_>,
    pts: &[[f64; 3]],
    marks: &[[u32; 4]],
    comp: &[u32],
    p: &[f64; 3],
) -> Result<u32, ()> {
    let Some(start) = v.iter().position(|tv| tv[0] != DEAD && !tv.contains(&INF)) else {
        // No finite cell: everything is exterior.
        return Ok(v
            .iter()
            .position(|tv| tv[0] != DEAD)
            .map_or(u32::MAX, |s| comp[s]));
    };
    let mut rng = 0x2545_F491u32;
    let t = walk_cells((v, adj), pts, p, start as u32, &mut rng) as usize;
    if v[t][3] == INF {
        return Ok(comp[t]);
    }
    // The star of p: finite cells whose closure holds p, connected across
    // the faces through p.
    let mut seen: IdSet<u32> = IdSet::default();
    let mut stack = vec![t];
    seen.insert(t as u32);
    while let Some(x) = stack.pop() {
        let tv = v[x];
        for (f, idx) in FACET.iter().enumerate() {
            let [a, b, c] = idx.map(|i| &pts[tv[i] as usize]);
            if orient3d(a, b, c, p) != 0.0 {
                continue;
            }
            if is_constraint(marks, x, f) {
                return Err(());
            }
            let u = adj[x][f] >> 2;
            if v[u as usize].contains(&INF) {
                continue;
            }
            if seen.insert(u) {
                stack.push(u as usize);
            }
        }
    }
    Ok(comp[t])
}

/// Carves the tetrahedralization (`v`, `adj`: with ghost cells) of the (scaled) points `pts` whose
/// constraint faces are marked in `marks` (per slot and face: the input
/// triangle the face lies on, `u32::MAX` for none; both sides of a face
/// marked alike), as the [module documentation](self) says. `scale` is the factor pair the input was scaled by.
pub(crate) fn carve(
    (v, adj): Arrays<'_>,
    pts: &[[f64; 3]],
    marks: &[[u32; 4]],
    domain: &Domain,
    scale: (f64, f64),
) -> Result<Carved, RecoverError> {
    let (comp, ncomp) = components((v, adj), marks);
    let cdepth = component_depths((v, adj), marks, &comp, ncomp);
    let mut exterior = u32::MAX;
    for (s, &c) in comp.iter().enumerate() {
        if c != u32::MAX && v[s].contains(&INF) {
            exterior = c;
            break;
        }
    }
    let scaled = |p: &[f64; 3]| crate::geom::scaled(*p, scale);
    let mut hole = vec![false; ncomp];
    for (index, h) in domain.holes.iter().enumerate() {
        let c = locate((v, adj), pts, marks, &comp, &scaled(h)).map_err(|()| {
            RecoverError::SeedOnSurface {
                kind: "hole",
                index,
            }
        })?;
        if let Some(x) = hole.get_mut(c as usize) {
            *x = true;
        }
    }
    let mut seed: Vec<Option<usize>> = vec![None; ncomp];
    for (index, r) in domain.regions.iter().enumerate() {
        let c = locate((v, adj), pts, marks, &comp, &scaled(&r.point)).map_err(|()| {
            RecoverError::SeedOnSurface {
                kind: "region",
                index,
            }
        })?;
        if let Some(x) = seed.get_mut(c as usize) {
            x.get_or_insert(index);
        }
    }
    let keep = |c: usize| {
        if hole[c] {
            false
        } else if c as u32 == exterior {
            domain.convex_hull
        } else {
            seed[c].is_some() || cdepth[c] % 2 == 1
        }
    };
    let holes_removed = (0..ncomp).filter(|&c| hole[c]).count();
    let max_attr = domain
        .regions
        .iter()
        .map(|r| r.attribute)
        .filter(|a| a.is_finite())
        .fold(0.0f64, f64::max)
        .floor();
    let mut next_auto = max_attr + 1.0;
    let mut order: Vec<usize> = Vec::new();
    if exterior != u32::MAX && keep(exterior as usize) {
        order.push(exterior as usize);
    }
    order.extend((0..ncomp).filter(|&c| c as u32 != exterior && keep(c)));
    let mut region_of = vec![u32::MAX; ncomp];
    let mut regions = Vec::with_capacity(order.len());
    for (i, &c) in order.iter().enumerate() {
        region_of[c] = i as u32;
        let is_ext = c as u32 == exterior;
        let (attribute, max_volume) = match seed[c] {
            Some(s) => {
                let r = &domain.regions[s];
                (r.attribute, r.max_volume.filter(|&v| v > 0.0))
            }
            None if is_ext => (0.0, None),
            None => {
                next_auto += 1.0;
                (next_auto - 1.0, None)
            }
        };
        regions.push(MeshRegion {
            attribute,
            max_volume,
            seed: seed[c],
            exterior: is_ext,
            tets: 0,
            volume: 0.0,
        });
    }
    let mut region = vec![u32::MAX; v.len()];
    for (s, r) in region.iter_mut().enumerate() {
        let c = comp[s];
        if c == u32::MAX || v[s].contains(&INF) {
            continue;
        }
        let g = region_of[c as usize];
        if g != u32::MAX {
            *r = g;
            regions[g as usize].tets += 1;
        }
    }
    Ok(Carved {
        region,
        regions,
        holes_removed,
    })
}

/// Removes the **chord slivers** from the carved domain and returns how
/// many: a kept cell `a b c m` with two boundary faces, `a b c` on an input
/// triangle and `b c m` (listed on it or on the other triangle at `b c`),
/// where `m` is an inexact Steiner point
/// rounded onto the subsegment `b c` (strictly between `b` and `c`, off
/// the line by a few units in the last place). The coverage test accepts
/// the chord `b c` with the thin face `b c m` closing the gap, but the
/// cell is flat (dihedral angles 0° and 180°) and no refinement or
/// optimisation can improve it. Without it, its faces `a b m` and `a c m`
/// (on the same triangle, since all their vertices lie on it; marked so
/// here) become the boundary faces: the proper refinement of the triangle.
/// The volume given up is that of a cell of height about one rounding
/// error. Repeated while the removal exposes another such cell (a chain
/// of several points under one chord). Only cells whose two other
/// neighbours are kept and in the same region are removed, so the domain
/// stays closed and region interfaces are untouched.
pub(crate) fn drop_chord_slivers(
    (v, adj): Arrays<'_>,
    pts: &[[f64; 3]],
    marks: &mut [[u32; 4]],
    carved: &mut Carved,
    inexact: &[u32],
) -> usize {
    let region = &mut carved.region;
    let kept = |region: &[u32], t: usize| region.get(t).is_some_and(|&r| r != u32::MAX);
    let mut is_inexact = vec![false; pts.len()];
    for &q in inexact {
        if let Some(x) = is_inexact.get_mut(q as usize) {
            *x = true;
        }
    }
    if !is_inexact.contains(&true) {
        return 0;
    }
    // Is `m` on the open segment `b c` up to rounding?
    let thin = |b: u32, c: u32, m: u32| -> bool {
        let [pb, pc, pm] = [b, c, m].map(|q| pts[q as usize]);
        if pb == pc || !place::strictly_between(&pb, &pc, &pm) {
            return false;
        }
        let mag = [pb, pc, pm]
            .iter()
            .flatten()
            .fold(0f64, |a, x| a.max(x.abs()));
        place::line_distance(&pb, &pc, &pm) <= 64.0 * f64::EPSILON * mag
    };
    let mut work: Vec<usize> = (0..v.len()).filter(|&t| kept(region, t)).collect();
    let mut dropped = 0;
    while let Some(t) = work.pop() {
        if !kept(region, t) {
            continue;
        }
        let tv = v[t];
        let nb = adj[t].map(|w| (w >> 2) as usize);
        let open: Vec<usize> = (0..4).filter(|&f| !kept(region, nb[f])).collect();
        let &[f1, f2] = open.as_slice() else {
            continue;
        };
        let inner: Vec<usize> = (0..4).filter(|&f| f != f1 && f != f2).collect();
        let (b, c) = (tv[inner[0]], tv[inner[1]]);
        // Face `f1` holds `tv[f2]`, face `f2` holds `tv[f1]`. The thin face
        // may be listed on either triangle at `b c`; the chord's face names
        // the triangle the cell sits on.
        let found =
            [(tv[f2], f1, f2), (tv[f1], f2, f1)]
                .into_iter()
                .find(|&(m, thin_f, chord_f)| {
                    marks[t][thin_f] != crate::NONE
                        && marks[t][chord_f] != crate::NONE
                        && is_inexact[m as usize]
                        && thin(b, c, m)
                });
        let Some((_, _, chord_f)) = found else {
            continue;
        };
        let tri = marks[t][chord_f];
        if inner.iter().any(|&f| {
            (marks[t][f] != tri && marks[t][f] != crate::NONE) || region[nb[f]] != region[t]
        }) {
            continue;
        }
        if let Some(g) = carved.regions.get_mut(region[t] as usize) {
            g.tets -= 1;
        }
        region[t] = u32::MAX;
        dropped += 1;
        // The inner faces join `a` and `m` to `b` or `c`: all on the
        // triangle, now its boundary faces.
        for &f in &inner {
            let w = adj[t][f];
            marks[t][f] = tri;
            marks[(w >> 2) as usize][(w & 3) as usize] = tri;
        }
        work.extend(inner.iter().map(|&f| nb[f]));
    }
    dropped
}
