//! The delone CLI.
fn main() {}
