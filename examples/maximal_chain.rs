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
//! Run: `cargo run --release --example maximal_chain`.

use std::time::Instant;

use dirac::prelude::*;

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
            /// Time per step (µs) over `steps` steps from the benchmark's state, at rest, and
            /// the largest constraint residual.
            fn measure(steps: usize) -> (f64, f64, f64) {
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
                let integ = ConstrainedIntegrator::new(sys, NewtonOptions::default());
                let start = Instant::now();
                let traj = integ.run(c0).steps(steps).collect().expect("the chain integrates");
                let us = start.elapsed().as_secs_f64() * 1e6 / steps as f64;
                (us, traj.max_constraint_residual(), traj.mean_iterations())
            }
        }
    };
}

maximal_chain!(chain16, Chain16, 16);
maximal_chain!(chain32, Chain32, 32);
maximal_chain!(chain64, Chain64, 64);
maximal_chain!(chain128, Chain128, 128);

fn main() {
    // No options: `--help` says so, and any argument stops the example with exit code 2.
    cli::Cli::new(
        "maximal_chain",
        "the scaling benchmark's chain in maximal coordinates, one constraint per link",
    )
    .finish();
    let steps = 2000;
    println!("Planar chain in maximal coordinates (cart + n end points, n length constraints), h = 0.01, {steps} steps:");
    println!(
        "{:>6} {:>10} {:>14} {:>18} {:>14}",
        "n", "unknowns", "µs per step", "max |phi| (l = 1)", "Newton/step"
    );
    let rows = [
        (16, Chain16::measure(steps)),
        (32, Chain32::measure(steps)),
        (64, Chain64::measure(steps)),
        (128, Chain128::measure(steps)),
    ];
    for (n, (us, phi, it)) in rows {
        println!(
            "{n:>6} {:>10} {us:>14.1} {phi:>18.1e} {it:>14.2}",
            3 * n + 1
        );
    }
    let slope = ((rows[3].1).0 / (rows[0].1).0).ln() / (128.0_f64 / 16.0).ln();
    println!("log-log slope of the step time, n = 16 … 128: {slope:.2} (linear: 1)");
}
