//! The user guide: how to write a system, integrate it, read what a run reports, and what each
//! failure means. Every code block in these chapters is compiled and run by `cargo test` (as a
//! doctest of this crate), so the guide cannot drift from the code.
//!
//! The chapters, in reading order:
//!
//! 1. [The paper's two systems](paper_systems): the charged particle (§7.1, Table 1) and the
//!    double spherical pendulum (§7.2, Figures 3–4), ready to run from [`crate::paper`].
//! 2. [Writing a Lagrangian](lagrangians): the attribute and its body language; discrete
//!    Lagrangians, continuous ones with a quadrature rule, degenerate ones, systems without
//!    symmetry; what the attribute emits and how it generates code.
//! 3. [Symmetries](symmetries): group coordinates, connections, translations declared on your
//!    own coordinates, indexed coordinates.
//! 4. [Forces and controls](forces): forces as their virtual work, control laws and sequences,
//!    the forced discrete Noether balance, the sensitivities of a step.
//! 5. [Constraints](constraints): holonomic `φ(q) = 0` and nonholonomic `A(q) v = 0`, the
//!    constrained steps (RATTLE, the discrete Lagrange–d'Alembert step), reduced and unreduced.
//! 6. [Integrators and the driver](integrators): the reduced (+)/(−) and unreduced integrators,
//!    symmetric compositions of order 4 and 6, an atlas of charts; one configured `run` (steps or an end time, step sizes per step), stop
//!    conditions and ensembles, the same for all of them.
//! 7. [Adaptive steps](adaptive_steps): `time(t), adapt = |q| g` — the Poincaré time
//!    transformation made variational: a fixed fictitious step, physical steps that follow the
//!    motion, the energy level and every momentum of a symmetry kept bit for bit.
//! 8. [High order](high_order): the Gauss–Legendre variational integrators of order `2s` for
//!    any continuous Lagrangian, adaptive at any order, symplectic, momenta bit for bit; round-off
//!    under control; against REBOUND's IAS15.
//! 9. [Rotations and directions](rotations): configurations on `SO(3)` and `S²` (rigid bodies,
//!    tops, satellites, pendula in 3-D) stepped on the group by Lie group variational
//!    integrators, with no charts.
//! 10. [Reduction by rotations](rotation_reduction): `symmetry(R)` and
//!     `symmetry(n1, n2, axis = z)`, the discrete Euler–Poincaré and Lagrange–Poincaré steps, the
//!     spatial momentum or its axial component as a parameter of the run.
//! 11. [Large systems](large_systems): the sparse backend, chord iterations, streaming runs in
//!     constant memory, ensembles on all cores, building the attribute optimized.
//! 12. [Systems sized at run time](run_time_sizes): element-wise bodies whose sizes are `usize`
//!     arguments — one build for every size, stencils checked at compile time, the element
//!     kernels assembled in parallel, 10⁵ degrees of freedom.
//! 13. [Systems given at run time](run_time_text): the attribute and function as text, compiled
//!     by the same compiler and Cranelift to machine code while the program runs, behind the
//!     same traits: the same integrators, the same messages, the same trajectories bit for bit.
//! 14. [Articulated bodies](articulated): robots and linkages read from URDF, their Lagrangian
//!     written as a system text and stepped by the same integrators; a floating base on `SE(3)`
//!     keeping the tree's total momentum.
//! 15. [Diagnostics](diagnostics): Newton statistics and conditioning per step, energies, the
//!     Dirac structure and the discrete action along a trajectory, the step-map Jacobian.
//! 16. [Errors](errors): the typed [`StepError`](crate::StepError) of a failed step, the
//!     trajectory kept up to it, and the compile errors of the attributes.
//! 17. [Limits](limits): what the integrators do not do, and where their guarantees end.
//!
//! Results that leave the process — runs and ensembles in Apache Parquet, sharded ensembles on a
//! Slurm cluster, progress bars — are the separate crate `dirac-io`, described in
//! `docs/output-and-clusters.md` and in that crate's rustdoc, whose examples its own test suite
//! compiles and runs.
//!
//! [Benchmarks](benchmarks) is the measurements page (also `BENCHMARKS.md` in the source): each
//! table with the command that makes it, the date and the machine.
//!
//! The API reference is the rest of this crate's documentation: [`crate::prelude`] lists what a
//! program names, [`crate::runtime`] holds the integrators' modules, [`crate::paper`] and
//! [`crate::systems::kepler`] are worked systems that the chapters reuse.

// Each capability still to come adds its chapter as a module here and a line in the list above.

pub mod adaptive_steps;
pub mod articulated;
pub mod benchmarks;
pub mod constraints;
pub mod diagnostics;
pub mod errors;
pub mod forces;
pub mod high_order;
pub mod integrators;
pub mod lagrangians;
pub mod large_systems;
pub mod limits;
pub mod paper_systems;
pub mod rotation_reduction;
pub mod rotations;
pub mod run_time_sizes;
pub mod run_time_text;
pub mod symmetries;
