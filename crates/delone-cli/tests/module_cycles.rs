//! No import cycle between the modules of `delone-cli` (see
//! `delone_testdata::modules` for what counts as a use).

#[test]
fn modules_have_no_import_cycle() {
    let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let report = delone_testdata::modules::cycle_report(&src);
    assert!(report.is_empty(), "{report}");
}
