use dirac::prelude::*;

#[reduced_lagrangian(coordinates(x[3]), translate(w), rule = midpoint)]
fn chain(q: Config, v: Velocity, m: f64) -> f64 {
    let mut l = 0.0;
    for i in 0..3 {
        l += 0.5 * m * v.x[i] * v.x[i] - (q.x[i] - q.x[(i + 1) % 3]).exp();
    }
    l
}

fn main() {}
