//! What a sentence asks, once its nodes and moment are found: the cue
//! words are read once (`Cues`), then each rule, in order, says what the
//! question asks or passes it on. The first rule that reads it wins; a
//! rule that returns no reading stops the rest (a why that names nothing
//! it could be about is no other question).

use super::cues::{Cues, Readings};
use super::{
    can_you, foil, gave_up, joined, loops_of, negated_first, progressive, uids_of, verbless, when,
    Mention, Sentence, When, NOT_A_VERB,
};
use crate::ask::parse::{Event, Intent, Subject, Which};
use crate::explain::{Question, RunQuestion, TreeQuestion};
use crate::model::{Tree, Uid};

/// The rules, in the order they are tried.
const RULES: &[fn(&Cues) -> Option<Readings>] = &[
    which_failed,
    can_you_asked,
    what_if,
    tick_by_number,
    all_well_in_few_words,
    handled_whether,
    anything_failed,
    recovered,
    how_often,
    when_it_happened,
    how_long,
    purpose,
    why_bare_verb,
    why,
    handled,
    next,
    what_went_wrong,
    anything_wrong,
    tick,
    goal_reached,
    task_outcome,
    how_achieved,
    subgoal_or_goal,
    which_of_two,
    doing,
    whether_it_happened,
    event_alone,
];

/// What a sentence asks: every reading, the best first.
pub(super) fn classify(s: &Sentence, tree: &Tree) -> Readings {
    let c = Cues::of(s, tree);
    RULES.iter().find_map(|rule| rule(&c)).unwrap_or_default()
}

/// "Which node failed?": what went wrong.
fn which_failed(c: &Cues) -> Option<Readings> {
    let s = c.s;
    ((s.has("which") || s.has("what"))
        && s.has_stem(&[
            "node", "step", "action", "part", "thing", "behavior", "leaf",
        ])
        && c.ev == Some(Event::Fail)
        && c.named.is_empty())
    .then(|| {
        vec![(
            Intent::Fixed(Question::Run(RunQuestion::WhatWentWrong)),
            c.sure_of_words(0.93),
        )]
    })
}

/// "Can you X?": the rest of the words are the behaviour.
fn can_you_asked(c: &Cues) -> Option<Readings> {
    let x = can_you(c.s, c.tree)?;
    c.only(Intent::Fixed(Question::CanYou(x)), 0.95)
}

/// "What if X fails?", "what would have happened if X had failed".
fn what_if(c: &Cues) -> Option<Readings> {
    let s = c.s;
    let conditional = s.phrase(&["what", "if"]).is_some()
        || s.phrase(&["happen", "if"]).is_some()
        || s.phrase(&["happens", "if"]).is_some()
        || s.phrase(&["happened", "if"]).is_some()
        || s.phrase(&["do", "if"]).is_some()
        || s.has("suppose")
        || s.has("supposing")
        || s.has("imagine")
        // "Had path clear returned SUCCESS, would …", "what would have
        // happened had X failed": the conditional put first.
        || c.first == "had"
        || s.has("had") && s.has("would")
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
        || (s.has("fails") || s.has("succeeds"))
            && (s.phrase(&["what", "happens"]).is_some()
                || s.phrase(&["what", "then"]).is_some()
                || s.phrase(&["then", "what"]).is_some())
        // "How would the run differ if look around had failed?", "say the
        // second move up had failed: then what?".
        || s.has("if") && (s.has("would") || s.has("had"))
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

/// The outcome said between a conditional's mark ("if", "had",
/// "suppose") and what is asked of it ("would", "what", "then").
fn supposed(s: &Sentence) -> Option<Event> {
    const MARK: &[&str] = &[
        "if",
        "had",
        "suppose",
        "supposing",
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

/// "Robot ok??", "something wrong?", "so far so good?": a few words asking
/// whether all is well.
fn all_well_in_few_words(c: &Cues) -> Option<Readings> {
    let s = c.s;
    // "Until now there is any problem?", "is all ok until here?".
    let so_far = s.phrase(&["so", "far"]).is_some()
        || s.phrase(&["until", "now"]).is_some()
        || s.phrase(&["until", "here"]).is_some()
        || s.phrase(&["till", "now"]).is_some()
        || s.phrase(&["up", "to", "this", "point"]).is_some()
        || s.phrase(&["up", "to", "now"]).is_some()
        // "All green through tick 2?": up to a tick said.
        || ["through", "until", "till", "to"]
            .iter()
            .any(|w| s.phrase(&[w, "tick"]).is_some());
    if (s.q.len() <= 3 || so_far)
        && (c.problem || c.fine)
        && c.named.is_empty()
        && !c.why
        && !c.what
    {
        return c.only(
            Intent::Fixed(Question::Run(RunQuestion::AnythingWrong)),
            0.9,
        );
    }
    None
}

/// "Was the failure handled?", "did the fallback take care of it?", "did
/// the agent cope?": whether a failure was handled is answered by how it
/// was (what handled it, and whether that worked).
fn handled_whether(c: &Cues) -> Option<Readings> {
    let s = c.s;
    let handle = s.has_stem(&["handl", "dealt", "cope", "mitig"])
        || s.phrase(&["deal", "with"]).is_some()
        || s.phrase(&["care", "of"]).is_some();
    let counted = s.phrase(&["how", "often"]).is_some() || s.phrase(&["how", "many"]).is_some();
    (handle
        && !c.why
        && !c.when_q
        && !counted
        && !s.has_prefix(&["recover"])
        && !of_a_goal_not_a_failure(c))
    .then(|| c.only(Intent::Fixed(Question::Run(RunQuestion::Handled)), 0.93))
    .flatten()
}

/// "Did anything fail (while patrolling)?": yes or no, whatever is named.
fn anything_failed(c: &Cues) -> Option<Readings> {
    let s = c.s;
    if c.yes_no
        && (s.has("anything") || s.has("something") || s.has("any") || s.has("everything"))
        && (c.problem || c.fine)
        && !c.why
        && !s.has_prefix(&["recover"])
    {
        return c.only(
            Intent::Fixed(Question::Run(RunQuestion::AnythingWrong)),
            0.93,
        );
    }
    None
}

/// A name that only says "the recovery" or "the retries".
fn generic(m: &Mention) -> bool {
    m.phrase.split_whitespace().all(|w| {
        [
            "the",
            "recovery",
            "recoveries",
            "recover",
            "recovered",
            "retry",
            "retries",
            "fallback",
            "behaviors",
            "behaviours",
            "actions",
            "node",
        ]
        .contains(&w)
    })
}

/// Did the recovery work?
fn recovered(c: &Cues) -> Option<Readings> {
    let s = c.s;
    let recovery_word = s.has_prefix(&["recover"])
        || s.nodes.iter().any(generic)
        || s.phrase(&["bounce", "back"]).is_some()
        || s.phrase(&["bounced", "back"]).is_some()
        // "Did it ever fail and come back from it?".
        || s.phrase(&["come", "back", "from"]).is_some()
        || s.phrase(&["came", "back", "from"]).is_some()
        || ["get", "got", "gotten", "getting"]
            .iter()
            .any(|g| s.phrase(&[g, "past"]).is_some())
        // "After look at chuck failed, did it still manage to insert the
        // large gear?": whether the task came through the failure.
        || s.has("still")
            && s.has_stem(&["manag"])
            && s.q.iter().any(|w| w.text == "after")
            && s.q.iter().any(|w| w.stem == "fail");
    let retry_word = s.has_prefix(&["retr", "fallback"]);
    // "Did clearing the costmap fix the failure?": whether it recovered.
    let fixed_it = s.has_stem(&["fix"])
        && (s.has("it") || s.has("that") || s.has("things") || c.yes_no && c.problem);
    // "Did it get going again after the controller gave up?".
    // "Is everything on track?" asks whether all is well; "back on track
    // after the failure?" whether it recovered.
    let on_track = s.phrase(&["on", "track"]).is_some()
        && (s.q.iter().any(|w| w.text == "back") || s.has("after") || c.problem)
        || s.phrase(&["back", "to", "normal"]).is_some()
        || s.phrase(&["going", "again"]).is_some() && s.has("after");
    if (!c.how || costed_after(s))
        && !c.why
        // "The retry box is lit - which subgoal is that?": the subgoal.
        && (!c.what || !asks_subgoal(c))
        // "Recoveries done, what comes next?", "RecoveryFallback is SUCCESS
        // at 6:12, and then what does it do" ask what comes next.
        && !s.has("next")
        && s.phrase(&["then", "what"]).is_none()
        // "L0 failed, but did the tree recover?": the question after "but".
        && (c.yes_no
            // "In the end, did the robot recover?".
            || (s.has("did") || s.has("has")) && !c.what && !c.when_q
            || s.has("manage")
            || s.has("managed")
            || c.first.starts_with("recover")
            || s.phrase(&["but", "did"]).is_some()
            // "It recovered or not, after this fail at tick 10?", "robot was
            // able to recover, or the mission failed finally?".
            || (s.has("recover") || s.has("recovered")) && !c.what && !c.when_q)
        && (recovery_word
            || fixed_it
            || on_track
            || retry_word && c.named.iter().all(|m| generic(m)))
        // "Did drive recover after being halted?": the verb asks.
        && (!matches!(c.ev, Some(Event::Halted | Event::Skipped | Event::NotRun))
            || s.has("recover")
            || s.has("recovered"))
        && (c.ev != Some(Event::Fail) || recovery_word || fixed_it || on_track)
    {
        return c.only(Intent::Recovered, 0.93);
    }
    None
}

/// "Did it recover after it failed at tick 10, and how many ticks did
/// getting back cost?": whether it recovered is asked first, what it cost
/// after it.
fn costed_after(s: &Sentence) -> bool {
    let at = |w: &str| s.free().position(|(_, x)| x.text == w);
    let recovery = s
        .free()
        .position(|(_, w)| w.text.starts_with("recover") || w.text == "back" || w.text == "track");
    let how = at("how");
    let costed = s.phrase(&["how", "many"]).is_some() || s.phrase(&["how", "long"]).is_some();
    costed && matches!((recovery, how), (Some(r), Some(h)) if r < h)
}

/// An event as counted or timed: not running is counted as runs.
fn counted(ev: Option<Event>) -> Event {
    match ev {
        Some(Event::NotRun) | Some(Event::Skipped) | None => Event::Run,
        Some(e) => e,
    }
}

/// "How often did X fail?".
fn how_often(c: &Cues) -> Option<Readings> {
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
fn how_long(c: &Cues) -> Option<Readings> {
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
fn spell_asked(s: &Sentence) -> bool {
    let stayed = s.has_stem(&["stay", "remain"]);
    (s.has("longest") || s.has("shortest") || s.has("average")) && (stayed || s.has("running"))
        || s.phrase(&["how", "many", "ticks"]).is_some() && stayed
}

/// "When did X first fail?".
fn when_it_happened(c: &Cues) -> Option<Readings> {
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

/// "This tree for, overall": the whole named, then "for" with no moment
/// or thing or deed after it ("the tree for tick 3", "the tree for
/// reaching the goal" are no purpose).
fn whole_for(s: &Sentence) -> bool {
    s.q.windows(2).enumerate().any(|(i, p)| {
        ["tree", "bt", "robot", "program", "system", "agent"].contains(&p[0].text.as_str())
            && p[1].text == "for"
            && s.q.get(i + 2).is_none_or(|n| {
                !["tick", "ticks", "step", "the", "a", "an", "each", "every", "this", "that"]
                    .contains(&n.text.as_str())
                    && n.text.parse::<u32>().is_err()
                    // "The strategy of the tree for reaching the goal".
                    && !n.text.ends_with("ing")
            })
    })
}

/// "What's the purpose of the thing you're doing now?", "what is L2 for?",
/// "whats the point of driving right now?": why it does what it does; the
/// whole's purpose ("big picture, what is it for?") is its goal.
fn purpose(c: &Cues) -> Option<Readings> {
    let s = c.s;
    let purpose = s.has_stem(&["purpos", "reason"])
        || s.phrase(&["point", "of"]).is_some()
        // "For what it runs the detect chuck action again?".
        || c.first == "for" && s.phrase(&["for", "what"]).is_some()
        // "CaseStudyFallback ultimately for what".
        || s.q.len() > 2 && s.ends_with(&["for", "what"])
        || c.what && s.q.last().is_some_and(|w| w.text == "for")
        // "What is this tree for, in plain words?".
        || c.what && s.phrase(&["for", "in"]).is_some() && s.phrase(&["this", "tree"]).is_some()
        // "What's this tree for, overall?", "whats this whole tree for, top
        // to bottom": what the whole is for, more said after.
        || c.what && whole_for(s);
    if !purpose || c.why {
        return None;
    }
    // "What is it running for?": the progressive says it runs now.
    let current = c.doing_words
        || s.has("now")
        || s.has("current")
        || s.has("running")
        || s.has_stem(&["action"]);
    // "What is this tree for?": the whole's purpose.
    let whole = c.whole || s.has("tree") || s.has("bt");
    // "What's the point of this robot?": the whole's, whatever it is doing.
    // "What is this taxi program for?" too.
    let of_the_agent = ["robot", "agent", "system", "program"].iter().any(|a| {
        s.phrase(&["of", "this", a]).is_some()
            || s.phrase(&["of", "the", a]).is_some()
            || s.has(a) && s.has("this")
    });
    if (whole && !current || of_the_agent) && c.named.is_empty() && !c.how {
        return c.only(Intent::Fixed(Question::Tree(TreeQuestion::Goal)), 0.9);
    }
    if matches!(c.ev, None | Some(Event::Run)) && (current || !c.named.is_empty()) {
        return c.only(Intent::Fixed(Question::Tree(TreeQuestion::Why)), 0.9);
    }
    None
}

/// "Why look around?": a bare verb after "why" asks why it does it.
fn why_bare_verb(c: &Cues) -> Option<Readings> {
    let s = c.s;
    let bare = s.q.first().is_some_and(|w| w.text == "why")
        && s.q
            .get(1)
            .is_some_and(|w| !NOT_A_VERB.contains(&w.text.as_str()));
    let contrast = s.has("instead") || s.phrase(&["rather", "than"]).is_some();
    (c.why && bare && !contrast && matches!(c.ev, None | Some(Event::Run)) && !c.named.is_empty())
        .then(|| {
            vec![(
                Intent::Fixed(Question::Tree(TreeQuestion::Why)),
                c.sure_of_words(0.85),
            )]
        })
}

/// A why: about a node's event, a contrast of two, or what it is doing.
/// A why that names nothing it could be about is read as nothing.
fn why(c: &Cues) -> Option<Readings> {
    if !c.why {
        return None;
    }
    Some(
        why_expected_actual(c)
            .or_else(|| why_with_a_clause(c))
            .or_else(|| why_not(c))
            .or_else(|| why_still_running(c))
            .or_else(|| why_doing_now(c))
            .or_else(|| why_of(c))
            .unwrap_or_default(),
    )
}

/// "Expected L1, got L2. Why?", "Actual: look at chuck FAILURE.
/// Expected: SUCCESS. Root cause?": a report of what was expected and
/// what happened. The why is about what happened, set against the node
/// expected where one is; "it" is the node that happened.
fn why_expected_actual(c: &Cues) -> Option<Readings> {
    const EXPECTED: &[&str] = &["expected", "expecting"];
    const ACTUAL: &[&str] = &["actual", "actually", "observed", "got", "saw"];
    let s = c.s;
    let marks: Vec<usize> = (0..s.q.len())
        .filter(|&i| !s.used[i])
        .filter(|&i| {
            [EXPECTED, ACTUAL]
                .iter()
                .any(|m| m.contains(&s.q[i].text.as_str()))
        })
        .collect();
    let mark = |of: &[&str]| {
        marks
            .iter()
            .copied()
            .find(|&i| of.contains(&s.q[i].text.as_str()))
    };
    // "Observed: BackUp never ran" needs no expectation said; "got" and
    // "saw" report only beside one.
    let actual = mark(ACTUAL)?;
    let expected = mark(EXPECTED);
    if expected.is_none() && !["actual", "observed"].contains(&s.q[actual].text.as_str()) {
        return None;
    }
    // A clause runs to the next mark of the other side ("actually saw
    // L2" is one).
    let expecting = |i: usize| EXPECTED.contains(&s.q[i].text.as_str());
    let clause = |from: usize| {
        from..marks
            .iter()
            .copied()
            .find(|&i| i > from && expecting(i) != expecting(from))
            .unwrap_or(s.q.len())
    };
    let first_in = |r: std::ops::Range<usize>| {
        c.named
            .iter()
            .copied()
            .find(|m| r.contains(&m.start) && !generic(m))
    };
    let happened = first_in(clause(actual))?;
    let done = Subject::Nodes(happened.uids.clone(), happened.phrase.clone());
    if let Some(e) = expected.and_then(|e| first_in(clause(e))) {
        if e.uids != happened.uids {
            let instead = Subject::Nodes(e.uids.clone(), e.phrase.clone());
            return Some(vec![(Intent::WhyNot { done, instead }, c.sure(0.9))]);
        }
    }
    // What happened is what the clause says happened, read as any
    // question's event is ("RUNNING again right after its FAILURE" ran).
    let only = clause(actual);
    let mut told = s.with_nodes(s.q, Vec::new());
    for (i, u) in told.used.iter_mut().enumerate() {
        *u |= !only.contains(&i);
    }
    let event = super::event(&told).0.or(c.ev).unwrap_or(Event::Run);
    let node = done;
    Some(vec![(
        Intent::Why {
            node,
            event,
            foil: None,
        },
        c.sure(0.9),
    )])
}

/// "Why didn't it X after Y failed": a why about X; the clause after
/// "after", "when" or "once" only says when.
fn why_with_a_clause(c: &Cues) -> Option<Readings> {
    let s = c.s;
    let named = &c.named;
    if named.len() < 2 {
        return None;
    }
    let cut = s.q[named[0].end..named[1].start]
        .iter()
        .position(|w| {
            ["after", "when", "once", "while", "since", "because"].contains(&w.text.as_str())
        })
        .map(|i| i + named[0].end)?;
    let mut main = Sentence {
        q: s.q,
        tree_words: s.tree_words,
        used: s.used.clone(),
        nodes: s.nodes.iter().filter(|m| m.end <= cut).cloned().collect(),
    };
    for u in &mut main.used[cut..] {
        *u = true;
    }
    Some(classify(&main, c.tree))
}

/// "Why X and not Y", "why X instead of Y": two nodes.
fn why_not(c: &Cues) -> Option<Readings> {
    let s = c.s;
    let not_between = c.named.len() >= 2
        && s.q[c.named[0].end..c.named[1].start]
            .iter()
            .any(|w| w.text == "not" || w.text == "never");
    // "Why was X never executed even though the controller failed?": what
    // is granted is no side of a contrast.
    let granted = s.phrase(&["even", "though"]).is_some()
        || s.has("although")
        || s.has("despite")
        || s.phrase(&["even", "if"]).is_some();
    let contrast = s.phrase(&["instead", "of"]).is_some()
        // "Why is L2 done here instead L1?".
        || s.has("instead") && c.named.len() >= 2
        || s.phrase(&["rather", "than"]).is_some()
        || not_between && !granted
        || s.has("over")
        || s.has("vs")
        || s.has("versus");
    if !contrast {
        return None;
    }
    let named = sides(c);
    // A node is never contrasted with itself ("why was the path not
    // clear" names path clear twice).
    if named.len() < 2 || named[0].uids == named[1].uids {
        return None;
    }
    let done = Subject::Nodes(named[0].uids.clone(), named[0].phrase.clone());
    let (uids, phrase) = alternatives(s, &named[1..]);
    let instead = Subject::Nodes(uids, phrase);
    let (done, instead) = if negated_first(s, named[0], named[1]) {
        (instead, done)
    } else {
        (done, instead)
    };
    Some(vec![(Intent::WhyNot { done, instead }, c.sure(0.93))])
}

/// "Rather than spin or back up": the nodes named one after another,
/// joined by "or" or "and", as one side; their uids and words.
fn alternatives(s: &Sentence, named: &[&Mention]) -> (Vec<Uid>, String) {
    let run = joined(s, named);
    let phrase = run
        .iter()
        .map(|m| m.phrase.as_str())
        .collect::<Vec<_>>()
        .join(" or ");
    (uids_of(&run), phrase)
}

/// The nodes a contrast may set against each other, in the order named:
/// the mentions, less a place the question is asked in, "retry" said of
/// the node after it, and the node that chose between the two.
fn sides<'a>(c: &Cues<'a, '_>) -> Vec<&'a Mention> {
    // "Why did the whole patrol fail rather than just the drive?": the
    // task itself may be one side of a contrast.
    let s = c.s;
    let named: Vec<&Mention> = if c.named.len() < 2 && s.nodes.len() >= 2 {
        s.nodes.iter().collect()
    } else {
        c.named.clone()
    };
    // "In the FollowPath recovery fallback, why did GoalUpdated get
    // checked instead of …": a place before the question is no side.
    let mut named = named;
    if named.len() >= 3
        && named[0].start > 0
        && named[0].start <= 2
        && ["in", "inside", "under", "within"].contains(&s.q[named[0].start - 1].text.as_str())
    {
        named.remove(0);
    }
    // "After FollowPath failed at tick 4, why did the fallback succeed via
    // GoalUpdated rather than …": a node told before the question word,
    // where two are named after it, is the story's, no side.
    if let Some(w) = s.q.iter().position(|w| w.text == "why") {
        if named.iter().filter(|m| m.start > w).count() >= 2 {
            named.retain(|m| m.start > w);
        }
    }
    // "Rather than retry FollowPath", "why retry the spin": "retry" says
    // what was done to the node after it, not the Retry decorator.
    let verb = |m: &Mention| ["retry", "retrying", "retried", "rerun"].contains(&m.phrase.as_str());
    let next_to = |a: &Mention, b: &Mention| {
        b.start >= a.end && s.q[a.end..b.start].iter().all(|w| w.text == "the")
    };
    let retried: Vec<usize> = (0..named.len().saturating_sub(1))
        .filter(|&k| verb(named[k]) && next_to(named[k], named[k + 1]))
        .collect();
    for k in retried.into_iter().rev() {
        named.remove(k);
    }
    // "Why did the recovery fallback end with GoalUpdated instead of
    // running the recoveries?", "why did the fallback pick L2 over L1?":
    // the node that chose is no side; what it chose is.
    if named.len() >= 3 {
        let gap = &s.q[named[0].end..named[1].start];
        let chose = gap.iter().any(|w| {
            [
                "end", "finish", "pick", "choos", "chose", "select", "go", "settl", "prefer",
                "take", "opt", "run", "tick", "execut", "call", "tri", "succeed", "use",
            ]
            .contains(&w.stem.as_str())
                || ["through", "via", "by"].contains(&w.text.as_str())
        });
        let apart = gap.iter().any(|w| {
            ["not", "never", "instead", "rather", "and", "or", "than"].contains(&w.text.as_str())
        });
        if chose && !apart {
            named.remove(0);
        }
    }
    named
}

/// "Why is FollowPath still running?": a node named as running on.
fn why_still_running(c: &Cues) -> Option<Readings> {
    // "Why is it still walking?", the node named by its verb, asks why it
    // does what it does (Han's Q2), as "why is it walking?".
    let named_by_verb = c.named.iter().any(|m| {
        c.s.q[m.start..m.end]
            .iter()
            .any(|w| w.text.len() > 4 && w.text.ends_with("ing"))
    }) && !c.s.has("running")
        && !c.s.has("going");
    let still = c.s.has("still") && progressive(c.s) && !named_by_verb;
    // "Why does drive keep running for several ticks?".
    let keeps = c.ev == Some(Event::KeepRunning)
        && (c.s.phrase(&["keep", "running"]).is_some()
            || c.s.phrase(&["keeps", "running"]).is_some());
    if !((still || keeps) && !c.named.is_empty()) {
        return None;
    }
    let node = c.subject()?;
    Some(vec![(
        Intent::Why {
            node,
            event: Event::KeepRunning,
            foil: None,
        },
        c.sure(0.9),
    )])
}

/// "Why is it looking at the chuck?", "why drop the passenger off now?":
/// why it is doing what it does.
fn why_doing_now(c: &Cues) -> Option<Readings> {
    let s = c.s;
    let now = s.has("now") && !["did", "was", "were", "had"].iter().any(|w| s.has(w));
    // "Why does it look at the chuck roughly again?": the present of a
    // node named, as "why is it looking at …".
    let present = (s.phrase(&["why", "does"]).is_some()
        // "Why it runs the CaseStudySequence at the moment?".
        || s.phrase(&["why", "it"]).is_some() && c.now_words)
        && !c.named.is_empty()
        && c.ev.is_none();
    ((progressive(s) || now || present)
        && matches!(c.ev, None | Some(Event::Run) | Some(Event::KeepRunning)))
    .then(|| {
        vec![(
            Intent::Fixed(Question::Tree(TreeQuestion::Why)),
            c.sure_of_words(0.93),
        )]
    })
}

/// "Why did X fail?", "why did it stop?", "why is it doing this?".
fn why_of(c: &Cues) -> Option<Readings> {
    let s = c.s;
    let Some(node) = c.subject() else {
        return (s.has("doing") || s.has("this") || s.has("that"))
            .then(|| c.only(Intent::Fixed(Question::Tree(TreeQuestion::Why)), 0.9))
            .flatten();
    };
    let doing_this =
        matches!(node, Subject::It) && (s.has("doing") || s.has("this") && c.ev.is_none());
    if doing_this && c.ev.is_none() {
        return c.only(Intent::Fixed(Question::Tree(TreeQuestion::Why)), 0.95);
    }
    let node = match node {
        Subject::Nodes(us, p) if gave_up(s) => match loops_of(c.tree, &us) {
            Some(loops) => Subject::Nodes(loops, p),
            None => Subject::Nodes(us, p),
        },
        other => other,
    };
    let event = match c.ev {
        Some(e) => e,
        None if c.negated => Event::NotRun,
        None => Event::Run,
    };
    let base = if c.ev.is_some() || matches!(node, Subject::Nodes(..)) {
        0.95
    } else {
        0.6
    };
    let mut out = vec![(
        Intent::Why {
            node,
            event,
            foil: foil(s),
        },
        c.sure(base),
    )];
    if matches!(event, Event::Fail) {
        out.push((
            Intent::Fixed(Question::Run(RunQuestion::WhatWentWrong)),
            0.3,
        ));
    }
    Some(out)
}

/// How was it handled?
fn handled(c: &Cues) -> Option<Readings> {
    let s = c.s;
    let handle = s.has_stem(&[
        "handl", "deal", "dealt", "respond", "respons", "react", "cope", "mitig", "recov",
        "recoveri", "fix", "fixed", "past", "overcom", "surviv",
    ]) || s.has_prefix(&["recover", "handl"]);
    // "How is it going to achieve the subgoal now that the sequence
    // failed?": how the (sub)goal is reached, the failure its occasion.
    let achieving = s.has_stem(&["achiev", "accomplish"]) && s.has_stem(&["goal", "subgoal"]);
    if achieving && !handle {
        return None;
    }
    if of_a_goal_not_a_failure(c) {
        return None;
    }
    if (c.how && (handle || c.problem && !s.has("often") && !s.has("many")))
        || c.how_handled && !c.why
        || c.after_failure
        || s.phrase(&["do", "about"]).is_some()
        || s.phrase(&["did", "about"]).is_some()
        || s.phrase(&["done", "about"]).is_some()
        || (c.what
            && s.has_prefix(&["recover"])
            && c.named.is_empty()
            && !asks_steps(c)
            && !s.has("next"))
    {
        return c.only(Intent::Fixed(Question::Run(RunQuestion::Handled)), 0.93);
    }
    None
}

/// What next?
fn next(c: &Cues) -> Option<Readings> {
    let s = c.s;
    let next = s.has("next")
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
    next.then(|| vec![(Intent::Next, c.sure_of_words(0.93))])
}

/// "What went wrong?", and "what made look at chuck fail?" (a why).
fn what_went_wrong(c: &Cues) -> Option<Readings> {
    let s = c.s;
    if !(c.problem && (c.what || s.empty() || s.has("where")) && !c.yes_no) {
        return None;
    }
    let asked_when = when::find(s.q);
    if asks_past_a_told_failure(s, asked_when.is_some()) {
        return None;
    }
    // "What failed in goal 1 - planner or controller?": which did is
    // what went wrong, not why one did.
    // "Tell me what failed earlier, the controller?" asks the same.
    let what_failed = ["failed", "broke", "crashed"]
        .iter()
        .any(|v| s.phrase(&["what", v]).is_some());
    let either = c.what && (s.has("or") || what_failed) && !c.why;
    let (told_first, told_after) = failure_told(c);
    if !c.named.is_empty()
        && c.ev == Some(Event::Fail)
        && asked_when.is_none()
        && !either
        && !told_first
        && !told_after
    {
        let node = c.subject().unwrap_or(Subject::Task);
        return Some(vec![(
            Intent::Why {
                node,
                event: Event::Fail,
                foil: None,
            },
            c.sure(0.85),
        )]);
    }
    Some(vec![
        (
            Intent::Fixed(Question::Run(RunQuestion::WhatWentWrong)),
            c.sure_of_words(0.95),
        ),
        (
            Intent::Fixed(Question::Run(RunQuestion::AnythingWrong)),
            0.3,
        ),
    ])
}

/// Whether what follows the last "what" asks past a failure the text
/// tells: "@2 (FP F, CLC S) - what happened exactly" (what happened at
/// that moment), "L0 just went red, what subgoal was it on?".
fn asks_past_a_told_failure(s: &Sentence, moment_said: bool) -> bool {
    let Some((what, _)) = s.free().filter(|(_, w)| w.text == "what").last() else {
        return false;
    };
    let asks_a_problem = |from: usize| {
        s.free()
            .any(|(i, w)| i > from && super::cues::PROBLEM.contains(&w.stem.as_str()))
    };
    if moment_said
        && what > 0
        && !asks_a_problem(what)
        && s.q[what + 1..].iter().any(|w| w.stem == "happen")
    {
        return true;
    }
    let told = s.q[..what]
        .iter()
        .any(|w| w.stem == "fail" || w.text == "failure");
    let asks_else = s.q[what + 1..].iter().any(|w| {
        ["subgoal", "goal", "doing", "next", "comes", "up", "purpose"].contains(&w.text.as_str())
    });
    let happened = s.free().any(|(i, w)| i > what && w.stem == "happen");
    what > 0 && told && !asks_a_problem(what) && !happened && asks_else
}

/// Whether a failure is told before what went wrong is asked ("FP F x2 -
/// what went wrong?"), or after it ("what went wrong, L0 is red"): what
/// went wrong is asked of the whole, not why that node failed.
fn failure_told(c: &Cues) -> (bool, bool) {
    let s = c.s;
    let told_first = s
        .free()
        .find(|(_, w)| w.text == "what")
        .is_some_and(|(what, _)| {
            c.named.iter().all(|m| m.end <= what)
                && s.q[..what]
                    .iter()
                    .any(|w| w.stem == "fail" || w.text == "failure")
        });
    let told_after = s.q.len() > 3
        && s.q[..3]
            .iter()
            .map(|w| w.text.as_str())
            .eq(["what", "went", "wrong"])
        && c.named.first().is_some_and(|m| {
            m.start == 3
                && s.q
                    .get(m.end)
                    .is_some_and(|w| ["is", "was"].contains(&w.text.as_str()))
        });
    (told_first, told_after)
}

/// "How does it handle the subgoal it's on?": how a goal is done, no
/// failure said.
fn of_a_goal_not_a_failure(c: &Cues) -> bool {
    c.s.has_stem(&["subgoal", "goal", "mission", "object"]) && !c.problem && !c.after_failure
}

/// "Any problems?": yes or no.
fn anything_wrong(c: &Cues) -> Option<Readings> {
    ((c.yes_no || c.s.has("any")) && (c.problem || c.fine) && c.named.is_empty()).then(|| {
        vec![
            (
                Intent::Fixed(Question::Run(RunQuestion::AnythingWrong)),
                c.sure_of_words(0.93),
            ),
            (
                Intent::Fixed(Question::Run(RunQuestion::WhatWentWrong)),
                0.3,
            ),
        ]
    })
}

/// "What happened in tick 4, right before the failure?", "tell me about
/// tick 6, the first time detection failed": a tick asked by its number,
/// right after the words that ask it; what follows says which it is.
fn tick_by_number(c: &Cues) -> Option<Readings> {
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
fn tick(c: &Cues) -> Option<Readings> {
    let s = c.s;
    let asked_when = when::find(s.q).map(|(w, _)| w);
    // "The tick where the spin failed": the moment is that failure's.
    let this_tick = s.phrase(&["this", "tick"]).is_some()
        || s.phrase(&["that", "tick"]).is_some()
        || s.phrase(&["current", "tick"]).is_some()
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
    let n = match asked_when {
        Some(When::Tick(n) | When::Step(n, _)) => n,
        _ => 0,
    };
    let walk = s.phrase(&["walk", "me", "through"]).is_some()
        || s.phrase(&["walk", "through"]).is_some()
        || s.phrase(&["went", "on"]).is_some()
        // "Tick 1 step by step".
        || s.phrase(&["step", "by", "step"]).is_some()
        || c.break_down;
    // "What went on", not "what went wrong"; "describe how it pursues its
    // subgoal at tick 5" asks how, not what happened.
    let asks_other = s.has_stem(&["achiev", "accomplish", "pursu"])
        && s.has_stem(&["goal", "subgoal"])
        || s.phrase(&["went", "wrong"]).is_some();
    let asks_tick = (s.has_stem(&[
        "happen", "chang", "occur", "describ", "summar", "show", "transit", "detail", "explain",
        "event", "recap", "memori", "episod", "summaris", "summariz",
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

/// "Did the robot still make it to the goal after the failures?": whether
/// the run came through; "at which tick did the goal get reached?": when
/// the task succeeded.
fn goal_reached(c: &Cues) -> Option<Readings> {
    let s = c.s;
    let reached = s.has_stem(&["reach", "arriv"])
        || s.phrase(&["make", "it"]).is_some()
        || s.phrase(&["get", "to"]).is_some()
        || s.phrase(&["got", "to"]).is_some();
    if !(reached && s.has_stem(&["goal", "destin", "target"]) && c.named.is_empty()) {
        return None;
    }
    if c.yes_no {
        return c.only(Intent::Recovered, 0.9);
    }
    c.when_q.then(|| {
        vec![(
            Intent::When {
                node: Subject::Task,
                event: Event::Succeed,
                which: Which::Every,
            },
            c.sure_of_words(0.85),
        )]
    })
}

/// "Did the task succeed?", "did the robot finish the job?": whether the
/// run came through, asked of the task, not what its goal is.
fn task_outcome(c: &Cues) -> Option<Readings> {
    let outcome = matches!(c.ev, Some(Event::Succeed | Event::Fail | Event::Finish));
    (c.yes_no
        && outcome
        && !c.why
        && c.named.is_empty()
        && c.s.has_stem(&["task", "mission", "job", "run"]))
    .then(|| {
        vec![(
            Intent::When {
                node: Subject::Task,
                event: c.ev.unwrap_or(Event::Finish),
                which: Which::Every,
            },
            c.sure_of_words(0.9),
        )]
    })
}

/// The words that name a part of the task: "the immediate objective",
/// "what part of the mission", "which phase of the patrol is underway?",
/// "which branch is it in", "at this stage (the current chunk)".
fn asks_subgoal(c: &Cues) -> bool {
    let s = c.s;
    let part = s.has_stem(&["immedi"]) || s.phrase(&["part", "of"]).is_some();
    let stage = s.has_stem(&["phase", "stage", "branch", "chunk", "leg", "portion"])
        || s.phrase(&["this", "level"]).is_some()
        || s.phrase(&["higher", "level"]).is_some()
        || (c.what || s.has("which")) && s.has("part") && !s.has("how");
    s.has_stem(&["subgoal", "subtask", "milestone"])
        || part && s.has_stem(&["goal", "object", "mission", "task", "job", "aim"])
        || s.phrase(&["sub", "goal"]).is_some()
        || s.phrase(&["sub", "task"]).is_some()
        || s.phrase(&["intermediate", "goal"]).is_some()
        || s.phrase(&["current", "step"]).is_some()
        // "Which step of the patrol is it on?".
        || s.has("which") && s.has_stem(&["step"]) && s.has("on")
        || stage && c.named.is_empty() && (c.what || s.has("which"))
        || where_it_is(c)
}

/// "What step is it on at the moment?", "which big step of the kit is it
/// on?", "what chunk of the work is it on?": the part of the task it is
/// in, not the steps of one.
fn where_it_is(c: &Cues) -> bool {
    let s = c.s;
    let part = s.has_stem(&[
        "step", "part", "chunk", "stage", "phase", "bit", "section", "leg",
    ]);
    // "Is it on the pickup leg or the drop-off leg?": which of the parts.
    let which = c.what || s.has("which") || s.has("or");
    let on = ["it", "you", "robot", "we"]
        .iter()
        .any(|who| s.phrase(&[who, "on"]).is_some() || s.phrase(&[who, "in"]).is_some())
        || s.phrase(&["working", "on"]).is_some();
    which && part && on
}

fn asks_goal(s: &Sentence) -> bool {
    s.has_stem(&[
        "goal", "object", "mission", "aim", "purpos", "task", "intent", "job", "target",
    ]) || s.phrase(&["trying", "to"]).is_some()
        || s.phrase(&["try", "to"]).is_some()
        // Not "which city is this grid supposed to be": what it is, not
        // what it is for.
        || s.phrase(&["supposed", "to"]).is_some() && !ends_being(s, "supposed")
        || s.phrase(&["meant", "to"]).is_some() && !ends_being(s, "meant")
        || s.phrase(&["working", "towards"]).is_some()
        || s.phrase(&["working", "toward"]).is_some()
        || s.phrase(&["get", "done"]).is_some()
        || s.has_stem(&["achiev", "accomplish"])
}

/// "… supposed to be" with nothing after it.
fn ends_being(s: &Sentence, verb: &str) -> bool {
    let free: Vec<&str> = s.free().map(|(_, w)| w.text.as_str()).collect();
    free.ends_with(&[verb, "to", "be"])
}

fn asks_steps(c: &Cues) -> bool {
    let s = c.s;
    // "At this step": a moment, not the steps.
    // "At step 6": a moment too.
    let this_step = ["this", "that", "current", "which"]
        .iter()
        .any(|w| s.phrase(&[w, "step"]).is_some())
        || s.free().any(|(i, w)| {
            w.text == "step"
                && s.q
                    .get(i + 1)
                    .is_some_and(|n| n.text.bytes().all(|b| b.is_ascii_digit()))
        });
    !s.has("doing")
        && !this_step
        && !where_it_is(c)
        && s.has_stem(&[
            "step", "plan", "procedur", "strategi", "approach", "outlin", "recip", "method",
            "mechan", "breakdown",
        ])
        || s.has("means")
        || s.phrase(&["walk", "me", "through"]).is_some()
        || c.break_down
        // "What does the tree do to get it done?": the steps to it.
        || c.what && s.phrase(&["do", "to"]).is_some()
        || (c.how
            && s.has_stem(&[
                "do",
                "get",
                "complet",
                "go",
                "make",
                "finish",
                "build",
                "work",
                "achiev",
                "accomplish",
                "reach",
            ]))
}

/// "How do you achieve your (sub)goal?", "outline the steps".
fn how_achieved(c: &Cues) -> Option<Readings> {
    let steps = asks_steps(c);
    // "Top level plan", "this subgoal - steps to finish it": steps of a
    // goal named, typed with no verb, are asked for.
    let goal_named = c.s.nodes.iter().any(|m| m.uids == [c.root]);
    let of_a_goal = asks_subgoal(c) || asks_goal(c.s) || c.whole || goal_named;
    let listed = steps
        && (c.what
            || c.s.empty()
            || ["outline", "walk", "breakdown"].contains(&c.first)
            || verbless(c.s) && of_a_goal && !c.why);
    if !c.how && !listed {
        return None;
    }
    // "How does it achieve what it's working on now?", "how does it
    // achieve the watch and walk bit?": the part it is in, or a part named.
    let now = c.now_words && !c.whole && c.named.is_empty();
    let part_named =
        matches!(&c.named[..], [m] if m.uids.iter().all(|&u| !c.tree.node(u).kind.is_leaf()));
    // "How does it achieve its goal, subgoal by subgoal?", "through which
    // subgoals does it reach its goal?": the subgoals are how the goal is.
    let by_subgoals = c.s.has("subgoals") || c.s.phrase(&["subgoal", "by", "subgoal"]).is_some();
    if by_subgoals && (asks_goal(c.s) || c.whole) && (steps || c.how) {
        return c.only(Intent::Fixed(Question::Tree(TreeQuestion::HowGoal)), 0.93);
    }
    if (asks_subgoal(c) || now || part_named && c.how && !goal_named) && (steps || c.how) {
        return c.only(
            Intent::Fixed(Question::Tree(TreeQuestion::HowSubgoal)),
            0.93,
        );
    }
    if (asks_goal(c.s) || c.whole || goal_named) && (steps || c.how) {
        return c.only(Intent::Fixed(Question::Tree(TreeQuestion::HowGoal)), 0.93);
    }
    steps.then(|| {
        vec![
            (
                Intent::Fixed(Question::Tree(TreeQuestion::HowSubgoal)),
                c.sure_of_words(0.85),
            ),
            (Intent::Fixed(Question::Tree(TreeQuestion::HowGoal)), 0.4),
        ]
    })
}

/// "What is your subgoal?", "what is your goal?".
fn subgoal_or_goal(c: &Cues) -> Option<Readings> {
    let s = c.s;
    if asks_subgoal(c) {
        return c.only(Intent::Fixed(Question::Tree(TreeQuestion::Subgoal)), 0.95);
    }
    if !asks_goal(s) || s.has("doing") {
        return None;
    }
    let trying = s.phrase(&["trying", "to"]).is_some() || s.phrase(&["try", "to"]).is_some();
    // "Trying to do on goal 1": the run named by its goal, whose goal it is.
    let named_goal = s.has_stem(&["goal", "object", "mission", "purpos", "job", "target"])
        || s.q
            .windows(2)
            .any(|p| p[0].text == "goal" && p[1].text.bytes().all(|b| b.is_ascii_digit()));
    // "What's the goal here?" names the goal; "what is it trying to get
    // done here" the part it is in.
    // "Manager here, what is it supposed to accomplish?": who asks, not
    // where the robot is.
    let introduced = s.q.len() > 2
        && s.q[1].text == "here"
        && ![
            "what", "is", "are", "why", "how", "which", "where", "and", "so",
        ]
        .contains(&s.q[0].text.as_str());
    let here_said =
        s.q.iter()
            .enumerate()
            .any(|(i, w)| w.text == "here" && !(introduced && i == 1));
    let here = c.now_words
        || (here_said || s.phrase(&["this", "point"]).is_some()) && !s.has_stem(&["goal"]);
    // "What is it trying to achieve?", with neither "now" nor "in the
    // end": the whole task's goal, or that of the part it is in. Both are
    // read, and asked back.
    if trying && !named_goal && !here && !c.whole {
        return Some(vec![
            (
                Intent::Fixed(Question::Tree(TreeQuestion::Goal)),
                c.sure_of_words(0.65),
            ),
            (Intent::Fixed(Question::Tree(TreeQuestion::Subgoal)), 0.6),
        ]);
    }
    let q = if here && !c.whole {
        TreeQuestion::Subgoal
    } else {
        TreeQuestion::Goal
    };
    // "Navigation fails even though the robot reaches the goal", "the
    // GoalUpdated condition cannot halt …": a goal said beside an event or
    // another node is likely not the question of what the goal is.
    let beside = !c.named.is_empty()
        || c.when_q
        || s.has_stem(&["fail", "reach", "arriv", "halt", "abort", "cancel"])
        // "Does the goal still succeed?", "what happens to the goal?": what
        // becomes of the goal, not what it is.
        || s.has_stem(&["succeed", "success"])
        || s.phrase(&["happens", "to"]).is_some()
        || s.phrase(&["happen", "to"]).is_some();
    let base = if beside { 0.6 } else { 0.9 };
    let mut out = vec![(Intent::Fixed(Question::Tree(q)), c.sure_of_words(base))];
    if beside && c.problem {
        out.push((
            Intent::Fixed(Question::Run(RunQuestion::WhatWentWrong)),
            0.5,
        ));
    }
    if beside {
        let other = if q == TreeQuestion::Goal {
            TreeQuestion::HowGoal
        } else {
            TreeQuestion::HowSubgoal
        };
        out.push((Intent::Fixed(Question::Tree(other)), 0.4));
    }
    Some(out)
}

/// "Is it planning or driving right now?": which of two it is doing.
fn which_of_two(c: &Cues) -> Option<Readings> {
    let either = c.named.len() == 2
        && c.yes_no
        && c.ev.is_none()
        && c.s.q[c.named[0].end..c.named[1].start]
            .iter()
            .all(|w| ["or", "the", "a", "an"].contains(&w.text.as_str()));
    either.then(|| c.only(Intent::Fixed(Question::Tree(TreeQuestion::Doing)), 0.9))?
}

/// "What are you doing?".
fn doing(c: &Cues) -> Option<Readings> {
    let s = c.s;
    let doing = c.doing_words
        || s.has_stem(&["happen", "run", "execut", "act", "action", "behavior"])
        || s.has_prefix(&["doin"]);
    // "What is it doing now, looking at the chuck again?": the names are
    // the asker's guess; the question is what it does.
    // "Guarded drive went orange, what is the robot up to": the names are
    // a story told first.
    let guessed = (s.has("doing") || s.has("tip") || s.phrase(&["up", "to"]).is_some())
        && c.what
        && !c.why
        && !c.how;
    // "Doing @ t30?": the chat's shorthand.
    let bare = c.first == "doing" && c.named.is_empty() && !c.why && !c.how;
    // "Running node?", not "NR running -> halted": a node said running.
    let opens = ["current", "active", "running"].contains(&c.first)
        && s.q.first().is_some_and(|w| w.text == c.first);
    (doing && (c.what || s.empty() || opens || bare) && (c.named.is_empty() || guessed))
        .then(|| c.only(Intent::Fixed(Question::Tree(TreeQuestion::Doing)), 0.93))?
}

/// "Did the planner run?", "has follow path failed": whether, and how often.
fn whether_it_happened(c: &Cues) -> Option<Readings> {
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
fn event_alone(c: &Cues) -> Option<Readings> {
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
