//! The Lie group variational integrator: the step on the charts of the
//! [module documentation](crate::lie), its checks, sensitivities and the Noether-exact momentum
//! update.

use std::cell::RefCell;
use std::marker::PhantomData;

use nalgebra::allocator::Allocator;
use nalgebra::{Const, DefaultAllocator, Dim, OVector, Vector3};

use super::model::LieHistory;
use super::{blocks, zeros, LieModel, LieStateOf, LieTrajectoryIn, SpatialMomentum};
pub use crate::constrained::UnreducedForm;
use crate::error::StepError;
use crate::linalg::LinearSolver;
use crate::newton::{self, slice_inf_norm, NewtonOptions};
use crate::stepper::{check_inputs, step_error, system_at, StepAt, StepStats, Stepper};
use crate::system::Variant;

/// The workspace of a run, built once per run: the linear solver, the chart coordinates of the
/// last two steps (which Newton's guess extrapolates), and the buffers a step writes its
/// unknown, residual, chart coordinate and Jacobian into — and a reduced step its start's
/// momentum and the symmetry's generator —, so that a step on vectors sized at run time
/// allocates nothing.
pub struct LieWorkspaceOf<B: LinearSolver, N: Dim>
where
    DefaultAllocator: Allocator<N>,
{
    /// What the step on the charts uses.
    pub(super) step: StepBuffers<B, N>,
    /// A reduced step's start momentum (the state's, with the symmetry's part set).
    pub(super) momentum: OVector<f64, N>,
    /// The generator of the symmetry in the chart (rotations about an axis).
    pub(super) generator: OVector<f64, N>,
}

/// The solver, the history and the buffers of the step on the charts.
pub(super) struct StepBuffers<B: LinearSolver, N: Dim>
where
    DefaultAllocator: Allocator<N>,
{
    solver: B,
    history: LieHistory<N>,
    /// Newton's unknown (`z`, or `w` for the (−) equations).
    unknown: OVector<f64, N>,
    /// The residual.
    residual: OVector<f64, N>,
    /// The chart coordinate `z` of the unknown.
    chart: OVector<f64, N>,
    /// The Jacobian's memory.
    jacobian: Option<B::Matrix>,
}

/// The workspace of a run at a fixed chart size `N` (see [`LieWorkspaceOf`]).
pub type LieWorkspace<B, const N: usize> = LieWorkspaceOf<B, Const<N>>;

impl<B: LinearSolver + std::fmt::Debug, N: Dim> std::fmt::Debug for LieWorkspaceOf<B, N>
where
    DefaultAllocator: Allocator<N>,
{
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LieWorkspace")
            .field("solver", &self.step.solver)
            .field("history", &self.step.history)
            .finish_non_exhaustive()
    }
}

impl<B: LinearSolver, N: Dim> LieWorkspaceOf<B, N>
where
    DefaultAllocator: Allocator<N>,
{
    /// The workspace of a run with chart size `n` on `solver`.
    pub(super) fn new(solver: B, n: N) -> Self {
        Self {
            step: StepBuffers {
                solver,
                history: LieHistory::new(n),
                unknown: zeros(n),
                residual: zeros(n),
                chart: zeros(n),
                jacobian: None,
            },
            momentum: zeros(n),
            generator: zeros(n),
        }
    }
}

/// The Lie group variational integrator of a [`LieModel`] (see the
/// [module documentation](crate::lie)) in the form `F` of its equations — unreduced
/// ([`UnreducedForm`]: [`LieIntegratorOf`]) or reduced by the system's rotation symmetry
/// ([`ReducedForm`](super::ReducedForm): [`ReducedLieIntegratorOf`](super::ReducedLieIntegratorOf))
/// —, at sizes `P` (a stored point) and `N` (the chart), fixed or chosen at run time. One type
/// for both forms: the step on the charts, its checks, the run API, compositions and the
/// diagnostics are written once; the form says what differs ([`LieForm`]).
#[derive(Clone, Debug)]
pub struct LieIntegratorIn<L, P: Dim, N: Dim, F> {
    system: L,
    options: NewtonOptions,
    variant: Variant,
    sizes: PhantomData<fn() -> (P, N)>,
    form: PhantomData<F>,
}

/// The Lie group variational integrator of a [`LieModel`] on the whole configuration space, at
/// any size (see [`LieIntegratorIn`]); [`LieIntegrator<L, P, N>`](LieIntegrator) names it at
/// fixed sizes.
pub type LieIntegratorOf<L, P, N> = LieIntegratorIn<L, P, N, UnreducedForm>;

/// The Lie group variational integrator of a [`LieLagrangian`](super::LieLagrangian) at fixed
/// sizes (see [`LieIntegratorIn`]).
pub type LieIntegrator<L, const P: usize, const N: usize> = LieIntegratorOf<L, Const<P>, Const<N>>;

/// Where the two forms of the integrator on rotation groups differ: the state a step maps, the
/// checks of a run's first state beyond the unreduced ones, and the step (the unreduced step's
/// on the charts, with the reduced equations and the symmetry's momentum set before and after
/// for the reduced form). Sealed: [`UnreducedForm`] and [`ReducedForm`](super::ReducedForm).
pub trait LieForm<L, P: Dim, N: Dim>:
    super::sealed::Sealed + Copy + std::fmt::Debug + Send + Sync + 'static
where
    L: LieModel<P, N>,
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    /// The state a step maps: [`LieStateOf`], or [`ReducedLieStateOf`](super::ReducedLieStateOf).
    type State: Clone + std::fmt::Debug + PartialEq + Send + Sync + 'static;

    /// The stored point of `state`.
    fn point(state: &Self::State) -> &OVector<f64, P>;

    /// The checks of a run's first state `initial` ([`Stepper::check`]).
    fn check(
        integrator: &LieIntegratorIn<L, P, N, Self>,
        initial: &Self::State,
    ) -> Result<(), StepError>;

    /// Step `at` from `state` into `next` ([`Stepper::step_into`]).
    fn step_into(
        integrator: &LieIntegratorIn<L, P, N, Self>,
        workspace: &mut LieWorkspaceOf<L::Linear, N>,
        at: StepAt<'_>,
        state: &Self::State,
        next: &mut Self::State,
    ) -> Result<StepStats, StepError>;
}

impl<L, P: Dim, N: Dim> LieForm<L, P, N> for UnreducedForm
where
    L: LieModel<P, N>,
    DefaultAllocator: Allocator<P> + Allocator<N>,
    LieStateOf<P, N>: Send + Sync,
{
    type State = LieStateOf<P, N>;

    #[inline]
    fn point(state: &LieStateOf<P, N>) -> &OVector<f64, P> {
        &state.q
    }

    /// The common checks (time step, finite parameters and state) and every coordinate on its
    /// manifold ([`Group::check`](super::Group::check)).
    fn check(
        integrator: &LieIntegratorOf<L, P, N>,
        initial: &LieStateOf<P, N>,
    ) -> Result<(), StepError> {
        integrator.check_unreduced(initial)
    }

    /// The unreduced step on the charts (see the [module documentation](crate::lie)).
    #[inline]
    fn step_into(
        integrator: &LieIntegratorOf<L, P, N>,
        workspace: &mut LieWorkspaceOf<L::Linear, N>,
        at: StepAt<'_>,
        state: &LieStateOf<P, N>,
        next: &mut LieStateOf<P, N>,
    ) -> Result<StepStats, StepError> {
        integrator.unreduced_step_into(workspace, at, state, next)
    }
}

impl<L, P: Dim, N: Dim, F> LieIntegratorIn<L, P, N, F> {
    /// The system being integrated.
    pub fn system(&self) -> &L {
        &self.system
    }

    /// The Newton options.
    pub fn options(&self) -> &NewtonOptions {
        &self.options
    }

    /// The same integrator (system, Newton options, side) in the form `G`.
    pub(super) fn in_form<G>(&self) -> LieIntegratorIn<L, P, N, G>
    where
        L: Clone,
    {
        LieIntegratorIn {
            system: self.system.clone(),
            options: self.options,
            variant: self.variant,
            sizes: PhantomData,
            form: PhantomData,
        }
    }
}

impl<L, P: Dim, N: Dim, F> LieIntegratorIn<L, P, N, F>
where
    L: LieModel<P, N>,
    F: LieForm<L, P, N>,
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    /// The integrator of `system` with Newton's `options` in the form `F`: the (+) equations,
    /// solved for the chart coordinate `z` of the next point about the current one — for the
    /// reduced form the reduced equations of the system's symmetry (see
    /// [`crate::lie::reduced`]).
    pub fn new(system: L, options: NewtonOptions) -> Self {
        Self {
            system,
            options,
            variant: Variant::Plus,
            sizes: PhantomData,
            form: PhantomData,
        }
    }

    crate::stepper::plus_or_minus!(
        /// The (−) integrator of Definition 2.8 on the charts: solved for the chart coordinate `w`
        /// of the current point about the next one, `q_k = φ_{q_{k+1}}(w)` (see the
        /// [module documentation](crate::lie#the-equations), where the (−) equations are shown to be
        /// the (+) equations at `z = −w`: the same steps). Reduced by every rotation, these are
        /// the equations of the reduced (−) Lagrangian `l_{d−}(G, s0, s1) = L_d(G, s0, I, s1)`
        /// with `G = R_{k+1}ᵀ R_k = cay(w)`.
    );
}

impl<L, P: Dim, N: Dim, F> LieIntegratorIn<L, P, N, F>
where
    L: LieModel<P, N>,
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    /// The spatial angular momentum `π = Σ R Π + Σ n × P + Σ (R Π + x × p)` of the rotation,
    /// direction and pose coordinates: the momentum map of rotating all of them together,
    /// conserved when `L_d` is invariant under that rotation (see the
    /// [module documentation](crate::lie)).
    pub fn spatial_momentum(&self, state: &LieStateOf<P, N>) -> Vector3<f64> {
        self.rigid_momentum(state).angular
    }

    /// The linear momentum `ℓ = Σ p` of the pose coordinates: the momentum map of translating
    /// all of them together (`x ↦ x + a`), conserved when `L_d` is invariant under that
    /// translation; zero without poses.
    pub fn linear_momentum(&self, state: &LieStateOf<P, N>) -> Vector3<f64> {
        self.rigid_momentum(state).linear
    }

    /// Both parts of the momentum map of the rigid motions of space
    /// ([`Self::spatial_momentum`], [`Self::linear_momentum`]), each coordinate's
    /// [`Group::spatial_momentum`](super::Group::spatial_momentum) summed.
    pub fn rigid_momentum(&self, state: &LieStateOf<P, N>) -> SpatialMomentum {
        let (q, p) = (state.q.as_slice(), state.p.as_slice());
        let mut sum = SpatialMomentum::default();
        for b in blocks(&self.system) {
            let group = b.kind.group();
            sum += group.spatial_momentum(b.of_point(q), b.of_chart(p));
        }
        sum
    }

    /// The chart coordinates `z` of `point` in the chart centred at `base`, the inverse of
    /// [`LieModel::retract_into`] (`φ_base(z) = point`), block by block
    /// ([`Group::chart_inverse`](super::Group::chart_inverse)): `x − x_base` for a scalar,
    /// `cay⁻¹(R_baseᵀ R) = 2 vee(F − Fᵀ)/(1 + tr F)` for a rotation (any rotation by less than
    /// π), `(n·e1, n·e2)/(n·n_base)` in the frame of `base` for a direction (any `n` in the
    /// open hemisphere about `n_base`), both for a pose.
    pub fn chart_coordinates(
        &self,
        base: &OVector<f64, P>,
        point: &OVector<f64, P>,
    ) -> OVector<f64, N> {
        let mut z = zeros(self.system.dims().1);
        for block in blocks(&self.system) {
            block.kind.group().chart_inverse(
                block.of_point(base.as_slice()),
                block.of_point(point.as_slice()),
                block.of_chart_mut(z.as_mut_slice()),
            );
        }
        z
    }

    /// The largest departure from the manifold over the coordinates of `q`
    /// ([`Group::manifold_defect`](super::Group::manifold_defect)): `‖RᵀR − I‖∞` of each
    /// rotation, frame and pose's rotation (for a direction this bounds `||n| − 1|`).
    pub fn manifold_defect(&self, q: &OVector<f64, P>) -> f64 {
        blocks(&self.system)
            .map(|b| b.kind.group().manifold_defect(b.of_point(q.as_slice())))
            .fold(0.0, f64::max)
    }

    /// [`LieIntegratorOf::symmetry_defect`] in either form (what a composition checks,
    /// [`SelfAdjoint::symmetry_defect`](crate::compose::SelfAdjoint::symmetry_defect)).
    pub(super) fn defect_of_symmetry(&self, q: &OVector<f64, P>) -> f64 {
        let backward = self.system.with_time_step(-self.system.time_step());
        let mut worst: f64 = 0.0;
        let (p_dim, n_dim) = self.system.dims();
        for j in 0..3 {
            let d = OVector::<f64, N>::from_fn_generic(n_dim, nalgebra::U1, |i, _| {
                0.05 * crate::compose::sample_direction(j, i)
            });
            let mut near = zeros(p_dim);
            self.system.retract_into(q, &d, &mut near);
            for (q0, q1) in [(q, &near), (&near, q)] {
                let minus = backward.lagrangian(q0, q1);
                let plus = self.system.lagrangian(q1, q0);
                worst = crate::compose::worse_defect(worst, minus, plus);
            }
        }
        worst
    }

    /// A fresh workspace of a run ([`Stepper::workspace`]).
    pub(super) fn new_workspace(&self) -> LieWorkspaceOf<L::Linear, N> {
        LieWorkspaceOf::new(self.system.linear_solver(), self.system.dims().1)
    }

    /// The common checks (time step, finite parameters and state) and every coordinate on its
    /// manifold ([`Group::check`](super::Group::check): every rotation and frame orthogonal
    /// with determinant 1 to [`MANIFOLD_TOLERANCE`](super::MANIFOLD_TOLERANCE), every direction
    /// a unit vector): the unreduced integrator's checks of a run's first state, which the
    /// reduced one makes on the state's `(q, p)`.
    pub(super) fn check_unreduced(&self, initial: &LieStateOf<P, N>) -> Result<(), StepError> {
        check_inputs(
            self.system.time_step(),
            &self.system.parameter_values(),
            initial.all_finite(),
        )?;
        check_sizes(&self.system, (&initial.q, &initial.p))?;
        crate::model::refuse_domain(
            &self.system,
            "a declared domain on a system on rotation groups (only a system on vector spaces \
             checks one)",
        )?;
        for block in blocks(&self.system) {
            block
                .kind
                .group()
                .check(block.name, block.of_point(initial.q.as_slice()))
                .map_err(|reason| StepError::OffManifold { reason })?;
        }
        Ok(())
    }

    /// The unreduced step `at` from `state` into `next`, whose memory a run sized at run time
    /// reuses: [`Self::chart_step_into`] with the unreduced equations.
    #[inline]
    pub(super) fn unreduced_step_into(
        &self,
        workspace: &mut LieWorkspaceOf<L::Linear, N>,
        at: StepAt<'_>,
        state: &LieStateOf<P, N>,
        next: &mut LieStateOf<P, N>,
    ) -> Result<StepStats, StepError> {
        check_sizes(&self.system, (&state.q, &state.p))?;
        match_sizes((&state.q, &state.p), (&mut next.q, &mut next.p));
        self.chart_step_into(
            &mut workspace.step,
            at,
            (&state.q, &state.p),
            &StepEquations::UNREDUCED,
            (&mut next.q, &mut next.p),
        )
    }

    /// Step `k`, of size `h`, from `state` with the `equations` (the unreduced step's or a
    /// reduced one's), into `next`: Newton on the residual for the chart coordinate `z` of the
    /// next point — for the (−) equations on `w = −z`, the coordinate of the current point in the
    /// chart about the next, with the residual `−R(−w)` (whose Jacobian in `w` is `R`'s in `z`)
    /// — then the retraction, the momentum update and its compensation ([`compensate`]). Newton
    /// starts from the unknown of the workspace's last steps, extrapolated; on a run's first step
    /// from no motion, or for adaptive steps from [`super::adaptive::first_increment`]. After an
    /// adaptive step the monitor and the sign of the physical time step are checked. The unknown
    /// solved for (`z`, or `w`) joins the workspace's history. Every vector is the workspace's or
    /// `next`'s: a step allocates nothing.
    #[inline]
    pub(super) fn chart_step_into(
        &self,
        workspace: &mut StepBuffers<L::Linear, N>,
        step_at: StepAt<'_>,
        (q, p): (&OVector<f64, P>, &OVector<f64, N>),
        equations: &StepEquations<L, P, N>,
        (next_q, next_p): (&mut OVector<f64, P>, &mut OVector<f64, N>),
    ) -> Result<StepStats, StepError> {
        let StepBuffers {
            solver,
            history,
            unknown,
            residual,
            chart,
            jacobian,
        } = workspace;
        let StepAt { k, h, u } = step_at;
        let guessed = history.predict_into(h, unknown);
        let owned = system_at(&self.system, k, h, u)?;
        let sys = owned.as_ref().unwrap_or(&self.system);
        let rho = slice_inf_norm(p.as_slice());
        // z = s u and R̃(u) = s R(s u) with s = ±1: dR̃/du = R'(z), and the (+) residual is s R̃.
        let s = match self.variant {
            Variant::Plus => 1.0,
            Variant::Minus => -1.0,
        };
        if !guessed {
            match sys.time_index() {
                Some(_) => {
                    super::adaptive::first_increment(sys, q, p, h, equations, unknown);
                    *unknown *= s;
                }
                None => unknown.fill(0.0),
            }
        }
        // The (+) equations read the unknown itself (`s = 1`: the products by `s` are exact, so
        // they are left out); the (−) ones its negation, written into the workspace's `chart`.
        let minus = s < 0.0;
        let negated = RefCell::new(&mut *chart);
        let at = |u: &OVector<f64, N>| {
            let mut z = negated.borrow_mut();
            z.copy_from(u);
            **z *= s;
            z
        };
        let solution = newton::solve_in(
            solver,
            unknown,
            residual,
            jacobian,
            rho,
            &self.options,
            |u, r| {
                if minus {
                    (equations.residual)(sys, q, p, &at(u), r);
                    *r *= s;
                } else {
                    (equations.residual)(sys, q, p, u, r);
                }
            },
            |u, r, j| {
                if minus {
                    (equations.residual_jacobian)(sys, q, p, &at(u), r, j);
                    *r *= s;
                } else {
                    (equations.residual_jacobian)(sys, q, p, u, r, j);
                }
            },
        )
        .map_err(|failure| step_error(k, failure))?;
        let z: &OVector<f64, N> = if minus {
            chart.copy_from(unknown);
            *chart *= s;
            *residual *= s;
            chart
        } else {
            unknown
        };
        sys.retract_into(q, z, next_q);
        (equations.momentum)(sys, q, p, z, next_p);
        compensate(sys, q, next_q, residual, next_p);
        if !crate::state::all_finite(&[next_q.as_slice(), next_p.as_slice()]) {
            return Err(StepError::NonFinite {
                step: k,
                what: "the updated state",
                residual: solution.residual,
            });
        }
        history.push(unknown, h);
        Ok(StepStats::from_solution(
            &solution,
            self.options.residual_tolerance(rho),
        ))
    }
}

/// A function of the step on the charts at the chart coordinate `z`, given the system, the
/// stored point `q` and the momentum `p`, writing its residual or the momentum update.
type ChartFn<L, P, N> =
    fn(&L, &OVector<f64, P>, &OVector<f64, N>, &OVector<f64, N>, &mut OVector<f64, N>);

/// The residual and its Jacobian, as [`ChartFn`].
type ChartJacobianFn<L, P, N> = fn(
    &L,
    &OVector<f64, P>,
    &OVector<f64, N>,
    &OVector<f64, N>,
    &mut OVector<f64, N>,
    &mut Option<<<L as LieModel<P, N>>::Linear as LinearSolver>::Matrix>,
);

/// The equations a step on the charts solves, as the system's functions: the unreduced ones of
/// [`LieModel`] ([`Self::UNREDUCED`]) or the reduced ones of [`super::SymmetricLieModel`]. One
/// step serves both; a step is inlined where it is called with a constant table, so the calls
/// are direct.
pub(super) struct StepEquations<L: LieModel<P, N>, P: Dim, N: Dim>
where
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    /// The step residual at `z`.
    pub residual: ChartFn<L, P, N>,
    /// The residual and its Jacobian at `z`.
    pub residual_jacobian: ChartJacobianFn<L, P, N>,
    /// The momentum update at the solution `z`.
    pub momentum: ChartFn<L, P, N>,
}

impl<L: LieModel<P, N>, P: Dim, N: Dim> StepEquations<L, P, N>
where
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    /// The unreduced step's equations.
    pub const UNREDUCED: Self = Self {
        residual: L::residual_into,
        residual_jacobian: L::residual_jacobian_into,
        momentum: L::momentum_into,
    };
}

/// The one run API of both forms: what differs is the form's ([`LieForm`]).
impl<L, P: Dim, N: Dim, F> Stepper for LieIntegratorIn<L, P, N, F>
where
    L: LieModel<P, N>,
    F: LieForm<L, P, N>,
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    type State = F::State;
    type Record = StepStats;
    type Workspace = LieWorkspaceOf<L::Linear, N>;
    type Trajectory = LieTrajectoryIn<F::State>;

    fn time_step(&self) -> f64 {
        self.system.time_step()
    }

    fn physical_time(&self, state: &F::State) -> Option<f64> {
        super::adaptive::time_of(&self.system, F::point(state))
    }

    /// `g(q)` at the state's point.
    fn monitor(&self, at: StepAt<'_>, state: &F::State) -> Result<Option<f64>, StepError> {
        let owned = system_at(&self.system, at.k, at.h, at.u)?;
        Ok(owned
            .as_ref()
            .unwrap_or(&self.system)
            .monitor(F::point(state)))
    }

    /// The form's checks ([`LieForm::check`]): for both, the unreduced ones (time step, finite
    /// parameters and state, every coordinate on its manifold:
    /// [`Group::check`](super::Group::check)).
    fn check(&self, initial: &F::State) -> Result<(), StepError> {
        F::check(self, initial)
    }

    fn control_dim(&self) -> usize {
        self.system.control_count()
    }

    /// The same solver and history of steps for both forms.
    fn workspace(&self) -> Self::Workspace {
        self.new_workspace()
    }

    /// The form's step ([`LieForm::step_into`]): Newton starts from the chart coordinate of the
    /// last steps, extrapolated (on the first step of a run from no motion, or for adaptive
    /// steps from the motion at the step's physical size), into `next`, whose memory a run
    /// sized at run time reuses ([`Stepper::step_with`] is the trait's: a step into a copy of
    /// the state).
    #[inline]
    fn step_into(
        &self,
        workspace: &mut Self::Workspace,
        at: StepAt<'_>,
        state: &F::State,
        next: &mut F::State,
    ) -> Result<StepStats, StepError> {
        F::step_into(self, workspace, at, state, next)
    }
}

impl<L, P: Dim, N: Dim, F> crate::compose::SelfAdjoint for LieIntegratorIn<L, P, N, F>
where
    L: LieModel<P, N>,
    F: LieForm<L, P, N>,
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    fn with_time_step(&self, h: f64) -> Self {
        Self {
            system: self.system.with_time_step(h),
            ..self.clone()
        }
    }

    fn symmetry_defect(&self, at: &F::State) -> f64 {
        self.defect_of_symmetry(F::point(at))
    }
}

/// Carries Newton's remaining residual `r = D1 L̃(0, z) + p_k` into the new momentum, so that
/// the discrete Noether balance holds to round-off and not only to the accepted residual: the
/// step solved `p̃_k = −D1 L̃ = p_k − r` exactly, and `J(q_{k+1}, p_{k+1}) = J(q_k, p̃_k)` by
/// invariance. Adding to each block of `p_{k+1}` the residual transported to `q_{k+1}`
/// ([`Group::carry_residual`](super::Group::carry_residual)) — `r` itself for a scalar (whose
/// momentum map is `p`), `F_kᵀ r` for a rotation with `F_k = R_kᵀ R_{k+1}` (whose momentum map
/// is `R Π`, and `R_{k+1} F_kᵀ r = R_k r`), for a pose the same on `Π` corrected by the moved
/// position — restores `J(q_{k+1}, p_{k+1}) = J(q_k, p_k)` for every symmetry that translates
/// scalars, rotates rotation coordinates or moves poses rigidly. A direction's residual is
/// carried by its frame (`e_a^{k+1}` components of `r_1 e_1^k + r_2 e_2^k`), which keeps its
/// momentum map to the size of `r`; a group scalar's momentum is the explicit Noether balance,
/// exact as it is. The change is of the size of the accepted residual, within the step's own
/// tolerance.
///
/// First each block's new point is brought back onto its manifold
/// ([`Group::reproject`](super::Group::reproject): one Newton–Schulz step for a stored rotation
/// or a pose's attitude), so that the attitudes stay on `SO(3)` at the round-off of one step over any
/// number of steps, and the momentum maps that read them with them.
fn compensate<L: LieModel<P, N>, P: Dim, N: Dim>(
    sys: &L,
    q: &OVector<f64, P>,
    q_next: &mut OVector<f64, P>,
    r: &OVector<f64, N>,
    p_next: &mut OVector<f64, N>,
) where
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    for block in blocks(sys) {
        let group = block.kind.group();
        group.reproject(block.of_point_mut(q_next.as_mut_slice()));
        group.carry_residual(
            block.of_point(q.as_slice()),
            block.of_point(q_next.as_slice()),
            block.of_chart(r.as_slice()),
            block.of_chart_mut(p_next.as_mut_slice()),
        );
    }
}

/// Refuses a state whose sizes are not the system's: a typed error for a state sized at run
/// time; never taken at fixed sizes, where the types say it.
pub(super) fn check_sizes<L: LieModel<P, N>, P: Dim, N: Dim>(
    sys: &L,
    (q, momentum): (&OVector<f64, P>, &OVector<f64, N>),
) -> Result<(), StepError>
where
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    let (p, n) = sys.dims();
    if q.len() != p.value() || momentum.len() != n.value() {
        return Err(StepError::OffManifold {
            reason: format!(
                "the state has a point of {} entries and {} momenta; the system's point has {} \
                 and its chart {}",
                q.len(),
                momentum.len(),
                p.value(),
                n.value()
            ),
        });
    }
    Ok(())
}

/// Makes `next` of `state`'s sizes (a copy) where it is not, so that a step can write into it.
pub(super) fn match_sizes<P: Dim, N: Dim>(
    state: (&OVector<f64, P>, &OVector<f64, N>),
    next: (&mut OVector<f64, P>, &mut OVector<f64, N>),
) where
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    if next.0.len() != state.0.len() || next.1.len() != state.1.len() {
        next.0.clone_from(state.0);
        next.1.clone_from(state.1);
    }
}
