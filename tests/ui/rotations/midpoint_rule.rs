use dirac::prelude::*;

#[reduced_lagrangian(rotation(r), rule = midpoint)]
fn body(q: Config, v: Velocity, h: f64) -> f64 {
    h
}

fn main() {}
