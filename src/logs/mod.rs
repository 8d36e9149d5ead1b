//! Logs that robots already write, opened as sessions.

pub mod btcm;
pub mod btlog;
mod cdr;
pub mod db3;
pub mod fbl;
pub mod rosbag;
pub mod ticks;

use crate::run::Status;
use crate::session::{format, Header, Index, Session, Source, Transition, TreeRef};
use crate::source::{Located, Warning};
use crate::xml::{load_str, LoadOptions};
use std::path::{Path, PathBuf};

/// The tree file a robot ran, given for a log whose embedded tree lost
/// what BehaviorTree.CPP does not write back (`_autoremap`, the
/// `<TreeNodesModel>`): checked against the log's tree, then used in its
/// place.
#[derive(Clone, Copy)]
pub struct GivenTree<'a> {
    pub tree: &'a crate::model::Tree,
    pub path: &'a Path,
    /// A bag's topic, when it has several (`--topic`).
    pub topic: Option<&'a str>,
}

impl GivenTree<'_> {
    /// The given tree, when it is the log's node for node, else an error
    /// naming the first nodes that differ.
    fn checked(
        &self,
        log: &Path,
        embedded: &crate::model::Tree,
    ) -> Result<crate::model::Tree, Located> {
        let diff = tree_mismatch(self.tree, embedded, 8);
        if diff.is_empty() {
            Ok(self.tree.clone())
        } else {
            Err(Located::file(
                log,
                format!(
                    "not a log of {} (--tree):\n  {}",
                    self.path.display(),
                    diff.join("\n  ")
                ),
            ))
        }
    }

    /// A session (btx's own, or read from a log) with the given tree in
    /// place of its own.
    pub fn put_in(&self, s: &mut Session) -> Result<(), Located> {
        s.tree = self.checked(&s.path, &s.tree)?;
        s.header.tree.path = Some(self.path.display().to_string());
        s.header.tree.xml = crate::xml::to_v4_xml(&s.tree);
        Ok(())
    }
}

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

fn btlog_session(
    path: &Path,
    len: usize,
    raw: btlog::RawLog,
    given: Option<GivenTree>,
) -> Result<Session, Located> {
    Ok(btlog_numbered(path, len, raw, given)?.into_session())
}

fn btlog_numbered(
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

fn live_session(
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
        let starts = rosbag::run_starts(&log.records);
        if let Some(cut) = log.cut.as_mut() {
            // Every run before the last ended (another started); the last
            // one did if its root completed before the cut.
            let last = &log.records[starts[starts.len() - 1]..];
            let done = |s: Status| matches!(s, Status::Success | Status::Failure);
            let mut root = last
                .iter()
                .filter(|r| r.uid == crate::model::Tree::ROOT)
                .rev();
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
                records: Recs::Records(self.log.records[start..end].into()),
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

/// What a log gave: its tree, its records, how much of its end was cut.
struct LogRun<'a> {
    /// The file's length, and the bytes at its end that are not a whole record.
    len: usize,
    partial_tail: usize,
    xml: &'a str,
    version: crate::model::Version,
    /// Owned where the caller gives them up: they are let go before the
    /// session is built (#31 item 1: 24 bytes a transition).
    records: Recs<'a>,
    kind: &'a str,
    /// The nodes' states read from the robot, after how many records (at
    /// 0: when recording began; none: all IDLE then).
    resyncs: &'a [(usize, Vec<crate::session::Before>)],
    /// The records' ticks when they are numbered already.
    ticks: Option<&'a [u32]>,
    /// The tree the robot ran, in place of the log's.
    given: Option<GivenTree<'a>>,
    /// That tree as the session's header writes it, where the caller made
    /// it once for many runs (a bag's).
    given_xml: Option<&'a str>,
}

/// A log's records: as its reader made them, or as columns (a `.btlog`'s,
/// 12 bytes a record where a `Record` is 24).
enum Recs<'a> {
    Records(std::borrow::Cow<'a, [btlog::Record]>),
    /// Record `i` is at offset `first + size × i`.
    Columns {
        cols: btlog::Columns,
        first: usize,
        size: usize,
    },
}

/// A log's run as a session; `place` names where a record is (a byte
/// offset, a table row).
fn session_from(
    path: &Path,
    run: LogRun,
    place: &dyn Fn(usize) -> String,
) -> Result<Session, Located> {
    let resyncs = run.resyncs;
    Ok(number(path, run, place)?.into_session_with(resyncs))
}

/// A log's run with its ticks numbered, not yet indexed: what `btx log`
/// prints from as it reads (an index of millions of transitions costs
/// more than the printing), and what a session is built from.
pub struct Numbered {
    pub path: PathBuf,
    pub tree: crate::model::Tree,
    pub warnings: Vec<Warning>,
    /// When each transition happened (µs since the epoch).
    pub times_us: Vec<i64>,
    /// Each transition's tick.
    ticks: Vec<u32>,
    /// Each transition's uid and status, in 4 bytes: a log's uids are
    /// BehaviorTree.CPP's 16-bit ones, checked against the tree.
    moves: Vec<u32>,
    header: Header,
    /// Run k of the n the log holds, when it holds several.
    run: Option<(usize, usize)>,
}

/// Each node's status as a log's records follow it, and as the robot last
/// said it (a live run's states read after a gap): what a transition
/// changed from. The recorder of a live run follows its records by it too.
pub(crate) struct Follower {
    followed: Vec<Status>,
    status: Vec<Status>,
}

impl Follower {
    pub(crate) fn new(nodes: usize) -> Follower {
        Follower {
            followed: vec![Status::Idle; nodes],
            status: vec![Status::Idle; nodes],
        }
    }

    /// The nodes' states as the robot said them (those of no node left out).
    pub(crate) fn read(&mut self, states: &[crate::session::Before]) {
        self.status.fill(Status::Idle);
        let len = self.status.len();
        for b in states
            .iter()
            .filter(|b| b.uid >= 1 && b.uid as usize <= len)
        {
            self.status[(b.uid - 1) as usize] = b.status;
        }
    }

    /// The status `uid` changes from, to `to`.
    pub(crate) fn step(&mut self, uid: crate::model::Uid, to: Status) -> Status {
        let u = (uid - 1) as usize;
        // A status the read already showed: the read came after this
        // transition, which left the status the records followed.
        let prev = if self.status[u] == to {
            self.followed[u]
        } else {
            self.status[u]
        };
        self.status[u] = to;
        self.followed[u] = to;
        prev
    }

    /// Each node's status now, by uid - 1.
    pub(crate) fn status(&self) -> &[Status] {
        &self.status
    }
}

/// What a walk over a log's run meets: the robot's reading of the
/// nodes' states, after how many transitions, or a transition.
enum Step<'a> {
    States(usize, &'a [crate::session::Before]),
    Move(usize, Transition),
}

use btlog::unpack;

/// Where each record of a log is.
enum Offsets {
    Every { first: usize, size: usize },
    At(Vec<usize>),
}

impl Offsets {
    /// Record `i`'s, of `n`.
    fn of(&self, i: usize, n: usize) -> Option<usize> {
        match self {
            _ if i >= n => None,
            Offsets::Every { first, size } => Some(first + size * i),
            Offsets::At(v) => v.get(i).copied(),
        }
    }
}

/// A log's records numbered into ticks, with the tree checked and what
/// the reading noticed said; the records are let go (when owned).
fn number(path: &Path, run: LogRun, place: &dyn Fn(usize) -> String) -> Result<Numbered, Located> {
    let LogRun {
        len,
        partial_tail,
        xml,
        version,
        records,
        kind,
        resyncs: _,
        ticks: numbered,
        given,
        given_xml,
    } = run;
    let tree = log_tree(path, xml, version, given)?;
    let (records, offsets) = as_columns(path, &tree, records, place)?;
    let mut warnings = Vec::new();
    if partial_tail > 0 {
        warnings.push(Warning {
            location: format!("{}: byte offset {}", crate::text::path(path), len - partial_tail),
            message: format!("the last {partial_tail} bytes are not a whole record (a log still being written?); left out"),
        });
    }
    let ticks::Ticks {
        numbers: ticks,
        fell_back,
        capped,
    } = match numbered {
        Some(n) => ticks::Ticks {
            numbers: n.to_vec(),
            fell_back: None,
            capped: None,
        },
        None => ticks::reconstruct(&tree, records.view()),
    };
    let at = |i: usize| place(offsets.of(i, records.len()).unwrap_or(len));
    if let Some(i) = capped {
        warnings.push(Warning {
            location: format!("{}: {}", crate::text::path(path), at(i)),
            message: format!(
                "the timestamps claim more than {} ticks in which nothing changed; from here a gap counts as one tick",
                crate::session::EMPTY_TICKS_MAX
            ),
        });
    }
    if let Some(i) = fell_back {
        warnings.push(Warning {
            location: format!("{}: {}", crate::text::path(path), at(i)),
            message:
                "the replay could not follow the log from here; ticks are told apart by timing"
                    .into(),
        });
    }
    let btlog::Columns {
        moves,
        times: times_us,
    } = records;
    let mut header = import_header_with(
        path,
        &tree,
        version,
        kind,
        Vec::new(),
        given_xml.map(str::to_string),
    );
    if let Some(g) = given {
        header.tree.path = Some(g.path.display().to_string());
    }
    Ok(Numbered {
        path: path.to_path_buf(),
        tree,
        warnings,
        times_us,
        ticks,
        moves,
        header,
        run: None,
    })
}

/// The tree a log's records are of: the one it embeds, or the tree file
/// the robot ran once checked against it (a rosbag embeds none).
fn log_tree(
    path: &Path,
    xml: &str,
    version: crate::model::Version,
    given: Option<GivenTree>,
) -> Result<crate::model::Tree, Located> {
    if let Some(g) = given.filter(|_| xml.is_empty()) {
        return Ok(g.tree.clone());
    }
    let name = PathBuf::from(format!("{} (embedded tree)", path.display()));
    let embedded = load_str(
        &name,
        xml,
        &LoadOptions {
            version: Some(version),
            main_tree: None,
            embedded: true,
            ..Default::default()
        },
    )?
    .tree;
    match given {
        Some(g) => g.checked(path, &embedded),
        None => Ok(embedded),
    }
}

/// A log's records as columns, each one's offset where it says one; an
/// error names the first record whose uid is no node of `tree`.
fn as_columns(
    path: &Path,
    tree: &crate::model::Tree,
    records: Recs,
    place: &dyn Fn(usize) -> String,
) -> Result<(btlog::Columns, Offsets), Located> {
    let not_a_node = |offset: usize, uid: u32| {
        Located::file(
            path,
            format!(
                "{}: uid {uid} is not a node of the log's tree ({} nodes)",
                place(offset),
                tree.len()
            ),
        )
    };
    match records {
        Recs::Records(r) => {
            if let Some(r) = r.iter().find(|r| tree.get(r.uid).is_none()) {
                return Err(not_a_node(r.offset, r.uid));
            }
            let offsets: Vec<usize> = r.iter().map(|r| r.offset).collect();
            Ok((btlog::Columns::of(&r), Offsets::At(offsets)))
        }
        Recs::Columns { cols, first, size } => {
            let bad = cols.moves.iter().map(|&m| btlog::unpack(m).0);
            if let Some((i, uid)) = bad.enumerate().find(|(_, u)| tree.get(*u).is_none()) {
                return Err(not_a_node(first + size * i, uid));
            }
            Ok((cols, Offsets::Every { first, size }))
        }
    }
}

/// Whether the root's transition from `prev` to `to`, in tick `tick` of a
/// run that started in tick `run_from`, ends a robot's run: the root back
/// to IDLE after it completed a run of several ticks, so that the next
/// (a Nav2 robot's next goal) is a run of its own. A tree that completes
/// within each tick it is ticked (a loop) is one run.
pub fn ends_a_run(prev: Status, to: Status, tick: u32, run_from: u32) -> bool {
    to == Status::Idle && prev.is_completed() && tick > run_from
}

impl Numbered {
    /// Where each of the robot's runs starts (`ends_a_run`): 0 first.
    pub fn run_starts(&self) -> Vec<usize> {
        let mut starts = vec![0];
        let (mut run_from, mut root) = (0, Status::Idle);
        for (i, (&m, &tick)) in self.moves.iter().zip(&self.ticks).enumerate() {
            let (uid, to) = unpack(m);
            if uid != crate::model::Tree::ROOT {
                continue;
            }
            let prev = std::mem::replace(&mut root, to);
            if prev == Status::Idle {
                run_from = tick;
            }
            if ends_a_run(prev, to, tick, run_from) && i + 1 < self.moves.len() {
                starts.push(i + 1);
            }
        }
        starts
    }

    /// Read whole, a log of several runs says so: an answer about "now"
    /// is about the last run's end, and ticks count through every run.
    pub fn say_runs(&mut self) {
        let n = self.run_starts().len();
        if n > 1 {
            self.warnings.push(Warning {
                location: crate::text::path(&self.path),
                message: format!("the log holds {n} runs (the root started again after it completed), read whole, its ticks counted through them all; --run N reads one, `btx log LOG --runs` lists them"),
            });
        }
    }

    /// Run `k` (from 1) of the log alone, its ticks from 1; said in its
    /// warnings when the log holds several.
    pub fn run(self, k: usize) -> Result<Numbered, Located> {
        let starts = self.run_starts();
        let mut run = self.run_of(&starts, k)?;
        let n = starts.len();
        if n > 1 {
            run.warnings.push(Warning {
                location: crate::text::path(&self.path),
                message: format!("the log holds {n} runs (the root started again after it completed); this is run {k}, its ticks from 1"),
            });
        }
        Ok(run)
    }

    /// Run `k` of the runs starting at `starts` (`run_starts`), unsaid.
    pub fn run_of(&self, starts: &[usize], k: usize) -> Result<Numbered, Located> {
        let n = starts.len();
        if k == 0 || k > n {
            return Err(Located::file(
                &self.path,
                format!("the log holds runs 1 to {n}; there is no run {k} (`btx log LOG --runs` lists them)"),
            ));
        }
        let range = starts[k - 1]..starts.get(k).copied().unwrap_or(self.moves.len());
        let base = self.ticks.get(range.start).map_or(0, |t| t - 1);
        Ok(Numbered {
            path: self.path.clone(),
            tree: self.tree.clone(),
            warnings: self.warnings.clone(),
            times_us: self.times_us[range.clone()].to_vec(),
            ticks: self.ticks[range.clone()].iter().map(|t| t - base).collect(),
            moves: self.moves[range].to_vec(),
            header: self.header.clone(),
            run: (n > 1).then_some((k, n)),
        })
    }

    /// The log's ticks, empty ones (a leaf running through them) counted.
    pub fn ticks(&self) -> u32 {
        self.ticks.last().copied().unwrap_or(0)
    }

    /// Each transition, with its place in the log, in order.
    pub fn each_transition(&self, mut f: impl FnMut(usize, Transition)) {
        self.walk(&[], |step| {
            if let Step::Move(i, t) = step {
                f(i, t)
            }
        });
    }

    /// Each transition of node `uid`, with its place in the log and its
    /// step in its tick, in order: `each_transition` for one node, which
    /// follows only that node (a log has no robot's reading of the states
    /// between its records, so a status changes from the node's last).
    pub fn each_transition_of(
        &self,
        uid: crate::model::Uid,
        mut f: impl FnMut(usize, u32, Transition),
    ) {
        let (mut prev, mut tick, mut first) = (Status::Idle, 0, 0);
        for (i, (&m, &t)) in self.moves.iter().zip(&self.ticks).enumerate() {
            if t != tick {
                (tick, first) = (t, i);
            }
            if m & btlog::PACKED_UID_MAX != uid {
                continue;
            }
            let (uid, status) = unpack(m);
            let from = std::mem::replace(&mut prev, status);
            let step = (i - first + 1) as u32;
            f(
                i,
                step,
                Transition {
                    tick,
                    uid,
                    prev: from,
                    status,
                },
            );
        }
    }

    /// The transitions in order, each robot's reading of the nodes'
    /// states (`resyncs`: after how many transitions) where it came.
    fn walk(&self, resyncs: &[(usize, Vec<crate::session::Before>)], mut f: impl FnMut(Step)) {
        let mut follower = Follower::new(self.tree.len());
        let mut next = resyncs.iter().peekable();
        for (i, (&m, &tick)) in self.moves.iter().zip(&self.ticks).enumerate() {
            while let Some((_, states)) = next.next_if(|(at, _)| *at <= i) {
                f(Step::States(i, states));
                follower.read(states);
            }
            let (uid, status) = unpack(m);
            let prev = follower.step(uid, status);
            f(Step::Move(
                i,
                Transition {
                    tick,
                    uid,
                    prev,
                    status,
                },
            ));
        }
        for (at, states) in next {
            f(Step::States(*at, states));
        }
    }

    /// The run as a session: its transitions indexed.
    pub fn into_session(self) -> Session {
        self.into_session_with(&[])
    }

    /// `into_session`, with the nodes' states the robot said after how
    /// many transitions (`resyncs`).
    fn into_session_with(self, resyncs: &[(usize, Vec<crate::session::Before>)]) -> Session {
        let mut index = Index::new(self.tree.len());
        index.reserve(self.moves.iter().map(|&m| unpack(m).0));
        self.walk(resyncs, |step| match step {
            Step::States(0, states) => index.set_before(states),
            Step::States(_, states) => index.push_resync(states),
            Step::Move(_, t) => index.push_transition(&self.tree, t, None),
        });
        let Numbered {
            path,
            tree,
            warnings,
            times_us,
            header,
            run,
            ..
        } = self;
        let span_us = times_us.first().zip(times_us.last()).map(|(a, b)| (*a, *b));
        let end = ending(&index);
        Session {
            path,
            header,
            tree,
            index,
            end,
            inserts: Vec::new(),
            span_us,
            times_us,
            warnings,
            run,
        }
    }
}

/// Where a tree file and the tree a log recorded differ, uid by uid (the
/// node's kind, type and name), each as one line naming the tree file's
/// line; empty when they match. At most `max` lines, then a count.
pub fn tree_mismatch(
    file: &crate::model::Tree,
    log: &crate::model::Tree,
    max: usize,
) -> Vec<String> {
    let mut out = Vec::new();
    if file.len() != log.len() {
        out.push(format!(
            "the tree file has {} nodes and the log's tree {}",
            file.len(),
            log.len()
        ));
    }
    let mut more = 0;
    for uid in 1..=file.len().min(log.len()) as u32 {
        let (a, b) = (file.node(uid), log.node(uid));
        let what =
            |t: &crate::model::Tree| format!("{} \"{}\"", t.type_name(uid), t.description(uid));
        if a.kind != b.kind || file.type_name(uid) != log.type_name(uid) || a.name != b.name {
            if out.len() >= max {
                more += 1;
                continue;
            }
            let (f, line, col) = file.location(uid);
            out.push(format!(
                "#{uid}: {f}:{line}:{col} has {}, the log {}",
                what(file),
                what(log)
            ));
        }
    }
    if more > 0 {
        out.push(format!("and {more} more nodes differ"));
    }
    out
}

/// The header of a session read from a log: the log's tree, embedded.
pub(crate) fn import_header(
    path: &Path,
    tree: &crate::model::Tree,
    version: crate::model::Version,
    kind: &str,
    blackboard: Vec<(crate::run::blackboard::EntryId, serde_json::Value)>,
) -> Header {
    import_header_with(path, tree, version, kind, blackboard, None)
}

/// `import_header`, with the tree's XML where the caller has it already.
fn import_header_with(
    path: &Path,
    tree: &crate::model::Tree,
    version: crate::model::Version,
    kind: &str,
    blackboard: Vec<(crate::run::blackboard::EntryId, serde_json::Value)>,
    xml: Option<String>,
) -> Header {
    Header {
        btx_session: format::FORMAT_VERSION,
        btx_version: env!("CARGO_PKG_VERSION").to_string(),
        tree: TreeRef {
            path: Some(path.display().to_string()),
            hash: None,
            xml: xml.unwrap_or_else(|| crate::xml::to_v4_xml(tree)),
            btcpp_format: version.number(),
            main_tree: tree.main_tree.clone(),
        },
        source: Source {
            kind: "import".into(),
            path: Some(path.display().to_string()),
            text: None,
            name: Some(kind.into()),
        },
        seed: None,
        tick_ms: 0,
        nav2: None,
        blackboard,
        before: Vec::new(),
    }
}

/// How a log's run ended, by the root's last transition: completed
/// (SUCCESS or FAILURE, or IDLE right after it, as BehaviorTree.CPP resets
/// a finished tree), or halted while RUNNING. A log that stops while the
/// root runs has no end: the run was cut off or is still going.
pub fn ending(index: &crate::session::Index) -> Option<(u32, Status, String)> {
    let last = index
        .transitions
        .iter()
        .rev()
        .find(|t| t.uid == crate::model::Tree::ROOT)?;
    let ticks = index.ticks();
    if let Some(done) = last.status.ended(last.prev) {
        return Some((ticks, done, "root completed".into()));
    }
    (last.prev == Status::Running && last.status == Status::Idle)
        .then(|| (ticks, Status::Idle, "root halted while RUNNING".into()))
}

/// Writes a session read from a log as a btx session file; a log that
/// stops while the root runs is written without an end.
pub fn write_session(s: &Session, out: &Path) -> Result<PathBuf, Located> {
    let mut w = crate::session::SessionWriter::create(out, &s.header)?;
    write_events(s, &mut w)?;
    match &s.end {
        Some((ticks, root, why)) => w.finish(*ticks, *root, why),
        None => w.finish_cut_off(),
    }
}

fn write_events(s: &Session, w: &mut crate::session::SessionWriter) -> Result<(), Located> {
    let idx = &s.index;
    let (mut wi, mut di, mut gi) = (0, 0, 0);
    // The states read when recording began are in the header.
    let resyncs: Vec<_> = idx.resyncs().into_iter().filter(|r| r.0 > 0).collect();
    let mut ri = 0;
    // The log's times are kept with its transitions.
    let timed = s.times_us.len() == idx.transitions.len();
    for (i, t) in idx.transitions.iter().enumerate() {
        while let Some((_, why)) = idx.gaps.get(gi).filter(|g| g.0 as usize <= i) {
            w.gap(t.tick, why)?;
            gi += 1;
        }
        while let Some((_, states)) = resyncs.get(ri).filter(|r| r.0 as usize <= i) {
            w.resync(idx.transitions[i - 1].tick, states)?;
            ri += 1;
        }
        while let Some(x) = idx.writes.get(wi).filter(|x| x.pos as usize <= i) {
            w.event(&crate::run::Event::Write {
                tick: x.tick,
                uid: x.uid,
                entry: x.entry.clone(),
                value: x.value.clone(),
            })?;
            wi += 1;
        }
        while let Some((_, tick, uid, d)) = idx.decision_calls.get(di).filter(|x| x.0 as usize <= i)
        {
            w.event(&crate::run::Event::Decision {
                tick: *tick,
                uid: *uid,
                decision: d.clone(),
            })?;
            di += 1;
        }
        w.timed(s.times_us.get(i).copied().filter(|_| timed));
        w.event(&crate::run::Event::Transition {
            tick: t.tick,
            uid: t.uid,
            prev: t.prev,
            status: t.status,
            decision: idx.transition_decision(i).map(str::to_string),
        })?;
    }
    for (_, why) in &idx.gaps[gi..] {
        w.gap(idx.ticks().max(1), why)?;
    }
    for (_, states) in &resyncs[ri..] {
        w.resync(idx.ticks().max(1), states)?;
    }
    Ok(())
}
