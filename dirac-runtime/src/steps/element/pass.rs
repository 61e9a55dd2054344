//! The pass over the elements that a step's residual and Jacobian are assembled from — one
//! implementation for the serial pass (every element, every row) and for a block of the parallel
//! pass (the elements touching the block's rows, written into those rows only) — and the
//! element scratch and gathers the other passes share.
//!
//! A family's stencil width is data ([`Family::width`]); the pass runs it as a constant for the
//! small widths of chains, lattices and meshes ([`with_width`]), so the gathers and scatters
//! unroll as straight-line code, and as a run-time value above.

use std::cell::RefCell;
use std::ops::Range;

use super::assembly::FamilyData;
use super::{Family, FamilyVisitor};

/// A pointer to a buffer that a pass writes: the serial pass alone, or the blocks of a parallel
/// pass at disjoint rows.
#[derive(Clone, Copy)]
pub(super) struct Shared(pub(super) *mut f64);

// SAFETY: a `Shared` is only written through by the blocks of one pass, each at the rows (and
// the Jacobian entries of the rows) it owns; the owned sets are disjoint.
unsafe impl Send for Shared {}
unsafe impl Sync for Shared {}

/// A family's stencil width in the passes' inner loops (see [`with_width`]).
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

/// Something run with a family's width.
pub(super) trait WithWidth {
    type Output;
    fn run<W: Width>(self, width: W) -> Self::Output;
}

/// Runs `f` with the width `w` as a constant ([`Fixed`]) for widths 1 to 4, as a run-time value
/// ([`Runtime`]) above: one instance of the pass per constant width.
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

/// The stencil values of an element, `v[st[a]]`, into `out` (as long as `st`).
#[inline(always)]
pub(super) fn gather(v: &[f64], st: &[usize], out: &mut [f64]) {
    for (o, &g) in out.iter_mut().zip(st) {
        *o = v[g];
    }
}

/// [`gather`] without bounds checks, for the step's inner loops.
///
/// # Safety
/// Every `st[a] < v.len()` and `out.len() >= st.len()`: the stencils are checked against the
/// dimension when the workspace is built (a workspace with an invalid stencil never assembles),
/// the vectors' lengths at the entry of the assembly, and the scratch is sized for the widest
/// family.
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

/// One pass of the assembly over every family, in the order of the body: `r += Σ D_1 L_d^e`,
/// `p += Σ D_2 L_d^e` and, when given, `jacobian += Σ D_1 D_2 L_d^e` at the pattern's positions
/// (each starting from what the caller put there) — every element into every row (serial), or
/// one block's elements into the block's rows only (parallel). Each row receives its
/// contributions in the same order either way, so the two give the same sums bit for bit.
///
/// The writers' contract: `r`, `p` have the system's dimension `n`, `jacobian` the pattern's
/// `nnz` entries, `q0`, `z` length `n`; no one else writes the rows the pass owns while it runs.
pub(super) struct Visit<'a> {
    pub(super) families: &'a [FamilyData],
    /// The block's rows and, per family, the elements that touch them; `None`: every row and
    /// element.
    pub(super) block: Option<(&'a Range<usize>, &'a [Vec<u32>])>,
    /// The index of the next family visited.
    pub(super) next: usize,
    pub(super) q0: &'a [f64],
    pub(super) z: &'a [f64],
    pub(super) r: Shared,
    pub(super) p: Shared,
    pub(super) jacobian: Option<Shared>,
    /// The element scratch (`scratch_len` of the widest family).
    pub(super) scratch: &'a mut [f64],
}

impl FamilyVisitor for Visit<'_> {
    fn family<F: Family>(&mut self, family: &F) {
        let index = self.next;
        self.next += 1;
        let data = &self.families[index];
        if data.width == 0 {
            return;
        }
        let (rows, elements) = match self.block {
            None => (None, None),
            Some((rows, lists)) => (Some(rows), Some(&lists[index][..])),
        };
        let pass = ElementsPass {
            family,
            data,
            rows,
            elements,
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

/// One family's part of a [`Visit`].
struct ElementsPass<'a, F> {
    family: &'a F,
    data: &'a FamilyData,
    /// The rows written (`None`: all).
    rows: Option<&'a Range<usize>>,
    /// The elements evaluated, in increasing order (`None`: all).
    elements: Option<&'a [u32]>,
    q0: &'a [f64],
    z: &'a [f64],
    r: Shared,
    p: Shared,
    jacobian: Option<Shared>,
    scratch: &'a mut [f64],
}

/// The rows a pass writes: all of them, or one block's.
trait Rows: Copy {
    fn owns(self, g: usize) -> bool;
}

#[derive(Clone, Copy)]
struct AllRows;

impl Rows for AllRows {
    #[inline(always)]
    fn owns(self, _: usize) -> bool {
        true
    }
}

impl Rows for &Range<usize> {
    #[inline(always)]
    fn owns(self, g: usize) -> bool {
        self.contains(&g)
    }
}

impl<F: Family> WithWidth for ElementsPass<'_, F> {
    type Output = ();

    #[inline(always)]
    fn run<W: Width>(self, width: W) {
        match (self.rows, self.elements) {
            (Some(rows), Some(list)) => {
                self.elements_of(width, rows, list.iter().map(|&e| e as usize));
            }
            _ => {
                let count = self.data.count;
                self.elements_of(width, AllRows, 0..count);
            }
        }
    }
}

impl<F: Family> ElementsPass<'_, F> {
    /// The pass over `elements` into `rows`, the width `width`.
    #[inline(always)]
    fn elements_of<W: Width, R: Rows>(
        self,
        width: W,
        rows: R,
        elements: impl Iterator<Item = usize>,
    ) {
        let ElementsPass {
            family,
            data,
            q0,
            z,
            r,
            p,
            jacobian,
            scratch,
            ..
        } = self;
        let (depth, w) = (data.depth, width.get());
        let (a0, a1, out) = split_scratch(scratch, w);
        let (a0, a1) = (&mut a0[..w], &mut a1[..w]);
        // SAFETY (every unchecked access below): `data` holds `count · w` stencil entries,
        // `count · depth` indices and `count · w²` positions, and every element listed is below
        // `count` (built together); the stencil entries are below `n` (checked when the
        // workspace was built); the buffers' lengths are the writers' contract of `Visit`; a
        // row written is owned by this pass alone.
        match jacobian {
            None => {
                let out = &mut out[..2 * w];
                for e in elements {
                    unsafe {
                        let st = data.stencils.get_unchecked(e * w..(e + 1) * w);
                        let indices = data.indices.get_unchecked(e * depth..(e + 1) * depth);
                        gather_unchecked(q0, st, a0);
                        gather_unchecked(z, st, a1);
                        family.d1_d2(indices, a0, a1, out);
                        for a in 0..w {
                            let g = *st.get_unchecked(a);
                            if rows.owns(g) {
                                *r.0.add(g) += *out.get_unchecked(a);
                                *p.0.add(g) += *out.get_unchecked(w + a);
                            }
                        }
                    }
                }
            }
            Some(j) => {
                let out = &mut out[..2 * w + w * w];
                for e in elements {
                    unsafe {
                        let st = data.stencils.get_unchecked(e * w..(e + 1) * w);
                        let indices = data.indices.get_unchecked(e * depth..(e + 1) * depth);
                        let pos = data.positions.get_unchecked(e * w * w..(e + 1) * w * w);
                        gather_unchecked(q0, st, a0);
                        gather_unchecked(z, st, a1);
                        family.d1_d2_d12(indices, a0, a1, out);
                        for a in 0..w {
                            let g = *st.get_unchecked(a);
                            if !rows.owns(g) {
                                continue;
                            }
                            *r.0.add(g) += *out.get_unchecked(a);
                            *p.0.add(g) += *out.get_unchecked(w + a);
                            for b in 0..w {
                                *j.0.add(*pos.get_unchecked(a * w + b)) +=
                                    *out.get_unchecked(2 * w + a * w + b);
                            }
                        }
                    }
                }
            }
        }
    }
}
