//! Progress on stderr: a bar on a terminal, a line every few seconds
//! otherwise, nothing during the first second of a stage and nothing with
//! `-Q`. Fed by the kernels' progress callbacks ([`Progress::update`]) and
//! by the library's progress reports ([`observe`]).

use std::cell::RefCell;
use std::io::{IsTerminal, Write};
use std::rc::Rc;
use std::time::{Duration, Instant};

/// One progress display.
pub struct Progress {
    enabled: bool,
    tty: bool,
    start: Instant,
    last: Option<Instant>,
    label: &'static str,
    /// A bar is on screen and needs a newline before anything else.
    open: bool,
}

impl Progress {
    pub fn new(enabled: bool, label: &'static str) -> Self {
        Progress {
            enabled,
            tty: std::io::stderr().is_terminal(),
            start: Instant::now(),
            last: None,
            label,
            open: false,
        }
    }

    /// Kernel callback: `done` of `total` points inserted.
    pub fn update(&mut self, done: usize, total: usize) {
        self.show(done as u64, Some(total as u64), "points");
    }

    /// Starts a new stage (ends the previous stage's bar).
    fn stage(&mut self, label: &'static str) {
        if label != self.label {
            self.finish();
            self.label = label;
            self.start = Instant::now();
            self.last = None;
        }
    }

    fn show(&mut self, done: u64, total: Option<u64>, unit: &str) {
        if !self.enabled || self.start.elapsed() < Duration::from_secs(1) {
            return;
        }
        let every = if self.tty {
            Duration::from_millis(200)
        } else {
            Duration::from_secs(2)
        };
        if self.last.is_some_and(|l| l.elapsed() < every) {
            return;
        }
        self.last = Some(Instant::now());
        let secs = self.start.elapsed().as_secs_f64();
        let mut err = std::io::stderr().lock();
        match total {
            Some(total) => {
                let pct = if total == 0 {
                    100.0
                } else {
                    100.0 * done as f64 / total as f64
                };
                if self.tty {
                    let w = 30usize;
                    let fill = (((pct / 100.0) * w as f64) as usize).min(w);
                    let _ = write!(
                        err,
                        "\r{}: [{}{}] {pct:5.1}% ({done}/{total} {unit})\x1b[K",
                        self.label,
                        "#".repeat(fill),
                        " ".repeat(w - fill),
                    );
                } else {
                    let _ = writeln!(err, "{}: {pct:.0}% ({done}/{total} {unit})", self.label);
                }
            }
            None => {
                if self.tty {
                    let _ = write!(err, "\r{}: {done} {unit} ({secs:.0} s)\x1b[K", self.label);
                } else {
                    let _ = writeln!(err, "{}: {done} {unit} ({secs:.0} s)", self.label);
                }
            }
        }
        self.open = self.tty;
        let _ = err.flush();
    }

    /// Ends the bar's line, if one is on screen.
    pub fn finish(&mut self) {
        if self.open {
            let _ = writeln!(std::io::stderr());
            self.open = false;
        }
    }
}

/// Runs `work` with the library's progress reports shown on stderr (unless
/// `enabled` is false).
pub fn observe<R>(enabled: bool, work: impl FnOnce() -> R) -> R {
    if !enabled {
        return work();
    }
    let shown = Rc::new(RefCell::new(Progress::new(true, "")));
    let sink = shown.clone();
    let out = delone::progress::observe(
        move |r: &delone::progress::Report| {
            let mut p = sink.borrow_mut();
            p.stage(r.stage);
            p.show(r.done, r.total, r.unit);
        },
        work,
    );
    shown.borrow_mut().finish();
    out
}
