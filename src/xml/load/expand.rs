//! Expanding the main tree: each SubTree instance in place, numbered as
//! BehaviorTree.CPP numbers them, with the blackboard scopes it opens;
//! the limits on size and depth, the tree a SubTree calls, cycles.

use super::*;

impl Loader {
    /// Expands the `<BehaviorTree>` `defs[main]` into nodes numbered as
    /// BehaviorTree.CPP numbers them, each SubTree instance expanded in
    /// place, and the blackboard scopes they open.
    pub(super) fn expand(
        &mut self,
        version: Version,
        defs: &[Def],
        roots: &[Option<Element>],
        (by_id, by_fullpath): ByIdAndPath,
        main: usize,
        main_id: &str,
    ) -> Result<(Vec<Node>, Vec<Scope>), Located> {
        let mut nodes: Vec<Node> = Vec::new();
        let mut scopes = vec![Scope {
            parent: None,
            subtree: None,
            remaps: Vec::new(),
            autoremap: false,
            shared: false,
        }];
        let tree_of = |d: &Def| {
            &roots[d.file]
                .as_ref()
                .expect("every file has a root")
                .children[d.idx]
                .children[0]
        };
        // The SubTree IDs on the path from the root: one is added on
        // entering a SubTree and removed by the `Leave` pushed under its
        // subtree, so the cycle check costs one lookup, not a walk up a
        // chain 10^4 deep.
        let mut on_path: std::collections::HashSet<String> =
            std::iter::once(main_id.to_string()).collect();
        let mut stack = vec![Step::Enter(Work {
            el: tree_of(&defs[main]),
            file: defs[main].file,
            parent: None,
            scope: 0,
            depth: 0,
            chain: std::rc::Rc::new(Chain {
                id: main_id.to_string(),
                up: None,
            }),
        })];
        while let Some(step) = stack.pop() {
            let w = match step {
                Step::Enter(w) => w,
                Step::Leave(id) => {
                    on_path.remove(&id);
                    continue;
                }
            };
            // SubTrees that call others twice double the tree at each
            // level: the count and depth after expansion are bounded.
            if nodes.len() >= NODES_MAX || w.depth as usize >= DEPTH_MAX {
                return Err(self.too_big(&w, nodes.len() >= NODES_MAX));
            }
            let uid = Uid::try_from(nodes.len() + 1).expect("fewer than 2^32 nodes");
            let mut node =
                self.make_node(version, w.file, w.el, uid, w.parent, w.scope, w.depth)?;
            if let Some(p) = w.parent {
                nodes[(p - 1) as usize].children.push(uid);
            }
            if node.kind == Kind::SubTree {
                let d = &defs[self.subtree_def(&node, &w, (by_id, by_fullpath))?];
                self.check_cycle(&node, &w, &on_path)?;
                on_path.insert(node.id.clone());
                stack.push(Step::Leave(node.id.clone()));
                let inner = enter_subtree(&mut node, &w, (d.file, tree_of(d)), &mut scopes);
                stack.push(Step::Enter(inner));
            } else {
                stack.extend(
                    w.el.children
                        .iter()
                        .rev()
                        .map(|c| Step::Enter(w.child(c, uid))),
                );
            }
            nodes.push(node);
        }
        Ok((nodes, scopes))
    }

    /// The error for a tree that grows past what btx expands.
    fn too_big(&self, w: &Work, nodes: bool) -> Located {
        self.err(
            w.file,
            w.el,
            format!(
                "the tree grows past {} once its SubTrees are expanded; btx stops here (at most {NODES_MAX} nodes, {DEPTH_MAX} levels deep)",
                if nodes {
                    format!("{NODES_MAX} nodes")
                } else {
                    format!("{DEPTH_MAX} levels")
                }
            ),
        )
        .with_help(if nodes {
            "SubTrees that call others more than once multiply the tree at each level"
        } else {
            // Measured with behaviortreepy (docs/limits.md).
            "BehaviorTree.CPP sets no limit of its own but recurses on its stack: BehaviorTree.CPP 4.8 on an 8 MiB stack crashes past about 13,900 levels"
        })
    }

    /// The `<BehaviorTree>` a SubTree node calls: by its `_fullpath` (a
    /// log's tree), else by its ID.
    fn subtree_def(
        &self,
        node: &Node,
        w: &Work,
        (by_id, by_fullpath): ByIdAndPath,
    ) -> Result<usize, Located> {
        let by_path =
            w.el.attr("_fullpath")
                .and_then(|p| by_fullpath.get(p).copied());
        let Some(di) = by_path.or_else(|| by_id.get(&node.id).copied()) else {
            let items: Vec<(String, String)> =
                by_id.keys().map(|k| (k.clone(), k.clone())).collect();
            const ELSEWHERE: &str = "tree defined in another file is read with --with FILE|DIR (a directory: every .xml in it)";
            let help = match crate::rank::misspelt(&node.id, by_id.keys().map(String::as_str)) {
                Some(k) => format!("did you mean \"{k}\"? Else a {ELSEWHERE}"),
                None => {
                    let near = crate::rank::rank(&node.id, &items, 5);
                    format!("A {ELSEWHERE}; the trees read are: {}", near.join(", "))
                }
            };
            return Err(self
                .err(
                    w.file,
                    w.el,
                    format!(
                        "unknown SubTree ID \"{}\": no <BehaviorTree> read has it",
                        node.id
                    ),
                )
                .with_help(help));
        };
        Ok(di)
    }

    /// A SubTree that includes itself, on the path from the root.
    fn check_cycle(
        &self,
        node: &Node,
        w: &Work,
        on_path: &std::collections::HashSet<String>,
    ) -> Result<(), Located> {
        if on_path.contains(&node.id) {
            let mut cycle: Vec<&str> = Vec::new();
            for c in w.chain.ids() {
                cycle.push(c);
                if c == node.id {
                    break;
                }
            }
            cycle.reverse();
            cycle.push(&node.id);
            return Err(self.err(
                w.file,
                w.el,
                format!(
                    "SubTree \"{}\" includes itself: {}",
                    node.id,
                    cycle.join(" → ")
                ),
            ));
        }
        Ok(())
    }
}

fn subtree_scope(node: &Node, el: &Element, parent: ScopeId) -> Scope {
    {
        let flag = |k: &str| {
            el.attr(k)
                .is_some_and(|v| matches!(v.trim(), "true" | "1" | "True" | "TRUE"))
        };
        let remaps = node
            .ports
            .iter()
            .map(|p| match &p.value {
                PortValue::Key(k) => Remap::Key {
                    inner: p.name.clone(),
                    outer: k.clone(),
                },
                PortValue::RootKey(k) => Remap::RootKey {
                    inner: p.name.clone(),
                    outer: k.clone(),
                },
                PortValue::Literal(v) => Remap::Literal {
                    inner: p.name.clone(),
                    value: v.clone(),
                },
            })
            .collect();
        Scope {
            parent: Some(parent),
            subtree: Some(node.uid),
            remaps,
            autoremap: flag("_autoremap") || flag("__autoremap"),
            shared: flag("__shared_blackboard"),
        }
    }
}

/// An element to expand, where it goes in the tree.
struct Work<'a> {
    el: &'a Element,
    file: FileId,
    parent: Option<Uid>,
    scope: ScopeId,
    depth: u32,
    chain: std::rc::Rc<Chain>,
}

impl<'a> Work<'a> {
    /// The work of one child element of the node `uid` that `self` made.
    fn child(&self, el: &'a Element, uid: Uid) -> Work<'a> {
        Work {
            el,
            file: self.file,
            parent: Some(uid),
            scope: self.scope,
            depth: self.depth + 1,
            chain: self.chain.clone(),
        }
    }
}

/// Enters the SubTree `node` made from `w`: the blackboard scope it opens
/// is pushed on `scopes`, and the work returned is its tree's root `el`
/// (in `file`), one level deeper with the SubTree's ID on its chain.
fn enter_subtree<'a>(
    node: &mut Node,
    w: &Work<'a>,
    (file, el): (FileId, &'a Element),
    scopes: &mut Vec<Scope>,
) -> Work<'a> {
    scopes.push(subtree_scope(node, w.el, w.scope));
    node.opens_scope = Some(scopes.len() - 1);
    Work {
        el,
        file,
        parent: Some(node.uid),
        scope: scopes.len() - 1,
        depth: w.depth + 1,
        chain: std::rc::Rc::new(Chain {
            id: node.id.clone(),
            up: Some(w.chain.clone()),
        }),
    }
}

/// Expanding is depth first on a stack of its own (a chain of SubTrees may
/// be 10^4 deep): an element to enter, or a SubTree left.
enum Step<'a> {
    Enter(Work<'a>),
    Leave(String),
}

struct Chain {
    id: String,
    up: Option<std::rc::Rc<Chain>>,
}

impl Chain {
    fn ids(&self) -> impl Iterator<Item = &str> {
        std::iter::successors(Some(self), |c| c.up.as_deref()).map(|c| c.id.as_str())
    }
}
