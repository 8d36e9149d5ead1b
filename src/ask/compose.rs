//! Query → answer: each intent answered from the run's record (when,
//! how often, what happened at a tick, did the recovery work), from the
//! tree (what next, what if), by Han's algorithms (`explain`) or by the
//! counterfactual search (`causal`). Each answer restates what it
//! answers, so that a misreading shows.

use super::context::{events, is_event, run_of, Context};
use super::nodes::{resolve, Unresolved};
use super::parse::{Event, Intent, Subject, Which};
use super::say::{moments, past, step_moment, times, upper, verb};
use super::Reply;
use crate::explain::han::and_list;
use crate::model::{Builtin, Tree, Uid};
use crate::run::Status;
use crate::session::{At, Moment};

/// The answer to a question btx understood; `failed`, where a question of
/// recovery names the failure it asks about, is its position in the run.
pub fn compose(cx: &Context, question: &str, intent: &Intent, failed: Option<u32>) -> Reply {
    let mut r = Reply::new(question, Some(intent.short()));
    r.moment = cx.at.as_ref().map(|a| a.moment().to_string());
    let done = match intent {
        Intent::Fixed(crate::explain::Question::Run(crate::explain::RunQuestion::Handled))
            if failed.is_some() =>
        {
            handled(cx, &mut r, failed.unwrap_or_default())
        }
        Intent::Fixed(q) => super::fixed::answer(cx, q, &mut r),
        Intent::Why { node, event, foil } => with_node(cx, node, Some(*event), &mut r, |u, r| {
            super::why::answer(cx, u, *event, *foil, r)
        }),
        Intent::WhyNot { done, instead } => {
            with_node(cx, done, Some(Event::Run), &mut r, |d, r| {
                // Of the nodes the other words name, the one nearest.
                let instead = match instead {
                    Subject::Nodes(us, p) => Subject::Nodes(nearest(cx.tree, d, us), p.clone()),
                    other => other.clone(),
                };
                with_node(cx, &instead, None, r, |i, r| {
                    super::why::instead(cx, d, i, r)
                })
            })
        }
        // When and how often: every node the words name, each in its line.
        Intent::When { node, event, which } => counted(cx, node, *event, &mut r, |u, r| {
            when(cx, u, *event, *which, r)
        }),
        Intent::HowOften { node, event } => {
            counted(cx, node, *event, &mut r, |u, r| how_often(cx, u, *event, r))
        }
        Intent::Tick(n) => {
            // 0: the tick of the moment the question named ("the last tick").
            let n = match (*n, cx.at.as_ref()) {
                (0, Some(at)) => cx.tick.unwrap_or_else(|| at.moment().tick),
                (n, _) => n,
            };
            tick(cx, n, &mut r)
        }
        Intent::Recovered => recovered(cx, &mut r, failed),
        // At a moment of a recorded run, the tree is run on from there.
        Intent::Next if cx.node.is_none() && cx.session.is_some() && cx.at.is_some() => {
            ahead(cx, &mut r)
        }
        Intent::Next => match cx.node.or_else(|| cx.at.as_ref().and_then(|a| a.current())) {
            Some(u) => next(cx, u, Status::Success, &mut r, true),
            None => Err(
                "nothing runs at this moment, so nothing comes next; pick a node with --node"
                    .into(),
            ),
        },
        Intent::WhatIf { node, event } => {
            // "What if FollowPath had succeeded?" asks of the one that did
            // not: of nodes named alike, those that failed, where some did.
            let node = match (node, cx.at.as_ref()) {
                (Subject::Nodes(us, p), Some(at)) if us.len() > 1 && *event == Event::Succeed => {
                    let failed = by_event(cx.tree, at, us, Event::Fail);
                    if failed.len() < us.len() {
                        Subject::Nodes(failed, p.clone())
                    } else {
                        node.clone()
                    }
                }
                _ => node.clone(),
            };
            with_node(cx, &node, Some(Event::Run), &mut r, |u, r| match event {
                Event::KeepRunning => keeps_running(cx, u, r),
                Event::Fail => next(cx, u, Status::Failure, r, false),
                _ => next(cx, u, Status::Success, r, false),
            })
        }
    };
    if let Err(e) = done {
        r.answer = e;
        r.answered = false;
    }
    r
}

/// `with_node` for a question that counts an event ("when", "how
/// often"): where the words name several nodes and only one ever had the
/// event, the answer is about that one and says the others never had it.
fn counted(
    cx: &Context,
    who: &Subject,
    event: Event,
    r: &mut Reply,
    f: impl Fn(Uid, &mut Reply) -> Result<(), String>,
) -> Result<(), String> {
    with_node(cx, who, Some(event), r, f)?;
    let (Subject::Nodes(all, _), Some(at), Some(u)) = (who, cx.at.as_ref(), r.about) else {
        return Ok(());
    };
    // None had it: `with_node` answered each, and "also names" would say
    // the one answered had.
    if all.len() < 2 || !all.contains(&u) || events(at, u, event).is_empty() {
        return Ok(());
    }
    let rest: Vec<Uid> = all
        .iter()
        .copied()
        .filter(|&v| v != u && events(at, v, event).is_empty())
        .collect();
    // Several had it: `with_node` answered each and said the rest.
    if rest.is_empty() || rest.len() + 1 != all.len() {
        return Ok(());
    }
    let labels = told_apart(cx.tree, all);
    let line = also_named(cx, all, &labels, &rest, cx.tree.description(u), event);
    r.answer.push('\n');
    r.answer.push_str(&line);
    r.nodes.extend(rest);
    Ok(())
}

/// "GoalUpdated also names the condition under … (#7), which never
/// succeeded by …": nodes the words name that the event never happened to,
/// by their `labels` among `all`.
fn also_named(
    cx: &Context,
    all: &[Uid],
    labels: &[String],
    rest: &[Uid],
    name: &str,
    e: Event,
) -> String {
    let kinds: Vec<String> = rest
        .iter()
        .map(|&v| labels[all.iter().position(|&a| a == v).unwrap_or(0)].clone())
        .collect();
    format!(
        "{} also names {}, which {} {}.",
        crate::causal::english::capitalised(name),
        and_list(&kinds),
        never(e),
        cx.at.as_ref().map_or(String::new(), |at| cx.by(at))
    )
}

/// Runs `f` on the node a subject names. Nodes that share the words are
/// told apart by what the run shows at the moment (the one that failed
/// then, for a why about a failure); otherwise each is answered in a line
/// of its own, never one of them picked silently.
fn with_node(
    cx: &Context,
    who: &Subject,
    event: Option<Event>,
    r: &mut Reply,
    f: impl Fn(Uid, &mut Reply) -> Result<(), String>,
) -> Result<(), String> {
    let named_alike: Vec<Uid> = match who {
        Subject::Nodes(us, _) => us.clone(),
        _ => Vec::new(),
    };
    let who = match (who, event, cx.at.as_ref()) {
        (Subject::It, Some(Event::Fail), Some(at)) => robots_failures(cx, at).map_or_else(
            || Subject::Nodes(vec![cx.it()], "it".into()),
            |u| Subject::Nodes(vec![u], "it".into()),
        ),
        (Subject::It, _, _) => Subject::Nodes(vec![cx.it()], "it".into()),
        (Subject::Nodes(us, p), Some(e), Some(at)) if us.len() > 1 => {
            Subject::Nodes(by_event(cx.tree, at, us, e), p.clone())
        }
        (w, _, _) => w.clone(),
    };
    match resolve(cx.tree, &who, cx.at.as_ref()) {
        Ok(u) => {
            r.about.get_or_insert(u);
            f(u, r)
        }
        Err(Unresolved::Several(us)) => each_named(cx, &who, &us, &named_alike, event, r, f),
        Err(Unresolved::Unknown(close)) => {
            let p = match &who {
                Subject::Named(p) | Subject::Nodes(_, p) => p.clone(),
                _ => unreachable!("the task is one node"),
            };
            let names: Vec<String> = close.iter().map(|&u| cx.name(u)).collect();
            Err(format!(
                "No node of the tree is called \"{p}\". The closest: {}.",
                and_list(&names)
            ))
        }
    }
}

/// "How many times did it fail to spot it?", "when did it stall for the
/// last time?": a failure asked of the robot (no node asked of before it,
/// none picked) while the task itself never failed is its actions'. The
/// one action that failed by the moment, if only one did.
fn robots_failures(cx: &Context, at: &At) -> Option<Uid> {
    let root = cx.tree.root().uid;
    if cx.last.get().is_some() || cx.node.is_some() || !events(at, root, Event::Fail).is_empty() {
        return None;
    }
    let mut failed = cx
        .tree
        .nodes
        .iter()
        .filter(|n| n.kind.is_leaf() && !events(at, n.uid, Event::Fail).is_empty());
    match (failed.next(), failed.next()) {
        (Some(n), None) => Some(n.uid),
        _ => None,
    }
}

/// Nodes named alike, each answered in a line of its own under the name
/// they share; those the event never happened to said too.
fn each_named(
    cx: &Context,
    who: &Subject,
    us: &[Uid],
    named_alike: &[Uid],
    event: Option<Event>,
    r: &mut Reply,
    f: impl Fn(Uid, &mut Reply) -> Result<(), String>,
) -> Result<(), String> {
    let phrase = match &who {
        Subject::Named(p) | Subject::Nodes(_, p) => p.clone(),
        _ => unreachable!("the task is one node"),
    };
    // The name as the XML writes it, where they all share it.
    let d = cx.tree.description(us[0]);
    let phrase = if us.iter().all(|&u| cx.tree.description(u) == d) {
        d.to_string()
    } else {
        phrase
    };
    // Told apart among every node the words name, so that those
    // the event never happened to can be said too: "names X and Y"
    // alone would say they are all.
    let all: Vec<Uid> = if us.iter().all(|u| named_alike.contains(u)) {
        named_alike.to_vec()
    } else {
        us.to_vec()
    };
    let labels = told_apart(cx.tree, &all);
    let label = |u: Uid| labels[all.iter().position(|&a| a == u).unwrap_or(0)].clone();
    let kinds: Vec<String> = us.iter().map(|&u| label(u)).collect();
    let mut lines = vec![format!(
        "{} names {}.",
        crate::causal::english::capitalised(&phrase),
        and_list(&kinds)
    )];
    for (&u, kind) in us.iter().zip(&kinds) {
        let mut sub = Reply::new(&r.question, r.short);
        let said = match f(u, &mut sub) {
            Ok(()) => sub.answer.clone(),
            Err(e) => e,
        };
        // Other nodes named alike within it ("rather than spin or back up"
        // of each ComputePathToPose): each of theirs, indented.
        let first = if sub.nodes.len() > 1 && said.contains(" names ") && said.contains('\n') {
            said.lines()
                .map(|l| format!("  {l}"))
                .collect::<Vec<_>>()
                .join("\n")
                .trim_start()
                .to_string()
        } else {
            super::detail::first_sentence(&said)
        };
        lines.push(format!(
            "{}: {first}",
            crate::causal::english::capitalised(kind)
        ));
        if r.understood.is_empty() {
            r.understood = sub
                .understood
                .replace(&cx.name(u), &format!("{phrase} ({})", hashes(us)));
        }
        r.nodes.extend(sub.nodes);
        r.nodes.push(u);
    }
    let rest: Vec<Uid> = all.iter().copied().filter(|u| !us.contains(u)).collect();
    if let (false, Some(e)) = (rest.is_empty(), event) {
        lines.push(also_named(cx, &all, &labels, &rest, &phrase, e));
        r.nodes.extend(rest);
    }
    r.about = us.first().copied();
    r.answer = lines.join("\n");
    Ok(())
}

fn hashes(us: &[Uid]) -> String {
    us.iter()
        .map(|u| format!("#{u}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Nodes a question's words name alike, each told apart from the others:
/// by its kind ("the RecoveryNode (#9)", "the action (#10)"), else by its
/// own name ("ClearLocalCostmap-Context (#13)"), else by its parent.
fn told_apart(tree: &Tree, us: &[Uid]) -> Vec<String> {
    let kind = |u: Uid| {
        let n = tree.node(u);
        match n.kind {
            crate::model::Kind::Action => "the action".to_string(),
            crate::model::Kind::Condition => "the condition".to_string(),
            crate::model::Kind::SubTree => "the subtree".to_string(),
            _ => format!("the {}", n.id),
        }
    };
    let distinct = |f: &dyn Fn(Uid) -> String| {
        let all: Vec<String> = us.iter().map(|&u| f(u)).collect();
        let mut seen = all.clone();
        seen.sort();
        seen.dedup();
        (seen.len() == all.len()).then_some(all)
    };
    let labels = distinct(&kind)
        .or_else(|| distinct(&|u| tree.description(u).to_string()))
        .unwrap_or_else(|| {
            us.iter()
                .map(|&u| match tree.parent(u) {
                    Some(p) => format!("{} under {}", kind(u), tree.description(p)),
                    None => kind(u),
                })
                .collect()
        });
    labels
        .into_iter()
        .zip(us)
        .map(|(l, u)| format!("{l} (#{u})"))
        .collect()
}

/// Among nodes that share a name, those the event happened to: the one
/// whose transition is the moment itself, else the ones it happened to by
/// then; all of them when it happened to none.
fn by_event(tree: &Tree, at: &At, us: &[Uid], e: Event) -> Vec<Uid> {
    if at.pos > 0 {
        let t = at.index.transitions[at.pos as usize - 1];
        if us.contains(&t.uid) && is_event(t.prev, t.status, e) {
            return vec![t.uid];
        }
    }
    let had: Vec<Uid> = us
        .iter()
        .copied()
        .filter(|&u| !events(at, u, e).is_empty())
        .collect();
    if had.is_empty() {
        return us.to_vec();
    }
    // A failure inside a node named alike (Nav2's FollowPath action under
    // the FollowPath RecoveryNode) is the cause of the outer one's: it is
    // answered first.
    let mut had = had;
    if e == Event::Fail {
        let outer = |u: Uid| {
            had.iter()
                .filter(|&&v| v != u && tree.is_ancestor(v, u))
                .count()
        };
        let mut keyed: Vec<(usize, Uid)> = had.iter().map(|&u| (outer(u), u)).collect();
        keyed.sort_by_key(|&(k, _)| std::cmp::Reverse(k));
        had = keyed.into_iter().map(|(_, u)| u).collect();
    }
    had
}

/// Of `us`, those nearest to `d` in the tree (the deepest common ancestor).
fn nearest(tree: &Tree, d: Uid, us: &[Uid]) -> Vec<Uid> {
    let depth_shared = |u: Uid| {
        tree.ancestors(u)
            .find(|&a| a == d || tree.is_ancestor(a, d))
            .map_or(0, |a| tree.node(a).depth)
    };
    let best = us.iter().map(|&u| depth_shared(u)).max().unwrap_or(0);
    us.iter()
        .copied()
        .filter(|&u| depth_shared(u) == best)
        .collect()
}

/// "never failed", "was never halted".
fn never(e: Event) -> String {
    match past(e).strip_prefix("was ") {
        Some(rest) => format!("was never {rest}"),
        None => format!("never {}", past(e)),
    }
}

/// A moment of the run as a "when" answer says it: with the robot's time
/// of day where the run keeps it ("10:1, 01:55:41.796 UTC").
fn timed_moment(cx: &Context, at: &At, p: u32) -> String {
    let m = step_moment(at.index, p).to_string();
    match cx
        .session
        .and_then(|s| s.times_us.get((p as usize).wrapping_sub(1)))
    {
        Some(&us) => format!("{m}, {} UTC", crate::clock::clock(us)),
        None => m,
    }
}

/// Each spell of RUNNING that starts at a position of `ps`: where it
/// ended and over how many ticks, or that it was still running; of
/// several, which lasted longest ("the longest time Spin stayed
/// RUNNING"). A long list is cut as `moments` cuts one: the first ten,
/// then the last.
fn spells(at: &At, u: Uid, ps: &[u32]) -> String {
    let span = |&p: &u32| spell(at, u, p);
    let said = |(from, to, ticks): (Moment, Option<Moment>, u32)| match to {
        Some(to) if ticks == 1 => format!("from {from} to {to}, within its tick"),
        Some(to) => format!("from {from} to {to}, over {ticks} ticks"),
        None => format!("from {from}, still running then"),
    };
    let spans: Vec<_> = ps.iter().map(span).collect();
    let list = match &spans[..] {
        [first @ .., last] if spans.len() > 12 => format!(
            "{}; … and {}",
            first[..10]
                .iter()
                .map(|&s| said(s))
                .collect::<Vec<_>>()
                .join("; "),
            said(*last)
        ),
        _ => spans
            .iter()
            .map(|&s| said(s))
            .collect::<Vec<_>>()
            .join("; "),
    };
    let longest = spans.iter().max_by_key(|s| s.2);
    match longest {
        Some(&l) if spans.iter().filter(|s| s.2 == l.2).count() == 1 && spans.len() > 1 => {
            format!("{list}. The longest: {}", said(l))
        }
        _ => list,
    }
}

/// The spell of RUNNING that starts at position `p`: from, to (None:
/// still running then), and over how many ticks.
fn spell(at: &At, u: Uid, p: u32) -> (Moment, Option<Moment>, u32) {
    let changes = at.index.changes_of(u);
    let from = step_moment(at.index, p);
    let next = changes.partition_point(|&c| c <= p);
    let to = changes
        .get(next)
        .copied()
        .filter(|&c| c <= at.pos)
        .map(|c| step_moment(at.index, c));
    let ticks = to.map_or(at.moment().tick, |t| t.tick) - from.tick + 1;
    (from, to, ticks)
}

/// In how many ticks the spells starting at `ps` were running (a tick
/// where one ended and the next began counted once).
fn ticks_running(at: &At, u: Uid, ps: &[u32]) -> u32 {
    let mut counted = 0;
    let mut last = 0;
    for &p in ps {
        let (from, to, _) = spell(at, u, p);
        let end = to.map_or(at.moment().tick, |t| t.tick);
        let start = from.tick.max(last + 1);
        counted += (end + 1).saturating_sub(start);
        last = last.max(end);
    }
    counted
}

fn when(cx: &Context, u: Uid, e: Event, which: Which, r: &mut Reply) -> Result<(), String> {
    let at = run_of(cx, &r.question)?;
    let ev = events(at, u, e);
    let (name, by) = (cx.name(u), cx.by(at));
    let what = match which {
        Which::First => "first ",
        Which::Last => "last ",
        Which::Every => "",
    };
    let timed = cx
        .session
        .is_some_and(|s| s.times_us.len() == at.index.transitions.len());
    r.understood = format!("When did {name} {what}{}?", verb(e));
    r.answer = match (ev.first(), ev.last(), which) {
        // "How long did drive stay running?": each spell, start to end.
        (Some(_), _, Which::Every) if e == Event::KeepRunning => format!(
            "{} {} {} {by}: {}.",
            upper(&name),
            past(e),
            times(ev.len()),
            spells(at, u, &ev)
        ),
        // Still running then: not yet, rather than never.
        (None, _, _)
            if matches!(e, Event::Succeed | Event::Fail | Event::Finish)
                && at.status(u) == Status::Running =>
        {
            format!(
                "{} {} {by}: it is still running then.",
                upper(&name),
                never(e)
            )
        }
        (None, _, _) => format!("{} {} {by}.", upper(&name), never(e)),
        (Some(&p), _, Which::First) => format!(
            "{} first {} at {} ({} in all {by}).",
            upper(&name),
            past(e),
            timed_moment(cx, at, p),
            times(ev.len())
        ),
        (_, Some(&p), Which::Last) => format!(
            "{} last {} at {} ({} in all {by}).",
            upper(&name),
            past(e),
            timed_moment(cx, at, p),
            times(ev.len())
        ),
        _ if timed && ev.len() <= 12 => {
            let ms: Vec<String> = ev.iter().map(|&p| timed_moment(cx, at, p)).collect();
            format!(
                "{} {} {} {by}: at {}.",
                upper(&name),
                past(e),
                times(ev.len()),
                ms.join("; ")
            )
        }
        _ => format!(
            "{} {} {} {by}: at {}.",
            upper(&name),
            past(e),
            times(ev.len()),
            moments(at.index, &ev)
        ),
    };
    // "When did the taxi pick up the passenger?": an action asked of by
    // what it does started, and was done when it ended; both are said.
    let asked: Vec<u32> = match which {
        Which::First => ev.first().copied().into_iter().collect(),
        Which::Last => ev.last().copied().into_iter().collect(),
        Which::Every => ev.clone(),
    };
    if e == Event::Run && cx.tree.node(u).kind.is_leaf() && (1..=3).contains(&asked.len()) {
        r.answer.push_str(&how_the_calls_ended(at, u, &asked));
    }
    r.nodes = vec![u];
    Ok(())
}

/// " It ended: SUCCESS at 8:1.", " They ended: FAILURE at 10:1 and SUCCESS
/// at 18:1.": how each call started at `starts` ended, by the moment asked.
fn how_the_calls_ended(at: &At, u: Uid, starts: &[u32]) -> String {
    let changes = at.index.changes_of(u);
    let ends: Vec<String> = starts
        .iter()
        .map(|&p| {
            let next = changes.get(changes.partition_point(|&c| c <= p)).copied();
            match next.filter(|&c| c <= at.pos) {
                Some(c) => match at.index.transitions[c as usize - 1].status {
                    Status::Success => format!("SUCCESS at {}", step_moment(at.index, c)),
                    Status::Failure => format!("FAILURE at {}", step_moment(at.index, c)),
                    _ => format!("halted at {}", step_moment(at.index, c)),
                },
                // Only the last call can be running at the moment asked.
                None => String::new(),
            }
        })
        .collect();
    match &ends[..] {
        [] => String::new(),
        [one] if one.is_empty() => " It was still running then.".to_string(),
        [one] => format!(" It ended: {one}."),
        [first @ .., last] if last.is_empty() => format!(
            " They ended: {}; the last was still running then.",
            first.join(", ")
        ),
        [first @ .., last] => format!(" They ended: {} and {last}.", first.join(", ")),
    }
}

fn how_often(cx: &Context, u: Uid, e: Event, r: &mut Reply) -> Result<(), String> {
    let at = run_of(cx, &r.question)?;
    let ev = events(at, u, e);
    let name = cx.name(u);
    r.understood = format!("How often did {name} {}?", verb(e));
    let started = events(at, u, Event::Run).len();
    r.answer = if ev.is_empty() {
        format!("{} {} {}.", upper(&name), never(e), cx.by(at))
    } else {
        let started = match e {
            Event::Run => String::new(),
            // "What fraction of ticks was drive RUNNING?".
            Event::KeepRunning => format!(
                "; it started {}, and was running in {} of the {} ticks",
                times(started),
                ticks_running(at, u, &ev),
                at.moment().tick
            ),
            _ => format!("; it started {}", times(started)),
        };
        format!(
            "{} {} {} {} (at {}){started}.",
            upper(&name),
            past(e),
            times(ev.len()),
            cx.by(at),
            moments(at.index, &ev),
        )
    };
    r.nodes = vec![u];
    Ok(())
}

fn tick(cx: &Context, n: u32, r: &mut Reply) -> Result<(), String> {
    let at = run_of(cx, &r.question)?;
    let ticks = at.index.ticks();
    r.understood = format!("What happened at tick {n}?");
    if n > ticks {
        return Err(format!(
            "The run has ticks 1 to {ticks}: there is no tick {n}."
        ));
    }
    let range = at.index.tick_range(n);
    let mut said = Vec::new();
    for t in &at.index.transitions[range.clone()] {
        let e = [Event::Fail, Event::Succeed, Event::Halted, Event::Run]
            .into_iter()
            .find(|&e| is_event(t.prev, t.status, e));
        if let Some(e) = e {
            said.push(format!("{} {}", cx.name(t.uid), past(e)));
        }
    }
    r.moment = Some(n.to_string());
    // A recorded run is told whole: where the tick goes past the moment
    // asked (a step of it, or an earlier tick), that is said first.
    let pos = at.pos as usize;
    let head = if range.is_empty() || pos >= range.end {
        format!("At tick {n}")
    } else if pos > range.start {
        format!(
            "At tick {n} (to {n}:{}, past the moment asked, {})",
            range.len(),
            at.moment()
        )
    } else {
        format!("At tick {n} (after the moment asked, {})", at.moment())
    };
    r.answer = match said.len() {
        0 if range.is_empty() => {
            format!("Nothing changed at tick {n}: every node that was running kept running.")
        }
        0 => format!("{head} only resets happened (nodes going back to IDLE)."),
        k if k > 12 => format!(
            "{head}: {}, and {} more (btx log shows every transition).",
            said[..12].join(", "),
            k - 12
        ),
        _ => format!("{head}: {}.", said.join(", ")),
    };
    Ok(())
}

/// "How was FollowPath's second failure handled?": that failure, and
/// what each fallback, retry or recovery above it did from then on, by
/// the moment asked (the words a call's why says it with).
fn handled(cx: &Context, r: &mut Reply, p: u32) -> Result<(), String> {
    let at = run_of(cx, &r.question)?;
    let session = cx.session.ok_or("a run is needed")?;
    let u = at.index.transitions[p as usize - 1].uid;
    let when = step_moment(at.index, p);
    r.understood = "How was the failure handled?".into();
    r.about = Some(u);
    r.nodes = std::iter::once(u)
        .chain(
            cx.tree
                .ancestors(u)
                .filter(|&a| crate::explain::failure::handles_failure(cx.tree, a)),
        )
        .collect();
    r.answer = format!(
        "{} failed at {when}. {}",
        upper(&cx.name(u)),
        crate::causal::calls::handled(session, u, p, at.pos)
    );
    Ok(())
}

/// "Did the recovery work?": yes where a handler above the failed leaf
/// succeeded after it, no where each failed, not yet where one had not
/// ended; then what each handler ran and how the leaf went when tried
/// again, so a recovery that ran but did not hold is seen as such.
fn recovered(cx: &Context, r: &mut Reply, said: Option<u32>) -> Result<(), String> {
    let at = run_of(cx, &r.question)?;
    let tree = cx.tree;
    r.understood = "Did the recovery work?".into();
    let failed = said.or_else(|| {
        (1..=at.pos).rev().find(|&p| {
            let t = at.index.transitions[p as usize - 1];
            t.status == Status::Failure && tree.node(t.uid).kind.is_leaf()
        })
    });
    let Some(p) = failed else {
        r.answer = format!(
            "Nothing failed {}, so nothing needed recovering.",
            cx.by(at)
        );
        return Ok(());
    };
    let leaf = at.index.transitions[p as usize - 1].uid;
    let when = step_moment(at.index, p);
    let handlers: Vec<Uid> = tree
        .ancestors(leaf)
        .filter(|&a| crate::explain::failure::handles_failure(tree, a))
        .collect();
    let Some(session) = cx.session.filter(|_| !handlers.is_empty()) else {
        r.answer = format!(
            "Nothing recovered from the last failure: {} failed at {when}, and no fallback, retry or recovery is above it.",
            cx.name(leaf)
        );
        return Ok(());
    };
    r.nodes = std::iter::once(leaf)
        .chain(handlers.iter().copied())
        .collect();
    let (handling, story) = crate::causal::calls::handling(session, leaf, p, at.pos);
    r.about = handling.by;
    let (verdict, nothing) = match handling.ended {
        Some(Status::Success) => ("Yes", ""),
        Some(_) => ("No", " Nothing above recovered."),
        None => ("Not yet", ""),
    };
    r.answer = format!(
        "{verdict}. {} failed at {when}. {story}{nothing}",
        upper(&cx.name(leaf))
    );
    Ok(())
}

/// "What if drop off passenger had kept running?": a node that runs on
/// holds each node above it running (a Sequence, a Fallback, a decorator
/// pass RUNNING up and tick nothing after it), up to the first that may
/// end or halt it by itself (a reactive or parallel node, a Timeout, a
/// node the tree alone does not describe).
fn keeps_running(cx: &Context, u: Uid, r: &mut Reply) -> Result<(), String> {
    let tree = cx.tree;
    let name = cx.name(u);
    r.about = Some(u);
    r.understood = format!("What happens if {name} keeps running?");
    let holds = |n: &crate::model::Node| {
        n.kind == crate::model::Kind::SubTree
            || matches!(
                n.builtin,
                Some(
                    Builtin::Sequence
                        | Builtin::AsyncSequence
                        | Builtin::SequenceWithMemory
                        | Builtin::Fallback
                        | Builtin::AsyncFallback
                        | Builtin::Inverter
                        | Builtin::ForceSuccess
                        | Builtin::ForceFailure
                        | Builtin::RetryUntilSuccessful
                        | Builtin::Repeat
                        | Builtin::KeepRunningUntilFailure
                        | Builtin::RecoveryNode
                        | Builtin::RoundRobin
                )
            )
    };
    let mut held: Vec<Uid> = Vec::new();
    let mut decider = None;
    let mut child = u;
    while let Some(p) = tree.parent(child) {
        if !holds(tree.node(p)) {
            decider = Some(p);
            break;
        }
        held.push(p);
        child = p;
    }
    r.nodes = std::iter::once(u).chain(held.iter().copied()).collect();
    let names: Vec<String> = held.iter().map(|&p| cx.name(p)).collect();
    let up = match names.len() {
        0 => String::new(),
        1 => format!("{} keeps running too, ", names[0]),
        _ => format!("{} keep running too, ", and_list(&names)),
    };
    r.answer = match decider {
        None => format!(
            "If {name} keeps running, {up}nothing after it starts, and the run does not end while it runs."
        ),
        Some(p) => format!(
            "If {name} keeps running, {up}nothing after it starts while it runs; {}, a {}, may still end or halt it by itself.",
            cx.name(p),
            tree.node(p).id
        ),
    };
    Ok(())
}

/// What a parent does when a child ends with a status.
enum Flow {
    /// It ends the same way (a decorator maps the status).
    Up(Status),
    /// It goes on to its next child when true, else ends with the status.
    Next(bool),
    /// It ticks the child again (a Retry after a failure, a Repeat after a
    /// success).
    Again,
    /// The tree alone does not say (reactive, parallel, custom nodes).
    Unknown,
}

fn flow(n: &crate::model::Node, child: Uid, status: Status) -> Flow {
    let flip = |s: Status| {
        if s == Status::Success {
            Status::Failure
        } else {
            Status::Success
        }
    };
    match n.builtin {
        // A reactive one goes on the same way within the tick.
        Some(
            Builtin::Sequence
            | Builtin::SequenceWithMemory
            | Builtin::ReactiveSequence
            | Builtin::AsyncSequence
            | Builtin::PipelineSequence,
        ) => Flow::Next(status == Status::Success),
        Some(Builtin::Fallback | Builtin::ReactiveFallback | Builtin::AsyncFallback) => {
            Flow::Next(status == Status::Failure)
        }
        Some(Builtin::Inverter) => Flow::Up(flip(status)),
        Some(Builtin::ForceSuccess) => Flow::Up(Status::Success),
        Some(Builtin::ForceFailure) => Flow::Up(Status::Failure),
        Some(Builtin::RetryUntilSuccessful) if status == Status::Failure => Flow::Again,
        Some(Builtin::Repeat) if status == Status::Success => Flow::Again,
        Some(Builtin::RetryUntilSuccessful | Builtin::Repeat | Builtin::SubTree) => {
            Flow::Up(status)
        }
        // Nav2's: the first child's success is its own, and so is the
        // recovery's failure. The first child's failure ticks the recovery
        // only while retries are left: the run's to say.
        Some(Builtin::RecoveryNode)
            if (n.children.first() == Some(&child)) == (status == Status::Success) =>
        {
            Flow::Up(status)
        }
        _ if n.kind == crate::model::Kind::SubTree => Flow::Up(status),
        _ => Flow::Unknown,
    }
}

/// What happens after the moment, by running the tree on from it.
fn ahead(cx: &Context, r: &mut Reply) -> Result<(), String> {
    let (Some(s), Some(at)) = (cx.session, cx.at.as_ref()) else {
        return Err("a run is needed".into());
    };
    r.understood = "What will I do next?".into();
    let a = crate::causal::ahead::ahead(s, at.pos).map_err(|e| format!("Nothing: {e}."))?;
    r.answer = a.text(cx.tree);
    let mut nodes: Vec<Uid> = a.steps.iter().map(|s| s.uid).collect();
    nodes.dedup();
    r.nodes = nodes;
    Ok(())
}

/// What the tree ticks after `u` ends with `s`, read from the tree: up
/// through the parents that pass the outcome on, to the next child a
/// Sequence or Fallback goes on to.
fn next(cx: &Context, u: Uid, s: Status, r: &mut Reply, asked_next: bool) -> Result<(), String> {
    let tree = cx.tree;
    let name = cx.name(u);
    let word = says(s);
    r.about = Some(u);
    r.understood = if asked_next {
        format!("What will I do next, once {name} succeeds?")
    } else {
        format!("What happens if {name} {word}?")
    };
    let (mut child, mut status) = (u, s);
    // The nodes that end because `u` did, each with how it ends.
    let mut ended: Vec<(Uid, Status)> = Vec::new();
    while let Some(p) = tree.parent(child) {
        let n = tree.node(p);
        match flow(n, child, status) {
            Flow::Up(st) => {
                status = st;
                child = p;
                ended.push((p, st));
            }
            Flow::Again => {
                let again = again(cx, u, child, p, &ended);
                r.answer = format!("If {name} {word}, {again}.");
                r.nodes = vec![u, p];
                return Ok(());
            }
            Flow::Unknown => {
                r.answer = format!(
                    "If {name} {word}, what comes next is up to {}, a {} that the tree alone does not decide; ask a run.",
                    cx.name(p),
                    n.id
                );
                return Ok(());
            }
            Flow::Next(go_on) => {
                let at = n.children.iter().position(|&c| c == child).unwrap_or(0);
                match n.children.get(at + 1) {
                    Some(&c) if go_on => {
                        let first = tree.leaves_below(c).next().unwrap_or(c);
                        r.answer = format!("If {name} {word}, {}", goes_on(cx, p, first));
                        r.nodes = vec![u, first];
                        return Ok(());
                    }
                    _ => {
                        child = p;
                        ended.push((p, status));
                    }
                }
            }
        }
    }
    r.answer = format!("If {name} {word}, {}", task_ends(cx, u, s, status, &ended));
    r.nodes = std::iter::once(u)
        .chain(ended.iter().map(|&(p, _)| p))
        .collect();
    Ok(())
}

/// The verb of an outcome, as "if X fails" says it.
fn says(s: Status) -> &'static str {
    if s == Status::Success {
        "succeeds"
    } else {
        "fails"
    }
}

/// "X ends, then the Retry (#7) tries it again": the loop `p` that ticks
/// `child` again, after the nodes that `ended` on the way up.
fn again(cx: &Context, u: Uid, child: Uid, p: Uid, ended: &[(Uid, Status)]) -> String {
    let way: String = ended
        .iter()
        .map(|&(e, st)| format!("{} {}, then ", cx.name(e), says(st)))
        .collect();
    let what = if child == u {
        "it".to_string()
    } else {
        cx.name(child)
    };
    let again = if cx.tree.node(p).builtin == Some(Builtin::Repeat) {
        format!("repeats {what} (while it has cycles left)")
    } else {
        format!("tries {what} again (while it has attempts left)")
    };
    format!("{way}{} {again}", cx.name(p))
}

/// "I will X next.": the first leaf of the child `p` goes on to; an async
/// control yields the tick between children.
fn goes_on(cx: &Context, p: Uid, first: Uid) -> String {
    let yields = matches!(
        cx.tree.node(p).builtin,
        Some(Builtin::AsyncSequence | Builtin::AsyncFallback)
    );
    if yields {
        format!(
            "{} goes on to {} when it is ticked again (it gives the tick back first).",
            cx.name(p),
            cx.tree.deed(first)
        )
    } else {
        format!("I will {} next.", cx.tree.deed(first))
    }
}

/// How the task ends when the outcome went up to the root, said with the
/// way up so the claim can be read against a run.
fn task_ends(cx: &Context, u: Uid, s: Status, status: Status, ended: &[(Uid, Status)]) -> String {
    let tree = cx.tree;
    // Only where every node above passes the same outcome on as the last
    // of its steps is `u` the task's last step.
    let last_step = s == Status::Success
        && ended.iter().all(|&(p, st)| {
            st == s
                && tree
                    .node(p)
                    .children
                    .last()
                    .is_some_and(|&c| c == u || tree.is_ancestor(c, u))
        });
    if last_step {
        return format!(
            "the task {}: {} is its last step.",
            says(status),
            tree.spoken(u)
        );
    }
    let way: Vec<String> = ended
        .iter()
        .filter(|&&(p, _)| p != Tree::ROOT)
        .map(|&(p, st)| format!("{} {}", cx.name(p), says(st)))
        .collect();
    let way = if way.is_empty() {
        String::new()
    } else {
        format!("{}, so ", way.join(", then "))
    };
    format!("{way}the task {}.", says(status))
}
