//! libFuzzer target `sol`: see `delone_fuzz::sol`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| delone_fuzz::sol(data));
