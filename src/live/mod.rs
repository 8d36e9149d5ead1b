//! A robot that is running now: BehaviorTree.CPP 4's Groot2 publisher
//! (ZeroMQ, port 1667), watched without changing what the robot does (no
//! hook or breakpoint is ever inserted). Transitions are polled from the
//! server's recording buffer often enough that it never fills; the run so
//! far is a session built by the same code as a `.btlog`'s.

pub mod groot1;
pub mod groot2;
pub mod recorder;
pub mod rep;
pub mod serve;
pub mod sub;
pub mod zmtp;

use crate::logs::btlog::Record;
use crate::logs::Protocol;
use crate::run::Status;
use crate::session::{Before, Session};
use crate::source::{Located, Warning};
use groot2::{Client, LiveError, SERVER_BUFFER};
use std::time::Duration;

/// How long a request may take before the server counts as gone (a
/// message naming the endpoint comes within 2 s).
pub const TIMEOUT: Duration = Duration::from_millis(1500);

/// A place in the run where transitions may be missing, and why.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Gap {
    /// Transitions received before it.
    pub at: usize,
    pub why: String,
}

/// A live run being watched.
pub struct Watch {
    pub endpoint: String,
    pub protocol: Protocol,
    /// A Groot2 robot's server.
    client: Option<Client>,
    /// A BehaviorTree.CPP 3 robot's publisher, and the publisher's port
    /// the user gave.
    groot1: Option<groot1::Link>,
    publisher: Option<u16>,
    /// The tree as the server sent it (XML with `_uid`s).
    pub xml: String,
    pub uuid: [u8; 16],
    /// The server's clock when recording started, µs since the epoch.
    t0: i64,
    /// Records received and not yet taken (`take_records`), and how many
    /// were taken before them.
    pub records: Vec<Record>,
    taken: usize,
    /// Gaps not yet taken (the live thread hands them over), and the last
    /// one's place and reason (a gap said again there is kept once).
    pub gaps: Vec<Gap>,
    last_gap: Option<(usize, u64)>,
    gap_count: usize,
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
    root: Option<(Status, Status)>,
    /// How the robot's run ended, when the robot went away after its root
    /// completed: the run is over, not cut off.
    pub finished: Option<String>,
    /// Replies larger than the buffer the server announced, in a row.
    oversized: usize,
}

/// Replies larger than the server's buffer, in a row, after which btx
/// leaves the robot: no publisher sends them, and one that floods would
/// take the time and the disk of every other robot watched.
pub const OVERSIZED_MAX: usize = 10;

/// How many times btx starts recording before it takes the statuses as
/// they are (a robot whose statuses never hold still that long).
const ATTACH_TRIES: usize = 5;

/// What `attach` found: the recording's start (the server's epoch µs), the
/// nodes' states then, the transitions recorded since, and whether the
/// states are exact.
struct Attached {
    t0: i64,
    /// Why the server's start time was not taken.
    note: Option<String>,
    before: Vec<Before>,
    first: Vec<groot2::Transition>,
    exact: bool,
}

/// The statuses when recording starts. They are read (`S`) before `r
/// start` and after it, and the transitions recorded meanwhile taken
/// (`t`): the states before are those at the start when some first of
/// those transitions lead from them to the states after. Otherwise a
/// transition fell between the first read and the start (it is not
/// recorded), and btx starts again.
fn attach(c: &mut Client) -> Result<Attached, LiveError> {
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
fn now_us() -> i64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_micros() as i64)
}

/// The recording's start as the server says it, or, when that cannot be
/// right (before 1970, or more than a day ahead of this machine's clock),
/// this machine's clock now, with a note saying so.
fn start_time(said: i64) -> (i64, Option<String>) {
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

fn attach_once(c: &mut Client) -> Result<Attached, LiveError> {
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
fn fnv(why: &str) -> u64 {
    why.bytes().fold(0xcbf29ce484222325, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x100000001b3)
    })
}

/// What a gap's reason says when btx read the statuses again after it.
const RESYNCED: &str = "; btx read every node's state again from the robot";

/// A UUID as text.
pub fn uuid_text(u: &[u8; 16]) -> String {
    u.iter().map(|b| format!("{b:02x}")).collect()
}

impl Watch {
    /// A watch with nothing received yet.
    fn new(endpoint: &str, protocol: Protocol, xml: String, uuid: [u8; 16], t0: i64) -> Watch {
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
        if overflowed {
            // Where the lost transitions left the nodes.
            let states = w.client.as_mut().map(|c| c.states()).transpose()?;
            if let Some(states) = states {
                w.resyncs.push((w.received(), states));
            }
        }
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
                let buffer = self.client.as_ref().map_or(SERVER_BUFFER, |c| c.buffer);
                let full = ts.len() >= buffer;
                let n = self.take(ts);
                if full || dropped.is_some() {
                    // The statuses now, as the lost transitions left them.
                    let states = self.client.as_mut().map(|c| c.states());
                    match states {
                        Some(Ok(states)) => self.resyncs.push((self.received(), states)),
                        Some(Err(e)) => {
                            self.client = None;
                            self.gap(format!("the connection dropped ({e})"));
                            return Err(e);
                        }
                        None => {}
                    }
                }
                Ok(n)
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
    fn end_of_run(&mut self) -> bool {
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
    fn completed(&self) -> Option<Status> {
        self.root.and_then(|(prev, now)| now.ended(prev))
    }

    /// Keeps the transitions of a `t` reply; how many came.
    fn take(&mut self, mut ts: Vec<groot2::Transition>) -> usize {
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
        self.keep(ts.into_iter().filter(|t| t.uid != 0));
        if zeroed > 0 {
            // Where the lost transitions left the nodes: without it a node
            // whose completion was lost would show RUNNING until its next
            // transition, and that one as a halt. A failed read leaves the
            // connection to the next poll.
            if let Some(Ok(states)) = self.client.as_mut().map(|c| c.states()) {
                self.resyncs.push((self.received(), states));
            }
        }
        n
    }

    /// Keeps transitions as records; how many.
    fn keep(&mut self, ts: impl Iterator<Item = groot2::Transition>) -> usize {
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
    fn gap(&mut self, why: String) {
        let at = self.received();
        let here = Some((at, fnv(&why)));
        if self.last_gap != here {
            self.last_gap = here;
            self.gap_count += 1;
            self.gaps.push(Gap { at, why });
        }
    }

    fn reconnect(&mut self) -> Result<(), LiveError> {
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
    fn rejoin(&mut self) -> Result<usize, LiveError> {
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

/// A blackboard of the robot (`B`), as the live thread last fetched it.
#[derive(Debug, Clone)]
pub struct LiveBlackboard {
    /// The blackboard's name (`Tree::blackboard_name`).
    pub name: String,
    pub fetched: std::time::Instant,
    /// Its entries, `{key: value}`, or why they could not be read.
    pub entries: Result<serde_json::Value, String>,
}

/// How often the blackboard asked for is fetched again.
pub const BLACKBOARD_EVERY: Duration = Duration::from_millis(300);

/// The blackboard the explorer wants (only while it shows one) and the
/// last one fetched, shared with the live thread.
#[derive(Default)]
struct Blackboards {
    want: Option<String>,
    got: Option<LiveBlackboard>,
}

/// What the polling thread hands over: the transitions numbered since the
/// last batch, the gaps and resyncs among them, the status.
struct Batch {
    /// Transitions received that this batch accounts for (numbered now,
    /// or held by the numbering thread for the rest of their tick).
    received: usize,
    numbered: Vec<(Record, u32)>,
    latency_us: Vec<i64>,
    gaps: Vec<Gap>,
    resyncs: Vec<(usize, Vec<Before>)>,
    notes: Vec<String>,
    status: LiveStatus,
}

/// A live run watched from a thread of its own, which does nothing but
/// empty the server's buffer every 2 to 25 ms, so that however long the
/// rest takes, no transition is lost; a second thread numbers the ticks as
/// transitions arrive (`logs::ticks::Stream`). The caller keeps the run
/// (`recorder::Recorder`): streamed to `OUT.partial`, and a bounded view.
pub struct Feed {
    pub protocol: Protocol,
    rx: std::sync::mpsc::Receiver<Batch>,
    /// Transitions handed to the threads and not taken here yet.
    in_flight: std::sync::Arc<std::sync::atomic::AtomicUsize>,
    /// Whether the last `poll` left batches waiting (its time was up).
    pub more: bool,
    stop: std::sync::Arc<std::sync::atomic::AtomicBool>,
    /// The polling thread, then the numbering thread.
    threads: Vec<std::thread::JoinHandle<()>>,
    pub status: LiveStatus,
    blackboards: std::sync::Arc<std::sync::Mutex<Blackboards>>,
    /// The tree's XML, the nodes' states when recording began.
    xml: String,
    before: Vec<(usize, Vec<Before>)>,
    recorder: recorder::Recorder,
    /// Every gap, as said (`btx watch` prints them as they come); bounded
    /// as the view is.
    pub gaps: Vec<Gap>,
    /// What the server said that cannot be right, or how ticks were told.
    pub notes: Vec<String>,
    /// A sample of the latency, µs from the robot to here (see
    /// `Watch::latency_us`): every `latency_every`-th, at most `LATENCY_KEPT`.
    latency_us: Vec<i64>,
    latency_every: usize,
    latency_seen: usize,
    /// Why the run could not be written (a full disk, `ulimit -f`): the
    /// caller stops watching and says it.
    pub write_error: Option<Located>,
    /// Whether the run grew since the last session built, and when that was.
    dirty: bool,
    built: std::time::Instant,
}

/// How often the server's buffer is emptied: as often as takes about
/// `POLL_TARGET` transitions each time (a quarter of the server's 1,000),
/// between `POLL_MIN` and `POLL_MAX` apart. At 10,000 transitions a second
/// that is every 25 ms; the buffer fills only past 500,000 a second. Fewer
/// requests also meet less often a race of BehaviorTree.CPP 4.8's publisher
/// (see `Watch::poll`).
pub const POLL_MIN: Duration = Duration::from_millis(2);
pub const POLL_MAX: Duration = Duration::from_millis(25);
const POLL_TARGET: f64 = 250.0;
/// Latency samples kept (for the median and the 99th percentile).
const LATENCY_KEPT: usize = 1 << 16;
/// Transitions that may wait between a feed's threads and its caller
/// (about 40 bytes each): 2.6 s at 100,000 a second.
pub const IN_FLIGHT_MAX: usize = 1 << 18;
/// The time one `Feed::poll` takes at most: with several robots, one that
/// floods cannot keep the caller from the others (the rest wait).
const POLL_TIME_MAX: Duration = Duration::from_millis(10);
/// The time `Feed::news` takes at most (the explorer's robot shown).
const NEWS_TIME_MAX: Duration = Duration::from_millis(60);

impl Feed {
    /// Connects (an error is returned at once), then watches from a thread;
    /// with `out`, the run streams to `OUT.partial` as its ticks are
    /// numbered, and is `OUT` once the feed stops.
    pub fn start(
        endpoint: &str,
        publisher: Option<u16>,
        out: Option<std::path::PathBuf>,
    ) -> Result<Feed, LiveError> {
        let mut w = Watch::start(endpoint, publisher)?;
        let protocol = w.protocol;
        // The tree is checked now, not at the first transition; the
        // states read with it are the tree's nodes' only (`states_of_nodes`).
        let shell =
            crate::logs::open_live(protocol, std::path::Path::new(endpoint), &w.xml, &[], &[])
                .map_err(|e| LiveError(format!("{endpoint}: the robot's tree: {}", e.message)))?;
        let odd = states_of_nodes(&mut w.resyncs, shell.tree.len());
        w.gaps.extend(odd);
        let name = protocol.source(endpoint);
        let mut header = shell.header.clone();
        if let Some((0, before)) = w.resyncs.first() {
            header.before = before.clone();
        }
        header.tree.path = Some(name.display().to_string());
        header.source.path = Some(name.display().to_string());
        let recorder = recorder::Recorder::new(&shell.tree, out.as_deref(), &header)
            .map_err(|e| LiveError(e.to_string()))?;
        let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        let halt = std::sync::Arc::clone(&stop);
        let status = w.status(0.0, None);
        let xml = w.xml.clone();
        let before = w.resyncs.clone();
        let blackboards = std::sync::Arc::new(std::sync::Mutex::new(Blackboards::default()));
        let shared = std::sync::Arc::clone(&blackboards);
        let tree = shell.tree;
        // What waits between the threads and the caller is bounded: past
        // `IN_FLIGHT_MAX` transitions the polling thread leaves the robot's
        // buffer unread (what it loses is said as a gap), never holds more.
        let (tx, rx) = std::sync::mpsc::channel();
        let (raw_tx, raw_rx) = std::sync::mpsc::channel();
        let in_flight = std::sync::Arc::new(std::sync::atomic::AtomicUsize::new(0));
        let flying = std::sync::Arc::clone(&in_flight);
        let numberer = std::thread::Builder::new()
            .name("btx-ticks".into())
            .spawn(move || numbering(&tree, &raw_rx, &tx))
            .map_err(|e| LiveError(format!("cannot start watching: {e}")))?;
        let poller = std::thread::Builder::new()
            .name("btx-live".into())
            .spawn(move || polling(&mut w, &raw_tx, &halt, &shared, &flying))
            .map_err(|e| LiveError(format!("cannot start watching: {e}")))?;
        Ok(Feed {
            protocol,
            rx,
            stop,
            threads: vec![poller, numberer],
            in_flight,
            more: false,
            status,
            blackboards,
            xml,
            before,
            recorder,
            gaps: Vec::new(),
            notes: Vec::new(),
            latency_us: Vec::new(),
            latency_every: 1,
            latency_seen: 0,
            write_error: None,
            dirty: false,
            built: std::time::Instant::now(),
        })
    }

    /// Keeps the rows of transitions as they are taken, for a caller that
    /// prints them (`take_rows`).
    pub fn print_rows(&mut self) {
        self.recorder.rows.get_or_insert_with(Vec::new);
    }

    /// Keeps no view of the run (`session` shows the tree only): a caller
    /// that prints the rows as they come needs none.
    pub fn without_view(&mut self) {
        self.recorder.view = false;
    }

    /// The rows taken since the last call (see `print_rows`).
    pub fn take_rows(&mut self) -> Vec<crate::session::LogRow> {
        self.recorder
            .rows
            .as_mut()
            .map(std::mem::take)
            .unwrap_or_default()
    }

    /// How the robot stands, in a few words (a robot picker's line):
    /// `finished (root SUCCESS)`, `running`, `failed`, `succeeded`, `idle`,
    /// or `unreachable (why)` while the connection is down.
    pub fn glance(&self) -> String {
        let (prev, now) = self.recorder.root();
        if self.status.finished.is_some() {
            return match now.ended(prev) {
                Some(done) => format!("finished (root {})", done.as_str()),
                None => "finished".into(),
            };
        }
        if !self.status.connected {
            return match &self.status.error {
                Some(e) => format!("unreachable ({e})"),
                None => "unreachable".into(),
            };
        }
        match now {
            Status::Running => "running".into(),
            Status::Failure => "failed".into(),
            Status::Success => "succeeded".into(),
            _ => match now.ended(prev) {
                Some(Status::Failure) => "idle after failing".into(),
                Some(_) => "idle after succeeding".into(),
                None => "idle".into(),
            },
        }
    }

    /// Transitions received so far.
    pub fn transitions(&self) -> usize {
        self.recorder.written
    }

    fn take(&mut self, b: Batch) -> bool {
        self.in_flight
            .fetch_sub(b.received, std::sync::atomic::Ordering::Relaxed);
        let grew = !b.numbered.is_empty() || !b.gaps.is_empty() || !b.notes.is_empty();
        for g in &b.gaps {
            if self.gaps.len() < recorder::VIEW_MARKS_MAX {
                self.gaps.push(g.clone());
            }
        }
        for g in b.gaps {
            self.recorder.gap(g);
        }
        for (at, states) in b.resyncs {
            self.recorder.resync(at, states);
        }
        self.notes.extend(b.notes);
        for l in b.latency_us {
            self.latency_seen += 1;
            if self.latency_seen.is_multiple_of(self.latency_every) {
                self.latency_us.push(l);
                if self.latency_us.len() >= LATENCY_KEPT {
                    // Every other one goes, and from now on one in twice as many is kept.
                    let mut i = 0;
                    self.latency_us.retain(|_| {
                        i += 1;
                        i % 2 == 0
                    });
                    self.latency_every *= 2;
                }
            }
        }
        self.status = b.status;
        if !self.recorder.abandoned() {
            if let Err(e) = self.recorder.take(&b.numbered) {
                // Nothing more is written: not the whole run either.
                self.recorder.abandon();
                self.write_error = Some(e);
            }
        }
        grew
    }

    /// Asks the live thread to fetch this blackboard (`B`) every
    /// `BLACKBOARD_EVERY`, or none (the explorer does not show one).
    pub fn want_blackboard(&self, name: Option<String>) {
        if let Ok(mut b) = self.blackboards.lock() {
            b.want = name;
        }
    }

    /// The blackboard last fetched, if it is the one wanted.
    pub fn blackboard(&self) -> Option<LiveBlackboard> {
        let b = self.blackboards.lock().ok()?;
        b.got.clone().filter(|g| b.want.as_ref() == Some(&g.name))
    }

    /// Takes what the thread handed over (written to `OUT.partial` as it
    /// comes); whether the run grew.
    pub fn poll(&mut self) -> bool {
        self.poll_for(POLL_TIME_MAX)
    }

    /// `poll`, taking at most `budget` (the explorer, which polls every
    /// 100 ms, takes most of it: the rest waits, bounded).
    pub fn poll_for(&mut self, budget: Duration) -> bool {
        let mut grew = false;
        let began = std::time::Instant::now();
        self.more = false;
        while let Ok(b) = self.rx.try_recv() {
            grew |= self.take(b);
            if began.elapsed() >= budget {
                self.more = true;
                break;
            }
        }
        grew
    }

    /// The run so far, when it grew and at most every `every` (building it
    /// takes time in proportion to the run).
    pub fn news(&mut self, every: Duration) -> Option<Result<Session, Located>> {
        self.dirty |= self.poll_for(NEWS_TIME_MAX);
        if !self.dirty || self.built.elapsed() < every {
            return None;
        }
        self.dirty = false;
        self.built = std::time::Instant::now();
        Some(self.session())
    }

    /// The run so far as a session (at most `recorder::VIEW_MAX`
    /// transitions), with each gap as a warning at its place.
    pub fn session(&self) -> Result<Session, Located> {
        let r = &self.recorder;
        let name = self.protocol.source(&self.status.endpoint);
        let mut resyncs = self.before.clone();
        resyncs.extend(r.resyncs.iter().cloned());
        let mut s = crate::logs::open_live_numbered(
            self.protocol,
            &name,
            &self.xml,
            &r.kept,
            &r.numbers,
            &resyncs,
        )?;
        s.index.gaps = r
            .gaps
            .iter()
            .map(|g| (g.at as u32, g.why.clone()))
            .collect();
        for n in &self.notes {
            s.warnings.push(Warning {
                location: crate::text::path(&name),
                message: n.clone(),
            });
        }
        for g in &r.gaps {
            s.warnings.push(Warning {
                location: format!("{}: transition {}", crate::text::path(&name), g.at + 1),
                message: format!("gap: {}", g.why),
            });
        }
        if r.unviewed > 0 {
            s.warnings.push(Warning {
                location: crate::text::path(&name),
                message: format!(
                    "the explorer holds the first {} transitions of a live run; the {} after them are {}",
                    recorder::VIEW_MAX,
                    r.unviewed,
                    match r.out() {
                        Some(o) => format!("in {} (open it once the run is over)", o.display()),
                        None => "not kept (watch with --out to keep them)".to_string(),
                    }
                ),
            });
        }
        Ok(s)
    }

    /// Stops watching, takes the last transitions, and with `out` finishes
    /// the session there: each run's session written (a robot's next run
    /// is a session of its own) and its transitions.
    pub fn stop(mut self) -> Result<Vec<(std::path::PathBuf, usize)>, Located> {
        self.finish()?;
        Ok(std::mem::take(&mut self.recorder.written_runs))
    }

    /// The median and the 99th percentile of the latency, in ms; `Err`
    /// with the median when the two clocks cannot be compared (a robot
    /// whose clock is a minute ahead of this machine's, or an hour behind,
    /// or timestamps that are no time: 2^48 − 1).
    pub fn latency_ms(&self) -> Option<Result<(f64, f64), f64>> {
        let mut l = self.latency_us.clone();
        if l.is_empty() {
            return None;
        }
        l.sort_unstable();
        let at = |q: f64| l[((l.len() - 1) as f64 * q).round() as usize] as f64 / 1000.0;
        let (median, p99) = (at(0.5), at(0.99));
        Some(if (-60_000.0..=3_600_000.0).contains(&median) {
            Ok((median, p99))
        } else {
            Err(median)
        })
    }

    /// Stops the thread and takes what it still had (its ticks numbered to
    /// the end).
    pub fn halt(&mut self) {
        self.stop.store(true, std::sync::atomic::Ordering::Relaxed);
        for t in self.threads.drain(..) {
            let _ = t.join();
        }
        while let Ok(b) = self.rx.try_recv() {
            self.dirty |= self.take(b);
        }
    }

    fn finish(&mut self) -> Result<Option<std::path::PathBuf>, Located> {
        self.halt();
        if let Some(e) = self.write_error.take() {
            return Err(e);
        }
        self.recorder.finish()
    }
}

impl Drop for Feed {
    fn drop(&mut self) {
        let _ = self.finish();
    }
}

/// What the polling thread hands to the numbering thread.
struct Raw {
    records: Vec<Record>,
    latency_us: Vec<i64>,
    gaps: Vec<Gap>,
    resyncs: Vec<(usize, Vec<Before>)>,
    notes: Vec<String>,
    status: LiveStatus,
    /// The last batch: the run is over, number everything.
    last: bool,
}

/// The polling thread: empties the server's buffer and hands over what
/// came, nothing else (a poll held up longer than the buffer lasts loses
/// transitions), until told to halt or the numbering thread is gone.
fn polling(
    w: &mut Watch,
    tx: &std::sync::mpsc::Sender<Raw>,
    halt: &std::sync::atomic::AtomicBool,
    shared: &std::sync::Mutex<Blackboards>,
    in_flight: &std::sync::atomic::AtomicUsize,
) {
    let mut rate = (std::time::Instant::now(), 0usize, 0.0f64);
    let mut sent = 0usize;
    // Handed over as they come, so that the thread holds none for long (a
    // resync holds every node's state); those at the start are the Feed's.
    w.resyncs.clear();
    let mut last = std::time::Instant::now();
    let mut polled = std::time::Instant::now();
    let mut every = POLL_MIN;
    // Transitions a second, smoothed: a robot ticks in bursts, and a poll
    // that falls between two must not set the next one 25 ms away (at
    // 100,000 a second the buffer lasts 10 ms).
    let mut per_s = 0.0f64;
    loop {
        let halting = halt.load(std::sync::atomic::Ordering::Relaxed);
        // Backpressure: the caller is behind; the robot's buffer waits.
        if !halting && in_flight.load(std::sync::atomic::Ordering::Relaxed) > IN_FLIGHT_MAX {
            std::thread::sleep(POLL_MIN);
            continue;
        }
        let since = polled.elapsed();
        polled = std::time::Instant::now();
        let error = match w.poll() {
            Ok(got) => {
                let now = got as f64 / since.as_secs_f64().max(1e-4);
                per_s = if now > per_s {
                    now
                } else {
                    0.9 * per_s + 0.1 * now
                };
                let want = POLL_TARGET / per_s.max(1.0);
                every = Duration::from_secs_f64(want)
                    .min(every.mul_f64(1.5))
                    .clamp(POLL_MIN, POLL_MAX);
                None
            }
            Err(e) => Some(e.to_string()),
        };
        // A robot gone after its run finished: nothing more will come.
        let halting = halting || w.finished.is_some();
        if error.is_none() && !halting {
            fetch_blackboard(w, shared);
        }
        let n = w.received();
        if rate.0.elapsed() >= Duration::from_secs(1) {
            let dt = rate.0.elapsed().as_secs_f64();
            rate = (std::time::Instant::now(), n, (n - rate.1) as f64 / dt);
        }
        let news = n > sent || !w.gaps.is_empty() || !w.notes.is_empty();
        if news || error.is_some() || last.elapsed() >= Duration::from_millis(500) || halting {
            last = std::time::Instant::now();
            let records = w.take_records();
            in_flight.fetch_add(records.len(), std::sync::atomic::Ordering::Relaxed);
            let raw = Raw {
                records,
                latency_us: std::mem::take(&mut w.latency_us),
                gaps: std::mem::take(&mut w.gaps),
                resyncs: std::mem::take(&mut w.resyncs),
                notes: std::mem::take(&mut w.notes),
                status: w.status(rate.2, error.clone()),
                last: halting,
            };
            sent = n;
            if tx.send(raw).is_err() || halting {
                break;
            }
        }
        std::thread::sleep(if error.is_some() {
            Duration::from_millis(500)
        } else {
            every.saturating_sub(polled.elapsed())
        });
    }
}

/// The numbering thread: numbers the ticks as transitions arrive
/// (`logs::ticks::Stream`) and hands them over, until the last batch.
fn numbering(
    tree: &crate::model::Tree,
    rx: &std::sync::mpsc::Receiver<Raw>,
    tx: &std::sync::mpsc::Sender<Batch>,
) {
    let mut ticks = crate::logs::ticks::Stream::new(tree);
    let (mut fell_back_said, mut capped_said, mut overlong_said) = (false, false, false);
    while let Ok(raw) = rx.recv() {
        let Raw {
            mut records,
            latency_us,
            mut gaps,
            mut resyncs,
            mut notes,
            status,
            last,
        } = raw;
        let received = records.len();
        let nodes = tree.len();
        no_node_left_out(&mut records, &mut gaps, nodes);
        gaps.extend(states_of_nodes(&mut resyncs, nodes));
        gaps.sort_by_key(|g| g.at);
        let mut numbered = numbered_around_gaps(&mut ticks, &records, &gaps);
        let quiet = records.is_empty();
        if last {
            numbered.extend(ticks.finish());
        } else if quiet {
            // No transition for half a second (the polling thread hands a
            // batch over at least that often).
            numbered.extend(ticks.settle());
        }
        if let (Some(at), false) = (ticks.fell_back, fell_back_said) {
            fell_back_said = true;
            notes.push(format!(
                "from transition {}, the replay could not follow the robot's run; ticks are told apart by timing",
                at + 1
            ));
        }
        if let (Some(at), false) = (ticks.overlong, overlong_said) {
            overlong_said = true;
            notes.push(format!(
                "from transition {}, the robot sent more than {} transitions with no tick's end: that tick is closed there, and ticks are told apart by timing",
                at + 1,
                crate::logs::ticks::TICK_RECORDS_MAX
            ));
        }
        if let (Some(at), false) = (ticks.capped, capped_said) {
            capped_said = true;
            notes.push(format!(
                "from transition {}, the timestamps claim more than {} ticks in which nothing changed; a gap counts as one tick",
                at + 1,
                crate::session::EMPTY_TICKS_MAX
            ));
        }
        let batch = Batch {
            received,
            numbered,
            latency_us,
            gaps,
            resyncs,
            notes,
            status,
        };
        if tx.send(batch).is_err() || last {
            break;
        }
    }
}

/// A uid the tree does not have names no node: the record is left out, as
/// a transition lost at its place.
fn no_node_left_out(records: &mut Vec<Record>, gaps: &mut Vec<Gap>, nodes: usize) {
    if records.iter().all(|r| recorder::is_node(r.uid, nodes)) {
        return;
    }
    for r in records.iter().filter(|r| !recorder::is_node(r.uid, nodes)) {
        gaps.push(Gap {
            at: r.offset,
            why: format!(
                "the server sent a transition of uid {}, which is no node of its tree ({nodes} nodes): it is left out",
                r.uid
            ),
        });
    }
    gaps.sort_by_key(|g| g.at);
    records.retain(|r| recorder::is_node(r.uid, nodes));
}

/// The records numbered into ticks: each gap's records before it are
/// numbered as they are, and ticks go by timing after it.
fn numbered_around_gaps(
    ticks: &mut crate::logs::ticks::Stream,
    records: &[Record],
    gaps: &[Gap],
) -> Vec<(Record, u32)> {
    let mut numbered = Vec::new();
    let mut from = 0;
    for g in gaps {
        let upto = records
            .iter()
            .position(|r| r.offset >= g.at)
            .unwrap_or(records.len())
            .max(from);
        numbered.extend(ticks.push(&records[from..upto]));
        numbered.extend(ticks.gap());
        from = upto;
    }
    numbered.extend(ticks.push(&records[from..]));
    numbered
}

/// Leaves out of `resyncs` the states of uids that are no node of a tree
/// of `nodes` nodes (a server's `S`, a Groot 1 message's statuses): a gap
/// says each place, as for a transition of no node.
fn states_of_nodes(resyncs: &mut [(usize, Vec<Before>)], nodes: usize) -> Vec<Gap> {
    let mut gaps = Vec::new();
    for (at, states) in resyncs {
        let mut odd = states
            .iter()
            .filter(|b| !recorder::is_node(b.uid, nodes))
            .map(|b| b.uid);
        if let Some(first) = odd.next() {
            let more = odd.count();
            gaps.push(Gap {
                at: *at,
                why: format!(
                    "the server sent the state of uid {first}{}, which is no node of its tree ({nodes} nodes): it is left out",
                    if more > 0 { format!(" and {more} more") } else { String::new() }
                ),
            });
            states.retain(|b| recorder::is_node(b.uid, nodes));
        }
    }
    gaps
}

/// Fetches the blackboard wanted, if it is due.
fn fetch_blackboard(w: &mut Watch, shared: &std::sync::Mutex<Blackboards>) {
    let due = shared.lock().ok().and_then(|b| {
        b.want.clone().filter(|n| {
            b.got
                .as_ref()
                .is_none_or(|g| g.name != *n || g.fetched.elapsed() >= BLACKBOARD_EVERY)
        })
    });
    let Some(name) = due else { return };
    let entries = w.blackboard(&name);
    if let Ok(mut b) = shared.lock() {
        b.got = Some(LiveBlackboard {
            name,
            fetched: std::time::Instant::now(),
            entries,
        });
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

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
    use std::sync::Arc;

    /// A Groot2 server of a two-node tree whose second `t` reply holds a
    /// zeroed record between two whole ones, as BehaviorTree.CPP 4.8's
    /// publisher sends when its buffer grows while it answers; `S` then
    /// says where the lost transition left the nodes.
    fn racing_server() -> (String, Arc<AtomicBool>) {
        let l = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
        let addr = l.local_addr().unwrap().to_string();
        let stop = Arc::new(AtomicBool::new(false));
        let ts = Arc::new(AtomicUsize::new(0));
        let answer: zmtp::Answer = Arc::new(move |parts: &[Vec<u8>]| {
            let mut h = parts[0].clone();
            h.extend_from_slice(&[7; 16]);
            let rec = |uid: u16, status: u8| {
                let mut r = 1_000u64.to_le_bytes()[..6].to_vec();
                r.extend_from_slice(&uid.to_le_bytes());
                r.push(status);
                r
            };
            let body = match parts[0][1] {
                b'T' => b"<root/>".to_vec(),
                b'r' => b"1700000000000000".to_vec(),
                b'S' if ts.load(Ordering::SeqCst) < 2 => vec![1, 0, 10, 2, 0, 10],
                // The root RUNNING, the leaf SUCCESS (its record was zeroed).
                b'S' => vec![1, 0, 1, 2, 0, 2],
                b't' => match ts.fetch_add(1, Ordering::SeqCst) {
                    1 => [rec(1, 1), vec![0; 9], rec(2, 1)].concat(),
                    _ => Vec::new(),
                },
                _ => Vec::new(),
            };
            vec![h, body]
        });
        let halt = Arc::clone(&stop);
        std::thread::spawn(move || rep::serve_rep(l, answer, &[], halt));
        (addr, stop)
    }

    #[test]
    fn zeroed_records_are_a_gap_after_which_every_nodes_state_is_read_again() {
        let (addr, stop) = racing_server();
        let mut w = Watch::start(&addr, None).unwrap();
        assert_eq!(w.poll().unwrap(), 3);
        let uids: Vec<u32> = w.records.iter().map(|r| r.uid).collect();
        assert_eq!(uids, vec![1, 2]);
        assert_eq!(w.gaps.len(), 1, "{:?}", w.gaps);
        assert!(
            w.gaps[0].why.contains("1 zeroed records") && w.gaps[0].why.ends_with(RESYNCED),
            "{:?}",
            w.gaps
        );
        // After the batch, the states the lost transition left.
        let (at, states) = w.resyncs.last().unwrap();
        assert_eq!(*at, 2);
        assert!(states
            .iter()
            .any(|b| b.uid == 2 && b.status == Status::Success));
        stop.store(true, std::sync::atomic::Ordering::Relaxed);
    }
}
