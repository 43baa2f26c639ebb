//! Weights (`-w`), Lloyd relaxation (`--lloyd N`), Voronoi / power diagram
//! output (`-v`) and the SVG picture (`--svg FILE`) of `delone tri`, and
//! `delone tet -v`.
//!
//! Weights (`-w`, as Detri2 and TetGen read them): from `FILE.weight` when it
//! exists next to `FILE.node`, else from the first attribute column of the
//! `.node` file. A `.weight` file has a header line whose first number is the
//! number of points, then one line per point: `<index> <weight>` (indices
//! counted from the `.node` file's first index, any order, each once) or
//! just `<weight>` (in point order). `#` starts a comment.

use std::fs::File;
use std::path::{Path, PathBuf};

use delone::tet::Voronoi3;
use delone::tri::{TriMesh, Voronoi2};
use delone_io::{NodeFile, SvgLayer};

use crate::fail::{input_err as fail, Failure};
use crate::paths::with_ext;

/// A mesh that does not fit its own points: a bug in delone, reported as
/// an error rather than a crash.
fn internal(e: delone::Error) -> Failure {
    fail(format!("internal error: {e}"))
}

/// Parses a `.weight` file for `n` points whose indices start at `first`.
pub fn parse_weights(text: &str, n: usize, first: u32, name: &str) -> Result<Vec<f64>, Failure> {
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(k, l)| (k + 1, l.split('#').next().unwrap_or("").trim()))
        .filter(|(_, l)| !l.is_empty());
    let Some((hl, header)) = lines.next() else {
        return Err(fail(format!("{name}: empty weight file")));
    };
    let count: usize = header
        .split_whitespace()
        .next()
        .and_then(|c| c.parse().ok())
        .ok_or_else(|| fail(format!("{name}: line {hl}: expected the number of points")))?;
    if count != n {
        return Err(fail(format!(
            "{name}: line {hl}: {count} weights for {n} points"
        )));
    }
    let mut w = vec![f64::NAN; n];
    let mut seen = vec![false; n];
    let mut k = 0usize;
    for (ln, l) in lines {
        let fields: Vec<&str> = l.split_whitespace().collect();
        let (index, value) = match fields.as_slice() {
            [v] => (k, *v),
            [i, v, ..] => {
                let i: u64 = i
                    .parse()
                    .map_err(|_| fail(format!("{name}: line {ln}: bad point index {i:?}")))?;
                let i = i
                    .checked_sub(u64::from(first))
                    .filter(|&i| (i as usize) < n)
                    .ok_or_else(|| fail(format!("{name}: line {ln}: no point {i}")))?;
                (i as usize, *v)
            }
            [] => continue,
        };
        if index >= n {
            return Err(fail(format!("{name}: line {ln}: more than {n} weights")));
        }
        if seen[index] {
            return Err(fail(format!(
                "{name}: line {ln}: a second weight for point {}",
                index as u64 + u64::from(first)
            )));
        }
        let x: f64 = value
            .parse()
            .map_err(|_| fail(format!("{name}: line {ln}: bad weight {value:?}")))?;
        if !x.is_finite() {
            return Err(fail(format!(
                "{name}: line {ln}: the weight of point {} is not finite",
                index as u64 + u64::from(first)
            )));
        }
        w[index] = x;
        seen[index] = true;
        k += 1;
    }
    if let Some(miss) = seen.iter().position(|&s| !s) {
        return Err(fail(format!(
            "{name}: no weight for point {}",
            miss as u64 + u64::from(first)
        )));
    }
    Ok(w)
}

/// The weights for `-w`: `FILE.weight` next to the `.node` file, else the
/// first node attribute.
pub fn read_weights(node_path: &Path, node: &NodeFile) -> Result<(Vec<f64>, String), Failure> {
    let s = node_path.to_string_lossy();
    let base = s.strip_suffix(".node").unwrap_or(&s);
    let wpath = PathBuf::from(format!("{base}.weight"));
    if wpath.exists() {
        let text = crate::guard::read_to_string(&wpath)
            .map_err(|e| fail(format!("cannot read {}: {e}", wpath.display())))?;
        let name = wpath.display().to_string();
        let w = parse_weights(&text, node.len(), node.first_index, &name)?;
        return Ok((w, name));
    }
    if node.n_attributes == 0 {
        return Err(fail(format!(
            "-w needs weights: no {} and {} has no attribute column",
            wpath.display(),
            node_path.display()
        )));
    }
    let w = node
        .attributes
        .iter()
        .step_by(node.n_attributes)
        .copied()
        .collect();
    Ok((w, format!("attribute 1 of {}", node_path.display())))
}

/// `--lloyd N`: the points after `N` Lloyd iterations in their bounding box.
pub fn lloyd(pts: &[[f64; 2]], iterations: usize) -> Result<Vec<[f64; 2]>, delone::Error> {
    delone::tri::lloyd(pts, crate::tri_out::bbox(pts), iterations)
}

/// The Voronoi (or, with weights, power) diagram of a 2D mesh.
pub fn voronoi2(
    pts: &[[f64; 2]],
    weights: Option<&[f64]>,
    mesh: &TriMesh,
) -> Result<Voronoi2, Failure> {
    match weights {
        Some(w) => Voronoi2::new_power(pts, w, mesh).map_err(internal),
        None => Voronoi2::new(pts, mesh).map_err(internal),
    }
}

fn write(
    path: &Path,
    written: &mut Vec<PathBuf>,
    f: impl FnOnce(File) -> Result<(), delone_io::IoError>,
) -> Result<(), Failure> {
    let file = crate::guard::create(path)?;
    f(file).map_err(|e| fail(format!("cannot write {}: {e}", path.display())))?;
    written.push(path.to_path_buf());
    Ok(())
}

/// `-v` in 2D: `<out>.v.node` and `<out>.v.edge` (Triangle's layout).
pub fn write_tri_voronoi(
    out_base: &Path,
    pts: &[[f64; 2]],
    v: &Voronoi2,
    first: u32,
    written: &mut Vec<PathBuf>,
) -> Result<(), Failure> {
    write(&with_ext(out_base, "v.node"), written, |f| {
        delone_io::write_voronoi_node(f, &v.vertices, first)
    })?;
    let ends: Vec<[u32; 2]> = v.edges.iter().map(|e| e.vertices).collect();
    let dirs: Vec<[f64; 2]> = v.edges.iter().map(|e| e.direction(pts)).collect();
    write(&with_ext(out_base, "v.edge"), written, |f| {
        delone_io::write_voronoi_edge(f, &ends, &dirs, v.vertices.len(), first)
    })
}

/// The Voronoi diagram (power diagram with weights) of a tetrahedralization.
pub fn voronoi3(
    pts: &[[f64; 3]],
    weights: Option<&[f64]>,
    mesh: &delone::TetMesh,
) -> Result<Voronoi3, Failure> {
    match weights {
        Some(w) => Voronoi3::new_power(pts, w, mesh).map_err(internal),
        None => Voronoi3::new(pts, mesh).map_err(internal),
    }
}

/// `--cells-vtu`: the cells clipped to the points' bounding box, as VTK
/// polyhedra with the (output-numbered) site as cell data.
pub fn write_tet_cells_vtu(
    path: &Path,
    pts: &[[f64; 3]],
    v: &Voronoi3,
    first: u32,
    written: &mut Vec<PathBuf>,
) -> Result<(), Failure> {
    let mut bbox = [[f64::INFINITY; 3], [f64::NEG_INFINITY; 3]];
    for p in pts {
        for k in 0..3 {
            bbox[0][k] = bbox[0][k].min(p[k]);
            bbox[1][k] = bbox[1][k].max(p[k]);
        }
    }
    let cells = v.cells_clipped(pts, bbox);
    let polys: Vec<delone_io::PolyhedronRef<'_>> = cells
        .cells
        .iter()
        .map(|c| (&c.vertices[..], &c.faces[..]))
        .collect();
    let sites: Vec<i32> = cells
        .cells
        .iter()
        .enumerate()
        .filter(|(_, c)| !c.faces.is_empty())
        .map(|(i, _)| i as i32 + first as i32)
        .collect();
    let site = [delone_io::DataArray {
        name: "site",
        values: delone_io::Values::Int32(&sites),
    }];
    write(path, written, |f| {
        delone_io::write_vtu_polyhedra(f, &polys, &site, delone_io::VtuFormat::Binary)
    })
}

/// `-v` in 3D: `<out>.v.node`, `.v.edge`, `.v.face`, `.v.cell` (TetGen's
/// layout) of the diagram `v`.
pub fn write_tet_voronoi(
    out_base: &Path,
    v: &Voronoi3,
    first: u32,
    written: &mut Vec<PathBuf>,
) -> Result<(), Failure> {
    write(&with_ext(out_base, "v.node"), written, |f| {
        delone_io::write_voronoi_node(f, &v.vertices, first)
    })?;
    let ends: Vec<[u32; 2]> = v.edges.iter().map(|e| e.vertices).collect();
    let mut dirs = vec![[0.0; 3]; v.edges.len()];
    for (&e, d) in v.ray_edges.iter().zip(&v.ray_directions) {
        // TetGen writes unit directions.
        let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        dirs[e as usize] = if len > 0.0 { d.map(|x| x / len) } else { *d };
    }
    write(&with_ext(out_base, "v.edge"), written, |f| {
        delone_io::write_voronoi_edge(f, &ends, &dirs, v.vertices.len(), first)
    })?;
    let cells: Vec<[u32; 2]> = v.faces.iter().map(|f| f.sites).collect();
    // TetGen ends an unbounded face's edges and an unbounded cell's faces
    // with -1 (u32::MAX for the writer).
    let cap = v.face_vertices.len() + 2 * v.open_faces.len();
    let (mut offsets, mut ids) = (vec![0u32], Vec::with_capacity(cap));
    let mut open = v.open_faces.iter().peekable();
    for fi in 0..v.faces.len() {
        ids.extend(v.face(fi).edges);
        if open.next_if(|&&o| o as usize == fi).is_some() {
            ids.push(u32::MAX);
        }
        offsets.push(ids.len() as u32);
    }
    write(&with_ext(out_base, "v.face"), written, |f| {
        delone_io::write_voronoi_face(f, &cells, &offsets, &ids, v.edges.len(), first)
    })?;
    let (mut offsets, mut ids) = (vec![0u32], Vec::with_capacity(v.cell_face_ids.len()));
    for p in 0..v.cell_offsets.len().saturating_sub(1) {
        let fs = &v.cell_face_ids[v.cell_offsets[p] as usize..v.cell_offsets[p + 1] as usize];
        ids.extend_from_slice(fs);
        if !fs.is_empty() && v.unbounded[p] {
            ids.push(u32::MAX);
        }
        offsets.push(ids.len() as u32);
    }
    write(&with_ext(out_base, "v.cell"), written, |f| {
        delone_io::write_voronoi_cell(f, &offsets, &ids, v.faces.len(), first)
    })
}

/// A pleasant pastel colour for cell `i` (deterministic).
pub fn pastel(i: usize) -> [u8; 3] {
    let h = (i as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 40;
    let c = |s: u32| 150 + ((h >> s) & 0x5f) as u8;
    [c(0), c(8), c(16)]
}

/// `--svg FILE` / `--png FILE`: the mesh, and with `-v` the cells clipped
/// to the points' bounding box (hidden points drawn as red dots); with
/// `--svg-quality` the triangles coloured by minimum angle.
pub fn write_picture(
    o: &crate::args::Opts,
    pts: &[[f64; 2]],
    mesh: &TriMesh,
    voronoi: Option<&Voronoi2>,
    written: &mut Vec<PathBuf>,
) -> Result<(), Failure> {
    let b = crate::tri_out::bbox(pts);
    let pad = 0.02 * (b[1][0] - b[0][0]).max(b[1][1] - b[0][1]);
    let view = [
        [b[0][0] - pad, b[0][1] - pad],
        [b[1][0] + pad, b[1][1] + pad],
    ];
    let cells = voronoi.map(|v| v.cells_clipped(pts, b));
    let fills: Vec<[u8; 3]> = (0..pts.len()).map(pastel).collect();
    let visible: Vec<[f64; 2]> = (0..pts.len())
        .filter(|&i| mesh.vertex_map[i] == i as u32)
        .map(|i| pts[i])
        .collect();
    let hidden: Vec<[f64; 2]> = mesh.hidden.iter().map(|&h| pts[h as usize]).collect();
    let n = pts.len().max(1) as f64;
    let radius = (300.0 / n.sqrt()).clamp(0.5, 3.0);
    let quality: Vec<[u8; 3]> = if o.svg_quality {
        mesh.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| pts[v as usize]);
                crate::tri_out::quality_colour(
                    delone::tri::quality::TriangleQuality::new(a, b, c).min_angle,
                )
            })
            .collect()
    } else {
        Vec::new()
    };
    let legend: Vec<([u8; 3], &str)> = crate::tri_out::QUALITY_CLASSES
        .iter()
        .map(|c| (c.1, c.2))
        .collect();
    let mut layers = Vec::new();
    if let Some(c) = &cells {
        layers.push(SvgLayer::Polygons {
            points: &c.polygon_points,
            offsets: &c.offsets,
            fills: &fills,
            stroke: "#555555",
            width: 0.6,
        });
    }
    if o.svg_quality {
        layers.push(SvgLayer::FilledTriangles {
            points: pts,
            triangles: &mesh.triangles,
            fills: &quality,
        });
    }
    layers.push(SvgLayer::Triangles {
        points: pts,
        triangles: &mesh.triangles,
        stroke: if cells.is_some() { "#3366aa" } else { "black" },
        width: if cells.is_some() { 0.4 } else { 0.6 },
    });
    layers.push(SvgLayer::Points {
        points: &visible,
        radius,
        fill: "black",
    });
    layers.push(SvgLayer::Points {
        points: &hidden,
        radius,
        fill: "red",
    });
    if o.svg_quality {
        layers.push(SvgLayer::Legend { entries: &legend });
    }
    let view = if o.svg_quality {
        crate::tri_out::legend_room(view, o)
    } else {
        view
    };
    crate::tri_out::emit(o, view, &layers, written)
}

/// The report line for hidden points (empty when there are none).
pub fn hidden_line(hidden: &[u32], first: u32) -> Option<String> {
    if hidden.is_empty() {
        return None;
    }
    let show: Vec<String> = hidden
        .iter()
        .take(10)
        .map(|&h| (u64::from(h) + u64::from(first)).to_string())
        .collect();
    Some(format!(
        "  hidden points (empty power cells): {}{}{}",
        hidden.len(),
        if show.is_empty() { "" } else { ": " },
        show.join(" ") + if hidden.len() > 10 { " ..." } else { "" }
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weight_files() {
        assert_eq!(
            parse_weights("3 1\n1 0.5\n3 -2\n2 1e-3 # c\n", 3, 1, "w").unwrap(),
            vec![0.5, 1e-3, -2.0]
        );
        assert_eq!(
            parse_weights("# x\n2\n0.25\n4\n", 2, 0, "w").unwrap(),
            vec![0.25, 4.0]
        );
        for (text, msg) in [
            ("3\n1 0\n2 0\n", "3 weights for 2 points"),
            ("2\n1 0\n1 0\n", "a second weight for point 1"),
            ("2\n1 0\n7 0\n", "no point 7"),
            ("2\n1 nan\n2 0\n", "not finite"),
            ("2\n1 0\n", "no weight for point 2"),
            ("2\n1 x\n2 0\n", "bad weight"),
            ("", "empty weight file"),
        ] {
            let e = parse_weights(text, 2, 1, "w").unwrap_err();
            assert!(e.message.contains(msg), "{text:?}: {}", e.message);
        }
    }
}
