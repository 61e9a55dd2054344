//! Systems with forces and controls shared by the element-wise tests: run-time-sized ones and the
//! same systems unrolled at a fixed size (the damped Toda lattice sized at run time is the
//! examples' `DampedTodaN`).
#![allow(dead_code)]

use dirac::prelude::*;

/// The damped Toda lattice of `examples/common/toda_n.rs` (`DampedTodaN`) at n = 16, unrolled.
#[reduced_lagrangian(coordinates(x[16]), translate(x), rule = midpoint,
    force = |dq| {
        let mut w = 0.0;
        for i in 0..16 {
            w -= c * v.x[i] * dq.x[i];
        }
        w
    })]
pub fn damped_toda16(q: Config, v: Velocity, m: f64, d: f64, c: f64) -> f64 {
    let mut l = 0.0;
    for i in 0..16 {
        l += 0.5 * m * v.x[i] * v.x[i];
    }
    for i in 0..15 {
        l -= (-(q.x[i + 1] - q.x[i] - d)).exp();
    }
    l - (-(q.x[0] + 16.0 * d - q.x[15] - d)).exp()
}

/// A driven, damped chain as a discrete Lagrangian with discrete forces, sized at run time: the
/// damping in loops, the drive `a` on the first particle outside them, a control.
#[reduced_lagrangian(coordinates(x[n]), controls(a),
    force = |dq0, dq1| {
        let mut w = 0.0;
        for i in 0..n {
            w -= 0.5 * c * (q1.x[i] - q0.x[i]) * (dq0.x[i] + dq1.x[i]);
        }
        w + 0.5 * h * a * (dq0.x[0] + dq1.x[0])
    })]
pub fn driven_chain(q0: Config, q1: Config, h: f64, c: f64, a: f64, n: usize) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        l += 0.5 * (q1.x[i] - q0.x[i]) * (q1.x[i] - q0.x[i]) / h;
    }
    for i in 0..n - 1 {
        l -= 0.25 * h * ((q0.x[i + 1] - q0.x[i]).powi(2) + (q1.x[i + 1] - q1.x[i]).powi(2));
    }
    l
}

/// The same at n = 5, unrolled.
#[reduced_lagrangian(shape(x[5]), group(), controls(a),
    force = |dq0, dq1| {
        let mut w = 0.0;
        for i in 0..5 {
            w -= 0.5 * c * (q1.x[i] - q0.x[i]) * (dq0.x[i] + dq1.x[i]);
        }
        w + 0.5 * h * a * (dq0.x[0] + dq1.x[0])
    })]
pub fn driven_chain5(q0: Config, q1: Config, h: f64, c: f64, a: f64) -> f64 {
    let mut l = 0.0;
    for i in 0..5 {
        l += 0.5 * (q1.x[i] - q0.x[i]) * (q1.x[i] - q0.x[i]) / h;
    }
    for i in 0..4 {
        l -= 0.25 * h * ((q0.x[i + 1] - q0.x[i]).powi(2) + (q1.x[i + 1] - q1.x[i]).powi(2));
    }
    l
}
