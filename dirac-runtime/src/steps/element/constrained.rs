//! Holonomic constraints of a run-time-sized system: `φ(q) = 0` with `φ` written row by row in
//! the loops of `constraints = |q| ..`, each row reading a stencil like an element.
//!
//! A step is the constrained discrete Lagrange–Dirac step of the fixed-size systems (RATTLE
//! form, Marsden & West §3.5; see `crate::constrained`), with every block assembled from the
//! elements and the constraint rows:
//!
//! ```text
//! position    p_k + D_1 L_d(q_k, q_{k+1}) + f_d^− − A(q_k)ᵀ λ_k = 0,     φ(q_{k+1}) = 0
//! momentum    p̃ = D_2 L_d(q_k, q_{k+1}) + f_d^+
//! projection  ∂L/∂v(q_{k+1}, v) − A(q_{k+1})ᵀ ν = p̃,   A(q_{k+1}) v = 0,   p_{k+1} = ∂L/∂v(q_{k+1}, v)
//! ```
//!
//! with `A = Dφ` (`m × n`, one sparse row per constraint). Both solves are Newton iterations of
//! the one driver on saddle-point (KKT) systems of `n + m` unknowns,
//!
//! ```text
//! [ J     −A(q_k)ᵀ ] [δq]        [ H     −A(q_{k+1})ᵀ ] [δv]
//! [ A(q)   0       ] [δλ]        [ A(q_{k+1})  0      ] [δν]
//! ```
//!
//! (`J = Σ_e D_1 D_2 L_d^e`, `H = Σ_e ∂²L^e/∂v²`, both on the element stencils' pattern), whose
//! common pattern is built once per run and factored with partial pivoting — by the banded LU
//! when a reverse Cuthill–McKee ordering makes it a narrow band (a chain of links: a band of a
//! few entries), by faer's sparse LU otherwise (the zero block rules out a Cholesky, or CG
//! without a preconditioner built for saddle points); chord iterations reuse its factors as in
//! the unconstrained step. The multipliers `λ_k`,
//! `ν_{k+1}` are reported per step. A constraint invariant under a declared translation (the
//! compiler checks it) has forces `Aᵀλ` with no component along the orbit, so the momentum map
//! is kept exact as in the unconstrained step (or follows the forced Noether balance).

use nalgebra::DVector;

use super::rows::{
    constraint_forces, constraint_velocities, rows_at, Legendre, RowCollector, RowData,
};
use super::solver::ElementSolver;
use super::step::{backward_point, flip_backward, keep_momentum_maps};
use super::{
    ElementIntegrator, ElementLagrangian, ElementState, ElementWorkspace, Parallel, StepSolver,
};
use crate::error::{IntegrationError, StepError, Steps};
use crate::newton::{slice_inf_norm, solve_in, NewtonOptions};
use crate::stepper::{step_error, system_at, Collect, StepAt, StepStats, StepStatsExt, Stepper};
use crate::system::Variant;

/// The workspace of an [`ElementConstrainedIntegrator`] run: the unconstrained step's
/// (assembly, pattern, guess), the constraint rows, the KKT pattern with the positions of each
/// block in it, and the two saddle-point solvers (banded or sparse LU). Built once per run.
pub struct ElementConstrainedWorkspace {
    base: ElementWorkspace,
    m: usize,
    rows: Vec<RowData>,
    invalid: Option<String>,
    /// The KKT position of each entry of the step Jacobian's pattern.
    j_to_kkt: Vec<usize>,
    position: ElementSolver,
    projection: ElementSolver,
    /// Structural nonzeros of the KKT pattern.
    kkt_nnz: usize,
    kkt: Option<Vec<f64>>,
    j: Vec<f64>,
    r: DVector<f64>,
    /// `A(q_k)` and `A(q_{k+1})` by element slot, in the order of the rows' stencils.
    a0: Vec<f64>,
    a1: Vec<f64>,
    /// The unknowns of the two solves, `(q_{k+1}, λ_k)` and `(v, ν_{k+1})`, the guess of
    /// `q_{k+1}` and the momentum before projection `p̃`.
    z: DVector<f64>,
    y: DVector<f64>,
    q1: DVector<f64>,
    ptilde: DVector<f64>,
    /// The last step's `(λ, ν)`, Newton's first guess.
    lambda: DVector<f64>,
    nu: DVector<f64>,
}

impl std::fmt::Debug for ElementConstrainedWorkspace {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ElementConstrainedWorkspace")
            .field("n", &self.base.dim())
            .field("m", &self.m)
            .field("kkt_nnz", &self.kkt_nnz)
            .field("solver", &self.position.name())
            .finish_non_exhaustive()
    }
}

impl ElementConstrainedWorkspace {
    fn new<L: ElementLagrangian>(system: &L, parallel: Parallel) -> Self {
        let base = ElementWorkspace::new(system, parallel, StepSolver::Direct);
        let (n, m) = (base.dim(), system.constraint_count());
        let (mut rows, invalid) = collect_rows(system, n);
        let invalid = base.invalid().map(str::to_string).or(invalid);
        // The KKT pattern: J's entries, A's and Aᵀ's, as (column, row) pairs.
        let (col_ptr, row_idx) = base.pattern();
        let mut entries: Vec<(usize, usize)> = Vec::with_capacity(row_idx.len());
        for c in 0..n {
            entries.extend(row_idx[col_ptr[c]..col_ptr[c + 1]].iter().map(|&r| (c, r)));
        }
        for f in &rows {
            for (e, st) in f.stencils.chunks_exact(f.width.max(1)).enumerate() {
                let row = n + f.rows[e];
                for &g in st {
                    entries.push((g, row));
                    entries.push((row, g));
                }
            }
        }
        // The diagonal of the multiplier block, structurally (a zero the LU pivots around).
        entries.extend((n..n + m).map(|i| (i, i)));
        entries.sort_unstable();
        entries.dedup();
        let mut kkt_col_ptr = vec![0usize; n + m + 1];
        for &(c, _) in &entries {
            kkt_col_ptr[c + 1] += 1;
        }
        for c in 0..n + m {
            kkt_col_ptr[c + 1] += kkt_col_ptr[c];
        }
        let kkt_row_idx: Vec<usize> = entries.iter().map(|&(_, r)| r).collect();
        drop(entries);
        let position = |row: usize, col: usize| -> usize {
            let start = kkt_col_ptr[col];
            start
                + kkt_row_idx[start..kkt_col_ptr[col + 1]]
                    .binary_search(&row)
                    .expect("every block entry is in the KKT pattern")
        };
        let mut j_to_kkt = Vec::with_capacity(row_idx.len());
        for c in 0..n {
            j_to_kkt.extend(
                row_idx[col_ptr[c]..col_ptr[c + 1]]
                    .iter()
                    .map(|&r| position(r, c)),
            );
        }
        for f in &mut rows {
            for (e, st) in f.stencils.chunks_exact(f.width.max(1)).enumerate() {
                let row = n + f.rows[e];
                for &g in st {
                    f.a_pos.push(position(row, g));
                    f.at_pos.push(position(g, row));
                }
            }
        }
        let slots: usize = rows.iter().map(|f| f.count * f.width).sum();
        let nnz = kkt_row_idx.len();
        let position = ElementSolver::saddle(n + m, &kkt_col_ptr, &kkt_row_idx);
        let projection = ElementSolver::saddle(n + m, &kkt_col_ptr, &kkt_row_idx);
        Self {
            j: vec![0.0; base.nnz()],
            base,
            m,
            rows,
            invalid,
            j_to_kkt,
            position,
            projection,
            kkt_nnz: nnz,
            kkt: Some(vec![0.0; nnz]),
            r: DVector::zeros(n + m),
            a0: vec![0.0; slots],
            a1: vec![0.0; slots],
            z: DVector::zeros(n + m),
            y: DVector::zeros(n + m),
            q1: DVector::zeros(n),
            ptilde: DVector::zeros(n),
            lambda: DVector::zeros(m),
            nu: DVector::zeros(m),
        }
    }

    /// The number of coordinates.
    pub fn dim(&self) -> usize {
        self.base.dim()
    }

    /// The number of constraint rows.
    pub fn constraints(&self) -> usize {
        self.m
    }

    /// The number of structural nonzeros of the KKT systems.
    pub fn nnz(&self) -> usize {
        self.kkt_nnz
    }

    /// The saddle-point systems' solver: `"banded LU"`, `"dense LU"` or `"sparse LU"`.
    pub fn linear_solver(&self) -> &'static str {
        self.position.name()
    }
}

/// The constraint rows of `system` against `n` coordinates, and the first reason they do not
/// fit: a row outside the constraint vector, a stencil outside the coordinates, or a row not
/// assigned exactly once. One pass over the rows, without the saddle-point pattern.
fn collect_rows<L: ElementLagrangian>(system: &L, n: usize) -> (Vec<RowData>, Option<String>) {
    let m = system.constraint_count();
    let mut collector = RowCollector {
        n,
        m,
        families: Vec::new(),
        invalid: None,
    };
    system.constraint_families(&mut collector);
    let RowCollector {
        families: rows,
        mut invalid,
        ..
    } = collector;
    let mut assigned = vec![0u32; m];
    for r in rows.iter().flat_map(|f| f.rows.iter()) {
        assigned[*r] += 1;
    }
    if invalid.is_none() {
        if let Some((row, &times)) = assigned.iter().enumerate().find(|(_, &t)| t != 1) {
            invalid = Some(format!(
                "constraint row {row} of {m} is assigned {times} times for sizes {:?}: every row \
                 of the constraint vector must be assigned exactly once",
                system.sizes()
            ));
        }
    }
    (rows, invalid)
}

/// What one constrained step reports besides the new state.
#[derive(Clone, Debug, PartialEq)]
pub struct ElementConstrainedStep {
    /// The position multipliers `λ_k` (the constraint impulse `A(q_k)ᵀ λ_k`).
    pub lambda: DVector<f64>,
    /// The projection multipliers `ν_{k+1}`.
    pub nu: DVector<f64>,
    /// `‖φ(q_{k+1})‖∞` at the accepted step.
    pub constraint_residual: f64,
    /// Newton statistics of both solves.
    pub stats: StepStats,
}

impl AsRef<StepStats> for ElementConstrainedStep {
    fn as_ref(&self) -> &StepStats {
        &self.stats
    }
}

/// Every state and step record of an [`ElementConstrainedIntegrator`] run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ElementConstrainedTrajectory {
    /// The integrator's time step (the default step of a run).
    pub h: f64,
    /// `(q_k, p_k)`, `k = 0..=steps`.
    pub states: Vec<ElementState>,
    /// `times[k] = t_k`, the time of `states[k]`.
    pub times: Vec<f64>,
    /// `step_sizes[k]` is the size step `k` was taken with, bit for bit as the run passed it to
    /// the step: `h` itself for a fixed step, `h_k` with a schedule (the last step shortened to
    /// land on an end time); with adaptive steps the fictitious step `ε_k` (the physical step is
    /// `times[k + 1] − times[k]`).
    pub step_sizes: Vec<f64>,
    /// Each step's multipliers, constraint residual and statistics.
    pub records: Vec<ElementConstrainedStep>,
    /// The Newton statistics of each step (as in `records`).
    pub stats: Vec<StepStats>,
}

impl ElementConstrainedTrajectory {
    crate::reduced::trajectory_accessors!(ElementState);

    /// The largest `‖φ(q_{k+1})‖∞` over the steps.
    pub fn max_constraint_residual(&self) -> f64 {
        self.records
            .iter()
            .map(|s| s.constraint_residual)
            .fold(0.0, f64::max)
    }
}

impl Steps for ElementConstrainedTrajectory {
    fn completed_steps(&self) -> usize {
        self.records.len()
    }
}

impl<L: ElementLagrangian> Collect<ElementConstrainedIntegrator<L>>
    for ElementConstrainedTrajectory
{
    // Each state kept is a copy of `state`'s vectors: room for them is asked for (and given
    // back) by `reserve_states`, where a failed allocation is an error rather than an abort.
    crate::stepper::collect_steps!(
        start(integrator: ElementConstrainedIntegrator<L>) {
            h: integrator.time_step(),
        },
        ElementState,
        ElementConstrainedStep,
        |step| step.stats,
        records: "step records" = step.clone();
        then crate::element::reserve_states
    );
}

/// What a failed [`ElementConstrainedIntegrator`] run keeps.
pub type ElementConstrainedError = IntegrationError<ElementConstrainedTrajectory>;

/// The integrator of a run-time-sized system with holonomic constraints (see the [module
/// documentation](self)).
#[derive(Clone, Debug)]
pub struct ElementConstrainedIntegrator<L> {
    base: ElementIntegrator<L>,
}

impl<L: ElementLagrangian> ElementConstrainedIntegrator<L> {
    /// The constrained integrator with `options`, assembling the elements in parallel above the
    /// threshold.
    pub fn new(system: L, options: NewtonOptions) -> Self {
        Self {
            base: ElementIntegrator::new(system, options),
        }
    }

    /// The (−) integrator with `options`: the (−) equations, solved for the backward increment
    /// `q_k − q_{k+1}` and the multipliers, as [`ElementIntegrator::minus`] does without
    /// constraints (the projection is the same on both sides). Started from the same state it
    /// computes the (+) trajectory, to round-off.
    pub fn minus(system: L, options: NewtonOptions) -> Self {
        Self {
            base: ElementIntegrator::minus(system, options),
        }
    }

    /// Which equations are solved: [`Variant::Plus`] ([`Self::new`]) or [`Variant::Minus`]
    /// ([`Self::minus`]).
    pub fn variant(&self) -> Variant {
        self.base.variant()
    }

    /// The same integrator with the assembly's parallelism set to `parallel`.
    pub fn with_parallel(mut self, parallel: Parallel) -> Self {
        self.base = self.base.with_parallel(parallel);
        self
    }

    /// The system being integrated.
    pub fn system(&self) -> &L {
        self.base.system()
    }

    /// Newton's tolerances and caps.
    pub fn options(&self) -> &NewtonOptions {
        self.base.options()
    }

    /// The momentum map of each declared translation ([`ElementIntegrator::momentum_map`]).
    pub fn momentum_map(&self, state: &ElementState) -> Result<Vec<f64>, StepError> {
        self.base.momentum_map(state)
    }

    /// `φ(q)`, one entry per constraint row. A vector without the system's number of
    /// coordinates, or sizes that do not fit the rows, are [`StepError::InvalidSize`].
    pub fn constraint(&self, q: &DVector<f64>) -> Result<DVector<f64>, StepError> {
        self.base.check_lengths(&[("q", q.len())])?;
        let system = self.system();
        let (rows, invalid) = collect_rows(system, system.dim());
        if let Some(reason) = invalid {
            return Err(self.base.invalid(reason));
        }
        let mut phi = DVector::zeros(system.constraint_count());
        rows_at(system, &rows, q.as_slice(), Some(phi.as_mut_slice()), None);
        Ok(phi)
    }

    /// The energy at a step's midpoint ([`ElementIntegrator::energy`]).
    pub fn energy(&self, q0: &DVector<f64>, q1: &DVector<f64>) -> Result<f64, StepError> {
        self.base.energy(q0, q1)
    }

    /// The continuous energy along a trajectory of this integrator, at its nodes and midpoints,
    /// as [`ElementIntegrator::energies`] gives it: at node `k`, `E(q_k, v_k)` with `v_k` from
    /// the Legendre map of the projected momentum `p_k` (whose velocity satisfies the
    /// constraints), at the midpoints `E((q_k + q_{k+1})/2, (q_{k+1} − q_k)/h_k)`. For a
    /// conservative system on its constraints the energy stays near its initial value, with no
    /// drift.
    pub fn energies(
        &self,
        trajectory: &ElementConstrainedTrajectory,
    ) -> Result<crate::continuous::ContinuousEnergies, StepError> {
        let view = super::ElementTrajectory {
            h: trajectory.h,
            variant: self.variant(),
            states: trajectory.states.clone(),
            times: trajectory.times.clone(),
            step_sizes: trajectory.step_sizes.clone(),
            stats: trajectory.stats.clone(),
        };
        self.base.energies(&view)
    }

    /// The constrained step from `state` into `next` (see the [module documentation](self)).
    #[allow(clippy::too_many_lines)]
    fn constrained_step(
        &self,
        ws: &mut ElementConstrainedWorkspace,
        sys: &L,
        k: usize,
        h: f64,
        state: &ElementState,
        next: &mut ElementState,
    ) -> Result<ElementConstrainedStep, StepError> {
        let (n, m) = (ws.base.dim(), ws.m);
        let options = self.base.options();
        let (q0, p0) = (state.q.as_slice(), state.p.as_slice());
        // The position solve, from the extrapolated configuration and the last multipliers.
        // (−): the unknown is the backward increment Δ = q_k − q_{k+1} (see `ElementIntegrator`'s
        // (−) side), so ∂/∂Δ = −∂/∂q_{k+1} in the `J` and `A(q_{k+1})` blocks.
        let minus = self.base.variant() == Variant::Minus;
        let sign = if minus { -1.0 } else { 1.0 };
        ws.base.guess(&state.q, h, &mut ws.q1);
        if minus {
            flip_backward(q0, ws.q1.as_mut_slice());
        }
        ws.z.rows_mut(0, n).copy_from(&ws.q1);
        ws.z.rows_mut(n, m).copy_from(&ws.lambda);
        rows_at(sys, &ws.rows, q0, None, Some(&mut ws.a0));
        let rho = slice_inf_norm(p0);
        let nnz = ws.kkt_nnz;
        let ElementConstrainedWorkspace {
            base,
            rows,
            j_to_kkt,
            position,
            projection,
            kkt,
            j,
            r,
            a0,
            a1,
            z,
            y,
            ptilde,
            nu: nu_last,
            q1: point,
            ..
        } = ws;
        let assembler = base.assembler();
        let (rows, a0, j_to_kkt) = (&rows[..], &a0[..], &j_to_kkt[..]);
        // The configuration `q_{k+1}` an unknown stands for, and the multipliers.
        let point = std::cell::RefCell::new(point);
        let at = |z: &DVector<f64>, run: &mut dyn FnMut(&[f64], &[f64])| {
            let (u, lambda) = z.as_slice().split_at(n);
            if minus {
                let mut q1 = point.borrow_mut();
                backward_point(q0, u, q1.as_mut_slice());
                run(q1.as_slice(), lambda);
            } else {
                run(u, lambda);
            }
        };
        let first = solve_in(
            position,
            z,
            r,
            kkt,
            rho,
            options,
            |z, r| {
                at(z, &mut |q1, lambda| {
                    let (r_q, r_phi) = r.as_mut_slice().split_at_mut(n);
                    assembler.residual_jacobian(sys, q0, p0, q1, r_q, None);
                    rows_at(sys, rows, q1, Some(r_phi), None);
                    constraint_forces(rows, a0, lambda, r_q, None, None);
                })
            },
            |z, r, kkt| {
                let kkt = kkt.get_or_insert_with(|| vec![0.0; nnz]);
                at(z, &mut |q1, lambda| {
                    let (r_q, r_phi) = r.as_mut_slice().split_at_mut(n);
                    assembler.residual_jacobian(sys, q0, p0, q1, r_q, Some(j.as_mut_slice()));
                    rows_at(sys, rows, q1, Some(r_phi), Some(a1.as_mut_slice()));
                    kkt.fill(0.0);
                    for (&p, v) in j_to_kkt.iter().zip(j.iter()) {
                        kkt[p] += sign * v;
                    }
                    constraint_forces(rows, a0, lambda, r_q, Some(kkt), Some((a1, sign)));
                })
            },
        )
        .map_err(|failure| step_error(k, failure))?;
        let mut stats = StepStats::from_solution(&first, options.residual_tolerance(rho));
        let constraint_residual = slice_inf_norm(&r.as_slice()[n..]);
        next.q.copy_from(&z.rows(0, n));
        if minus {
            // q_{k+1} = q_k − Δ, as the last residual pass formed it.
            flip_backward(q0, next.q.as_mut_slice());
        }
        let lambda = z.rows(n, m).into_owned();
        // The last pass was at the solution: its `D_2 L_d` is the momentum before projection.
        assembler.take_momentum(ptilde);
        // The projection, from the secant velocity and the last multipliers.
        let q1 = next.q.as_slice();
        rows_at(sys, rows, q1, None, Some(a1.as_mut_slice()));
        for i in 0..n {
            y[i] = (q1[i] - q0[i]) / h;
        }
        y.rows_mut(n, m).copy_from(&*nu_last);
        let rho2 = ptilde.amax();
        let families = assembler.families();
        let a1 = &a1[..];
        let ptilde = &*ptilde;
        let legendre = |v: &[f64], r_q: &mut [f64], kkt: Option<&mut [f64]>| {
            r_q.fill(0.0);
            let mut visit = Legendre {
                families,
                next: 0,
                q: q1,
                v,
                r: r_q,
                kkt: kkt.map(|k| (k, j_to_kkt)),
            };
            sys.families(&mut visit);
        };
        let second = solve_in(
            projection,
            y,
            r,
            kkt,
            rho2,
            options,
            |y, r| {
                let (v, nu) = y.as_slice().split_at(n);
                let (r_q, r_nu) = r.as_mut_slice().split_at_mut(n);
                legendre(v, r_q, None);
                r_q.iter_mut().zip(ptilde.iter()).for_each(|(a, b)| *a -= b);
                constraint_forces(rows, a1, nu, r_q, None, None);
                constraint_velocities(rows, a1, v, r_nu);
            },
            |y, r, kkt| {
                let kkt = kkt.get_or_insert_with(|| vec![0.0; nnz]);
                let (v, nu) = y.as_slice().split_at(n);
                let (r_q, r_nu) = r.as_mut_slice().split_at_mut(n);
                kkt.fill(0.0);
                legendre(v, r_q, Some(kkt.as_mut_slice()));
                r_q.iter_mut().zip(ptilde.iter()).for_each(|(a, b)| *a -= b);
                constraint_forces(rows, a1, nu, r_q, Some(kkt), Some((a1, 1.0)));
                constraint_velocities(rows, a1, v, r_nu);
            },
        )
        .map_err(|failure| step_error(k, failure))?;
        stats.accumulate(&StepStats::from_solution(
            &second,
            options.residual_tolerance(rho2),
        ));
        let nu = y.rows(n, m).into_owned();
        // p_{k+1} = ∂L/∂v(q_{k+1}, v).
        legendre(&y.as_slice()[..n], next.p.as_mut_slice(), None);
        keep_momentum_maps(sys, assembler.orbits(), q0, p0, q1, &mut next.p);
        if !next.p.iter().all(|v| v.is_finite()) {
            return Err(StepError::NonFinite {
                step: k,
                what: "the projected momentum",
                residual: stats.residual,
            });
        }
        ws.lambda.copy_from(&lambda);
        ws.nu.copy_from(&nu);
        ws.base.remember(&state.q, &next.q, h);
        Ok(ElementConstrainedStep {
            lambda,
            nu,
            constraint_residual,
            stats,
        })
    }
}

impl<L: ElementLagrangian> Stepper for ElementConstrainedIntegrator<L> {
    type State = ElementState;
    type Record = ElementConstrainedStep;
    type Workspace = ElementConstrainedWorkspace;
    type Trajectory = ElementConstrainedTrajectory;

    fn time_step(&self) -> f64 {
        self.base.system().time_step()
    }

    /// The inputs, the sizes against the stencils and rows, and `‖φ(q_0)‖∞` within the Newton
    /// tolerances (×10³): a typed [`StepError::ConstraintViolated`] otherwise.
    fn check(&self, initial: &ElementState) -> Result<(), StepError> {
        self.base.check(initial)?;
        let phi = self.constraint(&initial.q)?;
        crate::constrained::check_constraint(phi.amax(), initial.q.amax(), self.options())
    }

    fn workspace(&self) -> ElementConstrainedWorkspace {
        ElementConstrainedWorkspace::new(self.base.system(), self.base.parallel())
    }

    fn control_dim(&self) -> usize {
        self.base.system().control_count()
    }

    fn step_into(
        &self,
        workspace: &mut ElementConstrainedWorkspace,
        at: StepAt<'_>,
        state: &ElementState,
        next: &mut ElementState,
    ) -> Result<ElementConstrainedStep, StepError> {
        let StepAt { k, h, u } = at;
        // The system of this step (its controls checked first, before the workspace and state).
        let owned = system_at(self.base.system(), k, h, u)?;
        if let Some(reason) = &workspace.invalid {
            return Err(self.base.invalid(reason.clone()));
        }
        self.base.check_workspace(&workspace.base)?;
        let n = workspace.base.dim();
        if state.q.len() != n || state.p.len() != n {
            return Err(self.base.invalid(format!(
                "the state has {} coordinates and {} momenta, the system {n}",
                state.q.len(),
                state.p.len()
            )));
        }
        if next.q.len() != n || next.p.len() != n {
            *next = state.clone();
        }
        let sys = owned.as_ref().unwrap_or(self.base.system());
        self.constrained_step(workspace, sys, k, h, state, next)
    }
}
