//! Typed errors: a failed step is a value the caller cannot miss, never a panic or a silent NaN.

/// Why one step could not be computed. Every variant carries the step index `step` (the step
/// from `t_step` to `t_{step+1}`; 0 for problems with the initial data) and the residual
/// `‖R‖∞` at the last iterate.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum StepError {
    /// Newton's iteration reached its cap without meeting the tolerances.
    #[error(
        "step {step}: Newton iteration did not converge in {iterations} iterations \
         (residual {residual:.3e}); try a smaller time step or a larger iteration cap"
    )]
    NotConverged {
        /// Index of the failed step.
        step: usize,
        /// Newton corrections taken.
        iterations: usize,
        /// `‖R‖∞` at the last iterate.
        residual: f64,
    },
    /// The Jacobian of the step equations is singular: the discrete Lagrangian is degenerate at
    /// this point (or the reduction is not valid here, e.g. where the action is not free).
    #[error("step {step}: singular Jacobian of the step equations (residual {residual:.3e})")]
    SingularJacobian {
        /// Index of the failed step.
        step: usize,
        /// `‖R‖∞` at the iterate whose Jacobian is singular.
        residual: f64,
    },
    /// The step converged but its Jacobian is too ill-conditioned for the result to be trusted:
    /// its reciprocal condition estimate is below [`NewtonOptions::min_rcond`]. For reduced
    /// equations this happens where the symmetry action is not free (Remark 7.1).
    ///
    /// [`NewtonOptions::min_rcond`]: crate::NewtonOptions::min_rcond
    #[error(
        "step {step}: the step Jacobian is ill-conditioned (reciprocal condition estimate {rcond:.3e}, \
         residual {residual:.3e}); the solution cannot be trusted: the equations degenerate near a \
         singularity of the coordinates or of the reduction (e.g. where the symmetry action is not free)"
    )]
    IllConditioned {
        /// Index of the failed step.
        step: usize,
        /// The reciprocal condition estimate.
        rcond: f64,
        /// `‖R‖∞` at the solution.
        residual: f64,
    },
    /// A residual, Jacobian, correction or state component is NaN or infinite.
    #[error("step {step}: non-finite value in {what} (residual {residual:.3e})")]
    NonFinite {
        /// Index of the failed step.
        step: usize,
        /// What was not finite.
        what: &'static str,
        /// `‖R‖∞` at the last finite iterate (infinite if there was none).
        residual: f64,
    },
    /// An atlas of charts was set up inconsistently (see [`crate::atlas::AtlasIntegrator`]).
    #[error("invalid atlas: {reason}")]
    InvalidAtlas {
        /// What is wrong.
        reason: &'static str,
    },
    /// The sizes of a run-time-sized system ([`crate::element`]) do not fit its stencils, or a
    /// state does not have the system's number of coordinates.
    #[error("invalid size: {reason}")]
    InvalidSize {
        /// What is wrong, with the figures.
        reason: String,
    },
    /// The time step is not a positive finite number.
    #[error("invalid time step h = {h}: it must be positive and finite")]
    InvalidTimeStep {
        /// The offending value.
        h: f64,
    },
    /// A step-size policy gave a size that is not a positive finite number for step `step`
    /// (see [`crate::driver::StepSize`]).
    #[error("step {step}: invalid step size h = {h} from the step-size policy: it must be positive and finite")]
    InvalidStepSize {
        /// Index of the step.
        step: usize,
        /// The offending value.
        h: f64,
    },
    /// A step-size schedule ([`crate::driver::StepSizes`]) has no size for step `step`: it is
    /// shorter than the run.
    #[error("step {step}: the step-size schedule ended before the run (it has {step} size(s)); give one size per step or a shorter run")]
    ScheduleEnded {
        /// Index of the step that has no size.
        step: usize,
    },
    /// A run was configured inconsistently (no length, an end time before the start, a zero
    /// output stride; see [`crate::driver::Run`]). Nothing was computed.
    #[error("invalid run: {reason}")]
    InvalidRun {
        /// What is wrong, with the figures.
        reason: String,
    },
    /// A symmetric composition was asked of a discrete Lagrangian that is not symmetric:
    /// `L_d(q0, q1; −h) + L_d(q1, q0; h)` is not zero at sample points near the initial state
    /// (see [`crate::compose`]). Its step is not self-adjoint, so the composition does not reach
    /// its order.
    #[error(
        "the discrete Lagrangian is not symmetric: |L_d(q0, q1; -h) + L_d(q1, q0; h)| = {defect:.3e} \
         relative to |L_d| at a sample point near the initial state (accepted: at most {tolerance:.0e}); \
         a composition of a non-symmetric rule (e.g. the left-point rule) does not reach its order: \
         use a symmetric rule such as the midpoint or trapezoidal rule"
    )]
    NotSymmetric {
        /// The largest relative defect found.
        defect: f64,
        /// The largest accepted.
        tolerance: f64,
    },
    /// The initial state does not satisfy the holonomic constraints: `‖φ(q_0)‖∞` exceeds the
    /// tolerance (see [`crate::constrained`]).
    #[error(
        "the initial configuration violates the constraints: |phi(q0)| = {residual:.3e} > {tolerance:.3e}; \
         start on the constraint manifold"
    )]
    ConstraintViolated {
        /// `‖φ(q_0)‖∞`.
        residual: f64,
        /// The tolerance.
        tolerance: f64,
    },
    /// What was asked is not available for this system (e.g. step sensitivities of a system
    /// compiled without its step partials).
    #[error("not available: {what}")]
    Unsupported {
        /// What is not available, and why.
        what: &'static str,
    },
    /// The controls given for a step are not the ones the system declares (`controls(...)` in
    /// its attribute, [`crate::DiscreteLagrangian::CONTROLS`]): the wrong number of values, or
    /// a control sequence that ends before the run does.
    #[error(
        "step {step}: {found} control value(s) given, the system declares {expected} \
         (`controls(...)` in its attribute); a control sequence needs one row per step"
    )]
    InvalidControls {
        /// Index of the step.
        step: usize,
        /// The number of controls the system declares.
        expected: usize,
        /// The number of values given (0 past the end of a sequence).
        found: usize,
    },
}

impl StepError {
    /// A short name of the failure, for one-line summaries (e.g. [`IntegrationError`]'s
    /// message); the full message, with the figures, is the `Display` of `self`.
    pub fn kind(&self) -> &'static str {
        match self {
            StepError::NotConverged { .. } => "Newton did not converge",
            StepError::SingularJacobian { .. } => "singular Jacobian",
            StepError::IllConditioned { .. } => "ill-conditioned Jacobian",
            StepError::NonFinite { .. } => "non-finite value",
            StepError::InvalidAtlas { .. } => "invalid atlas",
            StepError::InvalidSize { .. } => "invalid size",
            StepError::InvalidTimeStep { .. } => "invalid time step",
            StepError::InvalidStepSize { .. } => "invalid step size",
            StepError::ScheduleEnded { .. } => "step-size schedule ended",
            StepError::InvalidRun { .. } => "invalid run",
            StepError::NotSymmetric { .. } => "non-symmetric discrete Lagrangian",
            StepError::InvalidControls { .. } => "invalid controls",
            StepError::ConstraintViolated { .. } => "constraint violated",
            StepError::Unsupported { .. } => "not available",
        }
    }

    /// Index of the step that failed.
    pub fn step(&self) -> usize {
        match *self {
            StepError::NotConverged { step, .. }
            | StepError::SingularJacobian { step, .. }
            | StepError::IllConditioned { step, .. }
            | StepError::NonFinite { step, .. }
            | StepError::InvalidStepSize { step, .. }
            | StepError::ScheduleEnded { step }
            | StepError::InvalidControls { step, .. } => step,
            StepError::InvalidTimeStep { .. }
            | StepError::InvalidRun { .. }
            | StepError::NotSymmetric { .. }
            | StepError::InvalidAtlas { .. }
            | StepError::InvalidSize { .. }
            | StepError::Unsupported { .. }
            | StepError::ConstraintViolated { .. } => 0,
        }
    }

    /// `‖R‖∞` at the last iterate (`NaN` for an invalid time step, a non-symmetric Lagrangian,
    /// an invalid atlas or invalid controls, where no residual exists).
    pub fn residual(&self) -> f64 {
        match *self {
            StepError::NotConverged { residual, .. }
            | StepError::SingularJacobian { residual, .. }
            | StepError::IllConditioned { residual, .. }
            | StepError::NonFinite { residual, .. } => residual,
            StepError::InvalidTimeStep { .. }
            | StepError::InvalidStepSize { .. }
            | StepError::ScheduleEnded { .. }
            | StepError::InvalidRun { .. }
            | StepError::NotSymmetric { .. }
            | StepError::InvalidAtlas { .. }
            | StepError::InvalidSize { .. }
            | StepError::InvalidControls { .. }
            | StepError::Unsupported { .. } => f64::NAN,
            StepError::ConstraintViolated { residual, .. } => residual,
        }
    }
}

/// A trajectory that knows how many steps it holds.
pub trait Steps {
    /// Number of completed steps.
    fn completed_steps(&self) -> usize;
}

/// An integration that stopped at a failed step. The trajectory computed up to that step is
/// kept, intact, in `trajectory`.
///
/// Its message names the step, the kind of failure ([`StepError::kind`]) and how much was kept;
/// the cause itself, with its figures, is [`std::error::Error::source`] (the [`StepError`]) and is
/// not repeated in the message, so a printed error chain shows each cause once.
#[derive(Clone, Debug, thiserror::Error)]
#[error(
    "integration stopped at step {} ({}): {} of {requested} steps completed, the trajectory so far kept",
    source.step(),
    source.kind(),
    trajectory.completed_steps()
)]
pub struct IntegrationError<T: Steps + std::fmt::Debug> {
    /// The step that failed.
    pub source: StepError,
    /// Everything computed before the failure.
    pub trajectory: T,
    /// The number of steps that were asked for.
    pub requested: usize,
}

impl<T: Steps + std::fmt::Debug> IntegrationError<T> {
    pub(crate) fn new(source: StepError, trajectory: T, requested: usize) -> Self {
        Self {
            source,
            trajectory,
            requested,
        }
    }
}
