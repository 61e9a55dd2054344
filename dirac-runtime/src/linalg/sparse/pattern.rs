//! [`DynPatternLu`]: the sparse backend's factorization ([`Factors`]) at a size chosen at run
//! time, on `DVector`s.

use super::{CscBuffer, Factors};
use crate::linalg::{FactorError, LinearSolver};

/// [`PatternLu`](super::PatternLu)'s factorization at a size chosen at run time, on `DVector`s: the backend of a
/// system on rotation groups given as text at any size, whose kernels write the residual and the
/// Jacobian's values into one [`CscBuffer`]. On the pattern the compiler emits for a system of
/// more than [`crate::DENSE_MAX`] chart coordinates, the same factorization (ordering, pivots,
/// bound) as the compiled-in [`SparseLu`](super::SparseLu), so the same steps; below it on the full pattern
/// ([`Self::dense`]), whose values are the dense kernels' Jacobian column by column. Solves are
/// in place: a Newton step allocates nothing.
pub struct DynPatternLu {
    factors: Factors,
    /// Whether a step first tries the factors of an earlier one: on a sparse pattern, as
    /// [`PatternLu`](super::PatternLu); not on the full pattern, as the dense [`crate::Lu`], where a
    /// factorization costs less than a residual.
    chord: bool,
}

impl std::fmt::Debug for DynPatternLu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DynPatternLu")
            .field("n", &self.factors.n)
            .field("nnz", &self.factors.pattern.row_idx().len())
            .field("factored", &self.factors.factored)
            .finish_non_exhaustive()
    }
}

impl DynPatternLu {
    /// The workspace for `n × n` Jacobians whose column `j` has the sorted, distinct rows
    /// `row_idx[col_ptr[j]..col_ptr[j + 1]]`, or `None` if the arrays do not describe one.
    pub fn new(n: usize, col_ptr: &[usize], row_idx: &[usize]) -> Option<Self> {
        let valid = col_ptr.len() == n + 1
            && col_ptr[0] == 0
            && col_ptr[n] == row_idx.len()
            && col_ptr.windows(2).all(|w| w[0] <= w[1])
            && (0..n).all(|j| {
                let rows = &row_idx[col_ptr[j]..col_ptr[j + 1]];
                rows.iter().all(|&r| r < n) && rows.windows(2).all(|w| w[0] < w[1])
            });
        valid.then(|| Self {
            factors: Factors::new(n, col_ptr, row_idx),
            chord: true,
        })
    }

    /// The workspace for dense `n × n` Jacobians, stored column by column (the full pattern).
    pub fn dense(n: usize) -> Self {
        let col_ptr: Vec<usize> = (0..=n).map(|j| j * n).collect();
        let row_idx: Vec<usize> = (0..n * n).map(|k| k % n).collect();
        Self {
            factors: Factors::new(n, &col_ptr, &row_idx),
            chord: false,
        }
    }

    /// Number of rows and columns.
    pub fn n(&self) -> usize {
        self.factors.n
    }
}

impl LinearSolver for DynPatternLu {
    type Vector = nalgebra::DVector<f64>;
    type Matrix = CscBuffer;

    fn factor(&mut self, j: &CscBuffer) -> Result<(), FactorError> {
        self.factors.factor(j.values())
    }

    fn solve(&mut self, b: &nalgebra::DVector<f64>) -> nalgebra::DVector<f64> {
        let mut x = b.clone();
        self.factors.solve_in_place(x.as_mut_slice(), false);
        x
    }

    fn solve_in_place(&mut self, b: &mut nalgebra::DVector<f64>) {
        self.factors.solve_in_place(b.as_mut_slice(), false);
    }

    fn norm1(&self) -> f64 {
        self.factors.norm1
    }

    fn rcond_lower_bound(&mut self) -> f64 {
        self.factors.rcond_lower_bound()
    }

    fn rcond(&mut self) -> f64 {
        self.factors.rcond()
    }

    /// On a sparse pattern as [`PatternLu`](super::PatternLu), yes once a factorization succeeded (chord
    /// iterations); on the full pattern never, as the dense [`crate::Lu`].
    fn has_reusable_factors(&self) -> bool {
        self.chord && self.factors.factored
    }
}
