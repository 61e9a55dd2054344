//! Run-time-sized systems on both sides: the (−) equations against the (+) ones, with
//! translations, forces, controls and compositions; and the step's sensitivities.

use dirac::prelude::*;
use dirac::runtime::element::ElementIntegrator;

#[path = "../examples/common/toda_n.rs"]
mod toda_n;
use toda_n::{initial, TodaN};

mod element_systems;
use element_systems::{DampedToda, DrivenChain};

fn tight() -> NewtonOptions {
    NewtonOptions {
        abs_tol: 1e-14,
        rel_tol: 1e-14,
        ..NewtonOptions::default()
    }
}

/// The largest difference between two trajectories' states, relative to their size.
fn gap(a: &ElementTrajectory, b: &ElementTrajectory) -> f64 {
    assert_eq!(a.states.len(), b.states.len());
    a.states
        .iter()
        .zip(&b.states)
        .map(|(x, y)| {
            let scale = x.q.amax().max(x.p.amax()).max(1.0);
            (&x.q - &y.q).amax().max((&x.p - &y.p).amax()) / scale
        })
        .fold(0.0, f64::max)
}

#[test]
fn the_minus_side_computes_the_plus_trajectory_with_translations_and_forces() {
    let (m, d, h) = (1.3, 0.9, 0.05);
    let toda = TodaN { m, d, h, n: 40 };
    let start = initial(&toda, 0.3, 0.5, 0.1);
    let plus = ElementIntegrator::new(toda, tight());
    let minus = ElementIntegrator::minus(toda, tight());
    assert_eq!(minus.variant(), Variant::Minus);
    let a = plus.run(start.clone()).steps(400).collect().unwrap();
    let b = minus.run(start.clone()).steps(400).collect().unwrap();
    assert_eq!((a.variant, b.variant), (Variant::Plus, Variant::Minus));
    let g = gap(&a, &b);
    assert!(g <= 1e-12, "Toda: {g:e}");
    // The momentum map is exact on the (−) side too.
    let mu0 = minus.momentum_map(&start).unwrap()[0];
    for s in &b.states {
        let mu = minus.momentum_map(s).unwrap()[0];
        assert!(
            (mu - mu0).abs() <= 1e-13 * mu0.abs().max(1.0),
            "{mu} vs {mu0}"
        );
    }
    // With a damping force: the same trajectory, and the forced Noether balance.
    let damped = DampedToda {
        m,
        d,
        c: 0.2,
        h,
        n: 40,
    };
    let plus = ElementIntegrator::new(damped, tight());
    let minus = ElementIntegrator::minus(damped, tight());
    let a = plus.run(start.clone()).steps(400).collect().unwrap();
    let b = minus.run(start.clone()).steps(400).collect().unwrap();
    let g = gap(&a, &b);
    assert!(g <= 1e-12, "damped Toda: {g:e}");
    for k in 0..400 {
        let mu = |s: &ElementState| minus.momentum_map(s).unwrap()[0];
        let impulse = -0.2 * (&b.states[k + 1].q - &b.states[k].q).sum();
        let balance = mu(&b.states[k + 1]) - mu(&b.states[k]) - impulse;
        assert!(balance.abs() <= 1e-14, "step {k}: {balance:e}");
    }
}

#[test]
fn the_minus_side_computes_the_plus_trajectory_under_feedback_controls() {
    let (h, c, a) = (0.05, 0.3, 0.7);
    let chain = DrivenChain { h, c, a, n: 30 };
    let start = ElementState::new(
        DVector::from_fn(30, |i, _| 0.1 * (i as f64).sin()),
        DVector::from_fn(30, |i, _| 0.2 * (i as f64).cos()),
    );
    let law = |k: usize, _: f64, s: &ElementState, u: &mut [f64]| {
        u[0] = a * (0.05 * k as f64).cos() - 0.5 * s.q[0];
    };
    let run = |integ: ElementIntegrator<DrivenChain>| {
        integ
            .run(start.clone())
            .steps(300)
            .feedback(law)
            .collect()
            .unwrap()
    };
    let g = gap(
        &run(ElementIntegrator::new(chain, tight())),
        &run(ElementIntegrator::minus(chain, tight())),
    );
    assert!(g <= 1e-12, "{g:e}");
}

#[test]
fn compositions_of_the_minus_side_have_orders_four_and_six() {
    let (m, d) = (1.0, 0.9);
    let toda = |h: f64| TodaN { m, d, h, n: 16 };
    let start = initial(&toda(0.1), 0.6, 1.2, 0.1);
    let last = |method: CompositionMethod, steps: usize, minus: bool| {
        let sys = toda(8.0 / steps as f64);
        let integ = if minus {
            ElementIntegrator::minus(sys, tight())
        } else {
            ElementIntegrator::new(sys, tight())
        };
        let traj = Composition::new(integ, method)
            .run(start.clone())
            .steps(steps)
            .collect()
            .unwrap();
        traj.last().q.clone()
    };
    for (method, order) in [
        (CompositionMethod::TRIPLE_JUMP, 4.0),
        (CompositionMethod::KAHAN_LI_6, 6.0),
    ] {
        let same = (last(method, 20, true) - last(method, 20, false)).amax();
        assert!(same <= 1e-11, "(−) against (+): {same:e}");
        let reference = last(method, 640, true);
        let e: Vec<f64> = [20, 40, 80]
            .iter()
            .map(|&n| (last(method, n, true) - &reference).amax())
            .collect();
        let observed = (e[1] / e[2]).log2();
        assert!(
            (observed - order).abs() < 0.5,
            "order {observed} from {e:?}"
        );
    }
}
