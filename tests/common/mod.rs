//! Test systems shared by several integration tests.
#![allow(dead_code)] // each test binary uses its own subset

use dirac::prelude::*;

/// The charged particle with a nonzero linear connection `ω_d = (θ1 − θ0) − B (x1 − x0)`,
/// `B = [0.3, −0.7, b]`: the physics is unchanged, the reduced momenta become `w = p_x + Bᵀ μ`.
#[reduced_lagrangian(shape(x, y, z), group(theta), connection = [[0.3, -0.7, b]])]
pub fn particle_with_connection(q0: Config, q1: Config, h: f64, m: f64, b0: f64, b: f64) -> f64 {
    let (dx, dy, dz) = (q1.x - q0.x, q1.y - q0.y, q1.z - q0.z);
    let a_dot_dq = 0.5 * b0 * (-q0.y * dx + q0.x * dy);
    let s = a_dot_dq + (q1.theta - q0.theta);
    0.5 * m / h * (dx * dx + dy * dy + dz * dz) + 0.5 / h * s * s
}

/// Two group coordinates (K = 2): a particle in the plane (gx, gy), translation invariant, coupled
/// to an anharmonic internal coordinate s; midpoint rule.
#[reduced_lagrangian(shape(s), group(gx, gy))]
#[allow(clippy::needless_range_loop)] // the point is to exercise an unrolled loop with indexing
pub fn planar_rotor(q0: Config, q1: Config, h: f64, m: f64, k: f64) -> f64 {
    let v = [(q1.gx - q0.gx) / h, (q1.gy - q0.gy) / h];
    let vs = (q1.s - q0.s) / h;
    let sm = 0.5 * (q0.s + q1.s);
    let mut kinetic = 0.5 * vs * vs;
    for i in 0..2 {
        kinetic += 0.5 * m * (1.0 + 0.3 * sm.sin()) * v[i] * v[i];
    }
    h * (kinetic + 0.2 * sm * v[0] - k * (1.0 - sm.cos()))
}

/// splitmix64: a small deterministic PRNG, so every run of a test sees the same points.
pub struct Rng(pub u64);

impl Rng {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[lo, hi)`.
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        let u = (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        lo + (hi - lo) * u
    }

    /// A vector with entries uniform in `[lo, hi)`.
    pub fn vector<const D: usize>(&mut self, lo: f64, hi: f64) -> SVector<f64, D> {
        SVector::from_fn(|_, _| self.uniform(lo, hi))
    }
}

/// The eccentric anomaly `E` of Kepler's equation `E − e sin E = t mod 2π` (mean motion 1), by
/// Newton's method.
pub fn eccentric_anomaly(e: f64, t: f64) -> f64 {
    let m = t.rem_euclid(2.0 * std::f64::consts::PI);
    let mut big_e = if e > 0.8 { std::f64::consts::PI } else { m };
    for _ in 0..100 {
        let d = (big_e - e * big_e.sin() - m) / (1.0 - e * big_e.cos());
        big_e -= d;
        if d.abs() < 1e-16 {
            break;
        }
    }
    big_e
}

/// `y(t)` of `y' = f(y)` from `y(0) = y0` by the classical Runge–Kutta method with
/// `per_unit` steps per unit time, the increments added by compensated (Kahan) summation: a
/// tight independent reference (over the 10⁵ steps of a reference for a high-order method the
/// plain sum's rounding, about `√n ε |y|`, would be 1e-13; compensated, the error is the
/// method's alone).
pub fn rk4<const M: usize>(
    y0: SVector<f64, M>,
    f: impl Fn(&SVector<f64, M>) -> SVector<f64, M>,
    t: f64,
    per_unit: f64,
) -> SVector<f64, M> {
    let n = (per_unit * t).ceil() as usize;
    let dt = t / n as f64;
    let (mut y, mut carry) = (y0, SVector::<f64, M>::zeros());
    for _ in 0..n {
        let k1 = f(&y);
        let k2 = f(&(y + k1 * (dt / 2.0)));
        let k3 = f(&(y + k2 * (dt / 2.0)));
        let k4 = f(&(y + k3 * dt));
        let increment = (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (dt / 6.0);
        for i in 0..M {
            let added = increment[i] + carry[i];
            let sum = y[i] + added;
            carry[i] = added - (sum - y[i]);
            y[i] = sum;
        }
    }
    y
}
