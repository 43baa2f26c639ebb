//! libFuzzer target `face`: see `delone_fuzz::face`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| delone_fuzz::face(data));
