use dirac::prelude::*;

// The time translated with the bodies: it is not a coordinate of its own.
#[reduced_lagrangian(coordinates(x[2], t), translate(x, t), time(t), adapt = |q| 1.0 + (q.x[1] - q.x[0]).powi(2), rule = midpoint)]
fn shared(q: Config, v: Velocity) -> f64 {
    0.5 * (v.x[0] * v.x[0] + v.x[1] * v.x[1]) - (q.x[1] - q.x[0]).powi(2)
}

// A monitor that reads where the bodies are, not how far apart: it breaks the translation.
#[reduced_lagrangian(coordinates(x[2], t), translate(x), translate(t), time(t), adapt = |q| 1.0 + q.x[0] * q.x[0], rule = midpoint)]
fn placed(q: Config, v: Velocity) -> f64 {
    0.5 * (v.x[0] * v.x[0] + v.x[1] * v.x[1]) - (q.x[1] - q.x[0]).powi(2)
}

fn main() {}
