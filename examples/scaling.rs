//! How dirac scales with the size of the system: compile time, code size, evaluation and step
//! time, Newton iterations and memory, for two systems written with `#[reduced_lagrangian]`,
//! optionally against CasADi and (for the lattice) a hand-written `O(n)` Newton step.
//!
//! ```sh
//! cargo run --release --example scaling -- [--casadi] [--chain 2,4,8,16,32,64] \
//!     [--lattice 16,64,200,1000] [--out DIR] [--build-timeout SECONDS]
//! ```
//!
//! # Systems
//!
//! * `chain`: `n` links (absolute angles) hanging from a cart, `shape(theta[n]), group(c)`,
//!   `mc = m = l = 1`, `gr = 9.81`, `h = 0.01`, from `θ_i = 0.3 sin(i + 1)` at rest
//!   (`n + 1` unknowns per step);
//! * `lattice`: the periodic Toda lattice of `n` unit masses in their own positions,
//!   `coordinates(x[n]), translate(x)`, `m = d = 1`, `h = 0.05`, from
//!   `x_i = i d + 0.1 sin(2πi/n)`, `v_i = 0.3 cos(2πi/n)` (`n` unknowns per step).
//!
//! # How
//!
//! The attribute needs the size as a literal, so for every `(system, n)` this example writes a
//! scratch crate `target/dirac-scaling/<system>_<n>/` from the templates in `benches/scaling/`
//! (`chain.rs.in`, `lattice.rs.in`, with `@N@` placeholders, plus `measure.rs`), depending on
//! this workspace's `dirac` by path, with the workspace's `Cargo.lock`, default
//! `[profile.release]` except for the attribute itself, built at `opt-level = 3` as the README
//! recommends for large systems, its own `[workspace]`, and one shared target directory
//! `target/dirac-scaling/target`. A warm-up crate (the smallest chain) is built first so that
//! dirac and its dependencies are compiled once and not counted. For every crate:
//!
//! * **compile s / compile MB**: after a first `cargo build --release`, `src/main.rs` is touched
//!   and the crate rebuilt; the wall time of that rebuild is the release compile time of the user
//!   crate alone (macro expansion, type checking, LLVM), and, where `/usr/bin/time -v` exists,
//!   its maximum resident set size is rustc's peak memory;
//! * the binary then measures in one process and prints one line: the operation count and
//!   Jacobian nonzeros of the reduced (+) residual with its Jacobian (from `<Type>::GENERATED`),
//!   the median ns of one `Reduced::<Plus, ..>::residual_jacobian` at a state from the run, the
//!   median ns per step of `ReducedIntegrator::plus(..).run(..)` over batches of ≈ 0.2 s, the
//!   mean Newton iterations, and the peak memory (`VmHWM`) after the runs; for the lattice also
//!   the hand-written banded Newton step of `benches/common/toda_hand.rs` (the physical-limit
//!   baseline), timed over the same steps from the same state with batches interleaved with
//!   dirac's, and the relative difference of the two next states from one state;
//! * with `--casadi`, `benches/casadi_scaling/run.sh` generates, compiles (gcc -O3, timeout 300 s)
//!   and times CasADi's residual + sparse Jacobian of the same equations: its instruction count,
//!   gcc time, ns per evaluation and the ratio dirac R+J / CasADi R+J.
//!
//! A failing build or run of one row is reported in its row and the example continues. The table
//! is printed, and `scaling.csv` and `scaling.svg` (log-log times against `n`, one panel per
//! system) are written under `--out` (default `target/dirac-figures/scaling/`). At the end the
//! issue-8 targets are printed as met / not met by this run.
//!
//! Timings are wall-clock on whatever machine runs this; on a shared machine they are noisy.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::fs;
use std::io;
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus, Stdio};
use std::time::{Duration, Instant, SystemTime};

use plotters::prelude::*;

const ROOT: &str = env!("CARGO_MANIFEST_DIR");
const MEASURE: &str = include_str!("../benches/scaling/measure.rs");
const CHAIN: &str = include_str!("../benches/scaling/chain.rs.in");
const LATTICE: &str = include_str!("../benches/scaling/lattice.rs.in");

/// A scalable system.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum System {
    Chain,
    Lattice,
}

impl System {
    fn name(self) -> &'static str {
        match self {
            System::Chain => "chain",
            System::Lattice => "lattice",
        }
    }

    /// Newton unknowns per step: `n` angles and the cart, or `n − 1` shapes and the group.
    fn unknowns(self, n: usize) -> usize {
        match self {
            System::Chain => n + 1,
            System::Lattice => n,
        }
    }

    /// The scratch crate's `main.rs`.
    fn source(self, n: usize) -> String {
        let hand = Path::new(ROOT).join("benches/common/toda_hand.rs");
        let template = match self {
            System::Chain => CHAIN,
            System::Lattice => LATTICE,
        };
        template
            .replace("@TODA_HAND@", &hand.display().to_string())
            .replace("@NU@", &self.unknowns(n).to_string())
            .replace("@NM1@", &(n - 1).to_string())
            .replace("@N@", &n.to_string())
    }
}

/// Command-line options.
struct Options {
    casadi: bool,
    chain: Vec<usize>,
    lattice: Vec<usize>,
    out: PathBuf,
    build_timeout: Duration,
}

fn parse_list(flag: &str, value: Option<String>, min: usize) -> Result<Vec<usize>, String> {
    let value = value.ok_or(format!("{flag} needs a value such as 2,8"))?;
    if value.is_empty() {
        return Ok(Vec::new());
    }
    value
        .split(',')
        .map(|s| match s.trim().parse::<usize>() {
            Ok(n) if n >= min => Ok(n),
            _ => Err(format!("{flag}: `{s}` is not an integer ≥ {min}")),
        })
        .collect()
}

fn parse_options() -> Result<Options, String> {
    let mut o = Options {
        casadi: false,
        chain: vec![2, 4, 8, 16, 32, 64],
        lattice: vec![16, 64, 200, 1000],
        out: Path::new(ROOT).join("target/dirac-figures/scaling"),
        build_timeout: Duration::from_secs(600),
    };
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--casadi" => o.casadi = true,
            "--chain" => o.chain = parse_list("--chain", args.next(), 1)?,
            "--lattice" => o.lattice = parse_list("--lattice", args.next(), 3)?,
            "--out" => o.out = PathBuf::from(args.next().ok_or("--out needs a directory")?),
            "--build-timeout" => {
                let s = args.next().ok_or("--build-timeout needs seconds")?;
                let secs: u64 = s
                    .parse()
                    .map_err(|_| format!("--build-timeout: `{s}` is not a number of seconds"))?;
                o.build_timeout = Duration::from_secs(secs);
            }
            "-h" | "--help" => {
                return Err(
                    "usage: cargo run --release --example scaling -- [--casadi] \
                     [--chain 2,4,8,16,32,64] [--lattice 16,64,200,1000] [--out DIR] \
                     [--build-timeout SECONDS]"
                        .into(),
                )
            }
            other => return Err(format!("unknown argument `{other}` (try --help)")),
        }
    }
    Ok(o)
}

/// How a child process ended.
enum Finished {
    Exited(ExitStatus),
    TimedOut,
}

/// Runs `cmd` in its own process group with stdout and stderr to `log`, killing the whole group
/// after `timeout`. Returns how it ended and its wall time.
fn run_logged(
    cmd: &mut Command,
    log: &Path,
    timeout: Duration,
) -> io::Result<(Finished, Duration)> {
    let out = fs::File::create(log)?;
    let err = out.try_clone()?;
    let t0 = Instant::now();
    let mut child = cmd
        .stdin(Stdio::null())
        .stdout(out)
        .stderr(err)
        .process_group(0)
        .spawn()?;
    loop {
        if let Some(status) = child.try_wait()? {
            return Ok((Finished::Exited(status), t0.elapsed()));
        }
        if t0.elapsed() >= timeout {
            // The group id is the child's pid (process_group(0)): end cargo and its rustc.
            let group = format!("-{}", child.id());
            let _ = Command::new("kill").args(["-KILL", "--", &group]).status();
            let _ = child.kill();
            let _ = child.wait();
            return Ok((Finished::TimedOut, t0.elapsed()));
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// The first line of a build log that says what went wrong.
fn first_error(log: &str) -> String {
    log.lines()
        .find(|l| l.starts_with("error"))
        .or_else(|| log.lines().rev().find(|l| !l.trim().is_empty()))
        .unwrap_or("(empty log)")
        .trim()
        .chars()
        .take(120)
        .collect()
}

/// `key=value` fields of the first line starting with `prefix`.
fn fields(output: &str, prefix: &str) -> Option<HashMap<String, String>> {
    let line = output.lines().find(|l| l.starts_with(prefix))?;
    Some(
        line[prefix.len()..]
            .split_whitespace()
            .filter_map(|kv| kv.split_once('='))
            .map(|(k, v)| (k.to_owned(), v.to_owned()))
            .collect(),
    )
}

fn num(f: &HashMap<String, String>, key: &str) -> Option<f64> {
    f.get(key).and_then(|v| v.parse().ok())
}

/// One row of the table; `None` is a quantity not measured.
#[derive(Default)]
struct Row {
    system: &'static str,
    n: usize,
    unknowns: usize,
    compile_s: Option<f64>,
    compile_mb: Option<f64>,
    ops: Option<f64>,
    nnz: Option<f64>,
    rj_ns: Option<f64>,
    step_ns: Option<f64>,
    iterations: Option<f64>,
    mem_mib: Option<f64>,
    hand_step_ns: Option<f64>,
    hand_diff: Option<f64>,
    casadi_instructions: Option<f64>,
    casadi_gcc_s: Option<String>,
    casadi_ns: Option<f64>,
    /// Why the dirac part of the row is incomplete.
    failure: Option<String>,
    casadi_failure: Option<String>,
}

impl Row {
    fn ratio(&self) -> Option<f64> {
        Some(self.rj_ns? / self.casadi_ns?)
    }

    fn hand_ratio(&self) -> Option<f64> {
        Some(self.step_ns? / self.hand_step_ns?)
    }
}

/// Where the scratch crates live.
struct Scratch {
    base: PathBuf,
    target: PathBuf,
    time_v: bool,
    timeout: Duration,
}

impl Scratch {
    fn new(timeout: Duration) -> Self {
        let base = Path::new(ROOT).join("target/dirac-scaling");
        Self {
            target: base.join("target"),
            base,
            time_v: Command::new("/usr/bin/time")
                .args(["-v", "true"])
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .status()
                .is_ok_and(|s| s.success()),
            timeout,
        }
    }

    fn package(system: System, n: usize) -> String {
        format!("scaling-{}-{n}", system.name())
    }

    /// Writes the crate (only files whose content changed, so a rerun rebuilds nothing extra).
    fn write(&self, system: System, n: usize) -> io::Result<PathBuf> {
        let dir = self.base.join(format!("{}_{n}", system.name()));
        fs::create_dir_all(dir.join("src"))?;
        let manifest = format!(
            "# Generated by examples/scaling.rs; not part of the dirac workspace.\n\
             [package]\nname = \"{}\"\nversion = \"0.0.0\"\nedition = \"2021\"\npublish = false\n\n\
             [dependencies]\ndirac = {{ path = \"{ROOT}\" }}\n\n[profile.release]\n\n\
             # As the README recommends for large systems: the attribute runs optimized.\n\
             [profile.release.package.dirac-macros]\nopt-level = 3\n\n[workspace]\n",
            Self::package(system, n)
        );
        let lock = fs::read_to_string(Path::new(ROOT).join("Cargo.lock")).unwrap_or_default();
        for (path, text) in [
            (dir.join("Cargo.toml"), manifest),
            (dir.join("src/main.rs"), system.source(n)),
            (dir.join("src/measure.rs"), MEASURE.to_owned()),
        ] {
            if fs::read_to_string(&path).ok().as_deref() != Some(text.as_str()) {
                fs::write(&path, text)?;
            }
        }
        // Pin dirac's dependencies to the workspace's versions (no registry lookup).
        if !lock.is_empty() && !dir.join("Cargo.lock").exists() {
            fs::write(dir.join("Cargo.lock"), lock)?;
        }
        Ok(dir)
    }

    /// `cargo build --release` of the crate in `dir`: wall time and, with `/usr/bin/time -v`,
    /// the peak RSS in MB. `Err` holds the message for the table.
    fn build(&self, dir: &Path) -> Result<(f64, Option<f64>), String> {
        let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
        let mut cmd = if self.time_v {
            let mut c = Command::new("/usr/bin/time");
            c.arg("-v").arg(&cargo);
            c
        } else {
            Command::new(&cargo)
        };
        cmd.args(["build", "--release", "--quiet", "--target-dir"])
            .arg(&self.target)
            .current_dir(dir)
            .env_remove("CARGO_TARGET_DIR");
        let log = dir.join("build.log");
        let (finished, wall) = run_logged(&mut cmd, &log, self.timeout)
            .map_err(|e| format!("build failed: cannot run {cargo}: {e}"))?;
        let text = fs::read_to_string(&log).unwrap_or_default();
        match finished {
            Finished::TimedOut => Err(format!("build timeout ({} s)", self.timeout.as_secs())),
            Finished::Exited(s) if !s.success() => {
                Err(format!("build failed: {}", first_error(&text)))
            }
            Finished::Exited(_) => {
                let rss = text
                    .lines()
                    .find_map(|l| l.trim().strip_prefix("Maximum resident set size (kbytes):"))
                    .and_then(|v| v.trim().parse::<f64>().ok())
                    .map(|kb| kb / 1024.0);
                Ok((wall.as_secs_f64(), rss))
            }
        }
    }

    /// Builds, times a rebuild of the user crate alone, runs the binary; fills `row`.
    fn measure(&self, system: System, n: usize, row: &mut Row) -> Result<(), String> {
        let dir = self
            .write(system, n)
            .map_err(|e| format!("cannot write the scratch crate: {e}"))?;
        self.build(&dir)?;
        let main = dir.join("src/main.rs");
        fs::File::options()
            .append(true)
            .open(&main)
            .and_then(|f| f.set_modified(SystemTime::now()))
            .map_err(|e| format!("cannot touch {}: {e}", main.display()))?;
        let (secs, mb) = self.build(&dir)?;
        row.compile_s = Some(secs);
        row.compile_mb = mb;
        let binary = self.target.join("release").join(Self::package(system, n));
        let log = dir.join("run.log");
        let (finished, _) = run_logged(&mut Command::new(&binary), &log, self.timeout)
            .map_err(|e| format!("run failed: cannot start {}: {e}", binary.display()))?;
        let text = fs::read_to_string(&log).unwrap_or_default();
        match finished {
            Finished::TimedOut => {
                return Err(format!("run timeout ({} s)", self.timeout.as_secs()))
            }
            Finished::Exited(s) if !s.success() => {
                return Err(format!("run failed: {}", first_error(&text)))
            }
            Finished::Exited(_) => {}
        }
        let f = fields(&text, "scaling:").ok_or("run failed: no `scaling:` line in its output")?;
        row.ops = num(&f, "ops");
        row.nnz = num(&f, "nnz");
        row.rj_ns = num(&f, "rj_ns");
        row.step_ns = num(&f, "step_ns");
        row.iterations = num(&f, "iterations");
        row.mem_mib = num(&f, "mem_mib");
        row.hand_step_ns = num(&f, "hand_step_ns");
        row.hand_diff = num(&f, "hand_rel_diff");
        Ok(())
    }
}

/// `bash benches/casadi_scaling/run.sh --system S --n N --gcc-timeout 300`; fills `row`.
fn casadi(system: System, n: usize, row: &mut Row, scratch: &Scratch) -> Result<(), String> {
    let log = scratch
        .base
        .join(format!("casadi_{}_{n}.log", system.name()));
    let mut cmd = Command::new("bash");
    cmd.arg(Path::new(ROOT).join("benches/casadi_scaling/run.sh"))
        .args(["--system", system.name(), "--n", &n.to_string()])
        .args(["--gcc-timeout", "300"])
        .current_dir(ROOT);
    // gcc has its own timeout; this one only guards against a hang elsewhere.
    let (finished, _) = run_logged(&mut cmd, &log, Duration::from_secs(1800))
        .map_err(|e| format!("cannot run bash: {e}"))?;
    let text = fs::read_to_string(&log).unwrap_or_default();
    match finished {
        Finished::TimedOut => return Err("casadi timeout".into()),
        Finished::Exited(s) if !s.success() => {
            return Err(format!("casadi failed: {}", first_error(&text)))
        }
        Finished::Exited(_) => {}
    }
    let f = fields(&text, "casadi-c:").ok_or("casadi: no `casadi-c:` line")?;
    row.casadi_instructions = num(&f, "instructions");
    row.casadi_gcc_s = f.get("gcc_s").cloned();
    row.casadi_ns = num(&f, "ns");
    Ok(())
}

fn fmt(v: Option<f64>, digits: usize) -> String {
    v.filter(|x| x.is_finite())
        .map_or("-".into(), |x| format!("{x:.digits$}"))
}

const HEADER: [&str; 16] = [
    "system",
    "n",
    "unknowns N",
    "compile s",
    "compile MB",
    "R+J ops",
    "nnz",
    "dirac R+J ns",
    "CasADi R+J ns",
    "ratio",
    "step µs",
    "Newton it.",
    "hand step µs",
    "step/hand",
    "memory MiB",
    "note",
];

fn cells(r: &Row, casadi: bool) -> Vec<String> {
    let casadi_ns = if casadi {
        r.casadi_ns.map_or_else(
            || r.casadi_gcc_s.clone().unwrap_or("-".into()),
            |v| format!("{v:.0}"),
        )
    } else {
        "-".into()
    };
    let mut note: Vec<String> = r.failure.iter().cloned().collect();
    note.extend(r.casadi_failure.iter().cloned());
    if let Some(d) = r.hand_diff {
        note.push(format!("hand vs dirac next state {d:.1e}"));
    }
    if let Some(g) = &r.casadi_gcc_s {
        let i = r
            .casadi_instructions
            .map_or("-".into(), |v| format!("{v:.0}"));
        note.push(format!("CasADi {i} instr, gcc {g} s"));
    }
    vec![
        r.system.into(),
        r.n.to_string(),
        r.unknowns.to_string(),
        fmt(r.compile_s, 1),
        fmt(r.compile_mb, 0),
        fmt(r.ops, 0),
        fmt(r.nnz, 0),
        fmt(r.rj_ns, 0),
        casadi_ns,
        fmt(r.ratio(), 2),
        fmt(r.step_ns.map(|v| v / 1e3), 2),
        fmt(r.iterations, 2),
        fmt(r.hand_step_ns.map(|v| v / 1e3), 2),
        fmt(r.hand_ratio(), 2),
        fmt(r.mem_mib, 1),
        note.join("; "),
    ]
}

fn print_table(rows: &[Row], casadi: bool) {
    let table: Vec<Vec<String>> = rows.iter().map(|r| cells(r, casadi)).collect();
    let width: Vec<usize> = (0..HEADER.len())
        .map(|c| {
            table
                .iter()
                .map(|r| r[c].chars().count())
                .chain([HEADER[c].chars().count()])
                .max()
                .unwrap_or(0)
        })
        .collect();
    let line = |r: &[String]| {
        let mut s = String::new();
        for (c, cell) in r.iter().enumerate() {
            let pad = width[c] - cell.chars().count();
            if c == HEADER.len() - 1 {
                s.push_str(cell);
            } else {
                let _ = write!(s, "{}{cell}  ", " ".repeat(pad));
            }
        }
        println!("{}", s.trim_end());
    };
    line(&HEADER.map(String::from));
    for r in &table {
        line(r);
    }
}

fn write_csv(rows: &[Row], path: &Path) -> io::Result<()> {
    let mut s = String::from(
        "system,n,unknowns,compile_s,compile_mb,rj_ops,nnz,dirac_rj_ns,casadi_instructions,\
         casadi_gcc_s,casadi_rj_ns,ratio,step_ns,newton_iterations,hand_step_ns,step_over_hand,\
         hand_rel_diff,memory_mib,note\n",
    );
    let c = |v: Option<f64>| {
        v.filter(|x| x.is_finite())
            .map_or(String::new(), |x| x.to_string())
    };
    for r in rows {
        let note = [r.failure.clone(), r.casadi_failure.clone()]
            .into_iter()
            .flatten()
            .collect::<Vec<_>>()
            .join("; ")
            .replace('"', "'");
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},\"{note}\"",
            r.system,
            r.n,
            r.unknowns,
            c(r.compile_s),
            c(r.compile_mb),
            c(r.ops),
            c(r.nnz),
            c(r.rj_ns),
            c(r.casadi_instructions),
            r.casadi_gcc_s.clone().unwrap_or_default(),
            c(r.casadi_ns),
            c(r.ratio()),
            c(r.step_ns),
            c(r.iterations),
            c(r.hand_step_ns),
            c(r.hand_ratio()),
            c(r.hand_diff),
            c(r.mem_mib),
        );
    }
    fs::write(path, s)
}

type Series = (&'static str, RGBColor, fn(&Row) -> Option<f64>);

/// Log-log times (ns) against `n`, one panel per system.
fn write_svg(rows: &[Row], path: &Path) -> Result<(), Box<dyn std::error::Error>> {
    let series: [Series; 4] = [
        ("dirac R+J", RGBColor(31, 119, 180), |r| r.rj_ns),
        ("CasADi R+J", RGBColor(255, 127, 14), |r| r.casadi_ns),
        ("dirac step", RGBColor(44, 160, 44), |r| r.step_ns),
        ("hand step", RGBColor(214, 39, 40), |r| r.hand_step_ns),
    ];
    let root = SVGBackend::new(path, (1100, 480)).into_drawing_area();
    root.fill(&WHITE)?;
    let panels = root.split_evenly((1, 2));
    for (area, system) in panels.iter().zip([System::Chain, System::Lattice]) {
        let points: Vec<(&Series, Vec<(f64, f64)>)> = series
            .iter()
            .map(|s| {
                let pts = rows
                    .iter()
                    .filter(|r| r.system == system.name())
                    .filter_map(|r| Some((r.n as f64, (s.2)(r).filter(|v| *v > 0.0)?)))
                    .collect();
                (s, pts)
            })
            .filter(|(_, p): &(_, Vec<_>)| !p.is_empty())
            .collect();
        let all = points.iter().flat_map(|(_, p)| p.iter());
        let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for &(x, y) in all {
            (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
        }
        if points.is_empty() {
            (x0, x1, y0, y1) = (1.0, 10.0, 1.0, 10.0);
        }
        let mut chart = ChartBuilder::on(area)
            .caption(
                format!("{}: time against n (log-log)", system.name()),
                ("sans-serif", 18),
            )
            .margin(12)
            .x_label_area_size(36)
            .y_label_area_size(64)
            .build_cartesian_2d(
                (x0 / 1.3..x1 * 1.3).log_scale(),
                (y0 / 2.0..y1 * 2.0).log_scale(),
            )?;
        chart
            .configure_mesh()
            .x_desc("n")
            .y_desc("ns")
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .draw()?;
        for ((name, color, _), pts) in &points {
            let color = *color;
            chart
                .draw_series(LineSeries::new(pts.iter().copied(), color.stroke_width(2)))?
                .label(*name)
                .legend(move |(x, y)| {
                    PathElement::new([(x, y), (x + 18, y)], color.stroke_width(2))
                });
            chart.draw_series(pts.iter().map(|&p| Circle::new(p, 3, color.filled())))?;
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()?;
    }
    root.present()?;
    Ok(())
}

/// The issue-8 targets, judged on this run's rows.
fn print_targets(rows: &[Row], casadi: bool) {
    let find = |s: System, n: usize| rows.iter().find(|r| r.system == s.name() && r.n == n);
    let verdict = |v: Option<bool>| match v {
        Some(true) => "met",
        Some(false) => "NOT met",
        None => "not measured",
    };
    let lattice = find(System::Lattice, 200);
    let chain32 = find(System::Chain, 32);
    let chain64 = find(System::Chain, 64);
    let targets: [(&str, Option<bool>, String); 5] = [
        (
            "lattice n = 200 compile ≤ 30 s",
            lattice.and_then(|r| r.compile_s).map(|s| s <= 30.0),
            fmt(lattice.and_then(|r| r.compile_s), 1) + " s",
        ),
        (
            "lattice n = 200 step ≤ 2 × hand step",
            lattice.and_then(Row::hand_ratio).map(|q| q <= 2.0),
            fmt(lattice.and_then(Row::hand_ratio), 2) + " ×",
        ),
        (
            "chain n = 32 compile ≤ 20 s",
            chain32.and_then(|r| r.compile_s).map(|s| s <= 20.0),
            fmt(chain32.and_then(|r| r.compile_s), 1) + " s",
        ),
        (
            "chain n = 32 R+J ≤ 1.0 × CasADi",
            chain32
                .filter(|_| casadi)
                .and_then(Row::ratio)
                .map(|q| q <= 1.0),
            fmt(chain32.and_then(Row::ratio), 2) + " ×",
        ),
        (
            "chain n = 64 compiles and runs",
            chain64.map(|r| r.failure.is_none() && r.step_ns.is_some()),
            chain64
                .and_then(|r| r.failure.clone())
                .unwrap_or_else(|| fmt(chain64.and_then(|r| r.compile_s), 1) + " s compile"),
        ),
    ];
    println!("\nissue-8 targets (this run):");
    for (what, ok, value) in targets {
        println!("  {:<12} {what}  ({value})", verdict(ok));
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let o = match parse_options() {
        Ok(o) => o,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(2);
        }
    };
    let scratch = Scratch::new(o.build_timeout);
    fs::create_dir_all(&scratch.base)?;
    fs::create_dir_all(&o.out)?;

    let work: Vec<(System, usize)> = o
        .chain
        .iter()
        .map(|&n| (System::Chain, n))
        .chain(o.lattice.iter().map(|&n| (System::Lattice, n)))
        .collect();
    // Warm-up: compiles dirac and its dependencies into the shared target directory (not
    // counted), with the smallest chain.
    let warm = o.chain.iter().min().copied().unwrap_or(2);
    eprintln!("warm-up: building dirac and its dependencies (chain n = {warm}, not counted)");
    let t0 = Instant::now();
    match scratch.write(System::Chain, warm) {
        Ok(dir) => match scratch.build(&dir) {
            Ok(_) => eprintln!("warm-up done in {:.0} s", t0.elapsed().as_secs_f64()),
            Err(e) => eprintln!("warm-up: {e} (continuing)"),
        },
        Err(e) => eprintln!("warm-up: cannot write the scratch crate: {e} (continuing)"),
    }

    let mut rows = Vec::new();
    for (system, n) in work {
        eprintln!("{} n = {n}: build, rebuild (timed), run", system.name());
        let mut row = Row {
            system: system.name(),
            n,
            unknowns: system.unknowns(n),
            ..Row::default()
        };
        if let Err(e) = scratch.measure(system, n, &mut row) {
            eprintln!("  {e}");
            row.failure = Some(e);
        }
        if o.casadi {
            eprintln!("{} n = {n}: CasADi", system.name());
            if let Err(e) = casadi(system, n, &mut row, &scratch) {
                eprintln!("  {e}");
                row.casadi_failure = Some(e);
            }
        }
        // The whole row as it stands, so a long run shows its results as they come.
        eprintln!("  {}", cells(&row, o.casadi).join(" | "));
        rows.push(row);
    }

    println!();
    print_table(&rows, o.casadi);
    let csv = o.out.join("scaling.csv");
    let svg = o.out.join("scaling.svg");
    write_csv(&rows, &csv)?;
    write_svg(&rows, &svg)?;
    println!("\nwrote {} and {}", csv.display(), svg.display());
    print_targets(&rows, o.casadi);
    Ok(())
}
