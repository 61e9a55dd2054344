//! High order on Kepler's problem: work against precision for the Gauss–Legendre variational
//! integrators of order 2s with adaptive steps (the Poincaré time transformation of
//! `time(t), adapt = |q| q.r * q.r.sqrt()`), side by side with REBOUND's IAS15 when it is
//! installed (`bash benches/rebound/run.sh` installs it and runs this example).
//!
//! For each eccentricity, span and stage count the example finds, by shrinking the fictitious
//! step by `--shrink`, the coarsest step whose position error after the span (at the physical
//! end time, reached exactly, against Kepler's equation) is at most `--tolerance`, and reports
//! the force evaluations it took — each Newton evaluation of the step equations evaluates the
//! force `∂L/∂q` at every one of the `s` stages, so a step costs `s (1 + corrections)`
//! evaluations, of which `s · factorizations` also evaluate the stage Jacobians — and the run's
//! wall time. With `--long N` it then runs N orbits at `e = 0.9` at the step found for 100
//! orbits and prints the energy error's mean over the first and last tenths.
//!
//! With `--pendulum` it measures instead the fixed-step orders of `s = 1 … 8` on the paper's
//! double spherical pendulum (its continuous Lagrangian, the paper's start, 20 time units):
//! the error at the end against RK4 of its Euler–Lagrange equations (written from the stage
//! derivatives, 2500 steps per time unit, compensated summation) for steps refined by 1.25
//! from the coarsest that converges until the error is below 3e-13, the order of each
//! refinement and the slope from the first error below 1e-4 to the last.
//!
//! Run: `cargo run --release --example high_order [-- --orbits 10,100 --stages 4,6,8]` (or
//! `-- --pendulum`); with `DEBUG_HIGH_ORDER=1` in the environment every trial step and its error
//! or failure go to stderr.

use std::f64::consts::PI;
use std::process::Command;
use std::time::Instant;

use dirac::prelude::*;

#[path = "common/cli.rs"]
mod cli;

use cli::{any, at_least, greater_than, Cli};

/// Kepler's problem in polar coordinates (`GM = k`), the step following the free-fall time
/// `r^{3/2}`.
#[reduced_lagrangian(shape(r), group(theta, t), time(t), adapt = |q| q.r * q.r.sqrt(), rule = midpoint)]
fn kepler(q: Config, v: Velocity, k: f64) -> f64 {
    0.5 * (v.r * v.r + q.r * q.r * v.theta * v.theta) + k / q.r
}

const TAU: f64 = 2.0 * PI;

/// The position `(x, y)` at time `t` of the orbit of eccentricity `e` (semi-major axis 1,
/// `GM = 1`, period 2π) from periapsis on the x axis: the closed form of
/// [`dirac::systems::kepler::Kepler::exact`] (Kepler's equation).
fn exact_position(e: f64, t: f64) -> [f64; 2] {
    let exact = dirac::systems::kepler::Kepler::unit(1.0).exact(1.0, e, t);
    let (r, phi) = (exact.x[0], exact.g[0]);
    [r * phi.cos(), r * phi.sin()]
}

/// Newton's options with `tol` as both tolerances (`--newton-tol`, default the default
/// options' 1e-12).
fn options(tol: f64) -> NewtonOptions {
    NewtonOptions {
        abs_tol: tol,
        rel_tol: tol,
        ..NewtonOptions::default()
    }
}

/// One adaptive run of `orbits` orbits with `stages` stages at the fictitious step `eps`.
struct Outcome {
    error: f64,
    evaluations: u64,
    jacobians: u64,
    steps: usize,
    seconds: f64,
    energy: Vec<f64>,
}

fn run(
    e: f64,
    orbits: f64,
    stages: usize,
    eps: f64,
    newton: f64,
    energies: bool,
) -> Option<Outcome> {
    let sys = Kepler { h: eps, k: 1.0 };
    let r0 = 1.0 - e;
    let start = sys
        .unreduced_state([r0, 0.0, 0.0], [0.0, (1.0 - e * e).sqrt() / (r0 * r0), 1.0])
        .ok()?;
    let integrator = GaussIntegrator::new(sys, stages, options(newton)).ok()?;
    let t_end = orbits * TAU;
    let clock = Instant::now();
    let traj = integrator
        .run(start)
        .end_time(t_end)
        .steps(usize::MAX)
        .collect();
    let traj = match traj {
        Ok(traj) => traj,
        Err(failure) => {
            if std::env::var_os("DEBUG_HIGH_ORDER").is_some() {
                eprintln!("e {e} s {stages} eps {eps:e}: {}", failure.source);
            }
            return None;
        }
    };
    let seconds = clock.elapsed().as_secs_f64();
    let last = traj.states.last()?;
    let (r, theta) = (last.q[0], last.q[1]);
    let [x, y] = exact_position(e, last.q[2]);
    let error = (r * theta.cos() - x).hypot(r * theta.sin() - y);
    if std::env::var_os("DEBUG_HIGH_ORDER").is_some() {
        eprintln!("e {e} s {stages} eps {eps:e}: error {error:e}");
    }
    let s = stages as u64;
    let evaluations = traj
        .stats
        .iter()
        .map(|st| s * (1 + st.iterations as u64))
        .sum();
    let jacobians = traj
        .stats
        .iter()
        .map(|st| s * st.factorizations as u64)
        .sum();
    let energy = if energies {
        // The physical energy H = (p_r² + p_θ²/r²)/2 − 1/r of the state (the momenta of the
        // time-transformed system are the physical ones; p_t = −E is kept exactly by
        // construction and says nothing).
        traj.states
            .iter()
            .map(|st| {
                0.5 * (st.p[0] * st.p[0] + st.p[1] * st.p[1] / (st.q[0] * st.q[0])) - 1.0 / st.q[0]
            })
            .collect()
    } else {
        Vec::new()
    };
    Some(Outcome {
        error,
        evaluations,
        jacobians,
        steps: traj.step_count(),
        seconds,
        energy,
    })
}

/// The coarsest fictitious step (from 1, shrinking by `shrink`) whose error is at most `tol`;
/// `Err(floor)` when four trials in a row stop improving (within a factor 3, below 1e-8): the
/// error no longer falls with the step, it is the rounding of the problem's own data.
fn coarsest(
    e: f64,
    orbits: f64,
    stages: usize,
    tol: f64,
    shrink: f64,
    newton: f64,
) -> Result<(f64, Outcome), f64> {
    let mut eps = 1.0;
    let mut errors: Vec<f64> = Vec::new();
    for _ in 0..60 {
        if let Some(outcome) = run(e, orbits, stages, eps, newton, false) {
            if outcome.error <= tol {
                return Ok((eps, outcome));
            }
            errors.push(outcome.error);
            if let [.., a, b, c, d] = errors[..] {
                let (lo, hi) = (a.min(b).min(c).min(d), a.max(b).max(c).max(d));
                if hi < 1e-8 && hi < 3.0 * lo {
                    return Err(lo);
                }
            }
        }
        eps /= shrink;
    }
    Err(errors.iter().copied().fold(f64::INFINITY, f64::min))
}

/// The cost of one stage evaluation (`f` and `p` at one `(Q, V)`) against one evaluation of the
/// second-order step's residual (the midpoint rule's unreduced residual `D1 L_d(q0, q1) + p0`) of
/// the same system, timed alternately in batches; the median ratio and its spread over seven
/// rounds.
fn stage_cost() {
    let sys = Kepler { h: 0.1, k: 1.0 };
    let (q, v) = (
        dirac::runtime::nalgebra::Vector3::new(0.7, 0.3, 1.0),
        dirac::runtime::nalgebra::Vector3::new(0.1, 0.9, 0.4),
    );
    let p = sys.legendre(&q, &v);
    let z = q + 0.1 * v;
    let n = 2_000_000;
    let time = |f: &dyn Fn(usize) -> f64| {
        let clock = Instant::now();
        let mut acc = 0.0;
        for i in 0..n {
            acc += f(i);
        }
        std::hint::black_box(acc);
        clock.elapsed().as_secs_f64() / n as f64
    };
    let mut ratios = Vec::new();
    let (mut stage_ns, mut residual_ns) = (Vec::new(), Vec::new());
    for _ in 0..7 {
        let a = time(&|i| {
            let qi = std::hint::black_box(q);
            sys.stage(&qi, &v).0[i & 1]
        });
        let b = time(&|i| {
            let qi = std::hint::black_box(q);
            sys.unreduced_residual(&qi, &p, &z)[i & 1]
        });
        ratios.push(a / b);
        stage_ns.push(a * 1e9);
        residual_ns.push(b * 1e9);
    }
    ratios.sort_by(f64::total_cmp);
    stage_ns.sort_by(f64::total_cmp);
    residual_ns.sort_by(f64::total_cmp);
    println!(
        "one stage evaluation {:.1} ns, one midpoint residual {:.1} ns (medians): ratio {:.2} [{:.2}, {:.2}] over 7 rounds",
        stage_ns[3], residual_ns[3], ratios[3], ratios[0], ratios[6]
    );
}

/// `--pendulum`: the observed orders of the fixed-step Gauss–Legendre integrators on the paper's
/// double spherical pendulum (see the module documentation).
fn pendulum_orders() {
    use dirac::paper::DoubleSphericalPendulumContinuous as Dsp;
    use dirac::runtime::nalgebra::{SVector, Vector4};
    let (sys, t) = (Dsp::paper(), 20.0);
    let start = UnreducedState::new([2.25, 2.0, 3.0, 0.0], [0.0, 1.0, 1.0, 0.0]);
    let v0 = sys
        .velocity(0, &start.q, &start.p, SVector::zeros())
        .expect("the paper's start is regular");
    // The Euler–Lagrange equations: ∂p/∂v q̈ = f − ∂p/∂q q̇.
    let rate = |y: &SVector<f64, 8>| {
        let q = Vector4::new(y[0], y[1], y[2], y[3]);
        let v = Vector4::new(y[4], y[5], y[6], y[7]);
        let j = sys.stage_jacobian(&q, &v);
        let a = j.p_v.lu().solve(&(j.f - j.p_q * v)).expect("regular");
        SVector::<f64, 8>::from_iterator(v.iter().chain(a.iter()).copied())
    };
    let steps = (2500.0 * t) as usize;
    let dt = t / steps as f64;
    let mut y = SVector::<f64, 8>::from_iterator(start.q.iter().chain(v0.iter()).copied());
    let mut carry = SVector::<f64, 8>::zeros();
    for _ in 0..steps {
        let k1 = rate(&y);
        let k2 = rate(&(y + k1 * (dt / 2.0)));
        let k3 = rate(&(y + k2 * (dt / 2.0)));
        let k4 = rate(&(y + k3 * dt));
        let increment = (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (dt / 6.0);
        for i in 0..8 {
            let added = increment[i] + carry[i];
            let sum = y[i] + added;
            carry[i] = added - (sum - y[i]);
            y[i] = sum;
        }
    }
    let q_ref = Vector4::new(y[0], y[1], y[2], y[3]);
    let p_ref = sys.legendre(&q_ref, &Vector4::new(y[4], y[5], y[6], y[7]));
    let tight = options(1e-14);
    println!("the double spherical pendulum over {t} time units: error at the end (max of |Δq| and |Δp|/|p|)");
    for s in 1..=8usize {
        // (error, steps) at the first error below 1e-4 and at the last.
        let mut first: Option<(f64, f64)> = None;
        let mut last: Option<(f64, f64)> = None;
        let mut n = 4.0;
        let mut line = format!("s = {s} (order {:>2}):", 2 * s);
        while n < 2e4 {
            let integrator =
                GaussIntegrator::new(Dsp { h: t / n, ..sys }, s, tight).expect("1 to 16 stages");
            if let Ok(traj) = integrator.run(start).steps(n as usize).collect() {
                let end = traj.states.last().expect("the start");
                let error = (end.q - q_ref)
                    .amax()
                    .max((end.p - p_ref).amax() / p_ref.amax());
                match last {
                    Some((e0, n0)) => {
                        line += &format!(
                            " {n} {error:.2e} ({:.2})",
                            (e0 / error).ln() / (n / n0).ln()
                        )
                    }
                    None => line += &format!(" {n} {error:.2e}"),
                }
                if error < 1e-4 {
                    first.get_or_insert((error, n));
                }
                last = Some((error, n));
                if error < 3e-13 {
                    break;
                }
            }
            n = (n * 1.25).ceil();
        }
        if let (Some((e0, n0)), Some((e1, n1))) = (first, last) {
            line += &format!("; slope {:.2}", (e0 / e1).ln() / (n1 / n0).ln());
        }
        println!("{line}");
    }
}

fn main() {
    let mut cli = Cli::new(
        "high_order",
        "work against precision of the Gauss–Legendre integrators on Kepler's problem, beside REBOUND's IAS15",
    );
    let orbits: Vec<f64> = cli.list(
        "--orbits",
        "N,..",
        "spans in orbits",
        &[10.0, 100.0],
        greater_than(0.0),
    );
    let eccentricities: Vec<f64> = cli.list(
        "--eccentricities",
        "E,..",
        "eccentricities",
        &[0.9, 0.99],
        greater_than(0.0),
    );
    let stages: Vec<usize> = cli.list(
        "--stages",
        "S,..",
        "stage counts (order 2s)",
        &[4, 6, 8],
        at_least(1),
    );
    let tol: f64 = cli.value(
        "--tolerance",
        "TOL",
        "position error each run must reach",
        1e-10,
        greater_than(0.0),
    );
    let shrink: f64 = cli.value(
        "--shrink",
        "F",
        "factor between trial fictitious steps",
        1.25,
        greater_than(1.0),
    );
    let newton: f64 = cli.value(
        "--newton-tol",
        "TOL",
        "Newton's absolute and relative tolerance",
        1e-12,
        greater_than(0.0),
    );
    let long: f64 = cli.value(
        "--long",
        "N",
        "orbits of the energy run at e = 0.9 (0: none)",
        0.0,
        at_least(0.0),
    );
    let rebound: Option<String> = cli.optional(
        "--rebound",
        "PYTHON",
        "a Python with REBOUND, to run IAS15 on the same problems",
        any(),
    );
    let pendulum = cli.switch(
        "--pendulum",
        "measure the fixed-step orders on the double spherical pendulum instead",
    );
    cli.finish();
    if pendulum {
        pendulum_orders();
        return;
    }

    println!("Kepler's problem (a = 1, GM = 1, from periapsis), position error ≤ {tol:e}");
    println!(
        "{:>5} {:>7} {:>22} {:>9} {:>10} {:>12} {:>10} {:>10}",
        "e", "orbits", "method", "eps", "error", "evaluations", "steps", "seconds"
    );
    let mut found_100 = None;
    let mut ias15_eps_100: Option<String> = None;
    for &e in &eccentricities {
        for &n in &orbits {
            for &s in &stages {
                match coarsest(e, n, s, tol, shrink, newton) {
                    Ok((eps, o)) => {
                        println!(
                            "{e:>5} {n:>7} {:>22} {eps:>9.3e} {:>10.2e} {:>12} {:>10} {:>10.4}",
                            format!("dirac Gauss s = {s} (order {})", 2 * s),
                            o.error,
                            o.evaluations,
                            o.steps,
                            o.seconds
                        );
                        println!("machine dirac e={e} orbits={n} stages={s} eps={eps:e} error={:e} evaluations={} jacobians={} steps={} seconds={}", o.error, o.evaluations, o.jacobians, o.steps, o.seconds);
                        if e == 0.9 && n == 100.0 && found_100.is_none() {
                            found_100 = Some((s, eps));
                        }
                    }
                    Err(floor) => println!(
                        "{e:>5} {n:>7} dirac Gauss s = {s}: no step reached {tol:e} (the error stops falling at {floor:.2e})"
                    ),
                }
            }
            if let Some(python) = &rebound {
                let script = concat!(env!("CARGO_MANIFEST_DIR"), "/benches/rebound/kepler.py");
                match Command::new(python)
                    .args([script, &e.to_string(), &n.to_string(), &tol.to_string()])
                    .output()
                {
                    Ok(out) if out.status.success() => {
                        let text = String::from_utf8_lossy(&out.stdout);
                        print!("{text}");
                        if e == 0.9 && n == 100.0 {
                            ias15_eps_100 = text
                                .lines()
                                .filter(|l| {
                                    l.starts_with("machine rebound") && l.contains("coarsest")
                                })
                                .find_map(|l| {
                                    l.split(" epsilon=")
                                        .nth(1)?
                                        .split(' ')
                                        .next()
                                        .map(str::to_owned)
                                });
                        }
                    }
                    Ok(out) => println!(
                        "REBOUND's run failed: {}",
                        String::from_utf8_lossy(&out.stderr).trim()
                    ),
                    Err(err) => println!("REBOUND's Python ({python}) did not start: {err}"),
                }
            }
        }
    }
    stage_cost();
    if rebound.is_none() {
        println!("REBOUND: not given (--rebound <python with rebound>; bash benches/rebound/run.sh installs it): dirac's figures alone");
    }
    if long > 0.0 {
        let Some((s, eps)) = found_100 else {
            println!("--long: no step found for e = 0.9 at 100 orbits");
            return;
        };
        let o = run(0.9, long, s, eps, newton, true).expect("the long run");
        let tenth = o.energy.len() / 10;
        let e0 = o.energy[0];
        let mean = |xs: &[f64]| xs.iter().map(|x| (x - e0).abs()).sum::<f64>() / xs.len() as f64;
        let (first, last) = (
            mean(&o.energy[..tenth]),
            mean(&o.energy[o.energy.len() - tenth..]),
        );
        println!(
            "long run: e = 0.9, {long} orbits, s = {s}, eps = {eps:e}: {} steps in {:.1} s; mean |ΔE| first tenth {first:.3e}, last tenth {last:.3e} (ratio {:.2}); position error {:.3e}",
            o.steps,
            o.seconds,
            last / first,
            o.error
        );
        println!("machine dirac-long orbits={long} stages={s} eps={eps:e} first={first:e} last={last:e} error={:e} seconds={}", o.error, o.seconds);
        if let (Some(python), Some(epsilon)) = (&rebound, &ias15_eps_100) {
            let script = concat!(env!("CARGO_MANIFEST_DIR"), "/benches/rebound/kepler.py");
            match Command::new(python)
                .args([script, "long", "0.9", &long.to_string(), epsilon])
                .output()
            {
                Ok(out) if out.status.success() => {
                    print!("{}", String::from_utf8_lossy(&out.stdout))
                }
                Ok(out) => println!(
                    "REBOUND's long run failed: {}",
                    String::from_utf8_lossy(&out.stderr).trim()
                ),
                Err(err) => println!("REBOUND's Python ({python}) did not start: {err}"),
            }
        }
    }
}
