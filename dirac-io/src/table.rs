//! An ensemble as a table: one row per member, one `f64` column per initial-state component or
//! parameter that varies (`x_phi1`, `w_phi1`, `mu_vt1`, `h`, `m`, …, named as in the
//! [trajectory schema](crate)). Read from CSV or Parquet, written to either; member `i` is row
//! `i`. What a column means is up to the closure that turns a [`Row`] into an integrator and an
//! initial state, which takes the components it finds and defaults for the others
//! ([`Row::state_or`], [`Row::get_or`]), or requires them ([`Row::require`]).
//!
//! A column the run does not read would be silently ignored, and every member would run its
//! default in its place: a misspelled `w__phi1` for `w_phi1`, a name given twice. So the
//! columns are checked before any member runs ([`Table::validate`], called by
//! [`run_shard`](crate::shard::run_shard)): every name must be one the run accepts
//! ([`RunInfo::table_columns`]: the state's columns, the parameters, the time step and the
//! Newton options, and the names declared with [`Table::accept`]), and no name may appear twice.
//! The error names the offending columns, suggests the closest accepted name for each unknown
//! one, and lists the accepted names.

use std::fs::File;
use std::io::{BufRead, BufReader, BufWriter, Write};
use std::path::Path;

use crate::columns::{float_text, RunInfo, StateColumns};
use crate::error::{Error, Result};

/// Rows of named `f64` columns (see the [module documentation](self)).
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    pub(crate) names: Vec<String>,
    /// Column-major; every column has the same length.
    pub(crate) columns: Vec<Vec<f64>>,
    /// Names accepted beyond those of the run's description ([`Table::accept`]).
    accepted: Vec<String>,
}

/// [`Row::require`] found no such column: the typed error a member closure returns with `?`,
/// which becomes the member's failed row (`error_kind = "member"`, `error_message` its text).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("the table has no column `{name}` (its columns: {})", list(.columns))]
pub struct MissingColumn {
    /// The column asked for.
    pub name: String,
    /// The table's columns.
    pub columns: Vec<String>,
}

/// `a, b, c`, or `(none)`.
fn list(names: &[String]) -> String {
    if names.is_empty() {
        "(none)".to_owned()
    } else {
        names.join(", ")
    }
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
        self.table.column(name)?.get(self.index).copied()
    }

    /// The value in column `name`, or a [`MissingColumn`] error naming it: in a member closure,
    /// `let m2 = row.require("m2")?;` makes a member without it a failed row with that message.
    pub fn require(&self, name: &str) -> Result<f64, MissingColumn> {
        self.get(name).ok_or_else(|| MissingColumn {
            name: name.to_owned(),
            columns: self.table.names.clone(),
        })
    }

    /// The value in column `name`, or `default` when the table has no such column.
    pub fn get_or(&self, name: &str, default: f64) -> f64 {
        self.get(name).unwrap_or(default)
    }

    /// The state whose component named `columns[c]` is taken from the table where it has that
    /// column, and from `default` otherwise (`columns` as [`StateColumns::column_names`]).
    pub fn state_or<St: StateColumns>(&self, columns: &[String], default: St) -> St {
        let mut values = vec![0.0; default.width()];
        default.write_to(&mut values);
        for (v, name) in values.iter_mut().zip(columns) {
            if let Some(x) = self.get(name) {
                *v = x;
            }
        }
        St::read_from(columns, &values)
    }
}

impl Table {
    /// An empty table with these columns.
    pub fn new<S: Into<String>>(names: impl IntoIterator<Item = S>) -> Self {
        let names: Vec<String> = names.into_iter().map(Into::into).collect();
        let columns = names.iter().map(|_| Vec::new()).collect();
        Table {
            names,
            columns,
            accepted: Vec::new(),
        }
    }

    /// Appends a row, one value per column in order; an error ([`Error::Usage`]) unless `row`
    /// has one value per column.
    pub fn push(&mut self, row: &[f64]) -> Result<()> {
        if row.len() != self.names.len() {
            return Err(Error::Usage(format!(
                "a row of {} values for a table of {} columns ({})",
                row.len(),
                self.names.len(),
                list(&self.names)
            )));
        }
        for (c, v) in self.columns.iter_mut().zip(row) {
            c.push(*v);
        }
        Ok(())
    }

    /// Declares columns that the member closure reads beyond those of the run's description
    /// (a seed, a perturbation's amplitude): [`Self::validate`] accepts them.
    #[must_use]
    pub fn accept<S: Into<String>>(mut self, names: impl IntoIterator<Item = S>) -> Self {
        self.accepted.extend(names.into_iter().map(Into::into));
        self
    }

    /// Checks the columns against the names a run accepts (`accepted`, e.g.
    /// [`RunInfo::table_columns`], and those declared with [`Self::accept`]): an
    /// [`Error::Columns`] naming every unknown column (with the closest accepted name when one
    /// is within a third of its length in edits: a misspelling) and every name given more than
    /// once, and listing the accepted names.
    pub fn validate<S: AsRef<str>>(&self, accepted: &[S]) -> Result<()> {
        let mut all: Vec<String> = accepted.iter().map(|a| a.as_ref().to_owned()).collect();
        for a in &self.accepted {
            if !all.contains(a) {
                all.push(a.clone());
            }
        }
        let mut unknown = Vec::new();
        let mut duplicated: Vec<String> = Vec::new();
        for (i, name) in self.names.iter().enumerate() {
            if self.names[..i].contains(name) {
                if !duplicated.contains(name) {
                    duplicated.push(name.clone());
                }
            } else if !all.contains(name) {
                unknown.push((name.clone(), closest(name, &all)));
            }
        }
        if unknown.is_empty() && duplicated.is_empty() {
            return Ok(());
        }
        Err(Error::Columns {
            unknown,
            duplicated,
            accepted: all,
        })
    }

    /// [`Self::validate`] against the columns a run described by `info` accepts
    /// ([`RunInfo::table_columns`]).
    pub fn validate_for(&self, info: &RunInfo) -> Result<()> {
        self.validate(&info.table_columns())
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

    /// The column `name`, if any (the first of that name).
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        let c = self.names.iter().position(|n| n == name)?;
        self.columns.get(c).map(Vec::as_slice)
    }

    /// Row `index`, if `index < self.len()`.
    pub fn row(&self, index: usize) -> Option<Row<'_>> {
        (index < self.len()).then_some(Row { table: self, index })
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
                None => {
                    let header = Table::new(fields);
                    if let Some(message) = header.repeated_name() {
                        return Err(Error::content(path, format!("line {}: {message}", n + 1)));
                    }
                    table = Some(header);
                }
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
                    t.push(&row)?;
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
                let row: Vec<String> = self
                    .columns
                    .iter()
                    .map(|c| c.get(i).map_or_else(String::new, |v| float_text(*v)))
                    .collect();
                writeln!(out, "{}", row.join(","))?;
            }
            out.flush()
        };
        write().map_err(Error::io(path))
    }
}

impl Table {
    /// The first name the header gives twice, as an error message: a second column of the same
    /// name could never be read (a reader finds the first), so a header with one is refused.
    pub(crate) fn repeated_name(&self) -> Option<String> {
        self.names.iter().enumerate().find_map(|(i, name)| {
            let first = self.names[..i].iter().position(|n| n == name)?;
            Some(format!(
                "column `{name}` is given more than once in the header (columns {} and {})",
                first + 1,
                i + 1
            ))
        })
    }
}

/// The accepted name closest to `name`, if it is a plausible misspelling: equal but for case, or
/// within `max(1, len / 3)` edits (insertions, deletions, substitutions, transpositions of
/// adjacent characters), the nearest first.
pub(crate) fn closest(name: &str, accepted: &[String]) -> Option<String> {
    let lower = name.to_lowercase();
    if let Some(a) = accepted.iter().find(|a| a.to_lowercase() == lower) {
        return Some(a.clone());
    }
    let limit = (name.chars().count() / 3).max(1);
    accepted
        .iter()
        .map(|a| (edit_distance(name, a), a))
        .filter(|(d, _)| *d <= limit)
        .min_by_key(|(d, _)| *d)
        .map(|(_, a)| a.clone())
}

/// The optimal-string-alignment distance between `a` and `b` (Damerau–Levenshtein without
/// repeated edits of a substring), over characters, by the usual dynamic programme on three
/// rows.
fn edit_distance(a: &str, b: &str) -> usize {
    let (a, b): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
    let mut before: Vec<usize> = vec![0; b.len() + 1];
    let mut previous: Vec<usize> = (0..=b.len()).collect();
    let mut current: Vec<usize> = vec![0; b.len() + 1];
    for i in 1..=a.len() {
        current[0] = i;
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            let mut d = (previous[j] + 1)
                .min(current[j - 1] + 1)
                .min(previous[j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                d = d.min(before[j - 2] + 1);
            }
            current[j] = d;
        }
        std::mem::swap(&mut before, &mut previous);
        std::mem::swap(&mut previous, &mut current);
    }
    previous[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edit_distances() {
        assert_eq!(edit_distance("w__phi1", "w_phi1"), 1);
        assert_eq!(edit_distance("w_ph1i", "w_phi1"), 1);
        assert_eq!(edit_distance("", "abc"), 3);
        assert_eq!(edit_distance("kitten", "sitting"), 3);
    }

    #[test]
    fn misspellings_find_their_name_and_strangers_none() {
        let accepted: Vec<String> = ["x_phi1", "w_phi1", "w_vt2", "m2"].map(String::from).into();
        assert_eq!(closest("w__phi1", &accepted).as_deref(), Some("w_phi1"));
        assert_eq!(closest("M2", &accepted).as_deref(), Some("m2"));
        assert_eq!(closest("seed", &accepted), None);
    }
}
