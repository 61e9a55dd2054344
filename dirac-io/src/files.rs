//! Files published whole: each is written under a hidden name beside its final one and renamed
//! when complete (an atomic rename: a reader sees the whole file or none), so that a killed
//! process leaves only hidden partial files, which no reader takes (pyarrow skips names starting
//! with `.`, and they match no `*.parquet`). The names of a run's parts, of an ensemble's
//! members, and the publication itself, shared by the observer, the readers, ensembles and
//! shards.

use std::path::{Path, PathBuf};

use crate::error::{Error, Result};

/// The file of member `i` in a directory of per-member files.
pub fn member_file(dir: &Path, i: usize) -> PathBuf {
    dir.join(format!("member-{i:06}.parquet"))
}

/// The published part `index` of a directory of parts.
pub(crate) fn part_file(dir: &Path, index: usize) -> PathBuf {
    dir.join(format!("part-{index:05}.parquet"))
}

/// Whether `name` is a published part's (`part-NNNNN.parquet`), and its index.
pub(crate) fn part_index(name: &str) -> Option<usize> {
    let digits = name.strip_prefix("part-")?.strip_suffix(".parquet")?;
    (!digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit()))
        .then(|| digits.parse().ok())
        .flatten()
}

/// The hidden name a file is written under until it is published: `.<name>.partial` beside it.
/// Readers skip it: pyarrow skips names starting with `.` or `_`, and it matches no `*.parquet`.
pub(crate) fn partial_file(path: &Path) -> PathBuf {
    let name = path.file_name().unwrap_or_default().to_string_lossy();
    path.with_file_name(format!(".{name}.partial"))
}

/// Publishes the closed file `partial` as `path`: a rename (atomic: a reader sees the whole
/// file or none), and with `sync` the directory synced so that the rename survives a crash of
/// the machine (the file itself was synced before its rename by its writer's `close`).
pub(crate) fn publish_file(partial: &Path, path: &Path, sync: bool) -> Result<()> {
    std::fs::rename(partial, path).map_err(Error::io(path))?;
    if sync {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            if let Ok(d) = std::fs::File::open(dir) {
                d.sync_all().map_err(Error::io(dir))?;
            }
        }
    }
    Ok(())
}

/// The published parts of the directory `dir`, in order, and whether it holds hidden partial
/// files of parts.
pub(crate) fn published_parts(dir: &Path) -> Result<(Vec<PathBuf>, Vec<PathBuf>)> {
    let mut parts = Vec::new();
    let mut partials = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(Error::io(dir))? {
        let entry = entry.map_err(Error::io(dir))?;
        let name = entry.file_name().to_string_lossy().into_owned();
        if let Some(i) = part_index(&name) {
            parts.push((i, entry.path()));
        } else if name.starts_with(".part-") && name.ends_with(".parquet.partial") {
            partials.push(entry.path());
        }
    }
    parts.sort();
    if let Some((k, (i, _))) = parts.iter().enumerate().find(|(k, (i, _))| k != i) {
        return Err(Error::content(
            dir,
            format!("part {k} is missing (the parts jump to {i}): not one run's parts"),
        ));
    }
    Ok((parts.into_iter().map(|(_, p)| p).collect(), partials))
}

/// Writes a complete file at `path` atomically: `write` fills a partial file beside it (hidden,
/// named after this process), which is then renamed over `path`; the directory is synced so the
/// rename survives a crash.
pub fn publish(path: &Path, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path
        .file_name()
        .ok_or_else(|| Error::content(path, "not a file name"))?;
    let partial = dir.join(format!(
        ".{}.partial-{}",
        name.to_string_lossy(),
        std::process::id()
    ));
    let result = write(&partial);
    if result.is_err() {
        let _ = std::fs::remove_file(&partial);
        return result;
    }
    std::fs::rename(&partial, path).map_err(Error::io(path))?;
    if let Ok(d) = std::fs::File::open(dir) {
        let _ = d.sync_all();
    }
    Ok(())
}

/// Removes the partial files that killed attempts at `path` left (see [`publish`]).
pub(crate) fn remove_partials(path: &Path) -> Result<()> {
    let dir = path.parent().unwrap_or(Path::new("."));
    let prefix = format!(
        ".{}.partial-",
        path.file_name().unwrap_or_default().to_string_lossy()
    );
    for entry in std::fs::read_dir(dir).map_err(Error::io(dir))? {
        let entry = entry.map_err(Error::io(dir))?;
        if entry.file_name().to_string_lossy().starts_with(&prefix) {
            std::fs::remove_file(entry.path()).map_err(Error::io(entry.path()))?;
        }
    }
    Ok(())
}
