//! Systems on rotation groups given as text: the compiled code ([`LieCode`]) and the system at
//! fixed dimensions ([`JitLie`]), which implements the runtime's `LieLagrangian` — and
//! `LieSymmetric` when the text declares a symmetry and the system is instantiated reduced
//! ([`Reduced`]) — by calling the kernels. The Lie group variational integrator (both sides),
//! its compositions, forces, controls and sensitivities, adaptive steps and reduction by
//! rotations then run it as they run a compiled-in system.
//!
//! A configuration is the runtime's stored point (`P` entries: scalars, then each rotation and
//! each direction's frame row by row), the momentum the chart covector (`N` entries);
//! [`JitLie::state`] builds a state from the coordinates as the text names them (rotation
//! matrices, unit vectors, scalars) and their momenta, and [`JitLie::configuration`] and
//! [`JitLie::momenta`] read them back.

use std::marker::PhantomData;
use std::sync::Arc;
use std::time::{Duration, Instant};

use dirac_compiler::program::Leaf;
use dirac_compiler::text::{self, LieSymmetryKind, LieSystem};
use dirac_runtime::lie::{
    CoordinateKind, LieLagrangian, LiePartials, LieSymmetric, RotationSymmetry,
};
use dirac_runtime::linalg::LinearSolver;
use dirac_runtime::nalgebra::SVector;
use dirac_runtime::{Form, LieState};

mod calls;
mod dynamic;

pub use dynamic::{DynJitLie, LieFront};

use crate::codegen::{Jit, Kernel};
use crate::error::Error;
use crate::system::{by_name, ld_layout, parameter_values, Module, UNUSED};
use crate::{Backend, Dense, Sparse, MAX_PARAMETERS};

/// The kernels of a system on rotation groups.
struct Kernels {
    lagrangian: Kernel,
    retract: Kernel,
    step: [Kernel; 3],
    reduced: Option<[Kernel; 3]>,
    partials: Option<Kernel>,
    monitor: Option<Kernel>,
    level: Option<Kernel>,
}

/// A system on rotation groups given as text, compiled to machine code: its names, its kernels,
/// and how long the compilation took. Shared ([`Arc`]) by every [`JitLie`] made from it.
pub struct LieCode {
    system: LieSystem,
    kinds: Vec<CoordinateKind>,
    symmetric: Vec<usize>,
    kernels: Kernels,
    compile_time: Duration,
    _module: Module,
}

impl std::fmt::Debug for LieCode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LieCode")
            .field("name", &self.system.name)
            .field("coordinates", &self.system.coordinates)
            .field("parameters", &self.system.parameters)
            .field("compile_time", &self.compile_time)
            .finish_non_exhaustive()
    }
}

/// Compiles a system on rotation groups given as text (see
/// [`dirac_compiler::text::compile_lie`] for what the text is) to machine code.
///
/// ```
/// use dirac_runtime::prelude::*;
/// use dirac_runtime::nalgebra::{Matrix3, Vector3};
///
/// let code = dirac_jit::compile_lie(
///     "#[reduced_lagrangian(rotation(R), symmetry(R))]
///      fn body(q0: Config, q1: Config, h: f64, j1: f64, j2: f64, j3: f64) -> f64 {
///          let f = q0.R.transpose() * q1.R;
///          let jd = Matrix3::from_diagonal(&Vector3::new(j1, j2, j3));
///          let jd = 0.5 * jd.trace() * Matrix3::identity() - jd;
///          ((Matrix3::identity() - f) * jd).trace() / h
///      }",
/// )?;
/// // P = 9 entries of a point (the matrix), N = 3 of the chart (the body frame).
/// let body = code.instantiate::<9, 3>(&[0.01, 1.0, 2.0, 3.0])?;
/// let start = body.state(&[&Matrix3::identity().transpose().as_slice()[..]], &[&[0.3, 1.0, 0.2]])?;
/// let integ = LieIntegrator::new(body, NewtonOptions::default());
/// let traj = integ.run(start).steps(100).collect()?;
/// let pi0 = integ.spatial_momentum(&traj.states[0]);
/// let pi1 = integ.spatial_momentum(traj.last());
/// assert!((pi1 - pi0).norm() < 1e-12);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn compile_lie(source: &str) -> Result<Arc<LieCode>, Error> {
    let start = Instant::now();
    let system = text::compile_lie(source)?;
    LieCode::from_system(system, start)
}

/// The arguments of a step's kernels: `q_k`, `p_k`, `z` in `a`, `b`, `c`.
fn step_layout(leaf: Leaf) -> (usize, usize) {
    match leaf {
        Leaf::Param(i) => (0, i),
        Leaf::Base(i) => (1, i),
        Leaf::P(j) => (2, j),
        Leaf::Chart(j) => (3, j),
        other => unreachable!("a step on rotation groups does not read {other:?}"),
    }
}

/// The monitor `g(q)`: the point in `a`.
fn monitor_layout(leaf: Leaf) -> (usize, usize) {
    match leaf {
        Leaf::Param(i) => (0, i),
        Leaf::Q0(i) => (1, i),
        other => unreachable!("the monitor reads the point and the parameters, not {other:?}"),
    }
}

impl LieCode {
    /// The machine code of a compiled system; `start` is when its compilation began.
    pub(crate) fn from_system(system: LieSystem, start: Instant) -> Result<Arc<LieCode>, Error> {
        let mut jit = Jit::new()?;
        let stepper = |jit: &mut Jit, st: &text::Stepper| -> Result<[usize; 3], Error> {
            Ok([
                jit.define(&st.residual, &step_layout)?,
                jit.define(&st.residual_jacobian, &step_layout)?,
                jit.define(&st.momentum, &step_layout)?,
            ])
        };
        let lagrangian = jit.define(&system.lagrangian, &ld_layout)?;
        let retract = jit.define(&system.retract, &step_layout)?;
        let step = stepper(&mut jit, &system.stepper)?;
        let reduced = system
            .symmetry
            .as_ref()
            .and_then(|s| s.reduced.as_ref())
            .map(|st| stepper(&mut jit, st))
            .transpose()?;
        let partials = system
            .partials
            .as_ref()
            .map(|p| jit.define(p, &step_layout))
            .transpose()?;
        let adaptive = system
            .adaptive
            .as_ref()
            .map(|a| {
                Ok::<_, Error>((
                    jit.define(&a.monitor, &monitor_layout)?,
                    jit.define(&a.level, &ld_layout)?,
                ))
            })
            .transpose()?;
        let (k, module) = jit.finish()?;
        let kernels = Kernels {
            lagrangian: k[lagrangian],
            retract: k[retract],
            step: step.map(|i| k[i]),
            reduced: reduced.map(|r| r.map(|i| k[i])),
            partials: partials.map(|i| k[i]),
            monitor: adaptive.map(|(m, _)| k[m]),
            level: adaptive.map(|(_, l)| k[l]),
        };
        let kinds = system
            .coordinates
            .iter()
            .map(|c| {
                CoordinateKind::by_name(c.kind.name()).ok_or_else(|| {
                    Error::Codegen(format!(
                        "the coordinate `{}` is declared `{}`, a kind the runtime does not have",
                        c.name,
                        c.kind.name()
                    ))
                })
            })
            .collect::<Result<_, _>>()?;
        let symmetric = match system.symmetry.as_ref().map(|s| &s.kind) {
            Some(LieSymmetryKind::Axis { coordinates, .. }) => coordinates.clone(),
            Some(
                LieSymmetryKind::Rotations { coordinate }
                | LieSymmetryKind::RigidMotions { coordinate },
            ) => vec![*coordinate],
            None => Vec::new(),
        };
        Ok(Arc::new(LieCode {
            system,
            kinds,
            symmetric,
            kernels,
            compile_time: start.elapsed(),
            _module: Module(Some(module)),
        }))
    }

    /// The compiled system's names and programs.
    pub fn system(&self) -> &LieSystem {
        &self.system
    }

    /// The runtime's kind of each coordinate, in the order of [`LieSystem::coordinates`]: what
    /// its point, chart, values and output names are.
    pub fn kinds(&self) -> &[CoordinateKind] {
        &self.kinds
    }

    /// How long the text took to become machine code.
    pub fn compile_time(&self) -> Duration {
        self.compile_time
    }

    /// The system at dimensions `P` (a stored point) and `N` (the chart) with `parameters` in
    /// declaration order, on the dense backend (`N ≤ 16`): what `LieIntegrator` takes. An error
    /// if the dimensions are not the system's or the values are not one finite number per
    /// parameter.
    pub fn instantiate<const P: usize, const N: usize>(
        self: &Arc<Self>,
        parameters: &[f64],
    ) -> Result<JitLie<P, N>, Error> {
        self.instantiate_on(parameters)
    }

    /// [`Self::instantiate`] with the parameters by name, in any order; every parameter once.
    pub fn instantiate_named<const P: usize, const N: usize>(
        self: &Arc<Self>,
        parameters: &[(&str, f64)],
    ) -> Result<JitLie<P, N>, Error> {
        let values = by_name(&self.system.name, &self.system.parameters, parameters)?;
        self.instantiate_on(&values)
    }

    /// [`Self::instantiate`] for a system of more than 16 chart coordinates, on the sparse
    /// backend.
    pub fn instantiate_sparse<const P: usize, const N: usize>(
        self: &Arc<Self>,
        parameters: &[f64],
    ) -> Result<JitLie<P, N, Sparse>, Error> {
        self.instantiate_on(parameters)
    }

    /// The system reduced by its declared rotation symmetry (`symmetry(..)` in the text), on
    /// the dense backend: what `ReducedLieIntegrator` takes. The checks of
    /// [`Self::instantiate`], and an error if the text declares no symmetry.
    pub fn instantiate_reduced<const P: usize, const N: usize>(
        self: &Arc<Self>,
        parameters: &[f64],
    ) -> Result<JitLie<P, N, Dense, Reduced>, Error> {
        self.instantiate_on(parameters)
    }

    /// [`Self::instantiate_reduced`] on the sparse backend.
    pub fn instantiate_reduced_sparse<const P: usize, const N: usize>(
        self: &Arc<Self>,
        parameters: &[f64],
    ) -> Result<JitLie<P, N, Sparse, Reduced>, Error> {
        self.instantiate_on(parameters)
    }

    fn instantiate_on<const P: usize, const N: usize, B: Backend<N>, R: Reduction>(
        self: &Arc<Self>,
        parameters: &[f64],
    ) -> Result<JitLie<P, N, B, R>, Error> {
        let sys = &self.system;
        let (p, n) = (sys.point_len(), sys.chart_len());
        if (p, n) != (P, N) {
            return Err(Error::LieDimensions {
                name: sys.name.clone(),
                p,
                n,
                want_p: P,
                want_n: N,
            });
        }
        if sys.stepper.pattern.is_some() != B::SPARSE {
            return Err(Error::Backend {
                name: sys.name.clone(),
                n,
                dense_max: dirac_runtime::DENSE_MAX,
                constrained: false,
            });
        }
        if R::FORM == Form::Reduced {
            self.check_reduced()?;
        }
        Ok(JitLie {
            code: Arc::clone(self),
            values: parameter_values(&sys.name, &sys.parameters, parameters)?,
            kind: PhantomData,
        })
    }

    /// The checks of a reduced instance: a declared symmetry, and a reduced step's Jacobian of
    /// the unreduced one's structure (one solver serves both steps).
    fn check_reduced(&self) -> Result<(), Error> {
        let sys = &self.system;
        let symmetry = sys.symmetry.as_ref().ok_or_else(|| Error::Symmetry {
            name: sys.name.clone(),
            reason: "the text declares no symmetry (`symmetry(..)` in the attribute)".into(),
        })?;
        let differs = |r: &text::Stepper| r.pattern != sys.stepper.pattern;
        if symmetry.reduced.as_ref().is_some_and(differs) {
            return Err(Error::Symmetry {
                name: sys.name.clone(),
                reason: "its reduced step's Jacobian has another sparsity pattern than the unreduced one".into(),
            });
        }
        Ok(())
    }
}

/// Whether a [`JitLie`] is the reduced system ([`Reduced`]: `LieSymmetric`, for
/// `ReducedLieIntegrator`) or not ([`Unreduced`]): the runtime's [`Form`] as a type. Sealed.
pub trait Reduction: sealed::Sealed + Send + Sync + 'static {
    /// The form of the equations the system is stepped with.
    const FORM: Form;
}

/// A [`JitLie`] stepped on the whole configuration space.
#[derive(Clone, Copy, Debug)]
pub struct Unreduced;

/// A [`JitLie`] reduced by its declared rotation symmetry: `LieSymmetric`.
#[derive(Clone, Copy, Debug)]
pub struct Reduced;

impl Reduction for Unreduced {
    const FORM: Form = Form::Unreduced;
}

impl Reduction for Reduced {
    const FORM: Form = Form::Reduced;
}

mod sealed {
    pub trait Sealed {}
    impl Sealed for super::Unreduced {}
    impl Sealed for super::Reduced {}
}

/// A system on rotation groups given as text, at dimensions `P` (a stored point) and `N` (the
/// chart) and with its parameter values: what the integrators take. Cloning it shares the code.
/// `B` is the backend of its steps ([`Dense`], [`Sparse`]), `R` whether it is reduced by its
/// symmetry ([`Unreduced`], [`Reduced`]).
pub struct JitLie<const P: usize, const N: usize, B = Dense, R = Unreduced> {
    code: Arc<LieCode>,
    values: [f64; MAX_PARAMETERS],
    kind: PhantomData<(B, R)>,
}

impl<const P: usize, const N: usize, B, R> Clone for JitLie<P, N, B, R> {
    fn clone(&self) -> Self {
        Self {
            code: Arc::clone(&self.code),
            values: self.values,
            kind: PhantomData,
        }
    }
}

impl<const P: usize, const N: usize, B, R> std::fmt::Debug for JitLie<P, N, B, R> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let sys = &self.code.system;
        f.debug_struct(&sys.name)
            .field("parameters", &&self.values[..sys.parameters.len()])
            .finish()
    }
}

impl<const P: usize, const N: usize, B, R> JitLie<P, N, B, R> {
    /// The compiled code this system runs.
    pub fn code(&self) -> &Arc<LieCode> {
        &self.code
    }

    /// Calls `kernel` on the parameters and `args`, writing its outputs at `out`
    /// ([`LieCode::call_into`]: the dimensions `P` and `N` are checked equal to the system's on
    /// instantiation).
    fn call_into(&self, kernel: Kernel, args: [*const f64; 3], out: *mut f64) {
        self.code.call_into(&self.values, kernel, args, out);
    }

    /// Calls `kernel`, its `M` outputs as a vector.
    fn call<const M: usize>(&self, kernel: Kernel, args: [*const f64; 3]) -> SVector<f64, M> {
        let mut out = SVector::<f64, M>::zeros();
        self.call_into(kernel, args, out.as_mut_ptr());
        out
    }

    fn step_args(
        q_k: &SVector<f64, P>,
        p_k: &SVector<f64, N>,
        z: &SVector<f64, N>,
    ) -> [*const f64; 3] {
        [q_k.as_ptr(), p_k.as_ptr(), z.as_ptr()]
    }

    /// The state at the configuration `q` with the momenta `p`, each coordinate as the text
    /// names it (its value, [`Group::point_from_value`](dirac_runtime::lie::Group::point_from_value)),
    /// in the order of the text's coordinates: a scalar one number, a rotation its matrix row by
    /// row (9 numbers), a direction the unit vector (3 numbers), a pose its rotation row by row
    /// then its position (12 numbers); a scalar's momentum one number, a rotation's discrete body
    /// momentum `Π` (3: the discrete Legendre momentum a step reads, not `JΩ`), a direction's
    /// momentum as a vector in space (3; its component along the direction is dropped), a pose's
    /// body angular momentum `Π` then its linear momentum `p` in space (6). An error for a wrong
    /// count, a matrix that is not a rotation or a vector that is not a unit vector (to `1e-9`),
    /// or a value that is not finite.
    pub fn state(&self, q: &[&[f64]], p: &[&[f64]]) -> Result<LieState<P, N>, Error> {
        let (mut point, mut chart) = (SVector::<f64, P>::zeros(), SVector::<f64, N>::zeros());
        self.code
            .fill_state(q, p, point.as_mut_slice(), chart.as_mut_slice())?;
        Ok(LieState { q: point, p: chart })
    }

    /// The configuration of a stored point, coordinate by coordinate as [`Self::state`] takes
    /// it (a rotation's matrix row by row, a direction's unit vector, a pose's 12 numbers).
    pub fn configuration(&self, q: &SVector<f64, P>) -> Vec<Vec<f64>> {
        self.code.configuration(q.as_slice())
    }

    /// The momenta of a state, coordinate by coordinate as [`Self::state`] takes them (a
    /// rotation's body momentum, a direction's momentum as a vector in space, tangent to the
    /// sphere, a pose's body angular and spatial linear momenta).
    pub fn momenta(&self, state: &LieState<P, N>) -> Vec<Vec<f64>> {
        self.code.momenta(state.q.as_slice(), state.p.as_slice())
    }

    /// Adaptive steps: the state at the configuration `q` (its time coordinate the physical
    /// time) and the physical velocity `v` (the one spelling of a state from a position and a
    /// velocity, as the runtime's `ContinuousLagrangian::unreduced_state`) (`velocity_len()` of [`text::LieKind`] entries per coordinate:
    /// a rotation's body angular velocity, a direction's velocity in space; the time
    /// coordinate's ignored), on the level set where the time-transformed system's solutions
    /// are the physical ones: the physical momenta `∂L/∂v` and `p_t = −E(q, v)`. An error for a
    /// system stepped in physical time, a velocity of the wrong length, or a monitor that is not
    /// positive and finite at `q`.
    pub fn unreduced_state(&self, q: &SVector<f64, P>, v: &[f64]) -> Result<LieState<P, N>, Error> {
        let mut p = SVector::<f64, N>::zeros();
        self.code
            .level_state(&self.values, q.as_slice(), v, p.as_mut_slice())?;
        Ok(LieState { q: *q, p })
    }
}

impl LieCode {
    /// Writes the stored point and the chart momentum of the configuration `q` with the momenta
    /// `p`, each coordinate as the text names it, into `point` and `chart` (of the system's
    /// sizes): what [`JitLie::state`] and [`DynJitLie::state`] build.
    pub(crate) fn fill_state(
        &self,
        q: &[&[f64]],
        p: &[&[f64]],
        point: &mut [f64],
        chart: &mut [f64],
    ) -> Result<(), Error> {
        let sys = &self.system;
        let fail = |reason: String| Error::State {
            name: sys.name.clone(),
            reason,
        };
        if q.len() != sys.coordinates.len() || p.len() != sys.coordinates.len() {
            return Err(fail(format!(
                "{} configurations and {} momenta for {} coordinates",
                q.len(),
                p.len(),
                sys.coordinates.len()
            )));
        }
        let (mut at, mut ch) = (0, 0);
        for (((c, kind), &qi), &pi) in sys.coordinates.iter().zip(&self.kinds).zip(q).zip(p) {
            let (name, group) = (&c.name, kind.group());
            let (want_q, want_p) = (group.value_len(), group.momentum_value_len());
            if qi.len() != want_q || pi.len() != want_p {
                return Err(fail(format!(
                    "`{name}` takes {want_q} numbers and a momentum of {want_p}, not {} and {}",
                    qi.len(),
                    pi.len()
                )));
            }
            if !qi.iter().chain(pi).all(|v| v.is_finite()) {
                return Err(fail(format!("`{name}` is not finite")));
            }
            let block = &mut point[at..at + group.point_len()];
            group.point_from_value(name, qi, block).map_err(fail)?;
            group.momentum_from_value(
                &point[at..at + group.point_len()],
                pi,
                &mut chart[ch..ch + group.chart_len()],
            );
            at += group.point_len();
            ch += group.chart_len();
        }
        Ok(())
    }

    /// The configuration of a stored point `q`, coordinate by coordinate.
    pub(crate) fn configuration(&self, q: &[f64]) -> Vec<Vec<f64>> {
        let mut at = 0;
        let mut out = Vec::with_capacity(self.kinds.len());
        for kind in &self.kinds {
            let group = kind.group();
            let mut value = Vec::with_capacity(group.value_len());
            group.value(&q[at..at + group.point_len()], &mut value);
            out.push(value);
            at += group.point_len();
        }
        out
    }

    /// The momenta of the state `(q, p)`, coordinate by coordinate.
    pub(crate) fn momenta(&self, q: &[f64], p: &[f64]) -> Vec<Vec<f64>> {
        let (mut at, mut ch) = (0, 0);
        let mut out = Vec::with_capacity(self.kinds.len());
        for kind in &self.kinds {
            let group = kind.group();
            let mut value = Vec::with_capacity(group.momentum_value_len());
            group.momentum_value(
                &q[at..at + group.point_len()],
                &p[ch..ch + group.chart_len()],
                &mut value,
            );
            out.push(value);
            at += group.point_len();
            ch += group.chart_len();
        }
        out
    }

    /// Adaptive steps: writes into `p` the momenta of the state at the point `q` with the
    /// physical velocity `v` on the level set (see [`JitLie::unreduced_state`]), the parameters
    /// `values`.
    pub(crate) fn level_state(
        &self,
        values: &[f64; MAX_PARAMETERS],
        q: &[f64],
        v: &[f64],
        p: &mut [f64],
    ) -> Result<(), Error> {
        let sys = &self.system;
        let fail = |reason: String| Error::State {
            name: sys.name.clone(),
            reason,
        };
        let Some(level) = self.kernels.level else {
            return Err(fail(
                "its steps are in physical time (no `time(..), adapt = ..`)".into(),
            ));
        };
        if v.len() != sys.velocity_len() {
            return Err(fail(format!(
                "a velocity has {} entries, not {}",
                sys.velocity_len(),
                v.len()
            )));
        }
        let mut out = vec![0.0; 1 + p.len()];
        // SAFETY: the level kernel reads the point (`P` entries, `q`'s length, checked by the
        // callers' sizes) and the velocity (checked above), and writes the monitor and `N`
        // momenta, `out`'s length.
        unsafe {
            level(
                values.as_ptr(),
                q.as_ptr(),
                v.as_ptr(),
                UNUSED,
                UNUSED,
                out.as_mut_ptr(),
            );
        }
        if !(out[0] > 0.0 && out[0].is_finite()) {
            return Err(fail(format!(
                "the monitor is {} at this configuration; it must be positive and finite",
                out[0]
            )));
        }
        p.copy_from_slice(&out[1..]);
        Ok(())
    }
}

crate::model::impl_system! {
    impl[const P: usize, const N: usize, B, R] for JitLie<P, N, B, R>; |sys| {
        coordinates: sys.code.system.coordinates.iter().map(|c| c.name.as_str()).collect(),
        time: sys.code.system.adaptive.as_ref().map(|a| a.time),
    }
}

/// A method of [`LieLagrangian`] or [`LieSymmetric`] that is one of the step's kernels at the
/// step's arguments `(q_k, p_k, z)` ([`JitLie::step_kernel`]): the residual (kernel 0) and the
/// momentum update (kernel 2), of the unreduced or the reduced step.
macro_rules! step_kernel {
    ($name:ident = $kernel:literal, reduced: $reduced:literal) => {
        fn $name(
            &self,
            q_k: &SVector<f64, P>,
            p_k: &SVector<f64, N>,
            z: &SVector<f64, N>,
        ) -> SVector<f64, N> {
            self.call(
                self.code.step_kernel($kernel, $reduced),
                Self::step_args(q_k, p_k, z),
            )
        }
    };
}

impl<const P: usize, const N: usize, B: Backend<N>, R: Reduction> LieLagrangian<P, N>
    for JitLie<P, N, B, R>
{
    /// Empty: a system given at run time names its coordinates through `coordinate`, which is
    /// what the integrators and output read; the constant cannot know them.
    const COORDINATES: &'static [(&'static str, CoordinateKind)] = &[];
    type Linear = B::Linear;

    fn coordinate(&self, i: usize) -> Option<(&str, CoordinateKind)> {
        self.code.coordinate(i)
    }

    fn monitor(&self, q: &SVector<f64, P>) -> Option<f64> {
        self.code.monitor(&self.values, q.as_ptr())
    }

    fn linear_solver(&self) -> Self::Linear {
        B::solver(&self.code.system.stepper)
    }

    fn lagrangian(&self, q0: &SVector<f64, P>, q1: &SVector<f64, P>) -> f64 {
        self.code.lagrangian(&self.values, q0.as_ptr(), q1.as_ptr())
    }

    fn retract(&self, q: &SVector<f64, P>, z: &SVector<f64, N>) -> SVector<f64, P> {
        self.call(self.code.kernels.retract, [q.as_ptr(), UNUSED, z.as_ptr()])
    }

    step_kernel!(residual = 0, reduced: false);

    fn residual_jacobian(
        &self,
        q_k: &SVector<f64, P>,
        p_k: &SVector<f64, N>,
        z: &SVector<f64, N>,
    ) -> (SVector<f64, N>, <Self::Linear as LinearSolver>::Matrix) {
        B::residual_jacobian(&self.code.system.stepper, |out| {
            self.call_into(self.code.kernels.step[1], Self::step_args(q_k, p_k, z), out)
        })
    }

    step_kernel!(momentum = 2, reduced: false);

    fn step_partials(
        &self,
        q_k: &SVector<f64, P>,
        p_k: &SVector<f64, N>,
        z: &SVector<f64, N>,
    ) -> Option<LiePartials> {
        self.code
            .step_partials(&self.values, Self::step_args(q_k, p_k, z))
    }
}

impl<const P: usize, const N: usize, B: Backend<N>> LieSymmetric<P, N>
    for JitLie<P, N, B, Reduced>
{
    /// A placeholder: a system given at run time says its symmetry through `symmetry`, which is
    /// what the reduced integrator reads; the constant cannot know it.
    const SYMMETRY: RotationSymmetry<'static> = RotationSymmetry::Axis {
        axis: 2,
        coordinates: &[],
    };
    /// A placeholder, as [`Self::SYMMETRY`]: read through `symmetry_forced`.
    const SYMMETRY_FORCED: bool = false;

    fn symmetry(&self) -> RotationSymmetry<'_> {
        self.code.symmetry()
    }

    fn symmetry_forced(&self) -> bool {
        self.code.system.symmetry.as_ref().is_some_and(|s| s.forced)
    }

    step_kernel!(reduced_residual = 0, reduced: true);

    fn reduced_residual_jacobian(
        &self,
        q_k: &SVector<f64, P>,
        p_k: &SVector<f64, N>,
        z: &SVector<f64, N>,
    ) -> (SVector<f64, N>, <Self::Linear as LinearSolver>::Matrix) {
        let (Some(k), Some(stepper)) = (
            self.code.kernels.reduced,
            self.code
                .system
                .symmetry
                .as_ref()
                .and_then(|s| s.reduced.as_ref()),
        ) else {
            return self.residual_jacobian(q_k, p_k, z);
        };
        B::residual_jacobian(stepper, |out| {
            self.call_into(k[1], Self::step_args(q_k, p_k, z), out)
        })
    }

    step_kernel!(reduced_momentum = 2, reduced: true);
}
