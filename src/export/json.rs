use crate::frame::{steps, Framed};
use crate::model::{Tree, Uid};
use serde_json::{json, Value};

fn node_ref(tree: &Tree, uid: Uid) -> Value {
    json!({ "uid": uid, "description": tree.description(uid) })
}

/// The tree as `btx.tree/1`: a flat list of nodes in uid order.
pub fn tree_json(tree: &Tree) -> Value {
    let paths = tree.display_paths();
    let nodes: Vec<Value> = tree
        .nodes
        .iter()
        .map(|n| {
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
                "path": paths[(n.uid - 1) as usize],
                "ports": ports,
                "scripts": scripts,
                "metadata": metadata,
                "subtree": subtree,
                "source": { "file": file, "line": line, "column": column },
            })
        })
        .collect();
    json!({
        "schema": "btx.tree/1",
        "btcpp_format": tree.version.number(),
        "main_tree": tree.main_tree,
        "node_count": tree.len(),
        "nodes": nodes,
    })
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
