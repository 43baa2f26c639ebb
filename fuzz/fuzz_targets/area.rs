//! libFuzzer target `area`: see `delone_fuzz::area`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| delone_fuzz::area(data));
