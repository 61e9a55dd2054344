//! Adapted coordinates of a symmetry declared on the user's own coordinates.
//!
//! `#[reduced_lagrangian(coordinates(x[6]), translate(x))]` declares a common translation of the
//! user's coordinates. The compiler builds adapted coordinates — the trivialization
//! `Q = Σ × G` of §2.2.1 — in which that translation moves one group coordinate: for each
//! `translate(a, b, ...)`, the group coordinate is `g = a[0]` and every other component `c` of the
//! listed coordinates becomes the shape coordinate `r_c = c − a[0]`. The change of coordinates
//! is linear and unimodular,
//!
//! ```text
//! q_user = T q:    a[0] = g,   c = g + r_c,   other coordinates unchanged,
//! ```
//!
//! and the system's vectors (its `DiscreteLagrangian`, `Reduced`, `Unreduced` and
//! `ContinuousLagrangian` implementations, hence every integrator and state) are in `q`, with the
//! connection `B = 0`. Momenta transform as covectors, `p = Tᵀ p_user`, so that `⟨p, dq⟩` is
//! the same in both: the group momentum `p_g` is the sum of the momenta of every component the
//! translation moves, the total momentum, which the reduced equations conserve exactly
//! (`μ = p_g`, eq. (3.6)). Velocities transform like positions.
//!
//! [`AdaptedCoordinates`] is implemented by the macro for every system (the identity when no
//! `translate` is declared).

use nalgebra::SVector;

use crate::state::UnreducedState;

/// Adapted coordinates `q = T⁻¹ q_user` of a symmetry declared on the user's coordinates
/// (`translate`): the unimodular change of coordinates of the trivialization `Q = Σ × G`
/// (§2.2.1) described in the [module documentation](self). `#[reduced_lagrangian]` emits
/// straight-line implementations (sums and differences only); the identity when no `translate`
/// is declared.
pub trait AdaptedCoordinates<const N: usize> {
    /// `q = T⁻¹ q_user`: `g = a[0]`, `r_c = c − a[0]`, other coordinates unchanged. Also maps
    /// velocities (`v = T⁻¹ v_user`), since `T` is linear.
    fn to_adapted(q_user: &SVector<f64, N>) -> SVector<f64, N>;

    /// `q_user = T q`: `a[0] = g`, `c = g + r_c` (the same sum the compiled Lagrangian forms, so
    /// the user's function on `from_adapted(q)` and the generated code read the same values).
    fn from_adapted(q: &SVector<f64, N>) -> SVector<f64, N>;

    /// `p = Tᵀ p_user`: `p_{r_c} = p_user,c`, and `p_g = Σ p_user,c` over every component the
    /// translation moves (`a[0]` included), the total momentum: the momentum map `J = p_g`
    /// (§2.1.1) in user terms.
    fn momentum_to_adapted(p_user: &SVector<f64, N>) -> SVector<f64, N>;

    /// `p_user = T⁻ᵀ p`: `p_user,c = p_{r_c}` and `p_user,a[0] = p_g − Σ_{c ≠ a[0]} p_{r_c}`.
    fn momentum_from_adapted(p: &SVector<f64, N>) -> SVector<f64, N>;

    /// The canonical state `(q, p) = (T⁻¹ q_user, Tᵀ p_user)` in adapted coordinates, from the
    /// user's positions and momenta; `trivialize` it (eq. (3.6)) for a reduced initial state.
    fn adapted_state(q_user: &SVector<f64, N>, p_user: &SVector<f64, N>) -> UnreducedState<N> {
        UnreducedState {
            q: Self::to_adapted(q_user),
            p: Self::momentum_to_adapted(p_user),
        }
    }

    /// [`Self::adapted_state`] of a state given in the user's coordinates.
    fn to_adapted_state(user: &UnreducedState<N>) -> UnreducedState<N> {
        Self::adapted_state(&user.q, &user.p)
    }

    /// The user's positions and momenta `(T q, T⁻ᵀ p)` of an adapted canonical state (e.g. from
    /// `untrivialize`, eq. (3.7)), as a `UnreducedState` in the user's coordinates.
    fn from_adapted_state(state: &UnreducedState<N>) -> UnreducedState<N> {
        UnreducedState {
            q: Self::from_adapted(&state.q),
            p: Self::momentum_from_adapted(&state.p),
        }
    }
}
