//! Sensitivities of one step: the derivative of the step map with respect to the state and the
//! controls, what trajectory optimisation (DMOC), LQR and Kalman filters need.
//!
//! A step solves `R(z; y, a, u) = 0` for its unknowns `z` given the step's data — `y` entering
//! nonlinearly (`x_k` reduced, `q_k` unreduced), the momenta `a` entering linearly (`w_k`, `μ_k`
//! reduced; `p_k` unreduced) — and the controls `u`, then forms explicit updates `o(y, z, u)`
//! (`w_{k+1}` and the group impulse `μ_{k+1} − μ_k`; `p_{k+1}`). By the implicit-function
//! theorem, where `J = ∂R/∂z` is invertible,
//!
//! ```text
//! dz = −J⁻¹ (∂R/∂y dy + ∂R/∂a da + ∂R/∂u du),    do = ∂o/∂y dy + ∂o/∂z dz + ∂o/∂u du,
//! ```
//!
//! with every partial derivative differentiated at compile time ([`StepPartials`]) and `J` the
//! step's own Jacobian, factored by the system's backend (dense or sparse). The reduced step then
//! adds the explicit lines of eqs. (4.6)/(4.8): `x_{k+1} = z_x`, `μ_{k+1} = μ_k + impulse`,
//! `g_{k+1} = g_k ± u_g + B (x_{k+1} − x_k)`.

use nalgebra::{DMatrix, Dim, Matrix, RawStorage, SVector};

use crate::error::StepError;
use crate::linalg::{LinearSolver, NewtonVector};
use crate::model::system_at;
use crate::reduced::{ReducedIntegrator, ReducedStep};
use crate::state::{ReducedState, UnreducedState};
use crate::stepper::{StepAt, Stepper};
use crate::system::{join, Reduced, Side, Unreduced, Variant};
use crate::UnreducedIntegrator;

/// The partial derivatives of one step's equations that its sensitivity needs, each a dense
/// matrix (rows: residual components or updates; columns: the variables): for a reduced step
/// `y = x_k` (`S`), `z = (x_{k+1}, u_g)` (`N`), updates `o = (w_{k+1}, μ_{k+1} − μ_k)`
/// (`S + K`); for an unreduced step `y = q_k`, `z = q_{k+1}`, `o = p_{k+1}` (`N` each); `m`
/// controls. Written by the emitted code ([`Reduced::step_partials`],
/// [`Unreduced::unreduced_step_partials`]), which sets only the entries that are not zero by
/// construction.
#[derive(Clone, Debug, PartialEq)]
pub struct StepPartials {
    /// `∂R/∂y`.
    pub r_y: DMatrix<f64>,
    /// `∂R/∂u`.
    pub r_u: DMatrix<f64>,
    /// `∂o/∂y`.
    pub o_y: DMatrix<f64>,
    /// `∂o/∂z`.
    pub o_z: DMatrix<f64>,
    /// `∂o/∂u`.
    pub o_u: DMatrix<f64>,
}

impl StepPartials {
    /// Zero matrices for `n_z` unknowns (and residual components), `n_y` data, `n_o` updates
    /// and `m` controls.
    pub fn zeros(n_z: usize, n_y: usize, n_o: usize, m: usize) -> Self {
        Self {
            r_y: DMatrix::zeros(n_z, n_y),
            r_u: DMatrix::zeros(n_z, m),
            o_y: DMatrix::zeros(n_o, n_y),
            o_z: DMatrix::zeros(n_o, n_z),
            o_u: DMatrix::zeros(n_o, m),
        }
    }
}

/// The derivative of one step `s_{k+1} = Φ(s_k, u_k)`: `state = ∂s_{k+1}/∂s_k` and
/// `control = ∂s_{k+1}/∂u_k`. The state is ordered `(x, w, μ, g)` for a reduced step
/// (`2S + 2K` components) and `(q, p)` for an unreduced one (`2N`).
#[derive(Clone, Debug, PartialEq)]
pub struct Sensitivity {
    /// `∂s_{k+1}/∂s_k`.
    pub state: DMatrix<f64>,
    /// `∂s_{k+1}/∂u_k` (one column per control).
    pub control: DMatrix<f64>,
}

impl Sensitivity {
    /// The sensitivity of an unreduced step `(q, p) ↦ (q', p')` with no controls, from its
    /// blocks `M = [[∂q'/∂q, ∂q'/∂p], [∂p'/∂q, ∂p'/∂p]]` (fixed- or run-time-sized matrices).
    pub fn from_blocks<R, C, St>(
        dq_dq: &Matrix<f64, R, C, St>,
        dq_dp: &Matrix<f64, R, C, St>,
        dp_dq: &Matrix<f64, R, C, St>,
        dp_dp: &Matrix<f64, R, C, St>,
    ) -> Self
    where
        R: Dim,
        C: Dim,
        St: RawStorage<f64, R, C>,
    {
        let n = dq_dq.nrows();
        let mut state = DMatrix::zeros(2 * n, 2 * n);
        for (block, (r, c)) in
            [dq_dq, dq_dp, dp_dq, dp_dp]
                .into_iter()
                .zip([(0, 0), (0, n), (n, 0), (n, n)])
        {
            for i in 0..n {
                for j in 0..n {
                    state[(r + i, c + j)] = block[(i, j)];
                }
            }
        }
        Self {
            state,
            control: DMatrix::zeros(2 * n, 0),
        }
    }

    /// Block `(r, c)` of an unreduced step's state matrix (`N = rows / 2`).
    fn block(&self, r: usize, c: usize) -> DMatrix<f64> {
        let n = self.state.nrows() / 2;
        self.state.view((r * n, c * n), (n, n)).into_owned()
    }

    /// `∂q_{k+1}/∂q_k` of an unreduced step.
    pub fn dq_dq(&self) -> DMatrix<f64> {
        self.block(0, 0)
    }

    /// `∂q_{k+1}/∂p_k` of an unreduced step.
    pub fn dq_dp(&self) -> DMatrix<f64> {
        self.block(0, 1)
    }

    /// `∂p_{k+1}/∂q_k` of an unreduced step.
    pub fn dp_dq(&self) -> DMatrix<f64> {
        self.block(1, 0)
    }

    /// `∂p_{k+1}/∂p_k` of an unreduced step.
    pub fn dp_dp(&self) -> DMatrix<f64> {
        self.block(1, 1)
    }

    /// The sensitivity of `self ∘ first` (first `first`, then `self`) by the chain rule:
    /// `state = A A₁`, and with the same controls held over both steps `control = A B₁ + B`
    /// (a step with no control columns depends on none: `A B₁`, or `B`). States of different
    /// sizes, or steps with different numbers of controls, are [`StepError::InvalidSize`].
    pub fn compose(&self, first: &Sensitivity) -> Result<Sensitivity, StepError> {
        let invalid = |reason: String| StepError::InvalidSize { reason };
        if self.state.ncols() != first.state.nrows() {
            return Err(invalid(format!(
                "a step from {} state components composed after one to {}",
                self.state.ncols(),
                first.state.nrows()
            )));
        }
        let control = match (first.control.ncols(), self.control.ncols()) {
            (a, b) if a == b => &self.state * &first.control + &self.control,
            (0, _) => self.control.clone(),
            (_, 0) => &self.state * &first.control,
            (a, b) => {
                return Err(invalid(format!(
                    "steps with {a} and {b} controls composed: the controls must be the same"
                )))
            }
        };
        Ok(Sensitivity {
            state: &self.state * &first.state,
            control,
        })
    }

    /// How far an unreduced step's `Mᵀ Ω M = Ω` (`Ω = [[0, I], [−I, 0]]`) is from holding,
    /// relative to the size of the terms. In blocks `M = [[A, B], [C, D]]` the condition is
    /// `AᵀC = CᵀA`, `BᵀD = DᵀB` and `AᵀD − CᵀB = I`; each residual is divided by the size of the
    /// products it cancels (`‖A‖‖C‖`, `‖B‖‖D‖`, `max(1, ‖A‖‖D‖ + ‖C‖‖B‖)`, max-norms of
    /// entries), so the result is dimensionless — the blocks can differ by many orders of
    /// magnitude (`∂p/∂q ≈ m l²/h`). Zero for a symplectic map; round-off gives ~1e-15 to
    /// 1e-12. NaN when the state matrix is not square with an even number of rows.
    pub fn symplecticity_defect(&self) -> f64 {
        if !self.state.is_square() || !self.state.nrows().is_multiple_of(2) {
            return f64::NAN;
        }
        let (a, b, c, d) = (self.dq_dq(), self.dq_dp(), self.dp_dq(), self.dp_dp());
        let n = a.nrows() as f64;
        let rel = |m: DMatrix<f64>, scale: f64| m.amax() / scale.max(f64::MIN_POSITIVE);
        let qq = rel(
            a.transpose() * &c - c.transpose() * &a,
            n * a.amax() * c.amax(),
        );
        let pp = rel(
            b.transpose() * &d - d.transpose() * &b,
            n * b.amax() * d.amax(),
        );
        let qp = rel(
            a.transpose() * &d
                - c.transpose() * &b
                - DMatrix::<f64>::identity(a.nrows(), a.nrows()),
            (n * (a.amax() * d.amax() + c.amax() * b.amax())).max(1.0),
        );
        qq.max(pp).max(qp)
    }
}

/// `J = ∂R/∂z` factored, or the typed error of step `k`.
fn factored<B: LinearSolver>(
    mut solver: B,
    r: &B::Vector,
    j: &B::Matrix,
    k: usize,
) -> Result<B, StepError> {
    let residual = r.components().iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    solver
        .factor(j)
        .map_err(|_| StepError::SingularJacobian { step: k, residual })?;
    Ok(solver)
}

/// `−J⁻¹ rhs` for each column of `rhs` (`N` rows), as the columns of an `N × cols` matrix.
fn solve_columns<B, const N: usize>(solver: &mut B, rhs: &DMatrix<f64>) -> DMatrix<f64>
where
    B: LinearSolver<Vector = SVector<f64, N>>,
{
    let mut out = DMatrix::zeros(N, rhs.ncols());
    for c in 0..rhs.ncols() {
        let b = SVector::<f64, N>::from_iterator(rhs.column(c).iter().copied());
        let x = solver.solve(&b);
        for r in 0..N {
            out[(r, c)] = -x[r];
        }
    }
    out
}

/// The error of a system compiled without its step partials.
fn unsupported() -> StepError {
    StepError::Unsupported {
        what:
            "step sensitivities: this system was compiled without its step partials (they are \
               emitted for systems with forces or controls); declare `controls(...)` or \
               `force = ...`, or use `UnreducedIntegrator::step_jacobian` for a conservative system",
    }
}

impl<L, D, const S: usize, const K: usize, const N: usize> ReducedIntegrator<L, D, S, K, N>
where
    D: Side,
    L: Reduced<D, S, K, N>,
{
    /// The sensitivity of step `k` from `state` to `next` (with `record`, what the step
    /// returned) under the controls `u` (empty: the system's own): `∂(x, w, μ, g)_{k+1} /
    /// ∂((x, w, μ, g)_k, u_k)` by the implicit-function theorem on the step residual (see the
    /// [module documentation](crate::sensitivity)). Costs one factorization of the step
    /// Jacobian and `2S + K + m` solves with it.
    pub fn sensitivity(
        &self,
        k: usize,
        state: &ReducedState<S, K>,
        next: &ReducedState<S, K>,
        record: &ReducedStep<K>,
        u: &[f64],
    ) -> Result<Sensitivity, StepError> {
        let owned = system_at(self.system(), k, self.system().time_step(), u)?;
        let sys = owned.as_ref().unwrap_or(self.system());
        let m = sys.control_count();
        let (x, w, mu) = (&state.x, &state.w, &state.mu);
        let z = join::<S, K, N>(&next.x, &record.group_unknown);
        let mut p = StepPartials::zeros(N, S, S + K, m);
        if !sys.step_partials(x, w, mu, &z, &mut p) {
            return Err(unsupported());
        }
        let (r, j) = sys.residual_jacobian(x, w, mu, &z);
        let mut solver = factored(sys.linear_solver(), &r, &j, k)?;
        // ∂R/∂(x_k, w_k, μ_k, u): w_k enters the shape rows with +1, μ_k the group rows with
        // −1 for (+) and +1 for (−) (see `Plus` and `Minus`).
        let mu_sign = match D::VARIANT {
            Variant::Plus => -1.0,
            Variant::Minus => 1.0,
        };
        let cols = 2 * S + K + m;
        let mut rhs = DMatrix::zeros(N, cols);
        rhs.view_mut((0, 0), (N, S)).copy_from(&p.r_y);
        for i in 0..S {
            rhs[(i, S + i)] = 1.0;
        }
        for j in 0..K {
            rhs[(S + j, 2 * S + j)] = mu_sign;
        }
        rhs.view_mut((0, 2 * S + K), (N, m)).copy_from(&p.r_u);
        let dz = solve_columns(&mut solver, &rhs);
        // Updates: o = (w_{k+1}, impulse) as functions of (x_k, z, u).
        let mut d_o = &p.o_z * &dz;
        let mut view = d_o.view_mut((0, 0), (S + K, S));
        view += &p.o_y;
        let mut view = d_o.view_mut((0, 2 * S + K), (S + K, m));
        view += &p.o_u;
        let b = sys.connection();
        let sign = D::group_increment(SVector::<f64, 1>::repeat(1.0))[0];
        let n_s = 2 * S + 2 * K;
        let mut full = DMatrix::zeros(n_s, cols);
        // x_{k+1} = z_x.
        full.view_mut((0, 0), (S, cols))
            .copy_from(&dz.view((0, 0), (S, cols)));
        // w_{k+1}, μ_{k+1} − μ_k.
        full.view_mut((S, 0), (S + K, cols)).copy_from(&d_o);
        for j in 0..K {
            full[(2 * S + j, 2 * S + j)] += 1.0;
        }
        // g_{k+1} = g_k ± u_g + B (x_{k+1} − x_k).
        let g_rows = 2 * S + K;
        for j in 0..K {
            for c in 0..cols {
                let mut v = sign * dz[(S + j, c)];
                for i in 0..S {
                    v += b[(j, i)] * dz[(i, c)];
                }
                if c < S {
                    v -= b[(j, c)];
                }
                full[(g_rows + j, c)] = v;
            }
        }
        // Columns: (x, w, μ) then u; g_k enters only through g_{k+1} = g_k + ….
        let mut state_m = DMatrix::zeros(n_s, n_s);
        state_m
            .view_mut((0, 0), (n_s, 2 * S + K))
            .copy_from(&full.view((0, 0), (n_s, 2 * S + K)));
        for j in 0..K {
            state_m[(g_rows + j, g_rows + j)] = 1.0;
        }
        let control = full.view((0, 2 * S + K), (n_s, m)).into_owned();
        Ok(Sensitivity {
            state: state_m,
            control,
        })
    }

    /// Takes step `k` from `state` with the controls `u` (empty: the system's own) in a fresh
    /// workspace and returns the new state, the step's record and its [`Sensitivity`].
    pub fn step_sensitivity(
        &self,
        k: usize,
        state: &ReducedState<S, K>,
        u: &[f64],
    ) -> Result<(ReducedState<S, K>, ReducedStep<K>, Sensitivity), StepError> {
        let at = StepAt::new(k, self.time_step()).with_controls(u);
        let (next, record) = self.step_with(&mut self.workspace(), at, state)?;
        let sensitivity = self.sensitivity(k, state, &next, &record, u)?;
        Ok((next, record, sensitivity))
    }
}

impl<L, const S: usize, const K: usize, const N: usize> UnreducedIntegrator<L, S, K, N>
where
    L: Unreduced<S, K, N>,
{
    /// The sensitivity `∂(q, p)_{k+1} / ∂((q, p)_k, u_k)` of step `k` from `state` to `next`
    /// under the controls `u` (empty: the system's own), by the implicit-function theorem on
    /// `R(q_{k+1}) = D1 L_d + p_k + f_d^− = 0` (see the [module
    /// documentation](crate::sensitivity)).
    pub fn sensitivity(
        &self,
        k: usize,
        state: &UnreducedState<N>,
        next: &UnreducedState<N>,
        u: &[f64],
    ) -> Result<Sensitivity, StepError> {
        let owned = system_at(self.system(), k, self.system().time_step(), u)?;
        let sys = owned.as_ref().unwrap_or(self.system());
        let m = sys.control_count();
        let (q, p_k, z) = (&state.q, &state.p, &next.q);
        let mut p = StepPartials::zeros(N, N, N, m);
        if !sys.unreduced_step_partials(q, p_k, z, &mut p) {
            return Err(unsupported());
        }
        let (r, j) = sys.unreduced_residual_jacobian(q, p_k, z);
        let mut solver = factored(sys.unreduced_linear_solver(), &r, &j, k)?;
        let cols = 2 * N + m;
        let mut rhs = DMatrix::zeros(N, cols);
        rhs.view_mut((0, 0), (N, N)).copy_from(&p.r_y);
        for i in 0..N {
            rhs[(i, N + i)] = 1.0;
        }
        rhs.view_mut((0, 2 * N), (N, m)).copy_from(&p.r_u);
        let dz = solve_columns(&mut solver, &rhs);
        let mut d_p = &p.o_z * &dz;
        let mut view = d_p.view_mut((0, 0), (N, N));
        view += &p.o_y;
        let mut view = d_p.view_mut((0, 2 * N), (N, m));
        view += &p.o_u;
        let mut full = DMatrix::zeros(2 * N, cols);
        full.view_mut((0, 0), (N, cols)).copy_from(&dz);
        full.view_mut((N, 0), (N, cols)).copy_from(&d_p);
        Ok(Sensitivity {
            state: full.view((0, 0), (2 * N, 2 * N)).into_owned(),
            control: full.view((0, 2 * N), (2 * N, m)).into_owned(),
        })
    }

    /// Takes step `k` from `state` with the controls `u` in a fresh workspace and returns the
    /// new state, the step's statistics and its [`Sensitivity`].
    pub fn step_sensitivity(
        &self,
        k: usize,
        state: &UnreducedState<N>,
        u: &[f64],
    ) -> Result<(UnreducedState<N>, crate::StepStats, Sensitivity), StepError> {
        let at = StepAt::new(k, self.time_step()).with_controls(u);
        let (next, stats) = self.step_with(&mut self.workspace(), at, state)?;
        let sensitivity = self.sensitivity(k, state, &next, u)?;
        Ok((next, stats, sensitivity))
    }
}
