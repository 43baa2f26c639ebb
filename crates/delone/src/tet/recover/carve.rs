//! Carving: which tetrahedra are inside the recovered surface.
//!
//! A breadth-first search from the ghost cells (outside, depth 0) crosses
//! faces; crossing a constraint face (a face lying on an input triangle)
//! increases the depth by one, any other face keeps it (a 0-1 search on a
//! deque, so every cell gets its least number of surface crossings). Cells
//! at odd depth are inside. For one closed surface this is the usual flood
//! fill stopped by constraint faces; nested closed surfaces (a solid with a
//! cavity) are handled too.

use std::collections::VecDeque;

use super::missing::fkey;
use super::surface::IdSet;
use crate::tet::delaunay::Core;
use crate::tet::local::{DEAD, INF};

/// Per slot: the least number of constraint faces crossed from outside
/// (`u32::MAX` for dead slots).
pub(crate) fn depths(core: &Core, constraint: &IdSet<[u32; 3]>) -> Vec<u32> {
    let n = core.v.len();
    let mut depth = vec![u32::MAX; n];
    let mut dq = VecDeque::new();
    for (t, tv) in core.v.iter().enumerate() {
        if tv[0] != DEAD && tv.contains(&INF) {
            depth[t] = 0;
            dq.push_back(t as u32);
        }
    }
    while let Some(t) = dq.pop_front() {
        let tv = core.v[t as usize];
        let d = depth[t as usize];
        for f in 0..4 {
            let u = (core.adj[t as usize][f] >> 2) as usize;
            let k = fkey([tv[(f + 1) % 4], tv[(f + 2) % 4], tv[(f + 3) % 4]]);
            let cost = u32::from(!k.contains(&INF) && constraint.contains(&k));
            let nd = d + cost;
            if nd < depth[u] {
                depth[u] = nd;
                if cost == 0 {
                    dq.push_front(u as u32);
                } else {
                    dq.push_back(u as u32);
                }
            }
        }
    }
    depth
}
