//! Ensembles: one system integrated from many initial states (or many parameter sets) in
//! parallel, each member with its own typed result.
//!
//! Members are independent integrations, so they are distributed over rayon's thread pool (one
//! linear-solver workspace per member, nothing shared but the read-only system). A failed member
//! is an `Err` at its position, carrying its step index, residual and the trajectory it computed;
//! the others are unaffected. Results come back in input order, and each is bit-for-bit what a
//! sequential integration of that member gives (the arithmetic of a member does not depend on the
//! thread it runs on). To run on a given number of threads, call inside
//! `rayon::ThreadPoolBuilder::new().num_threads(n).build()?.install(|| ..)`.

use rayon::prelude::*;

/// The thread pool the ensembles run on (e.g. `rayon::ThreadPoolBuilder` to fix the number of
/// threads).
pub use rayon;

use crate::error::IntegrationError;
use crate::integrate::{
    CanonicalTrajectory, ReducedIntegrator, RunSummary, StepRecord, Trajectory, UnreducedIntegrator,
};
use crate::state::{CanonicalState, ReducedState};
use crate::system::{Reduced, Side, Unreduced};
use nalgebra::SVector;

/// The result of one member of an ensemble: its trajectory, or the typed error with the part of
/// the trajectory computed before it.
pub type MemberResult<T> = Result<T, Box<IntegrationError<T>>>;

/// `f` applied to every item in parallel, results in input order: the ensemble over parameter
/// sets (build a system from each item and integrate it) or any other per-member computation.
///
/// ```
/// # use dirac_runtime::ensemble;
/// let squares = ensemble::map(&[1.0, 2.0, 3.0], |x| x * x);
/// assert_eq!(squares, vec![1.0, 4.0, 9.0]);
/// ```
pub fn map<T, R>(items: &[T], f: impl Fn(&T) -> R + Sync + Send) -> Vec<R>
where
    T: Sync,
    R: Send,
{
    items.par_iter().map(f).collect()
}

impl<L, D, const S: usize, const K: usize, const N: usize> ReducedIntegrator<L, D, S, K, N>
where
    D: Side,
    L: Reduced<D, S, K, N> + Sync,
{
    /// Integrates `steps` steps from each of `initials`, in parallel, keeping every state of
    /// every member (see [`ReducedIntegrator::integrate`]).
    pub fn integrate_ensemble(
        &self,
        initials: &[ReducedState<S, K>],
        steps: usize,
    ) -> Vec<MemberResult<Trajectory<S, K>>> {
        map(initials, |initial| self.collect(*initial, steps))
    }

    /// Runs `steps` steps from each of `initials` in parallel without storing trajectories: each
    /// member gets its own observer from `observer(member)`, which sees every state of that member
    /// (see [`ReducedIntegrator::run`]); the observer is returned with the member's summary, or
    /// with its typed error.
    #[allow(clippy::type_complexity)]
    pub fn run_ensemble<O>(
        &self,
        initials: &[ReducedState<S, K>],
        steps: usize,
        observer: impl Fn(usize) -> O + Sync + Send,
    ) -> Vec<(O, MemberResult<RunSummary<ReducedState<S, K>>>)>
    where
        O: FnMut(usize, &ReducedState<S, K>, Option<&StepRecord<SVector<f64, K>>>) + Send,
    {
        let members: Vec<(usize, ReducedState<S, K>)> =
            initials.iter().copied().enumerate().collect();
        map(&members, |(i, initial)| {
            let mut observe = observer(*i);
            let result = self.run(*initial, steps, &mut observe);
            (observe, result)
        })
    }
}

impl<L, const S: usize, const K: usize, const N: usize> UnreducedIntegrator<L, S, K, N>
where
    L: Unreduced<S, K, N> + Sync,
{
    /// Integrates `steps` steps from each of `initials`, in parallel (see
    /// [`UnreducedIntegrator::integrate`]).
    pub fn integrate_ensemble(
        &self,
        initials: &[CanonicalState<N>],
        steps: usize,
    ) -> Vec<MemberResult<CanonicalTrajectory<N>>> {
        map(initials, |initial| self.collect(*initial, steps))
    }
}
