//! Command-line parsing: Triangle/TetGen letter switches plus long options.

use std::path::PathBuf;

/// Which program the subcommand stands in for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// `delone tri`: Triangle's switches, 2D.
    Tri,
    /// `delone tet`: TetGen's switches, 3D.
    Tet,
}

impl Mode {
    pub fn name(self) -> &'static str {
        match self {
            Mode::Tri => "tri",
            Mode::Tet => "tet",
        }
    }
}

/// Everything a run needs to know.
#[derive(Debug, Clone, Default)]
pub struct Opts {
    pub zero: bool,
    pub quiet: bool,
    pub verbose: u8,
    pub check: bool,
    pub edges: bool,
    pub neigh: bool,
    pub all_faces: bool,
    pub no_node: bool,
    pub no_ele: bool,
    /// tet `-F`: no .face / .edge.
    pub no_face: bool,
    /// tri `-F`: Fortune's sweepline requested (accepted, not used).
    pub fortune: bool,
    pub no_iteration: bool,
    pub no_bound: bool,
    pub vtk_legacy: bool,
    pub vtu: Option<PathBuf>,
    pub vtu_ascii: bool,
    pub output_dir: Option<PathBuf>,
    pub input: PathBuf,
    /// tri `-p`: read a PSLG (.poly) and build its constrained Delaunay triangulation.
    pub pslg: bool,
    /// tri `-r`: refine an existing mesh (FILE.node + FILE.ele).
    pub refine_mesh: bool,
    /// tet `-m`: sizing from FILE.mtr or a background mesh FILE.b.*.
    pub sizing: bool,
    /// tet `-pY`: surface preservation (no Steiner point on the input surface).
    pub preserve_surface: bool,
    /// tet `-d`: only detect self-intersections of the input facets.
    pub detect: bool,
    /// tet `-M`: no merging of coplanar facets.
    pub no_merge: bool,
    /// tri `-c`: keep the convex hull (no removal of exterior triangles).
    pub convex_hull: bool,
    /// tri `-A`: regional attributes in the .ele output.
    pub region_attributes: bool,
    /// `-v`: Voronoi (power, with `-w`) diagram output (.v.node, .v.edge;
    /// tet also .v.face, .v.cell).
    pub voronoi: bool,
    /// `-w`: regular (weighted Delaunay) triangulation/tetrahedralization;
    /// weights from FILE.weight, else node attribute 1.
    pub weights: bool,
    /// tri `--lloyd N`: N Lloyd iterations in the bounding box first.
    pub lloyd: Option<usize>,
    /// tri `--svg FILE`: an SVG picture of the mesh (and cells with -v).
    pub svg: Option<PathBuf>,
    /// tet `--cells-vtu FILE`: the Voronoi (power, with -w) cells clipped to
    /// the points' bounding box, as VTK polyhedra.
    pub cells_vtu: Option<PathBuf>,
    /// tri `-q[angle]`: quality mesh with this minimum angle (degrees).
    pub min_angle: Option<f64>,
    /// tri `-a`: area constraints (regional; global too if a number follows).
    pub area: bool,
    /// tri `-a<area>`: global maximum triangle area.
    pub max_area: Option<f64>,
    /// tri `-S<n>`: Steiner point budget.
    pub max_steiner: Option<usize>,
    /// tet `-g`: Medit `.mesh` output next to the other files.
    pub medit_out: bool,
    /// tet `--medit FILE`: Medit `.mesh` output to FILE.
    pub medit: Option<PathBuf>,
    /// tet `--gmsh FILE`: Gmsh `.msh` 4.1 output to FILE.
    pub gmsh: Option<PathBuf>,
    /// tet `-q[ratio]`: quality mesh with this radius-edge bound.
    pub tet_ratio: Option<f64>,
    /// tet `-q[ratio]/[angle]`: the dihedral bound for the optimisation
    /// and its report (degrees).
    pub tet_min_dihedral: Option<f64>,
    /// tet `-O[level]`: mesh optimisation level (`-O0` off; default 3 with
    /// `-q`/`-a`, off otherwise).
    pub tet_optimize: Option<u32>,
    /// The switch letters as given, for messages.
    pub switches: String,
    /// tri `-P`: no .poly output.
    pub no_poly: bool,
    /// tri `-o2`: quadratic (6-node) triangles.
    pub second_order: bool,
    /// tri `--png FILE`: a PNG picture (the same scene as --svg).
    pub png: Option<PathBuf>,
    /// tri `--png-width N`: picture width in pixels (SVG and PNG; default 800).
    pub png_width: Option<u32>,
    /// tet `--cut x|y|z[=F]|none`: the cut of the `--png` picture.
    pub cut: Option<Option<(usize, f64)>>,
    /// tet `--view AZ,EL`: camera azimuth and elevation of `--png`, degrees.
    pub view: Option<(f64, f64)>,
    /// tri `--svg-quality`: colour the triangles by minimum angle.
    pub svg_quality: bool,
    /// tet `--keep-ratio`: the optimisation keeps the `-q` bound.
    pub keep_ratio: bool,
    /// `--warn-unmet` (tri and tet): elements of the final mesh that miss a
    /// bound asked for are a warning (exit code 0) instead of exit code 3.
    pub warn_unmet: bool,
    /// `--stats-json FILE`: mesh quality statistics as JSON (tri and tet).
    pub stats_json: Option<PathBuf>,
    /// tri `-D`: conforming Delaunay (every triangle truly Delaunay).
    pub conforming_delaunay: bool,
    /// tri `-Y` (1: no Steiner point on the boundary) / `-YY` (2: none on
    /// any segment).
    pub no_segment_splits: u8,
    /// tri `-j`: jettison vertices no triangle uses from the output .node.
    pub jettison: bool,
    /// tri `--threads N`: threads for quality refinement (default: all;
    /// the output does not depend on it).
    pub threads: Option<usize>,
}

/// What the command line asks for.
#[derive(Debug)]
pub enum Command {
    Run(Box<Opts>),
    Help,
    Version,
}

/// A usage error (exit code 2).
#[derive(Debug)]
pub struct Usage(pub String);

/// Switches of the original program that delone does not implement yet,
/// with a few words on what they do.
fn unimplemented(mode: Mode, c: char) -> Option<&'static str> {
    Some(match (mode, c) {
        (Mode::Tri, 'g') => "OFF output",
        (Mode::Tri, 'O') => "ignore holes",
        (Mode::Tri, 'X') => "no exact arithmetic",
        (Mode::Tri, 'i') => "incremental algorithm choice",
        (Mode::Tri, 'l') => "vertical cuts only in divide-and-conquer",
        (Mode::Tri, 's') => "segment splitting",
        (Mode::Tet, 'R') => "mesh coarsening",
        (Mode::Tet, 'i') => "insertion of additional points",
        (Mode::Tet, 'T') => "coplanarity tolerance",
        (Mode::Tet, 'X') => "no exact arithmetic",
        (Mode::Tet, 'D') => "conforming Delaunay",
        (Mode::Tet, 'o') => "second-order elements (-o2) / dihedral bound (-o/)",
        _ => return None,
    })
}

/// Where the number glued to a switch letter, starting at `chars[start]`,
/// ends: digits and `.`; with `slash` (tet `-q`) also `/` between two
/// numbers; and an exponent, `e`/`E` followed by a digit or by `+`/`-` and
/// a digit, after a digit of the same number. Any other `e`/`E` is the next
/// switch: `-pq1.2e` is `-q1.2` then `-e`, `-pq1.2e-3`... is `-q0.0012`.
fn number_end(chars: &[char], start: usize, slash: bool) -> usize {
    let mut k = start;
    let mut digit = false;
    while let Some(&ch) = chars.get(k) {
        if ch.is_ascii_digit() {
            digit = true;
            k += 1;
        } else if ch == '.' {
            k += 1;
        } else if slash && ch == '/' {
            digit = false;
            k += 1;
        } else if matches!(ch, 'e' | 'E') && digit {
            let d = |i: usize| chars.get(i).is_some_and(|c| c.is_ascii_digit());
            if d(k + 1) {
                k += 2;
            } else if matches!(chars.get(k + 1), Some('+' | '-')) && d(k + 2) {
                k += 3;
            } else {
                break;
            }
            // One exponent per number.
            while chars.get(k).is_some_and(|c| c.is_ascii_digit()) {
                k += 1;
            }
            if !(slash && chars.get(k) == Some(&'/')) {
                break;
            }
        } else {
            break;
        }
    }
    k
}

/// A number glued to a switch letter (`-q30`, `-a0.01`, `-S100`), if any.
fn number(c: char, num: &str) -> Result<Option<f64>, Usage> {
    if num.is_empty() {
        return Ok(None);
    }
    match num.parse::<f64>() {
        Ok(x) if x.is_finite() && x >= 0.0 => Ok(Some(x)),
        _ => Err(Usage(format!("-{c}{num}: {num} is not a number"))),
    }
}

fn letter(mode: Mode, c: char, num: &str, o: &mut Opts) -> Result<Option<Command>, Usage> {
    match (mode, c) {
        (Mode::Tri, 'q') => {
            let a = number(c, num)?.unwrap_or(20.0);
            if a > 60.0 {
                return Err(Usage(format!(
                    "-q{num}: the minimum angle must be at most 60"
                )));
            }
            o.min_angle = Some(a)
        }
        (Mode::Tri, 'a') => {
            o.area = true;
            if let Some(x) = number(c, num)? {
                if x <= 0.0 {
                    return Err(Usage(format!("-a{num}: the maximum area must be positive")));
                }
                o.max_area = Some(x);
            }
        }
        (Mode::Tri, 'S') => {
            o.max_steiner = Some(number(c, num)?.unwrap_or(0.0) as usize);
        }
        (Mode::Tri, 'P') => o.no_poly = true,
        (Mode::Tri, 'D') => o.conforming_delaunay = true,
        (Mode::Tri, 'Y') => o.no_segment_splits = (o.no_segment_splits + 1).min(2),
        (Mode::Tri, 'j') => o.jettison = true,
        (Mode::Tri, 'u') => {
            return Err(Usage(
                "-u (user-defined triangle test) needs the library API refine_with \
                 (delone::tri::refine::refine_with takes the test as a closure); \
                 the command line has no way to give one"
                    .into(),
            ))
        }
        (Mode::Tri, 'o') => {
            if num != "2" {
                return Err(Usage(format!(
                    "-o{num}: only -o2 (quadratic triangles) is known; -o FILE takes a separate file name"
                )));
            }
            o.second_order = true
        }
        (Mode::Tet, 'q') => {
            let (ratio, angle) = num.split_once('/').unwrap_or((num, ""));
            o.tet_ratio = Some(number(c, ratio)?.unwrap_or(2.0));
            if num.contains('/') {
                let d = number(c, angle)?.ok_or_else(|| {
                    Usage(format!(
                        "-q{num}: a dihedral angle in degrees follows the /"
                    ))
                })?;
                // The regular tetrahedron's dihedral angle, acos(1/3): no
                // tetrahedron has a larger smallest dihedral angle.
                if d <= 0.0 || d >= 70.52 {
                    return Err(Usage(format!(
                        "-q{num}: the dihedral bound must lie between 0 and 70.5 degrees"
                    )));
                }
                o.tet_min_dihedral = Some(d);
            }
        }
        (Mode::Tet, 'a') => {
            o.area = true;
            if let Some(x) = number(c, num)? {
                if x <= 0.0 {
                    return Err(Usage(format!(
                        "-a{num}: the maximum volume must be positive"
                    )));
                }
                o.max_area = Some(x);
            }
        }
        (Mode::Tet, 'O') => o.tet_optimize = Some(number(c, num)?.unwrap_or(3.0).max(0.0) as u32),
        (Mode::Tet, 'S') => o.max_steiner = Some(number(c, num)?.unwrap_or(0.0) as usize),
        (_, 'z') => o.zero = true,
        (_, 'v') => o.voronoi = true,
        (_, 'w') => o.weights = true,
        (_, 'p') => o.pslg = true,
        (Mode::Tri, 'r') => o.refine_mesh = true,
        (Mode::Tet, 'r') => o.refine_mesh = true,
        (Mode::Tet, 'm') => o.sizing = true,
        (_, 'c') => o.convex_hull = true,
        (_, 'A') => o.region_attributes = true,
        (Mode::Tet, 'g') => o.medit_out = true,
        (Mode::Tet, 'Y') => o.preserve_surface = true,
        (Mode::Tet, 'd') => o.detect = true,
        (Mode::Tet, 'M') => o.no_merge = true,
        (_, 'Q') => o.quiet = true,
        (_, 'V') => o.verbose = o.verbose.saturating_add(1),
        (_, 'C') => o.check = true,
        (_, 'e') => o.edges = true,
        (_, 'n') => o.neigh = true,
        (_, 'N') => o.no_node = true,
        (_, 'E') => o.no_ele = true,
        (_, 'I') => o.no_iteration = true,
        (_, 'B') => o.no_bound = true,
        (_, 'h') => return Ok(Some(Command::Help)),
        (Mode::Tri, 'F') => o.fortune = true,
        (Mode::Tet, 'F') => o.no_face = true,
        (Mode::Tet, 'f') => o.all_faces = true,
        (Mode::Tet, 'k') => o.vtk_legacy = true,
        // delone never drops vertices from the output .node, which is what
        // TetGen's -J asks for.
        (Mode::Tet, 'J') => {}
        _ => {
            return Err(Usage(match unimplemented(mode, c) {
                Some(what) => format!("switch -{c} ({what}) is not implemented yet"),
                None => format!(
                    "unknown switch -{c} for delone {} (see delone {} --help)",
                    mode.name(),
                    mode.name()
                ),
            }))
        }
    }
    Ok(None)
}

/// `x`, `y`, `z` with an optional `=FRACTION`, or `none`.
fn parse_cut(v: &str) -> Option<Option<(usize, f64)>> {
    if v == "none" {
        return Some(None);
    }
    let (axis, frac) = v.split_once('=').unwrap_or((v, "0.5"));
    let axis = ["x", "y", "z"].iter().position(|&a| a == axis)?;
    let frac: f64 = frac.parse().ok().filter(|f: &f64| f.is_finite())?;
    Some(Some((axis, frac)))
}

/// `AZIMUTH,ELEVATION` in degrees.
fn parse_view(v: &str) -> Option<(f64, f64)> {
    let (a, e) = v.split_once(',')?;
    let (a, e): (f64, f64) = (a.trim().parse().ok()?, e.trim().parse().ok()?);
    (a.is_finite() && e.is_finite()).then_some((a, e))
}

fn value(
    name: &str,
    inline: Option<&str>,
    it: &mut dyn Iterator<Item = String>,
) -> Result<String, Usage> {
    match inline {
        Some(v) if !v.is_empty() => Ok(v.to_string()),
        Some(_) => Err(Usage(format!("{name} needs a value"))),
        None => it
            .next()
            .filter(|v| !v.is_empty())
            .ok_or_else(|| Usage(format!("{name} needs a value"))),
    }
}

/// The switches a run would accept and not use, each with the reason:
/// the first one given is refused (see [`parse`]).
fn unused(mode: Mode, o: &Opts) -> Option<String> {
    let picture = o.svg.is_some() || o.png.is_some();
    let refining = o.min_angle.is_some()
        || o.area
        || o.max_steiner.is_some()
        || o.conforming_delaunay
        || o.no_segment_splits > 0;
    // (given, switch, why it has no effect in this run)
    let mut rules: Vec<(bool, &str, &str)> = Vec::new();
    let common = [
        (
            o.png_width.is_some() && !picture,
            "--png-width",
            "without --svg or --png: no picture is drawn",
        ),
        (
            o.svg_quality && !picture,
            "--svg-quality",
            "without --svg or --png: no picture is drawn",
        ),
        (
            o.cut.is_some() && o.png.is_none(),
            "--cut",
            "without --png: no picture is drawn",
        ),
        (
            o.view.is_some() && o.png.is_none(),
            "--view",
            "without --png: no picture is drawn",
        ),
    ];
    let bounded = match mode {
        Mode::Tri => o.min_angle.is_some() || o.area,
        Mode::Tet => o.tet_ratio.is_some() || o.area || o.sizing,
    };
    rules.push((
        o.warn_unmet && !bounded,
        "--warn-unmet",
        if mode == Mode::Tri {
            "without a bound (-q or -a): no triangle can miss one"
        } else {
            "without a bound (-q, -a or -m): no tetrahedron can miss one"
        },
    ));
    match mode {
        Mode::Tri => {
            rules.push((
                o.threads.is_some() && !refining,
                "--threads",
                "without refinement (-q, -a, -S, -D or -Y): only refinement runs in threads",
            ));
            if o.refine_mesh {
                let why = "with -r: delone tri -r writes only the .node, .ele and .poly files";
                rules.extend([
                    (o.edges, "-e", why),
                    (o.neigh, "-n", why),
                    (o.vtu.is_some(), "-o/--vtu", why),
                    (o.vtu_ascii, "--vtu-ascii", why),
                    (o.svg.is_some(), "--svg", why),
                    (o.png.is_some(), "--png", why),
                    (o.stats_json.is_some(), "--stats-json", why),
                    (o.second_order, "-o2", why),
                    (
                        o.convex_hull,
                        "-c",
                        "with -r: the input mesh's own boundary is kept",
                    ),
                    (
                        o.region_attributes,
                        "-A",
                        "with -r: the .ele keeps the input mesh's attributes",
                    ),
                    (
                        o.voronoi,
                        "-v",
                        "with -r: no Voronoi diagram of a refined mesh",
                    ),
                    (
                        o.weights,
                        "-w",
                        "with -r: the input mesh is refined as it is",
                    ),
                    (
                        o.lloyd.is_some(),
                        "--lloyd",
                        "with -r: the input points are kept",
                    ),
                ]);
            }
        }
        Mode::Tet => {
            if o.detect {
                let why = "with -d: nothing is meshed and no file is written";
                rules.extend([
                    (o.edges, "-e", why),
                    (o.neigh, "-n", why),
                    (o.all_faces, "-f", why),
                    (o.vtk_legacy, "-k", why),
                    (o.vtu.is_some(), "-o/--vtu", why),
                    (o.vtu_ascii, "--vtu-ascii", why),
                    (o.medit_out, "-g", why),
                    (o.medit.is_some(), "--medit", why),
                    (o.gmsh.is_some(), "--gmsh", why),
                    (o.png.is_some(), "--png", why),
                    (o.stats_json.is_some(), "--stats-json", why),
                    (o.cells_vtu.is_some(), "--cells-vtu", why),
                    (o.output_dir.is_some(), "--output-dir", why),
                    (o.no_node, "-N", why),
                    (o.no_ele, "-E", why),
                    (o.no_face, "-F", why),
                    (o.no_bound, "-B", why),
                    (o.no_iteration, "-I", why),
                    (
                        o.zero,
                        "-z",
                        "with -d: findings use the input file's own numbering",
                    ),
                    (o.region_attributes, "-A", why),
                    (o.convex_hull, "-c", why),
                    (o.no_merge, "-M", why),
                    (o.preserve_surface, "-Y", why),
                    (o.tet_ratio.is_some(), "-q", why),
                    (o.area, "-a", why),
                    (o.sizing, "-m", why),
                    (o.max_steiner.is_some(), "-S", why),
                    (o.tet_optimize.is_some(), "-O", why),
                    (o.keep_ratio, "--keep-ratio", why),
                    (o.warn_unmet, "--warn-unmet", why),
                    (o.check, "-C", why),
                    (o.voronoi, "-v", why),
                    (o.weights, "-w", why),
                    (o.refine_mesh, "-r", why),
                ]);
            }
            if !o.pslg && !o.refine_mesh {
                let why = "without -p or -r: a point set is only tetrahedralized";
                rules.extend([
                    (o.tet_optimize.is_some(), "-O", why),
                    (o.keep_ratio, "--keep-ratio", why),
                    (o.no_merge, "-M", why),
                    (o.preserve_surface, "-Y", why),
                    (
                        o.stats_json.is_some(),
                        "--stats-json",
                        "without -p or -r: the statistics are those of a quality mesh",
                    ),
                ]);
            }
            rules.push((
                o.keep_ratio && o.tet_ratio.is_none(),
                "--keep-ratio",
                "without -q: there is no radius-edge bound to keep",
            ));
            if o.refine_mesh {
                rules.extend([
                    (o.convex_hull, "-c", "with -r: the input mesh is the domain"),
                    (
                        o.no_merge,
                        "-M",
                        "with -r: the input mesh's faces are kept as they are",
                    ),
                    (
                        o.preserve_surface,
                        "-Y",
                        "with -r: not supported when refining a mesh",
                    ),
                    (
                        o.voronoi,
                        "-v",
                        "with -r: no Voronoi diagram of a refined mesh",
                    ),
                    (
                        o.weights,
                        "-w",
                        "with -r: the input mesh is refined as it is",
                    ),
                ]);
            }
            if o.pslg || o.refine_mesh {
                rules.push((
                    o.cells_vtu.is_some(),
                    "--cells-vtu",
                    "with -p or -r: Voronoi cells are drawn for point sets only",
                ));
            }
        }
    }
    rules.extend(common);
    rules
        .into_iter()
        .find(|r| r.0)
        .map(|(_, s, why)| format!("{s} has no effect {why}; leave it out"))
}

/// Parses the arguments after the subcommand name.
///
/// **Every switch is honoured or refused.** A switch or long option that
/// this parser accepts must change what the run does (its files, its
/// report, its exit code); when it would change nothing in the run asked
/// for (an output switch with `-d`, `-e` with `tri -r`, `--cut` without
/// `--png`, ...) the command line is refused with a usage error naming the
/// switch and the reason (see `unused`). Switches of Triangle/TetGen that
/// delone lacks are refused as "not implemented yet".
pub fn parse(mode: Mode, args: Vec<String>) -> Result<Command, Usage> {
    let mut o = Opts::default();
    let mut input: Option<String> = None;
    let mut it = args.into_iter();
    let mut only_files = false;
    while let Some(a) = it.next() {
        if only_files || a == "-" || !a.starts_with('-') {
            if let Some(prev) = &input {
                return Err(Usage(format!(
                    "more than one input file ({prev} and {a}); delone {} takes one",
                    mode.name()
                )));
            }
            input = Some(a);
            continue;
        }
        if a == "--" {
            only_files = true;
            continue;
        }
        if let Some(long) = a.strip_prefix("--") {
            let (name, inline) = match long.split_once('=') {
                Some((n, v)) => (n, Some(v)),
                None => (long, None),
            };
            let flag = || -> Result<(), Usage> {
                match inline {
                    Some(_) => Err(Usage(format!("--{name} takes no value"))),
                    None => Ok(()),
                }
            };
            match name {
                "help" => return Ok(Command::Help),
                "version" => return Ok(Command::Version),
                "quiet" => {
                    flag()?;
                    o.quiet = true
                }
                "verbose" => {
                    flag()?;
                    o.verbose = o.verbose.saturating_add(1)
                }
                "check" => {
                    flag()?;
                    o.check = true
                }
                "vtu-ascii" => {
                    flag()?;
                    o.vtu_ascii = true
                }
                "vtu" => o.vtu = Some(value("--vtu", inline, &mut it)?.into()),
                "svg" if mode == Mode::Tri => o.svg = Some(value("--svg", inline, &mut it)?.into()),
                "medit" if mode == Mode::Tet => {
                    o.medit = Some(value("--medit", inline, &mut it)?.into())
                }
                "gmsh" if mode == Mode::Tet => {
                    o.gmsh = Some(value("--gmsh", inline, &mut it)?.into())
                }
                "png" => o.png = Some(value("--png", inline, &mut it)?.into()),
                "cut" if mode == Mode::Tet => {
                    let v = value("--cut", inline, &mut it)?;
                    o.cut = Some(parse_cut(&v).ok_or_else(|| {
                        Usage(format!(
                            "--cut needs x, y or z (optionally =FRACTION) or none, not {v:?}"
                        ))
                    })?)
                }
                "view" if mode == Mode::Tet => {
                    let v = value("--view", inline, &mut it)?;
                    o.view = Some(parse_view(&v).ok_or_else(|| {
                        Usage(format!(
                            "--view needs AZIMUTH,ELEVATION in degrees, not {v:?}"
                        ))
                    })?)
                }
                "stats-json" => o.stats_json = Some(value("--stats-json", inline, &mut it)?.into()),
                "svg-quality" if mode == Mode::Tri => {
                    flag()?;
                    o.svg_quality = true
                }
                "keep-ratio" if mode == Mode::Tet => {
                    flag()?;
                    o.keep_ratio = true
                }
                "warn-unmet" => {
                    flag()?;
                    o.warn_unmet = true
                }
                "png-width" => {
                    let v = value("--png-width", inline, &mut it)?;
                    o.png_width = Some(
                        v.parse()
                            .ok()
                            .filter(|&w: &u32| (16..=16384).contains(&w))
                            .ok_or_else(|| {
                                Usage(format!(
                                    "--png-width needs a width of 16 to 16384 pixels, not {v:?}"
                                ))
                            })?,
                    )
                }
                "cells-vtu" if mode == Mode::Tet => {
                    o.cells_vtu = Some(value("--cells-vtu", inline, &mut it)?.into())
                }
                "lloyd" if mode == Mode::Tri => {
                    let v = value("--lloyd", inline, &mut it)?;
                    o.lloyd = Some(v.parse().map_err(|_| {
                        Usage(format!("--lloyd needs a number of iterations, not {v:?}"))
                    })?)
                }
                "output-dir" => o.output_dir = Some(value("--output-dir", inline, &mut it)?.into()),
                "threads" if mode == Mode::Tri => {
                    o.threads = Some(crate::threads::parse(&value(
                        "--threads",
                        inline,
                        &mut it,
                    )?)?)
                }
                _ => {
                    return Err(Usage(format!(
                        "unknown option --{name} (see delone {} --help)",
                        mode.name()
                    )))
                }
            }
            continue;
        }
        if a == "-o" {
            o.vtu = Some(value("-o", None, &mut it)?.into());
            continue;
        }
        let chars: Vec<char> = a[1..].chars().collect();
        let mut k = 0;
        while k < chars.len() {
            let c = chars[k];
            k += 1;
            let start = k;
            if matches!(c, 'q' | 'a' | 'S')
                || (mode == Mode::Tri && c == 'o')
                || (mode == Mode::Tet && c == 'O')
            {
                k = number_end(&chars, k, mode == Mode::Tet && c == 'q');
            }
            let num: String = chars[start..k].iter().collect();
            if let Some(cmd) = letter(mode, c, &num, &mut o)? {
                return Ok(cmd);
            }
        }
        o.switches.push_str(&a[1..]);
    }
    if mode == Mode::Tri
        && (o.min_angle.is_some() || o.area || o.max_steiner.is_some())
        && !o.pslg
        && !o.refine_mesh
    {
        return Err(Usage(
            "-q, -a and -S refine a PSLG (-p) or an existing mesh (-r)".into(),
        ));
    }
    if mode == Mode::Tri
        && (o.conforming_delaunay || o.no_segment_splits > 0)
        && !o.pslg
        && !o.refine_mesh
    {
        return Err(Usage(
            "-D and -Y apply to segments: use them with a PSLG (-p) or an existing mesh (-r)"
                .into(),
        ));
    }
    if o.jettison && o.refine_mesh {
        return Err(Usage(
            "-j with -r is not supported: -r keeps every vertex of the input mesh".into(),
        ));
    }
    if o.pslg && o.refine_mesh {
        return Err(Usage(
            "-p and -r together are not supported: -r reads FILE.poly's segments itself".into(),
        ));
    }
    if mode == Mode::Tet
        && (o.tet_ratio.is_some() || o.area || o.max_steiner.is_some() || o.sizing)
        && !o.pslg
        && !o.refine_mesh
    {
        return Err(Usage(
            "-q, -a, -m and -S refine a PLC or surface (-p) or an existing mesh (-r)".into(),
        ));
    }
    if let Some(msg) = unused(mode, &o) {
        return Err(Usage(msg));
    }
    match input {
        Some(i) => {
            o.input = i.into();
            Ok(Command::Run(Box::new(o)))
        }
        None => Err(Usage(format!(
            "no input file (usage: delone {} [-switches] FILE[.node]; see delone {} --help)",
            mode.name(),
            mode.name()
        ))),
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn cutaway_options() {
        assert_eq!(parse_cut("none"), Some(None));
        assert_eq!(parse_cut("y"), Some(Some((1, 0.5))));
        assert_eq!(parse_cut("z=0.25"), Some(Some((2, 0.25))));
        assert_eq!(parse_cut("w"), None);
        assert_eq!(parse_cut("x=nan"), None);
        assert_eq!(parse_view("30,-10"), Some((30.0, -10.0)));
        assert_eq!(parse_view("30"), None);
    }

    use super::*;

    fn p(mode: Mode, args: &[&str]) -> Result<Command, Usage> {
        parse(mode, args.iter().map(|s| s.to_string()).collect())
    }

    /// Every letter the parser accepts (or refuses with a reason other
    /// than "unknown") has an entry in its subcommand's help; the letters
    /// come from the parser itself, so the test follows it.
    #[test]
    fn every_accepted_letter_is_in_the_help() {
        for (mode, help) in [(Mode::Tri, crate::help::TRI), (Mode::Tet, crate::help::TET)] {
            let mut known = 0;
            for c in ('a'..='z').chain('A'..='Z').chain('0'..='9') {
                let r = letter(mode, c, "", &mut Opts::default());
                let unknown = matches!(&r, Err(Usage(m)) if m.starts_with("unknown switch"));
                if unknown {
                    continue;
                }
                known += 1;
                let not_yet = matches!(&r, Err(Usage(m)) if m.contains("not implemented yet"));
                let entry = help.lines().any(|l| {
                    l.strip_prefix("    -")
                        .is_some_and(|rest| rest.starts_with(c))
                });
                let listed = help.split("Not implemented yet").nth(1).is_some_and(|t| {
                    t.split_whitespace()
                        .take(12)
                        .any(|w| w.starts_with(&format!("-{c}")))
                });
                assert!(
                    entry || (not_yet && listed),
                    "delone {} --help has no entry for -{c}",
                    mode.name()
                );
            }
            assert!(known > 20, "{known}");
        }
    }

    #[test]
    fn letters_and_long_options() {
        let Ok(Command::Run(o)) = p(Mode::Tri, &["-zVVCen", "x.node", "--vtu=a.vtu", "-Q"]) else {
            panic!()
        };
        assert!(o.zero && o.check && o.edges && o.neigh && o.quiet);
        assert_eq!(o.verbose, 2);
        assert_eq!(o.vtu, Some("a.vtu".into()));
        assert_eq!(o.input, PathBuf::from("x.node"));
        let Ok(Command::Run(o)) = p(
            Mode::Tet,
            &["-fkF", "-o", "b.vtu", "--output-dir", "d", "y"],
        ) else {
            panic!()
        };
        assert!(o.all_faces && o.vtk_legacy && o.no_face);
        assert_eq!(o.output_dir, Some("d".into()));
        assert_eq!(o.vtu, Some("b.vtu".into()));
    }

    #[test]
    fn errors() {
        let msg = |m, a: &[&str]| match p(m, a) {
            Err(Usage(s)) => s,
            Ok(c) => panic!("{c:?}"),
        };
        assert_eq!(
            msg(Mode::Tri, &["-g", "x"]),
            "switch -g (OFF output) is not implemented yet"
        );
        assert!(msg(Mode::Tri, &["-pu", "x"])
            .starts_with("-u (user-defined triangle test) needs the library API refine_with"));
        assert!(msg(Mode::Tri, &["-D", "x"]).starts_with("-D and -Y apply to segments"));
        assert!(msg(Mode::Tri, &["-Y", "x"]).starts_with("-D and -Y apply to segments"));
        assert_eq!(
            msg(Mode::Tri, &["-q61", "x"]),
            "-q61: the minimum angle must be at most 60"
        );
        assert_eq!(
            msg(Mode::Tri, &["-q3.0.1", "x"]),
            "-q3.0.1: 3.0.1 is not a number"
        );
        assert_eq!(
            msg(Mode::Tri, &["-a0", "x"]),
            "-a0: the maximum area must be positive"
        );
        assert!(msg(Mode::Tri, &["-k", "x"]).starts_with("unknown switch -k for delone tri"));
        assert!(msg(Mode::Tet, &["-x"]).starts_with("unknown switch -x"));
        assert!(msg(Mode::Tet, &["a", "b"]).starts_with("more than one input file"));
        assert!(msg(Mode::Tet, &[]).starts_with("no input file"));
        assert_eq!(msg(Mode::Tri, &["-o"]), "-o needs a value");
        assert!(msg(Mode::Tri, &["-o3", "x"]).starts_with("-o3: only -o2"));
        assert!(msg(Mode::Tri, &["--png-width", "3", "x"]).starts_with("--png-width needs"));
        assert!(matches!(p(Mode::Tet, &["-zh"]), Ok(Command::Help)));
        assert!(msg(Mode::Tri, &["--lloyd", "x", "f"]).starts_with("--lloyd needs a number"));
        assert!(msg(Mode::Tet, &["--lloyd", "3", "f"]).starts_with("unknown option --lloyd"));
    }

    #[test]
    fn voronoi_weights_lloyd_svg() {
        let Ok(Command::Run(o)) = p(
            Mode::Tri,
            &["-vw", "--lloyd", "5", "--svg=pic.svg", "x.node"],
        ) else {
            panic!()
        };
        assert!(o.voronoi && o.weights);
        assert_eq!(o.lloyd, Some(5));
        assert_eq!(o.svg, Some("pic.svg".into()));
        let Ok(Command::Run(o)) = p(Mode::Tet, &["-v", "y"]) else {
            panic!()
        };
        assert!(o.voronoi);
    }

    #[test]
    fn output_switches() {
        let Ok(Command::Run(o)) = p(
            Mode::Tri,
            &[
                "-pq30o2PeB",
                "--png",
                "a.png",
                "--png-width=300",
                "--svg-quality",
                "--stats-json",
                "s.json",
                "x",
            ],
        ) else {
            panic!()
        };
        assert!(o.second_order && o.no_poly && o.edges && o.no_bound && o.svg_quality);
        assert_eq!(o.min_angle, Some(30.0));
        assert_eq!(o.png, Some("a.png".into()));
        assert_eq!(o.png_width, Some(300));
        assert_eq!(o.stats_json, Some("s.json".into()));
    }

    #[test]
    fn quality_switches() {
        let run = |a: &[&str]| match p(Mode::Tri, a) {
            Ok(Command::Run(o)) => o,
            other => panic!("{other:?}"),
        };
        let o = run(&["-pq", "x"]);
        assert_eq!((o.min_angle, o.area, o.max_area), (Some(20.0), false, None));
        let o = run(&["-pq34.5a0.01eS100", "x"]);
        assert_eq!(o.min_angle, Some(34.5));
        assert!(o.area && o.edges);
        assert_eq!(o.max_area, Some(0.01));
        assert_eq!(o.max_steiner, Some(100));
        let o = run(&["-pa", "x"]);
        assert_eq!((o.min_angle, o.area, o.max_area), (None, true, None));
        let o = run(&["-pqa.5", "x"]);
        assert_eq!((o.min_angle, o.max_area), (Some(20.0), Some(0.5)));
    }

    #[test]
    fn conforming_splits_jettison() {
        let run = |a: &[&str]| match p(Mode::Tri, a) {
            Ok(Command::Run(o)) => o,
            other => panic!("{other:?}"),
        };
        let o = run(&["-pD", "x"]);
        assert!(o.conforming_delaunay && o.no_segment_splits == 0 && !o.jettison);
        let o = run(&["-pqY", "x"]);
        assert_eq!(o.no_segment_splits, 1);
        let o = run(&["-pqYYY", "x"]);
        assert_eq!(o.no_segment_splits, 2);
        let o = run(&["-rYD", "x"]);
        assert!(o.refine_mesh && o.conforming_delaunay && o.no_segment_splits == 1);
        let o = run(&["-pjD", "x"]);
        assert!(o.jettison && o.conforming_delaunay);
        assert!(
            matches!(p(Mode::Tri, &["-rj", "x"]), Err(Usage(m)) if m.starts_with("-j with -r"))
        );
        let o = run(&["-cj", "x"]);
        assert!(o.jettison && o.convex_hull);
    }
}
