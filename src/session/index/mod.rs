//! The episodic memory indexed by moment: for any moment, every node's
//! status and last completed status, retry attempts, the current node, the
//! blackboard, each found by binary search, so stepping backwards costs what
//! stepping forwards does.

use crate::model::{Builtin, Tree, Uid};
use crate::run::blackboard::EntryId;
use crate::run::Status;
use serde_json::Value;
use std::collections::HashMap;
use std::fmt;

/// Ticks in which nothing changed that a session holds at most (beyond one
/// per record): each tick costs the index a few bytes, and a corrupt log
/// or session can claim billions.
#[cfg(not(fuzzing))]
pub const EMPTY_TICKS_MAX: u32 = 10_000_000;
// Under the fuzzer a smaller budget keeps inputs that claim many empty
// ticks fast enough to explore; the rule is the same.
#[cfg(fuzzing)]
pub const EMPTY_TICKS_MAX: u32 = 10_000;

/// A status transition of a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Transition {
    pub tick: u32,
    pub uid: Uid,
    pub prev: Status,
    pub status: Status,
}

/// `TICK` (the end of that tick) or `TICK:STEP` (after the STEP-th status
/// transition of that tick; `TICK:0` is its start). Ticks and steps count from 1.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Moment {
    pub tick: u32,
    pub step: Option<u32>,
}

impl Moment {
    pub fn parse(s: &str) -> Result<Moment, String> {
        let bad = || {
            format!("\"{s}\" is not a moment: write TICK or TICK:STEP, e.g. 10 or 10:3 (of a run: also last, end or -N, the N-th tick from the end)")
        };
        let (t, st) = match s.trim().split_once(':') {
            Some((t, st)) => (t, Some(st)),
            None => (s.trim(), None),
        };
        let tick: u32 = t.trim().parse().map_err(|_| bad())?;
        let step = match st {
            Some(st) => Some(st.trim().parse::<u32>().map_err(|_| bad())?),
            None => None,
        };
        if tick == 0 {
            return Err(format!("\"{s}\": ticks count from 1"));
        }
        Ok(Moment { tick, step })
    }

    /// `parse`, and also the moments a run of `ticks` ticks gives: `last`
    /// and `end` (the end of its last tick) and `-N` or `-N:STEP` (the N-th
    /// tick from the end: `-1` is the last).
    pub fn parse_within(s: &str, ticks: u32) -> Result<Moment, String> {
        let t = s.trim();
        if t.eq_ignore_ascii_case("last") || t.eq_ignore_ascii_case("end") {
            return Ok(Moment {
                tick: ticks.max(1),
                step: None,
            });
        }
        let Some(rest) = t.strip_prefix('-') else {
            return Moment::parse(s);
        };
        let m = Moment::parse(rest).map_err(|_| {
            format!("\"{s}\" is not a moment: write TICK, TICK:STEP, last, end or -N (the N-th tick from the end), e.g. 10, 10:3 or -1")
        })?;
        if m.tick > ticks {
            return Err(format!(
                "\"{s}\": the run has {ticks} tick{}",
                if ticks == 1 { "" } else { "s" }
            ));
        }
        Ok(Moment {
            tick: ticks + 1 - m.tick,
            step: m.step,
        })
    }
}

impl fmt::Display for Moment {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.step {
            Some(s) => write!(f, "{}:{}", self.tick, s),
            None => write!(f, "{}", self.tick),
        }
    }
}

/// A value that changes at some positions: (position, value) sorted.
#[derive(Debug, Clone, Default)]
pub struct Changes<T> {
    at: Vec<(u32, T)>,
}

impl<T> Changes<T> {
    fn push(&mut self, pos: u32, v: T) {
        match self.at.last_mut() {
            Some(last) if last.0 == pos => last.1 = v,
            _ => self.at.push((pos, v)),
        }
    }

    /// The value in force at `pos` (after `pos` transitions).
    pub fn at(&self, pos: u32) -> Option<&T> {
        let i = self.at.partition_point(|(p, _)| *p <= pos);
        i.checked_sub(1).map(|i| &self.at[i].1)
    }

    /// The value in force after every change so far.
    fn last(&self) -> Option<&T> {
        self.at.last().map(|(_, v)| v)
    }

    pub fn positions(&self) -> impl Iterator<Item = u32> + '_ {
        self.at.iter().map(|(p, _)| *p)
    }
}

/// A node's status and the status it last completed with, if known.
pub type NodeState = (Status, Option<Status>);

/// Positions count transitions applied: position 0 is before the first
/// transition, position `k` is after the k-th.
#[derive(Debug, Clone, Default)]
pub struct Index {
    pub transitions: Vec<Transition>,
    /// Position at the end of each tick (index = tick - 1).
    tick_end: Vec<u32>,
    /// Per node (uid - 1): positions after each of its transitions.
    by_node: Vec<Vec<u32>>,
    /// Per node: positions after each completion (SUCCESS/FAILURE).
    completed: Vec<Vec<u32>>,
    /// Transitions indexed (`index_pending` indexes those after them).
    indexed: usize,
    /// The current node (0 = none yet) at every `CURRENT_EVERY`-th
    /// position; between them it is found from the transitions (kept at
    /// every position it was 4 bytes a transition, 20 MB of a log of
    /// 5·10⁶).
    current: Vec<Uid>,
    /// The current node after the transitions indexed.
    current_now: Uid,
    attempts: HashMap<Uid, Changes<u32>>,
    /// What each node is to the tables (by uid - 1), worked out once for
    /// the tree's shape rather than for each transition.
    roles: Roles,
    entries: HashMap<EntryId, Changes<Value>>,
    decisions: HashMap<Uid, Changes<String>>,
    /// Decisions taken with a transition, by transition index.
    decided: HashMap<u32, String>,
    /// Blackboard writes by the node that made them, in order.
    pub writes: Vec<Write>,
    /// Decisions taken by a leaf that stayed RUNNING: (position, tick, uid, decision).
    pub decision_calls: Vec<(u32, u32, Uid, String)>,
    /// Places where transitions may be missing (a live run), as (position,
    /// why).
    pub gaps: Vec<(u32, String)>,
    /// Writes a leaf made during the call whose transition comes next: the
    /// blackboard shows them from that transition on, not before it.
    held: Vec<(Uid, EntryId, Value)>,
    /// Places where every node's state was read from the robot rather than
    /// followed (a run watched from its middle, at position 0; again after
    /// a gap), as (position, per node its status and last completion).
    /// Empty: every node IDLE, never done, and followed from there.
    resyncs: Vec<(u32, Vec<NodeState>)>,
    /// What answers keep of this run to use again (`causal::facts` keeps
    /// its replay at some ticks).
    pub scratch: super::scratch::Scratch,
}

/// A blackboard write made by a node during a tick, at a position.
#[derive(Debug, Clone)]
pub struct Write {
    pub pos: u32,
    pub tick: u32,
    pub uid: Uid,
    pub entry: EntryId,
    pub value: Value,
}

impl Index {
    pub fn new(nodes: usize) -> Index {
        Index {
            by_node: vec![Vec::new(); nodes],
            completed: vec![Vec::new(); nodes],
            current: vec![0],
            ..Default::default()
        }
    }

    /// Grows the per-node tables after nodes were inserted.
    pub fn resize(&mut self, nodes: usize) {
        self.by_node.resize(nodes, Vec::new());
        self.completed.resize(nodes, Vec::new());
        for (_, states) in &mut self.resyncs {
            states.resize(nodes, (Status::Idle, None));
        }
    }

    /// The nodes' states when recording began (a run watched from its
    /// middle), before any transition is pushed. A uid outside the tree is
    /// left out.
    pub fn set_before(&mut self, before: &[crate::session::Before]) {
        self.resyncs.retain(|(p, _)| *p != 0);
        if !before.is_empty() {
            let states = self.states_of(before);
            self.resyncs.insert(0, (0, states));
        }
    }

    /// Every node's state as read from the robot here (after a gap in a
    /// live run): from this position on, a node with no later transition
    /// has it.
    pub fn push_resync(&mut self, states: &[crate::session::Before]) {
        self.push_resync_at(self.transitions.len() as u32, states)
    }

    /// `push_resync` at a position.
    pub fn push_resync_at(&mut self, pos: u32, states: &[crate::session::Before]) {
        let states = self.states_of(states);
        self.resyncs.retain(|(p, _)| *p != pos);
        self.resyncs.push((pos, states));
    }

    fn states_of(&self, states: &[crate::session::Before]) -> Vec<(Status, Option<Status>)> {
        let mut all = vec![(Status::Idle, None); self.by_node.len()];
        for b in states {
            if let Some(x) = (b.uid as usize).checked_sub(1).and_then(|i| all.get_mut(i)) {
                *x = (b.status, b.done);
            }
        }
        all
    }

    /// Whether the run was recorded from its middle: what came before
    /// recording began is known only as each node's state then.
    pub fn attached(&self) -> bool {
        self.resyncs.first().is_some_and(|(p, _)| *p == 0)
    }

    /// A node's status and last completion when recording began.
    pub fn before(&self, uid: Uid) -> (Status, Option<Status>) {
        match self.resyncs.first() {
            Some((0, states)) => Self::state_in(states, uid),
            _ => (Status::Idle, None),
        }
    }

    fn state_in(states: &[(Status, Option<Status>)], uid: Uid) -> (Status, Option<Status>) {
        states
            .get((uid as usize).wrapping_sub(1))
            .copied()
            .unwrap_or((Status::Idle, None))
    }

    /// The last place at or before `pos` where the nodes' states were read
    /// from the robot (`push_resync`), if any.
    pub fn resync_at(&self, pos: u32) -> Option<(u32, &[NodeState])> {
        let i = self.resyncs.partition_point(|(p, _)| *p <= pos);
        i.checked_sub(1)
            .map(|i| (self.resyncs[i].0, self.resyncs[i].1.as_slice()))
    }

    /// Every place where the nodes' states were read from the robot, with
    /// the states read (as `Before`s: each node not IDLE-and-never-done).
    pub fn resyncs(&self) -> Vec<(u32, Vec<crate::session::Before>)> {
        self.resyncs
            .iter()
            .map(|(p, states)| {
                let list = states
                    .iter()
                    .enumerate()
                    .filter(|(_, s)| **s != (Status::Idle, None))
                    .map(|(i, &(status, done))| crate::session::Before {
                        uid: i as Uid + 1,
                        status,
                        done,
                    })
                    .collect();
                (*p, list)
            })
            .collect()
    }

    /// A transition, with the decision the leaf took in the same tick call.
    /// Shows the writes held for a leaf's call from now on.
    fn release_writes(&mut self) {
        if self.held.is_empty() {
            return;
        }
        for (_, e, v) in std::mem::take(&mut self.held) {
            self.push_write(e, v);
        }
    }

    /// Room for `n` more transitions, reserved at once: a run read whole
    /// knows its length, and growing by doubling would hold up to twice
    /// that while copying. (Each node's lists are reserved by the pass
    /// that fills them, `nodes_from`.)
    pub fn reserve(&mut self, n: usize) {
        room(&mut self.transitions, n);
    }

    pub fn push_transition(&mut self, tree: &Tree, t: Transition, decision: Option<String>) {
        if self.held.iter().any(|(u, _, _)| *u != t.uid) {
            self.release_writes();
        }
        if let Some(d) = decision {
            self.decided
                .insert(self.transitions.len() as u32, d.clone());
            self.push_decision(t.uid, d);
        }
        self.transitions.push(t);
        self.index_pending(tree);
        self.release_writes();
    }

    /// Indexes the transitions pushed since the last time.
    fn index_pending(&mut self, tree: &Tree) {
        let from = self.indexed;
        let (tables, ts) = self.split();
        let ts = &ts[from..];
        tables.fill(tree, from, ts.len(), &|| {
            ts.iter().map(|t| (t.tick, t.uid, t.status))
        });
    }

    /// The transitions of a run read whole, `n` of them: `push` pushes
    /// them (only it needs each one's previous status, which takes
    /// following the run), while the tables are filled from `moves`, the
    /// same transitions' ticks, nodes and statuses; the two at once, and
    /// the tables two at a time.
    pub fn push_whole<F, I>(
        &mut self,
        tree: &Tree,
        n: usize,
        moves: F,
        push: impl FnOnce(&mut Vec<Transition>) + Send,
    ) where
        F: Fn() -> I + Sync,
        I: Iterator<Item = (u32, Uid, Status)>,
    {
        let from = self.indexed;
        self.reserve(n);
        let (tables, ts) = self.split();
        rayon::join(|| push(ts), || tables.fill(tree, from, n, &moves));
        assert_eq!(
            self.transitions.len(),
            self.indexed,
            "pushed the transitions the tables were made from"
        );
    }

    fn split(&mut self) -> (Tables<'_>, &mut Vec<Transition>) {
        (
            Tables {
                roles: &mut self.roles,
                tick_end: &mut self.tick_end,
                by_node: &mut self.by_node,
                completed: &mut self.completed,
                indexed: &mut self.indexed,
                current: &mut self.current,
                current_now: &mut self.current_now,
                attempts: &mut self.attempts,
            },
            &mut self.transitions,
        )
    }

    /// Records that tick `tick` ended (it may have had no transitions).
    pub fn end_tick(&mut self, tick: u32) {
        self.release_writes();
        let pos = self.transitions.len() as u32;
        while self.tick_end.len() < tick as usize {
            self.tick_end.push(pos);
        }
    }

    pub fn push_write(&mut self, entry: EntryId, value: Value) {
        let pos = self.transitions.len() as u32;
        self.entries.entry(entry).or_default().push(pos, value);
    }

    /// A write by a node during a run (kept with its writer, for replays).
    pub fn push_write_by(&mut self, tick: u32, uid: Uid, entry: EntryId, value: Value) {
        self.writes.push(Write {
            pos: self.transitions.len() as u32,
            tick,
            uid,
            entry: entry.clone(),
            value: value.clone(),
        });
        if self.held.iter().any(|(u, _, _)| *u != uid) {
            self.release_writes();
        }
        self.held.push((uid, entry, value));
    }

    /// A decision by a leaf whose status did not change (it stayed RUNNING).
    pub fn push_decision_call(&mut self, tick: u32, uid: Uid, d: String) {
        self.release_writes();
        self.decision_calls
            .push((self.transitions.len() as u32, tick, uid, d.clone()));
        self.push_decision(uid, d);
    }

    pub fn push_decision(&mut self, uid: Uid, d: String) {
        let pos = self.transitions.len() as u32;
        self.decisions.entry(uid).or_default().push(pos, d);
    }

    pub fn ticks(&self) -> u32 {
        self.tick_end.len() as u32
    }

    /// Transitions of tick `tick` (1-based).
    pub fn tick_range(&self, tick: u32) -> std::ops::Range<usize> {
        let end = self.tick_end.get(tick as usize - 1).copied().unwrap_or(0) as usize;
        let start = if tick <= 1 {
            0
        } else {
            self.tick_end[tick as usize - 2] as usize
        };
        start..end
    }

    /// The position of a moment.
    pub fn position(&self, m: Moment) -> Result<u32, String> {
        if m.tick == 0 || m.tick > self.ticks() {
            return Err(format!(
                "moment {m} is outside the run: it has ticks 1 to {}",
                self.ticks()
            ));
        }
        let r = self.tick_range(m.tick);
        match m.step {
            None => Ok(r.end as u32),
            Some(s) => {
                let n = (r.end - r.start) as u32;
                if s > n {
                    Err(format!(
                        "moment {m}: tick {} has {n} transition{}",
                        m.tick,
                        if n == 1 { "" } else { "s" }
                    ))
                } else {
                    Ok(r.start as u32 + s)
                }
            }
        }
    }

    /// The moment of a position (`TICK:STEP`, or `TICK` at a tick's end).
    pub fn moment(&self, pos: u32) -> Moment {
        // A run stopped by an error in its first tick has a tick and no
        // transition: every position is its start.
        let pos = pos.min(self.transitions.len() as u32);
        if pos == 0 {
            return Moment {
                tick: 1,
                step: Some(0),
            };
        }
        let t = self.transitions[pos as usize - 1].tick;
        let r = self.tick_range(t);
        if pos as usize == r.end {
            Moment {
                tick: t,
                step: None,
            }
        } else {
            Moment {
                tick: t,
                step: Some(pos - r.start as u32),
            }
        }
    }

    pub fn at(&self, pos: u32) -> At<'_> {
        At {
            index: self,
            pos: pos.min(self.transitions.len() as u32),
        }
    }

    /// Whether the record holds more of the leaves' calls than their
    /// transitions: blackboard writes or decisions.
    pub fn records_calls(&self) -> bool {
        !(self.writes.is_empty() && self.decision_calls.is_empty() && self.decided.is_empty())
    }

    /// The decision taken with transition `i` (0-based), if any.
    pub fn transition_decision(&self, i: usize) -> Option<&str> {
        self.decided.get(&(i as u32)).map(String::as_str)
    }

    /// Positions at which a node changed status.
    pub fn changes_of(&self, uid: Uid) -> &[u32] {
        &self.by_node[(uid - 1) as usize]
    }

    /// Where node `u`'s call that ends at position `p` started: its last
    /// change out of IDLE before `p`.
    pub fn call_start(&self, u: Uid, p: u32) -> Option<u32> {
        self.changes_of(u)
            .iter()
            .copied()
            .take_while(|&q| q < p)
            .filter(|&q| self.transitions[q as usize - 1].prev == Status::Idle)
            .last()
    }

    /// What a node did in tick `tick`, as the timeline's strip shows it: a
    /// status only where the node ran in that tick (Groot2's log replay
    /// shows a status only where a node ran).
    pub fn tick_mark(&self, uid: Uid, tick: u32) -> TickMark {
        let r = self.tick_range(tick);
        let list = self.changes_of(uid);
        // Positions are 1-based: transition i is position i + 1.
        let lo = list.partition_point(|&p| (p as usize) <= r.start);
        let hi = list.partition_point(|&p| (p as usize) <= r.end);
        if self.at(r.end as u32).status(uid) == Status::Running {
            // Ticked and still RUNNING (a leaf kept RUNNING changes nothing).
            return TickMark::Running;
        }
        if lo == hi {
            let ran_before = lo > 0 || self.before(uid) != (Status::Idle, None);
            return if ran_before {
                TickMark::NotTicked
            } else {
                TickMark::NotYet
            };
        }
        let here = || {
            list[lo..hi]
                .iter()
                .map(|&p| self.transitions[p as usize - 1])
        };
        if let Some(done) = here().map(|t| t.status).rfind(|s| s.is_completed()) {
            return TickMark::Done(done);
        }
        // No completion: halted while RUNNING, or only reset to IDLE after
        // completing in an earlier tick (not ticked in this one).
        if here().any(|t| t.prev == Status::Running && t.status == Status::Idle) {
            TickMark::Halted
        } else {
            TickMark::NotTicked
        }
    }
}

/// A vector with room for `n` more, on huge pages where it is big (see
/// `pages`: a log of millions of transitions faulted them in 4 KB at a time).
fn room<T>(v: &mut Vec<T>, n: usize) {
    if v.capacity() - v.len() >= n {
        return;
    }
    let mut bigger = crate::pages::with_capacity(v.len() + n);
    bigger.append(v);
    *v = bigger;
}

/// Transitions below which the index's passes run one after the other:
/// a thread costs more than a short pass.
const PARALLEL_MIN: usize = 1 << 16;

/// The index's tables, each filled from the transitions' ticks, nodes and
/// statuses by its own pass. Positions count from 1: transition `i`
/// (0-based) is position `i + 1`.
struct Tables<'a> {
    roles: &'a mut Roles,
    tick_end: &'a mut Vec<u32>,
    by_node: &'a mut Vec<Vec<u32>>,
    completed: &'a mut Vec<Vec<u32>>,
    indexed: &'a mut usize,
    current: &'a mut Vec<Uid>,
    current_now: &'a mut Uid,
    attempts: &'a mut HashMap<Uid, Changes<u32>>,
}

impl Tables<'_> {
    /// The tables for `n` transitions after the first `from`.
    fn fill<F, I>(self, tree: &Tree, from: usize, n: usize, moves: &F)
    where
        F: Fn() -> I + Sync,
        I: Iterator<Item = (u32, Uid, Status)>,
    {
        let Tables {
            roles,
            tick_end,
            by_node,
            completed,
            indexed,
            current,
            current_now,
            attempts,
        } = self;
        *indexed = from + n;
        if roles.of.len() != tree.len() {
            *roles = Roles::of(tree);
        }
        let roles = &*roles;
        let mut nodes = || nodes_from(by_node, completed, from, n, moves);
        let mut rest = || {
            ticks_from(tick_end, from, moves());
            current_from(current, current_now, roles, from, moves());
            attempts_from(attempts, tree, roles, from, moves());
        };
        if n >= PARALLEL_MIN {
            rayon::join(nodes, rest);
        } else {
            nodes();
            rest();
        }
    }
}

/// The position at the end of each tick; a tick with no transition ends
/// where the one before it did.
fn ticks_from(
    tick_end: &mut Vec<u32>,
    from: usize,
    moves: impl Iterator<Item = (u32, Uid, Status)>,
) {
    for (i, (tick, _, _)) in (from..).zip(moves) {
        let t = tick as usize;
        if tick_end.len() == t {
            tick_end[t - 1] = i as u32 + 1;
            continue;
        }
        while tick_end.len() < t {
            tick_end.push(i as u32);
        }
        tick_end.truncate(t - 1);
        tick_end.push(i as u32 + 1);
    }
}

/// Each node's changes and completions; where there are many, each list
/// reserved first at its length.
fn nodes_from<I>(
    by_node: &mut [Vec<u32>],
    completed: &mut [Vec<u32>],
    from: usize,
    n: usize,
    moves: impl Fn() -> I,
) where
    I: Iterator<Item = (u32, Uid, Status)>,
{
    if n >= PARALLEL_MIN {
        let mut per = vec![(0usize, 0usize); by_node.len()];
        for (_, uid, status) in moves() {
            let c = &mut per[(uid - 1) as usize];
            c.0 += 1;
            c.1 += usize::from(status.is_completed());
        }
        for ((changes, done), (k, d)) in by_node.iter_mut().zip(completed.iter_mut()).zip(per) {
            room(changes, k);
            room(done, d);
        }
    }
    for (i, (_, uid, status)) in (from..).zip(moves()) {
        let u = (uid - 1) as usize;
        by_node[u].push(i as u32 + 1);
        if status.is_completed() {
            completed[u].push(i as u32 + 1);
        }
    }
}

/// What each node is to the index's tables (by uid - 1), and whether any
/// counts its child's attempts.
#[derive(Debug, Clone, Default)]
struct Roles {
    of: Vec<Role>,
    counting: bool,
}

impl Roles {
    fn of(tree: &Tree) -> Roles {
        let of = Role::all(tree);
        let counting = of.iter().any(|r| r.counts);
        Roles { of, counting }
    }

    /// Whether this transition makes its node the current one: a leaf
    /// ticked (Han's state listener reports the leaf ticked most recently).
    fn makes_current(&self, uid: Uid, status: Status) -> bool {
        status != Status::Idle
            && self
                .of
                .get((uid as usize).wrapping_sub(1))
                .is_some_and(|r| r.leaf)
    }
}

/// What a node is to the index's tables.
#[derive(Debug, Clone, Copy, Default)]
struct Role {
    leaf: bool,
    /// Which of its statuses its parent counts (a RetryUntilSuccessful its
    /// child's failures, a Repeat its successes).
    counted: Option<Status>,
    /// It counts its child's: its count starts again whenever it ends.
    counts: bool,
}

impl Role {
    fn all(tree: &Tree) -> Vec<Role> {
        let counter = |u: Uid| match tree.node(u).builtin {
            Some(Builtin::RetryUntilSuccessful) => Some(Status::Failure),
            Some(Builtin::Repeat) => Some(Status::Success),
            _ => None,
        };
        (1..=tree.len() as Uid)
            .map(|u| {
                let n = tree.node(u);
                Role {
                    leaf: n.kind.is_leaf(),
                    counted: n.parent.and_then(counter),
                    counts: counter(u).is_some(),
                }
            })
            .collect()
    }
}

/// Positions between two kept of the current node.
const CURRENT_EVERY: usize = 256;

/// The current node, the leaf ticked most recently, at every
/// `CURRENT_EVERY`-th position.
fn current_from(
    current: &mut Vec<Uid>,
    now: &mut Uid,
    roles: &Roles,
    from: usize,
    moves: impl Iterator<Item = (u32, Uid, Status)>,
) {
    for (i, (_, uid, status)) in (from..).zip(moves) {
        if roles.makes_current(uid, status) {
            *now = uid;
        }
        if (i + 1) % CURRENT_EVERY == 0 {
            current.push(*now);
        }
    }
}

/// Retry attempts (failures of the child) and Repeat cycles (successes),
/// counted from 0 again whenever the decorator ends or halts.
fn attempts_from(
    attempts: &mut HashMap<Uid, Changes<u32>>,
    tree: &Tree,
    roles: &Roles,
    from: usize,
    moves: impl Iterator<Item = (u32, Uid, Status)>,
) {
    if !roles.counting {
        return;
    }
    for (i, (_, uid, status)) in (from..).zip(moves) {
        let pos = i as u32 + 1;
        let role = roles.of[(uid - 1) as usize];
        if role.counted == Some(status) {
            let p = tree.node(uid).parent.expect("a counted node has a parent");
            let ch = attempts.entry(p).or_default();
            let k = ch.last().copied().unwrap_or(0);
            ch.push(pos, k + 1);
        }
        if role.counts && status != Status::Running {
            attempts.entry(uid).or_default().push(pos, 0);
        }
    }
}

/// What a node did in one tick (`Index::tick_mark`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TickMark {
    /// It has not run yet in this run.
    NotYet,
    /// It ran before, not in this tick (at most reset to IDLE in it).
    NotTicked,
    /// RUNNING at the tick's end.
    Running,
    /// It completed in this tick: its last completion in it.
    Done(Status),
    /// It was halted in this tick, with no completion.
    Halted,
}

/// The run as it was at one position.
#[derive(Clone, Copy)]
pub struct At<'a> {
    pub index: &'a Index,
    pub pos: u32,
}

impl At<'_> {
    fn last_before(list: &[u32], pos: u32) -> Option<&u32> {
        let i = list.partition_point(|&p| p <= pos);
        i.checked_sub(1).map(|i| &list[i])
    }

    /// The node's state read from the robot at the last resync, if no
    /// transition of the node (among `list`, its transitions or its
    /// completions) came after it up to this position.
    fn resynced(&self, list: &[u32], uid: Uid) -> Option<(Status, Option<Status>)> {
        let (at, states) = self.index.resync_at(self.pos)?;
        Self::last_before(list, self.pos)
            .is_none_or(|&p| p <= at)
            .then(|| Index::state_in(states, uid))
    }

    pub fn status(&self, uid: Uid) -> Status {
        let list = &self.index.by_node[(uid - 1) as usize];
        if let Some((s, _)) = self.resynced(list, uid) {
            return s;
        }
        match Self::last_before(list, self.pos) {
            Some(&p) => self.index.transitions[p as usize - 1].status,
            None => Status::Idle,
        }
    }

    /// The status the node last completed with, even if it was reset since
    /// (for a run recorded from its middle, maybe before recording began).
    pub fn last_completed(&self, uid: Uid) -> Option<Status> {
        let list = &self.index.completed[(uid - 1) as usize];
        if let Some((_, done)) = self.resynced(list, uid) {
            return done;
        }
        Self::last_before(list, self.pos).map(|&p| self.index.transitions[p as usize - 1].status)
    }

    /// The completion the node had when its state was last read from the
    /// robot (recording began, or a gap), if it has not completed since
    /// (at this position): known, but not when.
    pub fn done_before(&self, uid: Uid) -> Option<Status> {
        let list = &self.index.completed[(uid - 1) as usize];
        self.resynced(list, uid).and_then(|(_, done)| done)
    }

    /// Han's `failed`: the last completed status is FAILURE.
    pub fn failed(&self, uid: Uid) -> bool {
        self.last_completed(uid) == Some(Status::Failure)
    }

    /// The position just before the transition that started the root's
    /// current run (its last start from IDLE at or before this position;
    /// 0 before any).
    /// Han's released code looks only at this run: a failure from before
    /// the root last restarted is history, not what went wrong.
    pub fn run_start(&self) -> u32 {
        self.started_at(crate::model::Tree::ROOT)
    }

    /// The position of the node's last completion at or before this one,
    /// with its status.
    pub fn last_completion(&self, uid: Uid) -> Option<(u32, Status)> {
        let list = &self.index.completed[(uid - 1) as usize];
        Self::last_before(list, self.pos)
            .map(|&p| (p, self.index.transitions[p as usize - 1].status))
    }

    /// The position just before the node's last start from IDLE at or
    /// before this position (0 before any). A node that halts itself and
    /// completes in the same call (Nav2's RecoveryNode when its retries run
    /// out: RUNNING → IDLE, then at once IDLE → FAILURE) has not started
    /// again.
    pub fn started_at(&self, uid: Uid) -> u32 {
        let list = &self.index.by_node[(uid - 1) as usize];
        let i = list.partition_point(|&p| p <= self.pos);
        let t = |k: usize| &self.index.transitions[list[k] as usize - 1];
        (0..i)
            .rev()
            .find(|&k| {
                let here = t(k);
                let halted_just_before = k > 0 && list[k - 1] + 1 == list[k] && {
                    let h = t(k - 1);
                    h.prev == Status::Running && h.status == Status::Idle
                };
                here.prev == Status::Idle && !(here.status.is_completed() && halted_just_before)
            })
            .map_or(0, |k| list[k] - 1)
    }

    /// The position of the node's last FAILURE after position `since`, at
    /// or before this one (a failure stays a cause after a later success).
    pub fn last_failure_since(&self, uid: Uid, since: u32) -> Option<u32> {
        let list = &self.index.completed[(uid - 1) as usize];
        let i = list.partition_point(|&p| p <= self.pos);
        list[..i]
            .iter()
            .rev()
            .take_while(|&&p| p > since)
            .find(|&&p| self.index.transitions[p as usize - 1].status == Status::Failure)
            .copied()
    }

    /// How the root's current run ended, if it has: its completion status.
    pub fn root_outcome(&self) -> Option<Status> {
        self.last_completion(crate::model::Tree::ROOT)
            .filter(|&(p, _)| p > self.run_start())
            .map(|(_, s)| s)
    }

    /// The node's last change was a halt (RUNNING → IDLE).
    pub fn halted(&self, uid: Uid) -> bool {
        let list = &self.index.by_node[(uid - 1) as usize];
        Self::last_before(list, self.pos).is_some_and(|&p| {
            let t = &self.index.transitions[p as usize - 1];
            t.prev == Status::Running && t.status == Status::Idle
        })
    }

    /// The leaves RUNNING at this position, in tree order.
    pub fn running_leaves(&self, tree: &Tree) -> Vec<Uid> {
        tree.nodes
            .iter()
            .filter(|n| n.kind.is_leaf() && self.status(n.uid) == Status::Running)
            .map(|n| n.uid)
            .collect()
    }

    /// Failures so far of a RetryUntilSuccessful's child (cycles of a Repeat).
    pub fn attempts(&self, uid: Uid) -> u32 {
        self.index
            .attempts
            .get(&uid)
            .and_then(|c| c.at(self.pos))
            .copied()
            .unwrap_or(0)
    }

    /// The node Han's state listener reports: the leaf ticked most recently.
    /// Han's current node: that of the last transition. In a run recorded
    /// from its middle, before its first transition: the last node (in
    /// tree order, so a deepest one) running when recording began.
    pub fn current(&self) -> Option<Uid> {
        let i = self.index;
        let pos = self.pos as usize;
        let kept = pos / CURRENT_EVERY;
        let now = i.transitions[kept * CURRENT_EVERY..pos]
            .iter()
            .rev()
            .find(|t| i.roles.makes_current(t.uid, t.status))
            .map_or(i.current[kept], |t| t.uid);
        Some(now).filter(|&u| u != 0).or_else(|| {
            (1..=self.index.by_node.len() as Uid)
                .rev()
                .find(|&u| self.index.before(u).0 == Status::Running)
        })
    }

    pub fn entry(&self, e: &EntryId) -> Option<&Value> {
        self.index.entries.get(e).and_then(|c| c.at(self.pos))
    }

    /// Every blackboard entry with its value at this position.
    pub fn entries(&self) -> Vec<(&EntryId, &Value)> {
        let mut v: Vec<_> = self
            .index
            .entries
            .iter()
            .filter_map(|(e, c)| c.at(self.pos).map(|v| (e, v)))
            .collect();
        v.sort_by(|a, b| a.0.cmp(b.0));
        v
    }

    pub fn decision(&self, uid: Uid) -> Option<&str> {
        self.index
            .decisions
            .get(&uid)
            .and_then(|c| c.at(self.pos))
            .map(String::as_str)
    }

    pub fn moment(&self) -> Moment {
        self.index.moment(self.pos)
    }
}

#[cfg(test)]
mod tests;
