//! Checksums: every Parquet file this crate writes records, in its key-value metadata, a hash of
//! its bytes before the footer and a hash of its `dirac.*` metadata, and the readers, the
//! comparison, [`merge`](crate::shard::merge) and the shards' skip-as-complete check them.
//!
//! The parquet crate writes no page checksums (its page headers carry no CRC), so the hash is
//! the crate's own, taken as the bytes go to the file (no second pass) with XXH3-64: 10–30 GB/s,
//! well above what a disk takes, and any single flipped bit, any change of a byte, changes it.
//!
//! | key | value |
//! | --- | --- |
//! | `dirac.checksum` | `xxh3-64:` and 16 hex digits: XXH3-64 (seed 0) of bytes `0 .. N` of the file |
//! | `dirac.checksum.bytes` | `N`: the file's bytes before its footer (the `PAR1` magic and every row group) |
//! | `dirac.checksum.metadata` | `xxh3-64:` and 16 hex digits: XXH3-64 of what a reader takes from the footer: the other `dirac.*` pairs, the columns' names and types, the row groups' rows and column chunks' offsets and sizes |
//!
//! A file's footer is its end: `N` = the file's length − 8 − the footer's length (the 4 bytes
//! before the final `PAR1`), so another tool checks a file with, in Python,
//! `xxhash.xxh3_64(open(f, "rb").read()[:N]).hexdigest()`. A truncated file has no footer and is
//! not read at all; a flipped byte in the data changes the first hash; one in the footer either
//! makes it undecodable, or changes the second hash, or changes nothing a reader takes from it
//! (e.g. the writer's name).

use std::collections::BTreeMap;
use std::fs::File;
use std::hash::Hasher as _;
use std::io::{BufWriter, Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use arrow_array::RecordBatch;
use arrow_schema::{Schema, SchemaRef};
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use parquet::arrow::ArrowWriter;
use parquet::basic::Compression;
use parquet::file::metadata::{KeyValue, RowGroupMetaData};
use parquet::file::properties::{EnabledStatistics, WriterProperties};
use twox_hash::XxHash3_64;

use crate::error::{Error, Result};

/// The size at which row groups are cut ([`crate::output::ROW_GROUP_BYTES`]).
pub use crate::output::ROW_GROUP_BYTES;

/// The key of the hash of the data bytes.
pub const CHECKSUM: &str = "dirac.checksum";
/// The key of the number of bytes the hash covers.
pub const CHECKSUM_BYTES: &str = "dirac.checksum.bytes";
/// The key of the hash of the `dirac.*` metadata.
pub const CHECKSUM_METADATA: &str = "dirac.checksum.metadata";
const ALGORITHM: &str = "xxh3-64";

fn digest_text(hash: u64) -> String {
    format!("{ALGORITHM}:{hash:016x}")
}

/// The hash of what a reader takes from the footer: the `dirac.*` pairs of `kv` other than the
/// checksum's own, in key order; the columns (name, type, nullability); and each row group's
/// rows and column chunks (offsets, sizes, value count, compression), where a changed byte would
/// otherwise rename a column or move a reader to other bytes without notice.
fn metadata_digest<'a>(
    kv: impl IntoIterator<Item = (&'a str, &'a str)>,
    schema: &Schema,
    groups: &[RowGroupMetaData],
) -> u64 {
    let sorted: BTreeMap<&str, &str> = kv
        .into_iter()
        .filter(|(k, _)| k.starts_with("dirac.") && !k.starts_with(CHECKSUM))
        .collect();
    let mut text = String::new();
    for (k, v) in sorted {
        text.push_str(&format!("{k}={v}\n"));
    }
    for f in schema.fields() {
        text.push_str(&format!(
            "column {} {} {}\n",
            f.name(),
            f.data_type(),
            f.is_nullable()
        ));
    }
    for g in groups {
        text.push_str(&format!("group {}\n", g.num_rows()));
        for c in g.columns() {
            text.push_str(&format!(
                "chunk {} {} {:?} {} {} {} {:?}\n",
                c.column_path(),
                c.data_page_offset(),
                c.dictionary_page_offset(),
                c.compressed_size(),
                c.uncompressed_size(),
                c.num_values(),
                c.compression()
            ));
        }
    }
    XxHash3_64::oneshot(text.as_bytes())
}

/// Writer properties for `f64` columns: plain encoding (a dictionary of distinct floats is as
/// large as the data and costs a hash per value), no statistics and no offset index: the
/// footer, which the writer holds until the file is closed, then grows by one column chunk's
/// metadata per column and row group and nothing else. Row groups are cut at [`ROW_GROUP_BYTES`]
/// or `max_rows` rows, whichever comes first.
pub(crate) fn writer_properties(
    compression: Compression,
    kv: Vec<(String, String)>,
    max_rows: usize,
) -> WriterProperties {
    WriterProperties::builder()
        .set_compression(compression)
        .set_dictionary_enabled(false)
        .set_statistics_enabled(EnabledStatistics::None)
        // A column chunk of a row group is one or a few pages: an index of their offsets
        // would only grow the footer.
        .set_offset_index_disabled(true)
        .set_max_row_group_row_count((max_rows < usize::MAX).then_some(max_rows))
        .set_max_row_group_bytes(Some(ROW_GROUP_BYTES))
        .set_key_value_metadata(Some(
            kv.into_iter().map(|(k, v)| KeyValue::new(k, v)).collect(),
        ))
        .build()
}

/// A writer that hashes every byte that goes through it.
pub(crate) struct Hashing<W> {
    inner: W,
    hasher: XxHash3_64,
    bytes: u64,
}

impl<W: Write> Write for Hashing<W> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.inner.write(buf)?;
        self.hasher.write(&buf[..n]);
        self.bytes += n as u64;
        Ok(n)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.inner.flush()
    }
}

/// A Parquet file being written: the Arrow writer over a hashing, buffered file, and the
/// key-value metadata it will carry (so that their hash can be taken when it is closed).
pub(crate) struct FileWriter {
    writer: ArrowWriter<Hashing<BufWriter<File>>>,
    kv: Vec<(String, String)>,
    schema: SchemaRef,
    path: PathBuf,
}

impl FileWriter {
    /// Creates (or truncates) the file at `path`: columns `schema`, pages compressed with
    /// `compression`, key-value metadata `kv`.
    pub(crate) fn create(
        path: &Path,
        schema: SchemaRef,
        compression: Compression,
        kv: Vec<(String, String)>,
    ) -> Result<Self> {
        Self::create_with_groups(path, schema, compression, kv, usize::MAX)
    }

    /// [`Self::create`] with row groups of at most `rows` rows (a part's row groups, which
    /// never exceed the part).
    pub(crate) fn create_with_groups(
        path: &Path,
        schema: SchemaRef,
        compression: Compression,
        kv: Vec<(String, String)>,
        rows: usize,
    ) -> Result<Self> {
        let file = File::create(path).map_err(Error::io(path))?;
        let sink = Hashing {
            inner: BufWriter::with_capacity(1 << 20, file),
            hasher: XxHash3_64::default(),
            bytes: 0,
        };
        let properties = writer_properties(compression, kv.clone(), rows);
        let writer = ArrowWriter::try_new(sink, schema.clone(), Some(properties))
            .map_err(Error::parquet(path))?;
        Ok(FileWriter {
            writer,
            kv,
            schema,
            path: path.to_owned(),
        })
    }

    /// The file written.
    pub(crate) fn path(&self) -> &Path {
        &self.path
    }

    /// Buffers `batch` (row groups are cut at the properties' size).
    pub(crate) fn write(&mut self, batch: &RecordBatch) -> Result<()> {
        self.writer.write(batch).map_err(Error::parquet(&self.path))
    }

    /// Writes what is buffered as one row group.
    pub(crate) fn flush(&mut self) -> Result<()> {
        self.writer.flush().map_err(Error::parquet(&self.path))
    }

    /// Adds a key-value pair to the metadata written with the footer.
    pub(crate) fn append(&mut self, key: String, value: String) {
        self.writer
            .append_key_value_metadata(KeyValue::new(key.clone(), value.clone()));
        self.kv.push((key, value));
    }

    /// Writes the last row group, the checksums and the footer; with `sync`, also syncs the file
    /// to disk (so that a rename after it publishes a complete file).
    pub(crate) fn close(mut self, sync: bool) -> Result<()> {
        let path = self.path.clone();
        self.flush()?;
        // Every byte before the footer, through the hasher.
        self.writer.sync().map_err(Error::io(&path))?;
        let sink = self.writer.inner();
        let (data, bytes) = (sink.hasher.finish(), sink.bytes);
        let meta = metadata_digest(
            self.kv.iter().map(|(k, v)| (k.as_str(), v.as_str())),
            &self.schema,
            self.writer.flushed_row_groups(),
        );
        for (k, v) in [
            (CHECKSUM, digest_text(data)),
            (CHECKSUM_BYTES, bytes.to_string()),
            (CHECKSUM_METADATA, digest_text(meta)),
        ] {
            self.writer
                .append_key_value_metadata(KeyValue::new(k.to_owned(), v));
        }
        // `into_inner` writes the footer.
        let file = self
            .writer
            .into_inner()
            .map_err(Error::parquet(&path))?
            .inner
            .into_inner()
            .map_err(|e| Error::io(&path)(e.into_error()))?;
        if sync {
            file.sync_all().map_err(Error::io(&path))?;
        }
        Ok(())
    }
}

/// What a check of a file's checksums found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Checked {
    /// Both hashes agree with the file's content.
    Sound,
    /// The file carries no checksum (written by another program, or by dirac-io before it wrote
    /// them): nothing could be checked.
    Unchecked,
}

/// Checks the checksums of the Parquet file at `path` (see the [module documentation](self)):
/// reads the file once. An error names the file and says what disagrees: a truncated file, a
/// changed byte, changed metadata.
pub fn verify(path: &Path) -> Result<Checked> {
    let mut file = File::open(path).map_err(Error::io(path))?;
    let len = file.metadata().map_err(Error::io(path))?.len();
    let corrupt = |what: String| Error::content(path, format!("checksum: {what}"));
    if len < 12 {
        return Err(corrupt(format!(
            "{len} bytes: not a complete Parquet file (truncated?)"
        )));
    }
    let mut tail = [0u8; 8];
    file.seek(SeekFrom::Start(len - 8))
        .and_then(|_| file.read_exact(&mut tail))
        .map_err(Error::io(path))?;
    if &tail[4..] != b"PAR1" {
        return Err(corrupt(
            "no Parquet footer at the end of the file (truncated, or not written to the end)"
                .into(),
        ));
    }
    let footer = u64::from(u32::from_le_bytes([tail[0], tail[1], tail[2], tail[3]]));
    let data_end = len.checked_sub(8 + footer).ok_or_else(|| {
        corrupt(format!(
            "a footer of {footer} bytes in a file of {len}: truncated or damaged"
        ))
    })?;
    let reader = File::open(path).map_err(Error::io(path))?;
    let builder = ParquetRecordBatchReaderBuilder::try_new(reader).map_err(Error::parquet(path))?;
    let kv: BTreeMap<String, String> = builder
        .metadata()
        .file_metadata()
        .key_value_metadata()
        .into_iter()
        .flatten()
        .filter_map(|kv| Some((kv.key.clone(), kv.value.clone()?)))
        .collect();
    let present = [CHECKSUM, CHECKSUM_BYTES, CHECKSUM_METADATA].map(|k| kv.contains_key(k));
    if present == [false; 3] {
        return Ok(Checked::Unchecked);
    }
    // One of the three missing: a damaged key (one flipped byte changes one key at most).
    let Some(expected) = kv.get(CHECKSUM) else {
        return Err(corrupt(format!(
            "{CHECKSUM_BYTES} and {CHECKSUM_METADATA} without {CHECKSUM}: the footer was damaged"
        )));
    };
    let covered: Option<u64> = kv.get(CHECKSUM_BYTES).and_then(|b| b.parse().ok());
    if covered != Some(data_end) {
        return Err(corrupt(format!(
            "{CHECKSUM_BYTES} = {} where the data end at byte {data_end}: truncated, extended or damaged",
            kv.get(CHECKSUM_BYTES).map_or("(missing)", String::as_str)
        )));
    }
    file.seek(SeekFrom::Start(0)).map_err(Error::io(path))?;
    let mut hasher = XxHash3_64::default();
    let mut reader = file.take(data_end);
    let mut buffer = vec![0u8; 1 << 20];
    loop {
        let n = reader.read(&mut buffer).map_err(Error::io(path))?;
        if n == 0 {
            break;
        }
        hasher.write(&buffer[..n]);
    }
    let found = digest_text(hasher.finish());
    if &found != expected {
        return Err(corrupt(format!(
            "the data hash to {found} where {expected} was written: the file was changed or damaged after it was written"
        )));
    }
    let meta = digest_text(metadata_digest(
        kv.iter().map(|(k, v)| (k.as_str(), v.as_str())),
        builder.schema(),
        builder.metadata().row_groups(),
    ));
    if kv.get(CHECKSUM_METADATA) != Some(&meta) {
        return Err(corrupt(format!(
            "the footer (metadata, columns, row groups) hashes to {meta} where {} was written: it was changed or damaged",
            kv.get(CHECKSUM_METADATA)
                .map_or("(missing)", String::as_str)
        )));
    }
    Ok(Checked::Sound)
}

/// [`verify`], requiring a checksum: a file without one is an error naming it.
pub fn verify_required(path: &Path) -> Result<()> {
    match verify(path)? {
        Checked::Sound => Ok(()),
        Checked::Unchecked => Err(Error::content(
            path,
            "checksum: none recorded (not written by this version of dirac-io), so its content cannot be trusted; rerun it",
        )),
    }
}
