//! libFuzzer target `poly3d`: see `delone_fuzz::poly3d`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| delone_fuzz::poly3d(data));
