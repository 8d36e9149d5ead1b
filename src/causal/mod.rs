//! Counterfactual explanations (Love et al.): the explanation model of a
//! tick, the counterfactual search, and answers in plain English.
//!
//! The model is built per tick from a session: the tree, the domain the run
//! used (or one given), and the facts of the tick replayed through the
//! executor. Without a domain the model has the tree's structure only and
//! leaf outcomes are exogenous, so structural questions ("why did ask not
//! run?") still get answers.

pub mod ahead;
pub mod attempts;
pub mod calls;
pub mod chain;
pub mod compare;
pub mod english;
pub mod eval;
pub mod facts;
pub mod graph;
pub mod model;
pub mod query;
pub mod relevance;
pub mod search;
pub mod truth;
pub mod verify;

pub use facts::TickFacts;
pub use model::{Model, Val, VarId, VarKind};
pub use search::{search, Answer, Explanation, Next, Query};

use crate::run::domain::Domain;
use crate::session::{Moment, Session};
use crate::source::Located;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The domain a session's run used (embedded in it), or `over` instead.
pub fn session_domain(
    session: &Session,
    over: Option<&Path>,
) -> Result<Option<Arc<Domain>>, Located> {
    if let Some(p) = over {
        return Ok(Some(Arc::new(Domain::load(p)?)));
    }
    let src = &session.header.source;
    match (src.kind.as_str(), &src.text) {
        ("domain", Some(text)) => {
            let name = PathBuf::from(format!(
                "{} (domain embedded in {})",
                src.path.as_deref().unwrap_or("domain"),
                session.path.display()
            ));
            Ok(Some(Arc::new(Domain::parse(&name, text)?)))
        }
        _ => Ok(None),
    }
}

/// The explanation model of `tick` of a session.
pub fn model_at(
    session: &Session,
    domain: Option<Arc<Domain>>,
    tick: u32,
) -> Result<Model, Located> {
    let facts = TickFacts::of(session, tick).map_err(|m| Located::file(&session.path, m))?;
    Model::build(&session.tree, domain, facts)
}

/// A variable as the graph view draws it.
#[derive(Debug, Clone, PartialEq)]
pub struct GraphNode {
    pub var: VarId,
    pub name: String,
    pub value: String,
    /// A reason of the picked explanation.
    pub reason: bool,
    /// The variable asked about.
    pub target: bool,
}

/// A variable with its causes and effects in the model.
#[derive(Debug, Clone, PartialEq)]
pub struct Neighbourhood {
    pub centre: GraphNode,
    pub parents: Vec<GraphNode>,
    pub children: Vec<GraphNode>,
}

/// A "why?" question asked and answered.
pub struct Why {
    pub model: Model,
    pub query: Query,
    pub answer: Answer,
    /// The moment asked about, as written back (`TICK` or `TICK:STEP`).
    pub moment: String,
    /// What re-running the tree said of each explanation kept.
    pub checks: Vec<verify::Check>,
    /// Explanations the search found and re-running disproved: their
    /// sentence and what the re-run gave.
    pub dropped: Vec<(String, verify::Check)>,
    /// How many explanations the text shows (`None`: every one); the rest
    /// are counted.
    pub shown: Option<usize>,
    /// Causes found only by running the tree again with a leaf's outcome
    /// changed at a call the model's variables do not stand for (an
    /// earlier call of a node called again within the tick).
    pub call_changes: Vec<CallChange>,
    /// The answer from the run's own calls, where the model of the tick
    /// does not hold the call asked about or could only name later events.
    pub by_calls: Option<calls::Told>,
    /// A control node's failure followed down to the leaf it comes from:
    /// said first (#39 item 3).
    pub root: Option<chain::RootCause>,
    /// Say how each answer was found and checked (`--detail full`).
    pub full: bool,
}

/// A leaf's outcome at one of its calls in the tick, which running the
/// tree again with the other outcome shows to be a cause of the target.
#[derive(Debug, Clone)]
pub struct CallChange {
    pub uid: crate::model::Uid,
    pub call: u32,
    /// The moment its outcome was recorded (`TICK:STEP`).
    pub at: Moment,
    pub was: crate::run::Status,
    pub to: crate::run::Status,
    /// The target's value in the re-run.
    pub outcome: Val,
}

/// Checks every explanation of `answer` by re-running the session, and
/// drops those the re-run disproves. First, an explanation whose change
/// the model cannot follow to the end (a Retry that would try again, a leaf
/// nothing recorded) is said as what the tree would have done next, one
/// explanation per such consequent.
fn verified(
    session: &Session,
    model: &Model,
    query: &Query,
    mut answer: Answer,
    watch: Option<usize>,
) -> (Answer, Vec<verify::Check>, Vec<(String, verify::Check)>) {
    let rerunner = verify::Rerunner::new(session, model.facts.tick);
    let reach = verify::Reach::of(model, query);
    let mut split: Vec<Explanation> = Vec::new();
    for e in answer.explanations.drain(..) {
        split.extend(by_consequent(model, query, &reach, rerunner.is_err(), e));
    }
    let checks = match &rerunner {
        Ok(r) => checked_each(r, model, query, &mut split, watch),
        Err(why) => vec![verify::Check::NotRerun(why.clone()); split.len()],
    };
    let mut kept = Vec::new();
    let mut kept_checks = Vec::new();
    let mut dropped = Vec::new();
    for (e, c) in split.into_iter().zip(checks) {
        if matches!(c, verify::Check::Refuted { .. }) {
            dropped.push((english::sentence(model, query, &e), c));
        } else {
            kept.push(e);
            kept_checks.push(c);
        }
    }
    answer.explanations = kept;
    (answer, kept_checks, dropped)
}

/// An explanation split by what each of its assignments leads to past
/// what the model holds (none: the model follows it to the end); an
/// assignment that leaves the node's last call as it was is dropped.
fn by_consequent(
    model: &Model,
    query: &Query,
    reach: &verify::Reach,
    no_rerun: bool,
    e: Explanation,
) -> Vec<Explanation> {
    let mut parts: Vec<Explanation> = Vec::new();
    for values in &e.values {
        let dos: Vec<(VarId, Val)> = e.vars.iter().copied().zip(values.clone()).collect();
        // One evaluation of the change serves every test below (the
        // search evaluated it already, so it does not fail here).
        let vals = model.evaluate_with(&dos).ok();
        let vals = vals.as_deref();
        // The question is about the node's last call in the tick: a
        // change that leaves it as it was, only in another attempt,
        // explains nothing (a later attempt is said as a retry below).
        let later = vals.and_then(|v| verify::later_attempt_next(model, query, v));
        if later.is_none() && vals.is_some_and(|v| !same_in_tick(model, query, v)) {
            continue;
        }
        // A consequence the model only guesses is said as what it rests
        // on, unless a re-run settles it (below). Then a log's leaves
        // not ticked: what they would have returned decides whether a
        // Retry is reached at all.
        let mut next = vals.and_then(|v| verify::opaque_next(model, reach, v));
        if no_rerun && next.is_none() {
            let one = Explanation {
                values: vec![values.clone()],
                next: None,
                ..e.clone()
            };
            next = verify::unknown_next(model, query, reach, &one);
        }
        if next.is_none() {
            next = later;
        }
        if next.is_none() {
            next = vals.and_then(|v| verify::retry_next(model, query, reach, v));
        }
        match parts.iter_mut().find(|p| p.next == next) {
            Some(p) => p.values.push(values.clone()),
            None => parts.push(Explanation {
                values: vec![values.clone()],
                next,
                ..e.clone()
            }),
        }
    }
    parts
}

/// Each explanation re-run: a retry checked as one; a consequence the
/// model only guesses stands where a re-run confirms it, and is dropped
/// where a re-run disproves it.
fn checked_each(
    r: &verify::Rerunner,
    model: &Model,
    query: &Query,
    split: &mut [Explanation],
    watch: Option<usize>,
) -> Vec<verify::Check> {
    split
        .iter_mut()
        .map(|e| match e.next {
            Some(search::Next::Retry { node, .. }) => r.check_retry(model, query, e, node),
            Some(search::Next::Opaque(_)) => {
                let guess = Explanation {
                    next: None,
                    ..e.clone()
                };
                let c = r.check(model, query, &guess, watch);
                if !matches!(c, verify::Check::NotRerun(_)) {
                    e.next = None;
                }
                c
            }
            _ => r.check(model, query, e, watch),
        })
        .collect()
}

/// Whether, under the values `vals` of a change, each target's value in
/// the tick (its node's last call) is the value the model's variable takes.
fn same_in_tick(model: &Model, query: &Query, vals: &[Val]) -> bool {
    query.targets.iter().all(|&t| {
        model
            .in_tick(t, vals)
            .is_some_and(|x| model.snap(t, &x) == model.snap(t, &vals[t]))
    })
}

impl Why {
    /// The explanations as they read: merged copies, in order.
    pub fn groups(&self) -> Vec<Vec<usize>> {
        english::folded(&self.model, &self.answer)
    }

    pub fn sentences(&self) -> Vec<String> {
        self.groups()
            .iter()
            .map(|g| english::group_sentence(&self.model, &self.query, &self.answer, g))
            .collect()
    }

    /// The tree nodes a merged explanation's reasons are about.
    pub fn reason_nodes(&self, group: usize) -> Vec<crate::model::Uid> {
        let mut out = Vec::new();
        for g in self.groups().get(group).into_iter().flatten() {
            for &v in &self.answer.explanations[*g].vars {
                if let VarKind::Executed(u)
                | VarKind::Status(u)
                | VarKind::Decision(u)
                | VarKind::Attempts(u) = self.model.vars[v].kind
                {
                    let u = self.model.origin(u);
                    if !out.contains(&u) {
                        out.push(u);
                    }
                }
            }
        }
        out
    }

    /// The follow-up question on a merged explanation's first reason: why it
    /// had its value and not the value the explanation changes it to. A
    /// reason about copy 0 of a top-level variable after the first tick is
    /// asked in the tick before, at its end, where its value was set.
    pub fn follow_up(&self, group: usize) -> Option<(String, Vec<String>, Moment)> {
        let groups = self.groups();
        let e = &self.answer.explanations[*groups.get(group)?.first()?];
        let v = *e.vars.first()?;
        let foils: Vec<String> = e
            .values
            .iter()
            .map(|t| english::value_text(&t[0]))
            .collect::<std::collections::BTreeSet<_>>()
            .into_iter()
            .collect();
        let m = &self.model;
        let tick = m.facts.tick;
        let moment = Moment::parse(&self.moment).ok()?;
        // An attempt other than the last has no name to ask by.
        if let VarKind::Executed(u) | VarKind::Status(u) | VarKind::Decision(u) = m.vars[v].kind {
            if m.copy_of(u).is_some() {
                return None;
            }
        }
        Some(match m.vars[v].kind {
            VarKind::State { var, copy: 0 }
                if tick > 1
                    && m.domain
                        .as_ref()
                        .is_some_and(|d| d.vars[var].parents.is_empty()) =>
            {
                let name = m.domain.as_ref()?.vars[var].name.clone();
                (
                    name,
                    foils,
                    Moment {
                        tick: tick - 1,
                        step: None,
                    },
                )
            }
            VarKind::State { .. } => (m.var_name(v), foils, moment),
            VarKind::Executed(u) => (format!("executed(#{u})"), foils, moment),
            VarKind::Status(u) => (format!("status(#{u})"), foils, moment),
            VarKind::Decision(u) => (format!("decision(#{u})"), foils, moment),
            VarKind::Attempts(_) => return None,
        })
    }

    /// The variables a merged explanation intervenes on: its reasons.
    pub fn reason_vars(&self, group: usize) -> Vec<VarId> {
        self.groups()
            .get(group)
            .into_iter()
            .flatten()
            .flat_map(|&i| self.answer.explanations[i].vars.clone())
            .collect()
    }

    /// One variable of the model and its neighbours, for drawing it as a
    /// graph: its parents (causes) and children (effects) in the model,
    /// each as a `GraphNode`. `group` marks the picked explanation's reasons.
    pub fn neighbourhood(&self, v: VarId, group: usize) -> Neighbourhood {
        let m = &self.model;
        let reasons = self.reason_vars(group);
        let node = |x: VarId| GraphNode {
            var: x,
            name: m.var_name(x),
            value: english::value_text(&m.fact[x]),
            reason: reasons.contains(&x),
            target: self.query.targets.contains(&x),
        };
        let mut children: Vec<VarId> = (0..m.vars.len())
            .filter(|&c| m.parents[c].contains(&v))
            .collect();
        children.sort_by_key(|&c| m.display_key(c));
        let mut parents = m.parents[v].clone();
        parents.sort_by_key(|&p| m.display_key(p));
        Neighbourhood {
            centre: node(v),
            parents: parents.into_iter().map(node).collect(),
            children: children.into_iter().map(node).collect(),
        }
    }

    /// The target and its ancestors in layers by distance (0: the target),
    /// each as (name, value, is a reason of `group`).
    pub fn layers(&self, group: usize) -> Vec<Vec<(String, String, bool)>> {
        let m = &self.model;
        let dist = m.distances_to(&self.query.targets);
        let reasons = self.reason_vars(group);
        let mut layers: Vec<Vec<(String, String, bool)>> = Vec::new();
        for v in m.ancestors(&self.query.targets) {
            let d = dist[v];
            if d == usize::MAX {
                continue;
            }
            if layers.len() <= d {
                layers.resize(d + 1, Vec::new());
            }
            layers[d].push((
                m.var_name(v),
                english::value_text(&m.fact[v]),
                reasons.contains(&v),
            ));
        }
        layers
    }

    /// The causes found at calls the model does not hold, as sentences.
    pub fn call_sentences(&self) -> Vec<String> {
        let m = &self.model;
        let t = self.query.targets[0];
        self.call_changes
            .iter()
            .map(|c| {
                let past = |s: crate::run::Status| {
                    if s == crate::run::Status::Success {
                        "succeeded"
                    } else {
                        "failed"
                    }
                };
                format!(
                    "{} because {} (#{}) {} at {}. If it had {} then, {}.",
                    english::capitalised(&english::fact(m, t, &m.fact[t])),
                    m.tree.description(c.uid),
                    c.uid,
                    past(c.was),
                    c.at,
                    past(c.to),
                    english::would(m, t, &c.outcome)
                )
            })
            .collect()
    }

    pub fn text(&self) -> String {
        let text = self.body();
        // The root cause first, after the question.
        // The run's calls name the same leaf already, with more: once.
        let said = |c: &chain::RootCause| {
            self.by_calls.as_ref().is_some_and(|t| {
                t.found
                    .as_ref()
                    .is_ok_and(|f| f.causes.first().map(|x| x.leaf) == c.leaf(&self.model.tree))
            })
        };
        match &self.root {
            Some(c) if !said(c) => {
                let (asked, rest) = text.split_once('\n').unwrap_or((text.as_str(), ""));
                format!("{asked}\n{}\n{rest}", c.text(&self.model.tree))
            }
            _ => text,
        }
    }

    fn body(&self) -> String {
        if let Some(t) = &self.by_calls {
            return t.text(&self.model.tree, self.shown, self.full);
        }
        if !self.call_changes.is_empty() {
            let text = self.model_text();
            let (asked, rest) = text.split_once('\n').unwrap_or((text.as_str(), ""));
            let mut out = format!("{asked}\n");
            for c in self.call_sentences() {
                out.push_str(&format!("• {c}\n"));
                if self.full {
                    out.push_str("  Found by running the tree again with that call's outcome changed (btx's model of the tick does not hold that call).\n");
                }
            }
            out.push_str(rest);
            return out;
        }
        self.model_text()
    }

    fn model_text(&self) -> String {
        let mut out = english::to_text(
            &self.model,
            &self.query,
            &self.answer,
            &self.moment,
            self.shown,
            self.full,
        );
        // How each explanation was checked is said at full detail; that
        // none held is the answer itself.
        let checks = self.checks_text();
        if self.full {
            out.push_str(&checks);
        } else {
            for l in checks
                .lines()
                .filter(|l| l.starts_with("No explanation holds"))
            {
                out.push_str(l);
                out.push('\n');
            }
        }
        out
    }

    /// What re-running said, as lines after the explanations (numbered as
    /// the merged explanations are).
    pub fn checks_text(&self) -> String {
        let mut out = String::new();
        let tick = self.model.facts.tick;
        let mut groups = self.groups();
        // Only the explanations shown are numbered.
        groups.truncate(self.shown.unwrap_or(usize::MAX));
        let mut confirmed = Vec::new();
        let mut unchecked: Vec<(String, Vec<usize>)> = Vec::new();
        for (n, g) in groups.iter().enumerate() {
            match g
                .iter()
                .map(|&i| &self.checks[i])
                .find(|c| matches!(c, verify::Check::NotRerun(_)))
            {
                Some(verify::Check::NotRerun(why)) => {
                    match unchecked.iter_mut().find(|(w, _)| w == why) {
                        Some((_, ns)) => ns.push(n + 1),
                        None => unchecked.push((why.clone(), vec![n + 1])),
                    }
                }
                _ => confirmed.push(n + 1),
            }
        }
        let list = |ns: &[usize]| {
            ns.iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        };
        if unchecked.is_empty() && !confirmed.is_empty() {
            out.push_str(&format!(
                "Checked: running the tree again to tick {tick} with each change gives what {} says.\n",
                if confirmed.len() == 1 { "the explanation" } else { "every explanation" }
            ));
        } else if !confirmed.is_empty() {
            out.push_str(&format!(
                "Checked by running the tree again to tick {tick}: {}.\n",
                list(&confirmed)
            ));
        }
        for (why, ns) in &unchecked {
            if ns.len() == groups.len() {
                out.push_str(&format!("Not checked by running the tree again: {why}.\n"));
            } else {
                out.push_str(&format!(
                    "Not checked by running the tree again: {} ({why}).\n",
                    list(ns)
                ));
            }
        }
        if groups.is_empty() && !self.dropped.is_empty() {
            out.push_str(&format!(
                "No explanation holds: running the tree again disproved {} the model found.\n",
                if self.dropped.len() == 1 {
                    "the one".to_string()
                } else {
                    format!("all {}", self.dropped.len())
                }
            ));
        }
        for (sentence, c) in &self.dropped {
            if let verify::Check::Refuted {
                change,
                subject,
                claimed,
                got,
            } = c
            {
                out.push_str(&format!(
                    "dropped, as running the tree again disproved it: \"{sentence}\" (with {change}, {subject} was {got}, not {claimed})\n"
                ));
            }
        }
        out
    }

    pub fn json(&self) -> serde_json::Value {
        let mut j = english::to_json(&self.model, &self.query, &self.answer, &self.moment);
        let groups = self.groups();
        if let Some(list) = j["explanations"].as_array_mut() {
            for (x, g) in list.iter_mut().zip(&groups) {
                x["checks"] = g.iter().map(|&i| self.checks[i].json()).collect();
            }
        }
        if let Some(t) = &self.by_calls {
            j["question"] = serde_json::Value::from(t.question(&self.model.tree));
            j["by_calls"] = t.json(&self.model.tree);
        }
        if let Some(c) = &self.root {
            j["root_cause"] = serde_json::json!({
                "text": c.text(&self.model.tree),
                "leaf": c.leaf(&self.model.tree),
                "chain": c.chain.iter().zip(&c.moments).map(|(&(u, _, st), m)| serde_json::json!({
                    "uid": u, "status": st.as_str(), "at": m.to_string(),
                })).collect::<Vec<_>>(),
            });
        }
        j["call_changes"] = self
            .call_changes
            .iter()
            .zip(self.call_sentences())
            .map(|(c, text)| {
                serde_json::json!({
                    "text": text,
                    "uid": c.uid,
                    "call": c.call,
                    "at": c.at.to_string(),
                    "was": c.was.as_str(),
                    "to": c.to.as_str(),
                    "outcome": english::value_json(&c.outcome),
                    "rerun": true,
                    "confirmed": true,
                })
            })
            .collect();
        j["dropped"] = self
            .dropped
            .iter()
            .map(|(s, c)| {
                let mut v = c.json();
                v["text"] = serde_json::Value::from(s.clone());
                v
            })
            .collect();
        j
    }
}

/// The position from which a node's fact in the model of `tick` holds
/// within the tick (`None`: from its start): Love §5.3 explains a fact at
/// a time only if it holds then. A status holds once the node's last
/// transition into it in the tick was made; a decision or a node's having
/// run, once it was first ticked.
fn fact_from(session: &Session, model: &Model, v: VarId, tick: u32) -> Option<u32> {
    let range = session.index.tick_range(tick);
    // A copy stands for a call that had ended by the moment (`call_at`).
    if let VarKind::Status(u) | VarKind::Executed(u) | VarKind::Decision(u) | VarKind::Attempts(u) =
        model.vars[v].kind
    {
        if model.copy_of(u).is_some() {
            return None;
        }
    }
    let in_tick = |u: crate::model::Uid| {
        session
            .index
            .changes_of(u)
            .iter()
            .copied()
            .filter(move |&p| range.contains(&(p as usize - 1)))
    };
    let status_of = |p: u32| session.index.transitions[p as usize - 1].status;
    match (model.vars[v].kind, &model.fact[v]) {
        (VarKind::Status(u), Val::Status(s)) if *s != crate::run::Status::Idle => {
            in_tick(u).rfind(|&p| status_of(p) == *s)
        }
        (VarKind::Executed(u), Val::Bool(true)) | (VarKind::Decision(u), Val::Action(Some(_))) => {
            in_tick(u).next()
        }
        _ => None,
    }
}

/// At a step, the node asked about has just completed, as the log shows,
/// but the model's variable stands for another of its calls in the tick
/// (one it does not follow): the question would be another's.
fn another_call(
    session: &Session,
    model: &Model,
    v: VarId,
    moment: Moment,
    pos: u32,
) -> Option<String> {
    let (VarKind::Status(u), Some(_)) = (model.vars[v].kind, moment.step) else {
        return None;
    };
    let origin = model.origin(u);
    let range = session.index.tick_range(moment.tick);
    let logged = session
        .index
        .changes_of(origin)
        .iter()
        .copied()
        .filter(|&p| range.contains(&(p as usize - 1)) && p <= pos)
        .map(|p| session.index.transitions[p as usize - 1].status)
        .rfind(|s| matches!(s, crate::run::Status::Success | crate::run::Status::Failure))?;
    (model.fact[v] != Val::Status(logged)).then(|| {
        format!(
            "at {moment} {} (#{origin}) has just {}, as the run shows, but btx's model of tick {} does not hold that call (in the model, {}): it does not follow the tick's control flow around it (a node called again within the tick, as by a Nav2 RecoveryNode going back to its first child); ask at the end of tick {}, or about the nodes below it",
            model.tree.description(origin),
            if logged == crate::run::Status::Success { "succeeded" } else { "failed" },
            moment.tick,
            english::fact(model, v, &model.fact[v]),
            moment.tick
        )
    })
}

/// The last tick of a run: the tick of its last transition when the root
/// had completed by then, else the last tick the session counts.
pub fn last_tick(session: &Session) -> u32 {
    let idx = &session.index;
    let end = idx.at(idx.transitions.len() as u32);
    match (end.root_outcome(), idx.transitions.last()) {
        (Some(_), Some(t)) if end.status(crate::model::Tree::ROOT) == crate::run::Status::Idle => {
            t.tick
        }
        _ => idx.ticks(),
    }
}

/// The foils of a query that names none: every other value, except that a
/// ticked node is contrasted with the other outcomes of being ticked, and
/// a leaf that chose an action with its other actions ("not ticked" and
/// "no action" answer another question: ask executed(NODE) for that).
pub fn default_foils(model: &Model, v: VarId) -> Vec<Val> {
    let factual = model.snap(v, &model.fact[v]);
    let ticked_alt = |x: &Val| match (model.vars[v].kind, x) {
        (VarKind::Status(_), Val::Status(crate::run::Status::Idle)) => {
            factual == Val::Status(crate::run::Status::Idle)
        }
        (VarKind::Decision(_), Val::Action(None)) => factual == Val::Action(None),
        _ => true,
    };
    model.vars[v]
        .range
        .iter()
        .filter(|x| **x != factual && ticked_alt(x))
        .cloned()
        .collect()
}

/// The why-questions that can be asked about a node at a moment: its
/// status, whether it ran, its decision, and the state variables a leaf
/// reads or writes, as (target, question) pairs.
pub fn why_targets(
    session: &Session,
    domain: Option<Arc<Domain>>,
    uid: crate::model::Uid,
    at: Moment,
) -> Result<Vec<(String, String)>, Located> {
    let pos = session
        .index
        .position(at)
        .map_err(|m| Located::file(&session.path, m))?;
    let m = model_at(session, domain, at.tick)?;
    let mut vars = vec![m.r(uid), m.e(uid)];
    vars.extend(m.d(uid));
    let mut targets: Vec<String> = vec![format!("status(#{uid})"), format!("executed(#{uid})")];
    if m.d(uid).is_some() {
        targets.push(format!("decision(#{uid})"));
    }
    if let Some(d) = &m.domain {
        if let Some(l) = d.leaf_for(&m.tree, uid) {
            let mut names: Vec<usize> = d.leaves[l].inputs.clone();
            for o in &d.leaves[l].outputs {
                if !names.contains(o) {
                    names.push(*o);
                }
            }
            for x in names {
                if let Some(c) = m.copy_at(x, pos) {
                    vars.push(c);
                    targets.push(d.vars[x].name.clone());
                }
            }
        }
    }
    Ok(targets
        .into_iter()
        .zip(vars)
        .filter_map(|(t, v)| {
            let foils = default_foils(&m, v);
            (!foils.is_empty()).then(|| {
                let q = Query {
                    targets: vec![v],
                    foils: vec![foils],
                };
                (t, english::question(&m, &q))
            })
        })
        .collect())
}

/// Asks why `target` had its value at `at` (default: the end of the run)
/// and not one of `foils` (default: every other value).
pub fn why(
    session: &Session,
    domain: Option<Arc<Domain>>,
    target: &str,
    foils: &[String],
    at: Option<Moment>,
    max_depth: usize,
) -> Result<Why, Located> {
    let fail = |m: String| Located::file(&session.path, m);
    let (moment, pos) = moment_in_run(session, at).map_err(fail)?;
    let model = model_at(session, domain, moment.tick)?;
    faithful(&model, moment).map_err(fail)?;
    let t = query::parse_target(&model, target).map_err(fail)?;
    let t = match target_at_step(session, &model, t, moment, pos).map_err(fail)? {
        AtStep::Target(t) => t,
        AtStep::Told(told) => return Ok(told_why(session, model, told, moment, max_depth)),
    };
    let v = query::target_var(&model, &t, pos).map_err(fail)?;
    if let Some(e) = another_call(session, &model, v, moment, pos) {
        // The run itself holds the call: its recorded leaf outcomes, run
        // again, answer.
        let told = match model.vars[v].kind {
            VarKind::Status(u) => calls::Told::of(session, model.origin(u), pos),
            _ => None,
        };
        return match told {
            Some(told) => Ok(told_why(session, model, told, moment, max_depth)),
            None => Err(fail(e)),
        };
    }
    if let Some(when) = fact_from(session, &model, v, moment.tick).filter(|&p| p > pos) {
        let then = session.index.moment(when);
        return Err(fail(format!(
            "at {moment}, \"{}\" is not true yet: it becomes true at {then}; ask at {then} or later",
            english::fact(&model, v, &model.fact[v])
        )));
    }
    state_as_recorded(session, &model, &t, v, moment, pos).map_err(fail)?;
    let foil_vals = foil_values(&model, v, foils, moment).map_err(fail)?;
    if foil_vals.is_empty() {
        // A node whose outcome is fixed by its kind (AlwaysFailure): what
        // the run shows of its call is the answer.
        if let VarKind::Status(u) = model.vars[v].kind {
            if let Some(told) = calls::Told::of(session, model.origin(u), pos) {
                return Ok(told_why(session, model, told, moment, max_depth));
            }
        }
        return Err(fail(format!(
            "{} can take no other value: there is nothing to contrast it with",
            model.var_name(v)
        )));
    }
    let query = Query {
        targets: vec![v],
        foils: vec![foil_vals],
    };
    let answer = search(&model, &query, max_depth)?;
    // A state variable is checked where the model's copy is read, or at the
    // tick's end when that is the moment asked about.
    let watch = match (&model.vars[v].kind, moment.step, &t) {
        (_, None, query::Target::State { copy: None, .. }) => None,
        (VarKind::State { var, copy }, ..) => verify::watch_copy(&model, *var, *copy),
        _ => None,
    };
    let mut w = checked(session, model, query, answer, watch, moment.to_string());
    through_what_the_model_holds(session, &mut w, watch);
    if moment.step.is_some() {
        causes_before(session, &mut w, v, moment, pos);
    }
    from_the_run(session, &mut w, v, pos);
    Ok(w)
}

/// The moment asked about (default: the end of the run) and its position,
/// if the run has it.
fn moment_in_run(session: &Session, at: Option<Moment>) -> Result<(Moment, u32), String> {
    if session.index.ticks() == 0 {
        return Err("the session has no ticks".into());
    }
    // Ticks after the root completed are not part of the run, whatever an
    // end record says: nothing is replayed past the root's completion.
    let last = last_tick(session);
    let moment = at.unwrap_or(Moment {
        tick: last,
        step: None,
    });
    if moment.tick > last {
        return Err(format!(
            "tick {} is outside the run: it ended at tick {last}, when its root completed",
            moment.tick
        ));
    }
    let pos = session.index.position(moment)?;
    Ok((moment, pos))
}

/// A model that does not reproduce its tick cannot explain it.
fn faithful(model: &Model, moment: Moment) -> Result<(), String> {
    let Some(first) = model.unfaithful().first().cloned() else {
        return Ok(());
    };
    let hint = if model.domain.is_some() {
        "was the domain file changed since the run?"
    } else {
        "btx's model of a node differs from how it ran: a bug of btx's, please report it with the session"
    };
    Err(format!(
        "the model of tick {} does not reproduce the run, so it cannot explain it: {first} ({hint})",
        moment.tick
    ))
}

/// A target asked about at a step: the node's call at or before it.
enum AtStep {
    Target(query::Target),
    /// A call the model of the tick does not hold: the run's own calls
    /// answer.
    Told(calls::Told),
}

/// At a step, a node's facts are those of its call at or before it.
fn target_at_step(
    session: &Session,
    model: &Model,
    t: query::Target,
    moment: Moment,
    pos: u32,
) -> Result<AtStep, String> {
    let ours = |u: crate::model::Uid| u as usize <= model.session_len();
    Ok(AtStep::Target(match (t, moment.step) {
        (query::Target::Status(u), Some(step)) if ours(u) => match query::call_at(model, u, step) {
            Ok(c) => query::Target::Status(c),
            Err(e) => return calls::Told::of(session, u, pos).map(AtStep::Told).ok_or(e),
        },
        (query::Target::Executed(u), Some(step)) if ours(u) => {
            query::Target::Executed(query::call_at(model, u, step)?)
        }
        (query::Target::Decision(u), Some(step)) if ours(u) => {
            query::Target::Decision(query::call_at(model, u, step)?)
        }
        (t, _) => t,
    }))
}

/// A state variable asked about at the tick's end is the model's last
/// copy of it, which differs from the run's where no leaf read the newer
/// value: said, rather than explained wrong.
fn state_as_recorded(
    session: &Session,
    model: &Model,
    t: &query::Target,
    v: VarId,
    moment: Moment,
    pos: u32,
) -> Result<(), String> {
    let (query::Target::State { var, copy: None }, Some(d)) = (t, &model.domain) else {
        return Ok(());
    };
    let e = crate::run::blackboard::EntryId {
        scope: 0,
        key: d.vars[*var].name.clone(),
    };
    let at = session.index.at(pos);
    if let (Some(rec), Val::Data(m)) = (at.entry(&e), &model.fact[v]) {
        if !model::same_value(rec, m) {
            return Err(format!(
                "at {moment} the run has {} = {}, but the model's copy {} is {} (Love's model makes a new copy of a derived variable only where a leaf reads it); ask about {} at the moment a leaf read it",
                d.vars[*var].name,
                english::value_text(&Val::Data(rec.clone())),
                model.var_name(v),
                english::value_text(&model.fact[v]),
                model.var_name(v),
            ));
        }
    }
    Ok(())
}

/// The foils as values of `v` (default: every value it did not have).
fn foil_values(
    model: &Model,
    v: VarId,
    foils: &[String],
    moment: Moment,
) -> Result<Vec<Val>, String> {
    if foils.is_empty() {
        return Ok(default_foils(model, v));
    }
    let factual = model.snap(v, &model.fact[v]);
    let mut out = Vec::new();
    for f in foils {
        let x = query::parse_value(model, v, f)?;
        if x == factual {
            return Err(format!(
                "{} is {} at {moment}: a foil must be a value it did not have",
                model.var_name(v),
                english::value_text(&model.fact[v])
            ));
        }
        if !out.contains(&x) {
            out.push(x);
        }
    }
    Ok(out)
}

/// What the run itself says of a node's status: where the search found
/// nothing, a leaf decides its own outcome and what the run shows of its
/// call is the answer (without a domain to say what it depends on), and a
/// control node's, the run's calls searched; and a failure's root cause.
fn from_the_run(session: &Session, w: &mut Why, v: VarId, pos: u32) {
    let VarKind::Status(u) = w.model.vars[v].kind else {
        return;
    };
    if w.answer.explanations.is_empty() && w.by_calls.is_none() {
        let leaf = w.model.tree.node(w.model.origin(u)).kind.is_leaf();
        if !leaf || w.model.domain.is_none() {
            w.by_calls = calls::Told::of(session, w.model.origin(u), pos);
        }
    }
    w.root = root_of(session, w.model.origin(u), pos);
}

/// A control node's failure by position `pos` (in its tick), followed
/// down to the leaf it comes from.
fn root_of(session: &Session, u: crate::model::Uid, pos: u32) -> Option<chain::RootCause> {
    let idx = &session.index;
    if session.tree.node(u).kind.is_leaf() {
        return None;
    }
    let tick = idx.transitions.get((pos as usize).checked_sub(1)?)?.tick;
    let start = idx.tick_range(tick).start as u32;
    // Its state at the moment: the last change that was not a reset. Only
    // a failure it is still in is followed down (one it started again
    // after, in the tick, is not what is asked).
    let p = idx.changes_of(u).iter().copied().rev().find(|&q| {
        q <= pos && idx.transitions[q as usize - 1].status != crate::run::Status::Idle
    })?;
    (p > start && idx.transitions[p as usize - 1].status == crate::run::Status::Failure)
        .then(|| chain::RootCause::of(&session.tree, idx, u, p))
        .flatten()
}

/// A why answered from the run's own calls alone.
fn told_why(
    session: &Session,
    model: Model,
    told: calls::Told,
    moment: Moment,
    max_depth: usize,
) -> Why {
    let v = model.r(told.uid);
    let query = Query {
        targets: vec![v],
        foils: vec![default_foils(&model, v)],
    };
    let answer = Answer {
        depth: None,
        max_depth,
        explanations: Vec::new(),
        candidates: 0,
        evaluated: 0,
        stopped: None,
        omitted: 0,
        held: Vec::new(),
        held_tried: false,
        unsearched: 0,
    };
    let mut w = checked(session, model, query, answer, None, moment.to_string());
    w.root = root_of(session, told.uid, told.pos);
    w.by_calls = Some(told);
    w
}

/// A cause comes before its effect: at a step, an explanation resting on
/// a fact the tick made true only after it (the recovery a failure set
/// going) is dropped. Where that leaves nothing about a node's completion,
/// the run's own calls answer.
fn causes_before(session: &Session, w: &mut Why, v: VarId, moment: Moment, pos: u32) {
    let m = &w.model;
    let VarKind::Status(target) = m.vars[v].kind else {
        return;
    };
    let target = m.origin(target);
    // A status another node reached after the moment, not on the path
    // above the target (a log may write a parent's change after its
    // child's, as btcm's does).
    let after = |x: VarId| match m.vars[x].kind {
        VarKind::Status(u) => {
            let u = m.origin(u);
            !m.tree.is_ancestor(u, target)
                && u != target
                && fact_from(session, m, x, moment.tick).is_some_and(|q| q > pos)
        }
        _ => false,
    };
    let later: Vec<bool> = w
        .answer
        .explanations
        .iter()
        .map(|e| e.vars.iter().any(|&x| after(x)))
        .collect();
    if !later.contains(&true) {
        return;
    }
    let mut keep = later.iter().map(|l| !l);
    w.answer
        .explanations
        .retain(|_| keep.next().unwrap_or(true));
    if w.checks.len() == later.len() {
        let mut keep = later.iter().map(|l| !l);
        w.checks.retain(|_| keep.next().unwrap_or(true));
    }
    if w.answer.explanations.is_empty() {
        w.by_calls = calls::Told::of(session, target, pos);
    }
}

/// The most changes tried by running the tree again through what the
/// model holds as recorded, and the most ticks replayed for them in all.
const HELD_RERUNS_MAX: usize = 64;
const HELD_RERUN_TICKS_MAX: usize = 200_000;

/// Love's search covers the changes the model follows; a node the model
/// holds as recorded is not followed: one that decides by the blackboard
/// (a pre-condition script, a Switch, a BlackboardCheck, …), whose input a
/// leaf's writes may set, or a control node it does not follow in this
/// tick (a Nav2 RecoveryNode going back to its first child). Where such a
/// node ran and the search found nothing, or nothing about a leaf (only
/// that a parent ran), each leaf's other outcomes are tried by running the
/// tree again: one that gives a foil is an explanation, confirmed by the
/// re-run itself. Where nothing can be run again, "No explanation" says
/// what was not searched.
fn through_what_the_model_holds(session: &Session, w: &mut Why, watch: Option<usize>) {
    let m = &w.model;
    if w.answer.stopped.is_some() {
        return;
    }
    let held: Vec<crate::model::Uid> = (1..=m.session_len() as crate::model::Uid)
        .filter(|&u| m.facts.ticked[u as usize - 1] && m.may_be_opaque(u))
        .collect();
    let none = w.answer.explanations.is_empty();
    let about_a_leaf = |e: &Explanation| {
        e.vars.iter().all(|&v| match m.vars[v].kind {
            VarKind::Status(u) => m.tree.node(m.origin(u)).kind.is_leaf(),
            VarKind::Executed(_) | VarKind::Attempts(_) => false,
            _ => true,
        })
    };
    if held.is_empty() || w.answer.explanations.iter().any(about_a_leaf) {
        return;
    }
    let t = w.query.targets[0];
    let changes: Vec<(VarId, Val)> = (1..=m.session_len() as crate::model::Uid)
        .filter(|&u| m.tree.node(u).kind.is_leaf() && m.facts.ticked[u as usize - 1])
        .map(|u| m.r(u))
        .filter(|&v| v != t)
        .flat_map(|v| {
            m.vars[v]
                .range
                .iter()
                .filter(|x| **x != m.fact[v] && **x != Val::Status(crate::run::Status::Idle))
                .map(move |x| (v, x.clone()))
                .collect::<Vec<_>>()
        })
        .collect();
    let affordable = changes.len() <= HELD_RERUNS_MAX
        && changes.len() * m.facts.tick as usize <= HELD_RERUN_TICKS_MAX;
    let rerunner = match verify::Rerunner::new(session, m.facts.tick) {
        Ok(r) if affordable => r,
        _ => {
            if none {
                w.answer.held = held;
            }
            return;
        }
    };
    let found = rerun_changes(&rerunner, m, &w.query, changes, watch);
    if found.is_empty() {
        w.call_changes = rerun_calls(&rerunner, m, &w.query, watch);
    }
    if found.is_empty() && w.call_changes.is_empty() {
        // Every leaf's other outcomes were run: nothing at depth 1 gives a
        // foil through them either; deeper was not tried.
        if none && w.answer.max_depth > 1 {
            w.answer.held = held;
            w.answer.held_tried = true;
        }
        return;
    }
    // They are of size 1: smaller than what the model found, if larger.
    if w.answer.depth.is_some_and(|d| d > 1) {
        w.answer.explanations.clear();
        w.checks.clear();
    }
    for e in found {
        w.checks.push(verify::Check::Confirmed {
            checked: e.values.len(),
            of: e.values.len(),
        });
        w.answer.explanations.push(e);
    }
    w.answer.depth = Some(1);
    relevance::order(&w.model, &w.query, &mut w.answer, &mut w.checks);
}

/// Each plain leaf's other outcome (success for a failure, and the other
/// way round) at each of its calls in the tick that the model's variables
/// do not stand for, run again: those that give a foil.
fn rerun_calls(
    rerunner: &verify::Rerunner,
    m: &Model,
    query: &Query,
    watch: Option<usize>,
) -> Vec<CallChange> {
    use crate::run::Status;
    let t = query.targets[0];
    let tick = m.facts.tick;
    let mut out = Vec::new();
    let calls: Vec<_> = m
        .facts
        .call_log
        .iter()
        .filter(|r| {
            r.uid as usize <= m.session_len()
                && m.tree.node(r.uid).kind.is_leaf()
                && m.tree.node(r.uid).builtin.is_none()
                && matches!(r.returned, Status::Success | Status::Failure)
                // The model's variable stands for this call only if the
                // model has the leaf ticked in the tick.
                && !(rerunner.modelled_call(m, r.uid, r.call) && m.facts.ticked[r.uid as usize - 1])
        })
        .take(HELD_RERUNS_MAX)
        .collect();
    if calls.len() * tick as usize > HELD_RERUN_TICKS_MAX {
        return out;
    }
    for r in calls {
        let to = if r.returned == Status::Success {
            Status::Failure
        } else {
            Status::Success
        };
        let forced = crate::run::Forced {
            tick,
            uid: r.uid,
            call: r.call,
            status: to,
        };
        let Ok(got) = rerunner.outcome_forced(m, forced, t, watch) else {
            continue;
        };
        let got = m.snap(t, &got);
        if !query.foils[0].contains(&got) {
            continue;
        }
        // The step at which that call's outcome was recorded: the tick's
        // transitions when the call ended.
        let step = Some(r.transitions_after);
        out.push(CallChange {
            uid: r.uid,
            call: r.call,
            at: Moment { tick, step },
            was: r.returned,
            to,
            outcome: got,
        });
    }
    out
}

/// The changes that give a foil when the tick is run again with them, as
/// explanations (one per variable and outcome).
fn rerun_changes(
    rerunner: &verify::Rerunner,
    m: &Model,
    query: &Query,
    changes: Vec<(VarId, Val)>,
    watch: Option<usize>,
) -> Vec<Explanation> {
    let t = query.targets[0];
    let mut found: Vec<Explanation> = Vec::new();
    for (v, x) in changes {
        let Ok(got) = rerunner.outcome(m, &[(v, x.clone())], t, watch) else {
            continue;
        };
        let got = m.snap(t, &got);
        if !query.foils[0].contains(&got) {
            continue;
        }
        match found
            .iter_mut()
            .find(|e| e.vars == [v] && e.outcome == [got.clone()])
        {
            Some(e) => e.values.push(vec![x]),
            None => found.push(Explanation {
                vars: vec![v],
                values: vec![vec![x]],
                outcome: vec![got],
                next: None,
            }),
        }
    }
    found
}

/// The search's answer checked by re-running (`verified`) and put in
/// order, the cause first (`relevance`).
fn checked(
    session: &Session,
    model: Model,
    query: Query,
    answer: Answer,
    watch: Option<usize>,
    moment: String,
) -> Why {
    let (mut answer, mut checks, dropped) = verified(session, &model, &query, answer, watch);
    relevance::order(&model, &query, &mut answer, &mut checks);
    Why {
        model,
        query,
        answer,
        moment,
        checks,
        dropped,
        shown: None,
        call_changes: Vec::new(),
        by_calls: None,
        root: None,
        full: false,
    }
}
