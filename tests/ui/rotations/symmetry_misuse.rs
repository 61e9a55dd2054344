use dirac::prelude::*;

// Every rotation acts on one rotation coordinate; a scalar is not rotated; axes are x, y or z.
#[reduced_lagrangian(rotation(a, b), shape(x), symmetry(a, b))]
fn two(q0: Config, q1: Config, h: f64) -> f64 {
    let (f, g) = (q0.a.transpose() * q1.a, q0.b.transpose() * q1.b);
    (Matrix3::identity() * 2.0 - f - g).trace() / h + 0.5 * (q1.x - q0.x) * (q1.x - q0.x) / h
}

#[reduced_lagrangian(rotation(r), shape(x), symmetry(r, x))]
fn scalar(q0: Config, q1: Config, h: f64) -> f64 {
    let f = q0.r.transpose() * q1.r;
    (Matrix3::identity() - f).trace() / h + 0.5 * (q1.x - q0.x) * (q1.x - q0.x) / h
}

#[reduced_lagrangian(direction(n), symmetry(n, axis = w))]
fn axis(q0: Config, q1: Config, h: f64) -> f64 {
    0.5 * (q1.n - q0.n).norm_squared() / h
}

#[reduced_lagrangian(direction(n), symmetry(n))]
fn direction(q0: Config, q1: Config, h: f64) -> f64 {
    0.5 * (q1.n - q0.n).norm_squared() / h
}

fn main() {}
