//! Watching a robot: attaching to its recording (the statuses when it
//! starts, exactly), polling its transitions, the gaps and resyncs, its
//! status; and a snapshot of its tree and states for `btx ask --live`.

use super::*;
use crate::logs::btlog::Record;
use crate::logs::Protocol;
use crate::run::Status;
use crate::session::{Before, Session};
use crate::source::Warning;
use groot2::{Client, LiveError, SERVER_BUFFER};

mod publisher;
mod settle;

/// A live run being watched.
pub struct Watch {
    pub endpoint: String,
    pub protocol: Protocol,
    /// A Groot2 robot's server.
    pub(super) client: Option<Client>,
    /// A BehaviorTree.CPP 3 robot's publisher, and the publisher's port
    /// the user gave.
    pub(super) groot1: Option<publisher::Link>,
    pub(super) publisher: Option<u16>,
    /// The tree as the server sent it (XML with `_uid`s).
    pub xml: String,
    pub uuid: [u8; 16],
    /// The server's clock when recording started, µs since the epoch.
    pub(super) t0: i64,
    /// Records received and not yet taken (`take_records`), and how many
    /// were taken before them.
    pub records: Vec<Record>,
    pub(super) taken: usize,
    /// Gaps not yet taken (the live thread hands them over), and the last
    /// one's place and reason (a gap said again there is kept once).
    pub gaps: Vec<Gap>,
    pub(super) last_gap: Option<(usize, u64)>,
    pub(super) gap_count: usize,
    /// Per record, µs from the transition on the robot to its arrival here
    /// (both clocks are the robot's and this machine's wall clocks).
    pub latency_us: Vec<i64>,
    /// The nodes' states read from the robot, and after how many records:
    /// when recording began (at 0; none when the robot had not started) and
    /// after each gap.
    pub resyncs: Vec<(usize, Vec<Before>)>,
    /// What the server said that cannot be right, not yet taken.
    pub notes: Vec<String>,
    /// The root's last transition received (its status before and after).
    pub(super) root: Option<(Status, Status)>,
    /// How the robot's run ended, when the robot went away after its root
    /// completed: the run is over, not cut off.
    pub finished: Option<String>,
    /// Replies larger than the buffer the server announced, in a row.
    pub(super) oversized: usize,
    /// Transitions were lost: every node's state is to be read again.
    pub(super) unsettled: bool,
    /// The state read (`S` codes), to be placed among the transitions of
    /// the next reply (`settle`).
    pub(super) settling: Option<Vec<(u32, u8)>>,
}

/// Replies larger than the server's buffer, in a row, after which btx
/// leaves the robot: no publisher sends them, and one that floods would
/// take the time and the disk of every other robot watched.
pub const OVERSIZED_MAX: usize = 10;

/// How many times btx starts recording before it takes the statuses as
/// they are (a robot whose statuses never hold still that long).
pub(super) const ATTACH_TRIES: usize = 5;

/// What `attach` found: the recording's start (the server's epoch µs), the
/// nodes' states then, the transitions recorded since, and whether the
/// states are exact.
pub(super) struct Attached {
    pub(super) t0: i64,
    /// Why the server's start time was not taken.
    pub(super) note: Option<String>,
    pub(super) before: Vec<Before>,
    pub(super) first: Vec<groot2::Transition>,
    pub(super) exact: bool,
}

/// The statuses when recording starts. They are read (`S`) before `r
/// start` and after it, and the transitions recorded meanwhile taken
/// (`t`): the states before are those at the start when some first of
/// those transitions lead from them to the states after. Otherwise a
/// transition fell between the first read and the start (it is not
/// recorded), and btx starts again.
pub(super) fn attach(c: &mut Client) -> Result<Attached, LiveError> {
    let mut got = attach_once(c)?;
    for _ in 1..ATTACH_TRIES {
        // Starting again would drop what the full buffer still holds.
        if got.exact || got.first.len() >= c.buffer {
            break;
        }
        got = attach_once(c)?;
    }
    Ok(got)
}

/// This machine's clock, µs since the epoch.
pub(super) fn now_us() -> i64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_micros() as i64)
}

/// The recording's start as the server says it, or, when that cannot be
/// right (before 1970, or more than a day ahead of this machine's clock),
/// this machine's clock now, with a note saying so.
pub(super) fn start_time(said: i64) -> (i64, Option<String>) {
    let now = now_us();
    if said < 0 || said > now.saturating_add(86_400_000_000) {
        (
            now,
            Some(format!(
                "the server said recording started at {said} µs since 1970, which cannot be right; transitions are timed from this machine's clock when recording started"
            )),
        )
    } else {
        (said, None)
    }
}

pub(super) fn attach_once(c: &mut Client) -> Result<Attached, LiveError> {
    let before = c.codes()?;
    let (t0, note) = start_time(c.start_recording()?);
    let after = c.codes()?;
    let first = c.transitions()?;
    let mut now = before.clone();
    let exact = now == after
        || first.iter().any(|t| {
            if let Some(x) = now.iter_mut().find(|(u, _)| *u == t.uid) {
                x.1 = groot2::code_after(x.1, t.status);
            }
            now == after
        });
    Ok(Attached {
        t0,
        note,
        before: groot2::states_of(&before),
        first,
        exact,
    })
}

/// A reason's fingerprint (gaps repeat; one is kept).
pub(super) fn fnv(why: &str) -> u64 {
    why.bytes().fold(0xcbf29ce484222325, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x100000001b3)
    })
}

/// What a gap's reason says when btx read the statuses again after it.
pub(super) const RESYNCED: &str = "; btx read every node's state again from the robot";

/// A UUID as text.
pub fn uuid_text(u: &[u8; 16]) -> String {
    u.iter().map(|b| format!("{b:02x}")).collect()
}

impl Watch {
    /// A watch with nothing received yet.
    pub(super) fn new(
        endpoint: &str,
        protocol: Protocol,
        xml: String,
        uuid: [u8; 16],
        t0: i64,
    ) -> Watch {
        Watch {
            endpoint: endpoint.to_string(),
            protocol,
            client: None,
            groot1: None,
            publisher: None,
            xml,
            uuid,
            t0,
            records: Vec::new(),
            taken: 0,
            gaps: Vec::new(),
            last_gap: None,
            gap_count: 0,
            latency_us: Vec::new(),
            resyncs: Vec::new(),
            notes: Vec::new(),
            root: None,
            finished: None,
            oversized: 0,
            unsettled: false,
            settling: None,
        }
    }

    /// Connects, reads the tree and starts recording. The server tells
    /// which protocol it speaks: a BehaviorTree.CPP 3 robot publishes on
    /// `publisher`, or on the port below the server's.
    pub fn start(endpoint: &str, publisher: Option<u16>) -> Result<Watch, LiveError> {
        let mut c = Client::connect(endpoint, TIMEOUT)?;
        let xml = match c.tree()? {
            groot2::Served::Xml(xml) => xml,
            groot2::Served::Groot1(tree) => return Watch::start_groot1(endpoint, publisher, &tree),
        };
        let Attached {
            t0,
            note,
            before,
            first,
            exact,
        } = attach(&mut c)?;
        let mut gaps = Vec::new();
        let mut note_idle = None;
        let buffer = c.buffer;
        let overflowed = first.len() >= buffer;
        if overflowed {
            gaps.push(Gap {
                at: 0,
                why: format!(
                    "the robot made more transitions than the server's buffer holds ({buffer}) before btx's first read: the ones before these {buffer} are lost; {}",
                    if before.is_empty() {
                        "every node was IDLE when recording started"
                    } else {
                        "each node's state when recording started is known"
                    }
                ),
            });
        } else if before.iter().any(|b| b.status != Status::Idle) {
            gaps.push(Gap {
                at: 0,
                why: format!(
                    "btx attached to a robot that had been running: before this, each node's state then is known{}, not its transitions",
                    if exact { "" } else { " only roughly (it kept changing while btx read it)" }
                ),
            });
        } else if first.is_empty() && !before.is_empty() {
            // Every node IDLE, some done: the robot's run had ended. No
            // transition is missing; there is nothing to watch yet.
            note_idle = Some("the robot's tree is idle (its last run had ended): nothing to watch until its next run starts".to_string());
        }
        let mut w = Watch::new(endpoint, Protocol::Groot2, xml, c.uuid, t0);
        w.client = Some(c);
        w.last_gap = gaps.last().map(|g: &Gap| (g.at, fnv(&g.why)));
        w.gap_count = gaps.len();
        w.gaps = gaps;
        if !before.is_empty() {
            w.resyncs.push((0, before));
        }
        w.notes.extend(note);
        w.notes.extend(note_idle);
        if publisher.is_some() {
            w.notes.push("--publisher-port is for a BehaviorTree.CPP 3 robot; this one speaks Groot2, on one port: it is not used".into());
        }
        w.take(first);
        w.settle()?;
        Ok(w)
    }

    /// Records received so far, taken or not.
    pub fn received(&self) -> usize {
        self.taken + self.records.len()
    }

    /// The records not taken yet.
    pub fn take_records(&mut self) -> Vec<Record> {
        self.taken += self.records.len();
        std::mem::take(&mut self.records)
    }

    pub fn connected(&self) -> bool {
        self.client.is_some() || self.groot1.as_ref().is_some_and(|l| l.sub.is_some())
    }

    /// Takes the transitions recorded since the last poll; how many. When
    /// the connection is gone, tries once to connect again (a robot that
    /// restarted has another tree UUID): either way the place is a gap.
    pub fn poll(&mut self) -> Result<usize, LiveError> {
        if self.protocol == Protocol::Groot1 {
            return self.poll_groot1(groot1::POLL_WAIT);
        }
        let Some(c) = self.client.as_mut() else {
            return self.reconnect().map(|()| 0);
        };
        let got = c.transitions().map(|ts| (ts, c.uuid));
        match got {
            Ok((ts, uuid)) if uuid != self.uuid => {
                // The socket reconnected on its own to a robot that started
                // again: its recording is not started and its tree may be
                // another.
                self.gap(format!(
                    "the robot restarted (its tree UUID changed){RESYNCED}"
                ));
                self.uuid = uuid;
                let n = self.take(ts);
                self.rejoin().map(|k| n + k)
            }
            Ok((ts, _)) => {
                let dropped = self.client.as_mut().and_then(|c| c.dropped.take());
                if let Some(bytes) = dropped {
                    self.gap(format!(
                        "the server sent {bytes} bytes of transitions in one reply, more than the {} btx reads at once (BehaviorTree.CPP's publisher sends at most {SERVER_BUFFER}): they are lost{RESYNCED}",
                        groot2::TRANSITIONS_REPLY_MAX
                    ));
                }
                self.unsettled |= dropped.is_some();
                let n = self.take(ts);
                self.settle().map(|k| n + k)
            }
            Err(e) => {
                self.client = None;
                if self.end_of_run() {
                    return Ok(0);
                }
                self.gap(format!("the connection dropped ({e}); btx reads every node's state again once it reconnects"));
                Err(e)
            }
        }
    }

    /// Whether the robot went away once its run finished: the end of the
    /// run, not a gap in it (said in `finished`).
    pub(super) fn end_of_run(&mut self) -> bool {
        let Some(done) = self.completed() else {
            return false;
        };
        self.finished = Some(format!(
            "the robot's run finished (root {}), then the robot closed the connection",
            done.as_str()
        ));
        true
    }

    /// The root's completion, when its last transition completed it (or
    /// reset it to IDLE after, as BehaviorTree.CPP does to a finished tree).
    pub(super) fn completed(&self) -> Option<Status> {
        self.root.and_then(|(prev, now)| now.ended(prev))
    }

    /// Keeps the transitions of a `t` reply; how many came.
    pub(super) fn take(&mut self, mut ts: Vec<groot2::Transition>) -> usize {
        let buffer = self.client.as_ref().map_or(SERVER_BUFFER, |c| c.buffer);
        let sent = ts.len();
        if (1..=buffer).contains(&sent) {
            self.oversized = 0;
        }
        if ts.len() > buffer {
            // No publisher sends more than its buffer holds: a full buffer,
            // whose newest transitions are kept (as a ring keeps them), so
            // that what one reply makes btx hold is bounded by the buffer.
            let over = ts.len() - buffer;
            ts.drain(..over);
            self.gap(format!("the server sent {} transitions in one reply, more than the server's buffer of {buffer} it announced: the {over} oldest are left out, as a full buffer loses them{RESYNCED} after the {buffer} kept", buffer + over));
            self.oversized += 1;
            if self.oversized >= OVERSIZED_MAX {
                self.finished = Some(format!(
                    "btx left the robot: its server sent more transitions than its buffer of {buffer} in {OVERSIZED_MAX} replies in a row, as no BehaviorTree.CPP publisher does; what came before is kept"
                ));
            }
        } else if ts.len() == buffer {
            self.gap(format!("the server's buffer of {buffer} transitions was full: older ones may be lost{RESYNCED} after these {buffer}"));
        }
        let n = ts.len();
        // BehaviorTree.CPP 4.8's publisher sizes its reply before it locks
        // the buffer: records that arrive meanwhile come out as zeros (uid
        // 0, which no node has).
        let zeroed = ts.iter().filter(|t| t.uid == 0).count();
        if zeroed > 0 {
            self.gap(format!("the server sent {zeroed} zeroed records (its buffer grew while it answered): those transitions are lost{RESYNCED}"));
        }
        ts.retain(|t| t.uid != 0);
        let read = self.settling.take();
        // A read followed by lost transitions may belong among them: it is
        // placed first, where btx took it, and read again.
        let lost = sent >= buffer || zeroed > 0;
        self.unsettled |= lost;
        let at = read.as_ref().map_or(0, |codes| {
            (!lost)
                .then(|| settle::settled_at(codes, &ts))
                .flatten()
                .unwrap_or(0)
        });
        let after = ts.split_off(at);
        self.keep(ts.into_iter());
        if let Some(codes) = read {
            self.resyncs
                .push((self.received(), groot2::states_of(&codes)));
        }
        self.keep(after.into_iter());
        n
    }

    /// After lost transitions, reads where they left the nodes (without
    /// it a node whose completion was lost would show RUNNING until its
    /// next transition, and that one as a halt), then the transitions
    /// since, among which the read is placed (`settle::settled_at`); how
    /// many transitions came.
    pub(super) fn settle(&mut self) -> Result<usize, LiveError> {
        if !self.unsettled {
            return Ok(0);
        }
        let Some(c) = self.client.as_mut() else {
            return Ok(0);
        };
        self.unsettled = false;
        match c
            .codes()
            .and_then(|codes| c.transitions().map(|ts| (codes, ts)))
        {
            Ok((codes, ts)) => {
                self.settling = Some(codes);
                Ok(self.take(ts))
            }
            Err(e) => {
                self.client = None;
                self.gap(format!("the connection dropped ({e})"));
                Err(e)
            }
        }
    }

    /// Keeps transitions as records; how many.
    pub(super) fn keep(&mut self, ts: impl Iterator<Item = groot2::Transition>) -> usize {
        let now_us = now_us();
        let mut n = 0;
        for t in ts {
            n += 1;
            if t.uid == crate::model::Tree::ROOT {
                let prev = self.root.map_or(Status::Idle, |r| r.1);
                self.root = Some((prev, t.status));
            }
            let time_us = self.t0.saturating_add(t.time_us);
            self.latency_us.push(now_us.saturating_sub(time_us));
            let offset = self.received();
            self.records.push(Record {
                time_us,
                uid: t.uid,
                status: t.status,
                offset,
            });
        }
        n
    }

    /// A gap here, unless the last one was the same at the same place.
    pub(super) fn gap(&mut self, why: String) {
        let at = self.received();
        let here = Some((at, fnv(&why)));
        if self.last_gap != here {
            self.last_gap = here;
            self.gap_count += 1;
            self.gaps.push(Gap { at, why });
        }
    }

    pub(super) fn reconnect(&mut self) -> Result<(), LiveError> {
        let mut c = Client::connect(&self.endpoint, TIMEOUT)?;
        // The reply's header says the tree's UUID.
        c.tree_xml()?;
        if c.uuid != self.uuid {
            self.gap(format!(
                "the robot restarted (its tree UUID changed){RESYNCED}"
            ));
            self.uuid = c.uuid;
        }
        self.client = Some(c);
        self.rejoin().map(|_| ())
    }

    /// Joins the run again after a gap, as when watching began: checks the
    /// tree is the same, starts recording, and reads every node's state
    /// (`attach`); how many transitions came with it.
    pub(super) fn rejoin(&mut self) -> Result<usize, LiveError> {
        let c = self
            .client
            .as_mut()
            .ok_or_else(|| LiveError("not connected".into()))?;
        let joined = c.tree_xml().and_then(|xml| {
            if xml == self.xml {
                attach(c)
            } else {
                Err(LiveError(format!(
                    "{}: the robot now runs another tree; watch it anew",
                    self.endpoint
                )))
            }
        });
        match joined {
            Ok(Attached {
                t0,
                note,
                before,
                first,
                ..
            }) => {
                self.t0 = t0;
                self.notes.extend(note);
                self.resyncs.push((self.received(), before));
                Ok(self.take(first))
            }
            Err(e) => {
                self.client = None;
                Err(e)
            }
        }
    }
}

/// The robot's tree and its nodes' states now, as a session with no
/// transition (`btx ask --live`). Only `T` and `S` are asked of a Groot2
/// robot: recording (`r`, `t`) would take the transitions another client
/// is recording, as the server keeps one buffer for all. A BehaviorTree.CPP
/// 3 robot's states come with its publisher's next message.
pub fn snapshot(endpoint: &str, publisher: Option<u16>) -> Result<Session, LiveError> {
    let mut c = Client::connect(endpoint, TIMEOUT)?;
    let (protocol, xml, before, notes) = match c.tree()? {
        groot2::Served::Xml(xml) => (Protocol::Groot2, xml, c.states()?, Vec::new()),
        groot2::Served::Groot1(tree) => {
            let mut w = Watch::start_groot1(endpoint, publisher, &tree)?;
            let before = w.groot1_now();
            // Nothing asked of the present reads a blackboard.
            let mut notes: Vec<String> = std::mem::take(&mut w.notes)
                .into_iter()
                .filter(|n| n != groot1::NO_BLACKBOARD)
                .collect();
            if before.is_none() {
                notes.push(groot1::NO_MESSAGE.to_string());
            }
            (Protocol::Groot1, w.xml, before.unwrap_or_default(), notes)
        }
    };
    let name = protocol.source(endpoint);
    let mut s = crate::logs::open_live(protocol, &name, &xml, &[], &[(0, before)])
        .map_err(|e| LiveError(format!("{endpoint}: the robot's tree: {}", e.message)))?;
    for n in notes {
        s.warnings.push(Warning {
            location: crate::text::path(&name),
            message: n,
        });
    }
    Ok(s)
}

/// What the explorer shows of a live run besides the run itself.
#[derive(Debug, Clone, PartialEq)]
pub struct LiveStatus {
    pub endpoint: String,
    pub protocol: Protocol,
    pub uuid: String,
    pub connected: bool,
    /// Transitions a second over the last second.
    pub per_second: f64,
    pub transitions: usize,
    pub gaps: usize,
    /// The last error, while not connected.
    pub error: Option<String>,
    /// How the robot's run ended, once it went away after its root
    /// completed (watching is over).
    pub finished: Option<String>,
}

impl LiveStatus {
    /// One line: `live 127.0.0.1:1667 · tree 5cbb91d0… · connected · 812/s · 248 transitions · no gap`
    /// (`live 127.0.0.1:1667 (BehaviorTree.CPP 3) · …` for Groot 1's protocol).
    pub fn line(&self) -> String {
        format!(
            "live {}{} · tree {}… · {} · {:.0}/s · {} transitions · {}",
            self.endpoint,
            match self.protocol {
                Protocol::Groot2 => "",
                Protocol::Groot1 => " (BehaviorTree.CPP 3)",
            },
            self.uuid.get(..8).unwrap_or(&self.uuid),
            if let Some(f) = &self.finished {
                f.clone()
            } else if self.connected {
                "connected".to_string()
            } else {
                format!(
                    "reconnecting{}",
                    self.error
                        .as_ref()
                        .map_or(String::new(), |e| format!(" ({e})"))
                )
            },
            self.per_second,
            self.transitions,
            self.gaps_text()
        )
    }

    /// `no gap`, `1 gap`, `N gaps`.
    pub fn gaps_text(&self) -> String {
        match self.gaps {
            0 => "no gap".to_string(),
            1 => "1 gap".to_string(),
            n => format!("{n} gaps"),
        }
    }
}

impl Watch {
    /// One blackboard's entries (`B`), `{}` when the server has none by
    /// that name.
    pub fn blackboard(&mut self, name: &str) -> Result<serde_json::Value, String> {
        if self.protocol == Protocol::Groot1 {
            return Err(groot1::NO_BLACKBOARD.into());
        }
        let c = self.client.as_mut().ok_or("not connected")?;
        let all = c
            .blackboards(&[name.to_string()])
            .map_err(|e| e.to_string())?;
        // BehaviorTree.CPP sends an empty blackboard as nil.
        Ok(all
            .get(name)
            .filter(|v| !v.is_null())
            .cloned()
            .unwrap_or_else(|| serde_json::json!({})))
    }

    /// The status line's facts now.
    pub fn status(&self, per_second: f64, error: Option<String>) -> LiveStatus {
        LiveStatus {
            endpoint: self.endpoint.clone(),
            protocol: self.protocol,
            uuid: uuid_text(&self.uuid),
            connected: self.connected(),
            per_second,
            transitions: self.received(),
            gaps: self.gap_count,
            error,
            finished: self.finished.clone(),
        }
    }
}
