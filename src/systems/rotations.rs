//! Systems on rotation groups, written with `rotation(..)` and `direction(..)` coordinates
//! (see [`crate::lie`] and the guide's chapter on rotations): the free rigid body, the heavy top
//! (a rigid body on a fixed point in a uniform field, the 3-D pendulum), a satellite with a
//! reaction wheel, and the paper's double spherical pendulum on `S² × S²` with no charts.
//!
//! Every discrete Lagrangian here is symmetric (`L_d(q0, q1; −h) = −L_d(q1, q0; h)`), so its
//! step has order 2 and the compositions of [`crate::runtime::compose`] raise it to 4 and 6.

use crate::paper::{DoubleSphericalPendulum, DoubleSphericalPendulumContinuous};
use crate::prelude::*;
use crate::runtime::ContinuousLagrangian;

/// The free rigid body with principal moments of inertia `j1, j2, j3`: the discrete Lagrangian
/// of the Lie group variational integrator (Lee, Leok & McClamroch 2005),
/// `L_d(R0, R1) = tr((I − F) J_d)/h` with the relative rotation `F = R0ᵀ R1` and the nonstandard
/// inertia `J_d = ½ tr(J) I − J`. It is invariant under `R ↦ g R`, so the spatial angular
/// momentum `π = R Π` is conserved ([`LieIntegrator::spatial_momentum`]); declared
/// `symmetry(r)`, it also runs reduced ([`ReducedLieIntegrator`]: the discrete Euler–Poincaré
/// equations, `π` a parameter of the run).
#[reduced_lagrangian(rotation(r), symmetry(r))]
pub fn rigid_body(q0: Config, q1: Config, h: f64, j1: f64, j2: f64, j3: f64) -> f64 {
    let jd = Matrix3::from_diagonal(&Vector3::new(j2 + j3 - j1, j1 + j3 - j2, j1 + j2 - j3)) * 0.5;
    let f = q0.r.transpose() * q1.r;
    ((Matrix3::identity() - f) * jd).trace() / h
}

impl RigidBody {
    /// The body's energy `½ Πᵀ J⁻¹ Π` at `state`, with the stored discrete momentum `Π` (the
    /// discrete Legendre momentum, not `JΩ`: see [`crate::lie`]).
    pub fn energy(&self, state: &LieState<9, 3>) -> f64 {
        let pi = self.momenta(state).r;
        0.5 * pi.dot(&pi.component_div(&Vector3::new(self.j1, self.j2, self.j3)))
    }
}

/// The heavy top: a rigid body with principal moments `j1, j2, j3` on a fixed point, its centre
/// of mass on the body's third axis at distance `l`, in the field `(0, 0, −g)` (`mgl = m g l`):
/// `L_d = tr((I − F) J_d)/h − (h/2) m g l (R0[(2, 2)] + R1[(2, 2)])`, the trapezoid rule on the
/// potential `m g l e3ᵀ R e3`. With `j1 = j2` it is the Lagrange top; otherwise the 3-D pendulum
/// of Lee, Leok & McClamroch (2007). The rotations about the vertical keep the vertical component
/// of `π` (declared `symmetry(r, axis = z)`: [`ReducedLieIntegrator`] carries it as a parameter);
/// for `j1 = j2` the rotations about the body axis keep the axial body momentum `Π_3`.
#[reduced_lagrangian(rotation(r), symmetry(r, axis = z))]
pub fn heavy_top(q0: Config, q1: Config, h: f64, j1: f64, j2: f64, j3: f64, mgl: f64) -> f64 {
    let jd = Matrix3::from_diagonal(&Vector3::new(j2 + j3 - j1, j1 + j3 - j2, j1 + j2 - j3)) * 0.5;
    let f = q0.r.transpose() * q1.r;
    ((Matrix3::identity() - f) * jd).trace() / h - 0.5 * h * mgl * (q0.r[(2, 2)] + q1.r[(2, 2)])
}

impl HeavyTop {
    /// The energy `½ Πᵀ J⁻¹ Π + m g l e3ᵀ R e3` at `state`, with the stored discrete momentum
    /// `Π` (the discrete Legendre momentum, which differs from `JΩ` at first order in `h`, by
    /// the gravity torque among others: see [`crate::lie`]).
    pub fn energy(&self, state: &LieState<9, 3>) -> f64 {
        let (q, p) = (self.config(state), self.momenta(state));
        let omega = p.r.component_div(&Vector3::new(self.j1, self.j2, self.j3));
        0.5 * p.r.dot(&omega) + self.mgl * q.r[(2, 2)]
    }
}

/// A satellite with a reaction wheel: a rigid body (principal moments `j1, j2, j3`, wheel
/// included) and a wheel of axial moment `jw` spinning about the body's third axis by the angle
/// `phi`, driven by the motor torque `u` (a control). With the body's discrete angular velocity
/// `ω = vee(F − Fᵀ)/(2h)` (the Cayley parameter of `F` to second order),
/// `L_d = tr((I − F) J_d)/h + (h/2) jw (ω_3 + Δφ/h)²`, `Δφ = φ1 − φ0`, and the motor's virtual
/// work `(h/2) u (δφ0 + δφ1)` (the trapezoid rule on `u δφ`). The motor is internal: the
/// satellite's spatial angular momentum `π` is kept whatever `u` does, while the wheel's
/// momentum `p_φ` changes by exactly `h u` per step. Declared `symmetry(r)`, it runs reduced by
/// every rotation of the attitude ([`ReducedLieIntegrator`]: the discrete Lagrange–Poincaré
/// equations in `(Π, φ, p_φ)`).
#[reduced_lagrangian(rotation(r), shape(phi), symmetry(r), controls(u), force = |dq0, dq1| 0.5 * h * u * (dq0.phi + dq1.phi))]
#[allow(clippy::too_many_arguments)]
pub fn satellite(
    q0: Config,
    q1: Config,
    h: f64,
    j1: f64,
    j2: f64,
    j3: f64,
    jw: f64,
    u: f64,
) -> f64 {
    let jd = Matrix3::from_diagonal(&Vector3::new(j2 + j3 - j1, j1 + j3 - j2, j1 + j2 - j3)) * 0.5;
    let f = q0.r.transpose() * q1.r;
    let omega3 = 0.5 * (f[(1, 0)] - f[(0, 1)]) / h;
    let spin = omega3 + (q1.phi - q0.phi) / h;
    ((Matrix3::identity() - f) * jd).trace() / h + 0.5 * h * jw * spin * spin
}

/// The paper's double spherical pendulum (§7.2) on `S² × S²`: the directions `n1`, `n2` of the
/// two links, bobs at `r1 = l1 n1`, `r2 = r1 + l2 n2`, in the field `(0, 0, −g)`. The discrete
/// Lagrangian is the midpoint rule on the bobs' positions (chord velocities, the potential
/// averaged), the same as the Cartesian run with rod constraints of `examples/cartesian_dsp.rs`:
/// there is no chart, no singular configuration and no switch. The rotations about the vertical
/// are a symmetry (`symmetry(n1, n2, axis = z)`): [`ReducedLieIntegrator`] carries their
/// momentum, the vertical angular momentum, as a parameter.
#[reduced_lagrangian(direction(n1, n2), symmetry(n1, n2, axis = z))]
#[allow(clippy::too_many_arguments)]
pub fn dsp_on_spheres(
    q0: Config,
    q1: Config,
    h: f64,
    m1: f64,
    m2: f64,
    l1: f64,
    l2: f64,
    g: f64,
) -> f64 {
    let d1 = (q1.n1 - q0.n1) * l1;
    let d2 = d1 + (q1.n2 - q0.n2) * l2;
    let z1 = 0.5 * l1 * (q0.n1.z + q1.n1.z);
    let z2 = z1 + 0.5 * l2 * (q0.n2.z + q1.n2.z);
    (0.5 * m1 * d1.norm_squared() + 0.5 * m2 * d2.norm_squared()) / h - h * g * (m1 * z1 + m2 * z2)
}

impl DspOnSpheres {
    /// The paper's parameters ([`DoubleSphericalPendulum::paper`]) with time step `h`.
    pub fn paper(h: f64) -> Self {
        crate::paper::pendulum_parameters!(Self, DoubleSphericalPendulum::paper(), h = h)
    }

    /// The paper's initial state (§7.2) on `S² × S²`: the link directions, and their momenta from
    /// the bobs' velocities (`δr1 = l1 δn1`, `δr2 = l1 δn1 + l2 δn2`, so `P_n1 = l1 (p1 + p2)`
    /// and `P_n2 = l2 p2` with `p_i = m_i ṙ_i`).
    pub fn paper_initial_state(&self) -> LieState<18, 4> {
        let (r1, r2, v1, v2) = paper_bobs();
        let (p1, p2) = (v1 * self.m1, v2 * self.m2);
        self.state(
            &DspOnSpheresConfig {
                n1: r1 / self.l1,
                n2: (r2 - r1) / self.l2,
            },
            &DspOnSpheresMomentum {
                n1: (p1 + p2) * self.l1,
                n2: p2 * self.l2,
            },
        )
    }

    /// The positions of the two bobs at `state`.
    pub fn bobs(&self, state: &LieState<18, 4>) -> (Vector3<f64>, Vector3<f64>) {
        let q = self.config(state);
        let r1 = q.n1 * self.l1;
        (r1, r1 + q.n2 * self.l2)
    }

    /// The energy `½ m1 |ṙ1|² + ½ m2 |ṙ2|² + g (m1 z1 + m2 z2)` at `state`. In the tangent
    /// bases `(e1, e2)` of the two spheres the rates `v = (ṅ1·e1, ṅ1·e2, ṅ2·e1', ṅ2·e2')` give
    /// `ṙ1 = l1 ṅ1`, `ṙ2 = ṙ1 + l2 ṅ2`, the kinetic energy `½ vᵀ M v` and the momenta `M v`, which
    /// are the momenta's components in those bases: so the kinetic energy is `½ pᵀ M⁻¹ p`.
    pub fn energy(&self, state: &LieState<18, 4>) -> f64 {
        let (q, p) = (self.config(state), self.momenta(state));
        let (f1, f2) = (crate::lie::frame(&q.n1), crate::lie::frame(&q.n2));
        let zero = Vector3::zeros();
        // ∂ṙ1/∂v_k and ∂ṙ2/∂v_k.
        let dr1 = [f1.column(0) * self.l1, f1.column(1) * self.l1, zero, zero];
        let dr2 = [
            dr1[0],
            dr1[1],
            f2.column(0) * self.l2,
            f2.column(1) * self.l2,
        ];
        let mass = nalgebra::Matrix4::from_fn(|i, j| {
            self.m1 * dr1[i].dot(&dr1[j]) + self.m2 * dr2[i].dot(&dr2[j])
        });
        let momenta = nalgebra::Vector4::new(
            p.n1.dot(&f1.column(0)),
            p.n1.dot(&f1.column(1)),
            p.n2.dot(&f2.column(0)),
            p.n2.dot(&f2.column(1)),
        );
        let rates = mass.lu().solve(&momenta).unwrap_or_default();
        let (r1, r2) = (q.n1 * self.l1, q.n1 * self.l1 + q.n2 * self.l2);
        0.5 * momenta.dot(&rates) + self.g * (self.m1 * r1.z + self.m2 * r2.z)
    }
}

/// The bobs' positions and velocities `(r1, r2, ṙ1, ṙ2)` in the paper's initial state (§7.2),
/// from its angles and their rates: the state every Cartesian or spherical form of the double
/// spherical pendulum starts from.
pub fn paper_bobs() -> (Vector3<f64>, Vector3<f64>, Vector3<f64>, Vector3<f64>) {
    let paper = DoubleSphericalPendulum::paper();
    let continuous = DoubleSphericalPendulumContinuous::paper();
    let c0 = continuous.untrivialize(&DoubleSphericalPendulum::paper_initial_state());
    let v = continuous
        .velocity(0, &c0.q, &c0.p, SVector::zeros())
        .expect("the paper's state is regular");
    // q = (φ1, ϑ2, φ2, ϑ1) with the azimuths θ1 = ϑ1 − ϑ2, θ2 = ϑ1 + ϑ2 (see `crate::paper`).
    let (phi1, vt2, phi2, vt1) = (c0.q[0], c0.q[1], c0.q[2], c0.q[3]);
    let (dphi1, dvt2, dphi2, dvt1) = (v[0], v[1], v[2], v[3]);
    let (th1, th2, dth1, dth2) = (vt1 - vt2, vt1 + vt2, dvt1 - dvt2, dvt1 + dvt2);
    let (s1, c1, s2, c2) = (phi1.sin(), phi1.cos(), phi2.sin(), phi2.cos());
    let (st1, ct1, st2, ct2) = (th1.sin(), th1.cos(), th2.sin(), th2.cos());
    let (l1, l2) = (paper.l1, paper.l2);
    let v1 = Vector3::new(
        l1 * (c1 * ct1 * dphi1 - s1 * st1 * dth1),
        l1 * (c1 * st1 * dphi1 + s1 * ct1 * dth1),
        -l1 * s1 * dphi1,
    );
    let u2 = Vector3::new(
        l2 * (c2 * ct2 * dphi2 - s2 * st2 * dth2),
        l2 * (c2 * st2 * dphi2 + s2 * ct2 * dth2),
        -l2 * s2 * dphi2,
    );
    let (r1, r2) = paper.bob_positions(&c0.q);
    (Vector3::from(r1), Vector3::from(r2), v1, v1 + u2)
}
