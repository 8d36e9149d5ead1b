//! The server side of the Groot2 protocol: a recorded run (a session or a
//! log) replayed in real time, so that Groot2, btview or a second btx can
//! watch any run btx knows, and the live mode can be tried without a robot.
//! It answers `T` (the instantiated tree with `_uid`s), `S` (every node's
//! status now, IDLE as 10 + the status before it), `r start|stop`, `t` (the
//! transitions since the last `t`, as the publisher's 9-byte records, at
//! most the last 1,000 as BehaviorTree.CPP keeps, or as many as `--buffer`
//! says, which the READY command tells the client) and `B` (the blackboards' entries the run shows
//! at that moment, as MessagePack).
//! Hooks and breakpoints are refused, as btx never changes a run. The run
//! starts playing when the first client starts recording.

use super::groot2::{PROTOCOL, SERVER_BUFFER};
use crate::run::Status;
use crate::session::Session;
use std::sync::Mutex;
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

/// The replay's clock and what it has handed out.
struct State {
    /// When the replay started (tick 1 begins then): at the first `r start`,
    /// so that the first client to record sees the run from its start.
    started: Option<Instant>,
    /// When recording started, and the position handed out by `t` so far.
    recording: Option<(Instant, usize)>,
    /// The last `S` codes worked out: at which position, after how many
    /// of the run's resyncs (a client asks again and again as the run goes
    /// on, and each answer goes on from the last).
    codes: Option<(usize, usize, Vec<u8>)>,
}

/// A recorded run served as a robot that is running now.
pub struct Replay {
    session: Session,
    xml: String,
    /// Simulated time of one tick.
    tick: Duration,
    uuid: [u8; 16],
    /// The most transitions one `t` hands out (the last ones).
    buffer: usize,
    state: Mutex<State>,
}

/// The part of a tick period over which its transitions are played.
const PLAYING: f64 = 0.5;

/// The tick period of a session that records none (an imported log).
pub const DEFAULT_TICK: Duration = Duration::from_millis(100);

impl Replay {
    /// `speed` times as fast as the run's tick period.
    pub fn new(session: Session, speed: f64) -> Replay {
        let ms = match session.header.tick_ms {
            0 => DEFAULT_TICK.as_secs_f64() * 1000.0,
            t => t as f64,
        };
        let tick = Duration::from_secs_f64(ms / 1000.0 / speed.clamp(1e-3, 1e6));
        let xml = crate::xml::to_instantiated_xml(&session.tree);
        let mut uuid = [0u8; 16];
        let seed = crate::session::format::fnv64(&xml);
        uuid[..16].copy_from_slice(&seed.as_bytes()[..16]);
        Replay {
            session,
            xml,
            tick,
            uuid,
            buffer: SERVER_BUFFER,
            state: Mutex::new(State {
                started: None,
                recording: None,
                codes: None,
            }),
        }
    }

    /// Keeping the last `n` transitions between two `t`, not 1,000 (at
    /// least 1, at most what a client reads of one reply).
    pub fn with_buffer(mut self, n: usize) -> Replay {
        self.buffer = n.clamp(1, super::groot2::TRANSITIONS_REPLY_MAX);
        self
    }

    /// The transitions kept between two `t`.
    pub fn buffer(&self) -> usize {
        self.buffer
    }

    pub fn session(&self) -> &Session {
        &self.session
    }

    /// Transitions played by `now`: those of every tick over, and of the
    /// tick going on, as many as its first half has played. A robot takes
    /// time to tick, and so does the replay: a tick of thousands of
    /// transitions reaches a client over several `t` requests, never more
    /// than the publisher's buffer at once (were it played at once, the
    /// client could keep only its last 1,000).
    fn position(&self, started: Instant, now: Instant) -> usize {
        let idx = &self.session.index;
        let x = now.saturating_duration_since(started).as_secs_f64() / self.tick.as_secs_f64();
        let over = x.floor();
        if over >= f64::from(idx.ticks()) {
            return idx.transitions.len();
        }
        let r = idx.tick_range(over as u32 + 1);
        let played = ((x - over) / PLAYING).min(1.0);
        r.start + (r.len() as f64 * played).ceil() as usize
    }

    /// When tick `t` began.
    fn tick_start(&self, started: Instant, t: u32) -> Instant {
        started + self.tick.mul_f64(f64::from(t.saturating_sub(1)))
    }

    fn header(&self, request: &[u8]) -> Vec<u8> {
        let mut h = request.to_vec();
        h[0] = PROTOCOL;
        h.extend_from_slice(&self.uuid);
        h
    }

    /// The reply to one request.
    pub fn answer(&self, parts: &[Vec<u8>]) -> Vec<Vec<u8>> {
        let error = |m: &str| vec![b"error".to_vec(), m.as_bytes().to_vec()];
        let Some(h) = parts.first().filter(|h| h.len() == 6) else {
            return error("wrong request header");
        };
        let now = Instant::now();
        let mut st = self.state.lock().unwrap_or_else(|e| e.into_inner());
        // The first recording starts the run: it sees tick 1 whole.
        let first = h[1] == b'r'
            && parts.get(1).map(Vec::as_slice) == Some(b"start")
            && st.started.is_none();
        if first {
            st.started = Some(now);
        }
        let started = st.started.unwrap_or(now);
        let pos = if st.started.is_some() {
            self.position(started, now)
        } else {
            0
        };
        let body = match h[1] {
            b'T' => self.xml.as_bytes().to_vec(),
            b'S' => self.statuses(&mut st.codes, pos),
            b'B' => self.blackboards(pos, parts.get(1).map_or(&[][..], Vec::as_slice)),
            b'r' => match parts.get(1).map(Vec::as_slice) {
                Some(b"start") => {
                    st.recording = Some((now, if first { 0 } else { pos }));
                    let epoch = SystemTime::now()
                        .duration_since(UNIX_EPOCH)
                        .unwrap_or_default()
                        .as_micros();
                    epoch.to_string().into_bytes()
                }
                Some(b"stop") => {
                    st.recording = None;
                    Vec::new()
                }
                _ => return error("must be 2 parts message"),
            },
            b't' => match st.recording {
                Some((t0, from)) => {
                    let out = self.records(started, t0, from, pos);
                    st.recording = Some((t0, pos));
                    out
                }
                None => Vec::new(),
            },
            _ => return error("Request not recognized"),
        };
        vec![self.header(h), body]
    }

    /// `u16 uid | u8 code` for every node at position `pos`: its status,
    /// IDLE as 10 + the status before it (`groot2::code_after`), from the
    /// states the run was recorded from.
    fn statuses(&self, cache: &mut Option<(usize, usize, Vec<u8>)>, pos: usize) -> Vec<u8> {
        let idx = &self.session.index;
        let of = |state: (Status, Option<Status>)| match state {
            (Status::Idle, Some(done)) => 10 + done.code(),
            (s, _) => s.code(),
        };
        let nodes = self.session.tree.len();
        let resyncs: Vec<_> = idx.resyncs().into_iter().filter(|r| r.0 > 0).collect();
        let read = |states: &[crate::session::Before]| {
            let mut code = vec![10; nodes];
            for b in states {
                code[b.uid as usize - 1] = of((b.status, b.done));
            }
            code
        };
        // From the last answer when it is not past `pos`, else from the start.
        let (from, mut applied, mut code) = match cache.take() {
            Some((p, a, c)) if p <= pos => (p, a, c),
            _ => (
                0,
                0,
                (1..=nodes as u32).map(|u| of(idx.before(u))).collect(),
            ),
        };
        for i in from..=pos {
            while let Some((_, states)) = resyncs.get(applied).filter(|r| r.0 as usize <= i) {
                code = read(states);
                applied += 1;
            }
            if let Some(t) = idx.transitions[..pos].get(i) {
                let c = &mut code[t.uid as usize - 1];
                *c = super::groot2::code_after(*c, t.status);
            }
        }
        *cache = Some((pos, applied, code.clone()));
        let mut out = Vec::with_capacity(3 * code.len());
        for (i, c) in code.iter().enumerate() {
            out.extend_from_slice(&(i as u16 + 1).to_le_bytes());
            out.push(*c);
        }
        out
    }

    /// `B`: MessagePack of `{name: {key: value}}` for the blackboards named
    /// (`;` apart) that the run has entries in at position `pos`.
    fn blackboards(&self, pos: usize, names: &[u8]) -> Vec<u8> {
        let names = String::from_utf8_lossy(names);
        let tree = &self.session.tree;
        let at = self.session.index.at(pos as u32);
        let mut out = serde_json::Map::new();
        for name in names.split(';').filter(|n| !n.is_empty()) {
            let Some(scope) = (0..tree.scopes.len()).find(|&s| tree.blackboard_name(s) == name)
            else {
                continue;
            };
            let entries: serde_json::Map<String, serde_json::Value> = at
                .entries()
                .into_iter()
                .filter(|(e, _)| e.scope == scope)
                .map(|(e, v)| (e.key.clone(), v.clone()))
                .collect();
            out.insert(name.to_string(), serde_json::Value::Object(entries));
        }
        rmp_serde::to_vec_named(&serde_json::Value::Object(out)).unwrap_or_else(|_| vec![0x80])
    }

    /// The 9-byte records of transitions `from..to`, timed from `t0`; at
    /// most the last `buffer`, as the publisher keeps.
    fn records(&self, started: Instant, t0: Instant, from: usize, to: usize) -> Vec<u8> {
        let from = from.max(to.saturating_sub(self.buffer));
        let mut out = Vec::with_capacity(9 * (to - from));
        for t in &self.session.index.transitions[from..to] {
            let at = self.tick_start(started, t.tick);
            let us = at.saturating_duration_since(t0).as_micros() as u64;
            out.extend_from_slice(&us.to_le_bytes()[..6]);
            out.extend_from_slice(&(t.uid as u16).to_le_bytes());
            out.push(t.status.code());
        }
        out
    }

    /// Whether every tick has been played.
    pub fn over(&self) -> bool {
        let st = self.state.lock().unwrap_or_else(|e| e.into_inner());
        st.started.is_some_and(|s| {
            self.position(s, Instant::now()) >= self.session.index.transitions.len()
        })
    }
}
