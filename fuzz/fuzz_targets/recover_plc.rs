//! libFuzzer target `recover_plc`: see `delone_fuzz::recover_plc`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| delone_fuzz::recover_plc(data));
