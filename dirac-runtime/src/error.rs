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
    /// The step Jacobian is too ill-conditioned for a result to be trusted: its reciprocal
    /// condition estimate is below [`NewtonOptions::min_rcond`]. Either the iteration met its
    /// tolerance (`residual ≤ tolerance`) on that Jacobian, so the step converged but its
    /// solution has few or no correct digits, or it stopped without meeting it (`residual >
    /// tolerance`: not converged, and the ill-conditioned Jacobian is the likely cause); the
    /// message says which. For reduced equations this happens where the symmetry action is not
    /// free (Remark 7.1).
    ///
    /// [`NewtonOptions::min_rcond`]: crate::NewtonOptions::min_rcond
    #[error("{}", ill_conditioned_message(*.step, *.rcond, *.residual, *.tolerance))]
    IllConditioned {
        /// Index of the failed step.
        step: usize,
        /// The reciprocal condition estimate.
        rcond: f64,
        /// `‖R‖∞` at the last iterate (the solution when it is at most `tolerance`).
        residual: f64,
        /// The residual tolerance of the step ([`crate::NewtonOptions::residual_tolerance`]).
        tolerance: f64,
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
    /// Sizes that do not fit: those of a run-time-sized system ([`crate::element`]) against its
    /// stencils, a state or vector without the system's number of coordinates, or a workspace
    /// or trajectory that is not of this integrator.
    #[error("invalid size: {reason}")]
    InvalidSize {
        /// What is wrong, with the figures.
        reason: String,
    },
    /// An initial configuration that is not on its manifold: a rotation coordinate that is not a
    /// rotation matrix, or a direction that is not a unit vector with an orthonormal frame (see
    /// [`crate::lie`]).
    #[error("the initial configuration is not on its manifold: {reason}")]
    OffManifold {
        /// Which coordinate, and by how much.
        reason: String,
    },
    /// The step monitor `g(q)` of a system with adaptive steps (`time(t), adapt = |q| g`) is not
    /// a positive finite number at the state step `step` reached (0: the initial state): the
    /// physical step `Δt ≈ ε g` would vanish, turn back or be undefined there.
    #[error(
        "step {step}: the step monitor g(q) = {value} is not a positive finite number; adaptive steps need \
         g > 0 along the whole run (a monitor like a distance vanishes at a collision: add a floor, e.g. \
         `r.powf(1.5) + 1e-6`)"
    )]
    InvalidMonitor {
        /// The step after which the monitor was evaluated (0 for the initial state).
        step: usize,
        /// The monitor's value.
        value: f64,
    },
    /// Adaptive steps: the physical time step `Δt` that step `step` solved for does not have the
    /// sign of the fictitious step — the equations have a root that goes back in time, and Newton
    /// found it (the fictitious step is too large where the monitor is small).
    #[error(
        "step {step}: the physical time step Δt = {dt:.3e} does not have the sign of the fictitious step: the \
         step went back in time; take a smaller fictitious step (or a monitor that is smaller where the motion \
         is fast)"
    )]
    TimeReversed {
        /// The step.
        step: usize,
        /// The physical time step it solved for.
        dt: f64,
    },
    /// A state outside the domain the system declares (`domain(r > 0.0)` in its attribute, see
    /// [`crate::domain`]): after step `step` (`initial`: the initial state, before any step)
    /// coordinate `coordinate` has the value `value`, which violates the bound `coordinate
    /// bound`. After a step this is a step too coarse for the motion there (a solution of the
    /// step equations that has left the region where the Lagrangian means anything); the
    /// states before it are kept.
    #[error("{}", out_of_domain_message(*.step, *.initial, .coordinate, *.value, .bound))]
    OutOfDomain {
        /// The step that reached the state (0 with `initial`).
        step: usize,
        /// Whether the state is the initial one.
        initial: bool,
        /// The coordinate's name.
        coordinate: String,
        /// Its value.
        value: f64,
        /// The bound it violates, e.g. `> 0`.
        bound: String,
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
    /// output stride, a start time on a run with adaptive steps other than the initial state's
    /// own; see [`crate::driver::Run`]). Nothing was computed.
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
    /// its attribute, [`crate::System::CONTROLS`]): the wrong number of values
    /// (`found ≠ expected`), or a control law with no values for step `step` (`found =
    /// expected`: a [`crate::ControlSequence`] of `step` rows, which ended before the run did).
    #[error("{}", controls_message(*.step, *.expected, *.found))]
    InvalidControls {
        /// Index of the step.
        step: usize,
        /// The number of controls the system declares.
        expected: usize,
        /// The number of values given per step: a control sequence's row length, or the
        /// declared number for a feedback law.
        found: usize,
    },
    /// A stage of a composition ([`crate::Composition`]) failed: `error` is the stage's own
    /// error, with the index of the macro step and the stage's residual.
    #[error(
        "stage {} of {stages} (substep {substep:.6e}) of the composition failed: {error}",
        stage + 1
    )]
    StageFailed {
        /// Index of the stage that failed, from 0.
        stage: usize,
        /// The number of stages of a macro step.
        stages: usize,
        /// The stage's time step `γ_i h`.
        substep: f64,
        /// The stage's error.
        error: Box<StepError>,
    },
    /// A run needs more memory than can be allocated: checked before the memory is allocated
    /// (for a run-time-sized system, [`crate::element`], the workspace its sizes imply; for a
    /// collected run, [`crate::Run::collect`], the trajectory: every state of a run of known
    /// length before the first step, else each state before it is kept), so that a system or a
    /// run too large for the machine is an error rather than an aborted process.
    #[error(
        "not enough memory: {what} needs {bytes} bytes ({:.2} GiB), which cannot be allocated; \
         choose smaller sizes, fewer states kept (`.stream()` keeps none) or a machine with more \
         memory",
        *bytes as f64 / (1u64 << 30) as f64
    )]
    OutOfMemory {
        /// What needs the memory.
        what: String,
        /// The bytes needed.
        bytes: u128,
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
            StepError::OffManifold { .. } => "configuration off its manifold",
            StepError::OutOfDomain { .. } => "state outside the declared domain",
            StepError::InvalidTimeStep { .. } => "invalid time step",
            StepError::InvalidMonitor { .. } => "invalid step monitor",
            StepError::TimeReversed { .. } => "time went back",
            StepError::InvalidStepSize { .. } => "invalid step size",
            StepError::ScheduleEnded { .. } => "step-size schedule ended",
            StepError::InvalidRun { .. } => "invalid run",
            StepError::NotSymmetric { .. } => "non-symmetric discrete Lagrangian",
            StepError::InvalidControls { .. } => "invalid controls",
            StepError::ConstraintViolated { .. } => "constraint violated",
            StepError::Unsupported { .. } => "not available",
            StepError::StageFailed { error, .. } => error.kind(),
            StepError::OutOfMemory { .. } => "not enough memory",
        }
    }

    /// Index of the step that failed.
    pub fn step(&self) -> usize {
        match *self {
            StepError::StageFailed { ref error, .. } => error.step(),
            StepError::NotConverged { step, .. }
            | StepError::SingularJacobian { step, .. }
            | StepError::IllConditioned { step, .. }
            | StepError::NonFinite { step, .. }
            | StepError::InvalidStepSize { step, .. }
            | StepError::ScheduleEnded { step }
            | StepError::InvalidControls { step, .. }
            | StepError::InvalidMonitor { step, .. }
            | StepError::OutOfDomain { step, .. }
            | StepError::TimeReversed { step, .. } => step,
            StepError::InvalidTimeStep { .. }
            | StepError::InvalidRun { .. }
            | StepError::NotSymmetric { .. }
            | StepError::InvalidAtlas { .. }
            | StepError::InvalidSize { .. }
            | StepError::OffManifold { .. }
            | StepError::Unsupported { .. }
            | StepError::OutOfMemory { .. }
            | StepError::ConstraintViolated { .. } => 0,
        }
    }

    /// `‖R‖∞` at the last iterate (`NaN` for an invalid time step, a non-symmetric Lagrangian,
    /// an invalid atlas or invalid controls, where no residual exists).
    pub fn residual(&self) -> f64 {
        match *self {
            StepError::StageFailed { ref error, .. } => error.residual(),
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
            | StepError::OffManifold { .. }
            | StepError::InvalidControls { .. }
            | StepError::InvalidMonitor { .. }
            | StepError::OutOfDomain { .. }
            | StepError::TimeReversed { .. }
            | StepError::OutOfMemory { .. }
            | StepError::Unsupported { .. } => f64::NAN,
            StepError::ConstraintViolated { residual, .. } => residual,
        }
    }
}

/// The message of [`StepError::IllConditioned`]: a converged step whose solution cannot be
/// trusted, or a step that did not converge on an ill-conditioned Jacobian.
fn ill_conditioned_message(step: usize, rcond: f64, residual: f64, tolerance: f64) -> String {
    let cause = "the equations degenerate near a singularity of the coordinates or of the \
                 reduction (e.g. where the symmetry action is not free)";
    if residual <= tolerance {
        format!(
            "step {step}: the step Jacobian is ill-conditioned (reciprocal condition estimate \
             {rcond:.3e}, residual {residual:.3e}): the step converged but its solution cannot be \
             trusted: {cause}"
        )
    } else {
        format!(
            "step {step}: Newton iteration did not converge (residual {residual:.3e} above the \
             tolerance {tolerance:.3e}) on an ill-conditioned step Jacobian (reciprocal condition \
             estimate {rcond:.3e}): {cause}"
        )
    }
}

/// The message of [`StepError::OutOfDomain`]: the state a step reached, or the initial state,
/// outside the declared domain.
fn out_of_domain_message(
    step: usize,
    initial: bool,
    coordinate: &str,
    value: f64,
    bound: &str,
) -> String {
    if initial {
        format!(
            "the initial state has {coordinate} = {value}, outside the declared domain \
             ({coordinate} {bound}); start inside it"
        )
    } else {
        format!(
            "step {step}: the state it reached has {coordinate} = {value}, outside the declared \
             domain ({coordinate} {bound}): the step equations have a solution there that means \
             nothing, and Newton found it; the time step is too coarse for the motion here \
             (take a smaller one, or adaptive steps)"
        )
    }
}

/// The message of [`StepError::InvalidControls`]: the wrong number of values, or a law (a
/// sequence) that ended.
fn controls_message(step: usize, expected: usize, found: usize) -> String {
    if found == expected {
        format!(
            "step {step}: the controls ended: the control law has no values for step {step} \
             (a control sequence ended after {step} row(s) of {found} value(s)); a control \
             sequence needs one row per step"
        )
    } else {
        format!(
            "step {step}: {found} control value(s) given, the system declares {expected} \
             (`controls(...)` in its attribute)"
        )
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
