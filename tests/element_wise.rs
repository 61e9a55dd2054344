//! Element-wise systems with run-time sizes (`dirac::runtime::element`).

use dirac::prelude::*;
use dirac::runtime::element::ElementIntegrator;

#[path = "../examples/common/toda_n.rs"]
mod toda_n;
use toda_n::{initial, TodaN};

#[test]
fn one_build_runs_at_several_sizes() {
    for n in [3, 16, 200, 2000] {
        let sys = TodaN { m: 1.0, d: 1.0, h: 0.05, n };
        let integ = ElementIntegrator::new(sys, NewtonOptions::default());
        let start = initial(&sys, 0.1, 0.3, 0.05);
        let mu0 = integ.momentum_map(&start)[0];
        let traj = integ.integrate(start, 200).unwrap();
        let last = traj.states.last().unwrap();
        let mu = integ.momentum_map(last)[0];
        assert!((mu - mu0).abs() <= 1e-13 * mu0.abs().max(1.0), "n = {n}: {mu} vs {mu0}");
    }
}
