//! `Reduced<Plus>`, `Reduced<Minus>` (eqs. (4.6), (4.8)) and `Unreduced` (Definitions 2.7/2.8)
//! for a system given as text: each function one kernel call.

use dirac_compiler::program::Program;
use dirac_runtime::linalg::LinearSolver;
use dirac_runtime::nalgebra::{SMatrix, SVector};
use dirac_runtime::{LagrangianHessian, Minus, Plus, Reduced, StepPartials, Unreduced};

use super::backend::{Backend, Dense, ResidualJacobian};
use super::{JitSystem, ResidualMomentum, UNUSED};
use crate::codegen::Kernel;

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
                    Self::reduced_args(x_k, w_k, mu_k, x1),
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
                    Self::reduced_args(x_k, w_k, mu_k, x1),
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
                    Self::reduced_args(x_k, w_k, mu_k, x1),
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
                    Self::reduced_args(x_k, w_k, mu_k, x1),
                    SMatrix::zeros(),
                ))
            }

            fn step_partials(
                &self,
                x_k: &SVector<f64, S>,
                w_k: &SVector<f64, S>,
                mu_k: &SVector<f64, K>,
                z: &SVector<f64, N>,
                out: &mut StepPartials,
            ) -> bool {
                let Some(kernel) = self.side($plus).partials else {
                    return false;
                };
                let program = self.side_code($plus).partials.as_ref();
                self.partials_into(kernel, program, Self::reduced_args(x_k, w_k, mu_k, z), out)
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

    fn unreduced_step_partials(
        &self,
        q_k: &SVector<f64, N>,
        p_k: &SVector<f64, N>,
        z: &SVector<f64, N>,
        out: &mut StepPartials,
    ) -> bool {
        let Some(kernel) = self.code.kernels.unreduced_partials else {
            return false;
        };
        let program = self.code.system.unreduced_partials.as_ref();
        self.partials_into(
            kernel,
            program,
            [q_k.as_ptr(), p_k.as_ptr(), z.as_ptr(), UNUSED],
            out,
        )
    }
}

/// The second derivatives of `L_d` for the step-map Jacobian, compiled for systems of at most 16
/// coordinates without forces. A system given at run time of another kind has none: its
/// `lagrangian_hessian` is NaN, which `UnreducedIntegrator::step_jacobian` reports as
/// `StepError::NonFinite` rather than use.
impl<const S: usize, const K: usize, const N: usize> LagrangianHessian<S, K, N>
    for JitSystem<S, K, N, Dense>
{
    fn lagrangian_hessian(
        &self,
        q0: &SVector<f64, N>,
        q1: &SVector<f64, N>,
    ) -> (SMatrix<f64, N, N>, SMatrix<f64, N, N>, SMatrix<f64, N, N>) {
        let Some(kernel) = self.code.kernels.hessian else {
            let nan = SMatrix::repeat(f64::NAN);
            return (nan, nan, nan);
        };
        // The program lists each block row by row: the memory of its transpose.
        let blocks = self.call_pair(kernel, q0, q1, [SMatrix::<f64, N, N>::zeros(); 3]);
        (
            blocks[0].transpose(),
            blocks[1].transpose(),
            blocks[2].transpose(),
        )
    }
}

impl<const S: usize, const K: usize, const N: usize, B> JitSystem<S, K, N, B> {
    /// Runs a partial-derivatives kernel and spreads its outputs, block by block and row by
    /// row, over `out`, whose blocks the caller sized; `false` (no sensitivity) if their sizes
    /// are not the program's.
    fn partials_into(
        &self,
        kernel: Kernel,
        program: Option<&Program>,
        args: [*const f64; 4],
        out: &mut StepPartials,
    ) -> bool {
        let Some(program) = program else {
            return false;
        };
        let blocks = [
            &mut out.r_y,
            &mut out.r_u,
            &mut out.o_y,
            &mut out.o_z,
            &mut out.o_u,
        ];
        let len: usize = blocks.iter().map(|m| m.len()).sum();
        if len != program.outputs.len() {
            return false;
        }
        let mut values = vec![0.0; len];
        self.call_into(kernel, args, values.as_mut_ptr());
        let mut at = 0;
        for m in blocks {
            let (rows, cols) = m.shape();
            for i in 0..rows {
                for j in 0..cols {
                    m[(i, j)] = values[at];
                    at += 1;
                }
            }
        }
        true
    }
}
