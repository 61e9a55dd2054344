//! The examples' command-line helper (`examples/common/cli.rs`): declared options parse to typed
//! values, and every bad argument — unknown flag, missing value, unparsable or out-of-range value,
//! a value given to a switch, a flag given twice, a stray word — is an error with a message
//! instead of being ignored; `--help` asks for the help text.

#[path = "../examples/common/cli.rs"]
mod cli;

use cli::{any, at_least, greater_than, Cli};

/// A command line like cluster's: sizes, steps, a time step, a switch, a choice.
struct Parsed {
    sizes: Vec<usize>,
    steps: usize,
    h: f64,
    fast: bool,
    mode: u8,
    extra: Option<f64>,
}

fn parse(args: &[&str]) -> (Parsed, Result<bool, String>) {
    let mut cli = Cli::from_args("demo", "a test", args.iter().map(|s| s.to_string()));
    let parsed = Parsed {
        sizes: cli.list("--n", "N1,N2,..", "sizes", &[64, 128], at_least(2)),
        steps: cli.value("--steps", "S", "steps", 300, at_least(10)),
        h: cli.value("--h", "H", "time step", 0.002, greater_than(0.0)),
        fast: cli.switch("--fast", "go fast"),
        mode: cli.choice("--mode", "a mode", "a", &[("a", 1), ("b", 2)]),
        extra: cli.optional("--extra", "X", "optional", any()),
    };
    (parsed, cli.check())
}

fn error(args: &[&str]) -> String {
    parse(args).1.expect_err("a bad command line is an error")
}

#[test]
fn defaults_when_nothing_is_given() {
    let (p, ok) = parse(&[]);
    assert_eq!(ok, Ok(true));
    assert_eq!(p.sizes, vec![64, 128]);
    assert_eq!(p.steps, 300);
    assert_eq!(p.h, 0.002);
    assert!(!p.fast);
    assert_eq!(p.mode, 1);
    assert_eq!(p.extra, None);
}

#[test]
fn given_values_parse() {
    let (p, ok) = parse(&[
        "--n",
        "8,16, 32",
        "--steps=20",
        "--h",
        "1e-3",
        "--fast",
        "--mode",
        "b",
        "--extra",
        "-1.5",
    ]);
    assert_eq!(ok, Ok(true));
    assert_eq!(p.sizes, vec![8, 16, 32]);
    assert_eq!(p.steps, 20);
    assert_eq!(p.h, 1e-3);
    assert!(p.fast);
    assert_eq!(p.mode, 2);
    assert_eq!(p.extra, Some(-1.5));
}

#[test]
fn bad_arguments_are_errors_with_a_message() {
    let usage = "usage: demo [--n N1,N2,..] [--steps S] [--h H] [--fast] [--mode a|b] [--extra X]";
    let cases: [(&[&str], &str); 13] = [
        (&["--bogus"], "unknown flag `--bogus`"),
        (&["--bogus", "3"], "unknown flag `--bogus`"),
        (&["stray"], "unexpected argument `stray`"),
        (&["--steps"], "--steps needs a value S"),
        (&["--steps", "--fast"], "--steps needs a value S"),
        (&["--steps", "ten"], "--steps: `ten` is not an integer ≥ 10"),
        (&["--steps", "5"], "--steps: `5` is not an integer ≥ 10"),
        (&["--h", "0"], "--h: `0` is not a number > 0"),
        (&["--h", "NaN"], "--h: `NaN` is not a number > 0"),
        (&["--n", "8,1"], "--n: `1` is not an integer ≥ 2"),
        (&["--n", ""], "--n needs at least one value"),
        (&["--mode", "c"], "--mode: `c` is not one of a, b"),
        (&["--fast", "yes"], "--fast takes no value (given `yes`)"),
    ];
    for (args, message) in cases {
        let e = error(args);
        assert!(
            e.starts_with(&format!("demo: {message}\n")),
            "{args:?}: {e}"
        );
        assert!(e.contains(usage), "{args:?}: {e}");
    }
    let e = error(&["--steps", "20", "--steps", "30"]);
    assert!(e.starts_with("demo: --steps is given 2 times"), "{e}");
    assert!(error(&["--extra", "inf"]).starts_with("demo: --extra: `inf` is not a number"));
}

#[test]
fn help_is_asked_for_even_next_to_bad_arguments() {
    assert_eq!(parse(&["--help"]).1, Ok(false));
    assert_eq!(parse(&["-h"]).1, Ok(false));
    assert_eq!(parse(&["--steps", "1", "--help"]).1, Ok(false));
}

#[test]
fn an_empty_list_where_allowed_and_rejections_by_the_example() {
    let run = |args: &[&str]| {
        let mut cli = Cli::from_args("demo", "a test", args.iter().map(|s| s.to_string()));
        let chain: Vec<usize> = cli.list(
            "--chain",
            "N1,..",
            "chain sizes",
            &[2, 4],
            at_least(1).or_none(),
        );
        if chain.contains(&3) {
            cli.reject("3 is not allowed here");
        }
        (chain, cli.check())
    };
    assert_eq!(run(&["--chain", ""]), (vec![], Ok(true)));
    assert_eq!(run(&[]), (vec![2, 4], Ok(true)));
    let (_, e) = run(&["--chain", "1,3"]);
    assert!(e.unwrap_err().starts_with("demo: 3 is not allowed here\n"));
}
