//! Renderings of trees, framed trees and answers: indented text, Graphviz DOT
//! and JSON (schemas in the README).

mod dot;
mod json;
mod log;
mod text;

pub use dot::{framed_dot, tree_dot};
pub use json::{answers_json, framed_json, tree_json};
pub use log::{
    each_log_row, log_json, log_json_lines, log_rows, log_text, log_text_row, write_log_json,
    LogRow, LOG_TEXT_HEADER,
};
pub use text::{framed_text, tree_text};

use crate::model::{Kind, Port, PortValue, Tree, Uid};

/// How a node's type reads: `Sequence`, `Action move_to`, `SubTree go_pick`.
pub fn kind_label(tree: &Tree, uid: Uid) -> String {
    let n = tree.node(uid);
    match (n.kind, n.builtin) {
        (Kind::SubTree, _) => format!("SubTree {}", n.id),
        (Kind::Action | Kind::Condition, _) => {
            format!("{} {}", n.kind.as_str(), tree.type_name(uid))
        }
        (_, Some(_)) => tree.type_name(uid).to_string(),
        (k, None) => format!("{} {}", k.as_str(), n.id),
    }
}

/// `in:place="chuck place"`, `out:output={object pose}`.
pub fn port_label(p: &Port) -> String {
    let value = match &p.value {
        PortValue::Literal(s) => format!("{s:?}"),
        other => other.to_xml(),
    };
    match p.direction {
        Some(d) => format!("{}:{}={}", d.as_str(), p.name, value),
        None => format!("{}={}", p.name, value),
    }
}

/// Draws a tree with box-drawing guides, iteratively (trees can be deep).
fn draw<F, C>(root: usize, children: C, mut label: F) -> String
where
    C: Fn(usize) -> Vec<usize>,
    F: FnMut(usize) -> String,
{
    let mut out = String::new();
    // (node, prefix for its children, its own guide)
    let mut stack: Vec<(usize, String, String)> = vec![(root, String::new(), String::new())];
    while let Some((x, prefix, guide)) = stack.pop() {
        out.push_str(&guide);
        out.push_str(&label(x));
        out.push('\n');
        let kids = children(x);
        let last = kids.len().saturating_sub(1);
        for (i, &k) in kids.iter().enumerate().rev() {
            let (g, p) = if i == last {
                ("└─ ", "   ")
            } else {
                ("├─ ", "│  ")
            };
            stack.push((k, format!("{prefix}{p}"), format!("{prefix}{g}")));
        }
    }
    out
}
