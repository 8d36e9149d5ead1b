//! The session file: JSON Lines, version 1. A header line, then one record
//! per status transition (and per decision, blackboard write or inserted
//! subgoal), then an end record. See docs/formats.md, "Session files".

use crate::model::Uid;
use crate::run::blackboard::EntryId;
use crate::run::{Event, Status};
use crate::source::Located;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

pub const FORMAT_VERSION: u32 = 1;

/// The tree a session ran, embedded so the session stands alone.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct TreeRef {
    /// Where the tree was read from, if it was a file.
    pub path: Option<String>,
    /// FNV-1a 64 of the file's text, to tell whether it changed since.
    pub hash: Option<String>,
    /// The tree as BehaviorTree.CPP 4 XML written by btx (same uids).
    pub xml: String,
    pub btcpp_format: u8,
    pub main_tree: String,
}

/// What drove the leaves.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct Source {
    /// `plan`, `domain`, `world` or `import`.
    pub kind: String,
    pub path: Option<String>,
    /// The plan or domain text, embedded.
    pub text: Option<String>,
    /// The world's name.
    pub name: Option<String>,
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct Header {
    pub btx_session: u32,
    pub btx_version: String,
    pub tree: TreeRef,
    pub source: Source,
    pub seed: Option<u64>,
    pub tick_ms: u64,
    /// The Nav2 release the run followed, where it is not main.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub nav2: Option<crate::model::nav2::Release>,
    /// Blackboard entries before the first tick.
    #[serde(default)]
    pub blackboard: Vec<(EntryId, Value)>,
    /// A run recorded from its middle (a live robot btx attached to): each
    /// node that was not IDLE-and-never-done when recording began.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub before: Vec<Before>,
}

/// A node's state when recording began: its status, and the status it had
/// last completed with (when, the run does not say).
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, Eq)]
pub struct Before {
    pub uid: Uid,
    pub status: Status,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub done: Option<Status>,
}

/// One line after the header. `step` is the number of transitions of the
/// tick so far (a transition's own step counts it).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(tag = "k")]
pub enum Record {
    #[serde(rename = "t")]
    Transition {
        tick: u32,
        step: u32,
        uid: Uid,
        from: Status,
        to: Status,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        decision: Option<String>,
        /// The robot's clock, µs since the epoch, where the source had one
        /// (a log, a watched robot).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        time_us: Option<i64>,
    },
    #[serde(rename = "d")]
    Decision {
        tick: u32,
        step: u32,
        uid: Uid,
        decision: String,
    },
    #[serde(rename = "w")]
    Write {
        tick: u32,
        step: u32,
        uid: Uid,
        entry: EntryId,
        value: Value,
    },
    /// A subgoal inserted by "Can you X?": a copy of `copy_of` placed after
    /// `after`, its nodes numbered from `first_uid`.
    #[serde(rename = "i")]
    Insert {
        tick: u32,
        step: u32,
        copy_of: Uid,
        after: Uid,
        first_uid: Uid,
        question: String,
    },
    /// Transitions may be missing here (a live run: the server's buffer
    /// overflowed, the robot restarted, the connection dropped).
    #[serde(rename = "g")]
    Gap {
        tick: u32,
        step: u32,
        reason: String,
    },
    /// Every node's state, read from the robot here (a live run, after a
    /// gap): each node not IDLE-and-never-done, as `Header::before`.
    #[serde(rename = "s")]
    Resync {
        tick: u32,
        step: u32,
        states: Vec<Before>,
    },
    #[serde(rename = "end")]
    End {
        ticks: u32,
        root: Status,
        transitions: u64,
        reason: String,
    },
}

/// 64-bit FNV-1a, hex: enough to notice that a tree file changed.
pub fn fnv64(text: &str) -> String {
    let mut h: u64 = 0xcbf29ce484222325;
    for b in text.bytes() {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x100000001b3);
    }
    format!("{h:016x}")
}

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
                super::output::why(&e)
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

/// Every record's fields in one struct: reading through it is several times
/// faster than through the internally tagged enum, which serde buffers.
#[derive(Deserialize)]
struct Flat<'a> {
    k: &'a str,
    tick: Option<u32>,
    step: Option<u32>,
    uid: Option<Uid>,
    from: Option<Status>,
    to: Option<Status>,
    decision: Option<String>,
    entry: Option<EntryId>,
    value: Option<Value>,
    copy_of: Option<Uid>,
    after: Option<Uid>,
    first_uid: Option<Uid>,
    question: Option<String>,
    states: Option<Vec<Before>>,
    ticks: Option<u32>,
    root: Option<Status>,
    transitions: Option<u64>,
    reason: Option<String>,
    time_us: Option<i64>,
}

/// The transition lines btx itself writes, read without serde: they are
/// nearly all of a session, and this is several times faster.
fn fast_transition(line: &str) -> Option<Record> {
    fn num<'a>(s: &'a str, key: &str) -> Option<(u32, &'a str)> {
        let s = s.strip_prefix(key)?;
        let end = s.find(|c: char| !c.is_ascii_digit())?;
        Some((s[..end].parse().ok()?, &s[end..]))
    }
    fn word<'a>(s: &'a str, key: &str) -> Option<(Status, &'a str)> {
        let s = s.strip_prefix(key)?;
        let end = s.find('"')?;
        Some((Status::parse(&s[..end])?, &s[end + 1..]))
    }
    let (tick, s) = num(line, "{\"k\":\"t\",\"tick\":")?;
    let (step, s) = num(s, ",\"step\":")?;
    let (uid, s) = num(s, ",\"uid\":")?;
    let (from, s) = word(s, ",\"from\":\"")?;
    let (to, s) = word(s, ",\"to\":\"")?;
    let (time_us, s) = match s.strip_prefix(",\"time_us\":") {
        Some(t) => {
            let end = t.find(|c: char| !c.is_ascii_digit() && c != '-')?;
            (Some(t[..end].parse().ok()?), &t[end..])
        }
        None => (None, s),
    };
    (s == "}").then_some(Record::Transition {
        tick,
        step,
        uid,
        from,
        to,
        decision: None,
        time_us,
    })
}

/// The longest record line read after the header. btx writes none longer
/// than a 1 MiB script string escaped (at most 6 bytes a byte); a longer line
/// would cost up to 60 times its size once parsed into values.
pub const RECORD_MAX: usize = 8 << 20;
/// The longest header line (the tree's XML, the blackboard and the nodes'
/// states when the run began): btx writes no longer one, and refuses to
/// read one, before parsing it.
pub const HEADER_MAX: usize = 16 << 20;

/// A JSON error in one line of a session, as the column in that line:
/// serde says "at line 1 column 59" of the line alone, which reads as the
/// file's first line when the record is on its 50th.
pub fn json_error(e: &serde_json::Error) -> String {
    let text = e.to_string();
    match text.rsplit_once(" at line ") {
        Some((what, _)) if e.line() == 1 => format!("{what} (column {})", e.column()),
        _ => text,
    }
}

/// Reads one record line.
pub fn parse_record(line: &str) -> Result<Record, String> {
    if let Some(r) = fast_transition(line) {
        return Ok(r);
    }
    let f: Flat = serde_json::from_str(line).map_err(|e| json_error(&e))?;
    fn need<T>(v: Option<T>, k: &str, field: &str) -> Result<T, String> {
        v.ok_or_else(|| format!("a \"{k}\" record needs \"{field}\""))
    }
    let k = f.k;
    Ok(match k {
        "t" => Record::Transition {
            tick: need(f.tick, k, "tick")?,
            step: need(f.step, k, "step")?,
            uid: need(f.uid, k, "uid")?,
            from: need(f.from, k, "from")?,
            to: need(f.to, k, "to")?,
            decision: f.decision,
            time_us: f.time_us,
        },
        "d" => Record::Decision {
            tick: need(f.tick, k, "tick")?,
            step: need(f.step, k, "step")?,
            uid: need(f.uid, k, "uid")?,
            decision: need(f.decision, k, "decision")?,
        },
        "w" => Record::Write {
            tick: need(f.tick, k, "tick")?,
            step: need(f.step, k, "step")?,
            uid: need(f.uid, k, "uid")?,
            entry: need(f.entry, k, "entry")?,
            value: need(f.value, k, "value")?,
        },
        "i" => Record::Insert {
            tick: need(f.tick, k, "tick")?,
            step: need(f.step, k, "step")?,
            copy_of: need(f.copy_of, k, "copy_of")?,
            after: need(f.after, k, "after")?,
            first_uid: need(f.first_uid, k, "first_uid")?,
            question: need(f.question, k, "question")?,
        },
        "g" => Record::Gap {
            tick: need(f.tick, k, "tick")?,
            step: need(f.step, k, "step")?,
            reason: need(f.reason, k, "reason")?,
        },
        "s" => Record::Resync {
            tick: need(f.tick, k, "tick")?,
            step: need(f.step, k, "step")?,
            states: need(f.states, k, "states")?,
        },
        "end" => Record::End {
            ticks: need(f.ticks, k, "ticks")?,
            root: need(f.root, k, "root")?,
            transitions: need(f.transitions, k, "transitions")?,
            reason: need(f.reason, k, "reason")?,
        },
        other => return Err(format!("unknown record kind \"{other}\"")),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn records_read_back_as_written() {
        let recs = [
            Record::Transition {
                tick: 3,
                step: 2,
                uid: 7,
                from: Status::Idle,
                to: Status::Running,
                decision: Some("a".into()),
                time_us: Some(1_795_793_363_082_249),
            },
            Record::Transition {
                tick: 3,
                step: 3,
                uid: 7,
                from: Status::Running,
                to: Status::Idle,
                decision: None,
                time_us: None,
            },
            Record::Decision {
                tick: 4,
                step: 0,
                uid: 7,
                decision: "b".into(),
            },
            Record::Write {
                tick: 4,
                step: 0,
                uid: 7,
                entry: EntryId {
                    scope: 2,
                    key: "k \"q\"".into(),
                },
                value: Value::from(1.5),
            },
            Record::Insert {
                tick: 5,
                step: 0,
                copy_of: 8,
                after: 2,
                first_uid: 80,
                question: "Can you x?".into(),
            },
            Record::Gap {
                tick: 6,
                step: 1,
                reason: "the connection dropped".into(),
            },
            Record::Resync {
                tick: 6,
                step: 1,
                states: vec![Before {
                    uid: 3,
                    status: Status::Idle,
                    done: Some(Status::Failure),
                }],
            },
            Record::End {
                ticks: 9,
                root: Status::Success,
                transitions: 12,
                reason: "root completed".into(),
            },
        ];
        for r in recs {
            let line = serde_json::to_string(&r).unwrap();
            assert_eq!(parse_record(&line).unwrap(), r, "{line}");
        }
        assert!(parse_record("{\"k\":\"t\",\"tick\":1}")
            .unwrap_err()
            .contains("needs \"step\""));
        // The fast path falls back to serde on anything unusual.
        let spaced = "{ \"k\": \"t\", \"tick\": 1, \"step\": 2, \"uid\": 3, \"from\": \"IDLE\", \"to\": \"RUNNING\" }";
        assert!(matches!(
            parse_record(spaced),
            Ok(Record::Transition {
                tick: 1,
                step: 2,
                uid: 3,
                ..
            })
        ));
        assert!(parse_record(
            "{\"k\":\"t\",\"tick\":1,\"step\":2,\"uid\":3,\"from\":\"IDLE\",\"to\":\"BORED\"}"
        )
        .is_err());
        assert!(parse_record("{\"k\":\"zz\"}")
            .unwrap_err()
            .contains("unknown record kind"));
    }
}
