//! Small closed surfaces shared by the 3D integration tests.
#![allow(dead_code)] // each test file uses some of them

/// The 12 outward triangles of a box whose corner `i` is
/// `(i & 1, i >> 1 & 1, i >> 2 & 1)` scaled per axis.
pub const BOX_TRIANGLES: [[u32; 3]; 12] = [
    [0, 2, 1],
    [1, 2, 3],
    [4, 5, 6],
    [5, 7, 6],
    [0, 1, 4],
    [1, 5, 4],
    [2, 6, 3],
    [3, 6, 7],
    [0, 4, 2],
    [2, 4, 6],
    [1, 3, 5],
    [3, 7, 5],
];

/// The box `[0,w]×[0,d]×[0,h]`, two triangles per side.
pub fn cuboid(w: f64, d: f64, h: f64) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let pts = (0..8)
        .map(|i| {
            [
                (i & 1) as f64 * w,
                ((i >> 1) & 1) as f64 * d,
                ((i >> 2) & 1) as f64 * h,
            ]
        })
        .collect();
    (pts, BOX_TRIANGLES.to_vec())
}

/// The unit cube.
pub fn cube() -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    cuboid(1.0, 1.0, 1.0)
}

/// Appends the axis-aligned box `lo..hi` (outward triangles) to `pts` and
/// `tris`.
pub fn add_box(pts: &mut Vec<[f64; 3]>, tris: &mut Vec<[u32; 3]>, lo: [f64; 3], hi: [f64; 3]) {
    let b = pts.len() as u32;
    for i in 0..8 {
        pts.push([
            if i & 1 == 0 { lo[0] } else { hi[0] },
            if i & 2 == 0 { lo[1] } else { hi[1] },
            if i & 4 == 0 { lo[2] } else { hi[2] },
        ]);
    }
    tris.extend(BOX_TRIANGLES.iter().map(|t| t.map(|v| v + b)));
}

/// Schönhardt's twisted prism: the top triangle rotated by `twist` degrees,
/// each side quadrilateral split by its reflex diagonal (the one that is not
/// a convex-hull edge).
pub fn schonhardt(twist: f64) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let mut pts = Vec::new();
    for i in 0..3 {
        let a = (120.0 * i as f64).to_radians();
        pts.push([a.cos(), a.sin(), 0.0]);
    }
    for i in 0..3 {
        let a = (120.0 * i as f64 + twist).to_radians();
        pts.push([a.cos(), a.sin(), 1.0]);
    }
    let hull: Vec<[u32; 3]> = delone::tetrahedralize(&pts).unwrap().hull_faces().collect();
    let hull_edge = |a: u32, b: u32| {
        hull.iter().any(|f| {
            (0..3).any(|k| (f[k] == a && f[(k + 1) % 3] == b) || (f[k] == b && f[(k + 1) % 3] == a))
        })
    };
    let mut tris = vec![[0, 2, 1], [3, 4, 5]];
    for i in 0..3u32 {
        let j = (i + 1) % 3;
        let (a0, a1, b0, b1) = (i, j, i + 3, j + 3);
        if hull_edge(a0, b1) {
            // Reflex diagonal a1-b0.
            tris.push([a0, a1, b0]);
            tris.push([a1, b1, b0]);
        } else {
            tris.push([a0, a1, b1]);
            tris.push([a0, b1, b0]);
        }
    }
    (pts, tris)
}
