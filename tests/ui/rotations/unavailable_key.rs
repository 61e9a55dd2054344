use dirac::prelude::*;

#[reduced_lagrangian(rotation(r), shape(x), constraints = |q| [q.x])]
fn body(q0: Config, q1: Config, h: f64) -> f64 {
    ((q0.r.transpose() * q1.r).trace() + q1.x - q0.x) / h
}

fn main() {}
