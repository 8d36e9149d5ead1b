//! Changing a tree: inserting a copy of a subtree (Han et al.'s Alg. 9).

use super::{Tree, Uid};

/// A "Yes" to "Can you X?": what to insert where (`explain::insert`
/// decides it).
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

impl Tree {
    /// A tree with a copy of `src` (and everything below it) inserted right
    /// after `after`, as its next sibling. Existing nodes keep their uids; the
    /// copy is numbered from `len + 1` depth-first, which is returned too.
    /// The copy reads and writes the same blackboard entries as the original.
    pub fn with_copy_after(&self, src: Uid, after: Uid) -> Result<(Tree, Uid), String> {
        let Some(parent) = self.get(after).and_then(|n| n.parent) else {
            return Err(format!("cannot insert after #{after}: it has no parent"));
        };
        if self.get(src).is_none() {
            return Err(format!("there is no node #{src}"));
        }
        let mut t = self.clone();
        let first = (t.nodes.len() + 1) as Uid;
        // (original, new parent)
        let mut stack = vec![(src, parent)];
        let mut top = None;
        while let Some((orig, new_parent)) = stack.pop() {
            let uid = (t.nodes.len() + 1) as Uid;
            let mut n = self.node(orig).clone();
            n.uid = uid;
            n.parent = Some(new_parent);
            n.depth = t.node(new_parent).depth + 1;
            n.children = Vec::new();
            if top.is_none() {
                top = Some(uid);
            } else {
                t.nodes[(new_parent - 1) as usize].children.push(uid);
            }
            t.nodes.push(n);
            // Reversed, so the stack hands them out in order (depth-first uids).
            for &c in self.node(orig).children.iter().rev() {
                stack.push((c, uid));
            }
        }
        let top = top.expect("the copy has a top");
        let siblings = &mut t.nodes[(parent - 1) as usize].children;
        let at = siblings
            .iter()
            .position(|&c| c == after)
            .expect("after is a child of its parent")
            + 1;
        siblings.insert(at, top);
        Ok((t, first))
    }
}
