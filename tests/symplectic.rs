//! The unreduced (+) step map is symplectic, and `UnreducedIntegrator::step_jacobian` (the
//! implicit-function theorem with the generated second derivatives) is its Jacobian.

use dirac::paper::{ChargedParticle, DoubleSphericalPendulum};
use dirac::prelude::*;

mod common;
use common::{ParticleWithConnection, PlanarRotor};

/// Mᵀ Ω M = Ω along a trajectory, to 1e-9 relative to the size of the terms (see
/// `Sensitivity::symplecticity_defect`; measured values are ~1e-13 and below).
fn assert_symplectic<L, const S: usize, const K: usize, const N: usize>(
    sys: L,
    initial: UnreducedState<N>,
    steps: usize,
) where
    L: LagrangianHessian<S, K, N> + Copy,
{
    let integ = UnreducedIntegrator::new(sys, NewtonOptions::default());
    let traj = integ.clone().run(initial).steps(steps).collect().unwrap();
    for (k, pair) in traj.states.windows(2).enumerate() {
        let m = integ.step_jacobian(k, &pair[0], &pair[1]).unwrap();
        let defect = m.symplecticity_defect();
        assert!(defect < 1e-9, "step {k}: symplecticity defect {defect:e}");
    }
}

fn canonical<const N: usize>(q: [f64; N], p: [f64; N]) -> UnreducedState<N> {
    UnreducedState {
        q: SVector::from(q),
        p: SVector::from(p),
    }
}

#[test]
fn every_example_is_symplectic() {
    let cp = ChargedParticle::paper(100);
    assert_symplectic(
        cp,
        cp.untrivialize(&ChargedParticle::paper_initial_state()),
        100,
    );
    let with_b = ParticleWithConnection {
        h: 0.1,
        m: 1.3,
        b0: 0.8,
        b: 0.45,
    };
    assert_symplectic(
        with_b,
        canonical([0.2, -0.1, 0.3, 0.7], [0.9, 0.2, -0.4, 1.1]),
        100,
    );
    let rotor = PlanarRotor {
        h: 0.05,
        m: 2.0,
        k: 3.0,
    };
    assert_symplectic(rotor, canonical([0.4, 1.0, 2.0], [0.1, 0.5, -0.3]), 200);
    let dsp = DoubleSphericalPendulum::paper();
    assert_symplectic(
        dsp,
        dsp.untrivialize(&DoubleSphericalPendulum::paper_initial_state()),
        500,
    );
}

/// A map that is not symplectic is caught: scaling the momentum block of a true step Jacobian.
#[test]
fn a_non_symplectic_map_is_detected() {
    let sys = PlanarRotor {
        h: 0.05,
        m: 2.0,
        k: 3.0,
    };
    let integ = UnreducedIntegrator::new(sys, NewtonOptions::default());
    let start = canonical([0.4, 1.0, 2.0], [0.1, 0.5, -0.3]);
    let (next, _) = integ.step_from(0, &start, &start.q).unwrap();
    let mut m = integ.step_jacobian(0, &start, &next).unwrap();
    assert!(m.symplecticity_defect() < 1e-12);
    let n = m.state.nrows() / 2;
    m.state.view_mut((n, n), (n, n)).scale_mut(1.001); // ∂p'/∂p
    assert!(
        m.symplecticity_defect() > 1e-4,
        "{}",
        m.symplecticity_defect()
    );
}

/// The Jacobian agrees with central differences of the step map itself (each perturbed step
/// solved by Newton to round-off), column by column; tolerance 1e-6 relative to the column,
/// the accuracy of a central difference with ε = 1e-6.
#[test]
fn the_step_jacobian_is_the_derivative_of_the_step_map() {
    fn check<L, const S: usize, const K: usize, const N: usize>(sys: L, start: UnreducedState<N>)
    where
        L: LagrangianHessian<S, K, N> + Copy,
    {
        let integ = UnreducedIntegrator::new(sys, NewtonOptions::default());
        let step = |s: &UnreducedState<N>| integ.step_from(0, s, &s.q).unwrap().0;
        let next = step(&start);
        let m = integ.step_jacobian(0, &start, &next).unwrap();
        for j in 0..2 * N {
            let eps = 1e-6;
            let (mut plus, mut minus) = (start, start);
            if j < N {
                plus.q[j] += eps;
                minus.q[j] -= eps;
            } else {
                plus.p[j - N] += eps;
                minus.p[j - N] -= eps;
            }
            let (a, b) = (step(&plus), step(&minus));
            let dq = (a.q - b.q) / (2.0 * eps);
            let dp = (a.p - b.p) / (2.0 * eps);
            let (mq, mp) = if j < N {
                (
                    m.dq_dq().column(j).into_owned(),
                    m.dp_dq().column(j).into_owned(),
                )
            } else {
                (
                    m.dq_dp().column(j - N).into_owned(),
                    m.dp_dp().column(j - N).into_owned(),
                )
            };
            let scale = 1.0 + mq.amax().max(mp.amax());
            assert!(
                (dq - &mq).amax() < 1e-6 * scale,
                "column {j}: ∂q {dq} vs {mq}"
            );
            assert!(
                (dp - &mp).amax() < 1e-6 * scale,
                "column {j}: ∂p {dp} vs {mp}"
            );
        }
    }
    let cp = ChargedParticle::paper(100);
    check(cp, cp.untrivialize(&ChargedParticle::paper_initial_state()));
    check(
        PlanarRotor {
            h: 0.05,
            m: 2.0,
            k: 3.0,
        },
        canonical([0.4, 1.0, 2.0], [0.1, 0.5, -0.3]),
    );
    let with_b = ParticleWithConnection {
        h: 0.1,
        m: 1.3,
        b0: 0.8,
        b: 0.45,
    };
    check(
        with_b,
        canonical([0.2, -0.1, 0.3, 0.7], [0.9, 0.2, -0.4, 1.1]),
    );
}
