use super::kind_label;
use crate::frame::{Framed, Role};
use crate::model::{Kind, Tree, Uid};
use std::fmt::Write;

fn esc(s: &str) -> String {
    s.replace('\\', "\\\\")
        .replace('"', "\\\"")
        .replace('\n', "\\n")
}

/// Groot's palette: sequences pink, fallbacks blue, conditions green.
fn style(tree: &Tree, uid: Uid) -> (&'static str, &'static str) {
    let n = tree.node(uid);
    match n.kind {
        Kind::Action => ("box", "#ffffff"),
        Kind::Condition => ("ellipse", "#c8e6c9"),
        Kind::Decorator => ("diamond", "#fff3c4"),
        Kind::SubTree => ("folder", "#eeeeee"),
        Kind::Control => {
            let t = tree.type_name(uid);
            if t.contains("Fallback") {
                ("box", "#bbdefb")
            } else if t.contains("Sequence") {
                ("box", "#f8bbd0")
            } else {
                ("box", "#e1bee7")
            }
        }
    }
}

/// The full tree for Graphviz.
pub fn tree_dot(tree: &Tree) -> String {
    let mut out = String::from("digraph btx {\n  rankdir=TB;\n  node [fontname=\"Helvetica\", style=\"filled,rounded\"];\n");
    for n in &tree.nodes {
        let (shape, fill) = style(tree, n.uid);
        let _ = writeln!(
            out,
            "  n{} [label=\"{}\\n{}\\n#{}\", shape={}, fillcolor=\"{}\"];",
            n.uid,
            esc(&kind_label(tree, n.uid)),
            esc(tree.description(n.uid)),
            n.uid,
            shape,
            fill
        );
    }
    for n in &tree.nodes {
        for c in &n.children {
            let _ = writeln!(out, "  n{} -> n{};", n.uid, c);
        }
    }
    out.push_str("}\n");
    out
}

/// The framed tree for Graphviz.
pub fn framed_dot(tree: &Tree, framed: &Framed) -> String {
    let mut out = String::from("digraph btx_framed {\n  rankdir=TB;\n  node [fontname=\"Helvetica\", style=\"filled,rounded\"];\n");
    for f in &framed.nodes {
        let (role, shape, fill) = match f.role {
            Role::Goal => ("goal", "box", "#ffe0b2"),
            Role::Subgoal => ("subgoal", "folder", "#eeeeee"),
            Role::Step => ("step", "box", "#f8bbd0"),
            Role::Action => ("action", "box", "#ffffff"),
        };
        let _ = writeln!(
            out,
            "  n{} [label=\"{}\\n{}\\n#{}\", shape={}, fillcolor=\"{}\"];",
            f.uid,
            role,
            esc(tree.description(f.uid)),
            f.uid,
            shape,
            fill
        );
    }
    for f in &framed.nodes {
        for &c in &f.children {
            let _ = writeln!(out, "  n{} -> n{};", f.uid, framed.nodes[c].uid);
        }
    }
    out.push_str("}\n");
    out
}
