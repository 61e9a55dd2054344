//! The cart-pole with the cart position as the group coordinate: shared by
//! `examples/cartpole_lqr.rs` and `examples/dmoc_cartpole.rs` (included with `#[path]`).
//!
//! Cart mass `mc`, a point mass `m` at the end of a massless pole of length `l`, gravity `g`;
//! coordinates `theta` (the pole angle from upright, shape) and `s` (the cart position, group:
//! the Lagrangian does not depend on it, so translating the cart is a symmetry and its momentum
//! `μ` changes only by the impulse of the force `u` on the cart). The bob sits at
//! `(s + l sin θ, l cos θ)`, so
//! `L = ½ (mc + m) ṡ² + m l cos θ ṡ θ̇ + ½ m l² θ̇² − m g l cos θ`, discretized by the midpoint
//! rule, with the force `u` (a control) on the cart: virtual work `u δs`. This is the problem
//! that `examples/dmoc/cartpole_casadi.py` transcribes for CasADi and IPOPT.

use dirac::prelude::*;

/// The cart-pole (see the module documentation).
#[reduced_lagrangian(shape(theta), group(s), rule = midpoint, controls(u),
    force = |dq| u * dq.s)]
pub fn cartpole(q: Config, v: Velocity, mc: f64, m: f64, l: f64, g: f64, u: f64) -> f64 {
    0.5 * (mc + m) * v.s * v.s
        + m * l * q.theta.cos() * v.s * v.theta
        + 0.5 * m * l * l * v.theta * v.theta
        - m * g * l * q.theta.cos()
}

/// The cart-pole of the CasADi baseline: `mc = 1`, `m = 0.1`, `l = 0.5`, `g = 9.81`, time step
/// `h`, no force.
pub fn baseline(h: f64) -> Cartpole {
    Cartpole {
        h,
        mc: 1.0,
        m: 0.1,
        l: 0.5,
        g: 9.81,
        u: 0.0,
    }
}

/// The state at rest at pole angle `theta` and cart position `s` (all momenta zero).
pub fn at_rest(theta: f64, s: f64) -> ReducedState<1, 1> {
    ReducedState::new([theta], [0.0], [0.0], [s])
}
