//! The forms of the constrained steps ([`Form`]): where the unreduced and the reduced steps
//! differ, so that [`ConstrainedStepper`](super::ConstrainedStepper) writes the step once.

use nalgebra::SVector;

use super::{parts, Constrained};
use crate::newton::inf_norm;
use crate::state::{ReducedState, UnreducedState};
use crate::stepper::{predicted_increment, History};
use crate::system::{join, split, DiscreteLagrangian, Side};

/// The unreduced form of the equations. Of the constrained steps ([`Form`]): the state is the
/// canonical `(q, p)` ([`UnreducedState`]), the position step's unknowns `z = (q_{k+1}, λ_k)`.
/// Of the integrators on rotation groups ([`LieForm`](crate::lie::LieForm)): the state
/// `(q, p)` on the whole configuration space ([`LieStateOf`](crate::lie::LieStateOf)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct UnreducedForm;

mod sealed {
    pub trait Sealed {}
    impl Sealed for super::UnreducedForm {}
    impl<D: crate::system::Side> Sealed for D {}
}

/// Where the unreduced and the reduced constrained steps differ — the state, the guess of the
/// position step, the state that step leaves, and the state the projection gives — so that the
/// step itself, two Newton solves and their bookkeeping, is written once
/// ([`ConstrainedStepper`](super::ConstrainedStepper)), as [`Side`] does for the reduced (+) and (−) equations.
///
/// Sealed: the forms are [`UnreducedForm`], [`Plus`](crate::Plus) and [`Minus`](crate::Minus).
pub trait Form<const S: usize, const K: usize, const N: usize>:
    sealed::Sealed + Copy + Default + std::fmt::Debug + Send + Sync + 'static
{
    /// The state a step maps: [`UnreducedState`] or [`ReducedState`].
    type State: Copy + std::fmt::Debug + PartialEq + Send + Sync + 'static;
    /// What a step remembers for the next guess: `q_{k+1} − q_k`, or `(x_{k+1} − x_k, u)`.
    type Increment: Copy + std::fmt::Debug;
    /// The momentum the position step leaves: `p̃ ∈ R^N`, or `w̃ ∈ R^S`.
    type Momentum;
    /// Which equations, in words (what output's descriptions say).
    const EQUATIONS: &'static str;

    /// True when every component of `state` is finite.
    fn is_finite(state: &Self::State) -> bool;
    /// The momentum scale of the Newton tolerance: `‖p‖∞`, or `max(‖w‖∞, ‖μ‖∞)`.
    fn scale(state: &Self::State) -> f64;
    /// The configuration `q` of `state` (reduced: reconstructed, `(x, g)`), where `φ` is read.
    fn configuration<L: DiscreteLagrangian<S, K, N>>(
        sys: &L,
        state: &Self::State,
    ) -> SVector<f64, N>;
    /// `state` as an unreduced state `(q, p)` (reduced: by eq. (3.7)).
    fn unreduced<L: DiscreteLagrangian<S, K, N>>(sys: &L, state: &Self::State)
        -> UnreducedState<N>;
    /// The guess of the position step's configuration unknowns (the first `N` of `z`) for a
    /// step of size `h`: the configuration moved by the increment the last two steps (and their
    /// sizes) extrapolate.
    fn guess(state: &Self::State, history: &History<Self::Increment>, h: f64) -> SVector<f64, N>;
    /// The position step's configuration unknowns of a step that moves the configuration by
    /// `dq` (adaptive steps: a run's first guess, [`DiscreteLagrangian::adaptive_increment`]).
    fn moved<L: DiscreteLagrangian<S, K, N>>(
        sys: &L,
        state: &Self::State,
        dq: &SVector<f64, N>,
    ) -> SVector<f64, N>;
    /// The state the position step leaves at its solution `z` — the new configuration with the
    /// unprojected momentum ([`Constrained::constrained_momentum`]; reduced: `μ` moved by
    /// [`Constrained::constrained_impulse`] and `g` reconstructed) — and the step's increment.
    fn shake<L, const M: usize, const Z: usize>(
        sys: &L,
        state: &Self::State,
        z: &SVector<f64, Z>,
    ) -> (Self::State, Self::Increment)
    where
        L: Constrained<Self, S, K, N, M, Z>;
    /// The projection's velocity guess: the secant from `state` to `shake` over `h`.
    fn secant(state: &Self::State, shake: &Self::State, h: f64) -> SVector<f64, N>;
    /// The state `shake` with the projected momentum ([`Constrained::projected_momentum`]).
    fn projected(shake: &Self::State, momentum: &SVector<f64, N>) -> Self::State;
}

impl<const S: usize, const K: usize, const N: usize> Form<S, K, N> for UnreducedForm {
    type State = UnreducedState<N>;
    type Increment = SVector<f64, N>;
    type Momentum = SVector<f64, N>;
    const EQUATIONS: &'static str = "constrained, unreduced (position step, projection)";

    fn is_finite(state: &UnreducedState<N>) -> bool {
        state.is_finite()
    }

    fn scale(state: &UnreducedState<N>) -> f64 {
        inf_norm(&state.p)
    }

    fn configuration<L: DiscreteLagrangian<S, K, N>>(
        _sys: &L,
        state: &UnreducedState<N>,
    ) -> SVector<f64, N> {
        state.q
    }

    fn unreduced<L: DiscreteLagrangian<S, K, N>>(
        _sys: &L,
        state: &UnreducedState<N>,
    ) -> UnreducedState<N> {
        *state
    }

    fn guess(
        state: &UnreducedState<N>,
        history: &History<SVector<f64, N>>,
        h: f64,
    ) -> SVector<f64, N> {
        let dq = predicted_increment(history, h);
        dq.map_or(state.q, |d| state.q + d)
    }

    fn moved<L: DiscreteLagrangian<S, K, N>>(
        _sys: &L,
        state: &UnreducedState<N>,
        dq: &SVector<f64, N>,
    ) -> SVector<f64, N> {
        state.q + dq
    }

    fn shake<L, const M: usize, const Z: usize>(
        sys: &L,
        state: &UnreducedState<N>,
        z: &SVector<f64, Z>,
    ) -> (UnreducedState<N>, SVector<f64, N>)
    where
        L: Constrained<Self, S, K, N, M, Z>,
    {
        let (q1, _) = parts::<N, M, Z>(z);
        let shake = UnreducedState {
            q: q1,
            p: sys.constrained_momentum(state, z),
        };
        (shake, q1 - state.q)
    }

    fn secant(state: &UnreducedState<N>, shake: &UnreducedState<N>, h: f64) -> SVector<f64, N> {
        (shake.q - state.q) / h
    }

    fn projected(shake: &UnreducedState<N>, momentum: &SVector<f64, N>) -> UnreducedState<N> {
        UnreducedState {
            q: shake.q,
            p: *momentum,
        }
    }
}

impl<D: Side, const S: usize, const K: usize, const N: usize> Form<S, K, N> for D {
    type State = ReducedState<S, K>;
    type Increment = (SVector<f64, S>, SVector<f64, K>);
    type Momentum = SVector<f64, S>;
    const EQUATIONS: &'static str = match D::VARIANT {
        crate::system::Variant::Plus => "constrained, reduced (+) (position step, projection)",
        crate::system::Variant::Minus => "constrained, reduced (-) (position step, projection)",
    };

    fn is_finite(state: &ReducedState<S, K>) -> bool {
        state.is_finite()
    }

    fn scale(state: &ReducedState<S, K>) -> f64 {
        inf_norm(&state.w).max(inf_norm(&state.mu))
    }

    fn configuration<L: DiscreteLagrangian<S, K, N>>(
        sys: &L,
        state: &ReducedState<S, K>,
    ) -> SVector<f64, N> {
        sys.untrivialize(state).q
    }

    fn unreduced<L: DiscreteLagrangian<S, K, N>>(
        sys: &L,
        state: &ReducedState<S, K>,
    ) -> UnreducedState<N> {
        sys.untrivialize(state)
    }

    fn guess(
        state: &ReducedState<S, K>,
        history: &History<Self::Increment>,
        h: f64,
    ) -> SVector<f64, N> {
        let dx = predicted_increment(&history.map(|l| l.0), h);
        let du = predicted_increment(&history.map(|l| l.1), h);
        join::<S, K, N>(
            &dx.map_or(state.x, |d| state.x + d),
            &du.unwrap_or_else(SVector::zeros),
        )
    }

    /// `x + Δx` and the group unknown `u` with `D::group_increment(u) = Δg − B Δx`.
    fn moved<L: DiscreteLagrangian<S, K, N>>(
        sys: &L,
        state: &ReducedState<S, K>,
        dq: &SVector<f64, N>,
    ) -> SVector<f64, N> {
        let (dx, dg) = split::<S, K, N>(dq);
        let x1 = state.x + dx;
        join::<S, K, N>(&x1, &D::group_increment(dg - sys.h_d0(&state.x, &x1)))
    }

    /// `g_{k+1} = g_k + D::group_increment(u) + B (x_{k+1} − x_k)` ([`Side::group_increment`]).
    fn shake<L, const M: usize, const Z: usize>(
        sys: &L,
        state: &ReducedState<S, K>,
        z: &SVector<f64, Z>,
    ) -> (ReducedState<S, K>, Self::Increment)
    where
        L: Constrained<Self, S, K, N, M, Z>,
    {
        let (head, _) = parts::<N, M, Z>(z);
        let (x1, u) = split::<S, K, N>(&head);
        let shake = ReducedState {
            x: x1,
            w: sys.constrained_momentum(state, z),
            mu: if L::CONSTRAINED_GROUP_FORCED {
                state.mu + sys.constrained_impulse(state, z)
            } else {
                state.mu
            },
            g: state.g + D::group_increment(u) + sys.h_d0(&state.x, &x1),
        };
        (shake, (x1 - state.x, u))
    }

    /// The secant in the configuration `(x, g)`.
    fn secant(state: &ReducedState<S, K>, shake: &ReducedState<S, K>, h: f64) -> SVector<f64, N> {
        join::<S, K, N>(&((shake.x - state.x) / h), &((shake.g - state.g) / h))
    }

    fn projected(shake: &ReducedState<S, K>, momentum: &SVector<f64, N>) -> ReducedState<S, K> {
        let (w, mu) = split::<S, K, N>(momentum);
        ReducedState {
            x: shake.x,
            w,
            mu,
            g: shake.g,
        }
    }
}
