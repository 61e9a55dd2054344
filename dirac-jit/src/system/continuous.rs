//! `ContinuousLagrangian` for a system given as text: `L(q, v)`, the Legendre map, its Jacobian
//! `∂²L/∂v²` and the energy, each one kernel call — what the energies of a trajectory at its
//! nodes (the inverse Legendre map), the states from positions and velocities and the constrained
//! integrators' energies read. The Legendre map's Jacobian is dense up to 16 coordinates and
//! sparse above, as the attribute emits it; [`LegendreLu`] factors either, chosen by the text.

use dirac_runtime::linalg::{FactorError, LinearSolver};
use dirac_runtime::nalgebra::{SMatrix, SVector};
use dirac_runtime::{
    ContinuousLagrangian, CscBuffer, Lu, PatternLu, StageDerivatives, StageJacobian,
};

use super::backend::{Backend, Dense, Sparse, Variant};
use super::layout::ld_layout;
use super::{Code, JitSystem, Module, UNUSED};
use crate::codegen::{Jit, Kernel};
use crate::error::Error;

/// The machine code of a text's stage derivatives (its [`StagePrograms`]), compiled apart from
/// the rest of the system, on first use: a system never stepped by a Gauss–Legendre integrator
/// does not pay for it.
///
/// [`StagePrograms`]: dirac_compiler::text::StagePrograms
pub(crate) struct StageCode {
    values: Kernel,
    jacobian: Kernel,
    _module: Module,
}

impl Code {
    /// The stage derivatives a Gauss–Legendre step evaluates, compiled to machine code on the
    /// first call: an error for a system that has none (a discrete Lagrangian `L_d(q0, q1)`,
    /// constraints, or more than 16 coordinates) or whose code generation fails.
    pub(crate) fn stage_code(&self) -> Result<&StageCode, Error> {
        self.stages
            .get_or_init(|| {
                let programs = self
                    .system
                    .continuous
                    .as_ref()
                    .and_then(|c| c.stage.as_ref())
                    .ok_or_else(|| {
                        "a Gauss–Legendre step needs a continuous Lagrangian `L(q, v)` (with a \
                         `rule = ..`) on at most 16 coordinates without constraints"
                            .to_owned()
                    })?;
                let compile = || -> Result<StageCode, Error> {
                    let mut jit = Jit::new()?;
                    let values = jit.define(&programs.values, &ld_layout)?;
                    let jacobian = jit.define(&programs.jacobian, &ld_layout)?;
                    let (k, module) = jit.finish()?;
                    Ok(StageCode {
                        values: k[values],
                        jacobian: k[jacobian],
                        _module: Module(Some(module)),
                    })
                };
                compile().map_err(|e| e.to_string())
            })
            .as_ref()
            .map_err(|reason| Error::Request {
                reason: format!("the system `{}`: {reason}", self.system.name),
            })
    }

    /// Whether a Gauss–Legendre step can run this system (it has stage derivatives).
    pub fn has_stages(&self) -> bool {
        self.system
            .continuous
            .as_ref()
            .is_some_and(|c| c.stage.is_some())
    }
}

/// The stage derivatives by the text's machine code (compiled on first use). A system without
/// them (or whose code generation failed) gives NaN, which the Gauss–Legendre step reports as a
/// typed error; the run requests refuse such a system before it runs.
impl<const S: usize, const K: usize, const N: usize, V: Variant<N>> StageDerivatives<N>
    for JitSystem<S, K, N, V>
{
    fn stage(
        &self,
        q: &SVector<f64, N>,
        v: &SVector<f64, N>,
    ) -> (SVector<f64, N>, SVector<f64, N>) {
        let Ok(code) = self.code.stage_code() else {
            let nan = SVector::repeat(f64::NAN);
            return (nan, nan);
        };
        let [f, p] = self.call_pair(code.values, q, v, [SVector::<f64, N>::zeros(); 2]);
        (f, p)
    }

    fn stage_jacobian(&self, q: &SVector<f64, N>, v: &SVector<f64, N>) -> StageJacobian<N> {
        let Ok(code) = self.code.stage_code() else {
            let nan = SVector::repeat(f64::NAN);
            return StageJacobian {
                f: nan,
                p: nan,
                ..StageJacobian::default()
            };
        };
        // `StageJacobian` is `repr(C)`: f, p, ∂f/∂q, ∂f/∂v, ∂p/∂q, ∂p/∂v, the program's order.
        self.call_pair(code.jacobian, q, v, StageJacobian::default())
    }
}

/// The linear algebra of the inverse Legendre map of a system given as text: the dense
/// fixed-size LU or the sparse LU on the pattern of `∂²L/∂v²`, as the text's size chose.
#[allow(
    clippy::large_enum_variant,
    reason = "the dense factors live inline, as the dense backend's do: boxing them would allocate for every inverse Legendre map of the common small system"
)]
pub enum LegendreLu<const N: usize> {
    /// Up to 16 coordinates.
    Dense(Lu<N>),
    /// Above.
    Sparse(PatternLu<N>),
}

/// `∂²L/∂v²` as [`LegendreLu`] factors it.
#[allow(
    clippy::large_enum_variant,
    reason = "the dense Jacobian is returned by value, as the dense backend's is, with no allocation per Newton iteration"
)]
pub enum LegendreMatrix<const N: usize> {
    /// Column by column.
    Dense(SMatrix<f64, N, N>),
    /// The values of the pattern's structural nonzeros.
    Sparse(CscBuffer),
}

impl<const N: usize> LinearSolver for LegendreLu<N> {
    type Vector = SVector<f64, N>;
    type Matrix = LegendreMatrix<N>;

    fn factor(&mut self, j: &LegendreMatrix<N>) -> Result<(), FactorError> {
        match (self, j) {
            (LegendreLu::Dense(lu), LegendreMatrix::Dense(m)) => lu.factor(m),
            (LegendreLu::Sparse(lu), LegendreMatrix::Sparse(m)) => lu.factor(m),
            // The solver and the kernel are chosen by the same compiled pattern.
            _ => Err(FactorError::Singular),
        }
    }

    fn solve(&mut self, b: &SVector<f64, N>) -> SVector<f64, N> {
        match self {
            LegendreLu::Dense(lu) => lu.solve(b),
            LegendreLu::Sparse(lu) => lu.solve(b),
        }
    }

    fn solve_in_place(&mut self, b: &mut SVector<f64, N>) {
        match self {
            LegendreLu::Dense(lu) => lu.solve_in_place(b),
            LegendreLu::Sparse(lu) => lu.solve_in_place(b),
        }
    }

    fn norm1(&self) -> f64 {
        match self {
            LegendreLu::Dense(lu) => lu.norm1(),
            LegendreLu::Sparse(lu) => lu.norm1(),
        }
    }

    fn rcond_lower_bound(&mut self) -> f64 {
        match self {
            LegendreLu::Dense(lu) => lu.rcond_lower_bound(),
            LegendreLu::Sparse(lu) => lu.rcond_lower_bound(),
        }
    }

    fn rcond(&mut self) -> f64 {
        match self {
            LegendreLu::Dense(lu) => lu.rcond(),
            LegendreLu::Sparse(lu) => lu.rcond(),
        }
    }

    fn has_reusable_factors(&self) -> bool {
        match self {
            LegendreLu::Dense(lu) => lu.has_reusable_factors(),
            LegendreLu::Sparse(lu) => lu.has_reusable_factors(),
        }
    }
}

/// A system whose text is a discrete Lagrangian has no `L(q, v)`: its functions here are NaN,
/// which the inverse Legendre map reports as `LegendreError` and the integrators refuse in a
/// start state (`StepError`), never as a number.
impl<const S: usize, const K: usize, const N: usize, V: Variant<N>> ContinuousLagrangian<N>
    for JitSystem<S, K, N, V>
{
    /// Said by the text: `Code::system().continuous`'s `rule`.
    const RULE: &'static str = "the rule the text declares (`rule = ..`)";

    fn continuous_lagrangian(&self, q: &SVector<f64, N>, v: &SVector<f64, N>) -> f64 {
        let Some(kernel) = self.code.kernels.continuous_lagrangian else {
            return f64::NAN;
        };
        let l: SVector<f64, 1> = self.call(
            kernel,
            [q.as_ptr(), v.as_ptr(), UNUSED, UNUSED],
            SVector::zeros(),
        );
        l[0]
    }

    fn legendre(&self, q: &SVector<f64, N>, v: &SVector<f64, N>) -> SVector<f64, N> {
        JitSystem::legendre(self, q, v).unwrap_or_else(|| SVector::repeat(f64::NAN))
    }

    type LegendreLinear = LegendreLu<N>;

    fn legendre_solver(&self) -> LegendreLu<N> {
        match self.code.system.continuous.as_ref() {
            Some(c) if c.legendre_jacobian.pattern.is_some() => {
                LegendreLu::Sparse(<Sparse as Backend<N>>::solver(&c.legendre_jacobian))
            }
            _ => LegendreLu::Dense(Lu::empty()),
        }
    }

    fn legendre_jacobian(
        &self,
        q: &SVector<f64, N>,
        v: &SVector<f64, N>,
    ) -> (SVector<f64, N>, LegendreMatrix<N>) {
        let (Some(kernel), Some(c)) = (
            self.code.kernels.legendre_jacobian,
            self.code.system.continuous.as_ref(),
        ) else {
            let nan = SVector::repeat(f64::NAN);
            return (nan, LegendreMatrix::Dense(SMatrix::repeat(f64::NAN)));
        };
        let args = [q.as_ptr(), v.as_ptr(), UNUSED, UNUSED];
        let stepper = &c.legendre_jacobian;
        if stepper.pattern.is_some() {
            let (p, j) = <Sparse as Backend<N>>::residual_jacobian(stepper, |out| {
                self.call_into(kernel, args, out)
            });
            (p, LegendreMatrix::Sparse(j))
        } else {
            let (p, j) = <Dense as Backend<N>>::residual_jacobian(stepper, |out| {
                self.call_into(kernel, args, out)
            });
            (p, LegendreMatrix::Dense(j))
        }
    }

    fn energy(&self, q: &SVector<f64, N>, v: &SVector<f64, N>) -> f64 {
        JitSystem::energy(self, q, v).unwrap_or(f64::NAN)
    }
}
