//! Variational integrators of any even order: the Gauss–Legendre variational partitioned
//! Runge–Kutta methods (the Galerkin variational integrators of a continuous Lagrangian with
//! polynomials of degree `s` and Gauss quadrature at `s` nodes), `s = 1, 2, …`, order `2s`.
//!
//! # The discrete Lagrangian and its step
//!
//! On a step of size `h`, let `q(t0 + τh)` be a polynomial of degree `s` with `q(t0) = q0`,
//! `q(t0 + h) = q1`, and `c_i`, `b_i` the nodes and weights of the `s`-point Gauss–Legendre rule
//! on `[0, 1]`. The Galerkin discrete Lagrangian (Marsden & West, "Discrete mechanics and
//! variational integrators", §2.6; Ober-Blöbaum & Saake, "Construction and analysis of higher
//! order Galerkin variational integrators")
//!
//! ```text
//! L_d(q0, q1) = ext_{q(·)} h Σ_i b_i L(q(t0 + c_i h), q̇(t0 + c_i h)),
//! ```
//!
//! extremized over the interior of the polynomial, written with the stage velocities
//! `V_j = q̇(t0 + c_j h)` (the velocity polynomial of degree `s − 1` through them,
//! `q(t0 + τh) = q0 + h Σ_j V_j ∫_0^τ ℓ_j`), has stage positions and an end point
//!
//! ```text
//! Q_i = q0 + h Σ_j a_ij V_j,     q1 = q0 + h Σ_j b_j V_j,     a_ij = ∫_0^{c_i} ℓ_j(τ) dτ,
//! ```
//!
//! and its discrete Legendre transforms `p0 = −D1 L_d`, `p1 = D2 L_d` are the variational
//! partitioned Runge–Kutta method (Hairer, Lubich & Wanner, "Geometric numerical integration",
//! VI.6.3, Theorem 6.4; Marsden & West, Theorem 2.6.1):
//!
//! ```text
//! P_i = ∂L/∂v(Q_i, V_i) = p0 + h Σ_j â_ij f_j,      f_j = ∂L/∂q(Q_j, V_j) + F(Q_j, V_j),
//! p1  = p0 + h Σ_j b_j f_j,                           b_i â_ij + b_j a_ji = b_i b_j.
//! ```
//!
//! For Gauss–Legendre `a` itself satisfies `b_i a_ij + b_j a_ji = b_i b_j`, so `â = a`. A force
//! `F` (the attribute's `force = |dq| ⟨F(q, v), dq⟩`) enters as in the discrete
//! Lagrange–d'Alembert principle with the Galerkin quadrature of its virtual work,
//! `∫ ⟨F, δq⟩ ≈ h Σ_i b_i ⟨F(Q_i, V_i), δq(t0 + c_i h)⟩`, which adds `F` to `∂L/∂q` at each
//! stage (Ober-Blöbaum, Junge & Marsden, "Discrete mechanics and optimal control", §3.2, for
//! the forced Galerkin rule).
//!
//! # What is solved, and what is kept
//!
//! Newton's unknowns are the `sN` stage velocities `V`, the residual
//! `R_i(V) = ∂L/∂v(Q_i, V_i) − p0 − h Σ_j a_ij f_j`, and its Jacobian, block `(i, k)`,
//!
//! ```text
//! ∂R_i/∂V_k = δ_ik ∂p/∂v(i) + h a_ik ∂p/∂q(i) − h a_ik ∂f/∂v(k) − h² Σ_j a_ij a_jk ∂f/∂q(j),
//! ```
//!
//! from the straight-line stage derivatives the attribute emits ([`StageDerivatives`]), solved
//! by the one Newton driver on a dense LU in memory allocated once per run. The step map is
//! symplectic (it is the Legendre transform of `L_d`), of order `2s` (Hairer, Lubich & Wanner,
//! Theorem VI.6.4 with the order of Gauss collocation), self-adjoint, and keeps the momentum of
//! every translation symmetry exactly: where `L` and `F` do not read a group coordinate `g`, its
//! force is the constant `0` the compiler folds, and `p1_g = p0_g + h Σ_j b_j · 0 = p0_g` bit for
//! bit (the discrete Noether theorem, here with no rounding at all).
//!
//! The same step on the reduced states `(x, w, μ, g)` of eq. (3.6), for either side of the
//! reduced equations, is [`ReducedGaussIntegrator`] (its module documentation derives it).
//!
//! Newton starts from the velocity polynomial of the last step extrapolated to the new stages,
//! `V_i ≈ Σ_j V_j^{prev} ℓ_j(1 + c_i h/h_prev)`, and at a run's first step from the velocity
//! of the start, `∂L/∂v(q0, ·)⁻¹(p0)` ([`crate::ContinuousLagrangian::velocity`]; with adaptive
//! steps the velocity in fictitious time, [`crate::DiscreteLagrangian::adaptive_increment`]` / h`).

use nalgebra::{DVector, SMatrix, SVector};

use crate::continuous::{StageDerivatives, StageJacobian};
use crate::error::StepError;
use crate::linalg::LinearSolver;
use crate::linalg::{CscBuffer, DynPatternLu};
use crate::newton::{self, inf_norm, slice_inf_norm as inf_norm_slice, NewtonOptions};
use crate::reduced::flat_monitor;
use crate::sensitivity::Sensitivity;
use crate::state::UnreducedState;
use crate::stepper::{
    check_inputs, flat_level_set, step_error, system_at, Collect, LevelSet, StepAt, StepStats,
    Stepper,
};
use crate::system::DiscreteLagrangian;
use crate::unreduced::UnreducedTrajectory;

pub mod reduced;

pub use reduced::{ReducedGaussIntegrator, ReducedGaussWorkspace};

/// The most stages a [`GaussRule`] has (order 32): beyond it the nodes of the rule, computed in
/// double precision, and the extrapolated guesses lose digits the order cannot buy back.
pub const MAX_STAGES: usize = 16;

/// The most corrections past Newton's tolerance that a step takes to bring its stage velocities
/// to round-off (each one a residual evaluation and a solve with the factors at hand): they
/// stop earlier, at the first that does not shrink.
const POLISH_MAX: usize = 4;

/// The `s`-stage Gauss–Legendre rule on `[0, 1]`: nodes `c`, weights `b`, and the collocation
/// coefficients `a_ij = ∫_0^{c_i} ℓ_j` of the Lagrange polynomials `ℓ_j` on the nodes.
///
/// ```
/// use dirac_runtime::gauss::GaussRule;
///
/// let rule = GaussRule::new(2).unwrap();
/// let r3 = 3f64.sqrt() / 6.0;
/// assert!((rule.c()[0] - (0.5 - r3)).abs() < 1e-15 && (rule.c()[1] - (0.5 + r3)).abs() < 1e-15);
/// assert!(rule.b().iter().all(|b| (b - 0.5).abs() < 1e-15));
/// assert!((rule.a(0, 1) - (0.25 - r3)).abs() < 1e-15);
/// assert_eq!(rule.order(), 4);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct GaussRule {
    /// `a`, row by row.
    a: Vec<f64>,
    b: Vec<f64>,
    c: Vec<f64>,
}

impl GaussRule {
    /// The rule with `stages` nodes, `1 ≤ stages ≤` [`MAX_STAGES`]; `None` otherwise.
    ///
    /// The nodes are the roots of the Legendre polynomial `P_s` by Newton's method on its
    /// three-term recurrence, the weights `2 / ((1 − x²) P_s'(x)²)`, both mapped from `[−1, 1]`,
    /// and made exactly symmetric (`c_{s−1−i} = 1 − c_i`, `b_{s−1−i} = b_i`) so that the method
    /// is self-adjoint in floating point as in exact arithmetic; `a_ij` is the `s`-point rule
    /// itself on `[0, c_i]`, exact for the degree `s − 1` of `ℓ_j`.
    pub fn new(stages: usize) -> Option<Self> {
        if !(1..=MAX_STAGES).contains(&stages) {
            return None;
        }
        let s = stages;
        let (mut c, mut b) = (vec![0.5; s], vec![0.0; s]);
        for i in 0..s.div_ceil(2) {
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (s as f64 + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                let (p, d) = legendre(s, x);
                dp = d;
                let dx = p / d;
                x -= dx;
                if dx.abs() <= 1e-17 {
                    break;
                }
            }
            let (_, d) = legendre(s, x);
            dp = if d.is_finite() { d } else { dp };
            let w = 1.0 / ((1.0 - x * x) * dp * dp);
            // Descending x: ascending nodes from the left end.
            if 2 * i + 1 == s {
                (c[i], b[i]) = (0.5, w);
            } else {
                let left = (1.0 - x) / 2.0;
                (c[i], c[s - 1 - i]) = (left, 1.0 - left);
                (b[i], b[s - 1 - i]) = (w, w);
            }
        }
        let mut rule = GaussRule {
            a: vec![0.0; s * s],
            b,
            c,
        };
        for i in 0..s {
            for j in 0..s {
                let ci = rule.c[i];
                rule.a[i * s + j] = ci
                    * (0..s)
                        .map(|m| rule.b[m] * rule.lagrange(j, ci * rule.c[m]))
                        .sum::<f64>();
            }
        }
        Some(rule)
    }

    /// The number of stages `s`.
    pub fn stages(&self) -> usize {
        self.c.len()
    }

    /// The order `2s` of the method.
    pub fn order(&self) -> usize {
        2 * self.stages()
    }

    /// `a_ij`.
    pub fn a(&self, i: usize, j: usize) -> f64 {
        self.a[i * self.stages() + j]
    }

    /// The weights `b_i`.
    pub fn b(&self) -> &[f64] {
        &self.b
    }

    /// The nodes `c_i`.
    pub fn c(&self) -> &[f64] {
        &self.c
    }

    /// `ℓ_j(τ) = Π_{m ≠ j} (τ − c_m)/(c_j − c_m)`.
    pub fn lagrange(&self, j: usize, tau: f64) -> f64 {
        let cj = self.c[j];
        self.c
            .iter()
            .enumerate()
            .filter(|&(m, _)| m != j)
            .map(|(_, &cm)| (tau - cm) / (cj - cm))
            .product()
    }
}

/// `(P_s(x), P_s'(x))` by the three-term recurrence.
fn legendre(s: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    for k in 1..s {
        let k = k as f64;
        (p0, p1) = (p1, ((2.0 * k + 1.0) * x * p1 - k * p0) / (k + 1.0));
    }
    let p = if s == 0 { 1.0 } else { p1 };
    (p, s as f64 * (x * p - p0) / (x * x - 1.0))
}

/// The workspace of a Gauss–Legendre run: Newton's unknowns, residual and Jacobian, the dense
/// LU, the stages' derivatives at the last iterate, and the last step's stage velocities for
/// the next guess. Allocated once, when the run starts; a step allocates nothing.
#[derive(Debug)]
pub struct GaussWorkspace<const N: usize> {
    /// The dense LU of the `sN × sN` Jacobian, its factors reused ([`DynPatternLu::dense_reused`]).
    solver: DynPatternLu,
    z: DVector<f64>,
    r: DVector<f64>,
    /// A correction of the polishing iterations.
    dz: DVector<f64>,
    jacobian: Option<CscBuffer>,
    stages: Vec<StageJacobian<N>>,
    /// The last step's stage velocities and size.
    last: Option<(DVector<f64>, f64)>,
    /// The state the last step returned and the rounding errors of its `q` and `p`, which the
    /// next step from it adds back ([`GaussIntegrator::update`]).
    carry: Option<(UnreducedState<N>, SVector<f64, N>, SVector<f64, N>)>,
}

/// The Gauss–Legendre variational integrator with `s` stages, order `2s`, of a system with a
/// continuous Lagrangian (see the [module documentation](self)): the unreduced states
/// `(q, p)` and trajectories of [`crate::UnreducedIntegrator`], the same run API, step sizes,
/// controls, end times and adaptive steps (of the time-transformed Lagrangian the attribute
/// emits for `time(t), adapt = ..`).
#[derive(Clone, Debug)]
pub struct GaussIntegrator<L, const S: usize, const K: usize, const N: usize> {
    system: L,
    rule: GaussRule,
    options: NewtonOptions,
}

impl<L, const S: usize, const K: usize, const N: usize> GaussIntegrator<L, S, K, N>
where
    L: DiscreteLagrangian<S, K, N> + StageDerivatives<N>,
{
    /// The integrator of order `2 stages`; [`StepError::InvalidSize`] for `stages` outside
    /// `1..=`[`MAX_STAGES`].
    pub fn new(system: L, stages: usize, options: NewtonOptions) -> Result<Self, StepError> {
        let rule = GaussRule::new(stages).ok_or_else(|| StepError::InvalidSize {
            reason: format!(
                "a Gauss–Legendre integrator has 1 to {MAX_STAGES} stages (order 2 to {}), not {stages}",
                2 * MAX_STAGES
            ),
        })?;
        Ok(Self {
            system,
            rule,
            options,
        })
    }

    /// The system being integrated.
    pub fn system(&self) -> &L {
        &self.system
    }

    /// The rule.
    pub fn rule(&self) -> &GaussRule {
        &self.rule
    }

    /// The Newton options.
    pub fn options(&self) -> &NewtonOptions {
        &self.options
    }

    /// The momentum map `J(q, p) = p_g` of the declared translations at `state`.
    pub fn momentum_map(&self, state: &UnreducedState<N>) -> Result<SVector<f64, K>, StepError> {
        crate::stepper::finite_momentum_map(self.system.momentum_map(state))
    }

    /// The continuous energy of a trajectory of this integrator at its nodes and midpoints
    /// ([`crate::continuous_energies`]).
    pub fn energies(
        &self,
        trajectory: &UnreducedTrajectory<N>,
    ) -> Result<crate::ContinuousEnergies, crate::LegendreError> {
        crate::continuous_energies(&self.system, trajectory)
    }

    /// `Q_i = q0 + h Σ_j a_ij V_j`, the velocities `V` in `z` (stage by stage).
    fn stage_point(&self, i: usize, q0: &SVector<f64, N>, h: f64, z: &[f64]) -> SVector<f64, N> {
        let mut sum = SVector::<f64, N>::zeros();
        for j in 0..self.rule.stages() {
            sum += self.rule.a(i, j) * velocity(z, j);
        }
        q0 + h * sum
    }

    /// Solves the step `at` from `(q0, p0)` in `ws` (its `z` holding the guess, then the
    /// stage velocities), leaving each stage's derivatives in `ws.stages`.
    fn solve(
        &self,
        sys: &L,
        ws: &mut GaussWorkspace<N>,
        at: StepAt<'_>,
        state: &UnreducedState<N>,
    ) -> Result<StepStats, StepError> {
        let (h, s) = (at.h, self.rule.stages());
        let (q0, p0) = (&state.q, &state.p);
        if ws.last.is_none() {
            // The first step: the stages at the guess give the scale.
            for i in 0..s {
                let q = self.stage_point(i, q0, h, ws.z.as_slice());
                let (f, p) = sys.stage(&q, &velocity(ws.z.as_slice(), i));
                (ws.stages[i].f, ws.stages[i].p) = (f, p);
            }
        }
        let rho = self.momentum_scale(&ws.stages, h, p0);
        let GaussWorkspace {
            solver,
            z,
            r,
            dz,
            jacobian,
            stages,
            ..
        } = ws;
        let stages = std::cell::RefCell::new(stages);
        // R_i = P_i − p0 − h Σ_j a_ij f_j, from the stages' (f, p) in `stages`.
        let write_residual = |stages: &[StageJacobian<N>], r: &mut DVector<f64>| {
            for i in 0..s {
                let mut sum = SVector::<f64, N>::zeros();
                for (j, stage) in stages.iter().enumerate() {
                    sum += self.rule.a(i, j) * stage.f;
                }
                let ri = stages[i].p - p0 - h * sum;
                r.as_mut_slice()[i * N..(i + 1) * N].copy_from_slice(ri.as_slice());
            }
        };
        let mut residual = |z: &DVector<f64>, r: &mut DVector<f64>| {
            let mut stages = stages.borrow_mut();
            for i in 0..s {
                let q = self.stage_point(i, q0, h, z.as_slice());
                let (f, p) = sys.stage(&q, &velocity(z.as_slice(), i));
                (stages[i].f, stages[i].p) = (f, p);
            }
            write_residual(&stages, r);
        };
        let solution = newton::solve_in(
            solver,
            z,
            r,
            jacobian,
            rho,
            &self.options,
            &mut residual,
            |z, r, jacobian| {
                let mut stages = stages.borrow_mut();
                for i in 0..s {
                    let q = self.stage_point(i, q0, h, z.as_slice());
                    stages[i] = sys.stage_jacobian(&q, &velocity(z.as_slice(), i));
                }
                write_residual(&stages, r);
                let n = s * N;
                let j = jacobian.get_or_insert_with(|| CscBuffer::zeroed(n * n, 0));
                self.write_jacobian(&stages, h, j.as_mut_slice());
            },
        )
        .map_err(|failure| step_error(at.k, failure))?;
        let mut stats = StepStats::from_solution(&solution, self.options.residual_tolerance(rho));
        // Past the tolerance, corrections with the factors at hand as long as they shrink
        // (Hairer, McLachlan & Razakarivony, "Achieving Brouwer's law with implicit Runge–Kutta
        // methods", BIT 2008): the stage velocities to round-off, so that the step's error is
        // its rounding alone, without the sign a truncated iteration leaves the same way at
        // every step (a linear energy drift over long runs).
        if solver.has_reusable_factors() {
            let mut last = f64::INFINITY;
            for _ in 0..POLISH_MAX {
                dz.copy_from(r);
                solver.solve_in_place(dz);
                let size = inf_norm_slice(dz.as_slice());
                if size.is_nan() || size >= last || size == 0.0 {
                    break;
                }
                *z -= &*dz;
                last = size;
                residual(z, r);
                stats.iterations += 1;
            }
            stats.residual = inf_norm_slice(r.as_slice());
        }
        Ok(stats)
    }

    /// The size of the terms the residual balances, `max(‖p0‖, ‖P_i‖, h Σ_j |a_ij| ‖f_j‖)`
    /// (∞-norms) at `stages` (the last step's, or the guess's at a run's first step): what its
    /// relative tolerance is measured against ([`NewtonOptions`]). Against `‖p0‖` alone a
    /// residual whose terms are much larger than the momentum (the time-transformed Kepler
    /// problem near periapsis, where `∂L/∂q` grows like `r⁻²`) could not reach the tolerance
    /// for the rounding of its own terms.
    fn momentum_scale(&self, stages: &[StageJacobian<N>], h: f64, p0: &SVector<f64, N>) -> f64 {
        let mut rho = inf_norm(p0);
        for (i, stage) in stages.iter().enumerate() {
            let forces: f64 = stages
                .iter()
                .enumerate()
                .map(|(j, sj)| self.rule.a(i, j).abs() * inf_norm(&sj.f))
                .sum();
            rho = rho.max(inf_norm(&stage.p)).max(h.abs() * forces);
        }
        if rho.is_finite() {
            rho
        } else {
            inf_norm(p0)
        }
    }

    /// `∂R/∂V`, column by column (see the [module documentation](self)).
    fn write_jacobian(&self, stages: &[StageJacobian<N>], h: f64, values: &mut [f64]) {
        let s = self.rule.stages();
        let n = s * N;
        for i in 0..s {
            for k in 0..s {
                let aik = self.rule.a(i, k);
                let mut block = h * aik * (stages[i].p_q - stages[k].f_v);
                if i == k {
                    block += stages[i].p_v;
                }
                let mut fq = SMatrix::<f64, N, N>::zeros();
                for (j, stage) in stages.iter().enumerate() {
                    fq += (self.rule.a(i, j) * self.rule.a(j, k)) * stage.f_q;
                }
                block -= (h * h) * fq;
                for col in 0..N {
                    let start = (k * N + col) * n + i * N;
                    values[start..start + N].copy_from_slice(block.column(col).as_slice());
                }
            }
        }
    }

    /// `(q1, p1) = (q0 + h Σ b_j V_j, p0 + h Σ b_j f_j)` from the solved stages, the increments
    /// added with compensated summation: the rounding error of each addition (Knuth's TwoSum) is
    /// carried in the workspace and added to the next step's increment, as long as the next step
    /// starts from the state this one returned (a run's next step; any other start resets it).
    /// Without it a long run's positions and time gather one rounding of `|q|` per step — at
    /// 10⁴ steps of an orbit whose angle has grown to 600, about 1e-9 — which a high-order step
    /// would otherwise see as its error floor.
    fn update(
        &self,
        ws: &mut GaussWorkspace<N>,
        h: f64,
        state: &UnreducedState<N>,
    ) -> UnreducedState<N> {
        let (mut dq, mut dp) = (SVector::<f64, N>::zeros(), SVector::<f64, N>::zeros());
        for (j, (&b, stage)) in self.rule.b().iter().zip(&ws.stages).enumerate() {
            dq += b * velocity(ws.z.as_slice(), j);
            dp += b * stage.f;
        }
        let (mut cq, mut cp) = match &ws.carry {
            Some((from, cq, cp)) if same_bits(from, state) => (*cq, *cp),
            _ => (SVector::zeros(), SVector::zeros()),
        };
        let mut next = *state;
        for i in 0..N {
            (next.q[i], cq[i]) = two_sum(state.q[i], h * dq[i] + cq[i]);
            (next.p[i], cp[i]) = two_sum(state.p[i], h * dp[i] + cp[i]);
        }
        ws.carry = Some((next, cq, cp));
        next
    }

    /// Newton's guess in `ws.z`: the last step's velocity polynomial extrapolated to this step's
    /// stages, or at a run's first step the velocity of the start at every stage.
    fn guess(&self, sys: &L, ws: &mut GaussWorkspace<N>, h: f64, state: &UnreducedState<N>) {
        let s = self.rule.stages();
        match &ws.last {
            Some((last, h_last)) => {
                let ratio = h / h_last;
                for i in 0..s {
                    let tau = 1.0 + self.rule.c()[i] * ratio;
                    let mut v = SVector::<f64, N>::zeros();
                    for j in 0..s {
                        v += self.rule.lagrange(j, tau) * velocity(last.as_slice(), j);
                    }
                    ws.z.as_mut_slice()[i * N..(i + 1) * N].copy_from_slice(v.as_slice());
                }
            }
            None => {
                // Adaptive steps: the motion in fictitious time; else `∂L/∂v(q0, ·)⁻¹(p0)`.
                let v = match sys.adaptive_increment(&state.q, &state.p, h) {
                    Some(dq) => dq / h,
                    None => sys
                        .velocity(0, &state.q, &state.p, SVector::zeros())
                        .unwrap_or_else(|_| SVector::zeros()),
                };
                for i in 0..s {
                    ws.z.as_mut_slice()[i * N..(i + 1) * N].copy_from_slice(v.as_slice());
                }
            }
        }
    }
}

/// `(a + b, the rounding error of that sum)` exactly (Knuth's TwoSum).
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let sum = a + b;
    let b_virtual = sum - a;
    let a_virtual = sum - b_virtual;
    (sum, (a - a_virtual) + (b - b_virtual))
}

/// Whether two states are the same bit for bit.
fn same_bits<const N: usize>(a: &UnreducedState<N>, b: &UnreducedState<N>) -> bool {
    a.q.iter()
        .chain(a.p.iter())
        .zip(b.q.iter().chain(b.p.iter()))
        .all(|(x, y)| x.to_bits() == y.to_bits())
}

/// `V_j`, the `j`-th block of `N` in `z`.
fn velocity<const N: usize>(z: &[f64], j: usize) -> SVector<f64, N> {
    SVector::<f64, N>::from_column_slice(&z[j * N..(j + 1) * N])
}

impl<L, const S: usize, const K: usize, const N: usize> Collect<GaussIntegrator<L, S, K, N>>
    for UnreducedTrajectory<N>
where
    L: DiscreteLagrangian<S, K, N> + StageDerivatives<N>,
{
    crate::stepper::collect_steps!(
        start(integrator: GaussIntegrator<L, S, K, N>) {
            h: integrator.system.time_step(),
        },
        UnreducedState<N>,
        StepStats,
        |stats| *stats
    );
}

impl<L, const S: usize, const K: usize, const N: usize> Stepper for GaussIntegrator<L, S, K, N>
where
    L: DiscreteLagrangian<S, K, N> + StageDerivatives<N>,
{
    type State = UnreducedState<N>;
    type Record = StepStats;
    type Workspace = GaussWorkspace<N>;
    type Trajectory = UnreducedTrajectory<N>;

    fn time_step(&self) -> f64 {
        self.system.time_step()
    }

    crate::unreduced::unreduced_checks!();

    fn workspace(&self) -> GaussWorkspace<N> {
        let n = self.rule.stages() * N;
        GaussWorkspace {
            solver: DynPatternLu::dense_reused(n),
            z: DVector::zeros(n),
            r: DVector::zeros(n),
            dz: DVector::zeros(n),
            jacobian: None,
            stages: vec![StageJacobian::default(); self.rule.stages()],
            last: None,
            carry: None,
        }
    }

    fn control_dim(&self) -> usize {
        self.system.control_count()
    }

    fn step_into(
        &self,
        ws: &mut GaussWorkspace<N>,
        at: StepAt<'_>,
        state: &UnreducedState<N>,
        next: &mut UnreducedState<N>,
    ) -> Result<StepStats, StepError> {
        let owned = system_at(&self.system, at.k, at.h, at.u)?;
        let sys = owned.as_ref().unwrap_or(&self.system);
        self.guess(sys, ws, at.h, state);
        let stats = self.solve(sys, ws, at, state)?;
        let stepped = self.update(ws, at.h, state);
        if !stepped.is_finite() {
            return Err(StepError::NonFinite {
                step: at.k,
                what: "the updated state",
                residual: stats.residual,
            });
        }
        *next = stepped;
        match &mut ws.last {
            Some((last, h_last)) => {
                last.copy_from(&ws.z);
                *h_last = at.h;
            }
            None => ws.last = Some((ws.z.clone(), at.h)),
        }
        Ok(stats)
    }
}

impl<L, const S: usize, const K: usize, const N: usize> GaussIntegrator<L, S, K, N>
where
    L: DiscreteLagrangian<S, K, N> + StageDerivatives<N>,
{
    /// The Jacobian of the step map `(q0, p0) ↦ (q1, p1)` of step `k` from `from` with size `h`
    /// (the step taken again, then the implicit-function theorem on `R(V; q0, p0) = 0`):
    ///
    /// ```text
    /// ∂R_i/∂q0 = ∂p/∂q(i) − h Σ_j a_ij ∂f/∂q(j),   ∂R_i/∂p0 = −I,   dV = −(∂R/∂V)⁻¹ (∂R/∂q0 dq0 + ∂R/∂p0 dp0),
    /// dq1 = dq0 + h Σ_j b_j dV_j,   dp1 = dp0 + h Σ_j b_j (∂f/∂q(j) dQ_j + ∂f/∂v(j) dV_j),
    /// dQ_j = dq0 + h Σ_m a_jm dV_m.
    /// ```
    ///
    /// A variational integrator's step map is symplectic ([`Sensitivity::symplecticity_defect`]).
    pub fn step_jacobian(
        &self,
        k: usize,
        h: f64,
        from: &UnreducedState<N>,
    ) -> Result<Sensitivity, StepError> {
        let (s, n) = (self.rule.stages(), self.rule.stages() * N);
        let mut ws = self.workspace();
        let at = StepAt::new(k, h);
        let owned = system_at(&self.system, k, h, &[])?;
        let sys = owned.as_ref().unwrap_or(&self.system);
        self.guess(sys, &mut ws, h, from);
        self.solve(sys, &mut ws, at, from)?;
        for i in 0..s {
            let q = self.stage_point(i, &from.q, h, ws.z.as_slice());
            ws.stages[i] = sys.stage_jacobian(&q, &velocity(ws.z.as_slice(), i));
        }
        let mut j = CscBuffer::zeroed(n * n, 0);
        self.write_jacobian(&ws.stages, h, j.as_mut_slice());
        let jv = nalgebra::DMatrix::from_column_slice(n, n, j.values());
        let lu = jv.lu();
        // Right-hand sides: −∂R/∂(q0, p0), columns q0 then p0.
        let mut rhs = nalgebra::DMatrix::<f64>::zeros(n, 2 * N);
        for i in 0..s {
            let mut fq = SMatrix::<f64, N, N>::zeros();
            for (jj, stage) in ws.stages.iter().enumerate() {
                fq += self.rule.a(i, jj) * stage.f_q;
            }
            let dq0 = -(ws.stages[i].p_q - h * fq);
            rhs.view_mut((i * N, 0), (N, N)).copy_from(&dq0);
            rhs.view_mut((i * N, N), (N, N))
                .copy_from(&SMatrix::<f64, N, N>::identity());
        }
        let dv = lu.solve(&rhs).ok_or(StepError::SingularJacobian {
            step: k,
            residual: f64::NAN,
        })?;
        let block = |j: usize, col: usize| dv.view((j * N, col * N), (N, N)).into_owned();
        let mut out = [[SMatrix::<f64, N, N>::zeros(); 2]; 2];
        for (col, seed) in [SMatrix::<f64, N, N>::identity(), SMatrix::zeros()]
            .into_iter()
            .enumerate()
        {
            let (mut dq1, mut dp1) = (seed, SMatrix::<f64, N, N>::identity() - seed);
            for j in 0..s {
                let b = self.rule.b()[j];
                let dvj = SMatrix::<f64, N, N>::from_iterator(block(j, col).iter().copied());
                dq1 += (h * b) * dvj;
                let mut dqj = seed;
                for m in 0..s {
                    let dvm = SMatrix::<f64, N, N>::from_iterator(block(m, col).iter().copied());
                    dqj += (h * self.rule.a(j, m)) * dvm;
                }
                dp1 += (h * b) * (ws.stages[j].f_q * dqj + ws.stages[j].f_v * dvj);
            }
            out[col] = [dq1, dp1];
        }
        if out
            .iter()
            .flatten()
            .any(|m| m.iter().any(|x| !x.is_finite()))
        {
            return Err(StepError::NonFinite {
                step: k,
                what: "the step map's Jacobian",
                residual: f64::NAN,
            });
        }
        Ok(Sensitivity::from_blocks(
            &out[0][0], &out[1][0], &out[0][1], &out[1][1],
        ))
    }
}
