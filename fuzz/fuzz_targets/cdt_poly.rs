//! libFuzzer target `cdt_poly`: see `delone_fuzz::cdt_poly`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| delone_fuzz::cdt_poly(data));
