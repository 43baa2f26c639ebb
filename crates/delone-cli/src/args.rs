//! Command-line parsing: Triangle/TetGen letter switches plus long options.

use std::path::PathBuf;

use delone::switches::OutputSwitches;
use delone::tet::TetOptions;
use delone::tri::TriOptions;

pub use crate::fail::Usage;

/// Which program the subcommand stands in for: `delone tri` (Triangle's
/// switches, 2D) or `delone tet` (TetGen's, 3D).
pub type Mode = delone::switches::Program;

/// Everything a run needs to know.
#[derive(Debug, Clone, Default)]
pub struct Opts {
    /// The subcommand (`None` only before parsing).
    pub mode: Option<Mode>,
    /// The switches of `delone tri`, as the library parsed them (with
    /// `--threads`).
    pub tri: TriOptions,
    /// The switches of `delone tet`, as the library parsed them (with
    /// `--keep-ratio`).
    pub tet: TetOptions,
    pub vtu: Option<PathBuf>,
    pub vtu_ascii: bool,
    pub output_dir: Option<PathBuf>,
    pub input: PathBuf,
    /// tri `--lloyd N`: N Lloyd iterations in the bounding box first.
    pub lloyd: Option<usize>,
    /// tri `--svg FILE`: an SVG picture of the mesh (and cells with -v).
    pub svg: Option<PathBuf>,
    /// tet `--cells-vtu FILE`: the Voronoi (power, with -w) cells clipped to
    /// the points' bounding box, as VTK polyhedra.
    pub cells_vtu: Option<PathBuf>,
    /// tet `--medit FILE`: Medit `.mesh` output to FILE.
    pub medit: Option<PathBuf>,
    /// tet `--gmsh FILE`: Gmsh `.msh` 4.1 output to FILE.
    pub gmsh: Option<PathBuf>,
    /// tet `--threads N`: threads for reading the `.node` file, the
    /// Delaunay insertion and writing the `.node`/`.ele` files of a point
    /// set (tri's is `tri.threads`).
    pub threads: Option<usize>,
    /// The switch letters as given, for messages.
    pub switches: String,
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
    /// `--warn-unmet` (tri and tet): elements of the final mesh that miss a
    /// bound asked for are a warning (exit code 0) instead of exit code 3.
    pub warn_unmet: bool,
    /// `--stats-json FILE`: mesh quality statistics as JSON (tri and tet).
    pub stats_json: Option<PathBuf>,
}

/// What the command line asks for.
#[derive(Debug)]
pub enum Command {
    Run(Box<Opts>),
    Help,
    Version,
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

/// The long options a run would accept and not use, each with the
/// reason: the first one given is refused (see [`parse`]). The switch
/// letters' own rules are the library's (`TriOptions::check`,
/// `TetOptions::check`).
fn unused(mode: Mode, o: &Opts) -> Option<String> {
    let picture = o.svg.is_some() || o.png.is_some();
    // (given, switch, why it has no effect in this run)
    let mut rules: Vec<(bool, &str, &str)> = Vec::new();
    let bounded = match mode {
        Mode::Tri => o.tri.min_angle.is_some() || o.area(),
        Mode::Tet => o.tet.max_radius_edge.is_some() || o.area() || o.tet.sizing,
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
            if o.refine_mesh() {
                let why = "with -r: delone tri -r writes only the .node, .ele and .poly files";
                rules.extend([
                    (o.vtu.is_some(), "-o/--vtu", why),
                    (o.vtu_ascii, "--vtu-ascii", why),
                    (o.svg.is_some(), "--svg", why),
                    (o.png.is_some(), "--png", why),
                    (o.stats_json.is_some(), "--stats-json", why),
                    (
                        o.lloyd.is_some(),
                        "--lloyd",
                        "with -r: the input points are kept",
                    ),
                ]);
            }
        }
        Mode::Tet => {
            if o.tet.detect {
                let why = "with -d: nothing is meshed and no file is written";
                rules.extend([
                    (o.vtu.is_some(), "-o/--vtu", why),
                    (o.vtu_ascii, "--vtu-ascii", why),
                    (o.medit.is_some(), "--medit", why),
                    (o.gmsh.is_some(), "--gmsh", why),
                    (o.png.is_some(), "--png", why),
                    (o.stats_json.is_some(), "--stats-json", why),
                    (o.cells_vtu.is_some(), "--cells-vtu", why),
                    (o.output_dir.is_some(), "--output-dir", why),
                    (o.warn_unmet, "--warn-unmet", why),
                ]);
            }
            if !o.pslg() && !o.refine_mesh() {
                rules.push((
                    o.stats_json.is_some(),
                    "--stats-json",
                    "without -p or -r: the statistics are those of a quality mesh",
                ));
            }
            if o.pslg() || o.refine_mesh() {
                rules.extend([
                    (
                        o.cells_vtu.is_some(),
                        "--cells-vtu",
                        "with -p or -r: Voronoi cells are drawn for point sets only",
                    ),
                    (
                        o.threads.is_some(),
                        "--threads",
                        "with -p or -r: only point sets are read and written in threads",
                    ),
                ]);
            }
        }
    }
    rules.extend([
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
    ]);
    rules
        .into_iter()
        .find(|r| r.0)
        .map(|(_, s, why)| format!("{s} has no effect {why}; leave it out"))
}

impl Opts {
    /// The output letters both programs share (`-zQVCenNEIB`).
    pub fn out(&self) -> &OutputSwitches {
        match self.mode {
            Some(Mode::Tet) => &self.tet.output,
            _ => &self.tri.output,
        }
    }

    /// `-p`: a PSLG (tri) or a PLC or surface (tet).
    pub fn pslg(&self) -> bool {
        self.tri.pslg || self.tet.plc
    }

    /// `-r`: refine an existing mesh.
    pub fn refine_mesh(&self) -> bool {
        self.tri.refine_mesh || self.tet.refine_mesh
    }

    /// `-c`: keep the convex hull.
    pub fn convex_hull(&self) -> bool {
        self.tri.convex_hull || self.tet.convex_hull
    }

    /// `-A`: regional attributes in the `.ele`.
    pub fn region_attributes(&self) -> bool {
        self.tri.region_attributes || self.tet.region_attributes
    }

    /// `-v`: the Voronoi (power, with `-w`) diagram.
    pub fn voronoi(&self) -> bool {
        self.tri.voronoi || self.tet.voronoi
    }

    /// `-w`: a regular (weighted) triangulation/tetrahedralization.
    pub fn weights(&self) -> bool {
        self.tri.weights || self.tet.weights
    }

    /// `-a`: area (tri) or volume (tet) bounds, regional and, with a
    /// number, global.
    pub fn area(&self) -> bool {
        self.tri.regional_areas || self.tet.regional_volumes
    }

    /// `-a<x>`: the global area (tri) or volume (tet) bound.
    pub fn max_area(&self) -> Option<f64> {
        self.tri.max_area.or(self.tet.max_volume)
    }

    /// `-S<n>`: the Steiner point budget.
    pub fn max_steiner(&self) -> Option<usize> {
        self.tri.max_steiner.or(self.tet.max_steiner)
    }
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
    let mut o = Opts {
        mode: Some(mode),
        ..Opts::default()
    };
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
                "quiet" | "verbose" | "check" => {
                    flag()?;
                    let letter = match name {
                        "quiet" => "Q",
                        "verbose" => "V",
                        _ => "C",
                    };
                    match mode {
                        Mode::Tri => o.tri.add_switches(letter)?,
                        Mode::Tet => o.tet.add_switches(letter)?,
                    }
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
                    o.tet.keep_ratio = true
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
                "threads" => {
                    let n = crate::threads::parse(&value("--threads", inline, &mut it)?)?;
                    match mode {
                        Mode::Tri => o.tri.threads = Some(n),
                        Mode::Tet => o.threads = Some(n),
                    }
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
        let help = match mode {
            Mode::Tri => {
                o.tri.add_switches(&a[1..])?;
                o.tri.help
            }
            Mode::Tet => {
                o.tet.add_switches(&a[1..])?;
                o.tet.help
            }
        };
        if help {
            return Ok(Command::Help);
        }
        o.switches.push_str(&a[1..]);
    }
    match mode {
        Mode::Tri => o.tri.check()?,
        Mode::Tet => o.tet.check()?,
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
    use delone::switches::SwitchError;
    use delone::tri::refine::SegmentSplits;

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
                let r = match mode {
                    Mode::Tri => TriOptions::default().add_switches(&c.to_string()),
                    Mode::Tet => TetOptions::default().add_switches(&c.to_string()),
                };
                if matches!(r, Err(SwitchError::Unknown { .. })) {
                    continue;
                }
                known += 1;
                let not_yet = matches!(r, Err(SwitchError::NotImplemented { .. }));
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
        assert!(o.out().zero && o.out().check && o.out().edges && o.out().neigh && o.out().quiet);
        assert_eq!(o.out().verbose, 2);
        assert_eq!(o.vtu, Some("a.vtu".into()));
        assert_eq!(o.input, PathBuf::from("x.node"));
        let Ok(Command::Run(o)) = p(
            Mode::Tet,
            &["-fkF", "-o", "b.vtu", "--output-dir", "d", "y"],
        ) else {
            panic!()
        };
        assert!(o.tet.all_faces && o.tet.vtk_legacy && o.tet.no_face);
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
        assert!(o.voronoi() && o.weights());
        assert_eq!(o.lloyd, Some(5));
        assert_eq!(o.svg, Some("pic.svg".into()));
        let Ok(Command::Run(o)) = p(Mode::Tet, &["-v", "y"]) else {
            panic!()
        };
        assert!(o.voronoi());
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
        assert!(
            o.tri.second_order
                && o.tri.no_poly
                && o.out().edges
                && o.out().no_bound
                && o.svg_quality
        );
        assert_eq!(o.tri.min_angle, Some(30.0));
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
        assert_eq!(
            (o.tri.min_angle, o.area(), o.max_area()),
            (Some(20.0), false, None)
        );
        let o = run(&["-pq34.5a0.01eS100", "x"]);
        assert_eq!(o.tri.min_angle, Some(34.5));
        assert!(o.area() && o.out().edges);
        assert_eq!(o.max_area(), Some(0.01));
        assert_eq!(o.max_steiner(), Some(100));
        let o = run(&["-pa", "x"]);
        assert_eq!(
            (o.tri.min_angle, o.area(), o.max_area()),
            (None, true, None)
        );
        let o = run(&["-pqa.5", "x"]);
        assert_eq!((o.tri.min_angle, o.max_area()), (Some(20.0), Some(0.5)));
    }

    #[test]
    fn conforming_splits_jettison() {
        let run = |a: &[&str]| match p(Mode::Tri, a) {
            Ok(Command::Run(o)) => o,
            other => panic!("{other:?}"),
        };
        let o = run(&["-pD", "x"]);
        assert!(
            o.tri.conforming_delaunay
                && o.tri.segment_splits == SegmentSplits::All
                && !o.tri.jettison
        );
        let o = run(&["-pqY", "x"]);
        assert_eq!(o.tri.segment_splits, SegmentSplits::Interior);
        let o = run(&["-pqYYY", "x"]);
        assert_eq!(o.tri.segment_splits, SegmentSplits::None);
        let o = run(&["-rYD", "x"]);
        assert!(
            o.refine_mesh()
                && o.tri.conforming_delaunay
                && o.tri.segment_splits == SegmentSplits::Interior
        );
        let o = run(&["-pjD", "x"]);
        assert!(o.tri.jettison && o.tri.conforming_delaunay);
        assert!(
            matches!(p(Mode::Tri, &["-rj", "x"]), Err(Usage(m)) if m.starts_with("-j with -r"))
        );
        let o = run(&["-cj", "x"]);
        assert!(o.tri.jettison && o.convex_hull());
    }
}
