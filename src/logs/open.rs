//! Each kind of log opened as a session: a `.btlog`, a live robot, a
//! `.db3`, a rosbag (run by run), an `.fbl`, with the tree given or the
//! one the log embeds.

use super::numbered::*;
use super::*;
use crate::run::Status;
use crate::session::Session;
use crate::source::{Located, Warning};
use std::path::{Path, PathBuf};

/// A `.btlog` as a session: the tree from its XML, ticks reconstructed.
pub fn open_btlog(path: &Path, bytes: &[u8]) -> Result<Session, Located> {
    btlog_session(path, bytes.len(), btlog::parse(path, bytes)?, None)
}

/// `open_btlog`, with the tree the robot ran in place of the log's; the
/// file's bytes are let go once parsed.
pub fn open_btlog_as(
    path: &Path,
    bytes: Vec<u8>,
    given: Option<GivenTree>,
) -> Result<Session, Located> {
    Ok(number_btlog(path, bytes, given)?.into_session())
}

/// A `.btlog` numbered into ticks, not indexed (see `Numbered`).
pub fn number_btlog(
    path: &Path,
    bytes: Vec<u8>,
    given: Option<GivenTree>,
) -> Result<Numbered, Located> {
    let raw = btlog::parse(path, &bytes)?;
    let len = bytes.len();
    drop(bytes);
    btlog_numbered(path, len, raw, given)
}

pub(super) fn btlog_session(
    path: &Path,
    len: usize,
    raw: btlog::RawLog,
    given: Option<GivenTree>,
) -> Result<Session, Located> {
    Ok(btlog_numbered(path, len, raw, given)?.into_session())
}

pub(super) fn btlog_numbered(
    path: &Path,
    len: usize,
    raw: btlog::RawLog,
    given: Option<GivenTree>,
) -> Result<Numbered, Located> {
    number(
        path,
        LogRun {
            len,
            partial_tail: raw.partial_tail,
            xml: &raw.xml,
            version: crate::model::Version::V4,
            records: Recs::Columns {
                cols: raw.records,
                first: raw.first,
                size: 9,
            },
            kind: "btlog",
            resyncs: &[],
            ticks: None,
            given,
            given_xml: None,
        },
        &|o| format!("byte offset {o}"),
    )
}

/// What a robot watched live speaks: BehaviorTree.CPP 4's Groot2
/// protocol, or BehaviorTree.CPP 3's `PublisherZMQ`, which Groot 1 watched.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Protocol {
    Groot2,
    Groot1,
}

impl Protocol {
    /// The format of the trees its robots run.
    pub fn version(self) -> crate::model::Version {
        match self {
            Protocol::Groot2 => crate::model::Version::V4,
            Protocol::Groot1 => crate::model::Version::V3,
        }
    }

    /// Its name, as a session's source names it.
    pub fn name(self) -> &'static str {
        match self {
            Protocol::Groot2 => "groot2",
            Protocol::Groot1 => "groot1",
        }
    }

    /// A robot at `endpoint` named as a source: `groot2://host:port`.
    pub fn source(self, endpoint: &str) -> PathBuf {
        PathBuf::from(format!("{}://{endpoint}", self.name()))
    }
}

/// A run received live (`crate::live`) as a session: the tree from the
/// server and ticks reconstructed, by the same code as a `.btlog`'s.
/// `name` names the endpoint in messages; a record's `offset` is its place
/// in the run; `resyncs`, the nodes' states read from the server and how
/// many records came before each: at 0 when the robot was running when
/// recording began, and after gaps.
pub fn open_live(
    protocol: Protocol,
    name: &Path,
    xml: &str,
    records: &[btlog::Record],
    resyncs: &[(usize, Vec<crate::session::Before>)],
) -> Result<Session, Located> {
    live_session(protocol, name, xml, records, None, resyncs)
}

/// `open_live` for records whose ticks are numbered already, as a live
/// run's are as they arrive (`ticks::Stream`).
pub fn open_live_numbered(
    protocol: Protocol,
    name: &Path,
    xml: &str,
    records: &[btlog::Record],
    ticks: &[u32],
    resyncs: &[(usize, Vec<crate::session::Before>)],
) -> Result<Session, Located> {
    live_session(protocol, name, xml, records, Some(ticks), resyncs)
}

pub(super) fn live_session(
    protocol: Protocol,
    name: &Path,
    xml: &str,
    records: &[btlog::Record],
    ticks: Option<&[u32]>,
    resyncs: &[(usize, Vec<crate::session::Before>)],
) -> Result<Session, Located> {
    let mut s = session_from(
        name,
        LogRun {
            len: records.len(),
            partial_tail: 0,
            xml,
            version: protocol.version(),
            records: Recs::Records(records.into()),
            kind: protocol.name(),
            resyncs,
            ticks,
            given: None,
            given_xml: None,
        },
        &|o| format!("transition {}", o + 1),
    )?;
    if let Some((0, before)) = resyncs.first() {
        s.header.before = before.clone();
    }
    Ok(s)
}

/// One session of a SqliteLogger database (`which`, or the last one).
pub fn open_db3(path: &Path, which: Option<i64>) -> Result<Session, Located> {
    open_db3_as(path, which, None)
}

/// `open_db3`, with the tree the robot ran in place of the log's.
pub fn open_db3_as(
    path: &Path,
    which: Option<i64>,
    given: Option<GivenTree>,
) -> Result<Session, Located> {
    let (ids, mut raw) = db3::read(path, which)?;
    let id = raw.id;
    let mut s = session_from(
        path,
        LogRun {
            len: raw.records.len(),
            partial_tail: 0,
            xml: &raw.xml,
            version: crate::model::Version::V4,
            records: Recs::Records(std::mem::take(&mut raw.records).into()),
            kind: "db3",
            resyncs: &[],
            ticks: None,
            given,
            given_xml: None,
        },
        &|o| format!("table Transitions, session {id}, row {o}"),
    )?;
    for (uid, full) in &raw.nodes {
        if s.tree.get(*uid).is_none() {
            return Err(Located::file(
                path,
                format!(
                    "table Nodes, session {id}: uid {uid} ({full}) is not a node of the session's tree ({} nodes)",
                    s.tree.len()
                ),
            ));
        }
    }
    if ids.len() > 1 {
        s.warnings.push(Warning {
            location: crate::text::path(path),
            message: format!(
                "the database holds sessions {}; this is session {id} ({}); open another as {}#N",
                ids.iter()
                    .map(|x| x.to_string())
                    .collect::<Vec<_>>()
                    .join(", "),
                raw.date,
                path.display()
            ),
        });
    }
    Ok(s)
}

/// Nav2's `behavior_tree_log` in a rosbag2 bag, as the records of the
/// tree the robot ran (a bag holds none), and where each run (goal)
/// starts: a run becomes a session only when asked for.
pub struct BagRuns<'a> {
    path: PathBuf,
    given: GivenTree<'a>,
    /// The given tree's XML, written once for every run's header.
    xml: String,
    log: rosbag::BagRecords,
    starts: Vec<usize>,
}

impl<'a> BagRuns<'a> {
    pub fn read(path: &Path, given: Option<GivenTree<'a>>) -> Result<BagRuns<'a>, Located> {
        let Some(given) = given else {
            return Err(Located::file(
                path,
                "a rosbag holds no tree: give the tree the robot ran with --tree FILE (Nav2: the navigator's XML, bt_navigator's default_nav_to_pose_bt_xml, e.g. navigate_to_pose_w_replanning_and_recovery.xml)",
            ));
        };
        let mut log = rosbag::read(path, given.tree, given.topic)?;
        if log.records.is_empty() {
            return Err(Located::file(
                path,
                format!("{}: the topic holds no status change", log.topic),
            ));
        }
        let starts = rosbag::run_starts(log.records.iter());
        if let Some(cut) = log.cut.as_mut() {
            // Every run before the last ended (another started); the last
            // one did if its root completed before the cut.
            let roots: Vec<&crate::logs::btlog::Record> = log
                .records
                .iter_range(starts[starts.len() - 1], log.records.len())
                .filter(|r| r.uid == crate::model::Tree::ROOT)
                .collect();
            let done = |s: Status| matches!(s, Status::Success | Status::Failure);
            let mut root = roots.iter().rev();
            // BehaviorTree.CPP sets a finished tree back to IDLE.
            let ended = match (root.next(), root.next()) {
                (Some(a), _) if done(a.status) => true,
                (Some(a), Some(b)) => a.status == Status::Idle && done(b.status),
                _ => false,
            };
            let whole = starts.len() - 1 + usize::from(ended);
            cut.push_str(&format!("; {whole} of {} runs whole", starts.len()));
        }
        Ok(BagRuns {
            path: path.to_path_buf(),
            xml: crate::xml::to_v4_xml(given.tree),
            given,
            log,
            starts,
        })
    }

    /// How many runs the bag holds.
    pub fn len(&self) -> usize {
        self.starts.len()
    }

    pub fn is_empty(&self) -> bool {
        self.starts.is_empty()
    }

    /// Run `k` (from 1) as a session.
    pub fn session(&self, k: usize) -> Result<Session, Located> {
        let n = self.len();
        if k == 0 || k > n {
            return Err(Located::file(
                &self.path,
                format!("the bag holds runs 1 to {n}; there is no run {k} (`btx log BAG --runs --tree FILE` lists them)"),
            ));
        }
        let start = self.starts[k - 1];
        let end = self
            .starts
            .get(k)
            .copied()
            .unwrap_or(self.log.records.len());
        let topic = &self.log.topic;
        let mut s = session_from(
            &self.path,
            LogRun {
                len: end - start,
                partial_tail: 0,
                xml: "",
                version: self.given.tree.release,
                records: Recs::Records(self.log.records.range(start, end).into()),
                kind: "rosbag",
                resyncs: &[],
                ticks: None,
                given: Some(self.given),
                given_xml: Some(&self.xml),
            },
            &|o| format!("{topic}, status change {}", o + 1),
        )?;
        s.run = (n > 1).then_some((k, n));
        // Re-runs follow the release that recorded the bag, where it says.
        if let Some(r) = self.log.release {
            s.header.nav2 = Some(r);
        }
        for a in self.log.ambiguous.iter().chain(&self.log.cut) {
            s.warnings.push(Warning {
                location: crate::text::path(&self.path),
                message: a.clone(),
            });
        }
        Ok(s)
    }
}

/// Run `which` (from 1; the last when `None`) of a bag, saying the others.
pub fn open_rosbag(
    path: &Path,
    which: Option<usize>,
    given: Option<GivenTree>,
) -> Result<Session, Located> {
    let runs = BagRuns::read(path, given)?;
    let n = runs.len();
    let k = which.unwrap_or(n);
    let mut s = runs.session(k)?;
    if n > 1 {
        s.warnings.push(Warning {
            location: crate::text::path(path),
            message: format!(
                "the bag holds {n} runs (goals); this is run {k}; open another with --run N or {}#N",
                path.display()
            ),
        });
    }
    Ok(s)
}

/// A v3 `.fbl` as a session: the tree from its flatbuffer, ticks reconstructed.
pub fn open_fbl(path: &Path, bytes: &[u8]) -> Result<Session, Located> {
    open_fbl_as(path, bytes, None)
}

/// `open_fbl`, with the tree the robot ran in place of the log's.
pub fn open_fbl_as(
    path: &Path,
    bytes: &[u8],
    given: Option<GivenTree>,
) -> Result<Session, Located> {
    let raw = fbl::parse(path, bytes)?;
    let records: Vec<btlog::Record> = raw.records.iter().map(|(r, _)| *r).collect();
    session_from(
        path,
        LogRun {
            len: bytes.len(),
            partial_tail: raw.partial_tail,
            xml: &raw.xml,
            version: crate::model::Version::V3,
            records: Recs::Records(records.into()),
            kind: "fbl",
            resyncs: &[],
            ticks: None,
            given,
            given_xml: None,
        },
        &|o| format!("byte offset {o}"),
    )
}
