//! libFuzzer target `delaunay2`: see `delone_fuzz::delaunay2`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| delone_fuzz::delaunay2(data));
