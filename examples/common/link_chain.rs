//! A cart on a rail carrying a chain of `n` rigid links in maximal coordinates, with its size
//! chosen at run time: every link's end point `(x_i, y_i)` a coordinate and one length
//! constraint per link. Shared by `examples/maximal_chain.rs` and `tests/element_constraints.rs`
//! (included with `#[path]`).
#![allow(dead_code)]

use dirac::prelude::*;
use dirac::runtime::element::ElementState;

/// The chain of `n` links of length `l` under gravity `gr`, cart mass `mc`, end masses `m`.
#[reduced_lagrangian(coordinates(c, x[n], y[n]), rule = midpoint,
    constraints = |q| {
        let mut phi = vec![0.0; n];
        phi[0] = (q.x[0] - q.c) * (q.x[0] - q.c) + q.y[0] * q.y[0] - l * l;
        for i in 1..n {
            let (dx, dy) = (q.x[i] - q.x[i - 1], q.y[i] - q.y[i - 1]);
            phi[i] = dx * dx + dy * dy - l * l;
        }
        phi
    })]
pub fn link_chain(q: Config, v: Velocity, mc: f64, m: f64, l: f64, gr: f64, n: usize) -> f64 {
    let mut t = 0.5 * mc * v.c * v.c;
    for i in 0..n {
        t += 0.5 * m * (v.x[i] * v.x[i] + v.y[i] * v.y[i]) - m * gr * q.y[i];
    }
    t
}

/// The chain of `n` links of length `l` at the angles `θ_i = 0.3 sin(i + 1)` from the vertical
/// (the scaling benchmark's state), the cart at 0, at rest.
pub fn hanging(n: usize, l: f64) -> ElementState {
    let mut q = DVector::zeros(2 * n + 1);
    let (mut x, mut y) = (0.0, 0.0);
    for i in 0..n {
        let th = 0.3 * ((i + 1) as f64).sin();
        x += l * th.sin();
        y -= l * th.cos();
        q[1 + i] = x;
        q[1 + n + i] = y;
    }
    ElementState::new(q, DVector::zeros(2 * n + 1))
}
