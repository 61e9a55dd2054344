//! What the stepper benchmarks measure, shared by `benches/steppers.rs` (criterion),
//! `examples/bench_table.rs` (one process, one table) and `tests/bench_oracles.rs` (the baselines
//! agree with the generated code, so the timings compare equal work).
//!
//! * [`workload`]: states on the paper's trajectories (§7.1, §7.2) and the Newton guesses the
//!   integrator itself would start from;
//! * [`ad`]: the same discrete Lagrangians written a second time as generic functions over
//!   `num_dual::DualNum` and differentiated at run time, as a user without the attribute would;
//! * [`hand`]: the charged particle's reduced equations (4.6) derived and coded by hand.
//!
//! Each user compiles this tree on its own and uses part of it, hence `allow(dead_code)`.
#![allow(dead_code)]

pub mod ad;
pub mod hand;
pub mod workload;
