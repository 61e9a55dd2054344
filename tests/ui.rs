//! Compile-fail tests for `#[reduced_lagrangian]`: every case makes exactly one mistake and checks
//! that the macro reports it with a message saying what was found and what is accepted, and a span
//! pointing at the offending token.
//!
//! Run with `cargo test --workspace --test ui -- --ignored` (`.ci/run` does; the README's test
//! command leaves it out for time; `--workspace` resolves features as the test command does, so
//! nothing it built is built again); regenerate the expected output with
//! `TRYBUILD=overwrite cargo test --workspace --test ui -- --ignored`.

#[test]
#[ignore = "compiles every case with rustc (about 5 minutes on 2 cores): cargo test --workspace --test ui -- --ignored"]
fn ui() {
    let t = trybuild::TestCases::new();
    t.compile_fail("tests/ui/*/*.rs");
}
