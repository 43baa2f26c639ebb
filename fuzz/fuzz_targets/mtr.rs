//! libFuzzer target `mtr`: see `delone_fuzz::mtr`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| delone_fuzz::mtr(data));
