//! Reference executables: the `tetgen` and `triangle` command-line programs,
//! built on first use and run as black boxes (we run them and read their
//! output; their sources are never linked into, copied into or read for
//! delone).
//!
//! Two TetGen builds:
//!
//! * **TetGen 1.6.0**, the default 3D reference (programs `tetgen`,
//!   `tetgen-p`, `tetgen-pY`, `tetgen-pq`, `tetgen-pq-keep`): the sources of
//!   its official release, looked up at run time in `$DELONE_TETGEN_SRC` (a
//!   folder with `tetgen.cxx`) or else in `shared/reference/tetgen-1.6.0` of
//!   the nearest ancestor of this crate that has one, and compiled as its own
//!   makefile does: `predicates.cxx` with `-O0`, `tetgen.cxx` with `-O3`.
//! * **TetGen 1.5 as bundled (modified) in the `tritet` crate**, secondary
//!   (programs `tetgen15…`, run only when named): on the same switches it
//!   makes several times as many tetrahedra as 1.6 on large quality meshes,
//!   in several times the time, and many more Steiner points under `-p`.
//!   Its sources, and Triangle's, are looked up in `$DELONE_TRITET_SRC` (a
//!   `c_code` folder) if set, else `$CARGO_HOME/registry/src/*/tritet-*/c_code`
//!   (`~/.cargo` without `CARGO_HOME`), the highest version first, and
//!   compiled with `-O2`. The bundled `tetgen.h` defines `TETLIBRARY`; the
//!   executable is built from a three-line wrapper that includes the header,
//!   undefines the symbol and then includes `tetgen.cxx`, so its `main` is
//!   compiled.
//!
//! The compilers are `g++` / `gcc` (override with `$CXX` / `$CC`); the
//! executables go to `<target>/refbin/` (`$CARGO_TARGET_DIR` or the
//! workspace's `target`), where later calls find them. Nothing is compiled
//! at build time, so CI does not pay for it.
//!
//! Use (inside this crate):
//!
//! ```text
//! let tetgen = refbin::tetgen(refbin::Tetgen::V16)?;
//! Command::new(tetgen).arg("-v").arg("cube.node").status()
//! ```

use std::path::{Path, PathBuf};
use std::process::Command;

/// The directory of the cached executables: `<target>/refbin`.
pub fn dir() -> PathBuf {
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target"));
    target.join("refbin")
}

/// The bundled sources of the `tritet` crate (its `c_code` directory).
///
/// # Errors
/// A message when no `tritet-*/c_code` directory with `tetgen.cxx` is found.
pub fn sources() -> Result<PathBuf, String> {
    if let Some(d) = std::env::var_os("DELONE_TRITET_SRC") {
        let d = PathBuf::from(d);
        return if d.join("tetgen.cxx").is_file() {
            Ok(d)
        } else {
            Err(format!(
                "DELONE_TRITET_SRC={} has no tetgen.cxx",
                d.display()
            ))
        };
    }
    let home = std::env::var_os("CARGO_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cargo")))
        .ok_or("neither CARGO_HOME nor HOME is set")?;
    let registry = home.join("registry").join("src");
    let mut found: Vec<(Vec<u64>, PathBuf)> = Vec::new();
    let indexes = std::fs::read_dir(&registry)
        .map_err(|e| format!("cannot read {}: {e}", registry.display()))?;
    for index in indexes.flatten() {
        let Ok(crates) = std::fs::read_dir(index.path()) else {
            continue;
        };
        for c in crates.flatten() {
            let name = c.file_name().to_string_lossy().into_owned();
            let Some(version) = name.strip_prefix("tritet-") else {
                continue;
            };
            let code = c.path().join("c_code");
            if code.join("tetgen.cxx").is_file() {
                let key = version
                    .split(['.', '-'])
                    .map(|x| x.parse().unwrap_or(0))
                    .collect();
                found.push((key, code));
            }
        }
    }
    found.sort();
    found
        .pop()
        .map(|(_, p)| p)
        .ok_or_else(|| format!("no tritet-*/c_code/tetgen.cxx under {}", registry.display()))
}

/// Held while an executable is looked up and built: threads of one process
/// (the tests) share the temporary file names, which carry the process id.
static BUILDING: std::sync::Mutex<()> = std::sync::Mutex::new(());

fn building() -> std::sync::MutexGuard<'static, ()> {
    BUILDING
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

fn compile(exe: &Path, compiler: &str, args: &[&std::ffi::OsStr]) -> Result<(), String> {
    let out = Command::new(compiler)
        .args(args)
        .arg("-o")
        .arg(exe)
        .output()
        .map_err(|e| format!("cannot run {compiler}: {e}"))?;
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        let tail: Vec<&str> = err.lines().rev().take(20).collect();
        return Err(format!(
            "{compiler} failed building {}:\n{}",
            exe.display(),
            tail.into_iter().rev().collect::<Vec<_>>().join("\n")
        ));
    }
    Ok(())
}

/// A TetGen build the bench runs as a reference.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Tetgen {
    /// TetGen 1.6.0, the default 3D reference (programs `tetgen…`).
    V16,
    /// The modified TetGen 1.5 bundled in `tritet` (programs `tetgen15…`).
    V15,
}

impl Tetgen {
    /// The build a bench program name refers to: `tetgen15…` is
    /// [`Tetgen::V15`], every other `tetgen…` [`Tetgen::V16`].
    pub fn of(program: &str) -> Tetgen {
        if program.starts_with("tetgen15") {
            Tetgen::V15
        } else {
            Tetgen::V16
        }
    }
}

/// The `tetgen` executable of `build`, compiled on first use.
///
/// # Errors
/// A message when the sources are missing or the compiler fails.
pub fn tetgen(build: Tetgen) -> Result<PathBuf, String> {
    match build {
        Tetgen::V16 => tetgen16(),
        Tetgen::V15 => tetgen15(),
    }
}

/// TetGen 1.6.0's sources: `$DELONE_TETGEN_SRC`, else
/// `shared/reference/tetgen-1.6.0` in the nearest ancestor of this crate.
///
/// # Errors
/// A message naming where it looked when no folder with `tetgen.cxx` is found.
pub fn tetgen16_sources() -> Result<PathBuf, String> {
    if let Some(d) = std::env::var_os("DELONE_TETGEN_SRC") {
        let d = PathBuf::from(d);
        return if d.join("tetgen.cxx").is_file() {
            Ok(d)
        } else {
            Err(format!(
                "DELONE_TETGEN_SRC={} has no tetgen.cxx",
                d.display()
            ))
        };
    }
    let here = Path::new(env!("CARGO_MANIFEST_DIR"));
    here.ancestors()
        .map(|a| a.join("shared/reference/tetgen-1.6.0"))
        .find(|d| d.join("tetgen.cxx").is_file())
        .ok_or_else(|| {
            format!(
                "TetGen 1.6.0's sources not found: no shared/reference/tetgen-1.6.0/tetgen.cxx \
                 in any ancestor of {} (set DELONE_TETGEN_SRC)",
                here.display()
            )
        })
}

/// TetGen 1.6.0's executable `<target>/refbin/tetgen16`, compiled on first
/// use as its makefile does (`predicates.cxx` `-O0`, `tetgen.cxx` `-O3`).
fn tetgen16() -> Result<PathBuf, String> {
    let _building = building();
    let d = dir();
    let exe = d.join("tetgen16");
    if exe.is_file() {
        return Ok(exe);
    }
    let src = tetgen16_sources()?;
    std::fs::create_dir_all(&d).map_err(|e| format!("cannot create {}: {e}", d.display()))?;
    let cxx = std::env::var("CXX").unwrap_or_else(|_| "g++".into());
    let obj = d.join(format!("predicates16.{}.o", std::process::id()));
    compile(
        &obj,
        &cxx,
        &[
            "-O0".as_ref(),
            "-c".as_ref(),
            src.join("predicates.cxx").as_os_str(),
        ],
    )?;
    let tmp = d.join(format!("tetgen16.{}.tmp", std::process::id()));
    let built = compile(
        &tmp,
        &cxx,
        &[
            "-O3".as_ref(),
            "-w".as_ref(),
            src.join("tetgen.cxx").as_os_str(),
            obj.as_os_str(),
            "-lm".as_ref(),
        ],
    );
    std::fs::remove_file(&obj).ok();
    built?;
    std::fs::rename(&tmp, &exe).map_err(|e| format!("cannot move to {}: {e}", exe.display()))?;
    Ok(exe)
}

/// The `tetgen15` executable of `tritet`'s TetGen 1.5, compiled on first
/// use (`tetgen.cxx` + `predicates.cxx`, `-O2`, without `TETLIBRARY`).
fn tetgen15() -> Result<PathBuf, String> {
    let _building = building();
    let d = dir();
    let exe = d.join("tetgen15");
    if exe.is_file() {
        return Ok(exe);
    }
    let src = sources()?;
    std::fs::create_dir_all(&d).map_err(|e| format!("cannot create {}: {e}", d.display()))?;
    let wrapper = d.join("tetgen_main.cxx");
    std::fs::write(
        &wrapper,
        "#include \"tetgen.h\"\n#undef TETLIBRARY\n#include \"tetgen.cxx\"\n",
    )
    .map_err(|e| format!("cannot write {}: {e}", wrapper.display()))?;
    let cxx = std::env::var("CXX").unwrap_or_else(|_| "g++".into());
    let include = format!("-I{}", src.display());
    let tmp = d.join(format!("tetgen15.{}.tmp", std::process::id()));
    compile(
        &tmp,
        &cxx,
        &[
            "-O2".as_ref(),
            "-w".as_ref(),
            include.as_ref(),
            wrapper.as_os_str(),
            src.join("predicates.cxx").as_os_str(),
            "-lm".as_ref(),
        ],
    )?;
    std::fs::rename(&tmp, &exe).map_err(|e| format!("cannot move to {}: {e}", exe.display()))?;
    Ok(exe)
}

/// The `triangle` executable, compiled on first use (`triangle.c`, `-O2`,
/// without `TRILIBRARY`: the bundled file defines that symbol itself, so a
/// copy without that one line is compiled in `refbin/`, with `-DVOID=void`).
///
/// # Errors
/// A message when `triangle.c` is not bundled or the compiler fails.
pub fn triangle() -> Result<PathBuf, String> {
    let _building = building();
    let d = dir();
    let exe = d.join("triangle");
    if exe.is_file() {
        return Ok(exe);
    }
    let src = sources()?;
    let c = src.join("triangle.c");
    if !c.is_file() {
        return Err(format!("{} has no triangle.c", src.display()));
    }
    std::fs::create_dir_all(&d).map_err(|e| format!("cannot create {}: {e}", d.display()))?;
    let text =
        std::fs::read_to_string(&c).map_err(|e| format!("cannot read {}: {e}", c.display()))?;
    let exe_c = d.join("triangle_exe.c");
    let body: String = text
        .lines()
        .filter(|l| l.trim() != "#define TRILIBRARY")
        .flat_map(|l| [l, "\n"])
        .collect();
    std::fs::write(&exe_c, body).map_err(|e| format!("cannot write {}: {e}", exe_c.display()))?;
    let cc = std::env::var("CC").unwrap_or_else(|_| "gcc".into());
    let tmp = d.join(format!("triangle.{}.tmp", std::process::id()));
    compile(
        &tmp,
        &cc,
        &[
            "-O2".as_ref(),
            "-w".as_ref(),
            "-DVOID=void".as_ref(),
            exe_c.as_os_str(),
            "-lm".as_ref(),
        ],
    )?;
    std::fs::rename(&tmp, &exe).map_err(|e| format!("cannot move to {}: {e}", exe.display()))?;
    Ok(exe)
}

/// What one run of an external `tetgen` reported.
#[derive(Debug, Clone, PartialEq)]
pub struct TetgenRun {
    /// Seconds of TetGen's meshing phases as it prints them (every
    /// `… seconds:` line of its log but input, output and the total: 1.6
    /// prints Delaunay, surface mesh, boundary recovery, exterior removal,
    /// Delaunay recovery, refinement, mesh improvement and smoothing; 1.5
    /// names some phases differently): file input and output are left out,
    /// as they are for delone. TetGen measures them with `clock()`, CPU
    /// time of its single thread.
    pub seconds: f64,
    /// Tetrahedra in the output.
    pub tets: usize,
    /// Output points minus input points.
    pub steiner: usize,
    /// Peak resident memory of the process (kB), sampled from
    /// `/proc/PID/status` every millisecond (the last millisecond of growth
    /// may be missed).
    pub peak_kb: Option<u64>,
}

/// The value after `key` on a line of TetGen's summary, e.g. `Mesh points: 3024`.
fn field(out: &str, key: &str) -> Option<f64> {
    out.lines()
        .filter_map(|l| l.trim().strip_prefix(key))
        .filter_map(|r| r.trim().parse::<f64>().ok())
        .next_back()
}

/// The sum of the meshing phases in TetGen's log: every `NAME seconds:
/// VALUE` line except reading, writing and the total. Phases a run does
/// not have (refinement under bare `-p`) are not printed and count 0.
fn phase_seconds(out: &str) -> f64 {
    out.lines()
        .filter_map(|l| {
            let (name, value) = l.trim().split_once(" seconds:")?;
            let skip = ["Output", "Total running", "Input", "Reading"];
            (!skip.iter().any(|s| name.starts_with(s)))
                .then(|| value.trim().parse::<f64>().ok())
                .flatten()
        })
        .sum()
}

/// Writes the surface to a temporary `.off`, runs `tetgen SWITCHES` on it
/// and parses its summary; with `read_mesh`, also reads the output mesh.
fn run_tetgen(
    build: Tetgen,
    points: &[[f64; 3]],
    triangles: &[[u32; 3]],
    switches: &str,
    read_mesh: bool,
) -> Result<(TetgenRun, Option<NodeEle>), String> {
    use std::fmt::Write as _;
    let mut text = format!("OFF\n{} {} 0\n", points.len(), triangles.len());
    for q in points {
        let _ = writeln!(text, "{:?} {:?} {:?}", q[0], q[1], q[2]);
    }
    for t in triangles {
        let _ = writeln!(text, "3 {} {} {}", t[0], t[1], t[2]);
    }
    run_tetgen_bytes(build, text.as_bytes(), "off", switches, read_mesh)
}

/// Writes `bytes` to a temporary `s.EXT` (a TetGen input: `.node`, `.off`,
/// `.poly`, `.smesh`), runs `tetgen SWITCHES` on it and parses its
/// summary; with `read_mesh`, also reads the output mesh.
fn run_tetgen_bytes(
    build: Tetgen,
    bytes: &[u8],
    ext: &str,
    switches: &str,
    read_mesh: bool,
) -> Result<(TetgenRun, Option<NodeEle>), String> {
    let exe = tetgen(build)?;
    let dir = scratch("tg")?;
    let off = dir.join(format!("s.{ext}"));
    std::fs::write(&off, bytes).map_err(|e| format!("cannot write {}: {e}", off.display()))?;
    let run = run_sampled(&exe, &[switches.as_ref(), off.as_os_str()], &dir);
    let mesh = if read_mesh {
        read_node_ele(&dir.join("s.1.node"), &dir.join("s.1.ele"))
    } else {
        None
    };
    std::fs::remove_dir_all(&dir).ok();
    let (out, peak, _) = run?;
    let seconds = phase_seconds(&out);
    let tets = field(&out, "Mesh tetrahedra:").unwrap_or(0.0) as usize;
    if tets == 0 {
        let last = out
            .lines()
            .rev()
            .find(|l| !l.trim().is_empty())
            .unwrap_or("");
        return Err(format!("tetgen {switches} produced no tetrahedra: {last}"));
    }
    let input = field(&out, "Input points:").unwrap_or(0.0) as usize;
    let np = field(&out, "Mesh points:").unwrap_or(0.0) as usize;
    let run = TetgenRun {
        seconds,
        tets,
        steiner: np.saturating_sub(input),
        peak_kb: peak,
    };
    Ok((run, mesh))
}

/// Runs the reference `tetgen` without switches but `-NEF` (the Delaunay
/// tetrahedralization of a point set, no output files) on `points`
/// written to a temporary `.node` file.
///
/// # Errors
/// A message when TetGen cannot be built or run, or fails.
pub fn run_tetgen_points(build: Tetgen, points: &[[f64; 3]]) -> Result<TetgenRun, String> {
    use std::fmt::Write as _;
    let mut text = format!("{} 3 0 0\n", points.len());
    for (i, q) in points.iter().enumerate() {
        let _ = writeln!(text, "{i} {:?} {:?} {:?}", q[0], q[1], q[2]);
    }
    run_tetgen_bytes(build, text.as_bytes(), "node", "-NEF", false).map(|(r, _)| r)
}

/// Runs the reference `tetgen -p` (boundary recovery only, no quality) on a
/// closed triangle surface written to a temporary `.off` file.
///
/// # Errors
/// A message when TetGen cannot be built or run, or rejects the input.
pub fn run_tetgen_p(
    build: Tetgen,
    points: &[[f64; 3]],
    triangles: &[[u32; 3]],
) -> Result<TetgenRun, String> {
    run_tetgen(build, points, triangles, "-pNEF", false).map(|(r, _)| r)
}

/// Runs the reference `tetgen -pY` (boundary recovery preserving the
/// surface: Steiner points only inside the volume) like [`run_tetgen_p`].
///
/// # Errors
/// A message when TetGen cannot be built or run, or rejects the input.
pub fn run_tetgen_py(
    build: Tetgen,
    points: &[[f64; 3]],
    triangles: &[[u32; 3]],
) -> Result<TetgenRun, String> {
    run_tetgen(build, points, triangles, "-pYNEF", false).map(|(r, _)| r)
}

/// What one run of the external `tetgen -pqB` reported.
#[derive(Debug, Clone, PartialEq)]
pub struct TetgenQRun {
    /// Times (meshing phases, refinement and optimization included),
    /// tetrahedra, Steiner points, peak memory.
    pub run: TetgenRun,
    /// Minimum dihedral angle (degrees) of the output, from its `.node`
    /// and `.ele` files (`None` when they could not be read).
    pub min_dihedral: Option<f64>,
}

/// Runs the reference `tetgen -pqB` (quality refinement with radius-edge
/// bound `ratio`) on a closed triangle surface and reads its output mesh
/// for the minimum dihedral angle; with `keep_facets`, `tetgen -p180qB`:
/// every input triangle kept as a facet, as delone does.
///
/// # Errors
/// A message when TetGen cannot be built or run, or rejects the input.
pub fn run_tetgen_pq(
    build: Tetgen,
    points: &[[f64; 3]],
    triangles: &[[u32; 3]],
    ratio: f64,
    keep_facets: bool,
) -> Result<TetgenQRun, String> {
    // `-p180`: TetGen's facet angle tolerance at 180° (its default 179.9°
    // merges neighbouring triangles meeting at 179.9° or more into one
    // facet and re-triangulates across their shared edges; delone keeps
    // every input triangle).
    let p = if keep_facets { "-p180" } else { "-p" };
    let (run, mesh) = run_tetgen(build, points, triangles, &format!("{p}q{ratio}F"), true)?;
    let min_dihedral = mesh.map(|(p, t)| delone::tet::quality::TetStats::of(&p, &t).min_dihedral);
    Ok(TetgenQRun { run, min_dihedral })
}

/// Runs the reference `tetgen -p` (`ratio` `None`) or `tetgen -pqB` on a
/// TetGen PLC file's content (`ext` `poly` or `smesh`), reading the output
/// mesh for the minimum dihedral angle when refining.
///
/// # Errors
/// A message when TetGen cannot be built or run, or rejects the input.
pub fn run_tetgen_plc(
    build: Tetgen,
    bytes: &[u8],
    ext: &str,
    ratio: Option<f64>,
) -> Result<TetgenQRun, String> {
    let switches = ratio.map_or_else(|| "-pNEF".to_string(), |q| format!("-pq{q}F"));
    let (run, mesh) = run_tetgen_bytes(build, bytes, ext, &switches, ratio.is_some())?;
    let min_dihedral = mesh.map(|(p, t)| delone::tet::quality::TetStats::of(&p, &t).min_dihedral);
    Ok(TetgenQRun { run, min_dihedral })
}

/// Runs TetGen 1.6's `tetgen -pqB` like [`run_tetgen_pq`] and returns its
/// output mesh.
///
/// # Errors
/// A message when TetGen cannot be built or run, rejects the input, or its
/// output files cannot be read.
pub fn tetgen_pq_mesh(
    points: &[[f64; 3]],
    triangles: &[[u32; 3]],
    ratio: f64,
) -> Result<NodeEle, String> {
    run_tetgen(
        Tetgen::V16,
        points,
        triangles,
        &format!("-pq{ratio}F"),
        true,
    )?
    .1
    .ok_or_else(|| "cannot read TetGen's output mesh".to_string())
}

/// Points and tetrahedra of a TetGen output.
pub type NodeEle = (Vec<[f64; 3]>, Vec<[u32; 4]>);

/// Reads TetGen's `.node` and `.ele` files (first index 0 or 1).
fn read_node_ele(node: &Path, ele: &Path) -> Option<NodeEle> {
    fn rows(text: &str) -> impl Iterator<Item = Vec<&str>> {
        text.lines()
            .map(|l| l.split('#').next().unwrap_or(""))
            .map(|l| l.split_whitespace().collect::<Vec<_>>())
            .filter(|w| !w.is_empty())
    }
    let nt = std::fs::read_to_string(node).ok()?;
    let et = std::fs::read_to_string(ele).ok()?;
    let mut first = None;
    let mut pts = Vec::new();
    for w in rows(&nt).skip(1) {
        let i: i64 = w.first()?.parse().ok()?;
        first.get_or_insert(i);
        let c = |k: usize| w.get(k).and_then(|x| x.parse::<f64>().ok());
        pts.push([c(1)?, c(2)?, c(3)?]);
    }
    let base = first.unwrap_or(0);
    let mut tets = Vec::new();
    for w in rows(&et).skip(1) {
        let v = |k: usize| {
            w.get(k)
                .and_then(|x| x.parse::<i64>().ok())
                .and_then(|x| u32::try_from(x - base).ok())
        };
        tets.push([v(1)?, v(2)?, v(3)?, v(4)?]);
    }
    Some((pts, tets))
}

/// What one run of the external `triangle` reported.
#[derive(Debug, Clone, PartialEq)]
pub struct TriangleRun {
    /// Seconds of Triangle's meshing phases as it prints them with `-V`
    /// (Delaunay, segments, holes, quality; millisecond resolution): file
    /// input and output are left out, as they are for delone.
    pub seconds: f64,
    /// Triangles in the output.
    pub triangles: usize,
    /// Output vertices minus input vertices.
    pub steiner: usize,
    /// Peak resident memory of the process (kB), sampled as for TetGen.
    pub peak_kb: Option<u64>,
    /// CPU time of the whole process (seconds, from `/proc/PID/schedstat`
    /// sampled every millisecond: up to a millisecond short; includes
    /// reading the `.poly` file, which is small for the `2d-poly` cases).
    pub cpu_seconds: Option<f64>,
    /// Milliseconds of Triangle's phases as printed: Delaunay + segments +
    /// holes, and quality refinement.
    pub phase_ms: [f64; 2],
}

/// Runs `exe` with `args` in `dir`, sampling its peak RSS and CPU time
/// every millisecond; returns (standard output, peak kB, CPU seconds).
fn run_sampled(
    exe: &Path,
    args: &[&std::ffi::OsStr],
    dir: &Path,
) -> Result<(String, Option<u64>, Option<f64>), String> {
    let mut child = Command::new(exe)
        .args(args)
        .current_dir(dir)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::null())
        .spawn()
        .map_err(|e| format!("cannot run {}: {e}", exe.display()))?;
    let status_file = format!("/proc/{}/status", child.id());
    let sched_file = format!("/proc/{}/schedstat", child.id());
    let mut peak: Option<u64> = None;
    let mut cpu_ns: Option<u64> = None;
    let stdout = child.stdout.take();
    let reader = std::thread::spawn(move || {
        let mut s = String::new();
        if let Some(mut o) = stdout {
            use std::io::Read as _;
            let _ = o.read_to_string(&mut s);
        }
        s
    });
    let status = loop {
        if let Ok(text) = std::fs::read_to_string(&status_file) {
            let hwm = text
                .lines()
                .find_map(|l| l.strip_prefix("VmHWM:"))
                .and_then(|r| r.trim().trim_end_matches("kB").trim().parse::<u64>().ok());
            peak = peak.max(hwm);
        }
        if let Some(ns) = crate::child::schedstat_ns(&sched_file) {
            cpu_ns = cpu_ns.max(Some(ns));
        }
        match child.try_wait() {
            Ok(Some(st)) => break st,
            Ok(None) => std::thread::sleep(std::time::Duration::from_millis(1)),
            Err(e) => return Err(format!("waiting for {}: {e}", exe.display())),
        }
    };
    let out = reader.join().unwrap_or_default();
    if !status.success() {
        let last = out
            .lines()
            .rev()
            .find(|l| !l.trim().is_empty())
            .unwrap_or("");
        return Err(format!("{} failed ({status}): {last}", exe.display()));
    }
    Ok((out, peak, cpu_ns.map(|ns| ns as f64 * 1e-9)))
}

/// A fresh temporary directory for one reference run.
fn scratch(tag: &str) -> Result<PathBuf, String> {
    let dir = std::env::temp_dir().join(format!("delone-bench-{tag}{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    Ok(dir)
}

/// Runs the reference `triangle -p` (plus `q[angle]` / `a[area]` when
/// given) on `pslg`, written to a temporary `.poly` file.
///
/// # Errors
/// A message when Triangle cannot be built or run, or fails.
pub fn run_triangle_p(
    pslg: &delone::model::pslg::Pslg,
    min_angle: Option<f64>,
    max_area: Option<f64>,
) -> Result<TriangleRun, String> {
    use std::fmt::Write as _;
    let exe = triangle()?;
    let dir = scratch("tri")?;
    let file = dir.join("s.poly");
    let mut t = format!("{} 2 0 1\n", pslg.points.len());
    for (i, q) in pslg.points.iter().enumerate() {
        let m = pslg.point_markers.get(i).copied().unwrap_or(0);
        let _ = writeln!(t, "{i} {:?} {:?} {m}", q[0], q[1]);
    }
    let _ = writeln!(t, "{} 1", pslg.segments.len());
    for (i, s) in pslg.segments.iter().enumerate() {
        let m = pslg.segment_markers.get(i).copied().unwrap_or(0);
        let _ = writeln!(t, "{i} {} {} {m}", s[0], s[1]);
    }
    let _ = writeln!(t, "{}", pslg.holes.len());
    for (i, h) in pslg.holes.iter().enumerate() {
        let _ = writeln!(t, "{i} {:?} {:?}", h[0], h[1]);
    }
    let _ = writeln!(t, "{}", pslg.regions.len());
    for (i, r) in pslg.regions.iter().enumerate() {
        let _ = writeln!(
            t,
            "{i} {:?} {:?} {:?} {:?}",
            r.point[0], r.point[1], r.attribute, r.max_area
        );
    }
    std::fs::write(&file, t).map_err(|e| format!("cannot write {}: {e}", file.display()))?;
    let mut sw = String::from("-pzNEPV");
    if let Some(a) = min_angle {
        let _ = write!(sw, "q{a}");
    }
    if let Some(a) = max_area {
        let _ = write!(sw, "a{a:?}");
    }
    let run = run_sampled(&exe, &[sw.as_ref(), file.as_os_str()], &dir);
    std::fs::remove_dir_all(&dir).ok();
    let (out, peak_kb, cpu_seconds) = run?;
    let ms = |keys: &[&str]| keys.iter().filter_map(|k| field(&out, k)).sum::<f64>();
    let phase_ms = [
        ms(&[
            "Delaunay milliseconds:",
            "Segment milliseconds:",
            "Hole milliseconds:",
        ]),
        ms(&["Quality milliseconds:"]),
    ];
    let ms = phase_ms[0] + phase_ms[1];
    let triangles = field(&out, "Mesh triangles:").unwrap_or(0.0) as usize;
    let input = field(&out, "Input vertices:").unwrap_or(0.0) as usize;
    let mesh = field(&out, "Mesh vertices:").unwrap_or(0.0) as usize;
    Ok(TriangleRun {
        seconds: ms / 1000.0,
        triangles,
        steiner: mesh.saturating_sub(input),
        peak_kb,
        cpu_seconds,
        phase_ms,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Slow (compiles TetGen): `cargo test -p delone-bench -- --ignored refbin`.
    #[test]
    #[ignore]
    fn refbin_builds_and_runs() {
        let out = Command::new(triangle().unwrap())
            .arg("-h")
            .output()
            .unwrap();
        assert!(String::from_utf8_lossy(&out.stdout).contains("Triangle"));
        let dir = std::env::temp_dir().join(format!("refbin{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let node = dir.join("t.node");
        std::fs::write(&node, "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n").unwrap();
        for build in [Tetgen::V16, Tetgen::V15] {
            let st = Command::new(tetgen(build).unwrap())
                .arg("-Q")
                .arg(&node)
                .status()
                .unwrap();
            assert!(st.success(), "{build:?}");
            let ele = std::fs::read_to_string(dir.join("t.1.ele")).unwrap();
            assert!(ele.starts_with("1  4  0"), "{build:?}: {ele}");
            std::fs::remove_file(dir.join("t.1.ele")).unwrap();
        }
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn program_names_pick_the_build() {
        assert_eq!(Tetgen::of("tetgen-pq"), Tetgen::V16);
        assert_eq!(Tetgen::of("tetgen"), Tetgen::V16);
        assert_eq!(Tetgen::of("tetgen15-pq"), Tetgen::V15);
        assert_eq!(Tetgen::of("tetgen15"), Tetgen::V15);
    }

    #[test]
    fn phase_seconds_sum_the_meshing_phases_only() {
        let log = "Opening s.off.\nDelaunay seconds:  0.5\nSurface mesh seconds:  0.25\n\
                   Boundary recovery seconds:  1e-3\nRefinement seconds:  2\n\
                   Mesh improvement seconds:  0.125\nOutput seconds:  9\n\
                   Total running seconds:  99\n";
        assert!(
            (phase_seconds(log) - 2.876).abs() < 1e-12,
            "{}",
            phase_seconds(log)
        );
        assert_eq!(phase_seconds("no phases"), 0.0);
    }

    /// Slow (compiles TetGen): `cargo test -p delone-bench -- --ignored refbin`.
    #[test]
    #[ignore]
    fn refbin_tetgen_p_on_a_cube() {
        let pts: Vec<[f64; 3]> = (0..8)
            .map(|i| [(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64])
            .collect();
        let tris = [
            [0, 2, 1],
            [1, 2, 3],
            [4, 5, 6],
            [5, 7, 6],
            [0, 1, 4],
            [1, 5, 4],
            [2, 6, 3],
            [3, 6, 7],
            [0, 4, 2],
            [2, 4, 6],
            [1, 3, 5],
            [3, 7, 5],
        ];
        for build in [Tetgen::V16, Tetgen::V15] {
            let r = run_tetgen_p(build, &pts, &tris).unwrap();
            assert!(r.tets >= 5 && r.tets <= 6, "{build:?} {r:?}");
            assert_eq!(r.steiner, 0, "{build:?}");
            assert!(r.peak_kb.is_some_and(|k| k > 0), "{build:?}");
        }
        // The cube's eight corners alone: a Delaunay tetrahedralization.
        let r = run_tetgen_points(Tetgen::V16, &pts).unwrap();
        assert!(r.tets >= 5 && r.tets <= 6, "{r:?}");
    }

    /// Slow (compiles Triangle): `cargo test -p delone-bench -- --ignored refbin`.
    #[test]
    #[ignore]
    fn refbin_triangle_p_on_a_square_with_a_hole() {
        let g = delone::model::pslg::Pslg {
            points: vec![
                [0., 0.],
                [4., 0.],
                [4., 4.],
                [0., 4.],
                [1., 1.],
                [3., 1.],
                [3., 3.],
                [1., 3.],
            ],
            segments: vec![
                [0, 1],
                [1, 2],
                [2, 3],
                [3, 0],
                [4, 5],
                [5, 6],
                [6, 7],
                [7, 4],
            ],
            holes: vec![[2., 2.]],
            ..Default::default()
        };
        let r = run_triangle_p(&g, None, None).unwrap();
        assert_eq!((r.triangles, r.steiner), (8, 0), "{r:?}");
        let q = run_triangle_p(&g, Some(30.0), Some(0.1)).unwrap();
        assert!(q.triangles > 100 && q.steiner > 50, "{q:?}");
    }
}
