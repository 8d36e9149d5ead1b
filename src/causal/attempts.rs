//! Stage "attempts": a RetryUntilSuccessful or Repeat can tick its child
//! more than once within one tick. Love's model makes one copy of the state
//! per tick; btx makes one copy of the child's subtree per attempt within
//! the tick, so that what an earlier attempt did, and what another attempt
//! would do, are variables of the model like any other.
//!
//! The tree is unrolled: the loop's children become the copies in attempt
//! order. The session's own uids stand for each node's last call in the
//! tick (what the log shows last, and what `#N` picks); the other copies get
//! new uids past the tree's, with their origin and attempt. A copy is made
//! for every earlier attempt of the tick, and one more for the attempt that
//! would follow the last if it ended otherwise (when the loop would tick its
//! child again within the tick: in BehaviorTree.CPP 4 only after a child
//! that was already running, as a child started in the tick takes the
//! wake-up path).

use super::facts::TickFacts;
use crate::model::{Builtin, Tree, Uid, Version};
use crate::run::{CallRecord, Flow, Status};

/// At most this many copies of a loop's child per tick: a v3 loop with no
/// wake-up path may tick a child thousands of times in one tick; the
/// earliest attempts past this are folded into the attempt count.
pub const COPIES_MAX: usize = 8;

/// A node of the unrolled tree that is not one of the session's.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Copy {
    /// The session's node it copies.
    pub origin: Uid,
    /// Its call within the tick (from 1); 0 for the attempt that did not
    /// happen.
    pub call: u32,
    /// The attempt (cycle) of the loop it belongs to, from 1.
    pub attempt: i64,
}

/// What a RetryUntilSuccessful or Repeat does with its child's statuses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LoopKind {
    /// The status that makes it tick its child again: FAILURE for a Retry,
    /// SUCCESS for a Repeat.
    pub again: Status,
    /// Attempts (cycles) at most; −1: no limit.
    pub max: i64,
}

/// A node's loop kind, if it is a RetryUntilSuccessful or a Repeat.
pub fn loop_kind(tree: &Tree, uid: Uid) -> Option<LoopKind> {
    let n = tree.node(uid);
    let (again, port) = match n.builtin {
        Some(Builtin::RetryUntilSuccessful) => (Status::Failure, "num_attempts"),
        Some(Builtin::Repeat) => (Status::Success, "num_cycles"),
        _ => return None,
    };
    n.children.first()?;
    let max = n
        .ports
        .iter()
        .find(|p| p.name == port)
        .and_then(|p| match &p.value {
            crate::model::PortValue::Literal(s) => s.trim().parse().ok(),
            _ => None,
        })
        .unwrap_or(-1);
    Some(LoopKind { again, max })
}

/// The tree and facts with a copy of a loop's child per attempt.
#[derive(Debug, Clone)]
pub struct Unrolled {
    pub tree: Tree,
    pub facts: TickFacts,
    /// Per uid − 1 of the unrolled tree: `Some` for the copies.
    pub copy_of: Vec<Option<Copy>>,
    /// Per uid − 1: for a loop, the attempts of the tick that no copy
    /// stands for (ticks of its child before the first copy).
    pub folded: Vec<i64>,
}

/// The calls of `child` within the last call of `parent` in the tick.
fn calls_within(log: &[CallRecord], parent: Uid, child: Uid) -> Vec<&CallRecord> {
    let Some(p) = log.iter().rev().find(|r| r.uid == parent) else {
        return Vec::new();
    };
    let mut calls: Vec<&CallRecord> = log
        .iter()
        .filter(|r| r.uid == child && r.entry_seq > p.entry_seq && r.entry_seq <= p.exit_seq)
        .collect();
    calls.sort_by_key(|r| r.entry_seq);
    calls
}

/// Unrolls every loop of the tick that ticked its child more than once, or
/// could have (see the module's documentation). Loops inside a loop's child
/// are not unrolled again: their earlier attempts are folded.
pub fn unroll(tree: &Tree, facts: TickFacts) -> Unrolled {
    let base = tree.len();
    let mut u = Unrolled {
        tree: tree.clone(),
        facts,
        copy_of: vec![None; base],
        folded: vec![0; base],
    };
    let log = std::mem::take(&mut u.facts.call_log);
    let mut inside = vec![false; base];
    for l in tree.preorder() {
        let li = l as usize - 1;
        let Some(kind) = loop_kind(tree, l) else {
            continue;
        };
        let child = tree.node(l).children[0];
        if inside[li] || !u.facts.ticked[li] {
            // Its attempts within its last call, which its facts stand for
            // (a loop inside another's child is ticked afresh by each
            // attempt of the outer one: not the child's calls in the tick).
            let within = calls_within(&log, l, child).len();
            u.folded[li] = within.saturating_sub(1) as i64;
            continue;
        }
        if let Some(kids) = attempts(&mut u, tree, &log, l, &kind) {
            for d in tree.descendants(l).skip(1) {
                inside[d as usize - 1] = true;
            }
            u.tree.nodes[li].children = kids;
        }
    }
    at_last_calls(&mut u.facts, &log);
    u.facts.call_log = log;
    u
}

/// The children the loop `l` has unrolled: a copy of its child for each
/// earlier attempt in the tick (at most `COPIES_MAX` − 1, the rest folded),
/// the child itself for the last, and a copy for the attempt that would
/// come next; none where there is only the child.
fn attempts(
    u: &mut Unrolled,
    tree: &Tree,
    log: &[CallRecord],
    l: Uid,
    kind: &LoopKind,
) -> Option<Vec<Uid>> {
    let li = l as usize - 1;
    let child = tree.node(l).children[0];
    let calls = calls_within(log, l, child);
    let last = calls.last()?;
    let k = calls.len();
    let earlier = (k - 1).min(COPIES_MAX - 1);
    let folded = (k - 1 - earlier) as i64;
    u.folded[li] = folded;
    let start = u.facts.flows[li].count;
    let spent_before_last = start + k as i64 - 1;
    let more = spent_before_last + 1 < kind.max || kind.max == -1;
    let wakes = tree.version == Version::V4 && last.entry_status == Status::Idle;
    let next = last.returned != kind.again && last.returned != Status::Skipped && more && !wakes;
    if earlier == 0 && !next {
        return None;
    }
    let mut kids = Vec::new();
    for (j, c) in calls[k - 1 - earlier..k - 1].iter().enumerate() {
        let attempt = start + folded + j as i64 + 1;
        let window = Some((c.entry_seq, c.exit_seq));
        kids.push(copy_subtree(u, tree, log, child, l, attempt, window));
    }
    kids.push(child);
    if next {
        kids.push(copy_subtree(
            u,
            tree,
            log,
            child,
            l,
            spent_before_last + 2,
            None,
        ));
    }
    Some(kids)
}

/// A leaf ticked more than once is the session's node at its last call.
fn at_last_calls(facts: &mut TickFacts, log: &[CallRecord]) {
    for r in log {
        let i = r.uid as usize - 1;
        if r.call == facts.calls[i] {
            if let Some(c) = facts.per_call.get(&(r.uid, r.call)) {
                facts.state_before.insert(r.uid, c.state_before.clone());
                match c.done_at {
                    Some(p) => facts.done_at.insert(r.uid, p),
                    None => facts.done_at.remove(&r.uid),
                };
            }
        }
    }
}

/// Appends a copy of `src`'s subtree under `parent`, for `attempt`; with
/// the facts of the calls within `window` (entry and exit of the child's
/// call), or none (an attempt that did not happen).
fn copy_subtree(
    u: &mut Unrolled,
    tree: &Tree,
    log: &[CallRecord],
    src: Uid,
    parent: Uid,
    attempt: i64,
    window: Option<(u64, u64)>,
) -> Uid {
    let first = u.tree.nodes.len() as Uid + 1;
    let nodes: Vec<Uid> = tree.descendants(src).collect();
    let index: rustc_hash::FxHashMap<Uid, Uid> = nodes
        .iter()
        .enumerate()
        .map(|(i, &x)| (x, first + i as Uid))
        .collect();
    let new_of = |x: Uid| index[&x];
    for &x in &nodes {
        let mut n = tree.node(x).clone();
        n.uid = new_of(x);
        n.parent = Some(if x == src {
            parent
        } else {
            new_of(tree.node(x).parent.expect("below src"))
        });
        n.children = n.children.iter().map(|&c| new_of(c)).collect();
        n.name = format!("{} (attempt {attempt})", tree.description(x));
        u.tree.nodes.push(n);
        let rec = window.and_then(|(a, b)| {
            log.iter()
                .filter(|r| r.uid == x && r.entry_seq >= a && r.entry_seq <= b)
                .max_by_key(|r| r.entry_seq)
        });
        let f = &mut u.facts;
        let i = x as usize - 1;
        f.ticked.push(rec.is_some());
        f.returned.push(rec.map_or(Status::Idle, |r| r.returned));
        f.flows
            .push(rec.map_or_else(Flow::default, |r| r.entry.clone()));
        f.start.push(rec.map_or(Status::Idle, |r| r.entry_status));
        f.decisions.push(rec.and_then(|r| r.decision.clone()));
        f.outcome.push(rec.map_or(f.outcome[i], |r| r.returned));
        f.calls.push(u32::from(rec.is_some()));
        if let Some(c) = rec.and_then(|r| f.per_call.get(&(x, r.call))) {
            f.state_before.insert(new_of(x), c.state_before.clone());
            if let Some(p) = c.done_at {
                f.done_at.insert(new_of(x), p);
            }
        }
        u.copy_of.push(Some(Copy {
            origin: x,
            call: rec.map_or(0, |r| r.call),
            attempt,
        }));
        u.folded.push(0);
    }
    first
}

/// A planned run of a tree, for the tests of the stages that read it.
#[cfg(test)]
pub(crate) mod testing {
    use crate::model::Tree;
    use crate::run::plan::{Plan, PlanLeaves};
    use crate::run::RunOptions;
    use crate::session::record::simulate;
    use crate::session::{Session, Source};
    use std::path::Path;

    /// A Retry over a Sequence of two leaves, a and b.
    pub const RETRY: &str = r#"<root BTCPP_format="4"><BehaviorTree ID="M"><RetryUntilSuccessful num_attempts="3"><Sequence><a name="a"/><b name="b"/></Sequence></RetryUntilSuccessful></BehaviorTree></root>"#;

    pub fn planned(xml: &str, plan: &str, ticks: u32) -> (Tree, Session) {
        let tree = crate::xml::load_str(Path::new("t.xml"), xml, &Default::default())
            .unwrap()
            .tree;
        let plan = Plan::parse(Path::new("t.plan"), plan).unwrap();
        let source = Source {
            kind: "plan".into(),
            path: None,
            text: Some(plan.text.clone()),
            name: None,
        };
        let leaves = PlanLeaves::new(plan, &tree);
        let s = simulate(&tree, source, None, ticks, RunOptions::default(), leaves).unwrap();
        (tree, s)
    }
}

#[cfg(test)]
mod tests {
    use super::testing::{planned as run, RETRY};
    use super::*;
    use crate::causal::model::{Model, Val};

    #[test]
    fn an_earlier_attempt_of_the_tick_is_a_copy_with_its_own_facts() {
        // Tick 1: a runs. Tick 2: a fails, the Retry starts attempt 2 at
        // once, a and b succeed.
        let (tree, s) = run(RETRY, "a = 1RF, S\nb = S", 5);
        let u = unroll(&tree, TickFacts::of(&s, 2).unwrap());
        // The Sequence (2) and its leaves (3, 4) are copied as 5, 6, 7.
        assert_eq!(u.tree.node(1).children, vec![5, 2]);
        assert_eq!(u.tree.node(5).children, vec![6, 7]);
        assert_eq!(
            u.copy_of[5],
            Some(Copy {
                origin: 3,
                call: 1,
                attempt: 1
            })
        );
        assert_eq!(u.tree.description(6), "a (attempt 1)");
        // Attempt 1: a failed, b was not ticked; attempt 2 succeeded.
        assert_eq!(u.facts.returned[5], Status::Failure);
        assert!(!u.facts.ticked[6]);
        assert_eq!(u.facts.returned[4], Status::Failure);
        assert_eq!(u.facts.returned[1], Status::Success);
        assert_eq!(u.facts.returned[2], Status::Success);
        assert_eq!(u.folded[0], 0);
    }

    #[test]
    fn a_running_child_gets_a_copy_for_the_attempt_that_would_follow() {
        let (tree, s) = run(RETRY, "a = 2RS\nb = S", 5);
        // Tick 1 started the child: a failure would take the wake-up path.
        let u1 = unroll(&tree, TickFacts::of(&s, 1).unwrap());
        assert_eq!(u1.tree.len(), tree.len());
        // Tick 2 resumed it: a failure would start attempt 2 at once.
        let u2 = unroll(&tree, TickFacts::of(&s, 2).unwrap());
        assert_eq!(u2.tree.node(1).children, vec![2, 5]);
        assert_eq!(u2.copy_of[4].map(|c| (c.call, c.attempt)), Some((0, 2)));
        assert!(!u2.facts.ticked[4]);
    }

    #[test]
    fn the_model_of_the_copies_reproduces_the_run_and_retries() {
        let (tree, s) = run(RETRY, "a = 1RF, S, 2RS\nb = S", 5);
        for t in 1..=s.index.ticks() {
            let m = Model::build(&tree, None, TickFacts::of(&s, t).unwrap()).unwrap();
            assert!(m.unfaithful().is_empty(), "tick {t}: {:?}", m.unfaithful());
        }
        // Tick 2: had attempt 1's a succeeded, attempt 2 would not have run.
        let m = Model::build(&tree, None, TickFacts::of(&s, 2).unwrap()).unwrap();
        let vals = m
            .evaluate_with(&[(m.r(6), Val::Status(Status::Success))])
            .unwrap();
        assert_eq!(vals[m.e(2)], Val::Bool(false));
        assert_eq!(vals[m.r(1)], Val::Status(Status::Success));
        // Had the Retry spent its attempts but one, the failure ends it.
        let a = (0..m.vars.len())
            .find(|&v| m.vars[v].kind == crate::causal::model::VarKind::Attempts(1))
            .unwrap();
        assert_eq!(m.fact[a], Val::Data(0.into()));
        let vals = m.evaluate_with(&[(a, Val::Data(2.into()))]).unwrap();
        assert_eq!(vals[m.r(1)], Val::Status(Status::Failure));
        assert_eq!(vals[m.e(2)], Val::Bool(false));
        // A child resumed and still running: had it failed, attempt 2
        // would have started within the tick.
        let (tree, s) = run(RETRY, "a = 2RS\nb = S", 5);
        let m = Model::build(&tree, None, TickFacts::of(&s, 2).unwrap()).unwrap();
        assert!(m.unfaithful().is_empty(), "{:?}", m.unfaithful());
        let vals = m
            .evaluate_with(&[(m.r(3), Val::Status(Status::Failure))])
            .unwrap();
        assert_eq!(vals[m.e(5)], Val::Bool(true));
        assert_eq!(vals[m.e(6)], Val::Bool(true));
    }
}
