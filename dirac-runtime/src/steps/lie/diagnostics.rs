//! The paper's diagnostics along a trajectory on rotation groups, reduced or not: how far each
//! step is from the discrete Lagrange–Dirac equations (the Dirac structure, Propositions 3.8 and
//! 4.3, in the charts of [`crate::lie`]), the discrete generalized energy and the discrete
//! action.
//!
//! * **Dirac residual.** A step `(q_k, p_k) → (q_{k+1}, p_{k+1})` is a point of the discrete
//!   Dirac structure when, with `z_k` the chart coordinate of `q_{k+1}` about `q_k`
//!   ([`LieIntegrator::chart_coordinates`](super::LieIntegratorOf::chart_coordinates)), both momentum equations hold:
//!   `p_k = −D1 L̃(0, z_k) (− f_d^−)` and `p_{k+1} = D2 L_d · dφ_{q_{k+1}}(0) (+ f_d^+)`. The
//!   residual is the larger of the two ∞-norms, relative to the momenta's size; along a computed
//!   trajectory it is of the order of the Newton residual the steps were accepted with.
//! * **Discrete generalized energy.** On the trajectory the (+) generalized energy of §5,
//!   `E_{d+}(q_k, q_k^+, p_{k+1}) = L_d(q_k, q_k^+) + ⟨p_{k+1}, q_{k+1} ⊖ q_k^+⟩`, reduces to
//!   `(E_d)_k = L_d(q_k, q_{k+1})` (the pairing vanishes where `q_k^+ = q_{k+1}`: the paper's
//!   (5.7) and its Figure 4); it oscillates about a fixed value without drift.
//! * **Discrete action.** `Σ_k L_d(q_k, q_{k+1})`, each term at its own step size.
//!
//! All three read the system's own parameters: for a controlled run, evaluate them step by step
//! with the controls of each step.

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OVector};

use super::integrator::StepEquations;
use super::reduced::{set_group_part, RotationSymmetry};
use super::SymmetricLieModel;
use super::{
    zeros, LieForm, LieIntegratorIn, LieIntegratorOf, LieModel, LieStateOf, LieTrajectoryIn,
    LieTrajectoryOf, ReducedLieIntegratorOf, ReducedLieStateOf, ReducedLieTrajectoryOf,
};
use crate::newton::slice_inf_norm;

/// The relative Dirac residual of every step between the `states` at `times` for the
/// `equations` (the unreduced or the reduced ones), at each step's own size: `read` gives the
/// state a step read, `landed` the state it reached.
fn dirac_residuals<L, F, S, P: Dim, N: Dim>(
    integrator: &LieIntegratorIn<L, P, N, F>,
    (states, times): (&[S], &[f64]),
    equations: &StepEquations<L, P, N>,
    read: impl Fn(&S) -> LieStateOf<P, N>,
    landed: impl Fn(&S) -> LieStateOf<P, N>,
) -> Vec<f64>
where
    L: LieModel<P, N>,
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    let n = integrator.system().dims().1;
    let (mut r, mut m) = (zeros(n), zeros(n));
    states
        .windows(2)
        .zip(times.windows(2))
        .map(|(s, t)| {
            let sys = integrator.system().with_time_step(t[1] - t[0]);
            let (from, to) = (read(&s[0]), landed(&s[1]));
            let z = integrator.chart_coordinates(&from.q, &to.q);
            let scale = slice_inf_norm(from.p.as_slice())
                .max(slice_inf_norm(to.p.as_slice()))
                .max(1.0);
            (equations.residual)(&sys, &from.q, &from.p, &z, &mut r);
            (equations.momentum)(&sys, &from.q, &from.p, &z, &mut m);
            m -= &to.p;
            slice_inf_norm(r.as_slice()).max(slice_inf_norm(m.as_slice())) / scale
        })
        .collect()
}

impl<L, P: Dim, N: Dim, F> LieIntegratorIn<L, P, N, F>
where
    L: LieModel<P, N>,
    F: LieForm<L, P, N>,
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    /// The discrete generalized energy `(E_d)_k = L_d(q_k, q_{k+1})` of every step, at the step's
    /// own size (reduced: the reduced Lagrangian's value, `L_d` being invariant).
    pub fn discrete_energies(&self, trajectory: &LieTrajectoryIn<F::State>) -> Vec<f64> {
        let points: Vec<&OVector<f64, P>> = trajectory.states.iter().map(F::point).collect();
        points
            .windows(2)
            .zip(trajectory.times.windows(2))
            .map(|(q, t)| {
                let sys = self.system().with_time_step(t[1] - t[0]);
                sys.lagrangian(q[0], q[1])
            })
            .collect()
    }

    /// The discrete action `Σ_k L_d(q_k, q_{k+1})` of `trajectory`.
    pub fn discrete_action(&self, trajectory: &LieTrajectoryIn<F::State>) -> f64 {
        self.discrete_energies(trajectory).iter().sum()
    }
}

impl<L, P: Dim, N: Dim> LieIntegratorOf<L, P, N>
where
    L: LieModel<P, N>,
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    /// The relative Dirac residual of every step of `trajectory` (see the
    /// [module documentation](self)).
    pub fn dirac_residuals(&self, trajectory: &LieTrajectoryOf<P, N>) -> Vec<f64> {
        dirac_residuals(
            self,
            (&trajectory.states, &trajectory.times),
            &StepEquations::UNREDUCED,
            |s| s.clone(),
            |s| s.clone(),
        )
    }
}

impl<L, P: Dim, N: Dim> ReducedLieIntegratorOf<L, P, N>
where
    L: SymmetricLieModel<P, N>,
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    /// The relative Dirac residual of every step of `trajectory` for the reduced equations
    /// (the momentum each step read: `Π_k` for every rotation, the shape part of `p_k` with the
    /// group part `μ` for the rotations about an axis).
    pub fn dirac_residuals(&self, trajectory: &ReducedLieTrajectoryOf<P, N>) -> Vec<f64> {
        let read = |s: &ReducedLieStateOf<P, N>| {
            let mut from = s.unreduced();
            if let RotationSymmetry::Axis { axis, coordinates } = self.system().symmetry() {
                let mut zeta = zeros(self.system().dims().1);
                set_group_part(
                    self.system(),
                    (&from.q, &mut from.p),
                    (axis, coordinates),
                    s.mu[axis],
                    &mut zeta,
                );
            }
            from
        };
        dirac_residuals(
            self,
            (&trajectory.states, &trajectory.times),
            &Self::EQUATIONS,
            read,
            ReducedLieStateOf::unreduced,
        )
    }
}
