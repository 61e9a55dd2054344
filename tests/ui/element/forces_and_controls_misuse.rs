use dirac::prelude::*;

// Not linear in the virtual displacement.
#[reduced_lagrangian(coordinates(x[n]), rule = midpoint,
    force = |dq| {
        let mut w = 0.0;
        for i in 0..n {
            w -= c * v.x[i] * dq.x[i] * dq.x[i];
        }
        w
    })]
fn squared(q: Config, v: Velocity, c: f64, n: usize) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        l += 0.5 * v.x[i] * v.x[i] - 0.5 * q.x[i] * q.x[i];
    }
    l
}

// A term without its displacement.
#[reduced_lagrangian(coordinates(x[n]), rule = midpoint,
    force = |dq| {
        let mut w = 0.0;
        for i in 0..n {
            w -= c * v.x[i];
        }
        w
    })]
fn missing(q: Config, v: Velocity, c: f64, n: usize) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        l += 0.5 * v.x[i] * v.x[i] - 0.5 * q.x[i] * q.x[i];
    }
    l
}

// Two displacements for a continuous Lagrangian.
#[reduced_lagrangian(coordinates(x[n]), rule = midpoint, force = |dq0, dq1| c * (dq0.x[0] + dq1.x[0]))]
fn two(q: Config, v: Velocity, c: f64, n: usize) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        l += 0.5 * v.x[i] * v.x[i] - 0.5 * q.x[i] * q.x[i];
    }
    l
}

// A stencil that escapes the coordinates for every size.
#[reduced_lagrangian(coordinates(x[n]), rule = midpoint,
    force = |dq| {
        let mut w = 0.0;
        for i in 0..n {
            w -= c * v.x[i + n] * dq.x[i];
        }
        w
    })]
fn escaping(q: Config, v: Velocity, c: f64, n: usize) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        l += 0.5 * v.x[i] * v.x[i] - 0.5 * q.x[i] * q.x[i];
    }
    l
}

// A control that is not a parameter.
#[reduced_lagrangian(coordinates(x[n]), rule = midpoint, controls(z),
    force = |dq| c * dq.x[0])]
fn uncontrolled(q: Config, v: Velocity, c: f64, n: usize) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        l += 0.5 * v.x[i] * v.x[i] - 0.5 * q.x[i] * q.x[i];
    }
    l
}

fn main() {}
