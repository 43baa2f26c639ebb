//! libFuzzer target `off`: see `delone_fuzz::off`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| delone_fuzz::off(data));
