//! One run, summarised for the fleet: how it ended and what went wrong, and
//! for each node that ran, its failures, what recovered each, and how long
//! each of its RUNNING spells lasted. The summary keeps no transition, so
//! that a fleet holds one run's transitions per core, not every run's.

use crate::ask::{ask, Context};
use crate::explain::failure::recovery;
use crate::explain::fault::is_fault;
use crate::model::{Tree, Uid};
use crate::run::Status;
use crate::session::Session;

/// A run as the fleet counts it.
#[derive(Debug, Clone)]
pub struct RunSummary {
    /// The file, with `#k` for the k-th run of a log holding several.
    pub name: String,
    /// The file, and which of its runs when it holds several: to open it.
    pub file: std::path::PathBuf,
    pub run: Option<usize>,
    /// The bag's log topic, when it holds several robots' logs.
    pub topic: Option<String>,
    /// The tree, as its root's name says it.
    pub tree: String,
    /// Which tree, by its shape: nodes of runs of one tree pair by uid,
    /// as `btx diff` pairs them (a log's tree and the file it was run from
    /// are one tree, whatever names the log writes back).
    pub tree_key: String,
    pub ticks: u32,
    pub transitions: usize,
    /// The root's completion, if the run finished.
    pub outcome: Option<Status>,
    /// How the run ended, as `btx log` says it.
    pub ending: String,
    /// `btx ask RUN "What went wrong?"` at the run's end, when it failed.
    pub wrong: Option<String>,
    /// Places where the log says transitions may be missing.
    pub gaps: usize,
    /// Each node that ran, as read; a fleet counts them into its own and
    /// keeps `faulted` (`Fleet::add`).
    pub nodes: Vec<NodeRun>,
    /// The nodes whose failure was a fault in this run.
    pub faulted: Vec<Uid>,
    /// Compared with the reference run, subgoal by subgoal (`--reference`).
    pub diff: Option<crate::diff::Diff>,
    /// When the first and the last transition happened, as a log says.
    pub span_us: Option<(i64, i64)>,
    /// Its robot and day, when the fleet is exported.
    pub partition: Option<super::partition::Partition>,
}

/// A node in one run.
#[derive(Debug, Clone)]
pub struct NodeRun {
    /// The node's path of names.
    pub path: String,
    /// As answers name it: `look at chuck #18`.
    pub name: String,
    /// Its name alone: `look at chuck`.
    pub spoken: String,
    pub uid: Uid,
    pub leaf: bool,
    pub failures: u32,
    /// Of those, the faults (`explain::fault`): the rest are branches
    /// taken, checks that answered no as the tree is designed to.
    pub faults: u32,
    /// Ticks each RUNNING spell lasted, from the tick it went RUNNING to the
    /// tick it completed or was halted (spells still open at the end left
    /// out).
    pub running: Vec<u32>,
    /// For each fault of a leaf, the handler that recovered it (a
    /// Fallback, a Retry or a RecoveryNode that succeeded after it), named
    /// as answers name a node; `None`: none did by the run's end.
    pub recoveries: Vec<Option<String>>,
}

/// Summarises a run; `name` says which; compared with `reference` if given.
pub fn summarise(name: String, s: &Session, reference: Option<&Session>) -> RunSummary {
    let tree = &s.tree;
    let end = s.index.transitions.len() as u32;
    let at_end = s.index.at(end);
    let nodes = node_runs(s, &at_end);
    let outcome = s
        .end
        .as_ref()
        .map(|e| e.1)
        .filter(|st| st.is_completed())
        .or_else(|| at_end.root_outcome());
    let wrong = (outcome == Some(Status::Failure)).then(|| went_wrong(tree, s, end));
    RunSummary {
        tree: tree.spoken(Tree::ROOT),
        tree_key: shape(tree),
        ticks: s.index.ticks(),
        transitions: s.index.transitions.len(),
        outcome,
        ending: s.ending(),
        wrong,
        gaps: s.index.gaps.len(),
        span_us: s.span_us,
        partition: None,
        file: s.path.clone(),
        run: None,
        topic: None,
        nodes,
        faulted: Vec::new(),
        diff: reference.map(|r| {
            use crate::diff::{Diff, Side};
            Diff::new(
                &Side::session(r.path.display().to_string(), r),
                &Side::session(name.clone(), s),
            )
        }),
        name,
    }
}

/// What each node that ran did in the run: its failures and faults, its
/// spells of RUNNING in ticks, what recovered each fault of a leaf.
fn node_runs(s: &Session, at_end: &crate::session::index::At) -> Vec<NodeRun> {
    let tree = &s.tree;
    let n = tree.len();
    let mut nodes: Vec<Option<NodeRun>> = vec![None; n];
    let mut since: Vec<Option<u32>> = vec![None; n];
    for (i, t) in s.index.transitions.iter().enumerate() {
        let Some(node) = tree.get(t.uid) else {
            continue;
        };
        let k = (t.uid - 1) as usize;
        let ran = t.status != Status::Idle;
        if ran && nodes[k].is_none() {
            nodes[k] = Some(NodeRun {
                path: tree.full_path(t.uid),
                name: format!("{} #{}", tree.spoken(t.uid), t.uid),
                spoken: tree.spoken(t.uid),
                uid: t.uid,
                leaf: node.kind.is_leaf(),
                failures: 0,
                faults: 0,
                running: Vec::new(),
                recoveries: Vec::new(),
            });
        }
        match t.status {
            Status::Running if t.prev != Status::Running => since[k] = Some(t.tick),
            Status::Running => {}
            _ => {
                if let (Some(from), Some(nr)) = (since[k].take(), nodes[k].as_mut()) {
                    nr.running.push(t.tick.saturating_sub(from));
                }
            }
        }
        if t.status == Status::Failure {
            let nr = nodes[k].as_mut().expect("a node that failed ran");
            nr.failures += 1;
            if !is_fault(tree, &s.index, i as u32 + 1) {
                continue;
            }
            nr.faults += 1;
            if nr.leaf {
                let by = recovery(tree, at_end, t.uid, i as u32 + 1)
                    .map(|(h, _)| format!("{} #{h}", tree.spoken(h)));
                nr.recoveries.push(by);
            }
        }
    }
    nodes.into_iter().flatten().collect()
}

/// "What went wrong?" at position `end`, as `btx ask` answers it.
fn went_wrong(tree: &Tree, s: &Session, end: u32) -> String {
    let cx = Context {
        tree,
        session: Some(s),
        at: Some(s.index.at(end)),
        tick: None,
        node: None,
        detail: Default::default(),
        last: Default::default(),
    };
    ask(&cx, "What went wrong?").answer
}

/// The tree's shape as `model::same_shape` compares it (each node's kind,
/// parent and built-in type), as a key.
fn shape(tree: &Tree) -> String {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    for n in &tree.nodes {
        (n.kind, n.parent, n.builtin).hash(&mut h);
    }
    format!("{:016x}", h.finish())
}
