//! Ensemble tables are validated before any member runs: unknown, misspelled and duplicated
//! columns are errors that name them and list the accepted names; a member that cannot be built
//! is a failed-member row, not a panic, and the other members run; a description of another
//! state type is an error, not a panic.

use std::path::{Path, PathBuf};

use arrow_array::{Array, StringArray};
use dirac::paper::DoubleSphericalPendulum;
use dirac::prelude::*;
use dirac_io::read::read_batches;
use dirac_io::shard::{run_shard, Row, Shard, Table};
use dirac_io::{Describe, Options, ParquetObserver, RunInfo};

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch directory");
    dir
}

type Dsp = ReducedIntegrator<DoubleSphericalPendulum, Plus, 3, 1, 4>;

/// The paper's pendulum, with the mass `m2` and the initial state from the row.
fn member(row: Row<'_>) -> (Dsp, ReducedState<3, 1>) {
    let sys = DoubleSphericalPendulum {
        m2: row.get_or("m2", DoubleSphericalPendulum::paper().m2),
        ..DoubleSphericalPendulum::paper()
    };
    let integ = ReducedIntegrator::plus(sys, NewtonOptions::default());
    let names = integ.describe().columns;
    let initial = row.state_or(&names, DoubleSphericalPendulum::paper_initial_state());
    (integ, initial)
}

fn table(names: &[&str], rows: usize) -> Table {
    let mut t = Table::new(names.iter().copied());
    for i in 0..rows {
        // Masses near the paper's, other values away from the coordinates' singular points.
        let row: Vec<f64> = names
            .iter()
            .enumerate()
            .map(|(c, n)| match *n {
                "m2" => 35.0 + i as f64,
                _ => 0.3 + 0.01 * (i + c) as f64,
            })
            .collect();
        let _ = t.push(&row);
    }
    t
}

#[test]
fn a_misspelled_column_is_an_error_naming_it_and_the_accepted_names() {
    let dir = scratch("misspelled_column");
    let t = table(&["x_phi1", "w__phi1", "m2"], 3);
    let err = run_shard(&t, Shard::new(0, 1).unwrap(), &dir, 5, member)
        .expect_err("a misspelled column is an error")
        .to_string();
    assert!(err.contains("`w__phi1`"), "{err}");
    assert!(err.contains("did you mean `w_phi1`"), "{err}");
    for accepted in [
        "x_phi1",
        "w_vt2",
        "mu_vt1",
        "g_vt1",
        "m2",
        "h",
        "max_iterations",
    ] {
        assert!(err.contains(accepted), "{accepted} not listed: {err}");
    }
    // Nothing ran: no shard file.
    assert!(!dir.join(Shard::new(0, 1).unwrap().file_name()).exists());
}

#[test]
fn an_unknown_column_is_an_error() {
    let dir = scratch("unknown_column");
    let t = table(&["m2", "seed"], 2);
    let err = run_shard(&t, Shard::new(0, 1).unwrap(), &dir, 5, member)
        .expect_err("an unknown column is an error")
        .to_string();
    assert!(err.contains("`seed`"), "{err}");
    assert!(err.contains("x_phi1"), "{err}");
}

#[test]
fn a_duplicated_header_is_an_error() {
    let dir = scratch("duplicated_header");
    let csv = dir.join("table.csv");
    std::fs::write(&csv, "m2,w_phi1,m2\n30,0.1,40\n").unwrap();
    let err = Table::read(&csv)
        .expect_err("a duplicated header is an error")
        .to_string();
    assert!(
        err.contains("`m2`") && err.contains("more than once"),
        "{err}"
    );

    // A table built in memory with a duplicated name is refused before any member runs.
    let t = table(&["m2", "m2"], 2);
    let err = run_shard(&t, Shard::new(0, 1).unwrap(), &dir, 5, member)
        .expect_err("a duplicated column is an error")
        .to_string();
    assert!(
        err.contains("`m2`") && err.contains("more than once"),
        "{err}"
    );
}

fn strings(path: &Path, name: &str) -> Vec<Option<String>> {
    let batch = &read_batches(path).unwrap()[0];
    let c = batch.column_by_name(name).unwrap();
    let c = c.as_any().downcast_ref::<StringArray>().unwrap();
    (0..c.len())
        .map(|i| (!c.is_null(i)).then(|| c.value(i).to_owned()))
        .collect()
}

#[test]
fn a_member_that_panics_while_built_is_a_failed_row_and_the_others_run() {
    let dir = scratch("panicking_member");
    let t = table(&["m2"], 4);
    let report = run_shard(&t, Shard::new(0, 1).unwrap(), &dir, 5, |row: Row<'_>| {
        assert!(row.index() != 2, "member 2 cannot be built");
        member(row)
    })
    .expect("a member's failure is a row, not an error of the shard");
    assert_eq!(report.failed, 1);
    let status = strings(&report.path, "status");
    assert_eq!(
        status,
        ["completed", "completed", "failed", "completed"].map(|s| Some(s.to_owned()))
    );
    assert_eq!(
        strings(&report.path, "error_kind")[2].as_deref(),
        Some("member panicked")
    );
    let message = strings(&report.path, "error_message")[2].clone().unwrap();
    assert!(message.contains("member 2 cannot be built"), "{message}");
}

#[test]
fn an_observer_for_another_state_type_is_an_error_not_a_panic() {
    let dir = scratch("observer_mismatch");
    let info: RunInfo =
        ReducedIntegrator::plus(DoubleSphericalPendulum::paper(), NewtonOptions::default())
            .describe();
    // The description has the 8 columns of a `ReducedState<3, 1>`; a canonical state has 4.
    let created =
        ParquetObserver::<CanonicalState<2>>::create(dir.join("x.parquet"), info, Options::new());
    let err = created
        .err()
        .expect("a mismatched description is an error")
        .to_string();
    assert!(err.contains("8 columns") && err.contains('4'), "{err}");
}
