//! Edge removal's two halves that every mesh structure shares: the walk
//! around an edge (an ordered ring of tetrahedra and vertices) and the
//! dynamic program that triangulates the ring polygon (Shewchuk's edge
//! removal; a ring of 3 is the 3-2 flip, of 4 the 4-4 flip).
//!
//! Both are pure functions over accessors: the walk gets the mesh's
//! vertices and adjacency ([`super::DomainMesh::ring_into`], with or
//! without ghost cells), the dynamic program the caller's objective.

/// True when `q` is an even permutation of `tv` (same orientation).
pub(crate) fn even(tv: [u32; 4], q: [u32; 4]) -> bool {
    let pos = q.map(|x| tv.iter().position(|&y| y == x).unwrap_or(0));
    let mut inv = 0;
    for i in 0..4 {
        for j in i + 1..4 {
            inv += usize::from(pos[i] > pos[j]);
        }
    }
    inv % 2 == 0
}

/// The two vertices of `tv` other than `a` and `b`, ordered so that
/// `[a, b, x, y]` has the orientation of `tv`.
pub(crate) fn opposite(tv: [u32; 4], a: u32, b: u32) -> Option<(u32, u32)> {
    // A tetrahedron holding `a` and `b` once each and two other distinct
    // vertices: the parity of the positions `[a, b, c, d]` take in `tv`
    // (`c` before `d`) directly.
    let ia = tv.iter().position(|&w| w == a);
    let ib = tv.iter().position(|&w| w == b);
    if let (Some(ia), Some(ib)) = (ia, ib) {
        let mut rest = (0..4).filter(|&k| k != ia && k != ib);
        if let (Some(ic), Some(id), true) = (rest.next(), rest.next(), ia != ib) {
            let (c, d) = (tv[ic], tv[id]);
            if c != d && c != a && c != b && d != a && d != b {
                let inv = usize::from(ia > ib)
                    + usize::from(ia > ic)
                    + usize::from(ia > id)
                    + usize::from(ib > ic)
                    + usize::from(ib > id);
                return Some(if inv % 2 == 0 { (c, d) } else { (d, c) });
            }
        }
    }
    let mut o = tv.iter().copied().filter(|&w| w != a && w != b);
    let (c, d) = (o.next()?, o.next()?);
    Some(if even(tv, [a, b, c, d]) {
        (c, d)
    } else {
        (d, c)
    })
}

/// How a ring walk ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum RingEnd {
    /// Back at the first tetrahedron: a cyclic ring.
    Closed,
    /// At a face with no tetrahedron behind it (the last `y` is appended
    /// to the ring, which has one vertex more than the tetrahedra).
    Open,
}

/// Walks around edge `a b` from tetrahedron `start` whose vertices other
/// than `a`, `b` are `(x, y)` (`[a, b, x, y]` positive), crossing the face
/// opposite `x` each time, appending each tetrahedron to `tets` and its
/// `x` to `ring`: `[a, b, ring[i], ring[i + 1]]` is `tets[i]`.
/// `verts(t)` gives a tetrahedron's vertices; `cross(t, i)` the tetrahedron
/// behind the face opposite its local vertex `i`: `Ok(Some(n))`, `Ok(None)`
/// for no tetrahedron (an open ring), `Err(())` for a face that must not
/// be crossed. `None` when a face must not be crossed, the topology is
/// broken, or the ring would exceed `cap` tetrahedra.
pub(crate) fn walk(
    start: u32,
    (mut x, mut y): (u32, u32),
    (a, b): (u32, u32),
    cap: usize,
    (tets, ring): (&mut Vec<u32>, &mut Vec<u32>),
    verts: impl Fn(u32) -> [u32; 4],
    cross: impl Fn(u32, usize) -> Result<Option<u32>, ()>,
) -> Option<RingEnd> {
    let mut cur = start;
    loop {
        if tets.len() >= cap {
            return None;
        }
        tets.push(cur);
        ring.push(x);
        let ix = verts(cur).iter().position(|&w| w == x)?;
        let Some(next) = cross(cur, ix).ok()? else {
            ring.push(y);
            return Some(RingEnd::Open);
        };
        if next == start {
            return Some(RingEnd::Closed);
        }
        let z = verts(next)
            .into_iter()
            .find(|&w| w != a && w != b && w != y)?;
        cur = next;
        x = y;
        y = z;
    }
}

/// The dynamic program of edge removal over a ring polygon of `n`
/// vertices: for every chord `i j` (`i < j`) the best triangulation of the
/// sub-polygon `i ..= j`, built from the best of `i ..= k` and `k ..= j`
/// and the triangle `i k j`. `best` and `choice` are scratch tables
/// (resized to `n * n`); a ring side starts at `side`, every other chord at
/// `unset`. `chord(i, j)` is evaluated once per chord before its splits;
/// `split(i, k, j, left, right, current, &chord)` returns the value of the
/// split at `k` when it beats `current` (the objective — a sum of costs, a
/// smallest quality, … — is the caller's), else `None`. Returns the value
/// of the whole polygon (chord `0 n-1`); [`ring_tets`] reads the chosen
/// triangulation from `choice`.
pub(crate) fn triangulate<T: Copy, C>(
    n: usize,
    (unset, side): (T, T),
    best: &mut Vec<T>,
    choice: &mut Vec<usize>,
    mut chord: impl FnMut(usize, usize) -> C,
    mut split: impl FnMut(usize, usize, usize, T, T, T, &C) -> Option<T>,
) -> T {
    best.clear();
    best.resize(n * n, unset);
    choice.clear();
    choice.resize(n * n, 0);
    if n < 2 {
        return unset;
    }
    for i in 0..n - 1 {
        best[i * n + i + 1] = side;
    }
    for len in 2..n {
        for i in 0..n - len {
            let j = i + len;
            let c = chord(i, j);
            for k in i + 1..j {
                let (l, r) = (best[i * n + k], best[k * n + j]);
                if let Some(v) = split(i, k, j, l, r, best[i * n + j], &c) {
                    best[i * n + j] = v;
                    choice[i * n + j] = k;
                }
            }
        }
    }
    best[n - 1]
}

/// The edge removal of edge `a b` with ring `r` that maximises the
/// smallest quality of its tetrahedra (`[r_i, r_k, r_j, b]` and
/// `[r_i, r_j, r_k, a]` for each ring triangle `i k j`): its smallest
/// quality and tetrahedra, or `None` when no triangulation has all its
/// qualities above `need`. Sub-polygons and triangles at or below `need`
/// are pruned, so `qual` runs only where it can matter. `best` and
/// `choice` are [`triangulate`]'s scratch tables.
pub(crate) fn max_min(
    r: &[u32],
    (a, b): (u32, u32),
    need: f64,
    (best, choice): (&mut Vec<f64>, &mut Vec<usize>),
    mut qual: impl FnMut([u32; 4]) -> f64,
) -> Option<(f64, Vec<[u32; 4]>)> {
    let q = triangulate(
        r.len(),
        (f64::NEG_INFINITY, f64::INFINITY),
        best,
        choice,
        |_, _| (),
        |i, k, j, l, rr, cur, _| {
            let bound = l.min(rr);
            if bound <= cur || bound <= need {
                return None;
            }
            let q1 = qual([r[i], r[k], r[j], b]);
            if q1 <= need || q1 <= cur {
                return None;
            }
            let q2 = qual([r[i], r[j], r[k], a]);
            let v = bound.min(q1).min(q2);
            (v > cur).then_some(v)
        },
    );
    (q > need).then(|| (q, ring_tets(r, choice, a, b)))
}

/// The `2n - 4` tetrahedra of an edge removal: the triangulation of the ring
/// `r` (`n` vertices) that [`triangulate`] chose (`choice[i * n + j]` is the
/// apex `k` of the triangle on chord `i j`), each triangle joined to the
/// edge's two ends `a` and `b`.
pub(crate) fn ring_tets(r: &[u32], choice: &[usize], a: u32, b: u32) -> Vec<[u32; 4]> {
    let mut new = Vec::with_capacity(2 * r.len().saturating_sub(2));
    ring_tets_into(r, choice, a, b, &mut new);
    new
}

/// [`ring_tets`] into `new` (cleared first; no allocation once it has
/// room).
pub(crate) fn ring_tets_into(r: &[u32], choice: &[usize], a: u32, b: u32, new: &mut Vec<[u32; 4]>) {
    new.clear();
    split(r, choice, (a, b), (0, r.len().saturating_sub(1)), new);
}

/// The tetrahedra of the triangles below chord `i j` (depth first: the
/// chord's triangle, then those below `k j`, then those below `i k`).
fn split(
    r: &[u32],
    choice: &[usize],
    (a, b): (u32, u32),
    (i, j): (usize, usize),
    new: &mut Vec<[u32; 4]>,
) {
    if j < i + 2 {
        return;
    }
    let k = choice[i * r.len() + j];
    new.push([r[i], r[k], r[j], b]);
    new.push([r[i], r[j], r[k], a]);
    split(r, choice, (a, b), (k, j), new);
    split(r, choice, (a, b), (i, k), new);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parity_and_opposite() {
        assert!(even([0, 1, 2, 3], [1, 0, 3, 2]));
        assert!(!even([0, 1, 2, 3], [1, 0, 2, 3]));
        let (x, y) = opposite([4, 7, 5, 9], 7, 9).unwrap();
        assert!(even([4, 7, 5, 9], [7, 9, x, y]));
        assert!(opposite([7, 9, 7, 9], 7, 9).is_none());
    }

    /// The DP with a sum objective (fewest total "length") on a hexagon
    /// picks a fan or zig-zag of 4 triangles; `ring_tets` gives 2n - 4.
    #[test]
    fn triangulate_sum_and_max_min() {
        let n = 6;
        let (mut best, mut choice) = (Vec::new(), Vec::new());
        // Sum of chord lengths |i - j| (a fan from 0 is not cheapest).
        let total = triangulate(
            n,
            (i64::MAX, 0),
            &mut best,
            &mut choice,
            |i, j| (j - i) as i64,
            |_, _, _, l, r, cur, c| {
                if l == i64::MAX || r == i64::MAX {
                    return None;
                }
                let v = l + r + c;
                (v < cur).then_some(v)
            },
        );
        assert!(total < i64::MAX);
        let r: Vec<u32> = (10..16).collect();
        let tets = ring_tets(&r, &choice, 0, 1);
        assert_eq!(tets.len(), 2 * n - 4);
        // Max-min: the triangle with apex 3 is forbidden for chord 0-5.
        let mut bestf = Vec::new();
        let q = triangulate(
            n,
            (f64::NEG_INFINITY, f64::INFINITY),
            &mut bestf,
            &mut choice,
            |_, _| (),
            |i, k, j, l, r, cur, _| {
                if (i, j) == (0, 5) && k == 3 {
                    return None;
                }
                let v = l.min(r).min(1.0 / (j - i) as f64);
                (v > cur).then_some(v)
            },
        );
        assert!(q > 0.0);
        assert_ne!(choice[5], 3);
        // Too small a polygon.
        assert_eq!(
            triangulate(
                1,
                (0, 1),
                &mut best,
                &mut choice,
                |_, _| (),
                |_, _, _, _, _, _, _| None
            ),
            0
        );
    }

    /// A closed walk around the axis of a fan of four tetrahedra.
    #[test]
    fn walk_closed_and_open() {
        // Edge 0-1 with ring 2, 3, 4, 5: tets [0, 1, r_i, r_{i+1}].
        let ring_v = [2u32, 3, 4, 5];
        let tv: Vec<[u32; 4]> = (0..4)
            .map(|i| [0, 1, ring_v[i], ring_v[(i + 1) % 4]])
            .collect();
        let verts = |t: u32| tv[t as usize];
        // Across the face opposite x (= ring[i]) lies tet i + 1.
        let cross = |t: u32, i: usize| {
            assert_eq!(i, 2);
            Ok(Some((t + 1) % 4))
        };
        let (mut ts, mut r) = (Vec::new(), Vec::new());
        let end = walk(0, (2, 3), (0, 1), 16, (&mut ts, &mut r), verts, cross);
        assert_eq!(end, Some(RingEnd::Closed));
        assert_eq!(ts, vec![0, 1, 2, 3]);
        assert_eq!(r, vec![2, 3, 4, 5]);
        // Open after tet 2; too small a cap; a forbidden face.
        let open = |t: u32, _: usize| Ok((t < 2).then_some(t + 1));
        let (mut ts, mut r) = (Vec::new(), Vec::new());
        assert_eq!(
            walk(0, (2, 3), (0, 1), 16, (&mut ts, &mut r), verts, open),
            Some(RingEnd::Open)
        );
        assert_eq!(r, vec![2, 3, 4, 5]);
        let (mut ts, mut r) = (Vec::new(), Vec::new());
        assert!(walk(0, (2, 3), (0, 1), 2, (&mut ts, &mut r), verts, cross).is_none());
        let shut = |_: u32, _: usize| Err(());
        let (mut ts, mut r) = (Vec::new(), Vec::new());
        assert!(walk(0, (2, 3), (0, 1), 16, (&mut ts, &mut r), verts, shut).is_none());
    }
}
