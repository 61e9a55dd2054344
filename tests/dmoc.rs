//! The DMOC swing-up of the cart-pole (`examples/dmoc_cartpole.rs`): the chained constraint
//! Jacobian `∂s_N/∂u` against central differences, and the first-order conditions at the
//! optimiser's solution.

#[path = "../examples/common/cartpole.rs"]
mod cartpole;
#[path = "../examples/common/dmoc.rs"]
mod dmoc;

use dirac::nalgebra::DVector;
use dmoc::Swingup;

/// A control sequence that swings the pole well away from the hanging equilibrium.
fn probe_controls(n: usize) -> Vec<f64> {
    (0..n)
        .map(|k| {
            let t = k as f64 / n as f64;
            6.0 * (7.0 * t).sin() + 2.0 * t
        })
        .collect()
}

#[test]
fn chained_jacobian_matches_central_differences() {
    let problem = Swingup::new(30, 2.0);
    let u = probe_controls(problem.n);
    let shot = problem.shoot(&u).unwrap();
    let jac = problem.jacobian(&u, &shot).unwrap();
    let eps = 1e-6;
    let mut worst = 0.0_f64;
    for k in 0..problem.n {
        let (mut up, mut um) = (u.clone(), u.clone());
        up[k] += eps;
        um[k] -= eps;
        let fd =
            (problem.shoot(&up).unwrap().defect - problem.shoot(&um).unwrap().defect) / (2.0 * eps);
        for i in 0..4 {
            let scale = jac.column(k).amax().max(1e-3);
            worst = worst.max((fd[i] - jac[(i, k)]).abs() / scale);
        }
    }
    println!("largest relative difference {worst:.3e}");
    assert!(
        worst < 1e-6,
        "chained Jacobian differs from central differences by {worst:.3e}"
    );
}

/// The optimiser's solution of the swing-up with N = 30 satisfies single shooting's first-order
/// conditions: a plain forward pass of the optimal controls ends on the target, and the cost
/// gradient is `Jᵀλ` for the least-squares multipliers, with the chained Jacobian.
#[test]
fn optimum_satisfies_first_order_conditions() {
    let problem = Swingup::new(30, 2.0);
    let sol = dmoc::solve(
        &problem,
        &vec![0.0; problem.n],
        &problem.linear_guess(),
        dmoc::SqpOptions::default(),
    )
    .unwrap();
    let shot = problem.shoot(&sol.u).unwrap();
    let violation = shot.defect.amax();
    let jac = problem.jacobian(&sol.u, &shot).unwrap();
    let grad = DVector::from_column_slice(&sol.u) * (2.0 * problem.h);
    let (lambda, stationarity) = dmoc::multipliers(&grad, &jac);
    println!(
        "cost {:.12}, {} iterations, violation {violation:.2e}, stationarity {stationarity:.2e}, \
         λ = {:?}",
        sol.cost,
        sol.iterations,
        lambda.as_slice()
    );
    assert!(violation <= 1e-8, "constraint violation {violation:.3e}");
    // Not a trivial stationary point: the controls do work, and the multipliers are not zero.
    assert!(sol.cost > 1.0 && lambda.amax() > 1.0);
    // ∇J = Jᵀλ: the residual relative to ‖∇J‖∞ (which exceeds 1 here).
    assert!(grad.amax() > 1.0);
    assert!(
        stationarity <= 1e-6,
        "first-order residual {stationarity:.3e}"
    );
    // The residual is what the assertion measures: the same controls, perturbed, fail it.
    let mut off = sol.u.clone();
    off[3] += 1e-3;
    let shot = problem.shoot(&off).unwrap();
    let jac = problem.jacobian(&off, &shot).unwrap();
    let grad = DVector::from_column_slice(&off) * (2.0 * problem.h);
    let (_, perturbed) = dmoc::multipliers(&grad, &jac);
    assert!(
        perturbed > 1e-6,
        "a perturbed control passes: {perturbed:.3e}"
    );
}
