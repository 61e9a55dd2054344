use dirac::prelude::*;

#[reduced_lagrangian(shape(x, y), group(theta, phi), connection = [[0.0, 1.0]])]
fn particle(q0: Config, q1: Config, h: f64, m: f64) -> f64 {
    let (dx, dy) = (q1.x - q0.x, q1.y - q0.y);
    let (dg, dp) = (q1.theta - q0.theta, q1.phi - q0.phi);
    0.5 * m / h * (dx * dx + dy * dy + dg * dg + dp * dp)
}

fn main() {}
