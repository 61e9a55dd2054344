//! The linear algebra of a [`JitSystem`](super::JitSystem)'s solves — the dense fixed-size LU
//! ([`Dense`]) or the sparse LU on the Jacobian's structural nonzeros ([`Sparse`]), chosen by
//! size as the attribute chooses — and the kinds of system a type names ([`Variant`]).

use std::marker::PhantomData;

use dirac_compiler::text::{self, System};
use dirac_runtime::linalg::LinearSolver;
use dirac_runtime::nalgebra::{SMatrix, SVector};
use dirac_runtime::{CscBuffer, Lu, PatternLu, DENSE_MAX};

use crate::error::Error;

/// What a [`JitSystem`](super::JitSystem)'s type fixes beyond its dimensions: the backend of its steps
/// ([`Dense`], [`Sparse`]), or its constraints and the backend of their solves
/// ([`WithConstraints`]). Sealed.
pub trait Variant<const N: usize>: sealed::Sealed + Send + Sync + 'static {
    /// Whether the compiled system is one of this kind: the kernels write the Jacobians densely
    /// or as a pattern's values, and read and write as many entries as the dimensions say, so
    /// the memory safety of every call rests on this check.
    fn check(system: &System) -> Result<(), Error>;
}

/// The backend of steppers with `n` unknowns: sparse above [`DENSE_MAX`], as the compiler
/// chooses; an error unless `sparse` says the same.
fn check_backend(
    system: &System,
    steppers: &[&text::Stepper],
    (n, constrained): (usize, bool),
    sparse: bool,
) -> Result<(), Error> {
    let compiled = steppers.iter().any(|stepper| stepper.pattern.is_some());
    if compiled == sparse {
        Ok(())
    } else {
        Err(Error::Backend {
            name: system.name.clone(),
            n,
            dense_max: DENSE_MAX,
            constrained,
        })
    }
}

/// The backend of the unconstrained steps.
macro_rules! backend_variant {
    ($backend:ty) => {
        impl<const N: usize> Variant<N> for $backend {
            fn check(sys: &System) -> Result<(), Error> {
                let steppers = [&sys.plus.stepper, &sys.minus.stepper, &sys.unreduced];
                check_backend(sys, &steppers, (N, false), <$backend as Backend<N>>::SPARSE)
            }
        }
    };
}

backend_variant!(Dense);
backend_variant!(Sparse);

/// The linear algebra a [`JitSystem`](super::JitSystem)'s steps run on: [`Dense`] or [`Sparse`], fixed by the
/// system's size as for a compiled-in system (dense up to 16 coordinates).
pub trait Backend<const N: usize>: Variant<N> {
    /// Whether this is the sparse backend.
    const SPARSE: bool;
    /// The runtime's solver.
    type Linear: LinearSolver<Vector = SVector<f64, N>>;
    /// A solver's workspace for the Jacobians of `stepper`.
    fn solver(stepper: &text::Stepper) -> Self::Linear;
    /// Runs a residual-with-Jacobian kernel through `kernel(out)`, which writes the residual and
    /// then the Jacobian (column by column, or the values of `stepper`'s pattern) at `out`.
    fn residual_jacobian(
        stepper: &text::Stepper,
        kernel: impl FnOnce(*mut f64),
    ) -> (SVector<f64, N>, <Self::Linear as LinearSolver>::Matrix);
}

mod sealed {
    pub trait Sealed {}
    impl Sealed for super::Dense {}
    impl Sealed for super::Sparse {}
    impl<const M: usize, const Z: usize, B> Sealed for super::WithConstraints<M, Z, B> {}
}

/// The dense fixed-size backend ([`Lu`]): systems of at most 16 coordinates.
#[derive(Clone, Copy, Debug)]
pub struct Dense;

/// The sparse backend ([`PatternLu`] on the structural nonzeros of the step Jacobian, the
/// factorization of the attribute's sparse backend): systems of more than 16 coordinates.
#[derive(Clone, Copy, Debug)]
pub struct Sparse;

impl<const N: usize> Backend<N> for Dense {
    const SPARSE: bool = false;
    type Linear = Lu<N>;

    fn solver(_: &text::Stepper) -> Lu<N> {
        Lu::empty()
    }

    fn residual_jacobian(
        _: &text::Stepper,
        kernel: impl FnOnce(*mut f64),
    ) -> (SVector<f64, N>, SMatrix<f64, N, N>) {
        let mut rj = ResidualJacobian {
            r: SVector::<f64, N>::zeros(),
            j: SMatrix::<f64, N, N>::zeros(),
        };
        kernel((&mut rj as *mut ResidualJacobian<N>).cast::<f64>());
        (rj.r, rj.j)
    }
}

impl<const N: usize> Backend<N> for Sparse {
    const SPARSE: bool = true;
    type Linear = PatternLu<N>;

    fn solver(stepper: &text::Stepper) -> PatternLu<N> {
        let pattern = stepper.pattern.as_ref().expect(
            "a system on the sparse backend has sparse steppers (checked on instantiation)",
        );
        PatternLu::new(&pattern.col_ptr, &pattern.row_idx)
            .expect("the compiler emits a valid pattern of the stepper's size")
    }

    fn residual_jacobian(
        stepper: &text::Stepper,
        kernel: impl FnOnce(*mut f64),
    ) -> (SVector<f64, N>, CscBuffer) {
        let nnz = stepper
            .pattern
            .as_ref()
            .expect("a system on the sparse backend has sparse steppers (checked on instantiation)")
            .row_idx
            .len();
        let mut out = CscBuffer::zeroed(N + nnz, N);
        kernel(out.as_mut_slice().as_mut_ptr());
        (SVector::from_column_slice(out.leading()), out)
    }
}

/// The kind of a system with `M` constraints whose constrained solves, `Z = N + M` unknowns
/// each, run on backend `B` ([`Dense`] up to 16 unknowns, [`Sparse`] above): a
/// [`JitConstrained`](super::JitConstrained) is `Constraints` and `Constrained` for the unreduced and both reduced forms
/// of the step.
#[derive(Clone, Copy, Debug)]
pub struct WithConstraints<const M: usize, const Z: usize, B = Dense>(PhantomData<B>);

impl<const N: usize, const M: usize, const Z: usize, B: Backend<Z>> Variant<N>
    for WithConstraints<M, Z, B>
{
    fn check(sys: &System) -> Result<(), Error> {
        let m = sys.constrained.as_ref().map_or(0, |c| c.m);
        if m == 0 || m != M || Z != N + M {
            return Err(Error::Constraints {
                name: sys.name.clone(),
                m,
                n: N,
                want_m: M,
                want_z: Z,
            });
        }
        let c = sys.constrained.as_ref().expect("checked above");
        let steppers: Vec<&text::Stepper> = [&c.unreduced, &c.plus, &c.minus]
            .iter()
            .flat_map(|steps| [&steps.position, &steps.projection])
            .collect();
        check_backend(sys, &steppers, (Z, true), B::SPARSE)
    }
}

/// The residual and the Jacobian, as one kernel writes them.
#[repr(C)]
pub(super) struct ResidualJacobian<const N: usize> {
    pub(super) r: SVector<f64, N>,
    pub(super) j: SMatrix<f64, N, N>,
}
