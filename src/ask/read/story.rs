//! A question inside its text: a post that tells a story before it asks,
//! a challenge or a correction before the question, several questions in
//! one text, and which of them the text asks.

use super::*;

/// Whether the question `q` of the post `text` stands on its own: no
/// "it" or "that" pointing into the story (in a question of Han's that
/// names no node, "it" is the robot: "The arm has moved over to the caddy
/// now. How does it go about the task it's currently on?"), no topic
/// before a colon. "At this point" points at the story's moment, which
/// the reading takes from the whole, not at a thing the story names.
pub(super) fn stands_alone(text: &str, q: &str, it_is_the_robot: bool) -> bool {
    let said = words::words(q);
    let pointing: &[&str] = if it_is_the_robot {
        &["that", "this", "there", "them", "they", "these", "those"]
    } else {
        &[
            "it", "its", "that", "this", "there", "them", "they", "these", "those",
        ]
    };
    // "What went on in it?": an "it" after a preposition is a thing.
    let a_thing = |i: usize| {
        i > 0
            && [
                "in", "of", "on", "at", "about", "with", "for", "from", "during",
            ]
            .contains(&said[i - 1].text.as_str())
    };
    let story = &text[..text.find(q).unwrap_or(0)];
    // "L2 fails at step 6. Then what would the fallback have returned?":
    // what would be asks of what the story supposes.
    let supposed = said.iter().any(|w| w.text == "would")
        && words::words(story)
            .iter()
            .any(|w| ["fails", "succeeds", "suppose", "if", "imagine"].contains(&w.text.as_str()));
    // "… walk is still going. Query: why is the robot doing this?": a
    // label before the colon, not a topic.
    let topic = story.trim_end().strip_suffix(':').is_some_and(|before| {
        let last = before
            .rsplit(|c: char| !c.is_alphanumeric())
            .next()
            .unwrap_or("");
        !["query", "question", "q", "ask", "asked", "check", "verify"]
            .contains(&last.to_lowercase().as_str())
    });
    said.len() >= 3
        && !supposed
        && !topic
        && !said.iter().enumerate().any(|(i, w)| {
            // "Why is the robot doing this?": Han's question, of what it does.
            let doing_this = w.text == "this" && i > 0 && said[i - 1].text == "doing";
            (pointing.contains(&w.text.as_str()) && !doing_this
                || it_is_the_robot && ["it", "its"].contains(&w.text.as_str()) && a_thing(i))
                // "In this run", "this log": the whole, not the story.
                && !said.get(i + 1).is_some_and(|n| {
                    [
                        "point", "moment", "instant", "stage", "time", "run", "log", "tree",
                    ]
                    .contains(&n.text.as_str())
                })
        })
}

/// Whether "it" in a question of Han's is the robot: one that names no
/// node, or a why that names its own ("… Why is it asking for help at
/// this point?").
pub(super) fn of_the_robot(a: &Reading) -> bool {
    match a.intent {
        Intent::Fixed(Question::Tree(TreeQuestion::Why)) => a.about.is_some(),
        Intent::Fixed(Question::Tree(_)) => a.about.is_none(),
        _ => false,
    }
}

/// A report of what was expected and what happened ("Actual: …",
/// "Expected: …", "Observed: …").
pub(super) fn reported(text: &str) -> bool {
    words::words(text)
        .iter()
        .any(|w| ["expected", "actual", "observed"].contains(&w.text.as_str()))
}

/// Whether the story's reading is what its short question asks: "Why did
/// it fail?" and "Root cause?" of the node the story told failed; "Why
/// ask?" after "expected a 4th attempt, actual: ask ran" of the contrast.
pub(super) fn the_story_asks_it(asked: &Reading, story: &Reading) -> bool {
    match (&asked.intent, &story.intent) {
        (
            Intent::Why {
                node: Subject::It | Subject::Task,
                event: a,
                foil: None,
            },
            Intent::Why {
                node: Subject::Nodes(..),
                event: b,
                foil: None,
            },
        ) => a == b || *a == Event::Run,
        (
            Intent::Why {
                node: Subject::It | Subject::Task,
                ..
            },
            Intent::WhyNot { .. },
        ) => true,
        (
            Intent::Fixed(Question::Tree(TreeQuestion::Why)),
            Intent::WhyNot {
                done: Subject::Nodes(us, _),
                ..
            },
        ) => asked.about.as_ref() == Some(us),
        (
            Intent::Why {
                node: Subject::Nodes(a, _),
                ..
            },
            Intent::WhyNot {
                done: Subject::Nodes(b, _),
                ..
            },
        ) => a == b,
        _ => false,
    }
}

/// "Retreat arm succeeded at 11:1 but reset arm still returned FAILURE at
/// 11:3. Why?": a bare why after a story that sets one thing against
/// another asks why of the part after its last "but" or "yet".
pub(super) fn why_of_the_story(text: &str) -> Option<String> {
    const BARE: &[&str] = &[
        "why?",
        "why so?",
        "why is that?",
        "but why?",
        "how come?",
        "why though?",
    ];
    let t = text.trim();
    // ASCII: the lowercase copy keeps the text's offsets.
    if !t.is_ascii() {
        return None;
    }
    let lower = t.to_ascii_lowercase();
    let bare = BARE.iter().find(|b| lower.ends_with(*b))?;
    // Only after a sentence of its own: "…FAILURE at 11:3. Why?".
    let story = t[..t.len() - bare.len()]
        .trim_end()
        .strip_suffix(['.', ',', ';', '-'])?
        .trim_end();
    if story.is_empty() {
        return None;
    }
    let last = story
        .rfind(['.', '!', ';'])
        .map_or(story, |i| &story[i + 1..]);
    let l = last.to_ascii_lowercase();
    // "We expected L1 here but actually saw L2. Why?": an expectation
    // against what happened asks why the one and not the other, read whole.
    if [
        "expect", "thought", "should", "supposed", "wanted", "instead",
    ]
    .iter()
    .any(|w| l.contains(w))
    {
        return None;
    }
    // Only the part a "but" sets apart is the surprise; a story without
    // one is read whole (the why asks of what it tells as a whole).
    let after = [" but ", " yet "]
        .iter()
        .filter_map(|c| l.rfind(c).map(|i| i + c.len()))
        .max()?;
    let told = &last[after..];
    (told.split_whitespace().count() >= 2).then(|| format!("why {}?", told.trim()))
}

/// A "which" or "what" question without the asker's guess at its answer
/// put after it ("which step of the patrol is it in right now — the
/// drive bit?"): the guess names a node, but the question asks which.
pub(super) fn without_a_guess(text: &str) -> &str {
    const THING: &[&str] = &["one", "bit", "part", "thing", "ones", "bits", "stuff"];
    let Some(cut) = [", ", " — ", " – ", " - "]
        .iter()
        .filter_map(|m| text.rfind(m))
        .max()
    else {
        return text;
    };
    let asked = text[..cut].trim();
    let guess: Vec<String> = text[cut..]
        .split_whitespace()
        .map(|w| {
            w.trim_matches(|c: char| !c.is_alphanumeric())
                .to_lowercase()
        })
        .filter(|w| !w.is_empty())
        .collect();
    let opens = asked
        .split_whitespace()
        .next()
        .is_some_and(|w| ["which", "what"].contains(&w.to_lowercase().as_str()));
    let a_guess = guess.len() <= 5
        && guess.first().is_some_and(|w| w == "the")
        && guess.last().is_some_and(|w| THING.contains(&w.as_str()));
    if opens && a_guess && !asked.contains('?') {
        asked
    } else {
        text
    }
}

/// Questions without what their asker adds after a dash: guesses at the
/// answer of a "what" or "which" ("What's the subgoal it's on right now -
/// planning, following, recovering, something else?") and asides about
/// the asker ("Which subgoal is it on - I'd like to match it against our
/// plan?"). A "why" keeps what follows ("why did FollowPath fail - the
/// action or the recovery node?" says which).
pub(super) fn without_asides(text: &str) -> String {
    const ASIDES: &[&str] = &[
        "i", "i'd", "i'm", "i've", "id", "im", "ive", "ideally", "just", "roughly", "bonus", "no",
        "purely", "not",
    ];
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(end) = rest.find('?') {
        let sentence_start = rest[..end].rfind(['.', '!', ':', ';']).map_or(0, |i| i + 1);
        let sentence = &rest[sentence_start..end];
        let cut = [" - ", " — ", " – "]
            .iter()
            .filter_map(|d| sentence.find(d).map(|i| (i, i + d.len())))
            .min();
        let mut kept = sentence;
        if let Some((at, after)) = cut {
            let asked = sentence[..at].trim();
            let aside = sentence[after..].trim();
            let first = |s: &str| {
                s.split_whitespace()
                    .next()
                    .unwrap_or("")
                    .trim_matches(|c: char| !c.is_alphanumeric() && c != '\'')
                    .to_lowercase()
            };
            let opener = first(asked);
            let what = ["what", "what's", "whats", "which"].contains(&opener.as_str());
            let guesses = aside.contains(',') || aside.contains(" or ");
            let about_the_asker = ASIDES.contains(&first(aside).as_str());
            let asks = OPENS.contains(&opener.as_str()) && asked.split_whitespace().count() >= 3;
            // "- like, which chapter of the job are we in?": the question
            // said again, no guess.
            let restated = aside
                .split_whitespace()
                .any(|w| OPENS.contains(&first(w).as_str()));
            if asks && !restated && (what && guesses || about_the_asker) {
                kept = &sentence[..at];
            }
        }
        out.push_str(&rest[..sentence_start]);
        out.push_str(kept);
        out.push('?');
        rest = &rest[end + 1..];
    }
    out.push_str(rest);
    out
}

/// A question without the doubt put after it ("why is look at chuck
/// roughly being run again? didn't it already succeed?"): the doubt says
/// what the asker thought, not what is asked.
pub(super) fn without_a_challenge(text: &str) -> &str {
    const DOUBTS: &[&str] = &[
        "didn't",
        "didnt",
        "wasn't",
        "wasnt",
        "hasn't",
        "hasnt",
        "isn't",
        "isnt",
        "doesn't",
        "doesnt",
        "shouldn't",
        "shouldnt",
        "wouldn't",
        "wouldnt",
    ];
    let Some(end) = text.find("? ") else {
        return text;
    };
    let rest = text[end + 2..].trim_start();
    // "… but didn't it already succeed?" too.
    let mut words = rest
        .split_whitespace()
        .map(|w| w.to_lowercase())
        .skip_while(|w| w == "but");
    let doubt = words.next().is_some_and(|w| DOUBTS.contains(&w.as_str()));
    let asks_why = text[..end].to_lowercase().starts_with("why");
    if doubt && asks_why && !rest[..rest.len().saturating_sub(1)].contains('?') {
        &text[..=end]
    } else {
        text
    }
}

/// The words a question opens with, after a comma or a dash.
pub(super) const OPENS: &[&str] = &[
    "what", "whats", "what's", "why", "how", "when", "which", "where", "did", "does", "do", "is",
    "was", "were", "are", "can", "could", "has", "have", "will", "would",
];

/// The surest reading of what follows a comma where a question opens
/// there ("…, can the taxi move down", "…, what is it doing now").
pub(super) fn asked_after_a_comma(
    vocabulary: &Vocabulary,
    tree: &Tree,
    text: &str,
) -> Option<Reading> {
    // "…, but did anything go wrong on the way?".
    text.match_indices(", ")
        .map(|(i, _)| text[i + 2..].strip_prefix("but ").unwrap_or(&text[i + 2..]))
        .filter(|rest| {
            rest.split_whitespace()
                .next()
                .is_some_and(|w| OPENS.contains(&w.to_lowercase().as_str()))
        })
        .filter_map(|rest| read_one(vocabulary, tree, rest))
        .reduce(|a, b| if b.confidence > a.confidence { b } else { a })
}

/// The reading of a question that follows ", so" ("…, so why is it
/// running again?").
fn asked_after_so(vocabulary: &Vocabulary, tree: &Tree, text: &str) -> Option<Reading> {
    const OPENS: &[&str] = &["what", "why", "how", "when", "which", "where"];
    let (_, rest) = text.rsplit_once(", so ")?;
    let first = rest.split_whitespace().next()?.to_lowercase();
    OPENS
        .contains(&first.as_str())
        .then(|| read_one(vocabulary, tree, rest))
        .flatten()
}

/// The question a story's last clause asks, read surely: a scenario's
/// "then" ("Given …, when …, then what went on in this tick?"), what
/// follows ", so" ("Spin failed a moment ago within this same tick, so
/// why is it running again?") or a topic's dash; the story before it
/// says when (a scenario's, where it puts the asker: `whole` is the
/// moment the whole text says).
pub(super) fn asked_after_the_story(
    vocabulary: &Vocabulary,
    tree: &Tree,
    text: &str,
    whole: Option<When>,
) -> Option<Reading> {
    let sure = |a: &Reading| a.confidence >= SURE;
    asked_after_then(vocabulary, tree, text)
        .filter(sure)
        .or_else(|| {
            let mut a = asked_after_so(vocabulary, tree, text)
                .or_else(|| asked_after_a_dash(vocabulary, tree, text))
                .filter(sure)?;
            // "Sorry if this is obvious. I'm at tick 12 and lost track -
            // which part is it on?": the moment the story says, where the
            // whole has none.
            a.when = a
                .when
                .or(whole)
                .or_else(|| when::find(&words::words(text)).map(|(w, _)| w));
            Some(a)
        })
}

/// The reading of the question a scenario asks in its "then" ("Given the
/// cursor is on tick 26, when I expand it, then what went on in this
/// tick?"): what the "given" and "when" say is the story; where the
/// question names no moment, the story's is asked about.
fn asked_after_then(vocabulary: &Vocabulary, tree: &Tree, text: &str) -> Option<Reading> {
    let lower = text.to_lowercase();
    if lower.len() != text.len() {
        return None;
    }
    let opening = lower
        .split_once(':')
        .filter(|(label, _)| label.split_whitespace().count() <= 4)
        .map_or(lower.as_str(), |(_, rest)| rest)
        .trim_start();
    if !["given ", "when "].iter().any(|g| opening.starts_with(g)) {
        return None;
    }
    let opens = |rest: &str| {
        rest.split_whitespace()
            .next()
            .is_some_and(|w| OPENS.contains(&w.to_lowercase().trim_matches('?')))
    };
    // "Given a fresh taxi run, can you move down?": with no "then", the
    // question opens after the given's comma.
    let then = [", then ", "; then ", ". then "]
        .iter()
        .filter_map(|t| lower.rfind(t).map(|i| (i, i + t.len())))
        .max();
    // Not "Given look at chuck had succeeded at tick 10, would …": a given
    // that supposes is the question's own condition.
    let given = || {
        lower
            .match_indices(", ")
            .map(|(i, _)| (i, i + 2))
            .find(|&(_, j)| opens(&text[j..]))
            .filter(|&(_, j)| opening.starts_with("given ") && !lower[j..].contains("would"))
    };
    let at = then.or_else(given)?;
    let rest = &text[at.1..];
    if !opens(rest) {
        return None;
    }
    let mut a = read_one(vocabulary, tree, rest)?;
    let of_the_robot = matches!(a.intent, Intent::Fixed(Question::Tree(_)));
    a.when = a
        .when
        .or_else(|| where_the_story_is(&text[..at.0], of_the_robot));
    Some(a)
}

/// The moment a scenario's story tells: of Han's questions (what it is
/// doing, why), where the story puts the asker ("when I jump back to tick
/// 21", "the cursor is on tick 26"), not when an event of it happened
/// ("Given FollowPath failed at 4:1, then why is it running it again?"
/// asks at the cursor); of an event's ("Given look at chuck failed at
/// tick 10, how was that handled?"), either.
fn where_the_story_is(story: &str, of_the_robot: bool) -> Option<When> {
    let said = words::words(story);
    let (when, at) = when::find(&said)?;
    if !of_the_robot {
        return Some(when);
    }
    let first = *at.iter().min()?;
    let of_an_event = said[first.saturating_sub(2)..first].iter().any(|w| {
        [
            "fail", "succeed", "start", "finish", "ran", "run", "return", "halt", "stop", "complet",
        ]
        .contains(&w.stem.as_str())
    });
    (!of_an_event).then_some(when)
}

/// The reading of a question that follows a dash after a topic that asks
/// nothing ("Tuning the RateController hz - how many times did
/// ComputePathToPose run in this log?"); not "X sat in RUNNING - why?",
/// whose question is the whole, nor one that points into the topic.
fn asked_after_a_dash(vocabulary: &Vocabulary, tree: &Tree, text: &str) -> Option<Reading> {
    let (topic, rest) = [" - ", " — ", " – "]
        .iter()
        .filter_map(|d| text.rsplit_once(d))
        .max_by_key(|(topic, _)| topic.len())?;
    let asks = |w: &str| OPENS.contains(&w.to_lowercase().trim_matches('?'));
    // "L0 succeeds — how does the run change?": the topic supposes.
    let supposes = |w: &str| {
        ["succeeds", "fails", "if", "suppose", "had"].contains(&w.to_lowercase().as_str())
    };
    // Only the topic's last sentence can ask or suppose: "Sorry if this is
    // obvious. I'm at tick 12 and lost track - which part is it on?".
    let last = topic
        .rfind(['.', '!', ';'])
        .map_or(topic, |i| &topic[i + 1..]);
    // "… lost track of where we are in the plan - which part is it on?":
    // a "where" inside a clause asks nothing; one that opens it does.
    let opens_a_clause = last.split(',').any(|clause| {
        clause
            .split_whitespace()
            .find(|w| !["so", "and", "but", "then"].contains(&w.to_lowercase().as_str()))
            .is_some_and(asks)
    });
    let topic_asks = topic.contains('?') || opens_a_clause || last.split_whitespace().any(supposes);
    // "… - how did the tree respond, step by step? I need it for
    // Thursday's call.": the question ends at its question mark.
    let rest = rest.find("? ").map_or(rest, |i| &rest[..=i]);
    let opens = rest.split_whitespace().next().is_some_and(asks);
    if topic_asks || !opens || rest.split_whitespace().count() < 4 {
        return None;
    }
    // "Tick 14 - what went on there?": a question that points into the
    // topic is asked of it, as a whole.
    read_one(vocabulary, tree, rest).filter(|a| {
        // "Before I forward this log - did anything go wrong in the run,
        // or is it a clean one?": "it" is the run.
        let whole_run = a.intent == Intent::Fixed(Question::Run(RunQuestion::AnythingWrong));
        stands_alone(text, rest, of_the_robot(a) || whole_run) || of_the_failure_told(rest, a)
    })
}

/// "… where the insert large gear sequence fell over. I'm not worried
/// about the cause yet - how did the tree respond to that failure?": how a
/// failure was handled, or whether it was recovered from, asks of the
/// failure at the moment the story says, whichever node failed.
fn of_the_failure_told(question: &str, a: &Reading) -> bool {
    let of_a_failure = matches!(
        a.intent,
        Intent::Recovered | Intent::Fixed(Question::Run(RunQuestion::Handled))
    );
    let said = words::words(question);
    of_a_failure
        && said.windows(2).any(|p| {
            ["that", "this"].contains(&p[0].text.as_str())
                && ["failure", "error", "fault", "problem", "crash", "abort"]
                    .contains(&p[1].text.as_str())
        })
}

/// The questions a text of several sentences asks: each sentence that
/// ends in "?", and what follows a colon ("I need the exact point in the
/// run: when did look at chuck fail?"). None for a text of one sentence.
pub(super) fn questions_in(text: &str) -> Vec<&str> {
    let mut cuts = vec![0];
    let b = text.as_bytes();
    for i in 0..b.len().saturating_sub(1) {
        if matches!(b[i], b'.' | b'?' | b'!' | b':' | b';') && b[i + 1].is_ascii_whitespace() {
            cuts.push(i + 1);
        }
    }
    cuts.push(text.len());
    if cuts.len() <= 2 {
        return Vec::new();
    }
    // "CaseStudySequence has just returned FAILURE. Explain what went
    // wrong.": a last sentence that bids is asked as a question is.
    let last = cuts.len() - 2;
    // "ReactiveSequence re-ticks its condition, right? How many times …":
    // a tag before another question confirms the story, it asks nothing.
    let tag = |i: usize, s: &str| i < last && s.to_lowercase().ends_with(", right?");
    cuts.windows(2)
        .enumerate()
        .map(|(i, w)| (i, text[w[0]..w[1]].trim()))
        .filter(|&(i, s)| {
            s.ends_with('?') && !tag(i, s) || i == last && bids(s, &text[..cuts[last]])
        })
        .map(|(_, s)| s)
        .collect()
}

/// A sentence that bids the reader explain or describe, after a story that
/// supposes nothing ("Explain what went wrong.", not "Suppose X had
/// failed. Describe what the tree would do.").
pub(super) fn bids(sentence: &str, story: &str) -> bool {
    let mut words = sentence.split_whitespace();
    let first = words.next().unwrap_or("").to_lowercase();
    if !["explain", "describe"].contains(&first.as_str()) || words.count() < 2 {
        return false;
    }
    let supposes = story.split_whitespace().any(|w| {
        ["suppose", "imagine", "had", "if", "would", "hypothetically"].contains(
            &w.to_lowercase()
                .trim_matches(|c: char| !c.is_alphanumeric()),
        )
    });
    !supposes
}

/// The moment the story gives the node a question asks about: "`detect
/// chuck` came back SUCCESS at tick 6, yet `look at chuck` went to FAILURE
/// at tick 10. Why did look at chuck fail?" asks about tick 10, the
/// moment of the clause that names look at chuck, not the story's first.
pub(super) fn moment_of_the_node(
    vocabulary: &Vocabulary,
    tree: &Tree,
    story: &str,
    asked: &Reading,
) -> Option<When> {
    let uids = match &asked.intent {
        Intent::Why {
            node: Subject::Nodes(uids, _),
            ..
        }
        | Intent::When {
            node: Subject::Nodes(uids, _),
            ..
        }
        | Intent::WhatIf {
            node: Subject::Nodes(uids, _),
            ..
        } => uids,
        _ => return None,
    };
    let clauses = story.split([',', ';', '.', '?', '!']);
    let mut found = clauses.filter_map(|clause| {
        let q = words::words(clause);
        let (s, when) = named_parts(vocabulary, tree, &q);
        let names = s
            .nodes
            .iter()
            .any(|m| m.uids.iter().any(|u| uids.contains(u)));
        when.filter(|_| names)
    });
    // Only where one clause says it: two moments of the node leave it open.
    match (found.next(), found.next()) {
        (Some(w), None) => Some(w),
        _ => None,
    }
}
