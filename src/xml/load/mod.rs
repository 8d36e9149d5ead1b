//! BehaviorTree.CPP XML (v3 and v4) → one expanded [`Tree`].

mod expand;
mod node;

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
