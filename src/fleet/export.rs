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
use parquet::data_type::{ByteArray, Int32Type, Int64Type};
use parquet::file::properties::WriterProperties;
use rayon::prelude::*;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

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
    // A text column's min and max cost a comparison of every value and
    // prune nothing: a run's name, its nodes' names, five statuses. The
    // transitions' text is written by its places in a dictionary, with
    // none; the nodes table's is told here. Numbers keep theirs.
    let mut props = WriterProperties::builder().set_compression(Compression::SNAPPY);
    for text in ["run", "node", "prev", "status"] {
        props = props.set_column_statistics_enabled(
            parquet::schema::types::ColumnPath::from(text),
            parquet::file::properties::EnabledStatistics::None,
        );
    }
    // Ticks and times grow row by row: a dictionary of them interned
    // every value. Their differences, bit-packed (DELTA_BINARY_PACKED,
    // read by DuckDB, Spark, Trino and DataFusion alike), made the export
    // 0.8× the time and a sixth of the bytes.
    for rising in ["tick", "time_us"] {
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

/// Rows of one table waiting in a file for their row group: whole runs,
/// copied out of each run's session as it is read.
trait Rows: Default + Send {
    const TABLE: &'static str;
    const SCHEMA: &'static str;
    fn len(&self) -> usize;
    fn write(&self, c: &mut Columns) -> parquet::errors::Result<()>;
}

/// A row group's rows once this many are waiting: a row group a run (its
/// page headers, dictionaries and metadata, 19 column chunks a run) was
/// half of an export of 1,000 runs of 10,000 transitions.
const ROW_GROUP: usize = 1 << 16;

/// Rows waiting in all the files, a core's share: past it, the file
/// holding the most writes them (memory bounded by the cores, not by
/// the partitions nor the runs).
const WAITING_A_CORE: usize = 1 << 17;

/// The export's files of runs' rows (the transitions and nodes tables),
/// open while the fleet is read. A file belongs to a partition and is
/// written by one core at a time, so that a partition has a file a core,
/// not a file a run (creating 1,840 files was a quarter of an export's
/// time); its rows wait in it until they make a row group.
pub struct Files {
    root: PathBuf,
    made: AtomicUsize,
    waiting: AtomicUsize,
    transitions: Pool<Transitions>,
    nodes: Pool<Nodes>,
}

/// A table's files not being written, by partition.
type Pool<R> = Mutex<HashMap<Partition, Vec<Open<R>>>>;

/// A file being written, the runs it holds and the rows waiting in it.
struct Open<R> {
    path: PathBuf,
    w: crate::table::Writer,
    runs: Vec<String>,
    rows: R,
}

impl<R: Rows> Open<R> {
    /// Writes the waiting rows as a row group. Where that fails, the
    /// file is given up, and the error names every run it held.
    fn flush(&mut self) -> Result<(), Located> {
        if self.rows.len() == 0 {
            return Ok(());
        }
        let rows = std::mem::take(&mut self.rows);
        self.w.row_group(|c| rows.write(c)).map_err(|e| {
            let _ = std::fs::remove_file(self.path.with_extension("parquet.part"));
            Located::file(
                &self.path,
                format!("{} (the rows of {})", e.message, self.runs.join(", ")),
            )
        })
    }
}

fn lock<R>(pool: &Pool<R>) -> std::sync::MutexGuard<'_, HashMap<Partition, Vec<Open<R>>>> {
    pool.lock().unwrap_or_else(|e| e.into_inner())
}

impl Files {
    pub fn new(root: &Path) -> Files {
        Files {
            root: root.to_path_buf(),
            made: Default::default(),
            waiting: Default::default(),
            transitions: Default::default(),
            nodes: Default::default(),
        }
    }

    /// Adds `run`'s rows (`add`) to a file of `at`'s partition, writing a
    /// row group when enough wait.
    fn add<R: Rows>(
        &self,
        pool: &Pool<R>,
        at: &Partition,
        run: &str,
        add: impl FnOnce(&mut R),
    ) -> Result<(), Located> {
        let taken = lock(pool).get_mut(at).and_then(Vec::pop);
        let mut open = match taken {
            Some(open) => open,
            None => {
                let k = self.made.fetch_add(1, Ordering::Relaxed);
                let path = at
                    .dir(&self.root, R::TABLE)
                    .join(format!("part-{k:05}.parquet"));
                Open {
                    w: create_part(&path, R::SCHEMA)?,
                    path,
                    runs: Vec::new(),
                    rows: R::default(),
                }
            }
        };
        let before = open.rows.len();
        add(&mut open.rows);
        open.runs.push(run.to_string());
        let added = open.rows.len() - before;
        let waiting = self.waiting.fetch_add(added, Ordering::Relaxed) + added;
        if open.rows.len() >= ROW_GROUP {
            self.waiting.fetch_sub(open.rows.len(), Ordering::Relaxed);
            open.flush()?;
        }
        lock(pool).entry(at.clone()).or_default().push(open);
        if waiting > WAITING_A_CORE * rayon::current_num_threads().max(1) {
            self.flush_fullest(pool)?;
        }
        Ok(())
    }

    /// Writes the rows of the file where most wait.
    fn flush_fullest<R: Rows>(&self, pool: &Pool<R>) -> Result<(), Located> {
        let fullest = {
            let mut pool = lock(pool);
            let at = pool
                .iter()
                .flat_map(|(at, opens)| {
                    opens
                        .iter()
                        .enumerate()
                        .map(move |(i, o)| (o.rows.len(), at, i))
                })
                .max_by_key(|&(n, _, _)| n)
                .map(|(_, at, i)| (at.clone(), i));
            at.map(|(at, i)| (at.clone(), pool.get_mut(&at).map(|v| v.swap_remove(i))))
        };
        let Some((at, Some(mut open))) = fullest else {
            return Ok(());
        };
        self.waiting.fetch_sub(open.rows.len(), Ordering::Relaxed);
        let done = open.flush();
        if done.is_ok() {
            lock(pool).entry(at).or_default().push(open);
        }
        done
    }

    /// Writes every file's waiting rows and footer, a core each: what
    /// could not be written is said.
    pub fn close(self) -> Vec<String> {
        fn close<R: Rows>(pool: Pool<R>) -> Vec<String> {
            let opens: Vec<Open<R>> = pool
                .into_inner()
                .unwrap_or_else(|e| e.into_inner())
                .into_values()
                .flatten()
                .collect();
            opens
                .into_par_iter()
                .filter_map(|mut open| {
                    if let Err(e) = open.flush() {
                        return Some(e.to_string());
                    }
                    open.w.close_unsynced().err().map(|e| {
                        let _ = std::fs::remove_file(open.path.with_extension("parquet.part"));
                        format!("{e} (the rows of {})", open.runs.join(", "))
                    })
                })
                .collect()
        }
        let mut said = close(self.transitions);
        said.extend(close(self.nodes));
        said
    }
}

/// A node's name as the fleet's rows share it: made once for the whole
/// fleet. What is kept is bounded by the names of the fleet's trees, not
/// by its runs.
fn shared(name: &str) -> &'static str {
    static NAMES: Mutex<Option<std::collections::HashSet<&'static str>>> = Mutex::new(None);
    let mut names = NAMES.lock().unwrap_or_else(|e| e.into_inner());
    let names = names.get_or_insert_with(Default::default);
    match names.get(name) {
        Some(&k) => k,
        None => {
            let k: &'static str = Box::leak(name.to_string().into_boxed_str());
            names.insert(k);
            k
        }
    }
}

fn text(s: &'static str) -> ByteArray {
    ByteArray::from(bytes::Bytes::from_static(s.as_bytes()))
}

/// Rows of the transitions table: the text columns as places in their
/// row group's dictionaries, which are written as they are (the parquet
/// crate's column writer would hash every row's text to find them).
#[derive(Default)]
struct Transitions {
    runs: Vec<ByteArray>,
    run: Vec<u32>,
    names: Vec<ByteArray>,
    named: HashMap<&'static str, u32>,
    tick: Vec<i32>,
    step: Vec<u32>,
    time_us: Vec<i64>,
    timed: Vec<i16>,
    uid: Vec<u32>,
    node: Vec<u32>,
    prev: Vec<u32>,
    status: Vec<u32>,
}

/// The statuses' text, by BehaviorTree.CPP's code.
fn statuses() -> [ByteArray; 5] {
    [0, 1, 2, 3, 4].map(|c| text(Status::from_code(c).map_or("", Status::as_str)))
}

impl Transitions {
    /// Room for `n` rows at once, where growing by doubling copied each
    /// column four times a row group.
    fn reserve(&mut self, n: usize) {
        self.run.reserve(n);
        self.tick.reserve(n);
        self.step.reserve(n);
        self.time_us.reserve(n);
        self.timed.reserve(n);
        self.uid.reserve(n);
        self.node.reserve(n);
        self.prev.reserve(n);
        self.status.reserve(n);
    }

    fn push(&mut self, run: &str, s: &Session) {
        let ts = &s.index.transitions;
        if self.run.is_empty() {
            // Rows are written once they reach a row group, so the run
            // that crosses it lands past it: room for it too, or each
            // column is copied to twice its size once a row group.
            self.reserve(ts.len() + ROW_GROUP);
        }
        let r = self.runs.len() as u32;
        self.runs.push(ByteArray::from(run.as_bytes().to_vec()));
        // Each uid's place in the names' dictionary.
        let place: Vec<u32> = (1..=s.tree.len() as u32)
            .map(|u| {
                let name = shared(&s.tree.spoken(u));
                *self.named.entry(name).or_insert_with(|| {
                    self.names.push(text(name));
                    self.names.len() as u32 - 1
                })
            })
            .collect();
        let timed = s.times_us.len() == ts.len();
        // A column at a time: each loop is one idea the compiler makes
        // fast, where one loop pushing nine columns was a tenth of an
        // export.
        self.run.extend(ts.iter().map(|_| r));
        self.tick.extend(ts.iter().map(|t| t.tick as i32));
        let mut last = (0, 0);
        self.step.extend(ts.iter().map(|t| {
            last = (t.tick, if t.tick == last.0 { last.1 + 1 } else { 0 });
            last.1
        }));
        if timed {
            self.time_us.extend_from_slice(&s.times_us);
        }
        self.timed.extend(ts.iter().map(|_| i16::from(timed)));
        self.uid.extend(ts.iter().map(|t| t.uid - 1));
        self.node
            .extend(ts.iter().map(|t| place[(t.uid - 1) as usize]));
        self.prev
            .extend(ts.iter().map(|t| u32::from(t.prev.code())));
        self.status
            .extend(ts.iter().map(|t| u32::from(t.status.code())));
    }
}

impl Rows for Transitions {
    const TABLE: &'static str = "transitions";
    const SCHEMA: &'static str = TRANSITIONS;

    fn len(&self) -> usize {
        self.run.len()
    }

    fn write(&self, c: &mut Columns) -> parquet::errors::Result<()> {
        let statuses = statuses();
        // Uids count from 1: each is its place in 1..=the largest.
        let uids = counting(&self.uid);
        let steps = counting(&self.step);
        c.indexed(&self.runs, &self.run)?;
        c.values::<Int32Type>(&self.tick)?;
        c.indexed(&steps, &self.step)?;
        c.optional::<Int64Type>(&self.time_us, &self.timed)?;
        c.indexed(&uids, &self.uid)?;
        c.indexed(&self.names, &self.node)?;
        c.indexed(&statuses, &self.prev)?;
        c.indexed(&statuses, &self.status)
    }
}

/// 1, 2, … up to the largest place + 1: the dictionary of a column of
/// numbers counted from 1 (uids, steps), each row its number's place.
fn counting(places: &[u32]) -> Vec<i32> {
    (1..=places.iter().max().map_or(0, |&p| p + 1) as i32).collect()
}

/// Writes a run's transitions.
pub fn transitions(files: &Files, at: &Partition, run: &str, s: &Session) -> Result<(), Located> {
    files.add(&files.transitions, at, run, |rows| rows.push(run, s))
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

/// Rows of the nodes table: one a node that ran in a run, its counts
/// taken and its names shared (a copy of each run's nodes was a tenth of
/// an export's allocations).
#[derive(Default)]
struct Nodes {
    runs: Vec<(String, &'static str)>,
    rows: Vec<NodeRow>,
}

struct NodeRow {
    run: usize,
    uid: i32,
    spoken: &'static str,
    path: &'static str,
    leaf: bool,
    failures: i32,
    recovered: i32,
    unrecovered: i32,
    spells: i32,
    running: i64,
}

impl Rows for Nodes {
    const TABLE: &'static str = "nodes";
    const SCHEMA: &'static str = NODES;

    fn len(&self) -> usize {
        self.rows.len()
    }

    fn write(&self, c: &mut Columns) -> parquet::errors::Result<()> {
        let (runs, rows) = (&self.runs, &self.rows);
        c.strings(rows.iter().map(|n| Some(runs[n.run].0.as_str())))?;
        c.strings(rows.iter().map(|n| Some(runs[n.run].1)))?;
        c.ints(rows.iter().map(|n| Some(n.uid)))?;
        c.strings(rows.iter().map(|n| Some(n.spoken)))?;
        c.strings(rows.iter().map(|n| Some(n.path)))?;
        c.bools(rows.iter().map(|n| n.leaf))?;
        c.ints(rows.iter().map(|n| Some(n.failures)))?;
        c.ints(rows.iter().map(|n| Some(n.recovered)))?;
        c.ints(rows.iter().map(|n| Some(n.unrecovered)))?;
        c.ints(rows.iter().map(|n| Some(n.spells)))?;
        c.longs(rows.iter().map(|n| Some(n.running)))
    }
}

/// Writes a run's rows of the nodes table (one row a node that ran), in
/// its partition, as the run is read: a fleet keeps no run's nodes.
pub fn nodes(files: &Files, at: &Partition, r: &RunSummary) -> Result<(), Located> {
    files.add(&files.nodes, at, &r.name, |rows| {
        let run = rows.runs.len();
        rows.runs.push((r.name.clone(), shared(&r.tree)));
        rows.rows.extend(r.nodes.iter().map(|n| {
            let recovered = n.recoveries.iter().filter(|r| r.is_some()).count() as i32;
            NodeRow {
                run,
                uid: n.uid as i32,
                spoken: shared(&n.spoken),
                path: shared(&n.path),
                leaf: n.leaf,
                failures: n.failures as i32,
                recovered,
                unrecovered: n.recoveries.len() as i32 - recovered,
                spells: n.running.len() as i32,
                running: n.running.iter().map(|&d| i64::from(d)).sum(),
            }
        }))
    })
}
