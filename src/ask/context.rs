//! What a question is asked of (a tree, or a moment of a run) and what
//! the run holds for it: the run at the moment, the occurrences of an
//! event at a node.

use super::parse::Event;
use crate::model::{Tree, Uid};
use crate::run::Status;
use crate::session::{At, Session};

/// What a question is asked of: a tree, or a moment of a run.
pub struct Context<'a> {
    pub tree: &'a Tree,
    /// The run, when it can be re-run or searched (`btx why`'s input).
    pub session: Option<&'a Session>,
    pub at: Option<At<'a>>,
    /// The tick the user is at, where it is said: a tick where nothing
    /// changed has the position of the tick before it, and "this tick"
    /// is still this one.
    pub tick: Option<u32>,
    /// The node picked with `--node`, if any.
    pub node: Option<Uid>,
    pub detail: super::detail::Detail,
    /// The node the previous question was about: what "it" means next.
    pub last: std::cell::Cell<Option<Uid>>,
}

impl Context<'_> {
    /// "it": the node of the previous question, else the selected one,
    /// else the task.
    pub fn it(&self) -> Uid {
        self.last
            .get()
            .or(self.node)
            .unwrap_or(self.tree.root().uid)
    }

    pub(super) fn name(&self, uid: Uid) -> String {
        self.tree.told(uid)
    }

    /// "by the end of the run at tick 54", "by the end of tick 12" or "by
    /// moment 10:3".
    pub(super) fn by(&self, at: &At) -> String {
        crate::causal::calls::by_moment(at.index, at.pos)
    }
}

/// The run at the question's moment, or why there is none.
/// A live robot's statuses are read at one moment: what happened before
/// it (when, how often, a tick, a recovery, a why) is not known, and is
/// said so rather than answered from an empty history.
pub(super) fn run_of<'a>(cx: &'a Context, what: &str) -> Result<&'a At<'a>, String> {
    let at = cx.at.as_ref().ok_or_else(|| {
        format!("\"{what}\" is about a run: ask it of a session or a log, at a moment")
    })?;
    if cx.session.is_none() {
        return Err(format!(
            "\"{what}\" is about what happened before now, and btx read the robot's statuses at this moment only: keep the run with btx watch --out RUN.jsonl (or btx open --live --out) and ask the run"
        ));
    }
    Ok(at)
}

/// Whether transition `t` is an occurrence of `e`.
pub(super) fn is_event(prev: Status, status: Status, e: Event) -> bool {
    let done = |s: Status| matches!(s, Status::Success | Status::Failure);
    match e {
        Event::Fail => status == Status::Failure,
        Event::Succeed => status == Status::Success,
        Event::Finish => done(status),
        Event::Run => prev != Status::Running && status != Status::Idle && prev != status,
        Event::KeepRunning => status == Status::Running,
        Event::Halted => prev == Status::Running && status == Status::Idle,
        Event::NotRun | Event::Skipped => false,
    }
}

/// Positions, up to the moment, after each occurrence of `e` at `uid`.
/// A node halted within its own call (Nav2's `halt()` resets it to IDLE
/// before it returns FAILURE) does not start again when it completes:
/// RUNNING → IDLE → FAILURE in one tick is one call.
pub(super) fn events(at: &At, uid: Uid, e: Event) -> Vec<u32> {
    let changes = at.index.changes_of(uid);
    changes
        .iter()
        .enumerate()
        .filter(|&(_, &p)| p <= at.pos)
        .filter(|&(i, &p)| {
            let t = at.index.transitions[p as usize - 1];
            if !is_event(t.prev, t.status, e) {
                return false;
            }
            let halted_in_call = e == Event::Run
                && t.prev == Status::Idle
                && matches!(t.status, Status::Success | Status::Failure)
                && i > 0
                && {
                    let b = at.index.transitions[changes[i - 1] as usize - 1];
                    b.tick == t.tick && b.prev == Status::Running && b.status == Status::Idle
                };
            !halted_in_call
        })
        .map(|(_, &p)| p)
        .collect()
}
