//! Questions of an event as such: "can you X?", "what if X had failed?",
//! "did X happen?".

use super::*;

/// "Can you X?": the rest of the words are the behaviour.
pub(super) fn can_you_asked(c: &Cues) -> Option<Readings> {
    let x = can_you(c.s, c.tree)?;
    c.only(Intent::Fixed(Question::CanYou(x)), 0.95)
}

/// A "would" that supposes, not one that asks politely or prefers ("I'd
/// like to know", "I'd rather not find out on site").
fn would_supposes(s: &Sentence) -> bool {
    s.free().any(|(i, w)| {
        w.text == "would"
            && !s.q.get(i + 1).is_some_and(|n| {
                ["rather", "like", "love", "prefer", "appreciate"].contains(&n.text.as_str())
            })
    })
}

/// A "had" that may suppose, not "have had" ("the policies we've had").
fn had_supposes(s: &Sentence) -> bool {
    s.free().any(|(i, w)| {
        w.text == "had" && !(i > 0 && ["have", "has", "having"].contains(&s.q[i - 1].text.as_str()))
    })
}

/// "What if X fails?", "what would have happened if X had failed".
pub(super) fn what_if(c: &Cues) -> Option<Readings> {
    let s = c.s;
    let conditional = s.phrase(&["what", "if"]).is_some()
        || s.phrase(&["happen", "if"]).is_some()
        || s.phrase(&["happens", "if"]).is_some()
        || s.phrase(&["happened", "if"]).is_some()
        || s.phrase(&["do", "if"]).is_some()
        // "Suppose X had failed", not "after it ran out of tries, I suppose".
        || s.free().any(|(i, w)| {
            w.text == "suppose" && (i == 0 || !["i", "we"].contains(&s.q[i - 1].text.as_str()))
        })
        || s.has("supposing")
        // "Assume FollowPath held", not "I assume it is expected".
        || s.q.first().is_some_and(|w| ["assume", "assuming"].contains(&w.text.as_str()))
        || s.phrase(&["let's", "assume"]).is_some()
        || s.phrase(&["lets", "assume"]).is_some()
        || s.has("imagine")
        // "Had path clear returned SUCCESS, would …", "what would have
        // happened had X failed": the conditional put first.
        || c.first == "had"
        || had_supposes(s) && would_supposes(s)
        || s.phrase(&["consider", "the", "case"]).is_some()
        || s.phrase(&["in", "the", "event"]).is_some()
        || s.has("hypothetically")
        // "The counterfactual where the move right fails: what happens to
        // the goal?", as the papers' students say it.
        || s.has_prefix(&["counterfactual"]) && c.ev.is_some() && !c.why
        // "What intervention on walk would change things?".
        || s.has_stem(&["intervent", "interven"]) && s.has("would") && c.ev.is_some()
        || c.first == "if"
        // "Drop off fails, what happens", "X fails at tick 22 what then":
        // an outcome put in the present, then what comes of it.
        // "Scenario: walk fails at tick 3. What would the robot have
        // done?": a test's scenario, then what would have come of it.
        // "Third move right at tick 4 craps out. Consequence?", "L0
        // passes at 1:3 instead. Then what?".
        || outcome_in_the_present(s)
            && (s.phrase(&["what", "happens"]).is_some()
                || s.phrase(&["what", "then"]).is_some()
                || s.phrase(&["then", "what"]).is_some()
                || s.has_stem(&["consequ", "fallout", "knock"])
                || s.phrase(&["play", "out"]).is_some()
                || s.has("would") && s.has("have"))
        // "How would the run differ if look around had failed?", "say the
        // second move up had failed: then what?".
        || s.has("if") && (would_supposes(s) || had_supposes(s))
        || s.has("had") && (c.first == "say" || s.phrase(&["then", "what"]).is_some())
        // "Predict the outcome of the run had it failed instead".
        || s.has("had") && (s.has("instead") || s.has("outcome")) && !c.why
        // "L0 succeeds: how does the run change?".
        || c.how && s.has_stem(&["chang", "differ"]) && c.ev.is_some() && !c.named.is_empty();
    // "If a move failed here, what did the tree do about it in this
    // run?": what was done, in the run, whenever it happened.
    let what_was_done = s.phrase(&["did", "about"]).is_some()
        || s.phrase(&["do", "about", "it"]).is_some() && s.has("did");
    if !conditional || what_was_done && !s.has("would") {
        return None;
    }
    let node @ Subject::Nodes(..) = c.subject()? else {
        return None;
    };
    // The outcome supposed is the one said in the condition ("suppose X
    // had succeeded; would L2 still have been ticked?").
    let event = match supposed(s).or(c.ev) {
        Some(Event::Succeed) => Event::Succeed,
        // "If drop off passenger had kept returning RUNNING".
        Some(Event::KeepRunning) => Event::KeepRunning,
        _ => Event::Fail,
    };
    Some(vec![(Intent::WhatIf { node, event }, c.sure(0.92))])
}

/// "Fails", "succeeds", "passes", "craps out": an outcome put in the
/// present, as a scenario is.
fn outcome_in_the_present(s: &Sentence) -> bool {
    ["fails", "succeeds", "passes", "craps", "bombs", "conks"]
        .iter()
        .any(|w| s.has(w))
}

/// The outcome said between a conditional's mark ("if", "had",
/// "suppose") and what is asked of it ("would", "what", "then").
pub(super) fn supposed(s: &Sentence) -> Option<Event> {
    const MARK: &[&str] = &[
        "if",
        "had",
        "suppose",
        "supposing",
        "assume",
        "assuming",
        "case",
        "event",
        "counterfactual",
    ];
    let q = s.q;
    let from = q.iter().position(|w| MARK.contains(&w.text.as_str()))?;
    let clause: Vec<&crate::ask::read::words::Word> = q[from + 1..]
        .iter()
        .take_while(|w| !["would", "what", "then", "how"].contains(&w.text.as_str()))
        .collect();
    // "Had not failed" supposes it succeeded.
    let not = clause
        .iter()
        .any(|w| ["not", "never"].contains(&w.text.as_str()));
    // "Had drop off kept returning RUNNING", not "had path clear stayed
    // true" or "keeps failing".
    let runs_on = clause.iter().any(|w| {
        ["kept", "keep", "keeps", "stayed", "stuck", "hung", "still"].contains(&w.text.as_str())
    }) && clause.iter().any(|w| w.text == "running");
    if runs_on {
        return Some(Event::KeepRunning);
    }
    let said = clause.iter().find_map(|w| match w.stem.as_str() {
        // "Had path_clear held": a condition that held succeeded.
        "succeed" | "success" | "pass" | "true" | "held" | "hold" => Some(Event::Succeed),
        "fail" | "failur" | "fals" => Some(Event::Fail),
        _ => None,
    })?;
    Some(match (said, not) {
        (Event::Fail, true) => Event::Succeed,
        (Event::Succeed, true) => Event::Fail,
        (e, _) => e,
    })
}

/// "Did the planner run?", "has follow path failed": whether, and how often.
pub(super) fn whether_it_happened(c: &Cues) -> Option<Readings> {
    let (Some(m), Some(e), true) = (c.named.first(), c.ev, c.yes_no) else {
        return None;
    };
    let node = Subject::Nodes(m.uids.clone(), m.phrase.clone());
    let event = if e == Event::NotRun { Event::Run } else { e };
    Some(vec![
        (
            Intent::HowOften {
                node: node.clone(),
                event,
            },
            c.sure(0.85),
        ),
        (
            Intent::When {
                node,
                event,
                which: Which::Every,
            },
            0.5,
        ),
    ])
}

/// A node and an event with no question word: "look at chuck failed?".
pub(super) fn event_alone(c: &Cues) -> Option<Readings> {
    let (Some(m), Some(event)) = (c.s.nodes.first(), c.ev) else {
        return None;
    };
    let node = Subject::Nodes(m.uids.clone(), m.phrase.clone());
    Some(vec![
        (
            Intent::Why {
                node: node.clone(),
                event,
                foil: None,
            },
            c.sure(0.55),
        ),
        (
            Intent::When {
                node: node.clone(),
                event,
                which: Which::Every,
            },
            0.45,
        ),
        (Intent::HowOften { node, event }, 0.4),
    ])
}
