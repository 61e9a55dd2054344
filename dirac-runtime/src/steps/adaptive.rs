//! Adaptive time steps that keep the structure: a system declared with
//! `time(t), adapt = |q| g` is the Poincaré time transformation of its continuous Lagrangian,
//! stepped at a fixed fictitious step `ε` (the attribute's step parameter), each step covering
//! the physical time `Δt_k = t_{k+1} − t_k ≈ ε g(q)`.
//!
//! The compiler replaces `L(q, v)` by
//!
//! ```text
//! L₂(q, t, q', t') = t' L(q, q'/t') + (t' − g(q))² / (2 g(q))
//! ```
//!
//! (primes: derivatives in the fictitious time `τ`, `dt = g dτ`), the Legendre transform of the
//! regularized Poincaré Hamiltonian `K₂ = g (H + p_t) + ½ g (H + p_t)²`, whose solutions on the
//! level set `p_t = −H` are the physical ones reparametrized, with `t' = g` (the derivation is in
//! the guide's chapter on adaptive steps). `L₂` is an ordinary Lagrangian on `(q, t)`, so every
//! integrator steps it unchanged, and what they keep is kept here in extended phase space:
//!
//! * the discrete flow is symplectic in `(q, t, p, p_t)`, and symmetric for a symmetric rule
//!   (midpoint, trapezoid: time-reversible), raised to order 4 and 6 in `ε` by the compositions;
//! * `L₂` does not read `t` (the time is a group coordinate), so `p_t` is the momentum of a
//!   symmetry: the reduced integrators copy it, bit for bit — `p_t = −E` at the level the run
//!   started on — as they copy the momentum of every symmetry the monitor respects (the monitor
//!   may read shape coordinates only, checked at compile time);
//! * the momenta `p` conjugate to `q` are the physical ones, `∂L/∂v`, and the physical energy
//!   oscillates about `−p_t` without drift.
//!
//! A run must start on the level set, `p_t = −E(q, p)`: build the initial state from the
//! physical position and velocity with
//! [`sys.unreduced_state(q, v)`](crate::ContinuousLagrangian::unreduced_state) (or
//! `reduced_state`), which for such a system sets `t' = g` and so `p_t = −E` exactly. Every
//! run checks it before the first step, once for every integrator (each says only where its
//! state lies, [`crate::Stepper::level_set`]): a start farther from the level set than
//! [`LEVEL_SET_TOLERANCE`] (relative) is refused with [`crate::StepError::OffManifold`]. Each
//! step's monitor must be positive and finite ([`crate::StepError::InvalidMonitor`] otherwise,
//! with the step index) and its physical step `Δt_k` of the sign of `ε`
//! ([`crate::StepError::TimeReversed`]): the run loop checks both after every step, once for every
//! integrator (each says only how its state gives the monitor, [`crate::Stepper::monitor`], and
//! its time, [`crate::Stepper::physical_time`]); Newton's first guess for the time increment of
//! a run is `ε g(x)`.

use nalgebra::SVector;

use crate::continuous::ContinuousLagrangian;
use crate::error::StepError;
use crate::stepper::check_monitor;
use crate::system::DiscreteLagrangian;

/// Newton's guess for the increment of a run's first step of fictitious size `h` from `(q, p)`:
/// `h v`, with `v` the velocity in fictitious time on the level set — the time coordinate's rate
/// `g(x)` and the others solving the Legendre map `∂L₂/∂v_q (q, v) = p_q` at that rate (by a few
/// Newton iterations with a difference-quotient Jacobian: a guess, once per run). Starting from
/// rest instead, Newton meets the strongly nonlinear dependence of `L₂` on the time increment
/// (`Δt L(q, Δq/Δt)`) with the whole kinetic energy in its residual and can overshoot to a negative
/// `Δt`. `None` for a system without adaptive steps or a monitor that is not positive.
pub fn first_increment<L, const S: usize, const K: usize, const N: usize>(
    sys: &L,
    q: &SVector<f64, N>,
    p: &SVector<f64, N>,
    h: f64,
) -> Option<SVector<f64, N>>
where
    L: DiscreteLagrangian<S, K, N> + ContinuousLagrangian<N>,
{
    let time = S + sys.time_index()?;
    let g = sys.monitor(&q.fixed_rows::<S>(0).into_owned())?;
    first_increment_of(time, g, q, p, h, |q, v| sys.legendre(q, v))
}

/// [`first_increment`] for a system whose Legendre map is `legendre(q, v)`, whose time
/// coordinate is entry `time` of `q` and whose monitor is `g` at `q`: what a system that is not a
/// [`ContinuousLagrangian`] (one given at run time) computes it with. `None` for a monitor that is
/// not positive or an increment that is not finite.
pub fn first_increment_of<const N: usize>(
    time: usize,
    g: f64,
    q: &SVector<f64, N>,
    p: &SVector<f64, N>,
    h: f64,
    legendre: impl Fn(&SVector<f64, N>, &SVector<f64, N>) -> SVector<f64, N>,
) -> Option<SVector<f64, N>> {
    check_monitor(0, g).ok()?;
    let mut v = SVector::<f64, N>::zeros();
    v[time] = g;
    let rows: Vec<usize> = (0..N).filter(|&i| i != time).collect();
    let scale = p.amax().max(1.0);
    for _ in 0..8 {
        let r0 = legendre(q, &v) - p;
        if rows.iter().all(|&i| r0[i].abs() <= 1e-13 * scale) {
            break;
        }
        let mut jac = nalgebra::DMatrix::<f64>::zeros(rows.len(), rows.len());
        for (c, &i) in rows.iter().enumerate() {
            let step = 1e-7 * v[i].abs().max(g);
            let mut w = v;
            w[i] += step;
            let r1 = legendre(q, &w) - p;
            for (r, &k) in rows.iter().enumerate() {
                jac[(r, c)] = (r1[k] - r0[k]) / step;
            }
        }
        let rhs = nalgebra::DVector::from_iterator(rows.len(), rows.iter().map(|&k| r0[k]));
        let delta = jac.lu().solve(&rhs)?;
        for (c, &i) in rows.iter().enumerate() {
            v[i] -= delta[c];
        }
    }
    v.iter().all(|x| x.is_finite()).then(|| v * h)
}

pub use crate::continuous::fictitious_velocity;
pub use crate::stepper::LEVEL_SET_TOLERANCE;

/// How far `(q, p)` is from the level set `p_t = −E(q, p)` of a system with adaptive steps:
/// `(p_t + E, scale)` with `scale = max(|E|, |⟨p_q, u⟩|)` the size of the terms the energy is
/// formed from. On the level set the time coordinate's rate is `t' = g(x)`, and there
/// `∂L₂/∂t' = L(q, u) − ⟨u, ∂L/∂u⟩ = −E` (`L₂` of the [module documentation](self), `u = v/g`
/// the physical velocity): so `E` is read from the Legendre map of `L₂` at the velocity
/// [`first_increment`] solves for (`t' = g`, the other rows `∂L₂/∂v_q = p_q`). `None` for a
/// system without adaptive steps, a monitor that is not positive, or a velocity that cannot be
/// solved for.
pub fn level_set_defect<L, const S: usize, const K: usize, const N: usize>(
    sys: &L,
    q: &SVector<f64, N>,
    p: &SVector<f64, N>,
) -> Option<(f64, f64)>
where
    L: DiscreteLagrangian<S, K, N> + ContinuousLagrangian<N>,
{
    let time = S + sys.time_index()?;
    let g = sys.monitor(&q.fixed_rows::<S>(0).into_owned())?;
    level_set_defect_of(time, g, q, p, |q, v| sys.legendre(q, v))
}

/// [`level_set_defect`] for a system whose Legendre map is `legendre(q, v)`, whose time
/// coordinate is entry `time` of `q` and whose monitor is `g` at `q` (a system given at run
/// time).
pub fn level_set_defect_of<const N: usize>(
    time: usize,
    g: f64,
    q: &SVector<f64, N>,
    p: &SVector<f64, N>,
    legendre: impl Fn(&SVector<f64, N>, &SVector<f64, N>) -> SVector<f64, N>,
) -> Option<(f64, f64)> {
    let v = first_increment_of(time, g, q, p, 1.0, &legendre)?;
    let energy = -legendre(q, &v)[time];
    let work: f64 = (0..N).filter(|&i| i != time).map(|i| p[i] * v[i] / g).sum();
    let defect = p[time] + energy;
    defect
        .is_finite()
        .then(|| (defect, energy.abs().max(work.abs())))
}

/// The fictitious step that reaches `tolerance`, from a pilot at two steps: `run(ε)` integrates
/// whatever the caller cares about with the fictitious step `ε` (a short pilot run, or the run
/// itself when it is cheap) and returns the quantities whose error should stay below
/// `tolerance` (e.g. the final position and phase). The error at `ε0` is estimated by Richardson
/// extrapolation, `e ≈ ‖x(ε0) − x(ε0/2)‖∞ · 2^p/(2^p − 1)` for a method of order `p`, and the
/// step scaled as `ε = ε0 (tolerance/(2e))^{1/p}`, aiming at half the tolerance (a margin for
/// the estimate). The
/// estimate holds where the error behaves as `C ε^p`: start from an `ε0` at which the method
/// resolves the motion (a few steps per encounter), and not so small that round-off dominates.
/// `Err` passes on the pilot run's error; an estimate of zero (the two runs agree to the bit)
/// returns `ε0`.
pub fn step_for_tolerance<E>(
    order: u32,
    eps0: f64,
    tolerance: f64,
    mut run: impl FnMut(f64) -> Result<nalgebra::DVector<f64>, E>,
) -> Result<f64, E> {
    let coarse = run(eps0)?;
    let fine = run(eps0 / 2.0)?;
    let p = f64::from(order);
    let gain = 2f64.powf(p);
    let estimate = (coarse - fine).amax() * gain / (gain - 1.0);
    if estimate.is_nan() || estimate <= 0.0 || estimate.is_infinite() {
        return Ok(eps0);
    }
    Ok(eps0 * (0.5 * tolerance / estimate).powf(1.0 / p))
}

/// Lands a run on the physical time `end` exactly: `step(ε)` takes one step of fictitious size
/// `ε` from the last state before `end` (at physical time `t0 < end`, reached with the fictitious
/// step `h`) and returns the physical time it reaches with the new state; the step size is found
/// by the secant method on `ε ↦ t(ε) − end` in `(0, h]` (the time a step covers grows
/// monotonically with `ε`, and `t(0) = t0`), to `4 ulp(end)`. The final step is a step of the same
/// variational integrator at another fictitious step, so nothing it keeps is lost. A run stopped
/// on `t ≥ end` (`.stop(|_, _, s| s.g[j] >= end)`) ends one step past `end`: take that step again
/// from the state before it with this. `Err` passes on a failed step, or
/// [`StepError::InvalidRun`] when `end` is not within that step (`t0 < end ≤ t(h)`) or the
/// secant does not converge in 50 iterations.
pub fn land_at<S>(
    end: f64,
    t0: f64,
    h: f64,
    mut step: impl FnMut(f64) -> Result<(f64, S), StepError>,
) -> Result<S, StepError> {
    let (t_full, full) = step(h)?;
    land_within(end, t0, h, (t_full, full), step).map(|(_, landed)| landed)
}

/// [`land_at`] with the full step `(t(h), state)` already taken (the driver's landing on a
/// run's end time); with the landed state, the fictitious step that reached it.
pub(crate) fn land_within<S>(
    end: f64,
    t0: f64,
    h: f64,
    (t_full, full): (f64, S),
    mut step: impl FnMut(f64) -> Result<(f64, S), StepError>,
) -> Result<(f64, S), StepError> {
    let tolerance = landing_tolerance(end);
    if !(t0 < end && end <= t_full) {
        return Err(StepError::InvalidRun {
            reason: format!(
                "landing on t = {end}: it is not within the step from t = {t0} to t = {t_full}"
            ),
        });
    }
    if (t_full - end).abs() <= tolerance {
        return Ok((h, full));
    }
    // Secant iterates (ε, t(ε) − end), from ε = 0 (where t = t0) and ε = h.
    let (mut a, mut fa) = (0.0, t0 - end);
    let (mut b, mut fb) = (h, t_full - end);
    for _ in 0..50 {
        let eps = (b - fb * (b - a) / (fb - fa)).clamp(f64::MIN_POSITIVE, h);
        let (t, state) = step(eps)?;
        let f = t - end;
        if f.abs() <= tolerance {
            return Ok((eps, state));
        }
        (a, fa, b, fb) = (b, fb, eps, f);
    }
    Err(StepError::InvalidRun {
        reason: format!("landing on t = {end}: the secant on the fictitious step did not converge"),
    })
}

/// How close to a physical end time a step must come to have landed on it: 4 ulp of `end` (at
/// least of 1).
pub(crate) fn landing_tolerance(end: f64) -> f64 {
    4.0 * f64::EPSILON * end.abs().max(1.0)
}
