//! A log's records numbered into ticks as BehaviorTree.CPP ran them
//! (`Numbered`), followed run by run, and read as a session's columns.

use super::import::{ending, import_header_with, tree_mismatch};
use super::*;
use crate::run::Status;
use crate::session::{Header, Index, Session, Transition};
use crate::source::{Located, Warning};
use crate::xml::{load_str, LoadOptions};
use std::path::{Path, PathBuf};

/// What a log gave: its tree, its records, how much of its end was cut.
pub(super) struct LogRun<'a> {
    /// The file's length, and the bytes at its end that are not a whole record.
    pub(super) len: usize,
    pub(super) partial_tail: usize,
    pub(super) xml: &'a str,
    pub(super) version: crate::model::Version,
    /// Owned where the caller gives them up: they are let go before the
    /// session is built (#31 item 1: 24 bytes a transition).
    pub(super) records: Recs<'a>,
    pub(super) kind: &'a str,
    /// The nodes' states read from the robot, after how many records (at
    /// 0: when recording began; none: all IDLE then).
    pub(super) resyncs: &'a [(usize, Vec<crate::session::Before>)],
    /// The records' ticks when they are numbered already.
    pub(super) ticks: Option<&'a [u32]>,
    /// The tree the robot ran, in place of the log's.
    pub(super) given: Option<GivenTree<'a>>,
    /// That tree as the session's header writes it, where the caller made
    /// it once for many runs (a bag's).
    pub(super) given_xml: Option<&'a str>,
}

/// A log's records: as its reader made them, or as columns (a `.btlog`'s,
/// 12 bytes a record where a `Record` is 24).
pub(super) enum Recs<'a> {
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
pub(super) fn session_from(
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

use btlog::unpack;

/// Where each record of a log is.
pub(super) enum Offsets {
    Every { first: usize, size: usize },
    At(Vec<usize>),
}

impl Offsets {
    /// Record `i`'s, of `n`.
    pub(super) fn of(&self, i: usize, n: usize) -> Option<usize> {
        match self {
            _ if i >= n => None,
            Offsets::Every { first, size } => Some(first + size * i),
            Offsets::At(v) => v.get(i).copied(),
        }
    }
}

/// A log's records numbered into ticks, with the tree checked and what
/// the reading noticed said; the records are let go (when owned).
pub(super) fn number(
    path: &Path,
    run: LogRun,
    place: &dyn Fn(usize) -> String,
) -> Result<Numbered, Located> {
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
    warnings.extend(numbering_warnings(path, capped, fell_back, &at));
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

/// What numbering the ticks noticed, at the record (`at`) it noticed it:
/// where timestamps claim too many empty ticks (`capped`), where the
/// replay lost the log and timing told ticks apart (`fell_back`).
fn numbering_warnings(
    path: &Path,
    capped: Option<usize>,
    fell_back: Option<usize>,
    at: &dyn Fn(usize) -> String,
) -> Vec<Warning> {
    let mut warnings = Vec::new();
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
    warnings
}

/// The tree a log's records are of: the one it embeds, or the tree file
/// the robot ran once checked against it (a rosbag embeds none).
pub(super) fn log_tree(
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
pub(super) fn as_columns(
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
    pub fn each_transition(&self, f: impl FnMut(usize, Transition)) {
        self.walk(&[], f);
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

    /// The transitions in order, with their places in the log; each
    /// changes from the status the robot last said (`resyncs`: its readings
    /// of the nodes' states, after how many transitions) or the records
    /// followed since.
    pub(super) fn walk(
        &self,
        resyncs: &[(usize, Vec<crate::session::Before>)],
        mut f: impl FnMut(usize, Transition),
    ) {
        let mut follower = Follower::new(self.tree.len());
        let mut next = resyncs.iter().peekable();
        for (i, (&m, &tick)) in self.moves.iter().zip(&self.ticks).enumerate() {
            while let Some((_, states)) = next.next_if(|(at, _)| *at <= i) {
                follower.read(states);
            }
            let (uid, status) = unpack(m);
            let prev = follower.step(uid, status);
            f(
                i,
                Transition {
                    tick,
                    uid,
                    prev,
                    status,
                },
            );
        }
    }

    /// The run as a session: its transitions indexed.
    pub fn into_session(self) -> Session {
        self.into_session_with(&[])
    }

    /// `into_session`, with the nodes' states the robot said after how
    /// many transitions (`resyncs`).
    pub(super) fn into_session_with(
        self,
        resyncs: &[(usize, Vec<crate::session::Before>)],
    ) -> Session {
        let mut index = Index::new(self.tree.len());
        let moves = || {
            self.ticks.iter().zip(&self.moves).map(|(&tick, &m)| {
                let (uid, status) = unpack(m);
                (tick, uid, status)
            })
        };
        index.push_whole(&self.tree, self.moves.len(), moves, |ts| {
            self.walk(resyncs, |_, t| ts.push(t))
        });
        // Where the robot said the nodes' states: before any transition
        // (recording began in the run's middle), or after the transitions
        // before it (those past the end, at the end).
        let len = self.moves.len();
        for (at, states) in resyncs {
            match *at {
                0 => index.set_before(states),
                at => index.push_resync_at(at.min(len) as u32, states),
            }
        }
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
    pub(super) fn checked(
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

#[cfg(test)]
mod tests {
    use crate::session::Index;

    /// Every recorded log of the fixtures, as read and also repeated past
    /// the length where the index's passes run side by side: its tables
    /// as pushing the transitions one at a time makes them.
    #[test]
    fn a_run_read_whole_is_indexed_as_one_pushed_a_transition_at_a_time() {
        let logs = crate::logs::btlog::fixture_logs();
        for path in &logs {
            let bytes = std::fs::read(path).unwrap();
            let once = crate::logs::open_btlog(path, &bytes).unwrap();
            let times = (1 << 17) / once.index.transitions.len().max(1) + 1;
            let many = crate::logs::btlog::repeated(&bytes, times);
            for s in [once, crate::logs::open_btlog(path, &many).unwrap()] {
                let mut pushed = Index::new(s.tree.len());
                for &t in &s.index.transitions {
                    pushed.push_transition(&s.tree, t, None);
                }
                assert_eq!(s.index.tables(), pushed.tables(), "{}", path.display());
                // The current node, kept at some positions and found from the
                // transitions between: the leaf ticked most recently.
                let mut now = 0;
                for (pos, t) in std::iter::once(None)
                    .chain(s.index.transitions.iter().map(Some))
                    .enumerate()
                {
                    if let Some(t) = t.filter(|t| t.status != crate::run::Status::Idle) {
                        if s.tree.node(t.uid).kind.is_leaf() {
                            now = t.uid;
                        }
                    }
                    let shown = s.index.at(pos as u32).current();
                    assert_eq!(
                        shown,
                        Some(now).filter(|&u| u != 0),
                        "{} at {pos}",
                        path.display()
                    );
                }
            }
        }
    }
}
