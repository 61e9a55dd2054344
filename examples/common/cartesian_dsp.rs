//! The paper's double spherical pendulum in Cartesian coordinates with two rod constraints:
//! shared by `examples/cartesian_dsp.rs` and `tests/constraints.rs` (included with `#[path]`).

use dirac::paper::{DoubleSphericalPendulum, DoubleSphericalPendulumContinuous};
use dirac::prelude::*;
use dirac::runtime::ContinuousLagrangian;

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
    let continuous = DoubleSphericalPendulumContinuous::paper();
    let s0 = DoubleSphericalPendulum::paper_initial_state();
    let c0 = continuous.untrivialize(&s0);
    let v = continuous
        .velocity(0, &c0.q, &c0.p, SVector::zeros())
        .expect("the paper's state is regular");
    // q = (φ1, ϑ2, φ2, ϑ1) with the azimuths θ1 = ϑ1 − ϑ2, θ2 = ϑ1 + ϑ2 (src/paper.rs).
    let (phi1, vt2, phi2, vt1) = (c0.q[0], c0.q[1], c0.q[2], c0.q[3]);
    let (dphi1, dvt2, dphi2, dvt1) = (v[0], v[1], v[2], v[3]);
    let (th1, th2, dth1, dth2) = (vt1 - vt2, vt1 + vt2, dvt1 - dvt2, dvt1 + dvt2);
    let (s1, c1, s2, c2) = (phi1.sin(), phi1.cos(), phi2.sin(), phi2.cos());
    let (st1, ct1, st2, ct2) = (th1.sin(), th1.cos(), th2.sin(), th2.cos());
    let (l1, l2) = (paper.l1, paper.l2);
    let v1 = [
        l1 * (c1 * ct1 * dphi1 - s1 * st1 * dth1),
        l1 * (c1 * st1 * dphi1 + s1 * ct1 * dth1),
        -l1 * s1 * dphi1,
    ];
    let u2 = [
        l2 * (c2 * ct2 * dphi2 - s2 * st2 * dth2),
        l2 * (c2 * st2 * dphi2 + s2 * ct2 * dth2),
        -l2 * s2 * dphi2,
    ];
    let (r1, r2) = paper.bob_positions(&c0.q);
    let sys = CartesianDsp {
        h,
        m1: paper.m1,
        m2: paper.m2,
        l1,
        l2,
        g: paper.g,
    };
    let p = [
        sys.m1 * v1[0],
        sys.m1 * v1[1],
        sys.m1 * v1[2],
        sys.m2 * (v1[0] + u2[0]),
        sys.m2 * (v1[1] + u2[1]),
        sys.m2 * (v1[2] + u2[2]),
    ];
    let q = [r1[0], r1[1], r1[2], r2[0], r2[1], r2[2]];
    (sys, UnreducedState::new(q, p))
}

/// `max_j |φ_j(q)| / l_j²`.
pub fn sys_residual(sys: &CartesianDsp, s: &UnreducedState<6>) -> f64 {
    let phi = sys.constraint(&s.q);
    (phi[0] / (sys.l1 * sys.l1))
        .abs()
        .max((phi[1] / (sys.l2 * sys.l2)).abs())
}
