//! Runtime for the integrators that `#[reduced_lagrangian]` emits.
//!
//! The macro turns a discrete Lagrangian `L_d(q0, q1)` into straight-line `f64` code for the
//! reduced (+) and (−) discrete Lagrange–Poincaré–Dirac equations (Rodríguez Abella & Leok,
//! eqs. (4.6), (4.8)) and the unreduced ones, and implements the traits of [`system`] for a type
//! holding the Lagrangian's parameters: [`Reduced`] once per [`Side`] ([`Plus`], [`Minus`]). This crate
//! drives that code: [`newton`] solves each step's equations on fixed-size nalgebra types,
//! [`integrate`] marches a trajectory, [`state`] holds the reduced and canonical states, and
//! [`error`] reports a failed step as a value carrying its index and residual. [`compose`] raises
//! a symmetric rule to order 4 or 6 by symmetric composition, keeping μ exact and the step map
//! symplectic.
//!
//! Notation follows the paper: `Q = Σ × G` with shape coordinates `x ∈ Σ = R^S` and group
//! coordinates `g ∈ G = R^K` (G acts by translation), reduced momenta `w ∈ Σ*` and `mu ∈ g*`,
//! connection matrix `B` (`K × S`) of the linear discrete connection
//! `ω_d(q0, q1) = (g1 − g0) − B (x1 − x0)`.

pub mod adapted;
pub mod atlas;
pub mod compose;
pub mod continuous;
pub mod diagnostics;
pub mod ensemble;
pub mod error;
pub mod integrate;
pub mod lu;
pub mod newton;
pub mod sparse;
pub mod state;
pub mod system;

pub use adapted::AdaptedCoordinates;
pub use compose::{BaseStep, ComposedTrajectory, Composition, CompositionMethod};
pub use continuous::{
    continuous_energies, midpoint_energies, reduced_continuous_energies, ContinuousEnergies,
    ContinuousLagrangian, LegendreError,
};
pub use diagnostics::{
    dirac_differential_minus, dirac_differential_plus, dirac_membership_residuals,
    reduced_energy_minus, reduced_energy_plus, trajectory_energies, DiracDifferentialMinus,
    DiracDifferentialPlus, ReducedActionPlus,
};
pub use error::{IntegrationError, StepError, Steps};
pub use integrate::{
    CanonicalTrajectory, ReducedIntegrator, RunSummary, StepJacobian, StepRecord, StepStats,
    StepStatsExt, Trajectory, UnreducedIntegrator,
};
pub use lu::Lu;
pub use newton::{LinearSolver, NewtonOptions};
pub use sparse::{CscPattern, CscValues, SparseLu, DENSE_MAX};
pub use state::{CanonicalState, ReducedState};
pub use system::{
    DiscreteLagrangian, LagrangianHessian, Minus, Plus, Reduced, Side, Unreduced, Variant,
};

/// Re-exported so that emitted code and users name the same nalgebra.
pub use nalgebra;
