//! Rotations and directions: systems whose configurations live on `SO(3)` and `S²`, stepped by
//! the Lie group variational integrators that `#[reduced_lagrangian]` derives from `rotation(..)`
//! and `direction(..)` coordinates (`dirac::systems::rotations`).
//!
//! 1. The free rigid body over `--steps` steps (default 10⁶): `‖RᵀR − I‖`, the drift of the
//!    spatial angular momentum `π = R Π` and the energy error, with no projection anywhere.
//! 2. The heavy top (a symmetric top and an asymmetric 3-D pendulum): vertical and axial momenta,
//!    energy.
//! 3. The paper's double spherical pendulum on `S² × S²` from the paper's state over `--steps`
//!    steps (`h = 0.01`): no chart, no switch; `| |n_i| − 1 |`, the energy error; bob 2 at
//!    `T = 1` against the atlas run of the paper's angles at two steps (they approach as `h²`).
//! 4. A satellite with a reaction wheel: a rotation and an ordinary coordinate in one system,
//!    the wheel free and then driven by its motor (a feedback control).
//! 5. Cost: nanoseconds per step, median and range over `--repeats` interleaved repeats of the
//!    rigid body and the heavy top against a hand-written LGVI step for the same discrete
//!    Lagrangian (Newton on the Cayley parameter with the analytic 3 × 3 Jacobian), and of the
//!    double spherical pendulum on `S² × S²` against its atlas run (three charts, §6).
//!
//! Run: `cargo run --release --example rotations [-- --steps 1000000 --repeats 5]`.

use std::hint::black_box;
use std::time::Instant;

use dirac::lie::{cayley, orthogonality_defect};
use dirac::paper::DoubleSphericalPendulum;
use dirac::prelude::*;
use dirac::systems::rotations::{
    DspOnSpheres, HeavyTop, HeavyTopConfig, HeavyTopMomentum, RigidBody, RigidBodyConfig,
    RigidBodyMomentum, Satellite, SatelliteConfig, SatelliteMomentum,
};

#[path = "common/cli.rs"]
mod cli;
#[path = "common/lgvi.rs"]
mod lgvi;
#[path = "common/stats.rs"]
mod stats;
#[path = "common/timing.rs"]
mod timing;

use cli::{at_least, Cli};
use stats::{median, range};
use timing::per_step;

fn rigid_body() -> (RigidBody, LieState<9, 3>) {
    let sys = RigidBody {
        h: 0.01,
        j1: 1.0,
        j2: 2.0,
        j3: 3.0,
    };
    let s0 = sys.state(
        &RigidBodyConfig {
            r: cayley(&Vector3::new(0.2, -0.1, 0.4)),
        },
        &RigidBodyMomentum {
            r: Vector3::new(0.3, 1.0, -0.2),
        },
    );
    (sys, s0)
}

fn heavy_top(j2: f64) -> (HeavyTop, LieState<9, 3>) {
    let sys = HeavyTop {
        h: 0.01,
        j1: 1.0,
        j2,
        j3: 0.4,
        mgl: 2.0,
    };
    let s0 = sys.state(
        &HeavyTopConfig {
            r: cayley(&Vector3::new(0.6, -0.3, 0.2)),
        },
        &HeavyTopMomentum {
            r: Vector3::new(0.5, -0.3, 4.0),
        },
    );
    (sys, s0)
}

/// Nanoseconds per step of the hand-written LGVI (`step` from `(R, Π)` and a guess of `ξ`,
/// counting its Newton corrections into the last argument).
fn per_hand_step(
    steps: usize,
    mut state: (Matrix3<f64>, Vector3<f64>, Vector3<f64>),
    iterations: &mut usize,
    step: impl Fn(
        &Matrix3<f64>,
        &Vector3<f64>,
        Vector3<f64>,
        &mut usize,
    ) -> (Matrix3<f64>, Vector3<f64>, Vector3<f64>),
) -> f64 {
    let began = Instant::now();
    // Newton starts from the linear extrapolation of the last two Cayley parameters, as the
    // generated step's guess does.
    let mut before = state.2;
    for _ in 0..steps {
        let last = state.2;
        state = step(&state.0, &state.1, 2.0 * last - before, iterations);
        before = last;
    }
    black_box(&state);
    began.elapsed().as_secs_f64() * 1e9 / steps as f64
}

/// Nanoseconds per step of a collected run, and its mean Newton corrections per step.
fn per_step_iterations(
    integ: &LieIntegrator<impl LieLagrangian<9, 3>, 9, 3>,
    start: LieState<9, 3>,
    steps: usize,
) -> (f64, f64) {
    let began = Instant::now();
    let traj = integ
        .run(start)
        .steps(steps)
        .collect()
        .expect("the run succeeds");
    let ns = began.elapsed().as_secs_f64() * 1e9 / steps as f64;
    (ns, traj.mean_iterations())
}

fn report(what: &str, ours: Vec<f64>, theirs: Vec<f64>, baseline: &str) {
    let ratios: Vec<f64> = ours.iter().zip(&theirs).map(|(a, b)| a / b).collect();
    let (lo, hi) = range(&ratios);
    println!(
        "   {what:<34} {:>8.1} ns  {baseline} {:>8.1} ns  ratio {:.2} (range {lo:.2}–{hi:.2})",
        median(ours),
        median(theirs),
        median(ratios.clone()),
    );
}

fn main() {
    let mut cli = Cli::new(
        "rotations",
        "rigid bodies, tops and pendula on SO(3) and S², stepped by Lie group variational integrators",
    );
    let steps: usize = cli.value(
        "--steps",
        "S",
        "steps of the long runs",
        1_000_000,
        at_least(1),
    );
    let repeats: usize = cli.value(
        "--repeats",
        "R",
        "interleaved repeats of each timing",
        3,
        at_least(1),
    );
    let timed: usize = cli.value(
        "--timed-steps",
        "T",
        "steps of each timed run",
        200_000,
        at_least(1),
    );
    cli.finish();
    let options = NewtonOptions::default();

    println!("1. Free rigid body, J = diag(1, 2, 3), h = 0.01, {steps} steps:");
    let (sys, s0) = rigid_body();
    let integ = LieIntegrator::new(sys, options);
    let (pi0, e0) = (integ.spatial_momentum(&s0), sys.energy(&s0));
    let (mut orth, mut drift, mut energy): (f64, f64, f64) = (0.0, 0.0, 0.0);
    integ
        .run(s0)
        .steps(steps)
        .observe(|_, _, s: &LieState<9, 3>, _| {
            orth = orth.max(orthogonality_defect(&sys.config(s).r));
            drift = drift.max((integ.spatial_momentum(s) - pi0).norm());
            energy = energy.max((sys.energy(s) - e0).abs());
        })
        .stream()
        .expect("the rigid body integrates");
    println!("   generated:         max |RᵀR − I| = {orth:.2e}, max |π_k − π_0| / |π_0| = {:.2e}, max |E_k − E_0| / E_0 = {:.2e}", drift / pi0.norm(), energy / e0);
    // The hand-written LGVI over the same steps: the round-off of products of rotations.
    let jd = lgvi::nonstandard(&Vector3::new(sys.j1, sys.j2, sys.j3));
    let (mut r, mut pi, mut xi) = (sys.config(&s0).r, sys.momenta(&s0).r, Vector3::zeros());
    let (mut orth, mut drift) = (0.0_f64, 0.0_f64);
    for _ in 0..steps {
        (r, pi, xi) = lgvi::rigid_body_step(&jd, sys.h, &r, &pi, xi, 1e-16, &mut 0);
        orth = orth.max(orthogonality_defect(&r));
        drift = drift.max((r * pi - pi0).norm());
    }
    println!(
        "   hand-written LGVI: max |RᵀR − I| = {orth:.2e}, max |π_k − π_0| / |π_0| = {:.2e}",
        drift / pi0.norm()
    );

    println!("2. Heavy top, h = 0.01, {steps} steps (vertical π_z, axial Π_3, energy):");
    for (name, j2) in [
        ("Lagrange top (j1 = j2)", 1.0),
        ("3-D pendulum (j1 ≠ j2)", 1.5),
    ] {
        let (sys, s0) = heavy_top(j2);
        let integ = LieIntegrator::new(sys, options);
        let (v0, a0, e0) = (integ.spatial_momentum(&s0).z, s0.p[2], sys.energy(&s0));
        let (mut v, mut a, mut e): (f64, f64, f64) = (0.0, 0.0, 0.0);
        integ
            .run(s0)
            .steps(steps)
            .observe(|_, _, s: &LieState<9, 3>, _| {
                v = v.max((integ.spatial_momentum(s).z - v0).abs());
                a = a.max((s.p[2] - a0).abs());
                e = e.max((sys.energy(s) - e0).abs());
            })
            .stream()
            .expect("the heavy top integrates");
        println!(
            "   {name:<24} |Δπ_z| = {v:.2e}  |ΔΠ_3| = {a:.2e}{}  max |ΔE|/|E| = {:.2e}",
            if j2 == 1.0 { "" } else { " (not conserved)" },
            e / e0.abs()
        );
    }

    println!(
        "3. Double spherical pendulum on S² × S², the paper's state, h = 0.01, {steps} steps:"
    );
    let sys = DspOnSpheres::paper(0.01);
    let s0 = sys.paper_initial_state();
    let integ = LieIntegrator::new(sys, options);
    let e0 = sys.energy(&s0);
    let (mut unit, mut energy): (f64, f64) = (0.0, 0.0);
    let began = Instant::now();
    let summary = integ
        .run(s0)
        .steps(steps)
        .observe(|_, _, s: &LieState<18, 4>, _| {
            let q = sys.config(s);
            unit = unit
                .max((q.n1.norm() - 1.0).abs())
                .max((q.n2.norm() - 1.0).abs());
            energy = energy.max((sys.energy(s) - e0).abs());
        })
        .stream()
        .expect("the double spherical pendulum integrates on S² × S²");
    println!(
        "   {} steps in {:.2} s, no failed step; max | |n_i| − 1 | = {unit:.2e}; max |E_k − E_0| / |E_0| = {:.2e}",
        summary.step_count,
        began.elapsed().as_secs_f64(),
        energy / e0.abs()
    );

    // Against the atlas run of the paper's angles (a different discretization of the same
    // motion): bob 2 at T = 1 for two steps; the two approach each other as h².
    let bob2_at_one = |h: f64| {
        let n = (1.0 / h).round() as usize;
        let sys = DspOnSpheres::paper(h);
        let last = *LieIntegrator::new(sys, options)
            .run(sys.paper_initial_state())
            .steps(n)
            .collect()
            .expect("the double spherical pendulum integrates")
            .last();
        let paper = DoubleSphericalPendulum {
            h,
            ..DoubleSphericalPendulum::paper()
        };
        let atlas = paper
            .atlas(options)
            .run((
                dirac::paper::atlas::PAPER,
                DoubleSphericalPendulum::paper_initial_state(),
            ))
            .steps(n)
            .collect()
            .expect("the atlas integrates");
        let (chart, state) = atlas.last();
        let r2 = paper.charts().bob_positions(chart, state).1;
        (sys.bobs(&last).1 - Vector3::from(r2)).norm()
    };
    let (coarse, fine) = (bob2_at_one(0.01), bob2_at_one(0.005));
    println!(
        "   bob 2 at T = 1 against the atlas run: {coarse:.3e} (h = 0.01), {fine:.3e} (h = 0.005), ratio {:.2}",
        coarse / fine
    );

    println!("4. Satellite with a reaction wheel (a rotation and the wheel angle), {steps} steps:");
    let sys = Satellite {
        h: 0.01,
        j1: 2.0,
        j2: 3.0,
        j3: 4.0,
        jw: 0.5,
        u: 0.0,
    };
    let s0 = sys.state(
        &SatelliteConfig {
            r: cayley(&Vector3::new(0.1, 0.2, -0.3)),
            phi: 0.0,
        },
        &SatelliteMomentum {
            r: Vector3::new(0.4, -0.2, 1.0),
            phi: 0.7,
        },
    );
    let integ = LieIntegrator::new(sys, options);
    let pi0 = integ.spatial_momentum(&s0);
    let (mut wheel, mut spatial): (f64, f64) = (0.0, 0.0);
    integ
        .run(s0)
        .steps(steps)
        .observe(|_, _, s: &LieState<10, 4>, _| {
            wheel = wheel.max((sys.momenta(s).phi - 0.7).abs());
            spatial = spatial.max((integ.spatial_momentum(s) - pi0).norm());
        })
        .stream()
        .expect("the satellite integrates");
    println!(
        "   wheel free:   |Δp_wheel| = {wheel:.2e}, |Δπ| / |π| = {:.2e}",
        spatial / pi0.norm()
    );
    // The motor spins the wheel up to p_φ = 2 by the feedback u = 5 (2 − p_φ): the body turns
    // the other way, and the satellite's angular momentum in space does not change.
    let (mut spatial, mut last_wheel) = (0.0_f64, 0.0);
    let driven = steps.min(100_000);
    integ
        .run(s0)
        .steps(driven)
        .feedback(|_, _, s: &LieState<10, 4>, u: &mut [f64]| u[0] = 5.0 * (2.0 - s.p[3]))
        .observe(|_, _, s: &LieState<10, 4>, _| {
            spatial = spatial.max((integ.spatial_momentum(s) - pi0).norm());
            last_wheel = s.p[3];
        })
        .stream()
        .expect("the driven satellite integrates");
    println!(
        "   wheel driven: p_wheel 0.7 → {last_wheel:.6} over {driven} steps, |Δπ| / |π| = {:.2e}",
        spatial / pi0.norm()
    );

    println!(
        "5. Cost per step ({timed} steps, median over {repeats} interleaved repeats, ratio range):"
    );
    let (rb, rb0) = rigid_body();
    let rb_integ = LieIntegrator::new(rb, options);
    let rb_jd = lgvi::nonstandard(&Vector3::new(rb.j1, rb.j2, rb.j3));
    let rb_hand0 = (rb.config(&rb0).r, rb.momenta(&rb0).r, Vector3::zeros());
    let (top, top0) = heavy_top(1.5);
    let top_integ = LieIntegrator::new(top, options);
    let top_jd = lgvi::nonstandard(&Vector3::new(top.j1, top.j2, top.j3));
    let top_hand0 = (top.config(&top0).r, top.momenta(&top0).r, Vector3::zeros());
    let sphere = DspOnSpheres::paper(0.01);
    let sphere_integ = LieIntegrator::new(sphere, options);
    let sphere0 = sphere.paper_initial_state();
    let atlas = DoubleSphericalPendulum::paper().atlas(options);
    let atlas0 = (
        dirac::paper::atlas::PAPER,
        DoubleSphericalPendulum::paper_initial_state(),
    );
    // The hand-written steps stop at the residual the generated ones accept.
    let tol = |h: f64, pi: &Vector3<f64>| h * options.residual_tolerance(pi.amax());
    let mut t: [(Vec<f64>, Vec<f64>); 3] = Default::default();
    let (mut hand_iterations, mut rb_iterations, mut top_iterations) = ([0usize; 2], 0.0, 0.0);
    for _ in 0..repeats {
        t[0].0.push(per_step(&rb_integ, rb0, timed));
        t[0].1.push(per_hand_step(
            timed,
            rb_hand0,
            &mut hand_iterations[0],
            |r, pi, xi, n| lgvi::rigid_body_step(&rb_jd, rb.h, r, pi, xi, tol(rb.h, pi), n),
        ));
        t[1].0.push(per_step(&top_integ, top0, timed));
        t[1].1.push(per_hand_step(
            timed,
            top_hand0,
            &mut hand_iterations[1],
            |r, pi, xi, n| {
                lgvi::heavy_top_step(&top_jd, top.h, top.mgl, r, pi, xi, tol(top.h, pi), n)
            },
        ));
        t[2].0.push(per_step(&sphere_integ, sphere0, timed));
        t[2].1.push(per_step(&atlas, atlas0, timed));
    }
    rb_iterations += per_step_iterations(&rb_integ, rb0, timed).1;
    top_iterations += per_step_iterations(&top_integ, top0, timed).1;
    let [rb_t, top_t, dsp_t] = t;
    report("free rigid body", rb_t.0, rb_t.1, "hand-written LGVI");
    report(
        "heavy top (3-D pendulum)",
        top_t.0,
        top_t.1,
        "hand-written LGVI",
    );
    report(
        "double spherical pendulum, S² × S²",
        dsp_t.0,
        dsp_t.1,
        "atlas (3 charts)",
    );
    let per = |n: usize| n as f64 / (repeats * timed) as f64;
    println!(
        "   Newton corrections per step: rigid body {rb_iterations:.2} generated, {:.2} hand-written; heavy top {top_iterations:.2}, {:.2}",
        per(hand_iterations[0]),
        per(hand_iterations[1])
    );
}
