//! [`DynPatternLu`]: the sparse backend's factorization ([`Factors`]) at a size chosen at run
//! time, on `DVector`s, and below [`crate::DENSE_MAX`] a dense LU with partial pivoting in memory
//! allocated once ([`DenseFactors`]).

use super::{CscBuffer, Factors};
use crate::linalg::{column_norm1, reciprocal_condition, FactorError, HagerCache, LinearSolver};

/// [`PatternLu`](super::PatternLu)'s factorization at a size chosen at run time, on `DVector`s:
/// the backend of a system on rotation groups given as text at any size, whose kernels write the
/// residual and the Jacobian's values into one [`CscBuffer`]. On the pattern the compiler emits
/// for a system of more than [`crate::DENSE_MAX`] chart coordinates, the same factorization
/// (ordering, pivots, bound) as the compiled-in [`SparseLu`](super::SparseLu), so the same steps;
/// below it a dense LU with partial pivoting ([`Self::dense`]) of the dense kernels' Jacobian,
/// column by column, as the dense [`crate::Lu`] factors it. Solves are in place, the factors in
/// memory allocated when the workspace is built: a Newton step allocates nothing.
pub struct DynPatternLu {
    factors: Backend,
    /// Whether a dense backend's factors serve later corrections and steps (chord iterations,
    /// [`Self::dense_reused`]); the sparse backend's always do.
    reuse_dense: bool,
}

/// The factorization of a [`DynPatternLu`].
enum Backend {
    /// On the compiler's sparsity pattern.
    Sparse(Box<Factors>),
    /// Dense.
    Dense(Box<DenseFactors>),
}

impl std::fmt::Debug for DynPatternLu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.factors {
            Backend::Sparse(factors) => f
                .debug_struct("DynPatternLu")
                .field("n", &factors.n)
                .field("nnz", &factors.pattern.row_idx().len())
                .field("factored", &factors.factored)
                .finish_non_exhaustive(),
            Backend::Dense(factors) => f
                .debug_struct("DynPatternLu")
                .field("n", &factors.n)
                .field("dense", &true)
                .field("factored", &factors.factored)
                .finish_non_exhaustive(),
        }
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
            factors: Backend::Sparse(Box::new(Factors::new(n, col_ptr, row_idx))),
            reuse_dense: false,
        })
    }

    /// The workspace for dense `n × n` Jacobians, stored column by column.
    pub fn dense(n: usize) -> Self {
        Self {
            factors: Backend::Dense(Box::new(DenseFactors::new(n))),
            reuse_dense: false,
        }
    }

    /// [`Self::dense`] whose factors, once a factorization succeeded, later corrections and
    /// steps reuse (chord iterations, [`crate::newton::solve_with`]): for Jacobians whose
    /// factorization (`n³/3` flops) costs several residual evaluations, as the `sN × sN` stage
    /// Jacobian of a Gauss–Legendre step does once `sN` passes a dozen unknowns.
    pub fn dense_reused(n: usize) -> Self {
        Self {
            reuse_dense: true,
            ..Self::dense(n)
        }
    }

    /// Number of rows and columns.
    pub fn n(&self) -> usize {
        match &self.factors {
            Backend::Sparse(factors) => factors.n,
            Backend::Dense(factors) => factors.n,
        }
    }
}

impl LinearSolver for DynPatternLu {
    type Vector = nalgebra::DVector<f64>;
    type Matrix = CscBuffer;

    fn factor(&mut self, j: &CscBuffer) -> Result<(), FactorError> {
        match &mut self.factors {
            Backend::Sparse(factors) => factors.factor(j.values()),
            Backend::Dense(factors) => factors.factor(j.values()),
        }
    }

    fn solve(&mut self, b: &nalgebra::DVector<f64>) -> nalgebra::DVector<f64> {
        let mut x = b.clone();
        self.solve_in_place(&mut x);
        x
    }

    fn solve_in_place(&mut self, b: &mut nalgebra::DVector<f64>) {
        match &mut self.factors {
            Backend::Sparse(factors) => factors.solve_in_place(b.as_mut_slice(), false),
            Backend::Dense(factors) => factors.solve_in_place(b.as_mut_slice(), false),
        }
    }

    fn norm1(&self) -> f64 {
        match &self.factors {
            Backend::Sparse(factors) => factors.norm1,
            Backend::Dense(factors) => factors.norm1,
        }
    }

    fn rcond_lower_bound(&mut self) -> f64 {
        match &mut self.factors {
            Backend::Sparse(factors) => factors.rcond_lower_bound(),
            Backend::Dense(factors) => factors.rcond_lower_bound(),
        }
    }

    fn rcond(&mut self) -> f64 {
        match &mut self.factors {
            Backend::Sparse(factors) => factors.rcond(),
            Backend::Dense(factors) => {
                let norm1 = factors.factored.then_some(factors.norm1);
                HagerCache::rcond(
                    &mut **factors,
                    |f| &mut f.hager,
                    norm1,
                    DenseFactors::solve_in_place,
                )
            }
        }
    }

    /// On the compiler's sparse pattern as [`PatternLu`](super::PatternLu), yes once a
    /// factorization succeeded (chord iterations); dense only when built by
    /// [`Self::dense_reused`] — otherwise never, as the dense [`crate::Lu`], where a
    /// factorization costs less than a residual.
    fn has_reusable_factors(&self) -> bool {
        match &self.factors {
            Backend::Sparse(factors) => factors.factored,
            Backend::Dense(factors) => self.reuse_dense && factors.factored,
        }
    }
}

/// A dense LU with partial pivoting, `P A = L U` (`L` unit lower triangular), of an `n × n`
/// matrix given column by column, in memory allocated when it is built (Golub & Van Loan,
/// Alg. 3.4.1): the factors overwrite a copy of the matrix, the row interchanges are recorded
/// in the order they were made.
struct DenseFactors {
    n: usize,
    /// `L` below the diagonal, `U` on and above it, column by column.
    lu: Vec<f64>,
    /// Row `k` was interchanged with row `swaps[k] ≥ k` at step `k`.
    swaps: Vec<usize>,
    /// The conditioning bound's vector.
    work: Vec<f64>,
    /// The full pattern's column starts (for the 1-norm).
    col_ptr: Vec<usize>,
    norm1: f64,
    factored: bool,
    /// The conditioning bound of the current factors, once computed.
    bound: Option<f64>,
    hager: HagerCache,
}

impl DenseFactors {
    fn new(n: usize) -> Self {
        Self {
            n,
            lu: vec![0.0; n * n],
            swaps: vec![0; n],
            work: vec![0.0; n],
            col_ptr: (0..=n).map(|j| j * n).collect(),
            norm1: 0.0,
            factored: false,
            bound: None,
            hager: HagerCache::new(n),
        }
    }

    fn factor(&mut self, values: &[f64]) -> Result<(), FactorError> {
        let n = self.n;
        self.bound = None;
        self.norm1 = self
            .hager
            .refactor(&mut self.factored, &self.col_ptr, values)?;
        debug_assert_eq!(column_norm1(&self.col_ptr, values), Ok(self.norm1));
        let a = &mut self.lu;
        a.copy_from_slice(values);
        for k in 0..n {
            let (mut p, mut largest) = (k, a[k + k * n].abs());
            for i in k + 1..n {
                let v = a[i + k * n].abs();
                if v > largest {
                    (p, largest) = (i, v);
                }
            }
            if largest == 0.0 || !largest.is_finite() {
                return Err(FactorError::Singular);
            }
            self.swaps[k] = p;
            if p != k {
                for j in 0..n {
                    a.swap(k + j * n, p + j * n);
                }
            }
            let pivot = a[k + k * n];
            for i in k + 1..n {
                a[i + k * n] /= pivot;
            }
            for j in k + 1..n {
                let f = a[k + j * n];
                if f != 0.0 {
                    for i in k + 1..n {
                        a[i + j * n] -= a[i + k * n] * f;
                    }
                }
            }
        }
        self.factored = true;
        Ok(())
    }

    /// Overwrites `x` with `A⁻¹ x` (`transpose`: `A⁻ᵀ x`).
    fn solve_in_place(&mut self, x: &mut [f64], transpose: bool) {
        debug_assert!(self.factored, "solve before factor");
        let (n, a) = (self.n, &self.lu);
        if transpose {
            // Aᵀ = Uᵀ Lᵀ P: Uᵀ forward, Lᵀ backward, then the interchanges in reverse.
            for j in 0..n {
                let mut s = x[j];
                for i in 0..j {
                    s -= a[i + j * n] * x[i];
                }
                x[j] = s / a[j + j * n];
            }
            for j in (0..n).rev() {
                let mut s = x[j];
                for i in j + 1..n {
                    s -= a[i + j * n] * x[i];
                }
                x[j] = s;
            }
            for k in (0..n).rev() {
                x.swap(k, self.swaps[k]);
            }
            return;
        }
        for k in 0..n {
            x.swap(k, self.swaps[k]);
        }
        for j in 0..n {
            let xj = x[j];
            if xj != 0.0 {
                for i in j + 1..n {
                    x[i] -= a[i + j * n] * xj;
                }
            }
        }
        for j in (0..n).rev() {
            x[j] /= a[j + j * n];
            let xj = x[j];
            if xj != 0.0 {
                for i in 0..j {
                    x[i] -= a[i + j * n] * xj;
                }
            }
        }
    }

    /// `1 / (‖A‖₁ ‖M(U)⁻¹‖₁ ‖M(L)⁻¹‖₁)`, a guaranteed lower bound on the reciprocal condition
    /// number (the comparison-matrix bound of [`crate::Lu::inverse_norm1_bound`], Higham,
    /// Thm. 8.12), from one pass over the factors; 0 before a factorization.
    fn rcond_lower_bound(&mut self) -> f64 {
        if !self.factored {
            return 0.0;
        }
        if let Some(bound) = self.bound {
            return bound;
        }
        let (n, a, y) = (self.n, &self.lu, &mut self.work);
        // M(U)ᵀ y = e, forward.
        let mut u_max = 0.0f64;
        for j in 0..n {
            let mut s = 1.0;
            for i in 0..j {
                s += a[i + j * n].abs() * y[i];
            }
            y[j] = s / a[j + j * n].abs();
            u_max = u_max.max(y[j]);
        }
        // M(L)ᵀ y = e, backward (unit diagonal).
        let mut l_max = 0.0f64;
        for j in (0..n).rev() {
            let mut s = 1.0;
            for i in j + 1..n {
                s += a[i + j * n].abs() * y[i];
            }
            y[j] = s;
            l_max = l_max.max(s);
        }
        let bound = reciprocal_condition(self.norm1, u_max * l_max);
        self.bound = Some(bound);
        bound
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{DMatrix, DVector};

    /// The dense factorization solves `A x = b` and `Aᵀ x = b` of a matrix that must pivot, its
    /// bound lies below the exact reciprocal condition number, and a singular matrix is refused.
    #[test]
    fn the_dense_factors_solve_and_bound_as_the_dense_lu() {
        let n = 5;
        let a = DMatrix::from_fn(n, n, |i, j| {
            let v = ((3 * i + 7 * j) % 11) as f64 / 5.0 - 1.0;
            if i == j {
                1e-3 * v
            } else {
                v
            }
        });
        let mut buffer = CscBuffer::zeroed(n + n * n, n);
        buffer.as_mut_slice()[n..].copy_from_slice(a.as_slice());
        let mut lu = DynPatternLu::dense(n);
        lu.factor(&buffer).unwrap();
        let x = DVector::from_fn(n, |i, _| (i as f64 + 0.5).cos());
        let solved = lu.solve(&(&a * &x));
        assert!((solved - &x).amax() < 1e-10);
        let Backend::Dense(factors) = &mut lu.factors else {
            unreachable!("dense")
        };
        let mut t = (a.transpose() * &x).as_slice().to_vec();
        factors.solve_in_place(&mut t, true);
        assert!((DVector::from_vec(t) - &x).amax() < 1e-10);
        let inv = a.clone().try_inverse().unwrap();
        let n1 = |m: &DMatrix<f64>| {
            m.column_iter()
                .map(|c| c.iter().map(|v| v.abs()).sum::<f64>())
                .fold(0.0, f64::max)
        };
        let exact = 1.0 / (n1(&a) * n1(&inv));
        let bound = lu.rcond_lower_bound();
        assert!(
            bound > 0.0 && bound <= exact * (1.0 + 1e-9),
            "{bound:e} vs {exact:e}"
        );
        assert!(lu.rcond() >= bound * (1.0 - 1e-9));
        let mut singular = CscBuffer::zeroed(n + n * n, n);
        singular.as_mut_slice()[n..n + n].fill(1.0);
        assert_eq!(lu.factor(&singular), Err(FactorError::Singular));
        let mut broken = buffer;
        broken.as_mut_slice()[n + 2] = f64::NAN;
        assert_eq!(lu.factor(&broken), Err(FactorError::NonFinite));
    }
}
