//! Element-wise systems given as text: the compiled kernels of each family of elements
//! ([`ElementCode`]) and the system at its sizes ([`JitElement`]), which implements the
//! runtime's `ElementLagrangian` and `Family` by calling the kernels: `ElementIntegrator` (both
//! sides, compositions, forces, controls, step sensitivities) and, with constraints,
//! `ElementConstrainedIntegrator` run it as they run a compiled-in element-wise system.
//!
//! The attribute emits each family's stencil as integer code in the loop indices and the sizes;
//! here the stencils are evaluated once, when the system is instantiated at its sizes, into a
//! table of the elements' loop indices and coordinate indices, which every assembly walks. The
//! kernels are the same straight-line code for every size.

use std::ops::Range;
use std::sync::Arc;
use std::time::{Duration, Instant};

use dirac_compiler::program::Leaf;
use dirac_compiler::text::{self, ElementSystem, Stencil};

use crate::codegen::{Jit, Kernel};
use crate::error::Error;
use crate::system::{by_name, parameter_values, Module, UNUSED};
use crate::MAX_PARAMETERS;
use dirac_runtime::StepError;

mod family;

/// The most sizes a system may declare.
pub const MAX_SIZES: usize = 8;

/// The nests of element loops whose indices a kernel call passes from the stack; deeper ones
/// from a buffer per thread ([`JitElement::call`]).
const STACK_DEPTH: usize = 8;

thread_local! {
    /// The loop indices of an element of a nest deeper than [`STACK_DEPTH`], as numbers.
    static NUMBERS: std::cell::RefCell<Vec<f64>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// The kernels of one family.
#[derive(Clone, Copy)]
struct FamilyKernels {
    d1_d2: Kernel,
    d1_d2_d12: Kernel,
    partials: Kernel,
    value: Kernel,
    energy: Option<Kernel>,
    legendre: Option<Kernel>,
}

/// An element-wise system given as text, compiled to machine code. Shared ([`Arc`]) by every
/// [`JitElement`] made from it, at any sizes.
pub struct ElementCode {
    system: ElementSystem,
    families: Vec<FamilyKernels>,
    constraints: Vec<Kernel>,
    compile_time: Duration,
    _module: Module,
}

impl std::fmt::Debug for ElementCode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ElementCode")
            .field("name", &self.system.name)
            .field("sizes", &self.system.sizes)
            .field("parameters", &self.system.parameters)
            .field("families", &self.system.families.len())
            .field("compile_time", &self.compile_time)
            .finish_non_exhaustive()
    }
}

/// Compiles an element-wise system given as text (see
/// [`dirac_compiler::text::compile_element`] for what the text is) to machine code.
///
/// ```
/// use dirac_runtime::element::{ElementIntegrator, ElementState};
/// use dirac_runtime::nalgebra::DVector;
/// use dirac_runtime::prelude::*;
///
/// let code = dirac_jit::compile_element(
///     "#[reduced_lagrangian(coordinates(x[n]), translate(x), rule = midpoint)]
///      fn chain(q: Config, v: Velocity, k: f64, n: usize) -> f64 {
///          let mut l = 0.0;
///          for i in 0..n { l += 0.5 * v.x[i] * v.x[i]; }
///          for i in 0..n - 1 { l -= 0.5 * k * (q.x[i + 1] - q.x[i]) * (q.x[i + 1] - q.x[i]); }
///          l
///      }",
/// )?;
/// // Parameters k, h; the size n chosen here, at run time.
/// let chain = code.instantiate(&[1.0, 0.05], &[1000])?;
/// let q = DVector::from_fn(1000, |i, _| 0.01 * (i as f64).sin());
/// let start = ElementState::new(q, DVector::from_element(1000, 0.1));
/// let integ = ElementIntegrator::new(chain, NewtonOptions::default());
/// let traj = integ.run(start.clone()).steps(100).collect()?;
/// // The translation's momentum Σ p, kept to round-off.
/// let mu = |s: &ElementState| s.p.sum();
/// assert!((mu(traj.last()) - mu(&start)).abs() < 1e-10);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn compile_element(source: &str) -> Result<Arc<ElementCode>, Error> {
    let start = Instant::now();
    let system = text::compile_element(source)?;
    ElementCode::from_system(system, start)
}

/// Compiles the element view of a system on vector spaces given as text (see
/// [`dirac_compiler::text::compile_flat_elements`]): its `L_d` as one element reading every
/// coordinate, each group coordinate a translation whose momentum map `μ = p_g` the element
/// integrators keep exact, each holonomic constraint row a constraint family. Instantiated with
/// no sizes (`instantiate(&parameters, &[])`), it runs on `ElementIntegrator` (or, with
/// constraints, `ElementConstrainedIntegrator`) at any number of coordinates from one build —
/// the path of a system whose size the fixed-size instances ([`crate::with_dimensions!`],
/// [`crate::with_constrained_dimensions!`]) do not serve. Its (+) and (−) sides compute the
/// trajectory of the reduced (+) and (−) equations (4.6), (4.8), in the user's coordinates
/// `q = (x, g)`, `p = (w − Bᵀ μ, μ)` (eq. (3.7)), to round-off; the unreduced step is its (+)
/// side.
///
/// ```
/// use dirac_runtime::element::{ElementIntegrator, ElementState};
/// use dirac_runtime::prelude::*;
///
/// let code = dirac_jit::compile_flat_elements(
///     "#[reduced_lagrangian(shape(r), group(theta))]
///      fn kepler(q0: Config, q1: Config, h: f64) -> f64 {
///          let (dr, dth) = (q1.r - q0.r, q1.theta - q0.theta);
///          let r = 0.5 * (q0.r + q1.r);
///          0.5 / h * (dr * dr + r * r * dth * dth) + h / r
///      }",
/// )?;
/// let kepler = code.instantiate(&[0.01], &[])?;
/// let integ = ElementIntegrator::new(kepler, NewtonOptions::default());
/// let traj = integ.run(ElementState::new([1.0, 0.0], [0.0, 1.0])).steps(100).collect()?;
/// assert_eq!(traj.last().p[1], 1.0); // the angular momentum p_theta, exactly
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn compile_flat_elements(source: &str) -> Result<Arc<ElementCode>, Error> {
    let start = Instant::now();
    let system = text::compile_flat_elements(source)?;
    ElementCode::from_system(system, start)
}

/// An element's kernels: the parameters and sizes first, then `q0` (or `q`), `q1` (or `v`) and
/// the loop indices.
fn element_layout(p: usize, z: usize) -> impl Fn(Leaf) -> (usize, usize) {
    move |leaf| match leaf {
        Leaf::Param(i) if i < p + z => (0, i),
        Leaf::Param(i) => (3, i - p - z),
        Leaf::Q0(a) => (1, a),
        Leaf::Q1(a) => (2, a),
        other => unreachable!("an element does not read {other:?}"),
    }
}

/// A constraint row's kernel: `q` second whichever name the program gives it.
fn constraint_layout(p: usize, z: usize) -> impl Fn(Leaf) -> (usize, usize) {
    move |leaf| match leaf {
        Leaf::Param(i) if i < p + z => (0, i),
        Leaf::Param(i) => (3, i - p - z),
        Leaf::Q0(a) | Leaf::Q1(a) => (1, a),
        other => unreachable!("a constraint row does not read {other:?}"),
    }
}

impl ElementCode {
    /// The machine code of a compiled system; `start` is when its compilation began.
    pub(crate) fn from_system(
        system: ElementSystem,
        start: Instant,
    ) -> Result<Arc<ElementCode>, Error> {
        let fail = |reason: String| Error::Element {
            name: system.name.clone(),
            reason,
        };
        let (p, z) = (system.parameters.len(), system.sizes.len());
        if z > MAX_SIZES || p > MAX_PARAMETERS {
            return Err(fail(format!(
                "{p} parameters and {z} sizes: a system given at run time has at most {MAX_PARAMETERS} and {MAX_SIZES}"
            )));
        }
        let mut jit = Jit::new()?;
        let layout = element_layout(p, z);
        let mut defined = Vec::with_capacity(system.families.len());
        for f in &system.families {
            defined.push((
                jit.define(&f.d1_d2, &layout)?,
                jit.define(&f.d1_d2_d12, &layout)?,
                jit.define(&f.partials, &layout)?,
                jit.define(&f.value, &layout)?,
                f.energy
                    .as_ref()
                    .map(|e| jit.define(e, &layout))
                    .transpose()?,
                f.legendre
                    .as_ref()
                    .map(|l| jit.define(l, &layout))
                    .transpose()?,
            ));
        }
        let constraint_layout = constraint_layout(p, z);
        let constraints: Vec<usize> = system
            .constraints
            .iter()
            .flat_map(|c| &c.families)
            .map(|f| jit.define(&f.value_gradient, &constraint_layout))
            .collect::<Result<_, _>>()?;
        let (k, module) = jit.finish()?;
        let families = defined
            .into_iter()
            .map(|(d, dd, pa, v, e, l)| FamilyKernels {
                d1_d2: k[d],
                d1_d2_d12: k[dd],
                partials: k[pa],
                value: k[v],
                energy: e.map(|i| k[i]),
                legendre: l.map(|i| k[i]),
            })
            .collect();
        Ok(Arc::new(ElementCode {
            constraints: constraints.into_iter().map(|i| k[i]).collect(),
            system,
            families,
            compile_time: start.elapsed(),
            _module: Module(Some(module)),
        }))
    }

    /// The compiled system's names, stencils and programs.
    pub fn system(&self) -> &ElementSystem {
        &self.system
    }

    /// How long the text took to become machine code.
    pub fn compile_time(&self) -> Duration {
        self.compile_time
    }

    /// The system at `sizes` (in the order of [`ElementSystem::sizes`]) with `parameters` in
    /// declaration order: what `ElementIntegrator` takes. Every element's stencil is evaluated
    /// here, once; an error for a wrong number of sizes or parameters, a value that is not
    /// finite, or a stencil whose index arithmetic overflows (the runtime checks before the
    /// first step that every stencil stays inside its coordinate).
    pub fn instantiate(
        self: &Arc<Self>,
        parameters: &[f64],
        sizes: &[usize],
    ) -> Result<JitElement, Error> {
        let sys = &self.system;
        let fail = |reason: String| Error::Element {
            name: sys.name.clone(),
            reason,
        };
        let params = parameter_values(&sys.name, &sys.parameters, parameters)?;
        if sizes.len() != sys.sizes.len() {
            return Err(fail(format!(
                "{} sizes for {} ({})",
                sizes.len(),
                sys.sizes.len(),
                sys.sizes.join(", ")
            )));
        }
        let z: Vec<i64> = sizes
            .iter()
            .map(|&n| i64::try_from(n).map_err(|_| fail(format!("the size {n} is too large"))))
            .collect::<Result<_, _>>()?;
        // The offsets of the coordinates in the flat vector.
        let mut offsets = vec![0i64];
        for c in &sys.coordinates {
            let len = c
                .dims
                .iter()
                .try_fold(1i64, |acc, d| acc.checked_mul(d.eval(&z)))
                .ok_or_else(|| fail(format!("the length of `{}` overflows", c.name)))?;
            let last = *offsets.last().expect("starts with 0");
            let end = last
                .checked_add(len.max(0))
                .ok_or_else(|| fail("the number of coordinates overflows".into()))?;
            offsets.push(end);
        }
        let overflow = || fail("a stencil's index arithmetic overflows at these sizes".into());
        // Every family's elements are counted, and the tables' memory reserved, before any
        // element is stored: sizes whose tables cannot be allocated are refused here.
        let stencils: Vec<(&Stencil, Option<&text::IndexExpr>)> = sys
            .families
            .iter()
            .map(|f| (&f.stencil, None))
            .chain(
                sys.constraints
                    .iter()
                    .flat_map(|c| c.families.iter().map(|f| (&f.stencil, Some(&f.row)))),
            )
            .collect();
        let mut counts = Vec::with_capacity(stencils.len());
        for &(stencil, _) in &stencils {
            counts.push(Table::count(stencil, &z).ok_or_else(overflow)?);
        }
        let mut tables = reserve_tables(&stencils, &counts).map_err(|bytes| {
            Error::Step(StepError::OutOfMemory {
                what: format!(
                    "the tables of the elements of `{}` at sizes {sizes:?} ({} elements: loop \
                     indices and stencils)",
                    sys.name,
                    counts.iter().map(|&c| u128::from(c)).sum::<u128>()
                ),
                bytes,
            })
        })?;
        for (table, &(stencil, row)) in tables.iter_mut().zip(&stencils) {
            let mut loops = vec![0i64; stencil.loops.len()];
            table
                .walk(stencil, row, &z, &offsets, sys, &mut loops, 0)
                .ok_or_else(overflow)?;
        }
        let constraints = tables.split_off(sys.families.len());
        let families = tables;
        let (constraints, rows) = match &sys.constraints {
            None => (constraints, 0),
            Some(c) => (
                constraints,
                c.count
                    .eval(&z, &[])
                    .and_then(|m| usize::try_from(m).ok())
                    .unwrap_or(0),
            ),
        };
        // The parameters, then the sizes as numbers: what the kernels read in `a`.
        let mut values = [0.0; MAX_PARAMETERS + MAX_SIZES];
        let np = sys.parameters.len();
        values[..np].copy_from_slice(&params[..np]);
        for (k, &n) in sizes.iter().enumerate() {
            values[np + k] = n as f64;
        }
        Ok(JitElement {
            code: Arc::clone(self),
            values,
            at: Arc::new(AtSizes {
                sizes: sizes.to_vec(),
                offsets,
                families,
                constraints,
                rows,
            }),
        })
    }

    /// [`Self::instantiate`] with the parameters and the sizes by name, in any order; each
    /// once.
    pub fn instantiate_named(
        self: &Arc<Self>,
        parameters: &[(&str, f64)],
        sizes: &[(&str, usize)],
    ) -> Result<JitElement, Error> {
        let sys = &self.system;
        let values = by_name(&sys.name, &sys.parameters, parameters)?;
        let as_f64: Vec<(&str, f64)> = sizes.iter().map(|&(n, v)| (n, v as f64)).collect();
        let sizes: Vec<usize> = by_name(&sys.name, &sys.sizes, &as_f64)?
            .into_iter()
            .map(|v| v as usize)
            .collect();
        self.instantiate(&values, &sizes)
    }
}

/// The elements of one family at given sizes: per element its loop indices (`depth` of them,
/// as integers and as the numbers the kernels read) and the coordinate indices of its slots, and
/// for a constraint family the row it assigns.
struct Table {
    width: usize,
    depth: usize,
    count: usize,
    indices: Vec<i64>,
    numbers: Vec<f64>,
    stencils: Vec<i64>,
    rows: Vec<i64>,
}

impl Table {
    /// The number of elements of `stencil` at sizes `z`, counted without visiting the innermost
    /// loop's iterations (so sizes far beyond memory are counted at once); `None` when the
    /// loop bounds' arithmetic overflows. A count beyond [`MAX_ELEMENTS`] stops counting there:
    /// no table that large can be allocated.
    fn count(stencil: &Stencil, z: &[i64]) -> Option<u64> {
        /// The elements of the loops from `at` inward, the outer loops at `loops`.
        fn level(stencil: &Stencil, z: &[i64], loops: &mut [i64], at: usize) -> Option<u64> {
            let Some((lo, hi)) = stencil.loops.get(at) else {
                return Some(1);
            };
            let (lo, hi) = (lo.eval(z, loops)?, hi.eval(z, loops)?);
            let len = u64::try_from(hi.saturating_sub(lo)).unwrap_or(0);
            let inner = &stencil.loops[at + 1..];
            if len == 0 || inner.is_empty() {
                return Some(len);
            }
            // Inner loops whose bounds do not read this loop's index (a grid) have as many
            // elements in every iteration: counted once.
            if !inner.iter().any(|(a, b)| reads(a, at) || reads(b, at)) {
                loops[at] = lo;
                return Some(len.saturating_mul(level(stencil, z, loops, at + 1)?));
            }
            let mut count = 0u64;
            let mut check = 1u64 << 20;
            for i in lo..hi {
                loops[at] = i;
                count = count.saturating_add(level(stencil, z, loops, at + 1)?);
                // A count that memory cannot hold (8 bytes an element at least) ends the
                // counting: the tables' reservation fails on it all the same.
                if count >= check {
                    let words = usize::try_from(count).unwrap_or(usize::MAX);
                    if count > MAX_ELEMENTS || Vec::<u64>::new().try_reserve_exact(words).is_err() {
                        return Some(u64::MAX);
                    }
                    check = check.saturating_mul(2);
                }
            }
            Some(count)
        }
        let mut loops = vec![0i64; stencil.loops.len()];
        level(stencil, z, &mut loops, 0)
    }

    #[allow(
        clippy::too_many_arguments,
        reason = "the recursion's state, one argument each"
    )]
    fn walk(
        &mut self,
        stencil: &Stencil,
        row: Option<&text::IndexExpr>,
        z: &[i64],
        offsets: &[i64],
        sys: &ElementSystem,
        loops: &mut Vec<i64>,
        level: usize,
    ) -> Option<()> {
        if level == stencil.loops.len() {
            self.count += 1;
            self.indices.extend_from_slice(loops);
            self.numbers.extend(loops.iter().map(|&i| i as f64));
            for (c, ix) in &stencil.slots {
                let base = offsets[*c];
                let at = match (sys.coordinates[*c].dims.as_slice(), ix.as_slice()) {
                    ([], []) => base,
                    ([_], [i]) => base.checked_add(i.eval(z, loops)?)?,
                    ([_, d1], [i, j]) => base
                        .checked_add(i.eval(z, loops)?.checked_mul(d1.eval(z))?)?
                        .checked_add(j.eval(z, loops)?)?,
                    _ => return None,
                };
                self.stencils.push(at);
            }
            if let Some(row) = row {
                self.rows.push(row.eval(z, loops)?);
            }
            return Some(());
        }
        let (lo, hi) = &stencil.loops[level];
        let (lo, hi) = (lo.eval(z, loops)?, hi.eval(z, loops)?);
        for i in lo..hi {
            loops[level] = i;
            self.walk(stencil, row, z, offsets, sys, loops, level + 1)?;
        }
        Some(())
    }

    fn len(&self) -> usize {
        self.count
    }
}

/// Whether `index` reads the index of loop `k`.
fn reads(index: &text::IndexExpr, k: usize) -> bool {
    use text::IndexExpr as I;
    match index {
        I::Lit(_) | I::Size(_) => false,
        I::Loop(j) => *j == k,
        I::Add(a, b) | I::Sub(a, b) | I::Mul(a, b) | I::Rem(a, b) => reads(a, k) || reads(b, k),
    }
}

/// More elements than any table can hold (a table stores at least 8 bytes per element, and no
/// allocation exceeds `isize::MAX` bytes): where [`Table::count`] stops counting.
const MAX_ELEMENTS: u64 = (isize::MAX as u64) / 8;

/// Empty tables for the families `stencils` with `counts` elements, their memory reserved (per
/// element: its loop indices as integers and as numbers, its stencil's coordinate indices, and
/// the row a constraint family assigns, 8 bytes each); `Err` with the bytes they need when
/// that much cannot be allocated. The arithmetic is in `u128`, so no count overflows it.
fn reserve_tables(
    stencils: &[(&Stencil, Option<&text::IndexExpr>)],
    counts: &[u64],
) -> Result<Vec<Table>, u128> {
    let words = |(stencil, row): &(&Stencil, Option<&text::IndexExpr>)| {
        2 * stencil.loops.len() as u128 + stencil.slots.len() as u128 + u128::from(row.is_some())
    };
    let bytes: u128 = stencils
        .iter()
        .zip(counts)
        .map(|(s, &c)| 8 * words(s) * u128::from(c))
        .sum();
    let mut tables = Vec::with_capacity(stencils.len());
    for (&(stencil, row), &count) in stencils.iter().zip(counts) {
        let (width, depth) = (stencil.slots.len(), stencil.loops.len());
        let c = u128::from(count);
        let mut table = Table {
            width,
            depth,
            count: 0,
            indices: Vec::new(),
            numbers: Vec::new(),
            stencils: Vec::new(),
            rows: Vec::new(),
        };
        let reserved = reserve(&mut table.indices, c * depth as u128)
            && reserve(&mut table.numbers, c * depth as u128)
            && reserve(&mut table.stencils, c * width as u128)
            && reserve(&mut table.rows, if row.is_some() { c } else { 0 });
        if !reserved {
            return Err(bytes);
        }
        tables.push(table);
    }
    Ok(tables)
}

/// Reserves room for exactly `n` more items of 8 bytes in `v`; `false` when that much cannot be
/// allocated.
fn reserve<T>(v: &mut Vec<T>, n: u128) -> bool {
    usize::try_from(n)
        .ok()
        .filter(|&n| n <= isize::MAX as usize / 8)
        .is_some_and(|n| v.try_reserve_exact(n).is_ok())
}

/// What a system's sizes fix: the sizes, the coordinates' offsets and the elements' tables.
struct AtSizes {
    sizes: Vec<usize>,
    offsets: Vec<i64>,
    families: Vec<Table>,
    constraints: Vec<Table>,
    rows: usize,
}

/// An element-wise system given as text, at its sizes and with its parameter values: what the
/// integrators take. Cloning it (as a control law or a time-step schedule does before every
/// step) copies the parameter values and shares the code and the tables of elements.
#[derive(Clone)]
pub struct JitElement {
    code: Arc<ElementCode>,
    values: [f64; MAX_PARAMETERS + MAX_SIZES],
    at: Arc<AtSizes>,
}

impl std::fmt::Debug for JitElement {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let sys = &self.code.system;
        f.debug_struct(&sys.name)
            .field("parameters", &&self.values[..sys.parameters.len()])
            .field("sizes", &self.at.sizes)
            .finish()
    }
}

impl JitElement {
    /// The compiled code this system runs.
    pub fn code(&self) -> &Arc<ElementCode> {
        &self.code
    }

    /// Each coordinate's name and its range in the flat configuration vector (a grid row by
    /// row).
    pub fn coordinate_ranges(&self) -> Vec<(&str, Range<usize>)> {
        let o = &self.at.offsets;
        self.code
            .system
            .coordinates
            .iter()
            .enumerate()
            .map(|(c, coord)| (coord.name.as_str(), o[c] as usize..o[c + 1] as usize))
            .collect()
    }

    /// Calls `kernel` on the parameters and sizes, `a`, `b` and the loop indices of element
    /// `indices`, writing its outputs at `out`.
    /// The loop indices are passed as the numbers the kernels read: from a stack buffer for up
    /// to [`STACK_DEPTH`] nested loops, from this thread's buffer (grown once) for deeper nests,
    /// so a call allocates nothing whatever the family's depth.
    fn call(&self, kernel: Kernel, a: *const f64, b: *const f64, indices: &[i64], out: *mut f64) {
        // SAFETY: a kernel reads the parameters and sizes (inline, `MAX_PARAMETERS +
        // MAX_SIZES` of them, at most as many as the system declares: checked on compilation),
        // `S` entries of `a` and `b` (the family's width, which every caller checks), as many
        // loop indices as the family's depth (which every caller checks `indices` has, and
        // `numbers` holds as many as `indices`), and writes exactly as many values as its
        // program has outputs, which is the size of the memory at `out` at every call site.
        let run = |numbers: *const f64| unsafe {
            kernel(self.values.as_ptr(), a, b, numbers, UNUSED, out);
        };
        if indices.len() <= STACK_DEPTH {
            let mut numbers = [0.0; STACK_DEPTH];
            for (n, &i) in numbers.iter_mut().zip(indices) {
                *n = i as f64;
            }
            return run(numbers.as_ptr());
        }
        NUMBERS.with(|cell| {
            let numbers = |v: &mut Vec<f64>| {
                v.clear();
                v.extend(indices.iter().map(|&i| i as f64));
            };
            match cell.try_borrow_mut() {
                Ok(mut v) => {
                    numbers(&mut v);
                    run(v.as_ptr())
                }
                Err(_) => {
                    let mut v = Vec::new();
                    numbers(&mut v);
                    run(v.as_ptr())
                }
            }
        })
    }
}
