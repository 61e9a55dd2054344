//! The systems of the paper's §7, ready to integrate, written with `#[reduced_lagrangian]` exactly
//! as a user would write them.

use crate::prelude::*;

/// The double spherical pendulum's parameters, those of `p` (a [`DoubleSphericalPendulum`]), as
/// the type `$ty` of another of its formulations (each has the fields `h, m1, m2, l1, l2, g`),
/// with the time step `h` where one is given.
macro_rules! pendulum_parameters {
    ($ty:ident, $p:expr) => {{
        let p: &$crate::paper::DoubleSphericalPendulum = &$p;
        $crate::paper::pendulum_parameters!($ty, p, h = p.h)
    }};
    ($ty:ident, $p:expr, h = $h:expr) => {{
        let p: &$crate::paper::DoubleSphericalPendulum = &$p;
        $ty {
            h: $h,
            m1: p.m1,
            m2: p.m2,
            l1: p.l1,
            l2: p.l2,
            g: p.g,
        }
    }};
}
pub(crate) use pendulum_parameters;

pub mod atlas;

/// Charged particle in a magnetic field in Kaluza–Klein form (§7.1), with the left-point rule
/// `L_d(q0, q1) = h L_K(q0, (q1 − q0)/h)` and the vector potential of the constant field
/// `B = b0 ∂_z`, `A(q) = (b0/2)(−q² dq¹ + q¹ dq²)`:
///
/// `L_K = ½ m |q̇|² + ½ (⟨A(q), q̇⟩ + θ̇)²`.
///
/// The group `S¹` translates `θ`; the connection is `ω_d = θ1 − θ0` (B = 0).
#[reduced_lagrangian(shape(x, y, z), group(theta))]
pub fn charged_particle(q0: Config, q1: Config, h: f64, m: f64, b0: f64) -> f64 {
    let (dx, dy, dz) = (q1.x - q0.x, q1.y - q0.y, q1.z - q0.z);
    let a_dot_dq = 0.5 * b0 * (-q0.y * dx + q0.x * dy);
    let s = a_dot_dq + (q1.theta - q0.theta);
    0.5 * m / h * (dx * dx + dy * dy + dz * dz) + 0.5 / h * s * s
}

impl ChargedParticle {
    /// The paper's run (§7.2.1): `m = 1`, `B0 = 1`, time step `T / steps` with `T = 20`.
    pub fn paper(steps: usize) -> Self {
        Self {
            h: CHARGED_PARTICLE_T / steps as f64,
            m: 1.0,
            b0: 1.0,
        }
    }

    /// The paper's initial state: `q0 = 0`, `θ0 = 0`, `w0 = (1, 0, 1)`, `μ0 = 1` (eq. (3.6)).
    pub fn paper_initial_state() -> ReducedState<3, 1> {
        ReducedState::new([0.0; 3], [1.0, 0.0, 1.0], [1.0], [0.0])
    }

    /// The exact solution of the Lorentz force law (7.1) for `B0 = 1` from the paper's initial
    /// state: `q(t) = (sin t, cos t − 1, t)`.
    pub fn exact_position(t: f64) -> [f64; 3] {
        [t.sin(), t.cos() - 1.0, t]
    }
}

/// The final time of the charged-particle run, `T = 20`.
pub const CHARGED_PARTICLE_T: f64 = 20.0;

/// `|q(T) − q_N|` printed in the paper's Table 1, for `N = 10, 50, 100, 200`.
pub const TABLE_1: [(usize, f64); 4] =
    [(10, 1.6781), (50, 0.25971), (100, 0.06626), (200, 0.01664)];

/// Double spherical pendulum (§7.2): two point masses `m1`, `m2` on massless rigid links of
/// lengths `l1`, `l2`, the first hinged at a fixed pivot, in the uniform field `(0, 0, −g)`.
///
/// Each bob is placed in spherical coordinates about its own origin (the pivot, resp. the first
/// bob), `r1 = l1 (sin φ1 cos θ1, sin φ1 sin θ1, cos φ1)` and
/// `r2 = r1 + l2 (sin φ2 cos θ2, sin φ2 sin θ2, cos φ2)`, so `Q = S² × S²` with angles
/// `(θ1, φ1, θ2, φ2)`, and the paper changes coordinates to `ϑ1 = (θ1 + θ2)/2`,
/// `ϑ2 = (θ2 − θ1)/2`. The symmetry is the simultaneous rotation of both pendula about the
/// vertical axis, `G = S¹`, which translates `ϑ1` only: the shape is `x = (φ1, ϑ2, φ2)` and the
/// group coordinate is `ϑ1` (fields `phi1, vt2, phi2, vt1`, in this order in the configuration
/// vector). The connection is `ω_d = ϑ1⁺ − ϑ1` (B = 0).
///
/// The discrete Lagrangian is the midpoint rule `L_d(q0, q1) = h L((q0 + q1)/2, (q1 − q0)/h)`
/// (§7.2.1), with
///
/// `L = ½ m1 |ṙ1|² + ½ m2 |ṙ2|² − g (m1 l1 cos φ1 + m2 (l1 cos φ1 + l2 cos φ2))`,
///
/// the velocities `ṙ1`, `ṙ2` written out by the chain rule. This is the paper's `L` (its `T2`
/// expanded), in the "cartesian" form of the CasADi benchmark's `lagrangian()`.
///
/// Remark 7.1: the rotation is not free — it fixes the configurations with `φ1, φ2 ∈ πZ` (a bob
/// on the vertical axis), where these coordinates are singular. The reduced equations are valid
/// only along trajectories that avoid them.
#[reduced_lagrangian(shape(phi1, vt2, phi2), group(vt1))]
#[allow(clippy::too_many_arguments)]
pub fn double_spherical_pendulum(
    q0: Config,
    q1: Config,
    h: f64,
    m1: f64,
    m2: f64,
    l1: f64,
    l2: f64,
    g: f64,
) -> f64 {
    // The midpoint and the difference quotient of the midpoint rule.
    let (phi1, vt2, phi2, vt1) = (
        0.5 * (q0.phi1 + q1.phi1),
        0.5 * (q0.vt2 + q1.vt2),
        0.5 * (q0.phi2 + q1.phi2),
        0.5 * (q0.vt1 + q1.vt1),
    );
    let (dphi1, dvt2, dphi2, dvt1) = (
        (q1.phi1 - q0.phi1) / h,
        (q1.vt2 - q0.vt2) / h,
        (q1.phi2 - q0.phi2) / h,
        (q1.vt1 - q0.vt1) / h,
    );
    // Back to the azimuths of the two bobs.
    let (th1, th2) = (vt1 - vt2, vt1 + vt2);
    let (dth1, dth2) = (dvt1 - dvt2, dvt1 + dvt2);
    let (s1, c1, s2, c2) = (phi1.sin(), phi1.cos(), phi2.sin(), phi2.cos());
    let (st1, ct1, st2, ct2) = (th1.sin(), th1.cos(), th2.sin(), th2.cos());
    // ṙ1, and ṙ2 = ṙ1 + u2 with u2 the velocity of the second bob relative to the first.
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
    let v2 = [v1[0] + u2[0], v1[1] + u2[1], v1[2] + u2[2]];
    let kinetic = 0.5 * m1 * (v1[0] * v1[0] + v1[1] * v1[1] + v1[2] * v1[2])
        + 0.5 * m2 * (v2[0] * v2[0] + v2[1] * v2[1] + v2[2] * v2[2]);
    let potential = g * (m1 * l1 * c1 + m2 * (l1 * c1 + l2 * c2));
    h * (kinetic - potential)
}

impl DoubleSphericalPendulum {
    /// The paper's run (§7.2.2): `T = 100`, `N = 10⁴` (so `h = 0.01`), `m1 = 20`, `m2 = 35`,
    /// `l1 = 500`, `l2 = 800`, `g = 9.8` (SI units).
    pub fn paper() -> Self {
        Self {
            h: DSP_T / DSP_STEPS as f64,
            m1: 20.0,
            m2: 35.0,
            l1: 500.0,
            l2: 800.0,
            g: 9.8,
        }
    }

    /// The paper's initial state (§7.2.2): `q0 = (ϑ1, φ1, ϑ2, φ2) = (0, 9/4, 2, 3)` and
    /// `(μ0, w0) = (0, 0, 1, 1)`, i.e. `x = (φ1, ϑ2, φ2) = (9/4, 2, 3)`, `w = (0, 1, 1)`, `μ = 0`
    /// and `ϑ1 = 0` (the momenta trivialized by (3.6), `p0 = (μ0, w0)` since B = 0).
    pub fn paper_initial_state() -> ReducedState<3, 1> {
        ReducedState::new([2.25, 2.0, 3.0], [0.0, 1.0, 1.0], [0.0], [0.0])
    }

    /// The Cartesian positions `(r1, r2)` of the two bobs at a configuration
    /// `q = (φ1, ϑ2, φ2, ϑ1)`, with the pivot at the origin and the `z` axis pointing up.
    pub fn bob_positions(&self, q: &SVector<f64, 4>) -> ([f64; 3], [f64; 3]) {
        let (phi1, vt2, phi2, vt1) = (q[0], q[1], q[2], q[3]);
        let (th1, th2) = (vt1 - vt2, vt1 + vt2);
        let r1 = [
            self.l1 * phi1.sin() * th1.cos(),
            self.l1 * phi1.sin() * th1.sin(),
            self.l1 * phi1.cos(),
        ];
        let r2 = [
            r1[0] + self.l2 * phi2.sin() * th2.cos(),
            r1[1] + self.l2 * phi2.sin() * th2.sin(),
            r1[2] + self.l2 * phi2.cos(),
        ];
        (r1, r2)
    }

    /// The physical energy `T + V` at the midpoint of the step `(q0, q1)`, with the velocity
    /// `(q1 − q0)/h`.
    ///
    /// Derived from `L_d` itself rather than from a second copy of the formula: `T` is quadratic
    /// in the velocities and `L_d` is the midpoint rule, so with `q_mid = (q0 + q1)/2`,
    /// `L_d(q0, q1) = h (T − V)(q_mid)` and `L_d(q_mid, q_mid) = −h V(q_mid)`, whence
    /// `T + V = (L_d(q0, q1) − 2 L_d(q_mid, q_mid)) / h`.
    pub fn physical_energy(&self, q0: &SVector<f64, 4>, q1: &SVector<f64, 4>) -> f64 {
        let mid = 0.5 * (q0 + q1);
        (self.lagrangian(q0, q1) - 2.0 * self.lagrangian(&mid, &mid)) / self.h
    }
}

/// The final time of the double-spherical-pendulum run, `T = 100`.
pub const DSP_T: f64 = 100.0;

/// The number of steps of the double-spherical-pendulum run, `N = 10⁴`.
pub const DSP_STEPS: usize = 10_000;

/// The charged particle of [`charged_particle`] written as the physics: the continuous
/// Kaluza–Klein Lagrangian `L_K(q, q̇) = ½ m |q̇|² + ½ (⟨A(q), q̇⟩ + θ̇)²` and the paper's left-point
/// rule, which the attribute applies to form `L_d(q0, q1) = h L_K(q0, (q1 − q0)/h)`. The emitted
/// type also implements [`ContinuousLagrangian`]: the Legendre map,
/// the energy, and initial states from `(q, q̇)`.
///
/// The steps agree with [`ChargedParticle`]'s to the last few ulps, not bit for bit: the
/// hand-written form divides by `h` once (`½ m / h · Δx²`) where `h · ½ m (Δx/h)²` rounds
/// `Δx/h` first (`tests/continuous.rs` measures the difference).
#[reduced_lagrangian(shape(x, y, z), group(theta), rule = left)]
pub fn charged_particle_continuous(q: Config, v: Velocity, m: f64, b0: f64) -> f64 {
    let a_dot_v = 0.5 * b0 * (-q.y * v.x + q.x * v.y);
    let s = a_dot_v + v.theta;
    0.5 * m * (v.x * v.x + v.y * v.y + v.z * v.z) + 0.5 * s * s
}

/// The double spherical pendulum of [`double_spherical_pendulum`] written as its continuous
/// Lagrangian `L = T − V` with the paper's midpoint rule: the attribute forms
/// `L_d(q0, q1) = h L((q0 + q1)/2, (q1 − q0)/h)` exactly as the hand-written version spells it
/// out, so the generated code and every step are bit-for-bit the same (`tests/continuous.rs`).
#[reduced_lagrangian(shape(phi1, vt2, phi2), group(vt1), rule = midpoint)]
pub fn double_spherical_pendulum_continuous(
    q: Config,
    v: Velocity,
    m1: f64,
    m2: f64,
    l1: f64,
    l2: f64,
    g: f64,
) -> f64 {
    // Back to the azimuths of the two bobs.
    let (th1, th2) = (q.vt1 - q.vt2, q.vt1 + q.vt2);
    let (dth1, dth2) = (v.vt1 - v.vt2, v.vt1 + v.vt2);
    let (s1, c1, s2, c2) = (q.phi1.sin(), q.phi1.cos(), q.phi2.sin(), q.phi2.cos());
    let (st1, ct1, st2, ct2) = (th1.sin(), th1.cos(), th2.sin(), th2.cos());
    // ṙ1, and ṙ2 = ṙ1 + u2 with u2 the velocity of the second bob relative to the first.
    let v1 = [
        l1 * (c1 * ct1 * v.phi1 - s1 * st1 * dth1),
        l1 * (c1 * st1 * v.phi1 + s1 * ct1 * dth1),
        -l1 * s1 * v.phi1,
    ];
    let u2 = [
        l2 * (c2 * ct2 * v.phi2 - s2 * st2 * dth2),
        l2 * (c2 * st2 * v.phi2 + s2 * ct2 * dth2),
        -l2 * s2 * v.phi2,
    ];
    let v2 = [v1[0] + u2[0], v1[1] + u2[1], v1[2] + u2[2]];
    let kinetic = 0.5 * m1 * (v1[0] * v1[0] + v1[1] * v1[1] + v1[2] * v1[2])
        + 0.5 * m2 * (v2[0] * v2[0] + v2[1] * v2[1] + v2[2] * v2[2]);
    let potential = g * (m1 * l1 * c1 + m2 * (l1 * c1 + l2 * c2));
    kinetic - potential
}

impl ChargedParticleContinuous {
    /// The parameters of [`ChargedParticle::paper`].
    pub fn paper(steps: usize) -> Self {
        let p = ChargedParticle::paper(steps);
        Self {
            m: p.m,
            b0: p.b0,
            h: p.h,
        }
    }
}

impl DoubleSphericalPendulumContinuous {
    /// The parameters of [`DoubleSphericalPendulum::paper`].
    pub fn paper() -> Self {
        pendulum_parameters!(Self, DoubleSphericalPendulum::paper())
    }
}
