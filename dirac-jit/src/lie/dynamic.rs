//! Systems on rotation groups given as text at sizes chosen at run time ([`DynJitLie`]), and
//! what the front ends read of either kind of size ([`LieFront`]).

use std::marker::PhantomData;
use std::sync::Arc;

use dirac_compiler::text::LieSymmetryKind;
use dirac_runtime::lie::{
    CoordinateKind, LieModel, LiePartials, LieStateOf, RotationSymmetry, SymmetricLieModel,
};
use dirac_runtime::linalg::{CscBuffer, DynPatternLu};
use dirac_runtime::nalgebra::allocator::Allocator;
use dirac_runtime::nalgebra::{Const, DVector, DefaultAllocator, Dim, Dyn, OVector};
use dirac_runtime::Form;

use super::{JitLie, LieCode, Reduced, Reduction, Unreduced};
use crate::codegen::Kernel;
use crate::error::Error;
use crate::system::{by_name, parameter_values, UNUSED};
use crate::{Dense, MAX_PARAMETERS};

/// The arguments of a step's kernels: `q_k`, `p_k`, `z` in `a`, `b`, `c`.
fn step_layout_args(q_k: &DVector<f64>, p_k: &DVector<f64>, z: &DVector<f64>) -> [*const f64; 3] {
    [q_k.as_ptr(), p_k.as_ptr(), z.as_ptr()]
}

/// A system on rotation groups given as text, with its parameter values, at the sizes its text
/// declares: what `LieIntegratorOf` and, reduced ([`Reduced`]), `ReducedLieIntegratorOf` take at
/// `Dyn` sizes. Cloning it shares the code.
///
/// Any number of rotations, directions, poses and scalars, with no dimension among the type
/// parameters: it implements the runtime's dimension-generic [`LieModel`] at `Dyn` sizes (and
/// [`SymmetricLieModel`] when reduced by its declared symmetry), so the same integrators run it
/// — `LieIntegratorOf<DynJitLie, Dyn, Dyn>` and `ReducedLieIntegratorOf` — on `DVector`s that
/// a run allocates once, in its workspace: a step allocates nothing. The kernels are the ones
/// [`JitLie`] calls; the step Jacobian is written with the residual into one
/// buffer ([`CscBuffer`]) that the run reuses and factored by [`DynPatternLu`]: on the
/// compiler's sparsity pattern above 16 chart coordinates (the compiled-in system's
/// factorization, so the same steps), by a dense LU with partial pivoting below.
///
/// [`LieFront`] is what the front ends (Python, the command line) read of a system on rotation
/// groups given as text at either kind of size, so that one generic run serves both.
///
/// # Which sizes run where
///
/// The front ends keep the fixed-size instances for the small systems
/// ([`with_lie_dimensions!`](crate::with_lie_dimensions): at most two rotation or direction
/// coordinates, at most 8 chart coordinates) and run every other size here. On the small
/// systems the fixed-size step is the faster one: `jit_bench` (`--rounds 3 --steps 2000`,
/// 2026-11-28, the 2-core machine) measured the heavy top's step given as text at 1.17× the
/// compiled-in step at fixed sizes and 1.38× at run-time sizes, the pendulum on `S² × S²` at
/// 1.43× and 1.64× — beyond the 1.5× guaranteed for those systems (on 3 or 4 chart coordinates
/// the heap vectors and the calls through them weigh against the step's own arithmetic). On a
/// large system the factorization on the compiler's pattern is the compiled-in system's own,
/// and the steps are the same.
pub struct DynJitLie<R = Unreduced> {
    code: Arc<LieCode>,
    values: [f64; MAX_PARAMETERS],
    kind: PhantomData<R>,
}

impl<R> Clone for DynJitLie<R> {
    fn clone(&self) -> Self {
        Self {
            code: Arc::clone(&self.code),
            values: self.values,
            kind: PhantomData,
        }
    }
}

impl<R> std::fmt::Debug for DynJitLie<R> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let sys = &self.code.system;
        f.debug_struct(&sys.name)
            .field("parameters", &&self.values[..sys.parameters.len()])
            .finish()
    }
}

impl LieCode {
    /// The system at the sizes its text declares, with `parameters` in declaration order: what
    /// `LieIntegratorOf` takes at `Dyn` sizes, at any number of coordinates. An error if the
    /// values are not one finite number per parameter.
    pub fn instantiate_dyn(self: &Arc<Self>, parameters: &[f64]) -> Result<DynJitLie, Error> {
        self.instantiate_dyn_as(parameters)
    }

    /// The system reduced by its declared rotation symmetry, at the sizes its text declares:
    /// what `ReducedLieIntegratorOf` takes. The checks of [`Self::instantiate_dyn`], and an
    /// error if the text declares no symmetry.
    pub fn instantiate_dyn_reduced(
        self: &Arc<Self>,
        parameters: &[f64],
    ) -> Result<DynJitLie<Reduced>, Error> {
        self.instantiate_dyn_as(parameters)
    }

    /// The parameter values in declaration order from `parameters` by name, in any order; every
    /// parameter once (what [`Self::instantiate_named`] reads).
    pub fn values_by_name(&self, parameters: &[(&str, f64)]) -> Result<Vec<f64>, Error> {
        by_name(&self.system.name, &self.system.parameters, parameters)
    }

    fn instantiate_dyn_as<R: Reduction>(
        self: &Arc<Self>,
        parameters: &[f64],
    ) -> Result<DynJitLie<R>, Error> {
        if R::FORM == Form::Reduced {
            self.check_reduced()?;
        }
        Ok(DynJitLie {
            code: Arc::clone(self),
            values: parameter_values(&self.system.name, &self.system.parameters, parameters)?,
            kind: PhantomData,
        })
    }
}

impl<R> DynJitLie<R> {
    /// The compiled code this system runs.
    pub fn code(&self) -> &Arc<LieCode> {
        &self.code
    }

    /// Calls `kernel` on the parameters and `args`, writing its outputs into `out`
    /// ([`LieCode::call_into`]: `out`'s length is the kernel's number of outputs at every call
    /// site, checked in debug builds).
    fn call_into(&self, kernel: Kernel, args: [*const f64; 3], out: &mut [f64]) {
        self.code
            .call_into(&self.values, kernel, args, out.as_mut_ptr());
    }

    /// The state at the configuration `q` with the momenta `p`, each coordinate as the text
    /// names it ([`JitLie::state`]).
    pub fn state(&self, q: &[&[f64]], p: &[&[f64]]) -> Result<LieStateOf<Dyn, Dyn>, Error> {
        let sys = &self.code.system;
        let (mut point, mut chart) = (
            DVector::zeros(sys.point_len()),
            DVector::zeros(sys.chart_len()),
        );
        self.code
            .fill_state(q, p, point.as_mut_slice(), chart.as_mut_slice())?;
        Ok(LieStateOf { q: point, p: chart })
    }

    /// Adaptive steps: the state at the point `q` with the physical velocity `v` on the level
    /// set ([`JitLie::unreduced_state`]).
    pub fn unreduced_state(
        &self,
        q: &DVector<f64>,
        v: &[f64],
    ) -> Result<LieStateOf<Dyn, Dyn>, Error> {
        let sys = &self.code.system;
        if q.len() != sys.point_len() {
            return Err(Error::State {
                name: sys.name.clone(),
                reason: format!("a point has {} entries, not {}", sys.point_len(), q.len()),
            });
        }
        let mut p = DVector::zeros(sys.chart_len());
        self.code
            .level_state(&self.values, q.as_slice(), v, p.as_mut_slice())?;
        Ok(LieStateOf { q: q.clone(), p })
    }

    /// Writes the step's residual and Jacobian of the `reduced` step (when the system compiled
    /// one) into `jacobian`'s buffer and the residual into `r`.
    fn residual_jacobian_of(
        &self,
        reduced: bool,
        args: [*const f64; 3],
        r: &mut DVector<f64>,
        jacobian: &mut Option<CscBuffer>,
    ) {
        let kernels = &self.code.kernels;
        let sys = &self.code.system;
        let (kernel, stepper) = match (kernels.reduced, sys.symmetry.as_ref()) {
            (Some(k), Some(symmetry)) if reduced => (
                k[1],
                symmetry
                    .reduced
                    .as_ref()
                    .expect("a reduced kernel comes from a reduced stepper"),
            ),
            _ => (kernels.step[1], &sys.stepper),
        };
        let n = sys.chart_len();
        let values = stepper
            .pattern
            .as_ref()
            .map_or(n * n, |pattern| pattern.row_idx.len());
        let buffer = jacobian.get_or_insert_with(|| CscBuffer::zeroed(n + values, n));
        let out = buffer.as_mut_slice();
        debug_assert_eq!(out.len(), n + values);
        self.call_into(kernel, args, out);
        r.as_mut_slice().copy_from_slice(buffer.leading());
    }

    /// Step kernel `i` at the step's arguments, its `N` outputs into `out`.
    fn step_into(&self, i: usize, reduced: bool, args: [*const f64; 3], out: &mut DVector<f64>) {
        debug_assert_eq!(out.len(), self.code.system.chart_len());
        let kernel = self.code.step_kernel(i, reduced);
        self.call_into(kernel, args, out.as_mut_slice());
    }
}

/// The functions of [`LieModel`] or [`SymmetricLieModel`] that are a step's kernels at the
/// step's arguments `(q_k, p_k, z)`: the residual (kernel 0), the residual with its Jacobian
/// (kernel 1) and the momentum update (kernel 2), of the unreduced or the reduced step.
macro_rules! step_kernels {
    (reduced: $reduced:literal; $jacobian:ident; $($name:ident = $kernel:literal),+) => {
        fn $jacobian(
            &self,
            q_k: &DVector<f64>,
            p_k: &DVector<f64>,
            z: &DVector<f64>,
            r: &mut DVector<f64>,
            jacobian: &mut Option<CscBuffer>,
        ) {
            self.residual_jacobian_of($reduced, step_layout_args(q_k, p_k, z), r, jacobian);
        }

        $(
            fn $name(
                &self,
                q_k: &DVector<f64>,
                p_k: &DVector<f64>,
                z: &DVector<f64>,
                out: &mut DVector<f64>,
            ) {
                self.step_into($kernel, $reduced, step_layout_args(q_k, p_k, z), out);
            }
        )+
    };
}

crate::model::impl_system! {
    impl[R] for DynJitLie<R>; |sys| {
        coordinates: sys.code.system.coordinates.iter().map(|c| c.name.as_str()).collect(),
        time: sys.code.system.adaptive.as_ref().map(|a| a.time),
    }
}

impl<R: Reduction> LieModel<Dyn, Dyn> for DynJitLie<R> {
    type Linear = DynPatternLu;

    fn dims(&self) -> (Dyn, Dyn) {
        let sys = &self.code.system;
        (Dyn(sys.point_len()), Dyn(sys.chart_len()))
    }

    fn coordinate(&self, i: usize) -> Option<(&str, CoordinateKind)> {
        self.code.coordinate(i)
    }

    fn monitor(&self, q: &DVector<f64>) -> Option<f64> {
        self.code.monitor(&self.values, q.as_ptr())
    }

    fn linear_solver(&self) -> DynPatternLu {
        let stepper = &self.code.system.stepper;
        let n = self.code.system.chart_len();
        match &stepper.pattern {
            Some(pattern) => DynPatternLu::new(n, &pattern.col_ptr, &pattern.row_idx)
                .expect("the compiler emits a valid pattern of the stepper's size"),
            None => DynPatternLu::dense(n),
        }
    }

    fn lagrangian(&self, q0: &DVector<f64>, q1: &DVector<f64>) -> f64 {
        self.code.lagrangian(&self.values, q0.as_ptr(), q1.as_ptr())
    }

    fn retract_into(&self, q: &DVector<f64>, z: &DVector<f64>, out: &mut DVector<f64>) {
        debug_assert_eq!(out.len(), self.code.system.point_len());
        self.call_into(
            self.code.kernels.retract,
            [q.as_ptr(), UNUSED, z.as_ptr()],
            out.as_mut_slice(),
        );
    }

    step_kernels!(
        reduced: false;
        residual_jacobian_into;
        residual_into = 0,
        momentum_into = 2
    );

    fn step_partials(
        &self,
        q_k: &DVector<f64>,
        p_k: &DVector<f64>,
        z: &DVector<f64>,
    ) -> Option<LiePartials> {
        self.code
            .step_partials(&self.values, step_layout_args(q_k, p_k, z))
    }
}

impl SymmetricLieModel<Dyn, Dyn> for DynJitLie<Reduced> {
    fn symmetry(&self) -> RotationSymmetry<'_> {
        self.code.symmetry()
    }

    fn symmetry_forced(&self) -> bool {
        self.code.system.symmetry.as_ref().is_some_and(|s| s.forced)
    }

    step_kernels!(
        reduced: true;
        reduced_residual_jacobian_into;
        reduced_residual_into = 0,
        reduced_momentum_into = 2
    );
}

/// What a front end (Python, the command line) reads of a system on rotation groups given as
/// text, at fixed sizes ([`JitLie`] on the dense backend) or at sizes chosen at run time
/// ([`DynJitLie`]): its instances, unreduced and reduced, its states from the coordinates as the
/// text names them, and the coordinates of a state. One generic run serves both.
pub trait LieFront<P: Dim, N: Dim>: LieModel<P, N>
where
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    /// The system reduced by its declared symmetry.
    type Reduced: SymmetricLieModel<P, N>;

    /// The system with `parameters` ([`LieCode::instantiate`], [`LieCode::instantiate_dyn`]).
    fn instantiate(code: &Arc<LieCode>, parameters: &[f64]) -> Result<Self, Error>;

    /// The reduced system with `parameters`.
    fn instantiate_reduced(code: &Arc<LieCode>, parameters: &[f64])
        -> Result<Self::Reduced, Error>;

    /// The compiled code.
    fn lie_code(&self) -> &Arc<LieCode>;

    /// The state at the configuration `q` with the momenta `p` ([`JitLie::state`]).
    fn state_of(&self, q: &[&[f64]], p: &[&[f64]]) -> Result<LieStateOf<P, N>, Error>;

    /// The state at the point `q` with the physical velocity `v` ([`JitLie::unreduced_state`]).
    fn level_state_of(&self, q: &OVector<f64, P>, v: &[f64]) -> Result<LieStateOf<P, N>, Error>;

    /// The configuration of a stored point, coordinate by coordinate.
    fn configuration_of(&self, q: &OVector<f64, P>) -> Vec<Vec<f64>> {
        self.lie_code().configuration(q.as_slice())
    }

    /// The momenta of a state, coordinate by coordinate.
    fn momenta_of(&self, state: &LieStateOf<P, N>) -> Vec<Vec<f64>> {
        self.lie_code()
            .momenta(state.q.as_slice(), state.p.as_slice())
    }
}

impl<const P: usize, const N: usize> LieFront<Const<P>, Const<N>> for JitLie<P, N> {
    type Reduced = JitLie<P, N, Dense, Reduced>;

    fn instantiate(code: &Arc<LieCode>, parameters: &[f64]) -> Result<Self, Error> {
        code.instantiate::<P, N>(parameters)
    }

    fn instantiate_reduced(
        code: &Arc<LieCode>,
        parameters: &[f64],
    ) -> Result<Self::Reduced, Error> {
        code.instantiate_reduced::<P, N>(parameters)
    }

    fn lie_code(&self) -> &Arc<LieCode> {
        self.code()
    }

    fn state_of(
        &self,
        q: &[&[f64]],
        p: &[&[f64]],
    ) -> Result<LieStateOf<Const<P>, Const<N>>, Error> {
        self.state(q, p)
    }

    fn level_state_of(
        &self,
        q: &OVector<f64, Const<P>>,
        v: &[f64],
    ) -> Result<LieStateOf<Const<P>, Const<N>>, Error> {
        self.unreduced_state(q, v)
    }
}

impl LieFront<Dyn, Dyn> for DynJitLie {
    type Reduced = DynJitLie<Reduced>;

    fn instantiate(code: &Arc<LieCode>, parameters: &[f64]) -> Result<Self, Error> {
        code.instantiate_dyn(parameters)
    }

    fn instantiate_reduced(
        code: &Arc<LieCode>,
        parameters: &[f64],
    ) -> Result<Self::Reduced, Error> {
        code.instantiate_dyn_reduced(parameters)
    }

    fn lie_code(&self) -> &Arc<LieCode> {
        self.code()
    }

    fn state_of(&self, q: &[&[f64]], p: &[&[f64]]) -> Result<LieStateOf<Dyn, Dyn>, Error> {
        self.state(q, p)
    }

    fn level_state_of(&self, q: &DVector<f64>, v: &[f64]) -> Result<LieStateOf<Dyn, Dyn>, Error> {
        self.unreduced_state(q, v)
    }
}

impl LieCode {
    /// The declared symmetry as the runtime reads it.
    pub(crate) fn symmetry(&self) -> RotationSymmetry<'_> {
        match self.system.symmetry.as_ref().map(|s| &s.kind) {
            Some(LieSymmetryKind::Rotations { coordinate }) => RotationSymmetry::Rotations {
                coordinate: *coordinate,
            },
            Some(LieSymmetryKind::RigidMotions { coordinate }) => RotationSymmetry::RigidMotions {
                coordinate: *coordinate,
            },
            Some(LieSymmetryKind::Axis { axis, .. }) => RotationSymmetry::Axis {
                axis: *axis,
                coordinates: &self.symmetric,
            },
            None => unreachable!("a reduced system declares a symmetry (checked on instantiation)"),
        }
    }
}
