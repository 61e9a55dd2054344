//! Adaptive steps: `time(t), adapt = |q| g` — the Poincaré time transformation stepped at a
//! fixed fictitious step, against Kepler's closed form.

use dirac::prelude::*;

/// Kepler's problem in the plane in polar coordinates, its step following `r^{3/2}`.
#[reduced_lagrangian(shape(r), group(theta, t), time(t), adapt = |q| q.r.powf(1.5), rule = midpoint)]
fn kepler(q: Config, v: Velocity, k: f64) -> f64 {
    0.5 * (v.r * v.r + q.r * q.r * v.theta * v.theta) + k / q.r
}

/// The orbit of eccentricity `e` (semi-major axis 1, `k = 1`, period 2π) at time `t` from
/// periapsis at `t = 0`: `(r, θ)` by Kepler's equation `E − e sin E = t`, solved by Newton.
fn exact(e: f64, t: f64) -> (f64, f64) {
    let m = t.rem_euclid(2.0 * std::f64::consts::PI);
    let mut big_e = if e > 0.8 { std::f64::consts::PI } else { m };
    for _ in 0..100 {
        let d = (big_e - e * big_e.sin() - m) / (1.0 - e * big_e.cos());
        big_e -= d;
        if d.abs() < 1e-16 {
            break;
        }
    }
    let r = 1.0 - e * big_e.cos();
    let theta = 2.0
        * ((1.0 + e).sqrt() * (big_e / 2.0).sin()).atan2((1.0 - e).sqrt() * (big_e / 2.0).cos());
    let turns = (t / (2.0 * std::f64::consts::PI)).floor();
    (r, theta + turns * 2.0 * std::f64::consts::PI)
}

/// The reduced initial state at periapsis.
fn periapsis(sys: &Kepler, e: f64) -> ReducedState<1, 2> {
    let r0 = 1.0 - e;
    let omega = (1.0 - e * e).sqrt() / (r0 * r0);
    dirac::runtime::adaptive::reduced_state(sys, [r0, 0.0, 0.0], [0.0, omega, 1.0]).unwrap()
}

fn tight() -> NewtonOptions {
    NewtonOptions {
        abs_tol: 1e-14,
        rel_tol: 1e-14,
        ..NewtonOptions::default()
    }
}

#[test]
fn kepler_dbg() {
    let e = 0.9;
    for eps in [0.04, 0.02, 0.01] {
        let sys = Kepler { h: eps, k: 1.0 };
        let integ = ReducedIntegrator::plus(sys, tight());
        let s0 = periapsis(&sys, e);
        let n = (20.0 / eps) as usize;
        let traj = integ.run(s0).steps(n).collect().unwrap();
        let last = traj.last();
        let t = last.g[1];
        let (r, th) = exact(e, t);
        println!(
            "eps {eps} t {t} err r {:e} th {:e} mu {:?} iters {}",
            (last.x[0] - r).abs(),
            (last.g[0] - th).abs(),
            last.mu,
            traj.mean_iterations()
        );
    }
}

#[test]
fn newton_dbg() {
    let sys = Kepler { h: 0.04, k: 1.0 };
    let s0 = periapsis(&sys, 0.9);
    let g = (0.1f64).powf(1.5);
    let mut z = SVector::<f64, 3>::new(0.1, 0.0, 0.04 * g);
    for it in 0..8 {
        let (r, j) = <Kepler as dirac::runtime::Reduced<Plus, 1, 2, 3>>::residual_jacobian(
            &sys, &s0.x, &s0.w, &s0.mu, &z,
        );
        println!("{it} z {:?} r {:?}", z.as_slice(), r.as_slice());
        let j: SMatrix<f64, 3, 3> = j.into();
        let d = j.lu().solve(&r).unwrap();
        z -= d;
    }
}
