//! Reduction by rotations: the reduced integrators of `symmetry(..)` against the unreduced
//! steps of the same discrete Lagrangians (reconstructed), and their conserved momenta.

use dirac::lie::{cayley, orthogonality_defect};
use dirac::prelude::*;
use dirac::systems::rotations::{
    DspOnSpheres, HeavyTop, HeavyTopConfig, HeavyTopMomentum, RigidBody, RigidBodyConfig,
    RigidBodyMomentum, Satellite, SatelliteConfig, SatelliteMomentum,
};

fn body() -> (RigidBody, LieState<9, 3>) {
    let sys = RigidBody {
        h: 0.01,
        j1: 1.0,
        j2: 2.0,
        j3: 3.0,
    };
    let s0 = sys.state(
        &RigidBodyConfig {
            r: cayley(&Vector3::new(0.2, -0.1, 0.4)),
        },
        &RigidBodyMomentum {
            r: Vector3::new(0.3, 1.0, -0.2),
        },
    );
    (sys, s0)
}

/// The largest entrywise difference between the reduced run, reconstructed, and the unreduced
/// run of the same system over `steps` steps.
fn reduced_against_unreduced<L, const P: usize, const N: usize>(
    sys: L,
    s0: LieState<P, N>,
    steps: usize,
) -> f64
where
    L: LieSymmetric<P, N>,
{
    let unreduced = LieIntegrator::new(sys.clone(), NewtonOptions::default());
    let reduced = ReducedLieIntegrator::new(sys, NewtonOptions::default());
    let a = unreduced.run(s0).steps(steps).collect().unwrap();
    let b = reduced
        .run(reduced.reduce(&s0))
        .steps(steps)
        .collect()
        .unwrap();
    a.states
        .iter()
        .zip(&b.states)
        .map(|(a, b)| {
            let b = b.unreduced();
            (a.q - b.q)
                .amax()
                .max((a.p - b.p).amax() / a.p.amax().max(1.0))
        })
        .fold(0.0, f64::max)
}

#[test]
fn the_rigid_body_reduced_by_every_rotation_is_the_unreduced_step() {
    let (sys, s0) = body();
    let worst = reduced_against_unreduced(sys, s0, 2000);
    assert!(worst < 1e-12, "{worst:e}");
}

#[test]
fn the_reduced_rigid_body_keeps_its_spatial_momentum_and_coadjoint_orbit() {
    let (sys, s0) = body();
    let integ = ReducedLieIntegrator::new(sys, NewtonOptions::default());
    let r0 = integ.reduce(&s0);
    let pi0 = r0.mu;
    let (mut drift, mut orbit, mut orth): (f64, f64, f64) = (0.0, 0.0, 0.0);
    integ
        .run(r0)
        .steps(100_000)
        .observe(|_, _, s: &ReducedLieState<9, 3>, _| {
            assert_eq!(s.mu, pi0);
            let pi = integ.momentum_map(&s.unreduced()).unwrap();
            drift = drift.max((pi - pi0).norm());
            orbit = orbit.max((sys.momenta(&s.unreduced()).r.norm() - pi0.norm()).abs());
            orth = orth.max(orthogonality_defect(&sys.config(&s.unreduced()).r));
        })
        .stream()
        .unwrap();
    assert!(drift <= 1e-14 * pi0.norm(), "π drift {drift:e}");
    assert!(orbit <= 1e-14 * pi0.norm(), "|Π| drift {orbit:e}");
    assert!(orth < 1e-13, "|RᵀR − I| = {orth:e}");
}

#[test]
fn the_heavy_top_reduced_about_the_vertical_keeps_mu_bit_for_bit() {
    let sys = HeavyTop {
        h: 0.01,
        j1: 1.0,
        j2: 1.2,
        j3: 0.4,
        mgl: 2.0,
    };
    let s0 = sys.state(
        &HeavyTopConfig {
            r: cayley(&Vector3::new(0.6, 0.1, 0.0)),
        },
        &HeavyTopMomentum {
            r: Vector3::new(0.1, 0.3, 4.0),
        },
    );
    let worst = reduced_against_unreduced(sys, s0, 2000);
    assert!(worst < 1e-11, "{worst:e}");
    let integ = ReducedLieIntegrator::new(sys, NewtonOptions::default());
    let r0 = integ.reduce(&s0);
    let mut off: f64 = 0.0;
    integ
        .run(r0)
        .steps(20_000)
        .observe(|_, _, s: &ReducedLieState<9, 3>, _| {
            assert_eq!(s.mu, r0.mu);
            off = off.max((integ.momentum_map(&s.unreduced()).unwrap().z - r0.mu.z).abs());
        })
        .stream()
        .unwrap();
    assert!(off < 1e-14 * r0.mu.z.abs().max(1.0), "{off:e}");
}

#[test]
fn the_satellite_reduced_by_every_rotation_follows_its_wheel_control() {
    let sys = Satellite {
        h: 0.01,
        j1: 2.0,
        j2: 3.0,
        j3: 4.0,
        jw: 0.5,
        u: 0.0,
    };
    let s0 = sys.state(
        &SatelliteConfig {
            r: cayley(&Vector3::new(0.1, 0.2, -0.3)),
            phi: 0.0,
        },
        &SatelliteMomentum {
            r: Vector3::new(0.4, -0.2, 1.0),
            phi: 0.7,
        },
    );
    assert!(reduced_against_unreduced(sys, s0, 2000) < 1e-12);
    // A feedback law of the time and the wheel's momentum, the same for both runs.
    let torque = |t: f64, p_phi: f64| 0.3 * (2.0 * t).sin() - 0.1 * p_phi;
    let unreduced = LieIntegrator::new(sys, NewtonOptions::default());
    let reduced = ReducedLieIntegrator::new(sys, NewtonOptions::default());
    let a = unreduced
        .run(s0)
        .steps(3000)
        .feedback(|_, t, s: &LieState<10, 4>, u: &mut [f64]| u[0] = torque(t, s.p[3]))
        .collect()
        .unwrap();
    let b = reduced
        .run(reduced.reduce(&s0))
        .steps(3000)
        .feedback(|_, t, s: &ReducedLieState<10, 4>, u: &mut [f64]| u[0] = torque(t, s.p[3]))
        .collect()
        .unwrap();
    let worst = a
        .states
        .iter()
        .zip(&b.states)
        .map(|(a, b)| (a.q - b.q).amax().max((a.p - b.p).amax()))
        .fold(0.0, f64::max);
    assert!(worst < 1e-11, "{worst:e}");
    assert!(b.states.iter().all(|s| s.mu == b.states[0].mu));
}

#[test]
fn the_double_spherical_pendulum_reduced_about_the_vertical() {
    let sys = DspOnSpheres::paper(0.01);
    let s0 = sys.paper_initial_state();
    let worst = reduced_against_unreduced(sys, s0, 2000);
    assert!(worst < 1e-10, "{worst:e}");
}

/// Euler's equations `Π̇ = Π × J⁻¹Π` of the free rigid body — the reduced dynamics on `so(3)*`
/// alone — over `t` by the classical Runge–Kutta method with 20,000 steps per unit time.
fn euler_exact(j: &Vector3<f64>, pi: &Vector3<f64>, t: f64) -> Vector3<f64> {
    let f = |pi: &Vector3<f64>| pi.cross(&pi.component_div(j));
    let n = (20_000.0 * t).ceil() as usize;
    let dt = t / n as f64;
    let mut pi = *pi;
    for _ in 0..n {
        let k1 = f(&pi);
        let k2 = f(&(pi + k1 * (dt / 2.0)));
        let k3 = f(&(pi + k2 * (dt / 2.0)));
        let k4 = f(&(pi + k3 * dt));
        pi += (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (dt / 6.0);
    }
    pi
}

/// `|Π_N − Π(1)|` of the reduced free rigid body after `n` steps of size `1/n`, by the reduced
/// step or its triple-jump composition.
fn reduced_error(n: usize, composed: bool) -> f64 {
    let (mut sys, s0) = body();
    sys.h = 1.0 / n as f64;
    let options = NewtonOptions {
        abs_tol: 1e-14,
        rel_tol: 1e-14,
        ..NewtonOptions::default()
    };
    let integ = ReducedLieIntegrator::new(sys, options);
    let r0 = integ.reduce(&s0);
    let last = if composed {
        let c = Composition::new(integ, CompositionMethod::TRIPLE_JUMP);
        *c.run(r0).steps(n).collect().unwrap().last()
    } else {
        *integ.run(r0).steps(n).collect().unwrap().last()
    };
    let exact = euler_exact(&Vector3::new(1.0, 2.0, 3.0), &sys.momenta(&s0).r, 1.0);
    (sys.momenta(&last.unreduced()).r - exact).amax()
}

#[test]
fn the_reduced_rigid_body_has_order_two_and_its_triple_jump_order_four_against_euler() {
    for (composed, order, steps) in [(false, 2.0, [20, 40, 80]), (true, 4.0, [10, 20, 40])] {
        let e: Vec<f64> = steps.iter().map(|&n| reduced_error(n, composed)).collect();
        for w in e.windows(2) {
            let observed = (w[0] / w[1]).log2();
            assert!(
                (observed - order).abs() < 0.2,
                "order {observed} (expected {order}) from errors {e:?}"
            );
        }
    }
}

#[test]
fn the_diagnostics_of_reduced_and_unreduced_runs_agree() {
    let sys = DspOnSpheres::paper(0.01);
    let s0 = sys.paper_initial_state();
    let unreduced = LieIntegrator::new(sys, NewtonOptions::default());
    let reduced = ReducedLieIntegrator::new(sys, NewtonOptions::default());
    let a = unreduced.run(s0).steps(300).collect().unwrap();
    let b = reduced
        .run(reduced.reduce(&s0))
        .steps(300)
        .collect()
        .unwrap();
    // Each step is a point of the discrete Dirac structure to Newton's accepted residual.
    let worst = |r: Vec<f64>| r.into_iter().fold(0.0, f64::max);
    let (ra, rb) = (
        worst(unreduced.dirac_residuals(&a)),
        worst(reduced.dirac_residuals(&b)),
    );
    assert!(ra < 1e-8 && rb < 1e-8, "{ra:e} {rb:e}");
    // The discrete generalized energy along both runs, and the action.
    let (ea, eb) = (
        unreduced.discrete_energies(&a),
        reduced.discrete_energies(&b),
    );
    let scale = ea.iter().fold(0.0_f64, |m, e| m.max(e.abs()));
    let gap = ea
        .iter()
        .zip(&eb)
        .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
    assert!(gap < 1e-9 * scale, "{gap:e} of {scale:e}");
    let (sa, sb) = (unreduced.discrete_action(&a), reduced.discrete_action(&b));
    assert!((sa - sb).abs() < 1e-9 * sa.abs(), "{sa} {sb}");
    // A step that is not a solution is far from the structure.
    let mut broken = b.clone();
    broken.states[100].p[0] *= 1.01;
    assert!(worst(reduced.dirac_residuals(&broken)) > 1e-4);
}

#[test]
fn a_reduced_state_whose_momentum_is_not_its_momentum_map_is_rejected() {
    let (sys, s0) = body();
    let integ = ReducedLieIntegrator::new(sys, NewtonOptions::default());
    let mut r0 = integ.reduce(&s0);
    r0.mu.x += 0.1;
    let err = integ.run(r0).steps(10).collect().unwrap_err();
    assert!(matches!(err.source, StepError::OffManifold { .. }), "{err}");
    assert!(err.source.to_string().contains("reduce"), "{}", err.source);
}

#[test]
fn the_minus_equations_take_the_plus_steps_on_every_kind_of_chart() {
    // A rotation with a scalar (the satellite) and directions (the pendulum on S² × S²).
    let (sat, sat0) = (
        Satellite {
            h: 0.01,
            j1: 2.0,
            j2: 3.0,
            j3: 4.0,
            jw: 0.5,
            u: 0.2,
        },
        SatelliteConfig {
            r: cayley(&Vector3::new(0.1, 0.2, -0.3)),
            phi: 0.3,
        },
    );
    let sat0 = sat.state(
        &sat0,
        &SatelliteMomentum {
            r: Vector3::new(0.4, -0.2, 1.0),
            phi: 0.7,
        },
    );
    let plus = LieIntegrator::new(sat, NewtonOptions::default());
    let minus = LieIntegrator::minus(sat, NewtonOptions::default());
    assert_eq!(minus.variant(), Variant::Minus);
    let (a, b) = (
        plus.run(sat0).steps(500).collect().unwrap(),
        minus.run(sat0).steps(500).collect().unwrap(),
    );
    assert_eq!(a.states, b.states);
    // The (−) equations' chart relation: q_{k+1} = φ_{q_k}(−w) is q_k = φ_{q_{k+1}}(w), checked
    // through the inverse charts at sizable w on rotations, scalars and directions.
    let dsp = DspOnSpheres::paper(0.01);
    let s0 = dsp.paper_initial_state();
    let plus = LieIntegrator::new(dsp, NewtonOptions::default());
    let minus = LieIntegrator::minus(dsp, NewtonOptions::default());
    let a = plus.run(s0).steps(300).collect().unwrap();
    assert_eq!(a.states, minus.run(s0).steps(300).collect().unwrap().states);
    let w = SVector::<f64, 4>::new(0.3, -0.2, 0.1, 0.25);
    let next = dsp.retract(&s0.q, &(-w));
    let back = plus.chart_coordinates(&next, &s0.q);
    assert!((back - w).amax() < 1e-14, "{back} {w}");
    let w = SVector::<f64, 4>::new(0.3, -0.2, 0.4, 0.5);
    let next = sat.retract(&sat0.q, &(-w));
    let back = LieIntegrator::new(sat, NewtonOptions::default()).chart_coordinates(&next, &sat0.q);
    assert!((back - w).amax() < 1e-14, "{back} {w}");
    // The reduced (−) integrator and its triple jump likewise.
    let (body, b0) = body();
    let plus = ReducedLieIntegrator::new(body, NewtonOptions::default());
    let minus = ReducedLieIntegrator::minus(body, NewtonOptions::default());
    let r0 = plus.reduce(&b0);
    let jump = |i| Composition::new(i, CompositionMethod::TRIPLE_JUMP);
    assert_eq!(
        jump(plus).run(r0).steps(200).collect().unwrap().states,
        jump(minus).run(r0).steps(200).collect().unwrap().states
    );
}
