//! A [`Table`] in Parquet: one `f64` column per column (the Parquet half of
//! [`Table::read`] and [`Table::write`]).

use std::path::Path;
use std::sync::Arc;

use arrow_array::{Array, ArrayRef, Float64Array, RecordBatch};
use arrow_schema::{DataType, Field, Schema};
use parquet::basic::Compression;

use super::integrity::FileWriter;
use crate::error::{Error, Result};
use crate::table::Table;

impl Table {
    /// Reads Parquet: every column must be `f64` (as this crate writes tables).
    pub fn read_parquet(path: impl AsRef<Path>) -> Result<Self> {
        let path = path.as_ref();
        let batches = super::read::read_batches(path)?;
        let schema = match batches.first() {
            Some(b) => b.schema(),
            None => {
                let names: Vec<String> = super::read::schema(path)?
                    .fields()
                    .iter()
                    .map(|f| f.name().clone())
                    .collect();
                let table = Table::new(names);
                return match table.repeated_name() {
                    Some(message) => Err(Error::content(path, message)),
                    None => Ok(table),
                };
            }
        };
        let mut table = Table::new(schema.fields().iter().map(|f| f.name().clone()));
        if let Some(message) = table.repeated_name() {
            return Err(Error::content(path, message));
        }
        for batch in &batches {
            for (c, (field, column)) in schema.fields().iter().zip(batch.columns()).enumerate() {
                let values = column
                    .as_any()
                    .downcast_ref::<Float64Array>()
                    .filter(|v| v.null_count() == 0)
                    .ok_or_else(|| {
                        Error::content(
                            path,
                            format!(
                                "column `{}` is {}; a table's columns are f64 without nulls",
                                field.name(),
                                field.data_type()
                            ),
                        )
                    })?;
                if let Some(out) = table.columns.get_mut(c) {
                    out.extend_from_slice(values.values());
                }
            }
        }
        Ok(table)
    }

    /// Writes Parquet: one `f64` column per column, key-value metadata `dirac.table.fingerprint`.
    pub fn write_parquet(&self, path: impl AsRef<Path>) -> Result<()> {
        let path = path.as_ref();
        let schema = Arc::new(Schema::new(
            self.names
                .iter()
                .map(|n| Field::new(n, DataType::Float64, false))
                .collect::<Vec<_>>(),
        ));
        let kv = vec![(
            "dirac.table.fingerprint".to_owned(),
            format!("{:016x}", self.fingerprint()),
        )];
        let mut writer = FileWriter::create(path, schema.clone(), Compression::UNCOMPRESSED, kv)?;
        let columns: Vec<ArrayRef> = self
            .columns
            .iter()
            .map(|c| Arc::new(Float64Array::from(c.clone())) as ArrayRef)
            .collect();
        let batch = RecordBatch::try_new(schema, columns).map_err(Error::arrow(path))?;
        writer.write(&batch)?;
        writer.close(true)
    }
}
