//! `delone adapt`: adapts a triangle or tetrahedral mesh (Medit `.mesh`,
//! or Triangle/TetGen `.node` + `.ele`) to a metric (`--metric IN.sol`:
//! sizes or tensors at the vertices) or to a solution field (`--field
//! IN.sol`: the metric from its recovered Hessian), and writes the mesh and
//! its metric (`OUT.mesh`, `OUT.sol`). Option names follow MMG's where the
//! meaning is the same. With `-noinsert -noswap -nomove` it only measures
//! the input in the metric.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use delone::adapt::{
    adapt_tet, adapt_tri, metric_stats, AdaptOptions, AdaptReport, MetricField, MetricStats,
    SimplexMesh, LENGTH_BINS,
};
use delone::metric::{hessians, metric_from_hessians, metric_from_mesh, Metric, Target};
use delone_io::{DataArray, MeditMesh, MeditSol, SolField, SolKind, Values, VtuArray, VtuFormat};

use crate::fail::{input_err, usage_err, Failure};

/// Usage of `delone adapt`.
pub const HELP: &str = "\
delone adapt: adapt a mesh to a metric field (MMG-style options)

usage: delone adapt IN.mesh [--metric SOL | --field SOL] [-o OUT.mesh] [options]

  IN.mesh           Medit mesh (2D triangles or 3D tetrahedra, with references);
                    by extension also IN.vtu (VTK XML, ascii/base64/raw, not
                    compressed; cell data \"ref\" or \"gmsh:physical\" as references),
                    IN.msh (Gmsh 4.1 ASCII; physical tags as references), or
                    IN.node with IN.ele (Triangle/TetGen)
  --metric SOL      sizes (1 value) or tensors (m11 m12 m22 [m13 m23 m33], Medit
                    order) at the vertices; default IN.sol when it exists, else
                    each vertex's mean incident edge length (as MMG does)
  -hsiz H           one size everywhere instead of a metric
  --field SOL       a scalar solution: metric from its recovered Hessian
                    SOL is a Medit .sol (type 1 or 3), or point arrays of a .vtu:
                    FILE.vtu:NAME[,NAME...] (components side by side), or
                    :NAME[,NAME...] for the input .vtu's own arrays
  --complexity N    target complexity of the field's metric (default: the
                    input's number of vertices x sqrt(3)/2 in 2D, x 0.77 in 3D)
  --error E         target interpolation error instead of a complexity
  -p P              norm of the error (default 2)
  -o OUT.mesh       output mesh (default IN.o.mesh, IN.o.vtu, IN.o.msh by the
                    input's extension); its metric goes to OUT.sol; by extension
                    OUT.vtu (metric as point arrays m11 m12 m22 [m13 m23 m33];
                    elements, then boundary edges (2D) or triangles (3D), with
                    their references as cell data \"ref\")
                    or OUT.msh (Gmsh 4.1; metric in OUT.sol)
  -hmin H -hmax H   size bounds
  -hgrad G          gradation (default 1.3; -1 turns it off)
  -hausd H          Hausdorff bound to the input boundary (MMG's meaning): met
                    by construction, as the boundary is kept exactly (distance 0);
                    -V says so
  -noinsert -noswap -nomove   turn off splits and collapses, swaps, moves;
                    all three: measure the input in the metric only
  --max-passes N    most passes (default 30)
  --max-vertices N  vertex budget
  -V                report (counts, metric edge lengths, quality, time per phase)
  --stats-json FILE the report as JSON
  -Q                quiet
";

struct Args {
    input: PathBuf,
    metric: Option<String>,
    field: Option<String>,
    output: Option<PathBuf>,
    target: Option<Target>,
    p: f64,
    options: AdaptOptions,
    verbose: bool,
    quiet: bool,
    json: Option<PathBuf>,
    hausd: Option<f64>,
    hsiz: Option<f64>,
}

fn parse(argv: Vec<String>) -> Result<Option<Args>, Failure> {
    let mut a = Args {
        input: PathBuf::new(),
        metric: None,
        field: None,
        output: None,
        target: None,
        p: 2.0,
        options: AdaptOptions::default(),
        verbose: false,
        quiet: false,
        json: None,
        hausd: None,
        hsiz: None,
    };
    let mut complexity = None;
    let mut error = None;
    let mut it = argv.into_iter();
    while let Some(arg) = it.next() {
        let mut value = |name: &str| {
            it.next()
                .ok_or_else(|| usage_err(format!("{name} needs a value")))
        };
        let number = |name: &str, v: String| {
            v.parse::<f64>()
                .map_err(|_| usage_err(format!("{name}: {v:?} is not a number")))
        };
        match arg.as_str() {
            "-h" | "--help" => return Ok(None),
            "--metric" | "-met" | "-sol" => a.metric = Some(value(&arg)?),
            "--field" => a.field = Some(value(&arg)?),
            "-o" | "-out" => a.output = Some(value(&arg)?.into()),
            "-in" => a.input = value(&arg)?.into(),
            "--stats-json" => a.json = Some(value(&arg)?.into()),
            "--complexity" => complexity = Some(number(&arg, value(&arg)?)?),
            "--error" => error = Some(number(&arg, value(&arg)?)?),
            "-p" => a.p = number(&arg, value(&arg)?)?,
            "-hmin" => a.options.hmin = Some(number(&arg, value(&arg)?)?),
            "-hmax" => a.options.hmax = Some(number(&arg, value(&arg)?)?),
            "-hausd" | "-hsiz" => {
                let h = number(&arg, value(&arg)?)?;
                if !(h > 0.0 && h.is_finite()) {
                    return Err(usage_err(format!("{arg}: {h} is not positive and finite")));
                }
                *if arg == "-hsiz" {
                    &mut a.hsiz
                } else {
                    &mut a.hausd
                } = Some(h);
            }
            "-hgrad" => {
                let g = number(&arg, value(&arg)?)?;
                a.options.hgrad = (g > 0.0).then_some(g);
            }
            "--max-passes" => {
                a.options.max_passes = number(&arg, value(&arg)?)?.max(0.0) as usize;
            }
            "--max-vertices" => {
                a.options.max_vertices = Some(number(&arg, value(&arg)?)?.max(0.0) as usize);
            }
            "-noinsert" => a.options.insert = false,
            "-noswap" => a.options.swap = false,
            "-nomove" => a.options.smooth = false,
            "-V" | "-v" => a.verbose = true,
            "-Q" => a.quiet = true,
            s if !s.starts_with('-') && a.input.as_os_str().is_empty() => a.input = s.into(),
            s => {
                return Err(usage_err(format!(
                    "unknown option {s:?} (see delone adapt --help)"
                )))
            }
        }
    }
    if a.input.as_os_str().is_empty() {
        return Err(usage_err("no input mesh (see delone adapt --help)"));
    }
    if [a.metric.is_some(), a.field.is_some(), a.hsiz.is_some()]
        .iter()
        .filter(|&&x| x)
        .count()
        > 1
    {
        return Err(usage_err("--metric, --field and -hsiz exclude each other"));
    }
    a.target = match (complexity, error) {
        (Some(_), Some(_)) => return Err(usage_err("--complexity and --error exclude each other")),
        (Some(c), None) => Some(Target::Complexity {
            complexity: c,
            p: a.p,
        }),
        (None, Some(e)) => Some(Target::Error(e)),
        (None, None) => None,
    };
    Ok(Some(a))
}

/// Runs `delone adapt` with the arguments after the subcommand; the exit
/// code.
pub fn main(argv: Vec<String>) -> Result<i32, Failure> {
    let Some(args) = parse(argv)? else {
        print!("{HELP}");
        return Ok(0);
    };
    let clock = Instant::now();
    let (mesh, arrays) = read_mesh(&args.input)?;
    let source = args.field.clone().or(args.metric.clone()).or_else(|| {
        let p = args.input.with_extension("sol");
        (p.exists() && args.hsiz.is_none()).then(|| p.display().to_string())
    });
    // The solution and its file; none: the metric comes from -hsiz or the mesh.
    let mut sol = None;
    if let Some(name) = &source {
        let (s, path) = read_sol(name, &args.input, &arrays, mesh.dimension)?;
        if s.dimension != mesh.dimension {
            return Err(input_err(format!(
                "{name}: a {}D solution for a {}D mesh",
                s.dimension, mesh.dimension
            )));
        }
        if s.vertices != mesh.points.len() {
            return Err(input_err(format!(
                "{name}: {} values for a mesh of {} vertices (a .sol for another mesh?)",
                s.vertices,
                mesh.points.len()
            )));
        }
        sol = Some((s, name.as_str(), path));
    }
    let output = args.output.clone().unwrap_or_else(|| {
        let ext = args.input.extension().and_then(|e| e.to_str());
        let ext = ext.filter(|e| *e == "vtu" || *e == "msh").unwrap_or("mesh");
        args.input.with_extension(format!("o.{ext}"))
    });
    let measure_only = !args.options.insert && !args.options.swap && !args.options.smooth;
    let mut read = vec![(output.clone(), args.input.clone())];
    if let Some((_, _, path)) = &sol {
        read.push((output.with_extension("sol"), path.clone()));
    }
    for (written, read) in &read {
        if !measure_only && same_file(written, read) {
            return Err(usage_err(format!(
                "the output {} would overwrite the input (give -o)",
                written.display()
            )));
        }
    }
    // Progress of the passes on stderr (a bar on a terminal).
    let shown = !args.quiet;
    if mesh.dimension == 2 {
        let m = tri_mesh(&mesh);
        let met = metric_of::<2, 3>(&args, sol.as_ref(), &m)?;
        crate::progress::observe(shown, || finish(&args, &m, met, &output, clock, adapt_tri))
    } else {
        let m = tet_mesh(&mesh);
        let met = metric_of::<3, 4>(&args, sol.as_ref(), &m)?;
        crate::progress::observe(shown, || finish(&args, &m, met, &output, clock, adapt_tet))
    }
}

fn same_file(a: &Path, b: &Path) -> bool {
    a == b
        || a.canonicalize()
            .ok()
            .is_some_and(|x| b.canonicalize().ok() == Some(x))
}

fn read(path: &Path) -> Result<Vec<u8>, Failure> {
    std::fs::read(path).map_err(|e| input_err(format!("{}: {e}", path.display())))
}

/// The solution or metric named by `--metric`/`--field`: a Medit `.sol`
/// file, or point arrays of a `.vtu` (`FILE.vtu:NAME[,NAME...]`, or
/// `:NAME[,NAME...]` for the input `.vtu`'s), their components side by side
/// at each point. Also the path of the file read (to refuse overwriting it).
fn read_sol(
    source: &str,
    input: &Path,
    input_arrays: &[VtuArray],
    dimension: u8,
) -> Result<(MeditSol, PathBuf), Failure> {
    let vtu = source
        .rsplit_once(':')
        .filter(|(f, _)| f.is_empty() || f.ends_with(".vtu"));
    let Some((file, names)) = vtu else {
        let path = PathBuf::from(source);
        let sol = delone_io::read_medit_sol(&read(&path)?)
            .map_err(|e| input_err(format!("{source}: {e}")))?;
        return Ok((sol, path));
    };
    let (path, read_arrays);
    let arrays = if file.is_empty() {
        path = input.to_path_buf();
        input_arrays
    } else {
        path = PathBuf::from(file);
        let bytes = read(&path)?;
        read_arrays = delone_io::read_vtu(&bytes)
            .map_err(|e| input_err(format!("{file}: {e}")))?
            .1;
        &read_arrays[..]
    };
    let mut parts = Vec::new();
    for n in names.split(',') {
        let a = arrays.iter().find(|a| a.name == n).ok_or_else(|| {
            let known: Vec<&str> = arrays.iter().map(|a| a.name.as_str()).collect();
            input_err(format!(
                "{source}: no point array {n:?} (point arrays: {})",
                known.join(", ")
            ))
        })?;
        parts.push(a);
    }
    let width: usize = parts.iter().map(|a| a.components).sum();
    let kind = match width {
        1 => SolKind::Scalar,
        w if w == SolKind::Tensor.width(dimension) => SolKind::Tensor,
        w => {
            return Err(input_err(format!(
                "{source}: {w} components per point (1: a size or a solution; {}: a tensor, Medit order)",
                SolKind::Tensor.width(dimension)
            )))
        }
    };
    let n = parts[0].values.len() / parts[0].components.max(1);
    let mut values = Vec::with_capacity(n * width);
    for i in 0..n {
        for a in &parts {
            let c = a.components;
            let v = a.values.get(i * c..(i + 1) * c).ok_or_else(|| {
                input_err(format!("{source}: array {:?} has fewer points", a.name))
            })?;
            values.extend_from_slice(v);
        }
    }
    let sol = MeditSol {
        dimension,
        vertices: n,
        fields: vec![SolField { kind, values }],
    };
    Ok((sol, path))
}

/// The input mesh by extension: `.vtu` (with its point arrays), `.msh`
/// (Gmsh 4.1), `.node` (+ `.ele`), else Medit.
fn read_mesh(path: &Path) -> Result<(MeditMesh, Vec<VtuArray>), Failure> {
    let name = path.display().to_string();
    let io = |e: delone_io::IoError| input_err(format!("{name}: {e}"));
    match path.extension().and_then(|e| e.to_str()) {
        Some("vtu") => return delone_io::read_vtu(&read(path)?).map_err(io),
        Some("msh") => return Ok((delone_io::read_gmsh(&read(path)?).map_err(io)?, Vec::new())),
        Some("node" | "ele") => {}
        _ => {
            return Ok((
                delone_io::read_medit_mesh(&read(path)?).map_err(io)?,
                Vec::new(),
            ))
        }
    }
    let node = delone_io::read_node(&read(&path.with_extension("node"))?).map_err(io)?;
    let ele_path = path.with_extension("ele");
    let ele = delone_io::read_ele(&read(&ele_path)?, node.first_index)
        .map_err(|e| input_err(format!("{}: {e}", ele_path.display())))?;
    let d = node.dim;
    let mut m = MeditMesh {
        dimension: d as u8,
        points: node
            .coords
            .chunks(d)
            .map(|c| [c[0], c[1], if d == 3 { c[2] } else { 0.0 }])
            .collect(),
        point_refs: node.markers.unwrap_or_default(),
        ..Default::default()
    };
    let k = ele.nodes_per_element;
    if k != d + 1 {
        return Err(input_err(format!(
            "{}: {k} nodes per element (need {})",
            ele_path.display(),
            d + 1
        )));
    }
    let refs = |i: usize| {
        if ele.n_attributes > 0 {
            ele.attributes[i * ele.n_attributes] as i32
        } else {
            0
        }
    };
    for (i, e) in ele.elements.chunks(k).enumerate() {
        if d == 2 {
            m.triangles.push([e[0], e[1], e[2]]);
            m.triangle_refs.push(refs(i));
        } else {
            m.tetrahedra.push([e[0], e[1], e[2], e[3]]);
            m.tetrahedron_refs.push(refs(i));
        }
    }
    Ok((m, Vec::new()))
}

fn tri_mesh(m: &MeditMesh) -> SimplexMesh<2, 3> {
    SimplexMesh {
        points: m.points.iter().map(|p| [p[0], p[1]]).collect(),
        point_refs: m.point_refs.clone(),
        elements: m.triangles.clone(),
        element_refs: m.triangle_refs.clone(),
        faces: m.edges.clone(),
        face_refs: m.edge_refs.clone(),
        corners: m.corners.clone(),
        ridges: Vec::new(),
        required: m.required_vertices.clone(),
    }
}

fn tet_mesh(m: &MeditMesh) -> SimplexMesh<3, 4> {
    SimplexMesh {
        points: m.points.clone(),
        point_refs: m.point_refs.clone(),
        elements: m.tetrahedra.clone(),
        element_refs: m.tetrahedron_refs.clone(),
        faces: m.triangles.clone(),
        face_refs: m.triangle_refs.clone(),
        corners: m.corners.clone(),
        ridges: m
            .ridges
            .iter()
            .filter_map(|&e| m.edges.get(e as usize).copied())
            .collect(),
        required: m.required_vertices.clone(),
    }
}

/// The metric at the vertices: from `--metric` sizes or tensors, or from
/// the `--field` solution's Hessians.
fn metric_of<const D: usize, const K: usize>(
    args: &Args,
    sol: Option<&(MeditSol, &str, PathBuf)>,
    m: &SimplexMesh<D, K>,
) -> Result<Vec<Metric<D>>, Failure> {
    let Some((sol, name, _)) = sol else {
        return Ok(match args.hsiz {
            Some(h) => vec![Metric::isotropic(h); m.points.len()],
            None => {
                let (lo, hi) = (args.options.hmin, args.options.hmax);
                metric_from_mesh(
                    &m.points,
                    &m.elements,
                    lo.unwrap_or(0.0),
                    hi.unwrap_or(f64::INFINITY),
                )
                .map_err(|e| input_err(e.to_string()))?
            }
        });
    };
    let Some(f) = sol.fields.first() else {
        return Err(input_err(format!("{name}: no field")));
    };
    let lib = |e: delone::Error| input_err(format!("{name}: {e}"));
    if args.field.is_some() {
        if f.kind != SolKind::Scalar {
            return Err(input_err(format!(
                "{name}: --field needs a scalar field (type 1), not type {}",
                f.kind.code()
            )));
        }
        let h = hessians(&m.points, &m.elements, &f.values).map_err(lib)?;
        let target = args.target.unwrap_or(Target::Complexity {
            complexity: m.points.len() as f64 * if D == 2 { 3f64.sqrt() / 2.0 } else { 0.77 },
            p: args.p,
        });
        let diag = diagonal(&m.points);
        let hmin = args.options.hmin.unwrap_or(1e-6 * diag);
        let hmax = args.options.hmax.unwrap_or(diag);
        return metric_from_hessians(&m.points, &m.elements, &h, target, hmin, hmax).map_err(lib);
    }
    f.values
        .chunks(f.kind.width(sol.dimension))
        .enumerate()
        .map(|(i, c)| {
            let met = match f.kind {
                SolKind::Scalar if c[0] > 0.0 && c[0].is_finite() => Ok(Metric::isotropic(c[0])),
                SolKind::Scalar => Err(format!("the size {} is not positive and finite", c[0])),
                SolKind::Tensor => Metric::from_medit(c).map_err(|d| d.to_string()),
                SolKind::Vector => Err("is a vector (a metric is type 1 or 3)".into()),
            };
            met.map_err(|e| {
                input_err(format!(
                    "{name}: the metric at vertex {} (1-based) {e}",
                    i + 1
                ))
            })
        })
        .collect()
}

fn diagonal<const D: usize>(p: &[[f64; D]]) -> f64 {
    let mut s = 0.0;
    for k in 0..D {
        let lo = p.iter().map(|x| x[k]).fold(f64::INFINITY, f64::min);
        let hi = p.iter().map(|x| x[k]).fold(f64::NEG_INFINITY, f64::max);
        s += (hi - lo) * (hi - lo);
    }
    s.sqrt()
}

type Adapt<const D: usize, const K: usize> =
    fn(
        &SimplexMesh<D, K>,
        MetricField<'_, D>,
        &AdaptOptions,
    ) -> Result<delone::adapt::Adapted<D, K>, delone::Error>;

/// Adapts (or only measures), writes the mesh, its metric and the reports.
fn finish<const D: usize, const K: usize>(
    args: &Args,
    m: &SimplexMesh<D, K>,
    met: Vec<Metric<D>>,
    output: &Path,
    clock: Instant,
    adapt: Adapt<D, K>,
) -> Result<i32, Failure> {
    let o = &args.options;
    let measure_only = !o.insert && !o.swap && !o.smooth;
    let read_time = clock.elapsed().as_secs_f64();
    let report = if measure_only {
        let s = metric_stats(&m.points, &m.elements, &met);
        AdaptReport {
            before: s.clone(),
            after: s,
            ..Default::default()
        }
    } else {
        let out = adapt(m, MetricField::AtVertices(met), o)
            .map_err(|e| input_err(format!("{}: {e}", args.input.display())))?;
        let t = Instant::now();
        write_mesh(output, &out.mesh, &out.metric)?;
        let mut r = out.report;
        r.phases.push(("write", t.elapsed().as_secs_f64()));
        r
    };
    let mut report = report;
    report.phases.insert(0, ("read", read_time));
    if args.verbose && !args.quiet {
        let mut text = String::new();
        print_report(&mut text, &report, measure_only);
        if let Some(h) = args.hausd {
            let _ = writeln!(
                text,
                "-hausd {h}: met by construction (the boundary is kept exactly: every boundary vertex stays on its input edge or facet, Hausdorff distance 0)"
            );
        }
        // (A closed pipe is not an error of the run.)
        let _ = std::io::Write::write_all(&mut std::io::stdout(), text.as_bytes());
    }
    if let Some(path) = &args.json {
        let text = json(&report);
        std::fs::write(path, text).map_err(|e| input_err(format!("{}: {e}", path.display())))?;
    }
    Ok(0)
}

fn write(
    path: &Path,
    f: impl FnOnce(&mut std::io::BufWriter<std::fs::File>) -> Result<(), delone_io::IoError>,
) -> Result<(), Failure> {
    let file =
        std::fs::File::create(path).map_err(|e| input_err(format!("{}: {e}", path.display())))?;
    let mut w = std::io::BufWriter::new(file);
    f(&mut w).map_err(|e| input_err(format!("{}: {e}", path.display())))
}

/// Writes the mesh and its metric by the extension of `path`: `.vtu` (the
/// metric as point arrays `m11 m12 m22 [m13 m23 m33]`, the elements then
/// the boundary edges (2D) or triangles (3D), their references as cell data
/// `ref`), `.msh` (Gmsh 4.1; references as
/// physical tags) with the metric in the `.sol` next to it, else Medit
/// `.mesh` and `.sol`.
fn write_mesh<const D: usize, const K: usize>(
    path: &Path,
    m: &SimplexMesh<D, K>,
    metric: &[Metric<D>],
) -> Result<(), Failure> {
    let at = |p: &[f64; D]| [p[0], p[1], if D == 3 { p[2] } else { 0.0 }];
    let refs = |r: &Vec<i32>, n: usize| if r.is_empty() { vec![0; n] } else { r.clone() };
    let mut out = MeditMesh {
        dimension: D as u8,
        points: m.points.iter().map(at).collect(),
        point_refs: refs(&m.point_refs, m.points.len()),
        corners: m.corners.clone(),
        required_vertices: m.required.clone(),
        ..Default::default()
    };
    let face_refs = refs(&m.face_refs, m.faces.len());
    let el_refs = refs(&m.element_refs, m.elements.len());
    if D == 2 {
        out.edges = m.faces.iter().map(|f| [f[0], f[1]]).collect();
        out.edge_refs = face_refs;
        out.triangles = m.elements.iter().map(|e| [e[0], e[1], e[2]]).collect();
        out.triangle_refs = el_refs.clone();
    } else {
        out.triangles = m.faces.iter().map(|f| [f[0], f[1], f[2]]).collect();
        out.triangle_refs = face_refs;
        out.tetrahedra = m
            .elements
            .iter()
            .map(|e| [e[0], e[1], e[2], e[3]])
            .collect();
        out.tetrahedron_refs = el_refs.clone();
        for r in &m.ridges {
            out.ridges.push(out.edges.len() as u32);
            out.edges.push(*r);
            out.edge_refs.push(0);
        }
    }
    let ext = path.extension().and_then(|e| e.to_str());
    if ext == Some("vtu") {
        let comps: Vec<Vec<f64>> = (0..SolKind::Tensor.width(D as u8))
            .map(|k| metric.iter().map(|x| x.medit()[k]).collect())
            .collect();
        let names = ["m11", "m12", "m22", "m13", "m23", "m33"];
        let data: Vec<DataArray> = comps
            .iter()
            .zip(names)
            .map(|(c, name)| DataArray {
                name,
                values: Values::Float64(c),
            })
            .collect();
        // One reference per element, then per boundary face.
        let face_refs = if D == 2 {
            &out.edge_refs
        } else {
            &out.triangle_refs
        };
        let all_refs: Vec<i32> = el_refs.iter().chain(face_refs).copied().collect();
        let refs = [DataArray {
            name: "ref",
            values: Values::Int32(&all_refs),
        }];
        let f = VtuFormat::Binary;
        return write(path, |w| {
            if D == 2 {
                delone_io::write_vtu_with_faces(
                    w,
                    &out.points,
                    &out.triangles,
                    &out.edges,
                    &data,
                    &refs,
                    f,
                )
            } else {
                let (tets, tris) = (&out.tetrahedra, &out.triangles);
                delone_io::write_vtu_with_faces(w, &out.points, tets, tris, &data, &refs, f)
            }
        });
    }
    if ext == Some("msh") {
        write(path, |w| {
            if D == 2 {
                let (e, r) = (&out.edges, &out.edge_refs);
                delone_io::write_gmsh_2d(w, &out.points, &out.triangles, &el_refs, e, r)
            } else {
                let (t, r) = (&out.triangles, &out.triangle_refs);
                delone_io::write_gmsh(w, &out.points, t, r, &out.tetrahedra, &el_refs)
            }
        })?;
    } else {
        write(path, |w| delone_io::write_medit_mesh(w, &out))?;
    }
    let sol = MeditSol {
        dimension: D as u8,
        vertices: metric.len(),
        fields: vec![SolField {
            kind: SolKind::Tensor,
            values: metric.iter().flat_map(|x| x.medit()).collect(),
        }],
    };
    write(&path.with_extension("sol"), |w| {
        delone_io::write_medit_sol(w, &sol)
    })
}

fn print_stats(out: &mut String, label: &str, s: &MetricStats) {
    let _ = writeln!(
        out,
        "{label}: {} vertices, {} elements, {} edges; length min {:.3} mean {:.3} max {:.3}; {:.1}% in [1/sqrt2, sqrt2]; quality min {:.3} mean {:.3}",
        s.vertices,
        s.elements,
        s.edges,
        s.length_min,
        s.length_mean,
        s.length_max,
        100.0 * s.in_range_share(),
        s.quality_min,
        s.quality_mean
    );
    let mut lo = 0.0;
    let bins: Vec<String> = s
        .length_histogram
        .iter()
        .enumerate()
        .map(|(k, n)| {
            let hi = LENGTH_BINS
                .get(k)
                .map_or("inf".to_string(), |x| format!("{x:.2}"));
            let b = format!("[{lo:.2},{hi}) {n}");
            lo = LENGTH_BINS.get(k).copied().unwrap_or(0.0);
            b
        })
        .collect();
    let _ = writeln!(out, "  lengths: {}", bins.join("  "));
    let q: Vec<String> = s
        .quality_histogram
        .iter()
        .enumerate()
        .map(|(k, n)| format!("{:.1}:{n}", k as f64 / 10.0))
        .collect();
    let _ = writeln!(out, "  quality: {}", q.join("  "));
}

fn print_report(out: &mut String, r: &AdaptReport, measure_only: bool) {
    if measure_only {
        print_stats(out, "mesh", &r.after);
    } else {
        print_stats(out, "before", &r.before);
        print_stats(out, "after", &r.after);
        let _ = writeln!(
            out,
            "passes {}, splits {}, collapses {}, swaps {}, moves {}{}",
            r.passes,
            r.splits,
            r.collapses,
            r.swaps,
            r.moves,
            if r.budget_reached {
                " (vertex budget reached)"
            } else {
                ""
            }
        );
    }
    let t: Vec<String> = r
        .phases
        .iter()
        .map(|(n, s)| format!("{n} {s:.3}s"))
        .collect();
    let _ = writeln!(out, "time: {}", t.join(", "));
}

fn json_stats(s: &MetricStats) -> String {
    let list = |v: &[usize]| {
        v.iter()
            .map(|x| x.to_string())
            .collect::<Vec<_>>()
            .join(", ")
    };
    format!(
        "{{\"vertices\": {}, \"elements\": {}, \"edges\": {}, \"length_min\": {}, \"length_mean\": {}, \"length_max\": {}, \"in_range\": {}, \"in_range_share\": {}, \"length_histogram\": [{}], \"quality_min\": {}, \"quality_mean\": {}, \"quality_histogram\": [{}]}}",
        s.vertices,
        s.elements,
        s.edges,
        s.length_min,
        s.length_mean,
        s.length_max,
        s.in_range,
        s.in_range_share(),
        list(&s.length_histogram),
        s.quality_min,
        s.quality_mean,
        list(&s.quality_histogram)
    )
}

fn json(r: &AdaptReport) -> String {
    let phases: Vec<String> = r
        .phases
        .iter()
        .map(|(n, s)| format!("\"{n}\": {s}"))
        .collect();
    format!(
        "{{\"before\": {}, \"after\": {}, \"passes\": {}, \"splits\": {}, \"collapses\": {}, \"swaps\": {}, \"moves\": {}, \"budget_reached\": {}, \"phases\": {{{}}}}}\n",
        json_stats(&r.before),
        json_stats(&r.after),
        r.passes,
        r.splits,
        r.collapses,
        r.swaps,
        r.moves,
        r.budget_reached,
        phases.join(", ")
    )
}
