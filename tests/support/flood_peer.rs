//! A Groot2 server that floods: every request for transitions gets as many
//! as it is told, in the bounds of one reply. Shared by `tests/hostile.rs`
//! and `examples/flood_peer.rs` (for `benches/flood.sh`).

use btx::live::serve::Replay;
use btx::session::Session;
use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::Duration;

/// A Groot2 server written by hand on raw TCP (ZMTP 3.0, NULL): it answers
/// as `btx serve` would play `run` with a buffer of `buffer`, except that
/// every `t` gets `records` transitions, streamed in pieces so that this
/// process holds none of them (its memory counts in the peaks measured).
pub fn flooding(run: &Path, records: u64, buffer: usize) -> (u16, Arc<AtomicBool>) {
    use std::io::{Read, Write};
    let s = Session::load(run).unwrap();
    let replay = Arc::new(Replay::new(s, 50.0).with_buffer(buffer));
    let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let port = listener.local_addr().unwrap().port();
    let stop = Arc::new(AtomicBool::new(false));
    let halt = Arc::clone(&stop);
    std::thread::spawn(move || {
        listener.set_nonblocking(true).unwrap();
        while !halt.load(std::sync::atomic::Ordering::Relaxed) {
            let Ok((mut c, _)) = listener.accept() else {
                std::thread::sleep(Duration::from_millis(10));
                continue;
            };
            let replay = Arc::clone(&replay);
            std::thread::spawn(move || -> std::io::Result<()> {
                c.set_nonblocking(false)?;
                let mut greeting = [0u8; 64];
                greeting[0] = 0xFF;
                greeting[9] = 0x7F;
                greeting[10] = 3;
                greeting[12..16].copy_from_slice(b"NULL");
                c.write_all(&greeting)?;
                c.read_exact(&mut [0u8; 64])?;
                // READY, with the buffer in btx serve's property when it
                // is not BehaviorTree.CPP's.
                let mut body = b"\x05READY\x0bSocket-Type\0\0\0\x03REP".to_vec();
                if buffer != 1000 {
                    let said = buffer.to_string();
                    let name = btx::live::groot2::BUFFER_PROPERTY;
                    body.push(name.len() as u8);
                    body.extend_from_slice(name);
                    body.extend_from_slice(&(said.len() as u32).to_be_bytes());
                    body.extend_from_slice(said.as_bytes());
                }
                c.write_all(&[0x04, body.len() as u8])?;
                c.write_all(&body)?;
                let frame = |c: &mut std::net::TcpStream| -> std::io::Result<(u8, Vec<u8>)> {
                    let mut f = [0u8; 1];
                    c.read_exact(&mut f)?;
                    let size = if f[0] & 0x02 != 0 {
                        let mut b = [0u8; 8];
                        c.read_exact(&mut b)?;
                        u64::from_be_bytes(b)
                    } else {
                        let mut b = [0u8; 1];
                        c.read_exact(&mut b)?;
                        u64::from(b[0])
                    };
                    let mut body = vec![0u8; size.min(1 << 16) as usize];
                    c.read_exact(&mut body)?;
                    Ok((f[0], body))
                };
                frame(&mut c)?; // READY
                loop {
                    let mut parts = Vec::new();
                    loop {
                        let (flags, body) = frame(&mut c)?;
                        parts.push(body);
                        if flags & 0x01 == 0 {
                            break;
                        }
                    }
                    let request = &parts[1..];
                    let reply = replay.answer(request);
                    let put = |c: &mut std::net::TcpStream, more: bool, len: u64| {
                        let m = u8::from(more);
                        if len > 255 {
                            c.write_all(&[m | 0x02])?;
                            c.write_all(&len.to_be_bytes())
                        } else {
                            c.write_all(&[m, len as u8])
                        }
                    };
                    put(&mut c, true, 0)?;
                    if request.first().and_then(|h| h.get(1)) == Some(&b't') {
                        put(&mut c, true, reply[0].len() as u64)?;
                        c.write_all(&reply[0])?;
                        put(&mut c, false, 9 * records)?;
                        let mut piece = Vec::with_capacity(9 * 4096);
                        let mut left = records;
                        while left > 0 {
                            let n = left.min(4096);
                            piece.clear();
                            for i in 0..n {
                                piece.extend_from_slice(&i.to_le_bytes()[..6]);
                                piece.extend_from_slice(&1u16.to_le_bytes());
                                piece.push(if i % 2 == 0 { 1 } else { 2 });
                            }
                            c.write_all(&piece)?;
                            left -= n;
                        }
                    } else {
                        for (i, p) in reply.iter().enumerate() {
                            put(&mut c, i + 1 < reply.len(), p.len() as u64)?;
                            c.write_all(p)?;
                        }
                    }
                }
            });
        }
    });
    (port, stop)
}
