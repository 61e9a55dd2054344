//! The one system model: what every system answers, whatever its family.
//!
//! A system is a discrete Lagrangian `L_d(q0, q1; h, θ)` with its parameters `θ` (the time step
//! `h` one of them) held in a value. Three families extend [`System`] with the straight-line
//! functions of their steps: [`crate::DiscreteLagrangian`] (`Q = Σ × G` with `G` acting by
//! translation, §2.2.1 of the paper), [`crate::LieLagrangian`] (rotations and directions) and
//! [`crate::ElementLagrangian`] (a sum over elements, sized at run time). What they share — the
//! parameters, the time step and the same system at another one, the controls, the time
//! coordinate of adaptive steps, the declared domain and the coordinates' names — is declared
//! here once, and the copy of a system that a step of its own size or with its own controls
//! solves is formed by one function for every integrator.
//!
//! # Constants and methods
//!
//! Each item comes twice: a constant that `#[reduced_lagrangian]` sets for a system compiled in
//! (`PARAMETERS`, `CONTROLS`, `TIME`, `DOMAIN`), and a method the integrators and output read,
//! whose default returns the constant. A system given at run time (the text front end), whose
//! constants cannot know what its text declares, leaves the constants at their defaults (or
//! empty) and overrides the methods. Code written against the trait reads the methods only.
//!
//! ```
//! use dirac_runtime::System;
//!
//! /// `L_d` of a free particle, `m |q1 − q0|² / (2h)`, as its parameters only.
//! #[derive(Clone, Copy)]
//! struct Free {
//!     h: f64,
//!     m: f64,
//! }
//!
//! impl System for Free {
//!     const PARAMETERS: &'static [&'static str] = &["h", "m"];
//!     fn parameter_values(&self) -> Vec<f64> {
//!         vec![self.h, self.m]
//!     }
//!     fn time_step(&self) -> f64 {
//!         self.h
//!     }
//!     fn with_time_step(&self, h: f64) -> Self {
//!         Self { h, ..*self }
//!     }
//!     fn with_controls(&self, _u: &[f64]) -> Self {
//!         *self
//!     }
//!     fn coordinate_names(&self) -> Vec<&str> {
//!         vec!["x"]
//!     }
//! }
//!
//! let sys = Free { h: 0.1, m: 2.0 };
//! assert_eq!(sys.parameter_names(), ["h", "m"]);
//! assert_eq!(sys.with_time_step(0.05).parameter_values(), [0.05, 2.0]);
//! assert_eq!(sys.control_count(), 0);
//! ```

use crate::domain::Bound;
use crate::error::StepError;

/// What every system answers, whatever its family: its parameters, its time step `h` and the
/// same system at another step, its controls, the time coordinate of adaptive steps, its
/// declared domain and the names of its coordinates (see the [module documentation](self)).
/// [`crate::DiscreteLagrangian`], [`crate::LieLagrangian`] and [`crate::ElementLagrangian`]
/// extend it; `#[reduced_lagrangian]` implements it for the type it emits.
pub trait System {
    /// Names of the scalar parameters `θ`, in declaration order (the time step among them).
    const PARAMETERS: &'static [&'static str];

    /// Names of the controls (`controls(..)` in the attribute): parameters that a control law
    /// sets before every step ([`crate::Run::feedback`], [`crate::Run::controls`]), in the order
    /// a control vector `u_k` lists them. Empty for a system without controls.
    const CONTROLS: &'static [&'static str] = &[];

    /// Adaptive steps (`time(t), adapt = |q| g` in the attribute; see [`crate::adaptive`]): the
    /// index of the coordinate that is physical time, in the family's own list of coordinates —
    /// among the group coordinates `g` of a [`crate::DiscreteLagrangian`] (so `q[S + i]`), among
    /// the [`crate::LieLagrangian::COORDINATES`] of a system on rotation groups. `None` for a
    /// system stepped in physical time.
    const TIME: Option<usize> = None;

    /// The domain the system declares (`domain(r > 0.0)` in the attribute; see
    /// [`crate::domain`]): bounds on coordinates of the configuration that every state must
    /// satisfy, checked on the initial state and after every step. Empty (the default): no
    /// domain. Only the flat family ([`crate::DiscreteLagrangian`]) declares one; the integrators
    /// of the other families refuse a system that does ([`StepError::Unsupported`]) rather than
    /// not check it.
    const DOMAIN: &'static [Bound] = &[];

    /// The names of the parameters: [`Self::PARAMETERS`] for a system compiled in; a system
    /// given at run time says them here. What output (column names, metadata) reads.
    fn parameter_names(&self) -> Vec<&str> {
        Self::PARAMETERS.to_vec()
    }

    /// The parameter values, in the order of [`Self::parameter_names`]: what the integrators'
    /// input checks read (every value finite) and output records.
    fn parameter_values(&self) -> Vec<f64>;

    /// The time step `h`.
    fn time_step(&self) -> f64;

    /// The same system with time step `h` in place of [`Self::time_step`]: the discrete
    /// Lagrangian `L_d(q0, q1; h)` at another step, every other parameter (and size) unchanged.
    ///
    /// Any nonzero `h` is accepted here, negative included: a symmetric composition
    /// ([`crate::compose`]) steps with `γ_i h` where some `γ_i < 0`. The integrators still reject
    /// a user-facing time step that is not positive ([`StepError::InvalidTimeStep`]).
    fn with_time_step(&self, h: f64) -> Self
    where
        Self: Sized;

    /// The number of controls, what the integrators check a control vector against:
    /// `Self::CONTROLS.len()` for a system compiled in; a system given at run time says it here.
    fn control_count(&self) -> usize {
        Self::CONTROLS.len()
    }

    /// The names of the controls, [`Self::CONTROLS`] for a system compiled in; a system given at
    /// run time says them here (where it knows them: empty otherwise, with
    /// [`Self::control_count`] still the number).
    fn control_names(&self) -> Vec<&str> {
        Self::CONTROLS.to_vec()
    }

    /// The same system with its controls set to `u` (in the order of [`Self::control_names`],
    /// of length [`Self::control_count`]; the caller checks the length, and the integrators
    /// refuse another one with [`StepError::InvalidControls`]), every other parameter unchanged.
    fn with_controls(&self, u: &[f64]) -> Self
    where
        Self: Sized;

    /// Adaptive steps: the index of the time coordinate, [`Self::TIME`] for a system compiled
    /// in; a system given at run time says it here. What the integrators and output read.
    fn time_index(&self) -> Option<usize> {
        Self::TIME
    }

    /// The declared domain: [`Self::DOMAIN`] for a system compiled in; a system given at run
    /// time says it here. What the integrators check.
    fn domain(&self) -> &[Bound] {
        Self::DOMAIN
    }

    /// The names of the declared coordinates, in the order of the configuration: a flat
    /// system's shape coordinates then its group coordinates (`q = (x, g)`, §2.2.1); the
    /// coordinates of a system on rotation groups (a rotation or a direction is one name for its
    /// block of the point); the coordinate arrays of an element-wise system (each as many
    /// entries as its sizes give).
    fn coordinate_names(&self) -> Vec<&str>;
}

/// The system of step `k`: `sys` itself (`None`: borrow it, bit for bit the fixed-step system)
/// when the step has the system's own size `h` and no controls are given, otherwise a copy with
/// the controls `u` set ([`System::with_controls`]) and the time step `h`
/// ([`System::with_time_step`]). The typed error of step `k` when `u` has the wrong length or a
/// value that is not finite ([`check_controls`]). What every family's step and sensitivity form
/// their system with.
#[inline]
pub(crate) fn system_at<L: System>(
    sys: &L,
    k: usize,
    h: f64,
    u: &[f64],
) -> Result<Option<L>, StepError> {
    // The step of every fixed-step run without controls, decided inline.
    if u.is_empty() && same_step(h, sys.time_step()) {
        return Ok(None);
    }
    system_with(sys, k, h, u)
}

/// [`system_at`] when the step has controls or a size of its own: a copy of the system.
fn system_with<L: System>(sys: &L, k: usize, h: f64, u: &[f64]) -> Result<Option<L>, StepError> {
    let controlled = if u.is_empty() {
        None
    } else {
        check_controls(k, sys.control_count(), u)?;
        Some(sys.with_controls(u))
    };
    if same_step(h, sys.time_step()) {
        return Ok(controlled);
    }
    Ok(Some(match controlled {
        Some(c) => c.with_time_step(h),
        None => sys.with_time_step(h),
    }))
}

/// Whether `h` is the system's own step `own`, bit for bit (then the system serves unchanged).
#[inline]
pub(crate) fn same_step(h: f64, own: f64) -> bool {
    h.to_bits() == own.to_bits()
}

/// The typed error of step `k` when the controls `u` (not empty) are not `expected` in number
/// or have a value that is not finite.
fn check_controls(k: usize, expected: usize, u: &[f64]) -> Result<(), StepError> {
    if u.len() != expected {
        return Err(StepError::InvalidControls {
            step: k,
            expected,
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
    Ok(())
}

/// The typed error when a family that has no domain check is given a system declaring a domain
/// ([`System::domain`]): refused, rather than stepped without the check the declaration asks
/// for.
pub(crate) fn refuse_domain<L: System>(sys: &L, family: &'static str) -> Result<(), StepError> {
    if sys.domain().is_empty() {
        Ok(())
    } else {
        Err(StepError::Unsupported { what: family })
    }
}

pub mod adapted;
pub mod continuous;
pub mod domain;
pub mod state;
pub mod system;
