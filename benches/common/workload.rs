//! Realistic inputs: states on the paper's trajectories, each with the Newton guess that
//! `ReducedIntegrator::integrate` itself would start from, and the same physical state for the
//! unreduced stepper.

use dirac::paper::{ChargedParticle, DoubleSphericalPendulum, DSP_STEPS};
use dirac::prelude::*;
use dirac::runtime::reduced::reduced_guess;
use dirac::runtime::stepper::History;
use dirac::runtime::system::join;
use dirac::runtime::unreduced::canonical_guess;

/// One step of a paper run, ready to be taken again.
#[derive(Clone, Copy, Debug)]
pub struct StepCase<const S: usize, const K: usize, const N: usize> {
    /// The step index.
    pub k: usize,
    /// `(x_k, w_k, μ_k, g_k)` on the trajectory.
    pub state: ReducedState<S, K>,
    /// The integrator's guess for `z = (x_{k+1}, g_k^+)`: `integrate::reduced_guess`.
    pub guess: SVector<f64, N>,
    /// The solution the generated stepper found from `guess`.
    pub solution: SVector<f64, N>,
    /// Newton corrections the generated stepper took from `guess` on its default path.
    pub iterations: usize,
    /// The same physical state for the unreduced stepper, `(q_k, p_k)` by eq. (3.7).
    pub canonical: UnreducedState<N>,
    /// The unreduced integrator's guess, `integrate::canonical_guess`.
    pub canonical_guess: SVector<f64, N>,
}

/// A system, its paper run, and the steps of that run to take again.
pub struct Workload<L, const S: usize, const K: usize, const N: usize> {
    pub name: &'static str,
    pub system: L,
    pub trajectory: Trajectory<S, K>,
    pub cases: Vec<StepCase<S, K, N>>,
}

impl<L, const S: usize, const K: usize, const N: usize> Workload<L, S, K, N>
where
    L: Reduced<Plus, S, K, N> + Copy,
{
    /// Integrates `steps` steps from `initial` with the generated (+) stepper and keeps every
    /// `stride`-th step `k ≥ 1` (step 0 has no previous point to extrapolate from).
    pub fn new(
        name: &'static str,
        system: L,
        initial: ReducedState<S, K>,
        steps: usize,
        stride: usize,
    ) -> Self {
        let trajectory = ReducedIntegrator::plus(system, NewtonOptions::default())
            .run(initial)
            .steps(steps)
            .collect()
            .expect("the paper's run succeeds");
        let h = system.time_step();
        let config = |k: usize| {
            let s = &trajectory.states[k];
            join::<S, K, N>(&s.x, &s.g)
        };
        // Step `k − back`, as the integrator remembers it: its shape increment and group unknown.
        let step = |k: usize, back: usize| {
            (k >= back).then(|| {
                let j = k - back;
                (
                    trajectory.states[j + 1].x - trajectory.states[j].x,
                    trajectory.group_unknowns[j],
                )
            })
        };
        let cases = (1..steps)
            .step_by(stride)
            .map(|k| {
                let state = trajectory.states[k];
                let next = &trajectory.states[k + 1];
                StepCase {
                    k,
                    state,
                    guess: reduced_guess::<S, K, N>(
                        &state.x,
                        &History {
                            last: step(k, 1).map(|d| (d, h)),
                            before: step(k, 2).map(|d| (d, h)),
                        },
                        h,
                    ),
                    solution: join::<S, K, N>(&next.x, &trajectory.group_unknowns[k]),
                    iterations: trajectory.stats[k].iterations,
                    canonical: system.untrivialize(&state),
                    canonical_guess: canonical_guess(
                        &config(k),
                        &History {
                            last: (k >= 1).then(|| (config(k) - config(k - 1), h)),
                            before: (k >= 2).then(|| (config(k - 1) - config(k - 2), h)),
                        },
                        h,
                    ),
                }
            })
            .collect();
        Self {
            name,
            system,
            trajectory,
            cases,
        }
    }

    /// Mean Newton corrections per step over the cases.
    pub fn mean_iterations(&self) -> f64 {
        self.cases.iter().map(|c| c.iterations as f64).sum::<f64>() / self.cases.len() as f64
    }

    /// `n` cases spread evenly over the run: the points at which single evaluations are timed.
    pub fn spread(&self, n: usize) -> Vec<StepCase<S, K, N>> {
        let n = n.min(self.cases.len());
        (0..n)
            .map(|i| self.cases[i * self.cases.len() / n])
            .collect()
    }
}

/// §7.1: the charged particle, `ChargedParticle::paper(100)` (`h = 0.2`), every step of the run.
pub fn charged_particle() -> Workload<ChargedParticle, 3, 1, 4> {
    Workload::new(
        "charged particle (§7.1, N = 100)",
        ChargedParticle::paper(100),
        ChargedParticle::paper_initial_state(),
        100,
        1,
    )
}

/// Every how many steps of the double spherical pendulum's run a case is kept.
pub const DSP_STRIDE: usize = 10;

/// §7.2: the double spherical pendulum, `DoubleSphericalPendulum::paper()` (`h = 0.01`,
/// `N = 10⁴`), every [`DSP_STRIDE`]-th step of the run.
pub fn double_spherical_pendulum() -> Workload<DoubleSphericalPendulum, 3, 1, 4> {
    Workload::new(
        "double spherical pendulum (§7.2, N = 10⁴)",
        DoubleSphericalPendulum::paper(),
        DoubleSphericalPendulum::paper_initial_state(),
        DSP_STEPS,
        DSP_STRIDE,
    )
}
