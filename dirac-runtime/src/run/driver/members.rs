//! Ensembles: many initial states of one integrator ([`super::Drive::ensemble`]) or one
//! integrator per parameter set ([`parameters`]), configured by the options of a run and run in
//! parallel.

use std::marker::PhantomData;

use super::*;
use crate::ensemble;

/// The members of an [`Ensemble`]: where each member's integrator and initial state come from.
pub trait Members: Sync {
    /// The integrator type of every member.
    type Integrator: Stepper;

    /// The number of members.
    fn len(&self) -> usize;

    /// Whether there is no member.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Calls `f` with member `i`'s integrator and initial state.
    fn with_member<R>(
        &self,
        i: usize,
        f: impl FnOnce(&Self::Integrator, <Self::Integrator as Stepper>::State) -> R,
    ) -> R;
}

/// Members that share one integrator and differ in their initial states ([`Drive::ensemble`]).
pub struct States<'a, I: Stepper + ?Sized> {
    pub(super) integrator: &'a I,
    pub(super) initials: &'a [I::State],
}

impl<I: Stepper + Sync> Members for States<'_, I> {
    type Integrator = I;

    fn len(&self) -> usize {
        self.initials.len()
    }

    fn with_member<R>(&self, i: usize, f: impl FnOnce(&I, I::State) -> R) -> R {
        f(self.integrator, self.initials[i].clone())
    }
}

/// Members built from parameter sets ([`parameters`]): each item gives an integrator and its
/// initial state.
pub struct Parameters<'a, T, I, F> {
    items: &'a [T],
    member: F,
    integrator: PhantomData<fn() -> I>,
}

impl<T, I, F> Members for Parameters<'_, T, I, F>
where
    T: Sync,
    I: Stepper,
    F: Fn(&T) -> (I, I::State) + Sync,
{
    type Integrator = I;

    fn len(&self) -> usize {
        self.items.len()
    }

    fn with_member<R>(&self, i: usize, f: impl FnOnce(&I, I::State) -> R) -> R {
        let (integrator, initial) = (self.member)(&self.items[i]);
        f(&integrator, initial)
    }
}

/// An ensemble over parameter sets: for each item of `items`, `member(item)` builds an
/// integrator (a system with those parameters) and its initial state. Configured like a [`Run`]
/// and finished with [`Ensemble::collect`] or [`Ensemble::stream`].
pub fn parameters<T, I, F>(items: &[T], member: F) -> Ensemble<'_, Parameters<'_, T, I, F>>
where
    T: Sync,
    I: Stepper,
    F: Fn(&T) -> (I, I::State) + Sync,
{
    Ensemble::of(Parameters {
        items,
        member,
        integrator: PhantomData,
    })
}

/// Many runs in parallel (rayon's thread pool, one workspace per member), configured by the
/// options of a [`Run`] that apply to every member. Results come in input order; each is bit
/// for bit what the member's own run gives, and a failed member is an `Err` at its position that
/// leaves the others unaffected.
#[must_use = "an ensemble does nothing until it is finished with `.collect()` or `.stream(..)`"]
pub struct Ensemble<'a, M, P = Fixed, X = Never> {
    members: M,
    span: Span,
    step_size: P,
    stop: X,
    threads: Option<usize>,
    lifetime: PhantomData<&'a ()>,
}

type StateOf<M> = <<M as Members>::Integrator as Stepper>::State;
type TrajectoryOf<M> = <<M as Members>::Integrator as Stepper>::Trajectory;
type RecordOf<M> = <<M as Members>::Integrator as Stepper>::Record;

impl<M: Members> Ensemble<'_, M> {
    pub(super) fn of(members: M) -> Self {
        Ensemble {
            members,
            span: Span::default(),
            step_size: Fixed,
            stop: Never,
            threads: None,
            lifetime: PhantomData,
        }
    }
}

impl<'a, M, P, X> Ensemble<'a, M, P, X>
where
    M: Members,
    P: StepSize<StateOf<M>> + Clone + Sync,
    X: StopCondition<StateOf<M>> + Clone + Sync,
{
    span_options!();

    /// On `n` threads (a pool of its own) instead of rayon's global pool.
    pub fn threads(mut self, n: usize) -> Self {
        self.threads = Some(n);
        self
    }

    /// The step sizes of every member ([`Run::step_size`]; each member gets a clone).
    pub fn step_size<P2>(self, policy: P2) -> Ensemble<'a, M, P2, X>
    where
        P2: StepSize<StateOf<M>> + Clone + Sync,
    {
        Ensemble {
            members: self.members,
            span: self.span,
            step_size: policy,
            stop: self.stop,
            threads: self.threads,
            lifetime: PhantomData,
        }
    }

    /// The step sizes of every member computed as each run goes ([`Run::schedule`]; each member
    /// gets a clone of the closure).
    pub fn schedule<F>(self, schedule: F) -> Ensemble<'a, M, Schedule<F>, X>
    where
        F: FnMut(usize, f64, &StateOf<M>) -> f64 + Clone + Sync,
    {
        self.step_size(Schedule(schedule))
    }

    /// The stop condition of every member ([`Run::stop`]; each member gets a clone).
    pub fn stop<X2>(self, stop: X2) -> Ensemble<'a, M, P, X2>
    where
        X2: FnMut(usize, f64, &StateOf<M>) -> bool + Clone + Sync,
    {
        Ensemble {
            members: self.members,
            span: self.span,
            step_size: self.step_size,
            stop,
            threads: self.threads,
            lifetime: PhantomData,
        }
    }

    /// `f(i)` for every member index, in parallel, results in order, on the configured pool.
    fn map<R: Send>(&self, f: impl Fn(usize) -> R + Sync + Send) -> Vec<R> {
        let indices: Vec<usize> = (0..self.members.len()).collect();
        let run = || ensemble::map(&indices, |&i| f(i));
        match self.threads {
            // A pool that cannot be built (no threads available) leaves the global one.
            Some(n) => match rayon::ThreadPoolBuilder::new().num_threads(n).build() {
                Ok(pool) => pool.install(run),
                Err(_) => run(),
            },
            None => run(),
        }
    }

    /// Runs every member and keeps its trajectory ([`Run::collect`]).
    pub fn collect(self) -> Vec<MemberResult<TrajectoryOf<M>>>
    where
        TrajectoryOf<M>: Send,
    {
        self.map(|i| {
            self.members.with_member(i, |integrator, initial| {
                self.member_run(integrator, initial, Unobserved).collect()
            })
        })
    }

    /// Runs every member without keeping states ([`Run::stream`]): member `i` gets its own
    /// observer from `observer(i)`, which is returned with the member's summary or typed error.
    #[allow(clippy::type_complexity)]
    pub fn stream<O>(
        self,
        observer: impl Fn(usize) -> O + Sync + Send,
    ) -> Vec<(O, RunResult<StateOf<M>>)>
    where
        O: FnMut(usize, f64, &StateOf<M>, Option<&RecordOf<M>>) + Send,
    {
        self.map(|i| {
            let mut observe = observer(i);
            let result = self.members.with_member(i, |integrator, initial| {
                self.member_run(integrator, initial, &mut observe).stream()
            });
            (observe, result)
        })
    }

    /// The run of one member from its `integrator` and `initial` state: this ensemble's span,
    /// a clone of its step sizes and stop condition, no controls, and `observer`.
    fn member_run<'r, O>(
        &self,
        integrator: &'r M::Integrator,
        initial: StateOf<M>,
        observer: O,
    ) -> Run<'r, M::Integrator, P, NoControls, X, O> {
        Run {
            integrator,
            initial,
            span: self.span,
            step_size: self.step_size.clone(),
            controls: NoControls,
            stop: self.stop.clone(),
            observer,
        }
    }
}
