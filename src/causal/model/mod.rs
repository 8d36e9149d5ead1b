//! The explanation model of one tick (Love et al. §5.2): a DAG over the
//! execution E_i, return status r_i and decision d_i of every node and the
//! temporal copies X^(k) of the state variables. Its stages, each a module:
//! `flows` (what each node does, as the model sees it), `build`
//! (Algorithms 1–5, 7 and 8: the structure, the state copies, the graph),
//! `eval` (the structural functions of Algorithms 9–13, and the Do
//! operator), `faithful` (whether the model reproduces its run).

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

mod build;
mod eval;
mod faithful;
mod flows;

pub use eval::{Evaluator, Memo};

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
    /// Nav2's RoundRobin: from child `start`, each in turn (wrapping round
    /// where it `wraps`) until one does not fail, `failed` of them having
    /// failed before. One that does not wrap ends at its last child, with
    /// FAILURE whatever that child returned (main's source).
    RoundRobin {
        start: usize,
        failed: usize,
        wraps: bool,
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
    /// Each description's count among the session's nodes, made when a
    /// name is first asked for (naming every variable scanned the tree for
    /// each, quadratic on a deep chain).
    descriptions: std::sync::OnceLock<FxHashMap<String, usize>>,
    /// Per uid − 1: the nearest loop above with several attempts of its
    /// child in the tick, and the child of it on the way (`attempt_of`).
    loop_above: std::sync::OnceLock<Vec<Option<(Uid, Uid)>>>,
}

/// A model error: the domain or the record does not fit the tree.
fn model_err(msg: String) -> Located {
    Located::file(std::path::Path::new("explanation model"), msg)
}

impl Model {
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
        let counts = self.descriptions.get_or_init(|| {
            let mut counts: FxHashMap<String, usize> = FxHashMap::default();
            for n in &self.tree.nodes[..self.session_len] {
                *counts
                    .entry(self.tree.description(n.uid).to_string())
                    .or_default() += 1;
            }
            counts
        });
        let itself = usize::from((o as usize) <= self.session_len);
        let shared = counts.get(d).is_some_and(|&c| c > itself);
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
        let (a, child) = self.loop_above(u)?;
        let k = self
            .tree
            .node(a)
            .children
            .iter()
            .position(|&c| c == child)? as i64;
        Some(self.attempts_val(a, &self.fact) + k + 1)
    }

    fn loop_above(&self, u: Uid) -> Option<(Uid, Uid)> {
        let several =
            |a: Uid| self.attempt_loop(a).is_some() && self.tree.node(a).children.len() > 1;
        let walk = |u: Uid| {
            let mut child = u;
            for a in self.tree.ancestors(u) {
                if several(a) {
                    return Some((a, child));
                }
                child = a;
            }
            None
        };
        let all = self.loop_above.get_or_init(|| {
            let mut all: Vec<Option<(Uid, Uid)>> = Vec::with_capacity(self.tree.nodes.len());
            for n in &self.tree.nodes {
                let above = match self.tree.parent(n.uid) {
                    None => None,
                    Some(p) if several(p) => Some((p, n.uid)),
                    // Pre-order numbering: the parent's is known.
                    Some(p) if p < n.uid => all[p as usize - 1],
                    Some(_) => walk(n.uid),
                };
                all.push(above);
            }
            all
        });
        all.get(u as usize - 1).copied().flatten()
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
}

pub fn same_value(a: &Value, b: &Value) -> bool {
    match (a.as_f64(), b.as_f64()) {
        (Some(x), Some(y)) => (x - y).abs() <= 1e-9 * x.abs().max(y.abs()).max(1.0),
        _ => a == b,
    }
}

#[cfg(test)]
mod tests {
    use super::build::*;
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
                failed: 1,
                wraps: false
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
