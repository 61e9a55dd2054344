//! LU factorization with partial pivoting for fixed-size matrices, and the conditioning figures
//! a step is checked with.
//!
//! The factors live in plain row-major arrays `[[f64; N]; N]`: every loop runs over a constant
//! `N`, so LLVM unrolls it completely and keeps the matrix in registers, without the bounds
//! checks and strided column-major indexing of a generic nalgebra matrix (nalgebra's own `lu()`
//! needs `DimMin` bounds that a generic `Const<N>` cannot satisfy in generic code). The
//! arithmetic is the textbook order (Doolittle, row `r` updated by `a[r][c] / pivot`), so the
//! results are those of the straightforward loops.

// Triangular index loops over a constant `N` read as the textbook algorithm and unroll fully;
// iterator chains over the same index ranges would say less.
#![allow(clippy::needless_range_loop)]

use nalgebra::{SMatrix, SVector};

use super::{hager_inverse_norm1, reciprocal_condition, FactorError, LinearSolver};

/// `P A = L U`, with `L` unit lower triangular and `U` upper triangular stored together.
#[derive(Clone, Copy, Debug)]
pub struct Lu<const N: usize> {
    /// Row `i` of `L` (strictly below the diagonal) and of `U`, in pivoted order.
    lu: [[f64; N]; N],
    /// Row `i` of `P A` is row `perm[i]` of `A`.
    perm: [usize; N],
    /// `‖A‖₁`, kept for the condition figures.
    norm1: f64,
}

/// `‖A‖₁`, the largest absolute column sum.
pub fn norm1<const N: usize>(a: &SMatrix<f64, N, N>) -> f64 {
    a.column_iter()
        .map(|c| c.iter().map(|v| v.abs()).sum::<f64>())
        .fold(0.0, f64::max)
}

/// Step `c` of the elimination with partial pivoting: picks the largest pivot in column `c`,
/// swaps it into row `c` and eliminates below it. `C` is `c` when known at compile time (the
/// unrolled path) and 0 otherwise; `c ≥ N` is a no-op. `false` for an exactly zero pivot.
#[inline(always)]
fn eliminate_column<const N: usize, const C: usize>(
    lu: &mut [[f64; N]; N],
    perm: &mut [usize; N],
    c: usize,
) -> bool {
    let c = if C > 0 { C } else { c };
    if c >= N {
        return true;
    }
    let (mut best, mut best_abs) = (c, lu[c][c].abs());
    for (r, row) in lu.iter().enumerate().skip(c + 1) {
        let v = row[c].abs();
        if v > best_abs {
            best = r;
            best_abs = v;
        }
    }
    if best_abs == 0.0 {
        return false;
    }
    // The row swap as selects on rows of constant index, so the matrix stays in registers: a
    // swap at a run-time index would force it to memory.
    for r in c + 1..N {
        let take = r == best;
        for j in 0..N {
            let (top, other) = (lu[c][j], lu[r][j]);
            lu[c][j] = if take { other } else { top };
            lu[r][j] = if take { top } else { other };
        }
        let (top, other) = (perm[c], perm[r]);
        perm[c] = if take { other } else { top };
        perm[r] = if take { top } else { other };
    }
    let pivot_row = lu[c];
    let pivot = pivot_row[c];
    for row in lu.iter_mut().skip(c + 1) {
        let factor = row[c] / pivot;
        row[c] = factor;
        for j in c + 1..N {
            row[j] -= factor * pivot_row[j];
        }
    }
    true
}

impl<const N: usize> Lu<N> {
    /// Factors of nothing yet: a workspace for [`crate::linalg::LinearSolver::factor`] (the
    /// identity's factors, so every method is defined).
    pub fn empty() -> Self {
        let mut lu = [[0.0; N]; N];
        let mut perm = [0usize; N];
        for i in 0..N {
            lu[i][i] = 1.0;
            perm[i] = i;
        }
        Self {
            lu,
            perm,
            norm1: if N == 0 { 0.0 } else { 1.0 },
        }
    }

    /// Factors `a`; `None` when an entry is not finite or a pivot is exactly zero.
    pub fn new(a: SMatrix<f64, N, N>) -> Option<Self> {
        Self::factor(&a).ok()
    }

    /// Factors `a`, saying why it cannot.
    #[inline(always)]
    pub fn factor(a: &SMatrix<f64, N, N>) -> Result<Self, FactorError> {
        // Column sums of |a|: ‖A‖₁, and a finiteness test of every entry for free (a sum is
        // finite iff all its terms are; NaN propagates through `+` but not through `max`, so
        // the sums are tested, not their maximum).
        let mut norm1 = 0.0f64;
        let mut finite = true;
        let mut lu = [[0.0; N]; N];
        for c in 0..N {
            let mut sum = 0.0;
            for r in 0..N {
                let v = a[(r, c)];
                lu[r][c] = v;
                sum += v.abs();
            }
            finite &= sum.is_finite();
            norm1 = norm1.max(sum);
        }
        if !finite {
            return Err(FactorError::NonFinite);
        }
        let mut perm = [0usize; N];
        for i in 0..N {
            perm[i] = i;
        }
        // The columns one by one, each a separate instance with the column a constant, so that
        // every loop has a constant trip count and unrolls (LLVM does not unroll the triangular
        // loop nest by itself); beyond eight columns a plain loop.
        let regular = if N <= 8 {
            eliminate_column::<N, 0>(&mut lu, &mut perm, 0)
                && eliminate_column::<N, 1>(&mut lu, &mut perm, 1)
                && eliminate_column::<N, 2>(&mut lu, &mut perm, 2)
                && eliminate_column::<N, 3>(&mut lu, &mut perm, 3)
                && eliminate_column::<N, 4>(&mut lu, &mut perm, 4)
                && eliminate_column::<N, 5>(&mut lu, &mut perm, 5)
                && eliminate_column::<N, 6>(&mut lu, &mut perm, 6)
                && eliminate_column::<N, 7>(&mut lu, &mut perm, 7)
        } else {
            (0..N).all(|c| eliminate_column::<N, 0>(&mut lu, &mut perm, c))
        };
        if !regular {
            return Err(FactorError::Singular);
        }
        // Elimination of finite entries by nonzero pivots can still overflow: the factors are
        // then useless, as for an exactly singular matrix.
        let mut sum = 0.0;
        for row in &lu {
            for v in row {
                sum += v * 0.0;
            }
        }
        if sum != 0.0 {
            return Err(FactorError::Singular);
        }
        Ok(Self { lu, perm, norm1 })
    }

    /// Solves `A x = b`.
    #[inline(always)]
    pub fn solve(&self, b: &SVector<f64, N>) -> SVector<f64, N> {
        let lu = &self.lu;
        let mut x = [0.0; N];
        for i in 0..N {
            let mut s = b[self.perm[i]];
            for j in 0..i {
                s -= lu[i][j] * x[j];
            }
            x[i] = s;
        }
        for i in (0..N).rev() {
            let mut s = x[i];
            for j in i + 1..N {
                s -= lu[i][j] * x[j];
            }
            x[i] = s / lu[i][i];
        }
        SVector::from(x)
    }

    /// `‖A‖₁` of the factored matrix.
    pub fn norm1(&self) -> f64 {
        self.norm1
    }

    /// Solves `Aᵀ x = b`: `Uᵀ Lᵀ (P x) = b`.
    pub fn solve_transpose(&self, b: &SVector<f64, N>) -> SVector<f64, N> {
        let lu = &self.lu;
        let mut y = [0.0; N];
        for i in 0..N {
            let mut s = b[i];
            for j in 0..i {
                s -= lu[j][i] * y[j];
            }
            y[i] = s / lu[i][i];
        }
        for i in (0..N).rev() {
            let mut s = y[i];
            for j in i + 1..N {
                s -= lu[j][i] * y[j];
            }
            y[i] = s;
        }
        let mut x = SVector::<f64, N>::zeros();
        for (i, &p) in self.perm.iter().enumerate() {
            x[p] = y[i];
        }
        x
    }

    /// An upper bound on `‖A⁻¹‖₁`, from two triangular solves with the comparison matrices of
    /// the factors (Higham, *Accuracy and Stability of Numerical Algorithms*, Thm. 8.12: for
    /// triangular `T`, `|T⁻¹| ≤ M(T)⁻¹`, where `M(T)` has `|t_ii|` on the diagonal and `−|t_ij|`
    /// off it, and `M(T)⁻¹ ≥ 0`). With `A = Pᵀ L U`, `‖A⁻¹‖₁ ≤ ‖M(U)⁻¹‖₁ ‖M(L)⁻¹‖₁`, and the
    /// 1-norm of a nonnegative inverse is the largest entry of `M(T)⁻ᵀ e`. Partial pivoting keeps
    /// `|l_ij| ≤ 1`; for the Jacobians of healthy steps the bound is within a small factor of
    /// the true norm, at the cost of one solve.
    pub fn inverse_norm1_bound(&self) -> f64 {
        let lu = &self.lu;
        // M(U)ᵀ y = e, forward.
        let mut y = [0.0; N];
        let mut u_max = 0.0f64;
        for i in 0..N {
            let mut s = 1.0;
            for j in 0..i {
                s += lu[j][i].abs() * y[j];
            }
            y[i] = s / lu[i][i].abs();
            u_max = u_max.max(y[i]);
        }
        // M(L)ᵀ y = e, backward (unit diagonal).
        let mut l_max = 0.0f64;
        for i in (0..N).rev() {
            let mut s = 1.0;
            for j in i + 1..N {
                s += lu[j][i].abs() * y[j];
            }
            y[i] = s;
            l_max = l_max.max(s);
        }
        u_max * l_max
    }

    /// A guaranteed lower bound on the reciprocal condition number `1 / (‖A‖₁ ‖A⁻¹‖₁)` (up to
    /// the round-off of its own evaluation, a relative `O(N ε)`): see
    /// [`Self::inverse_norm1_bound`]. Cheap, so a step can be checked with it every time and
    /// call the estimator [`Self::rcond`] only when the bound does not clear the threshold.
    pub fn rcond_lower_bound(&self) -> f64 {
        reciprocal_condition(self.norm1, self.inverse_norm1_bound())
    }

    /// Estimate of the reciprocal condition number `1 / (‖A‖₁ ‖A⁻¹‖₁)`, with `‖A⁻¹‖₁` from
    /// Hager's estimator (Higham, *Accuracy and Stability of Numerical Algorithms*, Alg. 15.1):
    /// a handful of solves with `A` and `Aᵀ`, a lower bound on `‖A⁻¹‖₁` that is almost always
    /// within a small factor of it. Near 1 is well conditioned; near machine epsilon (≈ 1e-16) the
    /// solve has no correct digits.
    pub fn rcond(&self) -> f64 {
        reciprocal_condition(
            self.norm1,
            hager_inverse_norm1::<N>(|x, transpose| {
                *x = if transpose {
                    self.solve_transpose(x)
                } else {
                    self.solve(x)
                }
            }),
        )
    }
}

impl<const N: usize> LinearSolver for Lu<N> {
    type Vector = SVector<f64, N>;
    type Matrix = SMatrix<f64, N, N>;
    #[inline]
    fn factor(&mut self, j: &Self::Matrix) -> Result<(), FactorError> {
        *self = Lu::factor(j)?;
        Ok(())
    }
    #[inline]
    fn solve(&mut self, b: &Self::Vector) -> Self::Vector {
        Lu::solve(self, b)
    }
    fn norm1(&self) -> f64 {
        Lu::norm1(self)
    }
    fn rcond_lower_bound(&mut self) -> f64 {
        Lu::rcond_lower_bound(self)
    }
    fn rcond(&mut self) -> f64 {
        Lu::rcond(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Matrix3, Vector3};

    #[test]
    fn solves_a_system_that_needs_pivoting() {
        let a = Matrix3::new(0.0, 2.0, 1.0, 1.0, 1.0, 1.0, 4.0, -1.0, 3.0);
        let x = Vector3::new(1.0, -2.0, 0.5);
        let b = a * x;
        let solved = Lu::new(a).unwrap().solve(&b);
        assert!((solved - x).amax() < 1e-14, "{solved}");
    }

    #[test]
    fn transpose_solve() {
        let a = Matrix3::new(0.0, 2.0, 1.0, 1.0, 1.0, 1.0, 4.0, -1.0, 3.0);
        let x = Vector3::new(0.3, 1.0, -2.0);
        let solved = Lu::new(a).unwrap().solve_transpose(&(a.transpose() * x));
        assert!((solved - x).amax() < 1e-14, "{solved}");
    }

    #[test]
    fn condition_estimate_matches_the_exact_value_on_small_matrices() {
        // Exact κ₁ = ‖A‖₁ ‖A⁻¹‖₁ from the explicit inverse; Hager's estimate is a lower bound on
        // ‖A⁻¹‖₁, so rcond_est ≥ rcond_exact, and on these matrices it is exact.
        let cases = [
            Matrix3::new(0.0, 2.0, 1.0, 1.0, 1.0, 1.0, 4.0, -1.0, 3.0),
            Matrix3::new(1.0, 1.0, 1.0, 1.0, 1.0 + 1e-9, 1.0, 0.0, 0.0, 1.0),
            Matrix3::new(1e6, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1e-6),
        ];
        for a in cases {
            let inv = a.try_inverse().unwrap();
            let exact = 1.0 / (norm1(&a) * norm1(&inv));
            let est = Lu::new(a).unwrap().rcond();
            assert!(
                est >= exact * (1.0 - 1e-6) && est <= 3.0 * exact,
                "{est:e} vs {exact:e}"
            );
        }
    }

    #[test]
    fn the_cheap_bound_is_a_lower_bound_on_the_exact_rcond() {
        // Exact κ₁ from the explicit inverse; the comparison-matrix bound must never exceed the
        // exact reciprocal, on well and badly conditioned matrices, with and without pivoting;
        // and on these it stays within a factor 10 of it.
        let cases = [
            Matrix3::new(0.0, 2.0, 1.0, 1.0, 1.0, 1.0, 4.0, -1.0, 3.0),
            Matrix3::new(1.0, 1.0, 1.0, 1.0, 1.0 + 1e-9, 1.0, 0.0, 0.0, 1.0),
            Matrix3::new(1e6, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1e-6),
            Matrix3::new(2.0, -1.0, 0.0, -1.0, 2.0, -1.0, 0.0, -1.0, 2.0),
        ];
        for a in cases {
            let inv = a.try_inverse().unwrap();
            let exact = 1.0 / (norm1(&a) * norm1(&inv));
            let bound = Lu::new(a).unwrap().rcond_lower_bound();
            assert!(
                bound <= exact * (1.0 + 1e-12) && bound >= exact / 10.0,
                "{bound:e} vs {exact:e}"
            );
        }
    }

    #[test]
    fn non_finite_entries_and_zero_pivots_are_told_apart() {
        let mut a = Matrix3::identity();
        a[(1, 2)] = f64::NAN;
        assert_eq!(Lu::factor(&a).unwrap_err(), FactorError::NonFinite);
        a[(1, 2)] = f64::INFINITY;
        assert_eq!(Lu::factor(&a).unwrap_err(), FactorError::NonFinite);
        let singular = Matrix3::new(1.0, 2.0, 3.0, 2.0, 4.0, 6.0, 0.0, 1.0, 1.0);
        assert_eq!(Lu::factor(&singular).unwrap_err(), FactorError::Singular);
    }

    #[test]
    fn rejects_a_singular_matrix() {
        let a = Matrix3::new(1.0, 2.0, 3.0, 2.0, 4.0, 6.0, 0.0, 1.0, 1.0);
        assert!(Lu::new(a).is_none());
    }
}
