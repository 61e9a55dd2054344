use dirac::prelude::*;

#[reduced_lagrangian(rotation(r[2]))]
fn chain(q0: Config, q1: Config, h: f64) -> f64 {
    h
}

fn main() {}
