//! The recursive step of a fixed-base tree: the midpoint rule in the joint coordinates, its
//! residual and Newton corrections in `O(n)` for `n` bodies, whatever the tree's depth.
//!
//! [`Model::system_text`] writes a tree's Lagrangian as text and the compiler differentiates
//! it: every entry of the dense `n × n` step Jacobian becomes a straight line through the tree,
//! so a step costs `O(n³)` and the compile time grows as fast (a 40-link chain takes minutes).
//! [`ArticulatedIntegrator`] steps the *same* discrete Lagrangian with the recursions of rigid
//! body dynamics instead (Featherstone, *Rigid Body Dynamics Algorithms*, 2008, ch. 5–7), so a
//! step costs `O(n)` and a model of any size is ready at once, with no compilation.
//!
//! # The discrete equations
//!
//! The configuration is the vector `q` of joint angles and displacements (revolute,
//! continuous and prismatic joints). The discrete Lagrangian is the midpoint rule,
//! `L_d(q_0, q_1) = h L(q̄, v)` with `q̄ = (q_0 + q_1)/2`, `v = (q_1 − q_0)/h` — the rule of
//! [`Model::system_text`] for a fixed base — so the discrete Legendre transforms are
//!
//! ```text
//! −D_1 L_d = L_v − (h/2) L_q,      D_2 L_d = L_v + (h/2) L_q,      both at (q̄, v),
//! ```
//!
//! and with joint torques `τ` as the virtual work `τ·δq`, the discrete forces
//! `f_d^± = (h/2) τ`. A step solves the position–momentum form of the forced discrete
//! Euler–Lagrange equations (Marsden–West, *Discrete mechanics and variational integrators*,
//! 2001, §3.2) for `q_{k+1}`, then reads the new momentum:
//!
//! ```text
//! R(q_{k+1}) = p_k + (h/2) L_q − L_v + (h/2) τ_k = 0,      p_{k+1} = L_v + (h/2) L_q + (h/2) τ_k.
//! ```
//!
//! # `L_v` and `L_q` in two passes
//!
//! In the world frame every spatial vector is at the world origin (the conventions of
//! [`crate::kinematics`]): body `b`'s spatial velocity is `V_b = V_λ(b) + S_b v_b`, its
//! spatial momentum `h_b = I_b V_b` (angular momentum about the origin, linear momentum), the
//! wrench of its weight `w_b = (m_b c_b × g, m_b g)`. Summed over the subtree of `b`, leaves
//! first, they give the composite `H_b = Σ h` and `W_b = Σ w`. Then, for the joint of body `b`:
//!
//! * `∂L/∂v_b = S_b · H_b` — the generalized momentum `M(q) v`;
//! * `∂T/∂q_b = H_b · (V_λ(b) × S_b)`. Moving `q_b` by `δ` moves the subtree rigidly by the
//!   twist `ξ = S_b δ`: each descendant joint's axis changes by `ξ × S_j`, so each body's
//!   velocity by `ξ × (V − V_λ(b))` (as `ξ × S_b = 0`), and each spatial inertia by
//!   `ξ×* I − I ξ×`, which changes `½ Vᵀ I V` by `−h · (ξ × V)`; summed, `δT = −Σ h·(ξ × V_λ(b))
//!   = H_b · (V_λ(b) × ξ)`;
//! * `∂V/∂q_b = −W_b · S_b`, the work of the subtree's weight along the twist.
//!
//! So `L_q = ∂T/∂q − ∂V/∂q` and `L_v` cost one pass from the root (poses, axes, velocities)
//! and one from the leaves (the sums).
//!
//! # Newton's corrections in `O(n)`
//!
//! The step Jacobian is `J = ∂R/∂q_{k+1} = −M(q̄)/h + ½(L_qv − L_vq) + (h/4) L_qq`: dense,
//! but never formed. Its first term dominates (by `1/(h |q̇|)` and `1/(h² ω²)`), and
//! `M(q̄) x = b` is solved in `O(n)` by the articulated-body algorithm with no velocity and no
//! gravity (Featherstone ch. 7, Table 7.1): from the leaves, `U = I^A S`, `D = S·U`,
//! `u = b − S·p^A`, `I^A_λ += I^A − U Uᵀ/D`, `p^A_λ += p^A + U u/D`; from the root,
//! `x = (u − U·a_λ)/D`, `a = a_λ + S x`. Each Newton correction `J δ = −R` is solved by GMRES
//! preconditioned by `−M(q̄)/h` (Saad, *Iterative Methods for Sparse Linear Systems*, 2003,
//! §9.3), whose products `J z` are forward differences `(R(q + εz) − R(q))/ε` of the residual:
//! one residual pass and one articulated-body solve per Krylov vector, all `O(n)`. (The mass
//! term alone, as a simplified Newton iteration, shrinks the error only by about `h |q̇|` per
//! correction, and a long chain's fast joints then need ten corrections a step.) The
//! corrections are inexact — GMRES stops at a relative residual of `1e-6` — but what accepts
//! a step is the one Newton driver's test on a freshly evaluated residual, so the accepted
//! `q_{k+1}` solves the same equations to the same tolerance as with an exact Jacobian. The
//! conditioning checked is that of `−M(q̄)/h` (Hager's estimate, once per step).
//!
//! # What it steps, and what it does not
//!
//! Fixed-base trees of revolute, continuous and prismatic joints (fixed joints are fused by
//! the model); a spherical or free joint is refused with [`ModelError::Unsupported`] — the text
//! of [`Model::system_text`] steps those on their groups. The (+) equations only; no step
//! sensitivities (the compiled text has them); compositions of order 4 and 6 through
//! `SelfAdjoint`, step schedules, end times and controls through the one run API.

mod passes;
mod solver;

use std::cell::RefCell;

use dirac_runtime::compose::{sample_direction, SelfAdjoint};
use dirac_runtime::element::{ElementState, ElementSteps, ElementTrajectory, Increments};
use dirac_runtime::newton::{slice_inf_norm, solve_in, NewtonOptions};
use dirac_runtime::stepper::{step_error, StepAt, StepStats, Stepper};
use dirac_runtime::system::Variant;
use dirac_runtime::StepError;
use nalgebra::{DVector, Matrix3, Vector3};

use crate::error::{ModelError, StateError};
use crate::model::{JointKind, Model};
use crate::pose::Pose;
use passes::{Kinematics, Passes, StepData};
pub use solver::{ArticulatedSolver, MassOperator, StepJacobian};

/// One scalar joint of the tree, as the recursions read it.
#[derive(Clone, Debug)]
struct TreeJoint {
    /// The parent and child bodies.
    parent: usize,
    child: usize,
    /// The joint frame in the parent's frame.
    placement: Pose,
    /// The unit axis in the joint frame.
    axis: Vector3<f64>,
    /// A displacement along the axis (prismatic) rather than an angle about it.
    prismatic: bool,
}

/// A body's mass properties in its own frame.
#[derive(Clone, Copy, Debug)]
struct BodyMass {
    mass: f64,
    com: Vector3<f64>,
    inertia: Matrix3<f64>,
}

/// The step of a fixed-base tree of scalar joints by the recursions of rigid-body dynamics (see
/// the [module documentation](self)): the midpoint rule in the joint coordinates, `O(n)` per
/// Newton correction. States are [`ElementState`]s `(q, p)`: the joint coordinates in the order
/// of [`Model::coordinates`] and their conjugate momenta. Joint torques are its controls, one per
/// joint in the same order (zero unless a run sets them).
///
/// ```
/// use dirac_multibody::nalgebra::{Matrix3, Vector3};
/// use dirac_multibody::{ArticulatedIntegrator, Inertial, JointSpec, Model, Pose};
/// use dirac_runtime::prelude::*;
///
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// // A chain of 200 rods, hinged about y, 0.5 m apart.
/// let rod = Inertial::new(1.0, Vector3::new(0.0, 0.0, -0.25), Matrix3::from_diagonal(&Vector3::new(0.02, 0.02, 0.002)));
/// let mut builder = Model::builder().frame("l0");
/// for i in 1..=200 {
///     let at = Pose::from_translation(Vector3::new(0.0, 0.0, if i == 1 { 0.0 } else { -0.5 }));
///     builder = builder.body(format!("l{i}"), rod).joint(
///         JointSpec::revolute(format!("j{i}"), format!("l{}", i - 1), format!("l{i}"), Vector3::y()).at(at),
///     );
/// }
/// let model = builder.build()?;
/// let integ = ArticulatedIntegrator::new(&model, 1e-3, NewtonOptions::default())?;
/// let q: Vec<f64> = (0..200).map(|i| if i == 0 { 0.5 } else { 0.0 }).collect();
/// let start = integ.state(&q, &vec![0.0; 200])?;
/// let e0 = integ.energy(&start)?;
/// let traj = integ.run(start).steps(100).collect()?;
/// assert!((integ.energy(traj.last())? - e0).abs() < 1e-6 * e0.abs());
/// assert!(traj.stats.mean_iterations() <= 3.0);
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug)]
pub struct ArticulatedIntegrator {
    joints: Vec<TreeJoint>,
    bodies: Vec<BodyMass>,
    gravity: Vector3<f64>,
    /// The joints' names, for errors.
    names: Vec<String>,
    h: f64,
    options: NewtonOptions,
}

impl ArticulatedIntegrator {
    /// The integrator of `model` at time step `h` with Newton's `options`.
    ///
    /// # Errors
    /// [`ModelError::Unsupported`] for a model with a spherical or free joint,
    /// [`ModelError::NothingMoves`] for one without a moving joint.
    pub fn new(model: &Model, h: f64, options: NewtonOptions) -> Result<Self, ModelError> {
        if model.joints.is_empty() {
            return Err(ModelError::NothingMoves);
        }
        let mut joints = Vec::with_capacity(model.joints.len());
        for joint in &model.joints {
            let (axis, prismatic) = match joint.kind {
                JointKind::Revolute { axis } | JointKind::Continuous { axis } => (axis, false),
                JointKind::Prismatic { axis } => (axis, true),
                other => {
                    return Err(ModelError::Unsupported {
                        joint: joint.name.clone(),
                        feature: format!(
                            "type \"{}\" in the recursive step, which takes revolute, \
                             continuous and prismatic joints (the model's system text steps \
                             spherical and free joints)",
                            other.name()
                        ),
                    })
                }
            };
            joints.push(TreeJoint {
                parent: joint.parent,
                child: joint.child,
                placement: joint.placement,
                axis,
                prismatic,
            });
        }
        let bodies = model
            .bodies
            .iter()
            .map(|b| BodyMass {
                mass: b.inertial.mass,
                com: b.inertial.com,
                inertia: b.inertial.inertia,
            })
            .collect();
        Ok(Self {
            joints,
            bodies,
            gravity: model.gravity,
            names: model.joints.iter().map(|j| j.name.clone()).collect(),
            h,
            options,
        })
    }

    /// The number of joint coordinates.
    #[must_use]
    pub fn dim(&self) -> usize {
        self.joints.len()
    }

    /// The Newton options.
    #[must_use]
    pub fn options(&self) -> &NewtonOptions {
        &self.options
    }

    /// The state at joint coordinates `q` and rates `v`, its momentum the continuous Legendre
    /// transform `p = ∂L/∂v = M(q) v`.
    ///
    /// # Errors
    /// Slices of the wrong length, or entries that are not finite.
    pub fn state(&self, q: &[f64], v: &[f64]) -> Result<ElementState, StateError> {
        self.check_lengths(q, v)?;
        let mut kin = Kinematics::new(self.bodies.len());
        let q = DVector::from_column_slice(q);
        let mut p = DVector::zeros(q.len());
        kin.evaluate(self, q.as_slice(), v, None);
        kin.momenta(self, None, p.as_mut_slice());
        Ok(ElementState::new(q, p))
    }

    /// The joint rates `v = M(q)⁻¹ p` of `state`.
    ///
    /// # Errors
    /// A state of the wrong size or not finite.
    pub fn velocity(&self, state: &ElementState) -> Result<DVector<f64>, StateError> {
        self.check_lengths(state.q.as_slice(), state.p.as_slice())?;
        let n = self.dim();
        let mut kin = Kinematics::new(self.bodies.len());
        let mut mass = MassOperator::new(self.bodies.len(), n, 1.0);
        kin.evaluate(self, state.q.as_slice(), &vec![0.0; n], Some(&mut mass));
        let mut solver = ArticulatedSolver::new(self);
        // The state's entries are finite and every body has positive mass properties, so the
        // factorization succeeds; a failure would be an overflow, reported on the first joint.
        solver
            .factor_mass(&mass)
            .map_err(|_| StateError::NonFinite {
                joint: self.names[0].clone(),
            })?;
        let mut v = state.p.clone();
        solver.precondition(v.as_mut_slice());
        Ok(v)
    }

    /// The energy `T + V` of `state`, with `T = ½ vᵀ M v = ½ v·p` and the potential of
    /// [`Model::potential_energy`].
    ///
    /// # Errors
    /// A state of the wrong size or not finite.
    pub fn energy(&self, state: &ElementState) -> Result<f64, StateError> {
        let v = self.velocity(state)?;
        let mut kin = Kinematics::new(self.bodies.len());
        kin.evaluate(self, state.q.as_slice(), v.as_slice(), None);
        let potential: f64 = kin.potential;
        Ok(0.5 * v.dot(&state.p) + potential)
    }

    /// Checks joint coordinates `q` and rates (or momenta) `v`: their lengths, then that
    /// every entry is finite (the first joint that is not named).
    fn check_lengths(&self, q: &[f64], v: &[f64]) -> Result<(), StateError> {
        let n = self.dim();
        if q.len() != n {
            return Err(StateError::JointCount {
                expected: n,
                found: q.len(),
            });
        }
        if v.len() != n {
            return Err(StateError::VelocityLength {
                expected: n,
                found: v.len(),
            });
        }
        match (0..n).find(|&j| !(q[j].is_finite() && v[j].is_finite())) {
            Some(j) => Err(StateError::NonFinite {
                joint: self.names[j].clone(),
            }),
            None => Ok(()),
        }
    }

    /// The integrator at another time step (for compositions, whose stages step with `γ_i h`).
    #[must_use]
    pub fn with_time_step(&self, h: f64) -> Self {
        Self { h, ..self.clone() }
    }
}

/// What an [`ArticulatedIntegrator`] run carries from step to step.
#[derive(Debug)]
pub struct ArticulatedWorkspace {
    solver: ArticulatedSolver,
    passes: RefCell<Passes>,
    r: DVector<f64>,
    jacobian: Option<StepJacobian>,
    torque: Vec<f64>,
    history: Increments,
}

impl Stepper for ArticulatedIntegrator {
    type State = ElementState;
    type Record = StepStats;
    type Workspace = ArticulatedWorkspace;
    type Trajectory = ElementTrajectory;

    fn time_step(&self) -> f64 {
        self.h
    }

    fn check(&self, initial: &ElementState) -> Result<(), StepError> {
        if !(self.h.is_finite() && self.h != 0.0) {
            return Err(StepError::InvalidTimeStep { h: self.h });
        }
        self.check_lengths(initial.q.as_slice(), initial.p.as_slice())
            .map_err(|e| match e {
                StateError::NonFinite { .. } => StepError::NonFinite {
                    step: 0,
                    what: "the initial state",
                    residual: f64::NAN,
                },
                other => StepError::InvalidSize {
                    reason: other.to_string(),
                },
            })
    }

    fn workspace(&self) -> ArticulatedWorkspace {
        let (b, n) = (self.bodies.len(), self.joints.len());
        ArticulatedWorkspace {
            solver: ArticulatedSolver::new(self),
            passes: RefCell::new(Passes::new(self)),
            r: DVector::zeros(n),
            jacobian: Some(StepJacobian::new(b, n)),
            torque: vec![0.0; n],
            history: Increments::new(n),
        }
    }

    fn control_dim(&self) -> usize {
        self.joints.len()
    }

    /// Step `k`: the simplified Newton iteration on `R(q_{k+1}) = 0` from the extrapolated
    /// guess, then `p_{k+1} = L_v + (h/2)(L_q + τ)` (module documentation).
    fn step_into(
        &self,
        ws: &mut ArticulatedWorkspace,
        at: StepAt<'_>,
        state: &ElementState,
        next: &mut ElementState,
    ) -> Result<StepStats, StepError> {
        let StepAt { k, h, u } = at;
        let n = self.joints.len();
        if !(h.is_finite() && h != 0.0) {
            return Err(StepError::InvalidStepSize { step: k, h });
        }
        match u.len() {
            0 => ws.torque.fill(0.0),
            len if len == n => ws.torque.copy_from_slice(u),
            found => {
                return Err(StepError::InvalidControls {
                    step: k,
                    expected: n,
                    found,
                })
            }
        }
        if state.q.len() != n || state.p.len() != n {
            return Err(StepError::InvalidSize {
                reason: format!(
                    "the state has {} coordinates and {} momenta, the tree {n} joints",
                    state.q.len(),
                    state.p.len()
                ),
            });
        }
        if next.q.len() != n || next.p.len() != n {
            *next = state.clone();
        }
        ws.history.guess(&state.q, h, &mut next.q);
        let rho = slice_inf_norm(state.p.as_slice());
        let ArticulatedWorkspace {
            solver,
            passes,
            r,
            jacobian,
            torque,
            ..
        } = ws;
        let data = StepData {
            q0: state.q.as_slice(),
            p0: state.p.as_slice(),
            torque,
            h,
        };
        let solution = solve_in(
            solver,
            &mut next.q,
            r,
            jacobian,
            rho,
            &self.options,
            |q1, r| {
                passes
                    .borrow_mut()
                    .residual(self, &data, q1.as_slice(), r.as_mut_slice(), None);
            },
            |q1, r, j| {
                let j = j.get_or_insert_with(|| StepJacobian::new(self.bodies.len(), n));
                j.mass.scale = -1.0 / h;
                passes.borrow_mut().residual(
                    self,
                    &data,
                    q1.as_slice(),
                    r.as_mut_slice(),
                    Some(&mut j.mass),
                );
                j.at.copy_from_slice(q1.as_slice());
                j.residual.copy_from_slice(r.as_slice());
                j.q0.copy_from_slice(data.q0);
                j.p0.copy_from_slice(data.p0);
                j.torque.copy_from_slice(data.torque);
                j.h = h;
            },
        )
        .map_err(|failure| step_error(k, failure))?;
        // The last pass was at the solution: its sums give the next momentum.
        let passes = passes.borrow();
        for j in 0..n {
            next.p[j] = passes.lv[j] + 0.5 * h * (passes.lq[j] + data.torque[j]);
        }
        if !next.p.iter().all(|v| v.is_finite()) {
            return Err(StepError::NonFinite {
                step: k,
                what: "the new momentum",
                residual: solution.residual,
            });
        }
        ws.history.remember(&state.q, &next.q, h);
        Ok(StepStats::from_solution(
            &solution,
            self.options.residual_tolerance(rho),
        ))
    }
}

impl ArticulatedIntegrator {
    /// `L_d(q0, q1; h) = h L(q̄, v)`, with `L = ½ v·(M v) − V` from the two passes.
    fn discrete_lagrangian(&self, kin: &mut Kinematics, q0: &[f64], q1: &[f64], h: f64) -> f64 {
        let mut lv = vec![0.0; self.dim()];
        kin.midpoint(self, q0, q1, h, None);
        kin.momenta(self, None, &mut lv);
        let kinetic: f64 = 0.5 * lv.iter().zip(&kin.rate).map(|(a, b)| a * b).sum::<f64>();
        h * (kinetic - kin.potential)
    }
}

impl SelfAdjoint for ArticulatedIntegrator {
    fn with_time_step(&self, h: f64) -> Self {
        ArticulatedIntegrator::with_time_step(self, h)
    }

    /// The largest relative defect `|L_d(q0, q1; −h) + L_d(q1, q0; h)|` over sample pairs
    /// around the configuration of `at` (as [`dirac_runtime::compose::symmetry_defect`]): zero
    /// up to round-off, the midpoint rule being symmetric.
    fn symmetry_defect(&self, at: &ElementState) -> f64 {
        let q = &at.q;
        let mut kin = Kinematics::new(self.bodies.len());
        let delta = 0.05 * q.amax().max(1.0);
        let mut worst: f64 = 0.0;
        for j in 0..3 {
            let p = DVector::from_fn(q.len(), |i, _| q[i] + delta * sample_direction(j, i));
            for (q0, q1) in [(q, &p), (&p, q)] {
                let minus =
                    self.discrete_lagrangian(&mut kin, q0.as_slice(), q1.as_slice(), -self.h);
                let plus = self.discrete_lagrangian(&mut kin, q1.as_slice(), q0.as_slice(), self.h);
                let scale = minus.abs().max(plus.abs());
                if scale > 0.0 {
                    worst = worst.max((minus + plus).abs() / scale);
                }
            }
        }
        worst
    }
}

impl ElementSteps for ArticulatedIntegrator {
    fn variant(&self) -> Variant {
        Variant::Plus
    }
}
