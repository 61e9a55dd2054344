//! Sharded ensembles: deterministic assignment, shards merged equal to one process bit for bit,
//! restart after a killed shard, skipping complete shards, failed members recorded as rows.
//! The shards run as child processes of the `dsp-ensemble` program, as under Slurm.

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Duration;

use arrow_array::Array;
use dirac_io::read::{first_difference, key_values, read_batches, row_count};
use dirac_io::shard::{merge, Shard};

const BIN: &str = env!("CARGO_BIN_EXE_dsp-ensemble");

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch directory");
    dir
}

/// Runs `dsp-ensemble args`, which must succeed; returns its standard output.
fn dsp_ensemble(args: &[&str]) -> String {
    let out = Command::new(BIN)
        .args(args)
        .output()
        .expect("runs dsp-ensemble");
    assert!(
        out.status.success(),
        "dsp-ensemble {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn shard_assignment_is_a_deterministic_partition_in_order() {
    for total in [0, 1, 7, 10_000] {
        for count in [1, 3, 4, 16] {
            let ranges: Vec<_> = (0..count)
                .map(|i| Shard::new(i, count).unwrap().members(total))
                .collect();
            assert_eq!(ranges[0].start, 0);
            assert_eq!(ranges[count - 1].end, total);
            for w in ranges.windows(2) {
                assert_eq!(w[0].end, w[1].start);
            }
            // Balanced: sizes differ by at most one.
            let sizes: Vec<usize> = ranges.iter().map(|r| r.len()).collect();
            assert!(sizes.iter().max().unwrap() - sizes.iter().min().unwrap() <= 1);
        }
    }
    assert!(Shard::new(4, 4).is_err());
    assert_eq!(Shard::parse("2/4").unwrap(), Shard::new(2, 4).unwrap());
    assert!(Shard::parse("2-4").is_err());
}

/// Four shards, each run twice (the second run skips), then merged: the one-process run bit for
/// bit, whatever the number of threads a shard ran on.
#[test]
fn merged_shards_are_the_one_process_run_and_complete_shards_are_skipped() {
    let dir = scratch("merged_equals_one_process");
    let table = dir.join("table.parquet");
    dsp_ensemble(&["table", "--members", "103", "--out", s(&table), "--failing"]);
    let shards = dir.join("shards");
    for i in 0..4 {
        let threads = if i % 2 == 0 { "1" } else { "2" };
        let out = Command::new(BIN)
            .args([
                "shard",
                "--table",
                s(&table),
                "--out",
                s(&shards),
                "--steps",
                "300",
            ])
            .args(["--shard", &format!("{i}/4")])
            .env("RAYON_NUM_THREADS", threads)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let again = dsp_ensemble(&[
            "shard",
            "--table",
            s(&table),
            "--out",
            s(&shards),
            "--steps",
            "300",
            "--shard",
            &format!("{i}/4"),
        ]);
        assert!(again.contains("already complete, skipped"), "{again}");
    }
    // A shard of another run in the way is an error, not silently kept.
    let err = Command::new(BIN)
        .args([
            "shard",
            "--table",
            s(&table),
            "--out",
            s(&shards),
            "--steps",
            "301",
            "--shard",
            "0/4",
        ])
        .output()
        .unwrap();
    assert!(!err.status.success());
    assert!(
        String::from_utf8_lossy(&err.stderr).contains("dirac.steps = 300 where 301 was expected")
    );

    let merged = dir.join("merged.parquet");
    let report = merge(&shards, 4, &merged).unwrap();
    assert_eq!(report.rows, 103);
    let one = dir.join("one");
    dsp_ensemble(&[
        "shard",
        "--table",
        s(&table),
        "--out",
        s(&one),
        "--steps",
        "300",
        "--shard",
        "0/1",
    ]);
    let single = one.join("shard-00000-of-00001.parquet");
    assert_eq!(first_difference(&merged, &single).unwrap(), None);
    let kv = key_values(&merged).unwrap();
    assert_eq!(kv["dirac.shard.count"], "4");
    assert!(!kv.contains_key("dirac.shard.index"));

    // Failed members are rows with their typed error; the others completed.
    let batch = &read_batches(&merged).unwrap()[0];
    let strings = |name: &str| {
        let c = batch.column_by_name(name).unwrap();
        let c = c
            .as_any()
            .downcast_ref::<arrow_array::StringArray>()
            .unwrap();
        (0..c.len())
            .map(|i| (!c.is_null(i)).then(|| c.value(i).to_owned()))
            .collect::<Vec<_>>()
    };
    let status = strings("status");
    assert_eq!(status[0].as_deref(), Some("completed"));
    assert_eq!(status[1].as_deref(), Some("failed"));
    assert_eq!(status[2].as_deref(), Some("failed"));
    assert_eq!(
        status
            .iter()
            .filter(|s| s.as_deref() == Some("failed"))
            .count(),
        2
    );
    let kinds = strings("error_kind");
    assert_eq!(kinds[1].as_deref(), Some("Newton did not converge"));
    assert_eq!(kinds[2].as_deref(), Some("non-finite value"));
    let messages = strings("error_message");
    assert!(messages[1]
        .as_ref()
        .unwrap()
        .starts_with("step 0: Newton iteration did not converge in 1 iterations"));
    assert_eq!(messages[0], None);
}

/// A shard killed mid-run leaves no shard file (at most a hidden partial one); merging then names
/// it as missing; rerun, it completes, and the merged table is the one-process run bit for bit.
#[test]
fn a_killed_shard_is_simply_rerun() {
    let dir = scratch("killed_shard");
    let table = dir.join("table.csv");
    dsp_ensemble(&["table", "--members", "4000", "--out", s(&table)]);
    let shards = dir.join("shards");
    let args = |i: usize| {
        vec![
            "shard".to_owned(),
            "--table".into(),
            s(&table).into(),
            "--out".into(),
            s(&shards).into(),
            "--steps".into(),
            "800".into(),
            "--shard".into(),
            format!("{i}/2"),
        ]
    };
    dsp_ensemble(&args(0).iter().map(String::as_str).collect::<Vec<_>>());

    let mut child = Command::new(BIN)
        .args(args(1))
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut line = String::new();
    BufReader::new(child.stderr.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    assert!(line.starts_with("shard 1/2"), "{line}");
    std::thread::sleep(Duration::from_millis(200));
    assert_eq!(
        child.try_wait().unwrap(),
        None,
        "the shard ended before it could be killed: make it longer"
    );
    child.kill().unwrap();
    child.wait().unwrap();
    let killed = shards.join("shard-00001-of-00002.parquet");
    assert!(!killed.exists(), "a killed shard leaves no shard file");
    let err = merge(&shards, 2, &dir.join("merged.parquet")).unwrap_err();
    assert!(
        err.to_string().contains("shards 1 of 2 are missing"),
        "{err}"
    );

    let rerun = dsp_ensemble(&args(1).iter().map(String::as_str).collect::<Vec<_>>());
    assert!(rerun.contains("2000 members, 0 failed"), "{rerun}");
    assert_eq!(row_count(&killed).unwrap(), 2000);
    let merged = dir.join("merged.parquet");
    merge(&shards, 2, &merged).unwrap();
    dsp_ensemble(&[
        "shard",
        "--table",
        s(&table),
        "--out",
        s(&dir.join("one")),
        "--steps",
        "800",
        "--shard",
        "0/1",
    ]);
    let single = dir.join("one/shard-00000-of-00001.parquet");
    assert_eq!(first_difference(&merged, &single).unwrap(), None);
    let leftovers: Vec<_> = std::fs::read_dir(&shards)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(
        leftovers.len(),
        2,
        "partial files are removed: {leftovers:?}"
    );
}

/// Under Slurm the index comes from `SLURM_ARRAY_TASK_ID`; a resubmitted single task
/// (`SLURM_ARRAY_TASK_COUNT=1`) needs the count given, and without it is refused.
#[test]
fn the_shard_comes_from_slurm_array_variables() {
    let dir = scratch("slurm_variables");
    let table = dir.join("table.csv");
    dsp_ensemble(&["table", "--members", "10", "--out", s(&table)]);
    let run = |id: &str, count: &str, extra: &[&str]| {
        Command::new(BIN)
            .args([
                "shard",
                "--table",
                s(&table),
                "--out",
                s(&dir),
                "--steps",
                "10",
            ])
            .args(extra)
            .env("SLURM_ARRAY_TASK_ID", id)
            .env("SLURM_ARRAY_TASK_COUNT", count)
            .output()
            .unwrap()
    };
    assert!(run("1", "2", &[]).status.success());
    assert!(dir.join("shard-00001-of-00002.parquet").exists());
    let refused = run("2", "1", &[]);
    assert!(!refused.status.success());
    assert!(String::from_utf8_lossy(&refused.stderr).contains("give the number of shards"));
    assert!(run("2", "1", &["--shards", "4"]).status.success());
    assert!(dir.join("shard-00002-of-00004.parquet").exists());
}

/// Progress bars are drawn only on a terminal: with standard error a pipe (a batch job's log),
/// a shard writes its one start line there and nothing else.
#[test]
fn no_progress_bar_when_stderr_is_not_a_terminal() {
    let dir = scratch("quiet");
    let table = dir.join("table.csv");
    dsp_ensemble(&["table", "--members", "50", "--out", s(&table)]);
    let out = Command::new(BIN)
        .args([
            "shard",
            "--table",
            s(&table),
            "--out",
            s(&dir),
            "--steps",
            "200",
            "--shard",
            "0/1",
        ])
        .output()
        .unwrap();
    assert!(out.status.success());
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert_eq!(stderr.lines().count(), 1, "{stderr:?}");
    assert!(
        stderr.starts_with("shard 0/1: members 0..50 of 50"),
        "{stderr:?}"
    );
}

/// Shards that also write their members' trajectories (every k-th state, `member` column):
/// merged, the trajectories are those of the one-process run bit for bit, members in order,
/// a failed member's up to its failure.
#[test]
fn shard_trajectories_merge_into_the_one_process_trajectories() {
    let dir = scratch("states");
    let table = dir.join("table.csv");
    dsp_ensemble(&["table", "--members", "23", "--out", s(&table), "--failing"]);
    let shards = dir.join("shards");
    let run = |out: &Path, shard: &str| {
        dsp_ensemble(&[
            "shard",
            "--table",
            s(&table),
            "--out",
            s(out),
            "--steps",
            "200",
            "--every",
            "50",
            "--shard",
            shard,
        ])
    };
    for i in 0..3 {
        run(&shards, &format!("{i}/3"));
        assert!(shards
            .join(format!("shard-0000{i}-of-00003.states.parquet"))
            .exists());
    }
    // The same shard without states is another run: refused, not skipped.
    let other = Command::new(BIN)
        .args([
            "shard",
            "--table",
            s(&table),
            "--out",
            s(&shards),
            "--steps",
            "200",
            "--shard",
            "0/3",
        ])
        .output()
        .unwrap();
    assert!(!other.status.success());
    let merged = dir.join("merged.parquet");
    merge(&shards, 3, &merged).unwrap();
    let one = dir.join("one");
    run(&one, "0/1");
    let states = dirac_io::shard::states_path(&merged);
    assert_eq!(states, dir.join("merged.states.parquet"));
    let single = one.join("shard-00000-of-00001.states.parquet");
    assert_eq!(first_difference(&states, &single).unwrap(), None);
    let rows = row_count(&states).unwrap();
    // 5 states (0, 50, …, 200) per completed member; member 1 fails at step 0 (1 state), member
    // 2 has a NaN initial state (1 state).
    assert_eq!(rows, 21 * 5 + 2);
    let leftovers: Vec<_> = std::fs::read_dir(&shards)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(leftovers.len(), 6, "no parts left behind: {leftovers:?}");
}
