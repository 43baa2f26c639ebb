//! 3D power diagrams (duals of regular tetrahedralizations).

use delone::geom::SplitMix64;
use delone::tet::voronoi::Polyhedron;
use delone::tet::{regular_tetrahedralization, Voronoi3};

fn unit(r: &mut SplitMix64) -> f64 {
    (r.next_u64() >> 11) as f64 / (1u64 << 53) as f64
}

fn sub(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Newell normal of a polygon (outward for a counterclockwise face).
fn newell(pts: &[[f64; 3]]) -> [f64; 3] {
    let mut n = [0.0; 3];
    for k in 0..pts.len() {
        let (a, b) = (pts[k], pts[(k + 1) % pts.len()]);
        n[0] += (a[1] - b[1]) * (a[2] + b[2]);
        n[1] += (a[2] - b[2]) * (a[0] + b[0]);
        n[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    n
}

/// Smallest signed distance from `x` to the faces' planes (positive inside).
fn inside_margin(poly: &Polyhedron, x: &[f64; 3]) -> f64 {
    let mut worst = f64::INFINITY;
    for f in &poly.faces {
        let pts: Vec<[f64; 3]> = f.iter().map(|&v| poly.vertices[v as usize]).collect();
        let n = newell(&pts);
        let len = dot(&n, &n).sqrt();
        if len > 1e-12 {
            worst = worst.min(-dot(&sub(x, &pts[0]), &n) / len);
        }
    }
    worst
}

#[test]
fn power_cells_tile_the_box_and_contain_their_points() {
    for (n, seed, spread) in [(40, 1, 0.2), (300, 2, 0.05), (2000, 3, 0.01)] {
        let mut r = SplitMix64::new(seed);
        let pts: Vec<[f64; 3]> = (0..n)
            .map(|_| [unit(&mut r), unit(&mut r), unit(&mut r)])
            .collect();
        let ws: Vec<f64> = (0..n).map(|_| spread * unit(&mut r)).collect();
        let mesh = regular_tetrahedralization(&pts, &ws).unwrap();
        assert!(
            !mesh.hidden.is_empty() || n > 1000,
            "n={n}: expect hidden points"
        );
        let v = Voronoi3::new_power(&pts, &ws, &mesh);
        let bbox = [[-0.5; 3], [1.5; 3]];
        let cells = v.cells_clipped(&pts, bbox);
        let total: f64 = cells.volume.iter().sum();
        assert!(
            (total - 8.0).abs() < 1e-9 * 8.0,
            "n={n}: volumes sum to {total}"
        );
        for &h in &mesh.hidden {
            assert_eq!(cells.volume[h as usize], 0.0, "hidden {h} has a cell");
            assert!(v.cell_faces(h as usize).is_empty());
        }
        // Sampled points lie in the cell of a site of least power distance.
        let power = |x: &[f64; 3], i: usize| {
            let d = sub(x, &pts[i]);
            dot(&d, &d) - ws[i]
        };
        for _ in 0..300 {
            let x = [
                -0.5 + 2.0 * unit(&mut r),
                -0.5 + 2.0 * unit(&mut r),
                -0.5 + 2.0 * unit(&mut r),
            ];
            let best = (0..n).map(|i| power(&x, i)).fold(f64::INFINITY, f64::min);
            let found = (0..n)
                .filter(|&i| power(&x, i) <= best + 1e-9)
                .any(|i| inside_margin(&cells.cells[i], &x) > -1e-9);
            assert!(found, "n={n}: sample {x:?} is in no cell of least power");
        }
    }
}

#[test]
fn zero_weights_give_the_voronoi_diagram() {
    let mut r = SplitMix64::new(9);
    let pts: Vec<[f64; 3]> = (0..200)
        .map(|_| [unit(&mut r), unit(&mut r), unit(&mut r)])
        .collect();
    let zero = vec![0.0; pts.len()];
    let mesh = regular_tetrahedralization(&pts, &zero).unwrap();
    let a = Voronoi3::new_power(&pts, &zero, &mesh);
    let b = Voronoi3::new(&pts, &delone::tetrahedralize(&pts).unwrap());
    assert_eq!(a.vertices, b.vertices);
    assert_eq!(a.faces, b.faces);
    let bbox = [[0.0; 3], [1.0; 3]];
    assert_eq!(
        a.cells_clipped(&pts, bbox).volume,
        b.cells_clipped(&pts, bbox).volume
    );
}
