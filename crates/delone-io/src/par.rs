//! Work split over scoped threads.

/// Runs `job(k)` for every `k` in `0..n`: `job(0)` on this thread, each
/// other on a scoped thread of its own (on this thread when that thread
/// cannot start). The results come in the order of `k`; a job that
/// panicked on its own thread gives `Err` with the panic's payload (a
/// panic of `job(0)` unwinds here).
pub(crate) fn scoped_map<R: Send>(
    n: usize,
    job: impl Fn(usize) -> R + Sync,
) -> Vec<std::thread::Result<R>> {
    if n == 0 {
        return Vec::new();
    }
    let job = &job;
    std::thread::scope(|s| {
        let handles: Vec<_> = (1..n)
            .map(|k| std::thread::Builder::new().spawn_scoped(s, move || job(k)))
            .collect();
        let mut out = Vec::with_capacity(n);
        out.push(Ok(job(0)));
        for (k, h) in handles.into_iter().enumerate() {
            out.push(match h {
                Ok(h) => h.join(),
                Err(_) => Ok(job(k + 1)),
            });
        }
        out
    })
}
