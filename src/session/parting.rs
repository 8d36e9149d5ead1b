//! Where two runs part ways: the first transition of one with no
//! counterpart in the other. `btx diff`, its `--why` and `open --diff` all
//! start from it, so that they name the same place.

use super::{Moment, Session};
use crate::model::{Tree, Uid};
use crate::run::Status;

#[derive(Debug, Clone, PartialEq)]
pub enum Divergence {
    /// Both runs updated `uid` (B's), to different statuses.
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
    /// The runs updated different nodes: `first` is A's, `second` B's.
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

/// The first transition at which the runs differ, if any: the first
/// transition of A with no counterpart in B. Nodes pair by uid when the
/// trees have the same shape, else by path.
pub fn first_difference(a: &Session, b: &Session) -> Option<Difference> {
    let (ta, tb) = (&a.index.transitions, &b.index.transitions);
    let moment_b = |i: usize| b.index.moment((i as u32 + 1).min(tb.len() as u32));
    let by_uid = crate::model::same_shape(&a.tree, &b.tree);
    let paired = |x: Uid, y: Uid| {
        if by_uid {
            x == y
        } else {
            a.tree.get(x).is_some()
                && b.tree.get(y).is_some()
                && a.tree.full_path(x) == b.tree.full_path(y)
        }
    };
    for i in 0..ta.len().min(tb.len()) {
        let (x, y) = (&ta[i], &tb[i]);
        let what = if !paired(x.uid, y.uid) {
            Divergence::Node {
                first: x.uid,
                second: y.uid,
            }
        } else if x.status != y.status {
            Divergence::Status {
                uid: y.uid,
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
                uid: y.uid,
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

impl Difference {
    /// Where the runs part ways, in words; `a` and `b` name the runs,
    /// which ran `a_tree` and `b_tree`.
    pub fn text(&self, a_tree: &Tree, b_tree: &Tree, a: &str, b: &str) -> String {
        let named = |tree: &Tree, u: Uid| format!("{} (#{u})", tree.description(u));
        let node = |u: Uid| named(b_tree, u);
        let at = format!("at transition {} (moment {}):", self.index + 1, self.moment);
        match &self.what {
            Divergence::Status { uid, first, second } => format!(
                "{at} {} became {} in {b} and {} in {a}",
                node(*uid),
                second.as_str(),
                first.as_str()
            ),
            Divergence::Decision { uid, first, second } => format!(
                "{at} {} chose {} in {b} and {} in {a}",
                node(*uid),
                second.as_deref().unwrap_or("nothing"),
                first.as_deref().unwrap_or("nothing")
            ),
            Divergence::Node { first, second } => format!(
                "{at} {b} updated {} where {a} updated {}",
                node(*second),
                named(a_tree, *first)
            ),
            Divergence::Length => format!("{at} one run ended and the other went on"),
        }
    }
}
