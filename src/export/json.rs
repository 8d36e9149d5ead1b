use crate::frame::{steps, Framed};
use crate::model::{Tree, Uid};
use serde_json::{json, Value};

fn node_ref(tree: &Tree, uid: Uid) -> Value {
    json!({ "uid": uid, "description": tree.description(uid) })
}

/// A fault, a recovery or a run's end as `btx log --faults` and `btx
/// watch --format json` give it.
pub fn alert_json(tree: &Tree, a: &crate::explain::alerts::Alert) -> Value {
    let node = |u: Option<Uid>| u.map_or(Value::Null, |u| node_ref(tree, u));
    json!({
        "event": a.what,
        "moment": format!("{}:{}", a.tick, a.step),
        "node": node(Some(a.node)),
        "root_cause": node(a.root_cause),
        "handler": node(a.handler),
        "outcome": a.outcome.map(|o| o.as_str()),
        "text": a.text,
        "tick": a.tick,
        "step": a.step,
        "time": a.time_us.map(crate::clock::rfc3339),
        "time_us": a.time_us,
    })
}

/// One node of `btx.tree/2`.
fn node_json(tree: &Tree, n: &crate::model::Node) -> Value {
    let (file, line, column) = tree.location(n.uid);
    let ports: Vec<Value> = n
        .ports
        .iter()
        .map(|p| {
            json!({
                "name": p.name,
                "value": p.value.to_xml(),
                "kind": p.value.kind_str(),
                "key": p.value.key(),
                "direction": p.direction.map(|d| d.as_str()),
            })
        })
        .collect();
    let scripts: serde_json::Map<String, Value> = n
        .scripts
        .iter()
        .map(|(k, v)| (k.clone(), Value::from(v.clone())))
        .collect();
    let metadata: serde_json::Map<String, Value> = n
        .metadata
        .iter()
        .map(|(k, v)| (k.clone(), Value::from(v.clone())))
        .collect();
    let subtree = n.opens_scope.map(|s| {
        let sc = &tree.scopes[s];
        json!({ "id": n.id, "autoremap": sc.autoremap, "shared_blackboard": sc.shared })
    });
    json!({
        "uid": n.uid,
        "kind": n.kind,
        "type": tree.type_name(n.uid),
        "id": n.id,
        "name": n.name,
        "description": tree.description(n.uid),
        "has_name": tree.has_name(n.uid),
        "parent": n.parent,
        "children": n.children,
        "depth": n.depth,
        "ports": ports,
        "scripts": scripts,
        "metadata": metadata,
        "subtree": subtree,
        "source": { "file": file, "line": line, "column": column },
    })
}

/// The tree as `btx.tree/2`: a flat list of nodes in uid order, each
/// naming its parent (a path repeated at every node would grow with the
/// square of a deep tree's depth).
pub fn tree_json(tree: &Tree) -> Value {
    let mut v = tree_json_head(tree);
    v["nodes"] = tree.nodes.iter().map(|n| node_json(tree, n)).collect();
    v
}

fn tree_json_head(tree: &Tree) -> Value {
    json!({
        "schema": "btx.tree/2",
        "btcpp_format": tree.version.number(),
        "main_tree": tree.main_tree,
        "node_count": tree.len(),
    })
}

/// `tree_json` pretty-printed as it is made, a node at a time, to `out`:
/// the same text, in memory one node's.
pub fn write_tree_json(tree: &Tree, out: &mut dyn FnMut(&str)) {
    let head = serde_json::to_string_pretty(&tree_json_head(tree)).expect("JSON values serialise");
    // The head without its closing brace, then the nodes' list.
    out(head.trim_end().trim_end_matches('}').trim_end());
    out(",\n  \"nodes\": [");
    for (i, n) in tree.nodes.iter().enumerate() {
        let node =
            serde_json::to_string_pretty(&node_json(tree, n)).expect("JSON values serialise");
        out(if i == 0 { "\n" } else { ",\n" });
        let indented: Vec<String> = node.lines().map(|l| format!("    {l}")).collect();
        out(&indented.join("\n"));
    }
    out(if tree.nodes.is_empty() {
        "]\n}\n"
    } else {
        "\n  ]\n}\n"
    });
}

/// The framed tree and semantic sets as `btx.framed/1`.
pub fn framed_json(tree: &Tree, framed: &Framed) -> Value {
    let set = |g: Uid| {
        let mut v = node_ref(tree, g);
        v["steps"] = steps(tree, g)
            .into_iter()
            .map(|s| node_ref(tree, s))
            .collect();
        v
    };
    let nodes: Vec<Value> = framed
        .nodes
        .iter()
        .map(|f| {
            json!({
                "uid": f.uid,
                "role": f.role,
                "description": tree.description(f.uid),
                "merged": f.merged,
                "children": f.children.iter().map(|&c| framed.nodes[c].uid).collect::<Vec<_>>(),
            })
        })
        .collect();
    json!({
        "schema": "btx.framed/1",
        "goal": set(framed.goal),
        "subgoals": framed.subgoals.iter().map(|&g| set(g)).collect::<Vec<_>>(),
        "actions": framed.actions.iter().map(|&a| node_ref(tree, a)).collect::<Vec<_>>(),
        "nodes": nodes,
    })
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_tree_written_a_node_at_a_time_is_the_tree_as_one_value() {
        let t = crate::xml::load_file(
            std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/trees/kitting.xml")),
            &Default::default(),
        )
        .unwrap()
        .tree;
        let mut streamed = String::new();
        super::write_tree_json(&t, &mut |s| streamed.push_str(s));
        let whole = serde_json::to_string_pretty(&super::tree_json(&t)).unwrap() + "\n";
        assert_eq!(streamed, whole);
    }
}
