//! `dirac`: a system given as text, integrated from the command line into Apache Parquet — the
//! form a run (or each task of a cluster's array job) is launched in without writing Rust.
//!
//! ```text
//! dirac run SYSTEM.toml [--out PATH]   integrate and write every state to PATH (a directory of parts)
//! dirac check SYSTEM.toml              compile the system and print its names
//! ```
//!
//! The file:
//!
//! ```toml
//! system = "kepler.rs"      # the attribute and function, in a file beside this one
//! # text = """#[reduced_lagrangian(..)] fn ..."""   (or inline)
//! steps = 1000
//! method = "plus"           # "plus", "minus" (reduced) or "unreduced"
//! out = "kepler.parquet"    # relative to this file; --out overrides
//!
//! [parameters]              # every parameter of the function, by name
//! h = 0.01
//! k = 1.0
//!
//! [start]                   # x, w, mu, g (reduced) or q, p (unreduced)
//! x = [0.5]
//! w = [0.0]
//! mu = [0.8660254037844386]
//! g = [0.0]
//! ```
//!
//! Exit status 0 on success, 1 when the system or a step fails (the states computed before a
//! failed step are written and named), 2 for a malformed command line or file.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;

use dirac::prelude::*;
use dirac_io::{run_to_parquet, Describe, StateColumns};
use dirac_jit::Code;

/// Which equations a run solves.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Method {
    Plus,
    Minus,
    Unreduced,
}

/// A parsed system file.
struct Config {
    text: String,
    steps: usize,
    method: Method,
    out: PathBuf,
    parameters: Vec<(String, f64)>,
    start: Vec<(String, Vec<f64>)>,
}

/// A mistake in the command line or the file (exit status 2), or a failed system or run (1).
enum Failure {
    Usage(String),
    Run(String),
}

const USAGE: &str = "usage: dirac run SYSTEM.toml [--out PATH] | dirac check SYSTEM.toml";

fn main() -> ExitCode {
    match cli(std::env::args().skip(1).collect()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Usage(m)) => {
            eprintln!("error: {m}\n{USAGE}");
            ExitCode::from(2)
        }
        Err(Failure::Run(m)) => {
            eprintln!("error: {m}");
            ExitCode::from(1)
        }
    }
}

fn cli(args: Vec<String>) -> Result<(), Failure> {
    let (command, file, out) = match args.as_slice() {
        [c, f] => (c.as_str(), f, None),
        [c, f, o, path] if o == "--out" => (c.as_str(), f, Some(PathBuf::from(path))),
        [h] if h == "--help" || h == "-h" => {
            println!("{USAGE}");
            return Ok(());
        }
        _ => {
            return Err(Failure::Usage(
                "expected a command and a system file".into(),
            ))
        }
    };
    let path = Path::new(file);
    let mut config = parse(path)?;
    if let Some(out) = out {
        config.out = out;
    }
    let code = dirac_jit::compile(&config.text).map_err(|e| Failure::Run(e.to_string()))?;
    let sys = code.system();
    if sys.constrained.is_some() {
        return Err(Failure::Run(format!(
            "{}: a system with constraints; `dirac run` integrates systems without them \
             (the constrained integrators take it from Rust: `dirac_jit::Code::instantiate_constrained`)",
            sys.name
        )));
    }
    match command {
        "check" => {
            println!(
                "{}: compiled in {:.1} ms",
                sys.name,
                code.compile_time().as_secs_f64() * 1e3
            );
            println!("shape: {}", sys.shape.join(", "));
            println!("group: {}", sys.group.join(", "));
            println!("parameters: {}", sys.parameters.join(", "));
            Ok(())
        }
        "run" => {
            let (s, k) = (sys.shape.len(), sys.group.len());
            let report =
                dirac_jit::with_dimensions!(s, k, run(&code, &config)).map_err(Failure::Run)?;
            println!("{report}");
            Ok(())
        }
        other => Err(Failure::Usage(format!("unknown command `{other}`"))),
    }
}

/// Reads and checks the file (every mistake is a usage error, exit status 2).
fn parse(path: &Path) -> Result<Config, Failure> {
    let usage = |m: String| Failure::Usage(format!("{}: {m}", path.display()));
    let source = std::fs::read_to_string(path).map_err(|e| usage(e.to_string()))?;
    let table: toml::Table = source
        .parse()
        .map_err(|e: toml::de::Error| usage(e.to_string()))?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let known = [
        "system",
        "text",
        "steps",
        "method",
        "out",
        "parameters",
        "start",
    ];
    if let Some(key) = table.keys().find(|k| !known.contains(&k.as_str())) {
        return Err(usage(format!(
            "unknown key `{key}`; accepted: {}",
            known.join(", ")
        )));
    }
    let text =
        match (table.get("system"), table.get("text")) {
            (Some(toml::Value::String(file)), None) => std::fs::read_to_string(dir.join(file))
                .map_err(|e| usage(format!("system = \"{file}\": {e}")))?,
            (None, Some(toml::Value::String(text))) => text.clone(),
            _ => return Err(usage(
                "give the system as `system = \"file.rs\"` or `text = \"\"\"..\"\"\"`, one of them"
                    .into(),
            )),
        };
    let steps = match table.get("steps") {
        Some(toml::Value::Integer(n)) if *n > 0 => *n as usize,
        _ => return Err(usage("`steps` must be a positive integer".into())),
    };
    let method = match table.get("method").map(toml::Value::as_str) {
        None | Some(Some("plus")) => Method::Plus,
        Some(Some("minus")) => Method::Minus,
        Some(Some("unreduced")) => Method::Unreduced,
        _ => {
            return Err(usage(
                "`method` is \"plus\", \"minus\" or \"unreduced\"".into(),
            ))
        }
    };
    let out = match table.get("out") {
        Some(toml::Value::String(o)) => dir.join(o),
        None => path.with_extension("parquet"),
        _ => return Err(usage("`out` must be a path".into())),
    };
    let number = |v: &toml::Value| match v {
        toml::Value::Float(f) => Some(*f),
        toml::Value::Integer(i) => Some(*i as f64),
        _ => None,
    };
    let section = |name: &str| match table.get(name) {
        Some(toml::Value::Table(t)) => Ok(t.clone()),
        _ => Err(usage(format!("missing the table `[{name}]`"))),
    };
    let mut parameters = Vec::new();
    for (k, v) in section("parameters")? {
        let v = number(&v).ok_or_else(|| usage(format!("parameter `{k}` must be a number")))?;
        parameters.push((k, v));
    }
    let mut start = Vec::new();
    for (k, v) in section("start")? {
        let values = match &v {
            toml::Value::Array(a) => a.iter().map(number).collect::<Option<Vec<f64>>>(),
            _ => None,
        }
        .ok_or_else(|| usage(format!("`start.{k}` must be an array of numbers")))?;
        start.push((k, values));
    }
    Ok(Config {
        text,
        steps,
        method,
        out,
        parameters,
        start,
    })
}

/// The start's vector `name` of length `len`.
fn vector<const D: usize>(config: &Config, name: &str) -> Result<SVector<f64, D>, String> {
    let values = config
        .start
        .iter()
        .find(|(k, _)| k == name)
        .map(|(_, v)| v.as_slice())
        .or((D == 0).then_some(&[][..]))
        .ok_or_else(|| format!("`start.{name}` is missing ({D} values)"))?;
    if values.len() != D {
        return Err(format!(
            "`start.{name}` has {} values; the system has {D}",
            values.len()
        ));
    }
    Ok(SVector::from_column_slice(values))
}

/// Integrates the system at dimensions `S`, `K`, `N` and writes the run.
fn run<const S: usize, const K: usize, const N: usize>(
    code: &Arc<Code>,
    config: &Config,
) -> Result<String, String> {
    let named: Vec<(&str, f64)> = config
        .parameters
        .iter()
        .map(|(k, v)| (k.as_str(), *v))
        .collect();
    let sys = code
        .instantiate_named::<S, K, N>(&named)
        .map_err(|e| e.to_string())?;
    let options = NewtonOptions::default();
    match config.method {
        Method::Unreduced => {
            let start = UnreducedState {
                q: vector::<N>(config, "q")?,
                p: vector::<N>(config, "p")?,
            };
            write(UnreducedIntegrator::new(sys, options), start, config)
        }
        side => {
            let start = ReducedState {
                x: vector::<S>(config, "x")?,
                w: vector::<S>(config, "w")?,
                mu: vector::<K>(config, "mu")?,
                g: vector::<K>(config, "g")?,
            };
            if side == Method::Plus {
                write(ReducedIntegrator::plus(sys, options), start, config)
            } else {
                write(ReducedIntegrator::minus(sys, options), start, config)
            }
        }
    }
}

/// Runs `integ` from `start`, every state into the Parquet output.
fn write<I>(integ: I, start: I::State, config: &Config) -> Result<String, String>
where
    I: Describe + Drive,
    I::State: StateColumns,
    I::Record: AsRef<StepStats>,
{
    let options = NewtonOptions::default();
    let (result, path) = run_to_parquet(&integ, start, config.steps, &config.out, &options)
        .map_err(|e| e.to_string())?;
    match result {
        Ok(summary) => Ok(format!(
            "{} steps to t = {} written to {}",
            summary.steps,
            summary.t,
            path.display()
        )),
        Err(e) => Err(format!(
            "{e}; the states before it are written to {}",
            path.display()
        )),
    }
}
