//! The explanation model as a graph to read: DOT for Graphviz, and JSON.

use super::english::{value_json, value_text};
use super::model::{Model, VarKind};
use petgraph::visit::EdgeRef;
use serde_json::{json, Value};

fn kind_str(k: VarKind) -> &'static str {
    match k {
        VarKind::Executed(_) => "executed",
        VarKind::Status(_) => "status",
        VarKind::Decision(_) => "decision",
        VarKind::Attempts(_) => "attempts",
        VarKind::State { .. } => "state",
    }
}

fn esc(s: &str) -> String {
    s.replace('\\', "\\\\").replace('"', "\\\"")
}

pub fn dot(m: &Model) -> String {
    let mut out = format!(
        "// explanation model of tick {}: {} variables, {} edges\ndigraph model {{\n  rankdir=TB;\n  node [fontname=\"monospace\", fontsize=10];\n",
        m.facts.tick,
        m.vars.len(),
        m.edge_count()
    );
    for (v, info) in m.vars.iter().enumerate() {
        let (shape, colour) = match info.kind {
            VarKind::Executed(_) => ("box", "#dbe9f6"),
            VarKind::Status(_) => ("box", "#d5f0d5"),
            VarKind::Decision(_) => ("box", "#f6e3c6"),
            VarKind::Attempts(_) => ("box", "#eadcf4"),
            VarKind::State { .. } => ("ellipse", "#ececec"),
        };
        out.push_str(&format!(
            "  v{v} [label=\"{}\\n= {}\", shape={shape}, style=filled, fillcolor=\"{colour}\"];\n",
            esc(&m.var_name(v)),
            esc(&value_text(&m.fact[v]))
        ));
    }
    for e in m.graph.edge_references() {
        out.push_str(&format!(
            "  v{} -> v{};\n",
            e.source().index(),
            e.target().index()
        ));
    }
    out.push_str("}\n");
    out
}

/// The model as a Mermaid flowchart: each variable with its value, edges
/// from cause to effect.
pub fn mermaid(m: &Model) -> String {
    use crate::text::mermaid_label as label;
    let mut out = format!(
        "%% explanation model of tick {}: {} variables, {} edges\nflowchart TD\n",
        m.facts.tick,
        m.vars.len(),
        m.edge_count()
    );
    for (v, info) in m.vars.iter().enumerate() {
        let (open, close) = match info.kind {
            VarKind::State { .. } => ("([", "])"),
            _ => ("[", "]"),
        };
        out.push_str(&format!(
            "  v{v}{open}\"{} = {}\"{close}\n",
            label(&m.var_name(v)),
            label(&value_text(&m.fact[v]))
        ));
    }
    for e in m.graph.edge_references() {
        out.push_str(&format!(
            "  v{} --> v{}\n",
            e.source().index(),
            e.target().index()
        ));
    }
    out
}

pub fn json(m: &Model) -> Value {
    let nodes: Vec<Value> = m
        .vars
        .iter()
        .enumerate()
        .map(|(v, info)| {
            json!({
                "id": v,
                "name": m.var_name(v),
                "kind": kind_str(info.kind),
                "value": value_json(&m.fact[v]),
                "range": info.range.iter().map(value_json).collect::<Vec<_>>(),
                "intervene": info.intervene,
                "parents": m.parents[v],
            })
        })
        .collect();
    json!({
        "tick": m.facts.tick,
        "nodes": m.vars.len(),
        "edges": m.edge_count(),
        "extension_edges": m.extension_edges,
        "variables": nodes,
        "unfaithful": m.unfaithful(),
    })
}
