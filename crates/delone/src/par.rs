//! Work split over threads with results in a fixed order, so that the
//! output does not depend on the thread count (used by the Voronoi
//! extraction and the 2D refinement's final statistics).

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// `s` cut at `bounds` (`bounds[0] = 0`, last `= s.len()`, increasing).
pub(crate) fn split_mut<'a, T>(mut s: &'a mut [T], bounds: &[usize]) -> Vec<&'a mut [T]> {
    let mut out = Vec::with_capacity(bounds.len());
    for w in bounds.windows(2) {
        let (a, b) = std::mem::take(&mut s).split_at_mut(w[1] - w[0]);
        out.push(a);
        s = b;
    }
    out
}

/// `f(i, item)` for every item on at most `threads` threads (this one and
/// scoped ones), each thread taking the next item not yet taken; the results
/// in item order (`None` only if an item could not be run).
pub(crate) fn run_dynamic<I: Send, R: Send>(
    threads: usize,
    items: Vec<I>,
    f: impl Fn(usize, I) -> R + Sync,
) -> Vec<Option<R>> {
    let n = items.len();
    if threads <= 1 || n <= 1 {
        return items
            .into_iter()
            .enumerate()
            .map(|(i, x)| Some(f(i, x)))
            .collect();
    }
    let slots: Vec<Mutex<Option<I>>> = items.into_iter().map(|x| Mutex::new(Some(x))).collect();
    let results: Vec<Mutex<Option<R>>> = (0..n).map(|_| Mutex::new(None)).collect();
    let next = AtomicUsize::new(0);
    let (f, slots, results, next) = (&f, &slots, &results, &next);
    let work = move || loop {
        let i = next.fetch_add(1, Ordering::Relaxed);
        if i >= n {
            break;
        }
        if let Some(x) = slots[i].lock().ok().and_then(|mut s| s.take()) {
            let r = f(i, x);
            if let Ok(mut g) = results[i].lock() {
                *g = Some(r);
            }
        }
    };
    std::thread::scope(|sc| {
        let handles: Vec<_> = (1..threads.min(n))
            .map(|_| std::thread::Builder::new().spawn_scoped(sc, work).ok())
            .collect();
        work();
        for h in handles.into_iter().flatten() {
            h.join().unwrap_or_else(|e| std::panic::resume_unwind(e));
        }
    });
    slots
        .iter()
        .zip(results)
        .enumerate()
        .map(|(i, (s, r))| {
            // An item left behind (a poisoned lock): run it here.
            let left = s.lock().ok().and_then(|mut s| s.take());
            r.lock()
                .ok()
                .and_then(|mut r| r.take())
                .or_else(|| left.map(|x| f(i, x)))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn run_dynamic_keeps_item_order() {
        for threads in [1, 2, 3, 8] {
            let items: Vec<usize> = (0..17).collect();
            let out = run_dynamic(threads, items, |i, x| {
                assert_eq!(i, x);
                x * x
            });
            let want: Vec<Option<usize>> = (0..17).map(|x| Some(x * x)).collect();
            assert_eq!(out, want);
        }
    }
}
