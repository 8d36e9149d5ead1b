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

mod asked;
mod rerun;
mod why;

pub use asked::*;
pub use why::*;

pub use facts::TickFacts;
pub use model::{Model, Val, VarId, VarKind};
pub use search::{search, Answer, Explanation, Next, Query};

use crate::run::domain::Domain;
use crate::session::Session;
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
