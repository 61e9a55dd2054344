//! The compiled code of a system given as text ([`Code`]) and the system itself at fixed
//! dimensions ([`JitSystem`]), which implements the runtime's traits for systems on vector spaces
//! — `DiscreteLagrangian`, `Reduced` for both sides (eqs. (4.6), (4.8)) and `Unreduced`
//! (Definitions 2.7/2.8) — by calling the kernels: every integrator that runs a compiled-in
//! system runs it, on the backend the attribute would choose: the dense fixed-size LU up to 16
//! coordinates ([`Dense`]), the sparse LU on the Jacobian's structural nonzeros above
//! ([`Sparse`]). A system with constraints is also `Constraints` and `Constrained` for the
//! unreduced and both reduced forms ([`JitConstrained`]), which the constrained integrators
//! take.

use std::marker::PhantomData;
use std::sync::Arc;
use std::time::{Duration, Instant};

use cranelift_jit::JITModule;
use dirac_compiler::program::Program;
use dirac_compiler::text::{self, System};
use dirac_runtime::nalgebra::{SMatrix, SVector};
use dirac_runtime::DiscreteLagrangian;
use dirac_runtime::System as _;

use crate::codegen::{Jit, Kernel, Layout};
use crate::error::Error;

mod adapted;
mod backend;
mod constrained;
mod continuous;
mod layout;
mod steps;

pub use backend::{Backend, Dense, Sparse, Variant, WithConstraints};
use constrained::ConstrainedKernels;
pub use constrained::JitConstrained;
pub use continuous::{LegendreLu, LegendreMatrix};
pub(crate) use layout::ld_layout;
use layout::{monitor_layout, reduced_lagrangian_layout, reduced_layout, unreduced_layout};

/// The most parameters a system given at run time declares: the values travel inline with the
/// system, so a control law that sets them before every step allocates nothing.
pub const MAX_PARAMETERS: usize = 32;

/// The kernels of one stepper.
#[derive(Clone, Copy)]
struct StepperKernels {
    residual: Kernel,
    residual_jacobian: Kernel,
    momentum: Kernel,
    residual_momentum: Kernel,
}

/// The kernels of a stepper from their indices among the defined ones (`jit.define`'s order:
/// residual, with its Jacobian, momentum, residual with momentum).
fn stepper_kernels(k: &[Kernel], [r, rj, m, rm]: [usize; 4]) -> StepperKernels {
    StepperKernels {
        residual: k[r],
        residual_jacobian: k[rj],
        momentum: k[m],
        residual_momentum: k[rm],
    }
}

/// The kernels of the eliminated step (momentum-level elimination).
#[derive(Clone, Copy)]
struct EliminatedKernels {
    residual: Kernel,
    residual_jacobian: Kernel,
    group: Kernel,
    block: Kernel,
    pays: bool,
}

/// The kernels of one side of the reduced equations.
#[derive(Clone, Copy)]
struct SideKernels {
    lagrangian: Kernel,
    stepper: StepperKernels,
    impulse: Option<Kernel>,
    eliminated: Option<EliminatedKernels>,
    partials: Option<Kernel>,
}

struct Kernels {
    lagrangian: Kernel,
    connection: Kernel,
    plus: SideKernels,
    minus: SideKernels,
    unreduced: StepperKernels,
    unreduced_partials: Option<Kernel>,
    hessian: Option<Kernel>,
    legendre: Option<Kernel>,
    energy: Option<Kernel>,
    continuous_lagrangian: Option<Kernel>,
    legendre_jacobian: Option<Kernel>,
    monitor: Option<Kernel>,
    constrained: Option<ConstrainedKernels>,
}

/// The module that owns the kernels' memory, freed with the last [`Code`] that uses it.
pub(crate) struct Module(pub(crate) Option<JITModule>);

// SAFETY: after `finish` the module is never used again except to free its memory on drop,
// which happens once, when the last `Arc<Code>` goes; the kernels themselves are plain functions
// over their arguments.
unsafe impl Send for Module {}
// SAFETY: as above: no method of the module is called through a shared reference.
unsafe impl Sync for Module {}

impl Drop for Module {
    fn drop(&mut self) {
        if let Some(module) = self.0.take() {
            // SAFETY: the kernels are reached only through the `Code` that owns this module, and
            // it is being dropped: no kernel runs or will run.
            unsafe { module.free_memory() };
        }
    }
}

/// A system given as text, compiled to machine code: its names, its kernels, and how long the
/// compilation took. Shared ([`Arc`]) by every [`JitSystem`] made from it.
pub struct Code {
    system: System,
    /// The text it was compiled from, for its element view ([`Code::element_view`]).
    source: String,
    /// The element view, compiled on first use.
    view: std::sync::OnceLock<Result<Arc<crate::ElementCode>, String>>,
    /// The stage derivatives' machine code, compiled on first use ([`Code::stage_code`]).
    stages: std::sync::OnceLock<Result<continuous::StageCode, String>>,
    /// The declared domain, as the runtime reads it.
    domain: Vec<dirac_runtime::domain::Bound>,
    kernels: Kernels,
    compile_time: Duration,
    _module: Module,
}

impl std::fmt::Debug for Code {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Code")
            .field("name", &self.system.name)
            .field("shape", &self.system.shape)
            .field("group", &self.system.group)
            .field("parameters", &self.system.parameters)
            .field("compile_time", &self.compile_time)
            .finish_non_exhaustive()
    }
}

/// Compiles a system given as text (see [`dirac_compiler::text::compile`] for what the text is)
/// to machine code.
pub fn compile(source: &str) -> Result<Arc<Code>, Error> {
    let start = Instant::now();
    Code::from_system(text::compile(source)?, source, start)
}

impl Code {
    /// The machine code of a compiled system; `start` is when its compilation began.
    pub(crate) fn from_system(
        system: System,
        source: &str,
        start: Instant,
    ) -> Result<Arc<Code>, Error> {
        let s = system.shape.len();
        let mut jit = Jit::new()?;
        let stepper = |jit: &mut Jit, st: &text::Stepper, layout: Layout| {
            let programs = [
                &st.residual,
                &st.residual_jacobian,
                &st.momentum,
                &st.residual_momentum,
            ];
            define_each(jit, programs, layout)
        };
        let ld = jit.define(&system.lagrangian, &ld_layout)?;
        let b = jit.define(&system.connection, &ld_layout)?;
        let n = s + system.group.len();
        let reduced = |leaf| reduced_layout(leaf, s, n);
        let side = |jit: &mut Jit, side: &text::Side| -> Result<_, Error> {
            let l = jit.define(&side.lagrangian, &reduced_lagrangian_layout)?;
            let st = stepper(jit, &side.stepper, &reduced)?;
            let impulse = define_optional(jit, side.impulse.as_ref(), &reduced)?;
            let eliminated = side
                .eliminated
                .as_ref()
                .map(|e| {
                    let programs = [&e.residual, &e.residual_jacobian, &e.group, &e.block];
                    Ok::<_, Error>((define_each(jit, programs, &reduced)?, e.pays))
                })
                .transpose()?;
            let partials = define_optional(jit, side.partials.as_ref(), &reduced)?;
            Ok((l, st, impulse, eliminated, partials))
        };
        let plus = side(&mut jit, &system.plus)?;
        let minus = side(&mut jit, &system.minus)?;
        let unreduced = stepper(&mut jit, &system.unreduced, &unreduced_layout)?;
        let unreduced_partials = define_optional(
            &mut jit,
            system.unreduced_partials.as_ref(),
            &unreduced_layout,
        )?;
        let hessian = define_optional(&mut jit, system.hessian.as_ref(), &ld_layout)?;
        let monitor = system
            .adaptive
            .as_ref()
            .map(|a| jit.define(&a.monitor, &|leaf| monitor_layout(leaf, s)))
            .transpose()?;
        let continuous = system
            .continuous
            .as_ref()
            .map(|c| {
                let programs = [
                    &c.legendre,
                    &c.energy,
                    &c.lagrangian,
                    &c.legendre_jacobian.residual_jacobian,
                ];
                define_each(&mut jit, programs, &ld_layout)
            })
            .transpose()?;
        let constrained = system
            .constrained
            .as_ref()
            .map(|c| constrained::define(&mut jit, c, s, n))
            .transpose()?;
        let (k, module) = jit.finish()?;
        let stepper_kernels = |defined| stepper_kernels(&k, defined);
        type Defined = (
            usize,
            [usize; 4],
            Option<usize>,
            Option<([usize; 4], bool)>,
            Option<usize>,
        );
        let side_kernels = |(l, st, imp, el, partials): Defined| SideKernels {
            lagrangian: k[l],
            stepper: stepper_kernels(st),
            impulse: imp.map(|i| k[i]),
            eliminated: el.map(|([r, rj, g, a], pays)| EliminatedKernels {
                residual: k[r],
                residual_jacobian: k[rj],
                group: k[g],
                block: k[a],
                pays,
            }),
            partials: partials.map(|i| k[i]),
        };
        let kernels = Kernels {
            lagrangian: k[ld],
            connection: k[b],
            plus: side_kernels(plus),
            minus: side_kernels(minus),
            unreduced: stepper_kernels(unreduced),
            unreduced_partials: unreduced_partials.map(|i| k[i]),
            hessian: hessian.map(|i| k[i]),
            legendre: continuous.map(|[l, _, _, _]| k[l]),
            energy: continuous.map(|[_, e, _, _]| k[e]),
            continuous_lagrangian: continuous.map(|[_, _, l, _]| k[l]),
            legendre_jacobian: continuous.map(|[_, _, _, j]| k[j]),
            monitor: monitor.map(|m| k[m]),
            constrained: constrained.map(|defined| constrained::kernels(defined, &k)),
        };
        let domain = system
            .domain
            .iter()
            .map(|b| {
                use dirac_runtime::domain::{Bound, Relation};
                let relation = match b.relation {
                    text::DomainRelation::Above => Relation::Above,
                    text::DomainRelation::AtLeast => Relation::AtLeast,
                    text::DomainRelation::Below => Relation::Below,
                    text::DomainRelation::AtMost => Relation::AtMost,
                };
                Bound::new(b.coordinate, relation, b.value)
            })
            .collect();
        Ok(Arc::new(Code {
            system,
            source: source.to_owned(),
            view: std::sync::OnceLock::new(),
            stages: std::sync::OnceLock::new(),
            domain,
            kernels,
            compile_time: start.elapsed(),
            _module: Module(Some(module)),
        }))
    }
}

/// `jit.define` of each program on one layout: their indices among the defined kernels.
fn define_each<const M: usize>(
    jit: &mut Jit,
    programs: [&Program; M],
    layout: Layout,
) -> Result<[usize; M], Error> {
    let mut defined = [0; M];
    for (index, program) in defined.iter_mut().zip(programs) {
        *index = jit.define(program, layout)?;
    }
    Ok(defined)
}

/// `jit.define` of a program the system may not have.
fn define_optional(
    jit: &mut Jit,
    program: Option<&Program>,
    layout: Layout,
) -> Result<Option<usize>, Error> {
    program.map(|p| jit.define(p, layout)).transpose()
}

impl Code {
    /// The compiled system's names and programs.
    pub fn system(&self) -> &System {
        &self.system
    }

    /// Whether the fixed-size instances serve this system's dimensions: [`crate::with_dimensions!`]
    /// without constraints, [`crate::with_constrained_dimensions!`] with them. A system they do
    /// not serve runs on its [`Self::element_view`] (any number of coordinates and constraints).
    pub fn fixed_size(&self) -> bool {
        let (s, k) = (self.system.shape.len(), self.system.group.len());
        match &self.system.constrained {
            None => (1..=crate::MAX_DISPATCHED).contains(&(s + k)),
            Some(c) => {
                let (m, n, k_max) = crate::MAX_DISPATCHED_CONSTRAINED;
                (1..=m).contains(&c.m) && s + k <= n && k <= k_max && s + k >= 1
            }
        }
    }

    /// The element view of this system ([`crate::compile_flat_elements`] of its text), compiled
    /// on the first call and shared by every later one: what runs the system at any number of
    /// coordinates and constraints on the element integrators, with the trajectory of its
    /// reduced and unreduced integrators (eqs. (4.6), (4.8), Definitions 2.7/2.8) in the
    /// coordinates `q = (x, g)`, `p = (w − Bᵀ μ, μ)` (eq. (3.7)). An error for what the element
    /// integrators do not support (adaptive steps, a domain, nonholonomic constraints).
    pub fn element_view(&self) -> Result<Arc<crate::ElementCode>, Error> {
        self.view
            .get_or_init(|| {
                crate::compile_flat_elements(&self.source).map_err(|e| match e {
                    Error::Text(t) => t
                        .diagnostics
                        .iter()
                        .map(|d| d.message.clone())
                        .collect::<Vec<_>>()
                        .join("; "),
                    other => other.to_string(),
                })
            })
            .clone()
            .map_err(|reason| Error::Element {
                name: self.system.name.clone(),
                reason,
            })
    }

    /// The connection `B` (`K × S`, row by row) at `parameters` (in declaration order): what
    /// maps the reduced momenta to the user's, `p_x = w − Bᵀ μ` (eq. (3.7)). An error for a
    /// wrong number of parameters or a value that is not finite.
    pub fn connection(&self, parameters: &[f64]) -> Result<Vec<f64>, Error> {
        let values = parameter_values(&self.system.name, &self.system.parameters, parameters)?;
        let (s, k) = (self.system.shape.len(), self.system.group.len());
        let mut bt = vec![0.0; s * k];
        // SAFETY: the connection's kernel reads the parameters only (inline, `MAX_PARAMETERS`
        // of them, checked on compilation) and writes its `K × S` outputs, the length of `bt`.
        unsafe {
            (self.kernels.connection)(
                values.as_ptr(),
                UNUSED,
                UNUSED,
                UNUSED,
                UNUSED,
                bt.as_mut_ptr(),
            );
        }
        Ok(bt)
    }

    /// How long the text took to become machine code (parsing, the checks, differentiation and
    /// code generation).
    pub fn compile_time(&self) -> Duration {
        self.compile_time
    }

    /// The system at dimensions `S`, `K`, `N = S + K` with `parameters` in declaration order
    /// ([`System::parameters`]), on the dense backend (`N ≤ 16`); an error if the dimensions are
    /// not the system's or the values are not one finite number per parameter.
    pub fn instantiate<const S: usize, const K: usize, const N: usize>(
        self: &Arc<Self>,
        parameters: &[f64],
    ) -> Result<JitSystem<S, K, N>, Error> {
        self.instantiate_on(parameters)
    }

    /// [`Self::instantiate`] for a system of more than 16 coordinates, on the sparse backend
    /// (the LU on the Jacobian's structural nonzeros, as the attribute emits for it).
    pub fn instantiate_sparse<const S: usize, const K: usize, const N: usize>(
        self: &Arc<Self>,
        parameters: &[f64],
    ) -> Result<JitSystem<S, K, N, Sparse>, Error> {
        self.instantiate_on(parameters)
    }

    /// [`Self::instantiate`] with the parameters by name, in any order; every parameter once.
    pub fn instantiate_named<const S: usize, const K: usize, const N: usize>(
        self: &Arc<Self>,
        parameters: &[(&str, f64)],
    ) -> Result<JitSystem<S, K, N>, Error> {
        self.instantiate_on(&self.by_name(parameters)?)
    }

    /// [`Self::instantiate_sparse`] with the parameters by name, in any order.
    pub fn instantiate_sparse_named<const S: usize, const K: usize, const N: usize>(
        self: &Arc<Self>,
        parameters: &[(&str, f64)],
    ) -> Result<JitSystem<S, K, N, Sparse>, Error> {
        self.instantiate_on(&self.by_name(parameters)?)
    }

    /// The system with `M` constraints at dimensions `S`, `K`, `N = S + K`, `Z = N + M`, on the
    /// dense backend (`Z ≤ 16` unknowns in each solve): what the constrained integrators take
    /// (`ConstrainedIntegrator`, `ReducedConstrainedIntegrator`). The checks of
    /// [`Self::instantiate`], and an error if the text declares no constraints or another number
    /// of them.
    pub fn instantiate_constrained<
        const S: usize,
        const K: usize,
        const N: usize,
        const M: usize,
        const Z: usize,
    >(
        self: &Arc<Self>,
        parameters: &[f64],
    ) -> Result<JitConstrained<S, K, N, M, Z>, Error> {
        self.instantiate_on(parameters)
    }

    /// [`Self::instantiate_constrained`] for more than 16 unknowns in each solve, on the sparse
    /// backend.
    pub fn instantiate_constrained_sparse<
        const S: usize,
        const K: usize,
        const N: usize,
        const M: usize,
        const Z: usize,
    >(
        self: &Arc<Self>,
        parameters: &[f64],
    ) -> Result<JitConstrained<S, K, N, M, Z, Sparse>, Error> {
        self.instantiate_on(parameters)
    }

    /// The system of kind `V` (a backend, or constraints on one), after the checks
    /// [`Self::instantiate`] names and those of `V` against the system.
    fn instantiate_on<const S: usize, const K: usize, const N: usize, V: Variant<N>>(
        self: &Arc<Self>,
        parameters: &[f64],
    ) -> Result<JitSystem<S, K, N, V>, Error> {
        let sys = &self.system;
        let (s, k) = (sys.shape.len(), sys.group.len());
        if (s, k, s + k) != (S, K, N) {
            return Err(Error::Dimensions {
                name: sys.name.clone(),
                s,
                k,
                n: s + k,
                want_s: S,
                want_k: K,
                want_n: N,
            });
        }
        V::check(sys)?;
        Ok(JitSystem {
            code: Arc::clone(self),
            values: parameter_values(&sys.name, &sys.parameters, parameters)?,
            backend: PhantomData,
        })
    }

    /// The parameter values in declaration order from `(name, value)` pairs.
    fn by_name(&self, parameters: &[(&str, f64)]) -> Result<Vec<f64>, Error> {
        by_name(&self.system.name, &self.system.parameters, parameters)
    }
}

/// The inline parameter values of a system `name` declaring `declared`: an error unless
/// `parameters` holds one finite number for each, at most [`MAX_PARAMETERS`].
pub(crate) fn parameter_values(
    name: &str,
    declared: &[String],
    parameters: &[f64],
) -> Result<[f64; MAX_PARAMETERS], Error> {
    let fail = |reason: String| Error::Parameters {
        name: name.to_owned(),
        reason,
        declared: declared.join(", "),
    };
    if parameters.len() != declared.len() {
        return Err(fail(format!(
            "{} values for {} parameters",
            parameters.len(),
            declared.len()
        )));
    }
    if parameters.len() > MAX_PARAMETERS {
        return Err(fail(format!(
            "a system given at run time has at most {MAX_PARAMETERS} parameters"
        )));
    }
    if let Some(i) = parameters.iter().position(|p| !p.is_finite()) {
        return Err(fail(format!(
            "`{}` = {} is not finite",
            declared[i], parameters[i]
        )));
    }
    let mut values = [0.0; MAX_PARAMETERS];
    values[..parameters.len()].copy_from_slice(parameters);
    Ok(values)
}

/// The parameter values of a system `name` declaring `declared`, in declaration order, from
/// `(name, value)` pairs: every parameter once, no other name.
pub(crate) fn by_name(
    name: &str,
    declared: &[String],
    parameters: &[(&str, f64)],
) -> Result<Vec<f64>, Error> {
    let fail = |reason: String| Error::Parameters {
        name: name.to_owned(),
        reason,
        declared: declared.join(", "),
    };
    let mut values = vec![f64::NAN; declared.len()];
    let mut given = vec![false; declared.len()];
    for &(name, value) in parameters {
        let Some(i) = declared.iter().position(|p| p == name) else {
            return Err(fail(format!("no parameter `{name}`")));
        };
        if std::mem::replace(&mut given[i], true) {
            return Err(fail(format!("`{name}` given twice")));
        }
        values[i] = value;
    }
    if let Some(i) = given.iter().position(|g| !g) {
        return Err(fail(format!("`{}` not given", declared[i])));
    }
    Ok(values)
}

/// A system given as text, at dimensions `S`, `K`, `N = S + K` and with its parameter values:
/// what the integrators take. Cloning it shares the code. `V` is its kind: the backend of its
/// steps ([`Dense`], [`Sparse`]), or its constraints ([`WithConstraints`], [`JitConstrained`]).
pub struct JitSystem<const S: usize, const K: usize, const N: usize, V = Dense> {
    code: Arc<Code>,
    values: [f64; MAX_PARAMETERS],
    backend: PhantomData<V>,
}

impl<const S: usize, const K: usize, const N: usize, B> Clone for JitSystem<S, K, N, B> {
    fn clone(&self) -> Self {
        Self {
            code: Arc::clone(&self.code),
            values: self.values,
            backend: PhantomData,
        }
    }
}

impl<const S: usize, const K: usize, const N: usize, B> std::fmt::Debug for JitSystem<S, K, N, B> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let sys = &self.code.system;
        f.debug_struct(&sys.name)
            .field("parameters", &&self.values[..sys.parameters.len()])
            .finish()
    }
}

/// A pointer for an argument a kernel does not read.
pub(crate) const UNUSED: *const f64 = std::ptr::NonNull::<f64>::dangling().as_ptr();

/// The residual and the momentum update, as one kernel writes them.
#[repr(C)]
struct ResidualMomentum<const N: usize, const M: usize> {
    r: SVector<f64, N>,
    m: SVector<f64, M>,
}

impl<const S: usize, const K: usize, const N: usize, V> JitSystem<S, K, N, V> {
    /// The compiled code this system runs.
    pub fn code(&self) -> &Arc<Code> {
        &self.code
    }

    /// Calls `kernel` on the parameters and `args`, writing into `out` (a value whose memory is
    /// the kernel's outputs, in order: a vector, a matrix, or a `repr(C)` pair of them).
    fn call<T>(&self, kernel: Kernel, args: [*const f64; 4], mut out: T) -> T {
        self.call_into(kernel, args, (&mut out as *mut T).cast::<f64>());
        out
    }

    /// Calls `kernel` on the parameters and `args`, writing its outputs at `out`.
    fn call_into(&self, kernel: Kernel, args: [*const f64; 4], out: *mut f64) {
        // SAFETY: every kernel reads only the entries its layout names, which the compiler
        // bounds by the system's dimensions (checked equal to `S`, `K`, `N` on instantiation),
        // and writes exactly as many `f64` as its program has outputs, which is the size of the
        // memory at `out` at every call site: the value `call` writes into, or the buffer of
        // `Backend::residual_jacobian`, sized by the backend checked on instantiation.
        unsafe {
            kernel(
                self.values.as_ptr(),
                args[0],
                args[1],
                args[2],
                args[3],
                out,
            );
        }
    }

    /// Calls `kernel` on a pair of configuration-sized vectors, `(q0, q1)` or `(q, v)` (the
    /// layout of `L_d` and of a continuous Lagrangian's kernels), writing into `out` as
    /// [`Self::call`].
    fn call_pair<T>(&self, kernel: Kernel, a: &SVector<f64, N>, b: &SVector<f64, N>, out: T) -> T {
        self.call(kernel, [a.as_ptr(), b.as_ptr(), UNUSED, UNUSED], out)
    }

    /// The Legendre map `p = ∂L/∂v (q, v)` of a continuous Lagrangian; `None` for a discrete
    /// one.
    pub fn legendre(&self, q: &SVector<f64, N>, v: &SVector<f64, N>) -> Option<SVector<f64, N>> {
        let kernel = self.code.kernels.legendre?;
        Some(self.call_pair(kernel, q, v, SVector::zeros()))
    }

    /// The energy `⟨∂L/∂v, v⟩ − L` of a continuous Lagrangian at `(q, v)`; `None` for a
    /// discrete one.
    pub fn energy(&self, q: &SVector<f64, N>, v: &SVector<f64, N>) -> Option<f64> {
        let kernel = self.code.kernels.energy?;
        let e: SVector<f64, 1> = self.call_pair(kernel, q, v, SVector::zeros());
        Some(e[0])
    }

    fn side_code(&self, plus: bool) -> &text::Side {
        if plus {
            &self.code.system.plus
        } else {
            &self.code.system.minus
        }
    }

    fn side(&self, plus: bool) -> &SideKernels {
        if plus {
            &self.code.kernels.plus
        } else {
            &self.code.kernels.minus
        }
    }

    fn reduced_lagrangian_of(
        &self,
        plus: bool,
        x0: &SVector<f64, S>,
        x1: &SVector<f64, S>,
        u: &SVector<f64, K>,
    ) -> f64 {
        let l: SVector<f64, 1> = self.call(
            self.side(plus).lagrangian,
            [x0.as_ptr(), x1.as_ptr(), u.as_ptr(), UNUSED],
            SVector::zeros(),
        );
        l[0]
    }

    /// The arguments of a reduced step's kernel: the step's data `(x_k, w_k, μ_k)` and its
    /// unknowns, `z = (x_{k+1}, u)` (or `x_{k+1}` alone for the eliminated step).
    fn reduced_args<const Z: usize>(
        x_k: &SVector<f64, S>,
        w_k: &SVector<f64, S>,
        mu_k: &SVector<f64, K>,
        z: &SVector<f64, Z>,
    ) -> [*const f64; 4] {
        [x_k.as_ptr(), w_k.as_ptr(), mu_k.as_ptr(), z.as_ptr()]
    }
}

impl<const S: usize, const K: usize, const N: usize, V: Variant<N>> JitSystem<S, K, N, V> {
    /// What the adaptive guesses read at `q`: the index of the time coordinate in `q`, the
    /// monitor `g(x)` at the shape of `q`, and the Legendre map's kernel; `None` for a system
    /// stepped in physical time.
    fn adaptive_at(&self, q: &SVector<f64, N>) -> Option<(usize, f64, Kernel)> {
        let time = S + self.time_index()?;
        let g = self.monitor(&q.fixed_rows::<S>(0).into_owned())?;
        Some((time, g, self.code.kernels.legendre?))
    }
}

impl<const S: usize, const K: usize, const N: usize, V: Variant<N>> DiscreteLagrangian<S, K, N>
    for JitSystem<S, K, N, V>
{
    /// Placeholders: a system given at run time has its names in [`Code::system`] and says
    /// them through `shape_names` and `group_names` (and `System::parameter_names`), which is
    /// what output reads; the constants cannot know them.
    const SHAPE: [&'static str; S] = [""; S];
    /// Placeholders, as [`Self::SHAPE`].
    const GROUP: [&'static str; K] = [""; K];

    fn shape_names(&self) -> Vec<&str> {
        self.code.system.shape.iter().map(String::as_str).collect()
    }

    fn group_names(&self) -> Vec<&str> {
        self.code.system.group.iter().map(String::as_str).collect()
    }

    fn monitor(&self, x: &SVector<f64, S>) -> Option<f64> {
        let kernel = self.code.kernels.monitor?;
        let g: SVector<f64, 1> = self.call(
            kernel,
            [x.as_ptr(), UNUSED, UNUSED, UNUSED],
            SVector::zeros(),
        );
        Some(g[0])
    }

    /// As the attribute's ([`dirac_runtime::adaptive::first_increment`]), on this system's
    /// Legendre map.
    fn adaptive_increment(
        &self,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
        h: f64,
    ) -> Option<SVector<f64, N>> {
        let (time, g, legendre) = self.adaptive_at(q)?;
        dirac_runtime::adaptive::first_increment_of(time, g, q, p, h, |q, v| {
            self.call_pair(legendre, q, v, SVector::zeros())
        })
    }

    /// As the attribute's ([`dirac_runtime::adaptive::level_set_defect`]), on this system's
    /// Legendre map.
    fn level_set_defect(&self, q: &SVector<f64, N>, p: &SVector<f64, N>) -> Option<(f64, f64)> {
        let (time, g, legendre) = self.adaptive_at(q)?;
        dirac_runtime::adaptive::level_set_defect_of(time, g, q, p, |q, v| {
            self.call_pair(legendre, q, v, SVector::zeros())
        })
    }

    fn lagrangian(&self, q0: &SVector<f64, N>, q1: &SVector<f64, N>) -> f64 {
        let l: SVector<f64, 1> =
            self.call_pair(self.code.kernels.lagrangian, q0, q1, SVector::zeros());
        l[0]
    }

    fn connection(&self) -> SMatrix<f64, K, S> {
        // The program lists B row by row: the memory of its transpose.
        let bt: SMatrix<f64, S, K> =
            self.call(self.code.kernels.connection, [UNUSED; 4], SMatrix::zeros());
        bt.transpose()
    }
}

crate::model::impl_system! {
    impl[const S: usize, const K: usize, const N: usize, V] for JitSystem<S, K, N, V>; |sys| {
        coordinates: {
            let text = &sys.code.system;
            text.shape.iter().chain(&text.group).map(String::as_str).collect()
        },
        time: sys.code.system.adaptive.as_ref().map(|a| a.time),
        domain: &sys.code.domain,
    }
}
