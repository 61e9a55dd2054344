//! Random ensemble tables — headers with accepted, misspelled, unknown and duplicated names,
//! cells of random text, CSV and Parquet files cut at random lengths — fed to the table readers
//! and to `run_shard`: never a panic, always a table or a typed error; a table whose columns are
//! not all accepted exactly once never runs.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use dirac::paper::DoubleSphericalPendulum;
use dirac::prelude::*;
use dirac_io::shard::{run_shard, Member, Row, Shard, Table};
use dirac_io::Describe;
use proptest::prelude::*;

type Dsp = ReducedIntegrator<DoubleSphericalPendulum, Plus, 3, 1, 4>;

/// The names a table for the pendulum may have: its state columns, parameters and Newton
/// options.
const ACCEPTED: [&str; 18] = [
    "x_phi1",
    "x_vt2",
    "x_phi2",
    "w_phi1",
    "w_vt2",
    "w_phi2",
    "mu_vt1",
    "g_vt1",
    "h",
    "m1",
    "m2",
    "l1",
    "l2",
    "g",
    "abs_tol",
    "rel_tol",
    "max_iterations",
    "min_rcond",
];

/// A fresh directory per case.
fn case_dir() -> PathBuf {
    static CASE: AtomicUsize = AtomicUsize::new(0);
    let n = CASE.fetch_add(1, Ordering::Relaxed);
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("tables_never_panic")
        .join(n.to_string());
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch directory");
    dir
}

fn member(row: Row<'_>) -> Member<Dsp> {
    let p = DoubleSphericalPendulum::paper();
    let sys = DoubleSphericalPendulum {
        m2: row.get_or("m2", p.m2),
        ..p
    };
    let integ = ReducedIntegrator::plus(sys, NewtonOptions::default());
    let names = integ.describe().columns;
    let initial = row.state_or(&names, DoubleSphericalPendulum::paper_initial_state());
    Ok((integ, initial))
}

/// A header name: accepted, misspelled, unknown, empty or odd.
fn name() -> impl Strategy<Value = String> {
    prop_oneof![
        4 => proptest::sample::select(&ACCEPTED[..]).prop_map(str::to_owned),
        1 => proptest::sample::select(&ACCEPTED[..]).prop_map(|n| format!("{n}_")),
        1 => proptest::sample::select(&ACCEPTED[..]).prop_map(|n| n.replacen('_', "__", 1)),
        1 => "[a-z_]{0,6}",
        1 => "\\PC{0,4}",
    ]
}

/// A cell: a number (sometimes not finite), or random text.
fn cell() -> impl Strategy<Value = String> {
    prop_oneof![
        4 => (-2.0f64..2.0).prop_map(|v| format!("{v}")),
        1 => Just("NaN".to_owned()),
        1 => Just("inf".to_owned()),
        1 => "[0-9eE.+-]{0,5}",
        1 => "\\PC{0,3}",
    ]
}

/// CSV text of a random table: a header of 1–5 names, 0–4 rows of 0–6 cells, cut at a random
/// fraction of its length (on a character boundary).
fn csv() -> impl Strategy<Value = (Vec<String>, String)> {
    (
        proptest::collection::vec(name(), 1..=5),
        proptest::collection::vec(proptest::collection::vec(cell(), 0..=6), 0..=4),
        0.0f64..=1.5,
    )
        .prop_map(|(header, rows, cut)| {
            let mut text = header.join(",");
            text.push('\n');
            for row in rows {
                text.push_str(&row.join(","));
                text.push('\n');
            }
            // Cut fractions above 1 keep the whole text.
            let at = ((cut.min(1.0) * text.len() as f64) as usize).min(text.len());
            let at = (0..=at)
                .rev()
                .find(|&i| text.is_char_boundary(i))
                .unwrap_or(0);
            text.truncate(at);
            (header, text)
        })
}

/// Whether `names` are accepted names, each once.
fn valid(names: &[String]) -> bool {
    let unique: BTreeSet<&String> = names.iter().collect();
    unique.len() == names.len() && names.iter().all(|n| ACCEPTED.contains(&n.as_str()))
}

/// Runs a table that was read: refused unless its columns are valid, and then every member is
/// a row (completed or failed).
fn run(table: &Table, dir: &Path) {
    let result = run_shard(
        table,
        Shard::new(0, 1).unwrap(),
        &dir.join("shards"),
        2,
        member,
    );
    match result {
        Ok(report) => {
            assert!(
                valid(table.names()),
                "ran a table with columns {:?}",
                table.names()
            );
            assert_eq!(report.members, 0..table.len());
        }
        Err(e) => assert!(!e.to_string().is_empty()),
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    #[test]
    fn random_csv_tables_are_read_and_run_or_refused_never_a_panic((header, text) in csv()) {
        let dir = case_dir();
        let path = dir.join("table.csv");
        std::fs::write(&path, &text).unwrap();
        match Table::read(&path) {
            Ok(table) => {
                // A header with a name twice is refused by the reader.
                let trimmed: Vec<String> = table.names().to_vec();
                let unique: BTreeSet<&String> = trimmed.iter().collect();
                prop_assert_eq!(unique.len(), trimmed.len(), "{:?} from {:?}", trimmed, header);
                run(&table, &dir);
            }
            Err(e) => prop_assert!(!e.to_string().is_empty()),
        }
    }

    #[test]
    fn random_parquet_tables_cut_or_flipped_are_read_or_refused_never_a_panic(
        names in proptest::collection::vec(proptest::sample::select(&ACCEPTED[..]), 1..=4),
        rows in 0usize..4,
        cut in 0.0f64..=1.5,
        flip in proptest::option::of((0.0f64..1.0, 1u8..=255)),
    ) {
        let dir = case_dir();
        let mut table = Table::new(names.iter().copied());
        for i in 0..rows {
            let row: Vec<f64> = (0..names.len()).map(|c| 0.1 * (i * 7 + c) as f64).collect();
            table.push(&row).unwrap();
        }
        let path = dir.join("table.parquet");
        table.write(&path).unwrap();
        let mut bytes = std::fs::read(&path).unwrap();
        let at = ((cut.min(1.0) * bytes.len() as f64) as usize).min(bytes.len());
        bytes.truncate(at);
        if let Some((at, mask)) = flip {
            if !bytes.is_empty() {
                let i = ((at * bytes.len() as f64) as usize).min(bytes.len() - 1);
                bytes[i] ^= mask;
            }
        }
        std::fs::write(&path, &bytes).unwrap();
        match Table::read(&path) {
            Ok(read) => run(&read, &dir),
            Err(e) => prop_assert!(!e.to_string().is_empty()),
        }
    }
}
