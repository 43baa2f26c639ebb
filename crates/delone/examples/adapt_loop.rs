//! A solve–adapt loop: the "solution" is a tanh shock layer along a circle
//! (2D), u = tanh(40 (r − 0.6)) with r the distance from (−0.1, −0.1), or
//! along a sphere (3D, `3d`), u = tanh(20 (r − 0.8)) with r the distance
//! from (−0.1, −0.1, −0.1) on the unit cube; each iteration recovers its
//! Hessian at the mesh's vertices, builds the L² optimal metric for a fixed
//! complexity, and adapts the mesh to it, printing a line of statistics.
//! In 2D it writes the final mesh as a PNG.
//!
//! ```text
//! cargo run --release -p delone --example adapt_loop -- docs/adapt_loop.png
//! cargo run --release -p delone --example adapt_loop -- 3d
//! ```

use delone::adapt::{
    adapt_tet, adapt_tri, AdaptOptions, Adapted, MetricField, MetricStats, SimplexMesh, TetMesh,
    TriMesh,
};
use delone::metric::{hessians, metric_from_hessians, Target};
use delone::Error;

#[path = "../tests/common/cube.rs"]
mod cube;

fn field3(p: &[f64; 3]) -> f64 {
    let r = ((p[0] + 0.1).powi(2) + (p[1] + 0.1).powi(2) + (p[2] + 0.1).powi(2)).sqrt();
    (20.0 * (r - 0.8)).tanh()
}

fn print(it: usize, s: &MetricStats, what: &str, secs: f64) {
    println!(
        "iteration {it}: {} vertices, {} {what}, {:.1}% of edges in [1/√2, √2], quality min {:.3} mean {:.3}, {secs:.2} s",
        s.vertices,
        s.elements,
        100.0 * s.in_range_share(),
        s.quality_min,
        s.quality_mean
    );
}

/// Adapts `mesh` `iterations` times to the metric of `field`'s Hessian
/// (complexity `complexity`, sizes in `[hmin, hmax]`), a line each.
fn iterate<const D: usize, const K: usize>(
    mut mesh: SimplexMesh<D, K>,
    field: fn(&[f64; D]) -> f64,
    (complexity, hmin, hmax): (f64, f64, f64),
    iterations: usize,
    adapt: fn(&SimplexMesh<D, K>, MetricField<D>, &AdaptOptions) -> Result<Adapted<D, K>, Error>,
    what: &str,
) -> Result<SimplexMesh<D, K>, Error> {
    let target = Target::Complexity { complexity, p: 2.0 };
    for it in 1..=iterations {
        let clock = std::time::Instant::now();
        let u: Vec<f64> = mesh.points.iter().map(field).collect();
        let h = hessians(&mesh.points, &mesh.elements, &u)?;
        let metric = metric_from_hessians(&mesh.points, &mesh.elements, &h, target, hmin, hmax)?;
        let out = adapt(
            &mesh,
            MetricField::AtVertices(metric),
            &AdaptOptions::default(),
        )?;
        print(it, &out.report.after, what, clock.elapsed().as_secs_f64());
        mesh = out.mesh;
    }
    Ok(mesh)
}

fn field(p: &[f64; 2]) -> f64 {
    let r = (p[0] + 0.1).hypot(p[1] + 0.1);
    (40.0 * (r - 0.6)).tanh()
}

/// The unit square as an `n × n` grid of cells split into two triangles.
fn square(n: usize) -> TriMesh {
    let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut m = TriMesh::default();
    for j in 0..=n {
        for i in 0..=n {
            m.points.push([i as f64 / n as f64, j as f64 / n as f64]);
        }
    }
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            m.elements.extend([[a, b, c], [a, c, d]]);
        }
    }
    m.corners = vec![id(0, 0), id(n, 0), id(n, n), id(0, n)];
    m
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "adapt_loop.png".into());
    if path == "3d" {
        // 3 iterations from a 6³-cube mesh of the unit cube.
        let cube: TetMesh = cube::cube(6, false);
        iterate(cube, field3, (400.0, 1e-3, 0.3), 3, adapt_tet, "tetrahedra")?;
        return Ok(());
    }
    let mesh = iterate(
        square(10),
        field,
        (600.0, 1e-4, 0.2),
        5,
        adapt_tri,
        "triangles",
    )?;
    let layers = [delone_io::SvgLayer::Triangles {
        points: &mesh.points,
        triangles: &mesh.elements,
        stroke: "#2a3f54",
        width: 0.6,
    }];
    let style = delone_io::SvgStyle {
        width: 420.0,
        ..Default::default()
    };
    let file = std::io::BufWriter::new(std::fs::File::create(&path)?);
    delone_io::write_png(file, [[0.0, 0.0], [1.0, 1.0]], &layers, &style)?;
    println!("wrote {path}");
    Ok(())
}
