//! A session built record by record from whichever file holds it (JSON
//! lines or Parquet), so both are read under one set of checks.

use super::format::{self, Header, Record};
use super::index::{Index, Transition, EMPTY_TICKS_MAX};
use super::sink::{Locate, Sink};
use super::Session;
use crate::model::{Tree, Uid};
use crate::source::{Located, Warning};
use crate::xml::{load_str, LoadOptions};
use std::path::{Path, PathBuf};

pub(super) struct Builder {
    path: PathBuf,
    header: Header,
    tree: Tree,
    index: Index,
    end: Option<(u32, crate::run::Status, String)>,
    inserts: Vec<(u32, Uid, Uid, Uid, String)>,
    /// Each transition's time, while every one so far has one.
    times_us: Vec<i64>,
    warnings: Vec<Warning>,
}

impl Builder {
    /// Checks the header and loads the tree it embeds; `err` locates an
    /// error in the header.
    pub fn new(path: &Path, header: Header, err: Locate) -> Result<Builder, Located> {
        if header.btx_session != format::FORMAT_VERSION {
            return Err(err(format!(
                "session format {} is not one this btx reads (it reads {})",
                header.btx_session,
                format::FORMAT_VERSION
            )));
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
                return Err(err(format!(
                    "the blackboard names scope {}, and the session's tree has {scopes} scopes",
                    e.scope
                )));
            }
            index.push_write(e.clone(), v.clone());
        }
        Ok(Builder {
            path: path.to_path_buf(),
            header,
            tree,
            index,
            end: None,
            inserts: Vec::new(),
            times_us: Vec::new(),
            warnings: Vec::new(),
        })
    }

    /// A warning about the file, at `location`.
    pub fn warn(&mut self, location: String, message: String) {
        self.warnings.push(Warning { location, message });
    }

    fn known(&self, uid: Uid, err: Locate) -> Result<(), Located> {
        if self.tree.get(uid).is_none() {
            return Err(err(format!(
                "uid {uid} is not a node of the session's tree ({} nodes)",
                self.tree.len()
            )));
        }
        Ok(())
    }

    /// Record number `nth` (counting the header as the first): a tick number
    /// may run ahead of the records by the empty ticks a session may hold,
    /// since every tick costs the index a little.
    fn near(nth: usize, tick: u32, err: Locate) -> Result<(), Located> {
        if tick as u64 > nth as u64 + EMPTY_TICKS_MAX as u64 {
            return Err(err(format!(
                "tick {tick} leaves more than {EMPTY_TICKS_MAX} ticks in which nothing happened (at most that many are kept)"
            )));
        }
        Ok(())
    }

    /// Adds record number `nth` (the header is the first).
    pub fn record(&mut self, nth: usize, rec: Record, err: Locate) -> Result<(), Located> {
        if self.end.is_some() {
            return Err(err("a record after the end record".into()));
        }
        match rec {
            Record::Transition {
                tick,
                uid,
                from,
                to,
                decision,
                time_us,
                ..
            } => {
                self.known(uid, err)?;
                Self::near(nth, tick, err)?;
                let t = Transition {
                    tick,
                    uid,
                    prev: from,
                    status: to,
                };
                self.transition(t, decision, time_us, err)?;
            }
            Record::Decision {
                tick,
                uid,
                decision,
                ..
            } => {
                self.known(uid, err)?;
                self.index.push_decision_call(tick, uid, decision);
            }
            Record::Write {
                tick,
                uid,
                entry,
                value,
                ..
            } => self.write(tick, uid, entry, value, err)?,
            Record::Insert {
                copy_of,
                after,
                first_uid,
                question,
                ..
            } => self.insert(copy_of, after, first_uid, question, err)?,
            Record::Gap { reason, .. } => self.gap(reason),
            Record::Resync { states, .. } => {
                for b in &states {
                    self.known(b.uid, err)?;
                }
                self.index.push_resync(&states);
            }
            Record::End {
                ticks,
                root,
                reason,
                ..
            } => {
                Self::near(nth, ticks, err)?;
                self.index.end_tick(ticks);
                self.end = Some((ticks, root, reason));
            }
        }
        Ok(())
    }

    /// A blackboard write, to a scope the session's tree has.
    fn write(
        &mut self,
        tick: u32,
        uid: Uid,
        entry: crate::run::blackboard::EntryId,
        value: serde_json::Value,
        err: Locate,
    ) -> Result<(), Located> {
        if entry.scope >= self.tree.scopes.len() {
            return Err(err(format!(
                "a write to scope {}, and the session's tree has {} scopes",
                entry.scope,
                self.tree.scopes.len()
            )));
        }
        self.index.push_write_by(tick, uid, entry, value);
        Ok(())
    }

    /// Transitions the recorder lost: said, and kept where they were lost.
    fn gap(&mut self, reason: String) {
        let at = self.index.transitions.len();
        self.warn(
            format!("{}: transition {}", self.path.display(), at + 1),
            format!("gap: {reason}"),
        );
        self.index.gaps.push((at as u32, reason));
    }

    /// A status transition, in order of ticks; its time kept only if
    /// every transition has one.
    fn transition(
        &mut self,
        t: Transition,
        decision: Option<String>,
        time_us: Option<i64>,
        err: Locate,
    ) -> Result<(), Located> {
        if t.tick < self.index.ticks() || t.tick == 0 {
            return Err(err(format!(
                "tick {} comes after tick {}",
                t.tick,
                self.index.ticks()
            )));
        }
        self.index.push_transition(&self.tree, t, decision);
        match time_us {
            Some(us) if self.times_us.len() + 1 == self.index.transitions.len() => {
                self.times_us.push(us)
            }
            _ => self.times_us.clear(),
        }
        Ok(())
    }

    /// A behaviour inserted as a subgoal during the run ("Can you X?"):
    /// the tree grows by a copy of `copy_of` after `after`, numbered as
    /// the record says btx numbers it.
    fn insert(
        &mut self,
        copy_of: Uid,
        after: Uid,
        first_uid: Uid,
        question: String,
        err: Locate,
    ) -> Result<(), Located> {
        self.known(copy_of, err)?;
        self.known(after, err)?;
        let (t2, first) = self.tree.with_copy_after(copy_of, after).map_err(err)?;
        if first != first_uid {
            return Err(err(format!(
                "the inserted nodes were numbered from {first_uid}, btx numbers them from {first}"
            )));
        }
        self.tree = t2;
        self.index.resize(self.tree.len());
        self.inserts.push((
            self.index.transitions.len() as u32,
            copy_of,
            after,
            first_uid,
            question,
        ));
        Ok(())
    }

    pub fn finish(mut self) -> Session {
        // Writes of a last call whose transition never came are shown.
        self.index.end_tick(self.index.ticks());
        if self.end.is_none() {
            let location = self.path.display().to_string();
            let message = format!(
                "the session has no end record: the run stopped after tick {}",
                self.index.ticks()
            );
            self.warn(location, message);
        }
        let times_us = if self.times_us.len() == self.index.transitions.len() {
            std::mem::take(&mut self.times_us)
        } else {
            Vec::new()
        };
        Session {
            path: self.path,
            header: self.header,
            tree: self.tree,
            index: self.index,
            end: self.end,
            inserts: self.inserts,
            span_us: times_us.first().zip(times_us.last()).map(|(a, b)| (*a, *b)),
            times_us,
            warnings: self.warnings,
            run: None,
        }
    }
}

/// A session being read: the builder once the header has come.
#[derive(Default)]
pub(super) struct Building(Option<Builder>);

impl Building {
    /// The session read; a reader gives every file a header or an error.
    pub fn session(self) -> Session {
        self.0
            .expect("a session file's header is read first")
            .finish()
    }
}

impl Sink for Building {
    fn header(
        &mut self,
        path: &Path,
        _text: &str,
        header: Header,
        err: Locate,
    ) -> Result<(), Located> {
        self.0 = Some(Builder::new(path, header, err)?);
        Ok(())
    }

    fn record(&mut self, nth: usize, rec: Record, err: Locate) -> Result<(), Located> {
        match &mut self.0 {
            Some(b) => b.record(nth, rec, err),
            None => Err(err("a record before the session's header".into())),
        }
    }

    fn warn(&mut self, location: String, message: String) {
        if let Some(b) = &mut self.0 {
            b.warn(location, message);
        }
    }
}
