//! Runtime for the integrators that `#[reduced_lagrangian]` emits.
//!
//! The macro turns a discrete Lagrangian `L_d(q0, q1)` into straight-line `f64` code for the
//! reduced (+) and (−) discrete Lagrange–Poincaré–Dirac equations (Rodríguez Abella & Leok,
//! eqs. (4.6), (4.8)) and the unreduced ones, and implements the traits of [`system`] for a type
//! holding the Lagrangian's parameters: [`Reduced`] once per [`Side`] ([`Plus`], [`Minus`]).
//! This crate drives that code:
//!
//! * [`linalg`]: the linear solvers a Newton step runs on, dense ([`linalg::Lu`]) or sparse
//!   ([`linalg::SparseLu`]), behind one trait;
//! * [`newton`]: the one Newton driver, with its [`NewtonOptions`];
//! * [`stepper`]: the one stepping abstraction ([`Stepper`]), implemented by the integrators
//!   [`reduced`] (eqs. (4.6)/(4.8)), [`unreduced`] (Definitions 2.7/2.8), [`compose`] (symmetric
//!   compositions of order 4 and 6), [`atlas`] (§6: charts and transitions) and [`lie`]
//!   (rotations, directions and poses: Lie group variational integrators), whose kinds of
//!   coordinate are implementations of one trait in [`groups`];
//! * [`driver`]: the one run, configured ([`Drive::run`]: steps or an end time, step sizes per
//!   step, controls, stop conditions, observers; collected or streamed; ensembles), written once
//!   for every stepper; [`ensemble`]: parallel members;
//! * [`model`]: the one system model ([`System`]: parameters, time step, controls, time
//!   coordinate, domain, names), which the flat ([`system`]), rotation ([`lie`]) and element-wise
//!   ([`element`]) families extend;
//! * [`state`], [`error`] (a failed step is a value carrying its index and residual),
//!   [`diagnostics`] (the paper's Dirac structures, energies and action along a trajectory),
//!   [`domain`] (the bounds a system declares, checked after every step),
//!   [`continuous`] (a continuous Lagrangian's Legendre map and energy), [`adapted`] (declared
//!   translations), [`adaptive`] (adaptive steps by the Poincaré time transformation).
//!
//! Notation follows the paper: `Q = Σ × G` with shape coordinates `x ∈ Σ = R^S` and group
//! coordinates `g ∈ G = R^K` (G acts by translation), reduced momenta `w ∈ Σ*` and `mu ∈ g*`,
//! connection matrix `B` (`K × S`) of the linear discrete connection
//! `ω_d(q0, q1) = (g1 − g0) − B (x1 − x0)`.
//!
//! The crate root re-exports [`prelude`], the one list of what a user names; the backends and
//! the diagnostics are reached through their modules.
#![warn(missing_docs)]

pub mod error;
pub mod groups;
pub mod linalg;
pub mod model;
pub mod newton;

// The layers, folder by folder: the system model (`model/`: the one `System` trait, the flat
// family, states, domains, continuous Lagrangians), the configuration groups (`groups/`), the
// steps (`steps/`), the run (`run/`), what is read off a run (`analysis/`) and the linear
// algebra (`linalg/`). The modules keep their paths at the crate root.
mod analysis;
mod run;
mod steps;

pub use analysis::{diagnostics, sensitivity};
pub use model::{adapted, continuous, domain, state, system};
pub use run::{driver, ensemble};
pub use steps::{
    adaptive, atlas, compose, constrained, element, gauss, lie, reduced, stepper, unreduced,
};

/// Everything a user of the integrators names, in one list: the crate root re-exports it, and
/// so do the `dirac` facade's root and prelude.
pub mod prelude {
    pub use crate::adapted::AdaptedCoordinates;
    pub use crate::atlas::{AtlasIntegrator, AtlasStep, AtlasTrajectory, ChartTransition, Switch};
    pub use crate::compose::{ComposedTrajectory, Composition, CompositionMethod, SelfAdjoint};
    pub use crate::constrained::{
        Constrained, ConstrainedIntegrator, ConstrainedStep, ConstrainedStepper,
        ConstrainedTrajectory, Constraints, ReducedConstrainedIntegrator, UnreducedForm,
    };
    pub use crate::continuous::{
        continuous_energies, midpoint_energies, reduced_continuous_energies, ContinuousEnergies,
        ContinuousLagrangian, LegendreError, StageDerivatives, StageJacobian,
    };
    pub use crate::diagnostics::trajectory_energies;
    pub use crate::driver::{
        ControlLaw, ControlSequence, Drive, Ensemble, Fixed, Observer, Run, RunSummary, StepSize,
        StepSizes, StopCondition,
    };
    pub use crate::element::{
        ElementConstrainedIntegrator, ElementConstrainedTrajectory, ElementIntegrator,
        ElementLagrangian, ElementState, ElementTrajectory, Parallel, StepSolver,
    };
    pub use crate::error::{IntegrationError, StepError, Steps};
    pub use crate::gauss::{GaussIntegrator, GaussRule, ReducedGaussIntegrator};
    pub use crate::lie::{
        CoordinateKind, LieIntegrator, LieLagrangian, LiePartials, LieState, LieSymmetric,
        LieTrajectory, ReducedLieIntegrator, ReducedLieState, ReducedLieTrajectory,
        RotationSymmetry,
    };
    pub use crate::model::System;
    pub use crate::newton::NewtonOptions;
    pub use crate::reduced::{ReducedIntegrator, ReducedStep, Trajectory};
    pub use crate::sensitivity::{Sensitivity, StepPartials};
    pub use crate::state::{IntoVector, ReducedState, UnreducedState};
    pub use crate::stepper::{StepAt, StepStats, StepStatsExt, Stepper};
    pub use crate::system::{
        DiscreteLagrangian, Equations, Form, LagrangianHessian, Minus, Plus, Reduced, Side,
        Unreduced, Variant,
    };
    pub use crate::unreduced::{UnreducedIntegrator, UnreducedTrajectory};
}

pub use prelude::*;

// The paths the emitted code names (`::dirac::runtime::Lu`, ...): the backends live in `linalg`.
#[doc(hidden)]
pub use linalg::{CscBuffer, CscPattern, CscValues, Lu, PatternLu, SparseLu, DENSE_MAX};

/// Re-exported so that emitted code and users name the same nalgebra.
pub use nalgebra;
