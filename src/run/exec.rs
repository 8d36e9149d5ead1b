//! The executor: ticks a tree exactly as BehaviorTree.CPP 4.10 does
//! (`tickExactlyOnce`), and reports every status change as the library's
//! `StatusChangeLogger` sees it, halts and resets (→ IDLE) included.

mod nav2;

pub use nav2::ROBOT_READINGS;

use super::blackboard::{Blackboard, EntryId};
use super::status::Status;
use crate::model::{Builtin, Kind, PortValue, Tree, Uid};
use serde_json::Value;

/// A node's view of the blackboard, for its scripts.
struct NodeEnv<'a> {
    tree: &'a Tree,
    bb: &'a mut Blackboard,
    scope: crate::model::ScopeId,
    writes: &'a mut Vec<(EntryId, Value)>,
    enums: &'a [(String, i64)],
}

impl NodeEnv<'_> {
    fn entry(&self, name: &str) -> EntryId {
        match name.strip_prefix('@') {
            Some(root) => EntryId {
                scope: 0,
                key: root.to_string(),
            },
            None => self.bb.resolve(self.tree, self.scope, name),
        }
    }
}

impl super::script::Env for NodeEnv<'_> {
    fn get(&self, name: &str) -> Option<Value> {
        self.bb.get(&self.entry(name)).cloned()
    }
    fn set(&mut self, name: &str, v: Value) {
        let e = self.entry(name);
        self.bb.set(&e, v.clone());
        self.writes.push((e, v));
    }
    fn enum_value(&self, name: &str) -> Option<Value> {
        self.enums
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| Value::from(*v))
    }
    fn declared(&self, name: &str) -> bool {
        let e = self.entry(name);
        self.tree.nodes.iter().any(|n| {
            n.ports
                .iter()
                .any(|p| self.bb.port_entry(self.tree, n.scope, &p.value).as_ref() == Some(&e))
        })
    }
}

/// What a leaf's behaviour is asked to do.
pub struct LeafCall<'a> {
    pub tree: &'a Tree,
    pub uid: Uid,
    pub kind: Kind,
    /// `onRunning` (true) or `onStart` (false); conditions are always false.
    pub resumed: bool,
    pub tick: u32,
    bb: &'a mut Blackboard,
    writes: &'a mut Vec<(EntryId, Value)>,
}

impl LeafCall<'_> {
    /// Whether this leaf is one of Nav2's actions that complete in the tick
    /// they start (`model::nav2`): it takes no RUNNING outcome.
    pub fn completes_at_once(&self) -> bool {
        self.kind == Kind::Action
            && crate::model::nav2::at_once(&self.tree.node(self.uid).id, self.tree.release)
                .is_some()
    }

    /// A port's value: its literal, or the blackboard entry it names.
    pub fn input(&self, port: &str) -> Option<Value> {
        let n = self.tree.node(self.uid);
        let p = n.ports.iter().find(|p| p.name == port)?;
        match &p.value {
            PortValue::Literal(s) => Some(Value::from(s.clone())),
            v => {
                let e = self.bb.port_entry(self.tree, n.scope, v)?;
                self.bb.get(&e).cloned()
            }
        }
    }

    /// Ports this leaf writes to a blackboard entry.
    pub fn output_ports(&self) -> Vec<String> {
        self.tree
            .node(self.uid)
            .ports
            .iter()
            .filter(|p| {
                p.value.key().is_some() && p.assumed_direction() != crate::model::Direction::In
            })
            .map(|p| p.name.clone())
            .collect()
    }

    /// Writes a value through a port; ignored for literal ports.
    pub fn write_port(&mut self, port: &str, v: Value) {
        let n = self.tree.node(self.uid);
        let Some(p) = n.ports.iter().find(|p| p.name == port) else {
            return;
        };
        if let Some(e) = self.bb.port_entry(self.tree, n.scope, &p.value) {
            self.bb.set(&e, v.clone());
            self.writes.push((e, v));
        }
    }

    /// Writes a blackboard entry directly (a domain's state variable).
    pub fn write_entry(&mut self, e: EntryId, v: Value) {
        self.bb.set(&e, v.clone());
        self.writes.push((e, v));
    }

    pub fn blackboard(&self) -> &Blackboard {
        self.bb
    }
}

pub struct LeafOutcome {
    pub status: Status,
    /// The action the leaf chose (Love et al.'s d_i), if it chooses.
    pub decision: Option<String>,
}

/// What the leaves of a tree do: a plan, a domain file, a built-in world.
pub trait Leaves {
    fn tick(&mut self, call: &mut LeafCall) -> LeafOutcome;
    /// `onHalted`: the leaf was RUNNING and is halted.
    fn halt(&mut self, _uid: Uid) {}
    /// Blackboard entries the leaves start with (a domain's state).
    fn initial_entries(&self) -> Vec<(EntryId, Value)> {
        Vec::new()
    }
    /// Scripting enums the robot would register (`registerScriptingEnum`),
    /// declared by a plan or a domain: name → value.
    fn enums(&self) -> &[(String, i64)] {
        &[]
    }
    /// Sees every status transition, as a logger would (a replay of a log
    /// follows its position this way).
    fn observe(&mut self, _uid: Uid, _prev: Status, _status: Status) {}
    /// Whether the run is over after a tick that returned `root`: by
    /// default when the root completes; a domain may keep ticking a tree
    /// (a game of several rounds) until a leaf of its own says so.
    fn run_over(&mut self, root: Status) -> bool {
        root != Status::Running
    }
    /// An error the leaves met (a failing script); the run stops on it.
    fn take_error(&mut self) -> Option<crate::source::Located> {
        None
    }
    /// Whether the writes the leaf's last call made, as the leaves gave
    /// them, already hold those of its post-condition scripts (a replay of
    /// a session, which recorded them with the leaf's call): the executor
    /// does not run those scripts again.
    fn post_scripts_recorded(&self, _uid: Uid) -> bool {
        false
    }
}

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
        self.seq += 1;
        let seq = self.seq;
        let wraps = n.builtin == Some(Builtin::RoundRobin) && self.round_robin_wraps(uid);
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
        let own_before = self.rt[(uid - 1) as usize].transitions;
        let (transitions_before, events_before) = (self.tick_transitions, self.events.len());
        let mut s = match self.pre_conditions(uid)? {
            Some(s) => s,
            None => self.tick_node(uid)?,
        };
        if !self.forced.is_empty() {
            let call = self.calls[(uid - 1) as usize];
            let tick = self.tick;
            if let Some(f) = self
                .forced
                .iter()
                .find(|f| f.tick == tick && f.uid == uid && f.call == call)
            {
                s = f.status;
            }
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
            let r = &self.rt[(uid - 1) as usize];
            let record = CallRecord {
                uid,
                call: self.calls[(uid - 1) as usize],
                entry_seq: seq,
                exit_seq: self.seq,
                entry: r.entry.clone(),
                entry_status: r.entry_status,
                returned: s,
                transitions_before,
                transitions_after: self.tick_transitions,
                transitioned: r.transitions != own_before,
                // Only a leaf decides; a control node's call spans all of
                // its subtree's events, which are not searched.
                decision: n
                    .kind
                    .is_leaf()
                    .then(|| {
                        self.events[events_before.min(self.events.len())..]
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
                    })
                    .flatten(),
            };
            self.call_log.push(record);
        }
        Ok(s)
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

    fn tick_leaf(&mut self, uid: Uid) -> R<Status> {
        let n = self.tree.node(uid);
        let prev = self.status(uid);
        self.leaf_called = false;
        if n.kind == Kind::Action && prev.is_completed() {
            // A StatefulActionNode ticked again before a reset keeps its status.
            return Ok(prev);
        }
        let at_once = if n.kind == Kind::Action {
            crate::model::nav2::at_once(&n.id, self.tree.release)
        } else {
            None
        };
        if at_once == Some(true) && prev == Status::Idle {
            self.set_status(uid, Status::Running);
        }
        let mut writes = Vec::new();
        self.leaf_called = true;
        let out = {
            let mut call = LeafCall {
                tree: self.tree,
                uid,
                kind: n.kind,
                resumed: n.kind == Kind::Action && prev == Status::Running,
                tick: self.tick,
                bb: &mut self.bb,
                writes: &mut writes,
            };
            self.leaves.tick(&mut call)
        };
        for (entry, value) in writes {
            self.events.push(Event::Write {
                tick: self.tick,
                uid,
                entry,
                value,
            });
        }
        if let Some(d) = out.decision {
            if out.status == prev {
                self.events.push(Event::Decision {
                    tick: self.tick,
                    uid,
                    decision: d,
                });
            } else {
                self.pending_decision = Some((uid, d));
            }
        }
        if out.status == Status::Idle {
            return Err(self.err(uid, "the leaf returned IDLE"));
        }
        if at_once.is_some() && out.status == Status::Running {
            return Err(self.err(
                uid,
                format!(
                    "the leaf returned RUNNING, but Nav2's {} completes in the tick it starts (nav2_behavior_tree/plugins/action); give it SUCCESS or FAILURE",
                    n.id
                ),
            ));
        }
        Ok(out.status)
    }

    fn tick_builtin_leaf(&mut self, uid: Uid, b: Builtin) -> R<Status> {
        match b {
            Builtin::AlwaysSuccess => Ok(Status::Success),
            Builtin::AlwaysFailure => Ok(Status::Failure),
            Builtin::Sleep => {
                if self.status(uid) == Status::Idle {
                    let ms = self.port_int(uid, &["msec"], None)?;
                    if ms <= 0 {
                        return Ok(Status::Success);
                    }
                    let now = self.now_ms;
                    let r = self.rt(uid);
                    r.deadline = Some(now + ms as u64);
                    r.fired = false;
                    return Ok(Status::Running);
                }
                let r = self.rt(uid);
                if r.fired {
                    r.fired = false;
                    Ok(Status::Success)
                } else {
                    Ok(Status::Running)
                }
            }
            Builtin::SetBlackboard => {
                let value = self
                    .port_str(uid, "value")
                    .ok_or_else(|| self.err(uid, "the port value is missing"))?;
                let n = self.tree.node(uid);
                let key = n
                    .ports
                    .iter()
                    .find(|p| p.name == "output_key")
                    .ok_or_else(|| self.err(uid, "the port output_key is missing"))?;
                let entry = match &key.value {
                    PortValue::Literal(k) => self.bb.resolve(self.tree, n.scope, k),
                    v => self.bb.port_entry(self.tree, n.scope, v).expect("a key"),
                };
                self.write_entry(uid, entry, super::blackboard::typed_literal(&value));
                Ok(Status::Success)
            }
            Builtin::UnsetBlackboard => {
                let n = self.tree.node(uid);
                if let Some(k) = self.port_str(uid, "key") {
                    let e = self.bb.resolve(self.tree, n.scope, &k);
                    self.bb.remove(&e);
                }
                Ok(Status::Success)
            }
            Builtin::Script => {
                let code = self.port_str(uid, "code").unwrap_or_default();
                self.script(uid, &code, "code")?;
                Ok(Status::Success)
            }
            Builtin::ScriptCondition => {
                let code = self.port_str(uid, "code").unwrap_or_default();
                Ok(if self.script_test(uid, &code, "code")? {
                    Status::Success
                } else {
                    Status::Failure
                })
            }
            _ => Err(self.err(
                uid,
                format!(
                    "{} is not run by this version of btx",
                    self.tree.type_name(uid)
                ),
            )),
        }
    }

    // ---- scripts ----

    fn script(&mut self, uid: Uid, code: &str, what: &str) -> R<Value> {
        let tree = self.tree;
        let mut writes = Vec::new();
        let r = {
            let mut env = NodeEnv {
                tree,
                bb: &mut self.bb,
                scope: tree.node(uid).scope,
                writes: &mut writes,
                enums: self.leaves.enums(),
            };
            super::script::run(code, &mut env)
        };
        for (entry, value) in writes {
            self.events.push(Event::Write {
                tick: self.tick,
                uid,
                entry,
                value,
            });
        }
        r.map_err(|e| {
            self.err(
                uid,
                format!("{what}=\"{}\": {e}", crate::text::clip(code, QUOTED_MAX)),
            )
        })
    }

    fn script_test(&mut self, uid: Uid, code: &str, what: &str) -> R<bool> {
        let v = self.script(uid, code, what)?;
        Ok(match v {
            Value::Bool(b) => b,
            Value::Number(n) => n.as_f64().is_some_and(|x| x != 0.0),
            Value::String(s) => !s.is_empty() && s != "false",
            _ => false,
        })
    }

    fn script_attr(&self, uid: Uid, name: &str) -> Option<String> {
        self.tree
            .node(uid)
            .scripts
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v.clone())
    }

    /// `checkPreConditions`: `_failureIf`, `_successIf`, `_skipIf` while the
    /// node is IDLE, `_while` while IDLE or RUNNING.
    fn pre_conditions(&mut self, uid: Uid) -> R<Option<Status>> {
        if self.tree.node(uid).scripts.is_empty() {
            return Ok(None);
        }
        let status = self.status(uid);
        if status == Status::Idle {
            for (attr, result) in [
                ("_failureIf", Status::Failure),
                ("_successIf", Status::Success),
                ("_skipIf", Status::Skipped),
            ] {
                if let Some(code) = self.script_attr(uid, attr) {
                    if self.script_test(uid, &code, attr)? {
                        return Ok(Some(result));
                    }
                }
            }
        }
        if matches!(status, Status::Idle | Status::Running) {
            if let Some(code) = self.script_attr(uid, "_while") {
                if !self.script_test(uid, &code, "_while")? {
                    if status == Status::Running {
                        self.halt_node(uid);
                    }
                    return Ok(Some(Status::Skipped));
                }
            }
        }
        Ok(None)
    }

    /// `_onSuccess`, `_onFailure` and `_post` after a node completes.
    fn post_conditions(&mut self, uid: Uid, s: Status) -> R<()> {
        let which = match s {
            Status::Success => "_onSuccess",
            Status::Failure => "_onFailure",
            _ => return Ok(()),
        };
        for attr in [which, "_post"] {
            if let Some(code) = self.script_attr(uid, attr) {
                self.script(uid, &code, attr)?;
            }
        }
        Ok(())
    }

    fn tick_subtree(&mut self, uid: Uid) -> R<Status> {
        if self.status(uid) == Status::Idle {
            self.set_status(uid, Status::Running);
        }
        let child = self.tree.node(uid).children[0];
        let s = self.exec(child)?;
        if s.is_completed() {
            self.halt_child(child);
        }
        Ok(s)
    }

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

    /// IfThenElse: the condition, then its branch until that completes.
    fn tick_if_then_else(&mut self, uid: Uid) -> R<Status> {
        let tree = self.tree;
        let children = &tree.node(uid).children;
        self.set_status(uid, Status::Running);
        if self.rt(uid).idx == 0 {
            match self.exec(children[0])? {
                Status::Running => return Ok(Status::Running),
                Status::Success => self.rt(uid).idx = 1,
                Status::Failure if children.len() == 3 => self.rt(uid).idx = 2,
                Status::Failure => return Ok(Status::Failure),
                // BehaviorTree.CPP keeps the index at 0 and throws.
                _ => return Err(self.err(uid, "its condition was skipped; BehaviorTree.CPP throws \"Something unexpected happened in IfThenElseNode\"")),
            }
        }
        let i = self.rt(uid).idx;
        let s = self.exec(children[i])?;
        if s == Status::Running {
            return Ok(s);
        }
        self.reset_children(uid);
        self.rt(uid).idx = 0;
        Ok(s)
    }

    /// WhileDoElse: the condition every tick, and the branch it chooses (the other halted).
    fn tick_while_do_else(&mut self, uid: Uid) -> R<Status> {
        let tree = self.tree;
        let children = &tree.node(uid).children;
        self.set_status(uid, Status::Running);
        let c = self.exec(children[0])?;
        let s = match c {
            Status::Running => return Ok(Status::Running),
            Status::Success => {
                if children.len() == 3 {
                    self.halt_child(children[2]);
                }
                self.exec(children[1])?
            }
            Status::Failure if children.len() == 3 => {
                self.halt_child(children[1]);
                self.exec(children[2])?
            }
            Status::Failure => Status::Failure,
            // BehaviorTree.CPP returns IDLE, and setting it throws.
            _ => return Err(self.err(uid, "its condition was skipped; BehaviorTree.CPP throws \"you are not allowed to set manually the status to IDLE\"")),
        };
        if s == Status::Running {
            return Ok(s);
        }
        self.reset_children(uid);
        Ok(s)
    }

    /// Inverter: SUCCESS and FAILURE swapped.
    fn tick_inverter(&mut self, uid: Uid) -> R<Status> {
        let tree = self.tree;
        let children = &tree.node(uid).children;
        self.set_status(uid, Status::Running);
        let s = self.exec(children[0])?;
        Ok(match s {
            Status::Success => {
                self.halt_child(children[0]);
                Status::Failure
            }
            Status::Failure => {
                self.halt_child(children[0]);
                Status::Success
            }
            other => other,
        })
    }

    /// ForceSuccess and ForceFailure: a completed child's status replaced.
    fn tick_force(&mut self, uid: Uid, b: Builtin) -> R<Status> {
        let tree = self.tree;
        let children = &tree.node(uid).children;
        self.set_status(uid, Status::Running);
        let s = self.exec(children[0])?;
        if s.is_completed() {
            self.halt_child(children[0]);
            return Ok(if b == Builtin::ForceSuccess {
                Status::Success
            } else {
                Status::Failure
            });
        }
        Ok(s)
    }

    /// KeepRunningUntilFailure: RUNNING while the child succeeds.
    fn tick_keep_running(&mut self, uid: Uid) -> R<Status> {
        let tree = self.tree;
        let children = &tree.node(uid).children;
        self.set_status(uid, Status::Running);
        let s = self.exec(children[0])?;
        match s {
            Status::Failure => {
                self.halt_child(children[0]);
                Ok(Status::Failure)
            }
            Status::Success => {
                self.halt_child(children[0]);
                Ok(Status::Running)
            }
            // A skipped child leaves the node's own RUNNING.
            Status::Skipped => Ok(Status::Running),
            other => Ok(other),
        }
    }

    /// Timeout: the child halted and FAILURE once `msec` pass.
    fn tick_timeout(&mut self, uid: Uid) -> R<Status> {
        let tree = self.tree;
        let children = &tree.node(uid).children;
        if !self.rt(uid).started {
            let ms = self.port_int(uid, &["msec"], None)?;
            self.start_timer(uid, ms);
            // No timeout at all when msec <= 0.
            self.rt(uid).fired = false;
        }
        if self.rt(uid).fired {
            let r = self.rt(uid);
            r.started = false;
            r.fired = false;
            return Ok(Status::Failure);
        }
        let s = self.exec(children[0])?;
        if s.is_completed() {
            let r = self.rt(uid);
            r.started = false;
            r.deadline = None;
            self.halt_child(children[0]);
        }
        Ok(s)
    }

    /// Delay: the child ticked once `delay_msec` pass.
    fn tick_delay(&mut self, uid: Uid) -> R<Status> {
        let tree = self.tree;
        let children = &tree.node(uid).children;
        if !self.rt(uid).started {
            let ms = self.port_int(uid, &["delay_msec"], None)?;
            self.start_timer(uid, ms);
        }
        if !self.rt(uid).fired {
            return Ok(Status::Running);
        }
        let s = self.exec(children[0])?;
        if s.is_completed() {
            let r = self.rt(uid);
            r.started = false;
            r.fired = false;
            self.halt_child(children[0]);
        }
        Ok(s)
    }

    /// RunOnce: the child's first completion, kept (or skipped after it).
    fn tick_run_once(&mut self, uid: Uid) -> R<Status> {
        let tree = self.tree;
        let children = &tree.node(uid).children;
        let skip = self
            .port_str(uid, "then_skip")
            .is_none_or(|s| s.trim() != "false");
        if self.rt(uid).started {
            return Ok(if skip {
                Status::Skipped
            } else {
                self.rt(uid).cached
            });
        }
        self.set_status(uid, Status::Running);
        let s = self.exec(children[0])?;
        if s.is_completed() {
            let r = self.rt(uid);
            r.started = true;
            r.cached = s;
            self.halt_child(children[0]);
        }
        Ok(s)
    }

    /// BlackboardCheckInt, Double, String and Bool: the child ticked while
    /// the entry equals the value, else `return_on_mismatch`.
    fn tick_blackboard_check(&mut self, uid: Uid, b: Builtin) -> R<Status> {
        let tree = self.tree;
        let children = &tree.node(uid).children;
        let a = self.port_str(uid, "value_A");
        let bv = self.port_str(uid, "value_B");
        let equal = match (a, bv, b) {
            (Some(a), Some(bv), Builtin::BlackboardCheckInt | Builtin::BlackboardCheckDouble) => {
                match (a.trim().parse::<f64>(), bv.trim().parse::<f64>()) {
                    (Ok(x), Ok(y)) => x == y,
                    _ => a == bv,
                }
            }
            (Some(a), Some(bv), _) => a.trim() == bv.trim(),
            _ => false,
        };
        if equal {
            return self.exec(children[0]);
        }
        if self.status(children[0]) == Status::Running {
            self.halt_child(children[0]);
        }
        let ret = self
            .port_str(uid, "return_on_mismatch")
            .unwrap_or_else(|| "FAILURE".into());
        Status::parse(&ret)
            .ok_or_else(|| self.err(uid, format!("return_on_mismatch=\"{ret}\" is not a status")))
    }

    /// Precondition: the child ticked while `if` holds, else the `else` status.
    fn tick_precondition(&mut self, uid: Uid) -> R<Status> {
        let tree = self.tree;
        let children = &tree.node(uid).children;
        let child = children[0];
        let code = self.port_str(uid, "if").unwrap_or_default();
        if self.status(child) == Status::Running || self.script_test(uid, &code, "if")? {
            let s = self.exec(child)?;
            if s.is_completed() {
                self.halt_child(child);
            }
            return Ok(s);
        }
        let otherwise = self
            .port_str(uid, "else")
            .unwrap_or_else(|| "FAILURE".into());
        Status::parse(&otherwise)
            .ok_or_else(|| self.err(uid, format!("else=\"{otherwise}\" is not a status")))
    }

    /// Sequence (`goes_on` = SUCCESS) and Fallback (FAILURE), mirrors of
    /// each other; the Async variants return after a child that completed
    /// at once, so that one child runs per tick.
    fn tick_sequential(&mut self, uid: Uid, asynch: bool, goes_on: Status) -> R<Status> {
        let tree = self.tree;
        let children = &tree.node(uid).children;
        if !self.status(uid).is_active() {
            self.rt(uid).skipped = 0;
        }
        self.set_status(uid, Status::Running);
        while self.rt(uid).idx < children.len() {
            let c = children[self.rt(uid).idx];
            let prev = self.status(c);
            match self.exec(c)? {
                Status::Running => return Ok(Status::Running),
                Status::Skipped => {
                    let r = self.rt(uid);
                    r.idx += 1;
                    r.skipped += 1;
                }
                Status::Idle => unreachable!("exec rejects IDLE"),
                s if s == goes_on => {
                    self.rt(uid).idx += 1;
                    if asynch && prev == Status::Idle && self.rt(uid).idx < children.len() {
                        return Ok(Status::Running);
                    }
                }
                s => {
                    self.reset_children(uid);
                    self.rt(uid).idx = 0;
                    return Ok(s);
                }
            }
        }
        // The count starts again once the node completes: a node that
        // returned SKIPPED stays RUNNING, and ticked again it counts anew.
        let all_skipped = self.rt(uid).skipped == children.len();
        self.reset_children(uid);
        let r = self.rt(uid);
        r.idx = 0;
        r.skipped = 0;
        Ok(if all_skipped {
            Status::Skipped
        } else {
            goes_on
        })
    }

    fn tick_sequence_with_memory(&mut self, uid: Uid) -> R<Status> {
        let tree = self.tree;
        let children = &tree.node(uid).children;
        if !self.status(uid).is_active() {
            self.rt(uid).skipped = 0;
        }
        self.set_status(uid, Status::Running);
        while self.rt(uid).idx < children.len() {
            let i = self.rt(uid).idx;
            let prev = self.status(children[i]);
            match self.exec(children[i])? {
                Status::Running => return Ok(Status::Running),
                Status::Failure => {
                    // The index is kept: the next tick resumes at the failed child.
                    for &c in &children[i..] {
                        self.halt_child(c);
                    }
                    return Ok(Status::Failure);
                }
                Status::Success => {
                    self.rt(uid).idx += 1;
                    if self.rt(uid).idx < children.len() && self.wakes_up(prev) {
                        return Ok(Status::Running);
                    }
                }
                Status::Skipped => {
                    let r = self.rt(uid);
                    r.idx += 1;
                    r.skipped += 1;
                }
                Status::Idle => unreachable!("exec rejects IDLE"),
            }
        }
        let all_skipped = self.rt(uid).skipped == children.len();
        self.reset_children(uid);
        let r = self.rt(uid);
        r.idx = 0;
        r.skipped = 0;
        Ok(if all_skipped {
            Status::Skipped
        } else {
            Status::Success
        })
    }

    /// ReactiveSequence (`goes_on` = SUCCESS) and ReactiveFallback (FAILURE).
    fn tick_reactive(&mut self, uid: Uid, goes_on: Status) -> R<Status> {
        let tree = self.tree;
        let children = &tree.node(uid).children;
        if self.status(uid) == Status::Idle {
            self.rt(uid).idx = 0;
        }
        self.set_status(uid, Status::Running);
        let mut all_skipped = true;
        for (i, &c) in children.iter().enumerate() {
            let s = self.exec(c)?;
            all_skipped &= s == Status::Skipped;
            match s {
                Status::Running => {
                    for (j, &other) in children.iter().enumerate() {
                        if j != i {
                            self.halt_child(other);
                        }
                    }
                    if self.rt(uid).idx == 0 {
                        self.rt(uid).idx = i + 1;
                    }
                    return Ok(Status::Running);
                }
                Status::Skipped => self.halt_child(c),
                s if s == goes_on => {}
                s => {
                    self.reset_children(uid);
                    return Ok(s);
                }
            }
        }
        self.reset_children(uid);
        Ok(if all_skipped {
            Status::Skipped
        } else {
            goes_on
        })
    }

    fn tick_parallel(&mut self, uid: Uid) -> R<Status> {
        let tree = self.tree;
        let children = &tree.node(uid).children;
        let n = children.len() as i64;
        let v3 = self.tree.version == crate::model::Version::V3;
        let success = self.port_int(
            uid,
            &["success_count", "success_threshold"],
            Some(if v3 { n } else { -1 }),
        )?;
        let failure = self.port_int(uid, &["failure_count", "failure_threshold"], Some(1))?;
        let threshold = |t: i64| if t < 0 { (n + t + 1).max(0) } else { t };
        let (need_s, need_f) = (threshold(success), threshold(failure));
        if n < need_s || n < need_f {
            return Err(self.err(
                uid,
                format!(
                    "{n} children cannot reach the thresholds (success {need_s}, failure {need_f})"
                ),
            ));
        }
        // Skips are counted within the tick (BehaviorTree.CPP's local
        // count): a child skipped in an earlier tick is ticked again.
        self.rt(uid).skipped = 0;
        if self.rt(uid).completed.len() != children.len() {
            self.rt(uid).completed = vec![false; children.len()];
        }
        self.set_status(uid, Status::Running);
        for (i, &c) in children.iter().enumerate() {
            if !self.rt(uid).completed[i] {
                match self.exec(c)? {
                    Status::Skipped => self.rt(uid).skipped += 1,
                    Status::Success => {
                        let r = self.rt(uid);
                        r.completed[i] = true;
                        r.successes += 1;
                    }
                    Status::Failure => {
                        let r = self.rt(uid);
                        r.completed[i] = true;
                        r.failures += 1;
                    }
                    _ => {}
                }
            }
            let r = self.rt(uid);
            let (s, f, k) = (r.successes as i64, r.failures as i64, r.skipped as i64);
            if s >= need_s || (success < 0 && s + k >= need_s) {
                self.clear_parallel(uid);
                self.reset_children(uid);
                return Ok(Status::Success);
            }
            if n - f < need_s || f == need_f {
                self.clear_parallel(uid);
                self.reset_children(uid);
                return Ok(Status::Failure);
            }
        }
        Ok(if self.rt(uid).skipped == children.len() {
            Status::Skipped
        } else {
            Status::Running
        })
    }

    fn tick_parallel_all(&mut self, uid: Uid) -> R<Status> {
        let tree = self.tree;
        let children = &tree.node(uid).children;
        let n = children.len() as i64;
        let max_failures = self.port_int(uid, &["max_failures"], Some(1))?;
        let threshold = if max_failures < 0 {
            (n + max_failures + 1).max(0)
        } else {
            max_failures
        };
        if n < threshold {
            return Err(self.err(
                uid,
                format!("{n} children cannot reach max_failures {threshold}"),
            ));
        }
        if self.rt(uid).completed.len() != children.len() {
            self.rt(uid).completed = vec![false; children.len()];
        }
        self.set_status(uid, Status::Running);
        let mut skipped = 0;
        for (i, &c) in children.iter().enumerate() {
            if self.rt(uid).completed[i] {
                continue;
            }
            match self.exec(c)? {
                Status::Success => self.rt(uid).completed[i] = true,
                Status::Failure => {
                    let r = self.rt(uid);
                    r.completed[i] = true;
                    r.failures += 1;
                }
                Status::Skipped => skipped += 1,
                _ => {}
            }
        }
        if skipped == children.len() {
            return Ok(Status::Skipped);
        }
        let done = self.rt(uid).completed.iter().filter(|c| **c).count();
        if skipped + done >= children.len() {
            self.reset_children(uid);
            let failures = self.rt(uid).failures as i64;
            self.clear_parallel(uid);
            return Ok(if failures >= threshold {
                Status::Failure
            } else {
                Status::Success
            });
        }
        Ok(Status::Running)
    }

    fn tick_try_catch(&mut self, uid: Uid) -> R<Status> {
        let tree = self.tree;
        let children = &tree.node(uid).children;
        let catch = *children.last().expect("TryCatch has children");
        let body = &children[..children.len() - 1];
        if !self.status(uid).is_active() {
            self.rt(uid).skipped = 0;
        }
        self.set_status(uid, Status::Running);
        if !self.rt(uid).started {
            while self.rt(uid).idx < body.len() {
                let c = body[self.rt(uid).idx];
                match self.exec(c)? {
                    Status::Running => return Ok(Status::Running),
                    Status::Failure => {
                        for &b in body {
                            self.halt_child(b);
                        }
                        let r = self.rt(uid);
                        r.idx = 0;
                        r.started = true;
                        break;
                    }
                    Status::Success => self.rt(uid).idx += 1,
                    Status::Skipped => {
                        let r = self.rt(uid);
                        r.idx += 1;
                        r.skipped += 1;
                    }
                    Status::Idle => unreachable!("exec rejects IDLE"),
                }
            }
            if !self.rt(uid).started {
                let all_skipped = self.rt(uid).skipped == body.len();
                self.reset_children(uid);
                self.rt(uid).idx = 0;
                return Ok(if all_skipped {
                    Status::Skipped
                } else {
                    Status::Success
                });
            }
        }
        match self.exec(catch)? {
            Status::Running => Ok(Status::Running),
            _ => {
                self.reset_children(uid);
                self.rt(uid).started = false;
                Ok(Status::Failure)
            }
        }
    }

    fn tick_switch(&mut self, uid: Uid, cases: usize) -> R<Status> {
        let tree = self.tree;
        let children = &tree.node(uid).children;
        let mut matched = cases;
        if let Some(var) = self.port_str(uid, "variable") {
            for i in 0..cases {
                if let Some(v) = self.port_str(uid, &format!("case_{}", i + 1)) {
                    if v.trim() == var.trim() {
                        matched = i;
                        break;
                    }
                }
            }
        }
        let running = self.rt(uid).idx;
        if running != 0 && running - 1 != matched {
            self.halt_child(children[running - 1]);
        }
        let s = self.exec(children[matched])?;
        match s {
            Status::Skipped => self.rt(uid).idx = 0,
            Status::Running => self.rt(uid).idx = matched + 1,
            _ => {
                self.reset_children(uid);
                self.rt(uid).idx = 0;
            }
        }
        Ok(s)
    }

    /// BehaviorTree.CPP 4's wake-up path (`requiresWakeUp() && prev_status
    /// == IDLE`): a node whose child started and completed within one tick
    /// returns RUNNING instead of going on, and goes on at the next tick.
    /// Every tree a v4 factory builds has a wake-up instance; v3 has none.
    fn wakes_up(&self, prev: Status) -> bool {
        self.tree.version == crate::model::Version::V4 && prev == Status::Idle
    }

    /// A Retry or Repeat that ticks its child this often within one tick
    /// is making no progress (v3 has no wake-up path to end the loop): the
    /// run stops with an error instead of looping forever.
    fn check_progress(&self, uid: Uid, child: Uid) -> R<()> {
        let n = self.calls[(child - 1) as usize];
        if n >= CHILD_TICKS_IN_A_TICK_MAX {
            return Err(self.err(
                uid,
                format!(
                    "ticked its child {} {n} times within tick {} without the tick ending; a loop that makes no progress is stopped (at most {CHILD_TICKS_IN_A_TICK_MAX} ticks of a child within one tick)",
                    self.tree.description(child),
                    self.tick
                ),
            ));
        }
        Ok(())
    }

    fn tick_retry(&mut self, uid: Uid) -> R<Status> {
        let child = self.tree.node(uid).children[0];
        let max = self.port_int(uid, &["num_attempts"], None)?;
        self.set_status(uid, Status::Running);
        let mut do_loop = self.rt(uid).count < max || max == -1;
        while do_loop {
            self.check_progress(uid, child)?;
            let prev = self.status(child);
            match self.exec(child)? {
                Status::Success => {
                    self.rt(uid).count = 0;
                    self.halt_child(child);
                    return Ok(Status::Success);
                }
                Status::Failure => {
                    let r = self.rt(uid);
                    r.count += 1;
                    do_loop = r.count < max || max == -1;
                    self.halt_child(child);
                    if do_loop && self.wakes_up(prev) {
                        return Ok(Status::Running);
                    }
                }
                Status::Running => return Ok(Status::Running),
                Status::Skipped => {
                    self.halt_child(child);
                    return Ok(Status::Skipped);
                }
                Status::Idle => unreachable!("exec rejects IDLE"),
            }
        }
        self.rt(uid).count = 0;
        Ok(Status::Failure)
    }

    /// BehaviorTree.CPP 4's `LoopNode<T>` (`loop_node.h`): each tick pops
    /// the next value of `queue` into `value` and ticks the child once,
    /// RUNNING until the queue is empty, then `if_empty` (SUCCESS by
    /// default); a child's FAILURE fails it. A queue written in the tree
    /// (`queue="1;2;3"`) is copied afresh each time the node starts; one on
    /// the blackboard is a typed `std::deque` the robot's code puts there,
    /// which btx cannot make.
    fn tick_loop(&mut self, uid: Uid, b: Builtin) -> R<Status> {
        let tree = self.tree;
        let n = tree.node(uid);
        let child = n.children[0];
        let queue = match n.ports.iter().find(|p| p.name == "queue").map(|p| &p.value) {
            Some(PortValue::Literal(q)) => q.clone(),
            Some(v) => {
                return Err(self.err(
                    uid,
                    format!(
                        "{} reads its queue from the blackboard ({}): a typed std::deque the robot's code puts there, which btx cannot make; write the values in the tree to run it, queue=\"1;2;3\"",
                        tree.type_name(uid),
                        v.to_xml()
                    ),
                ))
            }
            None => return Err(self.err(uid, "the port queue is missing")),
        };
        let items: Vec<&str> = queue.split(';').filter(|x| !x.is_empty()).collect();
        if self.status(uid) == Status::Idle {
            let r = self.rt(uid);
            r.idx = 0;
            r.started = false;
        }
        let child_running = self.rt(uid).started;
        if !child_running {
            let Some(raw) = items.get(self.rt(uid).idx).copied() else {
                let e = self
                    .port_str(uid, "if_empty")
                    .unwrap_or_else(|| "SUCCESS".into());
                return Status::parse(&e)
                    .ok_or_else(|| self.err(uid, format!("if_empty=\"{e}\" is not a status")));
            };
            let v = match b {
                Builtin::LoopInt => raw.trim().parse::<i64>().map(Value::from).ok(),
                Builtin::LoopDouble => raw.trim().parse::<f64>().ok().map(Value::from),
                Builtin::LoopBool => match raw.trim() {
                    "true" | "TRUE" | "True" | "1" => Some(Value::Bool(true)),
                    "false" | "FALSE" | "False" | "0" => Some(Value::Bool(false)),
                    _ => None,
                },
                _ => Some(Value::from(raw)),
            }
            .ok_or_else(|| {
                self.err(
                    uid,
                    format!(
                        "queue item \"{raw}\" is not a {}",
                        tree.type_name(uid)
                            .trim_start_matches("Loop")
                            .to_lowercase()
                    ),
                )
            })?;
            self.rt(uid).idx += 1;
            self.write_output(uid, "value", v);
        }
        self.set_status(uid, Status::Running);
        let s = self.exec(child)?;
        self.rt(uid).started = s == Status::Running;
        if s.is_completed() {
            self.halt_child(child);
        }
        Ok(if s == Status::Failure {
            Status::Failure
        } else {
            Status::Running
        })
    }

    /// `setOutput`: writes `v` where output port `port` points (a literal
    /// port is no entry: nothing is written).
    fn write_output(&mut self, uid: Uid, port: &str, v: Value) {
        let tree = self.tree;
        let n = tree.node(uid);
        let Some(p) = n.ports.iter().find(|p| p.name == port) else {
            return;
        };
        if let Some(entry) = self.bb.port_entry(tree, n.scope, &p.value) {
            self.write_entry(uid, entry, v);
        }
    }

    /// A node writes an entry: the blackboard, and the event of the run.
    fn write_entry(&mut self, uid: Uid, entry: EntryId, v: Value) {
        self.bb.set(&entry, v.clone());
        self.events.push(Event::Write {
            tick: self.tick,
            uid,
            entry,
            value: v,
        });
    }

    fn tick_repeat(&mut self, uid: Uid) -> R<Status> {
        let child = self.tree.node(uid).children[0];
        let max = self.port_int(uid, &["num_cycles"], None)?;
        self.set_status(uid, Status::Running);
        let mut do_loop = self.rt(uid).count < max || max == -1;
        let mut all_skipped = true;
        while do_loop {
            self.check_progress(uid, child)?;
            let prev = self.status(child);
            let s = self.exec(child)?;
            all_skipped &= s == Status::Skipped;
            match s {
                Status::Success => {
                    let r = self.rt(uid);
                    r.count += 1;
                    do_loop = r.count < max || max == -1;
                    self.halt_child(child);
                    if do_loop && self.wakes_up(prev) {
                        return Ok(Status::Running);
                    }
                }
                Status::Failure => {
                    self.rt(uid).count = 0;
                    self.halt_child(child);
                    return Ok(Status::Failure);
                }
                Status::Running => return Ok(Status::Running),
                Status::Skipped => {
                    self.halt_child(child);
                    return Ok(Status::Skipped);
                }
                Status::Idle => unreachable!("exec rejects IDLE"),
            }
        }
        self.rt(uid).count = 0;
        Ok(if all_skipped {
            Status::Skipped
        } else {
            Status::Success
        })
    }
}

/// `; did you mean "Inverter"?` when `id` misspells a node btx knows.
fn did_you_mean(id: &str) -> String {
    crate::rank::misspelt(id, crate::model::builtins::spellings())
        .map_or(String::new(), |k| format!("; did you mean \"{k}\"?"))
}
