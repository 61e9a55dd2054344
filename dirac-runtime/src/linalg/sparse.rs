//! The large-system backend: the step Jacobian as the compile-time sparsity pattern the compiler
//! emits, factored by faer's sparse LU with partial pivoting.
//!
//! `#[reduced_lagrangian]` knows at compile time which entries of `∂R/∂z` can be nonzero (the
//! others are structural zeros of its expression graph). Above [`super::DENSE_MAX`] coordinates it emits
//! that pattern as a static [`CscPattern`] and the Jacobian as the values of those entries alone,
//! in compressed-sparse-column order ([`CscValues`]); a step then never forms, stores or factors a
//! dense `N × N` matrix. [`SparseLu`] is the workspace of one integration: it computes the
//! fill-reducing column ordering and the symbolic factorization once, when it is built, and every
//! Newton iteration of every step reuses them and their memory — the numeric factorization and the
//! solves run in preallocated scratch, with no allocation after the first factorization.
//!
//! Why faer: it is maintained, pure Rust (no BLAS/LAPACK or C toolchain on the user's machine),
//! and its sparse LU separates the symbolic analysis (COLAMD ordering) from the numeric
//! factorization, with explicit scratch memory (`MemStack`), which is exactly the reuse a Newton
//! iteration on a fixed pattern needs. dirac drives faer's *simplicial* (left-looking,
//! Gilbert–Peierls) numeric LU directly rather than through faer's wrapper: its factors `L` and
//! `U` are then readable, which gives the same cheap guaranteed conditioning bound as the dense
//! backend ([`SparseLu::rcond_lower_bound`]), so a healthy step skips Hager's estimator (about
//! ten sparse solves). faer's supernodal variant (dense blocks) would factor dense patterns such
//! as a long chain's faster, but its factors are not readable; with chord iterations
//! ([`crate::newton::solve_with`]) factorizations are rare on the lattices this backend is for
//! (2 in 20,000 steps of the 200-particle lattice). The patterns of mechanical systems are not
//! banded in general (a lattice with a common translation is cyclic tridiagonal plus a dense
//! border; a chain hanging from a cart is dense), so a banded solver would not cover them.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::perm::{Perm, PermRef};
use faer::sparse::linalg::lu::simplicial::{self, SimplicialLu};
use faer::sparse::linalg::lu::{
    factorize_symbolic_lu, LuRef, LuSymbolicParams, NumericLu, SymbolicLu,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par};
use nalgebra::SVector;

use super::{reciprocal_condition, FactorError, HagerCache, LinearSolver};

/// The structurally nonzero entries of an `n × n` step Jacobian, in compressed sparse columns:
/// the entries of column `j` are rows `row_idx[col_ptr[j]..col_ptr[j + 1]]`, increasing.
#[derive(Debug)]
pub struct CscPattern {
    /// Number of rows and columns.
    pub n: usize,
    /// Column starts, `n + 1` of them.
    pub col_ptr: &'static [usize],
    /// Row of each entry.
    pub row_idx: &'static [usize],
}

impl CscPattern {
    /// Number of structural nonzeros.
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// Whether the arrays describe a valid `n × n` pattern with sorted, distinct rows per column.
    pub fn is_valid(&self) -> bool {
        self.col_ptr.len() == self.n + 1
            && self.col_ptr[0] == 0
            && self.col_ptr[self.n] == self.row_idx.len()
            && self.col_ptr.windows(2).all(|w| w[0] <= w[1])
            && (0..self.n).all(|j| {
                let rows = &self.row_idx[self.col_ptr[j]..self.col_ptr[j + 1]];
                rows.iter().all(|&r| r < self.n) && rows.windows(2).all(|w| w[0] < w[1])
            })
    }

    /// The position of entry `(row, col)` in the values, if it is structurally nonzero.
    pub fn position(&self, row: usize, col: usize) -> Option<usize> {
        let start = self.col_ptr[col];
        self.row_idx[start..self.col_ptr[col + 1]]
            .binary_search(&row)
            .ok()
            .map(|i| start + i)
    }
}

/// The values of a sparse step Jacobian, in the order of its [`CscPattern`]: what the emitted
/// `residual_jacobian` of a large system returns (no heap, no dense matrix).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CscValues<const NNZ: usize>(pub [f64; NNZ]);

impl<const NNZ: usize> CscValues<NNZ> {
    /// Entry `(row, col)` of the matrix with this pattern (0 where structurally zero).
    pub fn get(&self, pattern: &CscPattern, row: usize, col: usize) -> f64 {
        pattern.position(row, col).map_or(0.0, |i| self.0[i])
    }

    /// The dense matrix, for tests and diagnostics (heap-allocated).
    pub fn to_dense(&self, pattern: &CscPattern) -> nalgebra::DMatrix<f64> {
        let mut m = nalgebra::DMatrix::zeros(pattern.n, pattern.n);
        for j in 0..pattern.n {
            for p in pattern.col_ptr[j]..pattern.col_ptr[j + 1] {
                m[(pattern.row_idx[p], j)] = self.0[p];
            }
        }
        m
    }
}

mod pattern;

pub use pattern::DynPatternLu;

/// Sparse LU with partial pivoting (faer's simplicial LU) on a pattern known at run time: the
/// numeric core of [`SparseLu`] (the compile-time pattern of a fixed-size system) and of
/// [`DynSparseLu`] (the pattern a run-time-sized system assembles from its element stencils).
/// The fill-reducing column ordering is computed once in [`Factors::new`]; each
/// [`Factors::factor`] is a numeric factorization into the same memory (`A Q = Pᵀ L U`, `Q` the
/// ordering, `P` the row pivoting, `L` unit lower triangular), and solves, the conditioning bound
/// and Hager's estimate run in scratch allocated here, so nothing allocates after the first
/// factorization.
struct Factors {
    n: usize,
    pattern: SymbolicSparseColMat<usize>,
    /// `Q`: COLAMD's column ordering of the pattern.
    col_perm: Perm<usize>,
    /// `P`, forward and inverse, as the last factorization pivoted.
    row_perm: Vec<usize>,
    row_perm_inv: Vec<usize>,
    lu: SimplicialLu<usize, f64>,
    /// Scratch of the numeric factorization and of the solves.
    scratch: MemBuffer,
    /// The conditioning bound's vector of length `n`.
    work: Vec<f64>,
    norm1: f64,
    factored: bool,
    /// The conditioning bound of the current factors, once computed: chord iterations check the
    /// same factors at every step.
    bound_cache: Option<f64>,
    /// Hager's estimate of the current factors, likewise.
    hager: HagerCache,
}

impl Factors {
    /// The workspace for `n × n` Jacobians with the CSC pattern `(col_ptr, row_idx)`.
    fn new(n: usize, col_ptr: &[usize], row_idx: &[usize]) -> Self {
        let pattern =
            SymbolicSparseColMat::new_checked(n, n, col_ptr.to_vec(), None, row_idx.to_vec());
        let symbolic = factorize_symbolic_lu(pattern.as_ref(), LuSymbolicParams::default())
            .expect("dirac: symbolic LU of the Jacobian's pattern (out of memory)");
        let (forward, inverse) = symbolic.col_perm().arrays();
        let col_perm = Perm::new_checked(forward.into(), inverse.into(), n);
        let req = StackReq::any_of(&[
            simplicial::factorize_simplicial_numeric_lu_scratch::<usize, f64>(n, n),
            simplicial::solve_in_place_scratch::<usize, f64>(n, 1, Par::Seq),
        ]);
        Self {
            n,
            pattern,
            col_perm,
            row_perm: vec![0; n],
            row_perm_inv: vec![0; n],
            lu: SimplicialLu::new(),
            scratch: MemBuffer::new(req),
            work: vec![0.0; n],
            norm1: 0.0,
            factored: false,
            bound_cache: None,
            hager: HagerCache::new(n),
        }
    }

    fn factor(&mut self, values: &[f64]) -> Result<(), FactorError> {
        self.bound_cache = None;
        self.norm1 = self
            .hager
            .refactor(&mut self.factored, self.pattern.col_ptr(), values)?;
        let a = SparseColMatRef::new(self.pattern.as_ref(), values);
        let stack = MemStack::new(&mut self.scratch);
        simplicial::factorize_simplicial_numeric_lu(
            &mut self.row_perm,
            &mut self.row_perm_inv,
            &mut self.lu,
            a,
            self.col_perm.as_ref(),
            stack,
        )
        .map_err(|_| FactorError::Singular)?;
        self.factored = true;
        Ok(())
    }

    /// Solves `A x = b` (or `Aᵀ x = b`) in place.
    fn solve_in_place(&mut self, x: &mut [f64], transpose: bool) {
        debug_assert!(self.factored, "solve before factor");
        let n = self.n;
        if transpose {
            let row_perm = PermRef::new_checked(&self.row_perm, &self.row_perm_inv, n);
            let col_perm = self.col_perm.as_ref();
            let rhs = MatMut::from_column_major_slice_mut(x, n, 1);
            let stack = MemStack::new(&mut self.scratch);
            self.lu.solve_transpose_in_place_with_conj(
                row_perm,
                col_perm,
                Conj::No,
                rhs,
                Par::Seq,
                stack,
            );
            return;
        }
        // faer's solve: a column-oriented solve written here on the same factors measured no
        // faster on the lattice and, by a different summation order, let the ill-conditioned
        // saddle-point steps of `examples/maximal_chain.rs` drift into a failed step.
        let row_perm = PermRef::new_checked(&self.row_perm, &self.row_perm_inv, n);
        let col_perm = self.col_perm.as_ref();
        let rhs = MatMut::from_column_major_slice_mut(x, n, 1);
        let stack = MemStack::new(&mut self.scratch);
        self.lu
            .solve_in_place_with_conj(row_perm, col_perm, Conj::No, rhs, Par::Seq, stack);
    }

    /// An upper bound on `‖A⁻¹‖₁ = ‖U⁻¹ L⁻¹‖₁ ≤ ‖M(U)⁻¹‖₁ ‖M(L)⁻¹‖₁` from one pass over each
    /// factor: the comparison-matrix bound of the dense [`crate::Lu::inverse_norm1_bound`]
    /// (Higham, Thm. 8.12), with the factors' columns read in place (the permutations leave
    /// 1-norms unchanged). In a column of `U` the diagonal entry is the one in row `j`; a column
    /// of `L` holds its unit diagonal and the rows below it.
    fn inverse_norm1_bound(&mut self) -> f64 {
        let (u, l) = (self.lu.u_factor_unsorted(), self.lu.l_factor_unsorted());
        let y = &mut self.work;
        y.fill(0.0);
        // M(U)ᵀ y = e, forward: column j of U gives row j of Uᵀ.
        let mut u_max = 0.0f64;
        for j in 0..self.n {
            let (mut s, mut diagonal) = (1.0, 0.0);
            for (&i, v) in u.row_idx_of_col_raw(j).iter().zip(u.val_of_col(j)) {
                if i == j {
                    diagonal = v.abs();
                } else {
                    s += v.abs() * y[i];
                }
            }
            y[j] = s / diagonal;
            u_max = u_max.max(y[j]);
        }
        // M(L)ᵀ y = e, backward (unit diagonal).
        let mut l_max = 0.0f64;
        for j in (0..self.n).rev() {
            let mut s = 1.0;
            for (&i, v) in l.row_idx_of_col_raw(j).iter().zip(l.val_of_col(j)) {
                if i != j {
                    s += v.abs() * y[i];
                }
            }
            y[j] = s;
            l_max = l_max.max(s);
        }
        u_max * l_max
    }

    /// `1 / (‖A‖₁ · bound)` with [`Self::inverse_norm1_bound`]: guaranteed below the true
    /// reciprocal condition number (up to round-off), at the cost of one pass over the factors.
    fn rcond_lower_bound(&mut self) -> f64 {
        if !self.factored {
            return 0.0;
        }
        if let Some(bound) = self.bound_cache {
            return bound;
        }
        let bound = reciprocal_condition(self.norm1, self.inverse_norm1_bound());
        self.bound_cache = Some(bound);
        bound
    }

    fn rcond(&mut self) -> f64 {
        let norm1 = self.factored.then_some(self.norm1);
        HagerCache::rcond(self, |f| &mut f.hager, norm1, Self::solve_in_place)
    }
}

/// Sparse LU with partial pivoting (faer's simplicial LU) on the compile-time pattern of a
/// fixed-size system, as a reusable workspace for Newton's iteration: the fill-reducing column
/// ordering is computed once in [`SparseLu::new`]; each [`LinearSolver::factor`] is a numeric
/// factorization into the same memory (`A Q = Pᵀ L U`, `Q` the ordering, `P` the row pivoting,
/// `L` unit lower triangular).
pub struct SparseLu<const N: usize, const NNZ: usize> {
    csc: &'static CscPattern,
    factors: Factors,
}

impl<const N: usize, const NNZ: usize> std::fmt::Debug for SparseLu<N, NNZ> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SparseLu")
            .field("n", &N)
            .field("nnz", &NNZ)
            .field("factored", &self.factors.factored)
            .finish_non_exhaustive()
    }
}

impl<const N: usize, const NNZ: usize> SparseLu<N, NNZ> {
    /// The workspace for Jacobians with `pattern`: fill-reducing column ordering (COLAMD) and
    /// all the scratch a factorization and a solve need.
    ///
    /// # Panics
    /// If `pattern` is not a valid `N × N` pattern with `NNZ` entries: the compiler emits the
    /// pattern, so this is a bug in dirac, not a user error.
    pub fn new(pattern: &'static CscPattern) -> Self {
        assert!(
            pattern.n == N && pattern.nnz() == NNZ && pattern.is_valid(),
            "dirac: the emitted sparsity pattern does not describe an {N} × {N} matrix with {NNZ} entries"
        );
        Self {
            csc: pattern,
            factors: Factors::new(N, pattern.col_ptr, pattern.row_idx),
        }
    }

    /// The pattern of the Jacobians this workspace factors.
    pub fn pattern(&self) -> &'static CscPattern {
        self.csc
    }

    /// An upper bound on `‖A⁻¹‖₁` from one pass over the factors (see
    /// [`crate::Lu::inverse_norm1_bound`]).
    pub fn inverse_norm1_bound(&mut self) -> f64 {
        self.factors.inverse_norm1_bound()
    }
}

/// The [`LinearSolver`] methods of a backend on `SVector<f64, N>` that delegates to [`Factors`]
/// in `self.factors`.
macro_rules! delegate_to_factors {
    () => {
        fn solve(&mut self, b: &SVector<f64, N>) -> SVector<f64, N> {
            let mut x = *b;
            self.factors.solve_in_place(x.as_mut_slice(), false);
            x
        }

        fn solve_in_place(&mut self, b: &mut SVector<f64, N>) {
            self.factors.solve_in_place(b.as_mut_slice(), false);
        }

        fn norm1(&self) -> f64 {
            self.factors.norm1
        }

        /// `1 / (‖A‖₁ · bound)`, the bound from one pass over the factors: guaranteed below the
        /// true reciprocal condition number (up to round-off).
        fn rcond_lower_bound(&mut self) -> f64 {
            self.factors.rcond_lower_bound()
        }

        fn rcond(&mut self) -> f64 {
            self.factors.rcond()
        }

        /// Yes once a factorization succeeded: a sparse factorization costs several residual
        /// evaluations, so a step first tries the factors of an earlier step (chord iterations).
        fn has_reusable_factors(&self) -> bool {
            self.factors.factored
        }
    };
}

impl<const N: usize, const NNZ: usize> LinearSolver for SparseLu<N, NNZ> {
    type Vector = SVector<f64, N>;
    type Matrix = CscValues<NNZ>;

    fn factor(&mut self, j: &CscValues<NNZ>) -> Result<(), FactorError> {
        self.factors.factor(&j.0)
    }

    delegate_to_factors!();
}

/// The values of a sparse Jacobian whose pattern is known only at run time, after `start`
/// leading entries (the residual, which a system's kernel writes into the same buffer): the
/// [`LinearSolver::Matrix`] of [`PatternLu`]. The memory comes from a small per-thread pool and
/// returns to it when the value is dropped, so after a run's first Jacobian no evaluation
/// allocates.
pub struct CscBuffer {
    data: Vec<f64>,
    start: usize,
}

thread_local! {
    /// Buffers of dropped [`CscBuffer`]s, reused by the next ones on this thread.
    static CSC_POOL: std::cell::RefCell<Vec<Vec<f64>>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// The most buffers a thread keeps for reuse (a Newton step holds one or two at a time).
const CSC_POOL_MAX: usize = 4;

impl CscBuffer {
    /// A zeroed buffer of `len` entries whose values start at `start`, from this thread's pool
    /// when it has one.
    pub fn zeroed(len: usize, start: usize) -> Self {
        assert!(start <= len, "dirac: a CSC buffer's values start inside it");
        let mut data = CSC_POOL
            .with(|pool| pool.borrow_mut().pop())
            .unwrap_or_default();
        data.clear();
        data.resize(len, 0.0);
        Self { data, start }
    }

    /// The whole buffer, the leading entries included: what a kernel writes.
    pub fn as_mut_slice(&mut self) -> &mut [f64] {
        &mut self.data
    }

    /// The leading entries (before the values).
    pub fn leading(&self) -> &[f64] {
        &self.data[..self.start]
    }

    /// The Jacobian's values, in the pattern's order.
    pub fn values(&self) -> &[f64] {
        &self.data[self.start..]
    }
}

impl Drop for CscBuffer {
    fn drop(&mut self) {
        let data = std::mem::take(&mut self.data);
        // A thread being torn down has no pool left: the memory is then simply freed.
        let _ = CSC_POOL.try_with(|pool| {
            let mut pool = pool.borrow_mut();
            if pool.len() < CSC_POOL_MAX {
                pool.push(data);
            }
        });
    }
}

impl std::fmt::Debug for CscBuffer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CscBuffer")
            .field("values", &self.values())
            .finish()
    }
}

/// [`SparseLu`]'s factorization — the same ordering, pivoting and conditioning bound, so the
/// same results — on a pattern known only at run time, with fixed-size vectors: the backend of
/// a large system given as text, whose pattern arrives with its compiled code. The Jacobian is a
/// [`CscBuffer`].
pub struct PatternLu<const N: usize> {
    factors: Factors,
}

impl<const N: usize> std::fmt::Debug for PatternLu<N> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PatternLu")
            .field("n", &N)
            .field("nnz", &self.factors.pattern.row_idx().len())
            .field("factored", &self.factors.factored)
            .finish_non_exhaustive()
    }
}

impl<const N: usize> PatternLu<N> {
    /// The workspace for `N × N` Jacobians whose column `j` has the sorted, distinct rows
    /// `row_idx[col_ptr[j]..col_ptr[j + 1]]`, or `None` if the arrays do not describe one.
    pub fn new(col_ptr: &[usize], row_idx: &[usize]) -> Option<Self> {
        let valid = col_ptr.len() == N + 1
            && col_ptr[0] == 0
            && col_ptr[N] == row_idx.len()
            && col_ptr.windows(2).all(|w| w[0] <= w[1])
            && (0..N).all(|j| {
                let rows = &row_idx[col_ptr[j]..col_ptr[j + 1]];
                rows.iter().all(|&r| r < N) && rows.windows(2).all(|w| w[0] < w[1])
            });
        valid.then(|| Self {
            factors: Factors::new(N, col_ptr, row_idx),
        })
    }
}

impl<const N: usize> LinearSolver for PatternLu<N> {
    type Vector = SVector<f64, N>;
    type Matrix = CscBuffer;

    fn factor(&mut self, j: &CscBuffer) -> Result<(), FactorError> {
        self.factors.factor(j.values())
    }

    delegate_to_factors!();
}

/// The sparse LU on a pattern built at run time: the backend of systems whose size is chosen at
/// run time (element-wise systems, [`crate::element`]), whose step Jacobian's pattern is
/// assembled once per run from the element stencils. Vectors are `DVector`s and the Jacobian is
/// its values in the pattern's CSC order; solves are in place, so a Newton step allocates
/// nothing.
///
/// Unlike [`SparseLu`] (lattices and chains of a fixed size, whose simplicial factors it reads
/// for a cheap conditioning bound), this backend lets faer choose between its simplicial and
/// supernodal numeric LU from the symbolic analysis: the pattern of a 2-D grid fills in far more
/// than a chain's, and there the supernodal factorization (dense blocks) is what makes a
/// factorization of 10⁵ unknowns affordable. The factors are then not readable, so the step is
/// checked with Hager's estimate — once per factorization, which chord iterations make rare.
pub struct DynSparseLu {
    n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    symbolic: SymbolicLu<usize>,
    numeric: NumericLu<usize, f64>,
    scratch: MemBuffer,
    /// Hager's estimate of the current factors, once computed.
    hager: HagerCache,
    norm1: f64,
    factored: bool,
}

impl std::fmt::Debug for DynSparseLu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        super::debug_solver(
            f,
            "DynSparseLu",
            self.n,
            &[("nnz", &self.row_idx.len())],
            self.factored,
        )
    }
}

impl DynSparseLu {
    /// The workspace for `n × n` Jacobians whose column `j` has the sorted, distinct rows
    /// `row_idx[col_ptr[j]..col_ptr[j + 1]]`: fill-reducing ordering, symbolic factorization
    /// and all scratch.
    ///
    /// # Panics
    /// If the arrays do not describe such a pattern (the runtime builds them; a bug in dirac).
    pub fn new(n: usize, col_ptr: Vec<usize>, row_idx: Vec<usize>) -> Self {
        let pattern = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
        let symbolic = factorize_symbolic_lu(pattern, LuSymbolicParams::default())
            .expect("dirac: symbolic LU of the Jacobian's pattern (out of memory)");
        let req = StackReq::any_of(&[
            symbolic.factorize_numeric_lu_scratch::<f64>(Par::Seq, Default::default()),
            symbolic.solve_in_place_scratch::<f64>(1, Par::Seq),
        ]);
        Self {
            n,
            col_ptr,
            row_idx,
            symbolic,
            numeric: NumericLu::new(),
            scratch: MemBuffer::new(req),
            hager: HagerCache::new(n),
            norm1: 0.0,
            factored: false,
        }
    }

    /// Number of rows and columns.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Number of structural nonzeros.
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// Column starts of the pattern.
    pub fn col_ptr(&self) -> &[usize] {
        &self.col_ptr
    }

    /// Row of each entry of the pattern.
    pub fn row_idx(&self) -> &[usize] {
        &self.row_idx
    }

    /// Solves `Aᵀ x = b` with the current factors, overwriting `b` with `x` (adjoint
    /// sensitivities).
    pub fn solve_transpose_in_place(&mut self, b: &mut nalgebra::DVector<f64>) {
        self.solve_slice(b.as_mut_slice(), true);
    }

    /// Solves `A x = b` (or `Aᵀ x = b`) in place.
    fn solve_slice(&mut self, x: &mut [f64], transpose: bool) {
        debug_assert!(self.factored, "solve before factor");
        // SAFETY (of `new_unchecked`): `numeric` is the output of this `symbolic`'s
        // `factorize_numeric_lu` on a matrix of its pattern (`factored` says one succeeded).
        let lu = LuRef::new_unchecked(&self.symbolic, &self.numeric);
        let rhs = MatMut::from_column_major_slice_mut(x, self.n, 1);
        let stack = MemStack::new(&mut self.scratch);
        if transpose {
            lu.solve_transpose_in_place_with_conj(Conj::No, rhs, Par::Seq, stack);
        } else {
            lu.solve_in_place_with_conj(Conj::No, rhs, Par::Seq, stack);
        }
    }
}

impl LinearSolver for DynSparseLu {
    type Vector = nalgebra::DVector<f64>;
    type Matrix = Vec<f64>;

    fn factor(&mut self, j: &Vec<f64>) -> Result<(), FactorError> {
        self.norm1 = self.hager.refactor(&mut self.factored, &self.col_ptr, j)?;
        let pattern = SymbolicSparseColMatRef::new_checked(
            self.n,
            self.n,
            &self.col_ptr,
            None,
            &self.row_idx,
        );
        let a = SparseColMatRef::new(pattern, &j[..]);
        let stack = MemStack::new(&mut self.scratch);
        self.symbolic
            .factorize_numeric_lu(&mut self.numeric, a, Par::Seq, stack, Default::default())
            .map_err(|_| FactorError::Singular)?;
        self.factored = true;
        Ok(())
    }

    dvector_solves!();
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{DMatrix, DVector};

    /// A cyclic tridiagonal 6 × 6 matrix with a dense last row and column (the pattern of a
    /// periodic lattice with a common translation), as a static pattern.
    static PATTERN: CscPattern = CscPattern {
        n: 6,
        col_ptr: &[0, 4, 8, 12, 16, 20, 26],
        row_idx: &[
            0, 1, 4, 5, // col 0
            0, 1, 2, 5, // col 1
            1, 2, 3, 5, // col 2
            2, 3, 4, 5, // col 3
            0, 3, 4, 5, // col 4
            0, 1, 2, 3, 4, 5, // col 5
        ],
    };

    fn values() -> CscValues<26> {
        let mut v = [0.0; 26];
        for (i, x) in v.iter_mut().enumerate() {
            // Off-diagonal entries of modest size; diagonal entries set below.
            *x = 0.3 * ((i * 7 % 11) as f64 - 5.0) / 5.0;
        }
        for c in 0..6 {
            let p = PATTERN.position(c, c).unwrap();
            v[p] = 4.0 + c as f64;
        }
        CscValues(v)
    }

    #[test]
    fn the_pattern_is_valid_and_positions_are_found() {
        assert!(PATTERN.is_valid());
        assert_eq!(PATTERN.position(5, 5), Some(25));
        assert_eq!(PATTERN.position(2, 0), None);
    }

    #[test]
    fn solves_as_the_dense_factorization_does_and_reuses_the_workspace() {
        let mut lu = SparseLu::<6, 26>::new(&PATTERN);
        for scale in [1.0, -2.5, 1e3] {
            let mut v = values();
            v.0.iter_mut().for_each(|x| *x *= scale);
            let a: DMatrix<f64> = v.to_dense(&PATTERN);
            let x = DVector::from_fn(6, |i, _| (i as f64 + 1.0).sin());
            let b = &a * &x;
            lu.factor(&v).unwrap();
            let solved = lu.solve(&SVector::<f64, 6>::from_column_slice(b.as_slice()));
            let err = (DVector::from_column_slice(solved.as_slice()) - &x).amax();
            assert!(err < 1e-13, "scale {scale}: {err:e}");
            // The 1-norm and Hager's estimate against the exact reciprocal condition number.
            let inv = a.clone().try_inverse().unwrap();
            let n1 = |m: &DMatrix<f64>| {
                m.column_iter()
                    .map(|c| c.iter().map(|x| x.abs()).sum::<f64>())
                    .fold(0.0, f64::max)
            };
            assert!((lu.norm1() - n1(&a)).abs() <= 1e-12 * n1(&a));
            let exact = 1.0 / (n1(&a) * n1(&inv));
            let est = lu.rcond();
            assert!(
                est >= exact * (1.0 - 1e-9) && est <= 3.0 * exact,
                "{est:e} vs {exact:e}"
            );
            // The cheap bound from the factors is below the exact value and, on this
            // diagonally dominant matrix, close to it (so a healthy step skips Hager).
            let bound = lu.rcond_lower_bound();
            assert!(
                bound <= exact * (1.0 + 1e-12) && bound >= 0.2 * exact,
                "bound {bound:e} vs exact {exact:e}"
            );
        }
    }

    /// The pattern given at run time factors and solves exactly as the compile-time one (the
    /// same ordering, pivots and bound), and its buffers come back to the thread's pool.
    #[test]
    fn a_pattern_given_at_run_time_factors_as_the_static_one() {
        assert!(PatternLu::<6>::new(&[0, 1], &[0]).is_none(), "wrong size");
        assert!(
            PatternLu::<2>::new(&[0, 2, 3], &[1, 0, 1]).is_none(),
            "unsorted rows"
        );
        let mut fixed = SparseLu::<6, 26>::new(&PATTERN);
        let mut given = PatternLu::<6>::new(PATTERN.col_ptr, PATTERN.row_idx).unwrap();
        let v = values();
        let mut buffer = CscBuffer::zeroed(6 + 26, 6);
        buffer.as_mut_slice()[6..].copy_from_slice(&v.0);
        assert_eq!(buffer.leading(), &[0.0; 6]);
        fixed.factor(&v).unwrap();
        given.factor(&buffer).unwrap();
        let b = SVector::<f64, 6>::from_fn(|i, _| (i as f64 + 1.0).cos());
        assert_eq!(fixed.solve(&b), given.solve(&b));
        assert_eq!(fixed.rcond_lower_bound(), given.rcond_lower_bound());
        assert_eq!(fixed.rcond(), given.rcond());
        // The memory of a dropped buffer is the next one's.
        let address = buffer.values().as_ptr();
        drop(buffer);
        let again = CscBuffer::zeroed(6 + 26, 6);
        assert_eq!(again.values().as_ptr(), address);
        assert!(again.values().iter().all(|&x| x == 0.0));
    }

    #[test]
    fn the_cheap_bound_holds_when_the_factorization_pivots() {
        // Small diagonal, large off-diagonal entries: partial pivoting must swap rows, so the
        // bound reads factors whose row order differs from the matrix's.
        let mut lu = SparseLu::<6, 26>::new(&PATTERN);
        let mut pivoted = 0;
        for seed in 0..20u64 {
            let mut v = [0.0; 26];
            let mut state = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
            for x in &mut v {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                *x = (state % 2001) as f64 / 1000.0 - 1.0;
            }
            for c in 0..6 {
                v[PATTERN.position(c, c).unwrap()] *= 1e-3;
            }
            let v = CscValues(v);
            let a = v.to_dense(&PATTERN);
            let Some(inv) = a.clone().try_inverse() else {
                continue;
            };
            lu.factor(&v).unwrap();
            pivoted += usize::from(lu.factors.row_perm.iter().enumerate().any(|(i, &p)| i != p));
            let n1 = |m: &DMatrix<f64>| {
                m.column_iter()
                    .map(|c| c.iter().map(|x| x.abs()).sum::<f64>())
                    .fold(0.0, f64::max)
            };
            let exact = 1.0 / (n1(&a) * n1(&inv));
            let bound = lu.rcond_lower_bound();
            assert!(
                bound > 0.0 && bound <= exact * (1.0 + 1e-9),
                "seed {seed}: bound {bound:e} vs exact {exact:e}"
            );
            let est = lu.rcond();
            assert!(
                est >= bound * (1.0 - 1e-9),
                "seed {seed}: {est:e} < {bound:e}"
            );
            // The solve on pivoted factors (rows interchanged, columns ordered).
            let x = DVector::from_fn(6, |i, _| (i as f64 + 0.5).cos());
            let b = &a * &x;
            let solved = lu.solve(&SVector::<f64, 6>::from_column_slice(b.as_slice()));
            let err = (DVector::from_column_slice(solved.as_slice()) - &x).amax();
            assert!(err < 1e-9 / exact.max(1e-6), "seed {seed}: {err:e}");
        }
        assert!(
            pivoted > 10,
            "only {pivoted} of 20 factorizations permuted rows"
        );
    }

    #[test]
    fn non_finite_entries_and_singular_matrices_are_errors() {
        let mut lu = SparseLu::<6, 26>::new(&PATTERN);
        let mut v = values();
        v.0[3] = f64::NAN;
        assert_eq!(lu.factor(&v), Err(FactorError::NonFinite));
        let singular = CscValues([0.0; 26]);
        assert!(
            lu.factor(&singular).is_err()
                || lu
                    .solve(&SVector::repeat(1.0))
                    .iter()
                    .any(|x| !x.is_finite()),
            "a zero matrix must not solve"
        );
    }
}
