use dirac::prelude::*;

#[reduced_lagrangian(coordinates(x[n]), rule = midpoint)]
fn lattice(q: Config, v: Velocity, m: f64, n: usize) -> f64 {
    let mut l = 0.0;
    for i in 0..m {
        l += 0.5 * v.x[i] * v.x[i];
    }
    l
}

fn main() {}
