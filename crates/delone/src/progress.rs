//! Progress reports from long-running operations.
//!
//! The library never prints. Long operations (segment and facet recovery,
//! Delaunay refinement, mesh optimisation, the constrained triangulation of
//! many segments) instead call [`report`] now and then; the reports go to
//! the sink installed by [`observe`] on the *calling thread*, and nowhere
//! when none is installed. The command-line tool installs a sink that draws
//! a bar or prints a line every few seconds on stderr (and none with `-Q`).
//!
//! A sink costs one thread-local lookup per report, and the library reports
//! at most every few thousand steps of a loop, so observing is free in
//! practice. Reports made on worker threads of a parallel phase are not
//! forwarded (the calling thread reports for them).
//!
//! The same report sites are where a long run can be stopped: [`stoppable`]
//! installs a stop flag for the calling thread, and once another thread sets
//! it the next report site ends its stage early, as it does when the stage's
//! budget is spent (refinement and optimisation keep what they have) or with
//! [`Error::Interrupted`](crate::Error::Interrupted) (segment insertion and
//! surface recovery, which have no partial result). [`stop_requested`] tells
//! the caller afterwards that the result is incomplete. A parallel phase
//! passes the flag on to its worker threads ([`stop_flag`]).
//!
//! ```
//! use delone::model::pslg::Pslg;
//! use delone::progress::{observe, Report};
//! use delone::tri::{constrained_triangulation, CdtOptions};
//! use std::{cell::RefCell, rc::Rc};
//!
//! let seen = Rc::new(RefCell::new(Vec::new()));
//! let log = seen.clone();
//! let pts: Vec<[f64; 2]> = (0..2000).map(|i| [i as f64, ((i * 7919) % 2003) as f64]).collect();
//! let segs: Vec<[u32; 2]> = (0..1999).step_by(2).map(|i| [i, i + 1]).collect();
//! let cdt = observe(
//!     move |r: &Report| log.borrow_mut().push((r.stage, r.done, r.total)),
//!     || constrained_triangulation(&Pslg::new(pts, segs), CdtOptions { convex_hull: true }),
//! );
//! assert!(cdt.is_ok());
//! // Counts never go backwards within a stage and never pass the total.
//! let seen = seen.borrow();
//! assert!(seen.iter().any(|r| r.0 == "inserting segments"));
//! assert!(seen.windows(2).all(|w| w[0].0 != w[1].0 || w[0].1 <= w[1].1));
//! assert!(seen.iter().all(|r| r.2.map_or(true, |t| r.1 <= t)));
//! ```
use std::cell::RefCell;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// One progress report.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Report {
    /// What is running, as a short lower-case phrase ("recovering segments",
    /// "refining", "optimising", ...).
    pub stage: &'static str,
    /// Work done so far in this stage, in `unit`s.
    pub done: u64,
    /// The total when it is known in advance (`done <= total`); `None` for
    /// open-ended work such as refinement, where only `done` grows.
    pub total: Option<u64>,
    /// What `done` counts ("segments", "points", "passes", ...).
    pub unit: &'static str,
}

type Sink<'a> = Box<dyn FnMut(&Report) + 'a>;

thread_local! {
    // The sink is stored type-erased and 'static; `observe` guarantees that
    // it is removed before the borrow it was made from ends (see `Guard`).
    static SINK: RefCell<Option<Sink<'static>>> = const { RefCell::new(None) };
    static STOP: RefCell<Option<Arc<AtomicBool>>> = const { RefCell::new(None) };
}

/// Runs `work` with `sink` receiving the progress reports that the library
/// makes on this thread meanwhile, and returns what `work` returns.
///
/// Sinks nest: an inner `observe` replaces the outer sink until it returns.
/// A report made while the sink itself runs (re-entrantly) is dropped.
///
/// ```
/// use delone::progress::{observe, report, Report};
/// use std::{cell::Cell, rc::Rc};
/// let n = Rc::new(Cell::new(0));
/// let m = n.clone();
/// let out = observe(move |_r: &Report| m.set(m.get() + 1), || {
///     report("testing", 1, Some(2), "steps");
///     report("testing", 2, Some(2), "steps");
///     7
/// });
/// assert_eq!((out, n.get()), (7, 2));
/// ```
pub fn observe<S, R>(sink: S, work: impl FnOnce() -> R) -> R
where
    S: FnMut(&Report) + 'static,
{
    let previous = SINK.with(|s| s.borrow_mut().replace(Box::new(sink)));
    // Restores the previous sink even when `work` unwinds.
    struct Guard(Option<Sink<'static>>);
    impl Drop for Guard {
        fn drop(&mut self) {
            let previous = self.0.take();
            SINK.with(|s| {
                if let Ok(mut s) = s.try_borrow_mut() {
                    *s = previous;
                }
            });
        }
    }
    let _guard = Guard(previous);
    work()
}

/// Whether a sink is installed on this thread. Loops can test it once and
/// skip the bookkeeping of their reports when nobody listens.
///
/// ```
/// assert!(!delone::progress::observed());
/// assert!(delone::progress::observe(|_: &delone::progress::Report| {}, delone::progress::observed));
/// ```
pub fn observed() -> bool {
    SINK.with(|s| s.try_borrow().map(|s| s.is_some()).unwrap_or(false))
}

/// Sends one report to this thread's sink, if any. Library code calls it
/// every few thousand steps of a long loop; it is public so that programs
/// built on the library can report through the same sink.
///
/// ```
/// // Without a sink a report goes nowhere.
/// delone::progress::report("testing", 1, None, "steps");
/// ```
pub fn report(stage: &'static str, done: u64, total: Option<u64>, unit: &'static str) {
    SINK.with(|s| {
        if let Ok(mut s) = s.try_borrow_mut() {
            if let Some(f) = s.as_mut() {
                f(&Report {
                    stage,
                    done,
                    total,
                    unit,
                });
            }
        }
    });
}

/// Runs `work` with `stop` as this thread's stop flag, and returns what
/// `work` returns. Setting the flag (from any thread) makes the library's
/// long loops running in `work` on this thread end at their next report site
/// (see the module docs). Flags nest like sinks.
///
/// ```
/// use delone::model::pslg::Pslg;
/// use delone::progress::{stop_requested, stoppable};
/// use delone::tri::{constrained_triangulation, CdtOptions};
/// use std::sync::{atomic::AtomicBool, Arc};
/// let pts: Vec<[f64; 2]> = (0..200).map(|i| [i as f64, ((i * 7919) % 211) as f64]).collect();
/// let segs: Vec<[u32; 2]> = (0..199).step_by(2).map(|i| [i, i + 1]).collect();
/// let g = Pslg::new(pts, segs);
/// // A flag set before the run stops it at the first report site.
/// let stop = Arc::new(AtomicBool::new(true));
/// let r = stoppable(stop, || (constrained_triangulation(&g, CdtOptions::default()), stop_requested()));
/// assert_eq!(r, (Err(delone::Error::Interrupted), true));
/// assert!(!stop_requested());
/// ```
pub fn stoppable<R>(stop: Arc<AtomicBool>, work: impl FnOnce() -> R) -> R {
    let previous = STOP.with(|s| s.borrow_mut().replace(stop));
    // Restores the previous flag even when `work` unwinds.
    struct Guard(Option<Arc<AtomicBool>>);
    impl Drop for Guard {
        fn drop(&mut self) {
            let previous = self.0.take();
            STOP.with(|s| *s.borrow_mut() = previous);
        }
    }
    let _guard = Guard(previous);
    work()
}

/// This thread's stop flag (a new, unset one when none is installed), for
/// a parallel phase to install in its worker threads with [`stoppable`].
///
/// ```
/// use std::sync::{atomic::{AtomicBool, Ordering}, Arc};
/// let f = Arc::new(AtomicBool::new(true));
/// let seen = delone::progress::stoppable(f, || delone::progress::stop_flag().load(Ordering::Relaxed));
/// assert!(seen);
/// ```
pub fn stop_flag() -> Arc<AtomicBool> {
    STOP.with(|s| s.borrow().clone())
        .unwrap_or_else(|| Arc::new(AtomicBool::new(false)))
}

/// Whether this thread's stop flag (installed by [`stoppable`]) is set.
/// Long loops check it where they [`report`].
///
/// ```
/// assert!(!delone::progress::stop_requested());
/// ```
pub fn stop_requested() -> bool {
    STOP.with(|s| {
        s.borrow()
            .as_ref()
            .is_some_and(|f| f.load(Ordering::Relaxed))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::Cell;
    use std::rc::Rc;

    #[test]
    fn nested_sinks_restore_the_outer_one() {
        let outer = Rc::new(Cell::new(0));
        let inner = Rc::new(Cell::new(0));
        let (o, i) = (outer.clone(), inner.clone());
        observe(
            move |_: &Report| o.set(o.get() + 1),
            || {
                report("a", 1, None, "x");
                observe(
                    move |_: &Report| i.set(i.get() + 1),
                    || report("b", 1, None, "x"),
                );
                report("a", 2, None, "x");
            },
        );
        assert_eq!((outer.get(), inner.get()), (2, 1));
        assert!(!observed());
    }

    #[test]
    fn sink_is_removed_after_a_panic() {
        let r = std::panic::catch_unwind(|| {
            observe(|_: &Report| {}, || panic!("boom"));
        });
        assert!(r.is_err());
        assert!(!observed());
    }

    #[test]
    fn reentrant_reports_are_dropped() {
        let n = Rc::new(Cell::new(0));
        let m = n.clone();
        observe(
            move |_: &Report| {
                m.set(m.get() + 1);
                report("inner", 1, None, "x");
            },
            || report("outer", 1, None, "x"),
        );
        assert_eq!(n.get(), 1);
    }
}
