//! `Reduced<Plus>`, `Reduced<Minus>` (eqs. (4.6), (4.8)) and `Unreduced` (Definitions 2.7/2.8)
//! for a system given as text: each function one kernel call.

use dirac_runtime::linalg::LinearSolver;
use dirac_runtime::nalgebra::{SMatrix, SVector};
use dirac_runtime::{Minus, Plus, Reduced, Unreduced};

use super::backend::{Backend, ResidualJacobian};
use super::{JitSystem, ResidualMomentum, UNUSED};

/// `Reduced<Plus>` and `Reduced<Minus>`: the same calls on each side's kernels.
macro_rules! reduced_impl {
    ($side:ty, $plus:expr) => {
        impl<const S: usize, const K: usize, const N: usize, B: Backend<N>> Reduced<$side, S, K, N>
            for JitSystem<S, K, N, B>
        {
            type Linear = B::Linear;

            fn linear_solver(&self) -> B::Linear {
                B::solver(&self.side_code($plus).stepper)
            }

            fn reduced_lagrangian(
                &self,
                x0: &SVector<f64, S>,
                x1: &SVector<f64, S>,
                u: &SVector<f64, K>,
            ) -> f64 {
                self.reduced_lagrangian_of($plus, x0, x1, u)
            }

            fn residual(
                &self,
                x_k: &SVector<f64, S>,
                w_k: &SVector<f64, S>,
                mu_k: &SVector<f64, K>,
                z: &SVector<f64, N>,
            ) -> SVector<f64, N> {
                self.call(
                    self.side($plus).stepper.residual,
                    Self::reduced_args(x_k, w_k, mu_k, z),
                    SVector::zeros(),
                )
            }

            fn residual_jacobian(
                &self,
                x_k: &SVector<f64, S>,
                w_k: &SVector<f64, S>,
                mu_k: &SVector<f64, K>,
                z: &SVector<f64, N>,
            ) -> (SVector<f64, N>, <B::Linear as LinearSolver>::Matrix) {
                B::residual_jacobian(&self.side_code($plus).stepper, |out| {
                    self.call_into(
                        self.side($plus).stepper.residual_jacobian,
                        Self::reduced_args(x_k, w_k, mu_k, z),
                        out,
                    )
                })
            }

            fn momentum(&self, x_k: &SVector<f64, S>, z: &SVector<f64, N>) -> SVector<f64, S> {
                self.call(
                    self.side($plus).stepper.momentum,
                    [x_k.as_ptr(), UNUSED, UNUSED, z.as_ptr()],
                    SVector::zeros(),
                )
            }

            fn residual_momentum(
                &self,
                x_k: &SVector<f64, S>,
                w_k: &SVector<f64, S>,
                mu_k: &SVector<f64, K>,
                z: &SVector<f64, N>,
            ) -> (SVector<f64, N>, SVector<f64, S>) {
                let rm = self.call(
                    self.side($plus).stepper.residual_momentum,
                    Self::reduced_args(x_k, w_k, mu_k, z),
                    ResidualMomentum {
                        r: SVector::zeros(),
                        m: SVector::zeros(),
                    },
                );
                (rm.r, rm.m)
            }

            /// Whether a force has a group component is known only at run time: `μ` is always
            /// updated by the impulse, which is exactly zero without one (`μ + 0 = μ`).
            const GROUP_FORCED: bool = true;

            const ELIMINATES_GROUP: bool = true;

            fn eliminates_group(&self) -> bool {
                self.side($plus).eliminated.is_some()
            }

            fn elimination_pays(&self) -> bool {
                self.side($plus).eliminated.is_some_and(|e| e.pays)
            }

            fn eliminated_residual(
                &self,
                x_k: &SVector<f64, S>,
                w_k: &SVector<f64, S>,
                mu_k: &SVector<f64, K>,
                x1: &SVector<f64, S>,
            ) -> Option<SVector<f64, S>> {
                let e = self.side($plus).eliminated?;
                Some(self.call(
                    e.residual,
                    [x_k.as_ptr(), w_k.as_ptr(), mu_k.as_ptr(), x1.as_ptr()],
                    SVector::zeros(),
                ))
            }

            fn eliminated_residual_jacobian(
                &self,
                x_k: &SVector<f64, S>,
                w_k: &SVector<f64, S>,
                mu_k: &SVector<f64, K>,
                x1: &SVector<f64, S>,
            ) -> Option<(SVector<f64, S>, SMatrix<f64, S, S>)> {
                let e = self.side($plus).eliminated?;
                let rj = self.call(
                    e.residual_jacobian,
                    [x_k.as_ptr(), w_k.as_ptr(), mu_k.as_ptr(), x1.as_ptr()],
                    ResidualJacobian {
                        r: SVector::zeros(),
                        j: SMatrix::zeros(),
                    },
                );
                Some((rj.r, rj.j))
            }

            fn eliminated_group(
                &self,
                x_k: &SVector<f64, S>,
                w_k: &SVector<f64, S>,
                mu_k: &SVector<f64, K>,
                x1: &SVector<f64, S>,
            ) -> Option<SVector<f64, K>> {
                let e = self.side($plus).eliminated?;
                Some(self.call(
                    e.group,
                    [x_k.as_ptr(), w_k.as_ptr(), mu_k.as_ptr(), x1.as_ptr()],
                    SVector::zeros(),
                ))
            }

            fn eliminated_group_block(
                &self,
                x_k: &SVector<f64, S>,
                w_k: &SVector<f64, S>,
                mu_k: &SVector<f64, K>,
                x1: &SVector<f64, S>,
            ) -> Option<SMatrix<f64, K, K>> {
                let e = self.side($plus).eliminated?;
                Some(self.call(
                    e.block,
                    [x_k.as_ptr(), w_k.as_ptr(), mu_k.as_ptr(), x1.as_ptr()],
                    SMatrix::zeros(),
                ))
            }

            fn group_impulse(&self, x_k: &SVector<f64, S>, z: &SVector<f64, N>) -> SVector<f64, K> {
                match self.side($plus).impulse {
                    Some(kernel) => self.call(
                        kernel,
                        [x_k.as_ptr(), UNUSED, UNUSED, z.as_ptr()],
                        SVector::zeros(),
                    ),
                    None => SVector::zeros(),
                }
            }
        }
    };
}

reduced_impl!(Plus, true);
reduced_impl!(Minus, false);

impl<const S: usize, const K: usize, const N: usize, B: Backend<N>> Unreduced<S, K, N>
    for JitSystem<S, K, N, B>
{
    type UnreducedLinear = B::Linear;

    fn unreduced_linear_solver(&self) -> B::Linear {
        B::solver(&self.code.system.unreduced)
    }

    fn unreduced_residual(
        &self,
        q_k: &SVector<f64, N>,
        p_k: &SVector<f64, N>,
        z: &SVector<f64, N>,
    ) -> SVector<f64, N> {
        self.call(
            self.code.kernels.unreduced.residual,
            [q_k.as_ptr(), p_k.as_ptr(), z.as_ptr(), UNUSED],
            SVector::zeros(),
        )
    }

    fn unreduced_residual_jacobian(
        &self,
        q_k: &SVector<f64, N>,
        p_k: &SVector<f64, N>,
        z: &SVector<f64, N>,
    ) -> (SVector<f64, N>, <B::Linear as LinearSolver>::Matrix) {
        B::residual_jacobian(&self.code.system.unreduced, |out| {
            self.call_into(
                self.code.kernels.unreduced.residual_jacobian,
                [q_k.as_ptr(), p_k.as_ptr(), z.as_ptr(), UNUSED],
                out,
            )
        })
    }

    fn unreduced_momentum(&self, q_k: &SVector<f64, N>, z: &SVector<f64, N>) -> SVector<f64, N> {
        self.call(
            self.code.kernels.unreduced.momentum,
            [q_k.as_ptr(), UNUSED, z.as_ptr(), UNUSED],
            SVector::zeros(),
        )
    }
}
