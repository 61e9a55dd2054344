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
//! method = "plus"           # "plus", "minus" (reduced; "reduced" is "plus") or "unreduced"
//! # order = 4               # 2 (default), 4 or 6: the integrator and its compositions
//! # scheme = "gauss"        # with `order` any even number to 32: the Gauss–Legendre integrator
//! #                         # (a continuous Lagrangian without constraints, at most 8 coordinates)
//! out = "kepler.parquet"    # relative to this file; --out overrides
//! # schedule = [0.01, 0.005, 0.005]   each step's size (at least `steps` of them; `steps`
//! #                                    defaults to their number), instead of the system's `h`
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
//! A system on rotation groups (`rotation(R)`, `direction(n)` coordinates) starts from its
//! coordinates by name — a rotation's matrix (rows, or 9 numbers row by row), a direction's
//! unit vector, a scalar — and their momenta (a rotation's body momentum, a direction's momentum
//! as a vector in space), or with adaptive steps their velocities (`[start.v]`); its `method` is
//! "plus" (or "unreduced"), "minus" or "reduced" (by its declared symmetry). The words read as
//! the Python package reads them, into the same run request (`dirac_jit::RunRequest`):
//!
//! ```toml
//! system = "heavy_top.rs"
//! steps = 1000
//! method = "reduced"
//!
//! [parameters]
//! h = 0.01
//! j1 = 1.0
//! j2 = 1.0
//! j3 = 0.5
//! mgl = 2.0
//!
//! [start.q]
//! r = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
//!
//! [start.p]
//! r = [0.2, -0.1, 3.0]
//! ```
//!
//! A robot from its URDF file: `urdf = "arm.urdf"` in place of `system` — the model's
//! Lagrangian written as text by `dirac-multibody` (joint angles with the midpoint rule for a
//! fixed base, a floating base on `SE(3)` beside them), its coordinates and so its columns named
//! after the joints. `torques = true` adds a control `tau_<joint>` for each scalar joint (given
//! in `[parameters]`, held over the run), `gravity = [0, 0, 0]` replaces the standard gravity
//! (a floating base out of gravity declares its rigid motions: `method = "reduced"` keeps its
//! total momentum as the run's parameter). A malformed file is refused naming the element:
//!
//! ```toml
//! urdf = "three_link_arm.urdf"
//! steps = 1000
//! method = "unreduced"
//!
//! [parameters]
//! h = 0.01
//!
//! [start]
//! q = [1.2, 0.3, -0.2]
//! p = [0.1, -0.05, 0.02]
//! ```
//!
//! An element-wise system (`coordinates(x[n])`) gives its sizes by name in `[sizes]` and starts
//! from `q` and `p`, every coordinate in order (a grid row by row); its `method` is "plus" (or
//! "unreduced") or "minus", and its file has one column per coordinate index (`q_0`, …):
//!
//! ```toml
//! system = "toda.rs"
//! steps = 1000
//!
//! [parameters]
//! m = 1.0
//! d = 1.0
//! h = 0.05
//!
//! [sizes]
//! n = 4
//!
//! [start]
//! q = [0.0, 1.1, 2.0, 2.9]
//! p = [0.3, 0.05, -0.2, 0.05]
//! ```
//!
//! A system on vector spaces runs at any size: up to 8 coordinates (with constraints up to 6,
//! one of them a group coordinate, and 3 constraints) on the fixed-size integrators, bit for bit
//! as compiled in; above, on its element view (`sizes`), the same trajectory to round-off, its
//! file then with the columns `q_<coordinate>` and `p_<coordinate>` whatever the method.
//!
//! Exit status 0 on success, 1 when the system or a step fails (the states computed before a
//! failed step are written and named), 2 for a malformed command line or file.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;

use dirac::prelude::*;
use dirac_io::{Describe, Options, ParquetObserver, StateColumns};
use dirac_jit::run::{gauss, Finish, Job, LieStart};
use dirac_jit::{Code, Compiled, ElementCode, LieCode, RunRequest};

/// A parsed system file.
struct Config {
    text: String,
    steps: usize,
    /// Which equations: one of the runtime's keywords (`Equations::KEYWORDS`), read as the
    /// system's family reads it ([`Config::request`]).
    method: &'static str,
    out: PathBuf,
    /// The order (`order = ..`, default 2).
    order: u32,
    /// How the order is reached (`scheme = ..`, default "composition").
    scheme: String,
    /// The size of each step (`schedule = [h0, h1, ..]`), or `None` for the system's own.
    schedule: Option<Vec<f64>>,
    parameters: Vec<(String, f64)>,
    /// The sizes of an element-wise system, by name (the table `[sizes]`; empty otherwise).
    sizes: Vec<(String, usize)>,
    start: toml::Table,
    /// The file read, named in the messages of its mistakes.
    file: PathBuf,
}

impl Config {
    /// The parameters by name, as the JIT's `instantiate_named` takes them.
    fn named(&self) -> Vec<(&str, f64)> {
        self.parameters
            .iter()
            .map(|(k, v)| (k.as_str(), *v))
            .collect()
    }

    /// The run the file asks of the compiled `system`: the one request every front end builds
    /// ([`RunRequest`]), the equations `method` names in the system's family (the runtime's one
    /// vocabulary: "plus" and "minus" the sides of its own form, "reduced" and "unreduced" the
    /// forms), checked against the system there (reduced equations only where it has them).
    fn request(&self, system: &Compiled) -> Result<RunRequest, Failure> {
        RunRequest::from_keywords(
            system,
            self.method,
            &self.scheme,
            self.order,
            self.steps,
            None,
        )
        .and_then(|r| r.with_schedule(self.schedule.clone()))
        .map_err(|e| Failure::Run(format!("{}: {e}", self.file.display())))
    }
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
    let system = dirac_jit::compile_any(&config.text).map_err(|e| Failure::Run(e.to_string()))?;
    let request = config.request(&system)?;
    // What `[start]` may hold and what it is, and the names `check` prints, by the family.
    let (accepted, kind, name, time, names): (&[&str], &str, _, _, Vec<(&str, String)>) =
        match &system {
            Compiled::Flat(code) => {
                let sys = code.system();
                let (accepted, kind): (&[&str], _) = match request.equations.form {
                    Form::Unreduced => (&["q", "p"], "the state of an unreduced run"),
                    Form::Reduced => (&["x", "w", "mu", "g"], "the state of a reduced run"),
                };
                let names = vec![
                    ("shape", sys.shape.join(", ")),
                    ("group", sys.group.join(", ")),
                    ("parameters", sys.parameters.join(", ")),
                ];
                (accepted, kind, &sys.name, code.compile_time(), names)
            }
            Compiled::Lie(code) => {
                let sys = code.system();
                let coordinates: Vec<String> = (sys.coordinates.iter())
                    .map(|c| format!("{} ({:?})", c.name, c.kind).to_lowercase())
                    .collect();
                let names = vec![
                    ("coordinates", coordinates.join(", ")),
                    ("parameters", sys.parameters.join(", ")),
                ];
                let kind = "a system on rotation groups starts from the tables `[start.q]` and \
                            `[start.p]`, or `[start.v]` with adaptive steps";
                (
                    &["q", "p", "v"],
                    kind,
                    &sys.name,
                    code.compile_time(),
                    names,
                )
            }
            Compiled::Element(code) => {
                let sys = code.system();
                let names = vec![
                    ("sizes", sys.sizes.join(", ")),
                    ("parameters", sys.parameters.join(", ")),
                ];
                let kind = "an element-wise system starts from `q` and `p`, its coordinates in \
                            order, each grid row by row";
                (&["q", "p"], kind, &sys.name, code.compile_time(), names)
            }
        };
    check_start(&config, accepted, kind)?;
    perform(command, (name, time, &names), || match &system {
        Compiled::Flat(code) => run_flat(code, &config, &request),
        Compiled::Lie(code) => run_lie(code, &config, &request),
        Compiled::Element(code) => run_element(code, &config, &request),
    })
}

/// `check` (the system's name, the time its text took to compile, its names) or `run` (the
/// run's report), as `command` asks.
fn perform(
    command: &str,
    (name, time, names): (&str, std::time::Duration, &[(&str, String)]),
    run: impl FnOnce() -> Result<String, String>,
) -> Result<(), Failure> {
    match command {
        "check" => {
            compiled(name, time);
            for (what, list) in names {
                println!("{what}: {list}");
            }
            Ok(())
        }
        "run" => {
            let report = run().map_err(Failure::Run)?;
            println!("{report}");
            Ok(())
        }
        other => Err(Failure::Usage(format!("unknown command `{other}`"))),
    }
}

/// The first line `check` prints: the system's name and the time its text took to compile.
fn compiled(name: &str, time: std::time::Duration) {
    println!("{name}: compiled in {:.1} ms", time.as_secs_f64() * 1e3);
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
        "urdf",
        "torques",
        "gravity",
        "steps",
        "method",
        "order",
        "scheme",
        "out",
        "schedule",
        "parameters",
        "sizes",
        "start",
    ];
    if let Some(key) = table.keys().find(|k| !known.contains(&k.as_str())) {
        return Err(usage(format!(
            "unknown key `{key}`; accepted: {}",
            known.join(", ")
        )));
    }
    let text = match (table.get("system"), table.get("text"), table.get("urdf")) {
        (Some(toml::Value::String(file)), None, None) => std::fs::read_to_string(dir.join(file))
            .map_err(|e| usage(format!("system = \"{file}\": {e}")))?,
        (None, Some(toml::Value::String(text)), None) => text.clone(),
        (None, None, Some(toml::Value::String(file))) => robot_text(&dir.join(file), &table)
            .map_err(|e| usage(format!("urdf = \"{file}\": {e}")))?,
        _ => {
            return Err(usage(
                "give the system as `system = \"file.rs\"`, `text = \"\"\"..\"\"\"` or \
                 `urdf = \"robot.urdf\"`, one of them"
                    .into(),
            ))
        }
    };
    if !table.contains_key("urdf") {
        if let Some(key) = ["torques", "gravity"]
            .into_iter()
            .find(|k| table.contains_key(*k))
        {
            return Err(usage(format!("`{key}` goes with `urdf = \"robot.urdf\"`")));
        }
    }
    // Positive finite sizes, one for each step: checked with the request (`with_schedule`).
    let schedule = match table.get("schedule") {
        None => None,
        Some(v @ toml::Value::Array(a)) if a.iter().all(|e| !e.is_array()) => numbers(v),
        Some(_) => None,
    };
    if table.contains_key("schedule") && schedule.is_none() {
        return Err(usage(
            "`schedule` must be an array of step sizes, `[h0, h1, ..]`".into(),
        ));
    }
    let steps = match (table.get("steps"), &schedule) {
        (Some(toml::Value::Integer(n)), _) if *n > 0 => *n as usize,
        (None, Some(sizes)) if !sizes.is_empty() => sizes.len(),
        _ => {
            return Err(usage(
                "`steps` must be a positive integer (or left out with a `schedule`: one step \
                 for each size)"
                    .into(),
            ))
        }
    };
    // One of the runtime's keywords; which equations it names depends on the system's family.
    let method = match table.get("method").map(toml::Value::as_str) {
        None => Some("plus"),
        Some(word) => word.and_then(|w| Equations::KEYWORDS.into_iter().find(|&k| k == w)),
    };
    let Some(method) = method else {
        return Err(usage(
            "`method` is \"plus\", \"minus\", \"unreduced\" or (on rotation groups) \"reduced\""
                .into(),
        ));
    };
    let order = match table.get("order") {
        None => 2,
        Some(toml::Value::Integer(n)) if (1..=u32::MAX as i64).contains(n) => *n as u32,
        Some(_) => return Err(usage("`order` must be a positive integer".into())),
    };
    let scheme = match table.get("scheme") {
        None => "composition".to_owned(),
        Some(toml::Value::String(word)) => word.clone(),
        Some(_) => return Err(usage("`scheme` is \"composition\" or \"gauss\"".into())),
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
    let mut sizes = Vec::new();
    if table.contains_key("sizes") {
        for (k, v) in section("sizes")? {
            let size = v
                .as_integer()
                .and_then(|n| usize::try_from(n).ok())
                .ok_or_else(|| usage(format!("size `{k}` must be a non-negative integer")))?;
            sizes.push((k, size));
        }
    }
    let start = section("start")?;
    Ok(Config {
        text,
        steps,
        method,
        order,
        scheme,
        out,
        schedule,
        parameters,
        sizes,
        start,
        file: path.to_owned(),
    })
}

/// The Lagrangian text of the robot in the URDF file `path` (`dirac_multibody::Model`'s
/// `system_text_with`), named after the file: its coordinates named after the joints, with
/// `torques = true` a control `tau_<joint>` for each scalar joint, and `gravity = [x, y, z]`
/// in place of the standard gravity along `−z` (`[0, 0, 0]`: a floating base in space,
/// reduced by its rigid motions). Every mistake is a message naming the element or key.
fn robot_text(path: &Path, table: &toml::Table) -> Result<String, String> {
    let mut model = dirac_multibody::Model::from_urdf_file(path).map_err(|e| e.to_string())?;
    if let Some(g) = table.get("gravity") {
        let g = numbers(g)
            .filter(|g| g.len() == 3)
            .ok_or("`gravity` must be an array of three numbers, `[x, y, z]`")?;
        model = model
            .with_gravity(dirac_multibody::nalgebra::Vector3::new(g[0], g[1], g[2]))
            .map_err(|e| e.to_string())?;
    }
    let torques = match table.get("torques") {
        None => false,
        Some(toml::Value::Boolean(b)) => *b,
        Some(_) => return Err("`torques` must be true or false".into()),
    };
    let name = path
        .file_stem()
        .map_or_else(|| "robot".to_owned(), |s| s.to_string_lossy().into_owned());
    let options = dirac_multibody::TextOptions { name, torques };
    model
        .system_text_with(&options)
        .map(|text| text.text)
        .map_err(|e| e.to_string())
}

/// Refuses a key of the table `[start]` that a system of this kind does not start from, as
/// [`parse`] refuses an unknown top-level key (a usage error, exit status 2): a misspelled key
/// would otherwise be ignored, and its system started from zeros or refused for a missing one.
/// `kind` says what these keys are the start of.
fn check_start(config: &Config, accepted: &[&str], kind: &str) -> Result<(), Failure> {
    match config
        .start
        .keys()
        .find(|k| !accepted.contains(&k.as_str()))
    {
        Some(key) => Err(Failure::Usage(format!(
            "{}: unknown key `start.{key}`; accepted: {} ({kind})",
            config.file.display(),
            accepted.join(", ")
        ))),
        None => Ok(()),
    }
}

/// The numbers of a value: a number, an array of numbers, or an array of arrays (a matrix's
/// rows), flattened in order; `None` for anything else.
fn numbers(v: &toml::Value) -> Option<Vec<f64>> {
    match v {
        toml::Value::Float(f) => Some(vec![*f]),
        toml::Value::Integer(i) => Some(vec![*i as f64]),
        toml::Value::Array(a) => a
            .iter()
            .map(|e| match e {
                toml::Value::Array(_) => numbers(e),
                toml::Value::Float(_) | toml::Value::Integer(_) => numbers(e),
                _ => None,
            })
            .collect::<Option<Vec<Vec<f64>>>>()
            .map(|rows| rows.concat()),
        _ => None,
    }
}

/// The start's values `name`, `len` of them (an array, or an array of arrays read row by row).
fn values(config: &Config, name: &str, len: usize) -> Result<Vec<f64>, String> {
    let values = match config.start.get(name) {
        Some(v @ toml::Value::Array(_)) => {
            numbers(v).ok_or_else(|| format!("`start.{name}` must be an array of numbers"))?
        }
        Some(_) => return Err(format!("`start.{name}` must be an array of numbers")),
        None if len == 0 => Vec::new(),
        None => return Err(format!("`start.{name}` is missing ({len} values)")),
    };
    if values.len() != len {
        return Err(format!(
            "`start.{name}` has {} values; the system has {len}",
            values.len()
        ));
    }
    Ok(values)
}

/// Integrates the system on vector spaces by the equations the file's `method` names and
/// writes the run: from the start `(q, p)` or `(x, w, μ, g)`, at its fixed sizes (with
/// constraints, the constrained integrators; with `scheme = "gauss"`, the Gauss–Legendre
/// integrators) or, at any other size, on its element view.
fn run_flat(code: &Arc<Code>, config: &Config, request: &RunRequest) -> Result<String, String> {
    let sys = code.system();
    let (s, k) = (sys.shape.len(), sys.group.len());
    let params = parameters(&Compiled::Flat(Arc::clone(code)), config)?;
    let parts: &[(&str, usize)] = match request.equations.form {
        Form::Unreduced => &[("q", s + k), ("p", s + k)],
        Form::Reduced => &[("x", s), ("w", s), ("mu", k), ("g", k)],
    };
    let start = (parts.iter())
        .map(|&(name, len)| values(config, name, len))
        .collect::<Result<Vec<_>, _>>()?;
    if request.scheme == dirac_jit::Scheme::Gauss {
        // The request is checked: the fixed sizes, without constraints.
        return written(dirac_jit::with_dimensions!(
            s,
            k,
            gauss::<_>(code, &params, &[start], request, Write(&config.out))
                else Err(dirac_jit::Error::Request {
                    reason: "a Gauss–Legendre run takes at most 8 coordinates".to_owned(),
                })
        ));
    }
    written(dirac_jit::run_flat!(
        code,
        &params,
        &[start],
        request,
        Write(&config.out)
    ))
}

/// The file's parameters, by name, as the values in declaration order.
fn parameters(system: &Compiled, config: &Config) -> Result<Vec<f64>, String> {
    system
        .values_by_name(&config.named())
        .map_err(|e| e.to_string())
}

/// The start's values of each coordinate from the table `start.{part}`, in the order of the
/// coordinates (`None` when the table is absent).
fn per_coordinate(
    config: &Config,
    code: &LieCode,
    part: &str,
) -> Result<Option<Vec<Vec<f64>>>, String> {
    let table = match config.start.get(part) {
        None => return Ok(None),
        Some(toml::Value::Table(t)) => t,
        Some(_) => return Err(format!("`start.{part}` must be a table of the coordinates")),
    };
    let coordinates = &code.system().coordinates;
    if let Some(k) = table
        .keys()
        .find(|k| !coordinates.iter().any(|c| &c.name == *k))
    {
        let names: Vec<&str> = coordinates.iter().map(|c| c.name.as_str()).collect();
        return Err(format!(
            "`start.{part}.{k}` is not a coordinate; the coordinates: {}",
            names.join(", ")
        ));
    }
    coordinates
        .iter()
        .map(|c| {
            let v = table
                .get(&c.name)
                .ok_or_else(|| format!("`start.{part}.{}` is missing", c.name))?;
            numbers(v).ok_or_else(|| format!("`start.{part}.{}` must be numbers", c.name))
        })
        .collect::<Result<Vec<_>, _>>()
        .map(Some)
}

/// Integrates the system on rotation groups by the equations the file asks for and writes
/// the run: at the fixed sizes of the small systems (stack vectors, the dense LU), any other at
/// the sizes the text declares.
fn run_lie(code: &Arc<LieCode>, config: &Config, request: &RunRequest) -> Result<String, String> {
    let params = parameters(&Compiled::Lie(Arc::clone(code)), config)?;
    let q = per_coordinate(config, code, "q")?.ok_or("the table `[start.q]` is missing")?;
    let start = match (
        per_coordinate(config, code, "p")?,
        per_coordinate(config, code, "v")?,
    ) {
        (Some(p), None) => LieStart { q, p: Some(p), v: None },
        (None, Some(v)) => LieStart { q, p: None, v: Some(v.concat()) },
        _ => {
            return Err(
                "give the momenta `[start.p]` or (with adaptive steps) the velocities `[start.v]`, one of them"
                    .into(),
            )
        }
    };
    written(dirac_jit::run_lie!(
        code,
        &params,
        &[start],
        request,
        Write(&config.out)
    ))
}

/// Integrates an element-wise system at the file's sizes by the element-wise integrator of the
/// side `method` names (the constrained one for a system with constraints) and writes the run:
/// one column per coordinate index (`q_0`, …, `p_0`, …), the sizes in `dirac.sizes`.
fn run_element(
    code: &Arc<ElementCode>,
    config: &Config,
    request: &RunRequest,
) -> Result<String, String> {
    let sizes: Vec<(&str, usize)> = config.sizes.iter().map(|(k, v)| (k.as_str(), *v)).collect();
    let sys = code
        .instantiate_named(&config.named(), &sizes)
        .map_err(|e| e.to_string())?;
    let n = sys.dim();
    let start = ElementState::new(values(config, "q", n)?, values(config, "p", n)?);
    written(dirac_jit::run::element(
        sys,
        vec![start],
        request,
        Write(&config.out),
    ))
}

/// A run written to Parquet at the path it holds, every state (the run's one output).
#[derive(Clone, Copy)]
struct Write<'a>(&'a Path);

impl Job for Write<'_> {
    /// What `run` prints, or why the run failed (the states before a failed step written).
    type Output = Result<String, String>;
}

impl<I> Finish<I> for Write<'_>
where
    I: Describe + Drive,
    I::State: StateColumns,
    I::Record: AsRef<StepStats>,
{
    fn finish(self, integ: I, starts: Vec<I::State>, request: &RunRequest) -> Self::Output {
        let start = starts.into_iter().next().ok_or("a run needs its start")?;
        let mut out = ParquetObserver::create(self.0, integ.describe(), Options::new())
            .map_err(|e| e.to_string())?;
        let result = dirac_jit::span!(integ.run(start), request, observe(out.observer()) => stream);
        let path = out.finish_with(&result).map_err(|e| e.to_string())?;
        match result {
            Ok(summary) => Ok(format!(
                "{} steps to t = {} written to {}",
                summary.step_count,
                summary.t,
                path.display()
            )),
            Err(e) => Err(format!(
                "{e}; the states before it are written to {}",
                path.display()
            )),
        }
    }
}

/// What a run ended with: its report, or why it failed (its system, request or start refused,
/// or a step).
fn written(run: Result<Result<String, String>, dirac_jit::Error>) -> Result<String, String> {
    run.map_err(|e| e.to_string())?
}
