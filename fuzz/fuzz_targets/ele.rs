//! libFuzzer target `ele`: see `delone_fuzz::ele`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| delone_fuzz::ele(data));
