//! The session as Apache Parquet (#31 item 3): the same header and records
//! as the JSON lines, a row each, in columns that compress to a fraction of
//! a `.btlog` and that DuckDB or Spark query as they are. A transition's
//! fields are columns of their own; every other record (decisions' own
//! lines, writes, gaps, re-reads of the states, inserts, the end) is its
//! JSON line, so nothing the JSON lines can say is lost either way. The
//! first row holds the header (the tree, the plan, the blackboard).
//! Statuses are BehaviorTree.CPP's codes, as in a `.btlog`: 0 IDLE,
//! 1 RUNNING, 2 SUCCESS, 3 FAILURE, 4 SKIPPED.

use super::format::{self, Record};
use super::sink::Sink;
use crate::run::Status;
use crate::source::Located;
use parquet::basic::{Compression, Encoding};
use parquet::data_type::{ByteArray, ByteArrayType, Int32Type, Int64Type};
use parquet::file::metadata::KeyValue;
use parquet::file::properties::WriterProperties;
use parquet::file::reader::{FileReader, SerializedFileReader};
use parquet::schema::types::ColumnPath;
use std::path::Path;

pub const SCHEMA: &str = "message btx_session {
  REQUIRED INT64 tick;
  REQUIRED INT64 step;
  OPTIONAL INT32 uid;
  OPTIONAL INT32 prev;
  OPTIONAL INT32 status;
  OPTIONAL BYTE_ARRAY decision (UTF8);
  OPTIONAL BYTE_ARRAY record (UTF8);
  OPTIONAL INT64 time_us;
}";

/// The key of the file's metadata that says it is a btx session, and its
/// format's version.
const KEY: &str = "btx.session";

/// Rows a row group: a reader holds one row group's columns at a time.
const ROWS: usize = 1 << 16;

/// Whether a file is Parquet (it begins and ends with `PAR1`).
pub fn is_parquet(bytes: &[u8]) -> bool {
    bytes.len() >= 12 && bytes.starts_with(b"PAR1") && bytes.ends_with(b"PAR1")
}

/// Whether the Parquet file at `path` is a btx session, by its footer
/// alone (a fleet's directory may also hold `btx fleet --export` tables).
pub fn is_session_file(path: &Path) -> bool {
    use std::io::{Read, Seek, SeekFrom};
    let footer = || -> std::io::Result<bool> {
        let mut f = std::fs::File::open(path)?;
        let mut tail = [0u8; 8];
        let len = f.seek(SeekFrom::End(0))?;
        if len < 12 {
            return Ok(false);
        }
        f.seek(SeekFrom::End(-8))?;
        f.read_exact(&mut tail)?;
        let size = u64::from(u32::from_le_bytes(tail[..4].try_into().expect("4 bytes")));
        if &tail[4..] != b"PAR1" || size + 12 > len || size > 64 << 20 {
            return Ok(false);
        }
        f.seek(SeekFrom::End(-8 - size as i64))?;
        let mut meta = vec![0; size as usize];
        f.read_exact(&mut meta)?;
        Ok(meta.windows(KEY.len()).any(|w| w == KEY.as_bytes()))
    };
    footer().unwrap_or(false)
}

/// Whether a path names a Parquet session to write (`.parquet`).
pub fn wanted(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("parquet"))
}

/// One row: the header or a record.
#[derive(Default)]
struct Rows {
    tick: Vec<i64>,
    step: Vec<i64>,
    uid: Vec<Option<i32>>,
    prev: Vec<Option<i32>>,
    status: Vec<Option<i32>>,
    decision: Vec<Option<String>>,
    time_us: Vec<Option<i64>>,
    record: Vec<Option<String>>,
}

impl Rows {
    fn push(&mut self, rec: &Record) {
        match rec {
            Record::Transition {
                tick,
                step,
                uid,
                from,
                to,
                decision,
                time_us,
            } => {
                self.time_us.push(*time_us);
                self.tick.push(i64::from(*tick));
                self.step.push(i64::from(*step));
                self.uid.push(Some(*uid as i32));
                self.prev.push(Some(i32::from(from.code())));
                self.status.push(Some(i32::from(to.code())));
                self.decision.push(decision.clone());
                self.record.push(None);
            }
            other => {
                let (tick, step) = place(other);
                self.other(
                    tick,
                    step,
                    serde_json::to_string(other).expect("records serialise"),
                );
            }
        }
    }

    fn other(&mut self, tick: u32, step: u32, json: String) {
        self.tick.push(i64::from(tick));
        self.step.push(i64::from(step));
        self.uid.push(None);
        self.prev.push(None);
        self.status.push(None);
        self.decision.push(None);
        self.time_us.push(None);
        self.record.push(Some(json));
    }

    fn len(&self) -> usize {
        self.tick.len()
    }

    fn write(&mut self, w: &mut crate::table::Writer) -> Result<(), Located> {
        let rows = std::mem::take(self);
        w.row_group(|c| {
            c.longs(rows.tick.into_iter().map(Some))?;
            c.longs(rows.step.into_iter().map(Some))?;
            c.ints(rows.uid.into_iter())?;
            c.ints(rows.prev.into_iter())?;
            c.ints(rows.status.into_iter())?;
            c.strings(rows.decision.iter().map(Option::as_deref))?;
            c.strings(rows.record.iter().map(Option::as_deref))?;
            c.longs(rows.time_us.into_iter())
        })
    }
}

/// A record's tick and step (the end's: its last tick, step 0).
fn place(rec: &Record) -> (u32, u32) {
    match rec {
        Record::Transition { tick, step, .. }
        | Record::Decision { tick, step, .. }
        | Record::Write { tick, step, .. }
        | Record::Insert { tick, step, .. }
        | Record::Gap { tick, step, .. }
        | Record::Resync { tick, step, .. } => (*tick, *step),
        Record::End { ticks, .. } => (*ticks, 0),
    }
}

fn properties() -> WriterProperties {
    let delta = |c: &str| ColumnPath::from(c);
    WriterProperties::builder()
        .set_compression(Compression::SNAPPY)
        .set_max_row_group_row_count(Some(ROWS))
        // Ticks and steps climb by small steps: deltas pack them in bits.
        .set_column_dictionary_enabled(delta("tick"), false)
        .set_column_encoding(delta("tick"), Encoding::DELTA_BINARY_PACKED)
        .set_column_dictionary_enabled(delta("step"), false)
        .set_column_encoding(delta("step"), Encoding::DELTA_BINARY_PACKED)
        .set_key_value_metadata(Some(vec![KeyValue::new(
            KEY.to_string(),
            format::FORMAT_VERSION.to_string(),
        )]))
        .build()
}

/// Writes the JSON-lines session at `jsonl` as Parquet at `part` (which
/// becomes `out`), as the JSON-lines reader hands it each record.
pub fn write_from_jsonl(jsonl: &Path, out: &Path, part: &Path) -> Result<(), Located> {
    let mut w = Writing {
        table: crate::table::Writer::create(out, part, SCHEMA, properties())?,
        rows: Rows::default(),
    };
    super::jsonl::jsonl_file(jsonl, &mut w)?;
    if w.rows.len() > 0 {
        w.rows.write(&mut w.table)?;
    }
    w.table.close()
}

/// A Parquet session being written, a row group at a time.
struct Writing {
    table: crate::table::Writer,
    rows: Rows,
}

impl Sink for Writing {
    fn header(
        &mut self,
        _path: &Path,
        text: &str,
        _header: format::Header,
        _err: super::sink::Locate,
    ) -> Result<(), Located> {
        self.rows.other(0, 0, text.to_string());
        Ok(())
    }

    fn record(
        &mut self,
        _nth: usize,
        rec: Record,
        _err: super::sink::Locate,
    ) -> Result<(), Located> {
        self.rows.push(&rec);
        if self.rows.len() == ROWS {
            self.rows.write(&mut self.table)?;
        }
        Ok(())
    }

    // What the reader warns of (a record cut off half way) is left out
    // of the copy as it is of the session.
    fn warn(&mut self, _location: String, _message: String) {}
}

/// Reads a Parquet session into `sink`, row by row: the header, then the
/// records. An error names the row (the header is row 1).
/// A row group's text columns (`decision`, `record`) decompress to at most
/// this: a row group is read whole, and what btx holds is bounded by it,
/// not by the file (a row group of btx's holds 65,536 rows).
pub const ROW_GROUP_TEXT_MAX: i64 = 256 << 20;

/// A Parquet session, from a file (read a row group at a time) or bytes.
pub fn read<R: parquet::file::reader::ChunkReader + 'static>(
    path: &Path,
    source: R,
    sink: &mut dyn Sink,
) -> Result<(), Located> {
    let bad = |e| unreadable(path, e);
    let r = SerializedFileReader::new(source).map_err(bad)?;
    let columns = our_columns(path, r.metadata())?;
    let mut nth = 0;
    for g in 0..r.num_row_groups() {
        let rg = r.get_row_group(g).map_err(bad)?;
        within_bound(path, &*rg, g, nth)?;
        read_group(path, &*rg, columns, &mut nth, sink)?;
    }
    if nth == 0 {
        return Err(Located::file(path, "the session is empty"));
    }
    Ok(())
}

/// Parquet's error, said for a session; a codec btx was built without is
/// named, with how to write the file again.
fn unreadable(path: &Path, e: parquet::errors::ParquetError) -> Located {
    let e = e.to_string();
    match e.split_once("Disabled feature at compile time: ") {
        Some((_, codec)) => Located::file(
            path,
            format!("a Parquet session compressed with {codec}, which btx does not read (it reads Snappy, zstd, gzip and LZ4): write it again with one of them, e.g. DuckDB's COPY … (FORMAT parquet, COMPRESSION zstd)"),
        ),
        None => Located::file(path, format!("not a readable Parquet session: {e}")),
    }
}

/// Whether the file is a btx session of a format this btx reads: its
/// number of columns.
fn our_columns(
    path: &Path,
    meta: &parquet::file::metadata::ParquetMetaData,
) -> Result<usize, Located> {
    let ours = meta
        .file_metadata()
        .key_value_metadata()
        .and_then(|kv| kv.iter().find(|k| k.key == KEY))
        .and_then(|k| k.value.clone());
    match ours.as_deref() {
        Some(v) if v == format::FORMAT_VERSION.to_string() => {}
        Some(v) => {
            return Err(Located::file(
                path,
                format!(
                    "session format {v} is not one this btx reads (it reads {})",
                    format::FORMAT_VERSION
                ),
            ))
        }
        None => {
            return Err(Located::file(
                path,
                "a Parquet file that is not a btx session (its metadata has no btx.session): btx reads the sessions it writes with --out RUN.parquet",
            ))
        }
    }
    // Files written before transitions kept their time have 7 columns.
    let columns = meta.file_metadata().schema_descr().num_columns();
    if columns != 7 && columns != 8 {
        return Err(Located::file(
            path,
            "a Parquet session of other columns than btx writes",
        ));
    }
    Ok(columns)
}

/// A row group's text columns are read whole: refused past their bound.
fn within_bound(
    path: &Path,
    rg: &dyn parquet::file::reader::RowGroupReader,
    g: usize,
    nth: usize,
) -> Result<(), Located> {
    for (i, name) in [(5, "decision"), (6, "record")] {
        let size = rg.metadata().column(i).uncompressed_size();
        if size > ROW_GROUP_TEXT_MAX {
            return Err(Located::file(
                path,
                format!(
                    "row group {} (from row {}): its {name} column is {} MiB decompressed, more than the {} MiB btx reads of a row group",
                    g + 1,
                    nth + 1,
                    size >> 20,
                    ROW_GROUP_TEXT_MAX >> 20
                ),
            ));
        }
    }
    Ok(())
}

/// The rows of a row group, each handed to the sink (the first row of the
/// file is the header); `nth` counts the rows read.
fn read_group(
    path: &Path,
    rg: &dyn parquet::file::reader::RowGroupReader,
    columns: usize,
    nth: &mut usize,
    sink: &mut dyn Sink,
) -> Result<(), Located> {
    let bad = |e| unreadable(path, e);
    let rows = rg.metadata().num_rows() as usize;
    let tick = crate::table::column::<Int64Type>(rg, 0, rows).map_err(bad)?;
    let step = crate::table::column::<Int64Type>(rg, 1, rows).map_err(bad)?;
    let uid = crate::table::column::<Int32Type>(rg, 2, rows).map_err(bad)?;
    let prev = crate::table::column::<Int32Type>(rg, 3, rows).map_err(bad)?;
    let status = crate::table::column::<Int32Type>(rg, 4, rows).map_err(bad)?;
    let decision = crate::table::column::<ByteArrayType>(rg, 5, rows).map_err(bad)?;
    let record = crate::table::column::<ByteArrayType>(rg, 6, rows).map_err(bad)?;
    let time_us = if columns == 8 {
        crate::table::column::<Int64Type>(rg, 7, rows).map_err(bad)?
    } else {
        vec![None; rows]
    };
    for i in 0..rows {
        *nth += 1;
        let n = *nth;
        let err = |m: String| Located::file(path, format!("row {n}: {m}"));
        // Bounded as a line of JSON lines is.
        for (v, name) in [(&decision[i], "decision"), (&record[i], "record")] {
            let len = v.as_ref().map_or(0, |b| b.len());
            if len > super::format::RECORD_MAX {
                return Err(err(format!(
                    "its {name} is {len} bytes, more than a record may be ({} MiB)",
                    super::format::RECORD_MAX >> 20
                )));
            }
        }
        let row = Row {
            tick: tick[i],
            step: step[i],
            uid: uid[i],
            prev: prev[i],
            status: status[i],
            decision: decision[i].as_ref(),
            record: record[i].as_ref(),
            time_us: time_us[i],
        };
        if n == 1 {
            let text = row.text(row.record, "record").map_err(&err)?;
            let h = super::jsonl::header(path, text, &err)?;
            sink.header(path, text, h, &err)?;
            continue;
        }
        let rec = row.record().map_err(&err)?;
        sink.record(n - 1, rec, &err)?;
    }
    Ok(())
}

/// One row as read.
struct Row<'a> {
    tick: Option<i64>,
    step: Option<i64>,
    uid: Option<i32>,
    prev: Option<i32>,
    status: Option<i32>,
    decision: Option<&'a ByteArray>,
    record: Option<&'a ByteArray>,
    time_us: Option<i64>,
}

impl<'a> Row<'a> {
    fn text(&self, v: Option<&'a ByteArray>, column: &str) -> Result<&'a str, String> {
        let v = v.ok_or_else(|| format!("no {column}"))?;
        std::str::from_utf8(v.data()).map_err(|_| format!("the {column} is not UTF-8"))
    }

    fn status(v: Option<i32>, column: &str) -> Result<Status, String> {
        v.and_then(|c| u8::try_from(c).ok())
            .and_then(Status::from_code)
            .ok_or_else(|| format!("{column} is not a status (0 to 4)"))
    }

    fn number(v: Option<i64>, column: &str) -> Result<u32, String> {
        v.and_then(|v| u32::try_from(v).ok())
            .ok_or_else(|| format!("{column} is not a number from 0 to {}", u32::MAX))
    }

    fn record(&self) -> Result<Record, String> {
        if self.record.is_some() {
            let json = self.text(self.record, "record")?;
            return format::parse_record(json).map_err(|e| format!("not a session record: {e}"));
        }
        let uid = self
            .uid
            .and_then(|u| u32::try_from(u).ok())
            .ok_or("a transition with no uid")?;
        Ok(Record::Transition {
            tick: Self::number(self.tick, "tick")?,
            step: Self::number(self.step, "step")?,
            uid,
            from: Self::status(self.prev, "prev")?,
            to: Self::status(self.status, "status")?,
            decision: self
                .decision
                .map(|_| self.text(self.decision, "decision").map(str::to_string))
                .transpose()?,
            time_us: self.time_us,
        })
    }
}
