//! The periodic Toda lattice of 200 particles, written in the particles' own positions with its
//! common translation declared: shared by `examples/lattice.rs` and `tests/driver.rs` (included
//! with `#[path]`, not part of `common/`, so that the other examples do not compile it).

use std::f64::consts::PI;

use dirac::prelude::*;

/// The number of particles.
pub const N: usize = 200;

/// The periodic Toda lattice, midpoint rule; the symmetry is a common translation of all `x[i]`.
#[reduced_lagrangian(coordinates(x[200]), translate(x), rule = midpoint)]
pub fn toda(q: Config, v: Velocity, m: f64, d: f64) -> f64 {
    let mut l = 0.0;
    for i in 0..200 {
        l += 0.5 * m * v.x[i] * v.x[i];
    }
    for i in 0..199 {
        l -= (-(q.x[i + 1] - q.x[i] - d)).exp();
    }
    l - (-(q.x[0] + 200.0 * d - q.x[199] - d)).exp()
}

/// A displaced, moving lattice: `x_i = i d + a sin(2π i/n)`, `v_i = b cos(2π i/n) + c`.
pub fn initial(sys: &Toda, a: f64, b: f64, c: f64) -> ReducedState<199, 1> {
    let q = SVector::<f64, N>::from_fn(|i, _| {
        i as f64 * sys.d + a * (2.0 * PI * i as f64 / N as f64).sin()
    });
    let p =
        SVector::<f64, N>::from_fn(|i, _| sys.m * (b * (2.0 * PI * i as f64 / N as f64).cos() + c));
    sys.trivialize(&Toda::adapted_state(&q, &p))
}
