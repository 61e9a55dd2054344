//! Ensembles written to Parquet: one file per member, or one file with a `member` column.

use std::path::PathBuf;

use dirac::prelude::*;
use dirac::runtime::driver::RunResult;
use dirac::runtime::ensemble::map;

use crate::columns::{RunInfo, StateColumns};
use crate::error::{Error, Result};
pub use crate::files::member_file;
use crate::files::publish;
use crate::output::Options;
use crate::parquet::ParquetObserver;
use crate::progress;
use crate::read::concatenate;

/// Where [`write_ensemble`] writes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum EnsembleOutput {
    /// One file per member in this directory (created if missing): `member-000000.parquet`,
    /// `member-000001.parquet`, … (six digits at least, so that names sort in member order),
    /// each recording its member's outcome ([`ParquetObserver::finish_with`]). Each is written
    /// under a hidden name and renamed when its member ends, so a killed ensemble leaves its
    /// finished members' files, complete; they are not synced one by one (many small files),
    /// so a crash of the machine itself may lose the last ones.
    PerMember(PathBuf),
    /// One file with a `member` column, members in input order. Members run in parallel, each
    /// into its own part next to `path` (`<path>.parts/`), and the parts are concatenated in
    /// order and removed: memory stays bounded by a row group per running member.
    OneFile(PathBuf),
}

/// Runs `steps` steps from each of `initials` in parallel (as [`Drive::ensemble`]) and
/// writes every member's states to Parquet as `output` says, with the writer options
/// `options(member)` (e.g. `|_| Options::new().every(10)`). Returns each member's run result, in
/// input order: a failed member keeps its typed error here (and in its file's metadata), the
/// others are unaffected. An I/O error ends the call.
///
/// A bar of members follows the ensemble on a terminal ([`progress`]).
pub fn write_ensemble<I>(
    integrator: &I,
    info: &RunInfo,
    initials: &[I::State],
    steps: usize,
    options: impl Fn(usize) -> Options<I::State> + Sync,
    output: &EnsembleOutput,
) -> Result<Vec<RunResult<I::State>>>
where
    I: Drive + Sync,
    I::State: StateColumns,
{
    let (dir, one_file) = match output {
        EnsembleOutput::PerMember(dir) => (dir.clone(), None),
        EnsembleOutput::OneFile(path) => {
            let mut parts = path.clone().into_os_string();
            parts.push(".parts");
            (PathBuf::from(parts), Some(path))
        }
    };
    std::fs::create_dir_all(&dir).map_err(Error::io(&dir))?;
    let bar = progress::bar(initials.len() as u64, "ensemble", "members");
    let members: Vec<usize> = (0..initials.len()).collect();
    let outcomes = map(&members, |&i| -> Result<RunResult<I::State>> {
        let initial = initials[i].clone();
        // The members occupy every core: each writes its own row groups.
        let mut member_options = options(i).background(false).member_file();
        if one_file.is_some() {
            member_options = member_options.member(i as u64);
        }
        let mut out = ParquetObserver::create(member_file(&dir, i), info.clone(), member_options)?;
        let result = integrator
            .run(initial)
            .steps(steps)
            .observe(out.observer())
            .stream();
        out.finish_with(&result)?;
        bar.inc(1);
        Ok(result)
    });
    bar.finish_and_clear();
    let results = outcomes.into_iter().collect::<Result<Vec<_>>>()?;
    if let Some(path) = one_file {
        let parts: Vec<PathBuf> = (0..initials.len()).map(|i| member_file(&dir, i)).collect();
        let mut kv = info.key_values();
        kv.push(("dirac.members".into(), initials.len().to_string()));
        publish(path, |partial| concatenate(&parts, partial, kv).map(drop))?;
        std::fs::remove_dir_all(&dir).map_err(Error::io(&dir))?;
    }
    Ok(results)
}
