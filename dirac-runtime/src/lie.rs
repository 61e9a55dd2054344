//! Configurations on rotation groups: rotations `R ∈ SO(3)`, directions `n ∈ S²` and ordinary
//! scalars, stepped by a Lie group variational integrator whose residual and Jacobian
//! `#[reduced_lagrangian]` derives from the discrete Lagrangian `L_d(q0, q1)` written with
//! matrices and vectors (`rotation(R)`, `direction(n)` in the attribute).
//!
//! # Charts centred at the current point
//!
//! The configuration space is `Q = R^m × SO(3)^a × (S²)^b`, of dimension `N = m + 3a + 2b`. At
//! each point `q` the integrator works in a chart `φ_q : R^N → Q` centred at `q` (`φ_q(0) = q`),
//! one block per coordinate:
//!
//! * a scalar `x`: `φ(ξ) = x + ξ`;
//! * a rotation `R`: `φ(ξ) = R cay(ξ)`, with the Cayley retraction
//!   `cay(ξ) = (I − ξ̂/2)⁻¹ (I + ξ̂/2) = I + 4/(4 + |ξ|²) (ξ̂ + ξ̂²/2)` ([`cayley`]), so that
//!   `dφ(0) η = R η̂`: the left trivialization, the body frame;
//! * a direction `n`, stored with an orthonormal frame `F = [e1 e2 n]` (a rotation whose third
//!   column is `n`, see [`frame`]): `φ(a, b) = (n + a e1 + b e2) / √(1 + a² + b²)`, the frame
//!   carried along by the rotation that takes `e3` to `u = (a, b, 1)/√(1 + a² + b²)` by the
//!   shortest arc, so `dφ(0) (a, b) = a e1 + b e2`.
//!
//! A configuration is stored as its point `q ∈ R^P` (scalars, then for each rotation its 9
//! entries row by row, for each direction its frame's 9 entries row by row, in the order the
//! attribute declares them), and a step's unknown is the chart coordinate `z ∈ R^N` of the next
//! point. The step is a smooth map of `z` (no angle, no chart switch) and the next point is
//! formed by products of rotations: it stays on the group to round-off with no projection.
//!
//! # The equations
//!
//! The momentum `p ∈ R^N` is the covector in the chart at its centre, `p·η = ⟨P, dφ_q(0) η⟩`:
//! for a rotation the body momentum `Π ∈ so(3)*` (`⟨P, R η̂⟩ = Π·η`), for a direction the
//! components `e_a·P` of its momentum in the frame, for a scalar its momentum. With the
//! variations `δq_k = dφ_{q_k}(0) η_k` — on a rotation `δR = R η̂`, the variations of the Lie
//! group variational integrators (Lee, Leok & McClamroch 2005, 2007; Bou-Rabee & Marsden 2009
//! for the Hamilton–Pontryagin form; Lee, Leok & McClamroch 2009 on two-spheres) — the discrete
//! Hamilton–Pontryagin principle `δ Σ L_d(q_k, q_{k+1}) = 0` gives
//! `D2 L_d(q_{k−1}, q_k)·δq_k + D1 L_d(q_k, q_{k+1})·δq_k = 0` for every `η_k`, and with the
//! discrete Legendre transforms in the trivialization the position–momentum form of the discrete
//! Lagrange–Dirac equations (the paper's Definition 2.7, on a Lie group):
//!
//! ```text
//! p_k · η     = −D1 L_d(q_k, q_{k+1}) · dφ_{q_k}(0) η
//! p_{k+1} · η =  D2 L_d(q_k, q_{k+1}) · dφ_{q_{k+1}}(0) η        for every η ∈ R^N.
//! ```
//!
//! On a rotation these read `Π_k = −T*_e L_{R_k}(D1 L_d)`, `Π_{k+1} = T*_e L_{R_{k+1}}(D2 L_d)`,
//! with `T*_e L_R(G) = vee(Rᵀ G − Gᵀ R)` for the matrix `G` of partial derivatives in the
//! entries. A step knows `(q_k, p_k)` and solves the first line for `z`, `q_{k+1} = φ_{q_k}(z)`:
//! with the chart Lagrangian `L̃(ξ0, ξ1) = L_d(φ_{q_k}(ξ0), φ_{q_k}(ξ1))` the residual is
//! `R(z) = D1 L̃(0, z) + p_k` and its Jacobian `D2 D1 L̃(0, z)`, both straight-line code the
//! compiler derives through `φ` ([`LieLagrangian`]); the second line is then explicit.
//!
//! For the free rigid body `L_d = tr((I − F_k) J_d)/h`, `F_k = R_kᵀ R_{k+1}`,
//! `J_d = ½ tr(J) I − J`, the first line is the LGVI's `h Π_k = vee(F_k J_d − J_d F_kᵀ)` and the
//! second `Π_{k+1} = F_kᵀ Π_k`.
//!
//! # What is kept
//!
//! The step map is the discrete flow of `L_d`: symplectic on `T*Q`. If `L_d` is invariant under
//! the rotation of every rotation and direction coordinate together (`R ↦ g R`, `n ↦ g n`,
//! scalars fixed), differentiating `L_d(g q_k, g q_{k+1}) = L_d(q_k, q_{k+1})` in `g` along `ζ`
//! gives `D1 L_d·(ζ̂ q_k) + D2 L_d·(ζ̂ q_{k+1}) = 0`; with `ζ̂ R = R (Rᵀζ)^` and
//! `⟨P, ζ × n⟩ = ζ·(n × P)` this is the discrete Noether theorem for the spatial angular momentum
//! ([`LieIntegrator::spatial_momentum`])
//!
//! ```text
//! π = Σ_rotations R Π + Σ_directions n × P,        π_{k+1} = π_k,
//! ```
//!
//! kept up to the residual Newton accepts (not bit for bit: the update is not a copy). A
//! rotation about one axis only (a body in a uniform field) keeps that component of `π`.
//!
//! A symmetric `L_d` (`L_d(q0, q1; −h) = −L_d(q1, q0; h)`, e.g. the rigid body's above or a
//! midpoint-type rule) gives a symmetric step of order 2, which the compositions of
//! [`crate::compose`] raise to order 4 and 6.

use nalgebra::{Matrix3, SVector, Vector3};

use crate::error::{StepError, Steps};
use crate::linalg::LinearSolver;
use crate::newton::{self, inf_norm, NewtonOptions};
use crate::reduced::trajectory_accessors;
use crate::state::IntoVector;
use crate::stepper::{
    check_inputs, predicted_increment, same_step, step_error, Collect, History, StepStats,
    StepStatsExt, Stepper,
};

/// What one declared coordinate of a system on rotation groups is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CoordinateKind {
    /// An ordinary real coordinate (`shape(x)`): one entry of the point, one of the chart.
    Scalar,
    /// A real coordinate whose translations are a symmetry (`group(x)`, checked at compile
    /// time): its momentum `μ` obeys the discrete Noether balance explicitly,
    /// `μ_{k+1} = μ_k + f_d^− + f_d^+` — copied bit for bit without forces.
    Group,
    /// A rotation matrix `R ∈ SO(3)` (`rotation(R)`): 9 entries of the point (row by row), 3 of
    /// the chart (the body-frame algebra element).
    Rotation,
    /// A unit vector `n ∈ S²` (`direction(n)`): the 9 entries of its frame `[e1 e2 n]` (row by
    /// row), 2 of the chart.
    Direction,
}

impl CoordinateKind {
    /// Entries of the stored point.
    pub const fn point_len(self) -> usize {
        match self {
            CoordinateKind::Scalar | CoordinateKind::Group => 1,
            CoordinateKind::Rotation | CoordinateKind::Direction => 9,
        }
    }

    /// Entries of the chart (and of the momentum).
    pub const fn chart_len(self) -> usize {
        match self {
            CoordinateKind::Scalar | CoordinateKind::Group => 1,
            CoordinateKind::Rotation => 3,
            CoordinateKind::Direction => 2,
        }
    }
}

/// A discrete Lagrangian on `Q = R^m × SO(3)^a × (S²)^b`, with the straight-line functions of
/// its Lie group variational step (see the [module documentation](self)). `P` is the length of a
/// stored point, `N = dim Q` that of the chart and the momentum. `#[reduced_lagrangian]`
/// implements it for a function with `rotation(..)` or `direction(..)` coordinates.
pub trait LieLagrangian<const P: usize, const N: usize>: Clone + Send + Sync + 'static {
    /// The coordinates, in the order of the point and the chart.
    const COORDINATES: &'static [(&'static str, CoordinateKind)];
    /// Names of the scalar parameters, in declaration order.
    const PARAMETERS: &'static [&'static str];
    /// Names of the controls (`controls(..)` in the attribute): parameters a control law sets
    /// before every step, in the order a control vector lists them.
    const CONTROLS: &'static [&'static str] = &[];

    /// The linear algebra of the steps: dense LU on the stack for small `N`.
    type Linear: LinearSolver<Vector = SVector<f64, N>>;

    /// A workspace for [`Self::Linear`], built once per run.
    fn linear_solver(&self) -> Self::Linear;

    /// `L_d(q0, q1)`, evaluated by the user's own function body.
    fn lagrangian(&self, q0: &SVector<f64, P>, q1: &SVector<f64, P>) -> f64;

    /// The time step `h`.
    fn time_step(&self) -> f64;

    /// The same system at time step `h` (any nonzero `h`, negative included for the stages of a
    /// composition).
    fn with_time_step(&self, h: f64) -> Self;

    /// The parameter values, in the order of [`Self::PARAMETERS`].
    fn parameter_values(&self) -> Vec<f64>;

    /// The same system with its controls set to `u` (in the order of [`Self::CONTROLS`]; the
    /// caller checks the length).
    fn with_controls(&self, u: &[f64]) -> Self {
        let _ = u;
        self.clone()
    }

    /// The point `φ_q(z)` of the chart centred at `q`.
    fn retract(&self, q: &SVector<f64, P>, z: &SVector<f64, N>) -> SVector<f64, P>;

    /// `R(z) = D1 L̃(0, z) + p_k`, the step residual in the chart centred at `q_k`.
    fn residual(
        &self,
        q_k: &SVector<f64, P>,
        p_k: &SVector<f64, N>,
        z: &SVector<f64, N>,
    ) -> SVector<f64, N>;

    /// `R(z)` and its exact Jacobian `D2 D1 L̃(0, z)`, from one straight-line function.
    fn residual_jacobian(
        &self,
        q_k: &SVector<f64, P>,
        p_k: &SVector<f64, N>,
        z: &SVector<f64, N>,
    ) -> (SVector<f64, N>, <Self::Linear as LinearSolver>::Matrix);

    /// The momentum update `p_{k+1} = D2 L_d(q_k, q_{k+1}) · dφ_{q_{k+1}}(0)` at
    /// `q_{k+1} = φ_{q_k}(z)` (`+ f_d^+` with forces); for a [`CoordinateKind::Group`]
    /// coordinate the Noether balance `p_k + f_d^− + f_d^+`, which reads `p_k`.
    fn momentum(
        &self,
        q_k: &SVector<f64, P>,
        p_k: &SVector<f64, N>,
        z: &SVector<f64, N>,
    ) -> SVector<f64, N>;

    /// The partial derivatives of the step from `(q_k, p_k)` to `q_{k+1} = φ_{q_k}(z)` that its
    /// sensitivity needs ([`LiePartials`]); `None` where the compiler emitted none (systems on
    /// the sparse backend).
    fn step_partials(
        &self,
        _q_k: &SVector<f64, P>,
        _p_k: &SVector<f64, N>,
        _z: &SVector<f64, N>,
    ) -> Option<LiePartials> {
        None
    }
}

/// The partial derivatives of a step in the charts at its nominal points (see
/// [`LieIntegrator::sensitivity`]): the step from `q' = φ_{q_k}(δ)` with momentum `p` to
/// `q'_{k+1} = φ_{q_{k+1}}(w)` solves `R̃(w; δ, p, u) = 0` (with `∂R̃/∂p = I`) and sets
/// `p_{k+1} = O(w; δ, u)`; each block is a derivative at `δ = 0`, `w = 0`.
#[derive(Clone, Debug, PartialEq)]
pub struct LiePartials {
    /// `∂R̃/∂w`.
    pub r_w: nalgebra::DMatrix<f64>,
    /// `∂R̃/∂δ`.
    pub r_y: nalgebra::DMatrix<f64>,
    /// `∂R̃/∂u`.
    pub r_u: nalgebra::DMatrix<f64>,
    /// `∂O/∂w`.
    pub o_w: nalgebra::DMatrix<f64>,
    /// `∂O/∂δ`.
    pub o_y: nalgebra::DMatrix<f64>,
    /// `∂O/∂u`.
    pub o_u: nalgebra::DMatrix<f64>,
}

/// A state `(q, p)` of a system on rotation groups: the stored point `q` (see
/// [`CoordinateKind`]) and the momentum `p` in the chart at `q` (body momenta for rotations,
/// frame components for directions).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LieState<const P: usize, const N: usize> {
    /// The stored point.
    pub q: SVector<f64, P>,
    /// The momentum in the chart centred at `q`.
    pub p: SVector<f64, N>,
}

impl<const P: usize, const N: usize> LieState<P, N> {
    /// The state from a stored point and a momentum (arrays or nalgebra vectors). The emitted
    /// `<Name>Config::to_point` and `<Name>Momentum::to_chart` build them from matrices and
    /// vectors.
    pub fn new(q: impl IntoVector<SVector<f64, P>>, p: impl IntoVector<SVector<f64, N>>) -> Self {
        Self {
            q: q.into_vector(),
            p: p.into_vector(),
        }
    }

    /// Whether every entry is finite.
    pub fn is_finite(&self) -> bool {
        self.q.iter().chain(self.p.iter()).all(|v| v.is_finite())
    }
}

/// A trajectory `(q_k, p_k)`, `k = 0..=steps()`, of a system on rotation groups.
#[derive(Clone, Debug, PartialEq)]
pub struct LieTrajectory<const P: usize, const N: usize> {
    /// The integrator's time step `h` (the default step of a run).
    pub h: f64,
    /// `states[k]` is the state at `times[k]`.
    pub states: Vec<LieState<P, N>>,
    /// `times[k] = t_k`.
    pub times: Vec<f64>,
    /// Newton statistics of each step.
    pub stats: Vec<StepStats>,
}

impl<const P: usize, const N: usize> LieTrajectory<P, N> {
    trajectory_accessors!(LieState<P, N>);
}

impl<const P: usize, const N: usize> Steps for LieTrajectory<P, N> {
    fn completed_steps(&self) -> usize {
        self.steps()
    }
}

impl<L, const P: usize, const N: usize> Collect<LieIntegrator<L, P, N>> for LieTrajectory<P, N>
where
    L: LieLagrangian<P, N>,
{
    fn start(integrator: &LieIntegrator<L, P, N>, steps: usize) -> Self {
        LieTrajectory {
            h: integrator.system.time_step(),
            states: crate::stepper::reserved(steps.saturating_add(1)),
            times: crate::stepper::reserved(steps.saturating_add(1)),
            stats: crate::stepper::reserved(steps),
        }
    }

    fn push(&mut self, t: f64, state: &LieState<P, N>, record: Option<&StepStats>) {
        self.states.push(*state);
        self.times.push(t);
        if let Some(stats) = record {
            self.stats.push(*stats);
        }
    }
}

/// The workspace of a run: the linear solver and the chart coordinates of the last two steps,
/// which Newton's guess extrapolates.
#[derive(Clone, Debug)]
pub struct LieWorkspace<B, const N: usize> {
    #[doc(hidden)]
    pub solver: B,
    #[doc(hidden)]
    pub history: History<SVector<f64, N>>,
}

/// The Lie group variational integrator of a [`LieLagrangian`] (see the
/// [module documentation](self)).
#[derive(Clone, Debug)]
pub struct LieIntegrator<L, const P: usize, const N: usize> {
    system: L,
    options: NewtonOptions,
}

/// Largest accepted `‖RᵀR − I‖∞` (and `|det R − 1|`) of an initial rotation or frame.
pub const MANIFOLD_TOLERANCE: f64 = 1e-10;

impl<L, const P: usize, const N: usize> LieIntegrator<L, P, N>
where
    L: LieLagrangian<P, N>,
{
    /// The integrator of `system` with Newton's `options`.
    pub fn new(system: L, options: NewtonOptions) -> Self {
        const {
            assert!(
                P >= N,
                "a stored point has at least as many entries as the chart"
            )
        };
        Self { system, options }
    }

    /// The system being integrated.
    pub fn system(&self) -> &L {
        &self.system
    }

    /// The Newton options.
    pub fn options(&self) -> &NewtonOptions {
        &self.options
    }

    /// The spatial angular momentum `π = Σ R Π + Σ n × P` of the rotation and direction
    /// coordinates: the momentum map of rotating all of them together, conserved when `L_d` is
    /// invariant under that rotation (see the [module documentation](self)).
    pub fn spatial_momentum(&self, state: &LieState<P, N>) -> Vector3<f64> {
        let mut pi = Vector3::zeros();
        for block in blocks::<L, P, N>() {
            match block.kind {
                CoordinateKind::Scalar | CoordinateKind::Group => {}
                CoordinateKind::Rotation => {
                    let r = matrix_at(&state.q, block.point);
                    let body = Vector3::new(
                        state.p[block.chart],
                        state.p[block.chart + 1],
                        state.p[block.chart + 2],
                    );
                    pi += r * body;
                }
                CoordinateKind::Direction => {
                    let f = matrix_at(&state.q, block.point);
                    let ambient =
                        f.column(0) * state.p[block.chart] + f.column(1) * state.p[block.chart + 1];
                    pi += f.column(2).cross(&ambient);
                }
            }
        }
        pi
    }

    /// The chart coordinates `z` of `point` in the chart centred at `base`, the inverse of
    /// [`LieLagrangian::retract`] (`φ_base(z) = point`): `x − x_base` for a scalar,
    /// `cay⁻¹(R_baseᵀ R) = 2 vee(F − Fᵀ)/(1 + tr F)` for a rotation (any rotation by less than
    /// π), `(n·e1, n·e2)/(n·n_base)` in the frame of `base` for a direction (any `n` in the
    /// open hemisphere about `n_base`).
    pub fn chart_coordinates(
        &self,
        base: &SVector<f64, P>,
        point: &SVector<f64, P>,
    ) -> SVector<f64, N> {
        let mut z = SVector::<f64, N>::zeros();
        for block in blocks::<L, P, N>() {
            let (at, c) = (block.point, block.chart);
            match block.kind {
                CoordinateKind::Scalar | CoordinateKind::Group => z[c] = point[at] - base[at],
                CoordinateKind::Rotation => {
                    let f = matrix_at(base, at).transpose() * matrix_at(point, at);
                    let xi = vee(&f) * (4.0 / (1.0 + f.trace()));
                    z[c] = xi.x;
                    z[c + 1] = xi.y;
                    z[c + 2] = xi.z;
                }
                CoordinateKind::Direction => {
                    let (f0, f1) = (matrix_at(base, at), matrix_at(point, at));
                    let n = f1.column(2);
                    let along = n.dot(&f0.column(2));
                    z[c] = n.dot(&f0.column(0)) / along;
                    z[c + 1] = n.dot(&f0.column(1)) / along;
                }
            }
        }
        z
    }

    /// The sensitivity of step `k` from `state` to `next` under the controls `u` (empty: the
    /// system's own), in the charts at the two points: the state near `(q, p)` is
    /// `(φ_q(δ), p)` — `δ` the chart coordinate, `p` the momentum in the chart at the perturbed
    /// point — so [`Sensitivity::state`](crate::Sensitivity::state) is `∂(w, p_{k+1})/∂(δ, p_k)` (each `N × N` block in the
    /// order of [`LieLagrangian::COORDINATES`]) and [`Sensitivity::control`](crate::Sensitivity::control) is
    /// `∂(w, p_{k+1})/∂u`, where `q'_{k+1} = φ_{q_{k+1}}(w)`. By the implicit-function theorem
    /// on the step residual in these charts ([`LiePartials`]): `dw = −R̃_w⁻¹ (R̃_δ dδ + dp + R̃_u
    /// du)`, `dp_{k+1} = O_w dw + O_δ dδ + O_u du`.
    ///
    /// A typed error for a system compiled without its partials (the sparse backend), a step
    /// whose chart Jacobian is singular, or controls of the wrong number.
    pub fn sensitivity(
        &self,
        k: usize,
        state: &LieState<P, N>,
        next: &LieState<P, N>,
        u: &[f64],
    ) -> Result<crate::Sensitivity, StepError> {
        let owned = self.system_at(k, self.system.time_step(), u)?;
        let sys = owned.as_ref().unwrap_or(&self.system);
        let z = self.chart_coordinates(&state.q, &next.q);
        let parts = sys
            .step_partials(&state.q, &state.p, &z)
            .ok_or(StepError::Unsupported {
                what: "step sensitivities: the compiler emits the step's partial derivatives for \
                       systems on rotation groups of at most 16 dimensions",
            })?;
        let m = L::CONTROLS.len();
        let cols = 2 * N + m;
        let mut rhs = nalgebra::DMatrix::<f64>::zeros(N, cols);
        rhs.view_mut((0, 0), (N, N)).copy_from(&parts.r_y);
        for i in 0..N {
            rhs[(i, N + i)] = 1.0;
        }
        rhs.view_mut((0, 2 * N), (N, m)).copy_from(&parts.r_u);
        let residual = crate::newton::inf_norm(&sys.residual(&state.q, &state.p, &z));
        let lu = parts.r_w.clone().lu();
        let dw = -lu
            .solve(&rhs)
            .ok_or(StepError::SingularJacobian { step: k, residual })?;
        let mut dp = &parts.o_w * &dw;
        let mut view = dp.view_mut((0, 0), (N, N));
        view += &parts.o_y;
        let mut view = dp.view_mut((0, 2 * N), (N, m));
        view += &parts.o_u;
        let mut full = nalgebra::DMatrix::<f64>::zeros(2 * N, cols);
        full.view_mut((0, 0), (N, cols)).copy_from(&dw);
        full.view_mut((N, 0), (N, cols)).copy_from(&dp);
        Ok(crate::Sensitivity {
            state: full.view((0, 0), (2 * N, 2 * N)).into_owned(),
            control: full.view((0, 2 * N), (2 * N, m)).into_owned(),
        })
    }

    /// Takes step `k` from `state` with the controls `u` in a fresh workspace and returns the
    /// new state, the step's statistics and its [`Self::sensitivity`].
    pub fn step_sensitivity(
        &self,
        k: usize,
        state: &LieState<P, N>,
        u: &[f64],
    ) -> Result<(LieState<P, N>, StepStats, crate::Sensitivity), StepError> {
        let (next, stats) = self.step_with(&mut self.workspace(), k, self.time_step(), state, u)?;
        let sensitivity = self.sensitivity(k, state, &next, u)?;
        Ok((next, stats, sensitivity))
    }

    /// The largest departure from the manifold over the rotation and direction coordinates of
    /// `q`: `‖RᵀR − I‖∞` of each rotation and frame (for a direction this bounds `||n| − 1|`).
    pub fn manifold_defect(&self, q: &SVector<f64, P>) -> f64 {
        blocks::<L, P, N>()
            .filter(|b| matches!(b.kind, CoordinateKind::Rotation | CoordinateKind::Direction))
            .map(|b| orthogonality_defect(&matrix_at(q, b.point)))
            .fold(0.0, f64::max)
    }

    /// The largest relative defect `|L_d(q0, q1; −h) + L_d(q1, q0; h)|` over sample pairs
    /// `(q, φ_q(δ d_j))` and the reversed pairs, for three fixed directions `d_j` and
    /// `δ = 0.05`: zero for a symmetric discrete Lagrangian, up to round-off.
    pub fn symmetry_defect(&self, q: &SVector<f64, P>) -> f64 {
        let backward = self.system.with_time_step(-self.system.time_step());
        let mut worst: f64 = 0.0;
        for j in 0..3 {
            let d = SVector::<f64, N>::from_fn(|i, _| {
                0.05 * (1.0 + 0.37 * j as f64 + 0.61 * i as f64 + 0.13 * (i * j) as f64).sin()
            });
            let near = self.system.retract(q, &d);
            for (q0, q1) in [(q, &near), (&near, q)] {
                let minus = backward.lagrangian(q0, q1);
                let plus = self.system.lagrangian(q1, q0);
                let scale = minus.abs().max(plus.abs()).max(f64::MIN_POSITIVE);
                let defect = (minus + plus).abs() / scale;
                worst = if defect.is_nan() || worst.is_nan() {
                    f64::NAN
                } else {
                    worst.max(defect)
                };
            }
        }
        worst
    }

    /// The system of step `k`: `None` (the system itself) for its own step without controls,
    /// otherwise a copy at step `h` with the controls `u` set; the typed error of step `k` for
    /// controls of the wrong number or not finite.
    fn system_at(&self, k: usize, h: f64, u: &[f64]) -> Result<Option<L>, StepError> {
        if u.is_empty() && same_step(h, self.system.time_step()) {
            return Ok(None);
        }
        let mut system = if u.is_empty() {
            self.system.clone()
        } else {
            if u.len() != L::CONTROLS.len() {
                return Err(StepError::InvalidControls {
                    step: k,
                    expected: L::CONTROLS.len(),
                    found: u.len(),
                });
            }
            if u.iter().any(|v| !v.is_finite()) {
                return Err(StepError::NonFinite {
                    step: k,
                    what: "the controls",
                    residual: f64::NAN,
                });
            }
            self.system.with_controls(u)
        };
        if !same_step(h, system.time_step()) {
            system = system.with_time_step(h);
        }
        Ok(Some(system))
    }

    /// The step of size `h` from `state`, Newton starting at `guess` for the chart coordinate of
    /// the next point.
    fn solve_step(
        &self,
        solver: &mut L::Linear,
        k: usize,
        h: f64,
        state: &LieState<P, N>,
        guess: &SVector<f64, N>,
        u: &[f64],
    ) -> Result<(LieState<P, N>, SVector<f64, N>, StepStats), StepError> {
        let owned = self.system_at(k, h, u)?;
        let sys = owned.as_ref().unwrap_or(&self.system);
        let (q, p) = (&state.q, &state.p);
        let rho = inf_norm(p);
        let (mut z, mut r, mut jacobian) = (*guess, SVector::<f64, N>::zeros(), None);
        let solution = newton::solve_in(
            solver,
            &mut z,
            &mut r,
            &mut jacobian,
            rho,
            &self.options,
            |z, r| *r = sys.residual(q, p, z),
            |z, r, j| {
                let (r_z, j_z) = sys.residual_jacobian(q, p, z);
                *r = r_z;
                *j = Some(j_z);
            },
        )
        .map_err(|failure| step_error(k, failure))?;
        let q_next = sys.retract(q, &z);
        let mut p_next = sys.momentum(q, p, &z);
        compensate::<L, P, N>(q, &q_next, &r, &mut p_next);
        let next = LieState {
            q: q_next,
            p: p_next,
        };
        if !next.is_finite() {
            return Err(StepError::NonFinite {
                step: k,
                what: "the updated state",
                residual: solution.residual,
            });
        }
        Ok((
            next,
            z,
            StepStats::from_solution(&solution, self.options.residual_tolerance(rho)),
        ))
    }
}

impl<L, const P: usize, const N: usize> Stepper for LieIntegrator<L, P, N>
where
    L: LieLagrangian<P, N>,
{
    type State = LieState<P, N>;
    type Record = StepStats;
    type Workspace = LieWorkspace<L::Linear, N>;
    type Trajectory = LieTrajectory<P, N>;

    fn time_step(&self) -> f64 {
        self.system.time_step()
    }

    /// The common checks (time step, finite parameters and state) and every rotation and frame
    /// orthogonal with determinant 1 to [`MANIFOLD_TOLERANCE`].
    fn check(&self, initial: &LieState<P, N>) -> Result<(), StepError> {
        check_inputs(
            self.system.time_step(),
            &self.system.parameter_values(),
            initial.is_finite(),
        )?;
        for block in blocks::<L, P, N>() {
            if matches!(block.kind, CoordinateKind::Scalar | CoordinateKind::Group) {
                continue;
            }
            let m = matrix_at(&initial.q, block.point);
            let (defect, det) = (orthogonality_defect(&m), m.determinant());
            if defect > MANIFOLD_TOLERANCE || (det - 1.0).abs() > MANIFOLD_TOLERANCE {
                let what = match block.kind {
                    CoordinateKind::Rotation => "the rotation",
                    _ => "the frame of the direction",
                };
                return Err(StepError::OffManifold {
                    reason: format!(
                        "{what} `{}` has |MᵀM − I| = {defect:.3e} and det M = {det}, tolerance \
                         {MANIFOLD_TOLERANCE:.0e}; build rotations with `dirac::lie::cayley`, \
                         nalgebra's `Rotation3`, or directions with `Config::to_point`",
                        block.name
                    ),
                });
            }
        }
        Ok(())
    }

    fn control_dim(&self) -> usize {
        L::CONTROLS.len()
    }

    fn workspace(&self) -> Self::Workspace {
        LieWorkspace {
            solver: self.system.linear_solver(),
            history: History::default(),
        }
    }

    /// Newton starts from the chart coordinate of the last steps, extrapolated (zero on the
    /// first step of a run).
    fn step_with(
        &self,
        workspace: &mut Self::Workspace,
        k: usize,
        h: f64,
        state: &LieState<P, N>,
        u: &[f64],
    ) -> Result<(LieState<P, N>, StepStats), StepError> {
        let guess = predicted_increment(&workspace.history, h).unwrap_or_else(SVector::zeros);
        let (next, z, stats) = self.solve_step(&mut workspace.solver, k, h, state, &guess, u)?;
        workspace.history.push(z, h);
        Ok((next, stats))
    }
}

impl<L, const P: usize, const N: usize> crate::compose::SelfAdjoint for LieIntegrator<L, P, N>
where
    L: LieLagrangian<P, N>,
{
    fn with_time_step(&self, h: f64) -> Self {
        Self::new(self.system.with_time_step(h), self.options)
    }

    fn symmetry_defect(&self, at: &LieState<P, N>) -> f64 {
        LieIntegrator::symmetry_defect(self, &at.q)
    }
}

/// Carries Newton's remaining residual `r = D1 L̃(0, z) + p_k` into the new momentum, so that
/// the discrete Noether balance holds to round-off and not only to the accepted residual: the
/// step solved `p̃_k = −D1 L̃ = p_k − r` exactly, and `J(q_{k+1}, p_{k+1}) = J(q_k, p̃_k)` by
/// invariance. Adding to each block of `p_{k+1}` the residual transported to `q_{k+1}` — `r`
/// itself for a scalar (whose momentum map is `p`), `F_kᵀ r` for a rotation with
/// `F_k = R_kᵀ R_{k+1}` (whose momentum map is `R Π`, and `R_{k+1} F_kᵀ r = R_k r`) — restores
/// `J(q_{k+1}, p_{k+1}) = J(q_k, p_k)` for every symmetry that translates scalars or rotates
/// rotation coordinates. A direction's residual is carried by its frame (`e_a^{k+1}` components
/// of `r_1 e_1^k + r_2 e_2^k`), which keeps its momentum map to the size of `r`. The change is of
/// the size of the accepted residual, within the step's own tolerance.
fn compensate<L: LieLagrangian<P, N>, const P: usize, const N: usize>(
    q: &SVector<f64, P>,
    q_next: &SVector<f64, P>,
    r: &SVector<f64, N>,
    p_next: &mut SVector<f64, N>,
) {
    for block in blocks::<L, P, N>() {
        let c = block.chart;
        match block.kind {
            CoordinateKind::Scalar => p_next[c] += r[c],
            // Its momentum is the explicit Noether balance, exact as it is.
            CoordinateKind::Group => {}
            CoordinateKind::Rotation => {
                let f = matrix_at(q, block.point).transpose() * matrix_at(q_next, block.point);
                let t = f.transpose() * Vector3::new(r[c], r[c + 1], r[c + 2]);
                p_next[c] += t.x;
                p_next[c + 1] += t.y;
                p_next[c + 2] += t.z;
            }
            CoordinateKind::Direction => {
                let (f0, f1) = (matrix_at(q, block.point), matrix_at(q_next, block.point));
                let ambient = f0.column(0) * r[c] + f0.column(1) * r[c + 1];
                p_next[c] += f1.column(0).dot(&ambient);
                p_next[c + 1] += f1.column(1).dot(&ambient);
            }
        }
    }
}

/// One coordinate's place in the point and the chart.
struct Block {
    name: &'static str,
    kind: CoordinateKind,
    point: usize,
    chart: usize,
}

fn blocks<L: LieLagrangian<P, N>, const P: usize, const N: usize>() -> impl Iterator<Item = Block> {
    let (mut point, mut chart) = (0, 0);
    L::COORDINATES.iter().map(move |&(name, kind)| {
        let block = Block {
            name,
            kind,
            point,
            chart,
        };
        point += kind.point_len();
        chart += kind.chart_len();
        block
    })
}

/// The 3 × 3 matrix stored row by row at `q[at..at + 9]`.
fn matrix_at<const P: usize>(q: &SVector<f64, P>, at: usize) -> Matrix3<f64> {
    Matrix3::from_fn(|i, j| q[at + 3 * i + j])
}

/// `‖MᵀM − I‖∞` (largest entry).
pub fn orthogonality_defect(m: &Matrix3<f64>) -> f64 {
    (m.transpose() * m - Matrix3::identity()).amax()
}

/// `ξ̂`, the skew-symmetric matrix with `ξ̂ v = ξ × v`.
pub fn hat(xi: &Vector3<f64>) -> Matrix3<f64> {
    xi.cross_matrix()
}

/// `vee(A)`, the vector of the skew-symmetric part of `A`: `vee(ξ̂) = ξ`, and
/// `vee(A) = vee((A − Aᵀ)/2)` in general.
pub fn vee(a: &Matrix3<f64>) -> Vector3<f64> {
    Vector3::new(
        0.5 * (a[(2, 1)] - a[(1, 2)]),
        0.5 * (a[(0, 2)] - a[(2, 0)]),
        0.5 * (a[(1, 0)] - a[(0, 1)]),
    )
}

/// The Cayley retraction `cay(ξ) = (I − ξ̂/2)⁻¹ (I + ξ̂/2) = I + 4/(4 + |ξ|²) (ξ̂ + ξ̂²/2)`: a
/// rotation for every `ξ ∈ R³`, with `cay(ξ) = exp(ξ̂) + O(|ξ|³)`.
pub fn cayley(xi: &Vector3<f64>) -> Matrix3<f64> {
    let s = hat(xi);
    Matrix3::identity() + (4.0 / (4.0 + xi.norm_squared())) * (s + 0.5 * s * s)
}

/// An orthonormal frame `[e1 e2 n]` (a rotation) whose third column is the unit vector `n` (`n`
/// is normalized first): the branch-free construction of Duff et al. (2017), continuous except
/// where `n_z` changes sign with `n_x = n_y = 0`.
pub fn frame(n: &Vector3<f64>) -> Matrix3<f64> {
    let n = n.normalize();
    let sign = 1.0_f64.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    let e1 = Vector3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    let e2 = Vector3::new(b, sign + n.y * n.y * a, -n.y);
    Matrix3::from_columns(&[e1, e2, n])
}

/// A rotation stored row by row, as in a point.
pub fn rows(m: &Matrix3<f64>) -> [f64; 9] {
    [
        m[(0, 0)],
        m[(0, 1)],
        m[(0, 2)],
        m[(1, 0)],
        m[(1, 1)],
        m[(1, 2)],
        m[(2, 0)],
        m[(2, 1)],
        m[(2, 2)],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cayley_is_a_rotation_close_to_the_exponential() {
        let xi = Vector3::new(0.3, -0.2, 0.5);
        let c = cayley(&xi);
        assert!(orthogonality_defect(&c) < 1e-15);
        assert!((c.determinant() - 1.0).abs() < 1e-15);
        // cay(ξ) = exp(ξ̂) + O(|ξ|³): the defect shrinks by 8 when ξ halves.
        let err = |s: f64| {
            let x = xi * s;
            (cayley(&x) - nalgebra::Rotation3::new(x).into_inner()).amax()
        };
        let ratio = err(0.02) / err(0.01);
        assert!((ratio - 8.0).abs() < 0.1, "ratio {ratio}");
    }

    #[test]
    fn frames_are_rotations_with_n_last() {
        for n in [
            Vector3::new(0.0, 0.0, 1.0),
            Vector3::new(0.0, 0.0, -1.0),
            Vector3::new(0.3, -0.4, 0.5),
            Vector3::new(-1.0, 2.0, -0.1),
        ] {
            let f = frame(&n);
            assert!(orthogonality_defect(&f) < 1e-15, "{n}");
            assert!((f.determinant() - 1.0).abs() < 1e-15, "{n}");
            assert!((f.column(2) - n.normalize()).amax() < 1e-16);
        }
    }

    #[test]
    fn hat_and_vee_are_inverse() {
        let xi = Vector3::new(0.1, -2.0, 3.5);
        assert_eq!(vee(&hat(&xi)), xi);
        assert_eq!(
            hat(&xi) * Vector3::new(1.0, 2.0, 3.0),
            xi.cross(&Vector3::new(1.0, 2.0, 3.0))
        );
    }
}
