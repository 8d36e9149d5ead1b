//! Clauses that change which node a name means or when a question is
//! asked: "before FollowPath failed", "the retreat arm in reset arm",
//! "retrying FollowPath", "the second move up", "instead of up".

use super::*;

/// "Why did it move right instead of up": a contrast whose second part
/// leaves out the verb the first has. Where nothing after "instead of" or
/// "rather than" names a node, the first mention's first word and the
/// words after are looked up together ("move up").
pub(super) fn elided_foil(
    vocabulary: &mentions::Vocabulary,
    tree: &Tree,
    q: &[Word],
    nodes: &[Mention],
) -> Option<Mention> {
    let after = (0..q.len().saturating_sub(1)).find_map(|i| {
        let pair = (q[i].text.as_str(), q[i + 1].text.as_str());
        matches!(pair, ("instead", "of") | ("rather", "than")).then_some(i + 2)
    })?;
    let [fact] = nodes else { return None };
    if fact.end > after || fact.end - fact.start < 2 || after >= q.len() {
        return None;
    }
    let rest = &q[after..q.len().min(after + 4)];
    let words: Vec<Word> = std::iter::once(q[fact.start].clone())
        .chain(rest.iter().cloned())
        .collect();
    let found = vocabulary
        .mentions(tree, &words, &asks)
        .into_iter()
        .find(|m| m.start == 0 && m.end >= 2 && !m.weak && m.uids != fact.uids)?;
    let end = after + found.end - 1;
    Some(Mention {
        start: after,
        end,
        uids: found.uids,
        score: found.score,
        weak: false,
        phrase: words::said(&q[after..end]),
    })
}

/// "The second move up", "the third move left": of the nodes a name
/// calls, the N-th in the tree (uids count in its order), where no
/// "time" or "try" after says it is the N-th run of one node. "The last
/// move left" of steps alike (one type, one kind: the taxi's four move
/// left actions) is the last of them, which is also the last to run; of
/// nodes that only share a name (a Sequence and its action), it is a time.
pub(super) fn counted_among_alike(tree: &Tree, q: &[Word], nodes: Vec<Mention>) -> Vec<Mention> {
    if when::nth_time(q).is_some() {
        return nodes;
    }
    nodes
        .into_iter()
        .map(|mut m| {
            let before = (0..m.start).rev().find(|&k| q[k].text != "the");
            let mut uids = m.uids.clone();
            uids.sort_unstable();
            let steps_alike = uids.iter().all(|&u| {
                let (a, b) = (tree.node(u), tree.node(uids[0]));
                a.id == b.id && a.kind == b.kind
            });
            // "When was the last move left done": the last time, asked of
            // them all.
            let timed = q
                .iter()
                .any(|w| ["when", "tick", "time", "ticks"].contains(&w.text.as_str()));
            let last = !timed
                && before.is_some_and(|k| {
                    ["last", "final"].contains(&q[k].text.as_str())
                        && k > 0
                        && q[k - 1].text == "the"
                });
            // "The first" most often means a time, not a node.
            let n = before
                .and_then(|k| when::ordinal(&q[k].text))
                .filter(|&n| n >= 2);
            let picked = match (n, last && steps_alike) {
                (Some(n), _) => uids.get(n as usize - 1),
                (None, true) => uids.last(),
                _ => None,
            };
            if let (Some(&u), true) = (picked, m.uids.len() >= 2) {
                m.uids = vec![u];
            }
            m
        })
        .collect()
}

/// Of nodes named alike, the one deepest in the tree.
pub(super) fn deepest(tree: &Tree, uids: &[Uid]) -> Uid {
    uids.iter()
        .copied()
        .max_by_key(|&u| tree.ancestors(u).count())
        .unwrap_or(tree.root().uid)
}

/// "(just) before X failed", "right after the X failure", "right before X
/// kicked in", in a question that asks what was done or running: the
/// moment, and the words that say it (the marker, the node's name, the
/// failure or the start).
pub(super) fn failure_clause(
    tree: &Tree,
    q: &[Word],
    used: &[bool],
    mentions: &[Mention],
) -> Option<(When, Vec<usize>)> {
    let doing = q.iter().any(|w| {
        [
            "doing",
            "running",
            "subgoal",
            "goal",
            "happening",
            "active",
            "executing",
        ]
        .contains(&w.text.as_str())
    });
    let k = q
        .iter()
        .enumerate()
        .position(|(i, w)| !used[i] && (w.text == "before" || w.text == "after"))?;
    // "After look at chuck failed, why did it retreat the arm …": a clause
    // that opens the question, another node asked about after it.
    let opens = q[..k]
        .iter()
        .all(|w| ["just", "right", "so", "and"].contains(&w.text.as_str()));
    // The name right after the marker (an article or an ordinal between),
    // then the failure.
    let m = mentions.iter().find(|m| {
        m.start > k
            && q[k + 1..m.start]
                .iter()
                .all(|w| w.text == "the" || when::ordinal(&w.text).is_some())
    })?;
    let (end, started) = event_after(q, m)?;
    // "After FollowPath failed the second time, did the bot come back from
    // that?": whether it recovered is asked after it.
    let rest = &q[end + 1..];
    let recovery_after = rest.iter().any(|w| w.text.starts_with("recover"))
        || rest.windows(2).any(|p| {
            ["come", "came", "get", "got", "bounce", "bounced"].contains(&p[0].text.as_str())
                && p[1].text == "back"
        });
    let asked_after = mentions.iter().any(|n| n.start > end) || recovery_after;
    if !(doing || opens && asked_after) {
        return None;
    }
    let mut said: Vec<usize> = (k..=end).collect();
    said.extend(
        (0..k)
            .rev()
            .take_while(|&j| ["just", "right"].contains(&q[j].text.as_str())),
    );
    // Of nodes named alike, the innermost: the one whose failure the
    // others pass on (the FollowPath action, not its RecoveryNode).
    let uid = deepest(tree, &m.uids);
    let nth = q[k + 1..m.start]
        .iter()
        .find_map(|w| when::ordinal(&w.text));
    let before = q[k].text == "before";
    let w = match (nth, before) {
        _ if started && before => When::BeforeStartOf(uid),
        _ if started => When::AfterStartOf(uid),
        (Some(n), _) => When::Ended {
            uid,
            n,
            failed: true,
            side: if before { Side::Before } else { Side::After },
        },
        (None, true) => When::BeforeFailureOf(uid),
        (None, false) => When::AfterFailureOf(uid),
    };
    Some((w, said))
}

/// The word after the name that says the event a clause's moment is
/// told by, and whether it is a start ("right before ask kicked in",
/// where no failure is said) rather than a failure.
fn event_after(q: &[Word], m: &Mention) -> Option<(usize, bool)> {
    const STARTS: &[&str] = &[
        "started",
        "starts",
        "start",
        "kicked",
        "kicks",
        "began",
        "begins",
        "launched",
        "triggered",
    ];
    let near = m.end..q.len().min(m.end + 2);
    if let Some(i) = near.clone().find(|&i| q[i].stem.starts_with("fail")) {
        return Some((i, false));
    }
    near.into_iter()
        .find(|&i| STARTS.contains(&q[i].text.as_str()))
        .map(|i| (i, true))
}

/// "The retreat arm in reset arm", "the costmap clearing under the
/// recovery branch": a node named within another is one of those under
/// it, and the other names no node of its own.
pub(super) fn scoped(tree: &Tree, q: &[Word], nodes: Vec<Mention>) -> Vec<Mention> {
    const WITHIN: &[&str] = &[
        "in", "under", "inside", "within", "of", "below", "beneath", "for", "from",
    ];
    let mut out: Vec<Mention> = Vec::with_capacity(nodes.len());
    for m in nodes {
        if let Some(a) = out.last_mut() {
            let between = &q[a.end..m.start];
            // "GoalUpdated fails in the RecoveryFallback": what it does
            // may come between the node and where it is.
            let deed = |w: &Word| {
                [
                    "fail", "succeed", "return", "run", "ran", "had", "has", "have", "been",
                ]
                .contains(&w.stem.as_str())
                    || ["false", "true", "fails", "failed", "succeeds", "succeeded"]
                        .contains(&w.text.as_str())
            };
            // "How come ask never ran in the insert large gear part?".
            let deed_or_not = |w: &Word| deed(w) || ["never", "not"].contains(&w.text.as_str());
            let within = !between.is_empty()
                && between.iter().any(|w| WITHIN.contains(&w.text.as_str()))
                && between.iter().all(|w| {
                    WITHIN.contains(&w.text.as_str())
                        || ["the", "a"].contains(&w.text.as_str())
                        || deed_or_not(w)
                });
            let told = between.iter().any(deed);
            let under: Vec<Uid> = a
                .uids
                .iter()
                .copied()
                .filter(|&u| m.uids.iter().any(|&p| p != u && tree.is_ancestor(p, u)))
                .collect();
            if within && !under.is_empty() && !m.weak && told {
                // The deed stays a word of the question; the place only
                // picks which of the nodes named alike.
                a.uids = under;
                continue;
            }
            if within && !under.is_empty() && !m.weak {
                a.uids = under;
                a.end = m.end;
                a.score = a.score.min(m.score);
                a.phrase = words::said(&q[a.start..a.end]);
                continue;
            }
        }
        out.push(m);
    }
    out
}

/// "Instead of retrying FollowPath": a verb said of a name right after it
/// is what was done to that node, not a node of its own (a Retry).
pub(super) fn governing_verbs_dropped(q: &[Word], nodes: Vec<Mention>) -> Vec<Mention> {
    let verb_before = |a: &Mention, b: &Mention| {
        a.end - a.start == 1
            && q[a.start].text.ends_with("ing")
            && a.end <= b.start
            && q[a.end..b.start]
                .iter()
                .all(|w| ["the", "a"].contains(&w.text.as_str()))
    };
    let keep: Vec<bool> = (0..nodes.len())
        .map(|i| !nodes.get(i + 1).is_some_and(|b| verb_before(&nodes[i], b)))
        .collect();
    nodes
        .into_iter()
        .zip(keep)
        .filter_map(|(m, k)| k.then_some(m))
        .collect()
}

/// "The second child of the FollowPath fallback", "the 5th child of
/// navigate to passenger", "the child of the RetryUntilSuccessful", "the
/// condition under the ReactiveSequence": a node named by its place under
/// another. Said beside a name ("look_at, 4th child of the insert large
/// gear Sequence"), the place picks which of the nodes so named.
pub(super) fn children_by_place(tree: &Tree, q: &[Word], nodes: Vec<Mention>) -> Vec<Mention> {
    const UNDER: &[&str] = &["of", "under", "in", "inside", "within", "below", "beneath"];
    let mut out: Vec<Mention> = Vec::with_capacity(nodes.len());
    for m in nodes {
        let mut k = m.start;
        while k > 0 && ["the", "a", "its"].contains(&q[k - 1].text.as_str()) {
            k -= 1;
        }
        let placed = (k >= 2 && UNDER.contains(&q[k - 1].text.as_str()))
            .then(|| place(tree, q, k - 2, &m))
            .flatten();
        let Some((start, children)) = placed else {
            out.push(m);
            continue;
        };
        // A kind word the place starts with ("the condition under") is no
        // mention of its own.
        while out.last().is_some_and(|a| a.start >= start) {
            out.pop();
        }
        // Beside a name said just before that is one of them, the place
        // only picks among that name's nodes.
        if let Some(a) = out.last_mut().filter(|a| {
            start >= a.end && start - a.end <= 8 && a.uids.iter().any(|u| children.contains(u))
        }) {
            a.uids.retain(|u| children.contains(u));
            a.end = m.end;
            a.phrase = words::said(&q[a.start..a.end]);
            continue;
        }
        if out.last().is_some_and(|a| a.end > start) {
            out.push(m);
            continue;
        }
        out.push(Mention {
            start,
            end: m.end,
            uids: children,
            score: m.score,
            weak: false,
            phrase: words::said(&q[start..m.end]),
        });
    }
    out
}

/// The nodes the words ending at `at` place under `of`'s nodes, and where
/// those words start: "[the] [N-th|last|only] child", or a kind word
/// ("the condition under").
fn place(tree: &Tree, q: &[Word], at: usize, of: &Mention) -> Option<(usize, Vec<Uid>)> {
    let word = q[at].text.as_str();
    let parents = of.uids.iter().map(|&u| tree.node(u));
    let (mut start, children): (usize, Vec<Uid>) = if ["child", "kid"].contains(&word) {
        let nth = at.checked_sub(1).and_then(|k| match q[k].text.as_str() {
            "last" => Some(0),
            w => when::ordinal(w).map(|n| n as usize),
        });
        let picked = parents
            .filter_map(|p| match nth {
                Some(0) => p.children.last().copied(),
                Some(n) => p.children.get(n - 1).copied(),
                None => (p.children.len() == 1).then(|| p.children[0]),
            })
            .collect();
        (if nth.is_some() { at - 1 } else { at }, picked)
    } else if mentions::is_kind_word(word) && !["node", "step"].contains(&word) {
        let picked: Vec<Uid> = parents
            .filter_map(|p| {
                let mut of_kind = p
                    .children
                    .iter()
                    .copied()
                    .filter(|&c| mentions::of_kind(word, tree.node(c)));
                match (of_kind.next(), of_kind.next()) {
                    (Some(c), None) => Some(c),
                    _ => None,
                }
            })
            .collect();
        (at, picked)
    } else {
        return None;
    };
    if children.is_empty() {
        return None;
    }
    while start > 0 && ["the", "a", "its"].contains(&q[start - 1].text.as_str()) {
        start -= 1;
    }
    Some((start, children))
}

/// "The tick where the spin failed", "the tick in which X failed": the
/// moment of that failure (X's first, or the N-th said), and the words
/// that say it.
pub(super) fn tick_of_a_failure(
    tree: &Tree,
    q: &[Word],
    used: &[bool],
    mentions: &[Mention],
) -> Option<(When, Vec<usize>)> {
    let k = (0..q.len()).find(|&i| !used[i] && q[i].text == "tick")?;
    let mut j = k + 1;
    while j < q.len() && ["where", "when", "in", "which", "that"].contains(&q[j].text.as_str()) {
        j += 1;
    }
    if j == k + 1 {
        return None;
    }
    let m = mentions.iter().find(|m| {
        m.start >= j
            && q[j..m.start]
                .iter()
                .all(|w| w.text == "the" || when::ordinal(&w.text).is_some())
    })?;
    let end = (m.end..q.len().min(m.end + 2)).find(|&i| q[i].stem.starts_with("fail"))?;
    let n = q[j..m.start]
        .iter()
        .chain(&q[end + 1..q.len().min(end + 3)])
        .find_map(|w| when::ordinal(&w.text))
        .unwrap_or(1);
    let w = When::Ended {
        uid: deepest(tree, &m.uids),
        n,
        failed: true,
        side: Side::At,
    };
    Some((w, (k + 1..=end).collect()))
}

/// "What happened when drop off passenger succeeded?", "what went on at
/// the moment it dropped the passenger off?", "what all happened the first
/// time FollowPath failed?": what happened is asked at the moment of an
/// event said of a node (its N-th failure, or its N-th end where it
/// succeeded or was done), and the words that say it.
pub(super) fn moment_of_an_event(
    tree: &Tree,
    q: &[Word],
    used: &[bool],
    mentions: &[Mention],
) -> Option<(When, Vec<usize>)> {
    let happened = q.iter().any(|w| {
        ["happened", "happen", "happening", "occurred", "occur"].contains(&w.text.as_str())
    }) || q
        .windows(2)
        .any(|p| ["went", "goes", "going"].contains(&p[0].text.as_str()) && p[1].text == "on");
    if !happened || !q.iter().any(|w| w.text == "what") {
        return None;
    }
    let marker = |i: usize| match q[i].text.as_str() {
        "when" | "moment" | "as" => true,
        "time" => i > 0 && when::ordinal(&q[i - 1].text).is_some(),
        _ => false,
    };
    let k = (0..q.len()).find(|&i| !used[i] && marker(i))?;
    // Between the marker and the name: who did it, or which time.
    let m = mentions.iter().find(|m| {
        m.start > k
            && q[k + 1..m.start].iter().all(|w| {
                [
                    "the", "it", "robot", "bot", "he", "she", "they", "first", "finally",
                ]
                .contains(&w.text.as_str())
                    || when::ordinal(&w.text).is_some()
            })
    })?;
    let after = m.end..q.len().min(m.end + 2);
    let failed = after.clone().find(|&i| q[i].stem.starts_with("fail"));
    let done = after.clone().find(|&i| {
        ["succeed", "finish", "complet", "done", "work"]
            .iter()
            .any(|v| q[i].stem.starts_with(v))
    });
    // "When it dropped the passenger off": a step said as done, by its verb.
    let said_done = q[m.start].text.ends_with("ed") || q[m.start].text == "did";
    let (end, failed) = match (failed, done) {
        (Some(i), _) => (i, true),
        (None, Some(i)) => (i, false),
        (None, None) if said_done => (m.end - 1, false),
        _ => return None,
    };
    let n = q[k.saturating_sub(1)..m.start]
        .iter()
        .chain(&q[end + 1..q.len().min(end + 3)])
        .find_map(|w| when::ordinal(&w.text))
        .unwrap_or(1);
    let w = When::Ended {
        uid: deepest(tree, &m.uids),
        n,
        failed,
        side: Side::At,
    };
    let from = if q[k].text == "time" { k - 1 } else { k };
    Some((w, (from..=end).collect()))
}
