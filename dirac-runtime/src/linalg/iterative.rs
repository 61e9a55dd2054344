//! The iterative backend: preconditioned conjugate gradients on a symmetric definite step
//! Jacobian, for the large systems where a sparse LU's fill costs most — fields on 2-D grids.
//!
//! The midpoint rule's step Jacobian of a field `L = Σ (ρ/2 u̇² − W(∇u))` is
//! `D_1 D_2 L_d = −(M/h + (h/4) K(u))` with `M` the (diagonal) mass and `K` the symmetric
//! stiffness: symmetric negative definite, and close to a multiple of the identity when
//! `h² ‖K‖ ≪ ‖M‖`. Conjugate gradients with the Jacobi (diagonal) preconditioner then converge
//! in a few iterations of one sparse product each, with no factorization, no fill and memory
//! linear in the size (measured in `examples/wave2d.rs`: see [`crate::element`] for when it is
//! chosen). A "factorization" here stores the matrix and its inverse diagonal, after checking
//! that the matrix is symmetric; a matrix that is not, or on which CG breaks down (not
//! definite), is an error the caller answers by falling back to the sparse LU.

use nalgebra::DVector;

use super::{FactorError, HagerCache, LinearSolver};

/// The relative residual `‖b − A x‖₂ ≤ tol ‖b‖₂` a solve stops at: below the Newton iteration's
/// own round-off, so a correction is as good as a direct solve's.
const CG_TOLERANCE: f64 = 1e-15;

/// Iterations after which a solve gives up (a breakdown: the caller falls back).
const CG_MAX_ITERATIONS: usize = 500;

/// Jacobi-preconditioned conjugate gradients on a CSC pattern (see the
/// [module documentation](self)).
#[derive(Debug)]
pub struct Pcg {
    n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    /// For each entry, the position of its transpose (the pattern is symmetric).
    transpose: Vec<usize>,
    values: Vec<f64>,
    inverse_diagonal: Vec<f64>,
    /// `r`, `z`, `p`, `Ap`.
    work: [Vec<f64>; 4],
    /// Hager's estimate of the stored matrix, once computed.
    hager: HagerCache,
    norm1: f64,
    factored: bool,
    /// Iterations of the last solve, and whether it converged.
    last: (usize, bool),
}

impl Pcg {
    /// The solver for the `n × n` pattern `(col_ptr, row_idx)`, or `None` when the pattern is
    /// not symmetric or lacks a diagonal entry.
    pub fn new(n: usize, col_ptr: &[usize], row_idx: &[usize]) -> Option<Self> {
        let mut transpose = vec![usize::MAX; row_idx.len()];
        for c in 0..n {
            for p in col_ptr[c]..col_ptr[c + 1] {
                let r = row_idx[p];
                let rows = &row_idx[col_ptr[r]..col_ptr[r + 1]];
                transpose[p] = col_ptr[r] + rows.binary_search(&c).ok()?;
            }
            row_idx[col_ptr[c]..col_ptr[c + 1]].binary_search(&c).ok()?;
        }
        Some(Self {
            n,
            col_ptr: col_ptr.to_vec(),
            row_idx: row_idx.to_vec(),
            transpose,
            values: vec![0.0; row_idx.len()],
            inverse_diagonal: vec![0.0; n],
            work: [vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]],
            hager: HagerCache::new(n),
            norm1: 0.0,
            factored: false,
            last: (0, true),
        })
    }

    /// Iterations of the last solve, and whether it met its tolerance.
    pub fn last_solve(&self) -> (usize, bool) {
        self.last
    }

    /// `y = A x`.
    fn product(&self, x: &[f64], y: &mut [f64]) {
        y.fill(0.0);
        for (c, &xc) in x.iter().enumerate() {
            for p in self.col_ptr[c]..self.col_ptr[c + 1] {
                y[self.row_idx[p]] += self.values[p] * xc;
            }
        }
    }

    /// Solves `A x = b` in place (`A` symmetric: also `Aᵀ x = b`), from `x = 0`.
    fn solve_slice(&mut self, b: &mut [f64]) {
        let [mut r, mut z, mut p, mut ap] = std::mem::take(&mut self.work);
        r.copy_from_slice(b);
        let b_norm = b.iter().map(|v| v * v).sum::<f64>().sqrt();
        b.fill(0.0);
        let x = b;
        let mut converged = b_norm == 0.0;
        let mut iterations = 0;
        if !converged {
            for ((zi, ri), di) in z.iter_mut().zip(&r).zip(&self.inverse_diagonal) {
                *zi = ri * di;
            }
            p.copy_from_slice(&z);
            let mut rz: f64 = r.iter().zip(&z).map(|(a, b)| a * b).sum();
            while iterations < CG_MAX_ITERATIONS {
                self.product(&p, &mut ap);
                let pap: f64 = p.iter().zip(&ap).map(|(a, b)| a * b).sum();
                if !(pap.is_finite() && pap != 0.0 && pap.signum() == rz.signum()) {
                    break;
                }
                let alpha = rz / pap;
                for i in 0..self.n {
                    x[i] += alpha * p[i];
                    r[i] -= alpha * ap[i];
                }
                iterations += 1;
                let r_norm = r.iter().map(|v| v * v).sum::<f64>().sqrt();
                if r_norm <= CG_TOLERANCE * b_norm {
                    converged = true;
                    break;
                }
                for ((zi, ri), di) in z.iter_mut().zip(&r).zip(&self.inverse_diagonal) {
                    *zi = ri * di;
                }
                let rz_next: f64 = r.iter().zip(&z).map(|(a, b)| a * b).sum();
                let beta = rz_next / rz;
                rz = rz_next;
                for (pi, zi) in p.iter_mut().zip(&z) {
                    *pi = zi + beta * *pi;
                }
            }
        }
        self.last = (iterations, converged);
        if !converged {
            // Not definite, or too ill-conditioned for CG: a non-finite correction, which the
            // Newton driver reports as a singular Jacobian (the caller falls back before).
            x.fill(f64::NAN);
        }
        self.work = [r, z, p, ap];
    }
}

impl LinearSolver for Pcg {
    type Vector = DVector<f64>;
    type Matrix = Vec<f64>;

    /// Stores `j` and its inverse diagonal; `Singular` when `j` is not symmetric (to round-off)
    /// or has a zero on its diagonal.
    fn factor(&mut self, j: &Vec<f64>) -> Result<(), FactorError> {
        let norm1 = self.hager.refactor(&mut self.factored, &self.col_ptr, j)?;
        let mut largest = 0.0f64;
        for (p, &t) in self.transpose.iter().enumerate() {
            largest = largest.max((j[p] - j[t]).abs());
        }
        if largest > 1e-12 * norm1 {
            return Err(FactorError::Singular);
        }
        for c in 0..self.n {
            let p = self.col_ptr[c]
                + self.row_idx[self.col_ptr[c]..self.col_ptr[c + 1]]
                    .binary_search(&c)
                    .expect("checked in new");
            if j[p] == 0.0 {
                return Err(FactorError::Singular);
            }
            self.inverse_diagonal[c] = 1.0 / j[p];
        }
        self.values.copy_from_slice(j);
        self.norm1 = norm1;
        self.factored = true;
        Ok(())
    }

    fn solve(&mut self, b: &DVector<f64>) -> DVector<f64> {
        let mut x = b.clone();
        self.solve_slice(x.as_mut_slice());
        x
    }

    fn solve_in_place(&mut self, b: &mut DVector<f64>) {
        self.solve_slice(b.as_mut_slice());
    }

    // `A` is symmetric: a transposed solve is a solve.
    hager_conditioning!(|pcg: &mut Self, x: &mut [f64], _| pcg.solve_slice(x));

    /// Yes once a matrix is stored (chord iterations: a solve costs the same either way, and
    /// the assembly of a fresh Jacobian is saved).
    fn has_reusable_factors(&self) -> bool {
        self.factored
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::DMatrix;

    /// A periodic 2-D 5-point pattern on an `m × m` grid with SPD values.
    fn grid(m: usize) -> (Vec<usize>, Vec<usize>, Vec<f64>, DMatrix<f64>) {
        let n = m * m;
        let mut a = DMatrix::zeros(n, n);
        for i in 0..m {
            for j in 0..m {
                let k = i * m + j;
                a[(k, k)] = 4.5 + 0.1 * ((k * 7 % 5) as f64);
                for l in [((i + 1) % m) * m + j, i * m + (j + 1) % m] {
                    a[(k, l)] -= 1.0;
                    a[(l, k)] -= 1.0;
                }
            }
        }
        let (mut col_ptr, mut row_idx, mut values) = (vec![0], Vec::new(), Vec::new());
        for c in 0..n {
            for r in 0..n {
                if a[(r, c)] != 0.0 {
                    row_idx.push(r);
                    values.push(a[(r, c)]);
                }
            }
            col_ptr.push(row_idx.len());
        }
        (col_ptr, row_idx, values, a)
    }

    #[test]
    fn solves_a_symmetric_definite_grid_to_round_off() {
        let (col_ptr, row_idx, values, a) = grid(9);
        let mut cg = Pcg::new(81, &col_ptr, &row_idx).unwrap();
        cg.factor(&values).unwrap();
        let x = DVector::from_fn(81, |i, _| (i as f64 * 0.3).sin());
        let b = &a * &x;
        let solved = cg.solve(&b);
        assert!((solved - &x).amax() < 1e-13);
        assert!(cg.last_solve().1);
        // A negative definite matrix (the midpoint rule's sign) solves the same way.
        let negated: Vec<f64> = values.iter().map(|v| -v).collect();
        cg.factor(&negated).unwrap();
        assert!((cg.solve(&-b) - &x).amax() < 1e-13);
        let exact = {
            let n1 = |m: &DMatrix<f64>| {
                m.column_iter()
                    .map(|c| c.iter().map(|v| v.abs()).sum::<f64>())
                    .fold(0.0, f64::max)
            };
            1.0 / (n1(&a) * n1(&a.clone().try_inverse().unwrap()))
        };
        let est = cg.rcond();
        assert!(
            est >= exact * (1.0 - 1e-9) && est <= 3.0 * exact,
            "{est:e} vs {exact:e}"
        );
    }

    #[test]
    fn asymmetric_and_indefinite_matrices_are_refused() {
        let (col_ptr, row_idx, mut values, _) = grid(5);
        let mut cg = Pcg::new(25, &col_ptr, &row_idx).unwrap();
        values[1] += 0.5;
        assert_eq!(cg.factor(&values), Err(FactorError::Singular));
        // Indefinite: CG breaks down and the correction is not finite.
        let (_, _, values, _) = grid(5);
        let indefinite: Vec<f64> = values
            .iter()
            .enumerate()
            .map(|(p, v)| if p % 7 == 0 && *v > 0.0 { -v } else { *v })
            .collect();
        if cg.factor(&indefinite).is_ok() {
            let b = DVector::from_fn(25, |i, _| i as f64 - 12.0);
            let x = cg.solve(&b);
            let (_, converged) = cg.last_solve();
            assert!(converged || x.iter().all(|v| v.is_nan()));
        }
    }
}
