//! One sentence read: its nodes and moment found, what it asks
//! classified, the readings weighed and the surest chosen.

use super::*;

pub(super) fn read_one(vocabulary: &Vocabulary, tree: &Tree, text: &str) -> Option<Reading> {
    heard(vocabulary, tree, text).ok()
}

/// Why a question has no reading: nothing in it read, or it asks of the
/// robot's world, which no run holds ("Who wrote this tree?", "what was
/// the motor's temperature?").
pub(super) enum Unread {
    Nothing,
    OfTheWorld,
}

/// A question read, or why it is not.
pub(super) fn heard(vocabulary: &Vocabulary, tree: &Tree, text: &str) -> Result<Reading, Unread> {
    if text.trim().eq_ignore_ascii_case("q5") {
        return Ok(Reading {
            intent: Intent::Fixed(Question::Tree(TreeQuestion::HowSubgoal)),
            confidence: 1.0,
            alternatives: Vec::new(),
            when: None,
            about: None,
        });
    }
    let text = states_as_outcomes(
        tree,
        &ids_as_uids(
            tree,
            &paths_as_uids(
                tree,
                &named_as_uids(
                    tree,
                    &ports_as_uids(
                        tree,
                        &shorthand::spelled_out(tree, &colours::as_statuses(tree, text)),
                    ),
                ),
            ),
        ),
    );
    let q = words::words(&text);
    if q.is_empty() {
        return Err(Unread::Nothing);
    }
    let (s, when) = named_parts(vocabulary, tree, &q);
    let mut in_mention = vec![false; q.len()];
    for m in &s.nodes {
        for f in &mut in_mention[m.start..m.end] {
            *f = true;
        }
    }
    // Typos in the words that ask ("wen", "frist", "fial"), now that the
    // tree's names have been found as they were written.
    let q: Vec<Word> = q
        .iter()
        .enumerate()
        .map(|(i, w)| {
            if in_mention[i] || s.used[i] {
                w.clone()
            } else {
                corrected(w, s.tree_words)
            }
        })
        .collect();
    if not_of_the_run(tree, &q, &s, &in_mention) {
        return Err(Unread::OfTheWorld);
    }
    chosen(tree, &s, &q, readings(tree, &s, &q), when).ok_or(Unread::Nothing)
}

/// What the sentence asks, best first: read with its strong mentions;
/// weak ones ("wait" in "wait, what failed?") stay words unless the
/// question names no other node and asks about one.
pub(super) fn readings(tree: &Tree, s: &Sentence, q: &[Word]) -> Vec<(Intent, f32)> {
    let strong: Vec<Mention> = s.nodes.iter().filter(|m| !m.weak).cloned().collect();
    let with_strong = s.with_nodes(q, strong);
    let mut r = classify(&with_strong, tree);
    if r.is_empty()
        || r.iter().all(|(i, _)| needs_node(i))
        || r.first().is_some_and(|(i, _)| about_task(i))
    {
        let weak: Vec<Mention> = s.nodes.iter().filter(|m| m.weak).cloned().collect();
        if !weak.is_empty() && with_strong.nodes.is_empty() {
            let with_weak = s.with_nodes(q, weak);
            let alt = classify(&with_weak, tree);
            if alt.iter().any(|(i, _)| subject_of(i).is_some()) {
                r = alt;
            }
        }
    }
    // "Why did it go to recoveries instead of trying the controller": a
    // contrast needs two nodes, and a node named by a word that also asks
    // ("recoveries") is the second.
    let contrast = with_strong.phrase(&["instead", "of"]).is_some()
        || with_strong.phrase(&["rather", "than"]).is_some();
    if contrast && with_strong.nodes.len() == 1 && s.nodes.len() > 1 {
        let all = s.with_nodes(q, s.nodes.clone());
        let alt = classify(&all, tree);
        if alt
            .first()
            .is_some_and(|(i, _)| matches!(i, Intent::WhyNot { .. }))
        {
            r = alt;
        }
    }
    r.sort_by(|a, b| b.1.total_cmp(&a.1));
    r
}

/// The best reading, up to three others as alternatives, the moment it is
/// asked at, and the node a question of Han's names.
pub(super) fn chosen(
    tree: &Tree,
    s: &Sentence,
    q: &[Word],
    readings: Vec<(Intent, f32)>,
    when: Option<When>,
) -> Option<Reading> {
    let mut it = readings.into_iter();
    let (intent, confidence) = it.next()?;
    let mut alternatives: Vec<Intent> = Vec::new();
    for (i, _) in it {
        if i != intent && !alternatives.contains(&i) && alternatives.len() < 3 {
            alternatives.push(i);
        }
    }
    // "Did it recover after the failure?": the failure is what the
    // recovery is from, not the moment to ask at.
    let when = match (&intent, when) {
        (Intent::Recovered, Some(When::AfterFailure | When::AfterRecovery)) => None,
        // "Did it recover in the end?", "did it eventually recover?":
        // by the end of the run, wherever it is asked. (Not a moment in
        // general: "what's it trying to achieve in the end?" asks the goal.)
        (Intent::Recovered, None) if in_the_end(q) => Some(When::LastTick),
        (_, w) => w,
    };
    let when = match (when::nth_time(q), when) {
        (Some(n), Some(When::BeforeFailureOf(uid) | When::AfterFailureOf(uid))) => {
            Some(When::Ended {
                uid,
                n,
                failed: true,
                side: if matches!(when, Some(When::BeforeFailureOf(_))) {
                    Side::Before
                } else {
                    Side::After
                },
            })
        }
        (Some(n), None) => nth_end(tree, &intent, n),
        (_, w) => w,
    };
    let when = when.or_else(|| failure_handled(tree, s, q, &intent));
    let about = match intent {
        Intent::Fixed(Question::Tree(_)) => s
            .nodes
            .iter()
            .find(|m| !m.weak && m.uids != [tree.root().uid])
            .map(|m| m.uids.clone()),
        _ => None,
    };
    Some(Reading {
        intent,
        confidence: confidence.clamp(0.0, 1.0),
        alternatives,
        when,
        about,
    })
}

fn in_the_end(q: &[Word]) -> bool {
    q.windows(3)
        .any(|w| w.iter().map(|w| w.text.as_str()).eq(["in", "the", "end"]))
        || q.iter()
            .any(|w| ["eventually", "ultimately"].contains(&w.text.as_str()))
}

/// "Why did FollowPath fail the second time?", "what if detect chuck
/// had succeeded on the third try?": the moment of the node's N-th end:
/// its N-th failure where a why asks about failing, else its N-th run to
/// an end ("why did it manage the second time": the second try; a
/// what-if's is the run it would change). "When did it fail the first
/// time" asks which, not at when.
pub(super) fn nth_end(tree: &Tree, intent: &Intent, n: u32) -> Option<When> {
    let (uids, failed) = match intent {
        // "Why did it stall the first time?": of the robot, whose failures
        // are its actions'.
        Intent::Why {
            node: Subject::It,
            event: Event::Fail,
            ..
        } => return Some(When::NthFailure(n)),
        Intent::Why {
            node: Subject::Nodes(us, _),
            event,
            ..
        } => (us, *event == Event::Fail),
        Intent::WhatIf {
            node: Subject::Nodes(us, _),
            ..
        } => (us, false),
        _ => return None,
    };
    Some(When::Ended {
        uid: deepest(tree, uids),
        n,
        failed,
        side: Side::At,
    })
}

/// "How did it handle the first follow path failure?", "what did it do
/// when FollowPath failed the second time?", "did it recover after
/// FollowPath's second failure?": the failure a question of handling or
/// recovery names, where it says which.
fn failure_handled(tree: &Tree, s: &Sentence, q: &[Word], intent: &Intent) -> Option<When> {
    let handled = Intent::Fixed(Question::Run(crate::explain::RunQuestion::Handled));
    if *intent != handled && *intent != Intent::Recovered {
        return None;
    }
    let n = q.iter().find_map(|w| when::ordinal(&w.text))?;
    let m = s
        .nodes
        .iter()
        .find(|m| !m.weak && m.uids != [tree.root().uid])?;
    q.iter()
        .any(|w| w.stem.starts_with("fail"))
        .then(|| When::Ended {
            uid: deepest(tree, &m.uids),
            n,
            failed: true,
            side: Side::At,
        })
}

/// A reading about the task or "it", where a weak mention may be the node.
pub(super) fn about_task(i: &Intent) -> bool {
    matches!(
        i,
        Intent::Why {
            node: Subject::Task | Subject::It,
            ..
        } | Intent::When {
            node: Subject::Task | Subject::It,
            ..
        } | Intent::HowOften {
            node: Subject::Task | Subject::It,
            ..
        }
    )
}

/// Words that ask, to correct a typo in one of them against.
pub(super) const CUE_WORDS: &[&str] = &[
    "when",
    "what",
    "why",
    "first",
    "fail",
    "failed",
    "failure",
    "happened",
    "happen",
    "succeed",
    "succeeded",
    "recover",
    "recovered",
    "recovery",
    "running",
    "started",
    "doing",
    "subgoal",
    "goal",
    "wrong",
    "next",
    "handled",
    "often",
    "times",
    "tick",
    "before",
    "after",
    "last",
    "final",
    "busy",
    "going",
    "computing",
    "finish",
    "finished",
    "halted",
    "skipped",
    "instead",
    "rather",
    "explain",
    "describe",
    "objective",
    "mission",
];

pub(super) fn corrected(w: &Word, tree_words: &rustc_hash::FxHashSet<String>) -> Word {
    let t = w.text.as_str();
    // A cue word's other forms ("happens" of "happen") are not typos.
    static CUE_STEMS: std::sync::OnceLock<rustc_hash::FxHashSet<String>> =
        std::sync::OnceLock::new();
    let cue_stems = CUE_STEMS.get_or_init(|| CUE_WORDS.iter().map(|c| words::stem(c)).collect());
    if t.chars().count() < 3
        || CUE_WORDS.contains(&t)
        // Words of their own a letter from a cue ("past" is not "last").
        || [
            "past", "fast", "lost", "cast", "vast", "then", "tickle", "fall", "falls", "hell",
        ]
        .contains(&t)
        || cue_stems.contains(&w.stem)
        || tree_words.contains(&w.stem)
        || FILLER.contains(&t)
        || IMPERATIVE.contains(&t)
        || LEAD.contains(&t)
        || !t.chars().all(|c| c.is_ascii_alphabetic())
    {
        return w.clone();
    }
    // "computin": a dropped g.
    if t.ends_with("in") && t.len() >= 5 {
        let g = format!("{t}g");
        let stem = words::stem(&g);
        if CUE_WORDS.contains(&g.as_str()) || tree_words.contains(&stem) {
            return Word { stem, text: g };
        }
    }
    let best = CUE_WORDS
        .iter()
        .filter(|c| c.len() >= 4 && c.len().abs_diff(t.len()) <= 1)
        .find(|c| strsim::osa_distance(c, t) <= 1 && (t.len() >= 4 || c.starts_with(&t[..1])));
    match best {
        Some(c) => Word {
            text: c.to_string(),
            stem: words::stem(c),
        },
        None => w.clone(),
    }
}

pub(super) fn needs_node(i: &Intent) -> bool {
    matches!(
        i,
        Intent::Why {
            node: Subject::Task,
            ..
        }
    )
}

pub(super) fn subject_of(i: &Intent) -> Option<&Subject> {
    match i {
        Intent::Why { node, .. }
        | Intent::When { node, .. }
        | Intent::HowOften { node, .. }
        | Intent::WhatIf { node, .. } => Some(node).filter(|s| matches!(s, Subject::Nodes(..))),
        _ => None,
    }
}
