//! The guide's errors chapter lists every variant of `StepError`: the variant names are read
//! from the enum's source and from the chapter's table, and compared both ways, so a variant
//! added to the enum without a row (or a row left behind by a removed variant) fails here.

use std::collections::BTreeSet;

fn read(path: &str) -> String {
    let full = format!("{}/{path}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&full).unwrap_or_else(|e| panic!("reading {full}: {e}"))
}

/// The variant names of `pub enum StepError` in `source`: the identifiers that open a line at
/// the enum's item depth (one level of indentation) between its braces.
fn enum_variants(source: &str) -> BTreeSet<String> {
    let start = source
        .find("pub enum StepError {")
        .expect("`pub enum StepError` in error.rs");
    let mut names = BTreeSet::new();
    for line in source[start..].lines().skip(1) {
        if line.starts_with('}') {
            return names;
        }
        let Some(item) = line.strip_prefix("    ") else {
            continue;
        };
        let name: String = item
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect();
        if name.starts_with(|c: char| c.is_ascii_uppercase()) {
            names.insert(name);
        }
    }
    panic!("`pub enum StepError` has no closing brace in error.rs");
}

/// The variant names in the first column of the chapter's table of `StepError`: rows that
/// start with ``//! | `Name`` (or `` `Name {``).
fn chapter_rows(chapter: &str) -> BTreeSet<String> {
    chapter
        .lines()
        .filter_map(|line| line.strip_prefix("//! | `"))
        .map(|cell| {
            cell.chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect::<String>()
        })
        .filter(|name| name.starts_with(|c: char| c.is_ascii_uppercase()))
        .collect()
}

#[test]
fn every_step_error_variant_has_a_row_in_the_errors_chapter() {
    let variants = enum_variants(&read("dirac-runtime/src/error.rs"));
    let rows = chapter_rows(&read("src/guide/errors.rs"));
    // The parser itself: the enum has its long-standing variants, and the table its rows.
    for known in ["NotConverged", "InvalidRun", "StageFailed"] {
        assert!(
            variants.contains(known),
            "{known} not read from error.rs: {variants:?}"
        );
        assert!(
            rows.contains(known),
            "{known} not read from the chapter: {rows:?}"
        );
    }
    let missing: Vec<_> = variants.difference(&rows).collect();
    let stale: Vec<_> = rows.difference(&variants).collect();
    assert!(
        missing.is_empty(),
        "StepError variants without a row in src/guide/errors.rs: {missing:?}"
    );
    assert!(
        stale.is_empty(),
        "rows of src/guide/errors.rs that are not StepError variants: {stale:?}"
    );
}
