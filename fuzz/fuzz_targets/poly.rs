//! libFuzzer target `poly`: see `delone_fuzz::poly`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| delone_fuzz::poly(data));
