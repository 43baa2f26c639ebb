//! A structured mesh of the unit cube with references, the starting mesh
//! of the 3D adaptation tests and benchmark.

use super::TetMesh;
use delone_predicates::orient3d;

/// The unit cube as `n³` cubes of six tetrahedra each (positive), region
/// 1 below z = 1/2 and 2 above (n even) when `interface` (else all in
/// region 1), the six sides as triangles with references 1..=6, the
/// interface z = 1/2 with reference 7 when `interface`, the eight
/// corners and the twelve edges as ridges.
pub fn cube(n: usize, interface: bool) -> TetMesh {
    let id = |i: usize, j: usize, k: usize| (i + (n + 1) * (j + (n + 1) * k)) as u32;
    let mut m = TetMesh::default();
    for k in 0..=n {
        for j in 0..=n {
            for i in 0..=n {
                m.points.push([i, j, k].map(|x| x as f64 / n as f64));
            }
        }
    }
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let c = |b: usize| id(i + (b & 1), j + (b >> 1 & 1), k + (b >> 2));
                // Kuhn's six tetrahedra on the diagonal 0-7.
                for path in [[1, 3], [1, 5], [2, 3], [2, 6], [4, 5], [4, 6]] {
                    let mut t = [c(0), c(path[0]), c(path[1]), c(7)];
                    let g = |q: u32| &m.points[q as usize];
                    if orient3d(g(t[0]), g(t[1]), g(t[2]), g(t[3])) > 0.0 {
                        t.swap(0, 1);
                    }
                    m.elements.push(t);
                    m.element_refs
                        .push(if 2 * k < n || !interface { 1 } else { 2 });
                }
            }
        }
    }
    // Faces: every element face on a side or on the interface.
    let mut faces: Vec<([u32; 3], i32)> = Vec::new();
    for t in &m.elements {
        for f in 0..4 {
            let mut k: Vec<u32> = (0..4).filter(|&i| i != f).map(|i| t[i]).collect();
            k.sort_unstable();
            let p: Vec<[f64; 3]> = k.iter().map(|&q| m.points[q as usize]).collect();
            let on = |axis: usize, v: f64| p.iter().all(|x| x[axis] == v);
            let r = (0..3)
                .flat_map(|a| [(a, 0.0), (a, 1.0)])
                .position(|(a, v)| on(a, v))
                .map(|i| i as i32 + 1)
                .or_else(|| (interface && on(2, 0.5)).then_some(7));
            if let Some(r) = r {
                let key = [k[0], k[1], k[2]];
                if !faces.iter().any(|f| f.0 == key) {
                    faces.push((key, r));
                }
            }
        }
    }
    m.faces = faces.iter().map(|f| f.0).collect();
    m.face_refs = faces.iter().map(|f| f.1).collect();
    m.corners = (0..8)
        .map(|b| id(n * (b & 1), n * (b >> 1 & 1), n * (b >> 2)))
        .collect();
    for a in 0..3 {
        for (u, v) in [(0, 0), (0, n), (n, 0), (n, n)] {
            for s in 0..n {
                let at = |s: usize| {
                    let mut x = [s; 3];
                    x[(a + 1) % 3] = u;
                    x[(a + 2) % 3] = v;
                    id(x[0], x[1], x[2])
                };
                m.ridges.push([at(s), at(s + 1)]);
            }
        }
    }
    m
}
