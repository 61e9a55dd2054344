//! The cost of the driver: nanoseconds per step of a streamed run with no options set (the
//! system's own step, no controls, no stop condition, no observer), on the paper's double
//! spherical pendulum (the dense backend) and the 200-particle Toda lattice (the sparse one).
//! Each figure is the median over `--repeats` runs, with its range, printed one per line so
//! that two builds can be compared run by run (see BENCHMARKS.md).
//!
//! ```text
//! cargo run --release --example run_cost -- [--repeats 7] [--system both|dsp|lattice]
//! ```

use dirac::paper::DoubleSphericalPendulum;
use dirac::prelude::*;

#[path = "common/cli.rs"]
mod cli;
#[path = "common/stats.rs"]
mod stats;
#[path = "common/timing.rs"]
mod timing;
#[path = "common/toda.rs"]
mod toda;

use cli::{at_least, Cli};
use stats::{median, range};
use timing::per_step;

fn main() {
    let mut cli = Cli::new(
        "run_cost",
        "nanoseconds per step of a configured run with no options set",
    );
    let repeats: usize = cli.value("--repeats", "R", "repeats of each run", 7, at_least(1));
    let (dsp_on, lattice_on) = cli.choice(
        "--system",
        "which systems to time",
        "both",
        &[
            ("both", (true, true)),
            ("dsp", (true, false)),
            ("lattice", (false, true)),
        ],
    );
    cli.finish();
    let dsp = ReducedIntegrator::plus(DoubleSphericalPendulum::paper(), NewtonOptions::default());
    let dsp_start = DoubleSphericalPendulum::paper_initial_state();
    let lattice = toda::Toda {
        m: 1.0,
        d: 1.0,
        h: 0.05,
    };
    let lattice_start = toda::initial(&lattice, 0.1, 0.3, 0.05);
    let lattice = ReducedIntegrator::plus(lattice, NewtonOptions::default());
    let (mut a, mut b) = (Vec::new(), Vec::new());
    for _ in 0..repeats {
        if dsp_on {
            a.push(per_step(&dsp, dsp_start, 20_000));
        }
        if lattice_on {
            b.push(per_step(&lattice, lattice_start, 2_000));
        }
    }
    for (name, v) in [
        ("double spherical pendulum", a),
        ("Toda lattice, n = 200", b),
    ] {
        if v.is_empty() {
            continue;
        }
        let (lo, hi) = range(&v);
        println!(
            "{name}: median {:.1} ns/step (range {lo:.1} .. {hi:.1}, {repeats} runs)",
            median(v.clone()),
        );
    }
}
