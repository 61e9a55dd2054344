//! The step Jacobian's solver of an element-wise run, chosen by the pattern's structure
//! ([`StepSolver`]): a banded LU when a reverse Cuthill–McKee ordering makes the pattern a narrow
//! band (chains, lattices, rings, arrays coupled element by element), conjugate gradients for
//! large multi-dimensional symmetric Jacobians, a dense LU with partial pivoting for small
//! patterns too wide for the band (an element reading every coordinate: the element view of a
//! flat system), faer's sparse LU otherwise (pairs, large grids), with the fallback from conjugate
//! gradients to the LU.

use nalgebra::DVector;

use super::StepSolver;
use crate::linalg::{
    BandedLu, CscBuffer, DynPatternLu, DynSparseLu, FactorError, LinearSolver, Pcg,
};

/// The smallest number of unknowns for which [`StepSolver::Auto`] solves a multi-dimensional
/// pattern (at least [`ITERATIVE_MIN_ENTRIES_PER_ROW`] entries per row, as a 2-D grid's 7) by
/// conjugate gradients. Measured on the membrane of `examples/wave2d.rs` at 316 × 316: the
/// sparse LU's first factorization takes ≈ 2 s and 0.6 GB of fill, its later steps ≈ 34 ms; see
/// BENCHMARKS.md for CG's figures. A lattice (3 entries per row) factors in linear time and
/// keeps the LU.
pub const ITERATIVE_MIN_DIM: usize = 20_000;

/// See [`ITERATIVE_MIN_DIM`].
pub const ITERATIVE_MIN_ENTRIES_PER_ROW: usize = 5;

/// The widest band (`k_l + k_u` after the reverse Cuthill–McKee ordering) that
/// [`StepSolver::Auto`] solves with the banded LU: a factorization costs about
/// `n k_l (k_l + k_u)` flops, below the sparse LU's symbolic bookkeeping for such bands and above
/// it for wider ones (a 2-D grid's band is its side).
pub const BANDED_MAX_WIDTH: usize = 16;

/// The most unknowns for which [`StepSolver::Auto`] (and a constrained step's saddle-point
/// system) factors a pattern too wide for the banded LU ([`BANDED_MAX_WIDTH`]) densely, by an LU
/// with partial pivoting in memory allocated once ([`DynPatternLu::dense`]), when at least
/// `1 /` [`DENSE_MIN_FILL`] of its entries are structural nonzeros: `n³/3` flops with no
/// symbolic bookkeeping and no indirection, against faer's sparse LU's supernodal machinery,
/// which wins only on large or sparse patterns.
///
/// Measured (one factorization and one solve, release, the 2-core machine under load 2–3,
/// `dense_against_sparse_factorization_times`; dense / sparse, scattered patterns with the
/// diagonal):
///
/// | n | full | half full | a quarter full | a tenth full |
/// | --- | --- | --- | --- | --- |
/// | 16 | 1.5 / 5.3 µs | 2.0 / 5.7 µs | 1.6 / 3.0 µs | 0.8 / 3.1 µs |
/// | 32 | 9.4 / 28 µs | 14 / 31 µs | 9.7 / 15 µs | 8.8 / 12 µs |
/// | 48 | 28 / 78 µs | 44 / 100 µs | 35 / 48 µs | 33 / 28 µs |
/// | 64 | 99 / 174 µs | 109 / 227 µs | 86 / 111 µs | 49 / 60 µs |
/// | 96 | 207 / 547 µs | 329 / 776 µs | 376 / 377 µs | 248 / 226 µs |
/// | 128 | 705 / 258 µs | 821 / 189 µs | 691 / 684 µs | 752 / 467 µs |
///
/// The dense LU wins by 2–3.5 × on full and half-full patterns up to 96 unknowns and loses
/// beyond (faer's supernodes), by 1.3–2 × at a quarter full up to 32, evenly at a tenth: 64
/// unknowns and a quarter full keep a margin on both sides.
pub const DENSE_MAX_DIM: usize = 64;

/// See [`DENSE_MAX_DIM`]: a pattern of `n ≤ DENSE_MAX_DIM` unknowns is factored densely when
/// `DENSE_MIN_FILL · nnz ≥ n²`.
pub const DENSE_MIN_FILL: usize = 4;

/// Whether [`StepSolver::Auto`] factors an `n × n` pattern of `nnz` entries, too wide for the
/// band, densely ([`DENSE_MAX_DIM`]).
fn dense_wins(n: usize, nnz: usize) -> bool {
    n <= DENSE_MAX_DIM && nnz.saturating_mul(DENSE_MIN_FILL) >= n * n
}

/// The step Jacobian's solver of an element-wise run ([`StepSolver`]): the sparse LU, or conjugate
/// gradients on a symmetric definite Jacobian, falling back to the LU for good when the
/// Jacobian turns out not to be symmetric or CG breaks down.
#[derive(Debug)]
#[doc(hidden)]
pub enum ElementSolver {
    /// The banded LU on a reverse Cuthill–McKee ordering.
    Banded(Box<BandedLu>),
    /// faer's sparse LU.
    Direct(Box<DynSparseLu>),
    /// A dense LU with partial pivoting of the pattern's values scattered into a full matrix.
    Dense(Box<DenseStep>),
    /// Jacobi-preconditioned conjugate gradients, with the pattern to fall back on.
    Iterative(Box<Pcg>, Vec<usize>, Vec<usize>),
}

impl ElementSolver {
    pub(super) fn new(n: usize, col_ptr: &[usize], row_idx: &[usize], linear: StepSolver) -> Self {
        let iterative = match linear {
            StepSolver::Direct | StepSolver::Banded => false,
            StepSolver::Iterative => true,
            StepSolver::Auto => {
                n >= ITERATIVE_MIN_DIM && row_idx.len() >= ITERATIVE_MIN_ENTRIES_PER_ROW * n
            }
        };
        if let Some(cg) = iterative.then(|| Pcg::new(n, col_ptr, row_idx)).flatten() {
            return ElementSolver::Iterative(Box::new(cg), col_ptr.to_vec(), row_idx.to_vec());
        }
        let max_width = match linear {
            StepSolver::Auto => Some(BANDED_MAX_WIDTH),
            StepSolver::Banded => Some(usize::MAX),
            StepSolver::Direct | StepSolver::Iterative => None,
        };
        // A band too wide to store falls back to the sparse LU.
        if let Some(banded) = max_width.and_then(|w| BandedLu::within(n, col_ptr, row_idx, w)) {
            return ElementSolver::Banded(Box::new(banded));
        }
        if linear == StepSolver::Auto && dense_wins(n, row_idx.len()) {
            return ElementSolver::Dense(Box::new(DenseStep::new(n, col_ptr, row_idx)));
        }
        ElementSolver::Direct(Box::new(DynSparseLu::new(
            n,
            col_ptr.to_vec(),
            row_idx.to_vec(),
        )))
    }

    /// The solver of a saddle-point (KKT) system of a constrained step: the banded LU when the
    /// reordered band is narrow ([`BANDED_MAX_WIDTH`]), the dense LU when the system is small
    /// and dense enough ([`DENSE_MAX_DIM`]; partial pivoting handles the zero block), the sparse
    /// LU otherwise (conjugate gradients do not apply to an indefinite system).
    pub(super) fn saddle(n: usize, col_ptr: &[usize], row_idx: &[usize]) -> Self {
        if let Some(banded) = BandedLu::within(n, col_ptr, row_idx, BANDED_MAX_WIDTH) {
            ElementSolver::Banded(Box::new(banded))
        } else if dense_wins(n, row_idx.len()) {
            ElementSolver::Dense(Box::new(DenseStep::new(n, col_ptr, row_idx)))
        } else {
            ElementSolver::Direct(Box::new(DynSparseLu::new(
                n,
                col_ptr.to_vec(),
                row_idx.to_vec(),
            )))
        }
    }

    /// Which solver this is: `"banded LU"`, `"dense LU"`, `"sparse LU"` or `"conjugate
    /// gradients (Jacobi)"`.
    pub fn name(&self) -> &'static str {
        match self {
            ElementSolver::Banded(_) => "banded LU",
            ElementSolver::Dense(_) => "dense LU",
            ElementSolver::Direct(_) => "sparse LU",
            ElementSolver::Iterative(..) => "conjugate gradients (Jacobi)",
        }
    }
}

impl LinearSolver for ElementSolver {
    type Vector = DVector<f64>;
    type Matrix = Vec<f64>;
    fn factor(&mut self, j: &Vec<f64>) -> Result<(), FactorError> {
        match self {
            ElementSolver::Banded(lu) => lu.factor(j),
            ElementSolver::Direct(lu) => lu.factor(j),
            ElementSolver::Dense(lu) => lu.factor(j),
            ElementSolver::Iterative(cg, col_ptr, row_idx) => match cg.factor(j) {
                Ok(()) => Ok(()),
                Err(FactorError::NonFinite) => Err(FactorError::NonFinite),
                // Not symmetric: the LU from now on (built once, here).
                Err(FactorError::Singular) => {
                    let n = col_ptr.len() - 1;
                    let mut lu =
                        DynSparseLu::new(n, std::mem::take(col_ptr), std::mem::take(row_idx));
                    let result = lu.factor(j);
                    *self = ElementSolver::Direct(Box::new(lu));
                    result
                }
            },
        }
    }
    fn solve(&mut self, b: &DVector<f64>) -> DVector<f64> {
        let mut x = b.clone();
        self.solve_in_place(&mut x);
        x
    }
    fn solve_in_place(&mut self, b: &mut DVector<f64>) {
        match self {
            ElementSolver::Banded(lu) => lu.solve_in_place(b),
            ElementSolver::Direct(lu) => lu.solve_in_place(b),
            ElementSolver::Dense(lu) => lu.solve_in_place(b),
            ElementSolver::Iterative(cg, ..) => cg.solve_in_place(b),
        }
    }
    fn norm1(&self) -> f64 {
        match self {
            ElementSolver::Banded(lu) => lu.norm1(),
            ElementSolver::Direct(lu) => lu.norm1(),
            ElementSolver::Dense(lu) => lu.norm1(),
            ElementSolver::Iterative(cg, ..) => cg.norm1(),
        }
    }
    fn rcond_lower_bound(&mut self) -> f64 {
        match self {
            ElementSolver::Banded(lu) => lu.rcond_lower_bound(),
            ElementSolver::Direct(lu) => lu.rcond_lower_bound(),
            ElementSolver::Dense(lu) => lu.rcond_lower_bound(),
            ElementSolver::Iterative(cg, ..) => cg.rcond_lower_bound(),
        }
    }
    fn rcond(&mut self) -> f64 {
        match self {
            ElementSolver::Banded(lu) => lu.rcond(),
            ElementSolver::Direct(lu) => lu.rcond(),
            ElementSolver::Dense(lu) => lu.rcond(),
            ElementSolver::Iterative(cg, ..) => cg.rcond(),
        }
    }
    fn has_reusable_factors(&self) -> bool {
        match self {
            ElementSolver::Banded(lu) => lu.has_reusable_factors(),
            ElementSolver::Direct(lu) => lu.has_reusable_factors(),
            ElementSolver::Dense(lu) => lu.has_reusable_factors(),
            ElementSolver::Iterative(cg, ..) => cg.has_reusable_factors(),
        }
    }
}

/// The dense backend of [`ElementSolver`]: the pattern's values scattered into a full `n × n`
/// matrix, column by column, and factored by [`DynPatternLu::dense`] (`P A = L U` with partial
/// pivoting, Golub & Van Loan Alg. 3.4.1; the comparison-matrix bound on the reciprocal
/// condition number, Higham Thm. 8.12, and Hager's estimate, as the other backends report a
/// singular or ill-conditioned Jacobian). All memory is allocated here, once per run.
#[derive(Debug)]
#[doc(hidden)]
pub struct DenseStep {
    n: usize,
    /// `dense[k]`: where the pattern's `k`-th value goes in the column-major matrix.
    dense: Vec<usize>,
    /// The full matrix (entries outside the pattern stay zero).
    full: CscBuffer,
    lu: DynPatternLu,
    /// Whether `lu` holds the factors of the last factorization (it succeeded).
    factored: bool,
}

impl DenseStep {
    fn new(n: usize, col_ptr: &[usize], row_idx: &[usize]) -> Self {
        let dense = (0..n)
            .flat_map(|j| {
                row_idx[col_ptr[j]..col_ptr[j + 1]]
                    .iter()
                    .map(move |&i| i + j * n)
            })
            .collect();
        Self {
            n,
            dense,
            full: CscBuffer::zeroed(n * n, 0),
            lu: DynPatternLu::dense(n),
            factored: false,
        }
    }

    fn factor(&mut self, j: &[f64]) -> Result<(), FactorError> {
        debug_assert_eq!(j.len(), self.dense.len());
        let full = self.full.as_mut_slice();
        for (&k, &v) in self.dense.iter().zip(j) {
            full[k] = v;
        }
        let result = self.lu.factor(&self.full);
        self.factored = result.is_ok();
        result
    }

    fn solve_in_place(&mut self, b: &mut DVector<f64>) {
        debug_assert_eq!(b.len(), self.n);
        self.lu.solve_in_place(b)
    }

    fn norm1(&self) -> f64 {
        self.lu.norm1()
    }

    fn rcond_lower_bound(&mut self) -> f64 {
        self.lu.rcond_lower_bound()
    }

    fn rcond(&mut self) -> f64 {
        self.lu.rcond()
    }

    /// Yes once a factorization succeeded, as the sparse LU it replaces: the element view's
    /// residual and Jacobian come from one kernel over every coordinate, whose evaluation and
    /// the factorization cost more than the few extra chord iterations (measured on the
    /// 30-coordinate cart: a step 11–16 µs refactoring at every iteration, see BENCHMARKS.md).
    fn has_reusable_factors(&self) -> bool {
        self.factored
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The pattern of an `n × n` matrix whose entry `(i, j)` is kept when `keep(i, j)` (the
    /// diagonal always), with values diagonally dominant up to `weak` on the diagonal.
    fn pattern(
        n: usize,
        keep: impl Fn(usize, usize) -> bool,
        weak: f64,
    ) -> (Vec<usize>, Vec<usize>, Vec<f64>) {
        let (mut col_ptr, mut row_idx, mut values) = (vec![0], Vec::new(), Vec::new());
        for j in 0..n {
            for i in 0..n {
                if i == j || keep(i, j) {
                    row_idx.push(i);
                    let v = ((37 * i + 11 * j * j + 5 * i * j) % 29) as f64 / 29.0 - 0.5;
                    values.push(if i == j { weak * n as f64 + v } else { v });
                }
            }
            col_ptr.push(row_idx.len());
        }
        (col_ptr, row_idx, values)
    }

    /// A pseudo-random pattern of about `fill · n²` entries.
    fn scattered(fill: f64) -> impl Fn(usize, usize) -> bool {
        move |i, j| ((i * 7919 + j * 104_729) % 1000) as f64 / 1000.0 < fill
    }

    /// `Auto` factors a small wide pattern (the element view's one element) and a small saddle
    /// point system densely, and keeps the banded LU for a chain and the sparse LU for a large
    /// or a sparse pattern; the dense factors solve as the sparse LU's, and a singular matrix
    /// is refused as by the other backends.
    #[test]
    fn small_wide_patterns_are_factored_densely_and_solve_as_the_sparse_lu() {
        let (col_ptr, row_idx, values) = pattern(30, |_, _| true, 0.02);
        let mut dense = ElementSolver::new(30, &col_ptr, &row_idx, StepSolver::Auto);
        assert_eq!(dense.name(), "dense LU");
        let mut sparse = ElementSolver::new(30, &col_ptr, &row_idx, StepSolver::Direct);
        assert_eq!(sparse.name(), "sparse LU");
        assert!(!dense.has_reusable_factors());
        dense.factor(&values).unwrap();
        sparse.factor(&values).unwrap();
        // Chord iterations on the held factors, as on the sparse LU's.
        assert!(dense.has_reusable_factors());
        let b = DVector::from_fn(30, |i, _| (i as f64 * 0.3).sin());
        let (x, y) = (dense.solve(&b), sparse.solve(&b));
        assert!((&x - &y).amax() <= 1e-12 * y.amax(), "{x} vs {y}");
        assert_eq!(dense.norm1(), sparse.norm1());
        let (bound, estimate) = (dense.rcond_lower_bound(), dense.rcond());
        assert!(bound > 0.0 && estimate >= bound * (1.0 - 1e-9));
        assert!((estimate - sparse.rcond()).abs() <= 1e-9 * estimate);
        // Two equal columns: singular, refused (not a NaN).
        let mut singular = values.clone();
        singular.copy_within(0..30, 30);
        assert_eq!(dense.factor(&singular), Err(FactorError::Singular));
        assert!(!dense.has_reusable_factors(), "no factors after a failure");
        let mut broken = values;
        broken[7] = f64::NAN;
        assert_eq!(dense.factor(&broken), Err(FactorError::NonFinite));

        // A saddle-point system [[H, Gᵀ], [G, 0]] with a dense H: its zero block pivots.
        let (n, m) = (30, 10);
        let kkt = |i: usize, j: usize| {
            (i < n && j < n) || ((i < n) != (j < n) && (i + j).is_multiple_of(3))
        };
        let (col_ptr, row_idx, mut values) = pattern(n + m, kkt, 1.0);
        let diagonal = |k: usize| {
            (col_ptr[k]..col_ptr[k + 1])
                .find(|&p| row_idx[p] == k)
                .unwrap()
        };
        for k in n..n + m {
            values[diagonal(k)] = 0.0;
        }
        let mut saddle = ElementSolver::saddle(n + m, &col_ptr, &row_idx);
        assert_eq!(saddle.name(), "dense LU");
        let mut reference = ElementSolver::new(n + m, &col_ptr, &row_idx, StepSolver::Direct);
        saddle.factor(&values).unwrap();
        reference.factor(&values).unwrap();
        let b = DVector::from_fn(n + m, |i, _| 1.0 + i as f64);
        let (x, y) = (saddle.solve(&b), reference.solve(&b));
        assert!((&x - &y).amax() <= 1e-12 * y.amax(), "{x} vs {y}");

        // A chain keeps the band, a large or sparse pattern the sparse LU.
        let (col_ptr, row_idx, _) = pattern(40, |i, j| i.abs_diff(j) <= 1, 1.0);
        let chain = ElementSolver::new(40, &col_ptr, &row_idx, StepSolver::Auto);
        assert_eq!(chain.name(), "banded LU");
        let n = DENSE_MAX_DIM + 1;
        let (col_ptr, row_idx, _) = pattern(n, |_, _| true, 1.0);
        let large = ElementSolver::new(n, &col_ptr, &row_idx, StepSolver::Auto);
        assert_eq!(large.name(), "sparse LU");
        assert_eq!(
            ElementSolver::saddle(n, &col_ptr, &row_idx).name(),
            "sparse LU"
        );
        let (col_ptr, row_idx, _) = pattern(60, scattered(0.05), 1.0);
        assert!(row_idx.len() * DENSE_MIN_FILL < 60 * 60);
        let sparse = ElementSolver::new(60, &col_ptr, &row_idx, StepSolver::Auto);
        assert_eq!(sparse.name(), "sparse LU");
    }

    /// The crossover of [`DENSE_MAX_DIM`] and [`DENSE_MIN_FILL`]: a factorization and a solve,
    /// dense against the sparse LU, on scattered patterns of several sizes and fills. A
    /// measurement: `cargo test --release -p dirac-runtime --lib element::solver -- --ignored
    /// --nocapture`.
    #[test]
    #[ignore = "timing; run in release with --ignored --nocapture"]
    fn dense_against_sparse_factorization_times() {
        for fill in [1.0, 0.5, 0.25, 0.1] {
            for n in [16, 24, 32, 48, 64, 96, 128] {
                let (col_ptr, row_idx, values) = pattern(n, scattered(fill), 1.0);
                let b = DVector::from_fn(n, |i, _| i as f64);
                let mut times = [0.0; 2];
                for (t, linear) in [StepSolver::Auto, StepSolver::Direct].iter().enumerate() {
                    let mut solver = if *linear == StepSolver::Auto {
                        ElementSolver::Dense(Box::new(DenseStep::new(n, &col_ptr, &row_idx)))
                    } else {
                        ElementSolver::new(n, &col_ptr, &row_idx, StepSolver::Direct)
                    };
                    let mut x = b.clone();
                    let reps = 2000;
                    let start = std::time::Instant::now();
                    for _ in 0..reps {
                        solver.factor(&values).unwrap();
                        x.copy_from(&b);
                        solver.solve_in_place(&mut x);
                    }
                    times[t] = start.elapsed().as_secs_f64() * 1e6 / reps as f64;
                }
                println!(
                    "fill {fill:.2} (nnz/n² {:.2}) n {n:4}: dense {:8.2} us, sparse {:8.2} us, ratio {:.2}",
                    row_idx.len() as f64 / (n * n) as f64,
                    times[0],
                    times[1],
                    times[0] / times[1]
                );
            }
        }
    }
}
