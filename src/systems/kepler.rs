//! The Kepler problem in polar coordinates, with its closed-form solution: the test bed for the
//! orders of the symmetric compositions ([`crate::Composition`]).
//!
//! `L = ½ (ṙ² + r² φ̇²) + k/r` is invariant under rotations, which translate the polar angle
//! `φ`: the group is `G = S¹` (K = 1) with coordinate `φ`, the shape is `r`, and the conserved
//! momentum `μ = p_φ = r² φ̇` is the angular momentum.

use crate::prelude::*;

/// The Kepler problem with the midpoint rule `L_d(q0, q1) = h L((q0 + q1)/2, (q1 − q0)/h)`, a
/// symmetric rule (`L_d(q0, q1; −h) = −L_d(q1, q0; h)`), so its step is self-adjoint and of
/// order 2. The radius is positive (`domain(r > 0.0)`): a step too coarse for the periapsis
/// passage, which the step equations solve with `r < 0`, stops a run with
/// [`crate::StepError::OutOfDomain`] instead of returning an orbit through the origin.
#[reduced_lagrangian(shape(r), group(phi), domain(r > 0.0))]
pub fn kepler(q0: Config, q1: Config, h: f64, k: f64) -> f64 {
    let r = 0.5 * (q0.r + q1.r);
    let (dr, dphi) = ((q1.r - q0.r) / h, (q1.phi - q0.phi) / h);
    h * (0.5 * (dr * dr + r * r * dphi * dphi) + k / r)
}

impl Kepler {
    /// The orbit of [`Self::exact`] and [`Self::periapsis_state`] for `k = 1`: semi-major axis
    /// `a = 1`, so the period is `2π`.
    pub fn unit(h: f64) -> Self {
        Self { h, k: 1.0 }
    }

    /// The state at periapsis of the elliptic orbit with semi-major axis `a` and eccentricity `e`
    /// (`0 ≤ e < 1`): `r = a (1 − e)`, `φ = 0`, `p_r = 0` and the angular momentum
    /// `μ = p_φ = √(k a (1 − e²))` (B = 0, so `w = p_r`).
    pub fn periapsis_state(&self, a: f64, e: f64) -> ReducedState<1, 1> {
        ReducedState::new(
            [a * (1.0 - e)],
            [0.0],
            [(self.k * a * (1.0 - e * e)).sqrt()],
            [0.0],
        )
    }

    /// The exact state at time `t` of the orbit started at periapsis by
    /// [`Self::periapsis_state`]: the eccentric anomaly `E` solves Kepler's equation
    /// `E − e sin E = n t` (`n = √(k/a³)`), then `r = a (1 − e cos E)`,
    /// `p_r = ṙ = a e n sin E / (1 − e cos E)`, and the polar angle is the true anomaly, taken
    /// continuous in `t` (no wrap to `(−π, π]`):
    /// `φ = E + 2 atan2(β sin E, 1 − β cos E)`, `β = e / (1 + √(1 − e²))`.
    pub fn exact(&self, a: f64, e: f64, t: f64) -> ReducedState<1, 1> {
        let n = (self.k / (a * a * a)).sqrt();
        let m = n * t;
        // Newton on f(E) = E − e sin E − M from E = M (+ e for a start on the right side of
        // the root); f' ≥ 1 − e > 0 and f is convex or concave between E = M and the root, so
        // it converges monotonically; 50 iterations is far beyond what e ≤ 0.9 needs.
        let mut ecc = m + e * m.sin();
        for _ in 0..50 {
            let delta = (ecc - e * ecc.sin() - m) / (1.0 - e * ecc.cos());
            ecc -= delta;
            if delta.abs() <= 1e-16 * ecc.abs().max(1.0) {
                break;
            }
        }
        let (s, c) = ecc.sin_cos();
        let beta = e / (1.0 + (1.0 - e * e).sqrt());
        let phi = ecc + 2.0 * (beta * s).atan2(1.0 - beta * c);
        let periapsis = self.periapsis_state(a, e);
        ReducedState::new(
            [a * (1.0 - e * c)],
            [a * e * n * s / (1.0 - e * c)],
            [periapsis.mu[0]],
            [phi],
        )
    }
}
