//! Code shared by the examples: the command line (`cli`, and `output_dir` for the examples whose
//! only option is `--out DIR`), the runs and figures of the paper's §7 systems, and a line-chart
//! helper.
//!
//! Every example compiles this module tree on its own and uses only part of it (the §7.1 example
//! has no use for the double spherical pendulum), hence `allow(dead_code)`.
#![allow(dead_code)]

pub mod charged_particle;
pub mod cli;
pub mod double_spherical_pendulum;

use std::error::Error;
use std::ops::Range;
use std::path::{Path, PathBuf};

use plotters::prelude::*;

/// The output directory: the value of `--out DIR`, the only option of the examples that call
/// this, or `default`; `example` and `about` name the example and what it does in `--help`. A
/// bad argument stops the example with its message and exit code 2.
pub fn output_dir(example: &'static str, about: &'static str, default: &str) -> PathBuf {
    let mut cli = cli::Cli::new(example, about);
    let out = cli.out_dir(default);
    cli.finish();
    out
}

/// One curve of a [`LineChart`].
pub struct Curve {
    /// Legend entry; the legend is drawn only when a chart has more than one curve.
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub color: RGBColor,
}

/// One panel of a figure: curves on linear axes fitted to the data.
pub struct LineChart {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub curves: Vec<Curve>,
    /// One unit is as long on both axes (for a trajectory in a plane).
    pub equal_axes: bool,
}

/// Pixels of the margin around a panel, of the x-label area (below) and of the y-label area
/// (left), and the caption's font size.
const MARGIN: u32 = 15;
const X_LABEL_AREA: u32 = 45;
const Y_LABEL_AREA: u32 = 90;
const CAPTION: u32 = 20;

/// Writes `panels`, stacked top to bottom, `width` × `panel_height` pixels each, as one SVG.
pub fn write_line_charts(
    path: &Path,
    width: u32,
    panel_height: u32,
    panels: &[LineChart],
) -> Result<(), Box<dyn Error>> {
    let height = panel_height * panels.len() as u32;
    let root = SVGBackend::new(path, (width, height)).into_drawing_area();
    root.fill(&WHITE)?;
    for (area, panel) in root.split_evenly((panels.len(), 1)).iter().zip(panels) {
        let (x, y) = data_ranges(panel);
        let (x, y) = if panel.equal_axes {
            // The plotting area left after the margins, the label areas and the caption.
            let (w, h) = area.dim_in_pixel();
            let plot_w = f64::from(w.saturating_sub(2 * MARGIN + Y_LABEL_AREA).max(1));
            let plot_h = f64::from(
                h.saturating_sub(2 * MARGIN + X_LABEL_AREA + 2 * CAPTION)
                    .max(1),
            );
            equalize(x, y, plot_w / plot_h)
        } else {
            (x, y)
        };
        let (y_lo, y_hi) = (y.start, y.end);
        let mut chart = ChartBuilder::on(area)
            .caption(&panel.title, ("sans-serif", CAPTION))
            .margin(MARGIN)
            .x_label_area_size(X_LABEL_AREA)
            .y_label_area_size(Y_LABEL_AREA)
            .build_cartesian_2d(x, y)?;
        // Tick labels that show the data's scale: fixed notation for ordinary magnitudes,
        // scientific for tiny or huge ones (e.g. an energy difference of 1e-7).
        let span = y_lo.abs().max(y_hi.abs());
        let scientific = !(1e-2..1e5).contains(&span);
        // Enough significant digits to tell neighbouring ticks apart when the range is small
        // next to the magnitude (e.g. T + V ≈ −4.41e5 varying by a few thousand).
        let range = (y_hi - y_lo).abs().max(f64::MIN_POSITIVE);
        let digits = ((span / range).log10().ceil().max(0.0) as usize + 1).min(8);
        let format_y = move |v: &f64| {
            if scientific {
                format!("{v:.digits$e}")
            } else {
                format!("{v:.1}")
            }
        };
        chart
            .configure_mesh()
            .x_desc(panel.x_label.as_str())
            .y_desc(panel.y_label.as_str())
            .y_label_formatter(&format_y)
            .draw()?;
        for curve in &panel.curves {
            let color = curve.color;
            chart
                .draw_series(LineSeries::new(curve.points.iter().copied(), color))?
                .label(curve.label.as_str())
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], color));
        }
        if panel.curves.len() > 1 {
            chart
                .configure_series_labels()
                .border_style(BLACK)
                .background_style(WHITE)
                .draw()?;
        }
    }
    root.present()?;
    Ok(())
}

/// The ranges of all the points of a chart, padded by 5% (and widened if flat).
fn data_ranges(panel: &LineChart) -> (Range<f64>, Range<f64>) {
    let points = || panel.curves.iter().flat_map(|c| c.points.iter());
    let padded = |values: &mut dyn Iterator<Item = f64>| {
        let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
        let pad = if hi > lo {
            0.05 * (hi - lo)
        } else {
            0.5 * lo.abs().max(1.0)
        };
        lo - pad..hi + pad
    };
    (
        padded(&mut points().map(|p| p.0)),
        padded(&mut points().map(|p| p.1)),
    )
}

/// Widens one of the ranges about its centre so that `x` spans `aspect` times as many units
/// as `y`.
fn equalize(x: Range<f64>, y: Range<f64>, aspect: f64) -> (Range<f64>, Range<f64>) {
    let widen = |r: Range<f64>, len: f64| {
        let c = 0.5 * (r.start + r.end);
        c - 0.5 * len..c + 0.5 * len
    };
    let (dx, dy) = (x.end - x.start, y.end - y.start);
    if dx / dy < aspect {
        (widen(x, dy * aspect), y)
    } else {
        (x, widen(y, dx / aspect))
    }
}
