use dirac::prelude::*;

#[reduced_lagrangian(rotation(r))]
fn body(q0: Config, q1: Config, h: f64) -> f64 {
    let f = q0.r.transpose() * q1.r;
    let omega = vee(&f) / h;
    0.5 * h * omega.norm_squared()
}

fn main() {}
