//! The step of an element-wise system ([`Stepper`] for [`ElementIntegrator`], both sides) and
//! its compositions ([`crate::compose::SelfAdjoint`]); see the [parent module](super).

use nalgebra::DVector;

use super::{
    sums, ElementIntegrator, ElementLagrangian, ElementState, ElementTrajectory, ElementWorkspace,
};
use crate::error::StepError;
use crate::model::{refuse_domain, system_at};
use crate::newton::solve_in;
use crate::stepper::{check_inputs, step_error, StepAt, StepStats, Stepper};
use crate::system::Variant;

impl<L: ElementLagrangian> Stepper for ElementIntegrator<L> {
    type State = ElementState;
    type Record = StepStats;
    type Workspace = ElementWorkspace;
    type Trajectory = ElementTrajectory;

    fn time_step(&self) -> f64 {
        self.system.time_step()
    }

    fn check(&self, initial: &ElementState) -> Result<(), StepError> {
        check_inputs(
            self.system.time_step(),
            &self.system.parameter_values(),
            initial.is_finite(),
        )?;
        refuse_domain(
            &self.system,
            "a declared domain on an element-wise system (only a system of fixed size checks one)",
        )?;
        if self.system.time_index().is_some() {
            return Err(StepError::Unsupported {
                what: "adaptive steps of an element-wise system (a time coordinate is declared \
                       only on a system of fixed size or on rotation groups)",
            });
        }
        self.check_sizes(initial)
    }

    fn workspace(&self) -> ElementWorkspace {
        ElementWorkspace::new(&self.system, self.parallel, self.linear)
    }

    fn control_dim(&self) -> usize {
        self.system.control_count()
    }

    /// Step `k` into `next` (whose memory is reused): Newton on `R(q_{k+1}) = 0` from the
    /// extrapolated guess, then `p_{k+1} = D_2 L_d` with the momentum map of each translation
    /// kept exact (see the [module documentation](super)).
    fn step_into(
        &self,
        workspace: &mut ElementWorkspace,
        at: StepAt<'_>,
        state: &ElementState,
        next: &mut ElementState,
    ) -> Result<StepStats, StepError> {
        let StepAt { k, h, u } = at;
        // The system of this step (its controls checked first, before the workspace and state).
        let owned = system_at(&self.system, k, h, u)?;
        self.check_workspace(workspace)?;
        let n = workspace.dim();
        if state.q.len() != n || state.p.len() != n {
            return Err(self.invalid(format!(
                "the state has {} coordinates and {} momenta, the system {n}",
                state.q.len(),
                state.p.len()
            )));
        }
        if next.q.len() != n || next.p.len() != n {
            *next = state.clone();
        }
        workspace.guess(&state.q, h, &mut next.q);
        let minus = self.variant == Variant::Minus;
        if minus {
            // The (−) unknown: the backward increment Δ = q_k − q_{k+1} of the same guess.
            flip_backward(state.q.as_slice(), next.q.as_mut_slice());
        }
        let rho = crate::newton::slice_inf_norm(state.p.as_slice());
        let sys = owned.as_ref().unwrap_or(&self.system);
        let (q0, p0) = (state.q.as_slice(), state.p.as_slice());
        let (solver, r, jacobian, assembler, scratch) = workspace.parts();
        let nnz = assembler.nnz();
        // The point `q_{k+1}` an unknown stands for: itself for (+), `q_k − Δ` for (−) (into
        // the workspace's scratch vector).
        let point = |unknown: &DVector<f64>, run: &mut dyn FnMut(&[f64])| {
            if minus {
                let mut z = scratch.borrow_mut();
                backward_point(q0, unknown.as_slice(), z.as_mut_slice());
                run(z.as_slice());
            } else {
                run(unknown.as_slice());
            }
        };
        let solution = solve_in(
            solver,
            &mut next.q,
            r,
            jacobian,
            rho,
            &self.options,
            |unknown, r| {
                point(unknown, &mut |z| {
                    assembler.residual_jacobian(sys, q0, p0, z, r.as_mut_slice(), None)
                })
            },
            |unknown, r, j| {
                let j = j.get_or_insert_with(|| vec![0.0; nnz]);
                point(unknown, &mut |z| {
                    assembler.residual_jacobian(
                        sys,
                        q0,
                        p0,
                        z,
                        r.as_mut_slice(),
                        Some(j.as_mut_slice()),
                    )
                });
                if minus {
                    // ∂R/∂Δ = −∂R/∂q_{k+1}.
                    j.iter_mut().for_each(|v| *v = -*v);
                }
            },
        )
        .map_err(|failure| step_error(k, failure))?;
        if minus {
            // q_{k+1} = q_k − Δ, as the last residual pass formed it.
            flip_backward(q0, next.q.as_mut_slice());
        }
        // The last pass was at the solution: its `D_2 L_d` is the next momentum.
        assembler.take_momentum(&mut next.p);
        keep_momentum_maps(
            sys,
            assembler.orbits(),
            q0,
            p0,
            next.q.as_slice(),
            &mut next.p,
        );
        if !next.p.iter().all(|v| v.is_finite()) {
            return Err(StepError::NonFinite {
                step: k,
                what: "the new momentum",
                residual: solution.residual,
            });
        }
        workspace.remember(&state.q, &next.q, h);
        Ok(StepStats::from_solution(
            &solution,
            self.options.residual_tolerance(rho),
        ))
    }
}

/// Compositions of order 4 and 6 ([`crate::Composition`]) of a run-time-sized system: each stage
/// is the system at the stage's step `γ_i h` (negative for some stages), stepped by the same
/// assembly and solver, in a workspace of its own.
impl<L: ElementLagrangian> crate::compose::SelfAdjoint for ElementIntegrator<L> {
    fn with_time_step(&self, h: f64) -> Self {
        Self {
            system: self.system.with_time_step(h),
            ..self.clone()
        }
    }

    /// The largest relative defect `|L_d(q0, q1; −h) + L_d(q1, q0; h)|` over the sample pairs
    /// of [`crate::compose::symmetry_defect`] around the configuration of `at` (NaN where a
    /// sample is outside the Lagrangian's domain or the state does not fit the sizes).
    fn symmetry_defect(&self, at: &ElementState) -> f64 {
        let backward = self.system.with_time_step(-self.system.time_step());
        let q = &at.q;
        let delta = 0.05 * q.amax().max(1.0);
        let mut worst: f64 = 0.0;
        for j in 0..3 {
            let d = DVector::from_fn(q.len(), |i, _| crate::compose::sample_direction(j, i));
            let p = q + d * delta;
            for (q0, q1) in [(q, &p), (&p, q)] {
                let minus = sums::value(&backward, q0.as_slice(), q1.as_slice());
                let plus = sums::value(&self.system, q1.as_slice(), q0.as_slice());
                let (Ok(minus), Ok(plus)) = (minus, plus) else {
                    return f64::NAN;
                };
                worst = crate::compose::worse_defect(worst, minus, plus);
            }
        }
        worst
    }
}

/// `x ← q_k − x`: a configuration to the (−) side's backward increment `Δ = q_k − q_{k+1}`,
/// and an increment back to its configuration (the map is its own inverse).
pub(super) fn flip_backward(q0: &[f64], x: &mut [f64]) {
    x.iter_mut().zip(q0).for_each(|(x, q)| *x = q - *x);
}

/// `point = q_k − Δ`: the configuration `q_{k+1}` a (−) unknown `Δ` stands for.
pub(super) fn backward_point(q0: &[f64], delta: &[f64], point: &mut [f64]) {
    point
        .iter_mut()
        .zip(q0.iter().zip(delta))
        .for_each(|(p, (q, d))| *p = q - d);
}

/// `μ_{k+1} = μ_k` exactly for each declared translation (with forces, `μ_k` plus their
/// impulse on the orbit: the forced discrete Noether balance): the first component of each
/// orbit of `p1` takes the difference (see the [module documentation](super)).
pub(super) fn keep_momentum_maps<L: ElementLagrangian>(
    sys: &L,
    orbits: &[Vec<std::ops::Range<usize>>],
    q0: &[f64],
    p0: &[f64],
    q1: &[f64],
    p1: &mut DVector<f64>,
) {
    let forced = sys.forced();
    for orbit in orbits {
        let impulse = if forced {
            sums::impulse(sys, orbit, q0, q1)
        } else {
            0.0
        };
        let mu0: f64 = orbit.iter().flat_map(|r| r.clone()).map(|i| p0[i]).sum();
        let mu1: f64 = orbit.iter().flat_map(|r| r.clone()).map(|i| p1[i]).sum();
        if let Some(first) = orbit.first().map(|r| r.start) {
            p1[first] += mu0 + impulse - mu1;
        }
    }
}
