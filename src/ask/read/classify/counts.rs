//! How often, for how long and when a node did something.

use super::*;

/// An event as counted or timed: not running is counted as runs.
pub(super) fn counted(ev: Option<Event>) -> Event {
    match ev {
        Some(Event::NotRun) | Some(Event::Skipped) | None => Event::Run,
        Some(e) => e,
    }
}

/// "How often did X fail?".
pub(super) fn how_often(c: &Cues) -> Option<Readings> {
    let s = c.s;
    // "Spin attempts", "path clear checks": a node and what is counted,
    // typed with no verb.
    let tallied = verbless(s)
        && !c.why
        && !c.when_q
        && !c.named.is_empty()
        && (s.has("total")
            || s.q.last().is_some_and(|w| {
                [
                    "attempts",
                    "tries",
                    "retries",
                    "checks",
                    "runs",
                    "calls",
                    "executions",
                    "evaluations",
                ]
                .contains(&w.text.as_str())
            }));
    let often = s.phrase(&["how", "often"]).is_some()
        || s.phrase(&["how", "many"]).is_some()
        || s.phrase(&["how", "frequently"]).is_some()
        || s.phrase(&["number", "of"]).is_some()
        // Not "what counts as done?": what is taken for it.
        || s.has_stem(&["count", "quantifi"])
            && s.phrase(&["counts", "as"]).is_none()
            && s.phrase(&["count", "as"]).is_none()
        || s.has_stem(&["fraction", "percentag", "proport", "ratio"])
        || tallied;
    if !often || spell_asked(s) {
        return None;
    }
    // "What fraction of ticks was drive RUNNING?": the ticks it spent
    // running, not its starts.
    let event = if s.has_prefix(&["tick"]) && (s.has("was") || s.has("were")) && s.has("running") {
        Event::KeepRunning
    } else {
        counted(c.ev)
    };
    // "How often did the frobnicator run?": a count of something the tree
    // has no name for is asked back as the task's, not answered as sure.
    let Some(node) = c.subject() else {
        return Some(vec![(
            Intent::HowOften {
                node: Subject::Task,
                event,
            },
            c.sure(0.6),
        )]);
    };
    Some(vec![(Intent::HowOften { node, event }, c.sure(0.95))])
}

/// "How long did drive stay running?", "GD R for how long": the spells
/// of a node named running, each from its start to its end.
pub(super) fn how_long(c: &Cues) -> Option<Readings> {
    let s = c.s;
    // Of the run: "how long did it stay running", not "how long will the
    // motors last" or "how long is the warranty".
    let past = ["did", "was", "were", "running", "ran"]
        .iter()
        .any(|w| s.has(w))
        || s.has_stem(&["stay", "remain"]);
    let ahead = ["will", "until", "till", "would", "is", "does", "last"]
        .iter()
        .any(|w| s.has(w));
    let asked =
        !c.why && (s.phrase(&["how", "long"]).is_some() && past && !ahead || spell_asked(s));
    let node = c.subject().filter(|n| matches!(n, Subject::Nodes(..)))?;
    asked.then(|| {
        vec![(
            Intent::When {
                node,
                event: Event::KeepRunning,
                which: Which::Every,
            },
            c.sure(0.85),
        )]
    })
}

/// "The longest time trial and error insert stayed RUNNING", "on average,
/// how many ticks does one move action stay RUNNING?": a spell of running
/// measured, not a count of starts.
pub(super) fn spell_asked(s: &Sentence) -> bool {
    let stayed = s.has_stem(&["stay", "remain"]);
    (s.has("longest") || s.has("shortest") || s.has("average")) && (stayed || s.has("running"))
        || s.phrase(&["how", "many", "ticks"]).is_some() && stayed
}

/// "When did X first fail?".
pub(super) fn when_it_happened(c: &Cues) -> Option<Readings> {
    let s = c.s;
    // "When the retries ran out, what did the tree do about it?": the
    // "when" says which failure; what was done about it is asked.
    let done_about = s.phrase(&["do", "about"]).is_some() || s.phrase(&["done", "about"]).is_some();
    if !c.when_q || c.why || c.after_failure || c.how_handled || done_about {
        return None;
    }
    let node = c.subject();
    let named_or_event = matches!(node, Some(Subject::Nodes(..))) || c.ev.is_some();
    let (Some(node), true) = (node, named_or_event) else {
        return None;
    };
    let which = if s.has("first") || s.has("1st") || s.has("initially") {
        Which::First
    } else if s.has("last") || s.has("final") || s.has("finally") || s.has("latest") {
        Which::Last
    } else {
        Which::Every
    };
    let event = counted(c.ev);
    Some(vec![(Intent::When { node, event, which }, c.sure(0.95))])
}
