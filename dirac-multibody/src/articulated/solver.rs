//! Newton's corrections of the recursive step in `O(n)` (module documentation of [`super`]):
//! the step Jacobian applied by a directional difference of the residual, GMRES preconditioned
//! by the mass term `−M(q̄)/h`, whose inverse the articulated-body algorithm applies.

use dirac_runtime::linalg::{hager_inverse_norm1_in, FactorError, LinearSolver};
use nalgebra::{DVector, Matrix6, Vector6};

use super::passes::{Passes, StepData};
use super::ArticulatedIntegrator;

/// The most Krylov vectors a correction builds.
const KRYLOV: usize = 12;

/// The relative residual at which GMRES stops: an inexact Newton iteration (Dembo, Eisenstat
/// and Steihaug, 1982) whose corrections shrink the error by this factor besides Newton's
/// quadratic term, so two or three corrections reach the step's tolerance; tighter costs more
/// Krylov vectors than it saves corrections (measured on chains of 10 to 1000 links).
const KRYLOV_TOL: f64 = 1e-6;

/// The mass term `scale · M(q̄)` of the step Jacobian: each body's spatial inertia and each
/// joint's axis at `q̄` (module documentation of [`super`]). Filled in place.
#[derive(Clone, Debug)]
pub struct MassOperator {
    pub(super) inertia: Vec<Matrix6<f64>>,
    pub(super) axis: Vec<Vector6<f64>>,
    /// The operator is `scale · M`.
    pub(super) scale: f64,
}

impl MassOperator {
    pub(super) fn new(bodies: usize, joints: usize, scale: f64) -> Self {
        Self {
            inertia: vec![Matrix6::zeros(); bodies],
            axis: vec![Vector6::zeros(); joints],
            scale,
        }
    }
}

/// The step Jacobian `∂R/∂q_{k+1}` at an iterate, as the corrections apply it: the iterate, the
/// residual there and the step's data (to difference the residual along a direction), and the
/// mass term at the iterate's midpoint (the preconditioner). Filled in place, so a step
/// allocates nothing.
#[derive(Clone, Debug)]
pub struct StepJacobian {
    pub(super) mass: MassOperator,
    pub(super) at: Vec<f64>,
    pub(super) residual: Vec<f64>,
    pub(super) q0: Vec<f64>,
    pub(super) p0: Vec<f64>,
    pub(super) torque: Vec<f64>,
    pub(super) h: f64,
}

impl StepJacobian {
    pub(super) fn new(bodies: usize, n: usize) -> Self {
        Self {
            mass: MassOperator::new(bodies, n, 1.0),
            at: vec![0.0; n],
            residual: vec![0.0; n],
            q0: vec![0.0; n],
            p0: vec![0.0; n],
            torque: vec![0.0; n],
            h: 1.0,
        }
    }
}

/// The [`LinearSolver`] of the recursive step: "factoring" the step Jacobian is the
/// articulated-body factorization of its mass term (`U_j`, `D_j` from the leaves), a solve is
/// GMRES on the Jacobian preconditioned by it. Every pass is `O(n)`.
#[derive(Clone, Debug)]
pub struct ArticulatedSolver {
    integ: ArticulatedIntegrator,
    parent: Vec<usize>,
    child: Vec<usize>,
    /// The factors of the mass term: `U_j = I^A S_j`, `D_j = S_j·U_j`, and the operator.
    u: Vec<Vector6<f64>>,
    d: Vec<f64>,
    operator: MassOperator,
    /// The Jacobian's point, residual and step data, copied at `factor`.
    jacobian: StepJacobian,
    /// Scratch of the articulated-body passes.
    articulated: Vec<Matrix6<f64>>,
    bias: Vec<Vector6<f64>>,
    acceleration: Vec<Vector6<f64>>,
    forces: Vec<f64>,
    /// Scratch of the directional differences.
    passes: Passes,
    shifted: Vec<f64>,
    /// GMRES: the Krylov basis `v_0..v_m`, the preconditioned directions `z_j = P⁻¹ v_j`, the
    /// Hessenberg matrix (column-major, `KRYLOV + 1` rows), the Givens rotations, the
    /// right-hand side `g` and the solution's coefficients.
    basis: Vec<f64>,
    directions: Vec<f64>,
    hessenberg: Vec<f64>,
    rotations: Vec<(f64, f64)>,
    g: Vec<f64>,
    y: Vec<f64>,
    /// Hager's scratch, the input of a product, and the estimates for the current factors.
    hager: [Vec<f64>; 3],
    product: Vec<f64>,
    rcond: Option<f64>,
    norm1: f64,
}

/// `a · b` of two slices.
fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

impl ArticulatedSolver {
    pub(super) fn new(integ: &ArticulatedIntegrator) -> Self {
        let (b, n) = (integ.bodies.len(), integ.joints.len());
        let m = KRYLOV.min(n);
        Self {
            integ: integ.clone(),
            parent: integ.joints.iter().map(|j| j.parent).collect(),
            child: integ.joints.iter().map(|j| j.child).collect(),
            u: vec![Vector6::zeros(); n],
            d: vec![0.0; n],
            operator: MassOperator::new(b, n, 1.0),
            jacobian: StepJacobian::new(b, n),
            articulated: vec![Matrix6::zeros(); b],
            bias: vec![Vector6::zeros(); b],
            acceleration: vec![Vector6::zeros(); b],
            forces: vec![0.0; n],
            passes: Passes::new(integ),
            shifted: vec![0.0; n],
            basis: vec![0.0; (m + 1) * n],
            directions: vec![0.0; m * n],
            hessenberg: vec![0.0; (m + 1) * m],
            rotations: vec![(1.0, 0.0); m],
            g: vec![0.0; m + 1],
            y: vec![0.0; m],
            hager: [vec![0.0; n], vec![0.0; n], vec![0.0; n]],
            product: vec![0.0; n],
            rcond: None,
            norm1: 0.0,
        }
    }

    /// The articulated-body factorization of `mass` (Featherstone Table 7.1, no velocity and
    /// no gravity): from the leaves, `U = I^A S`, `D = S·U`, `I^A_λ += I^A − U Uᵀ/D`.
    pub(super) fn factor_mass(&mut self, mass: &MassOperator) -> Result<(), FactorError> {
        self.rcond = None;
        if !mass.scale.is_finite()
            || mass.axis.iter().any(|s| !s.iter().all(|v| v.is_finite()))
            || mass
                .inertia
                .iter()
                .any(|i| !i.iter().all(|v| v.is_finite()))
        {
            return Err(FactorError::NonFinite);
        }
        self.operator.inertia.copy_from_slice(&mass.inertia);
        self.operator.axis.copy_from_slice(&mass.axis);
        self.operator.scale = mass.scale;
        self.articulated.copy_from_slice(&mass.inertia);
        for k in (0..self.u.len()).rev() {
            let (c, parent) = (self.child[k], self.parent[k]);
            let s = &self.operator.axis[k];
            let u = self.articulated[c] * s;
            let d = s.dot(&u);
            if !(d.is_finite() && d > 0.0) {
                return Err(FactorError::Singular);
            }
            self.u[k] = u;
            self.d[k] = d;
            let passed = self.articulated[c] - u * u.transpose() / d;
            self.articulated[parent] += passed;
        }
        Ok(())
    }

    /// `x ← (scale M)⁻¹ x`: the two passes of the articulated-body algorithm with the factors,
    /// from the leaves `u = x − S·p^A`, `p^A_λ += p^A + U u/D`, from the root
    /// `x = (u − U·a_λ)/D`, `a = a_λ + S x`.
    pub(super) fn precondition(&mut self, x: &mut [f64]) {
        self.bias.iter_mut().for_each(|b| *b = Vector6::zeros());
        for j in (0..x.len()).rev() {
            let (c, parent) = (self.child[j], self.parent[j]);
            let uj = x[j] - self.operator.axis[j].dot(&self.bias[c]);
            self.forces[j] = uj;
            let pass = self.bias[c] + self.u[j] * (uj / self.d[j]);
            self.bias[parent] += pass;
        }
        self.acceleration[0] = Vector6::zeros();
        for (j, out) in x.iter_mut().enumerate() {
            let (c, parent) = (self.child[j], self.parent[j]);
            let xj = (self.forces[j] - self.u[j].dot(&self.acceleration[parent])) / self.d[j];
            self.acceleration[c] = self.acceleration[parent] + self.operator.axis[j] * xj;
            *out = xj / self.operator.scale;
        }
    }

    /// `y ← (scale M) x` by the velocity pass and the momentum sums (for `‖P‖₁`).
    fn multiply(&mut self, x: &[f64], y: &mut [f64]) {
        self.acceleration[0] = Vector6::zeros();
        for (j, xj) in x.iter().enumerate() {
            let (c, parent) = (self.child[j], self.parent[j]);
            self.acceleration[c] = self.acceleration[parent] + self.operator.axis[j] * *xj;
        }
        for (b, bias) in self.bias.iter_mut().enumerate() {
            *bias = self.operator.inertia[b] * self.acceleration[b];
        }
        for j in (0..x.len()).rev() {
            let (c, parent) = (self.child[j], self.parent[j]);
            y[j] = self.operator.scale * self.operator.axis[j].dot(&self.bias[c]);
            let pass = self.bias[c];
            self.bias[parent] += pass;
        }
    }

    /// `w ← J z`, by the forward difference `(R(q + ε z) − R(q))/ε` of the residual at the
    /// Jacobian's point `q`, with `ε` scaled to `q` and `z` (relative accuracy about `1e-8`,
    /// which bounds how well a correction solves, not what a step accepts).
    fn apply(&mut self, z: &[f64], w: &mut [f64]) {
        let size = z.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        if size == 0.0 {
            w.fill(0.0);
            return;
        }
        let scale = self.jacobian.at.iter().fold(1.0f64, |m, v| m.max(v.abs()));
        let eps = 1e-8 * scale / size;
        for ((s, a), zi) in self.shifted.iter_mut().zip(&self.jacobian.at).zip(z) {
            *s = a + eps * zi;
        }
        let data = StepData {
            q0: &self.jacobian.q0,
            p0: &self.jacobian.p0,
            torque: &self.jacobian.torque,
            h: self.jacobian.h,
        };
        self.passes
            .residual(&self.integ, &data, &self.shifted, w, None);
        for (wi, r) in w.iter_mut().zip(&self.jacobian.residual) {
            *wi = (*wi - r) / eps;
        }
    }

    /// GMRES on `J x = b` with right preconditioning by the mass term (Saad, *Iterative
    /// Methods for Sparse Linear Systems*, 2003, Alg. 9.5), from `x = 0`, in place of `b`.
    fn gmres(&mut self, b: &mut [f64]) {
        let n = b.len();
        let m = KRYLOV.min(n);
        let beta = dot(b, b).sqrt();
        if beta == 0.0 || !beta.is_finite() {
            return;
        }
        let (mut basis, mut directions) = (
            std::mem::take(&mut self.basis),
            std::mem::take(&mut self.directions),
        );
        for (v, bi) in basis[..n].iter_mut().zip(b.iter()) {
            *v = bi / beta;
        }
        self.g.fill(0.0);
        self.g[0] = beta;
        let rows = m + 1;
        let mut used = 0;
        for j in 0..m {
            let (done, rest) = basis.split_at_mut((j + 1) * n);
            let z = &mut directions[j * n..(j + 1) * n];
            z.copy_from_slice(&done[j * n..]);
            self.precondition(z);
            let w = &mut rest[..n];
            self.apply(z, w);
            // Modified Gram–Schmidt against v_0..v_j.
            for i in 0..=j {
                let vi = &done[i * n..(i + 1) * n];
                let hij = dot(w, vi);
                self.hessenberg[j * rows + i] = hij;
                w.iter_mut().zip(vi).for_each(|(a, b)| *a -= hij * b);
            }
            let next = dot(w, w).sqrt();
            self.hessenberg[j * rows + j + 1] = next;
            if next > 0.0 {
                w.iter_mut().for_each(|a| *a /= next);
            }
            // The previous rotations on column j, then the one that zeroes its subdiagonal.
            let column = &mut self.hessenberg[j * rows..(j + 1) * rows];
            for (i, &(c, s)) in self.rotations[..j].iter().enumerate() {
                let (a, b) = (column[i], column[i + 1]);
                column[i] = c * a + s * b;
                column[i + 1] = -s * a + c * b;
            }
            let (a, b) = (column[j], column[j + 1]);
            let r = a.hypot(b);
            let (c, s) = if r == 0.0 { (1.0, 0.0) } else { (a / r, b / r) };
            self.rotations[j] = (c, s);
            column[j] = r;
            column[j + 1] = 0.0;
            self.g[j + 1] = -s * self.g[j];
            self.g[j] *= c;
            used = j + 1;
            if self.g[j + 1].abs() <= KRYLOV_TOL * beta || next == 0.0 {
                break;
            }
        }
        // y from the triangle, then x = Σ y_j z_j.
        for i in (0..used).rev() {
            let mut sum = self.g[i];
            for l in i + 1..used {
                sum -= self.hessenberg[l * rows + i] * self.y[l];
            }
            let diagonal = self.hessenberg[i * rows + i];
            self.y[i] = if diagonal == 0.0 { 0.0 } else { sum / diagonal };
        }
        b.fill(0.0);
        for (j, yj) in self.y[..used].iter().enumerate() {
            let z = &directions[j * n..(j + 1) * n];
            b.iter_mut().zip(z).for_each(|(x, zj)| *x += yj * zj);
        }
        (self.basis, self.directions) = (basis, directions);
    }
}

impl LinearSolver for ArticulatedSolver {
    type Vector = DVector<f64>;
    type Matrix = StepJacobian;

    fn factor(&mut self, j: &StepJacobian) -> Result<(), FactorError> {
        if !(j.residual.iter().chain(&j.at).all(|v| v.is_finite()) && j.h.is_finite()) {
            return Err(FactorError::NonFinite);
        }
        self.factor_mass(&j.mass)?;
        let mine = &mut self.jacobian;
        mine.at.copy_from_slice(&j.at);
        mine.residual.copy_from_slice(&j.residual);
        mine.q0.copy_from_slice(&j.q0);
        mine.p0.copy_from_slice(&j.p0);
        mine.torque.copy_from_slice(&j.torque);
        mine.h = j.h;
        Ok(())
    }

    fn solve(&mut self, b: &DVector<f64>) -> DVector<f64> {
        let mut x = b.clone();
        self.gmres(x.as_mut_slice());
        x
    }

    fn solve_in_place(&mut self, b: &mut DVector<f64>) {
        self.gmres(b.as_mut_slice());
    }

    /// `‖P‖₁` of the mass term `P = −M(q̄)/h` that preconditions the corrections (made with
    /// [`Self::rcond`]).
    fn norm1(&self) -> f64 {
        self.norm1
    }

    fn rcond_lower_bound(&mut self) -> f64 {
        self.rcond.unwrap_or(0.0)
    }

    /// Hager's estimate of `1/κ₁(P)` for the mass term `P = −M(q̄)/h` (its `‖P⁻¹‖₁` from the
    /// articulated-body solves, its `‖P‖₁` from products), once per factorization: the
    /// conditioning of what the corrections invert. A step whose mass matrix is too badly
    /// conditioned (a nearly massless chain end) is refused by it.
    fn rcond(&mut self) -> f64 {
        if let Some(r) = self.rcond {
            return r;
        }
        let [mut x, mut y, mut z] = std::mem::take(&mut self.hager);
        let mut input = std::mem::take(&mut self.product);
        self.norm1 = hager_inverse_norm1_in(&mut x, &mut y, &mut z, |v, _| {
            input.copy_from_slice(v);
            self.multiply(&input, v);
        });
        let inverse = hager_inverse_norm1_in(&mut x, &mut y, &mut z, |v, _| self.precondition(v));
        (self.hager, self.product) = ([x, y, z], input);
        let product = self.norm1 * inverse;
        let r = if product.is_finite() && product > 0.0 {
            1.0 / product
        } else {
            0.0
        };
        self.rcond = Some(r);
        r
    }
}
