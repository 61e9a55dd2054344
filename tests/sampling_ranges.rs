//! `ranges(...)`: a Lagrangian defined only on part of the configuration space compiles once the
//! attribute says where the invariance check may sample it, and integrates like any other.

use dirac::prelude::*;

/// A particle in the logarithmic potential `−ln(x − 3)`, defined only for `x > 3`: at every
/// point of the default sampling box `[−2, 2]` the body is NaN, so without `ranges(x = ...)`
/// the attribute rejects it (case `tests/ui/invariance/never_finite.rs`).
#[reduced_lagrangian(shape(x), group(theta), ranges(x = (3.5, 6.0), h = (0.001, 0.1)))]
fn log_well(q0: Config, q1: Config, h: f64, m: f64) -> f64 {
    let (dx, dg) = (q1.x - q0.x, q1.theta - q0.theta);
    0.5 * m / h * (dx * dx + dg * dg) + h * (q0.x - 3.0).ln()
}

#[test]
fn a_body_defined_on_part_of_the_space_compiles_and_integrates() {
    let sys = LogWell { h: 0.01, m: 1.0 };
    let initial = ReducedState::new([4.0], [0.0], [0.7], [0.0]);
    let integ = ReducedIntegrator::plus(sys, NewtonOptions::default());
    let traj = integ
        .run(initial)
        .steps(200)
        .collect()
        .expect("the steps converge");
    // The potential pushes x outwards; μ is conserved exactly (it is one of the equations).
    assert!(traj.last().x[0] > 4.0, "x = {}", traj.last().x[0]);
    assert_eq!(traj.last().mu, initial.mu);
    // θ advances at the rate μ / m with μ = 0.7 and m = 1 (the group coordinate is free).
    let t = 200.0 * sys.h;
    assert!(
        (traj.last().g[0] - 0.7 * t).abs() < 1e-9 * t,
        "θ = {}",
        traj.last().g[0]
    );
}
