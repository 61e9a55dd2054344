//! The paper's §7.1: a charged particle in a constant magnetic field, integrated with the reduced
//! (+) equations (4.6): Table 1 with the observed order of convergence, and the Figure 1 data
//! (CSV) and figure (SVG).

use std::error::Error;
use std::fs;
use std::path::Path;

use dirac::paper::{ChargedParticle, ChargedParticleContinuous, CHARGED_PARTICLE_T, TABLE_1};
use dirac::prelude::*;
use plotters::prelude::*;

/// Prints Table 1, `|q(T) − q_N|` for `N = 10 … 800` next to the paper's values, with the
/// observed order and the mean Newton iterations.
pub fn print_table_1() -> Result<(), Box<dyn Error>> {
    println!(
        "Charged particle in a magnetic field (§7.1): m = 1, B0 = 1, T = {CHARGED_PARTICLE_T}"
    );
    println!("reduced (+) equations (4.6), left-point discrete Lagrangian\n");
    println!(
        "{:>5} {:>8} {:>14} {:>10} {:>7} {:>11}",
        "N", "h", "|q(T) - q_N|", "paper", "order", "Newton it."
    );
    let mut previous: Option<(usize, f64)> = None;
    for n in [10, 50, 100, 200, 400, 800] {
        let traj = run(n)?;
        let error = final_error(&traj);
        let paper = TABLE_1
            .iter()
            .find(|(m, _)| *m == n)
            .map_or("-".to_string(), |(_, e)| format!("{e}"));
        let order = previous.map_or("-".to_string(), |(m, e)| {
            format!("{:.3}", (e / error).ln() / (n as f64 / m as f64).ln())
        });
        println!(
            "{n:>5} {:>8.4} {error:>14.5e} {paper:>10} {order:>7} {:>11.2}",
            CHARGED_PARTICLE_T / n as f64,
            traj.mean_iterations()
        );
        previous = Some((n, error));
    }
    // The same system written as the physics, L_K(q, q̇), with `rule = left` (dirac::paper).
    let n = 200;
    let sys = ChargedParticleContinuous::paper(n);
    let initial: ReducedState<3, 1> =
        sys.reduced_state(SVector::zeros(), SVector::from([1.0, 0.0, 1.0, 1.0]))?;
    let traj = ReducedIntegrator::plus(sys, NewtonOptions::default())
        .run(initial)
        .steps(n)
        .collect()?;
    println!(
        "continuous form (L_K(q, q̇), rule = left, initial state from q̇): N = {n}, |q(T) - q_N| = {:.5e}",
        final_error(&traj)
    );
    Ok(())
}

/// Integrates the paper's run with `n` steps.
pub fn run(n: usize) -> Result<Trajectory<3, 1>, Box<dyn Error>> {
    let integ = ReducedIntegrator::plus(ChargedParticle::paper(n), NewtonOptions::default());
    Ok(integ
        .run(ChargedParticle::paper_initial_state())
        .steps(n)
        .collect()?)
}

fn final_error(traj: &Trajectory<3, 1>) -> f64 {
    let exact = ChargedParticle::exact_position(CHARGED_PARTICLE_T);
    let x = traj.last().x;
    (0..3)
        .map(|i| (x[i] - exact[i]).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// Runs `N = 100` (`h = 0.2`) and writes `figure1.csv` and `figure1.svg` (exact and discrete
/// trajectories) into `out`, which is created if needed.
pub fn write_figure_1(out: &Path) -> Result<(), Box<dyn Error>> {
    fs::create_dir_all(out)?;
    let traj = run(100)?;
    let mut csv = String::from("t,x,y,z,x_exact,y_exact,z_exact\n");
    let mut approx = Vec::new();
    for (k, s) in traj.states.iter().enumerate() {
        let t = traj.times[k];
        let e = ChargedParticle::exact_position(t);
        csv.push_str(&format!(
            "{t},{},{},{},{},{},{}\n",
            s.x[0], s.x[1], s.x[2], e[0], e[1], e[2]
        ));
        approx.push((s.x[0], s.x[2], s.x[1]));
    }
    fs::write(out.join("figure1.csv"), csv)?;

    let exact: Vec<(f64, f64, f64)> = (0..=2000)
        .map(|i| {
            let e = ChargedParticle::exact_position(CHARGED_PARTICLE_T * i as f64 / 2000.0);
            (e[0], e[2], e[1])
        })
        .collect();
    let path = out.join("figure1.svg");
    let root = SVGBackend::new(&path, (800, 700)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            "Charged particle: exact and discrete (h = 0.2)",
            ("sans-serif", 22),
        )
        .margin(20)
        .build_cartesian_3d(-1.5..1.5, 0.0..20.0, -2.5..0.5)?;
    chart.with_projection(|mut p| {
        p.pitch = 0.35;
        p.yaw = 0.6;
        p.scale = 0.85;
        p.into_matrix()
    });
    chart.configure_axes().draw()?;
    chart
        .draw_series(LineSeries::new(exact, BLUE.stroke_width(2)))?
        .label("exact q(t) = (sin t, cos t - 1, t)")
        .legend(|(x, y)| PathElement::new([(x, y), (x + 20, y)], BLUE));
    chart
        .draw_series(LineSeries::new(approx.clone(), RED))?
        .label("reduced (+) integrator, N = 100")
        .legend(|(x, y)| PathElement::new([(x, y), (x + 20, y)], RED));
    chart.draw_series(approx.into_iter().map(|p| Circle::new(p, 2, RED.filled())))?;
    chart
        .configure_series_labels()
        .border_style(BLACK)
        .background_style(WHITE)
        .draw()?;
    root.present()?;
    Ok(())
}
