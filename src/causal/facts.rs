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
/// Beside them, the states the replay was in at the starts of the log's
/// runs (`Runs`), so that a run like one replayed before is not replayed
/// again.
#[derive(Default)]
struct Marks {
    laid: Vec<(Parked<Replay>, Feed)>,
    runs: Option<Runs>,
    /// The replay's distinct states at the start of a run (timeless: the
    /// same at any tick, `Executor::same_course`).
    states: Vec<Parked<Replay>>,
    /// Per run, its state's index in `states`, where known.
    at_start: Vec<Option<u32>>,
    /// A run of a kind begun in a state ends in this state.
    next: HashMap<(u32, u32), u32>,
    /// The ticks `lay_marks` has replayed to.
    covered: u32,
}

/// Ticks between two marks at least, and the marks kept at most, with the
/// bytes they may hold (a mark holds each node's control state).
const MARK_EVERY_MIN: u32 = 64;
const MARKS_MAX: usize = 1024;
const MARKS_BYTES: usize = 64 << 20;
/// Distinct run-start states kept at most: past them, a run whose state
/// is new is replayed as it comes (a run that leaves state behind, a
/// counter in the blackboard, makes each state new).
const STATES_MAX: usize = 16;

impl Marks {
    /// The latest mark at or before the start of `tick`, resumed.
    fn nearest<'t>(&mut self, tree: &'t Tree, tick: u32) -> Option<(Executor<'t, Replay>, Feed)> {
        let i = self.laid.partition_point(|(p, _)| p.ticks() < tick);
        let (parked, feed) = self.laid[..i].last()?;
        match parked.resume(tree) {
            Some(ex) => Some((ex, feed.clone())),
            None => {
                // Made with other nodes (a subgoal inserted since).
                *self = Marks::default();
                None
            }
        }
    }

    fn add(&mut self, parked: Parked<Replay>, feed: Feed, most: usize) {
        let marks = &mut self.laid;
        let i = marks.partition_point(|(p, _)| p.ticks() < parked.ticks());
        if marks
            .get(i)
            .is_some_and(|(p, _)| p.ticks() == parked.ticks())
        {
            return;
        }
        marks.insert(i, (parked, feed));
        if marks.len() > most {
            // Every other one goes: they stay spread over the run.
            let mut k = 0;
            marks.retain(|_| {
                k += 1;
                k % 2 == 0
            });
        }
    }

    /// Cuts the session's runs, once, with room for each one's state.
    fn cut_runs(&mut self, session: &Session) {
        let runs = self.runs.get_or_insert_with(|| Runs::of(session));
        if self.at_start.len() != runs.starts.len() {
            self.at_start = vec![None; runs.starts.len()];
        }
    }

    /// The latest run starting at or before `tick` whose state is known,
    /// going on from known states through runs like ones replayed before:
    /// the run's first tick and its state, resumed there. From run `from`
    /// (known) when given, and then only if it goes past it.
    fn run_start<'t>(
        &mut self,
        session: &'t Session,
        tick: u32,
        from: Option<usize>,
    ) -> Option<(u32, Executor<'t, Replay>)> {
        self.cut_runs(session);
        let runs = self.runs.as_ref().expect("cut above");
        let k = runs.starts.partition_point(|&s| s <= tick).checked_sub(1)?;
        let first = match from {
            Some(j) => j,
            None => (0..=k).rev().find(|&j| self.at_start[j].is_some())?,
        };
        let mut j = first;
        while j < k {
            let state = self.at_start[j]?;
            let Some(&after) = self.next.get(&(runs.kinds[j], state)) else {
                break;
            };
            self.at_start[j + 1] = Some(after);
            j += 1;
        }
        if from.is_some() && j == first {
            return None;
        }
        let state = self.at_start[j]?;
        let Some(mut ex) = self.states[state as usize].resume(&session.tree) else {
            *self = Marks::default();
            return None;
        };
        ex.rebase(runs.starts[j] - 1);
        ex.leaves.forget_before(u32::MAX);
        Some((runs.starts[j], ex))
    }

    /// The replay is at the start of tick `tick`: where that starts a
    /// run, its state is told apart from those kept, and the run before it
    /// (of a kind begun in a known state) learns where it ends. The run,
    /// where its state is known.
    fn passing(
        &mut self,
        session: &Session,
        tick: u32,
        ex: &Executor<'_, Replay>,
    ) -> Option<usize> {
        self.cut_runs(session);
        let runs = self.runs.as_ref().expect("cut above");
        let k = runs.starts.binary_search(&tick).ok()?;
        let same = |p: &Parked<Replay>| {
            p.peek().same_course(ex) && p.peek().leaves.same_memory(&ex.leaves)
        };
        let state = match self.states.iter().position(same) {
            Some(i) => i as u32,
            None if self.states.len() < STATES_MAX && ex.timeless() => {
                self.states.push(ex.clone().park());
                (self.states.len() - 1) as u32
            }
            None => return None,
        };
        self.at_start[k] = Some(state);
        if let Some(before) = k.checked_sub(1).and_then(|b| self.at_start[b]) {
            self.next.insert((runs.kinds[k - 1], before), state);
        }
        Some(k)
    }
}

/// A session's ticks cut into runs where the replay's state may start
/// again: after a tick that ended with the root back to IDLE (the tree
/// reset, as BehaviorTree.CPP does when its root completes). Runs of one
/// kind have the same transitions at the same ticks from their start and
/// as many ticks, so that a replay begun in one state ends each in one
/// state: the leaves' calls come from a tick's transitions alone. A
/// record that holds more of the calls (writes, decisions) is one run.
struct Runs {
    /// Each run's first tick, the first's 1.
    starts: Vec<u32>,
    kinds: Vec<u32>,
}

impl Runs {
    fn of(session: &Session) -> Runs {
        let idx = &session.index;
        let all = &idx.transitions;
        let mut starts = vec![1];
        let mut from = vec![0usize];
        if !idx.records_calls() {
            for &p in idx.changes_of(Tree::ROOT) {
                let p = p as usize;
                let ends_tick = all.get(p).is_some_and(|next| next.tick > all[p - 1].tick);
                if all[p - 1].status == Status::Idle && ends_tick {
                    starts.push(all[p].tick);
                    from.push(p);
                }
            }
        }
        let mut ends: Vec<(usize, u32)> = from.iter().skip(1).map(|&p| (p, all[p].tick)).collect();
        ends.push((all.len(), idx.ticks() + 1));
        let span = |k: usize| (from[k]..ends[k].0, starts[k], ends[k].1 - starts[k]);
        let key = |t: &crate::session::Transition, start: u32| (t.uid, t.status, t.tick - start);
        let mut seen: HashMap<(usize, u32, u64), Vec<u32>> = HashMap::new();
        let mut firsts: Vec<usize> = Vec::new();
        let mut kinds = Vec::with_capacity(starts.len());
        for k in 0..starts.len() {
            let (range, start, ticks) = span(k);
            let hash = all[range.clone()]
                .iter()
                .fold(0xcbf2_9ce4_8422_2325_u64, |h, t| {
                    let (u, s, dt) = key(t, start);
                    let word = u64::from(u) << 35 ^ u64::from(s.code()) << 32 ^ u64::from(dt);
                    (h ^ word).wrapping_mul(0x0100_0000_01b3)
                });
            let alike = seen.entry((range.len(), ticks, hash)).or_default();
            let same = |&&kind: &&u32| {
                let (r, s, _) = span(firsts[kind as usize]);
                all[r]
                    .iter()
                    .map(|t| key(t, s))
                    .eq(all[range.clone()].iter().map(|t| key(t, start)))
            };
            let kind = match alike.iter().find(same) {
                Some(&kind) => kind,
                None => {
                    firsts.push(k);
                    let kind = (firsts.len() - 1) as u32;
                    alike.push(kind);
                    kind
                }
            };
            kinds.push(kind);
        }
        Runs { starts, kinds }
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

/// The feed at the start of `tick`, of a record that holds no more of
/// the calls than the transitions (`Runs`).
fn feed_at(session: &Session, tick: u32) -> Feed {
    Feed {
        next: (session.index.tick_range(tick).start, 0, 0),
        pending: HashMap::new(),
    }
}

/// How a replay may start: from what answers kept of the run, or from its
/// first tick (to check what is kept against).
#[derive(Clone, Copy, PartialEq)]
enum From {
    Kept,
    #[cfg(test)]
    First,
}

/// The replay at the start of `tick`, from the nearest mark or run start
/// before it, laying marks on the way.
fn replay_to(
    session: &Session,
    tick: u32,
    from: From,
) -> Result<(Executor<'_, Replay>, Feed), String> {
    let tree = &session.tree;
    let idx = &session.index;
    let marks = &idx.scratch;
    let (most, every) = spacing(session);
    let kept = from == From::Kept;
    let laid = kept
        .then(|| marks.with(|m: &mut Marks| m.nearest(tree, tick)))
        .flatten();
    let run = kept
        .then(|| marks.with(|m: &mut Marks| m.run_start(session, tick, None)))
        .flatten();
    let (mut ex, mut feed) = match (laid, run) {
        (Some((ex, feed)), run) if run.as_ref().is_none_or(|(s, _)| ex.ticks() + 1 >= *s) => {
            (ex, feed)
        }
        (_, Some((start, ex))) => (ex, feed_at(session, start)),
        _ => {
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
        }
    };
    let mut t = ex.ticks() + 1;
    loop {
        // At a run's start in a known state, runs like ones replayed
        // before are gone over without a replay.
        let known = kept
            .then(|| marks.with(|m: &mut Marks| m.passing(session, t, &ex)))
            .flatten();
        if let Some((start, ahead)) =
            known.and_then(|k| marks.with(|m: &mut Marks| m.run_start(session, tick, Some(k))))
        {
            (ex, feed, t) = (ahead, feed_at(session, start), start);
            continue;
        }
        if t >= tick {
            break;
        }
        if kept && t % every == 0 {
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
        t += 1;
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
        let covered = session.index.scratch.with(|m: &mut Marks| m.covered);
        // The next mark: the start of the next multiple of `every` (where
        // runs repeat, the replay goes over them without laying one).
        let next = (covered + 1) / every * every + every;
        if next >= last {
            return false;
        }
        if replay_to(session, next + 1, From::Kept).is_err() {
            return false;
        }
        session.index.scratch.with(|m: &mut Marks| m.covered = next);
        if began.elapsed() >= budget {
            return true;
        }
    }
}

impl TickFacts {
    /// The facts of `tick` (from 1) of a session.
    pub fn of(session: &Session, tick: u32) -> Result<TickFacts, String> {
        Self::replayed(session, tick, From::Kept)
    }

    fn replayed(session: &Session, tick: u32, from: From) -> Result<TickFacts, String> {
        let idx = &session.index;
        if tick == 0 || tick > idx.ticks() {
            return Err(format!(
                "tick {tick} is outside the run: it has ticks 1 to {}",
                idx.ticks()
            ));
        }
        let r = replay_tick(session, tick, from)?;
        let (decisions, outcome) = recorded(session, tick, &r.ticked, &r.returned);
        let bb = blackboard_through(session, tick, &r.ticked);
        let per_call = per_call_facts(
            &session.tree,
            &r.call_log,
            &bb.start,
            &writes_of_tick(session, tick),
            idx.tick_range(tick).start as u32,
        );
        Ok(TickFacts {
            tick,
            ticked: r.ticked,
            returned: r.returned,
            flows: r.flows,
            start: r.start,
            decisions,
            outcome,
            state_start: bb.start,
            state_before: bb.before,
            state_end: bb.end,
            order: bb.order,
            done_at: bb.done_at,
            guessed: r.guessed,
            calls: r.calls,
            call_log: r.call_log,
            per_call,
        })
    }
}

/// What the executor did in one tick, replayed.
struct Replayed {
    ticked: Vec<bool>,
    returned: Vec<Status>,
    flows: Vec<Flow>,
    start: Vec<Status>,
    guessed: Vec<(u32, Uid)>,
    calls: Vec<u32>,
    call_log: Vec<CallRecord>,
}

/// Replays tick `tick`: which nodes were ticked in it, what they
/// returned, and the control state and status each began it with.
fn replay_tick(session: &Session, tick: u32, from: From) -> Result<Replayed, String> {
    let tree = &session.tree;
    let n = tree.len();
    let (mut ex, mut feed) = replay_to(session, tick, from)?;
    let uids = 1..=n as Uid;
    let mut flows: Vec<Flow> = uids.clone().map(|u| ex.flow(u)).collect();
    let mut start: Vec<Status> = uids.clone().map(|u| ex.status(u)).collect();
    ex.record_calls = true;
    feed.fill(session, &mut ex.leaves, tick);
    ex.tick_once()
        .map_err(|e| format!("replaying tick {tick}: {e}"))?;
    // Counted from the tick's start: the counter's value before it
    // depends on where the replay began (a run gone over, `Marks`).
    let mut call_log = ex.call_log().to_vec();
    let base = call_log.iter().map(|c| c.entry_seq).min().unwrap_or(1) - 1;
    for c in &mut call_log {
        c.entry_seq -= base;
        c.exit_seq -= base;
    }
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
    Ok(Replayed {
        guessed: ex.leaves.guessed.clone(),
        calls: uids.map(|u| ex.calls(u)).collect(),
        ticked,
        returned,
        flows,
        start,
        call_log,
    })
}

/// The leaves' decisions in tick `tick`, and the status each returns if
/// ticked (`TickFacts::outcome`), from the record and the replay.
fn recorded(
    session: &Session,
    tick: u32,
    ticked: &[bool],
    returned: &[Status],
) -> (Vec<Option<String>>, Vec<Status>) {
    let (tree, idx) = (&session.tree, &session.index);
    let n = tree.len();
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
    for u in 1..=n as Uid {
        if ticked[u as usize - 1] && tree.node(u).kind.is_leaf() {
            outcome[u as usize - 1] = returned[u as usize - 1];
        }
    }
    (decisions, outcome)
}

/// The blackboard through a tick, from the writes: at its start, before
/// each leaf's first call, and at its end; the leaves' first calls in
/// order, and where each had happened.
struct TickBlackboard {
    start: HashMap<EntryId, Value>,
    before: HashMap<Uid, HashMap<EntryId, Value>>,
    end: HashMap<EntryId, Value>,
    order: Vec<Uid>,
    done_at: HashMap<Uid, u32>,
}

fn blackboard_through(session: &Session, tick: u32, ticked: &[bool]) -> TickBlackboard {
    let (tree, idx) = (&session.tree, &session.index);
    let range = idx.tick_range(tick);
    let mut state: HashMap<EntryId, Value> = session.header.blackboard.iter().cloned().collect();
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
    for i in range {
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
    TickBlackboard {
        start: state_start,
        before: state_before,
        end: state,
        order,
        done_at,
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
    use super::{From, TickFacts};
    use crate::logs::btlog::repeated;

    /// The recorded kitting run, `times` over, as one `.btlog`.
    fn long_log(times: usize) -> Vec<u8> {
        let bytes = std::fs::read(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/fixtures/logs/kitting_lookat_fails_once.btlog"
        ))
        .unwrap();
        repeated(&bytes, times)
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
        // As one run, so that marks are laid, not runs gone over.
        marked.index.scratch.with(|m: &mut super::Marks| {
            m.runs = Some(super::Runs {
                starts: vec![1],
                kinds: vec![0],
            })
        });
        // Late first (marks are laid on the way), then around and between
        // them, each against a replay from the first tick.
        for tick in [ticks, 1, 63, 64, 65, 129, 1000, ticks / 2, ticks - 1, 700] {
            let a = TickFacts::of(&marked, tick).unwrap();
            let b = TickFacts::replayed(&marked, tick, From::First).unwrap();
            assert_eq!(canonical(&a), canonical(&b), "tick {tick}");
        }
        let kept = marked
            .index
            .scratch
            .with(|m: &mut super::Marks| m.laid.len());
        assert!(kept > 10, "{kept} marks");
    }

    #[test]
    fn a_late_tick_of_runs_alike_is_replayed_from_its_runs_start() {
        let bytes = long_log(40);
        let s = crate::logs::open_btlog(std::path::Path::new("long.btlog"), &bytes).unwrap();
        let ticks = s.index.ticks();
        TickFacts::of(&s, ticks).unwrap();
        let (runs, known, states, laid) = s.index.scratch.with(|m: &mut super::Marks| {
            let runs = m.runs.as_ref().map_or(0, |r| r.starts.len());
            let known = m.at_start.iter().filter(|k| k.is_some()).count();
            (runs, known, m.states.len(), m.laid.len())
        });
        // Forty runs, each the nominal run: the first from the fresh tree,
        // the second from the first's end, and from there one state.
        assert_eq!(runs, 40);
        assert_eq!(known, 40);
        assert!(states <= 2, "{states} states");
        // Laid over the first two runs only: the rest were gone over.
        let (_, every) = super::spacing(&s);
        let two_runs = 2 * ticks / 40;
        assert!(laid as u32 <= two_runs / every + 1, "{laid} marks laid");
    }

    /// Every recorded log of the fixtures, each tick asked out of order (a
    /// late one first), against its replay from the first tick.
    #[test]
    fn every_tick_from_what_is_kept_has_the_facts_of_a_replay_from_the_first() {
        let logs = crate::logs::btlog::fixture_logs();
        for (path, times) in logs.iter().flat_map(|p| [(p, 1), (p, 3)]) {
            let bytes = repeated(&std::fs::read(path).unwrap(), times);
            let s = crate::logs::open_btlog(path, &bytes).unwrap();
            let ticks = s.index.ticks();
            let step = (1..ticks)
                .rev()
                .find(|k| gcd(*k, ticks) == 1 && *k < ticks / 2 + 2);
            let order = (0..ticks).map(|k| 1 + (ticks - 1 + k * step.unwrap_or(1)) % ticks);
            for tick in order {
                let a = TickFacts::of(&s, tick).unwrap();
                let b = TickFacts::replayed(&s, tick, From::First).unwrap();
                assert_eq!(
                    canonical(&a),
                    canonical(&b),
                    "{} tick {tick}",
                    path.display()
                );
            }
        }
    }

    fn gcd(a: u32, b: u32) -> u32 {
        if b == 0 {
            a
        } else {
            gcd(b, a % b)
        }
    }

    #[test]
    fn runs_alike_in_their_records_but_not_in_the_blackboard_are_not_taken_for_each_other() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/fixtures/logs/counted_runs.btlog");
        let s = crate::logs::open_btlog(&path, &std::fs::read(&path).unwrap()).unwrap();
        let ticks = s.index.ticks();
        TickFacts::of(&s, ticks).unwrap();
        let (kinds, states, next) = s.index.scratch.with(|m: &mut super::Marks| {
            let kinds = m.runs.as_ref().map(|r| r.kinds.clone()).unwrap_or_default();
            (kinds, m.states.len(), m.next.len())
        });
        // The first run counts from zero, the second is early, the other
        // four are alike; each begins with another count.
        assert_eq!(kinds, vec![0, 1, 2, 2, 2, 2]);
        assert_eq!(states, 6);
        assert_eq!(next, 5);
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
        let (_, every) = super::spacing(&ahead);
        let ticks = ahead.index.ticks();
        let covered = ahead.index.scratch.with(|m: &mut super::Marks| m.covered);
        assert!(covered + 1 + every >= ticks, "{covered} of {ticks}");
        for tick in [ticks, ticks - 70, 500] {
            let a = TickFacts::of(&ahead, tick).unwrap();
            let b = TickFacts::replayed(&ahead, tick, From::First).unwrap();
            assert_eq!(canonical(&a), canonical(&b), "tick {tick}");
        }
    }
}
