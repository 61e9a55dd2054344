//! Progress bars for long runs, ensembles and shards: drawn on standard error when it is a
//! terminal, hidden otherwise (a batch job's log, CI, a pipe), so that logs stay clean and a
//! hidden bar costs nothing but an atomic add.

use std::io::IsTerminal;

pub use indicatif::ProgressBar;
use indicatif::{ProgressDrawTarget, ProgressStyle};

/// Whether bars are drawn: standard error is a terminal.
pub fn enabled() -> bool {
    std::io::stderr().is_terminal()
}

/// A bar of `len` units of `unit` (`"steps"`, `"members"`), labelled `label`; hidden when
/// [`enabled`] is false.
pub fn bar(len: u64, label: &str, unit: &str) -> ProgressBar {
    if !enabled() {
        return ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::hidden());
    }
    // Braces in `unit` would be read as template keys: doubled, they stand for themselves.
    let unit = unit.replace('{', "{{").replace('}', "}}");
    let style = ProgressStyle::with_template(&format!(
        "{{prefix}} [{{elapsed_precise}}] {{wide_bar}} {{human_pos}}/{{human_len}} {unit} ({{per_sec}}, eta {{eta}})"
    ))
    .unwrap_or_else(|_| ProgressStyle::default_bar());
    ProgressBar::new(len)
        .with_style(style)
        .with_prefix(label.to_owned())
}

/// How many steps pass between two updates of a run's bar: few enough updates that the bar
/// costs nothing measurable against a step (an update is an atomic add; indicatif redraws at
/// most 20 times a second).
const STRIDE: usize = 64;

/// Wraps a run's observer so that a bar of `steps` steps follows it: pass the result to
/// [`Drive::run`](dirac::Drive::run). The bar is finished when the last step is observed.
///
/// ```
/// use dirac::paper::DoubleSphericalPendulum;
/// use dirac::prelude::*;
/// use dirac_io::progress;
///
/// let integ = ReducedIntegrator::plus(DoubleSphericalPendulum::paper(), NewtonOptions::default());
/// let mut count = 0;
/// let observe = progress::follow(100, "run", |_, _, _: &ReducedState<3, 1>, _: Option<&ReducedStep<1>>| count += 1);
/// integ.run(DoubleSphericalPendulum::paper_initial_state()).steps(100).observe(observe).stream().unwrap();
/// assert_eq!(count, 101);
/// ```
pub fn follow<St, R>(
    steps: usize,
    label: &str,
    mut observe: impl FnMut(usize, f64, &St, Option<&R>),
) -> impl FnMut(usize, f64, &St, Option<&R>) {
    let bar = bar(steps as u64, label, "steps");
    move |k, t, state, record| {
        observe(k, t, state, record);
        if k.is_multiple_of(STRIDE) || k == steps {
            bar.set_position(k as u64);
            if k == steps {
                bar.finish();
            }
        }
    }
}
