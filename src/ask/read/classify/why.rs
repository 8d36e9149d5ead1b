//! Why: a node's event, a contrast of two, what it is doing, its purpose.

use super::*;

/// "This tree for, overall": the whole named, then "for" with no moment
/// or thing or deed after it ("the tree for tick 3", "the tree for
/// reaching the goal" are no purpose).
pub(super) fn whole_for(s: &Sentence) -> bool {
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
pub(super) fn purpose(c: &Cues) -> Option<Readings> {
    let s = c.s;
    // "The point of it", not "at this point of the delivery".
    let point_of = s.phrase(&["point", "of"]).is_some_and(|i| {
        i == 0 || !["this", "that", "which", "what", "some"].contains(&s.q[i - 1].text.as_str())
    });
    // "What's this in aid of?": what it is for.
    let in_aid = s.phrase(&["in", "aid", "of"]).is_some();
    let purpose = s.has_stem(&["purpos", "reason"])
        || point_of
        || in_aid
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
        || s.has_stem(&["action"])
        // "The purpose of the motion the arm is making at this point".
        || s.has_stem(&["motion", "movement"])
        || s.phrase(&["this", "point"]).is_some()
        || s.phrase(&["this", "moment"]).is_some()
        || in_aid && s.has("this");
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
pub(super) fn why_bare_verb(c: &Cues) -> Option<Readings> {
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
pub(super) fn why(c: &Cues) -> Option<Readings> {
    // "Explain what failed there and why it cascaded upwards": what went
    // wrong, told as the chain it was.
    if !c.why || a_chain_of_failures(c.s) && c.s.phrase(&["what", "failed"]).is_some() {
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
pub(super) fn why_expected_actual(c: &Cues) -> Option<Readings> {
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
    let event = crate::ask::read::event(&told)
        .0
        .or(c.ev)
        .unwrap_or(Event::Run);
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
pub(super) fn why_with_a_clause(c: &Cues) -> Option<Readings> {
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
pub(super) fn why_not(c: &Cues) -> Option<Readings> {
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
pub(super) fn alternatives(s: &Sentence, named: &[&Mention]) -> (Vec<Uid>, String) {
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
pub(super) fn sides<'a>(c: &Cues<'a, '_>) -> Vec<&'a Mention> {
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
pub(super) fn why_still_running(c: &Cues) -> Option<Readings> {
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
    // "Why was X stuck on RUNNING?", "X sat in RUNNING for two ticks - why?".
    let held = c.s.has("stuck")
        || c.s.has("running")
            && [
                "sat", "sit", "sits", "sitting", "stayed", "stays", "remained",
            ]
            .iter()
            .any(|w| c.s.has(w));
    let keeps = c.ev == Some(Event::KeepRunning)
        && (c.s.phrase(&["keep", "running"]).is_some()
            || c.s.phrase(&["keeps", "running"]).is_some()
            || held);
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
pub(super) fn why_doing_now(c: &Cues) -> Option<Readings> {
    let s = c.s;
    // "Reason for current action?", "rationale on current op?".
    let now = (s.has("now") || s.has("current") || s.has("currently"))
        && !["did", "was", "were", "had"].iter().any(|w| s.has(w));
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
pub(super) fn why_of(c: &Cues) -> Option<Readings> {
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
