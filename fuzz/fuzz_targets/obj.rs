//! libFuzzer target `obj`: see `delone_fuzz::obj`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| delone_fuzz::obj(data));
