//! Ensemble tables are validated before any member runs: unknown, misspelled and duplicated
//! columns are errors that name them and list the accepted names; a member that cannot be built
//! is a failed-member row, not a panic, and the other members run; a description of another
//! state type is an error, not a panic.

use std::path::{Path, PathBuf};

use arrow_array::{Array, StringArray};
use dirac::paper::DoubleSphericalPendulum;
use dirac::prelude::*;
use dirac_io::read::read_batches;
use dirac_io::shard::{run_shard, Member, Row, Shard, Table};
use dirac_io::{Describe, Options, ParquetObserver, RunInfo};

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch directory");
    dir
}

type Dsp = ReducedIntegrator<DoubleSphericalPendulum, Plus, 3, 1, 4>;

/// The paper's pendulum, with the mass `m2` and the initial state from the row.
fn member(row: Row<'_>) -> Member<Dsp> {
    let sys = DoubleSphericalPendulum {
        m2: row.get_or("m2", DoubleSphericalPendulum::paper().m2),
        ..DoubleSphericalPendulum::paper()
    };
    let integ = ReducedIntegrator::plus(sys, NewtonOptions::default());
    let names = integ.describe().columns;
    let initial = row.state_or(&names, DoubleSphericalPendulum::paper_initial_state());
    Ok((integ, initial))
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
        t.push(&row).unwrap();
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
        ParquetObserver::<UnreducedState<2>>::create(dir.join("x.parquet"), info, Options::new());
    let err = created
        .err()
        .expect("a mismatched description is an error")
        .to_string();
    assert!(
        err.contains("8 state columns") && err.contains("have 4"),
        "{err}"
    );
}

#[test]
fn a_member_whose_closure_fails_is_a_failed_row_with_its_message() {
    let dir = scratch("failing_member");
    // Member 1 has no `m2` (NaN stands for a missing value in this table): its closure says so.
    let mut t = Table::new(["m2", "w_phi1"]);
    for (i, m2) in [35.0, f64::NAN, 36.0].into_iter().enumerate() {
        t.push(&[m2, 0.3 + 0.01 * i as f64]).unwrap();
    }
    let steps = 5;
    let report = dirac_io::shard::run_shard_with_states(
        &t,
        Shard::new(0, 1).unwrap(),
        &dir,
        steps,
        Some(2),
        |row: Row<'_>| -> Member<Dsp> {
            let m2 = row.require("m2")?;
            if m2.is_nan() {
                return Err(format!("member {} has no mass m2", row.index()).into());
            }
            // A column the table does not have: a typed error naming it.
            let missing = row.require("l1").unwrap_err();
            assert_eq!(missing.name, "l1");
            assert!(missing.to_string().contains("no column `l1`"));
            member(row)
        },
    )
    .unwrap();
    assert_eq!(report.failed, 1);
    assert_eq!(
        strings(&report.path, "status")[1].as_deref(),
        Some("failed")
    );
    assert_eq!(
        strings(&report.path, "error_kind")[1].as_deref(),
        Some("member")
    );
    assert_eq!(
        strings(&report.path, "error_message")[1].as_deref(),
        Some("member 1 has no mass m2")
    );
    for i in [0, 2] {
        assert_eq!(
            strings(&report.path, "status")[i].as_deref(),
            Some("completed")
        );
    }
    let steps_column = dirac_io::read::read_batches(&report.path).unwrap()[0]
        .column_by_name("steps")
        .unwrap()
        .as_any()
        .downcast_ref::<arrow_array::UInt64Array>()
        .unwrap()
        .values()
        .to_vec();
    assert_eq!(steps_column, [5, 0, 5]);
    // The states file has the two members that ran: 0, 2, 4 and the last state, 5, each.
    let states = dir.join(Shard::new(0, 1).unwrap().states_file_name());
    let rows: usize = read_batches(&states)
        .unwrap()
        .iter()
        .map(|b| b.num_rows())
        .sum();
    assert_eq!(rows, 2 * 4);
}

#[test]
fn a_table_no_member_of_which_can_be_built_is_an_error_naming_the_first() {
    let dir = scratch("no_member_built");
    let t = table(&["m2"], 3);
    let err = run_shard(&t, Shard::new(0, 1).unwrap(), &dir, 5, |row: Row<'_>| {
        row.require("l2")?;
        member(row)
    })
    .expect_err("no member can be built")
    .to_string();
    assert!(
        err.contains("member 0") && err.contains("no column `l2`"),
        "{err}"
    );
}

#[test]
fn declared_extra_columns_are_accepted() {
    let dir = scratch("declared_columns");
    let t = table(&["m2", "seed"], 2).accept(["seed"]);
    let report = run_shard(&t, Shard::new(0, 1).unwrap(), &dir, 5, |row: Row<'_>| {
        row.require("seed")?;
        member(row)
    })
    .unwrap();
    assert_eq!(report.failed, 0);
}

#[test]
fn rows_of_the_wrong_length_and_rows_out_of_range_are_errors_not_panics() {
    let mut t = Table::new(["m2", "h"]);
    let err = t
        .push(&[1.0])
        .expect_err("one value for two columns")
        .to_string();
    assert!(
        err.contains("a row of 1 values for a table of 2 columns"),
        "{err}"
    );
    t.push(&[1.0, 0.01]).unwrap();
    assert_eq!(t.len(), 1);
    assert!(t.row(0).is_some());
    assert!(t.row(1).is_none());
    // A shard built by hand beyond its count is refused, not divided by zero.
    let bad = Shard { index: 0, count: 0 };
    assert!(bad.members(10).is_empty());
    let dir = scratch("bad_shard");
    assert!(run_shard(&t, bad, &dir, 1, member).is_err());
    assert!(dirac_io::shard::merge(&dir, 0, &dir.join("m.parquet")).is_err());
}
