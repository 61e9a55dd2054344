use dirac::prelude::*;

// The time is a shape coordinate.
#[reduced_lagrangian(shape(x, t), group(), time(t), adapt = |q| 1.0 + q.x * q.x, rule = midpoint)]
fn shape_time(q: Config, v: Velocity) -> f64 {
    0.5 * v.x * v.x
}

// A monitor without a time coordinate.
#[reduced_lagrangian(shape(x), group(t), adapt = |q| 1.0 + q.x * q.x, rule = midpoint)]
fn no_time(q: Config, v: Velocity) -> f64 {
    0.5 * v.x * v.x - q.x
}

// A discrete Lagrangian: there is no continuous L to transform.
#[reduced_lagrangian(shape(x), group(t), time(t), adapt = |q| 1.0 + q.x * q.x)]
fn discrete(q0: Config, q1: Config, h: f64) -> f64 {
    0.5 * (q1.x - q0.x) * (q1.x - q0.x) / h
}

// A force that acts on the time coordinate.
#[reduced_lagrangian(shape(x), group(t), time(t), adapt = |q| 1.0 + q.x * q.x, rule = midpoint, force = |dq| -v.x * dq.x + dq.t)]
fn pushed(q: Config, v: Velocity) -> f64 {
    0.5 * v.x * v.x - q.x
}

fn main() {}
