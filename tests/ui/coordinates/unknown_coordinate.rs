use dirac::prelude::*;

#[reduced_lagrangian(shape(x, y, z), group(theta))]
fn charged_particle(q0: Config, q1: Config, h: f64, m: f64) -> f64 {
    let (dx, dy, dz) = (q1.x - q0.x, q1.y - q0.w, q1.z - q0.z);
    let dg = q1.theta - q0.theta;
    0.5 * m / h * (dx * dx + dy * dy + dz * dz + dg * dg)
}

fn main() {}
