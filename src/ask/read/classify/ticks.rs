//! A tick told, by its number or its place, and what comes next.

use super::*;

/// "What happened in tick 4, right before the failure?", "tell me about
/// tick 6, the first time detection failed": a tick asked by its number,
/// right after the words that ask it; what follows says which it is.
pub(super) fn tick_by_number(c: &Cues) -> Option<Readings> {
    let words = c.s.q;
    if !words.iter().any(|w| w.text == "tick") {
        return None;
    }
    let q: Vec<&str> = words.iter().map(|w| w.text.as_str()).collect();
    let asks = |i: usize| {
        [
            "happened",
            "happens",
            "happen",
            "describe",
            "summary",
            "summarize",
            "summarise",
            "recap",
            "rundown",
            "account",
            "occurred",
            // "Tick 1 - full narrative please", "per-tick view for tick 4".
            "narrative",
            "narrate",
            "story",
            "view",
            "walkthrough",
            "timeline",
            "transcript",
        ]
        .contains(&q[i])
            || (q[i] == "about" && i >= 2 && q[i - 2] == "tell")
            // "What took place in tick 1", "walk me through tick 5".
            || (q[i] == "place" && i >= 1 && ["took", "take", "takes"].contains(&q[i - 1]))
            || (q[i] == "through" && i >= 1 && ["walk", "me", "us"].contains(&q[i - 1]))
    };
    // "t4: spin F then R again - explain": a tick said first, a story of
    // it, and only "explain" to ask.
    let explained = q[0] == "tick"
        && q.iter().rposition(|w| *w == "explain").is_some_and(|e| {
            q[e + 1..]
                .iter()
                .all(|w| ["the", "this", "that", "tick"].contains(w))
        });
    let at = (0..q.len()).find(|&i| asks(i)).or_else(|| {
        explained
            .then(|| q.iter().rposition(|w| *w == "explain"))
            .flatten()
    })?;
    let mut k = at + 1;
    // "Account for the transitions in tick 6", "an account of that tick".
    while k < q.len()
        && [
            "at",
            "in",
            "on",
            "during",
            "for",
            "the",
            "of",
            "that",
            "transitions",
            "events",
        ]
        .contains(&q[k])
    {
        k += 1;
    }
    // "Tick 13 summary", "t5 what happened": the tick said first.
    // "t5 - PC F … explain the tick": the tick said first is the one.
    let numbered =
        q.get(k) == Some(&"tick") && q.get(k + 1).is_some_and(|n| n.parse::<u32>().is_ok());
    if !numbered && (q[0] == "tick" || at >= 2 && q[at - 2] == "tick") {
        k = if q[0] == "tick" { 0 } else { at - 2 };
    }
    let n: u32 = (q.get(k) == Some(&"tick"))
        .then(|| q.get(k + 1)?.parse().ok())
        .flatten()?;
    let other = ["wrong", "why", "if", "how", "subgoal", "goal"];
    (n > 0 && !q.iter().any(|w| other.contains(w)))
        .then(|| vec![(Intent::Tick(n), c.sure_of_words(0.95))])
}

/// A tick's transitions: "describe tick 9", "what happened in the last tick".
pub(super) fn tick(c: &Cues) -> Option<Readings> {
    let s = c.s;
    let asked_when = when::find(s.q).map(|(w, _)| w);
    // "The tick where the spin failed": the moment is that failure's.
    let this_tick = s.phrase(&["this", "tick"]).is_some()
        || s.phrase(&["that", "tick"]).is_some()
        || s.phrase(&["current", "tick"]).is_some()
        // The explorer's words: "the tick under the cursor".
        || s.phrase(&["tick", "under", "the", "cursor"]).is_some()
        || s.phrase(&["tick", "at", "the", "cursor"]).is_some()
        || s.phrase(&["selected", "tick"]).is_some()
        || s.q.windows(2).enumerate().any(|(i, p)| {
            p[0].text == "tick"
                && !s.used[i]
                && s.used[i + 1]
                && ["where", "when", "in", "that"].contains(&p[1].text.as_str())
        });
    // "What happened when drop off passenger succeeded?": the moment is
    // that event's (`clauses::moment_of_an_event` took its words).
    let at_an_event = asked_when.is_none()
        && s.q
            .iter()
            .enumerate()
            .any(|(i, w)| s.used[i] && ["when", "moment", "as", "time"].contains(&w.text.as_str()));
    if asked_when.is_none() && !this_tick && !at_an_event {
        return None;
    }
    // "What was happening at 1:6?", "what were you on at 12:13?": what it
    // was doing at a step, not the whole tick.
    // ("On at 2:2" may be read as the moment: the words count.)
    let going_on = s.has("happening")
        || s.q
            .windows(2)
            .any(|p| p[0].text == "going" && p[1].text == "on")
        || on_it(s);
    if matches!(asked_when, Some(When::Step(..))) && going_on {
        return Some(vec![(
            Intent::Fixed(Question::Tree(TreeQuestion::Doing)),
            c.sure_of_words(0.93),
        )]);
    }
    let n = match asked_when {
        Some(When::Tick(n) | When::Step(n, _)) => n,
        _ => 0,
    };
    // "What's been going on in this tick so far?".
    let walk = walks_through(c) || going_on && this_tick;
    // "What went on", not "what went wrong"; "describe how it pursues its
    // subgoal at tick 5" asks how, not what happened.
    let asks_other = s.has_stem(&["achiev", "accomplish", "pursu"])
        && s.has_stem(&["goal", "subgoal"])
        || s.phrase(&["went", "wrong"]).is_some()
        // "At tick 35, what are the steps of the sub-task it's in?".
        || steps_of_a_part(s);
    let asks_tick = (s.has_stem(&[
        "happen", "chang", "occur", "describ", "summar", "show", "transit", "detail", "explain",
        "event", "recap", "memori", "episod", "summaris", "summariz", "sitrep",
    ]) || c.break_down
        || s.empty()
        || (c.what
            && !c.doing_words
            && !s.has_stem(&["run", "goal", "subgoal", "execut", "action"])))
        && !asks_other
        || walk;
    // "t10: FP S, then a bunch of halts. What exactly happened in that
    // tick?": the names are the story's, told before what is asked.
    let asked_from = s
        .free()
        .filter(|(_, w)| w.text == "what")
        .last()
        .map_or(0, |(i, _)| i);
    let named_in_question = c.named.iter().any(|m| m.end > asked_from);
    (asks_tick && !named_in_question && (!c.doing_words || walk))
        .then(|| vec![(Intent::Tick(n), c.sure_of_words(0.95))])
}

/// "Walk me through tick 4", "what went on", "tick 1 step by step",
/// "break it down": the tick told.
fn walks_through(c: &Cues) -> bool {
    let s = c.s;
    s.phrase(&["walk", "me", "through"]).is_some()
        || s.phrase(&["walk", "through"]).is_some()
        || s.phrase(&["went", "on"]).is_some()
        || s.phrase(&["step", "by", "step"]).is_some()
        || c.break_down
}

/// What next?
pub(super) fn next(c: &Cues) -> Option<Readings> {
    let s = c.s;
    // "How one failure led to the next": the next of a chain, not of the run.
    let next = s.has("next") && !a_chain_of_failures(s)
        || s.phrase(&["going", "to", "do"]).is_some()
        || s.phrase(&["will", "you", "do"]).is_some()
        || s.phrase(&["will", "it", "do"]).is_some()
        || s.phrase(&["will", "the", "robot", "do"]).is_some()
        || s.phrase(&["comes", "after"]).is_some()
        || s.phrase(&["after", "this"]).is_some()
        || s.phrase(&["after", "that"]).is_some()
        || s.has("afterwards")
        || s.has("upcoming")
        // "What does the policy move on to?".
        || (s.phrase(&["move", "on"]).is_some() || s.phrase(&["moves", "on"]).is_some())
            && !s.has("did")
        // "What's the following action gonna be?".
        || s.has("following") && (s.phrase(&["going", "to", "be"]).is_some() || s.has("will"))
        // "And then what does it do?".
        || s.phrase(&["then", "what"]).is_some() && !s.has("if")
        // "And then?".
        || s.q.len() <= 3 && s.q.last().is_some_and(|w| w.text == "then") && !s.has("if")
        || s.phrase(&["from", "here"]).is_some() && s.has("go")
        || (s.has("after") && (s.has("will") || s.has("happens")))
        // "And what does it do after picking the first screw?".
        || c.what && s.phrase(&["does", "it", "do", "after"]).is_some();
    // "What happens now?", "and now what?", "what will the tree do now?",
    // "what do you plan to do after walking?".
    let past = ["did", "was", "were", "had", "happened"]
        .iter()
        .any(|w| s.has(w));
    let next = next
        || !past
            && (s.phrase(&["what", "happens"]).is_some()
                && (s.has("now") || s.has("then") || s.has("after"))
                || s.ends_with(&["now", "what"])
                // "Look around done, what now?": what comes after it ("doing
                // what rn" asks what it does).
                || !c.doing_words && s.ends_with(&["what", "now"])
                || s.has("will") && s.has("do") && c.what && !c.how
                || s.phrase(&["plan", "to", "do"]).is_some());
    // "How's it gonna do this step?": how it does the part, not what next.
    let how_a_part = c.how && s.has_stem(&["step", "part", "subgoal", "stage"]);
    (next && !how_a_part).then(|| vec![(Intent::Next, c.sure_of_words(0.93))])
}
