//! A nonlinear membrane: the 2-D quasilinear wave equation
//! `ρ u_tt = ∇·(c² ∇u + β (∇u)³)` (component-wise cube) on a periodic `nx × ny` grid of spacing
//! `δ`, discretised in space by forward differences and in time by the midpoint rule; its
//! symmetry is the shift of the field, `u ↦ u + c`, with the total momentum `Σ p` conserved.
//! Shared by `examples/wave2d.rs` and `tests/element_wise.rs` (included with `#[path]`).

use std::f64::consts::PI;

use dirac::prelude::*;

/// `L = Σ_{i,j} δ² (ρ/2 u̇²_{ij} − c²/2 |∇u|²_{ij} − β/4 (u_x⁴ + u_y⁴)_{ij})`, forward
/// differences with periodic wrap.
#[reduced_lagrangian(coordinates(u[nx][ny]), translate(u), rule = midpoint)]
pub fn membrane(
    q: Config,
    v: Velocity,
    rho: f64,
    c2: f64,
    beta: f64,
    delta: f64,
    nx: usize,
    ny: usize,
) -> f64 {
    let mut l = 0.0;
    for i in 0..nx {
        for j in 0..ny {
            let ux = (q.u[(i + 1) % nx][j] - q.u[i][j]) / delta;
            let uy = (q.u[i][(j + 1) % ny] - q.u[i][j]) / delta;
            let w = v.u[i][j];
            l += delta
                * delta
                * (0.5 * rho * w * w
                    - 0.5 * c2 * (ux * ux + uy * uy)
                    - 0.25 * beta * (ux.powi(4) + uy.powi(4)));
        }
    }
    l
}

/// A Gaussian bump moving diagonally on a drifting field: `u = a exp(−r²/(2w²))`, momentum
/// `ρ δ² (s ∂_x u + drift)`.
pub fn initial(sys: &Membrane, a: f64, width: f64, s: f64, drift: f64) -> ElementState {
    let (nx, ny) = (sys.nx, sys.ny);
    let (lx, ly) = (nx as f64 * sys.delta, ny as f64 * sys.delta);
    let bump = |i: usize, j: usize| {
        let x = i as f64 * sys.delta - 0.5 * lx;
        let y = j as f64 * sys.delta - 0.5 * ly;
        let r2 = x * x + y * y;
        (
            a * (-r2 / (2.0 * width * width)).exp(),
            -x / (width * width),
        )
    };
    let mut q = DVector::zeros(nx * ny);
    let mut p = DVector::zeros(nx * ny);
    let mass = sys.rho * sys.delta * sys.delta;
    for i in 0..nx {
        for j in 0..ny {
            let (u, dudx_over_u) = bump(i, j);
            q[i * ny + j] = u + 0.01 * a * (2.0 * PI * j as f64 / ny as f64).sin();
            p[i * ny + j] = mass * (s * u * dudx_over_u + drift);
        }
    }
    ElementState::new(q, p)
}
