//! The runs of systems on vector spaces collected into arrays: what `System.run` and
//! `System.ensemble` hand the integrator their request chose to (`dirac_jit::run`: [`Collect`],
//! [`Ensemble`]), how each integrator of the family — unreduced, reduced on either side, their
//! compositions, the constrained ones — flattens its trajectory for NumPy ([`Flatten`]), and the
//! benchmark's bare run.

use std::marker::PhantomData;
use std::sync::atomic::AtomicBool;

use dirac_jit::run::{Finish, Job};
use dirac_jit::{JitConstrained, JitSystem, RunRequest};
use dirac_runtime::nalgebra::SVector;
use dirac_runtime::{
    continuous_energies, ComposedTrajectory, Composition, ConstrainedIntegrator,
    ConstrainedTrajectory, DiscreteLagrangian, Drive, Equations, Form, GaussIntegrator, Minus,
    Plus, ReducedConstrainedIntegrator, ReducedGaussIntegrator, ReducedIntegrator, ReducedState,
    SelfAdjoint, Side, StepStats, System, Trajectory, UnreducedIntegrator, UnreducedState,
    UnreducedTrajectory,
};

use crate::calls::until;
use crate::ensemble::Member;
use crate::results::{finish, reduced_flat, unreduced_flat, with_momenta, Energies, Flat};

/// A run collected into arrays (every class's `run`), with the continuous energies of its
/// states when `energies` is set; it ends after the step in progress once `cancel` is set. `F`:
/// what the class flattens a trajectory to.
pub(crate) struct Collect<'a, F> {
    pub(crate) cancel: &'a AtomicBool,
    pub(crate) energies: bool,
    pub(crate) flat: PhantomData<F>,
}

/// An ensemble collected into arrays (every class's `ensemble`), one member per start, on all
/// cores.
pub(crate) struct Ensemble<'a, F> {
    pub(crate) cancel: &'a AtomicBool,
    pub(crate) flat: PhantomData<F>,
}

impl<'a, F> Collect<'a, F> {
    pub(crate) fn new(cancel: &'a AtomicBool, energies: bool) -> Self {
        Collect {
            cancel,
            energies,
            flat: PhantomData,
        }
    }
}

impl<'a, F> Ensemble<'a, F> {
    pub(crate) fn new(cancel: &'a AtomicBool) -> Self {
        Ensemble {
            cancel,
            flat: PhantomData,
        }
    }
}

impl<F> Job for Collect<'_, F> {
    /// The trajectory flattened, or the failed step's error with the states before it; `Err`
    /// for a run that could not start.
    type Output = Result<Member<F>, String>;
}

impl<F> Job for Ensemble<'_, F> {
    /// Each member's outcome.
    type Output = Result<Vec<Member<F>>, String>;
}

impl<I: Flatten> Finish<I> for Collect<'_, I::Flat> {
    fn finish(self, integ: I, starts: Vec<I::State>, r: &RunRequest) -> Self::Output {
        let start = starts.into_iter().next().ok_or("a run needs its start")?;
        let run = dirac_jit::span!(integ.run(start), r, stop(until(self.cancel)) => collect);
        Ok(match finish(run, |t| integ.flat(t)) {
            Ok(mut flat) if self.energies => {
                integ.energies(&mut flat, r.equations);
                Ok(flat)
            }
            outcome => outcome,
        })
    }
}

impl<I: Flatten> Finish<I> for Ensemble<'_, I::Flat>
where
    I::Trajectory: Send,
{
    fn finish(self, integ: I, starts: Vec<I::State>, r: &RunRequest) -> Self::Output {
        let members =
            dirac_jit::span!(integ.ensemble(&starts), r, stop(until(self.cancel)) => collect);
        Ok(members
            .into_iter()
            .map(|m| finish(m, |t| integ.flat(t)))
            .collect())
    }
}

/// What a collected run has of one outcome: `dirac_jit::run`'s, its error as text.
pub(crate) fn collected<T>(run: Result<Result<T, String>, dirac_jit::Error>) -> Result<T, String> {
    run.map_err(|e| e.to_string())?
}

/// An integrator whose runs Python returns as arrays: its trajectory flattened (`Flat`, each
/// class's), and, where the system has them, the continuous energies of its states.
pub(crate) trait Flatten: Drive + Sync {
    /// What a trajectory is flattened to.
    type Flat;

    /// The states, times and statistics of a run, flattened.
    fn flat_states(&self, states: &[Self::State], times: &[f64], stats: &[StepStats])
        -> Self::Flat;

    /// A run's trajectory, flattened.
    fn flat(&self, t: &Self::Trajectory) -> Self::Flat;

    /// Sets the continuous energies of a run flattened by [`Self::flat`] (a system without
    /// constraints, its Lagrangian continuous); the default: none.
    fn energies(&self, flat: &mut Self::Flat, equations: Equations) {
        let _ = (flat, equations);
    }
}

/// A composition's states are its base integrator's.
impl<I> Flatten for Composition<I>
where
    I: Flatten + SelfAdjoint,
    Self: Drive<State = I::State, Trajectory = ComposedTrajectory<I::State>> + Sync,
{
    type Flat = I::Flat;

    fn flat_states(&self, states: &[Self::State], times: &[f64], stats: &[StepStats]) -> I::Flat {
        self.base().flat_states(states, times, stats)
    }

    fn flat(&self, t: &ComposedTrajectory<I::State>) -> I::Flat {
        self.flat_states(&t.states, &t.times, &t.stats)
    }

    fn energies(&self, flat: &mut I::Flat, equations: Equations) {
        self.base().energies(flat, equations)
    }
}

/// The integrators of a system without constraints — second-order and Gauss–Legendre,
/// unreduced and reduced on either side — flattened by their form, with the continuous energies
/// of their states.
macro_rules! flat_run {
    ($(
        $integrator:ident $(<$side:ident>)? => $state:ty, $trajectory:ty,
            |$sys:ident, $parts:ident| $flat:expr;
    )*) => {$(
        impl<$($side: Side,)? const S: usize, const K: usize, const N: usize> Flatten
            for $integrator<JitSystem<S, K, N>, $($side,)? S, K, N>
        where
            Self: Drive<State = $state, Trajectory = $trajectory> + Sync,
            JitSystem<S, K, N>: $(dirac_runtime::Reduced<$side, S, K, N> +)? Sized,
        {
            type Flat = Flat;

            fn flat_states(
                &self,
                states: &[Self::State],
                times: &[f64],
                stats: &[StepStats],
            ) -> Flat {
                let ($sys, $parts) = (self.system(), (states, times, stats));
                $flat
            }

            fn flat(&self, t: &$trajectory) -> Flat {
                self.flat_states(&t.states, &t.times, &t.stats)
            }

            fn energies(&self, flat: &mut Flat, equations: Equations) {
                flat.energies = Some(energies(self.system(), flat, equations));
            }
        }
    )*};
}

flat_run! {
    UnreducedIntegrator => UnreducedState<N>, UnreducedTrajectory<N>,
        |_sys, parts| unreduced_flat(parts);
    GaussIntegrator => UnreducedState<N>, UnreducedTrajectory<N>,
        |_sys, parts| unreduced_flat(parts);
    ReducedIntegrator<D> => ReducedState<S, K>, Trajectory<S, K>,
        |sys, parts| with_momenta(sys, reduced_flat(parts));
    ReducedGaussIntegrator<D> => ReducedState<S, K>, Trajectory<S, K>,
        |sys, parts| with_momenta(sys, reduced_flat(parts));
}

/// The constrained integrators: their states flattened as the unconstrained ones', and each
/// step's multipliers `λ_k` and constraint residual.
macro_rules! constrained_flat_run {
    ($($integrator:ident $(<$side:ident>)? => $state:ty, $flat:ident;)*) => {$(
        impl<const S: usize, const K: usize, const N: usize, const M: usize, const Z: usize>
            Flatten for $integrator<JitConstrained<S, K, N, M, Z>, $($side,)? S, K, N, M, Z>
        {
            type Flat = Flat;

            fn flat_states(
                &self,
                states: &[Self::State],
                times: &[f64],
                stats: &[StepStats],
            ) -> Flat {
                with_momenta(self.system(), $flat((states, times, stats)))
            }

            fn flat(&self, t: &ConstrainedTrajectory<$state, M>) -> Flat {
                let mut flat = self.flat_states(&t.states, &t.times, &t.stats);
                flat.multipliers = Some((
                    M,
                    t.records.iter().flat_map(|s| s.lambda.iter().copied()).collect(),
                    t.records.iter().map(|s| s.constraint_residual).collect(),
                ));
                flat
            }
        }
    )*};
}

constrained_flat_run! {
    ConstrainedIntegrator => UnreducedState<N>, unreduced_flat;
    ReducedConstrainedIntegrator<Plus> => ReducedState<S, K>, reduced_flat;
    ReducedConstrainedIntegrator<Minus> => ReducedState<S, K>, reduced_flat;
}

/// The continuous energies of the states of `flat` (`ContinuousLagrangian`: the inverse
/// Legendre map at each node, the midpoint rule between), reduced states mapped back to
/// `(q, p)` by eq. (3.7).
fn energies<const S: usize, const K: usize, const N: usize>(
    sys: &JitSystem<S, K, N>,
    flat: &Flat,
    method: Equations,
) -> Energies {
    let column = |name: &str| {
        flat.parts
            .iter()
            .find(|(n, _, _)| *n == name)
            .map_or(&[][..], |(_, _, data)| data.as_slice())
    };
    let rows = flat.t.len();
    let states: Vec<UnreducedState<N>> = (0..rows)
        .map(|k| match method.form {
            Form::Unreduced => UnreducedState {
                q: SVector::from_column_slice(&column("q")[k * N..(k + 1) * N]),
                p: SVector::from_column_slice(&column("p")[k * N..(k + 1) * N]),
            },
            Form::Reduced => sys.untrivialize(&ReducedState {
                x: SVector::from_column_slice(&column("x")[k * S..(k + 1) * S]),
                w: SVector::from_column_slice(&column("w")[k * S..(k + 1) * S]),
                mu: SVector::from_column_slice(&column("mu")[k * K..(k + 1) * K]),
                g: SVector::from_column_slice(&column("g")[k * K..(k + 1) * K]),
            }),
        })
        .collect();
    let trajectory = UnreducedTrajectory {
        h: sys.time_step(),
        states,
        times: flat.t.clone(),
        // Python's runs take the system's own step.
        step_sizes: vec![sys.time_step(); rows.saturating_sub(1)],
        stats: Vec::new(),
    };
    continuous_energies(sys, &trajectory)
        .map(|e| (e.nodes, e.midpoints))
        .map_err(|e| e.to_string())
}

/// The benchmark's bare run: the seconds of the run alone (collected, no arrays), timed around
/// the integrator its request chose.
pub(crate) struct Timed;

impl Job for Timed {
    type Output = Result<f64, String>;
}

impl<I: Drive> Finish<I> for Timed {
    fn finish(self, integ: I, starts: Vec<I::State>, r: &RunRequest) -> Self::Output {
        let start = starts.into_iter().next().ok_or("a run needs its start")?;
        let t = std::time::Instant::now();
        let traj = integ
            .run(start)
            .steps(r.steps)
            .collect()
            .map_err(|e| e.to_string())?;
        let elapsed = t.elapsed().as_secs_f64();
        drop(traj);
        Ok(elapsed)
    }
}
