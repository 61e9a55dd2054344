//! The systems of the paper's §7, ready to integrate, written with `#[reduced_lagrangian]` exactly
//! as a user would write them.

use crate::prelude::*;

/// Charged particle in a magnetic field in Kaluza–Klein form (§7.1), with the left-point rule
/// `L_d(q0, q1) = h L_K(q0, (q1 − q0)/h)` and the vector potential of the constant field
/// `B = b0 ∂_z`, `A(q) = (b0/2)(−q² dq¹ + q¹ dq²)`:
///
/// `L_K = ½ m |q̇|² + ½ (⟨A(q), q̇⟩ + θ̇)²`.
///
/// The group `S¹` translates `θ`; the connection is `ω_d = θ1 − θ0` (B = 0).
#[reduced_lagrangian(shape(x, y, z), group(theta))]
pub fn charged_particle(q0: Config, q1: Config, h: f64, m: f64, b0: f64) -> f64 {
    let (dx, dy, dz) = (q1.x - q0.x, q1.y - q0.y, q1.z - q0.z);
    let a_dot_dq = 0.5 * b0 * (-q0.y * dx + q0.x * dy);
    let s = a_dot_dq + (q1.theta - q0.theta);
    0.5 * m / h * (dx * dx + dy * dy + dz * dz) + 0.5 / h * s * s
}

impl ChargedParticle {
    /// The paper's run (§7.2.1): `m = 1`, `B0 = 1`, time step `T / steps` with `T = 20`.
    pub fn paper(steps: usize) -> Self {
        Self {
            h: CHARGED_PARTICLE_T / steps as f64,
            m: 1.0,
            b0: 1.0,
        }
    }

    /// The paper's initial state: `q0 = 0`, `θ0 = 0`, `w0 = (1, 0, 1)`, `μ0 = 1` (eq. (3.6)).
    pub fn paper_initial_state() -> ReducedState<3, 1> {
        ReducedState::new([0.0; 3], [1.0, 0.0, 1.0], [1.0], [0.0])
    }

    /// The exact solution of the Lorentz force law (7.1) for `B0 = 1` from the paper's initial
    /// state: `q(t) = (sin t, cos t − 1, t)`.
    pub fn exact_position(t: f64) -> [f64; 3] {
        [t.sin(), t.cos() - 1.0, t]
    }
}

/// The final time of the charged-particle run, `T = 20`.
pub const CHARGED_PARTICLE_T: f64 = 20.0;

/// `|q(T) − q_N|` printed in the paper's Table 1, for `N = 10, 50, 100, 200`.
pub const TABLE_1: [(usize, f64); 4] =
    [(10, 1.6781), (50, 0.25971), (100, 0.06626), (200, 0.01664)];
