//! The format-neutral output: the one observer ([`dirac_io::Output`]) writes any kind of run —
//! element-wise states sized at run time among them — into any [`Sink`], Parquet being one.

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use dirac::prelude::*;
use dirac_io::read::{key_values, read_f64_column, row_count};
use dirac_io::{
    write_ensemble, Describe, EnsembleOutput, Error, Options, Output, ParquetObserver, Rows, Sink,
};

#[allow(dead_code)]
#[path = "../../examples/common/toda_n.rs"]
mod toda_n;
use toda_n::{initial, TodaN};

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("dirac-io-sinks-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn lattice(n: usize) -> (ElementIntegrator<TodaN>, ElementState) {
    let sys = TodaN {
        m: 1.0,
        d: 1.0,
        h: 0.05,
        n,
    };
    let start = initial(&sys, 0.1, 0.3, 0.05);
    (ElementIntegrator::new(sys, NewtonOptions::default()), start)
}

/// An element-wise run (width 2n, known only when the system is built) through the Parquet
/// observer: one column per coordinate index, every value read back bit for bit against the
/// collected trajectory, the sizes in the metadata.
#[test]
fn an_element_wise_run_is_written_bit_for_bit() {
    let (integ, start) = lattice(8);
    let reference = integ.run(start.clone()).steps(40).collect().unwrap();
    let path = temp("element");
    let info = integ.describe();
    assert_eq!(info.columns.len(), 16);
    assert_eq!(
        (info.columns[0].as_str(), info.columns[15].as_str()),
        ("q_0", "p_7")
    );
    let mut out = ParquetObserver::create(&path, info, Options::new().rows_per_file(16)).unwrap();
    let result = integ.run(start).steps(40).observe(out.observer()).stream();
    out.finish_with(&result).unwrap();
    result.unwrap();
    assert_eq!(row_count(&path).unwrap(), 41);
    for i in 0..8 {
        let q = read_f64_column(&path, &format!("q_{i}")).unwrap();
        let p = read_f64_column(&path, &format!("p_{i}")).unwrap();
        for (k, s) in reference.states.iter().enumerate() {
            assert_eq!(q[k].to_bits(), s.q[i].to_bits(), "q_{i} at step {k}");
            assert_eq!(p[k].to_bits(), s.p[i].to_bits(), "p_{i} at step {k}");
        }
    }
    let kv = key_values(&path).unwrap();
    assert_eq!(kv["dirac.sizes"], "n=8");
    assert_eq!(kv["dirac.coordinates"], "x");
    assert_eq!(kv["dirac.parameters"], "m,d,h");
    assert_eq!(kv["dirac.integrator"], "element-wise (+)");
    assert_eq!(kv["dirac.outcome"], "completed");
    std::fs::remove_dir_all(path).unwrap();
}

/// An ensemble of element-wise runs, written to one file by the same observer.
#[test]
fn an_element_wise_ensemble_is_written_to_one_file() {
    let (integ, start) = lattice(6);
    let mut second = start.clone();
    second.p[0] += 0.1;
    let dir = temp("element-ensemble");
    let path = dir.join("members.parquet");
    let results = write_ensemble(
        &integ,
        &integ.describe(),
        &[start, second.clone()],
        20,
        |_| Options::new(),
        &EnsembleOutput::OneFile(path.clone()),
    )
    .unwrap();
    assert!(results.iter().all(Result::is_ok));
    assert_eq!(row_count(&path).unwrap(), 42);
    let last = integ.run(second).steps(20).collect().unwrap();
    let p0 = read_f64_column(&path, "p_0").unwrap();
    assert_eq!(p0[41].to_bits(), last.states[20].p[0].to_bits());
    std::fs::remove_dir_all(dir).unwrap();
}

/// A state of another width than the description's (another system's element-wise state) is
/// an error `finish` returns, not a panic or a row of wrong columns; the rows before it stay.
#[test]
fn a_state_of_another_width_is_an_error() {
    let (integ, start) = lattice(8);
    let (_, short) = lattice(4);
    let path = temp("width");
    let mut out = ParquetObserver::create(&path, integ.describe(), Options::new()).unwrap();
    out.observe(0, 0.0, &start, None);
    out.observe(1, 0.05, &short, None);
    let err = out.finish().unwrap_err();
    assert!(
        matches!(&err, Error::Usage(m) if m.contains("8 components") || m.contains("16 state columns")),
        "{err}"
    );
    assert_eq!(row_count(&path).unwrap(), 1);
    std::fs::remove_dir_all(path).unwrap();
}

/// Metadata pairs, as a sink receives them.
type Pairs = Vec<(String, String)>;

/// What a sink of one's own receives: the blocks in order, each part's end marked, and the
/// outcome once.
#[derive(Clone, Default)]
struct Memory {
    blocks: Arc<Mutex<Vec<Rows>>>,
    outcome: Arc<Mutex<Option<Pairs>>>,
}

impl Sink for Memory {
    fn write(&mut self, rows: Rows) -> dirac_io::Result<()> {
        self.blocks.lock().unwrap().push(rows);
        Ok(())
    }

    fn close(&mut self, outcome: Pairs) -> dirac_io::Result<()> {
        *self.outcome.lock().unwrap() = Some(outcome);
        Ok(())
    }

    fn path(&self) -> &Path {
        Path::new("memory")
    }
}

/// The observer is the format's neighbour, not part of it: a sink that keeps blocks in memory
/// gets the same rows (the system's column names in its layout, every state's values, the
/// stride's last state) and the run's outcome, with parts cut where the options say.
#[test]
fn the_observer_writes_into_any_sink() {
    let integ = ReducedIntegrator::plus(
        dirac::paper::DoubleSphericalPendulum::paper(),
        NewtonOptions::default(),
    );
    let start = dirac::paper::DoubleSphericalPendulum::paper_initial_state();
    let options = || Options::new().every(3).rows_per_file(4);
    let layout = options().layout(&integ.describe()).unwrap();
    assert_eq!(layout.state, integ.describe().columns);
    assert_eq!(layout.rows_per_part, Some(4));
    let memory = Memory::default();
    let mut out = Output::new(memory.clone(), &layout, options());
    let result = integ.run(start).steps(20).observe(out.observer()).stream();
    out.finish_with(&result).unwrap();
    let summary = result.unwrap();
    let blocks = memory.blocks.lock().unwrap();
    let steps: Vec<u64> = blocks.iter().flat_map(|b| b.step.clone()).collect();
    assert_eq!(steps, [0, 3, 6, 9, 12, 15, 18, 20]);
    let ends: Vec<bool> = blocks.iter().map(|b| b.ends_part).collect();
    assert_eq!(ends, [true, true]);
    let last = blocks.last().unwrap();
    assert_eq!(
        last.state[0].last().unwrap().to_bits(),
        summary.last.x[0].to_bits()
    );
    let outcome = memory.outcome.lock().unwrap().clone().unwrap();
    assert!(outcome.contains(&("dirac.outcome".to_owned(), "completed".to_owned())));
    assert!(outcome.contains(&("dirac.steps".to_owned(), "20".to_owned())));
}
