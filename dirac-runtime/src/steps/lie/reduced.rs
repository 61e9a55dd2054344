//! Reduction by rotations: the discrete Euler–Poincaré and Lagrange–Poincaré equations of a
//! discrete Lagrangian invariant under every rotation of one rotation coordinate, and the
//! reduced step of one invariant under the rotations about a fixed axis.
//!
//! # Every rotation of the attitude: `Q = SO(3) × S`
//!
//! Let `L_d(R0, s0, R1, s1)` be invariant under `R ↦ g R` for every `g ∈ SO(3)` (declared
//! `symmetry(R)`, sampled at compile time), `s` the other coordinates (scalars, other rotations
//! and directions, untouched by `g`). The discrete connection `A_d(q0, q1) = R1 R0⁻¹` identifies
//! `(Q × Q)/SO(3)` with `SO(3) × S × S` through `(R0, s0, R1, s1) ↦ (F = R0ᵀ R1, s0, s1)`, and the
//! reduced Lagrangian is
//!
//! ```text
//! l_d(F, s0, s1) = L_d(I, s0, F, s1) = L_d(R0, s0, R0 F, s1)            for every R0.
//! ```
//!
//! With the variations of the unreduced step, `δR_k = R_k η̂_k`, the relative rotation varies by
//! `δF_k = −η̂_k F_k + F_k η̂_{k+1}` (Marsden, Pekarsky & Shkoller 1999; Leok, Marsden &
//! Weinstein 2005), and the reduced Hamilton–Pontryagin principle
//! `δ Σ l_d(F_k, s_k, s_{k+1}) = 0` gives, with the body momentum `Π ∈ so(3)*` and the momenta
//! `w` of `s` in their charts, the position–momentum form of the reduced discrete
//! Lagrange–Poincaré–Dirac equations:
//!
//! ```text
//! Π_k · η     = ⟨D_F l_d, η̂ F_k⟩          w_k     = −D_{s0} l_d
//! Π_{k+1} · η = ⟨D_F l_d, F_k η̂⟩          w_{k+1} =  D_{s1} l_d          for every η ∈ R³,
//! R_{k+1}     = R_k F_k                                                  (reconstruction)
//! ```
//!
//! at `(F_k, s_k, s_{k+1})`. They are the unreduced equations of [`crate::lie`] with `R_k`
//! replaced by the identity: the compiler emits them from the same body with the stored
//! rotation set to `I` ([`LieSymmetric::reduced_residual`]), so a step solves for the chart
//! coordinate `z` of `F_k = cay(z)` and of `s_{k+1}` without reading the attitude, and the
//! attitude is reconstructed afterwards. For `S` empty (the free rigid body,
//! `l_d(F) = tr((I − F) J_d)/h`) these are the discrete Euler–Poincaré equations
//! `h Π_k = vee(F_k J_d − J_d F_kᵀ)`; with shapes (a satellite with rotors) the discrete
//! Lagrange–Poincaré equations.
//!
//! Since `F_k η̂ = (F_k η)^ F_k`, the two lines for `Π` give `Π_{k+1} · η = Π_k · (F_k η)`:
//!
//! ```text
//! Π_{k+1} = F_kᵀ Π_k = Ad*_{F_k} Π_k,
//! ```
//!
//! the discrete Lie–Poisson equation — `Π` moves on its coadjoint orbit (the sphere
//! `|Π| = const`, a Casimir), and the spatial momentum `π = R Π` is constant:
//! `R_{k+1} Π_{k+1} = R_k F_k F_kᵀ Π_k = R_k Π_k`. The reduced integrator therefore carries `π`
//! as a parameter of the run, as the abelian reduced integrators carry `μ`: a step reads `Π_k`
//! and the shapes, not `π`; after it, `Π_{k+1}` is scaled onto the orbit `|Π| = |π|` and the
//! reconstructed attitude is turned by the smallest rotation that makes `R_{k+1} Π_{k+1} = π`
//! and brought back onto `SO(3)` by one Newton–Schulz step `R (3I − RᵀR)/2` (the corrections
//! are of the size of the round-off of the step: in exact arithmetic they are the identity). So
//! `π_k = R_k Π_k` equals `π`, `|Π_k|` equals `|π|` and `R_kᵀ R_k` equals `I` to a few units of
//! round-off at every step, with no drift, where the unreduced step's `π` and `RᵀR` perform
//! random walks of round-off.
//!
//! # The rotations about a fixed axis `e`
//!
//! Declared `symmetry(R, n, .., axis = z)`: `L_d` invariant under `R ↦ exp(θ ê) R`,
//! `n ↦ exp(θ ê) n` of every listed coordinate together — a body in a uniform field along `e`
//! (the heavy top), pendula on a pivot. The group `SO(2)` is abelian and acts on a nonlinear
//! configuration space; in the chart centred at `q` its generator is
//! `ζ(q) = (Rᵀ e, ((e × n)·e_1, (e × n)·e_2), 0)` (a rotation's body components, a direction's
//! frame components, nothing on other coordinates), and its momentum map is
//! `μ = ⟨p, ζ(q)⟩ = e · π`. The reduced step carries `μ` as a parameter, as the paper's reduced
//! equations (4.6) do: the momentum a step reads is the shape part of `p_k` with the group part
//! `μ` — `p_k + (μ − ⟨p_k, ζ⟩) ζ / |ζ|²` — so the group component of the residual is the
//! equation `⟨D1 L̃, ζ⟩ + μ = 0`; the step then solves the chart equations of
//! [`crate::lie`], which by invariance read the configuration only through its orbit (`Rᵀ e`
//! for the heavy top), and the group part of `p_{k+1}` is set to `μ` again. `μ` is copied from
//! step to step, bit for bit, and the stored rotation's phase about `e` is the reconstruction.
//! A configuration on the axis (`|ζ| = 0`, e.g. a pendulum hanging straight down) has no group
//! part to set; there `μ = 0` necessarily.
//!
//! # Every rigid motion of a pose: `Q = SE(3) × S`
//!
//! Declared `symmetry(X)` for a pose coordinate `X = (R, x)`: `L_d` invariant under every
//! rigid motion `(A, a)·(R, x) = (A R, A x + a)` (a free-floating body, or a tree of bodies
//! carried by a floating base, out of gravity; checked at compile time on sample
//! configurations moved by a sample rotation and translation). The pose's momentum is its body
//! angular momentum `Π` and its linear momentum `p` in space (the chart `(R cay(ξ), x + v)`),
//! and the momentum map of the rigid motions is the total spatial momentum
//! `(π, p) = (R Π + x × p, p)`. As for every rotation, the reduced equations are the unreduced
//! step's in the chart at `X_k`, which by invariance read the pose only through the relative
//! pose; the reduced integrator carries `(π, p)` as parameters of the run: after each step,
//! the linear momentum is set to `p` (copied bit for bit) and the body angular momentum to
//! `Π_{k+1} = R_{k+1}ᵀ (π − x_{k+1} × p)` at the reconstructed pose (its attitude brought back
//! onto SO(3) by the step). Both corrections are of the size of the step's round-off; so
//! `R Π + x × p = π` holds at every step to the round-off of one evaluation, where the
//! unreduced step's `π` gathers the round-off of `x × p` step by step (large once the body has
//! drifted far from the origin). `mu` is `π`.
//!
//! # What is kept
//!
//! The reduced step is the unreduced step of the same `L_d` (to round-off), so everything of
//! [`crate::lie`] holds: symplecticity on `T*Q` (on the reduced space, the Lie–Poisson structure
//! of `so(3)*` and its coadjoint orbits for the free body), order 2 for a symmetric `L_d` and 4
//! and 6 by composition, the energy without drift over long runs. With forces that act on the
//! coordinates the symmetry moves, the momentum obeys the forced balance and is recomputed from
//! the state after every step (no orbit correction then).

use nalgebra::allocator::Allocator;
use nalgebra::{Const, DefaultAllocator, Dim, Matrix3, OVector, SVector, Vector3};

use super::integrator::{check_sizes, match_sizes, StepEquations};
use super::{
    blocks, matrix_at, zeros, LieForm, LieIntegratorIn, LieIntegratorOf, LieLagrangian, LieModel,
    LieStateOf, LieWorkspaceOf, SymmetricLieModel,
};
use crate::error::StepError;
use crate::stepper::{StepAt, StepStats};

/// A rotation symmetry of a system on rotation groups (`symmetry(..)` in the attribute).
///
/// `'a` is the lifetime of the list of coordinates of [`RotationSymmetry::Axis`]: `'static` for
/// a system compiled in ([`LieSymmetric::SYMMETRY`]), the system value's own for a system given
/// at run time ([`LieSymmetric::symmetry`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RotationSymmetry<'a> {
    /// Every rotation `R ↦ g R` of the rotation coordinate `coordinate`:
    /// `SO(3)`, with the spatial momentum `π = R Π` (`symmetry(R)`).
    Rotations {
        /// Its index among the coordinates ([`LieLagrangian::coordinate`]).
        coordinate: usize,
    },
    /// Every rigid motion `(A, a)·(R, x) = (A R, A x + a)` of the pose coordinate
    /// `coordinate`: `SE(3)`, with the spatial momentum `(π, p) = (R Π + x × p, p)`
    /// (`symmetry(X)`); `mu` carries `π`, the state's own linear momentum `p` (a pose's
    /// momentum is its body angular momentum `Π` and its linear momentum `p` in space) is
    /// copied from step to step.
    RigidMotions {
        /// Its index among the coordinates ([`LieLagrangian::coordinate`]).
        coordinate: usize,
    },
    /// The rotations about the coordinate axis `axis` (0, 1, 2 for x, y, z) of the listed
    /// coordinates together: `SO(2)`, with the momentum `μ = e · π`
    /// (`symmetry(R, n, .., axis = z)`).
    Axis {
        /// 0, 1 or 2.
        axis: usize,
        /// Their indices among the coordinates ([`LieLagrangian::coordinate`]).
        coordinates: &'a [usize],
    },
}

/// A [`LieLagrangian`] with a declared rotation symmetry, checked at compile time, and the
/// reduced step's straight-line functions (see the [module documentation](self)).
/// `#[reduced_lagrangian]` implements it for a function with `symmetry(..)` in its attribute.
pub trait LieSymmetric<const P: usize, const N: usize>: LieLagrangian<P, N> {
    /// The declared symmetry.
    const SYMMETRY: RotationSymmetry<'static>;
    /// Whether the forces act on a coordinate the symmetry moves (then its momentum obeys the
    /// forced balance instead of being constant).
    const SYMMETRY_FORCED: bool;

    /// The declared symmetry: [`Self::SYMMETRY`] for a system compiled in; a system given at run
    /// time (whose constants cannot know its coordinates) says it here. What the integrators and
    /// output read.
    fn symmetry(&self) -> RotationSymmetry<'_> {
        Self::SYMMETRY
    }

    /// Whether the forces act on a coordinate the symmetry moves: [`Self::SYMMETRY_FORCED`] for
    /// a system compiled in; a system given at run time says it here. What the integrators read.
    fn symmetry_forced(&self) -> bool {
        Self::SYMMETRY_FORCED
    }

    /// The reduced step residual (`R_k` replaced by the identity for [`RotationSymmetry::Rotations`];
    /// the unreduced residual for [`RotationSymmetry::Axis`]).
    fn reduced_residual(
        &self,
        q_k: &SVector<f64, P>,
        p_k: &SVector<f64, N>,
        z: &SVector<f64, N>,
    ) -> SVector<f64, N> {
        self.residual(q_k, p_k, z)
    }

    /// The reduced residual and its exact Jacobian.
    fn reduced_residual_jacobian(
        &self,
        q_k: &SVector<f64, P>,
        p_k: &SVector<f64, N>,
        z: &SVector<f64, N>,
    ) -> (
        SVector<f64, N>,
        <Self::Linear as crate::linalg::LinearSolver>::Matrix,
    ) {
        self.residual_jacobian(q_k, p_k, z)
    }

    /// The reduced momentum update.
    fn reduced_momentum(
        &self,
        q_k: &SVector<f64, P>,
        p_k: &SVector<f64, N>,
        z: &SVector<f64, N>,
    ) -> SVector<f64, N> {
        self.momentum(q_k, p_k, z)
    }
}

/// A state of a reduced system on rotation groups: the unreduced state's `(q, p)` and the
/// conserved momentum `mu` of the symmetry. At any size;
/// [`ReducedLieState<P, N>`](ReducedLieState) names it at fixed sizes.
#[derive(Clone, Debug, PartialEq)]
pub struct ReducedLieStateOf<P: Dim, N: Dim>
where
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    /// The stored point; the rotation the symmetry acts on is the reconstruction
    /// (`R_{k+1} = R_k F_k`), which the reduced dynamics does not read.
    pub q: OVector<f64, P>,
    /// The momentum in the chart centred at `q`: the reduced momentum `Π` for
    /// [`RotationSymmetry::Rotations`], with its group part `μ` for the rotations about an axis.
    pub p: OVector<f64, N>,
    /// The momentum of the symmetry, a parameter of the reduced dynamics: the spatial momentum
    /// `π` for every rotation, `μ e` (one nonzero entry, on the axis) for the rotations about an
    /// axis.
    pub mu: Vector3<f64>,
}

/// A state of a reduced system on rotation groups at fixed sizes (see [`ReducedLieStateOf`]).
pub type ReducedLieState<const P: usize, const N: usize> = ReducedLieStateOf<Const<P>, Const<N>>;

impl<const P: usize, const N: usize> Copy for ReducedLieStateOf<Const<P>, Const<N>> {}

impl<P: Dim, N: Dim> ReducedLieStateOf<P, N>
where
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    /// The unreduced state `(q, p)`.
    pub fn unreduced(&self) -> LieStateOf<P, N> {
        LieStateOf {
            q: self.q.clone(),
            p: self.p.clone(),
        }
    }

    /// Whether every entry is finite.
    pub fn is_finite(&self) -> bool {
        crate::state::all_finite(&[self.q.as_slice(), self.p.as_slice(), self.mu.as_slice()])
    }
}

/// A trajectory of a reduced system on rotation groups, at any size (see
/// [`LieTrajectoryIn`](super::LieTrajectoryIn)).
pub type ReducedLieTrajectoryOf<P, N> = super::LieTrajectoryIn<ReducedLieStateOf<P, N>>;

/// A trajectory of a reduced system on rotation groups at fixed sizes (see
/// [`LieTrajectoryIn`](super::LieTrajectoryIn)).
pub type ReducedLieTrajectory<const P: usize, const N: usize> =
    ReducedLieTrajectoryOf<Const<P>, Const<N>>;

/// The reduced form of the integrator on rotation groups ([`LieIntegratorIn`]): the reduced
/// equations of the system's declared symmetry on [`ReducedLieStateOf`]s, the symmetry's momentum
/// set before and after the unreduced step on the charts (see the [module documentation](self)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ReducedForm;

/// The reduced integrator of a [`LieSymmetric`] system (see the [module documentation](self)):
/// the same run API, compositions, checks and diagnostics as
/// [`LieIntegrator`](super::LieIntegratorOf) — one type, [`LieIntegratorIn`], in the form
/// [`ReducedForm`] —, on [`ReducedLieState`]s. At any size;
/// [`ReducedLieIntegrator<L, P, N>`](ReducedLieIntegrator) names it at fixed sizes.
pub type ReducedLieIntegratorOf<L, P, N> = LieIntegratorIn<L, P, N, ReducedForm>;

/// The reduced integrator of a [`LieSymmetric`] system at fixed sizes (see
/// [`ReducedLieIntegratorOf`]).
pub type ReducedLieIntegrator<L, const P: usize, const N: usize> =
    ReducedLieIntegratorOf<L, Const<P>, Const<N>>;

/// Largest accepted relative mismatch between a reduced state's `mu` and the momentum map of its
/// `(q, p)`.
const MOMENTUM_TOLERANCE: f64 = 1e-9;

impl<L, P: Dim, N: Dim> ReducedLieIntegratorOf<L, P, N>
where
    L: SymmetricLieModel<P, N>,
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    /// The unreduced integrator of the same system, Newton options and side (a copy): its steps
    /// are this integrator's to round-off. The diagnostics of the charts
    /// ([`manifold_defect`](LieIntegratorIn::manifold_defect),
    /// [`chart_coordinates`](LieIntegratorIn::chart_coordinates), ..) are this integrator's own,
    /// and apply to reduced states through [`ReducedLieState::unreduced`].
    pub fn unreduced(&self) -> LieIntegratorOf<L, P, N> {
        self.in_form()
    }

    /// The momentum map of the symmetry at `(q, p)`: `π = R Π` of the rotation coordinate for
    /// [`RotationSymmetry::Rotations`], `(e · π) e` for the rotations about the axis `e`. A
    /// `Result` as on every integrator: [`StepError::NonFinite`] for a state that is not
    /// finite.
    pub fn momentum_map(&self, state: &LieStateOf<P, N>) -> Result<Vector3<f64>, StepError> {
        crate::stepper::finite_momentum_map(self.spatial_momentum_map(state))
    }

    /// [`Self::momentum_map`]'s value, unchecked (what the reduction reads).
    fn spatial_momentum_map(&self, state: &LieStateOf<P, N>) -> Vector3<f64> {
        self.momentum_map_of(&state.q, &state.p)
    }

    /// The momentum map at the point `q` with the momentum `p`.
    fn momentum_map_of(&self, q: &OVector<f64, P>, p: &OVector<f64, N>) -> Vector3<f64> {
        self.momentum_map_with(q, p, &mut zeros(self.system().dims().1))
    }

    /// [`Self::momentum_map_of`], the generator of the rotations about an axis written into
    /// `zeta` (a step's buffer: nothing allocated).
    fn momentum_map_with(
        &self,
        q: &OVector<f64, P>,
        p: &OVector<f64, N>,
        zeta: &mut OVector<f64, N>,
    ) -> Vector3<f64> {
        let system = self.system();
        match system.symmetry() {
            RotationSymmetry::Rotations { coordinate } => {
                let (r, c) = rotation_block(system, coordinate);
                matrix_at(q.as_slice(), r) * Vector3::new(p[c], p[c + 1], p[c + 2])
            }
            RotationSymmetry::RigidMotions { coordinate } => {
                let (r, c) = rotation_block(system, coordinate);
                let x = Vector3::new(q[r + 9], q[r + 10], q[r + 11]);
                let linear = Vector3::new(p[c + 3], p[c + 4], p[c + 5]);
                matrix_at(q.as_slice(), r) * Vector3::new(p[c], p[c + 1], p[c + 2])
                    + x.cross(&linear)
            }
            RotationSymmetry::Axis { axis, coordinates } => {
                generator_into(system, q, (axis, coordinates), zeta);
                let mut mu = Vector3::zeros();
                mu[axis] = zeta.dot(p);
                mu
            }
        }
    }

    /// The reduced state of `state`: its momentum map as `mu`.
    pub fn reduce(&self, state: &LieStateOf<P, N>) -> ReducedLieStateOf<P, N> {
        ReducedLieStateOf {
            q: state.q.clone(),
            p: state.p.clone(),
            mu: self.spatial_momentum_map(state),
        }
    }

    /// The reduced step's equations.
    pub(super) const EQUATIONS: StepEquations<L, P, N> = StepEquations {
        residual: L::reduced_residual_into,
        residual_jacobian: L::reduced_residual_jacobian_into,
        momentum: L::reduced_momentum_into,
    };

    /// The step of size `h` from `state`, into `next`.
    fn solve_step_into(
        &self,
        workspace: &mut LieWorkspaceOf<L::Linear, N>,
        at: StepAt<'_>,
        state: &ReducedLieStateOf<P, N>,
        next: &mut ReducedLieStateOf<P, N>,
    ) -> Result<StepStats, StepError> {
        let system = self.system();
        let (symmetry, forced) = (system.symmetry(), system.symmetry_forced());
        match_sizes((&state.q, &state.p), (&mut next.q, &mut next.p));
        let LieWorkspaceOf {
            step,
            momentum,
            generator,
        } = workspace;
        // The momentum the step reads: the state's, with the symmetry's part `μ` for the
        // rotations about an axis.
        momentum.copy_from(&state.p);
        if let RotationSymmetry::Axis { axis, coordinates } = symmetry {
            set_group_part(
                system,
                (&state.q, &mut *momentum),
                (axis, coordinates),
                state.mu[axis],
                generator,
            );
        }
        let stats = self.chart_step_into(
            step,
            at,
            (&state.q, &*momentum),
            &Self::EQUATIONS,
            (&mut next.q, &mut next.p),
        )?;
        let mu = if forced {
            self.momentum_map_with(&next.q, &next.p, generator)
        } else {
            state.mu
        };
        match symmetry {
            RotationSymmetry::Rotations { coordinate } if !forced => {
                onto_level(system, (&mut next.q, &mut next.p), coordinate, &mu);
            }
            RotationSymmetry::RigidMotions { coordinate } if !forced => {
                onto_rigid_level(system, (&next.q, &mut next.p), coordinate, &mu, &state.p);
            }
            RotationSymmetry::Rotations { .. } | RotationSymmetry::RigidMotions { .. } => {}
            RotationSymmetry::Axis { axis, coordinates } => {
                set_group_part(
                    system,
                    (&next.q, &mut next.p),
                    (axis, coordinates),
                    mu[axis],
                    generator,
                );
            }
        }
        next.mu = mu;
        // The step checked its own state; what the corrections computed from it is checked here.
        if !next.mu.iter().chain(next.p.iter()).all(|v| v.is_finite()) {
            return Err(StepError::NonFinite {
                step: at.k,
                what: "the updated state",
                residual: stats.residual,
            });
        }
        Ok(stats)
    }
}

/// The point and chart offsets of coordinate `index` of `sys`.
fn rotation_block<L: LieModel<P, N>, P: Dim, N: Dim>(sys: &L, index: usize) -> (usize, usize)
where
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    let block = blocks(sys)
        .nth(index)
        .expect("the symmetry names a declared coordinate");
    (block.point, block.chart)
}

/// The generator `ζ(q)` of the rotations about coordinate axis `axis` of the listed
/// coordinates of `sys`, in the chart at `q`
/// ([`Group::rotation_generator`](super::Group::rotation_generator)): a rotation's body
/// components `Rᵀ e`, a direction's frame components `((e × n)·e_1, (e × n)·e_2)`, a pose's
/// `(Rᵀ e, e × x)`.
fn generator_into<L: LieModel<P, N>, P: Dim, N: Dim>(
    sys: &L,
    q: &OVector<f64, P>,
    (axis, coordinates): (usize, &[usize]),
    zeta: &mut OVector<f64, N>,
) where
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    let e = Vector3::ith(axis, 1.0);
    zeta.fill(0.0);
    for (index, block) in blocks(sys).enumerate() {
        if !coordinates.contains(&index) {
            continue;
        }
        block.kind.group().rotation_generator(
            block.of_point(q.as_slice()),
            &e,
            block.of_chart_mut(zeta.as_mut_slice()),
        );
    }
}

/// Sets the group part of `state.p` to `mu`: `p + (μ − ⟨p, ζ⟩) ζ / |ζ|²` (nothing on the axis,
/// where `ζ = 0`).
pub(super) fn set_group_part<L: LieModel<P, N>, P: Dim, N: Dim>(
    sys: &L,
    (q, p): (&OVector<f64, P>, &mut OVector<f64, N>),
    symmetry: (usize, &[usize]),
    mu: f64,
    zeta: &mut OVector<f64, N>,
) where
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    generator_into(sys, q, symmetry, zeta);
    let norm2 = zeta.norm_squared();
    if norm2 > 0.0 {
        let missing = mu - zeta.dot(p);
        let c = missing / norm2;
        for (p, z) in p.iter_mut().zip(zeta.iter()) {
            *p += z * c;
        }
    }
}

/// Puts `state` on the momentum level `R Π = π` of the rotation coordinate `index`: `Π` scaled
/// onto the orbit `|Π| = |π|`, then `R` turned by the smallest rotation taking `R Π` to `π` and
/// made orthogonal to round-off (all three of the size of the step's round-off). Nothing where
/// `π` or `Π` vanishes.
fn onto_level<L: LieModel<P, N>, P: Dim, N: Dim>(
    sys: &L,
    (q, p): (&mut OVector<f64, P>, &mut OVector<f64, N>),
    index: usize,
    pi: &Vector3<f64>,
) where
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    let (at, c) = rotation_block(sys, index);
    let body = Vector3::new(p[c], p[c + 1], p[c + 2]);
    let (size, own) = (pi.norm(), body.norm());
    if size == 0.0 || own == 0.0 {
        return;
    }
    let body = body * (size / own);
    let r = matrix_at(q.as_slice(), at);
    let (from, to) = ((r * body) / size, pi / size);
    // The smallest rotation taking `from` to `to` is `I + v̂ + v̂²/(1 + cos)`, `v = from × to`;
    // `|v|` is of the size of the step's round-off (the check of a run's first state bounds it
    // by 1e-9), so `v̂²` is below the round-off of `I + v̂` and is left out, and the
    // Newton–Schulz step below restores orthogonality to second order.
    let turned = r + super::hat(&from.cross(&to)) * r;
    // One Newton–Schulz step towards the nearest rotation, `R (3I − RᵀR)/2`: squares the
    // orthogonality defect, so the reconstruction stays on SO(3) at the round-off of one step
    // instead of a random walk of them (the reduced dynamics does not read it).
    let turned = turned * (Matrix3::identity() * 3.0 - turned.transpose() * turned) * 0.5;
    for i in 0..3 {
        for j in 0..3 {
            q[at + 3 * i + j] = turned[(i, j)];
        }
        p[c + i] = body[i];
    }
}

/// Puts `state` on the momentum level `(π, p)` of the rigid motions of the pose coordinate
/// `index`: the linear momentum `p` copied from the step's start `before` (bit for bit: it is
/// constant), and the body angular momentum set to `Π = Rᵀ (π − x × p)` at the new pose (a
/// change of the size of the step's round-off), so that `R Π + x × p = π` holds to the
/// round-off of one evaluation at every step instead of a sum of them.
fn onto_rigid_level<L: LieModel<P, N>, P: Dim, N: Dim>(
    sys: &L,
    (q, p): (&OVector<f64, P>, &mut OVector<f64, N>),
    index: usize,
    pi: &Vector3<f64>,
    before: &OVector<f64, N>,
) where
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    let (at, c) = rotation_block(sys, index);
    let linear = Vector3::new(before[c + 3], before[c + 4], before[c + 5]);
    let x = Vector3::new(q[at + 9], q[at + 10], q[at + 11]);
    let body = matrix_at(q.as_slice(), at).transpose() * (pi - x.cross(&linear));
    for i in 0..3 {
        p[c + i] = body[i];
        p[c + 3 + i] = linear[i];
    }
}

impl<L, P: Dim, N: Dim> LieForm<L, P, N> for ReducedForm
where
    L: SymmetricLieModel<P, N>,
    DefaultAllocator: Allocator<P> + Allocator<N>,
    ReducedLieStateOf<P, N>: Send + Sync,
{
    type State = ReducedLieStateOf<P, N>;

    #[inline]
    fn point(state: &ReducedLieStateOf<P, N>) -> &OVector<f64, P> {
        &state.q
    }

    /// The unreduced integrator's checks, and `mu` the momentum map of `(q, p)` (to `1e-9`
    /// relative; build reduced states with [`ReducedLieIntegrator::reduce`]).
    fn check(
        integrator: &ReducedLieIntegratorOf<L, P, N>,
        initial: &ReducedLieStateOf<P, N>,
    ) -> Result<(), StepError> {
        let state = initial.unreduced();
        integrator.check_unreduced(&state)?;
        let expected = integrator.spatial_momentum_map(&state);
        let scale = expected.norm().max(initial.mu.norm()).max(1.0);
        let off = (expected - initial.mu).norm();
        if off.is_nan() || off > MOMENTUM_TOLERANCE * scale {
            return Err(StepError::OffManifold {
                reason: format!(
                    "the momentum `mu` = {:?} of the reduced state is not the momentum map {:?} of its \
                     (q, p) (they differ by {off:.3e}); build reduced states with \
                     `ReducedLieIntegrator::reduce`",
                    initial.mu.as_slice(),
                    expected.as_slice()
                ),
            });
        }
        Ok(())
    }

    /// The unreduced step's with the reduced equations, Newton starting from the chart
    /// coordinate of the last steps, extrapolated; then the momentum of the symmetry set.
    fn step_into(
        integrator: &ReducedLieIntegratorOf<L, P, N>,
        workspace: &mut LieWorkspaceOf<L::Linear, N>,
        at: StepAt<'_>,
        state: &ReducedLieStateOf<P, N>,
        next: &mut ReducedLieStateOf<P, N>,
    ) -> Result<StepStats, StepError> {
        check_sizes(integrator.system(), (&state.q, &state.p))?;
        integrator.solve_step_into(workspace, at, state, next)
    }
}
