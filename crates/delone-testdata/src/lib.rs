//! # delone-testdata
//!
//! Finds the shared test corpus for the test suites of every delone crate.
//!
//! The corpus (third-party meshes, PSLGs, PLCs and point sets) lives outside
//! the repository in `shared/data`, next to the checkout: the tests look for
//! it in every ancestor of the crate directory (`<checkout>/../shared/data`,
//! one more level up from a worktree). [`corpus_dir`] returns it, or
//!
//! * panics with a message saying where it looked and how to get it, so that
//!   a test run without the corpus does not report "all passed" while it
//!   skipped the corpus tests;
//! * with `DELONE_NO_CORPUS=1` in the environment, returns `None`: the
//!   calling test skips itself, and a line naming the test and counting the
//!   corpus tests skipped so far in this test binary is written to standard
//!   error (not captured by the test harness, so it shows in every run).
//!
//! ```no_run
//! // In a test:
//! let Some(dir) = delone_testdata::corpus_dir(env!("CARGO_MANIFEST_DIR")) else {
//!     return; // DELONE_NO_CORPUS=1 and no corpus: skipped, and counted
//! };
//! assert!(dir.join("2d/A.poly").is_file());
//! ```
#![forbid(unsafe_code)]

pub mod modules;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// The environment variable that lets corpus tests skip when the corpus is
/// missing (any non-empty value other than `0`).
pub const OPT_OUT: &str = "DELONE_NO_CORPUS";

static SKIPPED: AtomicUsize = AtomicUsize::new(0);

/// `shared/data` in the nearest ancestor of `manifest_dir` that has one.
///
/// ```
/// let d = delone_testdata::find_corpus(std::path::Path::new("/nonexistent/x/y"));
/// assert!(d.is_none());
/// ```
pub fn find_corpus(manifest_dir: &Path) -> Option<PathBuf> {
    manifest_dir
        .ancestors()
        .map(|a| a.join("shared/data"))
        .find(|d| d.is_dir())
}

/// Whether [`OPT_OUT`] is set (non-empty and not `0`).
pub fn opted_out() -> bool {
    std::env::var_os(OPT_OUT).is_some_and(|v| !v.is_empty() && v != "0")
}

/// The shared corpus directory for a test in the crate at `manifest_dir`
/// (pass `env!("CARGO_MANIFEST_DIR")`).
///
/// # Panics
/// When the corpus is missing and [`OPT_OUT`] is not set: the message says
/// where it looked and how to get the corpus or opt out.
pub fn corpus_dir(manifest_dir: &str) -> Option<PathBuf> {
    corpus_dir_with(Path::new(manifest_dir), opted_out())
}

/// A file or folder inside the corpus (`corpus_path(env!("CARGO_MANIFEST_DIR"),
/// "3d_plc")`), with the behaviour of [`corpus_dir`] when the corpus is
/// missing. A path missing inside a present corpus panics too.
pub fn corpus_path(manifest_dir: &str, rel: &str) -> Option<PathBuf> {
    let d = corpus_dir(manifest_dir)?;
    let p = d.join(rel);
    assert!(
        p.exists(),
        "test corpus: {} is missing from {} (an outdated copy of shared/data?)",
        rel,
        d.display()
    );
    Some(p)
}

/// How many corpus tests skipped themselves so far in this process.
pub fn skipped() -> usize {
    SKIPPED.load(Ordering::SeqCst)
}

fn corpus_dir_with(manifest_dir: &Path, opted_out: bool) -> Option<PathBuf> {
    if let Some(d) = find_corpus(manifest_dir) {
        return Some(d);
    }
    if !opted_out {
        panic!(
            "the shared test corpus was not found: looked for shared/data in every \
             ancestor of {} (normally <checkout>/../shared/data). Put the project's \
             shared/ folder next to the checkout, or set {OPT_OUT}=1 to skip the \
             corpus tests (each skip is then reported and counted)",
            manifest_dir.display()
        );
    }
    let n = SKIPPED.fetch_add(1, Ordering::SeqCst) + 1;
    let thread = std::thread::current();
    let name = thread.name().unwrap_or("?");
    // Straight to the stream: the test harness captures only print!/eprint!.
    let _ = writeln!(
        std::io::stderr(),
        "corpus test skipped ({OPT_OUT} set, no shared/data): {name} \
         [{n} corpus test(s) skipped in this test binary]"
    );
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn missing_corpus_panics_with_where_it_looked() {
        let r = std::panic::catch_unwind(|| corpus_dir_with(Path::new("/nonexistent/a/b"), false));
        let e = r.unwrap_err();
        let msg = e.downcast_ref::<String>().unwrap();
        assert!(
            msg.contains("/nonexistent/a/b") && msg.contains(OPT_OUT),
            "{msg}"
        );
    }

    #[test]
    fn opt_out_skips_and_counts() {
        let before = skipped();
        assert_eq!(corpus_dir_with(Path::new("/nonexistent/a/b"), true), None);
        assert!(skipped() > before);
    }

    #[test]
    fn finds_a_corpus_in_an_ancestor() {
        let root = std::env::temp_dir().join(format!("delone-testdata-{}", std::process::id()));
        let deep = root.join("checkout/crates/x");
        std::fs::create_dir_all(&deep).unwrap();
        std::fs::create_dir_all(root.join("shared/data")).unwrap();
        assert_eq!(
            corpus_dir_with(&deep, false),
            Some(root.join("shared/data"))
        );
        std::fs::remove_dir_all(&root).unwrap();
    }
}
