//! Replaying a recorded run through the executor: every leaf call returns
//! what the record says that call returned (and makes the writes it made),
//! so the executor rebuilds what a record cannot hold: which nodes were
//! ticked in a tick (a node that stays RUNNING leaves no transition), where
//! a composite resumes, which Parallel children are done.

use super::blackboard::EntryId;
use super::exec::{LeafCall, LeafOutcome, Leaves};
use super::status::Status;
use crate::model::Uid;
use serde_json::Value;
use std::collections::{HashMap, VecDeque};

/// One recorded call of a leaf: what it returned, chose and wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct Call {
    pub status: Status,
    pub decision: Option<String>,
    pub writes: Vec<(EntryId, Value)>,
}

/// Leaves that do what a record says.
#[derive(Debug, Default, Clone)]
pub struct Replay {
    initial: Vec<(EntryId, Value)>,
    calls: HashMap<(u32, Uid), VecDeque<Call>>,
    /// The status a leaf returned last, for calls the record does not hold.
    last: HashMap<Uid, Status>,
    /// Calls the record did not hold and that were not resumptions: the
    /// replay guessed them (tick, uid).
    pub guessed: Vec<(u32, Uid)>,
    /// The record holds the writes of each call, its post-condition
    /// scripts' included (a session btx wrote, not a log).
    pub writes_recorded: bool,
    /// Whether each leaf's last call came from the record.
    from_record: HashMap<Uid, bool>,
    /// Each node's status now, as the executor set it.
    now: HashMap<Uid, Status>,
}

impl Replay {
    pub fn new(initial: Vec<(EntryId, Value)>) -> Replay {
        Replay {
            initial,
            ..Replay::default()
        }
    }

    /// Adds a recorded call of `uid` in `tick`, after the ones added before.
    pub fn push(&mut self, tick: u32, uid: Uid, call: Call) {
        self.calls.entry((tick, uid)).or_default().push_back(call);
    }

    /// Drops the calls of the ticks before `tick` that were not replayed.
    pub fn forget_before(&mut self, tick: u32) {
        self.calls.retain(|&(t, _), _| t >= tick);
    }

    /// Whether the calls not in the record are guessed alike from here
    /// (the status each leaf returned last, and has now, the same).
    pub fn same_memory(&self, o: &Replay) -> bool {
        let busy = |m: &HashMap<Uid, Status>| {
            let mut v: Vec<(Uid, Status)> = m
                .iter()
                .filter(|(_, s)| **s != Status::Idle)
                .map(|(u, s)| (*u, *s))
                .collect();
            v.sort_unstable_by_key(|(u, _)| *u);
            v
        };
        self.last == o.last
            && busy(&self.now) == busy(&o.now)
            && self.initial == o.initial
            && self.writes_recorded == o.writes_recorded
    }

    /// Whether every recorded call was replayed.
    pub fn exhausted(&self) -> bool {
        self.calls.values().all(VecDeque::is_empty)
    }
}

impl Leaves for Replay {
    fn tick(&mut self, call: &mut LeafCall) -> LeafOutcome {
        let next = self
            .calls
            .get_mut(&(call.tick, call.uid))
            .and_then(VecDeque::pop_front);
        self.from_record.insert(call.uid, next.is_some());
        let (status, decision) = match next {
            Some(c) => {
                for (e, v) in c.writes {
                    call.write_entry(e, v);
                }
                (c.status, c.decision)
            }
            // A RUNNING leaf ticked again without a change leaves no record;
            // so does a leaf that returns the status it has (a FAILURE
            // ticked again, as a reactive node or a pre-condition that no
            // longer holds for a node not IDLE leaves it).
            None if call.resumed => (Status::Running, None),
            None if self.now.get(&call.uid).is_some_and(|s| s.is_completed()) => {
                (self.now[&call.uid], None)
            }
            None => {
                self.guessed.push((call.tick, call.uid));
                (
                    self.last.get(&call.uid).copied().unwrap_or(Status::Success),
                    None,
                )
            }
        };
        self.last.insert(call.uid, status);
        LeafOutcome { status, decision }
    }

    fn observe(&mut self, uid: Uid, _prev: Status, status: Status) {
        self.now.insert(uid, status);
    }

    fn post_scripts_recorded(&self, uid: Uid) -> bool {
        self.writes_recorded && self.from_record.get(&uid).copied().unwrap_or(false)
    }

    fn initial_entries(&self) -> Vec<(EntryId, Value)> {
        self.initial.clone()
    }
}
