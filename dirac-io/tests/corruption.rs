//! Random damage fed to the readers and `merge`: a written file (a run's part, a shard) truncated
//! at a random length, or with a random bit of a random byte flipped. Never a panic; a truncated
//! file is an error; a flipped one is an error, or reads exactly as before — the same values,
//! columns and `dirac.*` metadata (a byte no reader takes, such as the writer's name in the
//! footer): never silently different values.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

use dirac::paper::DoubleSphericalPendulum;
use dirac::prelude::*;
use dirac_io::read::{first_difference, key_values, read_batches};
use dirac_io::shard::merge;
use dirac_io::{Describe, Options, ParquetObserver};
use proptest::prelude::*;

const BIN: &str = env!("CARGO_BIN_EXE_dsp-ensemble");

/// The files written once: a run in parts (`run/`), two shards (`shards/`) and their merge.
struct Written {
    root: PathBuf,
}

fn written() -> &'static Written {
    static WRITTEN: OnceLock<Written> = OnceLock::new();
    WRITTEN.get_or_init(|| {
        let root = Path::new(env!("CARGO_TARGET_TMPDIR")).join("corruption");
        let _ = std::fs::remove_dir_all(&root);
        std::fs::create_dir_all(&root).unwrap();
        let integ =
            ReducedIntegrator::plus(DoubleSphericalPendulum::paper(), NewtonOptions::default());
        let options = Options::new()
            .row_group_bytes(50 * 13 * 8)
            .rows_per_file(150);
        let mut out = ParquetObserver::create(root.join("run"), integ.describe(), options).unwrap();
        let result = integ
            .run(DoubleSphericalPendulum::paper_initial_state())
            .steps(400)
            .observe(out.observer())
            .stream();
        out.finish_with(&result).unwrap();
        let table = root.join("table.csv");
        let shards = root.join("shards");
        let run = |args: &[&str]| {
            let out = Command::new(BIN).args(args).output().unwrap();
            assert!(
                out.status.success(),
                "{}",
                String::from_utf8_lossy(&out.stderr)
            );
        };
        run(&["table", "--members", "12", "--out", table.to_str().unwrap()]);
        for i in 0..2 {
            run(&[
                "shard",
                "--table",
                table.to_str().unwrap(),
                "--out",
                shards.to_str().unwrap(),
                "--steps",
                "50",
                "--every",
                "10",
                "--shard",
                &format!("{i}/2"),
            ]);
        }
        merge(&shards, 2, &root.join("merged.parquet")).unwrap();
        Written { root }
    })
}

/// The files damaged: the run's parts, a shard and a shard's states.
const VICTIMS: [&str; 4] = [
    "run/part-00000.parquet",
    "run/part-00002.parquet",
    "shards/shard-00001-of-00002.parquet",
    "shards/shard-00000-of-00002.states.parquet",
];

#[derive(Clone, Debug)]
enum Damage {
    /// Keep this fraction (in millionths) of the file.
    Truncate(u32),
    /// Flip bit `bit` of the byte at this fraction (in millionths) of the file.
    Flip(u32, u8),
}

/// A copy of the written files with `victim` damaged; returns the copy's root.
fn damaged(case: u64, victim: &str, damage: &Damage) -> PathBuf {
    let w = written();
    let root = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("corruption-case-{case}"));
    let _ = std::fs::remove_dir_all(&root);
    for dir in ["run", "shards"] {
        std::fs::create_dir_all(root.join(dir)).unwrap();
        for entry in std::fs::read_dir(w.root.join(dir)).unwrap() {
            let entry = entry.unwrap();
            if entry.file_type().unwrap().is_file() {
                std::fs::copy(entry.path(), root.join(dir).join(entry.file_name())).unwrap();
            }
        }
    }
    let path = root.join(victim);
    let mut bytes = std::fs::read(&path).unwrap();
    let at = |f: u32| (bytes.len() as u64 * u64::from(f) / 1_000_000) as usize;
    match *damage {
        Damage::Truncate(f) => {
            let n = at(f).min(bytes.len() - 1);
            bytes.truncate(n);
        }
        Damage::Flip(f, bit) => {
            let i = at(f).min(bytes.len() - 1);
            bytes[i] ^= 1 << bit;
        }
    }
    std::fs::write(&path, &bytes).unwrap();
    root
}

fn damage() -> impl Strategy<Value = Damage> {
    prop_oneof![
        (0u32..1_000_000).prop_map(Damage::Truncate),
        (0u32..1_000_000, 0u8..8).prop_map(|(f, b)| Damage::Flip(f, b)),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 160, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn damaged_files_are_refused_or_read_unchanged(
        victim in 0usize..VICTIMS.len(),
        damage in damage(),
        case in any::<u64>(),
    ) {
        let w = written();
        let name = VICTIMS[victim];
        let root = damaged(case, name, &damage);
        let path = root.join(name);
        let original = w.root.join(name);
        let truncated = matches!(damage, Damage::Truncate(_));

        // The reader: an error, or (a flip no reader sees) the same values and metadata.
        let read = std::panic::catch_unwind(|| read_batches(&path));
        prop_assert!(read.is_ok(), "read_batches panicked on {name} {damage:?}");
        match read.unwrap() {
            Err(e) => prop_assert!(e.to_string().contains(path.to_str().unwrap()), "{e}"),
            Ok(_) => {
                prop_assert!(!truncated, "a truncated {name} was read: {damage:?}");
                prop_assert_eq!(first_difference(&path, &original).unwrap(), None);
                // The run's metadata (the checksums cover the `dirac.*` pairs and the columns;
                // other pairs, such as the Arrow schema's copy, may change unseen).
                let dirac = |p: &Path| {
                    key_values(p)
                        .unwrap()
                        .into_iter()
                        .filter(|(k, _)| k.starts_with("dirac."))
                        .collect::<Vec<_>>()
                };
                prop_assert_eq!(dirac(&path), dirac(&original));
            }
        }

        // The directory of parts as one table.
        if name.starts_with("run/") {
            let run = std::panic::catch_unwind(|| read_batches(&root.join("run")));
            prop_assert!(run.is_ok(), "reading the parts panicked: {damage:?}");
            if run.unwrap().is_ok() {
                prop_assert!(!truncated);
                prop_assert_eq!(
                    first_difference(&root.join("run"), &w.root.join("run")).unwrap(),
                    None
                );
            }
        }

        // Merge: an error naming the shard, or the same merged table.
        if name.starts_with("shards/") {
            let out = root.join("merged.parquet");
            let merged = std::panic::catch_unwind(|| merge(&root.join("shards"), 2, &out));
            prop_assert!(merged.is_ok(), "merge panicked on {name} {damage:?}");
            match merged.unwrap() {
                Err(e) => {
                    prop_assert!(!out.exists(), "a refused merge wrote {}", out.display());
                    prop_assert!(e.to_string().contains(path.to_str().unwrap()), "{e}");
                }
                Ok(_) => {
                    prop_assert!(!truncated, "a truncated shard was merged: {damage:?}");
                    let reference = w.root.join("merged.parquet");
                    prop_assert_eq!(first_difference(&out, &reference).unwrap(), None);
                    let states = root.join("merged.states.parquet");
                    let reference = w.root.join("merged.states.parquet");
                    prop_assert_eq!(first_difference(&states, &reference).unwrap(), None);
                }
            }
        }
        let _ = std::fs::remove_dir_all(&root);
    }
}
