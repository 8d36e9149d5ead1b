//! The tree model: one expanded tree (every SubTree instance inlined), its
//! nodes numbered as BehaviorTree.CPP numbers them, with the naming rules that
//! make Han et al.'s algorithms answer alike on v3 and v4 files.

pub mod builtins;
pub mod edit;
mod naming;
pub mod nav2;
pub mod nav2_words;

pub use naming::{as_deed, gerund, words, PathKey};

use std::collections::BTreeMap;
use std::path::PathBuf;

pub use builtins::Builtin;

/// A node uid, as BehaviorTree.CPP assigns it (from 1, depth-first in document
/// order, a subtree's nodes right after its SubTree node).
pub type Uid = u32;

/// Index of a blackboard scope (0 is the main tree's).
pub type ScopeId = usize;

/// Index of a source file in [`Tree::files`].
pub type FileId = usize;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Kind {
    Action,
    Condition,
    Control,
    Decorator,
    SubTree,
}

impl Kind {
    pub fn as_str(self) -> &'static str {
        match self {
            Kind::Action => "Action",
            Kind::Condition => "Condition",
            Kind::Control => "Control",
            Kind::Decorator => "Decorator",
            Kind::SubTree => "SubTree",
        }
    }

    pub fn is_leaf(self) -> bool {
        matches!(self, Kind::Action | Kind::Condition)
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Direction {
    In,
    Out,
    InOut,
}

impl Direction {
    pub fn as_str(self) -> &'static str {
        match self {
            Direction::In => "in",
            Direction::Out => "out",
            Direction::InOut => "inout",
        }
    }
}

/// BehaviorTree.CPP major version whose rules a file follows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize)]
pub enum Version {
    V3,
    V4,
}

impl Version {
    pub fn number(self) -> u8 {
        match self {
            Version::V3 => 3,
            Version::V4 => 4,
        }
    }
}

/// What a port is bound to.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum PortValue {
    /// A literal string, converted by the node.
    Literal(String),
    /// `{key}`: an entry of the node's own (subtree) blackboard.
    Key(String),
    /// `{@key}`: an entry of the root blackboard.
    RootKey(String),
}

impl PortValue {
    /// Parses an attribute value; `port` is the port's name, for `{=}`.
    pub fn parse(port: &str, raw: &str) -> PortValue {
        let t = raw.trim();
        if t == "=" || t == "{=}" {
            return PortValue::Key(port.to_string());
        }
        if t.len() >= 2 && t.starts_with('{') && t.ends_with('}') {
            let inner = &t[1..t.len() - 1];
            if let Some(root) = inner.strip_prefix('@') {
                return PortValue::RootKey(root.to_string());
            }
            if inner == "=" {
                return PortValue::Key(port.to_string());
            }
            return PortValue::Key(inner.to_string());
        }
        PortValue::Literal(raw.to_string())
    }

    /// The value as BehaviorTree.CPP 4 XML writes it.
    pub fn to_xml(&self) -> String {
        match self {
            PortValue::Literal(s) => s.clone(),
            PortValue::Key(k) => format!("{{{k}}}"),
            PortValue::RootKey(k) => format!("{{@{k}}}"),
        }
    }

    pub fn key(&self) -> Option<&str> {
        match self {
            PortValue::Literal(_) => None,
            PortValue::Key(k) | PortValue::RootKey(k) => Some(k),
        }
    }

    pub fn kind_str(&self) -> &'static str {
        match self {
            PortValue::Literal(_) => "literal",
            PortValue::Key(_) => "blackboard",
            PortValue::RootKey(_) => "root",
        }
    }
}

#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Port {
    pub name: String,
    pub value: PortValue,
    /// From a `<TreeNodesModel>` or the built-in table; `None` when nothing says.
    pub direction: Option<Direction>,
}

impl Port {
    /// The declared direction, or else Han et al.'s convention (which the
    /// fixture conversion follows too): a port named `output` is an output,
    /// any other an input.
    pub fn assumed_direction(&self) -> Direction {
        self.direction.unwrap_or(if self.name == "output" {
            Direction::Out
        } else {
            Direction::In
        })
    }
}

/// How a SubTree instance's blackboard sees its parent's.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Remap {
    /// The subtree's `inner` key aliases the parent's `outer` key.
    Key { inner: String, outer: String },
    /// The subtree's `inner` key aliases the root blackboard's `outer` key.
    RootKey { inner: String, outer: String },
    /// The subtree's `inner` key starts with this literal value.
    Literal { inner: String, value: String },
}

/// A blackboard scope: the main tree's, or one per SubTree instance.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Scope {
    pub parent: Option<ScopeId>,
    /// The SubTree node that opened this scope.
    pub subtree: Option<Uid>,
    pub remaps: Vec<Remap>,
    /// v4 `_autoremap` / v3 `__autoremap`: unknown keys are looked up in the parent.
    pub autoremap: bool,
    /// v3 `__shared_blackboard`: the subtree uses its parent's blackboard.
    pub shared: bool,
}

/// Where a node was written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Origin {
    pub file: FileId,
    /// Byte range of the start tag in the file.
    pub start: usize,
    pub end: usize,
}

#[derive(Debug, Clone)]
pub struct Node {
    pub uid: Uid,
    pub kind: Kind,
    /// Registration ID as written (v3 IDs may contain spaces).
    pub id: String,
    /// Instance name, after BehaviorTree.CPP's rules for the file's version.
    pub name: String,
    pub builtin: Option<Builtin>,
    pub ports: Vec<Port>,
    /// Pre/post-condition scripts (`_skipIf`, `_onSuccess`, ...), in order.
    pub scripts: Vec<(String, String)>,
    /// Attributes that start with `_` and are neither scripts nor
    /// BehaviorTree.CPP's own (`_collapsed`, `_description`, as editors
    /// write them): not ports, kept as written.
    pub metadata: Vec<(String, String)>,
    /// Whether the file said the node's kind (a built-in, a model, or the
    /// explicit form `<Condition ID="…"/>`), rather than btx guessing it
    /// from the children: a written file declares only what was said.
    pub kind_declared: bool,
    pub parent: Option<Uid>,
    pub children: Vec<Uid>,
    /// The blackboard scope the node's ports resolve in.
    pub scope: ScopeId,
    /// For SubTree nodes: the scope of the subtree they open.
    pub opens_scope: Option<ScopeId>,
    pub depth: u32,
    pub origin: Origin,
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SourceFile {
    pub path: PathBuf,
    pub text: String,
    /// Where each line starts, made the first time a place is asked for:
    /// a node's line is then a binary search, not a count of the newlines
    /// before it (which made `tree --format json` quadratic in the file).
    pub lines: std::sync::OnceLock<Vec<usize>>,
}

impl SourceFile {
    pub fn new(path: PathBuf, text: String) -> SourceFile {
        SourceFile {
            path,
            text,
            lines: std::sync::OnceLock::new(),
        }
    }

    /// 1-based line and column (in characters) of a byte offset, as
    /// `source::line_col` says them.
    pub fn line_col(&self, offset: usize) -> (usize, usize) {
        let starts = self.lines.get_or_init(|| {
            std::iter::once(0)
                .chain(self.text.match_indices('\n').map(|(i, _)| i + 1))
                .collect()
        });
        let offset = crate::source::floor_char_boundary(&self.text, offset.min(self.text.len()));
        let line = starts.partition_point(|&s| s <= offset);
        let start = starts[line - 1];
        (line, self.text[start..offset].chars().count() + 1)
    }
}

/// A port declared by a `<TreeNodesModel>`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PortModel {
    pub name: String,
    pub direction: Direction,
    pub default: Option<String>,
    pub type_name: Option<String>,
    pub description: Option<String>,
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NodeModel {
    pub kind: Kind,
    pub ports: Vec<PortModel>,
}

/// A fully expanded behaviour tree.
#[derive(Debug, Clone)]
pub struct Tree {
    pub version: Version,
    /// The BehaviorTree.CPP major the tree ran on: a session's tree is read
    /// back from v4 XML, and what a node did (Nav2's Humble against Jazzy)
    /// depends on the release it ran on.
    pub release: Version,
    /// The ID of the `<BehaviorTree>` that was executed.
    pub main_tree: String,
    /// Nodes indexed by `uid - 1`.
    pub nodes: Vec<Node>,
    pub scopes: Vec<Scope>,
    /// Models from `<TreeNodesModel>` (custom nodes).
    pub models: BTreeMap<String, NodeModel>,
    pub files: Vec<SourceFile>,
    /// `<BehaviorTree>`s of the file that the main tree does not run, as
    /// (ID, their v4 XML): kept so that writing the tree loses none.
    pub unused: Vec<(String, String)>,
}

impl Tree {
    pub const ROOT: Uid = 1;

    pub fn root(&self) -> &Node {
        &self.nodes[0]
    }

    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    pub fn node(&self, uid: Uid) -> &Node {
        &self.nodes[(uid - 1) as usize]
    }

    pub fn get(&self, uid: Uid) -> Option<&Node> {
        uid.checked_sub(1).and_then(|i| self.nodes.get(i as usize))
    }

    pub fn parent(&self, uid: Uid) -> Option<Uid> {
        self.node(uid).parent
    }

    /// The strict ancestors of a node, nearest first.
    pub fn ancestors(&self, uid: Uid) -> impl Iterator<Item = Uid> + '_ {
        std::iter::successors(self.parent(uid), move |&p| self.parent(p))
    }

    /// Whether `a` is a strict ancestor of `b`.
    pub fn is_ancestor(&self, a: Uid, b: Uid) -> bool {
        self.ancestors(b).any(|x| x == a)
    }

    /// The node and its descendants, depth-first in tree order. (Loaded trees
    /// number nodes this way, but nodes inserted later get the next free uids.)
    pub fn descendants(&self, uid: Uid) -> impl Iterator<Item = Uid> + '_ {
        let mut stack = vec![uid];
        std::iter::from_fn(move || {
            let u = stack.pop()?;
            stack.extend(self.node(u).children.iter().rev());
            Some(u)
        })
    }

    /// Every node, depth-first and left to right from the root.
    pub fn preorder(&self) -> Vec<Uid> {
        self.descendants(Tree::ROOT).collect()
    }

    /// The leaves (actions and conditions) below a node, in tree order.
    pub fn leaves_below(&self, uid: Uid) -> impl Iterator<Item = Uid> + '_ {
        self.descendants(uid)
            .filter(move |&u| self.node(u).kind.is_leaf())
    }

    pub fn is_decorator(&self, uid: Uid) -> bool {
        self.node(uid).kind == Kind::Decorator
    }

    /// The file and 1-based line and column where a node was written.
    pub fn location(&self, uid: Uid) -> (String, usize, usize) {
        let o = self.node(uid).origin;
        let f = &self.files[o.file];
        let (line, col) = f.line_col(o.start);
        (f.path.display().to_string(), line, col)
    }

    /// The node's type as a person reads it: the built-in's v4 name, or the ID.
    /// `SubTree` for subtrees, whose tree ID is their `id`.
    pub fn type_name(&self, uid: Uid) -> &str {
        let n = self.node(uid);
        if n.kind == Kind::SubTree {
            return "SubTree";
        }
        n.builtin.and_then(|b| b.v4_name()).unwrap_or(&n.id)
    }
}

/// Whether two trees have the same shape under the same uids (kinds and
/// parents; names may differ, as between a tree file and a log of it):
/// runs of such trees can be compared transition by transition.
pub fn same_shape(a: &Tree, b: &Tree) -> bool {
    a.len() == b.len()
        && a.nodes
            .iter()
            .zip(&b.nodes)
            .all(|(x, y)| x.kind == y.kind && x.parent == y.parent && x.builtin == y.builtin)
}

#[cfg(test)]
mod source_file_tests {
    use super::SourceFile;

    #[test]
    fn a_place_is_the_line_and_column_source_says() {
        let text = "ab\n  <é>\n\nx".to_string();
        let f = SourceFile::new("t.xml".into(), text.clone());
        for offset in 0..=text.len() + 2 {
            assert_eq!(
                f.line_col(offset),
                crate::source::line_col(&text, offset),
                "{offset}"
            );
        }
    }
}
