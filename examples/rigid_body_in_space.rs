//! A rigid body in space on `SE(3)`: one `pose(b)` coordinate (attitude and position together),
//! stepped by the Lie group variational integrator `#[reduced_lagrangian]` derives from
//!
//! ```text
//! L_d = tr((I − R0ᵀR1) J_d)/h + m |x1 − x0|²/(2h) − (h/2) m g e3·(x0 + x1),
//! ```
//!
//! with a thrust `T` along the body's third axis (the spatial force `T R e3`, by the trapezoid
//! rule), `J = diag(1, 2, 3)`, `m = 3`, `h = 0.01`. Each run prints what it keeps of the
//! momentum map of the rigid motions — the linear momentum `ℓ = p` and the angular momentum
//! `π = R Π + x × p` about the origin — as its largest drift relative to `|ℓ_0|` and `|π_0|`,
//! and the largest `‖RᵀR − I‖`:
//!
//! 1. coasting (no gravity, no thrust), `--steps` steps (default 10⁵): all of `ℓ` and `π`;
//! 2. falling (gravity), `--forced` steps (default 5·10⁴, 500 s): the horizontal `ℓ` and the
//!    vertical `π`;
//! 3. thrusting (gravity and `T = 40 > m g`), `--forced` steps: no momentum is kept, and the
//!    step balances the forces' impulse and its moment, `ℓ_{k+1} − ℓ_k = (h/2)(f_k + f_{k+1})`
//!    and `π_{k+1} − π_k = (h/2)(x_k × f_k + x_{k+1} × f_{k+1})`, `f = T R e3 − m g e3` (the
//!    largest error of a step, relative to the momenta then).
//!
//! The body tumbles in every run (its angular momentum off every axis). The runs with forces
//! take it far from the origin (`|x|` ≈ 1.2·10⁶ after 500 s of falling) at no cost to the
//! step: its residual `m (x1 − x0)/h − ..` reads the chart increment `v` of `x1 = x0 + v`
//! itself, not `(x0 + v) − x0` rounded at `|x0|`, so it stays at the round-off of the momenta
//! wherever the body is and Newton converges at the default tolerances. Storing the position
//! `x0 + v` rounds it at `|x|`, as any integrator's positions are rounded: `π = R Π + x × p`,
//! whose terms `|x| |p|` grow with the distance, then drifts by about `ε |x| |p|` a step (in
//! the coasting run, 4e-10 of `|π0|` over 10⁵ steps, in which `|x|` grows to about 370).
//!
//! `tests/se3.rs` holds the same system to a hand-written SE(3) integrator.
//!
//! Run: `cargo run --release --example rigid_body_in_space [-- --steps 100000 --forced 50000]`.

use dirac::lie::{cayley, orthogonality_defect};
use dirac::prelude::*;

#[path = "common/cli.rs"]
mod cli;

use cli::{at_least, Cli};

/// The body: `J = diag(j1, j2, j3)`, mass `m`, gravity `g`, thrust `thrust` along `R e3`.
#[reduced_lagrangian(pose(b),
    force = |dq0, dq1| 0.5 * h * thrust
        * ((q0.b.rotation * Vector3::z()).dot(&dq0.b.linear)
            + (q1.b.rotation * Vector3::z()).dot(&dq1.b.linear)))]
#[allow(clippy::too_many_arguments)]
fn body_in_space(
    q0: Config,
    q1: Config,
    h: f64,
    m: f64,
    g: f64,
    j1: f64,
    j2: f64,
    j3: f64,
    thrust: f64,
) -> f64 {
    let jd = Matrix3::from_diagonal(&Vector3::new(j2 + j3 - j1, j1 + j3 - j2, j1 + j2 - j3)) * 0.5;
    let f = q0.b.rotation.transpose() * q1.b.rotation;
    let dx = q1.b.translation - q0.b.translation;
    ((Matrix3::identity() - f) * jd).trace() / h + 0.5 * m * dx.norm_squared() / h
        - 0.5 * h * m * g * (q0.b.translation.z + q1.b.translation.z)
}

/// What a run measured: the largest drift of the kept momenta, relative to their start (or,
/// thrusting, the largest error of the step's balance, relative to the momenta then), and the
/// largest `‖RᵀR − I‖`.
#[derive(Default)]
struct Drift {
    linear: f64,
    angular: f64,
    orthogonality: f64,
}

/// The start of every run: tumbling (its angular momentum off every axis) and drifting.
fn tumbling(sys: &BodyInSpace) -> LieState<12, 6> {
    sys.state(
        &BodyInSpaceConfig {
            b: BodyInSpacePose {
                rotation: cayley(&Vector3::new(0.3, -0.2, 0.4)),
                translation: Vector3::new(1.0, -2.0, 0.5),
            },
        },
        &BodyInSpaceMomentum {
            b: BodyInSpacePoseMomentum {
                angular: Vector3::new(0.4, 1.0, -0.3),
                linear: Vector3::new(0.9, -0.3, 0.6),
            },
        },
    )
}

/// `steps` steps of `sys`; `kept` picks the components of `(ℓ − ℓ0, π − π0)` that are kept
/// (without thrust), or the run checks the forces' balance (with thrust).
fn run(
    sys: BodyInSpace,
    s0: LieState<12, 6>,
    steps: usize,
    kept: impl Fn(Vector3<f64>, Vector3<f64>) -> (Vector3<f64>, Vector3<f64>),
) -> Result<Drift, Box<dyn std::error::Error>> {
    let integ = LieIntegrator::new(sys, NewtonOptions::default());
    // The total force f = T R e3 − m g e3 and its moment x × f about the origin.
    let force = |s: &LieState<12, 6>| {
        sys.config(s).b.rotation * Vector3::z() * sys.thrust - Vector3::z() * (sys.m * sys.g)
    };
    let moment = |s: &LieState<12, 6>| sys.config(s).b.translation.cross(&force(s));
    let (l0, pi0) = (integ.linear_momentum(&s0), integ.spatial_momentum(&s0));
    let mut drift = Drift::default();
    let mut previous = s0;
    integ
        .run(s0)
        .steps(steps)
        .observe(|k, _, s: &LieState<12, 6>, _| {
            let (l, pi) = (integ.linear_momentum(s), integ.spatial_momentum(s));
            let (dl, dpi, size_l, size_pi) = if sys.thrust == 0.0 {
                let (dl, dpi) = kept(l - l0, pi - pi0);
                (dl, dpi, l0.norm(), pi0.norm())
            } else {
                // The balance of the step that ended here (zero at the start), relative to the
                // momenta (for π, to its terms |Π| + |x| |p|, larger than π itself).
                let half = 0.5 * sys.h;
                let b = sys.momenta(s).b;
                let terms = b.angular.norm() + sys.config(s).b.translation.norm() * l.norm();
                (
                    l - integ.linear_momentum(&previous) - (force(&previous) + force(s)) * half,
                    pi - integ.spatial_momentum(&previous) - (moment(&previous) + moment(s)) * half,
                    l.norm(),
                    terms,
                )
            };
            if k > 0 || sys.thrust == 0.0 {
                drift.linear = drift.linear.max(dl.norm() / size_l);
                drift.angular = drift.angular.max(dpi.norm() / size_pi);
            }
            drift.orthogonality = drift
                .orthogonality
                .max(orthogonality_defect(&sys.config(s).b.rotation));
            previous = *s;
        })
        .stream()?;
    Ok(drift)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut cli = Cli::new(
        "rigid_body_in_space",
        "a rigid body in space on SE(3), pose(b): its momenta over long runs",
    );
    let steps: usize = cli.value(
        "--steps",
        "S",
        "steps of the coasting run",
        100_000,
        at_least(1),
    );
    let forced: usize = cli.value(
        "--forced",
        "F",
        "steps of the falling and thrusting runs",
        50_000,
        at_least(1),
    );
    cli.finish();
    let body = |g: f64, thrust: f64| BodyInSpace {
        h: 0.01,
        m: 3.0,
        g,
        j1: 1.0,
        j2: 2.0,
        j3: 3.0,
        thrust,
    };
    println!("A rigid body in space, J = diag(1, 2, 3), m = 3, h = 0.01:");
    let all = |l: Vector3<f64>, pi: Vector3<f64>| (l, pi);
    let sys = body(0.0, 0.0);
    let d = run(sys, tumbling(&sys), steps, all)?;
    println!(
        "  coasting, {steps} steps: |ℓ − ℓ0|/|ℓ0| ≤ {:.1e}, |π − π0|/|π0| ≤ {:.1e}, ‖RᵀR − I‖ ≤ {:.1e}",
        d.linear, d.angular, d.orthogonality
    );
    let kept = |l: Vector3<f64>, pi: Vector3<f64>| {
        (Vector3::new(l.x, l.y, 0.0), Vector3::new(0.0, 0.0, pi.z))
    };
    let sys = body(9.81, 0.0);
    let d = run(sys, tumbling(&sys), forced, kept)?;
    println!(
        "  falling, {forced} steps: horizontal ℓ ≤ {:.1e}, vertical π ≤ {:.1e} (relative), ‖RᵀR − I‖ ≤ {:.1e}",
        d.linear, d.angular, d.orthogonality
    );
    let sys = body(9.81, 40.0);
    let d = run(sys, tumbling(&sys), forced, all)?;
    println!(
        "  thrusting, {forced} steps: impulse balance ≤ {:.1e}, its moment's ≤ {:.1e} (relative), ‖RᵀR − I‖ ≤ {:.1e}",
        d.linear, d.angular, d.orthogonality
    );
    Ok(())
}
