//! Framing (Han et al. §5): the semantic sets {goal, subgoals, steps, actions}
//! and the framed tree, in which decorators and the control nodes that only
//! repeat a name are folded away.

use crate::model::{Kind, Tree, Uid};

#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Role {
    Goal,
    Subgoal,
    Step,
    Action,
}

/// A node of the framed tree.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FramedNode {
    pub uid: Uid,
    /// Same-named control nodes below `uid` folded into it (Han: "control
    /// nodes that have a child sharing the same name"), outermost first.
    pub merged: Vec<Uid>,
    pub role: Role,
    pub children: Vec<usize>,
}

/// The framed tree and the semantic sets.
#[derive(Debug, Clone)]
pub struct Framed {
    /// Framed nodes in tree order; index 0 is the goal.
    pub nodes: Vec<FramedNode>,
    pub goal: Uid,
    /// Every SubTree node, in tree order.
    pub subgoals: Vec<Uid>,
    /// Every action and condition, in tree order.
    pub actions: Vec<Uid>,
}

impl Framed {
    pub fn new(tree: &Tree) -> Framed {
        let n = tree.len();
        // rep[uid-1] = index of the framed node that stands for this node.
        let mut rep: Vec<usize> = vec![0; n];
        let mut nodes: Vec<FramedNode> = Vec::new();
        let mut subgoals = Vec::new();
        let mut actions = Vec::new();
        for uid in tree.descendants(Tree::ROOT) {
            let i = (uid - 1) as usize;
            let node = tree.node(uid);
            let parent_rep = node.parent.map(|p| rep[(p - 1) as usize]);
            let role = match (parent_rep, node.kind) {
                (None, _) => Some(Role::Goal),
                (_, Kind::SubTree) => Some(Role::Subgoal),
                (_, Kind::Action | Kind::Condition) => Some(Role::Action),
                (_, Kind::Decorator) => None,
                (Some(pr), Kind::Control) => {
                    if !tree.has_name(uid) {
                        None
                    } else if tree.description(nodes[pr].uid) == tree.description(uid) {
                        nodes[pr].merged.push(uid);
                        None
                    } else {
                        Some(Role::Step)
                    }
                }
            };
            match role {
                Some(role) => {
                    let idx = nodes.len();
                    nodes.push(FramedNode {
                        uid,
                        merged: Vec::new(),
                        role,
                        children: Vec::new(),
                    });
                    if let Some(pr) = parent_rep {
                        nodes[pr].children.push(idx);
                    }
                    rep[i] = idx;
                    match role {
                        Role::Subgoal => subgoals.push(uid),
                        Role::Action => actions.push(uid),
                        _ => {}
                    }
                }
                None => rep[i] = parent_rep.unwrap_or(0),
            }
        }
        Framed {
            nodes,
            goal: Tree::ROOT,
            subgoals,
            actions,
        }
    }
}

/// Han's Algorithm 5: the steps of a goal or subgoal `g`, found depth-first;
/// a named, non-decorator node whose name differs from `g`'s is a step, and
/// the search does not go below it. Beyond the paper: the later children of
/// a Fallback or a Nav2 RecoveryNode the search goes through are what is
/// done when the first fails, not steps to do; those with a name are
/// `recoveries`, the others are left out.
pub fn steps(tree: &Tree, g: Uid) -> Vec<Uid> {
    walk(tree, g).0
}

/// The recoveries met by `steps`: (the branch that may fail, the named
/// recovery, or the named steps in turn of a recovery that has no name), in
/// tree order.
pub fn recoveries(tree: &Tree, g: Uid) -> Vec<(Uid, Vec<Uid>)> {
    walk(tree, g).1
}

/// Whether a node's later children recover from its first one's failure.
pub fn recovers(tree: &Tree, uid: Uid) -> bool {
    use crate::model::Builtin;
    matches!(
        tree.node(uid).builtin,
        Some(
            Builtin::Fallback
                | Builtin::ReactiveFallback
                | Builtin::AsyncFallback
                | Builtin::RecoveryNode
        )
    ) && tree.node(uid).children.len() > 1
}

fn walk(tree: &Tree, g: Uid) -> (Vec<Uid>, Vec<(Uid, Vec<Uid>)>) {
    let g_desc = tree.description(g);
    let mut out = Vec::new();
    let mut recovered = Vec::new();
    let below = |x: Uid, stack: &mut Vec<Uid>, recovered: &mut Vec<(Uid, Vec<Uid>)>| {
        let kids = &tree.node(x).children;
        if recovers(tree, x) {
            // A recovery without a name (Nav2's Sequence of a check and a
            // named ReactiveFallback) recovers by the steps inside it.
            for &c in &kids[1..] {
                if tree.has_name(c) {
                    recovered.push((kids[0], vec![c]));
                } else {
                    let inner = walk(tree, c).0;
                    if !inner.is_empty() {
                        recovered.push((kids[0], inner));
                    }
                }
            }
            stack.push(kids[0]);
        } else {
            stack.extend(kids.iter().rev().copied());
        }
    };
    let mut stack = Vec::new();
    below(g, &mut stack, &mut recovered);
    while let Some(x) = stack.pop() {
        if !tree.is_decorator(x) && tree.has_name(x) && tree.description(x) != g_desc {
            out.push(x);
        } else {
            below(x, &mut stack, &mut recovered);
        }
    }
    (out, recovered)
}
