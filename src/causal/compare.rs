//! Where two runs of one tree part ways, and the question that asks why:
//! the first differing node update (which node, then its status, then its
//! decision), asked about in the second run with the first run's value as
//! the foil.

use super::model::{Model, Val, VarId};
use crate::model::Uid;
use crate::run::Status;
use crate::session::{Moment, Session};

#[derive(Debug, Clone, PartialEq)]
pub enum Divergence {
    /// Both runs updated `uid`, to different statuses.
    Status {
        uid: Uid,
        first: Status,
        second: Status,
    },
    /// Same status, different decisions.
    Decision {
        uid: Uid,
        first: Option<String>,
        second: Option<String>,
    },
    /// The runs updated different nodes.
    Node { first: Uid, second: Uid },
    /// One run ended where the other went on.
    Length,
}

/// The first difference, at transition `index` (0-based) of both runs.
#[derive(Debug, Clone, PartialEq)]
pub struct Difference {
    pub index: usize,
    /// The moment of that transition in the second run (or its end).
    pub moment: Moment,
    pub what: Divergence,
}

/// The first transition at which the runs differ, if any.
pub fn first_difference(a: &Session, b: &Session) -> Option<Difference> {
    let (ta, tb) = (&a.index.transitions, &b.index.transitions);
    let moment_b = |i: usize| b.index.moment((i as u32 + 1).min(tb.len() as u32));
    for i in 0..ta.len().min(tb.len()) {
        let (x, y) = (&ta[i], &tb[i]);
        let what = if x.uid != y.uid {
            Divergence::Node {
                first: x.uid,
                second: y.uid,
            }
        } else if x.status != y.status {
            Divergence::Status {
                uid: x.uid,
                first: x.status,
                second: y.status,
            }
        } else {
            let (da, db) = (
                a.index.transition_decision(i),
                b.index.transition_decision(i),
            );
            if da == db {
                continue;
            }
            Divergence::Decision {
                uid: x.uid,
                first: da.map(str::to_string),
                second: db.map(str::to_string),
            }
        };
        return Some(Difference {
            index: i,
            moment: moment_b(i),
            what,
        });
    }
    (ta.len() != tb.len()).then(|| Difference {
        index: ta.len().min(tb.len()),
        moment: moment_b(ta.len().min(tb.len())),
        what: Divergence::Length,
    })
}

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

impl Difference {
    /// Where the runs part ways, in words; `a` and `b` name the runs.
    pub fn text(&self, tree: &crate::Tree, a: &str, b: &str) -> String {
        let node = |u: Uid| format!("{} (#{u})", tree.description(u));
        let at = format!("at transition {} (moment {})", self.index + 1, self.moment);
        match &self.what {
            Divergence::Status { uid, first, second } => format!(
                "{at}, {} became {} in {b} and {} in {a}",
                node(*uid),
                second.as_str(),
                first.as_str()
            ),
            Divergence::Decision { uid, first, second } => format!(
                "{at}, {} chose {} in {b} and {} in {a}",
                node(*uid),
                second.as_deref().unwrap_or("nothing"),
                first.as_deref().unwrap_or("nothing")
            ),
            Divergence::Node { first, second } => format!(
                "{at}, {b} updated {} where {a} updated {}",
                node(*second),
                node(*first)
            ),
            Divergence::Length => format!("{at}, one run ended and the other went on"),
        }
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
        let mut out = format!(
            "The runs part ways {}.\n",
            self.difference.text(tree, "A", "B")
        );
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
