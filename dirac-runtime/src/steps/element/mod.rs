//! Systems whose size is chosen at run time: a discrete Lagrangian that is a sum of one small
//! term over many elements, `L_d(q_k, q_{k+1}) = Σ_f Σ_{e ∈ f} L_d^e(q_k|_e, q_{k+1}|_e)`, each
//! element reading a fixed stencil of coordinates (`x[i]`, `x[i + 1]`, `x[(i + 1) % n]`, a pair
//! `x[i]`, `x[j]`, a grid neighbour `u[i][(j + 1) % m]`). `#[reduced_lagrangian]` emits one
//! kernel per family `f` of elements (a `for` loop of the body, or a term outside loops) —
//! the element's `D_1 L_d^e`, `D_1 D_2 L_d^e` and `D_2 L_d^e`, differentiated at compile time —
//! and the element's stencil as integer code in the loop indices and the sizes; this module
//! assembles them at run time, for whatever sizes the system is built with. Generated code and
//! compile time do not depend on the sizes.
//!
//! # The step
//!
//! [`ElementIntegrator`] solves the position–momentum form of the discrete Lagrange–Dirac (+)
//! equations (Definition 2.7; Marsden & West, eq. (1.5.6)) in the user's coordinates:
//!
//! ```text
//! R(q_{k+1}) = p_k + D_1 L_d(q_k, q_{k+1}) = 0,        p_{k+1} = D_2 L_d(q_k, q_{k+1}),
//! ```
//!
//! by the one Newton driver ([`crate::newton::solve_in`]) with chord iterations, on a pattern
//! built once per run from the stencils, `∂R/∂q_{k+1} = Σ_e D_1 D_2 L_d^e` scattered block by
//! block and solved as [`StepSolver`] chooses (the banded LU [`crate::linalg::BandedLu`] for a
//! narrow band once reordered, a dense LU for a small wide pattern, the sparse LU
//! [`crate::linalg::DynSparseLu`], or conjugate gradients for large grids). Nothing is
//! allocated per step:
//! the states are `DVector`s whose memory the driver's two states reuse
//! ([`crate::Stepper::step_into`]), and the residual, the Jacobian's values and the factors live
//! in the run's [`ElementWorkspace`].
//!
//! # The (−) side
//!
//! [`ElementIntegrator::minus`] solves the (−) equations of Definition 2.8,
//!
//! ```text
//! q_{k+1}^− = q_k,     p_k = −D_1 L_d(q_{k+1}^−, q_{k+1}),     p_{k+1} = D_2 L_d(q_{k+1}^−, q_{k+1}),
//! ```
//!
//! with the unknown trivialized at the next point, as the rotation integrators' (−) side is: the
//! backward increment `Δ = q_{k+1}^− − q_{k+1} = q_k − q_{k+1}`, so that
//! `R(Δ) = p_k + D_1 L_d(q_k, q_k − Δ) = 0` with `∂R/∂Δ = −Σ_e D_1 D_2 L_d^e` (the same pattern,
//! assembly and factorization), then `q_{k+1} = q_k − Δ`. With a declared translation, the
//! component of `Δ` along its orbit is the group unknown `g_{k+1}^− = g_k − g_{k+1}` of the
//! reduced (−) equations (4.8) (with the signs of [`crate::Minus`]) and the rest its shape
//! increment; `μ_{k+1} = μ_k` is kept exact as on the (+) side. Forces enter both sides alike
//! (`p_k = −D_1 L_d − f_d^−`, `p_{k+1} = D_2 L_d + f_d^+`). Newton's iterates in `Δ` are the
//! affine images of those in `q_{k+1}`, so the two sides compute the same trajectory — the
//! discrete Euler–Lagrange solution — up to round-off (`tests/element_wise.rs` checks it, with
//! forces, controls and compositions).
//!
//! # Translations and the exact momentum
//!
//! With `translate(x)` declared, `L_d` is invariant under `x ↦ x + c·1`, and the momentum map
//! `μ = Σ_{i} p_{x_i}` of each declared translation is conserved. In the adapted coordinates of
//! §2.2.1 (group `g = x_0`, shape `r_i = x_i − x_0`) the equations above are the reduced (+)
//! equations (4.6) with `B = 0` written in another basis — the same unknowns, the same solution —
//! and the reduced integrator sets `μ_{k+1} = μ_k` rather than computing it. This integrator
//! does the same: `p_{k+1}` is `D_2 L_d` in every component but the first of each orbit, which
//! takes the value that makes `Σ_i p_{x_i}` exactly `μ_k` (the user momentum of the reduced
//! state `(r_{k+1}, p_r = D_{r} ℓ, μ_k)`: `p_{x_i} = p_{r_i}` for `i ≥ 1`,
//! `p_{x_0} = μ − Σ_{i ≥ 1} p_{r_i}`). So `μ` is conserved to round-off, as in the reduced
//! integrator, whatever the Newton tolerance.
//!
//! # Parallel assembly
//!
//! Above a size threshold ([`Parallel::Auto`]) the elements are evaluated in parallel on
//! rayon's pool into per-element buffers, and each residual row and Jacobian entry then sums
//! its contributions, also in parallel, in the order the serial assembly adds them (family,
//! element, slot), starting from the same value. The result is bit for bit the serial one, on
//! any number of threads (`tests/element_wise.rs` checks it).

mod assembly;
pub mod constrained;
mod history;
mod legendre;
mod pass;
mod rows;
pub mod sensitivity;
mod solver;
mod stencils;
mod step;
mod sums;
#[cfg(test)]
mod tests;

use std::fmt::Debug;
use std::ops::Range;

use nalgebra::DVector;

use crate::continuous::ContinuousEnergies;
use crate::error::{IntegrationError, StepError, Steps};
use crate::model::System;
use crate::newton::NewtonOptions;
use crate::stepper::{Collect, StepStats, StepStatsExt};
use crate::system::Variant;

pub use history::Increments;

pub use assembly::ElementWorkspace;
pub use constrained::{
    ElementConstrainedError, ElementConstrainedIntegrator, ElementConstrainedStep,
    ElementConstrainedTrajectory, ElementConstrainedWorkspace,
};
pub use sensitivity::{CscMatrix, ElementSensitivity};
pub use solver::{
    DenseStep, ElementSolver, BANDED_MAX_WIDTH, DENSE_MAX_DIM, DENSE_MIN_FILL, ITERATIVE_MIN_DIM,
    ITERATIVE_MIN_ENTRIES_PER_ROW,
};

/// One family of elements of an element-wise Lagrangian: a loop of its body (or a term outside
/// loops), each element reading a stencil of [`Self::width`] coordinates. Emitted by
/// `#[reduced_lagrangian]` (the width then a literal of the emitted code) and formed at run time
/// by a system given as text (the width then data: one family may read any number of
/// coordinates).
///
/// The width is data rather than a type parameter, so that one instance of the runtime's
/// assembly serves every width: the element functions read their stencil values from slices of
/// `width` entries and write their outputs into a caller-provided slice, laid out as the
/// compiled kernels write them (below), which the run holds in its workspace — nothing is
/// allocated per element or per step.
#[doc(hidden)]
pub trait Family: Sync {
    /// The stencil width `S`: the number of coordinates an element reads.
    fn width(&self) -> usize;

    /// The number of loop indices of an element (0 for a term outside loops).
    fn depth(&self) -> usize;

    /// Whether the family is one of the forces (`force = |dq| ..`): its `d1_d2` are the discrete
    /// forces `f_d^{e−}`, `f_d^{e+}`, its `d1_d2_d12` adds `∂f_d^{e−}/∂q_{k+1}`, and it has no
    /// value, energy or share of the Legendre map.
    fn force(&self) -> bool {
        false
    }

    /// Calls `visit(indices, stencil)` for every element, in loop order: the values of the loop
    /// indices ([`Self::depth`] of them) and the global indices of the coordinates the element
    /// reads, slot by slot ([`Self::width`] of them; negative or too large when the sizes are
    /// too small for the stencil; the runtime checks them before any step).
    fn elements(&self, visit: &mut dyn FnMut(&[i64], &[i64]));

    /// `D_1 L_d^e` and `D_2 L_d^e` at the stencil values `q0`, `q1` of element `indices` into
    /// `out` (`2S` entries: `D_1 L_d^e`, then `D_2 L_d^e`), from one straight-line function
    /// (they share the element's subexpressions: a residual pass yields the next momentum at no
    /// extra transcendental cost). `q0`, `q1` have `S` entries.
    fn d1_d2(&self, indices: &[i64], q0: &[f64], q1: &[f64], out: &mut [f64]);

    /// `D_1 L_d^e`, `D_2 L_d^e` and `D_1 D_2 L_d^e` into `out` (`2S + S²` entries: the two
    /// vectors, then the matrix row by row, row `a`: `∂(D_1 L_d^e)_a / ∂q1_b`).
    fn d1_d2_d12(&self, indices: &[i64], q0: &[f64], q1: &[f64], out: &mut [f64]);

    /// The element's step partials, for a step's sensitivity, into `out` (`3S² + 2Sm` entries,
    /// `m` controls): the `S × S` blocks `∂d1/∂q0`, `∂d2/∂q0`, `∂d2/∂q1` row by row (row `a`:
    /// component `a` of `d1` or `d2`, the element's `D_1 L_d^e`, `D_2 L_d^e` or discrete
    /// forces), then the derivatives of `d1_a` and of `d2_a` in control `c` at `a·m + c`.
    /// `false` when the family has none (the default, for a family written by hand).
    fn step_partials(&self, indices: &[i64], q0: &[f64], q1: &[f64], out: &mut [f64]) -> bool {
        let _ = (indices, q0, q1, out);
        false
    }

    /// `L_d^e` itself.
    fn value(&self, indices: &[i64], q0: &[f64], q1: &[f64]) -> f64;

    /// The element's energy `E^e(q, v) = ⟨∂L^e/∂v, v⟩ − L^e` of a continuous Lagrangian (NaN
    /// for a discrete one).
    fn energy(&self, indices: &[i64], q: &[f64], v: &[f64]) -> f64;

    /// The element's share of the Legendre map, `∂L^e/∂v`, and its Jacobian `∂²L^e/∂v²` (row
    /// `a`) at `(q, v)` of a continuous Lagrangian, into `out` (`S + S²` entries); NaN for a
    /// discrete one, and by default for a family written by hand.
    fn legendre(&self, indices: &[i64], q: &[f64], v: &[f64], out: &mut [f64]) {
        let _ = (indices, q, v);
        out.fill(f64::NAN);
    }
}

/// The first `S` stencil values of `v` as an array, for the element functions the attribute
/// emits (which know their width): the runtime passes exactly [`Family::width`] values.
///
/// # Panics
/// If `v` has fewer than `S` entries (never, from the runtime's passes).
#[doc(hidden)]
#[inline(always)]
pub fn stencil<const S: usize>(v: &[f64]) -> &[f64; S] {
    match v.get(..S).map(<&[f64; S]>::try_from) {
        Some(Ok(array)) => array,
        _ => panic!(
            "dirac: an element function was passed {} stencil values for a width of {S}",
            v.len()
        ),
    }
}

/// The first `N` entries of an element function's output slice as an array, for the element
/// functions the attribute emits (which know their output's length).
///
/// # Panics
/// If `out` has fewer than `N` entries (never, from the runtime's passes).
#[doc(hidden)]
#[inline(always)]
pub fn outputs<const N: usize>(out: &mut [f64]) -> &mut [f64; N] {
    let len = out.len();
    match out.get_mut(..N).map(<&mut [f64; N]>::try_from) {
        Some(Ok(array)) => array,
        _ => panic!("dirac: an element function was given {len} outputs to write {N}"),
    }
}

/// The scratch entries a family of stencil width `width` needs for one element: its stencil
/// values `q0`, `q1` (`2S`) and the largest output of an element function (`2S + S²`).
pub(crate) fn scratch_len(width: usize) -> usize {
    4 * width + width * width
}

/// One family of holonomic constraint rows of an element-wise system (`constraints = |q| ..`):
/// an assignment `phi[<row>] = φ` of the closure, in loops or not, each element reading
/// [`Self::width`] coordinates (data, as for [`Family`]). Emitted by `#[reduced_lagrangian]`.
#[doc(hidden)]
pub trait ConstraintFamily: Sync {
    /// The stencil width `S`.
    fn width(&self) -> usize;
    /// The number of loop indices of an element.
    fn depth(&self) -> usize;
    /// Calls `visit(indices, row, stencil)` for every element: its loop indices, the constraint
    /// row it assigns and the global indices of the coordinates it reads (unchecked: the
    /// runtime checks rows and stencils before any step).
    #[allow(clippy::type_complexity)]
    fn elements(&self, visit: &mut dyn FnMut(&[i64], i64, &[i64]));
    /// `φ^e(q)` and its gradient `∂φ^e/∂q` at the stencil values `q` (`S` entries) into `out`
    /// (`1 + S` entries: the value, then the gradient).
    fn value_gradient(&self, indices: &[i64], q: &[f64], out: &mut [f64]);
}

/// What visits the constraint families of an [`ElementLagrangian`].
#[doc(hidden)]
pub trait ConstraintVisitor {
    /// Visits one family.
    fn constraint<F: ConstraintFamily>(&mut self, family: &F);
}

/// What visits the families of an [`ElementLagrangian`], one type per family.
#[doc(hidden)]
pub trait FamilyVisitor {
    /// Visits one family.
    fn family<F: Family>(&mut self, family: &F);
}

/// A discrete Lagrangian that is a sum over elements, with sizes chosen at run time: what
/// `#[reduced_lagrangian]` implements when the function takes `usize` sizes (see the
/// [module documentation](self)). The element-wise family of the one system model ([`System`]:
/// parameters, time step, controls and names are declared there; this family declares no
/// domain and no adaptive steps, and its integrators refuse a system that does).
pub trait ElementLagrangian: System + Clone + Debug + Send + Sync + 'static {
    /// The names of the sizes, in the order of the function's `usize` arguments.
    const SIZES: &'static [&'static str];
    /// The smallest value of every size for which every stencil stays inside its coordinate
    /// (checked by the compiler on sample sizes, and by the runtime for the sizes given).
    const MIN_SIZE: usize;
    /// Whether the system is a continuous Lagrangian with a quadrature rule (then it has an
    /// energy, [`ElementIntegrator::energy`]).
    const CONTINUOUS: bool;
    /// Whether the system declares forces (`force = |dq| ..`): families with
    /// [`Family::force`], and the momentum map of each translation changes by their impulse.
    const FORCED: bool = false;

    /// Whether the system declares holonomic constraints (`constraints = |q| ..`): then it is
    /// integrated by [`ElementConstrainedIntegrator`].
    const CONSTRAINED: bool = false;

    /// The names of the sizes, in the order of [`Self::sizes`]: [`Self::SIZES`] for a system
    /// compiled in; a system given at run time (whose constants cannot know its names) says
    /// them here. What the integrators' messages and output read.
    fn size_names(&self) -> Vec<&str> {
        Self::SIZES.to_vec()
    }

    /// The smallest value of every size: [`Self::MIN_SIZE`] for a system compiled in; a system
    /// given at run time says it here. What the integrators check the sizes against.
    fn min_size(&self) -> usize {
        Self::MIN_SIZE
    }

    /// Whether the system is a continuous Lagrangian with a quadrature rule:
    /// [`Self::CONTINUOUS`] for a system compiled in; a system given at run time says it here.
    /// What the integrators read (a discrete Lagrangian has no energy).
    fn continuous(&self) -> bool {
        Self::CONTINUOUS
    }

    /// Whether the system declares forces: [`Self::FORCED`] for a system compiled in; a system
    /// given at run time says it here. What the integrators read (the impulse of the forces on
    /// each translation's momentum map).
    fn forced(&self) -> bool {
        Self::FORCED
    }

    /// Whether the system declares holonomic constraints: [`Self::CONSTRAINED`] for a system
    /// compiled in; a system given at run time says it here.
    fn constrained(&self) -> bool {
        Self::CONSTRAINED
    }

    /// The number of constraint rows for these sizes.
    fn constraint_count(&self) -> usize {
        0
    }

    /// Visits every constraint family, in the order of the closure.
    fn constraint_families<V: ConstraintVisitor>(&self, visitor: &mut V) {
        let _ = visitor;
    }

    /// The sizes this system is built with, in the order of [`Self::size_names`].
    fn sizes(&self) -> Vec<usize>;
    /// The number of coordinates for these sizes.
    fn dim(&self) -> usize;
    /// One entry per declared translation: the ranges of coordinate indices it moves together
    /// (its orbit; the first index is where the momentum map is kept exact).
    fn translations(&self) -> Vec<Vec<Range<usize>>>;
    /// Visits every family of elements, in the order of the body.
    fn families<V: FamilyVisitor>(&self, visitor: &mut V);
}

/// A state of a run-time-sized system: configuration and momentum in the user's coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct ElementState {
    /// `q_k`.
    pub q: DVector<f64>,
    /// `p_k`.
    pub p: DVector<f64>,
}

impl ElementState {
    crate::state::qp_state!(
        /// The state `(q, p)`, each given as a slice, a `Vec`, an array or an nalgebra vector
        /// ([`crate::state::IntoVector`]).
        new(DVector<f64>, DVector<f64>)
    );
}

/// When the elements are assembled in parallel. The result is the same, bit for bit, either
/// way (see the [module documentation](self)); only the time differs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Parallel {
    /// In parallel when the Jacobian's element blocks hold at least [`PARALLEL_MIN_ENTRIES`]
    /// entries and rayon's pool has more than one thread.
    #[default]
    Auto,
    /// Always serial.
    Never,
    /// Always in parallel (on rayon's current pool).
    Always,
}

/// Which linear solver an element-wise run solves its step Jacobian with.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum StepSolver {
    /// Conjugate gradients for large multi-dimensional patterns (at least
    /// [`ITERATIVE_MIN_DIM`] unknowns and
    /// [`ITERATIVE_MIN_ENTRIES_PER_ROW`] entries per row: fields on grids), whose
    /// sparse LU fills in; the banded LU ([`crate::linalg::BandedLu`]) when a reverse
    /// Cuthill–McKee ordering makes the pattern a band of at most [`BANDED_MAX_WIDTH`]
    /// (chains, lattices, rings); a dense LU with partial pivoting for a wider pattern of at
    /// most [`DENSE_MAX_DIM`] unknowns and at least `1 /` [`DENSE_MIN_FILL`] full (small pairs,
    /// the element view of a flat system given as text: one element reading every
    /// coordinate); the sparse LU otherwise (larger pairs). CG falls back to the LU when the
    /// Jacobian is not symmetric.
    #[default]
    Auto,
    /// The banded LU on the reverse Cuthill–McKee ordering however wide the band, as long as
    /// its storage (`n` times the band's width) can be allocated; the sparse LU otherwise.
    Banded,
    /// Always faer's sparse LU ([`crate::linalg::DynSparseLu`]).
    Direct,
    /// Jacobi-preconditioned conjugate gradients ([`crate::linalg::Pcg`]) whenever the pattern
    /// is symmetric, falling back to the LU as [`StepSolver::Auto`] does.
    Iterative,
}

/// The smallest number of Jacobian block entries (elements × stencil²) for which
/// [`Parallel::Auto`] assembles in parallel: below, the parallel passes' extra memory traffic
/// and synchronisation cost more than a serial pass (measured on the lattice, `examples/toda_n`).
pub const PARALLEL_MIN_ENTRIES: usize = 1 << 16;

/// The (+) integrator of an element-wise system (see the [module documentation](self)).
#[derive(Clone, Debug)]
pub struct ElementIntegrator<L> {
    system: L,
    options: NewtonOptions,
    variant: Variant,
    parallel: Parallel,
    linear: StepSolver,
}

/// Every state and step record of an [`ElementIntegrator`] run (`Drive::run(..).collect()`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ElementTrajectory {
    /// The integrator's time step (the default step of a run).
    pub h: f64,
    /// The equations that produced it: [`Variant::Plus`] ([`ElementIntegrator::new`]) or
    /// [`Variant::Minus`] ([`ElementIntegrator::minus`]).
    pub variant: Variant,
    /// `(q_k, p_k)`, `k = 0..=steps`.
    pub states: Vec<ElementState>,
    /// `times[k] = t_k`, the time of `states[k]` (`k h` exactly for a fixed step).
    pub times: Vec<f64>,
    /// `step_sizes[k]` is the size step `k` was taken with, bit for bit as the run passed it to
    /// the step: `h` itself for a fixed step, `h_k` with a schedule (the last step shortened to
    /// land on an end time); with adaptive steps the fictitious step `ε_k` (the physical step is
    /// `times[k + 1] − times[k]`).
    pub step_sizes: Vec<f64>,
    /// The Newton statistics of each step.
    pub stats: Vec<StepStats>,
}

impl ElementTrajectory {
    crate::reduced::trajectory_accessors!(ElementState);
}

impl Steps for ElementTrajectory {
    fn completed_steps(&self) -> usize {
        self.stats.len()
    }
}

/// A stepper whose states are [`ElementState`]s and whose records are [`StepStats`]: what an
/// [`ElementTrajectory`] collects. [`ElementIntegrator`] is one; an integrator of another crate
/// on configurations sized at run time (the recursive step of articulated bodies) is another,
/// and its runs collect into the same trajectory.
pub trait ElementSteps: crate::stepper::Stepper<State = ElementState, Record = StepStats> {
    /// The equations it solves, as [`ElementTrajectory::variant`] records them.
    fn variant(&self) -> Variant;
}

impl<L: ElementLagrangian> ElementSteps for ElementIntegrator<L> {
    fn variant(&self) -> Variant {
        self.variant
    }
}

impl<St: ElementSteps> Collect<St> for ElementTrajectory {
    // Each state kept is a copy of `state`'s vectors: room for them is asked for (and given
    // back) by `reserve_states`, where a failed allocation is an error rather than an abort.
    crate::stepper::collect_steps!(
        start(integrator: St) {
            h: integrator.time_step(),
            variant: ElementSteps::variant(integrator),
        },
        ElementState,
        StepStats,
        |stats| *stats;
        then crate::element::reserve_states
    );
}

impl<L: ElementLagrangian> ElementIntegrator<L> {
    /// The (+) integrator with `options`, assembling in parallel above the threshold.
    pub fn new(system: L, options: NewtonOptions) -> Self {
        Self {
            system,
            options,
            variant: Variant::Plus,
            parallel: Parallel::Auto,
            linear: StepSolver::Auto,
        }
    }

    crate::stepper::plus_or_minus!(
        /// The (−) integrator with `options`: the (−) equations of Definition 2.8, solved for the
        /// backward increment `Δ = q_k − q_{k+1}` (see the [module documentation](self#the---side)).
        /// Started from the same state it computes the (+) integrator's trajectory, to round-off.
    );

    /// The same integrator with the step Jacobian's solver chosen by `solver`.
    pub fn with_solver(mut self, solver: StepSolver) -> Self {
        self.linear = solver;
        self
    }

    /// The same integrator with the assembly's parallelism set to `parallel`.
    pub fn with_parallel(mut self, parallel: Parallel) -> Self {
        self.parallel = parallel;
        self
    }

    /// The system being integrated.
    pub fn system(&self) -> &L {
        &self.system
    }

    /// Newton's tolerances and caps.
    pub fn options(&self) -> &NewtonOptions {
        &self.options
    }

    /// When the assembly runs in parallel.
    pub fn parallel(&self) -> Parallel {
        self.parallel
    }

    /// Which solver solves the step Jacobian.
    pub fn solver(&self) -> StepSolver {
        self.linear
    }

    /// The momentum map `μ` of each declared translation: `Σ p_i` over its orbit. A state
    /// without the system's number of coordinates is [`StepError::InvalidSize`].
    pub fn momentum_map(&self, state: &ElementState) -> Result<Vec<f64>, StepError> {
        self.check_lengths(&[("q", state.q.len()), ("p", state.p.len())])?;
        let n = state.p.len();
        self.system
            .translations()
            .iter()
            .map(|orbit| {
                orbit.iter().flat_map(|r| r.clone()).try_fold(0.0, |mu, i| {
                    // The orbits come from the system's declaration; one reaching past the
                    // coordinates is an inconsistent system, reported as such.
                    state.p.as_slice().get(i).map(|p| mu + p).ok_or_else(|| {
                        self.invalid(format!(
                            "a translation's orbit reads coordinate {i}, outside 0..{n}"
                        ))
                    })
                })
            })
            .collect()
    }

    /// `L_d(q0, q1)`: the sum of the element values. Vectors without the system's number of
    /// coordinates, or sizes too small for the stencils, are [`StepError::InvalidSize`].
    pub fn discrete_lagrangian(
        &self,
        q0: &DVector<f64>,
        q1: &DVector<f64>,
    ) -> Result<f64, StepError> {
        self.check_lengths(&[("q0", q0.len()), ("q1", q1.len())])?;
        sums::value(&self.system, q0.as_slice(), q1.as_slice()).map_err(|r| self.invalid(r))
    }

    /// The energy at the step's midpoint, `E((q0 + q1)/2, (q1 − q0)/h)`, of a continuous
    /// Lagrangian: the sum of the element energies, allocation-free. A discrete Lagrangian has
    /// none ([`StepError::Unsupported`]); vectors without the system's number of coordinates,
    /// or sizes too small for the stencils, are [`StepError::InvalidSize`].
    pub fn energy(&self, q0: &DVector<f64>, q1: &DVector<f64>) -> Result<f64, StepError> {
        self.energy_with(q0, q1, self.system.time_step())
    }

    /// [`Self::energy`] for a step of size `h`.
    fn energy_with(&self, q0: &DVector<f64>, q1: &DVector<f64>, h: f64) -> Result<f64, StepError> {
        self.require_continuous()?;
        self.check_lengths(&[("q0", q0.len()), ("q1", q1.len())])?;
        sums::energy(&self.system, q0.as_slice(), q1.as_slice(), h).map_err(|r| self.invalid(r))
    }

    /// The continuous energy of a trajectory of this integrator at its nodes and midpoints, as
    /// the fixed-size integrators' `energies` give it: at node `k`, `E(q_k, v_k)` with `v_k`
    /// solving the Legendre map `∂L/∂v (q_k, v_k) = p_k` for the discrete momentum (Newton from
    /// the adjacent difference quotient, the Jacobian `∂²L/∂v²` assembled element by element
    /// into the step Jacobian's pattern and solved by the sparse LU, with this integrator's
    /// tolerances); the midpoints as [`Self::midpoint_energies`]. A discrete Lagrangian has no
    /// energy ([`StepError::Unsupported`]); a degenerate one no node energies
    /// ([`StepError::SingularJacobian`] at the node, as the step index).
    pub fn energies(
        &self,
        trajectory: &ElementTrajectory,
    ) -> Result<ContinuousEnergies, StepError> {
        self.require_continuous()?;
        let states = &trajectory.states;
        let ws = ElementWorkspace::new(&self.system, Parallel::Never, StepSolver::Direct);
        if let Some(reason) = ws.invalid() {
            return Err(self.invalid(reason.to_string()));
        }
        let mut nodes = Vec::with_capacity(states.len());
        for (k, state) in states.iter().enumerate() {
            self.check_lengths(&[("q", state.q.len()), ("p", state.p.len())])?;
            let step = |j: usize| crate::stepper::step_between(&trajectory.times, j, trajectory.h);
            let guess = match (k.checked_sub(1), states.get(k + 1)) {
                (_, Some(next)) => (&next.q - &state.q) / step(k),
                (Some(prev), None) => (&state.q - &states[prev].q) / step(prev),
                (None, None) => DVector::zeros(state.q.len()),
            };
            let v = legendre::velocity(
                &self.system,
                ws.pattern(),
                k,
                &state.q,
                &state.p,
                guess,
                &self.options,
            )?;
            nodes.push(
                sums::energy_at(&self.system, state.q.as_slice(), v.as_slice())
                    .map_err(|r| self.invalid(r))?,
            );
        }
        Ok(ContinuousEnergies {
            nodes,
            midpoints: self.midpoint_energies(trajectory)?,
        })
    }

    /// The energy at each step's midpoint along a trajectory of this integrator
    /// ([`Self::energy`] of each step, with the step's own size `t_{k+1} − t_k`);
    /// [`Self::energies`] adds the node energies.
    pub fn midpoint_energies(&self, trajectory: &ElementTrajectory) -> Result<Vec<f64>, StepError> {
        trajectory
            .states
            .windows(2)
            .enumerate()
            .map(|(k, pair)| {
                let h = crate::stepper::step_between(&trajectory.times, k, trajectory.h);
                self.energy_with(&pair[0].q, &pair[1].q, h)
            })
            .collect()
    }

    /// The residual `R(z) = p0 + D_1 L_d(q0, z)` and the values of its Jacobian, in the order
    /// of the workspace's pattern ([`ElementWorkspace::pattern`]): what one Newton correction
    /// evaluates (public for benchmarks). `workspace` must be one of this integrator
    /// ([`crate::Stepper::workspace`]) and the vectors must have the system's number of coordinates:
    /// otherwise [`StepError::InvalidSize`], with nothing evaluated.
    pub fn residual_jacobian(
        &self,
        workspace: &mut ElementWorkspace,
        q0: &DVector<f64>,
        p0: &DVector<f64>,
        z: &DVector<f64>,
        r: &mut DVector<f64>,
        jacobian: &mut Vec<f64>,
    ) -> Result<(), StepError> {
        self.check_workspace(workspace)?;
        if workspace.sizes() != self.system.sizes() {
            return Err(self.invalid(format!(
                "the workspace was built for sizes {:?}, the system has sizes {:?}",
                workspace.sizes(),
                self.system.sizes()
            )));
        }
        self.check_lengths(&[
            ("q0", q0.len()),
            ("p0", p0.len()),
            ("z", z.len()),
            ("r", r.len()),
        ])?;
        jacobian.resize(workspace.nnz(), 0.0);
        workspace.assembler().residual_jacobian(
            &self.system,
            q0.as_slice(),
            p0.as_slice(),
            z.as_slice(),
            r.as_mut_slice(),
            Some(jacobian.as_mut_slice()),
        );
        Ok(())
    }

    /// Every vector in `lengths` (a name and a length) against the system's number of
    /// coordinates.
    fn check_lengths(&self, lengths: &[(&str, usize)]) -> Result<(), StepError> {
        let n = self.system.dim();
        match lengths.iter().find(|(_, len)| *len != n) {
            Some((name, len)) => Err(self.invalid(format!(
                "`{name}` has {len} components; the system with sizes {:?} has {n} coordinates",
                self.system.sizes()
            ))),
            None => Ok(()),
        }
    }

    /// Whether `workspace` serves this system: valid stencils, the system's number of
    /// coordinates and its families (stencil widths, loop depths). Allocation-free, so that a
    /// step can check it.
    fn check_workspace(&self, workspace: &ElementWorkspace) -> Result<(), StepError> {
        if let Some(reason) = workspace.invalid() {
            return Err(self.invalid(reason.to_string()));
        }
        if workspace.dim() != self.system.dim() || !workspace.fits(&self.system) {
            return Err(self.invalid(format!(
                "the workspace was built for another system ({} coordinates, {} families of \
                 elements); this one has {} coordinates",
                workspace.dim(),
                workspace.elements().len(),
                self.system.dim()
            )));
        }
        Ok(())
    }

    fn invalid(&self, reason: String) -> StepError {
        StepError::InvalidSize { reason }
    }

    /// `Ok` for a continuous Lagrangian; a discrete one has no energy.
    fn require_continuous(&self) -> Result<(), StepError> {
        if self.system.continuous() {
            Ok(())
        } else {
            Err(StepError::Unsupported {
                what: "the energy of a discrete Lagrangian (it has no velocity to evaluate an \
                       energy at; write the system as a continuous Lagrangian with a rule)",
            })
        }
    }

    /// The sizes, the state's dimensions and the stencils against each other.
    fn check_sizes(&self, state: &ElementState) -> Result<(), StepError> {
        let sizes = self.system.sizes();
        let min = self.system.min_size();
        if let Some((i, &n)) = sizes.iter().enumerate().find(|&(_, &n)| n < min) {
            let names = self.system.size_names();
            let name = names
                .get(i)
                .map_or_else(|| format!("#{i}"), |s| s.to_string());
            return Err(self.invalid(format!(
                "size `{name}` = {n} is below the smallest size the stencils allow ({min})"
            )));
        }
        let n = self.system.dim();
        if state.q.len() != n || state.p.len() != n {
            return Err(self.invalid(format!(
                "the state has {} coordinates and {} momenta; the system with sizes {:?} has {n}",
                state.q.len(),
                state.p.len(),
                sizes
            )));
        }
        let elements =
            stencils::check_stencils(&self.system).map_err(|reason| self.invalid(reason))?;
        stencils::check_memory(n, &elements)
    }
}

/// Whether `additional` more copies of `state`'s vectors can be allocated, as a trajectory
/// keeps them: asked for and given back at once (as [`stencils::check_memory`] asks for a run's
/// workspace), so that a trajectory longer than memory holds is the typed
/// [`StepError::OutOfMemory`] rather than an abort in the allocator. The arithmetic is in
/// `u128`, so no count overflows it.
pub(crate) fn reserve_states(state: &ElementState, additional: usize) -> Result<(), StepError> {
    let words = (state.q.len() as u128 + state.p.len() as u128) * additional as u128;
    if crate::linalg::allocatable(words.saturating_mul(8)) {
        Ok(())
    } else {
        Err(StepError::OutOfMemory {
            what: format!(
                "{additional} more states of {} coordinates kept by the trajectory",
                state.q.len()
            ),
            bytes: 8 * words,
        })
    }
}

/// What a failed [`ElementIntegrator`] run keeps.
pub type ElementError = IntegrationError<ElementTrajectory>;
