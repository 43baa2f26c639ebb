//! One run of `delone tri` / `delone tet`: read, mesh, check, write, report.

use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use delone_io::topo::{self, Entities};
use delone_io::{DataArray, NodeFile, Values, VtuFormat};

use crate::args::{Mode, Opts};
use crate::fail::{input_err, usage_err, Failure};
use crate::paths::{names, with_ext};
use crate::progress::Progress;

/// Timings and counts for the summary.
struct Report {
    lines: Vec<String>,
}

impl Report {
    fn push(&mut self, s: impl Into<String>) {
        self.lines.push(s.into());
    }
}

fn secs(d: Duration) -> String {
    format!("{:.3} s", d.as_secs_f64())
}

/// Writes one output file through `f`, adding its name to `written`.
fn write_file(
    path: &Path,
    written: &mut Vec<PathBuf>,
    f: impl FnOnce(File) -> Result<(), delone_io::IoError>,
) -> Result<(), Failure> {
    let file = crate::guard::create(path)?;
    f(file).map_err(|e| input_err(format!("cannot write {}: {e}", path.display())))?;
    written.push(path.to_path_buf());
    Ok(())
}

/// Frees a large buffer on a thread of its own (returning its pages to the
/// system takes a while), here when that thread cannot start.
fn drop_aside<T: Send + 'static>(buffer: T) {
    // A failed spawn drops the closure, and the buffer with it, here.
    let _ = std::thread::Builder::new().spawn(move || drop(buffer));
}

/// The parts of a mesh the writers need, whatever the dimension.
struct MeshOut<const K: usize> {
    cells: Vec<[u32; K]>,
    neighbors: Vec<[u32; K]>,
    vertex_map: Vec<u32>,
    duplicates: Vec<(u32, u32)>,
}

/// Output markers: the input marker when nonzero, else 1 on the hull, 0
/// inside; a duplicate point takes the marker of the point it duplicates.
fn node_markers(node: &NodeFile, hull: &[bool], vertex_map: &[u32]) -> Vec<i32> {
    let n = node.len();
    let own: Vec<i32> = (0..n)
        .map(|i| {
            let m = node.markers.as_ref().map_or(0, |m| m[i]);
            if m != 0 {
                m
            } else {
                i32::from(hull.get(i).copied().unwrap_or(false))
            }
        })
        .collect();
    (0..n)
        .map(|i| {
            let rep = vertex_map.get(i).map_or(i, |&r| r as usize);
            if rep != i && node.markers.as_ref().map_or(0, |m| m[i]) == 0 {
                own.get(rep).copied().unwrap_or(own[i])
            } else {
                own[i]
            }
        })
        .collect()
}

fn mesh_error(path: &Path, node: &NodeFile, e: delone::Error) -> Failure {
    let p = path.display();
    let f = node.first_index as usize;
    input_err(match e {
        delone::Error::InvalidCoordinate { index } => {
            let line = node.lines.get(index).copied().unwrap_or(0);
            format!(
                "{p}: line {line}: point {} has a NaN or infinite coordinate",
                index + f
            )
        }
        other => format!(
            "{p}: {}",
            crate::numbering::renumber(other, node.first_index)
        ),
    })
}

/// Runs one subcommand. Returns the exit code on success (0, or 1 when
/// `-C` found a violation).
pub fn run(mode: Mode, o: &Opts) -> Result<i32, Failure> {
    if o.pslg() && (o.voronoi() || o.weights() || o.lloyd.is_some()) {
        return Err(usage_err(
            "-v, -w and --lloyd are not supported with -p yet",
        ));
    }
    if mode == Mode::Tet && o.tet.detect {
        return crate::tetd::run(o);
    }
    if mode == Mode::Tet && o.pslg() {
        return crate::plc::run(o);
    }
    if mode == Mode::Tri && o.pslg() {
        return crate::pslg::run(o);
    }
    if mode == Mode::Tet && o.refine_mesh() {
        return crate::tetr::run(o);
    }
    if mode == Mode::Tri && o.refine_mesh() {
        return crate::remesh::run(o);
    }
    if (o.convex_hull() && mode == Mode::Tet) || o.region_attributes() {
        return Err(usage_err("switches -c and -A need -p (PSLG input)"));
    }
    if o.tri.jettison && (o.voronoi() || o.weights()) {
        return Err(usage_err("-j with -v or -w is not supported"));
    }
    if o.tet.medit || o.medit.is_some() || o.gmsh.is_some() {
        return Err(usage_err("-g, --medit and --gmsh need -p (PLC input)"));
    }
    let t_all = Instant::now();
    let names = names(&o.input, o.out().no_iteration, o.output_dir.as_deref())?;
    let dim = match mode {
        Mode::Tri => 2,
        Mode::Tet => 3,
    };

    // Output file list, checked for collisions with the input before any work.
    let ob = &names.out_base;
    let mut planned: Vec<(&'static str, PathBuf)> = Vec::new();
    if !o.out().no_node {
        planned.push(("node", with_ext(ob, "node")));
    }
    if !o.out().no_ele {
        planned.push(("ele", with_ext(ob, "ele")));
    }
    if mode == Mode::Tet && !o.tet.no_face {
        planned.push(("face", with_ext(ob, "face")));
    }
    if o.out().edges && !(mode == Mode::Tet && o.tet.no_face) {
        planned.push(("edge", with_ext(ob, "edge")));
    }
    if o.out().neigh {
        planned.push(("neigh", with_ext(ob, "neigh")));
    }
    if mode == Mode::Tet && o.tet.vtk_legacy {
        planned.push(("vtk", with_ext(ob, "vtk")));
    }
    let vtu_path = match (&o.vtu, o.vtu_ascii) {
        (Some(p), _) => Some(p.clone()),
        (None, true) => Some(with_ext(ob, "vtu")),
        (None, false) => None,
    };
    if let Some(p) = &vtu_path {
        planned.push(("vtu", p.clone()));
    }
    crate::guard::plan(mode, crate::guard::Kind::Points, o, ob);
    crate::guard::note_input(&names.node);
    crate::guard::check()?;

    // Read.
    let t0 = Instant::now();
    let threads = crate::threads::effective(o.threads.or(o.tri.threads));
    let bytes = crate::guard::read_threads(&names.node, threads)
        .map_err(|e| input_err(format!("cannot read {}: {e}", names.node.display())))?;
    let mut node = delone_io::read_node_threads(&bytes, threads)
        .map_err(|e| input_err(format!("{}: {e}", names.node.display())))?;
    drop_aside(bytes);
    if node.dim != dim {
        return Err(input_err(format!(
            "{}: line {}: the header gives dimension {}, delone {} needs {dim}D points{}",
            names.node.display(),
            node.header_line,
            node.dim,
            mode.name(),
            if node.dim == 3 {
                " (use delone tet)"
            } else {
                " (use delone tri)"
            }
        )));
    }
    let t_read = t0.elapsed();
    if let Some(dir) = &o.output_dir {
        std::fs::create_dir_all(dir)
            .map_err(|e| input_err(format!("cannot create directory {}: {e}", dir.display())))?;
    }
    let first = if o.out().zero { 0 } else { node.first_index };
    let quiet = o.out().quiet;
    let mut rep = Report { lines: Vec::new() };
    rep.push(format!(
        "delone {}: {} ({} point{}{})",
        mode.name(),
        names.node.display(),
        node.len(),
        if node.len() == 1 { "" } else { "s" },
        if node.n_attributes > 0 {
            format!(", {} attribute(s) each", node.n_attributes)
        } else {
            String::new()
        }
    ));
    if o.out().verbose > 0 && o.tri.fortune {
        rep.push(
            "  -F: Fortune's sweepline is not used; delone inserts points incrementally \
             (Bowyer-Watson, BRIO + Hilbert order, exact predicates)",
        );
    }

    match mode {
        Mode::Tri => {
            let mut pts = node.points::<2>().unwrap_or_default();
            if let Some(k) = o.lloyd {
                pts = crate::dual::lloyd(&pts, k).map_err(|e| mesh_error(&names.node, &node, e))?;
                rep.push(format!(
                    "  --lloyd: {k} Lloyd iteration(s) in the bounding box"
                ));
            }
            let weights = read_weights_if(o.weights(), &names.node, &node, &mut rep)?;
            let t1 = Instant::now();
            let res = match &weights {
                Some(w) => delone::tri::Delaunay2::from_weighted_points(&pts, w),
                None => {
                    let mut prog = Progress::new(!quiet, "triangulating");
                    let r = delone::tri::Delaunay2::from_points_with_progress(&pts, &mut |d, t| {
                        prog.update(d, t)
                    });
                    prog.finish();
                    r
                }
            };
            let mesh = res
                .map_err(|e| mesh_error(&names.node, &node, e))?
                .into_mesh();
            let t_mesh = t1.elapsed();
            let check = timed_check(o.out().check, || match &weights {
                Some(w) => delone::tri::validate_regular(&pts, w, &mesh),
                None => delone::tri::validate(&pts, &mesh),
            });
            let t_extra = Instant::now();
            let mut extra = Vec::new();
            if let Some(l) = crate::dual::hidden_line(&mesh.hidden, first) {
                rep.push(l);
            }
            let vor = o
                .voronoi()
                .then(|| crate::dual::voronoi2(&pts, weights.as_deref(), &mesh))
                .transpose()?;
            if let Some(v) = &vor {
                crate::dual::write_tri_voronoi(ob, &pts, v, first, &mut extra)?;
            }
            if o.svg.is_some() || o.png.is_some() {
                crate::dual::write_picture(o, &pts, &mesh, vor.as_ref(), &mut extra)?;
            }
            let stats = crate::tri_out::stats_if(o, &pts, &mesh.triangles, None, &mut extra)?;
            for l in stats
                .iter()
                .flat_map(|st| st.to_string().lines().map(String::from).collect::<Vec<_>>())
            {
                rep.push(format!("  {l}"));
            }
            drop(vor);
            let t_extra = t_extra.elapsed();
            let mut m = MeshOut {
                cells: mesh.triangles,
                neighbors: mesh.neighbors,
                vertex_map: mesh.vertex_map,
                duplicates: mesh.duplicates,
            };
            let t_derive = Instant::now();
            let mut edges = topo::tri_edges(&m.cells, &m.neighbors)
                .map_err(|e| input_err(format!("internal error: {e}")))?;
            let hull = topo::boundary_vertices(&edges, node.len());
            // -j: the .node keeps only the vertices of the triangles.
            let jet = o.tri.jettison.then(|| {
                let r = crate::jettison::Renumber::new(node.len(), &m.cells, node.len());
                r.apply(&mut m.cells);
                r.apply(&mut edges.items);
                m.vertex_map = (0..r.kept.len() as u32).collect();
                rep.push(format!(
                    "  -j: {} unused vertices left out of the .node",
                    r.dropped()
                ));
                (
                    crate::jettison::node_file(&node, &r),
                    r.rows(&pts, 1),
                    r.rows(&hull, 1),
                )
            });
            let (node_w, pts_w, hull_w) = match &jet {
                Some((n, p, h)) => (n, &p[..], &h[..]),
                None => (&node, &pts[..], &hull[..]),
            };
            if o.convex_hull() && !o.tri.no_poly {
                crate::jettison::write_hull_poly(
                    ob,
                    &edges.items,
                    &edges.boundary,
                    !o.out().no_bound,
                    first,
                    &mut extra,
                )?;
            }
            let t_derive = t_derive.elapsed();
            let t_o2 = Instant::now();
            let planned: Vec<_> = if o.tri.second_order {
                let markers = node_markers(node_w, hull_w, &m.vertex_map);
                crate::tri_out::write_plain_second_order(
                    o,
                    &planned,
                    &crate::tri_out::Plain {
                        node: node_w,
                        points: pts_w,
                        triangles: &m.cells,
                        neighbors: &m.neighbors,
                        markers: &markers,
                        first,
                    },
                    &mut extra,
                )?;
                planned
                    .into_iter()
                    .filter(|(k, _)| !matches!(*k, "node" | "ele" | "vtu"))
                    .collect()
            } else {
                planned
            };
            let t_o2 = t_o2.elapsed();
            let (written, t_write) = write_outputs(
                mode,
                o,
                node_w,
                pts_w,
                &m,
                &planned,
                first,
                hull_w,
                Some(&edges),
                None,
            )?;
            let mut written = written;
            written.extend(extra);
            let t_write = t_write + t_derive + t_extra + t_o2;
            summarize(
                mode, o, &node, &m, &edges, check, &mut rep, t_read, t_mesh, t_write, &written,
                t_all,
            )
        }
        Mode::Tet => {
            let mut pts = node.points_threads::<3>(threads).unwrap_or_default();
            // The coordinates live on in `pts` (one copy of them, not two;
            // lent to the Delaunay construction while it runs).
            drop_aside(std::mem::take(&mut node.coords));
            let weights = read_weights_if(o.weights(), &names.node, &node, &mut rep)?;
            let t1 = Instant::now();
            let mut prog = Progress::new(!quiet, "tetrahedralizing");
            let mut tick = |d, t| prog.update(d, t);
            let res = match &weights {
                Some(w) => {
                    delone::tet::Delaunay3::from_weighted_points_with_progress(&pts, w, &mut tick)
                }
                None => delone::tet::Delaunay3::from_points_in_place(&mut pts, threads, &mut tick),
            };
            prog.finish();
            let mesh = res
                .map_err(|e| mesh_error(&names.node, &node, e))?
                .into_mesh();
            let t_mesh = t1.elapsed();
            let check = timed_check(o.out().check, || match &weights {
                Some(w) => delone::tet::validate_regular(&pts, w, &mesh),
                None => delone::tet::validate(&pts, &mesh),
            });
            let t_extra = Instant::now();
            let mut extra = Vec::new();
            if let Some(l) = crate::dual::hidden_line(&mesh.hidden, first) {
                rep.push(l);
            }
            let vor = (o.voronoi() || o.cells_vtu.is_some())
                .then(|| crate::dual::voronoi3(&pts, weights.as_deref(), &mesh))
                .transpose()?;
            if let (Some(path), Some(v)) = (&o.cells_vtu, &vor) {
                crate::dual::write_tet_cells_vtu(path, &pts, v, first, &mut extra)?;
            }
            if let Some(v) = vor.as_ref().filter(|_| o.voronoi()) {
                crate::dual::write_tet_voronoi(ob, v, first, &mut extra)?;
            }
            if let Some(p) = &o.png {
                crate::cutaway::write_png(o, p, &pts, &mesh.tets, &mut extra)?;
            }
            drop(vor);
            let t_extra = t_extra.elapsed();
            let m = MeshOut {
                cells: mesh.tets,
                neighbors: mesh.neighbors,
                vertex_map: mesh.vertex_map,
                duplicates: mesh.duplicates,
            };
            let t_derive = Instant::now();
            let faces = topo::tet_faces_threads(&m.cells, &m.neighbors, o.tet.all_faces, threads)
                .map_err(|e| input_err(format!("internal error: {e}")))?;
            let hull = topo::boundary_vertices(&faces, node.len());
            let edges = if o.out().edges && !o.tet.no_face {
                Some(
                    topo::tet_edges(&m.cells, &m.neighbors)
                        .map_err(|e| input_err(format!("internal error: {e}")))?,
                )
            } else {
                None
            };
            let t_derive = t_derive.elapsed();
            let mut m = m;
            if !o.out().neigh {
                // Only `.neigh` still needs them: a smaller peak while writing.
                m.neighbors = Vec::new();
            }
            let (written, t_write) = write_outputs(
                mode,
                o,
                &node,
                &pts,
                &m,
                &planned,
                first,
                &hull,
                edges.as_ref(),
                Some(&faces),
            )?;
            let mut written = written;
            written.extend(extra);
            let t_write = t_write + t_derive + t_extra;
            summarize(
                mode, o, &node, &m, &faces, check, &mut rep, t_read, t_mesh, t_write, &written,
                t_all,
            )
        }
    }
}

#[allow(clippy::too_many_arguments)]
fn write_outputs<const D: usize, const K: usize>(
    mode: Mode,
    o: &Opts,
    node: &NodeFile,
    pts: &[[f64; D]],
    m: &MeshOut<K>,
    planned: &[(&'static str, PathBuf)],
    first: u32,
    hull: &[bool],
    edges: Option<&Entities<2>>,
    faces: Option<&Entities<3>>,
) -> Result<(Vec<PathBuf>, Duration), Failure> {
    let t = Instant::now();
    let threads = crate::threads::effective(o.threads.or(o.tri.threads));
    let markers = node_markers(node, hull, &m.vertex_map);
    let bound = !o.out().no_bound;
    let mut written = Vec::new();
    let attr_cols: Vec<Vec<f64>> = (0..node.n_attributes)
        .map(|k| {
            node.attributes
                .iter()
                .skip(k)
                .step_by(node.n_attributes)
                .copied()
                .collect()
        })
        .collect();
    let attr_names: Vec<String> = (0..node.n_attributes)
        .map(|k| format!("attribute_{}", k + 1))
        .collect();
    let point_data = || {
        let mut pd = Vec::new();
        if bound {
            pd.push(DataArray {
                name: "marker",
                values: Values::Int32(&markers),
            });
        }
        for (name, col) in attr_names.iter().zip(&attr_cols) {
            pd.push(DataArray {
                name,
                values: Values::Float64(col),
            });
        }
        pd
    };
    for (kind, path) in planned {
        match *kind {
            "node" => write_file(path, &mut written, |f| {
                delone_io::write_node_threads(
                    f,
                    pts,
                    &node.attributes,
                    node.n_attributes,
                    bound.then_some(&markers[..]),
                    first,
                    threads,
                )
            })?,
            "ele" => write_file(path, &mut written, |f| {
                delone_io::write_ele_threads(f, &m.cells, &[], 0, first, threads)
            })?,
            "neigh" => write_file(path, &mut written, |f| {
                delone_io::write_neigh(f, &m.neighbors, first)
            })?,
            "edge" => {
                if let Some(e) = edges {
                    let mk = e.markers();
                    write_file(path, &mut written, |f| {
                        delone_io::write_edge(f, &e.items, bound.then_some(&mk[..]), first)
                    })?
                }
            }
            "face" => {
                if let Some(fc) = faces {
                    let mk = fc.markers();
                    write_file(path, &mut written, |f| {
                        delone_io::write_face(f, &fc.items, bound.then_some(&mk[..]), first)
                    })?
                }
            }
            "vtk" => write_file(path, &mut written, |f| {
                delone_io::write_vtk_legacy(
                    f,
                    pts,
                    &m.cells,
                    &point_data(),
                    &[],
                    &format!("delone {} output", mode.name()),
                )
            })?,
            "vtu" => write_file(path, &mut written, |f| {
                delone_io::write_vtu(
                    f,
                    pts,
                    &m.cells,
                    &point_data(),
                    &[],
                    if o.vtu_ascii {
                        VtuFormat::Ascii
                    } else {
                        VtuFormat::Binary
                    },
                )
            })?,
            _ => {}
        }
    }
    Ok((written, t.elapsed()))
}

#[allow(clippy::too_many_arguments)]
fn summarize<const K: usize, const B: usize>(
    mode: Mode,
    o: &Opts,
    node: &NodeFile,
    m: &MeshOut<K>,
    boundary: &Entities<B>,
    check: Option<(Result<(), String>, Duration)>,
    rep: &mut Report,
    t_read: Duration,
    t_mesh: Duration,
    t_write: Duration,
    written: &[PathBuf],
    t_all: Instant,
) -> Result<i32, Failure> {
    let f = if o.out().zero { 0 } else { node.first_index } as usize;
    let fin = node.first_index as usize;
    let (elem, side) = match mode {
        Mode::Tri => ("triangles", "hull edges"),
        Mode::Tet => ("tetrahedra", "hull faces"),
    };
    rep.push(format!(
        "  duplicates: {}   {elem}: {}",
        m.duplicates.len(),
        m.cells.len()
    ));
    if o.out().verbose > 0 {
        let nhull = boundary.boundary.iter().filter(|&&b| b).count();
        rep.push(format!("  {side}: {nhull}"));
        let show = if o.out().verbose > 1 { usize::MAX } else { 20 };
        for &(d, orig) in m.duplicates.iter().take(show) {
            rep.push(format!(
                "  point {} (line {}) duplicates point {}",
                d as usize + fin,
                node.lines.get(d as usize).copied().unwrap_or(0),
                orig as usize + fin
            ));
        }
        if m.duplicates.len() > show {
            rep.push(format!(
                "  ... {} more duplicates (-VV lists all)",
                m.duplicates.len() - show
            ));
        }
        if f != fin {
            rep.push("  output numbered from 0 (-z)".to_string());
        }
    }
    let mut code = 0;
    let mut check_time = Duration::ZERO;
    if let Some((r, t)) = &check {
        check_time = *t;
        match r {
            Ok(()) => rep.push("  check (-C): the mesh passed delone's validator"),
            Err(v) => {
                eprintln!("delone: error: check (-C) failed: {v}");
                code = 1;
            }
        }
    }
    rep.push(format!(
        "  time: read {}, {} {}, {}write {}, total {}",
        secs(t_read),
        match mode {
            Mode::Tri => "triangulate",
            Mode::Tet => "tetrahedralize",
        },
        secs(t_mesh),
        if check.is_some() {
            format!("check {}, ", secs(check_time))
        } else {
            String::new()
        },
        secs(t_write),
        secs(t_all.elapsed())
    ));
    if !written.is_empty() {
        let list: Vec<String> = written.iter().map(|p| p.display().to_string()).collect();
        rep.push(format!("  wrote {}", list.join(", ")));
    }
    if !o.out().quiet {
        let mut out = std::io::stdout().lock();
        for l in &rep.lines {
            let _ = writeln!(out, "{l}");
        }
    }
    Ok(code)
}

/// The weights for `-w` (FILE.weight or the first node attribute), noting the
/// source in the report; `None` without `-w`.
fn read_weights_if(
    wanted: bool,
    node_path: &Path,
    node: &NodeFile,
    rep: &mut Report,
) -> Result<Option<Vec<f64>>, Failure> {
    if !wanted {
        return Ok(None);
    }
    let (w, source) = crate::dual::read_weights(node_path, node)?;
    rep.push(format!("  -w: weights from {source}"));
    Ok(Some(w))
}

/// Runs the validator for `-C` and times it; `None` without `-C`.
fn timed_check(
    enabled: bool,
    check: impl FnOnce() -> Result<(), delone::Violation>,
) -> Option<(Result<(), String>, Duration)> {
    enabled.then(|| {
        let t = Instant::now();
        let r = check().map_err(|v| v.to_string());
        (r, t.elapsed())
    })
}
