//! A fleet as Parquet tables that DuckDB, Spark, Trino and DataFusion read
//! as they are (#31 item 5): `runs/`, `nodes/` and `transitions/`, each
//! partitioned Hive-style by robot and day (`robot=R/day=YYYY-MM-DD/`), so
//! that the partition columns come from the paths and a query of one robot
//! or one day reads only its files. A run's transitions are written while
//! the run is read; the two small tables once every run is summarised.

use super::partition::Partition;
use super::summary::RunSummary;
use super::Fleet;
use crate::run::Status;
use crate::session::Session;
use crate::source::Located;
use crate::table::Columns;
use parquet::basic::Compression;
use parquet::file::properties::WriterProperties;
use std::path::{Path, PathBuf};

/// The tables' schemas, as the Parquet files declare them.
pub const TRANSITIONS: &str = "message transition {
  REQUIRED BYTE_ARRAY run (UTF8);
  REQUIRED INT32 tick;
  REQUIRED INT32 step;
  OPTIONAL INT64 time_us;
  REQUIRED INT32 uid;
  REQUIRED BYTE_ARRAY node (UTF8);
  REQUIRED BYTE_ARRAY prev (UTF8);
  REQUIRED BYTE_ARRAY status (UTF8);
}";

pub const RUNS: &str = "message run {
  REQUIRED BYTE_ARRAY run (UTF8);
  REQUIRED BYTE_ARRAY tree (UTF8);
  REQUIRED INT32 ticks;
  REQUIRED INT64 transitions;
  OPTIONAL BYTE_ARRAY outcome (UTF8);
  REQUIRED BYTE_ARRAY ending (UTF8);
  OPTIONAL BYTE_ARRAY what_went_wrong (UTF8);
  REQUIRED INT32 gaps;
  OPTIONAL INT64 first_us;
  OPTIONAL INT64 last_us;
}";

pub const NODES: &str = "message node {
  REQUIRED BYTE_ARRAY run (UTF8);
  REQUIRED BYTE_ARRAY tree (UTF8);
  REQUIRED INT32 uid;
  REQUIRED BYTE_ARRAY node (UTF8);
  REQUIRED BYTE_ARRAY path (UTF8);
  REQUIRED BOOLEAN leaf;
  REQUIRED INT32 failures;
  REQUIRED INT32 recovered;
  REQUIRED INT32 unrecovered;
  REQUIRED INT32 running_spells;
  REQUIRED INT64 running_ticks;
}";

impl Partition {
    fn dir(&self, root: &Path, table: &str) -> PathBuf {
        root.join(table)
            .join(format!("robot={}", self.robot))
            .join(format!("day={}", self.day))
    }
}

/// Makes the export's directory: a new one, or an empty one (tables of
/// another export would be read with these as one).
pub fn create(dir: &Path) -> Result<(), Located> {
    if dir.exists() {
        let empty = std::fs::read_dir(dir)
            .map_err(|e| Located::file(dir, format!("cannot read the directory: {e}")))?
            .next()
            .is_none();
        if !empty {
            return Err(Located::file(
                dir,
                "already holds files: give a new or empty directory (DuckDB and Spark would read both exports as one)",
            ));
        }
    }
    std::fs::create_dir_all(dir)
        .map_err(|e| Located::file(dir, format!("cannot create the directory: {e}")))
}

/// Syncs every file written, then gives each its name (`X.parquet.part`
/// becomes `X.parquet`), then syncs the names: two syncs of the file system
/// for the whole export (a sync a file made `--export` 4.6× slower than
/// `btx fleet`), and a crash before the end leaves `.part` files, which
/// DuckDB and Spark do not read as the table's. The export's directory was
/// new or empty, so every `.part` in it is one of these; nothing is held
/// a file meanwhile. The files not named are said.
pub fn commit(root: &Path) -> Vec<String> {
    let mut said = Vec::new();
    if let Err(e) = sync_fs(root) {
        said.push(format!(
            "{}: cannot sync the export: {e}",
            crate::text::path(root)
        ));
        return said;
    }
    let mut dirs = vec![root.to_path_buf()];
    while let Some(d) = dirs.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            said.push(format!(
                "{}: cannot read the directory",
                crate::text::path(&d)
            ));
            continue;
        };
        for e in entries.flatten() {
            let p = e.path();
            match e.file_type() {
                Ok(t) if t.is_dir() => dirs.push(p),
                Ok(t) if t.is_file() && p.extension().is_some_and(|x| x == "part") => {
                    let path = p.with_extension("");
                    if let Err(e) = std::fs::rename(&p, &path) {
                        said.push(format!(
                            "{}: cannot write the Parquet file: {e}",
                            crate::text::path(&path)
                        ));
                    }
                }
                _ => {}
            }
        }
    }
    if let Err(e) = sync_fs(root) {
        said.push(format!(
            "{}: cannot sync the export: {e}",
            crate::text::path(root)
        ));
    }
    said
}

/// Syncs the file system that holds `dir` (syncfs(2)): every file and
/// directory written there reaches the disk.
fn sync_fs(dir: &Path) -> std::io::Result<()> {
    use std::os::unix::io::AsRawFd;
    let d = std::fs::File::open(dir)?;
    // SAFETY: syncfs on a descriptor we own; it touches no memory of ours.
    if unsafe { libc::syncfs(d.as_raw_fd()) } != 0 {
        return Err(std::io::Error::last_os_error());
    }
    Ok(())
}

/// The writer's properties: snappy, and no statistics of the text columns.
fn properties() -> WriterProperties {
    // A text column's min and max cost a comparison of every value (a
    // fifth of an export's time) and prune nothing in files of one run:
    // its name, its nodes' names, five statuses. Numbers keep theirs.
    let mut props = WriterProperties::builder().set_compression(Compression::SNAPPY);
    for text in ["run", "node", "prev", "status"] {
        props = props.set_column_statistics_enabled(
            parquet::schema::types::ColumnPath::from(text),
            parquet::file::properties::EnabledStatistics::None,
        );
    }
    // Ticks and times grow row by row, steps count up in a tick: a
    // dictionary of them interned every value. Their differences,
    // bit-packed (DELTA_BINARY_PACKED, read by DuckDB, Spark,
    // Trino and DataFusion alike), made the export 0.8× the time and a
    // sixth of the bytes.
    for rising in ["tick", "step", "time_us"] {
        let c = parquet::schema::types::ColumnPath::from(rising);
        props = props
            .set_column_dictionary_enabled(c.clone(), false)
            .set_column_encoding(c, parquet::basic::Encoding::DELTA_BINARY_PACKED);
    }
    props.build()
}

/// Creates `path`'s `.part` file, its directory first.
fn create_part(path: &Path, schema: &str) -> Result<crate::table::Writer, Located> {
    let failed =
        |e: std::io::Error| Located::file(path, format!("cannot write the Parquet file: {e}"));
    if let Some(d) = path.parent() {
        std::fs::create_dir_all(d).map_err(failed)?;
    }
    crate::table::Writer::create(
        path,
        &path.with_extension("parquet.part"),
        schema,
        properties(),
    )
}

/// One Parquet file of one row group, its columns written by `columns` in
/// the schema's order, beside its place: `commit` names it.
fn write(
    path: &Path,
    schema: &str,
    columns: impl FnOnce(&mut Columns) -> parquet::errors::Result<()>,
) -> Result<(), Located> {
    let mut w = create_part(path, schema)?;
    let done = w
        .row_group(columns)
        .and_then(|()| w.close_unsynced().map(drop));
    if done.is_err() {
        // Half a file is never named.
        let _ = std::fs::remove_file(path.with_extension("parquet.part"));
    }
    done
}

/// The export's files of runs' rows (the transitions and nodes tables),
/// open while the fleet is read: each run's rows are a row group of a
/// file of its partition that no other core is writing, so that a
/// partition has a file a core, not a file a run (creating 1,840 files
/// was a quarter of an export's time).
pub struct Files {
    root: PathBuf,
    free: std::sync::Mutex<std::collections::HashMap<(&'static str, Partition), Vec<Open>>>,
    made: std::sync::atomic::AtomicUsize,
}

/// A file being written, and the runs it holds.
struct Open {
    path: PathBuf,
    w: crate::table::Writer,
    runs: Vec<String>,
}

impl Files {
    pub fn new(root: &Path) -> Files {
        Files {
            root: root.to_path_buf(),
            free: Default::default(),
            made: Default::default(),
        }
    }

    /// Writes `run`'s rows of `table` as a row group of one of its
    /// partition's files. Where that fails, the file is given up, and the
    /// error names every run whose rows it held.
    fn row_group(
        &self,
        table: &'static str,
        schema: &str,
        at: &Partition,
        run: &str,
        columns: impl FnOnce(&mut Columns) -> parquet::errors::Result<()>,
    ) -> Result<(), Located> {
        let key = (table, at.clone());
        let taken = self.lock().get_mut(&key).and_then(Vec::pop);
        let mut open = match taken {
            Some(open) => open,
            None => {
                let k = self.made.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let path = at
                    .dir(&self.root, table)
                    .join(format!("part-{k:05}.parquet"));
                let w = create_part(&path, schema)?;
                Open {
                    path,
                    w,
                    runs: Vec::new(),
                }
            }
        };
        match open.w.row_group(columns) {
            Ok(()) => {
                open.runs.push(run.to_string());
                self.lock().entry(key).or_default().push(open);
                Ok(())
            }
            Err(e) => {
                let _ = std::fs::remove_file(open.path.with_extension("parquet.part"));
                let mut lost = open.runs;
                lost.push(run.to_string());
                Err(Located::file(
                    &open.path,
                    format!("{} (the rows of {})", e.message, lost.join(", ")),
                ))
            }
        }
    }

    fn lock(
        &self,
    ) -> std::sync::MutexGuard<'_, std::collections::HashMap<(&'static str, Partition), Vec<Open>>>
    {
        self.free.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Writes every file's footer: what could not be written is said.
    pub fn close(self) -> Vec<String> {
        let open = self.free.into_inner().unwrap_or_else(|e| e.into_inner());
        let mut said = Vec::new();
        for open in open.into_values().flatten() {
            if let Err(e) = open.w.close_unsynced() {
                let _ = std::fs::remove_file(open.path.with_extension("parquet.part"));
                said.push(format!("{e} (the rows of {})", open.runs.join(", ")));
            }
        }
        said
    }
}

/// A node's name as the fleet's rows share it: made once for the whole
/// fleet, so that a row takes it without counting its users (a count
/// kept a row was a tenth of an export's time). What is kept is bounded
/// by the names of the fleet's trees, not by its runs.
fn shared(name: &str) -> parquet::data_type::ByteArray {
    static NAMES: std::sync::Mutex<Option<std::collections::HashSet<&'static str>>> =
        std::sync::Mutex::new(None);
    let mut names = NAMES.lock().unwrap_or_else(|e| e.into_inner());
    let names = names.get_or_insert_with(Default::default);
    let kept: &'static str = match names.get(name) {
        Some(&k) => k,
        None => {
            let k: &'static str = Box::leak(name.to_string().into_boxed_str());
            names.insert(k);
            k
        }
    };
    parquet::data_type::ByteArray::from(bytes::Bytes::from_static(kept.as_bytes()))
}

/// Writes a run's transitions.
pub fn transitions(files: &Files, at: &Partition, run: &str, s: &Session) -> Result<(), Located> {
    let ts = &s.index.transitions;
    let mut steps = Vec::with_capacity(ts.len());
    let mut last = (0, 0);
    for t in ts {
        last = if t.tick == last.0 {
            (t.tick, last.1 + 1)
        } else {
            (t.tick, 1)
        };
        steps.push(last.1);
    }
    // Indexed by uid - 1, then the run's name; statuses by their code.
    let mut names: Vec<_> = (1..=s.tree.len() as u32)
        .map(|u| shared(&s.tree.spoken(u)))
        .collect();
    names.push(parquet::data_type::ByteArray::from(run.as_bytes().to_vec()));
    // Static text is shared without counting its users: a count kept for
    // each row was a fifth of an export's time.
    let statuses: Vec<_> = (0..=4)
        .map(|c| {
            let name = Status::from_code(c).map_or("", Status::as_str);
            parquet::data_type::ByteArray::from(bytes::Bytes::from_static(name.as_bytes()))
        })
        .collect();
    let code = |st: Status| usize::from(st.code());
    let timed = s.times_us.len() == ts.len();
    files.row_group("transitions", TRANSITIONS, at, run, |c| {
        c.shared_strings(&names, ts.iter().map(|_| names.len() - 1))?;
        c.ints(ts.iter().map(|t| Some(t.tick as i32)))?;
        c.ints(steps.iter().map(|&k| Some(k)))?;
        c.longs((0..ts.len()).map(|i| timed.then(|| s.times_us[i])))?;
        c.ints(ts.iter().map(|t| Some(t.uid as i32)))?;
        c.shared_strings(&names, ts.iter().map(|t| (t.uid - 1) as usize))?;
        c.shared_strings(&statuses, ts.iter().map(|t| code(t.prev)))?;
        c.shared_strings(&statuses, ts.iter().map(|t| code(t.status)))
    })
}

/// Writes the runs table, one file a partition (the nodes table is
/// written a run at a time, `nodes`).
pub fn tables(root: &Path, fleet: &Fleet) -> Result<(), Located> {
    let mut parts: std::collections::BTreeMap<&Partition, Vec<&RunSummary>> = Default::default();
    for r in &fleet.runs {
        if let Some(p) = &r.partition {
            parts.entry(p).or_default().push(r);
        }
    }
    for (p, runs) in parts {
        let path = p.dir(root, "runs").join("runs.parquet");
        write(&path, RUNS, |c| {
            c.strings(runs.iter().map(|r| Some(r.name.as_str())))?;
            c.strings(runs.iter().map(|r| Some(r.tree.as_str())))?;
            c.ints(runs.iter().map(|r| Some(r.ticks as i32)))?;
            c.longs(runs.iter().map(|r| Some(r.transitions as i64)))?;
            c.strings(runs.iter().map(|r| r.outcome.map(|o| o.as_str())))?;
            c.strings(runs.iter().map(|r| Some(r.ending.as_str())))?;
            c.strings(runs.iter().map(|r| r.wrong.as_deref()))?;
            c.ints(runs.iter().map(|r| Some(r.gaps as i32)))?;
            c.longs(runs.iter().map(|r| r.span_us.map(|s| s.0)))?;
            c.longs(runs.iter().map(|r| r.span_us.map(|s| s.1)))
        })?;
    }
    Ok(())
}

/// Writes a run's rows of the nodes table (one row a node that ran), in
/// its partition, as the run is read: a fleet keeps no run's nodes.
pub fn nodes(files: &Files, at: &Partition, r: &RunSummary) -> Result<(), Located> {
    let rows = &r.nodes;
    files.row_group("nodes", NODES, at, &r.name, |c| {
        c.strings(rows.iter().map(|_| Some(r.name.as_str())))?;
        c.strings(rows.iter().map(|_| Some(r.tree.as_str())))?;
        c.ints(rows.iter().map(|n| Some(n.uid as i32)))?;
        c.strings(rows.iter().map(|n| Some(n.spoken.as_str())))?;
        c.strings(rows.iter().map(|n| Some(n.path.as_str())))?;
        c.bools(rows.iter().map(|n| n.leaf))?;
        c.ints(rows.iter().map(|n| Some(n.failures as i32)))?;
        c.ints(
            rows.iter()
                .map(|n| Some(n.recoveries.iter().filter(|r| r.is_some()).count() as i32)),
        )?;
        c.ints(
            rows.iter()
                .map(|n| Some(n.recoveries.iter().filter(|r| r.is_none()).count() as i32)),
        )?;
        c.ints(rows.iter().map(|n| Some(n.running.len() as i32)))?;
        c.longs(
            rows.iter()
                .map(|n| Some(n.running.iter().map(|&d| i64::from(d)).sum())),
        )
    })
}
