use dirac::prelude::*;

// The time is a shape coordinate.
#[reduced_lagrangian(rotation(r), shape(t), time(t), adapt = |q| 1.0 + q.r[(2, 2)], rule = trapezoid)]
fn shape_time(q: Config, v: Velocity) -> f64 {
    let _ = q.r;
    0.5 * v.r.norm_squared()
}

// A monitor that changes with the attitude, under every rotation of it: the step would
// depend on the orientation the symmetry moves.
#[reduced_lagrangian(rotation(r), group(t), symmetry(r), time(t), adapt = |q| 2.0 + q.r[(0, 0)], rule = trapezoid)]
fn turning_monitor(q: Config, v: Velocity) -> f64 {
    let _ = q.r;
    0.5 * v.r.norm_squared()
}

// A discrete Lagrangian: there is no continuous L to transform.
#[reduced_lagrangian(rotation(r), group(t), time(t), adapt = |q| 1.0)]
fn discrete(q0: Config, q1: Config, h: f64) -> f64 {
    ((Matrix3::identity() - q0.r.transpose() * q1.r)).trace() / h
}

// A monitor that reads the time.
#[reduced_lagrangian(direction(n), group(t), time(t), adapt = |q| 1.0 + q.t * q.t, rule = trapezoid)]
fn clock_monitor(q: Config, v: Velocity) -> f64 {
    0.5 * v.n.norm_squared() - q.n.z
}

// A Lagrangian that reads the time.
#[reduced_lagrangian(direction(n), group(t), time(t), adapt = |q| 1.5 + q.n.z, rule = trapezoid)]
fn clock_lagrangian(q: Config, v: Velocity) -> f64 {
    0.5 * v.n.norm_squared() - q.n.z * v.t
}

fn main() {}
