//! The periodic Toda lattice with its size chosen at run time: one build serves every `n`.
//! Shared by `examples/toda_n.rs`, `examples/scaling.rs` and `tests/element_wise.rs` (included
//! with `#[path]`).

use std::f64::consts::PI;

use dirac::prelude::*;

/// The periodic Toda lattice of `n` particles in their own positions, `x_n ≡ x_0 + n d`,
/// midpoint rule; the symmetry is the common translation of all `x[i]`.
#[reduced_lagrangian(coordinates(x[n]), translate(x), rule = midpoint)]
pub fn toda_n(q: Config, v: Velocity, m: f64, d: f64, n: usize) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        l += 0.5 * m * v.x[i] * v.x[i];
    }
    for i in 0..n - 1 {
        l -= (-(q.x[i + 1] - q.x[i] - d)).exp();
    }
    l - (-(q.x[0] + n as f64 * d - q.x[n - 1] - d)).exp()
}

/// The same lattice with a damping force `−c ẋ_i` on every particle (the forced step of a
/// run-time-sized system).
#[reduced_lagrangian(coordinates(x[n]), translate(x), rule = midpoint,
    force = |dq| {
        let mut w = 0.0;
        for i in 0..n {
            w -= c * v.x[i] * dq.x[i];
        }
        w
    })]
pub fn damped_toda_n(q: Config, v: Velocity, m: f64, d: f64, c: f64, n: usize) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        l += 0.5 * m * v.x[i] * v.x[i];
    }
    for i in 0..n - 1 {
        l -= (-(q.x[i + 1] - q.x[i] - d)).exp();
    }
    l - (-(q.x[0] + n as f64 * d - q.x[n - 1] - d)).exp()
}

/// A displaced, moving lattice: `x_i = i d + a sin(2π i/n)`, `p_i = m (b cos(2π i/n) + c)`.
pub fn initial(sys: &TodaN, a: f64, b: f64, c: f64) -> ElementState {
    let n = sys.n;
    let phase = |i: usize| 2.0 * PI * i as f64 / n as f64;
    let q = DVector::from_fn(n, |i, _| i as f64 * sys.d + a * phase(i).sin());
    let p = DVector::from_fn(n, |i, _| sys.m * (b * phase(i).cos() + c));
    ElementState::new(q, p)
}
