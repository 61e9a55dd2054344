use dirac::prelude::*;

#[reduced_lagrangian(rotation(r))]
fn body(q0: Config, q1: Config, h: f64) -> f64 {
    (q0.r.transpose() * q1.r).sin() / h
}

fn main() {}
