//! What a format implements to store a run: blocks of rows of named `f64` columns, in parts,
//! each published complete.

use std::path::Path;

use crate::error::Result;

/// The columns and metadata of a run's rows and how they are cut, given to a [`Sink`] when it is
/// created ([`super::Options::layout`]). The names come from the system's description
/// ([`crate::RunInfo`]), not from the format.
///
/// A row is: `member` (a constant, when [`Self::member`] is set), `step` (an integer), `t`, one
/// value per name of [`Self::state`], `iterations` (an integer), `residual` and `rcond` (the
/// three absent for the initial state, `rcond` also when no Jacobian was factored), then one
/// value per name of [`Self::extra`].
#[derive(Clone, Debug, PartialEq)]
pub struct Layout {
    /// The member every row belongs to (ensembles written to one file).
    pub member: Option<u64>,
    /// The state's column names ([`crate::RunInfo::columns`]).
    pub state: Vec<String>,
    /// The extra columns' names ([`super::Options::extra`]).
    pub extra: Vec<String>,
    /// The run's metadata: its description ([`crate::RunInfo::key_values`]), `dirac.every`,
    /// `dirac.member`. Every part carries it.
    pub metadata: Vec<(String, String)>,
    /// The most rows of a block ([`Rows`]).
    pub rows_per_group: usize,
    /// The rows of a part (the last one fewer); `None`: one file, published when the run ends.
    pub rows_per_part: Option<u64>,
    /// Whether a part is synced to disk before it is published.
    pub sync: bool,
    /// Whether values are compressed, where the format compresses.
    pub compress: bool,
}

/// A block of rows, column by column, as an [`super::Output`] hands it to its [`Sink`] (the
/// columns of a [`Layout`], in its order).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Rows {
    /// The step index `k` of each row.
    pub step: Vec<u64>,
    /// The time `t_k`.
    pub t: Vec<f64>,
    /// Column-major: `state[c]` is state column `c`.
    pub state: Vec<Vec<f64>>,
    /// The Newton corrections of the step that produced the state (`None` for the initial state).
    pub iterations: Vec<Option<u32>>,
    /// Its accepted residual `‖R‖∞`.
    pub residual: Vec<Option<f64>>,
    /// Its reciprocal condition estimate.
    pub rcond: Vec<Option<f64>>,
    /// Column-major: `extra[c]` is extra column `c`.
    pub extra: Vec<Vec<f64>>,
    /// Whether the last row is the last of a part: the sink publishes the part once the block is
    /// written.
    pub ends_part: bool,
}

impl Rows {
    /// An empty block with room for `rows` rows of `width` state and `extra` extra columns.
    pub fn new(width: usize, extra: usize, rows: usize) -> Self {
        Rows {
            step: Vec::with_capacity(rows),
            t: Vec::with_capacity(rows),
            state: (0..width).map(|_| Vec::with_capacity(rows)).collect(),
            iterations: Vec::with_capacity(rows),
            residual: Vec::with_capacity(rows),
            rcond: Vec::with_capacity(rows),
            extra: (0..extra).map(|_| Vec::with_capacity(rows)).collect(),
            ends_part: false,
        }
    }

    /// The number of rows.
    pub fn len(&self) -> usize {
        self.step.len()
    }

    /// Whether the block has no rows.
    pub fn is_empty(&self) -> bool {
        self.step.is_empty()
    }
}

/// A format that stores a run's rows ([`Rows`], laid out as a [`Layout`]) crash-safely: what an
/// [`super::Output`] observer writes into, for every kind of run. Parquet is one
/// ([`crate::parquet::Parquet`]).
///
/// The guarantees an implementation keeps, which the observer's own rest on:
///
/// * a part is invisible to readers until it is published, and published complete: written
///   under a hidden name and renamed (synced first with [`Layout::sync`]);
/// * [`Self::write`] of a block that ends a part ([`Rows::ends_part`]) returns only once that
///   part is published, so a killed process loses at most one part's rows;
/// * on an error (a full disk) the unpublished part is removed and nothing more is written;
///   the parts published before stay.
pub trait Sink: Send + 'static {
    /// Writes one block of rows (a unit the format keeps together: Parquet's row group), and
    /// publishes the part it ends ([`Rows::ends_part`]), beginning the next.
    fn write(&mut self, rows: Rows) -> Result<()>;

    /// Adds `outcome` to the metadata of the part being written (the run's outcome, or nothing)
    /// and publishes it: the output is complete. Called once, after the last [`Self::write`].
    fn close(&mut self, outcome: Vec<(String, String)>) -> Result<()>;

    /// The file or directory written.
    fn path(&self) -> &Path;
}
