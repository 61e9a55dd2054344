//! The linear algebra of a Newton step, behind one trait ([`LinearSolver`]) with one backend per
//! file: the dense fixed-size [`Lu`] ([`dense`]) for systems of at most [`DENSE_MAX`]
//! coordinates, and the sparse [`SparseLu`] ([`sparse`]) on the compile-time sparsity pattern of
//! the step Jacobian above. The Newton driver ([`crate::newton`]) is generic over the trait, so
//! every integrator runs on either backend (the separation of SUNDIALS/KINSOL and diffsol).
//!
//! The choice is made by the compiler from the size of the system, with the same constant:
//! `dirac-compiler` does not depend on this crate (it runs inside rustc, before it), so it keeps
//! its own copy of [`DENSE_MAX`], and `tests/large_systems.rs` fails if the two part (it checks
//! the backend emitted at `N = DENSE_MAX` and `N = DENSE_MAX + 1` against this constant).

/// The conditioning methods of a heap-backed [`LinearSolver`] whose only check is Hager's
/// estimate (none cheaper is readable from its factors), written once for the backends that
/// share them: [`LinearSolver::rcond_lower_bound`] is the estimate once made (0 before, so the
/// step is checked with [`LinearSolver::rcond`]), and [`LinearSolver::rcond`] makes it, once per
/// factorization ([`HagerCache`]). The backend has the fields `hager: HagerCache`,
/// `factored: bool` and `norm1: f64`; `$solve(backend, x, transpose)` overwrites `x` with
/// `A⁻¹ x` (`A⁻ᵀ x`).
macro_rules! hager_conditioning {
    ($solve:expr) => {
        fn norm1(&self) -> f64 {
            self.norm1
        }

        fn rcond_lower_bound(&mut self) -> f64 {
            self.hager.cached().unwrap_or(0.0)
        }

        fn rcond(&mut self) -> f64 {
            let norm1 = self.factored.then_some(self.norm1);
            HagerCache::rcond(self, |solver| &mut solver.hager, norm1, $solve)
        }
    };
}

/// The [`LinearSolver`] items shared by the solvers of run-time-sized systems, on `DVector`s: a
/// type with `solve_slice(x, transpose)` (overwriting `x` with `A⁻¹ x` or `A⁻ᵀ x`), the fields of
/// [`hager_conditioning`] and `factored`, whose factors chord iterations reuse once a
/// factorization succeeded (a factorization costs several residual evaluations).
macro_rules! dvector_solves {
    () => {
        fn solve(&mut self, b: &nalgebra::DVector<f64>) -> nalgebra::DVector<f64> {
            let mut x = b.clone();
            self.solve_slice(x.as_mut_slice(), false);
            x
        }

        fn solve_in_place(&mut self, b: &mut nalgebra::DVector<f64>) {
            self.solve_slice(b.as_mut_slice(), false);
        }

        // No bound is readable from the factors: a step is checked with Hager's estimate,
        // once per factorization.
        hager_conditioning!(Self::solve_slice);

        fn has_reusable_factors(&self) -> bool {
            self.factored
        }
    };
}

pub mod banded;
pub mod dense;
pub mod iterative;
pub mod sparse;

use nalgebra::SVector;

pub use banded::BandedLu;
pub use dense::Lu;
pub use iterative::Pcg;
pub use sparse::{
    CscBuffer, CscPattern, CscValues, DynPatternLu, DynSparseLu, PatternLu, SparseLu,
};

/// Systems with at most this many configuration coordinates get the dense fixed-size backend
/// ([`crate::Lu`], everything on the stack, unrolled); larger ones the sparse backend. The compiler
/// chooses by this size, not the user: at 16 unknowns a dense factorization is ≈ 1.5 k flops and
/// its matrix 2 KiB, beyond which the dense path's cost (`N³/3` flops, `8 N²` bytes of stack per
/// copy) grows faster than a sparse factorization of a mechanical system's Jacobian.
pub const DENSE_MAX: usize = 16;

/// Whether `bytes` bytes can be allocated now: reserved once, untouched, and released, so that a
/// size the allocator, the kernel or an address-space limit (`ulimit -v`) refuses is found before
/// anything is built (and reported as a typed error) instead of aborting the process on the
/// first allocation that fails. Counted in `u128` by the callers, so that no size overflows.
///
/// ```
/// assert!(dirac_runtime::linalg::allocatable(1 << 10));
/// assert!(!dirac_runtime::linalg::allocatable(u128::MAX));
/// ```
pub fn allocatable(bytes: u128) -> bool {
    usize::try_from(bytes)
        .ok()
        .filter(|&b| b <= isize::MAX as usize)
        .is_some_and(|b| Vec::<u8>::new().try_reserve_exact(b).is_ok())
}

/// Why a matrix could not be factored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FactorError {
    /// An entry is NaN or infinite.
    NonFinite,
    /// A pivot is exactly zero (the matrix is singular), or the elimination overflowed.
    Singular,
}

/// The unknowns and residuals of a Newton iteration: whatever holds its components contiguously
/// (fixed-size `SVector` for the small dense systems of a step, `DVector` for large ones).
#[doc(hidden)]
pub trait NewtonVector: Clone {
    /// The components.
    fn components(&self) -> &[f64];
    /// The components, mutably.
    fn components_mut(&mut self) -> &mut [f64];
}

impl<const N: usize> NewtonVector for SVector<f64, N> {
    fn components(&self) -> &[f64] {
        self.as_slice()
    }
    fn components_mut(&mut self) -> &mut [f64] {
        self.as_mut_slice()
    }
}

impl NewtonVector for nalgebra::DVector<f64> {
    fn components(&self) -> &[f64] {
        self.as_slice()
    }
    fn components_mut(&mut self) -> &mut [f64] {
        self.as_mut_slice()
    }
}

/// The linear solver the Newton driver is generic over (the separation of SUNDIALS/KINSOL): it
/// factors a Jacobian, solves with the factors, and reports the conditioning figures the step
/// is checked with. It is a workspace: `factor` overwrites the previous factors in place, so a
/// backend that needs memory (the sparse [`crate::SparseLu`]: its symbolic analysis, fill and
/// scratch) allocates it once, when it is built, and reuses it across Newton iterations and
/// steps. [`Lu`] is the dense fixed-size backend, whose factors live on the stack.
pub trait LinearSolver {
    /// The vector type of residuals and corrections.
    type Vector: NewtonVector;
    /// The Jacobian type, as the step functions return it.
    type Matrix;
    /// Factors `j`, replacing the previous factors.
    fn factor(&mut self, j: &Self::Matrix) -> Result<(), FactorError>;
    /// Solves `J x = b` with the current factors.
    fn solve(&mut self, b: &Self::Vector) -> Self::Vector;
    /// Solves `J x = b` with the current factors, overwriting `b` with `x` (a backend on heap
    /// vectors solves without allocating).
    fn solve_in_place(&mut self, b: &mut Self::Vector) {
        *b = self.solve(b);
    }
    /// `‖J‖₁` of the factored Jacobian.
    fn norm1(&self) -> f64;
    /// A cheap guaranteed lower bound on `1 / (‖J‖₁ ‖J⁻¹‖₁)` (0 where a backend has none).
    fn rcond_lower_bound(&mut self) -> f64;
    /// The (more expensive, more accurate) estimate of `1 / (‖J‖₁ ‖J⁻¹‖₁)`.
    fn rcond(&mut self) -> f64;
    /// Whether a solve should first try the factors this workspace holds (of a Jacobian from an
    /// earlier step) before evaluating and factoring a new one: chord iterations, see
    /// [`crate::newton::solve_with`]. The sparse backend says yes once it holds factors, because there a
    /// factorization costs many residual evaluations; the dense fixed-size [`Lu`] never (the
    /// default), because there it costs less than one.
    fn has_reusable_factors(&self) -> bool {
        false
    }
}

/// How far above [`crate::NewtonOptions::min_rcond`] the cheap lower bound must be for the estimator to
/// be skipped: a margin for the round-off of the estimate itself, whose solves carry a relative
/// error up to `κ ε` (≈ 1e-3 at the default threshold).
pub(crate) const RCOND_CLEARANCE: f64 = 2.0;

/// The conditioning figure a step is checked with: the guaranteed lower bound
/// [`LinearSolver::rcond_lower_bound`] when it clears `min_rcond` by a factor 2 (the
/// step is then certainly well enough conditioned, and Hager's estimate — never below the true
/// value up to its round-off — would have passed it too), otherwise Hager's estimate
/// [`LinearSolver::rcond`]. So a step is refused exactly when Hager's estimate is below
/// `min_rcond`, as if it ran on every step, while healthy steps pay for one extra solve instead
/// of up to ten.
#[doc(hidden)]
pub fn checked_rcond<B: LinearSolver>(factors: &mut B, min_rcond: f64) -> f64 {
    let bound = factors.rcond_lower_bound();
    if bound >= RCOND_CLEARANCE * min_rcond {
        bound
    } else {
        factors.rcond()
    }
}

/// `1 / (‖A‖₁ ‖A⁻¹‖₁)`, or 0 when either norm is zero or not finite (a singular or broken
/// factorization is never reported as well conditioned).
pub(crate) fn reciprocal_condition(norm1: f64, inverse_norm1: f64) -> f64 {
    let product = norm1 * inverse_norm1;
    if product.is_finite() && product > 0.0 {
        1.0 / product
    } else {
        0.0
    }
}

/// Hager's estimate of `‖A⁻¹‖₁` (Higham, *Accuracy and Stability of Numerical Algorithms*,
/// Alg. 15.1) from solves with the factors of `A`: `solve(x, false)` overwrites `x` with
/// `A⁻¹ x`, `solve(x, true)` with `A⁻ᵀ x`. At most five iterations of two solves; the result is
/// a lower bound on `‖A⁻¹‖₁` (up to the round-off of the solves), almost always within a small
/// factor of it. Shared by the dense [`Lu`] and the sparse [`crate::SparseLu`].
pub(crate) fn hager_inverse_norm1<const N: usize>(
    mut solve: impl FnMut(&mut SVector<f64, N>, bool),
) -> f64 {
    let mut x = SVector::<f64, N>::repeat(1.0 / N as f64);
    let mut estimate = 0.0;
    for _ in 0..5 {
        let mut y = x;
        solve(&mut y, false);
        estimate = y.iter().map(|v| v.abs()).sum::<f64>();
        let mut z = y.map(|v| if v >= 0.0 { 1.0 } else { -1.0 });
        solve(&mut z, true);
        let j = z.iamax();
        let zj = z[j].abs();
        if zj <= z.dot(&x) {
            break;
        }
        x = SVector::zeros();
        x[j] = 1.0;
    }
    estimate
}

/// Hager's estimate of `‖A⁻¹‖₁` (Higham, *Accuracy and Stability of Numerical Algorithms*,
/// Alg. 15.1) on slices of length `n` (the scratch `x`, `y`, `z`): `solve(x, false)` overwrites
/// `x` with `A⁻¹ x`, `solve(x, true)` with `A⁻ᵀ x`. Given products with `A` instead of solves, it
/// estimates `‖A‖₁`. For the sparse backend, whose scratch is allocated once per workspace, and
/// for a [`LinearSolver`] of another crate that solves without forming its matrix (the
/// articulated-body solve of a tree's mass matrix). (The dense backend keeps its own fixed-size
/// copy: nalgebra's `dot` sums in another order, and the dense results stay bit for bit what
/// they were.)
pub fn hager_inverse_norm1_in(
    x: &mut [f64],
    y: &mut [f64],
    z: &mut [f64],
    mut solve: impl FnMut(&mut [f64], bool),
) -> f64 {
    let n = x.len();
    x.fill(1.0 / n as f64);
    let mut estimate = 0.0;
    for _ in 0..5 {
        y.copy_from_slice(x);
        solve(y, false);
        estimate = y.iter().map(|v| v.abs()).sum::<f64>();
        for (zi, yi) in z.iter_mut().zip(y.iter()) {
            *zi = if *yi >= 0.0 { 1.0 } else { -1.0 };
        }
        solve(z, true);
        // The first index of the largest |z_j|, as nalgebra's `iamax`.
        let mut j = 0;
        for (i, v) in z.iter().enumerate() {
            if v.abs() > z[j].abs() {
                j = i;
            }
        }
        let zj = z[j].abs();
        let ztx: f64 = z.iter().zip(x.iter()).map(|(a, b)| a * b).sum();
        if zj <= ztx {
            break;
        }
        x.fill(0.0);
        x[j] = 1.0;
    }
    estimate
}

/// The `Debug` text of a heap-backed solver: its `name`, size `n`, the `fields` that describe
/// it and whether it holds factors; its buffers are left out.
fn debug_solver(
    f: &mut std::fmt::Formatter<'_>,
    name: &str,
    n: usize,
    fields: &[(&str, &dyn std::fmt::Debug)],
    factored: bool,
) -> std::fmt::Result {
    let mut text = f.debug_struct(name);
    text.field("n", &n);
    for (field, value) in fields {
        text.field(field, value);
    }
    text.field("factored", &factored).finish_non_exhaustive()
}

/// Hager's estimate of `1 / κ₁(A)` for a heap-backed solver ([`hager_inverse_norm1_in`] over
/// [`reciprocal_condition`]), made at most once per factorization — chord iterations check the
/// same factors at every step — in scratch allocated once with the solver.
#[derive(Clone, Debug, Default)]
pub(crate) struct HagerCache {
    /// The estimator's three vectors of length `n`.
    scratch: [Vec<f64>; 3],
    /// The estimate for the current factors, once made.
    rcond: Option<f64>,
}

impl HagerCache {
    /// The cache of an `n × n` solver, empty.
    pub(crate) fn new(n: usize) -> Self {
        Self {
            scratch: [vec![0.0; n], vec![0.0; n], vec![0.0; n]],
            rcond: None,
        }
    }

    /// Forgets the estimate: the factors changed.
    pub(crate) fn clear(&mut self) {
        self.rcond = None;
    }

    /// The start of a factorization of the CSC values `values` (column starts `col_ptr`), on a
    /// backend of [`hager_conditioning`]: the old factors (`factored`) and their estimate
    /// forgotten, and `‖A‖₁` with the finiteness test of [`column_norm1`].
    pub(crate) fn refactor(
        &mut self,
        factored: &mut bool,
        col_ptr: &[usize],
        values: &[f64],
    ) -> Result<f64, FactorError> {
        *factored = false;
        self.clear();
        column_norm1(col_ptr, values)
    }

    /// The estimate for the current factors, if made.
    pub(crate) fn cached(&self) -> Option<f64> {
        self.rcond
    }

    /// The estimate for the factors `solver` holds: 0 when `norm1` is `None` (no factorization
    /// succeeded), else the cached one, or the one made now and cached. `cache` finds `solver`'s
    /// own cache; `solve(solver, x, transpose)` overwrites `x` with `A⁻¹ x` (`A⁻ᵀ x`).
    pub(crate) fn rcond<T>(
        solver: &mut T,
        cache: impl Fn(&mut T) -> &mut Self,
        norm1: Option<f64>,
        mut solve: impl FnMut(&mut T, &mut [f64], bool),
    ) -> f64 {
        let Some(norm1) = norm1 else {
            return 0.0;
        };
        let own = cache(solver);
        if let Some(rcond) = own.rcond {
            return rcond;
        }
        let mut scratch = std::mem::take(&mut own.scratch);
        let [x, y, z] = &mut scratch;
        let estimate = hager_inverse_norm1_in(x, y, z, |v, transpose| solve(solver, v, transpose));
        let rcond = reciprocal_condition(norm1, estimate);
        let own = cache(solver);
        own.scratch = scratch;
        own.rcond = Some(rcond);
        rcond
    }
}

/// `‖A‖₁` of the CSC values `values` with column starts `col_ptr`, and a finiteness test of every
/// entry (a column sum is finite iff its terms are).
pub(crate) fn column_norm1(col_ptr: &[usize], values: &[f64]) -> Result<f64, FactorError> {
    let mut norm1 = 0.0f64;
    for c in 0..col_ptr.len() - 1 {
        let sum: f64 = values[col_ptr[c]..col_ptr[c + 1]]
            .iter()
            .map(|v| v.abs())
            .sum();
        if !sum.is_finite() {
            return Err(FactorError::NonFinite);
        }
        norm1 = norm1.max(sum);
    }
    Ok(norm1)
}
