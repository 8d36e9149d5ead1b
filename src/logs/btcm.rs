//! btcm's episodic memory (JSON; ../shared/docs/btcm.md §2.1), read as a
//! session: the tree from its node table, one transition per time step,
//! the leaf's action as its decision, and the state snapshots as writes to
//! the root blackboard (one entry per state variable, as domain runs keep
//! them). Ticks are 0-based in the file and 1-based in btx.
//!
//! py_trees composites without memory restart at their first child every
//! tick, which is BehaviorTree.CPP's ReactiveSequence/ReactiveFallback;
//! with memory they resume a RUNNING child, which is Sequence/Fallback.

use crate::model::Uid;
use crate::run::blackboard::EntryId;
use crate::run::Status;
use crate::session::{Index, Session, Transition};
use crate::source::{Located, Warning};
use crate::xml::{load_str, LoadOptions};
use serde_json::{Map, Value};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Whether a JSON text looks like a btcm log (an object with `tree` and
/// `state` before any tick).
pub fn is_btcm(text: &str) -> bool {
    let head: String = text.chars().take(4096).collect();
    head.trim_start().starts_with('{')
        && head.contains("\"tree\"")
        && !head.contains("\"btx_session\"")
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('"', "&quot;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

struct Reader<'a> {
    path: &'a Path,
}

impl Reader<'_> {
    fn err(&self, at: &str, msg: impl std::fmt::Display) -> Located {
        Located::file(self.path, format!("{at}: {msg}"))
    }

    fn obj<'v>(&self, v: &'v Value, at: &str) -> Result<&'v Map<String, Value>, Located> {
        v.as_object()
            .ok_or_else(|| self.err(at, "expected an object"))
    }

    fn str<'v>(&self, v: &'v Map<String, Value>, key: &str, at: &str) -> Result<&'v str, Located> {
        v.get(key)
            .and_then(Value::as_str)
            .ok_or_else(|| self.err(at, format!("\"{key}\" is missing or not a string")))
    }
}

/// The tree's XML as it is written, leaf kinds to declare, node ids in
/// pre-order.
struct Emitted {
    xml: String,
    models: Vec<(String, &'static str)>,
    order: Vec<String>,
    seen: std::collections::HashSet<String>,
}

fn emit(
    rd: &Reader,
    nodes: &Map<String, Value>,
    id: &str,
    depth: usize,
    out: &mut Emitted,
) -> Result<(), Located> {
    let at = format!("tree.{id}");
    if !out.seen.insert(id.to_string()) {
        return Err(rd.err(&at, "the node appears twice (a cycle?)"));
    }
    if depth > 1000 {
        return Err(rd.err(&at, "the tree is more than 1000 levels deep"));
    }
    out.order.push(id.to_string());
    let n = rd.obj(
        nodes
            .get(id)
            .ok_or_else(|| rd.err(&at, "a child that is not in the tree"))?,
        &at,
    )?;
    let name = rd.str(n, "name", &at)?;
    let pad = "  ".repeat(depth + 2);
    let cat = rd.str(n, "category", &at)?;
    match cat {
        "Sequence" | "Fallback" => {
            let memory = n.get("memory").and_then(Value::as_bool).unwrap_or(false);
            let tag = match (cat, memory) {
                ("Sequence", true) => "Sequence",
                ("Sequence", false) => "ReactiveSequence",
                (_, true) => "Fallback",
                _ => "ReactiveFallback",
            };
            out.xml
                .push_str(&format!("{pad}<{tag} name=\"{}\">\n", esc(name)));
            let kids = n
                .get("children")
                .and_then(Value::as_array)
                .ok_or_else(|| rd.err(&at, "\"children\" is missing"))?;
            if kids.is_empty() {
                return Err(rd.err(&at, "a composite without children"));
            }
            for k in kids {
                let k = k
                    .as_str()
                    .ok_or_else(|| rd.err(&at, "a child id is not a string"))?;
                emit(rd, nodes, k, depth + 1, out)?;
            }
            out.xml.push_str(&format!("{pad}</{tag}>\n"));
        }
        "Action" | "Condition" => {
            let class = n
                .get("class")
                .and_then(Value::as_str)
                .unwrap_or(name)
                .replace(|c: char| !c.is_ascii_alphanumeric() && c != '_', "_");
            let kind = if cat == "Action" {
                "Action"
            } else {
                "Condition"
            };
            if !out.models.iter().any(|(c, _)| *c == class) {
                out.models.push((class.clone(), kind));
            }
            out.xml
                .push_str(&format!("{pad}<{class} name=\"{}\"/>\n", esc(name)));
        }
        other => {
            return Err(rd.err(
                &at,
                format!("category \"{other}\" is not Sequence, Fallback, Action or Condition"),
            ))
        }
    }
    Ok(())
}

/// Reads a btcm log.
pub fn open_btcm(path: &Path, text: &str) -> Result<Session, Located> {
    let rd = Reader { path };
    let doc: Value = serde_json::from_str(text).map_err(|e| {
        Located::file(
            path,
            format!("line {}, column {}: not JSON: {e}", e.line(), e.column()),
        )
    })?;
    let top = rd.obj(&doc, "the log")?;
    let (tree, order) = btcm_tree(&rd, top)?;
    // Node ids in pre-order are uids 1, 2, … as BehaviorTree.CPP numbers them.
    let uid_of: HashMap<&str, Uid> = order
        .iter()
        .enumerate()
        .map(|(i, id)| (id.as_str(), i as Uid + 1))
        .collect();
    let mut r = Replayed::new(&tree);
    for (i, (t, steps)) in ticks_of(&rd, top)?.iter().enumerate() {
        let tick = i as u32 + 1;
        if *t != i as u64 {
            r.warnings.push(Warning {
                location: crate::text::path(path),
                message: format!(
                    "tick {t} follows tick {}: ticks are renumbered",
                    i as i64 - 1
                ),
            });
        }
        for (time, step) in time_steps(&rd, *t, steps)? {
            let at = format!("tick {t}, time {time}");
            r.step(&rd, &tree, &uid_of, tick, &at, step)?;
        }
        r.end_tick(&tree, tick);
    }
    let header = super::import_header(path, &tree, crate::model::Version::V4, "btcm", r.initial);
    let ticks = r.index.ticks();
    Ok(Session {
        path: path.to_path_buf(),
        header,
        tree,
        index: r.index,
        end: Some((ticks, r.root_status, "imported".into())),
        inserts: Vec::new(),
        span_us: None,
        times_us: Vec::new(),
        warnings: r.warnings,
        run: None,
    })
}

/// The log's tree, as BehaviorTree.CPP 4 XML loaded (leaves are declared
/// by kind), and its node ids in pre-order.
fn btcm_tree(rd: &Reader, top: &Map<String, Value>) -> Result<(crate::Tree, Vec<String>), Located> {
    let path = rd.path;
    let nodes = rd.obj(
        top.get("tree")
            .ok_or_else(|| rd.err("the log", "no \"tree\""))?,
        "tree",
    )?;
    let root_id = nodes
        .keys()
        .next()
        .ok_or_else(|| rd.err("tree", "no nodes"))?
        .clone();
    let mut out = Emitted {
        xml: String::from("<root BTCPP_format=\"4\" main_tree_to_execute=\"btcm\">\n  <BehaviorTree ID=\"btcm\">\n"),
        models: Vec::new(),
        order: Vec::new(),
        seen: Default::default(),
    };
    emit(rd, nodes, &root_id, 0, &mut out)?;
    // btcm takes the first node as the root; a node it never reaches would
    // be a second root whose run the log cannot place in the tree.
    if let Some(stray) = nodes.keys().find(|k| !out.seen.contains(k.as_str())) {
        return Err(rd.err(
            &format!("tree.{stray}"),
            format!(
                "the node is not under the root \"{root_id}\" (the first node of \"tree\"): a btcm tree has one root"
            ),
        ));
    }
    let Emitted {
        mut xml,
        models,
        order,
        ..
    } = out;
    xml.push_str("  </BehaviorTree>\n  <TreeNodesModel>\n");
    for (class, kind) in &models {
        xml.push_str(&format!("    <{kind} ID=\"{class}\"/>\n"));
    }
    xml.push_str("  </TreeNodesModel>\n</root>\n");
    let name = PathBuf::from(format!("{} (tree)", path.display()));
    let tree = load_str(
        &name,
        &xml,
        &LoadOptions {
            version: Some(crate::model::Version::V4),
            main_tree: None,
            embedded: true,
            ..Default::default()
        },
    )?
    .tree;
    Ok((tree, order))
}

/// Ticks: "0", "1", … in order, each with its time steps.
#[allow(clippy::type_complexity)]
fn ticks_of<'v>(
    rd: &Reader,
    top: &'v Map<String, Value>,
) -> Result<Vec<(u64, &'v Map<String, Value>)>, Located> {
    let mut ticks: Vec<(u64, &Map<String, Value>)> = Vec::new();
    for (k, v) in top {
        if let Ok(t) = k.parse::<u64>() {
            ticks.push((t, rd.obj(v, &format!("tick {k}"))?));
        }
    }
    ticks.sort_by_key(|(t, _)| *t);
    Ok(ticks)
}

/// A tick's time steps, keyed by a global counter, in order.
fn time_steps<'v>(
    rd: &Reader,
    t: u64,
    steps: &'v Map<String, Value>,
) -> Result<Vec<(u64, &'v Value)>, Located> {
    let mut times: Vec<(u64, &Value)> = Vec::new();
    for (k, v) in steps {
        let n = k.parse::<u64>().map_err(|_| {
            rd.err(
                &format!("tick {t}"),
                format!("time step key \"{k}\" is not a number"),
            )
        })?;
        times.push((n, v));
    }
    times.sort_by_key(|(n, _)| *n);
    Ok(times)
}

/// The run as the log's steps replay it.
struct Replayed {
    index: Index,
    status: Vec<Status>,
    state: HashMap<String, Value>,
    initial: Vec<(EntryId, Value)>,
    warnings: Vec<Warning>,
    root_status: Status,
}

impl Replayed {
    fn new(tree: &crate::Tree) -> Replayed {
        Replayed {
            index: Index::new(tree.len()),
            status: vec![Status::Idle; tree.len()],
            state: HashMap::new(),
            initial: Vec::new(),
            warnings: Vec::new(),
            root_status: Status::Idle,
        }
    }

    /// One time step: a node's update (its status, the state it wrote,
    /// an action's decision), or the initial state.
    fn step(
        &mut self,
        rd: &Reader,
        tree: &crate::Tree,
        uid_of: &HashMap<&str, Uid>,
        tick: u32,
        at: &str,
        step: &Value,
    ) -> Result<(), Located> {
        let step = rd.obj(step, at)?;
        let snapshot = step.get("state").and_then(Value::as_object);
        let Some(update) = step.get("update").and_then(Value::as_object) else {
            // The initial state (tick 0, time 0).
            if let Some(s) = snapshot {
                self.initial_state(s);
            }
            return Ok(());
        };
        let (id, u) = update
            .iter()
            .next()
            .ok_or_else(|| rd.err(at, "an empty update"))?;
        let u = rd.obj(u, at)?;
        let uid = *uid_of
            .get(id.as_str())
            .ok_or_else(|| rd.err(at, format!("node \"{id}\" is not in the tree")))?;
        let raw = rd.str(u, "status", at)?;
        let st = Status::parse(raw.trim_start_matches("Status."))
            .filter(|s| *s != Status::Idle)
            .ok_or_else(|| {
                rd.err(
                    at,
                    format!("status \"{raw}\" is not SUCCESS, FAILURE or RUNNING"),
                )
            })?;
        if let Some(s) = snapshot {
            for (k, v) in s {
                if self.state.get(k) != Some(v) {
                    self.state.insert(k.clone(), v.clone());
                    let e = EntryId {
                        scope: 0,
                        key: k.clone(),
                    };
                    self.index.push_write_by(tick, uid, e, v.clone());
                }
            }
        }
        let decision = match (tree.node(uid).kind, u.get("action").and_then(Value::as_str)) {
            (crate::model::Kind::Action, Some("NullAction")) => Some("null".to_string()),
            (crate::model::Kind::Action, Some(a)) => Some(a.to_string()),
            _ => None,
        };
        let prev = self.status[uid as usize - 1];
        self.status[uid as usize - 1] = st;
        if uid == 1 {
            self.root_status = st;
        }
        let t = Transition {
            tick,
            uid,
            prev,
            status: st,
        };
        self.index.push_transition(tree, t, decision);
        Ok(())
    }

    /// The state before the first transition: the blackboard's initial
    /// entries.
    fn initial_state(&mut self, s: &Map<String, Value>) {
        for (k, v) in s {
            if self.state.insert(k.clone(), v.clone()).is_none()
                && self.index.transitions.is_empty()
            {
                let e = EntryId {
                    scope: 0,
                    key: k.clone(),
                };
                self.initial.push((e, v.clone()));
            }
        }
    }

    /// A completed root ends the tick's run: every node is reset, as btcm
    /// resets its BT variables.
    fn end_tick(&mut self, tree: &crate::Tree, tick: u32) {
        if self.status[0].is_completed() {
            for u in 1..=tree.len() as Uid {
                let prev = self.status[u as usize - 1];
                if prev != Status::Idle {
                    self.status[u as usize - 1] = Status::Idle;
                    let t = Transition {
                        tick,
                        uid: u,
                        prev,
                        status: Status::Idle,
                    };
                    self.index.push_transition(tree, t, None);
                }
            }
        }
        self.index.end_tick(tick);
    }
}
