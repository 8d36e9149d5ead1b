//! "Can you X?": Han et al.'s Algorithms 8 and 9. Find the behaviour the
//! person names, climb to the self-contained node whose leaves produce every
//! blackboard entry it reads, and insert that after the current subgoal.

use super::han::subgoal;
use crate::model::{Builtin, Kind, Tree, Uid};
use crate::run::blackboard::{Blackboard, EntryId};
use std::collections::BTreeSet;

/// A "Yes": what to insert where.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Insertion {
    /// The node the question named.
    pub named: Uid,
    /// Algorithm 8's self-contained node: the one copied.
    pub copy_of: Uid,
    /// The current subgoal: the copy goes right after it.
    pub after: Uid,
    pub answer: String,
}

fn refuse(x: &str, why: &str) -> String {
    if why.is_empty() {
        format!("Sorry. I cannot redo \"{x}\".")
    } else {
        format!("Sorry. I cannot redo \"{x}\": {why}.")
    }
}

fn is_sequence_or_subtree(tree: &Tree, uid: Uid) -> bool {
    tree.node(uid).kind == Kind::SubTree
        || matches!(
            tree.node(uid).builtin,
            Some(
                Builtin::Sequence
                    | Builtin::SequenceWithMemory
                    | Builtin::ReactiveSequence
                    | Builtin::AsyncSequence
            )
        )
}

/// Every behaviour "X" names: the Sequences and SubTrees of that name in
/// the whole tree, those in the current subgoal first, then in tree order.
fn find_named(tree: &Tree, scope: Uid, x: &str) -> Vec<Uid> {
    // The name as written (what Han's rules compare).
    let matches = |u: Uid| {
        is_sequence_or_subtree(tree, u) && tree.description(u).eq_ignore_ascii_case(x.trim())
    };
    let (mut inside, outside): (Vec<Uid>, Vec<Uid>) = tree
        .descendants(Tree::ROOT)
        .filter(|&u| matches(u))
        .partition(|&u| u == scope || tree.is_ancestor(scope, u));
    inside.extend(outside);
    inside
}

/// Entries read and written by the leaves below `uid`.
fn leaf_io(tree: &Tree, bb: &Blackboard, uid: Uid) -> (BTreeSet<EntryId>, BTreeSet<EntryId>) {
    let (mut reads, mut writes) = (BTreeSet::new(), BTreeSet::new());
    for l in tree.leaves_below(uid) {
        let n = tree.node(l);
        for p in &n.ports {
            let Some(e) = bb.port_entry(tree, n.scope, &p.value) else {
                continue;
            };
            match p.assumed_direction() {
                crate::model::Direction::In => {
                    reads.insert(e);
                }
                crate::model::Direction::Out => {
                    writes.insert(e);
                }
                crate::model::Direction::InOut => {
                    reads.insert(e.clone());
                    writes.insert(e);
                }
            }
        }
    }
    (reads, writes)
}

/// Algorithm 8: the nearest node at or above `n` whose leaves write every
/// entry that the leaves below `n` read.
pub fn self_contained(tree: &Tree, n: Uid) -> Result<Uid, EntryId> {
    let bb = Blackboard::new(tree);
    let (needed, _) = leaf_io(tree, &bb, n);
    let mut ns = n;
    for e in &needed {
        loop {
            let (_, provided) = leaf_io(tree, &bb, ns);
            if provided.contains(e) {
                break;
            }
            match tree.parent(ns) {
                Some(p) => ns = p,
                None => return Err(e.clone()),
            }
        }
    }
    Ok(ns)
}

/// Answers "Can you X?" for the robot executing `current`: the first
/// behaviour of that name that can be inserted after the current subgoal
/// (Han §7.2 inserts even the subgoal being done, after itself); when none
/// can, the reason for the first, naming it by uid.
pub fn can_you(tree: &Tree, current: Uid, x: &str) -> Result<Insertion, String> {
    let Some(p) = subgoal(tree, current) else {
        return Err(refuse(x, "I don't have a subgoal to do it after"));
    };
    let named = find_named(tree, p, x);
    if named.is_empty() {
        return Err(refuse(x, "no sequence or subtree of mine is called that"));
    }
    if tree.parent(p).is_none() {
        return Err(refuse(x, "my subgoal is the whole tree"));
    }
    let mut first_refusal = None;
    for &n in &named {
        match insertable(tree, n, p) {
            Ok(ns) => {
                return Ok(Insertion {
                    named: n,
                    copy_of: ns,
                    after: p,
                    answer: format!("Yes. I will {} after {}.", tree.deed(n), tree.deed(p)),
                })
            }
            Err(why) => {
                first_refusal.get_or_insert((n, why));
            }
        }
    }
    let (n, why) = first_refusal.expect("one behaviour at least");
    Err(format!(
        "Sorry. I cannot redo \"{x}\" (#{n}): {why}{}.",
        if named.len() > 1 {
            format!(
                " (nor any of the {} other behaviours of that name)",
                named.len() - 1
            )
        } else {
            String::new()
        }
    ))
}

/// Algorithm 8 for `named`, and whether its self-contained node can go
/// after the subgoal `p`: not when it contains `p` (it would contain itself).
fn insertable(tree: &Tree, named: Uid, p: Uid) -> Result<Uid, String> {
    let ns = self_contained(tree, named).map_err(|e| {
        format!(
            "nothing I can do provides \"{}\", which it needs",
            e.display(tree)
        )
    })?;
    if tree.is_ancestor(ns, p) && ns == named {
        return Err("it contains what I am doing now".to_string());
    }
    if tree.is_ancestor(ns, p) {
        return Err(format!(
            "it needs all of \"{}\" (#{ns}), which contains what I am doing now",
            tree.spoken(ns)
        ));
    }
    Ok(ns)
}
