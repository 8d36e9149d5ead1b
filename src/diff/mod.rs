//! Expected vs actual (Han et al. §7.2.1, Fig. 14): the action sequence of
//! each subgoal in two trees, or the executed leaves of each subgoal in two
//! runs, aligned by a shortest edit script.
//!
//! A tree's sequence is its actions (and conditions) in tree order; a run's
//! is the leaves it executed, in the order they started. Each leaf belongs
//! to its nearest enclosing subgoal (a SubTree node), or to the goal.
//! Subgoals are matched by name, in order, so two trees written apart can be
//! compared; an unmatched subgoal's actions are all inserted or deleted.

pub mod align;
pub mod fleet;

pub use align::{Edit, Op};

use crate::model::{Kind, Tree, Uid};
use crate::run::Status;
use crate::session::Session;
use serde_json::{json, Value};

/// One side of a comparison: a tree, or a run of one.
pub struct Side<'a> {
    /// How the side is named in reports (its path, usually).
    pub name: String,
    pub tree: &'a Tree,
    pub session: Option<&'a Session>,
}

impl<'a> Side<'a> {
    pub fn tree(name: impl Into<String>, tree: &'a Tree) -> Side<'a> {
        Side {
            name: name.into(),
            tree,
            session: None,
        }
    }

    pub fn session(name: impl Into<String>, s: &'a Session) -> Side<'a> {
        Side {
            name: name.into(),
            tree: &s.tree,
            session: Some(s),
        }
    }
}

/// How a report describes a side: a run or a tree.
fn what(run: bool) -> &'static str {
    if run {
        "a run: the leaves each subgoal executed"
    } else {
        "a tree: each subgoal's actions in tree order"
    }
}

/// One action of a sequence.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Step {
    pub uid: Uid,
    pub name: String,
    /// For runs: the tick it started in, and how it ended (RUNNING: not yet
    /// at the end of the run; IDLE: halted).
    pub tick: Option<u32>,
    pub outcome: Option<Status>,
}

impl Step {
    fn key(&self, with_outcome: bool) -> String {
        match self.outcome {
            Some(o) if with_outcome => format!("{}\u{0}{}", self.name, o.as_str()),
            _ => self.name.clone(),
        }
    }

    /// The step as a report shows it: `#7 move right`, with the tick and any
    /// outcome but success for runs.
    pub fn label(&self) -> String {
        let mut s = match self.tick {
            Some(t) => format!("t{t} #{} {}", self.uid, self.name),
            None => format!("#{} {}", self.uid, self.name),
        };
        match self.outcome {
            None | Some(Status::Success) => {}
            Some(Status::Idle) => s.push_str(" (halted)"),
            Some(o) => {
                s.push_str(" (");
                s.push_str(o.as_str());
                s.push(')');
            }
        }
        s
    }

    fn json(&self, index: usize) -> Value {
        let mut v = json!({"index": index, "uid": self.uid, "name": self.name});
        if let Some(t) = self.tick {
            v["tick"] = json!(t);
        }
        if let Some(o) = self.outcome {
            v["outcome"] = json!(if o == Status::Idle {
                "HALTED"
            } else {
                o.as_str()
            });
        }
        v
    }
}

/// The steps of one subgoal (or of the goal itself: `subgoal` is the root).
#[derive(Debug, Clone)]
pub struct Sequence {
    pub subgoal: Uid,
    pub name: String,
    pub steps: Vec<Step>,
}

/// The subgoal a node belongs to: its nearest SubTree ancestor, or the root.
fn owner(tree: &Tree, uid: Uid) -> Uid {
    tree.ancestors(uid)
        .find(|&a| tree.node(a).kind == Kind::SubTree)
        .unwrap_or(Tree::ROOT)
}

/// The sequences of a side: the goal's first, then every subgoal in tree
/// order (also those that executed nothing).
pub fn sequences(side: &Side) -> Vec<Sequence> {
    let tree = side.tree;
    let mut seqs = vec![Sequence {
        subgoal: Tree::ROOT,
        name: tree.description(Tree::ROOT).to_string(),
        steps: Vec::new(),
    }];
    let mut slot = vec![0usize; tree.len() + 1];
    for uid in tree.descendants(Tree::ROOT) {
        if uid != Tree::ROOT && tree.node(uid).kind == Kind::SubTree {
            slot[uid as usize] = seqs.len();
            seqs.push(Sequence {
                subgoal: uid,
                name: tree.description(uid).to_string(),
                steps: Vec::new(),
            });
        }
    }
    let step = |uid: Uid, tick, outcome| Step {
        uid,
        name: tree.description(uid).to_string(),
        tick,
        outcome,
    };
    match side.session {
        None => {
            for uid in tree.leaves_below(Tree::ROOT) {
                seqs[slot[owner(tree, uid) as usize]]
                    .steps
                    .push(step(uid, None, None));
            }
        }
        Some(s) => {
            // An execution starts when a leaf leaves IDLE (or a finished
            // status) for RUNNING, SUCCESS or FAILURE; a RUNNING leaf's next
            // transition ends it. Re-ticks that do not change the status
            // leave no record in any log, so they cannot be counted.
            let mut open: Vec<Option<(usize, usize)>> = vec![None; tree.len() + 1];
            for t in &s.index.transitions {
                let Some(node) = tree.get(t.uid) else {
                    continue;
                };
                if !node.kind.is_leaf() {
                    continue;
                }
                if let Some((q, i)) = open[t.uid as usize].take() {
                    seqs[q].steps[i].outcome = Some(t.status);
                    if t.status == Status::Running {
                        open[t.uid as usize] = Some((q, i));
                    }
                    continue;
                }
                let starts = t.prev != Status::Running
                    && matches!(
                        t.status,
                        Status::Running | Status::Success | Status::Failure
                    );
                if starts {
                    let q = slot[owner(tree, t.uid) as usize];
                    seqs[q]
                        .steps
                        .push(step(t.uid, Some(t.tick), Some(t.status)));
                    if t.status == Status::Running {
                        open[t.uid as usize] = Some((q, seqs[q].steps.len() - 1));
                    }
                }
            }
        }
    }
    seqs
}

/// One subgoal compared: its steps on each side and the edit script. A
/// subgoal only one side has gets an empty sequence on the other.
#[derive(Debug, Clone)]
pub struct Section {
    pub name: String,
    pub a_subgoal: Option<Uid>,
    pub b_subgoal: Option<Uid>,
    pub a: Vec<Step>,
    pub b: Vec<Step>,
    pub edits: Vec<Edit>,
    /// The edit script is a shortest one (`false`: the alignment's time
    /// bound was reached, and the distance is an upper bound).
    pub exact: bool,
}

impl Section {
    pub fn distance(&self) -> usize {
        align::distance(&self.edits)
    }

    pub fn lcs(&self) -> usize {
        align::lcs(&self.edits)
    }

    pub fn count(&self, op: Op) -> usize {
        self.edits.iter().filter(|e| e.op == op).count()
    }

    pub fn diverges(&self) -> bool {
        self.edits.iter().any(|e| e.op != Op::Same)
    }

    /// "2 inserted, 1 changed", or "the same".
    pub fn summary(&self) -> String {
        let parts: Vec<String> = [
            (Op::Inserted, "inserted"),
            (Op::Deleted, "deleted"),
            (Op::Changed, "changed"),
        ]
        .iter()
        .filter_map(|&(op, w)| {
            let n = self.count(op);
            (n > 0).then(|| format!("{n} {w}"))
        })
        .collect();
        if parts.is_empty() {
            "the same".into()
        } else {
            parts.join(", ")
        }
    }

    fn json(&self) -> Value {
        let side = |steps: &[Step], i: Option<usize>| i.map(|i| steps[i].json(i));
        let pick = |op: Op| -> Vec<Value> {
            self.edits
                .iter()
                .filter(|e| e.op == op)
                .map(|e| match op {
                    Op::Inserted => side(&self.b, e.b).expect("an insertion is in b"),
                    Op::Deleted => side(&self.a, e.a).expect("a deletion is in a"),
                    _ => json!({"a": side(&self.a, e.a), "b": side(&self.b, e.b)}),
                })
                .collect()
        };
        json!({
            "subgoal": self.name,
            "a_uid": self.a_subgoal,
            "b_uid": self.b_subgoal,
            "a_len": self.a.len(),
            "b_len": self.b.len(),
            "distance": self.distance(),
            "exact": self.exact,
            "lcs": self.lcs(),
            "inserted": pick(Op::Inserted),
            "deleted": pick(Op::Deleted),
            "changed": pick(Op::Changed),
            "edits": self.edits.iter().map(|e| json!({
                "op": e.op,
                "a": side(&self.a, e.a),
                "b": side(&self.b, e.b),
            })).collect::<Vec<_>>(),
        })
    }
}

/// Two sides compared, subgoal by subgoal.
#[derive(Debug, Clone)]
pub struct Diff {
    pub a_name: String,
    pub b_name: String,
    /// Whether each side is a run (else a tree).
    pub a_run: bool,
    pub b_run: bool,
    pub sections: Vec<Section>,
}

impl Diff {
    pub fn new(a: &Side, b: &Side) -> Diff {
        let outcomes = a.session.is_some() && b.session.is_some();
        let (sa, sb) = (sequences(a), sequences(b));
        let mut sections = Vec::new();
        let mut pair = |x: Option<&Sequence>, y: Option<&Sequence>| {
            let name = match (x, y) {
                (Some(x), Some(y)) if x.name != y.name => format!("{} → {}", x.name, y.name),
                _ => x.or(y).map(|s| s.name.clone()).unwrap_or_default(),
            };
            let empty = Vec::new();
            let xs = x.map_or(&empty, |s| &s.steps);
            let ys = y.map_or(&empty, |s| &s.steps);
            let kx: Vec<String> = xs.iter().map(|s| s.key(outcomes)).collect();
            let ky: Vec<String> = ys.iter().map(|s| s.key(outcomes)).collect();
            let (edits, exact) = align::edits_bounded(&kx, &ky);
            sections.push(Section {
                name,
                a_subgoal: x.map(|s| s.subgoal),
                b_subgoal: y.map(|s| s.subgoal),
                a: xs.clone(),
                b: ys.clone(),
                edits,
                exact,
            });
        };
        // The goals always pair; subgoals pair by name, in order, and a
        // subgoal renamed in place pairs with its new name (which never
        // costs more than deleting one and inserting the other).
        pair(Some(&sa[0]), Some(&sb[0]));
        let na: Vec<&str> = sa[1..].iter().map(|s| s.name.as_str()).collect();
        let nb: Vec<&str> = sb[1..].iter().map(|s| s.name.as_str()).collect();
        for e in align::edits(&na, &nb) {
            match e.op {
                Op::Same | Op::Changed => pair(e.a.map(|i| &sa[i + 1]), e.b.map(|i| &sb[i + 1])),
                _ => {
                    if let Some(i) = e.a {
                        pair(Some(&sa[i + 1]), None);
                    }
                    if let Some(i) = e.b {
                        pair(None, Some(&sb[i + 1]));
                    }
                }
            }
        }
        Diff {
            a_name: a.name.clone(),
            b_name: b.name.clone(),
            a_run: a.session.is_some(),
            b_run: b.session.is_some(),
            sections,
        }
    }

    /// Whether outcomes are compared too (both sides are runs): a leaf that
    /// failed is then a different step from the same leaf succeeding.
    pub fn outcomes(&self) -> bool {
        self.a_run && self.b_run
    }

    pub fn distance(&self) -> usize {
        self.sections.iter().map(Section::distance).sum()
    }

    pub fn lcs(&self) -> usize {
        self.sections.iter().map(Section::lcs).sum()
    }

    pub fn is_empty(&self) -> bool {
        !self.sections.iter().any(Section::diverges)
    }

    /// Every divergent edit, in report order: (section, edit index).
    pub fn divergences(&self) -> Vec<(usize, usize)> {
        let mut out = Vec::new();
        for (s, sec) in self.sections.iter().enumerate() {
            for (i, e) in sec.edits.iter().enumerate() {
                if e.op != Op::Same {
                    out.push((s, i));
                }
            }
        }
        out
    }

    /// The nodes of either side that diverge: (uids in a, uids in b).
    pub fn divergent_nodes(&self) -> (Vec<Uid>, Vec<Uid>) {
        let (mut a, mut b) = (Vec::new(), Vec::new());
        for sec in &self.sections {
            for e in sec.edits.iter().filter(|e| e.op != Op::Same) {
                a.extend(e.a.map(|i| sec.a[i].uid));
                b.extend(e.b.map(|i| sec.b[i].uid));
            }
        }
        (a, b)
    }

    /// One sentence about an edit: what B does there that A does not.
    pub fn describe(&self, section: usize, edit: usize) -> String {
        self.describe_as(section, edit, "A", "B")
    }

    /// The same, naming the sides `an` and `bn`.
    pub fn describe_as(&self, section: usize, edit: usize, an: &str, bn: &str) -> String {
        let sec = &self.sections[section];
        let e = sec.edits[edit];
        let a = e.a.map(|i| &sec.a[i]);
        let b = e.b.map(|i| &sec.b[i]);
        let nth = |i: usize| ordinal(i + 1);
        match (e.op, a, b) {
            (Op::Inserted, _, Some(y)) => format!(
                "{}: {bn}'s {} action, {}, is not in {an}",
                sec.name,
                nth(e.b.unwrap_or(0)),
                quoted(y)
            ),
            (Op::Deleted, Some(x), _) => format!(
                "{}: {an}'s {} action, {}, is not in {bn}",
                sec.name,
                nth(e.a.unwrap_or(0)),
                quoted(x)
            ),
            (Op::Changed, Some(x), Some(y)) => format!(
                "{}: {an}'s {} action, {}, is {} in {bn}",
                sec.name,
                nth(e.a.unwrap_or(0)),
                quoted(x),
                quoted(y)
            ),
            _ => format!("{}: the same", sec.name),
        }
    }

    pub fn text(&self) -> String {
        let mut out = format!(
            "A  {}  ({})\nB  {}  ({})\n",
            self.a_name,
            what(self.a_run),
            self.b_name,
            what(self.b_run)
        );
        let width = self
            .sections
            .iter()
            .flat_map(|s| s.a.iter())
            .map(|s| s.label().chars().count())
            .max()
            .unwrap_or(0)
            .max(1);
        for sec in &self.sections {
            if sec.a.is_empty() && sec.b.is_empty() {
                continue;
            }
            let only = match (sec.a_subgoal, sec.b_subgoal) {
                (Some(_), None) => " (only in A)",
                (None, Some(_)) => " (only in B)",
                _ => "",
            };
            out.push_str(&format!(
                "\n{}{only}: edit distance {}{}, LCS {} (A {}, B {}): {}\n",
                sec.name,
                sec.distance(),
                if sec.exact {
                    ""
                } else {
                    " at most (aligning took longer than 2 s)"
                },
                sec.lcs(),
                plural(sec.a.len(), "action"),
                plural(sec.b.len(), "action"),
                sec.summary()
            ));
            for e in &sec.edits {
                let mark = match e.op {
                    Op::Same => ' ',
                    Op::Inserted => '+',
                    Op::Deleted => '-',
                    Op::Changed => '~',
                };
                let left = e.a.map(|i| sec.a[i].label()).unwrap_or_default();
                let right = e.b.map(|i| sec.b[i].label()).unwrap_or_default();
                let line = format!("  {mark} {left:<width$}   {right}");
                out.push_str(line.trim_end());
                out.push('\n');
            }
        }
        let steps: usize = self.sections.iter().map(|s| s.a.len()).sum();
        if self.is_empty() {
            out.push_str(&format!(
                "\nNo divergence: every subgoal has the same {} in A and B.\n",
                plural(steps, "action")
            ));
        } else {
            let (s, i) = self.divergences()[0];
            out.push_str(&format!(
                "\nIn all: edit distance {}{}, LCS {}. First divergence: {}.\n",
                self.distance(),
                if self.sections.iter().all(|s| s.exact) {
                    ""
                } else {
                    " at most"
                },
                self.lcs(),
                self.describe(s, i)
            ));
        }
        out
    }

    pub fn json(&self) -> Value {
        let first = self.divergences().first().map(|&(s, i)| {
            json!({
                "subgoal": self.sections[s].name,
                "edit": i,
                "text": self.describe(s, i),
            })
        });
        json!({
            "a": {"name": self.a_name, "kind": kind(self.a_run)},
            "b": {"name": self.b_name, "kind": kind(self.b_run)},
            "outcomes_compared": self.outcomes(),
            "identical": self.is_empty(),
            "distance": self.distance(),
            "lcs": self.lcs(),
            "first_divergence": first,
            "sections": self.sections.iter().map(Section::json).collect::<Vec<_>>(),
        })
    }
}

fn kind(run: bool) -> &'static str {
    if run {
        "run"
    } else {
        "tree"
    }
}

/// `"move right" (#7)`, with a run's tick and any outcome but success.
fn quoted(s: &Step) -> String {
    let mut out = format!("\"{}\" (#{}", s.name, s.uid);
    if let Some(t) = s.tick {
        out.push_str(&format!(", tick {t}"));
    }
    match s.outcome {
        None | Some(Status::Success) => {}
        Some(Status::Idle) => out.push_str(", halted"),
        Some(o) => out.push_str(&format!(", {}", o.as_str())),
    }
    out.push(')');
    out
}

fn plural(n: usize, w: &str) -> String {
    if n == 1 {
        format!("1 {w}")
    } else {
        format!("{n} {w}s")
    }
}

fn ordinal(n: usize) -> String {
    let suffix = match (n % 10, n % 100) {
        (_, 11..=13) => "th",
        (1, _) => "st",
        (2, _) => "nd",
        (3, _) => "rd",
        _ => "th",
    };
    format!("{n}{suffix}")
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
mod tests {
    use super::*;

    #[test]
    fn ordinals_read_as_english() {
        let got: Vec<String> = [1, 2, 3, 4, 11, 12, 13, 21, 22, 103]
            .into_iter()
            .map(ordinal)
            .collect();
        assert_eq!(
            got,
            ["1st", "2nd", "3rd", "4th", "11th", "12th", "13th", "21st", "22nd", "103rd"]
        );
    }
}
