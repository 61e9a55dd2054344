//! Long-run guarantees, in release mode. The tests are `#[ignore]`d, so `cargo test --workspace`
//! (debug) skips them; `.ci/run` runs them with
//! `cargo test --release --test long_run -- --ignored --nocapture`, which prints a summary of each.
//!
//! * The double spherical pendulum, 10⁶ steps at the paper's `h = 0.01` (T = 10⁴), with
//!   `ReducedIntegrator::plus`: no failed step; μ bit-for-bit constant; the physical energy
//!   `T + V` at the step midpoints without secular drift (|mean over the last 10% − mean over the
//!   first 10%| ≤ 0.1 × its spread) and with a spread that shrinks like h² (h against h/2 over the
//!   same T); the unreduced stepper's momentum-map drift over the same 10⁶ steps beside it.
//!   The run starts near a conical motion, not from the paper's initial state: see
//!   [`dsp_long_run_initial_state`] and the test `double_spherical_pendulum_from_the_paper_state`,
//!   which shows why (Remark 7.1); `tests/atlas_long_run.rs` runs the paper's state itself on an
//!   atlas of three charts (§6).
//! * The charged particle, 10⁶ steps at `h = 0.2` (the time step of the paper's N = 100 run):
//!   no failed step, μ bit-for-bit constant, the kinetic energy conserved (to round-off: see
//!   `charged_particle_million_steps` for why there is no h² oscillation there, and where h²
//!   shows instead).

use std::f64::consts::PI;
use std::time::{Duration, Instant};

use dirac::paper::{ChargedParticle, DoubleSphericalPendulum, DSP_STEPS};
use dirac::prelude::*;
use dirac::runtime::system::join;

/// The number of steps every long run takes at its coarser time step.
const STEPS: usize = 1_000_000;

/// A test's summary, printed in one piece when the test ends (also when it fails), so that the
/// summaries of tests running in parallel do not interleave.
struct Report(String);

impl Drop for Report {
    fn drop(&mut self) {
        print!("{}", self.0);
    }
}

/// `say!(out, "format", args…)` appends a line to the report `out`.
macro_rules! say {
    ($out:expr, $($arg:tt)*) => {{
        $out.0.push_str(&format!($($arg)*));
        $out.0.push('\n');
    }};
}

/// Mean, spread and drift of an energy series.
struct Summary {
    mean: f64,
    /// `max − min` over the run.
    spread: f64,
    /// Mean over the last 10% minus mean over the first 10%.
    drift: f64,
}

impl Summary {
    fn of(values: &[f64]) -> Self {
        // Sums of deviations from the first value: summing 10⁶ terms of size |E| would bury the
        // differences being measured under the round-off of the sum.
        let first = values[0];
        let mean_deviation = |s: &[f64]| s.iter().map(|e| e - first).sum::<f64>() / s.len() as f64;
        let (min, max) = values
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &e| {
                (lo.min(e), hi.max(e))
            });
        let tenth = values.len() / 10;
        Self {
            mean: first + mean_deviation(values),
            spread: max - min,
            drift: mean_deviation(&values[values.len() - tenth..])
                - mean_deviation(&values[..tenth]),
        }
    }

    fn print(&self, out: &mut Report, label: &str) {
        say!(out,
            "  {label:<26} mean {:.9e}  spread {:.4e} ({:.2e} relative)  drift {:+.3e} ({:+.4} x spread)",
            self.mean,
            self.spread,
            self.spread / self.mean.abs(),
            self.drift,
            self.drift / self.spread
        );
    }
}

/// Integrates with the reduced (+) equations (4.6), default Newton options; a failed step fails
/// the test with the typed error.
fn reduced_run<L, const S: usize, const K: usize, const N: usize>(
    sys: L,
    initial: ReducedState<S, K>,
    steps: usize,
) -> (Trajectory<S, K>, Duration)
where
    L: Reduced<Plus, S, K, N>,
{
    let start = Instant::now();
    let result = ReducedIntegrator::plus(sys, NewtonOptions::default())
        .run(initial)
        .steps(steps)
        .collect();
    let elapsed = start.elapsed();
    match result {
        Ok(trajectory) => (trajectory, elapsed),
        Err(e) => panic!(
            "h = {}: failed after {} of {steps} steps: {}",
            e.trajectory.h,
            e.trajectory.step_count(),
            e.source
        ),
    }
}

/// `μ_k = μ_0` bit for bit along the whole trajectory (`μ_{k+1} = μ_k` is one of the equations
/// (4.6): no Newton residual may leak into it).
fn assert_mu_exact<const S: usize, const K: usize>(trajectory: &Trajectory<S, K>) {
    let mu0 = trajectory.states[0].mu;
    if let Some(k) = trajectory.states.iter().position(|s| {
        s.mu.iter()
            .zip(&mu0)
            .any(|(a, b)| a.to_bits() != b.to_bits())
    }) {
        panic!(
            "h = {}: mu_{k} = {:?} differs from mu_0 = {:?}",
            trajectory.h, trajectory.states[k].mu, mu0
        );
    }
}

fn dsp_config(s: &ReducedState<3, 1>) -> SVector<f64, 4> {
    join::<3, 1, 4>(&s.x, &s.g)
}

/// `T + V` at the midpoint of every step (see [`DoubleSphericalPendulum::physical_energy`]).
fn dsp_physical_energies(sys: &DoubleSphericalPendulum, traj: &Trajectory<3, 1>) -> Vec<f64> {
    traj.states
        .windows(2)
        .map(|pair| sys.physical_energy(&dsp_config(&pair[0]), &dsp_config(&pair[1])))
        .collect()
}

/// `min_k |sin φ_i|` over the states, for the two polar angles: the distance from the
/// configurations where the spherical coordinates and the reduction are singular (Remark 7.1).
fn dsp_closest_to_poles(states: &[ReducedState<3, 1>]) -> (f64, f64) {
    states.iter().fold((1.0f64, 1.0f64), |(a, b), s| {
        (a.min(s.x[0].sin().abs()), b.min(s.x[2].sin().abs()))
    })
}

/// The conical relative equilibrium of the double spherical pendulum with the first link at
/// angle `a` from the downward vertical: both bobs in one vertical half-plane (ϑ2 = 0), at polar
/// angles `φ1 = π − a`, `φ2 = π − b`, turning about the vertical at the rate Ω. Returns `(b, Ω)`.
///
/// With `ρ1 = l1 sin a`, `ρ2 = ρ1 + l2 sin b` (the distances of the bobs from the axis) the
/// amended potential `V − ½ Ω² (m1 ρ1² + m2 ρ2²)` is stationary in φ2 when
/// `Ω² = g sin b / (ρ2 cos b)`, and in φ1 when
/// `g (m1 + m2) sin a = Ω² cos a (m1 ρ1 + m2 ρ2)`; `b` solves the second with the first
/// substituted, by bisection on (0, π/2).
fn conical_motion(sys: &DoubleSphericalPendulum, a: f64) -> (f64, f64) {
    let (m1, m2, l1, l2, g) = (sys.m1, sys.m2, sys.l1, sys.l2, sys.g);
    let omega2 = |b: f64| g * b.sin() / (b.cos() * (l1 * a.sin() + l2 * b.sin()));
    let balance = |b: f64| {
        g * (m1 + m2) * a.sin()
            - omega2(b) * a.cos() * (m1 * l1 * a.sin() + m2 * (l1 * a.sin() + l2 * b.sin()))
    };
    let (mut lo, mut hi) = (1e-9, 0.5 * PI - 1e-9);
    assert!(
        balance(lo) * balance(hi) < 0.0,
        "no conical motion at a = {a}"
    );
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if balance(lo) * balance(mid) <= 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let b = 0.5 * (lo + hi);
    (b, omega2(b).sqrt())
}

/// The canonical momenta `p = ∂L/∂q̇` at `(q, q̇)`, with `L(q, q̇) = L_d(q − h q̇/2, q + h q̇/2)/h`
/// (the midpoint rule puts the midpoint at `q` and the difference quotient at `q̇`). `L` is
/// quadratic in `q̇`, so the central difference is exact up to round-off.
fn dsp_momenta(
    sys: &DoubleSphericalPendulum,
    q: &SVector<f64, 4>,
    qdot: &SVector<f64, 4>,
) -> SVector<f64, 4> {
    let lagrangian = |v: &SVector<f64, 4>| {
        sys.lagrangian(&(q - 0.5 * sys.h * v), &(q + 0.5 * sys.h * v)) / sys.h
    };
    let eps = 1e-3;
    SVector::<f64, 4>::from_fn(|i, _| {
        let e = SVector::<f64, 4>::from_fn(|j, _| if i == j { eps } else { 0.0 });
        (lagrangian(&(qdot + e)) - lagrangian(&(qdot - e))) / (2.0 * eps)
    })
}

/// The initial state of the long runs: the paper's pendulum near its conical motion with the first
/// link 0.6 rad from the downward vertical (φ1 = π − 0.6, φ2 = π − 0.73, Ω = 0.104 rad/s, a
/// revolution in 60.5 s), displaced by 0.3 rad in φ1 and in ϑ2 with the conical motion's
/// velocities. Over 10⁶ steps it stays well away from the poles (|sin φ1| ≥ 0.22,
/// |sin φ2| ≥ 0.40; asserted), φ1 ranging over [2.43, 2.92] and φ2 over [2.38, 2.72].
///
/// Why not the paper's initial state: it starts almost at rest with μ = 0, so nothing keeps the
/// bobs off the vertical axis, where the spherical coordinates (and the reduction) are singular
/// (Remark 7.1). Its motion passes ever closer to the poles and, at a fixed time step, eventually
/// meets one it cannot resolve; `double_spherical_pendulum_from_the_paper_state` measures where.
fn dsp_long_run_initial_state(sys: &DoubleSphericalPendulum) -> ReducedState<3, 1> {
    let a = 0.6;
    let (b, omega) = conical_motion(sys, a);
    let q = SVector::<f64, 4>::new(PI - a + 0.3, 0.3, PI - b, 0.0);
    let qdot = SVector::<f64, 4>::new(0.0, 0.0, 0.0, omega);
    let p = dsp_momenta(sys, &q, &qdot);
    // B = 0: w = p_x, μ = p_g (eq. (3.6)).
    ReducedState::new([q[0], q[1], q[2]], [p[0], p[1], p[2]], [p[3]], [q[3]])
}

/// The long-run guarantees for the double spherical pendulum: 10⁶ steps at h = 0.01 (T = 10⁴) and
/// 2·10⁶ at h/2, no failed step, μ exact, no secular drift of `T + V`, spread ∝ h², and the
/// unreduced stepper's momentum-map drift over the same 10⁶ steps.
#[test]
#[ignore = "long run: release mode, run by .ci/run"]
fn double_spherical_pendulum_million_steps() {
    let mut out = Report(String::new());
    let start = Instant::now();
    let sys = DoubleSphericalPendulum::paper();
    let initial = dsp_long_run_initial_state(&sys);
    let half = DoubleSphericalPendulum {
        h: 0.5 * sys.h,
        ..sys
    };
    say!(
        out,
        "\nDouble spherical pendulum, paper's parameters, near the conical motion \
         (x0 = ({:.4}, {:.4}, {:.4}), mu0 = {:.6e})",
        initial.x[0],
        initial.x[1],
        initial.x[2],
        initial.mu[0]
    );

    let mut spreads = Vec::new();
    let mut reduced = None;
    for (sys, steps) in [(sys, STEPS), (half, 2 * STEPS)] {
        let (traj, wall) = reduced_run(sys, initial, steps);
        assert_eq!(traj.step_count(), steps);
        assert_mu_exact(&traj);
        let (sin1, sin2) = dsp_closest_to_poles(&traj.states);
        assert!(
            sin1 > 0.1 && sin2 > 0.1,
            "h = {}: the run came near a pole (min |sin phi1| = {sin1:.3e}, min |sin phi2| = \
             {sin2:.3e}), where the coordinates are singular (Remark 7.1)",
            sys.h
        );
        let energy = Summary::of(&dsp_physical_energies(&sys, &traj));
        say!(out,
            "  h = {:<6} {steps} steps, T = {:.0}: no failed step, {:.2} s ({:.2} us/step), \
             Newton it. mean {:.3}, worst rcond {:.2e}, min |sin phi1| {sin1:.3}, |sin phi2| {sin2:.3}",
            sys.h,
            traj.times[steps],
            wall.as_secs_f64(),
            1e6 * wall.as_secs_f64() / steps as f64,
            traj.mean_iterations(),
            traj.worst_rcond().map_or(f64::NAN, |(_, r)| r),
        );
        say!(out, "  max |mu_k - mu_0|         0 (bit for bit)");
        energy.print(&mut out, "T + V at midpoints");
        assert!(
            energy.drift.abs() <= 0.1 * energy.spread,
            "h = {}: secular drift of T + V: {:.3e} against a spread of {:.3e}",
            sys.h,
            energy.drift,
            energy.spread
        );
        spreads.push(energy.spread);
        if reduced.is_none() {
            reduced = Some(traj);
        }
    }
    let ratio = spreads[0] / spreads[1];
    say!(
        out,
        "  spread(h) / spread(h/2)   {ratio:.4} (h^2 scaling: 4)"
    );
    assert!(
        (3.0..=5.0).contains(&ratio),
        "the spread of T + V does not shrink like h^2: ratio {ratio}"
    );

    // The unreduced equations from the same state, over the same 10⁶ steps.
    let reduced = reduced.expect("the h run");
    let wall = Instant::now();
    let unreduced = UnreducedIntegrator::new(sys, NewtonOptions::default())
        .run(sys.untrivialize(&initial))
        .steps(STEPS)
        .collect()
        .unwrap_or_else(|e| {
            panic!(
                "unreduced: failed after {} steps: {}",
                e.trajectory.step_count(),
                e.source
            )
        });
    let wall = wall.elapsed();
    let j0 = sys.momentum_map(&unreduced.states[0])[0];
    let j_drift = unreduced
        .states
        .iter()
        .map(|s| (sys.momentum_map(s)[0] - j0).abs())
        .fold(0.0, f64::max);
    let q_diff = reduced
        .states
        .iter()
        .zip(&unreduced.states)
        .map(|(r, u)| (sys.untrivialize(r).q - u.q).amax())
        .fold(0.0, f64::max);
    say!(out,
        "  unreduced, h = {}: {STEPS} steps, {:.2} s; max |J(q_k, p_k) - J(q_0, p_0)| {j_drift:.3e} \
         ({:.2e} relative to |mu0|; reduced: exactly 0); max |q_reduced - q_unreduced| {q_diff:.3e}",
        sys.h,
        wall.as_secs_f64(),
        j_drift / j0.abs()
    );
    say!(
        out,
        "  test wall time {:.1} s",
        start.elapsed().as_secs_f64()
    );
}

/// Remark 7.1 on the long run, from the paper's own initial state (h = 0.01): the motion starts
/// almost at rest with μ = 0, so nothing keeps the bobs off the vertical axis, and it passes ever
/// closer to the poles of the spherical coordinates until a passage is too close for the time
/// step to resolve. Asserted: the paper's 10⁴ steps complete, μ is exact wherever the run went,
/// and the run ends complete or with a typed `StepError`, never a panic. Printed: how far it got;
/// where `T + V` first left a 10% band about its initial value (the breakdown; transient spikes at
/// close passages stay well inside it), how close to a pole the run was there, and what the
/// stepper accepted between the breakdown and the error.
#[test]
#[ignore = "long run: release mode, run by .ci/run"]
fn double_spherical_pendulum_from_the_paper_state() {
    let mut out = Report(String::new());
    let sys = DoubleSphericalPendulum::paper();
    let result = ReducedIntegrator::plus(sys, NewtonOptions::default())
        .run(DoubleSphericalPendulum::paper_initial_state())
        .steps(STEPS)
        .collect();
    let (traj, outcome) = match &result {
        Ok(traj) => (traj, "completed".to_string()),
        Err(e) => (&e.trajectory, format!("stopped: {}", e.source)),
    };
    let energy = dsp_physical_energies(&sys, traj);
    let e0 = energy[0];
    say!(
        out,
        "\nDouble spherical pendulum from the paper's initial state (mu0 = 0), h = {}",
        sys.h
    );
    say!(
        out,
        "  {} of {STEPS} steps (t = {:.2}), {outcome}",
        traj.step_count(),
        traj.times[traj.step_count()]
    );
    if energy.len() >= DSP_STEPS {
        Summary::of(&energy[..DSP_STEPS]).print(&mut out, "T + V, paper's 10^4 steps");
    }
    match energy.iter().position(|e| (e - e0).abs() > 0.1 * e0.abs()) {
        Some(k) => {
            let s = &traj.states[k];
            let (sin1, sin2) = dsp_closest_to_poles(&traj.states[..=k]);
            let worst_after = energy[k..].iter().fold(0.0f64, |m, e| m.max(e.abs()));
            say!(
                out,
                "  T + V left 10% of E_0 = {e0:.6e} at step {k} (t = {:.2}): |sin phi1| = {:.2e}, \
                 |sin phi2| = {:.2e} there (closest so far: {sin1:.2e}, {sin2:.2e}), \
                 d(vt2) = {:.2} rad in that step",
                traj.times[k],
                s.x[0].sin().abs(),
                s.x[2].sin().abs(),
                traj.states[k + 1].x[1] - s.x[1]
            );
            say!(
                out,
                "  steps accepted after it: {}, max |T + V| among them {worst_after:.3e}",
                traj.step_count() - k - 1
            );
        }
        None => say!(out, "  T + V stayed within 10% of E_0 = {e0:.6e}"),
    }
    assert!(
        traj.step_count() >= DSP_STEPS,
        "the paper's run itself failed: {outcome}"
    );
    assert_mu_exact(traj);
}

/// The long-run guarantees for the charged particle: 10⁶ steps at h = 0.2 and 2·10⁶ at h/2, no
/// failed step, μ exact, and the physical energy.
///
/// The physical energy is the kinetic energy ½ m |q̇|²: the Lorentz force does no work and there
/// is no potential (the Kaluza–Klein term ½ (⟨A, q̇⟩ + θ̇)² = ½ μ² is a constant). It is measured
/// with the step velocity `v_k = (q_{k+1} − q_k)/h`, the velocity the left-point `L_d` itself
/// uses (as `T + V` of the pendulum uses the midpoint rule's). The discrete Euler–Lagrange
/// equations of this `L_d` reduce to `m (v_k − v_{k−1}) = (μ b0 h / 2) (v_{k−1} + v_k)^⊥` in the
/// xy plane (⊥: rotation by a right angle) and `v_k^z = v_{k−1}^z`: a Cayley rotation, so |v_k|
/// is constant and this energy is conserved exactly, up to round-off and the Newton tolerance.
/// There is no O(h²) oscillation whose spread could shrink like h²; what shrinks like h² is its
/// constant offset from the exact energy, `E_h − E = −½ |w0_xy|² c² / ((1 + c²) m)` with
/// `c = μ b0 h / (2m)` (from `w_0 = m (v_0 − c v_0^⊥)` at q = 0), which is asserted. The energy
/// from the momenta at the nodes, `½ |w_k − μ A(q_k)|² / m` (`p = m q̇ + μ A`), equals the exact
/// energy 1 for every h, and is reported.
///
/// So the pendulum's drift criterion (|drift| ≤ 0.1 × spread) compares round-off with round-off:
/// the spread is itself the accumulated round-off, and a random walk's late mean differs from its
/// early mean by a good fraction of its range. It is printed; what is asserted is that the spread
/// and the drift are at round-off level, ≤ 1e-8 relative.
#[test]
#[ignore = "long run: release mode, run by .ci/run"]
fn charged_particle_million_steps() {
    let mut out = Report(String::new());
    let start = Instant::now();
    let initial = ChargedParticle::paper_initial_state();
    let (m, b0) = (1.0, 1.0);
    let exact = 0.5 * initial.w.norm_squared() / m; // q = 0: A = 0, p = m q̇
    say!(
        out,
        "\nCharged particle, m = {m}, b0 = {b0}, paper's initial state; exact energy {exact}"
    );
    let mut offsets = Vec::new();
    for (h, steps) in [(0.2, STEPS), (0.1, 2 * STEPS)] {
        let sys = ChargedParticle { h, m, b0 };
        let (traj, wall) = reduced_run(sys, initial, steps);
        assert_eq!(traj.step_count(), steps);
        assert_mu_exact(&traj);
        let step_velocity: Vec<f64> = traj
            .states
            .windows(2)
            .map(|pair| 0.5 * m * ((pair[1].x - pair[0].x) / h).norm_squared())
            .collect();
        let mu = initial.mu[0];
        let nodal: Vec<f64> = traj
            .states
            .iter()
            .map(|s| {
                let a = [-0.5 * b0 * s.x[1], 0.5 * b0 * s.x[0], 0.0];
                0.5 * (0..3).map(|i| (s.w[i] - mu * a[i]).powi(2)).sum::<f64>() / m
            })
            .collect();
        let (energy, nodal) = (Summary::of(&step_velocity), Summary::of(&nodal));
        say!(
            out,
            "  h = {:<6} {steps} steps, T = {:.0}: no failed step, {:.2} s ({:.3} us/step), \
             Newton it. mean {:.3}, max residual {:.2e}",
            h,
            traj.times[steps],
            wall.as_secs_f64(),
            1e6 * wall.as_secs_f64() / steps as f64,
            traj.mean_iterations(),
            traj.max_residual()
        );
        say!(out, "  max |mu_k - mu_0|         0 (bit for bit)");
        energy.print(&mut out, "1/2 m |v_k|^2");
        nodal.print(&mut out, "1/2 |w_k - mu A(q_k)|^2/m");
        let c = mu * b0 * h / (2.0 * m);
        let w_xy2 = initial.w[0].powi(2) + initial.w[1].powi(2);
        let predicted = -0.5 * w_xy2 * c * c / ((1.0 + c * c) * m);
        let offset = energy.mean - exact;
        say!(out,
            "  offset from the exact energy: step velocity {offset:.6e} (predicted {predicted:.6e}), \
             nodal momenta {:.3e}",
            nodal.mean - exact
        );
        for (what, s) in [("step-velocity", &energy), ("nodal", &nodal)] {
            assert!(
                s.spread <= 1e-8 * exact && s.drift.abs() <= 1e-8 * exact,
                "h = {h}: the {what} energy is not conserved: spread {:.3e}, drift {:.3e}",
                s.spread,
                s.drift
            );
        }
        assert!(
            (offset - predicted).abs() <= 1e-8 * exact,
            "h = {h}: energy offset {offset:.6e}, predicted {predicted:.6e}"
        );
        assert!(
            (nodal.mean - exact).abs() <= 1e-8 * exact,
            "h = {h}: nodal energy {} against the exact {exact}",
            nodal.mean
        );
        offsets.push(offset);
    }
    let ratio = offsets[0] / offsets[1];
    say!(
        out,
        "  offset(h) / offset(h/2)   {ratio:.4} (h^2 scaling: 4)"
    );
    assert!(
        (3.0..=5.0).contains(&ratio),
        "the energy offset does not shrink like h^2: ratio {ratio}"
    );
    say!(
        out,
        "  test wall time {:.1} s",
        start.elapsed().as_secs_f64()
    );
}
