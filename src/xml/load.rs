//! BehaviorTree.CPP XML (v3 and v4) → one expanded [`Tree`].

use super::parse::{parse_document, Element};
use crate::model::builtins::{self, Availability};
use crate::model::*;
use crate::source::{Located, Warning};
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};

/// How to read a file.
#[derive(Debug, Clone, Default)]
pub struct LoadOptions {
    /// Force the BehaviorTree.CPP version instead of detecting it.
    pub version: Option<Version>,
    /// Execute this `<BehaviorTree>` instead of the file's main tree.
    pub main_tree: Option<String>,
    /// The tree is embedded in a log or a session: it never reads another
    /// file (BehaviorTree.CPP's instantiated XML has no `<include>`, so one
    /// there is an attempt to read `/etc/passwd` or `/dev/zero`).
    pub embedded: bool,
    /// Models files (`--models`): each gives node kinds and port
    /// directions in a `<TreeNodesModel>` (Nav2's `nav2_tree_nodes.xml`, a
    /// Groot2 palette).
    pub models: Vec<PathBuf>,
    /// More tree files (`--with`): every `<BehaviorTree>` in them is
    /// registered, as BehaviorTree.CPP's `registerBehaviorTreeFromFile`
    /// does, for SubTrees to call; the main tree stays the first file's.
    pub with: Vec<PathBuf>,
    /// The tree file a log's robot ran (`--tree`), read with these options,
    /// in place of the tree the log embeds (`input::open`).
    pub run_tree: Option<PathBuf>,
    /// Which run of a log that holds several (a rosbag's goals), from 1.
    pub run: Option<usize>,
    /// Which `behavior_tree_log` topic of a bag that holds several (one
    /// robot's each, namespaced).
    pub topic: Option<String>,
}

/// The most warnings a load reports one by one.
pub const WARNINGS_MAX: usize = 50;

/// The most nodes a tree may have once its SubTrees are expanded.
pub const NODES_MAX: usize = 250_000;
/// The deepest a tree may be once its SubTrees are expanded.
pub const DEPTH_MAX: usize = 25_000;

/// The most files one tree may include, directly or not.
pub const INCLUDES_MAX: usize = 256;
/// The largest included file btx reads.
pub const INCLUDE_SIZE_MAX: u64 = 64 << 20;

/// A loaded tree and what the loader noticed on the way.
#[derive(Debug, Clone)]
pub struct Loaded {
    pub tree: Tree,
    pub warnings: Vec<Warning>,
}

/// Loads a tree file and the files it includes.
pub fn load_file(path: &Path, opts: &LoadOptions) -> Result<Loaded, Located> {
    let text = crate::source::read_text(path, INCLUDE_SIZE_MAX, "the tree file")?;
    load_str(path, &text, opts)
}

/// Loads a tree from text; `path` names it in messages and anchors includes.
pub fn load_str(path: &Path, text: &str, opts: &LoadOptions) -> Result<Loaded, Located> {
    let mut l = Loader {
        embedded: opts.embedded,
        ..Loader::default()
    };
    l.add_document(path.to_path_buf(), text.to_string())?;
    l.own_files = l.files.len();
    if !opts.embedded {
        for m in &opts.models {
            // The file as read now or before (the tree file itself, say).
            let f = l.add_extra(m, "models file")?;
            let has_models = l.roots[f]
                .as_ref()
                .is_some_and(|r| r.children.iter().any(|c| c.tag == "TreeNodesModel"));
            if !has_models {
                return Err(
                    Located::file(m, "--models: this file has no <TreeNodesModel>")
                        .with_help("give tree files that SubTrees call with --with"),
                );
            }
        }
        for w in &opts.with {
            l.add_extra(w, "tree file")?;
        }
    }
    l.finish(opts)
}

const SCRIPT_ATTRS: &[&str] = &[
    "_failureIf",
    "_successIf",
    "_skipIf",
    "_while",
    "_onSuccess",
    "_onFailure",
    "_onHalted",
    "_post",
];

/// A `<BehaviorTree>`: child `idx` of file `file`'s `<root>`.
struct Def {
    id: Option<String>,
    /// In the instantiated XML that BehaviorTree.CPP embeds in its logs,
    /// one `<BehaviorTree _fullpath=...>` per SubTree instance.
    fullpath: Option<String>,
    file: FileId,
    idx: usize,
}

#[derive(Default)]
struct Loader {
    /// The tree is embedded in a log or a session: no file is read.
    embedded: bool,
    /// Warnings counted past `WARNINGS_MAX`.
    more_warnings: usize,
    files: Vec<SourceFile>,
    /// Each file read, by its canonical path.
    seen: HashMap<PathBuf, FileId>,
    /// Each file's `<root>` element, by file (file 0 is the one opened first).
    roots: Vec<Option<Element>>,
    defs: Vec<Def>,
    /// The IDs of every `<BehaviorTree>` read (a bare `<ID/>` calls one).
    tree_ids: std::collections::HashSet<String>,
    /// The IDs of the `<BehaviorTree>`s read from files (not a log's
    /// instantiated ones, which carry a `_fullpath`): one is defined once.
    defined: std::collections::HashSet<String>,
    models: BTreeMap<String, NodeModel>,
    /// The kind each custom ID was first used as, and where.
    kinds: HashMap<String, (Kind, FileId, usize)>,
    /// IDs with no model, in order of first use: where first, how they are
    /// read, how many uses (said once each, when the tree is loaded).
    unknown: Vec<(String, FileId, usize, &'static str, usize)>,
    unknown_at: HashMap<String, usize>,
    warnings: Vec<Warning>,
    /// Files of the tree itself (the first and its includes); those after
    /// came with `--models` or `--with`, and their trees are never the main
    /// one.
    own_files: usize,
}

/// "an Action", "a Control".
fn a_kind(k: Kind) -> String {
    let s = k.as_str();
    let article = if s.starts_with(['A', 'E', 'I', 'O', 'U']) {
        "an"
    } else {
        "a"
    };
    format!("{article} {s}")
}

impl Loader {
    /// One warning per ID with no model, at its first use, with its count;
    /// then one hint.
    fn say_unknown(&mut self) {
        let unknown = std::mem::take(&mut self.unknown);
        for (id, file, start, what, n) in &unknown {
            let uses = if *n > 1 {
                format!(" ({n} uses; this is the first)")
            } else {
                String::new()
            };
            let mut known: Vec<&str> = crate::model::builtins::spellings().collect();
            known.extend(self.models.keys().map(String::as_str));
            known.extend(crate::model::nav2::NODES.iter().map(|n| n.id));
            let nav2 = crate::model::nav2::lookup(id).is_some();
            let near = match crate::rank::misspelt(id, known).filter(|_| !nav2) {
                Some(k) => format!(
                    "; did you mean \"{k}\"? BehaviorTree.CPP has no \"{id}\" (IDs are case-sensitive) and refuses to load the tree unless your code registers it"
                ),
                None => String::new(),
            };
            self.warn_at(
                *file,
                *start,
                format!("unknown node \"{id}\" has no model in <TreeNodesModel>; treated as {what}{uses}{near}"),
            );
        }
        if let Some((_, file, _, _, _)) = unknown.first() {
            let ids = match unknown.len() {
                1 => "1 node ID has".to_string(),
                n => format!("{n} node IDs have"),
            };
            let msg = format!(
                "{ids} no model: kinds are guessed from the children and ports have no direction; give a models file with --models FILE (Nav2 ships nav2_tree_nodes.xml; Groot2 writes a <TreeNodesModel>), or put one in the file"
            );
            // Said even past the warnings shown: it is what to do about them.
            let f = &self.files[*file];
            self.warnings.push(Warning {
                location: format!("{}:1:1", crate::text::path(&f.path)),
                message: msg,
            });
        }
    }

    fn err(&self, file: FileId, el: &Element, msg: impl Into<String>) -> Located {
        let f = &self.files[file];
        Located::at(&f.path, &f.text, el.start, el.end, msg)
    }

    fn root(&self, file: FileId) -> &Element {
        self.roots[file].as_ref().expect("every file has a root")
    }

    fn def_el(&self, d: &Def) -> &Element {
        &self.root(d.file).children[d.idx]
    }

    fn warn(&mut self, file: FileId, el: &Element, msg: impl Into<String>) {
        self.warn_at(file, el.start, msg);
    }

    fn warn_at(&mut self, file: FileId, start: usize, msg: impl Into<String>) {
        // Past a screenful, warnings are counted, not built (each one
        // costs a scan for its line): a tree of 500,000 unknown leaves
        // loads as fast as one of five.
        if self.warnings.len() >= WARNINGS_MAX {
            self.more_warnings += 1;
            return;
        }
        let f = &self.files[file];
        let (line, col) = crate::source::line_col(&f.text, start);
        self.warnings.push(Warning {
            location: format!("{}:{line}:{col}", crate::text::path(&f.path)),
            message: msg.into(),
        });
    }

    /// Reads a document (once: a file read before is not read again); its
    /// file id.
    fn add_document(&mut self, path: PathBuf, text: String) -> Result<FileId, Located> {
        let key = std::fs::canonicalize(&path).unwrap_or_else(|_| path.clone());
        if let Some(&f) = self.seen.get(&key) {
            return Ok(f);
        }
        let root = parse_document(&path, &text)?;
        let file = self.files.len();
        self.seen.insert(key, file);
        self.files.push(SourceFile::new(path, text));
        if root.tag != "root" {
            return Err(self.err(
                file,
                &root,
                format!("the top element must be <root>, found <{}>", root.tag),
            ));
        }
        self.roots.push(None);
        for (idx, child) in root.children.iter().enumerate() {
            match child.tag.as_str() {
                "include" => self.include(file, child)?,
                "BehaviorTree" => {
                    if child.children.len() != 1 {
                        let id = child.attr("ID").unwrap_or("");
                        return Err(self.err(
                            file,
                            child,
                            format!(
                                "<BehaviorTree ID=\"{id}\"> must have exactly one child, found {}",
                                child.children.len()
                            ),
                        ));
                    }
                    let id = child.attr("ID").map(str::to_string);
                    let fullpath = child.attr("_fullpath").map(str::to_string);
                    if let (Some(id), None) = (&id, &fullpath) {
                        if !self.defined.insert(id.clone()) {
                            return Err(self.err(
                                file,
                                child,
                                format!("a <BehaviorTree> with ID \"{id}\" is defined twice"),
                            ));
                        }
                    }
                    self.defs.push(Def {
                        id,
                        fullpath,
                        file,
                        idx,
                    });
                }
                "TreeNodesModel" => self.read_models(file, child),
                other => {
                    let msg =
                        format!("<{other}> is not part of the BehaviorTree.CPP format; ignored");
                    self.warn(file, child, msg);
                }
            }
        }
        self.roots[file] = Some(root);
        Ok(file)
    }

    /// A file given with `--models` or `--with`, read as a document of its
    /// own (a file already read, such as the tree itself, is read once).
    fn add_extra(&mut self, path: &Path, what: &str) -> Result<FileId, Located> {
        if self.files.len() >= INCLUDES_MAX {
            return Err(Located::file(
                path,
                format!("more than {INCLUDES_MAX} files are read; btx stops here"),
            ));
        }
        let text = crate::source::read_text(path, INCLUDE_SIZE_MAX, &format!("the {what}"))?;
        self.add_document(path.to_path_buf(), text)
    }

    fn include(&mut self, file: FileId, el: &Element) -> Result<(), Located> {
        if el.attr("ros_pkg").is_some() {
            return Err(self
                .err(
                    file,
                    el,
                    "<include ros_pkg=...> needs a ROS workspace, which btx does not read",
                )
                .with_help("give the path relative to this file instead"));
        }
        let Some(rel) = el.attr("path") else {
            return Err(self.err(file, el, "<include> needs a path attribute"));
        };
        let base = self.files[file]
            .path
            .parent()
            .map(Path::to_path_buf)
            .unwrap_or_default();
        if self.embedded {
            return Err(self.err(
                file,
                el,
                "an <include> in a tree embedded in a log or a session is not followed: BehaviorTree.CPP's instantiated XML never has one",
            ));
        }
        if self.files.len() >= INCLUDES_MAX {
            return Err(self.err(
                file,
                el,
                format!("more than {INCLUDES_MAX} files are included; btx stops here"),
            ));
        }
        let path = base.join(rel);
        let what = format!("included file {}", path.display());
        let bytes = crate::source::read_input(&path, INCLUDE_SIZE_MAX, &what)
            .map_err(|e| self.err(file, el, e.message))?;
        let text = String::from_utf8(bytes).map_err(|e| {
            self.err(
                file,
                el,
                format!(
                    "cannot include {}: not UTF-8 text (byte offset {})",
                    path.display(),
                    e.utf8_error().valid_up_to()
                ),
            )
        })?;
        self.add_document(path, text).map(|_| ())
    }

    fn read_models(&mut self, file: FileId, el: &Element) {
        for m in &el.children {
            let kind = match m.tag.as_str() {
                "Action" => Kind::Action,
                "Condition" => Kind::Condition,
                "Control" => Kind::Control,
                "Decorator" => Kind::Decorator,
                "SubTree" => Kind::SubTree,
                other => {
                    let msg = format!("<{other}> in <TreeNodesModel> is not a node kind; ignored");
                    self.warn(file, m, msg);
                    continue;
                }
            };
            let Some(id) = m.attr("ID") else {
                self.warn(file, m, "a model without an ID; ignored");
                continue;
            };
            let ports = m
                .children
                .iter()
                .filter_map(|p| {
                    let direction = match p.tag.as_str() {
                        "input_port" => Direction::In,
                        "output_port" => Direction::Out,
                        "inout_port" => Direction::InOut,
                        _ => return None,
                    };
                    Some(PortModel {
                        name: p.attr("name")?.to_string(),
                        direction,
                        default: p.attr("default").map(str::to_string),
                        type_name: p.attr("type").map(str::to_string),
                        description: Some(p.text.trim().to_string()).filter(|s| !s.is_empty()),
                    })
                })
                .collect();
            self.models
                .entry(id.to_string())
                .or_insert(NodeModel { kind, ports });
        }
    }

    fn detect_version(&mut self) -> Result<Version, Located> {
        let root = self.root(0);
        match root.attr("BTCPP_format") {
            Some("4") => Ok(Version::V4),
            Some("3") => Ok(Version::V3),
            Some(other) => Err(self.err(
                0,
                root,
                format!("BTCPP_format=\"{other}\" is not a BehaviorTree.CPP format (3 or 4)"),
            )),
            None => {
                let v4 = self.defs.iter().any(|d| uses_v4_only(self.def_el(d)));
                let msg = if v4 {
                    "no BTCPP_format attribute; the tree uses v4-only nodes or attributes, so it is read as BehaviorTree.CPP 4"
                } else {
                    "no BTCPP_format attribute: read as BehaviorTree.CPP 3 (SubTree names are their IDs); pass --btcpp 4 to read it as v4"
                };
                let start = root.start;
                self.warn_at(0, start, msg);
                Ok(if v4 { Version::V4 } else { Version::V3 })
            }
        }
    }

    fn main_tree(&self, opts: &LoadOptions) -> Result<usize, Located> {
        let (file, root) = (&0, self.root(0));
        let known = || {
            self.defs
                .iter()
                .filter_map(|d| d.id.clone())
                .collect::<Vec<_>>()
                .join(", ")
        };
        let find = |id: &str| self.defs.iter().position(|d| d.id.as_deref() == Some(id));
        if let Some(id) = &opts.main_tree {
            return find(id).ok_or_else(|| {
                Located::file(
                    &self.files[*file].path,
                    format!("there is no <BehaviorTree ID=\"{id}\">"),
                )
                .with_help(format!("the trees are: {}", known()))
            });
        }
        // An instantiated tree (from a log): the main tree's path is "".
        if let Some(i) = self
            .defs
            .iter()
            .position(|d| d.fullpath.as_deref() == Some(""))
        {
            if opts.main_tree.is_none() && root.attr("main_tree_to_execute").is_none() {
                return Ok(i);
            }
        }
        if let Some(id) = root.attr("main_tree_to_execute") {
            return find(id).ok_or_else(|| {
                self.err(*file, root, format!("main_tree_to_execute names \"{id}\", but there is no <BehaviorTree ID=\"{id}\">"))
                    .with_help(format!("the trees are: {}", known()))
            });
        }
        let own: Vec<usize> = (0..self.defs.len())
            .filter(|&i| self.defs[i].file < self.own_files.max(1))
            .collect();
        match own.len() {
            1 => Ok(own[0]),
            0 => Err(self.err(*file, root, "no main tree: the file has no <BehaviorTree>")),
            n => Err(self.err(*file, root, format!("no main tree: {n} <BehaviorTree> elements and no main_tree_to_execute"))
                .with_help(format!("add main_tree_to_execute=\"...\" to <root>, or pass --main-tree; the trees are: {}", known()))),
        }
    }

    fn finish(mut self, opts: &LoadOptions) -> Result<Loaded, Located> {
        let version = match opts.version {
            Some(v) => v,
            None => self.detect_version()?,
        };
        if self.defs.len() > 1 {
            if let Some(d) = self.defs.iter().find(|d| d.id.is_none()) {
                return Err(self.err(
                    d.file,
                    self.def_el(d),
                    "a <BehaviorTree> needs an ID when the file has more than one",
                ));
            }
        }
        let main = self.main_tree(opts)?;
        let main_id = self.defs[main]
            .id
            .clone()
            .unwrap_or_else(|| "MainTree".to_string());
        let by_id: HashMap<String, usize> = self
            .defs
            .iter()
            .enumerate()
            .filter_map(|(i, d)| d.id.clone().map(|id| (id, i)))
            .collect();

        let defs = std::mem::take(&mut self.defs);
        let roots = std::mem::take(&mut self.roots);
        self.tree_ids = by_id.keys().cloned().collect();
        // A log's instantiated trees, by the `_fullpath` of the SubTree
        // each stands for (the first of a path).
        let by_fullpath: HashMap<&str, usize> = defs
            .iter()
            .enumerate()
            .rev()
            .filter_map(|(i, d)| Some((d.fullpath.as_deref()?, i)))
            .collect();
        let index = (&by_id, &by_fullpath);
        let (nodes, scopes) = self.expand(version, &defs, &roots, index, main, &main_id)?;
        let unused = self.unused_definitions(version, &defs, &roots, index, &nodes, main);
        self.say_unknown();
        let tree = Tree {
            version,
            release: version,
            main_tree: main_id,
            nodes,
            scopes,
            models: self.models,
            files: self.files,
            unused,
        };
        let mut warnings = self.warnings;
        if self.more_warnings > 0 {
            warnings.push(Warning {
                location: tree
                    .files
                    .first()
                    .map_or_else(String::new, |f| f.path.display().to_string()),
                message: format!(
                    "{} more warnings are not shown (the first {WARNINGS_MAX} are)",
                    self.more_warnings
                ),
            });
        }
        Ok(Loaded { tree, warnings })
    }

    /// Expands the `<BehaviorTree>` `defs[main]` into nodes numbered as
    /// BehaviorTree.CPP numbers them, each SubTree instance expanded in
    /// place, and the blackboard scopes they open.
    fn expand(
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
        let def_el = |d: &Def| {
            &roots[d.file]
                .as_ref()
                .expect("every file has a root")
                .children[d.idx]
        };
        let main_def = &defs[main];
        // The SubTree IDs on the path from the root: one is added on
        // entering a SubTree and removed by the `Leave` pushed under its
        // subtree, so the cycle check costs one lookup, not a walk up a
        // chain 10^4 deep.
        let mut on_path: std::collections::HashSet<String> =
            std::iter::once(main_id.to_string()).collect();
        let mut stack = vec![Step::Enter(Work {
            el: &def_el(main_def).children[0],
            file: main_def.file,
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
                let di = self.subtree_def(&node, &w, (by_id, by_fullpath))?;
                self.check_cycle(&node, &w, &on_path)?;
                let scope = subtree_scope(&node, w.el, w.scope);
                scopes.push(scope);
                node.opens_scope = Some(scopes.len() - 1);
                let chain = Chain {
                    id: node.id.clone(),
                    up: Some(w.chain.clone()),
                };
                let d = &defs[di];
                on_path.insert(node.id.clone());
                stack.push(Step::Leave(node.id.clone()));
                stack.push(Step::Enter(Work {
                    el: &def_el(d).children[0],
                    file: d.file,
                    parent: Some(uid),
                    scope: scopes.len() - 1,
                    depth: w.depth + 1,
                    chain: std::rc::Rc::new(chain),
                }));
            } else {
                for c in w.el.children.iter().rev() {
                    stack.push(Step::Enter(Work {
                        el: c,
                        file: w.file,
                        parent: Some(uid),
                        scope: w.scope,
                        depth: w.depth + 1,
                        chain: w.chain.clone(),
                    }));
                }
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

    /// Every `<BehaviorTree>` of the files given (not those of `--with`)
    /// that the main tree does not instantiate, each written as BehaviorTree
    /// .CPP 4 XML by expanding it on its own, so that writing the tree loses
    /// none (`registerBehaviorTreeFromFile` registers them all). One that
    /// does not expand (it is not run, so BehaviorTree.CPP would not check
    /// it either) is kept out, with a warning.
    fn unused_definitions(
        &mut self,
        version: Version,
        defs: &[Def],
        roots: &[Option<Element>],
        (by_id, by_fullpath): ByIdAndPath,
        nodes: &[Node],
        main: usize,
    ) -> Vec<(String, String)> {
        let used: std::collections::HashSet<&str> = nodes
            .iter()
            .filter(|n| n.kind == Kind::SubTree)
            .map(|n| n.id.as_str())
            .collect();
        let mut out = Vec::new();
        for (i, d) in defs.iter().enumerate() {
            let Some(id) = d.id.as_deref() else { continue };
            if i == main
                || used.contains(id)
                || d.fullpath.is_some()
                || d.file >= self.own_files.max(1)
            {
                continue;
            }
            // Its warnings were said when it was read; expanding it again
            // must not count its unknown nodes twice.
            let saved = (
                self.warnings.len(),
                self.more_warnings,
                self.unknown.clone(),
                self.unknown_at.clone(),
                self.kinds.clone(),
            );
            let expanded = self.expand(version, defs, roots, (by_id, by_fullpath), i, id);
            self.warnings.truncate(saved.0);
            self.more_warnings = saved.1;
            self.unknown = saved.2;
            self.unknown_at = saved.3;
            self.kinds = saved.4;
            match expanded {
                Ok((nodes, scopes)) => {
                    let t = Tree {
                        version,
                        release: version,
                        main_tree: id.to_string(),
                        nodes,
                        scopes,
                        models: self.models.clone(),
                        files: Vec::new(),
                        unused: Vec::new(),
                    };
                    let xml = super::write::to_v4_xml(&t);
                    let block = xml.find("  <BehaviorTree ").and_then(|s| {
                        xml[s..]
                            .find("  </BehaviorTree>\n")
                            .map(|e| xml[s..s + e + 18].to_string())
                    });
                    if let Some(b) = block {
                        out.push((id.to_string(), b));
                    }
                }
                Err(e) => {
                    let el = &roots[d.file]
                        .as_ref()
                        .expect("every file has a root")
                        .children[d.idx];
                    let msg = format!(
                        "<BehaviorTree ID=\"{id}\"> is not run and is not written back: {}",
                        e.message
                    );
                    self.warn(d.file, el, msg);
                }
            }
        }
        out
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

impl Loader {
    #[allow(clippy::too_many_arguments)]
    fn make_node(
        &mut self,
        version: Version,
        file: FileId,
        el: &Element,
        uid: Uid,
        parent: Option<Uid>,
        scope: ScopeId,
        depth: u32,
    ) -> Result<Node, Located> {
        let tag = el.tag.as_str();
        let explicit_kind = explicit_kind(tag);
        let id = self.node_id(file, el, explicit_kind)?;
        // A bare element named after a <BehaviorTree> calls it as a SubTree
        // when no node is registered under that name (createNodeFromXML
        // looks at the factory's builders before the tree roots).
        let called = explicit_kind.is_none()
            && builtins::lookup(&id).is_none()
            && !self.models.contains_key(&id)
            && self.tree_ids.contains(&id);

        // What kind of node, and which built-in behaviour.
        let (kind, builtin, guessed) = self.kind_of(version, file, el, &id, explicit_kind, called);
        if builtin.is_none() {
            self.check_declared_kind(file, el, &id, explicit_kind, kind);
        }
        self.check_children(version, file, el, &id, kind, builtin)?;

        let name = instance_name(version, el, kind, &id);

        // Ports, scripts and subtree flags.
        let (mut ports, scripts, metadata) =
            self.attributes(version, file, el, uid, &id, kind, builtin)?;
        self.subtree_defaults(file, el, &id, kind, &mut ports)?;
        Ok(Node {
            uid,
            kind,
            id,
            name,
            builtin,
            ports,
            scripts,
            metadata,
            kind_declared: !guessed,
            parent,
            children: Vec::with_capacity(el.children.len()),
            scope,
            opens_scope: None,
            depth,
            origin: Origin {
                file,
                start: el.start,
                end: el.end,
            },
        })
    }

    /// A node's ID: the `ID` attribute of an explicit element (`<Action
    /// ID="…">`), else the tag of the compact form.
    fn node_id(
        &mut self,
        file: FileId,
        el: &Element,
        explicit_kind: Option<Kind>,
    ) -> Result<String, Located> {
        let tag = el.tag.as_str();
        Ok(match explicit_kind {
            Some(_) => match el.attr("ID") {
                Some(id) => id.to_string(),
                None => return Err(self.err(file, el, format!("<{tag}> needs an ID attribute"))),
            },
            None => {
                if matches!(tag, "root" | "BehaviorTree" | "TreeNodesModel" | "include") {
                    return Err(self.err(file, el, format!("<{tag}> cannot be used as a node")));
                }
                if el.attr("ID").is_some() {
                    self.warn(
                        file,
                        el,
                        format!("<{tag}> is in compact form, where ID is not allowed; ignored"),
                    );
                }
                tag.to_string()
            }
        })
    }

    /// A node's attributes: its ports (with their directions, from its
    /// model or the built-in's), its scripts and the editors' metadata.
    #[allow(clippy::too_many_arguments)]
    fn attributes(
        &self,
        version: Version,
        file: FileId,
        el: &Element,
        uid: Uid,
        id: &str,
        kind: Kind,
        builtin: Option<Builtin>,
    ) -> Result<Attributes, Located> {
        let old_style_subtree = el.tag == "SubTree" && version == Version::V3;
        let model_ports: &[PortModel] = self.models.get(id).map_or(&[], |m| &m.ports);
        let mut ports = Vec::new();
        let mut scripts = Vec::new();
        let mut metadata = Vec::new();
        for a in &el.attrs {
            let k = a.key.as_str();
            if k == "_uid" && a.value.trim().parse::<Uid>().ok() != Some(uid) {
                let msg = format!("this node is _uid=\"{}\" in the file, but BehaviorTree.CPP's numbering gives it {uid}", a.value);
                return Err(self.err(file, el, msg));
            }
            if matches!(k, "ID" | "name" | "_uid" | "_fullpath") {
                continue;
            }
            if SCRIPT_ATTRS.contains(&k) {
                scripts.push((k.to_string(), a.value.clone()));
                continue;
            }
            if kind == Kind::SubTree
                && matches!(k, "_autoremap" | "__autoremap" | "__shared_blackboard")
            {
                continue;
            }
            // Groot2 and other editors keep `_collapsed`, `_description`
            // and the like on nodes; BehaviorTree.CPP 4 reads no port from
            // them (`xml_parsing.cpp` skips the `_`-prefixed attributes it
            // does not know).
            if k.starts_with('_') && !k.starts_with("__") {
                metadata.push((k.to_string(), a.value.clone()));
                continue;
            }
            let value = if old_style_subtree {
                // v3 <SubTree inner="outer"/>: values are key names, without braces.
                match PortValue::parse(k, &a.value) {
                    PortValue::Literal(s) => PortValue::Key(s),
                    other => other,
                }
            } else {
                PortValue::parse(k, &a.value)
            };
            let direction = model_ports
                .iter()
                .find(|p| p.name == k)
                .map(|p| p.direction)
                .or_else(|| {
                    builtin
                        .filter(|b| *b != Builtin::SubTree)
                        .and_then(|b| b.spec().ports.iter().find(|p| p.0 == k).map(|p| p.1))
                });
            ports.push(Port {
                name: k.to_string(),
                value,
                direction,
            });
        }
        Ok((ports, scripts, metadata))
    }

    /// A SubTree's ports its instance does not remap, from its model.
    fn subtree_defaults(
        &self,
        file: FileId,
        el: &Element,
        id: &str,
        kind: Kind,
        ports: &mut Vec<Port>,
    ) -> Result<(), Located> {
        // A SubTree's model (the only models BehaviorTree.CPP 4's executor
        // reads): a port the instance does not remap takes the model's
        // default, and without one the tree is refused (`loadSubtreeModel`
        // and the check in `recursivelyCreateSubtree`, xml_parsing.cpp).
        if let Some(m) = self
            .models
            .get(id)
            .filter(|m| kind == Kind::SubTree && m.kind == Kind::SubTree)
        {
            for pm in &m.ports {
                if ports.iter().any(|p| p.name == pm.name) {
                    continue;
                }
                let Some(d) = &pm.default else {
                    return Err(self.err(
                        file,
                        el,
                        format!(
                            "the <TreeNodesModel> of SubTree \"{id}\" declares the port \"{}\" with no default, and this SubTree does not remap it; BehaviorTree.CPP refuses the tree",
                            pm.name
                        ),
                    ).with_help(format!("give it: {}=\"{{{}}}\" or a value, or a default in the model", pm.name, pm.name)));
                };
                ports.push(Port {
                    name: pm.name.clone(),
                    value: PortValue::parse(&pm.name, d),
                    direction: Some(pm.direction),
                });
            }
        }
        Ok(())
    }

    /// What kind of node `id` is, and which built-in behaviour: a SubTree
    /// called, a built-in (a name of the other version said), a model's
    /// declared kind, the element's, or a kind guessed from the children
    /// (counted, to be said once per ID). Whether it was guessed.
    #[allow(clippy::too_many_arguments)]
    fn kind_of(
        &mut self,
        version: Version,
        file: FileId,
        el: &Element,
        id: &str,
        explicit_kind: Option<Kind>,
        called: bool,
    ) -> (Kind, Option<Builtin>, bool) {
        let mut guessed = false;
        let (kind, builtin) = if explicit_kind == Some(Kind::SubTree) || called {
            (Kind::SubTree, Some(Builtin::SubTree))
        } else if let Some(spec) = builtins::lookup(id) {
            match (spec.availability, version) {
                (Availability::V3Only, Version::V4) => {
                    let msg = match spec.builtin.v4_name() {
                        Some(v4) => format!("\"{id}\" is a BehaviorTree.CPP 3 name; read as {v4}"),
                        None => format!("\"{id}\" exists only in BehaviorTree.CPP 3"),
                    };
                    self.warn(file, el, msg);
                }
                (Availability::V4Only, Version::V3) => {
                    self.warn(
                        file,
                        el,
                        format!("\"{id}\" does not exist in BehaviorTree.CPP 3"),
                    );
                }
                _ => {}
            }
            (spec.kind, Some(spec.builtin))
        } else if let Some(m) = self.models.get(id) {
            (m.kind, None)
        } else if let Some(k) = explicit_kind {
            (k, None)
        } else {
            guessed = true;
            let (k, what) = match el.children.len() {
                0 => (Kind::Action, "an Action"),
                1 => (Kind::Decorator, "a Decorator"),
                _ => (Kind::Control, "a Control"),
            };
            match self.unknown_at.get(id) {
                Some(&i) => self.unknown[i].4 += 1,
                None => {
                    self.unknown_at.insert(id.to_string(), self.unknown.len());
                    self.unknown.push((id.to_string(), file, el.start, what, 1));
                }
            }
            (k, None)
        };
        (kind, builtin, guessed)
    }

    /// A node that is not built in keeps one kind per ID, as
    /// BehaviorTree.CPP registers it: an element or a use elsewhere that
    /// says another is warned of.
    fn check_declared_kind(
        &mut self,
        file: FileId,
        el: &Element,
        id: &str,
        explicit_kind: Option<Kind>,
        kind: Kind,
    ) {
        if let Some(k) = explicit_kind.filter(|k| *k != kind) {
            let msg = format!(
                "<{}> names \"{id}\", which <TreeNodesModel> declares {}; read as {}",
                k.as_str(),
                a_kind(kind),
                a_kind(kind)
            );
            self.warn(file, el, msg);
        }
        let (first, ffile, fstart) = *self
            .kinds
            .entry(id.to_string())
            .or_insert((kind, file, el.start));
        if first != kind {
            let f = &self.files[ffile];
            let (line, _) = crate::source::line_col(&f.text, fstart);
            let msg = format!(
                "\"{id}\" is used as {} here and as {} at {}:{line}; BehaviorTree.CPP registers one kind per ID",
                a_kind(kind),
                a_kind(first),
                f.path.display()
            );
            self.warn(file, el, msg);
        }
    }

    /// Child counts, as BehaviorTree.CPP verifies them, and its other
    /// checks of children.
    #[allow(clippy::too_many_arguments)]
    fn check_children(
        &self,
        version: Version,
        file: FileId,
        el: &Element,
        id: &str,
        kind: Kind,
        builtin: Option<Builtin>,
    ) -> Result<(), Located> {
        // Child counts, as BehaviorTree.CPP verifies them. Version 3's
        // VerifyXML asks for a child only of Sequence, SequenceStar, Fallback
        // and FallbackStar (by element name, xml_parsing.cpp of 3.8): a
        // ManualSelector or a custom control node may have none.
        let n = el.children.len();
        let v3_childless = version == Version::V3
            && kind == Kind::Control
            && matches!(builtin, None | Some(Builtin::ManualSelector));
        let (min, max) = match builtin {
            _ if v3_childless => (0, None),
            Some(Builtin::SubTree) => (0, Some(0)),
            Some(b) => b.spec().children,
            None => match kind {
                Kind::Action | Kind::Condition | Kind::SubTree => (0, Some(0)),
                Kind::Decorator => (1, Some(1)),
                Kind::Control => (1, None),
            },
        };
        if n < min || max.is_some_and(|m| n > m) {
            let what = match (min, max) {
                (a, Some(b)) if a == b && a == 0 => "no children".to_string(),
                (a, Some(b)) if a == b && a == 1 => "exactly one child".to_string(),
                (a, Some(b)) if a == b => format!("exactly {a} children"),
                (a, Some(b)) => format!("{a} to {b} children"),
                (a, None) => format!("at least {a} {}", if a == 1 { "child" } else { "children" }),
            };
            return Err(self.err(
                file,
                el,
                format!("{} \"{id}\" must have {what}, found {n}", kind.as_str()),
            ));
        }

        // BehaviorTree.CPP 4's verifyXML: a ReactiveSequence may hold one
        // AsyncSequence at most (by element name), or two would race.
        if version == Version::V4
            && el.tag == "ReactiveSequence"
            && el
                .children
                .iter()
                .filter(|c| c.tag == "AsyncSequence")
                .count()
                > 1
        {
            return Err(self.err(
            file,
            el,
            "A ReactiveSequence cannot have more than one async child (BehaviorTree.CPP refuses it: two AsyncSequence children would race)".to_string(),
        ));
        }
        Ok(())
    }
}

/// Whether an element (or one below it) only makes sense in v4.
fn uses_v4_only(el: &Element) -> bool {
    let mut stack = vec![el];
    while let Some(e) = stack.pop() {
        let id = match e.tag.as_str() {
            "Action" | "Condition" | "Control" | "Decorator" => e.attr("ID").unwrap_or(""),
            t => t,
        };
        if builtins::lookup(id).is_some_and(|s| s.availability == Availability::V4Only) {
            return true;
        }
        if e.attrs.iter().any(|a| {
            a.key == "_autoremap"
                || SCRIPT_ATTRS.contains(&a.key.as_str())
                || a.value.trim().starts_with("{@")
        }) {
            return true;
        }
        stack.extend(e.children.iter());
    }
    false
}

/// The SubTrees open above a node, innermost first, shared: each SubTree
/// adds one link, so a chain thousands of levels deep holds one link a
/// level (a copy of the whole path a level held the square of the depth:
/// 470 MB for 4,000 SubTrees).
/// The definitions by ID, and a log's by the `_fullpath` they stand for.
type ByIdAndPath<'a, 'd> = (&'a HashMap<String, usize>, &'a HashMap<&'d str, usize>);

/// An element to expand, where it goes in the tree.
struct Work<'a> {
    el: &'a Element,
    file: FileId,
    parent: Option<Uid>,
    scope: ScopeId,
    depth: u32,
    chain: std::rc::Rc<Chain>,
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

/// A node's ports, scripts and metadata (`_`-prefixed attributes), as
/// `(name, value)` for the last two.
type Attributes = (Vec<Port>, Vec<(String, String)>, Vec<(String, String)>);

/// The kind an element's tag says, in the explicit form (`<Action ID=…>`).
fn explicit_kind(tag: &str) -> Option<Kind> {
    match tag {
        "Action" => Some(Kind::Action),
        "Condition" => Some(Kind::Condition),
        "Control" => Some(Kind::Control),
        "Decorator" => Some(Kind::Decorator),
        "SubTree" | "SubTreePlus" => Some(Kind::SubTree),
        _ => None,
    }
}

/// A node's instance name, by the version's rules.
fn instance_name(version: Version, el: &Element, kind: Kind, id: &str) -> String {
    let name_attr = el.attr("name");
    if kind == Kind::SubTree {
        match (version, name_attr, el.attr("_fullpath")) {
            (Version::V4, Some(n), _) if !n.is_empty() => n.to_string(),
            // The instantiated XML of a log names a subtree by its path.
            (_, None, Some(path)) => match path.rsplit('/').next() {
                Some(last) if !last.is_empty() && !last.contains("::") => last.to_string(),
                _ => id.to_string(),
            },
            _ => id.to_string(),
        }
    } else {
        name_attr.unwrap_or(id).to_string()
    }
}
