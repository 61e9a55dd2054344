//! Criterion benchmarks of the generated (+) steppers against run-time AD (num-dual), a
//! hand-coded stepper (charged particle) and the unreduced stepper from the same annotation, on
//! the paper's two systems. `examples/bench_table.rs` measures the same in one process and prints
//! the ratios, with CasADi's generated C beside them.
//!
//! `eval`: one residual+Jacobian evaluation of eq. (4.6), cycling over points spread along the
//! paper's run (at the integrator's Newton guess). `step`: one whole step (Newton included),
//! cycling over the steps of the paper's run, each from the trajectory's state and the guess the
//! integrator itself starts from; the mean Newton iterations of those steps are printed first.
//! `generated` is what `ReducedIntegrator::plus(sys, NewtonOptions::default())` runs; where the
//! attribute emitted a momentum-level elimination, both paths are also timed forced.
//!
//! `cargo bench --bench steppers` (add `-- --quick` for a fast pass).

mod common;

use std::hint::black_box;
use std::time::Duration;

use common::workload::{self, StepCase, Workload};
use common::{ad, hand};
use criterion::measurement::WallTime;
use criterion::{criterion_group, criterion_main, BenchmarkGroup, Criterion};
use dirac::prelude::*;

/// Evaluation points per system.
const EVAL_POINTS: usize = 64;

type Case = StepCase<3, 1, 4>;

/// Benchmarks `f` on `inputs[0], inputs[1], …` in turn, one per iteration.
fn cycling<T>(
    group: &mut BenchmarkGroup<'_, WallTime>,
    name: &str,
    inputs: &[Case],
    f: impl Fn(&Case) -> T,
) {
    group.bench_function(name, |b| {
        // A wrapping index rather than `i % len`: an integer division per iteration would be a
        // visible part of a 10 ns evaluation.
        let mut i = 0;
        b.iter(|| {
            i = if i + 1 == inputs.len() { 0 } else { i + 1 };
            f(black_box(&inputs[i]))
        })
    });
}

/// The benchmarks every system gets: generated, num-dual (both Jacobians) and unreduced.
fn bench_system<L>(c: &mut Criterion, short: &str, w: &Workload<L, 3, 1, 4>)
where
    L: Reduced<Plus, 3, 1, 4, Linear = dirac::runtime::Lu<4>>
        + Unreduced<3, 1, 4, UnreducedLinear = dirac::runtime::Lu<4>>
        + ad::DualLagrangian<4>
        + Copy,
{
    println!(
        "{}: {} steps timed, mean Newton iterations {:.3} on the default path ({})",
        w.name,
        w.cases.len(),
        w.mean_iterations(),
        if ReducedIntegrator::plus(w.system, NewtonOptions::default()).eliminates_group() {
            "eliminated"
        } else {
            "general"
        }
    );
    let sys = w.system;
    let points = w.spread(EVAL_POINTS);
    let options = NewtonOptions::default();

    let mut g = c.benchmark_group(format!("{short}/eval"));
    cycling(&mut g, "generated", &points, |p| {
        let s = &p.state;
        sys.residual_jacobian(&s.x, &s.w, &s.mu, &p.guess)
    });
    if <L as Reduced<Plus, 3, 1, 4>>::ELIMINATES_GROUP {
        cycling(&mut g, "generated_eliminated", &points, |p| {
            let s = &p.state;
            let x1 = p.guess.fixed_rows::<3>(0).into_owned();
            sys.eliminated_residual_jacobian(&s.x, &s.w, &s.mu, &x1)
        });
    }
    cycling(&mut g, "num_dual_hessian", &points, |p| {
        let s = &p.state;
        ad::residual_jacobian::<L, 3, 1, 4, 7>(&sys, &s.x, &s.w, &s.mu, &p.guess)
    });
    cycling(&mut g, "num_dual_partial_hessian", &points, |p| {
        let s = &p.state;
        ad::residual_jacobian_partial::<L, 3, 1, 4>(&sys, &s.x, &s.w, &s.mu, &p.guess)
    });
    cycling(&mut g, "unreduced_generated", &points, |p| {
        let s = &p.canonical;
        sys.unreduced_residual_jacobian(&s.q, &s.p, &p.canonical_guess)
    });
    g.finish();

    let mut g = c.benchmark_group(format!("{short}/step"));
    // The default path (what `ReducedIntegrator::plus` runs), then both paths forced.
    let integ = ReducedIntegrator::plus(sys, options);
    cycling(&mut g, "generated", &w.cases, |c| {
        integ.step_from(c.k, &c.state, &c.guess)
    });
    let general = ReducedIntegrator::plus(sys, options).with_elimination(false);
    cycling(&mut g, "generated_general_path", &w.cases, |c| {
        general.step_from(c.k, &c.state, &c.guess)
    });
    let eliminated = ReducedIntegrator::plus(sys, options).with_elimination(true);
    if eliminated.eliminates_group() {
        cycling(&mut g, "generated_eliminated_path", &w.cases, |c| {
            eliminated.step_from(c.k, &c.state, &c.guess)
        });
    }
    cycling(&mut g, "num_dual_hessian", &w.cases, |c| {
        ad::step::<L, 3, 1, 4, 7>(&sys, &options, ad::Jacobian::Hessian, &c.state, &c.guess)
    });
    cycling(&mut g, "num_dual_partial_hessian", &w.cases, |c| {
        let how = ad::Jacobian::PartialHessian;
        ad::step::<L, 3, 1, 4, 7>(&sys, &options, how, &c.state, &c.guess)
    });
    let unreduced = UnreducedIntegrator::new(sys, options);
    cycling(&mut g, "unreduced_generated", &w.cases, |c| {
        unreduced.step_from(c.k, &c.canonical, &c.canonical_guess)
    });
    g.finish();
}

fn charged_particle(c: &mut Criterion) {
    let w = workload::charged_particle();
    bench_system(c, "charged_particle", &w);
    let p = w.system;
    let options = NewtonOptions::default();
    let mut g = c.benchmark_group("charged_particle/eval");
    cycling(&mut g, "hand_coded", &w.spread(EVAL_POINTS), |pt| {
        let s = &pt.state;
        hand::residual_jacobian(&p, &s.x, &s.w, &s.mu, &pt.guess)
    });
    g.finish();
    let mut g = c.benchmark_group("charged_particle/step");
    cycling(&mut g, "hand_coded_newton", &w.cases, |c| {
        hand::newton_step(&p, &options, &c.state, &c.guess)
    });
    cycling(&mut g, "hand_coded_closed_form", &w.cases, |c| {
        hand::closed_form_step(&p, &c.state)
    });
    g.finish();
}

fn double_spherical_pendulum(c: &mut Criterion) {
    bench_system(
        c,
        "double_spherical_pendulum",
        &workload::double_spherical_pendulum(),
    );
}

fn config() -> Criterion {
    Criterion::default()
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2))
        .sample_size(30)
}

criterion_group! {
    name = steppers;
    config = config();
    targets = charged_particle, double_spherical_pendulum
}
criterion_main!(steppers);
