//! A bag's messages read on every core. The main thread reads the file
//! and hands out pieces of it (an MCAP chunk, a run of `.db3` messages);
//! each worker reads a piece's status changes, as long as every one is
//! plain (a uid that names the tree's node of that name, a status that is
//! one); the pieces are joined in the bag's order. A piece with anything
//! else (a channel or schema, a change without uid, a message its
//! definition does not read) comes back as it was, and is read on the
//! main thread in its turn, which says what is wrong exactly as a reading
//! in one piece would.

use super::*;
use crate::logs::cdr::Flat;
use std::collections::BTreeMap;
use std::sync::{mpsc, Arc, Mutex};

/// A piece of the bag, owned, so that a worker can read it.
pub(super) enum Piece {
    /// An MCAP chunk record: the bag, and where its bytes lie in it.
    Chunk(Arc<std::fs::File>, u64, usize),
    /// `.db3` messages one after the other, each ending where `ends` says.
    Messages(Vec<u8>, Vec<usize>),
}

/// What a worker read of a piece: its records (offsets counted in the
/// piece) and, for each message of the log, where its records end.
pub(super) struct Read {
    pub(super) records: Vec<Record>,
    pub(super) ends: Vec<usize>,
}

/// What reading a piece takes: the layout of the log's messages, each
/// node's name as a change gives it (by uid from 1), the log's channel.
#[derive(Clone)]
pub(super) struct Layout {
    pub(super) flat: Arc<Flat>,
    pub(super) direct: Option<Arc<super::direct::Direct>>,
    pub(super) named: Arc<[Box<[u8]>]>,
    pub(super) channel: u16,
}

/// A piece's changes, where every one is plain; `None` where one is not.
/// `buf` keeps its room from one piece to the next.
fn read(piece: &Piece, layout: &Layout, buf: &mut Vec<u8>) -> Option<Read> {
    // Room for every change the piece's bytes could hold: never moved.
    let room = match piece {
        Piece::Chunk(_, _, len) => *len,
        Piece::Messages(bytes, _) => bytes.len(),
    } / CHANGE_BYTES_MIN as usize;
    let mut out = Read {
        records: Vec::with_capacity(room),
        ends: Vec::new(),
    };
    let mut slots = Vec::new();
    let mut message = |data: &[u8], out: &mut Read| -> Option<()> {
        let mark = out.records.len();
        if let Some(direct) = &layout.direct {
            if direct.read(data, &layout.named, &mut out.records).is_some() {
                out.ends.push(out.records.len());
                return Some(());
            }
            out.records.truncate(mark);
        }
        by_slots(
            &layout.flat,
            &layout.named,
            data,
            &mut slots,
            &mut out.records,
        )?;
        out.ends.push(out.records.len());
        Some(())
    };
    match piece {
        Piece::Chunk(bag, at, len) => {
            use mcap::records::Record as R;
            chunk::read_at(bag, *at, *len, buf).ok()?;
            let (header, data) = chunk::open(&buf[..*len]).ok()?;
            for r in mcap::read::ChunkReader::new(header, &data).ok()? {
                match r.ok()? {
                    R::Message { header, data } if header.channel_id == layout.channel => {
                        message(&data, &mut out)?
                    }
                    R::Message { .. } => {}
                    _ => return None,
                }
            }
        }
        Piece::Messages(bytes, ends) => {
            let mut from = 0;
            for &end in ends {
                message(&bytes[from..end], &mut out)?;
                from = end;
            }
        }
    }
    // Kept until the bag is closed: the room not used is given back.
    out.records.shrink_to_fit();
    Some(out)
}

/// One message's changes onto `out` as its definition lays them out,
/// read into `slots`; `None` where any is not plain.
pub(super) fn by_slots(
    flat: &Flat,
    named: &[Box<[u8]>],
    data: &[u8],
    slots: &mut Vec<super::Slot>,
    out: &mut Vec<Record>,
) -> Option<()> {
    flat.decode(data, slots).ok()?;
    for c in slots.chunks_exact(CHANGE_PATHS.len()) {
        let c = change(c, data);
        let (uid, status) = plain(named, &c)?;
        out.push(Record {
            time_us: c.time_us,
            uid,
            status,
            offset: out.len(),
        });
    }
    Some(())
}

/// A piece given out, back read (or not), and not yet joined.
type Back = (usize, Piece, Option<Read>);

/// Workers reading pieces, and the pieces back but not yet joined.
pub(super) struct Pool {
    work: Option<mpsc::SyncSender<(usize, Piece)>>,
    back: mpsc::Receiver<Back>,
    workers: Vec<std::thread::JoinHandle<()>>,
    /// Pieces given out so far, and joined so far.
    given: usize,
    joined: usize,
    early: BTreeMap<usize, (Piece, Option<Read>)>,
    file: PathBuf,
}

impl Pool {
    /// A worker a core, where there are several; else none.
    pub(super) fn start(layout: Layout, file: &Path) -> Option<Pool> {
        let cores = crate::logs::cores();
        if cores < 2 {
            return None;
        }
        // A few pieces waiting a worker: the bag read ahead by that much.
        let (work, pieces) = mpsc::sync_channel::<(usize, Piece)>(cores * 2);
        let pieces = Arc::new(Mutex::new(pieces));
        let (done, back) = mpsc::channel();
        let workers = (0..cores)
            .map(|_| {
                let (pieces, done, layout) = (pieces.clone(), done.clone(), layout.clone());
                std::thread::spawn(move || {
                    let mut buf = Vec::new();
                    loop {
                        let next = pieces.lock().map(|p| p.recv());
                        let Ok(Ok((n, piece))) = next else { return };
                        let read = read(&piece, &layout, &mut buf);
                        if done.send((n, piece, read)).is_err() {
                            return;
                        }
                    }
                })
            })
            .collect();
        Some(Pool {
            work: Some(work),
            back,
            workers,
            given: 0,
            joined: 0,
            early: BTreeMap::new(),
            file: file.to_path_buf(),
        })
    }

    /// Gives `piece` to the workers, and joins, in order, what is back.
    pub(super) fn give(
        &mut self,
        piece: Piece,
        join: &mut impl FnMut(Piece, Option<Read>) -> Result<(), Located>,
    ) -> Result<(), Located> {
        let n = self.given;
        self.given += 1;
        // A send fails only where every worker is gone (or the pool is
        // finished): the piece is then read here, in its turn.
        let unsent = match &self.work {
            Some(work) => work.send((n, piece)).err().map(|mpsc::SendError((_, p))| p),
            None => Some(piece),
        };
        if let Some(piece) = unsent {
            self.early.insert(n, (piece, None));
        }
        while let Ok((n, piece, read)) = self.back.try_recv() {
            self.early.insert(n, (piece, read));
        }
        self.join_ready(join)
    }

    /// Joins every piece given, in order, waiting for those not back.
    pub(super) fn finish(
        &mut self,
        join: &mut impl FnMut(Piece, Option<Read>) -> Result<(), Located>,
    ) -> Result<(), Located> {
        // No more work: each worker ends when none is left, so that a
        // piece lost (a worker's panic) is said, not waited for.
        self.work = None;
        while self.joined < self.given {
            self.join_ready(join)?;
            if self.joined == self.given {
                break;
            }
            match self.back.recv() {
                Ok((n, piece, read)) => {
                    self.early.insert(n, (piece, read));
                }
                // Every worker gone (none can be, short of a panic): what
                // is missing cannot be read in its turn.
                Err(_) => {
                    return Err(Located::file(
                        &self.file,
                        "a thread reading the bag stopped before it was done",
                    ))
                }
            }
        }
        Ok(())
    }

    fn join_ready(
        &mut self,
        join: &mut impl FnMut(Piece, Option<Read>) -> Result<(), Located>,
    ) -> Result<(), Located> {
        while let Some((piece, read)) = self.early.remove(&self.joined) {
            self.joined += 1;
            join(piece, read)?;
        }
        Ok(())
    }
}

impl Drop for Pool {
    fn drop(&mut self) {
        // No more work: each worker ends after its piece.
        self.work = None;
        for w in self.workers.drain(..) {
            let _ = w.join();
        }
    }
}
