//! Reduction by rotations: the reduced integrators `#[reduced_lagrangian]` derives from a
//! declared rotation symmetry (`symmetry(R)`, `symmetry(n1, n2, axis = z)`), against the
//! unreduced Lie group steps of the same discrete Lagrangians (`dirac::systems::rotations`).
//!
//! 1. The free rigid body reduced by every rotation (the discrete Euler–Poincaré equations on
//!    `so(3)*`, the attitude reconstructed) over `--steps` steps (default 10⁶): the spatial
//!    momentum `π_k = R_k Π_k`, the orbit `|Π_k|`, `‖RᵀR − I‖` and the energy, beside the
//!    unreduced run's; the two runs after 10³ steps.
//! 2. A satellite with a reaction wheel reduced by every rotation (the discrete
//!    Lagrange–Poincaré equations in `(Π, φ, p_φ)`), the wheel driven by its motor: `π` and the
//!    reduced run against the unreduced one.
//! 3. The heavy top reduced by the rotations about the vertical: `μ = e3 · π` bit for bit over
//!    `--steps` steps, the energy.
//! 4. The paper's double spherical pendulum on `S² × S²` reduced by the rotations about the
//!    vertical, from the paper's state over the paper's run (`T = 100`, `h = 0.01`, the setting
//!    of its Figures 3 and 4): `μ` bit for bit, the discrete generalized energy
//!    `(E_d)_k = L_d(q_k, q_{k+1})` (Figure 4, top) and its difference from the unreduced run's
//!    (Figure 4, bottom), bob 2 at `T = 1` against the atlas run of the paper's angles at two
//!    steps (they approach as `h²`).
//! 5. Cost: nanoseconds per step, median and range over `--repeats` interleaved repeats, of each
//!    reduced integrator against the unreduced step of the same system.
//!
//! Run: `cargo run --release --example rotation_reduction [-- --steps 1000000 --repeats 5]`.

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

fn heavy_top() -> (HeavyTop, LieState<9, 3>) {
    let sys = HeavyTop {
        h: 0.01,
        j1: 1.0,
        j2: 1.5,
        j3: 0.4,
        mgl: 2.0,
    };
    let s0 = sys.state(
        &HeavyTopConfig {
            r: cayley(&Vector3::new(0.6, 0.1, 0.0)),
        },
        &HeavyTopMomentum {
            r: Vector3::new(0.1, 0.3, 4.0),
        },
    );
    (sys, s0)
}

fn satellite() -> (Satellite, LieState<10, 4>) {
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
    (sys, s0)
}

/// The largest difference between two runs' states (the momenta relative to their size).
fn gap<const P: usize, const N: usize>(a: &[LieState<P, N>], b: &[ReducedLieState<P, N>]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(a, b)| {
            let scale = a.p.amax().max(1.0);
            (a.q - b.q).amax().max((a.p - b.p).amax() / scale)
        })
        .fold(0.0, f64::max)
}

fn report(what: &str, ours: Vec<f64>, theirs: Vec<f64>) {
    let ratios: Vec<f64> = ours.iter().zip(&theirs).map(|(a, b)| a / b).collect();
    let (lo, hi) = range(&ratios);
    println!(
        "   {what:<40} reduced {:>7.1} ns  unreduced {:>7.1} ns  ratio {:.2} (range {lo:.2}–{hi:.2})",
        median(ours),
        median(theirs),
        median(ratios.clone()),
    );
}

fn main() {
    let mut cli = Cli::new(
        "rotation_reduction",
        "rigid bodies, a satellite, a top and the paper's pendulum reduced by rotations",
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

    println!("1. Free rigid body reduced by SO(3), J = diag(1, 2, 3), h = 0.01, {steps} steps:");
    let (sys, s0) = rigid_body();
    let reduced = ReducedLieIntegrator::new(sys, options);
    let unreduced = LieIntegrator::new(sys, options);
    let r0 = reduced.reduce(&s0);
    let (pi0, e0) = (r0.mu, sys.energy(&s0));
    let (mut drift, mut orbit, mut orth, mut energy): (f64, f64, f64, f64) = (0.0, 0.0, 0.0, 0.0);
    let began = Instant::now();
    reduced
        .run(r0)
        .steps(steps)
        .observe(|_, _, s: &ReducedLieState<9, 3>, _| {
            let s = s.unreduced();
            drift = drift.max((reduced.momentum_map(&s).expect("a finite state") - pi0).norm());
            orbit = orbit.max((s.p.norm() - pi0.norm()).abs());
            orth = orth.max(orthogonality_defect(&sys.config(&s).r));
            energy = energy.max((sys.energy(&s) - e0).abs());
        })
        .stream()
        .expect("the reduced rigid body integrates");
    let seconds = began.elapsed().as_secs_f64();
    println!(
        "   reduced:   max |π_k − π_0| / |π_0| = {:.2e}, max ||Π_k| − |π|| / |π| = {:.2e}, max |RᵀR − I| = {orth:.2e}, max |E_k − E_0| / E_0 = {:.2e} ({seconds:.2} s)",
        drift / pi0.norm(),
        orbit / pi0.norm(),
        energy / e0
    );
    let (mut drift, mut orbit, mut orth): (f64, f64, f64) = (0.0, 0.0, 0.0);
    unreduced
        .run(s0)
        .steps(steps)
        .observe(|_, _, s: &LieState<9, 3>, _| {
            drift = drift.max((unreduced.spatial_momentum(s) - pi0).norm());
            orbit = orbit.max((s.p.norm() - pi0.norm()).abs());
            orth = orth.max(orthogonality_defect(&sys.config(s).r));
        })
        .stream()
        .expect("the rigid body integrates");
    println!(
        "   unreduced: max |π_k − π_0| / |π_0| = {:.2e}, max ||Π_k| − |π|| / |π| = {:.2e}, max |RᵀR − I| = {orth:.2e}",
        drift / pi0.norm(),
        orbit / pi0.norm()
    );
    let a = unreduced.run(s0).steps(1000).collect().expect("runs");
    let b = reduced.run(r0).steps(1000).collect().expect("runs");
    println!(
        "   reduced (reconstructed) against unreduced over 10³ steps: {:.2e}",
        gap(&a.states, &b.states)
    );

    let driven = steps.min(100_000);
    println!("2. Satellite with a reaction wheel reduced by SO(3), wheel driven, {driven} steps:");
    let (sat, sat0) = satellite();
    let reduced = ReducedLieIntegrator::new(sat, options);
    let unreduced = LieIntegrator::new(sat, options);
    let torque = |t: f64, p_phi: f64| 0.5 * (0.3 * t).sin() - 0.1 * p_phi;
    let a = unreduced
        .run(sat0)
        .steps(driven)
        .feedback(|_, t, s: &LieState<10, 4>, u: &mut [f64]| u[0] = torque(t, s.p[3]))
        .collect()
        .expect("the satellite integrates");
    let b = reduced
        .run(reduced.reduce(&sat0))
        .steps(driven)
        .feedback(|_, t, s: &ReducedLieState<10, 4>, u: &mut [f64]| u[0] = torque(t, s.p[3]))
        .collect()
        .expect("the reduced satellite integrates");
    let pi0 = b.states[0].mu;
    let spatial = b
        .states
        .iter()
        .map(|s| {
            (reduced
                .momentum_map(&s.unreduced())
                .expect("a finite state")
                - pi0)
                .norm()
        })
        .fold(0.0, f64::max);
    let wheel = b.states.iter().map(|s| s.p[3]).fold(f64::NAN, f64::max);
    println!(
        "   max |π_k − π_0| / |π_0| = {:.2e} (the motor is internal), wheel momentum up to {wheel:.3}; reduced against unreduced over 10³ steps: {:.2e}",
        spatial / pi0.norm(),
        gap(&a.states[..=1000], &b.states[..=1000])
    );

    println!("3. Heavy top reduced by the rotations about the vertical, h = 0.01, {steps} steps:");
    let (top, top0) = heavy_top();
    let reduced = ReducedLieIntegrator::new(top, options);
    let t0 = reduced.reduce(&top0);
    let e0 = top.energy(&top0);
    let (mut changed, mut off, mut energy) = (0usize, 0.0_f64, 0.0_f64);
    reduced
        .run(t0)
        .steps(steps)
        .observe(|_, _, s: &ReducedLieState<9, 3>, _| {
            changed += usize::from(s.mu != t0.mu);
            off = off.max(
                (reduced
                    .momentum_map(&s.unreduced())
                    .expect("a finite state")
                    .z
                    - t0.mu.z)
                    .abs(),
            );
            energy = energy.max((top.energy(&s.unreduced()) - e0).abs());
        })
        .stream()
        .expect("the reduced heavy top integrates");
    println!(
        "   μ = {:.6}: steps where it changed {changed}; max |e3·π_k − μ| = {off:.2e}; max |E_k − E_0| / E_0 = {:.2e}",
        t0.mu.z,
        energy / e0.abs()
    );

    let paper_steps = 10_000;
    println!(
        "4. Double spherical pendulum on S² × S² reduced about the vertical, the paper's run (h = 0.01, {paper_steps} steps, T = 100):"
    );
    let dsp = DspOnSpheres::paper(0.01);
    let dsp0 = dsp.paper_initial_state();
    let reduced = ReducedLieIntegrator::new(dsp, options);
    let unreduced = LieIntegrator::new(dsp, options);
    let a = unreduced
        .run(dsp0)
        .steps(paper_steps)
        .collect()
        .expect("the pendulum integrates");
    let b = reduced
        .run(reduced.reduce(&dsp0))
        .steps(paper_steps)
        .collect()
        .expect("the reduced pendulum integrates");
    let mu0 = b.states[0].mu;
    let moved = b.states.iter().filter(|s| s.mu != mu0).count();
    let (ea, eb) = (
        unreduced.discrete_energies(&a),
        reduced.discrete_energies(&b),
    );
    let (lo, hi) = range(&eb);
    let mean = eb.iter().sum::<f64>() / eb.len() as f64;
    let (first, last) = (&eb[..eb.len() / 10], &eb[eb.len() - eb.len() / 10..]);
    let mean_of = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let difference = ea
        .iter()
        .zip(&eb)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    println!(
        "   μ = {:.6e}: steps where it changed {moved}; (E_d)_k in [{lo:.6e}, {hi:.6e}] (spread {:.2e} of its mean), mean of the first and last tenth {:.6e}, {:.6e}",
        mu0.z,
        (hi - lo) / mean.abs(),
        mean_of(first),
        mean_of(last)
    );
    let e0 = dsp.energy(&dsp0);
    let physical = b
        .states
        .iter()
        .map(|s| (dsp.energy(&s.unreduced()) - e0).abs())
        .fold(0.0, f64::max);
    println!(
        "   max |(E_d)_k reduced − unreduced| = {difference:.2e} ({:.2e} of its size); max Dirac residual {:.2e}; energy max |E_k − E_0| / |E_0| = {:.2e}",
        difference / mean.abs(),
        reduced.dirac_residuals(&b).into_iter().fold(0.0, f64::max),
        physical / e0.abs()
    );
    let bob2_at_one = |h: f64| {
        let n = (1.0 / h).round() as usize;
        let sys = DspOnSpheres::paper(h);
        let integ = ReducedLieIntegrator::new(sys, options);
        let last = *integ
            .run(integ.reduce(&sys.paper_initial_state()))
            .steps(n)
            .collect()
            .expect("the reduced pendulum integrates")
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
        (sys.bobs(&last.unreduced()).1 - Vector3::from(r2)).norm()
    };
    let (coarse, fine) = (bob2_at_one(0.01), bob2_at_one(0.005));
    println!(
        "   bob 2 at T = 1 against the atlas run: {coarse:.3e} (h = 0.01), {fine:.3e} (h = 0.005), ratio {:.2}",
        coarse / fine
    );

    println!(
        "5. Cost per step ({timed} steps, median over {repeats} interleaved repeats, ratio range):"
    );
    let (rb, rb0) = rigid_body();
    let (rb_red, rb_unred) = (
        ReducedLieIntegrator::new(rb, options),
        LieIntegrator::new(rb, options),
    );
    let rb_r0 = rb_red.reduce(&rb0);
    let (top_red, top_unred) = (
        ReducedLieIntegrator::new(top, options),
        LieIntegrator::new(top, options),
    );
    let top_r0 = top_red.reduce(&top0);
    let (sat_red, sat_unred) = (
        ReducedLieIntegrator::new(sat, options),
        LieIntegrator::new(sat, options),
    );
    let sat_r0 = sat_red.reduce(&sat0);
    let (dsp_red, dsp_unred) = (
        ReducedLieIntegrator::new(dsp, options),
        LieIntegrator::new(dsp, options),
    );
    let dsp_r0 = dsp_red.reduce(&dsp0);
    let mut t: [(Vec<f64>, Vec<f64>); 4] = Default::default();
    for _ in 0..repeats {
        t[0].0.push(per_step(&rb_red, rb_r0, timed));
        t[0].1.push(per_step(&rb_unred, rb0, timed));
        t[1].0.push(per_step(&sat_red, sat_r0, timed));
        t[1].1.push(per_step(&sat_unred, sat0, timed));
        t[2].0.push(per_step(&top_red, top_r0, timed));
        t[2].1.push(per_step(&top_unred, top0, timed));
        t[3].0.push(per_step(&dsp_red, dsp_r0, timed));
        t[3].1.push(per_step(&dsp_unred, dsp0, timed));
    }
    let [rb_t, sat_t, top_t, dsp_t] = t;
    report("free rigid body, by SO(3)", rb_t.0, rb_t.1);
    report("satellite with a wheel, by SO(3)", sat_t.0, sat_t.1);
    report("heavy top, about the vertical", top_t.0, top_t.1);
    report("pendulum on S² × S², about the vertical", dsp_t.0, dsp_t.1);
}
