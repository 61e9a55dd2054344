//! A quadruped in flight: the robot of `examples/data/quadruped.urdf` (a 12 kg trunk, four legs
//! of hip abduction, hip flexion and knee, illustrative numbers) thrown upward with a spin,
//! under gravity and without contact, its legs swinging under a PD law on the joint torques.
//! The model's system text puts the trunk's pose on `SE(3)` beside the twelve joint angles
//! (`rule = trapezoid`), compiled at run time; the torques are controls.
//!
//! In flight only gravity acts from outside, at the centre of mass `c`: the total linear
//! momentum `ℓ` gains `M g` a second and the centre of mass follows the parabola
//! `c(t) = c₀ + v₀ t + g t²/2`, while the angular momentum about the centre of mass,
//! `J_c = J_O − c × ℓ`, stays constant however the legs swing. The discrete Lagrangian is
//! invariant under the horizontal translations and the rotations about the vertical, so the
//! discrete Noether theorem keeps the horizontal momentum and the vertical angular momentum
//! about the origin to round-off; the trapezoid rule's gravity terms `h/2 (V(q_k) + V(q_{k+1}))`
//! make `ℓ_z` fall by `M g h` a step and `J_O` turn by `h/2 (c_k + c_{k+1}) × M g`. Along the
//! step (summing the forced balance of the rotations about the origin with
//! that of `ℓ`), `J_c` changes by `−(c_{k+1} − c_k) × (ℓ_k + ℓ_{k+1})/2`: zero only if the
//! centre of mass moves by `h ℓ̄/M` in each step, which the trapezoid rule keeps to `O(h³)`
//! when the joints move. So `J_c` and the parabola hold to the method's order 2, not to
//! round-off, and the example reports by how much.
//!
//! ```text
//! cargo run --release --manifest-path dirac-io/Cargo.toml --target-dir target -p dirac-jit \
//!     --example quadruped_flight -- [--steps 2000] [--h 0.001]
//! ```
//!
//! It flies twice, at `h` and at `h/2` over the same time, and prints for each the largest
//! drift of the horizontal linear momentum and of the vertical angular momentum (relative to
//! `|ℓ₀|`, `|J_O|`), the vertical momentum's distance from `ℓ_z0 − M g t` (relative to
//! `M g t`), the largest change of `J_c` (relative to `|J_c|`), the largest distance of the
//! centre of mass from its parabola, the time per step and Newton's iterations; then the
//! observed order of the last two as `h` halves. It exits with status 1 if the round-off claims
//! miss `1e-12`, `J_c` changes by more than `4e-5 (h / 1 ms)²` relative, the centre of mass
//! leaves its parabola by more than `0.6 µm (h / 1 ms)²` (twice what is measured at 1 ms:
//! `2.0e-5`, `0.29 µm`), either observed order is off 2 by more than 0.2, or the legs did not
//! swing.
//!
//! Default: 2000 steps of `h` = 1 ms, two seconds of flight from a throw at 9.81 m/s upward.

use std::sync::Arc;
use std::time::Instant;

use dirac_jit::{compile_model, Compiled, JitLie, LieCode, Sparse};
use dirac_multibody::nalgebra::{Matrix3, Vector3};
use dirac_multibody::{Model, TextOptions};
use dirac_runtime::prelude::*;

/// Joints of the legs.
#[path = "common/floating.rs"]
mod floating;
use floating::{base_pose, configuration, pose_numbers, slices, state_parts};

const J: usize = 12;
/// A state's stored point: the trunk's pose (12 numbers) and the joint angles.
const P: usize = 12 + J;
/// Its momenta: the trunk's `(Π, p)` and the joints'.
const N: usize = 6 + J;

fn args() -> (usize, f64) {
    let (mut steps, mut h) = (2000, 1e-3);
    let mut it = std::env::args().skip(1);
    while let Some(a) = it.next() {
        let mut value = || it.next().and_then(|s| s.parse::<f64>().ok());
        match a.as_str() {
            "--steps" => steps = value().expect("--steps takes a number") as usize,
            "--h" => h = value().expect("--h takes a number"),
            other => panic!("unknown argument {other}"),
        }
    }
    (steps, h)
}

/// What each joint of a leg is, read from its name in the URDF (the model orders its joints
/// breadth first: the four abductions, then the four flexions, then the four knees).
#[derive(Clone, Copy, PartialEq)]
enum Role {
    Abduction,
    Flexion,
    Knee,
}

/// Each joint's role and whether it is on a front leg, in the model's (and the text's) order.
fn legs(model: &Model) -> [(Role, bool); J] {
    let joints = &model.joints()[1..];
    assert_eq!(joints.len(), J, "a floating joint and twelve leg joints");
    std::array::from_fn(|j| {
        let name = &joints[j].name;
        let role = if name.ends_with("hip_abduction") {
            Role::Abduction
        } else if name.ends_with("hip_flexion") {
            Role::Flexion
        } else if name.ends_with("knee") {
            Role::Knee
        } else {
            panic!("a leg joint: {name}")
        };
        (role, name.starts_with('f'))
    })
}

/// Joint `j`'s angle at rest: the legs folded under the trunk.
fn rest((role, _): (Role, bool)) -> f64 {
    match role {
        Role::Abduction => 0.0,
        Role::Flexion => 0.7,
        Role::Knee => -1.4,
    }
}

/// The swing of a joint at time `t`: the hips' flexion and the knees oppose each other, the
/// front legs against the hind ones, at 2 Hz; the abduction in a slower sway.
fn swing((role, front): (Role, bool), t: f64) -> f64 {
    let phase = if front { 0.0 } else { std::f64::consts::PI };
    let w = 2.0 * std::f64::consts::PI * 2.0;
    rest((role, front))
        + match role {
            Role::Abduction => 0.15 * (0.5 * w * t + phase).sin(),
            Role::Flexion => 0.5 * (w * t + phase).sin(),
            Role::Knee => -0.4 * (w * t + phase).sin(),
        }
}

/// What one flight measured.
struct Flight {
    /// Largest drift of the horizontal linear momentum, relative to `|ℓ₀|`.
    horizontal: f64,
    /// Largest drift of the vertical angular momentum about the origin, relative to `|J_O|`.
    vertical_axis: f64,
    /// Largest distance of `ℓ_z` from `ℓ_z0 − M g t`, relative to `M g t` at the end.
    fall: f64,
    /// Largest change of the angular momentum about the centre of mass, relative to `|J_c|`.
    about_centre: f64,
    /// `|J_c|` at the start.
    jc: f64,
    /// Largest distance of the centre of mass from its parabola, m.
    parabola: f64,
    /// How far the centre of mass fell from its apex, m.
    fell: f64,
    /// Largest swing of a hip's flexion from rest, and the trunk's largest turn, rad.
    swung: f64,
    turned: f64,
    per_step: f64,
    iterations: f64,
    most: usize,
}

/// A flight of `steps` steps of `h`: thrown from 1 m up at 9.81 m/s upward and
/// 1.5 m/s forward, spinning about all three axes (body angular velocity), the legs folded
/// (`M(q) v` gives the momenta, the linear part back in space), the PD law swinging the legs.
fn fly(lie: &Arc<LieCode>, model: &Model, h: f64, steps: usize) -> Flight {
    let g = model.gravity();
    let mass = model.total_mass();
    let mut parameters = [0.0; J + 1];
    parameters[J] = h;
    // 18 chart coordinates: the sparse backend (the dense one stops at 16).
    let sys: JitLie<P, N, Sparse> = lie.instantiate_sparse(&parameters).expect("the dimensions");
    let legs = legs(model);
    let rest: [f64; J] = legs.map(rest);
    let (r0, x0) = (Matrix3::identity(), Vector3::new(0.0, 0.0, 1.0));
    let mut point = pose_numbers(&r0, &x0);
    point.extend_from_slice(&rest);
    let mut v0 = vec![0.0; N];
    v0[..6].copy_from_slice(&[1.2, 2.0, 3.0, 1.5, 0.3, 9.81]);
    let (q_parts, p_parts) = state_parts(model, &point, &v0);
    let start = sys
        .state(&slices(&q_parts), &slices(&p_parts))
        .expect("a finite start");

    // The PD law toward the swing, the rates from the last two nodes.
    let (kp, kd) = (20.0, 0.5);
    let mut previous = rest;
    let law = move |_k: usize, t: f64, s: &LieState<P, N>, u: &mut [f64]| {
        for j in 0..J {
            let q = s.q[12 + j];
            let rate = (q - previous[j]) / h;
            u[j] = -kp * (q - swing(legs[j], t)) - kd * rate;
            previous[j] = q;
        }
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

    let centre = |q: &[f64]| {
        model
            .centre_of_mass(&configuration(model, q))
            .expect("a configuration of the model")
    };
    let (l0, a0) = (
        integ.linear_momentum(&start),
        integ.spatial_momentum(&start),
    );
    let c0 = centre(start.q.as_slice());
    let jc0 = a0 - c0.cross(&l0);
    let (mut horizontal, mut vertical_axis, mut fall, mut about_centre, mut parabola) =
        (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let (mut swung, mut turned) = (0.0f64, 0.0f64);
    for (k, s) in traj.states.iter().enumerate() {
        let t = k as f64 * h;
        let (l, a) = (integ.linear_momentum(s), integ.spatial_momentum(s));
        let c = centre(s.q.as_slice());
        horizontal = horizontal.max((l.x - l0.x).abs().max((l.y - l0.y).abs()));
        vertical_axis = vertical_axis.max((a.z - a0.z).abs());
        fall = fall.max((l.z - (l0.z + mass * g.z * t)).abs());
        about_centre = about_centre.max((a - c.cross(&l) - jc0).norm());
        let expected = c0 + l0 * (t / mass) + g * (0.5 * t * t);
        parabola = parabola.max((c - expected).norm());
        for j in (0..J).filter(|&j| legs[j].0 == Role::Flexion) {
            swung = swung.max((s.q[12 + j] - rest[j]).abs());
        }
        let (r, _) = base_pose(s.q.as_slice());
        turned = turned.max(((r.trace() - 1.0) / 2.0).clamp(-1.0, 1.0).acos());
    }
    let impulse = mass * g.norm() * steps as f64 * h;
    let apex = c0.z + l0.z * l0.z / (2.0 * mass * mass * g.norm());
    Flight {
        horizontal: horizontal / l0.norm(),
        vertical_axis: vertical_axis / a0.norm(),
        fall: fall / impulse,
        about_centre: about_centre / jc0.norm(),
        jc: jc0.norm(),
        parabola,
        fell: apex - centre(traj.last().q.as_slice()).z,
        swung,
        turned,
        per_step,
        iterations: traj.stats.iter().map(|s| s.iterations).sum::<usize>() as f64
            / traj.stats.len() as f64,
        most: traj.stats.iter().map(|s| s.iterations).max().unwrap_or(0),
    }
}

fn main() {
    let (steps, h) = args();
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../examples/data/quadruped.urdf"
    );
    let model = Model::from_urdf_file(path).expect("the quadruped's URDF reads");
    let options = TextOptions {
        name: "quadruped".into(),
        torques: true,
    };
    let started = Instant::now();
    let code = compile_model(&model, &options).expect("the model compiles");
    let compile = started.elapsed();
    let Compiled::Lie(lie) = &code.compiled else {
        unreachable!("a floating base")
    };
    println!(
        "quadruped in flight ({:.1} kg, a trunk and 12 revolute joints, g = {:.2} m/s^2; {:.2} s \
         in {steps} steps of h = {} ms, then in {} steps of h/2):",
        model.total_mass(),
        model.gravity().norm(),
        steps as f64 * h,
        h * 1e3,
        2 * steps
    );
    println!(
        "  text {} bytes, compiled in {:.2} s",
        code.text.text.len(),
        compile.as_secs_f64()
    );
    let flights = [
        fly(lie, &model, h, steps),
        fly(lie, &model, h / 2.0, 2 * steps),
    ];
    let mut failed = false;
    let mut claim = |holds: bool, what: &str| {
        if !holds {
            eprintln!("FAILED: {what}");
            failed = true;
        }
    };
    for (f, step) in flights.iter().zip([h, h / 2.0]) {
        println!("  h = {} ms:", step * 1e3);
        println!(
            "    kept to round-off: horizontal linear momentum {:.1e} relative, vertical \
             angular momentum {:.1e}; vertical momentum off l_z0 - M g t by {:.1e} of M g t",
            f.horizontal, f.vertical_axis, f.fall
        );
        println!(
            "    angular momentum about the centre of mass (|J_c| = {:.3} kg m^2/s): largest \
             change {:.1e} relative",
            f.jc, f.about_centre
        );
        println!(
            "    centre of mass: largest distance from c0 + v0 t + g t^2/2 {:.1e} m (it fell \
             {:.2} m from its apex)",
            f.parabola, f.fell
        );
        println!(
            "    the legs swung (hip flexion up to {:.2} rad from rest), the trunk turned up to \
             {:.2} rad",
            f.swung, f.turned
        );
        println!(
            "    {:.2} us per step, {:.2} Newton iterations per step (at most {})",
            f.per_step * 1e6,
            f.iterations,
            f.most
        );
        claim(
            f.horizontal < 1e-12 && f.vertical_axis < 1e-12 && f.fall < 1e-12,
            "the momenta gravity allows are kept to 1e-12",
        );
        // Measured at h = 1 ms: 2.0e-5 and 0.29 um; the bounds are twice that, scaled by h².
        let scale = (step / 1e-3).powi(2);
        claim(
            f.about_centre < 4e-5 * scale,
            "the angular momentum about the centre of mass stays within 4e-5 (h / 1 ms)^2",
        );
        claim(
            f.parabola < 6e-7 * scale,
            "the centre of mass stays within 0.6 um (h / 1 ms)^2 of its parabola",
        );
        claim(f.swung > 0.3, "the legs swing");
    }
    let order = |a: f64, b: f64| (a / b).log2();
    let (jc_order, c_order) = (
        order(flights[0].about_centre, flights[1].about_centre),
        order(flights[0].parabola, flights[1].parabola),
    );
    println!(
        "  observed orders as h halves: J_c {jc_order:.2}, the centre of mass's distance from \
         its parabola {c_order:.2}"
    );
    claim(
        (jc_order - 2.0).abs() < 0.2 && (c_order - 2.0).abs() < 0.2,
        "both errors fall at order 2",
    );
    if failed {
        std::process::exit(1);
    }
}
