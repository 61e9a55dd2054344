//! The charged particle's reduced (+) equations (4.6), derived and coded by hand: what the
//! generated code is measured against as the physical limit.
//!
//! # Derivation
//!
//! `L_d(q0, q1) = m/(2h) |Δq|² + 1/(2h) (A(q0)·Δq + Δθ)²` with `A(q) = β (−y, x, 0)`,
//! `β = b0/2`, is invariant under `θ ↦ θ + c` and `B = 0`, so with `x = (x, y, z)`,
//! `d = x1 − x0` and `g1 = θ1 − θ0`,
//!
//! ```text
//! l(x0, x1, g1) = α/2 |d|² + s²/(2h),   α = m/h,
//! s = A(x0)·d + g1 = β (x0 y1 − y0 x1) + g1          (the y0 x0 terms cancel).
//! ```
//!
//! With `∂s/∂x0 = β (y1, −x1, 0)`, `∂s/∂x1 = β (−y0, x0, 0) = A(x0)`, `∂s/∂g1 = 1`:
//!
//! ```text
//! ∂l/∂x0 = −α d + (s/h) β (y1, −x1, 0),    ∂l/∂g1 = s/h,    ∂l/∂x1 = α d + (s/h) A(x0),
//! ```
//!
//! and the step residual in `z = (x1, y1, z1, g1)` is
//!
//! ```text
//! R = ( −α dx + (s/h) β y1 + w_x,  −α dy − (s/h) β x1 + w_y,  −α dz + w_z,  s/h − μ ).
//! ```
//!
//! Its Jacobian, with `s_z = ∂s/∂z = (−β y0, β x0, 0, 1)`:
//!
//! ```text
//! ∂R_x/∂z = −α e_x + (β y1/h) s_z + (β s/h) e_y
//! ∂R_y/∂z = −α e_y − (β x1/h) s_z − (β s/h) e_x
//! ∂R_z/∂z = −α e_z
//! ∂R_g/∂z = s_z / h
//! ```
//!
//! The step also has a closed form: `R_g = 0` is `s = h μ`, after which `R_x = R_y = 0` are
//! linear in `d` — a 2 × 2 rotation-dilation system (the discrete Lorentz force with gyration
//! `γ = μ β`) — and `R_z = 0` is `dz = w_z / α`; `g1` then follows from `s`. [`closed_form_step`]
//! is that solution: no Newton iteration at all.

use dirac::paper::ChargedParticle;
use dirac::prelude::*;
use dirac::runtime::newton::{self, NewtonFailure};

/// `R(z)` at `(x_k, w_k, μ_k)`.
pub fn residual(
    p: &ChargedParticle,
    x_k: &SVector<f64, 3>,
    w_k: &SVector<f64, 3>,
    mu_k: &SVector<f64, 1>,
    z: &SVector<f64, 4>,
) -> SVector<f64, 4> {
    let (alpha, beta, inv_h) = (p.m / p.h, 0.5 * p.b0, 1.0 / p.h);
    let (x0, y0, z0) = (x_k[0], x_k[1], x_k[2]);
    let (x1, y1, z1, g1) = (z[0], z[1], z[2], z[3]);
    let s_h = (beta * (x0 * y1 - y0 * x1) + g1) * inv_h;
    SVector::from([
        -alpha * (x1 - x0) + s_h * beta * y1 + w_k[0],
        -alpha * (y1 - y0) - s_h * beta * x1 + w_k[1],
        -alpha * (z1 - z0) + w_k[2],
        s_h - mu_k[0],
    ])
}

/// `R(z)` and `∂R/∂z`.
pub fn residual_jacobian(
    p: &ChargedParticle,
    x_k: &SVector<f64, 3>,
    w_k: &SVector<f64, 3>,
    mu_k: &SVector<f64, 1>,
    z: &SVector<f64, 4>,
) -> (SVector<f64, 4>, SMatrix<f64, 4, 4>) {
    let (alpha, beta, inv_h) = (p.m / p.h, 0.5 * p.b0, 1.0 / p.h);
    let (x0, y0, z0) = (x_k[0], x_k[1], x_k[2]);
    let (x1, y1, z1, g1) = (z[0], z[1], z[2], z[3]);
    let s_h = (beta * (x0 * y1 - y0 * x1) + g1) * inv_h;
    let r = SVector::from([
        -alpha * (x1 - x0) + s_h * beta * y1 + w_k[0],
        -alpha * (y1 - y0) - s_h * beta * x1 + w_k[1],
        -alpha * (z1 - z0) + w_k[2],
        s_h - mu_k[0],
    ]);
    // s_z / h = (−β y0, β x0, 0, 1) / h.
    let (sx, sy, sg) = (-beta * y0 * inv_h, beta * x0 * inv_h, inv_h);
    let (by1, bx1, bs) = (beta * y1, beta * x1, beta * s_h);
    #[rustfmt::skip]
    let jac = SMatrix::<f64, 4, 4>::new(
        -alpha + by1 * sx,  by1 * sy + bs,       0.0,    by1 * sg,
        -bx1 * sx - bs,     -alpha - bx1 * sy,   0.0,    -bx1 * sg,
        0.0,                0.0,                 -alpha, 0.0,
        sx,                 sy,                  0.0,    sg,
    );
    (r, jac)
}

/// `w_{k+1} = ∂l/∂x1 = α d + (s/h) A(x0)`.
pub fn momentum(
    p: &ChargedParticle,
    x_k: &SVector<f64, 3>,
    z: &SVector<f64, 4>,
) -> SVector<f64, 3> {
    let (alpha, beta) = (p.m / p.h, 0.5 * p.b0);
    let (x0, y0, z0) = (x_k[0], x_k[1], x_k[2]);
    let (x1, y1, z1, g1) = (z[0], z[1], z[2], z[3]);
    let s_h = (beta * (x0 * y1 - y0 * x1) + g1) / p.h;
    SVector::from([
        alpha * (x1 - x0) - s_h * beta * y0,
        alpha * (y1 - y0) + s_h * beta * x0,
        alpha * (z1 - z0),
    ])
}

/// One step with the hand-coded residual and Jacobian and the runtime's Newton solver and
/// tolerances (what `ReducedIntegrator::step` does with the generated ones). Returns the new
/// state, `g_k^+` and the Newton corrections taken.
pub fn newton_step(
    p: &ChargedParticle,
    options: &NewtonOptions,
    state: &ReducedState<3, 1>,
    guess: &SVector<f64, 4>,
) -> Result<(ReducedState<3, 1>, SVector<f64, 1>, usize), NewtonFailure> {
    let (x, w, mu) = (&state.x, &state.w, &state.mu);
    let rho = newton::inf_norm(w).max(newton::inf_norm(mu));
    let solution = newton::solve(
        *guess,
        rho,
        options,
        |z| residual(p, x, w, mu, z),
        |z| residual_jacobian(p, x, w, mu, z),
    )?;
    let z = solution.z;
    let g_plus = SVector::from([z[3]]);
    let next = ReducedState {
        x: SVector::from([z[0], z[1], z[2]]),
        w: momentum(p, x, &z),
        mu: *mu,
        g: state.g + g_plus,
    };
    Ok((next, g_plus, solution.iterations))
}

/// The step in closed form (see the module docs): `s = h μ`, then
///
/// ```text
/// [ −α   γ ] [dx]   [ −w_x − γ y0 ]
/// [ −γ  −α ] [dy] = [ −w_y + γ x0 ],   dz = w_z / α,   γ = μ β,
/// ```
///
/// `g1 = s − β (x0 y1 − y0 x1)` and `w_{k+1} = α d + μ A(x0)`.
pub fn closed_form_step(
    p: &ChargedParticle,
    state: &ReducedState<3, 1>,
) -> (ReducedState<3, 1>, f64) {
    let (alpha, beta) = (p.m / p.h, 0.5 * p.b0);
    let (x0, y0, z0) = (state.x[0], state.x[1], state.x[2]);
    let (w, mu) = (&state.w, state.mu[0]);
    let gamma = mu * beta;
    let (r0, r1) = (-w[0] - gamma * y0, -w[1] + gamma * x0);
    let det = alpha * alpha + gamma * gamma;
    let dx = (-alpha * r0 - gamma * r1) / det;
    let dy = (gamma * r0 - alpha * r1) / det;
    let dz = w[2] / alpha;
    let (x1, y1) = (x0 + dx, y0 + dy);
    let g_plus = p.h * mu - beta * (x0 * y1 - y0 * x1);
    let next = ReducedState {
        x: SVector::from([x1, y1, z0 + dz]),
        w: SVector::from([
            alpha * dx - mu * beta * y0,
            alpha * dy + mu * beta * x0,
            alpha * dz,
        ]),
        mu: state.mu,
        g: SVector::from([state.g[0] + g_plus]),
    };
    (next, g_plus)
}
