//! Higher order with every structure kept: symmetric compositions of a self-adjoint base step.
//!
//! A discrete Lagrangian is *symmetric* when `L_d(q0, q1; −h) = −L_d(q1, q0; h)` (the midpoint
//! and trapezoidal rules are; the left- and right-point rules are not). Its discrete flow `Φ_h`
//! is then self-adjoint, `Φ_{−h} = Φ_h^{-1}`, and of even order (2 for the midpoint rule). A
//! symmetric composition
//!
//! ```text
//! Ψ_h = Φ_{γ_s h} ∘ … ∘ Φ_{γ_2 h} ∘ Φ_{γ_1 h},    Σ γ_i = 1,  γ_i = γ_{s+1−i},
//! ```
//!
//! with coefficients solving the order conditions raises the order to 4 or 6 (Yoshida 1990;
//! Hairer, Lubich & Wanner, *Geometric Numerical Integration*, 2nd ed., §II.4 and §V.3.2).
//!
//! # Why negative substeps are legitimate here
//!
//! Every composition of order above 2 has a negative coefficient (the triple jump's
//! `γ_2 ≈ −1.70`), so some stages step with `γ_i h < 0`. A stage is a step of the discrete
//! Lagrange–Dirac equations of the same `L_d` at the time step `γ_i h`, which are well posed for
//! any nonzero step; for a symmetric `L_d` the step with `−|γ_i| h` is the inverse of the step
//! with `|γ_i| h`. Each stage is a variational step, hence each stage keeps `μ_{k+1} = μ_k`
//! exactly (the momentum line of eq. (4.6) does not involve `h`) and each stage map is symplectic
//! (Definition 2.7: `p_k = −D1 L_d`, `p_{k+1} = D2 L_d` generate a symplectic map for any `h`):
//! so is their composition. What stays forbidden is a non-positive *user-facing* step: the
//! macro step `h` of a composition is checked as the integrators check theirs
//! ([`StepError::InvalidTimeStep`]); the negative substeps exist only inside one macro step, whose
//! end state is again at time `t_k + h`.
//!
//! # One implementation for every integrator
//!
//! [`Composition`] is generic over [`SelfAdjoint`], which the reduced integrator (both the (+)
//! equations (4.6) and the (−) equations) and the unreduced integrator implement, and is itself a
//! [`Stepper`]: the one driver ([`crate::Drive`]) gives it `run`, `integrate`, ensembles and stop
//! conditions, and its workspace holds one workspace per stage. For the unreduced integrator the step-map Jacobian of
//! the composition is the product of the stage Jacobians (chain rule,
//! [`Composition::step_with_jacobian`]), so the symplecticity of the composed map is testable.
//!
//! # The base rule must be symmetric
//!
//! A composition of a non-symmetric rule (the charged particle's left-point rule) stays at the
//! base rule's order. A run of a [`Composition`] therefore checks the symmetry once, at
//! sample points near the initial state ([`Composition::symmetry_defect`]), and returns
//! [`StepError::NotSymmetric`] otherwise.
//!
//! ```
//! # // A doctest cannot use the attribute from this crate; see the `dirac` crate and its tests.
//! use dirac_runtime::compose::CompositionMethod;
//! let m = CompositionMethod::KAHAN_LI_6;
//! assert_eq!((m.order, m.stages()), (6, 9));
//! assert!((m.coefficients.iter().sum::<f64>() - 1.0).abs() < 1e-15);
//! ```

use nalgebra::{DMatrix, SVector};

use crate::error::{StepError, Steps};
use crate::reduced::ReducedIntegrator;
use crate::sensitivity::Sensitivity;
use crate::state::UnreducedState;
use crate::stepper::{check_adaptive_step, Collect, LevelSet, StepAt, StepStats, Stepper};
use crate::system::{join, DiscreteLagrangian, LagrangianHessian, Reduced, Side, Unreduced};
use crate::unreduced::UnreducedIntegrator;

/// A symmetric composition scheme: the coefficients `γ_1, …, γ_s` of the substeps `γ_i h`, with
/// `Σ γ_i = 1` and `γ_i = γ_{s+1−i}`, and the order it reaches from a symmetric base step of
/// order 2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CompositionMethod {
    /// A short name for tables and legends.
    pub name: &'static str,
    /// The order reached from a symmetric base step of order 2.
    pub order: u32,
    /// The substep coefficients `γ_i`, in the order the stages are taken.
    pub coefficients: &'static [f64],
}

// The coefficients keep the published digits, so they can be checked against the sources; the
// compiler rounds them to the nearest f64.
#[allow(clippy::excessive_precision)]
impl CompositionMethod {
    /// The base step itself (`s = 1`, `γ_1 = 1`): order 2 for the midpoint rule.
    pub const BASE: Self = Self {
        name: "base (order 2)",
        order: 2,
        coefficients: &[1.0],
    };

    /// The triple jump, order 4 with 3 stages: `γ_1 = γ_3 = 1/(2 − 2^{1/3})`,
    /// `γ_2 = −2^{1/3}/(2 − 2^{1/3})` (Creutz & Gocksch 1989, Forest 1989, Suzuki 1990,
    /// Yoshida 1990, Phys. Lett. A 150, 262; Hairer–Lubich–Wanner eq. (II.4.4)).
    pub const TRIPLE_JUMP: Self = Self {
        name: "triple jump (order 4)",
        order: 4,
        coefficients: &[
            1.351_207_191_959_657_634_047_687_808_971_5,
            -1.702_414_383_919_315_268_095_375_617_942_9,
            1.351_207_191_959_657_634_047_687_808_971_5,
        ],
    };

    /// Yoshida's order-6 composition with 7 stages, "solution A" of Yoshida (1990), Phys.
    /// Lett. A 150, 262, Table 1 (digits as in Hairer–Lubich–Wanner §V.3.2).
    pub const YOSHIDA_6: Self = Self {
        name: "Yoshida 7-stage (order 6)",
        order: 6,
        coefficients: &[
            0.784_513_610_477_557_263_819_497_63,
            0.235_573_213_359_358_133_684_793_18,
            -1.177_679_984_178_871_006_946_415_68,
            1.315_186_320_683_911_218_884_249_73,
            -1.177_679_984_178_871_006_946_415_68,
            0.235_573_213_359_358_133_684_793_18,
            0.784_513_610_477_557_263_819_497_63,
        ],
    };

    /// Kahan & Li's order-6 composition with 9 stages (`s9odr6a`), W. Kahan and R.-C. Li,
    /// "Composition constants for raising the orders of unconventional schemes for ordinary
    /// differential equations", Math. Comp. 66 (1997) 1089–1099 (digits as in
    /// Hairer–Lubich–Wanner eq. (V.3.11)). Two more stages than [`Self::YOSHIDA_6`], with
    /// coefficients of at most 0.8 in size: a far smaller error constant.
    pub const KAHAN_LI_6: Self = Self {
        name: "Kahan-Li 9-stage (order 6)",
        order: 6,
        coefficients: &[
            0.392_161_444_007_314_139_279_250_56,
            0.332_599_136_789_359_438_599_748_64,
            -0.706_246_172_557_639_359_809_964_82,
            0.082_213_596_293_550_800_231_490_45,
            0.798_543_990_934_829_963_398_950_35,
            0.082_213_596_293_550_800_231_490_45,
            -0.706_246_172_557_639_359_809_964_82,
            0.332_599_136_789_359_438_599_748_64,
            0.392_161_444_007_314_139_279_250_56,
        ],
    };

    /// The number of stages `s`.
    pub fn stages(&self) -> usize {
        self.coefficients.len()
    }
}

/// A base step a composition can raise in order: a [`Stepper`] whose time step can be changed
/// (each stage steps with `γ_i h`) and whose rule can be tested for symmetry. The reduced
/// integrator (both the (+) equations (4.6) and the (−) equations) and the unreduced integrator
/// implement it.
pub trait SelfAdjoint: Stepper + Sized {
    /// The same integrator (same equations, Newton options and path) for the system at time step
    /// `h` (any nonzero `h`, see [`crate::System::with_time_step`]).
    fn with_time_step(&self, h: f64) -> Self;

    /// The largest relative defect `|L_d(q0, q1; −h) + L_d(q1, q0; h)| / max(|L_d(q0, q1; −h)|,
    /// |L_d(q1, q0; h)|)` over sample pairs around the configuration of `at` (see
    /// [`symmetry_defect`]). Zero for a symmetric rule, up to round-off.
    fn symmetry_defect(&self, at: &Self::State) -> f64;
}

impl<L, D, const S: usize, const K: usize, const N: usize> SelfAdjoint
    for ReducedIntegrator<L, D, S, K, N>
where
    D: Side,
    L: Reduced<D, S, K, N>,
{
    fn with_time_step(&self, h: f64) -> Self {
        let integ = Self::new(self.system().with_time_step(h), *self.options());
        // Where the system cannot eliminate, the choice has no effect; where it can, this keeps
        // the path (default or forced) of `self`.
        integ.with_elimination(self.eliminates_group())
    }

    fn symmetry_defect(&self, at: &Self::State) -> f64 {
        symmetry_defect(self.system(), &join::<S, K, N>(&at.x, &at.g))
    }
}

impl<L, const S: usize, const K: usize, const N: usize> SelfAdjoint
    for UnreducedIntegrator<L, S, K, N>
where
    L: Unreduced<S, K, N>,
{
    fn with_time_step(&self, h: f64) -> Self {
        UnreducedIntegrator::new(self.system().with_time_step(h), *self.options())
    }

    fn symmetry_defect(&self, at: &Self::State) -> f64 {
        symmetry_defect(self.system(), &at.q)
    }
}

/// A trajectory of a composition: the states at the macro steps' times `t_k` (`k h` for a fixed
/// step; the stages inside a step are not kept: with negative substeps they are not on the time
/// grid), and per macro step the Newton statistics summed over its stages.
#[derive(Clone, Debug, PartialEq)]
pub struct ComposedTrajectory<St> {
    /// The macro time step `h` (the default step of a run).
    pub h: f64,
    /// The composition that produced it.
    pub method: CompositionMethod,
    /// `states[k]` is the state at `times[k]`.
    pub states: Vec<St>,
    /// `times[k] = t_k`, the time of `states[k]` (`k h` exactly for a fixed step).
    pub times: Vec<f64>,
    /// `step_sizes[k]` is the size step `k` was taken with, bit for bit as the run passed it to
    /// the step: `h` itself for a fixed step, `h_k` with a schedule (the last step shortened to
    /// land on an end time); with adaptive steps the fictitious step `ε_k` (the physical step is
    /// `times[k + 1] − times[k]`).
    pub step_sizes: Vec<f64>,
    /// Per macro step: Newton corrections summed over the stages, the largest accepted residual
    /// and the smallest reciprocal condition estimate of the stages.
    pub stats: Vec<StepStats>,
}

impl<St> ComposedTrajectory<St> {
    /// Number of completed macro steps.
    pub fn step_count(&self) -> usize {
        self.states.len() - 1
    }

    /// The last state.
    pub fn last(&self) -> &St {
        self.states
            .last()
            .expect("a trajectory holds its initial state")
    }

    /// Mean Newton corrections per macro step (all stages).
    pub fn mean_iterations(&self) -> f64 {
        crate::StepStatsExt::mean_iterations(self.stats.as_slice())
    }
}

impl<St: std::fmt::Debug> Steps for ComposedTrajectory<St> {
    fn completed_steps(&self) -> usize {
        self.step_count()
    }
}

/// The largest relative symmetry defect accepted by a run ([`crate::Drive::run`]) of a [`Composition`]. A symmetric rule
/// written the usual way evaluates `L_d(q0, q1; −h)` and `−L_d(q1, q0; h)` with the same
/// operations up to exact negations (the difference quotient `(q1 − q0)/(−h) = (q0 − q1)/h`, the
/// midpoint `(q0 + q1)/2`), so its defect is 0 or a few units of round-off (~1e-16); a first-order
/// rule (left or right point) differs by `h (L(q0, v) − L(q1, v))`, a relative `O(|q1 − q0|)`
/// ≈ 1e-2 at the sample points. The threshold sits between with six orders of magnitude each way.
pub const SYMMETRY_TOLERANCE: f64 = 1e-10;

/// A symmetric composition of a self-adjoint base step: see the [module documentation](self).
#[derive(Clone, Debug)]
pub struct Composition<I> {
    base: I,
    method: CompositionMethod,
    /// One integrator per stage, at the substep `γ_i h`; built once, so a step allocates nothing.
    stages: Vec<I>,
}

impl<I> Composition<I> {
    /// The composition scheme.
    pub fn method(&self) -> CompositionMethod {
        self.method
    }

    /// The base integrator, at the macro time step `h`.
    pub fn base(&self) -> &I {
        &self.base
    }

    /// The error of stage `stage` (from 0), `error`, as the composition reports it: naming the
    /// stage and its substep, with the stage's step index and residual.
    fn stage_failed(&self, stage: usize, substep: f64, error: StepError) -> StepError {
        StepError::StageFailed {
            stage,
            stages: self.stages.len(),
            substep,
            error: Box::new(error),
        }
    }
}

impl<I> Composition<I>
where
    I: SelfAdjoint,
{
    /// The composition `method` of `base`; the macro step is `base`'s time step `h`, the stages
    /// step with `γ_i h`.
    pub fn new(base: I, method: CompositionMethod) -> Self {
        let h = base.time_step();
        let stages = method
            .coefficients
            .iter()
            .map(|gamma| base.with_time_step(gamma * h))
            .collect();
        Self {
            base,
            method,
            stages,
        }
    }

    /// The symmetry defect of the base rule at sample points near `at`
    /// ([`SelfAdjoint::symmetry_defect`]).
    pub fn symmetry_defect(&self, at: &I::State) -> f64 {
        self.base.symmetry_defect(at)
    }
}

impl<St> Collect<Composition<St>> for ComposedTrajectory<St::State>
where
    St: SelfAdjoint,
{
    crate::stepper::collect_steps!(
        start(composition: Composition<St>) {
            h: composition.time_step(),
            method: composition.method,
        },
        St::State,
        StepStats,
        |stats| *stats
    );
}

/// A composition is a stepper: a macro step runs the stages in order, each in its own workspace
/// (one per stage, built once per run), so each stage's Newton iteration starts from the same
/// stage of the previous two macro steps (the shape advanced by the increment extrapolated from
/// that stage's last two) and, on the sparse backend, reuses that stage's factors. A failed stage
/// fails the macro step with [`StepError::StageFailed`]: the stage, its substep and its own error
/// with the macro step's index.
impl<I> Stepper for Composition<I>
where
    I: SelfAdjoint,
{
    type State = I::State;
    /// Per macro step: Newton corrections and factorizations summed over the stages, the largest
    /// accepted residual and the smallest reciprocal condition estimate of the stages.
    type Record = StepStats;
    type Workspace = Vec<I::Workspace>;
    type Trajectory = ComposedTrajectory<I::State>;

    /// The macro time step `h`.
    fn time_step(&self) -> f64 {
        self.base.time_step()
    }

    fn physical_time(&self, state: &I::State) -> Option<f64> {
        self.base.physical_time(state)
    }

    fn monitor(&self, at: StepAt<'_>, state: &I::State) -> Result<Option<f64>, StepError> {
        self.base.monitor(at, state)
    }

    fn level_set(&self, state: &I::State) -> Option<LevelSet> {
        self.base.level_set(state)
    }

    /// The base integrator's checks (the macro step must be positive and finite, the parameters
    /// and the initial state finite), and the discrete Lagrangian symmetric at sample points near
    /// `initial` ([`Self::symmetry_defect`] at most [`SYMMETRY_TOLERANCE`]).
    fn check(&self, initial: &I::State) -> Result<(), StepError> {
        self.base.check(initial)?;
        let defect = self.symmetry_defect(initial);
        // A NaN defect is rejected too.
        if defect.is_nan() || defect > SYMMETRY_TOLERANCE {
            return Err(StepError::NotSymmetric {
                defect,
                tolerance: SYMMETRY_TOLERANCE,
            });
        }
        Ok(())
    }

    /// The base integrator's domain check, on the macro step's end state.
    fn check_domain(&self, k: usize, state: &I::State) -> Result<(), StepError> {
        self.base.check_domain(k, state)
    }

    fn workspace(&self) -> Vec<I::Workspace> {
        self.stages.iter().map(Stepper::workspace).collect()
    }

    fn control_dim(&self) -> usize {
        self.stages.first().map_or(0, Stepper::control_dim)
    }

    /// Every stage takes the macro step's controls `u`: the forces of a composition are its
    /// stages' forces, each at its stage's time step `γ_i h`. A macro step `at` of size `h_k`
    /// runs stage `i` at [`StepAt::scaled`]`(γ_i)`, the same index and controls with size
    /// `γ_i h_k` (for `h_k = h` the stage's own step, bit for bit).
    fn step_with(
        &self,
        workspace: &mut Vec<I::Workspace>,
        at: StepAt<'_>,
        state: &I::State,
    ) -> Result<(I::State, StepStats), StepError> {
        if workspace.len() != self.stages.len() {
            return Err(StepError::InvalidSize {
                reason: format!(
                    "the workspace has {} stage workspaces, the composition {} stages: it is \
                     another composition's",
                    workspace.len(),
                    self.stages.len()
                ),
            });
        }
        let mut total = StepStats::default();
        let mut current = state.clone();
        let stages = self.stages.iter().zip(workspace.iter_mut());
        for (i, ((stage, stage_workspace), gamma)) in
            stages.zip(self.method.coefficients).enumerate()
        {
            let stage_at = at.scaled(*gamma);
            let (next, record) = stage
                .step_with(stage_workspace, stage_at, &current)
                .and_then(|(next, record)| {
                    check_adaptive_step(stage, stage_at, &current, &next)?;
                    Ok((next, record))
                })
                .map_err(|e| self.stage_failed(i, stage_at.h, e))?;
            total.accumulate(record.as_ref());
            current = next;
        }
        Ok((current, total))
    }
}

impl<L, const S: usize, const K: usize, const N: usize> Composition<UnreducedIntegrator<L, S, K, N>>
where
    L: LagrangianHessian<S, K, N> + Clone,
{
    /// Takes macro step `k` from `from` and returns the end state with the Jacobian of the
    /// composed step map, `M = M_s ⋯ M_2 M_1` by the chain rule, `M_i` the step-map Jacobian of
    /// stage `i` ([`UnreducedIntegrator::step_jacobian`]). A product of symplectic matrices is
    /// symplectic, so [`Sensitivity::symplecticity_defect`] of `M` stays at round-off.
    pub fn step_with_jacobian(
        &self,
        k: usize,
        from: &UnreducedState<N>,
    ) -> Result<(UnreducedState<N>, Sensitivity), StepError> {
        let mut current = *from;
        let mut product = Sensitivity {
            state: DMatrix::identity(2 * N, 2 * N),
            control: DMatrix::zeros(2 * N, 0),
        };
        for (i, stage) in self.stages.iter().enumerate() {
            let (next, _) = stage
                .step_from(k, &current, &current.q)
                .map_err(|e| self.stage_failed(i, stage.time_step(), e))?;
            let m = stage
                .step_jacobian(k, &current, &next)
                .map_err(|e| self.stage_failed(i, stage.time_step(), e))?;
            product = m.compose(&product)?;
            current = next;
        }
        Ok((current, product))
    }
}

/// The largest relative defect `|L_d(q0, q1; −h) + L_d(q1, q0; h)| / max(|L_d(q0, q1; −h)|,
/// |L_d(q1, q0; h)|)` of `system` over sample pairs around `q`: `(q, q + δ d_j)` and
/// `(q + δ d_j, q)` for three fixed directions `d_j` with entries in `[−1, 1]` and
/// `δ = 0.05 max(1, ‖q‖∞)`. NaN when a sample point is outside the Lagrangian's domain.
///
/// A necessary condition checked at a few points, not a proof: a Lagrangian that is symmetric
/// near `q` only would pass.
pub fn symmetry_defect<L, const S: usize, const K: usize, const N: usize>(
    system: &L,
    q: &SVector<f64, N>,
) -> f64
where
    L: DiscreteLagrangian<S, K, N>,
{
    let backward = system.with_time_step(-system.time_step());
    let delta = 0.05 * q.amax().max(1.0);
    let mut worst: f64 = 0.0;
    for j in 0..3 {
        let d = SVector::<f64, N>::from_fn(|i, _| sample_direction(j, i));
        let p = q + delta * d;
        for (q0, q1) in [(q, &p), (&p, q)] {
            let minus = backward.lagrangian(q0, q1);
            let plus = system.lagrangian(q1, q0);
            worst = worse_defect(worst, minus, plus);
        }
    }
    worst
}

/// Entry `i` of the `j`-th sample direction of [`symmetry_defect`] (and of every other
/// integrator's symmetry test, those of other crates included): fixed directions, neither
/// aligned with an axis nor with each other.
pub fn sample_direction(j: usize, i: usize) -> f64 {
    (1.0 + 0.37 * j as f64 + 0.61 * i as f64 + 0.13 * (i * j) as f64).sin()
}

/// `worst` updated with the relative defect of `L_d(q0, q1; −h) = minus` and
/// `L_d(q1, q0; h) = plus`. A NaN stays NaN (`f64::max` would drop it), so the caller rejects it.
pub(crate) fn worse_defect(worst: f64, minus: f64, plus: f64) -> f64 {
    let scale = minus.abs().max(plus.abs()).max(f64::MIN_POSITIVE);
    let defect = (minus + plus).abs() / scale;
    if defect.is_nan() || worst.is_nan() {
        f64::NAN
    } else {
        worst.max(defect)
    }
}

#[cfg(test)]
mod tests {
    use super::CompositionMethod;

    /// The order conditions a symmetric composition of a symmetric order-2 method must satisfy
    /// (Hairer–Lubich–Wanner §V.3.2): `Σ γ = 1`, `Σ γ³ = 0` for order 4, and also `Σ γ⁵ = 0` for
    /// order 6 (with one more condition, which only the observed order on Kepler checks). The
    /// tables have 20+ digits, so these hold to a few ulps; a typo in a digit breaks them.
    #[test]
    fn coefficients_satisfy_the_order_conditions() {
        for m in [
            CompositionMethod::BASE,
            CompositionMethod::TRIPLE_JUMP,
            CompositionMethod::YOSHIDA_6,
            CompositionMethod::KAHAN_LI_6,
        ] {
            let g = m.coefficients;
            let power = |p: i32| g.iter().map(|c| c.powi(p)).sum::<f64>();
            let scale = |p: i32| g.iter().map(|c| c.abs().powi(p)).sum::<f64>();
            assert!(
                (power(1) - 1.0).abs() < 1e-15,
                "{}: Σγ = {}",
                m.name,
                power(1)
            );
            let symmetric = g.iter().zip(g.iter().rev()).all(|(a, b)| a == b);
            assert!(symmetric, "{}: not symmetric", m.name);
            if m.order >= 4 {
                assert!(
                    power(3).abs() < 1e-14 * scale(3),
                    "{}: Σγ³ = {:e}",
                    m.name,
                    power(3)
                );
            }
            if m.order >= 6 {
                assert!(
                    power(5).abs() < 1e-14 * scale(5),
                    "{}: Σγ⁵ = {:e}",
                    m.name,
                    power(5)
                );
            }
        }
    }
}
