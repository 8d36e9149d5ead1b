//! The session file: JSON Lines, version 1. A header line, then one record
//! per status transition (and per decision, blackboard write or inserted
//! subgoal), then an end record. See docs/formats.md, "Session files".

use crate::model::Uid;
use crate::run::blackboard::EntryId;
use crate::run::Status;
use serde::{Deserialize, Serialize};
use serde_json::Value;

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
