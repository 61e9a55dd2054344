//! Systems with constraints given as text: `Constraints` and `Constrained` for the unreduced
//! and both reduced forms of the step ([`JitConstrained`]), each solve a kernel of the
//! compiler's constrained steps (`dirac_compiler::text::Constrained`).

use dirac_compiler::program::Leaf;
use dirac_compiler::text;
use dirac_runtime::constrained::Form;
use dirac_runtime::linalg::LinearSolver;
use dirac_runtime::nalgebra::SVector;
use dirac_runtime::{
    Constrained, Constraints, Minus, Plus, ReducedState, UnreducedForm, UnreducedState,
};

use super::backend::{Backend, Dense, WithConstraints};
use super::{ld_layout, reduced_layout, stepper_kernels, JitSystem, StepperKernels, UNUSED};
use crate::codegen::{Jit, Kernel, Layout};
use crate::error::Error;

/// A system given as text with `M` constraints, at dimensions `S`, `K`, `N = S + K` and
/// `Z = N + M` ([`Code::instantiate_constrained`](super::Code::instantiate_constrained)): what `ConstrainedIntegrator` and
/// `ReducedConstrainedIntegrator` take.
pub type JitConstrained<
    const S: usize,
    const K: usize,
    const N: usize,
    const M: usize,
    const Z: usize,
    B = Dense,
> = JitSystem<S, K, N, WithConstraints<M, Z, B>>;

/// The kernels of the two solves of one form of a constrained step.
#[derive(Clone, Copy)]
pub(super) struct ConstrainedStepsKernels {
    position: StepperKernels,
    impulse: Option<Kernel>,
    projection: StepperKernels,
}

/// The kernels of a system with constraints: `φ`, and the steps of each form (unreduced, (+),
/// (−), in the order of [`JitForm::INDEX`]).
#[derive(Clone, Copy)]
pub(super) struct ConstrainedKernels {
    constraint: Kernel,
    forms: [ConstrainedStepsKernels; 3],
}

/// The indices of a form's kernels among the defined ones: position step, impulse, projection.
type FormDefined = ([usize; 4], Option<usize>, [usize; 4]);

/// The indices of a constrained system's kernels among the defined ones: `φ`, and each form's.
pub(super) type Defined = (usize, [FormDefined; 3]);

/// Defines the kernels of `c`, a system of `s` shape coordinates and `n` in all.
pub(super) fn define(
    jit: &mut Jit,
    c: &text::Constrained,
    s: usize,
    n: usize,
) -> Result<Defined, Error> {
    let unreduced = |leaf| constrained_unreduced_layout(leaf, n);
    let reduced = |leaf| reduced_layout(leaf, s, n);
    let steps = |jit: &mut Jit, steps: &text::ConstrainedSteps, layout: Layout| {
        Ok::<_, Error>((
            constrained_stepper(jit, &steps.position, layout)?,
            steps
                .impulse
                .as_ref()
                .map(|p| jit.define(p, layout))
                .transpose()?,
            constrained_stepper(jit, &steps.projection, layout)?,
        ))
    };
    Ok((
        jit.define(&c.constraint, &ld_layout)?,
        [
            steps(jit, &c.unreduced, &unreduced)?,
            steps(jit, &c.plus, &reduced)?,
            steps(jit, &c.minus, &reduced)?,
        ],
    ))
}

/// The kernels of `defined`, from the finished module's kernels `k`.
pub(super) fn kernels((phi, forms): Defined, k: &[Kernel]) -> ConstrainedKernels {
    ConstrainedKernels {
        constraint: k[phi],
        forms: forms.map(|(position, impulse, projection)| ConstrainedStepsKernels {
            position: stepper_kernels(k, position),
            impulse: impulse.map(|i| k[i]),
            projection: stepper_kernels(k, projection),
        }),
    }
}

/// A constrained stepper's kernels: as an unconstrained one's, without the residual with the
/// momentum update, which the constrained steps do not call (its index repeats the residual's).
fn constrained_stepper(
    jit: &mut Jit,
    stepper: &text::Stepper,
    layout: Layout,
) -> Result<[usize; 4], Error> {
    let residual = jit.define(&stepper.residual, layout)?;
    Ok([
        residual,
        jit.define(&stepper.residual_jacobian, layout)?,
        jit.define(&stepper.momentum, layout)?,
        residual,
    ])
}

/// A constrained unreduced step: the state `(q, p)` in `a`, `b` (the position step's `q_k, p_k`,
/// the projection's `q_{k+1}, p̃`), the unknowns `(q_{k+1}, λ)` or `(v, ν)` in `d`.
fn constrained_unreduced_layout(leaf: Leaf, n: usize) -> (usize, usize) {
    match leaf {
        Leaf::Param(i) => (0, i),
        Leaf::Q0(i) => (1, i),
        Leaf::P(i) => (2, i),
        Leaf::Q1(i) => (4, i),
        Leaf::Lambda(j) => (4, n + j),
        other => unreachable!("a constrained unreduced step does not read {other:?}"),
    }
}

/// How the constrained kernels of a form read its state: the form's index among the compiled
/// steps (unreduced, (+), (−)) and the state's vectors as the kernels' arguments `a`, `b`, `c`
/// (the unknowns are `d`).
trait JitForm<const S: usize, const K: usize, const N: usize>: Form<S, K, N> {
    /// The form's steps among [`text::Constrained`]'s: unreduced, (+), (−).
    const INDEX: usize;
    /// Whether a position step moves `μ` ([`Constrained::CONSTRAINED_GROUP_FORCED`]).
    const GROUP_FORCED: bool;
    /// The state's vectors: `(q, p)`, or `(x, w, μ)`.
    fn args(state: &Self::State) -> [*const f64; 3];
    /// A momentum the position step's update kernel writes: `p̃ ∈ R^N` or `w̃ ∈ R^S`.
    fn momentum() -> Self::Momentum;
}

impl<const S: usize, const K: usize, const N: usize> JitForm<S, K, N> for UnreducedForm {
    const INDEX: usize = 0;
    const GROUP_FORCED: bool = false;

    fn args(state: &UnreducedState<N>) -> [*const f64; 3] {
        [state.q.as_ptr(), state.p.as_ptr(), UNUSED]
    }

    fn momentum() -> SVector<f64, N> {
        SVector::zeros()
    }
}

/// The reduced forms: `(x, w, μ)`.
macro_rules! reduced_form {
    ($side:ty, $index:expr) => {
        impl<const S: usize, const K: usize, const N: usize> JitForm<S, K, N> for $side {
            const INDEX: usize = $index;
            /// Whether the constraint forces or a force move `μ` is known only at run time: it
            /// is always updated by the impulse, which is exactly zero without either.
            const GROUP_FORCED: bool = true;

            fn args(state: &ReducedState<S, K>) -> [*const f64; 3] {
                [state.x.as_ptr(), state.w.as_ptr(), state.mu.as_ptr()]
            }

            fn momentum() -> SVector<f64, S> {
                SVector::zeros()
            }
        }
    };
}

reduced_form!(Plus, 1);
reduced_form!(Minus, 2);

impl<const S: usize, const K: usize, const N: usize, const M: usize, const Z: usize, B>
    JitConstrained<S, K, N, M, Z, B>
{
    /// The constraints' programs and kernels (present: checked on instantiation).
    fn constraints_code(&self) -> (&text::Constrained, &ConstrainedKernels) {
        let programs = self.code.system.constrained.as_ref();
        let kernels = self.code.kernels.constrained.as_ref();
        programs
            .zip(kernels)
            .expect("a constrained system has constraints (checked on instantiation)")
    }

    /// The programs and kernels of form `F`'s steps.
    fn form<F: JitForm<S, K, N>>(&self) -> (&text::ConstrainedSteps, &ConstrainedStepsKernels) {
        let (programs, kernels) = self.constraints_code();
        let steps = [&programs.unreduced, &programs.plus, &programs.minus];
        (steps[F::INDEX], &kernels.forms[F::INDEX])
    }

    /// A kernel of form `F` on `state` and the unknowns `unknowns`.
    fn form_args<F: JitForm<S, K, N>>(
        state: &F::State,
        unknowns: &SVector<f64, Z>,
    ) -> [*const f64; 4] {
        let [a, b, c] = F::args(state);
        [a, b, c, unknowns.as_ptr()]
    }
}

impl<const S: usize, const K: usize, const N: usize, const M: usize, const Z: usize, B>
    Constraints<S, K, N, M> for JitConstrained<S, K, N, M, Z, B>
where
    B: Backend<Z>,
{
    fn holonomic(&self) -> bool {
        self.constraints_code().0.holonomic
    }

    /// `φ(q)`; zero for nonholonomic constraints (whose program has no outputs).
    fn constraint(&self, q: &SVector<f64, N>) -> SVector<f64, M> {
        self.call(
            self.constraints_code().1.constraint,
            [q.as_ptr(), UNUSED, UNUSED, UNUSED],
            SVector::zeros(),
        )
    }
}

impl<F, const S: usize, const K: usize, const N: usize, const M: usize, const Z: usize, B>
    Constrained<F, S, K, N, M, Z> for JitConstrained<S, K, N, M, Z, B>
where
    F: JitForm<S, K, N>,
    B: Backend<Z>,
{
    const CONSTRAINED_GROUP_FORCED: bool = F::GROUP_FORCED;

    fn constrained_impulse(&self, state: &F::State, z: &SVector<f64, Z>) -> SVector<f64, K> {
        match self.form::<F>().1.impulse {
            Some(kernel) => self.call(kernel, Self::form_args::<F>(state, z), SVector::zeros()),
            None => SVector::zeros(),
        }
    }

    type PositionLinear = B::Linear;
    type ProjectionLinear = B::Linear;

    fn position_solver(&self) -> B::Linear {
        B::solver(&self.form::<F>().0.position)
    }

    fn projection_solver(&self) -> B::Linear {
        B::solver(&self.form::<F>().0.projection)
    }

    fn constrained_residual(&self, state: &F::State, z: &SVector<f64, Z>) -> SVector<f64, Z> {
        let kernel = self.form::<F>().1.position.residual;
        self.call(kernel, Self::form_args::<F>(state, z), SVector::zeros())
    }

    fn constrained_residual_jacobian(
        &self,
        state: &F::State,
        z: &SVector<f64, Z>,
    ) -> (SVector<f64, Z>, <B::Linear as LinearSolver>::Matrix) {
        let (programs, kernels) = self.form::<F>();
        B::residual_jacobian(&programs.position, |out| {
            self.call_into(
                kernels.position.residual_jacobian,
                Self::form_args::<F>(state, z),
                out,
            )
        })
    }

    fn constrained_momentum(&self, state: &F::State, z: &SVector<f64, Z>) -> F::Momentum {
        let kernel = self.form::<F>().1.position.momentum;
        self.call(kernel, Self::form_args::<F>(state, z), F::momentum())
    }

    fn projection_residual(&self, shake: &F::State, y: &SVector<f64, Z>) -> SVector<f64, Z> {
        let kernel = self.form::<F>().1.projection.residual;
        self.call(kernel, Self::form_args::<F>(shake, y), SVector::zeros())
    }

    fn projection_residual_jacobian(
        &self,
        shake: &F::State,
        y: &SVector<f64, Z>,
    ) -> (SVector<f64, Z>, <B::Linear as LinearSolver>::Matrix) {
        let (programs, kernels) = self.form::<F>();
        B::residual_jacobian(&programs.projection, |out| {
            self.call_into(
                kernels.projection.residual_jacobian,
                Self::form_args::<F>(shake, y),
                out,
            )
        })
    }

    fn projected_momentum(&self, shake: &F::State, y: &SVector<f64, Z>) -> SVector<f64, N> {
        let kernel = self.form::<F>().1.projection.momentum;
        self.call(kernel, Self::form_args::<F>(shake, y), SVector::zeros())
    }
}
