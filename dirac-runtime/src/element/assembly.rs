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

use super::solver::ElementSolver;
use super::stencils::FamilyPass;
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

/// A pointer to a buffer that the blocks of a parallel pass write at disjoint rows.
#[derive(Clone, Copy)]
struct Shared(*mut f64);

// SAFETY: a `Shared` is only written through by the blocks of one pass, each at the rows (and
// the Jacobian entries of the rows) it owns; the owned sets are disjoint.
unsafe impl Send for Shared {}
unsafe impl Sync for Shared {}

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
    /// `q_k − q_{k−1}` and `q_{k−1} − q_{k−2}`, and how many of them are known (0, 1, 2).
    last: DVector<f64>,
    before: DVector<f64>,
    known: u8,
    /// The sizes of those two steps, newest first.
    steps: (f64, f64),
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
            last: DVector::zeros(n),
            before: DVector::zeros(n),
            known: 0,
            steps: (f64::NAN, f64::NAN),
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

    /// Newton's first guess for `q_{k+1}`, over a step of size `h`, into `z`: `q_k` plus the
    /// increment the last two extrapolate (`2 Δ_{k−1} − Δ_{k−2}` on a uniform grid, the
    /// quadratic through the last three points on another: `crate::stepper`'s
    /// `predicted_increment`; `Δ_{k−1}` scaled to `h` after one step; none before).
    pub(super) fn guess(&self, q: &DVector<f64>, h: f64, z: &mut DVector<f64>) {
        z.copy_from(q);
        let (h1, h2) = self.steps;
        let same = |a: f64| a.to_bits() == h.to_bits();
        match self.known {
            0 => {}
            1 if same(h1) => *z += &self.last,
            1 => z.axpy(h / h1, &self.last, 1.0),
            _ if same(h1) && same(h2) => {
                for ((zi, l), b) in z.iter_mut().zip(self.last.iter()).zip(self.before.iter()) {
                    *zi += 2.0 * l - b;
                }
            }
            _ => {
                // Δ = h v1 + c (v1 − v2), v_i = Δ_i / h_i, c = h (h + h1) / (h1 + h2).
                let c = h * (h + h1) / (h1 + h2);
                let (a, b) = ((h + c) / h1, c / h2);
                for ((zi, l), p) in z.iter_mut().zip(self.last.iter()).zip(self.before.iter()) {
                    *zi += a * l - b * p;
                }
            }
        }
    }

    /// Records the step `q0 → q1`, of size `h`, for the next guess.
    pub(super) fn remember(&mut self, q0: &DVector<f64>, q1: &DVector<f64>, h: f64) {
        std::mem::swap(&mut self.last, &mut self.before);
        self.last.copy_from(q1);
        self.last -= q0;
        self.steps = (h, self.steps.0);
        self.known = (self.known + 1).min(2);
    }

    pub(super) fn assembler(&self) -> &Assembler {
        &self.assembler
    }
}

/// The buffers of a pass over the elements: `r += Σ D_1 L_d^e`, `p += Σ D_2 L_d^e` and, when
/// given, `jacobian += Σ D_1 D_2 L_d^e` (each starting from what the caller put there).
struct Pass<'a> {
    q0: &'a [f64],
    z: &'a [f64],
    r: &'a mut [f64],
    p: &'a mut [f64],
    jacobian: Option<&'a mut [f64]>,
}

struct Visit<'a, 'p> {
    assembler: &'a Assembler,
    next: usize,
    pass: Pass<'p>,
    /// The element scratch ([`scratch_len`] of the widest family).
    scratch: &'p mut [f64],
}

/// The stencil values of an element, `v[st[a]]`, into `out` (as long as `st`).
#[inline(always)]
pub(super) fn gather(v: &[f64], st: &[usize], out: &mut [f64]) {
    for (o, &g) in out.iter_mut().zip(st) {
        *o = v[g];
    }
}

/// [`gather`] without bounds checks, for the passes' inner loops.
///
/// # Safety
/// Every `st[a] < v.len()` and `out.len() >= st.len()`: the stencils are checked against the
/// dimension when the workspace is built (a workspace with an invalid stencil never assembles),
/// the vectors' lengths at the entry of [`Assembler::residual_jacobian`], and the scratch is
/// sized for the widest family.
#[inline(always)]
unsafe fn gather_unchecked(v: &[f64], st: &[usize], out: &mut [f64]) {
    for (a, &g) in st.iter().enumerate() {
        // SAFETY: see the function's contract.
        unsafe { *out.get_unchecked_mut(a) = *v.get_unchecked(g) };
    }
}

thread_local! {
    /// The element scratch of the passes outside a step's assembly (sums, impulses, constraint
    /// rows, the Legendre map, partials): a stencil's indices and its values and outputs, grown
    /// to the widest family a thread has seen, so that after a run's first step those passes
    /// allocate nothing.
    static SCRATCH: RefCell<(Vec<usize>, Vec<f64>)> = const { RefCell::new((Vec::new(), Vec::new())) };
}

/// Calls `f` with `stencil` indices and `len` numbers of scratch: this thread's buffers (grown
/// once when too short), or fresh ones when a pass on this thread already holds them.
pub(super) fn with_scratch<R>(
    stencil: usize,
    len: usize,
    f: impl FnOnce(&mut [usize], &mut [f64]) -> R,
) -> R {
    SCRATCH.with(|cell| match cell.try_borrow_mut() {
        Ok(mut buffers) => {
            let (st, values) = &mut *buffers;
            if st.len() < stencil {
                st.resize(stencil, 0);
            }
            if values.len() < len {
                values.resize(len, 0.0);
            }
            f(&mut st[..stencil], &mut values[..len])
        }
        Err(_) => f(&mut vec![0; stencil], &mut vec![0.0; len]),
    })
}

/// The element scratch of a family of width `w` split into the stencil values `q0`, `q1` (`w`
/// each) and the outputs (the rest).
#[inline(always)]
pub(super) fn split_scratch(scratch: &mut [f64], w: usize) -> (&mut [f64], &mut [f64], &mut [f64]) {
    let (a0, rest) = scratch.split_at_mut(w);
    let (a1, out) = rest.split_at_mut(w);
    (a0, a1, out)
}

/// A family's stencil width in the passes' inner loops: a constant for the small widths the
/// dispatch in [`with_width`] names, so that LLVM unrolls the gathers and scatters as it did when
/// the width was a const generic of the family, and the run-time value above them.
pub(super) trait Width: Copy {
    fn get(self) -> usize;
}

/// A width known when the pass is compiled.
#[derive(Clone, Copy)]
pub(super) struct Fixed<const S: usize>;

impl<const S: usize> Width for Fixed<S> {
    #[inline(always)]
    fn get(self) -> usize {
        S
    }
}

/// A width known when the run starts.
#[derive(Clone, Copy)]
pub(super) struct Runtime(usize);

impl Width for Runtime {
    #[inline(always)]
    fn get(self) -> usize {
        self.0
    }
}

/// Something run with a family's width: [`Fixed`] for widths 1 to 4, [`Runtime`] above.
pub(super) trait WithWidth {
    type Output;
    fn run<W: Width>(self, width: W) -> Self::Output;
}

/// Runs `f` with `w` as a constant when it is small (the stencils of chains, lattices and
/// meshes), else as a run-time value: one instance of the pass per constant width.
#[inline(always)]
pub(super) fn with_width<F: WithWidth>(w: usize, f: F) -> F::Output {
    match w {
        1 => f.run(Fixed::<1>),
        2 => f.run(Fixed::<2>),
        3 => f.run(Fixed::<3>),
        4 => f.run(Fixed::<4>),
        _ => f.run(Runtime(w)),
    }
}

/// The serial pass over one family's elements (see [`Visit`]).
struct SerialFamily<'a, 'b, F> {
    family: &'a F,
    data: &'a FamilyData,
    q0: &'a [f64],
    z: &'a [f64],
    r: &'b mut [f64],
    p: &'b mut [f64],
    jacobian: Option<&'b mut [f64]>,
    scratch: &'b mut [f64],
}

impl<F: Family> WithWidth for SerialFamily<'_, '_, F> {
    type Output = ();

    #[inline(always)]
    fn run<W: Width>(self, width: W) {
        let SerialFamily {
            family,
            data,
            q0,
            z,
            r,
            p,
            jacobian,
            scratch,
        } = self;
        let (depth, w) = (data.depth, width.get());
        let indices = |e: usize| &data.indices[e * depth..(e + 1) * depth];
        let (a0, a1, out) = split_scratch(scratch, w);
        let (a0, a1) = (&mut a0[..w], &mut a1[..w]);
        let stencils = data.stencils.chunks_exact(w);
        // SAFETY (every unchecked access below): the stencil entries are below the dimension
        // `n` (checked when the workspace was built), and `q0`, `z`, `r`, `p` have length `n`
        // (checked at the entry of the pass); the scratch holds `4w + w²` entries (sized for
        // the widest family); a Jacobian position is an index into the values of the pattern,
        // of length `nnz`, built with it.
        match jacobian {
            None => {
                let out = &mut out[..2 * w];
                for (e, st) in stencils.enumerate() {
                    let st = &st[..w];
                    unsafe {
                        gather_unchecked(q0, st, a0);
                        gather_unchecked(z, st, a1);
                    }
                    family.d1_d2(indices(e), a0, a1, out);
                    let (d1, d2) = out.split_at(w);
                    for a in 0..w {
                        unsafe {
                            let g = *st.get_unchecked(a);
                            *r.get_unchecked_mut(g) += *d1.get_unchecked(a);
                            *p.get_unchecked_mut(g) += *d2.get_unchecked(a);
                        }
                    }
                }
            }
            Some(j) => {
                let out = &mut out[..2 * w + w * w];
                let positions = data.positions.chunks_exact(w * w);
                for (e, (st, pos)) in stencils.zip(positions).enumerate() {
                    let (st, pos) = (&st[..w], &pos[..w * w]);
                    unsafe {
                        gather_unchecked(q0, st, a0);
                        gather_unchecked(z, st, a1);
                    }
                    family.d1_d2_d12(indices(e), a0, a1, out);
                    let (d1, rest) = out.split_at(w);
                    let (d2, d12) = rest.split_at(w);
                    for a in 0..w {
                        unsafe {
                            let g = *st.get_unchecked(a);
                            *r.get_unchecked_mut(g) += *d1.get_unchecked(a);
                            *p.get_unchecked_mut(g) += *d2.get_unchecked(a);
                        }
                    }
                    for b in 0..w * w {
                        unsafe {
                            *j.get_unchecked_mut(*pos.get_unchecked(b)) += *d12.get_unchecked(b)
                        };
                    }
                }
            }
        }
    }
}

impl FamilyVisitor for Visit<'_, '_> {
    fn family<F: Family>(&mut self, family: &F) {
        let index = self.next;
        self.next += 1;
        let data = &self.assembler.families[index];
        let Pass {
            q0,
            z,
            r,
            p,
            jacobian,
        } = &mut self.pass;
        if self.assembler.parallel.is_some() {
            unreachable!("parallel passes visit the families block by block");
        }
        if data.width == 0 {
            return;
        }
        let pass = SerialFamily {
            family,
            data,
            q0,
            z,
            r,
            p,
            jacobian: jacobian.as_deref_mut(),
            scratch: self.scratch,
        };
        with_width(data.width, pass);
    }
}

/// The parallel pass of one block: every family's elements that touch the block's rows, in
/// order, added into the block's rows only.
struct BlockVisit<'a> {
    families: &'a [FamilyData],
    blocks: &'a Blocks,
    block: usize,
    next: usize,
    q0: &'a [f64],
    z: &'a [f64],
    r: Shared,
    p: Shared,
    jacobian: Option<Shared>,
    /// The block's element scratch.
    scratch: &'a mut [f64],
}

/// The parallel pass over one family's elements that touch one block's rows (see
/// [`BlockVisit`]).
struct BlockFamily<'a, F> {
    family: &'a F,
    data: &'a FamilyData,
    elements: &'a [u32],
    owned: &'a Range<usize>,
    q0: &'a [f64],
    z: &'a [f64],
    r: Shared,
    p: Shared,
    jacobian: Option<Shared>,
    scratch: &'a mut [f64],
}

impl<F: Family> WithWidth for BlockFamily<'_, F> {
    type Output = ();

    #[inline(always)]
    fn run<W: Width>(self, width: W) {
        let BlockFamily {
            family,
            data,
            elements,
            owned,
            q0,
            z,
            r,
            p,
            jacobian,
            scratch,
        } = self;
        let (depth, w) = (data.depth, width.get());
        let (a0, a1, out) = split_scratch(scratch, w);
        let (a0, a1) = (&mut a0[..w], &mut a1[..w]);
        for &e in elements {
            let e = e as usize;
            let st = &data.stencils[e * w..(e + 1) * w];
            let indices = &data.indices[e * depth..(e + 1) * depth];
            // SAFETY: as in the serial pass (stencils below `n`, vectors of length `n`, the
            // scratch sized for the widest family).
            unsafe {
                gather_unchecked(q0, st, a0);
                gather_unchecked(z, st, a1);
            }
            match jacobian {
                None => {
                    let out = &mut out[..2 * w];
                    family.d1_d2(indices, a0, a1, out);
                    for a in 0..w {
                        if owned.contains(&st[a]) {
                            // SAFETY: row st[a] is owned by this block alone.
                            unsafe {
                                *r.0.add(st[a]) += out[a];
                                *p.0.add(st[a]) += out[w + a];
                            }
                        }
                    }
                }
                Some(j) => {
                    let out = &mut out[..2 * w + w * w];
                    family.d1_d2_d12(indices, a0, a1, out);
                    let pos = &data.positions[e * w * w..(e + 1) * w * w];
                    for a in 0..w {
                        if !owned.contains(&st[a]) {
                            continue;
                        }
                        // SAFETY: row st[a], and every Jacobian entry of that row, is owned by
                        // this block alone.
                        unsafe {
                            *r.0.add(st[a]) += out[a];
                            *p.0.add(st[a]) += out[w + a];
                            for b in 0..w {
                                *j.0.add(pos[a * w + b]) += out[2 * w + a * w + b];
                            }
                        }
                    }
                }
            }
        }
    }
}

impl FamilyVisitor for BlockVisit<'_> {
    fn family<F: Family>(&mut self, family: &F) {
        let index = self.next;
        self.next += 1;
        let data = &self.families[index];
        if data.width == 0 {
            return;
        }
        let pass = BlockFamily {
            family,
            data,
            elements: &self.blocks.lists[self.block][index],
            owned: &self.blocks.ranges[self.block],
            q0: self.q0,
            z: self.z,
            r: self.r,
            p: self.p,
            jacobian: self.jacobian,
            scratch: self.scratch,
        };
        with_width(data.width, pass);
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
            let mut visit = Visit {
                assembler: self,
                next: 0,
                pass: Pass {
                    q0,
                    z,
                    r,
                    p: p1.as_mut_slice(),
                    jacobian,
                },
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
            let mut visit = BlockVisit {
                families,
                blocks,
                block,
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
