//! Nav2's `behavior_tree_log` topic as rosbag2 keeps it: a bag directory
//! (`metadata.yaml` and its storage files) or one storage file, SQLite
//! (`.db3`, tables `topics` and `messages`) or MCAP. Each message is a
//! `nav2_msgs/msg/BehaviorTreeLog`, the status changes of one tick, read
//! by the definition the bag carries (`cdr`). The bag holds no tree: the
//! caller gives the tree the robot ran. Every goal (the root starting
//! again after it stopped) is a run of its own.

mod changes;
mod chunk;
mod direct;
mod mcap_file;
mod pool;
mod sqlite;

use super::btlog::Record;
use super::cdr::{Definitions, Slot, SlotKind, Value};
use crate::model::{Tree, Uid};
use crate::run::Status;
use crate::source::Located;
pub use changes::Changes;
use mcap_file::*;
use sqlite::*;
use std::path::{Path, PathBuf};

/// The type of the topic's messages.
pub const LOG_TYPE: &str = "nav2_msgs/msg/BehaviorTreeLog";

/// Humble's `BehaviorTreeStatusChange` (no uid), for bags that carry no
/// definition (rosbag2 keeps them from Iron on); Jazzy's has `uint16 uid`
/// after `node_name`.
const HUMBLE: &str = "builtin_interfaces/Time timestamp\nBehaviorTreeStatusChange[] event_log\n====\nMSG: nav2_msgs/BehaviorTreeStatusChange\nbuiltin_interfaces/Time timestamp\nstring node_name\nstring previous_status\nstring current_status\n";
const JAZZY: &str = "builtin_interfaces/Time timestamp\nBehaviorTreeStatusChange[] event_log\n====\nMSG: nav2_msgs/BehaviorTreeStatusChange\nbuiltin_interfaces/Time timestamp\nstring node_name\nuint16 uid\nstring previous_status\nstring current_status\n";

/// MCAP's magic.
const MCAP_MAGIC: &[u8] = b"\x89MCAP0\r\n";

/// One status change as Nav2 published it.
#[derive(Debug, Clone, PartialEq)]
struct Change<'a> {
    time_us: i64,
    /// As the message carries them, UTF-8 unchecked until said.
    name: &'a [u8],
    uid: Option<u32>,
    prev: &'a [u8],
    now: &'a [u8],
}

/// What a bag holds of the tree's run: its records, read as they come.
#[derive(Debug, Clone)]
pub struct BagRecords {
    pub topic: String,
    pub records: Changes,
    /// Several nodes have a name a change gave (a bag without uids): said
    /// once.
    pub ambiguous: Option<String>,
    /// The Nav2 release that recorded it, where the bag says: its
    /// metadata's `ros_distro`, else Humble for messages without uids
    /// (Jazzy added them; a bag with uids may be Jazzy's or later).
    pub release: Option<crate::model::nav2::Release>,
    /// Where the bag could be read only in part (cut by a stopped
    /// recorder, or past `BAG_TRANSITIONS_MAX`), said as it is.
    pub cut: Option<String>,
}

/// The status changes read of one bag at most (32 bytes each, then the
/// session's index): past them the rest is said, not read.
pub const BAG_TRANSITIONS_MAX: usize = 10_000_000;

/// The fewest bytes a status change takes in a message: its time (8),
/// and three strings of a length (4) and a NUL each.
const CHANGE_BYTES_MIN: u64 = 23;

/// Whether `path` is a bag: a directory with `metadata.yaml`, an MCAP
/// file, or a SQLite file with rosbag2's tables.
pub fn is_bag(path: &Path) -> bool {
    if path.is_dir() {
        return path.join("metadata.yaml").is_file();
    }
    // Never opened when not a regular file: opening a FIFO waits for a
    // writer (the reader says what such a file is).
    if !std::fs::metadata(path).is_ok_and(|m| m.is_file()) {
        return false;
    }
    // SQLite keeps its schema on the first page: a database whose first
    // 64 KiB never name rosbag2's tables is not opened to ask (a
    // SqliteLogger's, followed, is read again and again).
    let mut head = Vec::with_capacity(1 << 16);
    let read = std::fs::File::open(path)
        .and_then(|f| std::io::Read::read_to_end(&mut std::io::Read::take(f, 1 << 16), &mut head));
    if read.is_err() {
        return false;
    }
    if head.starts_with(MCAP_MAGIC) {
        return true;
    }
    let names = |word: &[u8]| {
        head.windows(word.len())
            .any(|w| w.eq_ignore_ascii_case(word))
    };
    head.starts_with(super::db3::MAGIC)
        && names(b"topics")
        && names(b"messages")
        && is_rosbag_db3(path)
}

/// A SQLite file with rosbag2's `topics` and `messages` tables (a
/// SqliteLogger's has `Transitions`, `Nodes` and `Definitions`).
fn is_rosbag_db3(path: &Path) -> bool {
    let Ok((conn, _copy)) = super::db3::open_schema(path) else {
        return false;
    };
    ["topics", "messages"].iter().all(|t| {
        conn.query_row(
            "SELECT count(*) FROM sqlite_master WHERE type = 'table' AND name = ?1",
            [t],
            |r| r.get::<_, i64>(0),
        )
        .is_ok_and(|n| n > 0)
    })
}

/// A storage file `metadata.yaml` names, which must be in the bag's own
/// folder: a name absolute, climbing out (`..`), or a link leading out is
/// refused, so a bag mailed around makes btx read nothing else.
fn inside(bag: &Path, name: &str) -> Result<PathBuf, Located> {
    let refuse = |why: &str| {
        Located::file(
            &bag.join("metadata.yaml"),
            format!(
                "relative_file_paths names {:?}, {why}: a bag's storage files are in its own folder",
                crate::text::visible(name)
            ),
        )
    };
    let rel = Path::new(name);
    if rel.is_absolute() {
        return Err(refuse("an absolute path"));
    }
    if rel.components().any(|c| {
        !matches!(
            c,
            std::path::Component::Normal(_) | std::path::Component::CurDir
        )
    }) {
        return Err(refuse("a path out of the bag's folder"));
    }
    let file = bag.join(rel);
    if let (Ok(real), Ok(home)) = (file.canonicalize(), bag.canonicalize()) {
        if !real.starts_with(&home) {
            return Err(refuse("a link out of the bag's folder"));
        }
    }
    Ok(file)
}

/// The storage files of a bag, in the order rosbag2 wrote them.
fn storage_files(path: &Path) -> Result<Vec<PathBuf>, Located> {
    if !path.is_dir() {
        return Ok(vec![path.to_path_buf()]);
    }
    let meta = std::fs::read_to_string(path.join("metadata.yaml"))
        .map_err(|e| Located::file(path, format!("metadata.yaml: {e}")))?;
    // `relative_file_paths:` then `- NAME` lines: the files in order.
    let mut files = Vec::new();
    let mut listing = false;
    for line in meta.lines() {
        let t = line.trim();
        if t.starts_with("relative_file_paths:") {
            listing = true;
            continue;
        }
        if listing {
            match t.strip_prefix("- ") {
                Some(name) => files.push(inside(path, name.trim().trim_matches(['"', '\'']))?),
                None if t.is_empty() => {}
                None => listing = false,
            }
        }
    }
    if files.is_empty() {
        let mut found: Vec<PathBuf> = std::fs::read_dir(path)
            .map_err(|e| Located::file(path, e.to_string()))?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "db3" || x == "mcap"))
            .collect();
        found.sort();
        files = found;
    }
    if files.is_empty() {
        return Err(Located::file(
            path,
            "metadata.yaml names no storage file, and the directory has no .db3 or .mcap",
        ));
    }
    Ok(files)
}

/// The `behavior_tree_log` topic as records of `tree`, in the bag's order.
/// `want` names the topic when the bag has several (`--topic`).
pub fn read(path: &Path, tree: &Tree, want: Option<&str>) -> Result<BagRecords, Located> {
    read_at_most(path, tree, want, BAG_TRANSITIONS_MAX, false).map(|(r, _)| r)
}

/// The bag read up to `max` changes, on this thread `alone` or else on
/// every core once its messages are known plain; with the pieces the
/// other threads read.
fn read_at_most(
    path: &Path,
    tree: &Tree,
    want: Option<&str>,
    max: usize,
    alone: bool,
) -> Result<(BagRecords, usize), Located> {
    let mut m = Matcher::new(path, tree);
    m.max = max;
    m.alone = alone;
    let mut topic = None;
    let mut cut = None;
    let files = storage_files(path)?;
    // Room for every change the files could hold, so that the records are
    // never moved as they grow: reserved, not touched, it costs no memory.
    let bytes: u64 = files
        .iter()
        .filter_map(|f| std::fs::metadata(f).ok())
        .map(|m| m.len())
        .sum();
    m.room = max.min((bytes / CHANGE_BYTES_MIN) as usize);
    for file in files {
        if !std::fs::metadata(&file).is_ok_and(|m| m.is_file()) {
            return Err(Located::file(
                &file,
                "a storage file of the bag that is not a regular file",
            ));
        }
        let (t, c) = if is_mcap(&file) {
            read_mcap(&file, &mut m, want)?
        } else {
            read_db3(&file, &mut m, want)?
        };
        topic.get_or_insert(t);
        // A bag's storage files follow each other: past a cut, or past
        // the bound, the rest is not the run's continuation.
        if let Some(c) = c.or_else(|| m.full().then(|| too_many(&m))) {
            cut = Some(c);
            break;
        }
    }
    let by_layout = (m.messages > 0 && !m.uids).then_some(crate::model::nav2::Release::Humble);
    let pieces = m.pieces;
    let records = BagRecords {
        topic: topic.unwrap_or_default(),
        ambiguous: m.said(),
        release: distro(path).or(by_layout),
        records: m.records,
        cut,
    };
    Ok((records, pieces))
}

/// The bag's `behavior_tree_log` topics, one robot's each, in the order
/// the bag names them: `btx fleet` and `btx import` read each as a robot.
pub fn log_topics(path: &Path) -> Result<Vec<String>, Located> {
    let mut logs: Vec<String> = Vec::new();
    for file in storage_files(path)? {
        let topics = if is_mcap(&file) {
            mcap_topics(&file)?
        } else {
            db3_topics(&file)?
        };
        for (n, t) in topics {
            if is_log(&n, &t) && !logs.contains(&n) {
                logs.push(n);
            }
        }
    }
    Ok(logs)
}

fn too_many(m: &Matcher) -> String {
    format!(
        "the bag holds more than {} status changes: btx read the first {} (to {}), not the rest",
        m.max,
        m.records.len(),
        m.records
            .last()
            .map_or(String::new(), |r| crate::clock::utc(r.time_us)),
    )
}

/// Said of a bag that ends in the middle of a record (its recorder was
/// stopped), or that cannot be read past a record, after the last change
/// read; `BagRuns` adds how many runs are whole.
fn cut_short(m: &Matcher, why: &str) -> String {
    let at = m
        .records
        .last()
        .map(|r| format!(" at {}", &crate::clock::utc(r.time_us)[11..]));
    // The reader asks for a record longer than what is left of the file.
    let cut = why.is_empty()
        || why.contains("in the middle of a record")
        || why.contains("exceeds limit");
    match (cut, at) {
        (true, Some(at)) => format!("the bag ends{at} in the middle of a record: a recorder stopped"),
        (true, None) => "the bag ends in the middle of a record, before any message of Nav2's log was whole: a recorder stopped".into(),
        (false, Some(at)) => format!("the bag cannot be read past its last whole record{at} ({why}): read up to there"),
        (false, None) => format!("the bag cannot be read ({why}) before any message of Nav2's log"),
    }
}

/// The `ros_distro` a bag directory's metadata names, if it is a Nav2
/// release btx knows.
fn distro(path: &Path) -> Option<crate::model::nav2::Release> {
    let meta = std::fs::read_to_string(path.join("metadata.yaml")).ok()?;
    meta.lines()
        .find_map(|l| l.trim().strip_prefix("ros_distro:"))
        .and_then(|d| crate::model::nav2::Release::parse(d.trim().trim_matches(['"', '\''])))
}

/// The namespace of a robot's log topic, without its slashes:
/// `/robot2/behavior_tree_log` is `robot2`, `/behavior_tree_log` empty.
pub fn namespace(topic: &str) -> &str {
    topic
        .strip_suffix("behavior_tree_log")
        .unwrap_or(topic)
        .trim_matches('/')
}

/// Whether a topic is Nav2's log: by its type, or by its name,
/// namespaced or not.
fn is_log(name: &str, ty: &str) -> bool {
    ty == LOG_TYPE || name == "behavior_tree_log" || name.ends_with("/behavior_tree_log")
}

/// The topic of Nav2's log among `(name, type)`: the one there is, or the
/// one `want` names. Two robots' logs are never read as one.
fn log_topic<'a>(
    path: &Path,
    topics: impl Iterator<Item = (&'a str, &'a str)>,
    want: Option<&str>,
) -> Result<String, Located> {
    let all: Vec<(&str, &str)> = topics.collect();
    let logs: Vec<&str> = all
        .iter()
        .filter(|(n, t)| is_log(n, t))
        .map(|(n, _)| *n)
        .collect();
    if let Some(w) = want {
        return match logs.iter().find(|n| **n == w) {
            Some(n) => Ok(n.to_string()),
            None => Err(Located::file(
                path,
                format!(
                    "the bag has no behavior_tree_log topic {w:?}; its behavior_tree_log topics: {}",
                    if logs.is_empty() {
                        "none".to_string()
                    } else {
                        logs.join(", ")
                    }
                ),
            )),
        };
    }
    match logs.as_slice() {
        [one] => Ok(one.to_string()),
        [] => Err(Located::file(
            path,
            format!(
                "the bag has no behavior_tree_log topic ({LOG_TYPE}); its topics: {}. Record Nav2's with `ros2 bag record /behavior_tree_log`",
                if all.is_empty() {
                    "none".to_string()
                } else {
                    all.iter().map(|(n, _)| *n).collect::<Vec<_>>().join(", ")
                }
            ),
        )),
        many => Err(several(path, many)),
    }
}

fn several(path: &Path, logs: &[&str]) -> Located {
    Located::file(
        path,
        format!(
            "the bag has {} behavior_tree_log topics ({}), one robot's each: pick one with --topic {}",
            logs.len(),
            logs.join(", "),
            logs[0]
        ),
    )
}

/// The definition to read the messages by: the bag's, or, when it carries
/// none (Humble), Humble's and else Jazzy's, whichever reads the first
/// message whole.
fn definitions(given: Option<&str>, first: Option<&[u8]>) -> Result<(Definitions, String), String> {
    if let Some(text) = given.filter(|t| !t.trim().is_empty()) {
        return Ok((Definitions::parse(LOG_TYPE, text)?, "the bag's".into()));
    }
    for (text, which) in [
        (HUMBLE, "Humble's (the bag carries none)"),
        (JAZZY, "Jazzy's (the bag carries none)"),
    ] {
        let d = Definitions::parse(LOG_TYPE, text)?;
        // The one that reads the first message whole, with statuses that
        // are statuses (a wrong one reads other bytes as strings).
        let fits = |b: &[u8]| {
            d.decode(b).is_ok_and(|v| {
                v.get("event_log").and_then(Value::list).is_some_and(|log| {
                    log.iter().all(|c| {
                        ["previous_status", "current_status"].iter().all(|f| {
                            c.get(f)
                                .and_then(Value::text)
                                .and_then(Status::parse)
                                .is_some()
                        })
                    })
                })
            })
        };
        if first.is_none_or(fits) {
            return Ok((d, which.into()));
        }
    }
    Err("the messages fit neither Humble's nor Jazzy's BehaviorTreeLog, and the bag carries no definition".into())
}

/// Each status change of one message, to `m`.
fn take_message(v: &Value, message: usize, m: &mut Matcher) -> Result<(), Located> {
    let log = v
        .get("event_log")
        .and_then(Value::list)
        .ok_or_else(|| m.at(message, "the message has no event_log".into()))?;
    for c in log {
        let missing = |f: &str| format!("a change without {f}");
        let t = c
            .get("timestamp")
            .ok_or_else(|| m.at(message, missing("timestamp")))?;
        let sec = t.get("sec").and_then(Value::int).unwrap_or(0);
        let nsec = t.get("nanosec").and_then(Value::int).unwrap_or(0);
        let text = |f: &str| {
            c.get(f)
                .and_then(Value::text)
                .ok_or_else(|| m.at(message, missing(f)))
        };
        let change = Change {
            time_us: sec.saturating_mul(1_000_000).saturating_add(nsec / 1000),
            name: text("node_name")?.as_bytes(),
            uid: c.get("uid").and_then(Value::int).map(|u| u as u32),
            prev: text("previous_status")?.as_bytes(),
            now: text("current_status")?.as_bytes(),
        };
        m.take(&change, message)?;
    }
    Ok(())
}

/// The name BehaviorTree.CPP gives a node: its instance name, else its ID.
fn bt_name(tree: &Tree, uid: Uid) -> &str {
    let n = tree.node(uid);
    if n.name.is_empty() {
        &n.id
    } else {
        &n.name
    }
}

/// Turns changes into the tree's records: by uid when the bag has them,
/// else by name. A name several nodes have is placed by their statuses
/// (the one whose status is the change's previous one) and then by the
/// tree's order: the first for a start (parents start before their
/// children), the last otherwise (children finish and halt before their
/// parents). The ambiguity is said once.
struct Matcher<'a> {
    path: &'a Path,
    /// The changes read at most (`BAG_TRANSITIONS_MAX`).
    max: usize,
    tree: &'a Tree,
    /// Each node's status after the changes up to `status_upto`, brought
    /// up to date only where a change is placed by name.
    status: Vec<Status>,
    status_upto: usize,
    names: std::collections::HashMap<Box<[u8]>, Vec<Uid>>,
    /// Each node's name as a change gives it (`bt_name`), by uid from 1.
    named: std::sync::Arc<[Box<[u8]>]>,
    records: Changes,
    /// Room for the changes the bag's bytes could hold.
    room: usize,
    /// One message's slots, or its plain changes, the buffers kept from
    /// message to message.
    slots: Vec<Slot>,
    plain: Vec<Record>,
    /// Messages read so far, and the first ambiguous name and its message.
    messages: usize,
    ambiguous: Option<(String, usize)>,
    /// Whether the changes carry uids (Jazzy's messages and later).
    uids: bool,
    /// Whether to read on this thread only; the pieces read on others.
    alone: bool,
    pieces: usize,
}

impl<'a> Matcher<'a> {
    fn new(path: &'a Path, tree: &'a Tree) -> Matcher<'a> {
        let mut names: std::collections::HashMap<Box<[u8]>, Vec<Uid>> = Default::default();
        for u in 1..=tree.len() as Uid {
            names
                .entry(bt_name(tree, u).as_bytes().into())
                .or_default()
                .push(u);
        }
        Matcher {
            path,
            max: BAG_TRANSITIONS_MAX,
            tree,
            status: vec![Status::Idle; tree.len()],
            status_upto: 0,
            names,
            named: (1..=tree.len() as Uid)
                .map(|u| bt_name(tree, u).as_bytes().into())
                .collect(),
            records: Changes::default(),
            room: 0,
            slots: Vec::new(),
            plain: Vec::new(),
            messages: 0,
            ambiguous: None,
            uids: false,
            alone: false,
            pieces: 0,
        }
    }

    /// Whether `max` changes are read.
    fn full(&self) -> bool {
        self.records.len() >= self.max
    }

    fn at(&self, message: usize, m: String) -> Located {
        Located::file(
            self.path,
            format!("behavior_tree_log message {message}: {m}"),
        )
    }

    /// The definition to read a topic's messages by (see `definitions`).
    fn definitions(
        &self,
        file: &Path,
        topic: &str,
        text: Option<&str>,
        first: Option<&[u8]>,
    ) -> Result<LogDefs, Located> {
        let defs = definitions(text, first)
            .map(|(d, _)| d)
            .map_err(|e| Located::file(file, format!("{topic}: {e}")))?;
        // Read flat where the changes' fields are where a change needs
        // them; else as a tree of values, which says what is missing.
        let flat = defs.flat("event_log", &CHANGE_PATHS).filter(|f| {
            let k = f.kinds();
            k[0] != SlotKind::Absent && [k[3], k[5], k[6]].iter().all(|&k| k == SlotKind::Text)
        });
        Ok(LogDefs {
            defs,
            direct: flat
                .as_ref()
                .and_then(direct::Direct::of)
                .map(std::sync::Arc::new),
            flat: flat.map(std::sync::Arc::new),
        })
    }

    /// One message's changes.
    fn message(&mut self, defs: &LogDefs, data: &[u8]) -> Result<(), Located> {
        self.messages += 1;
        let n = self.messages;
        let Some(flat) = &defs.flat else {
            let v = defs.defs.decode(data).map_err(|e| self.at(n, e))?;
            return take_message(&v, n, self);
        };
        if let Some(direct) = &defs.direct {
            let mut plain = std::mem::take(&mut self.plain);
            plain.clear();
            let read = direct.read(data, &self.named, &mut plain).is_some();
            for r in plain.iter().filter(|_| read) {
                self.uids = true;
                self.push(r.time_us, r.uid, r.status);
            }
            self.plain = plain;
            if read {
                return Ok(());
            }
        }
        let mut slots = std::mem::take(&mut self.slots);
        let taken = match flat.decode(data, &mut slots) {
            Ok(()) => slots
                .chunks_exact(CHANGE_PATHS.len())
                .try_for_each(|c| self.take(&change(c, data), n)),
            Err(e) => Err(self.at(n, e)),
        };
        self.slots = slots;
        taken
    }

    fn take(&mut self, c: &Change, message: usize) -> Result<(), Located> {
        if let Some((uid, now)) = plain(&self.named, c) {
            self.uids = true;
            self.push(c.time_us, uid, now);
            return Ok(());
        }
        let now = Status::parse_bytes(c.now).ok_or_else(|| {
            self.at(
                message,
                format!(
                    "the status \"{}\" is none BehaviorTree.CPP has",
                    said(c.now)
                ),
            )
        })?;
        self.uids |= c.uid.is_some();
        let uid = match c.uid {
            // A bag given another tree would be explained in that tree's
            // names: the names the bag carries must be the tree's.
            Some(u) if self.named.get((u as usize).wrapping_sub(1)).is_some_and(|n| **n != *c.name) => {
                return Err(self.at(
                    message,
                    format!(
                        "uid {u} is \"{}\" in the bag but \"{}\" in the tree given: is it the tree the robot ran?",
                        crate::text::visible(&said(c.name)),
                        crate::text::visible(bt_name(self.tree, u))
                    ),
                ))
            }
            Some(u) if self.tree.get(u).is_some() => u,
            Some(u) => {
                return Err(self.at(
                    message,
                    format!(
                        "uid {u} ({}) is not a node of the tree given ({} nodes): is it the tree the robot ran?",
                        said(c.name),
                        self.tree.len()
                    ),
                ))
            }
            None => {
                self.catch_up();
                let prev = Status::parse_bytes(c.prev).unwrap_or(Status::Idle);
                let all = self.names.get(c.name).map_or(&[][..], Vec::as_slice);
                let fits: Vec<Uid> = all
                    .iter()
                    .copied()
                    .filter(|&u| self.status[u as usize - 1] == prev)
                    .collect();
                let pool = if fits.is_empty() { all.to_vec() } else { fits };
                let pick = if now == Status::Running {
                    pool.first()
                } else {
                    pool.last()
                };
                let Some(&u) = pick else {
                    return Err(self.at(
                        message,
                        format!(
                            "no node of the tree given is named \"{}\": is it the tree the robot ran?",
                            said(c.name)
                        ),
                    ));
                };
                if pool.len() > 1 && self.ambiguous.is_none() {
                    self.ambiguous = Some((said(c.name).into_owned(), message));
                }
                u
            }
        };
        self.push(c.time_us, uid, now);
        Ok(())
    }

    fn push(&mut self, time_us: i64, uid: Uid, status: Status) {
        let r = Record {
            time_us,
            uid,
            status,
            offset: self.records.len(),
        };
        self.records.push(r, self.room);
    }

    /// Each node's status brought up to the last change.
    fn catch_up(&mut self) {
        let (from, to) = (self.status_upto, self.records.len());
        for r in self.records.iter_range(from, to) {
            self.status[r.uid as usize - 1] = r.status;
        }
        self.status_upto = to;
    }

    /// A piece's records, read on another thread, message by message as
    /// `message` would have taken them.
    fn join(&mut self, read: pool::Read) {
        self.pieces += 1;
        let mut from = 0;
        for &end in &read.ends {
            if self.records.len() + from >= self.max {
                break;
            }
            self.messages += 1;
            self.uids |= end > from;
            from = end;
        }
        let mut records = read.records;
        records.truncate(from);
        self.records.append(records);
    }

    /// How pieces of the bag can be read on other threads, where its
    /// messages so far were plain: uids, and a flat layout.
    fn layout(&self, defs: &LogDefs, channel: u16) -> Option<pool::Layout> {
        if !self.uids || self.alone {
            return None;
        }
        Some(pool::Layout {
            flat: defs.flat.clone()?,
            direct: defs.direct.clone(),
            named: self.named.clone(),
            channel,
        })
    }

    fn said(&self) -> Option<String> {
        self.ambiguous.as_ref().map(|(name, message)| {
            format!(
                "the bag names nodes, not uids (Humble), and several nodes are named \"{name}\" (first at message {message}): each change is placed by the nodes' statuses and the tree's order"
            )
        })
    }
}

/// A change whose uid names the tree's node of its name, to a status
/// that is one: its node and status, as read on any thread. Any other is
/// placed by `Matcher::take`, which says what is wrong with it.
fn plain(named: &[Box<[u8]>], c: &Change) -> Option<(Uid, Status)> {
    let uid = c.uid?;
    let name = named.get((uid as usize).wrapping_sub(1))?;
    (**name == *c.name).then_some(())?;
    Some((uid, Status::parse_bytes(c.now)?))
}

/// A message's text as said: its bytes as UTF-8, any that are not
/// replaced, as a message read by its definition gives them.
fn said(text: &[u8]) -> std::borrow::Cow<'_, str> {
    String::from_utf8_lossy(text)
}

/// The change one item's slots hold (`CHANGE_PATHS`), of `message`.
fn change<'m>(c: &[Slot], message: &'m [u8]) -> Change<'m> {
    let (sec, nsec) = (c[1].int().unwrap_or(0), c[2].int().unwrap_or(0));
    Change {
        time_us: sec.saturating_mul(1_000_000).saturating_add(nsec / 1000),
        name: c[3].bytes(message),
        uid: c[4].int().map(|u| u as u32),
        prev: c[5].bytes(message),
        now: c[6].bytes(message),
    }
}

/// A change's fields a `Flat` reads, in slot order.
const CHANGE_PATHS: [&str; 7] = [
    "timestamp",
    "timestamp.sec",
    "timestamp.nanosec",
    "node_name",
    "uid",
    "previous_status",
    "current_status",
];

/// The definition a topic's messages are read by, and its flat layout
/// where it has one.
struct LogDefs {
    defs: Definitions,
    flat: Option<std::sync::Arc<super::cdr::Flat>>,
    /// Where the layout is Nav2's own: changes read without slots.
    direct: Option<std::sync::Arc<direct::Direct>>,
}

/// Where each run starts among the records: at the first, and wherever
/// the root starts again after it stopped (a new goal).
pub fn run_starts<'r>(records: impl IntoIterator<Item = &'r Record>) -> Vec<usize> {
    let mut starts = vec![0];
    let mut root = Status::Idle;
    for (i, r) in records.into_iter().enumerate() {
        if r.uid != Tree::ROOT {
            continue;
        }
        if i > 0 && r.status == Status::Running && root != Status::Running {
            starts.push(i);
        }
        root = r.status;
    }
    starts.dedup();
    starts
}

#[cfg(test)]
#[path = "../../../tests/common/rechunk.rs"]
mod rechunk;

#[cfg(test)]
mod tests {
    use super::rechunk::rechunked;
    use super::*;

    #[test]
    fn a_bag_is_read_up_to_its_bound_and_the_rest_said() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/rosbag");
        let tree = crate::xml::load_file(&dir.join("navigator.xml"), &Default::default())
            .unwrap()
            .tree;
        let bag = dir.join("two_goals");
        let whole = read(&bag, &tree, None).unwrap();
        assert!(whole.cut.is_none());
        // Read message by message: the message that reaches the bound is
        // read whole, and nothing after it.
        let (part, _) = read_at_most(&bag, &tree, None, 5, false).unwrap();
        assert_eq!(part.records.len(), 10);
        assert_eq!(part.records.range(0, 10), whole.records.range(0, 10));
        assert!(whole.records.len() > 10);
        let cut = part.cut.unwrap();
        assert!(
            cut.starts_with(
                "the bag holds more than 5 status changes: btx read the first 10 (to 20"
            ),
            "{cut}"
        );
        assert!(cut.ends_with("), not the rest"), "{cut}");
    }

    #[test]
    fn a_bag_read_on_every_core_is_read_as_on_one_thread() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/rosbag");
        let tree = crate::xml::load_file(&dir.join("navigator.xml"), &Default::default())
            .unwrap()
            .tree;
        let tmp = tempfile::tempdir().unwrap();
        let small = tmp.path().join("small.mcap");
        rechunked(&dir.join("two_goals/two_goals.mcap"), 100, true, &small);
        let bytes = std::fs::read(&small).unwrap();
        let said = |r: Result<(BagRecords, usize), Located>| match r {
            Ok((b, n)) => (Ok((b.records.range(0, b.records.len()), b.cut, b.topic)), n),
            Err(e) => (Err(e.to_string()), 0),
        };
        let mut pooled = 0;
        // Whole, bounded at messages of each piece, and cut anywhere.
        for len in (40..bytes.len()).step_by(97).chain([bytes.len()]) {
            let cut = tmp.path().join("cut.mcap");
            std::fs::write(&cut, &bytes[..len]).unwrap();
            for max in [3, 17, 40, BAG_TRANSITIONS_MAX] {
                let (alone, none) = said(read_at_most(&cut, &tree, None, max, true));
                let (together, n) = said(read_at_most(&cut, &tree, None, max, false));
                assert_eq!(none, 0);
                assert_eq!(alone, together, "{len} bytes, at most {max}");
                if len == bytes.len() && max == BAG_TRANSITIONS_MAX {
                    pooled = n;
                }
            }
        }
        // The whole bag read on every core: each chunk (a message each)
        // after the first of the log.
        let messages = mcap::MessageStream::new(&bytes).unwrap().count();
        if std::thread::available_parallelism().map_or(1, |n| n.get()) > 1 {
            assert_eq!(pooled, messages - 1);
        }
    }

    fn rec(uid: Uid, status: Status) -> Record {
        Record {
            time_us: 0,
            uid,
            status,
            offset: 0,
        }
    }

    #[test]
    fn every_goal_is_a_run() {
        use Status::*;
        let r = [
            rec(1, Running),
            rec(2, Running),
            rec(2, Success),
            rec(1, Success),
            rec(1, Idle),
            rec(1, Running),
            rec(2, Running),
        ];
        assert_eq!(run_starts(&r), vec![0, 5]);
        assert_eq!(run_starts(&r[..4]), vec![0]);
    }
}
