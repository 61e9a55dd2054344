//! Reading back what this crate wrote: key-value metadata, concatenation of files in order
//! (an ensemble's members, a sharded ensemble's shards), and a bit-for-bit comparison.

use std::collections::BTreeMap;
use std::fs::File;
use std::path::{Path, PathBuf};

use arrow_array::{Array, Float64Array, RecordBatch};
use arrow_schema::DataType;
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use parquet::basic::Compression;

use crate::error::{Error, Result};
use crate::observer::{close_writer, create_writer, writer_properties};

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

fn builder(path: &Path) -> Result<ParquetRecordBatchReaderBuilder<File>> {
    let file = File::open(path).map_err(Error::io(path))?;
    ParquetRecordBatchReaderBuilder::try_new(file).map_err(Error::parquet(path))
}

/// The key-value metadata of the Parquet file at `path` (without the embedded Arrow schema).
pub fn key_values(path: &Path) -> Result<BTreeMap<String, String>> {
    guarded(path, || {
        let builder = builder(path)?;
        let kv = builder.metadata().file_metadata().key_value_metadata();
        Ok(kv
            .into_iter()
            .flatten()
            .filter(|kv| kv.key != "ARROW:schema")
            .filter_map(|kv| Some((kv.key.clone(), kv.value.clone()?)))
            .collect())
    })
}

/// The number of rows of the Parquet file at `path`, from its footer.
pub fn row_count(path: &Path) -> Result<u64> {
    guarded(path, || {
        let builder = builder(path)?;
        Ok(builder.metadata().file_metadata().num_rows() as u64)
    })
}

/// Every row of the Parquet file at `path`, as record batches.
pub fn read_batches(path: &Path) -> Result<Vec<RecordBatch>> {
    guarded(path, || {
        builder(path)?
            .build()
            .map_err(Error::parquet(path))?
            .map(|b| b.map_err(Error::arrow(path)))
            .collect()
    })
}

/// One `f64` column of the Parquet file at `path`, all rows (nulls as `NaN`).
pub fn read_f64_column(path: &Path, name: &str) -> Result<Vec<f64>> {
    let mut out = Vec::new();
    for batch in read_batches(path)? {
        let column = batch
            .column_by_name(name)
            .ok_or_else(|| Error::content(path, format!("no column `{name}`")))?;
        let values = column
            .as_any()
            .downcast_ref::<Float64Array>()
            .ok_or_else(|| Error::content(path, format!("column `{name}` is not f64")))?;
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

/// Writes the rows of `inputs`, in order, into one file at `out` (same schema required), with
/// key-value metadata `kv`; reads one batch at a time, so memory does not grow with the
/// inputs. Returns the number of rows.
pub fn concatenate(inputs: &[PathBuf], out: &Path, kv: Vec<(String, String)>) -> Result<u64> {
    guarded(out, || {
        let Some(first) = inputs.first() else {
            return Err(Error::content(out, "nothing to concatenate"));
        };
        let schema = builder(first)?.schema().clone();
        let mut writer = create_writer(
            out,
            schema.clone(),
            writer_properties(Compression::UNCOMPRESSED, kv),
        )?;
        let mut rows = 0;
        for input in inputs {
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
                writer.write(&batch).map_err(Error::parquet(out))?;
            }
        }
        close_writer(writer, out, true)?;
        Ok(rows)
    })
}

/// Compares the rows of two Parquet files bit for bit (floats by their bit patterns, so `NaN`
/// equals the same `NaN` and `0.0` differs from `-0.0`): `None` when they hold the same columns
/// and values, else a description of the first difference. Metadata is not compared.
pub fn first_difference(a: &Path, b: &Path) -> Result<Option<String>> {
    guarded(a, || {
        let (sa, sb) = (builder(a)?.schema().clone(), builder(b)?.schema().clone());
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
                let f64s = |path: &Path, c: &dyn Array| {
                    c.as_any()
                        .downcast_ref::<Float64Array>()
                        .cloned()
                        .ok_or_else(|| {
                            Error::content(path, format!("column `{}` is not f64", field.name()))
                        })
                };
                let (va, vb) = (f64s(a, ca.as_ref())?, f64s(b, cb.as_ref())?);
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
    })
}

/// The Arrow schema of the Parquet file at `path`.
pub fn schema(path: &Path) -> Result<arrow_schema::SchemaRef> {
    guarded(path, || Ok(builder(path)?.schema().clone()))
}

/// The number of row groups of the Parquet file at `path`, and the most rows one of them holds:
/// what a reader or the writer held in memory at once.
pub fn row_groups(path: &Path) -> Result<(usize, u64)> {
    guarded(path, || {
        let builder = builder(path)?;
        let groups = builder.metadata().row_groups();
        let largest = groups
            .iter()
            .map(|g| g.num_rows() as u64)
            .max()
            .unwrap_or(0);
        Ok((groups.len(), largest))
    })
}
