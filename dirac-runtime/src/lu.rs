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
}

impl<const N: usize> Lu<N> {
    /// Factors `a`; `None` when a pivot is exactly zero or not finite.
    pub fn new(mut a: SMatrix<f64, N, N>) -> Option<Self> {
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
        Some(Self { lu: a, perm })
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
    fn rejects_a_singular_matrix() {
        let a = Matrix3::new(1.0, 2.0, 3.0, 2.0, 4.0, 6.0, 0.0, 1.0, 1.0);
        assert!(Lu::new(a).is_none());
    }
}
