//! The cause first. Love et al. leave relevance as future work; btx orders
//! the explanations of one size so that the one a person would name comes
//! first (a leaf's outcome or a state variable before a control node's
//! status, fewer steps to the target, nearer in the tree), and leaves out
//! what explains nothing: a fact explained by itself (or by its own
//! execution), and a sentence already said.

use super::english;
use super::model::{Model, VarId, VarKind};
use super::search::{Answer, Query};
use super::verify::Check;
use crate::model::Uid;

/// Reorders `answer`'s explanations (and their checks, which run beside
/// them) and drops those that explain nothing.
pub fn order(model: &Model, query: &Query, answer: &mut Answer, checks: &mut Vec<Check>) {
    let dist = model.distances_to(&query.targets);
    let target_node = node_of(model, query.targets[0]);
    // Copies that read alike are one explanation (`english::merge`); a
    // sentence said by another explanation is not said again.
    let mut group_of = vec![0; answer.explanations.len()];
    for (g, members) in english::merge(model, answer).iter().enumerate() {
        for &i in members {
            group_of[i] = g;
        }
    }
    let mut seen: Vec<(String, usize)> = Vec::new();
    let mut kept: Vec<(Key, super::search::Explanation, Check)> = Vec::new();
    for (i, (e, c)) in answer
        .explanations
        .drain(..)
        .zip(checks.drain(..))
        .enumerate()
    {
        // An attempts count is the node's own state, not its outcome: it
        // may explain it.
        let own = e.vars.iter().all(|&v| {
            target_node.is_some()
                && node_of(model, v) == target_node
                && !matches!(model.vars[v].kind, VarKind::Attempts(_))
        });
        let said = english::sentence(model, query, &e);
        let again = seen.iter().any(|(s, g)| *s == said && *g != group_of[i]);
        if own || again {
            continue;
        }
        seen.push((said, group_of[i]));
        let key = Key {
            unlike: e
                .vars
                .iter()
                .filter(|&&v| !alike(model, v, query.targets[0]))
                .count() as u32,
            kind: e.vars.iter().map(|&v| kind_rank(model, v)).sum(),
            earlier: e.vars.iter().map(|&v| earlier(model, v)).max().unwrap_or(0),
            steps: e.vars.iter().map(|&v| dist[v].min(1 << 16)).sum(),
            tree: e
                .vars
                .iter()
                .map(|&v| tree_distance(model, node_of(model, v), target_node))
                .sum(),
            index: i,
        };
        kept.push((key, e, c));
    }
    // A group keeps together, at the place of its best member.
    let mut best: std::collections::HashMap<usize, (u32, u32, u32, usize, u32)> =
        Default::default();
    for (k, _, _) in &kept {
        let g = group_of[k.index];
        let mine = (k.unlike, k.kind, k.earlier, k.steps, k.tree);
        let b = best.entry(g).or_insert(mine);
        *b = (*b).min(mine);
    }
    kept.sort_by_key(|(k, _, _)| (best[&group_of[k.index]], group_of[k.index], k.index));
    for (_, e, c) in kept {
        answer.explanations.push(e);
        checks.push(c);
    }
}

struct Key {
    /// Reasons unlike the fact: a failure is explained by a failure first.
    unlike: u32,
    kind: u32,
    /// A leaf whose call changed nothing in the tick (Nav2's selectors,
    /// succeeding every tick) after one that changed.
    earlier: u32,
    steps: usize,
    tree: u32,
    index: usize,
}

/// Whether a reason is of the fact's own kind: a node's status like the
/// target's status (failed because another failed). Other reasons (a state
/// variable, a decision) are alike to any fact.
fn alike(m: &Model, reason: VarId, target: VarId) -> bool {
    match (&m.vars[reason].kind, &m.vars[target].kind) {
        (VarKind::Status(_), VarKind::Status(_)) => m.fact[reason] == m.fact[target],
        (VarKind::Executed(_), VarKind::Executed(_)) => m.fact[reason] == m.fact[target],
        _ => true,
    }
}

/// For a leaf's status or decision: 1 when its call in the tick changed
/// nothing (no transition: it did again what it did before, as Nav2's
/// selectors succeed every tick), else 0; such a reason is said after the
/// ones that changed.
fn earlier(m: &Model, v: VarId) -> u32 {
    match m.vars[v].kind {
        VarKind::Status(u) | VarKind::Decision(u) if m.tree.node(m.origin(u)).kind.is_leaf() => {
            let o = m.origin(u);
            u32::from(!m.facts.done_at.contains_key(&u) && !m.facts.done_at.contains_key(&o))
        }
        _ => 0,
    }
}

/// The tree node a variable is about (its first attempt's node for a copy).
fn node_of(m: &Model, v: VarId) -> Option<Uid> {
    match m.vars[v].kind {
        VarKind::Executed(u) | VarKind::Status(u) | VarKind::Decision(u) | VarKind::Attempts(u) => {
            Some(m.origin(u))
        }
        VarKind::State { .. } => None,
    }
}

/// What a person names first: what a leaf did, or the world's state; then a
/// control node's status; then how many attempts a loop had used; last,
/// whether a node ran at all.
fn kind_rank(m: &Model, v: VarId) -> u32 {
    match m.vars[v].kind {
        VarKind::State { .. } | VarKind::Decision(_) => 0,
        VarKind::Status(u) if m.tree.node(m.origin(u)).kind.is_leaf() => 0,
        VarKind::Status(_) => 1,
        VarKind::Attempts(_) => 2,
        VarKind::Executed(_) => 3,
    }
}

/// Edges between two nodes of the tree (0 for a state variable).
fn tree_distance(m: &Model, a: Option<Uid>, b: Option<Uid>) -> u32 {
    let (Some(a), Some(b)) = (a, b) else { return 0 };
    let up = |u: Uid| -> Vec<Uid> {
        let mut path = vec![u];
        path.extend(m.tree.ancestors(u));
        path
    };
    let (pa, pb) = (up(a), up(b));
    for (i, x) in pa.iter().enumerate() {
        if let Some(j) = pb.iter().position(|y| y == x) {
            return (i + j) as u32;
        }
    }
    (pa.len() + pb.len()) as u32
}
