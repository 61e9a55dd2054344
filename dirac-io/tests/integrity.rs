//! Corruption is detected: one flipped byte in the data of a shard file (its footer intact) is
//! noticed by the rerun (which runs the shard again instead of skipping it), by `merge` (which
//! refuses it, naming the file) and by the readers and the comparison.

use std::path::{Path, PathBuf};
use std::process::Command;

use arrow_array::{Array, Float64Array};
use dirac_io::read::{first_difference, read_batches};
use dirac_io::shard::merge;

const BIN: &str = env!("CARGO_BIN_EXE_dsp-ensemble");

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch directory");
    dir
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Runs `dsp-ensemble args`; returns (success, stdout, stderr).
fn dsp_ensemble(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(BIN)
        .args(args)
        .output()
        .expect("runs dsp-ensemble");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The offset of the footer of the Parquet file `bytes`: everything before it is data.
fn footer_start(bytes: &[u8]) -> usize {
    let n = bytes.len();
    let len = u32::from_le_bytes(bytes[n - 8..n - 4].try_into().unwrap()) as usize;
    n - 8 - len
}

/// Flips one bit of the value `v` where it is stored in the data of the file at `path`; returns
/// the offset of the byte flipped.
fn flip_value(path: &Path, v: f64) -> usize {
    let mut bytes = std::fs::read(path).unwrap();
    let end = footer_start(&bytes);
    let pattern = v.to_le_bytes();
    let at = bytes[..end]
        .windows(8)
        .position(|w| w == pattern)
        .expect("the value is stored in the data pages");
    // The third byte of the mantissa: the value changes in its 11th significant digit or so.
    bytes[at + 2] ^= 0x10;
    std::fs::write(path, &bytes).unwrap();
    at + 2
}

#[test]
fn a_flipped_data_byte_in_a_shard_is_detected_rerun_and_never_merged() {
    let dir = scratch("flipped_byte");
    let table = dir.join("table.csv");
    let shards = dir.join("shards");
    assert!(dsp_ensemble(&["table", "--members", "40", "--out", s(&table)]).0);
    let shard = |i: usize| {
        dsp_ensemble(&[
            "shard",
            "--table",
            s(&table),
            "--out",
            s(&shards),
            "--steps",
            "200",
            "--shard",
            &format!("{i}/2"),
        ])
    };
    for i in 0..2 {
        let (ok, _, err) = shard(i);
        assert!(ok, "{err}");
    }
    let victim = shards.join("shard-00001-of-00002.parquet");
    let pristine = dir.join("pristine.parquet");
    std::fs::copy(&victim, &pristine).unwrap();

    // Member 20's last x_phi1, stored as plain little-endian bits in the data pages.
    let batch = &read_batches(&victim).unwrap()[0];
    let column = batch.column_by_name("x_phi1").unwrap();
    let x = column
        .as_any()
        .downcast_ref::<Float64Array>()
        .unwrap()
        .value(0);
    flip_value(&victim, x);

    // The readers and the comparison refuse the file, naming it.
    let err = read_batches(&victim).expect_err("a corrupt file is not read as if it were sound");
    assert!(err.to_string().contains(s(&victim)), "{err}");
    assert!(err.to_string().contains("checksum"), "{err}");
    let err = first_difference(&victim, &pristine).expect_err("compare refuses a corrupt file");
    assert!(err.to_string().contains("checksum"), "{err}");

    // Merge refuses it, naming it, and writes nothing.
    let merged = dir.join("merged.parquet");
    let err = merge(&shards, 2, &merged).expect_err("a corrupt shard is never merged");
    assert!(err.to_string().contains(s(&victim)), "{err}");
    assert!(err.to_string().contains("checksum"), "{err}");
    assert!(!merged.exists());

    // The rerun does not take the shard for complete: it reports the corruption and runs the
    // shard again, which restores it bit for bit.
    let (ok, out, err) = shard(1);
    assert!(ok, "{err}");
    assert!(!out.contains("already complete, skipped"), "{out}");
    assert!(out.contains("corrupt"), "{out}");
    assert_eq!(first_difference(&victim, &pristine).unwrap(), None);
    assert_eq!(
        std::fs::read(&victim).unwrap(),
        std::fs::read(&pristine).unwrap()
    );
    let report = merge(&shards, 2, &merged).unwrap();
    assert_eq!(report.rows, 40);
    let column = read_batches(&merged).unwrap()[0]
        .column_by_name("x_phi1")
        .unwrap()
        .clone();
    assert_eq!(column.len(), 40);
}
