//! [`Tree`] → BehaviorTree.CPP 4 XML. Written so that BehaviorTree.CPP 4.10
//! loads it and btx reads it back with the same names and answers; this is
//! what makes `btx tree --format xml` a v3 → v4 converter without the bugs of
//! the library's own script (IDs with spaces, the retry typo, SubTree names).

use crate::model::*;
use std::collections::{HashMap, HashSet};
use std::fmt::Write;

/// A v4 model name: BehaviorTree.CPP ≥ 4.8.4 forbids spaces and
/// `<>&"'/\:*?|.`, and the compact form needs a valid XML element name.
pub fn sanitize_id(id: &str) -> String {
    let mut s: String = id
        .chars()
        .map(|c| {
            if c.is_alphanumeric() || c == '_' || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if s.is_empty() || s.starts_with(|c: char| c.is_ascii_digit() || c == '-') {
        s.insert(0, '_');
    }
    if s == "Root" {
        s.push('_');
    }
    s
}

fn escape(v: &str) -> String {
    let mut out = String::with_capacity(v.len());
    for c in v.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\n' => out.push_str("&#10;"),
            '\r' => out.push_str("&#13;"),
            '\t' => out.push_str("&#9;"),
            c => out.push(c),
        }
    }
    out
}

/// BehaviorTree.CPP's own nodes need no model; Nav2's do, for the library
/// or Groot2 to read the file without Nav2.
fn is_builtin(id: &str) -> bool {
    id == "SubTree" || crate::model::builtins::lookup(id).is_some_and(|s| s.builtin.is_btcpp())
}

/// Maps every custom and tree ID to a unique valid v4 name.
struct Names {
    map: HashMap<String, String>,
    /// Custom IDs the file uses as two kinds (a v3 `<Condition ID="x"/>`
    /// and `<Action ID="x"/>`): written in the explicit form, which keeps
    /// each node's kind, with no model.
    two_kinds: HashSet<String>,
}

impl Names {
    fn new(tree: &Tree) -> Names {
        // Nav2's spellings are free: its models keep their own names.
        let mut taken: HashSet<String> = crate::model::builtins::BUILTINS
            .iter()
            .filter(|s| s.builtin.is_btcpp())
            .map(|s| s.spelling.to_string())
            .collect();
        taken.insert("SubTree".into());
        let mut map = HashMap::new();
        let mut ids: Vec<&str> = vec![tree.main_tree.as_str()];
        for n in &tree.nodes {
            if n.builtin.is_none() || n.kind == Kind::SubTree {
                ids.push(&n.id);
            }
        }
        ids.extend(
            tree.models
                .keys()
                .map(String::as_str)
                .filter(|id| !is_builtin(id)),
        );
        for id in ids {
            if map.contains_key(id) {
                continue;
            }
            let base = sanitize_id(id);
            let mut cand = base.clone();
            let mut k = 2;
            while taken.contains(&cand) {
                cand = format!("{base}_{k}");
                k += 1;
            }
            taken.insert(cand.clone());
            map.insert(id.to_string(), cand);
        }
        let mut kinds: HashMap<&str, Kind> = HashMap::new();
        let mut two_kinds = HashSet::new();
        for n in tree.nodes.iter().filter(|n| n.builtin.is_none()) {
            if *kinds.entry(&n.id).or_insert(n.kind) != n.kind {
                two_kinds.insert(n.id.clone());
            }
        }
        Names { map, two_kinds }
    }

    fn get<'a>(&'a self, id: &'a str) -> &'a str {
        self.map.get(id).map(String::as_str).unwrap_or(id)
    }
}

/// Writes the tree as BehaviorTree.CPP 4 XML: one `<BehaviorTree>` per tree
/// definition (taken from its first instance), and a `<TreeNodesModel>` that
/// declares every custom node and the ports it is given.
pub fn to_v4_xml(tree: &Tree) -> String {
    let names = Names::new(tree);
    let mut out = String::new();
    let _ = writeln!(
        out,
        "<root BTCPP_format=\"4\" main_tree_to_execute=\"{}\">",
        escape(names.get(&tree.main_tree))
    );
    // Definitions in order of first use.
    let mut defs: Vec<(String, Uid)> = vec![(tree.main_tree.clone(), Tree::ROOT)];
    let mut seen: HashSet<&str> = HashSet::from([tree.main_tree.as_str()]);
    for n in &tree.nodes {
        if n.kind == Kind::SubTree && seen.insert(&n.id) {
            if let Some(&c) = n.children.first() {
                defs.push((n.id.clone(), c));
            }
        }
    }
    for (id, root) in &defs {
        let _ = writeln!(out, "  <BehaviorTree ID=\"{}\">", escape(names.get(id)));
        write_node(tree, &names, *root, false, &mut out);
        out.push_str("  </BehaviorTree>\n");
    }
    for (_, block) in &tree.unused {
        out.push_str(block);
    }
    write_models(tree, &names, &mut out);
    out.push_str("</root>\n");
    out
}

/// Writes the tree as BehaviorTree.CPP 4 writes an instantiated tree
/// (`WriteTreeToXML(tree, true)`, in `.btlog` files and Groot2's `T`
/// reply): one `<BehaviorTree>` per SubTree instance with its `_fullpath`,
/// every node with its `_uid`.
pub fn to_instantiated_xml(tree: &Tree) -> String {
    let names = Names::new(tree);
    let mut out = String::from("<root BTCPP_format=\"4\">\n");
    let mut instances: Vec<(String, String, Uid)> =
        vec![(tree.main_tree.clone(), String::new(), Tree::ROOT)];
    for u in tree.preorder() {
        let n = tree.node(u);
        if let (Kind::SubTree, Some(&c), Some(s)) = (n.kind, n.children.first(), n.opens_scope) {
            instances.push((n.id.clone(), tree.scope_path(s), c));
        }
    }
    for (id, path, root) in &instances {
        let _ = writeln!(
            out,
            "  <BehaviorTree ID=\"{}\" _fullpath=\"{}\">",
            escape(names.get(id)),
            escape(path)
        );
        write_node(tree, &names, *root, true, &mut out);
        out.push_str("  </BehaviorTree>\n");
    }
    write_models(tree, &names, &mut out);
    out.push_str("</root>\n");
    out
}

enum Step {
    Open(Uid, usize),
    Close(String, usize),
}

fn write_node(tree: &Tree, names: &Names, root: Uid, instantiated: bool, out: &mut String) {
    let mut stack = vec![Step::Open(root, 2)];
    while let Some(step) = stack.pop() {
        match step {
            Step::Close(tag, depth) => {
                let _ = writeln!(out, "{}</{}>", "  ".repeat(depth), tag);
            }
            Step::Open(uid, depth) => {
                let n = tree.node(uid);
                let (tag, mut attrs) = element_of(tree, names, uid);
                if instantiated {
                    if let Some(s) = n.opens_scope.filter(|_| n.kind == Kind::SubTree) {
                        attrs.push(("_fullpath".into(), tree.scope_path(s)));
                    }
                    attrs.push(("_uid".into(), uid.to_string()));
                }
                let _ = write!(out, "{}<{}", "  ".repeat(depth), tag);
                for (k, v) in &attrs {
                    let _ = write!(out, " {}=\"{}\"", k, escape(v));
                }
                if n.kind == Kind::SubTree || n.children.is_empty() {
                    out.push_str("/>\n");
                } else {
                    out.push_str(">\n");
                    stack.push(Step::Close(tag, depth));
                    for &c in n.children.iter().rev() {
                        stack.push(Step::Open(c, depth + 1));
                    }
                }
            }
        }
    }
}

/// The element name and attributes that express one node in v4.
fn element_of(tree: &Tree, names: &Names, uid: Uid) -> (String, Vec<(String, String)>) {
    let n = tree.node(uid);
    let mut attrs: Vec<(String, String)> = Vec::new();
    if n.kind == Kind::SubTree {
        attrs.push(("ID".into(), names.get(&n.id).to_string()));
        attrs.push(("name".into(), n.name.clone()));
        for p in &n.ports {
            attrs.push((p.name.clone(), p.value.to_xml()));
        }
        if let Some(s) = n.opens_scope.map(|s| &tree.scopes[s]) {
            if s.autoremap || s.shared {
                attrs.push(("_autoremap".into(), "true".into()));
            }
        }
        attrs.extend(n.scripts.iter().chain(&n.metadata).cloned());
        return (String::from("SubTree"), attrs);
    }
    let tag = match n.builtin {
        Some(b) => match b.v4_name() {
            Some(t) => t.to_string(),
            None => return blackboard_check(tree, uid),
        },
        None if names.two_kinds.contains(&n.id) => {
            attrs.push(("ID".into(), names.get(&n.id).to_string()));
            n.kind.as_str().to_string()
        }
        None => names.get(&n.id).to_string(),
    };
    let keep_name = if n.builtin.is_some() && !n.kind.is_leaf() {
        tree.has_name(uid)
    } else if n.builtin.is_none() {
        tree.description(uid) != names.get(&n.id)
    } else {
        tree.description(uid) != tag
    };
    if keep_name {
        attrs.push(("name".into(), tree.description(uid).to_string()));
    }
    for p in &n.ports {
        let name = match (n.builtin, p.name.as_str()) {
            (Some(Builtin::Parallel), "success_threshold") => "success_count",
            (Some(Builtin::Parallel), "failure_threshold") => "failure_count",
            (_, other) => other,
        };
        attrs.push((name.to_string(), p.value.to_xml()));
    }
    for (k, v) in n.scripts.iter().chain(&n.metadata) {
        attrs.push((k.clone(), v.clone()));
    }
    (tag, attrs)
}

/// v3's `BlackboardCheck*` has no v4 node; the migration guide's replacement is
/// a script, so it becomes `<Precondition if="A == B" else="...">`.
fn blackboard_check(tree: &Tree, uid: Uid) -> (String, Vec<(String, String)>) {
    let n = tree.node(uid);
    let quote = matches!(n.builtin, Some(Builtin::BlackboardCheckString));
    let operand = |port: &str| -> String {
        match n.ports.iter().find(|p| p.name == port).map(|p| &p.value) {
            Some(PortValue::Key(k)) => k.clone(),
            Some(PortValue::RootKey(k)) => format!("@{k}"),
            Some(PortValue::Literal(l)) if quote => format!("'{l}'"),
            Some(PortValue::Literal(l)) => l.clone(),
            None => "''".into(),
        }
    };
    let mut attrs = Vec::new();
    if tree.has_name(uid) {
        attrs.push(("name".into(), tree.description(uid).to_string()));
    }
    attrs.push((
        "if".into(),
        format!("{} == {}", operand("value_A"), operand("value_B")),
    ));
    let otherwise = n
        .ports
        .iter()
        .find(|p| p.name == "return_on_mismatch")
        .map(|p| p.value.to_xml())
        .unwrap_or_else(|| "FAILURE".into());
    attrs.push(("else".into(), otherwise));
    (String::from("Precondition"), attrs)
}

/// A port as the model writes it: name, direction, its model (type,
/// default, description), or a built-in's default.
type PortOut<'a> = (
    String,
    Direction,
    Option<&'a PortModel>,
    Option<&'static str>,
);

/// The `<TreeNodesModel>`: only what was declared, never a guess. A model
/// of the file or of `--models` as it was written; a Nav2 node btx knows,
/// from its spec (BehaviorTree.CPP does not register it); an ID the file
/// only wrote in the explicit form (`<Condition ID="x"/>`), its kind alone.
/// An ID whose kind btx guessed from its children gets none, and one used
/// as two kinds is written in the explicit form instead.
fn write_models(tree: &Tree, names: &Names, out: &mut String) {
    let models = models_written(tree, names);
    if models.is_empty() {
        return;
    }
    out.push_str("  <TreeNodesModel>\n");
    for (kind, id, declared) in models {
        let _ = write!(
            out,
            "    <{} ID=\"{}\"",
            kind.as_str(),
            escape(names.get(id))
        );
        if declared.is_empty() {
            out.push_str("/>\n");
            continue;
        }
        out.push_str(">\n");
        for port in declared {
            write_port(port, out);
        }
        let _ = writeln!(out, "    </{}>", kind.as_str());
    }
    out.push_str("  </TreeNodesModel>\n");
}

/// The models to write, in the order their IDs are first used (then the
/// models of IDs never used): each ID's kind and ports.
fn models_written<'a>(tree: &'a Tree, names: &Names) -> Vec<(Kind, &'a str, Vec<PortOut<'a>>)> {
    let mut order: Vec<&str> = Vec::new();
    let mut first: HashMap<&str, &Node> = HashMap::new();
    let mut guessed: HashSet<&str> = HashSet::new();
    for n in &tree.nodes {
        if n.kind == Kind::SubTree || n.builtin.is_some_and(|b| b.is_btcpp()) {
            continue;
        }
        if !first.contains_key(n.id.as_str()) {
            order.push(&n.id);
            first.insert(&n.id, n);
        }
        if !n.kind_declared {
            guessed.insert(&n.id);
        }
    }
    order.extend(
        tree.models
            .keys()
            .map(String::as_str)
            .filter(|id| !is_builtin(id) && !first.contains_key(id)),
    );
    let mut models: Vec<(Kind, &str, Vec<PortOut>)> = Vec::new();
    for id in order {
        if let Some(m) = tree.models.get(id) {
            let ports = m
                .ports
                .iter()
                .map(|p| (p.name.clone(), p.direction, Some(p), None))
                .collect();
            models.push((m.kind, id, ports));
        } else if let Some(b) = first.get(id).and_then(|n| n.builtin) {
            let spec = b.spec();
            let ports = spec
                .ports
                .iter()
                .map(|&(name, dir, default)| (name.to_string(), dir, None, default))
                .collect();
            models.push((spec.kind, id, ports));
        } else if !guessed.contains(id) && !names.two_kinds.contains(id) {
            models.push((first[id].kind, id, Vec::new()));
        }
    }
    models
}

/// One `<input_port>`, `<output_port>` or `<inout_port>` of a model.
fn write_port((name, dir, pm, spec_default): PortOut, out: &mut String) {
    let tag = match dir {
        Direction::In => "input_port",
        Direction::Out => "output_port",
        Direction::InOut => "inout_port",
    };
    let _ = write!(out, "      <{tag} name=\"{}\"", escape(&name));
    if let Some(d) = spec_default {
        let _ = write!(out, " default=\"{}\"", escape(d));
    }
    if let Some(pm) = pm {
        if let Some(t) = &pm.type_name {
            let _ = write!(out, " type=\"{}\"", escape(t));
        }
        if let Some(d) = &pm.default {
            let _ = write!(out, " default=\"{}\"", escape(d));
        }
        if let Some(desc) = &pm.description {
            let _ = writeln!(out, ">{}</{tag}>", escape(desc));
            return;
        }
    }
    out.push_str("/>\n");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_become_valid_v4_model_names() {
        assert_eq!(sanitize_id("move to"), "move_to");
        assert_eq!(sanitize_id("a.b/c"), "a_b_c");
        assert_eq!(sanitize_id("3d"), "_3d");
        assert_eq!(sanitize_id("Root"), "Root_");
    }

    #[test]
    fn an_instantiated_tree_reads_back_as_a_logs_tree() {
        let path = std::path::Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/tests/fixtures/kitting-tree.v4.xml"
        ));
        let tree = crate::xml::load_file(path, &Default::default())
            .unwrap()
            .tree;
        let xml = to_instantiated_xml(&tree);
        assert!(xml.contains(r#"<SubTree ID="go_insert_large_gear" name="go insert large gear" _fullpath="go insert large gear" _uid="2"/>"#), "{xml}");
        let back = crate::xml::load_str(
            std::path::Path::new("t"),
            &xml,
            &crate::xml::LoadOptions {
                embedded: true,
                ..Default::default()
            },
        )
        .unwrap()
        .tree;
        assert_eq!(back.len(), tree.len());
        for (a, b) in tree.nodes.iter().zip(&back.nodes) {
            assert_eq!((a.uid, &a.name, a.kind), (b.uid, &b.name, b.kind));
        }
    }
}
