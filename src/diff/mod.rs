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
    /// Shared by every step of its node: a long run has millions of steps.
    pub name: std::sync::Arc<str>,
    /// For runs: the tick it started in, and how it ended (RUNNING: not yet
    /// at the end of the run; IDLE: halted).
    pub tick: Option<u32>,
    pub outcome: Option<Status>,
    /// For runs: the transitions it spans, from its start to its outcome
    /// (0-based indices into the run's transitions).
    pub span: Option<(u32, u32)>,
    /// For runs: which run of the root it started in (from 0: the root's
    /// completions before it).
    pub episode: u32,
}

impl Step {
    /// What the alignment compares: the name, and the outcome too.
    fn key(&self, with_outcome: bool) -> (&str, Option<Status>) {
        (&self.name, self.outcome.filter(|_| with_outcome))
    }

    /// The transitions it spans, as indices.
    pub fn span(&self) -> Option<(usize, usize)> {
        self.span.map(|(a, b)| (a as usize, b as usize))
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
        let mut v = json!({"index": index, "uid": self.uid, "name": &*self.name});
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
    let (mut seqs, slot) = subgoals(tree);
    let names: Vec<std::sync::Arc<str>> = (0..=tree.len() as Uid)
        .map(|u| {
            tree.get(u)
                .map_or("".into(), |_| tree.description(u).into())
        })
        .collect();
    let step = |uid: Uid, tick, outcome, span, episode| Step {
        uid,
        name: names[uid as usize].clone(),
        tick,
        outcome,
        span,
        episode,
    };
    match side.session {
        None => {
            for uid in tree.leaves_below(Tree::ROOT) {
                seqs[slot[owner(tree, uid) as usize]]
                    .steps
                    .push(step(uid, None, None, None, 0));
            }
        }
        Some(s) => executions(tree, s, &slot, &mut seqs, &step),
    }
    seqs
}

/// A sequence for the root and for each SubTree, empty, and each SubTree's
/// place among them by uid.
fn subgoals(tree: &Tree) -> (Vec<Sequence>, Vec<usize>) {
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
    (seqs, slot)
}

/// A made step: uid, tick, outcome, span, episode.
type MakeStep<'a> = dyn Fn(Uid, Option<u32>, Option<Status>, Option<(u32, u32)>, u32) -> Step + 'a;

/// Each execution of a leaf in the run, as a step of its subgoal's
/// sequence. An execution starts when a leaf leaves IDLE (or a finished
/// status) for RUNNING, SUCCESS or FAILURE; a RUNNING leaf's next
/// transition ends it. Re-ticks that do not change the status leave no
/// record in any log, so they cannot be counted.
fn executions(tree: &Tree, s: &Session, slot: &[usize], seqs: &mut [Sequence], step: &MakeStep) {
    let mut open: Vec<Option<(usize, usize)>> = vec![None; tree.len() + 1];
    let mut episode = 0;
    for (k, t) in s.index.transitions.iter().enumerate() {
        if t.uid == Tree::ROOT && t.status.is_completed() {
            episode += 1;
        }
        let Some(node) = tree.get(t.uid) else {
            continue;
        };
        if !node.kind.is_leaf() {
            continue;
        }
        if let Some((q, i)) = open[t.uid as usize].take() {
            let st = &mut seqs[q].steps[i];
            st.outcome = Some(t.status);
            st.span = st.span.map(|(from, _)| (from, k as u32));
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
            seqs[q].steps.push(step(
                t.uid,
                Some(t.tick),
                Some(t.status),
                Some((k as u32, k as u32)),
                episode,
            ));
            if t.status == Status::Running {
                open[t.uid as usize] = Some((q, seqs[q].steps.len() - 1));
            }
        }
    }
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
    /// What each edit is to the comparison of two runs (parallel to `edits`).
    pub roles: Vec<Role>,
}

/// What a divergent edit is, between two runs: where they part ways, a
/// step that only ran (or did not) because they had parted, or a
/// difference of its own after that (a leaf both ran, ending otherwise).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Role {
    Same,
    /// The edit whose step holds the first transition where the runs differ.
    Parting,
    /// Inserted or deleted after the parting: the runs took other paths.
    Follows,
    /// A divergence of its own: a step both runs made, ending otherwise
    /// (or any divergence between two trees).
    Own,
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
            return "the same".into();
        }
        let mut out = parts.join(", ");
        let follow = self.roles.iter().filter(|r| **r == Role::Follows).count();
        if self.roles.contains(&Role::Parting) {
            out.push_str("; the first divergence (>)");
        }
        if follow > 0 {
            out.push_str(&format!(
                "; {follow} {} from where they part (·)",
                if follow == 1 { "follows" } else { "follow" }
            ));
        }
        out
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
            "edits": self.edits.iter().zip(&self.roles).map(|(e, r)| json!({
                "op": e.op,
                "role": r,
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
    /// Two runs: the first transition where they differ, and that in
    /// words ("at transition 32 (moment 10:1): … became FAILURE in B …").
    pub parting: Option<crate::session::parting::Difference>,
    pub parting_text: Option<String>,
    /// Whether the step marked as the parting holds that transition (else
    /// it is the first divergent step after it: the transition was in a
    /// step both runs made alike, as a leaf RUNNING one tick longer).
    pub parting_held: bool,
    /// Two runs that ended apart (one FAILURE, the other not): the edit
    /// holding the failing run's last fault before its root failed, what
    /// decided the outcome (`explain::fault`: never a check that answered
    /// no as designed).
    pub decisive: Option<(usize, usize)>,
}

/// The position (0-based) of the last leaf fault before the run's root
/// failed, when it failed.
fn last_fault(s: &Session) -> Option<usize> {
    let idx = &s.index;
    let failed = match last_root_completion(s)? {
        (p, Status::Failure) => p as usize - 1,
        _ => return None,
    };
    (0..failed).rev().find(|&q| {
        s.tree.node(idx.transitions[q].uid).kind.is_leaf()
            && crate::explain::fault::is_fault(&s.tree, idx, q as u32 + 1)
    })
}

/// Where and how a run's root last completed.
fn last_root_completion(s: &Session) -> Option<(u32, Status)> {
    let end = s.index.transitions.len() as u32;
    s.index.at(end).last_completion(s.tree.root().uid)
}

/// Between two runs, a changed pair of two different leaves says nothing
/// true ("A's stop is B's scan"): it is one step deleted and one inserted.
fn unlike_apart(edits: Vec<Edit>, a: &[Step], b: &[Step]) -> Vec<Edit> {
    let mut out = Vec::with_capacity(edits.len());
    for e in edits {
        match (e.op, e.a, e.b) {
            (Op::Changed, Some(i), Some(j)) if a[i].name != b[j].name => {
                out.push(Edit {
                    op: Op::Deleted,
                    a: Some(i),
                    b: None,
                });
                out.push(Edit {
                    op: Op::Inserted,
                    a: None,
                    b: Some(j),
                });
            }
            _ => out.push(e),
        }
    }
    out
}

/// Gives each divergent edit its role, the runs parting at transition
/// `at`: the edit whose step holds that transition (or, when none does,
/// the first to start after it) is the parting; after it, steps only one
/// run made follow from it (`follow`: runs of one tree, whose paths part
/// only through what happened; runs of two trees also differ where the
/// trees do), and a step both made that ended otherwise is a divergence
/// of its own.
fn mark_parting(sections: &mut [Section], at: usize, follow: bool) -> bool {
    let when = |st: &Step| match st.span() {
        Some((from, to)) if from <= at && at <= to => at,
        Some((from, _)) => from,
        None => usize::MAX,
    };
    let whens: Vec<Vec<usize>> = sections
        .iter()
        .map(|sec| {
            sec.edits
                .iter()
                .map(|e| {
                    let a = e.a.map(|k| when(&sec.a[k]));
                    a.into_iter()
                        .chain(e.b.map(|k| when(&sec.b[k])))
                        .min()
                        .unwrap_or(usize::MAX)
                })
                .collect()
        })
        .collect();
    let mut first: Option<(usize, usize, usize)> = None;
    for (s, sec) in sections.iter().enumerate() {
        for (i, e) in sec.edits.iter().enumerate() {
            let w = whens[s][i];
            if e.op != Op::Same && w >= at && first.is_none_or(|f| w < f.0) {
                first = Some((w, s, i));
            }
        }
    }
    let Some((held, ps, pi)) = first else {
        return false;
    };
    for (s, sec) in sections.iter_mut().enumerate() {
        for (i, e) in sec.edits.iter().enumerate() {
            sec.roles[i] = match e.op {
                Op::Same => Role::Same,
                _ if (s, i) == (ps, pi) => Role::Parting,
                // Before the parting the runs are one: an alignment that
                // says otherwise (past its time bound) is shown as it is.
                _ if whens[s][i] < at => Role::Own,
                Op::Changed => Role::Own,
                _ if follow => Role::Follows,
                _ => Role::Own,
            };
        }
    }
    held == at
}

/// The section of a subgoal of A (`x`) and of B (`y`), either of which
/// may be missing: their steps aligned.
fn section(x: Option<Sequence>, y: Option<Sequence>, outcomes: bool) -> Section {
    let name = match (&x, &y) {
        (Some(x), Some(y)) if x.name != y.name => format!("{} → {}", x.name, y.name),
        _ => x
            .as_ref()
            .or(y.as_ref())
            .map(|s| s.name.clone())
            .unwrap_or_default(),
    };
    let (a_subgoal, b_subgoal) = (x.as_ref().map(|s| s.subgoal), y.as_ref().map(|s| s.subgoal));
    let xs = x.map(|s| s.steps).unwrap_or_default();
    let ys = y.map(|s| s.steps).unwrap_or_default();
    let (edits, exact) = align_steps(&xs, &ys, outcomes);
    let roles = edits
        .iter()
        .map(|e| {
            if e.op == Op::Same {
                Role::Same
            } else {
                Role::Own
            }
        })
        .collect();
    Section {
        name,
        a_subgoal,
        b_subgoal,
        a: xs,
        b: ys,
        edits,
        exact,
        roles,
    }
}

/// The edits from steps `xs` to `ys`, and whether they are the fewest.
fn align_steps(xs: &[Step], ys: &[Step], outcomes: bool) -> (Vec<Edit>, bool) {
    let kx: Vec<_> = xs.iter().map(|s| s.key(outcomes)).collect();
    let ky: Vec<_> = ys.iter().map(|s| s.key(outcomes)).collect();
    // Runs that differ in a few places are aligned exactly, however
    // long (Myers' cost is length × distance).
    let near = align::edits_near(&kx, &ky);
    let (edits, exact) = if let Some(e) = near {
        (e, true)
    } else if outcomes {
        // Two long runs far apart: run of the root by run of the
        // root, then tick by tick, so that the answer does not hang
        // on a time bound (and so on the machine's load).
        let episode =
            |first: bool, i: usize| u64::from(if first { xs[i].episode } else { ys[i].episode });
        let tick = |first: bool, i: usize| {
            u64::from(if first { xs[i].tick } else { ys[i].tick }.unwrap_or(0))
        };
        (align::edits_by_units(&kx, &ky, &[&episode, &tick]), false)
    } else {
        align::edits_bounded(&kx, &ky)
    };
    if outcomes {
        return (unlike_apart(edits, xs, ys), exact);
    }
    (edits, exact)
}

impl Diff {
    pub fn new(a: &Side, b: &Side) -> Diff {
        let outcomes = a.session.is_some() && b.session.is_some();
        let (sa, sb) = (sequences(a), sequences(b));
        // The subgoals pair by name, in order, and a subgoal renamed in
        // place pairs with its new name (which never costs more than
        // deleting one and inserting the other).
        let subgoals = {
            let na: Vec<&str> = sa[1..].iter().map(|s| s.name.as_str()).collect();
            let nb: Vec<&str> = sb[1..].iter().map(|s| s.name.as_str()).collect();
            align::edits(&na, &nb)
        };
        // Each sequence goes into one section, moved, not copied.
        let (mut sa, mut sb): (Vec<_>, Vec<_>) = (
            sa.into_iter().map(Some).collect(),
            sb.into_iter().map(Some).collect(),
        );
        let mut sections = Vec::new();
        let mut pair =
            |x: Option<Sequence>, y: Option<Sequence>| sections.push(section(x, y, outcomes));
        // The goals always pair.
        pair(sa[0].take(), sb[0].take());
        for e in subgoals {
            let x = e.a.and_then(|i| sa[i + 1].take());
            let y = e.b.and_then(|i| sb[i + 1].take());
            match e.op {
                Op::Same | Op::Changed => pair(x, y),
                _ => {
                    if x.is_some() {
                        pair(x, None);
                    }
                    if y.is_some() {
                        pair(None, y);
                    }
                }
            }
        }
        let parting = match (a.session, b.session) {
            (Some(x), Some(y)) => crate::session::parting::first_difference(x, y),
            _ => None,
        };
        let parting_held = parting
            .as_ref()
            .is_some_and(|p| mark_parting(&mut sections, p.index, same_shape(a.tree, b.tree)));
        let parting_text = parting.as_ref().map(|p| p.text(a.tree, b.tree, "A", "B"));
        let mut d = Diff {
            a_name: a.name.clone(),
            b_name: b.name.clone(),
            a_run: a.session.is_some(),
            b_run: b.session.is_some(),
            sections,
            parting,
            parting_text,
            parting_held,
            decisive: None,
        };
        d.decisive = d.decided(a.session, b.session);
        d
    }

    /// The divergence that decided the outcome, when the runs ended apart.
    fn decided(&self, a: Option<&Session>, b: Option<&Session>) -> Option<(usize, usize)> {
        let (a, b) = (a?, b?);
        let outcome = |s: &Session| last_root_completion(s).map(|(_, st)| st);
        let (oa, ob) = (outcome(a), outcome(b));
        if oa == ob {
            return None;
        }
        let (in_b, fault) = match (oa, ob) {
            (_, Some(Status::Failure)) => (true, last_fault(b)?),
            (Some(Status::Failure), _) => (false, last_fault(a)?),
            _ => return None,
        };
        let holds = |st: &Step| st.span().is_some_and(|(x, y)| x <= fault && fault <= y);
        self.divergences().into_iter().find(|&(s, i)| {
            let (sec, e) = (&self.sections[s], self.sections[s].edits[i]);
            if in_b {
                e.b.is_some_and(|k| holds(&sec.b[k]))
            } else {
                e.a.is_some_and(|k| holds(&sec.a[k]))
            }
        })
    }

    /// The edit where the runs part ways: (section, edit).
    pub fn parting_edit(&self) -> Option<(usize, usize)> {
        self.edits_with(Role::Parting).next()
    }

    fn edits_with(&self, role: Role) -> impl Iterator<Item = (usize, usize)> + '_ {
        self.sections.iter().enumerate().flat_map(move |(s, sec)| {
            sec.roles
                .iter()
                .enumerate()
                .filter(move |(_, r)| **r == role)
                .map(move |(i, _)| (s, i))
        })
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

    /// The divergences, (section, edit index): where two runs part ways
    /// first, then each divergence of its own in report order (steps that
    /// only follow from the parting are not divergences of their own).
    pub fn divergences(&self) -> Vec<(usize, usize)> {
        self.parting_edit()
            .into_iter()
            .chain(self.edits_with(Role::Own))
            .collect()
    }

    /// The edits that follow from where the runs part ways.
    pub fn following(&self) -> Vec<(usize, usize)> {
        self.edits_with(Role::Follows).collect()
    }

    /// The nodes of either side that diverge: (uids in a, uids in b).
    pub fn divergent_nodes(&self) -> (Vec<Uid>, Vec<Uid>) {
        self.nodes_of(&self.divergences())
    }

    /// The nodes of either side whose steps follow from the parting.
    pub fn following_nodes(&self) -> (Vec<Uid>, Vec<Uid>) {
        self.nodes_of(&self.following())
    }

    fn nodes_of(&self, edits: &[(usize, usize)]) -> (Vec<Uid>, Vec<Uid>) {
        let (mut a, mut b) = (Vec::new(), Vec::new());
        for &(s, i) in edits {
            let (sec, e) = (&self.sections[s], self.sections[s].edits[i]);
            a.extend(e.a.map(|k| sec.a[k].uid));
            b.extend(e.b.map(|k| sec.b[k].uid));
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

    /// The report as text.
    pub fn text(&self) -> String {
        let mut out = Vec::new();
        self.write_text(&mut out).expect("writing to memory");
        String::from_utf8(out).expect("the report is text")
    }

    /// Writes the report as text a line at a time: a long run's report
    /// is not held whole.
    pub fn write_text(&self, out: &mut dyn std::io::Write) -> std::io::Result<()> {
        write!(
            out,
            "A  {}  ({})\nB  {}  ({})\n",
            self.a_name,
            what(self.a_run),
            self.b_name,
            what(self.b_run)
        )?;
        if self.parting_edit().is_some() {
            out.write_all(if self.parting_held {
                b"> where the runs part ways"
            } else {
                b"> the first step to differ after the runs part ways"
            })?;
            out.write_all("   · a step made (or not) only because they had parted\n".as_bytes())?;
        }
        let width = self
            .sections
            .iter()
            .flat_map(|s| s.a.iter())
            .map(|s| s.label().chars().count())
            .max()
            .unwrap_or(0)
            .max(1);
        for sec in &self.sections {
            self.write_section(out, sec, width)?;
        }
        self.write_in_all(out)
    }

    /// A subgoal's section: its distances and its steps side by side,
    /// each marked as the same, inserted, deleted or changed.
    fn write_section(
        &self,
        out: &mut dyn std::io::Write,
        sec: &Section,
        width: usize,
    ) -> std::io::Result<()> {
        if sec.a.is_empty() && sec.b.is_empty() {
            return Ok(());
        }
        let only = match (sec.a_subgoal, sec.b_subgoal) {
            (Some(_), None) => " (only in A)",
            (None, Some(_)) => " (only in B)",
            _ => "",
        };
        write!(
            out,
            "\n{}{only}: edit distance {}{}, LCS {} (A {}, B {}): {}\n",
            sec.name,
            sec.distance(),
            if sec.exact {
                ""
            } else {
                if self.outcomes() {
                    " at most (aligned run of the root by run of the root, then tick by tick)"
                } else {
                    " at most (aligning took longer than 2 s)"
                }
            },
            sec.lcs(),
            plural(sec.a.len(), "action"),
            plural(sec.b.len(), "action"),
            sec.summary()
        )?;
        for (e, role) in sec.edits.iter().zip(&sec.roles) {
            let mark = match e.op {
                Op::Same => ' ',
                Op::Inserted => '+',
                Op::Deleted => '-',
                Op::Changed => '~',
            };
            let lead = match role {
                Role::Parting => '>',
                Role::Follows => '·',
                _ => ' ',
            };
            let left = e.a.map(|i| sec.a[i].label()).unwrap_or_default();
            let right = e.b.map(|i| sec.b[i].label()).unwrap_or_default();
            let line = format!("{lead} {mark} {left:<width$}   {right}");
            writeln!(out, "{}", line.trim_end())?;
        }
        Ok(())
    }

    /// The last paragraph: the distances in all, what decided the outcome,
    /// where the runs part and the first divergence.
    fn write_in_all(&self, out: &mut dyn std::io::Write) -> std::io::Result<()> {
        let steps: usize = self.sections.iter().map(|s| s.a.len()).sum();
        let parted = self
            .parting_text
            .as_ref()
            .map(|p| format!(" The runs part ways {p}."))
            .unwrap_or_default();
        if self.is_empty() {
            let but = if parted.is_empty() { "" } else { " Yet" };
            write!(
                out,
                "\nNo divergence: every subgoal has the same {} in A and B.{}\n",
                plural(steps, "action"),
                parted.replacen(" The", &format!("{but} the"), 1)
            )?;
        } else {
            let (s, i) = self.divergences()[0];
            let follow = self.following().len();
            let others = self.divergences().len() - 1;
            let after = if self.parting_edit().is_some() {
                let follow = match follow {
                    0 => "no step follows from where they part".to_string(),
                    1 => "1 step follows from where they part".to_string(),
                    n => format!("{n} steps follow from where they part"),
                };
                let others = match others {
                    0 => "none diverges of its own".to_string(),
                    1 => "1 more diverges of its own".to_string(),
                    n => format!("{n} more diverge of their own"),
                };
                format!(" After it, {follow}, and {others}.")
            } else {
                String::new()
            };
            // What decided the outcome comes first, where it is not the
            // first divergence already.
            let decided = match self.decisive {
                Some(d) if d != (s, i) => {
                    format!(" What decided the outcome: {}.", self.describe(d.0, d.1))
                }
                _ => String::new(),
            };
            write!(
                out,
                "\nIn all: edit distance {}{}, LCS {}.{decided}{parted} First divergence: {}.{after}\n",
                self.distance(),
                if self.sections.iter().all(|s| s.exact) {
                    ""
                } else {
                    " at most"
                },
                self.lcs(),
                self.describe(s, i)
            )?;
        }
        Ok(())
    }

    pub fn json(&self) -> Value {
        let first = self.divergences().first().map(|&(s, i)| {
            json!({
                "subgoal": self.sections[s].name,
                "edit": i,
                "text": self.describe(s, i),
            })
        });
        let parting = self.parting.as_ref().map(|p| {
            json!({
                "transition": p.index + 1,
                "moment": p.moment.to_string(),
                "text": self.parting_text,
                "following": self.following().len(),
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
            "decisive": self.decisive.map(|(s, i)| json!({
                "subgoal": self.sections[s].name,
                "edit": i,
                "text": self.describe(s, i),
            })),
            "parting": parting,
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

pub use crate::model::same_shape;

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
