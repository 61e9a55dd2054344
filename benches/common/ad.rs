//! The baseline the attribute replaces: the same discrete Lagrangians differentiated at run time
//! by num-dual, written the way a user without `#[reduced_lagrangian]` would write them.
//!
//! `L_d` is one generic function over `DualNum<f64>` ([`DualLagrangian`]). The reduced (+)
//! Lagrangian with `B = 0` (both paper systems) is `l_{d+}(x0, x1, g1) = L_d((x0, 0), (x1, g1))`,
//! eq. (4.5), and the step of eq. (4.6) solves
//!
//! ```text
//! R(z) = ( ∂l/∂x0 + w_k ,  ∂l/∂g1 − μ_k ) = 0   in   z = (x1, g1),
//! ```
//!
//! the residual and Jacobian of `Reduced::<Plus, ..>::residual_jacobian`. They are taken from
//! num-dual in two ways:
//!
//! * [`residual_jacobian`]: `num_dual::hessian` of `l_{d+}` in all `2S + K` variables
//!   `(x0, x1, g1)`, then the rows `(x0, g1)` and columns `z` of the gradient and Hessian — the
//!   obvious code;
//! * [`residual_jacobian_partial`]: `num_dual::partial_hessian`, which propagates only the
//!   `N × N` block `∂²l/∂(x0, g1)∂z` — what a user who knows num-dual well would write.
//!
//! The residual alone (Newton's convergence test) is `num_dual::gradient` in the `N` variables
//! `(x0, g1)`, and `w_{k+1} = ∂l/∂x1` is `num_dual::gradient` in `x1`. [`step`] runs the runtime's
//! own Newton solver (`dirac::runtime::newton::solve`, same tolerances) on them, so the timings
//! differ only in how the derivatives are obtained.

use dirac::paper::{ChargedParticle, DoubleSphericalPendulum};
use dirac::prelude::*;
use dirac::runtime::newton::{self, NewtonFailure};
use dirac::runtime::system::{join, split};
use num_dual::{
    gradient, hessian, partial_hessian, Dual2SVec64, DualNum, DualSVec64, HyperDualSVec64,
};

/// A discrete Lagrangian `L_d(q0, q1)` on configurations `q = (x, g)`, generic over the number
/// type so one body serves `f64` and every dual number.
pub trait DualLagrangian<const N: usize> {
    fn ld<T: DualNum<Primitive = f64> + Copy>(&self, q0: [T; N], q1: [T; N]) -> T;
}

/// §7.1, the body of `dirac::paper::charged_particle` over `q = (x, y, z, θ)`.
impl DualLagrangian<4> for ChargedParticle {
    fn ld<T: DualNum<Primitive = f64> + Copy>(&self, q0: [T; 4], q1: [T; 4]) -> T {
        let (dx, dy, dz) = (q1[0] - q0[0], q1[1] - q0[1], q1[2] - q0[2]);
        let a_dot_dq = (-q0[1] * dx + q0[0] * dy) * (0.5 * self.b0);
        let s = a_dot_dq + (q1[3] - q0[3]);
        (dx * dx + dy * dy + dz * dz) * (0.5 * self.m / self.h) + s * s * (0.5 / self.h)
    }
}

/// §7.2, the body of `dirac::paper::double_spherical_pendulum` (the Cartesian-velocity form) over
/// `q = (φ1, ϑ2, φ2, ϑ1)`.
impl DualLagrangian<4> for DoubleSphericalPendulum {
    fn ld<T: DualNum<Primitive = f64> + Copy>(&self, q0: [T; 4], q1: [T; 4]) -> T {
        let (h, m1, m2, l1, l2, g) = (self.h, self.m1, self.m2, self.l1, self.l2, self.g);
        let mid = |i: usize| (q0[i] + q1[i]) * 0.5;
        let rate = |i: usize| (q1[i] - q0[i]) / h;
        let (phi1, vt2, phi2, vt1) = (mid(0), mid(1), mid(2), mid(3));
        let (dphi1, dvt2, dphi2, dvt1) = (rate(0), rate(1), rate(2), rate(3));
        let (th1, th2) = (vt1 - vt2, vt1 + vt2);
        let (dth1, dth2) = (dvt1 - dvt2, dvt1 + dvt2);
        let (s1, c1, s2, c2) = (phi1.sin(), phi1.cos(), phi2.sin(), phi2.cos());
        let (st1, ct1, st2, ct2) = (th1.sin(), th1.cos(), th2.sin(), th2.cos());
        let v1 = [
            (c1 * ct1 * dphi1 - s1 * st1 * dth1) * l1,
            (c1 * st1 * dphi1 + s1 * ct1 * dth1) * l1,
            -s1 * dphi1 * l1,
        ];
        let u2 = [
            (c2 * ct2 * dphi2 - s2 * st2 * dth2) * l2,
            (c2 * st2 * dphi2 + s2 * ct2 * dth2) * l2,
            -s2 * dphi2 * l2,
        ];
        let v2 = [v1[0] + u2[0], v1[1] + u2[1], v1[2] + u2[2]];
        let kinetic = (v1[0] * v1[0] + v1[1] * v1[1] + v1[2] * v1[2]) * (0.5 * m1)
            + (v2[0] * v2[0] + v2[1] * v2[1] + v2[2] * v2[2]) * (0.5 * m2);
        let potential = (c1 * (m1 * l1) + (c1 * l1 + c2 * l2) * m2) * g;
        (kinetic - potential) * h
    }
}

/// The constant part of the residual, `(w_k, −μ_k)`.
fn momenta<const S: usize, const K: usize, const N: usize>(
    w_k: &SVector<f64, S>,
    mu_k: &SVector<f64, K>,
) -> SVector<f64, N> {
    join::<S, K, N>(w_k, &-mu_k)
}

/// `R(z)` alone: the gradient of `l_{d+}` in `(x0, g1)` with first-order duals.
pub fn residual<L: DualLagrangian<N>, const S: usize, const K: usize, const N: usize>(
    sys: &L,
    x_k: &SVector<f64, S>,
    w_k: &SVector<f64, S>,
    mu_k: &SVector<f64, K>,
    z: &SVector<f64, N>,
) -> SVector<f64, N> {
    let (x1, g1) = split::<S, K, N>(z);
    let (_, grad) = gradient(
        |v: SVector<DualSVec64<N>, N>| {
            let zero = DualSVec64::<N>::from(0.0);
            let q0 = std::array::from_fn(|i| if i < S { v[i] } else { zero });
            let q1 = std::array::from_fn(|i| if i < S { x1[i].into() } else { v[i] });
            sys.ld(q0, q1)
        },
        &join::<S, K, N>(x_k, &g1),
    );
    grad + momenta::<S, K, N>(w_k, mu_k)
}

/// `R(z)` and `∂R/∂z` from `num_dual::hessian` of `l_{d+}` in all `M = 2S + K` variables
/// `v = (x0, x1, g1)`: the rows of `R` are the variables `x0` and `g1`, the columns of the
/// Jacobian the variables `z = (x1, g1)`.
pub fn residual_jacobian<
    L: DualLagrangian<N>,
    const S: usize,
    const K: usize,
    const N: usize,
    const M: usize,
>(
    sys: &L,
    x_k: &SVector<f64, S>,
    w_k: &SVector<f64, S>,
    mu_k: &SVector<f64, K>,
    z: &SVector<f64, N>,
) -> (SVector<f64, N>, SMatrix<f64, N, N>) {
    debug_assert_eq!(M, S + N);
    let v = SVector::<f64, M>::from_fn(|i, _| if i < S { x_k[i] } else { z[i - S] });
    let (_, grad, hess) = hessian(
        |v: SVector<Dual2SVec64<M>, M>| {
            let zero = Dual2SVec64::<M>::from(0.0);
            let q0 = std::array::from_fn(|i| if i < S { v[i] } else { zero });
            let q1 = std::array::from_fn(|i| v[S + i]);
            sys.ld(q0, q1)
        },
        &v,
    );
    let row = |r: usize| if r < S { r } else { S + r };
    let r = SVector::<f64, N>::from_fn(|r, _| grad[row(r)]) + momenta::<S, K, N>(w_k, mu_k);
    let jac = SMatrix::<f64, N, N>::from_fn(|r, c| hess[(row(r), S + c)]);
    (r, jac)
}

/// `R(z)` and `∂R/∂z` from `num_dual::partial_hessian`, which carries only the gradient in the
/// row variables `a = (x0, g1)`, the gradient in `z` and the block `∂²l/∂a∂z`. `g1` is both a
/// row and a column variable: its value rides on `z`, its row direction on a zero-valued `a_g`
/// added to it.
pub fn residual_jacobian_partial<
    L: DualLagrangian<N>,
    const S: usize,
    const K: usize,
    const N: usize,
>(
    sys: &L,
    x_k: &SVector<f64, S>,
    w_k: &SVector<f64, S>,
    mu_k: &SVector<f64, K>,
    z: &SVector<f64, N>,
) -> (SVector<f64, N>, SMatrix<f64, N, N>) {
    type H<const N: usize> = HyperDualSVec64<N, N>;
    let a = join::<S, K, N>(x_k, &SVector::zeros());
    let (_, grad_a, _, jac) = partial_hessian(
        |(a, z): (SVector<H<N>, N>, SVector<H<N>, N>)| {
            let zero = H::<N>::from(0.0);
            let q0 = std::array::from_fn(|i| if i < S { a[i] } else { zero });
            let q1 = std::array::from_fn(|i| if i < S { z[i] } else { z[i] + a[i] });
            sys.ld(q0, q1)
        },
        (&a, z),
    );
    (grad_a + momenta::<S, K, N>(w_k, mu_k), jac)
}

/// `w_{k+1} = ∂l_{d+}/∂x1`, the gradient in `x1`.
pub fn momentum<L: DualLagrangian<N>, const S: usize, const K: usize, const N: usize>(
    sys: &L,
    x_k: &SVector<f64, S>,
    z: &SVector<f64, N>,
) -> SVector<f64, S> {
    let (x1, g1) = split::<S, K, N>(z);
    let (_, grad) = gradient(
        |x1: SVector<DualSVec64<S>, S>| {
            let q0 = std::array::from_fn(|i| if i < S { x_k[i].into() } else { 0.0.into() });
            let q1 = std::array::from_fn(|i| if i < S { x1[i] } else { g1[i - S].into() });
            sys.ld(q0, q1)
        },
        &x1,
    );
    grad
}

/// Which num-dual Jacobian a [`step`] uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Jacobian {
    /// [`residual_jacobian`]: the full Hessian in `(x0, x1, g1)`.
    Hessian,
    /// [`residual_jacobian_partial`]: the `N × N` block only.
    PartialHessian,
}

/// One step of eq. (4.6) with num-dual derivatives, exactly as `ReducedIntegrator::step` takes it
/// with the generated ones: the runtime's Newton solver and tolerances, then `w_{k+1}`,
/// `μ_{k+1} = μ_k` and `g_{k+1} = g_k + g_k^+` (`B = 0`). Returns the new state, `g_k^+` and the
/// Newton corrections taken.
pub fn step<
    L: DualLagrangian<N>,
    const S: usize,
    const K: usize,
    const N: usize,
    const M: usize,
>(
    sys: &L,
    options: &NewtonOptions,
    jacobian: Jacobian,
    state: &ReducedState<S, K>,
    guess: &SVector<f64, N>,
) -> Result<(ReducedState<S, K>, SVector<f64, K>, usize), NewtonFailure> {
    let (x, w, mu) = (&state.x, &state.w, &state.mu);
    let rho = newton::inf_norm(w).max(newton::inf_norm(mu));
    let r = |z: &SVector<f64, N>| residual::<L, S, K, N>(sys, x, w, mu, z);
    let solution = match jacobian {
        Jacobian::Hessian => newton::solve(*guess, rho, options, r, |z| {
            residual_jacobian::<L, S, K, N, M>(sys, x, w, mu, z)
        }),
        Jacobian::PartialHessian => newton::solve(*guess, rho, options, r, |z| {
            residual_jacobian_partial::<L, S, K, N>(sys, x, w, mu, z)
        }),
    }?;
    let (x1, g_plus) = split::<S, K, N>(&solution.z);
    let next = ReducedState {
        x: x1,
        w: momentum::<L, S, K, N>(sys, x, &solution.z),
        mu: *mu,
        g: state.g + g_plus,
    };
    Ok((next, g_plus, solution.iterations))
}
