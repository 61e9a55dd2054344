//! The inverse Legendre map of an element-wise continuous Lagrangian: the velocity `v` with
//! `∂L/∂v (q, v) = p`, where `L = Σ_e L^e` and each element contributes its share of the map and
//! of its Jacobian `∂²L/∂v²` on its stencil. The Jacobian has the step Jacobian's pattern (both
//! couple exactly the coordinates an element reads together), so it is assembled into that
//! pattern and solved by the sparse LU; Newton's iteration is the one the fixed-size systems use
//! for their node energies ([`crate::ContinuousLagrangian::velocity_with`]): the residual accepted
//! at `abs_tol + rel_tol ‖p‖∞`, the Jacobian's conditioning checked against `min_rcond`.

use nalgebra::DVector;

use super::pass::{gather, split_scratch, with_scratch};
use super::{scratch_len, ElementLagrangian, Family, FamilyVisitor};
use crate::error::StepError;
use crate::linalg::{checked_rcond, DynSparseLu, LinearSolver};
use crate::newton::NewtonOptions;

/// Adds every element's `∂L^e/∂v` into `r` and `∂²L^e/∂v²` into `values` (the pattern's order).
struct Assemble<'a> {
    q: &'a [f64],
    v: &'a [f64],
    col_ptr: &'a [usize],
    row_idx: &'a [usize],
    r: &'a mut [f64],
    values: &'a mut [f64],
    /// The first element outside the coordinates or the pattern.
    invalid: Option<String>,
}

impl Assemble<'_> {
    /// The position of entry `(row, col)` in the pattern (rows sorted within each column).
    fn position(&self, row: usize, col: usize) -> Option<usize> {
        let (start, end) = (*self.col_ptr.get(col)?, *self.col_ptr.get(col + 1)?);
        self.row_idx[start..end]
            .binary_search(&row)
            .ok()
            .map(|i| start + i)
    }
}

impl FamilyVisitor for Assemble<'_> {
    fn family<F: Family>(&mut self, family: &F) {
        let (n, w) = (self.r.len(), family.width());
        with_scratch(w, scratch_len(w), |st, scratch| {
            let (a0, a1, out) = split_scratch(scratch, w);
            let out = &mut out[..w + w * w];
            family.elements(&mut |indices, stencil| {
                if self.invalid.is_some() {
                    return;
                }
                if stencil.len() != w || !stencil.iter().all(|&g| g >= 0 && (g as usize) < n) {
                    self.invalid = Some(format!(
                        "element {indices:?} reads coordinates {stencil:?}, outside 0..{n}"
                    ));
                    return;
                }
                for (s, &g) in st.iter_mut().zip(stencil) {
                    *s = g as usize;
                }
                gather(self.q, st, a0);
                gather(self.v, st, a1);
                family.legendre(indices, a0, a1, out);
                let (g, hessian) = out.split_at(w);
                for a in 0..w {
                    self.r[st[a]] += g[a];
                    for b in 0..w {
                        match self.position(st[a], st[b]) {
                            Some(i) => self.values[i] += hessian[a * w + b],
                            None => {
                                self.invalid = Some(format!(
                                    "element {indices:?} couples coordinates {} and {} outside \
                                     the step Jacobian's pattern",
                                    st[a], st[b]
                                ));
                                return;
                            }
                        }
                    }
                }
            });
        });
    }
}

/// The velocity `v` with `∂L/∂v (q, v) = p`, by Newton's method from `guess`, with the
/// Jacobian's pattern `(col_ptr, row_idx)`; `node` labels the errors (as a step index).
pub(super) fn velocity<L: ElementLagrangian>(
    system: &L,
    pattern: (&[usize], &[usize]),
    node: usize,
    q: &DVector<f64>,
    p: &DVector<f64>,
    guess: DVector<f64>,
    options: &NewtonOptions,
) -> Result<DVector<f64>, StepError> {
    let (col_ptr, row_idx) = pattern;
    let n = q.len();
    let mut lu = DynSparseLu::new(n, col_ptr.to_vec(), row_idx.to_vec());
    let tolerance = options.abs_tol + options.rel_tol * p.amax();
    let mut v = guess;
    let mut r = DVector::zeros(n);
    let mut values = vec![0.0; row_idx.len()];
    let mut residual = f64::INFINITY;
    for iteration in 0..=options.max_iterations {
        r.fill(0.0);
        values.fill(0.0);
        let mut visit = Assemble {
            q: q.as_slice(),
            v: v.as_slice(),
            col_ptr,
            row_idx,
            r: r.as_mut_slice(),
            values: &mut values,
            invalid: None,
        };
        system.families(&mut visit);
        if let Some(reason) = visit.invalid {
            return Err(StepError::InvalidSize { reason });
        }
        r -= p;
        residual = r.amax();
        if !residual.is_finite() {
            return Err(StepError::NonFinite {
                step: node,
                what: "the Legendre map (a discrete Lagrangian has none)",
                residual,
            });
        }
        // The Jacobian is checked even when the guess already solves the map: for a degenerate
        // Lagrangian every velocity does, and a small residual proves nothing.
        let singular = StepError::SingularJacobian {
            step: node,
            residual,
        };
        lu.factor(&values).map_err(|_| singular.clone())?;
        if checked_rcond(&mut lu, options.min_rcond) < options.min_rcond {
            return Err(singular);
        }
        if residual <= tolerance {
            return Ok(v);
        }
        if iteration == options.max_iterations {
            break;
        }
        lu.solve_in_place(&mut r);
        v -= &r;
    }
    Err(StepError::NotConverged {
        step: node,
        iterations: options.max_iterations,
        residual,
    })
}
