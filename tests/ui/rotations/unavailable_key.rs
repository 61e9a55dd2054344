use dirac::prelude::*;

#[reduced_lagrangian(rotation(r), shape(x), group(theta))]
fn body(q0: Config, q1: Config, h: f64) -> f64 {
    ((q0.r.transpose() * q1.r).trace() + q1.x - q0.x + q1.theta) / h
}

fn main() {}
