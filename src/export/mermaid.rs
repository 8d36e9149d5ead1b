//! Mermaid flowcharts (GitHub renders them in Markdown): the tree and the
//! framed tree. The explanation model's is `causal::graph::mermaid`.

use super::kind_label;
use crate::frame::{Framed, Role};
use crate::model::{Kind, Tree, Uid};
use crate::text::mermaid_label as label;
use std::fmt::Write;

/// A node's shape: `[…]` action, `([…])` condition, `{{…}}` decorator,
/// `[[…]]` subtree, `[/…/]` control.
fn shape(tree: &Tree, uid: Uid) -> (&'static str, &'static str) {
    match tree.node(uid).kind {
        Kind::Action => ("[", "]"),
        Kind::Condition => ("([", "])"),
        Kind::Decorator => ("{{", "}}"),
        Kind::SubTree => ("[[", "]]"),
        Kind::Control => ("[/", "/]"),
    }
}

/// The full tree as a Mermaid flowchart.
pub fn tree_mermaid(tree: &Tree) -> String {
    let mut out = String::from("flowchart TD\n");
    for n in &tree.nodes {
        let (open, close) = shape(tree, n.uid);
        let _ = writeln!(
            out,
            "  n{}{open}\"{}<br/>{} #35;{}\"{close}",
            n.uid,
            label(&kind_label(tree, n.uid)),
            label(tree.description(n.uid)),
            n.uid
        );
    }
    for n in &tree.nodes {
        for c in &n.children {
            let _ = writeln!(out, "  n{} --> n{c}", n.uid);
        }
    }
    out
}

/// The framed tree as a Mermaid flowchart.
pub fn framed_mermaid(tree: &Tree, framed: &Framed) -> String {
    let mut out = String::from("flowchart TD\n");
    for f in &framed.nodes {
        let (role, open, close) = match f.role {
            Role::Goal => ("goal", "[", "]"),
            Role::Subgoal => ("subgoal", "[[", "]]"),
            Role::Step => ("step", "[/", "/]"),
            Role::Action => ("action", "[", "]"),
        };
        let _ = writeln!(
            out,
            "  n{}{open}\"{role}<br/>{} #35;{}\"{close}",
            f.uid,
            label(tree.description(f.uid)),
            f.uid
        );
    }
    for f in &framed.nodes {
        for &c in &f.children {
            let _ = writeln!(out, "  n{} --> n{}", f.uid, framed.nodes[c].uid);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_kitting_tree_is_a_flowchart_of_every_node_and_edge() {
        let tree = crate::xml::load_file(
            std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/trees/kitting.xml")),
            &Default::default(),
        )
        .unwrap()
        .tree;
        let m = tree_mermaid(&tree);
        assert!(m.starts_with("flowchart TD\n"));
        assert_eq!(
            m.lines().filter(|l| l.contains("-->")).count(),
            tree.len() - 1
        );
        assert!(
            m.contains("  n18[\"Action look_at<br/>look at chuck #35;18\"]"),
            "{m}"
        );
        let f = framed_mermaid(&tree, &Framed::new(&tree));
        assert!(
            f.contains("[[\"subgoal<br/>go insert large gear #35;2\"]]"),
            "{f}"
        );
    }
}
