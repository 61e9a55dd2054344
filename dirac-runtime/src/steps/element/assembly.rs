//! Assembly of an element-wise system: the stencils and the Jacobian's pattern, built once per
//! run, and the passes over the elements that scatter their residuals, next momenta and Jacobian
//! blocks — serial, or in parallel with the same sums in the same order (see [`super`]).
//!
//! The parallel pass is owner-computes: the rows are cut into contiguous blocks, and a block
//! evaluates every element whose stencil touches one of its rows (an element on a boundary is
//! evaluated by each block it touches) and adds only into its own rows. So no two threads write
//! the same entry, and every row receives its contributions in the serial order — family by
//! family, element by element — from the same starting value: the result is the serial one, bit
//! for bit, for any number of threads and blocks.

use std::cell::RefCell;
use std::ops::Range;
use std::sync::Mutex;

use nalgebra::DVector;
use rayon::prelude::*;

use super::pass::{Shared, Visit};
use super::solver::ElementSolver;
use super::stencils::FamilyPass;
use super::Increments;
use super::{
    scratch_len, ElementLagrangian, Family, FamilyVisitor, Parallel, StepSolver,
    PARALLEL_MIN_ENTRIES,
};

/// The elements of one family as a run sees them.
pub(super) struct FamilyData {
    /// Stencil width `S`.
    pub(super) width: usize,
    /// Loop depth.
    pub(super) depth: usize,
    /// Number of elements.
    pub(super) count: usize,
    /// The loop indices of every element, `depth` per element.
    pub(super) indices: Vec<i64>,
    /// The global coordinate indices of every element's stencil, `width` per element.
    pub(super) stencils: Vec<usize>,
    /// For every element, the positions of its `width²` block entries in the Jacobian's values
    /// (entry `a·width + b`: row `stencil[a]`, column `stencil[b]`).
    pub(super) positions: Vec<usize>,
}

/// The row blocks of the parallel passes: block `b` owns rows `ranges[b]` and evaluates the
/// elements `lists[b][f]` of family `f` (those touching its rows, in increasing order), with
/// its own element scratch `scratch[b]` (locked by the one task that runs the block, so never
/// contended).
struct Blocks {
    ranges: Vec<Range<usize>>,
    lists: Vec<Vec<Vec<u32>>>,
    scratch: Vec<Mutex<Vec<f64>>>,
}

/// The most elements evaluated per element (over all blocks) for [`Parallel::Auto`] to assemble
/// in parallel (see [`Blocks::redundancy`]).
const MAX_REDUNDANCY: f64 = 1.25;

impl Blocks {
    /// Four blocks of contiguous rows per thread (at least one row each), and the elements each
    /// must evaluate.
    fn new(n: usize, threads: usize, families: &[FamilyData]) -> Self {
        let count = (4 * threads).clamp(1, n.max(1));
        let size = n.div_ceil(count).max(1);
        let ranges: Vec<Range<usize>> = (0..n.div_ceil(size))
            .map(|b| b * size..((b + 1) * size).min(n))
            .collect();
        let mut lists = vec![vec![Vec::new(); families.len()]; ranges.len()];
        for (fi, f) in families.iter().enumerate() {
            for (e, st) in f.stencils.chunks_exact(f.width.max(1)).enumerate() {
                let mut touched: Vec<usize> = st.iter().map(|&row| row / size).collect();
                touched.sort_unstable();
                touched.dedup();
                for b in touched {
                    lists[b][fi].push(e as u32);
                }
            }
        }
        let len = families
            .iter()
            .map(|f| scratch_len(f.width))
            .max()
            .unwrap_or(0);
        let scratch = (0..ranges.len())
            .map(|_| Mutex::new(vec![0.0; len]))
            .collect();
        Blocks {
            ranges,
            lists,
            scratch,
        }
    }

    /// Elements evaluated by the blocks per element of the system (1 when no element touches
    /// two blocks).
    fn redundancy(&self, families: &[FamilyData]) -> f64 {
        let evaluated: usize = self.lists.iter().flatten().map(Vec::len).sum();
        let elements: usize = families.iter().map(|f| f.count).sum();
        evaluated as f64 / elements.max(1) as f64
    }
}

/// The elements, the pattern and the passes over them.
pub(super) struct Assembler {
    families: Vec<FamilyData>,
    nnz: usize,
    parallel: Option<Blocks>,
    orbits: Vec<Vec<Range<usize>>>,
    /// `D_2 L_d(q0, z)` at the last `z` a pass evaluated: the next momentum once Newton stops.
    p1: RefCell<DVector<f64>>,
    /// The serial pass's element scratch: the stencil values and the outputs of one element
    /// ([`scratch_len`] of the widest family).
    scratch: RefCell<Vec<f64>>,
}

/// The workspace of an [`super::ElementIntegrator`] run: the elements' stencils, the Jacobian's
/// pattern and its sparse LU, the residual and Jacobian buffers, the last two increments
/// Newton's guess extrapolates from. Built once per run (the only allocations of a run).
pub struct ElementWorkspace {
    n: usize,
    /// The sizes of the system it was built for.
    sizes: Vec<usize>,
    invalid: Option<String>,
    solver: ElementSolver,
    /// The step Jacobian's pattern, compressed columns.
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    r: DVector<f64>,
    jacobian: Option<Vec<f64>>,
    assembler: Assembler,
    /// The point `q_{k+1} = q_k − Δ` of a (−) step's unknown, formed for each residual pass.
    scratch: RefCell<DVector<f64>>,
    /// The last two increments, for Newton's first guess.
    history: Increments,
}

impl std::fmt::Debug for ElementWorkspace {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ElementWorkspace")
            .field("n", &self.n)
            .field("nnz", &self.assembler.nnz)
            .field("families", &self.assembler.families.len())
            .field("parallel", &self.assembler.parallel.is_some())
            .finish_non_exhaustive()
    }
}

/// Whether the families of `system` have the shapes `families` records (stencil widths, loop
/// depths, as many families): allocation-free.
struct Fits<'a> {
    families: &'a [FamilyData],
    next: usize,
    fits: bool,
}

impl FamilyVisitor for Fits<'_> {
    fn family<F: Family>(&mut self, family: &F) {
        let f = self.families.get(self.next);
        self.fits &= f.is_some_and(|f| f.width == family.width() && f.depth == family.depth());
        self.next += 1;
    }
}

impl ElementWorkspace {
    pub(super) fn new<L: ElementLagrangian>(
        system: &L,
        parallel: Parallel,
        linear: StepSolver,
    ) -> Self {
        let n = system.dim();
        let mut pass = FamilyPass::<FamilyData>::new(n);
        system.families(&mut pass);
        let FamilyPass {
            mut families,
            invalid,
            ..
        } = pass;
        // The pattern: every block entry (row = stencil slot of q0, column = slot of q1).
        let mut entries: Vec<(usize, usize)> = Vec::new();
        for f in &families {
            for st in f.stencils.chunks_exact(f.width.max(1)) {
                for &row in st {
                    for &col in st {
                        entries.push((col, row));
                    }
                }
            }
        }
        // Every diagonal entry, so that the pattern is structurally nonsingular-capable.
        entries.extend((0..n).map(|i| (i, i)));
        entries.sort_unstable();
        entries.dedup();
        let mut col_ptr = vec![0usize; n + 1];
        for &(c, _) in &entries {
            col_ptr[c + 1] += 1;
        }
        for c in 0..n {
            col_ptr[c + 1] += col_ptr[c];
        }
        let row_idx: Vec<usize> = entries.iter().map(|&(_, r)| r).collect();
        drop(entries);
        let position = |row: usize, col: usize| -> usize {
            let start = col_ptr[col];
            start
                + row_idx[start..col_ptr[col + 1]]
                    .binary_search(&row)
                    .expect("every block entry is in the pattern")
        };
        let mut entries_total = 0;
        for f in &mut families {
            f.positions = Vec::with_capacity(f.count * f.width * f.width);
            for st in f.stencils.chunks_exact(f.width.max(1)) {
                for &row in st {
                    for &col in st {
                        f.positions.push(position(row, col));
                    }
                }
            }
            entries_total += f.count * f.width * f.width;
        }
        let nnz = row_idx.len();
        let threads = rayon::current_num_threads();
        let wanted = match parallel {
            Parallel::Never => false,
            Parallel::Always => true,
            Parallel::Auto => entries_total >= PARALLEL_MIN_ENTRIES && threads > 1,
        };
        let blocks = wanted.then(|| Blocks::new(n, threads, &families));
        let scratch = families
            .iter()
            .map(|f| scratch_len(f.width))
            .max()
            .unwrap_or(0);
        // Auto: only when the blocks evaluate few elements twice. Pairs touch rows everywhere,
        // so every block would evaluate most of them (measured on the Lennard-Jones cluster:
        // 2–4× slower than serial); lattices and grids evaluate a few boundary elements twice.
        let parallel = match (parallel, blocks) {
            (Parallel::Auto, Some(b)) if b.redundancy(&families) > MAX_REDUNDANCY => None,
            (_, b) => b,
        };
        Self {
            n,
            sizes: system.sizes(),
            invalid,
            solver: ElementSolver::new(n, &col_ptr, &row_idx, linear),
            col_ptr,
            row_idx,
            r: DVector::zeros(n),
            jacobian: None,
            scratch: RefCell::new(DVector::zeros(n)),
            assembler: Assembler {
                families,
                nnz,
                parallel,
                orbits: system.translations(),
                p1: RefCell::new(DVector::zeros(n)),
                scratch: RefCell::new(vec![0.0; scratch]),
            },
            history: Increments::new(n),
        }
    }

    /// The number of coordinates.
    pub fn dim(&self) -> usize {
        self.n
    }

    /// The number of structural nonzeros of the step Jacobian.
    pub fn nnz(&self) -> usize {
        self.assembler.nnz
    }

    /// The step Jacobian's pattern, as compressed columns `(col_ptr, row_idx)`.
    pub fn pattern(&self) -> (&[usize], &[usize]) {
        (&self.col_ptr, &self.row_idx)
    }

    /// The step Jacobian's solver this run uses (after any fallback).
    pub fn linear_solver(&self) -> &'static str {
        self.solver.name()
    }

    /// Whether this run assembles in parallel.
    pub fn is_parallel(&self) -> bool {
        self.assembler.parallel.is_some()
    }

    /// The number of elements of each family, in the order of the body.
    pub fn elements(&self) -> Vec<usize> {
        self.assembler.families.iter().map(|f| f.count).collect()
    }

    pub(super) fn invalid(&self) -> Option<&str> {
        self.invalid.as_deref()
    }

    /// The sizes of the system the workspace was built for.
    pub(super) fn sizes(&self) -> &[usize] {
        &self.sizes
    }

    /// Whether `system`'s families have the shapes of those the workspace was built from
    /// (allocation-free; the number of coordinates is checked by the caller).
    pub(super) fn fits<L: ElementLagrangian>(&self, system: &L) -> bool {
        let families = &self.assembler.families;
        let mut fits = Fits {
            families,
            next: 0,
            fits: true,
        };
        system.families(&mut fits);
        fits.fits && fits.next == families.len()
    }

    #[allow(clippy::type_complexity)]
    pub(super) fn parts(
        &mut self,
    ) -> (
        &mut ElementSolver,
        &mut DVector<f64>,
        &mut Option<Vec<f64>>,
        &Assembler,
        &RefCell<DVector<f64>>,
    ) {
        (
            &mut self.solver,
            &mut self.r,
            &mut self.jacobian,
            &self.assembler,
            &self.scratch,
        )
    }

    /// Newton's first guess for `q_{k+1}` ([`Increments::guess`]).
    pub(super) fn guess(&self, q: &DVector<f64>, h: f64, z: &mut DVector<f64>) {
        self.history.guess(q, h, z);
    }

    /// Records the step `q0 → q1`, of size `h`, for the next guess.
    pub(super) fn remember(&mut self, q0: &DVector<f64>, q1: &DVector<f64>, h: f64) {
        self.history.remember(q0, q1, h);
    }

    pub(super) fn assembler(&self) -> &Assembler {
        &self.assembler
    }
}

impl Assembler {
    pub(super) fn nnz(&self) -> usize {
        self.nnz
    }

    /// Every family's elements, in the order of the body.
    pub(super) fn families(&self) -> &[FamilyData] {
        &self.families
    }

    pub(super) fn orbits(&self) -> &[Vec<Range<usize>>] {
        &self.orbits
    }

    /// `r = p0 + D_1 L_d(q0, z)`, the next momentum `D_2 L_d(q0, z)` into the assembler's
    /// buffer ([`Self::take_momentum`]) and, when `jacobian` is given, its values
    /// `Σ_e D_1 D_2 L_d^e` in the pattern's order.
    pub(super) fn residual_jacobian<L: ElementLagrangian>(
        &self,
        system: &L,
        q0: &[f64],
        p0: &[f64],
        z: &[f64],
        r: &mut [f64],
        jacobian: Option<&mut [f64]>,
    ) {
        let n = self.p1.borrow().len();
        assert!(
            q0.len() == n && p0.len() == n && z.len() == n && r.len() == n,
            "dirac: an element pass on vectors of the wrong length (the integrator checks them)"
        );
        assert!(jacobian.as_ref().is_none_or(|j| j.len() == self.nnz));
        let mut p1 = self.p1.borrow_mut();
        let Some(blocks) = &self.parallel else {
            let mut scratch = self.scratch.borrow_mut();
            r.copy_from_slice(p0);
            p1.fill(0.0);
            let mut jacobian = jacobian;
            if let Some(j) = jacobian.as_deref_mut() {
                j.fill(0.0);
            }
            // SAFETY (the pointers): the serial pass is the only writer of `r`, `p1` and the
            // Jacobian while it runs, at indices below their lengths (see `pass::Visit`).
            let mut visit = Visit {
                families: &self.families,
                block: None,
                next: 0,
                q0,
                z,
                r: Shared(r.as_mut_ptr()),
                p: Shared(p1.as_mut_slice().as_mut_ptr()),
                jacobian: jacobian.map(|j| Shared(j.as_mut_ptr())),
                scratch: scratch.as_mut_slice(),
            };
            system.families(&mut visit);
            return;
        };
        // The starting values, in parallel (each entry written once: order-free).
        const CHUNK: usize = 1 << 13;
        r.par_chunks_mut(CHUNK)
            .zip(p0.par_chunks(CHUNK))
            .for_each(|(r, p0)| r.copy_from_slice(p0));
        p1.as_mut_slice()
            .par_chunks_mut(CHUNK)
            .for_each(|c| c.fill(0.0));
        let jacobian = jacobian.map(|j| {
            j.par_chunks_mut(CHUNK).for_each(|c| c.fill(0.0));
            Shared(j.as_mut_ptr())
        });
        let (r, p) = (
            Shared(r.as_mut_ptr()),
            Shared(p1.as_mut_slice().as_mut_ptr()),
        );
        let families = &self.families[..];
        (0..blocks.ranges.len()).into_par_iter().for_each(|block| {
            // One task per block: the lock is never contended (a poisoned one, after a panic in
            // another pass, still holds a usable buffer).
            let mut scratch = blocks.scratch[block]
                .lock()
                .unwrap_or_else(|poisoned| poisoned.into_inner());
            let mut visit = Visit {
                families,
                block: Some((&blocks.ranges[block], &blocks.lists[block])),
                next: 0,
                q0,
                z,
                r,
                p,
                jacobian,
                scratch: scratch.as_mut_slice(),
            };
            system.families(&mut visit);
        });
    }

    /// Swaps the next momentum of the last pass, `D_2 L_d(q0, z)`, into `p`.
    pub(super) fn take_momentum(&self, p: &mut DVector<f64>) {
        std::mem::swap(&mut *self.p1.borrow_mut(), p);
    }
}
