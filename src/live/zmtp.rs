//! A ZeroMQ REQ socket over TCP, as ZMTP 3.0 (RFC 23) defines it with the
//! NULL mechanism: the greeting, the READY handshake, and multipart
//! messages framed with a flags byte and a size. This is all of ZeroMQ the
//! Groot2 protocol needs, written against the specification so that every
//! read has a deadline and every length a bound: a server that never
//! answers, answers garbage or answers gigabytes gives an error naming the
//! endpoint, never a hang, a panic or an allocation the reply did not earn.
//!
//! (The pure-Rust `zeromq` crate asserts on a malformed reply and needs an
//! async runtime; the `zmq` crate builds libzmq with CMake, which a fresh
//! machine does not have.)

use std::io::{Read, Write};
use std::net::{TcpStream, ToSocketAddrs};
use std::time::{Duration, Instant};

/// The largest frame btx accepts (a tree's XML, a blackboard dump).
pub const FRAME_MAX: u64 = 64 << 20;
/// The most bytes a message may hold across its parts, unless the caller
/// bounds it lower (`Req::request_max`).
pub const MESSAGE_MAX: u64 = FRAME_MAX;
/// The most bytes a request to `serve_rep` may hold: a Groot2 request is
/// a header and at most a list of blackboard names.
pub const REQUEST_MAX: u64 = 64 << 10;
/// The most clients `serve_rep` serves at once; more are refused.
pub const CONNECTIONS_MAX: usize = 64;
/// A client of `serve_rep` that sends no request for this long is
/// disconnected (Groot2's heartbeat: its publisher drops hooks after it).
pub const IDLE_MAX: Duration = Duration::from_secs(5);

/// A message larger than its bound: read through and dropped, so that the
/// connection stays usable; how many bytes it had.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Oversize(pub u64);
/// The most frames in one reply.
pub const PARTS_MAX: usize = 16;

/// Why a request got no reply.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ZmtpError {
    pub endpoint: String,
    pub message: String,
}

impl std::fmt::Display for ZmtpError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.endpoint, self.message)
    }
}

impl std::error::Error for ZmtpError {}

/// A connected REQ socket.
pub struct Req {
    pub(super) stream: TcpStream,
    endpoint: String,
    timeout: Duration,
    /// The metadata of the server's READY (its properties).
    ready: Vec<u8>,
}

pub(super) const SIGNATURE_END: u8 = 0x7F;
pub(super) const MORE: u8 = 0x01;
pub(super) const LONG: u8 = 0x02;
pub(super) const COMMAND: u8 = 0x04;

impl Req {
    /// Connects to `host:port` and does the ZMTP handshake, each step
    /// within `timeout`.
    pub fn connect(endpoint: &str, timeout: Duration) -> Result<Req, ZmtpError> {
        Req::open(endpoint, timeout, b"REQ", &[b"REP", b"ROUTER"])
    }

    /// Connects and does the handshake as a socket of type `ours`, to a
    /// peer of one of the types `peers`.
    pub(super) fn open(
        endpoint: &str,
        timeout: Duration,
        ours: &[u8],
        peers: &[&[u8]],
    ) -> Result<Req, ZmtpError> {
        let err = |m: String| ZmtpError {
            endpoint: endpoint.to_string(),
            message: m,
        };
        let addrs: Vec<_> = endpoint
            .to_socket_addrs()
            .map_err(|e| err(format!("cannot resolve the address: {e}")))?
            .collect();
        let mut last = None;
        let mut stream = None;
        for a in &addrs {
            match TcpStream::connect_timeout(a, timeout) {
                Ok(s) => {
                    stream = Some(s);
                    break;
                }
                Err(e) => last = Some(e),
            }
        }
        let stream = stream.ok_or_else(|| {
            err(match last {
                Some(e) if e.kind() == std::io::ErrorKind::ConnectionRefused => {
                    "nothing is listening there (connection refused)".into()
                }
                Some(e) => format!("cannot connect: {e}"),
                None => "the address resolves to nothing".into(),
            })
        })?;
        let _ = stream.set_nodelay(true);
        let mut req = Req {
            stream,
            endpoint: endpoint.to_string(),
            timeout,
            ready: Vec::new(),
        };
        req.handshake(ours, peers)?;
        Ok(req)
    }

    /// A property the server's READY carried.
    pub fn property(&self, name: &[u8]) -> Option<&[u8]> {
        property(&self.ready, name)
    }

    pub(super) fn err(&self, m: impl Into<String>) -> ZmtpError {
        ZmtpError {
            endpoint: self.endpoint.clone(),
            message: m.into(),
        }
    }

    pub(super) fn write_all(&mut self, bytes: &[u8]) -> Result<(), ZmtpError> {
        self.stream
            .set_write_timeout(Some(self.timeout))
            .and_then(|()| self.stream.write_all(bytes))
            .map_err(|e| self.err(format!("the connection failed while sending: {e}")))
    }

    /// Reads exactly `buf.len()` bytes before `deadline`.
    fn read_exact(
        &mut self,
        buf: &mut [u8],
        deadline: Instant,
        what: &str,
    ) -> Result<(), ZmtpError> {
        let mut got = 0;
        while got < buf.len() {
            let left = deadline.saturating_duration_since(Instant::now());
            if left.is_zero() {
                return Err(self.err(format!(
                    "no answer within {} s ({what})",
                    self.timeout.as_secs_f64()
                )));
            }
            self.stream
                .set_read_timeout(Some(left))
                .map_err(|e| self.err(e.to_string()))?;
            match self.stream.read(&mut buf[got..]) {
                Ok(0) => return Err(self.err(format!("the server closed the connection ({what})"))),
                Ok(n) => got += n,
                Err(e)
                    if matches!(
                        e.kind(),
                        std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
                    ) => {}
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => return Err(self.err(format!("the connection failed ({what}): {e}"))),
            }
        }
        Ok(())
    }

    /// The greeting and READY, as `ours`; the peer must be one of `peers`.
    fn handshake(&mut self, ours: &[u8], peers: &[&[u8]]) -> Result<(), ZmtpError> {
        self.write_all(&greeting())?;
        let deadline = Instant::now() + self.timeout;
        let mut peer = [0u8; 64];
        self.read_exact(&mut peer[..10], deadline, "the ZMTP greeting")?;
        if peer[0] != 0xFF || peer[9] & 1 != 1 {
            return Err(
                self.err("this is not a ZeroMQ server (its first bytes are not a ZMTP greeting)")
            );
        }
        self.read_exact(&mut peer[10..], deadline, "the ZMTP greeting")?;
        if peer[10] < 3 {
            return Err(self.err(format!(
                "the server speaks ZMTP {}.{}; btx needs 3.0 or later",
                peer[10], peer[11]
            )));
        }
        if &peer[12..16] != b"NULL" {
            return Err(
                self.err("the server asks for a security mechanism btx does not have (only NULL)")
            );
        }
        // READY, with our socket type.
        let frame = ready(ours, &[]);
        self.write_all(&frame)?;
        let (flags, body) = self.read_frame(deadline, "the READY command")?;
        if flags & COMMAND == 0 || !body.starts_with(b"\x05READY") {
            return Err(self.err("the server did not send READY after the greeting"));
        }
        self.ready = body[6..].to_vec();
        if let Some(t) = property(&body[6..], b"Socket-Type") {
            if !peers.contains(&t) {
                return Err(self.err(format!(
                    "the peer's socket is {}, which cannot talk to a {} socket",
                    String::from_utf8_lossy(t),
                    String::from_utf8_lossy(ours)
                )));
            }
        }
        Ok(())
    }

    /// A frame; past `budget` bytes its body is read and dropped (`None`).
    fn read_frame_within(
        &mut self,
        deadline: Instant,
        what: &str,
        budget: u64,
    ) -> Result<(u8, u64, Option<Vec<u8>>), ZmtpError> {
        let (flags, size) = self.read_frame_head(deadline, what)?;
        if size > budget {
            let mut sink = [0u8; 1 << 16];
            let mut left = size;
            while left > 0 {
                let n = left.min(sink.len() as u64) as usize;
                self.read_exact(&mut sink[..n], deadline, what)?;
                left -= n as u64;
            }
            return Ok((flags, size, None));
        }
        let mut body = vec![0u8; size as usize];
        self.read_exact(&mut body, deadline, what)?;
        Ok((flags, size, Some(body)))
    }

    fn read_frame(&mut self, deadline: Instant, what: &str) -> Result<(u8, Vec<u8>), ZmtpError> {
        let (flags, _, body) = self.read_frame_within(deadline, what, FRAME_MAX)?;
        Ok((flags, body.unwrap_or_default()))
    }

    /// A frame's flags and size, checked.
    fn read_frame_head(&mut self, deadline: Instant, what: &str) -> Result<(u8, u64), ZmtpError> {
        let mut flags = [0u8; 1];
        self.read_exact(&mut flags, deadline, what)?;
        let flags = flags[0];
        if flags & !(MORE | LONG | COMMAND) != 0 {
            return Err(self.err(format!("a frame has unknown flags {flags:#04x} ({what})")));
        }
        let size = if flags & LONG != 0 {
            let mut b = [0u8; 8];
            self.read_exact(&mut b, deadline, what)?;
            u64::from_be_bytes(b)
        } else {
            let mut b = [0u8; 1];
            self.read_exact(&mut b, deadline, what)?;
            u64::from(b[0])
        };
        if size > FRAME_MAX {
            return Err(self.err(format!(
                "a frame of {size} bytes is more than btx accepts ({FRAME_MAX}) ({what})"
            )));
        }
        Ok((flags, size))
    }

    /// Sends an empty delimiter frame (as REQ and REP put before every
    /// message), then the parts.
    fn send(&mut self, parts: &[&[u8]]) -> Result<(), ZmtpError> {
        self.write_all(&message(parts))
    }

    /// Sends a multipart request and returns the reply's parts.
    pub fn request(&mut self, parts: &[&[u8]]) -> Result<Vec<Vec<u8>>, ZmtpError> {
        self.request_max(parts, MESSAGE_MAX).and_then(|r| {
            r.map_err(|Oversize(n)| {
                self.err(format!(
                    "a reply of {n} bytes is more than btx accepts ({MESSAGE_MAX})"
                ))
            })
        })
    }

    /// Sends a multipart request; the reply's parts, or how big it was
    /// when it held more than `max` bytes (read through and dropped).
    pub fn request_max(
        &mut self,
        parts: &[&[u8]],
        max: u64,
    ) -> Result<Result<Vec<Vec<u8>>, Oversize>, ZmtpError> {
        self.send(parts)?;
        let deadline = Instant::now() + self.timeout;
        self.receive(deadline, max)
    }

    /// A message's parts after its empty delimiter, read before `deadline`;
    /// past `max` bytes across its parts, the rest is read and dropped.
    fn receive(
        &mut self,
        deadline: Instant,
        max: u64,
    ) -> Result<Result<Vec<Vec<u8>>, Oversize>, ZmtpError> {
        let mut reply = Vec::new();
        let mut delimited = false;
        let mut total = 0u64;
        let mut over = false;
        loop {
            let budget = if over { 0 } else { max - total };
            let (flags, size, body) = self.read_frame_within(deadline, "the reply", budget)?;
            if flags & COMMAND != 0 {
                // PING and the like carry no reply: skip them.
                continue;
            }
            total = total.saturating_add(size);
            let Some(body) = body.filter(|_| !over) else {
                over = true;
                reply.clear();
                if flags & MORE == 0 {
                    return Ok(Err(Oversize(total)));
                }
                continue;
            };
            if !delimited {
                if !body.is_empty() {
                    return Err(self.err("the message does not start with the empty delimiter"));
                }
                delimited = true;
            } else {
                reply.push(body);
                if reply.len() > PARTS_MAX {
                    return Err(self.err(format!("the message has more than {PARTS_MAX} parts")));
                }
            }
            if flags & MORE == 0 {
                break;
            }
        }
        Ok(Ok(reply))
    }
}

/// What a server does with a request's parts: the reply's parts.
pub type Answer = std::sync::Arc<dyn Fn(&[Vec<u8>]) -> Vec<Vec<u8>> + Send + Sync>;

/// Our ZMTP 3.0 greeting, with the NULL mechanism.
pub(super) fn greeting() -> [u8; 64] {
    let mut g = [0u8; 64];
    g[0] = 0xFF;
    g[9] = SIGNATURE_END;
    g[10] = 3;
    g[12..16].copy_from_slice(b"NULL");
    g
}

/// The READY command frame, naming our socket type, then `extra`
/// properties (ZMTP 3.0 lets a peer add its own, named `X-…`; libzmq and
/// other peers pass over names they do not know).
pub(super) fn ready(socket_type: &[u8], extra: &[(&[u8], &[u8])]) -> Vec<u8> {
    let mut body = vec![5];
    body.extend_from_slice(b"READY");
    for (name, value) in
        std::iter::once((&b"Socket-Type"[..], socket_type)).chain(extra.iter().copied())
    {
        body.push(name.len() as u8);
        body.extend_from_slice(name);
        body.extend_from_slice(&(value.len() as u32).to_be_bytes());
        body.extend_from_slice(value);
    }
    let mut frame = if body.len() > 255 {
        let mut f = vec![COMMAND | LONG];
        f.extend_from_slice(&(body.len() as u64).to_be_bytes());
        f
    } else {
        vec![COMMAND, body.len() as u8]
    };
    frame.extend_from_slice(&body);
    frame
}

/// A message as REQ and REP frame it: an empty delimiter, then the parts.
pub(super) fn message(parts: &[&[u8]]) -> Vec<u8> {
    let mut out = vec![MORE, 0];
    for (i, p) in parts.iter().enumerate() {
        let more = if i + 1 < parts.len() { MORE } else { 0 };
        if p.len() > 255 {
            out.push(more | LONG);
            out.extend_from_slice(&(p.len() as u64).to_be_bytes());
        } else {
            out.push(more);
            out.push(p.len() as u8);
        }
        out.extend_from_slice(p);
    }
    out
}

/// A property's value in a READY command's metadata.
pub(super) fn property<'a>(mut meta: &'a [u8], name: &[u8]) -> Option<&'a [u8]> {
    while let Some((&n, rest)) = meta.split_first() {
        let (key, rest) = rest.split_at_checked(n as usize)?;
        let (len, rest) = rest.split_at_checked(4)?;
        let len = u32::from_be_bytes(len.try_into().ok()?) as usize;
        let (value, rest) = rest.split_at_checked(len)?;
        if key.eq_ignore_ascii_case(name) {
            return Some(value);
        }
        meta = rest;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::net::TcpListener;

    /// A server that accepts one connection and runs `f` on it.
    fn serve(f: impl FnOnce(TcpStream) + Send + 'static) -> String {
        let l = TcpListener::bind("127.0.0.1:0").unwrap();
        let addr = l.local_addr().unwrap().to_string();
        std::thread::spawn(move || {
            if let Ok((s, _)) = l.accept() {
                f(s)
            }
        });
        addr
    }

    #[test]
    fn nothing_listening_is_said_at_once() {
        let l = TcpListener::bind("127.0.0.1:0").unwrap();
        let addr = l.local_addr().unwrap().to_string();
        drop(l);
        let e = Req::connect(&addr, Duration::from_secs(2)).err().unwrap();
        assert!(e.to_string().contains("nothing is listening"), "{e}");
    }

    #[test]
    fn a_server_that_never_answers_times_out() {
        let addr = serve(|s| {
            std::thread::sleep(Duration::from_secs(3));
            drop(s)
        });
        let t = Instant::now();
        let e = Req::connect(&addr, Duration::from_millis(300))
            .err()
            .unwrap();
        assert!(e.to_string().contains("no answer within 0.3 s"), "{e}");
        assert!(t.elapsed() < Duration::from_secs(2));
    }

    #[test]
    fn a_server_that_is_not_zeromq_is_named() {
        let addr = serve(|mut s| {
            let _ = s.write_all(b"HTTP/1.1 400 Bad Request\r\n\r\n");
            std::thread::sleep(Duration::from_millis(500));
        });
        let e = Req::connect(&addr, Duration::from_secs(2)).err().unwrap();
        assert!(e.to_string().contains("not a ZeroMQ server"), "{e}");
    }

    #[test]
    fn properties_are_read_from_ready_metadata() {
        let mut m = vec![11];
        m.extend_from_slice(b"Socket-Type");
        m.extend_from_slice(&3u32.to_be_bytes());
        m.extend_from_slice(b"REP");
        assert_eq!(property(&m, b"socket-type"), Some(&b"REP"[..]));
        assert_eq!(property(&m[..5], b"Socket-Type"), None);
        let r = ready(b"REP", &[(b"X-Transitions-Buffer", b"20000")]);
        assert_eq!(property(&r[8..], b"Socket-Type"), Some(&b"REP"[..]));
        assert_eq!(
            property(&r[8..], b"x-transitions-buffer"),
            Some(&b"20000"[..])
        );
    }
}
