//! One run behind the run request, for every front end: the system given as text, its
//! parameters, its start(s) and a [`RunRequest`] in; the integrator the request names built
//! once — the family's (on vector spaces, with constraints, on the element view, on rotation
//! groups, element-wise), the equations' form and side, the order (the integrator itself or
//! its composition) — and handed with its starts to what the front end does with a run, a
//! [`Finish`]: collect it into arrays, run it as an ensemble, stream it into a file.
//!
//! The front ends (the Python package, the command line) differ only in their `Finish`: what a
//! run becomes is theirs (NumPy arrays, Parquet through `dirac-io`, which this crate does not
//! depend on), which integrator runs is decided here. A `Finish` is implemented for the
//! integrator types it takes (usually once, generic over any integrator whose states it can
//! write), and a family's function asks for exactly the integrators that family may choose.
//! The sizes of a system on vector spaces or rotation groups are type parameters here; a front
//! end reaches them through [`crate::with_dimensions!`] (and its constrained and Lie kin) with a
//! function of its own generic over the sizes that calls the family's function.
//!
//! ```
//! use dirac_jit::run::{Finish, Job};
//! use dirac_jit::{compile, Compiled, RunRequest};
//! use dirac_runtime::Drive;
//!
//! /// A front end's run: the final time, whatever the integrator.
//! struct LastTime;
//! impl Job for LastTime {
//!     type Output = f64;
//! }
//! impl<I: Drive> Finish<I> for LastTime {
//!     fn finish(self, integ: I, starts: Vec<I::State>, request: &RunRequest) -> f64 {
//!         let start = starts.into_iter().next().expect("one start");
//!         integ.run(start).steps(request.steps).stream().expect("runs").t
//!     }
//! }
//!
//! let kepler = compile(
//!     "#[reduced_lagrangian(shape(r), group(phi))]
//!      fn kepler(q0: Config, q1: Config, h: f64) -> f64 {
//!          let (dr, dphi) = (q1.r - q0.r, q1.phi - q0.phi);
//!          let r = 0.5 * (q0.r + q1.r);
//!          0.5 / h * (dr * dr + r * r * dphi * dphi) + h / r
//!      }",
//! )?;
//! let request =
//!     RunRequest::from_keywords(&Compiled::Flat(kepler.clone()), "minus", "composition", 4, 10, None)?;
//! // The reduced (−) integrator's composition of order 4, from (x, w, μ, g).
//! let start = vec![vec![1.0], vec![0.0], vec![1.0], vec![0.0]];
//! let t = dirac_jit::run::flat::<1, 1, 2, _>(&kepler, &[0.01], &[start], &request, LastTime)?;
//! assert!((t - 0.1).abs() < 1e-12);
//! # Ok::<(), dirac_jit::Error>(())
//! ```

use std::sync::Arc;

use dirac_runtime::element::{
    ElementConstrainedIntegrator, ElementIntegrator, ElementLagrangian, ElementState,
};
use dirac_runtime::lie::{LieIntegratorOf, LieStateOf, ReducedLieIntegratorOf};
use dirac_runtime::nalgebra::allocator::Allocator;
use dirac_runtime::nalgebra::{Const, DefaultAllocator, Dim, OVector, SVector};
use dirac_runtime::{
    Composition, CompositionMethod, ConstrainedIntegrator, Form, GaussIntegrator, Minus, Plus,
    ReducedConstrainedIntegrator, ReducedGaussIntegrator, ReducedIntegrator, ReducedState,
    SelfAdjoint, Stepper, UnreducedIntegrator, UnreducedState, Variant,
};

use crate::{Code, Compiled, Error, JitConstrained, JitElement, JitSystem, LieCode, LieFront};
use crate::{RunRequest, Scheme};

/// What a front end makes of a run: the type of its result, whichever integrator the request
/// chose.
pub trait Job {
    /// What a run ends as (a trajectory's arrays, an ensemble's, what a file written holds).
    type Output;
}

/// What a front end does with the integrator `I` a request chose and its starts: runs it (as
/// the request asks: its steps, end time and schedule, [`crate::span!`]) and makes the result of
/// it.
pub trait Finish<I: Stepper>: Job {
    /// Runs `integ` from `starts` (one for a single run, one per member for an ensemble) as
    /// `request` asks.
    fn finish(self, integ: I, starts: Vec<I::State>, request: &RunRequest) -> Self::Output;
}

/// The symmetric composition of order `order` of an integrator of order 2: the triple jump
/// (order 4) or Kahan–Li's of order 6.
pub fn composition(order: u32) -> CompositionMethod {
    match order {
        4 => CompositionMethod::TRIPLE_JUMP,
        _ => CompositionMethod::KAHAN_LI_6,
    }
}

/// `integ` at the order the request asks: itself (order 2) or its composition.
fn by_order<I, J>(integ: I, starts: Vec<I::State>, request: &RunRequest, job: J) -> J::Output
where
    I: SelfAdjoint,
    Composition<I>: Stepper<State = I::State>,
    J: Finish<I> + Finish<Composition<I>>,
{
    if request.order == 2 {
        Finish::<I>::finish(job, integ, starts, request)
    } else {
        let composed = Composition::new(integ, composition(request.order));
        Finish::<Composition<I>>::finish(job, composed, starts, request)
    }
}

/// A state the system cannot take: `reason`.
fn state(name: &str, reason: String) -> Error {
    Error::State {
        name: name.to_owned(),
        reason,
    }
}

/// The vectors of one start, as many as `lengths` and each of its length (`what` names them):
/// else a typed error.
fn vectors<'a>(
    name: &str,
    start: &'a [Vec<f64>],
    lengths: &[(&str, usize)],
) -> Result<&'a [Vec<f64>], Error> {
    if start.len() != lengths.len() {
        let names: Vec<&str> = lengths.iter().map(|(n, _)| *n).collect();
        return Err(state(
            name,
            format!("{} vectors; the start is {}", start.len(), names.join(", ")),
        ));
    }
    for (v, (what, len)) in start.iter().zip(lengths) {
        if v.len() != *len {
            return Err(state(
                name,
                format!("`{what}` has {} values; the system has {len}", v.len()),
            ));
        }
    }
    Ok(start)
}

/// Unreduced starts `(q, p)` of `N` coordinates from their vectors.
fn unreduced_starts<const N: usize>(
    name: &str,
    starts: &[Vec<Vec<f64>>],
) -> Result<Vec<UnreducedState<N>>, Error> {
    starts
        .iter()
        .map(|v| {
            let v = vectors(name, v, &[("q", N), ("p", N)])?;
            Ok(UnreducedState {
                q: SVector::from_column_slice(&v[0]),
                p: SVector::from_column_slice(&v[1]),
            })
        })
        .collect()
}

/// Reduced starts `(x, w, μ, g)` of `S` shape and `K` group coordinates from their vectors.
fn reduced_starts<const S: usize, const K: usize>(
    name: &str,
    starts: &[Vec<Vec<f64>>],
) -> Result<Vec<ReducedState<S, K>>, Error> {
    starts
        .iter()
        .map(|v| {
            let v = vectors(name, v, &[("x", S), ("w", S), ("mu", K), ("g", K)])?;
            Ok(ReducedState {
                x: SVector::from_column_slice(&v[0]),
                w: SVector::from_column_slice(&v[1]),
                mu: SVector::from_column_slice(&v[2]),
                g: SVector::from_column_slice(&v[3]),
            })
        })
        .collect()
}

/// The integrator of a system on vector spaces at its fixed sizes `S`, `K`, `N = S + K`
/// without constraints, from starts given as vectors — `q, p` for the unreduced equations,
/// `x, w, mu, g` for the reduced ones — the unreduced integrator or the reduced one of the
/// request's side (eqs. (4.6), (4.8)), at its order, handed to `job`.
pub fn flat<const S: usize, const K: usize, const N: usize, J>(
    code: &Arc<Code>,
    params: &[f64],
    starts: &[Vec<Vec<f64>>],
    request: &RunRequest,
    job: J,
) -> Result<J::Output, Error>
where
    J: Finish<UnreducedIntegrator<JitSystem<S, K, N>, S, K, N>>
        + Finish<Composition<UnreducedIntegrator<JitSystem<S, K, N>, S, K, N>>>
        + Finish<ReducedIntegrator<JitSystem<S, K, N>, Plus, S, K, N>>
        + Finish<Composition<ReducedIntegrator<JitSystem<S, K, N>, Plus, S, K, N>>>
        + Finish<ReducedIntegrator<JitSystem<S, K, N>, Minus, S, K, N>>
        + Finish<Composition<ReducedIntegrator<JitSystem<S, K, N>, Minus, S, K, N>>>,
{
    request.check(&Compiled::Flat(Arc::clone(code)))?;
    if request.scheme == Scheme::Gauss {
        return Err(Error::Request {
            reason: "a Gauss–Legendre request runs through `run::gauss`".to_owned(),
        });
    }
    let sys = code.instantiate::<S, K, N>(params)?;
    let (name, o) = (&code.system().name, request.newton);
    Ok(match (request.equations.form, request.equations.side) {
        (Form::Unreduced, _) => {
            let starts = unreduced_starts::<N>(name, starts)?;
            by_order(UnreducedIntegrator::new(sys, o), starts, request, job)
        }
        (Form::Reduced, Variant::Plus) => {
            let starts = reduced_starts::<S, K>(name, starts)?;
            by_order(ReducedIntegrator::plus(sys, o), starts, request, job)
        }
        (Form::Reduced, Variant::Minus) => {
            let starts = reduced_starts::<S, K>(name, starts)?;
            by_order(ReducedIntegrator::minus(sys, o), starts, request, job)
        }
    })
}

/// The Gauss–Legendre integrator of the request's order (`s = order / 2` stages) of a system on
/// vector spaces at its fixed sizes, from starts as [`flat`] reads them: on `(q, p)`, or on
/// `(x, w, μ, g)` for the reduced equations of the request's side; its stage derivatives
/// compiled to machine code here, before the run, so that a failure is this call's error.
pub fn gauss<const S: usize, const K: usize, const N: usize, J>(
    code: &Arc<Code>,
    params: &[f64],
    starts: &[Vec<Vec<f64>>],
    request: &RunRequest,
    job: J,
) -> Result<J::Output, Error>
where
    J: Finish<GaussIntegrator<JitSystem<S, K, N>, S, K, N>>
        + Finish<ReducedGaussIntegrator<JitSystem<S, K, N>, Plus, S, K, N>>
        + Finish<ReducedGaussIntegrator<JitSystem<S, K, N>, Minus, S, K, N>>,
{
    let gauss = RunRequest {
        scheme: Scheme::Gauss,
        ..request.clone()
    };
    gauss.check(&Compiled::Flat(Arc::clone(code)))?;
    code.stage_code()?;
    let sys = code.instantiate::<S, K, N>(params)?;
    let (name, o, s) = (
        &code.system().name,
        request.newton,
        request.order as usize / 2,
    );
    Ok(match (request.equations.form, request.equations.side) {
        (Form::Unreduced, _) => {
            let starts = unreduced_starts::<N>(name, starts)?;
            job.finish(GaussIntegrator::new(sys, s, o)?, starts, request)
        }
        (Form::Reduced, Variant::Plus) => {
            let starts = reduced_starts::<S, K>(name, starts)?;
            job.finish(ReducedGaussIntegrator::plus(sys, s, o)?, starts, request)
        }
        (Form::Reduced, Variant::Minus) => {
            let starts = reduced_starts::<S, K>(name, starts)?;
            job.finish(ReducedGaussIntegrator::minus(sys, s, o)?, starts, request)
        }
    })
}

/// The constrained integrator of a system on vector spaces with `M` constraints at its fixed
/// sizes (`Z = N + M` unknowns in each solve), from starts as [`flat`] reads them: unreduced
/// on `(q, p)` or reduced on the request's side on `(x, w, μ, g)`; order 2.
pub fn constrained<
    const S: usize,
    const K: usize,
    const N: usize,
    const M: usize,
    const Z: usize,
    J,
>(
    code: &Arc<Code>,
    params: &[f64],
    starts: &[Vec<Vec<f64>>],
    request: &RunRequest,
    job: J,
) -> Result<J::Output, Error>
where
    J: Finish<ConstrainedIntegrator<JitConstrained<S, K, N, M, Z>, S, K, N, M, Z>>
        + Finish<ReducedConstrainedIntegrator<JitConstrained<S, K, N, M, Z>, Plus, S, K, N, M, Z>>
        + Finish<ReducedConstrainedIntegrator<JitConstrained<S, K, N, M, Z>, Minus, S, K, N, M, Z>>,
{
    request.check(&Compiled::Flat(Arc::clone(code)))?;
    let sys = code.instantiate_constrained::<S, K, N, M, Z>(params)?;
    let (name, o) = (&code.system().name, request.newton);
    Ok(match (request.equations.form, request.equations.side) {
        (Form::Unreduced, _) => {
            let starts = unreduced_starts::<N>(name, starts)?;
            job.finish(ConstrainedIntegrator::new(sys, o), starts, request)
        }
        (Form::Reduced, Variant::Plus) => {
            let starts = reduced_starts::<S, K>(name, starts)?;
            job.finish(ReducedConstrainedIntegrator::plus(sys, o), starts, request)
        }
        (Form::Reduced, Variant::Minus) => {
            let starts = reduced_starts::<S, K>(name, starts)?;
            job.finish(ReducedConstrainedIntegrator::minus(sys, o), starts, request)
        }
    })
}

/// A system on vector spaces seen as one element ([`Code::element_view`]) and its connection
/// `B` at some parameters: the change between its states `(x, w, μ, g)` or `(q, p)` and the
/// element view's `(q, p)`, `q = (x, g)`, `p = (w − Bᵀ μ, μ)` (eq. (3.7)), both ways.
pub struct Connection {
    /// `B`, `K × S`, row by row.
    b: Vec<f64>,
    s: usize,
    k: usize,
}

impl Connection {
    /// The connection of `code` at `params`.
    pub fn new(code: &Code, params: &[f64]) -> Result<Connection, Error> {
        let text = code.system();
        Ok(Connection {
            b: code.connection(params)?,
            s: text.shape.len(),
            k: text.group.len(),
        })
    }

    /// `(Bᵀ μ)_i`.
    fn bt_mu(&self, mu: &[f64], i: usize) -> f64 {
        (0..self.k).map(|j| self.b[j * self.s + i] * mu[j]).sum()
    }

    /// The element view's state of a start given as vectors of the form `form`: `q, p` as
    /// given, or `x, w, μ, g` by eq. (3.7).
    pub fn element_state(
        &self,
        name: &str,
        form: Form,
        start: &[Vec<f64>],
    ) -> Result<ElementState, Error> {
        let (s, k) = (self.s, self.k);
        Ok(match form {
            Form::Unreduced => {
                let v = vectors(name, start, &[("q", s + k), ("p", s + k)])?;
                ElementState::new(v[0].clone(), v[1].clone())
            }
            Form::Reduced => {
                let v = vectors(name, start, &[("x", s), ("w", s), ("mu", k), ("g", k)])?;
                let (x, w, mu, g) = (&v[0], &v[1], &v[2], &v[3]);
                let q: Vec<f64> = x.iter().chain(g).copied().collect();
                let p: Vec<f64> = (0..s)
                    .map(|i| w[i] - self.bt_mu(mu, i))
                    .chain(mu.iter().copied())
                    .collect();
                ElementState::new(q, p)
            }
        })
    }

    /// The reduced state `(x, w, μ, g)` of the element view's `(q, p)`, eq. (3.7) inverted:
    /// `x`, `g` the parts of `q`, `μ` the group part of `p`, `w = p_x + Bᵀ μ`.
    pub fn reduced(&self, q: &[f64], p: &[f64]) -> [Vec<f64>; 4] {
        let s = self.s;
        let w = (0..s).map(|i| p[i] + self.bt_mu(&p[s..], i)).collect();
        [q[..s].to_vec(), w, p[s..].to_vec(), q[s..].to_vec()]
    }
}

/// What a [`Finish`] of the element integrators takes: the element-wise integrator (either
/// side), its compositions, and the element constrained integrator — every integrator [`view`]
/// and [`element`] may choose.
pub trait FinishElements:
    Finish<ElementIntegrator<JitElement>>
    + Finish<Composition<ElementIntegrator<JitElement>>>
    + Finish<ElementConstrainedIntegrator<JitElement>>
{
}

impl<J> FinishElements for J where
    J: Finish<ElementIntegrator<JitElement>>
        + Finish<Composition<ElementIntegrator<JitElement>>>
        + Finish<ElementConstrainedIntegrator<JitElement>>
{
}

/// A system on vector spaces at any size on its element view ([`Code::element_view`]: the
/// element integrators, sized at run time), from starts as [`flat`] reads them (eq. (3.7)):
/// the reduced (+)/(−) equations (4.6), (4.8) are the element (+)/(−) sides in the user's
/// coordinates, "unreduced" the (+) side; with constraints, the element constrained
/// integrator.
pub fn view<J>(
    code: &Arc<Code>,
    params: &[f64],
    starts: &[Vec<Vec<f64>>],
    request: &RunRequest,
    job: J,
) -> Result<J::Output, Error>
where
    J: FinishElements,
{
    request.check(&Compiled::Flat(Arc::clone(code)))?;
    let sys = code.element_view()?.instantiate(params, &[])?;
    let connection = Connection::new(code, params)?;
    let name = &code.system().name;
    let starts = starts
        .iter()
        .map(|s| connection.element_state(name, request.equations.form, s))
        .collect::<Result<Vec<_>, _>>()?;
    run_elements(sys, starts, request, job)
}

/// An element-wise system at its sizes (`sys`, [`crate::ElementCode::instantiate`]) from its states:
/// the element-wise integrator of the request's side at its order, or, for a system with
/// constraints, the element constrained integrator (order 2). An element-wise system declares
/// no reduction: the reduced equations are refused.
pub fn element<J>(
    sys: JitElement,
    starts: Vec<ElementState>,
    request: &RunRequest,
    job: J,
) -> Result<J::Output, Error>
where
    J: FinishElements,
{
    request.check(&Compiled::Element(Arc::clone(sys.code())))?;
    run_elements(sys, starts, request, job)
}

/// [`element`] and [`view`] once their request is checked and their starts are states.
fn run_elements<J>(
    sys: JitElement,
    starts: Vec<ElementState>,
    request: &RunRequest,
    job: J,
) -> Result<J::Output, Error>
where
    J: FinishElements,
{
    if let Some(i) = starts
        .iter()
        .position(|s| s.q.len() != sys.dim() || s.p.len() != sys.dim())
    {
        return Err(state(
            &sys.code().system().name,
            format!(
                "start {i} has {} and {} values; the system has {} at these sizes",
                starts[i].q.len(),
                starts[i].p.len(),
                sys.dim()
            ),
        ));
    }
    let (plus, o) = (request.equations.side == Variant::Plus, request.newton);
    Ok(match (sys.constrained(), plus) {
        (true, true) => job.finish(ElementConstrainedIntegrator::new(sys, o), starts, request),
        (true, false) => job.finish(ElementConstrainedIntegrator::minus(sys, o), starts, request),
        (false, true) => by_order(ElementIntegrator::new(sys, o), starts, request, job),
        (false, false) => by_order(ElementIntegrator::minus(sys, o), starts, request, job),
    })
}

/// The start of a system on rotation groups as a front end reads it: per coordinate (in the
/// text's order) its configuration (a rotation's 9 entries row by row, a direction's 3, a
/// pose's 12, a scalar) and its momentum or, with adaptive steps, the velocities of all
/// coordinates in order, from which the start on the level set is found.
#[derive(Clone, Debug, PartialEq)]
pub struct LieStart {
    /// Each coordinate's configuration.
    pub q: Vec<Vec<f64>>,
    /// Each coordinate's momentum (a rotation's body momentum, a direction's in space).
    pub p: Option<Vec<Vec<f64>>>,
    /// The velocities, every coordinate's in order (adaptive steps).
    pub v: Option<Vec<f64>>,
}

impl LieStart {
    /// The state of `sys` this start gives: from the momenta, or on the level set at the
    /// velocities.
    pub fn state<Sys, P: Dim, N: Dim>(&self, sys: &Sys) -> Result<LieStateOf<P, N>, Error>
    where
        Sys: LieFront<P, N>,
        DefaultAllocator: Allocator<P> + Allocator<N>,
    {
        let q: Vec<&[f64]> = self.q.iter().map(Vec::as_slice).collect();
        match (&self.p, &self.v) {
            (Some(p), None) => {
                let p: Vec<&[f64]> = p.iter().map(Vec::as_slice).collect();
                sys.state_of(&q, &p)
            }
            (None, Some(v)) => {
                // The point of the configuration, then the state on the level set at `v`.
                let zeros: Vec<Vec<f64>> = (sys.lie_code().kinds().iter())
                    .map(|k| vec![0.0; k.group().momentum_value_len()])
                    .collect();
                let zeros: Vec<&[f64]> = zeros.iter().map(Vec::as_slice).collect();
                let point = sys.state_of(&q, &zeros)?.q;
                sys.level_state_of(&point, v)
            }
            _ => Err(state(
                &sys.lie_code().system().name,
                "the start is the momenta `p` or (with adaptive steps) the velocities `v`, \
                 one of them"
                    .to_owned(),
            )),
        }
    }
}

impl LieCode {
    /// A state `(q, p)` (a stored point, chart momenta) as a front end shows it, coordinate by
    /// coordinate: each coordinate's configuration (a rotation's 9 entries row by row, a
    /// direction's 3, a pose's 12, a scalar) and its momentum, the forms [`LieStart`] reads.
    pub fn state_values(&self, q: &[f64], p: &[f64]) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
        (self.configuration(q), self.momenta(q, p))
    }
}

/// The integrator of a system on rotation groups `Sys` (at fixed sizes, `JitLie<P, N>`, or at
/// the sizes its text declares, `DynJitLie`): the Lie group variational integrator of the
/// request's side or, for the reduced equations, the reduced one of its declared symmetry
/// (started from the reduction of each start), at its order.
pub fn lie<Sys, P: Dim, N: Dim, J>(
    code: &Arc<LieCode>,
    params: &[f64],
    starts: &[LieStart],
    request: &RunRequest,
    job: J,
) -> Result<J::Output, Error>
where
    Sys: LieFront<P, N>,
    DefaultAllocator: Allocator<P> + Allocator<N>,
    OVector<f64, P>: Send + Sync,
    OVector<f64, N>: Send + Sync,
    J: Finish<LieIntegratorOf<Sys, P, N>>
        + Finish<Composition<LieIntegratorOf<Sys, P, N>>>
        + Finish<ReducedLieIntegratorOf<Sys::Reduced, P, N>>
        + Finish<Composition<ReducedLieIntegratorOf<Sys::Reduced, P, N>>>,
{
    request.check(&Compiled::Lie(Arc::clone(code)))?;
    let sys = Sys::instantiate(code, params)?;
    let states = starts
        .iter()
        .map(|s| s.state(&sys))
        .collect::<Result<Vec<_>, _>>()?;
    let o = request.newton;
    Ok(match (request.equations.form, request.equations.side) {
        (Form::Reduced, _) => {
            let integ = ReducedLieIntegratorOf::new(Sys::instantiate_reduced(code, params)?, o);
            let states = states.iter().map(|s| integ.reduce(s)).collect();
            by_order(integ, states, request, job)
        }
        (Form::Unreduced, Variant::Plus) => {
            by_order(LieIntegratorOf::new(sys, o), states, request, job)
        }
        (Form::Unreduced, Variant::Minus) => {
            by_order(LieIntegratorOf::minus(sys, o), states, request, job)
        }
    })
}

/// A run as the request `$r` asks it, its steps, end time and schedule applied to `$run` (a
/// run or an ensemble of the runtime's run API): at most `r.steps` steps and, when asked, up
/// to the time `r.end_time`, reached exactly, each step of the system's own size or of the
/// size the schedule gives (the runtime's `StepSizes`), then the options `$(.option(..))*`
/// (a stop condition, an observer) and `$finish` (`collect` or `stream`). The two kinds of step
/// size are two types of run, hence a macro: every step of the system's own size keeps
/// `t_k = t_0 + k h`, bit for bit the fixed-step run.
#[macro_export]
macro_rules! span {
    ($run:expr, $r:expr $(, $option:ident($($arg:expr),*))* => $finish:ident) => {{
        let r: &$crate::RunRequest = &$r;
        let run = $run.steps(r.steps);
        let run = match r.end_time {
            Some(t) => run.end_time(t),
            None => run,
        };
        match r.schedule.as_deref() {
            Some(sizes) => run
                .step_size($crate::__runtime::StepSizes(sizes))
                $(.$option($($arg),*))*
                .$finish(),
            None => run $(.$option($($arg),*))* .$finish(),
        }
    }};
}

impl Compiled {
    /// The parameter values in declaration order from `(name, value)` pairs in any order, every
    /// declared parameter once (what a front end that names them, the command line, reads).
    pub fn values_by_name(&self, parameters: &[(&str, f64)]) -> Result<Vec<f64>, Error> {
        let (name, declared) = match self {
            Compiled::Flat(code) => (&code.system().name, &code.system().parameters),
            Compiled::Lie(code) => (&code.system().name, &code.system().parameters),
            Compiled::Element(code) => (&code.system().name, &code.system().parameters),
        };
        crate::system::by_name(name, declared, parameters)
    }
}

/// [`lie`] at the fixed sizes `P` (a stored point) and `N` (the chart) of [`crate::JitLie`]: what
/// [`run_lie!`](crate::run_lie) calls for the small systems.
pub fn lie_fixed<const P: usize, const N: usize, J>(
    code: &Arc<LieCode>,
    params: &[f64],
    starts: &[LieStart],
    request: &RunRequest,
    job: J,
) -> Result<J::Output, Error>
where
    J: Finish<LieIntegratorOf<crate::JitLie<P, N>, Const<P>, Const<N>>>
        + Finish<Composition<LieIntegratorOf<crate::JitLie<P, N>, Const<P>, Const<N>>>>
        + Finish<
            ReducedLieIntegratorOf<
                crate::JitLie<P, N, crate::Dense, crate::Reduced>,
                Const<P>,
                Const<N>,
            >,
        > + Finish<
            Composition<
                ReducedLieIntegratorOf<
                    crate::JitLie<P, N, crate::Dense, crate::Reduced>,
                    Const<P>,
                    Const<N>,
                >,
            >,
        >,
{
    lie::<crate::JitLie<P, N>, Const<P>, Const<N>, J>(code, params, starts, request, job)
}

/// A run of a system on vector spaces (`code`, an `&Arc<Code>`) at any size, the one dispatch
/// on its sizes: at the fixed sizes of the small systems [`flat`] (without constraints,
/// [`with_dimensions!`](crate::with_dimensions)) or [`constrained`]
/// ([`with_constrained_dimensions!`](crate::with_constrained_dimensions)), bit for bit as the
/// system compiled in; at any other size [`view`], the element view. `$params`, `$starts`,
/// `$request` and `$job` as those functions take them; the result theirs,
/// `Result<J::Output, Error>`. A macro, so that the job's type is known where each size's
/// instance is made (the bounds of [`Finish`] are the front end's).
#[macro_export]
macro_rules! run_flat {
    ($code:expr, $params:expr, $starts:expr, $request:expr, $job:expr) => {{
        use $crate::run::{constrained as __constrained, flat as __flat};
        let code: &::std::sync::Arc<$crate::Code> = $code;
        let (params, starts, request, job) = ($params, $starts, $request, $job);
        let text = code.system();
        let (s, k) = (text.shape.len(), text.group.len());
        match text.constrained.as_ref().map(|c| c.m) {
            _ if !code.fixed_size() => $crate::run::view(code, params, starts, request, job),
            None => $crate::with_dimensions!(
                s,
                k,
                __flat::<_>(code, params, starts, request, job)
                    else $crate::run::view(code, params, starts, request, job)
            ),
            Some(m) => $crate::with_constrained_dimensions!(
                s,
                k,
                m,
                __constrained::<_>(code, params, starts, request, job)
                    else $crate::run::view(code, params, starts, request, job)
            ),
        }
    }};
}

/// A run of a system on rotation groups (`code`, an `&Arc<LieCode>`) at any size, the one
/// dispatch on its sizes: [`lie_fixed`] for the small systems (stack vectors, the dense LU;
/// [`with_lie_dimensions!`](crate::with_lie_dimensions)), [`lie`] of a
/// [`DynJitLie`](crate::DynJitLie) at the sizes its text declares for any other. The
/// arguments and the result as [`lie`]'s.
#[macro_export]
macro_rules! run_lie {
    ($code:expr, $params:expr, $starts:expr, $request:expr, $job:expr) => {{
        use $crate::run::lie_fixed as __lie_fixed;
        let code: &::std::sync::Arc<$crate::LieCode> = $code;
        let (params, starts, request, job) = ($params, $starts, $request, $job);
        let text = code.system();
        let (p, n) = (text.point_len(), text.chart_len());
        $crate::with_lie_dimensions!(
            p,
            n,
            __lie_fixed::<_>(code, params, starts, request, job)
                else $crate::run::lie::<
                    $crate::DynJitLie,
                    $crate::__runtime::nalgebra::Dyn,
                    $crate::__runtime::nalgebra::Dyn,
                    _,
                >(code, params, starts, request, job)
        )
    }};
}
