//! LU factorization with partial pivoting for fixed-size matrices.
//!
//! nalgebra's own `lu()` needs `DimMin` bounds that a generic `Const<N>` cannot satisfy in
//! generic code, so the few lines are written out here: everything lives on the stack.

use nalgebra::{SMatrix, SVector};

/// `P A = L U`, with `L` unit lower triangular and `U` upper triangular stored together.
#[derive(Clone, Copy, Debug)]
pub struct Lu<const N: usize> {
    lu: SMatrix<f64, N, N>,
    perm: [usize; N],
    /// `‖A‖₁`, kept for the condition estimate.
    norm1: f64,
}

/// `‖A‖₁`, the largest absolute column sum.
pub fn norm1<const N: usize>(a: &SMatrix<f64, N, N>) -> f64 {
    a.column_iter()
        .map(|c| c.iter().map(|v| v.abs()).sum::<f64>())
        .fold(0.0, f64::max)
}

impl<const N: usize> Lu<N> {
    /// Factors `a`; `None` when a pivot is exactly zero or not finite.
    pub fn new(mut a: SMatrix<f64, N, N>) -> Option<Self> {
        let norm1 = norm1(&a);
        let mut perm = [0usize; N];
        for (i, p) in perm.iter_mut().enumerate() {
            *p = i;
        }
        for c in 0..N {
            let (mut best, mut best_abs) = (c, a[(c, c)].abs());
            for r in c + 1..N {
                let v = a[(r, c)].abs();
                if v > best_abs {
                    best = r;
                    best_abs = v;
                }
            }
            if best_abs == 0.0 || !best_abs.is_finite() {
                return None;
            }
            if best != c {
                a.swap_rows(best, c);
                perm.swap(best, c);
            }
            let pivot = a[(c, c)];
            for r in c + 1..N {
                let factor = a[(r, c)] / pivot;
                a[(r, c)] = factor;
                for j in c + 1..N {
                    a[(r, j)] -= factor * a[(c, j)];
                }
            }
        }
        Some(Self { lu: a, perm, norm1 })
    }

    /// Solves `A x = b`.
    pub fn solve(&self, b: &SVector<f64, N>) -> SVector<f64, N> {
        let mut x = SVector::<f64, N>::from_fn(|i, _| b[self.perm[i]]);
        for i in 0..N {
            for j in 0..i {
                x[i] -= self.lu[(i, j)] * x[j];
            }
        }
        for i in (0..N).rev() {
            for j in i + 1..N {
                x[i] -= self.lu[(i, j)] * x[j];
            }
            x[i] /= self.lu[(i, i)];
        }
        x
    }
}

impl<const N: usize> Lu<N> {
    /// `‖A‖₁` of the factored matrix.
    pub fn norm1(&self) -> f64 {
        self.norm1
    }

    /// Solves `Aᵀ x = b`: `Uᵀ Lᵀ (P x) = b`.
    pub fn solve_transpose(&self, b: &SVector<f64, N>) -> SVector<f64, N> {
        let mut y = *b;
        for i in 0..N {
            for j in 0..i {
                y[i] -= self.lu[(j, i)] * y[j];
            }
            y[i] /= self.lu[(i, i)];
        }
        for i in (0..N).rev() {
            for j in i + 1..N {
                y[i] -= self.lu[(j, i)] * y[j];
            }
        }
        let mut x = SVector::<f64, N>::zeros();
        for (i, &p) in self.perm.iter().enumerate() {
            x[p] = y[i];
        }
        x
    }

    /// Estimate of the reciprocal condition number `1 / (‖A‖₁ ‖A⁻¹‖₁)`, with `‖A⁻¹‖₁` from
    /// Hager's estimator (Higham, *Accuracy and Stability of Numerical Algorithms*, Alg. 15.1):
    /// a handful of solves with `A` and `Aᵀ`, a lower bound on `‖A⁻¹‖₁` that is almost always
    /// within a small factor of it. Near 1 is well conditioned; near machine epsilon (≈ 1e-16) the
    /// solve has no correct digits.
    pub fn rcond(&self) -> f64 {
        if self.norm1 == 0.0 {
            return 0.0;
        }
        let mut x = SVector::<f64, N>::repeat(1.0 / N as f64);
        let mut estimate = 0.0;
        for _ in 0..5 {
            let y = self.solve(&x);
            estimate = y.iter().map(|v| v.abs()).sum::<f64>();
            let xi = y.map(|v| if v >= 0.0 { 1.0 } else { -1.0 });
            let z = self.solve_transpose(&xi);
            let (j, zj) = z.iter().enumerate().fold((0, 0.0), |(bj, bv), (i, v)| {
                if v.abs() > bv {
                    (i, v.abs())
                } else {
                    (bj, bv)
                }
            });
            if zj <= z.dot(&x) {
                break;
            }
            x = SVector::zeros();
            x[j] = 1.0;
        }
        if !estimate.is_finite() || estimate == 0.0 {
            return 0.0;
        }
        1.0 / (self.norm1 * estimate)
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
    fn rejects_a_singular_matrix() {
        let a = Matrix3::new(1.0, 2.0, 3.0, 2.0, 4.0, 6.0, 0.0, 1.0, 1.0);
        assert!(Lu::new(a).is_none());
    }
}
