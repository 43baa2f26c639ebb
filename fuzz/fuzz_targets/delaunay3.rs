//! libFuzzer target `delaunay3`: see `delone_fuzz::delaunay3`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| delone_fuzz::delaunay3(data));
