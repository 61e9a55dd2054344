use dirac::prelude::*;

#[reduced_lagrangian(coordinates(x[n]), rule = midpoint, nonholonomic = |q, v| [v.x[0]])]
fn lattice(q: Config, v: Velocity, m: f64, n: usize) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        l += 0.5 * m * v.x[i] * v.x[i];
    }
    l
}

fn main() {}
