//! Newton iteration: one driver, generic over its linear solver ([`LinearSolver`]); on the
//! fixed-size nalgebra types of a step with the dense [`Lu`], without heap allocation.

use nalgebra::{SMatrix, SVector};

use crate::linalg::{checked_rcond, FactorError, LinearSolver, Lu, NewtonVector};

/// Tolerances and iteration cap of the Newton iteration that solves each step.
///
/// A step has converged when the residual satisfies
/// `‖R‖∞ ≤ abs_tol + rel_tol · ρ`, where `ρ` is the size of the momenta the residual balances
/// (`‖(w_k, μ_k)‖∞` for eq. (4.6)), or when a Newton correction satisfies
/// `‖Δz‖∞ ≤ rel_tol · (1 + ‖z‖∞)`, after which the residual is at round-off level. The defaults sit
/// near machine precision: loosening them trades the structure (momentum, symplecticity) for
/// speed, so do it deliberately.
///
/// The defaults ([`NewtonOptions::default`]): `abs_tol = 1e-12`, `rel_tol = 1e-12`,
/// `max_iterations = 50`, `min_rcond = 1e-13`.
///
/// ```
/// # use dirac_runtime::NewtonOptions;
/// let options = NewtonOptions { max_iterations: 20, ..NewtonOptions::default() };
/// assert_eq!((options.abs_tol, options.rel_tol, options.min_rcond), (1e-12, 1e-12, 1e-13));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NewtonOptions {
    /// Absolute tolerance on `‖R‖∞`, in the units of momentum.
    pub abs_tol: f64,
    /// Relative tolerance on `‖R‖∞` (against the momenta) and on the Newton correction.
    pub rel_tol: f64,
    /// Maximum number of Newton corrections per step.
    pub max_iterations: usize,
    /// Smallest acceptable reciprocal condition estimate of the step Jacobian (see
    /// [`Lu::rcond`] and [`checked_rcond`]); a step whose Jacobian is worse is an error instead of a result with few or
    /// no correct digits. Where the symmetry action is not free (e.g. spherical coordinates at a
    /// pole, the paper's Remark 7.1) the reduced equations degenerate and this is what catches it.
    pub min_rcond: f64,
}

impl NewtonOptions {
    /// The residual tolerance `abs_tol + rel_tol · ρ` for momenta of size `ρ`: what a step's
    /// `‖R‖∞` is tested against (recorded in `StepStats::tolerance`).
    pub fn residual_tolerance(&self, rho: f64) -> f64 {
        self.abs_tol + self.rel_tol * rho
    }
}

impl Default for NewtonOptions {
    fn default() -> Self {
        Self {
            abs_tol: 1e-12,
            rel_tol: 1e-12,
            max_iterations: 50,
            min_rcond: 1e-13,
        }
    }
}

/// `‖v‖∞`, NaN if any component is NaN. (nalgebra's `amax` skips NaN, which would let a NaN
/// residual pass for converged.)
#[doc(hidden)]
pub fn inf_norm<const N: usize>(v: &SVector<f64, N>) -> f64 {
    slice_inf_norm(v.as_slice())
}

/// (Written as a branch-free select and a NaN flag, so that it vectorizes: on the large
/// element-wise systems it runs three times per Newton correction.)
#[inline]
pub fn slice_inf_norm(v: &[f64]) -> f64 {
    let (mut m, mut nan) = (0.0f64, false);
    for x in v {
        let a = x.abs();
        nan |= a.is_nan();
        m = if a > m { a } else { m };
    }
    if nan {
        f64::NAN
    } else {
        m
    }
}

/// A converged solve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NewtonSolution<V> {
    /// The root `z`.
    pub z: V,
    /// Number of Newton corrections (linear solves) taken.
    pub iterations: usize,
    /// Number of Jacobians factored: fewer than `iterations` when corrections used the factors
    /// of an earlier step (chord iterations, see [`solve_with`]).
    pub factorizations: usize,
    /// `‖R(z)‖∞` at the returned `z`.
    pub residual: f64,
    /// Conditioning figure of the last Jacobian factored (see [`checked_rcond`]: a guaranteed
    /// lower bound on its reciprocal condition number, or Hager's estimate when the bound does
    /// not clear [`NewtonOptions::min_rcond`]); `None` if the initial guess already met the
    /// tolerance and no Jacobian was factored.
    pub rcond: Option<f64>,
    /// `‖J‖₁` of that Jacobian.
    pub jacobian_norm1: Option<f64>,
}

/// Why a solve failed, with the residual at the last iterate. The integrators turn it into a
/// [`crate::StepError`], which adds the step index.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum NewtonFailure {
    /// The iteration cap was reached.
    #[error(
        "Newton iteration did not converge in {iterations} iterations (residual {residual:.3e})"
    )]
    NotConverged {
        /// Corrections taken.
        iterations: usize,
        /// `‖R‖∞` at the last iterate.
        residual: f64,
    },
    /// The LU factorization found a zero pivot.
    #[error("singular Jacobian (residual {residual:.3e})")]
    Singular {
        /// `‖R‖∞` at the iterate whose Jacobian is singular.
        residual: f64,
    },
    /// The Jacobian is too ill-conditioned to trust (below [`NewtonOptions::min_rcond`]): at the
    /// solution, or at the last iterate of a solve that failed.
    #[error("ill-conditioned Jacobian (reciprocal condition estimate {rcond:.3e}, residual {residual:.3e})")]
    IllConditioned {
        /// The reciprocal condition estimate.
        rcond: f64,
        /// `‖R‖∞` at the last iterate (the solution when at most `tolerance`).
        residual: f64,
        /// The residual tolerance of the solve.
        tolerance: f64,
    },
    /// The residual, the Jacobian or the correction is not finite.
    #[error("non-finite residual, Jacobian or correction (residual {residual:.3e})")]
    NonFinite {
        /// `‖R‖∞` at the last finite iterate (infinite if there was none).
        residual: f64,
    },
}

/// Solves `R(z) = 0` from `z0` by Newton's method, on fixed-size vectors with the dense [`Lu`].
///
/// `residual` evaluates `R` alone (used to test convergence after each correction);
/// `residual_jacobian` evaluates `R` and `∂R/∂z` together (its `R` also tests the initial
/// guess). `rho` is the momentum scale of the relative residual test (see [`NewtonOptions`]).
pub fn solve<const N: usize>(
    z0: SVector<f64, N>,
    rho: f64,
    options: &NewtonOptions,
    residual: impl FnMut(&SVector<f64, N>) -> SVector<f64, N>,
    residual_jacobian: impl FnMut(&SVector<f64, N>) -> (SVector<f64, N>, SMatrix<f64, N, N>),
) -> Result<NewtonSolution<SVector<f64, N>>, NewtonFailure> {
    solve_with(
        &mut Lu::<N>::empty(),
        z0,
        rho,
        options,
        residual,
        residual_jacobian,
    )
}

/// [`solve`] with the linear solver `solver` (its factors are overwritten): the one Newton
/// driver of every step, dense or sparse.
///
/// Per correction: factor the Jacobian at the iterate, solve, update. The new iterate is then
/// tested with a real residual, from `residual` alone when Newton's quadratic model says it has
/// probably converged, and otherwise from `residual_jacobian`, whose Jacobian the next correction
/// needs anyway (so no point is evaluated twice in the usual case). The model only chooses which
/// function to call: acceptance is always the residual test (or the correction test) on a
/// freshly evaluated residual.
///
/// Chord iterations: when the solver [holds factors worth reusing](LinearSolver::has_reusable_factors)
/// (from an earlier step of the same run), the solve starts with corrections from those
/// factors and residuals alone, as long as each one shrinks the residual by at least
/// a factor 10; the first that does not switches the rest of the solve to Newton's
/// iteration with a fresh Jacobian, whose factors the next steps then reuse. Acceptance is the
/// same residual test, so only the cost changes, not what is accepted.
///
/// The conditioning of the last Jacobian factored (for a chord solve: the Jacobian whose factors
/// it used) is checked once per solve, with [`checked_rcond`].
pub fn solve_with<B: LinearSolver>(
    solver: &mut B,
    z0: B::Vector,
    rho: f64,
    options: &NewtonOptions,
    mut residual: impl FnMut(&B::Vector) -> B::Vector,
    mut residual_jacobian: impl FnMut(&B::Vector) -> (B::Vector, B::Matrix),
) -> Result<NewtonSolution<B::Vector>, NewtonFailure> {
    let mut z = z0;
    let mut r = z.clone();
    let mut jacobian = None;
    let s = solve_in(
        solver,
        &mut z,
        &mut r,
        &mut jacobian,
        rho,
        options,
        |z, r| *r = residual(z),
        |z, r, j| {
            let (r_z, j_z) = residual_jacobian(z);
            *r = r_z;
            *j = Some(j_z);
        },
    )?;
    Ok(NewtonSolution {
        z,
        iterations: s.iterations,
        factorizations: s.factorizations,
        residual: s.residual,
        rcond: s.rcond,
        jacobian_norm1: s.jacobian_norm1,
    })
}

/// The one Newton driver, in place: [`solve_with`] on buffers the caller owns, so that a step
/// on heap-backed vectors allocates nothing. `z` holds the guess and receives the root, `r` is
/// the residual's buffer (its contents on entry are ignored), `jacobian` the Jacobian's slot,
/// which `residual_jacobian(z, r, jacobian)` fills (reusing the memory of a `Some`), and
/// `residual(z, r)` writes `R(z)` into `r`. The corrections are solved in `r`
/// ([`LinearSolver::solve_in_place`]). The returned solution carries no `z` (it is in `z`).
#[allow(clippy::too_many_arguments)]
#[doc(hidden)]
pub fn solve_in<B: LinearSolver>(
    solver: &mut B,
    z: &mut B::Vector,
    r: &mut B::Vector,
    jacobian: &mut Option<B::Matrix>,
    rho: f64,
    options: &NewtonOptions,
    mut residual: impl FnMut(&B::Vector, &mut B::Vector),
    mut residual_jacobian: impl FnMut(&B::Vector, &mut B::Vector, &mut Option<B::Matrix>),
) -> Result<NewtonSolution<()>, NewtonFailure> {
    let tol = options.residual_tolerance(rho);
    // Whether corrections use the factors the solver already holds (chord iterations).
    let mut chord = solver.has_reusable_factors();
    // Whether `jacobian` holds the Jacobian at `z`, evaluated and not yet factored.
    let mut fresh = if chord {
        residual(z, r);
        false
    } else {
        residual_jacobian(z, r, jacobian);
        true
    };
    let mut norm = slice_inf_norm(r.components());
    if !norm.is_finite() {
        return Err(NewtonFailure::NonFinite {
            residual: f64::INFINITY,
        });
    }
    let mut iterations = 0;
    // Whether `solver` holds the factors of a Jacobian this solve uses.
    let mut factored = chord;
    // The relative size of the last Newton correction, for the quadratic model.
    let mut last_step: Option<f64> = None;
    let min_rcond = options.min_rcond;
    let mut factorizations = 0;
    let done = |solver: &mut B, iterations, factorizations, residual, factored: bool| {
        let rcond = factored.then(|| checked_rcond(solver, min_rcond));
        let jacobian_norm1 = factored.then(|| solver.norm1());
        match rcond {
            Some(rcond) if rcond < min_rcond => Err(NewtonFailure::IllConditioned {
                rcond,
                residual,
                tolerance: tol,
            }),
            _ => Ok(NewtonSolution {
                z: (),
                iterations,
                factorizations,
                residual,
                rcond,
                jacobian_norm1,
            }),
        }
    };
    // A failure whose last Jacobian was ill-conditioned is reported as such: that is the cause.
    let failed = |solver: &mut B, failure: NewtonFailure, factored: bool| match factored
        .then(|| checked_rcond(solver, min_rcond))
    {
        Some(rcond) if rcond < min_rcond => NewtonFailure::IllConditioned {
            rcond,
            tolerance: tol,
            residual: match failure {
                NewtonFailure::NotConverged { residual, .. }
                | NewtonFailure::Singular { residual }
                | NewtonFailure::IllConditioned { residual, .. }
                | NewtonFailure::NonFinite { residual } => residual,
            },
        },
        _ => failure,
    };
    loop {
        if norm <= tol {
            return done(solver, iterations, factorizations, norm, factored);
        }
        if iterations == options.max_iterations {
            let failure = NewtonFailure::NotConverged {
                iterations,
                residual: norm,
            };
            return Err(failed(solver, failure, factored));
        }
        if !chord {
            if !fresh {
                residual_jacobian(z, r, jacobian);
            }
            fresh = false;
            factorizations += 1;
            let j = jacobian
                .as_ref()
                .expect("residual_jacobian fills the Jacobian's slot");
            match solver.factor(j) {
                Ok(()) => factored = true,
                Err(FactorError::NonFinite) => {
                    return Err(NewtonFailure::NonFinite { residual: norm })
                }
                Err(FactorError::Singular) => {
                    return Err(NewtonFailure::Singular { residual: norm })
                }
            }
        }
        // The correction, solved in the residual's buffer.
        solver.solve_in_place(r);
        let dz = r.components();
        if dz.iter().any(|v| !v.is_finite()) {
            return Err(NewtonFailure::Singular { residual: norm });
        }
        let previous = norm;
        for (zi, di) in z.components_mut().iter_mut().zip(dz) {
            *zi -= di;
        }
        iterations += 1;
        let scale = 1.0 + slice_inf_norm(z.components());
        let step = slice_inf_norm(dz) / scale;
        let small = step <= options.rel_tol;
        if chord {
            residual(z, r);
            norm = slice_inf_norm(r.components());
            // Too slow a contraction: the old factors no longer pay; Newton from here on.
            chord = norm <= CHORD_CONTRACTION * previous;
        } else {
            // Quadratic convergence: the next correction is about `C step²`, with `C` from the
            // last two corrections (`step / last²`), or 1 (unit curvature) at the first.
            let next_step = match last_step {
                Some(last) if last > 0.0 => step / (last * last) * step * step,
                _ => step * step,
            };
            last_step = Some(step);
            if small || next_step <= PREDICTED_CONVERGENCE * options.rel_tol {
                residual(z, r);
            } else {
                residual_jacobian(z, r, jacobian);
                fresh = true;
            }
            norm = slice_inf_norm(r.components());
        }
        if !norm.is_finite() {
            return Err(failed(
                solver,
                NewtonFailure::NonFinite { residual: previous },
                factored,
            ));
        }
        if small {
            return done(solver, iterations, factorizations, norm, factored);
        }
    }
}

/// The residual reduction a chord iteration (a correction from an earlier step's factors) must
/// achieve for the next correction to use the same factors: `‖R(z⁺)‖∞ ≤ θ ‖R(z)‖∞`. A chord
/// correction costs a residual and a solve; a Newton correction on the sparse backend also costs
/// a Jacobian and a factorization, several times more, while converging quadratically. At
/// θ = 0.1 a chord solve from a guess 10⁶ tolerances off takes at most six corrections, the
/// break-even point against two Newton corrections on the 200-particle lattice.
pub(crate) const CHORD_CONTRACTION: f64 = 0.1;

/// How large (in units of `rel_tol`) the next correction predicted by Newton's quadratic model
/// may be for the new iterate to be tested with the residual alone rather than with the residual
/// and Jacobian. Only the cost depends on it: too small, a converged iterate pays for a Jacobian
/// it does not need; too large, an unconverged one pays for a residual it evaluates again.
/// Measured on the double spherical pendulum's paper run (residual evaluations per step, from
/// the integrator's guess / from the CasADi driver's guess `(x_k, 0)`): 1e3 gives 1.49 / 2.02
/// residuals and 1.50 / 3.03 Jacobians, 1e-4 gives 1.13 / 1.04 and 1.51 / 3.03, 1e-6 gives
/// 0.88 / 0.95 and 1.69 / 3.09; a Jacobian costs about 2.5 residuals.
pub(crate) const PREDICTED_CONVERGENCE: f64 = 1e-4;

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Matrix2, Vector2};

    #[test]
    fn solves_a_nonlinear_system_quadratically() {
        // x² + y² = 4, x = y: root (√2, √2).
        let f = |z: &Vector2<f64>| Vector2::new(z[0] * z[0] + z[1] * z[1] - 4.0, z[0] - z[1]);
        let fj = |z: &Vector2<f64>| (f(z), Matrix2::new(2.0 * z[0], 2.0 * z[1], 1.0, -1.0));
        let sol = solve(
            Vector2::new(1.0, 0.5),
            1.0,
            &NewtonOptions::default(),
            f,
            fj,
        )
        .unwrap();
        assert!((sol.z[0] - 2f64.sqrt()).abs() < 1e-14);
        assert!((sol.z[1] - 2f64.sqrt()).abs() < 1e-14);
        assert!(sol.iterations <= 7, "{} iterations", sol.iterations);
    }

    /// The dense `Lu` offering its factors for reuse, as the sparse backend does.
    struct Reusing(Lu<2>, bool);

    impl LinearSolver for Reusing {
        type Vector = Vector2<f64>;
        type Matrix = Matrix2<f64>;
        fn factor(&mut self, j: &Matrix2<f64>) -> Result<(), FactorError> {
            self.1 = false;
            LinearSolver::factor(&mut self.0, j)?;
            self.1 = true;
            Ok(())
        }
        fn solve(&mut self, b: &Vector2<f64>) -> Vector2<f64> {
            self.0.solve(b)
        }
        fn norm1(&self) -> f64 {
            self.0.norm1()
        }
        fn rcond_lower_bound(&mut self) -> f64 {
            self.0.rcond_lower_bound()
        }
        fn rcond(&mut self) -> f64 {
            self.0.rcond()
        }
        fn has_reusable_factors(&self) -> bool {
            self.1
        }
    }

    #[test]
    fn chord_iterations_reuse_good_factors_and_drop_bad_ones() {
        // x² + y² = c, x = y: root (√(c/2), √(c/2)); Jacobian [[2x, 2y], [1, −1]].
        let system = |c: f64| {
            let f =
                move |z: &Vector2<f64>| Vector2::new(z[0] * z[0] + z[1] * z[1] - c, z[0] - z[1]);
            let fj =
                move |z: &Vector2<f64>| (f(z), Matrix2::new(2.0 * z[0], 2.0 * z[1], 1.0, -1.0));
            (f, fj)
        };
        let options = NewtonOptions::default();
        let mut solver = Reusing(Lu::empty(), false);
        let (f, fj) = system(4.0);
        let first = solve_with(&mut solver, Vector2::new(1.0, 0.5), 4.0, &options, f, fj).unwrap();
        assert_eq!(first.factorizations, first.iterations);
        // A nearby problem from a nearby guess: the old factors contract fast, none is formed.
        let (f, fj) = system(4.0001);
        let root = (4.0001f64 / 2.0).sqrt();
        let near = solve_with(&mut solver, first.z, 4.0, &options, f, fj).unwrap();
        assert_eq!(near.factorizations, 0, "{near:?}");
        assert!((near.z[0] - root).abs() < 1e-14 && (near.z[1] - root).abs() < 1e-14);
        // A far problem: the old factors contract too slowly, so Newton takes over and converges.
        let (f, fj) = system(400.0);
        let root = 200f64.sqrt();
        let far = solve_with(&mut solver, first.z, 400.0, &options, f, fj).unwrap();
        assert!(far.factorizations >= 1, "{far:?}");
        assert!((far.z[0] - root).abs() < 1e-12 && (far.z[1] - root).abs() < 1e-12);
        assert!(far.iterations <= 12, "{far:?}");
    }

    #[test]
    fn a_nan_residual_is_never_converged() {
        let f = |z: &Vector2<f64>| Vector2::new(z[0] - 1.0, (z[1] - 2.0).sqrt() * 0.0 + f64::NAN);
        let fj = |z: &Vector2<f64>| (f(z), Matrix2::identity());
        let err = solve(Vector2::zeros(), 1.0, &NewtonOptions::default(), f, fj).unwrap_err();
        assert!(matches!(err, NewtonFailure::NonFinite { .. }), "{err:?}");
        assert!(inf_norm(&Vector2::new(1.0, f64::NAN)).is_nan());
        assert!(inf_norm(&Vector2::new(f64::NAN, 1.0)).is_nan());
    }

    #[test]
    fn reports_a_singular_jacobian() {
        let f = |z: &Vector2<f64>| Vector2::new(z[0] + z[1] - 1.0, z[0] + z[1] - 2.0);
        let fj = |z: &Vector2<f64>| (f(z), Matrix2::new(1.0, 1.0, 1.0, 1.0));
        let err = solve(Vector2::zeros(), 1.0, &NewtonOptions::default(), f, fj).unwrap_err();
        assert!(
            matches!(err, NewtonFailure::Singular { residual } if residual == 2.0),
            "{err:?}"
        );
    }

    #[test]
    fn reports_non_convergence_with_the_last_residual() {
        // z³ − 2z + 2 = 0 from z = 0 cycles 0 → 1 → 0 → … (a classic Newton 2-cycle).
        let f =
            |z: &nalgebra::Vector1<f64>| nalgebra::Vector1::new(z[0].powi(3) - 2.0 * z[0] + 2.0);
        let fj =
            |z: &nalgebra::Vector1<f64>| (f(z), nalgebra::Matrix1::new(3.0 * z[0] * z[0] - 2.0));
        let options = NewtonOptions {
            max_iterations: 8,
            ..NewtonOptions::default()
        };
        let err = solve(nalgebra::Vector1::zeros(), 1.0, &options, f, fj).unwrap_err();
        assert_eq!(
            err,
            NewtonFailure::NotConverged {
                iterations: 8,
                residual: 2.0
            }
        );
    }
}
