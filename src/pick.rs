//! Picking a node: `#uid`, a description or ID, or a path of descriptions
//! from the root (`go insert large gear/detect chuck/lift torso`).

use crate::model::{Tree, Uid};

/// Why a pick did not resolve to one node.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum PickError {
    #[error("no node matches \"{query}\"{}", list(.candidates, "closest"))]
    Unknown {
        query: String,
        candidates: Vec<Candidate>,
    },
    #[error("there is no node #{uid}: the tree's uids are 1 to {len}")]
    NoUid { uid: Uid, len: usize },
    #[error("\"{query}\" matches {} nodes{}", .candidates.len(), list(.candidates, "pick one with its path or #uid"))]
    Ambiguous {
        query: String,
        candidates: Vec<Candidate>,
    },
}

/// A node offered in an error: its uid and a path that picks it.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct Candidate {
    pub uid: Uid,
    pub path: String,
}

fn list(c: &[Candidate], what: &str) -> String {
    if c.is_empty() {
        return String::new();
    }
    let mut s = format!("; {what}:");
    for x in c {
        s.push_str(&format!("\n  #{}  {}", x.uid, x.path));
    }
    s
}

/// How strictly a segment must match: the description first, then the name
/// or ID; exact case first, then any case.
#[derive(Clone, Copy)]
struct Tier {
    by_id: bool,
    fold: bool,
}

const TIERS: [Tier; 4] = [
    Tier {
        by_id: false,
        fold: false,
    },
    Tier {
        by_id: true,
        fold: false,
    },
    Tier {
        by_id: false,
        fold: true,
    },
    Tier {
        by_id: true,
        fold: true,
    },
];

fn matches(tree: &Tree, uid: Uid, segment: &str, tier: Tier) -> bool {
    let n = tree.node(uid);
    let eq = |a: &str| {
        if tier.fold {
            a.to_lowercase() == segment.to_lowercase()
        } else {
            a == segment
        }
    };
    eq(tree.description(uid)) || (tier.by_id && (eq(&n.id) || eq(&n.name)))
}

/// Resolves a pick to one node.
///
/// Segments of a path match, in order, any subsequence of the node's
/// ancestors (so unnamed nodes and repeated names need not be written), and
/// the last segment matches the node itself: by description, else by name or
/// ID; in exact case, else in any case. When every match lies on one
/// line of descent (a same-named SubTree, Fallback and Sequence), the
/// outermost is meant; otherwise a path written out in full (from the root
/// or any named ancestor) means the node it spells.
pub fn pick(tree: &Tree, query: &str) -> Result<Uid, PickError> {
    pick_among(tree, query).map(|(u, _)| u)
}

/// `pick`, and the other nodes the query matched when it resolved among
/// several (the outermost of nested same-named nodes): an answer about the
/// node chosen should say which it is.
pub fn pick_among(tree: &Tree, query: &str) -> Result<(Uid, Vec<Uid>), PickError> {
    let q = query.trim();
    if let Some(num) = q.strip_prefix('#') {
        if let Ok(uid) = num.trim().parse::<Uid>() {
            if tree.get(uid).is_some() {
                return Ok((uid, Vec::new()));
            }
            // A uid is exact: nodes "close" to it mean nothing.
            return Err(PickError::NoUid {
                uid,
                len: tree.len(),
            });
        }
        return Err(PickError::Unknown {
            query: q.to_string(),
            candidates: closest(tree, q),
        });
    }
    let segments: Vec<&str> = q
        .split('/')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .collect();
    if segments.is_empty() {
        return Err(PickError::Unknown {
            query: q.to_string(),
            candidates: closest(tree, q),
        });
    }
    for tier in TIERS {
        let found = find(tree, &segments, tier);
        if found.is_empty() {
            continue;
        }
        let outermost = found
            .iter()
            .copied()
            .find(|&a| found.iter().all(|&b| a == b || tree.is_ancestor(a, b)));
        // A path written out in full means the node whose path it is, not
        // one further down that merely contains its segments.
        let joined = segments.join("/");
        let suffix = format!("/{joined}");
        let mut spelled = found.iter().copied().filter(|&u| {
            let p = tree.display_path(u);
            p == joined || p.ends_with(&suffix)
        });
        let spelled_one = match (spelled.next(), spelled.next()) {
            (Some(u), None) if segments.len() > 1 => Some(u),
            _ => None,
        };
        return match outermost.or(spelled_one) {
            Some(uid) => Ok((uid, found.iter().copied().filter(|&u| u != uid).collect())),
            None => Err(PickError::Ambiguous {
                query: q.to_string(),
                candidates: found.iter().map(|&u| candidate(tree, u)).collect(),
            }),
        };
    }
    Err(PickError::Unknown {
        query: q.to_string(),
        candidates: closest(tree, q),
    })
}

fn find(tree: &Tree, segments: &[&str], tier: Tier) -> Vec<Uid> {
    let (last, rest) = segments.split_last().expect("non-empty");
    (1..=tree.len() as Uid)
        .filter(|&u| matches(tree, u, last, tier))
        .filter(|&u| {
            // Greedy from the nearest ancestor up finds a subsequence if one exists.
            let mut want = rest.iter().rev().peekable();
            for a in tree.ancestors(u) {
                match want.peek() {
                    // Ancestors may be named by ID too (a SubTree's).
                    Some(s)
                        if matches(
                            tree,
                            a,
                            s,
                            Tier {
                                by_id: true,
                                ..tier
                            },
                        ) =>
                    {
                        want.next();
                    }
                    Some(_) => {}
                    None => break,
                }
            }
            want.peek().is_none()
        })
        .collect()
}

fn candidate(tree: &Tree, uid: Uid) -> Candidate {
    Candidate {
        uid,
        path: tree.display_path(uid),
    }
}

fn closest(tree: &Tree, query: &str) -> Vec<Candidate> {
    let q = query.trim_start_matches('#');
    let last = q.rsplit('/').next().unwrap_or(q);
    let items: Vec<(String, Uid)> = (1..=tree.len() as Uid)
        .map(|u| {
            (
                if q.contains('/') {
                    tree.display_path(u)
                } else {
                    tree.description(u).to_string()
                },
                u,
            )
        })
        .collect();
    let query = if q.contains('/') { q } else { last };
    crate::rank::rank(query, &items, 5)
        .into_iter()
        .map(|u| candidate(tree, u))
        .collect()
}
