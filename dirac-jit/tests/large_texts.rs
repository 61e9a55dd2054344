//! Texts at the edges of what the compiler takes — a 10 MB body, nesting 10⁵ deep, element-wise
//! sizes far beyond memory — compile, or are refused with a typed error that names the limit:
//! never a stack overflow or an allocation failure, which would abort the program that compiles
//! them (a Python session, the command line).

use dirac_jit::Error;
use dirac_runtime::prelude::*;

/// The attribute and signature of every text here, up to the start of the body's last term.
const HEAD: &str = "#[reduced_lagrangian(shape(x), group(theta))]
fn big(q0: Config, q1: Config, h: f64, m: f64) -> f64 {
    0.5 * m / h * ((q1.x - q0.x) * (q1.x - q0.x) + (q1.theta - q0.theta) * (q1.theta - q0.theta))
";

/// A flat sum of `terms` terms after the kinetic energy, one per line (about 45 bytes each), as a
/// computer-algebra system writes a long potential.
fn flat_sum(terms: usize) -> String {
    let mut text = String::from(HEAD);
    for i in 0..terms {
        let c = 1.0 + i as f64 / 1024.0;
        text.push_str(&format!("        - h * m * q0.x * q1.x * {c:.10}\n"));
    }
    text.push_str("}\n");
    text
}

/// The kinetic energy minus `h · inner`, with `inner` wrapped `depth` times in `open` and
/// `close` (on line 4 of the text).
fn nested(depth: usize, open: &str, inner: &str, close: &str) -> String {
    format!(
        "{HEAD}        - h * {}{inner}{}\n}}\n",
        open.repeat(depth),
        close.repeat(depth)
    )
}

/// The text's refusal: its first diagnostic.
fn refusal(
    result: Result<std::sync::Arc<dirac_jit::Code>, Error>,
) -> dirac_compiler::text::Diagnostic {
    match result {
        Err(Error::Text(e)) => {
            assert!(!e.diagnostics.is_empty());
            e.diagnostics[0].clone()
        }
        Err(other) => panic!("not the text's error: {other}"),
        Ok(_) => panic!("compiled"),
    }
}

/// One reduced step of a compiled text from a small state: the code runs.
fn steps(code: &std::sync::Arc<dirac_jit::Code>) {
    let system = code
        .instantiate::<1, 1, 2>(&[0.01, 1.0])
        .expect("S = 1, K = 1");
    let start = ReducedState::new([1.0], [0.0], [0.1], [0.0]);
    let traj = ReducedIntegrator::plus(system, NewtonOptions::default())
        .run(start)
        .steps(2)
        .collect()
        .expect("two steps");
    assert!(traj.last().x[0].is_finite());
}

/// A 10 MB body, a flat sum of 2.2 × 10⁵ terms (rustc compiles it, given the stack): the text
/// front end used to die with SIGSEGV on it. It goes through every stage of the compiler, and
/// then either steps or is refused with the typed error that names the size of machine code
/// one function may have (its step's Jacobian is a straight line of 1.1 × 10⁶ operations, more
/// than Cranelift allocates registers for in one function).
#[test]
fn a_ten_megabyte_body_compiles_or_is_refused_naming_the_limit() {
    let text = flat_sum(220_000);
    assert!(text.len() > 10_000_000, "{} bytes", text.len());
    match dirac_jit::compile(&text) {
        Ok(code) => steps(&code),
        Err(Error::Codegen(message)) => {
            assert!(
                message.contains("operations is too large for one function of machine code")
                    && message.contains("2^21 values"),
                "{message}"
            );
            println!("refused: {message}");
        }
        Err(other) => panic!(
            "{}",
            other.to_string().chars().take(2000).collect::<String>()
        ),
    }
}

/// Parentheses nested 10⁴ and 10⁵ deep (the text front end used to abort with a stack
/// overflow) are refused with the limit, at the parenthesis that passes it: line 4, the
/// 256th `(` (the body's braces are the first level).
#[test]
fn parentheses_nested_beyond_the_limit_are_refused_where_they_pass_it() {
    assert_eq!(dirac_compiler::text::MAX_NESTING, 256);
    for depth in [10_000, 100_000] {
        let text = nested(depth, "(", "q0.x", ")");
        let d = refusal(dirac_jit::compile(&text));
        assert!(
            d.message.contains("nested deeper than 256 levels"),
            "{}",
            d.message
        );
        let line = text.lines().nth(d.line - 1).expect("the line");
        let before = "        - h * ".len();
        assert_eq!((d.line, d.column), (4, before + 256), "{}", d.message);
        assert!(line[..d.column].ends_with('('));
    }
}

/// Nesting within the limit compiles: parentheses 250 deep, and sums nested 100 deep.
#[test]
fn nesting_within_the_limit_compiles() {
    let code =
        dirac_jit::compile(&nested(250, "(", "q0.x * q1.x", ")")).unwrap_or_else(|e| panic!("{e}"));
    steps(&code);
    let code = dirac_jit::compile(&nested(100, "(q0.x * 0.5 + q1.x * 0.25 + ", "q0.x", ")"))
        .unwrap_or_else(|e| panic!("{e}"));
    steps(&code);
}

/// The chain the scan gives the least stack a level of the syntax tree: a flat sum of 3 × 10⁵
/// single names (one operator each). It compiles, or is refused with a typed error.
#[test]
fn a_flat_sum_of_single_names_is_never_a_crash() {
    let text = format!("{HEAD}        - h * q0.x{}\n}}\n", " + h".repeat(300_000));
    match dirac_jit::compile(&text) {
        Ok(code) => steps(&code),
        Err(e) => println!("{}", e.to_string().chars().take(300).collect::<String>()),
    }
}

/// Every other way to nest 10⁵ deep — brackets, blocks, unary minus, closures, `else if`,
/// generic arguments, method calls and fields (which the lowering walks down, recursively, to
/// the innermost before it refuses the method or field) — gives a typed error (the limit, or
/// what the body language does not accept), never an abort.
#[test]
fn every_kind_of_deep_nesting_is_a_typed_error() {
    const DEEP: usize = 100_000;
    let else_ifs = format!(
        "{HEAD}        - h * if q0.x > 0.0 {{ q0.x }}{} else {{ q1.x }}\n}}\n",
        " else if q0.x > 1.0 { q1.x }".repeat(DEEP)
    );
    let generics = format!(
        "{HEAD}        - h * {{ let v: {}f64{} = 1.0; q0.x }}\n}}\n",
        "Vec<".repeat(DEEP),
        ">".repeat(DEEP)
    );
    let cases = [
        ("brackets", nested(DEEP, "[", "q0.x", "][0]")),
        ("blocks", nested(DEEP, "{", "q0.x", "}")),
        ("unary minus", nested(DEEP, "-", "q0.x", "")),
        ("negations", nested(DEEP, "!", "q0.x", "")),
        ("closures", nested(DEEP, "|a: f64| ", "q0.x", "")),
        ("else if", else_ifs),
        (
            "method calls",
            nested(1, "", &format!("q0.x{}", ".floor()".repeat(DEEP)), ""),
        ),
        (
            "fields",
            nested(1, "", &format!("q0{}", ".x".repeat(DEEP)), ""),
        ),
        ("generic arguments", generics),
    ];
    for (what, text) in cases {
        let d = refusal(dirac_jit::compile(&text));
        assert!(d.line >= 1 && d.column >= 1, "{what}: {d:?}");
        println!("{what}: {}", d.message);
    }
}

/// Whether this process is the child a test started (see the memory test below).
fn is_child() -> bool {
    std::env::var_os("DIRAC_TEST_CHILD").is_some()
}

/// A chain given as text instantiated at n = 10⁸ and n = 10¹⁰ under a 4 GB address-space limit
/// (`ulimit -v`, in a child process so that an abort ends the child, not the harness): the
/// tables of its elements need 5.6 GB and 560 GB, and instantiation says so with the runtime's
/// typed `StepError::OutOfMemory` before allocating them, where it used to fill them element by
/// element until the allocator aborted the process.
#[cfg(target_os = "linux")]
#[test]
fn element_sizes_beyond_memory_are_refused_before_allocating() {
    const NAME: &str = "element_sizes_beyond_memory_are_refused_before_allocating";
    if !is_child() {
        let out = std::process::Command::new("sh")
            .arg("-c")
            .arg("ulimit -v 4000000 && exec \"$0\" --exact \"$1\" --nocapture --test-threads=1")
            .arg(std::env::current_exe().expect("the test binary"))
            .arg(NAME)
            .env("DIRAC_TEST_CHILD", "1")
            .output()
            .expect("the child runs");
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(
            out.status.success() && stdout.matches("typed error:").count() == 2,
            "the child ended with {:?}\n{stdout}\n{}",
            out.status,
            String::from_utf8_lossy(&out.stderr)
        );
        return;
    }
    let code = dirac_jit::compile_element(
        "#[reduced_lagrangian(coordinates(x[n]), translate(x), rule = midpoint)]
         fn chain(q: Config, v: Velocity, k: f64, n: usize) -> f64 {
             let mut l = 0.0;
             for i in 0..n { l += 0.5 * v.x[i] * v.x[i]; }
             for i in 0..n - 1 { l -= 0.5 * k * (q.x[i + 1] - q.x[i]) * (q.x[i + 1] - q.x[i]); }
             l
         }",
    )
    .expect("compiles");
    // Within memory, the same code instantiates.
    assert!(code.instantiate(&[1.0, 0.05], &[1000]).is_ok());
    for n in [100_000_000, 10_000_000_000] {
        match code.instantiate(&[1.0, 0.05], &[n]) {
            Err(Error::Step(StepError::OutOfMemory { what, bytes })) => {
                // Per element of the two families: loop index twice and the stencil.
                assert_eq!(bytes, 8 * (3 * n as u128 + 4 * (n as u128 - 1)), "{what}");
                println!("typed error: {what}, {bytes} bytes");
            }
            Err(other) => panic!("n = {n}: {other}"),
            Ok(_) => panic!("n = {n}: instantiated"),
        }
    }
}
