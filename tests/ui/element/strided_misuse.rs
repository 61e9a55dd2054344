use dirac::prelude::*;

// A length that is a product of two sizes.
#[reduced_lagrangian(coordinates(x[m * n]), rule = midpoint)]
fn product(q: Config, v: Velocity, n: usize, m: usize) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        l += 0.5 * v.x[i] * v.x[i] - 0.5 * q.x[i] * q.x[i];
    }
    l
}

// A strided read past the end: point `i + 1` of the last particle.
#[reduced_lagrangian(coordinates(x[3 * n]), rule = midpoint)]
fn past(q: Config, v: Velocity, n: usize) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        for d in 0..3 {
            l += 0.5 * v.x[3 * i + d] * v.x[3 * i + d] - 0.5 * q.x[3 * (i + 1) + d].powi(2);
        }
    }
    l
}

fn main() {}
