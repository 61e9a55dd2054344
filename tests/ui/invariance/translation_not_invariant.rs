use dirac::prelude::*;

/// A harmonic trap `x[0]²` pins the first particle: not invariant under the common translation.
#[reduced_lagrangian(coordinates(x[3]), translate(x), rule = midpoint)]
fn trapped_chain(q: Config, v: Velocity, m: f64) -> f64 {
    let mut l = 0.0;
    for i in 0..3 {
        l += 0.5 * m * v.x[i] * v.x[i] - (q.x[i] - q.x[(i + 1) % 3]).powi(2);
    }
    l - q.x[0] * q.x[0]
}

fn main() {}
