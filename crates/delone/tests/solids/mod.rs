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

/// Counterclockwise quad `a b c d` (seen from outside) as two triangles.
pub fn quad(tris: &mut Vec<[u32; 3]>, q: [u32; 4]) {
    tris.push([q[0], q[1], q[2]]);
    tris.push([q[0], q[2], q[3]]);
}

/// A unit cube whose sides are `n × n` grids of squares, two triangles
/// each, oriented outward. With `alternate` the diagonals alternate from
/// square to square; otherwise every square is cut along the same
/// diagonal.
pub fn grid_cube(n: u32, alternate: bool) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let mut pts = Vec::new();
    let mut ids = std::collections::BTreeMap::new();
    let mut tris = Vec::new();
    for axis in 0..3 {
        for side in [0, n] {
            for i in 0..n {
                for j in 0..n {
                    let mut c = [0u32; 4];
                    for (k, (di, dj)) in [(0, 0), (1, 0), (1, 1), (0, 1)].into_iter().enumerate() {
                        let mut p = [0u32; 3];
                        p[axis] = side;
                        p[(axis + 1) % 3] = i + di;
                        p[(axis + 2) % 3] = j + dj;
                        c[k] = *ids.entry(p).or_insert_with(|| {
                            pts.push(p.map(|x| f64::from(x) / f64::from(n)));
                            pts.len() as u32 - 1
                        });
                    }
                    if !alternate {
                        if side == n {
                            quad(&mut tris, c);
                        } else {
                            tris.extend([[c[0], c[2], c[1]], [c[0], c[3], c[2]]]);
                        }
                        continue;
                    }
                    if side == 0 {
                        c.reverse();
                    }
                    if (i + j) % 2 == 0 {
                        quad(&mut tris, c);
                    } else {
                        quad(&mut tris, [c[1], c[2], c[3], c[0]]);
                    }
                }
            }
        }
    }
    (pts, tris)
}

/// Breakpoints of `k` V-shaped notches of half-width `w` across `0..len`,
/// with the depth factor (0 or 1) at each.
pub fn notch_profile(k: usize, len: f64, w: f64) -> Vec<(f64, f64)> {
    let mut out = vec![(0.0, 0.0)];
    for i in 0..k {
        let c = (i as f64 + 0.5) * len / k as f64;
        out.extend([(c - w, 0.0), (c, 1.0), (c + w, 0.0)]);
    }
    out.push((len, 0.0));
    out
}

/// Chazelle-style polyhedron: a `len × len × h` box whose top has `k`
/// V-notches of depth `d` running along y and whose bottom has `k` running
/// along x, so that the two families of grooves nearly meet (the classic
/// input needing many Steiner points). Returns the surface and its volume.
pub fn chazelle(k: usize, len: f64, h: f64, d: f64) -> (Vec<[f64; 3]>, Vec<[u32; 3]>, f64) {
    let w = 0.3 * len / k as f64;
    let xs = notch_profile(k, len, w); // top: z = h - d·f(x)
    let ys = notch_profile(k, len, w); // bottom: z = d·f(y)
    let (nx, ny) = (xs.len(), ys.len());
    let mut pts = Vec::new();
    // Top grid, then bottom grid.
    for &(x, fx) in &xs {
        for &(y, _) in &ys {
            pts.push([x, y, h - d * fx]);
        }
    }
    for &(x, _) in &xs {
        for &(y, fy) in &ys {
            pts.push([x, y, d * fy]);
        }
    }
    let top = |i: usize, j: usize| (i * ny + j) as u32;
    let bot = |i: usize, j: usize| (nx * ny + i * ny + j) as u32;
    let mut tris = Vec::new();
    for i in 0..nx - 1 {
        for j in 0..ny - 1 {
            quad(
                &mut tris,
                [top(i, j), top(i + 1, j), top(i + 1, j + 1), top(i, j + 1)],
            );
            quad(
                &mut tris,
                [bot(i, j), bot(i, j + 1), bot(i + 1, j + 1), bot(i + 1, j)],
            );
        }
    }
    // Sides x = 0 and x = len (outward -x and +x).
    for j in 0..ny - 1 {
        quad(
            &mut tris,
            [bot(0, j), top(0, j), top(0, j + 1), bot(0, j + 1)],
        );
        let l = nx - 1;
        quad(
            &mut tris,
            [bot(l, j), bot(l, j + 1), top(l, j + 1), top(l, j)],
        );
    }
    // Sides y = 0 and y = len (outward -y and +y).
    for i in 0..nx - 1 {
        quad(
            &mut tris,
            [bot(i, 0), bot(i + 1, 0), top(i + 1, 0), top(i, 0)],
        );
        let l = ny - 1;
        quad(
            &mut tris,
            [bot(i, l), top(i, l), top(i + 1, l), bot(i + 1, l)],
        );
    }
    // Each notch removes a prism of cross-section w·d and length len.
    let vol = len * len * h - 2.0 * k as f64 * len * w * d;
    (pts, tris, vol)
}
