//! What happened in one tick of a session, as the explanation model needs
//! it. The record is replayed through the executor (`run::replay`), so which
//! nodes were ticked and where composites resumed come from the executor's
//! own semantics, not from a second reading of the log.

use crate::model::{Kind, Tree, Uid};
use crate::run::blackboard::EntryId;
use crate::run::replay::{Call, Replay};
use crate::run::{CallRecord, Executor, Flow, Parked, RunOptions, Status};
use crate::session::Session;
use serde_json::Value;
use std::collections::HashMap;

/// One tick of a run.
#[derive(Debug, Clone)]
pub struct TickFacts {
    pub tick: u32,
    /// Ticked in this tick (E_i), per uid − 1.
    pub ticked: Vec<bool>,
    /// What the node returned when last ticked in this tick (r_i); IDLE if
    /// it was not ticked.
    pub returned: Vec<Status>,
    /// Control-flow state at the start of the tick, per uid − 1.
    pub flows: Vec<Flow>,
    /// Statuses at the start of the tick, per uid − 1.
    pub start: Vec<Status>,
    /// The leaf's decision in this tick, if it took one.
    pub decisions: Vec<Option<String>>,
    /// The status a leaf returns if it is ticked: what it returned in this
    /// tick, else the last status it returned before, else SUCCESS. The
    /// outcome of a leaf without domain knowledge is exogenous.
    pub outcome: Vec<Status>,
    /// Blackboard at the start of the tick, before each leaf's first call
    /// (by uid), and at the end.
    pub state_start: HashMap<EntryId, Value>,
    pub state_before: HashMap<Uid, HashMap<EntryId, Value>>,
    pub state_end: HashMap<EntryId, Value>,
    /// Leaf calls of this tick, in the order they happened (first call of each leaf).
    pub order: Vec<Uid>,
    /// Position (transitions applied) after which each leaf's first call
    /// in this tick had happened.
    pub done_at: HashMap<Uid, u32>,
    /// Calls the replay had to guess in this tick (the record did not
    /// hold them).
    pub guessed: Vec<(u32, Uid)>,
    /// How often each node was ticked in the tick (a child under a Retry
    /// or Repeat may be ticked more than once), per uid − 1.
    pub calls: Vec<u32>,
    /// Every tick of a node in this tick, in the order the calls ended.
    pub call_log: Vec<CallRecord>,
    /// For a leaf ticked more than once in the tick, per call: the
    /// blackboard before it and the position after which it had happened.
    pub per_call: HashMap<(Uid, u32), CallFacts>,
}

/// One call of a leaf ticked more than once in a tick.
#[derive(Debug, Clone, Default)]
pub struct CallFacts {
    pub state_before: HashMap<EntryId, Value>,
    pub done_at: Option<u32>,
}

fn plain_leaf(tree: &Tree, uid: Uid) -> bool {
    let n = tree.node(uid);
    n.kind.is_leaf() && n.builtin.is_none()
}

/// The leaf calls of a session, handed to the replay a tick at a time:
/// holding every call of a long run at once cost about 110 bytes a
/// transition (#31 item 1).
#[derive(Default, Clone)]
struct Feed {
    /// The next transition, write and decision to hand over.
    next: (usize, usize, usize),
    /// Writes of a call whose transition has not come yet.
    pending: HashMap<(u32, Uid), Vec<(EntryId, Value)>>,
}

impl Feed {
    /// Hands `r` every recorded call of the ticks up to `tick`, and drops
    /// what is left of the ticks before it (calls the replay did not take).
    fn fill(&mut self, session: &Session, r: &mut Replay, tick: u32) {
        let tree = &session.tree;
        let idx = &session.index;
        r.forget_before(tick);
        let (mut i, mut w, mut d) = self.next;
        while i <= idx.transitions.len() {
            while let Some(x) = idx
                .writes
                .get(w)
                .filter(|x| x.pos as usize <= i && x.tick <= tick)
            {
                if tree.get(x.uid).is_some() && plain_leaf(tree, x.uid) {
                    self.pending
                        .entry((x.tick, x.uid))
                        .or_default()
                        .push((x.entry.clone(), x.value.clone()));
                }
                w += 1;
            }
            while let Some((_, t, uid, dec)) = idx
                .decision_calls
                .get(d)
                .filter(|x| x.0 as usize <= i && x.1 <= tick)
            {
                let writes = self.pending.remove(&(*t, *uid)).unwrap_or_default();
                r.push(
                    *t,
                    *uid,
                    Call {
                        status: Status::Running,
                        decision: Some(dec.clone()),
                        writes,
                    },
                );
                d += 1;
            }
            let Some(t) = idx.transitions.get(i).filter(|t| t.tick <= tick) else {
                break;
            };
            // A Nav2 action that completes in its tick sets RUNNING itself
            // before it returns: that transition is the executor's, not a call.
            let set_by_itself = t.status == Status::Running
                && crate::model::nav2::at_once(&tree.node(t.uid).id, tree.release) == Some(true);
            if t.status != Status::Idle && plain_leaf(tree, t.uid) && !set_by_itself {
                let writes = self.pending.remove(&(t.tick, t.uid)).unwrap_or_default();
                r.push(
                    t.tick,
                    t.uid,
                    Call {
                        status: t.status,
                        decision: idx.transition_decision(i).map(str::to_string),
                        writes,
                    },
                );
            }
            i += 1;
        }
        self.next = (i, w, d);
    }
}

/// The replay of a session kept at some of its ticks, so that the facts
/// of a tick late in a long run are replayed from the nearest one before
/// it, not from the first tick (the explorer at the end of 5·10^6
/// transitions took 0.6 s a question). Each is the replay at the start of
/// a tick: the executor parked after the ticks before it, and the feed.
#[derive(Default)]
struct Marks(Vec<(Parked<Replay>, Feed)>);

/// Ticks between two marks at least, and the marks kept at most, with the
/// bytes they may hold (a mark holds each node's control state).
const MARK_EVERY_MIN: u32 = 64;
const MARKS_MAX: usize = 1024;
const MARKS_BYTES: usize = 64 << 20;

impl Marks {
    /// The latest mark at or before the start of `tick`, resumed.
    fn nearest<'t>(&mut self, tree: &'t Tree, tick: u32) -> Option<(Executor<'t, Replay>, Feed)> {
        let i = self.0.partition_point(|(p, _)| p.ticks() < tick);
        let (parked, feed) = self.0[..i].last()?;
        match parked.resume(tree) {
            Some(ex) => Some((ex, feed.clone())),
            None => {
                // Made with other nodes (a subgoal inserted since).
                self.0.clear();
                None
            }
        }
    }

    fn add(&mut self, parked: Parked<Replay>, feed: Feed, most: usize) {
        let i = self.0.partition_point(|(p, _)| p.ticks() < parked.ticks());
        if self
            .0
            .get(i)
            .is_some_and(|(p, _)| p.ticks() == parked.ticks())
        {
            return;
        }
        self.0.insert(i, (parked, feed));
        if self.0.len() > most {
            // Every other one goes: they stay spread over the run.
            let mut k = 0;
            self.0.retain(|_| {
                k += 1;
                k % 2 == 0
            });
        }
    }
}

/// The marks a session keeps at most, and the ticks between two.
fn spacing(session: &Session) -> (usize, u32) {
    let n = session.tree.len();
    let most = MARKS_MAX.min(MARKS_BYTES / (n * 320).max(1)).max(2);
    // Rounded up, so that marks every `every` ticks are at most `most`
    // and none is thinned out as soon as it is laid.
    let every = session
        .index
        .ticks()
        .div_ceil(most as u32)
        .max(MARK_EVERY_MIN);
    (most, every)
}

/// The replay at the start of `tick`, from the nearest mark before it,
/// laying marks on the way.
fn replay_to(session: &Session, tick: u32) -> Result<(Executor<'_, Replay>, Feed), String> {
    let tree = &session.tree;
    let idx = &session.index;
    let marks = &idx.scratch;
    let (most, every) = spacing(session);
    let (mut ex, mut feed) = marks
        .with(|m: &mut Marks| m.nearest(tree, tick))
        .unwrap_or_else(|| {
            let mut replay = Replay::new(session.header.blackboard.clone());
            replay.writes_recorded = !idx.writes.is_empty();
            let ex = Executor::new(
                tree,
                replay,
                RunOptions {
                    tick_ms: session.header.tick_ms.max(1),
                    nav2: session.header.nav2.unwrap_or_default(),
                },
            );
            (ex, Feed::default())
        });
    for t in ex.ticks() + 1..tick {
        if t % every == 0 {
            let (parked, kept) = (ex.clone().park(), feed.clone());
            marks.with(|m: &mut Marks| m.add(parked, kept, most));
        }
        feed.fill(session, &mut ex.leaves, t);
        ex.tick_once()
            .map_err(|e| format!("replaying tick {t}: {e}"))?;
        ex.take_events();
        // Only the asked tick's guesses are facts; kept, the list would
        // grow with the run and be copied into every mark.
        ex.leaves.guessed.clear();
    }
    Ok((ex, feed))
}

/// Lays the marks of a session ahead of any question, a stretch at a time,
/// for about `budget`: whether there are more to lay. The explorer calls it
/// while nobody presses a key, so that the first question late in a long
/// run does not replay it all.
pub fn lay_marks(session: &Session, budget: std::time::Duration) -> bool {
    let began = std::time::Instant::now();
    let (_, every) = spacing(session);
    let last = session.index.ticks();
    loop {
        let laid = session
            .index
            .scratch
            .with(|m: &mut Marks| m.0.last().map_or(0, |(p, _)| p.ticks()));
        // The next mark: the start of the next multiple of `every`.
        let next = (laid + 1) / every * every + every;
        if next >= last {
            return false;
        }
        if replay_to(session, next + 1).is_err() {
            return false;
        }
        if began.elapsed() >= budget {
            return true;
        }
    }
}

impl TickFacts {
    /// The facts of `tick` (from 1) of a session.
    pub fn of(session: &Session, tick: u32) -> Result<TickFacts, String> {
        let tree = &session.tree;
        let idx = &session.index;
        if tick == 0 || tick > idx.ticks() {
            return Err(format!(
                "tick {tick} is outside the run: it has ticks 1 to {}",
                idx.ticks()
            ));
        }
        let n = tree.len();
        let (mut ex, mut feed) = replay_to(session, tick)?;
        let uids = 1..=n as Uid;
        let mut flows: Vec<Flow> = uids.clone().map(|u| ex.flow(u)).collect();
        let mut start: Vec<Status> = uids.clone().map(|u| ex.status(u)).collect();
        ex.record_calls = true;
        feed.fill(session, &mut ex.leaves, tick);
        ex.tick_once()
            .map_err(|e| format!("replaying tick {tick}: {e}"))?;
        let call_log = ex.call_log().to_vec();
        // A node ticked more than once in the tick (under a Retry or a
        // Repeat) is taken at its last tick, and its descendants at the
        // ticks that belong to it: those that began after it began.
        let mut ticked = vec![false; n];
        let mut returned = vec![Status::Idle; n];
        for u in tree.preorder() {
            let i = u as usize - 1;
            let (t, s) = ex.last_ticked(u);
            let (seq, flow, entry_status) = ex.last_entry(u);
            let in_parent = tree
                .node(u)
                .parent
                .is_none_or(|p| ticked[p as usize - 1] && ex.last_entry(p).0 < seq);
            if t == tick && in_parent {
                ticked[i] = true;
                returned[i] = s;
                flows[i] = flow.clone();
                start[i] = entry_status;
            }
        }
        let guessed = ex.leaves.guessed.clone();
        let calls: Vec<u32> = (1..=n as Uid).map(|u| ex.calls(u)).collect();

        // Decisions and outcomes from the record.
        let range = idx.tick_range(tick);
        let mut decisions = vec![None; n];
        let mut outcome = vec![Status::Success; n];
        for (i, t) in idx.transitions[..range.end].iter().enumerate() {
            if t.status == Status::Idle || !tree.node(t.uid).kind.is_leaf() {
                continue;
            }
            outcome[t.uid as usize - 1] = t.status;
            if range.contains(&i) {
                if let Some(dd) = idx.transition_decision(i) {
                    decisions[t.uid as usize - 1] = Some(dd.to_string());
                }
            }
        }
        for &(_, t, uid, ref dd) in &idx.decision_calls {
            if t == tick && tree.get(uid).is_some() {
                decisions[uid as usize - 1] = Some(dd.clone());
            }
        }
        for u in uids {
            if ticked[u as usize - 1] && tree.node(u).kind.is_leaf() {
                outcome[u as usize - 1] = returned[u as usize - 1];
            }
        }

        // The blackboard through the tick, from the writes.
        let mut state: HashMap<EntryId, Value> =
            session.header.blackboard.iter().cloned().collect();
        let mut w = 0;
        let writes = &idx.writes;
        while let Some(x) = writes.get(w).filter(|x| x.tick < tick) {
            state.insert(x.entry.clone(), x.value.clone());
            w += 1;
        }
        let state_start = state.clone();
        let mut state_before = HashMap::new();
        let mut order = Vec::new();
        let mut done_at = HashMap::new();
        let mut first_call = |uid: Uid, state: &HashMap<EntryId, Value>| {
            if tree.node(uid).kind.is_leaf() && !state_before.contains_key(&uid) {
                state_before.insert(uid, state.clone());
                order.push(uid);
            }
        };
        for i in range.clone() {
            while let Some(x) = writes
                .get(w)
                .filter(|x| x.tick == tick && x.pos as usize <= i)
            {
                first_call(x.uid, &state);
                state.insert(x.entry.clone(), x.value.clone());
                w += 1;
            }
            let t = &idx.transitions[i];
            if t.status != Status::Idle {
                first_call(t.uid, &state);
                if tree.node(t.uid).kind.is_leaf() {
                    done_at.entry(t.uid).or_insert(i as u32 + 1);
                }
            }
        }
        while let Some(x) = writes.get(w).filter(|x| x.tick == tick) {
            first_call(x.uid, &state);
            state.insert(x.entry.clone(), x.value.clone());
            w += 1;
        }
        // An action ticked again while RUNNING leaves no record of its
        // call; the state it read is taken as the tick's start (exact
        // unless a leaf before it in the tick wrote one of its inputs).
        for (u, &t) in ticked.iter().enumerate() {
            let uid = u as Uid + 1;
            if t && tree.node(uid).kind == Kind::Action && !state_before.contains_key(&uid) {
                state_before.insert(uid, state_start.clone());
            }
        }
        let per_call = per_call_facts(
            tree,
            &call_log,
            &state_start,
            &writes_of_tick(session, tick),
            range.start as u32,
        );
        Ok(TickFacts {
            tick,
            ticked,
            returned,
            flows,
            start,
            decisions,
            outcome,
            state_start,
            state_before,
            state_end: state,
            order,
            done_at,
            guessed,
            calls,
            call_log,
            per_call,
        })
    }
}

/// The writes of one tick, as (position, uid, entry, value).
fn writes_of_tick(session: &Session, tick: u32) -> Vec<(u32, Uid, EntryId, Value)> {
    session
        .index
        .writes
        .iter()
        .filter(|x| x.tick == tick)
        .map(|x| (x.pos, x.uid, x.entry.clone(), x.value.clone()))
        .collect()
}

/// The blackboard before each call, and where each call had happened, of
/// the leaves ticked more than once in the tick (under a Retry or Repeat).
fn per_call_facts(
    tree: &Tree,
    log: &[CallRecord],
    state_start: &HashMap<EntryId, Value>,
    writes: &[(u32, Uid, EntryId, Value)],
    tick_start: u32,
) -> HashMap<(Uid, u32), CallFacts> {
    let mut out = HashMap::new();
    let mut calls: HashMap<Uid, u32> = HashMap::new();
    for r in log {
        let c = calls.entry(r.uid).or_insert(0);
        *c = (*c).max(r.call);
    }
    for r in log {
        if !tree.node(r.uid).kind.is_leaf() || calls.get(&r.uid).is_none_or(|&c| c < 2) {
            continue;
        }
        // Writes before the call's first transition, and those at its
        // place made before the leaf's own.
        let at = tick_start + r.transitions_before;
        let mut state = state_start.clone();
        for (pos, uid, e, v) in writes {
            if *pos > at || (*pos == at && *uid == r.uid) {
                break;
            }
            state.insert(e.clone(), v.clone());
        }
        out.insert(
            (r.uid, r.call),
            CallFacts {
                state_before: state,
                done_at: r.transitioned.then_some(tick_start + r.transitions_after),
            },
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::TickFacts;

    /// The recorded kitting run, `times` over, as one `.btlog`.
    fn long_log(times: usize) -> Vec<u8> {
        let bytes = std::fs::read(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/fixtures/logs/kitting_lookat_fails_once.btlog"
        ))
        .unwrap();
        let n = i32::from_le_bytes(bytes[19..23].try_into().unwrap()) as usize;
        let (head, body) = bytes.split_at(31 + n);
        let span = u64::from_le_bytes(
            [&body[body.len() - 9..body.len() - 3], &[0, 0][..]]
                .concat()
                .try_into()
                .unwrap(),
        ) + 100_000;
        let mut out = head.to_vec();
        for k in 0..times as u64 {
            for r in body.chunks_exact(9) {
                let dt = u64::from_le_bytes([&r[..6], &[0, 0][..]].concat().try_into().unwrap());
                out.extend_from_slice(&(dt + k * span).to_le_bytes()[..6]);
                out.extend_from_slice(&r[6..]);
            }
        }
        out
    }

    /// The facts as text, their maps in order.
    fn canonical(f: &TickFacts) -> String {
        let sorted = |m: &std::collections::HashMap<_, _>| -> String {
            let mut v: Vec<String> = m
                .iter()
                .map(
                    |(k, x): (&crate::run::blackboard::EntryId, &serde_json::Value)| {
                        format!("{k:?}={x}")
                    },
                )
                .collect();
            v.sort();
            v.join(",")
        };
        let mut before: Vec<String> = f
            .state_before
            .iter()
            .map(|(u, m)| format!("{u}:{}", sorted(m)))
            .collect();
        before.sort();
        let mut done: Vec<(u32, u32)> = f.done_at.iter().map(|(&u, &p)| (u, p)).collect();
        done.sort();
        let mut per_call: Vec<String> = f
            .per_call
            .iter()
            .map(|(k, c)| format!("{k:?}:{}:{:?}", sorted(&c.state_before), c.done_at))
            .collect();
        per_call.sort();
        format!(
            "{} {:?} {:?} {:?} {:?} {:?} {:?} {} {before:?} {} {:?} {done:?} {:?} {:?} {:?} {per_call:?}",
            f.tick,
            f.ticked,
            f.returned,
            f.flows,
            f.start,
            f.decisions,
            f.outcome,
            sorted(&f.state_start),
            sorted(&f.state_end),
            f.order,
            f.guessed,
            f.calls,
            f.call_log,
        )
    }

    #[test]
    fn a_tick_replayed_from_a_kept_mark_has_the_facts_of_a_whole_replay() {
        let bytes = long_log(40);
        let path = std::path::Path::new("long.btlog");
        let marked = crate::logs::open_btlog(path, &bytes).unwrap();
        let ticks = marked.index.ticks();
        assert!(ticks > 2000, "{ticks}");
        // Late first (marks are laid on the way), then around and between
        // them, each against a replay from the first tick.
        for tick in [ticks, 1, 63, 64, 65, 129, 1000, ticks / 2, ticks - 1, 700] {
            let fresh = crate::logs::open_btlog(path, &bytes).unwrap();
            let a = TickFacts::of(&marked, tick).unwrap();
            let b = TickFacts::of(&fresh, tick).unwrap();
            assert_eq!(canonical(&a), canonical(&b), "tick {tick}");
        }
        let kept = marked.index.scratch.with(|m: &mut super::Marks| m.0.len());
        assert!(kept > 10, "{kept} marks");
    }

    #[test]
    fn marks_laid_ahead_of_a_question_answer_it_as_a_whole_replay_does() {
        let bytes = long_log(40);
        let path = std::path::Path::new("long.btlog");
        let ahead = crate::logs::open_btlog(path, &bytes).unwrap();
        let mut slices = 0;
        while super::lay_marks(&ahead, std::time::Duration::ZERO) {
            slices += 1;
            assert!(slices < 10_000, "marks laid for ever");
        }
        let (most, every) = super::spacing(&ahead);
        let kept = ahead.index.scratch.with(|m: &mut super::Marks| m.0.len());
        assert!(kept > 10 && kept <= most, "{kept} marks");
        let ticks = ahead.index.ticks();
        let last_mark = ahead
            .index
            .scratch
            .with(|m: &mut super::Marks| m.0.last().map(|(p, _)| p.ticks()));
        assert!(
            last_mark.is_some_and(|t| t + 1 + every >= ticks),
            "{last_mark:?} of {ticks}"
        );
        let fresh = crate::logs::open_btlog(path, &bytes).unwrap();
        for tick in [ticks, ticks - 70, 500] {
            let a = TickFacts::of(&ahead, tick).unwrap();
            let b = TickFacts::of(&fresh, tick).unwrap();
            assert_eq!(canonical(&a), canonical(&b), "tick {tick}");
        }
    }
}
