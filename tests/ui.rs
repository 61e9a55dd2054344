//! Compile-fail tests for `#[reduced_lagrangian]`: every case makes exactly one mistake and checks
//! that the macro reports it with a message saying what was found and what is accepted, and a span
//! pointing at the offending token.
//!
//! Regenerate the expected output with `TRYBUILD=overwrite cargo test --test ui`.

#[test]
fn ui() {
    let t = trybuild::TestCases::new();
    t.compile_fail("tests/ui/*/*.rs");
}
