//! An ensemble as a table: one row per member, one `f64` column per initial-state component or
//! parameter that varies (`x_phi1`, `w_phi1`, `mu_vt1`, `h`, `m`, …, named as in the
//! [trajectory schema](crate)). Read from CSV or Parquet, written to either; member `i` is row
//! `i`. What a column means is up to the closure that turns a [`Row`] into an integrator and an
//! initial state, which takes the components it finds and defaults for the others
//! ([`Row::state_or`], [`Row::get_or`]).

use std::fs::File;
use std::io::{BufRead, BufReader, BufWriter, Write};
use std::path::Path;
use std::sync::Arc;

use arrow_array::{Array, ArrayRef, Float64Array, RecordBatch};
use arrow_schema::{DataType, Field, Schema};
use parquet::basic::Compression;

use crate::columns::{float_text, StateColumns};
use crate::error::{Error, Result};
use crate::integrity::FileWriter;

/// Rows of named `f64` columns (see the [module documentation](self)).
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    names: Vec<String>,
    /// Column-major.
    columns: Vec<Vec<f64>>,
}

/// Row `index` of a [`Table`]: member `index` of the ensemble.
#[derive(Clone, Copy, Debug)]
pub struct Row<'a> {
    table: &'a Table,
    index: usize,
}

impl Row<'_> {
    /// The row's index, the member's number.
    pub fn index(&self) -> usize {
        self.index
    }

    /// The value in column `name`, if the table has it.
    pub fn get(&self, name: &str) -> Option<f64> {
        self.table.column(name).map(|c| c[self.index])
    }

    /// The value in column `name`, or `default` when the table has no such column.
    pub fn get_or(&self, name: &str, default: f64) -> f64 {
        self.get(name).unwrap_or(default)
    }

    /// The state whose component named `columns[c]` is taken from the table where it has that
    /// column, and from `default` otherwise (`columns` as [`StateColumns::column_names`]).
    pub fn state_or<St: StateColumns>(&self, columns: &[String], default: St) -> St {
        let mut values = vec![0.0; St::WIDTH];
        default.write_to(&mut values);
        for (v, name) in values.iter_mut().zip(columns) {
            if let Some(x) = self.get(name) {
                *v = x;
            }
        }
        St::read_from(&values)
    }
}

impl Table {
    /// An empty table with these columns.
    pub fn new<S: Into<String>>(names: impl IntoIterator<Item = S>) -> Self {
        let names: Vec<String> = names.into_iter().map(Into::into).collect();
        let columns = names.iter().map(|_| Vec::new()).collect();
        Table { names, columns }
    }

    /// Appends a row, one value per column in order.
    ///
    /// # Panics
    /// If `row` does not have one value per column.
    pub fn push(&mut self, row: &[f64]) {
        assert_eq!(row.len(), self.names.len(), "one value per column");
        for (c, v) in self.columns.iter_mut().zip(row) {
            c.push(*v);
        }
    }

    /// The column names.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// The number of rows (members).
    pub fn len(&self) -> usize {
        self.columns.first().map_or(0, Vec::len)
    }

    /// Whether the table has no rows.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The column `name`, if any.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        let c = self.names.iter().position(|n| n == name)?;
        Some(&self.columns[c])
    }

    /// Row `index`.
    ///
    /// # Panics
    /// If `index >= self.len()`.
    pub fn row(&self, index: usize) -> Row<'_> {
        assert!(index < self.len(), "row {index} of {}", self.len());
        Row { table: self, index }
    }

    /// A 64-bit FNV-1a hash of the names and the values' bits: shards record it, and merging
    /// refuses shards of another table.
    pub fn fingerprint(&self) -> u64 {
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        let mut eat = |bytes: &[u8]| {
            for b in bytes {
                h = (h ^ u64::from(*b)).wrapping_mul(0x0100_0000_01b3);
            }
        };
        for (name, column) in self.names.iter().zip(&self.columns) {
            eat(name.as_bytes());
            eat(&[0]);
            for v in column {
                eat(&v.to_bits().to_le_bytes());
            }
        }
        h
    }

    /// Reads a table from `path`: Parquet if its name ends in `.parquet`, CSV otherwise.
    pub fn read(path: impl AsRef<Path>) -> Result<Self> {
        let path = path.as_ref();
        if path.extension().is_some_and(|e| e == "parquet") {
            Self::read_parquet(path)
        } else {
            Self::read_csv(path)
        }
    }

    /// Writes the table to `path`: Parquet if its name ends in `.parquet`, CSV otherwise.
    pub fn write(&self, path: impl AsRef<Path>) -> Result<()> {
        let path = path.as_ref();
        if path.extension().is_some_and(|e| e == "parquet") {
            self.write_parquet(path)
        } else {
            self.write_csv(path)
        }
    }

    /// Reads CSV: a header line of names, then one line of comma-separated numbers per row
    /// (Rust's `f64` syntax: `1.5`, `-2e-3`, `NaN`, `inf`); blank lines and lines starting with
    /// `#` are skipped.
    pub fn read_csv(path: impl AsRef<Path>) -> Result<Self> {
        let path = path.as_ref();
        let file = File::open(path).map_err(Error::io(path))?;
        let mut table: Option<Table> = None;
        for (n, line) in BufReader::new(file).lines().enumerate() {
            let line = line.map_err(Error::io(path))?;
            let line = line.trim();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let fields = line.split(',').map(str::trim);
            match &mut table {
                None => table = Some(Table::new(fields)),
                Some(t) => {
                    let row = fields
                        .enumerate()
                        .map(|(c, f)| {
                            f.parse::<f64>().map_err(|_| {
                                Error::content(
                                    path,
                                    format!(
                                        "line {}, column {}: `{f}` is not a number",
                                        n + 1,
                                        c + 1
                                    ),
                                )
                            })
                        })
                        .collect::<Result<Vec<f64>>>()?;
                    if row.len() != t.names.len() {
                        return Err(Error::content(
                            path,
                            format!(
                                "line {}: {} values, the header names {} columns",
                                n + 1,
                                row.len(),
                                t.names.len()
                            ),
                        ));
                    }
                    t.push(&row);
                }
            }
        }
        table.ok_or_else(|| Error::content(path, "no header line"))
    }

    /// Writes CSV in the form [`Self::read_csv`] reads, each value in Rust's shortest form that
    /// reads back to the same bits.
    pub fn write_csv(&self, path: impl AsRef<Path>) -> Result<()> {
        let path = path.as_ref();
        let file = File::create(path).map_err(Error::io(path))?;
        let mut out = BufWriter::new(file);
        let mut write = || -> std::io::Result<()> {
            writeln!(out, "{}", self.names.join(","))?;
            for i in 0..self.len() {
                let row: Vec<String> = self.columns.iter().map(|c| float_text(c[i])).collect();
                writeln!(out, "{}", row.join(","))?;
            }
            out.flush()
        };
        write().map_err(Error::io(path))
    }

    /// Reads Parquet: every column must be `f64` (as this crate writes tables).
    pub fn read_parquet(path: impl AsRef<Path>) -> Result<Self> {
        let path = path.as_ref();
        let batches = crate::read::read_batches(path)?;
        let schema = match batches.first() {
            Some(b) => b.schema(),
            None => {
                let names: Vec<String> = crate::read::schema(path)?
                    .fields()
                    .iter()
                    .map(|f| f.name().clone())
                    .collect();
                return Ok(Table::new(names));
            }
        };
        let mut table = Table::new(schema.fields().iter().map(|f| f.name().clone()));
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
                table.columns[c].extend_from_slice(values.values());
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
