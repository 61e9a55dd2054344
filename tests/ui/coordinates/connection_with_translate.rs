use dirac::prelude::*;

#[reduced_lagrangian(coordinates(x[2]), translate(x), connection = [[0.5]])]
fn pair(q0: Config, q1: Config, h: f64, m: f64) -> f64 {
    let (d0, d1) = (q1.x[0] - q0.x[0], q1.x[1] - q0.x[1]);
    0.5 * m / h * (d0 * d0 + d1 * d1) - h * (q0.x[1] - q0.x[0]).powi(2)
}

fn main() {}
