use dirac::prelude::*;

#[reduced_lagrangian(shape(x[3]), group(theta))]
fn chain(q0: Config, q1: Config, h: f64, m: f64) -> f64 {
    let mut l = 0.5 * m / h * (q1.theta - q0.theta).powi(2);
    for i in 0..3 {
        l += 0.5 * m / h * (q1.x[i] - q0.x[i]).powi(2) - h * q0.x[i] * q0.x[i + 1];
    }
    l
}

fn main() {}
