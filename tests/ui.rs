//! Compile-fail tests for `#[reduced_lagrangian]`: every case makes exactly one mistake and checks
//! that the macro reports it with a message saying what was found and what is accepted, and a span
//! pointing at the offending token.
//!
//! Run with `cargo test --workspace -- --ignored --exact ui` (`.ci/run` does; the README's test
//! command leaves it out for time). The command selects the same targets as the test command, so
//! cargo resolves the same features and builds nothing again (`--test ui` alone leaves out the
//! dev-dependencies of the other members, whose features would rebuild every crate).
//! Regenerate the expected output with
//! `TRYBUILD=overwrite cargo test --workspace -- --ignored --exact ui`.

#[test]
#[ignore = "compiles every case with rustc (about 5 minutes on 2 cores): cargo test --workspace -- --ignored --exact ui"]
fn ui() {
    let t = trybuild::TestCases::new();
    t.compile_fail("tests/ui/*/*.rs");
}
