//! The traits that `#[reduced_lagrangian]` implements for the type it emits.
//!
//! Dimensions are const generics: `S` shape coordinates, `K` group coordinates and `N = S + K`
//! configuration coordinates, ordered `q = (x, g)` (the trivialization `Q = Σ × G` of §2.2.1).

use nalgebra::{SMatrix, SVector};

use crate::linalg::LinearSolver;
use crate::model::System;
use crate::state::{ReducedState, UnreducedState};

/// A discrete Lagrangian `L_d : Q × Q → R` invariant under translation of the group coordinates,
/// together with a linear discrete connection `ω_d(q0, q1) = (g1 − g0) − B (x1 − x0)`: the flat
/// family of the one system model ([`System`]: parameters, time step, controls, time coordinate,
/// domain and names are declared there).
///
/// In the paper's notation (§2.2.1) this connection has `h_d((x0, g0), x1) = g0 + B (x1 − x0)`,
/// so `h_d^0(x0, x1) = B (x1 − x0)`, `h_{d,Σ} = B`, `h*_{d,Σ} = Bᵀ` and `h_{d,Q}((x0, 0)) = −B x0`
/// (eqs. (2.5)–(2.6)).
pub trait DiscreteLagrangian<const S: usize, const K: usize, const N: usize>: System {
    /// Names of the shape coordinates `x`, in the order of the configuration vector.
    const SHAPE: [&'static str; S];
    /// Names of the group coordinates `g`, which follow the shape coordinates in `q`.
    const GROUP: [&'static str; K];

    /// The names of the shape coordinates: [`Self::SHAPE`] for a system compiled in; a system
    /// given at run time (whose constants cannot know its names) says them here. What output
    /// (column names, metadata) reads.
    fn shape_names(&self) -> Vec<&str> {
        Self::SHAPE.to_vec()
    }

    /// The names of the group coordinates: [`Self::GROUP`], or a run-time system's own.
    fn group_names(&self) -> Vec<&str> {
        Self::GROUP.to_vec()
    }

    /// Whether the system declares forces (`force = ...` in the attribute): its steps solve the
    /// forced discrete Lagrange–Dirac equations `p_k = −D1 L_d − f_d^−`,
    /// `p_{k+1} = D2 L_d + f_d^+`, and its energy is not conserved.
    const FORCED: bool = false;

    /// Adaptive steps: the step monitor `g(x) > 0` at the shape `x` (`dt = g dτ`); `None` for a
    /// system stepped in physical time. The time coordinate is [`System::time_index`], among
    /// the group coordinates.
    fn monitor(&self, x: &SVector<f64, S>) -> Option<f64> {
        let _ = x;
        None
    }

    /// Adaptive steps: Newton's guess for the increment `q_{k+1} − q_k` of a run's first step of
    /// fictitious size `h` from `(q, p)` (`h` times the velocity in fictitious time, see
    /// [`crate::adaptive::first_increment`]); `None` for a system stepped in physical time, whose
    /// first guess is no motion.
    fn adaptive_increment(
        &self,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
        h: f64,
    ) -> Option<SVector<f64, N>> {
        let _ = (q, p, h);
        None
    }

    /// Adaptive steps: how far the state `(q, p)` is from the energy level set `p_t = −E(q, p)`
    /// on which the transformed system's solutions are the physical ones (see
    /// [`crate::adaptive::level_set_defect`]): `(p_t + E, scale)`, the defect and the size of the
    /// terms `E` is formed from, which the integrators' input checks compare at
    /// [`crate::adaptive::LEVEL_SET_TOLERANCE`]. `None` for a system stepped in physical time.
    fn level_set_defect(&self, q: &SVector<f64, N>, p: &SVector<f64, N>) -> Option<(f64, f64)> {
        let _ = (q, p);
        None
    }

    /// `L_d(q0, q1)`, evaluated by the user's own function body.
    fn lagrangian(&self, q0: &SVector<f64, N>, q1: &SVector<f64, N>) -> f64;

    /// The connection matrix `B` (`K × S`); zero unless the attribute declares one.
    fn connection(&self) -> SMatrix<f64, K, S>;

    /// Right trivialization of `T*Q`, eq. (3.6): `(q, p) ↦ (q, w, μ)` with
    /// `w = p_x + h*_{d,Σ}(p_g) = p_x + Bᵀ p_g` and `μ = J(q, p) = p_g` (Lemma 2.2).
    fn trivialize(&self, state: &UnreducedState<N>) -> ReducedState<S, K> {
        let (x, g) = split::<S, K, N>(&state.q);
        let (p_x, p_g) = split::<S, K, N>(&state.p);
        ReducedState {
            x,
            w: p_x + self.connection().transpose() * p_g,
            mu: p_g,
            g,
        }
    }

    /// Inverse trivialization, eq. (3.7): `p = (w − h*_{d,Σ}(μ), μ) = (w − Bᵀ μ, μ)`.
    fn untrivialize(&self, state: &ReducedState<S, K>) -> UnreducedState<N> {
        let p_x = state.w - self.connection().transpose() * state.mu;
        UnreducedState {
            q: join::<S, K, N>(&state.x, &state.g),
            p: join::<S, K, N>(&p_x, &state.mu),
        }
    }

    /// The momentum map of the translation action, `J(q, p) = p_g` (§2.1.1, Lemma 2.2).
    fn momentum_map(&self, state: &UnreducedState<N>) -> SVector<f64, K> {
        split::<S, K, N>(&state.p).1
    }

    /// The (+) discrete generalized energy, eq. (5.7):
    /// `E_{d+}(q0, q0^+, q1, p1) = L_d(q0, q0^+) + ⟨p1, q1 − q0^+⟩`.
    fn generalized_energy_plus(
        &self,
        q0: &SVector<f64, N>,
        q0_plus: &SVector<f64, N>,
        q1: &SVector<f64, N>,
        p1: &SVector<f64, N>,
    ) -> f64 {
        self.lagrangian(q0, q0_plus) + p1.dot(&(q1 - q0_plus))
    }

    /// The discrete connection `ω_d(q0, q1) = (g1 − g0) − B (x1 − x0)` (Definition 2.1).
    fn discrete_connection(&self, q0: &SVector<f64, N>, q1: &SVector<f64, N>) -> SVector<f64, K> {
        let (x0, g0) = split::<S, K, N>(q0);
        let (x1, g1) = split::<S, K, N>(q1);
        (g1 - g0) - self.h_d0(&x0, &x1)
    }

    /// `h_d^0(x0, x1) = B (x1 − x0)`, eq. (2.5): the group shift the connection assigns to a shape
    /// step. The one place the runtime forms `B (x1 − x0)` (reconstruction, diagnostics, `ω_d`).
    fn h_d0(&self, x0: &SVector<f64, S>, x1: &SVector<f64, S>) -> SVector<f64, K> {
        self.connection() * (x1 - x0)
    }
}

/// Which reduced equations, as a type: [`Plus`] (eq. (4.6)) or [`Minus`] (eq. (4.8) with the
/// signs of Definition 2.8). [`Reduced`] is parameterised by it, so each idea of a reduced stepper
/// — Newton on the residual, the momentum update, the elimination of the group unknowns,
/// reconstruction — is written once and statically dispatched; the two sides differ only where
/// the paper's equations differ, which is what this trait states.
///
/// Sealed: the paper has exactly two sides.
pub trait Side:
    sealed::Sealed + Copy + Default + std::fmt::Debug + PartialEq + Eq + Send + Sync + 'static
{
    /// The same side as a value, recorded in [`crate::Trajectory::variant`].
    const VARIANT: Variant;

    /// The increment `g_{k+1} − g_k − h_d^0(x_k, x_{k+1})` that the solved group unknown `u` gives
    /// in reconstruction: `u = g_k^+` for (+) (last line of eq. (4.6)), `−u` with
    /// `u = g_{k+1}^−` for (−) (the reconstruction line in [`Minus`]).
    fn group_increment<const K: usize>(u: SVector<f64, K>) -> SVector<f64, K>;
}

mod sealed {
    pub trait Sealed {}
    impl Sealed for super::Plus {}
    impl Sealed for super::Minus {}
}

/// Which reduced equations a trajectory was computed with: the value-level name of a [`Side`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Variant {
    /// Eq. (4.6): unknowns `(x_{k+1}, g_k^+)` (see [`Plus`]).
    #[default]
    Plus,
    /// Eq. (4.8) with the signs of Definition 2.8: unknowns `(x_{k+1}, g_{k+1}^−)` (see
    /// [`Minus`]).
    Minus,
}

/// The form of the equations a run solves, in the paper's words: the unreduced discrete
/// Lagrange–Dirac equations on `T*Q` (Definitions 2.7 and 2.8: [`Unreduced`],
/// [`crate::LieIntegrator`], [`crate::ElementIntegrator`]) or the reduced discrete
/// Lagrange–Poincaré–Dirac equations (eqs. (4.6) and (4.8): [`Reduced`],
/// [`crate::ReducedLieIntegrator`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Form {
    /// On `T*Q`, the group coordinates carried along.
    Unreduced,
    /// On the reduced space, the symmetry's momentum `μ` kept apart.
    Reduced,
}

/// Which equations a run solves: their [`Form`] and their side ([`Variant`]). The one vocabulary
/// of the programs that choose equations by name — the Python module's `method=` and the command
/// line's `method =` — read through [`Self::from_keyword`], so a keyword means the same
/// equations everywhere.
///
/// ```
/// use dirac_runtime::{Equations, Form, Variant};
///
/// // A flat system's own equations are the reduced ones, a rotation system's the unreduced.
/// let minus = Equations::from_keyword("minus", Form::Reduced).unwrap();
/// assert_eq!((minus.form, minus.side), (Form::Reduced, Variant::Minus));
/// let reduced = Equations::from_keyword("reduced", Form::Unreduced).unwrap();
/// assert_eq!((reduced.form, reduced.side), (Form::Reduced, Variant::Plus));
/// assert_eq!(reduced.keyword(Form::Unreduced), "reduced");
/// assert_eq!(Equations::from_keyword("midpoint", Form::Reduced), None);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Equations {
    /// Unreduced or reduced.
    pub form: Form,
    /// (+) or (−).
    pub side: Variant,
}

impl Equations {
    /// The words equations are named by: `"plus"` and `"minus"` (a side, in the family's own
    /// form), `"unreduced"` and `"reduced"` (a form, on the (+) side).
    pub const KEYWORDS: [&'static str; 4] = ["plus", "minus", "unreduced", "reduced"];

    /// The equations `word` names for a family whose own form is `own` (a flat system's are the
    /// reduced equations; the unreduced ones of a system on rotation groups or of an element-wise
    /// one): `"plus"` and `"minus"` the side in that form, `"unreduced"` and `"reduced"` the
    /// form on the (+) side (unconstrained, the unreduced (+) and (−) equations are one set,
    /// Definition 2.8). `None` for a word not in [`Self::KEYWORDS`]; whether the family has the
    /// equations named (a reduction needs a symmetry) is the caller's to check.
    pub fn from_keyword(word: &str, own: Form) -> Option<Self> {
        let (form, side) = match word {
            "plus" => (own, Variant::Plus),
            "minus" => (own, Variant::Minus),
            "unreduced" => (Form::Unreduced, Variant::Plus),
            "reduced" => (Form::Reduced, Variant::Plus),
            _ => return None,
        };
        Some(Self { form, side })
    }

    /// The keyword of these equations for a family whose own form is `own`: the inverse of
    /// [`Self::from_keyword`] (the side's name in the family's own form, the form's otherwise).
    pub fn keyword(self, own: Form) -> &'static str {
        match (self.form == own, self.side, self.form) {
            (true, Variant::Plus, _) => "plus",
            (true, Variant::Minus, _) => "minus",
            (false, _, Form::Unreduced) => "unreduced",
            (false, _, Form::Reduced) => "reduced",
        }
    }
}

/// The reduced (+) discrete Lagrange–Poincaré–Dirac equations, eq. (4.6), for the reduced
/// Lagrangian `l_{d+}(x0, x1, g1) = L_d(x0, 0, x1, g1 + h_d^0(x0, x1))`, eq. (4.5).
///
/// With the linear connection of [`DiscreteLagrangian`], eq. (4.6) reads
///
/// ```text
/// w_{k+1}            = ∂l_{d+}/∂x1                          (first line)
/// μ_{k+1}            = ∂l_{d+}/∂g1 = μ_k                     (second and fourth lines)
/// w_k − Bᵀ μ_k       = −∂l_{d+}/∂x0 − Bᵀ ∂l_{d+}/∂g1         (third line)
/// x_k^+              = x_{k+1}
/// g_k^+ − B x_k      = g_{k+1} − B x_{k+1}                   (last line, g_{k+1} relative to g_k)
/// ```
///
/// with every partial derivative at `(x_k, x_{k+1}, g_k^+)`. A forward step solves the third and
/// fourth lines for the unknowns `z = (x_{k+1}, g_k^+) ∈ R^N`; on solutions the third line is
/// `w_k = −∂l_{d+}/∂x0`, so the step residual ([`Reduced::residual`]) is
///
/// ```text
/// R(z) = ( ∂l_{d+}/∂x0 + w_k ,  ∂l_{d+}/∂g1 − μ_k ).
/// ```
///
/// (The printed third line is this `R_x` plus `Bᵀ R_g`: a constant invertible recombination of
/// the rows, which leaves Newton's iterates unchanged.) The momentum update is
/// `w_{k+1} = ∂l_{d+}/∂x1` and reconstruction `g_{k+1} = g_k + g_k^+ + B (x_{k+1} − x_k)`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Plus;

/// The reduced (−) discrete Lagrange–Poincaré–Dirac equations for the reduced Lagrangian
/// `l_{d−}(x0, g0, x1) = L_d(x0, g0 + h_d^0(x1, x0), x1, 0)`, eq. (4.7), with
/// `h_d^0(x1, x0) = B (x0 − x1)`.
///
/// # Derivation, and a sign discrepancy in the paper
///
/// The (−) equations of Definition 2.8 read `q_{k+1}^− = q_k`, `p_k = −D1 L_d(q_{k+1}^−, q_{k+1})`,
/// `p_{k+1} = D2 L_d(q_{k+1}^−, q_{k+1})`: in the unconstrained case they are the (+) equations,
/// i.e. the discrete Euler–Lagrange equations with the discrete Legendre transforms
/// `p_k = −D1 L_d`, `p_{k+1} = D2 L_d` (end of §2.3.2). By G-invariance,
/// `L_d(q_k, q_{k+1}) = l_{d−}(x_k, g_{k+1}^−, x_{k+1})` with
/// `g_{k+1}^− = g_k − g_{k+1} − B (x_k − x_{k+1}) = −ω_d(q_k, q_{k+1})`, and the chain rule
/// (Lemma 4.7) gives `∂L_d/∂x0 = ∂l/∂x0 − Bᵀ ∂l/∂g0`, `∂L_d/∂g0 = ∂l/∂g0`,
/// `∂L_d/∂x1 = ∂l/∂x1 + Bᵀ ∂l/∂g0`, `∂L_d/∂g1 = −∂l/∂g0`. With the trivialization (3.6)
/// (`w = p_x + Bᵀ p_g`, `μ = p_g`) the (−) equations become, at `(x_k, g_{k+1}^−, x_{k+1})`,
///
/// ```text
/// w_k     = −∂l_{d−}/∂x0          μ_k = −∂l_{d−}/∂g0
/// w_{k+1} =  ∂l_{d−}/∂x1          μ_{k+1} = μ_k
/// g_{k+1} = g_k − g_{k+1}^− + B (x_{k+1} − x_k)
/// ```
///
/// A forward step knows `(x_k, w_k, μ_k, g_k)` and solves the first line for
/// `z = (x_{k+1}, g_{k+1}^−)`: `R(z) = (∂l_{d−}/∂x0 + w_k, ∂l_{d−}/∂g0 + μ_k) = 0`; the second
/// and third lines are then explicit.
///
/// The paper's eq. (4.8) has the opposite sign on every momentum (`∂l_{d−}/∂x0 = w_k`,
/// `∂l_{d−}/∂g0 = μ_k = μ_{k+1}`, `−∂l_{d−}/∂x1 = w_{k+1}`): it follows the (−) action (2.12),
/// whose variation in `q_{k+1}^−` gives `p_k = +D1 L_d`, whereas Definition 2.8 and
/// Propositions 3.10 and 4.4 use `p_k = −D1 L_d`. Taken literally with the same `(w_0, μ_0)` as the
/// (+) equations, (4.8) integrates the motion with reversed momenta. The signs above are the ones
/// for which the (+) and (−) steppers, started from the same physical state, produce the same
/// physical trajectory — the discrete Euler–Lagrange solution — as the paper states they must.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Minus;

impl Side for Plus {
    const VARIANT: Variant = Variant::Plus;

    #[inline]
    fn group_increment<const K: usize>(u: SVector<f64, K>) -> SVector<f64, K> {
        u
    }
}

impl Side for Minus {
    const VARIANT: Variant = Variant::Minus;

    #[inline]
    fn group_increment<const K: usize>(u: SVector<f64, K>) -> SVector<f64, K> {
        -u
    }
}

/// The reduced discrete Lagrange–Poincaré–Dirac equations of side `D` ([`Plus`]: eq. (4.6);
/// [`Minus`]: eq. (4.8) with the signs of Definition 2.8), as the straight-line functions a step
/// needs. `#[reduced_lagrangian]` implements it for both sides.
///
/// Every function reads the step's data `(x_k, w_k, μ_k)` and the unknowns
/// `z = (x_{k+1}, u) ∈ R^N`, where the group unknown `u` is `g_k^+` for (+) and `g_{k+1}^−` for
/// (−); see [`Plus`] and [`Minus`] for the equations. A type implementing both sides names one
/// with the side: `Reduced::<Plus, S, K, N>::residual(&sys, ..)`.
pub trait Reduced<D: Side, const S: usize, const K: usize, const N: usize>:
    DiscreteLagrangian<S, K, N>
{
    /// The linear algebra of this side's steps, chosen by the compiler from the size of the
    /// system: [`crate::Lu`] (dense, fixed-size, on the stack) for `N ≤` [`crate::DENSE_MAX`],
    /// [`crate::SparseLu`] on the compile-time sparsity pattern of `∂R/∂z` above.
    type Linear: LinearSolver<Vector = SVector<f64, N>>;

    /// A workspace for [`Self::Linear`]: built once per integration (for the sparse backend this
    /// is the symbolic factorization and all scratch memory) and reused by every step.
    fn linear_solver(&self) -> Self::Linear;

    /// The reduced Lagrangian at `(x0, x1)` and the group unknown `u`:
    /// `l_{d+}(x0, x1, g1 = u)`, eq. (4.5), or `l_{d−}(x0, g0 = u, x1)`, eq. (4.7).
    fn reduced_lagrangian(
        &self,
        x0: &SVector<f64, S>,
        x1: &SVector<f64, S>,
        u: &SVector<f64, K>,
    ) -> f64;

    /// The step residual `R(z)` at `(x_k, w_k, μ_k)`: `(∂l/∂x0 + w_k, ∂l/∂u ∓ μ_k)` (`−` for
    /// (+), `+` for (−)), every derivative at `(x_k, z)`.
    fn residual(
        &self,
        x_k: &SVector<f64, S>,
        w_k: &SVector<f64, S>,
        mu_k: &SVector<f64, K>,
        z: &SVector<f64, N>,
    ) -> SVector<f64, N>;

    /// `R(z)` and its exact Jacobian `∂R/∂z` (second derivatives of the reduced Lagrangian),
    /// computed together in one straight-line function so shared subexpressions are evaluated
    /// once.
    fn residual_jacobian(
        &self,
        x_k: &SVector<f64, S>,
        w_k: &SVector<f64, S>,
        mu_k: &SVector<f64, K>,
        z: &SVector<f64, N>,
    ) -> (SVector<f64, N>, <Self::Linear as LinearSolver>::Matrix);

    /// The momentum update `w_{k+1} = ∂l/∂x1 (x_k, z)` (first line of eq. (4.6); the `w_{k+1}`
    /// line of [`Minus`]).
    fn momentum(&self, x_k: &SVector<f64, S>, z: &SVector<f64, N>) -> SVector<f64, S>;

    /// `R(z)` and `w_{k+1}` at `z` together: the test of a Newton iterate and, if it passes,
    /// the momentum update, from one straight line that shares their subexpressions.
    fn residual_momentum(
        &self,
        x_k: &SVector<f64, S>,
        w_k: &SVector<f64, S>,
        mu_k: &SVector<f64, K>,
        z: &SVector<f64, N>,
    ) -> (SVector<f64, N>, SVector<f64, S>) {
        (self.residual(x_k, w_k, mu_k, z), self.momentum(x_k, z))
    }

    /// Whether a force has a group component: then `μ` is not conserved but obeys the forced
    /// discrete Noether balance `μ_{k+1} = μ_k + f_{d,g}^− + f_{d,g}^+` ([`Self::group_impulse`]),
    /// applied explicitly, so it holds to round-off at every step. Without a group force `μ` is
    /// copied: constant bit for bit.
    const GROUP_FORCED: bool = false;

    /// The group impulse of the step, `f_{d,g}^− + f_{d,g}^+` at `(x_k, z)`: the change of `μ`
    /// over the step (zero without a group force).
    fn group_impulse(&self, _x_k: &SVector<f64, S>, _z: &SVector<f64, N>) -> SVector<f64, K> {
        SVector::zeros()
    }

    /// Writes the partial derivatives of the step at `(x_k, w_k, μ_k, z)` into `out`
    /// ([`crate::StepPartials`], with data `y = x_k` and updates `o = (w_{k+1}, μ_{k+1} − μ_k)`),
    /// what [`crate::ReducedIntegrator::sensitivity`] needs; `false` when the system was compiled
    /// without them (systems without forces or controls).
    fn step_partials(
        &self,
        _x_k: &SVector<f64, S>,
        _w_k: &SVector<f64, S>,
        _mu_k: &SVector<f64, K>,
        _z: &SVector<f64, N>,
        _out: &mut crate::StepPartials,
    ) -> bool {
        false
    }

    /// Whether the momentum equations (the last `K` rows of `R`) are affine in the group unknown
    /// and were solved in closed form at compile time (momentum-level elimination, beyond the
    /// paper: a discrete Routh-type step). Then the `eliminated_*` functions return `Some` and a
    /// step runs Newton on the `S` shape unknowns alone.
    const ELIMINATES_GROUP: bool = false;

    /// Whether the eliminated stepper is the better default: the compiler's verdict that its
    /// straight-line code is no larger (within 10%) than the general path's.
    const ELIMINATION_PAYS: bool = false;

    /// Whether this system's steps may eliminate the group unknowns: [`Self::ELIMINATES_GROUP`]
    /// for a system compiled in; a system given at run time says it here.
    fn eliminates_group(&self) -> bool {
        Self::ELIMINATES_GROUP
    }

    /// Whether elimination is the better default: [`Self::ELIMINATION_PAYS`] for a system
    /// compiled in; a system given at run time says it here.
    fn elimination_pays(&self) -> bool {
        Self::ELIMINATION_PAYS
    }

    /// The shape residual `R_x(x_{k+1}, u(x_{k+1}))` with the group unknown eliminated.
    fn eliminated_residual(
        &self,
        _x_k: &SVector<f64, S>,
        _w_k: &SVector<f64, S>,
        _mu_k: &SVector<f64, K>,
        _x1: &SVector<f64, S>,
    ) -> Option<SVector<f64, S>> {
        None
    }

    /// The eliminated shape residual and its exact `S × S` Jacobian (the total derivative in
    /// `x_{k+1}`, through the eliminated group unknown).
    fn eliminated_residual_jacobian(
        &self,
        _x_k: &SVector<f64, S>,
        _w_k: &SVector<f64, S>,
        _mu_k: &SVector<f64, K>,
        _x1: &SVector<f64, S>,
    ) -> Option<(SVector<f64, S>, SMatrix<f64, S, S>)> {
        None
    }

    /// The group unknown `u` solving the momentum equations at `x_{k+1}`, in closed form.
    fn eliminated_group(
        &self,
        _x_k: &SVector<f64, S>,
        _w_k: &SVector<f64, S>,
        _mu_k: &SVector<f64, K>,
        _x1: &SVector<f64, S>,
    ) -> Option<SVector<f64, K>> {
        None
    }

    /// The block `A = ∂R_g/∂u` that the closed form inverts, at `x_{k+1}`; the runtime
    /// estimates its conditioning, which the shape Jacobian no longer shows.
    fn eliminated_group_block(
        &self,
        _x_k: &SVector<f64, S>,
        _w_k: &SVector<f64, S>,
        _mu_k: &SVector<f64, K>,
        _x1: &SVector<f64, S>,
    ) -> Option<SMatrix<f64, K, K>> {
        None
    }
}

/// The unreduced (+) discrete Lagrange–Dirac equations on `Q` (Definition 2.7):
/// `p_k = −D1 L_d(q_k, q_{k+1})`, `p_{k+1} = D2 L_d(q_k, q_{k+1})`. A step solves
/// `R(q_{k+1}) = D1 L_d(q_k, q_{k+1}) + p_k = 0`. In the unconstrained case the (−) equations of
/// Definition 2.8 (with `q_{k+1}^− = q_k`) are the same equations, so one implementation serves
/// both. This is the baseline every reduced integrator is compared with: it knows nothing of the
/// symmetry, carries the group coordinates, and evaluates `L_d` at absolute group coordinates.
pub trait Unreduced<const S: usize, const K: usize, const N: usize>:
    DiscreteLagrangian<S, K, N>
{
    /// The linear algebra of the unreduced steps (see [`Reduced::Linear`]).
    type UnreducedLinear: LinearSolver<Vector = SVector<f64, N>>;

    /// A workspace for [`Self::UnreducedLinear`], built once per integration.
    fn unreduced_linear_solver(&self) -> Self::UnreducedLinear;

    /// `R(z) = D1 L_d(q_k, z) + p_k`.
    fn unreduced_residual(
        &self,
        q_k: &SVector<f64, N>,
        p_k: &SVector<f64, N>,
        z: &SVector<f64, N>,
    ) -> SVector<f64, N>;

    /// `R(z)` and `∂R/∂z = D2 D1 L_d(q_k, z)`, from one straight-line function.
    fn unreduced_residual_jacobian(
        &self,
        q_k: &SVector<f64, N>,
        p_k: &SVector<f64, N>,
        z: &SVector<f64, N>,
    ) -> (
        SVector<f64, N>,
        <Self::UnreducedLinear as LinearSolver>::Matrix,
    );

    /// `p_{k+1} = D2 L_d(q_k, q_{k+1})` (`+ f_d^+` with forces).
    fn unreduced_momentum(&self, q_k: &SVector<f64, N>, z: &SVector<f64, N>) -> SVector<f64, N>;

    /// Writes the partial derivatives of the step at `(q_k, p_k, z)` into `out`
    /// ([`crate::StepPartials`], with data `y = q_k` and update `o = p_{k+1}`), what
    /// [`crate::UnreducedIntegrator::sensitivity`] needs; `false` when the system was compiled
    /// without them.
    fn unreduced_step_partials(
        &self,
        _q_k: &SVector<f64, N>,
        _p_k: &SVector<f64, N>,
        _z: &SVector<f64, N>,
        _out: &mut crate::StepPartials,
    ) -> bool {
        false
    }
}

/// The second derivatives of `L_d`, emitted for systems on the dense backend
/// (`N ≤` [`crate::DENSE_MAX`]): what the step-map Jacobian needs
/// ([`crate::UnreducedIntegrator::step_jacobian`]). A large system's step-map Jacobian is a dense
/// `2N × 2N` matrix and is not offered.
pub trait LagrangianHessian<const S: usize, const K: usize, const N: usize>:
    Unreduced<S, K, N>
{
    /// The Hessian blocks `(D11 L_d, D12 L_d, D22 L_d)` at `(q0, q1)`, with
    /// `D12[(i, j)] = ∂²L_d/∂q0_i ∂q1_j`: what the step-map Jacobian needs (see
    /// [`crate::UnreducedIntegrator::step_jacobian`]).
    #[allow(clippy::type_complexity)]
    fn lagrangian_hessian(
        &self,
        q0: &SVector<f64, N>,
        q1: &SVector<f64, N>,
    ) -> (SMatrix<f64, N, N>, SMatrix<f64, N, N>, SMatrix<f64, N, N>);
}

/// Splits `q = (x, g)`.
pub fn split<const S: usize, const K: usize, const N: usize>(
    q: &SVector<f64, N>,
) -> (SVector<f64, S>, SVector<f64, K>) {
    const { assert!(S + K == N, "the configuration dimension N must be S + K") };
    (
        q.fixed_rows::<S>(0).into_owned(),
        q.fixed_rows::<K>(S).into_owned(),
    )
}

/// Joins `x` and `g` into `q = (x, g)`.
pub fn join<const S: usize, const K: usize, const N: usize>(
    x: &SVector<f64, S>,
    g: &SVector<f64, K>,
) -> SVector<f64, N> {
    const { assert!(S + K == N, "the configuration dimension N must be S + K") };
    let mut q = SVector::<f64, N>::zeros();
    q.fixed_rows_mut::<S>(0).copy_from(x);
    q.fixed_rows_mut::<K>(S).copy_from(g);
    q
}
