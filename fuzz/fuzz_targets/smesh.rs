//! libFuzzer target `smesh`: see `delone_fuzz::smesh`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| delone_fuzz::smesh(data));
