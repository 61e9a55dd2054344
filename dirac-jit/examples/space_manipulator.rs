//! A free-floating space manipulator: the satellite of `examples/data/space_manipulator.urdf`
//! (a 500 kg base with a 6-DoF revolute arm, illustrative numbers), out of gravity, its joints
//! moved to new angles by a PD law on the joint torques while the base turns and translates in
//! reaction. The model's system text puts the base's pose on `SE(3)` beside the six joint
//! angles (`rule = trapezoid`), compiled at run time; the torques are controls. A rigid motion
//! of the whole system leaves the discrete Lagrangian unchanged and the joint torques are
//! internal, so the discrete Noether theorem keeps the total linear and angular momentum to
//! round-off however hard the arm works.
//!
//! ```text
//! cargo run --release --manifest-path dirac-io/Cargo.toml --target-dir target -p dirac-jit \
//!     --example space_manipulator -- [--steps 100000]
//! ```
//!
//! It prints the compile time, the largest relative drift of the total linear and angular
//! momentum over the run (the integrator's momentum map at every node, and `dirac-multibody`'s
//! `Model::momentum` at every hundredth node, its velocity from the node's momenta through the
//! mass matrix), the largest orthonormality defect `‖RᵀR − I‖` (Frobenius) of the base's
//! attitude, the joints' distance from their targets at the end, the angle the base turned
//! through and how far it moved, the time per step and Newton's iterations. It exits with
//! status 1 if the momentum drifts by more than `1e-13 + 2e-17 n + 2e-22 n²` relative over
//! `n` steps (integrator; `1e-12 + 4e-17 n + 2e-22 n²` for the model, whose own evaluation
//! adds round-off), the attitude's defect exceeds `1e-13 + 2e-16 n`, a joint ends more than
//! `1e-3` rad from its target (after a run of at least 20 s), or the base did not turn. The
//! attitude is brought back onto SO(3) after every step (one Newton–Schulz step), so its
//! defect stays at round-off. The momentum bounds grow with `n`: the angular momentum about
//! the origin is `π = R Π + x × p` with the base drifting away (23 m over 10⁶ steps), and
//! the round-off of `x × p`, about `ε |x| |p|` a step, is large against `|π|` (it prints
//! both): a random walk of it over the run (measured: `6.4e-13` over 10⁵ steps, `9.1e-11`
//! over 10⁶).
//!
//! Then it runs the same motion reduced by the rigid motions of the whole tree (the model's
//! text declares `symmetry(<base>)` out of gravity; `ReducedLieIntegrator`), whose total
//! momentum is the run's parameter: it prints the reduced run's drift, attitude defect and how
//! far its joints end from the unreduced run's, and exits with status 1 unless the linear
//! momentum is kept bit for bit and the angular momentum to `1e-13` relative (measured:
//! `1.2e-16` over 10⁵ and over 10⁶ steps).
//!
//! Default: 10⁵ steps of `h` = 1 ms (100 s; the PD law settles in about 15 s).

use std::time::Instant;

use dirac_jit::{compile_model, Compiled, Dense, JitLie, Reduced};
use dirac_multibody::nalgebra::{DVector, Matrix3, Vector3};
use dirac_multibody::{Configuration, Model, TextOptions};
use dirac_runtime::prelude::*;

/// Joints of the arm.
#[path = "common/floating.rs"]
mod floating;
use floating::{base_pose, configuration, pose_numbers, slices, state_parts};

const J: usize = 6;
/// A state's stored point: the base's pose (12 numbers) and the joint angles.
const P: usize = 12 + J;
/// Its momenta: the base's `(Π, p)` and the joints'.
const N: usize = 6 + J;
/// The time step, s.
const H: f64 = 1e-3;

fn steps() -> usize {
    let mut steps = 100_000;
    let mut it = std::env::args().skip(1);
    while let Some(a) = it.next() {
        match a.as_str() {
            "--steps" => {
                steps = it
                    .next()
                    .and_then(|s| s.parse().ok())
                    .expect("--steps takes a number")
            }
            other => panic!("unknown argument {other}"),
        }
    }
    steps
}

/// The model's velocity at a state: `M(q) v = p` for the state's momenta in the model's
/// coordinates (the base's `Π`, its body linear momentum `Rᵀ p`, the joints'), the inverse
/// Legendre map at the node.
fn velocity(model: &Model, config: &Configuration, q: &[f64], p: &[f64]) -> Vec<f64> {
    let (r, _) = base_pose(q);
    let linear = r.transpose() * Vector3::new(p[3], p[4], p[5]);
    let mut momenta = p.to_vec();
    momenta[3..6].copy_from_slice(linear.as_slice());
    let m = model
        .mass_matrix(config)
        .expect("a configuration of the model");
    m.lu()
        .solve(&DVector::from_vec(momenta))
        .expect("a regular mass matrix")
        .as_slice()
        .to_vec()
}

/// The angle of the rotation `R`, from `tr R = 1 + 2 cos θ`.
fn angle(r: &Matrix3<f64>) -> f64 {
    ((r.trace() - 1.0) / 2.0).clamp(-1.0, 1.0).acos()
}

fn main() {
    let steps = steps();
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../examples/data/space_manipulator.urdf"
    );
    let model = Model::from_urdf_file(path)
        .expect("the space manipulator's URDF reads")
        .with_gravity(Vector3::zeros())
        .expect("zero gravity");
    let options = TextOptions {
        name: "space_manipulator".into(),
        torques: true,
    };
    let started = Instant::now();
    let code = compile_model(&model, &options).expect("the model compiles");
    let compile = started.elapsed();
    let Compiled::Lie(lie) = &code.compiled else {
        unreachable!("a floating base")
    };
    let mut parameters = [0.0; J + 1];
    parameters[J] = H;
    let sys: JitLie<P, N> = lie.instantiate(&parameters).expect("the dimensions");

    // The base drifts at 2 cm/s without turning, the arm at rest bent: M(q) v gives the
    // momenta, the linear part back in space.
    let (r0, x0) = (Matrix3::identity(), Vector3::new(1.0, -0.5, 2.0));
    let q0 = [0.2, 0.6, -1.2, 0.3, 0.8, -0.4];
    let mut point = pose_numbers(&r0, &x0);
    point.extend_from_slice(&q0);
    let config0 = configuration(&model, &point);
    let mut v0 = vec![0.0; N];
    v0[3..6].copy_from_slice(&[0.02, 0.01, -0.005]);
    let (q_parts, p_parts) = state_parts(&model, &point, &v0);
    let start = sys
        .state(&slices(&q_parts), &slices(&p_parts))
        .expect("a finite start");

    // The PD law, gains from each joint's inertia as the arm holds it (natural frequency
    // 1 rad/s, critically damped), the rates from the last two nodes.
    let target = [1.4, -0.3, 0.9, -0.8, -0.6, 1.2];
    let inertia = [120.0, 110.0, 35.0, 0.3, 0.6, 0.08];
    let pd = move |previous: &mut [f64; J], point: &[f64], u: &mut [f64]| {
        for j in 0..J {
            let q = point[12 + j];
            let rate = (q - previous[j]) / H;
            u[j] = -inertia[j] * (q - target[j]) - 2.0 * inertia[j] * rate;
            previous[j] = q;
        }
    };
    let mut previous = q0;
    let law = move |_k: usize, _t: f64, s: &LieState<P, N>, u: &mut [f64]| {
        pd(&mut previous, s.q.as_slice(), u);
    };

    let integ = LieIntegrator::new(sys, NewtonOptions::default());
    let started = Instant::now();
    let traj = integ
        .run(start)
        .steps(steps)
        .feedback(law)
        .collect()
        .expect("the steps");
    let per_step = started.elapsed().as_secs_f64() / steps as f64;

    let (l0, a0) = (
        integ.linear_momentum(&start),
        integ.spatial_momentum(&start),
    );
    let first = model.momentum(&config0, &v0).expect("a state of the model");
    let (mut linear_drift, mut angular_drift, mut model_drift, mut defect) =
        (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for (k, s) in traj.states.iter().enumerate() {
        let (l, a) = (integ.linear_momentum(s), integ.spatial_momentum(s));
        linear_drift = linear_drift.max((l - l0).norm() / l0.norm());
        angular_drift = angular_drift.max((a - a0).norm() / a0.norm());
        let (r, _) = base_pose(s.q.as_slice());
        defect = defect.max((r.transpose() * r - Matrix3::identity()).norm());
        if k % 100 == 0 || k == steps {
            let config = configuration(&model, s.q.as_slice());
            let v = velocity(&model, &config, s.q.as_slice(), s.p.as_slice());
            let m = model.momentum(&config, &v).expect("a state of the model");
            model_drift = model_drift
                .max((m.linear - first.linear).norm() / first.linear.norm())
                .max((m.angular - first.angular).norm() / first.angular.norm());
        }
    }
    // The same run reduced by the rigid motions of the whole tree (the text declares them out of
    // gravity): the total momentum is the run's parameter, `p` copied, `π` held at every step.
    let reduced_sys: JitLie<P, N, Dense, Reduced> = lie
        .instantiate_reduced(&parameters)
        .expect("the dimensions");
    let reduced = ReducedLieIntegrator::new(reduced_sys, NewtonOptions::default());
    let mut previous = q0;
    let reduced_law = move |_k: usize, _t: f64, s: &ReducedLieState<P, N>, u: &mut [f64]| {
        pd(&mut previous, s.q.as_slice(), u);
    };
    let started = Instant::now();
    let reduced_traj = reduced
        .run(reduced.reduce(&start))
        .steps(steps)
        .feedback(reduced_law)
        .collect()
        .expect("the reduced steps");
    let reduced_per_step = started.elapsed().as_secs_f64() / steps as f64;
    let (mut reduced_linear, mut reduced_angular, mut reduced_defect) = (0.0f64, 0.0f64, 0.0f64);
    for s in &reduced_traj.states {
        let u = s.unreduced();
        let (l, a) = (integ.linear_momentum(&u), integ.spatial_momentum(&u));
        reduced_linear = reduced_linear.max((l - l0).norm() / l0.norm());
        reduced_angular = reduced_angular.max((a - a0).norm() / a0.norm());
        let (r, _) = base_pose(s.q.as_slice());
        reduced_defect = reduced_defect.max((r.transpose() * r - Matrix3::identity()).norm());
    }
    let reduced_joints = (0..J)
        .map(|j| (reduced_traj.last().q[12 + j] - traj.last().q[12 + j]).abs())
        .fold(0.0, f64::max);

    let last = traj.last();
    let tracking = (0..J)
        .map(|j| (last.q[12 + j] - target[j]).abs())
        .fold(0.0, f64::max);
    let (r, x) = base_pose(last.q.as_slice());
    // The round-off of `x × p` a step, relative to `|π|`, at the base's farthest position.
    let farthest = traj
        .states
        .iter()
        .map(|s| base_pose(s.q.as_slice()).1.norm())
        .fold(0.0, f64::max);
    let cross_roundoff = f64::EPSILON * farthest * l0.norm() / a0.norm();
    let turned = angle(&(r * r0.transpose()));
    let drifted = x0 + (l0 / model.total_mass()) * (steps as f64 * H);
    let moved = (x - x0).norm();
    let reaction = (x - drifted).norm();
    let iterations =
        traj.stats.iter().map(|s| s.iterations).sum::<usize>() as f64 / traj.stats.len() as f64;
    let most = traj.stats.iter().map(|s| s.iterations).max().unwrap_or(0);

    println!(
        "space manipulator (a {:.0} kg base, 6 revolute joints, no gravity; h = 1 ms, {steps} \
         steps, {:.0} s):",
        model.bodies()[1].inertial.mass,
        steps as f64 * H
    );
    println!(
        "  text {} bytes, compiled in {:.2} s",
        code.text.text.len(),
        compile.as_secs_f64()
    );
    println!(
        "  total momentum, largest relative drift: linear {linear_drift:.1e}, angular \
         {angular_drift:.1e} (integrator's momentum map, every node); {model_drift:.1e} \
         (the model's momentum, every 100th node)"
    );
    println!(
        "  |pi| = {:.3e}, |p| = {:.3e}, the base at most {farthest:.2} m from the origin: the \
         round-off of x × p is {cross_roundoff:.1e} of |pi| a step",
        a0.norm(),
        l0.norm()
    );
    println!("  base attitude: largest |R^T R - I| {defect:.1e}; turned through {turned:.3} rad");
    println!(
        "  base position: moved {moved:.3} m, {reaction:.3} m off the drift of the total momentum"
    );
    println!("  joints: largest distance from their targets at the end {tracking:.1e} rad");
    println!(
        "  {:.2} us per step, {iterations:.2} Newton iterations per step (at most {most})",
        per_step * 1e6
    );
    println!(
        "  reduced by the rigid motions: linear {reduced_linear:.1e}, angular {reduced_angular:.1e} \
         (largest relative drift); |R^T R - I| {reduced_defect:.1e}; joints end {reduced_joints:.1e} rad \
         from the unreduced run's; {:.2} us per step",
        reduced_per_step * 1e6
    );

    // The attitude is reprojected onto SO(3) after every step, so its defect stays at
    // round-off; the momentum map `R Π + x × p` gathers the round-off of `x × p`, the more as
    // the base drifts away from the origin. The momentum bounds are about three times what is
    // measured at 10⁵ and 10⁶ steps.
    let n = steps as f64;
    let (defect_bound, drift_bound, model_bound) = (
        1e-14,
        1e-13 + 2e-17 * n + 2e-22 * n * n,
        1e-12 + 4e-17 * n + 2e-22 * n * n,
    );
    let mut failed = false;
    let mut claim = |holds: bool, what: &str| {
        if !holds {
            eprintln!("FAILED: {what}");
            failed = true;
        }
    };
    claim(
        linear_drift < drift_bound && angular_drift < drift_bound,
        &format!("the momentum map stays within {drift_bound:.1e} relative"),
    );
    claim(
        model_drift < model_bound,
        &format!("the model's momentum stays within {model_bound:.1e} relative"),
    );
    claim(
        defect < defect_bound,
        &format!("the base's attitude is orthonormal to {defect_bound:.1e}"),
    );
    claim(
        steps as f64 * H < 20.0 || tracking < 1e-3,
        "the joints reach their targets to 1e-3 rad",
    );
    claim(turned > 1e-2, "the base turns in reaction to the arm");
    // Reduced: the momentum is the run's parameter, held at every step to the round-off of one
    // evaluation of `R Π + x × p`, whatever the length of the run.
    claim(
        reduced_linear == 0.0 && reduced_angular < 1e-13,
        "reduced, the total momentum stays within 1e-13 relative",
    );
    claim(
        reduced_defect < defect_bound,
        &format!("reduced, the base's attitude is orthonormal to {defect_bound:.1e}"),
    );
    if failed {
        std::process::exit(1);
    }
}
