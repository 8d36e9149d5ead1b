//! "Why did Spin never run?": told from the run itself, across all its
//! ticks. The nearest node above that did run, each time it ran, ended
//! or stayed on before it reached the branch the node is in; what its kind
//! does with its children says why, and which child decided it.

use super::*;
use crate::model::Builtin;

/// What a control node's kind makes of the children before a branch.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Rule {
    /// Goes on to a child when those before it fail.
    Fallback,
    /// Goes on to a child when those before it succeed.
    Sequence,
    /// Runs its second child when its first fails.
    Recovery,
    /// Ticks one child each time it runs.
    RoundRobin,
    /// Anything else: its own rule, which the run does not show.
    Own,
}

fn rule_of(tree: &Tree, a: Uid) -> Rule {
    match tree.node(a).builtin {
        Some(Builtin::Fallback | Builtin::AsyncFallback | Builtin::ReactiveFallback) => {
            Rule::Fallback
        }
        Some(
            Builtin::Sequence
            | Builtin::AsyncSequence
            | Builtin::SequenceWithMemory
            | Builtin::ReactiveSequence
            | Builtin::PipelineSequence
            | Builtin::PersistentSequence
            | Builtin::NonblockingSequence,
        ) => Rule::Sequence,
        Some(Builtin::RecoveryNode) => Rule::Recovery,
        Some(Builtin::RoundRobin) => Rule::RoundRobin,
        _ => Rule::Own,
    }
}

/// One run of the node above, from its start to where it ended (or the
/// moment asked), and the child before the branch that decided it.
struct Turn {
    start: u32,
    decider: Option<(Uid, Status, u32)>,
}

/// Why `u` never ran by position `upto`, or `None` where it did run.
pub fn never_ran(session: &Session, u: Uid, upto: u32) -> Option<String> {
    let idx = &session.index;
    let tree = &session.tree;
    let ran = |n: Uid| idx.changes_of(n).iter().any(|&p| p <= upto);
    if ran(u) {
        return None;
    }
    let mut branch = u;
    let above = loop {
        let p = tree.parent(branch)?;
        if ran(p) {
            break p;
        }
        branch = p;
    };
    let by = super::by_moment(idx, upto);
    let mut said = format!("{} never ran {by}", capitalised(&tree.told(u)));
    if branch != u {
        said.push_str(&format!(", nor did {} above it", tree.told(branch)));
    }
    let turns = turns(session, above, branch, upto);
    said.push_str(&format!(
        ": {} ran {}{}",
        tree.told(above),
        times(turns.len()),
        kind_said(rule_of(tree, above))
    ));
    said.push_str(&deciders(session, above, branch, &turns));
    Some(said)
}

fn kind_said(rule: Rule) -> &'static str {
    match rule {
        Rule::Fallback => " (a fallback: it tries a child only when the ones before it fail)",
        Rule::Sequence => {
            " (a sequence: it goes on to a child only when the ones before it succeed)"
        }
        Rule::Recovery => {
            " (a recovery node: it runs its recovery only when its first child fails)"
        }
        Rule::RoundRobin => " (a RoundRobin: it ticks one child each time it runs)",
        Rule::Own => "",
    }
}

/// Each run of `above` by `upto`, with the last child before `branch` to
/// change status in it.
fn turns(session: &Session, above: Uid, branch: Uid, upto: u32) -> Vec<Turn> {
    let idx = &session.index;
    let tree = &session.tree;
    let changes: Vec<u32> = idx
        .changes_of(above)
        .iter()
        .copied()
        .filter(|&p| p <= upto)
        .collect();
    let mut starts: Vec<u32> = changes
        .iter()
        .copied()
        .filter(|&p| idx.transitions[p as usize - 1].prev == Status::Idle)
        .collect();
    // A record that begins with the node already running: that is a run.
    if changes.first().is_some_and(|f| starts.first() != Some(f)) {
        starts.insert(0, changes[0]);
    }
    let before: Vec<Uid> = tree
        .node(above)
        .children
        .iter()
        .copied()
        .take_while(|&c| c != branch)
        .collect();
    starts
        .iter()
        .enumerate()
        .map(|(i, &start)| {
            let end = starts.get(i + 1).map_or(upto, |&n| n - 1);
            let decider = before
                .iter()
                .filter_map(|&c| {
                    idx.changes_of(c)
                        .iter()
                        .copied()
                        .filter(|&p| p > start && p <= end)
                        .map(|p| (p, idx.transitions[p as usize - 1].status))
                        .filter(|(_, s)| *s != Status::Idle)
                        .last()
                        .map(|(p, s)| (c, s, p))
                })
                .max_by_key(|&(_, _, p)| p);
            Turn { start, decider }
        })
        .collect()
}

/// Which child ended or held each run before the branch, and, where one
/// child did so every time right before the branch, what would have let
/// the branch run.
fn deciders(session: &Session, above: Uid, branch: Uid, turns: &[Turn]) -> String {
    let idx = &session.index;
    let tree = &session.tree;
    let rule = rule_of(tree, above);
    if rule == Rule::RoundRobin || turns.iter().all(|t| t.decider.is_none()) {
        let ran: Vec<String> = tree
            .node(above)
            .children
            .iter()
            .copied()
            .filter(|&c| {
                idx.changes_of(c)
                    .iter()
                    .any(|&p| turns.first().is_some_and(|t| p > t.start))
            })
            .map(|c| tree.told(c))
            .collect();
        return match ran.is_empty() {
            true => format!(
                ", and never ticked {}; the run does not show why.",
                tree.told(branch)
            ),
            false => format!(
                ", and ran {} instead.",
                super::super::english::and_list(&ran)
            ),
        };
    }
    let each = by_decider(turns);
    let told: Vec<String> = each
        .iter()
        .map(|(c, s, ps)| {
            let at: Vec<String> = ps
                .iter()
                .map(|&p| step_moment(idx, p).to_string())
                .collect();
            let (how, at_or_from) = match s {
                Status::Running => ("was still running", "from"),
                s => (past(*s), "at"),
            };
            let at = if at.len() > 6 {
                format!("{}, … and {}", at[..5].join(", "), at[at.len() - 1])
            } else {
                super::super::english::and_list(&at)
            };
            format!("{} {how} {at_or_from} {at}", tree.told(*c))
        })
        .collect();
    let each_time = if turns.len() > 1 { "each time " } else { "" };
    let mut out = format!(
        ", and {each_time}{}.",
        super::super::english::and_list(&told)
    );
    let previous = tree
        .node(above)
        .children
        .iter()
        .copied()
        .take_while(|&c| c != branch)
        .last();
    let needed = match rule {
        Rule::Fallback | Rule::Recovery => Some((Status::Success, "failed")),
        Rule::Sequence => Some((Status::Failure, "succeeded")),
        _ => None,
    };
    if let ([(d, s, _)], Some((blocking, other))) = (&each[..], needed) {
        if Some(*d) == previous && *s == blocking {
            out.push_str(&format!(
                " {} would have run had {} {other}.",
                capitalised(&tree.told(branch)),
                tree.told(*d)
            ));
        }
    }
    out
}

/// The runs grouped by the child that decided them and how: each with the
/// positions where it did.
fn by_decider(turns: &[Turn]) -> Vec<(Uid, Status, Vec<u32>)> {
    let mut each: Vec<(Uid, Status, Vec<u32>)> = Vec::new();
    for (c, s, p) in turns.iter().filter_map(|t| t.decider) {
        match each.iter_mut().find(|(d, st, _)| *d == c && *st == s) {
            Some(e) => e.2.push(p),
            None => each.push((c, s, vec![p])),
        }
    }
    each
}
