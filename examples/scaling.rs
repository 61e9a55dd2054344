//! How dirac scales with the size of the system: compile time, code size, evaluation and step
//! time, Newton iterations and memory, for three systems written with `#[reduced_lagrangian]`,
//! optionally against CasADi and (for the lattice) a hand-written `O(n)` Newton step.
//!
//! ```sh
//! cargo run --release --example scaling -- [--casadi] [--chain 2,4,8,16,32,64] \
//!     [--lattice 16,64,200,1000] [--lattice-n 100,1000,10000,100000] [--out DIR] \
//!     [--build-timeout SECONDS]
//! ```
//!
//! The lists shown are the defaults; an empty list (`--chain ''`) skips that system, and so does
//! `--lattice-n 0`. The `--lattice-n` sizes are run in ascending order.
//!
//! # Systems
//!
//! * `chain`: `n` links (absolute angles) hanging from a cart, `shape(theta[n]), group(c)`,
//!   `mc = m = l = 1`, `gr = 9.81`, `h = 0.01`, from `θ_i = 0.3 sin(i + 1)` at rest
//!   (`n + 1` unknowns per step);
//! * `lattice`: the periodic Toda lattice of `n` unit masses in their own positions,
//!   `coordinates(x[n]), translate(x)`, `m = d = 1`, `h = 0.05`, from
//!   `x_i = i d + 0.1 sin(2πi/n)`, `v_i = 0.3 cos(2πi/n)` (`n` unknowns per step);
//! * `lattice_n`: the same lattice as an element-wise system sized at run time (the body of
//!   `examples/common/toda_n.rs`, `coordinates(x[n]), translate(x)`, a `usize` argument `n`),
//!   integrated by `ElementIntegrator` (sparse LU, chord Newton): `m = 1`, `h = 0.05`, positions
//!   from the equilibrium sites (`d = 0`, the same dynamics as any `d`, without the rounding of
//!   `x_i ≈ i d` at large n), from `x_i = 0.1 sin(2πi/n)`, `p_i = 0.3 cos(2πi/n)` (`n` unknowns
//!   per step).
//!
//! # How
//!
//! For `chain` and `lattice` the attribute needs the size as a literal, so for every
//! `(system, n)` this example writes a scratch crate `target/dirac-scaling/<system>_<n>/` from
//! the templates in `benches/scaling/` (`chain.rs.in`, `lattice.rs.in`, with `@N@`
//! placeholders, plus `measure.rs` and the examples' `stats.rs` and `cli.rs`), depending on this
//! workspace's `dirac` by path, with the workspace's `Cargo.lock`, default `[profile.release]`
//! except for the attribute itself, built at `opt-level = 3` as the README recommends for large
//! systems, its own `[workspace]`, and one shared target directory `target/dirac-scaling/target`. A warm-up crate (the smallest chain)
//! is built first so that dirac and its dependencies are compiled once and not counted. For
//! every crate:
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
//! `lattice_n` is one crate for every `n` (`target/dirac-scaling/lattice_n/`, from
//! `benches/scaling/lattice_n.rs.in`, no placeholders), built and timed once as above (its
//! compile s / MB are repeated in each of its rows: the same build), then run once with all the
//! sizes on its command line, ascending; it prints one `scaling-element:` line per size:
//!
//! * **R+J ns**: the median ns of one `ElementIntegrator::residual_jacobian` at the initial state
//!   with `z = q0 + h p0`, serial (`Parallel::Never`, the column's figure and the one compared
//!   with CasADi); the same on all of rayon's threads (`Parallel::Always`) is in the note and the
//!   CSV (`dirac_rj_parallel_ns`; CasADi map's C size is `casadi_c_bytes`). It evaluates
//!   `R(z) = p0 + D1 L_d(q0, z)`, the Jacobian's values **and the next momentum
//!   `D2 L_d(q0, z)`** (fused into every residual pass): a superset of what CasADi's `rj`
//!   computes;
//! * **step**: the median ns per step of `step_into` with the default `Parallel::Auto` over
//!   batches of ≈ 0.2 s (at least 100 steps), every batch from the initial state with a fresh
//!   workspace (pattern, ordering, symbolic factorization) built before its clock starts; the
//!   mean Newton corrections per step; the process's peak memory (`VmHWM`) after that size;
//!   no hand-written step and no operation count;
//! * with `--casadi`, `benches/casadi_map/run.sh --n N` generates, compiles and times CasADi's
//!   `map` of the lattice's elements (R + sparse J, midpoint rule, user coordinates, `m = d = 1`,
//!   at `q0_i = i + 0.1 sin(2πi/n)`, `z = q0 + h p0`, `p0_i = 0.3 cos(2πi/n)`: the same point up
//!   to the translation by `i d`), single-threaded: its C size, gcc time, ns per evaluation and
//!   the ratio dirac serial R+J / CasADi map R+J.
//!
//! A failing build or run of one row is reported in its row and the example continues. The table
//! is printed, and `scaling.csv` and `scaling.svg` (log-log times against `n`, one panel per
//! system measured) are written under `--out` (default `target/dirac-figures/scaling/`). At the
//! end the targets are printed as met / not met by this run, with the measured values, each
//! block only when its systems were measured: those of the systems sized at compile time (chain
//! and lattice) and those of the system sized at run time (`lattice_n`: the one build ≤ 5 s,
//! peak memory at n = 10^5 ≤ 200 MB, log-log slope of the step time over n = 10^3 … 10^5 within
//! 1 ± 0.1, and with `--casadi` R+J at n = 10^4 ≤ 1.0 × CasADi map).
//!
//! Timings are wall-clock on whatever machine runs this; on a loaded machine they are noisy.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::fs;
use std::io;
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus, Stdio};
use std::time::{Duration, Instant, SystemTime};

use plotters::prelude::*;

#[path = "common/cli.rs"]
mod cli;
use cli::{at_least, Check, Cli};

const ROOT: &str = env!("CARGO_MANIFEST_DIR");
const MEASURE: &str = include_str!("../benches/scaling/measure.rs");
const STATS: &str = include_str!("common/stats.rs");
const CLI: &str = include_str!("common/cli.rs");
const CHAIN: &str = include_str!("../benches/scaling/chain.rs.in");
const LATTICE: &str = include_str!("../benches/scaling/lattice.rs.in");
const LATTICE_N: &str = include_str!("../benches/scaling/lattice_n.rs.in");

/// A scalable system.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum System {
    Chain,
    Lattice,
    /// The element-wise lattice sized at run time: one crate for every `n`.
    LatticeN,
}

impl System {
    fn name(self) -> &'static str {
        match self {
            System::Chain => "chain",
            System::Lattice => "lattice",
            System::LatticeN => "lattice_n",
        }
    }

    /// Newton unknowns per step: `n` angles and the cart, or `n − 1` shapes and the group.
    fn unknowns(self, n: usize) -> usize {
        match self {
            System::Chain => n + 1,
            System::Lattice | System::LatticeN => n,
        }
    }

    /// The scratch crate's `main.rs`.
    fn source(self, n: usize) -> String {
        if self == System::LatticeN {
            return LATTICE_N.to_owned();
        }
        let hand = Path::new(ROOT).join("benches/common/toda_hand.rs");
        let template = match self {
            System::Chain => CHAIN,
            System::Lattice => LATTICE,
            System::LatticeN => unreachable!("no placeholders"),
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
    lattice_n: Vec<usize>,
    out: PathBuf,
    build_timeout: Duration,
}

/// The command line: `--help` lists it; a bad value stops the example with exit code 2.
fn parse_options() -> Options {
    let mut cli = Cli::new(
        "scaling",
        "compile time, code size, step time and memory against the size of the system",
    );
    let casadi = cli.switch(
        "--casadi",
        "also time CasADi's generated C (benches/casadi_scaling, benches/casadi_map)",
    );
    let chain = cli.list(
        "--chain",
        "N1,N2,..",
        "chain sizes",
        &[2, 4, 8, 16, 32, 64],
        at_least(1).or_none(),
    );
    let lattice = cli.list(
        "--lattice",
        "N1,N2,..",
        "lattice sizes (one build each)",
        &[16, 64, 200, 1000],
        at_least(3).or_none(),
    );
    let mut lattice_n = cli.list(
        "--lattice-n",
        "N1,N2,..",
        "lattice sizes at run time (one build), run in ascending order",
        &[100, 1000, 10_000, 100_000],
        Check::new("an integer ≥ 3 (or 0 alone: none)", |&n| n == 0 || n >= 3).or_none(),
    );
    if lattice_n == [0] {
        lattice_n.clear();
    } else if lattice_n.contains(&0) {
        cli.reject("--lattice-n: 0 (none) cannot be listed with sizes");
    }
    // Ascending: the peak memory reported after each size is the process's.
    lattice_n.sort_unstable();
    lattice_n.dedup();
    let out = cli.out_dir(Path::new(ROOT).join("target/dirac-figures/scaling"));
    let build_timeout = cli.value(
        "--build-timeout",
        "SECONDS",
        "wall-time limit of one scratch crate's build",
        600,
        at_least(1),
    );
    cli.finish();
    Options {
        casadi,
        chain,
        lattice,
        lattice_n,
        out,
        build_timeout: Duration::from_secs(build_timeout),
    }
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
    all_fields(output, prefix).into_iter().next()
}

/// `key=value` fields of every line starting with `prefix`, in order.
fn all_fields(output: &str, prefix: &str) -> Vec<HashMap<String, String>> {
    output
        .lines()
        .filter_map(|l| l.strip_prefix(prefix))
        .map(|rest| {
            rest.split_whitespace()
                .filter_map(|kv| kv.split_once('='))
                .map(|(k, v)| (k.to_owned(), v.to_owned()))
                .collect()
        })
        .collect()
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
    /// `lattice_n`: R+J assembled in parallel on rayon's pool (`rj_ns` is the serial one).
    rj_par_ns: Option<f64>,
    step_ns: Option<f64>,
    iterations: Option<f64>,
    mem_mib: Option<f64>,
    hand_step_ns: Option<f64>,
    hand_diff: Option<f64>,
    casadi_instructions: Option<f64>,
    casadi_gcc_s: Option<String>,
    casadi_ns: Option<f64>,
    /// `lattice_n`: the size of CasADi map's generated C.
    casadi_c_bytes: Option<f64>,
    /// Facts about the row (how it was measured), shown in its note.
    notes: Vec<String>,
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

    /// The scratch crate's package (and binary) name; `lattice_n` has one crate for every `n`.
    fn package(system: System, n: usize) -> String {
        match system {
            System::LatticeN => "scaling-lattice-n".into(),
            _ => format!("scaling-{}-{n}", system.name()),
        }
    }

    /// The scratch crate's directory.
    fn dir(&self, system: System, n: usize) -> PathBuf {
        match system {
            System::LatticeN => self.base.join(system.name()),
            _ => self.base.join(format!("{}_{n}", system.name())),
        }
    }

    /// Writes the crate (only files whose content changed, so a rerun rebuilds nothing extra).
    fn write(&self, system: System, n: usize) -> io::Result<PathBuf> {
        let dir = self.dir(system, n);
        fs::create_dir_all(dir.join("src"))?;
        let manifest = format!(
            "# Generated by examples/scaling.rs; not part of the dirac workspace.\n\
             [package]\nname = \"{}\"\nversion = \"0.0.0\"\nedition = \"2021\"\npublish = false\n\n\
             [dependencies]\ndirac = {{ path = \"{ROOT}\" }}\n\n[profile.release]\n\n\
             # As the README recommends for large systems: the attribute runs optimized.\n\
             [profile.release.package.dirac-compiler]\nopt-level = 3\n\n[workspace]\n",
            Self::package(system, n)
        );
        let lock = fs::read_to_string(Path::new(ROOT).join("Cargo.lock")).unwrap_or_default();
        for (path, text) in [
            (dir.join("Cargo.toml"), manifest),
            (dir.join("src/main.rs"), system.source(n)),
            (dir.join("src/measure.rs"), MEASURE.to_owned()),
            (dir.join("src/stats.rs"), STATS.to_owned()),
            (dir.join("src/cli.rs"), CLI.to_owned()),
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

    /// Writes and builds the crate, then times a rebuild of the user crate alone (`src/main.rs`
    /// touched): its wall time in s and rustc's peak memory in MB.
    fn build_timed(&self, system: System, n: usize) -> Result<(PathBuf, f64, Option<f64>), String> {
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
        Ok((dir, secs, mb))
    }

    /// Runs the crate's binary with `args`, its output logged to `run.log`; returns the output.
    fn run(&self, system: System, n: usize, dir: &Path, args: &[String]) -> Result<String, String> {
        let binary = self.target.join("release").join(Self::package(system, n));
        let log = dir.join("run.log");
        let (finished, _) = run_logged(Command::new(&binary).args(args), &log, self.timeout)
            .map_err(|e| format!("run failed: cannot start {}: {e}", binary.display()))?;
        let text = fs::read_to_string(&log).unwrap_or_default();
        match finished {
            Finished::TimedOut => Err(format!("run timeout ({} s)", self.timeout.as_secs())),
            Finished::Exited(s) if !s.success() => {
                Err(format!("run failed: {}", first_error(&text)))
            }
            Finished::Exited(_) => Ok(text),
        }
    }

    /// Builds, times a rebuild of the user crate alone, runs the binary; fills `row`.
    fn measure(&self, system: System, n: usize, row: &mut Row) -> Result<(), String> {
        let (dir, secs, mb) = self.build_timed(system, n)?;
        row.compile_s = Some(secs);
        row.compile_mb = mb;
        let text = self.run(system, n, &dir, &[])?;
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

/// The `lattice_n` rows: one crate built once (the touched rebuild timed), run once with every
/// size in `sizes`; one row per size, each with the same compile time and memory.
fn measure_lattice_n(scratch: &Scratch, sizes: &[usize]) -> Vec<Row> {
    let system = System::LatticeN;
    let mut rows: Vec<Row> = sizes
        .iter()
        .map(|&n| Row {
            system: system.name(),
            n,
            unknowns: system.unknowns(n),
            ..Row::default()
        })
        .collect();
    let fail = |rows: &mut Vec<Row>, e: String| {
        eprintln!("  {e}");
        for r in rows.iter_mut().filter(|r| r.step_ns.is_none()) {
            r.failure = Some(e.clone());
        }
    };
    eprintln!("lattice_n: build, rebuild (timed) once for every n");
    let (dir, secs, mb) = match scratch.build_timed(system, 0) {
        Ok(b) => b,
        Err(e) => {
            fail(&mut rows, e);
            return rows;
        }
    };
    for (k, r) in rows.iter_mut().enumerate() {
        r.compile_s = Some(secs);
        r.compile_mb = mb;
        r.notes.push(if k == 0 {
            "one build for every n".into()
        } else {
            format!("same build as n = {}", sizes[0])
        });
    }
    let list = sizes
        .iter()
        .map(usize::to_string)
        .collect::<Vec<_>>()
        .join(",");
    eprintln!("lattice_n: run n = {list}");
    // A failed run still reports the sizes it finished.
    let text = scratch
        .run(system, 0, &dir, &["--n".into(), list])
        .unwrap_or_else(|e| {
            fail(&mut rows, e);
            fs::read_to_string(dir.join("run.log")).unwrap_or_default()
        });
    for f in all_fields(&text, "scaling-element:") {
        let Some(r) = num(&f, "n").and_then(|n| rows.iter_mut().find(|r| r.n as f64 == n)) else {
            continue;
        };
        r.nnz = num(&f, "nnz");
        r.rj_ns = num(&f, "rj_ns");
        r.rj_par_ns = num(&f, "rj_par_ns");
        r.step_ns = num(&f, "step_ns");
        r.iterations = num(&f, "iterations");
        r.mem_mib = num(&f, "peak_mib");
        r.notes.push(format!(
            "R+J parallel {} ns ({} threads); step parallel: {}",
            fmt(r.rj_par_ns, 0),
            f.get("threads").map_or("?", String::as_str),
            f.get("parallel").map_or("?", String::as_str)
        ));
        r.failure = None;
    }
    for r in rows
        .iter_mut()
        .filter(|r| r.step_ns.is_none() && r.failure.is_none())
    {
        r.failure = Some("run failed: no `scaling-element:` line for this n".into());
    }
    rows
}

/// `bash benches/casadi_map/run.sh --n N` (CasADi `map` of the lattice's elements, R + sparse J
/// of the same equations in user coordinates); fills `row`.
fn casadi_map(n: usize, row: &mut Row, scratch: &Scratch) -> Result<(), String> {
    let log = scratch.base.join(format!("casadi_map_{n}.log"));
    let mut cmd = Command::new("bash");
    cmd.arg(Path::new(ROOT).join("benches/casadi_map/run.sh"))
        .args(["--n", &n.to_string(), "--gcc-timeout", "300"])
        .current_dir(ROOT);
    let (finished, _) = run_logged(&mut cmd, &log, Duration::from_secs(1800))
        .map_err(|e| format!("cannot run bash: {e}"))?;
    let text = fs::read_to_string(&log).unwrap_or_default();
    match finished {
        Finished::TimedOut => return Err("casadi map timeout".into()),
        Finished::Exited(s) if !s.success() => {
            return Err(format!("casadi map failed: {}", first_error(&text)))
        }
        Finished::Exited(_) => {}
    }
    let f = fields(&text, "casadi-map:").ok_or("casadi: no `casadi-map:` line")?;
    row.casadi_c_bytes = num(&f, "c_bytes");
    row.casadi_gcc_s = f.get("gcc_s").cloned();
    row.casadi_ns = num(&f, "ns");
    Ok(())
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
    note.extend(r.notes.iter().cloned());
    if let Some(d) = r.hand_diff {
        note.push(format!("hand vs dirac next state {d:.1e}"));
    }
    if let Some(g) = &r.casadi_gcc_s {
        if let Some(bytes) = r.casadi_c_bytes {
            note.push(format!("CasADi map {bytes:.0} C bytes, gcc {g} s"));
        } else {
            let i = r
                .casadi_instructions
                .map_or("-".into(), |v| format!("{v:.0}"));
            note.push(format!("CasADi {i} instr, gcc {g} s"));
        }
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
         hand_rel_diff,memory_mib,dirac_rj_parallel_ns,casadi_c_bytes,note\n",
    );
    let c = |v: Option<f64>| {
        v.filter(|x| x.is_finite())
            .map_or(String::new(), |x| x.to_string())
    };
    for r in rows {
        let note = [r.failure.clone(), r.casadi_failure.clone()]
            .into_iter()
            .flatten()
            .chain(r.notes.iter().cloned())
            .collect::<Vec<_>>()
            .join("; ")
            .replace('"', "'");
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},\"{note}\"",
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
            c(r.rj_par_ns),
            c(r.casadi_c_bytes),
        );
    }
    fs::write(path, s)
}

type Series = (&'static str, RGBColor, fn(&Row) -> Option<f64>);

/// Log-log times (ns) against `n`, one panel per system measured.
fn write_svg(rows: &[Row], path: &Path) -> Result<(), Box<dyn std::error::Error>> {
    let series: [Series; 4] = [
        ("dirac R+J", RGBColor(31, 119, 180), |r| r.rj_ns),
        ("CasADi R+J", RGBColor(255, 127, 14), |r| r.casadi_ns),
        ("dirac step", RGBColor(44, 160, 44), |r| r.step_ns),
        ("hand step", RGBColor(214, 39, 40), |r| r.hand_step_ns),
    ];
    let element: [Series; 4] = [
        ("dirac R+J serial", RGBColor(31, 119, 180), |r| r.rj_ns),
        ("dirac R+J parallel", RGBColor(148, 103, 189), |r| {
            r.rj_par_ns
        }),
        ("CasADi map R+J", RGBColor(255, 127, 14), |r| r.casadi_ns),
        ("dirac step (Auto)", RGBColor(44, 160, 44), |r| r.step_ns),
    ];
    let mut systems: Vec<System> = [System::Chain, System::Lattice, System::LatticeN]
        .into_iter()
        .filter(|s| rows.iter().any(|r| r.system == s.name()))
        .collect();
    if systems.is_empty() {
        systems.push(System::Chain);
    }
    let width = 550 * systems.len() as u32;
    let root = SVGBackend::new(path, (width, 480)).into_drawing_area();
    root.fill(&WHITE)?;
    let panels = root.split_evenly((1, systems.len()));
    for (area, &system) in panels.iter().zip(&systems) {
        let (series, caption) = match system {
            System::LatticeN => (&element, "lattice_n (one build, run-time n)".to_string()),
            _ => (&series, system.name().to_string()),
        };
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
                format!("{caption}: time against n (log-log)"),
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
            .x_label_formatter(&|v| format!("{v:.0}"))
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

fn verdict(v: Option<bool>) -> &'static str {
    match v {
        Some(true) => "met",
        Some(false) => "NOT met",
        None => "not measured",
    }
}

/// The least-squares slope of `ln y` against `ln x`; `None` below two points.
fn log_log_slope(points: &[(f64, f64)]) -> Option<f64> {
    if points.len() < 2 {
        return None;
    }
    let pts: Vec<(f64, f64)> = points.iter().map(|&(x, y)| (x.ln(), y.ln())).collect();
    let k = pts.len() as f64;
    let (mx, my) = pts
        .iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x / k, b + y / k));
    let (num, den) = pts.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
        (a + (x - mx) * (y - my), b + (x - mx) * (x - mx))
    });
    Some(num / den)
}

/// The targets of the systems sized at compile time (chain, lattice) and at run time
/// (lattice_n), judged on this run's rows; each block only when its systems were measured.
fn print_targets(rows: &[Row], casadi: bool) {
    let find = |s: System, n: usize| rows.iter().find(|r| r.system == s.name() && r.n == n);
    let measured = |s: System| rows.iter().any(|r| r.system == s.name());
    if measured(System::Chain) || measured(System::Lattice) {
        print_compile_time_targets(rows, casadi);
    }
    if !measured(System::LatticeN) {
        return;
    }
    let element: Vec<&Row> = rows
        .iter()
        .filter(|r| r.system == System::LatticeN.name())
        .collect();
    let build = element.iter().find_map(|r| r.compile_s);
    let build_mb = element.iter().find_map(|r| r.compile_mb);
    let big = find(System::LatticeN, 100_000);
    let mib = big.and_then(|r| r.mem_mib);
    let mb = mib.map(|m| m * 1_048_576.0 / 1e6);
    // The slope over the sizes measured in 10^3 ..= 10^5, both ends included.
    let span: Vec<(f64, f64)> = element
        .iter()
        .filter(|r| (1000..=100_000).contains(&r.n))
        .filter_map(|r| Some((r.n as f64, r.step_ns?)))
        .collect();
    let ends = [1000.0, 100_000.0].map(|n| span.iter().any(|p| p.0 == n));
    let slope = log_log_slope(&span).filter(|_| ends == [true, true]);
    let sizes = span
        .iter()
        .map(|p| format!("{:.0}", p.0))
        .collect::<Vec<_>>()
        .join(", ");
    let mid = find(System::LatticeN, 10_000);
    let targets: [(&str, Option<bool>, String); 4] = [
        (
            "lattice_n one build (touched rebuild, release) ≤ 5 s",
            build.map(|s| s <= 5.0),
            format!("{} s, rustc {} MB", fmt(build, 2), fmt(build_mb, 0)),
        ),
        (
            "lattice_n n = 10^5 peak memory ≤ 200 MB",
            mb.map(|m| m <= 200.0),
            format!("{} MB = {} MiB VmHWM", fmt(mb, 1), fmt(mib, 1)),
        ),
        (
            "lattice_n log-log slope of step time over n = 10^3 … 10^5 in 1 ± 0.1",
            slope.map(|q| (q - 1.0).abs() <= 0.1),
            format!("{} over n = {sizes}", fmt(slope, 3)),
        ),
        (
            "lattice_n n = 10^4 R+J ≤ 1.0 × CasADi map",
            mid.filter(|_| casadi)
                .and_then(Row::ratio)
                .map(|q| q <= 1.0),
            format!(
                "{} × = {} / {} ns, dirac serial, its R+J also computing D2 L_d",
                fmt(mid.and_then(Row::ratio), 2),
                fmt(mid.and_then(|r| r.rj_ns), 0),
                fmt(mid.and_then(|r| r.casadi_ns), 0)
            ),
        ),
    ];
    println!("\ntargets of the system sized at run time (this run):");
    for (what, ok, value) in targets {
        println!("  {:<12} {what}  ({value})", verdict(ok));
    }
}

/// The targets of the systems sized at compile time, judged on this run's rows.
fn print_compile_time_targets(rows: &[Row], casadi: bool) {
    let find = |s: System, n: usize| rows.iter().find(|r| r.system == s.name() && r.n == n);
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
    println!("\ntargets of the systems sized at compile time (this run):");
    for (what, ok, value) in targets {
        println!("  {:<12} {what}  ({value})", verdict(ok));
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let o = parse_options();
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
    if !o.lattice_n.is_empty() {
        for mut row in measure_lattice_n(&scratch, &o.lattice_n) {
            if o.casadi {
                eprintln!("lattice_n n = {}: CasADi map", row.n);
                if let Err(e) = casadi_map(row.n, &mut row, &scratch) {
                    eprintln!("  {e}");
                    row.casadi_failure = Some(e);
                }
            }
            eprintln!("  {}", cells(&row, o.casadi).join(" | "));
            rows.push(row);
        }
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
