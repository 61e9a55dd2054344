//! `dirac check` on system files at the edges of what the compiler takes: a body nested 10⁴ and
//! 10⁵ deep (the command line used to abort with a stack overflow) and a 10 MB body. Each ends
//! with an exit status and a message — success, or the typed error naming the limit — never a
//! signal.

use std::path::{Path, PathBuf};
use std::process::Command;

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch directory");
    dir
}

/// The attribute and signature, and the body's first term.
const HEAD: &str = "#[reduced_lagrangian(shape(x), group(theta))]
fn big(q0: Config, q1: Config, h: f64, m: f64) -> f64 {
    0.5 * m / h * ((q1.x - q0.x) * (q1.x - q0.x) + (q1.theta - q0.theta) * (q1.theta - q0.theta))
";

const TOML: &str = r#"system = "system.rs"
steps = 10

[parameters]
h = 0.01
m = 1.0

[start]
x = [1.0]
w = [0.0]
mu = [0.1]
g = [0.0]
"#;

/// `dirac check` of `system`: the exit status (`None` for a signal), stdout and stderr.
fn check(dir: &Path, system: &str) -> (Option<i32>, String, String) {
    std::fs::write(dir.join("system.rs"), system).unwrap();
    let file = dir.join("system.toml");
    std::fs::write(&file, TOML).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_dirac"))
        .args(["check", file.to_str().unwrap()])
        .output()
        .expect("the binary runs");
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Parentheses nested 10⁴ and 10⁵ deep: exit status 1 with the limit, the line and the column
/// of the parenthesis that passes it.
#[test]
fn check_refuses_parentheses_nested_beyond_the_limit() {
    let dir = scratch("cli_nested");
    for depth in [10_000, 100_000] {
        let system = format!(
            "{HEAD}        - h * {}q0.x{}\n}}\n",
            "(".repeat(depth),
            ")".repeat(depth)
        );
        let (code, _, stderr) = check(&dir, &system);
        let head: String = stderr.chars().take(400).collect();
        assert_eq!(code, Some(1), "{head}");
        assert!(head.contains("nested deeper than 256 levels"), "{head}");
        assert!(head.contains(" --> 4:270"), "{head}");
    }
}

/// A 10 MB body, a flat sum of 2.2 × 10⁵ terms (the command line used to die with SIGSEGV):
/// `dirac check` compiles it, or refuses it with exit status 1 and the typed error naming the
/// size of machine code one function may have.
#[test]
fn check_compiles_a_ten_megabyte_body_or_refuses_it_naming_the_limit() {
    let dir = scratch("cli_ten_megabytes");
    let mut system = String::from(HEAD);
    for i in 0..220_000 {
        let c = 1.0 + f64::from(i) / 1024.0;
        system.push_str(&format!("        - h * m * q0.x * q1.x * {c:.10}\n"));
    }
    system.push_str("}\n");
    assert!(system.len() > 10_000_000);
    let (code, stdout, stderr) = check(&dir, &system);
    let head: String = stderr.chars().take(2000).collect();
    match code {
        Some(0) => assert!(stdout.contains("shape: x"), "{stdout}"),
        Some(1) => assert!(
            head.contains("operations is too large for one function of machine code"),
            "{head}"
        ),
        other => panic!("ended with {other:?}: {head}"),
    }
}
