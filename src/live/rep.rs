//! The server side of ZMTP (a REP socket): one thread serves every client
//! through readiness events (mio), so that clients cost buffers, not
//! threads. Each connection is a small state machine fed the bytes that
//! arrived: the greeting, the READY handshake, then requests, each
//! answered before the next is read. What a client can make the server
//! hold is bounded: `REQUEST_MAX` bytes of request, one reply, at most
//! `CONNECTIONS_MAX` clients, none silent for longer than `IDLE_MAX`.

use super::zmtp::{
    greeting, message, property, ready, Answer, COMMAND, CONNECTIONS_MAX, IDLE_MAX, LONG, MORE,
    PARTS_MAX, REQUEST_MAX,
};
use mio::net::{TcpListener, TcpStream};
use mio::{Events, Interest, Poll, Token};
use std::io::{Read, Write};
use std::time::{Duration, Instant};

const LISTENER: Token = Token(usize::MAX);

/// Where a connection is in the protocol.
#[derive(PartialEq)]
enum Phase {
    /// Waiting for the client's 64-byte greeting.
    Greeting,
    /// Waiting for its READY command.
    Ready,
    /// Requests.
    Open,
}

struct Conn {
    stream: TcpStream,
    phase: Phase,
    input: Vec<u8>,
    output: Vec<u8>,
    /// The request being read: its parts after the delimiter.
    parts: Vec<Vec<u8>>,
    delimited: bool,
    size: u64,
    /// When the client last sent a whole request (or connected).
    heard: Instant,
    /// Our READY command, sent after the client's greeting.
    ready: std::rc::Rc<[u8]>,
}

/// Why a connection is closed.
type Closed = ();

impl Conn {
    fn new(stream: TcpStream, ready: std::rc::Rc<[u8]>) -> Conn {
        Conn {
            stream,
            phase: Phase::Greeting,
            input: Vec::new(),
            output: greeting().to_vec(),
            parts: Vec::new(),
            delimited: false,
            size: 0,
            heard: Instant::now(),
            ready,
        }
    }

    /// Reads what arrived, only while no reply waits (one request at a
    /// time, so that a client that never reads holds one reply at most);
    /// whether the socket is drained (else a reply waits to be written).
    fn read(&mut self, answer: &Answer) -> Result<bool, Closed> {
        let mut buf = [0u8; 1 << 14];
        while self.output.is_empty() {
            match self.stream.read(&mut buf) {
                Ok(0) => return Err(()),
                Ok(n) => {
                    self.input.extend_from_slice(&buf[..n]);
                    self.step(answer)?;
                }
                Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => return Ok(true),
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(_) => return Err(()),
            }
        }
        Ok(false)
    }

    /// Writes what waits; whether everything went.
    fn write(&mut self) -> Result<bool, Closed> {
        while !self.output.is_empty() {
            match self.stream.write(&self.output) {
                Ok(0) => return Err(()),
                Ok(n) => {
                    self.output.drain(..n);
                }
                Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => return Ok(false),
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(_) => return Err(()),
            }
        }
        Ok(true)
    }

    /// Takes what the input holds, as far as it goes.
    fn step(&mut self, answer: &Answer) -> Result<(), Closed> {
        loop {
            match self.phase {
                Phase::Greeting => {
                    if self.input.len() < 64 {
                        return Ok(());
                    }
                    let g: Vec<u8> = self.input.drain(..64).collect();
                    if g[0] != 0xFF || g[9] & 1 != 1 || g[10] < 3 || &g[12..16] != b"NULL" {
                        return Err(());
                    }
                    self.output.extend_from_slice(&self.ready);
                    self.phase = Phase::Ready;
                }
                _ => {
                    let Some((flags, body)) = self.frame()? else {
                        return Ok(());
                    };
                    if flags & COMMAND != 0 {
                        if self.phase == Phase::Ready {
                            if !body.starts_with(b"\x05READY") {
                                return Err(());
                            }
                            let peer = property(&body[6..], b"Socket-Type");
                            if peer.is_some_and(|t| t != b"REQ" && t != b"DEALER") {
                                return Err(());
                            }
                            self.phase = Phase::Open;
                        }
                        // PING and the like carry no request.
                        continue;
                    }
                    if self.phase != Phase::Open {
                        return Err(());
                    }
                    self.part(flags, body, answer)?;
                    if !self.output.is_empty() {
                        return Ok(());
                    }
                }
            }
        }
    }

    /// One whole frame off the input, if it has one; a frame or request
    /// past its bound closes the connection before it is read.
    fn frame(&mut self) -> Result<Option<(u8, Vec<u8>)>, Closed> {
        let Some(&flags) = self.input.first() else {
            return Ok(None);
        };
        if flags & !(MORE | LONG | COMMAND) != 0 {
            return Err(());
        }
        let (head, size) = if flags & LONG != 0 {
            let Some(b) = self.input.get(1..9) else {
                return Ok(None);
            };
            (9, u64::from_be_bytes(b.try_into().expect("8 bytes")))
        } else {
            let Some(&b) = self.input.get(1) else {
                return Ok(None);
            };
            (2, u64::from(b))
        };
        if self.size.saturating_add(size) > REQUEST_MAX {
            return Err(());
        }
        let end = head + size as usize;
        if self.input.len() < end {
            return Ok(None);
        }
        let body = self.input[head..end].to_vec();
        self.input.drain(..end);
        Ok(Some((flags, body)))
    }

    /// A part of a request; the reply is queued once the request is whole.
    fn part(&mut self, flags: u8, body: Vec<u8>, answer: &Answer) -> Result<(), Closed> {
        self.size += body.len() as u64;
        if !self.delimited {
            if !body.is_empty() {
                return Err(());
            }
            self.delimited = true;
        } else {
            self.parts.push(body);
            if self.parts.len() > PARTS_MAX {
                return Err(());
            }
        }
        if flags & MORE != 0 {
            return Ok(());
        }
        let request = std::mem::take(&mut self.parts);
        (self.delimited, self.size) = (false, 0);
        self.heard = Instant::now();
        let reply = answer(&request);
        let parts: Vec<&[u8]> = reply.iter().map(Vec::as_slice).collect();
        self.output = message(&parts);
        Ok(())
    }
}

/// Serves REQ clients on `listener` from this thread until `stop`: each
/// request's parts go to `answer`, and its parts are the reply. At most
/// `CONNECTIONS_MAX` clients at once (more are refused, with a line on
/// stderr at most once a second); a client that breaks the protocol, sends
/// a request over `REQUEST_MAX` bytes or stays silent `IDLE_MAX` loses its
/// connection, not the server. `properties` go in our READY, after the
/// socket type.
pub fn serve_rep(
    listener: std::net::TcpListener,
    answer: Answer,
    properties: &[(&[u8], &[u8])],
    stop: std::sync::Arc<std::sync::atomic::AtomicBool>,
) -> std::io::Result<()> {
    listener.set_nonblocking(true)?;
    let mut server = Server {
        ready: ready(b"REP", properties).into(),
        endpoint: listener.local_addr()?.to_string(),
        listener: TcpListener::from_std(listener),
        poll: Poll::new()?,
        conns: Vec::new(),
        refused_said: Instant::now() - Duration::from_secs(60),
    };
    server
        .poll
        .registry()
        .register(&mut server.listener, LISTENER, Interest::READABLE)?;
    let mut events = Events::with_capacity(256);
    while !stop.load(std::sync::atomic::Ordering::Relaxed) {
        match server
            .poll
            .poll(&mut events, Some(Duration::from_millis(100)))
        {
            Ok(()) => {}
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(e),
        }
        for ev in &events {
            if ev.token() == LISTENER {
                server.accept_all();
            } else {
                server.serve(ev.token().0, &answer);
            }
        }
        server.close_idle();
    }
    Ok(())
}

/// The REP server's state between events: its clients by token.
struct Server {
    ready: std::rc::Rc<[u8]>,
    endpoint: String,
    listener: TcpListener,
    poll: Poll,
    conns: Vec<Option<Conn>>,
    /// When a refused client was last told of on stderr.
    refused_said: Instant,
}

impl Server {
    /// Accepts every client waiting, up to `CONNECTIONS_MAX` connected.
    fn accept_all(&mut self) {
        loop {
            let (mut stream, peer) = match self.listener.accept() {
                Ok(x) => x,
                Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => break,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                // Out of descriptors and the like: this client is
                // lost, the server goes on.
                Err(_) => break,
            };
            let open = self.conns.iter().filter(|c| c.is_some()).count();
            if open >= CONNECTIONS_MAX {
                drop(stream);
                if self.refused_said.elapsed() >= Duration::from_secs(1) {
                    self.refused_said = Instant::now();
                    eprintln!("{}: refused a client ({peer}): {CONNECTIONS_MAX} are connected, the most btx serves at once", self.endpoint);
                }
                continue;
            }
            let _ = stream.set_nodelay(true);
            let slot = self
                .conns
                .iter()
                .position(Option::is_none)
                .unwrap_or_else(|| {
                    self.conns.push(None);
                    self.conns.len() - 1
                });
            let interest = Interest::READABLE | Interest::WRITABLE;
            if self
                .poll
                .registry()
                .register(&mut stream, Token(slot), interest)
                .is_ok()
            {
                let mut c = Conn::new(stream, std::rc::Rc::clone(&self.ready));
                // The greeting goes at once.
                if c.write().is_ok() {
                    self.conns[slot] = Some(c);
                }
            }
        }
    }

    /// Serves the client in `slot` after an event on its socket; one that
    /// broke the protocol or hung up is closed.
    fn serve(&mut self, slot: usize, answer: &Answer) {
        let Some(c) = self.conns.get_mut(slot).and_then(Option::as_mut) else {
            return;
        };
        // Events come on edges: write what waits, read until the socket
        // is drained, answering as requests come whole.
        let alive = (|| -> Result<(), Closed> {
            loop {
                if !c.write()? {
                    // The rest waits for the socket to take it.
                    return Ok(());
                }
                if c.read(answer)? {
                    return c.write().map(|_| ());
                }
            }
        })();
        if alive.is_err() {
            close(&self.poll, &mut self.conns[slot]);
        }
    }

    /// Closes the connections silent for `IDLE_MAX`.
    fn close_idle(&mut self) {
        for slot in &mut self.conns {
            if slot.as_ref().is_some_and(|c| c.heard.elapsed() >= IDLE_MAX) {
                close(&self.poll, slot);
            }
        }
    }
}

fn close(poll: &Poll, slot: &mut Option<Conn>) {
    if let Some(mut c) = slot.take() {
        let _ = poll.registry().deregister(&mut c.stream);
    }
}
