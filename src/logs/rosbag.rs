//! Nav2's `behavior_tree_log` topic as rosbag2 keeps it: a bag directory
//! (`metadata.yaml` and its storage files) or one storage file, SQLite
//! (`.db3`, tables `topics` and `messages`) or MCAP. Each message is a
//! `nav2_msgs/msg/BehaviorTreeLog`, the status changes of one tick, read
//! by the definition the bag carries (`cdr`). The bag holds no tree: the
//! caller gives the tree the robot ran. Every goal (the root starting
//! again after it stopped) is a run of its own.

use super::btlog::Record;
use super::cdr::{Definitions, Value};
use crate::model::{Tree, Uid};
use crate::run::Status;
use crate::source::Located;
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
pub struct Change {
    pub time_us: i64,
    pub name: String,
    pub uid: Option<u32>,
    pub prev: String,
    pub now: String,
    /// Which message of the topic it came in (from 1).
    pub message: usize,
}

/// What a bag holds of the tree's run.
#[derive(Debug, Clone)]
pub struct BagLog {
    pub topic: String,
    pub changes: Vec<Change>,
    /// How the messages were read (their definition, or the one assumed).
    pub definition: String,
}

/// Whether `path` is a bag: a directory with `metadata.yaml`, an MCAP
/// file, or a SQLite file with rosbag2's tables.
pub fn is_bag(path: &Path) -> bool {
    if path.is_dir() {
        return path.join("metadata.yaml").is_file();
    }
    let mut head = [0u8; 16];
    let n = std::fs::File::open(path)
        .and_then(|mut f| std::io::Read::read(&mut f, &mut head))
        .unwrap_or(0);
    if head[..n].starts_with(MCAP_MAGIC) {
        return true;
    }
    head[..n].starts_with(super::db3::MAGIC) && is_rosbag_db3(path)
}

/// A SQLite file with rosbag2's `topics` and `messages` tables (a
/// SqliteLogger's has `Transitions`, `Nodes` and `Definitions`).
fn is_rosbag_db3(path: &Path) -> bool {
    let Ok((conn, _copy)) = super::db3::open_read_only(path) else {
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
                Some(name) => files.push(path.join(name.trim().trim_matches(['"', '\'']))),
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

/// The `behavior_tree_log` topic's status changes, in the bag's order.
pub fn read(path: &Path) -> Result<BagLog, Located> {
    let mut out: Option<BagLog> = None;
    for file in storage_files(path)? {
        let part = if std::fs::File::open(&file)
            .and_then(|mut f| {
                let mut h = [0u8; 8];
                std::io::Read::read_exact(&mut f, &mut h).map(|()| h)
            })
            .is_ok_and(|h| h == MCAP_MAGIC)
        {
            read_mcap(&file)?
        } else {
            read_db3(&file)?
        };
        match out.as_mut() {
            None => out = Some(part),
            Some(o) => {
                let base = o.changes.last().map_or(0, |c| c.message);
                o.changes.extend(part.changes.into_iter().map(|mut c| {
                    c.message += base;
                    c
                }));
            }
        }
    }
    out.ok_or_else(|| Located::file(path, "the bag has no storage file"))
}

/// The topic of Nav2's log among `(name, type)`: `behavior_tree_log`,
/// namespaced or not.
fn log_topic<'a>(
    path: &Path,
    topics: impl Iterator<Item = (&'a str, &'a str)>,
) -> Result<String, Located> {
    let all: Vec<(&str, &str)> = topics.collect();
    let logs: Vec<&str> = all
        .iter()
        .filter(|(n, t)| *t == LOG_TYPE || n.ends_with("/behavior_tree_log"))
        .map(|(n, _)| *n)
        .collect();
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
        many => Err(Located::file(
            path,
            format!(
                "the bag has {} behavior_tree_log topics ({}): one robot per bag, please (split it with `ros2 bag convert`)",
                many.len(),
                many.join(", ")
            ),
        )),
    }
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
        if first.is_none_or(|b| d.decode(b).is_ok()) {
            return Ok((d, which.into()));
        }
    }
    Err("the messages fit neither Humble's nor Jazzy's BehaviorTreeLog, and the bag carries no definition".into())
}

/// The status changes of one message.
fn changes_of(v: &Value, message: usize) -> Result<Vec<Change>, String> {
    let log = v
        .get("event_log")
        .and_then(Value::list)
        .ok_or("the message has no event_log")?;
    log.iter()
        .map(|c| {
            let t = c.get("timestamp").ok_or("a change without a timestamp")?;
            let sec = t.get("sec").and_then(Value::int).unwrap_or(0);
            let nsec = t.get("nanosec").and_then(Value::int).unwrap_or(0);
            let text = |f: &str| {
                c.get(f)
                    .and_then(Value::text)
                    .map(str::to_string)
                    .ok_or(format!("a change without {f}"))
            };
            Ok(Change {
                time_us: sec.saturating_mul(1_000_000).saturating_add(nsec / 1000),
                name: text("node_name")?,
                uid: c.get("uid").and_then(Value::int).map(|u| u as u32),
                prev: text("previous_status")?,
                now: text("current_status")?,
                message,
            })
        })
        .collect()
}

fn read_db3(file: &Path) -> Result<BagLog, Located> {
    let fail = |m: String| Located::file(file, m);
    let sql = |what: &str, e: rusqlite::Error| fail(format!("{what}: {e}"));
    let (conn, _copy) = super::db3::open_read_only(file)?;
    let topics: Vec<(i64, String, String)> = {
        let mut st = conn
            .prepare("SELECT id, name, type FROM topics")
            .map_err(|e| sql("table topics", e))?;
        let rows = st
            .query_map([], |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?)))
            .map_err(|e| sql("table topics", e))?;
        rows.collect::<Result<_, _>>()
            .map_err(|e| sql("table topics", e))?
    };
    let topic = log_topic(
        file,
        topics.iter().map(|(_, n, t)| (n.as_str(), t.as_str())),
    )?;
    let id = topics.iter().find(|t| t.1 == topic).map_or(0, |t| t.0);
    // From Iron on, the bag keeps each type's definition.
    let definition: Option<String> = conn
        .query_row(
            "SELECT encoded_message_definition FROM message_definitions WHERE topic_type = ?1",
            [LOG_TYPE],
            |r| r.get(0),
        )
        .ok();
    let mut st = conn
        .prepare("SELECT data FROM messages WHERE topic_id = ?1 ORDER BY timestamp, id")
        .map_err(|e| sql("table messages", e))?;
    let rows = st
        .query_map([id], |r| r.get::<_, Vec<u8>>(0))
        .map_err(|e| sql("table messages", e))?;
    let mut data = Vec::new();
    for r in rows {
        data.push(r.map_err(|e| sql("table messages", e))?);
    }
    decode_all(
        file,
        topic,
        definition.as_deref(),
        &data,
        "table messages, row",
    )
}

fn read_mcap(file: &Path) -> Result<BagLog, Located> {
    let bytes = crate::source::read_input(file, crate::source::INPUT_SIZE_MAX, "the bag")?;
    let stream = mcap::MessageStream::new(&bytes)
        .map_err(|e| Located::file(file, format!("not a readable MCAP file: {e}")))?;
    let mut topic: Option<String> = None;
    let mut definition: Option<String> = None;
    let mut data = Vec::new();
    let mut topics: Vec<(String, String)> = Vec::new();
    for m in stream {
        let m = m.map_err(|e| Located::file(file, format!("MCAP: {e}")))?;
        let ty = m
            .channel
            .schema
            .as_ref()
            .map_or(String::new(), |s| s.name.clone());
        if !topics.iter().any(|(n, _)| *n == m.channel.topic) {
            topics.push((m.channel.topic.clone(), ty.clone()));
        }
        let is_log = ty == LOG_TYPE || m.channel.topic.ends_with("/behavior_tree_log");
        if !is_log {
            continue;
        }
        if topic.is_none() {
            topic = Some(m.channel.topic.clone());
            definition = m
                .channel
                .schema
                .as_ref()
                .filter(|s| s.encoding == "ros2msg")
                .map(|s| String::from_utf8_lossy(&s.data).into_owned());
        }
        if topic.as_deref() == Some(m.channel.topic.as_str()) {
            data.push(m.data.into_owned());
        }
    }
    let topic = match topic {
        Some(t) => t,
        None => log_topic(file, topics.iter().map(|(n, t)| (n.as_str(), t.as_str())))?,
    };
    decode_all(file, topic, definition.as_deref(), &data, "message")
}

fn decode_all(
    file: &Path,
    topic: String,
    definition: Option<&str>,
    data: &[Vec<u8>],
    place: &str,
) -> Result<BagLog, Located> {
    let (defs, which) = definitions(definition, data.first().map(Vec::as_slice))
        .map_err(|e| Located::file(file, format!("{topic}: {e}")))?;
    let mut changes = Vec::new();
    for (i, d) in data.iter().enumerate() {
        let v = defs
            .decode(d)
            .map_err(|e| Located::file(file, format!("{topic}: {place} {}: {e}", i + 1)))?;
        changes.extend(
            changes_of(&v, i + 1)
                .map_err(|e| Located::file(file, format!("{topic}: {place} {}: {e}", i + 1)))?,
        );
    }
    Ok(BagLog {
        topic,
        changes,
        definition: which,
    })
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

/// The changes as the tree's records: by uid when the bag has them, else
/// by name. A name several nodes have is placed by their statuses (the one
/// whose status is the change's previous one) and then by the tree's
/// order: the first for a start (parents start before their children),
/// the last otherwise (children finish and halt before their parents).
/// The second value says the ambiguity, once.
pub fn records(
    path: &Path,
    tree: &Tree,
    changes: &[Change],
) -> Result<(Vec<Record>, Option<String>), Located> {
    let mut status = vec![Status::Idle; tree.len()];
    let mut out = Vec::with_capacity(changes.len());
    let mut ambiguous: Option<(String, usize)> = None;
    let by_name = |name: &str| -> Vec<Uid> {
        (1..=tree.len() as Uid)
            .filter(|&u| bt_name(tree, u) == name)
            .collect()
    };
    let mut names: std::collections::HashMap<&str, Vec<Uid>> = std::collections::HashMap::new();
    for c in changes {
        let at = |m: String| {
            Located::file(
                path,
                format!("behavior_tree_log message {}: {m}", c.message),
            )
        };
        let now = Status::parse(&c.now).ok_or_else(|| {
            at(format!(
                "the status \"{}\" is none BehaviorTree.CPP has",
                c.now
            ))
        })?;
        let prev = Status::parse(&c.prev).unwrap_or(Status::Idle);
        let uid = match c.uid {
            Some(u) if tree.get(u).is_some() => u,
            Some(u) => {
                return Err(at(format!(
                    "uid {u} ({}) is not a node of the tree given ({} nodes): is it the tree the robot ran?",
                    c.name,
                    tree.len()
                )))
            }
            None => {
                let all = names.entry(c.name.as_str()).or_insert_with(|| by_name(&c.name));
                let fits: Vec<Uid> = all
                    .iter()
                    .copied()
                    .filter(|&u| status[u as usize - 1] == prev)
                    .collect();
                let pool = if fits.is_empty() { all.clone() } else { fits };
                let pick = if now == Status::Running {
                    pool.first()
                } else {
                    pool.last()
                };
                let Some(&u) = pick else {
                    return Err(at(format!(
                        "no node of the tree given is named \"{}\": is it the tree the robot ran?",
                        c.name
                    )));
                };
                if pool.len() > 1 && ambiguous.is_none() {
                    ambiguous = Some((c.name.clone(), c.message));
                }
                u
            }
        };
        status[uid as usize - 1] = now;
        out.push(Record {
            time_us: c.time_us,
            uid,
            status: now,
            offset: out.len(),
        });
    }
    let said = ambiguous.map(|(name, message)| {
        format!(
            "the bag names nodes, not uids (Humble), and several nodes are named \"{name}\" (first at message {message}): each change is placed by the nodes' statuses and the tree's order"
        )
    });
    Ok((out, said))
}

/// Where each run starts among the records: at the first, and wherever
/// the root starts again after it stopped (a new goal).
pub fn run_starts(records: &[Record]) -> Vec<usize> {
    let mut starts = vec![0];
    let mut root = Status::Idle;
    for (i, r) in records.iter().enumerate() {
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
mod tests {
    use super::*;

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
