//! The double spherical pendulum ensemble's members: shared by the `dsp-ensemble` program and
//! the `ensemble_scaling` example (included with `#[path]`).

use dirac::paper::DoubleSphericalPendulum;
use dirac::prelude::*;
use dirac_io::shard::{MemberError, Row, Table};
use dirac_io::{Describe, Error};

/// Member `row`: the paper's system and initial state, with what the row gives in their place;
/// an error (the member's failed row) for an iteration cap that is not a positive whole number.
pub fn member(
    row: Row<'_>,
) -> Result<
    (
        impl Describe<State = ReducedState<3, 1>>,
        ReducedState<3, 1>,
    ),
    MemberError,
> {
    let p = DoubleSphericalPendulum::paper();
    let sys = DoubleSphericalPendulum {
        h: row.get_or("h", p.h),
        m1: row.get_or("m1", p.m1),
        m2: row.get_or("m2", p.m2),
        l1: row.get_or("l1", p.l1),
        l2: row.get_or("l2", p.l2),
        g: row.get_or("g", p.g),
    };
    let defaults = NewtonOptions::default();
    let cap = row.get_or("max_iterations", defaults.max_iterations as f64);
    if !(cap >= 1.0 && cap.fract() == 0.0 && cap <= u32::MAX as f64) {
        return Err(format!("max_iterations = {cap} is not a positive whole number").into());
    }
    let options = NewtonOptions {
        max_iterations: cap as usize,
        ..defaults
    };
    let integ = ReducedIntegrator::plus(sys, options);
    let columns = integ.describe().columns;
    let initial = row.state_or(&columns, DoubleSphericalPendulum::paper_initial_state());
    Ok((integ, initial))
}

/// The table of `members` perturbed members (see the module documentation).
pub fn table(members: usize, failing: bool) -> Result<Table, Error> {
    let start = DoubleSphericalPendulum::paper_initial_state();
    let m2 = DoubleSphericalPendulum::paper().m2;
    let mut t = Table::new([
        "x_phi1",
        "w_phi1",
        "w_vt2",
        "mu_vt1",
        "m2",
        "max_iterations",
    ]);
    let cap = NewtonOptions::default().max_iterations as f64;
    for i in 0..members {
        // A low-discrepancy walk (golden-ratio steps) over a small box around the paper's state.
        let u = |k: f64| ((i as f64 + 1.0) * k).fract() - 0.5;
        let mut row = [
            start.x[0] + 0.2 * u(0.618_033_988_749_895),
            start.w[0] + 0.5 * u(0.754_877_666_246_693),
            start.w[1] + 0.5 * u(0.569_840_290_998_053),
            start.mu[0] + 0.5 * u(0.438_302_769_446_591),
            m2 * (1.0 + 0.2 * u(0.347_296_355_333_861)),
            cap,
        ];
        if failing && i == 1 {
            row[5] = 1.0;
        }
        if failing && i == 2 {
            row[0] = f64::NAN;
        }
        t.push(&row)?;
    }
    Ok(t)
}
