//! The root cause first (#39 item 3): a control node's failure followed
//! down, child by child, to the leaf outcome it comes from, told in one
//! sentence. `btx why` and `btx ask` both lead with it.

use super::calls::step_moment;
use crate::model::{Builtin, Tree, Uid};
use crate::run::Status;
use crate::session::{Index, Moment};

/// A failure's chain: the node asked about first, each child whose
/// outcome ended its parent's call, down to a leaf where it reaches one.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RootCause {
    /// (node, record position of its completion, that completion).
    pub chain: Vec<(Uid, u32, Status)>,
    /// The moment of each completion.
    pub moments: Vec<Moment>,
}

impl RootCause {
    /// The failure of control node `u` at position `p` followed down to the
    /// leaf it comes from, in one sentence: at each node, the child whose
    /// failure ended it since it started (a fallback's, a recovery's or a
    /// retry's first child, whose failure the others only answered; any other
    /// node's last failed child), until a leaf, or an Inverter whose child
    /// succeeded. `None` when no child failed since it started (it failed by
    /// its own rule: a Timeout, a Parallel's count).
    pub fn of(tree: &Tree, idx: &Index, u: Uid, p: u32) -> Option<RootCause> {
        let mut chain: Vec<(Uid, u32, Status)> = vec![(u, p, Status::Failure)];
        let (mut cur, mut pos, mut wanted) = (u, p, Status::Failure);
        while !tree.node(cur).kind.is_leaf() {
            let since = idx.call_start(cur, pos).unwrap_or(0);
            match tree.node(cur).builtin {
                // An outcome forced by design has no cause below it.
                Some(Builtin::ForceFailure | Builtin::ForceSuccess) => break,
                Some(Builtin::Inverter) => {
                    wanted = if wanted == Status::Failure {
                        Status::Success
                    } else {
                        Status::Failure
                    }
                }
                _ => {}
            }
            let last_of = |c: Uid| {
                idx.changes_of(c).iter().copied().rev().find(|&q| {
                    q > since && q < pos && idx.transitions[q as usize - 1].status == wanted
                })
            };
            let kids = &tree.node(cur).children;
            let primary_first =
                wanted == Status::Failure && crate::explain::failure::handles_failure(tree, cur);
            let found = if primary_first {
                kids.iter().find_map(|&c| last_of(c).map(|q| (c, q)))
            } else {
                kids.iter()
                    .filter_map(|&c| last_of(c).map(|q| (c, q)))
                    .max_by_key(|&(_, q)| q)
            };
            let Some((c, q)) = found else { break };
            chain.push((c, q, wanted));
            (cur, pos) = (c, q);
        }
        let moments = chain.iter().map(|&(_, q, _)| step_moment(idx, q)).collect();
        (chain.len() >= 2).then_some(RootCause { chain, moments })
    }

    /// The leaf the chain reaches, if it reaches one.
    pub fn leaf(&self, tree: &Tree) -> Option<Uid> {
        let &(u, _, _) = self.chain.last()?;
        tree.node(u).kind.is_leaf().then_some(u)
    }

    /// "X failed at 7:4 because Y failed at 7:1, because Z returned FAILURE
    /// at 7:1."
    pub fn text(&self, tree: &Tree) -> String {
        let did = |c: Uid, q: Moment, st: Status| {
            let verb = if tree.node(c).kind.is_leaf() {
                format!("returned {}", st.as_str())
            } else if st == Status::Success {
                "succeeded".to_string()
            } else {
                "failed".to_string()
            };
            format!("{} {verb} at {q}", tree.told(c))
        };
        let u = self.chain[0].0;
        let steps: Vec<String> = self.chain[1..]
            .iter()
            .zip(&self.moments[1..])
            .map(|(&(c, _, st), &m)| did(c, m, st))
            .collect();
        // A chain that stops above the leaves stops at a node that fails
        // by its own rule: say which.
        let last = self.chain.last().map_or(u, |c| c.0);
        let rule = match tree.node(last).builtin {
            Some(Builtin::ForceFailure) => ", as a ForceFailure does whatever its child returns",
            Some(Builtin::Precondition) => ", its `if` being false",
            _ => "",
        };
        format!(
            "{} failed at {} because {}{rule}.",
            super::english::capitalised(&tree.told(u)),
            self.moments[0],
            steps.join(", because ")
        )
    }
}
