//! The run as the model (#39 item 1): every leaf's outcome at each of its
//! calls, as recorded, drives the executor again, so that every TICK:STEP
//! of a run is a real call, whatever re-calls a tick holds (a Nav2
//! RecoveryNode running its pipeline again, reactive re-ticks, retries).
//! A counterfactual flips one leaf's outcome at one call; the executor
//! says what the tree would then have done. Where the executor cannot
//! reproduce the record (time-driven nodes, blackboard values the record
//! does not hold), nothing is claimed from a re-run.

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
    /// The completion of node `u` at position `p` (its SUCCESS or FAILURE):
    /// each earlier leaf call whose other outcome changes it, found by
    /// running the tree again with that one outcome flipped.
    pub fn causes(&self, u: Uid, p: u32, within: Within) -> CallCauses {
        let idx = &self.session.index;
        let tree = &self.session.tree;
        let event = idx.transitions[p as usize - 1];
        let ended = |s: Status| matches!(s, Status::Success | Status::Failure);
        // Which of u's completions this is.
        let nth = idx
            .changes_of(u)
            .iter()
            .filter(|&&q| q <= p && ended(idx.transitions[q as usize - 1].status))
            .count();
        let since = idx.call_start(u, p).unwrap_or(0);
        let mut cands: Vec<(Uid, usize, u32, Status)> = Vec::new();
        for (i, calls) in self.calls.iter().enumerate() {
            let leaf = i as Uid + 1;
            if leaf == u {
                continue;
            }
            if within == Within::Below && !tree.is_ancestor(u, leaf) {
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

/// A why about a node's completion, answered from the run's calls.
#[derive(Debug, Clone)]
pub struct Told {
    pub uid: Uid,
    /// The record's position of the completion, its status and moment.
    pub pos: u32,
    pub status: Status,
    pub moment: Moment,
    /// The causes found, or why the run could not be replayed.
    pub found: Result<CallCauses, String>,
    /// The record's last tick (a re-run that did not end the call by then).
    pub last_tick: u32,
    /// For a leaf: what the run shows of its call.
    pub leaf_facts: Option<String>,
    /// For a control node: what the run shows of how it ended (the child
    /// it ended after, and what its kind does with that).
    pub design: Option<String>,
}

fn past(s: Status) -> &'static str {
    match s {
        Status::Success => "succeeded",
        Status::Failure => "failed",
        Status::Running => "kept running",
        _ => "was not ticked",
    }
}

impl Told {
    /// Node `u`'s last completion at or before position `pos`, in its tick,
    /// explained by the run's calls; `None` when it completed in no call
    /// by then in that tick.
    pub fn of(session: &Session, u: Uid, pos: u32) -> Option<Told> {
        let idx = &session.index;
        let tick = idx.transitions.get(pos.checked_sub(1)? as usize)?.tick;
        let start = idx.tick_range(tick).start as u32;
        let p = idx.changes_of(u).iter().copied().rev().find(|&q| {
            q <= pos
                && q > start
                && matches!(
                    idx.transitions[q as usize - 1].status,
                    Status::Success | Status::Failure
                )
        })?;
        let t = idx.transitions[p as usize - 1];
        let leaf = session.tree.node(u).kind.is_leaf();
        // A leaf decides its own outcome: what the run shows of its call
        // is the answer, and nothing is searched.
        let found = if leaf {
            Ok(CallCauses::default())
        } else {
            Replay::new(session, p).map(|r| {
                let below = r.causes(u, p, Within::Below);
                if below.causes.is_empty() {
                    r.causes(u, p, Within::Anywhere)
                } else {
                    below
                }
            })
        };
        Some(Told {
            uid: u,
            pos: p,
            status: t.status,
            moment: step_moment(idx, p),
            found,
            leaf_facts: leaf.then(|| leaf_facts(session, u, p, idx.transitions.len() as u32)),
            design: (!leaf).then(|| design(session, u, p)),
            last_tick: idx.ticks(),
        })
    }

    /// Each cause as a sentence.
    pub fn sentences(&self, tree: &Tree) -> Vec<String> {
        let Ok(found) = &self.found else {
            return Vec::new();
        };
        let me = tree.told(self.uid);
        // One leaf's several calls are one cause: it failed again.
        let mut groups: Vec<Vec<&CallCause>> = Vec::new();
        for c in &found.causes {
            match groups
                .iter_mut()
                .find(|g| g[0].leaf == c.leaf && g[0].was == c.was)
            {
                Some(g) => g.push(c),
                None => groups.push(vec![c]),
            }
        }
        groups
            .iter()
            .map(|g| {
                let c = g[0];
                let other = if c.was == Status::Success {
                    Status::Failure
                } else {
                    Status::Success
                };
                let would = |c: &CallCause| match c.instead {
                    Some((s, m)) => format!("{me} would have {} at {m}", past(s)),
                    None => format!(
                        "{me} would not have ended that call by tick {}, where the run ends",
                        self.last_tick
                    ),
                };
                let mut assumed: Vec<Uid> = Vec::new();
                for c in g {
                    for &a in &c.assumed {
                        if !assumed.contains(&a) {
                            assumed.push(a);
                        }
                    }
                }
                let assumed = if assumed.is_empty() {
                    String::new()
                } else {
                    let names: Vec<String> = assumed.iter().map(|&a| tree.told(a)).collect();
                    format!(
                        " (assuming {} went on as the run last showed)",
                        names.join(", ")
                    )
                };
                if g.len() == 1 {
                    return format!(
                        "{} {} at {} because {} {} at {}. Had it {} then, {}{assumed}.",
                        capitalised(&me),
                        past(self.status),
                        self.moment,
                        tree.told(c.leaf),
                        past(c.was),
                        c.at,
                        past(other),
                        would(c),
                    );
                }
                let earlier: Vec<String> = g[1..].iter().map(|c| c.at.to_string()).collect();
                let alternatives: Vec<String> = g[1..]
                    .iter()
                    .map(|c| format!("had it {} at {}, {}", past(other), c.at, would(c)))
                    .collect();
                format!(
                    "{} {} at {} because {} {} again at {}, after it {} at {}{}. Had it {} at {}, {}; {}{assumed}.",
                    capitalised(&me),
                    past(self.status),
                    self.moment,
                    tree.told(c.leaf),
                    past(c.was),
                    c.at,
                    past(c.was),
                    earlier.join(", "),
                    self.retries_used(tree, c.leaf),
                    past(other),
                    c.at,
                    would(c),
                    alternatives.join("; "),
                )
            })
            .collect()
    }

    /// ", and the retries of the node that repeats `leaf` were used on it
    /// (number_of_retries=1)", where a RecoveryNode or a retry between the
    /// node asked about and the leaf gives it.
    fn retries_used(&self, tree: &Tree, leaf: Uid) -> String {
        use crate::model::{Builtin, PortValue};
        let Some(a) = std::iter::once(leaf)
            .chain(tree.ancestors(leaf))
            .find(|&a| {
                matches!(
                    tree.node(a).builtin,
                    Some(Builtin::RecoveryNode | Builtin::RetryUntilSuccessful)
                ) && (a == self.uid || tree.is_ancestor(self.uid, a))
            })
        else {
            return String::new();
        };
        let port = tree.node(a).ports.iter().find_map(|p| match &p.value {
            PortValue::Literal(v)
                if matches!(p.name.as_str(), "number_of_retries" | "num_attempts") =>
            {
                Some((p.name.clone(), v.clone()))
            }
            _ => None,
        });
        let whose = if a == self.uid {
            "its".to_string()
        } else {
            format!("{}'s", tree.told(a))
        };
        match port {
            Some((p, v)) if p == "number_of_retries" => format!(
                " and {whose} {} ({p}={v}) {} used",
                if v == "1" {
                    "one retry".to_string()
                } else {
                    format!("{v} retries")
                },
                if v == "1" { "was" } else { "were" }
            ),
            Some((p, v)) => format!(" and {whose} attempts ({p}={v}) were all made"),
            None => String::new(),
        }
    }

    /// The answer: the causes found, latest first (at most `shown`), or
    /// for a leaf what the run shows of its call; `full` adds how they
    /// were found.
    pub fn text(&self, tree: &Tree, shown: Option<usize>, full: bool) -> String {
        let mut out = format!("{}\n", self.question(tree));
        let sentences = self.sentences(tree);
        let n = shown.unwrap_or(usize::MAX).min(sentences.len());
        for (i, s) in sentences[..n].iter().enumerate() {
            out.push_str(&format!("{}. {s}\n", i + 1));
        }
        if n < sentences.len() {
            out.push_str(&format!(
                "{} more (--all shows them).\n",
                sentences.len() - n
            ));
        }
        if sentences.is_empty() {
            if let Some(f) = self.leaf_facts.as_ref().or(self.design.as_ref()) {
                out.push_str(f);
                out.push('\n');
            } else {
                out.push_str(&format!(
                    "No other outcome of one leaf's call before {} changes it.\n",
                    self.moment
                ));
            }
        }
        match &self.found {
            Err(e) if full || sentences.is_empty() => out.push_str(&format!(
                "The run could not be replayed to look further: {e}.\n"
            )),
            Ok(f) if full && f.candidates > 0 => out.push_str(&format!(
                "Found by running the tree again on the run's own leaf outcomes, each of {} of the {} leaf calls before {} changed in turn.\n",
                f.tried, f.candidates, self.moment
            )),
            _ => {}
        }
        out
    }

    pub fn question(&self, tree: &Tree) -> String {
        format!(
            "Why did {} {} at {}?",
            tree.told(self.uid),
            match self.status {
                Status::Success => "succeed",
                _ => "fail",
            },
            self.moment
        )
    }

    pub fn json(&self, tree: &Tree) -> serde_json::Value {
        let found = self.found.as_ref().ok();
        serde_json::json!({
            "question": self.question(tree),
            "uid": self.uid,
            "status": self.status.as_str(),
            "at": self.moment.to_string(),
            "sentences": self.sentences(tree),
            "causes": found.map(|f| f.causes.iter().map(|c| serde_json::json!({
                "leaf": c.leaf,
                "at": c.at.to_string(),
                "was": c.was.as_str(),
                "instead": c.instead.map(|(s, m)| serde_json::json!({"status": s.as_str(), "at": m.to_string()})),
                "assumed": c.assumed,
                "rerun": true,
            })).collect::<Vec<_>>()),
            "tried": found.map(|f| f.tried),
            "candidates": found.map(|f| f.candidates),
            "not_replayed": self.found.as_ref().err(),
            "leaf_facts": self.leaf_facts,
            "design": self.design,
        })
    }
}

/// A record's position as TICK:STEP.
pub fn step_moment(idx: &crate::session::Index, pos: u32) -> Moment {
    let t = idx.transitions[pos as usize - 1].tick;
    Moment {
        tick: t,
        step: Some(pos - idx.tick_range(t).start as u32),
    }
}

/// How a control node's call ended, as the run shows it: the child it
/// ended after, and what a node of its kind does with that ("a ForceFailure
/// fails whatever its child returns").
fn design(session: &Session, u: Uid, p: u32) -> String {
    use crate::model::Builtin;
    let idx = &session.index;
    let tree = &session.tree;
    let t = idx.transitions[p as usize - 1];
    let me = capitalised(&tree.told(u));
    let start = idx.call_start(u, p).unwrap_or(0);
    let child = (start + 1..p).rev().find_map(|q| {
        let x = idx.transitions[q as usize - 1];
        (tree.parent(x.uid) == Some(u) && x.status.is_completed()).then_some((q, x))
    });
    let kind = match tree.node(u).builtin {
        Some(Builtin::ForceFailure) => " A ForceFailure fails whatever its child returns.",
        Some(Builtin::ForceSuccess) => " A ForceSuccess succeeds whatever its child returns.",
        Some(Builtin::Inverter) => " An Inverter turns its child's outcome around.",
        Some(Builtin::Precondition) => {
            " A Precondition whose `if` is false returns its `else` without ticking its child."
        }
        _ => "",
    };
    let then = past(t.status);
    match child {
        Some((q, x)) => format!(
            "{me} {then} at {} after {} {} at {}.{kind}",
            step_moment(idx, p),
            tree.told(x.uid),
            past(x.status),
            step_moment(idx, q)
        ),
        None => format!(
            "{me} {then} at {} without a child of it ending in that call.{kind}",
            step_moment(idx, p)
        ),
    }
}

/// What a leaf's call read and wrote, where the run holds the blackboard:
/// its inputs as they were when it started, its outputs when it ended
/// (Nav2's `error_code_id`). Empty where the run holds none of them.
fn ports_said(session: &Session, u: Uid, start: u32, end: u32) -> String {
    use crate::model::Direction;
    let tree = &session.tree;
    let n = tree.node(u);
    let bb = crate::run::blackboard::Blackboard::new(tree);
    let (before, after) = (
        session.index.at(start.saturating_sub(1)),
        session.index.at(end),
    );
    let mut read = Vec::new();
    let mut wrote = Vec::new();
    for port in &n.ports {
        let Some(e) = bb.port_entry(tree, n.scope, &port.value) else {
            continue;
        };
        match port.assumed_direction() {
            Direction::Out => {
                if let Some(v) = after.entry(&e) {
                    wrote.push(format!("{} = {v}", e.key));
                }
            }
            _ => {
                if let Some(v) = before.entry(&e) {
                    read.push(format!("{} = {v}", e.key));
                }
            }
        }
    }
    let mut said = Vec::new();
    if !read.is_empty() {
        said.push(format!("read {}", read.join(", ")));
    }
    if !wrote.is_empty() {
        said.push(format!("wrote {}", wrote.join(", ")));
    }
    if said.is_empty() {
        String::new()
    } else {
        format!("It {}.", said.join(" and "))
    }
}

/// "once", "twice", "N times".
pub fn times(n: usize) -> String {
    match n {
        1 => "once".into(),
        2 => "twice".into(),
        n => format!("{n} times"),
    }
}

/// What the run shows of a leaf's completion at position `p`: that it
/// returned the status itself, when it started and how long it ran, how
/// often it had ended so before, what handled a failure and whether that
/// worked (by the record's end), and where its outcome came from.
pub fn leaf_facts(session: &Session, u: Uid, p: u32, upto: u32) -> String {
    let t = session.index.transitions[p as usize - 1];
    let start = session.index.call_start(u, p);
    let mut out = vec![
        returned_itself(session, u, p, start),
        ended_so_before(session, u, p),
    ];
    if t.status == Status::Failure {
        out.push(handled(session, u, p, upto));
    }
    out.push(ports_said(session, u, start.unwrap_or(p), p));
    out.push(match session.header.source.kind.as_str() {
        "domain" => String::new(),
        "plan" => format!(
            "Why it {} is not in the run: the plan scripted it; give a domain file (--domain FILE) to say what it depends on.",
            past(t.status)
        ),
        "world" => format!(
            "Why it {} is not in the run: the world's scenario decided it.",
            past(t.status)
        ),
        _ => format!(
            "Why it {} is not in the run: the robot's log records the outcome, not its reason (the node's own logs or its outputs may say).",
            past(t.status)
        ),
    });
    out.retain(|l| !l.is_empty());
    out.join(" ")
}

/// "X returned FAILURE itself at 10:1, after running from 9:3 (2 ticks):
/// it is an action, so nothing in the tree decided it."
fn returned_itself(session: &Session, u: Uid, p: u32, start: Option<u32>) -> String {
    let idx = &session.index;
    let t = idx.transitions[p as usize - 1];
    let name = capitalised(&session.tree.told(u));
    let m = step_moment(idx, p);
    let what = session.tree.node(u).kind.as_str().to_lowercase();
    let ran = match start {
        Some(q) if idx.transitions[q as usize - 1].status == Status::Running => {
            let ticks = t.tick - idx.transitions[q as usize - 1].tick + 1;
            format!(
                ", after running from {} ({ticks} tick{})",
                step_moment(idx, q),
                if ticks == 1 { "" } else { "s" }
            )
        }
        _ => " in the call that started it".to_string(),
    };
    format!(
        "{name} returned {} itself at {m}{ran}: it is {} {what}, so nothing in the tree decided it.",
        t.status.as_str(),
        if what.starts_with(['a', 'e', 'i', 'o', 'u']) { "an" } else { "a" }
    )
}

/// How often, and when, the leaf had ended so before position `p`.
fn ended_so_before(session: &Session, u: Uid, p: u32) -> String {
    let idx = &session.index;
    let t = idx.transitions[p as usize - 1];
    let before: Vec<String> = idx
        .changes_of(u)
        .iter()
        .copied()
        .filter(|&q| q < p && idx.transitions[q as usize - 1].status == t.status)
        .map(|q| step_moment(idx, q).to_string())
        .collect();
    match before.len() {
        0 => format!("It had not {} before.", past(t.status)),
        n if n > 12 => format!(
            "It had {} {} before, at {}, … and {}.",
            past(t.status),
            times(n),
            before[..10].join(", "),
            before[n - 1]
        ),
        n => format!(
            "It had {} {} before, at {}.",
            past(t.status),
            times(n),
            before.join(", ")
        ),
    }
}

/// What handled the leaf's failure at `p`, by position `upto`: each
/// handler above it in turn, from where the one below ended.
fn handled(session: &Session, u: Uid, p: u32, upto: u32) -> String {
    let idx = &session.index;
    let tree = &session.tree;
    let mut said = Vec::new();
    let mut from = p;
    let by = if upto as usize >= idx.transitions.len() {
        "when the run ends".to_string()
    } else {
        format!("by moment {}", idx.moment(upto))
    };
    for h in tree
        .ancestors(u)
        .filter(|&a| crate::explain::failure::handles_failure(tree, a))
    {
        let done = idx
            .changes_of(h)
            .iter()
            .copied()
            .filter(|&q| q > from && q <= upto)
            .map(|q| (q, idx.transitions[q as usize - 1].status))
            .find(|(_, s)| matches!(s, Status::Success | Status::Failure));
        let hn = tree.told(h);
        let again = tried_again(session, u, p, from, upto, done.map(|d| d.0), &hn);
        if let Some(line) = &again {
            said.push(line.clone());
        }
        match done {
            Some((q, Status::Success)) => {
                said.push(format!(
                    "{hn} {} succeeded at {}",
                    if again.is_some() {
                        "then"
                    } else {
                        "handled it and"
                    },
                    step_moment(idx, q)
                ));
                break;
            }
            Some((q, _)) => {
                said.push(format!("{hn} then failed, at {}", step_moment(idx, q)));
                from = q;
            }
            None => {
                said.push(format!("{hn} handles it, and had not finished {by}"));
                break;
            }
        }
    }
    if said.is_empty() {
        "No fallback, retry or recovery is above it: its failure went up the tree.".into()
    } else {
        format!("{}.", capitalised(&said.join("; ")))
    }
}

/// Whether the handler `hn` tried the leaf again after `from` before it
/// ended (at `done`), and how that went.
fn tried_again(
    session: &Session,
    u: Uid,
    p: u32,
    from: u32,
    upto: u32,
    done: Option<u32>,
    hn: &str,
) -> Option<String> {
    let idx = &session.index;
    let status = idx.transitions[p as usize - 1].status;
    let before_done = |q: u32| q <= upto && done.is_none_or(|d| q < d);
    let a = idx
        .changes_of(u)
        .iter()
        .copied()
        .filter(|&q| q > from && before_done(q))
        .find(|&q| idx.transitions[q as usize - 1].prev == Status::Idle)?;
    let ended = idx
        .changes_of(u)
        .iter()
        .copied()
        .filter(|&q| q >= a && before_done(q))
        .map(|q| (q, idx.transitions[q as usize - 1].status))
        .find(|(_, s)| matches!(s, Status::Success | Status::Failure));
    Some(match ended {
        Some((q, s)) => format!(
            "{hn} tried it again at {}, and it {} at {}",
            step_moment(idx, a),
            if s == status {
                format!("{} again", past(s))
            } else {
                past(s).to_string()
            },
            step_moment(idx, q)
        ),
        None => format!("{hn} tried it again at {}", step_moment(idx, a)),
    })
}
