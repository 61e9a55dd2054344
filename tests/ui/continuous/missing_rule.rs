use dirac::prelude::*;

#[reduced_lagrangian(shape(x), group())]
fn particle(q: Config, v: Velocity, m: f64) -> f64 {
    0.5 * m * v.x * v.x - q.x * q.x
}

fn main() {}
