//! What a question says happened: the event ("failed", "kept running",
//! "did not run"), what was expected instead (the foil), and who it is
//! said of (a node named, "it", or the task).

use super::*;

/// Words after which what is said is granted, not asked ("even though
/// L0 failed").
const GRANTS: &[&str] = &["although", "despite", "though"];

pub(super) fn event(s: &Sentence) -> (Option<Event>, bool) {
    // "Why did X succeed even though the controller failed": what is
    // granted after "even though" is not the event asked about.
    let concession = s.q.iter().enumerate().position(|(i, w)| {
        GRANTS.contains(&w.text.as_str())
            || w.text == "even" && s.q.get(i + 1).is_some_and(|n| n.text == "if")
    });
    let before = |k: usize| {
        let mut used = s.used.clone();
        for u in &mut used[k..] {
            *u = true;
        }
        Sentence {
            q: s.q,
            tree_words: s.tree_words,
            used,
            nodes: Vec::new(),
        }
    };
    if let Some(k) = concession.filter(|&k| k > 0) {
        return event_of(&before(k));
    }
    // "Why did the fallback succeed when its first child failed": a
    // clause that says when does not say the event asked about, where
    // one is said before it.
    // Not "…, when did it fail": a question's own "when"; not a contrast,
    // whose sides each say their event.
    let asks = |i: usize| {
        s.q.get(i + 1).is_some_and(|n| {
            ["did", "does", "do", "was", "is", "were", "had", "has"].contains(&n.text.as_str())
        })
    };
    let contrast = s.phrase(&["as", "opposed"]).is_some()
        || s.has("instead")
        || s.phrase(&["rather", "than"]).is_some();
    let clause =
        s.q.iter().enumerate().position(|(i, w)| {
            i > 0 && !s.used[i] && SAYS_WHEN.contains(&w.text.as_str()) && !asks(i)
        });
    // "Why RUS R @2, FP fb only just S'd": a why's event is the one said
    // of the node it names first; a second node named with its own event
    // is told.
    if s.q.first().is_some_and(|w| w.text == "why") && !contrast {
        if let [first, second, ..] = &s.nodes[..] {
            let said = event_of(&before(second.start));
            if said.0.is_some() && first.end < second.start && first.start <= 2 {
                return said;
            }
        }
    }
    let clause = clause.filter(|_| !contrast);
    if let Some(said) = clause
        .map(|k| event_of(&before(k)))
        .filter(|e| e.0.is_some())
    {
        return said;
    }
    event_of(s)
}

/// Words that open a clause saying when or why something else happened
/// ("… succeed when its first child failed").
const SAYS_WHEN: &[&str] = &["when", "after", "once", "because", "since"];

fn event_of(s: &Sentence) -> (Option<Event>, bool) {
    // "Did it get past that glitch or not?": "or not" asks yes or no.
    // "Only start at tick 8 and not earlier": a time denied, not the event.
    let time_denied = s.q.windows(2).any(|p| {
        p[0].text == "not" && ["earlier", "sooner", "before", "later"].contains(&p[1].text.as_str())
    });
    // "When did detect chuck (the action, not the sequence) first
    // succeed?": a kind denied says which node, not that it did not.
    let kind_denied = |i: usize| {
        let next = s.q[i + 1..]
            .iter()
            .map(|w| w.text.as_str())
            .find(|w| !["the", "a", "an"].contains(w));
        next.is_some_and(mentions::is_kind_word)
    };
    // "Why did not the action run?" still denies.
    let after_a_verb = |i: usize| {
        i > 0 && NOT_A_VERB.contains(&s.q[i - 1].text.as_str()) && s.q[i - 1].text != "the"
    };
    let a_plain_not = s
        .free()
        .any(|(i, w)| w.text == "not" && (after_a_verb(i) || !kind_denied(i)));
    let negated = a_plain_not && s.phrase(&["or", "not"]).is_none() && !time_denied
        || s.has("never")
        // "Why did none of the recovery actions ever run?".
        || s.phrase(&["none", "of"]).is_some()
        // "… yes or no?" asks yes or no; it denies nothing.
        || s.has("no") && !s.has("one") && s.phrase(&["yes", "or", "no"]).is_none();
    // "Why did it end up asking for help?": it came to do it, which is
    // running it, not finishing ("ends up aborting" is aborting).
    let ended_up = s.q.windows(3).any(|w| {
        ["end", "ended", "ends"].contains(&w[0].text.as_str())
            && w[1].text == "up"
            && w[2].text.ends_with("ing")
    });
    let e = match verbs_said(s).or_else(|| done_to(s)) {
        Some(Event::Finish) if ended_up => Some(Event::Run),
        e => e,
    };
    // "Why did it keep trying to detect the chuck?": it ran again and
    // again, which is starting, not one call running on.
    let retrying = s.has_stem(&["keep", "kept"])
        && s.free().any(|(_, w)| {
            ["trying", "retrying", "attempting", "restarting"].contains(&w.text.as_str())
        });
    let e = if retrying && e == Some(Event::KeepRunning) {
        Some(Event::Run)
    } else {
        e
    };
    // "Why couldn't it look at the chuck?": it tried and did not manage,
    // which is failing, not never running.
    let could_not = could_not(s);
    let negated = negated || could_not;
    // "Why did the path clear check say no?": a condition's answer.
    let free: Vec<&str> = s.free().map(|(_, w)| w.text.as_str()).collect();
    let says = |answer| {
        free.windows(2).any(|p| {
            ["say", "said", "says", "answer", "answered"].contains(&p[0]) && p[1] == answer
        })
    };
    if says("no") {
        return (Some(Event::Fail), false);
    }
    if says("yes") {
        return (Some(Event::Succeed), false);
    }
    let e = match (e, negated) {
        (Some(Event::Run) | None, true) if could_not => Some(Event::Fail),
        (Some(Event::Run), true) => Some(Event::NotRun),
        (Some(Event::Succeed), true) => Some(Event::Fail),
        (Some(Event::Fail), true) if s.has_stem(&["fail"]) => Some(Event::Succeed),
        (Some(Event::Finish), true) => Some(Event::KeepRunning),
        (None, true) => Some(Event::NotRun),
        (e, _) => e,
    };
    (e, negated)
}

/// "Couldn't detect the chuck", "could the robot not follow its path" (the
/// "not" a few words on), "was unable to", "not able to": it tried and did
/// not manage.
pub(super) fn could_not(s: &Sentence) -> bool {
    let free: Vec<&str> = s.free().map(|(_, w)| w.text.as_str()).collect();
    free.iter().enumerate().any(|(i, w)| {
        ["could", "can"].contains(w) && free[i + 1..].iter().take(3).any(|n| *n == "not")
    }) || s.phrase(&["not", "able"]).is_some()
        || s.phrase(&["unable", "to"]).is_some()
        || s.phrase(&["was", "unable"]).is_some()
}

/// "Why is it still running?", "so slow", "TEI stayed R for two ticks":
/// a call that ran on.
fn runs_on(s: &Sentence) -> bool {
    s.has_stem(&["keep", "still", "stick", "forev", "hang", "slow"])
        || s.has("longer")
        || s.phrase(&["so", "long"]).is_some()
        || s.phrase(&["take", "long"]).is_some()
        || s.phrase(&["taking", "long"]).is_some()
        || s.phrase(&["took", "long"]).is_some()
        || s.phrase(&["long", "time"]).is_some()
        || s.has_stem(&["stay", "remain"]) && s.has("running")
        // "Why was X stuck on RUNNING?", "X sat in RUNNING for two ticks".
        || s.has("stuck")
        || ["sat", "sit", "sits", "sitting"].iter().any(|w| s.has(w)) && s.has("running")
}

/// "OK", "okay" said of a node, not "ok but why no spin?", where it
/// only opens what is said.
fn ok_said(s: &Sentence) -> bool {
    // "Suppose look at chuck had gone fine": it went well, it succeeded.
    let went_well = s.q.windows(2).any(|p| {
        ["gone", "went"].contains(&p[0].text.as_str())
            && ["fine", "well", "right", "smoothly", "ok", "okay"].contains(&p[1].text.as_str())
    });
    went_well
        || s.free().any(|(i, w)| {
            w.stem == "ok"
                && !(i == 0
                    && s.q.get(1).is_some_and(|n| {
                        ["but", "so", "then", "and", "now", "thanks", "cool", "great"]
                            .contains(&n.text.as_str())
                    }))
        })
}

/// "GIG done at which tick?", "when was the last move left done": done
/// as finished, not "halfway done".
fn done_said(s: &Sentence) -> bool {
    s.free().any(|(i, w)| {
        w.text == "done"
            && (i == 0
                || ![
                    "halfway", "half", "partly", "almost", "nearly", "get", "got",
                ]
                .contains(&s.q[i - 1].text.as_str()))
    })
}

/// "When was the passenger picked up?": a node named by what was done
/// to its object, done (its verb past, its particle last), succeeded.
fn done_to(s: &Sentence) -> Option<Event> {
    s.nodes
        .iter()
        .any(|m| {
            let span = &s.q[m.start..m.end];
            span.len() > 2
                && ["up", "down", "off", "on", "out", "in"]
                    .contains(&span[span.len() - 1].text.as_str())
                && span[span.len() - 2].text.ends_with("ed")
        })
        .then_some(Event::Succeed)
}

/// The event the sentence's verbs say, before negation: failing first,
/// then skipping, halting, running on, succeeding, finishing, running.
/// "Why'd FollowPath bomb out?", "move right craps out": slang for
/// failing, a verb and "out".
fn conked_out(s: &Sentence) -> bool {
    s.q.windows(2).any(|p| {
        p[1].text == "out"
            && ["bomb", "crap", "conk", "flake", "peter"]
                .iter()
                .any(|v| p[0].text.starts_with(v))
    })
}

fn verbs_said(s: &Sentence) -> Option<Event> {
    let keep = runs_on(s);
    // "When did looking at the chuck go wrong?", "why did the sequence box
    // go red?" (Groot draws a failure red, a success green).
    let went_wrong = (s.phrase(&["go", "wrong"]).is_some()
        || s.phrase(&["gone", "wrong"]).is_some())
        && !s.nodes.is_empty();
    let said = |words: &[&str]| words.iter().any(|w| s.has(w));
    let coloured = |colour: &str| {
        ["go", "goes", "went", "gone", "turn", "turned"]
            .iter()
            .any(|v| s.phrase(&[v, colour]).is_some())
    };
    // "Why did drive get aborted?", "why was it aborted": a node aborted
    // by another was halted (a game engine's observer abort); one that
    // aborts (Nav2's controller) failed.
    let aborted_by_another = s.free().any(|(i, w)| {
        w.text == "aborted"
            && i > 0
            && ["get", "got", "was", "were", "been", "be", "gets", "getting"]
                .contains(&s.q[i - 1].text.as_str())
    });
    if aborted_by_another {
        Some(Event::Halted)
    } else if gave_up(s)
        || went_wrong
        || coloured("red")
        || coloured("negative")
        || conked_out(s)
        || s.has("false")
        || s.has_stem(&[
            "fail", "abort", "crash", "die", "error", "fault", "broke", "break", "bail", "stall",
        ])
    {
        Some(Event::Fail)
    } else if s.has_stem(&["skip"]) {
        Some(Event::Skipped)
    } else if s.has_stem(&[
        "halt",
        "stop",
        "interrupt",
        "cancel",
        "preempt",
        "kill",
        "abandon",
    ]) {
        Some(Event::Halted)
    } else if keep {
        Some(Event::KeepRunning)
    } else if s.has_stem(&["succeed", "success", "pass", "manag"])
        || ok_said(s)
        || said(&[
            "true",
            "successful",
            "successfully",
            "work",
            "worked",
            "works",
        ])
        || coloured("green")
    {
        Some(Event::Succeed)
    } else if s.has_stem(&["finish", "end", "complet"]) || done_said(s) || wrapped_up(s) {
        Some(Event::Finish)
    } else if s.has_stem(&[
        "run", "start", "execut", "tick", "call", "trigger", "begin", "activ", "launch", "fire",
        "check", "kick", "invok", "attempt", "tri", "tried", "enter", "chose", "choos", "pick",
        "select", "use",
    ]) {
        Some(Event::Run)
    } else if s.has_stem(&["reach", "arriv"]) {
        // "When did it reach the goal": got there, said of the task.
        Some(Event::Succeed)
    } else {
        None
    }
}

/// "When did walk wrap up?": it finished.
fn wrapped_up(s: &Sentence) -> bool {
    ["wrap", "wraps", "wrapped", "wrapping"]
        .iter()
        .any(|w| s.phrase(&[w, "up"]).is_some())
}

/// The event a question's verbs name, if any, and whether they are negated.
/// "The retry gave up", "why did it stop trying to detect the chuck": a
/// loop that stopped trying failed.
pub(super) fn gave_up(s: &Sentence) -> bool {
    let give = ["give", "gave", "giving", "gives", "given"];
    let stop = ["stop", "stopped", "stops", "stopping", "quit", "quits"];
    let trying = ["trying", "retrying", "attempting"];
    // "How many times did it try X before giving up?": a time, not the deed.
    let a_time =
        |i: usize| i > 0 && ["before", "until", "till"].contains(&s.q[i - 1].text.as_str());
    give.iter()
        .any(|g| s.phrase(&[g, "up"]).is_some_and(|i| !a_time(i)))
        || stop
            .iter()
            .any(|st| trying.iter().any(|t| s.phrase(&[st, t]).is_some()))
}

/// Of nodes a question says stopped trying, the loops that tried them: each
/// node's nearest retry above it (itself, if it is one); `None` where one
/// has none.
pub(super) fn loops_of(tree: &Tree, us: &[Uid]) -> Option<Vec<Uid>> {
    let retries = |u: Uid| {
        let id = &tree.node(u).id;
        id.starts_with("Retry") || id == "RecoveryNode"
    };
    let mut out: Vec<Uid> = Vec::new();
    for &u in us {
        let l = std::iter::once(u)
            .chain(tree.ancestors(u))
            .find(|&a| retries(a))?;
        if !out.contains(&l) {
            out.push(l);
        }
    }
    Some(out)
}

/// A query typed as into a search box, with no verb to tense it: "spin
/// why running", "top level plan".
pub(super) fn verbless(s: &Sentence) -> bool {
    const AUXILIARIES: [&str; 20] = [
        "is", "are", "am", "was", "were", "be", "been", "do", "does", "did", "has", "have", "had",
        "will", "would", "can", "could", "should", "shall", "may",
    ];
    !s.q.iter().any(|w| AUXILIARIES.contains(&w.text.as_str()))
}

/// "why is it looking at the chuck", "why does it keep driving": asked
/// of what it is doing now, in the present progressive; "drive why
/// running", with no verb to tense it, too.
pub(super) fn progressive(s: &Sentence) -> bool {
    if s.has("long") {
        return false;
    }
    // Not "drive kept running for several ticks, why?": a past said.
    let past = s.free().any(|(_, w)| {
        w.text.len() > 3 && w.text.ends_with("ed")
            || ["kept", "ran", "went", "got", "began"].contains(&w.text.as_str())
    });
    if verbless(s)
        && !past
        && ["running", "active", "busy", "ticking"]
            .iter()
            .any(|w| s.has(w))
    {
        return true;
    }
    let be = s.q.iter().enumerate().position(|(i, w)| {
        ["is", "are", "am", "was", "were", "keeps", "still"].contains(&w.text.as_str())
            || w.text == "keep" && i > 0 && ["does", "do"].contains(&s.q[i - 1].text.as_str())
            || w.text == "keep" && s.q.iter().any(|w| w.text == "does")
    });
    let Some(be) = be else {
        return false;
    };
    s.q[be + 1..].iter().any(|w| {
        w.text.len() > 4 && w.text.ends_with("ing") && w.text != "something"
            // "convertng": the i dropped.
            || w.text.len() > 6 && w.text.ends_with("ng") && !w.text.ends_with("ong")
            || ["active", "busy"].contains(&w.text.as_str())
            // "computin": the g dropped from a verb of the tree's.
            || w.text.len() > 4
                && w.text.ends_with("in")
                && s.tree_words.contains(&words::stem(&format!("{}g", w.text)))
    })
}

/// "why not X but Y": the node after a negation was the one not done.
pub(super) fn negated_first(s: &Sentence, a: &Mention, b: &Mention) -> bool {
    // "Instead of inserting the large gear it asked for help": the node
    // after "instead of" is the one not done.
    let foil_first = s.q[a.start.saturating_sub(3)..a.start].windows(2).any(|p| {
        matches!(
            (p[0].text.as_str(), p[1].text.as_str()),
            ("instead", "of") | ("rather", "than")
        )
    });
    foil_first
        || s.q[..a.start]
            .iter()
            .any(|w| w.text == "not" || w.text == "never")
            && !s.q[a.end..b.start]
                .iter()
                .any(|w| w.text == "not" || w.text == "instead")
}

/// "X failed instead of succeeding": the outcome the person expected.
pub(super) fn foil(s: &Sentence) -> Option<Event> {
    let at = s
        .phrase(&["instead", "of"])
        .or_else(|| s.phrase(&["rather", "than"]))
        .or_else(|| s.phrase(&["and", "not"]))
        .or_else(|| s.phrase(&["but", "not"]))?;
    let after: Vec<&Word> = s.q[at + 2..].iter().collect();
    after.iter().find_map(|w| match w.stem.as_str() {
        "succeed" | "pass" | "work" => Some(Event::Succeed),
        "fail" => Some(Event::Fail),
        "run" | "start" => Some(Event::Run),
        _ => None,
    })
}

/// "Spin, Wait and BackUp", "spin or back up": the mentions from the
/// first of `chain` on, one after another with only "and", "or", "nor",
/// "either", "the" (or a comma) between them, "and" or "or" said once at
/// least; the first alone where they are not so joined.
pub(super) fn joined<'m>(s: &Sentence, chain: &[&'m Mention]) -> Vec<&'m Mention> {
    const JOINS: &[&str] = &["and", "or", "nor", "either", "the"];
    let mut run = chain[..chain.len().min(1)].to_vec();
    let mut conjunction = false;
    for pair in chain.windows(2) {
        let gap = &s.q[pair[0].end..pair[1].start];
        if !gap.iter().all(|w| JOINS.contains(&w.text.as_str())) {
            break;
        }
        conjunction |= gap.iter().any(|w| w.text != "the");
        run.push(pair[1]);
    }
    if !conjunction {
        run.truncate(1);
    }
    run
}

/// The uids of the mentions, each once, in the order named.
pub(super) fn uids_of(run: &[&Mention]) -> Vec<Uid> {
    let mut uids: Vec<Uid> = Vec::new();
    for m in run {
        uids.extend(
            m.uids
                .iter()
                .filter(|u| !uids.contains(u))
                .collect::<Vec<_>>(),
        );
    }
    uids
}

/// Nodes listed from `m` on ("Spin, Wait and BackUp stay grey the whole
/// run - why") as one subject; else `m` alone.
fn listed(s: &Sentence, m: &Mention) -> Subject {
    let chain: Vec<&Mention> = s
        .nodes
        .iter()
        .skip_while(|n| !std::ptr::eq(*n, m))
        .collect();
    let run = joined(s, &chain);
    let names: Vec<String> = run.iter().map(|n| n.phrase.clone()).collect();
    match names.split_last() {
        Some((last, rest)) if !rest.is_empty() => {
            Subject::Nodes(uids_of(&run), format!("{} and {last}", rest.join(", ")))
        }
        _ => Subject::Nodes(m.uids.clone(), m.phrase.clone()),
    }
}

/// The subject of a question about a node: the node named, "it"/"that",
/// or the task itself.
pub(super) fn subject(s: &Sentence, root: Uid) -> Option<Subject> {
    // The task named ("nav2", "the patrol") yields to another node named,
    // but not to one in a clause that only says when ("why did the patrol
    // fail after path clear failed").
    let cut =
        s.q.iter()
            .enumerate()
            .position(|(i, w)| i > 0 && SAYS_WHEN.contains(&w.text.as_str()));
    let task_first = cut.is_some_and(|k| {
        s.nodes
            .first()
            .is_some_and(|m| m.uids == [root] && m.end <= k)
            && s.nodes.iter().all(|m| m.uids == [root] || m.start > k)
    });
    // "Why did CSF end up S even though L0 F'd": what is granted after
    // "even though" is not what is asked about.
    let granted = s.q.iter().position(|w| GRANTS.contains(&w.text.as_str()));
    let asked = |m: &&Mention| granted.is_none_or(|k| m.start < k);
    let m = s
        .nodes
        .iter()
        .filter(asked)
        .find(|m| m.uids != [root] && !task_first)
        .or_else(|| s.nodes.iter().find(asked))
        .or_else(|| s.nodes.first().filter(|_| granted.is_none()));
    if let Some(m) = m {
        return Some(listed(s, m));
    }
    if s.has("it") || s.has("that") || s.has("this") || s.has("thing") {
        return Some(Subject::It);
    }
    // "The run", "this run": the task; "did the frobnicator run": a verb.
    let the_run = s.free().any(|(i, w)| {
        w.text == "run"
            && i > 0
            && [
                "the", "this", "that", "whole", "entire", "my", "our", "a", "each", "every",
            ]
            .contains(&s.q[i - 1].text.as_str())
    });
    if s.has("you")
        || the_run
        || s.has_stem(&[
            "robot", "task", "mission", "tree", "bt", "root", "agent", "navig", "whole", "overal",
            "everyth", "i", "trip", "journey", "taxi", "car", "vehicl", "drone", "kit", "job",
            "ride", "deliveri",
        ])
    {
        return Some(Subject::Task);
    }
    None
}
