//! Completions of a question being typed (the explorer's prompt): after a
//! lead that names a node ("why did …", "when did …", "can you …"), the
//! tree's names that match what is typed so far, in whole questions; else
//! the questions btx can answer that come closest.

use crate::model::{Tree, Uid};

/// Leads that a node's name follows, and how the question ends.
const LEADS: &[(&str, &str)] = &[
    ("why did ", " fail?"),
    ("why didn't ", " run?"),
    ("why was ", " skipped?"),
    ("when did ", " fail?"),
    ("how often did ", " fail?"),
    ("how many times did ", " fail?"),
    ("what if ", " fails?"),
    ("can you ", "?"),
    ("could you ", "?"),
];

/// Up to `limit` whole questions that complete `typed`, best first; what
/// was typed comes first when btx already reads it as a question and no
/// name completes it.
pub fn complete(tree: &Tree, typed: &str, limit: usize) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    let lower = typed.to_lowercase();
    let lead = LEADS.iter().find(|(l, _)| lower.starts_with(l));
    let reads = super::read::read(&super::read::Vocabulary::new(tree), tree, typed).is_some();
    // Past a lead, a name is being typed: the names complete it.
    if lead.is_none() && reads {
        out.push(typed.trim().to_string());
    }
    let candidates: Vec<String> = match lead {
        Some((l, end)) => {
            let partial = typed[l.len()..].trim_end_matches('?').trim();
            names(tree)
                .into_iter()
                .filter(|n| fuzzy(n, partial))
                .map(|n| format!("{}{n}{end}", &typed[..l.len()]))
                .collect()
        }
        None => general(tree),
    };
    // Past a lead with the verb typed too ("why did look at chuck fail"),
    // no name completes it: it is a question as it is.
    if lead.is_some() && reads && candidates.is_empty() {
        out.push(typed.trim().to_string());
    }
    let keyed: Vec<(String, String)> = candidates.iter().map(|c| (c.clone(), c.clone())).collect();
    for c in crate::rank::rank(typed, &keyed, limit + 1) {
        if !out.contains(&c) {
            out.push(c);
        }
    }
    out.truncate(limit);
    out
}

/// Whether `name` holds the letters of `partial` in order (the finder's
/// matching); an empty partial matches every name.
fn fuzzy(name: &str, partial: &str) -> bool {
    let matcher = fuzzy_matcher::skim::SkimMatcherV2::default().ignore_case();
    partial.is_empty()
        || fuzzy_matcher::FuzzyMatcher::fuzzy_match(&matcher, name, partial).is_some()
}

/// The names people ask about: every named node and every leaf, as words,
/// once each.
fn names(tree: &Tree) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for u in tree.preorder() {
        if tree.has_name(u) || tree.node(u).kind.is_leaf() {
            let n = tree.words_of(u);
            if !out.contains(&n) {
                out.push(n);
            }
        }
    }
    out
}

fn general(tree: &Tree) -> Vec<String> {
    let mut qs: Vec<String> = crate::explain::Question::fixed()
        .iter()
        .map(|q| q.wording())
        .collect();
    qs.extend(
        [
            "Why did the task fail?",
            "Did the recovery work?",
            "What will you do next?",
            "What happened at tick 1?",
        ]
        .map(String::from),
    );
    let root: Uid = tree.root().uid;
    qs.push(format!("How do you {}?", tree.deed(root)));
    qs
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::xml::{load_str, LoadOptions};

    #[test]
    fn a_lead_is_completed_with_the_names_that_match() {
        let t = load_str(
            std::path::Path::new("t.xml"),
            r#"<root BTCPP_format="4"><BehaviorTree ID="M"><Sequence name="go">
                 <Action ID="LookAt" name="look at chuck"/><Action ID="Lift" name="lift torso"/>
               </Sequence></BehaviorTree></root>"#,
            &LoadOptions::default(),
        )
        .unwrap()
        .tree;
        assert_eq!(
            complete(&t, "why did look", 3),
            ["why did look at chuck fail?"]
        );
        assert_eq!(complete(&t, "Can you lft", 3), ["Can you lift torso?"]);
        let c = complete(&t, "what went wr", 3);
        assert_eq!(c[0], "What went wrong?");
    }
}
