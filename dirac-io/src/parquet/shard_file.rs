//! A shard's file in Parquet: one row per member ([the shard schema](crate::shard)).

use std::path::Path;
use std::sync::Arc;

use arrow_array::{ArrayRef, Float64Array, RecordBatch, StringArray, UInt64Array};
use arrow_schema::{DataType, Field, Schema};
use dirac::prelude::*;
use parquet::basic::Compression;

use super::integrity::FileWriter;
use crate::error::{Error, Result};

/// One member's row of a shard file.
pub(crate) struct MemberRow {
    pub(crate) member: u64,
    pub(crate) steps: u64,
    pub(crate) t: f64,
    pub(crate) last: Vec<f64>,
    pub(crate) summary: [u64; 3],
    pub(crate) max_residual: f64,
    pub(crate) worst_rcond: Option<(usize, f64)>,
    pub(crate) error: Option<Failure>,
}

/// Why a member failed, as its row records it.
pub(crate) struct Failure {
    pub(crate) kind: String,
    pub(crate) step: Option<u64>,
    pub(crate) residual: Option<f64>,
    pub(crate) message: String,
}

impl From<StepError> for Failure {
    fn from(e: StepError) -> Self {
        Failure {
            kind: e.kind().to_owned(),
            step: Some(e.step() as u64),
            residual: Some(e.residual()),
            message: e.to_string(),
        }
    }
}

/// Writes the shard file at `path`: one row per member (the [shard schema](crate::shard)), the
/// state columns named `columns`, key-value metadata `kv`, checksums; synced.
pub(crate) fn write_rows(
    path: &Path,
    columns: &[String],
    rows: &[MemberRow],
    kv: Vec<(String, String)>,
) -> Result<()> {
    let mut fields = vec![
        Field::new("member", DataType::UInt64, false),
        Field::new("status", DataType::Utf8, false),
        Field::new("steps", DataType::UInt64, false),
        Field::new("t", DataType::Float64, false),
    ];
    fields.extend(
        columns
            .iter()
            .map(|c| Field::new(c, DataType::Float64, false)),
    );
    for name in ["iterations", "max_iterations", "factorizations"] {
        fields.push(Field::new(name, DataType::UInt64, false));
    }
    fields.extend([
        Field::new("max_residual", DataType::Float64, false),
        Field::new("worst_rcond", DataType::Float64, true),
        Field::new("worst_rcond_step", DataType::UInt64, true),
        Field::new("error_kind", DataType::Utf8, true),
        Field::new("error_step", DataType::UInt64, true),
        Field::new("error_residual", DataType::Float64, true),
        Field::new("error_message", DataType::Utf8, true),
    ]);
    let schema = Arc::new(Schema::new(fields));
    let u64s = |f: &dyn Fn(&MemberRow) -> u64| -> ArrayRef {
        Arc::new(rows.iter().map(f).collect::<UInt64Array>())
    };
    let f64s = |f: &dyn Fn(&MemberRow) -> f64| -> ArrayRef {
        Arc::new(rows.iter().map(f).collect::<Float64Array>())
    };
    let mut arrays: Vec<ArrayRef> = vec![
        u64s(&|r| r.member),
        Arc::new(
            rows.iter()
                .map(|r| {
                    Some(if r.error.is_some() {
                        "failed"
                    } else {
                        "completed"
                    })
                })
                .collect::<StringArray>(),
        ),
        u64s(&|r| r.steps),
        f64s(&|r| r.t),
    ];
    for c in 0..columns.len() {
        arrays.push(f64s(&|r| r.last.get(c).copied().unwrap_or(f64::NAN)));
    }
    for s in 0..3 {
        arrays.push(u64s(&|r| r.summary[s]));
    }
    arrays.push(f64s(&|r| r.max_residual));
    arrays.push(Arc::new(
        rows.iter()
            .map(|r| r.worst_rcond.map(|w| w.1))
            .collect::<Float64Array>(),
    ));
    arrays.push(Arc::new(
        rows.iter()
            .map(|r| r.worst_rcond.map(|w| w.0 as u64))
            .collect::<UInt64Array>(),
    ));
    arrays.push(Arc::new(
        rows.iter()
            .map(|r| r.error.as_ref().map(|e| e.kind.as_str()))
            .collect::<StringArray>(),
    ));
    arrays.push(Arc::new(
        rows.iter()
            .map(|r| r.error.as_ref().and_then(|e| e.step))
            .collect::<UInt64Array>(),
    ));
    arrays.push(Arc::new(
        rows.iter()
            .map(|r| r.error.as_ref().and_then(|e| e.residual))
            .collect::<Float64Array>(),
    ));
    arrays.push(Arc::new(
        rows.iter()
            .map(|r| r.error.as_ref().map(|e| e.message.as_str()))
            .collect::<StringArray>(),
    ));
    let mut writer = FileWriter::create(path, schema.clone(), Compression::UNCOMPRESSED, kv)?;
    let batch = RecordBatch::try_new(schema, arrays).map_err(Error::arrow(path))?;
    writer.write(&batch)?;
    writer.close(true)
}
