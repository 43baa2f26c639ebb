//! `delone tri -r`: refine an existing mesh (FILE.node + FILE.ele, segments
//! from FILE.poly if present, per-triangle area bounds from FILE.area with
//! `-a` and no number), writing FILE.<n+1>.{node,ele,poly}.

use std::path::{Path, PathBuf};
use std::time::Instant;

use delone::model::pslg::Pslg;
use delone::tri::constrain::{check_cdt, Cdt};
use delone::tri::existing::ExistingMesh;
use delone::tri::refine::{refine, RefineOptions};

use crate::args::Opts;
use crate::fail::{input_err, Failure};

fn read(path: &Path) -> Result<Vec<u8>, Failure> {
    crate::guard::read(path).map_err(|e| input_err(format!("cannot read {}: {e}", path.display())))
}

fn write(
    path: &Path,
    f: impl FnOnce(std::fs::File) -> Result<(), delone_io::IoError>,
) -> Result<(), Failure> {
    let file = crate::guard::create(path)?;
    f(file).map_err(|e| input_err(format!("{}: {e}", path.display())))
}

/// `mesh.1`, `mesh.1.node` or `mesh.1.ele` → (`mesh.1`, `mesh.2`).
fn names(o: &Opts) -> (String, PathBuf) {
    let s = o.input.to_string_lossy().to_string();
    let base = [".node", ".ele", ".poly", ".area"]
        .iter()
        .find_map(|x| s.strip_suffix(x))
        .unwrap_or(&s)
        .to_string();
    let out = crate::paths::output_base(&base, o.out().no_iteration, o.output_dir.as_deref());
    (base, out)
}

/// Runs `delone tri -r`. Returns the exit code (1 when `-C` finds a violation).
pub fn run(o: &Opts) -> Result<i32, Failure> {
    let t_all = Instant::now();
    let (base, out) = names(o);
    crate::guard::plan(crate::args::Mode::Tri, crate::guard::Kind::Refine, o, &out);
    let p = |ext: &str| PathBuf::from(format!("{base}.{ext}"));
    let node_path = p("node");
    let node = delone_io::read_node(&read(&node_path)?)
        .map_err(|e| input_err(format!("{}: {e}", node_path.display())))?;
    let Some(points) = node.points::<2>() else {
        return Err(input_err(format!(
            "{}: the points are not 2D",
            node_path.display()
        )));
    };
    let ele_path = p("ele");
    let ele = delone_io::read_ele(&read(&ele_path)?, node.first_index)
        .map_err(|e| input_err(format!("{}: {e}", ele_path.display())))?;
    if ele.nodes_per_element != 3 {
        return Err(input_err(format!(
            "{}: {} nodes per element (-r refines 3-node triangles)",
            ele_path.display(),
            ele.nodes_per_element
        )));
    }
    let triangles: Vec<[u32; 3]> = ele
        .elements
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    let attributes: Vec<f64> = if ele.n_attributes > 0 {
        ele.attributes
            .chunks_exact(ele.n_attributes)
            .map(|a| a[0])
            .collect()
    } else {
        Vec::new()
    };
    let poly_path = p("poly");
    let (segments, segment_markers, holes) = if poly_path.exists() {
        let poly = delone_io::read_poly(&read(&poly_path)?)
            .map_err(|e| input_err(format!("{}: {e}", poly_path.display())))?;
        let segs = poly
            .segments_zero_based(node.first_index)
            .map_err(|e| input_err(format!("{}: {e}", poly_path.display())))?;
        (
            segs,
            poly.segment_markers.clone().unwrap_or_default(),
            poly.holes.clone(),
        )
    } else {
        (Vec::new(), Vec::new(), Vec::new())
    };
    let max_areas = if o.area() && o.max_area().is_none() {
        let area_path = p("area");
        let a = delone_io::read_area(&read(&area_path)?)
            .map_err(|e| input_err(format!("{}: {e}", area_path.display())))?;
        if a.len() != triangles.len() {
            return Err(input_err(format!(
                "{}: {} area bounds for {} triangles",
                area_path.display(),
                a.len(),
                triangles.len()
            )));
        }
        a
    } else {
        Vec::new()
    };
    crate::guard::check()?;
    let t_read = t_all.elapsed();
    let t1 = Instant::now();
    let n_in = points.len();
    let cdt = Cdt::from_mesh(ExistingMesh {
        points: points.clone(),
        triangles,
        segments: segments.clone(),
        segment_markers: segment_markers.clone(),
        attributes: attributes.clone(),
        max_areas,
    })
    .map_err(|e| {
        let e = crate::numbering::renumber(e, node.first_index);
        input_err(format!("{}: {e}", ele_path.display()))
    })?;
    let r = refine(
        &cdt,
        &RefineOptions {
            min_angle: o.tri.min_angle,
            max_area: o.max_area(),
            regional_areas: o.area(),
            max_steiner: o.max_steiner(),
            off_centers: true,
            segment_splits: o.tri.segment_splits,
            conforming_delaunay: o.tri.conforming_delaunay,
            threads: crate::threads::effective(o.tri.threads),
            ..RefineOptions::default()
        },
    )
    .map_err(|e| crate::pslg::refine_err(&base, e))?;
    let t_refine = t1.elapsed();
    let m = &r.mesh;
    let mut code = 0;
    let mut lines = Vec::new();
    if o.out().check {
        let mut g = Pslg::new(points, segments);
        g.segment_markers = segment_markers;
        match check_cdt(&g, m) {
            Ok(()) => lines.push("check: constrained Delaunay triangulation is valid".to_string()),
            Err(v) => {
                lines.push(format!("check FAILED: {v}"));
                code = 1;
            }
        }
    }
    code = code.max(crate::pslg::check_conforming(
        o,
        &m.points,
        &m.triangles,
        &mut lines,
    ));
    let (bound_code, bound_msg) = crate::pslg::bound_status(o, &r.report);
    code = crate::pslg::combine(code, bound_code);
    if let Some(dir) = &o.output_dir {
        std::fs::create_dir_all(dir)
            .map_err(|e| input_err(format!("cannot create directory {}: {e}", dir.display())))?;
    }
    let first = if o.out().zero { 0 } else { node.first_index };
    let mut markers: Vec<i32> = (0..m.points.len())
        .map(|i| {
            node.markers
                .as_ref()
                .and_then(|v| v.get(i).copied())
                .unwrap_or(0)
        })
        .collect();
    let bounding: Vec<_> = m.segments.iter().filter(|s| s.bounding).collect();
    for s in &bounding {
        for &v in &s.v {
            if v as usize >= n_in && markers[v as usize] == 0 {
                markers[v as usize] = s.marker;
            }
        }
    }
    let with_ext = |ext: &str| PathBuf::from(format!("{}.{ext}", out.display()));
    if !o.out().no_node {
        write(&with_ext("node"), |f| {
            delone_io::write_node(
                f,
                &m.points,
                &[],
                0,
                (!o.out().no_bound).then_some(&markers[..]),
                first,
            )
        })?;
    }
    if !o.out().no_ele {
        let na = usize::from(!attributes.is_empty());
        let attrs = if na == 1 {
            m.attributes.clone()
        } else {
            Vec::new()
        };
        write(&with_ext("ele"), |f| {
            delone_io::write_ele(f, &m.triangles, &attrs, na, first)
        })?;
    }
    if !o.tri.no_poly {
        let segs: Vec<[u32; 2]> = bounding.iter().map(|s| s.v).collect();
        let sm: Vec<i32> = bounding.iter().map(|s| s.marker).collect();
        write(&with_ext("poly"), |f| {
            delone_io::write_poly(
                f,
                &[],
                &segs,
                (!o.out().no_bound).then_some(&sm[..]),
                &holes,
                &[],
                first,
            )
        })?;
    }
    if !o.out().quiet {
        println!(
            "delone tri -r: {base} ({} vertices, {} triangles, {} segments)",
            cdt.points.len(),
            cdt.triangles.len(),
            segments_len(&cdt)
        );
        println!(
            "  {} vertices, {} triangles; {} Steiner points; minimum angle {:.4}, maximum angle {:.4}; bounds {}",
            m.points.len(),
            m.triangles.len(),
            m.points.len() - n_in,
            r.report.min_angle,
            r.report.max_angle,
            if r.report.met { "met" } else { "NOT met" }
        );
        if let Some(l) = crate::pslg::conforming_line(o, &r.report) {
            println!("{l}");
        }
        if o.out().verbose > 0 {
            println!(
                "  read {:.3} s, refine {:.3} s",
                t_read.as_secs_f64(),
                t_refine.as_secs_f64()
            );
        }
        for l in &lines {
            println!("  {l}");
        }
        println!("  output: {}.{{node,ele,poly}}", out.display());
    } else if code != 0 {
        for l in &lines {
            eprintln!("{l}");
        }
    }
    if let Some(m) = bound_msg {
        eprintln!("delone: {m}");
    }
    Ok(code)
}

fn segments_len(c: &Cdt) -> usize {
    c.segments.len()
}
