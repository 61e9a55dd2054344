//! The step Jacobian's solver of an element-wise run, chosen by the pattern's structure
//! ([`StepSolver`]): a banded LU when a reverse Cuthill–McKee ordering makes the pattern a narrow
//! band (chains, lattices, rings, arrays coupled element by element), conjugate gradients for
//! large multi-dimensional symmetric Jacobians, faer's sparse LU otherwise (pairs, small grids),
//! with the fallback from conjugate gradients to the LU.

use nalgebra::DVector;

use super::StepSolver;
use crate::linalg::{BandedLu, DynSparseLu, FactorError, LinearSolver, Pcg};

/// The smallest number of unknowns for which [`StepSolver::Auto`] solves a multi-dimensional
/// pattern (at least [`ITERATIVE_MIN_ENTRIES_PER_ROW`] entries per row, as a 2-D grid's 7) by
/// conjugate gradients. Measured on the membrane of `examples/wave2d.rs` at 316 × 316: the
/// sparse LU's first factorization takes ≈ 2 s and 0.6 GB of fill, its later steps ≈ 34 ms; see
/// BENCHMARKS.md for CG's figures. A lattice (3 entries per row) factors in linear time and
/// keeps the LU.
pub const ITERATIVE_MIN_DIM: usize = 20_000;

/// See [`ITERATIVE_MIN_DIM`].
pub const ITERATIVE_MIN_ENTRIES_PER_ROW: usize = 5;

/// The widest band (`k_l + k_u` after the reverse Cuthill–McKee ordering) that
/// [`StepSolver::Auto`] solves with the banded LU: a factorization costs about
/// `n k_l (k_l + k_u)` flops, below the sparse LU's symbolic bookkeeping for such bands and above
/// it for wider ones (a 2-D grid's band is its side).
pub const BANDED_MAX_WIDTH: usize = 16;

/// The step Jacobian's solver of an element-wise run ([`StepSolver`]): the sparse LU, or conjugate
/// gradients on a symmetric definite Jacobian, falling back to the LU for good when the
/// Jacobian turns out not to be symmetric or CG breaks down.
#[derive(Debug)]
#[doc(hidden)]
pub enum ElementSolver {
    /// The banded LU on a reverse Cuthill–McKee ordering.
    Banded(Box<BandedLu>),
    /// faer's sparse LU.
    Direct(Box<DynSparseLu>),
    /// Jacobi-preconditioned conjugate gradients, with the pattern to fall back on.
    Iterative(Box<Pcg>, Vec<usize>, Vec<usize>),
}

impl ElementSolver {
    pub(super) fn new(n: usize, col_ptr: &[usize], row_idx: &[usize], linear: StepSolver) -> Self {
        let iterative = match linear {
            StepSolver::Direct | StepSolver::Banded => false,
            StepSolver::Iterative => true,
            StepSolver::Auto => {
                n >= ITERATIVE_MIN_DIM && row_idx.len() >= ITERATIVE_MIN_ENTRIES_PER_ROW * n
            }
        };
        if let Some(cg) = iterative.then(|| Pcg::new(n, col_ptr, row_idx)).flatten() {
            return ElementSolver::Iterative(Box::new(cg), col_ptr.to_vec(), row_idx.to_vec());
        }
        let max_width = match linear {
            StepSolver::Auto => Some(BANDED_MAX_WIDTH),
            StepSolver::Banded => Some(usize::MAX),
            StepSolver::Direct | StepSolver::Iterative => None,
        };
        // A band too wide to store falls back to the sparse LU.
        if let Some(banded) = max_width.and_then(|w| BandedLu::within(n, col_ptr, row_idx, w)) {
            return ElementSolver::Banded(Box::new(banded));
        }
        ElementSolver::Direct(Box::new(DynSparseLu::new(
            n,
            col_ptr.to_vec(),
            row_idx.to_vec(),
        )))
    }

    /// The solver of a saddle-point (KKT) system of a constrained step: the banded LU when the
    /// reordered band is narrow ([`BANDED_MAX_WIDTH`]), the sparse LU otherwise (conjugate
    /// gradients do not apply to an indefinite system).
    pub(super) fn saddle(n: usize, col_ptr: &[usize], row_idx: &[usize]) -> Self {
        if let Some(banded) = BandedLu::within(n, col_ptr, row_idx, BANDED_MAX_WIDTH) {
            ElementSolver::Banded(Box::new(banded))
        } else {
            ElementSolver::Direct(Box::new(DynSparseLu::new(
                n,
                col_ptr.to_vec(),
                row_idx.to_vec(),
            )))
        }
    }

    /// Which solver this is: `"banded LU"`, `"sparse LU"` or `"conjugate gradients (Jacobi)"`.
    pub fn name(&self) -> &'static str {
        match self {
            ElementSolver::Banded(_) => "banded LU",
            ElementSolver::Direct(_) => "sparse LU",
            ElementSolver::Iterative(..) => "conjugate gradients (Jacobi)",
        }
    }
}

impl LinearSolver for ElementSolver {
    type Vector = DVector<f64>;
    type Matrix = Vec<f64>;
    fn factor(&mut self, j: &Vec<f64>) -> Result<(), FactorError> {
        match self {
            ElementSolver::Banded(lu) => lu.factor(j),
            ElementSolver::Direct(lu) => lu.factor(j),
            ElementSolver::Iterative(cg, col_ptr, row_idx) => match cg.factor(j) {
                Ok(()) => Ok(()),
                Err(FactorError::NonFinite) => Err(FactorError::NonFinite),
                // Not symmetric: the LU from now on (built once, here).
                Err(FactorError::Singular) => {
                    let n = col_ptr.len() - 1;
                    let mut lu =
                        DynSparseLu::new(n, std::mem::take(col_ptr), std::mem::take(row_idx));
                    let result = lu.factor(j);
                    *self = ElementSolver::Direct(Box::new(lu));
                    result
                }
            },
        }
    }
    fn solve(&mut self, b: &DVector<f64>) -> DVector<f64> {
        let mut x = b.clone();
        self.solve_in_place(&mut x);
        x
    }
    fn solve_in_place(&mut self, b: &mut DVector<f64>) {
        match self {
            ElementSolver::Banded(lu) => lu.solve_in_place(b),
            ElementSolver::Direct(lu) => lu.solve_in_place(b),
            ElementSolver::Iterative(cg, ..) => cg.solve_in_place(b),
        }
    }
    fn norm1(&self) -> f64 {
        match self {
            ElementSolver::Banded(lu) => lu.norm1(),
            ElementSolver::Direct(lu) => lu.norm1(),
            ElementSolver::Iterative(cg, ..) => cg.norm1(),
        }
    }
    fn rcond_lower_bound(&mut self) -> f64 {
        match self {
            ElementSolver::Banded(lu) => lu.rcond_lower_bound(),
            ElementSolver::Direct(lu) => lu.rcond_lower_bound(),
            ElementSolver::Iterative(cg, ..) => cg.rcond_lower_bound(),
        }
    }
    fn rcond(&mut self) -> f64 {
        match self {
            ElementSolver::Banded(lu) => lu.rcond(),
            ElementSolver::Direct(lu) => lu.rcond(),
            ElementSolver::Iterative(cg, ..) => cg.rcond(),
        }
    }
    fn has_reusable_factors(&self) -> bool {
        match self {
            ElementSolver::Banded(lu) => lu.has_reusable_factors(),
            ElementSolver::Direct(lu) => lu.has_reusable_factors(),
            ElementSolver::Iterative(cg, ..) => cg.has_reusable_factors(),
        }
    }
}
