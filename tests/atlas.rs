//! Charts and transitions (§6): the double spherical pendulum's three charts
//! (`dirac::paper::atlas`), the transitions `#[chart_transition]` compiles, and the atlas
//! integrator across a switch.

use dirac::paper::atlas::{
    chart_quality, Bob1FrameToBob2Frame, Bob1FrameToPaper, Bob2FrameToBob1Frame, Bob2FrameToPaper,
    PaperToBob1Frame, PaperToBob2Frame, BOB1_FRAME, BOB2_FRAME, PAPER,
};
use dirac::paper::DoubleSphericalPendulum;
use dirac::prelude::*;
use dirac::runtime::atlas::transform_state;
use dirac::runtime::system::join;
use dirac::{Sensitivity, UnreducedIntegrator};

mod common;
use common::Rng;

type Transition = dyn ChartTransition<3, 1, 4>;

/// Every declared transition, `(from, to, map)`.
fn transitions() -> [(usize, usize, &'static Transition); 6] {
    [
        (PAPER, BOB1_FRAME, &PaperToBob1Frame),
        (BOB1_FRAME, PAPER, &Bob1FrameToPaper),
        (PAPER, BOB2_FRAME, &PaperToBob2Frame),
        (BOB2_FRAME, PAPER, &Bob2FrameToPaper),
        (BOB1_FRAME, BOB2_FRAME, &Bob1FrameToBob2Frame),
        (BOB2_FRAME, BOB1_FRAME, &Bob2FrameToBob1Frame),
    ]
}

/// A random state of chart `chart`, regular for it and for every chart (quality ≥ 0.3), with
/// momenta of the size of the paper's run.
fn random_state(rng: &mut Rng, chart: usize) -> ReducedState<3, 1> {
    loop {
        // Principal ranges, so the inverse transition returns the same numbers: ϑ2 ∈ (−π/2, π/2]
        // in the paper's chart, `(a, b) ∈ [0, π] × (−π, π]` in the link frames.
        let x = if chart == PAPER {
            [
                rng.uniform(0.3, 2.8),
                rng.uniform(-1.5, 1.5),
                rng.uniform(0.3, 2.8),
            ]
        } else {
            [
                rng.uniform(0.3, 2.8),
                rng.uniform(0.3, 2.8),
                rng.uniform(-3.0, 3.0),
            ]
        };
        let state = ReducedState::new(
            x,
            [
                rng.uniform(-5e4, 5e4),
                rng.uniform(-5e4, 5e4),
                rng.uniform(-5e4, 5e4),
            ],
            [rng.uniform(-5e4, 5e4)],
            [rng.uniform(-3.0, 3.0)],
        );
        let all_regular = (0..3).all(|to| {
            let mapped = if to == chart {
                Some(state)
            } else {
                transitions()
                    .iter()
                    .find(|(f, t, _)| *f == chart && *t == to)
                    .and_then(|(_, _, m)| {
                        transform_state::<Transition, 3, 1, 4>(
                            *m,
                            &state,
                            &Default::default(),
                            &Default::default(),
                        )
                    })
            };
            mapped.is_some_and(|s| chart_quality(to, &s) >= 0.3)
        });
        if all_regular {
            return state;
        }
    }
}

/// Across every transition: μ copied bit for bit; the physical energy `T + V` (the Hamiltonian,
/// intrinsic to `T*Q`) and the Cartesian bob positions equal to round-off (1e-12 relative: a few
/// dozen operations on numbers of size ≤ 1e5); and the inverse transition gives the state back.
#[test]
fn transitions_preserve_mu_energy_and_positions() {
    let charts = DoubleSphericalPendulum::paper().charts();
    let mut rng = Rng(11);
    let zero = SMatrix::<f64, 1, 3>::zeros();
    for (from, to, map) in transitions() {
        let back = transitions()
            .into_iter()
            .find(|(f, t, _)| *f == to && *t == from)
            .expect("every transition has its inverse")
            .2;
        for _ in 0..50 {
            let before = random_state(&mut rng, from);
            let after = transform_state::<Transition, 3, 1, 4>(map, &before, &zero, &zero)
                .expect("regular");
            assert_eq!(after.mu[0].to_bits(), before.mu[0].to_bits());
            let (e0, e1) = (
                charts.energy(from, &before).unwrap(),
                charts.energy(to, &after).unwrap(),
            );
            assert!(
                (e1 - e0).abs() <= 1e-12 * e0.abs().max(1e5),
                "{from} → {to}: T + V {e0:e} → {e1:e}"
            );
            let (r0, r1) = (
                charts.bob_positions(from, &before),
                charts.bob_positions(to, &after),
            );
            for (a, b) in r0.0.iter().chain(&r0.1).zip(r1.0.iter().chain(&r1.1)) {
                assert!((a - b).abs() <= 1e-9, "{from} → {to}: bob at {a} vs {b}");
            }
            let round = transform_state::<Transition, 3, 1, 4>(back, &after, &zero, &zero)
                .expect("regular");
            // Angles come back up to 2π (the inverse picks principal branches): compare the
            // physical state, positions and momenta through the energy and the positions.
            let r2 = charts.bob_positions(from, &round);
            for (a, b) in r0.0.iter().chain(&r0.1).zip(r2.0.iter().chain(&r2.1)) {
                assert!((a - b).abs() <= 1e-9, "{from} → {to} → {from}: {a} vs {b}");
            }
            let wrap = |d: f64| {
                (d + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
            };
            for i in 0..3 {
                assert!(wrap(round.x[i] - before.x[i]).abs() <= 1e-9);
                assert!((round.w[i] - before.w[i]).abs() <= 1e-9 * before.w.amax());
            }
            assert!(wrap(round.g[0] - before.g[0]).abs() <= 1e-9);
        }
    }
}

/// `Dφ` from the compiler against central differences of `φ` (step 1e-6: truncation ≈ 1e-12,
/// round-off ≈ 1e-10 on values of size π; tolerance 1e-7).
#[test]
fn transition_jacobians_match_finite_differences() {
    let mut rng = Rng(12);
    for (from, _, map) in transitions() {
        for _ in 0..20 {
            let s = random_state(&mut rng, from);
            let q = join::<3, 1, 4>(&s.x, &s.g);
            let (value, d) = map.map_jacobian(&q);
            assert_eq!(value, map.map(&q));
            for j in 0..4 {
                let e = SVector::<f64, 4>::from_fn(|i, _| if i == j { 1e-6 } else { 0.0 });
                let fd = (map.map(&(q + e)) - map.map(&(q - e))) / 2e-6;
                for i in 0..4 {
                    assert!(
                        (fd[i] - d[(i, j)]).abs() <= 1e-7,
                        "∂φ{i}/∂q{j}: {} vs {}",
                        d[(i, j)],
                        fd[i]
                    );
                }
            }
        }
    }
}

/// The step map composed across a switch — a step in the old chart, the cotangent lift of the
/// transition, a step in the new chart — is symplectic. The step Jacobians are exact
/// ([`UnreducedIntegrator::step_jacobian`]); the lift's Jacobian `[[Dφ, 0], [∂p'/∂q, Dφ^{-T}]]`
/// uses the compiler's `Dφ` and central differences of `Dφ^{-T} p` for the `∂p'/∂q` block
/// (step 1e-5: error ≈ 1e-10 relative). A lift with one entry perturbed by 1e-4 of the block's size is caught.
#[test]
fn composed_step_map_across_a_switch_is_symplectic() {
    let charts = DoubleSphericalPendulum::paper().charts();
    let opts = NewtonOptions::default();
    let mut rng = Rng(13);
    let zero = SMatrix::<f64, 1, 3>::zeros();
    for (from, to, map) in transitions() {
        let state = random_state(&mut rng, from);
        let canonical = |c: usize, s: &ReducedState<3, 1>| match c {
            PAPER => charts.paper.untrivialize(s),
            BOB1_FRAME => charts.bob1.untrivialize(s),
            _ => charts.bob2.untrivialize(s),
        };
        let step = |c: usize, s: &UnreducedState<4>| -> (UnreducedState<4>, Sensitivity) {
            macro_rules! go {
                ($sys:expr) => {{
                    let integ = UnreducedIntegrator::new($sys, opts);
                    let (next, _) = integ.step_from(0, s, &s.q).expect("regular step");
                    let m = integ.step_jacobian(0, s, &next).expect("regular");
                    (next, m)
                }};
            }
            match c {
                PAPER => go!(charts.paper),
                BOB1_FRAME => go!(charts.bob1),
                _ => go!(charts.bob2),
            }
        };
        let z0 = canonical(from, &state);
        let (z1, m_old) = step(from, &z0);
        let lifted = map.lift(&z1).expect("regular");
        // The reduced transformation is the canonical lift (B = 0 in every chart).
        let reduced =
            transform_state::<Transition, 3, 1, 4>(map, &charts_state(&z1), &zero, &zero).unwrap();
        assert!((canonical(to, &reduced).p - lifted.p).amax() <= 1e-9 * lifted.p.amax());
        let (_, m_new) = step(to, &lifted);
        let (_, d) = map.map_jacobian(&z1.q);
        let d_inv_t = d.try_inverse().unwrap().transpose();
        let eps = 1e-5;
        let mut dp_dq = SMatrix::<f64, 4, 4>::zeros();
        for j in 0..4 {
            let e = SVector::<f64, 4>::from_fn(|i, _| if i == j { eps } else { 0.0 });
            let p_at = |q: SVector<f64, 4>| map.lift(&UnreducedState { q, p: z1.p }).unwrap().p;
            dp_dq.set_column(j, &((p_at(z1.q + e) - p_at(z1.q - e)) / (2.0 * eps)));
        }
        let lift = Sensitivity::from_blocks(&d, &SMatrix::zeros(), &dp_dq, &d_inv_t);
        let composed = compose(&m_new, &compose(&lift, &m_old));
        let defect = composed.symplecticity_defect();
        assert!(defect <= 1e-8, "{from} → {to}: defect {defect:e}");
        assert!(lift.symplecticity_defect() <= 1e-8);
        let mut perturbed = lift.clone();
        perturbed.state[(4, 4)] += 1e-4 * d_inv_t.amax(); // the (0, 0) entry of ∂p'/∂p
        let caught = compose(&m_new, &compose(&perturbed, &m_old)).symplecticity_defect();
        println!("{from} → {to}: defect {defect:.2e}, perturbed {caught:.2e}");
        assert!(
            caught > 100.0 * defect.max(1e-12),
            "{from} → {to}: perturbed map {caught:e}"
        );
    }
}

fn charts_state(z: &UnreducedState<4>) -> ReducedState<3, 1> {
    // B = 0: w = p_x, μ = p_g.
    ReducedState {
        x: z.q.fixed_rows::<3>(0).into_owned(),
        w: z.p.fixed_rows::<3>(0).into_owned(),
        mu: z.p.fixed_rows::<1>(3).into_owned(),
        g: z.q.fixed_rows::<1>(3).into_owned(),
    }
}

/// `a ∘ b` in blocks.
fn compose(a: &Sensitivity, b: &Sensitivity) -> Sensitivity {
    Sensitivity::from_blocks(
        &(a.dq_dq() * b.dq_dq() + a.dq_dp() * b.dp_dq()),
        &(a.dq_dq() * b.dq_dp() + a.dq_dp() * b.dp_dp()),
        &(a.dp_dq() * b.dq_dq() + a.dp_dp() * b.dp_dq()),
        &(a.dp_dq() * b.dq_dp() + a.dp_dp() * b.dp_dp()),
    )
}

/// Up to its first switch the atlas is the single-chart integrator, bit for bit (same steps, same
/// Newton guesses); across every switch μ is copied bit for bit, the switch is recorded with its
/// step and charts, and `T + V` is continuous. With the threshold lowered to 0.05 the first switch
/// from the paper's initial state comes at step 5419.
#[test]
fn atlas_equals_the_single_chart_run_up_to_the_first_switch() {
    let sys = DoubleSphericalPendulum::paper();
    let charts = sys.charts();
    let opts = NewtonOptions::default();
    let atlas = sys.atlas(opts).with_quality(0.05, chart_quality);
    let initial = DoubleSphericalPendulum::paper_initial_state();
    let steps = 6_000;
    let traj = atlas
        .run((PAPER, initial))
        .steps(steps)
        .collect()
        .expect("the atlas does not fail");
    let first = traj.switches.first().expect("a switch").step;
    assert!(first > 1000, "first switch at {first}");
    let single = ReducedIntegrator::plus(sys, opts)
        .run(initial)
        .steps(first)
        .collect()
        .expect("the single chart reaches the switch");
    // The state at the switch is stored in the new chart, `before` holds the old one.
    assert_eq!(&single.states[..first], &traj.states[..first]);
    assert_eq!(single.states[first], traj.switches[0].before);
    assert_eq!(traj.stats[..first], single.stats[..]);
    for sw in &traj.switches {
        assert_eq!(traj.states[sw.step], sw.after);
        assert_eq!(traj.charts[sw.step], sw.to);
        assert_eq!(traj.charts[sw.step - 1], sw.from);
        assert_eq!(sw.after.mu[0].to_bits(), initial.mu[0].to_bits());
        let (e0, e1) = (
            charts.energy(sw.from, &sw.before).unwrap(),
            charts.energy(sw.to, &sw.after).unwrap(),
        );
        assert!((e1 - e0).abs() <= 1e-12 * e0.abs());
    }
    assert!(traj.states.iter().all(|s| s.mu == initial.mu));
}

/// Where both links are vertical the rotation is not free (Remark 7.1): every chart is singular
/// there, and the atlas stops with a typed error carrying the step index, keeping the trajectory.
#[test]
fn both_links_vertical_is_a_typed_error() {
    let sys = DoubleSphericalPendulum::paper();
    let atlas = sys.atlas(NewtonOptions::default());
    let initial = ReducedState::new(
        [std::f64::consts::PI, 0.3, std::f64::consts::PI],
        [0.0, 1.0, 1.0],
        [0.0],
        [0.0],
    );
    let err = atlas
        .run((PAPER, initial))
        .steps(10)
        .collect()
        .expect_err("no chart is regular here");
    assert_eq!(err.source.step(), 0);
    assert_eq!(err.trajectory.step_count(), 0);
    assert_eq!(err.trajectory.states[0], initial);
    assert!(err.trajectory.switches.is_empty());
}

/// A transition of the charged particle's chart (`B ≠ 0` in both charts: the physics is the same,
/// the reduced momenta `w = p_x + Bᵀ μ` differ), nonlinear in the shape and with a
/// shape-dependent shift of the group coordinate.
#[chart_transition(from(shape(x, y, z), group(theta)), to(shape(u, v, s), group(phi)))]
fn sheared(q: Config) -> (f64, f64, f64, f64) {
    (
        q.x + 0.1 * q.y * q.y,
        q.y,
        q.z.sinh() + 0.3 * q.x,
        q.theta + q.x * q.z - 0.2 * q.y.cos(),
    )
}

/// The reduced transformation `(x, w, μ, g) ↦ (ψ(x), Dψ^{-T}(w − B_oldᵀμ − Dcᵀμ) + B_newᵀμ, μ,
/// g + c(x))` (block formula, `S × S` solve) equals the canonical route: untrivialize with
/// `B_old` (3.7), the full cotangent lift `p' = Dφ^{-T} p` (`N × N` solve), trivialize with
/// `B_new` (3.6). Tolerance 1e-12 relative: two different solves of the same small system.
#[test]
fn reduced_transformation_is_the_cotangent_lift_with_connections() {
    let old = common::ParticleWithConnection {
        h: 0.1,
        m: 1.3,
        b0: 0.7,
        b: 0.4,
    };
    let new = common::ParticleWithConnection { b: -1.1, ..old };
    let (b_old, b_new) = (old.connection(), new.connection());
    assert_ne!(b_old, b_new);
    let mut rng = Rng(14);
    for _ in 0..100 {
        let state = ReducedState {
            x: rng.vector(-1.0, 1.0),
            w: rng.vector(-2.0, 2.0),
            mu: rng.vector(-2.0, 2.0),
            g: rng.vector(-3.0, 3.0),
        };
        let reduced =
            transform_state::<Sheared, 3, 1, 4>(&Sheared, &state, &b_old, &b_new).expect("regular");
        let canonical = new.trivialize(&Sheared.lift(&old.untrivialize(&state)).expect("regular"));
        assert_eq!(reduced.mu, state.mu);
        let scale = state.w.amax().max(state.mu.amax());
        assert!((reduced.x - canonical.x).amax() <= 1e-12);
        assert!((reduced.g - canonical.g).amax() <= 1e-12);
        assert!(
            (reduced.w - canonical.w).amax() <= 1e-12 * scale,
            "{} vs {}",
            reduced.w,
            canonical.w
        );
    }
}

/// A transition declared between charts that were not added (or from a chart to itself) is a
/// typed error of the run, not a panic while the atlas is set up; the initial state is kept.
#[test]
fn a_transition_between_unknown_charts_is_a_typed_error() {
    let sys = DoubleSphericalPendulum::paper();
    for (from, to) in [(PAPER, 7), (9, PAPER), (PAPER, PAPER)] {
        let atlas = std::panic::catch_unwind(|| {
            sys.atlas(NewtonOptions::default())
                .transition(from, to, PaperToBob1Frame)
        });
        let Ok(atlas) = atlas else {
            panic!("transition {from} -> {to}: a panic while setting up the atlas");
        };
        let err = atlas
            .run((PAPER, DoubleSphericalPendulum::paper_initial_state()))
            .steps(3)
            .collect()
            .unwrap_err();
        assert!(
            err.source.to_string().contains("transition"),
            "{from} -> {to}: {}",
            err.source
        );
        assert_eq!(err.trajectory.states.len(), 1);
    }
}
