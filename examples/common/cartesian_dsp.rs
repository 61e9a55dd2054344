//! The paper's double spherical pendulum in Cartesian coordinates with two rod constraints:
//! shared by `examples/cartesian_dsp.rs` and `tests/constraints.rs` (included with `#[path]`).

use dirac::paper::DoubleSphericalPendulum;
use dirac::prelude::*;

/// Two bobs at `r1 = (x1, y1, z1)`, `r2`, hanging from the origin on rods of lengths `l1`, `l2`
/// (`z` up), midpoint rule.
#[reduced_lagrangian(shape(x1, y1, z1, x2, y2, z2), group(), rule = midpoint,
    constraints = |q| [
        q.x1 * q.x1 + q.y1 * q.y1 + q.z1 * q.z1 - l1 * l1,
        (q.x2 - q.x1) * (q.x2 - q.x1) + (q.y2 - q.y1) * (q.y2 - q.y1) + (q.z2 - q.z1) * (q.z2 - q.z1) - l2 * l2,
    ])]
#[allow(clippy::too_many_arguments)]
pub fn cartesian_dsp(q: Config, v: Velocity, m1: f64, m2: f64, l1: f64, l2: f64, g: f64) -> f64 {
    0.5 * m1 * (v.x1 * v.x1 + v.y1 * v.y1 + v.z1 * v.z1)
        + 0.5 * m2 * (v.x2 * v.x2 + v.y2 * v.y2 + v.z2 * v.z2)
        - g * (m1 * q.z1 + m2 * q.z2)
}

/// The paper's initial state in Cartesian positions and momenta.
pub fn cartesian_initial(h: f64) -> (CartesianDsp, UnreducedState<6>) {
    let paper = DoubleSphericalPendulum::paper();
    let (r1, r2, v1, v2) = dirac::systems::rotations::paper_bobs();
    let sys = CartesianDsp {
        h,
        m1: paper.m1,
        m2: paper.m2,
        l1: paper.l1,
        l2: paper.l2,
        g: paper.g,
    };
    let (p1, p2) = (v1 * sys.m1, v2 * sys.m2);
    let q = [r1.x, r1.y, r1.z, r2.x, r2.y, r2.z];
    let p = [p1.x, p1.y, p1.z, p2.x, p2.y, p2.z];
    (sys, UnreducedState::new(q, p))
}

/// `max_j |φ_j(q)| / l_j²`.
pub fn sys_residual(sys: &CartesianDsp, s: &UnreducedState<6>) -> f64 {
    let phi = sys.constraint(&s.q);
    (phi[0] / (sys.l1 * sys.l1))
        .abs()
        .max((phi[1] / (sys.l2 * sys.l2)).abs())
}
