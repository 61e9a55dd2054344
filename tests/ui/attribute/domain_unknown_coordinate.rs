use dirac::prelude::*;

#[reduced_lagrangian(shape(r), group(phi), domain(s > 0.0))]
fn kepler(q0: Config, q1: Config, h: f64, k: f64) -> f64 {
    let r = 0.5 * (q0.r + q1.r);
    let (dr, dphi) = ((q1.r - q0.r) / h, (q1.phi - q0.phi) / h);
    h * (0.5 * (dr * dr + r * r * dphi * dphi) + k / r)
}

fn main() {}
