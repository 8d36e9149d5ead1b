//! A live run as it is kept: each transition, once its tick is numbered
//! (`logs::ticks::Stream`), is appended to `OUT.partial` and let go, so
//! that memory stays bounded however long the robot runs; the explorer's
//! view keeps at most `VIEW_MAX` transitions.

use super::Gap;
use crate::logs::btlog::Record;
use crate::model::{Tree, Uid};
use crate::run::{Event, Status};
use crate::session::LogRow;
use crate::session::{Before, Header, SessionWriter};
use crate::source::Located;
use std::collections::VecDeque;
use std::path::{Path, PathBuf};

/// The most transitions of a live run the explorer holds; past them the
/// run goes on to the file (`--out`) and the view says it stopped growing.
pub const VIEW_MAX: usize = 1_000_000;
/// The most gaps and resyncs the explorer's view holds (each resync is
/// every node's state); the file holds them all.
pub const VIEW_MARKS_MAX: usize = 1_000;

/// Something said at a place in the run: a gap, or the states read again.
enum Mark {
    Gap(Gap),
    Resync(usize, Vec<Before>),
}

impl Mark {
    fn at(&self) -> usize {
        match self {
            Mark::Gap(g) => g.at,
            Mark::Resync(at, _) => *at,
        }
    }
}

pub struct Recorder {
    out: Option<PathBuf>,
    writer: Option<SessionWriter>,
    /// The header each run's session starts from.
    header: Header,
    /// Each run's session written (the robot's runs, one a session), and
    /// whether the next run's is yet to be made (at its first transition).
    pub written_runs: Vec<(PathBuf, usize)>,
    next_run: bool,
    /// The ticks of the runs before this one: each run's ticks count from 1.
    tick_base: u32,
    run_written: usize,
    /// The watch's tick the root last started in.
    run_from: u32,
    /// Each node's status as the records follow it, and as last read.
    /// Each node's status, as the records and the states read say.
    follow: crate::logs::Follower,
    /// Marks waiting for the first transition at or after their place.
    marks: VecDeque<Mark>,
    tick: u32,
    step: u32,
    last_tick: u32,
    /// The root's last transition: its status before and after.
    root: (Status, Status),
    /// Rows for a caller that prints them (`btx watch`), if it asked, and
    /// the gap to say with the next one.
    pub rows: Option<Vec<LogRow>>,
    pending_gap: Option<String>,
    /// The view (unless `view` is off: `btx watch` shows none): numbered
    /// records, gaps, resyncs after 0, within bounds.
    pub view: bool,
    pub kept: Vec<Record>,
    pub numbers: Vec<u32>,
    pub gaps: Vec<Gap>,
    pub resyncs: Vec<(usize, Vec<Before>)>,
    /// Transitions past the view's bound (on file only).
    pub unviewed: usize,
    /// Transitions written (or, without a file, taken).
    pub written: usize,
    abandoned: bool,
}

impl Recorder {
    /// With `out`, the run streams to `OUT.partial` from the header on.
    pub fn new(tree: &Tree, out: Option<&Path>, header: &Header) -> Result<Recorder, Located> {
        let mut follow = crate::logs::Follower::new(tree.len());
        follow.read(&header.before);
        // Attached to a robot that was running: its root runs already.
        let root = follow.status().first().copied().unwrap_or(Status::Idle);
        let writer = match out {
            Some(o) => Some(SessionWriter::create(o, header)?),
            None => None,
        };
        Ok(Recorder {
            out: out.map(Path::to_path_buf),
            writer,
            header: header.clone(),
            written_runs: Vec::new(),
            next_run: false,
            tick_base: 0,
            run_written: 0,
            run_from: 0,
            follow,
            marks: VecDeque::new(),
            tick: 0,
            step: 0,
            last_tick: 0,
            root: (Status::Idle, root),
            rows: None,
            pending_gap: None,
            view: true,
            kept: Vec::new(),
            numbers: Vec::new(),
            gaps: Vec::new(),
            resyncs: Vec::new(),
            unviewed: 0,
            written: 0,
            abandoned: false,
        })
    }

    pub fn gap(&mut self, g: Gap) {
        self.place(Mark::Gap(g));
    }

    pub fn resync(&mut self, at: usize, states: Vec<Before>) {
        self.place(Mark::Resync(at, states));
    }

    /// Keeps the marks in the order of their places (a batch brings its
    /// gaps and its resyncs apart), after those already at the same place.
    fn place(&mut self, m: Mark) {
        let i = self.marks.partition_point(|x| x.at() <= m.at());
        self.marks.insert(i, m);
    }

    /// Writes numbered records, each after the marks at or before its
    /// place; flushed, so that a reader of `OUT.partial` sees them.
    pub fn take(&mut self, numbered: &[(Record, u32)]) -> Result<(), Located> {
        for &(r, tick) in numbered {
            if self.next_run {
                self.start_run(tick)?;
            }
            self.marks_before(r.offset, tick)?;
            let prev = self.follow.step(r.uid, r.status);
            if tick != self.tick {
                self.tick = tick;
                self.step = 0;
            }
            self.step += 1;
            self.last_tick = tick;
            if r.uid == Tree::ROOT {
                self.root = (prev, r.status);
                if prev == Status::Idle {
                    self.run_from = tick;
                }
            }
            // The session's and the rows' ticks are the run's own; the
            // explorer's view numbers the whole watch.
            let local = self.local(tick);
            if let Some(w) = self.writer.as_mut() {
                w.timed(Some(r.time_us));
                w.event(&Event::Transition {
                    tick: local,
                    uid: r.uid,
                    prev,
                    status: r.status,
                    decision: None,
                })?;
            }
            self.run_written += 1;
            if let Some(rows) = self.rows.as_mut() {
                rows.push(LogRow {
                    tick: local,
                    step: self.step,
                    uid: r.uid,
                    prev,
                    status: r.status,
                    decision: None,
                    gap: self.pending_gap.take(),
                    time_us: Some(r.time_us),
                });
            }
            if self.view && self.kept.len() < VIEW_MAX {
                self.kept.push(r);
                self.numbers.push(tick);
            } else if self.view {
                self.unviewed += 1;
            }
            self.written += 1;
            // The robot's run ended: its next is a session of its own.
            if r.uid == Tree::ROOT && crate::logs::ends_a_run(prev, r.status, tick, self.run_from) {
                self.end_run(local, prev)?;
            }
        }
        if let Some(w) = self.writer.as_mut() {
            w.flush()?;
        }
        Ok(())
    }

    /// A tick of the watch as the run's session numbers it (from 1).
    fn local(&self, tick: u32) -> u32 {
        tick.saturating_sub(self.tick_base).max(1)
    }

    /// The run ended at `tick` (its own numbering) with `root`: its
    /// session is finished, and the next is made at its first transition.
    fn end_run(&mut self, tick: u32, root: Status) -> Result<(), Located> {
        let Some(w) = self.writer.take() else {
            return Ok(());
        };
        let path = w.finish(tick, root, "the robot's run finished")?;
        self.written_runs.push((path, self.run_written));
        self.run_written = 0;
        self.next_run = true;
        Ok(())
    }

    /// The next run's session, at its first transition (of the watch's
    /// tick `tick`): `OUT-2.jsonl`, `OUT-3.jsonl` (the first name free).
    fn start_run(&mut self, tick: u32) -> Result<(), Located> {
        self.next_run = false;
        self.tick_base = tick.saturating_sub(1);
        let Some(out) = &self.out else {
            return Ok(());
        };
        let k = self.written_runs.len() + 1;
        let path = (k..k + 1000)
            .map(|k| run_path(out, k))
            .find(|p| !p.exists() && !SessionWriter::partial_path(p).exists())
            .unwrap_or_else(|| run_path(out, k));
        // Every node as it stands when the run starts (IDLE, after the
        // robot reset its tree).
        let mut header = self.header.clone();
        header.before = self
            .follow
            .status()
            .iter()
            .enumerate()
            .filter(|(_, s)| **s != Status::Idle)
            .map(|(i, s)| Before {
                uid: i as Uid + 1,
                status: *s,
                done: None,
            })
            .collect();
        self.writer = Some(SessionWriter::create(&path, &header)?);
        Ok(())
    }

    /// Writes the marks placed at or before record `at` (of tick `tick`).
    fn marks_before(&mut self, at: usize, tick: u32) -> Result<(), Located> {
        while self.marks.front().is_some_and(|m| m.at() <= at) {
            let m = self.marks.pop_front().expect("front");
            self.mark(m, tick)?;
        }
        Ok(())
    }

    fn mark(&mut self, m: Mark, tick: u32) -> Result<(), Located> {
        let viewed = self.view && self.kept.len() < VIEW_MAX;
        match m {
            Mark::Gap(g) => {
                let tick = self.local(tick);
                if let Some(w) = self.writer.as_mut() {
                    w.gap(tick, &g.why)?;
                }
                if self.rows.is_some() {
                    // Said with the next row printed.
                    self.pending_gap = Some(g.why.clone());
                }
                if viewed && self.gaps.len() < VIEW_MARKS_MAX {
                    self.gaps.push(Gap {
                        at: self.kept.len(),
                        why: g.why,
                    });
                }
            }
            Mark::Resync(at, states) => {
                let last = self.local(self.last_tick);
                if let Some(w) = self.writer.as_mut() {
                    // After the transition before it, in that one's tick.
                    w.resync(last, &states)?;
                }
                self.follow.read(&states);
                // Joined while the robot ran: the root runs though no
                // transition of it came (a status of it read is no change).
                let root = self.follow.status()[(Tree::ROOT - 1) as usize];
                if root != self.root.1 {
                    self.root = (self.root.1, root);
                }
                if viewed && at > 0 && self.resyncs.len() < VIEW_MARKS_MAX {
                    self.resyncs.push((self.kept.len(), states));
                }
            }
        }
        Ok(())
    }

    /// The run is over: the marks left are written at its end, and with a
    /// file, the session is finished (`OUT`); where it was written.
    pub fn finish(&mut self) -> Result<Option<PathBuf>, Located> {
        let tick = self.last_tick.max(1);
        while let Some(m) = self.marks.pop_front() {
            self.mark(m, tick)?;
        }
        // The run finished when the root's last transition completed it
        // (or reset it to IDLE right after, as BehaviorTree.CPP does).
        let (prev, now) = self.root;
        let (root, why) = match now.ended(prev) {
            Some(done) => (done, "the robot's run finished"),
            None => (now, "watching stopped"),
        };
        let last = self.local(self.last_tick);
        match self.writer.take() {
            Some(w) => {
                let path = w.finish(last, root, why)?;
                self.written_runs.push((path.clone(), self.run_written));
                self.run_written = 0;
                Ok(Some(path))
            }
            None => Ok(self.written_runs.last().map(|(p, _)| p.clone())),
        }
    }

    /// Stops writing after an error: the file keeps what it had, and is
    /// not finished as a whole run.
    pub fn abandon(&mut self) {
        self.writer = None;
        self.abandoned = true;
    }

    /// The root's last transition written: its status before and after.
    pub fn root(&self) -> (Status, Status) {
        self.root
    }

    pub fn abandoned(&self) -> bool {
        self.abandoned
    }

    /// Where the run is written, if it is.
    pub fn out(&self) -> Option<&Path> {
        self.out.as_deref()
    }
}

/// Where a watch keeps the robot's `k`-th run: `OUT` for the first, then
/// `OUT-2.jsonl` (`OUT-2.parquet`), and so on.
pub fn run_path(out: &Path, k: usize) -> PathBuf {
    if k <= 1 {
        return out.to_path_buf();
    }
    let stem = out
        .file_stem()
        .map_or("run".into(), |s| s.to_string_lossy().into_owned());
    let name = match out.extension() {
        Some(x) => format!("{stem}-{k}.{}", x.to_string_lossy()),
        None => format!("{stem}-{k}"),
    };
    out.with_file_name(name)
}

/// Whether `uid` names a node of a tree of `len` nodes.
pub fn is_node(uid: Uid, len: usize) -> bool {
    uid >= 1 && (uid as usize) <= len
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tree() -> Tree {
        crate::xml::load_str(
            Path::new("t.xml"),
            r#"<root BTCPP_format="4"><BehaviorTree ID="M"><Sequence>
                 <AlwaysSuccess/><AlwaysSuccess/></Sequence></BehaviorTree></root>"#,
            &Default::default(),
        )
        .unwrap()
        .tree
    }

    fn rec(uid: Uid, status: Status, offset: usize) -> (Record, u32) {
        let r = Record {
            time_us: offset as i64,
            uid,
            status,
            offset,
        };
        (r, 1)
    }

    /// Attached while the robot ran and stopped before its run ended:
    /// the root was RUNNING all along, though no transition of it came.
    #[test]
    fn a_watch_that_joined_a_running_robot_ends_with_the_root_running() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("w.jsonl");
        let tree = tree();
        let mut header = crate::logs::import_header(
            Path::new("x"),
            &tree,
            crate::model::Version::V4,
            "t",
            vec![],
        );
        header.before = vec![
            Before {
                uid: 1,
                status: Status::Running,
                done: None,
            },
            Before {
                uid: 2,
                status: Status::Running,
                done: None,
            },
        ];
        let mut r = Recorder::new(&tree, Some(&out), &header).unwrap();
        r.take(&[rec(2, Status::Success, 0), rec(3, Status::Running, 1)])
            .unwrap();
        assert_eq!(r.root(), (Status::Idle, Status::Running));
        let path = r.finish().unwrap().unwrap();
        let s = crate::session::Session::load(&path).unwrap();
        assert!(
            s.ending().contains("with the root RUNNING"),
            "{}",
            s.ending()
        );
        // Read again after a gap, the same.
        let mut r = Recorder::new(
            &tree,
            None,
            &crate::logs::import_header(
                Path::new("x"),
                &tree,
                crate::model::Version::V4,
                "t",
                vec![],
            ),
        )
        .unwrap();
        r.resync(0, header.before.clone());
        r.take(&[rec(2, Status::Success, 0)]).unwrap();
        assert_eq!(r.root().1, Status::Running);
    }
}
