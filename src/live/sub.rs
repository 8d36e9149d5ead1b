//! A ZeroMQ SUB socket over TCP (ZMTP 3.0), subscribed to everything: what
//! BehaviorTree.CPP 3's `PublisherZMQ` publishes its statuses on. A PUB
//! socket sends when it likes, so bytes are read as they come and kept
//! until they make whole messages: a read that ends mid-frame loses
//! nothing, and every frame is bounded as `Req`'s are.

use super::zmtp::{Req, ZmtpError, COMMAND, FRAME_MAX, LONG, MORE, PARTS_MAX};
use std::io::Read;
use std::time::{Duration, Instant};

/// A connected SUB socket.
pub struct Sub {
    conn: Req,
    /// Bytes read that do not make a whole frame yet.
    buf: Vec<u8>,
    /// The frames of a message whose last frame has not come.
    parts: Vec<Vec<u8>>,
    /// Why the connection ended, once it did: said after the messages that
    /// came before it are taken.
    ended: Option<ZmtpError>,
}

/// The bytes of one read.
const CHUNK: usize = 1 << 16;
/// The bytes one `receive` reads at most.
const RECEIVE_MAX: usize = 4 << 20;

impl Sub {
    /// Connects to a PUB socket and subscribes to every message.
    pub fn connect(endpoint: &str, timeout: Duration) -> Result<Sub, ZmtpError> {
        let mut conn = Req::open(endpoint, timeout, b"SUB", &[b"PUB", b"XPUB"])?;
        // ZMTP 3.0 subscribes with a message: 1, then the prefix wanted
        // (none: every message).
        conn.write_all(&[0, 1, 1])?;
        Ok(Sub {
            conn,
            buf: Vec::new(),
            parts: Vec::new(),
            ended: None,
        })
    }

    /// The messages that came within `wait` (each as its frames): waits
    /// for the first bytes, then takes what is there. A closed connection
    /// is an error once the messages before it are taken.
    pub fn receive(&mut self, wait: Duration) -> Result<Vec<Vec<Vec<u8>>>, ZmtpError> {
        if let Some(e) = self.ended.take() {
            return Err(e);
        }
        let deadline = Instant::now() + wait;
        let mut out = Vec::new();
        let mut chunk = vec![0u8; CHUNK];
        let mut got = 0usize;
        // A publisher that floods is read `RECEIVE_MAX` at a time: the
        // rest waits in the socket (and the robot's queue), never here.
        while got < RECEIVE_MAX {
            let left = deadline.saturating_duration_since(Instant::now());
            if left.is_zero() {
                break;
            }
            self.conn
                .stream
                .set_read_timeout(Some(left))
                .map_err(|e| self.conn.err(e.to_string()))?;
            match self.conn.stream.read(&mut chunk) {
                Ok(0) => {
                    self.ended = Some(self.conn.err("the publisher closed the connection"));
                    break;
                }
                Ok(n) => {
                    got += n;
                    self.buf.extend_from_slice(&chunk[..n]);
                    self.frames(&mut out)?;
                    // More is waiting when the read filled the chunk.
                    if !out.is_empty() && n < CHUNK {
                        break;
                    }
                }
                Err(e)
                    if matches!(
                        e.kind(),
                        std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
                    ) =>
                {
                    break
                }
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => {
                    self.ended = Some(self.conn.err(format!("the connection failed: {e}")));
                    break;
                }
            }
        }
        if out.is_empty() {
            if let Some(e) = self.ended.take() {
                return Err(e);
            }
        }
        Ok(out)
    }

    /// Moves the whole frames of `buf` into messages.
    fn frames(&mut self, out: &mut Vec<Vec<Vec<u8>>>) -> Result<(), ZmtpError> {
        let mut at = 0;
        while let Some((flags, head, size)) = frame_head(&self.buf[at..]) {
            if flags & !(MORE | LONG | COMMAND) != 0 {
                return Err(self.conn.err(format!(
                    "a frame from the publisher has unknown flags {flags:#04x}"
                )));
            }
            if size > FRAME_MAX {
                return Err(self.conn.err(format!(
                    "a message of {size} bytes from the publisher is more than btx accepts ({FRAME_MAX})"
                )));
            }
            let end = at + head + size as usize;
            if self.buf.len() < end {
                break;
            }
            let body = self.buf[at + head..end].to_vec();
            at = end;
            if flags & COMMAND != 0 {
                // PING and the like: nothing of the run.
                continue;
            }
            self.parts.push(body);
            if self.parts.len() > PARTS_MAX {
                return Err(self.conn.err(format!(
                    "a message from the publisher has more than {PARTS_MAX} parts"
                )));
            }
            if flags & MORE == 0 {
                out.push(std::mem::take(&mut self.parts));
            }
        }
        self.buf.drain(..at);
        Ok(())
    }
}

/// A frame's flags, the length of its head and its body's size, once the
/// head is all there.
fn frame_head(b: &[u8]) -> Option<(u8, usize, u64)> {
    let &flags = b.first()?;
    if flags & LONG != 0 {
        let size = u64::from_be_bytes(b.get(1..9)?.try_into().ok()?);
        Some((flags, 9, size))
    } else {
        Some((flags, 2, u64::from(*b.get(1)?)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;
    use std::net::TcpListener;

    /// A PUB peer: greets, reads the subscription, then writes `bytes` in
    /// pieces of `piece` with a pause between them, and closes.
    fn publisher(bytes: Vec<u8>, piece: usize) -> String {
        let l = TcpListener::bind("127.0.0.1:0").unwrap();
        let addr = l.local_addr().unwrap().to_string();
        std::thread::spawn(move || {
            let (mut s, _) = l.accept().unwrap();
            s.write_all(&super::super::zmtp::greeting()).unwrap();
            s.write_all(&super::super::zmtp::ready(b"PUB", &[]))
                .unwrap();
            let mut got = vec![0u8; 64 + super::super::zmtp::ready(b"SUB", &[]).len() + 3];
            let mut n = 0;
            while n < got.len() {
                n += s.read(&mut got[n..]).unwrap();
            }
            assert_eq!(&got[got.len() - 3..], &[0, 1, 1], "subscribed to all");
            for p in bytes.chunks(piece) {
                s.write_all(p).unwrap();
                std::thread::sleep(Duration::from_millis(5));
            }
        });
        addr
    }

    #[test]
    fn messages_split_across_reads_come_whole_then_the_end_is_said() {
        let mut bytes = Vec::new();
        bytes.extend_from_slice(&[0, 3, b'a', b'b', b'c']);
        // A PING command between the messages is passed over.
        bytes.extend_from_slice(&[COMMAND, 5, 4, b'P', b'I', b'N', b'G']);
        bytes.push(MORE | LONG);
        bytes.extend_from_slice(&300u64.to_be_bytes());
        bytes.extend_from_slice(&[7; 300]);
        bytes.extend_from_slice(&[0, 1, b'z']);
        let addr = publisher(bytes, 7);
        let mut s = Sub::connect(&addr, Duration::from_secs(2)).unwrap();
        let mut got = Vec::new();
        let start = Instant::now();
        let err = loop {
            match s.receive(Duration::from_millis(50)) {
                Ok(m) => got.extend(m),
                Err(e) => break e,
            }
            assert!(start.elapsed() < Duration::from_secs(5));
        };
        assert_eq!(
            got,
            vec![vec![b"abc".to_vec()], vec![vec![7; 300], b"z".to_vec()]]
        );
        assert!(err.to_string().contains("closed the connection"), "{err}");
    }

    #[test]
    fn a_frame_bigger_than_btx_takes_is_refused_before_it_is_read() {
        let mut bytes = vec![LONG];
        bytes.extend_from_slice(&(FRAME_MAX + 1).to_be_bytes());
        let addr = publisher(bytes, 64);
        let mut s = Sub::connect(&addr, Duration::from_secs(2)).unwrap();
        let e = s.receive(Duration::from_millis(500)).unwrap_err();
        assert!(e.to_string().contains("more than btx accepts"), "{e}");
    }
}
