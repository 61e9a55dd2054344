//! Assembly of an element-wise system: the stencils and the Jacobian's pattern, built once per
//! run, and the passes over the elements that scatter their residuals and Jacobian blocks —
//! serial, or in parallel with the same sums in the same order (see [`super`]).

use std::cell::RefCell;
use std::ops::Range;

use nalgebra::DVector;
use rayon::prelude::*;

use super::{ElementLagrangian, Family, FamilyVisitor, Parallel, PARALLEL_MIN_ENTRIES};
use crate::linalg::DynSparseLu;

/// The elements of one family as a run sees them.
struct FamilyData {
    /// Stencil width `S`.
    width: usize,
    /// Loop depth.
    depth: usize,
    /// Number of elements.
    count: usize,
    /// The loop indices of every element, `depth` per element.
    indices: Vec<i64>,
    /// The global coordinate indices of every element's stencil, `width` per element.
    stencils: Vec<usize>,
    /// For every element, the positions of its `width²` block entries in the Jacobian's values.
    positions: Vec<usize>,
    /// Where this family's slots start in the per-element buffers of a parallel pass.
    slot_offset: usize,
    /// Where this family's block entries start in the per-element buffers of a parallel pass.
    block_offset: usize,
}

/// For each target (a residual row, a Jacobian value) the offsets of its contributions in the
/// per-element buffers, in increasing order: compressed rows.
struct Gather {
    ptr: Vec<usize>,
    offsets: Vec<usize>,
}

impl Gather {
    /// From `(target, offset)` pairs: grouped by target, offsets increasing.
    fn new(targets: usize, mut pairs: Vec<(usize, usize)>) -> Self {
        pairs.sort_unstable();
        let mut ptr = vec![0; targets + 1];
        for &(t, _) in &pairs {
            ptr[t + 1] += 1;
        }
        for t in 0..targets {
            ptr[t + 1] += ptr[t];
        }
        Self {
            ptr,
            offsets: pairs.into_iter().map(|(_, o)| o).collect(),
        }
    }

    /// `out[t] = start(t) + Σ buffer[offsets of t]`, in offset order, in parallel over `t`.
    fn sum_into(&self, out: &mut [f64], buffer: &[f64], start: impl Fn(usize) -> f64 + Sync) {
        out.par_iter_mut()
            .with_min_len(4096)
            .enumerate()
            .for_each(|(t, o)| {
                let mut v = start(t);
                for &off in &self.offsets[self.ptr[t]..self.ptr[t + 1]] {
                    v += buffer[off];
                }
                *o = v;
            });
    }
}

/// The parallel passes' memory: every element's slots and block entries, and how to gather
/// them into rows and Jacobian values.
struct ParallelPasses {
    rows: Gather,
    values: Gather,
    slots: RefCell<Vec<f64>>,
    blocks: RefCell<Vec<f64>>,
}

/// The elements, the pattern and the passes over them.
pub(super) struct Assembler {
    families: Vec<FamilyData>,
    nnz: usize,
    parallel: Option<ParallelPasses>,
    orbits: Vec<Vec<Range<usize>>>,
}

/// The workspace of an [`super::ElementIntegrator`] run: the elements' stencils, the Jacobian's
/// pattern and its sparse LU, the residual and Jacobian buffers, the last two increments
/// Newton's guess extrapolates from. Built once per run (the only allocations of a run).
pub struct ElementWorkspace {
    n: usize,
    invalid: Option<String>,
    solver: DynSparseLu,
    r: DVector<f64>,
    jacobian: Option<Vec<f64>>,
    assembler: Assembler,
    /// `q_k − q_{k−1}` and `q_{k−1} − q_{k−2}`, and how many of them are known (0, 1, 2).
    last: DVector<f64>,
    before: DVector<f64>,
    known: u8,
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

/// Collects every family's elements and stencils; records the first stencil out of range.
struct Collector {
    n: usize,
    families: Vec<FamilyData>,
    invalid: Option<String>,
}

impl FamilyVisitor for Collector {
    fn family<const S: usize, F: Family<S>>(&mut self, family: &F) {
        let (n, index) = (self.n, self.families.len());
        let mut data = FamilyData {
            width: S,
            depth: F::DEPTH,
            count: 0,
            indices: Vec::new(),
            stencils: Vec::new(),
            positions: Vec::new(),
            slot_offset: 0,
            block_offset: 0,
        };
        let invalid = &mut self.invalid;
        family.elements(&mut |indices, stencil| {
            data.count += 1;
            data.indices.extend_from_slice(indices);
            for (slot, &g) in stencil.iter().enumerate() {
                match usize::try_from(g).ok().filter(|&g| g < n) {
                    Some(g) => data.stencils.push(g),
                    None => {
                        if invalid.is_none() {
                            *invalid = Some(format!(
                                "element {indices:?} of family {index} reads coordinate {g} (slot {slot}), outside 0..{n}: the sizes are too small for its stencil"
                            ));
                        }
                        data.stencils.push(0);
                    }
                }
            }
        });
        self.families.push(data);
    }
}

/// Every stencil against the system's dimension: `Err` with the first one out of range.
pub(super) fn check_stencils<L: ElementLagrangian>(system: &L) -> Result<(), String> {
    let mut collector = Collector {
        n: system.dim(),
        families: Vec::new(),
        invalid: None,
    };
    system.families(&mut collector);
    collector.invalid.map_or(Ok(()), Err)
}

impl ElementWorkspace {
    pub(super) fn new<L: ElementLagrangian>(system: &L, parallel: Parallel) -> Self {
        let n = system.dim();
        let mut collector = Collector {
            n,
            families: Vec::new(),
            invalid: None,
        };
        system.families(&mut collector);
        let Collector {
            mut families,
            invalid,
            ..
        } = collector;
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
        let (mut slots, mut blocks) = (0, 0);
        for f in &mut families {
            f.positions = Vec::with_capacity(f.count * f.width * f.width);
            for st in f.stencils.chunks_exact(f.width.max(1)) {
                for &row in st {
                    for &col in st {
                        f.positions.push(position(row, col));
                    }
                }
            }
            f.slot_offset = slots;
            f.block_offset = blocks;
            slots += f.count * f.width;
            blocks += f.count * f.width * f.width;
        }
        let nnz = row_idx.len();
        let threads = rayon::current_num_threads();
        let parallel = match parallel {
            Parallel::Never => false,
            Parallel::Always => true,
            Parallel::Auto => blocks >= PARALLEL_MIN_ENTRIES && threads > 1,
        };
        let parallel = parallel.then(|| {
            let mut rows = Vec::with_capacity(slots);
            let mut values = Vec::with_capacity(blocks);
            for f in &families {
                for (e, st) in f.stencils.chunks_exact(f.width.max(1)).enumerate() {
                    for (a, &row) in st.iter().enumerate() {
                        rows.push((row, f.slot_offset + e * f.width + a));
                    }
                }
                for (b, &p) in f.positions.iter().enumerate() {
                    values.push((p, f.block_offset + b));
                }
            }
            ParallelPasses {
                rows: Gather::new(n, rows),
                values: Gather::new(nnz, values),
                slots: RefCell::new(vec![0.0; slots]),
                blocks: RefCell::new(vec![0.0; blocks]),
            }
        });
        Self {
            n,
            invalid,
            solver: DynSparseLu::new(n, col_ptr, row_idx),
            r: DVector::zeros(n),
            jacobian: None,
            assembler: Assembler {
                families,
                nnz,
                parallel,
                orbits: system.translations(),
            },
            last: DVector::zeros(n),
            before: DVector::zeros(n),
            known: 0,
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
        (self.solver.col_ptr(), self.solver.row_idx())
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

    #[allow(clippy::type_complexity)]
    pub(super) fn parts(
        &mut self,
    ) -> (
        &mut DynSparseLu,
        &mut DVector<f64>,
        &mut Option<Vec<f64>>,
        &Assembler,
    ) {
        (
            &mut self.solver,
            &mut self.r,
            &mut self.jacobian,
            &self.assembler,
        )
    }

    /// Newton's first guess for `q_{k+1}` into `z`: `q_k` plus the increment the last two
    /// extrapolate (`2 Δ_{k−1} − Δ_{k−2}`, or `Δ_{k−1}`, or none).
    pub(super) fn guess(&self, q: &DVector<f64>, z: &mut DVector<f64>) {
        z.copy_from(q);
        match self.known {
            0 => {}
            1 => *z += &self.last,
            _ => {
                for ((zi, l), b) in z.iter_mut().zip(self.last.iter()).zip(self.before.iter()) {
                    *zi += 2.0 * l - b;
                }
            }
        }
    }

    /// Records the step `q0 → q1` for the next guess.
    pub(super) fn remember(&mut self, q0: &DVector<f64>, q1: &DVector<f64>) {
        std::mem::swap(&mut self.last, &mut self.before);
        self.last.copy_from(q1);
        self.last -= q0;
        self.known = (self.known + 1).min(2);
    }

    pub(super) fn residual_jacobian<L: ElementLagrangian>(
        &self,
        system: &L,
        q0: &[f64],
        p0: &[f64],
        z: &[f64],
        r: &mut [f64],
        jacobian: Option<&mut [f64]>,
    ) {
        self.assembler
            .residual_jacobian(system, q0, p0, z, r, jacobian)
    }
}

/// What a pass over the elements computes.
enum Pass<'a> {
    /// `r += Σ D_1 L_d^e` (serial), and `jacobian += Σ D_1 D_2 L_d^e` when given.
    Residual {
        q0: &'a [f64],
        z: &'a [f64],
        r: &'a mut [f64],
        jacobian: Option<&'a mut [f64]>,
    },
    /// `p += Σ D_2 L_d^e` (serial).
    Momentum {
        q0: &'a [f64],
        z: &'a [f64],
        p: &'a mut [f64],
    },
    /// Every element's `D_1 L_d^e` (or `D_2 L_d^e`) into `slots` and, when given,
    /// `D_1 D_2 L_d^e` into `blocks` (parallel).
    Elements {
        q0: &'a [f64],
        z: &'a [f64],
        second: bool,
        slots: &'a mut [f64],
        blocks: Option<&'a mut [f64]>,
    },
}

struct Visit<'a, 'p> {
    families: &'a [FamilyData],
    next: usize,
    pass: Pass<'p>,
}

/// The stencil values of element `e`.
#[inline(always)]
fn gather<const S: usize>(v: &[f64], st: &[usize]) -> [f64; S] {
    std::array::from_fn(|a| v[st[a]])
}

impl FamilyVisitor for Visit<'_, '_> {
    fn family<const S: usize, F: Family<S>>(&mut self, family: &F) {
        let data = &self.families[self.next];
        self.next += 1;
        let (depth, count) = (data.depth, data.count);
        let indices = |e: usize| &data.indices[e * depth..(e + 1) * depth];
        let stencil = |e: usize| &data.stencils[e * S..(e + 1) * S];
        match &mut self.pass {
            Pass::Residual {
                q0,
                z,
                r,
                jacobian: None,
            } => {
                for e in 0..count {
                    let st = stencil(e);
                    let d1 = family.d1(indices(e), &gather(q0, st), &gather(z, st));
                    for a in 0..S {
                        r[st[a]] += d1[a];
                    }
                }
            }
            Pass::Residual {
                q0,
                z,
                r,
                jacobian: Some(j),
            } => {
                for e in 0..count {
                    let st = stencil(e);
                    let (d1, d12) = family.d1_d12(indices(e), &gather(q0, st), &gather(z, st));
                    for a in 0..S {
                        r[st[a]] += d1[a];
                    }
                    let pos = &data.positions[e * S * S..(e + 1) * S * S];
                    for a in 0..S {
                        for b in 0..S {
                            j[pos[a * S + b]] += d12[a][b];
                        }
                    }
                }
            }
            Pass::Momentum { q0, z, p } => {
                for e in 0..count {
                    let st = stencil(e);
                    let d2 = family.d2(indices(e), &gather(q0, st), &gather(z, st));
                    for a in 0..S {
                        p[st[a]] += d2[a];
                    }
                }
            }
            Pass::Elements {
                q0,
                z,
                second,
                slots,
                blocks,
            } => {
                let (q0, z, second) = (*q0, *z, *second);
                let slots = &mut slots[data.slot_offset..data.slot_offset + count * S];
                match blocks {
                    Some(blocks) => {
                        let blocks =
                            &mut blocks[data.block_offset..data.block_offset + count * S * S];
                        slots
                            .par_chunks_mut(S.max(1))
                            .zip(blocks.par_chunks_mut((S * S).max(1)))
                            .with_min_len(256)
                            .enumerate()
                            .for_each(|(e, (d1_out, d12_out))| {
                                let st = stencil(e);
                                let (d1, d12) =
                                    family.d1_d12(indices(e), &gather(q0, st), &gather(z, st));
                                d1_out.copy_from_slice(&d1);
                                for a in 0..S {
                                    d12_out[a * S..(a + 1) * S].copy_from_slice(&d12[a]);
                                }
                            });
                    }
                    None => {
                        slots
                            .par_chunks_mut(S.max(1))
                            .with_min_len(256)
                            .enumerate()
                            .for_each(|(e, out)| {
                                let st = stencil(e);
                                let (a, b) = (gather(q0, st), gather(z, st));
                                let d = if second {
                                    family.d2(indices(e), &a, &b)
                                } else {
                                    family.d1(indices(e), &a, &b)
                                };
                                out.copy_from_slice(&d);
                            });
                    }
                }
            }
        }
    }
}

impl Assembler {
    pub(super) fn nnz(&self) -> usize {
        self.nnz
    }

    pub(super) fn orbits(&self) -> &[Vec<Range<usize>>] {
        &self.orbits
    }

    fn visit<L: ElementLagrangian>(&self, system: &L, pass: Pass<'_>) {
        let mut visit = Visit {
            families: &self.families,
            next: 0,
            pass,
        };
        system.families(&mut visit);
    }

    /// `r = p0 + D_1 L_d(q0, z)` and, when `jacobian` is given, its values
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
        match &self.parallel {
            None => {
                r.copy_from_slice(p0);
                let jacobian = jacobian.map(|j| {
                    j.fill(0.0);
                    j
                });
                self.visit(
                    system,
                    Pass::Residual {
                        q0,
                        z,
                        r,
                        jacobian,
                    },
                );
            }
            Some(passes) => {
                let mut slots = passes.slots.borrow_mut();
                let mut blocks = passes.blocks.borrow_mut();
                let with_jacobian = jacobian.is_some();
                self.visit(
                    system,
                    Pass::Elements {
                        q0,
                        z,
                        second: false,
                        slots: &mut slots,
                        blocks: with_jacobian.then_some(&mut blocks[..]),
                    },
                );
                passes.rows.sum_into(r, &slots, |t| p0[t]);
                if let Some(j) = jacobian {
                    passes.values.sum_into(j, &blocks, |_| 0.0);
                }
            }
        }
    }

    /// `p = D_2 L_d(q0, z)`.
    pub(super) fn momentum<L: ElementLagrangian>(
        &self,
        system: &L,
        q0: &[f64],
        z: &[f64],
        p: &mut [f64],
    ) {
        match &self.parallel {
            None => {
                p.fill(0.0);
                self.visit(system, Pass::Momentum { q0, z, p });
            }
            Some(passes) => {
                let mut slots = passes.slots.borrow_mut();
                self.visit(
                    system,
                    Pass::Elements {
                        q0,
                        z,
                        second: true,
                        slots: &mut slots,
                        blocks: None,
                    },
                );
                passes.rows.sum_into(p, &slots, |_| 0.0);
            }
        }
    }
}

/// Sums a per-element scalar over every element, serially, in order.
struct Scalar<G> {
    element: G,
    /// The number of coordinates: an element reading outside makes the sum NaN.
    n: usize,
    total: f64,
}

/// What a scalar pass evaluates per element: its stencil values in `q0` and `q1`.
trait ElementScalar {
    fn eval<const S: usize, F: Family<S>>(&self, f: &F, indices: &[i64], st: [usize; S]) -> f64;
}

impl<G: ElementScalar> FamilyVisitor for Scalar<G> {
    fn family<const S: usize, F: Family<S>>(&mut self, family: &F) {
        let (element, n) = (&self.element, self.n);
        let mut total = self.total;
        family.elements(&mut |indices, stencil| {
            if stencil.iter().all(|&g| g >= 0 && (g as usize) < n) {
                total += element.eval(family, indices, stencil.map(|g| g as usize));
            } else {
                total = f64::NAN;
            }
        });
        self.total = total;
    }
}

struct Value<'a> {
    q0: &'a [f64],
    q1: &'a [f64],
}

impl ElementScalar for Value<'_> {
    fn eval<const S: usize, F: Family<S>>(&self, f: &F, indices: &[i64], st: [usize; S]) -> f64 {
        f.value(indices, &gather(self.q0, &st), &gather(self.q1, &st))
    }
}

struct Energy<'a> {
    q0: &'a [f64],
    q1: &'a [f64],
    h: f64,
}

impl ElementScalar for Energy<'_> {
    fn eval<const S: usize, F: Family<S>>(&self, f: &F, indices: &[i64], st: [usize; S]) -> f64 {
        let q = std::array::from_fn(|a| 0.5 * (self.q0[st[a]] + self.q1[st[a]]));
        let v = std::array::from_fn(|a| (self.q1[st[a]] - self.q0[st[a]]) / self.h);
        f.energy(indices, &q, &v)
    }
}

fn scalar<L: ElementLagrangian, G: ElementScalar>(system: &L, element: G) -> f64 {
    let mut visit = Scalar {
        element,
        n: system.dim(),
        total: 0.0,
    };
    system.families(&mut visit);
    visit.total
}

/// `L_d(q0, q1)`, the sum of the element values (NaN when a stencil is out of range or the
/// vectors are shorter than the system).
pub(super) fn value<L: ElementLagrangian>(system: &L, q0: &[f64], q1: &[f64]) -> f64 {
    if q0.len() != system.dim() || q1.len() != system.dim() {
        return f64::NAN;
    }
    scalar(system, Value { q0, q1 })
}

/// `E((q0 + q1)/2, (q1 − q0)/h)`, the sum of the element energies.
pub(super) fn energy<L: ElementLagrangian>(system: &L, q0: &[f64], q1: &[f64], h: f64) -> f64 {
    if q0.len() != system.dim() || q1.len() != system.dim() {
        return f64::NAN;
    }
    scalar(system, Energy { q0, q1, h })
}
