//! The 3-2 flip that recovers a missing face crossed by one edge.
//!
//! Edge `p q` with exactly three tetrahedra around it, whose ring `r1 r2 r3`
//! is a triangle crossed properly by `p q`: the three tetrahedra are replaced
//! by `r1 r2 r3 p` and `r1 r2 r3 q`, which makes `r1 r2 r3` a face.
//! Combinatorics only; the one geometric decision (the proper crossing) is
//! made by the caller with exact predicates.

use crate::tet::delaunay::Core;
use crate::tet::dmesh::journal::Journaled;
use crate::tet::dmesh::ring::{walk, RingEnd};
use crate::tet::local::{DEAD, INF};
use crate::tet::Delaunay3;

/// The tetrahedra around edge `p q`, starting at `t` (which contains it), in
/// rotational order; `None` when a ghost cell is met or the ring is longer
/// than `cap`.
pub(crate) fn ring(core: &Core, t: u32, p: u32, q: u32, cap: usize) -> Option<Vec<u32>> {
    let mut o = core.v[t as usize].into_iter().filter(|&x| x != p && x != q);
    let (r, s) = (o.next()?, o.next()?);
    let cross = |c: u32, i: usize| {
        let cv = core.v[c as usize];
        if cv[0] == DEAD || cv.contains(&INF) {
            Err(())
        } else {
            Ok(Some(core.adj[c as usize][i] >> 2))
        }
    };
    let (mut tets, mut verts) = (Vec::new(), Vec::new());
    let end = walk(
        t,
        (r, s),
        (p, q),
        cap,
        (&mut tets, &mut verts),
        |c| core.v[c as usize],
        cross,
    )?;
    (end == RingEnd::Closed).then_some(tets)
}

/// Replaces the three tetrahedra `ring` around edge `p q` of `dt` by the
/// two sharing face `r` (the ring vertices), oriented with `orient` (true
/// when `[r0, r1, r2, p]` is positive), by the domain mesh's one
/// replacement ([`Journaled::replace`]).
pub(crate) fn flip32(
    dt: &mut Delaunay3<'_>,
    ring: &[u32],
    (p, q): (u32, u32),
    r: [u32; 3],
    orient: bool,
) {
    let (ra, rb) = if orient { (r[0], r[1]) } else { (r[1], r[0]) };
    // [ra, rb, r2, p] positive; then [rb, ra, r2, q] is positive (q is on the
    // other side of the plane).
    let mut cm = Journaled::new(std::mem::take(dt));
    cm.replace(ring, &[[ra, rb, r[2], p], [rb, ra, r[2], q]]);
    *dt = cm.into_dt();
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tet::dmesh::tests::three_around_an_edge;
    use crate::tet::recover::missing;

    #[test]
    fn flip32_creates_the_ring_face() {
        // p and q close to the plane of r0 r1 r2: the Delaunay
        // tetrahedralization has edge p q with three tetrahedra around it.
        let pts = three_around_an_edge();
        let mut dt = Delaunay3::from_points(&pts).unwrap();
        assert_eq!(dt.num_tets(), 3);
        assert!(!missing(&[[0, 1, 2]], dt.tets()).triangles.is_empty());
        let t = dt
            .core
            .v
            .iter()
            .position(|tv| {
                tv[0] != DEAD && !tv.contains(&INF) && tv.contains(&3) && tv.contains(&4)
            })
            .unwrap() as u32;
        let r = ring(&dt.core, t, 3, 4, 8).unwrap();
        assert_eq!(r.len(), 3);
        let orient = delone_predicates::orient3d(&pts[0], &pts[1], &pts[2], &pts[3]) < 0.0;
        flip32(&mut dt, &r, (3, 4), [0, 1, 2], orient);
        dt.check_topology().unwrap();
        assert_eq!(dt.num_tets(), 2);
        assert!(missing(&[[0, 1, 2]], dt.tets()).is_empty());
        // A ring through a ghost cell is refused.
        let hull = dt
            .core
            .v
            .iter()
            .position(|tv| tv[0] != DEAD && tv.contains(&INF))
            .unwrap();
        let tv = dt.core.v[hull];
        assert!(ring(&dt.core, hull as u32, tv[0], tv[1], 8).is_none());
    }
}
