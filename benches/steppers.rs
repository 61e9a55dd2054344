//! Criterion benchmarks of the generated (+) steppers against run-time AD (num-dual), a
//! hand-coded stepper (charged particle) and the unreduced stepper from the same annotation, on
//! the paper's two systems. `examples/bench_table.rs` measures the same in one process and prints
//! the ratios, with CasADi's generated C beside them.
//!
//! `eval`: one residual+Jacobian evaluation of eq. (4.6), cycling over points spread along the
//! paper's run (at the integrator's Newton guess). `step`: one whole step (Newton included),
//! cycling over the steps of the paper's run, each from the trajectory's state and the guess the
//! integrator itself starts from; the mean Newton iterations of those steps are printed first.
//!
//! `cargo bench --bench steppers` (add `-- --quick` for a fast pass).

mod common;

use std::hint::black_box;
use std::time::Duration;

use common::workload::{self, Workload};
use common::{ad, hand};
use criterion::{criterion_group, criterion_main, Criterion};
use dirac::prelude::*;

/// Evaluation points per system.
const EVAL_POINTS: usize = 64;

/// `f(i)` for `i = 0, 1, 2, …`, one call per iteration.
fn cycling<T>(mut f: impl FnMut(usize) -> T) -> impl FnMut() -> T {
    let mut i = 0;
    move || {
        i += 1;
        f(i - 1)
    }
}

/// The benchmarks every system gets: generated, num-dual (both Jacobians) and unreduced.
fn bench_system<L>(c: &mut Criterion, short: &str, w: &Workload<L, 3, 1, 4>)
where
    L: ReducedPlus<3, 1, 4>
        + ReducedMinus<3, 1, 4>
        + Unreduced<3, 1, 4>
        + ad::DualLagrangian<4>
        + Copy,
{
    println!(
        "{}: {} steps timed, mean Newton iterations {:.3}",
        w.name,
        w.cases.len(),
        w.mean_iterations()
    );
    let sys = w.system;
    let points = w.spread(EVAL_POINTS);
    let options = NewtonOptions::default();

    let mut g = c.benchmark_group(format!("{short}/eval"));
    let mut eval = |name: &str,
                    f: &dyn Fn(
        &ReducedState<3, 1>,
        &SVector<f64, 4>,
    ) -> (SVector<f64, 4>, SMatrix<f64, 4, 4>)| {
        g.bench_function(name, |b| {
            let mut next = cycling(|i| {
                let p = &points[i % points.len()];
                f(black_box(&p.state), black_box(&p.guess))
            });
            b.iter(&mut next)
        });
    };
    eval("generated", &|s, z| {
        sys.plus_residual_jacobian(&s.x, &s.w, &s.mu, z)
    });
    eval("num_dual_hessian", &|s, z| {
        ad::residual_jacobian::<L, 3, 1, 4, 7>(&sys, &s.x, &s.w, &s.mu, z)
    });
    eval("num_dual_partial_hessian", &|s, z| {
        ad::residual_jacobian_partial::<L, 3, 1, 4>(&sys, &s.x, &s.w, &s.mu, z)
    });
    g.bench_function("unreduced_generated", |b| {
        let mut next = cycling(|i| {
            let p = &points[i % points.len()];
            let s = black_box(&p.canonical);
            sys.unreduced_residual_jacobian(&s.q, &s.p, black_box(&p.canonical_guess))
        });
        b.iter(&mut next)
    });
    g.finish();

    let cases = &w.cases;
    let mut g = c.benchmark_group(format!("{short}/step"));
    let integ = ReducedIntegrator::plus(sys, options);
    g.bench_function("generated", |b| {
        let mut next = cycling(|i| {
            let c = &cases[i % cases.len()];
            integ.step(c.k, black_box(&c.state), black_box(&c.guess))
        });
        b.iter(&mut next)
    });
    for (name, how) in [
        ("num_dual_hessian", ad::Jacobian::Hessian),
        ("num_dual_partial_hessian", ad::Jacobian::PartialHessian),
    ] {
        g.bench_function(name, |b| {
            let mut next = cycling(|i| {
                let c = &cases[i % cases.len()];
                ad::step::<L, 3, 1, 4, 7>(
                    &sys,
                    &options,
                    how,
                    black_box(&c.state),
                    black_box(&c.guess),
                )
            });
            b.iter(&mut next)
        });
    }
    let unreduced = UnreducedIntegrator::plus(sys, options);
    g.bench_function("unreduced_generated", |b| {
        let mut next = cycling(|i| {
            let c = &cases[i % cases.len()];
            unreduced.step(c.k, black_box(&c.canonical), black_box(&c.canonical_guess))
        });
        b.iter(&mut next)
    });
    g.finish();
}

fn charged_particle(c: &mut Criterion) {
    let w = workload::charged_particle();
    bench_system(c, "charged_particle", &w);
    let p = w.system;
    let points = w.spread(EVAL_POINTS);
    let options = NewtonOptions::default();
    c.bench_function("charged_particle/eval/hand_coded", |b| {
        let mut next = cycling(|i| {
            let pt = &points[i % points.len()];
            let s = black_box(&pt.state);
            hand::residual_jacobian(&p, &s.x, &s.w, &s.mu, black_box(&pt.guess))
        });
        b.iter(&mut next)
    });
    let cases = &w.cases;
    c.bench_function("charged_particle/step/hand_coded_newton", |b| {
        let mut next = cycling(|i| {
            let c = &cases[i % cases.len()];
            hand::newton_step(&p, &options, black_box(&c.state), black_box(&c.guess))
        });
        b.iter(&mut next)
    });
    c.bench_function("charged_particle/step/hand_coded_closed_form", |b| {
        let mut next =
            cycling(|i| hand::closed_form_step(&p, black_box(&cases[i % cases.len()].state)));
        b.iter(&mut next)
    });
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
