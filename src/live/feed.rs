//! A robot watched from threads of its own: one empties the server's
//! buffer, one numbers the ticks, and the caller takes batches (`Feed`),
//! records the run and asks for a blackboard.

use super::watch::*;
use super::*;
use crate::logs::btlog::Record;
use crate::logs::Protocol;
use crate::run::Status;
use crate::session::{Before, Session};
use crate::source::{Located, Warning};
use groot2::LiveError;
use std::time::Duration;

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
pub(super) struct Blackboards {
    pub(super) want: Option<String>,
    pub(super) got: Option<LiveBlackboard>,
}

/// What the polling thread hands over: the transitions numbered since the
/// last batch, the gaps and resyncs among them, the status.
pub(super) struct Batch {
    /// Transitions received that this batch accounts for (numbered now,
    /// or held by the numbering thread for the rest of their tick).
    pub(super) received: usize,
    pub(super) numbered: Vec<(Record, u32)>,
    pub(super) latency_us: Vec<i64>,
    pub(super) gaps: Vec<Gap>,
    pub(super) resyncs: Vec<(usize, Vec<Before>)>,
    pub(super) notes: Vec<String>,
    pub(super) status: LiveStatus,
}

/// A live run watched from a thread of its own, which does nothing but
/// empty the server's buffer every 2 to 25 ms, so that however long the
/// rest takes, no transition is lost; a second thread numbers the ticks as
/// transitions arrive (`logs::ticks::Stream`). The caller keeps the run
/// (`recorder::Recorder`): streamed to `OUT.partial`, and a bounded view.
pub struct Feed {
    pub protocol: Protocol,
    pub(super) rx: std::sync::mpsc::Receiver<Batch>,
    /// Transitions handed to the threads and not taken here yet.
    pub(super) in_flight: std::sync::Arc<std::sync::atomic::AtomicUsize>,
    /// Whether the last `poll` left batches waiting (its time was up).
    pub more: bool,
    pub(super) stop: std::sync::Arc<std::sync::atomic::AtomicBool>,
    /// The polling thread, then the numbering thread.
    pub(super) threads: Vec<std::thread::JoinHandle<()>>,
    pub status: LiveStatus,
    pub(super) blackboards: std::sync::Arc<std::sync::Mutex<Blackboards>>,
    /// The tree's XML, the nodes' states when recording began.
    pub(super) xml: String,
    pub(super) before: Vec<(usize, Vec<Before>)>,
    pub(super) recorder: recorder::Recorder,
    /// Every gap, as said (`btx watch` prints them as they come); bounded
    /// as the view is.
    pub gaps: Vec<Gap>,
    /// What the server said that cannot be right, or how ticks were told.
    pub notes: Vec<String>,
    /// A sample of the latency, µs from the robot to here (see
    /// `Watch::latency_us`): every `latency_every`-th, at most `LATENCY_KEPT`.
    pub(super) latency_us: Vec<i64>,
    pub(super) latency_every: usize,
    pub(super) latency_seen: usize,
    /// Why the run could not be written (a full disk, `ulimit -f`): the
    /// caller stops watching and says it.
    pub write_error: Option<Located>,
    /// Whether the run grew since the last session built, and when that was.
    pub(super) dirty: bool,
    pub(super) built: std::time::Instant,
}

/// How often the server's buffer is emptied: as often as takes about
/// `POLL_TARGET` transitions each time (a quarter of the server's 1,000),
/// between `POLL_MIN` and `POLL_MAX` apart. At 10,000 transitions a second
/// that is every 25 ms; the buffer fills only past 500,000 a second. Fewer
/// requests also meet less often a race of BehaviorTree.CPP 4.8's publisher
/// (see `Watch::poll`).
pub const POLL_MIN: Duration = Duration::from_millis(2);
pub const POLL_MAX: Duration = Duration::from_millis(25);
pub(super) const POLL_TARGET: f64 = 250.0;
/// Latency samples kept (for the median and the 99th percentile).
pub(super) const LATENCY_KEPT: usize = 1 << 16;
/// Transitions that may wait between a feed's threads and its caller
/// (about 40 bytes each): 2.6 s at 100,000 a second.
pub const IN_FLIGHT_MAX: usize = 1 << 18;
/// The time one `Feed::poll` takes at most: with several robots, one that
/// floods cannot keep the caller from the others (the rest wait).
pub(super) const POLL_TIME_MAX: Duration = Duration::from_millis(10);
/// The time `Feed::news` takes at most (the explorer's robot shown).
pub(super) const NEWS_TIME_MAX: Duration = Duration::from_millis(60);

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

    pub(super) fn take(&mut self, b: Batch) -> bool {
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

    pub(super) fn finish(&mut self) -> Result<Option<std::path::PathBuf>, Located> {
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
pub(super) struct Raw {
    pub(super) records: Vec<Record>,
    pub(super) latency_us: Vec<i64>,
    pub(super) gaps: Vec<Gap>,
    pub(super) resyncs: Vec<(usize, Vec<Before>)>,
    pub(super) notes: Vec<String>,
    pub(super) status: LiveStatus,
    /// The last batch: the run is over, number everything.
    pub(super) last: bool,
}

/// The polling thread: empties the server's buffer and hands over what
/// came, nothing else (a poll held up longer than the buffer lasts loses
/// transitions), until told to halt or the numbering thread is gone.
pub(super) fn polling(
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
pub(super) fn numbering(
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
pub(super) fn no_node_left_out(records: &mut Vec<Record>, gaps: &mut Vec<Gap>, nodes: usize) {
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
pub(super) fn numbered_around_gaps(
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
pub(super) fn states_of_nodes(resyncs: &mut [(usize, Vec<Before>)], nodes: usize) -> Vec<Gap> {
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
pub(super) fn fetch_blackboard(w: &mut Watch, shared: &std::sync::Mutex<Blackboards>) {
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
