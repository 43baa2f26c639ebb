//! `delone tet -r` (refine an existing mesh FILE.node + FILE.ele, with
//! FILE.face markers when present) and the sizing files of `-m`:
//!
//! * `FILE.b.node` + `FILE.b.ele` + `FILE.b.mtr`: a background mesh with a
//!   size at each of its points (tried first);
//! * else `FILE.mtr`: a size per input point — with `-p` interpolated over
//!   the Delaunay tetrahedralization of the input points, with `-r` over the
//!   input mesh itself.
//!
//! `.mtr`: header `<#points> <#sizes per point>`, then one size per point
//! (the first value of each record); sizes ≤ 0 mean "no constraint".

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use delone::tet::pipeline::optimize_stage;
use delone::tet::recover::check_recovered;
use delone::tet::refine::existing::refine_mesh;
use delone::tet::refine::sizing::{Background, Sizing};
use delone::tet::refine::RefineOptions;
use delone::NONE;

use crate::args::Opts;
use crate::fail::{input_err, usage_err, Failure};
use crate::guard::write;
use crate::paths::with_ext;

fn read_file(p: &Path) -> Result<Vec<u8>, String> {
    crate::guard::read(p).map_err(|e| format!("cannot read {}: {e}", p.display()))
}

fn io_err(p: &Path) -> impl Fn(delone_io::IoError) -> String + '_ {
    move |e| format!("{}: {e}", p.display())
}

/// Points and tetrahedra (first 4 nodes of each element) of `base.node` +
/// `base.ele`, the first element attribute of each tetrahedron (empty when
/// none) and the numbering of the `.node` file.
#[allow(clippy::type_complexity)]
fn read_mesh(base: &Path) -> Result<(Vec<[f64; 3]>, Vec<[u32; 4]>, Vec<f64>, u32), String> {
    let np = with_ext(base, "node");
    let node = delone_io::read_node(&read_file(&np)?).map_err(io_err(&np))?;
    let points = node
        .points::<3>()
        .ok_or_else(|| format!("{}: not a 3D .node file", np.display()))?;
    let ep = with_ext(base, "ele");
    let ele = delone_io::read_ele(&read_file(&ep)?, node.first_index).map_err(io_err(&ep))?;
    let k = ele.nodes_per_element;
    if k < 4 {
        return Err(format!(
            "{}: {k} nodes per element, tetrahedra need 4",
            ep.display()
        ));
    }
    let tets: Vec<[u32; 4]> = ele
        .elements
        .chunks_exact(k)
        .map(|c| [c[0], c[1], c[2], c[3]])
        .collect();
    let attributes = if ele.n_attributes > 0 {
        ele.attributes
            .chunks_exact(ele.n_attributes)
            .map(|c| c[0])
            .collect()
    } else {
        Vec::new()
    };
    Ok((points, tets, attributes, node.first_index))
}

fn read_sizes(p: &Path) -> Result<Vec<f64>, String> {
    delone_io::read_mtr(&read_file(p)?).map_err(io_err(p))
}

/// The sizing of `-m` for input base `base` (see the module docs); `mesh`:
/// the input mesh's points and tetrahedra (`-r`), else the input points
/// (`-p`, tetrahedra empty).
pub fn load_sizing(base: &Path, points: &[[f64; 3]], tets: &[[u32; 4]]) -> Result<Sizing, String> {
    let bbase = with_ext(base, "b");
    let (bnode, bele) = (with_ext(&bbase, "node"), with_ext(&bbase, "ele"));
    let bg = if bnode.is_file() && bele.is_file() {
        let (bp, bt, _, _) = read_mesh(&bbase)?;
        let sizes = read_sizes(&with_ext(&bbase, "mtr"))?;
        Background::new(bp, bt, sizes).map_err(|e| format!("{}: {e}", bbase.display()))?
    } else {
        let mp = with_ext(base, "mtr");
        if !mp.is_file() {
            return Err(format!(
                "-m: neither {} nor {} + {} exists",
                mp.display(),
                bnode.display(),
                bele.display()
            ));
        }
        let sizes = read_sizes(&mp)?;
        if sizes.len() != points.len() {
            return Err(format!(
                "{}: {} sizes for {} input points",
                mp.display(),
                sizes.len(),
                points.len()
            ));
        }
        let r = if tets.is_empty() {
            Background::from_points(points.to_vec(), sizes)
        } else {
            Background::new(points.to_vec(), tets.to_vec(), sizes)
        };
        r.map_err(|e| format!("{}: {e}", mp.display()))?
    };
    Ok(Sizing::Background(Arc::new(bg)))
}

/// `-m` with `-p`: the sizing for the PLC/surface input `o.input`.
pub fn plc_sizing(o: &Opts, points: &[[f64; 3]]) -> Result<Sizing, String> {
    if !o.tet.sizing {
        return Ok(Sizing::None);
    }
    const EXT: [&str; 8] = ["poly", "smesh", "off", "stl", "ply", "obj", "mesh", "node"];
    let known = o
        .input
        .extension()
        .is_some_and(|e| EXT.contains(&e.to_string_lossy().to_ascii_lowercase().as_str()));
    let base: PathBuf = if known {
        o.input.with_extension("")
    } else {
        o.input.clone()
    };
    load_sizing(&base, points, &[])
}

/// Runs `delone tet -r`.
pub fn run(o: &Opts) -> Result<i32, Failure> {
    let t_all = Instant::now();
    let names = crate::paths::names(&o.input, o.out().no_iteration, o.output_dir.as_deref())?;
    let node_s = names.node.to_string_lossy();
    let base = PathBuf::from(node_s.strip_suffix(".node").unwrap_or(&node_s));
    let out = names.out_base;
    crate::guard::plan(crate::args::Mode::Tet, crate::guard::Kind::Refine, o, &out);
    let (points, tets, attributes, first_in) = read_mesh(&base).map_err(input_err)?;
    let fp = with_ext(&base, "face");
    let (faces, markers) = if fp.is_file() {
        let f = delone_io::read_face(&read_file(&fp).map_err(input_err)?, first_in)
            .map_err(|e| input_err(io_err(&fp)(e)))?;
        (f.faces, f.markers)
    } else {
        (Vec::new(), None)
    };
    let sizing = if o.tet.sizing {
        load_sizing(&base, &points, &tets).map_err(input_err)?
    } else {
        Sizing::None
    };
    crate::guard::check()?;
    o.tet.check_bounds().map_err(|e| usage_err(e.to_string()))?;
    let t_read = t_all.elapsed();
    let t1 = Instant::now();
    let opts = RefineOptions {
        max_radius_edge: o.tet.max_radius_edge,
        max_volume: o.max_area(),
        max_steiner: o.max_steiner(),
        sizing,
        ..RefineOptions::default()
    };
    let name = base.display();
    let r = refine_mesh(&points, &tets, &attributes, &faces, &opts)
        .map_err(|e| input_err(format!("{name}: {e}")))?;
    let mut rec = r.refined.rec;
    let report = r.refined.report;
    let optimized = optimize_stage(&o.tet, points.len(), &mut rec, Some(&opts))
        .map_err(|e| input_err(format!("{name}: {e}")))?;
    let t_mesh = t1.elapsed();
    // Markers: a listed face's, else 1 (boundary and region interfaces).
    let tri_marker: Vec<i32> = r
        .listed
        .iter()
        .map(|&l| match (&markers, l) {
            (Some(m), l) if l != NONE => m.get(l as usize).copied().unwrap_or(1),
            _ => 1,
        })
        .collect();
    let mut lines =
        crate::tetq::report(o, &rec, Some(&report), optimized.as_ref()).map_err(input_err)?;
    if let Some(x) = &optimized {
        lines.extend(crate::tetq::optimize_lines(o, x));
    }
    let (bound_code, bound_msg) = crate::tetq::bound_status(o, &rec, &report, optimized.as_ref());
    let code = crate::tetq::check_and_prepare(
        o,
        || check_recovered(&points, &r.triangles, &rec),
        "every boundary/interface face of the input mesh is a union of mesh faces",
        &mut lines,
    )?;
    let first = if o.out().zero { 0 } else { first_in };
    let mut written = Vec::new();
    if !o.out().no_node {
        let p = with_ext(&out, "node");
        write(&p, |f| {
            delone_io::write_node(f, &rec.points, &[], 0, None, first)
        })?;
        written.push(p);
    }
    let mut oo = o.clone();
    oo.tet.region_attributes |= !attributes.is_empty();
    let marked = delone::tet::pipeline::marked_faces(&rec, &tri_marker);
    let out_mesh = crate::tetout::TetOutput::new(&rec, &tri_marker, marked);
    written.extend(out_mesh.write_all(&oo, &out, first)?);
    if !o.out().quiet {
        println!(
            "delone tet -r: {name} ({} points, {} tetrahedra, {} constraint faces)",
            points.len(),
            tets.len(),
            r.triangles.len()
        );
        println!(
            "  tetrahedra: {}   boundary faces: {}   points: {}",
            rec.mesh.tets.len(),
            rec.boundary.len(),
            rec.points.len()
        );
        if report.remaining_too_big > 0 {
            println!(
                "  {} tetrahedra left above the size (-m)",
                report.remaining_too_big
            );
        }
    }
    crate::tetq::print_tail(
        o.out().quiet,
        &lines,
        || {
            format!(
                "time: read {:.3} s, refine {:.3} s, total {:.3} s",
                t_read.as_secs_f64(),
                t_mesh.as_secs_f64(),
                t_all.elapsed().as_secs_f64()
            )
        },
        &written,
    );
    if let Some(m) = bound_msg {
        eprintln!("delone: {m}");
    }
    Ok(crate::pslg::combine(code, bound_code))
}
