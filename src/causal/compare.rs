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
