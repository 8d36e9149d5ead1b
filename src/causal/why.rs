//! A "why?" answered: the search's answer checked by re-running the tree
//! (`verified`), put in order, the cause first, and told in English.

use super::*;
use crate::session::{Moment, Session};

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
pub(super) fn verified(
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
pub(super) fn by_consequent(
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
pub(super) fn checked_each(
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
pub(super) fn same_in_tick(model: &Model, query: &Query, vals: &[Val]) -> bool {
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

    pub(super) fn body(&self) -> String {
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

    pub(super) fn model_text(&self) -> String {
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

/// The search's answer checked by re-running (`verified`) and put in
/// order, the cause first (`relevance`).
pub(super) fn checked(
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
