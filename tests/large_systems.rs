//! Systems above the dense threshold: the sparse backend against an independent dense solve of
//! the same step equations, the choice of backend by size, streaming runs and ensembles.

use dirac::prelude::*;
use dirac::runtime::linalg::LinearSolver;
use dirac::runtime::newton;
use dirac::runtime::{CscValues, Lu, SparseLu, DENSE_MAX};
use nalgebra::DMatrix;

/// The periodic Toda lattice of 24 particles, midpoint rule, common translation declared:
/// N = 24 > DENSE_MAX, so the sparse backend.
#[reduced_lagrangian(coordinates(x[24]), translate(x), rule = midpoint)]
fn toda24(q: Config, v: Velocity, m: f64, d: f64) -> f64 {
    let mut l = 0.0;
    for i in 0..24 {
        l += 0.5 * m * v.x[i] * v.x[i];
    }
    for i in 0..23 {
        l -= (-(q.x[i + 1] - q.x[i] - d)).exp();
    }
    l - (-(q.x[0] + 24.0 * d - q.x[23] - d)).exp()
}

/// The same lattice with 16 particles: N = DENSE_MAX, the dense backend.
#[reduced_lagrangian(coordinates(x[16]), translate(x), rule = midpoint)]
fn toda16(q: Config, v: Velocity, m: f64, d: f64) -> f64 {
    let mut l = 0.0;
    for i in 0..16 {
        l += 0.5 * m * v.x[i] * v.x[i];
    }
    for i in 0..15 {
        l -= (-(q.x[i + 1] - q.x[i] - d)).exp();
    }
    l - (-(q.x[0] + 16.0 * d - q.x[15] - d)).exp()
}

/// And 17: one past the threshold, the sparse backend.
#[reduced_lagrangian(coordinates(x[17]), translate(x), rule = midpoint)]
fn toda17(q: Config, v: Velocity, m: f64, d: f64) -> f64 {
    let mut l = 0.0;
    for i in 0..17 {
        l += 0.5 * m * v.x[i] * v.x[i];
    }
    for i in 0..16 {
        l -= (-(q.x[i + 1] - q.x[i] - d)).exp();
    }
    l - (-(q.x[0] + 17.0 * d - q.x[16] - d)).exp()
}

const SYS: Toda24 = Toda24 {
    m: 1.0,
    d: 1.0,
    h: 0.05,
};

fn initial(j: usize) -> ReducedState<23, 1> {
    let n = 24.0;
    let q = SVector::<f64, 24>::from_fn(|i, _| {
        let phase = 2.0 * std::f64::consts::PI * i as f64 / n;
        i as f64 + (0.1 + 0.01 * j as f64) * phase.sin()
    });
    let p = SVector::<f64, 24>::from_fn(|i, _| {
        0.3 * (2.0 * std::f64::consts::PI * i as f64 / n).cos() + 0.05
    });
    SYS.trivialize(&Toda24::adapted_state(&q, &p))
}

/// An independent dense solver for the same Newton driver: nalgebra's LU with partial pivoting
/// on the Jacobian expanded from its CSC values.
struct DenseOracle {
    lu: Option<nalgebra::LU<f64, nalgebra::Dyn, nalgebra::Dyn>>,
    norm1: f64,
}

impl LinearSolver for DenseOracle {
    type Vector = SVector<f64, 24>;
    type Matrix = DMatrix<f64>;
    fn factor(&mut self, j: &DMatrix<f64>) -> Result<(), dirac::runtime::linalg::FactorError> {
        self.norm1 = j
            .column_iter()
            .map(|c| c.iter().map(|v| v.abs()).sum::<f64>())
            .fold(0.0, f64::max);
        let lu = j.clone().lu();
        if !lu.is_invertible() {
            return Err(dirac::runtime::linalg::FactorError::Singular);
        }
        self.lu = Some(lu);
        Ok(())
    }
    fn solve(&mut self, b: &SVector<f64, 24>) -> SVector<f64, 24> {
        let x = self
            .lu
            .as_ref()
            .and_then(|lu| lu.solve(&nalgebra::DVector::from_column_slice(b.as_slice())))
            .expect("factored and invertible");
        SVector::from_column_slice(x.as_slice())
    }
    fn norm1(&self) -> f64 {
        self.norm1
    }
    fn rcond_lower_bound(&mut self) -> f64 {
        1.0 // the oracle does not check conditioning
    }
    fn rcond(&mut self) -> f64 {
        1.0
    }
}

#[test]
fn the_backend_follows_the_size() {
    let name = |s: &str| s.rsplit("::").next().unwrap_or(s).to_string();
    let linear16 = std::any::type_name::<<Toda16 as Reduced<Plus, 15, 1, 16>>::Linear>();
    let linear17 = std::any::type_name::<<Toda17 as Reduced<Plus, 16, 1, 17>>::Linear>();
    let unreduced17 = std::any::type_name::<<Toda17 as Unreduced<16, 1, 17>>::UnreducedLinear>();
    assert_eq!(DENSE_MAX, 16);
    assert!(name(linear16).starts_with("Lu<16"), "{linear16}");
    assert!(linear17.contains("SparseLu<17"), "{linear17}");
    assert!(unreduced17.contains("SparseLu<17"), "{unreduced17}");
    let _: Lu<16> = <Toda16 as Reduced<Plus, 15, 1, 16>>::linear_solver(&Toda16 {
        m: 1.0,
        d: 1.0,
        h: 0.1,
    });
    let _: SparseLu<17, _> = <Toda17 as Reduced<Plus, 16, 1, 17>>::linear_solver(&Toda17 {
        m: 1.0,
        d: 1.0,
        h: 0.1,
    });
}

#[test]
fn the_sparse_jacobian_is_the_dense_one_and_so_are_the_steps() {
    let integ = ReducedIntegrator::plus(SYS, NewtonOptions::default());
    let traj = integ.clone().run(initial(0)).steps(50).collect().unwrap();
    for k in [0, 17, 49] {
        let (state, next) = (&traj.states[k], &traj.states[k + 1]);
        let z = dirac::runtime::system::join::<23, 1, 24>(&next.x, &traj.group_unknowns[k]);
        // The sparse values, placed by their pattern, equal central differences of the residual
        // (an independent check of the pattern and of every entry).
        let (_, values): (_, CscValues<_>) =
            Reduced::<Plus, 23, 1, 24>::residual_jacobian(&SYS, &state.x, &state.w, &state.mu, &z);
        let pattern = <Toda24 as Reduced<Plus, 23, 1, 24>>::linear_solver(&SYS).pattern();
        assert!(pattern.is_valid());
        let dense = values.to_dense(pattern);
        let eps = 1e-6;
        for c in 0..24 {
            let (mut zp, mut zm) = (z, z);
            zp[c] += eps;
            zm[c] -= eps;
            let rp = Reduced::<Plus, 23, 1, 24>::residual(&SYS, &state.x, &state.w, &state.mu, &zp);
            let rm = Reduced::<Plus, 23, 1, 24>::residual(&SYS, &state.x, &state.w, &state.mu, &zm);
            for r in 0..24 {
                let fd = (rp[r] - rm[r]) / (2.0 * eps);
                assert!(
                    (fd - dense[(r, c)]).abs() <= 1e-6 * (1.0 + dense[(r, c)].abs()),
                    "step {k}: J[{r},{c}] = {} against {fd}",
                    dense[(r, c)]
                );
            }
        }
        // The same Newton driver with the dense oracle from the same guess reaches the same
        // step to round-off.
        let guess = dirac::runtime::system::join::<23, 1, 24>(&state.x, &SVector::zeros());
        let rho = state.w.amax().max(state.mu.amax());
        let mut oracle = DenseOracle {
            lu: None,
            norm1: 0.0,
        };
        let dense_solution = newton::solve_with(
            &mut oracle,
            guess,
            rho,
            &NewtonOptions::default(),
            |z| Reduced::<Plus, 23, 1, 24>::residual(&SYS, &state.x, &state.w, &state.mu, z),
            |z| {
                let (r, v) = Reduced::<Plus, 23, 1, 24>::residual_jacobian(
                    &SYS, &state.x, &state.w, &state.mu, z,
                );
                (r, v.to_dense(pattern))
            },
        )
        .unwrap();
        let (sparse_step, _) = integ.step_from(k, state, &guess).unwrap();
        let dx = (dense_solution.z.fixed_rows::<23>(0) - sparse_step.x).amax();
        assert!(
            dx <= 1e-12 * (1.0 + sparse_step.x.amax()),
            "step {k}: sparse and dense solves differ by {dx:e}"
        );
    }
}

#[test]
fn chord_iterations_reach_the_steps_newton_reaches() {
    // A run keeps one sparse workspace, so after its first step a step corrects with the factors
    // of an earlier step as long as they contract the residual; `step` builds a fresh workspace
    // and so runs Newton with a Jacobian per correction. Both accept on the same residual test.
    let integ = ReducedIntegrator::plus(SYS, NewtonOptions::default());
    let steps = 200;
    let traj = integ
        .clone()
        .run(initial(2))
        .steps(steps)
        .collect()
        .unwrap();
    let factored: usize = traj.stats.iter().map(|s| s.factorizations).sum();
    assert!(traj.stats[0].factorizations >= 1);
    assert!(
        factored < steps / 4,
        "{factored} Jacobians factored in {steps} steps: the factors are not reused"
    );
    for k in (0..steps).step_by(20) {
        let state = &traj.states[k];
        let guess = dirac::runtime::system::join::<23, 1, 24>(&state.x, &SVector::zeros());
        let (newton_step, ReducedStep { stats, .. }) = integ.step_from(k, state, &guess).unwrap();
        assert_eq!(
            stats.factorizations, stats.iterations,
            "step {k}: {stats:?}"
        );
        let next = &traj.states[k + 1];
        let dx = (newton_step.x - next.x).amax();
        let dw = (newton_step.w - next.w).amax();
        assert!(
            dx <= 1e-12 * (1.0 + next.x.amax()) && dw <= 1e-12 * (1.0 + next.w.amax()),
            "step {k}: chord and Newton steps differ by {dx:e} (x), {dw:e} (w)"
        );
        assert_eq!(newton_step.mu, next.mu);
    }
}

#[test]
fn the_conditioning_threshold_holds_on_the_sparse_backend_with_chord_steps() {
    // The worst figure a run records is that of the factors its steps used; a threshold above it
    // turns the run into the typed error, with the steps before the failure kept.
    let integ = ReducedIntegrator::plus(SYS, NewtonOptions::default());
    let traj = integ.clone().run(initial(3)).steps(100).collect().unwrap();
    let (_, worst) = traj.worst_rcond().expect("the steps factored a Jacobian");
    let strict = NewtonOptions {
        min_rcond: 2.0 * worst,
        ..NewtonOptions::default()
    };
    let err = ReducedIntegrator::plus(SYS, strict)
        .run(initial(3))
        .steps(100)
        .collect()
        .unwrap_err();
    match err.source {
        StepError::IllConditioned { step, rcond, .. } => {
            assert!(rcond < 2.0 * worst, "{rcond:e}");
            assert_eq!(err.trajectory.states.len(), step + 1);
        }
        other => panic!("expected IllConditioned, got {other:?}"),
    }
}

#[test]
fn a_streaming_run_sees_what_integrate_keeps_and_keeps_nothing() {
    let integ = ReducedIntegrator::plus(SYS, NewtonOptions::default());
    let traj = integ.clone().run(initial(1)).steps(300).collect().unwrap();
    let mut seen = Vec::new();
    let mut every_50th = Vec::new();
    let summary = integ
        .run(initial(1))
        .steps(300)
        .observe(|k, _, state, step| {
            assert_eq!(step.is_none(), k == 0);
            if let Some(step) = step {
                assert_eq!(step.stats, traj.stats[k - 1]);
                assert_eq!(step.group_unknown, traj.group_unknowns[k - 1]);
            }
            seen.push(k);
            if k % 50 == 0 {
                every_50th.push(*state);
            }
        })
        .stream()
        .unwrap();
    assert_eq!(seen, (0..=300).collect::<Vec<_>>());
    assert_eq!(summary.step_count, 300);
    assert_eq!(summary.last, *traj.last());
    assert_eq!(summary.mean_iterations(), traj.mean_iterations());
    assert_eq!(summary.max_residual, traj.max_residual());
    assert_eq!(summary.worst_rcond, traj.worst_rcond());
    for (j, state) in every_50th.iter().enumerate() {
        assert_eq!(*state, traj.states[50 * j], "state {}", 50 * j);
    }
    // μ, the total momentum, is exact along the run.
    assert!(traj.states.iter().all(|s| s.mu == traj.states[0].mu));
    // A failing run keeps its summary: an invalid time step fails before the first step.
    let bad = ReducedIntegrator::plus(Toda24 { h: -0.1, ..SYS }, NewtonOptions::default());
    let err = bad
        .run(initial(1))
        .steps(10)
        .observe(|_, _, _, _| {})
        .stream()
        .unwrap_err();
    assert!(matches!(err.source, StepError::InvalidTimeStep { .. }));
    assert_eq!(err.trajectory.step_count, 0);
    assert_eq!(err.trajectory.last, initial(1));
}

#[test]
fn ensemble_members_are_the_sequential_runs_each_with_its_own_result() {
    let integ = ReducedIntegrator::plus(SYS, NewtonOptions::default());
    let mut starts: Vec<ReducedState<23, 1>> = (0..6).map(initial).collect();
    starts[3].w[5] = f64::NAN; // this member must fail, alone, with a typed error
    let results = integ.ensemble(&starts).steps(40).collect();
    assert_eq!(results.len(), 6);
    for (j, result) in results.iter().enumerate() {
        if j == 3 {
            let err = result.as_ref().unwrap_err();
            assert!(
                matches!(err.source, StepError::NonFinite { step: 0, .. }),
                "{err}"
            );
            continue;
        }
        let sequential = integ.clone().run(starts[j]).steps(40).collect().unwrap();
        assert_eq!(result.as_ref().unwrap(), &sequential, "member {j}");
    }
    // With observers: each member streams its own states; the summaries are the runs'.
    let streamed = integ
        .ensemble(&starts[..2])
        .steps(25)
        .stream(|_| |_, _, _: &ReducedState<23, 1>, _: Option<&_>| {});
    for (j, (_, result)) in streamed.iter().enumerate() {
        let sequential = integ.clone().run(starts[j]).steps(25).collect().unwrap();
        assert_eq!(
            result.as_ref().unwrap().last,
            *sequential.last(),
            "member {j}"
        );
    }
}
