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
            let pi = integ.momentum_map(&s.unreduced());
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
            off = off.max((integ.momentum_map(&s.unreduced()).z - r0.mu.z).abs());
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
