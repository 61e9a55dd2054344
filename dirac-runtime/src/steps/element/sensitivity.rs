//! Sensitivities of a run-time-sized step, as sparse matrices.
//!
//! A step solves `R(q_{k+1}; q_k, p_k, u) = p_k + Σ_e d1^e(q_k, q_{k+1}; u) = 0` and sets
//! `p_{k+1} = Σ_e d2^e(q_k, q_{k+1}; u)`, with `d1^e`, `d2^e` each element's `D_1 L_d^e`,
//! `D_2 L_d^e` (plus its discrete forces `f_d^{e∓}`). By the implicit-function theorem, where
//! `J = ∂R/∂q_{k+1} = Σ_e ∂d1^e/∂q1` is invertible,
//!
//! ```text
//! dq_{k+1} = −J⁻¹ (R_q dq_k + dp_k + R_u du),       R_q = Σ_e ∂d1^e/∂q0,   R_u = Σ_e ∂d1^e/∂u,
//! dp_{k+1} = P_q dq_k + P_z dq_{k+1} + P_u du,      P_q = Σ_e ∂d2^e/∂q0,   P_z = Σ_e ∂d2^e/∂q1,
//! ```
//!
//! every block differentiated at compile time (`Family::step_partials`) and assembled into the
//! step Jacobian's pattern: `J`, `R_q`, `P_q` and `P_z` are sparse with the element stencils'
//! pattern, `R_u` and `P_u` are `n × m` (`m` controls). The step map itself is dense (`J⁻¹`
//! couples every coordinate), so [`ElementSensitivity`] keeps the sparse blocks and the sparse LU
//! of `J` and applies the derivative — forward, `(dq, dp, du) ↦ (dq', dp')`, at the cost of one
//! solve, or adjoint, `(λq', λp') ↦ (λq, λp, λu)`, at the cost of one transposed solve:
//!
//! ```text
//! y = J⁻ᵀ (λq' + P_zᵀ λp'),   λq = P_qᵀ λp' − R_qᵀ y,   λp = −y,   λu = P_uᵀ λp' − R_uᵀ y,
//! ```
//!
//! which is what gradients of a cost along a trajectory (the discrete adjoint of DMOC) need.
//! [`ElementSensitivity::to_dense`] forms the whole [`Sensitivity`] for small systems. The
//! momentum map kept exact by the step (`crate::element`'s translations) is the same function
//! of the state on solutions, so its derivative is the one above. Both sides compute the same
//! step map, so their sensitivities are the same.

use nalgebra::{DMatrix, DVector};

use super::assembly::FamilyData;
use super::pass::{gather, with_scratch};
use super::{
    ElementIntegrator, ElementLagrangian, ElementState, ElementWorkspace, Family, FamilyVisitor,
    Parallel, StepSolver,
};
use crate::error::StepError;
use crate::linalg::{DynSparseLu, LinearSolver};
use crate::sensitivity::Sensitivity;
use crate::stepper::{system_at, StepAt, StepStats, Stepper};

/// A sparse matrix in compressed columns: column `j` holds the rows
/// `row_idx[col_ptr[j]..col_ptr[j + 1]]` (sorted) with the values at the same positions.
#[derive(Clone, Debug, PartialEq)]
pub struct CscMatrix {
    /// Number of rows.
    pub nrows: usize,
    /// Number of columns.
    pub ncols: usize,
    /// Column starts (`ncols + 1` entries).
    pub col_ptr: Vec<usize>,
    /// Row of each stored entry.
    pub row_idx: Vec<usize>,
    /// Value of each stored entry.
    pub values: Vec<f64>,
}

impl CscMatrix {
    /// Entry `(row, col)` (zero where none is stored).
    pub fn get(&self, row: usize, col: usize) -> f64 {
        let range = self.col_ptr[col]..self.col_ptr[col + 1];
        self.row_idx[range.clone()]
            .binary_search(&row)
            .map_or(0.0, |i| self.values[range.start + i])
    }

    /// `A x`.
    ///
    /// # Panics
    /// If `x` does not have `ncols` components.
    pub fn mul_vec(&self, x: &DVector<f64>) -> DVector<f64> {
        assert_eq!(x.len(), self.ncols, "A x with x of the wrong length");
        let mut y = DVector::zeros(self.nrows);
        for (j, xj) in x.iter().enumerate() {
            for p in self.col_ptr[j]..self.col_ptr[j + 1] {
                y[self.row_idx[p]] += self.values[p] * xj;
            }
        }
        y
    }

    /// `Aᵀ y`.
    ///
    /// # Panics
    /// If `y` does not have `nrows` components.
    pub fn tr_mul_vec(&self, y: &DVector<f64>) -> DVector<f64> {
        assert_eq!(y.len(), self.nrows, "Aᵀ y with y of the wrong length");
        DVector::from_fn(self.ncols, |j, _| {
            (self.col_ptr[j]..self.col_ptr[j + 1])
                .map(|p| self.values[p] * y[self.row_idx[p]])
                .sum()
        })
    }

    /// The dense matrix.
    pub fn to_dense(&self) -> DMatrix<f64> {
        let mut a = DMatrix::zeros(self.nrows, self.ncols);
        for j in 0..self.ncols {
            for p in self.col_ptr[j]..self.col_ptr[j + 1] {
                a[(self.row_idx[p], j)] += self.values[p];
            }
        }
        a
    }
}

/// The derivative of one step `(q_{k+1}, p_{k+1}) = Φ(q_k, p_k, u_k)` of a run-time-sized system:
/// its sparse partial derivatives and the sparse LU of its Jacobian (see the [module
/// documentation](self)).
#[derive(Debug)]
pub struct ElementSensitivity {
    /// The step it is the derivative of (for errors).
    step: usize,
    jacobian: CscMatrix,
    residual_q: CscMatrix,
    momentum_q: CscMatrix,
    momentum_z: CscMatrix,
    residual_u: DMatrix<f64>,
    momentum_u: DMatrix<f64>,
    lu: DynSparseLu,
}

impl ElementSensitivity {
    /// The number of coordinates `n`.
    pub fn dim(&self) -> usize {
        self.jacobian.nrows
    }

    /// The number of controls `m`.
    pub fn control_dim(&self) -> usize {
        self.residual_u.ncols()
    }

    /// `J = ∂R/∂q_{k+1}`, the step Jacobian.
    pub fn jacobian(&self) -> &CscMatrix {
        &self.jacobian
    }

    /// `R_q = ∂R/∂q_k`.
    pub fn residual_q(&self) -> &CscMatrix {
        &self.residual_q
    }

    /// `P_q = ∂p_{k+1}/∂q_k` at fixed `q_{k+1}`.
    pub fn momentum_q(&self) -> &CscMatrix {
        &self.momentum_q
    }

    /// `P_z = ∂p_{k+1}/∂q_{k+1}` at fixed `q_k`.
    pub fn momentum_z(&self) -> &CscMatrix {
        &self.momentum_z
    }

    /// `R_u = ∂R/∂u` (`n × m`).
    pub fn residual_u(&self) -> &DMatrix<f64> {
        &self.residual_u
    }

    /// `P_u = ∂p_{k+1}/∂u` (`n × m`).
    pub fn momentum_u(&self) -> &DMatrix<f64> {
        &self.momentum_u
    }

    /// The step this is the derivative of.
    pub fn step(&self) -> usize {
        self.step
    }

    /// The lengths of the vectors in `what` (a name, a length, the length wanted), and whether
    /// every component of `values` is finite (a NaN would spread through the solve silently).
    fn check(&self, what: &[(&str, usize, usize)], values: &[&[f64]]) -> Result<(), StepError> {
        if let Some((name, len, want)) = what.iter().find(|(_, len, want)| len != want) {
            return Err(StepError::InvalidSize {
                reason: format!("`{name}` has {len} components; the step's has {want}"),
            });
        }
        if values.iter().any(|v| v.iter().any(|x| !x.is_finite())) {
            return Err(StepError::NonFinite {
                step: self.step,
                what: "a direction or covector given to the step's sensitivity",
                residual: f64::NAN,
            });
        }
        Ok(())
    }

    /// The forward derivative `(dq_{k+1}, dp_{k+1})` of the step in the direction
    /// `(dq_k, dp_k, du)` (`du` empty for no change of the controls): one sparse solve.
    /// Vectors of the wrong lengths are [`StepError::InvalidSize`].
    pub fn apply(
        &mut self,
        dq: &DVector<f64>,
        dp: &DVector<f64>,
        du: &[f64],
    ) -> Result<(DVector<f64>, DVector<f64>), StepError> {
        let (n, m) = (self.dim(), self.control_dim());
        let du_len = if du.is_empty() { m } else { du.len() };
        self.check(
            &[("dq", dq.len(), n), ("dp", dp.len(), n), ("du", du_len, m)],
            &[dq.as_slice(), dp.as_slice(), du],
        )?;
        let mut b = self.residual_q.mul_vec(dq) + dp;
        let mut dp1 = self.momentum_q.mul_vec(dq);
        if !du.is_empty() {
            let du = DVector::from_column_slice(du);
            b += &self.residual_u * &du;
            dp1 += &self.momentum_u * &du;
        }
        self.lu.solve_in_place(&mut b);
        let dq1 = -b;
        dp1 += self.momentum_z.mul_vec(&dq1);
        Ok((dq1, dp1))
    }

    /// The adjoint: for a covector `(λq_{k+1}, λp_{k+1})` on the new state, its pull-back
    /// `(λq_k, λp_k, λu)` onto the old state and the controls (`⟨λ', dΦ·(dq, dp, du)⟩ =
    /// ⟨λq, dq⟩ + ⟨λp, dp⟩ + ⟨λu, du⟩`): one transposed sparse solve. Vectors of the wrong
    /// lengths are [`StepError::InvalidSize`].
    #[allow(clippy::type_complexity)]
    pub fn apply_transpose(
        &mut self,
        lq: &DVector<f64>,
        lp: &DVector<f64>,
    ) -> Result<(DVector<f64>, DVector<f64>, DVector<f64>), StepError> {
        let n = self.dim();
        self.check(
            &[("lq", lq.len(), n), ("lp", lp.len(), n)],
            &[lq.as_slice(), lp.as_slice()],
        )?;
        let mut y = lq + self.momentum_z.tr_mul_vec(lp);
        self.lu.solve_transpose_in_place(&mut y);
        let l_q = self.momentum_q.tr_mul_vec(lp) - self.residual_q.tr_mul_vec(&y);
        let l_u = self.momentum_u.tr_mul(lp) - self.residual_u.tr_mul(&y);
        Ok((l_q, -y, l_u))
    }

    /// The whole derivative as a dense [`Sensitivity`] (state ordered `(q, p)`, one column per
    /// control): `2n + m` solves, for systems small enough to hold `(2n)²` entries.
    pub fn to_dense(&mut self) -> Sensitivity {
        let (n, m) = (self.dim(), self.control_dim());
        let mut state = DMatrix::zeros(2 * n, 2 * n);
        let mut control = DMatrix::zeros(2 * n, m);
        let zero = DVector::zeros(n);
        for c in 0..2 * n + m {
            let unit = |i: usize| DVector::from_fn(n, |r, _| if r == i { 1.0 } else { 0.0 });
            let (dq, dp, du) = match c {
                c if c < n => (unit(c), zero.clone(), Vec::new()),
                c if c < 2 * n => (zero.clone(), unit(c - n), Vec::new()),
                c => {
                    let mut du = vec![0.0; m];
                    du[c - 2 * n] = 1.0;
                    (zero.clone(), zero.clone(), du)
                }
            };
            let (dq1, dp1) = self
                .apply(&dq, &dp, &du)
                .expect("unit vectors have the step's lengths");
            let column = dq1.iter().chain(dp1.iter());
            if c < 2 * n {
                state
                    .column_mut(c)
                    .iter_mut()
                    .zip(column)
                    .for_each(|(a, b)| *a = *b);
            } else {
                control
                    .column_mut(c - 2 * n)
                    .iter_mut()
                    .zip(column)
                    .for_each(|(a, b)| *a = *b);
            }
        }
        Sensitivity { state, control }
    }
}

/// Adds every element's step partials into the pattern's values and the control columns.
struct PartialsVisit<'a> {
    families: &'a [FamilyData],
    next: usize,
    q0: &'a [f64],
    q1: &'a [f64],
    m: usize,
    /// `R_q`, `P_q`, `P_z` values in the pattern's order.
    values: [&'a mut [f64]; 3],
    residual_u: &'a mut DMatrix<f64>,
    momentum_u: &'a mut DMatrix<f64>,
    supported: bool,
}

impl FamilyVisitor for PartialsVisit<'_> {
    fn family<F: Family>(&mut self, family: &F) {
        let data = &self.families[self.next];
        self.next += 1;
        let (w, m, depth) = (data.width, self.m, data.depth);
        if w == 0 || !self.supported {
            return;
        }
        let len = 3 * w * w + 2 * w * m;
        with_scratch(0, 2 * w + len, |_, scratch| {
            let (a0, rest) = scratch.split_at_mut(w);
            let (a1, out) = rest.split_at_mut(w);
            for e in 0..data.count {
                let st = &data.stencils[e * w..(e + 1) * w];
                let indices = &data.indices[e * depth..(e + 1) * depth];
                gather(self.q0, st, a0);
                gather(self.q1, st, a1);
                if !family.step_partials(indices, a0, a1, out) {
                    self.supported = false;
                    return;
                }
                let (blocks, controls) = out.split_at(3 * w * w);
                let (u1, u2) = controls.split_at(w * m);
                let positions = &data.positions[e * w * w..(e + 1) * w * w];
                for a in 0..w {
                    for b in 0..w {
                        let p = positions[a * w + b];
                        for (k, values) in self.values.iter_mut().enumerate() {
                            values[p] += blocks[k * w * w + a * w + b];
                        }
                    }
                    for c in 0..m {
                        self.residual_u[(st[a], c)] += u1[a * m + c];
                        self.momentum_u[(st[a], c)] += u2[a * m + c];
                    }
                }
            }
        });
    }
}

impl<L: ElementLagrangian> ElementIntegrator<L> {
    /// The derivative of step `k` from `state` to `next` under the controls `u` (empty: the
    /// system's own) — see the [module documentation](self): the step's sparse partial
    /// derivatives, assembled element by element, and the sparse LU of its Jacobian at
    /// `(q_k, q_{k+1})`. The same for both sides. States or controls that do not fit the system
    /// are typed errors; a singular Jacobian is [`StepError::SingularJacobian`] at step `k`.
    pub fn sensitivity(
        &self,
        k: usize,
        state: &ElementState,
        next: &ElementState,
        u: &[f64],
    ) -> Result<ElementSensitivity, StepError> {
        self.check_sizes(state)?;
        self.check_lengths(&[("next.q", next.q.len()), ("next.p", next.p.len())])?;
        let m = self.system.control_count();
        let owned = system_at(&self.system, k, self.system.time_step(), u)?;
        let sys = owned.as_ref().unwrap_or(&self.system);
        let ws = ElementWorkspace::new(sys, Parallel::Never, StepSolver::Direct);
        if let Some(reason) = ws.invalid() {
            return Err(self.invalid(reason.to_string()));
        }
        let n = ws.dim();
        let (q0, p0, q1) = (&state.q, &state.p, &next.q);
        let mut r = DVector::zeros(n);
        let mut j = vec![0.0; ws.nnz()];
        ws.assembler().residual_jacobian(
            sys,
            q0.as_slice(),
            p0.as_slice(),
            q1.as_slice(),
            r.as_mut_slice(),
            Some(&mut j),
        );
        let mut values = [
            vec![0.0; ws.nnz()],
            vec![0.0; ws.nnz()],
            vec![0.0; ws.nnz()],
        ];
        let (mut residual_u, mut momentum_u) = (DMatrix::zeros(n, m), DMatrix::zeros(n, m));
        let [r_q, p_q, p_z] = &mut values;
        let mut visit = PartialsVisit {
            families: ws.assembler().families(),
            next: 0,
            q0: q0.as_slice(),
            q1: q1.as_slice(),
            m,
            values: [r_q, p_q, p_z],
            residual_u: &mut residual_u,
            momentum_u: &mut momentum_u,
            supported: true,
        };
        sys.families(&mut visit);
        if !visit.supported {
            return Err(StepError::Unsupported {
                what: "step sensitivities: a family of this system has no step partials (a \
                       family written by hand; `#[reduced_lagrangian]` emits them)",
            });
        }
        let (col_ptr, row_idx) = ws.pattern();
        let (col_ptr, row_idx) = (col_ptr.to_vec(), row_idx.to_vec());
        let mut lu = DynSparseLu::new(n, col_ptr.clone(), row_idx.clone());
        lu.factor(&j).map_err(|_| StepError::SingularJacobian {
            step: k,
            residual: r.amax(),
        })?;
        let csc = |values: Vec<f64>| CscMatrix {
            nrows: n,
            ncols: n,
            col_ptr: col_ptr.clone(),
            row_idx: row_idx.clone(),
            values,
        };
        let [r_q, p_q, p_z] = values;
        Ok(ElementSensitivity {
            step: k,
            jacobian: csc(j),
            residual_q: csc(r_q),
            momentum_q: csc(p_q),
            momentum_z: csc(p_z),
            residual_u,
            momentum_u,
            lu,
        })
    }

    /// Takes step `k` from `state` with the controls `u` (empty: the system's own) in a fresh
    /// workspace and returns the new state, the step's statistics and its
    /// [`ElementSensitivity`].
    pub fn step_sensitivity(
        &self,
        k: usize,
        state: &ElementState,
        u: &[f64],
    ) -> Result<(ElementState, StepStats, ElementSensitivity), StepError> {
        self.check(state)?;
        let at = StepAt::new(k, self.time_step()).with_controls(u);
        let (next, stats) = self.step_with(&mut self.workspace(), at, state)?;
        let sensitivity = self.sensitivity(k, state, &next, u)?;
        Ok((next, stats, sensitivity))
    }
}
