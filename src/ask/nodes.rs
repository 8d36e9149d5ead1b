//! A phrase → the node it names: a pick as everywhere (`#uid`, a
//! description or ID, a path), then the name as words ("follow path" for
//! `FollowPath`), then every word of the phrase in the name. Several
//! matches are not guessed between, unless only one had run by then.

use super::parse::Subject;
use crate::model::{Tree, Uid};
use crate::session::At;

/// Why a phrase named no single node.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Unresolved {
    /// Nothing matched; the closest names, best first.
    Unknown(Vec<Uid>),
    /// Several matched, and more than one had run (or none had).
    Several(Vec<Uid>),
}

/// The node a subject names, at a moment of a run if there is one.
pub fn resolve(tree: &Tree, who: &Subject, run: Option<&At>) -> Result<Uid, Unresolved> {
    let phrase = match who {
        Subject::Task | Subject::It => return Ok(tree.root().uid),
        Subject::Named(p) => trimmed(p),
        Subject::Nodes(us, _) => {
            return choose(tree, us.clone(), run).unwrap_or(Err(Unresolved::Unknown(Vec::new())))
        }
    };
    if let Ok(uid) = crate::pick::pick(tree, &phrase) {
        return Ok(uid);
    }
    let as_words = |uid: Uid| tree.words_of(uid).to_lowercase();
    let exact: Vec<Uid> = tree
        .preorder()
        .into_iter()
        .filter(|&u| as_words(u) == phrase || tree.node(u).id.to_lowercase() == phrase)
        .collect();
    let found = if exact.is_empty() {
        let wanted: Vec<&str> = phrase.split_whitespace().collect();
        tree.preorder()
            .into_iter()
            .filter(|&u| {
                let name = as_words(u);
                let words: Vec<&str> = name.split_whitespace().collect();
                !wanted.is_empty() && wanted.iter().all(|w| words.contains(w))
            })
            .collect()
    } else {
        exact
    };
    choose(tree, found, run).ok_or_else(|| {
        let items: Vec<(String, Uid)> = tree
            .preorder()
            .into_iter()
            .map(|u| (tree.words_of(u), u))
            .collect();
        Unresolved::Unknown(crate::rank::rank(&phrase, &items, 3))
    })?
}

/// One of several matches: the outermost when they lie on one line of
/// descent (a SubTree and the Sequence inside it named alike), else the
/// only one that had run by the moment.
fn choose(tree: &Tree, found: Vec<Uid>, run: Option<&At>) -> Option<Result<Uid, Unresolved>> {
    if found.is_empty() {
        return None;
    }
    let found = super::read::mentions::outermost(tree, found);
    if found.len() == 1 {
        return Some(Ok(found[0]));
    }
    if let Some(at) = run {
        let ran: Vec<Uid> = found
            .iter()
            .copied()
            .filter(|&u| at.index.changes_of(u).first().is_some_and(|&p| p <= at.pos))
            .collect();
        if ran.len() == 1 {
            return Some(Ok(ran[0]));
        }
    }
    Some(Err(Unresolved::Several(found)))
}

/// The phrase without quotes, articles and a trailing kind of node.
fn trimmed(p: &str) -> String {
    let mut s = p.trim().trim_matches(['\'', '"', '`']).trim().to_string();
    for a in ["the ", "a ", "an ", "node ", "step "] {
        if let Some(rest) = s.strip_prefix(a) {
            s = rest.to_string();
        }
    }
    for k in [
        " node",
        " action",
        " step",
        " condition",
        " subtree",
        " leaf",
    ] {
        if let Some(rest) = s.strip_suffix(k) {
            s = rest.to_string();
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::xml::{load_str, LoadOptions};

    fn tree() -> Tree {
        load_str(
            std::path::Path::new("t.xml"),
            r#"<root BTCPP_format="4"><BehaviorTree ID="Main">
                 <Sequence name="go home">
                   <FollowPath/>
                   <Action ID="LookAt" name="look at chuck"/>
                   <Action ID="Detect" name="detect chuck"/>
                 </Sequence>
               </BehaviorTree></root>"#,
            &LoadOptions::default(),
        )
        .unwrap()
        .tree
    }

    #[test]
    fn names_are_found_as_written_as_words_and_by_their_words() {
        let t = tree();
        let named = |s: &str| resolve(&t, &Subject::Named(s.into()), None);
        assert_eq!(named("the look at chuck"), Ok(3));
        assert_eq!(named("follow path"), Ok(2));
        assert_eq!(named("FollowPath action"), Ok(2));
        assert_eq!(named("#4"), Ok(4));
        assert_eq!(named("chuck"), Err(Unresolved::Several(vec![3, 4])));
        assert!(matches!(named("fly"), Err(Unresolved::Unknown(_))));
        assert_eq!(resolve(&t, &Subject::Task, None), Ok(1));
    }
}
