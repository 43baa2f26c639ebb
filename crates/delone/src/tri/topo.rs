//! Local numbering and ghost conventions of the 2D kernel (no coordinates here).
//!
//! A triangle `t` stores its vertices counterclockwise in `tri_v[t] = [v0, v1, v2]`.
//! Edge `i` is the edge *opposite* vertex `i`; it runs from `v[i+1]` to `v[i+2]`
//! (indices mod 3), which is the counterclockwise direction around `t`:
//!
//! ```text
//!                 v2
//!                 /\
//!                /  \
//!      edge 1   /    \   edge 0
//!   (v2 -> v0) /  t   \ (v1 -> v2)
//!             /        \
//!          v0 ---------- v1
//!              edge 2
//!            (v0 -> v1)
//! ```
//!
//! Adjacency is stored as packed words `tri_adj[t][i] = 3 * t' + i'`: the
//! neighbour `t'` across edge `i` *and* the local index `i'` of the same edge in
//! `t'` come in one load. The twin edge in `t'` runs the opposite way.
//!
//! **Ghost triangles.** An infinite vertex [`INF`] closes the hull: every hull
//! edge has a ghost triangle on its outer side, so every edge has exactly two
//! triangles. A ghost always keeps `INF` in position 2, `[u, w, INF]`; its edge 2
//! (`u -> w`) is the hull edge, with the outside of the hull on its left (the
//! finite triangle across it holds the edge as `w -> u`):
//!
//! ```text
//!          INF (far away, outside)
//!           .
//!          . ghost [u, w, INF]
//!     u ----------- w        <- hull edge, seen from outside: u -> w
//!       \  finite /
//!        \  tri  /
//!          \   /
//! ```
//!
//! Ghosts are linked to each other across their edges 0 (`w -> INF`) and
//! 1 (`INF -> u`), so going around the hull is going around `INF`.

/// The infinite vertex that closes the hull (never a point index: point
/// indices are below `u32::MAX - 2`).
pub const INF: u32 = u32::MAX - 1;

/// Marker in `tri_v[t][0]` of a dead (free) triangle slot.
pub(crate) const DEAD: u32 = u32::MAX;

/// `NEXT[i] = (i + 1) % 3`.
pub(crate) const NEXT: [usize; 3] = [1, 2, 0];
/// `PREV[i] = (i + 2) % 3`.
pub(crate) const PREV: [usize; 3] = [2, 0, 1];

/// Packs triangle `t` and local edge `i` into one adjacency word.
#[inline(always)]
pub(crate) fn pack(t: usize, i: usize) -> u32 {
    (3 * t + i) as u32
}

/// Splits an adjacency word into (triangle, local edge).
#[inline(always)]
pub(crate) fn unpack(w: u32) -> (usize, usize) {
    ((w / 3) as usize, (w % 3) as usize)
}

/// The directed edge `i` of a triangle with vertices `v`: `(v[i+1], v[i+2])`.
#[inline(always)]
pub(crate) fn edge(v: &[u32; 3], i: usize) -> (u32, u32) {
    (v[NEXT[i]], v[PREV[i]])
}

/// True if `v` is a ghost triangle (holds [`INF`], always in position 2).
#[inline(always)]
pub(crate) fn is_ghost(v: &[u32; 3]) -> bool {
    v[2] == INF
}
