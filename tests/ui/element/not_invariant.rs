use dirac::prelude::*;

#[reduced_lagrangian(coordinates(x[n]), translate(x), rule = midpoint)]
fn pinned(q: Config, v: Velocity, m: f64, n: usize) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        l += 0.5 * m * v.x[i] * v.x[i] - 0.5 * q.x[i] * q.x[i];
    }
    l
}

fn main() {}
