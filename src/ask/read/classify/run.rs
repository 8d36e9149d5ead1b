//! Whether and how the run went: what went wrong, whether anything did,
//! whether and how a failure was handled and recovered, whether the task
//! came through.

use super::*;

/// "Which node failed?": what went wrong.
pub(super) fn which_failed(c: &Cues) -> Option<Readings> {
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

/// "Robot ok??", "something wrong?", "so far so good?": a few words asking
/// whether all is well.
pub(super) fn all_well_in_few_words(c: &Cues) -> Option<Readings> {
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
        // "How were faults handled so far?" asks how, not whether.
        && !c.how
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
pub(super) fn handled_whether(c: &Cues) -> Option<Readings> {
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
        && !of_a_goal_not_a_failure(c)
        && !does_a_part(c))
    .then(|| c.only(Intent::Fixed(Question::Run(RunQuestion::Handled)), 0.93))
    .flatten()
}

/// "How does it handle picking up the screw?", "how does it handle the
/// bit it's on right now?": how it does a part, no failure said.
fn does_a_part(c: &Cues) -> bool {
    let s = c.s;
    c.how
        && (s.has("does") || s.has("do"))
        && s.has_prefix(&["handl"])
        && !c.problem
        && !c.after_failure
        && !s.has_prefix(&["recover"])
}

/// "Did anything fail (while patrolling)?": yes or no, whatever is named.
pub(super) fn anything_failed(c: &Cues) -> Option<Readings> {
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
pub(super) fn generic(m: &Mention) -> bool {
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

/// "Did it bounce back?", whatever node "back" may start the name of
/// ("back to approach pose"); "bounced back to planning" went back.
fn bounced_back(s: &Sentence) -> bool {
    s.q.windows(2).enumerate().any(|(i, p)| {
        ["bounce", "bounced", "bounces"].contains(&p[0].text.as_str())
            && p[1].text == "back"
            && s.q.get(i + 2).is_none_or(|w| w.text != "to")
    })
}

/// Did the recovery work?
pub(super) fn recovered(c: &Cues) -> Option<Readings> {
    let s = c.s;
    let recovery_word = s.has_prefix(&["recover"])
        || s.nodes.iter().any(generic)
        || bounced_back(s)
        // "Did it ever fail and come back from it?".
        || s.phrase(&["come", "back", "from"]).is_some()
        || s.phrase(&["came", "back", "from"]).is_some()
        || ["get", "got", "gotten", "getting"]
            .iter()
            .any(|g| s.phrase(&[g, "past"]).is_some() || s.phrase(&[g, "over"]).is_some())
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
        // "After that failure" may be read as the moment: its words count.
        || s.phrase(&["going", "again"]).is_some() && s.q.iter().any(|w| w.text == "after");
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
            // "Confirm recovery from CaseStudySequence failure.".
            || s.q.first().is_some_and(|w| ["confirm", "verify"].contains(&w.text.as_str()))
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
pub(super) fn costed_after(s: &Sentence) -> bool {
    let at = |w: &str| s.free().position(|(_, x)| x.text == w);
    let recovery = s
        .free()
        .position(|(_, w)| w.text.starts_with("recover") || w.text == "back" || w.text == "track");
    let how = at("how");
    let costed = s.phrase(&["how", "many"]).is_some() || s.phrase(&["how", "long"]).is_some();
    costed && matches!((recovery, how), (Some(r), Some(h)) if r < h)
}

/// How was it handled?
pub(super) fn handled(c: &Cues) -> Option<Readings> {
    let s = c.s;
    let handle = s.has_stem(&[
        "handl", "deal", "dealt", "respond", "respons", "react", "cope", "mitig", "recov",
        "recoveri", "fix", "fixed", "past", "overcom", "surviv",
    ]) || s.has_prefix(&["recover", "handl"]);
    // "How is it going to achieve the subgoal now that the sequence
    // failed?": how the (sub)goal is reached, the failure its occasion.
    // "How does it get its subgoal done if Spin keeps failing?" too.
    let get_done = s.has("done") && ["get", "gets", "getting"].iter().any(|g| s.has(g));
    let achieving =
        (s.has_stem(&["achiev", "accomplish"]) || get_done) && s.has_stem(&["goal", "subgoal"]);
    if achieving && !handle {
        return None;
    }
    if of_a_goal_not_a_failure(c) || does_a_part(c) || a_chain_of_failures(s) && !handle {
        return None;
    }
    if (c.how && (handle || c.problem && !s.has("often") && !s.has("many")))
        || c.how_handled && !c.why
        || c.after_failure
        || s.phrase(&["do", "about"]).is_some()
        || s.phrase(&["did", "about"]).is_some()
        // "What's it doing about the failure just now?".
        || s.phrase(&["doing", "about"]).is_some() && c.problem
        // "Copy FollowPath fault at tick 4. What action taken?",
        // "detect chuck failed three times. Response?".
        || c.problem && !c.why && !c.when_q && answered_by_action(s)
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

/// "What failed here and how one failure led to the next?", "why it
/// cascaded upwards": how the failures followed one from another, which
/// is what went wrong, not how it was handled.
pub(super) fn a_chain_of_failures(s: &Sentence) -> bool {
    ["led", "lead", "leads", "leading"]
        .iter()
        .any(|l| s.phrase(&[l, "to"]).is_some())
        || s.has_stem(&["cascad"])
        || s.has("chain")
}

/// "Corrective action", "action taken", "response": what was done about
/// a failure said beside it.
fn answered_by_action(s: &Sentence) -> bool {
    s.has_stem(&["correct"])
        || s.phrase(&["action", "taken"]).is_some()
        || s.phrase(&["actions", "taken"]).is_some()
        || s.has("response")
}

/// "What went wrong?", and "what made look at chuck fail?" (a why).
/// "What was it doing at tick 8, before the second detect chuck
/// failure?": the failure says when; what it was doing is asked.
fn doing_by_a_failure(c: &Cues) -> bool {
    let q = c.s.q;
    let problem_at =
        |w: &super::super::Word| crate::ask::read::cues::PROBLEM.contains(&w.stem.as_str());
    let clause = q
        .iter()
        .position(|w| ["before", "after", "until", "till"].contains(&w.text.as_str()));
    c.s.has("doing")
        && clause.is_some_and(|k| !q[..k].iter().any(problem_at) && q[k..].iter().any(problem_at))
}

pub(super) fn what_went_wrong(c: &Cues) -> Option<Readings> {
    let s = c.s;
    // "NavigateWithReplanning has just failed, what's gone wrong there?":
    // a statement, then what is asked.
    let asks_what = ["went", "is", "has"].iter().any(|v| {
        s.phrase(&["what", v, "wrong"]).is_some()
            || s.phrase(&["what", v, "gone", "wrong"]).is_some()
    });
    if !(c.problem && (c.what || s.empty() || s.has("where")) && (!c.yes_no || asks_what)) {
        return None;
    }
    let asked_when = when::find(s.q);
    if asks_past_a_told_failure(s, asked_when.is_some()) || doing_by_a_failure(c) {
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
pub(super) fn asks_past_a_told_failure(s: &Sentence, moment_said: bool) -> bool {
    let Some((what, _)) = s.free().filter(|(_, w)| w.text == "what").last() else {
        return false;
    };
    let asks_a_problem = |from: usize| {
        s.free()
            .any(|(i, w)| i > from && crate::ask::read::cues::PROBLEM.contains(&w.stem.as_str()))
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
pub(super) fn failure_told(c: &Cues) -> (bool, bool) {
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
pub(super) fn of_a_goal_not_a_failure(c: &Cues) -> bool {
    c.s.has_stem(&["subgoal", "goal", "mission", "object"]) && !c.problem && !c.after_failure
}

/// "Any problems?": yes or no.
pub(super) fn anything_wrong(c: &Cues) -> Option<Readings> {
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

/// "Did the robot still make it to the goal after the failures?": whether
/// the run came through; "at which tick did the goal get reached?": when
/// the task succeeded.
pub(super) fn goal_reached(c: &Cues) -> Option<Readings> {
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
pub(super) fn task_outcome(c: &Cues) -> Option<Readings> {
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
