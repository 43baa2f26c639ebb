//! libFuzzer target `medit`: see `delone_fuzz::medit`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| delone_fuzz::medit(data));
