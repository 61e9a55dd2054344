//! The damped, driven oscillator and the torqued turntable with their closed form: shared by
//! `examples/forced.rs` and `tests/forces.rs` (included with `#[path]`).

use dirac::prelude::*;

/// `m ẍ = −k x − c ẋ + a`, the drive `a` a control.
#[reduced_lagrangian(shape(x), group(), rule = midpoint, controls(a),
    force = |dq| (a - c * v.x) * dq.x)]
pub fn oscillator(q: Config, v: Velocity, m: f64, k: f64, c: f64, a: f64) -> f64 {
    0.5 * m * v.x * v.x - 0.5 * k * q.x * q.x
}

/// A turntable of inertia `i0` with a pendulum (mass `m`, length `l`, damping `c`) hinged on
/// its axis; the torque `tau` on the table is a control.
#[reduced_lagrangian(shape(x), group(phi), rule = midpoint, controls(tau),
    force = |dq| tau * dq.phi - c * v.x * dq.x)]
pub fn turntable(q: Config, v: Velocity, i0: f64, m: f64, l: f64, c: f64, tau: f64) -> f64 {
    let r = l * q.x.sin();
    0.5 * i0 * v.phi * v.phi
        + 0.5 * m * (l * l * v.x * v.x + r * r * v.phi * v.phi)
        + 9.81 * m * l * q.x.cos()
}

/// The closed-form solution of `m ẍ + c ẋ + k x = a0 cos ωt` with `x(0) = x0`, `ẋ(0) = 0`
/// (underdamped).
pub fn exact(m: f64, k: f64, c: f64, a0: f64, omega: f64, x0: f64, t: f64) -> f64 {
    let (re, im) = (k - m * omega * omega, c * omega);
    let den = re * re + im * im;
    let (pa, pb) = (a0 * re / den, a0 * im / den);
    let gamma = c / (2.0 * m);
    let wd = (k / m - gamma * gamma).sqrt();
    let cc = x0 - pa;
    let dd = (gamma * cc - omega * pb) / wd;
    (-gamma * t).exp() * (cc * (wd * t).cos() + dd * (wd * t).sin())
        + pa * (omega * t).cos()
        + pb * (omega * t).sin()
}
