//! CPU time of the calling thread, shared by the optimisation examples
//! (`opt_table`, `opt_probe`) through `#[path]`.

/// CPU time of this thread (seconds), from /proc; 0 when unavailable.
pub fn cpu() -> f64 {
    let s = std::fs::read_to_string("/proc/thread-self/stat").unwrap_or_default();
    let rest = s.rsplit(')').next().unwrap_or("");
    let f: Vec<&str> = rest.split_whitespace().collect();
    let t = |i: usize| f.get(i).and_then(|x| x.parse::<f64>().ok()).unwrap_or(0.0);
    (t(11) + t(12)) / 100.0
}
