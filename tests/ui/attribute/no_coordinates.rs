use dirac::prelude::*;

#[reduced_lagrangian(shape(), group())]
fn nothing(q0: Config, q1: Config, h: f64) -> f64 {
    h
}

fn main() {}
