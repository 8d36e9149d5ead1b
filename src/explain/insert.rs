//! "Can you X?": Han et al.'s Algorithms 8 and 9. Find the behaviour the
//! person names, climb to the self-contained node whose leaves produce every
//! blackboard entry it reads, and insert that after the current subgoal.

use super::han::subgoal;
use crate::model::{Builtin, Kind, Tree, Uid};
use crate::run::blackboard::{Blackboard, EntryId};
use std::collections::BTreeSet;

pub use crate::model::edit::Insertion;

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

/// Every behaviour "X" names, those in `scope` first, then in tree order:
/// the Sequences and SubTrees of that name (Han's), else any step or leaf
/// of that name, written or read as words ("back up" for `BackUp`), else
/// the named nodes whose name has every word of X.
fn find_named(tree: &Tree, scope: Uid, x: &str) -> Vec<Uid> {
    let want = x.trim().to_lowercase();
    let words_of = |u: Uid| tree.words_of(u).to_lowercase();
    let exact = |u: Uid| tree.description(u).to_lowercase() == want || words_of(u) == want;
    let all: Vec<Uid> = tree.descendants(Tree::ROOT).collect();
    let mut found: Vec<Uid> = all
        .iter()
        .copied()
        .filter(|&u| is_sequence_or_subtree(tree, u) && exact(u))
        .collect();
    if found.is_empty() {
        found = all.iter().copied().filter(|&u| exact(u)).collect();
    }
    if found.is_empty() {
        let wanted: Vec<&str> = want
            .split_whitespace()
            .filter(|w| !["the", "a", "an", "my", "your", "some"].contains(w))
            .collect();
        found = all
            .iter()
            .copied()
            .filter(|&u| {
                let name = words_of(u);
                let have: Vec<&str> = name.split_whitespace().collect();
                tree.has_name(u) && !wanted.is_empty() && wanted.iter().all(|w| have.contains(w))
            })
            .collect();
    }
    let (mut inside, outside): (Vec<Uid>, Vec<Uid>) = found
        .into_iter()
        .partition(|&u| u == scope || tree.is_ancestor(scope, u));
    inside.extend(outside);
    inside
}

/// Where a tree with no subgoal to insert after (no SubTree above the
/// current node, or only the whole tree) takes a new behaviour: after the
/// current step of the nearest sequence above the current node.
fn step_of_sequence(tree: &Tree, current: Uid) -> Option<(Uid, Uid)> {
    let mut child = current;
    for a in tree.ancestors(current) {
        if matches!(
            tree.node(a).builtin,
            Some(Builtin::Sequence | Builtin::SequenceWithMemory | Builtin::PipelineSequence)
        ) {
            return Some((a, child));
        }
        child = a;
    }
    None
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
/// entry that the leaves below `n` read. Beyond the paper, an entry no leaf
/// of the tree writes is the tree's input (Nav2's `goal`, set by the
/// navigator before the first tick): it is there wherever the behaviour
/// goes, and `available` are entries written before the place it goes.
pub fn self_contained(tree: &Tree, n: Uid) -> Result<Uid, EntryId> {
    self_contained_given(tree, n, &BTreeSet::new())
}

fn self_contained_given(
    tree: &Tree,
    n: Uid,
    available: &BTreeSet<EntryId>,
) -> Result<Uid, EntryId> {
    let bb = Blackboard::new(tree);
    let (needed, _) = leaf_io(tree, &bb, n);
    let (_, written) = leaf_io(tree, &bb, Tree::ROOT);
    let mut ns = n;
    for e in needed
        .iter()
        .filter(|e| written.contains(*e) && !available.contains(*e))
    {
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

/// The behaviours of the tree "X" names, wherever they are ("can you look
/// around?" asked once the run has ended: whether the tree has it at all).
pub fn named_in_tree(tree: &Tree, x: &str) -> Vec<Uid> {
    find_named(tree, Tree::ROOT, x)
}

/// Answers "Can you X?" for the robot executing `current`: the first
/// behaviour of that name that can be inserted after the current subgoal
/// (Han §7.2 inserts even the subgoal being done, after itself); when none
/// can, the reason for the first, naming it by uid.
pub fn can_you(tree: &Tree, current: Uid, x: &str) -> Result<Insertion, String> {
    // Han's place: after the current subgoal. Beyond the paper, where
    // there is none to go after, after the current step of the nearest
    // sequence, said with where.
    let (p, within) = match subgoal(tree, current).filter(|&g| tree.parent(g).is_some()) {
        Some(g) => (g, None),
        None => match step_of_sequence(tree, current) {
            Some((seq, step)) => (step, Some(seq)),
            None => {
                return Err(refuse(
                    x,
                    &format!(
                        "nothing above {} (#{current}) is a sequence or subgoal to do it after",
                        tree.spoken(current)
                    ),
                ))
            }
        },
    };
    let named = find_named(tree, p, x);
    if named.is_empty() {
        return Err(refuse(x, &none_called(tree, x)));
    }
    let mut first_refusal = None;
    for &n in &named {
        match insertable(tree, n, p, within) {
            Ok(ns) => {
                let answer = match within {
                    None => format!("Yes. I will {} after {}.", tree.deed(n), tree.deed(p)),
                    Some(seq) => format!(
                        "Yes. I will {} after {}, the step of {} (#{seq}) I am on.",
                        tree.deed(n),
                        tree.deed(p),
                        tree.spoken(seq)
                    ),
                };
                return Ok(Insertion {
                    named: n,
                    copy_of: ns,
                    after: p,
                    answer,
                });
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

/// Why no behaviour is called X: none is, and the closest names, those
/// that hold X's letters in order, as the finder matches.
fn none_called(tree: &Tree, x: &str) -> String {
    let items: Vec<(String, Uid)> = tree
        .descendants(Tree::ROOT)
        .filter(|&u| tree.has_name(u))
        .map(|u| (tree.words_of(u), u))
        .collect();
    let matcher = fuzzy_matcher::skim::SkimMatcherV2::default().ignore_case();
    let close: Vec<String> = crate::rank::rank(x, &items, 3)
        .into_iter()
        .filter(|&u| {
            fuzzy_matcher::FuzzyMatcher::fuzzy_match(&matcher, &tree.words_of(u), x).is_some()
        })
        .map(|u| format!("\"{}\" (#{u})", tree.spoken(u)))
        .collect();
    let none = "no subgoal, sequence or step of mine is called that";
    if close.is_empty() {
        none.to_string()
    } else {
        format!("{none} (the closest: {})", super::han::and_list(&close))
    }
}

/// Algorithm 8 for `named`, and whether its self-contained node can go
/// after the subgoal `p`: not when it contains `p` (it would contain itself).
fn insertable(tree: &Tree, named: Uid, p: Uid, within: Option<Uid>) -> Result<Uid, String> {
    // After the current step of a sequence (beyond the paper), what the
    // steps up to it wrote is there already.
    let available = match within {
        Some(_) => written_up_to(tree, p),
        None => BTreeSet::new(),
    };
    let ns = self_contained_given(tree, named, &available).map_err(|e| {
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

/// Entries written by the leaves that come, in tree order, no later than
/// the last leaf of `p`: those a behaviour inserted right after `p` finds.
fn written_up_to(tree: &Tree, p: Uid) -> BTreeSet<EntryId> {
    let bb = Blackboard::new(tree);
    let last = tree.leaves_below(p).last().unwrap_or(p);
    let mut out = BTreeSet::new();
    for u in tree.preorder() {
        if tree.node(u).kind.is_leaf() {
            out.extend(leaf_io(tree, &bb, u).1);
        }
        if u == last {
            break;
        }
    }
    out
}

/// "Can you X?" asked of a run about to be recorded, at the end of `tick`:
/// the behaviour named (the whole text when it is not such a question) and
/// Algorithms 8 and 9 to decide it with when the tick comes.
pub fn asked_during_run(tick: u32, question: &str) -> crate::session::record::Asked {
    let behaviour = match super::Question::parse(question) {
        Some(super::Question::CanYou(x)) => x,
        _ => question.trim().to_string(),
    };
    crate::session::record::Asked {
        tick,
        behaviour,
        decide: can_you,
    }
}
