use dirac::prelude::*;

#[reduced_lagrangian(rotation(r), group(x))]
fn body(q0: Config, q1: Config, h: f64, g: f64) -> f64 {
    let f = q0.r.transpose() * q1.r;
    (Matrix3::identity() - f).trace() / h + 0.5 * (q1.x - q0.x) * (q1.x - q0.x) / h - h * g * q0.x
}

fn main() {}
