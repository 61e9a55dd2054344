use dirac::prelude::*;

#[reduced_lagrangian(shape(x), group(), rule = left)]
fn particle(v: Velocity, q: Config, m: f64) -> f64 {
    0.5 * m * v.x * v.x - q.x * q.x
}

fn main() {}
