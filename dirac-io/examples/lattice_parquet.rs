//! What writing every state to Parquet costs: the 200-particle Toda lattice (the root crate's
//! `examples/lattice.rs`) run with a no-op observer and with a [`ParquetObserver`] writing every
//! state (400 state columns; the default output: parts of 64 MiB published by rename, with
//! checksums), in one process, alternately, best of five; before that, the peak
//! memory of runs 1× and 4× as long written in parts (`Options::rows_per_file`), which does not
//! grow with the run, and of the 4× run written to one file, whose footer does.
//!
//! ```sh
//! cargo run --release --manifest-path dirac-io/Cargo.toml --target-dir target \
//!     --example lattice_parquet -- [--steps 5000] [--out target/lattice.parquet]
//! ```
//!
//! Target: Parquet ≤ 1.3× the no-op run.

use std::path::PathBuf;
use std::time::Instant;

use dirac::prelude::*;
use dirac_io::{progress, Describe, Options, ParquetObserver};

#[path = "../../examples/common/cli.rs"]
mod cli;
#[path = "../../examples/common/stats.rs"]
mod stats;
use stats::peak_memory_mib;
#[path = "../../examples/common/toda.rs"]
mod toda;

/// CPU time of this process so far (all threads, those ended included), in seconds (Linux;
/// `None` elsewhere): what a busy machine, or an ensemble on every core, pays.
fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the command name (which may hold spaces) in parentheses: utime and stime
    // are the 12th and 13th, in clock ticks of 1/100 s.
    let after = &stat[stat.rfind(')')? + 2..];
    let fields: Vec<&str> = after.split_whitespace().collect();
    let ticks: f64 = fields.get(11)?.parse::<f64>().ok()? + fields.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

/// Wall and CPU time of `f`.
fn timed(
    f: impl FnOnce() -> Result<(), Box<dyn std::error::Error>>,
) -> Result<(f64, f64), Box<dyn std::error::Error>> {
    let (t, c) = (Instant::now(), cpu_seconds().unwrap_or(0.0));
    f()?;
    Ok((t.elapsed().as_secs_f64(), cpu_seconds().unwrap_or(0.0) - c))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut cli = cli::Cli::new(
        "lattice_parquet",
        "every state of the 200-particle lattice to Parquet against a no-op observer",
    );
    let steps = cli.value(
        "--steps",
        "N",
        "steps of the timed runs",
        5000,
        cli::at_least(1),
    );
    let out = cli.value(
        "--out",
        "FILE",
        "the Parquet file (its parts: FILE with the extension .parts)",
        PathBuf::from("target/lattice.parquet"),
        cli::any(),
    );
    cli.finish();
    if let Some(dir) = out.parent() {
        std::fs::create_dir_all(dir)?;
    }
    let sys = toda::Toda {
        m: 1.0,
        d: 1.0,
        h: 0.05,
    };
    let start = toda::initial(&sys, 0.1, 0.3, 0.05);
    let integ = ReducedIntegrator::plus(sys, NewtonOptions::default());
    println!(
        "Toda lattice, n = {}, {steps} steps, {} state columns",
        toda::N,
        2 * toda::N
    );

    // Memory first (the peak is a high-water mark): split into parts of `steps` rows, memory does
    // not depend on the run's length; one file keeps its growing footer in memory until closed
    // (one entry per column and row group).
    let peak_memory = |n: usize, split: bool| -> Result<Option<f64>, Box<dyn std::error::Error>> {
        let options = if split {
            Options::new().rows_per_file(steps as u64)
        } else {
            Options::new().single_file()
        };
        let target = if split {
            out.with_extension("parts")
        } else {
            out.clone()
        };
        let _ = std::fs::remove_dir_all(&target);
        let _ = std::fs::remove_file(&target);
        let mut writer = ParquetObserver::create(&target, integ.describe(), options)?;
        let label = format!("{n} steps{}", if split { ", in parts" } else { "" });
        let result = integ
            .run(start)
            .steps(n)
            .observe(progress::follow(n, &label, writer.observer()))
            .stream();
        writer.finish_with(&result)?;
        result?;
        Ok(peak_memory_mib())
    };
    let parts = [peak_memory(steps, true)?, peak_memory(4 * steps, true)?];
    let single = peak_memory(4 * steps, false)?;
    if let ([Some(a), Some(b)], Some(c)) = (parts, single) {
        println!(
            "  peak memory, parts of {steps} rows: {a:.1} MiB after {steps} steps, {b:.1} MiB after {} steps",
            4 * steps
        );
        println!(
            "  peak memory, one file of {} steps: {c:.1} MiB (the footer grows with the run)",
            4 * steps
        );
    }
    let noop = |label: &str| {
        timed(|| {
            integ
                .run(start)
                .steps(steps)
                .observe(progress::follow(
                    steps,
                    label,
                    |_, _, _, _: Option<&ReducedStep<1>>| {},
                ))
                .stream()?;
            Ok(())
        })
    };
    let parquet = |label: &str, background: bool| {
        timed(|| {
            let options = Options::new().background(background);
            let _ = std::fs::remove_file(&out);
            let mut writer = ParquetObserver::create(&out, integ.describe(), options)?;
            let result = integ
                .run(start)
                .steps(steps)
                .observe(progress::follow(steps, label, writer.observer()))
                .stream();
            writer.finish_with(&result)?;
            result?;
            Ok(())
        })
    };
    // Alternating, best of five: the machine may be shared, and the best run is the one least
    // disturbed.
    let (mut best_noop, mut best_parquet) = ((f64::MAX, f64::MAX), (f64::MAX, f64::MAX));
    let mut best_inline = (f64::MAX, f64::MAX);
    let best = |b: &mut (f64, f64), r: (f64, f64)| *b = (b.0.min(r.0), b.1.min(r.1));
    for round in 1..=5 {
        best(&mut best_noop, noop(&format!("no-op {round}/5"))?);
        best(
            &mut best_parquet,
            parquet(&format!("parquet {round}/5"), true)?,
        );
        best(
            &mut best_inline,
            parquet(&format!("parquet, one thread {round}/5"), false)?,
        );
    }
    let mut bytes = 0;
    for file in dirac_io::read::files(&out)? {
        bytes += std::fs::metadata(file)?.len();
    }
    let per_step = |s: f64| s * 1e6 / steps as f64;
    println!(
        "  no-op observer:       {:7.3} s wall ({:.1} µs/step), {:.2} s CPU",
        best_noop.0,
        per_step(best_noop.0),
        best_noop.1
    );
    println!(
        "  Parquet, every state: {:7.3} s wall ({:.1} µs/step), {:.2} s CPU, {:.1} MiB written",
        best_parquet.0,
        per_step(best_parquet.0),
        best_parquet.1,
        bytes as f64 / (1 << 20) as f64
    );
    println!(
        "  Parquet, written on the run's thread: {:7.3} s wall, {:.2} s CPU",
        best_inline.0, best_inline.1
    );
    println!(
        "  ratio Parquet / no-op: {:.3} wall (target ≤ 1.3), {:.3} CPU; on the run's thread only: {:.3} wall",
        best_parquet.0 / best_noop.0,
        best_parquet.1 / best_noop.1,
        best_inline.0 / best_noop.0
    );
    Ok(())
}
