//! Sessions: the episodic memory of a run (Love et al. §5.1), as a file and
//! as an index by moment.

pub mod format;
pub mod index;
pub mod output;
pub mod parting;
pub mod record;
pub mod rerun;

pub use format::{Before, Header, Record, SessionWriter, Source, TreeRef};
pub use index::{At, Index, Moment, TickMark, Transition, Write, EMPTY_TICKS_MAX};
pub use output::OutputLock;

use crate::model::{Tree, Uid};
use crate::source::{Located, Warning};
use crate::xml::{load_str, LoadOptions};
use std::path::{Path, PathBuf};

/// A loaded session.
pub struct Session {
    pub path: PathBuf,
    pub header: Header,
    /// The tree as it ran, inserted subgoals included.
    pub tree: Tree,
    pub index: Index,
    /// The end record, if the run finished.
    pub end: Option<(u32, crate::run::Status, String)>,
    /// Subgoals inserted during the run: (position, copy of, after, first uid, question).
    pub inserts: Vec<(u32, Uid, Uid, Uid, String)>,
    /// When the first and the last transition happened (µs since the
    /// epoch), as a log says; a session keeps no times.
    pub span_us: Option<(i64, i64)>,
    /// When each transition happened (µs since the epoch), as a log says;
    /// empty for a session, which keeps no times.
    pub times_us: Vec<i64>,
    pub warnings: Vec<Warning>,
}

impl Session {
    /// How the run ended, as a line: the root's last status and why it
    /// stopped, or the error that stopped it, or that nothing says.
    pub fn ending(&self) -> String {
        match &self.end {
            Some((ticks, _, reason)) if reason.starts_with("error: ") => {
                format!("stopped at tick {ticks} by an {reason}")
            }
            Some((ticks, root, reason)) if root.is_completed() => {
                format!("ended at tick {ticks}: root {} ({reason})", root.as_str())
            }
            Some((ticks, root, reason)) => format!(
                "stopped at tick {ticks} with the root {} ({reason})",
                root.as_str()
            ),
            None => format!(
                "no end recorded after tick {}: the run was cut off or is still going",
                self.index.ticks()
            ),
        }
    }

    pub fn load(path: &Path) -> Result<Session, Located> {
        let text = crate::source::read_text(path, crate::source::INPUT_SIZE_MAX, "the session")?;
        Session::parse(path, &text)
    }

    pub fn parse(path: &Path, text: &str) -> Result<Session, Located> {
        let mut lines = Vec::new();
        let mut offset = 0;
        for l in text.split_inclusive('\n') {
            lines.push((offset, l));
            offset += l.len();
        }
        let err_at = |start: usize, len: usize, msg: String| {
            Located::at(path, text, start, start + len, msg)
        };
        let Some(&(_, first)) = lines.first() else {
            return Err(Located::at(path, text, 0, 0, "the session is empty"));
        };
        if first.len() > format::HEADER_MAX {
            return Err(Located::file(
                path,
                format!(
                    "line 1: a session header of {} bytes: a header (the tree, its blackboard and the nodes' states) is at most {} MiB",
                    first.len(),
                    format::HEADER_MAX >> 20
                ),
            ));
        }
        let header: Header = serde_json::from_str(first.trim_end()).map_err(|e| {
            err_at(
                0,
                first.trim_end().len(),
                format!("not a btx session header: {e}"),
            )
        })?;
        if header.btx_session != format::FORMAT_VERSION {
            return Err(err_at(
                0,
                first.len(),
                format!(
                    "session format {} is not one this btx reads (it reads {})",
                    header.btx_session,
                    format::FORMAT_VERSION
                ),
            ));
        }
        let tree_name = PathBuf::from(format!("{} (embedded tree)", path.display()));
        let opts = LoadOptions {
            version: Some(crate::model::Version::V4),
            main_tree: None,
            embedded: true,
            ..Default::default()
        };
        let mut tree = load_str(&tree_name, &header.tree.xml, &opts)?.tree;
        if header.tree.btcpp_format == 3 {
            tree.release = crate::model::Version::V3;
        }
        let mut index = Index::new(tree.len());
        index.set_before(&header.before);
        let scopes = tree.scopes.len();
        for (e, v) in &header.blackboard {
            if e.scope >= scopes {
                return Err(err_at(
                    0,
                    first.trim_end().len(),
                    format!(
                        "the blackboard names scope {}, and the session's tree has {scopes} scopes",
                        e.scope
                    ),
                ));
            }
            index.push_write(e.clone(), v.clone());
        }
        let mut warnings = Vec::new();
        let mut end = None;
        let mut inserts = Vec::new();
        let n = lines.len();
        for (i, &(start, line)) in lines.iter().enumerate().skip(1) {
            let body = line.trim_end();
            if body.is_empty() {
                continue;
            }
            if body.len() > format::RECORD_MAX {
                return Err(err_at(
                    start,
                    body.len(),
                    format!(
                        "a record of {} bytes: a session's records (after the header) are at most {} MiB",
                        body.len(),
                        format::RECORD_MAX >> 20
                    ),
                ));
            }
            let rec: Record = match format::parse_record(body) {
                Ok(r) => r,
                Err(e) if i == n - 1 && !line.ends_with('\n') => {
                    warnings.push(Warning {
                        location: format!("{}:{}:1", path.display(), i + 1),
                        message: format!(
                            "the last record was cut off half way ({e}); it is left out"
                        ),
                    });
                    break;
                }
                Err(e) => {
                    return Err(err_at(
                        start,
                        body.len(),
                        format!("not a session record: {e}"),
                    ))
                }
            };
            let bad_uid = |uid: Uid, tree: &Tree| {
                if tree.get(uid).is_none() {
                    Err(err_at(
                        start,
                        body.len(),
                        format!(
                            "uid {uid} is not a node of the session's tree ({} nodes)",
                            tree.len()
                        ),
                    ))
                } else {
                    Ok(())
                }
            };
            // Every tick costs the index a little: a tick number may run
            // ahead of the records by the empty ticks a session may hold.
            let too_far = |tick: u32| {
                if tick as u64 > i as u64 + EMPTY_TICKS_MAX as u64 {
                    Err(err_at(
                        start,
                        body.len(),
                        format!(
                            "tick {tick} leaves more than {EMPTY_TICKS_MAX} ticks in which nothing happened (at most that many are kept)"
                        ),
                    ))
                } else {
                    Ok(())
                }
            };
            if end.is_some() {
                return Err(err_at(
                    start,
                    body.len(),
                    "a record after the end record".into(),
                ));
            }
            match rec {
                Record::Transition {
                    tick,
                    uid,
                    from,
                    to,
                    decision,
                    ..
                } => {
                    bad_uid(uid, &tree)?;
                    too_far(tick)?;
                    if tick < index.ticks() || tick == 0 {
                        return Err(err_at(
                            start,
                            body.len(),
                            format!("tick {tick} comes after tick {}", index.ticks()),
                        ));
                    }
                    index.push_transition(
                        &tree,
                        Transition {
                            tick,
                            uid,
                            prev: from,
                            status: to,
                        },
                        decision,
                    );
                }
                Record::Decision {
                    tick,
                    uid,
                    decision,
                    ..
                } => {
                    bad_uid(uid, &tree)?;
                    index.push_decision_call(tick, uid, decision);
                }
                Record::Write {
                    tick,
                    uid,
                    entry,
                    value,
                    ..
                } => {
                    if entry.scope >= tree.scopes.len() {
                        return Err(err_at(
                            start,
                            body.len(),
                            format!(
                                "a write to scope {}, and the session's tree has {} scopes",
                                entry.scope,
                                tree.scopes.len()
                            ),
                        ));
                    }
                    index.push_write_by(tick, uid, entry, value)
                }
                Record::Insert {
                    copy_of,
                    after,
                    first_uid,
                    question,
                    ..
                } => {
                    bad_uid(copy_of, &tree)?;
                    bad_uid(after, &tree)?;
                    let (t2, first) = tree
                        .with_copy_after(copy_of, after)
                        .map_err(|m| err_at(start, body.len(), m))?;
                    if first != first_uid {
                        return Err(err_at(start, body.len(), format!("the inserted nodes were numbered from {first_uid}, btx numbers them from {first}")));
                    }
                    tree = t2;
                    index.resize(tree.len());
                    inserts.push((
                        index.transitions.len() as u32,
                        copy_of,
                        after,
                        first_uid,
                        question,
                    ));
                }
                Record::Gap { reason, .. } => {
                    let at = index.transitions.len();
                    warnings.push(Warning {
                        location: format!("{}: transition {}", path.display(), at + 1),
                        message: format!("gap: {reason}"),
                    });
                    index.gaps.push((at as u32, reason));
                }
                Record::Resync { states, .. } => {
                    for b in &states {
                        bad_uid(b.uid, &tree)?;
                    }
                    index.push_resync(&states);
                }
                Record::End {
                    ticks,
                    root,
                    reason,
                    ..
                } => {
                    too_far(ticks)?;
                    index.end_tick(ticks);
                    end = Some((ticks, root, reason));
                }
            }
        }
        // Writes of a last call whose transition never came are shown.
        index.end_tick(index.ticks());
        if end.is_none() {
            warnings.push(Warning {
                location: path.display().to_string(),
                message: format!(
                    "the session has no end record: the run stopped after tick {}",
                    index.ticks()
                ),
            });
        }
        Ok(Session {
            path: path.to_path_buf(),
            header,
            tree,
            index,
            end,
            inserts,
            span_us: None,
            times_us: Vec::new(),
            warnings,
        })
    }

    pub fn at(&self, m: Moment) -> Result<At<'_>, String> {
        Ok(self.index.at(self.index.position(m)?))
    }
}
