//! The DMOC swing-up of the cart-pole: single shooting, its exact Jacobian and the optimiser.
//! Shared by `examples/dmoc_cartpole.rs` and `tests/dmoc.rs` (each includes it with `#[path]`,
//! next to `common/cartpole.rs` as the module `cartpole`).
//!
//! The unknowns are the controls `u ∈ R^N`. A forward pass integrates the cart-pole
//! (`cartpole::baseline(h)`, reduced (+) midpoint rule) from hanging at rest,
//! `at_rest(π, 0)`, under the sequence `u`; the four equality constraints are that the final
//! reduced state `(x, w, μ, g)_N` is upright at rest, `at_rest(0, 0)` — `q_N = (0, 0)`,
//! `p_N = 0` of the CasADi transcription, since the connection `B` is zero. The cost is
//! `J = h Σ u_k²`. The constraint Jacobian `∂s_N/∂u` is chained exactly from the step
//! sensitivities `A_k = ∂s_{k+1}/∂s_k`, `B_k = ∂s_{k+1}/∂u_k`:
//! `∂s_N/∂u_k = A_{N−1} ⋯ A_{k+1} B_k`, accumulated backwards from `k = N − 1` (the adjoint
//! recursion, four rows at a time).
//!
//! The optimiser is [`solve`]: a Newton–KKT SQP on the lifted form of the same shooting problem
//! (see its documentation for why lifted, and `examples/dmoc_cartpole.rs` for why not a crate's
//! solver).

#![allow(dead_code)] // the example and the test use different parts

use std::f64::consts::PI;

use dirac::nalgebra::{DMatrix, DVector, SMatrix, SVector};
use dirac::prelude::*;

use super::cartpole::{at_rest, baseline, Cartpole};

/// The reduced (+) integrator of the cart-pole: one shape (`theta`), one group coordinate (`s`).
pub type Integrator = ReducedIntegrator<Cartpole, Plus, 1, 1, 2>;

/// The state `(x, w, μ, g)` of a reduced state, in the order of the sensitivities.
pub fn components(s: &ReducedState<1, 1>) -> SVector<f64, 4> {
    SVector::<f64, 4>::new(s.x[0], s.w[0], s.mu[0], s.g[0])
}

/// The swing-up problem: `N` steps over the horizon `T`.
pub struct Swingup {
    /// The integrator (time step `h = T / N`).
    pub integ: Integrator,
    /// Number of steps (and of controls).
    pub n: usize,
    /// The time step.
    pub h: f64,
    /// Hanging at rest, `(θ, s) = (π, 0)`.
    pub initial: ReducedState<1, 1>,
    /// Upright at rest, `(θ, s) = (0, 0)`, as `(x, w, μ, g)`.
    pub target: SVector<f64, 4>,
}

/// One forward pass and its constraint values.
pub struct Shot {
    /// The trajectory under `u`.
    pub traj: Trajectory<1, 1>,
    /// `c(u) = s_N − target`.
    pub defect: SVector<f64, 4>,
}

impl Swingup {
    /// The problem of `examples/dmoc/cartpole_casadi.py` with `N` steps over `T`.
    pub fn new(n: usize, t: f64) -> Self {
        let h = t / n as f64;
        Self {
            integ: ReducedIntegrator::plus(baseline(h), NewtonOptions::default()),
            n,
            h,
            initial: at_rest(PI, 0.0),
            target: components(&at_rest(0.0, 0.0)),
        }
    }

    /// `J(u) = h Σ u_k²`.
    pub fn cost(&self, u: &[f64]) -> f64 {
        self.h * u.iter().map(|v| v * v).sum::<f64>()
    }

    /// The forward pass under `u` and the defect `s_N − target`.
    pub fn shoot(&self, u: &[f64]) -> Result<Shot, String> {
        assert_eq!(u.len(), self.n, "one control per step");
        let traj = self
            .integ
            .run(self.initial)
            .steps(self.n)
            .controls(ControlSequence::flat(u, 1))
            .collect()
            .map_err(|e| format!("forward pass failed: {e}"))?;
        let defect = components(traj.last()) - self.target;
        Ok(Shot { traj, defect })
    }

    /// The exact constraint Jacobian `∂s_N/∂u` (4 × N) of the shot `shot` under `u`, chained
    /// backwards from the step sensitivities.
    pub fn jacobian(&self, u: &[f64], shot: &Shot) -> Result<DMatrix<f64>, String> {
        let traj = &shot.traj;
        let mut jac = DMatrix::zeros(4, self.n);
        // adj = ∂s_N/∂s_{k+1}, from the identity at k = N − 1.
        let mut adj = SMatrix::<f64, 4, 4>::identity();
        for k in (0..self.n).rev() {
            let record = ReducedStep {
                group_unknown: traj.group_unknowns[k],
                stats: traj.stats[k],
            };
            let sens = self
                .integ
                .sensitivity(k, &traj.states[k], &traj.states[k + 1], &record, &u[k..=k])
                .map_err(|e| format!("sensitivity of step {k}: {e}"))?;
            let a = SMatrix::<f64, 4, 4>::from_iterator(sens.state.iter().copied());
            let b = SVector::<f64, 4>::from_iterator(sens.control.iter().copied());
            jac.set_column(k, &(adj * b));
            adj *= a;
        }
        Ok(jac)
    }
}

/// Options of [`solve`].
#[derive(Clone, Copy, Debug)]
pub struct SqpOptions {
    /// Stop when the largest continuity defect and the scaled stationarity
    /// `‖∇J − Gᵀλ‖∞ / max(1, ‖∇J‖∞)` (`G` the condensed constraint Jacobian, equal to `∂s_N/∂u`
    /// once the defects vanish) are both below this.
    pub tol: f64,
    /// Most iterations.
    pub max_iterations: usize,
    /// Print one line per iteration on standard error.
    pub trace: bool,
}

impl Default for SqpOptions {
    fn default() -> Self {
        Self {
            tol: 1e-10,
            max_iterations: 200,
            trace: false,
        }
    }
}

/// The outcome of [`solve`].
pub struct Solution {
    /// The optimal controls.
    pub u: Vec<f64>,
    /// `J(u)`.
    pub cost: f64,
    /// The multipliers `λ` of `∇J = Jᵀλ`.
    pub lambda: SVector<f64, 4>,
    /// SQP iterations (each: the Hessian blocks, one Riccati solve, a line search).
    pub iterations: usize,
    /// Sweeps over the `N` steps: one per trial of the line search (steps only; an accepted
    /// trial's sensitivities reuse its steps) and five per Hessian (steps and sensitivities).
    pub sweeps: usize,
    /// The largest continuity defect at the solution.
    pub violation: f64,
    /// `‖∇J − Gᵀλ‖∞ / max(1, ‖∇J‖∞)` at the solution.
    pub stationarity: f64,
}

/// The least-squares multipliers of `∇J = Jᵀλ` and the scaled residual
/// `‖∇J − Jᵀλ‖∞ / max(1, ‖∇J‖∞)`.
pub fn multipliers(grad: &DVector<f64>, jac: &DMatrix<f64>) -> (SVector<f64, 4>, f64) {
    let jjt = jac * jac.transpose();
    let lambda = jjt
        .cholesky()
        .map(|c| c.solve(&(jac * grad)))
        .unwrap_or_else(|| DVector::zeros(4));
    let lambda = SVector::<f64, 4>::from_iterator(lambda.iter().copied());
    let r = grad - jac.transpose() * DVector::from_iterator(4, lambda.iter().copied());
    let scale = grad.amax().max(1.0);
    (lambda, r.amax() / scale)
}

/// One linearization of the lifted problem: for every step `k`, from the lifted state `s_k`
/// under `u_k`, the defect `r_k = Φ(s_k, u_k) − s_{k+1}` and the step sensitivities `A_k`, `B_k`.
struct Linearization {
    defects: Vec<SVector<f64, 4>>,
    a: Vec<SMatrix<f64, 4, 4>>,
    b: Vec<SVector<f64, 4>>,
}

impl Linearization {
    /// `Σ_k ‖r_k‖₁`.
    fn defect_l1(&self) -> f64 {
        self.defects.iter().map(|r| r.lp_norm(1)).sum()
    }

    /// `max_k ‖r_k‖∞`.
    fn defect_max(&self) -> f64 {
        self.defects.iter().map(|r| r.amax()).fold(0.0, f64::max)
    }

    /// The condensed constraint `G Δu = −c̃` of the linearized dynamics with `Δs_0 = Δs_N = 0`:
    /// `G = ∂s_N/∂u` (4 × N, column `k` = `A_{N−1} ⋯ A_{k+1} B_k`) and `c̃ = Σ_k A_{N−1} ⋯
    /// A_{k+1} r_k`, both by the backward recursion.
    fn condensed(&self) -> (DMatrix<f64>, SVector<f64, 4>) {
        let n = self.b.len();
        let mut g = DMatrix::zeros(4, n);
        let mut c = SVector::<f64, 4>::zeros();
        let mut adj = SMatrix::<f64, 4, 4>::identity();
        for k in (0..n).rev() {
            g.set_column(k, &(adj * self.b[k]));
            c += adj * self.defects[k];
            adj *= self.a[k];
        }
        (g, c)
    }
}

/// A reduced state from its components `(x, w, μ, g)`.
fn state_of(v: &SVector<f64, 4>) -> ReducedState<1, 1> {
    ReducedState::new([v[0]], [v[1]], [v[2]], [v[3]])
}

impl Swingup {
    /// The states of CasADi's initial guess: the configurations linear in `k` between the two
    /// boundary configurations, and the momenta of that motion (`θ̇ = −π/T`, `ṡ = 0`, so
    /// `w = m l² θ̇`, `μ = m l cos θ θ̇`); the boundary states themselves.
    pub fn linear_guess(&self) -> Vec<SVector<f64, 4>> {
        let sys = &self.integ.system();
        let n = self.n;
        let theta0 = self.initial.x[0];
        let rate = (self.target[0] - theta0) / (n as f64 * self.h);
        (0..=n)
            .map(|k| {
                if k == 0 {
                    components(&self.initial)
                } else if k == n {
                    self.target
                } else {
                    let theta = theta0 + rate * (k as f64 * self.h);
                    let w = sys.m * sys.l * sys.l * rate;
                    let mu = sys.m * sys.l * theta.cos() * rate;
                    SVector::<f64, 4>::new(theta, w, mu, 0.0)
                }
            })
            .collect()
    }

    /// Every step taken from its own lifted state `s[k]` under `u[k]` (`s[0]` the initial
    /// state, `s[N]` the target), in one workspace, and the defects `Φ(s_k, u_k) − s_{k+1}`.
    /// `None` when a step fails.
    fn take_steps(&self, u: &DVector<f64>, s: &[SVector<f64, 4>]) -> Option<Steps> {
        let mut ws = self.integ.workspace();
        let mut out = Steps {
            next: Vec::with_capacity(self.n),
            records: Vec::with_capacity(self.n),
            defects: Vec::with_capacity(self.n),
        };
        for k in 0..self.n {
            let (next, record) = self
                .integ
                .step_with(
                    &mut ws,
                    StepAt::new(k, self.integ.time_step()).with_controls(&[u[k]]),
                    &state_of(&s[k]),
                )
                .ok()?;
            out.defects.push(components(&next) - s[k + 1]);
            out.next.push(next);
            out.records.push(record);
        }
        Some(out)
    }

    /// The lifted problem's linearization from the steps `steps` at `(u, s)`: the sensitivities
    /// of every step. `None` when one fails.
    fn linearize(
        &self,
        u: &DVector<f64>,
        s: &[SVector<f64, 4>],
        steps: Steps,
    ) -> Option<Linearization> {
        let mut lin = Linearization {
            defects: steps.defects,
            a: Vec::with_capacity(self.n),
            b: Vec::with_capacity(self.n),
        };
        for k in 0..self.n {
            let sens = self
                .integ
                .sensitivity(
                    k,
                    &state_of(&s[k]),
                    &steps.next[k],
                    &steps.records[k],
                    &[u[k]],
                )
                .ok()?;
            lin.a.push(SMatrix::<f64, 4, 4>::from_iterator(
                sens.state.iter().copied(),
            ));
            lin.b.push(SVector::<f64, 4>::from_iterator(
                sens.control.iter().copied(),
            ));
        }
        Some(lin)
    }
}

/// The steps of one sweep over the lifted states: what [`Swingup::take_steps`] returns.
struct Steps {
    next: Vec<ReducedState<1, 1>>,
    records: Vec<ReducedStep<1>>,
    defects: Vec<SVector<f64, 4>>,
}

impl Steps {
    /// `Σ_k ‖r_k‖₁`.
    fn defect_l1(&self) -> f64 {
        self.defects.iter().map(|r| r.lp_norm(1)).sum()
    }
}

/// The Hessian blocks of the Lagrangian at one step: `∇²_{(s_k, u_k)} (h u_k² + λ_{k+1}ᵀ Φ)`,
/// split as `Q` (state–state), `S` (state–control) and `R` (control–control).
#[derive(Clone, Copy)]
struct Block {
    q: SMatrix<f64, 4, 4>,
    s: SVector<f64, 4>,
    r: f64,
}

/// The Riccati solution of one QP: the steps and the new multipliers `λ_1 … λ_N`.
struct QpStep {
    du: DVector<f64>,
    ds: Vec<SVector<f64, 4>>,
    lambda: Vec<SVector<f64, 4>>,
}

impl Swingup {
    /// The Hessian blocks at every step by forward differences of `[A_k B_k]ᵀ λ_{k+1}` (the
    /// gradient of `λ_{k+1}ᵀ Φ`, exact from the sensitivities): five more steps per step (one
    /// for `k = 0`, whose state is fixed). `None` when a step fails.
    fn hessian_blocks(
        &self,
        u: &DVector<f64>,
        s: &[SVector<f64, 4>],
        lin: &Linearization,
        lambda: &[SVector<f64, 4>],
    ) -> Option<Vec<Block>> {
        let mut blocks = Vec::with_capacity(self.n);
        for k in 0..self.n {
            let lam = &lambda[k];
            let base = SVector::<f64, 5>::new(
                (lin.a[k].transpose() * lam)[0],
                (lin.a[k].transpose() * lam)[1],
                (lin.a[k].transpose() * lam)[2],
                (lin.a[k].transpose() * lam)[3],
                lin.b[k].dot(lam),
            );
            let mut hess = SMatrix::<f64, 5, 5>::zeros();
            let first = if k == 0 { 4 } else { 0 };
            for j in first..5 {
                let (mut sk, mut uk) = (s[k], u[k]);
                let eps = if j < 4 {
                    let e = 1e-7 * sk[j].abs().max(1.0);
                    sk[j] += e;
                    e
                } else {
                    let e = 1e-7 * uk.abs().max(1.0);
                    uk += e;
                    e
                };
                let (_, _, sens) = self.integ.step_sensitivity(k, &state_of(&sk), &[uk]).ok()?;
                let a = SMatrix::<f64, 4, 4>::from_iterator(sens.state.iter().copied());
                let b = SVector::<f64, 4>::from_iterator(sens.control.iter().copied());
                let at = a.transpose() * lam;
                let col = SVector::<f64, 5>::new(at[0], at[1], at[2], at[3], b.dot(lam));
                hess.set_column(j, &((col - base) / eps));
            }
            let hess = (hess + hess.transpose()) * 0.5;
            blocks.push(Block {
                q: hess.fixed_view::<4, 4>(0, 0).into_owned(),
                s: hess.fixed_view::<4, 1>(0, 4).into_owned(),
                r: 2.0 * self.h + hess[(4, 4)],
            });
        }
        Some(blocks)
    }
}

/// The SQP step: the QP `min Σ_k ½ (Δs_k, Δu_k)ᵀ H_k (Δs_k, Δu_k) + 2h u_k Δu_k` subject to the
/// linearized dynamics `Δs_{k+1} = A_k Δs_k + B_k Δu_k + r_k`, `Δs_0 = Δs_N = 0`, by a Riccati
/// recursion (one control per step: every division is by a scalar). The terminal constraint
/// enters through its multiplier `ν = λ_N`: the recursion is affine in `ν`, the rollout gives
/// `Δs_N = a + C ν`, and `C ν = −a` is 4 × 4. `None` when a pivot `R̃_k` is not positive (the
/// caller regularizes).
fn riccati(
    u: &DVector<f64>,
    h: f64,
    lin: &Linearization,
    blocks: &[Block],
    delta: f64,
) -> Option<QpStep> {
    type M4 = SMatrix<f64, 4, 4>;
    type V4 = SVector<f64, 4>;
    let n = u.len();
    // Gains: Δu_k = K_k·Δs_k + k0_k + kn_k·ν.
    let mut gain = vec![V4::zeros(); n];
    let mut k0 = vec![0.0; n];
    let mut kn = vec![V4::zeros(); n];
    // Value function at k: ½ xᵀ P_k x + (p_k + Π_k ν)ᵀ x.
    let mut pm = vec![M4::zeros(); n + 1];
    let mut pv = vec![V4::zeros(); n + 1];
    let mut pi = vec![M4::identity(); n + 1];
    for k in (0..n).rev() {
        let (a, b, r) = (&lin.a[k], &lin.b[k], &lin.defects[k]);
        let blk = &blocks[k];
        let p = &pm[k + 1];
        let pb = p * b;
        let rt = blk.r + delta + b.dot(&pb);
        if rt.is_nan() || rt <= 1e-12 * h {
            return None;
        }
        let st = blk.s + a.transpose() * pb;
        let pr = p * r + pv[k + 1];
        let rho0 = 2.0 * h * u[k] + b.dot(&pr);
        gain[k] = -st / rt;
        k0[k] = -rho0 / rt;
        kn[k] = -(pi[k + 1].transpose() * b) / rt;
        let q = blk.q + M4::identity() * delta;
        let next = q + a.transpose() * p * a - st * st.transpose() / rt;
        pm[k] = (next + next.transpose()) * 0.5;
        pv[k] = a.transpose() * pr + st * k0[k];
        pi[k] = a.transpose() * pi[k + 1] + st * kn[k].transpose();
    }
    let rollout = |nu: &V4| -> (DVector<f64>, Vec<V4>) {
        let mut ds = vec![V4::zeros(); n + 1];
        let mut du = DVector::zeros(n);
        for k in 0..n {
            du[k] = gain[k].dot(&ds[k]) + k0[k] + kn[k].dot(nu);
            ds[k + 1] = lin.a[k] * ds[k] + lin.b[k] * du[k] + lin.defects[k];
        }
        (du, ds)
    };
    let (_, ds0) = rollout(&V4::zeros());
    let a_end = ds0[n];
    let mut c = M4::zeros();
    for i in 0..4 {
        let (_, dsi) = rollout(&V4::ith(i, 1.0));
        c.set_column(i, &(dsi[n] - a_end));
    }
    let nu = c.lu().solve(&(-a_end))?;
    let (du, mut ds) = rollout(&nu);
    ds[n] = V4::zeros();
    // λ_{k} = P_k Δs_k + p_k + Π_k ν for k = 1 … N (λ_N = ν).
    let lambda = (1..=n)
        .map(|k| pm[k] * ds[k] + pv[k] + pi[k] * nu)
        .collect();
    Some(QpStep { du, ds, lambda })
}

/// Minimises `J(u) = h Σ u_k²` subject to `s_N(u) = target` from the controls `u0` and the
/// states `s0` (`N + 1` of them; the first and the last are replaced by the boundary states).
///
/// Plain single shooting — an SQP on `u` alone with the chained Jacobian [`Swingup::jacobian`]
/// — stalls on this problem: from `u = 0` it brings the final angle close quickly, then the
/// final angular momentum `w_N` is so nonlinear in `u` that the line search accepts only 1/64 to
/// 1/256 of each SQP step, with a BFGS Hessian and even with an exact (finite-difference) one,
/// and a trust region did no better. So the solver **lifts** the shooting (the lifted Newton
/// method of Albersmeyer and Diehl, i.e. multiple shooting with a node at every step): the
/// states `s_1 … s_{N−1}` are unknowns beside `u` — started at `s0`, e.g. the configurations of
/// CasADi's initial guess ([`Swingup::linear_guess`]; from the simulated trajectory of `u = 0`
/// the iterates reach a feasible point of cost 128 and crawl) — dirac takes every step from its
/// own lifted state, and the continuity defects `r_k = Φ(s_k, u_k) − s_{k+1}` are the
/// constraints. Newton–KKT: the Hessian of the Lagrangian `J + Σ λ_{k+1}ᵀ r_k` is block diagonal
/// — one 5 × 5 block per step, `∇²(λ_{k+1}ᵀ Φ)` by forward differences of the exact gradients
/// `[A_k B_k]ᵀ λ_{k+1}` — and the KKT system is solved by a Riccati recursion in `O(N)`,
/// regularized (`+ δ I`) where a pivot is not positive. Line search on the ℓ1 merit
/// `J + ρ Σ_k ‖r_k‖₁`. At the solution the defects vanish and `u` solves the single-shooting
/// problem: the stopping test is single shooting's first-order conditions, with the condensed
/// Jacobian (the example and the test check them again with [`Swingup::shoot`] and
/// [`Swingup::jacobian`]). The linear algebra is nalgebra's.
pub fn solve(
    problem: &Swingup,
    u0: &[f64],
    s0: &[SVector<f64, 4>],
    options: SqpOptions,
) -> Result<Solution, String> {
    let n = problem.n;
    let h = problem.h;
    assert_eq!(
        (u0.len(), s0.len()),
        (n, n + 1),
        "N controls and N + 1 states"
    );
    let mut u = DVector::from_column_slice(u0);
    // The lifted states; s[0] and s[N] are the boundary states and stay fixed.
    let mut s = s0.to_vec();
    s[0] = components(&problem.initial);
    s[n] = problem.target;
    let mut sweeps = 0;
    let mut lin = problem
        .take_steps(&u, &s)
        .and_then(|steps| problem.linearize(&u, &s, steps))
        .ok_or("a step fails at the initial guess")?;
    sweeps += 1;
    let mut lambda = vec![SVector::<f64, 4>::zeros(); n];
    let mut rho = 0.0_f64;
    for iteration in 0..=options.max_iterations {
        let grad = &u * (2.0 * h);
        let (g, _) = lin.condensed();
        let (mu, stationarity) = multipliers(&grad, &g);
        let violation = lin.defect_max();
        let cost = problem.cost(u.as_slice());
        if options.trace {
            eprintln!(
                "it {iteration:3} cost {cost:.12} defects {violation:.3e} stationarity {stationarity:.3e} sweeps {sweeps}"
            );
        }
        if violation <= options.tol && stationarity <= options.tol {
            return Ok(Solution {
                cost,
                u: u.as_slice().to_vec(),
                lambda: mu,
                iterations: iteration,
                sweeps,
                violation,
                stationarity,
            });
        }
        if iteration == options.max_iterations {
            break;
        }
        let blocks = if lambda.iter().all(|l| l.amax() == 0.0) {
            vec![
                Block {
                    q: SMatrix::zeros(),
                    s: SVector::zeros(),
                    r: 2.0 * h,
                };
                n
            ]
        } else {
            sweeps += 5;
            problem
                .hessian_blocks(&u, &s, &lin, &lambda)
                .ok_or_else(|| format!("a step fails in the Hessian at iteration {iteration}"))?
        };
        let mut delta = 0.0;
        let qp = loop {
            if let Some(qp) = riccati(&u, h, &lin, &blocks, delta) {
                break qp;
            }
            delta = if delta == 0.0 { 1e-4 * h } else { 10.0 * delta };
            if delta > 1e6 {
                return Err(format!(
                    "no regularization makes the QP convex at iteration {iteration}"
                ));
            }
        };
        let pmax = qp.lambda.iter().map(|l| l.amax()).fold(0.0, f64::max);
        rho = rho.max(1.1 * pmax);
        let l1 = lin.defect_l1();
        let slope = grad.dot(&qp.du) - rho * l1;
        let m0 = cost + rho * l1;
        let mut alpha = 1.0;
        let mut accepted = None;
        while alpha > 1e-12 {
            let ut = &u + &qp.du * alpha;
            let st: Vec<SVector<f64, 4>> = s
                .iter()
                .zip(&qp.ds)
                .map(|(sk, dk)| sk + dk * alpha)
                .collect();
            sweeps += 1;
            if let Some(steps) = problem.take_steps(&ut, &st) {
                let m = problem.cost(ut.as_slice()) + rho * steps.defect_l1();
                if m <= m0 + 1e-4 * alpha * slope.min(0.0) {
                    accepted = Some((ut, st, steps));
                    break;
                }
            }
            alpha *= 0.5;
        }
        if options.trace {
            eprintln!("    delta {delta:.3e} rho {rho:.3e} alpha {alpha:.3e} |du| {:.3e} slope {slope:.3e}", qp.du.amax());
        }
        let (ut, st, steps) =
            accepted.ok_or_else(|| format!("line search failed at iteration {iteration}"))?;
        let lt = problem
            .linearize(&ut, &st, steps)
            .ok_or_else(|| format!("a sensitivity fails at iteration {iteration}"))?;
        for (l, lq) in lambda.iter_mut().zip(&qp.lambda) {
            *l += (lq - *l) * alpha;
        }
        u = ut;
        s = st;
        lin = lt;
    }
    Err(format!(
        "no convergence in {} iterations: largest defect {:.3e}",
        options.max_iterations,
        lin.defect_max()
    ))
}
