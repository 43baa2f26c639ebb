//! `delone tet -p`: tetrahedral mesh of the inside of a closed PLC or
//! surface mesh (TetGen `.poly`/`.smesh`, OFF, STL, PLY, OBJ, Medit
//! `.mesh`), by conforming boundary recovery.

use std::path::{Path, PathBuf};
use std::time::Instant;

use delone::model::plc::{Facet, Plc, Region};
use delone::tet::recover::check_recovered;
use delone::tet::{TetError, TetOptions, TetResult};

use crate::args::Opts;
use crate::fail::{input_err, usage_err, Failure};
use crate::guard::write;
use crate::paths::with_ext;

const EXTENSIONS: [&str; 8] = ["poly", "smesh", "off", "stl", "ply", "obj", "mesh", "node"];

/// The input file (`FILE.ext`, or `FILE` with `.poly` / `.smesh` tried as
/// TetGen does), its extension, and the output base (`FILE.1`, or `FILE`
/// with `-I`).
fn names(o: &Opts) -> Result<(PathBuf, String, PathBuf), Failure> {
    let given = o.input.clone();
    let ext = given
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .filter(|e| EXTENSIONS.contains(&e.as_str()));
    let (path, ext, base) = match ext {
        Some(e) => {
            let base = given.with_extension("");
            (given, e, base)
        }
        None => {
            let found = ["poly", "smesh"]
                .into_iter()
                .map(|e| (with_ext(&given, e), e))
                .find(|(p, _)| p.is_file())
                .ok_or_else(|| {
                    input_err(format!(
                        "cannot find {}.poly or {}.smesh",
                        given.display(),
                        given.display()
                    ))
                })?;
            (found.0, found.1.to_string(), given)
        }
    };
    if ext == "node" {
        return Err(Failure {
            message: "delone tet -p needs a PLC or surface file (.poly, .smesh, .off, .stl, .ply, .obj, .mesh)".into(),
            code: 2,
        });
    }
    let mut out = if o.out().no_iteration {
        base
    } else {
        with_ext(&base, "1")
    };
    if let Some(dir) = &o.output_dir {
        if let Some(f) = out.file_name() {
            out = dir.join(f);
        }
    }
    Ok((path, ext, out))
}

/// Reads the input as a PLC (TetGen formats) or a surface (the others),
/// with the marker of each facet.
fn read(path: &Path, ext: &str) -> Result<(Plc, u32), Failure> {
    let bytes = crate::guard::read(path)
        .map_err(|e| input_err(format!("cannot read {}: {e}", path.display())))?;
    let err = |e: delone_io::IoError| input_err(format!("{}: {e}", path.display()));
    match ext {
        "poly" | "smesh" => {
            let f = if ext == "poly" {
                delone_io::read_poly3d(&bytes).map_err(err)?
            } else {
                delone_io::read_smesh(&bytes).map_err(err)?
            };
            let mut plc = Plc::new(f.points);
            plc.holes = f.holes;
            plc.regions = f
                .regions
                .into_iter()
                .map(|r| Region {
                    point: r.point,
                    attribute: r.attribute,
                    max_volume: r.max_volume,
                })
                .collect();
            for facet in f.facets {
                plc.facets.push(Facet {
                    polygons: facet.polygons,
                    holes: facet.holes,
                    marker: facet.marker,
                });
            }
            Ok((plc, f.first_index))
        }
        _ => {
            let mut s = delone_io::read_surface(&bytes, ext).map_err(err)?;
            s.merge_exact_duplicates();
            let mut plc = Plc::new(s.points);
            for face in s.faces {
                let mut f = Facet::polygon(face);
                f.marker = 1;
                plc.facets.push(f);
            }
            Ok((plc, 1))
        }
    }
}

/// The input of `delone tet -p` / `-d`, read.
pub(crate) struct Input {
    /// The input file, its extension and the output base.
    pub path: PathBuf,
    pub ext: String,
    pub out: PathBuf,
    /// The complex, and the first index of its file (for the output).
    pub plc: Plc,
    pub first: u32,
    /// The first index of the file's own numbering of points and facets,
    /// used in messages: the first index of a `.poly`/`.smesh`, 1 for a
    /// Medit `.mesh`, 0 for OFF, STL, PLY and OBJ.
    pub msg_first: u32,
}

/// Reads the input named by `o` (not yet validated).
pub(crate) fn read_input(o: &Opts) -> Result<Input, Failure> {
    let (path, ext, out) = names(o)?;
    let (plc, first) = read(&path, &ext)?;
    let msg_first = match ext.as_str() {
        "poly" | "smesh" => first,
        "mesh" => 1,
        _ => 0,
    };
    Ok(Input {
        path,
        ext,
        out,
        plc,
        first,
        msg_first,
    })
}

/// The facets of a PLC triangulated (triangles and each one's facet).
pub(crate) type Triangulated = (Vec<[u32; 3]>, Vec<u32>);

/// Facets set aside: 0-based input facet index and defect.
pub(crate) type Defects = Vec<(usize, delone::FacetDefect)>;

/// Reads the input named by `o`, validates it and triangulates its facets
/// for `-d`: degenerate facets are set aside and returned (0-based input
/// facet index and defect) instead of failing, and the facet of each
/// triangle names the input facets; other errors name the file and the
/// offending item in the file's numbering.
pub(crate) fn load_lenient(o: &Opts) -> Result<(Input, Triangulated, Defects), Failure> {
    let mut input = read_input(o)?;
    let plc = &mut input.plc;
    let name = input.path.display().to_string();
    // Input facet index of each facet still in `plc`.
    let mut keep: Vec<u32> = (0..plc.facets.len() as u32).collect();
    let mut defects = Vec::new();
    let (triangles, owner) = loop {
        match plc.validate().and_then(|()| plc.triangulate_facets()) {
            Ok(t) => break t,
            Err(delone::Error::DegenerateFacet { index, defect }) if index < plc.facets.len() => {
                defects.push((keep[index] as usize, defect));
                plc.facets.remove(index);
                keep.remove(index);
            }
            Err(e) => {
                let e = crate::numbering::renumber(e, input.msg_first);
                return Err(input_err(format!("{name}: {e}")));
            }
        }
    };
    let facet_of = owner.iter().map(|&f| keep[f as usize]).collect();
    Ok((input, (triangles, facet_of), defects))
}

/// Why carving left no tetrahedron: the holes, numbered from `msg_first`.
fn why_empty(plc: &Plc, msg_first: u32) -> String {
    let holes: Vec<String> = plc
        .holes
        .iter()
        .enumerate()
        .map(|(k, h)| {
            format!(
                "hole {} at ({}, {}, {})",
                k as u32 + msg_first,
                h[0],
                h[1],
                h[2]
            )
        })
        .collect();
    format!(
        "no tetrahedron left after carving{}",
        if holes.is_empty() {
            String::new()
        } else {
            format!(
                ": {} removed every tetrahedron it reached (a hole point in the only region, on a facet or outside the surface removes the whole domain)",
                holes.join(", ")
            )
        }
    )
}

/// Runs `delone tet -p`. Returns the exit code (1 when `-C` finds a
/// violation).
pub fn run(o: &Opts) -> Result<i32, Failure> {
    let t_all = Instant::now();
    let Input {
        path,
        out,
        plc,
        first: first_in,
        msg_first,
        ..
    } = read_input(o)?;
    crate::guard::plan(crate::args::Mode::Tet, crate::guard::Kind::Domain, o, &out);
    crate::guard::check()?;
    let name = path.display();
    let opts = TetOptions {
        size_field: if o.tet.sizing {
            Some(
                crate::tetr::plc_sizing(o, &plc.points)
                    .map_err(|e| input_err(format!("{name}: {e}")))?,
            )
        } else {
            None
        },
        ..o.tet.clone()
    };
    let t_read = t_all.elapsed();
    let t1 = Instant::now();
    let result = delone::tet::mesh(&plc, &opts).map_err(|e| match e {
        TetError::Input(e) => input_err(format!(
            "{name}: {}",
            crate::numbering::renumber(e, msg_first)
        )),
        TetError::Bound(e) => usage_err(e.to_string()),
        TetError::Empty { .. } => input_err(format!("{name}: {}", why_empty(&plc, msg_first))),
        e => input_err(format!("{name}: {e}")),
    })?;
    let TetResult {
        mesh: rec,
        triangles,
        triangle_markers: facet_marker,
        faces,
        face_markers,
        face_triangles,
        refine: refined,
        optimize: optimized,
        optimize_time: t_opt,
        ..
    } = result;
    let t_mesh = t1.elapsed();
    let mut code = 0;
    let mut lines =
        crate::tetq::report(o, &rec, refined.as_ref(), optimized.as_ref()).map_err(input_err)?;
    if let Some(r) = &optimized {
        lines.extend(crate::tetq::optimize_lines(o, r));
        lines.push(format!(
            "optimization: {:.3} s of the {:.3} s of meshing",
            t_opt.as_secs_f64(),
            t_mesh.as_secs_f64()
        ));
    }
    code |= crate::tetq::check_and_prepare(
        o,
        || check_recovered(&plc.points, &triangles, &rec),
        "every input facet is a union of mesh faces",
        &mut lines,
    )?;
    let (bound_code, bound_msg) = refined.as_ref().map_or((0, None), |r| {
        crate::tetq::bound_status(o, &rec, r, optimized.as_ref())
    });
    code = crate::pslg::combine(code, bound_code);
    let t2 = Instant::now();
    let first = if o.out().zero { 0 } else { first_in };
    let mut written = Vec::new();
    if !o.out().no_node {
        let p = with_ext(&out, "node");
        write(&p, |f| {
            delone_io::write_node(f, &rec.points, &[], 0, None, first)
        })?;
        written.push(p);
    }
    let out_mesh =
        crate::tetout::TetOutput::new(&rec, &facet_marker, (faces, face_markers, face_triangles));
    written.extend(out_mesh.write_all(o, &out, first)?);
    let t_write = t2.elapsed();
    if !o.out().quiet {
        let r = &rec.report;
        println!(
            "delone tet -p: {name} ({} points, {} facets)",
            plc.points.len(),
            plc.facets.len()
        );
        println!(
            "  tetrahedra: {}   boundary faces: {}   Steiner points: {} (on edges {}, on facets {}, interior {})",
            rec.mesh.tets.len(),
            rec.boundary.len(),
            r.steiner(),
            r.steiner_on_edges,
            r.steiner_on_facets,
            r.steiner_interior
        );
        if o.out().verbose > 0 {
            println!(
                "  regions: {}   holes: {} point(s), {} region(s) removed   hull tetrahedra before carving: {}",
                rec.regions.len(),
                plc.holes.len(),
                r.holes_removed,
                r.hull_tets
            );
            // Edges in more than two facets (each in an even number, or
            // recovery would have refused the surface as open): the facets
            // bound several closed parts, touching solids or parts split
            // by internal walls, each meshed as a region of its own.
            let man = delone::tet::intersect::manifold_report(&triangles);
            if let Some(&[a, b]) = man.nonmanifold_edges.first() {
                println!(
                    "  non-manifold surface: {} edge(s) in more than two facets (first: points {a}-{b}); the facets bound several closed parts (touching solids or internal walls), each meshed as its own region",
                    man.nonmanifold_edges.len()
                );
            }
            for (i, g) in rec.regions.iter().enumerate() {
                println!(
                    "    region {i}: attribute {}, {} tetrahedra, volume {:e}{}{}",
                    g.attribute,
                    g.tets,
                    g.volume,
                    g.seed
                        .map_or(String::new(), |s| format!(", region point {s}")),
                    if g.exterior {
                        ", outside the surface (-c)"
                    } else {
                        ""
                    }
                );
            }
            println!(
                "  recovery: {} rounds, {} 2-3 flips, {} edge removals{}",
                r.rounds,
                r.flips23,
                r.edge_removals,
                if r.unguided_rounds > 0 {
                    format!(
                        " (guided flips; the unguided ones gave up after {} rounds)",
                        r.unguided_rounds
                    )
                } else {
                    String::new()
                }
            );
            println!(
                "  coplanar facets: {} group(s) merged and re-triangulated, {} kept as given (-M: no merging)",
                r.coplanar_groups, r.coplanar_kept
            );
        }
        if r.inexact_steiner > 0 {
            println!(
                "  {} Steiner point(s) rounded off their edge/facet (largest deviation {:e}); {} flat cell(s) under a chord removed",
                r.inexact_steiner, r.max_deviation, r.chord_slivers
            );
        }
    }
    crate::tetq::print_tail(
        o.out().quiet,
        &lines,
        || {
            format!(
                "time: read {:.3} s, recover {:.3} s, write {:.3} s, total {:.3} s",
                t_read.as_secs_f64(),
                t_mesh.as_secs_f64(),
                t_write.as_secs_f64(),
                t_all.elapsed().as_secs_f64()
            )
        },
        &written,
    );
    if let Some(m) = bound_msg {
        eprintln!("delone: {m}");
    }
    Ok(code)
}
