//! # delone-py
//!
//! The native module `delone._delone` of the Python package `delone`
//! (built by maturin from the repository's `pyproject.toml`; the Python
//! side is in `python/delone`). Each function takes numpy arrays (float64
//! coordinates, int64 indices, checked here), runs the library on a worker
//! thread with the GIL released, and returns a dict of numpy arrays (float64
//! coordinates, int32 indices, `-1` for "none").
//!
//! While the worker runs, the calling thread waits for it in slices of
//! 50 ms, forwards the library's progress reports to the optional Python
//! callback and polls `check_signals`: a Ctrl-C (or an exception raised by
//! the callback) sets the worker's stop flag ([`delone::progress::stoppable`]),
//! waits for the library to end its stage early, and raises that exception.
//!
//! Errors: the library's typed errors become `delone.InvalidInput` (a
//! `ValueError`) when the input is at fault — the message names the point,
//! segment, facet or switch — and `delone.MeshingError` (a `RuntimeError`)
//! otherwise. A panic in the worker is caught and reported as a
//! `MeshingError`, never a crash of the interpreter.
//!
//! PyO3's macros expand to `unsafe` blocks, so this crate cannot
//! `#![forbid(unsafe_code)]` like the others; it denies `unsafe` in its own
//! code instead (see `Cargo.toml`).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{mpsc, Arc};
use std::time::Duration;

use delone::adapt::{AdaptOptions, AdaptReport, MetricField, MetricStats, SimplexMesh};
use delone::metric::{Metric, Target};
use delone::model::plc::{Facet, Plc, Region as Region3};
use delone::model::pslg::{Pslg, Region as Region2};
use delone::progress::{self, Report};
use delone::tet::recover::RecoverError;
use delone::tet::{TetError, TetOptions};
use delone::tri::constrain::Cdt;
use delone::tri::existing::ExistingMesh;
use delone::tri::pipeline::{edge_key, hull_edge_keys};
use delone::tri::refine::refine;
use delone::tri::{TriError, TriOptions, TriResult};
use delone::{Error, NONE};
use numpy::{
    PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods,
};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

pyo3::create_exception!(
    delone,
    InvalidInput,
    PyValueError,
    "The input is invalid; the message names the offending point, segment, facet or switch."
);
pyo3::create_exception!(
    delone,
    MeshingError,
    PyRuntimeError,
    "Meshing failed for a reason other than invalid input (a budget, an unrecoverable surface, ...)."
);

/// Stack of the worker thread: the library's deepest recursions fit with
/// a wide margin (only touched pages cost memory).
const STACK: usize = 256 << 20;

fn invalid(msg: impl Into<String>) -> PyErr {
    InvalidInput::new_err(msg.into())
}

/// Whether a library error blames the input (`InvalidInput`) or the run.
fn lib_err(e: &Error) -> PyErr {
    match e {
        Error::CapacityExceeded { .. } | Error::Interrupted => MeshingError::new_err(e.to_string()),
        _ => invalid(e.to_string()),
    }
}

fn tri_err(e: TriError) -> PyErr {
    match &e {
        TriError::Input(x) | TriError::Refine(x) => lib_err(x),
        _ => invalid(e.to_string()),
    }
}

fn tet_err(e: TetError) -> PyErr {
    match &e {
        TetError::Input(x) | TetError::Bound(x) | TetError::Recover(RecoverError::Input(x)) => {
            lib_err(x)
        }
        TetError::Recover(
            RecoverError::OpenSurface { .. }
            | RecoverError::SeedOnSurface { .. }
            | RecoverError::MarkerCount { .. }
            | RecoverError::PointOnTriangle { .. }
            | RecoverError::SegmentTooShort { .. },
        )
        | TetError::Empty { .. } => invalid(e.to_string()),
        _ => MeshingError::new_err(e.to_string()),
    }
}

enum Msg<T> {
    Report(Report),
    Done(T),
}

/// Runs `work` on a worker thread with the GIL released (see the crate docs
/// for progress and interruption).
fn run<T: Send + 'static>(
    py: Python<'_>,
    progress: Option<&Bound<'_, PyAny>>,
    work: impl FnOnce() -> T + Send,
) -> PyResult<T> {
    let stop = Arc::new(AtomicBool::new(false));
    let (tx, rx) = mpsc::channel::<Msg<T>>();
    let observed = progress.is_some();
    std::thread::scope(|s| {
        let flag = stop.clone();
        let handle = std::thread::Builder::new()
            .name("delone".into())
            .stack_size(STACK)
            .spawn_scoped(s, move || {
                let reports = tx.clone();
                let out = progress::stoppable(flag, || {
                    if observed {
                        let sink = move |r: &Report| {
                            let _ = reports.send(Msg::Report(*r));
                        };
                        progress::observe(sink, work)
                    } else {
                        work()
                    }
                });
                let _ = tx.send(Msg::Done(out));
            })
            .map_err(|e| MeshingError::new_err(format!("cannot start a thread: {e}")))?;
        let mut raised: Option<PyErr> = None;
        let mut rx = rx;
        let out = loop {
            let (msg, back) = py.detach(move || (rx.recv_timeout(Duration::from_millis(50)), rx));
            rx = back;
            match msg {
                Ok(Msg::Done(out)) => break Some(out),
                Ok(Msg::Report(r)) => {
                    if let (None, Some(cb)) = (&raised, progress) {
                        if let Err(e) = cb.call1((r.stage, r.done, r.total, r.unit)) {
                            stop.store(true, Ordering::Relaxed);
                            raised = Some(e);
                        }
                    }
                }
                Err(mpsc::RecvTimeoutError::Timeout) => {
                    if raised.is_none() {
                        if let Err(e) = py.check_signals() {
                            stop.store(true, Ordering::Relaxed);
                            raised = Some(e);
                        }
                    }
                }
                Err(mpsc::RecvTimeoutError::Disconnected) => break None,
            }
        };
        let joined = py.detach(|| handle.join());
        if let Some(e) = raised {
            return Err(e);
        }
        match (out, joined) {
            (Some(out), Ok(())) => Ok(out),
            (_, Err(p)) => {
                let what = p
                    .downcast_ref::<&str>()
                    .map(|s| s.to_string())
                    .or_else(|| p.downcast_ref::<String>().cloned())
                    .unwrap_or_default();
                Err(MeshingError::new_err(format!("internal error: {what}")))
            }
            (None, Ok(())) => Err(MeshingError::new_err("internal error: no result")),
        }
    })
}

// ---------------------------------------------------------------- input

/// The rows of an `(n, D)` float64 array.
fn rows<const D: usize>(a: &PyReadonlyArray2<'_, f64>, what: &str) -> PyResult<Vec<[f64; D]>> {
    let shape = a.shape();
    if shape[1] != D {
        return Err(invalid(format!(
            "{what} must be an (n, {D}) array, got shape ({}, {})",
            shape[0], shape[1]
        )));
    }
    // Contiguous input (what the Python wrappers pass) is read as one slice.
    if let Ok(flat) = a.as_slice() {
        return Ok(flat
            .chunks_exact(D)
            .map(|c| std::array::from_fn(|k| c[k]))
            .collect());
    }
    let v = a.as_array();
    Ok(v.outer_iter()
        .map(|r| std::array::from_fn(|k| r[k]))
        .collect())
}

/// The rows of an `(n, K)` int64 index array, each index checked against
/// `n` items (`what` names a row, `of` the items).
fn index_rows<const K: usize>(
    a: &PyReadonlyArray2<'_, i64>,
    n: usize,
    what: &str,
    of: &str,
) -> PyResult<Vec<[u32; K]>> {
    let shape = a.shape();
    if shape[1] != K && shape[0] > 0 {
        return Err(invalid(format!(
            "{what}s must be an (m, {K}) array, got shape ({}, {})",
            shape[0], shape[1]
        )));
    }
    let v = a.as_array();
    let mut out = Vec::with_capacity(shape[0]);
    for (i, r) in v.outer_iter().enumerate() {
        let mut row = [0u32; K];
        for (k, x) in row.iter_mut().enumerate() {
            *x = check_index(r[k], n, || format!("{what} {i}"), of)?;
        }
        out.push(row);
    }
    Ok(out)
}

fn check_index(x: i64, n: usize, who: impl Fn() -> String, of: &str) -> PyResult<u32> {
    if x < 0 || x as u64 >= n as u64 {
        return Err(invalid(format!(
            "{} refers to {of} {x}, out of range for {n} {of}s",
            who()
        )));
    }
    Ok(x as u32)
}

fn opt_vec<T: numpy::Element + Copy>(
    a: Option<&PyReadonlyArray1<'_, T>>,
    len: usize,
    what: &str,
) -> PyResult<Vec<T>> {
    match a {
        None => Ok(Vec::new()),
        Some(a) => {
            if a.len() != len {
                return Err(invalid(format!(
                    "{what} has {} entries for {len} items",
                    a.len()
                )));
            }
            Ok(a.as_array().iter().copied().collect())
        }
    }
}

// ---------------------------------------------------------------- output

fn coords<'py, const D: usize>(
    py: Python<'py>,
    v: &[[f64; D]],
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    PyArray1::from_vec(py, v.as_flattened().to_vec()).reshape([v.len(), D])
}

/// Index rows as int32, [`NONE`] as -1.
fn ids<'py, const K: usize>(
    py: Python<'py>,
    v: &[[u32; K]],
) -> PyResult<Bound<'py, PyArray2<i32>>> {
    // Exact-size iteration (a flattening iterator would grow the vector).
    let flat: Vec<i32> = v.as_flattened().iter().map(|&x| x as i32).collect();
    PyArray1::from_vec(py, flat).reshape([v.len(), K])
}

/// [`ids`] for an owned result: the rows are flattened and turned into int32
/// in place, and numpy takes the buffer (no copy, no new pages).
fn ids_vec<'py, const K: usize>(
    py: Python<'py>,
    v: Vec<[u32; K]>,
) -> PyResult<Bound<'py, PyArray2<i32>>> {
    let n = v.len();
    // Same size and alignment: `collect` reuses the allocation.
    let flat: Vec<i32> = v.into_flattened().into_iter().map(|x| x as i32).collect();
    PyArray1::from_vec(py, flat).reshape([n, K])
}

fn ids1<'py>(py: Python<'py>, v: &[u32]) -> Bound<'py, PyArray1<i32>> {
    PyArray1::from_vec(py, v.iter().map(|&x| x as i32).collect())
}

fn pairs<'py>(py: Python<'py>, v: &[(u32, u32)]) -> PyResult<Bound<'py, PyArray2<i32>>> {
    let v: Vec<[u32; 2]> = v.iter().map(|&(a, b)| [a, b]).collect();
    ids(py, &v)
}

// ---------------------------------------------------------------- point sets

/// `work`'s result and its wall time in seconds (the library's share of a
/// call, for the benchmark's overhead figure).
fn timed<T>(work: impl FnOnce() -> T) -> (T, f64) {
    let t = std::time::Instant::now();
    let out = work();
    (out, t.elapsed().as_secs_f64())
}

/// Delaunay (or, with weights, regular) triangulation of an `(n, 2)` or
/// `(n, 3)` float64 array: `simplices`, `neighbors`, `duplicates`, `hidden`,
/// and `seconds` (the library's time, without the conversions).
#[pyfunction]
#[pyo3(signature = (points, weights=None))]
fn delaunay<'py>(
    py: Python<'py>,
    points: PyReadonlyArray2<'py, f64>,
    weights: Option<PyReadonlyArray1<'py, f64>>,
) -> PyResult<Bound<'py, PyDict>> {
    let n = points.shape()[0];
    let w = weights
        .as_ref()
        .map(|w| opt_vec(Some(w), n, "weights"))
        .transpose()?;
    let d = PyDict::new(py);
    let (dup, hidden) = if points.shape()[1] == 2 {
        let p = rows::<2>(&points, "points")?;
        let m = run(py, None, || {
            timed(|| match &w {
                Some(w) => delone::tri::regular_triangulation(&p, w),
                None => delone::tri::triangulate(&p),
            })
        })?;
        d.set_item("seconds", m.1)?;
        let m = m.0.map_err(|e| lib_err(&e))?;
        d.set_item("simplices", ids_vec(py, m.triangles)?)?;
        d.set_item("neighbors", ids_vec(py, m.neighbors)?)?;
        (m.duplicates, m.hidden)
    } else {
        let p = rows::<3>(&points, "points")?;
        let m = run(py, None, || {
            timed(|| match &w {
                Some(w) => delone::tet::regular_tetrahedralization(&p, w),
                None => delone::tet::tetrahedralize(&p),
            })
        })?;
        d.set_item("seconds", m.1)?;
        let m = m.0.map_err(|e| lib_err(&e))?;
        d.set_item("simplices", ids_vec(py, m.tets)?)?;
        d.set_item("neighbors", ids_vec(py, m.neighbors)?)?;
        (m.duplicates, m.hidden)
    };
    d.set_item("duplicates", pairs(py, &dup)?)?;
    d.set_item("hidden", ids1(py, &hidden))?;
    Ok(d)
}

/// Convex hull of an `(n, 2)` or `(n, 3)` array: its edges (counterclockwise
/// around the hull) or its triangles (counterclockwise seen from outside).
#[pyfunction]
fn convex_hull<'py>(
    py: Python<'py>,
    points: PyReadonlyArray2<'py, f64>,
) -> PyResult<Bound<'py, PyArray2<i32>>> {
    if points.shape()[1] == 2 {
        let p = rows::<2>(&points, "points")?;
        let m = run(py, None, || delone::tri::triangulate(&p))?.map_err(|e| lib_err(&e))?;
        let hull: Vec<[u32; 2]> = m
            .triangles
            .iter()
            .zip(&m.neighbors)
            .flat_map(|(t, n)| {
                (0..3)
                    .filter(move |&k| n[k] == NONE)
                    .map(move |k| [t[(k + 1) % 3], t[(k + 2) % 3]])
            })
            .collect();
        ids(py, &hull)
    } else {
        let p = rows::<3>(&points, "points")?;
        let m = run(py, None, || delone::tet::tetrahedralize(&p))?.map_err(|e| lib_err(&e))?;
        let hull: Vec<[u32; 3]> = m.hull_faces().collect();
        ids(py, &hull)
    }
}

/// Voronoi (with weights: power) diagram of an `(n, 2)` or `(n, 3)` array:
/// `vertices`, `edges` (`-1` second end: a ray), `directions` (of the rays,
/// zero for finite edges), `edge_sites`; in 3D also the faces (`face_offsets`,
/// `face_vertices`, `face_sites`).
#[pyfunction]
#[pyo3(signature = (points, weights=None))]
fn voronoi<'py>(
    py: Python<'py>,
    points: PyReadonlyArray2<'py, f64>,
    weights: Option<PyReadonlyArray1<'py, f64>>,
) -> PyResult<Bound<'py, PyDict>> {
    let n = points.shape()[0];
    let w = weights
        .as_ref()
        .map(|w| opt_vec(Some(w), n, "weights"))
        .transpose()?;
    let d = PyDict::new(py);
    if points.shape()[1] == 2 {
        let p = rows::<2>(&points, "points")?;
        let v = run(py, None, || {
            let m = match &w {
                Some(w) => delone::tri::regular_triangulation(&p, w)?,
                None => delone::tri::triangulate(&p)?,
            };
            match &w {
                Some(w) => delone::tri::Voronoi2::new_power(&p, w, &m),
                None => delone::tri::Voronoi2::new(&p, &m),
            }
        })?
        .map_err(|e| lib_err(&e))?;
        let edges: Vec<[u32; 2]> = v.edges.iter().map(|e| e.vertices).collect();
        let sites: Vec<[u32; 2]> = v.edges.iter().map(|e| e.sites).collect();
        let dirs: Vec<[f64; 2]> = v.edges.iter().map(|e| e.direction(&p)).collect();
        d.set_item("vertices", coords(py, &v.vertices)?)?;
        d.set_item("edges", ids(py, &edges)?)?;
        d.set_item("directions", coords(py, &dirs)?)?;
        d.set_item("edge_sites", ids(py, &sites)?)?;
    } else {
        let p = rows::<3>(&points, "points")?;
        let v = run(py, None, || {
            let m = match &w {
                Some(w) => delone::tet::regular_tetrahedralization(&p, w)?,
                None => delone::tet::tetrahedralize(&p)?,
            };
            match &w {
                Some(w) => delone::tet::Voronoi3::new_power(&p, w, &m),
                None => delone::tet::Voronoi3::new(&p, &m),
            }
        })?
        .map_err(|e| lib_err(&e))?;
        let edges: Vec<[u32; 2]> = v.edges.iter().map(|e| e.vertices).collect();
        let sites: Vec<[u32; 3]> = v.edges.iter().map(|e| e.sites).collect();
        let mut dirs = vec![[0.0; 3]; v.edges.len()];
        for (&e, &dir) in v.ray_edges.iter().zip(&v.ray_directions) {
            dirs[e as usize] = dir;
        }
        let face_sites: Vec<[u32; 2]> = v.faces.iter().map(|f| f.sites).collect();
        d.set_item("vertices", coords(py, &v.vertices)?)?;
        d.set_item("edges", ids(py, &edges)?)?;
        d.set_item("directions", coords(py, &dirs)?)?;
        d.set_item("edge_sites", ids(py, &sites)?)?;
        d.set_item("face_offsets", ids1(py, &v.face_offsets))?;
        d.set_item("face_vertices", ids1(py, &v.face_vertices))?;
        d.set_item("face_sites", ids(py, &face_sites)?)?;
    }
    Ok(d)
}

// ---------------------------------------------------------------- 2D meshing

/// Triangle's marker of a boundary or segment edge: the segment's own
/// marker, else 1 on the boundary, else 0.
fn marker(own: i32, on_boundary: bool) -> i32 {
    if own != 0 {
        own
    } else {
        i32::from(on_boundary)
    }
}

/// Triangle's segments of a mesh: the subsegments, then the boundary edges
/// that are none (the hull with `c`), with [`marker`]s.
fn boundary_segments(
    tris: &[[u32; 3]],
    nbrs: &[[u32; 3]],
    subs: &[([u32; 2], i32)],
) -> (Vec<[u32; 2]>, Vec<i32>) {
    let hull = hull_edge_keys(tris, nbrs);
    let mut keys: Vec<u64> = subs.iter().map(|(s, _)| edge_key(s[0], s[1])).collect();
    keys.sort_unstable();
    let (mut segs, mut markers): (Vec<[u32; 2]>, Vec<i32>) = subs
        .iter()
        .map(|&(s, m)| {
            (
                s,
                marker(m, hull.binary_search(&edge_key(s[0], s[1])).is_ok()),
            )
        })
        .unzip();
    for (tv, nb) in tris.iter().zip(nbrs) {
        for k in (0..3).filter(|&k| nb[k] == NONE) {
            let (a, b) = (tv[(k + 1) % 3], tv[(k + 2) % 3]);
            if keys.binary_search(&edge_key(a, b)).is_err() {
                segs.push([a, b]);
                markers.push(1);
            }
        }
    }
    (segs, markers)
}

/// The unique edges of `tris` with their [`marker`]s.
fn edges_with_markers(
    tris: &[[u32; 3]],
    nbrs: &[[u32; 3]],
    subs: &[([u32; 2], i32)],
) -> (Vec<[u32; 2]>, Vec<i32>) {
    let mut marks: Vec<(u64, i32)> = subs
        .iter()
        .map(|&(s, m)| (edge_key(s[0], s[1]), m))
        .collect();
    marks.sort_unstable();
    let (mut edges, mut markers) = (Vec::new(), Vec::new());
    for (t, (tv, nb)) in tris.iter().zip(nbrs).enumerate() {
        for k in 0..3 {
            // Each edge once: from the lower triangle, or the only one.
            if nb[k] != NONE && (nb[k] as usize) < t {
                continue;
            }
            let (a, b) = (tv[(k + 1) % 3], tv[(k + 2) % 3]);
            let own = marks
                .binary_search_by_key(&edge_key(a, b), |&(e, _)| e)
                .map_or(0, |i| marks[i].1);
            edges.push([a, b]);
            markers.push(marker(own, nb[k] == NONE));
        }
    }
    (edges, markers)
}

fn quality2(py: Python<'_>, points: &[[f64; 2]], tris: &[[u32; 3]]) -> PyResult<Py<PyDict>> {
    let d = PyDict::new(py);
    if let Ok(s) = delone::tri::quality::TriStats::new(points, tris) {
        d.set_item("vertices", s.vertices)?;
        d.set_item("triangles", s.triangles)?;
        d.set_item("edges", s.edges)?;
        d.set_item("boundary_edges", s.boundary_edges)?;
        d.set_item("min_angle", s.min_angle)?;
        d.set_item("max_angle", s.max_angle)?;
        d.set_item("min_area", s.min_area)?;
        d.set_item("max_area", s.max_area)?;
        d.set_item("total_area", s.total_area)?;
        d.set_item("shortest_edge", s.shortest_edge)?;
        d.set_item("longest_edge", s.longest_edge)?;
        d.set_item("max_aspect_ratio", s.max_aspect_ratio)?;
        d.set_item("max_radius_edge", s.max_radius_edge)?;
    }
    Ok(d.unbind())
}

/// Constrained (quality) triangulation of a PSLG with Triangle's switches,
/// or (`r`) refinement of the given triangles.
#[pyfunction]
#[pyo3(signature = (points, switches, segments, point_markers=None, segment_markers=None,
    holes=None, regions=None, triangles=None, triangle_attributes=None, triangle_max_area=None,
    edges=false, progress=None))]
#[allow(clippy::too_many_arguments)]
fn triangulate<'py>(
    py: Python<'py>,
    points: PyReadonlyArray2<'py, f64>,
    switches: &str,
    segments: PyReadonlyArray2<'py, i64>,
    point_markers: Option<PyReadonlyArray1<'py, i32>>,
    segment_markers: Option<PyReadonlyArray1<'py, i32>>,
    holes: Option<PyReadonlyArray2<'py, f64>>,
    regions: Option<PyReadonlyArray2<'py, f64>>,
    triangles: Option<PyReadonlyArray2<'py, i64>>,
    triangle_attributes: Option<PyReadonlyArray1<'py, f64>>,
    triangle_max_area: Option<PyReadonlyArray1<'py, f64>>,
    edges: bool,
    progress: Option<Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let opts = TriOptions::from_switches(switches)
        .map_err(|e| invalid(format!("switches {switches:?}: {e}")))?;
    if opts.second_order || opts.voronoi || opts.weights {
        return Err(invalid(format!(
            "switches {switches:?}: -o2, -v and -w are not available here (use delone.voronoi / delone.regular)"
        )));
    }
    let p = rows::<2>(&points, "points")?;
    let n = p.len();
    let mut g = Pslg::new(p, index_rows::<2>(&segments, n, "segment", "point")?);
    g.point_markers = opt_vec(point_markers.as_ref(), n, "point_markers")?;
    g.segment_markers = opt_vec(
        segment_markers.as_ref(),
        g.segments.len(),
        "segment_markers",
    )?;
    if let Some(h) = &holes {
        g.holes = rows::<2>(h, "holes")?;
    }
    if let Some(r) = &regions {
        g.regions = rows::<4>(r, "regions")?
            .into_iter()
            .map(|r| Region2 {
                point: [r[0], r[1]],
                attribute: r[2],
                max_area: if r[3] > 0.0 { r[3] } else { -1.0 },
            })
            .collect();
    }
    let result: TriResult = if opts.refine_mesh {
        let Some(t) = &triangles else {
            return Err(invalid("switch r refines a mesh: give its triangles"));
        };
        let tris = index_rows::<3>(t, n, "triangle", "point")?;
        let nt = tris.len();
        let existing = ExistingMesh {
            points: g.points.clone(),
            triangles: tris,
            segments: g.segments.clone(),
            segment_markers: g.segment_markers.clone(),
            attributes: opt_vec(triangle_attributes.as_ref(), nt, "triangle_attributes")?,
            max_areas: opt_vec(triangle_max_area.as_ref(), nt, "triangle_max_area")?,
        };
        let ro = opts.refine_options();
        let r = run(py, progress.as_ref(), || {
            let cdt = Cdt::from_mesh(existing)?;
            refine(&cdt, &ro)
        })?
        .map_err(|e| lib_err(&e))?;
        TriResult {
            mesh: r.mesh,
            unrefined: None,
            refine: Some(r.report),
            refine_time: Duration::ZERO,
        }
    } else {
        run(py, progress.as_ref(), || delone::tri::mesh(&g, &opts))?.map_err(tri_err)?
    };
    let m = &result.mesh;
    let subs = result.subsegments();
    let d = PyDict::new(py);
    d.set_item("points", coords(py, &m.points)?)?;
    d.set_item("triangles", ids(py, &m.triangles)?)?;
    d.set_item("neighbors", ids(py, &m.neighbors)?)?;
    d.set_item(
        "point_markers",
        PyArray1::from_vec(py, result.vertex_markers(&g)),
    )?;
    let (seg, seg_markers) = boundary_segments(&m.triangles, &m.neighbors, &subs);
    d.set_item("segments", ids(py, &seg)?)?;
    d.set_item("segment_markers", PyArray1::from_vec(py, seg_markers))?;
    d.set_item("attributes", PyArray1::from_slice(py, &m.attributes))?;
    d.set_item("regions", ids1(py, &m.regions))?;
    if edges || opts.output.edges {
        let (e, em) = edges_with_markers(&m.triangles, &m.neighbors, &subs);
        d.set_item("edges", ids(py, &e)?)?;
        d.set_item("edge_markers", PyArray1::from_vec(py, em))?;
    }
    d.set_item("quality", quality2(py, &m.points, &m.triangles)?)?;
    Ok(d)
}

// ---------------------------------------------------------------- 3D meshing

/// The quality report of a tetrahedral mesh: the statistics of the final
/// mesh (those the optimisation computed when it ran) and the
/// optimisation's stages (`optimization_stages`, empty when it did not run).
fn quality3(py: Python<'_>, r: &delone::tet::TetResult) -> PyResult<Py<PyDict>> {
    let rec = &r.mesh;
    let computed;
    let s = match &r.optimize {
        Some(o) => &o.after,
        None => {
            computed = delone::tet::quality::TetStats::of(&rec.points, &rec.mesh.tets);
            &computed
        }
    };
    let d = PyDict::new(py);
    d.set_item("tetrahedra", s.tets)?;
    d.set_item("min_dihedral", s.min_dihedral)?;
    d.set_item("max_dihedral", s.max_dihedral)?;
    d.set_item("min_radius_edge", s.min_radius_edge)?;
    d.set_item("max_radius_edge", s.max_radius_edge)?;
    d.set_item("mean_radius_edge", s.mean_radius_edge)?;
    d.set_item("min_volume", s.min_volume)?;
    d.set_item("max_volume", s.max_volume)?;
    d.set_item("total_volume", s.total_volume)?;
    d.set_item("min_edge", s.min_edge)?;
    d.set_item("max_edge", s.max_edge)?;
    let stages = PyList::empty(py);
    for st in r.optimize.iter().flat_map(|o| &o.stages) {
        let x = PyDict::new(py);
        x.set_item("threshold", st.threshold)?;
        x.set_item("second_run", st.second_run)?;
        x.set_item("evaluations", st.evaluations)?;
        x.set_item("undone_evaluations", st.undone_evaluations)?;
        x.set_item("worst_reached", st.worst_reached)?;
        x.set_item("attempts", st.attempts)?;
        x.set_item("successes", st.successes)?;
        x.set_item("worst", (st.worst[0], st.worst[1]))?;
        x.set_item("below", (st.below[0], st.below[1]))?;
        x.set_item("stop", st.stop.to_string())?;
        stages.append(x)?;
    }
    d.set_item("optimization_stages", stages)?;
    Ok(d.unbind())
}

/// Tetrahedral mesh of a closed surface or PLC with TetGen's switches.
/// `faces` are polygons given flat (`face_vertices`) with `face_offsets`
/// (`len(faces) + 1` entries).
#[pyfunction]
#[pyo3(signature = (points, face_vertices, face_offsets, switches, face_markers=None,
    holes=None, regions=None, progress=None))]
#[allow(clippy::too_many_arguments)]
fn tetrahedralize<'py>(
    py: Python<'py>,
    points: PyReadonlyArray2<'py, f64>,
    face_vertices: PyReadonlyArray1<'py, i64>,
    face_offsets: PyReadonlyArray1<'py, i64>,
    switches: &str,
    face_markers: Option<PyReadonlyArray1<'py, i32>>,
    holes: Option<PyReadonlyArray2<'py, f64>>,
    regions: Option<PyReadonlyArray2<'py, f64>>,
    progress: Option<Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let mut opts = TetOptions::from_switches(switches)
        .map_err(|e| invalid(format!("switches {switches:?}: {e}")))?;
    // The quality dict shows the final statistics and the optimisation's
    // stages only: the reports' other diagnostics are not gathered.
    opts.no_diagnostics = true;
    let p = rows::<3>(&points, "points")?;
    let n = p.len();
    let fv = face_vertices.as_array();
    let fo = face_offsets.as_array();
    let nf = fo.len().saturating_sub(1);
    let markers = opt_vec(face_markers.as_ref(), nf, "face_markers")?;
    let mut facets = Vec::with_capacity(nf);
    for f in 0..nf {
        let (a, b) = (fo[f], fo[f + 1]);
        if a < 0 || b < a || b as usize > fv.len() {
            return Err(invalid(format!("face {f}: bad offsets {a}..{b}")));
        }
        let corners = (a as usize..b as usize)
            .map(|k| check_index(fv[k], n, || format!("face {f}"), "point"))
            .collect::<PyResult<Vec<u32>>>()?;
        let mut facet = Facet::polygon(corners);
        facet.marker = markers.get(f).copied().unwrap_or(0);
        facets.push(facet);
    }
    let mut plc = Plc::new(p);
    plc.facets = facets;
    if let Some(h) = &holes {
        plc.holes = rows::<3>(h, "holes")?;
    }
    if let Some(r) = &regions {
        plc.regions = rows::<5>(r, "regions")?
            .into_iter()
            .map(|r| Region3 {
                point: [r[0], r[1], r[2]],
                attribute: r[3],
                max_volume: (r[4] > 0.0).then_some(r[4]),
            })
            .collect();
    }
    let r = run(py, progress.as_ref(), || delone::tet::mesh(&plc, &opts))?.map_err(tet_err)?;
    let rec = &r.mesh;
    let d = PyDict::new(py);
    d.set_item("points", coords(py, &rec.points)?)?;
    d.set_item("tetrahedra", ids(py, &rec.mesh.tets)?)?;
    d.set_item("neighbors", ids(py, &rec.mesh.neighbors)?)?;
    d.set_item("faces", ids(py, &r.faces)?)?;
    d.set_item("face_markers", PyArray1::from_slice(py, &r.face_markers))?;
    d.set_item("attributes", PyArray1::from_vec(py, r.attributes()))?;
    d.set_item("regions", ids1(py, &rec.tet_region))?;
    d.set_item("quality", quality3(py, &r)?)?;
    Ok(d)
}

// ---------------------------------------------------------------- adaptation

/// The metric of each of `n` vertices from an `(n, 1)` array of sizes or an
/// `(n, D(D+1)/2)` array of tensors in Medit's order.
fn metrics<const D: usize>(a: &PyReadonlyArray2<'_, f64>, n: usize) -> PyResult<Vec<Metric<D>>> {
    let c = D * (D + 1) / 2;
    let shape = a.shape();
    if shape[0] != n || (shape[1] != 1 && shape[1] != c) {
        return Err(invalid(format!(
            "metric must have one row per point ({n}) of 1 size or {c} tensor components, got shape ({}, {})",
            shape[0], shape[1]
        )));
    }
    let v = a.as_array();
    v.outer_iter()
        .enumerate()
        .map(|(i, r)| {
            let row: Vec<f64> = r.iter().copied().collect();
            let m = if row.len() == 1 {
                if !row[0].is_finite() {
                    Err(delone::MetricDefect::NotFinite)
                } else if row[0] > 0.0 {
                    Ok(Metric::isotropic(row[0]))
                } else {
                    Err(delone::MetricDefect::NotPositiveDefinite)
                }
            } else {
                Metric::from_medit(&row)
            };
            m.map_err(|defect| lib_err(&Error::InvalidMetric { vertex: i, defect }))
        })
        .collect()
}

/// Metrics as an `(n, D(D+1)/2)` array in Medit's order.
fn metric_array<'py, const D: usize>(
    py: Python<'py>,
    m: &[Metric<D>],
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let c = D * (D + 1) / 2;
    let flat: Vec<f64> = m.iter().flat_map(|m| m.medit()).collect();
    PyArray1::from_vec(py, flat).reshape([m.len(), c])
}

fn stats_dict<'py>(py: Python<'py>, s: &MetricStats) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("vertices", s.vertices)?;
    d.set_item("elements", s.elements)?;
    d.set_item("edges", s.edges)?;
    d.set_item("length_min", s.length_min)?;
    d.set_item("length_max", s.length_max)?;
    d.set_item("length_mean", s.length_mean)?;
    d.set_item("in_range", s.in_range)?;
    d.set_item("in_range_share", s.in_range_share())?;
    d.set_item("length_histogram", s.length_histogram.to_vec())?;
    d.set_item("quality_min", s.quality_min)?;
    d.set_item("quality_mean", s.quality_mean)?;
    d.set_item("quality_histogram", s.quality_histogram.to_vec())?;
    Ok(d)
}

fn report_dict<'py>(py: Python<'py>, r: &AdaptReport) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("before", stats_dict(py, &r.before)?)?;
    d.set_item("after", stats_dict(py, &r.after)?)?;
    d.set_item("passes", r.passes)?;
    d.set_item("splits", r.splits)?;
    d.set_item("collapses", r.collapses)?;
    d.set_item("swaps", r.swaps)?;
    d.set_item("moves", r.moves)?;
    d.set_item("budget_reached", r.budget_reached)?;
    d.set_item("phases", r.phases.clone())?;
    Ok(d)
}

/// The optional arrays of an adaptation's input mesh.
struct MeshExtras<'a, 'py> {
    faces: Option<&'a PyReadonlyArray2<'py, i64>>,
    face_refs: Option<&'a PyReadonlyArray1<'py, i32>>,
    element_refs: Option<&'a PyReadonlyArray1<'py, i32>>,
    corners: Option<&'a PyReadonlyArray1<'py, i64>>,
    required: Option<&'a PyReadonlyArray1<'py, i64>>,
    ridges: Option<&'a PyReadonlyArray2<'py, i64>>,
}

fn vertex_list(a: Option<&PyReadonlyArray1<'_, i64>>, n: usize, what: &str) -> PyResult<Vec<u32>> {
    a.map_or(Ok(Vec::new()), |a| {
        a.as_array()
            .iter()
            .enumerate()
            .map(|(i, &x)| check_index(x, n, || format!("{what} {i}"), "point"))
            .collect()
    })
}

fn simplex_mesh<const D: usize, const K: usize>(
    points: &PyReadonlyArray2<'_, f64>,
    elements: &PyReadonlyArray2<'_, i64>,
    x: &MeshExtras<'_, '_>,
) -> PyResult<SimplexMesh<D, K>> {
    let points = rows::<D>(points, "points")?;
    let n = points.len();
    let elements = index_rows::<K>(elements, n, "element", "point")?;
    let faces = match x.faces {
        Some(f) => index_rows::<D>(f, n, "face", "point")?,
        None => Vec::new(),
    };
    let ridges = match x.ridges {
        Some(r) => index_rows::<2>(r, n, "ridge", "point")?,
        None => Vec::new(),
    };
    Ok(SimplexMesh {
        face_refs: opt_vec(x.face_refs, faces.len(), "face_markers")?,
        element_refs: opt_vec(x.element_refs, elements.len(), "element_markers")?,
        corners: vertex_list(x.corners, n, "corner")?,
        required: vertex_list(x.required, n, "required vertex")?,
        points,
        point_refs: Vec::new(),
        elements,
        faces,
        ridges,
    })
}

fn adapt_dict<'py, const D: usize, const K: usize>(
    py: Python<'py>,
    a: delone::adapt::Adapted<D, K>,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("points", coords(py, &a.mesh.points)?)?;
    d.set_item("elements", ids(py, &a.mesh.elements)?)?;
    d.set_item(
        "element_markers",
        PyArray1::from_slice(py, &a.mesh.element_refs),
    )?;
    d.set_item("faces", ids(py, &a.mesh.faces)?)?;
    d.set_item("face_markers", PyArray1::from_slice(py, &a.mesh.face_refs))?;
    d.set_item("metric", metric_array(py, &a.metric)?)?;
    d.set_item("report", report_dict(py, &a.report)?)?;
    Ok(d)
}

/// The metric given (see [`metrics`]), else the mesh's own sizes bounded
/// by the options' `hmin`/`hmax` ([`delone::metric::metric_from_mesh`]).
fn metric_or_own<const D: usize, const K: usize>(
    metric: Option<&PyReadonlyArray2<'_, f64>>,
    mesh: &SimplexMesh<D, K>,
    opts: &AdaptOptions,
) -> PyResult<Vec<Metric<D>>> {
    match metric {
        Some(a) => metrics::<D>(a, mesh.points.len()),
        None => delone::metric::metric_from_mesh(
            &mesh.points,
            &mesh.elements,
            opts.hmin.unwrap_or(0.0),
            opts.hmax.unwrap_or(f64::INFINITY),
        )
        .map_err(|e| lib_err(&e)),
    }
}

/// Adapts a triangle (points `(n, 2)`) or tetrahedral (`(n, 3)`) mesh to a
/// metric given at its vertices, or to its own sizes without one (see
/// `delone.adapt`).
#[pyfunction]
#[pyo3(signature = (points, elements, metric=None, faces=None, face_markers=None,
    element_markers=None, corners=None, required=None, ridges=None, hmin=None, hmax=None,
    hgrad=None, insert=true, swap=true, smooth=true, max_passes=30, max_vertices=None,
    progress=None))]
#[allow(clippy::too_many_arguments)]
fn adapt<'py>(
    py: Python<'py>,
    points: PyReadonlyArray2<'py, f64>,
    elements: PyReadonlyArray2<'py, i64>,
    metric: Option<PyReadonlyArray2<'py, f64>>,
    faces: Option<PyReadonlyArray2<'py, i64>>,
    face_markers: Option<PyReadonlyArray1<'py, i32>>,
    element_markers: Option<PyReadonlyArray1<'py, i32>>,
    corners: Option<PyReadonlyArray1<'py, i64>>,
    required: Option<PyReadonlyArray1<'py, i64>>,
    ridges: Option<PyReadonlyArray2<'py, i64>>,
    hmin: Option<f64>,
    hmax: Option<f64>,
    hgrad: Option<f64>,
    insert: bool,
    swap: bool,
    smooth: bool,
    max_passes: usize,
    max_vertices: Option<usize>,
    progress: Option<Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let opts = AdaptOptions {
        hmin,
        hmax,
        hgrad,
        insert,
        swap,
        smooth,
        max_passes,
        max_vertices,
    };
    let extras = MeshExtras {
        faces: faces.as_ref(),
        face_refs: face_markers.as_ref(),
        element_refs: element_markers.as_ref(),
        corners: corners.as_ref(),
        required: required.as_ref(),
        ridges: ridges.as_ref(),
    };
    if points.shape()[1] == 2 {
        let mesh = simplex_mesh::<2, 3>(&points, &elements, &extras)?;
        let m = metric_or_own(metric.as_ref(), &mesh, &opts)?;
        let a = run(py, progress.as_ref(), || {
            delone::adapt::adapt_tri(&mesh, MetricField::AtVertices(m), &opts)
        })?
        .map_err(|e| lib_err(&e))?;
        adapt_dict(py, a)
    } else {
        let mesh = simplex_mesh::<3, 4>(&points, &elements, &extras)?;
        let m = metric_or_own(metric.as_ref(), &mesh, &opts)?;
        let a = run(py, progress.as_ref(), || {
            delone::adapt::adapt_tet(&mesh, MetricField::AtVertices(m), &opts)
        })?
        .map_err(|e| lib_err(&e))?;
        adapt_dict(py, a)
    }
}

fn field_metric<'py, const D: usize, const K: usize>(
    py: Python<'py>,
    points: &PyReadonlyArray2<'py, f64>,
    elements: &PyReadonlyArray2<'py, i64>,
    values: &[f64],
    target: Target,
    bounds: (f64, f64, Option<f64>),
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let p = rows::<D>(points, "points")?;
    let e = index_rows::<K>(elements, p.len(), "element", "point")?;
    if values.len() != p.len() {
        return Err(lib_err(&Error::MetricCount {
            vertices: p.len(),
            metrics: values.len(),
        }));
    }
    let h = delone::metric::hessians(&p, &e, values).map_err(|e| lib_err(&e))?;
    let mut m = delone::metric::metric_from_hessians(&p, &e, &h, target, bounds.0, bounds.1)
        .map_err(|e| lib_err(&e))?;
    if let Some(beta) = bounds.2 {
        delone::metric::gradate(&p, &delone::metric::edges(&e), &mut m, beta);
    }
    metric_array(py, &m)
}

/// The metric that minimises the interpolation error of a scalar field given
/// at the vertices (see `delone.metric_from_field`).
#[pyfunction]
#[pyo3(signature = (points, elements, values, complexity=None, error=None, p=2.0,
    hmin=1e-12, hmax=1e12, hgrad=None))]
#[allow(clippy::too_many_arguments)]
fn metric_from_field<'py>(
    py: Python<'py>,
    points: PyReadonlyArray2<'py, f64>,
    elements: PyReadonlyArray2<'py, i64>,
    values: PyReadonlyArray1<'py, f64>,
    complexity: Option<f64>,
    error: Option<f64>,
    p: f64,
    hmin: f64,
    hmax: f64,
    hgrad: Option<f64>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let target = match (complexity, error) {
        (Some(c), None) => Target::Complexity { complexity: c, p },
        (None, Some(e)) => Target::Error(e),
        _ => return Err(invalid("give exactly one of complexity= and error=")),
    };
    let v: Vec<f64> = values.as_array().iter().copied().collect();
    let bounds = (hmin, hmax, hgrad);
    if points.shape()[1] == 2 {
        field_metric::<2, 3>(py, &points, &elements, &v, target, bounds)
    } else {
        field_metric::<3, 4>(py, &points, &elements, &v, target, bounds)
    }
}

/// Edge lengths and element quality of a mesh in a metric (see
/// `delone.metric_stats`).
#[pyfunction]
fn metric_stats<'py>(
    py: Python<'py>,
    points: PyReadonlyArray2<'py, f64>,
    elements: PyReadonlyArray2<'py, i64>,
    metric: PyReadonlyArray2<'py, f64>,
) -> PyResult<Bound<'py, PyDict>> {
    if points.shape()[1] == 2 {
        let p = rows::<2>(&points, "points")?;
        let e = index_rows::<3>(&elements, p.len(), "element", "point")?;
        let m = metrics::<2>(&metric, p.len())?;
        stats_dict(py, &delone::adapt::metric_stats(&p, &e, &m))
    } else {
        let p = rows::<3>(&points, "points")?;
        let e = index_rows::<4>(&elements, p.len(), "element", "point")?;
        let m = metrics::<3>(&metric, p.len())?;
        stats_dict(py, &delone::adapt::metric_stats(&p, &e, &m))
    }
}

/// The native part of the `delone` Python package.
#[pymodule]
fn _delone(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("InvalidInput", m.py().get_type::<InvalidInput>())?;
    m.add("MeshingError", m.py().get_type::<MeshingError>())?;
    m.add_function(wrap_pyfunction!(delaunay, m)?)?;
    m.add_function(wrap_pyfunction!(convex_hull, m)?)?;
    m.add_function(wrap_pyfunction!(voronoi, m)?)?;
    m.add_function(wrap_pyfunction!(triangulate, m)?)?;
    m.add_function(wrap_pyfunction!(tetrahedralize, m)?)?;
    m.add_function(wrap_pyfunction!(adapt, m)?)?;
    m.add_function(wrap_pyfunction!(metric_from_field, m)?)?;
    m.add_function(wrap_pyfunction!(metric_stats, m)?)?;
    Ok(())
}
