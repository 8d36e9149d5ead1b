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
    pub fn text(&self) -> String {
        english::to_text(&self.model, &self.query, &self.answer, &self.moment)
    }

    pub fn json(&self) -> serde_json::Value {
        english::to_json(&self.model, &self.query, &self.answer, &self.moment)
    }
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
    // By default a ticked node is contrasted with the other outcomes of
    // being ticked, and a leaf that decided with its other actions: "not
    // ticked" and "no action" answer a different question (ask
    // executed(NODE) for that).
    let ticked_alt = |x: &Val| match (model.vars[v].kind, x) {
        (VarKind::Status(_), Val::Status(crate::run::Status::Idle)) => {
            factual == Val::Status(crate::run::Status::Idle)
        }
        (VarKind::Decision(_), Val::Action(None)) => factual == Val::Action(None),
        _ => true,
    };
    let foil_vals: Vec<Val> = if foils.is_empty() {
        model.vars[v]
            .range
            .iter()
            .filter(|x| **x != factual && ticked_alt(x))
            .cloned()
            .collect()
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
