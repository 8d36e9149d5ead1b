//! The explanation model of one tick (Love et al. §5.2): a DAG over the
//! execution E_i, return status r_i and decision d_i of every node and the
//! temporal copies X^(k) of the state variables, built by Algorithms 1–5, 7
//! and 8, with the structural functions of Algorithms 9–13. Leaf functions
//! are the domain file's own (the simulator runs the same ones); control
//! flow beyond Sequence and Fallback follows the executor, whose state at
//! the start of the tick says where composites resume.

use super::facts::TickFacts;
use crate::model::{Builtin, Kind, PortValue, Tree, Uid};
use crate::run::blackboard::EntryId;
use crate::run::domain::{str_key, value_key, Domain, LeafFn, State, VarType};
use crate::run::Status;
use crate::source::Located;
use petgraph::graph::{DiGraph, NodeIndex};
use rustc_hash::FxHashMap;
use serde_json::Value;
use std::collections::HashSet;
use std::sync::Arc;

pub type VarId = usize;

/// What a variable of the model stands for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum VarKind {
    Executed(Uid),
    Status(Uid),
    Decision(Uid),
    /// The attempts (cycles) a RetryUntilSuccessful (Repeat) had spent
    /// before its first attempt modelled in the tick.
    Attempts(Uid),
    /// Copy `copy` (from 0, within the tick) of domain variable `var`.
    State {
        var: usize,
        copy: u32,
    },
}

/// A RetryUntilSuccessful's or Repeat's last attempt in a model.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AttemptLoop {
    /// The status that makes it try again.
    pub again: Status,
    /// Attempts used before that attempt.
    pub spent: i64,
    /// Attempts at most (−1: no limit).
    pub max: i64,
    /// Whether the attempt's copy takes the wake-up path.
    pub wakes: bool,
    /// The attempt's copy of the child.
    pub last: Uid,
}

/// A value of a variable.
#[derive(Debug, Clone, PartialEq)]
pub enum Val {
    Bool(bool),
    Status(Status),
    /// An action name; `None` is the null action.
    Action(Option<String>),
    Data(Value),
}

impl Val {
    fn is_true(&self) -> bool {
        matches!(self, Val::Bool(true))
    }

    fn status(&self) -> Status {
        match self {
            Val::Status(s) => *s,
            _ => Status::Idle,
        }
    }

    /// A key for memoising leaf functions on their inputs (a first cache
    /// in front of the domain's: a hit here builds no state and takes no
    /// lock).
    fn key(&self, out: &mut Vec<u8>) {
        match self {
            Val::Bool(b) => out.extend_from_slice(&[10, u8::from(*b)]),
            Val::Status(s) => out.extend_from_slice(&[11, s.code()]),
            Val::Action(None) => out.push(12),
            Val::Action(Some(a)) => {
                out.push(13);
                str_key(a, out);
            }
            Val::Data(v) => value_key(v, out),
        }
    }
}

/// How a control node decides which child runs next and what it returns.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Flow {
    /// Sequence (`cont` = SUCCESS) or Fallback (FAILURE), resuming at
    /// `start`; the Async variants return RUNNING after a child that
    /// completed in its first tick.
    Sequential {
        cont: Status,
        start: usize,
        asynch: bool,
    },
    Reactive {
        cont: Status,
    },
    Parallel {
        need_s: i64,
        need_f: i64,
        any_s: bool,
    },
    ParallelAll {
        threshold: i64,
    },
    /// IfThenElse and WhileDoElse: a condition, then one branch; `start` is
    /// the branch an IfThenElse resumes (0: the condition first).
    Branch {
        start: usize,
    },
    /// A decorator that maps its child's status.
    Map(Mapping),
    /// Nav2's PipelineSequence: every child from the first each tick; a
    /// child RUNNING before `last` (the furthest reached) lets the next run.
    Pipeline {
        last: usize,
    },
    /// Nav2's RoundRobin: from child `start`, each in turn (wrapping round)
    /// until one does not fail, `failed` of them having failed before.
    RoundRobin {
        start: usize,
        failed: usize,
    },
    /// Nav2's RecoveryNode in a tick where it ticks each child at most
    /// once: from child `start`, the recovery after a failure while fewer
    /// than `retries` recoveries (`count` spent) have run. A recovery that
    /// succeeds sends it back to its first child within the tick, which the
    /// model does not follow (`Model::opaque`).
    Recovery {
        start: usize,
        count: i64,
        retries: i64,
    },
    /// Children ticked or not by what the executor saw (timers, scripts,
    /// blackboard values): the recorded choice is exogenous.
    Gated,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Mapping {
    Same,
    Invert,
    ForceSuccess,
    ForceFailure,
    KeepRunning,
    /// RetryUntilSuccessful (`again` = FAILURE) or Repeat (SUCCESS), out of
    /// `max` attempts or cycles (−1: no limit). Its children are the copies
    /// of its child, one per attempt (`causal::attempts`); the attempts
    /// spent before the first are its `Attempts` variable. A copy started
    /// in the tick takes BehaviorTree.CPP 4's wake-up path: another attempt
    /// waits for the next tick and the node returns RUNNING.
    Loop {
        again: Status,
        max: i64,
    },
}

#[derive(Debug, Clone)]
enum Func {
    /// E of the root: always ticked.
    Root,
    /// No parents: the factual value.
    Exo,
    ExecChild {
        parent: Uid,
        index: usize,
    },
    LeafStatus {
        uid: Uid,
        leaf: Option<usize>,
    },
    CompositeStatus {
        uid: Uid,
    },
    Decision {
        uid: Uid,
        leaf: usize,
    },
    Copy {
        var: usize,
        prev: Option<VarId>,
        sparents: Vec<(usize, VarId)>,
        writers: Vec<Uid>,
    },
}

#[derive(Debug, Clone)]
pub struct VarInfo {
    pub kind: VarKind,
    /// Every value the variable can take (empty: not enumerable).
    pub range: Vec<Val>,
    /// Whether the search may intervene on it.
    pub intervene: bool,
    func: Func,
}

/// The explanation model of one tick of a session.
pub struct Model {
    pub tree: Tree,
    pub domain: Option<Arc<Domain>>,
    pub facts: TickFacts,
    pub vars: Vec<VarInfo>,
    pub graph: DiGraph<VarId, ()>,
    pub parents: Vec<Vec<VarId>>,
    /// What each variable's function reads: its parents and, for a copy a
    /// leaf writes, the leaf's inputs (Algorithm 13 runs p_i on the inputs
    /// of d_i, which reach the copy only through d_i's edge).
    deps: Vec<Vec<VarId>>,
    topo: Vec<VarId>,
    pub topo_pos: Vec<usize>,
    e_of: Vec<VarId>,
    r_of: Vec<VarId>,
    d_of: Vec<Option<VarId>>,
    flows: Vec<Flow>,
    leaf_of: Vec<Option<usize>>,
    /// The copies each leaf reads, by uid − 1.
    inputs_of: Vec<Vec<(usize, VarId)>>,
    /// Of those, the ones each of its functions reads (by `LeafFn`): the
    /// memo keys and the states its functions see.
    reads_of: Vec<[Vec<(usize, VarId)>; 3]>,
    /// Per domain variable, its copies in order.
    pub copies: Vec<Vec<VarId>>,
    /// Per leaf (domain order), the copy counts τ after it (Alg. 3).
    tau_after: Vec<(Uid, Vec<u32>)>,
    /// Values with no intervention.
    pub fact: Vec<Val>,
    /// Each node's place in the tree's pre-order, by uid − 1.
    pre_pos: Vec<usize>,
    /// Edges added beyond Algorithms 1–8 for control flow the paper does
    /// not cover (resumed composites, Parallel, branches, gates).
    pub extension_edges: usize,
    /// Per uid − 1 of the model's tree: the attempts variable of a loop.
    a_of: Vec<Option<VarId>>,
    /// Per uid − 1: `Some` for the copies of a loop's child.
    copy_of: Vec<Option<super::attempts::Copy>>,
    /// Per uid − 1: attempts of a loop no copy stands for.
    folded: Vec<i64>,
    session_len: usize,
}

fn status_range(kind: Kind) -> Vec<Val> {
    let mut r = vec![Val::Status(Status::Success), Val::Status(Status::Failure)];
    if kind != Kind::Condition {
        r.insert(0, Val::Status(Status::Running));
    }
    r.push(Val::Status(Status::Idle));
    r
}

/// The statuses a built-in node can return, where they are fewer than
/// its kind allows: no explanation may suppose a Script failing, a
/// ForceSuccess failing or an AlwaysFailure succeeding. A node with
/// pre- or post-condition scripts may be made to return anything.
fn returns(node: &crate::model::Node) -> Option<&'static [Status]> {
    use Status::{Failure, Running, Success};
    if !node.scripts.is_empty() {
        return None;
    }
    Some(match node.builtin? {
        Builtin::AlwaysSuccess
        | Builtin::Script
        | Builtin::SetBlackboard
        | Builtin::UnsetBlackboard => &[Success],
        Builtin::AlwaysFailure => &[Failure],
        Builtin::Sleep => &[Running, Success],
        Builtin::ForceSuccess => &[Running, Success],
        Builtin::ForceFailure => &[Running, Failure],
        Builtin::KeepRunningUntilFailure => &[Running, Failure],
        _ => return None,
    })
}

fn state_range(ty: &VarType) -> Vec<Val> {
    match ty {
        VarType::Bool => vec![Val::Data(Value::Bool(true)), Val::Data(Value::Bool(false))],
        VarType::Int { min, max } => (*min..=*max)
            .take(10_000)
            .map(|i| Val::Data(Value::from(i)))
            .collect(),
        VarType::Cat { values } => values
            .iter()
            .map(|v| Val::Data(Value::from(v.clone())))
            .collect(),
        VarType::Float { min, max, grid } => {
            let n = (*grid).max(2);
            (0..n)
                .map(|i| {
                    let x = min + (max - min) * i as f64 / (n - 1) as f64;
                    Val::Data(Value::from((x * 1e10).round() / 1e10))
                })
                .collect()
        }
        VarType::Any => Vec::new(),
    }
}

fn literal_int(tree: &Tree, uid: Uid, names: &[&str], default: i64) -> i64 {
    names
        .iter()
        .find_map(|name| literal_port(tree, uid, name).ok().flatten())
        .unwrap_or(default)
}

/// A port's integer as written in the tree: `Ok(None)` when absent,
/// `Err` when it is a blackboard entry or not a number (the model cannot
/// know its value).
fn literal_port(tree: &Tree, uid: Uid, name: &str) -> Result<Option<i64>, ()> {
    match tree.node(uid).ports.iter().find(|p| p.name == name) {
        None => Ok(None),
        Some(p) => match &p.value {
            PortValue::Literal(s) => s.trim().parse().map(Some).map_err(|_| ()),
            _ => Err(()),
        },
    }
}

/// Nav2's RecoveryNode in the tick: a `Flow::Recovery` when it ticked each
/// child at most once and never went back from its recovery to its first
/// child; otherwise its choices are the recorded ones (`Flow::Gated`).
fn recovery_flow(tree: &Tree, uid: Uid, facts: &TickFacts) -> Flow {
    let kids = &tree.node(uid).children;
    let f = &facts.flows[uid as usize - 1];
    let Ok(retries) = literal_port(tree, uid, "number_of_retries") else {
        return Flow::Gated;
    };
    if kids.len() != 2 || f.idx > 1 {
        return Flow::Gated;
    }
    let calls = |c: Uid| facts.calls[c as usize - 1];
    let looped = calls(kids[0]) > 1
        || calls(kids[1]) > 1
        || (f.idx == 1 && facts.ticked[kids[0] as usize - 1]);
    if looped {
        return Flow::Gated;
    }
    Flow::Recovery {
        start: f.idx,
        count: f.count,
        retries: retries.unwrap_or(1),
    }
}

fn flow_of(tree: &Tree, uid: Uid, f: &crate::run::Flow) -> Flow {
    let n = tree.node(uid);
    let seq = |cont, asynch| Flow::Sequential {
        cont,
        start: f.idx,
        asynch,
    };
    if n.kind == Kind::SubTree {
        return Flow::Map(Mapping::Same);
    }
    match n.builtin {
        Some(Builtin::Sequence) => seq(Status::Success, false),
        // A child that starts and succeeds within a tick wakes the tree up
        // for the next (BehaviorTree.CPP 4), as in the Async composites.
        Some(Builtin::SequenceWithMemory) => {
            seq(Status::Success, tree.version == crate::model::Version::V4)
        }
        Some(Builtin::AsyncSequence) => seq(Status::Success, true),
        Some(Builtin::Fallback) => seq(Status::Failure, false),
        Some(Builtin::AsyncFallback) => seq(Status::Failure, true),
        Some(Builtin::ReactiveSequence) => Flow::Reactive {
            cont: Status::Success,
        },
        Some(Builtin::ReactiveFallback) => Flow::Reactive {
            cont: Status::Failure,
        },
        Some(Builtin::Parallel) => {
            let k = n.children.len() as i64;
            let v3 = tree.version == crate::model::Version::V3;
            let s = literal_int(
                tree,
                uid,
                &["success_count", "success_threshold"],
                if v3 { k } else { -1 },
            );
            let fl = literal_int(tree, uid, &["failure_count", "failure_threshold"], 1);
            let th = |t: i64| if t < 0 { (k + t + 1).max(0) } else { t };
            Flow::Parallel {
                need_s: th(s),
                need_f: th(fl),
                any_s: s < 0,
            }
        }
        Some(Builtin::ParallelAll) => {
            let k = n.children.len() as i64;
            let m = literal_int(tree, uid, &["max_failures"], 1);
            Flow::ParallelAll {
                threshold: if m < 0 { (k + m + 1).max(0) } else { m },
            }
        }
        Some(Builtin::IfThenElse) => Flow::Branch { start: f.idx },
        Some(Builtin::WhileDoElse) => Flow::Branch { start: 0 },
        Some(Builtin::Inverter) => Flow::Map(Mapping::Invert),
        Some(Builtin::ForceSuccess) => Flow::Map(Mapping::ForceSuccess),
        Some(Builtin::ForceFailure) => Flow::Map(Mapping::ForceFailure),
        Some(Builtin::KeepRunningUntilFailure) => Flow::Map(Mapping::KeepRunning),
        Some(Builtin::RetryUntilSuccessful | Builtin::Repeat) => Flow::Map(Mapping::Same),
        Some(Builtin::PipelineSequence) => Flow::Pipeline { last: f.idx },
        Some(Builtin::RoundRobin) if f.idx < n.children.len() => Flow::RoundRobin {
            start: f.idx,
            failed: f.failures.min(n.children.len()),
        },
        _ => Flow::Gated,
    }
}

/// A decorator the model gates (which child it ticks is the recorded
/// choice) whose status is then its ticked child's, as each source has it.
fn passes_ticked_child(b: Option<Builtin>) -> bool {
    matches!(
        b,
        Some(
            Builtin::Timeout
                | Builtin::Delay
                | Builtin::RunOnce
                | Builtin::Precondition
                | Builtin::Switch(_)
                | Builtin::SkipUnlessUpdated
                | Builtin::WaitValueUpdate
                | Builtin::BlackboardCheckInt
                | Builtin::BlackboardCheckDouble
                | Builtin::BlackboardCheckString
                | Builtin::BlackboardCheckBool
                | Builtin::RateController
                | Builtin::DistanceController
                | Builtin::SpeedController
                | Builtin::GoalUpdatedController
                | Builtin::GoalUpdater
                | Builtin::SingleTrigger
        )
    )
}

/// The script attributes that can decide a node's status before it runs.
const PRE_CONDITIONS: [&str; 4] = ["_skipIf", "_successIf", "_failureIf", "_while"];

/// The script attributes that write the blackboard after a node runs.
const POST_CONDITIONS: [&str; 4] = ["_onSuccess", "_onFailure", "_post", "_onHalted"];

fn has_script(n: &crate::model::Node, attrs: &[&str]) -> bool {
    n.scripts.iter().any(|(k, _)| attrs.contains(&k.as_str()))
}

/// A node whose status or choice of child a script or a blackboard entry
/// decides.
fn reads_blackboard(n: &crate::model::Node) -> bool {
    has_script(n, &PRE_CONDITIONS)
        || matches!(
            n.builtin,
            Some(
                Builtin::ScriptCondition
                    | Builtin::Precondition
                    | Builtin::Switch(_)
                    | Builtin::BlackboardCheckInt
                    | Builtin::BlackboardCheckDouble
                    | Builtin::BlackboardCheckString
                    | Builtin::BlackboardCheckBool
                    | Builtin::WasEntryUpdated
                    | Builtin::SkipUnlessUpdated
                    | Builtin::WaitValueUpdate
                    | Builtin::DistanceController
                    | Builtin::SpeedController
                    | Builtin::GoalUpdatedController
                    | Builtin::PathLongerOnApproach
            )
        )
}

/// A node that writes the blackboard when it runs or completes.
fn writes_blackboard(n: &crate::model::Node) -> bool {
    has_script(n, &POST_CONDITIONS)
        || matches!(
            n.builtin,
            Some(
                Builtin::Script
                    | Builtin::SetBlackboard
                    | Builtin::UnsetBlackboard
                    | Builtin::LoopInt
                    | Builtin::LoopDouble
                    | Builtin::LoopString
                    | Builtin::LoopBool
                    | Builtin::GoalUpdater
            )
        )
}

/// A gated decorator that ticks its child in the tick it starts from IDLE
/// (Timeout arms its timer, Nav2's controllers take their first reading),
/// so that the model follows it when a change starts it.
fn starts_its_child(b: Option<Builtin>) -> bool {
    matches!(
        b,
        Some(
            Builtin::Timeout
                | Builtin::RateController
                | Builtin::DistanceController
                | Builtin::SpeedController
                | Builtin::GoalUpdater
        )
    )
}

/// A RetryUntilSuccessful's or Repeat's control flow.
fn loop_of(tree: &Tree, uid: Uid) -> Option<Flow> {
    let k = super::attempts::loop_kind(tree, uid)?;
    Some(Flow::Map(Mapping::Loop {
        again: k.again,
        max: k.max,
    }))
}

fn continues(s: Status, cont: Status) -> bool {
    s == cont || s == Status::Skipped
}

/// A model error: the domain or the record does not fit the tree.
fn model_err(msg: String) -> Located {
    Located::file(std::path::Path::new("explanation model"), msg)
}

struct Builder {
    vars: Vec<VarInfo>,
    edges: HashSet<(VarId, VarId)>,
    edge_list: Vec<(VarId, VarId)>,
    extension: usize,
}

impl Builder {
    fn var(&mut self, kind: VarKind, range: Vec<Val>, intervene: bool, func: Func) -> VarId {
        self.vars.push(VarInfo {
            kind,
            range,
            intervene,
            func,
        });
        self.vars.len() - 1
    }

    fn edge(&mut self, a: VarId, b: VarId) -> bool {
        if self.edges.insert((a, b)) {
            self.edge_list.push((a, b));
            true
        } else {
            false
        }
    }

    fn extra(&mut self, a: VarId, b: VarId) {
        if self.edge(a, b) {
            self.extension += 1;
        }
    }
}

/// The tree's variables and edges (Algorithm 7, and btx's control flow
/// beyond it): E, r and d per node.
struct Structure {
    e_of: Vec<VarId>,
    r_of: Vec<VarId>,
    d_of: Vec<Option<VarId>>,
    leaf_of: Vec<Option<usize>>,
}

/// The state's temporal copies (Algorithms 3–5 and 8).
struct StateCopies {
    copies: Vec<Vec<VarId>>,
    inputs_of: Vec<Vec<(usize, VarId)>>,
    tau_after: Vec<(Uid, Vec<u32>)>,
}

/// The variables as a graph, in an order to evaluate them in.
struct Assembled {
    graph: DiGraph<VarId, ()>,
    parents: Vec<Vec<VarId>>,
    deps: Vec<Vec<VarId>>,
    topo: Vec<VarId>,
    topo_pos: Vec<usize>,
}

/// Stage "attempts": how each control node goes on in the tick, from where
/// it resumed, and how Retry and Repeat spend attempts within the tick.
fn control_flows(tree: &Tree, facts: &TickFacts) -> Vec<Flow> {
    (1..=tree.len() as Uid)
        .map(|u| {
            if decided_by_precondition(tree, facts, u) {
                return Flow::Gated;
            }
            if tree.node(u).builtin == Some(Builtin::RecoveryNode) {
                return recovery_flow(tree, u, facts);
            }
            loop_of(tree, u).unwrap_or_else(|| flow_of(tree, u, &facts.flows[u as usize - 1]))
        })
        .collect()
}

/// A node whose pre-condition script (`_skipIf`, `_successIf`,
/// `_failureIf`, `_while`) decided its status in the tick: it was ticked
/// and none of its children was. What it returned is the recorded choice
/// (the script reads the blackboard, which the model does not hold).
fn decided_by_precondition(tree: &Tree, facts: &TickFacts, u: Uid) -> bool {
    let n = tree.node(u);
    !n.children.is_empty()
        && has_script(n, &PRE_CONDITIONS)
        && facts.ticked[u as usize - 1]
        && n.children.iter().all(|&c| !facts.ticked[c as usize - 1])
}

/// Stage "structure": Algorithm 7's variables and structural edges.
fn structure(
    tree: &Tree,
    domain: &Option<Arc<Domain>>,
    order: &[Uid],
    flows: &[Flow],
    copy_of: &[Option<super::attempts::Copy>],
    b: &mut Builder,
) -> Structure {
    let n = tree.len();
    let mut e_of = vec![usize::MAX; n];
    let mut r_of = vec![usize::MAX; n];
    let mut d_of = vec![None; n];
    let mut leaf_of = vec![None; n];
    // Algorithm 7: variables and structural edges.
    for &u in order {
        let node = tree.node(u);
        let i = u as usize - 1;
        let is_leaf = node.kind.is_leaf();
        let leaf = if is_leaf && node.builtin.is_none() {
            // A copy is the leaf it copies (its name says the attempt).
            let origin = copy_of.get(i).copied().flatten().map_or(u, |c| c.origin);
            domain.as_ref().and_then(|d| d.leaf_for(tree, origin))
        } else {
            None
        };
        leaf_of[i] = leaf;
        let e_func = match node.parent {
            None => Func::Root,
            Some(p) => Func::ExecChild {
                parent: p,
                index: tree
                    .node(p)
                    .children
                    .iter()
                    .position(|&c| c == u)
                    .unwrap_or(0),
            },
        };
        e_of[i] = b.var(
            VarKind::Executed(u),
            vec![Val::Bool(true), Val::Bool(false)],
            true,
            e_func,
        );
        let r_func = if is_leaf {
            Func::LeafStatus { uid: u, leaf }
        } else {
            Func::CompositeStatus { uid: u }
        };
        // A built-in leaf other than Sleep is synchronous: BehaviorTree.CPP
        // throws if it returns RUNNING, so no explanation may suppose it.
        let mut range = status_range(node.kind);
        if is_leaf && node.builtin.is_some_and(|b| b != Builtin::Sleep) {
            range.retain(|x| *x != Val::Status(Status::Running));
        }
        if let Some(can) = returns(node) {
            range.retain(|x| matches!(x, Val::Status(s) if *s == Status::Idle || can.contains(s)));
        }
        r_of[i] = b.var(VarKind::Status(u), range, true, r_func);
        if let (Some(l), Kind::Action) = (leaf, node.kind) {
            let d = domain.as_ref().expect("a leaf has a domain");
            let mut range: Vec<Val> = d.leaves[l]
                .actions
                .iter()
                .map(|a| Val::Action(Some(a.clone())))
                .collect();
            range.push(Val::Action(None));
            d_of[i] = Some(b.var(
                VarKind::Decision(u),
                range,
                true,
                Func::Decision { uid: u, leaf: l },
            ));
        }
    }
    for &u in order {
        let node = tree.node(u);
        let i = u as usize - 1;
        b.edge(e_of[i], r_of[i]);
        if let Some(d) = d_of[i] {
            b.edge(e_of[i], d);
            b.edge(d, r_of[i]);
        }
        for &c in &node.children {
            b.edge(r_of[c as usize - 1], r_of[i]);
        }
        let Some(p) = node.parent else { continue };
        let siblings = &tree.node(p).children;
        let k = siblings.iter().position(|&c| c == u).unwrap_or(0);
        let ep = e_of[p as usize - 1];
        // A RoundRobin ticks its children in turn from where it stopped:
        // each depends on those before it in that turn, not in the tree.
        if let Flow::RoundRobin { start, .. } = flows[p as usize - 1] {
            let n = siblings.len();
            let pos = (k + n - start) % n;
            let at = |j: usize| r_of[siblings[(start + j) % n] as usize - 1];
            if pos == 0 {
                b.edge(ep, e_of[i]);
            } else {
                b.edge(at(pos - 1), e_of[i]);
                b.extra(ep, e_of[i]);
                for j in 0..pos - 1 {
                    b.extra(at(j), e_of[i]);
                }
            }
            continue;
        }
        if k == 0 {
            b.edge(ep, e_of[i]);
        } else {
            b.edge(r_of[siblings[k - 1] as usize - 1], e_of[i]);
        }
        match flows[p as usize - 1] {
            Flow::Sequential { start, .. } | Flow::Branch { start } if start == k && k > 0 => {
                b.extra(ep, e_of[i])
            }
            Flow::Parallel { .. } | Flow::ParallelAll { .. } if k > 0 => {
                b.extra(ep, e_of[i]);
                for &s in &siblings[..k - 1] {
                    b.extra(r_of[s as usize - 1], e_of[i]);
                }
            }
            Flow::Branch { .. } if k == 2 => b.extra(r_of[siblings[0] as usize - 1], e_of[i]),
            Flow::Gated | Flow::Map(_) | Flow::Pipeline { .. } | Flow::Recovery { .. } if k > 0 => {
                b.extra(ep, e_of[i])
            }
            _ => {}
        }
    }

    Structure {
        e_of,
        r_of,
        d_of,
        leaf_of,
    }
}

/// Stage "attempts", its variables: each RetryUntilSuccessful's and
/// Repeat's attempts spent before its first copy in the tick (the count it
/// resumed with, and attempts no copy stands for). It decides what the loop
/// returns and whether each further copy of its child is ticked.
fn attempt_counts(
    tree: &Tree,
    facts: &TickFacts,
    flows: &[Flow],
    folded: &[i64],
    st: &Structure,
    b: &mut Builder,
) -> Vec<Option<VarId>> {
    let mut a_of = vec![None; tree.len()];
    for (i, f) in flows.iter().enumerate() {
        let Flow::Map(Mapping::Loop { max, .. }) = *f else {
            continue;
        };
        let u = i as Uid + 1;
        let spent = facts.flows[i].count + folded[i];
        // Every count the node can resume with, when there are few. A loop
        // that started afresh in the tick (or whose last call did: inside
        // another loop's child) used none before: that is not a cause
        // anything could have changed.
        let resumed = facts.start[i] == Status::Running && facts.calls[i] == 1;
        let (range, intervene) = if resumed && (1..=ATTEMPTS_RANGE_MAX).contains(&max) {
            ((0..max).map(|k| Val::Data(Value::from(k))).collect(), true)
        } else {
            (vec![Val::Data(Value::from(spent))], false)
        };
        let a = b.var(VarKind::Attempts(u), range, intervene, Func::Exo);
        b.edge(a, st.r_of[i]);
        for &c in tree.node(u).children.iter().skip(1) {
            b.edge(a, st.e_of[c as usize - 1]);
        }
        a_of[i] = Some(a);
    }
    a_of
}

/// A loop's attempts variable has one value per count up to this many
/// attempts; past it (or with no limit) it is not intervened on.
const ATTEMPTS_RANGE_MAX: i64 = 100;

/// Stage "domain": the state's temporal copies, read and written by the
/// leaves in tree order (Algorithms 3–5 and 8).
fn state_copies(
    tree: &Tree,
    domain: &Option<Arc<Domain>>,
    order: &[Uid],
    st: &Structure,
    b: &mut Builder,
) -> StateCopies {
    let n = tree.len();
    let Structure {
        e_of,
        r_of,
        d_of,
        leaf_of,
    } = st;
    // Algorithms 3–5 and 8: the state's temporal copies.
    let mut copies: Vec<Vec<VarId>> = Vec::new();
    let mut inputs_of: Vec<Vec<(usize, VarId)>> = vec![Vec::new(); n];
    let mut tau_after = Vec::new();
    if let Some(d) = &domain {
        let nv = d.vars.len();
        copies = vec![Vec::new(); nv];
        let mut tau = vec![0u32; nv];
        // Ancestors in the state graph, nearest first, each once.
        let ancestors: Vec<Vec<usize>> = (0..nv)
            .map(|x| {
                let mut seen = vec![false; nv];
                let mut out = Vec::new();
                let mut stack: Vec<usize> = d.vars[x].parents.clone();
                while let Some(a) = stack.pop() {
                    if !seen[a] {
                        seen[a] = true;
                        out.push(a);
                        stack.extend(d.vars[a].parents.iter().copied());
                    }
                }
                out.sort_unstable();
                out
            })
            .collect();
        let ensure = |b: &mut Builder, copies: &mut Vec<Vec<VarId>>, x: usize, k: u32| {
            while copies[x].len() <= k as usize {
                let c = copies[x].len() as u32;
                let v = &d.vars[x];
                let id = b.var(
                    VarKind::State { var: x, copy: c },
                    state_range(&v.ty),
                    v.intervene && v.ty != VarType::Any,
                    Func::Copy {
                        var: x,
                        prev: None,
                        sparents: Vec::new(),
                        writers: Vec::new(),
                    },
                );
                copies[x].push(id);
            }
            copies[x][k as usize]
        };
        for x in 0..nv {
            ensure(b, &mut copies, x, 0);
        }
        for &u in order {
            let Some(l) = leaf_of[u as usize - 1] else {
                continue;
            };
            let i = u as usize - 1;
            let def = &d.leaves[l];
            let mut touched: Vec<usize> = Vec::new();
            for &x in &def.inputs {
                let xc = ensure(b, &mut copies, x, tau[x]);
                let mut set = ancestors[x].clone();
                set.push(x);
                for &a in &ancestors[x] {
                    ensure(b, &mut copies, a, tau[a]);
                }
                for &y in &set {
                    for &p in &d.vars[y].parents {
                        if set.contains(&p) {
                            let (pc, yc) = (copies[p][tau[p] as usize], copies[y][tau[y] as usize]);
                            if b.edge(pc, yc) {
                                if let Func::Copy { sparents, .. } = &mut b.vars[yc].func {
                                    sparents.push((p, pc));
                                }
                            }
                        }
                    }
                }
                b.edge(xc, r_of[i]);
                if let Some(dv) = d_of[i] {
                    b.edge(xc, dv);
                }
                inputs_of[u as usize - 1].push((x, xc));
                touched.extend(set);
            }
            touched.sort_unstable();
            touched.dedup();
            for x in touched {
                tau[x] += 1;
            }
            for &y in &def.outputs {
                let yc = ensure(b, &mut copies, y, tau[y]);
                b.edge(e_of[i], yc);
                if let Some(dv) = d_of[i] {
                    b.edge(dv, yc);
                }
                if let Func::Copy { writers, .. } = &mut b.vars[yc].func {
                    if !writers.contains(&u) {
                        writers.push(u);
                    }
                }
            }
            tau_after.push((u, tau.clone()));
        }
        carry_forward(d, &copies, b);
    }

    StateCopies {
        copies,
        inputs_of,
        tau_after,
    }
}

/// Algorithm 8: top-level variables carry their value from copy to copy;
/// a copy nothing computes or writes is exogenous.
fn carry_forward(d: &Domain, copies: &[Vec<VarId>], b: &mut Builder) {
    // Algorithm 8: top-level variables carry their value forward.
    // A copy of a derived variable that a leaf writes and nothing
    // recomputes carries its previous copy too (btx's addition).
    for (x, cs) in copies.iter().enumerate() {
        let top = d.vars[x].parents.is_empty();
        for k in 1..cs.len() {
            let (a, c) = (cs[k - 1], cs[k]);
            let needs = match &b.vars[c].func {
                Func::Copy {
                    sparents, writers, ..
                } => top || (sparents.is_empty() && !writers.is_empty()),
                _ => false,
            };
            if needs {
                if top {
                    b.edge(a, c);
                } else {
                    b.extra(a, c);
                }
                if let Func::Copy { prev, .. } = &mut b.vars[c].func {
                    *prev = Some(a);
                }
            }
        }
    }
    for cs in copies {
        for &c in cs {
            if let Func::Copy {
                prev: None,
                sparents,
                writers,
                ..
            } = &b.vars[c].func
            {
                if sparents.is_empty() && writers.is_empty() {
                    b.vars[c].func = Func::Exo;
                }
            }
        }
    }
}

/// The graph of the variables, its topological order, and what each
/// variable's function reads.
fn assemble(b: &Builder, inputs_of: &[Vec<(usize, VarId)>]) -> Result<Assembled, Located> {
    let nvars = b.vars.len();
    let mut graph = DiGraph::<VarId, ()>::with_capacity(nvars, b.edge_list.len());
    for v in 0..nvars {
        graph.add_node(v);
    }
    let mut parents = vec![Vec::new(); nvars];
    for &(a, c) in &b.edge_list {
        graph.add_edge(NodeIndex::new(a), NodeIndex::new(c), ());
        parents[c].push(a);
    }
    let topo: Vec<VarId> = petgraph::algo::toposort(&graph, None)
        .map_err(|c| {
            model_err(format!(
                "the explanation model has a cycle through variable {}",
                c.node_id().index()
            ))
        })?
        .into_iter()
        .map(|n| n.index())
        .collect();
    let mut deps = parents.clone();
    for (v, info) in b.vars.iter().enumerate() {
        if let Func::Copy { writers, .. } = &info.func {
            for w in writers {
                for &(_, c) in &inputs_of[*w as usize - 1] {
                    if !deps[v].contains(&c) {
                        deps[v].push(c);
                    }
                }
            }
        }
    }
    let mut topo_pos = vec![0; nvars];
    for (i, &v) in topo.iter().enumerate() {
        topo_pos[v] = i;
    }
    Ok(Assembled {
        graph,
        parents,
        deps,
        topo,
        topo_pos,
    })
}

impl Model {
    /// Builds the model of the tick in `facts`, stage by stage: the control
    /// flow of the tick, the tree's structure, the domain's state copies,
    /// the graph, then the facts (every variable's value with no change).
    /// Without a domain, the model has the tree's structure only and leaf
    /// outcomes are exogenous.
    pub fn build(
        tree: &Tree,
        domain: Option<Arc<Domain>>,
        facts: TickFacts,
    ) -> Result<Model, Located> {
        let session_len = tree.len();
        let super::attempts::Unrolled {
            tree: unrolled,
            facts,
            copy_of,
            folded,
        } = super::attempts::unroll(tree, facts);
        let tree = &unrolled;
        let n = tree.len();
        let order = tree.preorder();
        let mut pre_pos = vec![0; n];
        for (i, &u) in order.iter().enumerate() {
            pre_pos[u as usize - 1] = i;
        }
        let mut b = Builder {
            vars: Vec::new(),
            edges: HashSet::new(),
            edge_list: Vec::new(),
            extension: 0,
        };
        let flows = control_flows(tree, &facts);
        let st = structure(tree, &domain, &order, &flows, &copy_of, &mut b);
        let a_of = attempt_counts(tree, &facts, &flows, &folded, &st, &mut b);
        let sc = state_copies(tree, &domain, &order, &st, &mut b);
        let g = assemble(&b, &sc.inputs_of)?;
        let leaf_of = st.leaf_of;
        let inputs_of = sc.inputs_of;
        let reads_of = inputs_of
            .iter()
            .zip(&leaf_of)
            .map(|(inputs, l)| {
                let def = domain.as_ref().zip(*l).map(|(d, l)| &d.leaves[l]);
                [LeafFn::Status, LeafFn::Decide, LeafFn::Effect].map(|f| {
                    inputs
                        .iter()
                        .filter(|(x, _)| def.is_some_and(|def| def.reads(f).contains(x)))
                        .copied()
                        .collect()
                })
            })
            .collect();
        let mut m = Model {
            tree: unrolled,
            domain,
            facts,
            vars: b.vars,
            graph: g.graph,
            parents: g.parents,
            deps: g.deps,
            topo: g.topo,
            topo_pos: g.topo_pos,
            e_of: st.e_of,
            r_of: st.r_of,
            d_of: st.d_of,
            flows,
            leaf_of,
            inputs_of,
            reads_of,
            copies: sc.copies,
            tau_after: sc.tau_after,
            fact: Vec::new(),
            pre_pos,
            extension_edges: b.extension,
            a_of,
            copy_of,
            folded,
            session_len,
        };
        // Stage "facts": every variable's value with no intervention.
        m.fact = m.evaluate_all()?;
        Ok(m)
    }

    pub fn edge_count(&self) -> usize {
        self.graph.edge_count()
    }

    pub fn e(&self, uid: Uid) -> VarId {
        self.e_of[uid as usize - 1]
    }

    pub fn r(&self, uid: Uid) -> VarId {
        self.r_of[uid as usize - 1]
    }

    pub fn d(&self, uid: Uid) -> Option<VarId> {
        self.d_of[uid as usize - 1]
    }

    /// The copy of a domain variable that holds its value once the leaves
    /// that ran up to `pos` (transitions applied) have run.
    pub fn copy_at(&self, var: usize, pos: u32) -> Option<VarId> {
        let copies = self.copies.get(var)?;
        let mut k = 0u32;
        for (u, tau) in &self.tau_after {
            if self.facts.done_at.get(u).is_some_and(|&p| p <= pos) {
                k = k.max(tau[var]);
            }
        }
        let k = (k as usize).min(copies.len() - 1);
        Some(copies[k])
    }

    /// The leaf after which copy `k` (> 0) of a domain variable holds: the
    /// first leaf, in tree order, to move its count to `k` (Alg. 3 moves
    /// counts over every leaf, ticked or not).
    pub fn copy_writer(&self, var: usize, k: u32) -> Option<Uid> {
        self.tau_after
            .iter()
            .filter(|(_, tau)| tau.get(var).is_some_and(|&t| t >= k))
            .map(|(u, _)| (self.pre_pos[*u as usize - 1], *u))
            .min()
            .map(|(_, u)| u)
    }

    /// The leaves that write copy `k` of a domain variable.
    pub fn copy_writers(&self, var: usize, k: u32) -> Vec<Uid> {
        match self
            .copies
            .get(var)
            .and_then(|cs| cs.get(k as usize))
            .map(|&c| &self.vars[c].func)
        {
            Some(Func::Copy { writers, .. }) => writers.clone(),
            _ => Vec::new(),
        }
    }

    /// The copies of other domain variables that copy `k` of a derived
    /// variable is computed from, as (variable, copy).
    pub fn copy_sources(&self, var: usize, k: u32) -> Vec<(usize, u32)> {
        match self
            .copies
            .get(var)
            .and_then(|cs| cs.get(k as usize))
            .map(|&c| &self.vars[c].func)
        {
            Some(Func::Copy { sparents, .. }) => sparents
                .iter()
                .filter_map(|&(p, pc)| match self.vars[pc].kind {
                    VarKind::State { copy, .. } => Some((p, copy)),
                    _ => None,
                })
                .collect(),
            _ => Vec::new(),
        }
    }

    /// The leaves that read copy `k` of a domain variable.
    pub fn copy_readers(&self, var: usize, k: u32) -> Vec<Uid> {
        let Some(&c) = self.copies.get(var).and_then(|cs| cs.get(k as usize)) else {
            return Vec::new();
        };
        self.inputs_of
            .iter()
            .enumerate()
            .filter(|(_, ins)| ins.iter().any(|&(_, x)| x == c))
            .map(|(i, _)| i as Uid + 1)
            .collect()
    }

    /// Values of every variable, computed from the exogenous ones.
    fn evaluate_all(&self) -> Result<Vec<Val>, Located> {
        self.evaluate_with(&[])
    }

    /// Do(v = x for each (v, x)), every other variable recomputed from its
    /// parents, none skipped: the reference the incremental evaluator must
    /// agree with.
    pub fn evaluate_with(&self, dos: &[(VarId, Val)]) -> Result<Vec<Val>, Located> {
        let mut vals = vec![Val::Bool(false); self.vars.len()];
        let mut memo = Memo::default();
        for &v in &self.topo {
            vals[v] = match dos.iter().find(|(d, _)| *d == v) {
                Some((_, x)) => x.clone(),
                None => self.eval(v, &vals, &mut memo)?,
            };
        }
        Ok(vals)
    }

    /// The factual value of an exogenous variable.
    fn exogenous(&self, v: VarId) -> Val {
        match self.vars[v].kind {
            VarKind::State { var, copy } => {
                let d = self.domain.as_ref().expect("state variables have a domain");
                let e = EntryId {
                    scope: 0,
                    key: d.vars[var].name.clone(),
                };
                let src = if copy == 0 {
                    &self.facts.state_start
                } else {
                    &self.facts.state_end
                };
                Val::Data(
                    src.get(&e)
                        .cloned()
                        .unwrap_or_else(|| d.vars[var].initial.clone()),
                )
            }
            VarKind::Executed(u) => Val::Bool(self.facts.ticked[u as usize - 1]),
            VarKind::Status(u) => Val::Status(self.facts.returned[u as usize - 1]),
            VarKind::Decision(u) => Val::Action(self.facts.decisions[u as usize - 1].clone()),
            VarKind::Attempts(u) => {
                let i = u as usize - 1;
                Val::Data(Value::from(self.facts.flows[i].count + self.folded[i]))
            }
        }
    }

    fn leaf_state(&self, f: LeafFn, uid: Uid, vals: &[Val]) -> State {
        let d = self.domain.as_ref().expect("a domain");
        let mut s: State = vec![Value::Null; d.vars.len()];
        for &(x, c) in &self.reads_of[uid as usize - 1][f as usize] {
            if let Val::Data(v) = &vals[c] {
                s[x] = v.clone();
            }
        }
        s
    }

    /// The memo key of a leaf function on its current inputs, built in
    /// the memo's buffer (no allocation once it has grown).
    fn memo_key(&self, f: LeafFn, uid: Uid, vals: &[Val], extra: Option<&Val>, k: &mut Vec<u8>) {
        k.clear();
        k.push(f as u8);
        k.extend_from_slice(&uid.to_le_bytes());
        for &(_, c) in &self.reads_of[uid as usize - 1][f as usize] {
            vals[c].key(k);
        }
        if let Some(x) = extra {
            x.key(k);
        }
    }

    fn action_of(&self, uid: Uid, vals: &[Val]) -> Option<String> {
        match self.d_of[uid as usize - 1].map(|d| &vals[d]) {
            Some(Val::Action(a)) => a.clone(),
            _ => None,
        }
    }

    /// F_v (Algorithm 9) on the current values of v's parents.
    fn eval(&self, v: VarId, vals: &[Val], memo: &mut Memo) -> Result<Val, Located> {
        Ok(match &self.vars[v].func {
            Func::Root => Val::Bool(true),
            Func::Exo => self.exogenous(v),
            Func::ExecChild { parent, index } => Val::Bool(self.exec_child(*parent, *index, vals)),
            Func::LeafStatus { uid, leaf } => {
                if !vals[self.e(*uid)].is_true() {
                    return Ok(Val::Status(Status::Idle));
                }
                match leaf {
                    None => Val::Status(self.facts.outcome[*uid as usize - 1]),
                    Some(l) => {
                        let dv = self.d(*uid).map(|d| &vals[d]);
                        self.memo_key(LeafFn::Status, *uid, vals, dv, &mut memo.buf);
                        if let Some(x) = memo.status.get(&memo.buf[..]) {
                            return Ok(Val::Status(*x));
                        }
                        let action = self.action_of(*uid, vals);
                        let d = self.domain.as_ref().expect("a domain");
                        let state = self.leaf_state(LeafFn::Status, *uid, vals);
                        let s = d.status(*l, &state, &action)?;
                        memo.status.insert(memo.buf.clone(), s);
                        Val::Status(s)
                    }
                }
            }
            Func::CompositeStatus { uid } => Val::Status(self.composite(*uid, vals)),
            Func::Decision { uid, leaf } => {
                if !vals[self.e(*uid)].is_true() {
                    return Ok(Val::Action(None));
                }
                self.memo_key(LeafFn::Decide, *uid, vals, None, &mut memo.buf);
                if let Some(x) = memo.decide.get(&memo.buf[..]) {
                    return Ok(Val::Action(x.clone()));
                }
                let d = self.domain.as_ref().expect("a domain");
                let a = d.decide(*leaf, &self.leaf_state(LeafFn::Decide, *uid, vals))?;
                memo.decide.insert(memo.buf.clone(), a.clone());
                Val::Action(a)
            }
            Func::Copy {
                var,
                prev,
                sparents,
                writers,
            } => {
                let d = self.domain.as_ref().expect("a domain");
                let mut value = if let Some(p) = prev {
                    vals[*p].clone()
                } else if !sparents.is_empty() {
                    let key = &mut memo.buf;
                    key.clear();
                    key.push(3);
                    key.extend_from_slice(&(*var as u32).to_le_bytes());
                    for &(_, c) in sparents {
                        vals[c].key(key);
                    }
                    match memo.derive.get(&memo.buf[..]) {
                        Some(x) => Val::Data(x.clone()),
                        None => {
                            let mut s: State = vec![Value::Null; d.vars.len()];
                            for &(x, c) in sparents {
                                if let Val::Data(val) = &vals[c] {
                                    s[x] = val.clone();
                                }
                            }
                            let x = d.derive(*var, &s)?;
                            memo.derive.insert(memo.buf.clone(), x.clone());
                            Val::Data(x)
                        }
                    }
                } else {
                    self.exogenous(v)
                };
                for &w in writers {
                    if !vals[self.e(w)].is_true() {
                        continue;
                    }
                    let l = self.leaf_of[w as usize - 1].expect("writers have domain leaves");
                    let dv = self.d(w).map(|d| &vals[d]);
                    self.memo_key(LeafFn::Effect, w, vals, dv, &mut memo.buf);
                    let effect = match memo.effect.get(&memo.buf[..]) {
                        Some(e) => Arc::clone(e),
                        None => {
                            let action = self.action_of(w, vals);
                            let state = self.leaf_state(LeafFn::Effect, w, vals);
                            let e = Arc::new(d.effect(l, &state, &action)?);
                            memo.effect.insert(memo.buf.clone(), Arc::clone(&e));
                            e
                        }
                    };
                    if let Some((_, x)) = effect.iter().find(|(x, _)| x == var) {
                        value = Val::Data(x.clone());
                    }
                }
                value
            }
        })
    }

    fn r_val(&self, uid: Uid, vals: &[Val]) -> Status {
        vals[self.r(uid)].status()
    }

    /// Whether child `k` of `p` is ticked, as the executor ticks it.
    fn exec_child(&self, p: Uid, k: usize, vals: &[Val]) -> bool {
        let kids = &self.tree.node(p).children;
        let ep = vals[self.e(p)].is_true();
        let left = |j: usize| self.r_val(kids[j], vals);
        let fi = p as usize - 1;
        match self.flows[fi] {
            Flow::Sequential {
                cont,
                start,
                asynch,
            } => {
                if k < start {
                    false
                } else if k == start {
                    ep
                } else {
                    continues(left(k - 1), cont)
                        && (!asynch
                            || self.facts.start[kids[k - 1] as usize - 1] == Status::Running)
                }
            }
            Flow::Reactive { cont } => {
                if k == 0 {
                    ep
                } else {
                    continues(left(k - 1), cont)
                }
            }
            Flow::Parallel { .. } | Flow::ParallelAll { .. } => {
                let done = &self.facts.flows[fi].completed;
                if !ep || done.get(k).copied().unwrap_or(false) {
                    return false;
                }
                // Ticked unless the Parallel already decided before child k.
                !matches!(self.parallel(p, vals, k), Some(s) if s != Status::Running)
            }
            Flow::Branch { start } => {
                if start > 0 {
                    k == start && ep
                } else {
                    match k {
                        0 => ep,
                        1 => left(0) == Status::Success,
                        _ => left(0) == Status::Failure,
                    }
                }
            }
            Flow::Map(Mapping::Loop { again, max }) => {
                if k == 0 {
                    return ep;
                }
                let spent = self.attempts_val(p, vals) + k as i64;
                ep && left(k - 1) == again && (spent < max || max == -1) && !self.wakes(kids[k - 1])
            }
            Flow::Map(_) => ep,
            Flow::Pipeline { last } => {
                ep && (k == 0
                    || match left(k - 1) {
                        Status::Success => true,
                        Status::Running => k - 1 < last,
                        _ => false,
                    })
            }
            Flow::RoundRobin { start, failed } => {
                let n = kids.len();
                let pos = (k + n - start) % n;
                ep && pos < n - failed && (0..pos).all(|j| left((start + j) % n) == Status::Failure)
            }
            Flow::Recovery {
                start,
                count,
                retries,
            } => {
                ep && match (start, k) {
                    (0, 0) | (1, 1) => true,
                    (0, 1) => left(0) == Status::Failure && count < retries,
                    // Back to the first child after a recovery: not followed.
                    _ => false,
                }
            }
            Flow::Gated => {
                ep && if self.facts.ticked[fi] {
                    self.facts.ticked[kids[k] as usize - 1]
                } else {
                    k == 0
                        || matches!(self.tree.node(p).builtin, Some(Builtin::Switch(_)))
                            && k + 1 == kids.len()
                }
            }
        }
    }

    /// A Parallel's status after its children before `upto` (all if
    /// `upto` = their number): `None` while undecided.
    fn parallel(&self, p: Uid, vals: &[Val], upto: usize) -> Option<Status> {
        let kids = &self.tree.node(p).children;
        let fi = p as usize - 1;
        let f = &self.facts.flows[fi];
        let n = kids.len() as i64;
        let (mut s, mut fl, mut sk) = (f.successes as i64, f.failures as i64, f.skipped as i64);
        let mut done: Vec<bool> = f.completed.clone();
        done.resize(kids.len(), false);
        for (i, &c) in kids.iter().enumerate().take(upto) {
            if !done[i] {
                match self.r_val(c, vals) {
                    Status::Success => {
                        s += 1;
                        done[i] = true
                    }
                    Status::Failure => {
                        fl += 1;
                        done[i] = true
                    }
                    Status::Skipped => sk += 1,
                    Status::Idle => return Some(Status::Idle),
                    Status::Running => {}
                }
            }
            if let Flow::Parallel {
                need_s,
                need_f,
                any_s,
            } = self.flows[fi]
            {
                if s >= need_s || (any_s && s + sk >= need_s) {
                    return Some(Status::Success);
                }
                if n - fl < need_s || fl == need_f {
                    return Some(Status::Failure);
                }
            }
        }
        if let Flow::ParallelAll { threshold } = self.flows[fi] {
            if upto < kids.len() {
                return None;
            }
            if sk == n {
                return Some(Status::Skipped);
            }
            let finished = done.iter().filter(|d| **d).count() as i64;
            if sk + finished >= n {
                return Some(if fl >= threshold {
                    Status::Failure
                } else {
                    Status::Success
                });
            }
            return Some(Status::Running);
        }
        if upto < kids.len() {
            None
        } else if sk == n {
            Some(Status::Skipped)
        } else {
            Some(Status::Running)
        }
    }

    /// r of a control node (Algorithm 11, and the executor's other nodes).
    fn composite(&self, uid: Uid, vals: &[Val]) -> Status {
        if !vals[self.e(uid)].is_true() {
            return Status::Idle;
        }
        let kids = &self.tree.node(uid).children;
        let fi = uid as usize - 1;
        let r = |j: usize| self.r_val(kids[j], vals);
        match self.flows[fi] {
            Flow::Sequential {
                cont,
                start,
                asynch,
            } => {
                let mut skipped = self.facts.flows[fi].skipped;
                if self.facts.start[fi].is_active() {
                    skipped = skipped.min(start);
                } else {
                    skipped = 0;
                }
                for k in start..kids.len() {
                    match r(k) {
                        Status::Skipped => skipped += 1,
                        s if s == cont => {
                            let fresh = self.facts.start[kids[k] as usize - 1] != Status::Running;
                            if asynch && fresh && k + 1 < kids.len() {
                                return Status::Running;
                            }
                        }
                        s => return s,
                    }
                }
                if skipped == kids.len() {
                    Status::Skipped
                } else {
                    cont
                }
            }
            Flow::Reactive { cont } => {
                let mut all_skipped = true;
                for k in 0..kids.len() {
                    match r(k) {
                        Status::Skipped => {}
                        s if s == cont => all_skipped = false,
                        s => return s,
                    }
                }
                if all_skipped {
                    Status::Skipped
                } else {
                    cont
                }
            }
            Flow::Parallel { .. } | Flow::ParallelAll { .. } => self
                .parallel(uid, vals, kids.len())
                .unwrap_or(Status::Running),
            Flow::Branch { start } => {
                if start > 0 {
                    return r(start);
                }
                match r(0) {
                    Status::Success => r(1),
                    Status::Failure if kids.len() == 3 => r(2),
                    Status::Failure => Status::Failure,
                    other => other,
                }
            }
            Flow::Map(Mapping::Loop { again, max }) => {
                let spent = self.attempts_val(uid, vals);
                for (k, &kid) in kids.iter().enumerate() {
                    let s = self.r_val(kid, vals);
                    if s != again {
                        return s;
                    }
                    let more = spent + k as i64 + 1 < max || max == -1;
                    if !more {
                        return if again == Status::Failure {
                            Status::Failure
                        } else {
                            Status::Success
                        };
                    }
                    if self.wakes(kid) {
                        return Status::Running;
                    }
                }
                // The node would tick its child again within the tick, in
                // an attempt the model has no copy for (see
                // causal::verify::retry_next).
                again
            }
            Flow::Map(m) => {
                let s = r(0);
                match (m, s) {
                    (_, Status::Idle) => Status::Idle,
                    (Mapping::Invert, Status::Success) => Status::Failure,
                    (Mapping::Invert, Status::Failure) => Status::Success,
                    (Mapping::ForceSuccess, x) if x.is_completed() => Status::Success,
                    (Mapping::ForceFailure, x) if x.is_completed() => Status::Failure,
                    (Mapping::KeepRunning, Status::Success | Status::Skipped) => Status::Running,
                    _ => s,
                }
            }
            Flow::Pipeline { last } => {
                for k in 0..kids.len() {
                    match r(k) {
                        Status::Success => {}
                        Status::Running if k < last => {}
                        s => return s,
                    }
                }
                Status::Success
            }
            Flow::RoundRobin { start, failed } => {
                let n = kids.len();
                for j in 0..n - failed {
                    match r((start + j) % n) {
                        Status::Failure => {}
                        s => return s,
                    }
                }
                Status::Failure
            }
            Flow::Recovery {
                start,
                count,
                retries,
            } => {
                let main = if start == 0 { r(0) } else { Status::Failure };
                match main {
                    Status::Failure if start == 1 || count < retries => match r(1) {
                        // Back to the first child (`Model::opaque`).
                        Status::Success | Status::Running => Status::Running,
                        _ => Status::Failure,
                    },
                    s => s,
                }
            }
            Flow::Gated => {
                // As recorded while its children are; otherwise the child
                // that is ticked decides, else what the node returned
                // without ticking one (`Model::opaque` says where that is
                // a guess).
                if self.facts.ticked[fi] && self.children_as_recorded(uid, vals) {
                    return match self.facts.returned[fi] {
                        Status::Idle => Status::Failure,
                        s => s,
                    };
                }
                for (k, &c) in kids.iter().enumerate() {
                    let s = r(k);
                    if s != Status::Idle
                        && (self.facts.ticked[c as usize - 1] || !self.facts.ticked[fi])
                    {
                        return s;
                    }
                }
                match self.facts.returned[fi] {
                    Status::Idle => Status::Failure,
                    s => s,
                }
            }
        }
    }

    /// Whether every child of `uid` has, in `vals`, the status it returned
    /// in the run (IDLE: not ticked).
    fn children_as_recorded(&self, uid: Uid, vals: &[Val]) -> bool {
        self.tree
            .node(uid)
            .children
            .iter()
            .all(|&c| self.r_val(c, vals) == self.facts.returned[c as usize - 1])
    }

    /// The nodes whose way on, under the values `vals`, the model does not
    /// follow, so that what it says follows from them is a guess: a control
    /// node it does not model (a custom one, Nav2's PersistentSequence, a
    /// RecoveryNode that went back to its first child in the tick, …) whose
    /// children now do otherwise than in the run, or that now runs and did
    /// not; and a RecoveryNode whose recovery now succeeds, after which it
    /// ticks its first child again within the tick. Decorators that pass up
    /// the status of the child they tick (Timeout, Delay, RateController,
    /// …) are followed: which child they tick is the recorded choice.
    ///
    /// And the blackboard, which the model does not hold: a node whose
    /// status a script or a blackboard entry decides (a pre-condition, a
    /// ScriptCondition, a Switch, …) is followed only as recorded, so it is
    /// opaque where it now runs and did not, or where a node that writes the
    /// blackboard (a Script, a post-condition, …) now does otherwise.
    pub fn opaque(&self, vals: &[Val]) -> Vec<Uid> {
        let differs = |u: Uid| {
            let i = u as usize - 1;
            vals[self.e(u)].is_true() != self.facts.ticked[i]
                || (self.facts.ticked[i] && self.r_val(u, vals) != self.facts.returned[i])
        };
        let written_otherwise = (1..=self.tree.len() as Uid)
            .any(|u| writes_blackboard(self.tree.node(u)) && differs(u));
        (1..=self.tree.len() as Uid)
            .filter(|&u| {
                let i = u as usize - 1;
                let n = self.tree.node(u);
                if !vals[self.e(u)].is_true() {
                    return false;
                }
                if reads_blackboard(n) && (!self.facts.ticked[i] || written_otherwise) {
                    return true;
                }
                if n.children.is_empty() {
                    return false;
                }
                match self.flows[i] {
                    Flow::Recovery { .. } => self.r_val(n.children[1], vals) == Status::Success,
                    Flow::Gated if !self.facts.ticked[i] => {
                        !(starts_its_child(n.builtin) && self.facts.start[i] == Status::Idle)
                    }
                    Flow::Gated => {
                        !passes_ticked_child(n.builtin) && !self.children_as_recorded(u, vals)
                    }
                    _ => false,
                }
            })
            .collect()
    }

    /// Whether some change could make `u` one of `opaque`'s nodes.
    pub fn may_be_opaque(&self, u: Uid) -> bool {
        let n = self.tree.node(u);
        reads_blackboard(n)
            || (!n.children.is_empty()
                && matches!(
                    self.flows[u as usize - 1],
                    Flow::Recovery { .. } | Flow::Gated
                ))
    }

    /// A float variable's value moved to the nearest value of its grid (ties
    /// to the smaller), as foils of discretised variables are compared.
    pub fn snap(&self, v: VarId, x: &Val) -> Val {
        let (VarKind::State { var, .. }, Val::Data(Value::Number(n))) = (self.vars[v].kind, x)
        else {
            return x.clone();
        };
        let d = self.domain.as_ref().expect("a domain");
        if !matches!(d.vars[var].ty, VarType::Float { .. }) {
            return x.clone();
        }
        let x0 = n.as_f64().unwrap_or(0.0);
        let mut best: Option<(f64, &Val)> = None;
        for g in &self.vars[v].range {
            if let Val::Data(Value::Number(m)) = g {
                let dist = (m.as_f64().unwrap_or(0.0) - x0).abs();
                if best.is_none_or(|(b, _)| dist < b - 1e-12) {
                    best = Some((dist, g));
                }
            }
        }
        best.map_or_else(|| x.clone(), |(_, g)| g.clone())
    }

    /// A RetryUntilSuccessful's or Repeat's last attempt in the model, as
    /// its structural function counts it with no change: the status that
    /// makes it try again, the attempts spent before that attempt, the most
    /// it makes (−1: no limit), whether the attempt's copy takes the wake-up
    /// path, and the copy.
    pub fn attempt_loop(&self, u: Uid) -> Option<AttemptLoop> {
        match self.flows[u as usize - 1] {
            Flow::Map(Mapping::Loop { again, max }) => {
                let kids = &self.tree.node(u).children;
                let &last = kids.last()?;
                Some(AttemptLoop {
                    again,
                    spent: self.attempts_val(u, &self.fact) + kids.len() as i64 - 1,
                    max,
                    wakes: self.wakes(last),
                    last,
                })
            }
            _ => None,
        }
    }

    /// Whether, under `vals`, loop `u` ticks its child again within the
    /// tick after its last copy: the attempt the model has no copy for,
    /// as the attempt it would be (from 1).
    pub fn loop_goes_on(&self, u: Uid, vals: &[Val]) -> Option<i64> {
        let Flow::Map(Mapping::Loop { again, max }) = self.flows[u as usize - 1] else {
            return None;
        };
        let kids = &self.tree.node(u).children;
        let &last = kids.last()?;
        let spent = self.attempts_val(u, vals) + kids.len() as i64 - 1;
        let goes_on = vals[self.e(u)].is_true()
            && self.r_val(last, vals) == again
            && (max == -1 || spent + 1 < max)
            && !self.wakes(last);
        goes_on.then_some(spent + 2)
    }

    /// The value, under `vals`, of what a question about variable `t` asks
    /// of the tick: for a node with copies (attempts of a loop above it),
    /// the node's last call in the tick, which may be another attempt's
    /// copy than the one `t` is of (a change can end the tick's attempts
    /// sooner, or later); otherwise `vals[t]`.
    ///
    /// `None` where that is unknown: the node was ticked more often in the
    /// tick than the model has copies of it (under a RecoveryNode that went
    /// back to its first child, or in attempts folded into a count), and
    /// under `vals` none of its modelled calls happens, so its last call is
    /// one the model does not hold.
    pub fn in_tick(&self, t: VarId, vals: &[Val]) -> Option<Val> {
        let u = match self.vars[t].kind {
            VarKind::Executed(u) | VarKind::Status(u) | VarKind::Decision(u) => u,
            _ => return Some(vals[t].clone()),
        };
        let origin = self.origin(u);
        let attempt = |c: Uid| self.attempt_of(c).unwrap_or(0);
        let mine: Vec<Uid> = (1..=self.tree.len() as Uid)
            .filter(|&c| self.origin(c) == origin)
            .collect();
        let modelled = mine
            .iter()
            .filter(|&&c| self.facts.ticked[c as usize - 1])
            .count() as u32;
        let last = mine
            .iter()
            .copied()
            .filter(|&c| vals[self.e(c)].is_true())
            .max_by_key(|&c| attempt(c));
        if last.is_none() && self.facts.calls[origin as usize - 1] > modelled {
            return None;
        }
        Some(match (self.vars[t].kind, last) {
            (VarKind::Executed(_), l) => Val::Bool(l.is_some()),
            (VarKind::Status(_), Some(c)) => vals[self.r(c)].clone(),
            (VarKind::Status(_), None) => Val::Status(Status::Idle),
            (VarKind::Decision(_), Some(c)) => {
                self.d(c).map_or(Val::Action(None), |d| vals[d].clone())
            }
            _ => Val::Action(None),
        })
    }

    /// A loop's attempts variable.
    pub fn attempts_var(&self, u: Uid) -> Option<VarId> {
        self.a_of.get(u as usize - 1).copied().flatten()
    }

    /// The attempts a loop had spent before its first copy, in `vals`.
    fn attempts_val(&self, u: Uid, vals: &[Val]) -> i64 {
        match self
            .a_of
            .get(u as usize - 1)
            .copied()
            .flatten()
            .map(|a| &vals[a])
        {
            Some(Val::Data(Value::Number(n))) => n.as_i64().unwrap_or(0),
            _ => 0,
        }
    }

    /// Whether a copy of a loop's child was started in the tick, so that
    /// ending in another attempt takes BehaviorTree.CPP 4's wake-up path.
    fn wakes(&self, child: Uid) -> bool {
        self.tree.version == crate::model::Version::V4
            && self.facts.start[child as usize - 1] == Status::Idle
    }

    /// The copy a node of the model is, if it is not one of the session's
    /// (an attempt of a loop's child other than its last in the tick).
    pub fn copy_of(&self, u: Uid) -> Option<super::attempts::Copy> {
        self.copy_of.get(u as usize - 1).copied().flatten()
    }

    /// The session's node a node of the model stands for.
    pub fn origin(&self, u: Uid) -> Uid {
        self.copy_of(u).map_or(u, |c| c.origin)
    }

    /// Attempts of a loop in the tick that no copy stands for.
    pub fn folded(&self, u: Uid) -> i64 {
        self.folded.get(u as usize - 1).copied().unwrap_or(0)
    }

    /// How many nodes the session's tree has (the model's tree may have
    /// more: the copies).
    pub fn session_len(&self) -> usize {
        self.session_len
    }

    /// A node as answers name it: its description, with its uid when
    /// another node of the tree reads the same ("insert large gear (#13)").
    pub fn node_name(&self, u: Uid) -> String {
        let o = self.origin(u);
        let d = self.tree.description(o);
        let shared = self.tree.nodes[..self.session_len]
            .iter()
            .any(|n| n.uid != o && self.tree.description(n.uid) == d);
        match (self.attempt_of(u), shared) {
            (Some(a), true) => format!("{d} (#{o}, attempt {a})"),
            (Some(a), false) => format!("{d} (attempt {a})"),
            (None, true) => format!("{d} (#{u})"),
            (None, false) => d.to_string(),
        }
    }

    /// The attempt of a loop a node belongs to, when the model has more
    /// than one attempt of that loop in the tick.
    pub fn attempt_of(&self, u: Uid) -> Option<i64> {
        if let Some(c) = self.copy_of(u) {
            return Some(c.attempt);
        }
        let mut child = u;
        for a in self.tree.ancestors(u) {
            let kids = &self.tree.node(a).children;
            if self.attempt_loop(a).is_some() && kids.len() > 1 {
                let k = kids.iter().position(|&c| c == child)? as i64;
                return Some(self.attempts_val(a, &self.fact) + k + 1);
            }
            child = a;
        }
        None
    }

    /// A human name for a variable: `executed(L0)`, `X_b^1`.
    pub fn var_name(&self, v: VarId) -> String {
        match self.vars[v].kind {
            VarKind::Executed(u) => format!("executed({})", self.node_name(u)),
            VarKind::Status(u) => format!("status({})", self.node_name(u)),
            VarKind::Decision(u) => format!("decision({})", self.node_name(u)),
            VarKind::Attempts(u) => format!("attempts({})", self.node_name(u)),
            VarKind::State { var, copy } => {
                let d = self.domain.as_ref().expect("a domain");
                format!("{}^{copy}", d.vars[var].name)
            }
        }
    }

    /// Variables whose model value differs from the record: empty when the
    /// model is faithful to the run.
    pub fn unfaithful(&self) -> Vec<String> {
        let mut out = Vec::new();
        for u in 1..=self.tree.len() as Uid {
            let i = u as usize - 1;
            let e = self.fact[self.e(u)].is_true();
            if e != self.facts.ticked[i] {
                out.push(format!(
                    "executed({}) is {e} in the model, {} in the run",
                    self.tree.description(u),
                    self.facts.ticked[i]
                ));
            }
            let r = self.fact[self.r(u)].status();
            if r != self.facts.returned[i] {
                out.push(format!(
                    "status({}) is {r} in the model, {} in the run",
                    self.tree.description(u),
                    self.facts.returned[i]
                ));
            }
            if let Some(d) = self.d(u) {
                if let Val::Action(a) = &self.fact[d] {
                    let rec = &self.facts.decisions[i];
                    let same = match (a, rec) {
                        (None, None) => true,
                        (None, Some(x)) => x == "null",
                        (Some(a), Some(x)) => a == x,
                        (Some(_), None) => !self.facts.ticked[i],
                    };
                    if !same {
                        out.push(format!(
                            "decision({}) is {a:?} in the model, {rec:?} in the run",
                            self.tree.description(u)
                        ));
                    }
                }
            }
        }
        let Some(d) = &self.domain else {
            return out;
        };
        let key = |x: usize| EntryId {
            scope: 0,
            key: d.vars[x].name.clone(),
        };
        for (i, inputs) in self.inputs_of.iter().enumerate() {
            let u = &(i as Uid + 1);
            if inputs.is_empty() || !self.facts.ticked[i] {
                continue;
            }
            let Some(before) = self.facts.state_before.get(u) else {
                continue;
            };
            for &(x, c) in inputs {
                if let (Val::Data(m), Some(r)) = (&self.fact[c], before.get(&key(x))) {
                    if !same_value(m, r) {
                        out.push(format!(
                            "{} read by {} is {m} in the model, {r} in the run",
                            self.var_name(c),
                            self.tree.description(*u)
                        ));
                    }
                }
            }
        }
        // A derived variable's last copy is its value when last read; its
        // parents may change after that, so only top-level ones are checked.
        for (x, cs) in self.copies.iter().enumerate() {
            if !d.vars[x].parents.is_empty() {
                continue;
            }
            let last = *cs.last().expect("every variable has copy 0");
            if let (Val::Data(m), Some(r)) = (&self.fact[last], self.facts.state_end.get(&key(x))) {
                if !same_value(m, r) {
                    out.push(format!(
                        "{} at the end of the tick is {m} in the model, {r} in the run",
                        self.var_name(last)
                    ));
                }
            }
        }
        out.sort();
        out
    }

    /// The order variables read in: the tree's (pre-order; execution,
    /// status, decision), then the state's (declaration order, copy).
    pub fn display_key(&self, v: VarId) -> (u8, usize, u32) {
        match self.vars[v].kind {
            VarKind::Executed(u) => (0, self.pre_pos[u as usize - 1], 0),
            VarKind::Status(u) => (0, self.pre_pos[u as usize - 1], 1),
            VarKind::Decision(u) => (0, self.pre_pos[u as usize - 1], 2),
            VarKind::Attempts(u) => (0, self.pre_pos[u as usize - 1], 3),
            VarKind::State { var, copy } => (1, var, copy),
        }
    }

    /// For every variable, the fewest edges from it to one of `vs`
    /// (`usize::MAX` if none).
    pub fn distances_to(&self, vs: &[VarId]) -> Vec<usize> {
        let mut dist = vec![usize::MAX; self.vars.len()];
        let mut queue = std::collections::VecDeque::new();
        for &v in vs {
            dist[v] = 0;
            queue.push_back(v);
        }
        while let Some(v) = queue.pop_front() {
            for &p in &self.parents[v] {
                if dist[p] == usize::MAX {
                    dist[p] = dist[v] + 1;
                    queue.push_back(p);
                }
            }
        }
        dist
    }

    /// Ancestors of `vs` (and `vs`), in topological order.
    pub fn ancestors(&self, vs: &[VarId]) -> Vec<VarId> {
        let mut seen = vec![false; self.vars.len()];
        let mut stack: Vec<VarId> = vs.to_vec();
        while let Some(v) = stack.pop() {
            if !seen[v] {
                seen[v] = true;
                stack.extend(self.deps[v].iter().copied());
            }
        }
        let mut out: Vec<VarId> = (0..self.vars.len()).filter(|&v| seen[v]).collect();
        out.sort_by_key(|&v| self.topo_pos[v]);
        out
    }

    /// An evaluator for interventions restricted to `within` (topologically
    /// sorted, closed under ancestors).
    pub fn evaluator<'m>(&'m self, within: &'m [VarId]) -> Evaluator<'m> {
        Evaluator {
            m: self,
            within,
            vals: self.fact.clone(),
            changed: vec![false; self.vars.len()],
            fixed: vec![false; self.vars.len()],
            touched: Vec::new(),
            memo: Memo::default(),
        }
    }
}

pub fn same_value(a: &Value, b: &Value) -> bool {
    match (a.as_f64(), b.as_f64()) {
        (Some(x), Some(y)) => (x - y).abs() <= 1e-9 * x.abs().max(y.abs()).max(1.0),
        _ => a == b,
    }
}

/// Leaf functions already evaluated on the same inputs: the domain's
/// functions are deterministic, so each input is evaluated once.
#[derive(Default)]
pub struct Memo {
    status: FxHashMap<Vec<u8>, Status>,
    decide: FxHashMap<Vec<u8>, Option<String>>,
    effect: FxHashMap<Vec<u8>, Arc<Vec<(usize, Value)>>>,
    derive: FxHashMap<Vec<u8>, Value>,
    buf: Vec<u8>,
}

/// Evaluates interventions (the Do operator): only descendants of the
/// intervened variables are recomputed, and only while values change.
pub struct Evaluator<'m> {
    m: &'m Model,
    within: &'m [VarId],
    vals: Vec<Val>,
    changed: Vec<bool>,
    fixed: Vec<bool>,
    touched: Vec<VarId>,
    memo: Memo,
}

impl Evaluator<'_> {
    /// Do(v = x for each (v, x)); afterwards `value` reads the result.
    pub fn run(&mut self, dos: &[(VarId, Val)]) -> Result<(), Located> {
        for &t in &self.touched {
            self.vals[t] = self.m.fact[t].clone();
            self.changed[t] = false;
            self.fixed[t] = false;
        }
        self.touched.clear();
        let mut first = usize::MAX;
        for (v, x) in dos {
            self.vals[*v] = x.clone();
            self.fixed[*v] = true;
            self.changed[*v] = *x != self.m.fact[*v];
            self.touched.push(*v);
            first = first.min(self.m.topo_pos[*v]);
        }
        let start = self.within.partition_point(|&v| self.m.topo_pos[v] < first);
        for &v in &self.within[start..] {
            if self.fixed[v] || !self.m.deps[v].iter().any(|&p| self.changed[p]) {
                continue;
            }
            let nv = self.m.eval(v, &self.vals, &mut self.memo)?;
            if nv != self.vals[v] {
                self.vals[v] = nv;
                self.changed[v] = true;
                self.touched.push(v);
            }
        }
        Ok(())
    }

    pub fn value(&self, v: VarId) -> &Val {
        &self.vals[v]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::session::Session;
    use std::path::Path;

    fn case_study() -> (Session, Arc<Domain>) {
        let s =
            Session::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("sessions/case-study.jsonl"))
                .unwrap();
        let d = crate::causal::session_domain(&s, None).unwrap().unwrap();
        (s, d)
    }

    fn builder() -> Builder {
        Builder {
            vars: Vec::new(),
            edges: HashSet::new(),
            edge_list: Vec::new(),
            extension: 0,
        }
    }

    #[test]
    fn structure_gives_e_r_and_d_per_node() {
        let (s, d) = case_study();
        let facts = TickFacts::of(&s, 1).unwrap();
        let flows = control_flows(&s.tree, &facts);
        let mut b = builder();
        let st = structure(&s.tree, &Some(d), &s.tree.preorder(), &flows, &[], &mut b);
        // Five nodes: E and r each, d for the two action leaves L1 and L2.
        assert_eq!(b.vars.len(), 12);
        assert!(st.e_of.iter().chain(&st.r_of).all(|&v| v < 12));
        assert_eq!(st.d_of.iter().flatten().count(), 2);
        assert_eq!(b.extension, 0, "Love's case study needs no extension edge");
    }

    #[test]
    fn state_copies_follow_the_leaves_in_tree_order() {
        let (s, d) = case_study();
        let facts = TickFacts::of(&s, 1).unwrap();
        let flows = control_flows(&s.tree, &facts);
        let order = s.tree.preorder();
        let mut b = builder();
        let dom = Some(Arc::clone(&d));
        let st = structure(&s.tree, &dom, &order, &flows, &[], &mut b);
        let sc = state_copies(&s.tree, &dom, &order, &st, &mut b);
        let count = |name: &str| sc.copies[d.var(name).unwrap()].len();
        // Love's Table 1 model: X_a twice, X_b three times, X_c and X_d once.
        assert_eq!(
            (count("X_a"), count("X_b"), count("X_c"), count("X_d")),
            (2, 3, 1, 1)
        );
        assert_eq!(b.vars.len(), 19);
        let g = assemble(&b, &sc.inputs_of).unwrap();
        assert_eq!(g.graph.edge_count(), 34);
        for &(a, c) in &b.edge_list {
            assert!(g.topo_pos[a] < g.topo_pos[c], "topological order");
        }
    }

    #[test]
    fn attempts_follow_the_wake_up_path() {
        let xml = r#"<root BTCPP_format="4"><BehaviorTree ID="M"><RetryUntilSuccessful num_attempts="3"><a name="a"/></RetryUntilSuccessful></BehaviorTree></root>"#;
        let (tree, s) = crate::causal::attempts::testing::planned(xml, "a = F, 1RF, S", 10);
        // Tick 1: a starts and fails at once; the Retry waits for tick 2:
        // one attempt, no other copy.
        let m1 = Model::build(&tree, None, TickFacts::of(&s, 1).unwrap()).unwrap();
        assert!(matches!(
            m1.flows[0],
            Flow::Map(Mapping::Loop { max: 3, .. })
        ));
        assert_eq!(m1.tree.node(1).children, vec![2]);
        let l = m1.attempt_loop(1).unwrap();
        assert_eq!(
            (l.again, l.spent, l.max, l.wakes, l.last),
            (Status::Failure, 0, 3, true, 2)
        );
        // Tick 3: a was running, fails, and the Retry tries again at once:
        // attempt 2 is a copy, attempt 3 the session's node.
        let facts = TickFacts::of(&s, 3).unwrap();
        assert_eq!(facts.calls[1], 2);
        let m3 = Model::build(&tree, None, facts).unwrap();
        assert_eq!(m3.tree.node(1).children, vec![3, 2]);
        let l = m3.attempt_loop(1).unwrap();
        assert_eq!(
            (l.again, l.spent, l.max, l.wakes, l.last),
            (Status::Failure, 2, 3, true, 2)
        );
        // And the model reproduces every tick of it.
        for t in 1..=s.index.ticks() {
            let m = Model::build(&tree, None, TickFacts::of(&s, t).unwrap()).unwrap();
            assert!(m.unfaithful().is_empty(), "tick {t}: {:?}", m.unfaithful());
        }
    }
    fn nav2_model(body: &str, plan: &str, tick: u32) -> Model {
        let xml =
            format!(r#"<root BTCPP_format="4"><BehaviorTree ID="M">{body}</BehaviorTree></root>"#);
        let (tree, s) = crate::causal::attempts::testing::planned(&xml, plan, 10);
        let m = Model::build(&tree, None, TickFacts::of(&s, tick).unwrap()).unwrap();
        assert!(m.unfaithful().is_empty(), "{:?}", m.unfaithful());
        m
    }

    fn executed(m: &Model, dos: &[(VarId, Val)], u: Uid) -> bool {
        m.evaluate_with(dos).unwrap()[m.e(u)].is_true()
    }

    #[test]
    fn a_pipeline_lets_a_child_before_the_furthest_run_on() {
        let body = r#"<PipelineSequence><a name="a"/><b name="b"/></PipelineSequence>"#;
        let plan = "a = 1RS, 1RS\nb = 3RS";
        // Tick 2: a succeeds and b starts (the furthest child reached).
        let m = nav2_model(body, plan, 2);
        assert_eq!(m.flows[0], Flow::Pipeline { last: 0 });
        let running = Val::Status(Status::Running);
        assert!(!executed(&m, &[(m.r(2), running.clone())], 3));
        // Tick 3: a, ticked again, runs while b is the furthest: b is
        // still ticked, and the pipeline's status is b's.
        let m = nav2_model(body, plan, 3);
        assert_eq!(m.flows[0], Flow::Pipeline { last: 1 });
        assert!(executed(&m, &[], 3));
        let failed = m
            .evaluate_with(&[(m.r(3), Val::Status(Status::Failure))])
            .unwrap();
        assert_eq!(failed[m.r(1)], Val::Status(Status::Failure));
        assert!(m.opaque(&m.fact).is_empty());
    }

    #[test]
    fn a_round_robin_goes_on_from_where_it_stopped() {
        let body = r#"<RoundRobin><a name="a"/><b name="b"/><c name="c"/></RoundRobin>"#;
        // Tick 1: a fails, b runs; tick 2 starts at b with one failure.
        let m = nav2_model(body, "a = F\nb = 2RS\nc = S", 2);
        assert_eq!(
            m.flows[0],
            Flow::RoundRobin {
                start: 1,
                failed: 1
            }
        );
        assert!(!executed(&m, &[], 2) && executed(&m, &[], 3));
        // Were b to fail, c would run, and a not again (it failed already).
        let dos = [(m.r(3), Val::Status(Status::Failure))];
        assert!(executed(&m, &dos, 4) && !executed(&m, &dos, 2));
    }

    #[test]
    fn a_recovery_node_is_followed_until_it_would_go_back_to_its_first_child() {
        let body =
            r#"<RecoveryNode number_of_retries="1"><a name="a"/><b name="b"/></RecoveryNode>"#;
        let m = nav2_model(body, "a = 2RS\nb = S", 1);
        assert_eq!(
            m.flows[0],
            Flow::Recovery {
                start: 0,
                count: 0,
                retries: 1
            }
        );
        let fail = (m.r(2), Val::Status(Status::Failure));
        assert!(executed(&m, std::slice::from_ref(&fail), 3));
        let recovering = [fail.clone(), (m.r(3), Val::Status(Status::Running))];
        assert!(m.opaque(&m.evaluate_with(&recovering).unwrap()).is_empty());
        // A recovery that succeeds sends it back to a within the tick.
        let back = [fail, (m.r(3), Val::Status(Status::Success))];
        assert_eq!(m.opaque(&m.evaluate_with(&back).unwrap()), vec![1]);
        // In a tick where it went back, its choices are the recorded ones.
        let m = nav2_model(body, "a = F, 1RS\nb = S", 1);
        assert_eq!(m.flows[0], Flow::Gated);
        let stop = [(m.r(3), Val::Status(Status::Failure))];
        assert_eq!(m.opaque(&m.evaluate_with(&stop).unwrap()), vec![1]);
    }
}
