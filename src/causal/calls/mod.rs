//! The run as the model (#39 item 1): every leaf's outcome at each of its
//! calls, as recorded, drives the executor again, so that every TICK:STEP
//! of a run is a real call, whatever re-calls a tick holds (a Nav2
//! RecoveryNode running its pipeline again, reactive re-ticks, retries).
//! A counterfactual flips one leaf's outcome at one call; the executor
//! says what the tree would then have done. Where the executor cannot
//! reproduce the record (time-driven nodes, blackboard values the record
//! does not hold), nothing is claimed from a re-run.

mod never;
mod told;

pub use never::never_ran;
pub use told::*;

/// "by moment 4:5", "by the end of tick 6", or "by the end of the run at
/// tick 10": how far the run is told, at position `upto`.
pub fn by_moment(idx: &crate::session::Index, upto: u32) -> String {
    let m = idx.moment(upto);
    if upto as usize >= idx.transitions.len() {
        format!("by the end of the run at tick {}", m.tick)
    } else if m.step.is_none() {
        format!("by the end of tick {}", m.tick)
    } else {
        format!("by moment {m}")
    }
}

use super::english::capitalised;
use crate::model::{Tree, Uid};
use crate::run::exec::{Event, Executor, LeafCall, LeafOutcome, Leaves, RunOptions};
use crate::run::Status;
use crate::session::{Moment, Session};

/// How one recorded call of a leaf ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum End {
    Done(Status),
    /// Halted, or still running when the record ends: what it would have
    /// returned next is not in the run.
    Cut,
}

#[derive(Debug, Clone, Copy)]
struct Call {
    /// The tick it started in.
    start: u32,
    /// Ticks from its start to its end (0: it completed when it started).
    ticks: u32,
    end: End,
    /// The record's position of its completion or halt (0 when it was
    /// still running at the record's end).
    end_pos: u32,
    /// The record's position of its start.
    start_pos: u32,
}

/// Each leaf's recorded calls, in order. A call the record shows is one
/// that changed the leaf's status: a leaf ticked again with the status it
/// already had (a condition under a reactive node) leaves no transition,
/// and is replayed as such a repeat.
fn recorded_calls(session: &Session) -> Vec<Vec<Call>> {
    let idx = &session.index;
    let mut calls: Vec<Vec<Call>> = vec![Vec::new(); session.tree.len()];
    let mut open: Vec<Option<(u32, u32)>> = vec![None; session.tree.len()];
    let done = |s: Status| matches!(s, Status::Success | Status::Failure);
    for (i, t) in idx.transitions.iter().enumerate() {
        let n = session.tree.node(t.uid);
        if !n.kind.is_leaf() || n.builtin.is_some() {
            continue;
        }
        let u = t.uid as usize - 1;
        let pos = i as u32 + 1;
        match (t.prev, t.status) {
            (Status::Running, s) if done(s) => {
                let (start, start_pos) = open[u].take().unwrap_or((t.tick, pos));
                calls[u].push(Call {
                    start,
                    ticks: t.tick - start,
                    end: End::Done(s),
                    end_pos: pos,
                    start_pos,
                });
            }
            (Status::Running, Status::Idle) => {
                let (start, start_pos) = open[u].take().unwrap_or((t.tick, pos));
                calls[u].push(Call {
                    start,
                    ticks: t.tick - start,
                    end: End::Cut,
                    end_pos: pos,
                    start_pos,
                });
            }
            (_, Status::Running) => open[u] = Some((t.tick, pos)),
            (_, s) if done(s) => calls[u].push(Call {
                start: t.tick,
                ticks: 0,
                end: End::Done(s),
                end_pos: pos,
                start_pos: pos,
            }),
            _ => {}
        }
    }
    for (u, o) in open.iter().enumerate() {
        if let Some((start, start_pos)) = *o {
            calls[u].push(Call {
                start,
                ticks: u32::MAX,
                end: End::Cut,
                end_pos: 0,
                start_pos,
            });
        }
    }
    calls
}

/// Leaves that return what the record says each of their calls returned,
/// with one call's outcome flipped where a counterfactual asks.
struct ReplayLeaves {
    calls: Vec<Vec<Call>>,
    next: Vec<usize>,
    /// The open call of each leaf: its start tick and index.
    open: Vec<Option<(u32, usize)>>,
    /// Each leaf's status, as the executor set it.
    status: Vec<Status>,
    flip: Option<(Uid, usize, Status)>,
    /// Leaves asked for more than the record holds (a call it has not, or
    /// past a halt): they return what they last returned, or keep running.
    assumed: Vec<Uid>,
    /// Actions with no call left are started, and run on (a prediction:
    /// an action's next call has not ended yet), rather than repeat their
    /// last outcome (a counterfactual's re-run of a record).
    actions_run: Vec<bool>,
}

impl ReplayLeaves {
    fn new(
        calls: Vec<Vec<Call>>,
        flip: Option<(Uid, usize, Status)>,
        actions_run: Vec<bool>,
    ) -> Self {
        let n = calls.len();
        ReplayLeaves {
            actions_run,
            calls,
            next: vec![0; n],
            open: vec![None; n],
            status: vec![Status::Idle; n],
            flip,
            assumed: Vec::new(),
        }
    }

    fn assume(&mut self, uid: Uid) {
        if !self.assumed.contains(&uid) {
            self.assumed.push(uid);
        }
    }
}

impl Leaves for ReplayLeaves {
    fn tick(&mut self, call: &mut LeafCall) -> LeafOutcome {
        let i = call.uid as usize - 1;
        let now = self.status[i];
        let (start, k) = match self.open[i] {
            Some(o) => o,
            // Ticked again with the outcome it had, and the record's next
            // call is later: a repeat the record could not show.
            None if matches!(now, Status::Success | Status::Failure)
                && self.calls[i]
                    .get(self.next[i])
                    .is_none_or(|c| c.start > call.tick) =>
            {
                return LeafOutcome {
                    status: now,
                    decision: None,
                };
            }
            None => {
                let k = self.next[i];
                self.next[i] += 1;
                self.open[i] = Some((call.tick, k));
                (call.tick, k)
            }
        };
        let status = match self.calls[i].get(k).copied() {
            Some(c) if call.tick < start.saturating_add(c.ticks) => Status::Running,
            Some(Call {
                end: End::Done(s), ..
            }) => match self.flip {
                Some((u, fk, to)) if u == call.uid && fk == k => to,
                _ => s,
            },
            Some(Call { end: End::Cut, .. }) => {
                self.assume(call.uid);
                Status::Running
            }
            None if self.actions_run.get(i).copied().unwrap_or(false) => {
                self.assume(call.uid);
                Status::Running
            }
            None => {
                self.assume(call.uid);
                // As it last ended in the record, else a success.
                self.calls[i]
                    .iter()
                    .rev()
                    .find_map(|c| match c.end {
                        End::Done(s) => Some(s),
                        End::Cut => None,
                    })
                    .unwrap_or(Status::Success)
            }
        };
        if status != Status::Running {
            self.open[i] = None;
        }
        LeafOutcome {
            status,
            decision: None,
        }
    }

    fn halt(&mut self, uid: Uid) {
        self.open[uid as usize - 1] = None;
    }

    fn observe(&mut self, uid: Uid, _prev: Status, status: Status) {
        if let Some(s) = self.status.get_mut(uid as usize - 1) {
            *s = status;
        }
    }
}

/// A session whose run the executor reproduces from its recorded calls.
pub struct Replay<'s> {
    pub(super) session: &'s Session,
    calls: Vec<Vec<Call>>,
    /// Which leaves are actions that start and run on once their recorded
    /// calls are used up (`as_of`); empty: none.
    actions_run: Vec<bool>,
}

/// Why a run cannot be replayed from its calls.
fn not_replayable(session: &Session) -> Option<String> {
    if session.index.attached() {
        return Some("the record starts in the middle of the run".into());
    }
    if !session.inserts.is_empty() {
        return Some("a subgoal was inserted during the run".into());
    }
    if !session.index.gaps.is_empty() {
        return Some("the record has gaps".into());
    }
    None
}

/// The most ticks one re-run may take (past the record's last tick it
/// stops anyway).
const TICKS_MAX: u32 = 1_000_000;

impl<'s> Replay<'s> {
    /// The run's calls, checked: running them again gives the recorded
    /// transitions up to position `upto`, else the reason it does not.
    pub fn new(session: &'s Session, upto: u32) -> Result<Replay<'s>, String> {
        if let Some(why) = not_replayable(session) {
            return Err(why);
        }
        Replay {
            session,
            calls: recorded_calls(session),
            actions_run: Vec::new(),
        }
        .checked(upto)
    }

    /// The run's calls as they stood at position `pos`, when nothing later
    /// was known: a call running then keeps running; past its recorded
    /// calls a condition repeats its last outcome and an action starts and
    /// runs on (`assumed`). Checked as `new`.
    pub(super) fn as_of(session: &'s Session, pos: u32) -> Result<Replay<'s>, String> {
        if let Some(why) = not_replayable(session) {
            return Err(why);
        }
        let mut calls = recorded_calls(session);
        for cs in &mut calls {
            cs.retain(|c| c.start_pos <= pos);
            // Ended after `pos`: then it was running, its end not known.
            if let Some(c) = cs.last_mut().filter(|c| c.end_pos > pos) {
                c.end = End::Cut;
                c.ticks = u32::MAX;
                c.end_pos = 0;
            }
        }
        let actions_run = session
            .tree
            .nodes
            .iter()
            .map(|n| {
                n.kind == crate::model::Kind::Action
                    && n.builtin.is_none()
                    // Nav2's selectors and the like end in the tick they start.
                    && crate::model::nav2::at_once(&n.id, session.tree.release).is_none()
            })
            .collect();
        Replay {
            session,
            calls,
            actions_run,
        }
        .checked(pos)
    }

    fn checked(self, upto: u32) -> Result<Replay<'s>, String> {
        let r = self;
        let session = r.session;
        let want = &session.index.transitions[..upto as usize];
        let mut got = 0usize;
        let mut differs = None;
        r.run(None, session.index.ticks(), |_, t| {
            if got >= want.len() {
                return false;
            }
            let w = want[got];
            if (w.tick, w.uid, w.prev, w.status) != t {
                differs = Some(got + 1);
                return false;
            }
            got += 1;
            true
        })?;
        match differs {
            Some(i) => Err(format!(
                "running the tree again on the recorded outcomes of its leaves does not give the recorded run (transition {i} differs: {})",
                describe(&session.tree, &want[i - 1])
            )),
            None if got < want.len() => Err(format!(
                "running the tree again on the recorded outcomes of its leaves stops before the recorded run does (at transition {})",
                got + 1
            )),
            None => Ok(r),
        }
    }

    /// Runs the tree on the recorded calls (with `flip`), handing each
    /// transition to `sink` until it says stop, the root completes or the
    /// record's ticks are past. The leaves the re-run asked more of than the
    /// record holds.
    pub(super) fn run(
        &self,
        flip: Option<(Uid, usize, Status)>,
        last: u32,
        mut sink: impl FnMut(u32, (u32, Uid, Status, Status)) -> bool,
    ) -> Result<Vec<Uid>, String> {
        let s = self.session;
        let mut ex = Executor::new(
            &s.tree,
            ReplayLeaves::new(self.calls.clone(), flip, self.actions_run.clone()),
            RunOptions {
                tick_ms: s.header.tick_ms.max(1),
                nav2: s.header.nav2.unwrap_or_default(),
            },
        );
        let last = last.min(TICKS_MAX);
        for _ in 1..=last {
            let r = ex.tick_once();
            let mut in_tick = 0u32;
            for e in ex.take_events() {
                if let Event::Transition {
                    tick,
                    uid,
                    prev,
                    status,
                    ..
                } = e
                {
                    in_tick += 1;
                    if !sink(in_tick, (tick, uid, prev, status)) {
                        return Ok(ex.leaves.assumed.clone());
                    }
                }
            }
            match r {
                Ok(Status::Success | Status::Failure) => break,
                Ok(_) => {}
                Err(e) => return Err(format!("the re-run stopped: {e}")),
            }
        }
        Ok(ex.leaves.assumed.clone())
    }
}

fn describe(tree: &Tree, t: &crate::session::Transition) -> String {
    format!(
        "{} (#{}) {} -> {} in tick {}",
        tree.description(t.uid),
        t.uid,
        t.prev.as_str(),
        t.status.as_str(),
        t.tick
    )
}

/// One leaf's call whose other outcome changes the event asked about,
/// found by running the tree again with it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CallCause {
    pub leaf: Uid,
    /// The record's position of that call's completion, and its moment.
    pub pos: u32,
    pub at: Moment,
    pub was: Status,
    /// What the node asked about did then instead: its call's status and
    /// moment, or `None` when that call had not ended by the record's end.
    pub instead: Option<(Status, Moment)>,
    /// Leaves the re-run needed more of than the record holds.
    pub assumed: Vec<Uid>,
}

/// What the search over a run's calls found for one event.
#[derive(Debug, Clone, Default)]
pub struct CallCauses {
    /// Latest first.
    pub causes: Vec<CallCause>,
    /// Calls tried, and calls there were to try.
    pub tried: usize,
    pub candidates: usize,
}

/// The most calls tried for one event, and the most ticks replayed for
/// them in all.
const CALLS_MAX: usize = 64;
const TICKS_BUDGET: u64 = 400_000;

/// Which calls a search tries.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Within {
    /// Leaves below the node, since its call started: what it answered.
    Below,
    /// Any leaf before the event.
    Anywhere,
}

impl Replay<'_> {
    /// The leaf calls that ended before position `p` and may have caused
    /// `u`'s completion there: (leaf, which call, where it ended, how).
    fn candidates(&self, u: Uid, p: u32, within: Within) -> Vec<(Uid, usize, u32, Status)> {
        let tree = &self.session.tree;
        let since = self.session.index.call_start(u, p).unwrap_or(0);
        let mut cands = Vec::new();
        for (i, calls) in self.calls.iter().enumerate() {
            let leaf = i as Uid + 1;
            if leaf == u || within == Within::Below && !tree.is_ancestor(u, leaf) {
                continue;
            }
            for (k, c) in calls.iter().enumerate() {
                if let End::Done(s) = c.end {
                    if c.end_pos < p && (within == Within::Anywhere || c.end_pos > since) {
                        cands.push((leaf, k, c.end_pos, s));
                    }
                }
            }
        }
        cands
    }

    /// The completion of node `u` at position `p` (its SUCCESS or FAILURE):
    /// each earlier leaf call whose other outcome changes it, found by
    /// running the tree again with that one outcome flipped.
    pub fn causes(&self, u: Uid, p: u32, within: Within) -> CallCauses {
        let idx = &self.session.index;
        let event = idx.transitions[p as usize - 1];
        let ended = |s: Status| matches!(s, Status::Success | Status::Failure);
        // Which of u's completions this is.
        let nth = idx
            .changes_of(u)
            .iter()
            .filter(|&&q| q <= p && ended(idx.transitions[q as usize - 1].status))
            .count();
        let mut cands = self.candidates(u, p, within);
        cands.sort_by_key(|c| std::cmp::Reverse(c.2));
        let mut out = CallCauses {
            candidates: cands.len(),
            ..CallCauses::default()
        };
        let per_run = u64::from(event.tick.max(1));
        for (leaf, k, pos, was) in cands.into_iter().take(CALLS_MAX) {
            if (out.tried as u64 + 1) * per_run > TICKS_BUDGET {
                break;
            }
            out.tried += 1;
            let to = if was == Status::Success {
                Status::Failure
            } else {
                Status::Success
            };
            let mut seen = 0usize;
            let mut instead = None;
            let last = idx.ticks();
            let Ok(assumed) =
                self.run(Some((leaf, k, to)), last, |step, (tick, uid, _, status)| {
                    if uid == u && ended(status) {
                        seen += 1;
                        if seen == nth {
                            instead = Some((
                                status,
                                Moment {
                                    tick,
                                    step: Some(step),
                                },
                            ));
                            return false;
                        }
                    }
                    true
                })
            else {
                continue;
            };
            if instead.is_some_and(|(s, _)| s == event.status) {
                continue;
            }
            out.causes.push(CallCause {
                leaf,
                pos,
                at: step_moment(idx, pos),
                was,
                instead,
                assumed,
            });
        }
        out
    }
}
