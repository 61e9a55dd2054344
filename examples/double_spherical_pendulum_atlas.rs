//! The paper's double spherical pendulum (§7.2) on an atlas of three charts (§6), from the
//! paper's own initial state, extended to `T = 10⁴` (10⁶ steps at `h = 0.01`): the run the
//! paper's chart alone cannot make (it stops at step 725,521, Remark 7.1). Prints a summary and
//! writes Figure 3/4-style plots with the chart in use beneath each, so every switch shows, and
//! the switches as CSV.
//!
//! ```text
//! cargo run --release --example double_spherical_pendulum_atlas [-- --out DIR]
//! ```

mod common;

use std::error::Error;
use std::io::Write;

use common::{write_line_charts, Curve, LineChart};
use dirac::paper::atlas::PAPER;
use dirac::paper::DoubleSphericalPendulum;
use dirac::prelude::*;
use plotters::style::{BLACK, BLUE, RED};

/// `T = 10⁴` at the paper's `h = 0.01`.
const STEPS: usize = 1_000_000;
/// One plotted point per this many steps (the run is kept in constant memory).
const EVERY: usize = 100;

fn main() -> Result<(), Box<dyn Error>> {
    let out = common::output_dir(
        "double_spherical_pendulum_atlas",
        "the double spherical pendulum on its atlas of charts, T = 10⁴ from the paper's state",
        "target/dirac-figures/double_spherical_pendulum_atlas",
    );
    std::fs::create_dir_all(&out)?;
    let sys = DoubleSphericalPendulum::paper();
    let charts = sys.charts();
    let atlas = sys.atlas(NewtonOptions::default());
    let initial = DoubleSphericalPendulum::paper_initial_state();
    let e0 = charts
        .energy(PAPER, &initial)
        .ok_or("singular initial state")?;

    let (mut z1, mut z2, mut xy2, mut energy, mut chart_in_use) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let (mut e_min, mut e_max) = (e0, e0);
    let mut j = 0usize;
    let start = std::time::Instant::now();
    let mut switches: Vec<Switch<3, 1>> = Vec::new();
    let run = atlas
        .run((PAPER, initial))
        .steps(STEPS)
        .observe(|_, _, &(chart, ref state), step| {
            let (rescue, switch) = step.map_or((None, None), |s| (s.rescue, s.switch));
            // The chart index steps at the switch itself, so every switch shows in the plot.
            let mut plot_switch = |sw: Switch<3, 1>, chart_in_use: &mut Vec<(f64, f64)>| {
                let t = sw.step as f64 * sys.h;
                chart_in_use.push((t, sw.from as f64));
                chart_in_use.push((t, sw.to as f64));
                switches.push(sw);
            };
            if let Some(sw) = rescue {
                plot_switch(sw, &mut chart_in_use);
            }
            // A state that changed chart after its step is shown in the chart it was computed in.
            let (chart, state) = match &switch {
                Some(sw) => (sw.from, &sw.before),
                None => (chart, state),
            };
            {
                let e = charts.energy(chart, state).unwrap_or(f64::NAN);
                (e_min, e_max) = (e_min.min(e), e_max.max(e));
                if j.is_multiple_of(EVERY) {
                    let t = j as f64 * sys.h;
                    let (r1, r2) = charts.bob_positions(chart, state);
                    z1.push((t, r1[2]));
                    z2.push((t, r2[2]));
                    xy2.push((r2[0], r2[1]));
                    energy.push((t, e));
                    chart_in_use.push((t, chart as f64));
                }
                j += 1;
            }
            if let Some(sw) = switch {
                plot_switch(sw, &mut chart_in_use);
            }
        })
        .stream();
    let elapsed = start.elapsed();
    let run = run.map_err(|e| format!("{e}"))?;
    println!(
        "Double spherical pendulum on the atlas from the paper's initial state, h = {}:",
        sys.h
    );
    println!(
        "  {} steps (t = {:.0}) in {elapsed:.2?}; {} switches, the first at step {}",
        run.step_count,
        run.step_count as f64 * sys.h,
        switches.len(),
        switches.first().map_or(0, |s| s.step)
    );
    for (i, name) in atlas.chart_names().iter().enumerate() {
        let into = switches.iter().filter(|s| s.to == i).count();
        println!("  chart {i}, {name}: entered {into} times");
    }
    println!(
        "  T + V: E_0 = {e0:.9e}, spread {:.4e} ({:.2e} relative); mu = {} throughout (exactly)",
        e_max - e_min,
        (e_max - e_min) / e0.abs(),
        run.last.1.mu[0]
    );

    let mut csv = std::fs::File::create(out.join("switches.csv"))?;
    writeln!(csv, "step,t,from,to,rescue")?;
    for sw in &switches {
        writeln!(
            csv,
            "{},{},{},{},{}",
            sw.step,
            sw.step as f64 * sys.h,
            sw.from,
            sw.to,
            sw.rescue
        )?;
    }
    let chart_panel = || LineChart {
        title: "Chart in use (0: paper, 1: link-1 frame, 2: link-2 frame)".into(),
        x_label: "t".into(),
        y_label: "chart".into(),
        curves: vec![Curve {
            label: "chart".into(),
            points: chart_in_use.clone(),
            color: BLACK,
        }],
        equal_axes: false,
    };
    write_line_charts(
        &out.join("figure3_atlas.svg"),
        1000,
        320,
        &[
            LineChart {
                title: "Heights of the bobs, T = 10^4 on the atlas".into(),
                x_label: "t".into(),
                y_label: "z".into(),
                curves: vec![
                    Curve {
                        label: "z1".into(),
                        points: z1,
                        color: BLUE,
                    },
                    Curve {
                        label: "z2".into(),
                        points: z2,
                        color: RED,
                    },
                ],
                equal_axes: false,
            },
            LineChart {
                title: "Second bob projected on the XY plane".into(),
                x_label: "x".into(),
                y_label: "y".into(),
                curves: vec![Curve {
                    label: "(x2, y2)".into(),
                    points: xy2,
                    color: RED,
                }],
                equal_axes: true,
            },
            chart_panel(),
        ],
    )?;
    write_line_charts(
        &out.join("figure4_atlas.svg"),
        1000,
        320,
        &[
            LineChart {
                title: "Physical energy T + V at the nodes (Hamiltonian, chart-independent)".into(),
                x_label: "t".into(),
                y_label: "T + V".into(),
                curves: vec![Curve {
                    label: "T + V".into(),
                    points: energy,
                    color: BLUE,
                }],
                equal_axes: false,
            },
            chart_panel(),
        ],
    )?;
    println!(
        "\nfigure3_atlas.svg, figure4_atlas.svg, switches.csv: {}",
        out.display()
    );
    Ok(())
}
