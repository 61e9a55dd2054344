//! Hand-written Lie group variational integrators (Lee, Leok & McClamroch 2005, 2007) for the
//! free rigid body and the heavy top, with the same discrete Lagrangians as
//! `dirac::systems::rotations`: Newton on the Cayley parameter `ξ ∈ R³` with the analytic 3 × 3
//! Jacobian. The reference the generated steps are tested and timed against (shared by
//! `examples/rotations.rs` and `tests/rotations.rs`).

#![allow(dead_code)]

use dirac::lie::{cayley, hat, vee};
use dirac::prelude::*;

/// `J_d = ½ tr(J) I − J` for `J = diag(j)`.
pub fn nonstandard(j: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::from_diagonal(&Vector3::new(
        j.y + j.z - j.x,
        j.x + j.z - j.y,
        j.x + j.y - j.z,
    )) * 0.5
}

/// `∂ cay(ξ)/∂ξ_c` for `cay(ξ) = I + α (ξ̂ + ξ̂²/2)`, `α = 4/(4 + |ξ|²)`:
/// `−(α²/2) ξ_c (ξ̂ + ξ̂²/2) + α (ê_c + (ê_c ξ̂ + ξ̂ ê_c)/2)`.
fn cayley_derivative(xi: &Vector3<f64>, c: usize) -> Matrix3<f64> {
    let alpha = 4.0 / (4.0 + xi.norm_squared());
    let s = hat(xi);
    let mut e = Vector3::zeros();
    e[c] = 1.0;
    let ec = hat(&e);
    (s + s * s * 0.5) * (-0.5 * alpha * alpha * xi[c]) + (ec + (ec * s + s * ec) * 0.5) * alpha
}

/// Solves `vee(F J_d − J_d Fᵀ) = b` for `F = cay(ξ)` by Newton from `ξ = guess` with the
/// analytic Jacobian, to `|residual| ≤ tol` or a correction at round-off (`≤ 4ε |ξ|`); the
/// solution and its number of corrections.
pub fn solve_cayley(
    jd: &Matrix3<f64>,
    b: &Vector3<f64>,
    guess: Vector3<f64>,
    tol: f64,
) -> (Vector3<f64>, usize) {
    let mut xi = guess;
    for iterations in 0..50 {
        let f = cayley(&xi);
        let r = vee(&(f * jd - jd * f.transpose())) - b;
        if r.amax() <= tol {
            return (xi, iterations);
        }
        let mut jac = Matrix3::zeros();
        for c in 0..3 {
            let df = cayley_derivative(&xi, c);
            jac.set_column(c, &vee(&(df * jd - jd * df.transpose())));
        }
        let dxi = jac.lu().solve(&r).expect("a regular LGVI Jacobian");
        xi -= dxi;
        if dxi.amax() <= 4.0 * f64::EPSILON * xi.amax() {
            return (xi, iterations + 1);
        }
    }
    panic!("the hand-written LGVI did not converge");
}

/// One step of the free rigid body: `h Π_k = vee(F J_d − J_d Fᵀ)`, `R_{k+1} = R_k F`,
/// `Π_{k+1} = Fᵀ Π_k`. Returns the new state and `ξ` (the next step's guess); `iterations`
/// counts the Newton corrections.
pub fn rigid_body_step(
    jd: &Matrix3<f64>,
    h: f64,
    r: &Matrix3<f64>,
    pi: &Vector3<f64>,
    guess: Vector3<f64>,
    tol: f64,
    iterations: &mut usize,
) -> (Matrix3<f64>, Vector3<f64>, Vector3<f64>) {
    let (xi, n) = solve_cayley(jd, &(pi * h), guess, tol);
    *iterations += n;
    let f = cayley(&xi);
    (r * f, f.transpose() * pi, xi)
}

/// One step of the heavy top (`mgl e3ᵀ R e3` potential, trapezoid rule), as [`rigid_body_step`]:
/// `vee(F J_d − J_d Fᵀ) = h Π_k − (h²/2) m g l (e3 × R_kᵀ e3)`, then
/// `Π_{k+1} = Fᵀ (Π_k − (h/2) m g l (e3 × R_kᵀ e3)) − (h/2) m g l (e3 × R_{k+1}ᵀ e3)`.
#[allow(clippy::too_many_arguments)]
pub fn heavy_top_step(
    jd: &Matrix3<f64>,
    h: f64,
    mgl: f64,
    r: &Matrix3<f64>,
    pi: &Vector3<f64>,
    guess: Vector3<f64>,
    tol: f64,
    iterations: &mut usize,
) -> (Matrix3<f64>, Vector3<f64>, Vector3<f64>) {
    let e3 = Vector3::z();
    let torque = |r: &Matrix3<f64>| e3.cross(&(r.transpose() * e3)) * (0.5 * h * mgl);
    let kick = pi - torque(r);
    let (xi, n) = solve_cayley(jd, &(kick * h), guess, tol);
    *iterations += n;
    let f = cayley(&xi);
    let next = r * f;
    (next, f.transpose() * kick - torque(&next), xi)
}
