//! Why two runs of one tree part ways: the first differing node update
//! (`session::parting`), asked about in the second run with the first run's
//! value as the foil.

use super::model::{Model, Val, VarId};
use crate::run::Status;
pub use crate::session::parting::{first_difference, Difference, Divergence};
use crate::session::Session;

/// The contrastive query about a difference, in the second run's model of
/// that tick: the target variable and the foil (the first run's value).
pub fn difference_query(m: &Model, d: &Difference) -> Option<(VarId, Vec<Val>)> {
    match &d.what {
        Divergence::Status { uid, first, .. } => {
            let foil = if *first == Status::Idle {
                Status::Idle
            } else {
                *first
            };
            Some((m.r(*uid), vec![Val::Status(foil)]))
        }
        Divergence::Decision { uid, first, .. } => {
            let v = m.d(*uid)?;
            let foil = match first.as_deref() {
                None | Some("null") => Val::Action(None),
                Some(a) => Val::Action(Some(a.to_string())),
            };
            Some((v, vec![foil]))
        }
        Divergence::Node { first, .. } => {
            // The first run updated a node the second did not update here:
            // ask why it ran (or not) in the second run.
            let e = m.e(*first);
            let other = Val::Bool(!matches!(m.fact[e], Val::Bool(true)));
            Some((e, vec![other]))
        }
        Divergence::Length => None,
    }
}

/// Two runs' first divergence, and why the second run went its own way.
pub struct Diverged {
    pub difference: Difference,
    /// The contrastive question in the second run (none when one run only
    /// ended earlier: there is no value to contrast).
    pub why: Option<super::Why>,
}

impl Diverged {
    /// What two runs agreeing is said as.
    pub const SAME: &'static str = "The runs make the same transitions: they do not diverge.";

    /// Where the runs part ways, then the answer to why (after `lead`), in
    /// the second run's tree; the runs are A and B.
    pub fn text(&self, tree: &crate::Tree, lead: &str) -> String {
        format!(
            "The runs part ways {}.\n{}",
            self.difference.text(tree, tree, "A", "B"),
            self.why_text(lead)
        )
    }

    /// The answer to why alone (after `lead`), for a report that said
    /// where the runs part ways already.
    pub fn why_text(&self, lead: &str) -> String {
        let mut out = String::new();
        match &self.why {
            Some(w) => {
                out.push_str(lead);
                out.push_str(&w.text());
            }
            None => out.push_str("There is no value in B to contrast with A's.\n"),
        }
        out
    }
}

/// Finds where run `b` first diverges from run `a` and asks, in `b`'s model
/// of that tick, why it did not do what `a` did. `None`: the runs agree.
pub fn why_diverged(
    a: &Session,
    b: &Session,
    domain: Option<std::sync::Arc<crate::run::domain::Domain>>,
    max_depth: usize,
) -> Result<Option<Diverged>, crate::Located> {
    let Some(difference) = first_difference(a, b) else {
        return Ok(None);
    };
    let model = super::model_at(b, domain, difference.moment.tick)?;
    let why = match difference_query(&model, &difference) {
        Some((target, foils)) => {
            let query = super::Query {
                targets: vec![target],
                foils: vec![foils],
            };
            let answer = super::search(&model, &query, max_depth)?;
            let watch = match model.vars[target].kind {
                super::VarKind::State { var, copy } => super::verify::watch_copy(&model, var, copy),
                _ => None,
            };
            Some(super::checked(
                b,
                model,
                query,
                answer,
                watch,
                difference.moment.to_string(),
            ))
        }
        None => None,
    };
    Ok(Some(Diverged { difference, why }))
}
