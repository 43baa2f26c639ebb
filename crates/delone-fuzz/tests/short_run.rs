//! The short fuzz run of CI, on stable Rust: every target of `delone_fuzz`
//! on its seeds (built-in samples and the shared corpus) and on mutations of
//! them, for `DELONE_FUZZ_SECS` seconds per target (default 2).
//!
//! Checked for every input: no panic (the target's own checks included),
//! no single execution longer than `DELONE_FUZZ_CASE_SECS` (default 5, a
//! hang shows as that), and no allocation larger than 64 MiB or 256 bytes
//! per input byte, whichever is larger (a header count trusted for a
//! reservation shows as that). A finding is written to
//! `target/fuzz-findings/<target>-<n>` and the test fails naming it.
#![allow(unsafe_code)] // the allocation-tracking allocator below

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use delone_fuzz::{mutate, seeds, Rng, Target, TARGETS};

/// The system allocator, recording the largest single request made while
/// `TRACK` is set (by any thread: tests run on one thread here, see
/// `fuzz_all`).
struct Tracking;

static TRACK: AtomicBool = AtomicBool::new(false);
static LARGEST: AtomicUsize = AtomicUsize::new(0);

// SAFETY: forwards every call to `System` unchanged; only records sizes.
unsafe impl GlobalAlloc for Tracking {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if TRACK.load(Ordering::Relaxed) {
            LARGEST.fetch_max(layout.size(), Ordering::Relaxed);
        }
        // SAFETY: same contract as the caller's.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: same contract as the caller's.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if TRACK.load(Ordering::Relaxed) {
            LARGEST.fetch_max(new_size, Ordering::Relaxed);
        }
        // SAFETY: same contract as the caller's.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static ALLOC: Tracking = Tracking;

fn env_secs(name: &str, default: f64) -> Duration {
    let s = std::env::var(name)
        .ok()
        .and_then(|v| v.parse::<f64>().ok())
        .unwrap_or(default);
    Duration::from_secs_f64(s.max(0.0))
}

fn save(target: &Target, n: usize, input: &[u8]) -> String {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("../fuzz-findings");
    let _ = std::fs::create_dir_all(&dir);
    let p = dir.join(format!("{}-{n}", target.name));
    let _ = std::fs::write(&p, input);
    p.display().to_string()
}

/// Runs one input; `Err` describes a finding.
fn one(target: &Target, input: &[u8], case_limit: Duration) -> Result<(), String> {
    LARGEST.store(0, Ordering::SeqCst);
    TRACK.store(true, Ordering::SeqCst);
    let t0 = Instant::now();
    let r = std::panic::catch_unwind(|| (target.run)(input));
    let took = t0.elapsed();
    TRACK.store(false, Ordering::SeqCst);
    let largest = LARGEST.load(Ordering::SeqCst);
    let limit = (64 << 20usize).max(256 * input.len());
    if let Err(e) = r {
        let msg = e
            .downcast_ref::<String>()
            .cloned()
            .or_else(|| e.downcast_ref::<&str>().map(|s| s.to_string()))
            .unwrap_or_default();
        return Err(format!("panicked: {msg}"));
    }
    if took > case_limit {
        return Err(format!("took {took:?} (limit {case_limit:?})"));
    }
    if largest > limit {
        return Err(format!(
            "allocated {largest} bytes at once for {} input bytes",
            input.len()
        ));
    }
    Ok(())
}

fn run_target(target: &Target, corpus: Option<&std::path::Path>) -> (usize, Vec<String>) {
    let budget = env_secs("DELONE_FUZZ_SECS", 2.0);
    let case_limit = env_secs("DELONE_FUZZ_CASE_SECS", 5.0);
    let seeds = seeds(target, corpus, 64 << 10);
    let mut findings = Vec::new();
    let mut execs = 0;
    let mut check = |input: &[u8], findings: &mut Vec<String>| {
        execs += 1;
        if let Err(e) = one(target, input, case_limit) {
            let path = save(target, findings.len(), input);
            findings.push(format!("{}: {e} (input saved to {path})", target.name));
        }
    };
    for s in &seeds {
        check(s, &mut findings);
    }
    // Fixed seed per target: a run repeats, and a finding reproduces.
    let mut rng = Rng::new(target.name.bytes().fold(0x5eed, |h: u64, b| {
        h.wrapping_mul(31).wrapping_add(u64::from(b))
    }));
    let t0 = Instant::now();
    while t0.elapsed() < budget && findings.len() < 5 {
        let s = &seeds[rng.below(seeds.len())];
        let m = mutate(s, &mut rng);
        check(&m, &mut findings);
    }
    (execs, findings)
}

/// One test for all targets so that the allocation tracking sees only the
/// target under test (the other tests of this binary would allocate too).
#[test]
fn fuzz_all() {
    let corpus = delone_testdata::corpus_dir(env!("CARGO_MANIFEST_DIR"));
    let only = std::env::var("DELONE_FUZZ_TARGET").ok();
    let mut all = Vec::new();
    for t in TARGETS {
        if only.as_deref().is_some_and(|o| o != t.name) {
            continue;
        }
        let (execs, findings) = run_target(t, corpus.as_deref());
        // Straight to the stream so that CI's log shows the counts.
        use std::io::Write;
        let _ = writeln!(
            std::io::stderr(),
            "fuzz {}: {execs} executions, {} findings",
            t.name,
            findings.len()
        );
        all.extend(findings);
    }
    assert!(all.is_empty(), "fuzz findings:\n{}", all.join("\n"));
}

/// Regression inputs: each one was a finding once (see `fuzz/README.md`).
#[test]
fn known_findings_stay_fixed() {
    for (name, input) in REGRESSIONS {
        let t = delone_fuzz::target(name).unwrap();
        (t.run)(input);
    }
}

const REGRESSIONS: &[(&str, &[u8])] = &[
    // `SolAtVertices` of 4e9 (and 4.29e9) vertices with no field: the
    // reader accepted it and the writer looped over every vertex; a
    // solution needs a field.
    (
        "sol",
        include_bytes!("../../../fuzz/regressions/sol-no-fields"),
    ),
    (
        "sol",
        include_bytes!("../../../fuzz/regressions/sol-no-fields-2"),
    ),
    // 3D vertices, then `Dimension 2`: the mesh read as 2D kept z, which a
    // 2D file cannot write back; the dimension cannot change after vertices.
    (
        "medit",
        include_bytes!("../../../fuzz/regressions/medit-dimension-change"),
    ),
    // `-nan` read, `NaN` written: the round-trip checks compare every NaN
    // as one.
    (
        "medit",
        include_bytes!("../../../fuzz/regressions/medit-negative-nan"),
    ),
    (
        "sol",
        include_bytes!("../../../fuzz/regressions/sol-negative-nan"),
    ),
    // Three nearly collinear points: `tri::validate` measured the hull's
    // winding in floating point and rejected a valid sliver triangle.
    (
        "delaunay2",
        include_bytes!("../../../fuzz/regressions/delaunay2-hull-sliver"),
    ),
    // 80 points mixing 2e139 with small integers: the 2D kernel panicked
    // (predicates underflowed after rescaling); now a CoordinateRange error.
    (
        "delaunay2",
        include_bytes!("../../../fuzz/regressions/delaunay2-range-1e139"),
    ),
    // Points spanning 1e132: `tri::validate` reported a false violation.
    (
        "delaunay2",
        include_bytes!("../../../fuzz/regressions/delaunay2-range-1e132"),
    ),
    // A segment reaching 1e23 crossing one near 1: the crossing was judged
    // outside the long piece by a rounded dot product and replaced by the
    // nearest end, off the short segment (`check_cdt` rejected it).
    (
        "cdt_poly",
        include_bytes!("../../../fuzz/regressions/cdt_poly-crossing-1e23"),
    ),
    // A point 4e43 on the x-axis among points near 1: `check_cdt` judged a
    // vertex on a segment 4e43 long outside it by a rounded dot product.
    (
        "cdt_poly",
        include_bytes!("../../../fuzz/regressions/cdt_poly-collinear-4e43"),
    ),
    // A surface with one point 4e9 away: `check_recovered` compared needle
    // triangles' areas with a relative tolerance below their rounding.
    (
        "recover_plc",
        include_bytes!("../../../fuzz/regressions/recover_plc-needle-4e9"),
    ),
    // Coordinates 1e23 and 1.8e19 among ones near 0.1: the self-intersection
    // grid took 2^24 cells (100 MB) for 24 triangles.
    (
        "recover_plc",
        include_bytes!("../../../fuzz/regressions/recover_plc-grid-1e23"),
    ),
];
