//! The paper's §7.2 run of the double spherical pendulum: the Lagrangian against an independent
//! evaluation, exact conservation of μ, no energy drift, and the cost of the run.

use std::f64::consts::PI;

use dirac::paper::{DoubleSphericalPendulum, DSP_STEPS, DSP_T};
use dirac::prelude::*;
use dirac::runtime::system::join;

fn paper_run() -> Trajectory<3, 1> {
    let integ = ReducedIntegrator::plus(DoubleSphericalPendulum::paper(), NewtonOptions::default());
    integ
        .run(DoubleSphericalPendulum::paper_initial_state())
        .steps(DSP_STEPS)
        .collect()
        .expect("the paper's run succeeds")
}

fn config(s: &ReducedState<3, 1>) -> SVector<f64, 4> {
    join::<3, 1, 4>(&s.x, &s.g)
}

/// A small deterministic generator (64-bit LCG, top bits), uniform in `[lo, hi)`.
struct Lcg(u64);

impl Lcg {
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        lo + (hi - lo) * (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The kinetic and potential energies at `(q, v)` from the Cartesian bob positions alone:
/// `ṙ_i = d/dt r_i(q + t v)` at `t = 0` by a central difference, `V = g (m1 z1 + m2 z2)`.
fn independent_energies(
    sys: &DoubleSphericalPendulum,
    q: &SVector<f64, 4>,
    v: &SVector<f64, 4>,
) -> (f64, f64) {
    let eps = 1e-5;
    let (a1, a2) = sys.bob_positions(&(q + eps * v));
    let (b1, b2) = sys.bob_positions(&(q - eps * v));
    let speed2 = |a: [f64; 3], b: [f64; 3]| {
        (0..3)
            .map(|i| ((a[i] - b[i]) / (2.0 * eps)).powi(2))
            .sum::<f64>()
    };
    let kinetic = 0.5 * sys.m1 * speed2(a1, b1) + 0.5 * sys.m2 * speed2(a2, b2);
    let (r1, r2) = sys.bob_positions(q);
    (kinetic, sys.g * (sys.m1 * r1[2] + sys.m2 * r2[2]))
}

/// `L_d(q0, q1) = h L((q0 + q1)/2, (q1 − q0)/h)` with `L = T − V` evaluated independently of the
/// macro's formula, and `physical_energy` is `T + V` there.
#[test]
fn lagrangian_matches_an_independent_evaluation() {
    let sys = DoubleSphericalPendulum::paper();
    let mut rng = Lcg(0x2545_f491_4f6c_dd1d);
    for _ in 0..200 {
        let q0 = SVector::<f64, 4>::from_fn(|_, _| rng.uniform(-2.0 * PI, 2.0 * PI));
        // Angular velocities up to 0.5 rad/s: bob speeds up to ~10³, T comparable to V.
        let v = SVector::<f64, 4>::from_fn(|_, _| rng.uniform(-0.5, 0.5));
        let q1 = q0 + sys.h * v;
        let mid = 0.5 * (q0 + q1);
        let (kinetic, potential) = independent_energies(&sys, &mid, &v);
        let expected = sys.h * (kinetic - potential);
        let scale = sys.h * (kinetic + potential.abs());
        let got = sys.lagrangian(&q0, &q1);
        assert!(
            (got - expected).abs() <= 1e-8 * scale,
            "L_d at q0 = {q0:?}, v = {v:?}: {got} vs {expected}"
        );
        let energy = sys.physical_energy(&q0, &q1);
        assert!(
            (energy - (kinetic + potential)).abs() <= 1e-8 * (kinetic + potential.abs()),
            "T + V at q0 = {q0:?}, v = {v:?}: {energy} vs {}",
            kinetic + potential
        );
    }
}

/// The paper's initial state is the one printed in §7.2.2.
#[test]
fn paper_parameters_and_initial_state() {
    let sys = DoubleSphericalPendulum::paper();
    assert_eq!(sys.h, DSP_T / DSP_STEPS as f64);
    assert_eq!(
        (sys.m1, sys.m2, sys.l1, sys.l2, sys.g),
        (20.0, 35.0, 500.0, 800.0, 9.8)
    );
    let s = DoubleSphericalPendulum::paper_initial_state();
    // q0 = (ϑ1, φ1, ϑ2, φ2) = (0, 9/4, 2, 3), (μ0, w0) = (0, 0, 1, 1).
    assert_eq!(config(&s).as_slice(), &[2.25, 2.0, 3.0, 0.0]);
    assert_eq!((s.w.as_slice(), s.mu[0]), (&[0.0, 1.0, 1.0][..], 0.0));
}

/// One run of the paper's whole case (under half a second in a debug build) checks μ, the
/// energy and the Newton cost.
#[test]
fn paper_run_conserves_mu_and_energy() {
    let sys = DoubleSphericalPendulum::paper();
    let traj = paper_run();
    assert_eq!(traj.step_count(), DSP_STEPS);

    // μ_{k+1} = μ_k is one of the equations (4.6): it holds bit for bit.
    let mu0 = traj.states[0].mu[0];
    assert!(traj
        .states
        .iter()
        .all(|s| s.mu[0].to_bits() == mu0.to_bits()));

    let mean_iterations = traj.mean_iterations();
    assert!(
        mean_iterations <= 4.0,
        "mean Newton iterations {mean_iterations}"
    );

    // No drift: the mean over the last 10% of the run minus the mean over the first 10% is
    // below a tenth of the spread. The test is on the physical energy T + V: the paper's
    // (E_d)_k = L_d(q_k, q_{k+1}) is h (T − V), which swings with the pendulum (period ~15 s,
    // against 10 s windows) and fails this criterion without any drift (about 0.22 × spread).
    let energy: Vec<f64> = traj
        .states
        .windows(2)
        .map(|p| sys.physical_energy(&config(&p[0]), &config(&p[1])))
        .collect();
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let tenth = energy.len() / 10;
    let drift = mean(&energy[energy.len() - tenth..]) - mean(&energy[..tenth]);
    let (min, max) = energy
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &e| {
            (lo.min(e), hi.max(e))
        });
    assert!(
        drift.abs() < 0.1 * (max - min),
        "drift {drift}, spread {}",
        max - min
    );
    // And against the energy itself: the level moves by ~1e-5 (at the passages near the pole).
    assert!(drift.abs() < 1e-4 * energy[0].abs(), "drift {drift}");

    // The discrete energy oscillates in a fixed band: the second half stays within the range
    // of the first half, widened by a tenth of its width.
    let ed = dirac::trajectory_energies(&sys, &traj);
    let band = |v: &[f64]| {
        v.iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &e| {
                (lo.min(e), hi.max(e))
            })
    };
    let (lo, hi) = band(&ed[..ed.len() / 2]);
    let (lo2, hi2) = band(&ed[ed.len() / 2..]);
    let slack = 0.1 * (hi - lo);
    assert!(
        lo2 >= lo - slack && hi2 <= hi + slack,
        "E_d: first half [{lo}, {hi}], second half [{lo2}, {hi2}]"
    );
}
