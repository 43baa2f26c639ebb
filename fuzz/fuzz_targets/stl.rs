//! libFuzzer target `stl`: see `delone_fuzz::stl`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| delone_fuzz::stl(data));
