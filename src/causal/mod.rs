//! Counterfactual explanations (Love et al.): the explanation model of a
//! tick, the counterfactual search, and answers in plain English.
//!
//! The model is built per tick from a session: the tree, the domain the run
//! used (or one given), and the facts of the tick replayed through the
//! executor. Without a domain the model has the tree's structure only and
//! leaf outcomes are exogenous, so structural questions ("why did ask not
//! run?") still get answers.

pub mod compare;
pub mod english;
pub mod eval;
pub mod facts;
pub mod graph;
pub mod model;
pub mod query;
pub mod search;

pub use facts::TickFacts;
pub use model::{Model, Val, VarId, VarKind};
pub use search::{search, Answer, Explanation, Query};

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

/// A "why?" question asked and answered.
pub struct Why {
    pub model: Model,
    pub query: Query,
    pub answer: Answer,
    /// The moment asked about, as written back (`TICK` or `TICK:STEP`).
    pub moment: String,
}

impl Why {
    /// The explanations as they read: merged copies, in order.
    pub fn groups(&self) -> Vec<Vec<usize>> {
        english::merge(&self.model, &self.answer)
    }

    pub fn sentences(&self) -> Vec<String> {
        self.groups()
            .iter()
            .map(|g| english::sentence(&self.model, &self.query, &self.answer.explanations[g[0]]))
            .collect()
    }

    /// The tree nodes a merged explanation's reasons are about.
    pub fn reason_nodes(&self, group: usize) -> Vec<crate::model::Uid> {
        let mut out = Vec::new();
        for g in self.groups().get(group).into_iter().flatten() {
            for &v in &self.answer.explanations[*g].vars {
                if let VarKind::Executed(u) | VarKind::Status(u) | VarKind::Decision(u) =
                    self.model.vars[v].kind
                {
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
        })
    }

    /// The target and its ancestors in layers by distance (0: the target),
    /// each as (name, value, is a reason of `group`).
    pub fn layers(&self, group: usize) -> Vec<Vec<(String, String, bool)>> {
        let m = &self.model;
        let dist = m.distances_to(&self.query.targets);
        let reasons: Vec<VarId> = self
            .groups()
            .get(group)
            .into_iter()
            .flatten()
            .flat_map(|&i| self.answer.explanations[i].vars.clone())
            .collect();
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

    pub fn text(&self) -> String {
        english::to_text(&self.model, &self.query, &self.answer, &self.moment)
    }

    pub fn json(&self) -> serde_json::Value {
        english::to_json(&self.model, &self.query, &self.answer, &self.moment)
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
    let ticks = session.index.ticks();
    if ticks == 0 {
        return Err(fail("the session has no ticks".into()));
    }
    let moment = at.unwrap_or(Moment {
        tick: ticks,
        step: None,
    });
    let pos = session.index.position(moment).map_err(fail)?;
    let model = model_at(session, domain, moment.tick)?;
    let t = query::parse_target(&model, target).map_err(fail)?;
    let v = query::target_var(&model, &t, pos).map_err(fail)?;
    let factual = model.snap(v, &model.fact[v]);
    let foil_vals: Vec<Val> = if foils.is_empty() {
        default_foils(&model, v)
    } else {
        let mut out = Vec::new();
        for f in foils {
            let x = query::parse_value(&model, v, f).map_err(fail)?;
            if x == factual {
                return Err(fail(format!(
                    "{} is {} at {moment}: a foil must be a value it did not have",
                    model.var_name(v),
                    english::value_text(&model.fact[v])
                )));
            }
            if !out.contains(&x) {
                out.push(x);
            }
        }
        out
    };
    if foil_vals.is_empty() {
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
    Ok(Why {
        model,
        query,
        answer,
        moment: moment.to_string(),
    })
}
