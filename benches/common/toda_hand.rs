//! The periodic Toda lattice's reduced (+) equations, eq. (4.6) of Rodríguez Abella & Leok
//! (`B = 0`, group origin at the start of the step), derived and solved by hand with an `O(n)`
//! bordered-tridiagonal Newton step: the physical-limit baseline for the lattice that
//! `benches/casadi_scaling` generates with CasADi (same equations, same coordinates).
//!
//! Self-contained (`std` only, no allocation per step); its tests run standalone:
//!
//! ```text
//! rustc -O --edition 2021 --test benches/common/toda_hand.rs -o /tmp/toda && /tmp/toda
//! /tmp/toda timing --nocapture        # ns per step at n = 200, h = 0.05
//! ```
//!
//! # The system
//!
//! `n` particles of mass `m` on a line, spacing `d`, user coordinates `x_0 … x_{n−1}`,
//!
//! ```text
//! L(x, ẋ) = Σ_i m/2 ẋ_i² − Σ_{j=0}^{n−1} exp(−(x_{j+1} − x_j − d)),     x_n ≡ x_0 + n d,
//! ```
//!
//! invariant under the common translation. Adapted coordinates: group `g = x_0` (`K = 1`), shape
//! `r_i = x_i − x_0`, `i = 1 … n−1`, so `x_0 = g`, `x_i = g + r_i`. Below, shape index `s = i − 1`
//! (`s = 0 … n−2`) and bond `j` joins particles `j` and `j + 1` (bond `n − 1` joins `n − 1` and `0`).
//!
//! # Derivation of `R`, `∂R/∂z` and `w_{k+1}`
//!
//! Midpoint rule `L_d(q0, q1) = h L((q0 + q1)/2, (q1 − q0)/h)` and (+) reduction with the group
//! origin at the start of the step: `l(a, b, γ) = L_d(q0 = (0, a), q1 = (γ, b))` where `a = r_k`,
//! `b = r_{k+1}`, `γ = g_k^+` (the group increment). In user coordinates
//!
//! ```text
//! q0: x_0 = 0, x_i = a_i;        q1: x_0 = γ, x_i = γ + b_i;
//! midpoints  x̄_0 = γ/2,          x̄_i = γ/2 + ρ_i,   ρ_i = (a_i + b_i)/2;
//! velocities v_0 = γ/h,          v_i = (γ + b_i − a_i)/h.
//! ```
//!
//! The bond lengths at the midpoint do not see `γ`: with `ρ_0 = 0`, `ρ_n = n d`,
//! `s_j = x̄_{j+1} − x̄_j = ρ_{j+1} − ρ_j`, and `E_j = exp(−(s_j − d))`. So
//!
//! ```text
//! l(a, b, γ) = h Σ_{i=0}^{n−1} m/2 v_i² − h Σ_{j=0}^{n−1} E_j.
//! ```
//!
//! Since `∂s_{i−1}/∂a_i = ∂s_{i−1}/∂b_i = +1/2`, `∂s_i/∂a_i = ∂s_i/∂b_i = −1/2` and
//! `∂E_j/∂s_j = −E_j`, for `i = 1 … n−1`:
//!
//! ```text
//! ∂l/∂a_i = −m v_i + h/2 (E_{i−1} − E_i),     ∂l/∂b_i = +m v_i + h/2 (E_{i−1} − E_i),
//! ∂l/∂γ   = m/h (n γ + Σ_i (b_i − a_i))       (= total momentum Σ_i m v_i).
//! ```
//!
//! (`h/2 (E_{i−1} − E_i)` is `h/2` times the force on particle `i` at the midpoint.) With the
//! unknowns `z = (b, γ)`, the residual of eq. (4.6) is
//!
//! ```text
//! R_i = ∂l/∂a_i + w_{k,i} = −m/h (γ + b_i − a_i) + h/2 (E_{i−1} − E_i) + w_{k,i},   i = 1 … n−1,
//! R_γ = ∂l/∂γ − μ_k       =  m/h (n γ + Σ_i (b_i − a_i)) − μ_k,
//! ```
//!
//! and after the solve `w_{k+1} = ∂l/∂b` (formula above, at the solution), `μ_{k+1} = ∂l/∂γ`
//! (`= μ_k` up to the residual: the momentum map is conserved), `r_{k+1} = b`,
//! `g_{k+1} = g_k + γ`.
//!
//! The Jacobian `∂R/∂z`: `∂E_{i−1}/∂b_i = −E_{i−1}/2`, `∂E_i/∂b_i = +E_i/2`,
//! `∂E_i/∂b_{i+1} = −E_i/2`, `∂E_{i−1}/∂b_{i−1} = +E_{i−1}/2`, hence
//!
//! ```text
//! ∂R_i/∂b_i     = −m/h − h/4 (E_{i−1} + E_i),
//! ∂R_i/∂b_{i+1} = ∂R_{i+1}/∂b_i = h/4 E_i,
//! ∂R_i/∂γ       = −m/h,        ∂R_γ/∂b_i = m/h,        ∂R_γ/∂γ = n m/h.
//! ```
//!
//! So `J = [[T, −(m/h) 1], [(m/h) 1ᵀ, n m/h]]` with `T` symmetric **tridiagonal** (`(n−1)²`
//! block). In user coordinates the potential's Hessian is cyclic tridiagonal, but the periodic
//! corner (bond `n − 1` between particles `n − 1` and `0`) only involves `x_0 = g` and `r_{n−1}`:
//! in adapted coordinates bond `0` depends on `r_1` alone and bond `n − 1` on `r_{n−1}` alone, so the
//! corners of the shape block vanish and the coupling through particle `0` is carried by the
//! border — whose potential part vanishes too (translation invariance), leaving the constant
//! kinetic border above. (The dense reference in the tests builds `J` from the cyclic user-
//! coordinate Hessian and reduces it, as a check of this.)
//!
//! # The linear solve, and what it relies on
//!
//! `T = −(m/h) I − (h/4) Dᵀ diag(E) D` (`D` the bond-difference operator), so `T` is symmetric
//! negative definite and **strictly diagonally dominant by `m/h` for every `h > 0`**
//! (`|T_ss| − Σ_{t≠s} |T_st| = m/h`): the Thomas algorithm without pivoting is stable, each pivot
//! has modulus ≥ `m/h` and the multipliers have modulus < 1. The border is eliminated by the
//! Schur complement: `T y = −R_x`, `T u = (m/h) 1` (one factorization, two right-hand sides), then
//!
//! ```text
//! Δγ = (−R_γ − (m/h) 1ᵀ y) / S,   S = n m/h − (m/h) 1ᵀ u = n m/h + (m/h)² 1ᵀ T⁻¹ 1,
//! Δb = y + Δγ u,
//! ```
//!
//! and `S ∈ [m/h, n m/h]` (from `0 ≤ −(m/h) 1ᵀ T⁻¹ 1 ≤ n − 1`, since `−(m/h) T⁻¹ ⪯ I`), so the
//! border elimination is well conditioned. `O(n)` per Newton iteration.

use std::fmt;

/// Physical and numerical parameters of the periodic Toda lattice.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TodaParams {
    /// Number of particles (`n ≥ 2`; shape dimension `n − 1`).
    pub n: usize,
    /// Particle mass `m`.
    pub m: f64,
    /// Equilibrium spacing `d`.
    pub d: f64,
    /// Time step `h`.
    pub h: f64,
}

/// Reduced state `(r, w, μ, g)`: shape `r_i = x_i − x_0` (`i = 1 … n−1`), shape momenta `w`,
/// momentum map `μ` (total momentum), group `g = x_0`.
#[derive(Clone, Debug, PartialEq)]
pub struct TodaState {
    /// Shape `r` (`n − 1` entries).
    pub r: Vec<f64>,
    /// Shape momenta `w` (`n − 1` entries): particle momenta `p_1 … p_{n−1}`.
    pub w: Vec<f64>,
    /// Momentum map `μ = Σ_i p_i`.
    pub mu: f64,
    /// Group coordinate `g = x_0`.
    pub g: f64,
}

impl TodaState {
    /// From user positions `x` and velocities `v` (Legendre transform `p = m v`).
    pub fn from_positions_velocities(p: &TodaParams, x: &[f64], v: &[f64]) -> Self {
        assert!(x.len() == p.n && v.len() == p.n);
        Self {
            r: x[1..].iter().map(|xi| xi - x[0]).collect(),
            w: v[1..].iter().map(|vi| p.m * vi).collect(),
            mu: v.iter().map(|vi| p.m * vi).sum(),
            g: x[0],
        }
    }

    /// The lattice's energy `Σ p_i²/(2m) + Σ_j exp(−(x_{j+1} − x_j − d))` with `p_0 = μ − Σ w`.
    pub fn energy(&self, p: &TodaParams) -> f64 {
        let p0 = self.mu - self.w.iter().sum::<f64>();
        let kin = (p0 * p0 + self.w.iter().map(|wi| wi * wi).sum::<f64>()) / (2.0 * p.m);
        let n = p.n;
        let pos = |i: usize| if i == 0 { 0.0 } else { self.r[i - 1] };
        let mut pot = 0.0;
        for j in 0..n {
            let next = if j + 1 < n {
                pos(j + 1)
            } else {
                n as f64 * p.d
            };
            pot += (-(next - pos(j) - p.d)).exp();
        }
        kin + pot
    }
}

/// Newton did not reach the tolerance in the allowed iterations (or produced non-finite values).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NewtonFailure {
    /// `‖R‖∞` at the last iterate.
    pub residual: f64,
    /// Corrections taken.
    pub iterations: usize,
}

impl fmt::Display for NewtonFailure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "Newton failed after {} corrections (‖R‖∞ = {:.3e})",
            self.iterations, self.residual
        )
    }
}

/// Maximum Newton corrections per step.
pub const MAX_ITERATIONS: usize = 50;
/// Absolute and relative residual tolerance: `‖R‖∞ ≤ ABS_TOL + REL_TOL · max(‖w_k‖∞, |μ_k|)`.
pub const ABS_TOL: f64 = 1e-12;
/// See [`ABS_TOL`].
pub const REL_TOL: f64 = 1e-12;

/// The hand-written (+) stepper of eq. (4.6) for the periodic Toda lattice: exact analytic
/// residual and Jacobian, `O(n)` bordered-tridiagonal Newton solve; all work arrays allocated once
/// in [`TodaHand::new`].
pub struct TodaHand {
    p: TodaParams,
    /// Bond exponentials `E_j`, `j = 0 … n−1`, at the current iterate.
    e: Vec<f64>,
    /// Residual: `R_x` (`n − 1`), then `R_γ`.
    res: Vec<f64>,
    /// Iterate, stored as `(δ, γ)` with `δ = b − a = r_{k+1} − r_k`: `z = (a + δ, γ)`. The same
    /// unknowns as eq. (4.6), but resolved to the precision of the increment rather than of
    /// `r_i ≈ i d` (at `n = 200`, `ulp(r) · m/h · √n` alone exceeds the `10⁻¹²` residual
    /// tolerance: Newton on the absolute `b` stalls at `‖R‖∞ ≈ 2.5·10⁻¹²`).
    z: Vec<f64>,
    /// Diagonal of `T`; `off[s] = T_{s,s+1} = T_{s+1,s}`.
    diag: Vec<f64>,
    off: Vec<f64>,
    /// Thomas: modified super-diagonal, then the two solutions `y` (for `−R_x`) and `u` (for `(m/h) 1`).
    cp: Vec<f64>,
    y: Vec<f64>,
    u: Vec<f64>,
    /// The last two increments `(b − a, γ)` for the extrapolated guess (as `dirac`'s
    /// `integrate::reduced_guess`), and how many of them are valid.
    last: Vec<f64>,
    before: Vec<f64>,
    history: usize,
}

impl TodaHand {
    /// Allocates the work arrays for `p.n` particles.
    pub fn new(p: TodaParams) -> Self {
        assert!(p.n >= 2, "the lattice needs n ≥ 2 particles");
        assert!(p.h > 0.0 && p.m > 0.0);
        let s = p.n - 1;
        Self {
            p,
            e: vec![0.0; p.n],
            res: vec![0.0; p.n],
            z: vec![0.0; p.n],
            diag: vec![0.0; s],
            off: vec![0.0; s.saturating_sub(1)],
            cp: vec![0.0; s],
            y: vec![0.0; s],
            u: vec![0.0; s],
            last: vec![0.0; p.n],
            before: vec![0.0; p.n],
            history: 0,
        }
    }

    /// The parameters.
    pub fn params(&self) -> &TodaParams {
        &self.p
    }

    /// Forgets the increments of earlier steps (the next guess is `z = (r_k, 0)`).
    pub fn reset_history(&mut self) {
        self.history = 0;
    }

    /// Evaluates `R(z)` at the iterate `self.z = (δ, γ)`, `z = (a + δ, γ)`, into `self.res` and the
    /// Jacobian's tridiagonal block into `diag`/`off` (the border is constant: `−m/h`, `m/h`,
    /// `n m/h`); returns `‖R‖∞`.
    fn eval(&mut self, a: &[f64], w: &[f64], mu: f64) -> f64 {
        let (n, m, h) = (self.p.n, self.p.m, self.p.h);
        let ns = n - 1;
        let (mh, h2, h4) = (m / h, 0.5 * h, 0.25 * h);
        let gamma = self.z[ns];
        let delta = &self.z[..ns];
        bonds(&mut self.e, a, delta, self.p.d);
        let mut norm = 0.0f64;
        let mut sum_db = 0.0;
        for s in 0..ns {
            let db = delta[s];
            sum_db += db;
            let (el, er) = (self.e[s], self.e[s + 1]); // bonds i − 1 = s and i = s + 1
            let r = -mh * (gamma + db) + h2 * (el - er) + w[s];
            self.res[s] = r;
            norm = norm.max(r.abs());
            self.diag[s] = -mh - h4 * (el + er);
            if s + 1 < ns {
                self.off[s] = h4 * er;
            }
        }
        let rg = mh * (n as f64 * gamma + sum_db) - mu;
        self.res[ns] = rg;
        norm.max(rg.abs())
    }

    /// Solves `J Δz = −R` (bordered tridiagonal, see the module docs) and applies `z += Δz`
    /// (to the stored increment `δ` and to `γ`); returns `‖Δz‖∞ / (1 + ‖z‖∞)`, the relative size
    /// of the correction.
    fn correct(&mut self) -> f64 {
        let (n, m, h) = (self.p.n, self.p.m, self.p.h);
        let ns = n - 1;
        let mh = m / h;
        // Thomas forward sweep on T with right-hand sides −R_x (→ y) and (m/h) 1 (→ u).
        // (one division per row: |den| ≥ m/h, see the module docs)
        let mut inv = 1.0 / self.diag[0];
        self.cp[0] = if ns > 1 { self.off[0] * inv } else { 0.0 };
        self.y[0] = -self.res[0] * inv;
        self.u[0] = mh * inv;
        for s in 1..ns {
            let o = self.off[s - 1];
            inv = 1.0 / (self.diag[s] - o * self.cp[s - 1]);
            self.cp[s] = if s + 1 < ns { self.off[s] * inv } else { 0.0 };
            self.y[s] = (-self.res[s] - o * self.y[s - 1]) * inv;
            self.u[s] = (mh - o * self.u[s - 1]) * inv;
        }
        // back substitution
        let (mut sy, mut su) = (self.y[ns - 1], self.u[ns - 1]);
        for s in (0..ns - 1).rev() {
            self.y[s] -= self.cp[s] * self.y[s + 1];
            self.u[s] -= self.cp[s] * self.u[s + 1];
            sy += self.y[s];
            su += self.u[s];
        }
        // border: (m/h) 1ᵀ Δb + (n m/h) Δγ = −R_γ with Δb = y + Δγ u
        let schur = n as f64 * mh + mh * su;
        let dgamma = (-self.res[ns] - mh * sy) / schur;
        let (mut dz, mut z) = (dgamma.abs(), 0.0f64);
        for s in 0..ns {
            let d = self.y[s] + dgamma * self.u[s];
            self.z[s] += d;
            dz = dz.max(d.abs());
            z = z.max(self.z[s].abs());
        }
        self.z[ns] += dgamma;
        dz / (1.0 + z.max(self.z[ns].abs()))
    }

    /// One step of eq. (4.6) from `state`, replaced by the next state. Newton starts from the
    /// quadratic extrapolation of the last two increments (`z = (r_k, 0)` on the first step, linear
    /// on the second), stops when `‖R‖∞ ≤ 10⁻¹² + 10⁻¹² · max(‖w_k‖∞, |μ_k|)` or when a correction
    /// is below `10⁻¹² (1 + ‖z‖∞)` (the acceptance rules of dirac's Newton driver), at most
    /// [`MAX_ITERATIONS`] corrections. Returns the corrections taken.
    pub fn step(&mut self, state: &mut TodaState) -> Result<usize, NewtonFailure> {
        for s in 0..self.p.n {
            self.z[s] = match self.history {
                0 => 0.0,
                1 => self.last[s],
                _ => 2.0 * self.last[s] - self.before[s],
            };
        }
        self.solve_from_z(state)
    }

    /// One step starting Newton at the given `guess` for `z = (r_{k+1}, g_k^+)`.
    pub fn step_from(
        &mut self,
        state: &mut TodaState,
        guess: &[f64],
    ) -> Result<usize, NewtonFailure> {
        self.set_z(&state.r, guess);
        self.solve_from_z(state)
    }

    fn solve_from_z(&mut self, state: &mut TodaState) -> Result<usize, NewtonFailure> {
        let ns = self.p.n - 1;
        let rho = state
            .w
            .iter()
            .fold(state.mu.abs(), |acc, wi| acc.max(wi.abs()));
        let tol = ABS_TOL + REL_TOL * rho;
        let mut iterations = 0;
        loop {
            let norm = self.eval(&state.r, &state.w, state.mu);
            if !norm.is_finite() {
                return Err(NewtonFailure {
                    residual: norm,
                    iterations,
                });
            }
            if norm <= tol {
                break;
            }
            if iterations == MAX_ITERATIONS {
                return Err(NewtonFailure {
                    residual: norm,
                    iterations,
                });
            }
            let step = self.correct();
            iterations += 1;
            // A correction at round-off level ends the iteration, as in dirac's Newton driver
            // (at large n the residual's own rounding can exceed the tolerance).
            if step <= REL_TOL {
                self.eval(&state.r, &state.w, state.mu);
                break;
            }
        }
        // `self.e` is at the solution (the last `eval`).
        let (m, h) = (self.p.m, self.p.h);
        let (mh, h2) = (m / h, 0.5 * h);
        let gamma = self.z[ns];
        let mut sum_db = 0.0;
        std::mem::swap(&mut self.before, &mut self.last);
        for s in 0..ns {
            let db = self.z[s];
            sum_db += db;
            self.last[s] = db;
            state.w[s] = mh * (gamma + db) + h2 * (self.e[s] - self.e[s + 1]); // ∂l/∂b
            state.r[s] += db;
        }
        self.last[ns] = gamma;
        self.history = (self.history + 1).min(2);
        state.mu = mh * (self.p.n as f64 * gamma + sum_db); // ∂l/∂γ
        state.g += gamma;
        Ok(iterations)
    }

    /// Sets the iterate from `z = (b, γ)`: `δ = b − a`.
    fn set_z(&mut self, a: &[f64], z: &[f64]) {
        let ns = self.p.n - 1;
        for s in 0..ns {
            self.z[s] = z[s] - a[s];
        }
        self.z[ns] = z[ns];
    }

    /// `R(z)` at `(a, w, μ)` into `out` (`n` entries), for tests and comparisons.
    pub fn residual(&mut self, a: &[f64], w: &[f64], mu: f64, z: &[f64], out: &mut [f64]) {
        self.set_z(a, z);
        self.eval(a, w, mu);
        out.copy_from_slice(&self.res);
    }

    /// The dense Jacobian `∂R/∂z` (row-major `n × n`) assembled from the analytic tridiagonal
    /// block and border, for tests.
    pub fn jacobian_dense(&mut self, a: &[f64], w: &[f64], mu: f64, z: &[f64], out: &mut [f64]) {
        let n = self.p.n;
        let ns = n - 1;
        let mh = self.p.m / self.p.h;
        self.set_z(a, z);
        self.eval(a, w, mu);
        out.iter_mut().for_each(|v| *v = 0.0);
        for s in 0..ns {
            out[s * n + s] = self.diag[s];
            if s + 1 < ns {
                out[s * n + s + 1] = self.off[s];
                out[(s + 1) * n + s] = self.off[s];
            }
            out[s * n + ns] = -mh;
            out[ns * n + s] = mh;
        }
        out[ns * n + ns] = n as f64 * mh;
    }
}

/// The bond exponentials `E_j = exp(−(s_j − d))`, `j = 0 … n−1`, at the midpoint of `(a, a + δ)`:
/// `s_j = ρ_{j+1} − ρ_j`, `ρ_i = a_i + δ_i/2` (shape index `i − 1`), `ρ_0 = 0`, `ρ_n = n d`,
/// computed as `(a_{j+1} − a_j) + (δ_{j+1} − δ_j)/2` (the first difference is exact for
/// neighbouring positions within a factor 2 of each other).
fn bonds(e: &mut [f64], a: &[f64], delta: &[f64], d: f64) {
    let n = e.len();
    let (mut a_prev, mut d_prev) = (0.0, 0.0);
    for j in 0..n {
        let (a_next, d_next) = if j + 1 < n {
            (a[j], delta[j])
        } else {
            (n as f64 * d, 0.0)
        };
        e[j] = (d - ((a_next - a_prev) + 0.5 * (d_next - d_prev))).exp();
        (a_prev, d_prev) = (a_next, d_next);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn params(n: usize, h: f64) -> TodaParams {
        TodaParams {
            n,
            m: 1.0,
            d: 1.0,
            h,
        }
    }

    /// The brief's perturbed equilibrium: `x_i = i d + 0.1 sin(2πi/n)`,
    /// `v_i = 0.3 cos(2πi/n) + drift`.
    fn perturbed(p: &TodaParams, drift: f64) -> TodaState {
        let n = p.n;
        let x: Vec<f64> = (0..n)
            .map(|i| i as f64 * p.d + 0.1 * (2.0 * PI * i as f64 / n as f64).sin())
            .collect();
        let v: Vec<f64> = (0..n)
            .map(|i| 0.3 * (2.0 * PI * i as f64 / n as f64).cos() + drift)
            .collect();
        TodaState::from_positions_velocities(p, &x, &v)
    }

    /// A point away from any symmetry: `(a, w, μ)` from `perturbed` plus irregular offsets, and
    /// `z = (b, γ)` near a plausible step.
    fn irregular_point(p: &TodaParams) -> (Vec<f64>, Vec<f64>, f64, Vec<f64>) {
        let s = perturbed(p, 0.05);
        let ns = p.n - 1;
        let a: Vec<f64> = (0..ns)
            .map(|i| s.r[i] + 0.03 * (1.7 * i as f64 + 0.4).sin())
            .collect();
        let w: Vec<f64> = (0..ns)
            .map(|i| s.w[i] + 0.1 * (0.9 * i as f64).cos())
            .collect();
        let mut z: Vec<f64> = (0..ns)
            .map(|i| a[i] + p.h * (0.2 + 0.4 * (1.3 * i as f64 + 0.1).cos()))
            .collect();
        z.push(p.h * 0.17);
        (a, w, s.mu + 0.3, z)
    }

    /// `l(a, b, γ)` written independently, in user coordinates with the periodic wrap:
    /// `h Σ m/2 v_i² − h Σ_j exp(−(x̄_{j+1} − x̄_j − d))`.
    fn l(p: &TodaParams, a: &[f64], b: &[f64], gamma: f64) -> f64 {
        let n = p.n;
        let x0 = |i: usize| if i == 0 { 0.0 } else { a[i - 1] };
        let x1 = |i: usize| if i == 0 { gamma } else { gamma + b[i - 1] };
        let (mut kin, mut pot) = (0.0, 0.0);
        for i in 0..n {
            let v = (x1(i) - x0(i)) / p.h;
            kin += 0.5 * p.m * v * v;
            let j = (i + 1) % n;
            let wrap = if i + 1 == n { n as f64 * p.d } else { 0.0 };
            let len = 0.5 * (x0(j) + x1(j)) + wrap - 0.5 * (x0(i) + x1(i));
            pot += (-(len - p.d)).exp();
        }
        p.h * (kin - pot)
    }

    #[test]
    fn jacobian_matches_central_differences() {
        for &n in &[2usize, 3, 12] {
            let p = params(n, 0.05);
            let mut t = TodaHand::new(p);
            let (a, w, mu, z) = irregular_point(&p);
            let mut jac = vec![0.0; n * n];
            t.jacobian_dense(&a, &w, mu, &z, &mut jac);
            let scale = jac.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let (mut rp, mut rm) = (vec![0.0; n], vec![0.0; n]);
            let eps = 1e-6;
            let mut worst = 0.0f64;
            for c in 0..n {
                let mut zp = z.clone();
                let mut zm = z.clone();
                zp[c] += eps;
                zm[c] -= eps;
                t.residual(&a, &w, mu, &zp, &mut rp);
                t.residual(&a, &w, mu, &zm, &mut rm);
                for r in 0..n {
                    let fd = (rp[r] - rm[r]) / (2.0 * eps);
                    worst = worst.max((fd - jac[r * n + c]).abs() / scale);
                }
            }
            assert!(worst < 1e-8, "n = {n}: max |FD − J| / max|J| = {worst:e}");
        }
    }

    #[test]
    fn residual_and_momentum_update_are_derivatives_of_l() {
        let p = params(9, 0.05);
        let n = p.n;
        let ns = n - 1;
        let mut t = TodaHand::new(p);
        let (a, w, mu, z) = irregular_point(&p);
        let mut res = vec![0.0; n];
        t.residual(&a, &w, mu, &z, &mut res);
        let (b, gamma) = (&z[..ns], z[ns]);
        let eps = 1e-6;
        let tol = 1e-7;
        for s in 0..ns {
            let (mut ap, mut am) = (a.clone(), a.clone());
            ap[s] += eps;
            am[s] -= eps;
            let dl = (l(&p, &ap, b, gamma) - l(&p, &am, b, gamma)) / (2.0 * eps);
            assert!(
                (res[s] - (dl + w[s])).abs() < tol,
                "R_{s}: {} vs {}",
                res[s],
                dl + w[s]
            );
        }
        let dl = (l(&p, &a, b, gamma + eps) - l(&p, &a, b, gamma - eps)) / (2.0 * eps);
        assert!((res[ns] - (dl - mu)).abs() < tol);
        // w_{k+1} = ∂l/∂b and μ_{k+1} = ∂l/∂γ at the step's solution
        let mut state = TodaState {
            r: a.clone(),
            w: w.clone(),
            mu,
            g: 0.4,
        };
        t.step(&mut state).unwrap();
        let b = &state.r;
        let gamma = state.g - 0.4;
        for s in 0..ns {
            let (mut bp, mut bm) = (b.clone(), b.clone());
            bp[s] += eps;
            bm[s] -= eps;
            let dl = (l(&p, &a, &bp, gamma) - l(&p, &a, &bm, gamma)) / (2.0 * eps);
            assert!(
                (state.w[s] - dl).abs() < tol,
                "w_{s}: {} vs {dl}",
                state.w[s]
            );
        }
        let dl = (l(&p, &a, b, gamma + eps) - l(&p, &a, b, gamma - eps)) / (2.0 * eps);
        assert!((state.mu - dl).abs() < tol);
    }

    /// Straightforward dense reference: `R` and `∂R/∂z` from the cyclic user-coordinate
    /// formulation (forces and the full `n × n` Hessian of the potential, reduced by the chain
    /// rule `x_0 = g`, `x_i = g + r_i`), Gaussian elimination with partial pivoting, same tolerance.
    fn dense_step(p: &TodaParams, state: &TodaState, guess: &[f64]) -> (TodaState, usize) {
        let (n, m, h, d) = (p.n, p.m, p.h, p.d);
        let ns = n - 1;
        let a = &state.r;
        let x0 = |i: usize| if i == 0 { 0.0 } else { a[i - 1] };
        let mut z = guess.to_vec();
        let rho = state
            .w
            .iter()
            .fold(state.mu.abs(), |acc, wi| acc.max(wi.abs()));
        let tol = ABS_TOL + REL_TOL * rho;
        let eval = |z: &[f64]| -> (Vec<f64>, Vec<f64>, Vec<f64>) {
            let x1 = |i: usize| if i == 0 { z[ns] } else { z[ns] + z[i - 1] };
            let xm: Vec<f64> = (0..n).map(|i| 0.5 * (x0(i) + x1(i))).collect();
            let v: Vec<f64> = (0..n).map(|i| (x1(i) - x0(i)) / h).collect();
            let mut force = vec![0.0; n];
            let mut hess = vec![0.0; n * n];
            for j in 0..n {
                let k = (j + 1) % n;
                let wrap = if j + 1 == n { n as f64 * d } else { 0.0 };
                let e = (-(xm[k] + wrap - xm[j] - d)).exp();
                force[j] -= e; // −∂V/∂x_j
                force[k] += e;
                for (r, sr) in [(j, -1.0), (k, 1.0)] {
                    for (c, sc) in [(j, -1.0), (k, 1.0)] {
                        hess[r * n + c] += e * sr * sc;
                    }
                }
            }
            // ∂L_d/∂x0_i = −m v_i + h/2 F_i,  ∂L_d/∂x1_i = m v_i + h/2 F_i
            let mut res = vec![0.0; n];
            for s in 0..ns {
                res[s] = -m * v[s + 1] + 0.5 * h * force[s + 1] + state.w[s];
            }
            res[ns] = (0..n).map(|i| m * v[i] + 0.5 * h * force[i]).sum::<f64>() - state.mu;
            // ∂²L_d/∂x0_i∂x1_k = −(m/h) δ − h/4 H,  ∂²L_d/∂x1_i∂x1_k = (m/h) δ − h/4 H
            let d01 = |i: usize, k: usize| {
                -(if i == k { m / h } else { 0.0 }) - 0.25 * h * hess[i * n + k]
            };
            let d11 = |i: usize, k: usize| {
                (if i == k { m / h } else { 0.0 }) - 0.25 * h * hess[i * n + k]
            };
            let mut jac = vec![0.0; n * n];
            for s in 0..ns {
                for t in 0..ns {
                    jac[s * n + t] = d01(s + 1, t + 1);
                }
                jac[s * n + ns] = (0..n).map(|k| d01(s + 1, k)).sum();
            }
            for t in 0..ns {
                jac[ns * n + t] = (0..n).map(|i| d11(i, t + 1)).sum();
            }
            jac[ns * n + ns] = (0..n).map(|i| (0..n).map(|k| d11(i, k)).sum::<f64>()).sum();
            (res, jac, force)
        };
        let mut it = 0;
        loop {
            let (res, mut jac, force) = eval(&z);
            let norm = res.iter().fold(0.0f64, |acc, r| acc.max(r.abs()));
            if norm <= tol {
                let x1 = |i: usize| if i == 0 { z[ns] } else { z[ns] + z[i - 1] };
                let v: Vec<f64> = (0..n).map(|i| (x1(i) - x0(i)) / h).collect();
                let next = TodaState {
                    r: z[..ns].to_vec(),
                    w: (0..ns)
                        .map(|s| m * v[s + 1] + 0.5 * h * force[s + 1])
                        .collect(),
                    mu: (0..n).map(|i| m * v[i] + 0.5 * h * force[i]).sum(),
                    g: state.g + z[ns],
                };
                return (next, it);
            }
            assert!(it < MAX_ITERATIONS, "dense Newton did not converge");
            // Gaussian elimination with partial pivoting on [J | −R]
            let mut rhs: Vec<f64> = res.iter().map(|r| -r).collect();
            for c in 0..n {
                let piv = (c..n)
                    .max_by(|&i, &k| jac[i * n + c].abs().total_cmp(&jac[k * n + c].abs()))
                    .unwrap();
                if piv != c {
                    for k in 0..n {
                        jac.swap(c * n + k, piv * n + k);
                    }
                    rhs.swap(c, piv);
                }
                for r in c + 1..n {
                    let f = jac[r * n + c] / jac[c * n + c];
                    for k in c..n {
                        jac[r * n + k] -= f * jac[c * n + k];
                    }
                    rhs[r] -= f * rhs[c];
                }
            }
            for r in (0..n).rev() {
                let mut acc = rhs[r];
                for k in r + 1..n {
                    acc -= jac[r * n + k] * rhs[k];
                }
                rhs[r] = acc / jac[r * n + r];
            }
            for k in 0..n {
                z[k] += rhs[k];
            }
            it += 1;
        }
    }

    #[test]
    fn agrees_with_dense_newton() {
        for &(n, h) in &[(2usize, 0.05), (5, 0.05), (24, 0.05), (24, 0.3)] {
            let p = params(n, h);
            let ns = n - 1;
            let mut t = TodaHand::new(p);
            let mut state = perturbed(&p, 0.07);
            let mut last: Vec<f64> = vec![0.0; n];
            let mut worst = 0.0f64;
            for _ in 0..60 {
                let guess: Vec<f64> = (0..n)
                    .map(|s| if s < ns { state.r[s] } else { 0.0 } + last[s])
                    .collect();
                let (dense, it_dense) = dense_step(&p, &state, &guess);
                let before = state.clone();
                let it = t.step_from(&mut state, &guess).unwrap();
                assert!(it >= 1 && it_dense >= 1);
                for s in 0..ns {
                    worst = worst
                        .max((state.r[s] - dense.r[s]).abs())
                        .max((state.w[s] - dense.w[s]).abs());
                    last[s] = state.r[s] - before.r[s];
                }
                last[ns] = state.g - before.g;
                worst = worst
                    .max((state.mu - dense.mu).abs())
                    .max((state.g - dense.g).abs());
            }
            assert!(
                worst <= 1e-12,
                "n = {n}, h = {h}: hand vs dense differ by {worst:e}"
            );
        }
    }

    #[test]
    fn total_momentum_conserved_over_1000_steps() {
        let p = params(32, 0.05);
        let n = p.n as f64;
        let mut t = TodaHand::new(p);
        let mut state = perturbed(&p, 0.11);
        let mu0 = state.mu;
        assert!(mu0.abs() > 1.0, "the test needs a nonzero total momentum");
        let com = |s: &TodaState| (n * s.g + s.r.iter().sum::<f64>()) / n; // (1/n) Σ x_i
        let com0 = com(&state);
        let mut tol_sum = 0.0;
        for k in 1..=1000 {
            let rho = state
                .w
                .iter()
                .fold(state.mu.abs(), |acc, wi| acc.max(wi.abs()));
            tol_sum += ABS_TOL + REL_TOL * rho;
            t.step(&mut state).unwrap();
            // μ_{k+1} = μ_k + R_γ: drifts at most by the accumulated residual tolerance
            assert!(
                (state.mu - mu0).abs() <= tol_sum,
                "step {k}: μ = {} vs {mu0}",
                state.mu
            );
            // the centre of mass moves uniformly: Σ x_i advances by h μ/m per step
            let expect = com0 + k as f64 * p.h * mu0 / (n * p.m);
            assert!(
                (com(&state) - expect).abs() <= 1e-9 * (1.0 + expect.abs()),
                "step {k}"
            );
        }
    }

    /// Max `|H_k − H_0|` over `T = 50` time units at step `h`.
    fn energy_error(h: f64) -> f64 {
        let p = params(32, h);
        let mut t = TodaHand::new(p);
        let mut state = perturbed(&p, 0.0);
        let e0 = state.energy(&p);
        let steps = (50.0 / h).round() as usize;
        let mut worst = 0.0f64;
        for _ in 0..steps {
            t.step(&mut state).unwrap();
            worst = worst.max((state.energy(&p) - e0).abs());
        }
        worst
    }

    #[test]
    fn energy_bounded_and_second_order() {
        // 1000 steps at h = 0.05, 2000 at h/2 (same time span): a symplectic second-order method
        // keeps the energy error bounded, of size O(h²), so halving h divides it by about 4.
        let (e1, e2) = (energy_error(0.05), energy_error(0.025));
        let p = params(32, 0.05);
        let kin = {
            let s = perturbed(&p, 0.0);
            s.energy(&p) - p.n as f64 // kinetic + potential excess over equilibrium (V = n there)
        };
        assert!(
            e1 < 1e-2 * kin,
            "energy error {e1:e} vs excitation energy {kin:e}"
        );
        let ratio = e1 / e2;
        assert!(
            (3.0..5.0).contains(&ratio),
            "errors {e1:e}, {e2:e}: ratio {ratio}"
        );
    }

    /// Median over batches of ns per step at n = 200, h = 0.05 from the perturbed equilibrium;
    /// prints (run with `--nocapture`), asserts nothing about time.
    #[test]
    fn timing() {
        use std::hint::black_box;
        use std::time::Instant;
        let p = params(200, 0.05);
        let mut t = TodaHand::new(p);
        let mut state = perturbed(&p, 0.0);
        for _ in 0..200 {
            t.step(&mut state).unwrap();
        }
        let (batches, per_batch) = (9, 2000);
        let mut ns_step = Vec::with_capacity(batches);
        let mut iters = 0usize;
        for _ in 0..batches {
            let t0 = Instant::now();
            for _ in 0..per_batch {
                iters += t.step(black_box(&mut state)).unwrap();
            }
            ns_step.push(t0.elapsed().as_nanos() as f64 / per_batch as f64);
        }
        // residual + Jacobian evaluation alone, and one evaluation + bordered solve, at the state
        let n = p.n;
        let mut z: Vec<f64> = state.r.clone();
        z.push(0.001);
        let evals = 20000;
        let (mut ns_eval, mut ns_iter) = (Vec::new(), Vec::new());
        for _ in 0..batches {
            t.z.copy_from_slice(&z);
            let t0 = Instant::now();
            for i in 0..evals {
                t.z[n - 1] = 0.001 + 1e-15 * (i & 7) as f64;
                black_box(t.eval(black_box(&state.r), &state.w, state.mu));
            }
            ns_eval.push(t0.elapsed().as_nanos() as f64 / evals as f64);
            let t0 = Instant::now();
            for i in 0..evals {
                t.z.copy_from_slice(&z);
                t.z[n - 1] = 0.001 + 1e-15 * (i & 7) as f64;
                black_box(t.eval(black_box(&state.r), &state.w, state.mu));
                t.correct();
            }
            ns_iter.push(t0.elapsed().as_nanos() as f64 / evals as f64);
        }
        let median = |v: &mut Vec<f64>| {
            v.sort_by(f64::total_cmp);
            v[v.len() / 2]
        };
        println!(
            "toda-hand: n={} h={} ns_per_step={:.0} iterations_per_step={:.2} ns_per_eval={:.0} ns_per_eval_and_solve={:.0}",
            p.n,
            p.h,
            median(&mut ns_step),
            iters as f64 / (batches * per_batch) as f64,
            median(&mut ns_eval),
            median(&mut ns_iter)
        );
    }
}
