//! The one guard between a run's inputs and its outputs: no output ever
//! overwrites a file the run reads, and a refused run writes nothing.
//!
//! * Every input file (the main input and its companions: `.node`, `.ele`,
//!   `.face`, `.area`, `.poly`, `.smesh`, `.mesh`, `.off`, `.stl`, `.ply`,
//!   `.obj`, `.mtr`, `.weight`, `.b.*`, ...) is read through [`read`] /
//!   [`read_to_string`], which record it.
//! * Each run states the outputs it may write, with the switch that asks
//!   for each, through [`plan`] (computed from the switches alone by
//!   [`outputs`]).
//! * Every output file is created through [`create`]. Its first call checks
//!   the whole plan against the recorded inputs and refuses the run (exit
//!   code 2, naming the file and the switch) before anything is written;
//!   every call also refuses its own path when it is an input (a guard for
//!   an output missing from the plan; in debug builds such an output is a
//!   bug and panics, so the CLI tests keep the plan complete).

use std::fs::File;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use crate::args::{Mode, Opts};
use crate::fail::{input_err, Failure};
use crate::paths::with_ext;

#[derive(Default)]
struct State {
    /// The files read, as named.
    inputs: Vec<PathBuf>,
    /// The outputs the run may write: what asks for it, and its path.
    plan: Vec<(String, PathBuf)>,
    /// How many of `inputs` have been checked against `plan`.
    checked: usize,
    /// Whether `plan` was called.
    planned: bool,
}

static STATE: Mutex<State> = Mutex::new(State {
    inputs: Vec::new(),
    plan: Vec::new(),
    checked: 0,
    planned: false,
});

fn state() -> std::sync::MutexGuard<'static, State> {
    STATE.lock().unwrap_or_else(|e| e.into_inner())
}

/// Records `path` as an input of the run.
pub fn note_input(path: &Path) {
    state().inputs.push(path.to_path_buf());
}

/// Reads an input file, recording it.
pub fn read(path: &Path) -> std::io::Result<Vec<u8>> {
    note_input(path);
    std::fs::read(path)
}

/// [`read`] with a large file read in as many parts as `threads`, side by
/// side (copying from the page cache and the first touch of the buffer's
/// pages are most of the time of a read).
pub fn read_threads(path: &Path, threads: usize) -> std::io::Result<Vec<u8>> {
    note_input(path);
    #[cfg(unix)]
    if let Some(bytes) = read_parts(path, threads, 8 << 20) {
        return Ok(bytes);
    }
    std::fs::read(path)
}

/// The bytes of the file at `path` read in up to `threads` parts of
/// `min_part` bytes at least on as many threads; `None` for a small file or
/// when anything fails or the file changes length meanwhile (the caller
/// then reads it the ordinary way, which also reports the error).
#[cfg(unix)]
fn read_parts(path: &Path, threads: usize, min_part: usize) -> Option<Vec<u8>> {
    use std::os::unix::fs::FileExt;
    let file = File::open(path).ok()?;
    let n = usize::try_from(file.metadata().ok()?.len()).ok()?;
    let parts = threads.min(n / min_part.max(1));
    if parts < 2 {
        return None;
    }
    let mut buf = vec![0u8; n];
    let step = n.div_ceil(parts);
    let file = &file;
    let ok = std::thread::scope(|s| {
        let mut chunks = buf.chunks_mut(step).enumerate();
        let first = chunks.next();
        let others: Vec<_> = chunks
            .map(|(k, part)| s.spawn(move || file.read_exact_at(part, (k * step) as u64)))
            .collect();
        let mut ok = first.is_none_or(|(_, part)| file.read_exact_at(part, 0).is_ok());
        for h in others {
            ok &= h.join().is_ok_and(|r| r.is_ok());
        }
        ok
    });
    let same = file.metadata().is_ok_and(|m| m.len() == n as u64);
    (ok && same).then_some(buf)
}

/// Reads an input text file, recording it.
pub fn read_to_string(path: &Path) -> std::io::Result<String> {
    note_input(path);
    std::fs::read_to_string(path)
}

/// Whether `a` and `b` name the same existing file (same device and inode
/// on Unix, else the same canonical path).
fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let (Ok(x), Ok(y)) = (std::fs::metadata(a), std::fs::metadata(b)) {
            return x.dev() == y.dev() && x.ino() == y.ino();
        }
    }
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    }
}

/// Which kind of run writes the outputs (see [`outputs`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// `tri` / `tet` of a `.node` point set.
    Points,
    /// `tri -p` / `tet -p`.
    Domain,
    /// `tri -r` / `tet -r`.
    Refine,
}

/// Every output a run of `mode`/`kind` with switches `o` may write next to
/// output base `out`, with the switch (or file kind) that asks for it.
pub fn outputs(mode: Mode, kind: Kind, o: &Opts, out: &Path) -> Vec<(String, PathBuf)> {
    let mut v: Vec<(String, PathBuf)> = Vec::new();
    let mut base = |ext: &str, why: &str| {
        let label = if o.out().no_iteration {
            format!("the .{ext} output{why} (named after the input by -I)")
        } else {
            format!("the .{ext} output{why}")
        };
        v.push((label, with_ext(out, ext)))
    };
    if !o.out().no_node {
        base("node", "");
    }
    if !o.out().no_ele {
        base("ele", "");
    }
    let tet = mode == Mode::Tet;
    if tet && !o.tet.no_face {
        base("face", "");
    }
    if o.out().edges && !(tet && o.tet.no_face) {
        base("edge", " of -e");
    }
    if o.out().neigh {
        base("neigh", " of -n");
    }
    if tet && o.tet.vtk_legacy {
        base("vtk", " of -k");
    }
    if o.vtu.is_none() && o.vtu_ascii {
        base("vtu", " of --vtu-ascii");
    }
    match (mode, kind) {
        (Mode::Tri, Kind::Points) => {
            if o.convex_hull() && !o.tri.no_poly {
                base("poly", " of -c");
            }
        }
        (Mode::Tri, _) => {
            if !o.tri.no_poly {
                base("poly", "");
            }
        }
        (Mode::Tet, Kind::Points) => {}
        (Mode::Tet, _) => {
            if o.tet.medit && o.medit.is_none() {
                base("mesh", " of -g");
            }
        }
    }
    if o.voronoi() && kind == Kind::Points {
        base("v.node", " of -v");
        base("v.edge", " of -v");
        if tet {
            base("v.face", " of -v");
            base("v.cell", " of -v");
        }
    }
    if tet && kind != Kind::Points {
        // The VTK outputs of a domain mesh have a companion file of the
        // faces on input facets.
        let vtu = o
            .vtu
            .clone()
            .or_else(|| o.vtu_ascii.then(|| with_ext(out, "vtu")));
        if let Some(p) = vtu {
            v.push((
                "the faces companion of the .vtu output".to_string(),
                crate::paths::face_companion(&p),
            ));
        }
        if o.tet.vtk_legacy {
            v.push((
                "the faces companion of -k's .vtk".to_string(),
                crate::paths::face_companion(&with_ext(out, "vtk")),
            ));
        }
    }
    let named: [(&str, &Option<PathBuf>); 7] = [
        ("-o/--vtu", &o.vtu),
        ("--svg", &o.svg),
        ("--png", &o.png),
        ("--stats-json", &o.stats_json),
        ("--medit", &o.medit),
        ("--gmsh", &o.gmsh),
        ("--cells-vtu", &o.cells_vtu),
    ];
    for (switch, p) in named {
        if let Some(p) = p {
            v.push((format!("the output of {switch}"), p.clone()));
        }
    }
    v
}

/// States the outputs the run may write (see [`outputs`]).
pub fn plan(mode: Mode, kind: Kind, o: &Opts, out: &Path) {
    let list = outputs(mode, kind, o, out);
    let mut s = state();
    s.plan = list;
    s.planned = true;
    s.checked = 0;
}

/// The refusal when output `path` (asked for by `label`) is input `input`.
fn refusal(label: &str, path: &Path, input: &Path) -> Failure {
    Failure {
        message: format!(
            "{label}, {}, would overwrite the input file {}; nothing was written \
             (choose another name, drop -I, or use --output-dir)",
            path.display(),
            input.display()
        ),
        code: 2,
    }
}

/// Checks the plan against the inputs read so far (done again by
/// [`create`] when inputs were read since; call it right after reading to
/// refuse before a long computation).
pub fn check() -> Result<(), Failure> {
    let mut s = state();
    for (label, p) in &s.plan {
        if let Some(i) = s.inputs.iter().find(|i| same_file(p, i)) {
            return Err(refusal(label, p, i));
        }
    }
    s.checked = s.inputs.len();
    Ok(())
}

/// Creates output file `path`: the plan is checked first (once), and
/// `path` itself must not be an input.
pub fn create(path: &Path) -> Result<File, Failure> {
    let (checked, planned) = {
        let s = state();
        (s.checked == s.inputs.len(), s.planned)
    };
    if !checked {
        check()?;
    }
    {
        let s = state();
        if let Some(i) = s.inputs.iter().find(|i| same_file(path, i)) {
            return Err(refusal("an output", path, i));
        }
        debug_assert!(
            planned && s.plan.iter().any(|(_, p)| p == path),
            "output {} is missing from the guard's plan",
            path.display()
        );
    }
    File::create(path).map_err(|e| Failure {
        message: format!("cannot create {}: {e}", path.display()),
        code: 1,
    })
}

/// Writes `bytes` to output `path` through [`create`].
pub fn write_bytes(path: &Path, bytes: &[u8]) -> Result<(), Failure> {
    use std::io::Write;
    let mut f = create(path)?;
    f.write_all(bytes).map_err(|e| Failure {
        message: format!("cannot write {}: {e}", path.display()),
        code: 1,
    })
}

/// Creates output `path` ([`create`]) and writes it through `f`; a write
/// error names the file.
pub fn write(
    path: &Path,
    f: impl FnOnce(std::fs::File) -> Result<(), delone_io::IoError>,
) -> Result<(), Failure> {
    let file = create(path)?;
    f(file).map_err(|e| input_err(format!("{}: {e}", path.display())))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Read in parts, a file gives the bytes `std::fs::read` gives, for any
    /// number of parts (files of one part are left to `std::fs::read`).
    #[test]
    #[cfg(unix)]
    fn read_in_parts_gives_the_file() {
        let dir = std::env::temp_dir().join(format!("delone-guard-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("bytes.node");
        let mut x = 0x9E37_79B9u32;
        let bytes: Vec<u8> = (0..100_003)
            .map(|_| {
                x ^= x << 13;
                x ^= x >> 17;
                x ^= x << 5;
                x as u8
            })
            .collect();
        std::fs::write(&path, &bytes).unwrap();
        for threads in [1, 2, 3, 7] {
            let got = read_parts(&path, threads, 1000);
            assert_eq!(got.is_some(), threads > 1);
            if let Some(got) = got {
                assert!(got == bytes, "{threads} parts");
            }
        }
        assert!(read_parts(&path, 4, 60_000).is_none());
        assert!(read_threads(&path, 3).unwrap() == bytes);
        assert!(read_parts(&dir.join("missing.node"), 2, 1).is_none());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
