//! Faults and branches (#39 item 5). A FAILURE is a fault when it is an
//! action's, when it made a subgoal or the root fail, when it set a
//! recovery going (a RecoveryNode's first child, a Retry's child), or when
//! a check verifies what an action did before it ("check if grasped"); a
//! control node's, when a fault below it made it fail. A check that
//! answered no and whose parent went on as designed (an e-stop check under
//! an Inverter, Nav2's GoalUpdated and WouldA…RecoveryHelp, a guard at the
//! head of a Sequence) is a branch taken. Jumping to failures and the
//! fleet's lists go by faults.

use crate::model::{Builtin, Kind, Tree, Uid};
use crate::run::Status;
use crate::session::Index;

/// Whether the transition at position `p` (1-based) is a fault.
pub fn is_fault(tree: &Tree, idx: &Index, p: u32) -> bool {
    let Some(t) = idx.transitions.get((p as usize).wrapping_sub(1)).copied() else {
        return false;
    };
    if t.status != Status::Failure {
        return false;
    }
    let n = tree.node(t.uid);
    if is_action(tree, t.uid) || t.uid == Tree::ROOT {
        return true;
    }
    // A control node fails because of what failed below it in this call.
    if !n.kind.is_leaf() {
        let start = idx.call_start(t.uid, p).unwrap_or(0);
        return (start + 1..p).any(|q| {
            let x = idx.transitions[q as usize - 1];
            x.status == Status::Failure
                && tree.node(x.uid).kind.is_leaf()
                && tree.is_ancestor(t.uid, x.uid)
                && is_fault(tree, idx, q)
        });
    }
    reaches_a_goal(tree, idx, t.uid, p) || verifies(tree, t.uid)
}

pub(crate) fn is_action(tree: &Tree, u: Uid) -> bool {
    let n = tree.node(u);
    n.kind == Kind::Action && n.builtin.is_none()
}

/// Whether a check's failure went up, failing each parent in its tick, to
/// the root, a SubTree (Han's subgoal), or a handler that set a recovery
/// going (a RecoveryNode's first child, a Retry's child). Out of a
/// RecoveryNode's recovery branch it goes no further: that failure belongs
/// to the fault that started the recovery (Nav2's WouldA…RecoveryHelp
/// saying no).
fn reaches_a_goal(tree: &Tree, idx: &Index, u: Uid, p: u32) -> bool {
    let end = idx.tick_range(idx.transitions[p as usize - 1].tick).end as u32;
    goes_up_to_a_goal(tree, u, p, |parent, from| {
        let changes = idx.changes_of(parent);
        let after = changes.partition_point(|&q| q <= from);
        changes[after..]
            .iter()
            .copied()
            .take_while(|&q| q <= end)
            .map(|q| (q, idx.transitions[q as usize - 1].status))
            .find(|&(_, s)| matches!(s, Status::Success | Status::Failure))
    })
}

/// `reaches_a_goal` over any record of the tick: `next_done(parent, from)`
/// is the parent's first completion after `from` in the tick (its place
/// and status). A watch reads a tick as it comes (`alerts`), a session
/// through its index: one rule for both.
pub(crate) fn goes_up_to_a_goal<P: Copy>(
    tree: &Tree,
    u: Uid,
    from: P,
    next_done: impl Fn(Uid, P) -> Option<(P, Status)>,
) -> bool {
    let (mut child, mut from) = (u, from);
    while let Some(parent) = tree.parent(child) {
        let pn = tree.node(parent);
        let first = pn.children.first() == Some(&child);
        match pn.builtin {
            Some(Builtin::RecoveryNode) => return first,
            Some(Builtin::RetryUntilSuccessful) => return true,
            _ => {}
        }
        match next_done(parent, from) {
            Some((q, Status::Failure)) => {
                if parent == Tree::ROOT || pn.kind == Kind::SubTree {
                    return true;
                }
                child = parent;
                from = q;
            }
            _ => return false,
        }
    }
    false
}

/// Whether a check comes after an action in its Sequence: it verifies what
/// was done ("check if grasped"), and its no is a fault; a check before
/// any action is a guard, and its no a branch.
pub(crate) fn verifies(tree: &Tree, u: Uid) -> bool {
    let Some(parent) = tree.parent(u) else {
        return false;
    };
    let pn = tree.node(parent);
    let sequence = matches!(
        pn.builtin,
        Some(
            Builtin::Sequence
                | Builtin::SequenceWithMemory
                | Builtin::ReactiveSequence
                | Builtin::AsyncSequence
        )
    );
    sequence
        && pn
            .children
            .iter()
            .take_while(|&&c| c != u)
            .any(|&c| tree.descendants(c).any(|d| is_action(tree, d)))
}
