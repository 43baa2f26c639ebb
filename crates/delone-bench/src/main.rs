//! delone-bench.
fn main() {}
