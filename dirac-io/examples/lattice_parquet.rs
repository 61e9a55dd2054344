//! What writing every state to Parquet costs: the 200-particle Toda lattice (the root crate's
//! `examples/lattice.rs`) run with a no-op observer and with a [`ParquetObserver`] writing every
//! state (400 state columns), in one process, alternately, best of three; then the peak memory
//! after a run 4× longer, to show that the writer's memory does not grow with the run.
//!
//! ```sh
//! cargo run --release --manifest-path dirac-io/Cargo.toml --target-dir target \
//!     --example lattice_parquet -- [--steps 5000] [--out target/lattice.parquet]
//! ```
//!
//! Target (issue 22): Parquet ≤ 1.3× the no-op run.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use dirac::prelude::*;
use dirac_io::{progress, Describe, Options, ParquetObserver};

#[path = "../../examples/common/toda.rs"]
mod toda;

/// Peak resident memory of this process, in MiB (Linux; `None` elsewhere).
fn peak_memory_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut steps = 5000;
    let mut out = PathBuf::from("target/lattice.parquet");
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--steps" => steps = args.next().ok_or("--steps N")?.parse()?,
            "--out" => out = args.next().ok_or("--out FILE")?.into(),
            _ => {
                return Err(format!("unknown argument {a}; usage: [--steps N] [--out FILE]").into())
            }
        }
    }
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

    let noop = |label: &str| -> Result<Duration, Box<dyn std::error::Error>> {
        let t = Instant::now();
        integ.run(
            start,
            steps,
            progress::follow(steps, label, |_, _, _: Option<&ReducedStep<1>>| {}),
        )?;
        Ok(t.elapsed())
    };
    let parquet = |n: usize, label: &str| -> Result<Duration, Box<dyn std::error::Error>> {
        let t = Instant::now();
        let mut writer = ParquetObserver::create(&out, integ.describe(), Options::new())?;
        let result = integ.run(start, n, progress::follow(n, label, writer.observer()));
        writer.finish_with(&result)?;
        result?;
        Ok(t.elapsed())
    };
    let (mut best_noop, mut best_parquet) = (Duration::MAX, Duration::MAX);
    for round in 1..=3 {
        best_noop = best_noop.min(noop(&format!("no-op {round}/3"))?);
        best_parquet = best_parquet.min(parquet(steps, &format!("parquet {round}/3"))?);
    }
    let bytes = std::fs::metadata(&out)?.len();
    let peak = peak_memory_mib();
    println!(
        "  no-op observer:   {:8.3} s ({:.1} µs/step)",
        best_noop.as_secs_f64(),
        best_noop.as_secs_f64() * 1e6 / steps as f64
    );
    println!(
        "  Parquet, every state: {:8.3} s ({:.1} µs/step), {:.1} MiB written ({:.0} MB/s)",
        best_parquet.as_secs_f64(),
        best_parquet.as_secs_f64() * 1e6 / steps as f64,
        bytes as f64 / (1 << 20) as f64,
        bytes as f64 / 1e6 / best_parquet.as_secs_f64()
    );
    println!(
        "  ratio Parquet / no-op: {:.3} (target ≤ 1.3)",
        best_parquet.as_secs_f64() / best_noop.as_secs_f64()
    );
    parquet(4 * steps, "parquet, 4× longer")?;
    let longer = std::fs::metadata(&out)?.len();
    if let (Some(a), Some(b)) = (peak, peak_memory_mib()) {
        println!(
            "  peak memory: {a:.1} MiB after {steps} steps, {b:.1} MiB after {} steps ({:.1} MiB written)",
            4 * steps,
            longer as f64 / (1 << 20) as f64
        );
    }
    Ok(())
}
