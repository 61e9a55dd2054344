//! Reading back what this crate wrote: key-value metadata, concatenation of files in order
//! (an ensemble's members, a sharded ensemble's shards), and a bit-for-bit comparison.

use std::collections::BTreeMap;
use std::fs::File;
use std::path::{Path, PathBuf};

use arrow_array::{Array, Float64Array, RecordBatch, UInt64Array};
use arrow_schema::DataType;
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use parquet::basic::Compression;

use super::integrity::{verify, FileWriter};
use crate::columns::StateColumns;
use crate::error::{Error, Result};
use crate::files::published_parts;

/// `read()` with a panic of the Parquet reader caught: a corrupt file (a flipped byte in the
/// footer's offsets) can trip an assertion inside the `parquet` crate, which is then an
/// [`Error::Content`] naming the file like any other unreadable file.
fn guarded<T>(path: &Path, read: impl FnOnce() -> Result<T>) -> Result<T> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(read)).unwrap_or_else(|payload| {
        let message = payload
            .downcast_ref::<&str>()
            .map(|s| (*s).to_owned())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_default();
        Err(Error::content(
            path,
            format!("corrupt Parquet file: the reader failed ({message})"),
        ))
    })
}

/// The key-value metadata of the Parquet file at `path` (without the embedded Arrow schema);
/// for a directory of parts, its last part's (the run's description and outcome). Read from the
/// footer alone: the data are not checked (the readers below check them).
pub fn key_values(path: &Path) -> Result<BTreeMap<String, String>> {
    guarded(path, || key_values_unguarded(path))
}

/// The number of rows of the Parquet file (or directory of parts) at `path`, from the footers.
pub fn row_count(path: &Path) -> Result<u64> {
    guarded(path, || row_count_unguarded(path))
}

/// Every row of the Parquet file (or directory of parts) at `path`, as record batches, after
/// checking the checksums of each file ([`super::integrity::verify`]; a file without them, not
/// written by this crate, is read unchecked).
pub fn read_batches(path: &Path) -> Result<Vec<RecordBatch>> {
    guarded(path, || read_batches_unguarded(path))
}

/// One `f64` column of the Parquet file (or directory of parts) at `path`, all rows (nulls as
/// `NaN`), checked as by [`read_batches`].
pub fn read_f64_column(path: &Path, name: &str) -> Result<Vec<f64>> {
    guarded(path, || read_f64_column_unguarded(path, name))
}

/// Writes the rows of `inputs` (files or directories of parts), in order, into one file at
/// `out` (same schema required), with key-value metadata `kv` and checksums, and syncs it;
/// reads one batch at a time, so memory does not grow with the inputs, and checks each input's
/// checksums first. Returns the number of rows.
pub fn concatenate(inputs: &[PathBuf], out: &Path, kv: Vec<(String, String)>) -> Result<u64> {
    guarded(out, || concatenate_unguarded(inputs, out, kv))
}

/// Compares the rows of two Parquet files bit for bit (floats by their bit patterns, so `NaN`
/// equals the same `NaN` and `0.0` differs from `-0.0`): `None` when they hold the same columns
/// and values, else a description of the first difference. Metadata is not compared. Either may
/// be a directory of parts; a file whose checksums disagree with it is an error.
pub fn first_difference(a: &Path, b: &Path) -> Result<Option<String>> {
    guarded(a, || first_difference_unguarded(a, b))
}

/// The Arrow schema of the Parquet file at `path` (for a directory of parts, its first part's).
pub fn schema(path: &Path) -> Result<arrow_schema::SchemaRef> {
    guarded(path, || schema_unguarded(path))
}

/// The number of row groups of the Parquet file at `path`, and the most rows one of them holds:
/// what a reader or the writer held in memory at once.
pub fn row_groups(path: &Path) -> Result<(usize, u64)> {
    guarded(path, || row_groups_unguarded(path))
}

/// The last state written to the trajectory file (or directory of parts) at `path`, and its
/// step, checked as by [`read_batches`]: where a killed run is continued from
/// ([`ParquetObserver::resume`](crate::ParquetObserver::resume)). `columns` are the state's
/// column names ([`RunInfo::columns`](crate::RunInfo)).
pub fn last_state<St: StateColumns>(path: &Path, columns: &[String]) -> Result<(usize, f64, St)> {
    guarded(path, || last_state_unguarded::<St>(path, columns))
}

fn builder(path: &Path) -> Result<ParquetRecordBatchReaderBuilder<File>> {
    let file = File::open(path).map_err(Error::io(path))?;
    ParquetRecordBatchReaderBuilder::try_new(file).map_err(Error::parquet(path))
}

/// The files of `path`: itself, or for a directory of parts (a [`ParquetObserver`] run's), its
/// published parts in order (hidden partial parts are not read).
///
/// [`ParquetObserver`]: crate::ParquetObserver
pub fn files(path: &Path) -> Result<Vec<PathBuf>> {
    if !path.is_dir() {
        return Ok(vec![path.to_owned()]);
    }
    let (parts, _) = published_parts(path)?;
    if parts.is_empty() {
        return Err(Error::content(
            path,
            "no published part (`part-NNNNN.parquet`) in this directory",
        ));
    }
    Ok(parts)
}

/// The key-value metadata of the Parquet file at `path` (without the embedded Arrow schema),
/// read from its footer without checking the checksums.
pub(crate) fn key_values_unchecked(path: &Path) -> Result<BTreeMap<String, String>> {
    let builder = builder(path)?;
    let kv = builder.metadata().file_metadata().key_value_metadata();
    Ok(kv
        .into_iter()
        .flatten()
        .filter(|kv| kv.key != "ARROW:schema")
        .filter_map(|kv| Some((kv.key.clone(), kv.value.clone()?)))
        .collect())
}

/// [`key_values`] without the guard.
fn key_values_unguarded(path: &Path) -> Result<BTreeMap<String, String>> {
    let files = files(path)?;
    key_values_unchecked(files.last().unwrap_or(&path.to_owned()))
}

/// [`row_count`] without the guard.
fn row_count_unguarded(path: &Path) -> Result<u64> {
    let mut rows = 0;
    for file in files(path)? {
        rows += builder(&file)?.metadata().file_metadata().num_rows() as u64;
    }
    Ok(rows)
}

/// [`read_batches`] without the guard.
fn read_batches_unguarded(path: &Path) -> Result<Vec<RecordBatch>> {
    let mut out = Vec::new();
    for file in files(path)? {
        verify(&file)?;
        for batch in builder(&file)?.build().map_err(Error::parquet(&file))? {
            out.push(batch.map_err(Error::arrow(&file))?);
        }
    }
    Ok(out)
}

/// [`read_f64_column`] without the guard.
fn read_f64_column_unguarded(path: &Path, name: &str) -> Result<Vec<f64>> {
    let mut out = Vec::new();
    for batch in read_batches(path)? {
        let values = f64_column(&batch, path, name)?;
        out.extend((0..values.len()).map(|i| {
            if values.is_null(i) {
                f64::NAN
            } else {
                values.value(i)
            }
        }));
    }
    Ok(out)
}

fn f64_column<'a>(batch: &'a RecordBatch, path: &Path, name: &str) -> Result<&'a Float64Array> {
    let column = batch
        .column_by_name(name)
        .ok_or_else(|| Error::content(path, format!("no column `{name}`")))?;
    column
        .as_any()
        .downcast_ref::<Float64Array>()
        .ok_or_else(|| Error::content(path, format!("column `{name}` is not f64")))
}

/// [`last_state`] without the guard.
fn last_state_unguarded<St: StateColumns>(
    path: &Path,
    columns: &[String],
) -> Result<(usize, f64, St)> {
    // The last part of a run that ended with a full part holds only its outcome: the state is
    // in the last part with rows.
    let mut last = path.to_owned();
    let mut batches = Vec::new();
    for file in files(path)?.into_iter().rev() {
        batches = read_batches(&file)?;
        last = file;
        if batches.iter().any(|b| b.num_rows() > 0) {
            break;
        }
    }
    let Some(batch) = batches.iter().rev().find(|b| b.num_rows() > 0) else {
        return Err(Error::content(&last, "no rows"));
    };
    let row = batch.num_rows() - 1;
    if let Some(width) = St::WIDTH.filter(|w| *w != columns.len()) {
        return Err(Error::Usage(format!(
            "{} column names for a state of {width} columns",
            columns.len(),
        )));
    }
    let step = batch
        .column_by_name("step")
        .and_then(|c| c.as_any().downcast_ref::<UInt64Array>())
        .ok_or_else(|| Error::content(&last, "no u64 column `step`: not a trajectory"))?
        .value(row);
    let t = f64_column(batch, &last, "t")?.value(row);
    let mut values = Vec::with_capacity(columns.len());
    for name in columns {
        values.push(f64_column(batch, &last, name)?.value(row));
    }
    Ok((step as usize, t, St::read_from(columns, &values)))
}

/// [`concatenate`] without the guard.
fn concatenate_unguarded(inputs: &[PathBuf], out: &Path, kv: Vec<(String, String)>) -> Result<u64> {
    let mut all = Vec::new();
    for input in inputs {
        all.extend(files(input)?);
    }
    let Some(first) = all.first() else {
        return Err(Error::content(out, "nothing to concatenate"));
    };
    let schema = builder(first)?.schema().clone();
    let mut writer = FileWriter::create(out, schema.clone(), Compression::UNCOMPRESSED, kv)?;
    let mut rows = 0;
    for input in &all {
        verify(input)?;
        let reader = builder(input)?;
        if reader.schema().fields() != schema.fields() {
            return Err(Error::content(
                input,
                format!("its columns differ from those of {}", first.display()),
            ));
        }
        for batch in reader.build().map_err(Error::parquet(input))? {
            let batch = batch.map_err(Error::arrow(input))?;
            rows += batch.num_rows() as u64;
            writer.write(&batch)?;
        }
    }
    writer.close(true)?;
    Ok(rows)
}

/// [`first_difference`] without the guard.
fn first_difference_unguarded(a: &Path, b: &Path) -> Result<Option<String>> {
    let (sa, sb) = (schema(a)?, schema(b)?);
    if sa.fields() != sb.fields() {
        return Ok(Some(format!(
            "the columns differ: {:?} against {:?}",
            sa.fields().iter().map(|f| f.name()).collect::<Vec<_>>(),
            sb.fields().iter().map(|f| f.name()).collect::<Vec<_>>()
        )));
    }
    let one_batch = |path: &Path, schema| -> Result<RecordBatch> {
        let batches = read_batches(path)?;
        arrow_select::concat::concat_batches(schema, &batches).map_err(Error::arrow(path))
    };
    let (ba, bb) = (one_batch(a, &sa)?, one_batch(b, &sb)?);
    if ba.num_rows() != bb.num_rows() {
        return Ok(Some(format!(
            "{} rows against {}",
            ba.num_rows(),
            bb.num_rows()
        )));
    }
    for (field, (ca, cb)) in sa
        .fields()
        .iter()
        .zip(ba.columns().iter().zip(bb.columns()))
    {
        if field.data_type() == &DataType::Float64 {
            let (Some(va), Some(vb)) = (
                ca.as_any().downcast_ref::<Float64Array>(),
                cb.as_any().downcast_ref::<Float64Array>(),
            ) else {
                return Ok(Some(format!(
                    "column `{}` is not f64 in both",
                    field.name()
                )));
            };
            for i in 0..va.len() {
                let x = (!va.is_null(i)).then(|| va.value(i).to_bits());
                let y = (!vb.is_null(i)).then(|| vb.value(i).to_bits());
                if x != y {
                    return Ok(Some(format!(
                        "column `{}`, row {i}: {:?} against {:?}",
                        field.name(),
                        x.map(f64::from_bits),
                        y.map(f64::from_bits)
                    )));
                }
            }
        } else if ca.to_data() != cb.to_data() {
            return Ok(Some(format!("column `{}` differs", field.name())));
        }
    }
    Ok(None)
}

/// [`schema`] without the guard.
fn schema_unguarded(path: &Path) -> Result<arrow_schema::SchemaRef> {
    let files = files(path)?;
    Ok(builder(files.first().unwrap_or(&path.to_owned()))?
        .schema()
        .clone())
}

/// [`row_groups`] without the guard.
fn row_groups_unguarded(path: &Path) -> Result<(usize, u64)> {
    let (mut count, mut largest) = (0, 0);
    for file in files(path)? {
        let builder = builder(&file)?;
        let groups = builder.metadata().row_groups();
        count += groups.len();
        largest = groups
            .iter()
            .map(|g| g.num_rows() as u64)
            .fold(largest, u64::max);
    }
    Ok((count, largest))
}
