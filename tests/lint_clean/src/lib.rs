//! Lagrangians that exercise what the generated code must not trip over in a strict user crate:
//! folded constants near π (`clippy::approx_constant`), long literals (`excessive_precision`,
//! `unreadable_literal`), many parameters (`too_many_arguments`), short names
//! (`many_single_char_names`). The user's own code here is written to pass the same lints, so
//! every remaining warning comes from the expansion.
#![deny(warnings, clippy::all, clippy::pedantic)]

use dirac::prelude::*;

/// A pendulum whose frequency is given in hertz: `2π` folds to `6.283185307179586` in the
/// generated code, and `/ (2π)` to its reciprocal.
#[reduced_lagrangian(shape(phi), group(theta))]
#[must_use]
pub fn hertz_pendulum(q0: Config, q1: Config, h: f64, freq: f64, m: f64) -> f64 {
    let omega = 2.0 * std::f64::consts::PI * freq;
    let phi = 0.5 * (q0.phi + q1.phi);
    let (dphi, dtheta) = ((q1.phi - q0.phi) / h, (q1.theta - q0.theta) / h);
    let k = 0.5 * m * (dphi * dphi + phi.sin() * phi.sin() * dtheta * dtheta);
    h * (k - m * omega * omega * (1.0 - phi.cos()) / (2.0 * std::f64::consts::PI))
}

/// Many single-letter parameters, long literals and a connection.
#[reduced_lagrangian(shape(a, b), group(c), connection = [[e, 1.0 / std::f64::consts::PI]])]
#[must_use]
pub fn many(q0: Config, q1: Config, h: f64, d: f64, e: f64, f: f64, g: f64, k: f64, m: f64) -> f64 {
    let (x, y) = (q1.a - q0.a, q1.b - q0.b);
    let w = q1.c - q0.c - e * x - std::f64::consts::FRAC_1_PI * y;
    let t = 0.5 * m / h * (x * x + y * y) + 0.5 * k / h * w * w;
    let v =
        h * (d * q0.a * q0.a + f * q0.b * q0.b) * std::f64::consts::PI / 1.234_567_890_123_456_7e10;
    t - v - h * g * 1_000_000.123_456_789 * (q0.a + q1.a)
}

/// A continuous Lagrangian without symmetry (`group()`): the quadrature rule, the Legendre map and
/// the energy are generated too, with the folded `2π`.
#[reduced_lagrangian(shape(x), group(), rule = midpoint)]
#[must_use]
pub fn continuous_oscillator(q: Config, v: Velocity, freq: f64) -> f64 {
    let omega = 2.0 * std::f64::consts::PI * freq;
    0.5 * v.x * v.x - 0.5 * omega * omega * q.x * q.x
}

/// Runs the generated steppers, so the emitted items are used.
///
/// # Errors
/// A failed step.
pub fn run() -> Result<f64, Box<dyn std::error::Error>> {
    let sys = HertzPendulum {
        h: 0.01,
        freq: 0.5,
        m: 1.0,
    };
    let integ = ReducedIntegrator::plus(sys, NewtonOptions::default());
    let traj = integ
        .run(ReducedState::new([0.5], [0.0], [0.1], [0.0]))
        .steps(10)
        .collect()?;
    let sys = Many {
        h: 0.01,
        d: 1.0,
        e: 0.5,
        f: 2.0,
        g: 0.1,
        k: 3.0,
        m: 1.0,
    };
    let integ = UnreducedIntegrator::new(sys, NewtonOptions::default());
    let canon = integ
        .run(sys.untrivialize(&ReducedState::new([0.1, 0.2], [0.0, 0.0], [0.3], [0.0])))
        .steps(10)
        .collect()?;
    let osc = ContinuousOscillator { freq: 1.0, h: 0.01 };
    let start = osc.unreduced_state(SVector::from([1.0]), SVector::from([0.0]))?;
    let o = UnreducedIntegrator::new(osc, NewtonOptions::default())
        .run(start)
        .steps(10)
        .collect()?;
    Ok(traj.last().x[0] + canon.last().q[0] + o.last().q[0])
}

/// A chart transition: its emitted `φ` and `Dφ` carry the same allowances.
#[chart_transition(from(shape(r), group(theta)), to(shape(s), group(phi)))]
pub fn stretch(q: Config) -> (f64, f64) {
    (2.0 * std::f64::consts::PI * q.r, q.theta + q.r)
}

/// An element-wise system sized at run time (a grid with wrap-around, a pair loop, a size and a
/// loop index read as values): its kernels, stencils, configuration type and trait impls.
#[reduced_lagrangian(
    coordinates(u[nx][ny], c[k]),
    translate(u),
    rule = midpoint
)]
#[must_use]
#[allow(
    clippy::cast_precision_loss,
    reason = "grid indices are far below 2^52"
)]
pub fn grid_and_pairs(
    q: Config,
    v: Velocity,
    m: f64,
    s: f64,
    nx: usize,
    ny: usize,
    k: usize,
) -> f64 {
    let mut l = 0.0;
    for i in 0..nx {
        for j in 0..ny {
            let du = q.u[(i + 1) % nx][j] - q.u[i][j];
            l += 0.5 * m * v.u[i][j] * v.u[i][j] - 0.5 * s * du * du * (1.0 + i as f64 / nx as f64);
        }
    }
    for a in 0..k {
        l += 0.5 * v.c[a] * v.c[a];
        for b in a + 1..k {
            l -= (q.c[a] - q.c[b]).powi(2) * 1.234_567_890_123_456_7e-3;
        }
    }
    l
}

/// A damped, driven chain sized at run time: forces per element, written with loops like the
/// body.
#[reduced_lagrangian(
    coordinates(x[n]),
    translate(x),
    rule = trapezoid,
    controls(a),
    force = |dq| {
        let mut w = 0.0;
        for i in 0..n {
            w -= c * v.x[i] * dq.x[i];
        }
        w + a * (dq.x[0] - dq.x[n - 1])
    }
)]
#[must_use]
pub fn damped_chain(q: Config, v: Velocity, m: f64, c: f64, a: f64, n: usize) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        l += 0.5 * m * v.x[i] * v.x[i];
    }
    for i in 0..n - 1 {
        l -= 0.5 * (q.x[i + 1] - q.x[i]).powi(2);
    }
    l
}

/// A cart carrying a chain of links in maximal coordinates, sized at run time: one length
/// constraint per link, written row by row.
#[reduced_lagrangian(coordinates(c, x[n], y[n]), rule = midpoint,
    constraints = |q| {
        let mut phi = vec![0.0; n];
        phi[0] = (q.x[0] - q.c) * (q.x[0] - q.c) + q.y[0] * q.y[0] - l * l;
        for i in 1..n {
            let (dx, dy) = (q.x[i] - q.x[i - 1], q.y[i] - q.y[i - 1]);
            phi[i] = dx * dx + dy * dy - l * l;
        }
        phi
    })]
#[must_use]
pub fn link_chain(q: Config, v: Velocity, mc: f64, m: f64, l: f64, gr: f64, n: usize) -> f64 {
    let mut t = 0.5 * mc * v.c * v.c;
    for i in 0..n {
        t += 0.5 * m * (v.x[i] * v.x[i] + v.y[i] * v.y[i]) - m * gr * q.y[i];
    }
    t
}

/// A heavy top beside a wheel angle, and a pendulum direction: rotation, direction and scalar
/// coordinates with the matrix and vector operations of the body language, and the rotations
/// about the vertical as a symmetry.
#[reduced_lagrangian(rotation(r), direction(n), shape(phi), symmetry(r, n, axis = z))]
#[must_use]
pub fn top_and_pendulum(
    q0: Config,
    q1: Config,
    h: f64,
    j1: f64,
    j3: f64,
    mgl: f64,
    jw: f64,
) -> f64 {
    let jd = Matrix3::from_diagonal(&Vector3::new(0.5 * j3, 0.5 * j3, j1 - 0.5 * j3));
    let f = q0.r.transpose() * q1.r;
    let spin = 0.5 * vee(&(f - f.transpose())).z / h + (q1.phi - q0.phi) / h;
    let dn = q1.n - q0.n;
    let up = Vector3::z();
    ((Matrix3::identity() - f) * jd).trace() / h
        + 0.5 * h * jw * spin * spin
        + 0.5 * dn.norm_squared() / h
        - 0.5 * h * mgl * (q0.r[(2, 2)] + q1.r[(2, 2)] + q0.n.dot(&up) + q1.n.cross(&up).norm())
}

/// A body with a wheel in empty space, reduced by every rotation of its attitude, with a motor
/// torque on the wheel.
#[reduced_lagrangian(rotation(r), shape(phi), symmetry(r), controls(u), force = |dq0, dq1| 0.5 * h * u * (dq0.phi + dq1.phi))]
#[must_use]
pub fn body_and_wheel(q0: Config, q1: Config, h: f64, j1: f64, j3: f64, jw: f64, u: f64) -> f64 {
    let jd = Matrix3::from_diagonal(&Vector3::new(0.5 * j3, 0.5 * j3, j1 - 0.5 * j3));
    let f = q0.r.transpose() * q1.r;
    let spin = 0.5 * vee(&(f - f.transpose())).z / h + (q1.phi - q0.phi) / h;
    ((Matrix3::identity() - f) * jd).trace() / h + 0.5 * h * jw * spin * spin
}

/// Kepler's problem with adaptive steps: the step follows the free-fall time `r^{3/2}`.
#[reduced_lagrangian(shape(r), group(theta, t), time(t), adapt = |q| q.r * q.r.sqrt(), rule = midpoint)]
#[must_use]
pub fn kepler_adaptive(q: Config, v: Velocity, k: f64) -> f64 {
    0.5 * (v.r * v.r + q.r * q.r * v.theta * v.theta) + k / q.r
}

/// A rigid body in space as one pose, with a thrust along its third axis: a pose's parts, its
/// velocity and virtual displacement, a continuous Lagrangian, a control.
#[reduced_lagrangian(pose(body), rule = trapezoid, step = h, controls(u),
    force = |dq| u * (q.body.rotation * Vector3::z()).dot(&dq.body.linear))]
#[must_use]
pub fn thrust_body(q: Config, v: Velocity, m: f64, g: f64, j1: f64, j3: f64, u: f64) -> f64 {
    let w = v.body.angular;
    0.5 * (j1 * (w.x * w.x + w.y * w.y) + j3 * w.z * w.z) + 0.5 * m * v.body.linear.norm_squared()
        - m * g * q.body.translation.z
}
