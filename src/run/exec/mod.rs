//! The executor: ticks a tree exactly as BehaviorTree.CPP 4.10 does
//! (`tickExactlyOnce`), and reports every status change as the library's
//! `StatusChangeLogger` sees it, halts and resets (→ IDLE) included.

mod controls;
mod decorators;
mod leaves;
mod nav2;
mod scripts;

pub use leaves::{LeafCall, LeafOutcome, Leaves};
pub use nav2::ROBOT_READINGS;

use super::blackboard::{Blackboard, EntryId};
use super::status::Status;
use crate::model::{Builtin, Kind, PortValue, Tree, Uid};
use serde_json::Value;

/// One thing that happened during a run.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum Event {
    /// A status change, as StatusChangeLogger reports it.
    Transition {
        tick: u32,
        uid: Uid,
        prev: Status,
        status: Status,
        #[serde(skip_serializing_if = "Option::is_none")]
        decision: Option<String>,
    },
    /// A leaf chose an action without changing status (it stays RUNNING).
    Decision {
        tick: u32,
        uid: Uid,
        decision: String,
    },
    /// A blackboard entry written by a node.
    Write {
        tick: u32,
        uid: Uid,
        entry: EntryId,
        value: Value,
    },
}

/// A run that cannot go on: a node the library would throw on.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("tick {tick}: {node} #{uid}: {message}")]
pub struct RunError {
    pub tick: u32,
    pub uid: Uid,
    pub node: String,
    pub message: String,
}

#[derive(Debug, Clone, Default)]
struct NodeRt {
    status: Status,
    /// Current child (sequences, fallbacks, IfThenElse, TryCatch), or the
    /// running child + 1 (reactive nodes, Switch; 0 = none).
    idx: usize,
    /// Retry attempts or Repeat cycles so far.
    count: i64,
    completed: Vec<bool>,
    successes: usize,
    failures: usize,
    skipped: usize,
    /// Timeout/Delay started; RunOnce done; TryCatch in its catch.
    started: bool,
    /// Timeout halted its child; Delay's time is up.
    fired: bool,
    cached: Status,
    deadline: Option<u64>,
    /// Nav2's RateController and SpeedController: when its period began
    /// (simulated ms); SpeedController's period (s).
    since_ms: u64,
    period_s: f64,
    /// Nav2's DistanceController: the distance travelled when its distance
    /// began.
    origin: f64,
    /// What a Nav2 decorator last saw: GoalUpdatedController's goals,
    /// SingleTrigger's run id.
    seen: Vec<Option<Value>>,
    /// The tick the node was last ticked in, and what it returned then.
    ticked: u32,
    returned: Status,
    /// When the node was last ticked (a counter over all ticks of nodes),
    /// and its control state and status as that tick began: a node ticked
    /// again within one tick (under a Retry) starts from a reset state.
    entry_seq: u64,
    entry: Flow,
    entry_status: Status,
    /// Transitions of this node so far.
    transitions: u64,
}

impl NodeRt {
    /// The same control state: what the node does when ticked next. Every
    /// field is named, so that a new one is sorted here too.
    fn same_control(&self, o: &NodeRt) -> bool {
        let NodeRt {
            status,
            idx,
            count,
            completed,
            successes,
            failures,
            skipped,
            started,
            fired,
            cached,
            deadline,
            since_ms,
            period_s,
            origin,
            seen,
            ticked: _,
            returned: _,
            entry_seq: _,
            entry: _,
            entry_status: _,
            transitions: _,
        } = self;
        *status == o.status
            && *idx == o.idx
            && *count == o.count
            && *completed == o.completed
            && *successes == o.successes
            && *failures == o.failures
            && *skipped == o.skipped
            && *started == o.started
            && *fired == o.fired
            && *cached == o.cached
            && *deadline == o.deadline
            && *since_ms == o.since_ms
            && period_s.to_bits() == o.period_s.to_bits()
            && origin.to_bits() == o.origin.to_bits()
            && *seen == o.seen
    }

    /// Forgets when the node was last ticked and how it began then.
    fn forget_calls(&mut self) {
        self.ticked = 0;
        self.returned = Status::Idle;
        self.entry_seq = 0;
        self.entry = Flow::default();
        self.entry_status = Status::Idle;
        self.transitions = 0;
    }
}

/// What a control node carries from one tick into the next, as the causal
/// model needs it: where a composite resumes, which Parallel children are
/// done, how many retries are spent.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Flow {
    pub idx: usize,
    pub completed: Vec<bool>,
    pub successes: usize,
    pub failures: usize,
    pub skipped: usize,
    pub count: i64,
    pub started: bool,
    /// A Nav2 RoundRobin that wraps around past its last child (the
    /// run's release and its `wrap_around` port decide).
    pub wraps: bool,
}

/// Options of a run.
#[derive(Debug, Clone, Copy)]
pub struct RunOptions {
    /// Simulated time between ticks, for Timeout, Delay and Sleep.
    pub tick_ms: u64,
    /// The Nav2 release whose nodes the run follows where they differ.
    pub nav2: crate::model::nav2::Release,
}

impl Default for RunOptions {
    fn default() -> Self {
        RunOptions {
            tick_ms: 10,
            nav2: Default::default(),
        }
    }
}

/// What a parked executor holds in place of its tree: it is never ticked
/// while parked.
static NO_TREE: std::sync::LazyLock<Tree> = std::sync::LazyLock::new(|| Tree {
    version: crate::model::Version::V4,
    release: crate::model::Version::V4,
    main_tree: String::new(),
    nodes: Vec::new(),
    scopes: Vec::new(),
    models: Default::default(),
    files: Vec::new(),
    unused: Vec::new(),
});

/// An executor's state without its tree (`Executor::park`): a replay kept
/// at a tick, to go on from there without replaying the ticks before it.
#[derive(Clone)]
pub struct Parked<L: Leaves>(Executor<'static, L>);

impl<L: Leaves + Clone> Parked<L> {
    /// Goes on with `tree`, the one the executor ran: `None` when its
    /// nodes are not those (a subgoal inserted since).
    pub fn resume<'u>(&self, tree: &'u Tree) -> Option<Executor<'u, L>> {
        (self.0.rt.len() == tree.len()).then(|| self.0.clone().rebind(tree))
    }

    /// The tick it was parked after.
    pub fn ticks(&self) -> u32 {
        self.0.tick
    }

    /// The executor as it was parked, to compare (not to tick: it has no tree).
    pub fn peek(&self) -> &Executor<'static, L> {
        &self.0
    }
}

// Clone: a live run's tick replay goes on from a copy, kept at the last
// whole tick, when a tick's records have not all arrived (`logs::ticks`).
#[derive(Clone)]
pub struct Executor<'t, L: Leaves> {
    tree: &'t Tree,
    pub leaves: L,
    rt: Vec<NodeRt>,
    pub bb: Blackboard,
    tick: u32,
    now_ms: u64,
    opts: RunOptions,
    events: Vec<Event>,
    pending_decision: Option<(Uid, String)>,
    seq: u64,
    /// Interventions of a counterfactual re-run: node `uid`'s `call`-th
    /// tick within tick `tick` returns `status`, whatever it computed.
    pub forced: Vec<Forced>,
    /// How often each node was ticked in the current tick (uid − 1).
    calls: Vec<u32>,
    /// Whether to keep `call_log` (the causal model's attempt copies read
    /// it; a plain run does not pay for it).
    pub record_calls: bool,
    call_log: Vec<CallRecord>,
    /// Transitions emitted in the current tick.
    tick_transitions: u32,
    /// Interventions of a counterfactual re-run on Love's attempt count:
    /// at the start of tick `.0`, Retry or Repeat `.1` has spent `.2`.
    pub set_count: Vec<(u32, Uid, i64)>,
    /// The leaf being ticked was called (a completed action ticked again
    /// before a reset keeps its status without a call).
    leaf_called: bool,
}

/// Where a call began: its sequence number and the counts of transitions
/// and events then, which say what the call itself did.
struct CallStart {
    seq: u64,
    own_transitions: u64,
    tick_transitions: u32,
    events: usize,
}

/// One tick of a node within the current tick: the causal model gives each
/// attempt of a Retry's or Repeat's child its own copy of the child's
/// variables, from these.
#[derive(Debug, Clone, PartialEq)]
pub struct CallRecord {
    pub uid: Uid,
    /// Which of the node's ticks within the tick, from 1.
    pub call: u32,
    /// When the call began and ended (the executor's counter of node ticks).
    pub entry_seq: u64,
    pub exit_seq: u64,
    /// The node's control state and status as the call began.
    pub entry: Flow,
    pub entry_status: Status,
    pub returned: Status,
    /// Transitions of the tick emitted when the call ended, and whether
    /// the call emitted one of the node's own.
    pub transitions_before: u32,
    pub transitions_after: u32,
    pub transitioned: bool,
    /// The action a leaf chose in this call, if it chose one.
    pub decision: Option<String>,
}

/// One forced return status (a counterfactual re-run's intervention on
/// Love's r_i): the node's children still run as they would.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Forced {
    pub tick: u32,
    pub uid: Uid,
    /// Which of the node's ticks within the tick, from 1.
    pub call: u32,
    pub status: Status,
}

type R<T> = Result<T, RunError>;

/// The most of a script an error quotes (bytes).
const QUOTED_MAX: usize = 200;

/// The most ticks of one child within one tick (a Retry or Repeat loop).
pub const CHILD_TICKS_IN_A_TICK_MAX: u32 = 100_000;

impl<'t, L: Leaves> Executor<'t, L> {
    pub fn new(tree: &'t Tree, leaves: L, opts: RunOptions) -> Self {
        let mut bb = Blackboard::new(tree);
        for (e, v) in leaves.initial_entries() {
            bb.set(&e, v);
        }
        Executor {
            tree,
            leaves,
            rt: vec![NodeRt::default(); tree.len()],
            bb,
            tick: 0,
            now_ms: 0,
            opts,
            events: Vec::new(),
            pending_decision: None,
            seq: 0,
            forced: Vec::new(),
            calls: vec![0; tree.len()],
            record_calls: false,
            call_log: Vec::new(),
            tick_transitions: 0,
            set_count: Vec::new(),
            leaf_called: false,
        }
    }

    /// Carries the run on with a tree that has nodes inserted (existing uids
    /// unchanged, new ones appended), as after "Can you X?".
    pub fn retarget<'u>(self, tree: &'u Tree) -> Executor<'u, L> {
        let mut ex = self.rebind(tree);
        ex.rt.resize(tree.len(), NodeRt::default());
        ex.calls = vec![0; tree.len()];
        ex.call_log = Vec::new();
        ex.tick_transitions = 0;
        ex.leaf_called = false;
        ex
    }

    /// The run as it stands, kept apart from its tree: to go on from here
    /// later, as often as wanted (`Parked::resume`).
    pub fn park(self) -> Parked<L> {
        Parked(self.rebind(&NO_TREE))
    }

    /// Every field as it is, with another tree of the same nodes.
    fn rebind<'u>(self, tree: &'u Tree) -> Executor<'u, L> {
        Executor {
            tree,
            leaves: self.leaves,
            rt: self.rt,
            bb: self.bb,
            tick: self.tick,
            now_ms: self.now_ms,
            opts: self.opts,
            events: self.events,
            pending_decision: self.pending_decision,
            seq: self.seq,
            forced: self.forced,
            calls: self.calls,
            record_calls: self.record_calls,
            call_log: self.call_log,
            tick_transitions: self.tick_transitions,
            set_count: self.set_count,
            leaf_called: self.leaf_called,
        }
    }

    /// How often the node was ticked in the last tick (a node under a
    /// Retry or Repeat can be ticked more than once).
    pub fn calls(&self, uid: Uid) -> u32 {
        self.calls[(uid - 1) as usize]
    }

    /// Every tick of a node in the last tick, in the order the calls
    /// ended (kept only with `record_calls`).
    pub fn call_log(&self) -> &[CallRecord] {
        &self.call_log
    }

    /// Ticks completed so far.
    pub fn ticks(&self) -> u32 {
        self.tick
    }

    /// Whether this executor and `other` go on alike from the start of
    /// their next ticks, given the same leaf calls in the same order: every
    /// node's control state and the blackboard are equal (when and what each
    /// node was last ticked aside), and no node waits on simulated time (a
    /// deadline, a period begun), so that either is the same state at any
    /// tick (`rebase`). The replay's marks share such states between the
    /// runs of a log that a reset of the whole tree separates.
    pub fn same_course(&self, other: &Executor<'_, L>) -> bool {
        self.timeless()
            && other.timeless()
            && self.pending_decision == other.pending_decision
            && self.bb == other.bb
            && self.rt.len() == other.rt.len()
            && self
                .rt
                .iter()
                .zip(&other.rt)
                .all(|(a, b)| a.same_control(b))
    }

    /// No node waits on simulated time: the state is the same at any tick.
    pub fn timeless(&self) -> bool {
        self.rt
            .iter()
            .all(|r| r.deadline.is_none() && r.since_ms == 0)
    }

    /// A timeless executor (`same_course`) moved to the end of tick
    /// `ticks`, as if it had come there: what each node did last is
    /// forgotten, as it belongs to other ticks.
    pub fn rebase(&mut self, ticks: u32) {
        debug_assert!(self.timeless());
        self.tick = ticks;
        self.now_ms = u64::from(ticks.saturating_sub(1)) * self.opts.tick_ms;
        for r in &mut self.rt {
            r.forget_calls();
        }
    }

    pub fn status(&self, uid: Uid) -> Status {
        self.rt[(uid - 1) as usize].status
    }

    /// Retry attempts (failures so far) of a RetryUntilSuccessful, or cycles of a Repeat.
    pub fn attempts(&self, uid: Uid) -> i64 {
        self.rt[(uid - 1) as usize].count
    }

    /// The tick in which a node was last ticked (0: never) and the status
    /// it returned then (a ticked node may return SKIPPED).
    pub fn last_ticked(&self, uid: Uid) -> (u32, Status) {
        let r = &self.rt[(uid - 1) as usize];
        (r.ticked, r.returned)
    }

    /// When the node was last ticked (an increasing counter, 0: never),
    /// with its control state and status as that tick began.
    pub fn last_entry(&self, uid: Uid) -> (u64, &Flow, Status) {
        let r = &self.rt[(uid - 1) as usize];
        (r.entry_seq, &r.entry, r.entry_status)
    }

    pub fn flow(&self, uid: Uid) -> Flow {
        let r = &self.rt[(uid - 1) as usize];
        Flow {
            idx: r.idx,
            completed: r.completed.clone(),
            successes: r.successes,
            failures: r.failures,
            skipped: r.skipped,
            count: r.count,
            started: r.started,
            wraps: self.round_robin_wraps(uid),
        }
    }

    /// Whether a Nav2 RoundRobin wraps around past its last child: always
    /// in Humble and Jazzy, in main only with `wrap_around="true"`.
    pub(crate) fn round_robin_wraps(&self, uid: Uid) -> bool {
        use crate::model::nav2::Release;
        match self.opts.nav2 {
            Release::Humble | Release::Jazzy => true,
            Release::Main => self
                .port_str(uid, "wrap_around")
                .is_some_and(|w| w.trim().eq_ignore_ascii_case("true")),
        }
    }

    /// The events since the last call.
    pub fn take_events(&mut self) -> Vec<Event> {
        std::mem::take(&mut self.events)
    }

    /// One `tickExactlyOnce()`: fire due timers, tick the root, and reset the
    /// root when it completes.
    pub fn tick_once(&mut self) -> R<Status> {
        self.tick += 1;
        self.calls.iter_mut().for_each(|c| *c = 0);
        self.call_log.clear();
        self.tick_transitions = 0;
        for &(t, uid, count) in &self.set_count {
            if t == self.tick && (uid as usize) <= self.rt.len() {
                self.rt[(uid - 1) as usize].count = count;
            }
        }
        self.now_ms = u64::from(self.tick - 1) * self.opts.tick_ms;
        self.fire_timers()?;
        let s = self.exec(Tree::ROOT)?;
        if s.is_completed() {
            self.set_status(Tree::ROOT, Status::Idle);
        }
        Ok(s)
    }

    fn err(&self, uid: Uid, message: impl Into<String>) -> RunError {
        RunError {
            tick: self.tick,
            uid,
            node: self.tree.description(uid).to_string(),
            message: message.into(),
        }
    }

    fn rt(&mut self, uid: Uid) -> &mut NodeRt {
        &mut self.rt[(uid - 1) as usize]
    }

    fn set_status(&mut self, uid: Uid, s: Status) {
        let prev = self.rt(uid).status;
        if prev == s {
            return;
        }
        self.rt(uid).status = s;
        self.rt(uid).transitions += 1;
        self.tick_transitions += 1;
        self.leaves.observe(uid, prev, s);
        let decision = match self.pending_decision.take() {
            Some((u, d)) if u == uid => Some(d),
            other => {
                self.pending_decision = other;
                None
            }
        };
        self.events.push(Event::Transition {
            tick: self.tick,
            uid,
            prev,
            status: s,
            decision,
        });
    }

    // ---- ports of built-in nodes ----

    fn port_str(&self, uid: Uid, name: &str) -> Option<String> {
        let n = self.tree.node(uid);
        let p = n.ports.iter().find(|p| p.name == name)?;
        match &p.value {
            PortValue::Literal(s) => Some(s.clone()),
            v => {
                let e = self.bb.port_entry(self.tree, n.scope, v)?;
                self.bb.get(&e).map(|v| match v {
                    Value::String(s) => s.clone(),
                    other => other.to_string(),
                })
            }
        }
    }

    fn port_int(&self, uid: Uid, names: &[&str], default: Option<i64>) -> R<i64> {
        for name in names {
            if let Some(s) = self.port_str(uid, name) {
                return s
                    .trim()
                    .parse::<i64>()
                    .map_err(|_| self.err(uid, format!("port {name}=\"{s}\" is not an integer")));
            }
        }
        default.ok_or_else(|| self.err(uid, format!("the port {} is missing", names[0])))
    }

    // ---- halting and resetting ----

    fn reset_status(&mut self, uid: Uid) {
        self.set_status(uid, Status::Idle);
    }

    /// `haltNode()`: the node's `halt()`.
    fn halt_node(&mut self, uid: Uid) {
        let n = self.tree.node(uid);
        match n.builtin {
            Some(Builtin::SequenceWithMemory) => {}
            Some(Builtin::RetryUntilSuccessful | Builtin::Repeat) => self.rt(uid).count = 0,
            Some(Builtin::Timeout | Builtin::Delay | Builtin::Sleep) => {
                let r = self.rt(uid);
                r.started = false;
                r.fired = false;
                r.deadline = None;
            }
            Some(Builtin::Parallel | Builtin::ParallelAll) => self.clear_parallel(uid),
            Some(Builtin::RecoveryNode | Builtin::RoundRobin) => {
                let r = self.rt(uid);
                r.idx = 0;
                r.count = 0;
                r.failures = 0;
            }
            Some(Builtin::RunOnce) => {}
            _ => {
                let r = self.rt(uid);
                r.idx = 0;
                r.skipped = 0;
                r.started = false;
            }
        }
        if n.kind.is_leaf() {
            if self.status(uid) == Status::Running && n.builtin.is_none() {
                self.leaves.halt(uid);
            }
        } else {
            self.reset_children(uid);
        }
        if let Some(code) = self.script_attr(uid, "_onHalted") {
            // A failing _onHalted script cannot stop a halt; it is skipped.
            let _ = self.script(uid, &code, "_onHalted");
        }
        self.reset_status(uid);
    }

    fn halt_child(&mut self, child: Uid) {
        if self.status(child) == Status::Running {
            self.halt_node(child);
        }
        self.reset_status(child);
    }

    /// `resetChildren()` / `resetChild()`.
    fn reset_children(&mut self, uid: Uid) {
        let tree = self.tree;
        for &c in &tree.node(uid).children {
            self.halt_child(c);
        }
    }

    fn clear_parallel(&mut self, uid: Uid) {
        let r = self.rt(uid);
        r.completed.iter_mut().for_each(|c| *c = false);
        r.successes = 0;
        r.failures = 0;
        r.skipped = 0;
    }

    // ---- timers on the simulated clock ----

    /// Timeout's and Delay's first tick: RUNNING, and a timer that fires
    /// `ms` from now (at once when `ms` <= 0).
    fn start_timer(&mut self, uid: Uid, ms: i64) {
        self.set_status(uid, Status::Running);
        let now = self.now_ms;
        let r = self.rt(uid);
        r.started = true;
        r.fired = ms <= 0;
        r.deadline = (ms > 0).then_some(now + ms as u64);
    }

    fn fire_timers(&mut self) -> R<()> {
        for i in 0..self.rt.len() {
            let Some(deadline) = self.rt[i].deadline else {
                continue;
            };
            if deadline > self.now_ms {
                continue;
            }
            let uid = (i + 1) as Uid;
            self.rt[i].deadline = None;
            match self.tree.node(uid).builtin {
                Some(Builtin::Timeout) => {
                    let child = self.tree.node(uid).children[0];
                    if self.status(child) == Status::Running {
                        self.rt[i].fired = true;
                        self.halt_child(child);
                    }
                }
                _ => self.rt[i].fired = true,
            }
        }
        Ok(())
    }

    // ---- ticking ----

    /// `executeTick()`: tick, then take the returned status (a SKIPPED node
    /// stays IDLE).
    fn exec(&mut self, uid: Uid) -> R<Status> {
        let n = self.tree.node(uid);
        let start = self.enter_call(uid);
        let mut s = match self.pre_conditions(uid)? {
            Some(s) => s,
            None => self.tick_node(uid)?,
        };
        if let Some(forced) = self.forced_status(uid) {
            s = forced;
        }
        let replayed = n.kind.is_leaf()
            && n.builtin.is_none()
            && self.leaf_called
            && self.leaves.post_scripts_recorded(uid);
        if !n.scripts.is_empty() && !replayed {
            self.post_conditions(uid, s)?;
        }
        if s == Status::Idle {
            return Err(self.err(uid, "a node returned IDLE when ticked"));
        }
        let tick = self.tick;
        let r = self.rt(uid);
        r.ticked = tick;
        r.returned = s;
        if s != Status::Skipped {
            self.set_status(uid, s);
        }
        if self.record_calls {
            let record = self.call_record(uid, &start, s);
            self.call_log.push(record);
        }
        Ok(s)
    }

    /// Counts a call of `uid` and keeps its state as the call found it
    /// (what a counterfactual replays the call from).
    fn enter_call(&mut self, uid: Uid) -> CallStart {
        self.seq += 1;
        let seq = self.seq;
        let wraps =
            self.tree.node(uid).builtin == Some(Builtin::RoundRobin) && self.round_robin_wraps(uid);
        let r = self.rt(uid);
        r.entry.wraps = wraps;
        r.entry_seq = seq;
        r.entry_status = r.status;
        r.entry.idx = r.idx;
        r.entry.successes = r.successes;
        r.entry.failures = r.failures;
        r.entry.skipped = r.skipped;
        r.entry.count = r.count;
        r.entry.started = r.started;
        if !r.completed.is_empty() || !r.entry.completed.is_empty() {
            r.entry.completed.clone_from(&r.completed);
        }
        let c = &mut self.calls[(uid - 1) as usize];
        *c = c.saturating_add(1);
        CallStart {
            seq,
            own_transitions: self.rt[(uid - 1) as usize].transitions,
            tick_transitions: self.tick_transitions,
            events: self.events.len(),
        }
    }

    /// The status a plan forces on this call of `uid` in this tick, if any.
    fn forced_status(&self, uid: Uid) -> Option<Status> {
        let call = self.calls[(uid - 1) as usize];
        self.forced
            .iter()
            .find(|f| f.tick == self.tick && f.uid == uid && f.call == call)
            .map(|f| f.status)
    }

    /// The record of the call of `uid` that began at `start` and returned `s`.
    fn call_record(&self, uid: Uid, start: &CallStart, s: Status) -> CallRecord {
        let r = &self.rt[(uid - 1) as usize];
        CallRecord {
            uid,
            call: self.calls[(uid - 1) as usize],
            entry_seq: start.seq,
            exit_seq: self.seq,
            entry: r.entry.clone(),
            entry_status: r.entry_status,
            returned: s,
            transitions_before: start.tick_transitions,
            transitions_after: self.tick_transitions,
            transitioned: r.transitions != start.own_transitions,
            // Only a leaf decides; a control node's call spans all of
            // its subtree's events, which are not searched.
            decision: self
                .tree
                .node(uid)
                .kind
                .is_leaf()
                .then(|| self.decision_since(uid, start.events))
                .flatten(),
        }
    }

    /// The last decision `uid` made among the events from `from` on.
    fn decision_since(&self, uid: Uid, from: usize) -> Option<String> {
        self.events[from.min(self.events.len())..]
            .iter()
            .rev()
            .find_map(|e| match e {
                Event::Transition {
                    uid: u,
                    decision: Some(d),
                    ..
                }
                | Event::Decision {
                    uid: u,
                    decision: d,
                    ..
                } if *u == uid => Some(d.clone()),
                _ => None,
            })
    }

    fn tick_node(&mut self, uid: Uid) -> R<Status> {
        let n = self.tree.node(uid);
        match (n.kind, n.builtin) {
            (Kind::SubTree, _) => self.tick_subtree(uid),
            (Kind::Action | Kind::Condition, Some(b)) => self.tick_builtin_leaf(uid, b),
            (Kind::Action | Kind::Condition, None) => self.tick_leaf(uid),
            (_, Some(b)) => self.tick_builtin(uid, b),
            (Kind::Control, None) => Err(self.err(
                uid,
                format!(
                    "custom control node \"{}\" has no behaviour in btx{}",
                    n.id,
                    did_you_mean(&n.id)
                ),
            )),
            (Kind::Decorator, None) => Err(self.err(
                uid,
                format!(
                    "custom decorator \"{}\" has no behaviour in btx{}",
                    n.id,
                    did_you_mean(&n.id)
                ),
            )),
        }
    }

    // ---- scripts ----

    fn tick_builtin(&mut self, uid: Uid, b: Builtin) -> R<Status> {
        let tree = self.tree;
        match b {
            Builtin::Sequence | Builtin::AsyncSequence => self.tick_sequential(uid, b == Builtin::AsyncSequence, Status::Success),
            Builtin::Fallback | Builtin::AsyncFallback => self.tick_sequential(uid, b == Builtin::AsyncFallback, Status::Failure),
            Builtin::SequenceWithMemory => self.tick_sequence_with_memory(uid),
            Builtin::ReactiveSequence => self.tick_reactive(uid, Status::Success),
            Builtin::ReactiveFallback => self.tick_reactive(uid, Status::Failure),
            Builtin::Parallel => self.tick_parallel(uid),
            Builtin::ParallelAll => self.tick_parallel_all(uid),
            Builtin::IfThenElse => self.tick_if_then_else(uid),
            Builtin::WhileDoElse => self.tick_while_do_else(uid),
            Builtin::TryCatch => self.tick_try_catch(uid),
            Builtin::PipelineSequence => self.tick_pipeline(uid),
            Builtin::RecoveryNode => self.tick_recovery(uid),
            Builtin::RoundRobin => self.tick_round_robin(uid),
            Builtin::PersistentSequence => self.tick_persistent_sequence(uid),
            Builtin::NonblockingSequence => self.tick_nonblocking_sequence(uid),
            Builtin::PauseResumeController => self.tick_pause_resume(uid),
            Builtin::Switch(k) => self.tick_switch(uid, k as usize),
            Builtin::ManualSelector => Err(self.err(uid, "ManualSelector asks a person at the terminal; btx cannot run it")),
            Builtin::Inverter => self.tick_inverter(uid),
            Builtin::ForceSuccess | Builtin::ForceFailure => self.tick_force(uid, b),
            Builtin::RateController => self.tick_rate_controller(uid),
            Builtin::DistanceController => self.tick_distance_controller(uid),
            Builtin::SpeedController => self.tick_speed_controller(uid),
            Builtin::GoalUpdatedController => self.tick_goal_updated_controller(uid),
            Builtin::GoalUpdater => self.tick_goal_updater(uid),
            Builtin::PathLongerOnApproach => self.tick_path_longer_on_approach(uid),
            Builtin::SingleTrigger => self.tick_single_trigger(uid),
            Builtin::RetryUntilSuccessful => self.tick_retry(uid),
            Builtin::Repeat => self.tick_repeat(uid),
            Builtin::KeepRunningUntilFailure => self.tick_keep_running(uid),
            Builtin::Timeout => self.tick_timeout(uid),
            Builtin::Delay => self.tick_delay(uid),
            Builtin::RunOnce => self.tick_run_once(uid),
            Builtin::BlackboardCheckInt
            | Builtin::BlackboardCheckDouble
            | Builtin::BlackboardCheckString
            | Builtin::BlackboardCheckBool => self.tick_blackboard_check(uid, b),
            Builtin::Precondition => self.tick_precondition(uid),
            Builtin::LoopInt | Builtin::LoopBool | Builtin::LoopDouble | Builtin::LoopString => self.tick_loop(uid, b),
            Builtin::SkipUnlessUpdated
            | Builtin::WaitValueUpdate => Err(self.err(
                uid,
                format!("{} needs BehaviorTree.CPP scripts or typed queues, which this version of btx does not run", tree.type_name(uid)),
            )),
            Builtin::SubTree
            | Builtin::AlwaysSuccess
            | Builtin::AlwaysFailure
            | Builtin::Script
            | Builtin::ScriptCondition
            | Builtin::SetBlackboard
            | Builtin::UnsetBlackboard
            | Builtin::Sleep
            | Builtin::WasEntryUpdated => unreachable!("leaves and subtrees are ticked elsewhere"),
        }
    }
}

/// `; did you mean "Inverter"?` when `id` misspells a node btx knows.
fn did_you_mean(id: &str) -> String {
    crate::rank::misspelt(id, crate::model::builtins::spellings())
        .map_or(String::new(), |k| format!("; did you mean \"{k}\"?"))
}
