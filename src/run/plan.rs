//! Scripted leaf outcomes in the fixture syntax (`key = S, F, 2RS, 1RF`), so
//! that any tree runs without code.

use super::exec::{LeafCall, LeafOutcome, Leaves};
use super::status::Status;
use crate::model::{Kind, PathKey, Tree, Uid, Version};
use crate::source::{Located, Warning};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// One scripted outcome.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Outcome {
    /// Ticks the action returns RUNNING (the first at its start).
    pub running: u32,
    /// SUCCESS or FAILURE after that.
    pub then: Status,
}

impl std::fmt::Display for Outcome {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let c = if self.then == Status::Success {
            'S'
        } else {
            'F'
        };
        if self.running > 0 {
            write!(f, "{}R{c}", self.running)
        } else {
            write!(f, "{c}")
        }
    }
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PlanEntry {
    pub key: String,
    pub outcomes: Vec<Outcome>,
    pub line: usize,
}

/// A parsed plan file.
#[derive(Debug, Clone)]
pub struct Plan {
    pub path: PathBuf,
    pub text: String,
    pub entries: Vec<PlanEntry>,
    /// Scripting enums (`@enum RED = 0`, `@enum Color = RED, GREEN`).
    pub enums: Vec<(String, i64)>,
}

fn parse_outcome(s: &str) -> Option<Outcome> {
    let s = s.trim();
    let then = match s.chars().last()? {
        'S' | 's' => Status::Success,
        'F' | 'f' => Status::Failure,
        _ => return None,
    };
    let head = &s[..s.len() - 1];
    if head.is_empty() {
        return Some(Outcome { running: 0, then });
    }
    let n = head.strip_suffix(['R', 'r'])?;
    Some(Outcome {
        running: n.parse().ok()?,
        then,
    })
}

/// The names an `@enum` line declares: `@enum RED = 0`, or a C++ enum's
/// names numbered from 0, `@enum Color = RED, GREEN, BLUE`.
fn declared_enums(
    name: &str,
    list: &str,
    enums: &[(String, i64)],
    at: &dyn Fn(String) -> Located,
) -> Result<Vec<(String, i64)>, Located> {
    let declared: Vec<(String, i64)> = match list.trim().parse::<i64>() {
        Ok(v) => vec![(name.to_string(), v)],
        Err(_) => list
            .split(',')
            .map(str::trim)
            .enumerate()
            .map(|(i, n)| (n.to_string(), i as i64))
            .collect(),
    };
    for (n, _) in &declared {
        let ok = n
            .chars()
            .next()
            .is_some_and(|c| c.is_alphabetic() || c == '_')
            && n.chars().all(|c| c.is_alphanumeric() || c == '_');
        if !ok {
            return Err(at(format!("\"{n}\" is not an enum name")).with_help(
                "`@enum NAME = 3`, or `@enum Color = RED, GREEN, BLUE` (numbered from 0)",
            ));
        }
        if enums.iter().any(|(m, _)| m == n) {
            return Err(at(format!("the enum \"{n}\" is declared twice")));
        }
    }
    Ok(declared)
}

/// A plan line's outcomes, `S, F, 2RS`.
fn outcomes_of(list: &str, at: &dyn Fn(String) -> Located) -> Result<Vec<Outcome>, Located> {
    list.split(',')
        .map(|o| {
            parse_outcome(o).ok_or_else(|| {
                at(format!("\"{}\" is not an outcome", o.trim())).with_help(
                    "outcomes are S, F, nRS or nRF (RUNNING for n ticks, then SUCCESS or FAILURE)",
                )
            })
        })
        .collect()
}

impl Plan {
    pub fn parse(path: &Path, text: &str) -> Result<Plan, Located> {
        let mut entries: Vec<PlanEntry> = Vec::new();
        let mut enums: Vec<(String, i64)> = Vec::new();
        let mut offset = 0;
        for (i, raw) in text.split_inclusive('\n').enumerate() {
            let start = offset;
            offset += raw.len();
            let line = raw.trim_end_matches(['\n', '\r']);
            let content = line.trim();
            if content.is_empty() || content.starts_with('#') {
                continue;
            }
            let at = |msg: String| Located::at(path, text, start, start + line.len(), msg);
            let Some((key, list)) = content.split_once('=') else {
                return Err(at("a plan line is `key = outcome, ...`".into())
                    .with_help("outcomes are S, F, nRS or nRF, e.g. `look at chuck = 1RF, 1RS`"));
            };
            // A `#` after the `=` starts a comment, as in a domain file (no
            // outcome has one; a key may, being a node's name).
            let list = list.split_once('#').map_or(list, |(l, _)| l);
            if let Some(name) = key.trim().strip_prefix("@enum ") {
                let declared = declared_enums(name.trim(), list, &enums, &at)?;
                enums.extend(declared);
                continue;
            }
            let key = key.trim().to_string();
            if key.is_empty() {
                return Err(at("a plan line needs a key before `=`".into()));
            }
            let outcomes = outcomes_of(list, &at)?;
            if key.starts_with('@') && key != "@default_action" && key != "@default_condition" {
                return Err(at(format!("\"{key}\" is not a plan directive")).with_help(
                    "the directives are @default_action, @default_condition and @enum",
                ));
            }
            if let Some(prev) = entries.iter().find(|e| e.key == key) {
                return Err(at(format!(
                    "\"{key}\" is already planned on line {}",
                    prev.line
                )));
            }
            entries.push(PlanEntry {
                key,
                outcomes,
                line: i + 1,
            });
        }
        Ok(Plan {
            path: path.to_path_buf(),
            text: text.to_string(),
            entries,
            enums,
        })
    }

    pub fn load(path: &Path) -> Result<Plan, Located> {
        let text = crate::source::read_text(path, crate::source::TEXT_SIZE_MAX, "the plan")?;
        Plan::parse(path, &text)
    }

    /// Each key's first entry, by the key's `PathKey` (a fullPath is matched
    /// by its key, never written out: on a deep chain of SubTrees the paths
    /// grow with depth squared).
    fn entries_by_key(&self) -> HashMap<PathKey, usize> {
        let mut by_key = HashMap::with_capacity(self.entries.len());
        for (i, e) in self.entries.iter().enumerate() {
            by_key.entry(PathKey::of(&e.key)).or_insert(i);
        }
        by_key
    }
}

/// Leaves driven by a plan, as the fixture runner drives them: actions are
/// stateful (each start takes the next outcome), conditions take one outcome
/// per tick; each node steps through its own copy of its list and the last
/// outcome repeats. On SUCCESS an action writes `value of <port> from
/// '<name>'` to its output ports.
pub struct PlanLeaves {
    plan: Plan,
    /// leaf uid → (plan entry, cursor)
    assigned: HashMap<Uid, (Option<usize>, usize)>,
    /// Each plan key's first entry.
    by_key: HashMap<PathKey, usize>,
    /// Cursor keys (fullPath in v4, `#uid` in v3) → cursor.
    cursor_ids: HashMap<PathKey, usize>,
    /// Position of each cursor in its list.
    cursors: Vec<usize>,
    running: HashMap<Uid, (u32, Status)>,
    pub warnings: Vec<Warning>,
    /// Root blackboard entries the run starts with (`btx run --set`).
    pub seeds: Vec<(super::blackboard::EntryId, serde_json::Value)>,
}

impl PlanLeaves {
    pub fn new(plan: Plan, tree: &Tree) -> PlanLeaves {
        let mut p = PlanLeaves {
            by_key: plan.entries_by_key(),
            plan,
            assigned: HashMap::new(),
            cursor_ids: HashMap::new(),
            cursors: Vec::new(),
            running: HashMap::new(),
            warnings: Vec::new(),
            seeds: Vec::new(),
        };
        let mut used = vec![false; p.plan.entries.len()];
        // Built-in leaves (Script, AlwaysSuccess, SetBlackboard…) run by
        // their own rules and take no plan entry.
        let scope_keys = tree.scope_path_keys();
        for n in &tree.nodes {
            if n.kind.is_leaf() && n.builtin.is_none() {
                if let Some(e) = p.assign(tree, scope_keys[n.scope], n.uid) {
                    used[e] = true;
                }
            }
        }
        p.warn_unplanned(tree);
        p.warn_at_once(tree);
        p.warn_unused(tree, &used);
        p
    }

    /// Leaves no plan entry drives: they succeed at once, said.
    fn warn_unplanned(&mut self, tree: &Tree) {
        let mut unplanned: Vec<String> = self
            .assigned
            .iter()
            .filter(|(_, (e, _))| e.is_none())
            .map(|(u, _)| format!("{} #{u}", tree.description(*u)))
            .collect();
        if !unplanned.is_empty() {
            unplanned.sort();
            self.warnings.push(Warning {
            location: crate::text::path(&self.plan.path),
            message: format!(
                "no plan entry for {} (add @default_action / @default_condition); they succeed at once",
                unplanned.join(", ")
            ),
        });
        }
    }

    /// Nav2 actions that complete in the tick they start, given RUNNING
    /// ticks by the plan: the ticks are dropped, said at the entry's line.
    fn warn_at_once(&mut self, tree: &Tree) {
        let mut at_once: Vec<(usize, &str)> = self
            .assigned
            .iter()
            .filter_map(|(&u, &(e, _))| {
                let n = tree.node(u);
                let e = e?;
                let entry = &self.plan.entries[e];
                (n.kind == Kind::Action
                    && crate::model::nav2::at_once(&n.id, tree.release).is_some()
                    && !entry.key.starts_with('@')
                    && entry.outcomes.iter().any(|o| o.running > 0))
                .then_some((entry.line, n.id.as_str()))
            })
            .collect();
        at_once.sort();
        at_once.dedup();
        for (line, id) in at_once {
            self.warnings.push(Warning {
            location: format!("{}:{line}:1", crate::text::path(&self.plan.path)),
            message: format!(
                "Nav2's {id} completes in the tick it starts and never returns RUNNING; its RUNNING ticks here are dropped"
            ),
        });
        }
    }

    /// Plan entries that match no leaf, each with the name it might have
    /// meant.
    fn warn_unused(&mut self, tree: &Tree, used: &[bool]) {
        // The names a key might have meant, made only when one matches none.
        let unused = self
            .plan
            .entries
            .iter()
            .zip(used)
            .any(|(e, u)| !u && !e.key.starts_with('@'));
        let mut keys: Vec<(String, String)> = Vec::new();
        let mut seen = std::collections::HashSet::new();
        let scope_paths = if unused {
            tree.scope_paths()
        } else {
            Vec::new()
        };
        for n in tree.nodes.iter().filter(|n| unused && n.kind.is_leaf()) {
            let scope = scope_paths.get(n.scope).map(String::as_str);
            for k in super::leaf_keys_under(tree, scope, n.uid) {
                if !k.starts_with('@') && seen.insert(k.clone()) {
                    keys.push((k.clone(), k));
                }
            }
        }
        for (e, u) in self.plan.entries.iter().zip(used) {
            if !u && !e.key.starts_with('@') {
                self.warnings.push(Warning {
                    location: format!("{}:{}:1", crate::text::path(&self.plan.path), e.line),
                    message: format!(
                        "\"{}\" matches no leaf of the tree{}",
                        e.key,
                        closest(&e.key, &keys)
                    ),
                });
            }
        }
    }

    /// Which plan entry drives a leaf: its fullPath (v4 only), then its
    /// instance name, then its registration ID, then the default.
    /// `scope`: the key of the leaf's scope's path.
    fn assign(&mut self, tree: &Tree, scope: PathKey, uid: Uid) -> Option<usize> {
        let n = tree.node(uid);
        let full = (tree.version == Version::V4).then(|| tree.full_path_key(scope, uid));
        let default = if n.kind == Kind::Condition {
            "@default_condition"
        } else {
            "@default_action"
        };
        // The order of `leaf_keys`, matched by key.
        let named = (!n.name.is_empty()).then(|| PathKey::of(&n.name));
        let entry = full
            .into_iter()
            .chain(named)
            .chain([PathKey::of(&n.id), PathKey::of(default)])
            .find_map(|k| self.by_key.get(&k).copied());
        // Each node steps through its own copy of its list: keyed by fullPath
        // in v4, by uid in v3, as the fixture runner did.
        let cursor = full.unwrap_or_else(|| PathKey::of(&format!("#{uid}")));
        let next = self.cursors.len();
        let id = *self.cursor_ids.entry(cursor).or_insert(next);
        if id == next {
            self.cursors.push(0);
        }
        self.assigned.insert(uid, (entry, id));
        entry
    }

    /// The next outcome of a leaf, and the plan key it came from.
    fn next(&mut self, uid: Uid) -> (Outcome, Option<&str>) {
        let Some(&(entry, cursor)) = self.assigned.get(&uid) else {
            return (
                Outcome {
                    running: 0,
                    then: Status::Success,
                },
                None,
            );
        };
        let Some(e) = entry else {
            return (
                Outcome {
                    running: 0,
                    then: Status::Success,
                },
                None,
            );
        };
        let list = &self.plan.entries[e].outcomes;
        let pos = &mut self.cursors[cursor];
        let o = list[(*pos).min(list.len() - 1)];
        *pos += 1;
        (o, Some(self.plan.entries[e].key.as_str()))
    }
}

impl PlanLeaves {
    /// `KEY=VALUE` (or `@KEY=VALUE`, the same root entry as `{@KEY}`): the
    /// root blackboard starts with it. VALUE is JSON, else text.
    pub fn seed(&mut self, assignment: &str) -> Result<(), String> {
        let (key, raw) = assignment
            .split_once('=')
            .ok_or_else(|| format!("--set {assignment}: write KEY=VALUE"))?;
        let key = key.trim().trim_start_matches('@');
        if key.is_empty() {
            return Err(format!("--set {assignment}: the key is empty"));
        }
        let raw = raw.trim();
        let v = serde_json::from_str(raw).unwrap_or_else(|_| serde_json::Value::from(raw));
        let e = super::blackboard::EntryId {
            scope: 0,
            key: key.to_string(),
        };
        self.seeds.retain(|(x, _)| *x != e);
        self.seeds.push((e, v));
        Ok(())
    }
}

impl Leaves for PlanLeaves {
    fn enums(&self) -> &[(String, i64)] {
        &self.plan.enums
    }

    fn initial_entries(&self) -> Vec<(super::blackboard::EntryId, serde_json::Value)> {
        self.seeds.clone()
    }

    fn tick(&mut self, call: &mut LeafCall) -> LeafOutcome {
        let uid = call.uid;
        if !self.assigned.contains_key(&uid) {
            // A leaf inserted during the run ("Can you X?").
            let scope = PathKey::of(&call.tree.scope_path(call.tree.node(uid).scope));
            self.assign(call.tree, scope, uid);
        }
        // A condition, or a Nav2 action that completes at once, takes the
        // completed part of each outcome.
        let status = if call.kind == Kind::Condition || call.completes_at_once() {
            self.next(uid).0.then
        } else if let Some((left, then)) = self.running.get_mut(&uid) {
            if *left > 0 {
                *left -= 1;
                Status::Running
            } else {
                let then = *then;
                self.running.remove(&uid);
                then
            }
        } else {
            let (o, _) = self.next(uid);
            if o.running > 0 {
                self.running.insert(uid, (o.running - 1, o.then));
                Status::Running
            } else {
                o.then
            }
        };
        if status == Status::Success && call.kind == Kind::Action {
            let name = call.tree.description(uid).to_string();
            for p in call.output_ports() {
                call.write_port(
                    &p,
                    serde_json::Value::from(format!("value of {p} from '{name}'")),
                );
            }
        }
        LeafOutcome {
            status,
            decision: None,
        }
    }

    fn halt(&mut self, uid: Uid) {
        self.running.remove(&uid);
    }
}

/// `; did you mean "FollowPath"?` for a key that misspells a leaf's, else
/// the three leaf keys closest to it.
fn closest(key: &str, keys: &[(String, String)]) -> String {
    if let Some(k) = crate::rank::misspelt(key, keys.iter().map(|(k, _)| k.as_str())) {
        return format!("; did you mean \"{k}\"?");
    }
    let near = crate::rank::rank(key, keys, 3);
    if near.is_empty() {
        return String::new();
    }
    let quoted: Vec<String> = near.iter().map(|k| format!("\"{k}\"")).collect();
    format!("; the closest: {}", quoted.join(", "))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_the_fixture_syntax() {
        let p = Plan::parse(
            Path::new("p.plan"),
            "# c\n@default_action = 1RS\nlook at chuck = 1RF, 1RS\nx = S, F,2RF\n",
        )
        .unwrap();
        assert_eq!(p.entries.len(), 3);
        assert_eq!(p.entries[1].key, "look at chuck");
        assert_eq!(
            p.entries[1].outcomes[0],
            Outcome {
                running: 1,
                then: Status::Failure
            }
        );
        assert_eq!(
            p.entries[2]
                .outcomes
                .iter()
                .map(|o| o.to_string())
                .collect::<Vec<_>>(),
            ["S", "F", "2RF"]
        );
        assert_eq!(p.entries[2].line, 4);
    }

    #[test]
    fn a_comment_may_end_a_line_as_in_the_guide() {
        let readme = include_str!("../../docs/trees-and-runs.md");
        let block = readme
            .split("## Plans")
            .nth(1)
            .and_then(|s| s.split("```text\n").nth(1))
            .and_then(|s| s.split("```").next())
            .unwrap();
        let p = Plan::parse(Path::new("docs/trees-and-runs.md"), block).unwrap();
        assert_eq!(p.entries.len(), 3);
        assert_eq!(p.entries[0].outcomes[0].to_string(), "1RS");
        assert_eq!(p.entries[2].outcomes[1].to_string(), "1RS");
        // A `#` in a key is the node's name.
        let p = Plan::parse(Path::new("p.plan"), "pick #2 = F # first\n").unwrap();
        assert_eq!(p.entries[0].key, "pick #2");
    }

    #[test]
    fn bad_lines_are_located() {
        let e = Plan::parse(Path::new("p.plan"), "a = S\nb = 2RX\n").unwrap_err();
        assert!(
            e.to_string()
                .starts_with("p.plan:2:1: \"2RX\" is not an outcome"),
            "{e}"
        );
        let e = Plan::parse(Path::new("p.plan"), "a = S\n\njust words\n").unwrap_err();
        assert!(e.to_string().starts_with("p.plan:3:1:"), "{e}");
        let e = Plan::parse(Path::new("p.plan"), "a = S\na = F\n").unwrap_err();
        assert!(e.to_string().contains("already planned on line 1"), "{e}");
    }
}
