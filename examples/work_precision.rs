//! Work–precision: error against wall time for the midpoint rule (order 2) and its symmetric
//! compositions — the triple jump (order 4), Yoshida's 7-stage and Kahan–Li's 9-stage schemes
//! (order 6) — on the Kepler problem in polar coordinates (against Kepler's equation) and on the
//! paper's double spherical pendulum (against a Kahan–Li run at a much smaller step). Prints the table and the observed orders, and writes one SVG per system.
//!
//! ```text
//! cargo run --release --example work_precision [-- --out DIR]
//! ```

mod common;

use std::error::Error;
use std::f64::consts::PI;
use std::time::Instant;

use common::{Curve, LineChart};
use dirac::paper::DoubleSphericalPendulum;
use dirac::prelude::*;
use dirac::systems::kepler::Kepler;
use plotters::style::RGBColor;

/// The methods compared, with their plot colours.
const METHODS: [(CompositionMethod, RGBColor); 4] = [
    (CompositionMethod::BASE, RGBColor(0, 0, 0)),
    (CompositionMethod::TRIPLE_JUMP, RGBColor(31, 119, 180)),
    (CompositionMethod::YOSHIDA_6, RGBColor(44, 160, 44)),
    (CompositionMethod::KAHAN_LI_6, RGBColor(214, 39, 40)),
];

/// Newton solved to round-off for every method (the defaults, 1e-12 on the momentum residual,
/// leave up to 1e-12 of momentum error per stage, which floors an order-6 run near 1e-9).
fn tight() -> NewtonOptions {
    NewtonOptions {
        abs_tol: 1e-15,
        rel_tol: 1e-15,
        ..NewtonOptions::default()
    }
}

/// Runs of the fastest of `repeats` timings.
const REPEATS: usize = 5;

/// One measured point.
struct Point {
    steps: usize,
    h: f64,
    error: f64,
    seconds: f64,
    newton_per_stage: f64,
}

/// Integrates `steps` macro steps of `method` from `initial` with `base` (at the macro step),
/// returning the last state, the best wall time of [`REPEATS`] and the mean Newton corrections
/// per stage.
fn timed_run<I: SelfAdjoint>(
    base: I,
    method: CompositionMethod,
    initial: I::State,
    steps: usize,
) -> Result<(I::State, f64, f64), Box<dyn Error>> {
    let comp = Composition::new(base, method);
    let mut best = f64::INFINITY;
    let mut result = None;
    for _ in 0..REPEATS {
        let start = Instant::now();
        let traj = comp.run(initial.clone()).steps(steps).collect()?;
        best = best.min(start.elapsed().as_secs_f64());
        result = Some(traj);
    }
    let traj = result.ok_or("no run")?;
    let per_stage = traj.mean_iterations() / method.stages() as f64;
    Ok((traj.last().clone(), best, per_stage))
}

/// The least-squares slope of `log error` against `log h`.
fn slope(points: &[&Point]) -> f64 {
    let n = points.len() as f64;
    let (mx, my) = points.iter().fold((0.0, 0.0), |(a, b), p| {
        (a + p.h.ln() / n, b + p.error.ln() / n)
    });
    let sxy: f64 = points
        .iter()
        .map(|p| (p.h.ln() - mx) * (p.error.ln() - my))
        .sum();
    let sxx: f64 = points.iter().map(|p| (p.h.ln() - mx).powi(2)).sum();
    sxy / sxx
}

/// Prints one system's table and returns its chart. The observed orders are fitted over the
/// points with errors in `fit_window`: above the round-off floor and out of the pre-asymptotic
/// range of the largest steps.
fn report(
    system: &str,
    error_name: &str,
    results: &[(CompositionMethod, RGBColor, Vec<Point>)],
    fit_window: std::ops::Range<f64>,
) -> LineChart {
    println!("\n{system}: {error_name} against wall time (best of {REPEATS} runs)");
    println!(
        "{:28} {:>7} {:>10} {:>11} {:>12} {:>14}",
        "method", "steps", "h", "error", "wall [ms]", "Newton/stage"
    );
    for (method, _, points) in results {
        for p in points {
            println!(
                "{:28} {:>7} {:>10.3e} {:>11.3e} {:>12.3} {:>14.2}",
                method.name,
                p.steps,
                p.h,
                p.error,
                p.seconds * 1e3,
                p.newton_per_stage
            );
        }
    }
    println!(
        "observed orders (least-squares slope of log error against log h, errors in {:.0e}..{:.0e}):",
        fit_window.start, fit_window.end
    );
    for (method, _, points) in results {
        let fit: Vec<&Point> = points
            .iter()
            .filter(|p| fit_window.contains(&p.error))
            .collect();
        if fit.len() >= 2 {
            println!(
                "  {:28} {:.2} (over {} step sizes)",
                method.name,
                slope(&fit),
                fit.len()
            );
        }
    }
    LineChart {
        title: format!("{system}: work–precision"),
        x_label: "log10 wall time [s]".into(),
        y_label: format!("log10 {error_name}"),
        curves: results
            .iter()
            .map(|(method, color, points)| Curve {
                label: method.name.into(),
                points: points
                    .iter()
                    .map(|p| (p.seconds.log10(), p.error.log10()))
                    .collect(),
                color: *color,
            })
            .collect(),
        equal_axes: false,
    }
}

/// Whether the last point no longer improves on the one before by a factor 2: the error has
/// reached the round-off floor, and smaller steps only cost time.
fn reached_floor(points: &[Point]) -> bool {
    matches!(points, [.., a, b] if b.error > 0.5 * a.error)
}

/// Kepler, eccentricity 0.5, over 10 periods (T = 20π); error `max(|Δr|, |Δφ|, |Δp_r|)` at T.
fn kepler() -> Result<LineChart, Box<dyn Error>> {
    let (a, e) = (1.0, 0.5);
    let t = 20.0 * PI;
    let exact = Kepler::unit(1.0).exact(a, e, t);
    let mut results = Vec::new();
    for (method, color) in METHODS {
        let mut points = Vec::new();
        for k in 0..9 {
            let steps = 250 << k;
            if steps > 2_000_000 / method.stages() {
                break;
            }
            let sys = Kepler::unit(t / steps as f64);
            let (end, seconds, newton_per_stage) = timed_run(
                ReducedIntegrator::plus(sys, tight()),
                method,
                sys.periapsis_state(a, e),
                steps,
            )?;
            let error = (end.x[0] - exact.x[0])
                .abs()
                .max((end.g[0] - exact.g[0]).abs())
                .max((end.w[0] - exact.w[0]).abs());
            points.push(Point {
                steps,
                h: sys.h,
                error,
                seconds,
                newton_per_stage,
            });
            if reached_floor(&points) {
                break;
            }
        }
        results.push((method, color, points));
    }
    Ok(report(
        "Kepler (e = 0.5, 10 periods)",
        "max |Δ(r, φ, p_r)|",
        &results,
        1e-8..1e-2,
    ))
}

/// The double spherical pendulum of §7.2 (paper's parameters and initial state) over T = 10;
/// error `max |Δq|` (radians) at T against a Kahan–Li run with h = T / 3,200 (its truncation error,
/// extrapolated at order 6 from the table, is ~1e-13). A smaller reference step is worse, not
/// better: the motion is chaotic and amplifies the round-off of every stage, so a reference with
/// h = T / 64,000 (576,000 stages) differs by 5e-8 from the same run at 2h. For the same reason
/// the interval is T = 10, not the paper's 100: over T = 50 round-off alone leaves ~2e-7.
fn double_spherical_pendulum() -> Result<LineChart, Box<dyn Error>> {
    let t = 10.0;
    let initial = DoubleSphericalPendulum::paper_initial_state();
    let at = |steps: usize| DoubleSphericalPendulum {
        h: t / steps as f64,
        ..DoubleSphericalPendulum::paper()
    };
    let reference_steps = 3_200;
    let (reference, _, _) = timed_run(
        ReducedIntegrator::plus(at(reference_steps), tight()),
        CompositionMethod::KAHAN_LI_6,
        initial,
        reference_steps,
    )?;
    // The reference's own error, estimated by a run at twice its step (order 6: the difference is
    // ~63 times the reference's truncation error, plus round-off).
    let (coarser, _, _) = timed_run(
        ReducedIntegrator::plus(at(reference_steps / 2), tight()),
        CompositionMethod::KAHAN_LI_6,
        initial,
        reference_steps / 2,
    )?;
    let distance =
        |s: &ReducedState<3, 1>| (s.x - reference.x).amax().max((s.g - reference.g).amax());
    // How much the motion amplifies a round-off-sized change of the initial state: the floor
    // under every curve.
    let mut nudged = initial;
    nudged.x[0] += 1e-15;
    let (perturbed, _, _) = timed_run(
        ReducedIntegrator::plus(at(reference_steps), tight()),
        CompositionMethod::KAHAN_LI_6,
        nudged,
        reference_steps,
    )?;
    println!(
        "\nDouble spherical pendulum reference: Kahan–Li, h = {:.3e}; |reference − run at 2h| = {:.1e}; \
         φ1(0) changed by 1e-15 changes q(T) by {:.1e} (chaotic motion: the error floor)",
        t / reference_steps as f64,
        distance(&coarser),
        distance(&perturbed)
    );
    let mut results = Vec::new();
    for (method, color) in METHODS {
        let mut points = Vec::new();
        for k in 0..9 {
            let steps = 50 << k;
            if steps > 8_000 {
                break;
            }
            match timed_run(
                ReducedIntegrator::plus(at(steps), tight()),
                method,
                initial,
                steps,
            ) {
                Ok((end, seconds, newton_per_stage)) => points.push(Point {
                    steps,
                    h: t / steps as f64,
                    error: distance(&end),
                    seconds,
                    newton_per_stage,
                }),
                Err(e) => println!("{} with {steps} steps: {e}", method.name),
            }
            if reached_floor(&points) {
                break;
            }
        }
        results.push((method, color, points));
    }
    Ok(report(
        "Double spherical pendulum (§7.2, T = 10)",
        "max |Δq| [rad]",
        &results,
        1e-8..1e-2,
    ))
}

fn main() -> Result<(), Box<dyn Error>> {
    let out = common::output_dir(
        "work_precision",
        "compositions: error against wall time on Kepler and the double spherical pendulum",
        "target/dirac-figures/work_precision",
    );
    std::fs::create_dir_all(&out)?;
    let kepler = kepler()?;
    let dsp = double_spherical_pendulum()?;
    common::write_line_charts(&out.join("kepler.svg"), 900, 600, &[kepler])?;
    common::write_line_charts(&out.join("double_spherical_pendulum.svg"), 900, 600, &[dsp])?;
    println!(
        "\nFigures: {}/{{kepler,double_spherical_pendulum}}.svg",
        out.display()
    );
    Ok(())
}
