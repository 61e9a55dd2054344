//! Discrete-mechanics optimal control (DMOC): the swing-up of the cart-pole, solved in Rust
//! with dirac's steps and step sensitivities, and compared with the same discrete problem
//! transcribed in CasADi and solved by IPOPT (`examples/dmoc/cartpole_casadi.py`).
//!
//! ```sh
//! cargo run --release --example dmoc_cartpole -- [--N 100] [--T 2] [--repeats 10] [--casadi]
//! ```
//!
//! The problem (`examples/common/dmoc.rs`, the docstring of the CasADi script): the cart-pole of
//! `examples/common/cartpole.rs`, midpoint rule, `N` steps over `T`, from hanging at rest
//! `(θ, s) = (π, 0)` to upright at rest `(0, 0)`, minimising `J = h Σ u_k²`. The optimiser is a
//! Newton–KKT SQP on the lifted shooting problem (exact first derivatives from dirac's
//! sensitivities, Hessian blocks by differences of them, a Riccati recursion; see
//! `dmoc::solve`), started from CasADi's initial guess (`u = 0`, configurations linear in `k`).
//! The example prints the optimal cost, the iterations, the constraint violation of the optimal
//! controls under a plain forward pass (single shooting), single shooting's first-order
//! residual `‖∇J − Jᵀλ‖` with the chained Jacobian, and the median and minimum wall time of the
//! solve over `--repeats` solves from the same guess. With `--casadi` it also runs the CasADi
//! baseline (installed by `scripts/setup-casadi.sh`) on the same `N`, `T` and repeats and prints
//! both costs, their relative difference and the ratio of the median solve times.
//!
//! Why no optimisation crate: `optimization_engine` 0.12 (augmented Lagrangian with
//! `constraints::Zero` on `s_N − target`, PANOC inside, the exact `Jᵀy` from the same
//! sensitivities; single shooting from `u = 0`, N = 100) did not converge: with tolerances
//! 1e-6 it stopped after 100 outer and 4,795 inner iterations, 1.08 s, at cost 54.53 with a
//! violation of 5.9e-4; with 1e-4, after 0.11 s at cost 73.9 (violation 1.1e-3); its
//! multipliers ran to 1e6–1e7 as the penalty grew. The final state is a badly scaled, strongly
//! nonlinear function of `u` (the pole's final angular momentum `w_N`: `m l² = 0.025`), which a
//! first-order inner solver cannot resolve to 1e-6 in any time near IPOPT's.

use std::process::Command;
use std::time::Instant;

use dirac::nalgebra::DVector;

#[path = "common/cli.rs"]
mod cli;
use cli::{at_least, greater_than, Cli};
#[path = "common/stats.rs"]
mod stats;
use stats::median;

#[path = "common/cartpole.rs"]
mod cartpole;
#[path = "common/dmoc.rs"]
mod dmoc;

use dmoc::{multipliers, solve, SqpOptions, Swingup};

struct Args {
    n: usize,
    t: f64,
    repeats: usize,
    casadi: bool,
}

/// The command line: `--help` lists it; a bad value stops the example with exit code 2.
fn parse_args() -> Args {
    let mut cli = Cli::new(
        "dmoc_cartpole",
        "DMOC swing-up of the cart-pole by dirac's SQP, optionally against CasADi + IPOPT",
    );
    let args = Args {
        n: cli.value("--N", "N", "number of time steps", 100, at_least(2)),
        t: cli.value("--T", "T", "final time", 2.0, greater_than(0.0)),
        repeats: cli.value("--repeats", "R", "timed solves", 10, at_least(1)),
        casadi: cli.switch(
            "--casadi",
            "also solve the same problem with CasADi + IPOPT (python3)",
        ),
    };
    cli.finish();
    args
}

/// The number after `"key":` in a one-line JSON object.
fn json_number(json: &str, key: &str) -> Option<f64> {
    let start = json.find(&format!("\"{key}\":"))? + key.len() + 3;
    let rest = json[start..].trim_start();
    let end = rest.find([',', '}']).unwrap_or(rest.len());
    rest[..end].trim().parse().ok()
}

/// Runs the CasADi baseline on the same problem; `Ok(None)` (with the reason printed) when
/// python3 is missing.
fn run_casadi(args: &Args) -> Result<Option<String>, String> {
    if Command::new("python3").arg("--version").output().is_err() {
        println!("casadi: skipped, python3 is not installed (scripts/setup-casadi.sh needs it)");
        return Ok(None);
    }
    let root = env!("CARGO_MANIFEST_DIR");
    let setup = Command::new(format!("{root}/scripts/setup-casadi.sh"))
        .output()
        .map_err(|e| format!("scripts/setup-casadi.sh: {e}"))?;
    if !setup.status.success() {
        return Err(format!(
            "scripts/setup-casadi.sh failed: {}",
            String::from_utf8_lossy(&setup.stderr)
        ));
    }
    let python = String::from_utf8_lossy(&setup.stdout).trim().to_string();
    let run = Command::new(format!("{root}/{python}"))
        .arg(format!("{root}/examples/dmoc/cartpole_casadi.py"))
        .args(["--N", &args.n.to_string(), "--T", &args.t.to_string()])
        .args(["--repeats", &args.repeats.to_string()])
        .output()
        .map_err(|e| format!("{python}: {e}"))?;
    if !run.status.success() {
        return Err(format!(
            "the CasADi baseline failed: {}",
            String::from_utf8_lossy(&run.stderr)
        ));
    }
    Ok(Some(
        String::from_utf8_lossy(&run.stdout).trim().to_string(),
    ))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = parse_args();
    let problem = Swingup::new(args.n, args.t);
    let (u0, s0) = (vec![0.0; args.n], problem.linear_guess());
    println!(
        "DMOC swing-up of the cart-pole: N = {}, T = {}, h = {}; dirac's lifted Newton-KKT SQP \
         from u = 0 and linear configurations",
        args.n, args.t, problem.h
    );
    let mut times = Vec::with_capacity(args.repeats);
    let mut best = None;
    for _ in 0..args.repeats {
        let start = Instant::now();
        let sol = solve(&problem, &u0, &s0, SqpOptions::default())?;
        times.push(start.elapsed().as_secs_f64());
        best = Some(sol);
    }
    let sol = best.expect("at least one solve");
    // The optimum as a single-shooting solution: a plain forward pass and the chained Jacobian.
    let shot = problem.shoot(&sol.u)?;
    let jac = problem.jacobian(&sol.u, &shot)?;
    let grad = DVector::from_column_slice(&sol.u) * (2.0 * problem.h);
    let (lambda, stationarity) = multipliers(&grad, &jac);
    let (med, min) = (
        median(times.clone()),
        times.iter().copied().fold(f64::INFINITY, f64::min),
    );
    println!("  optimal cost J                 {:.15}", sol.cost);
    println!(
        "  iterations                     {} ({} sweeps over the N steps)",
        sol.iterations, sol.sweeps
    );
    println!(
        "  constraint violation           {:.2e} (|s_N - target|, forward pass of the optimal u)",
        shot.defect.amax()
    );
    println!("  first-order residual           {stationarity:.2e} (|grad J - J^T lambda| / |grad J|, chained Jacobian)");
    println!("  multipliers (x, w, mu, g)_N    {:?}", lambda.as_slice());
    println!(
        "  solve wall time                median {:.3} ms, min {:.3} ms over {} solves",
        med * 1e3,
        min * 1e3,
        args.repeats
    );
    if args.casadi {
        match run_casadi(&args)? {
            None => {}
            Some(json) => {
                let field = |k: &str| {
                    json_number(&json, k).ok_or(format!("no {k} in the CasADi output: {json}"))
                };
                let (cost, it) = (field("cost")?, field("iterations")?);
                let (cmed, cmin) = (field("solve_seconds_median")?, field("solve_seconds_min")?);
                println!("CasADi + IPOPT (examples/dmoc/cartpole_casadi.py, same N, T, repeats):");
                println!("  optimal cost J                 {cost:.15} ({it} IPOPT iterations)");
                println!(
                    "  solve wall time                median {:.3} ms, min {:.3} ms",
                    cmed * 1e3,
                    cmin * 1e3
                );
                println!(
                    "  cost relative difference       {:.2e} (target <= 1e-6)",
                    ((sol.cost - cost) / cost).abs()
                );
                println!(
                    "  solve time dirac / CasADi      {:.2} (median), {:.2} (min) (target <= 1)",
                    med / cmed,
                    min / cmin
                );
            }
        }
    }
    Ok(())
}
