//! libFuzzer target `node`: see `delone_fuzz::node`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| delone_fuzz::node(data));
