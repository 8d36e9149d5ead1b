//! Writing a session file as a run goes, JSON lines first, then Parquet
//! where the name asks for it (`columnar`).

use super::format::*;
use crate::model::Uid;
use crate::run::{Event, Status};
use crate::source::Located;
use serde::Serialize;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// Writes a session as the run goes: into `NAME.partial`, flushed after
/// every tick so a killed run leaves a readable prefix; `finish` renames it
/// to `NAME` without ever replacing an existing file.
pub struct SessionWriter {
    path: PathBuf,
    partial: PathBuf,
    out: BufWriter<File>,
    tick: u32,
    step: u32,
    transitions: u64,
    /// The time of the next transition written (`timed`).
    next_time: Option<i64>,
    /// What the last flush made durable: the tick it ended, and the
    /// transitions up to it (said when a later write fails).
    kept: (u32, u64),
}

fn io_err(path: &Path, what: &str, e: std::io::Error) -> Located {
    Located::file(path, format!("{what}: {e}"))
}

impl SessionWriter {
    pub fn partial_path(path: &Path) -> PathBuf {
        let mut p = path.as_os_str().to_owned();
        p.push(".partial");
        PathBuf::from(p)
    }

    /// Why `path` cannot be a new session file, if something is there:
    /// btx overwrites nothing, but a directory or a device is not an old
    /// session, and saying which helps.
    pub fn refuse_existing(path: &Path) -> Result<(), Located> {
        let Ok(meta) = std::fs::symlink_metadata(path) else {
            return Ok(());
        };
        let what = if meta.is_dir() {
            "a directory is here; --out names the session file to write"
        } else if !meta.is_file() {
            "this is a device, a FIFO or a link, not a file; --out names a new session file"
        } else if super::read::format_of(path).is_some() {
            "a session already exists here; btx does not overwrite sessions"
        } else {
            "a file that is not a btx session is here; btx overwrites no file"
        };
        Err(Located::file(path, what)
            .with_help("choose another --out, or remove what is there first"))
    }

    pub fn create(path: &Path, header: &Header) -> Result<SessionWriter, Located> {
        let line = serde_json::to_string(header).expect("headers serialise");
        Self::create_as(path, &line)
    }

    /// A new session file with this header text as it is (a copy of
    /// another session keeps its header to the byte).
    pub fn create_as(path: &Path, line: &str) -> Result<SessionWriter, Located> {
        Self::refuse_existing(path)?;
        let partial = Self::partial_path(path);
        let file = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&partial)
            .map_err(|e| {
                if e.kind() == std::io::ErrorKind::AlreadyExists {
                    Located::file(
                        &partial,
                        "a run is writing this session, or one was stopped half way",
                    )
                    .with_help("open it with btx to see what it recorded, then remove it")
                } else {
                    io_err(&partial, "cannot create the session", e)
                }
            })?;
        let mut w = SessionWriter {
            path: path.to_path_buf(),
            partial,
            out: BufWriter::new(file),
            tick: 0,
            step: 0,
            transitions: 0,
            next_time: None,
            kept: (0, 0),
        };
        if line.len() > HEADER_MAX {
            drop(w);
            let _ = std::fs::remove_file(Self::partial_path(path));
            return Err(Located::file(
                path,
                format!(
                    "the session's header would be {} bytes, more than btx reads back ({} MiB): the tree is too large to record",
                    line.len(),
                    HEADER_MAX >> 20
                ),
            ));
        }
        w.out
            .write_all(line.as_bytes())
            .and_then(|()| w.out.write_all(b"\n"))
            .map_err(|e| w.failed(e))?;
        w.flush()?;
        Ok(w)
    }

    fn line(&mut self, v: &impl Serialize) -> Result<(), Located> {
        let mut s = serde_json::to_string(v).expect("records serialise");
        s.push('\n');
        self.out.write_all(s.as_bytes()).map_err(|e| self.failed(e))
    }

    /// A write that failed mid-run: which file, why, and what it keeps.
    fn failed(&self, e: std::io::Error) -> Located {
        let (tick, n) = self.kept;
        Located::file(
            &self.partial,
            format!(
                "cannot write the session: {}; this file keeps the run up to tick {tick} ({n} transitions)",
                why(&e)
            ),
        )
    }

    fn at(&mut self, tick: u32) -> u32 {
        if tick != self.tick {
            self.tick = tick;
            self.step = 0;
        }
        self.step
    }

    /// The robot's clock at the next transition written: a session keeps
    /// the time of day its source had.
    pub fn timed(&mut self, time_us: Option<i64>) {
        self.next_time = time_us;
    }

    pub fn event(&mut self, e: &Event) -> Result<(), Located> {
        let rec = match e {
            Event::Transition {
                tick,
                uid,
                prev,
                status,
                decision,
            } => {
                self.at(*tick);
                self.step += 1;
                self.transitions += 1;
                Record::Transition {
                    tick: *tick,
                    step: self.step,
                    uid: *uid,
                    from: *prev,
                    to: *status,
                    decision: decision.clone(),
                    time_us: self.next_time.take(),
                }
            }
            Event::Decision {
                tick,
                uid,
                decision,
            } => Record::Decision {
                tick: *tick,
                step: self.at(*tick),
                uid: *uid,
                decision: decision.clone(),
            },
            Event::Write {
                tick,
                uid,
                entry,
                value,
            } => Record::Write {
                tick: *tick,
                step: self.at(*tick),
                uid: *uid,
                entry: entry.clone(),
                value: value.clone(),
            },
        };
        self.line(&rec)
    }

    /// A place where transitions may be missing, and why.
    pub fn gap(&mut self, tick: u32, reason: &str) -> Result<(), Located> {
        let step = self.at(tick);
        self.line(&Record::Gap {
            tick,
            step,
            reason: reason.to_string(),
        })
    }

    /// Every node's state as read from the robot here (`Record::Resync`).
    pub fn resync(&mut self, tick: u32, states: &[Before]) -> Result<(), Located> {
        let step = self.at(tick);
        self.line(&Record::Resync {
            tick,
            step,
            states: states.to_vec(),
        })
    }

    pub fn insert(
        &mut self,
        tick: u32,
        copy_of: Uid,
        after: Uid,
        first_uid: Uid,
        question: &str,
    ) -> Result<(), Located> {
        let step = self.at(tick);
        self.line(&Record::Insert {
            tick,
            step,
            copy_of,
            after,
            first_uid,
            question: question.to_string(),
        })
    }

    /// Makes everything written so far readable by another process.
    pub fn flush(&mut self) -> Result<(), Located> {
        self.out.flush().map_err(|e| self.failed(e))?;
        self.kept = (self.tick, self.transitions);
        Ok(())
    }

    pub fn finish(mut self, ticks: u32, root: Status, reason: &str) -> Result<PathBuf, Located> {
        let end = Record::End {
            ticks,
            root,
            transitions: self.transitions,
            reason: reason.to_string(),
        };
        self.line(&end)?;
        self.close()
    }

    /// Finishes a session with no end record: a run that stops while its
    /// root runs (a log cut off), which every reader says as such.
    pub fn finish_cut_off(self) -> Result<PathBuf, Located> {
        self.close()
    }

    /// Flushes and syncs the partial file, then gives it its name.
    fn close(mut self) -> Result<PathBuf, Located> {
        self.flush()?;
        self.out
            .get_ref()
            .sync_all()
            .map_err(|e| io_err(&self.partial, "cannot write the session", e))?;
        let whole = if super::columnar::wanted(&self.path) {
            self.as_parquet()?
        } else {
            self.partial.clone()
        };
        // A hard link fails rather than replace a session created meanwhile.
        std::fs::hard_link(&whole, &self.path)
            .or_else(|e| {
                if e.kind() == std::io::ErrorKind::AlreadyExists {
                    Err(e)
                } else {
                    // File systems without hard links: rename, after checking again.
                    if self.path.exists() {
                        Err(std::io::Error::from(std::io::ErrorKind::AlreadyExists))
                    } else {
                        std::fs::rename(&whole, &self.path)
                    }
                }
            })
            .map_err(|e| {
                io_err(
                    &self.path,
                    "cannot finalise the session (it is kept as .partial)",
                    e,
                )
            })?;
        let _ = std::fs::remove_file(&whole);
        let _ = std::fs::remove_file(&self.partial);
        Ok(self.path)
    }

    /// The run written so far as JSON lines, written again as Parquet beside
    /// it (`--out RUN.parquet`): the JSON lines keep a killed run readable
    /// until the end, when the Parquet file is made whole at once.
    fn as_parquet(&self) -> Result<PathBuf, Located> {
        let mut part = self.path.as_os_str().to_owned();
        part.push(format!(".next-{}", std::process::id()));
        let part = PathBuf::from(part);
        super::columnar::write_from_jsonl(&self.partial, &self.path, &part).map_err(|e| {
            let _ = std::fs::remove_file(&part);
            Located::file(
                &self.path,
                format!(
                    "{e}; the run is kept as JSON lines in {}",
                    self.partial.display()
                ),
            )
        })?;
        Ok(part)
    }

    /// A record as it is (a copy of another session's).
    pub fn record(&mut self, rec: &Record) -> Result<(), Located> {
        match rec {
            Record::Transition { tick, step, .. } => {
                self.tick = *tick;
                self.step = *step;
                self.transitions += 1;
            }
            Record::End { .. } => {}
            Record::Decision { tick, step, .. }
            | Record::Write { tick, step, .. }
            | Record::Insert { tick, step, .. }
            | Record::Gap { tick, step, .. }
            | Record::Resync { tick, step, .. } => {
                self.tick = *tick;
                self.step = *step;
            }
        }
        self.line(rec)
    }

    /// Gives up the session: its partial file is removed.
    pub fn discard(self) {
        let _ = std::fs::remove_file(&self.partial);
    }

    /// Finishes a copy: its end record, if any, was copied as a record.
    pub fn finish_copy(self) -> Result<PathBuf, Located> {
        self.close()
    }
}

/// Why a write failed, in the user's terms.
pub fn why(e: &std::io::Error) -> String {
    use std::io::ErrorKind as K;
    match e.kind() {
        K::ReadOnlyFilesystem => "the file system is read-only".to_string(),
        K::StorageFull | K::QuotaExceeded => "the disk is full".to_string(),
        K::FileTooLarge => "the file size limit (ulimit -f) is reached".to_string(),
        K::PermissionDenied => "permission denied: this directory cannot be written".to_string(),
        _ => e.to_string(),
    }
}
