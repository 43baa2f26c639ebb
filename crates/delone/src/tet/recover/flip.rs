//! The 3-2 flip that recovers a missing face crossed by one edge.
//!
//! Edge `p q` with exactly three tetrahedra around it, whose ring `r1 r2 r3`
//! is a triangle crossed properly by `p q`: the three tetrahedra are replaced
//! by `r1 r2 r3 p` and `r1 r2 r3 q`, which makes `r1 r2 r3` a face.
//! Combinatorics only; the one geometric decision (the proper crossing) is
//! made by the caller with exact predicates.

use crate::tet::delaunay::Core;
use crate::tet::local::fkey;
use crate::tet::local::{DEAD, INF};

/// The tetrahedra around edge `p q`, starting at `t` (which contains it), in
/// rotational order; `None` when a ghost cell is met or the ring is longer
/// than `cap`.
pub(crate) fn ring(core: &Core, t: u32, p: u32, q: u32, cap: usize) -> Option<Vec<u32>> {
    let tv = core.v[t as usize];
    let mut r = *tv.iter().find(|&&x| x != p && x != q)?;
    let mut cur = t;
    let mut out = Vec::new();
    loop {
        let cv = core.v[cur as usize];
        if cv[0] == DEAD || cv.contains(&INF) || out.len() >= cap {
            return None;
        }
        out.push(cur);
        let ir = cv.iter().position(|&x| x == r)?;
        let s = *cv.iter().find(|&&x| x != p && x != q && x != r)?;
        let w = core.adj[cur as usize][ir];
        cur = w >> 2;
        r = s;
        if cur == t {
            return Some(out);
        }
    }
}

/// Replaces the three tetrahedra `ring` around edge `p q` by the two sharing
/// face `r` (the ring vertices), oriented with `orient` (true when
/// `[r0, r1, r2, p]` is positive). Returns the two new slots.
pub(crate) fn flip32(
    core: &mut Core,
    ring: &[u32],
    p: u32,
    q: u32,
    r: [u32; 3],
    orient: bool,
) -> [u32; 2] {
    let mut outer: Vec<([u32; 3], u32)> = Vec::with_capacity(6);
    for &t in ring {
        let tv = core.v[t as usize];
        for f in 0..4 {
            if tv[f] == p || tv[f] == q {
                let k = [tv[(f + 1) % 4], tv[(f + 2) % 4], tv[(f + 3) % 4]];
                outer.push((fkey(k), core.adj[t as usize][f]));
            }
        }
    }
    for &t in ring {
        core.release(t);
    }
    let (ra, rb) = if orient { (r[0], r[1]) } else { (r[1], r[0]) };
    // [ra, rb, r2, p] positive; then [rb, ra, r2, q] is positive (q is on the
    // other side of the plane).
    let a = core.alloc([ra, rb, r[2], p]);
    let b = core.alloc([rb, ra, r[2], q]);
    let inner = fkey(r);
    for x in [a, b] {
        let xv = core.v[x as usize];
        for f in 0..4 {
            let k = fkey([xv[(f + 1) % 4], xv[(f + 2) % 4], xv[(f + 3) % 4]]);
            if k == inner {
                continue;
            }
            if let Some(&(_, w)) = outer.iter().find(|(kk, _)| *kk == k) {
                core.link(x, f, w >> 2, (w & 3) as usize);
            }
        }
    }
    // Face opposite p in a, opposite q in b.
    core.link(a, 3, b, 3);
    core.last = a;
    [a, b]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tet::recover::missing;
    use crate::tet::Delaunay3;

    #[test]
    fn flip32_creates_the_ring_face() {
        // p and q close to the plane of r0 r1 r2: the Delaunay
        // tetrahedralization has edge p q with three tetrahedra around it.
        let s = 3f64.sqrt() / 2.0;
        let pts = [
            [1.0, 0.0, 0.0],
            [-0.5, s, 0.0],
            [-0.5, -s, 0.0],
            [0.0, 0.0, 0.1],
            [0.0, 0.0, -0.1],
        ];
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
        flip32(&mut dt.core, &r, 3, 4, [0, 1, 2], orient);
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
