//! Faults and branches (#39 item 5). A FAILURE is a fault when it is an
//! action's, when it made a subgoal or the root fail, or when it set a
//! recovery going (a RecoveryNode's first child failing); a check that
//! answered no and whose parent went on as designed (an e-stop check under
//! an Inverter, Nav2's GoalUpdated and WouldA…RecoveryHelp) is a branch
//! taken. Jumping to failures, the fleet's lists and "What went wrong?" go
//! by faults.

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
    if n.kind == Kind::Action && n.builtin.is_none() || t.uid == Tree::ROOT {
        return true;
    }
    // A control node fails because of what failed below it in this call:
    // an action there makes its failure that action's fault too.
    if !n.kind.is_leaf() && action_failed_below(tree, idx, t.uid, p) {
        return true;
    }
    // Follow the failure up through its tick.
    let end = idx.tick_range(t.tick).end as u32;
    let (mut child, mut from) = (t.uid, p);
    while let Some(parent) = tree.parent(child) {
        let pn = tree.node(parent);
        if pn.builtin == Some(Builtin::RecoveryNode) && pn.children.first() == Some(&child) {
            return true;
        }
        let changes = idx.changes_of(parent);
        let after = changes.partition_point(|&q| q <= from);
        let next = changes[after..]
            .iter()
            .copied()
            .take_while(|&q| q <= end)
            .find(|&q| {
                matches!(
                    idx.transitions[q as usize - 1].status,
                    Status::Success | Status::Failure
                )
            });
        match next {
            // A SubTree is what Han's framing calls a subgoal.
            Some(q) if idx.transitions[q as usize - 1].status == Status::Failure => {
                if parent == Tree::ROOT || tree.node(parent).kind == Kind::SubTree {
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

/// Whether an action below `u` failed in `u`'s call that ended at `p`.
fn action_failed_below(tree: &Tree, idx: &Index, u: Uid, p: u32) -> bool {
    let start = idx.call_start(u, p).unwrap_or(0);
    idx.transitions[start as usize..p as usize].iter().any(|t| {
        t.status == Status::Failure
            && tree.is_ancestor(u, t.uid)
            && tree.node(t.uid).kind == Kind::Action
            && tree.node(t.uid).builtin.is_none()
    })
}

/// The positions of the run's faults, in order.
pub fn faults(tree: &Tree, idx: &Index) -> Vec<u32> {
    (1..=idx.transitions.len() as u32)
        .filter(|&p| is_fault(tree, idx, p))
        .collect()
}
