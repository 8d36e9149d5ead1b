//! Han et al.'s Algorithm 7: "Was there anything wrong?", "What went
//! wrong?", "How was the failure handled?", at a moment of a run.

use super::han::and_list;
use crate::model::{Builtin, Kind, Tree, Uid};
use crate::run::Status;
use crate::session::At;

/// What Algorithm 7 found above the current node.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Diagnosis {
    /// The sentence of "What went wrong?" ("" when nothing did).
    pub text: String,
    /// The Fallback that fell back, and the child it fell back to.
    pub fell_back: Option<(Uid, Option<Uid>)>,
    /// Retry nodes retrying, with their attempt counts, nearest first.
    pub retrying: Vec<(Uid, u32)>,
    /// The leaf whose failure is the reason.
    pub failed_leaf: Option<Uid>,
    pub nodes: Vec<Uid>,
    /// The text says what the run cannot tell (a run recorded from its
    /// middle), not that something went wrong.
    pub unknown: bool,
}

fn is_fallback(tree: &Tree, uid: Uid) -> bool {
    matches!(
        tree.node(uid).builtin,
        Some(Builtin::Fallback | Builtin::ReactiveFallback | Builtin::AsyncFallback)
    )
}

fn is_retry(tree: &Tree, uid: Uid) -> bool {
    tree.node(uid).builtin == Some(Builtin::RetryUntilSuccessful)
}

/// The leaf below `p` that failed last since `since` (a position): the
/// cause of the failure being explained, even if it has succeeded since (a
/// retry is under way).
fn last_failed_leaf(tree: &Tree, run: &At, p: Uid, since: u32) -> Option<Uid> {
    tree.descendants(p)
        .filter(|&u| tree.node(u).kind.is_leaf())
        .filter_map(|u| run.last_failure_since(u, since).map(|pos| (pos, u)))
        .max()
        .map(|(_, u)| u)
}

/// Han's Fallback test: the first child's current status is FAILURE. A
/// recorded run also has the moments, within the tick, after a Fallback
/// that completes reset that child to IDLE and before anything ticked it
/// again: there its last completion, in this run of the Fallback (and of
/// the root, which has not completed), is the failure the Fallback fell
/// back from. (A ReactiveFallback resets a failed first child while a
/// later one runs, and ticks it again each tick: for it, the current
/// status is the test.)
fn first_child_failed(tree: &Tree, run: &At, x: Uid, first: Uid) -> bool {
    let reactive = tree.node(x).builtin == Some(Builtin::ReactiveFallback);
    match run.status(first) {
        Status::Failure => true,
        Status::Idle if !reactive && run.root_outcome().is_none() => {
            let since = run.started_at(x);
            since >= run.run_start()
                && run
                    .last_completion(first)
                    .is_some_and(|(p, s)| s == Status::Failure && p > since)
        }
        _ => false,
    }
}

/// The nearest ancestor that has a name (Han's `find_non_null_parent`).
fn named_ancestor(tree: &Tree, uid: Uid) -> Option<Uid> {
    tree.ancestors(uid).find(|&a| tree.has_name(a))
}

/// Algorithm 7, from the current node `n` up to its subgoal.
pub fn diagnose(tree: &Tree, run: &At, n: Uid) -> Diagnosis {
    // A fault first: a fallback that went on past a check answering no
    // took a branch (Nav2's "is a new path needed?"); a failure higher up
    // that made a fallback or recovery act is what went wrong, if any.
    let d = diagnose_from(tree, run, n, true);
    if d.text.is_empty() {
        diagnose_from(tree, run, n, false)
    } else {
        d
    }
}

/// Whether only checks failed below `first` since `since`: a condition
/// did, and no action did (where the record shows no failure, as a live
/// robot's statuses may not, nothing is known to be a branch).
fn only_checks_failed(tree: &Tree, run: &At, first: Uid, since: u32) -> bool {
    let below: Vec<Uid> = std::iter::once(first)
        .chain(tree.descendants(first))
        .collect();
    let failed = |u: &&Uid| run.last_failure_since(**u, since).is_some();
    let is = |u: Uid, k: Kind| tree.node(u).kind == k && tree.node(u).builtin.is_none();
    // A check: a condition, or an Inverter over one.
    let check = |u: Uid| {
        is(u, Kind::Condition)
            || (tree.node(u).builtin == Some(Builtin::Inverter)
                && tree
                    .node(u)
                    .children
                    .iter()
                    .all(|&c| is(c, Kind::Condition)))
    };
    below.iter().filter(failed).any(|&u| check(u))
        && !below.iter().filter(failed).any(|&u| is(u, Kind::Action))
}

fn diagnose_from(tree: &Tree, run: &At, n: Uid, skip_branches: bool) -> Diagnosis {
    let mut d = Diagnosis::default();
    let mut fallback = None;
    let mut p = tree.parent(n);
    while let Some(x) = p {
        if tree.node(x).kind == Kind::SubTree {
            break;
        }
        let first = tree.node(x).children[0];
        let fell_back = fell_back(tree, run, x);
        if fell_back
            && skip_branches
            && tree.node(x).builtin != Some(Builtin::RecoveryNode)
            && only_checks_failed(tree, run, first, run.started_at(x))
        {
            p = tree.parent(x);
            continue;
        }
        if fell_back {
            fallback = Some(x);
            why_fell_back(tree, run, x, &mut d);
            break;
        }
        if let Some(c) = handled_elsewhere(tree, run, x) {
            failed_under(tree, run, x, c, &mut d);
            break;
        }
        if is_retry(tree, x) && run.attempts(x) > 0 {
            retrying(tree, run, x, &mut d);
            break;
        }
        p = tree.parent(x);
    }
    if let Some(fb) = fallback {
        retries_above(tree, run, fb, &mut d);
    }
    if d.text.is_empty() && run.root_outcome() == Some(Status::Failure) {
        root_failure(tree, run, &mut d);
    }
    if d.text.is_empty() {
        failing_now(tree, run, n, &mut d);
    }
    if d.text.is_empty() {
        attached_unknown(tree, run, n, &mut d);
    }
    d
}

/// Whether `x` has fallen back from its first child in its present run.
fn fell_back(tree: &Tree, run: &At, x: Uid) -> bool {
    let children = &tree.node(x).children;
    // Han's released code tests the first child's current status.
    // Nav2's RecoveryNode halts its first child before the recovery
    // runs: its failure within this run of the node is the test.
    if tree.node(x).builtin == Some(Builtin::RecoveryNode) {
        run.status(x) == Status::Running
            && run
                .last_failure_since(children[0], run.started_at(x))
                .is_some()
    } else {
        is_fallback(tree, x) && first_child_failed(tree, run, x, children[0])
    }
}

/// "I could not X because …": what failed under the first child of the
/// fallback `x`, and the child that handles it.
fn why_fell_back(tree: &Tree, run: &At, x: Uid, d: &mut Diagnosis) {
    let children = &tree.node(x).children;
    d.text = format!("I could not {} because ", tree.deed(x));
    d.nodes.push(x);
    let since = run.started_at(x);
    match (
        last_failed_leaf(tree, run, children[0], since),
        inverted_failure(tree, run, children[0], since),
    ) {
        (Some(f), _) => {
            // The paper's line 9 compares with `=`; its own examples
            // only come out when the parent is named if it differs.
            if let Some(fp) = tree
                .parent(f)
                .filter(|&fp| tree.description(fp) != tree.description(x))
            {
                d.text
                    .push_str(&format!("I was unable to {} as ", tree.deed(fp)));
                d.nodes.push(fp);
            }
            d.text.push_str(&format!("{} failed.", tree.spoken(f)));
            d.failed_leaf = Some(f);
            d.nodes.push(f);
        }
        (None, Some((inv, child))) => {
            d.text.push_str(&inverted_text(tree, inv, child));
            d.failed_leaf = Some(child);
            d.nodes.extend([inv, child]);
        }
        (None, None) => failed_unseen(tree, run, x, d),
    }
    // The child that runs, or ran, after the first child's last failure:
    // a RecoveryNode whose first child failed again at 6:1 has not fallen
    // back to the recovery it ran at 4:6.
    let failed_at = run.last_failure_since(children[0], since);
    let handler = children[1..].iter().copied().find(|&c| {
        run.status(c).is_active()
            || match (failed_at, run.last_completion(c)) {
                (Some(f), Some((q, _))) => q > f,
                _ => run.last_completed(c).is_some(),
            }
    });
    d.fell_back = Some((x, handler));
}

/// The first child of `x` failed where the run does not show the leaf:
/// before recording began, or the leaf has succeeded since.
fn failed_unseen(tree: &Tree, run: &At, x: Uid, d: &mut Diagnosis) {
    match failed_before(tree, run, tree.node(x).children[0])[..] {
        // The leaf that failed has succeeded since (a later attempt).
        [] => d.text = format!("I could not {} earlier.", tree.deed(x)),
        [f] => {
            d.text.push_str(&format!(
                "{} failed, {}.",
                tree.spoken(f),
                read_at(run, "before")
            ));
            d.failed_leaf = Some(f);
            d.nodes.push(f);
        }
        ref fs => {
            d.text.push_str(&format!(
                "one of {} failed, {} (which one, the statuses it read do not say).",
                described(tree, fs),
                read_at(run, "before")
            ));
            d.nodes.extend(fs);
        }
    }
}

/// "I am retrying for attempt N to X. I could not Y because Z failed.":
/// the retry `x` and the leaf whose failure it retries.
fn retrying(tree: &Tree, run: &At, x: Uid, d: &mut Diagnosis) {
    let a = run.attempts(x);
    d.retrying.push((x, a));
    let rp = named_ancestor(tree, x);
    d.text = format!(
        "I am retrying for attempt {a} to {}. ",
        tree.deed(rp.unwrap_or(x))
    );
    d.nodes.extend(rp);
    if let Some(f) = last_failed_leaf(tree, run, x, run.started_at(x)) {
        let fp = named_ancestor(tree, f).unwrap_or(x);
        d.text.push_str(&format!(
            "I could not {} because {} failed.",
            tree.deed(fp),
            tree.spoken(f)
        ));
        d.failed_leaf = Some(f);
        d.nodes.extend([fp, f]);
    }
    d.text = d.text.trim_end().to_string();
}

/// Lines 25-33: a Retry above the Fallback `fb` is retrying too.
fn retries_above(tree: &Tree, run: &At, fb: Uid, d: &mut Diagnosis) {
    let mut p = tree.parent(fb);
    while let Some(x) = p {
        if tree.node(x).kind == Kind::SubTree {
            break;
        }
        if is_retry(tree, x) && run.attempts(x) > 0 {
            let a = run.attempts(x);
            d.retrying.push((x, a));
            if let Some(rp) = named_ancestor(tree, x) {
                d.text.push_str(&format!(
                    " I am retrying for attempt {a} to {}.",
                    tree.deed(rp)
                ));
                d.nodes.push(rp);
            }
        }
        p = tree.parent(x);
    }
}

/// Leaves below `p` whose last completion, FAILURE, came before recording
/// began (a run recorded from its middle): when, the run does not say.
fn failed_before(tree: &Tree, run: &At, p: Uid) -> Vec<Uid> {
    tree.descendants(p)
        .filter(|&u| tree.node(u).kind.is_leaf())
        .filter(|&u| run.done_before(u) == Some(Status::Failure))
        .collect()
}

/// When btx last read every node's state rather than followed it ("when
/// btx attached", or after a gap), with `at` ("when", "before") first.
fn read_at(run: &At, at: &str) -> String {
    match run.index.resync_at(run.pos) {
        Some((0, _)) | None => format!("{at} btx attached"),
        Some((p, _)) => {
            format!("{at} btx read the statuses again after a gap (after transition {p})")
        }
    }
}

fn described(tree: &Tree, nodes: &[Uid]) -> String {
    let names: Vec<String> = nodes
        .iter()
        .map(|&u| format!("{} (#{u})", tree.spoken(u)))
        .collect();
    super::han::and_list(&names)
}

/// Beyond Algorithm 7, which knows Fallbacks and Retries: a control node
/// or decorator whose handling of a failure btx does not know (a custom
/// one) or that Algorithm 7 leaves out (TryCatch), with a child that failed
/// in its current run: the first such child, as Algorithm 7 tests a
/// Fallback's first child. Its failure went somewhere other than up, or the
/// node would have completed.
fn handled_elsewhere(tree: &Tree, run: &At, x: Uid) -> Option<Uid> {
    let n = tree.node(x);
    let unknown = n.builtin.is_none() && matches!(n.kind, Kind::Control | Kind::Decorator);
    if !(unknown || n.builtin == Some(Builtin::TryCatch)) || !run.status(x).is_active() {
        return None;
    }
    let since = run.started_at(x);
    n.children
        .iter()
        .copied()
        .find(|&c| run.last_failure_since(c, since).is_some())
}

/// What went wrong below `x` (see `handled_elsewhere`): child `c` failed,
/// and why; for a node btx does not know, that what it did about it btx
/// cannot tell.
fn failed_under(tree: &Tree, run: &At, x: Uid, c: Uid, d: &mut Diagnosis) {
    d.text = failed_because(tree, run, c, run.started_at(x), x, d);
    if tree.node(x).builtin.is_none() {
        d.nodes.push(x);
        d.text.push_str(&format!(
            " What {} (#{x}) did about it, btx cannot tell: it does not know how a {} handles a failure.",
            tree.spoken(x),
            tree.node(x).id
        ));
    }
}

/// Beyond Algorithm 7: between a failure and what handles it. Within a
/// tick, a node above the current one has failed and its parent has not
/// yet done anything about it (a Fallback whose last child failed, before
/// the Retry above it starts again): the highest such node, and the leaf
/// whose failure it was. Nothing has gone right again yet.
fn failing_now(tree: &Tree, run: &At, n: Uid, d: &mut Diagnosis) {
    let Some(x) = std::iter::once(n)
        .chain(tree.ancestors(n))
        .filter(|&a| run.status(a) == Status::Failure)
        .last()
    else {
        return;
    };
    d.text = failed_because(tree, run, x, run.started_at(x), x, d);
}

/// "I could not X because L failed.", for node `c` that failed in its run
/// since `since`: X is `c` if it has a name, else its nearest named
/// ancestor (else `or`), and L the leaf below it that failed last; or "C
/// failed." when no other leaf did.
fn failed_because(tree: &Tree, run: &At, c: Uid, since: u32, or: Uid, d: &mut Diagnosis) -> String {
    let what = if tree.has_name(c) {
        c
    } else {
        named_ancestor(tree, c).unwrap_or(or)
    };
    d.nodes.push(what);
    match last_failed_leaf(tree, run, c, since).filter(|&f| f != c) {
        Some(f) => {
            d.failed_leaf = Some(f);
            d.nodes.push(f);
            format!(
                "I could not {} because {} failed.",
                tree.deed(what),
                tree.spoken(f)
            )
        }
        None => {
            d.failed_leaf = tree.node(c).kind.is_leaf().then_some(c);
            format!("{} failed.", capitalised(&tree.spoken(c)))
        }
    }
}

fn capitalised(s: &str) -> String {
    let mut c = s.chars();
    c.next()
        .map_or_else(String::new, |f| f.to_uppercase().chain(c).collect())
}

/// Nothing went wrong in what the run recorded, and the statuses read when
/// recording began show every Fallback's state exactly; but a Retry above
/// `n` was running then, and how many attempts it had used they do not
/// say (a failed attempt is reset, and a later success hides it). Say so,
/// rather than "Nothing went wrong", naming the leaves below it whose last
/// completion then was FAILURE.
fn attached_unknown(tree: &Tree, run: &At, n: Uid, d: &mut Diagnosis) {
    let Some((read, _)) = run.index.resync_at(run.pos) else {
        return;
    };
    let mut p = tree.parent(n);
    let mut retry = None;
    while let Some(x) = p {
        if tree.node(x).kind == Kind::SubTree {
            break;
        }
        if is_retry(tree, x) && run.started_at(x) <= read && run.status(x) == Status::Running {
            retry = Some(x);
            break;
        }
        p = tree.parent(x);
    }
    let Some(r) = retry else { return };
    let failed = failed_before(tree, run, r);
    d.text = match failed.as_slice() {
        [] => format!(
            "I cannot tell: I was already running {} (#{r}) {}, and whether an attempt of it had failed before that, the statuses btx read do not say.",
            tree.spoken(r),
            read_at(run, "when")
        ),
        fs => format!(
            "I cannot tell: I was already running {} (#{r}) {}, and {} had last failed before that; whether that was in this run of it, the statuses btx read do not say.",
            tree.spoken(r),
            read_at(run, "when"),
            described(tree, fs)
        ),
    };
    d.unknown = true;
    d.nodes.push(r);
    d.nodes.extend(failed);
}

/// Beyond Algorithm 7: the root itself failed (through a Timeout, a
/// reactive guard, a Parallel threshold, or a failure nothing handled), so
/// say what ended the task.
fn root_failure(tree: &Tree, run: &At, d: &mut Diagnosis) {
    let since = run.run_start();
    let ended = match last_failed_leaf(tree, run, Tree::ROOT, since) {
        Some(leaf) => {
            let stopped = stopped_above(tree, leaf);
            d.failed_leaf = Some(leaf);
            d.nodes.extend([stopped, leaf]);
            // An unnamed root is the task itself, not a "Sequence".
            if stopped == Tree::ROOT && !tree.has_name(stopped) {
                format!("{} failed.", tree.spoken(leaf))
            } else {
                format!(
                    "{} stopped because {} failed.",
                    tree.spoken(stopped),
                    tree.spoken(leaf)
                )
            }
        }
        None => {
            // No leaf failed: a node failed of its own accord (a Timeout
            // that ran out, a Parallel that could no longer succeed). Take
            // the deepest node that failed in this run.
            let deepest = tree
                .descendants(Tree::ROOT)
                .filter(|&u| run.last_failure_since(u, since).is_some())
                .filter(|&u| {
                    tree.node(u)
                        .children
                        .iter()
                        .all(|&c| run.last_failure_since(c, since).is_none())
                })
                .last()
                .unwrap_or(Tree::ROOT);
            let node = tree.node(deepest);
            match node.builtin {
                Some(Builtin::Timeout) => {
                    d.nodes.push(deepest);
                    format!("{} stopped because its time ran out.", tree.spoken(deepest))
                }
                Some(Builtin::Inverter) if node.children.len() == 1 => {
                    let child = node.children[0];
                    let stopped = stopped_above(tree, deepest);
                    d.failed_leaf = Some(child);
                    d.nodes.extend([stopped, deepest, child]);
                    format!(
                        "{} stopped because {}",
                        tree.spoken(stopped),
                        inverted_text(tree, deepest, child)
                    )
                }
                _ => {
                    d.nodes.push(deepest);
                    format!("{} failed.", tree.spoken(deepest))
                }
            }
        }
    };
    d.text = format!("The task failed: {ended}");
}

/// A check that came out the wrong way round below `p` since `since`: the
/// last Inverter (in tree order) that failed while its child did not, with
/// that child. No leaf failed, yet `p` did.
fn inverted_failure(tree: &Tree, run: &At, p: Uid, since: u32) -> Option<(Uid, Uid)> {
    tree.descendants(p)
        .filter(|&u| {
            let n = tree.node(u);
            n.builtin == Some(Builtin::Inverter)
                && n.children.len() == 1
                && run.last_failure_since(u, since).is_some()
                && run.last_failure_since(n.children[0], since).is_none()
        })
        .last()
        .map(|u| (u, tree.node(u).children[0]))
}

fn inverted_text(tree: &Tree, inverter: Uid, child: Uid) -> String {
    let inverter = if tree.has_name(inverter) {
        tree.spoken(inverter)
    } else {
        "the inverter above it".to_string()
    };
    format!(
        "{} succeeded and {inverter} turned that into a failure.",
        tree.spoken(child)
    )
}

/// The nearest named ancestor, not a decorator and not named like `uid`,
/// that stopped because `uid` failed (the root if none).
fn stopped_above(tree: &Tree, uid: Uid) -> Uid {
    tree.ancestors(uid)
        .find(|&a| {
            !tree.is_decorator(a)
                && tree.has_name(a)
                && tree.description(a) != tree.description(uid)
        })
        .unwrap_or(Tree::ROOT)
}

pub const NOTHING_WRONG: &str = "Nothing went wrong.";

/// Nothing is failing now: "Nothing went wrong.", or, when leaves failed
/// earlier in the root's current run and were recovered from, that
/// history ("Nothing is wrong now. Follow path failed at ticks 6 and 8;
/// navigate recovery (#1) ran clear local costmap and succeeded at tick
/// 10."): a person who saw the failure asks about it.
fn nothing_now(tree: &Tree, run: &At, n: Uid) -> (String, Vec<Uid>) {
    let (before, mut earlier) = said_failed_before(tree, run);
    match history(tree, run) {
        Some((text, mut nodes)) => {
            nodes.append(&mut earlier);
            (format!("Nothing is wrong now. {text}{before}"), nodes)
        }
        None if !earlier.is_empty() => (
            format!("Nothing went wrong since recording began.{before}"),
            earlier,
        ),
        None => (NOTHING_WRONG.to_string(), vec![n]),
    }
}

/// A run recorded from its middle (btx attached to a running robot): the
/// leaves whose last completion before then was a failure, said as what
/// the states read show, since the transitions are not in the session.
fn said_failed_before(tree: &Tree, run: &At) -> (String, Vec<Uid>) {
    // Failed before, whatever came since: what recovered from it, if
    // anything did, the transitions since may show.
    if !run.index.attached() {
        return (String::new(), Vec::new());
    }
    let leaves: Vec<Uid> = tree
        .descendants(Tree::ROOT)
        .filter(|&u| tree.node(u).kind.is_leaf())
        .filter(|&u| run.index.before(u).1 == Some(Status::Failure))
        .collect();
    if leaves.is_empty() {
        return (String::new(), leaves);
    }
    let names: Vec<String> = leaves.iter().map(|&u| tree.spoken(u)).collect();
    (
        format!(
            " Before recording began, {} had last failed: how, and what handled it, is not in the session.",
            and_list(&names)
        ),
        leaves,
    )
}

/// The leaves that failed in the root's current run, by the ticks they
/// failed in, and what recovered from the last of them.
pub fn history(tree: &Tree, run: &At) -> Option<(String, Vec<Uid>)> {
    let since = run.run_start();
    let mut failed: Vec<(Uid, Vec<u32>)> = Vec::new();
    let mut last = None;
    let mut first = None;
    for p in since + 1..=run.pos {
        let t = run.index.transitions[p as usize - 1];
        if t.status != Status::Failure || !tree.node(t.uid).kind.is_leaf() {
            continue;
        }
        last = Some((t.uid, p));
        first.get_or_insert(p);
        match failed.iter_mut().find(|(u, _)| *u == t.uid) {
            Some((_, ticks)) if ticks.last() == Some(&t.tick) => {}
            Some((_, ticks)) => ticks.push(t.tick),
            None => failed.push((t.uid, vec![t.tick])),
        }
    }
    let (leaf, at) = last?;
    let said: Vec<String> = failed
        .iter()
        .map(|(u, ticks)| {
            let ts: Vec<String> = ticks.iter().map(u32::to_string).collect();
            let which = if ticks.len() == 1 { "tick" } else { "ticks" };
            format!("{} failed at {which} {}", tree.spoken(*u), and_list(&ts))
        })
        .collect();
    let mut nodes: Vec<Uid> = failed.iter().map(|(u, _)| *u).collect();
    let mut text = capitalise(&said.join("; "));
    let from = first.unwrap_or(at);
    if let Some((h, done, ran)) = recovered_by(tree, run, leaf, at, from) {
        let (said, handlers) = recovery_said(tree, run, h, done, &ran);
        text.push_str(&said);
        nodes.extend(handlers);
        nodes.extend(ran.iter().map(|&(_, u)| u));
    }
    Some((format!("{text}."), nodes))
}

/// How the handler `h` recovered by position `done`, running `ran`: first
/// what each handler below it tried and failed, then `h`'s own recovery;
/// with the handlers told of.
fn recovery_said(
    tree: &Tree,
    run: &At,
    h: Uid,
    done: u32,
    ran: &[Recovered],
) -> (String, Vec<Uid>) {
    // What one handler ran, each deed once.
    let deeds_of = |by: Uid| {
        let mut deeds: Vec<String> = Vec::new();
        for d in ran
            .iter()
            .filter(|&&(g, _)| g == by)
            .map(|&(_, u)| tree.deed(u))
        {
            if !deeds.contains(&d) {
                deeds.push(d);
            }
        }
        deeds
    };
    let mut text = String::new();
    let mut nodes = Vec::new();
    // A handler below `h` that ran its recovery first, and failed: its
    // recovery is its own, not `h`'s.
    let mut inner: Vec<Uid> = Vec::new();
    for &(g, _) in ran {
        if g != h && !inner.contains(&g) {
            inner.push(g);
        }
    }
    for g in inner {
        let said = and_list(&deeds_of(g));
        // A RecoveryNode goes back to its first child; a Fallback
        // does not.
        let how = if tree.node(g).builtin == Some(Builtin::RecoveryNode) {
            format!("first recovered ({said}) and tried again, which failed")
        } else {
            format!("first fell back ({said}) and failed")
        };
        text.push_str(&format!("; {} {how}", tree.told(g)));
        nodes.push(g);
    }
    let deeds = deeds_of(h);
    let how = match tree.node(h).builtin {
        Some(Builtin::RetryUntilSuccessful) => "tried again and".to_string(),
        _ if deeds.is_empty() => "went on and".to_string(),
        _ => format!("recovered ({}) and", and_list(&deeds)),
    };
    text.push_str(&format!(
        "; {} (#{h}) {how} succeeded at tick {}",
        tree.spoken(h),
        run.index.transitions[done as usize - 1].tick
    ));
    nodes.push(h);
    (text, nodes)
}

/// A handler, and a leaf that ran in its recovery.
pub type Recovered = (Uid, Uid);

/// The node above `leaf` that handled its failure at position `at` and
/// succeeded afterwards (by this moment): a Fallback, a Retry or a
/// RecoveryNode. With the position of its success and the recovery
/// actions that succeeded from position `from` (the first failure) on.
pub fn recovered_by(
    tree: &Tree,
    run: &At,
    leaf: Uid,
    at: u32,
    from: u32,
) -> Option<(Uid, u32, Vec<Recovered>)> {
    let (h, end) = recovery(tree, run, leaf, at)?;
    // What ran to recover: leaves in the later children of a Fallback
    // or RecoveryNode between `h` and them (the nominal steps that
    // went on are not a recovery).
    // Only a handler of this failure (an ancestor of the leaf) recovers:
    // a Fallback beside it that took its second child is a branch taken.
    let handler_of = |u: Uid| -> Option<Uid> {
        let mut c = u;
        while let Some(p) = tree.parent(c) {
            let fallback = matches!(
                tree.node(p).builtin,
                Some(
                    Builtin::Fallback
                        | Builtin::ReactiveFallback
                        | Builtin::AsyncFallback
                        | Builtin::RecoveryNode
                )
            );
            if fallback && tree.node(p).children.first() != Some(&c) {
                return Some(p);
            }
            if p == h {
                return None;
            }
            c = p;
        }
        None
    };
    let in_recovery = |u: Uid| handler_of(u).is_some_and(|f| f == h || tree.is_ancestor(f, leaf));
    let mut ran: Vec<Recovered> = Vec::new();
    for q in from + 1..end {
        let t = run.index.transitions[q as usize - 1];
        if t.status == Status::Success
            && tree.node(t.uid).kind.is_leaf()
            && tree.is_ancestor(h, t.uid)
            && in_recovery(t.uid)
            && !ran.iter().any(|&(_, l)| l == t.uid)
        {
            ran.push((handler_of(t.uid).unwrap_or(h), t.uid));
        }
    }
    Some((h, end, ran))
}

/// The handler above `node` (a Fallback, a Retry or a RecoveryNode) that
/// succeeded after its failure at position `at` (by this moment), and the
/// position of that success; `None` when every handler failed too, or had
/// not completed yet.
pub fn recovery(tree: &Tree, run: &At, node: Uid, at: u32) -> Option<(Uid, u32)> {
    for h in tree.ancestors(node).filter(|&a| handles_failure(tree, a)) {
        let changes = run.index.changes_of(h);
        let after = changes.partition_point(|&q| q <= at);
        let end = changes[after..]
            .iter()
            .copied()
            .take_while(|&q| q <= run.pos)
            .find(|&q| {
                matches!(
                    run.index.transitions[q as usize - 1].status,
                    Status::Success | Status::Failure
                )
            })?;
        if run.index.transitions[end as usize - 1].status == Status::Success {
            return Some((h, end));
        }
    }
    None
}

/// A node that handles its children's failures: a Fallback tries the next
/// child, a Retry tries again, a RecoveryNode runs its recovery.
pub fn handles_failure(tree: &Tree, uid: Uid) -> bool {
    matches!(
        tree.node(uid).builtin,
        Some(
            Builtin::Fallback
                | Builtin::ReactiveFallback
                | Builtin::AsyncFallback
                | Builtin::RetryUntilSuccessful
                | Builtin::RecoveryNode
        )
    )
}

fn capitalise(s: &str) -> String {
    let mut c = s.chars();
    c.next().map_or(String::new(), |f| {
        f.to_uppercase().collect::<String>() + c.as_str()
    })
}

/// "What went wrong?"
pub fn what_went_wrong(tree: &Tree, run: &At, n: Uid) -> (String, Vec<Uid>) {
    let d = diagnose(tree, run, n);
    if d.text.is_empty() {
        nothing_now(tree, run, n)
    } else {
        (d.text, d.nodes)
    }
}

/// "Was there anything wrong?"
pub fn anything_wrong(tree: &Tree, run: &At, n: Uid) -> (String, Vec<Uid>) {
    let d = diagnose(tree, run, n);
    if d.text.is_empty() {
        nothing_now(tree, run, n)
    } else if d.unknown {
        (d.text, d.nodes)
    } else {
        (format!("Yes. {}", d.text), d.nodes)
    }
}

/// The handler a fallback fell back to: "fell back to run the X" reads as
/// "fell back to the X", and an unnamed handler is said as what it runs,
/// not as its type ("the sequence").
fn fell_back_to(tree: &Tree, h: Uid) -> String {
    let deed = tree.deed(h);
    if tree.has_name(h) || tree.node(h).children.is_empty() {
        return deed.strip_prefix("run ").unwrap_or(&deed).to_string();
    }
    let parts: Vec<String> = tree
        .node(h)
        .children
        .iter()
        .map(|&c| format!("{} (#{c})", tree.description(c)))
        .collect();
    let parts: Vec<&str> = parts.iter().map(String::as_str).collect();
    format!(
        "the {} (#{h}) of {}",
        tree.node(h).id,
        super::han::and_list(&parts)
    )
}

/// "I am retrying to X: N attempts failed, this is attempt N+1 of M.":
/// the Retry `r` (of the named `rp`) after `a` failed attempts.
fn retrying_text(tree: &Tree, r: Uid, rp: Uid, a: u32) -> String {
    let max = tree
        .node(r)
        .ports
        .iter()
        .find(|p| p.name == "num_attempts")
        .and_then(|p| match &p.value {
            crate::model::PortValue::Literal(s) => s.trim().parse::<i64>().ok(),
            _ => None,
        });
    let of = match max {
        Some(m) if m > 0 => format!(" of {m}"),
        _ => String::new(),
    };
    format!(
        "I am retrying to {}: {} attempt{} failed, this is attempt {}{of}.",
        tree.deed(rp),
        a,
        if a == 1 { "" } else { "s" },
        a + 1
    )
}

/// "How was the failure handled?"
pub fn how_handled(tree: &Tree, run: &At, n: Uid) -> (String, Vec<Uid>) {
    let d = diagnose(tree, run, n);
    if d.text.is_empty() {
        return nothing_now(tree, run, n);
    }
    if d.unknown {
        return (d.text, d.nodes);
    }
    let mut parts = Vec::new();
    let mut nodes = Vec::new();
    if let Some((fb, handler)) = d.fell_back {
        nodes.push(fb);
        // Asked at the failure itself, nothing has run in its place yet
        // (said below).
        if let Some(h) = handler {
            let first = tree.node(fb).children[0];
            parts.push(format!(
                "When {} failed, I fell back to {}.",
                tree.spoken(first),
                fell_back_to(tree, h)
            ));
            nodes.push(h);
        }
    }
    for &(r, a) in &d.retrying {
        let rp = named_ancestor(tree, r).unwrap_or(r);
        parts.push(retrying_text(tree, r, rp, a));
        nodes.extend([r, rp]);
    }
    if parts.is_empty() && run.status(Tree::ROOT) == Status::Running {
        // Asked at the failure itself: what handles it comes after.
        return (
            format!(
                "{} Nothing has handled it yet at {}: the run goes on.",
                d.text,
                run.index.moment(run.pos)
            ),
            d.nodes,
        );
    }
    if parts.is_empty() {
        // The root failed and nothing above the failure handled it.
        return (format!("{} Nothing handled the failure.", d.text), d.nodes);
    }
    (parts.join(" "), nodes)
}

#[cfg(test)]
mod tests;
