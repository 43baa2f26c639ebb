//! libFuzzer target `ply`: see `delone_fuzz::ply`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| delone_fuzz::ply(data));
