use dirac::prelude::*;

// A driven oscillator reads the time: it is not autonomous.
#[reduced_lagrangian(shape(x), group(t), time(t), adapt = |q| 1.0 + q.x * q.x, rule = midpoint)]
fn driven(q: Config, v: Velocity, w: f64) -> f64 {
    0.5 * v.x * v.x - 0.5 * q.x * q.x + q.x * (w * q.t).cos()
}

fn main() {}
