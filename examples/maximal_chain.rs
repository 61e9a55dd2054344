//! The planar chain of the scaling benchmark (`n` links hanging from a cart) in maximal
//! coordinates: the cart `c` and every link's end point `(x_i, y_i)`, one length
//! constraint per link, integrated by the unreduced constrained integrator. Each step solves two
//! saddle-point systems of `3n + 1` unknowns on the sparse backend (banded: each link couples
//! only to its neighbours), so the time per step grows about linearly with `n` where the chain
//! in relative angles (a dense `n × n` coupling) grows as `n³`.
//!
//! The coordinates are the plain ones: declaring the cart's translation (`coordinates(c, x[n],
//! y[n]), translate(c, x)`, as `tests/constraints.rs` does for the reduced equations) makes the
//! group coordinate's row of the step Jacobian dense (every `x_i = g + r_i`), and the LU's
//! partial pivoting picks that row early and fills the band: measured slope 1.87 instead of
//! 1.13 (BENCHMARKS.md).
//!
//! The same chain written once with its size chosen at run time (`coordinates(c, x[n], y[n])`,
//! `constraints = |q| { let mut phi = vec![0.0; n]; .. }`, integrated by
//! `ElementConstrainedIntegrator`) follows the unrolled chain at every size both reach, and runs
//! where unrolled code cannot be built (n = 10⁴): the example prints both, the largest
//! difference between their trajectories and the log–log slope of the run-time-sized step.
//!
//! Run: `cargo run --release --example maximal_chain -- --n 100,1000,10000`.

use std::time::Instant;

use dirac::prelude::*;
use dirac::runtime::element::{ElementConstrainedIntegrator, ElementIntegrator};

#[path = "common/cli.rs"]
mod cli;

macro_rules! maximal_chain {
    ($name:ident, $ty:ident, $n:literal) => {
        /// The chain of `$n` links in maximal coordinates.
        #[reduced_lagrangian(shape(c, x[$n], y[$n]), group(), rule = midpoint,
                            constraints = |q| {
                                let mut phi = [0.0; $n];
                                phi[0] = (q.x[0] - q.c) * (q.x[0] - q.c) + q.y[0] * q.y[0] - l * l;
                                for i in 1..$n {
                                    let (dx, dy) = (q.x[i] - q.x[i - 1], q.y[i] - q.y[i - 1]);
                                    phi[i] = dx * dx + dy * dy - l * l;
                                }
                                phi
                            })]
        fn $name(q: Config, v: Velocity, mc: f64, m: f64, l: f64, gr: f64) -> f64 {
            let mut t = 0.5 * mc * v.c * v.c;
            let mut u = 0.0;
            for i in 0..$n {
                t += 0.5 * m * (v.x[i] * v.x[i] + v.y[i] * v.y[i]);
                u += m * gr * q.y[i];
            }
            t - u
        }

        impl $ty {
            /// Time per step (µs) over `steps` steps from the benchmark's state, at rest, the
            /// largest constraint residual, the Newton corrections per step and the last
            /// configuration.
            fn measure(steps: usize, options: NewtonOptions) -> (f64, f64, f64, DVector<f64>) {
                let sys = $ty {
                    h: 0.01,
                    mc: 1.0,
                    m: 1.0,
                    l: 1.0,
                    gr: 9.81,
                };
                // θ_i = 0.3 sin(i + 1), as in benches/scaling/chain.rs.in.
                let mut q = SVector::<f64, { 2 * $n + 1 }>::zeros();
                let (mut x, mut y) = (0.0, 0.0);
                for i in 0..$n {
                    let th = 0.3 * ((i + 1) as f64).sin();
                    x += th.sin();
                    y -= th.cos();
                    q[1 + i] = x;
                    q[1 + $n + i] = y;
                }
                let user = UnreducedState {
                    q,
                    p: SVector::zeros(),
                };
                let c0 = <$ty>::to_adapted_state(&user);
                let integ = ConstrainedIntegrator::new(sys, options);
                let start = Instant::now();
                let traj = integ.run(c0).steps(steps).collect().expect("the chain integrates");
                let us = start.elapsed().as_secs_f64() * 1e6 / steps as f64;
                let last = <$ty>::from_adapted_state(traj.last()).q;
                (
                    us,
                    traj.max_constraint_residual(),
                    traj.mean_iterations(),
                    DVector::from_column_slice(last.as_slice()),
                )
            }
        }
    };
}

maximal_chain!(chain16, Chain16, 16);
maximal_chain!(chain32, Chain32, 32);
maximal_chain!(chain64, Chain64, 64);
maximal_chain!(chain128, Chain128, 128);

/// The same chain with its number of links chosen at run time.
#[path = "common/link_chain.rs"]
mod link_chain;
use link_chain::{hanging, LinkChain};

/// The run-time-sized chain of `n` links over `steps` steps from the benchmark's state: µs per
/// step, the largest constraint residual, Newton corrections per step, the last configuration.
fn measure_n(
    n: usize,
    steps: usize,
    h: f64,
    options: NewtonOptions,
) -> (f64, f64, f64, DVector<f64>) {
    let sys = LinkChain {
        h,
        mc: 1.0,
        m: 1.0,
        l: 1.0,
        gr: 9.81,
        n,
    };
    let integ = ElementConstrainedIntegrator::new(sys, options);
    let start = Instant::now();
    // A falling chain is chaotic: two roundings of it part within a few hundred steps, and a
    // run may reach a configuration where `h` is too coarse for Newton's iteration (the tip's
    // whip). Such a run is reported, and timed over the steps it completed.
    let traj = match integ.run(hanging(n, 1.0)).steps(steps).collect() {
        Ok(traj) => traj,
        Err(e) => {
            println!(
                "    (n = {n}: stopped after {} of {steps} steps: {})",
                e.trajectory.step_count(),
                e.source
            );
            e.trajectory
        }
    };
    let done = traj.step_count().max(1);
    let us = start.elapsed().as_secs_f64() * 1e6 / done as f64;
    let iterations = traj.stats.iter().map(|s| s.iterations as f64).sum::<f64>() / done as f64;
    (
        us,
        traj.max_constraint_residual(),
        iterations,
        traj.last().q.clone(),
    )
}

/// The same chain with stiff springs `k/2 (|Δ| − l)²` in place of the length constraints: the
/// unconstrained step of the same coordinates, for the cost of the constraints.
#[reduced_lagrangian(coordinates(c, x[n], y[n]), rule = midpoint)]
fn spring_chain(q: Config, v: Velocity, mc: f64, m: f64, l: f64, gr: f64, k: f64, n: usize) -> f64 {
    let mut t = 0.5 * mc * v.c * v.c;
    for i in 0..n {
        t += 0.5 * m * (v.x[i] * v.x[i] + v.y[i] * v.y[i]) - m * gr * q.y[i];
    }
    let s0 = ((q.x[0] - q.c) * (q.x[0] - q.c) + q.y[0] * q.y[0]).sqrt() - l;
    t -= 0.5 * k * s0 * s0;
    for i in 1..n {
        let (dx, dy) = (q.x[i] - q.x[i - 1], q.y[i] - q.y[i - 1]);
        let s = (dx * dx + dy * dy).sqrt() - l;
        t -= 0.5 * k * s * s;
    }
    t
}

/// Time per step (µs) of the constrained chain over the spring chain (`k = 10⁴`, `h ω = 1`),
/// both sized at run time, `n` links, from the same state, 200 steps each, interleaved
/// `repeats` times: the median ratio and its range.
fn constrained_over_springs(n: usize, repeats: usize) -> (f64, f64, f64) {
    let start = hanging(n, 1.0);
    let springs = ElementIntegrator::new(
        SpringChain {
            h: 0.01,
            mc: 1.0,
            m: 1.0,
            l: 1.0,
            gr: 9.81,
            k: 1e4,
            n,
        },
        NewtonOptions::default(),
    );
    let steps = 200;
    let mut ratios = Vec::new();
    for _ in 0..repeats {
        let (constrained, _, _, _) = measure_n(n, steps, 0.01, NewtonOptions::default());
        let t0 = Instant::now();
        springs
            .run(start.clone())
            .steps(steps)
            .observe(|_, _, _, _| ())
            .stream()
            .expect("the spring chain integrates");
        let spring_us = t0.elapsed().as_secs_f64() * 1e6 / steps as f64;
        ratios.push(constrained / spring_us);
    }
    ratios.sort_by(f64::total_cmp);
    (
        ratios[ratios.len() / 2],
        ratios[0],
        ratios[ratios.len() - 1],
    )
}

fn main() {
    let mut cli = cli::Cli::new(
        "maximal_chain",
        "the scaling benchmark's chain in maximal coordinates, one constraint per link",
    );
    let sizes = cli.list(
        "--n",
        "N1,N2,..",
        "link counts of the run-time-sized chain beyond the unrolled ones",
        &[100, 1000, 10000],
        cli::at_least(2),
    );
    let long = cli.value(
        "--steps-large",
        "S",
        "steps of each run-time-sized chain in --n",
        200,
        cli::at_least(10),
    );
    cli.finish();
    let steps = 2000;
    println!("Planar chain in maximal coordinates (cart + n end points, n length constraints), h = 0.01, {steps} steps:");
    println!(
        "{:>6} {:>10} {:>14} {:>18} {:>14}",
        "n", "unknowns", "µs per step", "max |phi| (l = 1)", "Newton/step"
    );
    let defaults = NewtonOptions::default();
    let rows = [
        (16, Chain16::measure(steps, defaults)),
        (32, Chain32::measure(steps, defaults)),
        (64, Chain64::measure(steps, defaults)),
        (128, Chain128::measure(steps, defaults)),
    ];
    // The two codes' trajectories, compared over 100 steps at tight tolerances (the falling
    // chain is chaotic: over 2000 steps any two roundings of it part).
    let tight = NewtonOptions {
        abs_tol: 1e-13,
        rel_tol: 1e-13,
        ..defaults
    };
    let unrolled_tight = [
        Chain16::measure(100, tight).3,
        Chain32::measure(100, tight).3,
        Chain64::measure(100, tight).3,
        Chain128::measure(100, tight).3,
    ];
    for (n, (us, phi, it, _)) in &rows {
        println!(
            "{n:>6} {:>10} {us:>14.1} {phi:>18.1e} {it:>14.2}",
            3 * n + 1
        );
    }
    let slope = ((rows[3].1).0 / (rows[0].1).0).ln() / (128.0_f64 / 16.0).ln();
    println!("log-log slope of the step time, n = 16 … 128: {slope:.2} (linear: 1)");
    println!();
    println!("The same chain sized at run time (one build), against the unrolled chain (the last column: after 100 steps at tolerance 1e-13):");
    println!(
        "{:>6} {:>14} {:>12} {:>18} {:>14} {:>22}",
        "n",
        "µs per step",
        "/ unrolled",
        "max |phi| (l = 1)",
        "Newton/step",
        "max |q - q_unrolled|"
    );
    for ((n, (us_fixed, _, _, _)), q_fixed) in rows.iter().zip(&unrolled_tight) {
        let (us, phi, it, _) = measure_n(*n, steps, 0.01, defaults);
        let gap = (measure_n(*n, 100, 0.01, tight).3 - q_fixed).amax();
        println!(
            "{n:>6} {us:>14.1} {:>12.2} {phi:>18.1e} {it:>14.2} {gap:>22.1e}",
            us / us_fixed
        );
    }
    println!(
        "Run-time sizes beyond the unrolled ones ({long} steps each, h = 0.01 (128/n)^(1/2): the \
         hanging chain's fastest transverse wave has ω ∝ (tension)^(1/2) ∝ n^(1/2), so h ω is held at \
         its n = 128 value):"
    );
    let mut timed = Vec::new();
    for &n in &sizes {
        let h = 0.01 * (128.0 / n as f64).sqrt().min(1.0);
        let (us, phi, it, _) = measure_n(n, long, h, defaults);
        println!("{n:>6} {us:>14.1} {:>12} {phi:>18.1e} {it:>14.2}", "");
        timed.push((n as f64, us));
    }
    if let (Some(first), Some(last)) = (timed.first(), timed.last()) {
        if last.0 > first.0 {
            let slope = (last.1 / first.1).ln() / (last.0 / first.0).ln();
            println!(
                "log-log slope of the run-time-sized step, n = {} … {}: {slope:.2} (linear: 1)",
                first.0, last.0
            );
        }
    }
    println!(
        "The constrained step over the same chain with stiff springs (k = 10^4) in place of the \
         constraints, both sized at run time, h = 0.01, 200 steps, median of 5 interleaved runs:"
    );
    for n in [32, 128] {
        let (median, lo, hi) = constrained_over_springs(n, 5);
        println!("{n:>6} {median:>14.2} ({lo:.2}–{hi:.2})");
    }
}
