//! The timing the cost examples share: nanoseconds per step of a streamed run, through the one
//! run API (so any integrator, reduced or not, composed or not). Included with `#[path]`.

use std::hint::black_box;
use std::time::Instant;

use dirac::prelude::*;

/// Nanoseconds per step of `steps` steps of `integ` from `start`, streamed.
pub fn per_step<I: Drive>(integ: &I, start: I::State, steps: usize) -> f64 {
    let began = Instant::now();
    let summary = integ
        .run(start)
        .steps(steps)
        .stream()
        .expect("the run succeeds");
    black_box(&summary.last);
    began.elapsed().as_secs_f64() * 1e9 / steps as f64
}
