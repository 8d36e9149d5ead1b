//! Han et al.'s questions of the tree: what it is doing, its subgoal and
//! goal, and how it achieves them.

use super::*;

/// The words that name a part of the task: "the immediate objective",
/// "what part of the mission", "which phase of the patrol is underway?",
/// "which branch is it in", "at this stage (the current chunk)".
pub(super) fn asks_subgoal(c: &Cues) -> bool {
    let s = c.s;
    // "What smaller aim is it working on, within the whole trip?": a goal
    // within the goal.
    let part = s.has_stem(&["immedi"])
        || s.q.windows(2).any(|p| {
            ["part", "chunk", "portion", "piece", "section"].contains(&p[0].text.as_str())
                && p[1].text == "of"
        })
        || ["smaller", "little", "small"].iter().any(|a| {
            ["goal", "aim", "objective"]
                .iter()
                .any(|g| s.phrase(&[a, g]).is_some())
        });
    let stage = s.has_stem(&["phase", "stage", "branch", "chunk", "leg", "portion"])
        || s.phrase(&["this", "level"]).is_some()
        || s.phrase(&["higher", "level"]).is_some()
        || (c.what || s.has("which")) && s.has("part") && !s.has("how");
    s.has_stem(&["subgoal", "subtask", "milestone"])
        // "Which chunk of the job": "the job" names the root, and is still
        // the whole the part is of.
        || part
            && s.q.iter().any(|w| {
                ["goal", "object", "mission", "task", "job", "aim"].contains(&w.stem.as_str())
            })
        || s.phrase(&["sub", "goal"]).is_some()
        || s.phrase(&["sub", "task"]).is_some()
        || s.phrase(&["intermediate", "goal"]).is_some()
        || s.phrase(&["current", "step"]).is_some()
        // "Which step of the patrol is it on?", "which step is it in
        // right now", "the step it's in".
        || s.has("which") && s.has_stem(&["step"]) && s.has("on")
        || s.q.windows(3).enumerate().any(|(i, p)| {
            p[0].text == "which"
                && (p[1].text == "step" || p[2].text == "step")
                && s.q[i + 2..].iter().any(|w| w.text == "in")
        })
        || s.has_stem(&["step"])
            && (s.phrase(&["it", "is", "in"]).is_some() || s.phrase(&["is", "it", "in"]).is_some())
        || stage && c.named.is_empty() && (c.what || s.has("which"))
        || where_it_is(c)
}

/// "What step is it on at the moment?", "which big step of the kit is it
/// on?", "what chunk of the work is it on?": the part of the task it is
/// in, not the steps of one.
/// "The steps of the sub-task it's in", "the plan for the current
/// step", "steps for what it's doing now": the steps of a part, wherever
/// it is said to be; not "the steps in tick 5".
pub(super) fn steps_of_a_part(s: &Sentence) -> bool {
    // "Which steps make up the subgoal it is working on?".
    let make_up = ["make", "makes", "making"].iter().any(|m| {
        s.phrase(&["steps", m, "up"]).is_some() || s.phrase(&["steps", "that", m, "up"]).is_some()
    });
    make_up
        || s.q.windows(2).enumerate().any(|(i, p)| {
            ["steps", "plan", "procedure"].contains(&p[0].text.as_str())
                && ["of", "for", "in", "to"].contains(&p[1].text.as_str())
                && s.q[i + 2..]
                    .iter()
                    .find(|w| !["the", "this", "its", "that", "a"].contains(&w.text.as_str()))
                    .is_some_and(|w| !["tick", "ticks", "run", "log"].contains(&w.text.as_str()))
        })
}

pub(super) fn where_it_is(c: &Cues) -> bool {
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

pub(super) fn asks_goal(s: &Sentence) -> bool {
    s.has_stem(&[
        "goal", "object", "mission", "aim", "purpos", "task", "intent", "job", "target",
    ]) || s.phrase(&["trying", "to"]).is_some()
        || s.phrase(&["try", "to"]).is_some()
        // Not "which city is this grid supposed to be": what it is, not
        // what it is for.
        || s.phrase(&["supposed", "to"]).is_some() && !ends_being(s, "supposed")
        || s.phrase(&["meant", "to"]).is_some() && !ends_being(s, "meant")
        // Translated: "the finality of the robot", "the ultimate scope of
        // this tree", "what does it want to reach finally".
        || s.has("finality")
        || s.has("scope") && ["ultimate", "final", "overall", "general"].iter().any(|w| s.has(w))
        || s.has_stem(&["want"]) && ["reach", "obtain", "achieve"].iter().any(|w| s.has(w))
        // "What was the robot going for overall?".
        || s.phrase(&["going", "for"]).is_some() && (s.has("overall") || s.has("ultimately"))
        || s.phrase(&["working", "towards"]).is_some()
        || s.phrase(&["working", "toward"]).is_some()
        || s.phrase(&["get", "done"]).is_some()
        || s.has_stem(&["achiev", "accomplish"])
}

/// "… supposed to be" with nothing after it, or only where: "what city
/// is this taxi supposed to be in?" asks where it is, not what it is for.
pub(super) fn ends_being(s: &Sentence, verb: &str) -> bool {
    let free: Vec<&str> = s.free().map(|(_, w)| w.text.as_str()).collect();
    let Some(i) = free.windows(3).rposition(|w| w == [verb, "to", "be"]) else {
        return false;
    };
    match &free[i + 3..] {
        [] => true,
        [place] => ["in", "at", "on", "near", "from", "located", "based"].contains(place),
        _ => false,
    }
}

pub(super) fn asks_steps(c: &Cues) -> bool {
    let s = c.s;
    if steps_of_a_part(s) {
        return true;
    }
    // "At this step": a moment, not the steps.
    // "At step 6": a moment too.
    // "The step it's in": the part it is in, not the steps of one.
    let this_step = ["this", "that", "current", "which"]
        .iter()
        .any(|w| s.phrase(&[w, "step"]).is_some())
        || s.phrase(&["step", "it", "is", "in"]).is_some() && !s.has("steps")
        || s.free().any(|(i, w)| {
            w.text == "step"
                && s.q
                    .get(i + 1)
                    .is_some_and(|n| n.text.bytes().all(|b| b.is_ascii_digit()))
        });
    // "What steps does it take for what it's doing now?": the steps asked
    // of what it does.
    let steps_asked = ["what", "which"]
        .iter()
        .any(|w| s.phrase(&[w, "steps"]).is_some());
    (!s.has("doing") || steps_asked)
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
pub(super) fn how_achieved(c: &Cues) -> Option<Readings> {
    let steps = asks_steps(c);
    // "Top level plan", "this subgoal - steps to finish it": steps of a
    // goal named, typed with no verb, are asked for.
    let goal_named = c.s.nodes.iter().any(|m| m.uids == [c.root]);
    let of_a_goal = asks_subgoal(c) || asks_goal(c.s) || c.whole || goal_named;
    let listed = steps
        && (c.what
            || c.s.empty()
            // "Plan for this step?", "request steps for current leg.".
            || steps_of_a_part(c.s) && !c.why
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
    if (asks_subgoal(c) || now || this_part(c.s) || part_named && c.how && !goal_named)
        && (steps || c.how)
    {
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

/// "This step", "the current leg": the part it is in, said as one.
fn this_part(s: &Sentence) -> bool {
    ["this", "current", "present"].iter().any(|a| {
        ["step", "leg", "stage", "phase", "part", "bit", "subtask"]
            .iter()
            .any(|p| s.phrase(&[a, p]).is_some())
    })
}

/// "What's it meant to be doing overall?", "the whole task it's supposed
/// to be doing": what it is for, as a whole, is its goal; what it is meant
/// to be doing now is what it does.
fn meant_overall(c: &Cues) -> bool {
    let s = c.s;
    (s.phrase(&["meant", "to"]).is_some() || s.phrase(&["supposed", "to"]).is_some())
        && c.whole
        && !c.now_words
}

/// "What is your subgoal?", "what is your goal?".
pub(super) fn subgoal_or_goal(c: &Cues) -> Option<Readings> {
    let s = c.s;
    if asks_subgoal(c) {
        return c.only(Intent::Fixed(Question::Tree(TreeQuestion::Subgoal)), 0.95);
    }
    if !asks_goal(s) || s.has("doing") && !meant_overall(c) {
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
pub(super) fn which_of_two(c: &Cues) -> Option<Readings> {
    let either = c.named.len() == 2
        && c.yes_no
        && c.ev.is_none()
        && c.s.q[c.named[0].end..c.named[1].start]
            .iter()
            .all(|w| ["or", "the", "a", "an"].contains(&w.text.as_str()));
    either.then(|| c.only(Intent::Fixed(Question::Tree(TreeQuestion::Doing)), 0.9))?
}

/// "What are you on right now?", "what were you on at 12:13?": what it
/// is busy with; not "which step is it on?" (read before).
pub(super) fn on_it(s: &Sentence) -> bool {
    s.q.windows(3).any(|p| {
        ["you", "it", "we", "robot"].contains(&p[0].text.as_str()) && p[1].text == "on" && {
            let after = p[2].text.as_str();
            ["at", "right", "now", "rn", "atm", "currently", "in"].contains(&after)
        }
    }) || s.ends_with(&["you", "on"])
        || s.ends_with(&["it", "on"])
}

/// "What are you doing?".
pub(super) fn doing(c: &Cues) -> Option<Readings> {
    let s = c.s;
    let doing = c.doing_words
        || on_it(s)
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
