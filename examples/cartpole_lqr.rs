//! An LQR controller for the cart-pole, designed on the discrete linearisation that the step
//! sensitivities give.
//!
//! The cart position is the group coordinate (the cart-pole is invariant under translating the
//! cart), the force on the cart a control. The step sensitivity at the upright equilibrium,
//! `s_{k+1} ≈ A s_k + B u_k` in the reduced state `s = (θ, w, μ, g)` (pole angle, its reduced
//! momentum, the cart's momentum, the cart position), is exactly the linearisation of the
//! integrator itself, so the controller is designed for the discrete system it runs on. The
//! discrete algebraic Riccati equation is solved by its fixed-point iteration; the feedback
//! `u_k = −K s_k` then stabilises the upright pole from a displaced start in the full nonlinear
//! forced integrator.
//!
//! Run: `cargo run --release --example cartpole_lqr`.

use dirac::prelude::*;
use nalgebra::{DMatrix, SMatrix, SVector};

#[path = "common/cli.rs"]
mod cli;

#[path = "common/cartpole.rs"]
mod cartpole;

fn main() {
    // No options: `--help` says so, and any argument stops the example with exit code 2.
    cli::Cli::new(
        "cartpole_lqr",
        "an LQR controller for the cart-pole, designed on the step sensitivities",
    )
    .finish();
    let h = 0.01;
    let sys = cartpole::baseline(h);
    let integ = ReducedIntegrator::plus(sys, NewtonOptions::default());
    // The discrete linearisation at the upright equilibrium, u = 0.
    let upright = cartpole::at_rest(0.0, 0.0);
    let (_, _, lin) = integ
        .step_sensitivity(0, &upright, &[0.0])
        .expect("the equilibrium step");
    let a = SMatrix::<f64, 4, 4>::from_iterator(lin.state.iter().copied());
    let b = SVector::<f64, 4>::from_iterator(lin.control.iter().copied());
    println!("Cart-pole (mc = 1, m = 0.1, l = 0.5), h = {h}: the step's sensitivity at the upright equilibrium");
    println!("A = ∂s_(k+1)/∂s_k (s = (theta, w, mu, s_cart)):{a}B = ∂s_(k+1)/∂u_k:{b}");

    // LQR weights: the pole angle and the cart position, lightly the momenta; R on the force.
    let q = SMatrix::<f64, 4, 4>::from_diagonal(&SVector::from([10.0, 1.0, 1.0, 10.0]));
    let r = 0.1;
    // The discrete algebraic Riccati equation by its fixed-point iteration.
    let mut p = q;
    let mut iterations = 0;
    let k = loop {
        iterations += 1;
        let btp = b.transpose() * p;
        let gain = (btp * a) / (r + (btp * b)[0]);
        let next = q + a.transpose() * p * a - a.transpose() * p * b * gain;
        let change = (next - p).amax() / next.amax();
        p = next;
        if change < 1e-13 || iterations == 100_000 {
            break gain;
        }
    };
    let closed = a - b * k;
    let radius = DMatrix::from_iterator(4, 4, closed.iter().copied())
        .complex_eigenvalues()
        .iter()
        .map(|e| e.norm())
        .fold(0.0, f64::max);
    println!("LQR gain K = {k}(Riccati iteration: {iterations} steps); spectral radius of A − B K: {radius:.6}");

    // The nonlinear forced integrator under the feedback u_k = −K s_k, from a displaced start.
    let start = cartpole::at_rest(0.25, 0.5);
    let steps = 1000;
    let feedback = |_k: usize, _t: f64, s: &ReducedState<1, 1>, u: &mut [f64]| {
        let state = SVector::<f64, 4>::from([s.x[0], s.w[0], s.mu[0], s.g[0]]);
        u[0] = -(k * state)[0];
    };
    let traj = integ
        .run(start)
        .steps(steps)
        .feedback(feedback)
        .collect()
        .expect("the closed loop integrates");
    println!("\nClosed loop from theta = 0.25 rad, cart at 0.5 m, at rest:");
    println!("{:>8} {:>12} {:>12} {:>12}", "t", "theta", "cart", "force");
    for i in (0..=steps).step_by(100) {
        let s = &traj.states[i];
        let state = SVector::<f64, 4>::from([s.x[0], s.w[0], s.mu[0], s.g[0]]);
        let force = -(k * state)[0];
        println!(
            "{:>8.2} {:>12.3e} {:>12.3e} {:>12.3e}",
            traj.times[i], s.x[0], s.g[0], force
        );
    }
    let last = traj.last();
    let norm = [last.x[0], last.w[0], last.mu[0], last.g[0]]
        .iter()
        .fold(0.0_f64, |m, v| m.max(v.abs()));
    println!(
        "After {} s the state is within {norm:.2e} of upright at rest: the pole is stabilised.",
        traj.times[steps]
    );
    assert!(
        radius < 1.0 && norm < 1e-3,
        "the LQR feedback did not stabilise the pole"
    );
}
