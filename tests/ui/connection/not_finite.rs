use dirac::prelude::*;

// B = sqrt(b − 3) is not a number for any b in the default sampling range [0.5, 2].
#[reduced_lagrangian(shape(x), group(theta), connection = [[(b - 3.0).sqrt()]])]
fn particle(q0: Config, q1: Config, h: f64, m: f64, b: f64) -> f64 {
    let (dx, dg) = (q1.x - q0.x, q1.theta - q0.theta);
    0.5 * m / h * (dx * dx + dg * dg)
}

fn main() {}
