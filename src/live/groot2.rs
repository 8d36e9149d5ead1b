//! The Groot2 protocol of BehaviorTree.CPP 4 (`groot2_protocol.h`,
//! `groot2_publisher.cpp`), client side: multipart requests whose first part
//! is a 6-byte header `u8 protocol (2) | u8 type | u32 id`, replies whose
//! first part echoes it followed by the tree's 16-byte UUID, or the two
//! parts `error`, message.

use super::zmtp::{Req, ZmtpError};
use crate::run::Status;
use std::time::Duration;

pub const PROTOCOL: u8 = 2;
/// Groot2's port (`Groot2Publisher`'s default, Nav2's `groot_server_port`).
pub const DEFAULT_PORT: u16 = 1667;
/// The transitions the server keeps between two `t` requests; a reply this
/// long may have lost older ones. BehaviorTree.CPP's publisher keeps 1,000.
pub const SERVER_BUFFER: usize = 1000;
/// The READY property in which a server says it keeps another number of
/// transitions (`btx serve --buffer`); BehaviorTree.CPP's says none.
pub const BUFFER_PROPERTY: &[u8] = b"X-Transitions-Buffer";

/// One transition as the server records it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Transition {
    /// Microseconds since the recording started.
    pub time_us: i64,
    pub uid: u32,
    pub status: Status,
}

/// An error of the live client: the endpoint and what went wrong.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LiveError(pub String);

impl LiveError {
    /// Whether nothing answered at the address yet: a robot not up, which
    /// may come up later.
    /// (A Groot 1 robot whose server answers and whose publisher does
    /// not is up, and its publisher's port likely another: said at once.)
    pub fn not_up(&self) -> bool {
        (self.0.contains("nothing is listening there") || self.0.contains("cannot connect"))
            && !self.0.contains("the publisher of")
    }
}

impl std::fmt::Display for LiveError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for LiveError {}

impl From<ZmtpError> for LiveError {
    fn from(e: ZmtpError) -> Self {
        LiveError(e.to_string())
    }
}

/// `HOST:PORT` from `[HOST][:PORT]` (default 127.0.0.1:1667).
pub fn endpoint(spec: &str) -> String {
    let spec = spec.trim().trim_start_matches("tcp://");
    match spec.rsplit_once(':') {
        Some((h, p)) if !p.is_empty() && p.chars().all(|c| c.is_ascii_digit()) => {
            let h = if h.is_empty() { "127.0.0.1" } else { h };
            format!("{h}:{p}")
        }
        _ if spec.is_empty() => format!("127.0.0.1:{DEFAULT_PORT}"),
        _ => format!("{spec}:{DEFAULT_PORT}"),
    }
}

/// The request header of `kind` with `id`.
pub fn header(kind: u8, id: u32) -> [u8; 6] {
    let mut h = [0u8; 6];
    h[0] = PROTOCOL;
    h[1] = kind;
    h[2..].copy_from_slice(&id.to_le_bytes());
    h
}

/// A status byte of the protocol (IDLE, RUNNING, SUCCESS, FAILURE, SKIPPED;
/// in `S` replies IDLE after a status is 10 + that status).
pub(super) fn status_of(b: u8) -> Option<Status> {
    Some(match b {
        0 | 10..=14 => Status::Idle,
        1 => Status::Running,
        2 => Status::Success,
        3 => Status::Failure,
        4 => Status::Skipped,
        _ => return None,
    })
}

/// The 9-byte records of a `t` reply.
pub fn parse_transitions(body: &[u8]) -> Result<Vec<Transition>, String> {
    if !body.len().is_multiple_of(9) {
        return Err(format!(
            "a transitions reply of {} bytes is not whole 9-byte records",
            body.len()
        ));
    }
    body.chunks_exact(9)
        .enumerate()
        .map(|(i, r)| {
            let mut t = [0u8; 8];
            t[..6].copy_from_slice(&r[..6]);
            let status = status_of(r[8]).ok_or_else(|| {
                format!(
                    "record {} has status byte {}, which is no status",
                    i + 1,
                    r[8]
                )
            })?;
            Ok(Transition {
                time_us: i64::from_le_bytes(t),
                uid: u32::from(u16::from_le_bytes([r[6], r[7]])),
                status,
            })
        })
        .collect()
}

/// The `u16 uid | u8 code` records of an `S` reply, each code checked: a
/// status (0-4), or IDLE after a status (10 + that status).
pub fn parse_codes(body: &[u8]) -> Result<Vec<(u32, u8)>, String> {
    if !body.len().is_multiple_of(3) {
        return Err(format!(
            "a status reply of {} bytes is not whole 3-byte records",
            body.len()
        ));
    }
    body.chunks_exact(3)
        .map(|r| {
            let uid = u32::from(u16::from_le_bytes([r[0], r[1]]));
            status_of(r[2])
                .map(|_| (uid, r[2]))
                .ok_or_else(|| format!("node {uid} has status byte {}, which is no status", r[2]))
        })
        .collect()
}

/// The code `S` gives a node after a transition to `status` from `code`:
/// the server keeps IDLE as 10 + the status before it.
pub fn code_after(code: u8, status: Status) -> u8 {
    match status {
        Status::Idle if code >= 10 => code,
        Status::Idle => 10 + code,
        s => s.code(),
    }
}

/// The nodes' states of `S` codes: each node's status, and the status it
/// last completed with. Nodes IDLE and never done are left out.
pub fn states_of(codes: &[(u32, u8)]) -> Vec<crate::session::Before> {
    let mut out = Vec::new();
    for &(uid, code) in codes {
        let Some(status) = status_of(code) else {
            continue;
        };
        let done = match code {
            // Halted while RUNNING (11), or never done (10): what it last
            // completed with, if ever, is not said.
            1 | 10 | 11 => None,
            12 => Some(Status::Success),
            13 => Some(Status::Failure),
            14 => Some(Status::Skipped),
            _ => Some(status).filter(|s| *s != Status::Idle),
        };
        if status != Status::Idle || done.is_some() {
            out.push(crate::session::Before { uid, status, done });
        }
    }
    out
}

/// The nodes' states of an `S` reply (`parse_codes`, `states_of`).
pub fn parse_states(body: &[u8]) -> Result<Vec<crate::session::Before>, String> {
    parse_codes(body).map(|c| states_of(&c))
}

/// A `B` reply: MessagePack of a map from blackboard name to entries (nil
/// when none of the names is known).
pub fn decode_blackboards(body: &[u8]) -> Result<serde_json::Value, String> {
    match rmp_serde::from_slice::<serde_json::Value>(body) {
        Ok(serde_json::Value::Null) => Ok(serde_json::Value::Object(Default::default())),
        Ok(v @ serde_json::Value::Object(_)) => Ok(v),
        Ok(_) => Err("the blackboard reply is not a map of blackboards".into()),
        Err(e) => Err(format!(
            "the blackboard reply is not MessagePack that JSON can hold: {e}"
        )),
    }
}

/// The most transitions btx reads from one `t` reply: a hundred times the
/// publisher's buffer. A server that sends more in one reply loses them
/// (`Client::dropped`), and btx bounds what a peer makes it hold.
pub const TRANSITIONS_REPLY_MAX: usize = 100 * SERVER_BUFFER;
/// The most bytes of one blackboard reply (`B`) btx reads; a larger one is
/// not shown, and the explorer says so with its size.
pub const BLACKBOARD_REPLY_MAX: u64 = 1 << 20;

/// What a server answered when asked for its tree.
pub enum Served {
    /// A Groot2 server's XML, with `_uid` attributes.
    Xml(String),
    /// BehaviorTree.CPP 3's tree flatbuffer (Groot 1's protocol).
    Groot1(Vec<u8>),
}

/// A connection to a Groot2 server.
pub struct Client {
    req: Req,
    endpoint: String,
    next_id: u32,
    /// The tree's UUID as of the last reply.
    pub uuid: [u8; 16],
    /// A `t` reply larger than `TRANSITIONS_REPLY_MAX` records was dropped:
    /// its size in bytes (taken by the caller, who says the gap).
    pub dropped: Option<u64>,
    /// The transitions the server keeps between two `t`: a reply this long
    /// may have lost older ones.
    pub buffer: usize,
}

/// The buffer a server says it keeps: BehaviorTree.CPP's when it says
/// none, or nothing btx can use (not a number, 0, or more than a reply
/// btx reads).
fn buffer_of(said: Option<&[u8]>) -> usize {
    said.and_then(|v| std::str::from_utf8(v).ok()?.trim().parse::<usize>().ok())
        .filter(|n| (1..=TRANSITIONS_REPLY_MAX).contains(n))
        .unwrap_or(SERVER_BUFFER)
}

impl Client {
    pub fn connect(endpoint: &str, timeout: Duration) -> Result<Client, LiveError> {
        let req = Req::connect(endpoint, timeout)?;
        let buffer = buffer_of(req.property(BUFFER_PROPERTY));
        Ok(Client {
            req,
            endpoint: endpoint.to_string(),
            next_id: std::process::id().wrapping_mul(2_654_435_761),
            uuid: [0; 16],
            dropped: None,
            buffer,
        })
    }

    fn err(&self, m: impl std::fmt::Display) -> LiveError {
        LiveError(format!("{}: {m}", self.endpoint))
    }

    /// One request; the reply's parts after the header, or the size of a
    /// reply over `max` bytes (read through and dropped).
    fn call_max(
        &mut self,
        kind: u8,
        arg: Option<&[u8]>,
        max: u64,
    ) -> Result<Result<Vec<Vec<u8>>, super::zmtp::Oversize>, LiveError> {
        self.next_id = self.next_id.wrapping_add(1);
        let h = header(kind, self.next_id);
        let mut parts: Vec<&[u8]> = vec![&h];
        if let Some(a) = arg {
            parts.push(a);
        }
        let reply = match self.req.request_max(&parts, max)? {
            Ok(r) => r,
            Err(over) => return Ok(Err(over)),
        };
        self.groot2_reply(&h, reply).map(Ok)
    }

    /// A reply's parts after its header, which must echo the request's `h`.
    fn groot2_reply(
        &mut self,
        h: &[u8; 6],
        mut reply: Vec<Vec<u8>>,
    ) -> Result<Vec<Vec<u8>>, LiveError> {
        let first = reply.first().cloned().unwrap_or_default();
        if first == b"error" {
            let msg = reply
                .get(1)
                .map(|m| String::from_utf8_lossy(m).into_owned())
                .unwrap_or_default();
            return Err(self.err(format!("the server refused the request: {msg}")));
        }
        if first.len() != 22 || first[..6] != h[..] {
            return Err(self.err(
                "the reply is not a Groot2 reply (its header does not echo the request): is this a BehaviorTree.CPP 4 Groot2Publisher?",
            ));
        }
        self.uuid.copy_from_slice(&first[6..22]);
        reply.remove(0);
        Ok(reply)
    }

    /// `T`, asked of a server that may speak either protocol: a Groot2
    /// server answers the tree's XML; BehaviorTree.CPP 3's `PublisherZMQ`
    /// answers any request with its tree's flatbuffer, in one part.
    pub fn tree(&mut self) -> Result<Served, LiveError> {
        self.next_id = self.next_id.wrapping_add(1);
        let h = header(b'T', self.next_id);
        let mut reply = self.req.request(&[&h])?;
        if reply.len() == 1 && !reply[0].starts_with(&h) && reply[0] != b"error" {
            return Ok(Served::Groot1(reply.swap_remove(0)));
        }
        let mut parts = self.groot2_reply(&h, reply)?;
        if parts.is_empty() {
            return Err(self.err("the tree reply has no body"));
        }
        String::from_utf8(parts.swap_remove(0))
            .map(Served::Xml)
            .map_err(|_| self.err("the tree's XML is not UTF-8"))
    }

    fn one(&mut self, kind: u8, arg: Option<&[u8]>, what: &str) -> Result<Vec<u8>, LiveError> {
        self.one_max(kind, arg, what, super::zmtp::MESSAGE_MAX)?
            .map_err(|super::zmtp::Oversize(n)| {
                self.err(format!(
                    "the {what} reply is {n} bytes, more than btx reads ({})",
                    super::zmtp::MESSAGE_MAX
                ))
            })
    }

    fn one_max(
        &mut self,
        kind: u8,
        arg: Option<&[u8]>,
        what: &str,
        max: u64,
    ) -> Result<Result<Vec<u8>, super::zmtp::Oversize>, LiveError> {
        let mut r = match self.call_max(kind, arg, max)? {
            Ok(r) => r,
            Err(over) => return Ok(Err(over)),
        };
        if r.is_empty() {
            return Err(self.err(format!("the {what} reply has no body")));
        }
        Ok(Ok(r.swap_remove(0)))
    }

    /// `T`: the tree as XML, with `_uid` attributes.
    pub fn tree_xml(&mut self) -> Result<String, LiveError> {
        match self.tree()? {
            Served::Xml(xml) => Ok(xml),
            Served::Groot1(_) => Err(self.err(
                "the server now answers as BehaviorTree.CPP 3 (Groot 1), not Groot2: watch it anew",
            )),
        }
    }

    /// `r start`: starts recording; the server's clock then, in µs since the epoch.
    pub fn start_recording(&mut self) -> Result<i64, LiveError> {
        let b = self.one(b'r', Some(b"start"), "recording")?;
        String::from_utf8_lossy(&b)
            .trim()
            .parse()
            .map_err(|_| self.err("the recording reply is not a time in µs"))
    }

    /// `t`: the transitions since the last `t`.
    pub fn transitions(&mut self) -> Result<Vec<Transition>, LiveError> {
        // The reply's header (22 bytes) and the records.
        let max = 64 + 9 * TRANSITIONS_REPLY_MAX as u64;
        match self.one_max(b't', None, "transitions", max)? {
            Ok(b) => parse_transitions(&b).map_err(|m| self.err(m)),
            Err(super::zmtp::Oversize(n)) => {
                self.dropped = Some(n);
                Ok(Vec::new())
            }
        }
    }

    /// Every node's state now (`S`), as `parse_states` reads it.
    pub fn states(&mut self) -> Result<Vec<crate::session::Before>, LiveError> {
        self.codes().map(|c| states_of(&c))
    }

    /// `B`: the blackboards named (a subtree instance's `_fullpath`, the
    /// main tree's ID for the root), as JSON: `{name: {key: value}}`. The
    /// server sends MessagePack; a name it does not know is left out.
    pub fn blackboards(&mut self, names: &[String]) -> Result<serde_json::Value, LiveError> {
        let arg = names.join(";");
        match self.one_max(
            b'B',
            Some(arg.as_bytes()),
            "blackboard",
            BLACKBOARD_REPLY_MAX,
        )? {
            Ok(b) => decode_blackboards(&b).map_err(|m| self.err(m)),
            Err(super::zmtp::Oversize(n)) => Err(self.err(format!(
                "the blackboard is {} KiB, more than the {} KiB btx reads of one; not shown",
                n >> 10,
                BLACKBOARD_REPLY_MAX >> 10
            ))),
        }
    }

    /// Every node's `S` code now.
    pub fn codes(&mut self) -> Result<Vec<(u32, u8)>, LiveError> {
        let b = self.one(b'S', None, "status")?;
        parse_codes(&b).map_err(|m| self.err(m))
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_buffer_a_server_says_is_taken_when_btx_can_read_it() {
        assert_eq!(buffer_of(None), SERVER_BUFFER);
        assert_eq!(buffer_of(Some(b"20000")), 20_000);
        assert_eq!(buffer_of(Some(b"100000")), TRANSITIONS_REPLY_MAX);
        for odd in [&b"0"[..], b"100001", b"-5", b"lots", b"\xff"] {
            assert_eq!(buffer_of(Some(odd)), SERVER_BUFFER, "{odd:?}");
        }
    }

    use super::*;

    #[test]
    fn endpoints_default_to_loopback_and_groots_port() {
        assert_eq!(endpoint(""), "127.0.0.1:1667");
        assert_eq!(endpoint(":1777"), "127.0.0.1:1777");
        assert_eq!(endpoint("robot"), "robot:1667");
        assert_eq!(endpoint("tcp://10.0.0.2:1667"), "10.0.0.2:1667");
    }

    #[test]
    fn records_are_read_as_the_publisher_writes_them() {
        let mut b = Vec::new();
        b.extend_from_slice(&1_234_567u64.to_le_bytes()[..6]);
        b.extend_from_slice(&7u16.to_le_bytes());
        b.push(3);
        assert_eq!(
            parse_transitions(&b).unwrap(),
            vec![Transition {
                time_us: 1_234_567,
                uid: 7,
                status: Status::Failure
            }]
        );
        assert!(parse_transitions(&b[..8]).is_err());
        b[8] = 9;
        assert!(parse_transitions(&b).unwrap_err().contains("status byte 9"));
        // IDLE after SUCCESS is 12 in a status reply; IDLE never done (10)
        // and IDLE after a halt (11) say no completion.
        let b = |uid, status, done| crate::session::Before { uid, status, done };
        assert_eq!(
            parse_states(&[2, 0, 12, 3, 0, 1, 4, 0, 10, 5, 0, 11, 6, 0, 13, 7, 0, 3]).unwrap(),
            vec![
                b(2, Status::Idle, Some(Status::Success)),
                b(3, Status::Running, None),
                b(6, Status::Idle, Some(Status::Failure)),
                b(7, Status::Failure, Some(Status::Failure)),
            ]
        );
        assert!(parse_states(&[2, 0, 9])
            .unwrap_err()
            .contains("status byte 9"));
        assert_eq!(header(b'T', 1), [2, b'T', 1, 0, 0, 0]);
    }
}
